//! The MAVLink side: the bridge is a MAVLink 2 gimbal device (component 154) and camera
//! (component 100) towards ArduPilot (`MNT1_TYPE` 6, `CAM1_TYPE` 6), PX4 (gimbal v2
//! output) and, through their routing, QGroundControl (`shared/MAVLINK-TRAFFIC.md`).
//!
//! - **Identity.** Both components send HEARTBEAT at 1 Hz (type 26 GIMBAL and 30 CAMERA,
//!   autopilot INVALID) with the system id of the autopilot, learnt from its own
//!   HEARTBEAT (component 1); nothing is sent before it is heard. Each component numbers
//!   its frames itself.
//! - **Commands** (COMMAND_LONG and COMMAND_INT, any MAV_CMD value) addressed to the
//!   device's system (or 0) and to one of its components (or 0, broadcast: ArduPilot 4.5
//!   and 4.6 send camera commands to 0/0): each one a component acts on is answered with
//!   COMMAND_ACK to its sender; one addressed to a component that cannot serve it gets
//!   MAV_RESULT_UNSUPPORTED (GIMBAL_MANAGER_INFORMATION from QGroundControl, ROI,
//!   SET_MESSAGE_INTERVAL, video streaming, storage format); a broadcast command neither
//!   component serves is someone else's and left alone. MAV_CMD_REQUEST_MESSAGE is
//!   answered with the ACK, then the message, from the component that owns it (only the
//!   gimbal answers GIMBAL_DEVICE_INFORMATION: PX4 takes the gimbal's component id from
//!   it); the deprecated MAV_CMD_REQUEST_CAMERA_* commands the same way.
//! - **Gimbal** ([`gimbal`]): GIMBAL_DEVICE_SET_ATTITUDE in every form the autopilots send
//!   becomes angles or rates for the pod; GIMBAL_DEVICE_ATTITUDE_STATUS goes out at 10 Hz
//!   from the pod's attitude (roll and pitch against the horizon, yaw relative to the
//!   vehicle, flagged so), with COMMS_ERROR set while the pod does not report; the device
//!   information carries the pod's limits (pitch −90°..+30°, yaw ±180°, from the K40T
//!   document's 0x000012) and versions.
//! - **Camera** ([`camera`]): photos (single and interval), video, zoom, focus and mode
//!   reach the pod; their ACK waits for the pod's; CAMERA_IMAGE_CAPTURED follows each
//!   photo with the position the pod was given for its geotag.
//! - **Time and position.** Copter streams nothing to a new port, PX4's gimbal mode no
//!   position or time: the gimbal asks the autopilot with MAV_CMD_SET_MESSAGE_INTERVAL
//!   for SYSTEM_TIME, GLOBAL_POSITION_INT, ATTITUDE (10 Hz) and GPS_RAW_INT (2 Hz), again
//!   whenever one stops (an autopilot reboot forgets them), once a second for the first
//!   tries, then every 10 s. SYSTEM_TIME's Unix time is a UTC sample (ArduPilot sends 0
//!   until its clock is set: rejected), GLOBAL_POSITION_INT a fix while GPS_RAW_INT
//!   reports a 3D fix (ArduPilot sends positions without one), with the aircraft's
//!   attitude from ATTITUDE or AUTOPILOT_STATE_FOR_GIMBAL_DEVICE, whose yaw also turns
//!   earth-frame gimbal yaw into the pod's vehicle-relative yaw.
//! - **TIMESYNC** requests (tc1 = 0, ArduPilot's every 10 s) are answered with the
//!   bridge's clock in ns, so that the autopilot's round-trip log works.

mod camera;
mod gimbal;
mod math;

use crate::bridge::discipline::Sample;
use crate::bridge::fixes::{Fix, Velocity};
use crate::bridge::pod::PodNotice;
use crate::bridge::time::{Duration, Instant};
use crate::k40t::{GpsRequest, Header as PodHeader};
use crate::mavlink::dialect::{
    GPS_RAW_INT_DATA, GpsFixType, HEARTBEAT_DATA, MavAutopilot, MavModeFlag, MavState, MavType,
    TIMESYNC_DATA,
};
use crate::mavlink::{
    self, Frame, Header, MAX_FRAME_LEN, MavMessage, MavlinkFraming, Message, Packet, Raw,
};

