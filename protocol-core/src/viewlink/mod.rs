//! The Viewlink (Viewpro) serial protocol V3.4.4 (`004_97d9a16052f5b223.txt`).
//!
//! Frame: `55 AA DC LEN ID DATA XOR`, 115200 8N1. LEN bits 0..5 count the bytes from LEN
//! through the checksum (4..=63), bits 6..7 are a frame counter; the checksum is the
//! XOR of LEN (counter bits included) through the last data byte. Data fields are
//! big-endian. The data of a frame is one packet block or a fixed combination of
//! blocks, selected by the frame id ([`CATALOG`], 37 ids).
//!
//! - [`Frame`] is the checked zero-copy view; [`ViewlinkFraming`] plugs the protocol into
//!   the shared [`Deframer`](crate::wire::Deframer).
//! - [`Packet`] (sync order, frame counter and a [`Message`]) parses from a frame and
//!   emits into a buffer; [`FrameCounter`] produces the counter a sender keeps.
//! - Every block is a typed struct or enum implementing [`Block`]: [`A1`] [`A2`] [`B1`]
//!   [`B2`] [`C1`] [`C2`] [`D1`] [`D2`] [`E1`] [`E2`] [`F1`] [`F2`] [`S1`] [`S2`] [`T1`]
//!   [`T2`] [`M`] [`U`] [`V`] and the small packets.
//! - [`tcp`] is the TCP envelope `EB 90 LEN BODY SUM`.
//!
//! # Decisions where the document is ambiguous (see the README)
//! - The length byte is authoritative: a fixed-size block with more or fewer bytes is
//!   [`Error::BadLength`]. Printed examples with a spurious or missing byte are rejected
//!   (their checksum byte is not at the position LEN gives); the deframer then
//!   resynchronises on the next sync bytes.
//! - Sync: frames are sent `55 AA DC`; `AA 55 DC` (the document's ACK example) is
//!   decoded too and re-encoded as received ([`HeaderOrder`]). The deframer accepts one
//!   order ([`ViewlinkFraming::swapped`] for the other).
//! - C1 is a big-endian `u16` with a 7-bit operation command (bits 6..12), as the bit
//!   table, every example and ArduPilot have it (the prose says 3 bits).
//! - Blocks whose parameters depend on a command byte (A1, C2, E2, S1, U, the SD
//!   feedback) are enums with one variant per command with defined parameters; the
//!   other commands keep their parameter bytes in a `Plain` variant. Reserved bytes and
//!   bits, and unlisted enumeration values, are kept, so every decoded frame re-encodes
//!   byte for byte; encoding a bit field whose value does not fit is
//!   [`Error::OutOfRange`].
//! - M (0xB1): data-type bit 0 selects the 6-byte attitude group (roll, pitch, yaw, per
//!   SPEC-NOTES), bit 1 the 28-byte GPS group; the document defines no bytes for the
//!   gyro bit (2), so it adds none. Byte 1 and the seven reserved bytes 2..8 are always
//!   present: an M packet has 8, 14, 36 or 42 bytes. Date: day bits 15..11, month
//!   10..7, year-2000 6..0; time: 3 bytes of 0.01 s since UTC midnight.
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
//! - The frame counter is kept in [`Packet::counter`]; decoding accepts any value and
//!   emitting writes the one given.
//! - Sign conventions are the document's: ArduPilot sends pitch angles and rates
//!   negated (positive down) and reads B1 pitch negated.
//! - Directions in [`CATALOG`]: section 2.2 lists the handshake (0x00) and heartbeat
//!   (0x10) as payload to console, but 2.3 c) and ArduPilot send them to the payload
//!   (which answers with 0x40): the catalogue says console to payload; decoding does
//!   not depend on the direction.
//! - A1 0x0E (listed "reserved") has the click-to-track parameters of 3.3.1.7; E1 0x06
//!   and 0x07 (listed "reserved") the speed parameters of 3.11.1; C2 0x08 and 0x14 the
//!   parameters of 3.8.1 (whose headings are garbled). Fields the document calls
//!   unsigned but gives signed ranges (click coordinates, gyro bias) are signed.

#[macro_use]
mod block;
mod frame;

mod ahrs;
mod config;
mod control;
mod enums;
mod packets;
mod status;
pub mod tcp;

