//! The K40T four-sensor pod protocol (K40T external protocol, single-channel streaming).
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
//! - Every payload type implements [`MessageData`] (its id, name and length) with
//!   `Protocol = `[`K40t`], so one message is sent with [`encode`] and recognised with
//!   [`Message::get`].
//! - [`CATALOG`] lists every base id with the kinds it has.
//!
//! # Decisions where the document is silent (see docs/src/protocols/k40t.md)
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
use crate::{Error, Result};

pub use crate::wire::MessageData;

/// An ACK payload: a response code, possibly followed by data.
pub trait AckPayload {
    /// The response code.
    fn code(&self) -> ResponseCode;
}

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

impl CatalogEntry {
    /// The entry of a table row with the encoded lengths of its messages, by kind: a row
    /// without an ACK is a periodic report (every request has one).
    const fn new(base: u16, name: &'static str, kinds: &[usize]) -> Self {
        CatalogEntry {
            base,
            name,
            report: kinds.len() < 2,
            ack: kinds.len() >= 2,
            status: kinds.len() >= 3,
        }
    }
}

// The messages of every base id, by kind: the request or report (kind 0x00), then its ACK
// and its status frame where they exist. An ACK of a bare response code is a struct of one
// `code` field, decoded through `ResponseCode`'s one decoder.
message_table! {
    /// The K40T pod protocol: every message's payload type implements [`MessageData`] with
    /// `Protocol = K40t`.
    ///
    /// ```
    /// use protocol_core::k40t::{HybridZoom, MessageData, MsgId, Kind};
    /// assert_eq!(HybridZoom::ID, MsgId::new(Kind::Request, 0x0304));
    /// assert_eq!(HybridZoom::NAME, "HybridZoom");
    /// assert_eq!(HybridZoom::ENCODED_LEN, 3);
    /// ```
    protocol K40t {
        id: MsgId, key: u16, order: Le, lengths: fixed, encoders: out_of_line,
    }
    /// Every base id this codec knows, in document order, with its kinds.
    catalog;
    /// A decoded message: what the payload of a frame means.
    message Message [Eq] {
        /// Unknown id or kind.
        Raw;
        /// Kind 0x00: requests and settings, and the periodic reports.
        Request [Eq] = MsgId::new(Kind::Request);
        /// Kind 0x01: acknowledgements, with their data where the document gives some.
        Ack [Eq] = MsgId::new(Kind::Ack) impl AckPayload {
            fn code(&self) -> ResponseCode {
                self.code
            }
        };
        /// Kind 0x02: status frames sent while a request executes.
        Status [Eq] = MsgId::new(Kind::Status);
    }
    // 3.1 gimbal
    0x0001 GimbalStatus: Request(GimbalStatus);
    0x0002 GimbalAttitude: Request(GimbalAttitude);
    0x0010 GimbalControl: Request(GimbalControl), Ack(GimbalControlAck { code: ResponseCode });
    0x0012 GimbalAngle: Request(GimbalAngle), Ack(GimbalAngleAck { code: ResponseCode });
    0x0013 DriftCalibration:
        Request(DriftCalibration), Ack(DriftCalibrationAck { code: ResponseCode });
    0x0017 DialSpeed: Request(DialSpeed), Ack(DialSpeedAck { code: ResponseCode });
    0x0018 GimbalVersion: Request(GimbalVersionQuery), Ack(GimbalVersionAck);
    0x002C PointToAim: Request(PointToAim), Ack(PointToAimAck { code: ResponseCode });
    0x002D ServoOff: Request(ServoOff), Ack(ServoOffAck { code: ResponseCode });
    0x002E LinearCalibration:
        Request(LinearCalibration), Ack(LinearCalibrationAck { code: ResponseCode });
    0x002F SoftRestart: Request(SoftRestart), Ack(SoftRestartAck { code: ResponseCode });
    0x0030 UseFcAttitude: Request(UseFcAttitude), Ack(UseFcAttitudeAck { code: ResponseCode });
    0x0031 AccelCalibration:
        Request(AccelCalibration), Ack(AccelCalibrationAck { code: ResponseCode });
    0x0033 Stabilization: Request(Stabilization), Ack(StabilizationAck { code: ResponseCode });
    // 3.2.1 camera reports
    0x0003 SystemStatus: Request(SystemStatus);
    0x0004 IrStatus: Request(IrStatus);
    0x0005 VisibleStatus: Request(VisibleStatus);
    0x0008 UpgradeStatus: Request(UpgradeStatus);
    // 3.2.2 infrared
    0x0100 IrParams: Request(IrParamsQuery), Ack(IrParams);
    0x0105 IrDigitalZoom: Request(IrDigitalZoom), Ack(IrDigitalZoomAck { code: ResponseCode });
    0x0106 IrPalette: Request(IrPalette), Ack(IrPaletteAck { code: ResponseCode });
    0x0108 IrMeasurement: Request(IrMeasurement), Ack(IrMeasurementAck { code: ResponseCode });
    0x010A IrSharpness: Request(IrSharpness), Ack(IrSharpnessAck { code: ResponseCode });
    0x010B IrBrightness: Request(IrBrightness), Ack(IrBrightnessAck { code: ResponseCode });
    0x010C IrContrast: Request(IrContrast), Ack(IrContrastAck { code: ResponseCode });
    0x010D IrDenoise: Request(IrDenoise), Ack(IrDenoiseAck { code: ResponseCode });
    0x010E IrEnhancement: Request(IrEnhancement), Ack(IrEnhancementAck { code: ResponseCode });
    0x010F IrPointMeasure: Request(IrPointMeasure), Ack(IrPointMeasureAck { code: ResponseCode });
    0x0110 IrAreaMeasure: Request(IrAreaMeasure), Ack(IrAreaMeasureAck { code: ResponseCode });
    0x0123 IrGainMode: Request(IrGainMode), Ack(IrGainModeAck { code: ResponseCode });
    0x0124 IrTempWarning: Request(IrTempWarning), Ack(IrTempWarningAck { code: ResponseCode });
    0x0125 IrTempOverlay: Request(IrTempOverlay), Ack(IrTempOverlayAck { code: ResponseCode });
    0x0126 IrThresholdWarning:
        Request(IrThresholdWarning), Ack(IrThresholdWarningAck { code: ResponseCode });
    // 3.2.3 visible
    0x0200 VisibleParams: Request(VisibleParamsQuery), Ack(VisibleParams);
    0x0201 VideoResolution:
        Request(VideoResolutionSetting), Ack(VideoResolutionAck { code: ResponseCode });
    0x0202 PhotoResolution:
        Request(PhotoResolutionSetting), Ack(PhotoResolutionAck { code: ResponseCode });
    0x0203 Iso: Request(IsoSetting), Ack(IsoAck { code: ResponseCode });
    0x0204 Shutter: Request(ShutterSetting), Ack(ShutterAck { code: ResponseCode });
    0x0205 Ev: Request(EvSetting), Ack(EvAck { code: ResponseCode });
    0x0206 WhiteBalance: Request(WhiteBalanceSetting), Ack(WhiteBalanceAck { code: ResponseCode });
    0x0207 AntiFlicker: Request(AntiFlickerSetting), Ack(AntiFlickerAck { code: ResponseCode });
    0x0208 StrongLight: Request(StrongLightSetting), Ack(StrongLightAck { code: ResponseCode });
    0x0209 Backlight: Request(BacklightSetting), Ack(BacklightAck { code: ResponseCode });
    0x020A AeLock: Request(AeLockSetting), Ack(AeLockAck { code: ResponseCode });
    0x020B Metering: Request(MeteringSetting), Ack(MeteringAck { code: ResponseCode });
    // 3.2.4 common
    0x0300 CaptureMode: Request(CaptureModeSetting), Ack(CaptureModeAck { code: ResponseCode });
    0x0301 PhotoParams: Request(PhotoParams), Ack(PhotoParamsAck { code: ResponseCode });
    0x0302 TakePhoto:
        Request(TakePhoto), Ack(TakePhotoAck { code: ResponseCode }), Status(PhotoStatus);
    0x0303 Record: Request(Record), Ack(RecordAck { code: ResponseCode }), Status(RecordStatus);
    0x0304 HybridZoom:
        Request(HybridZoom), Ack(HybridZoomAck { code: ResponseCode }), Status(ZoomStatus);
    0x0306 ContinuousZoom: Request(ContinuousZoom), Ack(ContinuousZoomAck { code: ResponseCode });
    0x0307 AccurateShoot:
        Request(AccurateShoot),
        Ack(AccurateShootAck { code: ResponseCode }),
        Status(AccurateShootStatus);
    0x0308 StreamBitrate:
        Request(StreamBitrateSetting), Ack(StreamBitrateAck { code: ResponseCode });
    0x030A OutputResolution:
        Request(OutputResolutionSetting), Ack(OutputResolutionAck { code: ResponseCode });
    0x030B OutputCodec: Request(OutputCodecSetting), Ack(OutputCodecAck { code: ResponseCode });
    0x030C TfUpgrade:
        Request(TfUpgrade), Ack(TfUpgradeAck { code: ResponseCode }), Status(TfUpgradeStatus);
    0x030D FormatSd:
        Request(FormatSd), Ack(FormatSdAck { code: ResponseCode }), Status(FormatStatus);
    0x030E TimeSync: Request(TimeSync), Ack(TimeSyncAck { code: ResponseCode });
    0x030F FactoryReset: Request(FactoryReset), Ack(FactoryResetAck { code: ResponseCode });
    0x0310 GpsRequest: Request(GpsRequest), Ack(GpsReply);
    0x0311 SetIp: Request(SetIp), Ack(SetIpAck { code: ResponseCode });
    0x0312 GetIp: Request(IpQuery), Ack(IpConfigAck);
    0x0313 Focus: Request(Focus), Ack(FocusAck { code: ResponseCode });
    0x0314 Watermark: Request(Watermark), Ack(WatermarkAck { code: ResponseCode });
    0x0316 Shutdown: Request(Shutdown), Ack(ShutdownAck { code: ResponseCode });
    0x0317 CameraVersion: Request(CameraVersionQuery), Ack(CameraVersionAck);
    0x0318 ImageMode: Request(ImageModeSetting), Ack(ImageModeAck { code: ResponseCode });
    0x0319 AiRecognition: Request(AiRecognition), Ack(AiRecognitionAck { code: ResponseCode });
    0x0320 TargetGps: Request(TargetGpsRequest), Ack(TargetGpsAck);
    0x0324 TrackBox: Request(TrackBox), Ack(TrackBoxAck { code: ResponseCode });
    // 3.2.5 laser
    0x0400 LaserRange: Request(LaserRange), Ack(LaserDistance);
    0x0406 LaserPeriodic:
        Request(LaserPeriodic),
        Ack(LaserPeriodicAck { code: ResponseCode }),
        Status(LaserPeriodicStatus(LaserDistance));
    // 3.2.6 SBUS
    0x0500 SbusRange: Request(SbusRange), Ack(SbusRangeAck { code: ResponseCode });
    0x0501 SbusChannels: Request(SbusChannels), Ack(SbusChannelsAck { code: ResponseCode });
    0x0502 SbusConfig: Request(SbusConfigQuery), Ack(SbusConfig);
}

