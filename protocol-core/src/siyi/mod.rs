//! The SIYI gimbal camera SDK protocol (the command ids its tables lack taken from SIYI's
//! public "External SDK Protocol" V0.1.1; see docs/src/protocols/siyi.md).
//!
//! Frame: `55 66 CTRL LEN(u16 LE) SEQ(u16 LE) CMD DATA CRC16(LE)`, CRC-16/XMODEM over
//! everything before the CRC; 115200 8N1 on the UART. All data fields little-endian.
//!
//! ```
//! use protocol_core::Direction;
//! use protocol_core::siyi::{
//!     self, GimbalAttitude, GimbalAttitudeQuery, Header, Packet, SiyiFraming,
//! };
//! use protocol_core::wire::{Deframer, Event};
//!
//! // A gimbal (or a bridge acting as one) answers 0x0D with its attitude.
//! let attitude = GimbalAttitude {
//!     yaw_deg_x10: -9,
//!     pitch_deg_x10: -880,
//!     roll_deg_x10: 0,
//!     yaw_rate_dps_x10: -3,
//!     pitch_rate_dps_x10: -129,
//!     roll_rate_dps_x10: 0,
//! };
//! let mut buf = [0u8; siyi::DEFAULT_MAX_FRAME_LEN];
//! let n = siyi::encode(&attitude, &Header::reply(6), &mut buf)?;
//! assert_eq!(&buf[..n], &[0x55, 0x66, 0x02, 0x0C, 0x00, 0x06, 0x00, 0x0D, 0xF7, 0xFF,
//!                         0x90, 0xFC, 0x00, 0x00, 0xFD, 0xFF, 0x7F, 0xFF, 0x00, 0x00,
//!                         0x89, 0x4B]);
//!
//! // The flight controller finds it in its byte stream and decodes it as a reply.
//! let mut deframer = Deframer::<_, { siyi::DEFAULT_MAX_FRAME_LEN }>::new(SiyiFraming::default());
//! let mut found = None;
//! deframer.push(&buf[..n], |event| {
//!     if let Event::Frame(bytes) = event {
//!         found = Packet::decode(bytes, Direction::FromGimbal)
//!             .ok()
//!             .and_then(|p| p.message.get::<GimbalAttitude>());
//!     }
//! });
//! assert_eq!(found, Some(attitude));
//!
//! // The request it answers: an empty 0x0D, CTRL = 1 as ArduPilot sends it.
//! let n = siyi::encode(&GimbalAttitudeQuery {}, &Header::request(0), &mut buf)?;
//! let request = Packet::decode(&buf[..n], Direction::ToGimbal)?;
//! assert!(request.message.get::<GimbalAttitudeQuery>().is_some());
//! # Ok::<(), protocol_core::Error>(())
//! ```
//!
//! - [`Frame`] is the checked zero-copy view; [`Ctrl`] the CTRL flags (`need_ack`,
//!   `is_ack`); [`SiyiFraming`] plugs the protocol into the shared
//!   [`Deframer`](crate::wire::Deframer), with a configurable maximum payload length.
//! - [`Packet`] (a [`Header`]: CTRL and sequence number; and a [`Message`]) parses from
//!   a frame and emits into a buffer. [`Message`] is a [`Request`] (flight controller to
//!   gimbal, [`Direction::ToGimbal`]), a [`Reply`] (gimbal to flight controller,
//!   including pushed data, [`Direction::FromGimbal`]) or [`Raw`].
//! - Every (command id, direction) has its own payload type implementing
//!   [`MessageData`] (id, name, length; `Protocol = `[`Siyi`]) and [`Directed`] (its
//!   direction), so one message is sent with
//!   [`encode`] and recognised with [`Message::get`]. Where several messages share a
//!   layout, each has a newtype over it ([`GimbalRotationAck`]`(`[`SetStatus`]`)`,
//!   [`CurrentZoom`]`(`[`ZoomLevel`]`)`); a direction without data has an empty struct
//!   ([`FirmwareVersionQuery`]` {}`).
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
//!   `is_ack` flag suggests ([`Ctrl::direction`]), and if the payload length does not
//!   fit that direction's layout, the other direction.
//!
//! Encoding writes the CTRL byte the [`Header`] carries: [`Header::request`] is CTRL = 1
//! (need_ack, as ArduPilot sends), [`Header::reply`] CTRL = 2 (is_ack, as SIYI gimbals
//! send). A reply encodes exactly the layout ArduPilot's `AP_Mount_Siyi` parses (it
//! checks the exact length of 0x01, 0x0B, 0x0D, 0x14 and 0x05 replies).
//!
//! # Decisions where the documents are silent (see docs/src/protocols/siyi.md)
//! - Payload lengths are exact: a length other than the layout's is
//!   [`Error::BadLength`], except the variants seen in the wild, which decode and
//!   re-encode to the same length: 0x00 heartbeat with 0 or 1 byte (the document's
//!   example carries 0x00), 0x01 reply with 8 or 12 bytes, 0x0A reply with 5..=8 bytes,
//!   0x20 reply with 8 or 9 bytes (without or with the frame rate; ArduPilot accepts
//!   both). [`MessageData::ENCODED_LEN`] is the longest of these.
//! - Directions a command does not use carry no data (empty structs): the requests of
//!   the "get" commands and of 0x0B, and the replies of 0x00, 0x0C, 0x22 and 0x3E.
//! - The one-byte results whose meaning the document does not spell out (0x35 reply) are
//!   [`SetStatus`] like the other `sta` bytes.
//! - Temperatures are u16 in 0.01 °C as typed in the document (the low-gain range reaches
//!   550 °C, beyond i16); ArduPilot reads 0x14 as i16.
//! - Hardware id: the product is the first two characters read as hex (either case);
//!   both 0x82 (document) and 0x83 (ArduPilot) are ZT6; [`HardwareId::for_product`] writes
//!   upper case and 0x83 for ZT6, which ArduPilot recognises.
//! - The firmware version words keep their ignored high byte, so decoding is lossless.
//! - Unknown command ids decode to [`Raw`] (with the direction used), never an error.

