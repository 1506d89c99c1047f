//! The Viewlink side: the bridge acts as a Viewpro gimbal towards ArduPilot's
//! `AP_Mount_Viewpro` (and towards any console that speaks the Viewlink protocol).
//!
//! What ArduPilot needs, and what the bridge does (the mapping table:
//! docs/src/bridge/viewlink.md):
//! - **Status.** The 0x00 handshake, the 0x10 heartbeat and the control frames are
//!   answered with a 0x40 (T1 + F1 + B1 + D1, 41 data bytes), at most one per
//!   [`STATUS_GAP`] (ArduPilot's 10 Hz cycle gets one; a flood of frames does not
//!   flood the FC), built at once from the pod's cached state: attitude in B1 (roll 12 bits, yaw, pitch negated as
//!   ArduPilot reads it), tracker state in F1, sensor, IR zoom, recording, laser
//!   distance (0.1 m) and zoom ratio (0.1x) in D1, the aircraft's last position in T1.
//!   ArduPilot is healthy while a 0x40 arrived within 1 s: while the pod does not
//!   report its attitude the bridge sends none, as a Viewpro whose gimbal died.
//! - **Identity.** U queries 0xE4 (model) and 0xD0 (firmware) are answered with a V of
//!   the same code: the model from [`Config`](crate::Config), the firmware text from
//!   the bridge's version ([`Version::viewlink_text`](crate::version::Version::viewlink_text)).
//! - **Motion.** A1 speed (0x01) and absolute angles (0x0B, 0x1B) go to the pod driver
//!   every time they arrive (its edge trigger, dead-bands, rate limits and FC-silence
//!   stop apply); follow yaw (0x03) and follow yaw disabled (0x0A) set the yaw mode;
//!   home (0x04), look down (0x12), relative angles (0x09) and click-to-track (0x0E)
//!   are actions. ArduPilot sends pitch negated (positive down), angles in
//!   360/65536° and rates in 0.01°/s.
//! - **Camera** (C1, C2): zoom in/out/stop, absolute zoom, focus +/−/stop, AF/MF,
//!   photo, record start/stop, IR digital zoom, palettes, sensor selection, laser
//!   rangefinder single/continuous/stop. **Tracking** (E1, E2): start/stop, a point or a
//!   box ([`Command::Track`]); a point without a tracking start turns the gimbal to it
//!   ([`Command::Aim`]).
//! - **Edge trigger.** A control enumeration acts when it changes: the same C1
//!   operation, C1 rangefinder command, C2, E1, E2 or A1 action received again within
//!   [`REPEAT_WINDOW`] of the previous identical one is a repeat, not a new action; "no
//!   action" (0) re-arms. A console streaming 0x30 at its frame rate holds a value
//!   without repeating the action; ArduPilot's single blocks, sent once per user action,
//!   act every time (two photos a second apart are two photos).
//! - **Time and position.** M_AHRS (0xB1) is the only source: its date and time in
//!   0.01 s feed the UTC discipline (10 ms resolution), its position and the aircraft's
//!   attitude the fix history. The relative altitude of a fix is the MSL altitude above
//!   that of the first position received (M carries no home altitude).
//!
//! Replies carry the frame counter a Viewlink sender keeps (1, 2, 3, 0, ...); ArduPilot
//! masks it. Every reply fits ArduPilot's 63-byte packet buffer.

use crate::discipline::Sample;
use crate::fixes::Velocity;
use crate::gimbal::{Command, GimbalMode, Motion, Ranging, Target, View};
use crate::pod::PodNotice;
use crate::time::{Duration, Instant, TimeOfDay, UtcTime};
use protocol_core::Text;
use protocol_core::k40t::{AckCode, CaptureMode, Palette};
use protocol_core::viewlink::{
    self, A1, A2, B1, B2, Block, C1, C2, C2Command, Control, ControlTgcc, D1, D2, D2Sensor, Date,
    DistanceSource, E1, E2, F1, F2, FixedBlock, Frame, FrameCounter, GpsStage, Handshake,
    Heartbeat, IrColorMode, LaserCommand, LrfCommand, M, MessageData, OperationCommand,
    PixelFormat, Point, RareControl, RareControlTgcc, RareStatus, RecordStatus, S1, S2, Sensor,
    ServoCommand, Status, T1, T2, TimeCs, TrackerSensor, TrackerState, TrackingCommand, U,
    UCommand, V, VCommand, VData, VideoSource, ViewlinkFraming,
};

use super::{Ctx, FcHandler, Home, TimedFrom, clamp_i16};

/// Deframer buffer: the largest Viewlink frame (63 bytes of body).
pub(crate) const BUF: usize = viewlink::MAX_FRAME_LEN;

