//! The GCU side: the bridge acts as an XF Robot GCU (gimbal control unit) towards
//! ArduPilot's `AP_Mount_XFRobot` and any host that follows the GCU private protocol.
//!
//! What the host needs, and what the bridge does (the mapping table:
//! docs/src/bridge/gcu.md):
//! - **Question and answer.** Every valid host package (`A8 E5`, any version byte, 72 to
//!   [`BUF`] bytes) gets exactly one `8A 5E` reply in the same call, built from the pod's
//!   cached state, with the host's version byte and, when the host asks for it (request
//!   code 0x01), the sub data frame. A CRC-bad, truncated or overlong package gets no
//!   reply and is counted by the deframer (the engine's `fc_rejected`).
//! - **Health.** While the pod reports its attitude the reply is 73 bytes (order +
//!   execution state), what ArduPilot needs. While it does not (pod lost, or not yet
//!   reporting), the package is still answered, with the 72-byte form (order byte, no
//!   execution state), zero angles and the hardware-error bit: ArduPilot's parser takes
//!   it but ignores packages shorter than 73 bytes, so the mount turns unhealthy within
//!   1 s, as SIYI's does when its attitude stops.
//! - **Edge trigger.** An order executes when it differs from the previous package's
//!   order (the null order 0x00 re-arms a repeated one); external track (0x1B) executes
//!   every time. The control quantities (status bit 2) act in every package, read per
//!   the current mode: angles in FPV / ArduPilot's angle control (0x10, 0x1C) and Euler
//!   angle control (0x14, yaw converted to the body frame with the carrier's yaw), rates
//!   (0.1 °/s divided by the zoom ratio) in head lock, head follow and orthoview (yaw
//!   only).
//! - **Feedback.** An order the bridge sent to the pod is answered `order, 0x00` at once
//!   when the pod's state lets it execute, else with the failure state (`0x01`, or the
//!   failed cameras for camera orders). The pod's ACK comes later: a refusal or a
//!   time-out is reported once, `order, failure`, in the next reply whose own order
//!   carries no news (null, a repeat, set attitude or a mode), which is where ArduPilot
//!   reads it ("failed to take picture"); a repeated order is answered with its latest
//!   state (`0x02` operating while a status order's ACK is pending).
//! - **Time and position.** The sub frame's GPS week and time of week (GPS time of the
//!   last fix, held between fixes) become a held UTC sample with the leap seconds of
//!   [`Config`](crate::Config); its position (longitude first) and relative
//!   altitude, with the main frame's carrier attitude, a fix.
//! - **The target** (reply bytes 43..58, GCU private protocol V2.0.2, 2.3): the laser's
//!   distance while it measures, and the target's position: the pod's (0x000320, asked
//!   five times a second with the aircraft's latest fix while the laser measures, used
//!   while at most 500 ms old), else computed from the distance along the camera's
//!   direction from the aircraft's fix (flat earth: docs/src/bridge/gcu.md); zeros
//!   without a distance.
//! - **Thermal status** (byte 63 in ArduPilot's revision of the reply): bit 7 while the
//!   pod measures temperatures (0x000004 comes), bits 0 and 1 its low and high
//!   temperature warnings.

use crate::discipline::Sample;
use crate::fixes::{Fix, Velocity};
use crate::gimbal::{Command, GimbalMode, Motion, Ranging, Target, View};
use crate::pod::PodNotice;
use crate::time::{Duration, Instant, UtcTime};
use protocol_core::gcu::{
    self, CameraSet, CameraStatus, ClickToAim, Execution, ExternalTrack, ExternalTrackAction,
    Feedback, Frame, GcuFrames, GcuFraming, GcuMain, GcuPacket, GcuSub, GimbalCode,
    GimbalMode as GcuMode, HostFrames, HostMain, HostPacket, Order, Palette, PaletteAction,
    PictureInPicture, PipView, RangingState, Record, SUB_HEADER, Shutter, Track, TrackAction,
    ZoomTo,
};
use protocol_core::k40t::{self, GimbalAttitude as PodAttitude, SdState};

use super::geo::{LookAt, Position, look_at};
use super::{Ctx, FcHandler, TimedFrom, clamp_i16, math};

/// Two bytes sent after every reply ([`GcuIdentity::resync_mark`](crate::GcuIdentity)):
/// a first header byte followed by one that is not the second. `AP_Mount_XFRobot`'s
/// parser keeps the bytes it skips while looking for a header in its buffer and checks
/// the CRC over all of it, so after one corrupted reply it can stay out of step with
/// the 50 Hz replies for good (each reset lands the same distance before the next
/// header); this pair resets it exactly at the end of every reply. A parser in step takes
/// the pair for a broken header and skips it.
const RESYNC_MARK: [u8; 2] = [0x8A, 0x00];

/// Deframer buffer, the longest package answered: the document's longest is 84 bytes
/// (gaze, 0x15), ArduPilot's are 72 and 73; 96 leaves room for 26 bytes of parameters.
/// Longer packages (no known order has them) are rejected and counted as length errors.
pub(crate) const BUF: usize = 96;

