//! The K40T four-sensor pod protocol (`000_cac8f3505cecd78b.txt`).
//!
//! Frame: `FD LEN DST_SYS DST_COMP SEQ SRC_SYS SRC_COMP MSGID(3, LE) PAYLOAD CRC(2, LE)`,
//! 115200 8N1. The message id's high byte is the [`Kind`] (0x00 request or report, 0x01
//! ACK, 0x02 status frame); the low 16 bits are the base id the document lists.
//!
//! - [`Frame`] is the checked zero-copy view; [`K40tFraming`] plugs the protocol into
//!   the shared [`Deframer`](crate::wire::Deframer).
//! - [`Packet`] (addresses, sequence and a [`Message`]) parses from a frame and emits
//!   into a buffer; [`Message`] is [`Request`], [`Ack`], [`Status`] or [`Raw`].
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

#[macro_use]
mod field;
mod frame;

mod camera;
mod common;
mod gimbal;
mod ir;
mod laser_sbus;
mod visible;

pub use crate::Text;
pub use camera::*;
pub use common::*;
pub use field::{AckCode, Payload, ResponseCode, Version};
pub use frame::{
    Address, CrcCoverage, Frame, HEADER_LEN, K40tFraming, Kind, MAX_FRAME_LEN, MAX_PAYLOAD_LEN,
    MIN_FRAME_LEN, MsgId, STX,
};
pub use gimbal::*;
pub use ir::*;
pub use laser_sbus::*;
pub use visible::*;

use crate::wire::Writer;
use crate::{Error, Result};
use field::decode_payload;

/// An ACK payload: a response code, possibly followed by data.
pub trait AckPayload {
    /// The response code.
    fn code(&self) -> ResponseCode;
}

impl Payload for ResponseCode {
    const LEN: usize = 2;
    fn decode(r: &mut crate::wire::Reader<'_>) -> Result<Self> {
        field::Field::<crate::wire::field::Le>::read(r)
    }
    fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
        field::Field::<crate::wire::field::Le>::write(self, w)
    }
}

impl AckPayload for ResponseCode {
    fn code(&self) -> ResponseCode {
        *self
    }
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

macro_rules! present {
    () => {
        false
    };
    ($t:ty) => {
        true
    };
}

macro_rules! is_report {
    (report) => {
        true
    };
    (request) => {
        false
    };
}

/// Declares every message: base id, name, the payload of kind 0x00, and the ACK and
/// status payloads where they exist. Generates [`Request`], [`Ack`], [`Status`] and
/// [`CATALOG`] from the one table, so they cannot disagree.
macro_rules! messages {
    ($(
        $base:literal $name:ident { $role:ident: $req:ty $(, ack: $ack:ty)? $(, status: $status:ty)? $(,)? }
    )*) => {
        /// Kind 0x00: requests and settings, and the periodic reports.
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        #[cfg_attr(feature = "serde", derive(serde::Serialize))]
        pub enum Request {
            $(
                #[doc = concat!("Base id ", stringify!($base), ": [`", stringify!($req), "`].")]
                $name($req),
            )*
        }

        /// Kind 0x01: acknowledgements, with their data where the document gives some.
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        #[cfg_attr(feature = "serde", derive(serde::Serialize))]
        pub enum Ack {
            $( $(
                #[doc = concat!("ACK of ", stringify!($base), ": [`", stringify!($ack), "`].")]
                $name($ack),
            )? )*
        }

        /// Kind 0x02: status frames sent while a request executes.
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        #[cfg_attr(feature = "serde", derive(serde::Serialize))]
        pub enum Status {
            $( $(
                #[doc = concat!("Status frame of ", stringify!($base), ": [`", stringify!($status), "`].")]
                $name($status),
            )? )*
        }

        impl Request {
            /// The base id.
            pub const fn base(&self) -> u16 {
                match self { $( Self::$name(_) => $base, )* }
            }
            /// The message name.
            pub const fn name(&self) -> &'static str {
                match self { $( Self::$name(_) => stringify!($name), )* }
            }
            /// Encoded payload length.
            pub const fn payload_len(&self) -> usize {
                match self { $( Self::$name(_) => <$req as Payload>::LEN, )* }
            }
            fn decode(base: u16, payload: &[u8]) -> Option<Result<Self>> {
                match base {
                    $( $base => Some(decode_payload::<$req>(payload).map(Self::$name)), )*
                    _ => None,
                }
            }
            fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
                match self { $( Self::$name(m) => m.encode(w), )* }
            }
        }