use super::{Ctx, FcHandler, TimedFrom, clamp_i16};

/// Deframer buffer: the longest MAVLink 2 frame (signed, 255-byte payload).
pub(crate) const BUF: usize = MAX_FRAME_LEN;

/// The autopilot's component id.
const AUTOPILOT: u8 = 1;
/// HEARTBEAT period of each component.
const HEARTBEAT_PERIOD: Duration = Duration::from_secs(1);
/// A stream not received for this long is asked for again.
const STREAM_STALE: Duration = Duration::from_secs(3);
/// Tries of SET_MESSAGE_INTERVAL a second apart before slowing to one every
/// [`STREAM_BACKOFF`].
const STREAM_QUICK_TRIES: u8 = 5;
/// Retry period after the quick tries.
const STREAM_BACKOFF: Duration = Duration::from_secs(10);
/// The aircraft's attitude older than this is not used.
const VEHICLE_FRESH: Duration = Duration::from_secs(1);
/// A GPS_RAW_INT 3D fix older than this does not make positions fixes.
const GPS_FRESH: Duration = Duration::from_secs(3);

/// MAV_RESULT values.
mod result {
    pub(super) const ACCEPTED: u8 = 0;
    pub(super) const TEMPORARILY_REJECTED: u8 = 1;
    pub(super) const DENIED: u8 = 2;
    pub(super) const UNSUPPORTED: u8 = 3;
    pub(super) const FAILED: u8 = 4;
}

/// MAV_CMD values the device reads.
mod cmd {
    pub(super) const SET_MESSAGE_INTERVAL: u16 = 511;
    pub(super) const REQUEST_MESSAGE: u16 = 512;
    pub(super) const REQUEST_CAMERA_INFORMATION: u16 = 521;
    pub(super) const REQUEST_CAMERA_SETTINGS: u16 = 522;
    pub(super) const REQUEST_STORAGE_INFORMATION: u16 = 525;
    pub(super) const REQUEST_CAMERA_CAPTURE_STATUS: u16 = 527;
    pub(super) const SET_CAMERA_MODE: u16 = 530;
    pub(super) const SET_CAMERA_ZOOM: u16 = 531;
    pub(super) const SET_CAMERA_FOCUS: u16 = 532;
    pub(super) const IMAGE_START_CAPTURE: u16 = 2000;
    pub(super) const IMAGE_STOP_CAPTURE: u16 = 2001;
    pub(super) const REQUEST_CAMERA_IMAGE_CAPTURE: u16 = 2002;
    pub(super) const VIDEO_START_CAPTURE: u16 = 2500;
    pub(super) const VIDEO_STOP_CAPTURE: u16 = 2501;
}

/// Message ids the device sends or asks for.
mod id {
    pub(super) const HEARTBEAT: u32 = 0;
    pub(super) const COMMAND_ACK: u32 = 77;
    pub(super) const CAMERA_INFORMATION: u32 = 259;
    pub(super) const CAMERA_SETTINGS: u32 = 260;
    pub(super) const STORAGE_INFORMATION: u32 = 261;
    pub(super) const CAMERA_CAPTURE_STATUS: u32 = 262;
    pub(super) const CAMERA_IMAGE_CAPTURED: u32 = 263;
    pub(super) const GIMBAL_DEVICE_INFORMATION: u32 = 283;
    pub(super) const GIMBAL_DEVICE_ATTITUDE_STATUS: u32 = 285;
}

/// The streams the device asks the autopilot for (message ids).
mod stream {
    pub(super) const SYSTEM_TIME: u8 = 2;
    pub(super) const GPS_RAW_INT: u8 = 24;
    pub(super) const ATTITUDE: u8 = 30;
    pub(super) const GLOBAL_POSITION_INT: u8 = 33;
}

/// One of the device's two components.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Comp {
    /// MAV_COMP_ID_GIMBAL.
    Gimbal,
    /// MAV_COMP_ID_CAMERA.
    Camera,
}

