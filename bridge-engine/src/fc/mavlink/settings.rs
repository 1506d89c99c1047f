//! The camera settings the bridge offers as camera-definition parameters
//! (`bridge-engine/camera/k40t.xml`): for each, its name, its values, the K40T set
//! command that changes it and where the pod reports it (the mapping table:
//! docs/src/bridge/mavlink.md). A test checks the XML against this table.
//!
//! Values are the K40T document's codes wherever the pod has codes (resolutions, ISO,
//! shutter, EV, white balance, ...), so that a value goes to the pod and comes back
//! unchanged; switches the pod codes as 1 on / 2 off (AE lock, strong-light suppression,
//! backlight compensation) or 0 on / 1 off (IR measurement) are 0 off / 1 on, as every
//! switch of the definition.

use crate::pod::PodState;
use protocol_core::k40t::{
    self, AeLock, AeLockSetting, AntiFlicker, AntiFlickerSetting, BacklightSetting, CaptureMode,
    CaptureModeSetting, Ev, EvSetting, ImageMode, ImageModeSetting, IrDenoise, IrDigitalZoom,
    IrGain, IrGainMode, IrMeasurement, IrParams, IrTempOverlay, Iso, IsoSetting, MeasureSwitch,
    Metering, MeteringSetting, OnOff, OutputCodecSetting, Palette, PhotoMode, PhotoParams,
    PhotoResolution, PhotoResolutionSetting, Request, Shutter, ShutterSetting, Stabilization,
    StabilizationState, StreamBitrate, StreamBitrateSetting, StrongLightSetting, Toggle,
    VideoCodec, VideoResolution, VideoResolutionSetting, VisibleParams, Watermark, WhiteBalance,
    WhiteBalanceSetting,
};

/// One camera setting (a parameter of the camera definition), in the definition's order
/// (its index is the parameter's `param_index`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Setting {
    Mode,
    ImageMode,
    PhotoMode,
    Burst,
    Lapse,
    PhotoResolution,
    VideoResolution,
    StreamBitrate,
    StreamEncoding,
    Osd,
    Stabilization,
    Iso,
    Shutter,
    Ev,
    WhiteBalance,
    AntiFlicker,
    Metering,
    AeLock,
    StrongLight,
    StrongLightLevel,
    Backlight,
    BacklightLevel,
    IrPalette,
    IrGain,
    IrMeasure,
    IrTempOverlay,
    IrZoom,
    IrSharpness,
    IrBrightness,
    IrContrast,
    IrDenoise,
    IrDenoiseLevel,
    IrEnhancement,
}

/// Number of settings.
pub(super) const COUNT: usize = 33;

/// Every setting, in the definition's order.
pub(super) const ALL: [Setting; COUNT] = [
    Setting::Mode,
    Setting::ImageMode,
    Setting::PhotoMode,
    Setting::Burst,
    Setting::Lapse,
    Setting::PhotoResolution,
    Setting::VideoResolution,
    Setting::StreamBitrate,
    Setting::StreamEncoding,
    Setting::Osd,
    Setting::Stabilization,
    Setting::Iso,
    Setting::Shutter,
    Setting::Ev,
    Setting::WhiteBalance,
    Setting::AntiFlicker,
    Setting::Metering,
    Setting::AeLock,
    Setting::StrongLight,
    Setting::StrongLightLevel,
    Setting::Backlight,
    Setting::BacklightLevel,
    Setting::IrPalette,
    Setting::IrGain,
    Setting::IrMeasure,
    Setting::IrTempOverlay,
    Setting::IrZoom,
    Setting::IrSharpness,
    Setting::IrBrightness,
    Setting::IrContrast,
    Setting::IrDenoise,
    Setting::IrDenoiseLevel,
    Setting::IrEnhancement,
];

/// The values a setting takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Values {
    /// One of these (the definition's `<options>`).
    Options(&'static [u8]),
    /// `min..=max` in steps of 1 (the definition's `min`, `max`, `step`).
    Range(u8, u8),
}

/// Where the pod reports a setting.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Source {
    /// The ACK of 0x000100 (asked again after a change).
    Ir,
    /// The ACK of 0x000200 (asked again after a change).
    Visible,
    /// A periodic report (0x000001, 0x000003, 0x000005).
    Report,
    /// Nowhere: the bridge remembers what the pod last accepted.
    None,
}

const OFF_ON: &[u8] = &[0, 1];
const LEVEL: Values = Values::Range(0, 100);

