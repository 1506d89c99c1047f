//! A simulated ArduPilot with a MAVLink gimbal (`MNT1_TYPE` 6, `AP_Mount_MAVLink`:
//! `mount.rs`) and a MAVLink camera (`CAM1_TYPE` 6, `AP_Camera_MAVLinkCamV2`: `camera.rs`)
//! on one serial port (`SERIALn_PROTOCOL` 2: its GCS link, `gcs.rs`), as
//! docs/src/autopilots/ardupilot.md describes what ArduPilot sends and reads:
//!
//! - **Loop.** The main loop runs at `SCHED_LOOP_RATE` ([`ApMavlink::loop_rate_hz`]:
//!   Copter 400 Hz, Plane 50 Hz), paced by the IMU ([`MainLoop::Imu`],
//!   [`ApMavlinkConfig::imu_ppm`], `loop_jitter_us`), so its phase against the FC's
//!   millisecond grid is not locked. Each loop: the GCS receive processing handles the
//!   bytes the UART delivered so far (a frame that arrives is acted on in the next loop,
//!   never at arrival), the mount and camera updates run every (loop rate / 50)-th loop
//!   (50 Hz), and the GCS send processing sends what is due. What one loop writes leaves
//!   in one burst after a transport jitter (`jitter_us`).
//! - **Telemetry port** ([`ApMavlink::telemetry`]): an ArduPilot port without a MAVLink
//!   mount or camera that shares the FC clock and the aircraft of another simulated
//!   driver on the same board (e.g. [`Autopilot::clock`] of [`super::ap_siyi::ApSiyi`]).
//! - **Reboot** ([`Autopilot::reboot`], on the [`Board`]): silent for the off time, then
//!   a new boot clock, streams back to the defaults, the drivers searching again.

use std::collections::BTreeMap;

use protocol_core::mavlink::dialect::{
    CAMERA_CAPTURE_STATUS_DATA, CAMERA_IMAGE_CAPTURED_DATA, CAMERA_INFORMATION_DATA,
    COMMAND_ACK_DATA, GIMBAL_DEVICE_ATTITUDE_STATUS_DATA, GIMBAL_DEVICE_INFORMATION_DATA,
    GIMBAL_DEVICE_SET_ATTITUDE_DATA, MavType,
};
use protocol_core::mavlink::{Header, MavMessage};

use super::board::{Aircraft, Autopilot, Board, MainLoop, board_field};
use super::describe::MavlinkFrames;
use super::ground::GroundLink;
use super::mav::{self, AUTOPILOT, Endpoint, Rx, TimesyncAnswer};
use super::pilot::Pilot;
use super::qgc::Qgc;
use super::{FcClock, XorShift};

mod camera;
mod gcs;
mod mount;
#[cfg(test)]
mod tests;

pub use crate::sim::mount_target::MountTarget;

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
    /// The newest source: a location target goes to a gimbal that can point at one as
    /// MAV_CMD_DO_SET_ROI_LOCATION (else, as released ArduPilot does, as angles).
    pub roi_to_device: bool,
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
            roi_to_device: false,
        }
    }
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

impl<T> Heard<T> {
    /// `data` from `header`, read at true time `at_us`.
    fn new(at_us: u64, header: Header, data: T) -> Self {
        Heard {
            at_us,
            header,
            data,
        }
    }
}

/// The simulated ArduPilot.
#[derive(Debug)]
pub struct ApMavlink {
    /// Settings.
    pub config: ApMavlinkConfig,
    /// A ground station attached to the FC's routing.
    pub gcs: Option<Qgc>,
    /// A ground app on another of the FC's links (`gcs.rs`).
    pub ground: Option<GroundLink>,
    board: Board,
    /// Chunks the UART delivered since the last loop: (true time, bytes).
    uart: Vec<(u64, Vec<u8>)>,
    me: Endpoint,
    rx: Rx,
    /// Stream intervals of the device's port, µs.
    pub intervals: BTreeMap<u32, u64>,
    next_due: BTreeMap<u32, u64>,
    last_heartbeat_ms: Option<u64>,
    ground_heartbeat_ms: Option<u64>,
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
    pub target: Option<MountTarget>,
    /// The location last sent to the device, with when (FC ms).
    roi_sent: Option<((i32, i32, f32), u64)>,
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
            gcs: None,
            ground: None,
            board: Board::new(clock, XorShift::new(config.seed), main_loop).flying(aircraft),
            uart: Vec::new(),
            me: Endpoint::new(config.sysid, AUTOPILOT),
            rx: Rx::default(),
            intervals: BTreeMap::new(),
            next_due: BTreeMap::new(),
            last_heartbeat_ms: None,
            ground_heartbeat_ms: None,
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
            roi_sent: None,
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
}

/// The system of the device a HEARTBEAT from `h` announces, when it is the first of the
/// `(type, component)` a driver looks for (none found yet).
fn announced(
    found: Option<u8>,
    h: &Header,
    mavtype: MavType,
    (want, comp): (MavType, u8),
) -> Option<u8> {
    (found.is_none() && mavtype == want && h.component_id == comp).then_some(h.system_id)
}

/// A message from `h` comes from the device a driver found (system `found`), component
/// `comp`.
fn from_device(found: Option<u8>, h: &Header, comp: u8) -> bool {
    found == Some(h.system_id) && h.component_id == comp
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

    /// Frames the MAVLink receiver dropped for a bad checksum or length.
    fn parse_errors(&self) -> u32 {
        self.rx.errors()
    }

    /// The UART delivers `bytes` (a chunk) at `now_us`; the next loop reads them.
    fn take_bytes(&mut self, now_us: u64, bytes: &[u8]) {
        // Loops due before this chunk came read what was there then.
        self.run_loop_until(now_us, false);
        self.board.set_now(now_us);
        self.uart.push((now_us, bytes.to_vec()));
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
        self.ground_run();
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
        self.roi_sent = None;
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

    fn first_utc_sent_us(&self) -> Option<u64> {
        self.sent.iter().find_map(|(t, m)| match m {
            MavMessage::SYSTEM_TIME(s) if s.time_unix_usec != 0 => Some(*t),
            _ => None,
        })
    }
    fn mount_angles(&self) -> Option<(f64, f64)> {
        self.attitude.map(|(_, _, pitch, yaw, _)| (yaw, pitch))
    }

    fn point(&mut self, yaw_deg: f64, pitch_deg: f64) {
        self.set_target(MountTarget::Angle {
            roll_deg: 0.0,
            pitch_deg,
            yaw_deg,
            yaw_is_ef: false,
        });
    }
    fn turn(&mut self, yaw_dps: f64, pitch_dps: f64) {
        self.set_target(MountTarget::Rate {
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
