//! Camera messages: focus and zoom (0x04..0x06, 0x0F, 0x16, 0x18), photo and record
//! functions (0x0B, 0x0C), video stitching (0x10, 0x11) and codec settings (0x20, 0x21).

use super::payload::{AckStatus, Payload, Trailing, optional, trailing_len};
use crate::wire::encoding::{Field, Le};
use crate::wire::{Reader, Writer};
use crate::{Error, Result};

wire_struct! {
    Le;
    /// 0x04: auto focus once at a point of the image (optical-zoom models).
    pub struct AutoFocus {
        /// 1: start one auto focus.
        pub start: u8,
        /// X coordinate, 0..video width (half the width in stitched images).
        pub x: u16,
        /// Y coordinate, 0..video height.
        pub y: u16,
    }
}

code_enum! {
    /// Manual zoom command of 0x05 (sent as a signed byte: -1 is 0xFF).
    pub enum ZoomDirection: i8 {
        /// 1: zoom in.
        In = 1,
        /// 0: stop zooming (sent on release).
        Stop = 0,
        /// -1: zoom out.
        Out = -1,
    }
}

wire_struct! {
    Le;
    /// 0x05: manual zoom (with auto focus on optical-zoom models).
    pub struct ManualZoom {
        /// Zoom in, out or stop.
        pub direction: ZoomDirection,
    }
}

wire_struct! {
    Le;
    /// Reply of 0x05: the current (hybrid) zoom ratio.
    pub struct ZoomRatio {
        /// Zoom ratio times ten (45 = 4.5x).
        pub zoom_x10: u16,
    }
}

code_enum! {
    /// Manual focus command of 0x06.
    pub enum FocusDirection: i8 {
        /// 1: focus far.
        Far = 1,
        /// 0: stop focusing (sent on release).
        Stop = 0,
        /// -1: focus near.
        Near = -1,
    }
}

wire_struct! {
    Le;
    /// 0x06: manual focus.
    pub struct ManualFocus {
        /// Far, near or stop.
        pub direction: FocusDirection,
    }
}

wire_struct! {
    Le, bytes;
    /// A zoom ratio as integer and tenths: the layout of [`AbsoluteZoom`](super::AbsoluteZoom)
    /// (0x0F request, integer 0x01..0x1E, tenths 0..9), [`MaxZoom`](super::MaxZoom) (0x16 reply)
    /// and [`CurrentZoom`](super::CurrentZoom) (0x18 reply).
    pub struct ZoomLevel {
        /// Integer part.
        pub integer: u8,
        /// Tenths of the ratio, 0..=9.
        pub tenths: u8,
    }
}

impl ZoomLevel {
    /// The ratio times ten (4.5x is 45).
    #[must_use]
    pub const fn zoom_x10(self) -> u16 {
        (self.integer as u16)
            .saturating_mul(10)
            .saturating_add(self.tenths as u16)
    }

    /// The level for a ratio times ten (45 is 4 and 5).
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for a ratio above 255.9x.
    pub fn from_zoom_x10(zoom_x10: u16) -> Result<Self> {
        let integer = u8::try_from(zoom_x10 / 10).map_err(|_| Error::OutOfRange)?;
        let tenths = u8::try_from(zoom_x10 % 10).map_err(|_| Error::OutOfRange)?;
        Ok(ZoomLevel { integer, tenths })
    }
}

code_enum! {
    /// Event of 0x0B (pushed by the camera).
    pub enum FeedbackInfo: u8 {
        /// 0: photo taken.
        PhotoOk = 0,
        /// 1: photo failed (is a TF card inserted?).
        PhotoFailed = 1,
        /// 2: HDR on.
        HdrOn = 2,
        /// 3: HDR off.
        HdrOff = 3,
        /// 4: recording failed (is a TF card inserted?).
        RecordFailed = 4,
        /// 5: recording started.
        RecordStarted = 5,
        /// 6: recording stopped.
        RecordStopped = 6,
    }
}

wire_struct! {
    Le;
    /// Reply (push) of 0x0B: function feedback.
    pub struct FunctionFeedback {
        /// What happened: photo taken or failed, recording started, stopped or failed, HDR
        /// on or off.
        pub info: FeedbackInfo,
    }
}

code_enum! {
    /// Function of 0x0C.
    pub enum CameraFunctionType: u8 {
        /// 0: take a photo.
        TakePhoto = 0,
        /// 1: toggle HDR (not supported yet by the cameras).
        HdrToggle = 1,
        /// 2: start or stop recording.
        RecordToggle = 2,
        /// 3: motion mode lock.
        LockMode = 3,
        /// 4: motion mode follow.
        FollowMode = 4,
        /// 5: motion mode FPV.
        FpvMode = 5,
        /// 6: HDMI video output (ZT6, A8 mini; after reboot).
        HdmiOutput = 6,
        /// 7: CVBS video output (ZT6, A8 mini; after reboot).
        CvbsOutput = 7,
        /// 8: HDMI and CVBS output off (ZT6, A8 mini; after reboot).
        VideoOutputOff = 8,
        /// 9: tilt downward.
        TiltDownward = 9,
        /// 10: zoom linkage.
        ZoomLinkage = 10,
    }
}

