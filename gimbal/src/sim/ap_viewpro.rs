//! A simulated ArduPilot `AP_Mount_Viewpro` driver: the flight controller as a Viewpro
//! gimbal (the Viewlink protocol) sees it, following the driver's code
//! (`libraries/AP_Mount/AP_Mount_Viewpro.cpp`) as docs/src/autopilots/ardupilot.md
//! describes what it sends and reads.
//!
//! - **Loop.** `update()` is called at 50 Hz on the FC's own crystal
//!   ([`ApViewproConfig::ppm`]), each call a few hundred microseconds late
//!   ([`ApViewproConfig::loop_jitter_us`]); its body runs when at least 100 ms (FC
//!   milliseconds) passed since it last ran. The body, in the driver's order: read and
//!   parse every byte received since the last run; 0x01 U 0xE4 (model) until a V 0xE4
//!   came; 0x01 U 0xD0 (firmware) until a V 0xD0 came; 0x00 handshake; 0xB1 M_AHRS
//!   (only with a position, [`ApViewproConfig::position`]); then, unless the last 0x40
//!   said the tracker searches or tracks, the target: lock (A1 0x0A) or follow (0x03)
//!   when it changed (the driver starts "follow"), then A1 rates (0x01) or absolute
//!   angles (0x0B). Every frame one run writes leaves in one burst after a per-run
//!   transport jitter (uniform in `0..ApViewproConfig::jitter_us`, 10 ms by default).
//! - **Camera API** (called between runs, written at once, after the jitter): C1
//!   photo, record start/stop, zoom in/out/stop (EO speed 7, or IR zoom 0x1B/0x1C
//!   speed 1 when the sensor is IR), focus +/−/stop, autofocus; C2 0x53 absolute zoom
//!   (percent of 10x); C1 sensor selection (lens, camera source); C1 rangefinder
//!   continuous/stop; E1 + E2 tracking (point, rectangle, stop). Every C1 carries the
//!   sensor the last 0x40 reported, as the driver's `_image_sensor`. [`ApViewpro::send_raw`]
//!   sends any other block, as a console would.
//! - **Parser.** The driver's byte state machine: `55 AA DC`, LEN (bits 0..5; the
//!   counter masked), frame id, at least one data byte, XOR from LEN through the last
//!   data byte; a header mismatch or a bad checksum resets it (no rewind).
//! - **Reading.** V 0xD0: firmware digits at data[4..10]; V 0xE4: model at data[1..]
//!   (10 characters). 0x40: [22] bits 3..4 tracking, [23]&0x0F and [24] 12-bit roll
//!   (×180/4095 − 90), [25..26] yaw, [27..28] pitch (negated), [29] bits 0..2 sensor
//!   − 1 and bits 3..6 IR zoom − 1, [32] & 0x07 recording, [33..34] LRF (0.1 m),
//!   [39..40] EO zoom (0.1x). A 0x40 shorter than 41 data bytes is counted
//!   ([`ApViewpro::short_status`]); the real driver would read stale bytes.
//! - **Health.** A 0x40 processed within the last second (the driver is initialised
//!   from the start).
//!
//! - **Reboot** ([`Autopilot::reboot`], on the [`Board`]): then the driver starts from
//!   scratch (frame counter, model and firmware queries, follow mode) on the new boot
//!   clock; M_AHRS carries a zero date and time until the new boot's UTC is valid, then
//!   that UTC.
//!
//! Time is true time in µs. The FC's clock is `fc(t) = t·(1 + ppm) + boot`; its UTC is
//! ArduPilot's `AP_RTC` (`fc + shift`, the shift frozen), equal to
//! [`ApViewproConfig::utc_at_zero_us`] at true time 0 (after a reboot: as [`FcClock`]
//! says): [`Autopilot::fc_utc_us`] is the reference of the bridge's time sync. M_AHRS
//! carries it as date and hundredths of a second since midnight, read when the run writes the frame (truncated to 10 ms), so
//! its read phase is locked to the FC loop.
//!
//! Angles the driver converts from floats to 16-bit fields are written as two's
//! complement (x86 SITL's behaviour; a negative float converted to `uint16_t` is
//! undefined in C++).

