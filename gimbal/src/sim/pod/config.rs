//! The simulated pod's settings ([`PodSimConfig`]); what each does is in the module
//! documentation of [`super`].

use super::*;

/// The infrared measurements reported in 0x000004 at power-up ([`ir_scene`] at 0).
pub const IR_STATUS: IrStatus = IrStatus {
    max_temp_dc: 412,
    min_temp_dc: 153,
    center_temp_dc: 251,
    point_temp_dc: 268,
    avg_temp_dc: 240,
    max_x: 1360,
    max_y: 544,
    min_x: 560,
    min_y: 544,
    center_x: 960,
    center_y: 544,
    point_x: 960,
    point_y: 544,
    high_warning: 0,
    low_warning: 0,
    diff_warning: 0,
    threshold_warning: 0,
    reserved: [0; 4],
};

/// GPS requests the pod sends that are no photo's (see docs/src/protocols/k40t.md, "GPS
/// requests": its document says a request precedes each photo and no more; a pod that
/// also asks periodically, or while recording, is plausible and the bridge must not take
/// those for photos).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PeriodicGps {
    /// Only before photos (the document's reading).
    #[default]
    Never,
    /// Every `period_us`, from power-up.
    Always {
        /// The period, µs.
        period_us: u64,
    },
    /// Every `period_us` while recording.
    WhileRecording {
        /// The period, µs.
        period_us: u64,
    },
}

impl PeriodicGps {
    /// The period, when any.
    #[must_use]
    pub const fn period_us(self) -> Option<u64> {
        match self {
            PeriodicGps::Never => None,
            PeriodicGps::Always { period_us } | PeriodicGps::WhileRecording { period_us } => {
                Some(period_us)
            }
        }
    }
}

/// Periods of the periodic reports, microseconds (0 = not sent).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReportPeriods {
    /// 0x000001 gimbal status (document: 2 Hz).
    pub gimbal_status_us: u64,
    /// 0x000002 gimbal attitude (10 Hz).
    pub attitude_us: u64,
    /// 0x000003 camera system status (1 Hz).
    pub system_status_us: u64,
    /// 0x000004 infrared status (5 Hz).
    pub ir_status_us: u64,
    /// 0x000005 visible status (5 Hz).
    pub visible_status_us: u64,
}

impl Default for ReportPeriods {
    fn default() -> Self {
        ReportPeriods {
            gimbal_status_us: 500_000,
            attitude_us: 100_000,
            system_status_us: 1_000_000,
            ir_status_us: 200_000,
            visible_status_us: 200_000,
        }
    }
}

impl ReportPeriods {
    pub(super) fn as_array(&self) -> [u64; 5] {
        [
            self.gimbal_status_us,
            self.attitude_us,
            self.system_status_us,
            self.ir_status_us,
            self.visible_status_us,
        ]
    }
}

/// Corruption of the pod's output (probabilities per frame, 0.0..=1.0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputFaults {
    /// Seed of the generator (0 is replaced by a fixed non-zero value).
    pub seed: u64,
    /// Probability that a burst of 1..=`max_garbage_len` random bytes precedes a frame.
    pub garbage_probability: f64,
    /// Longest garbage burst.
    pub max_garbage_len: usize,
    /// Probability that one random bit of a frame is flipped.
    pub bit_flip_probability: f64,
}

impl Default for OutputFaults {
    fn default() -> Self {
        OutputFaults {
            seed: 1,
            garbage_probability: 0.0,
            max_garbage_len: 8,
            bit_flip_probability: 0.0,
        }
    }
}

/// The sequence number of an ACK.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AckSeq {
    /// The document's reading: an ACK is a message the pod sends, so it takes the next
    /// number of its source address's counter, like a report.
    OwnCounter,
    /// The ACK carries the request's sequence number and does not advance the counter
    /// (as the reference ACK exchange of docs/src/protocols/k40t.md has it; the type's
    /// default, kept from before the bridge matched ACKs as docs/src/bridge/engine.md
    /// says: [`PodSimConfig`] takes [`AckSeq::OwnCounter`]).
    #[default]
    Echo,
}