wire_struct! {
    Le;
    /// 0x0C: photo, record, motion mode and video output functions (no reply).
    pub struct CameraFunction {
        /// Photo, recording, motion mode or video output.
        pub function: CameraFunctionType,
    }
}

code_enum! {
    /// Video stitching mode (0x10, 0x11; ZT30, ZT6): what the main and sub streams
    /// show. Picture-in-picture modes are the stitched ones.
    pub enum StitchingMode: u8 {
        /// 0: main zoom & thermal, sub wide angle.
        PipZoomThermalSubWide = 0,
        /// 1: main wide angle & thermal, sub zoom.
        PipWideThermalSubZoom = 1,
        /// 2: main zoom & wide angle, sub thermal.
        PipZoomWideSubThermal = 2,
        /// 3: main zoom, sub thermal.
        ZoomSubThermal = 3,
        /// 4: main zoom, sub wide angle.
        ZoomSubWide = 4,
        /// 5: main wide angle, sub thermal.
        WideSubThermal = 5,
        /// 6: main wide angle, sub zoom.
        WideSubZoom = 6,
        /// 7: main thermal, sub zoom.
        ThermalSubZoom = 7,
        /// 8: main thermal, sub wide angle.
        ThermalSubWide = 8,
    }
}

wire_struct! {
    Le;
    /// Reply of 0x10: the video stitching mode (also the layout of 0x11,
    /// [`SetStitching`](super::SetStitching) and [`SetStitchingAck`](super::SetStitchingAck)).
    pub struct Stitching {
        /// The mode (`vdisp_mode`).
        pub mode: StitchingMode,
    }
}

code_enum! {
    /// Video stream of 0x20, 0x21.
    pub enum StreamType: u8 {
        /// 0: recording stream.
        Record = 0,
        /// 1: main stream.
        Main = 1,
        /// 2: sub stream (ZT30, ZT6).
        Sub = 2,
    }
}

code_enum! {
    /// Video encoding of 0x20, 0x21.
    pub enum VideoEncoding: u8 {
        /// 1: H.264.
        H264 = 1,
        /// 2: H.265.
        H265 = 2,
    }
}

wire_struct! {
    Le;
    /// 0x20: get the codec settings of a stream.
    pub struct CodecQuery {
        /// Recording, main or sub stream.
        pub stream: StreamType,
    }
}

wire_derive! {
    [Eq, Hash, Default]
    /// Reply of 0x20: codec settings of a stream. 9 bytes; 8-byte replies without the
    /// frame rate (which ArduPilot also accepts) decode with `fps: None` and re-encode to 8.
    pub struct CodecSpecs {
        /// Recording, main or sub stream.
        pub stream: StreamType,
        /// H.264 or H.265.
        pub encoding: VideoEncoding,
        /// Width, pixels.
        pub width: u16,
        /// Height, pixels.
        pub height: u16,
        /// Bit rate, kbit/s.
        pub bitrate_kbps: u16,
        /// Frame rate, frames per second.
        pub fps: Option<u8>,
    }
}

/// 0x20 reply without the frame rate.
const CODEC_SPECS_MIN_LEN: usize = 8;

impl Payload for CodecSpecs {
    const MAX_LEN: usize = 9;

    fn decode(data: &[u8]) -> Result<Self> {
        if data.len() != CODEC_SPECS_MIN_LEN && data.len() != Self::MAX_LEN {
            return Err(Error::BadLength);
        }
        let mut r = Reader::new(data);
        let v = CodecSpecs {
            stream: Field::<Le>::read(&mut r)?,
            encoding: Field::<Le>::read(&mut r)?,
            width: Field::<Le>::read(&mut r)?,
            height: Field::<Le>::read(&mut r)?,
            bitrate_kbps: Field::<Le>::read(&mut r)?,
            fps: optional(&mut r)?,
        };
        r.finish()?;
        Ok(v)
    }
    fn encoded_len(&self) -> usize {
        CODEC_SPECS_MIN_LEN.saturating_add(trailing_len(&[(self.fps.is_some(), 1)]))
    }
    fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
        Field::<Le>::write(&self.stream, w)?;
        Field::<Le>::write(&self.encoding, w)?;
        Field::<Le>::write(&self.width, w)?;
        Field::<Le>::write(&self.height, w)?;
        Field::<Le>::write(&self.bitrate_kbps, w)?;
        Trailing::new(w).field(self.fps.as_ref())
    }
}

wire_struct! {
    Le;
    /// 0x21: set the codec of a stream.
    pub struct SetCodec {
        /// Recording, main or sub stream.
        pub stream: StreamType,
        /// H.264 or H.265.
        pub encoding: VideoEncoding,
        /// Width, pixels (1920, 1280).
        pub width: u16,
        /// Height, pixels (1080, 720).
        pub height: u16,
        /// Bit rate, kbit/s.
        pub bitrate_kbps: u16,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

wire_struct! {
    Le;
    /// Reply of 0x21.
    pub struct SetCodecAck {
        /// Recording, main or sub stream.
        pub stream: StreamType,
        /// Whether the codec was set.
        pub status: AckStatus,
    }
}
