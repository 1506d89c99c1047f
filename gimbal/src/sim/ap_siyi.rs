//! A simulated ArduPilot `AP_Mount_Siyi` driver: the flight controller as a SIYI gimbal
//! sees it, following the driver's code as docs/src/autopilots/ardupilot.md describes
//! what it sends and reads.
//!
//! - **Loop.** `update()` runs at 50 Hz on the FC's own crystal ([`ApSiyiConfig::ppm`]),
//!   each run a few hundred microseconds late ([`ApSiyiConfig::loop_jitter_us`]). Every
//!   frame one run writes leaves in one burst, after a per-run transport jitter (uniform
//!   in `0..ApSiyiConfig::jitter_us`, 10 ms by default; [`ApSiyiConfig::jitter_per_frame`]
//!   draws it per frame instead).
//! - **Start-up, gated in order** (nothing later happens until the earlier step is
//!   answered): 0x02 hardware id at 1 Hz until any reply; 0x01 firmware at 1 Hz until a
//!   reply of 8 or 12 bytes with a non-zero camera version; with
//!   [`ApSiyiConfig::codec_gate`] (newer releases), 0x20 for streams 0 and 1 until a reply of
//!   at least 8 bytes for each: until then no attitude is requested.
//! - **Steady state.** 1 Hz: 0x0A, and 0x30 (UTC, µs) five times once the clock is valid.
//!   Every ≥ 50 ms 0x0D; on a ZT30 every > 100 ms 0x15; ZT30/ZT6 0x14 (thermal min/max);
//!   every > 100 ms 0x22 (aircraft attitude) and 0x3E (position). Motion every run: 0x07
//!   rates, from a rate target or from an angle target through the P controller (gain 1.5)
//!   on the last 0x0D (0/0 when no 0x0D for 200 ms); before a rotation whose yaw frame
//!   changed, 0x0C lock/follow then 0x0A.
//! - **Parser.** `55 66`, CTRL and SEQ ignored, a frame with more data than
//!   [`ApSiyiConfig::max_data`] (32; 12 before 2024) dropped, CRC-16/XMODEM over the whole
//!   frame, reset to the header on failure (no rewind).
//! - **Health.** Firmware received and a 0x0D reply within the last second.
//!
//! - **Reboot** ([`Autopilot::reboot`], on the [`Board`]): then the driver starts again
//!   from scratch (sequence 0, 0x02, 0x01, 0x20 gating, config, a new mount target) on
//!   the new boot clock (`time_boot_ms` of 0x22/0x3E), and once its UTC is valid it sends
//!   0x30 five times again, with the new boot's UTC.
//!
//! Time is true time in µs. The FC's clock is `fc(t) = t·(1 + ppm) + boot`; its UTC is
//! `fc + shift` (ArduPilot's `AP_RTC`: boot clock plus a shift set once from GPS), with
//! the shift chosen so that the FC's UTC equals [`ApSiyiConfig::utc_at_zero_us`] at true
//! time 0; after a reboot, both restart as [`FcClock`] says. The reference for the
//! bridge's time sync is [`Autopilot::fc_utc_us`], which follows the FC's UTC of the
//! boot in effect.

use super::board::{Autopilot, Board, board_field};
use super::describe::SiyiFrames;
use super::pilot::ClockSettings;
use super::pilot::Pilot;
use protocol_core::Direction;
use protocol_core::siyi::{
    self, AbsoluteZoom, AutoFocus, CameraFunction, CameraFunctionType, Center, CenterPosition,
    CodecQuery, FcAttitude, FcPosition, FeedbackInfo, FirmwareVersionQuery, FocusDirection,
    GimbalAttitudeQuery, GimbalConfigQuery, GimbalRotation, GlobalTemperatureRequest,
    HardwareIdQuery, Header, LaserDistanceQuery, ManualFocus, ManualZoom, MessageData, MotionMode,
    Packet, RecordStatus, SetStitching, SetThermalGain, SetThermalPalette, Siyi, Stitching,
    StitchingMode, StreamType, ThermalGain, ThermalPalette, UtcTime, ZoomDirection, ZoomLevel,
};
use protocol_core::wire::crc16_xmodem;