impl Comp {
    const fn id(self) -> u8 {
        match self {
            Comp::Gimbal => 154,
            Comp::Camera => 100,
        }
    }

    fn of(compid: u8) -> Option<Self> {
        [Comp::Gimbal, Comp::Camera]
            .into_iter()
            .find(|c| c.id() == compid)
    }
}

/// A stream the device asks the autopilot for.
#[derive(Debug, Clone, Copy)]
struct Stream {
    /// The message id (all below 256).
    id: u8,
    interval_us: u32,
    /// The last one received.
    last: Option<Instant>,
    /// Requests since it was last received.
    tries: u8,
    /// When it may be asked for again.
    next_try: Instant,
}

impl Stream {
    const fn new(id: u8, interval_us: u32) -> Self {
        Stream {
            id,
            interval_us,
            last: None,
            tries: 0,
            next_try: Instant::ZERO,
        }
    }
}

/// The aircraft's attitude, 0.01° (yaw from north) and 0.01°/s.
#[derive(Debug, Clone, Copy)]
struct Vehicle {
    roll: i32,
    pitch: i32,
    yaw: i32,
    /// Earth-frame yaw rate, when known.
    yaw_rate: Option<i32>,
    at: Instant,
}

/// A command, from COMMAND_LONG or COMMAND_INT (any MAV_CMD value, known or not).
#[derive(Debug, Clone, Copy)]
struct Cmd {
    command: u16,
    /// param1..param7 (COMMAND_INT: x and y as numbers).
    params: [f32; 7],
    target_system: u8,
    target_component: u8,
    /// The sender.
    from: Header,
}

impl Cmd {
    /// Parameter `n` (1..=7); NaN when absent.
    fn param(&self, n: usize) -> f32 {
        self.params
            .get(n.wrapping_sub(1))
            .copied()
            .unwrap_or(f32::NAN)
    }

    /// From a COMMAND_LONG or COMMAND_INT payload as sent (zero-extended): the layout both
    /// share where it matters (seven 4-byte parameters, the command at byte 28, the
    /// targets at 30 and 31), for any MAV_CMD value, known to the dialect or not.
    #[allow(clippy::cast_precision_loss)] // COMMAND_INT x and y as parameters
    fn from_payload(msg_id: u32, payload: &[u8], from: Header) -> Option<Self> {
        let mut p = [0u8; 35];
        for (d, s) in p.iter_mut().zip(payload) {
            *d = *s;
        }
        let word = |at: usize| -> [u8; 4] {
            let mut w = [0u8; 4];
            for (d, s) in w.iter_mut().zip(p.iter().skip(at)) {
                *d = *s;
            }
            w
        };
        let mut params = [0f32; 7];
        for (i, slot) in params.iter_mut().enumerate() {
            let w = word(i.saturating_mul(4));
            *slot = if msg_id == 75 && (i == 4 || i == 5) {
                i32::from_le_bytes(w) as f32
            } else {
                f32::from_le_bytes(w)
            };
        }
        let [c0, c1, ts, tc] = word(28);
        (msg_id == 75 || msg_id == 76).then_some(Cmd {
            command: u16::from_le_bytes([c0, c1]),
            params,
            target_system: ts,
            target_component: tc,
            from,
        })
    }
}

/// The MAVLink side (its link, deframer and bursts, is [`FcLink`](super::FcLink)).
#[derive(Debug, Clone)]
pub(crate) struct MavlinkSide {
    /// The autopilot's system id, the device's own (from the autopilot's HEARTBEAT).
    sysid: Option<u8>,
    /// Next sequence number of the gimbal's and the camera's frames.
    seq: [u8; 2],
    next_heartbeat: Instant,
    next_status: Instant,
    streams: [Stream; 4],
    vehicle: Option<Vehicle>,
    /// The last GPS_RAW_INT with a 3D fix.
    gps_fix_at: Option<Instant>,
    /// The pod's reports came back at this instant (versions are asked then).
    pod_up_since: Option<Instant>,
    gimbal: gimbal::Gimbal,
    camera: camera::Camera,
}

