//! A simulated ArduPilot `AP_Mount_XFRobot` driver: the flight controller as an XF Robot
//! GCU sees it, following the driver's code as docs/src/autopilots/ardupilot.md describes
//! what it sends and reads.
//!
//! - **Loop.** `update()` runs at 50 Hz on the FC's own crystal ([`ApXfRobotConfig::ppm`]),
//!   each run a few hundred microseconds late ([`ApXfRobotConfig::loop_jitter_us`]), and
//!   sends one set-attitude package (72 bytes, order 0x10, version 0x02) every run,
//!   healthy or not. Every package one run writes leaves in one burst after a per-run
//!   transport jitter (uniform in `0..ApXfRobotConfig::jitter_us`).
//! - **Set attitude.** Control roll, pitch (earth frame) and yaw (body frame) in 0.01°
//!   from the mount target: angles as they are, rates integrated at 50 Hz into the angle
//!   target within the mount's limits (ArduPilot's `update_angle_target_from_rate`), an
//!   earth-frame yaw turned into a body-frame one with the vehicle's yaw. Status: INS valid
//!   and control valid. Vehicle roll, pitch, yaw (±18000 in the u16 field), accelerations
//!   and velocities; request code 0x01; sub frame: longitude, latitude, altitude (mm),
//!   satellites, the GPS time of the last fix (week and time of week in ms: the value
//!   the GPS driver holds between fixes), relative altitude (mm).
//! - **GPS.** Fixes at [`ApXfRobotConfig::gps_hz`] on GPS-time boundaries, reaching the
//!   FC [`ApXfRobotConfig::gps_latency_us`] after their epoch; GPS time is UTC plus
//!   [`ApXfRobotConfig::leap_seconds`]. Before [`ApXfRobotConfig::gps_valid_at_us`]: no
//!   fix, no position, week and time of week 0.
//! - **Simple commands** (73 bytes: zero main and sub frames but the request code, order,
//!   one parameter), only while healthy: 0x20 shutter 1, 0x21 record 1/0 (refused while a
//!   request waits for its reply; 1 s time-out), 0x22/0x23/0x24 zoom 1, 0x26 focus 1
//!   (auto focus), 0x74 picture in picture (lens 0..3 -> 4, 2, 1, 3).
//! - **Parser** (ArduPilot's byte state machine, its quirks included): `8A 5E`, a length
//!   byte pair of which only the low byte counts, 10..=80 accepted, CRC-16/XMODEM over all
//!   but the last two bytes, stored high byte first. Bytes before a header are kept in
//!   the buffer until it overflows (80 bytes), so a stray byte from the gimbal spoils
//!   the next reply. A package shorter than 73 bytes is accepted and ignored.
//! - **Reading a reply** (at least 73 bytes): earth-frame roll (bytes 18..19) and pitch
//!   (20..21) and body-frame yaw (`angle_z`, 16..17) in 0.01°, the versions (38, 39) once,
//!   the order (69) and its execution state (70) for shutter and record.
//! - **Health.** A reply of at least 73 bytes within the last second.
//!
//! - **Reboot** ([`Autopilot::reboot`], on the [`Board`]): then the driver starts from
//!   scratch on the new boot clock (neutral target, no attitude, unhealthy until the
//!   first reply); the GPS has no fix (week and time of week 0) until the new boot's UTC
//!   is valid, and its UTC is shifted as the boot's ([`super::FcReboot::utc_shift_us`]).
//!
//! Time is true time in µs. The reference for the bridge's time sync is the GPS's UTC,
//! [`ApXfRobot::gps_utc_us`] (the FC only relays the time of the last fix).

use super::board::{Autopilot, Board, board_field};
use super::describe::GcuFrames;
use super::mount_target::MountTarget;
use super::pilot::ClockSettings;
use super::pilot::Pilot;
use protocol_core::gcu::{
    self, Header, HostFrames, HostMain, HostPacket, HostStatus, HostSub, Message, Raw,
};
use protocol_core::wire::crc16_xmodem;