/// Name, values and definition default of each setting, in [`ALL`]'s order.
const DEFS: [(&str, Values, u8); COUNT] = [
    ("CAM_MODE", Values::Options(&[0, 1]), 0),
    ("CAM_IMAGEMODE", Values::Options(&[5, 0, 7]), 5),
    ("CAM_PHOTOMODE", Values::Options(&[0, 1, 2]), 0),
    ("CAM_BURST", Values::Options(&[3, 5]), 3),
    ("CAM_LAPSE", Values::Options(&[5, 7, 30, 60]), 5),
    ("CAM_PHOTORES", Values::Options(&[0x14, 0x15]), 0x15),
    ("CAM_VIDRES", Values::Options(&[0x08, 0x26, 0x36]), 0x08),
    ("CAM_STREAMBR", Values::Options(&[1, 2, 3, 4, 5, 6]), 4),
    ("CAM_STREAMENC", Values::Options(&[0, 1]), 0),
    ("CAM_OSD", Values::Options(OFF_ON), 0),
    ("CAM_STABILIZE", Values::Options(OFF_ON), 0),
    ("CAM_ISO", Values::Options(&[0, 1, 2, 3, 4, 5, 6, 7]), 0),
    (
        "CAM_SHUTTERSPD",
        Values::Options(&[0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14]),
        0,
    ),
    (
        "CAM_EV",
        Values::Options(&[0, 0x23, 0x1C, 0x16, 0x10, 0x0A]),
        0,
    ),
    ("CAM_WBMODE", Values::Options(&[1, 2, 3, 4, 5, 6, 7, 8]), 1),
    ("CAM_FLICKER", Values::Options(&[1, 2, 3, 4]), 4),
    ("CAM_METERING", Values::Options(&[1, 2, 3]), 1),
    ("CAM_AELOCK", Values::Options(OFF_ON), 0),
    ("CAM_HLSUPP", Values::Options(OFF_ON), 0),
    ("CAM_HLSUPP_LV", LEVEL, 50),
    ("CAM_BACKLIGHT", Values::Options(OFF_ON), 0),
    ("CAM_BACKLIGHT_LV", LEVEL, 50),
    (
        "IR_PALETTE",
        Values::Options(&[
            1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20,
        ]),
        1,
    ),
    ("IR_GAIN", Values::Options(&[0, 1, 2]), 0),
    ("IR_MEASURE", Values::Options(OFF_ON), 1),
    ("IR_TEMP_OSD", Values::Options(OFF_ON), 0),
    ("IR_ZOOM", Values::Options(&[1, 2, 3, 4, 5, 6, 7, 8]), 1),
    ("IR_SHARPNESS", LEVEL, 50),
    ("IR_BRIGHTNESS", LEVEL, 50),
    ("IR_CONTRAST", LEVEL, 50),
    ("IR_DENOISE", Values::Options(OFF_ON), 1),
    ("IR_DENOISE_LV", LEVEL, 50),
    ("IR_ENHANCE", Values::Range(0, 10), 0),
];

/// 0 off / 1 on from a switch.
fn on(b: bool) -> u8 {
    u8::from(b)
}

/// A 1 on / 2 off switch byte from 0 off / 1 on.
fn toggle(v: u8) -> Toggle {
    if v == 1 { Toggle::On } else { Toggle::Off }
}

fn on_off(v: u8) -> OnOff {
    if v == 1 { OnOff::On } else { OnOff::Off }
}

/// A "switch in bit 7, level in bits 0..6" byte of the 0x000200 ACK (strong-light
/// suppression, backlight compensation; the document also writes 0x01 on / 0x02 off for
/// the switch, which bit 7 cannot hold: the bit is read).
fn bit7(byte: u8) -> (u8, u8) {
    (byte >> 7, byte & 0x7F)
}

impl Setting {
    /// Its position in [`ALL`] (the parameter index).
    pub(super) const fn index(self) -> usize {
        self as usize
    }

    /// The setting at `index`.
    pub(super) fn at(index: usize) -> Option<Self> {
        ALL.get(index).copied()
    }

    /// The setting named `name` (the parameter id, at most 16 characters).
    pub(super) fn named(name: &[u8]) -> Option<Self> {
        ALL.iter().copied().find(|s| s.name().as_bytes() == name)
    }

    fn def(self) -> (&'static str, Values, u8) {
        DEFS.get(self.index())
            .copied()
            .unwrap_or(("", Values::Range(0, 0), 0))
    }