mod frame;
mod payload;

mod camera;
mod gimbal;
mod laser;
mod system;
mod thermal;

pub use crate::Direction;
pub use camera::*;
pub use frame::{
    CRC_LEN, Ctrl, DEFAULT_MAX_FRAME_LEN, DEFAULT_MAX_PAYLOAD_LEN, Frame, HEADER_LEN,
    MAX_PAYLOAD_LEN, MIN_FRAME_LEN, STX, SiyiFraming,
};
pub use gimbal::*;
pub use laser::*;
pub use payload::{AckStatus, FirmwareVersion, HardwareId, OnOff, Payload, Product, SetStatus};
pub use system::*;
pub use thermal::*;

use crate::wire::Writer;
use crate::{Error, Result};

pub use crate::wire::MessageData;

/// The direction a SIYI payload type travels in: each command id has a payload type per
/// direction (implemented by the message table; the same id has another type the other
/// way).
pub trait Directed {
    /// [`Direction::ToGimbal`] for a request, [`Direction::FromGimbal`] for a reply.
    const DIRECTION: Direction;
}

/// One entry of [`CATALOG`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CatalogEntry {
    /// Command id.
    pub id: u8,
    /// Name of the command.
    pub name: &'static str,
    /// The request carries no data.
    pub request_empty: bool,
    /// The reply carries no data (the gimbal sends none).
    pub reply_empty: bool,
}

impl CatalogEntry {
    /// The entry of a table row with the longest encoded lengths of its request and its
    /// reply.
    const fn new(id: u8, name: &'static str, lens: &[usize]) -> Self {
        let (request_empty, reply_empty) = match lens {
            [request, reply, ..] => (*request == 0, *reply == 0),
            _ => (false, false),
        };
        CatalogEntry {
            id,
            name,
            request_empty,
            reply_empty,
        }
    }
}

