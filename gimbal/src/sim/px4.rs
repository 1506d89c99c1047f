//! A simulated PX4 with the gimbal v2 output (`MNT_MODE_OUT` 2) on a MAVLink port in mode
//! Gimbal (10), Normal (0) or Onboard (2), as docs/src/autopilots/px4.md describes what
//! PX4 sends and reads:
//!
//! - HEARTBEAT (QUADROTOR, autopilot PX4) at 1 Hz.
//! - **Discovery**: COMMAND_LONG REQUEST_MESSAGE(GIMBAL_DEVICE_INFORMATION) to 0/0 every
//!   second until any information arrives; the gimbal's component id is the source of
//!   that message; pitch and yaw limits are copied from it (roll is not).
//! - **GIMBAL_DEVICE_SET_ATTITUDE**, 20 Hz in mode Gimbal, 5 Hz in Normal, re-sending
//!   the last setpoint: target = this system and the discovered component (before
//!   discovery: [`Px4Config::initial_target_component`], the code's initial value being
//!   unconfirmed); the quaternion of the angle setpoint, always finite (a rate input is
//!   integrated into it, within the copied limits) with the rate as angular velocity
//!   (NaN when pointing); ROLL_LOCK and PITCH_LOCK (absolute), YAW_LOCK for an
//!   absolute (earth-frame) yaw; YAW_IN_EARTH_FRAME is never set.
//! - **AUTOPILOT_STATE_FOR_GIMBAL_DEVICE** at 20 Hz in mode Gimbal only (targets 0,
//!   64-bit µs, landed state IN_AIR).
//! - **Streams of mode Normal**: GLOBAL_POSITION_INT and GPS_RAW_INT 5 Hz, ATTITUDE 15 Hz;
//!   mode Gimbal streams no position or time. SYSTEM_TIME is in neither. A
//!   MAV_CMD_SET_MESSAGE_INTERVAL is honoured when [`Px4Config::honours_interval`] (PX4's
//!   receiver supports it; not verified in mode Gimbal: the other reading answers
//!   UNSUPPORTED and streams nothing more).
//! - **Streams of mode Onboard**: TIMESYNC requests 10 Hz (tc1 0, ts1 boot ns),
//!   SYSTEM_TIME 1 Hz, GLOBAL_POSITION_INT 50 Hz, GPS_RAW_INT "unlimited" (here 10 Hz),
//!   ATTITUDE 100 Hz, GIMBAL_DEVICE_SET_ATTITUDE 5 Hz, no AUTOPILOT_STATE.
//! - **SYSTEM_TIME** is never sent while the clock is invalid
//!   ([`Px4Config::utc_valid_at_us`]); `time_unix_usec` and `time_boot_ms` (hrt / 1000)
//!   come from one reading.
//! - **TIMESYNC**: a request (tc1 0, target 0 or this system) is answered at once, in
//!   its own burst: tc1 = `hrt_absolute_time()` × 1000 read when the receive thread
//!   parses the frame, the frame's end arrival plus a latency uniform in
//!   `0..parse_latency_us`; ts1 echoed; target = the requester's system and component
//!   (PR #25949), or left unset by PX4 1.16 ([`Px4Config::timesync_targets`]). Every answer is recorded ([`Px4::timesync_answers`]); replies to this
//!   PX4's own requests are recorded too ([`Px4::timesync_replies`]).
//! - **Camera** (`TRIG_INTERFACE` 3): camera commands re-emitted as COMMAND_LONG to the
//!   camera ([`Px4Config::camera_target_component`]).
//! - **Forwarding** (`MAV_1_FORWARD` 1) to an attached ground station ([`Qgc`]), and
//!   to and from a ground app on another link ([`Px4::ground`], where PX4 is the gimbal
//!   manager: `manager.rs`); the ground station's commands to this autopilot (component
//!   1) are kept, not forwarded.
//! - **Gimbal manager inputs** from the ground station (MAVSDK's Gimbal plugin, QGC's
//!   controls): MAV_CMD_DO_GIMBAL_MANAGER_PITCHYAW (COMMAND_LONG: param1 pitch, param2
//!   yaw, param3/4 rates, param5 flags; COMMAND_INT: flags in x) becomes an angle
//!   setpoint (yaw absolute with GIMBAL_MANAGER_FLAGS_YAW_LOCK) or a rate input;
//!   MAV_CMD_DO_SET_ROI_LOCATION (COMMAND_INT, degE7, m) an angle setpoint PX4 computes
//!   itself from the aircraft's position every tick, yaw absolute (no ROI goes to the
//!   device); MAV_CMD_DO_SET_ROI_NONE ends it (the gimbal holds). ACKed ACCEPTED.
//! - **PX4 1.16 in mode Gimbal** ([`Px4Config::gimbal_link_only`]): the link handles
//!   only the gimbal messages: no answer to SET_MESSAGE_INTERVAL (not even an ACK) or to
//!   TIMESYNC, so a device there has neither time nor position.
//! - **SITL in lockstep** ([`Px4Config::sitl_lockstep`]), as a capture of PX4 v1.16 SITL
//!   shows it (`lockstep.rs`): the boot clock (`time_boot_ms`, TIMESYNC) is the
//!   simulation's, in 4 ms steps, 0.87 % slow against the host's clock with a wander of
//!   tens of ms ([`LockstepConfig`]); `time_unix_usec` is the host's clock (true time).
//!   The MAVLink threads run at every step, so the streams are scheduled on simulation
//!   time (SYSTEM_TIME's `time_boot_ms` advances by exactly 100 ms); TIMESYNC's `tc1`
//!   lags the streams' boot clock by one step; its reply fills only `tc1` and `ts1`
//!   (PX4 1.16: [`TimesyncTargets::Unset`]). Reboots are not simulated in this mode.
//! - **Health** (this simulator's own rule; PX4 has none found): the information came and
//!   an attitude status within the last second.