pub use crate::Text;
pub use ahrs::*;
pub use block::{Block, Bytes, Date, FixedBlock, TimeCs};
pub use config::*;
pub use control::*;
pub use enums::*;
pub use frame::{
    Frame, FrameCounter, HeaderOrder, MAX_BODY_LEN, MAX_DATA_LEN, MAX_FRAME_LEN, MIN_BODY_LEN,
    MIN_FRAME_LEN, SYNC, SYNC_SWAPPED, ViewlinkFraming, len_byte,
};
pub use packets::*;
pub use status::*;

use crate::wire::{Reader, Writer};
use crate::{Error, Result};

wire_struct! {
    Be;
    /// Frame 0x30: A1 + C1 + E1 (14 bytes), console to payload.
    pub struct Control {
        /// Servo control.
        pub a1: A1,
        /// Optical control.
        pub c1: C1,
        /// Tracking command.
        pub e1: E1,
    }
}

wire_struct! {
    Be;
    /// Frame 0x32: A1 + C1 + E1 + S1 (28 bytes), console to payload.
    pub struct ControlTgcc {
        /// Servo control.
        pub a1: A1,
        /// Optical control.
        pub c1: C1,
        /// Tracking command.
        pub e1: E1,
        /// Target calculation control.
        pub s1: S1,
    }
}

wire_struct! {
    Be;
    /// Frame 0x31: A2 + C2 + E2 (10 bytes), console to payload.
    pub struct RareControl {
        /// Servo control, infrequent.
        pub a2: A2,
        /// Optical control, infrequent.
        pub c2: C2,
        /// Tracking command, infrequent.
        pub e2: E2,
    }
}

wire_struct! {
    Be;
    /// Frame 0x33: A2 + C2 + E2 + S2 (15 bytes), console to payload.
    pub struct RareControlTgcc {
        /// Servo control, infrequent.
        pub a2: A2,
        /// Optical control, infrequent.
        pub c2: C2,
        /// Tracking command, infrequent.
        pub e2: E2,
        /// Target calculation control, infrequent.
        pub s2: S2,
    }
}

wire_struct! {
    Be;
    /// Frames 0x40 and 0x42: T1 + F1 + B1 + D1 (41 bytes), payload to console: the
    /// status a gimbal sends in reply to control frames and heartbeats (ArduPilot reads
    /// 0x40).
    pub struct Status {
        /// Target calculation status.
        pub t1: T1,
        /// Tracker status.
        pub f1: F1,
        /// Servo status.
        pub b1: B1,
        /// Optical status.
        pub d1: D1,
    }
}

wire_struct! {
    Be;
    /// Frame 0x41: T2 + F2 + B2 + D2 (49 bytes), payload to console: sent once when an
    /// A2 asks for it.
    pub struct RareStatus {
        /// Target calculation status, infrequent.
        pub t2: T2,
        /// Tracker status, infrequent.
        pub f2: F2,
        /// Servo status, infrequent.
        pub b2: B2,
        /// Optical status, infrequent.
        pub d2: D2,
    }
}

wire_derive! {
    [Eq, Hash]
    /// Who sends a frame.
    pub enum Direction {
        /// Console (flight controller, ground station) to payload (gimbal).
        ToPayload,
        /// Payload to console.
        FromPayload,
        /// AHRS (flight controller) to payload.
        FromAhrs,
    }
}

impl Direction {
    /// A short name.
    pub const fn as_str(self) -> &'static str {
        match self {
            Direction::ToPayload => "console->payload",
            Direction::FromPayload => "payload->console",
            Direction::FromAhrs => "ahrs->payload",
        }
    }
}

/// One entry of [`CATALOG`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CatalogEntry {
    /// The frame id.
    pub id: u8,
    /// The [`Message`] variant's name.
    pub name: &'static str,
    /// The blocks, as section 2.2 writes them.
    pub blocks: &'static str,
    /// Who sends it.
    pub direction: Direction,
}