// Every command: its request (flight controller to gimbal) and its reply (gimbal to flight
// controller, pushed data included). A direction without data is an empty struct
// (`FirmwareVersionQuery {}`), a message sharing another's layout a newtype over it
// (`GimbalRotationAck(SetStatus)`), decoded through that layout's one function (~900 bytes
// less for SIYI than a decoder per newtype).
message_table! {
    /// The SIYI gimbal camera SDK protocol: every payload type implements
    /// [`MessageData`] with `Protocol = Siyi`, and [`Directed`].
    ///
    /// ```
    /// use protocol_core::Direction;
    /// use protocol_core::siyi::{
    ///     Directed, FirmwareVersions, GimbalRotationAck, MessageData, SetStatus,
    /// };
    /// assert_eq!(GimbalRotationAck::ID, 0x07);
    /// assert_eq!(GimbalRotationAck::DIRECTION, Direction::FromGimbal);
    /// assert_eq!(GimbalRotationAck::NAME, "GimbalRotation");
    /// assert_eq!(GimbalRotationAck::ENCODED_LEN, 1);
    /// // Variable-length replies give their longest layout.
    /// assert_eq!(FirmwareVersions::ENCODED_LEN, 12);
    /// ```
    protocol Siyi { id: u8, key: u8, order: Le, lengths: variable, encoders: inlined }
    /// Every command id this codec knows, in id order, each with both directions.
    catalog;
    /// A decoded message: what the payload of a frame means.
    message Message [] {
        /// Unknown command id.
        Raw;
        /// Flight controller to gimbal ([`Direction::ToGimbal`]): one variant per command
        /// id.
        Request [] impl Directed {
            const DIRECTION: Direction = Direction::ToGimbal;
        };
        /// Gimbal to flight controller ([`Direction::FromGimbal`]; replies and pushed
        /// data): one variant per command id.
        Reply [Eq] impl Directed {
            const DIRECTION: Direction = Direction::FromGimbal;
        };
    }
    0x00 Heartbeat: Request(Heartbeat), Reply(HeartbeatReply {});
    0x01 FirmwareVersion: Request(FirmwareVersionQuery {}), Reply(FirmwareVersions);
    0x02 HardwareId: Request(HardwareIdQuery {}), Reply(HardwareId);
    0x04 AutoFocus: Request(AutoFocus), Reply(AutoFocusAck(SetStatus));
    0x05 ManualZoom: Request(ManualZoom), Reply(ZoomRatio);
    0x06 ManualFocus: Request(ManualFocus), Reply(ManualFocusAck(SetStatus));
    0x07 GimbalRotation: Request(GimbalRotation), Reply(GimbalRotationAck(SetStatus));
    0x08 Center: Request(Center), Reply(CenterAck(SetStatus));
    0x0A GimbalConfig: Request(GimbalConfigQuery {}), Reply(GimbalConfig);
    0x0B FunctionFeedback: Request(FunctionFeedbackRequest {}), Reply(FunctionFeedback);
    0x0C CameraFunction: Request(CameraFunction), Reply(CameraFunctionReply {});
    0x0D GimbalAttitude: Request(GimbalAttitudeQuery {}), Reply(GimbalAttitude);
    0x0E SetAngles: Request(SetAngles), Reply(SetAnglesAck(Angles));
    0x0F AbsoluteZoom: Request(AbsoluteZoom(ZoomLevel)), Reply(AbsoluteZoomAck(SetStatus));
    0x10 GetStitching: Request(GetStitching {}), Reply(Stitching);
    0x11 SetStitching: Request(SetStitching(Stitching)), Reply(SetStitchingAck(Stitching));
    0x12 PointTemperature: Request(PointTemperatureRequest), Reply(PointTemperature);
    0x13 BoxTemperature: Request(BoxTemperatureRequest), Reply(BoxTemperature);
    0x14 GlobalTemperature: Request(GlobalTemperatureRequest), Reply(GlobalTemperature);
    0x15 LaserDistance: Request(LaserDistanceQuery {}), Reply(LaserDistance);
    0x16 MaxZoom: Request(MaxZoomQuery {}), Reply(MaxZoom(ZoomLevel));
    0x17 LaserTarget: Request(LaserTargetQuery {}), Reply(LaserTarget);
    0x18 CurrentZoom: Request(CurrentZoomQuery {}), Reply(CurrentZoom(ZoomLevel));
    0x19 GimbalMode: Request(GimbalModeQuery {}), Reply(GimbalMode);
    0x1A GetThermalPalette: Request(GetThermalPalette {}), Reply(ThermalPalette);
    0x1B SetThermalPalette:
        Request(SetThermalPalette(ThermalPalette)), Reply(SetThermalPaletteAck(ThermalPalette));
    0x20 GetCodec: Request(CodecQuery), Reply(CodecSpecs);
    0x21 SetCodec: Request(SetCodec), Reply(SetCodecAck);
    0x22 FcAttitude: Request(FcAttitude), Reply(FcAttitudeReply {});
    0x24 FcDataStream: Request(FcStreamRequest), Reply(FcStreamAck);
    0x25 GimbalDataStream: Request(GimbalStreamRequest), Reply(GimbalStreamAck);
    0x26 MagneticEncoder: Request(MagneticEncoderQuery {}), Reply(MagneticEncoder(Angles));
    0x30 SetUtcTime: Request(UtcTime), Reply(TimeAck);
    0x31 GetLaserState: Request(GetLaserState {}), Reply(LaserState);
    0x32 SetLaserState: Request(SetLaserState(LaserState)), Reply(SetLaserStateAck(SetStatus));
    0x33 GetThermalOutput: Request(GetThermalOutput {}), Reply(ThermalOutputMode);
    0x34 SetThermalOutput:
        Request(SetThermalOutput(ThermalOutputMode)), Reply(SetThermalOutputAck(ThermalOutputMode));
    0x35 TemperatureFrame: Request(TemperatureFrame {}), Reply(TemperatureFrameAck(SetStatus));
    0x37 GetThermalGain: Request(GetThermalGain {}), Reply(ThermalGain);
    0x38 SetThermalGain:
        Request(SetThermalGain(ThermalGain)), Reply(SetThermalGainAck(ThermalGain));
    0x39 GetThermalEnvironment: Request(GetThermalEnvironment {}), Reply(ThermalEnvironment);
    0x3A SetThermalEnvironment:
        Request(SetThermalEnvironment(ThermalEnvironment)),
        Reply(SetThermalEnvironmentAck(SetStatus));
    0x3B GetEnvCorrection: Request(GetEnvCorrection {}), Reply(EnvCorrection);
    0x3C SetEnvCorrection:
        Request(SetEnvCorrection(EnvCorrection)), Reply(SetEnvCorrectionAck(EnvCorrection));
    0x3E FcPosition: Request(FcPosition), Reply(FcPositionReply {});
    0x41 SingleAxisAngle: Request(SingleAxisAngle), Reply(SingleAxisAngleAck(Angles));
    0x48 FormatSd: Request(FormatSd {}), Reply(FormatSdAck(SetStatus));
    0x80 SoftReboot: Request(SoftReboot), Reply(SoftRebootAck(SoftReboot));
}

