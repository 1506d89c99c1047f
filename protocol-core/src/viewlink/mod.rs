//! The Viewlink serial command protocol V3.4.4 (of Viewpro gimbals).
//!
//! Frame: `55 AA DC LEN ID DATA XOR`, 115200 8N1. LEN bits 0..5 count the bytes from LEN
//! through the checksum (4..=63), bits 6..7 are a frame counter; the checksum is the
//! XOR of LEN (counter bits included) through the last data byte. Data fields are
//! big-endian. The data of a frame (its payload) is one packet block or a fixed
//! combination of blocks, selected by the frame id ([`CATALOG`], 37 ids).
//!
//! ```
//! use protocol_core::viewlink::{
//!     self, C1, Header, LrfCommand, OperationCommand, Packet, Sensor, ViewlinkFraming,
//! };
//! use protocol_core::wire::{Deframer, Event};
//!
//! // Build a message (the document's zoom in, as ArduPilot sends it: C1 alone, frame
//! // 0x1C) and emit it as a frame with frame counter 1.
//! let zoom_in = C1 {
//!     sensor: Sensor::NoAction,
//!     zoom_speed: 7,
//!     operation: OperationCommand::ZoomIn,
//!     lrf: LrfCommand::NoAction,
//! };
//! let mut buf = [0u8; viewlink::MAX_FRAME_LEN];
//! let n = viewlink::encode(&zoom_in, &Header::new(1), &mut buf)?;
//! assert_eq!(&buf[..n], &[0x55, 0xAA, 0xDC, 0x45, 0x1C, 0x02, 0x78, 0x23]);
//!
//! // Find it in a byte stream and decode it.
//! let mut deframer = Deframer::<_, { viewlink::MAX_FRAME_LEN }>::new(ViewlinkFraming::new());
//! let mut found = None;
//! deframer.push(&buf[..n], |event| {
//!     if let Event::Frame(bytes) = event {
//!         found = Packet::decode(bytes).ok().and_then(|p| p.message.get::<C1>());
//!     }
//! });
//! assert_eq!(found, Some(zoom_in));
//! # Ok::<(), protocol_core::Error>(())
//! ```
//!
//! - [`Frame`] is the checked zero-copy view; [`ViewlinkFraming`] plugs the protocol into
//!   the shared [`Deframer`](crate::wire::Deframer).
//! - [`Packet`] (a [`Header`]: sync order and frame counter; and a [`Message`]) parses
//!   from a frame and emits into a buffer; [`FrameCounter`] produces the counter a
//!   sender keeps.
//! - Every frame id has its own payload type implementing [`MessageData`] (its id, name
//!   and largest length; `Protocol = `[`Viewlink`]), so one message is sent with
//!   [`encode`] and recognised with
//!   [`Message::get`]. 0x42 and 0x92 carry the layouts of 0x40 and 0x29 under their own
//!   types ([`StatusOsd`], [`IpFeedback`]).
//! - Every block is a typed struct or enum implementing [`Block`]: [`A1`] [`A2`] [`B1`]
//!   [`B2`] [`C1`] [`C2`] [`D1`] [`D2`] [`E1`] [`E2`] [`F1`] [`F2`] [`S1`] [`S2`] [`T1`]
//!   [`T2`] [`M`] [`U`] [`V`] and the small packets; the combinations ([`Control`],
//!   [`Status`], ...) are blocks made of blocks.
//! - [`tcp`] is the TCP envelope `EB 90 LEN BODY SUM`.
//!
//! # Decisions where the document is ambiguous (see docs/src/protocols/viewlink.md)
//! - The length byte is authoritative: a fixed-size block with more or fewer bytes is
//!   [`Error::BadLength`]. Printed examples with a spurious or missing byte are rejected
//!   (their checksum byte is not at the position LEN gives); the deframer then
//!   resynchronises on the next sync bytes.
//! - Sync: frames are sent `55 AA DC`; `AA 55 DC` (the document's ACK example) is
//!   decoded too and re-encoded as received ([`SyncOrder`], in the [`Header`]). The
//!   deframer accepts one order ([`ViewlinkFraming::swapped`] for the other).
//! - C1 is a big-endian `u16` with a 7-bit operation command (bits 6..12), as the bit
//!   table, every example and ArduPilot have it (the prose says 3 bits).
//! - Blocks whose parameters depend on a command byte (A1, C2, E2, S1, U, the SD
//!   feedback) are enums with one variant per command with defined parameters; the
//!   other commands keep their parameter bytes in a `Plain` variant. Reserved bytes and
//!   bits, and unlisted enumeration values, are kept, so every decoded frame re-encodes
//!   byte for byte; encoding a bit field whose value does not fit is
//!   [`Error::OutOfRange`].
//! - M (0xB1): data-type bit 0 selects the 6-byte attitude group (roll, pitch, yaw: the
//!   document's 3.19 labels bytes 9..10 "tilt"), bit 1 the 28-byte GPS group; the
//!   document defines no bytes for the gyro bit (2), so it adds none. Byte 1 and the
//!   seven reserved bytes 2..8 are always present: an M packet has 8, 14, 36 or 42
//!   bytes. Date: day bits 15..11, month 10..7, year-2000 6..0; time: 3 bytes of 0.01 s
//!   since UTC midnight.
//! - B1 roll: 12 bits of 180/4095°, 0 at -90° (ArduPilot's reading).
//! - T2 bytes 13..14 (printed "pitch" twice) are roll; T1 "attitude" fields are
//!   altitudes in metres.
//! - U: the settings of section 3.1 and the appendix's parameter ids share the command
//!   byte; where they disagree 3.1 wins (0x0A: int16 in bytes 2..3; 0x10: the nine-byte
//!   channel map). Appendix values are one byte in byte 2, except 0x1F (pitch
//!   declination, int16 0.01°) and 0x30 (attitude interval, uint16 ms), which take bytes
//!   2..3 like 0x0A.
//! - V: typed when it carries at least its command's effective length (extra bytes are
//!   kept as `trailing`), else raw. The reply codes of section 3.2 (0xFC..0xFE) and the
//!   query codes (0x82..0xEE, which ArduPilot matches replies by) are both known; a
//!   bridge answering ArduPilot replies with the query code (0xD0 firmware, 20 bytes;
//!   0xE4 model, 10 bytes). The four alarm bytes are an int16 and two kept bytes.
//! - A2 and B2 byte 1: action bits 0..4, bit 5, counter bits 6..7; B2's "0xEE fault"
//!   does not fit 5 bits and is recognised on the whole byte ([`B2::is_fault`]).
//! - KLV (0xF4): the data bytes are kept as present on the wire (57 when padded);
//!   `valid_len` (byte 3) says how many count. AI (0xF3): 8 header bytes and 0..=4
//!   targets of 13 bytes.
//! - The frame counter is kept in [`Header::counter`]; decoding accepts any value and
//!   emitting writes the one given.
//! - Sign conventions are the document's: ArduPilot sends pitch angles and rates
//!   negated (positive down) and reads B1 pitch negated.
//! - Directions in [`CATALOG`]: section 2.2 lists the handshake (0x00) and heartbeat
//!   (0x10) as payload to console, but 2.3 c) and ArduPilot send them to the payload
//!   (which answers with 0x40): the catalogue says console to payload
//!   ([`Direction::ToGimbal`], with [`CatalogEntry::from_ahrs`] for the AHRS's M);
//!   decoding does not depend on the direction.
//! - Transparent data (0xFF) is copied into [`Transparent`] (at most 60 bytes, one
//!   frame's payload), so every typed message owns its data; only [`Raw`] borrows.
//! - A1 0x0E (listed "reserved") has the click-to-track parameters of 3.3.1.7; E1 0x06
//!   and 0x07 (listed "reserved") the speed parameters of 3.11.1; C2 0x08 and 0x14 the
//!   parameters of 3.8.1 (whose headings are garbled). Fields the document calls
//!   unsigned but gives signed ranges (click coordinates, gyro bias) are signed.

