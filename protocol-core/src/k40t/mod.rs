//! The K40T four-sensor pod protocol (`000_cac8f3505cecd78b.txt`).
//!
//! Frame: `FD LEN DST_SYS DST_COMP SEQ SRC_SYS SRC_COMP MSGID(3, LE) PAYLOAD CRC(2, LE)`,
//! 115200 8N1. The message id's high byte is the [`Kind`] (0x00 request or report, 0x01
//! ACK, 0x02 status frame); the low 16 bits are the base id the document lists.
//!
//! ```
//! use protocol_core::k40t::{self, Address, Header, HybridZoom, K40tFraming, Packet};
//! use protocol_core::wire::{Deframer, Event};
//!
//! // Build a message and emit it as a frame.
//! let header = Header::new(Address::FLIGHT_CONTROLLER, Address::POD, 7);
//! let zoom = HybridZoom { start: 0, zoom_x10: 45 };
//! let mut buf = [0u8; k40t::MAX_FRAME_LEN];
//! let n = k40t::encode(&zoom, &header, &mut buf)?;
//! assert_eq!(&buf[..n], &[0xFD, 0x03, 0x04, 0x01, 0x07, 0x02, 0x01, 0x04, 0x03, 0x00,
//!                         0x00, 0x2D, 0x00, 0xCE, 0x89]);
//!
//! // Find it in a byte stream and decode it.
//! let mut deframer = Deframer::<_, { k40t::MAX_FRAME_LEN }>::new(K40tFraming::any());
//! let mut found = None;
//! deframer.push(&buf[..n], |event| {
//!     if let Event::Frame(bytes) = event {
//!         found = Packet::decode(bytes).ok().and_then(|p| p.message.get::<HybridZoom>());
//!     }
//! });
//! assert_eq!(found, Some(zoom));
//! # Ok::<(), protocol_core::Error>(())
//! ```
//!
//! - [`Frame`] is the checked zero-copy view; [`K40tFraming`] plugs the protocol into
//!   the shared [`Deframer`](crate::wire::Deframer).
//! - [`Packet`] (a [`Header`]: addresses, sequence number, CRC coverage; and a
//!   [`Message`]) parses from a frame and emits into a buffer; [`Message`] is
//!   [`Request`], [`Ack`], [`Status`] or [`Raw`].
//! - Every payload type implements [`MessageData`] (its id, name and length), so one
//!   message is sent with [`encode`] and recognised with [`Message::get`].
//! - [`CATALOG`] lists every base id with the kinds it has.
//!
//! # Decisions where the document is silent (see the README)
//! - CRC: CRC-16/MCRF4XX over LEN..payload ([`CrcCoverage::ExcludeStx`], the default) or
//!   STX..payload ([`CrcCoverage::IncludeStx`]); [`Frame::detect_coverage`] tells which.
//! - All payload fields little-endian; the ACK response code is written big-endian and
//!   read in either order ([`ResponseCode`]).
//! - A payload shorter than the document's layout is zero-extended (MAVLink v2 payload
//!   truncation, which the document's LEN description echoes; it also absorbs the
//!   layouts that disagree by a trailing reserved byte); a longer one is an error.
//!   Encoding always writes the full layout.
//! - Reserved bytes and unlisted enumeration values are kept, so every decoded frame
//!   re-encodes byte for byte.
//! - Every request has an ACK (a bare response code unless the document gives data);
//!   periodic reports (0x000001..0x000008) have none.

mod frame;
#[macro_use]
mod payload;

mod camera;
mod common;
mod gimbal;
mod ir;
mod laser_sbus;
mod visible;

pub use crate::Text;
pub use camera::*;
pub use common::*;
pub use frame::{
    Address, CrcCoverage, Frame, HEADER_LEN, K40tFraming, Kind, MAX_FRAME_LEN, MAX_PAYLOAD_LEN,
    MIN_FRAME_LEN, MsgId, STX,
};
pub use gimbal::*;
pub use ir::*;
pub use laser_sbus::*;
pub use payload::{AckCode, ResponseCode, Version};
pub use visible::*;

use crate::wire::Writer;
use crate::wire::encoding::{Field, Le};
use crate::{Error, Result};
use payload::decode_payload;

/// A typed K40T message: a payload type that knows its message id (after rust-mavlink's
/// `MessageData`). Every request, report, ACK and status payload implements it, from
/// the one table that also builds [`CATALOG`].
///
/// ```
/// use protocol_core::k40t::{HybridZoom, MessageData, MsgId, Kind};
/// assert_eq!(HybridZoom::ID, MsgId::new(Kind::Request, 0x0304));
/// assert_eq!(HybridZoom::NAME, "HybridZoom");
/// assert_eq!(HybridZoom::ENCODED_LEN, 3);
/// ```
pub trait MessageData: Field<Le> + Copy {
    /// The message id (kind and base id).
    const ID: MsgId;
    /// The message name, as [`CATALOG`] lists it (shared by the kinds of one base id).
    const NAME: &'static str;
    /// Encoded payload length in bytes.
    const ENCODED_LEN: usize;