impl MavlinkSide {
    pub(crate) fn new() -> Self {
        MavlinkSide {
            sysid: None,
            seq: [0; 2],
            next_heartbeat: Instant::ZERO,
            next_status: Instant::ZERO,
            streams: [
                Stream::new(stream::SYSTEM_TIME, 100_000),
                Stream::new(stream::GLOBAL_POSITION_INT, 100_000),
                Stream::new(stream::ATTITUDE, 100_000),
                Stream::new(stream::GPS_RAW_INT, 500_000),
            ],
            vehicle: None,
            gps_fix_at: None,
            pod_up_since: None,
            gimbal: gimbal::Gimbal::default(),
            camera: camera::Camera::default(),
        }
    }
}

impl FcHandler for MavlinkSide {
    type Framing = MavlinkFraming;
    // An autopilot composes each message when it writes it (a stream's message, an
    // answer): its values are read at the frame's own first byte.
    const TIMED_FROM: TimedFrom = TimedFrom::Frame;

    fn frame(&mut self, ctx: &mut Ctx<'_>, f: &[u8]) {
        ctx.seen();
        let Ok(frame) = Frame::new_checked(f) else {
            ctx.ignored();
            return;
        };
        let header = Header {
            sequence: frame.sequence(),
            system_id: frame.system_id(),
            component_id: frame.component_id(),
        };
        // Commands are read from their bytes: any MAV_CMD value, known to the dialect or
        // not, is answered.
        if let Some(c) = Cmd::from_payload(frame.message_id(), frame.payload_ref(), header) {
            self.command(ctx, &c);
            return;
        }
        match Packet::parse(&frame).map(|p| p.message) {
            Ok(Message::Known(m)) => self.message(ctx, header, m),
            _ => ctx.ignored(),
        }
    }

    fn poll(&mut self, ctx: &mut Ctx<'_>) {
        if self.sysid.is_some() {
            if ctx.now >= self.next_heartbeat {
                self.next_heartbeat = ctx.now.saturating_add(HEARTBEAT_PERIOD);
                self.heartbeat(ctx, Comp::Gimbal);
                self.heartbeat(ctx, Comp::Camera);
            }
            if ctx.now >= self.next_status {
                self.next_status = ctx.now.saturating_add(gimbal::STATUS_PERIOD);
                self.attitude_status(ctx);
            }
            self.request_streams(ctx);
        }
        self.camera_poll(ctx);
    }

    fn poll_at(&self) -> Option<Instant> {
        let device = self.sysid.map(|_| {
            let streams = self.streams.iter().map(Self::stream_due);
            streams
                .chain([self.next_heartbeat, self.next_status])
                .min()
                .unwrap_or(self.next_status)
        });
        [device, self.camera.poll_at()].into_iter().flatten().min()
    }

    fn pod_notice(&mut self, ctx: &mut Ctx<'_>, notice: PodNotice) {
        match notice {
            PodNotice::LinkUp => self.pod_up_since = Some(ctx.now),
            PodNotice::LinkDown => self.pod_up_since = None,
            PodNotice::Acked { base, code } => {
                self.camera_pod_answer(ctx, base, code == crate::k40t::AckCode::Ok);
            }
            PodNotice::TimedOut { base } => self.camera_pod_answer(ctx, base, false),
            PodNotice::GpsRequest { .. } => {}
        }
    }

    /// The pod asks where a photo was taken: noted for the photo's CAMERA_IMAGE_CAPTURED;
    /// the engine answers it from the fix history.
    fn gps_request(&mut self, ctx: &mut Ctx<'_>, header: PodHeader, request: GpsRequest) -> bool {
        let _ = header;
        self.camera_gps_request(ctx, request);
        false
    }
}

impl MavlinkSide {
    /// The device's frame header for `comp` (its next sequence number).
    fn header(&mut self, comp: Comp) -> Option<Header> {
        let system_id = self.sysid?;
        let slot = self.seq.get_mut(usize::from(comp == Comp::Camera))?;
        let sequence = *slot;
        *slot = slot.wrapping_add(1);
        Some(Header {
            sequence,
            system_id,
            component_id: comp.id(),
        })
    }

