//! The GCU private protocol V2.0.2 (Nanjing Xianfei, XF Robot gimbals).
//!
//! Package (both directions): `SYNC(2) LENGTH(u16 LE) VERSION MAIN(32) SUB(32) ORDER
//! PAYLOAD CRC(u16 BE)`, 115200 8N1 (or 250000, 500000, 1000000). The host computer
//! (flight controller) sends `A8 E5` packages with a command part; the GCU answers
//! every valid package with one `8A 5E` package carrying a feedback part
//! (question and answer). LENGTH is the whole package S; the CRC is CRC-16/XMODEM over
//! bytes 0..=S-3, stored big-endian; every other field is little-endian.
//!
//! ```
//! use protocol_core::gcu::{
//!     self, CameraSet, Execution, GcuFraming, GcuFrames, Header, HostFrames, HostPacket,
//!     Shutter,
//! };
//! use protocol_core::wire::{Deframer, Event};
//!
//! // Build a command and emit it as a host package (ArduPilot's version byte).
//! let shutter = Shutter(CameraSet::CAMERA_1);
//! let mut buf = [0u8; gcu::MAX_FRAME_LEN];
//! let n = gcu::encode(&shutter, &Header::ARDUPILOT, &HostFrames::default(), &mut buf)?;
//! assert_eq!(n, 73);
//! assert_eq!(&buf[..5], &[0xA8, 0xE5, 73, 0x00, 0x02]);
//! assert_eq!(&buf[69..71], &[0x20, 0x01]); // order, parameter
//!
//! // Find it in a byte stream (as a GCU, or a bridge acting as one), decode it, answer.
//! let mut deframer = Deframer::<_, { gcu::MAX_FRAME_LEN }>::new(GcuFraming::host());
//! let mut found = None;
//! let mut reply = [0u8; gcu::MAX_FRAME_LEN];
//! let mut reply_len = 0;
//! deframer.push(&buf[..n], |event| {
//!     if let Event::Frame(bytes) = event
//!         && let Ok(request) = HostPacket::decode(bytes)
//!     {
//!         found = request.message.get::<Shutter>();
//!         let answer = request.answer(GcuFrames::default(), Execution::Success);
//!         reply_len = answer.emit(&mut reply).unwrap_or(0);
//!     }
//! });
//! assert_eq!(found, Some(shutter));
//! assert_eq!(&reply[..5], &[0x8A, 0x5E, 73, 0x00, 0x02]); // the host's version echoed
//! assert_eq!(&reply[69..reply_len - 2], &[0x20, 0x00]); // order, success
//! # Ok::<(), protocol_core::Error>(())
//! ```
//!
//! # The common codec shape, for a protocol with two kinds of package
//! The other codecs have one `Packet { header, message }`. In a GCU package both the
//! data frames and the order part change type with the direction (the sync bytes), so:
//! - [`Frame`] is the checked zero-copy view of either direction; its `id()` is the
//!   order byte and its payload the bytes after it (the host's parameters, the GCU's
//!   execution state). [`GcuFraming`] plugs one direction into the shared
//!   [`Deframer`](crate::wire::Deframer).
//! - [`Header`] is what every package carries besides its data frames and its order
//!   part: the version byte.
//! - The data frames: [`HostFrames`] ([`HostMain`], [`HostSub`]) in host packages,
//!   [`GcuFrames`] ([`GcuMain`], [`GcuSub`]) in GCU packages.
//! - The order part: [`Message`] in host packages, a [`Command`] (one typed command
//!   per order) or [`Raw`]; [`Feedback`] (order and execution state) in GCU packages.
//! - [`HostPacket`] (direction [`ToGimbal`](crate::Direction::ToGimbal): header, host
//!   frames, message) and [`GcuPacket`] (direction
//!   [`FromGimbal`](crate::Direction::FromGimbal): header, GCU frames, feedback) parse
//!   from a frame and emit into a buffer; [`Packet`] is either, chosen by the sync
//!   bytes. [`HostPacket::answer`] builds the GCU's reply to a host package.
//! - Every typed command implements [`MessageData`] (its order byte, name and length;
//!   `Protocol = `[`Gcu`]), so one command is sent with [`encode`] and recognised with
//!   [`Message::get`].
//! - [`CATALOG`] lists the 26 orders; [`GpsTime`] converts GPS week + time of week.
//!
//! # Decisions where the document is silent (see docs/src/protocols/gcu.md)
//! - One framing per direction ([`GcuFraming::host`], [`GcuFraming::gcu`]): each wire of
//!   the UART carries one direction, and the shared deframer looks for one sync pattern.
//!   [`Frame`] and [`Packet`] accept both directions.
//! - Package length: 72 (order byte, no parameters) to 257 bytes (the document's CRC
//!   routine takes a `uint8_t` length: at most 255 bytes are covered).
//! - The version byte is kept as received (the document uses 0x01, ArduPilot 0x02);
//!   [`HostPacket::answer`] answers with the host's version.
//! - A command whose parameters have another length than the document gives its order
//!   decodes to [`Message::Raw`], like an unknown order; decoding a CRC-valid package
//!   never fails on its content, so the GCU side can always answer.
//! - `KK` camera bytes are a [`CameraSet`]. The single parameter of shutter (0x20),
//!   record (0x21) and focus (0x26), printed `0x01`, and the first parameter of palette
//!   (0x2A, `0x02`) and night vision (0x2B, `0x01`) are read as camera sets too (camera 1
//!   is the visible camera, camera 2 the thermal one); ArduPilot sends record 0x01 to
//!   start and 0x00 to stop.
//! - Feedback is `order, state` for every order ([`Feedback`]). The state reads as a
//!   status (0 success, 1 fail, 2 operating) or, for the orders whose failure the
//!   document prints as `NN` or as the camera byte (0x17, 0x1A, 0x1B, 0x20..0x26, 0x2A,
//!   0x2B), as the set of cameras that failed ([`FeedbackKind`]). The null order's
//!   feedback is printed as a bare `0x00`; it is encoded `00 00` like the others,
//!   because ArduPilot ignores GCU packages shorter than 73 bytes. A feedback with the
//!   order byte alone still decodes.
//! - "GNSS microsecond" (host bytes 51..54) is the GPS time of week in milliseconds.
//! - Host carrier yaw is a u16 (0..36000) as documented; ArduPilot writes an i16
//!   (-18000..18000): [`HostMain::carrier_yaw_0_36000_cdeg`] folds it.
//! - GCU sub-frame bytes 63..68 are reserved in V2.0.2 and kept as bytes (ArduPilot reads
//!   thermal status, camera status and time zone there, from a later revision).
//! - PiP (0x74) values 1..4 are named after ArduPilot's views; the document defines 0x00.

