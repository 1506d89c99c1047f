//! The SIYI gimbal camera SDK protocol (`003_d4f397a57e673bf9.txt`, completed by
//! `siyi-commands.md`).
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
//!   [`MessageData`] (id, direction, name, length), so one message is sent with
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
//! # Decisions where the documents are silent (see the README)
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

/// A typed SIYI message: the payload type of one command id in one direction (after
/// rust-mavlink's `MessageData`). Every payload type implements it, from the one table
/// that also builds [`CATALOG`].
///
/// ```
/// use protocol_core::Direction;
/// use protocol_core::siyi::{GimbalRotationAck, FirmwareVersions, MessageData, SetStatus};
/// assert_eq!(GimbalRotationAck::ID, 0x07);
/// assert_eq!(GimbalRotationAck::DIRECTION, Direction::FromGimbal);
/// assert_eq!(GimbalRotationAck::NAME, "GimbalRotation");
/// assert_eq!(GimbalRotationAck::ENCODED_LEN, 1);
/// // Variable-length replies give their longest layout.
/// assert_eq!(FirmwareVersions::ENCODED_LEN, 12);
/// ```
pub trait MessageData: Payload + Copy {
    /// The command id.
    const ID: u8;
    /// The direction this payload travels in (the same id has another payload type the
    /// other way).
    const DIRECTION: Direction;
    /// The command name, as [`CATALOG`] lists it (shared by both directions).
    const NAME: &'static str;
    /// Encoded payload length in bytes; the longest one for the variable-length replies
    /// (0x00, 0x01, 0x0A, 0x20), see [`Payload::encoded_len`] for a given value.
    const ENCODED_LEN: usize;

    /// This payload as a decoded [`Message`].
    fn into_message(self) -> Message<'static>;

    /// The payload, if `message` is this message (same id and direction).
    fn from_message(message: &Message<'_>) -> Option<Self>;
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

/// Declares the payload types the message table names but no module defines: a
/// direction without data (`Name {}`) or a message sharing another's layout
/// (`Name(Inner)`). A type written alone is defined elsewhere.
///
/// A newtype is the [`Payload`] of its inner layout (not a `Field`, which the blanket
/// implementation would decode): all messages of one layout then share one decode
/// function, as the code size of the firmware wants (~900 bytes less for SIYI).
macro_rules! siyi_payload_type {
    ($what:literal $cmd:literal $msg:ident $name:ident) => {};
    // `$empty:block`: the `{}` of the table (see `siyi_messages!`).
    ($what:literal $cmd:literal $msg:ident $name:ident $empty:block) => {
        wire_struct! {
            Le;
            #[doc = concat!($what, " of ", stringify!($cmd), " (", stringify!($msg), "): no data.")]
            pub struct $name {}
        }
    };
    ($what:literal $cmd:literal $msg:ident $name:ident ($inner:ty)) => {
        wire_derive! {
            [Eq, Hash, Default]
            #[doc = concat!($what, " of ", stringify!($cmd), " (", stringify!($msg), "): the layout of [`", stringify!($inner), "`].")]
            pub struct $name(pub $inner);
        }

        impl Payload for $name {
            const MAX_LEN: usize = <$inner as Payload>::MAX_LEN;
            fn decode(data: &[u8]) -> Result<Self> {
                <$inner as Payload>::decode(data).map(Self)
            }
            fn encoded_len(&self) -> usize {
                self.0.encoded_len()
            }
            fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
                self.0.encode(w)
            }
        }
    };
}

/// Implements [`MessageData`] (and `From` into [`Message`]) for the payload of one
/// command in one direction.
macro_rules! siyi_message_data {
    ($ty:ident, $kind:ident, $direction:ident, $cmd:literal, $name:ident) => {
        impl MessageData for $ty {
            const ID: u8 = $cmd;
            const DIRECTION: Direction = Direction::$direction;
            const NAME: &'static str = stringify!($name);
            const ENCODED_LEN: usize = <$ty as Payload>::MAX_LEN;

            fn into_message(self) -> Message<'static> {
                Message::$kind($kind::$name(self))
            }

            fn from_message(message: &Message<'_>) -> Option<Self> {
                match message {
                    Message::$kind($kind::$name(m)) => Some(*m),
                    _ => None,
                }
            }
        }

        impl From<$ty> for Message<'_> {
            fn from(m: $ty) -> Self {
                m.into_message()
            }
        }
    };
}