/// The thermal min/max of a 0x14 reply, as `AP_Mount_Siyi` reads it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SiyiThermal {
    /// When it arrived, true µs.
    pub at_us: u64,
    /// Maximum, °C (an i16 of 0.01 °C).
    pub max_c: f64,
    /// Minimum, °C.
    pub min_c: f64,
    /// Where the maximum is (x, y).
    pub max_pos: (u16, u16),
    /// Where the minimum is.
    pub min_pos: (u16, u16),
}

/// Settings of the simulated driver.
#[derive(Debug, Clone)]
pub struct ApSiyiConfig {
    /// FC crystal error, ppm.
    pub ppm: f64,
    /// Per-run transport jitter bound, µs (uniform in `0..jitter_us`).
    pub jitter_us: u64,
    /// Draw the jitter per frame, not per run.
    pub jitter_per_frame: bool,
    /// Lateness of each run, µs (uniform in `0..loop_jitter_us`).
    pub loop_jitter_us: u64,
    /// Largest reply data accepted (32 current, 12 before 2024).
    pub max_data: usize,
    /// Newer releases: wait for the codec specs of streams 0 and 1.
    pub codec_gate: bool,
    /// The FC's UTC at true time 0, µs since the Unix epoch.
    pub utc_at_zero_us: u64,
    /// The FC's clock reads this at true time 0, µs.
    pub boot_us: u64,
    /// When the FC's clock becomes valid (GPS), true µs.
    pub utc_valid_at_us: u64,
    /// Seed of the random jitter.
    pub seed: u64,
    /// Send 0x3E positions (a GPS fix exists).
    pub position: bool,
}

impl Default for ApSiyiConfig {
    fn default() -> Self {
        ApSiyiConfig {
            ppm: 0.0,
            jitter_us: 10_000,
            jitter_per_frame: false,
            loop_jitter_us: 500,
            max_data: 32,
            codec_gate: true,
            // 2026-11-23T10:00:00.123456Z
            utc_at_zero_us: 1_795_428_000_123_456,
            boot_us: 3_000_000,
            utc_valid_at_us: 0,
            seed: 1,
            position: true,
        }
    }
}

/// What the mount is told to do.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MountTarget {
    /// Turn at these rates (deg/s; yaw positive right, pitch positive up).
    Rate {
        /// Yaw rate.
        yaw_dps: f64,
        /// Pitch rate.
        pitch_dps: f64,
        /// Yaw in the earth frame (lock).
        yaw_is_ef: bool,
    },
    /// Hold these angles (deg; body-frame yaw).
    Angle {
        /// Yaw, positive right.
        yaw_deg: f64,
        /// Pitch, positive up.
        pitch_deg: f64,
    },
}

impl MountTarget {
    /// Turn at these body-frame rates (deg/s).
    #[must_use]
    pub fn body_rate(yaw_dps: f64, pitch_dps: f64) -> Self {
        MountTarget::Rate {
            yaw_dps,
            pitch_dps,
            yaw_is_ef: false,
        }
    }
}

/// A reply the driver received, with the true time of its arrival.
#[derive(Debug, Clone, PartialEq)]
pub struct Received {
    /// True time of arrival.
    pub at_us: u64,
    /// Command id.
    pub id: u8,
    /// Data bytes.
    pub data: Vec<u8>,
}

/// When the driver last sent each of its periodic frames, FC ms.
#[derive(Debug, Clone, Copy, Default)]
struct LastSent {
    /// The 1 Hz group: 0x02/0x01 until answered, then 0x0A, 0x30, 0x20.
    config_ms: Option<u64>,
    /// 0x0D.
    attitude_req_ms: Option<u64>,
    /// 0x15.
    range_req_ms: Option<u64>,
    /// 0x14.
    thermal_req_ms: Option<u64>,
    /// 0x22 and 0x3E.
    attitude_sent_ms: Option<u64>,
    /// 0x05 while zooming.
    zoom_ms: Option<u64>,
}