/// Unix time of the GPS epoch, µs.
const GPS_EPOCH_UNIX_US: u64 = 315_964_800_000_000;
/// A GPS week, µs.
const WEEK_US: u64 = 604_800_000_000;
/// Largest reply the driver takes.
pub const RECV_LENGTH_MAX: usize = 80;
/// Smallest reply the driver reads.
pub const REPLY_MIN: usize = 73;

/// Settings of the simulated driver.
#[derive(Debug, Clone)]
pub struct ApXfRobotConfig {
    /// FC crystal error, ppm.
    pub ppm: f64,
    /// Per-run transport jitter bound, µs.
    pub jitter_us: u64,
    /// Lateness of each run, µs (uniform in `0..loop_jitter_us`).
    pub loop_jitter_us: u64,
    /// The FC's clock reads this at true time 0, µs.
    pub boot_us: u64,
    /// Seed of the random jitter.
    pub seed: u64,
    /// UTC (as GPS keeps it) at true time 0, µs since the Unix epoch.
    pub utc_at_zero_us: u64,
    /// GPS − UTC, seconds.
    pub leap_seconds: u8,
    /// GPS fix rate.
    pub gps_hz: u32,
    /// From a fix's epoch to the FC knowing it, µs.
    pub gps_latency_us: u64,
    /// First fix, true µs.
    pub gps_valid_at_us: u64,
    /// The version byte (ArduPilot: 0x02).
    pub version: u8,
    /// Send the 50 Hz set-attitude packages (false: only what the test writes).
    pub send_attitude: bool,
}

impl Default for ApXfRobotConfig {
    fn default() -> Self {
        ApXfRobotConfig {
            ppm: 0.0,
            jitter_us: 10_000,
            loop_jitter_us: 500,
            boot_us: 3_000_000,
            seed: 1,
            // 2026-11-23T10:00:00.123456Z
            utc_at_zero_us: 1_795_428_000_123_456,
            leap_seconds: 18,
            gps_hz: 10,
            gps_latency_us: 0,
            gps_valid_at_us: 0,
            version: gcu::VERSION_ARDUPILOT,
            send_attitude: true,
        }
    }
}

/// A document host in place of ArduPilot's set-attitude: every run sends `order` with
/// these control quantities (status: INS and control valid), the carrier's data and the
/// sub frame as ArduPilot fills them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HostControl {
    /// The order of every package.
    pub order: u8,
    /// Roll control quantity.
    pub roll: i16,
    /// Pitch control quantity.
    pub pitch: i16,
    /// Yaw control quantity.
    pub yaw: i16,
}

/// A package the driver wrote.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Sent {
    /// True time it was written.
    pub at_us: u64,
    /// Its order byte.
    pub order: u8,
    /// Its bytes.
    pub bytes: Vec<u8>,
}

/// A package the parser accepted (CRC valid, 10..=80 bytes).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Reply {
    /// True time its last byte arrived.
    pub at_us: u64,
    /// Its bytes.
    pub bytes: Vec<u8>,
}

impl Reply {
    fn i16_at(&self, at: usize) -> i16 {
        i16::from_le_bytes([self.bytes[at], self.bytes[at + 1]])
    }

    fn u16_at(&self, at: usize) -> u16 {
        u16::from_le_bytes([self.bytes[at], self.bytes[at + 1]])
    }

    /// Earth-frame roll, 0.01° (bytes 18..19).
    #[must_use]
    pub fn roll_cdeg(&self) -> i16 {
        self.i16_at(18)
    }

    /// Earth-frame pitch, 0.01° (bytes 20..21).
    #[must_use]
    pub fn pitch_cdeg(&self) -> i16 {
        self.i16_at(20)
    }

    /// Body-frame yaw (`angle_z`), 0.01° (bytes 16..17).
    #[must_use]
    pub fn yaw_bf_cdeg(&self) -> i16 {
        self.i16_at(16)
    }

    /// Distance to the target, 0.1 m (bytes 43..46).
    #[must_use]
    pub fn distance_dm(&self) -> i32 {
        i32::from_le_bytes(self.bytes[43..47].try_into().unwrap())
    }

    /// The target's longitude, latitude (1e-7 degree) and altitude (mm) (bytes 47..58).
    #[must_use]
    pub fn target(&self) -> (i32, i32, i32) {
        let i32_at = |at: usize| i32::from_le_bytes(self.bytes[at..at + 4].try_into().unwrap());
        (i32_at(47), i32_at(51), i32_at(55))
    }