    /// This payload as a decoded [`Message`].
    fn into_message(self) -> Message<'static>;

    /// The payload, if `message` is this message.
    fn from_message(message: &Message<'_>) -> Option<Self>;
}

/// An ACK payload: a response code, possibly followed by data.
pub trait AckPayload {
    /// The response code.
    fn code(&self) -> ResponseCode;
}

macro_rules! ack_with_data {
    ($($t:ty),*) => {$(
        impl AckPayload for $t {
            fn code(&self) -> ResponseCode {
                self.code
            }
        }
    )*};
}

ack_with_data!(
    GimbalVersionAck,
    IrParams,
    VisibleParams,
    GpsReply,
    IpConfigAck,
    CameraVersionAck,
    TargetGpsAck,
    LaserDistance,
    SbusConfig
);

/// One entry of [`CATALOG`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CatalogEntry {
    /// Base id (low 16 bits of the message id).
    pub base: u16,
    /// Name of the message.
    pub name: &'static str,
    /// A periodic report (kind 0x00, no ACK) rather than a request.
    pub report: bool,
    /// Has an ACK (kind 0x01).
    pub ack: bool,
    /// Has a status frame (kind 0x02).
    pub status: bool,
}

macro_rules! is_report {
    (report) => {
        true
    };
    (request) => {
        false
    };
}

/// Declares the payload types the message table names but no module defines: an ACK
/// that is a bare response code (`Name {code}`) or a second message sharing another's
/// layout (`Name(Inner)`). A type written alone is defined elsewhere.
macro_rules! k40t_payload_type {
    ($what:literal $base:literal $name:ident) => {};
    ($what:literal $base:literal $name:ident {code}) => {
        wire_struct! {
            Le;
            #[doc = concat!($what, " of ", stringify!($base), ": a bare response code.")]
            pub struct $name {
                /// The response code.
                pub code: ResponseCode,
            }
        }

        impl AckPayload for $name {
            fn code(&self) -> ResponseCode {
                self.code
            }
        }

        impl From<ResponseCode> for $name {
            fn from(code: ResponseCode) -> Self {
                $name { code }
            }
        }
    };
    ($what:literal $base:literal $name:ident ($inner:ty)) => {
        wire_derive! {
            [Eq, Hash, Default]
            #[doc = concat!($what, " of ", stringify!($base), ": the layout of [`", stringify!($inner), "`].")]
            pub struct $name(pub $inner);
        }

        impl Field<Le> for $name {
            const LEN: usize = <$inner as Field<Le>>::LEN;
            fn read(r: &mut crate::wire::Reader<'_>) -> Result<Self> {
                <$inner as Field<Le>>::read(r).map(Self)
            }
            fn write(&self, w: &mut Writer<'_>) -> Result<()> {
                <$inner as Field<Le>>::write(&self.0, w)
            }
        }

        impl From<$inner> for $name {
            fn from(inner: $inner) -> Self {
                $name(inner)
            }
        }
    };
}