mod feedback;
mod frame;
mod gcu_frames;
mod host_frames;
mod orders;
mod params;
mod time;

pub use feedback::{Execution, Feedback, FeedbackKind};
pub use frame::{
    CRC_LEN, Frame, GCU_SYNC, GcuFraming, HEADER_LEN, HOST_SYNC, MAIN_LEN, MAX_FRAME_LEN,
    MAX_PAYLOAD_LEN, MIN_FRAME_LEN, SUB_LEN, VERSION_ARDUPILOT, VERSION_DOC, direction_of, sync_of,
};
pub use gcu_frames::{CameraStatus, GcuFrames, GcuMain, GcuSub, GimbalCode, GimbalMode};
pub use host_frames::{ControlMeaning, HostFrames, HostMain, HostStatus, HostSub, SUB_HEADER};
pub use orders::*;
pub use params::{
    CameraSet, ClickToAim, ExternalTrack, ExternalTrackAction, GeoTarget, NightVision, OnOff,
    Palette, PaletteAction, PipView, RangingState, Track, TrackAction, ZoomTo,
};
pub use time::{DEFAULT_LEAP_SECONDS, GPS_EPOCH_UNIX_MS, GpsTime, WEEK_MS};

use crate::wire::encoding::{Field, Le};
use crate::wire::table::PayloadCodec;
use crate::wire::{Reader, Writer};
use crate::{Direction, Error, Result};

const _: () = {
    assert!(HostMain::LEN == MAIN_LEN);
    assert!(HostSub::LEN == SUB_LEN);
    assert!(GcuMain::LEN == MAIN_LEN);
    assert!(GcuSub::LEN == SUB_LEN);
    assert!(HostFrames::LEN == MAIN_LEN + SUB_LEN);
    assert!(GcuFrames::LEN == MAIN_LEN + SUB_LEN);
};

/// Decodes exactly `T::LEN` bytes; any other length is [`Error::BadLength`].
#[inline]
fn decode_exact<T: Field<Le>>(bytes: &[u8]) -> Result<T> {
    if bytes.len() != T::LEN {
        return Err(Error::BadLength);
    }
    let mut r = Reader::new(bytes);
    let v = T::read(&mut r)?;
    r.finish()?;
    Ok(v)
}