    /// Thermal camera status of ArduPilot's revision (byte 63).
    #[must_use]
    pub fn thermal_status(&self) -> u8 {
        self.bytes[63]
    }

    /// Zoom ratio of the visible camera, 0.1x (bytes 59..60).
    #[must_use]
    pub fn zoom_rgb_x10(&self) -> u16 {
        self.u16_at(59)
    }

    /// Zoom ratio of the thermal camera, 0.1x (bytes 61..62).
    #[must_use]
    pub fn zoom_thermal_x10(&self) -> u16 {
        self.u16_at(61)
    }

    /// Camera status of ArduPilot's revision (bytes 64..65).
    #[must_use]
    pub fn camera_status(&self) -> u16 {
        self.u16_at(64)
    }

    /// Main-frame camera status (bytes 6..7).
    #[must_use]
    pub fn main_status(&self) -> u16 {
        self.u16_at(6)
    }

    /// Error code (bytes 41..42).
    #[must_use]
    pub fn error_code(&self) -> u16 {
        self.u16_at(41)
    }

    /// The order answered (byte 69).
    #[must_use]
    pub fn order(&self) -> u8 {
        self.bytes[69]
    }

    /// The execution state (byte 70), when the reply has one.
    #[must_use]
    pub fn execution(&self) -> Option<u8> {
        (self.bytes.len() >= REPLY_MIN).then(|| self.bytes[70])
    }
}

/// ArduPilot's parser states.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum ParseState {
    Header1,
    Header2,
    LengthLow,
    LengthHigh,
    Data,
    CrcHigh,
    CrcLow,
}

/// The simulated `AP_Mount_XFRobot`.
#[derive(Debug)]
pub struct ApXfRobot {
    /// The simulated driver's settings (rates, GPS, seed).
    pub config: ApXfRobotConfig,
    /// The mount target (none: neutral, 0/0/0).
    pub target: Option<MountTarget>,
    /// A document host's control in place of ArduPilot's set attitude.
    pub host_control: Option<HostControl>,
    board: Board,
    /// The angle target: roll, pitch, yaw (deg), yaw in the earth frame.
    angle: (f64, f64, f64, bool),
    // Parser.
    buf: Vec<u8>,
    state: ParseState,
    len_expected: u8,
    crc: u16,
    /// `attitude_latest`: true µs of arrival, earth-frame roll, pitch, body-frame yaw (deg).
    pub attitude: Option<(u64, f64, f64, f64)>,
    got_firmware_version: bool,
    /// Recording request: (true µs, start).
    record_request: Option<(u64, bool)>,
    /// `GCS_SEND_TEXT` messages: (true µs, text).
    pub texts: Vec<(u64, String)>,
    /// Every package written.
    pub sent: Vec<Sent>,
    /// Every package the parser accepted.
    pub replies: Vec<Reply>,
}

impl ApXfRobot {
    /// A driver that starts at true time 0.
    #[must_use]
    pub fn new(config: ApXfRobotConfig) -> Self {
        let board = Board::scheduler_50hz(config.clock(), config.seed, config.loop_jitter_us);
        ApXfRobot {
            config,
            target: None,
            host_control: None,
            board,
            angle: (0.0, 0.0, 0.0, false),
            buf: Vec::new(),
            state: ParseState::Header1,
            len_expected: 0,
            crc: 0,
            attitude: None,
            got_firmware_version: false,
            record_request: None,
            texts: Vec::new(),
            sent: Vec::new(),
            replies: Vec::new(),
        }
    }

    /// UTC as the GPS keeps it (µs since the Unix epoch) at true time `t_us`: the
    /// reference of the time sync (shifted by the reboots before `t_us`). The FC's own
    /// UTC ([`Autopilot::fc_utc_us`], what a MAVLink telemetry port of the same autopilot
    /// tells) differs from it by the crystal's error.
    #[must_use]
    pub fn gps_utc_us(&self, t_us: u64) -> u64 {
        self.board.clock().gps_utc_us(t_us)
    }