wire_derive! {
    [Eq]
    /// A message of a command id this codec does not know, with its payload.
    pub struct Raw<'a> {
        /// The command id.
        pub id: u8,
        /// The payload bytes.
        pub payload: &'a [u8],
        /// The direction it was decoded for.
        pub direction: Direction,
    }
}

impl<'a> Message<'a> {
    /// Decodes the payload of command `id` travelling in `direction`. Unknown ids give
    /// [`Message::Raw`].
    ///
    /// # Errors
    /// [`Error::BadLength`] when a known id's payload length is not one its layout
    /// allows.
    pub fn decode(id: u8, payload: &'a [u8], direction: Direction) -> Result<Self> {
        let known = match direction {
            Direction::ToGimbal => Request::decode(id, payload).map(|r| r.map(Message::Request)),
            Direction::FromGimbal => Reply::decode(id, payload).map(|r| r.map(Message::Reply)),
        };
        known.unwrap_or(Ok(Message::Raw(Raw {
            id,
            payload,
            direction,
        })))
    }

    /// The direction the message was decoded for.
    #[must_use]
    pub const fn direction(&self) -> Direction {
        match self {
            Message::Request(_) => Request::DIRECTION,
            Message::Reply(_) => Reply::DIRECTION,
            Message::Raw(r) => r.direction,
        }
    }
}

