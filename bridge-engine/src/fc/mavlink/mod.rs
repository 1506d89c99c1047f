//! The MAVLink side: the bridge is a MAVLink 2 gimbal device (component 154) and camera
//! (component 100) towards ArduPilot (`MNT1_TYPE` 6, `CAM1_TYPE` 6), PX4 (gimbal v2
//! output) and, through their routing, QGroundControl (the mapping table:
//! docs/src/bridge/mavlink.md; what each of them sends and reads:
//! docs/src/autopilots/ardupilot.md, docs/src/autopilots/px4.md,
//! docs/src/autopilots/qgroundcontrol.md).
//!
//! - **Identity.** Both components send HEARTBEAT at 1 Hz (type 26 GIMBAL and 30 CAMERA,
//!   autopilot INVALID) with the system id of the autopilot, learnt from its own
//!   HEARTBEAT (component 1) and then pinned (`autopilot_sysid`, `autopilot_forget_ms`:
//!   another autopilot's heartbeat changes nothing); nothing is sent before it is heard.
//!   Each component numbers its frames itself.
//! - **The gate.** Every message that changes something ([`GATED`](crate::access::GATED):
//!   commands, GIMBAL_DEVICE_SET_ATTITUDE, PARAM_EXT_SET, PARAM_SET, FTP writes,
//!   SETUP_SIGNING) passes the sender and signing rules before any handler reads it
//!   (docs/src/security.md, "The gate").
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
//!   document's 0x000012), the bridge's version as its firmware and the pod's gimbal
//!   hardware version.
//! - **Version**: each component answers MAV_CMD_REQUEST_MESSAGE(AUTOPILOT_VERSION) and
//!   MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES addressed to it (not broadcast: the
//!   autopilot answers those) with AUTOPILOT_VERSION: the bridge's version and commit
//!   ([`version`]).
//! - **Camera** ([`camera`]): photos (single and interval), video, zoom, focus and mode
//!   reach the pod; their ACK waits for the pod's; CAMERA_IMAGE_CAPTURED follows each
//!   photo with the position the pod was given for its geotag.
//! - **Time and position** ([`autopilot`], shared with the telemetry link). Copter
//!   streams nothing to a new port, PX4's gimbal mode no position or time: the gimbal
//!   asks the autopilot with MAV_CMD_SET_MESSAGE_INTERVAL for SYSTEM_TIME,
//!   GLOBAL_POSITION_INT, ATTITUDE (10 Hz) and GPS_RAW_INT (2 Hz), again whenever one
//!   stops (an autopilot reboot forgets them), once a second for the first tries, then
//!   every 10 s. UTC comes from TIMESYNC (the bridge asks, 3 to 7 times a second) and
//!   SYSTEM_TIME (ArduPilot sends 0 until its clock is set: no time);
//!   GLOBAL_POSITION_INT is a fix while GPS_RAW_INT reports a 3D fix (ArduPilot sends
//!   positions without one), with the aircraft's attitude from ATTITUDE or
//!   AUTOPILOT_STATE_FOR_GIMBAL_DEVICE, whose yaw also turns earth-frame gimbal yaw into
//!   the pod's vehicle-relative yaw. TIMESYNC requests (ArduPilot's every 10 s) are
//!   answered with the bridge's clock in ns.

mod autopilot;
mod bridge_params;
mod camera;
mod capture;
#[cfg(test)]
mod definition_tests;
mod destructive;
mod fov;
mod ftp;
mod gimbal;
mod intervals;
mod params;
mod roi;
mod sensors;
mod settings;
mod signing;
#[cfg(feature = "telemetry")]
mod telemetry;
mod tracking;
mod version;
mod video;

pub(crate) use signing::LinkSigning;
#[cfg(feature = "telemetry")]
pub(crate) use telemetry::TelemetrySide;

use crate::access::Refusal;
use crate::pod::PodNotice;
use crate::time::{Duration, Instant};
use protocol_core::k40t::{GpsRequest, Header as PodHeader};
use protocol_core::mavlink::dialect::{
    HEARTBEAT_DATA, MavAutopilot, MavModeFlag, MavState, MavType,
};
use protocol_core::mavlink::{
    DEFRAMER_LEN, Frame, Header, MavMessage, MavlinkFraming, Message, Packet,
};

use autopilot::{Autopilot, Heartbeat, Took, Vehicle};