    /// The parameter id.
    pub(super) fn name(self) -> &'static str {
        self.def().0
    }

    /// The values it takes.
    pub(super) fn values(self) -> Values {
        self.def().1
    }

    /// The definition's default: what is reported while the pod has not told the value.
    pub(super) fn default_value(self) -> u8 {
        self.def().2
    }

    /// Its MAVLink type is uint32 (CAM_MODE, as the Camera Protocol's examples type it);
    /// every other setting is uint8.
    pub(super) fn wide(self) -> bool {
        self == Setting::Mode
    }

    /// `v` is one of its values.
    pub(super) fn allows(self, v: u8) -> bool {
        match self.values() {
            Values::Options(o) => o.contains(&v),
            Values::Range(min, max) => (min..=max).contains(&v),
        }
    }

    /// Where the pod reports it.
    pub(super) fn source(self) -> Source {
        use Setting as S;
        match self {
            S::Mode
            | S::ImageMode
            | S::PhotoMode
            | S::Burst
            | S::Lapse
            | S::StreamBitrate
            | S::StreamEncoding
            | S::Stabilization => Source::Report,
            S::IrTempOverlay => Source::None,
            S::IrPalette
            | S::IrGain
            | S::IrMeasure
            | S::IrZoom
            | S::IrSharpness
            | S::IrBrightness
            | S::IrContrast
            | S::IrDenoise
            | S::IrDenoiseLevel
            | S::IrEnhancement => Source::Ir,
            _ => Source::Visible,
        }
    }

    /// The value the pod last reported (`None`: not reported yet, or not at all).
    pub(super) fn read(self, pod: &PodState) -> Option<u8> {
        use Setting as S;
        let sys = pod.system;
        let vis = pod.visible_params;
        let ir = pod.ir_params;
        let v = |f: fn(&VisibleParams) -> u8| vis.as_ref().map(f);
        let i = |f: fn(&IrParams) -> u8| ir.as_ref().map(f);
        match self {
            S::Mode => sys.map(|s| s.mode.value()),
            // 0x05 and 0x06 are both visible light (K40T external protocol, 3.2.4.22).
            S::ImageMode => sys.map(|s| match s.stream {
                ImageMode::VisibleAlt => ImageMode::Visible.value(),
                m => m.value(),
            }),
            S::PhotoMode => sys.map(|s| s.photo_mode.value()),
            S::Burst => sys.map(|s| s.burst_count),
            S::Lapse => sys.map(|s| s.timelapse_s),
            S::StreamBitrate => sys.map(|s| s.preview_bitrate.value()),
            S::StreamEncoding => sys.map(|s| s.preview_codec.value()),
            S::Stabilization => pod
                .gimbal_status
                .map(|g| on(g.stabilization != StabilizationState::Off)),
            S::PhotoResolution => v(|p| p.photo_resolution.value()),
            S::VideoResolution => v(|p| p.video_resolution.value()),
            S::Osd => v(|p| on(p.osd_flicker.watermark() != 0)),
            S::Iso => v(|p| p.iso.value()),
            S::Shutter => v(|p| p.shutter.value()),
            // The periodic visible status (0x000005) first: it is the fresher.
            S::Ev => pod.visible.map(|s| s.ev.value()).or(v(|p| p.ev.value())),
            S::WhiteBalance => v(|p| p.white_balance.value() & 0x0F),
            S::AntiFlicker => v(|p| p.osd_flicker.anti_flicker().value()),
            S::Metering => v(|p| p.metering.value()),
            S::AeLock => match pod.visible.map(|s| s.ae_lock).or(vis.map(|p| p.ae_lock)) {
                Some(AeLock::On) => Some(1),
                Some(AeLock::Off) => Some(0),
                _ => None,
            },
            S::StrongLight => v(|p| bit7(p.strong_light).0),
            S::StrongLightLevel => v(|p| bit7(p.strong_light).1),
            S::Backlight => v(|p| bit7(p.backlight).0),
            S::BacklightLevel => v(|p| bit7(p.backlight).1),
            S::IrPalette => i(|p| p.palette.value()),
            S::IrGain => i(|p| p.gain.value()),
            S::IrMeasure => i(|p| on(p.measure.measuring())),
            S::IrTempOverlay => None,
            // Bits 3..7 of byte 4; 0 (no magnification) reads as 1x.
            S::IrZoom => i(|p| p.measure.digital_zoom().max(1)),
            S::IrSharpness => i(|p| p.sharpness),
            S::IrBrightness => i(|p| p.brightness),
            S::IrContrast => i(|p| p.contrast),
            S::IrDenoise => i(|p| on(p.denoise.on())),
            S::IrDenoiseLevel => i(|p| p.denoise.level()),
            // The byte as 0x00010E sets it: 0 off, 1..=10 the level (the document's bit 0
            // "switch" overlaps its bits 0..6 "parameters"; see docs/src/bridge/mavlink.md).
            S::IrEnhancement => i(|p| p.enhancement),
        }
    }

    /// The K40T request that sets it to `v`; a command that sets several settings at once
    /// (0x000301, 0x000208, 0x000209, 0x00010D) takes the others from `current`.
    #[allow(clippy::too_many_lines)] // one short arm per setting
    pub(super) fn request(self, v: u8, current: impl Fn(Setting) -> u8) -> Request {
        use Setting as S;
        let get = |s: Setting| if s == self { v } else { current(s) };
        match self {
            S::Mode => Request::CaptureMode(CaptureModeSetting {
                mode: CaptureMode::from_value(v),
                reserved: 0,
            }),
            S::ImageMode => Request::ImageMode(ImageModeSetting {
                mode: ImageMode::from_value(v),
                reserved: 0,
            }),
            S::PhotoMode | S::Burst | S::Lapse => Request::PhotoParams(PhotoParams {
                mode: PhotoMode::from_value(get(S::PhotoMode)),
                timelapse_s: get(S::Lapse),
                burst_count: get(S::Burst),
                reserved: 0,
            }),
            S::PhotoResolution => Request::PhotoResolution(PhotoResolutionSetting {
                start: 0,
                resolution: PhotoResolution::from_value(v),
            }),
            S::VideoResolution => Request::VideoResolution(VideoResolutionSetting {
                start: 0,
                resolution: VideoResolution::from_value(v),
            }),
            S::StreamBitrate => Request::StreamBitrate(StreamBitrateSetting {
                bitrate: StreamBitrate::from_value(v),
                reserved: 0,
            }),
            S::StreamEncoding => Request::OutputCodec(OutputCodecSetting {
                codec: VideoCodec::from_value(v),
                reserved: 0,
            }),
            S::Osd => Request::Watermark(Watermark {
                enable: on_off(v),
                reserved: [0; 2],
            }),
            S::Stabilization => Request::Stabilization(Stabilization {
                enable: on_off(v),
                reserved: 0,
            }),
            S::Iso => Request::Iso(IsoSetting {
                start: 0,
                iso: Iso::from_value(v),
            }),
            S::Shutter => Request::Shutter(ShutterSetting {
                start: 0,
                shutter: Shutter::from_value(v),
            }),
            S::Ev => Request::Ev(EvSetting {
                start: 0,
                ev: Ev::from_value(v),
            }),
            S::WhiteBalance => Request::WhiteBalance(WhiteBalanceSetting {
                start: 0,
                white_balance: WhiteBalance::from_value(v),
                reserved: [0; 2],
            }),
            S::AntiFlicker => Request::AntiFlicker(AntiFlickerSetting {
                start: 0,
                mode: AntiFlicker::from_value(v),
            }),
            S::Metering => Request::Metering(MeteringSetting {
                start: 0,
                mode: Metering::from_value(v),
            }),
            S::AeLock => Request::AeLock(AeLockSetting {
                start: 0,
                lock: if v == 1 { AeLock::On } else { AeLock::Off },
            }),
            S::StrongLight | S::StrongLightLevel => Request::StrongLight(StrongLightSetting {
                start: 0,
                enable: toggle(get(S::StrongLight)),
                value: get(S::StrongLightLevel),
            }),
            S::Backlight | S::BacklightLevel => Request::Backlight(BacklightSetting {
                start: 0,
                enable: toggle(get(S::Backlight)),
                value: get(S::BacklightLevel),
            }),
            S::IrPalette => Request::IrPalette(k40t::IrPalette {
                palette: Palette::from_value(v),
                reserved: 0,
            }),
            S::IrGain => Request::IrGainMode(IrGainMode {
                gain: IrGain::from_value(v),
                reserved: 0,
            }),
            S::IrMeasure => Request::IrMeasurement(IrMeasurement {
                switch: if v == 1 {
                    MeasureSwitch::On
                } else {
                    MeasureSwitch::Off
                },
                reserved: 0,
            }),
            S::IrTempOverlay => Request::IrTempOverlay(IrTempOverlay {
                overlay: on_off(v),
                reserved: 0,
            }),
            S::IrZoom => Request::IrDigitalZoom(IrDigitalZoom {
                zoom_x: v,
                reserved: 0,
            }),
            S::IrSharpness => Request::IrSharpness(k40t::IrSharpness {
                sharpness: v,
                reserved: 0,
            }),
            S::IrBrightness => Request::IrBrightness(k40t::IrBrightness {
                brightness: v,
                reserved: 0,
            }),
            S::IrContrast => Request::IrContrast(k40t::IrContrast {
                contrast: v,
                reserved: 0,
            }),
            S::IrDenoise | S::IrDenoiseLevel => Request::IrDenoise(IrDenoise {
                enable: on_off(get(S::IrDenoise)),
                level: get(S::IrDenoiseLevel),
                reserved: 0,
            }),
            S::IrEnhancement => Request::IrEnhancement(k40t::IrEnhancement {
                level: v,
                reserved: 0,
            }),
        }
    }
}