/// The GCU length rules, for the message table: a command's parameters have exactly its
/// layout's length.
impl<T: Field<Le>> PayloadCodec<T> for Gcu {
    const MAX_LEN: usize = T::LEN;

    fn decode(payload: &[u8]) -> Result<T> {
        decode_exact(payload)
    }

    fn encoded_len(_: &T) -> usize {
        T::LEN
    }

    fn encode(value: &T, w: &mut Writer<'_>) -> Result<()> {
        value.write(w)
    }
}

pub use crate::wire::MessageData;

wire_derive! {
    [Eq, Hash]
    /// A command whose order this codec does not know, or whose parameters do not have
    /// the length the document gives the order; kept as received.
    pub struct Raw<'a> {
        /// The order byte.
        pub id: u8,
        /// The parameter bytes.
        pub payload: &'a [u8],
    }
}

impl<'a> Message<'a> {
    /// The message for an order byte and its parameters. Never fails: an unknown order,
    /// or parameters of another length than the order's, give [`Message::Raw`].
    #[must_use]
    pub fn decode(id: u8, payload: &'a [u8]) -> Self {
        match Command::decode(id, payload) {
            Some(Ok(command)) => Message::Command(command),
            Some(Err(_)) | None => Message::Raw(Raw { id, payload }),
        }
    }

    /// The order of the command part (unknown ones as [`Order::Other`]).
    #[must_use]
    pub const fn order(&self) -> Order {
        Order::from_value(self.id())
    }
}

impl<'a> From<Raw<'a>> for Message<'a> {
    fn from(r: Raw<'a>) -> Self {
        Message::Raw(r)
    }
}

wire_derive! {
    [Eq, Hash]
    /// What every package carries besides its data frames and its order part: the
    /// protocol version byte (kept as received; a GCU answers with the host's).
    pub struct Header {
        /// Protocol version byte ([`VERSION_DOC`], [`VERSION_ARDUPILOT`], or any other).
        pub version: u8,
    }
}

impl Header {
    /// The document's version byte (0x01).
    pub const DOC: Header = Header::new(VERSION_DOC);
    /// ArduPilot's version byte (0x02).
    pub const ARDUPILOT: Header = Header::new(VERSION_ARDUPILOT);

    /// A header with version byte `version`.
    #[must_use]
    pub const fn new(version: u8) -> Self {
        Header { version }
    }
}

/// Writes a whole package: header, the two data frames, the order byte `id`, the payload
/// (`payload_len` bytes, through `payload`) and the CRC.
fn emit_package(
    buf: &mut [u8],
    direction: Direction,
    header: Header,
    frames: &impl Field<Le>,
    id: u8,
    payload_len: usize,
    payload: impl FnOnce(&mut Writer<'_>) -> Result<()>,
) -> Result<usize> {
    let total = MIN_FRAME_LEN.saturating_add(payload_len);
    if total > MAX_FRAME_LEN {
        return Err(Error::BadLength);
    }
    let len_field = u16::try_from(total).map_err(|_| Error::BadLength)?;
    let buf = buf.get_mut(..total).ok_or(Error::BufferTooSmall)?;
    let mut frame = Frame::new_unchecked(&mut *buf);
    frame.set_start(direction, len_field);
    frame.set_version(header.version);
    frames.write(&mut Writer::new(frame.frames_mut()))?;
    frame.set_id(id);
    let mut w = Writer::new(frame.payload_mut());
    payload(&mut w)?;
    if w.len() != payload_len {
        return Err(Error::BadLength);
    }
    frame.fill_checksum();
    Ok(total)
}

/// Checks the frame's length and that its sync bytes are `expected`'s.
fn checked_direction(frame: &Frame<&[u8]>, expected: Direction) -> Result<()> {
    frame.check_len()?;
    if frame.direction() == Some(expected) {
        Ok(())
    } else {
        Err(Error::BadSync)
    }
}

/// Encodes one typed command as a whole host package into `buf` and returns its length:
/// `gcu::encode(&Shutter(CameraSet::CAMERA_1), &Header::ARDUPILOT, &frames, &mut buf)`.
///
/// # Errors
/// [`Error::BufferTooSmall`] when `buf` cannot hold the package.
pub fn encode<M: MessageData<Protocol = Gcu>>(
    message: &M,
    header: &Header,
    frames: &HostFrames,
    buf: &mut [u8],
) -> Result<usize> {
    emit_package(
        buf,
        Direction::ToGimbal,
        *header,
        frames,
        M::ID,
        M::ENCODED_LEN,
        |w| message.encode_payload(w),
    )
}

wire_derive! {
    [Eq, Hash]
    /// A package from the host computer (flight controller) to the GCU (`A8 E5`,
    /// [`Direction::ToGimbal`]).
    pub struct HostPacket<'a> {
        /// The version byte.
        pub header: Header,
        /// Main and sub data frames.
        pub frames: HostFrames,
        /// The command part.
        pub message: Message<'a>,
    }
}