/// The same control value received again within this time of the previous one is a
/// repeat (the edge trigger); a longer pause re-arms it.
pub(crate) const REPEAT_WINDOW: Duration = Duration::from_millis(300);
/// After a tracking start (E1), how long the side waits for the point or box (E2) that
/// ArduPilot sends right behind it before tracking the centre of the picture.
const TRACK_TARGET_WAIT: Duration = Duration::from_millis(50);
/// A sensor asked for is reported until the pod's own report agrees, or for this long.
const SENSOR_SETTLE: Duration = Duration::from_secs(2);
/// Least time between two status frames (0x40, 0x41).
pub(crate) const STATUS_GAP: Duration = Duration::from_millis(50);
/// The K40T's thermal digital zoom range.
const IR_ZOOM_MAX: u8 = 8;
/// The picture's centre, in the pixels of [`Target`].
const CENTRE: Target = Target::Point { x: 960, y: 540 };

/// The last value of one control enumeration and when it came (the edge trigger).
#[derive(Debug, Clone, Copy)]
struct Edge<T> {
    last: Option<(T, Instant)>,
}

impl<T: Copy + PartialEq> Edge<T> {
    const NEW: Self = Edge { last: None };

    /// Records `value`; true when it is a new action (not a repeat within
    /// [`REPEAT_WINDOW`] of the same value).
    fn fresh(&mut self, now: Instant, value: T) -> bool {
        let repeat = self
            .last
            .is_some_and(|(v, at)| v == value && now.saturating_duration_since(at) < REPEAT_WINDOW);
        self.last = Some((value, now));
        !repeat
    }

    /// "No action": the next value acts, whatever it is.
    fn rearm(&mut self) {
        self.last = None;
    }
}

/// The lens group a continuous C1 operation moves (what "stop" stops).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum LensMotion {
    None,
    Zoom,
    Focus,
}

/// The Viewlink side (its link, deframer and bursts, is [`FcLink`](super::FcLink)).
#[derive(Debug, Clone)]
pub(crate) struct ViewlinkSide {
    /// When a status frame was last sent.
    status_sent: Option<Instant>,
    /// The frame counter of the replies.
    counter: FrameCounter,
    /// The servo state reported in B1: the last A1 command acted on.
    servo: ServoCommand,
    /// The sensor asked for last (C1), and when.
    sensor: Option<(Sensor, Instant)>,
    /// The tracker state reported in F1.
    tracker: TrackerState,
    /// A track command waits for its pod ACK.
    track_pending: bool,
    /// A tracking start (E1) waits for its point or box since then.
    track_armed: Option<Instant>,
    /// The top-left corner of a tracking box (E2 0x0B), waiting for the bottom-right.
    rect_top_left: Option<Point>,
    /// The thermal digital zoom the pod acknowledged (1..=8), and one waiting for its ACK.
    ir_zoom: u8,
    ir_zoom_pending: Option<u8>,
    /// What a C1 "stop" stops.
    lens_motion: LensMotion,
    /// MSL altitude of the first position, 0.1 m (the relative altitude's zero).
    home: Home,
    /// The date of the last M_AHRS (for the 0x41 status).
    date: Date,
    /// The instant of the last laser distance seen, and D1's toggle bit.
    laser_seen: Option<Instant>,
    lrf_toggle: bool,
    // The edge trigger, per control enumeration.
    a1: Edge<A1>,
    c1_op: Edge<OperationCommand>,
    c1_lrf: Edge<LrfCommand>,
    c2: Edge<C2>,
    e1: Edge<E1>,
    e2: Edge<E2>,
}

impl ViewlinkSide {
    pub(crate) fn new() -> Self {
        ViewlinkSide {
            status_sent: None,
            counter: FrameCounter::new(),
            servo: ServoCommand::FollowYaw,
            sensor: None,
            tracker: TrackerState::Stop,
            track_pending: false,
            track_armed: None,
            rect_top_left: None,
            ir_zoom: 1,
            ir_zoom_pending: None,
            lens_motion: LensMotion::None,
            home: Home::default(),
            date: Date::default(),
            laser_seen: None,
            lrf_toggle: false,
            a1: Edge::NEW,
            c1_op: Edge::NEW,
            c1_lrf: Edge::NEW,
            c2: Edge::NEW,
            e1: Edge::NEW,
            e2: Edge::NEW,
        }
    }
}

impl FcHandler for ViewlinkSide {
    type Framing = ViewlinkFraming;
    const TIMED_FROM: TimedFrom = TimedFrom::Burst;

    fn frame(&mut self, ctx: &mut Ctx<'_>, f: &[u8]) {
        self.fc_frame(ctx, f);
    }

    fn poll(&mut self, ctx: &mut Ctx<'_>) {
        if let Some(at) = self.track_armed
            && ctx.now >= at.saturating_add(TRACK_TARGET_WAIT)
        {
            // A tracking start without a point or a box: what is under the cross.
            self.start_track(ctx, 0x1E03, CENTRE);
        }
    }

    fn poll_at(&self) -> Option<Instant> {
        self.track_armed
            .map(|at| at.saturating_add(TRACK_TARGET_WAIT))
    }