use std::collections::BTreeMap;

use protocol_core::mavlink::dialect::{
    ATTITUDE_DATA, AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA, COMMAND_ACK_DATA,
    GIMBAL_DEVICE_ATTITUDE_STATUS_DATA, GIMBAL_DEVICE_INFORMATION_DATA,
    GIMBAL_DEVICE_SET_ATTITUDE_DATA, GLOBAL_POSITION_INT_DATA, GPS_RAW_INT_DATA, GimbalDeviceFlags,
    GpsFixType, MavAutopilot, MavCmd, MavLandedState, MavResult, MavType, MessageData as _,
    SYSTEM_TIME_DATA, TIMESYNC_DATA,
};
use protocol_core::mavlink::{Header, MavMessage};

use super::board::{Autopilot, Board, MainLoop, board_field};
use super::describe::MavlinkFrames;
use super::ground::GroundLink;
use super::mav::{self, AUTOPILOT, AircraftState, Endpoint, Rx, TimesyncAnswer};
use super::pilot::Pilot;
use super::qgc::Qgc;
use super::{FcClock, XorShift};

mod lockstep;
mod manager;

pub use lockstep::{Lockstep, LockstepConfig};

/// The port's mode (`MAV_n_MODE`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Px4Mode {
    /// 10: Gimbal.
    Gimbal,
    /// 0: Normal.
    Normal,
    /// 2: Onboard.
    Onboard,
}

/// The target fields of PX4's TIMESYNC replies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimesyncTargets {
    /// The requester's system and component (PX4 since PR #25949, late 2025).
    Requester,
    /// Not filled (PX4 1.16 fills only `tc1` and `ts1`): what the memory held, here the
    /// values a real PX4 1.16 SITL sent, as often as it sent them (208/17 in 607 of 611
    /// replies; 17/0, 1/0 and 40/126 once or twice each).
    Unset,
}

/// Settings of the simulated PX4.
#[derive(Debug, Clone)]
pub struct Px4Config {
    /// Seed of the random jitter.
    pub seed: u64,
    /// Per-message transport jitter bound, µs.
    pub jitter_us: u64,
    /// Crystal error, ppm.
    pub ppm: f64,
    /// UTC at true time 0, µs.
    pub utc_at_zero_us: u64,
    /// Uptime at true time 0, µs.
    pub boot_us: u64,
    /// `MAV_SYS_ID`.
    pub sysid: u8,
    /// The port's mode.
    pub mode: Px4Mode,
    /// SET_MESSAGE_INTERVAL honoured on this port.
    pub honours_interval: bool,
    /// GIMBAL_DEVICE_SET_ATTITUDE's target component before discovery.
    pub initial_target_component: u8,
    /// Where re-emitted camera commands go (component).
    pub camera_target_component: u8,
    /// The clock (CLOCK_REALTIME) is valid from this true instant; no SYSTEM_TIME before.
    pub utc_valid_at_us: u64,
    /// Latency of the receive thread, from a frame's last byte to its parse: uniform in
    /// `0..parse_latency_us`.
    pub parse_latency_us: u64,
    /// The port's baud rate (places a frame's end inside a chunk the UART delivered).
    pub baud: u32,
    /// PX4 1.16's link in mode Gimbal: only the gimbal messages are handled (no answer
    /// to SET_MESSAGE_INTERVAL or TIMESYNC).
    pub gimbal_link_only: bool,
    /// SITL in lockstep: the boot clock is [`Px4Config::lockstep`]'s, UTC the host's (true
    /// time); [`Px4Config::ppm`] is not used.
    pub sitl_lockstep: bool,
    /// The lockstep clock of SITL.
    pub lockstep: LockstepConfig,
    /// The target fields of TIMESYNC replies.
    pub timesync_targets: TimesyncTargets,
}

impl Px4Config {
    /// PX4 1.16 with the port in mode Gimbal as its users run it: the link answers no
    /// SET_MESSAGE_INTERVAL and no TIMESYNC, and streams no time or position.
    #[must_use]
    pub fn px4_1_16_gimbal_mode() -> Self {
        Px4Config {
            mode: Px4Mode::Gimbal,
            gimbal_link_only: true,
            ..Px4Config::default()
        }
    }

    /// PX4 v1.16 SITL in lockstep with the port in mode Normal, as the capture shows it:
    /// its boot clock in 4 ms steps, 0.87 % slow against UTC (the host's clock) with a
    /// wander of tens of ms; TIMESYNC replies with unset targets; a pseudo-terminal's
    /// transport delays (the capture's: p50 144 µs, p99 814 µs).
    #[must_use]
    pub fn sitl_lockstep() -> Self {
        Px4Config {
            mode: Px4Mode::Normal,
            sitl_lockstep: true,
            timesync_targets: TimesyncTargets::Unset,
            jitter_us: 1_000,
            ..Px4Config::default()
        }
    }
}

impl Default for Px4Config {
    fn default() -> Self {
        Px4Config {
            seed: 1,
            jitter_us: 2_000,
            ppm: 0.0,
            utc_at_zero_us: 1_795_428_000_123_456,
            boot_us: 5_000_000,
            sysid: 1,
            mode: Px4Mode::Gimbal,
            honours_interval: true,
            initial_target_component: 0,
            camera_target_component: 100,
            utc_valid_at_us: 0,
            parse_latency_us: 300,
            baud: 115_200,
            gimbal_link_only: false,
            sitl_lockstep: false,
            lockstep: LockstepConfig::default(),
            timesync_targets: TimesyncTargets::Requester,
        }
    }
}

