//! The SIYI gimbal camera SDK protocol (`003_d4f397a57e673bf9.txt`, completed by
//! `siyi-commands.md`).
//!
//! Frame: `55 66 CTRL LEN(u16 LE) SEQ(u16 LE) CMD DATA CRC16(LE)`, CRC-16/XMODEM over
//! everything before the CRC; 115200 8N1 on the UART. All data fields little-endian.
//!
//! - [`Frame`] is the checked zero-copy view; [`Ctrl`] the CTRL flags (`need_ack`,
//!   `is_ack`); [`SiyiFraming`] plugs the protocol into the shared
//!   [`Deframer`](crate::wire::Deframer), with a configurable maximum data length.
//! - [`Packet`] (CTRL, sequence and a [`Message`]) parses from a frame and emits into a
//!   buffer. [`Message`] is a [`Request`] (flight controller to gimbal), a [`Reply`]
//!   (gimbal to flight controller, including pushed data) or [`Raw`].
//! - [`CATALOG`] lists the 48 command ids, each with both directions.
//!
//! # Direction
//! One command id means a request one way and a reply the other (0x0D is an empty
//! request from the flight controller and a 12-byte attitude from the gimbal), and the
//! frame does not say reliably which one it is: ArduPilot sets CTRL = 1 on every
//! request and ignores CTRL on replies, gimbals reply with CTRL = 2 but may push data
//! (0x0B, streamed 0x0D) with other values. So decoding takes a [`Direction`]:
//! - [`Packet::decode`] / [`Packet::parse`] with the direction the caller knows (a
//!   bridge knows which port a frame came from). This is the reliable way.
//! - [`Packet::decode_auto`] for captures of unknown origin: the direction the CTRL
//!   `is_ack` flag suggests ([`Direction::from_ctrl`]), and if the data length does not
//!   fit that direction's layout, the other direction.
//!
//! Encoding writes the CTRL byte the [`Packet`] carries: [`Packet::request`] uses
//! CTRL = 1 (need_ack, as ArduPilot sends), [`Packet::reply`] CTRL = 2 (is_ack, as SIYI
//! gimbals send). A reply encodes exactly the layout ArduPilot's `AP_Mount_Siyi` parses
//! (it checks the exact length of 0x01, 0x0B, 0x0D, 0x14 and 0x05 replies).
//!
//! # Decisions where the documents are silent (see the README)
//! - Data lengths are exact: a length other than the layout's is [`Error::BadLength`],
//!   except the variants seen in the wild, which decode and re-encode to the same
//!   length: 0x00 heartbeat with 0 or 1 byte (the document's example carries 0x00),
//!   0x01 reply with 8 or 12 bytes, 0x0A reply with 5..=8 bytes, 0x20 reply with 8 or 9
//!   bytes (without or with the frame rate; ArduPilot accepts both).
//! - Directions a command does not use carry no data ([`Empty`]): the requests of the
//!   "get" commands, and the replies of 0x00, 0x0C, 0x22 and 0x3E.
//! - The one-byte results whose meaning the document does not spell out (0x35 reply) are
//!   [`SetStatus`] like the other `sta` bytes.
//! - Temperatures are u16 in 0.01 °C as typed in the document (the low-gain range reaches
//!   550 °C, beyond i16); ArduPilot reads 0x14 as i16.
//! - Hardware id: the product is the first two characters read as hex (either case);
//!   both 0x82 (document) and 0x83 (ArduPilot) are ZT6; [`HardwareId::for_product`] writes
//!   upper case and 0x83 for ZT6, which ArduPilot recognises.
//! - The firmware version words keep their ignored high byte, so decoding is lossless.
//! - Unknown command ids decode to [`Raw`] (with the direction used), never an error.

#[macro_use]
mod field;
mod frame;

mod camera;
mod gimbal;
mod laser;
mod system;
mod thermal;

pub use camera::*;
pub use field::{
    AckStatus, Empty, FirmwareVersion, HardwareId, OnOff, Payload, Product, SetStatus,
};
pub use frame::{
    CRC_LEN, Ctrl, DEFAULT_MAX_DATA_LEN, DEFAULT_MAX_FRAME_LEN, Frame, HEADER_LEN, MAX_DATA_LEN,
    MIN_FRAME_LEN, STX, SiyiFraming,
};
pub use gimbal::*;
pub use laser::*;
pub use system::*;
pub use thermal::*;

use crate::wire::Writer;
use crate::{Error, Result};

/// Which way a message travels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Direction {
    /// Flight controller (or ground station) to gimbal: a command or a query.
    Request,
    /// Gimbal to flight controller: the reply (ACK) to a request, or pushed data.
    Reply,
}