    fn pod_notice(&mut self, _ctx: &mut Ctx<'_>, notice: PodNotice) {
        let (base, ok) = match notice {
            PodNotice::Acked { base, code } => (base, code == AckCode::Ok),
            PodNotice::TimedOut { base } => (base, false),
            PodNotice::LinkDown => {
                self.tracker = TrackerState::Stop;
                self.track_pending = false;
                self.track_armed = None;
                return;
            }
            _ => return,
        };
        match base {
            0x0324 if core::mem::take(&mut self.track_pending) => {
                self.tracker = if ok && self.tracker == TrackerState::Search {
                    TrackerState::Tracking
                } else {
                    TrackerState::Stop
                };
            }
            0x0105 => {
                if let Some(z) = self.ir_zoom_pending.take().filter(|_| ok) {
                    self.ir_zoom = z;
                }
            }
            _ => {}
        }
    }
}

/// A block decoded from a whole payload.
fn block<B: Block>(payload: &[u8]) -> Option<B> {
    B::from_bytes(payload).ok()
}

/// The FC id of a command for [`Ctx::command`]'s event: the frame id, then the block's
/// command byte.
fn fc_id(frame: u8, command: u8) -> u16 {
    u16::from_be_bytes([frame, command])
}

impl ViewlinkSide {
    /// Encodes a reply with the next frame counter and queues it for the FC.
    fn send<Msg: MessageData<Protocol = protocol_core::viewlink::Viewlink>>(
        &mut self,
        ctx: &mut Ctx<'_>,
        message: &Msg,
    ) -> bool {
        let mut buf = [0u8; BUF];
        match viewlink::encode(message, &self.counter.next_header(), &mut buf) {
            Ok(n) => ctx.reply(buf.get(..n).unwrap_or_default()),
            Err(_) => false,
        }
    }

    /// One valid frame from the FC. Only the blocks the side handles are decoded (by
    /// frame id, not through [`viewlink::Message`]), so that the codec's other types
    /// stay out of the firmware.
    fn fc_frame(&mut self, ctx: &mut Ctx<'_>, f: &[u8]) {
        ctx.seen();
        let Ok(frame) = Frame::new_checked(f) else {
            ctx.ignored();
            return;
        };
        let id = frame.id();
        let payload = frame.payload_ref();
        let handled = match id {
            // S1 and S2 (target calculation) have no K40T equivalent.
            Handshake::ID | Heartbeat::ID | S1::ID | S2::ID => {
                self.answer(ctx);
                true
            }
            U::ID => self.query(ctx, payload),
            M::ID => block(payload).map(|m: M| self.ahrs(ctx, &m)).is_some(),
            A1::ID => block(payload)
                .map(|a1| {
                    self.servo_control(ctx, id, a1);
                    self.answer(ctx);
                })
                .is_some(),
            C1::ID => block(payload)
                .map(|c1| {
                    self.optics(ctx, id, c1);
                    self.answer(ctx);
                })
                .is_some(),
            E1::ID => block(payload)
                .map(|e1| {
                    self.tracking(ctx, id, e1);
                    self.answer(ctx);
                })
                .is_some(),
            C2::ID => block(payload)
                .map(|c2| {
                    self.optics2(ctx, id, c2);
                    self.answer(ctx);
                })
                .is_some(),
            E2::ID => block(payload)
                .map(|e2| {
                    self.tracking2(ctx, id, e2);
                    self.answer(ctx);
                })
                .is_some(),
            A2::ID => block(payload).map(|a2| self.answer_rare(ctx, a2)).is_some(),
            Control::ID | ControlTgcc::ID => {
                // 0x32 is 0x30 followed by S1.
                let len = if id == Control::ID {
                    <Control as FixedBlock>::LEN
                } else {
                    <ControlTgcc as FixedBlock>::LEN
                };
                let c = (payload.len() == len)
                    .then(|| payload.get(..<Control as FixedBlock>::LEN))
                    .flatten()
                    .and_then(block::<Control>);
                c.map(|c| {
                    self.servo_control(ctx, id, c.a1);
                    self.optics(ctx, id, c.c1);
                    self.tracking(ctx, id, c.e1);
                    self.answer(ctx);
                })
                .is_some()
            }
            RareControl::ID | RareControlTgcc::ID => {
                // 0x33 is 0x31 followed by S2.
                let len = if id == RareControl::ID {
                    <RareControl as FixedBlock>::LEN
                } else {
                    <RareControlTgcc as FixedBlock>::LEN
                };
                let c = (payload.len() == len)
                    .then(|| payload.get(..<RareControl as FixedBlock>::LEN))
                    .flatten()
                    .and_then(block::<RareControl>);
                c.map(|c| {
                    self.optics2(ctx, id, c.c2);
                    self.tracking2(ctx, id, c.e2);
                    self.answer_rare(ctx, c.a2);
                })
                .is_some()
            }
            // Frames a gimbal sends, and queries the K40T cannot answer (SD card, IP
            // address, KLV, transparent data): ignored, as a Viewpro without the
            // feature ignores them.
            _ => false,
        };
        if !handled {
            ctx.ignored();
        }
    }

    // ------------------------------------------------------------------ replies

    /// A 0x40 status frame (ArduPilot's handshake, a console's control frame), unless
    /// one went out within [`STATUS_GAP`].
    fn answer(&mut self, ctx: &mut Ctx<'_>) {
        let owed = self
            .status_sent
            .is_none_or(|at| ctx.now.saturating_duration_since(at) >= STATUS_GAP);
        if !owed {
            return;
        }
        if let Some(s) = self.status(ctx)
            && self.send(ctx, &s)
        {
            self.status_sent = Some(ctx.now);
        }
    }

