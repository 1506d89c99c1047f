//! The camera (component 100): Camera Protocol v2 as ArduPilot (`CAM1_TYPE` 6) and
//! QGroundControl use it.
//!
//! - **CAMERA_INFORMATION** on request: photo, video, modes (the K40T has a photo and a
//!   video mode, 0x000300, and its document says it ignores photos in video mode and
//!   recording in photo mode), basic zoom and focus, the camera definition, the sensors'
//!   flags; the bridge's version as the firmware version ([`crate::version`]; the pod's
//!   own, 0x000317, is asked before it is answered); the focal length configured
//!   (`lens.focal_length_min_um`), else the one the pod reports in its visible-light
//!   status (0x000005, 0.01 mm: the focal length at the zoom of the moment), else NaN.
//!   A VIDEO_STREAM_INFORMATION follows it while the stream's address is known (MAVSDK
//!   reads the camera's information and never asks for the stream's).
//! - **Commands** and what reaches the pod: IMAGE_START_CAPTURE single (0x000302; a
//!   repeated capture sequence number, param4, is a retransmission: ACKed, not shot
//!   again) or every `param2` seconds (at least 1 s) `param3` times (0: until
//!   IMAGE_STOP_CAPTURE), each shot a single 0x000302 sent by the bridge; VIDEO_START /
//!   STOP_CAPTURE (0x000303); SET_CAMERA_MODE (0x000300); SET_CAMERA_ZOOM continuous
//!   (0x000306), range (0–100 % of the hybrid zoom's 1x..160x, 0x000304) and step (twice
//!   or half the pod's zoom); SET_CAMERA_FOCUS continuous, step (200 ms of continuous
//!   focus) and auto (0x000313); range and distance focus are not the pod's:
//!   UNSUPPORTED. Before a photo in video mode (not recording) or a recording in photo
//!   mode, the bridge switches the pod's mode (ArduPilot never sends SET_CAMERA_MODE).
//! - **Their COMMAND_ACK** waits for the pod's ACK (ACCEPTED, or FAILED on a refusal or
//!   time-out); a command while the pod does not report is TEMPORARILY_REJECTED; an
//!   interval start or stop is the bridge's own and ACCEPTED at once.
//! - **CAMERA_IMAGE_CAPTURED** once per photo the pod takes, broadcast: the photo's UTC
//!   and the position the pod was given for its geotag (the engine's answer to its
//!   0x000310, from the same fix history, at the instant the pod named), the pod's
//!   attitude, the image index; which GPS requests are photos', and what a photo without
//!   a geotag reports: [`capture`](super::capture).
//! - **CAMERA_CAPTURE_STATUS** on request and, unasked, whenever the image or video
//!   status changes (QGroundControl keeps the shutter busy until it reads idle).
//! - **CAMERA_SETTINGS** (mode from the pod's status, zoom level in %, focus level
//!   unknown: NaN) and **STORAGE_INFORMATION** (the pod's SD card, 0x000003) on request.

use crate::fc::Ctx;
use crate::gimbal::{Command, Motion};
use crate::time::{Duration, Instant};
use protocol_core::k40t::{CaptureMode, SdState};
use protocol_core::mavlink::MavMessage;
use protocol_core::mavlink::dialect::{
    CAMERA_CAPTURE_STATUS_DATA, CAMERA_INFORMATION_DATA, CAMERA_SETTINGS_DATA, CameraCapFlags,
    CameraMode, CharArray, STORAGE_INFORMATION_DATA, StorageStatus, StorageType, StorageUsageFlag,
};

use super::capture::Captures;
use super::gimbal::{MODEL, VENDOR, boot_ms, name};
use super::{Cmd, Comp, MavlinkSide, cmd, id, result};

/// Commands waiting for the pod's ACK.
const ACKS: usize = 4;
/// A pod ACK not come after this: the command failed.
const ACK_WAIT: Duration = Duration::from_millis(1500);
/// Shortest photo interval.
const MIN_INTERVAL: Duration = Duration::from_secs(1);
/// One focus step: continuous focus for this long.
const FOCUS_STEP: Duration = Duration::from_millis(200);
/// The hybrid zoom's range, ×10 (K40T 0x000304).
const ZOOM_MIN_X10: u16 = 10;
const ZOOM_MAX_X10: u16 = 1600;