use super::{Ctx, FcHandler, TimedFrom, geo, math};

/// Deframer buffer: what judges a frame of an unknown id on every byte that can decide
/// it (`MavlinkFraming`): the frame, a frame starting inside it and the byte after.
pub(crate) const BUF: usize = DEFRAMER_LEN;

/// HEARTBEAT period of each component.
const HEARTBEAT_PERIOD: Duration = Duration::from_secs(1);

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
    pub(super) const REQUEST_MESSAGE: u16 = 512;
    pub(super) const REQUEST_CAMERA_INFORMATION: u16 = 521;
    pub(super) const REQUEST_CAMERA_SETTINGS: u16 = 522;
    pub(super) const REQUEST_STORAGE_INFORMATION: u16 = 525;
    pub(super) const REQUEST_CAMERA_CAPTURE_STATUS: u16 = 527;
    pub(super) const STORAGE_FORMAT: u16 = 526;
    pub(super) const RESET_CAMERA_SETTINGS: u16 = 529;
    pub(super) const SET_CAMERA_MODE: u16 = 530;
    pub(super) const SET_CAMERA_ZOOM: u16 = 531;
    pub(super) const SET_CAMERA_FOCUS: u16 = 532;
    pub(super) const IMAGE_START_CAPTURE: u16 = 2000;
    pub(super) const IMAGE_STOP_CAPTURE: u16 = 2001;
    pub(super) const REQUEST_CAMERA_IMAGE_CAPTURE: u16 = 2002;
    pub(super) const VIDEO_START_CAPTURE: u16 = 2500;
    pub(super) const VIDEO_STOP_CAPTURE: u16 = 2501;
    pub(super) const DO_SET_ROI_LOCATION: u16 = 195;
    pub(super) const DO_SET_ROI_NONE: u16 = 197;
    pub(super) const SET_MESSAGE_INTERVAL: u16 = 511;
    pub(super) const SET_CAMERA_SOURCE: u16 = 534;
    pub(super) const CAMERA_TRACK_POINT: u16 = 2004;
    pub(super) const CAMERA_TRACK_RECTANGLE: u16 = 2005;
    pub(super) const CAMERA_STOP_TRACKING: u16 = 2010;
    pub(super) const VIDEO_START_STREAMING: u16 = 2502;
    pub(super) const VIDEO_STOP_STREAMING: u16 = 2503;
    pub(super) const REQUEST_VIDEO_STREAM_INFORMATION: u16 = 2504;
    pub(super) const REQUEST_VIDEO_STREAM_STATUS: u16 = 2505;
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
    pub(super) const DISTANCE_SENSOR: u32 = 132;
    pub(super) const VIDEO_STREAM_INFORMATION: u32 = 269;
    pub(super) const VIDEO_STREAM_STATUS: u32 = 270;
    pub(super) const CAMERA_FOV_STATUS: u32 = 271;
    pub(super) const CAMERA_TRACKING_IMAGE_STATUS: u32 = 275;
    pub(super) const CAMERA_THERMAL_RANGE: u32 = 277;
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

/// A command, from COMMAND_LONG or COMMAND_INT (any MAV_CMD value, known or not).
#[derive(Debug, Clone, Copy)]
struct Cmd {
    command: u16,
    /// param1..param7 (COMMAND_INT: x and y as numbers).
    params: [f32; 7],
    target_system: u8,
    target_component: u8,
    /// COMMAND_INT's x and y as sent (e.g. latitude and longitude, degE7) and its frame.
    int: Option<(i32, i32, u8)>,
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

    /// The requested message's own parameter (a stream id, a storage id, an image
    /// index): param2 of REQUEST_MESSAGE, param1 of the older REQUEST_* commands.
    fn message_param(&self) -> f32 {
        if self.command == cmd::REQUEST_MESSAGE {
            self.param(2)
        } else {
            self.param(1)
        }
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
        let [frame, ..] = word(32);
        let int = (msg_id == 75).then(|| {
            (
                i32::from_le_bytes(word(16)),
                i32::from_le_bytes(word(20)),
                frame,
            )
        });
        (msg_id == 75 || msg_id == 76).then_some(Cmd {
            command: u16::from_le_bytes([c0, c1]),
            params,
            target_system: ts,
            target_component: tc,
            int,
            from,
        })
    }
}