use super::board::{Autopilot, Board, board_field};
use super::describe::ViewlinkFrames;
use super::pilot::ClockSettings;
use super::pilot::Pilot;
use protocol_core::viewlink::{
    self, A1, AbsoluteAngle, C1, C2, Date, E1, E2, FrameCounter, Handshake, LrfCommand, M,
    MAttitude, MGps, ManualSpeed, MessageData, OperationCommand, Point, QueryParams, Sensor,
    ServoCommand, TimeCs, TrackingCommand, TrackingSource, U, Viewlink, Zoom,
};

use super::ap_siyi::MountTarget;

/// The frame header the driver's parser looks for.
const HEADER: [u8; 3] = [0x55, 0xAA, 0xDC];

/// Settings of the simulated driver.
#[derive(Debug, Clone)]
pub struct ApViewproConfig {
    /// FC crystal error, ppm.
    pub ppm: f64,
    /// Per-run transport jitter bound, µs (uniform in `0..jitter_us`).
    pub jitter_us: u64,
    /// Lateness of each loop call, µs (uniform in `0..loop_jitter_us`).
    pub loop_jitter_us: u64,
    /// The FC's UTC at true time 0, µs since the Unix epoch.
    pub utc_at_zero_us: u64,
    /// The FC's clock reads this at true time 0, µs.
    pub boot_us: u64,
    /// When the FC's clock becomes valid (GPS), true µs; before, M_AHRS carries a zero
    /// date and time, as the driver sends when `AP_RTC` has no time.
    pub utc_valid_at_us: u64,
    /// Seed of the random jitter.
    pub seed: u64,
    /// The vehicle knows its position (M_AHRS is only sent then).
    pub position: bool,
    /// Body-frame yaw limits of the mount, degrees (`MNTx_YAW_MIN/MAX`).
    pub yaw_limits_deg: (f64, f64),
}

impl Default for ApViewproConfig {
    fn default() -> Self {
        ApViewproConfig {
            ppm: 0.0,
            jitter_us: 10_000,
            loop_jitter_us: 500,
            // 2026-11-23T10:00:00.123456Z
            utc_at_zero_us: 1_795_428_000_123_456,
            boot_us: 3_000_000,
            utc_valid_at_us: 0,
            seed: 1,
            position: true,
            yaw_limits_deg: (-180.0, 180.0),
        }
    }
}

/// A frame the driver processed, with the true time it was read (the run's start).
#[derive(Debug, Clone, PartialEq)]
pub struct Received {
    /// True time of processing.
    pub at_us: u64,
    /// Frame counter (LEN bits 6..7).
    pub counter: u8,
    /// Frame id.
    pub id: u8,
    /// Data bytes.
    pub data: Vec<u8>,
}

/// What the driver read from the last 0x40.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GimbalReading {
    /// True time of processing.
    pub at_us: u64,
    /// Roll, degrees.
    pub roll_deg: f64,
    /// Pitch, degrees (positive up: the wire value negated).
    pub pitch_deg: f64,
    /// Yaw, degrees (body frame, positive right).
    pub yaw_deg: f64,
}

/// The tracker state of F1, as the driver names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrackingStatus {
    /// Not tracking.
    Stopped,
    /// Tracking requested; the gimbal has not reported a lock yet.
    Searching,
    /// Locked on a target.
    Tracking,
    /// Lost the target.
    Lost,
}

/// A tracking request of the driver's `set_tracking`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Tracking {
    /// Stop tracking.
    None,
    /// A point, 0..1 from the left and the top.
    Point(f64, f64),
    /// A rectangle: top-left and bottom-right, 0..1.
    Rectangle((f64, f64), (f64, f64)),
}