#[macro_use]
mod block;
mod frame;

mod ahrs;
mod combinations;
mod config;
mod control;
mod enums;
mod packets;
mod status;
pub mod tcp;

pub use crate::Direction;
pub use crate::Text;
pub use ahrs::*;
pub use block::{Block, Bytes, Date, FixedBlock, TimeCs};
pub use combinations::*;
pub use config::*;
pub use control::*;
pub use enums::*;
pub use frame::{
    Frame, FrameCounter, HEADER_LEN, MAX_BODY_LEN, MAX_FRAME_LEN, MAX_PAYLOAD_LEN, MIN_BODY_LEN,
    MIN_FRAME_LEN, SYNC, SYNC_SWAPPED, SyncOrder, ViewlinkFraming, len_byte,
};
pub use packets::*;
pub use status::*;

use crate::wire::{Reader, Writer};
use crate::{Error, Result};

pub use crate::wire::MessageData;

/// One entry of [`CATALOG`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CatalogEntry {
    /// The frame id.
    pub id: u8,
    /// The [`Message`] variant's name.
    pub name: &'static str,
    /// The blocks, as section 2.2 writes them.
    pub blocks: &'static str,
    /// Which way the frame travels.
    pub direction: Direction,
    /// Sent to the gimbal by the AHRS (the flight controller's sensor output, M) rather
    /// than by the console.
    pub from_ahrs: bool,
}