/// What the gimbal is told to do (PX4's gimbal input).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Px4Target {
    /// Angles, degrees; yaw absolute (from north) or relative.
    Angle {
        /// Pitch, positive up.
        pitch_deg: f64,
        /// Yaw.
        yaw_deg: f64,
        /// Yaw from north.
        yaw_absolute: bool,
    },
    /// Rates, deg/s (integrated into the angle setpoint).
    Rate {
        /// Pitch rate.
        pitch_dps: f64,
        /// Yaw rate.
        yaw_dps: f64,
    },
    /// A location (region of interest): latitude, longitude degE7, altitude m AMSL.
    Location {
        /// Latitude.
        lat_e7: i32,
        /// Longitude.
        lon_e7: i32,
        /// Altitude, m AMSL.
        alt_m: f64,
    },
}

/// The simulated PX4.
#[derive(Debug)]
pub struct Px4 {
    /// Settings.
    pub config: Px4Config,
    /// A ground station the port forwards to.
    pub gcs: Option<Qgc>,
    /// A ground app on another of PX4's links (PX4 is its gimbal manager).
    pub ground: Option<GroundLink>,
    manager: manager::Manager,
    board: Board,
    me: Endpoint,
    rx: Rx,
    /// Stream intervals (µs) by message id.
    pub intervals: BTreeMap<u32, u64>,
    next_due: BTreeMap<u32, u64>,
    last_heartbeat_us: Option<u64>,
    last_info_req_us: Option<u64>,
    /// The gimbal's component id (the source of GIMBAL_DEVICE_INFORMATION).
    pub gimbal_compid: Option<u8>,
    /// GIMBAL_DEVICE_INFORMATION.
    pub info: Option<GIMBAL_DEVICE_INFORMATION_DATA>,
    /// Pitch and yaw limits copied from it (degrees): pitch min, max, yaw min, max.
    pub limits: Option<[f64; 4]>,
    /// The gimbal input.
    pub target: Option<Px4Target>,
    /// The angle setpoint (pitch, yaw; degrees).
    setpoint: (f64, f64),
    last_integrate_us: u64,
    image_seq: u32,
    /// Every attitude status (forwarded to the ground station).
    pub statuses: Vec<(u64, Header, GIMBAL_DEVICE_ATTITUDE_STATUS_DATA)>,
    /// Every COMMAND_ACK received.
    pub acks: Vec<(u64, Header, COMMAND_ACK_DATA)>,
    /// GIMBAL_DEVICE_SET_ATTITUDE sent.
    pub set_attitudes: Vec<(u64, GIMBAL_DEVICE_SET_ATTITUDE_DATA)>,
    /// Every frame sent: (true µs, message).
    pub sent: Vec<(u64, MavMessage)>,
    /// Every frame received: (true µs, header, id).
    pub received: Vec<(u64, Header, u32)>,
    /// The TIMESYNC requests answered.
    pub timesync_answers: Vec<TimesyncAnswer>,
    /// Replies to this PX4's own TIMESYNC requests: (true time, tc1).
    pub timesync_replies: Vec<(u64, i64)>,
    /// ts1 of this PX4's latest own TIMESYNC requests.
    own_ts1: std::collections::VecDeque<i64>,
    /// SITL's lockstep clock.
    lockstep: Option<Lockstep>,
    /// SITL: the true time of the next lockstep step (a run of the MAVLink threads).
    next_step_us: u64,
}

impl Px4 {
    /// A PX4 that starts at true time 0.
    #[must_use]
    pub fn new(config: Px4Config) -> Self {
        let clock = FcClock::new(
            config.ppm,
            config.boot_us,
            config.utc_at_zero_us,
            config.utc_valid_at_us,
        );
        let mut p = Px4 {
            gcs: None,
            ground: None,
            manager: manager::Manager::default(),
            board: Board::new(
                clock,
                XorShift::new(config.seed),
                // SITL's threads run at every lockstep step (`Autopilot::run_due` below).
                if config.sitl_lockstep {
                    MainLoop::None
                } else {
                    MainLoop::ticks(5_000)
                },
            ),
            me: Endpoint::new(config.sysid, AUTOPILOT),
            rx: Rx::default(),
            intervals: BTreeMap::new(),
            next_due: BTreeMap::new(),
            last_heartbeat_us: None,
            last_info_req_us: None,
            gimbal_compid: None,
            info: None,
            limits: None,
            target: None,
            setpoint: (0.0, 0.0),
            last_integrate_us: 0,
            image_seq: 0,
            statuses: Vec::new(),
            acks: Vec::new(),
            set_attitudes: Vec::new(),
            sent: Vec::new(),
            received: Vec::new(),
            timesync_answers: Vec::new(),
            timesync_replies: Vec::new(),
            own_ts1: std::collections::VecDeque::new(),
            lockstep: config
                .sitl_lockstep
                .then(|| Lockstep::new(config.lockstep.clone(), config.boot_us, config.seed)),
            next_step_us: 0,
            config,
        };
        p.mode_streams();
        p
    }

    fn mode_streams(&mut self) {
        self.intervals.clear();
        self.next_due.clear();
        let set_attitude = GIMBAL_DEVICE_SET_ATTITUDE_DATA::ID;
        match self.config.mode {
            Px4Mode::Gimbal => {
                self.intervals.insert(set_attitude, 50_000);
                self.intervals
                    .insert(AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA::ID, 50_000);
            }
            Px4Mode::Normal => {
                self.intervals.insert(set_attitude, 200_000);
                self.intervals.insert(GLOBAL_POSITION_INT_DATA::ID, 200_000);
                self.intervals.insert(GPS_RAW_INT_DATA::ID, 200_000);
                self.intervals.insert(ATTITUDE_DATA::ID, 66_667);
            }
            Px4Mode::Onboard => {
                self.intervals.insert(set_attitude, 200_000);
                self.intervals.insert(TIMESYNC_DATA::ID, 100_000);
                self.intervals.insert(SYSTEM_TIME_DATA::ID, 1_000_000);
                self.intervals.insert(GLOBAL_POSITION_INT_DATA::ID, 20_000);
                self.intervals.insert(GPS_RAW_INT_DATA::ID, 100_000);
                self.intervals.insert(ATTITUDE_DATA::ID, 10_000);
            }
        }
    }