/// K40T base ids the camera waits on.
const PHOTO: u16 = 0x0302;
const RECORD: u16 = 0x0303;

/// A command whose COMMAND_ACK waits for the pod.
#[derive(Debug, Clone, Copy)]
struct Waiting {
    base: u16,
    command: u16,
    from: protocol_core::mavlink::Header,
    at: Instant,
}

/// An interval capture under way.
#[derive(Debug, Clone, Copy)]
struct Interval {
    period: Duration,
    /// Photos still to take (`None`: until stopped).
    left: Option<u32>,
    next: Instant,
}

/// The camera's own state.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Camera {
    /// The mode SET_CAMERA_MODE asked last (video: true).
    video_mode: Option<bool>,
    /// The capture sequence number (param4) of the last single capture.
    last_seq: Option<u32>,
    interval: Option<Interval>,
    /// The photos the pod takes.
    pub(super) captures: Captures,
    /// The recording the bridge started, since when (the pod ACKed it).
    recording_since: Option<Instant>,
    /// The last record command: start (true) or stop.
    record_asked: Option<bool>,
    focus_stop: Option<Instant>,
    waiting: [Option<Waiting>; ACKS],
    /// Image and video status last sent.
    reported: Option<(u8, u8)>,
}

/// A camera command this component acts on.
pub(super) fn is_camera_command(c: u16) -> bool {
    matches!(
        c,
        cmd::IMAGE_START_CAPTURE
            | cmd::IMAGE_STOP_CAPTURE
            | cmd::VIDEO_START_CAPTURE
            | cmd::VIDEO_STOP_CAPTURE
            | cmd::SET_CAMERA_MODE
            | cmd::SET_CAMERA_ZOOM
            | cmd::SET_CAMERA_FOCUS
    )
}

/// A count or index from a command parameter (whole, non-negative).
#[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // checked range
fn whole(p: f32) -> Option<u32> {
    (0.0..4.0e9).contains(&p).then_some(p as u32)
}

/// The zoom level in % of the hybrid range for a ratio ×10.
#[allow(clippy::cast_precision_loss)] // small integers
fn zoom_pct(zoom_x10: u16) -> f32 {
    let z = zoom_x10
        .clamp(ZOOM_MIN_X10, ZOOM_MAX_X10)
        .saturating_sub(ZOOM_MIN_X10);
    f32::from(z) * 100.0 / f32::from(ZOOM_MAX_X10.saturating_sub(ZOOM_MIN_X10))
}

/// The ratio ×10 for a zoom level in %.
#[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // clamped first
fn zoom_of_pct(pct: f32) -> u16 {
    let span = f32::from(ZOOM_MAX_X10.saturating_sub(ZOOM_MIN_X10));
    let z = (pct.clamp(0.0, 100.0) * span / 100.0 + 0.5) as u16;
    ZOOM_MIN_X10.saturating_add(z).min(ZOOM_MAX_X10)
}