    /// A2 asks for one 0x41 (infrequently used status) instead of the 0x40.
    fn answer_rare(&mut self, ctx: &mut Ctx<'_>, a2: A2) {
        if !a2.request_status {
            self.answer(ctx);
            return;
        }
        if let Some(s) = self.rare_status(ctx, a2)
            && self.send(ctx, &s)
        {
            self.status_sent = Some(ctx.now);
        }
    }

    /// The 0x40 frame from the pod's state; `None` while the pod reports no attitude.
    fn status(&mut self, ctx: &Ctx<'_>) -> Option<Status> {
        let a = ctx.fresh_attitude()?;
        let pod = ctx.pod();
        let laser = pod.laser_dm.filter(|(_, at)| ctx.is_fresh(*at));
        if let Some((_, at)) = laser
            && self.laser_seen != Some(at)
        {
            self.laser_seen = Some(at);
            self.lrf_toggle = !self.lrf_toggle;
        }
        let lrf_dm = laser.map_or(0, |(d, _)| d);
        let fix = ctx.fixes.latest();
        let sensor = self.reported_sensor(ctx);
        let record = if pod.is_recording() {
            RecordStatus::Recording
        } else if pod.system.is_some_and(|s| s.mode == CaptureMode::Photo) {
            RecordStatus::PictureMode
        } else {
            RecordStatus::Stopped
        };
        Some(Status {
            t1: T1 {
                distance_source: if lrf_dm > 0 {
                    DistanceSource::Laser
                } else {
                    DistanceSource::None
                },
                gps_stage: if fix.is_some() {
                    GpsStage::Locked3d
                } else {
                    GpsStage::NoSignal
                },
                lat_e7: fix.map_or(0, |f| f.lat_e7),
                lon_e7: fix.map_or(0, |f| f.lon_e7),
                alt_m: fix.map_or(0, |f| f.alt_msl_dm / 10),
                ..T1::default()
            },
            f1: F1 {
                sensor: tracker_sensor(sensor),
                state: self.tracker,
                reserved: 0,
            },
            b1: B1 {
                servo: self.servo_status(),
                roll_raw12: B1::roll_raw_from_cdeg(i32::from(a.roll_cdeg)),
                yaw_bam16: cdeg_to_bam16(i32::from(a.yaw_joint_cdeg)),
                // ArduPilot negates what it reads: positive down on the wire.
                pitch_bam16: cdeg_to_bam16(i32::from(a.pitch_cdeg).saturating_neg()),
            },
            d1: D1 {
                source: video_source(sensor),
                ir_dzoom_index: self.ir_zoom.saturating_sub(1).min(15),
                lrf_toggle: self.lrf_toggle,
                record,
                // Always grayscale: ArduPilot reads byte 32 & 0x07 as the recording
                // status, so a colour mode bit would hide the recording.
                ir_color: IrColorMode::Grayscale,
                lrf_dm,
                // The hybrid (optical and electronic) ratio; no separate digital index.
                zoom_x10: pod.zoom_x10(),
                // Fields of view: not known (0).
                ..D1::default()
            },
        })
    }

    /// The 0x41 frame (asked by A2 bit 5): rates and roll in B2, the sensor in D2, the
    /// aircraft's attitude and the UTC time in T2.
    fn rare_status(&mut self, ctx: &Ctx<'_>, a2: A2) -> Option<RareStatus> {
        let a = ctx.fresh_attitude()?;
        let fix = ctx.fixes.latest().unwrap_or_default();
        let time = ctx
            .time
            .utc(ctx.now)
            .map(|u| u.time_of_day().millis_of_day() / 10)
            .unwrap_or_default();
        let sensor = self.reported_sensor(ctx);
        Some(RareStatus {
            t2: T2 {
                date: self.date,
                time: TimeCs(time),
                yaw_bam16: cdeg_to_bam16(i32::from(fix.yaw_cdeg)),
                pitch_bam16: cdeg_to_bam16(i32::from(fix.pitch_cdeg).saturating_neg()),
                roll_bam16: cdeg_to_bam16(i32::from(fix.roll_cdeg)),
                ..T2::default()
            },
            f2: F2::default(),
            b2: B2 {
                counter: a2.counter,
                roll_bam16: cdeg_to_bam16(i32::from(a.roll_cdeg)),
                roll_rate_cdeg_s: a.roll_rate_cdeg_s,
                yaw_rate_cdeg_s: a.yaw_rate_cdeg_s,
                pitch_rate_cdeg_s: a.pitch_rate_cdeg_s.saturating_neg(),
                ..B2::default()
            },
            d2: D2 {
                sensor: match sensor {
                    Sensor::Ir | Sensor::Ir1_13mm | Sensor::Ir2_52mm => D2Sensor::Ir,
                    Sensor::Eo1IrPip | Sensor::Fusion => D2Sensor::Eo1IrPip,
                    Sensor::IrEo1Pip => D2Sensor::IrEo1Pip,
                    _ => D2Sensor::Eo1,
                },
                pixels: PixelFormat::P1080,
                ..D2::default()
            },
        })
    }