    /// The gimbal's attitude as forwarded (roll, pitch, yaw from the nose), degrees.
    #[must_use]
    pub fn mount_angles(&self) -> Option<(f64, f64, f64)> {
        let (_, _, s) = self.statuses.last()?;
        mav::euler_deg(s.q)
    }

    /// PX4's boot clock (µs) at true time `t`: the board's, or SITL's lockstep clock.
    fn boot_us(&self, t: u64) -> u64 {
        match &self.lockstep {
            Some(l) => l.boot_us(t),
            None => self.board.fc_us(t),
        }
    }

    /// The boot clock TIMESYNC's `tc1` reads at true time `t` (µs).
    fn timesync_us(&self, t: u64) -> u64 {
        match &self.lockstep {
            Some(l) => l.timesync_us(t),
            None => self.board.fc_us(t),
        }
    }

    /// The clock the MAVLink threads schedule on (µs): true time, or SITL's simulation
    /// time.
    fn schedule_us(&self, t: u64) -> u64 {
        match &self.lockstep {
            Some(l) => l.boot_us(t),
            None => t,
        }
    }

    /// The UTC PX4 reports at true time `t`: its clock's, or with SITL in lockstep the
    /// host's (the true rate).
    fn utc_us(&self, t: u64) -> u64 {
        if self.config.sitl_lockstep {
            self.board.clock().gps_utc_us(t)
        } else {
            self.fc_utc_us(t)
        }
    }

    fn camera_command(&mut self, cmd: MavCmd, p: [f32; 4]) {
        let target = (self.config.sysid, self.config.camera_target_component);
        self.send(&mav::camera_command(cmd, p, target));
    }

    fn send(&mut self, msg: &MavMessage) {
        self.send_at(self.board.now_us(), msg);
    }

    /// Sends `msg` written at true time `t` (its own burst, after the transport
    /// jitter); returns the burst's start.
    fn send_at(&mut self, t: u64, msg: &MavMessage) -> u64 {
        if self.board.is_off() {
            return t;
        }
        if let MavMessage::TIMESYNC(s) = msg
            && s.tc1 == 0
        {
            if self.own_ts1.len() >= 32 {
                self.own_ts1.pop_front();
            }
            self.own_ts1.push_back(s.ts1);
        }
        let f = self.me.frame(msg);
        self.sent.push((t, msg.clone()));
        let at = t + self.board.rng().uniform(self.config.jitter_us);
        self.board.write_in_order(at, f);
        at
    }

    /// Integrates a rate input into the angle setpoint, within the limits.
    fn integrate(&mut self) {
        let now = self.board.now_us();
        let dt = (now - self.last_integrate_us) as f64 / 1e6;
        self.last_integrate_us = now;
        match self.target {
            Some(Px4Target::Rate { pitch_dps, yaw_dps }) => {
                let [pmin, pmax, ymin, ymax] = self.limits.unwrap_or([-90.0, 90.0, -180.0, 180.0]);
                self.setpoint.0 = (self.setpoint.0 + pitch_dps * dt).clamp(pmin, pmax);
                self.setpoint.1 = (self.setpoint.1 + yaw_dps * dt).clamp(ymin, ymax);
            }
            Some(Px4Target::Angle {
                pitch_deg, yaw_deg, ..
            }) => self.setpoint = (pitch_deg, yaw_deg),
            Some(Px4Target::Location {
                lat_e7,
                lon_e7,
                alt_m,
            }) => {
                let a = self.board.aircraft();
                let (lat, lon) = a.position_e7(now);
                let here = (lat, lon, a.alt_msl_m);
                let (bearing, elevation) = mav::bearing_elevation(here, (lat_e7, lon_e7, alt_m));
                self.setpoint = (elevation, bearing);
            }
            None => {}
        }
    }

    /// A ground station's command for this autopilot's gimbal manager (see the module
    /// documentation); false when it is not one (forwarded).
    fn manager_command(&mut self, frame: &[u8], gcs: &mut Qgc) -> bool {
        let Ok(p) = protocol_core::mavlink::Packet::decode(frame) else {
            return false;
        };
        let protocol_core::mavlink::Message::Known(m) = p.message else {
            return false;
        };
        let (command, params, xy, target) = match &m {
            MavMessage::COMMAND_LONG(c) => (
                c.command,
                [c.param1, c.param2, c.param3, c.param4, c.param5],
                None,
                (c.target_system, c.target_component),
            ),
            MavMessage::COMMAND_INT(c) => (
                c.command,
                [c.param1, c.param2, c.param3, c.param4, c.x as f32],
                Some((c.x, c.y, c.z)),
                (c.target_system, c.target_component),
            ),
            _ => return false,
        };
        if target != (self.config.sysid, AUTOPILOT) {
            return false;
        }
        self.target = match command {
            // Nothing set: the gimbal holds still.
            MavCmd::MAV_CMD_DO_GIMBAL_MANAGER_PITCHYAW => {
                Some(manager::pitchyaw_target(params).unwrap_or(Px4Target::Rate {
                    pitch_dps: 0.0,
                    yaw_dps: 0.0,
                }))
            }
            MavCmd::MAV_CMD_DO_SET_ROI_LOCATION => {
                let Some((x, y, z)) = xy else {
                    return false;
                };
                Some(Px4Target::Location {
                    lat_e7: x,
                    lon_e7: y,
                    alt_m: f64::from(z),
                })
            }
            MavCmd::MAV_CMD_DO_SET_ROI_NONE => {
                let (pitch_deg, yaw_deg) = self.setpoint;
                Some(Px4Target::Angle {
                    pitch_deg,
                    yaw_deg,
                    yaw_absolute: true,
                })
            }
            _ => return false,
        };
        let ack = mav::command_ack(command, MavResult::MAV_RESULT_ACCEPTED, &p.header);
        let me = Header {
            sequence: 0,
            system_id: self.config.sysid,
            component_id: AUTOPILOT,
        };
        gcs.receive(self.board.now_us(), me, &ack);
        true
    }

