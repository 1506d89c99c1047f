//! A simulated ArduPilot with a MAVLink gimbal (`MNT1_TYPE` 6, `AP_Mount_MAVLink`) and a
//! MAVLink camera (`CAM1_TYPE` 6, `AP_Camera_MAVLinkCamV2`) on one serial port
//! (`SERIALn_PROTOCOL` 2), written from `shared/MAVLINK-TRAFFIC.md` §1–§3, §6–§8:
//!
//! - **Loop.** The main loop runs at `SCHED_LOOP_RATE` ([`ApMavlink::loop_rate_hz`]:
//!   Copter 400 Hz, Plane 50 Hz), paced by the IMU, whose oscillator is not the FC
//!   crystal: loop `k` of a boot runs at true time `power-on + k·period/(1 + imu_ppm)`
//!   ([`ApMavlinkConfig::imu_ppm`]) plus a per-loop lateness uniform in
//!   `0..loop_jitter_us`, so its phase against the FC's millisecond grid is not locked.
//!   Each loop: the GCS receive processing handles the bytes the UART delivered so far
//!   (a frame that arrives is acted on in the next loop, never at arrival), the mount
//!   and camera updates run every (loop rate / 50)-th loop (50 Hz), and the GCS send
//!   processing sends what is due (HEARTBEAT, type QUADROTOR or FIXED_WING, autopilot
//!   ARDUPILOTMEGA, at 1 Hz; the streams). What one loop writes leaves in one burst
//!   after a transport jitter (`jitter_us`).
//! - **Streams.** Copter's defaults stream nothing to the port; Plane's 1 Hz
//!   ([`ApVehicle`]). MAV_CMD_SET_MESSAGE_INTERVAL to this system and component 1 sets
//!   the port's interval of a message (0 default, −1 stop), DENIED above 0.8 ×
//!   `SCHED_LOOP_RATE` ([`ApMavlinkConfig::loop_rate_hz`]). SYSTEM_TIME's Unix time is 0
//!   until the clock is set from GPS; GPS_RAW_INT's `time_usec` is the fix time since
//!   boot; GLOBAL_POSITION_INT is sent with or without a fix.
//! - **Mount.** Looks for a HEARTBEAT of type 26 from component 154 from 10 s of uptime
//!   until uptime > 60 s and armed; then asks GIMBAL_DEVICE_INFORMATION from that
//!   system/154 every second until it comes (ACKs not looked at); then enables
//!   AUTOPILOT_STATE_FOR_GIMBAL_DEVICE at 20 000 µs on the port: refused (a 50 Hz
//!   interval above 0.8 × the loop rate), the driver never initialises and no
//!   GIMBAL_DEVICE_SET_ATTITUDE is ever sent (§8.1). Initialised: SET_ATTITUDE every
//!   mount update: an angle as a quaternion (rates NaN) with flags 28 for an earth-frame
//!   yaw, 0 for a vehicle-relative one; a rate with the quaternion NaN (same flag rule;
//!   a rate from a MAVLink command zeroed after 3 s); retract as flags 1 with the
//!   quaternion NaN and rates 0; neutral as the angle of `MNT1_NEUTRAL_*` (0, 0, 0).
//!   Health: information received, an attitude status within 1 s, none of the failure
//!   flags 8..128. The status's quaternion is read as roll and pitch against the
//!   horizon and yaw relative to the vehicle whatever its flags; `delta_yaw`, once
//!   non-zero, gives the earth yaw. [`ApMavlinkConfig::old_gremsy`]: the older driver,
//!   which takes a status only when its `time_boot_ms` changed.
//! - **Camera.** Looks for a HEARTBEAT of type 30 from component 100 in the same window;
//!   REQUEST_MESSAGE(CAMERA_INFORMATION) to it every second until it comes; its flags
//!   gate what the driver sends (photo CAPTURE_IMAGE, video CAPTURE_VIDEO, zoom
//!   HAS_BASIC_ZOOM, focus HAS_BASIC_FOCUS: a missing flag refuses locally). Commands
//!   to 0/0 (4.5/4.6) or to system/100 (newest), [`CameraTargets`]: one photo as
//!   IMAGE_START_CAPTURE (0, 0, 1, counter + 1), video start/stop, zoom continuous or
//!   range, focus continuous, range or auto. Camera ACKs are recorded, not consumed.
//!   [`ApMavlinkConfig::capture_status_requests`] (newest source): CAMERA_CAPTURE_STATUS
//!   asked at 1 Hz, every 10 s after three misses.
//! - **TIMESYNC** request every 10 s (tc1 0, ts1 boot ns + sysid); replies with that ts1
//!   are recorded. A request from the device (tc1 0, target 0 or this system and 0 or
//!   component 1) is answered in the loop that reads it, in that loop's burst, on this
//!   port: ts1 echoed, no target fields, tc1 = boot µs × 1000 of the UART's estimate of
//!   the request's start (ChibiOS `receive_time_constraint_us(len)`): the FC-clock
//!   timestamp of the last chunk the UART delivered, minus (len + the bytes still
//!   unread behind the request) × the byte time at [`ApMavlinkConfig::baud`] (10 bits,
//!   integer µs as ChibiOS computes it). `len` is the frame's length or GCS_Common's
//!   `PAYLOAD_SIZE(TIMESYNC)` ([`TimesyncLen`]). Every answer is recorded
//!   ([`ApMavlink::timesync_answers`]).
//! - **SYSTEM_TIME**: `time_unix_usec` (the FC's UTC, 0 until set) and `time_boot_ms`
//!   (boot µs / 1000, truncated) from one reading of the FC clock at composition.
//! - **Telemetry port** ([`ApMavlink::telemetry`]): an ArduPilot port without a MAVLink
//!   mount or camera that shares the FC clock and the aircraft of another simulated
//!   driver on the same board (e.g. [`Autopilot::clock`] of [`super::ap_siyi::ApSiyi`]).
//! - **Routing.** A ground station ([`Qgc`]) can be attached: the device's messages
//!   without a target, with target 0 or the ground station's system reach it; its
//!   messages for the device (or broadcast) go onto the port as they came.
//! - **Reboot** ([`Autopilot::reboot`], on the [`Board`]): silent for the off time, then
//!   a new boot clock, streams back to the defaults, the drivers searching again.

use std::collections::BTreeMap;

use protocol_core::mavlink::dialect::{
    ATTITUDE_DATA, AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA, CAMERA_CAPTURE_STATUS_DATA,
    CAMERA_IMAGE_CAPTURED_DATA, CAMERA_INFORMATION_DATA, COMMAND_ACK_DATA, CameraCapFlags,
    GIMBAL_DEVICE_ATTITUDE_STATUS_DATA, GIMBAL_DEVICE_INFORMATION_DATA,
    GIMBAL_DEVICE_SET_ATTITUDE_DATA, GLOBAL_POSITION_INT_DATA, GPS_RAW_INT_DATA, GimbalDeviceFlags,
    GpsFixType, MavAutopilot, MavCmd, MavLandedState, MavResult, MavType, MessageData as _,
    SYSTEM_TIME_DATA, TIMESYNC_DATA,
};
use protocol_core::mavlink::{Header, MavMessage};

use super::board::{Aircraft, Autopilot, Board, MainLoop, board_field};
use super::describe::MavlinkFrames;
use super::mav::{self, AUTOPILOT, AircraftState, CAMERA, Endpoint, GIMBAL, Rx, TimesyncAnswer};
use super::pilot::Pilot;
use super::qgc::Qgc;
use super::{FcClock, XorShift};