/// Resolution of the held GPS time: the host's package period (ArduPilot's mount update
/// runs at 50 Hz), the most by which the first package after a GPS fix was read late.
const GPS_HOLD_US: u32 = 20_000;
/// The largest hybrid zoom of the K40T (0.1x), the top of the host's 1..10000 range.
const MAX_ZOOM_X10: u16 = 1600;
/// The largest thermal digital zoom of the K40T.
const MAX_THERMAL_ZOOM: u8 = 8;
/// Half the horizontal field of view at 1x, 0.01° (external track's miss scale).
const HALF_HFOV_CDEG: i32 = 3000;
/// External-track misses at or beyond this mark lost tracking.
const MISS_INVALID: i16 = 3071;
/// The host's rate control range, 0.1 °/s.
const RATE_LIMIT: i16 = 1500;
/// The laser target is asked this often while the laser measures, and the pod's answer
/// (or a fix) used while this fresh.
const TARGET_ASK: Duration = Duration::from_millis(200);
const TARGET_FRESH: Duration = Duration::from_millis(500);

/// The orders this side reads by number.
mod order {
    pub(super) const NULL: u8 = 0x00;
    pub(super) const NEUTRAL: u8 = 0x03;
    /// FPV in the V2.0.2 document; "angle control" (roll and pitch earth frame, yaw body
    /// frame) in ArduPilot's driver, which sends it with every set-attitude package.
    pub(super) const ANGLE: u8 = 0x10;
    pub(super) const HEAD_LOCK: u8 = 0x11;
    pub(super) const HEAD_FOLLOW: u8 = 0x12;
    pub(super) const ORTHOVIEW: u8 = 0x13;
    pub(super) const EULER: u8 = 0x14;
    pub(super) const GAZE_LOCK: u8 = 0x16;
    pub(super) const TRACK: u8 = 0x17;
    pub(super) const CLICK_TO_AIM: u8 = 0x1A;
    pub(super) const EXTERNAL_TRACK: u8 = 0x1B;
    /// FPV in the later protocol revision ArduPilot's driver lists (not in V2.0.2).
    pub(super) const FPV: u8 = 0x1C;
    pub(super) const SHUTTER: u8 = 0x20;
    pub(super) const RECORD: u8 = 0x21;
    pub(super) const ZOOM_IN: u8 = 0x22;
    pub(super) const ZOOM_OUT: u8 = 0x23;
    pub(super) const ZOOM_STOP: u8 = 0x24;
    pub(super) const ZOOM_TO: u8 = 0x25;
    pub(super) const FOCUS: u8 = 0x26;
    pub(super) const PALETTE: u8 = 0x2A;
    pub(super) const PIP: u8 = 0x74;
    pub(super) const RANGING: u8 = 0x81;
}

/// A camera order sent to the pod, waiting for its ACK.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Awaiting {
    order: u8,
    base: u16,
    cameras: CameraSet,
}

/// The Gcu side (its link, deframer and bursts, is [`FcLink`](super::FcLink)).
#[derive(Debug, Clone)]
pub(crate) struct GcuSide {
    /// The previous package's order (the edge trigger).
    last_order: Option<u8>,
    /// The GCU mode byte (reply byte 5): the mode order last executed.
    mode: u8,
    /// The mode to return to when tracking ends.
    track_return: u8,
    /// Tracking started and not refused or ended.
    tracking: bool,
    /// The carrier's yaw (0.01°, ±18000) from the last main frame with valid INS data.
    carrier_yaw: Option<i16>,
    /// The last sub frame carried a position.
    positioned: bool,
    /// Centre or look down under way: a zero rate does not cancel it.
    function_pending: bool,
    /// The last executed order and its state (answered to its repeats).
    last_feedback: (u8, Execution),
    /// The camera order waiting for its pod ACK.
    awaiting: Option<Awaiting>,
    /// A failure to report in the next reply without news of its own.
    report: Option<(u8, Execution)>,
    /// The thermal palette last selected (K40T code; "next" cycles from it).
    palette: u8,
    /// The picture-in-picture view last selected (ArduPilot's 1..4; 0: none yet).
    pip: u8,
    /// The thermal digital zoom last selected.
    thermal_zoom: u8,
    /// When the laser target was last asked.
    target_asked: Option<Instant>,
}

impl GcuSide {
    pub(crate) fn new() -> Self {
        GcuSide {
            last_order: None,
            mode: order::HEAD_FOLLOW,
            track_return: order::HEAD_FOLLOW,
            tracking: false,
            carrier_yaw: None,
            positioned: false,
            function_pending: false,
            last_feedback: (order::NULL, Execution::Success),
            awaiting: None,
            report: None,
            palette: k40t::Palette::WhiteHot.value(),
            pip: 0,
            thermal_zoom: 1,
            target_asked: None,
        }
    }
}