wire_derive! {
    [Eq, Hash]
    /// Everything of a frame but its message: the CTRL byte and the sequence number.
    pub struct Header {
        /// The CTRL byte (kept as received; decoding does not interpret it).
        pub ctrl: Ctrl,
        /// Sequence number.
        pub seq: u16,
    }
}

impl Header {
    /// A header with any CTRL byte.
    #[must_use]
    pub const fn new(ctrl: Ctrl, seq: u16) -> Self {
        Header { ctrl, seq }
    }

    /// A request header: CTRL = 1 (need_ack), as ArduPilot sends every request.
    #[must_use]
    pub const fn request(seq: u16) -> Self {
        Header::new(Ctrl::NEED_ACK, seq)
    }

    /// A reply header: CTRL = 2 (is_ack), as SIYI gimbals send their replies.
    #[must_use]
    pub const fn reply(seq: u16) -> Self {
        Header::new(Ctrl::IS_ACK, seq)
    }
}

wire_derive! {
    []
    /// A whole SIYI packet: the header (CTRL, sequence number) and the message.
    pub struct Packet<'a> {
        /// CTRL and sequence number.
        pub header: Header,
        /// What the payload means.
        pub message: Message<'a>,
    }
}

impl<'a> Packet<'a> {
    /// A request with CTRL = 1 (need_ack), as ArduPilot sends.
    #[must_use]
    pub const fn request(seq: u16, request: Request) -> Self {
        Packet {
            header: Header::request(seq),
            message: Message::Request(request),
        }
    }

    /// A reply with CTRL = 2 (is_ack), as SIYI gimbals send.
    #[must_use]
    pub const fn reply(seq: u16, reply: Reply) -> Self {
        Packet {
            header: Header::reply(seq),
            message: Message::Reply(reply),
        }
    }

    /// Parses a frame view travelling in `direction` (its CRC is not verified here: the
    /// deframer or [`Frame::verify`] does that).
    ///
    /// # Errors
    /// The frame's own length errors ([`Frame::check_len`]) and those of
    /// [`Message::decode`].
    pub fn parse(frame: &Frame<&'a [u8]>, direction: Direction) -> Result<Self> {
        frame.check_len()?;
        Ok(Packet {
            header: Header::new(frame.ctrl(), frame.seq()),
            message: Message::decode(frame.id(), frame.payload_ref(), direction)?,
        })
    }

    /// Checks, verifies and parses a complete frame travelling in `direction` (bytes
    /// after it are ignored).
    ///
    /// # Errors
    /// As [`Frame::new_checked`], [`Frame::verify`] and [`Packet::parse`].
    pub fn decode(bytes: &'a [u8], direction: Direction) -> Result<Self> {
        let frame = Frame::new_checked(bytes)?;
        frame.verify()?;
        Packet::parse(&frame, direction)
    }