    fn set_attitude(&self) -> Option<GIMBAL_DEVICE_SET_ATTITUDE_DATA> {
        let target = self.target?;
        let (pitch, yaw) = self.setpoint;
        let (rates, absolute) = match target {
            Px4Target::Rate { pitch_dps, yaw_dps } => (
                [
                    0.0,
                    pitch_dps.to_radians() as f32,
                    yaw_dps.to_radians() as f32,
                ],
                false,
            ),
            Px4Target::Angle { yaw_absolute, .. } => ([f32::NAN; 3], yaw_absolute),
            Px4Target::Location { .. } => ([f32::NAN; 3], true),
        };
        let mut flags = GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_ROLL_LOCK
            | GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_PITCH_LOCK;
        if absolute {
            flags |= GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_YAW_LOCK;
        }
        Some(GIMBAL_DEVICE_SET_ATTITUDE_DATA {
            q: mav::quat_deg(0.0, pitch, yaw),
            angular_velocity_x: rates[0],
            angular_velocity_y: rates[1],
            angular_velocity_z: rates[2],
            flags,
            target_system: self.config.sysid,
            target_component: self
                .gimbal_compid
                .unwrap_or(self.config.initial_target_component),
        })
    }

    fn stream_message(&self, id: u32) -> Option<MavMessage> {
        let t = self.board.now_us();
        let us = self.boot_us(t);
        let a = AircraftState::of(self.board.aircraft(), t, us);
        let (lat, lon) = a.lat_lon_e7;
        Some(match id {
            GIMBAL_DEVICE_SET_ATTITUDE_DATA::ID => {
                MavMessage::GIMBAL_DEVICE_SET_ATTITUDE(self.set_attitude()?)
            }
            AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA::ID => {
                a.autopilot_state(us, 0x3F, 0, MavLandedState::MAV_LANDED_STATE_IN_AIR)
            }
            // Not sent at all while the clock is invalid.
            SYSTEM_TIME_DATA::ID if !self.board.utc_valid() => return None,
            SYSTEM_TIME_DATA::ID => MavMessage::SYSTEM_TIME(SYSTEM_TIME_DATA {
                time_unix_usec: self.utc_us(t),
                time_boot_ms: a.boot_ms,
            }),
            TIMESYNC_DATA::ID => MavMessage::TIMESYNC(TIMESYNC_DATA {
                tc1: 0,
                ts1: (us * 1000) as i64,
                target_system: 0,
                target_component: 0,
            }),
            GLOBAL_POSITION_INT_DATA::ID => a.global_position(58_000),
            // PX4 stamps it with its boot clock (hrt), not UTC.
            GPS_RAW_INT_DATA::ID => MavMessage::GPS_RAW_INT(GPS_RAW_INT_DATA {
                time_usec: us,
                lat,
                lon,
                alt: a.alt_mm,
                fix_type: GpsFixType::GPS_FIX_TYPE_3D_FIX,
                satellites_visible: 12,
                ..GPS_RAW_INT_DATA::default()
            }),
            ATTITUDE_DATA::ID => a.attitude(),
            _ => return None,
        })
    }

    /// A frame delivered at `now` whose last byte arrived at `end`.
    fn process(&mut self, now: u64, end: u64, r: mav::Received) {
        let h = r.header;
        self.received.push((now, h, mav::id_of(&r.message)));
        if let Some(gcs) = self.gcs.as_mut()
            && mav::routed_to(&r.message, gcs.config.sysid)
        {
            gcs.receive(now, h, &r.message);
        }
        if let Some(g) = self.ground.as_mut() {
            g.forward(&r.message, &r.bytes);
        }
        match r.message {
            MavMessage::GIMBAL_DEVICE_INFORMATION(i) if self.info.is_none() => {
                self.gimbal_compid = Some(h.component_id);
                self.limits = Some([
                    f64::from(i.pitch_min).to_degrees(),
                    f64::from(i.pitch_max).to_degrees(),
                    f64::from(i.yaw_min).to_degrees(),
                    f64::from(i.yaw_max).to_degrees(),
                ]);
                self.info = Some(i);
            }
            MavMessage::GIMBAL_DEVICE_ATTITUDE_STATUS(s) => self.statuses.push((now, h, s)),
            MavMessage::COMMAND_ACK(a) => self.acks.push((now, h, a)),
            MavMessage::TIMESYNC(t)
                if t.tc1 == 0
                    && !self.config.gimbal_link_only
                    && (t.target_system == 0 || t.target_system == self.config.sysid) =>
            {
                // The receive thread parses it, reads hrt and answers at once.
                let parse = end + self.board.rng().uniform(self.config.parse_latency_us);
                let tc1 = (self.timesync_us(parse) * 1000) as i64;
                let target = match self.config.timesync_targets {
                    TimesyncTargets::Requester => (h.system_id, h.component_id),
                    TimesyncTargets::Unset => match self.board.rng().uniform(611) {
                        0 => (17, 0),
                        1 => (1, 0),
                        2 => (40, 126),
                        _ => (208, 17),
                    },
                };
                let at = parse.max(now);
                let msg = MavMessage::TIMESYNC(TIMESYNC_DATA {
                    tc1,
                    ts1: t.ts1,
                    target_system: target.0,
                    target_component: target.1,
                });
                let sent_at_us = self.send_at(at, &msg);
                self.timesync_answers.push(TimesyncAnswer {
                    from: h,
                    handled_at_us: parse,
                    sent_at_us,
                    ts1: t.ts1,
                    tc1,
                    target,
                });
            }
            MavMessage::TIMESYNC(t) if t.tc1 != 0 && self.own_ts1.contains(&t.ts1) => {
                self.timesync_replies.push((now, t.tc1));
            }
            MavMessage::COMMAND_LONG(c)
                if c.command == MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL
                    && c.target_system == self.config.sysid
                    && (c.target_component == AUTOPILOT || c.target_component == 0)
                    && !self.config.gimbal_link_only =>
            {
                let result = if !self.config.honours_interval {
                    MavResult::MAV_RESULT_UNSUPPORTED
                } else if c.param2 > 0.0 {
                    self.intervals.insert(c.param1 as u32, c.param2 as u64);
                    self.next_due.remove(&(c.param1 as u32));
                    MavResult::MAV_RESULT_ACCEPTED
                } else {
                    self.intervals.remove(&(c.param1 as u32));
                    MavResult::MAV_RESULT_ACCEPTED
                };
                self.send(&mav::command_ack(c.command, result, &h));
            }
            _ => {}
        }
    }
}