impl FcHandler for GcuSide {
    type Framing = GcuFraming;
    const TIMED_FROM: TimedFrom = TimedFrom::Frame;

    fn frame(&mut self, ctx: &mut Ctx<'_>, f: &[u8]) {
        self.fc_frame(ctx, f);
    }

    /// Question and answer: nothing is sent unasked.
    fn poll(&mut self, ctx: &mut Ctx<'_>) {
        let _ = ctx;
    }

    fn poll_at(&self) -> Option<Instant> {
        None
    }

    fn pod_notice(&mut self, ctx: &mut Ctx<'_>, notice: PodNotice) {
        let _ = ctx;
        let (base, failed) = match notice {
            PodNotice::Acked { base, code } => (base, code != k40t::AckCode::Ok),
            PodNotice::TimedOut { base } => (base, true),
            _ => return,
        };
        let Some(a) = self.awaiting.filter(|a| a.base == base) else {
            return;
        };
        self.awaiting = None;
        let state = if failed {
            Execution::failure(Order::from_value(a.order), a.cameras)
        } else {
            Execution::Success
        };
        if self.last_feedback.0 == a.order {
            self.last_feedback.1 = state;
        }
        if failed {
            self.report = Some((a.order, state));
            if a.order == order::TRACK && self.tracking {
                self.tracking = false;
                self.mode = self.track_return;
            }
        }
    }
}

/// A screen coordinate of the host (0..=10000) in pixels of a `size`-pixel side.
fn pixels(v: u16, size: u16) -> u16 {
    let p = u32::from(v.min(10_000)).saturating_mul(u32::from(size)) / 10_000;
    u16::try_from(p).unwrap_or(size)
}

/// An angle in 0.01° wrapped to ±18000.
fn wrap_cdeg(v: i32) -> i32 {
    v.saturating_add(18_000)
        .rem_euclid(36_000)
        .saturating_sub(18_000)
}

/// The K40T view of a picture-in-picture choice (ArduPilot's 1..4).
fn view_of(pip: u8) -> Option<View> {
    match PipView::from_value(pip) {
        PipView::PipZoomMainThermalSub | PipView::PipThermalMainZoomSub => Some(View::Split),
        PipView::ThermalMainZoomSub => Some(View::Thermal),
        PipView::ZoomMainThermalSub => Some(View::Visible),
        _ => None,
    }
}

/// Reply byte 63 (ArduPilot's revision): bit 7 temperatures available (the pod measures),
/// bits 0 and 1 the low and high temperature warnings of 0x000004.
fn thermal_status(ctx: &Ctx<'_>) -> u8 {
    let Some((ir, _)) = ctx
        .pod()
        .ir
        .filter(|(_, at)| ctx.pod().link && ctx.is_fresh(*at))
    else {
        return 0;
    };
    0x80 | u8::from(ir.low_warning != 0) | (u8::from(ir.high_warning != 0) << 1)
}

/// The SD card lets the camera shoot or record (unknown: assumed so).
fn card_ok(ctx: &Ctx<'_>) -> bool {
    ctx.pod().system.is_none_or(|s| {
        !matches!(
            s.sd,
            SdState::Missing | SdState::Full | SdState::Abnormal | SdState::FormatError
        )
    })
}

impl GcuSide {
    /// One valid package from the host.
    fn fc_frame(&mut self, ctx: &mut Ctx<'_>, f: &[u8]) {
        let packet = Frame::new_checked(f)
            .ok()
            .and_then(|frame| HostPacket::parse(&frame).ok());
        ctx.seen();
        let Some(p) = packet else {
            ctx.ignored();
            return;
        };
        self.feed(ctx, &p.frames);
        let id = p.message.id();
        let new = self.last_order != Some(id) || id == order::EXTERNAL_TRACK;
        self.last_order = Some(id);
        let executed = new.then(|| self.execute(ctx, &p));
        if let Some(e) = executed {
            self.last_feedback = (id, e);
        }
        self.control(ctx, &p.frames.main);
        self.ask_target(ctx);
        self.reply(ctx, &p, executed);
    }