impl MavlinkSide {
    /// A camera command (see the module documentation).
    pub(super) fn camera_command(&mut self, ctx: &mut Ctx<'_>, c: &Cmd) {
        if !ctx.pod().link {
            self.ack(
                ctx,
                Comp::Camera,
                c.command,
                result::TEMPORARILY_REJECTED,
                c.from,
            );
            return;
        }
        let v = c.param(2);
        match c.command {
            cmd::IMAGE_START_CAPTURE => self.image_start(ctx, c),
            cmd::IMAGE_STOP_CAPTURE => {
                self.camera.interval = None;
                self.ack(ctx, Comp::Camera, c.command, result::ACCEPTED, c.from);
                self.capture_status_changed(ctx);
            }
            cmd::VIDEO_START_CAPTURE | cmd::VIDEO_STOP_CAPTURE => {
                let start = c.command == cmd::VIDEO_START_CAPTURE;
                if start && self.pod_mode(ctx) == Some(false) {
                    ctx.command(c.command, Command::VideoMode(true));
                }
                self.camera.record_asked = Some(start);
                let base = ctx.command(c.command, Command::Record(start));
                self.await_pod(ctx, c, base);
            }
            cmd::SET_CAMERA_MODE => {
                // CAMERA_MODE_IMAGE 0, VIDEO 1, IMAGE_SURVEY 2 (a photo mode).
                let video = whole(v) == Some(1);
                self.camera.video_mode = Some(video);
                let base = ctx.command(c.command, Command::VideoMode(video));
                self.await_pod(ctx, c, base);
            }
            cmd::SET_CAMERA_ZOOM => {
                let zoom = ctx.pod().zoom_x10();
                let command = match whole(c.param(1)) {
                    // ZOOM_TYPE_STEP: twice or half the ratio.
                    Some(0) if v > 0.0 => Some(Command::ZoomTo {
                        zoom_x10: zoom.saturating_mul(2).min(ZOOM_MAX_X10),
                    }),
                    Some(0) if v < 0.0 => Some(Command::ZoomTo {
                        zoom_x10: (zoom / 2).max(ZOOM_MIN_X10),
                    }),
                    Some(1) => Some(Command::Zoom(motion(v))),
                    Some(2) if v.is_finite() => Some(Command::ZoomTo {
                        zoom_x10: zoom_of_pct(v),
                    }),
                    _ => None,
                };
                self.camera_action(ctx, c, command);
            }
            cmd::SET_CAMERA_FOCUS => {
                let command = match whole(c.param(1)) {
                    // FOCUS_TYPE_STEP: a moment of continuous focus.
                    Some(0) if v.is_finite() && v.abs() > 0.0 => {
                        self.camera.focus_stop = Some(ctx.now.saturating_add(FOCUS_STEP));
                        Some(Command::Focus(motion(v)))
                    }
                    Some(1) => Some(Command::Focus(motion(v))),
                    // FOCUS_TYPE_AUTO, AUTO_SINGLE, AUTO_CONTINUOUS.
                    Some(4..=6) => Some(Command::AutoFocus(None)),
                    _ => None,
                };
                self.camera_action(ctx, c, command);
            }
            _ => self.ack(ctx, Comp::Camera, c.command, result::UNSUPPORTED, c.from),
        }
    }

    /// A command with a pod equivalent (or UNSUPPORTED without one).
    fn camera_action(&mut self, ctx: &mut Ctx<'_>, c: &Cmd, command: Option<Command>) {
        match command {
            Some(command) => {
                let base = ctx.command(c.command, command);
                self.await_pod(ctx, c, base);
            }
            None => self.ack(ctx, Comp::Camera, c.command, result::UNSUPPORTED, c.from),
        }
    }

    /// The pod's mode from its status (video: true), else the mode last asked.
    fn pod_mode(&self, ctx: &Ctx<'_>) -> Option<bool> {
        ctx.pod()
            .system
            .map(|s| s.mode == CaptureMode::Video)
            .or(self.camera.video_mode)
    }

    /// The command's ACK waits for the pod's ACK of `base` (no pod request: UNSUPPORTED).
    pub(super) fn await_pod(&mut self, ctx: &mut Ctx<'_>, c: &Cmd, base: Option<u16>) {
        let Some(base) = base else {
            self.ack(ctx, Comp::Camera, c.command, result::UNSUPPORTED, c.from);
            return;
        };
        let w = Waiting {
            base,
            command: c.command,
            from: c.from,
            at: ctx.now,
        };
        match self.camera.waiting.iter_mut().find(|s| s.is_none()) {
            Some(slot) => *slot = Some(w),
            // Too many at once: this one is not followed.
            None => self.ack(ctx, Comp::Camera, c.command, result::ACCEPTED, c.from),
        }
    }

    fn image_start(&mut self, ctx: &mut Ctx<'_>, c: &Cmd) {
        let interval_s = c.param(2);
        let count = whole(c.param(3)).unwrap_or(1);
        let repeat = (interval_s.is_finite() && interval_s > 0.0) || count > 1;
        if !repeat {
            let seq = whole(c.param(4)).filter(|s| *s > 0);
            if seq.is_some() && seq == self.camera.last_seq {
                // The same capture again (a retransmission): one photo per capture.
                self.ack(ctx, Comp::Camera, c.command, result::ACCEPTED, c.from);
                return;
            }
            self.camera.last_seq = seq;
            let base = self.shoot(ctx, c.command);
            self.await_pod(ctx, c, base);
            return;
        }
        let period = period_of(interval_s).max(MIN_INTERVAL);
        self.camera.interval = Some(Interval {
            period,
            left: (count > 0).then_some(count),
            next: ctx.now,
        });
        self.ack(ctx, Comp::Camera, c.command, result::ACCEPTED, c.from);
        self.camera_poll(ctx);
    }