/// Generates the methods both per-direction enums ([`Request`], [`Reply`]) have.
macro_rules! siyi_kind_impl {
    ($kind:ident, $direction:ident: $( [$cmd:literal $name:ident $ty:ident] )*) => {
        impl $kind {
            /// The direction of every message of this enum.
            pub const DIRECTION: Direction = Direction::$direction;

            /// The command id.
            #[must_use]
            pub const fn id(&self) -> u8 {
                match self { $( Self::$name(_) => $cmd, )* }
            }
            /// The command name.
            #[must_use]
            pub const fn name(&self) -> &'static str {
                match self { $( Self::$name(_) => stringify!($name), )* }
            }
            /// Encoded payload length.
            #[must_use]
            pub fn payload_len(&self) -> usize {
                match self { $( Self::$name(m) => Payload::encoded_len(m), )* }
            }
            /// Decodes the payload of a known id (`None` for an unknown id).
            ///
            /// # Errors
            /// [`Error::BadLength`] when the payload length is not one the layout allows.
            pub fn decode(id: u8, payload: &[u8]) -> Option<Result<Self>> {
                match id {
                    $( $cmd => Some(<$ty as Payload>::decode(payload).map(Self::$name)), )*
                    _ => None,
                }
            }
            /// Writes the payload.
            ///
            /// # Errors
            /// [`Error::BufferTooSmall`] when `w` has no room for it;
            /// [`Error::OutOfRange`] for a variable-length reply with a trailing field
            /// after a missing one.
            pub fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
                match self { $( Self::$name(m) => Payload::encode(m, w), )* }
            }
        }
    };
}

/// Declares every command: id, name, the request payload and the reply payload.
/// Generates the payload types the table defines, [`Request`], [`Reply`],
/// [`MessageData`] for every payload type, and [`CATALOG`] from the one table, so they
/// cannot disagree.
///
/// A payload is a type defined in a module (`AutoFocus`), an empty struct to define
/// (`FirmwareVersionQuery {}`) or a newtype to define over a shared layout
/// (`GimbalRotationAck(SetStatus)`).
macro_rules! siyi_messages {
    ($(
        $cmd:literal $name:ident {
            // `{}` is matched as a block: an optional `tt` followed by `,` would be
            // ambiguous to the macro parser, a block cannot start with `,`.
            request: $req:ident $($req_empty:block)? $(($req_inner:ty))?,
            reply: $rep:ident $($rep_empty:block)? $(($rep_inner:ty))? $(,)?
        }
    )*) => {
        $( siyi_payload_type!("Request" $cmd $name $req $($req_empty)? $(($req_inner))?); )*
        $( siyi_payload_type!("Reply" $cmd $name $rep $($rep_empty)? $(($rep_inner))?); )*

        wire_derive! {
            []
            /// Flight controller to gimbal ([`Direction::ToGimbal`]): one variant per
            /// command id.
            pub enum Request {
                $(
                    #[doc = concat!("Command ", stringify!($cmd), ", flight controller to gimbal: [`", stringify!($req), "`].")]
                    $name($req),
                )*
            }
        }

        wire_derive! {
            [Eq]
            /// Gimbal to flight controller ([`Direction::FromGimbal`]; replies and pushed
            /// data): one variant per command id.
            pub enum Reply {
                $(
                    #[doc = concat!("Command ", stringify!($cmd), ", gimbal to flight controller: [`", stringify!($rep), "`].")]
                    $name($rep),
                )*
            }
        }

        siyi_kind_impl!(Request, ToGimbal: $( [$cmd $name $req] )*);
        siyi_kind_impl!(Reply, FromGimbal: $( [$cmd $name $rep] )*);

        $( siyi_message_data!($req, Request, ToGimbal, $cmd, $name); )*
        $( siyi_message_data!($rep, Reply, FromGimbal, $cmd, $name); )*

        /// Every command id this codec knows, in id order, each with both directions.
        pub const CATALOG: &[CatalogEntry] = &[$(
            CatalogEntry {
                id: $cmd,
                name: stringify!($name),
                request_empty: <$req as Payload>::MAX_LEN == 0,
                reply_empty: <$rep as Payload>::MAX_LEN == 0,
            },
        )*];
    };
}