/// The sender column of the frame table.
#[derive(Clone, Copy)]
enum Sender {
    /// The console, to the gimbal.
    ToGimbal,
    /// The AHRS (M), to the gimbal.
    FromAhrs,
    /// The gimbal (the document's "payload"), to the console.
    FromGimbal,
}

use Sender::{FromAhrs, FromGimbal, ToGimbal};

impl CatalogEntry {
    /// The entry of a table row (the encoded length of its message is not listed).
    const fn new(
        id: u8,
        name: &'static str,
        _lens: &[usize],
        blocks: &'static str,
        sender: Sender,
    ) -> Self {
        let (direction, from_ahrs) = match sender {
            ToGimbal => (Direction::ToGimbal, false),
            FromAhrs => (Direction::ToGimbal, true),
            FromGimbal => (Direction::FromGimbal, false),
        };
        CatalogEntry {
            id,
            name,
            blocks,
            direction,
            from_ahrs,
        }
    }
}

// Every frame id: its [`Message`] variant and payload type, the blocks as section 2.2
// writes them, and who sends it. 0x42 and 0x92 carry the layouts of 0x40 and 0x29 under
// types of their own.
message_table! {
    /// The Viewlink protocol: every payload type implements [`MessageData`] with
    /// `Protocol = Viewlink`.
    ///
    /// ```
    /// use protocol_core::viewlink::{M, MessageData, Status, StatusOsd};
    /// assert_eq!(Status::ID, 0x40);
    /// assert_eq!(StatusOsd::ID, 0x42);
    /// assert_eq!(Status::NAME, "Status");
    /// assert_eq!(Status::ENCODED_LEN, 41);
    /// assert_eq!(M::ENCODED_LEN, 42); // the largest M
    /// ```
    protocol Viewlink { id: u8, key: u8, order: Be, lengths: variable, encoders: inlined }
    /// Every frame id this codec knows, in the order of section 2.2.
    catalog;
    /// A decoded frame: what its payload means, by frame id.
    message Message [Eq] {
        /// A frame id this codec does not know, with its payload.
        Raw;
    }
    /// 0x30: A1 + C1 + E1.
    0x30 Control: Message(Control) => "A1+C1+E1", ToGimbal;
    /// 0x32: A1 + C1 + E1 + S1.
    0x32 ControlTgcc: Message(ControlTgcc) => "A1+C1+E1+S1", ToGimbal;
    /// 0x1A: A1 alone.
    0x1A A1: Message(A1) => "A1", ToGimbal;
    /// 0x1C: C1 alone.
    0x1C C1: Message(C1) => "C1", ToGimbal;
    /// 0x1E: E1 alone.
    0x1E E1: Message(E1) => "E1", ToGimbal;
    /// 0x16: S1 alone.
    0x16 S1: Message(S1) => "S1", ToGimbal;
    /// 0x31: A2 + C2 + E2.
    0x31 RareControl: Message(RareControl) => "A2+C2+E2", ToGimbal;
    /// 0x33: A2 + C2 + E2 + S2.
    0x33 RareControlTgcc: Message(RareControlTgcc) => "A2+C2+E2+S2", ToGimbal;
    /// 0x2A: A2 alone.
    0x2A A2: Message(A2) => "A2", ToGimbal;
    /// 0x2C: C2 alone.
    0x2C C2: Message(C2) => "C2", ToGimbal;
    /// 0x2E: E2 alone.
    0x2E E2: Message(E2) => "E2", ToGimbal;
    /// 0x26: S2 alone.
    0x26 S2: Message(S2) => "S2", ToGimbal;
    /// 0x01: U, configuration control.
    0x01 U: Message(U) => "U", ToGimbal;
    /// 0x02: V, configuration status.
    0x02 V: Message(V) => "V", FromGimbal;
    /// 0x40: T1 + F1 + B1 + D1.
    0x40 Status: Message(Status) => "T1+F1+B1+D1", FromGimbal;
    /// 0x42: T1 + F1 + B1 + D1, sent to refresh the OSD (payload to console).
    0x42 StatusOsd: Message(StatusOsd(Status)) => "T1+F1+B1+D1 (refresh OSD)", FromGimbal;
    /// 0x41: T2 + F2 + B2 + D2.
    0x41 RareStatus: Message(RareStatus) => "T2+F2+B2+D2", FromGimbal;
    /// 0xB1: M, AHRS data.
    0xB1 M: Message(M) => "M", FromAhrs;
    /// 0xF3: AI identification feedback.
    0xF3 AiTargets: Message(AiTargets) => "F3 (AI identify)", FromGimbal;
    /// 0xF4: KLV data.
    0xF4 Klv: Message(Klv) => "F4 (KLV)", ToGimbal;
    /// 0x00: handshake.
    0x00 Handshake: Message(Handshake) => "SH (handshake)", ToGimbal;
    /// 0x10: heartbeat.
    0x10 Heartbeat: Message(Heartbeat) => "HB (heartbeat)", ToGimbal;
    /// 0xAC: ACK.
    0xAC Ack: Message(Ack) => "ACK", FromGimbal;
    /// 0x1D: D1 alone.
    0x1D D1: Message(D1) => "D1", FromGimbal;
    /// 0x1B: B1 alone.
    0x1B B1: Message(B1) => "B1", FromGimbal;
    /// 0x1F: F1 alone.
    0x1F F1: Message(F1) => "F1", FromGimbal;
    /// 0x17: T1 alone.
    0x17 T1: Message(T1) => "T1", FromGimbal;
    /// 0x27: T2 alone.
    0x27 T2: Message(T2) => "T2", FromGimbal;
    /// 0x2F: F2 alone.
    0x2F F2: Message(F2) => "F2", FromGimbal;
    /// 0x2B: B2 alone.
    0x2B B2: Message(B2) => "B2", FromGimbal;
    /// 0x2D: D2 alone.
    0x2D D2: Message(D2) => "D2", FromGimbal;
    /// 0xFF: transparent data.
    0xFF Transparent: Message(Transparent) => "FW (transparent)", FromGimbal;
    /// 0x5D: SD card query.
    0x5D SdQuery: Message(SdQuery) => "CMD_SD", ToGimbal;
    /// 0xD5: SD card feedback.
    0xD5 SdFeedback: Message(SdFeedback) => "ACK_SD", FromGimbal;
    /// 0x19: IP query.
    0x19 IpQuery: Message(IpQuery) => "IP_INQ", ToGimbal;
    /// 0x29: IP set.
    0x29 IpSet: Message(IpAddress) => "IP_SET", ToGimbal;
    /// 0x92: IP feedback, the gimbal's IP address (payload to console).
    0x92 IpFeedback: Message(IpFeedback(IpAddress)) => "ACK_IP", FromGimbal;
}