    /// Encodes `msg` from `comp` and queues it for the FC.
    fn send(&mut self, ctx: &mut Ctx<'_>, comp: Comp, msg: &MavMessage) {
        let Some(header) = self.header(comp) else {
            return;
        };
        let mut buf = [0u8; MAX_FRAME_LEN];
        if let Ok(n) = mavlink::encode(msg, &header, &mut buf) {
            ctx.reply(buf.get(..n).unwrap_or_default());
        }
    }

    /// COMMAND_ACK from `comp` to the sender of `c` (built from its bytes, so that a
    /// MAV_CMD value the dialect does not list is answered too).
    fn ack(&mut self, ctx: &mut Ctx<'_>, comp: Comp, command: u16, result: u8, to: Header) {
        let Some(header) = self.header(comp) else {
            return;
        };
        let [c0, c1] = command.to_le_bytes();
        let payload = [c0, c1, result, 0, 0, 0, 0, 0, to.system_id, to.component_id];
        // MAVLink 2 drops trailing zero bytes (one byte stays).
        let n = payload
            .iter()
            .rposition(|b| *b != 0)
            .map_or(1, |i| i.saturating_add(1));
        let message = Message::Raw(Raw {
            id: id::COMMAND_ACK,
            payload: payload.get(..n).unwrap_or_default(),
        });
        let mut buf = [0u8; MAX_FRAME_LEN];
        if let Ok(n) = Packet::new(header, message).emit(&mut buf) {
            ctx.reply(buf.get(..n).unwrap_or_default());
        }
    }

    fn heartbeat(&mut self, ctx: &mut Ctx<'_>, comp: Comp) {
        let mavtype = match comp {
            Comp::Gimbal => MavType::MAV_TYPE_GIMBAL,
            Comp::Camera => MavType::MAV_TYPE_CAMERA,
        };
        let hb = MavMessage::HEARTBEAT(HEARTBEAT_DATA {
            custom_mode: 0,
            mavtype,
            autopilot: MavAutopilot::MAV_AUTOPILOT_INVALID,
            base_mode: MavModeFlag::empty(),
            system_status: MavState::MAV_STATE_ACTIVE,
            mavlink_version: 3,
        });
        self.send(ctx, comp, &hb);
    }

    /// The sender is the autopilot.
    fn is_autopilot(&self, h: Header) -> bool {
        h.component_id == AUTOPILOT && self.sysid == Some(h.system_id)
    }

    /// A message addressed to `comp` of this device, or broadcast.
    fn addressed(&self, target_system: u8, target_component: u8, comp: Comp) -> bool {
        (target_system == 0 || self.sysid == Some(target_system))
            && (target_component == 0 || target_component == comp.id())
    }

    fn message(&mut self, ctx: &mut Ctx<'_>, h: Header, m: MavMessage) {
        let autopilot = self.is_autopilot(h);
        match m {
            MavMessage::HEARTBEAT(hb) => self.autopilot_heartbeat(ctx, h, &hb),
            MavMessage::GIMBAL_DEVICE_SET_ATTITUDE(s) => self.set_attitude(ctx, &s),
            MavMessage::TIMESYNC(t) => self.timesync(ctx, h, &t),
            MavMessage::SYSTEM_TIME(t) if autopilot => {
                self.stream_seen(ctx, stream::SYSTEM_TIME);
                let s = Sample::new(ctx.now, t.time_unix_usec, 1).with_transit(ctx.transit);
                ctx.time.utc_sample(s);
            }
            MavMessage::GPS_RAW_INT(g) if autopilot => {
                self.stream_seen(ctx, stream::GPS_RAW_INT);
                self.gps_raw(ctx, &g);
            }
            MavMessage::GLOBAL_POSITION_INT(p) if autopilot => {
                self.stream_seen(ctx, stream::GLOBAL_POSITION_INT);
                self.position(ctx, &p);
            }
            MavMessage::ATTITUDE(a) if autopilot => {
                self.stream_seen(ctx, stream::ATTITUDE);
                let c = |r: f32| math::cdeg(r).unwrap_or(0);
                let yaw_rate = math::cdeg(a.yawspeed);
                self.vehicle_attitude(ctx, [c(a.roll), c(a.pitch), c(a.yaw)], yaw_rate);
            }
            MavMessage::AUTOPILOT_STATE_FOR_GIMBAL_DEVICE(s) if autopilot => {
                if let Some(e) = math::euler(s.q) {
                    let e = e.map(|r| math::cdeg(r).unwrap_or(0));
                    let rate = math::cdeg(s.angular_velocity_z);
                    self.vehicle_attitude(ctx, e, rate);
                }
            }
            _ => ctx.ignored(),
        }
    }