/// The simulated `AP_Mount_Viewpro`.
#[derive(Debug)]
pub struct ApViewpro {
    /// The simulated driver's settings (rates, seed).
    pub config: ApViewproConfig,
    board: Board,
    last_update_ms: Option<u64>,
    counter: FrameCounter,
    // Parser.
    rx: Vec<u8>,
    state: u8,
    buf: Vec<u8>,
    data_len: u8,
    data_received: u16,
    // Driver state.
    /// The model (V 0xE4).
    pub model: Option<String>,
    /// The firmware (V 0xD0): major, minor, patch.
    pub firmware: Option<(u8, u8, u8)>,
    last_lock: bool,
    /// `_image_sensor`: from the last 0x40 (C1 code).
    pub image_sensor: u8,
    /// `_recording`.
    pub recording: bool,
    /// `_zoom_times`.
    pub zoom_times: f64,
    /// `_rangefinder_dist_m`.
    pub rangefinder_m: f64,
    /// `_last_tracking_status`.
    pub tracking: TrackingStatus,
    /// The last attitude read.
    pub attitude: Option<GimbalReading>,
    /// Every frame processed.
    pub received: Vec<Received>,
    /// Every frame sent: (true time it was written, frame id, data).
    pub sent: Vec<(u64, u8, Vec<u8>)>,
    /// The mount target.
    pub target: Option<MountTarget>,
    /// 0x40 frames with fewer than 41 data bytes.
    pub short_status: u32,
}

impl ApViewpro {
    /// A driver that starts at true time 0.
    #[must_use]
    pub fn new(config: ApViewproConfig) -> Self {
        let board = Board::scheduler_50hz(config.clock(), config.seed, config.loop_jitter_us);
        ApViewpro {
            config,
            board,
            last_update_ms: None,
            counter: FrameCounter::new(),
            rx: Vec::new(),
            state: 0,
            buf: Vec::new(),
            data_len: 0,
            data_received: 0,
            model: None,
            firmware: None,
            last_lock: false,
            image_sensor: 0,
            recording: false,
            zoom_times: 1.0,
            rangefinder_m: 0.0,
            tracking: TrackingStatus::Stopped,
            attitude: None,
            received: Vec::new(),
            sent: Vec::new(),
            target: None,
            short_status: 0,
        }
    }

    /// Queues one frame (id + data) in the current burst (`send_packet`).
    fn send_packet(&mut self, id: u8, data: &[u8]) {
        if self.board.is_off() {
            return;
        }
        let mut frame = vec![0x55, 0xAA, 0xDC];
        let len = (data.len() + 3) as u8;
        frame.push((self.counter.next_value() << 6) | (len & 0x3F));
        frame.push(id);
        frame.extend_from_slice(data);
        let x = frame[3..].iter().fold(0u8, |a, b| a ^ b);
        frame.push(x);
        self.sent.push((self.board.now_us(), id, data.to_vec()));
        self.board.write_run(frame, self.config.jitter_us);
    }

    /// Sends a typed block as a frame of its own (any block: a console's frames too).
    pub fn send_raw<Msg: MessageData<Protocol = Viewlink>>(&mut self, message: &Msg) {
        let mut buf = [0u8; viewlink::MAX_FRAME_LEN];
        let n = viewlink::encode(message, &viewlink::Header::new(0), &mut buf).unwrap();
        let data = buf[5..n - 1].to_vec();
        self.send_packet(Msg::ID, &data);
    }

    /// `send_camera_command`: C1 with the sensor, speed, operation and LRF command.
    fn camera_command(&mut self, sensor: u8, op: OperationCommand, speed: u8, lrf: LrfCommand) {
        let c1 = C1 {
            sensor: Sensor::from_value(sensor),
            zoom_speed: speed & 0x07,
            operation: op,
            lrf,
        };
        self.send_raw(&c1);
    }

    /// Zoom rate: < 0 out, 0 stop, > 0 in (the EO or the IR zoom, by the sensor).
    pub fn set_zoom_rate(&mut self, rate: f64) {
        let s = self.image_sensor;
        let ir = matches!(s, 2 | 4);
        let (op, speed) = if ir {
            // The driver's IR_ZOOM_OUT is 0x1B and IR_ZOOM_IN 0x1C, and it sends
            // IR_ZOOM_OUT for a positive rate: 0x1B ("IR digital zoom +") to zoom in.
            use OperationCommand::{IrDzoomIn, IrDzoomOut};
            (by_sign(rate, [IrDzoomOut, IrDzoomIn]), 1)
        } else {
            use OperationCommand::{ZoomIn, ZoomOut};
            (by_sign(rate, [ZoomOut, ZoomIn]), 7)
        };
        self.camera_command(s, op, speed, LrfCommand::NoAction);
    }