    /// The servo state reported in B1.
    fn servo_status(&self) -> ServoCommand {
        match self.tracker {
            TrackerState::Search | TrackerState::Tracking => ServoCommand::Tracking,
            _ => self.servo,
        }
    }

    /// The sensor reported in D1 (and compared with C1's): the one asked for, until
    /// the pod's report disagrees for longer than [`SENSOR_SETTLE`]; else the pod's.
    fn reported_sensor(&self, ctx: &Ctx<'_>) -> Sensor {
        let pod_view = ctx.pod().view();
        match self.sensor {
            Some((s, at))
                if pod_view.is_none()
                    || pod_view == view_of(s)
                    || ctx.now.saturating_duration_since(at) < SENSOR_SETTLE =>
            {
                s
            }
            _ => match pod_view {
                Some(View::Thermal) => Sensor::Ir,
                Some(View::Split) => Sensor::Eo1IrPip,
                _ => Sensor::Eo1,
            },
        }
    }

    /// U: the model and firmware queries ArduPilot sends until answered (V with the
    /// query's code). Returns false for the other U commands.
    fn query(&mut self, ctx: &mut Ctx<'_>, payload: &[u8]) -> bool {
        if payload.len() != <U as FixedBlock>::LEN {
            return false;
        }
        let id = ctx.config.viewlink;
        let command = UCommand::from_value(payload.first().copied().unwrap_or_default());
        let data = match command {
            UCommand::QueryModel => VData::Model(Text { raw: id.model }),
            UCommand::QueryFirmware => VData::Firmware(Text {
                raw: ctx.build.version.viewlink_text(),
            }),
            // Settings of the Viewpro's serial link, OSD and RC channels: nothing on
            // the K40T to set or report.
            _ => return false,
        };
        self.send(ctx, &V::new(VCommand::from_value(command.value()), data));
        true
    }

    // ------------------------------------------------------------------ AHRS

    /// M_AHRS: UTC, position and the aircraft's attitude.
    fn ahrs(&mut self, ctx: &mut Ctx<'_>, m: &M) {
        let Some(g) = m.gps else {
            return;
        };
        let transit = ctx.transit;
        let utc = TimeOfDay::from_millis_of_day(g.time.0.saturating_mul(10)).and_then(|tod| {
            UtcTime::from_date_time(g.date.year(), g.date.month(), g.date.day(), tod)
        });
        if utc.is_some() {
            self.date = g.date;
        }
        if let Some(utc) = utc.filter(|_| ctx.feeds) {
            ctx.time.utc_sample(
                Sample::new(ctx.now, utc.as_unix_micros(), 10_000).with_transit(transit),
            );
        }
        if g.lat_e7 == 0 && g.lon_e7 == 0 {
            return;
        }
        let attitude = m.attitude.map_or([0; 3], |a| {
            [
                clamp_i16(bam16_to_cdeg(a.roll_bam16)),
                // ArduPilot sends the aircraft's pitch negated.
                clamp_i16(bam16_to_cdeg(a.pitch_bam16).saturating_neg()),
                clamp_i16(bam16_to_cdeg(a.yaw_bam16)),
            ]
        });
        let velocity = Velocity::from_cm_s(
            i32::from(g.vel_north_cm_s),
            i32::from(g.vel_east_cm_s),
            i32::from(g.vel_down_cm_s),
        );
        let fix = self.home.fix(
            ctx.now.saturating_sub(transit),
            (g.lat_e7, g.lon_e7, g.height_mm / 100),
            attitude,
            velocity,
        );
        ctx.push_fix(fix);
    }

    // ------------------------------------------------------------------ A1