    /// GPS week and time of week (ms) of the last fix the FC knows at true time `t_us`
    /// (zeros before the first fix of the boot in effect).
    #[must_use]
    pub fn gps_time(&self, t_us: u64) -> (u16, u32) {
        if !self.board.clock().utc_valid(t_us) {
            return (0, 0);
        }
        let gps_us = self.gps_utc_us(t_us) + u64::from(self.config.leap_seconds) * 1_000_000
            - GPS_EPOCH_UNIX_US;
        let period = 1_000_000 / u64::from(self.config.gps_hz.max(1));
        let epoch = (gps_us - self.config.gps_latency_us) / period * period;
        ((epoch / WEEK_US) as u16, ((epoch % WEEK_US) / 1000) as u32)
    }

    /// Queues a package for the current run (one burst per run).
    fn write(&mut self, order: u8, bytes: Vec<u8>) {
        if self.board.is_off() {
            return;
        }
        self.sent.push(Sent {
            at_us: self.board.now_us(),
            order,
            bytes: bytes.clone(),
        });
        self.write_raw(bytes);
    }

    /// Writes bytes now, in the current burst (garbage, vectors).
    pub fn write_raw(&mut self, bytes: Vec<u8>) {
        if self.board.is_off() {
            return;
        }
        self.board.write_run(bytes, self.config.jitter_us);
    }

    /// A package with order `order`, parameters `params`, and the data frames of a
    /// simple command (zero but the request code).
    pub fn send_command(&mut self, order: u8, params: &[u8]) {
        let frames = HostFrames {
            main: HostMain {
                sub_request: 0x01,
                ..HostMain::default()
            },
            sub: HostSub::ABSENT,
        };
        let p = HostPacket {
            header: Header::new(self.config.version),
            frames,
            message: Message::Raw(Raw {
                id: order,
                payload: params,
            }),
        };
        let mut buf = [0u8; gcu::MAX_FRAME_LEN];
        let n = p.emit(&mut buf).unwrap();
        self.write(order, buf[..n].to_vec());
    }

    /// `send_simple_command`: only while healthy.
    fn simple_command(&mut self, order: u8, param: u8) -> bool {
        if !self.board.healthy() {
            return false;
        }
        self.send_command(order, &[param]);
        true
    }

    fn text(&mut self, s: String) {
        self.texts.push((self.board.now_us(), s));
    }

    /// `take_picture()`.
    pub fn take_picture(&mut self) -> bool {
        self.text("XFRobot: take picture".into());
        self.simple_command(0x20, 0x01)
    }

    /// `record_video(start)`.
    pub fn record_video(&mut self, start: bool) -> bool {
        if self.record_request.is_some() {
            return false;
        }
        if self.simple_command(0x21, u8::from(start)) {
            self.record_request = Some((self.board.now_us(), start));
            return true;
        }
        false
    }

    /// `set_zoom(RATE, rate)`: in (> 0), out (< 0), stop.
    pub fn set_zoom_rate(&mut self, rate: f64) -> bool {
        let order = if rate > 0.0 {
            0x22
        } else if rate < 0.0 {
            0x23
        } else {
            0x24
        };
        self.simple_command(order, 0x01)
    }

    /// `set_focus(AUTO)`.
    pub fn autofocus(&mut self) -> bool {
        self.simple_command(0x26, 0x01)
    }

    /// `set_lens(lens)`: 0 RGB, 1 thermal, 2 RGB with thermal PiP, 3 thermal with RGB PiP.
    pub fn set_lens(&mut self, lens: u8) -> bool {
        const TABLE: [u8; 4] = [4, 2, 1, 3];
        match TABLE.get(usize::from(lens)) {
            Some(&t) => self.simple_command(0x74, t),
            None => false,
        }
    }

    /// The vehicle's yaw, degrees.
    fn vehicle_yaw_deg(&self) -> f64 {
        self.board.aircraft().attitude_deg(self.board.now_us()).2
    }