/// The simulated `AP_Mount_Siyi`.
#[derive(Debug)]
pub struct ApSiyi {
    /// The simulated driver's settings (rates, camera model, seed).
    pub config: ApSiyiConfig,
    board: Board,
    seq: u16,
    // Parser.
    buf: Vec<u8>,
    // Driver state.
    got_hardware_id: bool,
    /// The model from the hardware id's first two characters.
    pub model: Option<[u8; 2]>,
    fw_received: bool,
    codec_record: bool,
    codec_main: bool,
    last: LastSent,
    sent_time_count: u8,
    /// `_config_info.motion_mode` as the driver believes it.
    motion_mode: Option<MotionMode>,
    /// `_config_info.record_status`.
    pub record_status: RecordStatus,
    /// The last 0x0D: (true ms of arrival, yaw, pitch, roll in degrees, ArduPilot's sign
    /// convention: yaw negated back to positive right).
    pub attitude: Option<(u64, f64, f64, f64)>,
    /// The last zoom ratio replied (0x05).
    pub zoom_mult: Option<f64>,
    /// The last rangefinder reading (0x15), as ArduPilot reads it.
    pub rangefinder: Option<(u64, u16)>,
    /// The last thermal min/max as the driver reads 0x14: temperatures i16 × 0.01 °C,
    /// positions as sent.
    pub thermal: Option<SiyiThermal>,
    /// 0x0B messages.
    pub feedback: Vec<(u64, FeedbackInfo)>,
    /// Every reply received.
    pub received: Vec<Received>,
    /// Every frame sent: (true time it was written, id).
    pub sent: Vec<(u64, u8)>,
    /// The mount target.
    pub target: Option<MountTarget>,
    zoom_rate: i8,
}

impl ApSiyi {
    /// A driver that starts at true time 0.
    #[must_use]
    pub fn new(config: ApSiyiConfig) -> Self {
        let board = Board::scheduler_50hz(config.clock(), config.seed, config.loop_jitter_us);
        ApSiyi {
            config,
            board,
            seq: 0,
            buf: Vec::new(),
            got_hardware_id: false,
            model: None,
            fw_received: false,
            codec_record: false,
            codec_main: false,
            last: LastSent::default(),
            sent_time_count: 0,
            motion_mode: None,
            record_status: RecordStatus::Off,
            attitude: None,
            zoom_mult: None,
            rangefinder: None,
            thermal: None,
            feedback: Vec::new(),
            received: Vec::new(),
            sent: Vec::new(),
            target: None,
            zoom_rate: 0,
        }
    }

    /// The firmware reply has been accepted.
    #[must_use]
    pub fn initialised(&self) -> bool {
        self.fw_received
    }

    fn send_zoom_rate(&mut self) {
        let direction = match self.zoom_rate {
            1 => ZoomDirection::In,
            -1 => ZoomDirection::Out,
            _ => ZoomDirection::Stop,
        };
        self.send(&ManualZoom { direction });
    }

    /// Zoom to a percentage of the model's range (0x0F).
    pub fn set_zoom_pct(&mut self, pct: f64) {
        let max = if self.model == Some(*b"7A") {
            30.0
        } else {
            6.0
        };
        let mult = 1.0 + (max - 1.0) * pct.clamp(0.0, 100.0) / 100.0;
        let level = ZoomLevel {
            integer: mult.trunc() as u8,
            tenths: ((mult.fract() * 10.0) as u8).min(9),
        };
        self.send(&AbsoluteZoom(level));
    }

    /// Focus rate: -1 near, 0 hold, 1 far.
    pub fn set_focus_rate(&mut self, rate: i8) {
        let direction = match rate.signum() {
            1 => FocusDirection::Far,
            -1 => FocusDirection::Near,
            _ => FocusDirection::Stop,
        };
        self.send(&ManualFocus { direction });
    }

    /// Autofocus at the picture's centre.
    pub fn autofocus(&mut self) {
        self.send(&AutoFocus {
            start: 1,
            x: 960,
            y: 540,
        });
    }

    /// Lens (ZT30 table of the driver).
    pub fn set_lens(&mut self, lens: u8) {
        const TABLE: [u8; 9] = [3, 5, 7, 0, 1, 2, 4, 6, 8];
        if let Some(&mode) = TABLE.get(usize::from(lens)) {
            self.send(&SetStitching(Stitching {
                mode: StitchingMode::from_value(mode),
            }));
        }
    }