        impl Ack {
            /// The base id of the request acknowledged.
            pub const fn base(&self) -> u16 {
                match self { $( $( Self::$name(_) => { let _ = stringify!($ack); $base } )? )* }
            }
            /// The message name (of the request acknowledged).
            pub const fn name(&self) -> &'static str {
                match self { $( $( Self::$name(_) => { let _ = stringify!($ack); stringify!($name) } )? )* }
            }
            /// Encoded payload length.
            pub const fn payload_len(&self) -> usize {
                match self { $( $( Self::$name(_) => <$ack as Payload>::LEN, )? )* }
            }
            /// The response code.
            pub fn code(&self) -> ResponseCode {
                match self { $( $( Self::$name(m) => AckPayload::code(m as &$ack), )? )* }
            }
            fn decode(base: u16, payload: &[u8]) -> Option<Result<Self>> {
                match base {
                    $( $( $base => Some(decode_payload::<$ack>(payload).map(Self::$name)), )? )*
                    _ => None,
                }
            }
            fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
                match self { $( $( Self::$name(m) => (m as &$ack).encode(w), )? )* }
            }
        }

        impl Status {
            /// The base id of the request this status belongs to.
            pub const fn base(&self) -> u16 {
                match self { $( $( Self::$name(_) => { let _ = stringify!($status); $base } )? )* }
            }
            /// The message name (of the request).
            pub const fn name(&self) -> &'static str {
                match self { $( $( Self::$name(_) => { let _ = stringify!($status); stringify!($name) } )? )* }
            }
            /// Encoded payload length.
            pub const fn payload_len(&self) -> usize {
                match self { $( $( Self::$name(_) => <$status as Payload>::LEN, )? )* }
            }
            fn decode(base: u16, payload: &[u8]) -> Option<Result<Self>> {
                match base {
                    $( $( $base => Some(decode_payload::<$status>(payload).map(Self::$name)), )? )*
                    _ => None,
                }
            }
            fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
                match self { $( $( Self::$name(m) => (m as &$status).encode(w), )? )* }
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