/// Declares every frame id with its [`Message`] variant and block type; generates
/// [`Message`], its decoding and encoding, and [`CATALOG`] from the one table.
macro_rules! frames {
    ($(
        $(#[$m:meta])* $id:literal $variant:ident($ty:ty), $blocks:literal, $dir:ident;
    )*) => {
        /// A decoded frame: what its data means, by frame id.
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        #[cfg_attr(feature = "serde", derive(serde::Serialize))]
        pub enum Message<'a> {
            $( $(#[$m])* $variant($ty), )*
            /// A frame id this codec does not know, with its data.
            Raw(Raw<'a>),
        }

        impl<'a> Message<'a> {
            /// Decodes the data of a frame. Unknown ids give [`Message::Raw`]; a known id
            /// whose data has the wrong length is [`Error::BadLength`].
            pub fn decode(id: u8, data: &'a [u8]) -> Result<Self> {
                match id {
                    $( $id => <$ty as Block>::from_bytes(data).map(Message::$variant), )*
                    _ => Ok(Message::Raw(Raw { id, data })),
                }
            }

            /// The frame id.
            pub const fn id(&self) -> u8 {
                match self {
                    $( Message::$variant(_) => $id, )*
                    Message::Raw(r) => r.id,
                }
            }

            /// The variant's name (`"Raw"` for unknown ids).
            pub const fn name(&self) -> &'static str {
                match self {
                    $( Message::$variant(_) => stringify!($variant), )*
                    Message::Raw(_) => "Raw",
                }
            }

            /// Encoded data length.
            pub fn data_len(&self) -> usize {
                match self {
                    $( Message::$variant(m) => m.block_len(), )*
                    Message::Raw(r) => r.data.len(),
                }
            }

            /// Writes the data.
            pub fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
                match self {
                    $( Message::$variant(m) => m.write_block(w), )*
                    Message::Raw(r) => w.put(r.data),
                }
            }
        }

        /// Every frame id this codec knows, in the order of section 2.2.
        pub const CATALOG: &[CatalogEntry] = &[$(
            CatalogEntry {
                id: $id,
                name: stringify!($variant),
                blocks: $blocks,
                direction: Direction::$dir,
            },
        )*];
    };
}

frames! {
    /// 0x30: A1 + C1 + E1.
    0x30 Control(Control), "A1+C1+E1", ToPayload;
    /// 0x32: A1 + C1 + E1 + S1.
    0x32 ControlTgcc(ControlTgcc), "A1+C1+E1+S1", ToPayload;
    /// 0x1A: A1 alone.
    0x1A A1(A1), "A1", ToPayload;
    /// 0x1C: C1 alone.
    0x1C C1(C1), "C1", ToPayload;
    /// 0x1E: E1 alone.
    0x1E E1(E1), "E1", ToPayload;
    /// 0x16: S1 alone.
    0x16 S1(S1), "S1", ToPayload;
    /// 0x31: A2 + C2 + E2.
    0x31 RareControl(RareControl), "A2+C2+E2", ToPayload;
    /// 0x33: A2 + C2 + E2 + S2.
    0x33 RareControlTgcc(RareControlTgcc), "A2+C2+E2+S2", ToPayload;
    /// 0x2A: A2 alone.
    0x2A A2(A2), "A2", ToPayload;
    /// 0x2C: C2 alone.
    0x2C C2(C2), "C2", ToPayload;
    /// 0x2E: E2 alone.
    0x2E E2(E2), "E2", ToPayload;
    /// 0x26: S2 alone.
    0x26 S2(S2), "S2", ToPayload;
    /// 0x01: U, configuration control.
    0x01 U(U), "U", ToPayload;
    /// 0x02: V, configuration status.
    0x02 V(V), "V", FromPayload;
    /// 0x40: T1 + F1 + B1 + D1.
    0x40 Status(Status), "T1+F1+B1+D1", FromPayload;
    /// 0x42: T1 + F1 + B1 + D1, OSD refresh.
    0x42 StatusOsd(Status), "T1+F1+B1+D1 (refresh OSD)", FromPayload;
    /// 0x41: T2 + F2 + B2 + D2.
    0x41 RareStatus(RareStatus), "T2+F2+B2+D2", FromPayload;
    /// 0xB1: M, AHRS data.
    0xB1 M(M), "M", FromAhrs;
    /// 0xF3: AI identification feedback.
    0xF3 AiTargets(AiTargets), "F3 (AI identify)", FromPayload;
    /// 0xF4: KLV data.
    0xF4 Klv(Klv), "F4 (KLV)", ToPayload;
    /// 0x00: handshake.
    0x00 Handshake(Handshake), "SH (handshake)", ToPayload;
    /// 0x10: heartbeat.
    0x10 Heartbeat(Heartbeat), "HB (heartbeat)", ToPayload;
    /// 0xAC: ACK.
    0xAC Ack(Ack), "ACK", FromPayload;
    /// 0x1D: D1 alone.
    0x1D D1(D1), "D1", FromPayload;
    /// 0x1B: B1 alone.
    0x1B B1(B1), "B1", FromPayload;
    /// 0x1F: F1 alone.
    0x1F F1(F1), "F1", FromPayload;
    /// 0x17: T1 alone.
    0x17 T1(T1), "T1", FromPayload;
    /// 0x27: T2 alone.
    0x27 T2(T2), "T2", FromPayload;
    /// 0x2F: F2 alone.
    0x2F F2(F2), "F2", FromPayload;
    /// 0x2B: B2 alone.
    0x2B B2(B2), "B2", FromPayload;
    /// 0x2D: D2 alone.
    0x2D D2(D2), "D2", FromPayload;
    /// 0xFF: transparent data.
    0xFF Transparent(Transparent), "FW (transparent)", FromPayload;
    /// 0x5D: SD card query.
    0x5D SdQuery(SdQuery), "CMD_SD", ToPayload;
    /// 0xD5: SD card feedback.
    0xD5 SdFeedback(SdFeedback), "ACK_SD", FromPayload;
    /// 0x19: IP query.
    0x19 IpQuery(IpQuery), "IP_INQ", ToPayload;
    /// 0x29: IP set.
    0x29 IpSet(IpAddress), "IP_SET", ToPayload;
    /// 0x92: IP feedback.
    0x92 IpFeedback(IpAddress), "ACK_IP", FromPayload;
}

wire_derive! {
    [Eq]
    /// A frame id this codec does not know, with its data.
    pub struct Raw<'a> {
        /// The frame id.
        pub id: u8,
        /// The data bytes.
        pub data: &'a [u8],
    }
}