    /// The autopilot's HEARTBEAT gives the device its system id. GCS, gimbal and camera
    /// heartbeats (routed onto this link) do not.
    fn autopilot_heartbeat(&mut self, ctx: &mut Ctx<'_>, h: Header, hb: &HEARTBEAT_DATA) {
        let autopilot = h.component_id == AUTOPILOT
            && hb.autopilot != MavAutopilot::MAV_AUTOPILOT_INVALID
            && !matches!(
                hb.mavtype,
                MavType::MAV_TYPE_GCS | MavType::MAV_TYPE_GIMBAL | MavType::MAV_TYPE_CAMERA
            );
        if !autopilot {
            ctx.ignored();
            return;
        }
        if self.sysid != Some(h.system_id) {
            self.sysid = Some(h.system_id);
            // Introduce both components now, and ask for the streams.
            self.next_heartbeat = ctx.now;
            self.next_status = ctx.now;
            for s in &mut self.streams {
                s.tries = 0;
                s.next_try = ctx.now;
            }
        }
    }

    fn stream_seen(&mut self, ctx: &Ctx<'_>, id: u8) {
        if let Some(s) = self.streams.iter_mut().find(|s| s.id == id) {
            s.last = Some(ctx.now);
            s.tries = 0;
        }
    }

    /// When `s` is next asked for (stale: at its retry instant).
    fn stream_due(s: &Stream) -> Instant {
        match s.last {
            Some(last) => s.next_try.max(last.saturating_add(STREAM_STALE)),
            None => s.next_try,
        }
    }

    /// MAV_CMD_SET_MESSAGE_INTERVAL to the autopilot for every stream that is not coming.
    fn request_streams(&mut self, ctx: &mut Ctx<'_>) {
        for i in 0..self.streams.len() {
            let Some(s) = self.streams.get(i).copied() else {
                continue;
            };
            if ctx.now < Self::stream_due(&s) {
                continue;
            }
            let wait = if s.tries < STREAM_QUICK_TRIES {
                Duration::from_secs(1)
            } else {
                STREAM_BACKOFF
            };
            if let Some(slot) = self.streams.get_mut(i) {
                slot.tries = slot.tries.saturating_add(1);
                slot.next_try = ctx.now.saturating_add(wait);
            }
            self.command_autopilot(
                ctx,
                cmd::SET_MESSAGE_INTERVAL,
                [id_f32(u32::from(s.id)), id_f32(s.interval_us)],
                s.tries,
            );
        }
    }

    /// A COMMAND_LONG from the gimbal component to the autopilot.
    fn command_autopilot(&mut self, ctx: &mut Ctx<'_>, command: u16, p: [f32; 2], tries: u8) {
        let Some(sysid) = self.sysid else {
            return;
        };
        let Some(header) = self.header(Comp::Gimbal) else {
            return;
        };
        // COMMAND_LONG: param1..7, command, target system and component, confirmation.
        let mut payload = [0u8; 33];
        for (d, s) in payload
            .iter_mut()
            .zip(p[0].to_le_bytes().into_iter().chain(p[1].to_le_bytes()))
        {
            *d = s;
        }
        let [c0, c1] = command.to_le_bytes();
        for (d, s) in payload
            .iter_mut()
            .skip(28)
            .zip([c0, c1, sysid, AUTOPILOT, tries])
        {
            *d = s;
        }
        let n = payload
            .iter()
            .rposition(|b| *b != 0)
            .map_or(1, |i| i.saturating_add(1));
        let message = Message::Raw(Raw {
            id: 76,
            payload: payload.get(..n).unwrap_or_default(),
        });
        let mut buf = [0u8; MAX_FRAME_LEN];
        if let Ok(n) = Packet::new(header, message).emit(&mut buf) {
            ctx.reply(buf.get(..n).unwrap_or_default());
        }
    }