/// The vehicle type: its default stream rates and loop rate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ApVehicle {
    /// Copter/Heli: every stream 0 Hz on a new port; 400 Hz loop.
    Copter,
    /// Plane: SYSTEM_TIME, positions, attitude, GPS at 1 Hz; 50 Hz loop.
    Plane,
}

/// The `len` ArduPilot hands `receive_time_constraint_us` for a TIMESYNC request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimesyncLen {
    /// The request frame's own length (as received: MAVLink 2 trims trailing zeros).
    Frame,
    /// `PAYLOAD_SIZE(chan, TIMESYNC)` as `GCS_Common.cpp` passes it: the MAVLink 2
    /// overhead (12) plus the full TIMESYNC payload (18), whatever the frame's length.
    PayloadSize,
}

/// MAVLink 2 overhead without signing (10 header + 2 checksum) plus TIMESYNC's full
/// payload (16 + the two target bytes).
pub const TIMESYNC_PAYLOAD_SIZE: usize = 12 + 18;

/// Where the camera driver sends its commands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CameraTargets {
    /// ArduPilot 4.5/4.6: target system and component 0 (the struct is zeroed).
    Broadcast,
    /// Newest source: the camera's system and component.
    Addressed,
}

/// Settings of the simulated ArduPilot.
#[derive(Debug, Clone)]
pub struct ApMavlinkConfig {
    /// Seed of the random jitter.
    pub seed: u64,
    /// FC crystal error, ppm.
    pub ppm: f64,
    /// Per-burst transport jitter bound, µs (uniform).
    pub jitter_us: u64,
    /// Lateness of each loop, µs (uniform).
    pub loop_jitter_us: u64,
    /// Rate error of the IMU oscillator that paces the loop, ppm (fast when positive).
    pub imu_ppm: f64,
    /// The port's baud rate (`SERIALn_BAUD`), for the UART's receive-time estimate.
    pub baud: u32,
    /// The `len` of the TIMESYNC receive-time estimate.
    pub timesync_len: TimesyncLen,
    /// The FC's UTC at true time 0, µs since the Unix epoch.
    pub utc_at_zero_us: u64,
    /// The FC's uptime at true time 0, µs.
    pub boot_us: u64,
    /// When the FC's clock is set from GPS (true µs); SYSTEM_TIME carries 0 before.
    pub utc_valid_at_us: u64,
    /// The FC's system id.
    pub sysid: u8,
    /// Vehicle type.
    pub vehicle: ApVehicle,
    /// `SCHED_LOOP_RATE` (None: the vehicle's default).
    pub loop_rate_hz: Option<u32>,
    /// `MNT1_TYPE` 6.
    pub mount: bool,
    /// `CAM1_TYPE` 6.
    pub camera: bool,
    /// Where camera commands go.
    pub camera_targets: CameraTargets,
    /// Newest source: ask CAMERA_CAPTURE_STATUS at 1 Hz.
    pub capture_status_requests: bool,
    /// The older `AP_Mount_Gremsy`: a status counts only when its time_boot_ms changed.
    pub old_gremsy: bool,
    /// Armed from this true instant (the drivers stop searching after 60 s of uptime).
    pub armed_at_us: Option<u64>,
    /// The GPS has a 3D fix.
    pub gps_fix: bool,
    /// Home altitude (relative altitude's zero), m.
    pub home_alt_m: f64,
}

impl Default for ApMavlinkConfig {
    fn default() -> Self {
        ApMavlinkConfig {
            seed: 1,
            ppm: 0.0,
            jitter_us: 2_000,
            loop_jitter_us: 500,
            imu_ppm: 37.0,
            baud: 115_200,
            timesync_len: TimesyncLen::Frame,
            // 2026-11-23T10:00:00.123456Z
            utc_at_zero_us: 1_795_428_000_123_456,
            // Booted 12 s before the bridge: the drivers already search.
            boot_us: 12_000_000,
            utc_valid_at_us: 0,
            sysid: 1,
            vehicle: ApVehicle::Copter,
            loop_rate_hz: None,
            mount: true,
            camera: true,
            camera_targets: CameraTargets::Broadcast,
            capture_status_requests: false,
            old_gremsy: false,
            armed_at_us: None,
            gps_fix: true,
            home_alt_m: 430.0,
        }
    }
}

/// What the mount is told to do.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ApMountTarget {
    /// Hold these angles (degrees): roll and pitch against the horizon, yaw from north
    /// (`yaw_is_ef`) or from the nose.
    Angle {
        /// Roll.
        roll_deg: f64,
        /// Pitch, positive up.
        pitch_deg: f64,
        /// Yaw, positive right.
        yaw_deg: f64,
        /// Yaw from north.
        yaw_is_ef: bool,
    },
    /// Turn at these rates (deg/s).
    Rate {
        /// Pitch rate.
        pitch_dps: f64,
        /// Yaw rate.
        yaw_dps: f64,
        /// Earth-frame yaw rate.
        yaw_is_ef: bool,
        /// Set by a MAVLink command (zeroed after 3 s without another), else RC.
        from_mavlink: bool,
    },
    /// Retracted.
    Retract,
    /// Neutral (`MNT1_NEUTRAL_*`: 0, 0, 0).
    Neutral,
}

/// A message from the device, with the true time of the loop that read it.
#[derive(Debug, Clone)]
pub struct Heard<T> {
    /// True time.
    pub at_us: u64,
    /// Who sent it.
    pub header: Header,
    /// The message.
    pub data: T,
}

/// The simulated ArduPilot.
#[derive(Debug)]
pub struct ApMavlink {
    /// Settings.
    pub config: ApMavlinkConfig,
    /// The aircraft.
    pub aircraft: Aircraft,
    /// A ground station attached to the FC's routing.
    pub gcs: Option<Qgc>,
    board: Board,
    /// Chunks the UART delivered since the last loop: (true time, bytes).
    uart: Vec<(u64, Vec<u8>)>,
    me: Endpoint,
    rx: Rx,
    /// Stream intervals of the device's port, µs.
    pub intervals: BTreeMap<u32, u64>,
    next_due: BTreeMap<u32, u64>,
    last_heartbeat_ms: Option<u64>,
    last_timesync_ms: Option<u64>,
    /// TIMESYNC replies to this FC's requests: (true time, tc1).
    pub timesync_replies: Vec<(u64, i64)>,
    /// The device's TIMESYNC requests this FC answered.
    pub timesync_answers: Vec<TimesyncAnswer>,
    // Mount driver.
    /// The gimbal found (its system id).
    pub mount_found: Option<u8>,
    /// When it was found (true µs).
    pub mount_found_at_us: Option<u64>,
    /// GIMBAL_DEVICE_INFORMATION received.
    pub mount_info: Option<Heard<GIMBAL_DEVICE_INFORMATION_DATA>>,
    last_info_req_ms: Option<u64>,
    /// AUTOPILOT_STATE enabled: the driver is initialised.
    pub mount_initialised: bool,
    /// The AUTOPILOT_STATE interval was refused: never initialised.
    pub mount_refused: bool,
    /// The mount target.
    pub target: Option<ApMountTarget>,
    rate_set_ms: u64,
    /// The last attitude status taken (old driver: only new time_boot_ms).
    pub status: Option<Heard<GIMBAL_DEVICE_ATTITUDE_STATUS_DATA>>,
    /// Every attitude status received.
    pub statuses: u32,
    /// The mount's attitude as the driver reads it: (true time, roll, pitch, yaw from the
    /// nose, earth yaw when delta_yaw is non-zero), degrees.
    pub attitude: Option<(u64, f64, f64, f64, Option<f64>)>,
    /// GIMBAL_DEVICE_SET_ATTITUDE sent: (true time, message).
    pub set_attitudes: Vec<(u64, GIMBAL_DEVICE_SET_ATTITUDE_DATA)>,
    // Camera driver.
    /// The camera found (its system id).
    pub camera_found: Option<u8>,
    /// CAMERA_INFORMATION received.
    pub camera_info: Option<Heard<CAMERA_INFORMATION_DATA>>,
    last_cam_req_ms: Option<u64>,
    image_counter: u32,
    capture_req: (Option<u64>, u8),
    /// Camera actions refused locally (no information, or a capability flag missing).
    pub refused_locally: u32,
    /// Every COMMAND_ACK received, with its sender.
    pub acks: Vec<Heard<COMMAND_ACK_DATA>>,
    /// CAMERA_IMAGE_CAPTURED received.
    pub images: Vec<Heard<CAMERA_IMAGE_CAPTURED_DATA>>,
    /// CAMERA_CAPTURE_STATUS received.
    pub capture_statuses: Vec<Heard<CAMERA_CAPTURE_STATUS_DATA>>,
    /// Every frame received: (true time of the loop that read it, header, message id).
    pub received: Vec<(u64, Header, u32)>,
    /// Every frame sent: (true time it was written, message id, the message).
    pub sent: Vec<(u64, MavMessage)>,
}