impl<'a> HostPacket<'a> {
    /// A package with the document's version (0x01), a zero main frame, no sub frame
    /// and `message`.
    pub fn new(message: impl Into<Message<'a>>) -> Self {
        HostPacket {
            header: Header::DOC,
            frames: HostFrames::default(),
            message: message.into(),
        }
    }

    /// Parses a frame view (its CRC is not verified here: the deframer or
    /// [`Frame::verify`] does that).
    ///
    /// # Errors
    /// [`Error::BadSync`] for a GCU package, and the frame's own length errors.
    pub fn parse(frame: &Frame<&'a [u8]>) -> Result<Self> {
        checked_direction(frame, Direction::ToGimbal)?;
        Ok(HostPacket {
            header: Header::new(frame.version()),
            frames: HostFrames {
                main: decode_exact(frame.main_ref())?,
                sub: decode_exact(frame.sub_ref())?,
            },
            message: Message::decode(frame.id(), frame.payload_ref()),
        })
    }

    /// Checks, verifies and parses a complete package (bytes after it are ignored).
    ///
    /// # Errors
    /// As [`Frame::new_checked`], [`Frame::verify`] and [`HostPacket::parse`].
    pub fn decode(bytes: &'a [u8]) -> Result<Self> {
        let frame = Frame::new_checked(bytes)?;
        frame.verify()?;
        HostPacket::parse(&frame)
    }

    /// Length of the encoded package.
    #[must_use]
    pub const fn buffer_len(&self) -> usize {
        MIN_FRAME_LEN.saturating_add(self.message.payload_len())
    }

    /// Encodes the package into `buf` and returns its length.
    ///
    /// # Errors
    /// [`Error::BufferTooSmall`] when `buf` is shorter than [`HostPacket::buffer_len`];
    /// [`Error::BadLength`] for a package longer than [`MAX_FRAME_LEN`].
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize> {
        emit_package(
            buf,
            Direction::ToGimbal,
            self.header,
            &self.frames,
            self.message.id(),
            self.message.payload_len(),
            |w| self.message.encode(w),
        )
    }

    /// The GCU's answer to this package: the host's version byte, `frames` (with the
    /// sub frame replaced by [`GcuSub::ABSENT`] unless the host requested the sub frame
    /// the document defines, [`SUB_HEADER`]), and the feedback `execution` for this
    /// package's order.
    #[must_use]
    pub fn answer(&self, frames: GcuFrames, execution: Execution) -> GcuPacket<'static> {
        let sub = if self.frames.main.sub_request == SUB_HEADER {
            frames.sub
        } else {
            GcuSub::ABSENT
        };
        GcuPacket {
            header: self.header,
            frames: GcuFrames {
                main: frames.main,
                sub,
            },
            feedback: Feedback::new(self.message.order(), execution),
        }
    }
}

wire_derive! {
    [Eq, Hash]
    /// A package from the GCU to the host computer (`8A 5E`, [`Direction::FromGimbal`]).
    pub struct GcuPacket<'a> {
        /// The version byte.
        pub header: Header,
        /// Main and sub data frames ([`GcuSub::ABSENT`] for an unknown request code).
        pub frames: GcuFrames,
        /// The feedback part.
        pub feedback: Feedback<'a>,
    }
}

impl<'a> GcuPacket<'a> {
    /// Parses a frame view (its CRC is not verified here).
    ///
    /// # Errors
    /// [`Error::BadSync`] for a host package, and the frame's own length errors.
    pub fn parse(frame: &Frame<&'a [u8]>) -> Result<Self> {
        checked_direction(frame, Direction::FromGimbal)?;
        Ok(GcuPacket {
            header: Header::new(frame.version()),
            frames: GcuFrames {
                main: decode_exact(frame.main_ref())?,
                sub: decode_exact(frame.sub_ref())?,
            },
            feedback: Feedback::decode(frame.id(), frame.payload_ref()),
        })
    }