    /// Thermal palette setting (SIYI numbering).
    pub fn set_thermal_palette(&mut self, palette: u8) {
        self.send(&SetThermalPalette(ThermalPalette {
            palette: siyi::Palette::from_value(palette),
        }));
    }

    /// Thermal gain setting (0 low, 1 high).
    pub fn set_thermal_gain(&mut self, gain: u8) {
        self.send(&SetThermalGain(ThermalGain {
            gain: siyi::Gain::from_value(gain),
        }));
    }

    /// Centre the gimbal (0x08 1).
    pub fn center(&mut self) {
        self.send(&Center {
            position: CenterPosition::OneKeyCenter,
        });
    }

    /// Queues one request frame for the current run.
    fn send<M: MessageData<Protocol = Siyi>>(&mut self, m: &M) {
        if self.board.is_off() {
            return;
        }
        let mut buf = [0u8; 64];
        let Ok(n) = siyi::encode(m, &Header::request(self.seq), &mut buf) else {
            return;
        };
        self.seq = self.seq.wrapping_add(1);
        let now = self.board.now_us();
        self.sent.push((now, M::ID));
        let frame = buf[..n].to_vec();
        if self.config.jitter_per_frame {
            let at = now + self.board.rng().uniform(self.config.jitter_us);
            self.board.write_at(at, frame);
        } else {
            self.board.write_run(frame, self.config.jitter_us);
        }
    }

    fn send_target(&mut self) {
        let Some(target) = self.target else {
            return;
        };
        let (yaw_s, pitch_s, ef) = match target {
            MountTarget::Rate {
                yaw_dps,
                pitch_dps,
                yaw_is_ef,
            } => (
                (100.0 * yaw_dps / 90.0).clamp(-100.0, 100.0),
                (100.0 * pitch_dps / 90.0).clamp(-100.0, 100.0),
                yaw_is_ef,
            ),
            MountTarget::Angle { yaw_deg, pitch_deg } => {
                let now = self.board.now_us();
                let fresh = self
                    .attitude
                    .is_some_and(|(at, ..)| now.saturating_sub(at) < 200_000);
                match self.attitude.filter(|_| fresh) {
                    None => (0.0, 0.0, false),
                    Some((_, yaw, pitch, _)) => (
                        (100.0 * (yaw_deg - yaw) * 1.5 / 90.0).clamp(-100.0, 100.0),
                        (100.0 * (pitch_deg - pitch) * 1.5 / 90.0).clamp(-100.0, 100.0),
                        false,
                    ),
                }
            }
        };
        let mode = if ef {
            MotionMode::Lock
        } else {
            MotionMode::Follow
        };
        if self.motion_mode != Some(mode) {
            self.send(&CameraFunction {
                function: if ef {
                    CameraFunctionType::LockMode
                } else {
                    CameraFunctionType::FollowMode
                },
            });
            self.motion_mode = Some(mode);
            self.send(&GimbalConfigQuery {});
        }
        self.send(&GimbalRotation {
            yaw: yaw_s as i8,
            pitch: pitch_s as i8,
        });
    }

    /// ArduPilot's byte parser.
    fn parse(&mut self, now_us: u64, bytes: &[u8]) {
        for &b in bytes {
            self.buf.push(b);
            let n = self.buf.len();
            let reset = match n {
                1 => b != 0x55,
                2 => b != 0x66,
                5 => {
                    usize::from(u16::from_le_bytes([self.buf[3], self.buf[4]]))
                        > self.config.max_data
                }
                _ if n >= 10 => {
                    let len = usize::from(u16::from_le_bytes([self.buf[3], self.buf[4]]));
                    if n == 10 + len {
                        let crc = crc16_xmodem(&self.buf[..n - 2]);
                        if crc == u16::from_le_bytes([self.buf[n - 2], self.buf[n - 1]]) {
                            let id = self.buf[7];
                            let data = self.buf[8..n - 2].to_vec();
                            self.process(now_us, id, &data);
                        } else {
                            self.board.parse_error();
                        }
                        true
                    } else {
                        false
                    }
                }
                _ => false,
            };
            if reset {
                if n >= 5 && n != 10 + usize::from(u16::from_le_bytes([self.buf[3], self.buf[4]])) {
                    self.board.parse_error();
                }
                self.buf.clear();
            }
        }
    }