impl ApMavlink {
    /// An FC that starts at true time 0.
    #[must_use]
    pub fn new(config: ApMavlinkConfig) -> Self {
        let clock = FcClock::new(
            config.ppm,
            config.boot_us,
            config.utc_at_zero_us,
            config.utc_valid_at_us,
        );
        Self::with_clock(config, clock, Aircraft::default())
    }

    /// The MAVLink telemetry port (`SERIALn_PROTOCOL` 2, no MAVLink mount or camera:
    /// `MNT1_TYPE` and `CAM1_TYPE` are another driver's) of the autopilot that also runs
    /// another simulated driver, e.g. [`super::ap_siyi::ApSiyi`]: pass that driver's
    /// [`Autopilot::clock`] and aircraft, so that both ports agree on time
    /// and position. The clock is a copy: when the other driver reboots, reboot this
    /// one too at the same instant with the same [`super::FcReboot`] (the clocks then stay
    /// equal, [`FcClock::reboot`] being deterministic). Other settings are the
    /// defaults of [`ApMavlinkConfig`] (Copter).
    #[must_use]
    pub fn telemetry(clock: FcClock, aircraft: Aircraft, seed: u64, sysid: u8) -> Self {
        let first = clock.boots()[0];
        let config = ApMavlinkConfig {
            seed,
            sysid,
            mount: false,
            camera: false,
            ppm: clock.ppm(),
            boot_us: first.clock_us,
            utc_at_zero_us: first.utc_us,
            utc_valid_at_us: first.utc_valid_at_us,
            ..ApMavlinkConfig::default()
        };
        Self::with_clock(config, clock, aircraft)
    }

    /// An FC on a given clock and aircraft (`config`'s clock settings unused). Its
    /// loop starts at the clock's latest power-on.
    #[must_use]
    pub fn with_clock(config: ApMavlinkConfig, clock: FcClock, aircraft: Aircraft) -> Self {
        let main_loop = MainLoop::imu(loop_rate_hz(&config), config.imu_ppm, config.loop_jitter_us);
        let mut ap = ApMavlink {
            aircraft,
            gcs: None,
            board: Board::new(clock, XorShift::new(config.seed), main_loop),
            uart: Vec::new(),
            me: Endpoint::new(config.sysid, AUTOPILOT),
            rx: Rx::default(),
            intervals: BTreeMap::new(),
            next_due: BTreeMap::new(),
            last_heartbeat_ms: None,
            last_timesync_ms: None,
            timesync_replies: Vec::new(),
            timesync_answers: Vec::new(),
            mount_found: None,
            mount_found_at_us: None,
            mount_info: None,
            last_info_req_ms: None,
            mount_initialised: false,
            mount_refused: false,
            target: None,
            rate_set_ms: 0,
            status: None,
            statuses: 0,
            attitude: None,
            set_attitudes: Vec::new(),
            camera_found: None,
            camera_info: None,
            last_cam_req_ms: None,
            image_counter: 0,
            capture_req: (None, 0),
            refused_locally: 0,
            acks: Vec::new(),
            images: Vec::new(),
            capture_statuses: Vec::new(),
            received: Vec::new(),
            sent: Vec::new(),
            config,
        };
        ap.default_streams();
        ap
    }

    /// True time of the next loop.
    #[must_use]
    pub fn next_loop_at_us(&self) -> u64 {
        self.board.next_run_us()
    }

    /// The loop rate, Hz.
    #[must_use]
    pub fn loop_rate_hz(&self) -> u32 {
        loop_rate_hz(&self.config)
    }

    fn default_streams(&mut self) {
        self.intervals.clear();
        self.next_due.clear();
        if self.config.vehicle == ApVehicle::Plane {
            for id in [
                SYSTEM_TIME_DATA::ID,
                GLOBAL_POSITION_INT_DATA::ID,
                ATTITUDE_DATA::ID,
                GPS_RAW_INT_DATA::ID,
            ] {
                self.intervals.insert(id, 1_000_000);
            }
        }
    }

    /// Messages of type `M` sent to the device, with their true time.
    pub fn sent_of(&self, id: u32) -> impl Iterator<Item = &(u64, MavMessage)> {
        self.sent.iter().filter(move |(_, m)| mav::id_of(m) == id)
    }

    fn send(&mut self, msg: &MavMessage) {
        if self.board.is_off() {
            return;
        }
        let frame = self.me.frame(msg);
        self.sent.push((self.board.now_us(), msg.clone()));
        self.board.write_loop(frame, self.config.jitter_us);
    }

    fn in_search_window(&self) -> bool {
        let uptime_ms = self.board.fc_ms();
        let armed = self
            .config
            .armed_at_us
            .is_some_and(|a| self.board.now_us() >= a);
        uptime_ms >= 10_000 && !(uptime_ms > 60_000 && armed)
    }

    // Actions.

    /// Take one picture (through the camera driver).
    pub fn take_picture(&mut self) {
        if !self.camera_can(CameraCapFlags::CAMERA_CAP_FLAGS_CAPTURE_IMAGE) {
            return;
        }
        self.image_counter += 1;
        let n = self.image_counter as f32;
        self.camera_command(MavCmd::MAV_CMD_IMAGE_START_CAPTURE, [0.0, 0.0, 1.0, n]);
    }

    /// Start or stop recording.
    pub fn record_video(&mut self, on: bool) {
        if !self.camera_can(CameraCapFlags::CAMERA_CAP_FLAGS_CAPTURE_VIDEO) {
            return;
        }
        self.camera_command(mav::video_capture(on), [0.0; 4]);
    }

    /// Continuous zoom: -1 out, 0 stop, 1 in.
    pub fn zoom_rate(&mut self, rate: i8) {
        if self.camera_can(CameraCapFlags::CAMERA_CAP_FLAGS_HAS_BASIC_ZOOM) {
            let r = f32::from(rate.signum());
            self.camera_command(MavCmd::MAV_CMD_SET_CAMERA_ZOOM, [1.0, r, 0.0, 0.0]);
        }
    }