wire_derive! {
    [Eq]
    /// A whole Viewlink frame: sync order, frame counter and message.
    pub struct Packet<'a> {
        /// The sync bytes.
        pub header: HeaderOrder,
        /// The frame counter (LEN bits 6..7, 0..=3).
        pub counter: u8,
        /// The message.
        pub message: Message<'a>,
    }
}

impl<'a> Packet<'a> {
    /// A packet with standard sync bytes.
    pub const fn new(counter: u8, message: Message<'a>) -> Self {
        Packet {
            header: HeaderOrder::Standard,
            counter,
            message,
        }
    }

    /// Parses a frame view (its checksum is not verified here: the deframer or
    /// [`Frame::verify`] does that).
    pub fn parse(frame: &Frame<&'a [u8]>) -> Result<Self> {
        frame.check_len()?;
        Ok(Packet {
            header: frame.header(),
            counter: frame.counter(),
            message: Message::decode(frame.frame_id(), frame.data_ref())?,
        })
    }

    /// Checks, verifies and parses a complete frame (bytes after it are ignored).
    pub fn decode(bytes: &'a [u8]) -> Result<Self> {
        let frame = Frame::new_checked(bytes)?;
        frame.verify()?;
        Packet::parse(&frame)
    }

    /// Length of the encoded frame.
    pub fn buffer_len(&self) -> usize {
        self.message.data_len().saturating_add(MIN_FRAME_LEN - 1)
    }

    /// Encodes the frame into `buf` and returns its length. A message longer than 60
    /// data bytes (or empty) is [`Error::BadLength`]; a counter above 3 is
    /// [`Error::OutOfRange`].
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize> {
        if self.counter > 3 {
            return Err(Error::OutOfRange);
        }
        let data_len = self.message.data_len();
        if data_len == 0 || data_len > MAX_DATA_LEN {
            return Err(Error::BadLength);
        }
        let total = self.buffer_len();
        let body = u8::try_from(total.saturating_sub(3)).map_err(|_| Error::BadLength)?;
        let buf = buf.get_mut(..total).ok_or(Error::BufferTooSmall)?;
        let mut frame = Frame::new_unchecked(&mut *buf);
        frame.set_header(self.header);
        frame.set_len(body, self.counter);
        frame.set_frame_id(self.message.id());
        let mut w = Writer::new(frame.data_mut());
        self.message.encode(&mut w)?;
        if w.len() != data_len {
            return Err(Error::BadLength);
        }
        frame.fill_checksum();
        Ok(total)
    }
}

impl<'a> From<Message<'a>> for Packet<'a> {
    fn from(message: Message<'a>) -> Self {
        Packet::new(0, message)
    }
}

/// Reads a block from the front of `data` and returns it with the rest (a helper for
/// parsing block combinations that are not frames of their own).
pub fn read_block<B: Block>(data: &[u8]) -> Result<(B, &[u8])> {
    let mut r = Reader::new(data);
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