    /// A1: motion goes to the pod driver as it comes; actions are edge-triggered.
    fn servo_control(&mut self, ctx: &mut Ctx<'_>, frame: u8, a1: A1) {
        let command = a1.command();
        let id = fc_id(frame, command.value());
        let fresh = self.a1.fresh(ctx.now, a1);
        match a1 {
            A1::ManualSpeed(s) => {
                self.servo = command;
                ctx.command(
                    id,
                    Command::Rates {
                        yaw_cdeg_s: i32::from(s.yaw_cdeg_s),
                        pitch_cdeg_s: i32::from(s.pitch_cdeg_s).saturating_neg(),
                    },
                );
            }
            A1::AbsoluteAngle(a) => {
                self.servo = command;
                ctx.command(
                    id,
                    Command::Angles {
                        yaw_cdeg: bam16_to_cdeg(a.yaw_bam16),
                        pitch_cdeg: bam16_to_cdeg(a.pitch_bam16).saturating_neg(),
                    },
                );
            }
            A1::AbsoluteAngle720(a) => {
                self.servo = command;
                ctx.command(
                    id,
                    Command::Angles {
                        yaw_cdeg: bam14_to_cdeg(a.yaw_bam14),
                        pitch_cdeg: bam14_to_cdeg(a.pitch_bam14).saturating_neg(),
                    },
                );
            }
            A1::RelativeAngle(r) if fresh => {
                // From where the gimbal is now: once per new value, never accumulated.
                if let Some(now) = ctx.fresh_attitude() {
                    self.servo = command;
                    let yaw = i32::from(now.yaw_joint_cdeg)
                        .saturating_add(bam16_to_cdeg(r.yaw_bam16))
                        .saturating_add(18_000)
                        .rem_euclid(36_000)
                        .saturating_sub(18_000);
                    let pitch =
                        i32::from(now.pitch_cdeg).saturating_sub(bam16_to_cdeg(r.pitch_bam16));
                    ctx.command(
                        id,
                        Command::Angles {
                            yaw_cdeg: yaw,
                            pitch_cdeg: pitch,
                        },
                    );
                }
            }
            A1::TrackClick(c) if fresh => {
                let target = Target::Point {
                    x: pixel(c.yaw_px, 960),
                    y: pixel(c.pitch_px, 540),
                };
                self.start_track(ctx, id, target);
            }
            A1::Plain { command, .. } => match command {
                ServoCommand::FollowYaw => {
                    self.servo = command;
                    ctx.command(id, Command::Mode(GimbalMode::Follow));
                }
                ServoCommand::FollowYawDisable => {
                    self.servo = command;
                    ctx.command(id, Command::Mode(GimbalMode::Lock));
                }
                ServoCommand::Home if fresh => {
                    self.servo = command;
                    ctx.command(id, Command::Center);
                }
                ServoCommand::LookDown if fresh => {
                    self.servo = command;
                    ctx.command(id, Command::LookDown);
                }
                ServoCommand::NoChange => self.a1.rearm(),
                ServoCommand::Home | ServoCommand::LookDown | ServoCommand::Tracking => {}
                _ => ctx.ignored(),
            },
            A1::RelativeAngle(_) | A1::TrackClick(_) => {}
            // Motor power, scans, RC mode, gyro and frame-heading corrections: nothing
            // on the K40T does them.
            _ => ctx.ignored(),
        }
    }

    // ------------------------------------------------------------------ C1, C2

    /// C1: sensor, operation and rangefinder, each its own control enumeration.
    fn optics(&mut self, ctx: &mut Ctx<'_>, frame: u8, c1: C1) {
        self.select_sensor(ctx, frame, c1.sensor);
        let op = c1.operation;
        if op == OperationCommand::NoAction {
            self.c1_op.rearm();
        } else if self.c1_op.fresh(ctx.now, op) {
            self.operation(ctx, fc_id(frame, op.value()), op);
        }
        let lrf = c1.lrf;
        if lrf == LrfCommand::NoAction {
            self.c1_lrf.rearm();
        } else if self.c1_lrf.fresh(ctx.now, lrf) {
            let ranging = match lrf {
                LrfCommand::Single => Ranging::Single,
                LrfCommand::Continuous | LrfCommand::LpclContinuous => Ranging::Continuous,
                LrfCommand::Stop => Ranging::Off,
                _ => {
                    ctx.ignored();
                    return;
                }
            };
            ctx.command(fc_id(frame, lrf.value()), Command::Laser(ranging));
        }
    }

    /// C1's sensor: a change of the picture streamed (ArduPilot repeats the current
    /// sensor in every C1, which is no change).
    fn select_sensor(&mut self, ctx: &mut Ctx<'_>, frame: u8, sensor: Sensor) {
        let Some(view) = view_of(sensor) else {
            return;
        };
        let current = self.reported_sensor(ctx);
        if sensor == current {
            return;
        }
        self.sensor = Some((sensor, ctx.now));
        if view_of(current) != Some(view) {
            ctx.command(fc_id(frame, sensor.value()), Command::View(view));
        }
    }