/// Implements [`MessageData`] for the payload of one message kind.
macro_rules! k40t_message_data {
    ($ty:ty, $kind:ident, $base:literal, $name:ident) => {
        impl MessageData for $ty {
            const ID: MsgId = MsgId::new(Kind::$kind, $base);
            const NAME: &'static str = stringify!($name);
            const ENCODED_LEN: usize = <$ty as Field<Le>>::LEN;

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

/// Decodes a payload of type `$ty`; a type declared over a shared layout (a bare ACK
/// `{code}`, a newtype `(Inner)`) is decoded through that layout's one decoder.
macro_rules! k40t_read {
    ($payload:ident, $ty:ty) => {
        decode_payload::<$ty>($payload)
    };
    ($payload:ident, $ty:ty; {code}) => {
        decode_payload::<ResponseCode>($payload).map(<$ty>::from)
    };
    ($payload:ident, $ty:ty; ($inner:ty)) => {
        decode_payload::<$inner>($payload).map(<$ty>::from)
    };
}

/// Writes a payload, through the shared layout's one encoder as [`k40t_read!`] reads it.
macro_rules! k40t_write {
    ($m:ident, $w:ident) => {
        Field::<Le>::write($m, $w)
    };
    ($m:ident, $w:ident; {code}) => {
        Field::<Le>::write(&$m.code, $w)
    };
    ($m:ident, $w:ident; ($inner:ty)) => {
        Field::<Le>::write(&$m.0, $w)
    };
}

/// Generates the methods every per-kind enum ([`Request`], [`Ack`], [`Status`]) has.
macro_rules! k40t_kind_impl {
    // `$def`: how the message table declared the type (`{code}`, `(Inner)` or nothing),
    // so that types sharing a layout share its decoder and encoder.
    ($kind:ident: $( [$base:literal $name:ident $ty:ty $(; $def:tt)?] )*) => {
        impl $kind {
            /// The message id.
            #[must_use]
            pub const fn id(&self) -> MsgId {
                MsgId::new(Kind::$kind, self.base())
            }
            /// The base id.
            #[must_use]
            pub const fn base(&self) -> u16 {
                match self { $( Self::$name(_) => $base, )* }
            }
            /// The message name.
            #[must_use]
            pub const fn name(&self) -> &'static str {
                match self { $( Self::$name(_) => stringify!($name), )* }
            }
            /// Encoded payload length.
            #[must_use]
            pub const fn payload_len(&self) -> usize {
                match self { $( Self::$name(_) => <$ty as Field<Le>>::LEN, )* }
            }
            /// Decodes the payload of a known base id (`None` for an unknown one).
            ///
            /// # Errors
            /// [`Error::BadLength`] when the payload is longer than the layout (a shorter
            /// one is zero-extended, see the module documentation).
            pub fn decode(base: u16, payload: &[u8]) -> Option<Result<Self>> {
                match base {
                    $( $base => Some(k40t_read!(payload, $ty $(; $def)?).map(Self::$name)), )*
                    _ => None,
                }
            }
            /// Writes the payload.
            ///
            /// # Errors
            /// [`Error::BufferTooSmall`] when `w` has no room for it.
            // One out-of-line copy per kind: inlined into every caller it costs kilobytes.
            #[inline(never)]
            pub fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
                match self { $( Self::$name(m) => k40t_write!(m, w $(; $def)?), )* }
            }
            /// Encodes this payload as a whole frame with `header` into `buf` and
            /// returns its length (as [`Packet::emit`], without the other kinds'
            /// encoders).
            ///
            /// # Errors
            /// [`Error::BufferTooSmall`] when `buf` is shorter than the frame.
            pub fn emit(&self, header: &Header, buf: &mut [u8]) -> Result<usize> {
                emit_frame(*header, self.id(), self.payload_len(), buf, |w| self.encode(w))
            }
        }
    };
}

/// Declares every message: base id, name, the payload of kind 0x00, and the ACK and
/// status payloads where they exist. Generates [`Request`], [`Ack`], [`Status`],
/// [`MessageData`] for every payload type, and [`CATALOG`] from the one table, so they
/// cannot disagree.
macro_rules! k40t_messages {
    ($(
        $base:literal $name:ident {
            $role:ident: $req:ty
            // `$ack_def`/`$status_def`: `{code}` or `(Inner)` asks `k40t_payload_type!` to
            // define the type; one token tree each.
            $(, ack: $ack:ident $($ack_def:tt)?)?
            $(, status: $status:ident $($status_def:tt)?)?
            $(,)?
        }
    )*) => {
        $( $( k40t_payload_type!("ACK" $base $ack $($ack_def)?); )? )*
        $( $( k40t_payload_type!("Status frame" $base $status $($status_def)?); )? )*

        wire_derive! {
            [Eq]
            /// Kind 0x00: requests and settings, and the periodic reports.
            pub enum Request {
                $(
                    #[doc = concat!("Base id ", stringify!($base), ": [`", stringify!($req), "`].")]
                    $name($req),
                )*
            }
        }

        wire_derive! {
            [Eq]
            /// Kind 0x01: acknowledgements, with their data where the document gives some.
            pub enum Ack {
                $( $(
                    #[doc = concat!("ACK of ", stringify!($base), ": [`", stringify!($ack), "`].")]
                    $name($ack),
                )? )*
            }
        }

        wire_derive! {
            [Eq]
            /// Kind 0x02: status frames sent while a request executes.
            pub enum Status {
                $( $(
                    #[doc = concat!("Status frame of ", stringify!($base), ": [`", stringify!($status), "`].")]
                    $name($status),
                )? )*
            }
        }

        k40t_kind_impl!(Request: $( [$base $name $req] )*);
        k40t_kind_impl!(Ack: $( $( [$base $name $ack $(; $ack_def)?] )? )*);
        k40t_kind_impl!(Status: $( $( [$base $name $status $(; $status_def)?] )? )*);

        $( k40t_message_data!($req, Request, $base, $name); )*
        $( $( k40t_message_data!($ack, Ack, $base, $name); )? )*
        $( $( k40t_message_data!($status, Status, $base, $name); )? )*

        impl Ack {
            /// The response code.
            #[must_use]
            pub fn code(&self) -> ResponseCode {
                match self { $( $( Self::$name(m) => AckPayload::code(m as &$ack), )? )* }
            }
        }

        /// Every base id this codec knows, in document order, with its kinds.
        pub const CATALOG: &[CatalogEntry] = &[$(
            CatalogEntry {
                base: $base,
                name: stringify!($name),
                report: is_report!($role),
                ack: present!($($ack)?),
                status: present!($($status)?),
            },
        )*];
    };
}

k40t_messages! {
    // 3.1 gimbal
    0x0001 GimbalStatus { report: GimbalStatus }
    0x0002 GimbalAttitude { report: GimbalAttitude }
    0x0010 GimbalControl { request: GimbalControl, ack: GimbalControlAck {code} }
    0x0012 GimbalAngle { request: GimbalAngle, ack: GimbalAngleAck {code} }
    0x0013 DriftCalibration { request: DriftCalibration, ack: DriftCalibrationAck {code} }
    0x0017 DialSpeed { request: DialSpeed, ack: DialSpeedAck {code} }
    0x0018 GimbalVersion { request: GimbalVersionQuery, ack: GimbalVersionAck }
    0x002C PointToAim { request: PointToAim, ack: PointToAimAck {code} }
    0x002D ServoOff { request: ServoOff, ack: ServoOffAck {code} }
    0x002E LinearCalibration { request: LinearCalibration, ack: LinearCalibrationAck {code} }
    0x002F SoftRestart { request: SoftRestart, ack: SoftRestartAck {code} }
    0x0030 UseFcAttitude { request: UseFcAttitude, ack: UseFcAttitudeAck {code} }
    0x0031 AccelCalibration { request: AccelCalibration, ack: AccelCalibrationAck {code} }
    0x0033 Stabilization { request: Stabilization, ack: StabilizationAck {code} }
    // 3.2.1 camera reports
    0x0003 SystemStatus { report: SystemStatus }
    0x0004 IrStatus { report: IrStatus }
    0x0005 VisibleStatus { report: VisibleStatus }
    0x0008 UpgradeStatus { report: UpgradeStatus }
    // 3.2.2 infrared
    0x0100 IrParams { request: IrParamsQuery, ack: IrParams }
    0x0105 IrDigitalZoom { request: IrDigitalZoom, ack: IrDigitalZoomAck {code} }
    0x0106 IrPalette { request: IrPalette, ack: IrPaletteAck {code} }
    0x0108 IrMeasurement { request: IrMeasurement, ack: IrMeasurementAck {code} }
    0x010A IrSharpness { request: IrSharpness, ack: IrSharpnessAck {code} }
    0x010B IrBrightness { request: IrBrightness, ack: IrBrightnessAck {code} }
    0x010C IrContrast { request: IrContrast, ack: IrContrastAck {code} }
    0x010D IrDenoise { request: IrDenoise, ack: IrDenoiseAck {code} }
    0x010E IrEnhancement { request: IrEnhancement, ack: IrEnhancementAck {code} }
    0x010F IrPointMeasure { request: IrPointMeasure, ack: IrPointMeasureAck {code} }
    0x0110 IrAreaMeasure { request: IrAreaMeasure, ack: IrAreaMeasureAck {code} }
    0x0123 IrGainMode { request: IrGainMode, ack: IrGainModeAck {code} }
    0x0124 IrTempWarning { request: IrTempWarning, ack: IrTempWarningAck {code} }
    0x0125 IrTempOverlay { request: IrTempOverlay, ack: IrTempOverlayAck {code} }
    0x0126 IrThresholdWarning { request: IrThresholdWarning, ack: IrThresholdWarningAck {code} }
    // 3.2.3 visible
    0x0200 VisibleParams { request: VisibleParamsQuery, ack: VisibleParams }
    0x0201 VideoResolution { request: VideoResolutionSetting, ack: VideoResolutionAck {code} }
    0x0202 PhotoResolution { request: PhotoResolutionSetting, ack: PhotoResolutionAck {code} }
    0x0203 Iso { request: IsoSetting, ack: IsoAck {code} }
    0x0204 Shutter { request: ShutterSetting, ack: ShutterAck {code} }
    0x0205 Ev { request: EvSetting, ack: EvAck {code} }
    0x0206 WhiteBalance { request: WhiteBalanceSetting, ack: WhiteBalanceAck {code} }
    0x0207 AntiFlicker { request: AntiFlickerSetting, ack: AntiFlickerAck {code} }
    0x0208 StrongLight { request: StrongLightSetting, ack: StrongLightAck {code} }
    0x0209 Backlight { request: BacklightSetting, ack: BacklightAck {code} }
    0x020A AeLock { request: AeLockSetting, ack: AeLockAck {code} }
    0x020B Metering { request: MeteringSetting, ack: MeteringAck {code} }
    // 3.2.4 common
    0x0300 CaptureMode { request: CaptureModeSetting, ack: CaptureModeAck {code} }
    0x0301 PhotoParams { request: PhotoParams, ack: PhotoParamsAck {code} }
    0x0302 TakePhoto { request: TakePhoto, ack: TakePhotoAck {code}, status: PhotoStatus }
    0x0303 Record { request: Record, ack: RecordAck {code}, status: RecordStatus }
    0x0304 HybridZoom { request: HybridZoom, ack: HybridZoomAck {code}, status: ZoomStatus }
    0x0306 ContinuousZoom { request: ContinuousZoom, ack: ContinuousZoomAck {code} }
    0x0307 AccurateShoot { request: AccurateShoot, ack: AccurateShootAck {code}, status: AccurateShootStatus }
    0x0308 StreamBitrate { request: StreamBitrateSetting, ack: StreamBitrateAck {code} }
    0x030A OutputResolution { request: OutputResolutionSetting, ack: OutputResolutionAck {code} }
    0x030B OutputCodec { request: OutputCodecSetting, ack: OutputCodecAck {code} }
    0x030C TfUpgrade { request: TfUpgrade, ack: TfUpgradeAck {code}, status: TfUpgradeStatus }
    0x030D FormatSd { request: FormatSd, ack: FormatSdAck {code}, status: FormatStatus }
    0x030E TimeSync { request: TimeSync, ack: TimeSyncAck {code} }
    0x030F FactoryReset { request: FactoryReset, ack: FactoryResetAck {code} }
    0x0310 GpsRequest { request: GpsRequest, ack: GpsReply }
    0x0311 SetIp { request: SetIp, ack: SetIpAck {code} }
    0x0312 GetIp { request: IpQuery, ack: IpConfigAck }
    0x0313 Focus { request: Focus, ack: FocusAck {code} }
    0x0314 Watermark { request: Watermark, ack: WatermarkAck {code} }
    0x0316 Shutdown { request: Shutdown, ack: ShutdownAck {code} }
    0x0317 CameraVersion { request: CameraVersionQuery, ack: CameraVersionAck }
    0x0318 ImageMode { request: ImageModeSetting, ack: ImageModeAck {code} }
    0x0319 AiRecognition { request: AiRecognition, ack: AiRecognitionAck {code} }
    0x0320 TargetGps { request: TargetGpsRequest, ack: TargetGpsAck }
    0x0324 TrackBox { request: TrackBox, ack: TrackBoxAck {code} }
    // 3.2.5 laser
    0x0400 LaserRange { request: LaserRange, ack: LaserDistance }
    0x0406 LaserPeriodic { request: LaserPeriodic, ack: LaserPeriodicAck {code}, status: LaserPeriodicStatus(LaserDistance) }
    // 3.2.6 SBUS
    0x0500 SbusRange { request: SbusRange, ack: SbusRangeAck {code} }
    0x0501 SbusChannels { request: SbusChannels, ack: SbusChannelsAck {code} }
    0x0502 SbusConfig { request: SbusConfigQuery, ack: SbusConfig }
}

wire_derive! {
    [Eq]
    /// A message this codec does not know (unknown base id, or a kind the document does not
    /// define for it), with its payload.
    pub struct Raw<'a> {
        /// The message id.
        pub id: MsgId,
        /// The payload bytes.
        pub payload: &'a [u8],
    }
}