    /// Zoom to a percentage (C2 0x53, 0..100 of 10x: the value is the percentage).
    pub fn set_zoom_pct(&mut self, pct: f64) {
        let v = pct.clamp(0.0, 100.0) as u16;
        self.send_raw(&C2::SetEoZoom(Zoom { zoom_x10: v }));
    }

    /// Focus rate: < 0 focus −, 0 stop, > 0 focus +.
    pub fn set_focus_rate(&mut self, rate: f64) {
        let s = self.image_sensor;
        let op = by_sign(
            rate,
            [OperationCommand::FocusDown, OperationCommand::FocusUp],
        );
        self.camera_command(s, op, 0, LrfCommand::NoAction);
    }

    /// Sends an autofocus command, as the driver does for a focus request.
    pub fn autofocus(&mut self) {
        let s = self.image_sensor;
        self.camera_command(s, OperationCommand::AutoFocus, 0, LrfCommand::NoAction);
    }

    /// `set_lens(lens)`: lens 0..=6 is the sensor code minus one.
    pub fn set_lens(&mut self, lens: u8) {
        if lens < 7 {
            self.camera_command(
                lens + 1,
                OperationCommand::NoAction,
                0,
                LrfCommand::NoAction,
            );
        }
    }

    /// `set_camera_source(primary, secondary)`: 0/1 RGB, 2 IR; secondary 0 none,
    /// 1 RGB, 2 IR (picture in picture).
    pub fn set_camera_source(&mut self, primary: u8, secondary: u8) -> bool {
        let sensor = match (primary, secondary) {
            (0 | 1, 0) => 1,
            (0 | 1, 2) => 3,
            (2, 0) => 2,
            (2, 1) => 4,
            _ => return false,
        };
        self.camera_command(sensor, OperationCommand::NoAction, 0, LrfCommand::NoAction);
        true
    }

    /// `set_rangefinder_enable`.
    pub fn set_rangefinder_enable(&mut self, enable: bool) {
        let lrf = if enable {
            LrfCommand::Continuous
        } else {
            LrfCommand::Stop
        };
        self.camera_command(0, OperationCommand::NoAction, 0, lrf);
    }

    /// `set_tracking`.
    pub fn set_tracking(&mut self, tracking: Tracking) {
        let source = if matches!(self.image_sensor, 2 | 4 | 6 | 7) {
            TrackingSource::Ir
        } else {
            TrackingSource::Eo1
        };
        let px = |(x, y): (f64, f64)| Point {
            x_px: ((x - 0.5) * 2.0 * 960.0) as i16,
            y_px: ((y - 0.5) * 2.0 * 540.0) as i16,
        };
        match tracking {
            Tracking::None => self.send_raw(&E1::new(source, TrackingCommand::Stop)),
            Tracking::Point(x, y) => {
                self.send_raw(&E1::new(source, TrackingCommand::Start));
                self.send_raw(&E2::TrackPoint(px((x, y))));
            }
            Tracking::Rectangle(p1, p2) => {
                self.send_raw(&E1::new(source, TrackingCommand::Start));
                self.send_raw(&E2::RectTopLeft(px(p1)));
                self.send_raw(&E2::RectBottomRight(px(p2)));
            }
        }
    }

    /// `set_lock`: A1 0x0A (lock) or 0x03 (follow) when it changed.
    fn set_lock(&mut self, lock: bool) {
        if self.last_lock == lock {
            return;
        }
        let servo = if lock {
            ServoCommand::FollowYawDisable
        } else {
            ServoCommand::FollowYaw
        };
        self.send_raw(&A1::plain(servo));
        self.last_lock = lock;
    }