    #[allow(clippy::too_many_lines)] // one short arm per operation
    fn operation(&mut self, ctx: &mut Ctx<'_>, id: u16, op: OperationCommand) {
        let cmd = match op {
            OperationCommand::StopZoomFocus => {
                let m = core::mem::replace(&mut self.lens_motion, LensMotion::None);
                if m == LensMotion::Focus {
                    Command::Focus(Motion::Stop)
                } else {
                    Command::Zoom(Motion::Stop)
                }
            }
            OperationCommand::ZoomIn | OperationCommand::ZoomOut => {
                self.lens_motion = LensMotion::Zoom;
                Command::Zoom(if op == OperationCommand::ZoomIn {
                    Motion::In
                } else {
                    Motion::Out
                })
            }
            OperationCommand::FocusUp | OperationCommand::FocusDown => {
                self.lens_motion = LensMotion::Focus;
                // Focus + (ArduPilot's "out", +1) is far, as the SIYI side's far.
                Command::Focus(if op == OperationCommand::FocusUp {
                    Motion::In
                } else {
                    Motion::Out
                })
            }
            OperationCommand::TakePicture => Command::TakePhoto,
            OperationCommand::StartRecord => Command::Record(true),
            OperationCommand::StopRecord => Command::Record(false),
            OperationCommand::AutoFocus => Command::AutoFocus(None),
            OperationCommand::ManualFocus => Command::ManualFocus(true),
            OperationCommand::IrDzoomIn | OperationCommand::IrDzoomOut => {
                let from = self.ir_zoom_pending.unwrap_or(self.ir_zoom);
                let ratio = if op == OperationCommand::IrDzoomIn {
                    from.saturating_add(1).min(IR_ZOOM_MAX)
                } else {
                    from.saturating_sub(1).max(1)
                };
                self.ir_zoom_pending = Some(ratio);
                Command::ThermalZoom { ratio }
            }
            OperationCommand::IrWhiteHot => Command::Palette(Palette::WhiteHot),
            OperationCommand::IrBlackHot => Command::Palette(Palette::BlackHot),
            OperationCommand::IrRainbow => Command::Palette(Palette::Rainbow),
            OperationCommand::IrColorExt1
            | OperationCommand::IrColorExt2
            | OperationCommand::IrColorExt3
            | OperationCommand::IrColorExt4
            | OperationCommand::IrColorExt5
            | OperationCommand::IrColorExt6 => {
                // The document names no colours: the K40T palettes after the three
                // named ones, in K40T order (ext 1 = high-contrast red ... ext 6 =
                // grey red).
                let n = op
                    .value()
                    .saturating_sub(OperationCommand::IrColorExt1.value());
                Command::Palette(Palette::from_value(n.saturating_add(4)))
            }
            _ => {
                // Brightness, contrast, aperture, gain, NUC, capture mode switches, SD
                // card format and queries, thermal raw: no K40T command through the
                // bridge.
                ctx.ignored();
                return;
            }
        };
        ctx.command(id, cmd);
    }

    /// C2: absolute EO zoom, thermal digital zoom, laser on/off.
    fn optics2(&mut self, ctx: &mut Ctx<'_>, frame: u8, c2: C2) {
        let command = c2.command();
        if command == C2Command::NoAction {
            self.c2.rearm();
            return;
        }
        if !self.c2.fresh(ctx.now, c2) {
            return;
        }
        let id = fc_id(frame, command.value());
        let cmd = match c2 {
            C2::SetEoZoom(z) => Command::ZoomTo {
                zoom_x10: z.zoom_x10,
            },
            C2::SetIrZoom(z) => {
                let ratio = u8::try_from(z.zoom_x10.saturating_add(5) / 10)
                    .unwrap_or(IR_ZOOM_MAX)
                    .clamp(1, IR_ZOOM_MAX);
                self.ir_zoom_pending = Some(ratio);
                Command::ThermalZoom { ratio }
            }
            // The K40T's laser is its rangefinder: on ranges continuously.
            C2::Laser(l) if l.command == LaserCommand::On => Command::Laser(Ranging::Continuous),
            C2::Laser(l) if l.command == LaserCommand::Off => Command::Laser(Ranging::Off),
            _ => {
                ctx.ignored();
                return;
            }
        };
        ctx.command(id, cmd);
    }

    // ------------------------------------------------------------------ E1, E2

    /// E1: tracking start and stop.
    fn tracking(&mut self, ctx: &mut Ctx<'_>, frame: u8, e1: E1) {
        if e1.command == TrackingCommand::NoAction {
            self.e1.rearm();
            return;
        }
        if !self.e1.fresh(ctx.now, e1) {
            return;
        }
        let id = fc_id(frame, e1.command.value());
        match e1.command {
            TrackingCommand::Stop => {
                self.track_armed = None;
                self.rect_top_left = None;
                self.track_pending = false;
                self.tracker = TrackerState::Stop;
                ctx.command(id, Command::Track(None));
            }
            TrackingCommand::Start | TrackingCommand::ToCross => {
                // The point or box follows (ArduPilot sends E2 right behind); else
                // the centre, after a short wait (see `poll`).
                self.track_armed = Some(ctx.now);
                self.tracker = TrackerState::Search;
            }
            // Search cross, AI and template settings: no K40T equivalent here.
            _ => ctx.ignored(),
        }
    }

    /// E2: the tracking point or box.
    fn tracking2(&mut self, ctx: &mut Ctx<'_>, frame: u8, e2: E2) {
        let command = e2.command();
        if command.value() == 0 {
            self.e2.rearm();
            return;
        }
        if !self.e2.fresh(ctx.now, e2) {
            return;
        }
        let id = fc_id(frame, command.value());
        match e2 {
            E2::TrackPoint(p) => {
                let target = Target::Point {
                    x: pixel(p.x_px, 960),
                    y: pixel(p.y_px, 540),
                };
                if self.track_armed.is_some() || self.tracker != TrackerState::Stop {
                    self.start_track(ctx, id, target);
                } else {
                    // Not tracking: bring that point to the centre.
                    ctx.command(id, Command::Aim(target));
                }
            }
            E2::RectTopLeft(p) => self.rect_top_left = Some(p),
            E2::RectBottomRight(p) => {
                if let Some(tl) = self.rect_top_left.take() {
                    let target = Target::Box {
                        x0: pixel(tl.x_px, 960),
                        y0: pixel(tl.y_px, 540),
                        x1: pixel(p.x_px, 960),
                        y1: pixel(p.y_px, 540),
                    };
                    self.start_track(ctx, id, target);
                }
            }
            _ => ctx.ignored(),
        }
    }