wire_derive! {
    [Eq]
    /// A decoded message: what the payload of a frame means.
    pub enum Message<'a> {
        /// Kind 0x00.
        Request(Request),
        /// Kind 0x01.
        Ack(Ack),
        /// Kind 0x02.
        Status(Status),
        /// Unknown id or kind.
        Raw(Raw<'a>),
    }
}

impl<'a> Message<'a> {
    /// Decodes a payload. Unknown ids give [`Message::Raw`].
    ///
    /// # Errors
    /// [`Error::BadLength`] when a known id's payload is longer than its layout.
    pub fn decode(id: MsgId, payload: &'a [u8]) -> Result<Self> {
        let known = match id.kind {
            Kind::Request => Request::decode(id.base, payload).map(|r| r.map(Message::Request)),
            Kind::Ack => Ack::decode(id.base, payload).map(|r| r.map(Message::Ack)),
            Kind::Status => Status::decode(id.base, payload).map(|r| r.map(Message::Status)),
            Kind::Other(_) => None,
        };
        known.unwrap_or(Ok(Message::Raw(Raw { id, payload })))
    }

    /// The message id.
    #[must_use]
    pub const fn id(&self) -> MsgId {
        match self {
            Message::Request(m) => m.id(),
            Message::Ack(m) => m.id(),
            Message::Status(m) => m.id(),
            Message::Raw(r) => r.id,
        }
    }