    /// Time and position from the data frames.
    fn feed(&mut self, ctx: &mut Ctx<'_>, frames: &HostFrames) {
        let main = &frames.main;
        if main.status.ins_valid() {
            self.carrier_yaw = Some(carrier_yaw(main));
        }
        let sub = &frames.sub;
        if !sub.is_present() {
            return;
        }
        // The FC read these values before it wrote the package's first byte.
        let transit = ctx.transit;
        let week = u16::from_ne_bytes(sub.gps_week.to_ne_bytes());
        let utc = UtcTime::from_gps(week, sub.gps_tow_ms, ctx.config.leap_seconds);
        if let Some(utc) = utc.filter(|_| ctx.feeds) {
            let s = Sample::new(ctx.now, utc.as_unix_micros(), GPS_HOLD_US)
                .held()
                .with_transit(transit);
            ctx.time.utc_sample(s);
        }
        self.positioned = sub.lat_e7 != 0 || sub.lon_e7 != 0;
        if self.positioned {
            let dm = |mm: i32| clamp_i16(mm / 100);
            ctx.push_fix(Fix {
                at: ctx.now.saturating_sub(transit),
                lat_e7: sub.lat_e7,
                lon_e7: sub.lon_e7,
                alt_msl_dm: dm(sub.alt_mm),
                rel_alt_dm: dm(sub.rel_height_mm),
                yaw_cdeg: carrier_yaw(main),
                roll_cdeg: clamp_i16(wrap_cdeg(i32::from(main.carrier_roll_cdeg))),
                pitch_cdeg: main.carrier_pitch_cdeg,
                velocity: Some(Velocity::from_cm_s(
                    i32::from(main.vel_north_dmps).saturating_mul(10),
                    i32::from(main.vel_east_dmps).saturating_mul(10),
                    i32::from(main.vel_up_dmps).saturating_mul(-10),
                )),
            });
        }
    }

    /// Asks the pod where its laser points while it measures (five times a second).
    fn ask_target(&mut self, ctx: &mut Ctx<'_>) {
        let ranging = ctx
            .pod()
            .laser_dm
            .is_some_and(|(d, at)| d > 0 && ctx.is_fresh(at));
        let due = self
            .target_asked
            .is_none_or(|t| ctx.now.saturating_duration_since(t) >= TARGET_ASK);
        let fix = ctx
            .fixes
            .latest()
            .filter(|f| ctx.now.saturating_duration_since(f.at) <= TARGET_ASK);
        if let Some(f) = fix.filter(|_| ranging && due && ctx.pod().link) {
            self.target_asked = Some(ctx.now);
            let utc_ms = ctx
                .time
                .utc(f.at)
                .map_or(0, UtcTime::as_unix_millis_rounded);
            ctx.pod.request_target(ctx.now, &f, utc_ms, ctx.out);
        }
    }

    /// The laser target's position at `distance_dm`: the pod's while fresh, else along the
    /// camera's direction from the aircraft's latest fix.
    fn target(
        &self,
        ctx: &Ctx<'_>,
        att: Option<&PodAttitude>,
        distance_dm: u16,
    ) -> Option<Position> {
        if let Some((t, at)) = ctx.pod().target
            && ctx.now.saturating_duration_since(at) <= TARGET_FRESH
        {
            return Some(Position {
                lat_e7: t.lat_e7,
                lon_e7: t.lon_e7,
                alt_mm: t.alt_mm,
            });
        }
        let a = att?;
        let f = ctx
            .fixes
            .latest()
            .filter(|f| ctx.now.saturating_duration_since(f.at) <= TARGET_FRESH)?;
        let here = Position {
            lat_e7: f.lat_e7,
            lon_e7: f.lon_e7,
            alt_mm: i32::from(f.alt_msl_dm).saturating_mul(100),
        };
        let yaw = i32::from(self.carrier_yaw?).saturating_add(i32::from(a.yaw_joint_cdeg));
        let range = f32::from(distance_dm) / 10.0;
        match look_at(
            here,
            math::rad(i32::from(a.pitch_cdeg)),
            math::rad(wrap_cdeg(yaw)),
            Some(range),
            0.0,
        ) {
            LookAt::At(p) => Some(p),
            LookAt::Sky | LookAt::Unknown => None,
        }
    }

    /// The reply to package `p`; `executed` is the state of its order when it executed.
    fn reply(&mut self, ctx: &mut Ctx<'_>, p: &HostPacket<'_>, executed: Option<Execution>) {
        let id = p.message.id();
        let att = ctx.fresh_attitude();
        let frames = self.frames(ctx, att.as_ref());
        let mut packet: GcuPacket<'static> = p.answer(frames, Execution::Success);
        packet.feedback = if att.is_none() {
            // No execution state: ArduPilot ignores the package (see the module docs).
            Feedback {
                order: Order::from_value(id),
                execution: None,
                extra: &[],
            }
        } else {
            let routine = executed.is_none() || is_routine(id);
            let (order, state) = match (self.report, routine) {
                (Some(r), true) => {
                    self.report = None;
                    r
                }
                _ => (id, executed.unwrap_or_else(|| self.repeat_state(id))),
            };
            Feedback::new(Order::from_value(order), state)
        };
        let mut buf = [0u8; gcu::MIN_FRAME_LEN + 1 + RESYNC_MARK.len()];
        if let Ok(n) = packet.emit(&mut buf) {
            let n = if ctx.config.gcu.resync_mark {
                buf.get_mut(n..)
                    .and_then(|tail| tail.get_mut(..RESYNC_MARK.len()))
                    .map_or(n, |tail| {
                        tail.copy_from_slice(&RESYNC_MARK);
                        n.saturating_add(RESYNC_MARK.len())
                    })
            } else {
                n
            };
            ctx.reply(buf.get(..n).unwrap_or_default());
        }
    }