siyi_messages! {
    0x00 Heartbeat { request: Heartbeat, reply: HeartbeatReply {} }
    0x01 FirmwareVersion { request: FirmwareVersionQuery {}, reply: FirmwareVersions }
    0x02 HardwareId { request: HardwareIdQuery {}, reply: HardwareId }
    0x04 AutoFocus { request: AutoFocus, reply: AutoFocusAck(SetStatus) }
    0x05 ManualZoom { request: ManualZoom, reply: ZoomRatio }
    0x06 ManualFocus { request: ManualFocus, reply: ManualFocusAck(SetStatus) }
    0x07 GimbalRotation { request: GimbalRotation, reply: GimbalRotationAck(SetStatus) }
    0x08 Center { request: Center, reply: CenterAck(SetStatus) }
    0x0A GimbalConfig { request: GimbalConfigQuery {}, reply: GimbalConfig }
    0x0B FunctionFeedback { request: FunctionFeedbackRequest {}, reply: FunctionFeedback }
    0x0C CameraFunction { request: CameraFunction, reply: CameraFunctionReply {} }
    0x0D GimbalAttitude { request: GimbalAttitudeQuery {}, reply: GimbalAttitude }
    0x0E SetAngles { request: SetAngles, reply: SetAnglesAck(Angles) }
    0x0F AbsoluteZoom { request: AbsoluteZoom(ZoomLevel), reply: AbsoluteZoomAck(SetStatus) }
    0x10 GetStitching { request: GetStitching {}, reply: Stitching }
    0x11 SetStitching { request: SetStitching(Stitching), reply: SetStitchingAck(Stitching) }
    0x12 PointTemperature { request: PointTemperatureRequest, reply: PointTemperature }
    0x13 BoxTemperature { request: BoxTemperatureRequest, reply: BoxTemperature }
    0x14 GlobalTemperature { request: GlobalTemperatureRequest, reply: GlobalTemperature }
    0x15 LaserDistance { request: LaserDistanceQuery {}, reply: LaserDistance }
    0x16 MaxZoom { request: MaxZoomQuery {}, reply: MaxZoom(ZoomLevel) }
    0x17 LaserTarget { request: LaserTargetQuery {}, reply: LaserTarget }
    0x18 CurrentZoom { request: CurrentZoomQuery {}, reply: CurrentZoom(ZoomLevel) }
    0x19 GimbalMode { request: GimbalModeQuery {}, reply: GimbalMode }
    0x1A GetThermalPalette { request: GetThermalPalette {}, reply: ThermalPalette }
    0x1B SetThermalPalette {
        request: SetThermalPalette(ThermalPalette),
        reply: SetThermalPaletteAck(ThermalPalette),
    }
    0x20 GetCodec { request: CodecQuery, reply: CodecSpecs }
    0x21 SetCodec { request: SetCodec, reply: SetCodecAck }
    0x22 FcAttitude { request: FcAttitude, reply: FcAttitudeReply {} }
    0x24 FcDataStream { request: FcStreamRequest, reply: FcStreamAck }
    0x25 GimbalDataStream { request: GimbalStreamRequest, reply: GimbalStreamAck }
    0x26 MagneticEncoder { request: MagneticEncoderQuery {}, reply: MagneticEncoder(Angles) }
    0x30 SetUtcTime { request: UtcTime, reply: TimeAck }
    0x31 GetLaserState { request: GetLaserState {}, reply: LaserState }
    0x32 SetLaserState { request: SetLaserState(LaserState), reply: SetLaserStateAck(SetStatus) }
    0x33 GetThermalOutput { request: GetThermalOutput {}, reply: ThermalOutputMode }
    0x34 SetThermalOutput {
        request: SetThermalOutput(ThermalOutputMode),
        reply: SetThermalOutputAck(ThermalOutputMode),
    }
    0x35 TemperatureFrame { request: TemperatureFrame {}, reply: TemperatureFrameAck(SetStatus) }
    0x37 GetThermalGain { request: GetThermalGain {}, reply: ThermalGain }
    0x38 SetThermalGain {
        request: SetThermalGain(ThermalGain),
        reply: SetThermalGainAck(ThermalGain),
    }
    0x39 GetThermalEnvironment { request: GetThermalEnvironment {}, reply: ThermalEnvironment }
    0x3A SetThermalEnvironment {
        request: SetThermalEnvironment(ThermalEnvironment),
        reply: SetThermalEnvironmentAck(SetStatus),
    }
    0x3B GetEnvCorrection { request: GetEnvCorrection {}, reply: EnvCorrection }
    0x3C SetEnvCorrection {
        request: SetEnvCorrection(EnvCorrection),
        reply: SetEnvCorrectionAck(EnvCorrection),
    }
    0x3E FcPosition { request: FcPosition, reply: FcPositionReply {} }
    0x41 SingleAxisAngle { request: SingleAxisAngle, reply: SingleAxisAngleAck(Angles) }
    0x48 FormatSd { request: FormatSd {}, reply: FormatSdAck(SetStatus) }
    0x80 SoftReboot { request: SoftReboot, reply: SoftRebootAck(SoftReboot) }
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

wire_derive! {
    []
    /// A decoded message: what the payload of a frame means.
    pub enum Message<'a> {
        /// Flight controller to gimbal.
        Request(Request),
        /// Gimbal to flight controller.
        Reply(Reply),
        /// Unknown command id.
        Raw(Raw<'a>),
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

    /// The direction.
    #[must_use]
    pub const fn direction(&self) -> Direction {
        match self {
            Message::Request(_) => Request::DIRECTION,
            Message::Reply(_) => Reply::DIRECTION,
            Message::Raw(r) => r.direction,
        }
    }

    /// The command id.
    #[must_use]
    pub const fn id(&self) -> u8 {
        match self {
            Message::Request(m) => m.id(),
            Message::Reply(m) => m.id(),
            Message::Raw(r) => r.id,
        }
    }

    /// The command name (`"Raw"` for unknown ids).
    #[must_use]
    pub const fn name(&self) -> &'static str {
        match self {
            Message::Request(m) => m.name(),
            Message::Reply(m) => m.name(),
            Message::Raw(_) => "Raw",
        }
    }

    /// Encoded payload length.
    #[must_use]
    pub fn payload_len(&self) -> usize {
        match self {
            Message::Request(m) => m.payload_len(),
            Message::Reply(m) => m.payload_len(),
            Message::Raw(r) => r.payload.len(),
        }
    }

    /// Writes the payload.
    ///
    /// # Errors
    /// [`Error::BufferTooSmall`] when `w` has no room for it; [`Error::OutOfRange`] for
    /// a variable-length reply with a trailing field after a missing one.
    pub fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
        match self {
            Message::Request(m) => m.encode(w),
            Message::Reply(m) => m.encode(w),
            Message::Raw(r) => w.put(r.payload),
        }
    }

    /// The typed payload, if this is message `M` (same id and direction):
    /// `message.get::<GimbalAttitude>()`.
    #[must_use]
    pub fn get<M: MessageData>(&self) -> Option<M> {
        M::from_message(self)
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
        /// The message.
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
pub fn encode<M: MessageData>(message: &M, header: &Header, buf: &mut [u8]) -> Result<usize> {
    emit_frame(*header, M::ID, buf, |w| message.encode(w))
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