    /// The message name (`"Raw"` for unknown ids).
    #[must_use]
    pub const fn name(&self) -> &'static str {
        match self {
            Message::Request(m) => m.name(),
            Message::Ack(m) => m.name(),
            Message::Status(m) => m.name(),
            Message::Raw(_) => "Raw",
        }
    }

    /// Encoded payload length.
    #[must_use]
    pub const fn payload_len(&self) -> usize {
        match self {
            Message::Request(m) => m.payload_len(),
            Message::Ack(m) => m.payload_len(),
            Message::Status(m) => m.payload_len(),
            Message::Raw(r) => r.payload.len(),
        }
    }

    /// Writes the payload.
    ///
    /// # Errors
    /// [`Error::BufferTooSmall`] when `w` has no room for it.
    pub fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
        match self {
            Message::Request(m) => m.encode(w),
            Message::Ack(m) => m.encode(w),
            Message::Status(m) => m.encode(w),
            Message::Raw(r) => w.put(r.payload),
        }
    }

    /// The typed payload, if this is message `M`:
    /// `message.get::<HybridZoom>()`.
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

impl From<Ack> for Message<'_> {
    fn from(m: Ack) -> Self {
        Message::Ack(m)
    }
}

impl From<Status> for Message<'_> {
    fn from(m: Status) -> Self {
        Message::Status(m)
    }
}