/// Configuration of a [`SimPod`]. Every default follows the module documentation.
#[derive(Debug, Clone, PartialEq)]
pub struct PodSimConfig {
    /// Source of gimbal-class frames (0x000001, 0x000002, ACKs of 0x000010..0x0000FF).
    pub gimbal_address: Address,
    /// Source of every other frame.
    pub camera_address: Address,
    /// Destination of reports, status frames and GPS requests.
    pub fc_address: Address,
    /// CRC coverage of every frame sent, and of the frames accepted.
    pub coverage: CrcCoverage,
    /// Accept received frames with either CRC coverage.
    pub accept_any_coverage: bool,
    /// Ignore received frames not addressed to the gimbal or camera address.
    pub strict_destination: bool,
    /// Silence after which the line is idle and an incomplete frame is given up (0 =
    /// never).
    pub rx_idle_timeout_us: u64,
    /// Report periods.
    pub reports: ReportPeriods,
    /// Delay between a request and its ACK (and the status frames that follow it).
    pub ack_delay_us: u64,
    /// Sequence number of the ACKs ([`AckSeq::OwnCounter`] by default, the document's
    /// reading; [`AckSeq::Echo`] the alternative).
    pub ack_seq: AckSeq,
    /// First sequence number of every source's counter, at power-up and after each
    /// reboot.
    pub seq_start: u8,
    /// Write the ACK response code little-endian.
    pub ack_code_le: bool,
    /// Per base id: answer with this code and do not execute the command.
    pub nak: BTreeMap<u16, AckCode>,
    /// Per base id: drop this many ACKs first (the command is executed).
    pub drop_acks: BTreeMap<u16, u32>,
    /// Answer unknown base ids with a bare OK.
    pub ack_unknown: bool,
    /// Initial pitch dial speed, 0.2°/s.
    pub pitch_dial_x5: u8,
    /// Initial yaw dial speed, 0.2°/s.
    pub yaw_dial_x5: u8,
    /// Speed of target moves (0x000012, centre, look down, point to aim), °/s.
    pub slew_speed_dps: f64,
    /// Pitch range, degrees (min, max).
    pub pitch_limits_deg: (f64, f64),
    /// Yaw range, degrees (min, max).
    pub yaw_limits_deg: (f64, f64),
    /// Horizontal field of view at 1x, degrees (point to aim).
    pub hfov_1x_deg: f64,
    /// Frame tracking requires AI recognition on.
    pub track_requires_ai: bool,
    /// Motion commands have no effect while tracking.
    pub track_blocks_motion: bool,
    /// Smallest hybrid zoom, 0.1x.
    pub zoom_min_x10: u16,
    /// Largest hybrid zoom, 0.1x.
    pub zoom_max_x10: u16,
    /// Zoom speed: natural-log units of the ratio per second.
    pub zoom_rate_per_s: f64,
    /// One zoom step of 0x000306 (3, 4), 0.1x.
    pub zoom_step_x10: u16,
    /// Focal length at 1x, 0.01 mm.
    pub focal_length_1x_10um: u16,
    /// Duration of an auto focus.
    pub focus_duration_us: u64,
    /// Delay between a photo request and the shot (and its GPS request).
    pub photo_gps_delay_us: u64,
    /// The GPS request of photo N (0-based, in the order the pod took them) leaves the
    /// pod this much after the photo, naming the photo's instant all the same: requests
    /// that reach the bridge out of the order of their photos.
    pub photo_gps_late_us: BTreeMap<usize, u64>,
    /// Interval between the shots of a burst.
    pub burst_interval_us: u64,
    /// Send status frames for a single shot too.
    pub single_shot_status: bool,
    /// Refuse photos in video mode and recording in photo mode (code Failure).
    pub enforce_capture_mode: bool,
    /// Laser distance, 0.1 m.
    pub laser_distance_dm: u16,
    /// The camera's IP address, subnet mask and gateway (0x000312; the document's
    /// default address 192.168.144.64, 2.3.1).
    pub ip: [[u8; 4]; 3],
    /// Gimbal hardware version (0x000018).
    pub gimbal_hardware: Version,
    /// Gimbal software version (0x000018).
    pub gimbal_software: Version,
    /// Camera version (0x000317).
    pub camera_version: Version,
    /// The pod's clock at `now_us` = 0, ms since the Unix epoch.
    pub initial_unix_ms: u64,
    /// How fast the pod's clock runs, parts per million.
    pub clock_drift_ppm: i32,
    /// Error the pod adds when it sets its clock from a sync, microseconds.
    pub sync_error_us: i64,
    /// Longest delay from a rising edge to the start of its 0x00030E.
    pub sync_window_us: u64,
    /// Ask for GPS even when never synchronised.
    pub gps_when_unsynced: bool,
    /// Ask for GPS in local time (the sync's time zone) rather than UTC.
    pub gps_local_time: bool,
    /// Lens enable byte of 0x000310 (before a photo).
    pub gps_lens_enable: u8,
    /// GPS requests that are no photo's ([`PeriodicGps`]).
    pub gps_periodic: PeriodicGps,
    /// Lens enable byte of those.
    pub gps_periodic_lens_enable: u8,
    /// Time after which a GPS request counts as unanswered.
    pub gps_timeout_us: u64,
    /// Corruption of the output.
    pub faults: OutputFaults,
}

