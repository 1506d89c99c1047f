//! The camera settings the pod keeps (K40T external protocol, 3.2.2 infrared, 3.2.3
//! visible, 3.2.4 common), as its all-settings ACKs (0x000100, 0x000200) report them; the
//! set commands that change them; the SD card's format (0x00030D) and the factory reset
//! (0x00030F).
//!
//! - Every set command is ACKed OK and applied, except where the document says the pod
//!   refuses: strong-light suppression and backlight compensation "cannot be set at the
//!   same time" (3.2.3.9, 3.2.3.10: switching one on while the other is on is answered
//!   Failure), and formatting "fails during video recording and photo taking" (3.2.4.12:
//!   Recording, or PhotoInProgress). Any other refusal on demand:
//!   [`PodSimConfig::nak`](super::PodSimConfig::nak).
//! - The values the document leaves open are this simulator's: the initial settings are
//!   the camera definition's defaults (`bridge-engine/camera/k40t.xml`); 0x000100's
//!   enhancement byte carries the level as 0x00010E sets it; the watermark switch of
//!   0x000200's byte 16 is 1 when on.
//! - **Format**: status frames (0x02030D) "in progress" at once and every 200 ms for
//!   [`FORMAT_US`], then "completed"; from then on 0x000003 reports the card empty.
//! - **Factory reset**: every setting back to its initial value (the pod's restart a
//!   second later and its IP configuration are not modelled).

use super::*;

/// How long a format takes.
pub const FORMAT_US: u64 = 1_000_000;
/// Interval of the format status frames (5 Hz).
const FORMAT_STATUS_PERIOD_US: u64 = 200_000;

/// The settings 0x000100 and 0x000200 report that [`CameraState`] does not otherwise hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PodSettings {
    /// 0x000202.
    pub photo_resolution: PhotoResolution,
    /// 0x000201.
    pub video_resolution: VideoResolution,
    /// 0x000203.
    pub iso: k40t::Iso,
    /// 0x000204.
    pub shutter: Shutter,
    /// 0x000206.
    pub white_balance: WhiteBalance,
    /// 0x000207.
    pub anti_flicker: k40t::AntiFlicker,
    /// 0x00020B.
    pub metering: Metering,
    /// 0x000208: on, level.
    pub strong_light: (bool, u8),
    /// 0x000209: on, level.
    pub backlight: (bool, u8),
    /// 0x000314.
    pub watermark: bool,
    /// 0x000123.
    pub ir_gain: IrGain,
    /// 0x000105, 1..=8.
    pub ir_zoom: u8,
    /// 0x00010A.
    pub ir_sharpness: u8,
    /// 0x00010B.
    pub ir_brightness: u8,
    /// 0x00010C.
    pub ir_contrast: u8,
    /// 0x00010D: on, level.
    pub ir_denoise: (bool, u8),
    /// 0x00010E: 0 off, 1..=10.
    pub ir_enhancement: u8,
    /// 0x000125 (not in any report).
    pub ir_temp_overlay: bool,
    /// The card was formatted: empty from this instant on (0x00030D).
    pub card_emptied_at_us: Option<u64>,
}

impl Default for PodSettings {
    fn default() -> Self {
        PodSettings {
            photo_resolution: PhotoResolution::R4000x3000,
            video_resolution: VideoResolution::R1080p,
            iso: k40t::Iso::Auto,
            shutter: Shutter::Auto,
            white_balance: WhiteBalance::Auto,
            anti_flicker: k40t::AntiFlicker::Auto,
            metering: Metering::CenterWeighted,
            strong_light: (false, 50),
            backlight: (false, 50),
            watermark: false,
            ir_gain: IrGain::High,
            ir_zoom: 1,
            ir_sharpness: 50,
            ir_brightness: 50,
            ir_contrast: 50,
            ir_denoise: (true, 50),
            ir_enhancement: 0,
            ir_temp_overlay: false,
            card_emptied_at_us: None,
        }
    }
}

/// A switch in bit 7 and a level in bits 0..6.
fn bit7((on, level): (bool, u8)) -> u8 {
    (u8::from(on) << 7) | (level & 0x7F)
}