wire_derive! {
    [Eq, Hash]
    /// Everything of a frame but its message: addresses, sequence number, CRC coverage.
    pub struct Header {
        /// Receiver.
        pub dst: Address,
        /// Sender.
        pub src: Address,
        /// Sequence number.
        pub seq: u8,
        /// Which bytes the CRC covers (found when parsing, used when emitting).
        pub coverage: CrcCoverage,
    }
}

impl Header {
    /// A header from `src` to `dst` with sequence number `seq` and the default CRC
    /// coverage.
    #[must_use]
    pub const fn new(src: Address, dst: Address, seq: u8) -> Self {
        Header {
            dst,
            src,
            seq,
            coverage: CrcCoverage::ExcludeStx,
        }
    }
}

wire_derive! {
    [Eq]
    /// A whole K40T packet: the header and the message.
    pub struct Packet<'a> {
        /// Addresses, sequence number and CRC coverage.
        pub header: Header,
        /// The message.
        pub message: Message<'a>,
    }
}

impl<T: AsRef<[u8]>> Frame<T> {
    /// The header, with the CRC coverage that makes the frame valid (`None` when neither
    /// does). The frame must have passed [`Frame::check_len`].
    #[must_use]
    pub fn header(&self) -> Option<Header> {
        Some(Header {
            dst: self.dst(),
            src: self.src(),
            seq: self.seq(),
            coverage: self.detect_coverage()?,
        })
    }

    /// The payload as message `M`: `None` when the frame carries another message, else
    /// `M` decoded exactly as [`Message::decode`] decodes it. A program that handles a
    /// few messages decodes them this way and keeps the decoders of the other hundred
    /// out of its binary (the bridge firmware saves about 12 KB of flash).
    ///
    /// ```
    /// use protocol_core::k40t::{self, Address, Frame, GimbalAttitude, Header, HybridZoom};
    /// let zoom = HybridZoom { start: 0, zoom_x10: 40 };
    /// let header = Header::new(Address::new(4, 1), Address::new(2, 1), 7);
    /// let mut buf = [0u8; 64];
    /// let n = k40t::encode(&zoom, &header, &mut buf)?;
    /// let frame = Frame::new_checked(&buf[..n])?;
    /// assert_eq!(frame.decode_as::<HybridZoom>(), Some(Ok(zoom)));
    /// assert_eq!(frame.decode_as::<GimbalAttitude>(), None);
    /// # Ok::<(), protocol_core::Error>(())
    /// ```
    ///
    /// # Errors
    /// Inside the `Some`: [`Error::BadLength`] when the payload is longer than `M`'s
    /// layout (a shorter one is zero-extended, see the module documentation).
    pub fn decode_as<M: MessageData>(&self) -> Option<Result<M>> {
        (self.id() == M::ID).then(|| decode_payload::<M>(self.payload()))
    }
}

impl<'a> Packet<'a> {
    /// Parses a frame view. The CRC is verified under both coverages and the one that
    /// matches is recorded in the header.
    ///
    /// # Errors
    /// [`Error::BadChecksum`] when neither coverage matches (reported for the default
    /// one), the frame's own length errors, and those of [`Message::decode`].
    pub fn parse(frame: &Frame<&'a [u8]>) -> Result<Self> {
        frame.check_len()?;
        let Some(coverage) = frame.detect_coverage() else {
            return Err(Error::BadChecksum {
                computed: frame.compute_checksum(CrcCoverage::default()),
                received: frame.checksum(),
            });
        };
        Ok(Packet {
            header: Header {
                dst: frame.dst(),
                src: frame.src(),
                seq: frame.seq(),
                coverage,
            },
            message: Message::decode(frame.id(), frame.payload_ref())?,
        })
    }