    fn gps_raw(&mut self, ctx: &Ctx<'_>, g: &GPS_RAW_INT_DATA) {
        let fixed = matches!(
            g.fix_type,
            GpsFixType::GPS_FIX_TYPE_3D_FIX
                | GpsFixType::GPS_FIX_TYPE_DGPS
                | GpsFixType::GPS_FIX_TYPE_RTK_FLOAT
                | GpsFixType::GPS_FIX_TYPE_RTK_FIXED
                | GpsFixType::GPS_FIX_TYPE_STATIC
                | GpsFixType::GPS_FIX_TYPE_PPP
        );
        self.gps_fix_at = if fixed { Some(ctx.now) } else { None };
    }

    /// The aircraft's attitude now, when fresh.
    fn vehicle(&self, now: Instant) -> Option<Vehicle> {
        self.vehicle
            .filter(|v| now.saturating_duration_since(v.at) <= VEHICLE_FRESH)
    }

    fn vehicle_attitude(&mut self, ctx: &Ctx<'_>, [roll, pitch, yaw]: [i32; 3], rate: Option<i32>) {
        self.vehicle = Some(Vehicle {
            roll,
            pitch,
            yaw: math::wrap_cdeg(yaw),
            yaw_rate: rate,
            at: ctx.now.saturating_sub(ctx.transit),
        });
    }

    /// A GLOBAL_POSITION_INT becomes a fix while the GPS has a 3D fix.
    fn position(&mut self, ctx: &mut Ctx<'_>, p: &mavlink::dialect::GLOBAL_POSITION_INT_DATA) {
        let fixed = self
            .gps_fix_at
            .is_some_and(|t| ctx.now.saturating_duration_since(t) <= GPS_FRESH);
        if !fixed {
            return;
        }
        let attitude = self.vehicle(ctx.now).map(|v| [v.roll, v.pitch, v.yaw]);
        let [roll, pitch, yaw] = attitude.unwrap_or_else(|| {
            // The heading only (UINT16_MAX: unknown).
            let hdg = if p.hdg == u16::MAX {
                0
            } else {
                math::wrap_cdeg(i32::from(p.hdg))
            };
            [0, 0, hdg]
        });
        let dm = |mm: i32| clamp_i16(mm / 100);
        ctx.fixes.push(Fix {
            at: ctx.now.saturating_sub(ctx.transit),
            lat_e7: p.lat,
            lon_e7: p.lon,
            alt_msl_dm: dm(p.alt),
            rel_alt_dm: dm(p.relative_alt),
            yaw_cdeg: clamp_i16(yaw),
            roll_cdeg: clamp_i16(roll),
            pitch_cdeg: clamp_i16(pitch),
            velocity: Some(Velocity::from_cm_s(
                i32::from(p.vx),
                i32::from(p.vy),
                i32::from(p.vz),
            )),
        });
        // A photo waiting for the fix after its instant has it now.
        self.finish_shots(ctx);
    }

    /// Answers a TIMESYNC request (tc1 = 0) with the bridge's clock in ns.
    fn timesync(&mut self, ctx: &mut Ctx<'_>, h: Header, t: &TIMESYNC_DATA) {
        if t.tc1 != 0 || !self.addressed(t.target_system, t.target_component, Comp::Gimbal) {
            ctx.ignored();
            return;
        }
        let now_ns = i64::try_from(ctx.now.as_micros())
            .unwrap_or(i64::MAX)
            .saturating_mul(1000);
        let reply = MavMessage::TIMESYNC(TIMESYNC_DATA {
            tc1: now_ns.max(1),
            ts1: t.ts1,
            target_system: h.system_id,
            target_component: h.component_id,
        });
        self.send(ctx, Comp::Gimbal, &reply);
    }