impl Autopilot for Px4 {
    board_field!();

    /// The boot clock: the board's, or SITL's lockstep clock.
    fn fc_us(&self, t_us: u64) -> u64 {
        self.boot_us(t_us)
    }

    /// SITL: the next lockstep step.
    fn next_work_us(&self) -> u64 {
        match self.lockstep {
            Some(_) => self.next_step_us,
            None => self.board.next_run_us(),
        }
    }

    /// SITL: a run at every lockstep step up to `now_us`.
    fn run_due(&mut self, now_us: u64) {
        if self.lockstep.is_some() {
            while self.next_step_us <= now_us {
                let at = self.next_step_us;
                self.board.set_now(at);
                self.run();
                self.next_step_us = self
                    .lockstep
                    .as_ref()
                    .map_or(u64::MAX, |l| l.next_step_after(at));
            }
        } else {
            self.run_loop_until(now_us, true);
        }
        self.board.set_now(now_us);
        self.update_health();
    }

    /// Frames the MAVLink receiver dropped for a bad checksum or length.
    fn parse_errors(&self) -> u32 {
        self.rx.errors()
    }

    fn take_bytes(&mut self, now_us: u64, bytes: &[u8]) {
        let byte_us = 1e7 / f64::from(self.config.baud.max(1));
        for (r, after) in self.rx.push_counting(bytes) {
            // The frame's last byte came `after` bytes before the chunk's last.
            let end = now_us.saturating_sub((after as f64 * byte_us).round() as u64);
            self.process(now_us, end, r);
        }
    }

    /// One 5 ms tick of the MAVLink threads.
    fn run(&mut self) {
        let now = self.board.now_us();
        // What the threads schedule on (SITL: simulation time).
        let clock = self.schedule_us(now);
        if self
            .last_heartbeat_us
            .is_none_or(|l| clock - l >= 1_000_000)
        {
            self.last_heartbeat_us = Some(clock);
            self.send(&mav::autopilot_heartbeat(
                MavType::MAV_TYPE_QUADROTOR,
                MavAutopilot::MAV_AUTOPILOT_PX4,
            ));
        }
        if self.info.is_none() && self.last_info_req_us.is_none_or(|l| clock - l >= 1_000_000) {
            self.last_info_req_us = Some(clock);
            self.send(&mav::request_message(
                GIMBAL_DEVICE_INFORMATION_DATA::ID,
                (0, 0),
            ));
        }
        self.integrate();
        let ids: Vec<(u32, u64)> = self.intervals.iter().map(|(k, v)| (*k, *v)).collect();
        for (id, interval) in ids {
            let due = self.next_due.get(&id).copied().unwrap_or(clock);
            if clock >= due {
                self.next_due.insert(id, (due + interval).max(clock));
                if let Some(m) = self.stream_message(id) {
                    if let MavMessage::GIMBAL_DEVICE_SET_ATTITUDE(s) = &m {
                        self.set_attitudes.push((now, s.clone()));
                    }
                    self.send(&m);
                }
            }
        }
        if let Some(mut gcs) = self.gcs.take() {
            gcs.poll(now);
            for f in gcs.transmit() {
                if !self.manager_command(&f, &mut gcs) {
                    self.board.write_in_order(now, f);
                }
            }
            self.gcs = Some(gcs);
        }
        self.ground_run(now);
    }

    fn update_health(&mut self) {
        let now = self.board.now_us();
        let fresh = self
            .statuses
            .last()
            .is_some_and(|(t, ..)| now.saturating_sub(*t) < 1_000_000);
        let healthy = self.info.is_some() && fresh && !self.board.is_off();
        self.board.set_healthy(healthy);
    }

    fn power_on(&mut self) {
        self.me = Endpoint::new(self.config.sysid, AUTOPILOT);
        self.rx = Rx::default();
        self.mode_streams();
        self.last_heartbeat_us = None;
        self.last_info_req_us = None;
        self.gimbal_compid = None;
        self.info = None;
        self.limits = None;
        self.target = None;
    }
}

impl Pilot for Px4 {
    const DRIVER: &'static str = "PX4 gimbal v2 output (simulated)";
    type Frames = MavlinkFrames;

    fn first_utc_sent_us(&self) -> Option<u64> {
        self.sent.iter().find_map(|(t, m)| match m {
            MavMessage::SYSTEM_TIME(_) => Some(*t),
            _ => None,
        })
    }
    /// The UTC PX4 reports (with SITL in lockstep: the host's).
    fn true_utc_us(&self, t_us: u64) -> u64 {
        self.utc_us(t_us)
    }
    fn mount_angles(&self) -> Option<(f64, f64)> {
        Px4::mount_angles(self).map(|(_, pitch, yaw)| (yaw, pitch))
    }