messages! {
    // 3.1 gimbal
    0x0001 GimbalStatus { report: GimbalStatus }
    0x0002 GimbalAttitude { report: GimbalAttitude }
    0x0010 GimbalControl { request: GimbalControl, ack: ResponseCode }
    0x0012 GimbalAngle { request: GimbalAngle, ack: ResponseCode }
    0x0013 DriftCalibration { request: DriftCalibration, ack: ResponseCode }
    0x0017 DialSpeed { request: DialSpeed, ack: ResponseCode }
    0x0018 GimbalVersion { request: GimbalVersionQuery, ack: GimbalVersionAck }
    0x002C PointToAim { request: PointToAim, ack: ResponseCode }
    0x002D ServoOff { request: ServoOff, ack: ResponseCode }
    0x002E LinearCalibration { request: LinearCalibration, ack: ResponseCode }
    0x002F SoftRestart { request: SoftRestart, ack: ResponseCode }
    0x0030 UseFcAttitude { request: UseFcAttitude, ack: ResponseCode }
    0x0031 AccelCalibration { request: AccelCalibration, ack: ResponseCode }
    0x0033 Stabilization { request: Stabilization, ack: ResponseCode }
    // 3.2.1 camera reports
    0x0003 SystemStatus { report: SystemStatus }
    0x0004 IrStatus { report: IrStatus }
    0x0005 VisibleStatus { report: VisibleStatus }
    0x0008 UpgradeStatus { report: UpgradeStatus }
    // 3.2.2 infrared
    0x0100 IrParams { request: IrParamsQuery, ack: IrParams }
    0x0105 IrDigitalZoom { request: IrDigitalZoom, ack: ResponseCode }
    0x0106 IrPalette { request: IrPalette, ack: ResponseCode }
    0x0108 IrMeasurement { request: IrMeasurement, ack: ResponseCode }
    0x010A IrSharpness { request: IrSharpness, ack: ResponseCode }
    0x010B IrBrightness { request: IrBrightness, ack: ResponseCode }
    0x010C IrContrast { request: IrContrast, ack: ResponseCode }
    0x010D IrDenoise { request: IrDenoise, ack: ResponseCode }
    0x010E IrEnhancement { request: IrEnhancement, ack: ResponseCode }
    0x010F IrPointMeasure { request: IrPointMeasure, ack: ResponseCode }
    0x0110 IrAreaMeasure { request: IrAreaMeasure, ack: ResponseCode }
    0x0123 IrGainMode { request: IrGainMode, ack: ResponseCode }
    0x0124 IrTempWarning { request: IrTempWarning, ack: ResponseCode }
    0x0125 IrTempOverlay { request: IrTempOverlay, ack: ResponseCode }
    0x0126 IrThresholdWarning { request: IrThresholdWarning, ack: ResponseCode }
    // 3.2.3 visible
    0x0200 VisibleParams { request: VisibleParamsQuery, ack: VisibleParams }
    0x0201 VideoResolution { request: VideoResolutionSetting, ack: ResponseCode }
    0x0202 PhotoResolution { request: PhotoResolutionSetting, ack: ResponseCode }
    0x0203 Iso { request: IsoSetting, ack: ResponseCode }
    0x0204 Shutter { request: ShutterSetting, ack: ResponseCode }
    0x0205 Ev { request: EvSetting, ack: ResponseCode }
    0x0206 WhiteBalance { request: WhiteBalanceSetting, ack: ResponseCode }
    0x0207 AntiFlicker { request: AntiFlickerSetting, ack: ResponseCode }
    0x0208 StrongLight { request: StrongLightSetting, ack: ResponseCode }
    0x0209 Backlight { request: BacklightSetting, ack: ResponseCode }
    0x020A AeLock { request: AeLockSetting, ack: ResponseCode }
    0x020B Metering { request: MeteringSetting, ack: ResponseCode }
    // 3.2.4 common
    0x0300 CaptureMode { request: CaptureModeSetting, ack: ResponseCode }
    0x0301 PhotoParams { request: PhotoParams, ack: ResponseCode }
    0x0302 TakePhoto { request: TakePhoto, ack: ResponseCode, status: PhotoStatus }
    0x0303 Record { request: Record, ack: ResponseCode, status: RecordStatus }
    0x0304 HybridZoom { request: HybridZoom, ack: ResponseCode, status: ZoomStatus }
    0x0306 ContinuousZoom { request: ContinuousZoom, ack: ResponseCode }
    0x0307 AccurateShoot { request: AccurateShoot, ack: ResponseCode, status: AccurateShootStatus }
    0x0308 StreamBitrate { request: StreamBitrateSetting, ack: ResponseCode }
    0x030A OutputResolution { request: OutputResolutionSetting, ack: ResponseCode }
    0x030B OutputCodec { request: OutputCodecSetting, ack: ResponseCode }
    0x030C TfUpgrade { request: TfUpgrade, ack: ResponseCode, status: TfUpgradeStatus }
    0x030D FormatSd { request: FormatSd, ack: ResponseCode, status: FormatStatus }
    0x030E TimeSync { request: TimeSync, ack: ResponseCode }
    0x030F FactoryReset { request: FactoryReset, ack: ResponseCode }
    0x0310 GpsRequest { request: GpsRequest, ack: GpsReply }
    0x0311 SetIp { request: SetIp, ack: ResponseCode }
    0x0312 GetIp { request: IpQuery, ack: IpConfigAck }
    0x0313 Focus { request: Focus, ack: ResponseCode }
    0x0314 Watermark { request: Watermark, ack: ResponseCode }
    0x0316 Shutdown { request: Shutdown, ack: ResponseCode }
    0x0317 CameraVersion { request: CameraVersionQuery, ack: CameraVersionAck }
    0x0318 ImageMode { request: ImageModeSetting, ack: ResponseCode }
    0x0319 AiRecognition { request: AiRecognition, ack: ResponseCode }
    0x0320 TargetGps { request: TargetGpsRequest, ack: TargetGpsAck }
    0x0324 TrackBox { request: TrackBox, ack: ResponseCode }
    // 3.2.5 laser
    0x0400 LaserRange { request: LaserRange, ack: LaserDistance }
    0x0406 LaserPeriodic { request: LaserPeriodic, ack: ResponseCode, status: LaserDistance }
    // 3.2.6 SBUS
    0x0500 SbusRange { request: SbusRange, ack: ResponseCode }
    0x0501 SbusChannels { request: SbusChannels, ack: ResponseCode }
    0x0502 SbusConfig { request: SbusConfigQuery, ack: SbusConfig }
}

/// A message this codec does not know (unknown base id, or a kind the document does not
/// define for it), with its payload.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Raw<'a> {
    /// The message id.
    pub id: MsgId,
    /// The payload bytes.
    pub payload: &'a [u8],
}

/// A decoded message: what the payload of a frame means.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
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