    /// Checks, verifies and parses a complete package (bytes after it are ignored).
    ///
    /// # Errors
    /// As [`Frame::new_checked`], [`Frame::verify`] and [`GcuPacket::parse`].
    pub fn decode(bytes: &'a [u8]) -> Result<Self> {
        let frame = Frame::new_checked(bytes)?;
        frame.verify()?;
        GcuPacket::parse(&frame)
    }

    /// Length of the encoded package.
    #[must_use]
    pub const fn buffer_len(&self) -> usize {
        MIN_FRAME_LEN.saturating_add(self.feedback.payload_len())
    }

    /// Encodes the package into `buf` and returns its length.
    ///
    /// # Errors
    /// [`Error::BufferTooSmall`] when `buf` is shorter than [`GcuPacket::buffer_len`];
    /// [`Error::BadLength`] for a package longer than [`MAX_FRAME_LEN`];
    /// [`Error::OutOfRange`] for extra feedback bytes without an execution state.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize> {
        emit_package(
            buf,
            Direction::FromGimbal,
            self.header,
            &self.frames,
            self.feedback.id(),
            self.feedback.payload_len(),
            |w| self.feedback.encode(w),
        )
    }
}

wire_derive! {
    [Eq, Hash]
    /// A package of either direction.
    pub enum Packet<'a> {
        /// From the host computer (`A8 E5`, [`Direction::ToGimbal`]).
        Host(HostPacket<'a>),
        /// From the GCU (`8A 5E`, [`Direction::FromGimbal`]).
        Gcu(GcuPacket<'a>),
    }
}

impl<'a> Packet<'a> {
    /// Parses a frame view of either direction (its CRC is not verified here).
    ///
    /// # Errors
    /// The frame's own length and sync errors.
    pub fn parse(frame: &Frame<&'a [u8]>) -> Result<Self> {
        frame.check_len()?;
        match frame.direction() {
            Some(Direction::ToGimbal) => HostPacket::parse(frame).map(Packet::Host),
            Some(Direction::FromGimbal) => GcuPacket::parse(frame).map(Packet::Gcu),
            None => Err(Error::BadSync),
        }
    }

    /// Checks, verifies and parses a complete package of either direction.
    ///
    /// # Errors
    /// As [`Frame::new_checked`], [`Frame::verify`] and [`Packet::parse`].
    pub fn decode(bytes: &'a [u8]) -> Result<Self> {
        let frame = Frame::new_checked(bytes)?;
        frame.verify()?;
        Packet::parse(&frame)
    }

    /// The direction, from the sync bytes.
    #[must_use]
    pub const fn direction(&self) -> Direction {
        match self {
            Packet::Host(_) => Direction::ToGimbal,
            Packet::Gcu(_) => Direction::FromGimbal,
        }
    }

    /// The header (the version byte).
    #[must_use]
    pub const fn header(&self) -> Header {
        match self {
            Packet::Host(p) => p.header,
            Packet::Gcu(p) => p.header,
        }
    }

    /// The message id: the order byte of the command or feedback part.
    #[must_use]
    pub const fn id(&self) -> u8 {
        match self {
            Packet::Host(p) => p.message.id(),
            Packet::Gcu(p) => p.feedback.id(),
        }
    }

    /// The order of the command or feedback part.
    #[must_use]
    pub const fn order(&self) -> Order {
        Order::from_value(self.id())
    }

    /// Length of the encoded package.
    #[must_use]
    pub const fn buffer_len(&self) -> usize {
        match self {
            Packet::Host(p) => p.buffer_len(),
            Packet::Gcu(p) => p.buffer_len(),
        }
    }

    /// Encodes the package into `buf` and returns its length.
    ///
    /// # Errors
    /// As [`HostPacket::emit`] and [`GcuPacket::emit`].
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize> {
        match self {
            Packet::Host(p) => p.emit(buf),
            Packet::Gcu(p) => p.emit(buf),
        }
    }
}

impl<'a> From<HostPacket<'a>> for Packet<'a> {
    fn from(p: HostPacket<'a>) -> Self {
        Packet::Host(p)
    }
}

impl<'a> From<GcuPacket<'a>> for Packet<'a> {
    fn from(p: GcuPacket<'a>) -> Self {
        Packet::Gcu(p)
    }
}