    /// Checks and parses a complete frame (bytes after it are ignored).
    ///
    /// # Errors
    /// As [`Frame::new_checked`] and [`Packet::parse`].
    pub fn decode(bytes: &'a [u8]) -> Result<Self> {
        Packet::parse(&Frame::new_checked(bytes)?)
    }

    /// Length of the encoded frame.
    #[must_use]
    pub const fn buffer_len(&self) -> usize {
        MIN_FRAME_LEN.saturating_add(self.message.payload_len())
    }

    /// Encodes the frame into `buf` and returns its length.
    ///
    /// # Errors
    /// [`Error::BufferTooSmall`] when `buf` is shorter than [`Packet::buffer_len`];
    /// [`Error::BadLength`] for a payload longer than 243 bytes.
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

/// Encodes one typed message as a whole frame into `buf` and returns its length:
/// `k40t::encode(&HybridZoom { start: 0, zoom_x10: 45 }, &header, &mut buf)`.
///
/// # Errors
/// [`Error::BufferTooSmall`] when `buf` cannot hold the frame.
pub fn encode<M: MessageData>(message: &M, header: &Header, buf: &mut [u8]) -> Result<usize> {
    emit_frame(*header, M::ID, M::ENCODED_LEN, buf, |w| message.write(w))
}

/// Writes header, payload (through `payload`) and CRC.
fn emit_frame(
    header: Header,
    id: MsgId,
    payload_len: usize,
    buf: &mut [u8],
    payload: impl FnOnce(&mut Writer<'_>) -> Result<()>,
) -> Result<usize> {
    let len_field = u8::try_from(payload_len)
        .ok()
        .filter(|&l| usize::from(l) <= MAX_PAYLOAD_LEN)
        .ok_or(Error::BadLength)?;
    let total = MIN_FRAME_LEN.saturating_add(payload_len);
    let buf = buf.get_mut(..total).ok_or(Error::BufferTooSmall)?;
    let mut frame = Frame::new_unchecked(&mut *buf);
    frame.set_start(len_field);
    frame.set_dst(header.dst);
    frame.set_seq(header.seq);
    frame.set_src(header.src);
    frame.set_id(id);
    let mut w = Writer::new(frame.payload_mut());
    payload(&mut w)?;
    if w.len() != payload_len {
        return Err(Error::BadLength);
    }
    frame.fill_checksum(header.coverage);
    Ok(total)
}

#[cfg(test)]
mod tests {
    use super::*;

    const ZOOM: [u8; 15] = [
        0xFD, 0x03, 0x04, 0x01, 0x07, 0x02, 0x01, 0x04, 0x03, 0x00, 0x00, 0x2D, 0x00, 0xCE, 0x89,
    ];
    const ZOOM_ACK: [u8; 14] = [
        0xFD, 0x02, 0x02, 0x01, 0x07, 0x04, 0x01, 0x04, 0x03, 0x01, 0x00, 0x00, 0xE8, 0xEB,
    ];

    #[test]
    fn spec_notes_reference_frames() {
        let p = Packet::decode(&ZOOM).unwrap();
        assert_eq!(p.header.dst, Address::POD);
        assert_eq!(p.header.src, Address::FLIGHT_CONTROLLER);
        assert_eq!(p.header.seq, 7);
        assert_eq!(p.header.coverage, CrcCoverage::ExcludeStx);
        assert_eq!(
            p.message,
            Message::Request(Request::HybridZoom(HybridZoom {
                start: 0,
                zoom_x10: 45
            }))
        );
        let mut buf = [0u8; MAX_FRAME_LEN];
        let n = p.emit(&mut buf).unwrap();
        assert_eq!(&buf[..n], &ZOOM);

        let a = Packet::decode(&ZOOM_ACK).unwrap();
        assert_eq!(a.message.id().to_u32(), 0x01_0304);
        match a.message {
            Message::Ack(ack) => assert_eq!(ack.code().code(), AckCode::Ok),
            other => panic!("{other:?}"),
        }
        assert_eq!(
            Frame::new_checked(&ZOOM[..]).unwrap().detect_coverage(),
            Some(CrcCoverage::ExcludeStx)
        );
    }

    /// `Frame::decode_as` gives what `Message::decode` gives, for the right type only,
    /// with the same length rules; `Request::emit` encodes as `Packet::emit`.
    #[test]
    fn decode_as_and_emit_per_kind_agree_with_the_enums() {
        let zoom = Frame::new_checked(&ZOOM[..]).unwrap();
        assert_eq!(
            zoom.decode_as::<HybridZoom>(),
            Some(Ok(HybridZoom {
                start: 0,
                zoom_x10: 45
            }))
        );
        assert_eq!(zoom.decode_as::<HybridZoomAck>(), None);
        assert_eq!(zoom.decode_as::<ZoomStatus>(), None);
        assert_eq!(zoom.header(), Some(Packet::decode(&ZOOM).unwrap().header));
        let ack = Frame::new_checked(&ZOOM_ACK[..]).unwrap();
        assert_eq!(
            ack.decode_as::<HybridZoomAck>(),
            Some(Ok(HybridZoomAck {
                code: ResponseCode::OK
            }))
        );
        // A bad CRC: no header.
        let mut bad = ZOOM;
        bad[11] ^= 1;
        assert_eq!(Frame::new_checked(&bad[..]).unwrap().header(), None);

        let header = Header::new(Address::FLIGHT_CONTROLLER, Address::POD, 9);
        let mut buf = [0u8; MAX_FRAME_LEN];
        // Shorter payload: zero-extended by both; longer: BadLength from both.
        for payload in [&[0x2D][..], &[0x00, 0x2D, 0x00, 0x07][..]] {
            let raw = Packet {
                header,
                message: Message::Raw(Raw {
                    id: HybridZoom::ID,
                    payload,
                }),
            };
            let n = raw.emit(&mut buf).unwrap();
            let frame = Frame::new_checked(&buf[..n]).unwrap();
            let via_enum = Packet::decode(&buf[..n]).map(|p| p.message.get::<HybridZoom>());
            let via_type = frame.decode_as::<HybridZoom>().unwrap().map(Some);
            assert_eq!(via_type, via_enum, "{payload:?}");
        }

        // Per-kind emit: byte-identical to Packet::emit.
        let request = Request::GimbalVersion(GimbalVersionQuery {
            command: 1,
            reserved: 0,
        });
        let n = request.emit(&header, &mut buf).unwrap();
        let mut again = [0u8; MAX_FRAME_LEN];
        let m = Packet {
            header,
            message: Message::Request(request),
        }
        .emit(&mut again)
        .unwrap();
        assert_eq!(buf[..n], again[..m]);
        assert_eq!(
            request.emit(&header, &mut buf[..n - 1]),
            Err(Error::BufferTooSmall)
        );
    }

    #[test]
    fn typed_messages_know_their_ids() {
        let header = Header::new(Address::FLIGHT_CONTROLLER, Address::POD, 7);
        let zoom = HybridZoom {
            start: 0,
            zoom_x10: 45,
        };
        let mut buf = [0u8; MAX_FRAME_LEN];
        let n = encode(&zoom, &header, &mut buf).unwrap();
        assert_eq!(&buf[..n], &ZOOM);
        let p = Packet::decode(&buf[..n]).unwrap();
        assert_eq!(p.message.get::<HybridZoom>(), Some(zoom));
        assert_eq!(p.message.get::<HybridZoomAck>(), None);
        assert_eq!(p.message.get::<ContinuousZoom>(), None);

        let ack = Packet::decode(&ZOOM_ACK).unwrap();
        assert_eq!(
            ack.message.get::<HybridZoomAck>(),
            Some(HybridZoomAck {
                code: ResponseCode::OK
            })
        );
        assert_eq!(HybridZoomAck::ID.to_u32(), 0x01_0304);
        assert_eq!(ZoomStatus::ID.to_u32(), 0x02_0304);
        assert_eq!(LaserPeriodicStatus::ID.to_u32(), 0x02_0406);
        assert_eq!(LaserDistance::ID.to_u32(), 0x01_0400);
        assert_eq!(TimeSync::ENCODED_LEN, 16);
        assert_eq!(Message::from(zoom), p.message);

        // The other CRC coverage is found when parsing and kept when re-encoding.
        let include = Header {
            coverage: CrcCoverage::IncludeStx,
            ..header
        };
        let n = encode(&zoom, &include, &mut buf).unwrap();
        let p = Packet::decode(&buf[..n]).unwrap();
        assert_eq!(p.header, include);
        let mut again = [0u8; MAX_FRAME_LEN];
        assert_eq!(p.emit(&mut again), Ok(n));
        assert_eq!(again[..n], buf[..n]);
        // A CRC valid under neither coverage is an error.
        buf[n - 1] ^= 0x01;
        assert!(matches!(
            Packet::decode(&buf[..n]),
            Err(Error::BadChecksum { .. })
        ));
    }

    #[test]
    fn catalog_has_75_distinct_base_ids() {
        assert_eq!(CATALOG.len(), 75);
        for (i, a) in CATALOG.iter().enumerate() {
            assert!(
                CATALOG[i + 1..].iter().all(|b| b.base != a.base),
                "{:#x}",
                a.base
            );
        }
    }
}