    /// The state answered to a repeated order.
    fn repeat_state(&self, id: u8) -> Execution {
        let order = Order::from_value(id);
        if self.awaiting.is_some_and(|a| a.order == id)
            && order.feedback_kind() == gcu::FeedbackKind::Status
        {
            return Execution::Operating;
        }
        match self.last_feedback {
            (o, e) if o == id => e,
            _ => Execution::Success,
        }
    }

    /// The reply's data frames from the pod's state.
    fn frames(&self, ctx: &Ctx<'_>, att: Option<&PodAttitude>) -> GcuFrames {
        let pod = ctx.pod();
        let a = att.copied().unwrap_or_default();
        let distance = pod
            .laser_dm
            .filter(|(d, at)| *d > 0 && ctx.is_fresh(*at))
            .map(|(d, _)| d);
        let yaw_abs = match self.carrier_yaw {
            Some(c) => i32::from(c).saturating_add(i32::from(a.yaw_joint_cdeg)),
            None => i32::from(a.yaw_cdeg),
        };
        let main = GcuMain {
            mode: GcuMode::from_value(self.mode),
            camera_status: CameraStatus(0)
                .with_tracking(self.tracking)
                .with_range_valid(distance.is_some())
                .with_ranging(pod.ranging),
            miss_horizontal: 0,
            miss_vertical: 0,
            // Appendix 3: the X axis is the pitch axis, its angle the pitch negated.
            rel_x_cdeg: a.pitch_joint_cdeg.saturating_neg(),
            rel_y_cdeg: a.roll_joint_cdeg,
            // ArduPilot reads this as the body-frame yaw (positive right).
            rel_z_cdeg: a.yaw_joint_cdeg,
            roll_cdeg: a.roll_cdeg,
            pitch_cdeg: a.pitch_cdeg,
            yaw_cdeg: u16::try_from(yaw_abs.rem_euclid(36_000)).unwrap_or(0),
            rate_x_cdps: a.pitch_rate_cdeg_s.saturating_neg(),
            rate_y_cdps: a.roll_rate_cdeg_s,
            rate_z_cdps: a.yaw_rate_cdeg_s,
            reserved: [0; 7],
        };
        let id = &ctx.config.gcu;
        // ArduPilot's revision: bit 7 hardware error, bit 14 GNSS not positioned.
        let error_code = (if att.is_none() { 1u16 << 7 } else { 0 })
            | (if self.positioned { 0 } else { 1 << 14 });
        // ArduPilot's revision of bytes 63..68: thermal status, camera status (bits 0..2
        // picture in picture, bit 4 recording), time zone (hours east).
        let pip = match pod.view() {
            Some(v) if view_of(self.pip) == Some(v) => self.pip,
            Some(View::Thermal) => PipView::ThermalMainZoomSub.value(),
            Some(View::Split) => PipView::PipZoomMainThermalSub.value(),
            _ => PipView::ZoomMainThermalSub.value(),
        };
        let camera = u16::from(pip & 0x07) | if pod.is_recording() { 1 << 4 } else { 0 };
        let [c0, c1] = camera.to_le_bytes();
        let tz_hours = clamp_i16(ctx.config.tz_minuteswest.saturating_neg() / 60).clamp(-12, 12);
        let [tz, _] = tz_hours.to_le_bytes();
        let target = distance.and_then(|d| self.target(ctx, att, d));
        let sub = GcuSub {
            header: SUB_HEADER,
            hardware_version: id.hardware_x10,
            firmware_version: ctx.build.version.gcu_x10(),
            gimbal_code: GimbalCode::from_value(id.gimbal_code),
            error_code,
            distance_dm: distance.map_or(0, i32::from),
            target_lon_e7: target.map_or(0, |p| p.lon_e7),
            target_lat_e7: target.map_or(0, |p| p.lat_e7),
            target_alt_mm: target.map_or(0, |p| p.alt_mm),
            zoom1_x10: pod.zoom_x10(),
            zoom2_x10: u16::from(self.thermal_zoom).saturating_mul(10),
            reserved: [thermal_status(ctx), c0, c1, tz, 0, 0],
        };
        GcuFrames { main, sub }
    }

    /// Sends a command the pod acknowledges, for `cameras` of order `id`: success at once
    /// when it went out, the failure state when the pod cannot take it.
    fn act(&mut self, ctx: &mut Ctx<'_>, id: u8, cameras: CameraSet, cmd: Command) -> Execution {
        let sent = if ctx.pod().link {
            ctx.command(u16::from(id), cmd)
        } else {
            None
        };
        match sent {
            Some(base) => {
                self.awaiting = Some(Awaiting {
                    order: id,
                    base,
                    cameras,
                });
                Execution::Success
            }
            None => Execution::failure(Order::from_value(id), cameras),
        }
    }