impl Direction {
    /// The direction the CTRL byte suggests: [`Direction::Reply`] when `is_ack` is set,
    /// else [`Direction::Request`]. A hint only (see the module documentation).
    pub const fn from_ctrl(ctrl: Ctrl) -> Self {
        if ctrl.is_ack() {
            Direction::Reply
        } else {
            Direction::Request
        }
    }

    /// The other direction.
    pub const fn reverse(self) -> Self {
        match self {
            Direction::Request => Direction::Reply,
            Direction::Reply => Direction::Request,
        }
    }
}

/// One entry of [`CATALOG`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CatalogEntry {
    /// Command id.
    pub cmd: u8,
    /// Name of the command.
    pub name: &'static str,
    /// The request carries no data.
    pub request_empty: bool,
    /// The reply carries no data (the gimbal sends none).
    pub reply_empty: bool,
}

macro_rules! is_empty {
    (Empty) => {
        true
    };
    ($t:ident) => {
        false
    };
}

/// Declares every command: id, name, request type and reply type. Generates
/// [`Request`], [`Reply`] and [`CATALOG`] from the one table.
macro_rules! messages {
    ($( $cmd:literal $name:ident { request: $req:ident, reply: $rep:ident $(,)? } )*) => {
        /// Flight controller to gimbal: one variant per command id.
        #[derive(Debug, Clone, Copy, PartialEq)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        #[cfg_attr(feature = "serde", derive(serde::Serialize))]
        pub enum Request {
            $(
                #[doc = concat!("Command ", stringify!($cmd), ", flight controller to gimbal: [`", stringify!($req), "`].")]
                $name($req),
            )*
        }

        /// Gimbal to flight controller (replies and pushed data): one variant per id.
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        #[cfg_attr(feature = "serde", derive(serde::Serialize))]
        pub enum Reply {
            $(
                #[doc = concat!("Command ", stringify!($cmd), ", gimbal to flight controller: [`", stringify!($rep), "`].")]
                $name($rep),
            )*
        }

        impl Request {
            /// The command id.
            pub const fn cmd(&self) -> u8 {
                match self { $( Self::$name(_) => $cmd, )* }
            }
            /// The command name.
            pub const fn name(&self) -> &'static str {
                match self { $( Self::$name(_) => stringify!($name), )* }
            }
            /// Encoded data length.
            pub fn data_len(&self) -> usize {
                match self { $( Self::$name(m) => Payload::encoded_len(m), )* }
            }
            /// Decodes the data of a known id (`None` for an unknown id).
            pub fn decode(cmd: u8, data: &[u8]) -> Option<Result<Self>> {
                match cmd {
                    $( $cmd => Some(<$req as Payload>::decode(data).map(Self::$name)), )*
                    _ => None,
                }
            }
            /// Writes the data.
            pub fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
                match self { $( Self::$name(m) => Payload::encode(m, w), )* }
            }
        }

        impl Reply {
            /// The command id.
            pub const fn cmd(&self) -> u8 {
                match self { $( Self::$name(_) => $cmd, )* }
            }
            /// The command name.
            pub const fn name(&self) -> &'static str {
                match self { $( Self::$name(_) => stringify!($name), )* }
            }
            /// Encoded data length.
            pub fn data_len(&self) -> usize {
                match self { $( Self::$name(m) => Payload::encoded_len(m), )* }
            }
            /// Decodes the data of a known id (`None` for an unknown id).
            pub fn decode(cmd: u8, data: &[u8]) -> Option<Result<Self>> {
                match cmd {
                    $( $cmd => Some(<$rep as Payload>::decode(data).map(Self::$name)), )*
                    _ => None,
                }
            }
            /// Writes the data.
            pub fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
                match self { $( Self::$name(m) => Payload::encode(m, w), )* }
            }
        }

        /// Every command id this codec knows, in id order, each with both directions.
        pub const CATALOG: &[CatalogEntry] = &[$(
            CatalogEntry {
                cmd: $cmd,
                name: stringify!($name),
                request_empty: is_empty!($req),
                reply_empty: is_empty!($rep),
            },
        )*];
    };
}