    /// Zoom to a percentage of the range.
    pub fn zoom_pct(&mut self, pct: f32) {
        if self.camera_can(CameraCapFlags::CAMERA_CAP_FLAGS_HAS_BASIC_ZOOM) {
            self.camera_command(MavCmd::MAV_CMD_SET_CAMERA_ZOOM, [2.0, pct, 0.0, 0.0]);
        }
    }

    /// Focus: `kind` 1 continuous (`value` -1/0/1), 2 range (%), 4 auto.
    pub fn focus(&mut self, kind: u8, value: f32) {
        if self.camera_can(CameraCapFlags::CAMERA_CAP_FLAGS_HAS_BASIC_FOCUS) {
            let k = f32::from(kind);
            self.camera_command(MavCmd::MAV_CMD_SET_CAMERA_FOCUS, [k, value, 0.0, 0.0]);
        }
    }

    fn camera_can(&mut self, flag: CameraCapFlags) -> bool {
        let ok = self
            .camera_info
            .as_ref()
            .is_some_and(|i| i.data.flags.contains(flag));
        if !ok {
            self.refused_locally += 1;
        }
        ok
    }

    fn camera_command(&mut self, cmd: MavCmd, p: [f32; 4]) {
        let target = match self.config.camera_targets {
            CameraTargets::Broadcast => (0, 0),
            CameraTargets::Addressed => (self.camera_found.unwrap_or(0), CAMERA),
        };
        self.send(&mav::camera_command(cmd, p, target));
    }

    // The loop.

    /// The GCS receive processing: every byte the UART delivered so far.
    fn gcs_receive(&mut self) {
        let chunks = std::mem::take(&mut self.uart);
        let Some(&(last_at, _)) = chunks.last() else {
            return;
        };
        // The UART's timestamp of the last chunk it delivered, on the FC clock.
        let stamp_us = self.board.fc_us(last_at);
        let bytes: Vec<u8> = chunks.into_iter().flat_map(|(_, b)| b).collect();
        for (r, after) in self.rx.push_counting(&bytes) {
            self.process(r, stamp_us, after);
        }
    }

    /// ChibiOS `receive_time_constraint_us(len)`: the UART's estimate (FC µs) of when a
    /// `len`-byte packet began, `after` bytes being still unread behind it.
    fn receive_time_constraint_us(&self, stamp_us: u64, len: usize, after: usize) -> u64 {
        // 10 bits a byte, in whole µs as the driver computes it.
        let byte_us = 10_000_000 / u64::from(self.config.baud.max(1));
        stamp_us.saturating_sub(byte_us * (len + after) as u64)
    }

    /// The GCS send processing: heartbeat, own TIMESYNC request, due streams.
    fn update_send(&mut self) {
        let ms = self.board.fc_ms();
        if self.last_heartbeat_ms.is_none_or(|l| ms - l >= 1000) {
            self.last_heartbeat_ms = Some(ms);
            let mavtype = match self.config.vehicle {
                ApVehicle::Copter => MavType::MAV_TYPE_QUADROTOR,
                ApVehicle::Plane => MavType::MAV_TYPE_FIXED_WING,
            };
            let autopilot = MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA;
            self.send(&mav::autopilot_heartbeat(mavtype, autopilot));
        }
        if self.last_timesync_ms.is_none_or(|l| ms - l >= 10_000) {
            self.last_timesync_ms = Some(ms);
            let ts1 = (self.board.fc_us(self.board.now_us()) * 1000 + u64::from(self.config.sysid))
                as i64;
            self.send(&MavMessage::TIMESYNC(TIMESYNC_DATA {
                tc1: 0,
                ts1,
                target_system: 0,
                target_component: 0,
            }));
        }
        self.streams();
    }

    fn streams(&mut self) {
        let fc_us = self.board.fc_us(self.board.now_us());
        let due: Vec<u32> = self
            .intervals
            .iter()
            .filter(|(id, _)| self.next_due.get(id).is_none_or(|&d| fc_us >= d))
            .map(|(id, _)| *id)
            .collect();
        for id in due {
            let interval = self.intervals[&id];
            let next = self.next_due.get(&id).copied().unwrap_or(fc_us) + interval;
            self.next_due.insert(
                id,
                if next <= fc_us {
                    fc_us + interval
                } else {
                    next
                },
            );
            if let Some(msg) = self.stream_message(id) {
                self.send(&msg);
            }
        }
    }

    /// The stream message `id` now.
    fn stream_message(&self, id: u32) -> Option<MavMessage> {
        let t = self.board.now_us();
        let fc_us = self.board.fc_us(t);
        let a = AircraftState::of(&self.aircraft, t, fc_us);
        let (lat, lon) = a.lat_lon_e7;
        let alt_mm = a.alt_mm;
        Some(match id {
            SYSTEM_TIME_DATA::ID => MavMessage::SYSTEM_TIME(SYSTEM_TIME_DATA {
                time_unix_usec: if self.board.utc_valid() {
                    self.board.clock().utc_us(t)
                } else {
                    0
                },
                time_boot_ms: a.boot_ms,
            }),
            GPS_RAW_INT_DATA::ID => MavMessage::GPS_RAW_INT(GPS_RAW_INT_DATA {
                // The last fix's time since boot (5 Hz GPS), not UTC.
                time_usec: fc_us / 200_000 * 200_000,
                lat,
                lon,
                alt: alt_mm,
                eph: 90,
                epv: 140,
                vel: (self.aircraft.speed_m_s * 100.0) as u16,
                cog: (self.aircraft.heading_deg * 100.0) as u16,
                fix_type: if self.config.gps_fix {
                    GpsFixType::GPS_FIX_TYPE_3D_FIX
                } else {
                    GpsFixType::GPS_FIX_TYPE_NO_FIX
                },
                satellites_visible: 14,
                alt_ellipsoid: alt_mm + 48_000,
                h_acc: 700,
                v_acc: 1200,
                vel_acc: 150,
                hdg_acc: 0,
                yaw: 0,
            }),
            GLOBAL_POSITION_INT_DATA::ID => a.global_position(
                ((self.aircraft.alt_msl_m - self.config.home_alt_m) * 1000.0) as i32,
            ),
            ATTITUDE_DATA::ID => a.attitude(),
            // AP_HAL::micros(): 32 bits.
            AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA::ID => a.autopilot_state(
                u64::from(fc_us as u32),
                0x01A7,
                self.config.sysid,
                MavLandedState::MAV_LANDED_STATE_UNDEFINED,
            ),
            _ => return None,
        })
    }

    /// `set_message_interval` on this port: the result.
    fn set_interval(&mut self, id: u32, interval_us: f32) -> MavResult {
        let known = [
            SYSTEM_TIME_DATA::ID,
            GPS_RAW_INT_DATA::ID,
            ATTITUDE_DATA::ID,
            GLOBAL_POSITION_INT_DATA::ID,
            AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA::ID,
        ];
        if !known.contains(&id) {
            return MavResult::MAV_RESULT_UNSUPPORTED;
        }
        if interval_us < -0.5 {
            self.intervals.remove(&id);
        } else if interval_us < 0.5 {
            let plane = self.config.vehicle == ApVehicle::Plane
                && id != AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA::ID;
            if plane {
                self.intervals.insert(id, 1_000_000);
            } else {
                self.intervals.remove(&id);
            }
        } else {
            let hz = 1e6 / f64::from(interval_us);
            if hz > 0.8 * f64::from(self.loop_rate_hz()) {
                return MavResult::MAV_RESULT_DENIED;
            }
            self.intervals.insert(id, interval_us as u64);
            self.next_due.remove(&id);
        }
        MavResult::MAV_RESULT_ACCEPTED
    }