    /// Executes the order of package `p` (a new order, or external track).
    #[allow(clippy::too_many_lines)] // one short arm per order
    fn execute(&mut self, ctx: &mut Ctx<'_>, p: &HostPacket<'_>) -> Execution {
        let id = p.message.id();
        let fail = |cameras: CameraSet| Execution::failure(Order::from_value(id), cameras);
        let m = &p.message;
        match id {
            order::NULL => Execution::Success,
            order::NEUTRAL => self.neutral(ctx),
            order::ANGLE | order::HEAD_FOLLOW => self.set_mode(ctx, id, GimbalMode::Follow),
            order::FPV => self.set_mode(ctx, id, GimbalMode::Fpv),
            order::HEAD_LOCK | order::EULER => self.set_mode(ctx, id, GimbalMode::Lock),
            order::ORTHOVIEW => {
                let e = self.set_mode(ctx, id, GimbalMode::Follow);
                ctx.command(u16::from(id), Command::LookDown);
                self.function_pending = true;
                e
            }
            order::TRACK => match m.get::<Track>() {
                Some(t) if t.action == TrackAction::Start => {
                    let target = Target::Box {
                        x0: pixels(t.x0, 1920),
                        y0: pixels(t.y0, 1080),
                        x1: pixels(t.x1, 1920),
                        y1: pixels(t.y1, 1080),
                    };
                    let e = self.act(ctx, id, t.cameras, Command::Track(Some(target)));
                    if e.is_success() {
                        if !self.tracking {
                            self.track_return = self.mode;
                        }
                        self.tracking = true;
                        self.mode = order::TRACK;
                    }
                    e
                }
                Some(t) if t.action == TrackAction::Exit => {
                    self.end_tracking();
                    self.act(ctx, id, t.cameras, Command::Track(None))
                }
                Some(t) => fail(t.cameras),
                None => fail(CameraSet::NONE),
            },
            order::CLICK_TO_AIM => match m.get::<ClickToAim>() {
                Some(c) => {
                    let target = Target::Point {
                        x: pixels(c.x, 1920),
                        y: pixels(c.y, 1080),
                    };
                    self.act(ctx, id, c.cameras, Command::Aim(target))
                }
                None => fail(CameraSet::NONE),
            },
            order::EXTERNAL_TRACK => external_track(ctx, m.get::<ExternalTrack>()),
            order::SHUTTER => {
                let cameras = m.get::<Shutter>().map_or(CameraSet::CAMERA_1, |s| s.0);
                if card_ok(ctx) {
                    self.act(ctx, id, cameras, Command::TakePhoto)
                } else {
                    fail(cameras)
                }
            }
            order::RECORD => {
                // ArduPilot: 0x01 start, 0x00 stop (the document's 0x01 "start / stop"
                // toggle could invert the state when host and pod disagree).
                let cameras = m.get::<Record>().map_or(CameraSet::NONE, |r| r.0);
                let start = !cameras.is_empty();
                if ctx.pod().link && ctx.pod().is_recording() == start {
                    Execution::Success
                } else if start && !card_ok(ctx) {
                    fail(cameras)
                } else {
                    self.act(ctx, id, cameras, Command::Record(start))
                }
            }
            order::ZOOM_IN | order::ZOOM_OUT | order::ZOOM_STOP => {
                let cameras = m.get::<gcu::ZoomIn>().map(|z| z.0).or_else(|| {
                    m.get::<gcu::ZoomOut>()
                        .map(|z| z.0)
                        .or_else(|| m.get::<gcu::ZoomStop>().map(|z| z.0))
                });
                let motion = match id {
                    order::ZOOM_IN => Motion::In,
                    order::ZOOM_OUT => Motion::Out,
                    _ => Motion::Stop,
                };
                self.zoom(ctx, id, cameras.unwrap_or(CameraSet::CAMERA_1), motion)
            }
            order::ZOOM_TO => match m.get::<ZoomTo>() {
                Some(z) => self.zoom_to(ctx, z),
                None => fail(CameraSet::NONE),
            },
            order::FOCUS => {
                let cameras = m.get::<gcu::Focus>().map_or(CameraSet::CAMERA_1, |f| f.0);
                if cameras.is_empty() || cameras.contains(1) {
                    // The thermal camera has no focus: it fails if named too.
                    let e = self.act(ctx, id, cameras, Command::AutoFocus(None));
                    others_failed(e, cameras)
                } else {
                    fail(cameras)
                }
            }
            order::PALETTE => match m.get::<Palette>() {
                Some(p) if p.action == PaletteAction::Next => {
                    // K40T palettes are numbered 1..=20.
                    let next = self.palette.checked_rem(20).unwrap_or(0).saturating_add(1);
                    let e = self.act(
                        ctx,
                        id,
                        p.cameras,
                        Command::Palette(k40t::Palette::from_value(next)),
                    );
                    if e.is_success() {
                        self.palette = next;
                    }
                    e
                }
                Some(p) => fail(p.cameras),
                None => fail(CameraSet::NONE),
            },
            order::PIP => {
                let wanted = m.get::<PictureInPicture>().map(|p| p.0);
                let view = match wanted {
                    Some(PipView::Next) => Some(match ctx.pod().view() {
                        Some(View::Visible) | None => View::Thermal,
                        Some(View::Thermal) => View::Split,
                        Some(View::Split) => View::Visible,
                    }),
                    Some(v) => view_of(v.value()),
                    None => None,
                };
                match view {
                    Some(v) => {
                        let e = self.act(ctx, id, CameraSet::NONE, Command::View(v));
                        if let Some(w) = wanted.filter(|_| e.is_success()) {
                            self.pip = w.value();
                        }
                        e
                    }
                    None => fail(CameraSet::NONE),
                }
            }
            order::RANGING => {
                let r = match m.get::<gcu::Ranging>().map(|r| r.0) {
                    Some(RangingState::On) => Some(Ranging::Continuous),
                    Some(RangingState::Off) => Some(Ranging::Off),
                    _ => None,
                };
                match r {
                    Some(r) => self.act(ctx, id, CameraSet::NONE, Command::Laser(r)),
                    None => fail(CameraSet::NONE),
                }
            }
            _ => {
                // Calibration, gaze, night vision, OSD, lighting, unknown orders: the
                // K40T has no equivalent.
                ctx.ignored();
                fail(CameraSet::NONE)
            }
        }
    }

