//! The XF Robot GCU private protocol V2.0.2 (`001_8e19e435fc647e3e.txt`).
//!
//! Package (both directions): `SYNC(2) LENGTH(u16 LE) VERSION MAIN(32) SUB(32) ORDER
//! PARAMS CRC(u16 BE)`, 115200 8N1 (or 250000, 500000, 1000000). The host computer
//! (flight controller) sends `A8 E5` packages with a command part; the GCU answers
//! every valid package with one `8A 5E` package carrying a feedback part
//! (question and answer). LENGTH is the whole package S; the CRC is CRC-16/XMODEM over
//! bytes 0..=S-3, stored big-endian; every other field is little-endian.
//!
//! - [`Frame`] is the checked zero-copy view; [`GcuFraming`] plugs one direction into the
//!   shared [`Deframer`](crate::wire::Deframer).
//! - [`HostPacket`] ([`HostMain`], [`HostSub`], [`Command`]) and [`GcuPacket`]
//!   ([`GcuMain`], [`GcuSub`], [`Feedback`]) parse from a frame and emit into a buffer;
//!   [`Packet`] is either, chosen by the sync bytes.
//! - [`CATALOG`] lists the 26 orders; [`GpsTime`] converts GPS week + time of week.
//!
//! # Decisions where the document is silent (see the README)
//! - One framing per direction ([`GcuFraming::host`], [`GcuFraming::gcu`]): each wire of
//!   the UART carries one direction, and the shared deframer looks for one sync pattern.
//!   [`Frame`] and [`Packet`] accept both directions.
//! - Package length: 72 (order byte, no parameters) to 257 bytes (the document's CRC
//!   routine takes a `uint8_t` length: at most 255 bytes are covered).
//! - The version byte is kept as received (the document uses 0x01, ArduPilot 0x02);
//!   answering with the host's version is the caller's choice.
//! - A command whose parameters have another length than the document gives its order
//!   decodes to [`Command::Raw`], like an unknown order; decoding a CRC-valid package
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

#[macro_use]
mod field;
mod command;
mod frame;
mod host;
mod reply;
mod time;

pub use command::{
    CATALOG, CameraSet, CatalogEntry, ClickToAim, Command, Execution, ExternalTrack,
    ExternalTrackAction, Feedback, FeedbackKind, GeoTarget, NightVision, OnOff, Order, Palette,
    PaletteAction, PipView, RangingState, RawCommand, Track, TrackAction, ZoomTo,
};
pub use frame::{
    CRC_LEN, Direction, Frame, GCU_SYNC, GcuFraming, HOST_SYNC, MAIN_LEN, MAIN_OFFSET,
    MAX_FRAME_LEN, MAX_PARAMS_LEN, MIN_FRAME_LEN, ORDER_OFFSET, SUB_LEN, SUB_OFFSET,
    VERSION_ARDUPILOT, VERSION_DOC,
};
pub use host::{ControlMeaning, HostMain, HostStatus, HostSub, SUB_HEADER};
pub use reply::{CameraStatus, GcuMain, GcuSub, GimbalCode, GimbalMode};
pub use time::{DEFAULT_LEAP_SECONDS, GPS_EPOCH_UNIX_MS, GpsTime, WEEK_MS};

use crate::wire::Writer;
use crate::{Error, Result};
use field::Field;

const _: () = {
    assert!(HostMain::LEN == MAIN_LEN);
    assert!(HostSub::LEN == SUB_LEN);
    assert!(GcuMain::LEN == MAIN_LEN);
    assert!(GcuSub::LEN == SUB_LEN);
};

/// Writes a whole package: header, the two data frames, the order/parameter part
/// (`part`, `part_len` bytes after the order byte included) and the CRC.
fn emit_package(
    buf: &mut [u8],
    direction: Direction,
    version: u8,
    main: &impl Field<crate::wire::encoding::Le>,
    sub: &impl Field<crate::wire::encoding::Le>,
    part_len: usize,
    part: impl FnOnce(&mut Writer<'_>) -> Result<()>,
) -> Result<usize> {
    let total = MIN_FRAME_LEN.saturating_add(part_len);
    if total > MAX_FRAME_LEN {
        return Err(Error::BadLength);
    }
    let len_field = u16::try_from(total).map_err(|_| Error::BadLength)?;
    let buf = buf.get_mut(..total).ok_or(Error::BufferTooSmall)?;
    let mut w = Writer::new(&mut *buf);
    w.put(&direction.sync())?;
    w.u16_le(len_field)?;
    w.u8(version)?;
    main.write(&mut w)?;
    sub.write(&mut w)?;
    part(&mut w)?;
    if w.len() != total.saturating_sub(CRC_LEN) {
        return Err(Error::BadLength);
    }
    Frame::new_unchecked(buf).fill_checksum();
    Ok(total)
}

fn checked_direction(frame: &Frame<&[u8]>, expected: Direction) -> Result<()> {
    frame.check_len()?;
    if frame.direction() == Some(expected) {
        Ok(())
    } else {
        Err(Error::BadSync)
    }
}

/// A package from the host computer (flight controller) to the GCU.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct HostPacket<'a> {
    /// Protocol version byte (kept as received).
    pub version: u8,
    /// Main data frame.
    pub main: HostMain,
    /// Sub data frame ([`HostSub::ABSENT`] when there is none).
    pub sub: HostSub,
    /// Command part.
    pub command: Command<'a>,
}