    /// `update_mnt_target` + `update_angle_target_from_rate`.
    fn update_target(&mut self) {
        const DT: f64 = 0.02;
        let (roll_min, roll_max) = (-30.0, 30.0);
        let (pitch_min, pitch_max) = (-90.0, 20.0);
        let (yaw_min, yaw_max) = (-180.0, 180.0);
        match self.target {
            // This driver is given angles and rates only; the modes hold neutral.
            None
            | Some(MountTarget::Retract | MountTarget::Neutral | MountTarget::Location { .. }) => {
                self.angle = (0.0, 0.0, 0.0, false);
            }
            Some(MountTarget::Angle {
                roll_deg,
                pitch_deg,
                yaw_deg,
                yaw_is_ef,
            }) => {
                let yaw = if yaw_is_ef {
                    yaw_deg
                } else {
                    f64::clamp(wrap180(yaw_deg), yaw_min, yaw_max)
                };
                self.angle = (
                    roll_deg.clamp(roll_min, roll_max),
                    pitch_deg.clamp(pitch_min, pitch_max),
                    yaw,
                    yaw_is_ef,
                );
            }
            Some(MountTarget::Rate {
                pitch_dps,
                yaw_dps,
                yaw_is_ef,
                ..
            }) => {
                let vy = self.vehicle_yaw_deg();
                let (roll, pitch, mut yaw, ef) = self.angle;
                let pitch = (pitch + pitch_dps * DT).clamp(pitch_min, pitch_max);
                if ef != yaw_is_ef {
                    yaw = if yaw_is_ef {
                        wrap180(yaw + vy)
                    } else {
                        wrap180(yaw - vy)
                    };
                }
                yaw += yaw_dps * DT;
                yaw = if yaw_is_ef {
                    wrap180(yaw)
                } else {
                    yaw.clamp(yaw_min, yaw_max)
                };
                self.angle = (roll, pitch, yaw, yaw_is_ef);
            }
        }
    }

    /// `send_target_angles` (or the document host's package).
    fn send_attitude(&mut self) {
        let t = self.board.now_us();
        let (r, p, y) = self.board.aircraft().attitude_deg(t);
        let (troll, tpitch, tyaw, ef) = self.angle;
        let yaw_bf = if ef { wrap180(tyaw - y) } else { tyaw };
        let cd = |deg: f64, lim: f64| (deg * 100.0).clamp(-lim, lim) as i16;
        let (order, roll_c, pitch_c, yaw_c) = match self.host_control {
            Some(h) => (h.order, h.roll, h.pitch, h.yaw),
            None => (
                0x10,
                cd(troll, 18000.0),
                cd(tpitch, 9000.0),
                cd(yaw_bf, 18000.0),
            ),
        };
        let v = self.board.aircraft().speed_m_s;
        let h = self.board.aircraft().heading_deg.to_radians();
        let main = HostMain {
            roll_control: roll_c,
            pitch_control: pitch_c,
            yaw_control: yaw_c,
            status: HostStatus(0).with_ins_valid(true).with_control_valid(true),
            carrier_roll_cdeg: cd(r, 18000.0),
            carrier_pitch_cdeg: cd(p, 9000.0),
            // ArduPilot writes an int16 in -18000..18000.
            carrier_yaw_cdeg: cd(wrap180(y), 18000.0) as u16,
            accel_north_cmps2: 0,
            accel_east_cmps2: 0,
            accel_up_cmps2: 0,
            vel_north_dmps: (v * h.cos() * 10.0) as i16,
            vel_east_dmps: (v * h.sin() * 10.0) as i16,
            vel_up_dmps: 0,
            sub_request: 0x01,
            reserved: [0; 6],
        };
        let gps = self.board.utc_valid();
        let (lat, lon) = if gps {
            self.board.aircraft().position_e7(t)
        } else {
            (0, 0)
        };
        let (week, tow_ms) = self.gps_time(t);
        let sub = HostSub {
            header: gcu::SUB_HEADER,
            lon_e7: lon,
            lat_e7: lat,
            alt_mm: if gps {
                (self.board.aircraft().alt_msl_m * 1000.0) as i32
            } else {
                0
            },
            satellites: if gps { 17 } else { 0 },
            gps_tow_ms: tow_ms,
            gps_week: week as i16,
            rel_height_mm: if gps { 52_300 } else { 0 },
            reserved: [0; 8],
        };
        let p = HostPacket {
            header: Header::new(self.config.version),
            frames: HostFrames { main, sub },
            message: Message::Raw(Raw {
                id: order,
                payload: &[],
            }),
        };
        let mut buf = [0u8; gcu::MAX_FRAME_LEN];
        let n = p.emit(&mut buf).unwrap();
        self.write(order, buf[..n].to_vec());
    }