    /// A mode order.
    fn set_mode(&mut self, ctx: &mut Ctx<'_>, id: u8, mode: GimbalMode) -> Execution {
        if self.tracking {
            self.tracking = false;
            ctx.command(u16::from(order::TRACK), Command::Track(None));
        }
        self.mode = id;
        ctx.command(u16::from(id), Command::Mode(mode));
        Execution::Success
    }

    fn end_tracking(&mut self) {
        if self.tracking {
            self.tracking = false;
            self.mode = self.track_return;
        }
    }

    /// Neutral: back to the pitch and yaw neutral position in head lock and follow,
    /// yaw only in orthoview; leaves tracking; no response in FPV, Euler and gaze.
    fn neutral(&mut self, ctx: &mut Ctx<'_>) -> Execution {
        let id = u16::from(order::NEUTRAL);
        match self.mode {
            order::ANGLE | order::FPV | order::EULER | order::GAZE_LOCK => {
                Execution::failure(Order::from_value(order::NEUTRAL), CameraSet::NONE)
            }
            order::ORTHOVIEW => {
                ctx.command(
                    id,
                    Command::Angles {
                        yaw_cdeg: 0,
                        pitch_cdeg: -9000,
                    },
                );
                Execution::Success
            }
            _ => {
                if self.tracking {
                    self.end_tracking();
                    ctx.command(id, Command::Track(None));
                }
                ctx.command(id, Command::Center);
                self.function_pending = true;
                Execution::Success
            }
        }
    }

    /// Continuous zoom: the visible camera's hybrid zoom. The thermal camera has no
    /// continuous zoom: it fails when named.
    fn zoom(&mut self, ctx: &mut Ctx<'_>, id: u8, cameras: CameraSet, m: Motion) -> Execution {
        if cameras.is_empty() || cameras.contains(1) {
            let e = self.act(ctx, id, cameras, Command::Zoom(m));
            others_failed(e, cameras)
        } else {
            Execution::failure(Order::from_value(id), cameras)
        }
    }

    /// Zoom to a ratio (≤ -10: the ratio in 0.1x) or a fraction of the range (1..=10000):
    /// camera 1 the hybrid zoom (1x..160x), camera 2 the thermal digital zoom (1..8x).
    fn zoom_to(&mut self, ctx: &mut Ctx<'_>, z: ZoomTo) -> Execution {
        let id = order::ZOOM_TO;
        let fraction = |f: u16, lo: u32, hi: u32| {
            // lo + (hi - lo)·(f - 1)/9999, f in 1..=10000.
            let span = hi.saturating_sub(lo);
            lo.saturating_add(span.saturating_mul(u32::from(f.saturating_sub(1))) / 9999)
        };
        let (visible, thermal) = match (z.ratio_x10(), z.fraction()) {
            (Some(r), _) => (u32::from(r), u32::from(r).saturating_add(5) / 10),
            (_, Some(f)) => (
                fraction(f, 10, u32::from(MAX_ZOOM_X10)),
                fraction(f, 1, u32::from(MAX_THERMAL_ZOOM)),
            ),
            _ => return Execution::failure(Order::from_value(id), z.cameras),
        };
        let all = z.cameras.is_empty();
        let mut e = Execution::Success;
        if all || z.cameras.contains(1) {
            let zoom_x10 = u16::try_from(visible).unwrap_or(MAX_ZOOM_X10);
            e = self.act(ctx, id, z.cameras, Command::ZoomTo { zoom_x10 });
        }
        if e.is_success() && z.cameras.contains(2) {
            let ratio = u8::try_from(thermal.clamp(1, u32::from(MAX_THERMAL_ZOOM))).unwrap_or(1);
            e = self.act(ctx, id, z.cameras, Command::ThermalZoom { ratio });
            if e.is_success() {
                self.thermal_zoom = ratio;
            }
        }
        e
    }