/// The MAVLink side (its link, deframer and bursts, is [`FcLink`](super::FcLink)).
#[derive(Debug, Clone)]
pub(crate) struct MavlinkSide {
    /// The autopilot (the gimbal component talks to it).
    ap: Autopilot,
    next_heartbeat: Instant,
    next_status: Instant,
    /// The pod's reports came back at this instant (versions are asked then).
    pod_up_since: Option<Instant>,
    gimbal: gimbal::Gimbal,
    camera: camera::Camera,
    /// The camera definition's FTP server.
    ftp: ftp::Ftp,
    /// The camera's settings as extended parameters.
    params: params::Params,
    /// Storage format and camera reset.
    destructive: destructive::Destructive,
    video: video::Video,
    sensors: sensors::Sensors,
    tracking: tracking::Tracking,
    roi: roi::Roi,
    /// The bridge's settings as parameters of the gimbal's component.
    bridge_params: bridge_params::BridgeParams,
}

impl MavlinkSide {
    pub(crate) fn new(config: &crate::Config) -> Self {
        MavlinkSide {
            ap: Autopilot::new(Comp::Gimbal.id(), config),
            next_heartbeat: Instant::ZERO,
            next_status: Instant::ZERO,
            pod_up_since: None,
            gimbal: gimbal::Gimbal::default(),
            camera: camera::Camera::default(),
            ftp: ftp::Ftp::default(),
            params: params::Params::default(),
            destructive: destructive::Destructive::default(),
            video: video::Video::default(),
            sensors: sensors::Sensors::default(),
            tracking: tracking::Tracking::default(),
            roi: roi::Roi::default(),
            bridge_params: bridge_params::BridgeParams::default(),
        }
    }
}

impl MavlinkSide {
    /// The link's signing (the engine saves and restores its timestamp and key).
    pub(crate) fn signing(&mut self) -> &mut LinkSigning {
        &mut self.ap.signing
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
        let Some(signed) = self.ap.admit(ctx, f) else {
            return;
        };
        let header = Header {
            sequence: frame.sequence(),
            system_id: frame.system_id(),
            component_id: frame.component_id(),
        };
        // Everything that changes something passes the gate first, before any handler
        // reads it (docs/src/security.md, "The gate").
        let components = [Comp::Gimbal.id(), Comp::Camera.id()];
        if let Some(refusal) = self.ap.gate(ctx, &frame, signed, &components) {
            self.gate_refused(ctx, &frame, header, refusal);
            return;
        }
        // Commands are read from their bytes: any MAV_CMD value, known to the dialect or
        // not, is answered.
        if let Some(c) = Cmd::from_payload(frame.message_id(), frame.payload_ref(), header) {
            self.command(ctx, &c);
            return;
        }
        // So are FTP and parameter requests (any opcode, any parameter type).
        match frame.message_id() {
            ftp::ID if self.ap.sysid.is_some() => {
                self.ftp_request(ctx, header, frame.payload_ref());
                return;
            }
            id @ (params::REQUEST_READ | params::REQUEST_LIST | params::SET)
                if self.ap.sysid.is_some() =>
            {
                self.param_request(ctx, header, id, frame.payload_ref());
                return;
            }
            // The bridge's own parameters, on the gimbal's component.
            id @ (bridge_params::REQUEST_READ
            | bridge_params::REQUEST_LIST
            | bridge_params::SET)
                if self.ap.sysid.is_some() =>
            {
                let own = Comp::Gimbal.id();
                if !self
                    .bridge_params
                    .request(ctx, &mut self.ap, own, id, frame.payload_ref())
                {
                    ctx.ignored();
                }
                return;
            }
            _ => {}
        }
        match Packet::parse(&frame).map(|p| p.message) {
            Ok(Message::Known(MavMessage::SETUP_SIGNING(s))) => {
                if self.ap.setup_signing(ctx, header, &s, signed) == Took::No {
                    ctx.ignored();
                }
            }
            Ok(Message::Known(m)) => self.message(ctx, header, m),
            _ => ctx.ignored(),
        }
    }