    /// ArduPilot's byte parser.
    fn parse(&mut self, now_us: u64, bytes: &[u8]) {
        for &b in bytes {
            self.buf.push(b);
            let mut reset = self.buf.len() > RECV_LENGTH_MAX;
            match self.state {
                ParseState::Header1 => {
                    // The driver keeps non-header bytes in its buffer (no reset here).
                    if b == 0x8A {
                        self.state = ParseState::Header2;
                    }
                }
                ParseState::Header2 => {
                    if b == 0x5E {
                        self.state = ParseState::LengthLow;
                    } else {
                        reset = true;
                    }
                }
                ParseState::LengthLow => {
                    self.len_expected = b;
                    self.state = ParseState::LengthHigh;
                }
                ParseState::LengthHigh => {
                    // `len_expected` is a uint8_t: the high byte is lost.
                    let len = usize::from(self.len_expected);
                    if !(10..=RECV_LENGTH_MAX).contains(&len) {
                        reset = true;
                    } else {
                        self.state = ParseState::Data;
                    }
                }
                ParseState::Data => {
                    if self.buf.len() >= usize::from(self.len_expected) - 2 {
                        self.state = ParseState::CrcHigh;
                    }
                }
                ParseState::CrcHigh => {
                    self.crc = u16::from(b) << 8;
                    self.state = ParseState::CrcLow;
                }
                ParseState::CrcLow => {
                    self.crc |= u16::from(b);
                    let n = self.buf.len();
                    if crc16_xmodem(&self.buf[..n - 2]) == self.crc {
                        self.process(now_us);
                    } else {
                        self.board.parse_error();
                    }
                    reset = true;
                }
            }
            if reset {
                self.buf.clear();
                self.state = ParseState::Header1;
            }
        }
    }

    /// `process_packet`.
    fn process(&mut self, now_us: u64) {
        let reply = Reply {
            at_us: now_us,
            bytes: self.buf.clone(),
        };
        self.replies.push(reply.clone());
        if self.buf.len() < REPLY_MIN {
            return;
        }
        self.attitude = Some((
            now_us,
            f64::from(reply.roll_cdeg()) * 0.01,
            f64::from(reply.pitch_cdeg()) * 0.01,
            f64::from(reply.yaw_bf_cdeg()) * 0.01,
        ));
        if !self.got_firmware_version {
            let hw = f64::from(self.buf[38]) * 0.1;
            let fw = f64::from(self.buf[39]) * 0.1;
            self.text(format!("XFRobot: hw:{hw:.1} fw:{fw:.1}"));
            self.got_firmware_version = true;
        }
        let (order, state) = (reply.order(), self.buf[70]);
        if order == 0x20 && state == 0x01 {
            self.text("XFRobot: failed to take picture".into());
        }
        if order == 0x21 {
            let start = self.record_request.is_none_or(|(_, s)| s);
            let text = if state == 0 {
                format!("XFRobot: recording {}", if start { "ON" } else { "OFF" })
            } else {
                format!(
                    "XFRobot: failed to {} recording",
                    if start { "start" } else { "stop" }
                )
            };
            self.text(text);
            self.record_request = None;
        }
    }

    /// The replies with an execution state, with the order they answer.
    #[must_use]
    pub fn feedback(&self) -> Vec<(u64, u8, u8)> {
        self.replies
            .iter()
            .filter_map(|r| r.execution().map(|e| (r.at_us, r.order(), e)))
            .collect()
    }

    /// Texts containing `s`.
    #[must_use]
    pub fn texts_with(&self, s: &str) -> Vec<(u64, String)> {
        self.texts
            .iter()
            .filter(|(_, t)| t.contains(s))
            .cloned()
            .collect()
    }
}

/// Degrees wrapped to ±180.
fn wrap180(d: f64) -> f64 {
    let w = (d + 180.0).rem_euclid(360.0) - 180.0;
    if w == -180.0 { 180.0 } else { w }
}