    /// The control quantities of a main frame, read per the current mode.
    fn control(&mut self, ctx: &mut Ctx<'_>, main: &HostMain) {
        if !main.status.control_valid() {
            return;
        }
        let (pitch, yaw) = (main.pitch_control, main.yaw_control);
        match self.mode {
            order::ANGLE | order::FPV => self.angles(ctx, i32::from(yaw), pitch),
            order::EULER => {
                let yaw = i32::from(yaw).saturating_sub(i32::from(self.carrier_yaw.unwrap_or(0)));
                self.angles(ctx, wrap_cdeg(yaw), pitch);
            }
            order::HEAD_LOCK | order::HEAD_FOLLOW | order::GAZE_LOCK => {
                self.rates(ctx, yaw, pitch);
            }
            order::ORTHOVIEW => self.rates(ctx, yaw, 0),
            _ => {}
        }
    }

    fn angles(&mut self, ctx: &mut Ctx<'_>, yaw_cdeg: i32, pitch_cdeg: i16) {
        self.function_pending = false;
        ctx.command(
            u16::from(self.mode),
            Command::Angles {
                yaw_cdeg,
                pitch_cdeg: i32::from(pitch_cdeg),
            },
        );
    }

    /// Rates in 0.1 °/s divided by the zoom ratio of the main screen.
    fn rates(&mut self, ctx: &mut Ctx<'_>, yaw: i16, pitch: i16) {
        if yaw == 0 && pitch == 0 && self.function_pending {
            return;
        }
        self.function_pending = false;
        let zoom = i32::from(ctx.pod().zoom_x10().max(10));
        // 0.1 °/s · 10 / (zoom_x10 / 10) = 0.01 °/s.
        let r = |v: i16| {
            i32::from(v.clamp(-RATE_LIMIT, RATE_LIMIT))
                .saturating_mul(100)
                .checked_div(zoom)
                .unwrap_or(0)
        };
        ctx.command(
            u16::from(self.mode),
            Command::Rates {
                yaw_cdeg_s: r(yaw),
                pitch_cdeg_s: r(pitch),
            },
        );
    }
}

/// External track: the miss measured by an external image processor becomes a
/// turn rate that brings the target to the centre in about a second.
fn external_track(ctx: &mut Ctx<'_>, t: Option<ExternalTrack>) -> Execution {
    let id = order::EXTERNAL_TRACK;
    let Some(t) = t else {
        return Execution::failure(Order::from_value(id), CameraSet::NONE);
    };
    let valid = t.miss_x.unsigned_abs() < MISS_INVALID.unsigned_abs()
        && t.miss_y.unsigned_abs() < MISS_INVALID.unsigned_abs();
    let on = t.action == ExternalTrackAction::Start && valid;
    let zoom = i32::from(ctx.pod().zoom_x10().max(10));
    // miss/1024 of half the field of view, at 1x; 0.01 °/s = 0.01° per second.
    let rate = |miss: i16| {
        i32::from(miss.clamp(-1024, 1024))
            .saturating_mul(HALF_HFOV_CDEG.saturating_mul(10))
            .checked_div(zoom.saturating_mul(1024))
            .unwrap_or(0)
    };
    let (yaw, pitch) = if on {
        (rate(t.miss_x), rate(t.miss_y).saturating_neg())
    } else {
        (0, 0)
    };
    ctx.command(
        u16::from(id),
        Command::Rates {
            yaw_cdeg_s: yaw,
            pitch_cdeg_s: pitch,
        },
    );
    if t.action == ExternalTrackAction::Start && !valid {
        Execution::failure(Order::from_value(id), t.cameras)
    } else {
        Execution::Success
    }
}

/// Orders whose feedback carries no news: a pending failure report may replace it.
fn is_routine(id: u8) -> bool {
    matches!(
        id,
        order::NULL
            | order::ANGLE
            | order::HEAD_LOCK
            | order::HEAD_FOLLOW
            | order::ORTHOVIEW
            | order::EULER
            | order::FPV
    )
}

/// When camera 1 executed, the other cameras named (the thermal camera, 2) failed.
fn others_failed(e: Execution, cameras: CameraSet) -> Execution {
    let others = CameraSet(cameras.0 & CameraSet::CAMERA_2.0);
    if e.is_success() && !others.is_empty() {
        Execution::FailedCameras(others)
    } else {
        e
    }
}

/// The carrier's yaw of a main frame in ±18000 (the document sends 0..36000, ArduPilot
/// a signed ±18000 in the same bytes).
fn carrier_yaw(main: &HostMain) -> i16 {
    clamp_i16(wrap_cdeg(i32::from(main.carrier_yaw_0_36000_cdeg())))
}