    /// Sends one photo to the pod (switching it to photo mode first when it is in video
    /// mode and not recording); returns the K40T base id.
    fn shoot(&mut self, ctx: &mut Ctx<'_>, fc_id: u16) -> Option<u16> {
        if self.pod_mode(ctx) == Some(true) && !ctx.pod().is_recording() {
            ctx.command(fc_id, Command::VideoMode(false));
        }
        let base = ctx.command(fc_id, Command::TakePhoto)?;
        self.capture_commanded(ctx);
        self.capture_status_changed(ctx);
        Some(base)
    }

    /// The pod answered (or never did) a request of base `base`.
    pub(super) fn camera_pod_answer(&mut self, ctx: &mut Ctx<'_>, base: u16, ok: bool) {
        for i in 0..ACKS {
            let Some(w) = self
                .camera
                .waiting
                .get(i)
                .copied()
                .flatten()
                .filter(|w| w.base == base)
            else {
                continue;
            };
            if let Some(slot) = self.camera.waiting.get_mut(i) {
                *slot = None;
            }
            let r = if ok { result::ACCEPTED } else { result::FAILED };
            self.ack(ctx, Comp::Camera, w.command, r, w.from);
        }
        match base {
            PHOTO => {
                self.capture_acked(ctx, ok);
                self.capture_status_changed(ctx);
            }
            RECORD if ok => {
                self.camera.recording_since = match self.camera.record_asked {
                    Some(true) => self.camera.recording_since.or(Some(ctx.now)),
                    _ => None,
                };
                self.capture_status_changed(ctx);
            }
            _ => {}
        }
    }

    /// Periodic camera work: focus steps, interval photos, photos to report, ACKs that
    /// never came, status changes.
    pub(super) fn camera_poll(&mut self, ctx: &mut Ctx<'_>) {
        let now = ctx.now;
        if self.camera.focus_stop.is_some_and(|t| now >= t) {
            self.camera.focus_stop = None;
            ctx.command(cmd::SET_CAMERA_FOCUS, Command::Focus(Motion::Stop));
        }
        if let Some(mut iv) = self.camera.interval.filter(|i| now >= i.next) {
            iv.next = now.saturating_add(iv.period);
            iv.left = iv.left.map(|n| n.saturating_sub(1));
            self.camera.interval = iv.left.is_none_or(|n| n > 0).then_some(iv);
            if ctx.pod().link {
                self.shoot(ctx, cmd::IMAGE_START_CAPTURE);
            }
            self.capture_status_changed(ctx);
        }
        self.capture_poll(ctx);
        for i in 0..ACKS {
            let stale = self
                .camera
                .waiting
                .get(i)
                .copied()
                .flatten()
                .filter(|w| now.saturating_duration_since(w.at) >= ACK_WAIT);
            if let Some(w) = stale {
                if let Some(slot) = self.camera.waiting.get_mut(i) {
                    *slot = None;
                }
                self.ack(ctx, Comp::Camera, w.command, result::FAILED, w.from);
            }
        }
        self.capture_status_changed(ctx);
    }

    /// The image and video status (CAMERA_CAPTURE_STATUS).
    fn capture_state(&self, ctx: &Ctx<'_>) -> (u8, u8) {
        let busy = self.camera.captures.busy();
        let image = match (self.camera.interval.is_some(), busy) {
            (false, false) => 0,
            (false, true) => 1,
            (true, false) => 2,
            (true, true) => 3,
        };
        (image, u8::from(ctx.pod().is_recording()))
    }

    /// Sends CAMERA_CAPTURE_STATUS when the image or video status changed.
    fn capture_status_changed(&mut self, ctx: &mut Ctx<'_>) {
        let state = self.capture_state(ctx);
        if self.camera.reported != Some(state) && self.ap.sysid.is_some() {
            self.capture_status(ctx);
        }
    }