impl SimPod {
    /// A setting, the format or the factory reset (the requests
    /// [`SimPod::execute`](super::SimPod) leaves to this module); anything else: OK, no
    /// effect.
    pub(super) fn apply_setting(
        &mut self,
        t: u64,
        request: Request,
    ) -> Result<Option<Vec<u8>>, AckCode> {
        let s = &mut self.camera.settings;
        match request {
            Request::PhotoResolution(r) => s.photo_resolution = r.resolution,
            Request::VideoResolution(r) => s.video_resolution = r.resolution,
            Request::Iso(r) => s.iso = r.iso,
            Request::Shutter(r) => s.shutter = r.shutter,
            Request::WhiteBalance(r) => s.white_balance = r.white_balance,
            Request::AntiFlicker(r) => s.anti_flicker = r.mode,
            Request::Metering(r) => s.metering = r.mode,
            Request::StrongLight(r) => {
                let on = r.enable == Toggle::On;
                if on && s.backlight.0 {
                    return Err(AckCode::Failure);
                }
                s.strong_light = (on, r.value.min(100));
            }
            Request::Backlight(r) => {
                let on = r.enable == Toggle::On;
                if on && s.strong_light.0 {
                    return Err(AckCode::Failure);
                }
                s.backlight = (on, r.value.min(100));
            }
            Request::Watermark(w) => s.watermark = w.enable == OnOff::On,
            Request::IrGainMode(g) => s.ir_gain = g.gain,
            Request::IrDigitalZoom(z) => s.ir_zoom = z.zoom_x.clamp(1, 8),
            Request::IrSharpness(v) => s.ir_sharpness = v.sharpness.min(100),
            Request::IrBrightness(v) => s.ir_brightness = v.brightness.min(100),
            Request::IrContrast(v) => s.ir_contrast = v.contrast.min(100),
            Request::IrDenoise(d) => s.ir_denoise = (d.enable == OnOff::On, d.level.min(100)),
            Request::IrEnhancement(e) => s.ir_enhancement = e.level.min(10),
            Request::IrTempOverlay(o) => s.ir_temp_overlay = o.overlay == OnOff::On,
            Request::FormatSd(_) => return self.format(t),
            Request::FactoryReset(_) => {
                self.camera = initial_camera(
                    &self.config,
                    self.camera.laser_distance_dm,
                    self.camera.photos_taken,
                );
                self.stabilization = false;
            }
            _ => {}
        }
        Ok(None)
    }

    /// 0x00030D: refused while recording or shooting; else status frames and, after
    /// [`FORMAT_US`], an empty card.
    fn format(&mut self, t: u64) -> Result<Option<Vec<u8>>, AckCode> {
        if self.camera.recording.is_some() {
            return Err(AckCode::Recording);
        }
        if self.photo_job.is_some() || !self.single_shots.is_empty() {
            return Err(AckCode::PhotoInProgress);
        }
        let start = t.saturating_add(self.config.ack_delay_us);
        let done = start.saturating_add(FORMAT_US);
        let status = |state| FormatStatus {
            state,
            reserved: [0; 2],
        };
        self.deferred
            .push(message(&status(k40t::FormatState::InProgress)));
        let mut at = start.saturating_add(FORMAT_STATUS_PERIOD_US);
        while at < done {
            let (id, bytes) = message(&status(k40t::FormatState::InProgress));
            self.send_payload(at, id, bytes);
            at = at.saturating_add(FORMAT_STATUS_PERIOD_US);
        }
        let (id, bytes) = message(&status(k40t::FormatState::Done));
        self.send_payload(done, id, bytes);
        self.camera.settings.card_emptied_at_us = Some(done);
        Ok(None)
    }

    /// The SD card's (total, free, used) capacities at `t`, 10 MB units.
    pub(super) fn card_at(&self, t: u64) -> (u16, u16, u16) {
        let total = 12_207;
        if self
            .camera
            .settings
            .card_emptied_at_us
            .is_some_and(|at| t >= at)
        {
            (total, total, 0)
        } else {
            (total, 11_007, 1_200)
        }
    }

    /// The 0x000100 ACK: every infrared setting.
    pub(super) fn ir_params(&self) -> IrParams {
        let s = &self.camera.settings;
        IrParams {
            code: ResponseCode::OK,
            palette: self.camera.palette,
            // Bit 0 clear: measuring; bit 1 area; bit 2 radiometric core; bits 3..7 zoom.
            measure: MeasureConfig(
                (if self.camera.ir_measuring { 0x06 } else { 0x07 }) | (s.ir_zoom << 3),
            ),
            sharpness: s.ir_sharpness,
            gain: s.ir_gain,
            brightness: s.ir_brightness,
            contrast: s.ir_contrast,
            denoise: SwitchLevel(bit7(s.ir_denoise)),
            enhancement: s.ir_enhancement,
            high_warning_dc: -2732,
            low_warning_dc: -2732,
            diff_warning_dc: -2732,
            threshold_warning: OnOff::Off,
            threshold_ref_dc: 0,
            threshold_float_dc: 0,
            reserved: [0; 2],
        }
    }

    /// The 0x000200 ACK: every visible-camera setting.
    pub(super) fn visible_params(&self) -> VisibleParams {
        let s = &self.camera.settings;
        VisibleParams {
            code: ResponseCode::OK,
            photo_resolution: s.photo_resolution,
            video_resolution: s.video_resolution,
            video_bitrate: 1,
            white_balance: s.white_balance,
            reserved: [0; 2],
            ev: self.camera.ev,
            iso: s.iso,
            shutter: s.shutter,
            zoom_fine: 0,
            backlight: bit7(s.backlight),
            strong_light: bit7(s.strong_light),
            ae_lock: self.camera.ae_lock,
            osd_flicker: k40t::OsdFlicker((s.anti_flicker.value() << 4) | u8::from(s.watermark)),
            metering: s.metering,
        }
    }
}