    fn poll(&mut self, ctx: &mut Ctx<'_>) {
        if self.ap.sysid.is_some() {
            if ctx.now >= self.next_heartbeat {
                self.next_heartbeat = ctx.now.saturating_add(HEARTBEAT_PERIOD);
                self.heartbeat(ctx, Comp::Gimbal);
                self.heartbeat(ctx, Comp::Camera);
            }
            if ctx.now >= self.next_status {
                self.next_status = ctx.now.saturating_add(gimbal::STATUS_PERIOD);
                self.attitude_status(ctx);
                self.roi_refresh(ctx);
            }
            self.ap.poll(ctx);
            self.params_poll(ctx);
            self.bridge_params
                .poll(ctx, &mut self.ap, Comp::Gimbal.id());
            self.ftp_poll(ctx);
            self.sensors_poll(ctx);
        }
        self.camera_poll(ctx);
        self.destructive_poll(ctx);
    }

    fn poll_at(&self) -> Option<Instant> {
        let device = self
            .ap
            .sysid
            .map(|_| self.next_heartbeat.min(self.next_status));
        let sensors = self.ap.sysid.and_then(|_| self.sensors_poll_at());
        [
            device,
            self.ap.poll_at(),
            self.camera.poll_at(),
            self.ap.sysid.and(self.params.poll_at()),
            self.ap.sysid.and(self.bridge_params.poll_at()),
            self.ap.sysid.and(self.ftp.poll_at()),
            self.destructive.poll_at(),
            sensors,
        ]
        .into_iter()
        .flatten()
        .min()
    }

    fn pod_notice(&mut self, ctx: &mut Ctx<'_>, notice: PodNotice) {
        match notice {
            PodNotice::LinkUp => {
                self.pod_up_since = Some(ctx.now);
                self.params_pod_up(ctx);
                self.sensors_link_up(ctx);
            }
            PodNotice::LinkDown => self.pod_up_since = None,
            PodNotice::Acked { base, code } => {
                let ok = code == protocol_core::k40t::AckCode::Ok;
                self.camera_pod_answer(ctx, base, ok);
                self.params_pod_answer(ctx, base, ok);
                self.destructive_pod_answer(ctx, base, ok);
                self.sensors_pod_answer(ctx, base, ok);
            }
            PodNotice::TimedOut { base } => {
                self.camera_pod_answer(ctx, base, false);
                self.params_pod_answer(ctx, base, false);
                self.destructive_pod_answer(ctx, base, false);
                self.sensors_pod_answer(ctx, base, false);
            }
            PodNotice::Photo(state) => self.capture_photo_status(ctx, state),
            PodNotice::GpsRequest { .. } => {}
        }
    }

    /// Every pod frame: new readings (laser, tracking's end) are reported at once.
    fn pod_frame(&mut self, ctx: &mut Ctx<'_>, frame: super::PodFrame<'_>) {
        let _ = frame;
        if self.ap.sysid.is_some() {
            self.sensors_frame(ctx);
        }
    }

    /// The pod asks where a photo was taken: noted for the photo's CAMERA_IMAGE_CAPTURED;
    /// the engine answers it from the fix history.
    fn gps_request(&mut self, ctx: &mut Ctx<'_>, header: PodHeader, request: GpsRequest) -> bool {
        let _ = header;
        self.capture_gps_request(ctx, request);
        false
    }
}

impl MavlinkSide {
    /// COMMAND_ACK from `comp` to the sender of `c` (built from its bytes, so that a
    /// MAV_CMD value the dialect does not list is answered too).
    fn ack(&mut self, ctx: &mut Ctx<'_>, comp: Comp, command: u16, result: u8, to: Header) {
        ack(&mut self.ap, ctx, comp.id(), command, result, to);
    }

    /// Encodes `msg` from `comp` and queues it for the FC.
    fn send(&mut self, ctx: &mut Ctx<'_>, comp: Comp, msg: &MavMessage) {
        self.ap.send(ctx, comp.id(), msg);
    }