    /// Checks, verifies and parses a complete frame whose direction is not known: the
    /// direction of [`Ctrl::direction`], or the other one when only that one fits the
    /// payload length.
    ///
    /// # Errors
    /// As [`Packet::decode`]; [`Error::BadLength`] when neither direction's layout fits.
    pub fn decode_auto(bytes: &'a [u8]) -> Result<Self> {
        let frame = Frame::new_checked(bytes)?;
        frame.verify()?;
        let guess = frame.ctrl().direction();
        match Packet::parse(&frame, guess) {
            Err(Error::BadLength) => {
                Packet::parse(&frame, guess.reverse()).map_err(|_| Error::BadLength)
            }
            other => other,
        }
    }

    /// Length of the encoded frame.
    #[must_use]
    pub fn buffer_len(&self) -> usize {
        MIN_FRAME_LEN.saturating_add(self.message.payload_len())
    }

    /// Encodes the frame into `buf` and returns its length.
    ///
    /// # Errors
    /// [`Error::BufferTooSmall`] when `buf` is shorter than [`Packet::buffer_len`] (the
    /// buffer's content is then unspecified); [`Error::BadLength`] for a payload longer
    /// than [`MAX_PAYLOAD_LEN`];
    /// [`Error::OutOfRange`] for a variable-length reply with a trailing field after a
    /// missing one.
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize> {
        emit_frame(self.header, self.message.id(), buf, |w| {
            self.message.encode(w)
        })
    }
}

/// Encodes one typed message as a whole frame into `buf` and returns its length. The
/// CTRL byte is the header's, whatever the message's direction:
/// `siyi::encode(&GimbalAttitude { .. }, &Header::reply(seq), &mut buf)`.
///
/// # Errors
/// [`Error::BufferTooSmall`] when `buf` cannot hold the frame; [`Error::OutOfRange`] for
/// a variable-length reply with a trailing field after a missing one.
pub fn encode<M: MessageData<Protocol = Siyi>>(
    message: &M,
    header: &Header,
    buf: &mut [u8],
) -> Result<usize> {
    emit_frame(*header, M::ID, buf, |w| message.encode_payload(w))
}