wire_derive! {
    [Eq]
    /// A frame id this codec does not know, with its payload.
    pub struct Raw<'a> {
        /// The frame id.
        pub id: u8,
        /// The payload (data) bytes.
        pub payload: &'a [u8],
    }
}

wire_derive! {
    [Eq, Hash, Default]
    /// Everything of a frame but its message: the sync order and the frame counter.
    pub struct Header {
        /// The sync bytes (standard `55 AA DC` unless a frame came swapped).
        pub sync: SyncOrder,
        /// The frame counter (LEN bits 6..7, 0..=3).
        pub counter: u8,
    }
}

impl Header {
    /// A header with standard sync bytes and frame counter `counter` (see
    /// [`FrameCounter::next_header`]).
    #[must_use]
    pub const fn new(counter: u8) -> Self {
        Header {
            sync: SyncOrder::Standard,
            counter,
        }
    }
}

wire_derive! {
    [Eq]
    /// A whole Viewlink frame: the header (sync order, frame counter) and the message.
    pub struct Packet<'a> {
        /// Sync order and frame counter.
        pub header: Header,
        /// What the payload means.
        pub message: Message<'a>,
    }
}

impl<'a> Packet<'a> {
    /// A packet of `message` with `header`.
    #[must_use]
    pub const fn new(header: Header, message: Message<'a>) -> Self {
        Packet { header, message }
    }