    /// The driver's U packet: command and nine unused bytes.
    fn comm_config(&mut self, query_model: bool) {
        let u = if query_model {
            U::QueryModel(QueryParams::default())
        } else {
            U::QueryFirmware(QueryParams::default())
        };
        self.send_raw(&u);
    }

    /// `send_m_ahrs`.
    fn send_m_ahrs(&mut self) {
        if !self.config.position {
            return;
        }
        let t = self.board.now_us();
        let (date, cs) = if self.board.utc_valid() {
            let utc_us = self.board.clock().utc_us(t);
            let days = utc_us / 86_400_000_000;
            let (y, m, d) = civil_from_days(days as i64);
            let tod_ms = (utc_us / 1000) % 86_400_000;
            let date =
                ((y - 2000) as u16 & 0x7F) | ((m as u16 & 0x0F) << 7) | ((d as u16 & 0x1F) << 11);
            // (h·3600 + m·60 + s)·100 + ms·0.1, truncated.
            (date, (tod_ms / 10) as u32)
        } else {
            // AP_RTC without time: all zero, month + 1.
            (48 | (1 << 7), 0)
        };
        let (roll, pitch, yaw) = self.board.aircraft().attitude_deg(t);
        let bam = |deg: f64| (deg * 65536.0 / 360.0) as i32 as i16;
        let (lat_e7, lon_e7) = self.board.aircraft().position_e7(t);
        let h = self.board.aircraft().heading_deg.to_radians();
        let v = self.board.aircraft().speed_m_s;
        let m = M::new(
            Some(MAttitude {
                roll_bam16: bam(roll),
                pitch_bam16: bam(-pitch),
                // Whole degrees 0..359 (uint16), as a binary angle.
                yaw_bam16: (f64::from((yaw.rem_euclid(360.0)) as u16) * 65536.0 / 360.0) as u32
                    as u16 as i16,
            }),
            Some(MGps {
                date: Date(date),
                time: TimeCs(cs),
                gps_yaw_bam16: bam(self.board.aircraft().heading_deg.rem_euclid(360.0)),
                position_mark: 0x0F,
                lat_e7,
                lon_e7,
                height_mm: (self.board.aircraft().alt_msl_m * 1000.0) as i32,
                vel_north_cm_s: (v * h.cos() * 100.0) as i16,
                vel_east_cm_s: (v * h.sin() * 100.0) as i16,
                vdop_x100: 120,
                vel_down_cm_s: 0,
            }),
        );
        self.send_raw(&m);
    }

    fn send_target(&mut self) {
        let Some(target) = self.target else {
            return;
        };
        match target {
            MountTarget::Rate {
                yaw_dps,
                pitch_dps,
                yaw_is_ef,
            } => {
                self.set_lock(yaw_is_ef);
                self.send_raw(&A1::ManualSpeed(ManualSpeed {
                    yaw_cdeg_s: (yaw_dps * 100.0) as i16,
                    pitch_cdeg_s: (-pitch_dps * 100.0) as i16,
                    reserved: [0; 4],
                }));
            }
            MountTarget::Angle { yaw_deg, pitch_deg } => {
                self.set_lock(false);
                let (lo, hi) = self.config.yaw_limits_deg;
                let yaw = yaw_deg.clamp(lo, hi);
                self.send_raw(&A1::AbsoluteAngle(AbsoluteAngle {
                    yaw_bam16: (yaw * 65536.0 / 360.0) as i32 as i16,
                    pitch_bam16: (-pitch_deg * 65536.0 / 360.0) as i32 as i16,
                    reserved: [0; 4],
                }));
            }
        }
    }

    /// The gated body of `update()`.
    fn update(&mut self) {
        let now_ms = self.board.fc_ms();
        if self
            .last_update_ms
            .is_some_and(|l| now_ms.saturating_sub(l) < 100)
        {
            return;
        }
        self.last_update_ms = Some(now_ms);
        self.read_incoming();
        if self.model.is_none() {
            self.comm_config(true);
        }
        if self.firmware.is_none() {
            self.comm_config(false);
        }
        self.send_raw(&Handshake { value: 0 });
        self.send_m_ahrs();
        if matches!(
            self.tracking,
            TrackingStatus::Searching | TrackingStatus::Tracking
        ) {
            return;
        }
        self.send_target();
    }