impl<'a> Message<'a> {
    /// Decodes a payload. Unknown ids give [`Message::Raw`]; a known id whose payload is
    /// longer than its layout is [`Error::BadLength`].
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
    pub const fn id(&self) -> MsgId {
        match self {
            Message::Request(m) => MsgId::new(Kind::Request, m.base()),
            Message::Ack(m) => MsgId::new(Kind::Ack, m.base()),
            Message::Status(m) => MsgId::new(Kind::Status, m.base()),
            Message::Raw(r) => r.id,
        }
    }

    /// The message name (`"Raw"` for unknown ids).
    pub const fn name(&self) -> &'static str {
        match self {
            Message::Request(m) => m.name(),
            Message::Ack(m) => m.name(),
            Message::Status(m) => m.name(),
            Message::Raw(_) => "Raw",
        }
    }

    /// Encoded payload length.
    pub const fn payload_len(&self) -> usize {
        match self {
            Message::Request(m) => m.payload_len(),
            Message::Ack(m) => m.payload_len(),
            Message::Status(m) => m.payload_len(),
            Message::Raw(r) => r.payload.len(),
        }
    }

    /// Writes the payload.
    pub fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
        match self {
            Message::Request(m) => m.encode(w),
            Message::Ack(m) => m.encode(w),
            Message::Status(m) => m.encode(w),
            Message::Raw(r) => w.put(r.payload),
        }
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

/// A whole K40T packet: addressing, sequence number and message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Packet<'a> {
    /// Receiver.
    pub dst: Address,
    /// Sender.
    pub src: Address,
    /// Sequence number.
    pub seq: u8,
    /// The message.
    pub message: Message<'a>,
}

impl<'a> Packet<'a> {
    /// Parses a frame view (its CRC is not verified here: the deframer or
    /// [`Frame::verify`] does that).
    pub fn parse(frame: &Frame<&'a [u8]>) -> Result<Self> {
        frame.check_len()?;
        Ok(Packet {
            dst: frame.dst(),
            src: frame.src(),
            seq: frame.seq(),
            message: Message::decode(frame.msg_id(), frame.payload_ref())?,
        })
    }

    /// Checks, verifies (with `coverage`) and parses a complete frame.
    pub fn decode(bytes: &'a [u8], coverage: CrcCoverage) -> Result<Self> {
        let frame = Frame::new_checked(bytes)?;
        frame.verify(coverage)?;
        Packet::parse(&frame)
    }

    /// Length of the encoded frame.
    pub const fn buffer_len(&self) -> usize {
        MIN_FRAME_LEN.saturating_add(self.message.payload_len())
    }

    /// Encodes the frame into `buf` and returns its length.
    pub fn emit(&self, buf: &mut [u8], coverage: CrcCoverage) -> Result<usize> {
        let payload_len = u8::try_from(self.message.payload_len())
            .ok()
            .filter(|&l| usize::from(l) <= MAX_PAYLOAD_LEN)
            .ok_or(Error::BadLength)?;
        let total = self.buffer_len();
        let buf = buf.get_mut(..total).ok_or(Error::BufferTooSmall)?;
        let mut frame = Frame::new_unchecked(&mut *buf);
        frame.set_start(payload_len);
        frame.set_dst(self.dst);
        frame.set_seq(self.seq);
        frame.set_src(self.src);
        frame.set_msg_id(self.message.id());
        let mut w = Writer::new(frame.payload_mut());
        self.message.encode(&mut w)?;
        if w.len() != usize::from(payload_len) {
            return Err(Error::BadLength);
        }
        frame.fill_checksum(coverage);
        Ok(total)
    }
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
        let p = Packet::decode(&ZOOM, CrcCoverage::ExcludeStx).unwrap();
        assert_eq!(p.dst, Address::POD);
        assert_eq!(p.src, Address::FLIGHT_CONTROLLER);
        assert_eq!(p.seq, 7);
        assert_eq!(
            p.message,
            Message::Request(Request::HybridZoom(HybridZoom {
                start: 0,
                zoom_x10: 45
            }))
        );
        let mut buf = [0u8; MAX_FRAME_LEN];
        let n = p.emit(&mut buf, CrcCoverage::ExcludeStx).unwrap();
        assert_eq!(&buf[..n], &ZOOM);

        let a = Packet::decode(&ZOOM_ACK, CrcCoverage::ExcludeStx).unwrap();
        assert_eq!(a.message.id().to_u32(), 0x010304);
        match a.message {
            Message::Ack(ack) => assert_eq!(ack.code().code(), AckCode::Ok),
            other => panic!("{other:?}"),
        }
        assert_eq!(
            Frame::new_checked(&ZOOM[..]).unwrap().detect_coverage(),
            Some(CrcCoverage::ExcludeStx)
        );
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