    #[allow(clippy::cast_precision_loss)] // capacities in MiB
    fn capture_status(&mut self, ctx: &mut Ctx<'_>) {
        let (image_status, video_status) = self.capture_state(ctx);
        self.camera.reported = Some((image_status, video_status));
        let recording_ms = self
            .camera
            .recording_since
            .filter(|_| video_status == 1)
            .map_or(0, |t| {
                u32::try_from(ctx.now.saturating_duration_since(t).as_millis()).unwrap_or(u32::MAX)
            });
        let msg = MavMessage::CAMERA_CAPTURE_STATUS(CAMERA_CAPTURE_STATUS_DATA {
            time_boot_ms: boot_ms(ctx),
            image_interval: self
                .camera
                .interval
                .map_or(0.0, |i| i.period.as_millis() as f32 / 1000.0),
            recording_time_ms: recording_ms,
            available_capacity: ctx
                .pod()
                .system
                .map_or(f32::NAN, |s| f32::from(s.sd_free_10mb) * 10.0),
            image_status,
            video_status,
            image_count: self.camera.captures.image_count,
            camera_device_id: 0,
        });
        self.send(ctx, Comp::Camera, &msg);
    }

    /// A request of a camera message (REQUEST_MESSAGE or a deprecated REQUEST_CAMERA_*):
    /// false when addressed to the gimbal (which does not serve it).
    pub(super) fn camera_request(
        &mut self,
        ctx: &mut Ctx<'_>,
        c: &Cmd,
        to: Option<Comp>,
        msg: u32,
    ) -> bool {
        if to == Some(Comp::Gimbal) {
            return false;
        }
        let arg = c.message_param();
        let r = match msg {
            id::CAMERA_INFORMATION => {
                // With the stream's address too, when the pod tells it at once.
                let known = ctx.pod().camera_version.is_some() && Self::stream_uri(ctx).is_some();
                if self.pod_identified(ctx, known) {
                    result::ACCEPTED
                } else {
                    result::TEMPORARILY_REJECTED
                }
            }
            // Storage 0 (all) or 1 (the SD card).
            id::STORAGE_INFORMATION if !matches!(whole(arg).unwrap_or(0), 0 | 1) => result::DENIED,
            id::CAMERA_IMAGE_CAPTURED => {
                let held = self.camera.captures.last.map(|l| l.index);
                if whole(arg).and_then(|i| i32::try_from(i).ok()) == held && held.is_some() {
                    result::ACCEPTED
                } else {
                    result::DENIED
                }
            }
            _ => result::ACCEPTED,
        };
        self.ack(ctx, Comp::Camera, c.command, r, c.from);
        if r != result::ACCEPTED {
            return true;
        }
        match msg {
            id::CAMERA_INFORMATION => self.camera_information(ctx),
            id::CAMERA_SETTINGS => self.camera_settings(ctx),
            id::STORAGE_INFORMATION => self.storage_information(ctx),
            id::CAMERA_CAPTURE_STATUS => self.capture_status(ctx),
            id::CAMERA_IMAGE_CAPTURED => {
                if let Some(last) = self.camera.captures.last {
                    self.send_captured(ctx, &last);
                }
            }
            _ => {}
        }
        true
    }

    fn camera_information(&mut self, ctx: &mut Ctx<'_>) {
        let flags = CameraCapFlags::CAMERA_CAP_FLAGS_CAPTURE_VIDEO
            | CameraCapFlags::CAMERA_CAP_FLAGS_CAPTURE_IMAGE
            | CameraCapFlags::CAMERA_CAP_FLAGS_HAS_MODES
            | CameraCapFlags::CAMERA_CAP_FLAGS_HAS_BASIC_ZOOM
            | CameraCapFlags::CAMERA_CAP_FLAGS_HAS_BASIC_FOCUS
            | Self::sensor_flags(ctx);
        let lens = ctx.config.lens;
        // The lens facts (mm, pixels): NaN and 0 when unknown.
        #[allow(clippy::cast_precision_loss)] // µm below 2^24
        let mm = |um: u32| {
            if um == 0 {
                f32::NAN
            } else {
                um as f32 / 1000.0
            }
        };
        let px = |v: u32| u16::try_from(v).unwrap_or(0);
        // The configured focal length, else the one the pod reports (0x000005, 0.01 mm).
        let reported = ctx
            .pod()
            .visible
            .map_or(0, |v| u32::from(v.focal_length_10um).saturating_mul(10));
        let focal_length_um = match lens.focal_length_min_um {
            0 => reported,
            configured => configured,
        };
        let msg = MavMessage::CAMERA_INFORMATION(CAMERA_INFORMATION_DATA {
            time_boot_ms: boot_ms(ctx),
            // The bridge's version (the pod's own is in its 0x000001 reply, not here).
            firmware_version: ctx.build.version.mavlink(),
            focal_length: mm(focal_length_um),
            sensor_size_h: mm(lens.sensor_width_um),
            sensor_size_v: mm(lens.sensor_height_um),
            flags,
            resolution_h: px(lens.resolution_h),
            resolution_v: px(lens.resolution_v),
            cam_definition_version: super::ftp::DEFINITION_VERSION,
            vendor_name: name::<32>(VENDOR),
            model_name: name::<32>(MODEL),
            lens_id: 0,
            cam_definition_uri: CharArray::from(name::<140>(super::ftp::DEFINITION_URI)),
            gimbal_device_id: Comp::Gimbal.id(),
            camera_device_id: 0,
        });
        self.send(ctx, Comp::Camera, &msg);
        // The stream's address follows, asked or not: MAVSDK (4.1) reads the camera's
        // information and never asks for its stream's.
        self.video_information(ctx);
    }