    fn mount_update(&mut self) {
        let ms = self.board.fc_ms();
        let Some(sysid) = self.mount_found else {
            return;
        };
        if self.mount_info.is_none() {
            let id = GIMBAL_DEVICE_INFORMATION_DATA::ID;
            self.last_info_req_ms =
                self.ask_every_second(self.last_info_req_ms, id, (sysid, GIMBAL));
            return;
        }
        if !self.mount_initialised {
            return;
        }
        let Some(target) = self.target else {
            return;
        };
        let nan = [f32::NAN; 4];
        let ef_flags = |ef: bool| {
            if ef {
                GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_ROLL_LOCK
                    | GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_PITCH_LOCK
                    | GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_YAW_LOCK
            } else {
                GimbalDeviceFlags::empty()
            }
        };
        let (q, rates, flags) = match target {
            ApMountTarget::Angle {
                roll_deg,
                pitch_deg,
                yaw_deg,
                yaw_is_ef,
            } => (
                mav::quat_deg(roll_deg, pitch_deg, yaw_deg),
                [f32::NAN; 3],
                ef_flags(yaw_is_ef),
            ),
            ApMountTarget::Rate {
                pitch_dps,
                yaw_dps,
                yaw_is_ef,
                from_mavlink,
            } => {
                let stale = from_mavlink && ms.saturating_sub(self.rate_set_ms) > 3_000;
                let r = |dps: f64| if stale { 0.0 } else { dps.to_radians() as f32 };
                (nan, [0.0, r(pitch_dps), r(yaw_dps)], ef_flags(yaw_is_ef))
            }
            ApMountTarget::Retract => (
                nan,
                [0.0; 3],
                GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_RETRACT,
            ),
            ApMountTarget::Neutral => (
                mav::quat_deg(0.0, 0.0, 0.0),
                [f32::NAN; 3],
                GimbalDeviceFlags::empty(),
            ),
        };
        let set = GIMBAL_DEVICE_SET_ATTITUDE_DATA {
            q,
            angular_velocity_x: rates[0],
            angular_velocity_y: rates[1],
            angular_velocity_z: rates[2],
            flags,
            target_system: sysid,
            target_component: GIMBAL,
        };
        self.set_attitudes.push((self.board.now_us(), set.clone()));
        self.send(&MavMessage::GIMBAL_DEVICE_SET_ATTITUDE(set));
    }

    /// Sets the mount target; a MAVLink rate command restarts its 3 s.
    pub fn set_target(&mut self, target: ApMountTarget) {
        if matches!(
            target,
            ApMountTarget::Rate {
                from_mavlink: true,
                ..
            }
        ) {
            self.rate_set_ms = self.board.fc_ms();
        }
        self.target = Some(target);
    }

    /// Asks `target` for message `id` when a second (FC ms) has passed since `last_ms`;
    /// returns the instant of the last request.
    fn ask_every_second(&mut self, last_ms: Option<u64>, id: u32, target: (u8, u8)) -> Option<u64> {
        let ms = self.board.fc_ms();
        if last_ms.is_some_and(|l| ms - l < 1000) {
            return last_ms;
        }
        self.send(&mav::request_message(id, target));
        Some(ms)
    }

    fn camera_update(&mut self) {
        let ms = self.board.fc_ms();
        let Some(sysid) = self.camera_found else {
            return;
        };
        if self.camera_info.is_none() {
            let id = CAMERA_INFORMATION_DATA::ID;
            self.last_cam_req_ms = self.ask_every_second(self.last_cam_req_ms, id, (sysid, CAMERA));
            return;
        }
        if self.config.capture_status_requests {
            let (last, misses) = self.capture_req;
            let wait = if misses >= 3 { 10_000 } else { 1_000 };
            if last.is_none_or(|l| ms - l >= wait) {
                self.capture_req = (Some(ms), misses.saturating_add(1));
                self.send(&mav::request_message(
                    CAMERA_CAPTURE_STATUS_DATA::ID,
                    (sysid, CAMERA),
                ));
            }
        }
    }

    /// A frame from the device, read in the loop at the board's time; `stamp_us` is the
    /// UART's timestamp of the last chunk, `after` the bytes unread behind the frame.
    fn process(&mut self, r: mav::Received, stamp_us: u64, after: usize) {
        let now_us = self.board.now_us();
        let h = r.header;
        let id = mav::id_of(&r.message);
        self.received.push((now_us, h, id));
        self.route_to_gcs(now_us, &r);
        match r.message {
            MavMessage::HEARTBEAT(hb) => {
                let window = self.in_search_window();
                if window
                    && self.config.mount
                    && self.mount_found.is_none()
                    && hb.mavtype == MavType::MAV_TYPE_GIMBAL
                    && h.component_id == GIMBAL
                {
                    self.mount_found = Some(h.system_id);
                    self.mount_found_at_us = Some(now_us);
                }
                if window
                    && self.config.camera
                    && self.camera_found.is_none()
                    && hb.mavtype == MavType::MAV_TYPE_CAMERA
                    && h.component_id == CAMERA
                {
                    self.camera_found = Some(h.system_id);
                }
            }
            MavMessage::GIMBAL_DEVICE_INFORMATION(info)
                if self.mount_found == Some(h.system_id)
                    && h.component_id == GIMBAL
                    && self.mount_info.is_none() =>
            {
                self.mount_info = Some(Heard {
                    at_us: now_us,
                    header: h,
                    data: info,
                });
                // Enable AUTOPILOT_STATE_FOR_GIMBAL_DEVICE at 50 Hz on this port.
                let r = self.set_interval(AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA::ID, 20_000.0);
                self.mount_initialised = r == MavResult::MAV_RESULT_ACCEPTED;
                self.mount_refused = !self.mount_initialised;
            }
            MavMessage::GIMBAL_DEVICE_ATTITUDE_STATUS(s)
                if self.mount_found == Some(h.system_id) && h.component_id == GIMBAL =>
            {
                self.statuses += 1;
                let repeated = self.config.old_gremsy
                    && self
                        .status
                        .as_ref()
                        .is_some_and(|p| p.data.time_boot_ms == s.time_boot_ms);
                if !repeated {
                    if let Some((roll, pitch, yaw)) = mav::euler_deg(s.q) {
                        let earth = (s.delta_yaw != 0.0 || s.delta_yaw_velocity != 0.0)
                            .then(|| yaw + f64::from(s.delta_yaw).to_degrees());
                        self.attitude = Some((now_us, roll, pitch, yaw, earth));
                    }
                    self.status = Some(Heard {
                        at_us: now_us,
                        header: h,
                        data: s,
                    });
                }
            }
            MavMessage::CAMERA_INFORMATION(info)
                if self.camera_found == Some(h.system_id)
                    && h.component_id == CAMERA
                    && self.camera_info.is_none() =>
            {
                self.camera_info = Some(Heard {
                    at_us: now_us,
                    header: h,
                    data: info,
                });
            }
            MavMessage::CAMERA_CAPTURE_STATUS(s) => {
                self.capture_req.1 = 0;
                self.capture_statuses.push(Heard {
                    at_us: now_us,
                    header: h,
                    data: s,
                });
            }
            MavMessage::CAMERA_IMAGE_CAPTURED(c) => self.images.push(Heard {
                at_us: now_us,
                header: h,
                data: c,
            }),
            MavMessage::COMMAND_ACK(a) => self.acks.push(Heard {
                at_us: now_us,
                header: h,
                data: a,
            }),
            MavMessage::COMMAND_LONG(c)
                if c.command == MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL
                    && c.target_system == self.config.sysid
                    && c.target_component == AUTOPILOT =>
            {
                let result = self.set_interval(c.param1 as u32, c.param2);
                self.send(&mav::command_ack(c.command, result, &h));
            }
            MavMessage::TIMESYNC(t)
                if t.tc1 == 0
                    && (t.target_system == 0 || t.target_system == self.config.sysid)
                    && (t.target_component == 0 || t.target_component == AUTOPILOT) =>
            {
                let len = match self.config.timesync_len {
                    TimesyncLen::Frame => r.bytes.len(),
                    TimesyncLen::PayloadSize => TIMESYNC_PAYLOAD_SIZE,
                };
                let rx_us = self.receive_time_constraint_us(stamp_us, len, after);
                let tc1 = (rx_us * 1000) as i64;
                self.send(&MavMessage::TIMESYNC(TIMESYNC_DATA {
                    tc1,
                    ts1: t.ts1,
                    target_system: 0,
                    target_component: 0,
                }));
                if let Some(sent_at_us) = self.board.last_burst_at() {
                    self.timesync_answers.push(TimesyncAnswer {
                        from: h,
                        handled_at_us: now_us,
                        sent_at_us,
                        ts1: t.ts1,
                        tc1,
                        target: (0, 0),
                    });
                }
            }
            MavMessage::TIMESYNC(t) if t.tc1 != 0 => {
                let mine = self
                    .sent
                    .iter()
                    .any(|(_, m)| matches!(m, MavMessage::TIMESYNC(s) if s.ts1 == t.ts1));
                if mine {
                    self.timesync_replies.push((now_us, t.tc1));
                }
            }
            _ => {}
        }
    }