    /// `read_incoming_packets`: the driver's parser over everything received.
    fn read_incoming(&mut self) {
        let bytes = std::mem::take(&mut self.rx);
        for b in bytes {
            self.buf.push(b);
            let mut reset = self.buf.len() > 63;
            match self.state {
                // The header `55 AA DC`, one byte a state; the buffer starts after it.
                0..=2 => {
                    if HEADER.get(usize::from(self.state)) == Some(&b) {
                        self.buf.clear();
                        self.state += 1;
                    } else {
                        reset = true;
                    }
                }
                3 => {
                    self.data_len = b & 0x3F;
                    self.state = 4;
                }
                4 => {
                    self.data_received = 0;
                    self.state = 5;
                }
                5 => {
                    self.data_received += 1;
                    if i32::from(self.data_received) >= i32::from(self.data_len) - 3 {
                        self.state = 6;
                    }
                }
                _ => {
                    let n = self.buf.len();
                    let x = self.buf[..n - 1].iter().fold(0u8, |a, b| a ^ b);
                    if x == b {
                        let counter = self.buf[0] >> 6;
                        let id = self.buf[1];
                        let data = self.buf[2..n - 1].to_vec();
                        self.process(counter, id, data);
                    } else {
                        self.board.parse_error();
                    }
                    reset = true;
                }
            }
            if reset {
                self.buf.clear();
                self.state = 0;
            }
        }
    }

    fn process(&mut self, counter: u8, id: u8, data: Vec<u8>) {
        let at_us = self.board.now_us();
        let byte = |i: usize| data.get(i).copied().unwrap_or(0);
        match id {
            0x02 => match byte(0) {
                0xD0 => {
                    let num = |i: usize| {
                        std::str::from_utf8(&[byte(i), byte(i + 1)])
                            .ok()
                            .and_then(|s| s.trim().parse::<u8>().ok())
                            .unwrap_or(0)
                    };
                    self.firmware = Some((num(4), num(6), num(8)));
                }
                0xE4 => {
                    let text: Vec<u8> = data
                        .iter()
                        .skip(1)
                        .take(10)
                        .copied()
                        .take_while(|&c| c != 0)
                        .collect();
                    self.model = Some(String::from_utf8_lossy(&text).into_owned());
                }
                _ => {}
            },
            0x40 => {
                if data.len() < 41 {
                    self.short_status += 1;
                }
                self.tracking = match (byte(22) & 0x18) >> 3 {
                    0 => TrackingStatus::Stopped,
                    1 => TrackingStatus::Searching,
                    2 => TrackingStatus::Tracking,
                    _ => TrackingStatus::Lost,
                };
                let be = |i: usize| i16::from_be_bytes([byte(i), byte(i + 1)]);
                let roll_raw = u16::from_be_bytes([byte(23) & 0x0F, byte(24)]);
                self.attitude = Some(GimbalReading {
                    at_us,
                    roll_deg: f64::from(roll_raw) * (180.0 / 4095.0) - 90.0,
                    yaw_deg: f64::from(be(25)) * 360.0 / 65536.0,
                    pitch_deg: -f64::from(be(27)) * 360.0 / 65536.0,
                });
                self.image_sensor = (byte(29) & 0x07) + 1;
                self.recording = byte(32) & 0x07 == 1;
                self.zoom_times = match self.image_sensor {
                    2 | 4 => f64::from(((byte(29) >> 3) & 0x0F) + 1),
                    _ => f64::from(u16::from_be_bytes([byte(39), byte(40)])) * 0.1,
                };
                self.rangefinder_m = f64::from(u16::from_be_bytes([byte(33), byte(34)])) * 0.1;
            }
            _ => {}
        }
        self.received.push(Received {
            at_us,
            counter,
            id,
            data,
        });
    }