    fn camera_settings(&mut self, ctx: &mut Ctx<'_>) {
        let mode_id = if self.pod_mode(ctx) == Some(true) {
            CameraMode::CAMERA_MODE_VIDEO
        } else {
            CameraMode::CAMERA_MODE_IMAGE
        };
        let msg = MavMessage::CAMERA_SETTINGS(CAMERA_SETTINGS_DATA {
            time_boot_ms: boot_ms(ctx),
            mode_id,
            zoomLevel: zoom_pct(ctx.pod().zoom_x10()),
            focusLevel: f32::NAN,
            camera_device_id: 0,
        });
        self.send(ctx, Comp::Camera, &msg);
    }

    /// STORAGE_INFORMATION from the pod's SD card (capacities in units of 10 MB).
    pub(super) fn storage_information(&mut self, ctx: &mut Ctx<'_>) {
        let system = ctx.pod().system;
        let status = match system.map(|s| s.sd) {
            None => StorageStatus::STORAGE_STATUS_NOT_SUPPORTED,
            Some(SdState::Missing) => StorageStatus::STORAGE_STATUS_EMPTY,
            Some(SdState::Abnormal | SdState::FormatError) => {
                StorageStatus::STORAGE_STATUS_UNFORMATTED
            }
            Some(_) => StorageStatus::STORAGE_STATUS_READY,
        };
        let mib = |v: Option<u16>| v.map_or(0.0, |v| f32::from(v) * 10.0);
        let msg = MavMessage::STORAGE_INFORMATION(STORAGE_INFORMATION_DATA {
            time_boot_ms: boot_ms(ctx),
            total_capacity: mib(system.map(|s| s.sd_total_10mb)),
            used_capacity: mib(system.map(|s| s.sd_used_10mb)),
            available_capacity: mib(system.map(|s| s.sd_free_10mb)),
            read_speed: f32::NAN,
            write_speed: f32::NAN,
            storage_id: 1,
            storage_count: 1,
            status,
            mavtype: StorageType::STORAGE_TYPE_SD,
            name: CharArray::from([0u8; 32]),
            storage_usage: StorageUsageFlag::STORAGE_USAGE_FLAG_SET
                | StorageUsageFlag::STORAGE_USAGE_FLAG_PHOTO
                | StorageUsageFlag::STORAGE_USAGE_FLAG_VIDEO,
        });
        self.send(ctx, Comp::Camera, &msg);
    }
}

impl Camera {
    /// When the camera has work.
    pub(super) fn poll_at(&self) -> Option<Instant> {
        let acks = self
            .waiting
            .iter()
            .flatten()
            .map(|w| w.at.saturating_add(ACK_WAIT));
        acks.chain(self.captures.poll_at())
            .chain(self.focus_stop)
            .chain(self.interval.map(|i| i.next))
            .min()
    }
}

/// Continuous zoom or focus from a normalised rate: positive in (zoom in, focus far),
/// negative out, 0 (or NaN) stop.
fn motion(v: f32) -> Motion {
    if v > 0.0 {
        Motion::In
    } else if v < 0.0 {
        Motion::Out
    } else {
        Motion::Stop
    }
}

/// A period in seconds.
#[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // clamped first
fn period_of(s: f32) -> Duration {
    let ms = if s.is_finite() {
        (s.clamp(0.0, 86_400.0) * 1000.0) as u64
    } else {
        0
    };
    Duration::from_millis(ms)
}