    /// The aircraft's attitude now, when fresh.
    fn vehicle(&self, now: Instant) -> Option<Vehicle> {
        self.ap.vehicle(now)
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

    /// A message addressed to `comp` of this device, or broadcast.
    fn addressed(&self, target_system: u8, target_component: u8, comp: Comp) -> bool {
        self.ap
            .addressed(target_system, target_component, comp.id())
    }

    fn message(&mut self, ctx: &mut Ctx<'_>, h: Header, m: MavMessage) {
        match m {
            MavMessage::HEARTBEAT(hb) => match self.ap.heartbeat(ctx, h, &hb) {
                // Introduce both components now.
                Heartbeat::New => {
                    self.next_heartbeat = ctx.now;
                    self.next_status = ctx.now;
                }
                Heartbeat::Known | Heartbeat::Other => {}
                Heartbeat::NotAutopilot => ctx.ignored(),
            },
            // Past the gate: from an allowed sender.
            MavMessage::GIMBAL_DEVICE_SET_ATTITUDE(s) => self.set_attitude(ctx, &s),
            m => match self.ap.message(ctx, h, &m) {
                Took::No => ctx.ignored(),
                Took::Yes => {}
                // A photo waiting for the fix after its instant has it now.
                Took::Fix => self.finish_shots(ctx),
            },
        }
    }

    /// A message the gate refused: a command from a sender that may not command, naming
    /// a component of this device, is answered DENIED (the rest is not answered).
    fn gate_refused(
        &mut self,
        ctx: &mut Ctx<'_>,
        frame: &Frame<&[u8]>,
        h: Header,
        refusal: Refusal,
    ) {
        let cmd = Cmd::from_payload(frame.message_id(), frame.payload_ref(), h);
        if let Some(c) = cmd.filter(|_| refusal == Refusal::Sender)
            && let Some(comp) = Comp::of(c.target_component)
        {
            self.ack(ctx, comp, c.command, result::DENIED, c.from);
        }
    }

    /// A command from COMMAND_LONG or COMMAND_INT (see the module documentation), past
    /// the gate.
    fn command(&mut self, ctx: &mut Ctx<'_>, c: &Cmd) {
        let system = c.target_system == 0 || self.ap.sysid == Some(c.target_system);
        let to = Comp::of(c.target_component);
        if !system || (to.is_none() && c.target_component != 0) || self.ap.sysid.is_none() {
            // Someone else's.
            ctx.ignored();
            return;
        }
        let handled = match c.command {
            // Either component's version, when addressed to it (broadcast: the autopilot's).
            _ if version::asks_version(c) => to.is_some_and(|comp| {
                self.serve_version(ctx, c, comp);
                true
            }),
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
            cmd::REQUEST_VIDEO_STREAM_INFORMATION => {
                self.sensor_request(ctx, c, to, id::VIDEO_STREAM_INFORMATION)
            }
            cmd::REQUEST_VIDEO_STREAM_STATUS => {
                self.sensor_request(ctx, c, to, id::VIDEO_STREAM_STATUS)
            }
            cmd::SET_MESSAGE_INTERVAL => self.set_interval(ctx, c, to),
            cmd::DO_SET_ROI_LOCATION | cmd::DO_SET_ROI_NONE if to == Some(Comp::Gimbal) => {
                self.roi_command(ctx, c);
                true
            }
            _ if to != Some(Comp::Gimbal) && sensors::is_sensor_command(c.command) => {
                self.sensor_command(ctx, c);
                true
            }
            _ if to != Some(Comp::Gimbal) && camera::is_camera_command(c.command) => {
                self.camera_command(ctx, c);
                true
            }
            cmd::STORAGE_FORMAT | cmd::RESET_CAMERA_SETTINGS if to != Some(Comp::Gimbal) => {
                self.destructive_command(ctx, c);
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
            m if sensors::is_sensor_message(m) => Some(Comp::Camera),
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
            m if sensors::is_sensor_message(m) => {
                self.sensor_request(ctx, c, to, m);
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

/// COMMAND_ACK from component `comp` (an id) to the sender `to`, built from its bytes so
/// that a MAV_CMD value the dialect does not list is answered too.
fn ack(ap: &mut Autopilot, ctx: &mut Ctx<'_>, comp: u8, command: u16, result: u8, to: Header) {
    let [c0, c1] = command.to_le_bytes();
    let payload = [c0, c1, result, 0, 0, 0, 0, 0, to.system_id, to.component_id];
    ap.send_raw(ctx, comp, id::COMMAND_ACK, &payload);
}

/// The parameter is the whole number `v` (to the nearest).
pub(super) fn param_is(p: f32, v: u8) -> bool {
    let d = p - f32::from(v);
    d > -0.5 && d < 0.5
}

/// A message id from a command parameter (a whole, non-negative number).
#[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // checked range
fn param_id(p: f32) -> Option<u32> {
    (0.0..16_777_216.0).contains(&p).then_some(p as u32)
}