    /// Tracks `target`: manual motion ends (the tracker turns the gimbal), the tracker
    /// searches until the pod acknowledges.
    fn start_track(&mut self, ctx: &mut Ctx<'_>, id: u16, target: Target) {
        self.track_armed = None;
        ctx.command(
            id,
            Command::Rates {
                yaw_cdeg_s: 0,
                pitch_cdeg_s: 0,
            },
        );
        self.tracker = TrackerState::Search;
        self.track_pending = ctx.command(id, Command::Track(Some(target))).is_some();
        if !self.track_pending {
            self.tracker = TrackerState::Stop;
        }
    }
}

/// The picture a sensor choice streams (`None`: no action).
fn view_of(s: Sensor) -> Option<View> {
    match s {
        Sensor::Eo1 => Some(View::Visible),
        Sensor::Ir | Sensor::Ir1_13mm | Sensor::Ir2_52mm => Some(View::Thermal),
        Sensor::Eo1IrPip | Sensor::IrEo1Pip | Sensor::Fusion => Some(View::Split),
        _ => None,
    }
}

/// D1's video source: one less than C1's sensor code.
fn video_source(s: Sensor) -> VideoSource {
    VideoSource::from_value(s.value().saturating_sub(1).min(6))
}

/// F1's tracking sensor.
fn tracker_sensor(s: Sensor) -> TrackerSensor {
    match s {
        Sensor::Ir | Sensor::IrEo1Pip | Sensor::Ir1_13mm | Sensor::Ir2_52mm => TrackerSensor::Ir,
        _ => TrackerSensor::Eo1,
    }
}

/// A centred pixel offset (`-half..=half`) as a pixel of the 1920 x 1080 picture.
fn pixel(offset: i16, half: u16) -> u16 {
    let p = i32::from(offset)
        .saturating_add(i32::from(half))
        .clamp(0, i32::from(half).saturating_mul(2));
    u16::try_from(p).unwrap_or(0)
}

/// A 16-bit binary angle (360/65536°) in 0.01°, rounded.
fn bam16_to_cdeg(v: i16) -> i32 {
    let x = i64::from(v).saturating_mul(36_000).saturating_add(32_768);
    clamp_i32(x.checked_div_euclid(65_536).unwrap_or(0))
}

/// A 720° binary angle (720/32768° = 360/16384° per bit) in 0.01°, rounded.
fn bam14_to_cdeg(v: i16) -> i32 {
    let x = i64::from(v).saturating_mul(36_000).saturating_add(8_192);
    clamp_i32(x.checked_div_euclid(16_384).unwrap_or(0))
}

/// 0.01° as a 16-bit binary angle, rounded, wrapped to ±180°.
fn cdeg_to_bam16(cdeg: i32) -> i16 {
    let x = i64::from(cdeg)
        .saturating_mul(65_536)
        .saturating_add(18_000);
    let [b0, b1, ..] = x.checked_div_euclid(36_000).unwrap_or(0).to_le_bytes();
    i16::from_le_bytes([b0, b1])
}

/// An `i64` saturated to `i32`.
fn clamp_i32(v: i64) -> i32 {
    i32::try_from(v).unwrap_or(if v < 0 { i32::MIN } else { i32::MAX })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angle_units() {
        assert_eq!(bam16_to_cdeg(0x3FFC), 8_998); // the document's "90°" example
        assert_eq!(bam16_to_cdeg(0x4000), 9_000);
        assert_eq!(bam16_to_cdeg(i16::MIN), -18_000);
        assert_eq!(bam14_to_cdeg(0x2000), 18_000);
        assert_eq!(cdeg_to_bam16(9_000), 0x4000);
        assert_eq!(cdeg_to_bam16(-4_500), -0x2000);
        assert_eq!(cdeg_to_bam16(18_000), i16::MIN, "wraps");
        for c in [-17_999, -1_234, -1, 0, 1, 4_567, 17_999] {
            assert!((bam16_to_cdeg(cdeg_to_bam16(c)) - c).abs() <= 1, "{c}");
        }
        assert_eq!(pixel(-960, 960), 0);
        assert_eq!(pixel(0, 540), 540);
        assert_eq!(pixel(2000, 960), 1920);
    }

    #[test]
    fn sizes() {
        let side = core::mem::size_of::<super::super::FcLink<ViewlinkSide, BUF>>();
        let state = core::mem::size_of::<ViewlinkSide>();
        println!("the Viewlink link {side} B, of which the side's state {state} B");
        assert!(state <= 320);
    }

    #[test]
    fn edge_trigger() {
        let mut e = Edge::<u8>::NEW;
        let t = Instant::from_millis;
        assert!(e.fresh(t(0), 1));
        assert!(!e.fresh(t(100), 1), "a repeat");
        assert!(!e.fresh(t(350), 1), "held: each repeat renews the window");
        assert!(e.fresh(t(400), 2), "a change");
        assert!(e.fresh(t(800), 2), "after a pause: a new action");
        e.rearm();
        assert!(e.fresh(t(810), 2), "re-armed by no action");
    }
}