    /// Parses a frame view (its checksum is not verified here: the deframer or
    /// [`Frame::verify`] does that).
    ///
    /// # Errors
    /// The frame's own length errors ([`Frame::check_len`]) and those of
    /// [`Message::decode`].
    pub fn parse(frame: &Frame<&'a [u8]>) -> Result<Self> {
        frame.check_len()?;
        Ok(Packet {
            header: Header {
                sync: frame.sync_order(),
                counter: frame.counter(),
            },
            message: Message::decode(frame.id(), frame.payload_ref())?,
        })
    }

    /// Checks, verifies and parses a complete frame (bytes after it are ignored).
    ///
    /// # Errors
    /// As [`Frame::new_checked`], [`Frame::verify`] and [`Packet::parse`].
    pub fn decode(bytes: &'a [u8]) -> Result<Self> {
        let frame = Frame::new_checked(bytes)?;
        frame.verify()?;
        Packet::parse(&frame)
    }

    /// Length of the encoded frame.
    #[must_use]
    pub fn buffer_len(&self) -> usize {
        self.message.payload_len().saturating_add(HEADER_LEN + 1)
    }

    /// Encodes the frame into `buf` and returns its length.
    ///
    /// # Errors
    /// [`Error::BadLength`] for a payload longer than 60 bytes (or empty),
    /// [`Error::OutOfRange`] for a counter above 3 or a bit field whose value does not
    /// fit its bits, [`Error::BufferTooSmall`] when `buf` is shorter than
    /// [`Packet::buffer_len`].
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize> {
        emit_frame(
            self.header,
            self.message.id(),
            self.message.payload_len(),
            buf,
            |w| self.message.encode(w),
        )
    }
}

impl<'a> From<Message<'a>> for Packet<'a> {
    fn from(message: Message<'a>) -> Self {
        Packet::new(Header::default(), message)
    }
}

/// Encodes one typed message as a whole frame into `buf` and returns its length:
/// `viewlink::encode(&status, &counter.next_header(), &mut buf)`.
///
/// ```
/// use protocol_core::viewlink::{self, B1, FrameCounter, ServoCommand, Status};
///
/// // A gimbal's status reply (frame 0x40), as ArduPilot reads it.
/// let mut counter = FrameCounter::new();
/// let status = Status {
///     b1: B1 { servo: ServoCommand::FollowYaw, yaw_bam16: 0x2000, ..B1::default() },
///     ..Status::default()
/// };
/// let mut buf = [0u8; viewlink::MAX_FRAME_LEN];
/// let n = viewlink::encode(&status, &counter.next_header(), &mut buf)?;
/// assert_eq!(n, 47);
/// assert_eq!(&buf[..5], &[0x55, 0xAA, 0xDC, 0x6C, 0x40]); // LEN 44, counter 1
/// # Ok::<(), protocol_core::Error>(())
/// ```
///
/// # Errors
/// As [`Packet::emit`].
pub fn encode<M: MessageData<Protocol = Viewlink>>(
    message: &M,
    header: &Header,
    buf: &mut [u8],
) -> Result<usize> {
    emit_frame(*header, M::ID, message.payload_len(), buf, |w| {
        message.encode_payload(w)
    })
}