    fn point(&mut self, yaw_deg: f64, pitch_deg: f64) {
        self.target = Some(Px4Target::Angle {
            pitch_deg,
            yaw_deg,
            yaw_absolute: false,
        });
    }
    fn turn(&mut self, yaw_dps: f64, pitch_dps: f64) {
        self.target = Some(Px4Target::Rate { pitch_dps, yaw_dps });
    }
    /// Continuous zoom.
    fn zoom(&mut self, rate: i8) {
        let r = f32::from(rate.signum());
        self.camera_command(MavCmd::MAV_CMD_SET_CAMERA_ZOOM, [1.0, r, 0.0, 0.0]);
    }
    /// Takes one picture (a re-emitted camera command).
    fn take_picture(&mut self) {
        self.image_seq += 1;
        let n = self.image_seq as f32;
        self.camera_command(MavCmd::MAV_CMD_IMAGE_START_CAPTURE, [0.0, 0.0, 1.0, n]);
    }
    /// Starts or stops recording.
    fn record(&mut self, on: bool) {
        self.camera_command(mav::video_capture(on), [0.0; 4]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::mav::testing::{Driver, byte_us, set_interval, timesync_request, uart_chunks};
    use protocol_core::mavlink::dialect::HEARTBEAT_DATA;
    use protocol_core::mavlink::dialect::TIMESYNC_DATA;

    fn system_times(d: &Driver) -> Vec<(u64, SYSTEM_TIME_DATA)> {
        d.frames()
            .into_iter()
            .filter_map(|(at, r)| match r.message {
                MavMessage::SYSTEM_TIME(s) => Some((at, s)),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn px4_answers_timesync_at_parse_time_with_the_requesters_target() {
        let mut px4 = Px4::new(Px4Config {
            ppm: 9.0,
            jitter_us: 0,
            ..Px4Config::default()
        });
        let mut d = Driver::new();
        let mut dev = Endpoint::new(1, mav::CAMERA);
        let byte = byte_us(115_200);
        let mut latencies = Vec::new();
        for i in 0..40u64 {
            let t0 = 1_000_000 + i * 98_765;
            let ts1 = 9_000_000_000 + i as i64;
            let req = dev.frame(&timesync_request(ts1, (if i % 3 == 0 { 0 } else { 1 }, 1)));
            let mut wire = req.clone();
            if i % 2 == 1 {
                // Bytes behind it in the same chunks.
                wire.extend(dev.frame(&MavMessage::HEARTBEAT(HEARTBEAT_DATA::default())));
            }
            let chunks = uart_chunks(t0, 115_200, &wire);
            d.deliver(&mut px4, &chunks);
            d.run_until(&mut px4, t0 + 20_000);
            let a = px4.timesync_answers.last().unwrap().clone();
            assert_eq!(px4.timesync_answers.len() as u64, i + 1);
            assert_eq!((a.ts1, a.target, a.from.component_id), (ts1, (1, 100), 100));
            // tc1: hrt at the parse, the frame's end plus the receive thread's latency.
            let end = t0 as f64 + req.len() as f64 * byte;
            let latency = a.handled_at_us as f64 - end;
            assert!((-1.0..=301.0).contains(&latency), "trial {i}: {latency}");
            latencies.push(latency);
            assert_eq!(a.tc1, (px4.fc_us(a.handled_at_us) * 1000) as i64);
            // Sent at once: its own burst, not before the chunk was handed over.
            let handed = chunks
                .iter()
                .scan(0, |n, (at, c)| {
                    *n += c.len();
                    Some((*n, *at))
                })
                .find(|(n, _)| *n >= req.len())
                .unwrap()
                .1;
            assert_eq!(a.sent_at_us, a.handled_at_us.max(handed));
            let on_wire: Vec<_> = d
                .frames()
                .into_iter()
                .filter_map(|(at, r)| match r.message {
                    MavMessage::TIMESYNC(t) if t.ts1 == ts1 => Some((at, t)),
                    _ => None,
                })
                .collect();
            assert_eq!(on_wire.len(), 1);
            let (at, t) = &on_wire[0];
            assert_eq!(*at, a.sent_at_us);
            assert_eq!(
                (t.tc1, t.target_system, t.target_component),
                (a.tc1, 1, 100)
            );
        }
        // The latency spreads over its range.
        let max = latencies.iter().copied().fold(0.0, f64::max);
        let min = latencies.iter().copied().fold(1e9, f64::min);
        assert!(min < 60.0 && max > 240.0, "{min}..{max}");
        // A request for another system is not answered.
        let n = px4.timesync_answers.len();
        d.send(&mut px4, 6_000_000, &mut dev, &timesync_request(1, (7, 1)));
        d.run_until(&mut px4, 6_100_000);
        assert_eq!(px4.timesync_answers.len(), n);
    }

    #[test]
    fn px4_system_time_only_on_request_in_gimbal_and_normal_modes() {
        for (mode, honours) in [
            (Px4Mode::Gimbal, true),
            (Px4Mode::Normal, true),
            (Px4Mode::Gimbal, false),
        ] {
            let mut px4 = Px4::new(Px4Config {
                mode,
                honours_interval: honours,
                ppm: -14.0,
                ..Px4Config::default()
            });
            let mut d = Driver::new();
            d.run_until(&mut px4, 3_000_000);
            assert!(system_times(&d).is_empty(), "{mode:?}");
            let mut dev = Endpoint::new(1, mav::GIMBAL);
            let cmd = set_interval(SYSTEM_TIME_DATA::ID, 100_000.0);
            d.send(&mut px4, 3_000_000, &mut dev, &cmd);
            d.run_until(&mut px4, 6_000_000);
            let expected = if honours {
                MavResult::MAV_RESULT_ACCEPTED
            } else {
                MavResult::MAV_RESULT_UNSUPPORTED
            };
            assert_eq!(px4.acks.len(), 0);
            assert!(d.frames().iter().any(|(_, r)| matches!(&r.message,
                MavMessage::COMMAND_ACK(a) if a.result == expected)));
            let times = system_times(&d);
            if !honours {
                assert!(times.is_empty());
                continue;
            }
            assert!((29..=31).contains(&times.len()), "{}", times.len());
            // One reading: the Unix time minus the boot ms is the UTC shift plus the
            // truncated sub-ms.
            let shift = px4.fc_utc_us(4_000_000) as i64 - px4.fc_us(4_000_000) as i64;
            for (_, s) in &times {
                let d = s.time_unix_usec as i64 - 1000 * i64::from(s.time_boot_ms) - shift;
                assert!((0..1000).contains(&d), "{d}");
            }
        }
    }

    /// SITL in lockstep as the capture shows it: its threads run at every 4 ms step of
    /// simulation time, so SYSTEM_TIME's `time_boot_ms` advances by exactly 100 ms while
    /// its `time_unix_usec` (the host's clock) advances by 100.0–103 ms (the capture:
    /// 100.14–102.50); every boot-clock value a whole step; TIMESYNC's tc1 one step behind
    /// the streams' boot clock, the reply's targets unset (mostly 208/17).
    #[test]
    fn px4_sitl_streams_on_simulation_time_and_answers_as_1_16() {
        let mut px4 = Px4::new(Px4Config {
            jitter_us: 0,
            ..Px4Config::sitl_lockstep()
        });
        let mut d = Driver::new();
        let mut dev = Endpoint::new(1, mav::GIMBAL);
        d.send(
            &mut px4,
            1_000,
            &mut dev,
            &set_interval(SYSTEM_TIME_DATA::ID, 100_000.0),
        );
        for i in 0..40u64 {
            let t0 = 1_000_000 + i * 123_457;
            d.send(
                &mut px4,
                t0,
                &mut dev,
                &timesync_request(7 + i as i64, (1, 1)),
            );
        }
        d.run_until(&mut px4, 12_000_000);
        let times = system_times(&d);
        assert!((100..=120).contains(&times.len()), "{}", times.len());
        for w in times.windows(2) {
            let (a, b) = (&w[0].1, &w[1].1);
            assert_eq!(b.time_boot_ms - a.time_boot_ms, 100);
            let host = b.time_unix_usec - a.time_unix_usec;
            assert!((100_000..=103_000).contains(&host), "{host}");
        }
        // Sent at the step: the boot clock then is the one it carries; UTC the host's.
        for (at, t) in &times {
            assert_eq!(px4.fc_us(*at), u64::from(t.time_boot_ms) * 1000);
            assert_eq!(t.time_unix_usec, px4.true_utc_us(*at));
        }
        assert!(d.frames().iter().all(|(_, r)| match &r.message {
            MavMessage::ATTITUDE(a) => a.time_boot_ms % 4 == 0,
            MavMessage::GLOBAL_POSITION_INT(p) => p.time_boot_ms % 4 == 0,
            _ => true,
        }));
        assert_eq!(px4.timesync_answers.len(), 40);
        let mut usual = 0;
        for a in &px4.timesync_answers {
            assert_eq!(a.tc1 % 4_000_000, 0);
            assert_eq!(a.tc1 as u64, (px4.fc_us(a.handled_at_us) - 4_000) * 1000);
            assert_ne!(a.target, (1, mav::GIMBAL));
            usual += usize::from(a.target == (208, 17));
        }
        assert!(usual >= 38, "{usual}");
    }

    #[test]
    fn px4_onboard_streams_time_and_position_and_withholds_an_invalid_clock() {
        let mut px4 = Px4::new(Px4Config {
            mode: Px4Mode::Onboard,
            utc_valid_at_us: 2_500_000,
            ..Px4Config::default()
        });
        let mut d = Driver::new();
        d.run_until(&mut px4, 10_000_000);
        let times = system_times(&d);
        // 1 Hz, none while the clock is invalid.
        assert!((7..=8).contains(&times.len()), "{}", times.len());
        assert!(times.iter().all(|(at, _)| *at >= 2_500_000));
        let count = |id: u32| px4.sent.iter().filter(|(_, m)| mav::id_of(m) == id).count();
        assert!((99..=101).contains(&count(TIMESYNC_DATA::ID)));
        assert!((499..=501).contains(&count(GLOBAL_POSITION_INT_DATA::ID)));
        assert!((99..=101).contains(&count(GPS_RAW_INT_DATA::ID)));
        assert!((999..=1001).contains(&count(ATTITUDE_DATA::ID)));
        assert_eq!(count(AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA::ID), 0);
        // Its own requests carry boot ns; a reply to one is recorded.
        let (sent_at, ts1) = px4
            .sent
            .iter()
            .rev()
            .find_map(|(t, m)| match m {
                MavMessage::TIMESYNC(s) => Some((*t, s.ts1)),
                _ => None,
            })
            .unwrap();
        assert_eq!(ts1, (px4.fc_us(sent_at) * 1000) as i64);
        let mut dev = Endpoint::new(1, mav::GIMBAL);
        let reply = MavMessage::TIMESYNC(TIMESYNC_DATA {
            tc1: 42,
            ts1,
            target_system: 1,
            target_component: 1,
        });
        d.send(&mut px4, 10_000_000, &mut dev, &reply);
        assert_eq!(px4.timesync_replies.len(), 1);
        assert_eq!(px4.timesync_replies[0].1, 42);
    }
}