impl Default for PodSimConfig {
    fn default() -> Self {
        PodSimConfig {
            gimbal_address: Address::GIMBAL,
            camera_address: Address::POD,
            fc_address: Address::FLIGHT_CONTROLLER,
            coverage: CrcCoverage::ExcludeStx,
            accept_any_coverage: false,
            strict_destination: false,
            rx_idle_timeout_us: 10_000,
            reports: ReportPeriods::default(),
            ack_delay_us: 0,
            ack_seq: AckSeq::OwnCounter,
            seq_start: 0,
            ack_code_le: false,
            nak: BTreeMap::new(),
            drop_acks: BTreeMap::new(),
            ack_unknown: false,
            pitch_dial_x5: 50,
            yaw_dial_x5: 50,
            slew_speed_dps: 45.0,
            pitch_limits_deg: (-90.0, 30.0),
            yaw_limits_deg: (-180.0, 180.0),
            hfov_1x_deg: 60.0,
            track_requires_ai: true,
            track_blocks_motion: true,
            zoom_min_x10: 10,
            zoom_max_x10: 1600,
            zoom_rate_per_s: 1.0,
            zoom_step_x10: 10,
            focal_length_1x_10um: 450,
            focus_duration_us: 500_000,
            photo_gps_delay_us: 20_000,
            photo_gps_late_us: BTreeMap::new(),
            burst_interval_us: 300_000,
            single_shot_status: false,
            enforce_capture_mode: false,
            laser_distance_dm: 1234,
            ip: [[192, 168, 144, 64], [255, 255, 255, 0], [192, 168, 144, 1]],
            gimbal_hardware: Version {
                major: 1,
                minor: 0,
                patch: 0,
            },
            gimbal_software: Version {
                major: 1,
                minor: 2,
                patch: 3,
            },
            camera_version: Version {
                major: 2,
                minor: 0,
                patch: 1,
            },
            initial_unix_ms: 0,
            clock_drift_ppm: 0,
            sync_error_us: 0,
            sync_window_us: 100_000,
            gps_when_unsynced: true,
            gps_local_time: false,
            gps_lens_enable: 1,
            gps_periodic: PeriodicGps::Never,
            gps_periodic_lens_enable: 0,
            gps_timeout_us: 1_000_000,
            faults: OutputFaults::default(),
        }
    }
}

/// The thermal picture in the IR coordinates of 0x000004, 0x00010F and 0x000110: a
/// 1920 × 1088 frame whose picture, the 640 × 512 sensor at twice its size, is x
/// 320..1599, y 32..1055 (docs/src/protocols/k40t.md).
pub const IR_PICTURE: ((u16, u16), (u16, u16)) = ((320, 32), (1280, 1024));

/// What the thermal camera sees at `t_us` (0x000004): a hot spot and a cold spot going
/// round the picture's centre on opposite sides (a 20 s turn, 400 × 300 px), the
/// maximum and minimum swinging by 1.5 °C (30 s); the region is the whole picture, the
/// measured point its centre.
#[must_use]
pub fn ir_scene(t_us: u64) -> IrStatus {
    let s = t_us as f64 / 1e6;
    let turn = s * std::f64::consts::TAU / 20.0;
    let swing = (s * std::f64::consts::TAU / 30.0).sin();
    let ((left, top), (w, h)) = IR_PICTURE;
    let (cx, cy) = (
        f64::from(left) + f64::from(w) / 2.0,
        f64::from(top) + f64::from(h) / 2.0,
    );
    let (dx, dy) = (400.0 * turn.cos(), 300.0 * turn.sin());
    let px = |v: f64| v.round() as u16;
    let dc = |v: f64| v.round() as i16;
    IrStatus {
        max_temp_dc: dc(412.0 + 15.0 * swing),
        min_temp_dc: dc(153.0 - 15.0 * swing),
        max_x: px(cx + dx),
        max_y: px(cy + dy),
        min_x: px(cx - dx),
        min_y: px(cy - dy),
        ..IR_STATUS
    }
}