/// Writes the payload (through `payload`) after the header's place, then the header
/// (LEN is what the payload wrote) and the CRC.
fn emit_frame(
    header: Header,
    id: u8,
    buf: &mut [u8],
    payload: impl FnOnce(&mut Writer<'_>) -> Result<()>,
) -> Result<usize> {
    let room = buf.len().saturating_sub(CRC_LEN);
    let mut w = Writer::new(buf.get_mut(HEADER_LEN..room).ok_or(Error::BufferTooSmall)?);
    payload(&mut w)?;
    let payload_len = w.len();
    let len_field = u16::try_from(payload_len).map_err(|_| Error::BadLength)?;
    let total = MIN_FRAME_LEN.saturating_add(payload_len);
    let mut frame = Frame::new_unchecked(buf.get_mut(..total).ok_or(Error::BufferTooSmall)?);
    frame.set_start(len_field);
    frame.set_ctrl(header.ctrl);
    frame.set_seq(header.seq);
    frame.set_id(id);
    frame.fill_checksum();
    Ok(total)
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEARTBEAT: [u8; 11] = [
        0x55, 0x66, 0x01, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x59, 0x8B,
    ];
    /// An attitude reply captured from a SIYI gimbal.
    const ATTITUDE: [u8; 22] = [
        0x55, 0x66, 0x02, 0x0C, 0x00, 0x06, 0x00, 0x0D, 0xF7, 0xFF, 0x90, 0xFC, 0x00, 0x00, 0xFD,
        0xFF, 0x7F, 0xFF, 0x00, 0x00, 0x89, 0x4B,
    ];

    #[test]
    fn catalog_has_48_distinct_ids_in_order() {
        assert_eq!(CATALOG.len(), 48);
        for w in CATALOG.windows(2) {
            assert!(w[0].id < w[1].id, "{:#04x}", w[1].id);
        }
    }

    #[test]
    fn document_heartbeat_round_trips() {
        let p = Packet::decode(&HEARTBEAT, Direction::ToGimbal).unwrap();
        assert_eq!(p.header, Header::request(0));
        assert_eq!(
            p.message,
            Message::Request(Request::Heartbeat(Heartbeat::DOCUMENT))
        );
        let mut out = [0u8; 16];
        let n = p.emit(&mut out).unwrap();
        assert_eq!(&out[..n], &HEARTBEAT);
        let n = encode(&Heartbeat::DOCUMENT, &Header::request(0), &mut out).unwrap();
        assert_eq!(&out[..n], &HEARTBEAT);
    }

    #[test]
    fn typed_messages_know_their_ids_and_directions() {
        let p = Packet::decode(&ATTITUDE, Direction::FromGimbal).unwrap();
        assert_eq!(p.header, Header::reply(6));
        let attitude = p.message.get::<GimbalAttitude>().unwrap();
        assert_eq!(attitude.pitch_deg_x10, -880);
        assert_eq!(p.message.get::<GimbalAttitudeQuery>(), None);
        assert_eq!(p.message.get::<SetAnglesAck>(), None);
        assert_eq!(Message::from(attitude), p.message);
        let mut buf = [0u8; DEFAULT_MAX_FRAME_LEN];
        let n = encode(&attitude, &Header::reply(6), &mut buf).unwrap();
        assert_eq!(&buf[..n], &ATTITUDE);

        assert_eq!(GimbalAttitude::ID, 0x0D);
        assert_eq!(GimbalAttitude::DIRECTION, Direction::FromGimbal);
        assert_eq!(GimbalAttitudeQuery::ID, 0x0D);
        assert_eq!(GimbalAttitudeQuery::DIRECTION, Direction::ToGimbal);
        assert_eq!(GimbalAttitudeQuery::ENCODED_LEN, 0);
        assert_eq!(AbsoluteZoom::ID, 0x0F);
        assert_eq!(MaxZoom::ID, 0x16);
        assert_eq!(CurrentZoom::ID, 0x18);
        assert_eq!(SoftRebootAck::DIRECTION, Direction::FromGimbal);
        assert_eq!(GimbalConfig::ENCODED_LEN, 8);
        assert_eq!(CodecSpecs::ENCODED_LEN, 9);
        assert_eq!(Heartbeat::ENCODED_LEN, 1);
        assert_eq!(FcPosition::ENCODED_LEN, 32);

        // The CTRL byte is the header's, not the message's direction.
        let odd = Header::new(Ctrl(0x00), 9);
        let n = encode(&attitude, &odd, &mut buf).unwrap();
        let p = Packet::decode_auto(&buf[..n]).unwrap();
        assert_eq!(p.header, odd);
        assert_eq!(p.message.get::<GimbalAttitude>(), Some(attitude));

        // A newtype over a shared layout: the same bytes, told apart by id.
        let zoom = ZoomLevel {
            integer: 4,
            tenths: 5,
        };
        let n = encode(&CurrentZoom(zoom), &Header::reply(1), &mut buf).unwrap();
        let p = Packet::decode(&buf[..n], Direction::FromGimbal).unwrap();
        assert_eq!(p.message.get::<CurrentZoom>(), Some(CurrentZoom(zoom)));
        assert_eq!(p.message.get::<MaxZoom>(), None);
        assert_eq!(p.message.get::<AbsoluteZoom>(), None);
    }

    #[test]
    fn ctrl_flags() {
        assert_eq!(Ctrl::new(true, false), Ctrl::NEED_ACK);
        assert_eq!(Ctrl::new(false, true), Ctrl::IS_ACK);
        assert_eq!(Ctrl(0xFD).reserved(), 0x3F);
        assert_eq!(Ctrl::IS_ACK.direction(), Direction::FromGimbal);
        assert_eq!(Ctrl::NEED_ACK.direction(), Direction::ToGimbal);
        assert_eq!(Ctrl(0x03).direction(), Direction::FromGimbal);
    }
}