    /// ArduPilot's routing towards the ground station: messages without a target, with
    /// target system 0 or the ground station's system.
    fn route_to_gcs(&mut self, now_us: u64, r: &mav::Received) {
        let Some(gcs) = self.gcs.as_mut() else {
            return;
        };
        if mav::routed_to(&r.message, gcs.config.sysid) {
            gcs.receive(now_us, r.header, &r.message);
        }
    }

    /// The ground station's frame onto the device's port when it is for the device (its
    /// system, or broadcast), as it came.
    fn route_from_gcs(&mut self, frame: Vec<u8>) {
        let mut rx = Rx::default();
        let Some(r) = rx.push(&frame).pop() else {
            return;
        };
        let for_device = match mav::target_of(&r.message) {
            None => true,
            Some((sys, comp)) => sys == 0 || (sys == self.config.sysid && comp != AUTOPILOT),
        };
        if for_device && !self.board.is_off() {
            self.board.write_loop(frame, self.config.jitter_us);
        }
    }
}

/// `SCHED_LOOP_RATE`: the setting, else the vehicle's default.
fn loop_rate_hz(config: &ApMavlinkConfig) -> u32 {
    config.loop_rate_hz.unwrap_or(match config.vehicle {
        ApVehicle::Copter => 400,
        ApVehicle::Plane => 50,
    })
}

impl Autopilot for ApMavlink {
    board_field!();

    /// The UART delivers `bytes` (a chunk) at `now_us`; the next loop reads them.
    fn take_bytes(&mut self, now_us: u64, bytes: &[u8]) {
        // Loops due before this chunk came read what was there then.
        self.run_loop_until(now_us, false);
        self.board.set_now(now_us);
        self.uart.push((now_us, bytes.to_vec()));
        self.update_health();
    }

    /// One main loop at its instant: GCS receive, mount and camera (50 Hz), GCS send.
    fn run(&mut self) {
        self.gcs_receive();
        if let Some(mut gcs) = self.gcs.take() {
            gcs.poll(self.board.now_us());
            for frame in gcs.transmit() {
                self.route_from_gcs(frame);
            }
            self.gcs = Some(gcs);
        }
        let every = u64::from((self.loop_rate_hz() / 50).max(1));
        if self.board.run_index().is_multiple_of(every) {
            if self.config.mount {
                self.mount_update();
            }
            if self.config.camera {
                self.camera_update();
            }
        }
        self.update_send();
    }

    fn update_health(&mut self) {
        let now = self.board.now_us();
        let fresh = self
            .status
            .as_ref()
            .is_some_and(|s| now.saturating_sub(s.at_us) < 1_000_000);
        let critical = self
            .status
            .as_ref()
            .is_some_and(|s| s.data.failure_flags.bits() & (8 | 16 | 32 | 64 | 128) != 0);
        let healthy = self.mount_info.is_some() && fresh && !critical && !self.board.is_off();
        self.board.set_healthy(healthy);
    }

    fn power_on(&mut self) {
        self.uart.clear();
        self.me = Endpoint::new(self.config.sysid, AUTOPILOT);
        self.rx = Rx::default();
        self.default_streams();
        self.last_heartbeat_ms = None;
        self.last_timesync_ms = None;
        self.mount_found = None;
        self.mount_found_at_us = None;
        self.mount_info = None;
        self.last_info_req_ms = None;
        self.mount_initialised = false;
        self.mount_refused = false;
        self.target = None;
        self.status = None;
        self.attitude = None;
        self.camera_found = None;
        self.camera_info = None;
        self.last_cam_req_ms = None;
        self.capture_req = (None, 0);
    }

    fn power_off(&mut self) {
        self.uart.clear();
    }
}

impl Pilot for ApMavlink {
    const DRIVER: &'static str = "ArduPilot AP_Mount_MAVLink + AP_Camera_MAVLinkCamV2 (simulated)";
    type Frames = MavlinkFrames;

    fn with_seed(seed: u64) -> Self {
        ApMavlink::new(ApMavlinkConfig {
            seed,
            ..ApMavlinkConfig::default()
        })
    }

    fn first_utc_sent_us(&self) -> Option<u64> {
        self.sent.iter().find_map(|(t, m)| match m {
            MavMessage::SYSTEM_TIME(s) if s.time_unix_usec != 0 => Some(*t),
            _ => None,
        })
    }
    fn aircraft(&self) -> &Aircraft {
        &self.aircraft
    }
    fn parse_errors(&self) -> u32 {
        self.rx.errors()
    }
    fn mount_angles(&self) -> Option<(f64, f64)> {
        self.attitude.map(|(_, _, pitch, yaw, _)| (yaw, pitch))
    }