impl<'a> HostPacket<'a> {
    /// A package with the document's version (0x01), a zero main frame, no sub frame
    /// and `command`.
    pub fn new(command: Command<'a>) -> Self {
        HostPacket {
            version: VERSION_DOC,
            main: HostMain::default(),
            sub: HostSub::ABSENT,
            command,
        }
    }

    /// Parses a frame view (its CRC is not verified here: the deframer or
    /// [`Frame::verify`] does that). A GCU package is [`Error::BadSync`].
    pub fn parse(frame: &Frame<&'a [u8]>) -> Result<Self> {
        checked_direction(frame, Direction::Host)?;
        Ok(HostPacket {
            version: frame.version(),
            main: field::decode_exact(frame.main_ref())?,
            sub: field::decode_exact(frame.sub_ref())?,
            command: Command::decode(frame.order(), frame.params_ref()),
        })
    }

    /// Checks, verifies and parses a complete package.
    pub fn decode(bytes: &'a [u8]) -> Result<Self> {
        let frame = Frame::new_checked(bytes)?;
        frame.verify()?;
        HostPacket::parse(&frame)
    }

    /// Length of the encoded package.
    pub const fn buffer_len(&self) -> usize {
        MIN_FRAME_LEN.saturating_add(self.command.params_len())
    }

    /// Encodes the package into `buf` and returns its length.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize> {
        emit_package(
            buf,
            Direction::Host,
            self.version,
            &self.main,
            &self.sub,
            self.command.params_len(),
            |w| self.command.encode(w),
        )
    }
}

/// A package from the GCU to the host computer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct GcuPacket<'a> {
    /// Protocol version byte (kept as received).
    pub version: u8,
    /// Main data frame.
    pub main: GcuMain,
    /// Sub data frame ([`GcuSub::ABSENT`] for an unknown request code).
    pub sub: GcuSub,
    /// Feedback part.
    pub feedback: Feedback<'a>,
}

impl<'a> GcuPacket<'a> {
    /// Parses a frame view (its CRC is not verified here). A host package is
    /// [`Error::BadSync`].
    pub fn parse(frame: &Frame<&'a [u8]>) -> Result<Self> {
        checked_direction(frame, Direction::Gcu)?;
        Ok(GcuPacket {
            version: frame.version(),
            main: field::decode_exact(frame.main_ref())?,
            sub: field::decode_exact(frame.sub_ref())?,
            feedback: Feedback::decode(frame.order(), frame.params_ref()),
        })
    }

    /// Checks, verifies and parses a complete package.
    pub fn decode(bytes: &'a [u8]) -> Result<Self> {
        let frame = Frame::new_checked(bytes)?;
        frame.verify()?;
        GcuPacket::parse(&frame)
    }

    /// Length of the encoded package.
    pub const fn buffer_len(&self) -> usize {
        MIN_FRAME_LEN.saturating_add(self.feedback.data_len())
    }

    /// Encodes the package into `buf` and returns its length.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize> {
        emit_package(
            buf,
            Direction::Gcu,
            self.version,
            &self.main,
            &self.sub,
            self.feedback.data_len(),
            |w| self.feedback.encode(w),
        )
    }
}

/// A package of either direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Packet<'a> {
    /// From the host computer (`A8 E5`).
    Host(HostPacket<'a>),
    /// From the GCU (`8A 5E`).
    Gcu(GcuPacket<'a>),
}

impl<'a> Packet<'a> {
    /// Parses a frame view of either direction (its CRC is not verified here).
    pub fn parse(frame: &Frame<&'a [u8]>) -> Result<Self> {
        frame.check_len()?;
        match frame.direction() {
            Some(Direction::Host) => HostPacket::parse(frame).map(Packet::Host),
            Some(Direction::Gcu) => GcuPacket::parse(frame).map(Packet::Gcu),
            None => Err(Error::BadSync),
        }
    }

    /// Checks, verifies and parses a complete package of either direction.
    pub fn decode(bytes: &'a [u8]) -> Result<Self> {
        let frame = Frame::new_checked(bytes)?;
        frame.verify()?;
        Packet::parse(&frame)
    }

    /// The direction.
    pub const fn direction(&self) -> Direction {
        match self {
            Packet::Host(_) => Direction::Host,
            Packet::Gcu(_) => Direction::Gcu,
        }
    }

    /// The order of the command or feedback part.
    pub const fn order(&self) -> Order {
        match self {
            Packet::Host(p) => p.command.order(),
            Packet::Gcu(p) => p.feedback.order,
        }
    }

    /// The protocol version byte.
    pub const fn version(&self) -> u8 {
        match self {
            Packet::Host(p) => p.version,
            Packet::Gcu(p) => p.version,
        }
    }

    /// Length of the encoded package.
    pub const fn buffer_len(&self) -> usize {
        match self {
            Packet::Host(p) => p.buffer_len(),
            Packet::Gcu(p) => p.buffer_len(),
        }
    }

    /// Encodes the package into `buf` and returns its length.
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