    /// A command from COMMAND_LONG or COMMAND_INT (see the module documentation).
    fn command(&mut self, ctx: &mut Ctx<'_>, c: &Cmd) {
        let system = c.target_system == 0 || self.sysid == Some(c.target_system);
        let to = Comp::of(c.target_component);
        if !system || (to.is_none() && c.target_component != 0) || self.sysid.is_none() {
            // Someone else's.
            ctx.ignored();
            return;
        }
        let handled = match c.command {
            cmd::REQUEST_MESSAGE => self.request_message(ctx, c, to),
            cmd::REQUEST_CAMERA_INFORMATION => {
                self.camera_request(ctx, c, to, id::CAMERA_INFORMATION)
            }
            cmd::REQUEST_CAMERA_SETTINGS => self.camera_request(ctx, c, to, id::CAMERA_SETTINGS),
            cmd::REQUEST_STORAGE_INFORMATION => {
                self.camera_request(ctx, c, to, id::STORAGE_INFORMATION)
            }
            cmd::REQUEST_CAMERA_CAPTURE_STATUS => {
                self.camera_request(ctx, c, to, id::CAMERA_CAPTURE_STATUS)
            }
            cmd::REQUEST_CAMERA_IMAGE_CAPTURE => {
                self.camera_request(ctx, c, to, id::CAMERA_IMAGE_CAPTURED)
            }
            _ if to != Some(Comp::Gimbal) && camera::is_camera_command(c.command) => {
                self.camera_command(ctx, c);
                true
            }
            _ => false,
        };
        if !handled {
            match to {
                // Addressed to a component that cannot serve it: say so.
                Some(comp) => self.ack(ctx, comp, c.command, result::UNSUPPORTED, c.from),
                // Broadcast, and neither component serves it: not for this device.
                None => ctx.ignored(),
            }
        }
    }

    /// MAV_CMD_REQUEST_MESSAGE: the ACK, then the message, from the component that owns
    /// it. Returns false when the addressed component (or, broadcast, neither) cannot.
    fn request_message(&mut self, ctx: &mut Ctx<'_>, c: &Cmd, to: Option<Comp>) -> bool {
        let Some(msg) = param_id(c.param(1)) else {
            return false;
        };
        let owner = match msg {
            id::HEARTBEAT => to.or(Some(Comp::Gimbal)),
            id::GIMBAL_DEVICE_INFORMATION | id::GIMBAL_DEVICE_ATTITUDE_STATUS => Some(Comp::Gimbal),
            id::CAMERA_INFORMATION
            | id::CAMERA_SETTINGS
            | id::STORAGE_INFORMATION
            | id::CAMERA_CAPTURE_STATUS
            | id::CAMERA_IMAGE_CAPTURED => Some(Comp::Camera),
            _ => None,
        };
        let Some(owner) = owner.filter(|o| to.is_none_or(|t| t == *o)) else {
            return false;
        };
        match msg {
            id::HEARTBEAT => {
                self.ack(ctx, owner, c.command, result::ACCEPTED, c.from);
                self.heartbeat(ctx, owner);
            }
            id::GIMBAL_DEVICE_INFORMATION => self.serve_device_information(ctx, c),
            id::GIMBAL_DEVICE_ATTITUDE_STATUS => {
                self.ack(ctx, owner, c.command, result::ACCEPTED, c.from);
                self.attitude_status(ctx);
            }
            other => {
                self.camera_request(ctx, c, to, other);
            }
        }
        true
    }

    /// The pod has reported long enough for its versions to be known (they are asked at
    /// every reconnection), or has told them.
    fn pod_identified(&self, ctx: &Ctx<'_>, version_known: bool) -> bool {
        ctx.pod().link
            && (version_known
                || self.pod_up_since.is_some_and(|t| {
                    ctx.now.saturating_duration_since(t) >= Duration::from_secs(1)
                }))
    }
}

/// A message id or interval as a command parameter.
#[allow(clippy::cast_precision_loss)] // ids and intervals below 2^24 are exact
fn id_f32(v: u32) -> f32 {
    v as f32
}

/// A message id from a command parameter (a whole, non-negative number).
#[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // checked range
fn param_id(p: f32) -> Option<u32> {
    (0.0..16_777_216.0).contains(&p).then_some(p as u32)
}