    fn process(&mut self, now_us: u64, id: u8, data: &[u8]) {
        self.received.push(Received {
            at_us: now_us,
            id,
            data: data.to_vec(),
        });
        let le = |i: usize| i16::from_le_bytes([data[i], data[i + 1]]);
        match id {
            0x01 if (data.len() == 12 || data.len() == 8) && data[..3] != [0, 0, 0] => {
                self.fw_received = true;
            }
            0x02 => {
                self.got_hardware_id = true;
                if data.len() >= 2 {
                    self.model = Some([data[0], data[1]]);
                }
            }
            0x05 if data.len() == 2 => {
                self.zoom_mult = Some(f64::from(u16::from_le_bytes([data[0], data[1]])) * 0.1);
            }
            0x0A if data.len() >= 5 => {
                self.record_status = RecordStatus::from_value(data[3]);
                self.motion_mode = Some(MotionMode::from_value(data[4]));
            }
            0x0B if data.len() == 1 => {
                self.feedback
                    .push((now_us, FeedbackInfo::from_value(data[0])));
            }
            0x0D if data.len() == 12 => {
                self.attitude = Some((
                    now_us,
                    -f64::from(le(0)) * 0.1,
                    f64::from(le(2)) * 0.1,
                    f64::from(le(4)) * 0.1,
                ));
            }
            0x14 if data.len() == 12 => {
                let u = |i: usize| u16::from_le_bytes([data[i], data[i + 1]]);
                self.thermal = Some(SiyiThermal {
                    at_us: now_us,
                    max_c: f64::from(le(0)) * 0.01,
                    min_c: f64::from(le(2)) * 0.01,
                    max_pos: (u(4), u(6)),
                    min_pos: (u(8), u(10)),
                });
            }
            0x15 if data.len() >= 2 => {
                self.rangefinder = Some((now_us, u16::from_le_bytes([data[0], data[1]])));
            }
            0x20 if data.len() >= 8 => match StreamType::from_value(data[0]) {
                StreamType::Record => self.codec_record = true,
                StreamType::Main => self.codec_main = true,
                _ => {}
            },
            _ => {}
        }
    }

    /// Decodes a reply as the bridge meant it (for assertions).
    #[must_use]
    pub fn decoded(frame: &[u8]) -> Option<Packet<'_>> {
        Packet::decode(frame, Direction::FromGimbal).ok()
    }
}

impl Autopilot for ApSiyi {
    board_field!();

    fn take_bytes(&mut self, now_us: u64, bytes: &[u8]) {
        self.parse(now_us, bytes);
    }