messages! {
    0x00 Heartbeat { request: Heartbeat, reply: Empty }
    0x01 FirmwareVersion { request: Empty, reply: FirmwareVersions }
    0x02 HardwareId { request: Empty, reply: HardwareId }
    0x04 AutoFocus { request: AutoFocus, reply: SetStatus }
    0x05 ManualZoom { request: ManualZoom, reply: ZoomRatio }
    0x06 ManualFocus { request: ManualFocus, reply: SetStatus }
    0x07 GimbalRotation { request: GimbalRotation, reply: SetStatus }
    0x08 Center { request: Center, reply: SetStatus }
    0x0A GimbalConfig { request: Empty, reply: GimbalConfig }
    0x0B FunctionFeedback { request: Empty, reply: FunctionFeedback }
    0x0C CameraFunction { request: CameraFunction, reply: Empty }
    0x0D GimbalAttitude { request: Empty, reply: GimbalAttitude }
    0x0E SetAngles { request: SetAngles, reply: Angles }
    0x0F AbsoluteZoom { request: ZoomLevel, reply: SetStatus }
    0x10 GetStitching { request: Empty, reply: Stitching }
    0x11 SetStitching { request: Stitching, reply: Stitching }
    0x12 PointTemperature { request: PointTemperatureRequest, reply: PointTemperature }
    0x13 BoxTemperature { request: BoxTemperatureRequest, reply: BoxTemperature }
    0x14 GlobalTemperature { request: GlobalTemperatureRequest, reply: GlobalTemperature }
    0x15 LaserDistance { request: Empty, reply: LaserDistance }
    0x16 MaxZoom { request: Empty, reply: ZoomLevel }
    0x17 LaserTarget { request: Empty, reply: LaserTarget }
    0x18 CurrentZoom { request: Empty, reply: ZoomLevel }
    0x19 GimbalMode { request: Empty, reply: GimbalMode }
    0x1A GetThermalPalette { request: Empty, reply: ThermalPalette }
    0x1B SetThermalPalette { request: ThermalPalette, reply: ThermalPalette }
    0x20 GetCodec { request: CodecQuery, reply: CodecSpecs }
    0x21 SetCodec { request: SetCodec, reply: SetCodecAck }
    0x22 FcAttitude { request: FcAttitude, reply: Empty }
    0x24 FcDataStream { request: FcStreamRequest, reply: FcStreamAck }
    0x25 GimbalDataStream { request: GimbalStreamRequest, reply: GimbalStreamAck }
    0x26 MagneticEncoder { request: Empty, reply: Angles }
    0x30 SetUtcTime { request: UtcTime, reply: TimeAck }
    0x31 GetLaserState { request: Empty, reply: LaserState }
    0x32 SetLaserState { request: LaserState, reply: SetStatus }
    0x33 GetThermalOutput { request: Empty, reply: ThermalOutputMode }
    0x34 SetThermalOutput { request: ThermalOutputMode, reply: ThermalOutputMode }
    0x35 TemperatureFrame { request: Empty, reply: SetStatus }
    0x37 GetThermalGain { request: Empty, reply: ThermalGain }
    0x38 SetThermalGain { request: ThermalGain, reply: ThermalGain }
    0x39 GetThermalEnvironment { request: Empty, reply: ThermalEnvironment }
    0x3A SetThermalEnvironment { request: ThermalEnvironment, reply: SetStatus }
    0x3B GetEnvCorrection { request: Empty, reply: EnvCorrection }
    0x3C SetEnvCorrection { request: EnvCorrection, reply: EnvCorrection }
    0x3E FcPosition { request: FcPosition, reply: Empty }
    0x41 SingleAxisAngle { request: SingleAxisAngle, reply: Angles }
    0x48 FormatSd { request: Empty, reply: SetStatus }
    0x80 SoftReboot { request: SoftReboot, reply: SoftReboot }
}

/// A message of a command id this codec does not know, with its data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Raw<'a> {
    /// The direction it was decoded for.
    pub direction: Direction,
    /// The command id.
    pub cmd: u8,
    /// The data bytes.
    pub data: &'a [u8],
}

/// The typed content of a frame.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Message<'a> {
    /// Flight controller to gimbal.
    Request(Request),
    /// Gimbal to flight controller.
    Reply(Reply),
    /// Unknown command id.
    Raw(Raw<'a>),
}

impl<'a> Message<'a> {
    /// Decodes the data of command `cmd` travelling in `direction`. Unknown ids give
    /// [`Message::Raw`]; a known id whose data length its layout does not allow is
    /// [`Error::BadLength`].
    pub fn decode(direction: Direction, cmd: u8, data: &'a [u8]) -> Result<Self> {
        let known = match direction {
            Direction::Request => Request::decode(cmd, data).map(|r| r.map(Message::Request)),
            Direction::Reply => Reply::decode(cmd, data).map(|r| r.map(Message::Reply)),
        };
        known.unwrap_or(Ok(Message::Raw(Raw {
            direction,
            cmd,
            data,
        })))
    }

    /// The direction.
    pub const fn direction(&self) -> Direction {
        match self {
            Message::Request(_) => Direction::Request,
            Message::Reply(_) => Direction::Reply,
            Message::Raw(r) => r.direction,
        }
    }

    /// The command id.
    pub const fn cmd(&self) -> u8 {
        match self {
            Message::Request(m) => m.cmd(),
            Message::Reply(m) => m.cmd(),
            Message::Raw(r) => r.cmd,
        }
    }