    fn point(&mut self, yaw_deg: f64, pitch_deg: f64) {
        self.set_target(ApMountTarget::Angle {
            roll_deg: 0.0,
            pitch_deg,
            yaw_deg,
            yaw_is_ef: false,
        });
    }
    fn turn(&mut self, yaw_dps: f64, pitch_dps: f64) {
        self.set_target(ApMountTarget::Rate {
            pitch_dps,
            yaw_dps,
            yaw_is_ef: false,
            from_mavlink: false,
        });
    }
    fn zoom(&mut self, rate: i8) {
        self.zoom_rate(rate);
    }
    fn take_picture(&mut self) {
        ApMavlink::take_picture(self);
    }
    fn record(&mut self, on: bool) {
        self.record_video(on);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::FcReboot;
    use crate::sim::ap_siyi::{ApSiyi, ApSiyiConfig};
    use crate::sim::mav::testing::{Driver, byte_us, uart_chunks};
    use protocol_core::mavlink::dialect::GIMBAL_DEVICE_INFORMATION_DATA;
    use protocol_core::mavlink::dialect::{HEARTBEAT_DATA, MavModeFlag, MavState};

    /// The device: the FC's system, the gimbal's component.
    fn device() -> Endpoint {
        Endpoint::new(1, GIMBAL)
    }

    fn request(ts1: i64, target: (u8, u8)) -> MavMessage {
        MavMessage::TIMESYNC(TIMESYNC_DATA {
            tc1: 0,
            ts1,
            target_system: target.0,
            target_component: target.1,
        })
    }

    fn heartbeat(mavtype: MavType) -> MavMessage {
        MavMessage::HEARTBEAT(HEARTBEAT_DATA {
            custom_mode: 0,
            mavtype,
            autopilot: MavAutopilot::MAV_AUTOPILOT_INVALID,
            base_mode: MavModeFlag::empty(),
            system_status: MavState::MAV_STATE_ACTIVE,
            mavlink_version: 3,
        })
    }

    fn set_interval(id: u32, interval_us: f32) -> MavMessage {
        mav::command_long(
            MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
            [id as f32, interval_us, 0.0, 0.0, 0.0, 0.0, 0.0],
            (1, AUTOPILOT),
            0,
        )
    }

    /// One request on the wire from true `t0`, optionally followed at once by a
    /// HEARTBEAT; checks the answer against the UART model and the true start, returns
    /// the answer's error against the FC clock at the request's true start, µs.
    fn timesync_trial(
        ap: &mut ApMavlink,
        d: &mut Driver,
        t0: u64,
        msg: &MavMessage,
        trailing: bool,
    ) -> f64 {
        let mut dev = device();
        let req = dev.frame(msg);
        let mut wire = req.clone();
        if trailing {
            wire.extend(dev.frame(&heartbeat(MavType::MAV_TYPE_GIMBAL)));
        }
        let baud = ap.config.baud;
        let chunks = uart_chunks(t0, baud, &wire);
        let req_end = chunks
            .iter()
            .scan(0, |n, (at, c)| {
                *n += c.len();
                Some((*n, *at))
            })
            .find(|(n, _)| *n >= req.len())
            .map(|(_, at)| at)
            .unwrap();
        let answers = ap.timesync_answers.len();
        d.deliver(ap, &chunks);
        d.run_until(ap, t0 + 30_000);
        assert_eq!(ap.timesync_answers.len(), answers + 1);
        let a = ap.timesync_answers.last().unwrap().clone();
        let MavMessage::TIMESYNC(t) = msg else {
            unreachable!()
        };
        assert_eq!((a.ts1, a.target), (t.ts1, (0, 0)));
        // Read by the first loop after the chunk that completed it, not at arrival.
        let first_loop = *d.wakeups.iter().find(|&&w| w >= req_end).unwrap();
        assert_eq!(a.handled_at_us, first_loop);
        // The UART model: the last chunk delivered by then, the bytes after the request.
        let delivered: Vec<_> = chunks.iter().filter(|(at, _)| *at <= first_loop).collect();
        let stamp = ap.fc_us(delivered.last().unwrap().0);
        let total: usize = delivered.iter().map(|(_, c)| c.len()).sum();
        let after = total - req.len();
        let len = match ap.config.timesync_len {
            TimesyncLen::Frame => req.len(),
            TimesyncLen::PayloadSize => TIMESYNC_PAYLOAD_SIZE,
        };
        let expected = stamp - 86 * (len + after) as u64;
        assert_eq!(a.tc1, (expected * 1000) as i64, "the UART estimate");
        // On the wire: in the burst of that loop (no transport jitter here), ts1 echoed.
        let on_wire: Vec<_> = d
            .frames()
            .into_iter()
            .filter(|(_, r)| matches!(&r.message, MavMessage::TIMESYNC(s) if s.ts1 == t.ts1))
            .collect();
        assert_eq!(on_wire.len(), 1);
        assert_eq!(on_wire[0].0, a.handled_at_us);
        assert_eq!(a.sent_at_us, a.handled_at_us);
        assert!(
            d.wakeups.contains(&on_wire[0].0),
            "leaves at a loop instant"
        );
        let MavMessage::TIMESYNC(reply) = &on_wire[0].1.message else {
            unreachable!()
        };
        assert_eq!(
            (reply.tc1, reply.target_system, reply.target_component),
            (a.tc1, 0, 0)
        );
        a.tc1 as f64 / 1000.0 - ap.fc_us(t0) as f64
    }

    #[test]
    fn ardupilot_answers_timesync_with_the_uart_receive_estimate_of_the_request_start() {
        let mut ap = ApMavlink::new(ApMavlinkConfig {
            ppm: 23.0,
            jitter_us: 0,
            ..ApMavlinkConfig::default()
        });
        assert_eq!(ap.loop_rate_hz(), 400);
        let mut d = Driver::new();
        let byte = byte_us(115_200);
        for i in 0..40u64 {
            let t0 = 1_000_000 + i * 123_457;
            // Targeted at the autopilot: a full 30-byte frame.
            let msg = request(7_000_000_000_000 + i as i64, (1, AUTOPILOT));
            let err = timesync_trial(&mut ap, &mut d, t0, &msg, i % 2 == 1);
            // Late by the whole-µs byte time's 0.8 µs a byte, at most one byte time
            // plus the chunk stamp's rounding; never early.
            assert!((-1.0..=byte + 1.0).contains(&err), "trial {i}: {err} µs");
        }
        // A broadcast request is answered too; one for another component is not.
        let t0 = 7_000_000;
        let err = timesync_trial(&mut ap, &mut d, t0, &request(5, (0, 0)), false);
        assert!((-1.0..=byte + 1.0).contains(&err));
        let n = ap.timesync_answers.len();
        let mut dev = device();
        d.deliver(
            &mut ap,
            &uart_chunks(8_000_000, 115_200, &dev.frame(&request(6, (1, CAMERA)))),
        );
        d.run_until(&mut ap, 8_100_000);
        assert_eq!(ap.timesync_answers.len(), n);
    }

    #[test]
    fn ardupilot_timesync_estimate_with_payload_size_reading() {
        let mut ap = ApMavlink::new(ApMavlinkConfig {
            jitter_us: 0,
            timesync_len: TimesyncLen::PayloadSize,
            ..ApMavlinkConfig::default()
        });
        let mut d = Driver::new();
        let byte = byte_us(115_200);
        // No targets and a small ts1: MAVLink 2 trims the frame to 24 bytes; the driver
        // still counts 30, so the estimate is 6 bytes early.
        for i in 0..10u64 {
            let msg = request(3_000_000_000 + i as i64, (0, 0));
            assert_eq!(device().frame(&msg).len(), 24);
            let err = timesync_trial(&mut ap, &mut d, 2_000_000 + i * 77_777, &msg, i % 2 == 0);
            let early = -6.0 * 86.0;
            assert!(
                (early - 1.0..=early + byte + 1.0).contains(&err),
                "trial {i}: {err} µs"
            );
        }
        // The frame reading on the same request is within a byte.
        let mut ap = ApMavlink::new(ApMavlinkConfig {
            jitter_us: 0,
            ..ApMavlinkConfig::default()
        });
        let mut d = Driver::new();
        let msg = request(3_000_000_000, (0, 0));
        let err = timesync_trial(&mut ap, &mut d, 2_000_000, &msg, true);
        assert!((-1.0..=byte + 1.0).contains(&err), "{err} µs");
    }

    #[test]
    fn ardupilot_loop_phase_sweeps_the_ms_grid_and_system_time_gives_the_utc_shift() {
        let mut ap = ApMavlink::new(ApMavlinkConfig {
            ppm: 11.0,
            utc_valid_at_us: 1_000_000,
            ..ApMavlinkConfig::default()
        });
        let mut d = Driver::new();
        let mut dev = device();
        d.deliver(
            &mut ap,
            &uart_chunks(
                10_000,
                115_200,
                &dev.frame(&set_interval(SYSTEM_TIME_DATA::ID, 100_000.0)),
            ),
        );
        d.run_until(&mut ap, 31_000_000);
        assert!(ap.acks.is_empty());
        let frames = d.frames();
        assert!(frames.iter().any(|(_, r)| matches!(&r.message,
            MavMessage::COMMAND_ACK(a) if a.result == MavResult::MAV_RESULT_ACCEPTED)));

        // Loops: 400 Hz on the IMU, their phase against the FC's ms grid not locked.
        let first_3s: Vec<u64> = d
            .wakeups
            .iter()
            .copied()
            .filter(|&w| w < 3_000_000)
            .collect();
        assert!(
            (1195..=1205).contains(&first_3s.len()),
            "{}",
            first_3s.len()
        );
        let mut bins = [0u32; 10];
        for &w in &first_3s {
            bins[(ap.fc_us(w) % 1000 / 100) as usize] += 1;
        }
        assert!(bins.iter().all(|&b| b > 0), "{bins:?}");

        // SYSTEM_TIME at 10 Hz; the Unix time 0 until set; both fields from one reading.
        let times: Vec<SYSTEM_TIME_DATA> = frames
            .iter()
            .filter_map(|(_, r)| match &r.message {
                MavMessage::SYSTEM_TIME(s) => Some(s.clone()),
                _ => None,
            })
            .collect();
        assert!((305..=312).contains(&times.len()), "{}", times.len());
        // Due every 100 ms of the FC clock, sent by the first loop after (a 2.5 ms
        // loop, up to 0.5 ms late), the ms truncated.
        for w in times.windows(2) {
            let dt = w[1].time_boot_ms - w[0].time_boot_ms;
            assert!((97..=103).contains(&dt), "{dt}");
        }
        let shift = ap.fc_utc_us(5_000_000) as i64 - ap.fc_us(5_000_000) as i64;
        let set: Vec<i64> = times
            .iter()
            .filter(|s| s.time_unix_usec != 0)
            .map(|s| s.time_unix_usec as i64 - 1000 * i64::from(s.time_boot_ms) - shift)
            .collect();
        assert!(set.len() >= 295 && set.len() < times.len(), "{}", set.len());
        assert!(set.iter().all(|d| (0..1000).contains(d)));
        let min = *set.iter().min().unwrap();
        assert!((0..=50).contains(&min), "min d - shift = {min} µs");
        // No Unix time before the clock was set.
        let first_set = ap.first_utc_sent_us().unwrap();
        assert!((1_000_000..1_110_000).contains(&first_set));
    }

    #[test]
    fn ardupilot_mount_updates_at_50_hz_in_the_400_hz_loop() {
        let mut ap = ApMavlink::new(ApMavlinkConfig {
            camera: false,
            ..ApMavlinkConfig::default()
        });
        let mut d = Driver::new();
        let mut dev = device();
        d.deliver(
            &mut ap,
            &uart_chunks(
                50_000,
                115_200,
                &dev.frame(&heartbeat(MavType::MAV_TYPE_GIMBAL)),
            ),
        );
        d.run_until(&mut ap, 100_000);
        assert_eq!(ap.mount_found, Some(1));
        let info = MavMessage::GIMBAL_DEVICE_INFORMATION(GIMBAL_DEVICE_INFORMATION_DATA {
            pitch_min: -1.5,
            pitch_max: 0.5,
            yaw_min: -3.0,
            yaw_max: 3.0,
            ..GIMBAL_DEVICE_INFORMATION_DATA::default()
        });
        d.deliver(&mut ap, &uart_chunks(150_000, 115_200, &dev.frame(&info)));
        d.run_until(&mut ap, 200_000);
        assert!(ap.mount_initialised);
        ap.set_target(ApMountTarget::Angle {
            roll_deg: 0.0,
            pitch_deg: -30.0,
            yaw_deg: 10.0,
            yaw_is_ef: false,
        });
        d.run_until(&mut ap, 2_200_000);
        let times: Vec<u64> = ap.set_attitudes.iter().map(|(t, _)| *t).collect();
        assert!((99..=101).contains(&times.len()), "{}", times.len());
        for w in times.windows(2) {
            // Eight loops of 2 500 µs, each up to 500 µs late.
            let dt = w[1] - w[0];
            assert!((19_499..=20_501).contains(&dt), "{dt}");
        }
        assert!(times.iter().all(|t| d.wakeups.contains(t)));
        // AUTOPILOT_STATE at the enabled 50 Hz, from the loop's stream sender.
        let states = ap
            .sent_of(AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA::ID)
            .count();
        assert!((98..=103).contains(&states), "{states}");

        // Plane's 50 Hz loop refuses the 50 Hz AUTOPILOT_STATE: never initialised.
        let mut plane = ApMavlink::new(ApMavlinkConfig {
            vehicle: ApVehicle::Plane,
            camera: false,
            ..ApMavlinkConfig::default()
        });
        let mut d = Driver::new();
        let mut dev = device();
        let hb = dev.frame(&heartbeat(MavType::MAV_TYPE_GIMBAL));
        d.deliver(&mut plane, &uart_chunks(50_000, 115_200, &hb));
        d.deliver(
            &mut plane,
            &uart_chunks(150_000, 115_200, &dev.frame(&info)),
        );
        d.run_until(&mut plane, 1_000_000);
        assert!(plane.mount_refused && !plane.mount_initialised);
        let loops = d.wakeups.iter().filter(|&&w| w < 1_000_000).count();
        assert!((49..=51).contains(&loops), "{loops}");
    }

    #[test]
    fn telemetry_port_shares_the_clock_and_aircraft_of_the_board() {
        let mut siyi = ApSiyi::new(ApSiyiConfig {
            ppm: 17.0,
            ..ApSiyiConfig::default()
        });
        let mut tel = ApMavlink::telemetry(siyi.clock().clone(), siyi.aircraft, 9, 1);
        assert!(!tel.config.mount && !tel.config.camera);
        for t in [0, 1_234_567, 20_000_000] {
            assert_eq!(tel.fc_us(t), siyi.fc_us(t));
            assert_eq!(tel.fc_utc_us(t), siyi.fc_utc_us(t));
            assert_eq!(tel.aircraft.position_e7(t), siyi.aircraft.position_e7(t));
        }
        // Both ports reboot together: the clocks stay equal.
        let r = FcReboot {
            boot_clock_us: 1_500,
            utc_shift_us: 40_000,
            ..FcReboot::default()
        };
        siyi.reboot(5_000_000, r);
        tel.reboot(5_000_000, r);
        assert_eq!(tel.clock(), siyi.clock());
        let on = tel.boots()[1].at_us;
        let mut d = Driver::new();
        d.run_until(&mut tel, on + 2_000_000);
        assert!(d.wakeups.iter().all(|&w| w < 5_000_000 || w >= on));
        assert_eq!(tel.fc_us(on + 1_000_000), siyi.fc_us(on + 1_000_000));
        assert_eq!(
            tel.fc_utc_us(on + 1_000_000),
            siyi.fc_utc_us(on + 1_000_000)
        );
        // The telemetry port streams on request; no mount or camera traffic.
        assert!(tel.set_attitudes.is_empty());
        assert!(
            tel.sent
                .iter()
                .all(|(_, m)| matches!(m, MavMessage::HEARTBEAT(_) | MavMessage::TIMESYNC(_)))
        );
    }
}