    /// The last 0x40 data bytes processed.
    #[must_use]
    pub fn last_status(&self) -> Option<&Received> {
        self.received.iter().rev().find(|r| r.id == 0x40)
    }
}

/// The operation for a rate: `[negative, positive]`, or stop when it is 0.
fn by_sign(rate: f64, [negative, positive]: [OperationCommand; 2]) -> OperationCommand {
    if rate < 0.0 {
        negative
    } else if rate > 0.0 {
        positive
    } else {
        OperationCommand::StopZoomFocus
    }
}

/// Proleptic Gregorian date of a day number since 1970-01-01 (Howard Hinnant's
/// algorithm).
fn civil_from_days(z: i64) -> (i64, u32, u32) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let y = yoe + era * 400;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    (if m <= 2 { y + 1 } else { y }, m, d)
}

impl Autopilot for ApViewpro {
    board_field!();

    /// Its health only at its runs (the bytes wait for them).
    const HEALTH_ON_RECEIVE: bool = false;

    fn take_bytes(&mut self, _now_us: u64, bytes: &[u8]) {
        // The driver reads its UART at its next run.
        self.rx.extend_from_slice(bytes);
    }

    /// A call of `update()`; the driver's health is taken after each.
    fn run(&mut self) {
        self.update();
        self.update_health();
    }

    fn update_health(&mut self) {
        let b = &self.board;
        let fresh = self
            .attitude
            .is_some_and(|a| b.fc_ms() <= b.fc_us(a.at_us) / 1000 + 1000);
        self.board.set_healthy(fresh);
    }

    fn power_on(&mut self) {
        self.last_update_ms = None;
        self.counter = FrameCounter::new();
        self.rx.clear();
        self.state = 0;
        self.buf.clear();
        self.data_len = 0;
        self.data_received = 0;
        self.model = None;
        self.firmware = None;
        self.last_lock = false;
        self.image_sensor = 0;
        self.recording = false;
        self.zoom_times = 1.0;
        self.rangefinder_m = 0.0;
        self.tracking = TrackingStatus::Stopped;
        self.attitude = None;
        self.target = None;
    }
}

impl Pilot for ApViewpro {
    const DRIVER: &'static str = "ArduPilot AP_Mount_Viewpro (simulated)";
    const TELEMETRY_PORT: bool = true;
    type Frames = ViewlinkFrames;

    fn first_utc_sent_us(&self) -> Option<u64> {
        // 0xB1: M_AHRS, whose date and time count once the FC's UTC is valid.
        let valid = |t: u64| self.board.clock().utc_valid(t);
        let utc = |(t, id, _): &(u64, u8, Vec<u8>)| (*id == 0xB1 && valid(*t)).then_some(*t);
        self.sent.iter().find_map(utc)
    }
    fn mount_angles(&self) -> Option<(f64, f64)> {
        self.attitude.map(|a| (a.yaw_deg, a.pitch_deg))
    }