impl Autopilot for ApXfRobot {
    board_field!();

    fn take_bytes(&mut self, now_us: u64, bytes: &[u8]) {
        self.parse(now_us, bytes);
    }

    /// One `update()` run.
    fn run(&mut self) {
        if let Some((at, start)) = self.record_request
            && self.board.now_us().saturating_sub(at) > 1_000_000
        {
            let what = if start { "start" } else { "stop" };
            self.text(format!("XFRobot: failed to {what} recording"));
            self.record_request = None;
        }
        self.update_target();
        if self.config.send_attitude {
            self.send_attitude();
        }
    }

    fn update_health(&mut self) {
        let now = self.board.now_us();
        let fresh = self
            .attitude
            .is_some_and(|(at, ..)| now.saturating_sub(at) < 1_000_000);
        self.board.set_healthy(fresh);
    }

    fn power_on(&mut self) {
        self.target = None;
        self.angle = (0.0, 0.0, 0.0, false);
        self.buf.clear();
        self.state = ParseState::Header1;
        self.len_expected = 0;
        self.crc = 0;
        self.attitude = None;
        self.got_firmware_version = false;
        self.record_request = None;
    }
}

impl Pilot for ApXfRobot {
    const DRIVER: &'static str = "ArduPilot AP_Mount_XFRobot (simulated)";
    const TELEMETRY_PORT: bool = true;
    type Frames = GcuFrames;

    fn true_utc_us(&self, t_us: u64) -> u64 {
        self.gps_utc_us(t_us)
    }
    fn first_utc_sent_us(&self) -> Option<u64> {
        self.sent
            .iter()
            .find(|s| s.order == 0x10 && self.board.clock().utc_valid(s.at_us))
            .map(|s| s.at_us)
    }
    fn mount_angles(&self) -> Option<(f64, f64)> {
        self.attitude.map(|(_, _, pitch, yaw)| (yaw, pitch))
    }

    fn point(&mut self, yaw_deg: f64, pitch_deg: f64) {
        self.target = Some(MountTarget::body_angles(pitch_deg, yaw_deg));
    }
    fn turn(&mut self, yaw_dps: f64, pitch_dps: f64) {
        self.target = Some(MountTarget::Rate {
            pitch_dps,
            yaw_dps,
            yaw_is_ef: false,
            from_mavlink: false,
        });
    }
    fn zoom(&mut self, rate: i8) {
        self.set_zoom_rate(f64::from(rate));
    }
    fn take_picture(&mut self) {
        ApXfRobot::take_picture(self);
    }
    fn record(&mut self, on: bool) {
        self.record_video(on);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{FcReboot, Peer};

    #[test]
    fn a_reboot_silences_the_fc_and_its_gps_time_comes_back_shifted() {
        let mut fc = ApXfRobot::new(ApXfRobotConfig::default());
        let utc0 = fc.config.utc_at_zero_us;
        fc.poll(5_005_000);
        let before = fc.gps_time(5_000_000);
        assert_ne!(before, (0, 0));
        fc.reboot(
            5_005_000,
            FcReboot {
                off_us: 2_000_000,
                boot_clock_us: 0,
                utc_shift_us: 1_000_000,
                utc_valid_after_us: 1_000_000,
            },
        );
        fc.poll(10_000_000);
        assert!(
            !fc.sent
                .iter()
                .any(|s| (5_005_000..7_005_000).contains(&s.at_us))
        );
        assert!(fc.sent.iter().any(|s| s.at_us >= 7_000_000));
        assert_eq!(fc.gps_time(7_500_000), (0, 0), "no fix yet");
        assert_eq!(fc.gps_utc_us(4_000_000), utc0 + 4_000_000);
        assert_eq!(fc.gps_utc_us(9_000_000), utc0 + 10_000_000);
        let (week, tow) = fc.gps_time(9_000_000);
        let shifted = ApXfRobot::new(ApXfRobotConfig {
            utc_at_zero_us: utc0 + 1_000_000,
            ..ApXfRobotConfig::default()
        });
        assert_eq!((week, tow), shifted.gps_time(9_000_000));
        assert!(fc.fc_us(7_005_000) < 20_000, "the boot clock restarts");
    }
}