    /// The command name (`"Raw"` for unknown ids).
    pub const fn name(&self) -> &'static str {
        match self {
            Message::Request(m) => m.name(),
            Message::Reply(m) => m.name(),
            Message::Raw(_) => "Raw",
        }
    }

    /// Encoded data length.
    pub fn data_len(&self) -> usize {
        match self {
            Message::Request(m) => m.data_len(),
            Message::Reply(m) => m.data_len(),
            Message::Raw(r) => r.data.len(),
        }
    }

    /// Writes the data.
    pub fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
        match self {
            Message::Request(m) => m.encode(w),
            Message::Reply(m) => m.encode(w),
            Message::Raw(r) => w.put(r.data),
        }
    }
}

impl From<Request> for Message<'_> {
    fn from(m: Request) -> Self {
        Message::Request(m)
    }
}

impl From<Reply> for Message<'_> {
    fn from(m: Reply) -> Self {
        Message::Reply(m)
    }
}

/// A whole SIYI packet: CTRL, sequence number and message.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Packet<'a> {
    /// The CTRL byte (kept as received; not interpreted by decoding).
    pub ctrl: Ctrl,
    /// Sequence number.
    pub seq: u16,
    /// The message.
    pub message: Message<'a>,
}

impl<'a> Packet<'a> {
    /// A request with CTRL = 1 (need_ack), as ArduPilot sends.
    pub const fn request(seq: u16, request: Request) -> Self {
        Packet {
            ctrl: Ctrl::NEED_ACK,
            seq,
            message: Message::Request(request),
        }
    }

    /// A reply with CTRL = 2 (is_ack), as SIYI gimbals send.
    pub const fn reply(seq: u16, reply: Reply) -> Self {
        Packet {
            ctrl: Ctrl::IS_ACK,
            seq,
            message: Message::Reply(reply),
        }
    }

    /// Parses a frame view travelling in `direction` (its CRC is not verified here: the
    /// deframer or [`Frame::verify`] does that).
    pub fn parse(frame: &Frame<&'a [u8]>, direction: Direction) -> Result<Self> {
        frame.check_len()?;
        Ok(Packet {
            ctrl: frame.ctrl(),
            seq: frame.seq(),
            message: Message::decode(direction, frame.cmd(), frame.data_ref())?,
        })
    }

    /// Checks, verifies and parses a complete frame travelling in `direction`.
    pub fn decode(bytes: &'a [u8], direction: Direction) -> Result<Self> {
        let frame = Frame::new_checked(bytes)?;
        frame.verify()?;
        Packet::parse(&frame, direction)
    }

    /// Checks, verifies and parses a complete frame whose direction is not known: the
    /// direction of [`Direction::from_ctrl`], or the other one when only that one fits
    /// the data length.
    pub fn decode_auto(bytes: &'a [u8]) -> Result<Self> {
        let frame = Frame::new_checked(bytes)?;
        frame.verify()?;
        let guess = Direction::from_ctrl(frame.ctrl());
        match Packet::parse(&frame, guess) {
            Err(Error::BadLength) => {
                Packet::parse(&frame, guess.reverse()).map_err(|_| Error::BadLength)
            }
            other => other,
        }
    }

    /// Length of the encoded frame.
    pub fn buffer_len(&self) -> usize {
        MIN_FRAME_LEN.saturating_add(self.message.data_len())
    }

    /// Encodes the frame into `buf` and returns its length.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize> {
        let data_len = u16::try_from(self.message.data_len()).map_err(|_| Error::BadLength)?;
        let total = self.buffer_len();
        let buf = buf.get_mut(..total).ok_or(Error::BufferTooSmall)?;
        let mut frame = Frame::new_unchecked(&mut *buf);
        frame.set_start(data_len);
        frame.set_ctrl(self.ctrl);
        frame.set_seq(self.seq);
        frame.set_cmd(self.message.cmd());
        let mut w = Writer::new(frame.data_mut());
        self.message.encode(&mut w)?;
        if w.len() != usize::from(data_len) {
            return Err(Error::BadLength);
        }
        frame.fill_checksum();
        Ok(total)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn catalog_has_48_distinct_ids_in_order() {
        assert_eq!(CATALOG.len(), 48);
        for w in CATALOG.windows(2) {
            assert!(w[0].cmd < w[1].cmd, "{:#04x}", w[1].cmd);
        }
    }

    #[test]
    fn document_heartbeat_round_trips() {
        let hb = [
            0x55, 0x66, 0x01, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x59, 0x8B,
        ];
        let p = Packet::decode(&hb, Direction::Request).unwrap();
        assert_eq!(p.ctrl, Ctrl::NEED_ACK);
        assert_eq!(
            p.message,
            Message::Request(Request::Heartbeat(Heartbeat::DOCUMENT))
        );
        let mut out = [0u8; 16];
        let n = p.emit(&mut out).unwrap();
        assert_eq!(&out[..n], &hb);
    }
}