    /// One `update()` run.
    fn run(&mut self) {
        let now_ms = self.board.fc_ms();
        let t = self.board.now_us();
        if self.last.config_ms.is_none_or(|l| now_ms - l >= 1000) {
            self.last.config_ms = Some(now_ms);
            if !self.got_hardware_id {
                self.send(&HardwareIdQuery {});
                return;
            } else if !self.fw_received {
                self.send(&FirmwareVersionQuery {});
                return;
            }
            self.send(&GimbalConfigQuery {});
            if self.sent_time_count < 5 && self.board.utc_valid() {
                self.send(&UtcTime {
                    unix_us: self.board.clock().utc_us(t),
                });
                self.sent_time_count += 1;
            }
            if self.config.codec_gate && !(self.codec_record && self.codec_main) {
                for stream in [StreamType::Record, StreamType::Main] {
                    self.send(&CodecQuery { stream });
                }
            }
        }
        if self.config.codec_gate && !(self.codec_record && self.codec_main) {
            return;
        }
        if self.last.attitude_req_ms.is_none_or(|l| now_ms - l >= 50) {
            self.last.attitude_req_ms = Some(now_ms);
            self.send(&GimbalAttitudeQuery {});
        }
        let zt30 = self.model == Some(*b"7A");
        if zt30 && self.last.range_req_ms.is_none_or(|l| now_ms - l > 100) {
            self.last.range_req_ms = Some(now_ms);
            self.send(&LaserDistanceQuery {});
        }
        if (zt30 || self.model == Some(*b"83"))
            && self.last.thermal_req_ms.is_none_or(|l| now_ms - l > 1000)
        {
            self.last.thermal_req_ms = Some(now_ms);
            self.send(&GlobalTemperatureRequest {
                flag: siyi::MeasureFlag::from_value(2),
            });
        }
        if self.last.attitude_sent_ms.is_none_or(|l| now_ms - l > 100) {
            self.last.attitude_sent_ms = Some(now_ms);
            let time_boot_ms = now_ms as u32;
            let (r, p, y) = self.board.aircraft().attitude_deg(t);
            let [roll_rad, pitch_rad, yaw_rad] = [r, p, y].map(|deg| deg.to_radians() as f32);
            self.send(&FcAttitude {
                time_boot_ms,
                roll_rad,
                pitch_rad,
                yaw_rad,
                roll_rate_rad_s: 0.0,
                pitch_rate_rad_s: 0.0,
                yaw_rate_rad_s: 0.0,
            });
            if self.config.position {
                let (lat_e7, lon_e7) = self.board.aircraft().position_e7(t);
                let alt = (self.board.aircraft().alt_msl_m * 100.0) as i32;
                self.send(&FcPosition {
                    time_boot_ms,
                    lat_e7,
                    lon_e7,
                    alt_msl_cm: alt,
                    alt_ellipsoid_cm: alt + 4_800,
                    vel_north_mm_s: 5_657,
                    vel_east_mm_s: 5_657,
                    vel_down_mm_s: 0,
                });
            }
        }
        // Zoom control: a non-zero rate is repeated at 1 Hz.
        if self.zoom_rate != 0 && self.last.zoom_ms.is_none_or(|l| now_ms - l >= 1000) {
            self.last.zoom_ms = Some(now_ms);
            self.send_zoom_rate();
        }
        self.send_target();
    }

    fn update_health(&mut self) {
        let now = self.board.now_us();
        let fresh = self
            .attitude
            .is_some_and(|(at, ..)| now.saturating_sub(at) <= 1_000_000);
        self.board.set_healthy(self.fw_received && fresh);
    }

    fn power_on(&mut self) {
        self.seq = 0;
        self.buf.clear();
        self.got_hardware_id = false;
        self.model = None;
        self.fw_received = false;
        self.codec_record = false;
        self.codec_main = false;
        self.last = LastSent::default();
        self.sent_time_count = 0;
        self.motion_mode = None;
        self.record_status = RecordStatus::Off;
        self.attitude = None;
        self.zoom_mult = None;
        self.rangefinder = None;
        self.thermal = None;
        self.target = None;
        self.zoom_rate = 0;
    }
}

impl Pilot for ApSiyi {
    const DRIVER: &'static str = "ArduPilot AP_Mount_Siyi (simulated)";
    const TELEMETRY_PORT: bool = true;
    type Frames = SiyiFrames;

    fn first_utc_sent_us(&self) -> Option<u64> {
        // 0x30: SIYI's UTC.
        let utc = |&(t, id): &(u64, u8)| (id == 0x30).then_some(t);
        self.sent.iter().find_map(utc)
    }
    fn mount_angles(&self) -> Option<(f64, f64)> {
        self.attitude.map(|(_, yaw, pitch, _)| (yaw, pitch))
    }