/// Writes sync bytes, LEN, id, payload (through `payload`) and checksum.
fn emit_frame(
    header: Header,
    id: u8,
    payload_len: usize,
    buf: &mut [u8],
    payload: impl FnOnce(&mut Writer<'_>) -> Result<()>,
) -> Result<usize> {
    if header.counter > 3 {
        return Err(Error::OutOfRange);
    }
    if payload_len == 0 || payload_len > MAX_PAYLOAD_LEN {
        return Err(Error::BadLength);
    }
    let total = payload_len.saturating_add(HEADER_LEN + 1);
    let body = u8::try_from(total.saturating_sub(3)).map_err(|_| Error::BadLength)?;
    let buf = buf.get_mut(..total).ok_or(Error::BufferTooSmall)?;
    let mut frame = Frame::new_unchecked(&mut *buf);
    frame.set_sync_order(header.sync);
    frame.set_len(body, header.counter);
    frame.set_id(id);
    let mut w = Writer::new(frame.payload_mut());
    payload(&mut w)?;
    if w.len() != payload_len {
        return Err(Error::BadLength);
    }
    frame.fill_checksum();
    Ok(total)
}

/// Reads a block from the front of `payload` and returns it with the rest (a helper for
/// parsing block combinations that are not frames of their own).
///
/// # Errors
/// As [`Block::read_block`].
pub fn read_block<B: Block>(payload: &[u8]) -> Result<(B, &[u8])> {
    let mut r = Reader::new(payload);
    let b = B::read_block(&mut r)?;
    Ok((b, r.rest()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn catalog_has_37_distinct_ids() {
        assert_eq!(CATALOG.len(), 37);
        for (i, a) in CATALOG.iter().enumerate() {
            assert!(CATALOG[i + 1..].iter().all(|b| b.id != a.id), "{:#x}", a.id);
        }
    }

    #[test]
    fn combination_lengths_follow_section_2_2() {
        assert_eq!(<Control as FixedBlock>::LEN, 14);
        assert_eq!(<ControlTgcc as FixedBlock>::LEN, 28);
        assert_eq!(<RareControl as FixedBlock>::LEN, 10);
        assert_eq!(<RareControlTgcc as FixedBlock>::LEN, 15);
        assert_eq!(<Status as FixedBlock>::LEN, 41);
        assert_eq!(<RareStatus as FixedBlock>::LEN, 49);
        assert_eq!(<U as FixedBlock>::LEN, 10);
    }

    #[test]
    fn typed_messages_know_their_ids() {
        assert_eq!((Status::ID, StatusOsd::ID), (0x40, 0x42));
        assert_eq!((IpAddress::ID, IpFeedback::ID), (0x29, 0x92));
        assert_eq!((IpAddress::NAME, IpFeedback::NAME), ("IpSet", "IpFeedback"));
        assert_eq!(Transparent::ENCODED_LEN, MAX_PAYLOAD_LEN);
        assert_eq!(V::ENCODED_LEN, 23);
        let status = Status::default();
        let mut buf = [0u8; MAX_FRAME_LEN];
        let n = encode(&StatusOsd(status), &Header::new(2), &mut buf).unwrap();
        let p = Packet::decode(&buf[..n]).unwrap();
        assert_eq!(p.header, Header::new(2));
        assert_eq!(p.message.get::<StatusOsd>(), Some(StatusOsd(status)));
        assert_eq!(p.message.get::<Status>(), None);
        assert_eq!(p.message, Message::from(StatusOsd(status)));
        let mut again = [0u8; MAX_FRAME_LEN];
        assert_eq!(p.emit(&mut again), Ok(n));
        assert_eq!(again[..n], buf[..n]);
        let swapped = Header {
            sync: SyncOrder::Swapped,
            counter: 3,
        };
        let n = encode(&Heartbeat { value: 0 }, &swapped, &mut buf).unwrap();
        assert_eq!(&buf[..n], &[0xAA, 0x55, 0xDC, 0xC4, 0x10, 0x00, 0xD4]);
        assert_eq!(Packet::decode(&buf[..n]).unwrap().header, swapped);
        let mut counter = FrameCounter::new();
        let headers: [Header; 4] = core::array::from_fn(|_| counter.next_header());
        assert_eq!(headers.map(|h| h.counter), [1, 2, 3, 0]);
    }

    #[test]
    fn zoom_in_example() {
        let f = [
            0x55, 0xAA, 0xDC, 0x11, 0x30, 0x0F, 0, 0, 0, 0, 0, 0, 0, 0, 0x02, 0x78, 0, 0, 0, 0x54,
        ];
        let p = Packet::decode(&f).unwrap();
        let Message::Control(c) = p.message else {
            panic!("{p:?}")
        };
        assert_eq!(c.c1.operation, OperationCommand::ZoomIn);
        assert_eq!(c.c1.zoom_speed, 7);
        let mut out = [0u8; MAX_FRAME_LEN];
        let n = p.emit(&mut out).unwrap();
        assert_eq!(&out[..n], &f);
    }
}