/// The base id and a per-kind encoder on each kind's enum ([`Request`], [`Ack`],
/// [`Status`]), besides what the message table generates.
macro_rules! kind_methods {
    ($($kind:ident)*) => {$(
        impl $kind {
            /// The base id (the message id without its kind).
            #[must_use]
            pub const fn base(&self) -> u16 {
                self.id().base
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
    )*};
}

kind_methods!(Request Ack Status);

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
}

wire_derive! {
    [Eq, Hash]
    /// Everything of a frame but its message: addresses, sequence number, CRC coverage.
    pub struct Header {
        /// The receiver's system and component ids.
        pub dst: Address,
        /// The sender's system and component ids.
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
        /// What the payload means.
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
    pub fn decode_as<M: MessageData<Protocol = K40t>>(&self) -> Option<Result<M>> {
        (self.id() == M::ID).then(|| M::decode_payload(self.payload()))
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
pub fn encode<M: MessageData<Protocol = K40t>>(
    message: &M,
    header: &Header,
    buf: &mut [u8],
) -> Result<usize> {
    emit_frame(*header, M::ID, M::ENCODED_LEN, buf, |w| {
        message.encode_payload(w)
    })
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

    /// Reference frames built by an encoder independent of the project, following the
    /// codec's decisions (the document prints none; see docs/src/protocols/k40t.md).
    #[test]
    fn independent_reference_frames() {
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