    fn point(&mut self, yaw_deg: f64, pitch_deg: f64) {
        self.target = Some(MountTarget::Angle { yaw_deg, pitch_deg });
    }
    fn turn(&mut self, yaw_dps: f64, pitch_dps: f64) {
        self.target = Some(MountTarget::body_rate(yaw_dps, pitch_dps));
    }
    /// Zoom rate: -1 out, 0 hold, 1 in (repeated at 1 Hz while non-zero).
    fn zoom(&mut self, rate: i8) {
        self.zoom_rate = rate.signum();
        self.send_zoom_rate();
        self.last.zoom_ms = Some(self.board.fc_ms());
    }
    /// Take a picture (0x0C 0).
    fn take_picture(&mut self) {
        self.send(&CameraFunction {
            function: CameraFunctionType::TakePhoto,
        });
    }
    /// Start or stop recording: a toggle only when the last 0x0A says it is needed.
    fn record(&mut self, start: bool) {
        let on = self.record_status == RecordStatus::On;
        if start != on && self.record_status != RecordStatus::NoCard {
            self.send(&CameraFunction {
                function: CameraFunctionType::RecordToggle,
            });
        }
        self.send(&GimbalConfigQuery {});
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{FcReboot, Peer};

    /// A SIYI gimbal that answers what the driver waits for (0x02, 0x01, 0x20, 0x0D),
    /// 1 ms after each request, and logs the driver's frames: (true µs, id, data).
    struct Gimbal {
        seen: Vec<(u64, u8, Vec<u8>)>,
        replies: Vec<(u64, Vec<u8>)>,
    }

    fn frame(cmd: u8, data: &[u8]) -> Vec<u8> {
        let mut f = vec![0x55, 0x66, 0x02];
        f.extend_from_slice(&(data.len() as u16).to_le_bytes());
        f.extend_from_slice(&[0, 0, cmd]);
        f.extend_from_slice(data);
        let crc = crc16_xmodem(&f);
        f.extend_from_slice(&crc.to_le_bytes());
        f
    }

    impl Gimbal {
        /// The data of the driver's frames `id`, with their instants.
        fn seen_of(&self, id: u8) -> impl Iterator<Item = (u64, &[u8])> {
            self.seen
                .iter()
                .filter(move |(_, i, _)| *i == id)
                .map(|(at, _, d)| (*at, d.as_slice()))
        }

        fn take(&mut self, at: u64, mut bytes: &[u8]) {
            while bytes.len() >= 10 {
                assert_eq!(bytes[..2], [0x55, 0x66]);
                let len = usize::from(u16::from_le_bytes([bytes[3], bytes[4]]));
                let (cmd, data) = (bytes[7], bytes[8..8 + len].to_vec());
                let reply = match cmd {
                    0x02 => Some(b"7A0000000001".to_vec()),
                    0x01 => Some(vec![1, 3, 0, 0, 1, 3, 0, 0, 0, 1, 0, 0]),
                    0x20 => Some(vec![data[0], 1, 0x80, 7, 0x38, 4, 0x40, 0x1F, 30]),
                    0x0D => Some(vec![0; 12]),
                    _ => None,
                };
                if let Some(r) = reply {
                    self.replies.push((at + 1_000, frame(cmd, &r)));
                }
                self.seen.push((at, cmd, data));
                bytes = &bytes[10 + len..];
            }
        }
    }

    /// Runs `fc` against `g` until `end`; `at_reboot` is called once at `reboot_at`.
    fn run(fc: &mut ApSiyi, g: &mut Gimbal, end: u64, reboot_at: u64, reboot: FcReboot) {
        let mut rebooted = false;
        loop {
            let next_reply = g.replies.iter().map(|r| r.0).min().unwrap_or(u64::MAX);
            let mut t = fc.next_wakeup().min(next_reply);
            if !rebooted {
                t = t.min(reboot_at);
            }
            if t > end {
                break;
            }
            if !rebooted && t == reboot_at {
                fc.reboot(t, reboot);
                rebooted = true;
            }
            let due: Vec<(u64, Vec<u8>)> = g.replies.iter().filter(|r| r.0 <= t).cloned().collect();
            g.replies.retain(|r| r.0 > t);
            for (at, bytes) in due {
                fc.receive(at, &bytes);
            }
            if fc.next_wakeup() <= t {
                fc.poll(t);
            }
            for (at, bytes) in fc.transmit(0) {
                g.take(at, &bytes);
            }
        }
    }

    #[test]
    fn a_reboot_restarts_the_boot_clock_the_start_up_and_the_utc() {
        let mut fc = ApSiyi::new(ApSiyiConfig::default());
        let mut g = Gimbal {
            seen: Vec::new(),
            replies: Vec::new(),
        };
        // The first boot's UTC was 1.5 s fast; the new one is right.
        let reboot = FcReboot {
            off_us: 3_000_000,
            boot_clock_us: 1_000,
            utc_shift_us: -1_500_000,
            utc_valid_after_us: 2_000_000,
        };
        let (off, on) = (20_000_000, 23_000_000);
        run(&mut fc, &mut g, 40_000_000, off, reboot);

        let times: Vec<(u64, u64)> = g
            .seen_of(0x30)
            .map(|(at, d)| (at, u64::from_le_bytes(d[..8].try_into().unwrap())))
            .collect();
        assert_eq!(times.len(), 10, "five per boot");
        let utc0 = ApSiyiConfig::default().utc_at_zero_us;
        // The UTC is read when the run writes the frame, which leaves up to 10 ms later.
        let read_before = |utc: u64, reference: u64| reference - utc <= 10_500;
        for &(at, utc) in &times[..5] {
            assert!(at < off);
            assert!(read_before(utc, utc0 + at), "{at} {utc}");
            assert!(read_before(utc, fc.fc_utc_us(at)));
        }
        for &(at, utc) in &times[5..] {
            // Not before the new boot's UTC is valid; 1.5 s behind the old boot's UTC.
            assert!(at >= on + 2_000_000, "{at}");
            assert!(read_before(utc, utc0 + at - 1_500_000), "{at} {utc}");
            assert!(read_before(utc, fc.fc_utc_us(at)));
        }
        assert_eq!(
            fc.fc_utc_us(on + 5_000_000),
            utc0 + on + 5_000_000 - 1_500_000
        );
        assert_eq!(fc.fc_utc_us(off - 1), utc0 + off - 1);

        // Nothing at all while off; the start-up sequence again from power-on.
        assert!(!g.seen.iter().any(|(at, ..)| (off..on).contains(at)));
        let after: Vec<u8> = g
            .seen
            .iter()
            .filter(|(at, ..)| *at >= on)
            .map(|(_, id, _)| *id)
            .collect();
        assert_eq!(after[..3], [0x02, 0x01, 0x0A], "{after:x?}");
        assert!(after.contains(&0x20));
        // time_boot_ms in 0x22: tens of seconds before the reboot, near 0 after.
        let boot_ms: Vec<(u64, u32)> = g
            .seen_of(0x22)
            .map(|(at, d)| (at, u32::from_le_bytes(d[..4].try_into().unwrap())))
            .collect();
        let before = boot_ms.iter().rfind(|(at, _)| *at < off).unwrap().1;
        let first_after = boot_ms.iter().find(|(at, _)| *at >= on).unwrap();
        assert!(before > 22_000, "{before}");
        assert!(first_after.1 < 3_000, "{first_after:?}");
        assert!(fc.fc_us(first_after.0) / 1000 - u64::from(first_after.1) <= 11);

        // Unhealthy from the power cut, healthy again after the start-up.
        let log: Vec<bool> = fc.health_log().iter().map(|h| h.1).collect();
        assert_eq!(log, [true, false, true]);
        assert_eq!(fc.health_log()[1].0, off);
        assert!(fc.healthy());
        assert_eq!(fc.boots().len(), 2);
        assert_eq!(fc.boots()[1].at_us, on);
    }

    #[test]
    fn bytes_to_an_fc_that_is_off_are_lost() {
        let mut fc = ApSiyi::new(ApSiyiConfig::default());
        fc.poll(1_000_000);
        fc.reboot(1_000_000, FcReboot::default());
        // What was written before the power cut is on the wire.
        assert!(fc.transmit(0).iter().all(|(at, _)| *at <= 1_000_000));
        assert!(fc.is_off());
        assert_eq!(fc.next_wakeup(), 4_000_000);
        fc.receive(2_000_000, &frame(0x02, b"7A0000000001"));
        assert_eq!(fc.lost_while_off(), 22);
        assert!(fc.received.is_empty());
        fc.take_picture();
        fc.poll(3_999_999);
        assert!(fc.transmit(0).is_empty());
        fc.poll(4_100_000);
        assert!(!fc.is_off());
        let out = fc.transmit(0);
        assert_eq!(out.len(), 1);
        assert_eq!(out[0].1[7], 0x02, "the hardware id query first");
    }
}