    fn point(&mut self, yaw_deg: f64, pitch_deg: f64) {
        self.target = Some(MountTarget::Angle { yaw_deg, pitch_deg });
    }
    fn turn(&mut self, yaw_dps: f64, pitch_dps: f64) {
        self.target = Some(MountTarget::body_rate(yaw_dps, pitch_dps));
    }
    fn zoom(&mut self, rate: i8) {
        self.set_zoom_rate(f64::from(rate));
    }
    /// Take a picture.
    fn take_picture(&mut self) {
        let s = self.image_sensor;
        self.camera_command(s, OperationCommand::TakePicture, 0, LrfCommand::NoAction);
    }
    /// Start or stop recording.
    fn record(&mut self, start: bool) {
        let s = self.image_sensor;
        let op = if start {
            OperationCommand::StartRecord
        } else {
            OperationCommand::StopRecord
        };
        self.camera_command(s, op, 0, LrfCommand::NoAction);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{FcReboot, Peer};

    #[test]
    fn dates() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(20_415), (2025, 11, 23));
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
    }

    #[test]
    fn a_run_writes_queries_handshake_ahrs_and_the_target() {
        let mut ap = ApViewpro::new(ApViewproConfig {
            jitter_us: 0,
            ..ApViewproConfig::default()
        });
        ap.target = Some(MountTarget::Rate {
            yaw_dps: 10.0,
            pitch_dps: 5.0,
            yaw_is_ef: true,
        });
        ap.poll(1);
        let ids: Vec<u8> = ap.sent.iter().map(|(_, id, _)| *id).collect();
        assert_eq!(ids, vec![0x01, 0x01, 0x00, 0xB1, 0x1A, 0x1A]);
        let frames = ap.transmit(0);
        assert_eq!(frames.len(), 1, "one burst");
        let bytes = &frames[0].1;
        // Frame counter 1, 2, 3, ...; every frame decodes with the crate's codec.
        let mut p = 0;
        let mut packets = vec![];
        while p < bytes.len() {
            let len = usize::from(bytes[p + 3] & 0x3F) + 3;
            packets.push(viewlink::Packet::decode(&bytes[p..p + len]).unwrap());
            p += len;
        }
        let counters: Vec<u8> = packets.iter().map(|p| p.header.counter).collect();
        assert_eq!(counters, vec![1, 2, 3, 0, 1, 2]);
        assert_eq!(ap.sent[4].2[0], 0x0A, "lock before earth-frame rates");
        assert_eq!(&ap.sent[5].2[..5], &[0x01, 0x03, 0xE8, 0xFE, 0x0C]);
        // The M_AHRS date and time: 2026-11-23, 10:00:00.12 (the run at true time 0).
        let m = packets[3].message.get::<M>().unwrap();
        let g = m.gps.unwrap();
        assert_eq!(
            (g.date.year(), g.date.month(), g.date.day()),
            (2026, 11, 23)
        );
        assert_eq!(g.time.0, 10 * 3600 * 100 + 12);
    }

    #[test]
    fn a_reboot_restarts_the_driver_and_shifts_the_ahrs_time() {
        let mut ap = ApViewpro::new(ApViewproConfig::default());
        let utc0 = ap.config.utc_at_zero_us;
        ap.poll(10_005_000);
        ap.reboot(
            10_005_000,
            FcReboot {
                off_us: 3_000_000,
                boot_clock_us: 0,
                utc_shift_us: 250_000,
                utc_valid_after_us: 1_000_000,
            },
        );
        ap.receive(11_000_000, &[0x55, 0xAA, 0xDC]);
        assert_eq!(ap.lost_while_off(), 3);
        assert_eq!(ap.next_wakeup(), 13_005_000);
        ap.poll(20_000_000);
        // M_AHRS time: 3 bytes, 0.01 s since UTC midnight, read at the run.
        let ahrs: Vec<(u64, u32)> = ap
            .sent
            .iter()
            .filter(|(_, id, _)| *id == 0xB1)
            .map(|(at, _, d)| (*at, u32::from_be_bytes([0, d[16], d[17], d[18]])))
            .collect();
        let cs = |utc_us: u64| ((utc_us / 10_000) % 8_640_000) as u32;
        assert!(
            ahrs.iter()
                .all(|(at, _)| !(10_005_000..13_005_000).contains(at))
        );
        for &(at, time) in &ahrs {
            if at < 10_005_000 {
                assert_eq!(time, cs(utc0 + at), "{at}");
            } else if at < 14_005_000 {
                assert_eq!(time, 0, "no UTC yet at {at}");
            } else {
                assert_eq!(time, cs(utc0 + at + 250_000), "{at}");
                assert_eq!(time, cs(ap.fc_utc_us(at)));
            }
        }
        assert!(ahrs.iter().filter(|(at, _)| *at >= 14_005_000).count() >= 50);
        // The driver starts again: model query first, frame counter from 1.
        let first = ap.sent.iter().find(|(at, ..)| *at >= 13_000_000).unwrap();
        assert_eq!((first.1, first.2[0]), (0x01, 0xE4));
        assert!(ap.fc_us(13_005_000) < 20_000, "the boot clock restarts");
        assert_eq!(ap.boots().len(), 2);
    }
}
