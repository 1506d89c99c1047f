//! A simulated K40T four-sensor pod (`000_cac8f3505cecd78b.txt`), sans-IO, in simulated
//! time, for the bridge's host tests and the demo.
//!
//! The pod talks to one peer, the bridge acting as the flight controller. Time is plain
//! `u64` microseconds chosen by the caller (independent of the bridge's own time type);
//! it never goes backwards inside the simulator (an earlier `now_us` is taken as the
//! latest one seen).
//!
//! ```
//! use gimbal::sim::pod::{PodSimConfig, SimPod};
//!
//! let mut pod = SimPod::new(PodSimConfig::default());
//! let mut wire = Vec::new();
//! while pod.next_wakeup() <= 1_000_000 {
//!     let t = pod.next_wakeup();
//!     pod.poll(t);
//!     wire.extend(pod.transmit()); // bytes for the bridge
//! }
//! // 1 s of reports: 2 gimbal status, 10 attitude, 1 system, 5 IR, 5 visible (the
//! // schedule starts at the first call, t = 0, and includes t = 1 s).
//! assert_eq!(pod.sent_count(0x00_0002), 11);
//! assert!(!wire.is_empty());
//! ```
//!
//! # Interface
//! - [`SimPod::receive`]: bytes from the bridge, found with the crate's
//!   [`Deframer`] (garbage, bit flips and cut frames are skipped, as a real receiver
//!   would; see [`RxStats`]).
//! - [`SimPod::rtc_edge`]: the RTC_IO pin as the pod sees it.
//! - [`SimPod::poll`]: periodic work; [`SimPod::next_wakeup`] says when it is next due.
//! - [`SimPod::transmit`]: bytes for the bridge, in order.
//!
//! Every entry point first runs the work due up to `now_us` (reports, status frames,
//! photos, timeouts; each at its own due instant, so a late call catches up and loses
//! nothing), then does its own part, then runs what became due at `now_us`.
//!
//! # Behaviour, and the choices where the document is open
//! **Frames.** Sent with the configured CRC coverage ([`CrcCoverage::ExcludeStx`] by
//! default). Received frames must carry the same coverage (a device computes one CRC);
//! [`PodSimConfig::accept_any_coverage`] accepts either. The destination address of a
//! received frame is not checked unless [`PodSimConfig::strict_destination`] is set (then
//! only the gimbal and camera addresses are accepted). The line is treated as idle when
//! no byte came for [`PodSimConfig::rx_idle_timeout_us`] (10 ms): an incomplete frame
//! (e.g. a length byte corrupted upwards) is then given up and the bytes behind it are
//! scanned again.
//!
//! **Addresses.** The document puts the gimbal at 0x03/0x01 (section 3.1) and the pod at
//! 0x04/0x01 (2.1, 3.2). Gimbal-class messages (reports 0x000001/0x000002 and the ACKs of
//! 0x000010..0x0000FF) come from [`PodSimConfig::gimbal_address`] (0x03/0x01 by default),
//! everything else from [`PodSimConfig::camera_address`] (0x04/0x01). ACKs go to the
//! request's sender; reports, status frames and GPS requests go to
//! [`PodSimConfig::fc_address`] (0x02/0x01).
//!
//! **Sequence numbers.** Each source address has its own counter (one counter when both
//! addresses are equal), starting at [`PodSimConfig::seq_start`] (0) at every boot and
//! incremented for every frame that source sends (reports, status frames, GPS
//! requests). The document's field table says the SEQ byte is incremented by each
//! component for every message it sends; an ACK is a message the pod sends, so in the
//! document's reading ([`AckSeq::OwnCounter`]) an ACK takes the next number of its
//! source's counter, like a report: this is the default. [`AckSeq::Echo`] gives an ACK
//! the request's sequence number and leaves the counter alone, as the one reference ACK
//! of SPEC-NOTES happens to do (tests run the bridge against both). A requester that
//! insists on an echoed SEQ retries every command sent to an `OwnCounter` pod. Frames
//! generated while the cable is cut ([`SimPod::set_silent`]) are lost but still consume
//! their number, so the bridge sees a gap.
//!
//! **Reports.** 0x000001 at 2 Hz, 0x000002 at 10 Hz, 0x000003 at 1 Hz, 0x000004 and
//! 0x000005 at 5 Hz ([`ReportPeriods`]; a period of 0 disables one). The schedule starts
//! at the first call (power-up) with all five reports, then every period exactly
//! (no jitter). 0x000004 stops while IR measurement is off (0x000108), as the document's
//! measurement switch says. 0x000008 (upgrade progress) is not sent: there is no upgrade.
//! Report contents: links and self-test all normal; stabilisation `Active` after
//! 0x000033 on, `Off` otherwise; IR temperatures are fixed values
//! ([`IR_STATUS`]); visible status carries the zoom model, its state and focus state.
//!
//! **ACKs.** Every request gets its ACK at once (after [`PodSimConfig::ack_delay_us`],
//! 0 by default) with a sequence number as [`PodSimConfig::ack_seq`] says, response code
//! OK, and the data the document defines: versions (0x000018, 0x000317), all IR parameters (0x000100), all
//! visible parameters (0x000200), the IP configuration (0x000312, 192.168.144.64/24,
//! gateway 192.168.144.1), the laser target's position (0x000320), the laser distance
//! (0x000400) and the SBUS configuration (0x000502). Faults, per base id:
//! [`PodSimConfig::nak`] answers with that code instead, with the ACK's data fields zeroed,
//! and the command is *not* executed; [`PodSimConfig::drop_acks`] drops the first N ACKs
//! (the command *is* executed: the ACK is what got lost). The response code is written
//! big-endian (the crate's reading), little-endian with [`PodSimConfig::ack_code_le`].
//! Frames the bridge should not send (the periodic report ids, 0x000310 requests, ACKs
//! other than 0x010310, status frames) are counted and otherwise ignored. An unknown
//! base id is counted and not answered, unless [`PodSimConfig::ack_unknown`] (then a bare
//! OK).
//!
//! **Motion** (sign convention: yaw positive to the right, seen from above; pitch
//! positive up; 0/0 is the centre; angles in the reports are 0.01°, rates 0.01°/s). Each
//! axis holds, moves at a rate, or moves to a target:
//! - 0x000010 with no quick function: each axis moves left/right (up/down) at its dial
//!   speed, or stops; it stops by itself at the limits. Centre moves both axes to 0;
//!   look down moves pitch to −90° and keeps yaw (the motion bytes are then ignored).
//! - 0x000017 sets the dial speeds, unit 0.2°/s, clamped to 5..=150 (1..=30°/s);
//!   default 50 (10°/s) on both axes. A rate in progress takes the new speed at once.
//! - 0x000012 moves to absolute joint angles (unit 0.01° per SPEC-NOTES; direction byte
//!   2 leaves that axis alone), clamped to the limits (pitch −90..+30°, yaw ±180°, hard
//!   stops, no wrap). Target moves (and centre, look down, point to aim) run at
//!   [`PodSimConfig::slew_speed_dps`] (45°/s), not at the dial speed, which the document
//!   ties to manual (dial) control.
//! - 0x00002C point to aim: the pixel (x, y) of a 1920 x 1080 image becomes the centre,
//!   with a pinhole model whose horizontal field of view is
//!   [`PodSimConfig::hfov_1x_deg`] (60°) divided by the command's zoom; the visible zoom
//!   then goes to the command's zoom when the lens is the telephoto one.
//! - 0x00002D servo off: both axes hold where they are.
//! - While frame tracking (0x000324) is on, motion commands are ACKed but have no
//!   effect ([`PodSimConfig::track_blocks_motion`]; the document says the gimbal is in
//!   tracking mode until tracking is switched off); switching it on stops both axes (the
//!   simulated target does not move). Tracking can only be switched on
//!   while AI recognition (0x000319) is on, else the ACK says Failure
//!   ([`PodSimConfig::track_requires_ai`]).
//! - Attitude angles equal the joint angles (the simulated aircraft is level, heading
//!   north); roll is 0. Rates are the current commanded motion (0 at a limit).
//!
//! **Camera.**
//! - Zoom: the ratio moves at a constant logarithmic rate
//!   ([`PodSimConfig::zoom_rate_per_s`], 1.0: ×e per second, 1x→160x in 5.1 s) between
//!   1x and 160x. 0x000304 moves to the ratio (clamped) and sends 0x020304 status frames
//!   (zooming) at once and every 200 ms, and one "completed" at the instant the ratio is
//!   reached. 0x000306 zooms continuously until stop or a limit; "zoom in/out" (3/4)
//!   moves one step of [`PodSimConfig::zoom_step_x10`] (1.0x); no status frames.
//!   0x000005 reports the ratio, "zooming" while it moves, and a focal length of
//!   [`PodSimConfig::focal_length_1x_10um`] times the optical part (up to 11x).
//! - Focus (0x000313): auto, area and one-touch focus take
//!   [`PodSimConfig::focus_duration_us`]; manual +/− focus until stop; auto focus after
//!   zoom (on/off) starts a focus when a zoom move ends.
//! - Photo (0x000302, start): ACK; the shot is taken
//!   [`PodSimConfig::photo_gps_delay_us`] (20 ms) later, and "before taking a photo" the
//!   pod sends 0x000310 asking for the UTC time of day of that instant, read from its own
//!   clock. Single shot: no status frame (the document says so;
//!   [`PodSimConfig::single_shot_status`] sends "single shot in progress" and "photo
//!   taken"); every single-shot request that reaches the pod takes its own photo, even
//!   one that comes while the previous shot is pending (a retried request is a second
//!   photo, as on a real camera); burst (0x000301): one shot and one GPS request every
//!   [`PodSimConfig::burst_interval_us`], a status frame per shot, then "taken";
//!   time-lapse: one shot every interval until stop ("stopped"). A photo request while
//!   a burst or time-lapse runs (or a burst request while a shot is pending) gets "photo
//!   in progress" (0x0203) and takes nothing. Stop ends a burst or time-lapse.
//! - Recording (0x000303): start (repeating it does not stop), 0x020303 status at once and
//!   every second with the elapsed seconds, one "stopped" frame on stop. Starting a
//!   recording switches the mode 0x000003 reports to video (as 0x000300 would; it stays
//!   so after the stop). The document says the camera ignores photo commands in video
//!   mode and recording commands in photo mode; this is off by default and, with
//!   [`PodSimConfig::enforce_capture_mode`], answered with the code Failure.
//! - Settings that show in the reports: capture mode 0x000300, photo parameters 0x000301,
//!   bitrate 0x000308, codec 0x00030B, image mode 0x000318 (the stream field of
//!   0x000003), EV 0x000205, AE lock 0x00020A; palette 0x000106 and measurement switch
//!   0x000108 show in the 0x000100 ACK.
//! - Laser: 0x000400 single ranging answers the configured distance
//!   ([`SimPod::set_laser_distance_dm`]; 0 when the command is "disable"); 0x000406
//!   sends 0x020406 with the distance at once and every second until disabled.
//!
//! **Time.** The pod has its own free-running clock: it reads
//! [`PodSimConfig::initial_unix_ms`] at `now_us` = 0 (0 by default: 1970-01-01, time of
//! day 00:00:00.000 at power-up) and runs [`PodSimConfig::clock_drift_ppm`] fast. A rising
//! edge of RTC_IO is recorded; a 0x00030E whose first byte arrives within
//! [`PodSimConfig::sync_window_us`] (100 ms) after the latest rising edge sets the clock so
//! that the edge instant reads the frame's `unix_ms` (plus
//! [`PodSimConfig::sync_error_us`], a systematic error of the pod), and consumes the edge.
//! Every 0x00030E is recorded ([`SimPod::syncs`]) with the edge instant, the instant its
//! first byte and its last byte arrived (the `now_us` of the `receive` calls that
//! brought them), the value, the edge-to-frame delay and the outcome: applied, no edge
//! (not applied: the frame carries no instant of its own), an edge older than the window,
//! or an edge after the frame had started. The ACK is OK in every case. Time zone fields
//! are recorded; the time of day asked in 0x000310 is UTC (local time, with the time zone
//! of the last applied sync, with [`PodSimConfig::gps_local_time`]). An unsynchronised pod still asks, with its free-running
//! time, unless [`PodSimConfig::gps_when_unsynced`] is off.
//!
//! **GPS.** Each 0x000310 is recorded ([`SimPod::gps_requests`]); every 0x010310 received
//! is recorded ([`SimPod::gps_replies`]) and matched to a request of the current boot as
//! SPEC-NOTES matches ACKs (the reply is the FC's message, so it may carry the FC's own
//! counter rather than the request's SEQ): a pending request with the same sequence
//! number (the oldest), else the most recent request that timed out with that number
//! (a late reply), else the oldest pending request; the SEQ is preferred, never
//! required. A request without a reply within [`PodSimConfig::gps_timeout_us`] (1 s)
//! counts as unanswered ([`SimPod::gps_unanswered`]) and is not repeated (the document
//! specifies no retry); a later reply is still recorded, marked late.
//!
//! **Reboot.** [`SimPod::reboot`] cuts the pod's power: for the given time it is dead
//! (nothing goes out, received bytes and RTC_IO edges are dropped, pending ACKs, status
//! frames, shots and GPS requests are lost; a pending GPS request counts as unanswered),
//! then it boots as at power-up: the clock restarts from
//! [`PodSimConfig::initial_unix_ms`] (no UTC until the next applied sync), the time zone
//! is cleared, zoom 1x, gimbal centred and holding, dial speeds from the configuration,
//! stabilisation, recording, laser ranging, AI and tracking off, camera settings at their
//! defaults, the report schedule restarts at the boot instant with all five reports, and
//! every sequence counter starts again at [`PodSimConfig::seq_start`] (or the start given
//! to [`SimPod::reboot_with`]). The logs and counters kept for assertions (frames,
//! requests, photos, syncs, GPS records, motions, faults) survive; [`SimPod::boots`]
//! lists the power-up instants.
//!
//! **Faults.** [`SimPod::set_silent`] cuts the cable: nothing goes out (generated frames
//! are lost), received bytes and RTC_IO edges are dropped; the pod keeps running (its
//! motion, clock and schedules go on). [`OutputFaults`] inserts garbage bursts before
//! frames and flips one bit in frames, with probabilities and a seeded xorshift64*
//! generator, so a run is reproducible.
//!
//! **Records.** Every frame received and sent is kept (with its bytes) for assertions, a
//! few MB per simulated hour; [`SimPod::clear_records`] drops those two logs in a long
//! run (the counters stay). Every request is also logged, decoded, with what the pod did
//! about it ([`SimPod::requests`], [`SimPod::requests_received`],
//! [`SimPod::photo_requests`]): "one photo per shutter press" is
//! `photos().len() == photo_requests()` and one request per press.
//!
//! **Not modelled.** Serial line timing (the caller delivers bytes when it wants;
//! [`SimPod::transmit`] returns everything generated so far), SD card space and errors,
//! upgrades, the soft restart command (0x00002F: ACKed, nothing restarts; a power
//! cycle is [`SimPod::reboot`]), a boot time before the first report (the pod reports at
//! the instant it is powered), IR image content, electronic zoom of the wide and IR
//! lenses (recorded only).

use super::XorShift;
use std::collections::{BTreeMap, VecDeque};

use protocol_core::k40t::{
    self, Ack, AckCode, Address, AeLock, CameraVersionAck, CaptureMode, CrcCoverage, Ev, FocusMode,
    FocusState, GimbalAngle, GimbalAttitude, GimbalControl, GimbalFunction, GimbalStatus,
    GimbalVersionAck, GpsReply, GpsRequest, Header, ImageMode, IpConfigAck, IrGain, IrParams,
    IrStatus, K40t, K40tFraming, Kind, LaserDistance, LaserMode, LaserPeriodicStatus, Lens, Links,
    MAX_FRAME_LEN, MeasureConfig, MeasureSwitch, Message, MessageData, Metering, MsgId, OnOff,
    Packet, Palette, PhotoMode, PhotoResolution, PhotoSensors, PhotoState, PhotoStatus,
    PitchMotion, PointToAim, PreviewResolution, Raw, RecordAction, RecordSensors, RecordState,
    RecordStatus, Request, ResponseCode, SbusChannelMap, SbusConfig, SdState, SelfTest,
    ShootAction, Shutter, StabilizationState, StreamBitrate, SwitchLevel, SystemStatus,
    TargetGpsAck, TargetGpsRequest, Toggle, TrackBox, UpgradeState, Version, VideoCodec,
    VideoResolution, VisibleParams, VisibleStatus, WhiteBalance, YawMotion, ZoomControl, ZoomState,
    ZoomStatus,
};
use protocol_core::wire::{Deframer, Event, Stats, Writer};

/// Base ids of the periodic reports, in [`ReportPeriods`] order.
const REPORT_IDS: [u16; 5] = [0x0001, 0x0002, 0x0003, 0x0004, 0x0005];
/// Interval of the 0x020304 status frames while a hybrid zoom moves.
const ZOOM_STATUS_PERIOD_US: u64 = 200_000;
/// Interval of the 0x020303 and 0x020406 status frames.
const ONE_SECOND_US: u64 = 1_000_000;
/// Milliseconds in a day.
const DAY_MS: i128 = 86_400_000;
/// Image size point-to-aim coordinates refer to (the document's 1..=1920 x 1..=1080).
const IMAGE_W: f64 = 1920.0;
const IMAGE_H: f64 = 1080.0;
/// Optical part of the hybrid zoom (the document: above 11x is electronic).
const OPTICAL_MAX_X10: f64 = 110.0;
/// Rounding tolerance of target moves: 1e-9 degree, 1e-12 of the zoom's logarithm.
const ANGLE_EPSILON_DEG: f64 = 1e-9;
const ZOOM_EPSILON_LN: f64 = 1e-12;

/// The fixed infrared measurements reported in 0x000004.
pub const IR_STATUS: IrStatus = IrStatus {
    max_temp_dc: 412,
    min_temp_dc: 153,
    center_temp_dc: 251,
    point_temp_dc: 268,
    avg_temp_dc: 240,
    max_x: 320,
    max_y: 200,
    min_x: 40,
    min_y: 480,
    center_x: 320,
    center_y: 256,
    point_x: 320,
    point_y: 256,
    high_warning: 0,
    low_warning: 0,
    diff_warning: 0,
    threshold_warning: 0,
    reserved: [0; 4],
};

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
    fn as_array(&self) -> [u64; 5] {
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
    /// (the default on this branch until the bridge matches ACKs as SPEC-NOTES says).
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
    /// Interval between the shots of a burst.
    pub burst_interval_us: u64,
    /// Send status frames for a single shot too.
    pub single_shot_status: bool,
    /// Refuse photos in video mode and recording in photo mode (code Failure).
    pub enforce_capture_mode: bool,
    /// Laser distance, 0.1 m.
    pub laser_distance_dm: u16,
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
    /// Lens enable byte of 0x000310.
    pub gps_lens_enable: u8,
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
            burst_interval_us: 300_000,
            single_shot_status: false,
            enforce_capture_mode: false,
            laser_distance_dm: 1234,
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
            gps_timeout_us: 1_000_000,
            faults: OutputFaults::default(),
        }
    }
}

/// Receive-side counters.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RxStats {
    /// Bytes received (while not silent).
    pub bytes: u64,
    /// Valid frames (CRC and length correct).
    pub frames: u64,
    /// The deframer's counters (CRC and length errors, discarded bytes).
    pub deframer: Stats,
    /// Valid frames whose payload is longer than the message's layout.
    pub malformed: u64,
    /// Frames ignored for their destination ([`PodSimConfig::strict_destination`]).
    pub misaddressed: u64,
    /// Bytes dropped while the cable was cut.
    pub dropped_while_silent: u64,
    /// Bytes dropped while the pod was off ([`SimPod::reboot`]).
    pub dropped_while_off: u64,
}

/// A valid frame the pod received.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RxRecord {
    /// When its first byte arrived.
    pub start_us: u64,
    /// When its last byte arrived.
    pub at_us: u64,
    /// Its header.
    pub header: Header,
    /// Its message id.
    pub id: MsgId,
    /// The whole frame.
    pub frame: Vec<u8>,
}

/// A frame the pod put on the line (before output faults).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TxRecord {
    /// When it was sent.
    pub at_us: u64,
    /// Its header.
    pub header: Header,
    /// Its message id.
    pub id: MsgId,
    /// The whole frame, uncorrupted.
    pub frame: Vec<u8>,
}

/// A request the pod received, and what it did about it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RequestRecord {
    /// Arrival (last byte).
    pub at_us: u64,
    /// Its header (the requester's address and sequence number).
    pub header: Header,
    /// The request, decoded.
    pub request: Request,
    /// The response code of its ACK (`None`: the pod does not answer it: periodic
    /// report ids and 0x000310 from the bridge).
    pub code: Option<AckCode>,
    /// It was carried out (false: refused, with [`PodSimConfig::nak`] or by the
    /// camera, or not the pod's business).
    pub executed: bool,
    /// The sequence number of its ACK (`None`: no ACK, or dropped by
    /// [`PodSimConfig::drop_acks`]).
    pub ack_seq: Option<u8>,
}

/// A gimbal motion command the pod received (and ACKed OK).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionCommand {
    /// 0x000010.
    Control(GimbalControl),
    /// 0x000012.
    Angle(GimbalAngle),
    /// 0x000017.
    DialSpeed(k40t::DialSpeed),
    /// 0x00002C.
    PointToAim(PointToAim),
    /// 0x00002D.
    ServoOff,
}

/// A motion command and when it came.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MotionRecord {
    /// Arrival (last byte).
    pub at_us: u64,
    /// The command.
    pub command: MotionCommand,
    /// False when it had no effect (tracking).
    pub applied: bool,
}

/// The gimbal's state at the last processed instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GimbalState {
    /// Yaw joint angle, degrees, positive right.
    pub yaw_deg: f64,
    /// Pitch joint angle, degrees, positive up.
    pub pitch_deg: f64,
    /// Yaw rate, °/s.
    pub yaw_rate_dps: f64,
    /// Pitch rate, °/s.
    pub pitch_rate_dps: f64,
    /// Yaw dial speed, °/s.
    pub yaw_speed_dps: f64,
    /// Pitch dial speed, °/s.
    pub pitch_speed_dps: f64,
    /// Image stabilisation on.
    pub stabilization: bool,
}

/// A recording in progress.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Recording {
    /// Which sensors record (the request's sensor bits).
    pub sensors: RecordSensors,
    /// When it started.
    pub since_us: u64,
}

/// The camera's state at the last processed instant.
#[derive(Debug, Clone, PartialEq)]
pub struct CameraState {
    /// Photo or video mode (0x000300; video while recording).
    pub mode: CaptureMode,
    /// Photo function (0x000301).
    pub photo_mode: PhotoMode,
    /// Time-lapse interval, s.
    pub timelapse_s: u8,
    /// Burst count.
    pub burst_count: u8,
    /// Streamed image (0x000318).
    pub image_mode: ImageMode,
    /// Stream codec (0x00030B).
    pub codec: VideoCodec,
    /// Stream bitrate (0x000308).
    pub bitrate: StreamBitrate,
    /// Thermal palette (0x000106).
    pub palette: Palette,
    /// IR measurement on (0x000108).
    pub ir_measuring: bool,
    /// Hybrid zoom ratio, 0.1x (fractional while moving).
    pub zoom_x10: f64,
    /// Where a zoom move is going (None: not moving, or continuous).
    pub zoom_target_x10: Option<f64>,
    /// The zoom is moving.
    pub zooming: bool,
    /// Last focus command.
    pub focus: Option<FocusMode>,
    /// Auto focus after zoom.
    pub af_after_zoom: bool,
    /// Recording in progress.
    pub recording: Option<Recording>,
    /// Photos taken so far.
    pub photos_taken: u32,
    /// Laser periodic ranging on.
    pub laser_periodic: bool,
    /// Laser distance, 0.1 m.
    pub laser_distance_dm: u16,
    /// AI recognition on (0x000319).
    pub ai: bool,
    /// Frame tracking box, while on (0x000324).
    pub track: Option<TrackBox>,
    /// EV (0x000205).
    pub ev: Ev,
    /// AE lock (0x00020A).
    pub ae_lock: AeLock,
}

/// A level change of RTC_IO.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RtcEdge {
    /// Simulated time of the event, µs.
    pub at_us: u64,
    /// The new level (true: rising edge).
    pub high: bool,
}

/// What a 0x00030E did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SyncOutcome {
    /// The clock was set: the edge instant reads the frame's time.
    Applied,
    /// No rising edge since the previous sync: not applied.
    NoEdge,
    /// The latest rising edge is older than the window: not applied.
    EdgeTooOld,
    /// The latest rising edge came after the frame had started: not applied.
    EdgeAfterFrameStart,
}

/// One 0x00030E received.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SyncRecord {
    /// The rising edge it was matched with (the latest unconsumed one).
    pub edge_us: Option<u64>,
    /// When its first byte arrived.
    pub frame_start_us: u64,
    /// When its last byte arrived.
    pub arrival_us: u64,
    /// Its time, ms since the Unix epoch.
    pub unix_ms: u64,
    /// Its time zone, minutes west.
    pub tz_minuteswest: i32,
    /// Its DST type.
    pub tz_dsttime: i32,
    /// Edge to first byte (when the edge came first).
    pub delay_us: Option<u64>,
    /// What it did.
    pub outcome: SyncOutcome,
}

/// One 0x000310 the pod sent.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GpsRequestRecord {
    /// Simulated time of the event, µs.
    pub at_us: u64,
    /// Its sequence number.
    pub seq: u8,
    /// Its payload.
    pub request: GpsRequest,
    /// The pod's clock at the shot, ms since the Unix epoch.
    pub pod_unix_ms: u64,
    /// The pod had been synchronised.
    pub synced: bool,
    /// Index of the photo in [`SimPod::photos`].
    pub photo: usize,
    /// Index of the reply in [`SimPod::gps_replies`].
    pub reply: Option<usize>,
    /// No reply within the timeout (or the pod rebooted before one came).
    pub timed_out: bool,
    /// The boot it belongs to (index in [`SimPod::boots`]).
    pub boot: usize,
}

/// One 0x010310 the pod received.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GpsReplyRecord {
    /// Simulated time of the event, µs.
    pub at_us: u64,
    /// Its header.
    pub header: Header,
    /// Its payload (code, echoed time, position, attitude).
    pub reply: GpsReply,
    /// Index of the request it answers in [`SimPod::gps_requests`], if any (see the
    /// module documentation for the matching rule).
    pub request: Option<usize>,
    /// Its sequence number equals the matched request's.
    pub seq_matches: bool,
    /// Request to reply.
    pub latency_us: Option<u64>,
    /// The echoed time of day equals the request's.
    pub time_matches: bool,
    /// It came after the timeout.
    pub late: bool,
}

/// One photo taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PhotoRecord {
    /// Simulated time of the photo, µs.
    pub at_us: u64,
    /// Which sensors took it (the request's sensor bits).
    pub sensors: PhotoSensors,
    /// The pod's clock, ms since the Unix epoch.
    pub pod_unix_ms: u64,
    /// Shot number within its burst or time-lapse, from 1.
    pub shot: u16,
    /// Index of its GPS request in [`SimPod::gps_requests`].
    pub gps_request: Option<usize>,
}

/// One axis of the gimbal.
#[derive(Debug, Clone, Copy)]
enum AxisMotion {
    Hold,
    /// Direction −1, 0 or +1 at the dial speed.
    Rate(f64),
    /// Target angle at the slew speed.
    Target(f64),
}

#[derive(Debug, Clone, Copy)]
struct Axis {
    angle: f64,
    motion: AxisMotion,
    min: f64,
    max: f64,
}

impl Axis {
    fn new((min, max): (f64, f64)) -> Self {
        Axis {
            angle: 0.0,
            motion: AxisMotion::Hold,
            min,
            max,
        }
    }

    fn advance(&mut self, dt_s: f64, dial_dps: f64, slew_dps: f64) {
        match self.motion {
            AxisMotion::Hold => {}
            AxisMotion::Rate(dir) => {
                self.angle = (self.angle + dir * dial_dps * dt_s).clamp(self.min, self.max);
            }
            AxisMotion::Target(target) => {
                let diff = target - self.angle;
                let step = slew_dps * dt_s;
                // The tolerance absorbs rounding over many steps: a move that should end
                // at an instant ends there.
                if diff.abs() <= step + ANGLE_EPSILON_DEG {
                    self.angle = target;
                    self.motion = AxisMotion::Hold;
                } else {
                    self.angle += step.copysign(diff);
                }
            }
        }
    }

    fn rate(&self, dial_dps: f64, slew_dps: f64) -> f64 {
        match self.motion {
            AxisMotion::Hold => 0.0,
            AxisMotion::Rate(dir) => {
                let blocked =
                    (dir > 0.0 && self.angle >= self.max) || (dir < 0.0 && self.angle <= self.min);
                if blocked { 0.0 } else { dir * dial_dps }
            }
            AxisMotion::Target(target) if target > self.angle => slew_dps,
            AxisMotion::Target(target) if target < self.angle => -slew_dps,
            AxisMotion::Target(_) => 0.0,
        }
    }

    fn go_to(&mut self, angle: f64) {
        self.motion = AxisMotion::Target(angle.clamp(self.min, self.max));
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum ZoomMotion {
    Idle,
    /// Towards a ratio; `hybrid`: a 0x000304 move (with status frames).
    Target {
        target: f64,
        hybrid: bool,
    },
    /// Continuous, direction −1 or +1.
    Continuous(f64),
}

#[derive(Debug, Clone, Copy)]
struct PhotoJob {
    sensors: PhotoSensors,
    mode: PhotoMode,
    /// Shots to take (None: until stopped).
    total: Option<u16>,
    done: u16,
    next_us: u64,
    interval_us: u64,
}

/// The pod's clock: `base_unix_us` at simulated instant `base_us`.
#[derive(Debug, Clone, Copy)]
struct PodClock {
    base_us: u64,
    base_unix_us: i128,
    drift_ppm: i32,
    synced: bool,
}

impl PodClock {
    fn unix_us(&self, now_us: u64) -> i128 {
        let elapsed = i128::from(now_us) - i128::from(self.base_us);
        self.base_unix_us + elapsed + elapsed * i128::from(self.drift_ppm) / 1_000_000
    }
}

/// A frame waiting for its instant.
#[derive(Debug, Clone)]
struct Queued {
    due_us: u64,
    header: Header,
    id: MsgId,
    payload: Vec<u8>,
}

/// Work with a due instant, in firing order for equal instants.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Timer {
    RxIdle,
    Outbox,
    Report(usize),
    ZoomStatus,
    RecordStatus,
    Laser,
    PhotoShot,
    GpsTimeout,
}

/// The simulated pod. See the module documentation.
pub struct SimPod {
    config: PodSimConfig,
    now_us: u64,
    booted: bool,
    silent: bool,
    /// Off (rebooting) until then.
    off_until: Option<u64>,
    /// Sequence start of the next boot.
    next_seq_start: u8,
    /// Power-up instants.
    boots: Vec<u64>,
    /// The line level as the pod last saw it, while off too.
    rtc_line_high: bool,

    deframer: Deframer<K40tFraming, MAX_FRAME_LEN>,
    /// Bytes fed to the deframer so far.
    rx_fed: u64,
    /// (stream offset of a chunk's first byte, its arrival instant), oldest first.
    rx_chunks: VecDeque<(u64, u64)>,
    last_rx_us: u64,
    rx: RxStats,
    rx_counts: BTreeMap<u32, u32>,
    received: Vec<RxRecord>,

    out: Vec<u8>,
    outbox: Vec<Queued>,
    /// Frames to send after the ACK being built.
    deferred: Vec<(MsgId, Vec<u8>)>,
    seqs: BTreeMap<(u8, u8), u8>,
    /// Where the counters of this boot start.
    seq_base: u8,
    sent: Vec<TxRecord>,
    tx_counts: BTreeMap<u32, u32>,
    lost_while_silent: u64,
    acks_dropped: u32,
    rng: XorShift,
    garbage_bursts: u32,
    bit_flips: u32,

    report_due: [Option<u64>; 5],
    zoom_status_due: Option<u64>,
    record_status_due: Option<u64>,
    laser_due: Option<u64>,

    model_us: u64,
    yaw: Axis,
    pitch: Axis,
    pitch_dial_x5: u8,
    yaw_dial_x5: u8,
    stabilization: bool,
    camera: CameraState,
    zoom: ZoomMotion,
    focus_until_us: u64,
    manual_focus: bool,
    photo_job: Option<PhotoJob>,
    /// Single shots waiting for their instant: (due, sensors).
    single_shots: VecDeque<(u64, PhotoSensors)>,
    motions: Vec<MotionRecord>,
    requests: Vec<RequestRecord>,

    clock: PodClock,
    tz: (i32, i32),
    rtc_high: bool,
    pending_edge: Option<u64>,
    rtc_edges: Vec<RtcEdge>,
    syncs: Vec<SyncRecord>,

    photos: Vec<PhotoRecord>,
    gps_requests: Vec<GpsRequestRecord>,
    gps_open: VecDeque<usize>,
    gps_replies: Vec<GpsReplyRecord>,
    gps_unanswered: usize,
}

impl SimPod {
    /// A pod, powered up at the first call.
    #[must_use]
    pub fn new(config: PodSimConfig) -> Self {
        let camera = initial_camera(&config, config.laser_distance_dm, 0);
        SimPod {
            deframer: Deframer::new(framing_of(&config)),
            rx_fed: 0,
            rx_chunks: VecDeque::new(),
            last_rx_us: 0,
            rx: RxStats::default(),
            rx_counts: BTreeMap::new(),
            received: Vec::new(),
            out: Vec::new(),
            outbox: Vec::new(),
            deferred: Vec::new(),
            seqs: BTreeMap::new(),
            seq_base: config.seq_start,
            sent: Vec::new(),
            tx_counts: BTreeMap::new(),
            lost_while_silent: 0,
            acks_dropped: 0,
            rng: XorShift::new(config.faults.seed),
            garbage_bursts: 0,
            bit_flips: 0,
            report_due: [None; 5],
            zoom_status_due: None,
            record_status_due: None,
            laser_due: None,
            model_us: 0,
            yaw: Axis::new(config.yaw_limits_deg),
            pitch: Axis::new(config.pitch_limits_deg),
            pitch_dial_x5: config.pitch_dial_x5.clamp(5, 150),
            yaw_dial_x5: config.yaw_dial_x5.clamp(5, 150),
            stabilization: false,
            camera,
            zoom: ZoomMotion::Idle,
            focus_until_us: 0,
            manual_focus: false,
            photo_job: None,
            single_shots: VecDeque::new(),
            motions: Vec::new(),
            requests: Vec::new(),
            clock: PodClock {
                base_us: 0,
                base_unix_us: i128::from(config.initial_unix_ms) * 1000,
                drift_ppm: config.clock_drift_ppm,
                synced: false,
            },
            tz: (0, 0),
            rtc_high: false,
            pending_edge: None,
            rtc_edges: Vec::new(),
            syncs: Vec::new(),
            photos: Vec::new(),
            gps_requests: Vec::new(),
            gps_open: VecDeque::new(),
            gps_replies: Vec::new(),
            gps_unanswered: 0,
            now_us: 0,
            booted: false,
            silent: false,
            off_until: None,
            next_seq_start: config.seq_start,
            boots: Vec::new(),
            rtc_line_high: false,
            config,
        }
    }

    /// The configuration (NAK and drop maps as configured at creation).
    #[must_use]
    pub fn config(&self) -> &PodSimConfig {
        &self.config
    }

    /// The latest instant processed.
    #[must_use]
    pub fn now_us(&self) -> u64 {
        self.now_us
    }

    // ----- interface -----

    /// Bytes from the bridge, all arrived at `now_us`.
    pub fn receive(&mut self, now_us: u64, bytes: &[u8]) {
        let now = self.enter(now_us);
        if self.is_off() {
            self.rx.dropped_while_off =
                self.rx.dropped_while_off.saturating_add(bytes.len() as u64);
            return;
        }
        if self.silent {
            self.rx.dropped_while_silent = self
                .rx
                .dropped_while_silent
                .saturating_add(bytes.len() as u64);
            return;
        }
        self.rx.bytes = self.rx.bytes.saturating_add(bytes.len() as u64);
        self.last_rx_us = now;
        self.rx_chunks.push_back((self.rx_fed, now));
        let mut input = bytes;
        while !input.is_empty() {
            let n = self.deframer.feed(input);
            self.rx_fed += n as u64;
            input = input.get(n..).unwrap_or_default();
            let found = self.drain_deframer(now, false);
            if n == 0 && !found {
                // Cannot happen (a full buffer always yields an event); never spin.
                break;
            }
        }
        self.prune_chunks();
        self.run_until(now);
    }

    /// The RTC_IO pin as the pod sees it, at `now_us`.
    pub fn rtc_edge(&mut self, now_us: u64, high: bool) {
        let now = self.enter(now_us);
        self.rtc_line_high = high;
        if self.is_off() || self.silent || high == self.rtc_high {
            return;
        }
        self.rtc_high = high;
        self.rtc_edges.push(RtcEdge { at_us: now, high });
        if high {
            self.pending_edge = Some(now);
        }
        self.run_until(now);
    }

    /// Runs the work due up to `now_us`.
    pub fn poll(&mut self, now_us: u64) {
        self.enter(now_us);
    }

    /// The bytes generated so far, for the bridge.
    pub fn transmit(&mut self) -> Vec<u8> {
        std::mem::take(&mut self.out)
    }

    /// When [`SimPod::poll`] next has work (`u64::MAX`: none; before the first call: 0).
    #[must_use]
    pub fn next_wakeup(&self) -> u64 {
        if !self.booted {
            return 0;
        }
        if let Some(on) = self.off_until {
            return on;
        }
        self.next_timer().map_or(u64::MAX, |(t, _)| t)
    }

    // ----- power -----

    /// Cuts the pod's power at `now_us` for `off_us`, then boots it as at power-up, with
    /// its sequence counters at [`PodSimConfig::seq_start`] (see the module
    /// documentation). Work due up to `now_us` is done first.
    pub fn reboot(&mut self, now_us: u64, off_us: u64) {
        self.reboot_with(now_us, off_us, None);
    }

    /// [`SimPod::reboot`], with the counters of the new boot starting at `seq_start`
    /// (`None`: [`PodSimConfig::seq_start`]).
    pub fn reboot_with(&mut self, now_us: u64, off_us: u64, seq_start: Option<u8>) {
        let now = self.enter(now_us);
        // Whatever was in progress dies with the power.
        while let Some(i) = self.gps_open.pop_front() {
            if let Some(r) = self.gps_requests.get_mut(i) {
                r.timed_out = true;
            }
            self.gps_unanswered += 1;
        }
        self.outbox.clear();
        self.deferred.clear();
        self.photo_job = None;
        self.single_shots.clear();
        self.off_until = Some(now.saturating_add(off_us));
        self.next_seq_start = seq_start.unwrap_or(self.config.seq_start);
    }

    /// The pod is without power (rebooting) at the latest instant processed.
    #[must_use]
    pub fn is_off(&self) -> bool {
        self.off_until.is_some_and(|on| self.now_us < on)
    }

    /// The instants the pod was powered up: the first call, then the end of each reboot.
    #[must_use]
    pub fn boots(&self) -> &[u64] {
        &self.boots
    }

    /// Powers up at `t`: every state as at the first power-up, but the records.
    fn boot(&mut self, t: u64) {
        let first = !self.booted;
        self.booted = true;
        self.boots.push(t);
        self.off_until = None;
        if !first {
            self.deframer = Deframer::new(framing_of(&self.config));
            self.rx_chunks.clear();
            self.outbox.clear();
            self.deferred.clear();
            self.seqs.clear();
            self.yaw = Axis::new(self.config.yaw_limits_deg);
            self.pitch = Axis::new(self.config.pitch_limits_deg);
            self.pitch_dial_x5 = self.config.pitch_dial_x5.clamp(5, 150);
            self.yaw_dial_x5 = self.config.yaw_dial_x5.clamp(5, 150);
            self.stabilization = false;
            // The laser's distance is the scene's, not the pod's state.
            self.camera = initial_camera(
                &self.config,
                self.camera.laser_distance_dm,
                self.camera.photos_taken,
            );
            self.zoom = ZoomMotion::Idle;
            self.focus_until_us = 0;
            self.manual_focus = false;
            self.photo_job = None;
            self.single_shots.clear();
            self.clock = PodClock {
                base_us: t,
                base_unix_us: i128::from(self.config.initial_unix_ms) * 1000,
                drift_ppm: self.config.clock_drift_ppm,
                synced: false,
            };
            self.tz = (0, 0);
            self.rtc_high = self.rtc_line_high;
            self.pending_edge = None;
        }
        self.seq_base = self.next_seq_start;
        self.zoom_status_due = None;
        self.record_status_due = None;
        self.laser_due = None;
        self.model_us = t;
        for (due, period) in self
            .report_due
            .iter_mut()
            .zip(self.config.reports.as_array())
        {
            *due = (period > 0).then_some(t);
        }
    }

    // ----- fault injection -----

    /// Cuts (true) or restores (false) the pod's cable.
    pub fn set_silent(&mut self, silent: bool) {
        self.silent = silent;
    }

    /// The cable is cut.
    #[must_use]
    pub fn is_silent(&self) -> bool {
        self.silent
    }

    /// Replaces the output corruption (the generator restarts from the new seed).
    pub fn set_output_faults(&mut self, faults: OutputFaults) {
        self.rng = XorShift::new(faults.seed);
        self.config.faults = faults;
    }

    /// Answers requests of `base` with `code` (None: OK again).
    pub fn set_nak(&mut self, base: u16, code: Option<AckCode>) {
        match code {
            Some(code) => self.config.nak.insert(base, code),
            None => self.config.nak.remove(&base),
        };
    }

    /// Drops the next `count` ACKs of `base`.
    pub fn drop_acks(&mut self, base: u16, count: u32) {
        self.config.drop_acks.insert(base, count);
    }

    /// Sets the distance the laser measures, 0.1 m.
    pub fn set_laser_distance_dm(&mut self, distance_dm: u16) {
        self.camera.laser_distance_dm = distance_dm;
    }

    // ----- observation -----

    /// The gimbal at the latest processed instant.
    #[must_use]
    pub fn gimbal(&self) -> GimbalState {
        let (yaw_dial, pitch_dial) = self.dial_dps();
        let slew = self.config.slew_speed_dps;
        GimbalState {
            yaw_deg: self.yaw.angle,
            pitch_deg: self.pitch.angle,
            yaw_rate_dps: self.yaw.rate(yaw_dial, slew),
            pitch_rate_dps: self.pitch.rate(pitch_dial, slew),
            yaw_speed_dps: yaw_dial,
            pitch_speed_dps: pitch_dial,
            stabilization: self.stabilization,
        }
    }

    /// The camera at the latest processed instant.
    #[must_use]
    pub fn camera(&self) -> &CameraState {
        &self.camera
    }

    /// The last motion command.
    #[must_use]
    pub fn last_motion(&self) -> Option<&MotionRecord> {
        self.motions.last()
    }

    /// Every motion command, in order.
    #[must_use]
    pub fn motions(&self) -> &[MotionRecord] {
        &self.motions
    }

    /// When the first command to stop both axes (0x000010 yaw and pitch Stop) came after
    /// true time `after_us`.
    #[must_use]
    pub fn first_stop_after(&self, after_us: u64) -> Option<u64> {
        self.motions
            .iter()
            .find(|m| {
                m.at_us > after_us
                    && matches!(m.command, MotionCommand::Control(c)
                        if c.yaw == YawMotion::Stop && c.pitch == PitchMotion::Stop)
            })
            .map(|m| m.at_us)
    }

    /// The pod's clock at `now_us`, ms since the Unix epoch (0 before the epoch).
    #[must_use]
    pub fn clock_unix_ms(&self, now_us: u64) -> u64 {
        u64::try_from(self.clock.unix_us(now_us).div_euclid(1000)).unwrap_or(0)
    }

    /// A sync has set the clock.
    #[must_use]
    pub fn is_synced(&self) -> bool {
        self.clock.synced
    }

    /// Every RTC_IO level change.
    #[must_use]
    pub fn rtc_edges(&self) -> &[RtcEdge] {
        &self.rtc_edges
    }

    /// Every 0x00030E received.
    #[must_use]
    pub fn syncs(&self) -> &[SyncRecord] {
        &self.syncs
    }

    /// Every photo taken.
    #[must_use]
    pub fn photos(&self) -> &[PhotoRecord] {
        &self.photos
    }

    /// Every 0x000310 sent.
    #[must_use]
    pub fn gps_requests(&self) -> &[GpsRequestRecord] {
        &self.gps_requests
    }

    /// Every 0x010310 received.
    #[must_use]
    pub fn gps_replies(&self) -> &[GpsReplyRecord] {
        &self.gps_replies
    }

    /// GPS requests that got no reply within the timeout.
    #[must_use]
    pub fn gps_unanswered(&self) -> usize {
        self.gps_unanswered
    }

    /// Receive-side counters.
    #[must_use]
    pub fn rx_stats(&self) -> RxStats {
        RxStats {
            deframer: self.deframer.stats(),
            ..self.rx
        }
    }

    /// Every valid frame received, in order.
    #[must_use]
    pub fn received(&self) -> &[RxRecord] {
        &self.received
    }

    /// Valid frames received with the 24-bit message id `id` (e.g. 0x000304).
    #[must_use]
    pub fn received_count(&self, id: u32) -> u32 {
        self.rx_counts.get(&id).copied().unwrap_or(0)
    }

    /// Every received message of type `M`, with arrival instant and header.
    #[must_use]
    pub fn received_of<M: MessageData<Protocol = K40t>>(&self) -> Vec<(u64, Header, M)> {
        self.received
            .iter()
            .filter(|r| r.id == M::ID)
            .filter_map(|r| {
                let p = Packet::decode(&r.frame).ok()?;
                Some((r.at_us, r.header, p.message.get::<M>()?))
            })
            .collect()
    }

    /// Every frame put on the line, in order (uncorrupted).
    #[must_use]
    pub fn sent(&self) -> &[TxRecord] {
        &self.sent
    }

    /// Frames put on the line with the 24-bit message id `id`.
    #[must_use]
    pub fn sent_count(&self, id: u32) -> u32 {
        self.tx_counts.get(&id).copied().unwrap_or(0)
    }

    /// Every sent message of type `M`, with instant and header.
    #[must_use]
    pub fn sent_of<M: MessageData<Protocol = K40t>>(&self) -> Vec<(u64, Header, M)> {
        self.sent
            .iter()
            .filter(|r| r.id == M::ID)
            .filter_map(|r| {
                let p = Packet::decode(&r.frame).ok()?;
                Some((r.at_us, r.header, p.message.get::<M>()?))
            })
            .collect()
    }

    /// Frames generated while the cable was cut.
    #[must_use]
    pub fn lost_while_silent(&self) -> u64 {
        self.lost_while_silent
    }

    /// ACKs dropped by [`PodSimConfig::drop_acks`].
    #[must_use]
    pub fn acks_dropped(&self) -> u32 {
        self.acks_dropped
    }

    /// Every request received (but unknown ids), decoded, with what the pod did about it;
    /// kept by [`SimPod::clear_records`] and across reboots.
    #[must_use]
    pub fn requests(&self) -> &[RequestRecord] {
        &self.requests
    }

    /// Requests received with base id `base` (e.g. 0x0302), carried out or not.
    #[must_use]
    pub fn requests_received(&self, base: u16) -> usize {
        self.requests
            .iter()
            .filter(|r| r.request.base() == base)
            .count()
    }

    /// Photo requests (0x000302 start) received: shutter presses as the pod saw them.
    #[must_use]
    pub fn photo_requests(&self) -> usize {
        self.requests
            .iter()
            .filter(|r| matches!(r.request, Request::TakePhoto(p) if p.action != ShootAction::Stop))
            .count()
    }

    /// Drops the logs of received and sent frames ([`SimPod::received`], [`SimPod::sent`]);
    /// the per-id counters and every other record stay.
    pub fn clear_records(&mut self) {
        self.received.clear();
        self.sent.clear();
    }

    /// Output faults injected: (garbage bursts, bit flips).
    #[must_use]
    pub fn faults_injected(&self) -> (u32, u32) {
        (self.garbage_bursts, self.bit_flips)
    }

    // ----- scheduling -----

    /// Takes `now_us` (never backwards), powers up on the first call and at the end of
    /// a reboot, runs due work (none while off).
    fn enter(&mut self, now_us: u64) -> u64 {
        let now = now_us.max(self.now_us);
        if !self.booted {
            self.boot(now);
        }
        self.now_us = now;
        if let Some(on) = self.off_until {
            if now < on {
                return now;
            }
            self.boot(on);
        }
        self.run_until(now);
        now
    }

    fn next_timer(&self) -> Option<(u64, Timer)> {
        let idle =
            (self.config.rx_idle_timeout_us > 0 && self.deframer.buffered() > 0).then(|| {
                self.last_rx_us
                    .saturating_add(self.config.rx_idle_timeout_us)
            });
        let gps = self.gps_open.front().and_then(|&i| {
            self.gps_requests
                .get(i)
                .map(|r| r.at_us.saturating_add(self.config.gps_timeout_us))
        });
        let mut candidates = vec![
            (idle, Timer::RxIdle),
            (self.outbox.first().map(|q| q.due_us), Timer::Outbox),
        ];
        candidates.extend(
            self.report_due
                .iter()
                .enumerate()
                .map(|(i, &due)| (due, Timer::Report(i))),
        );
        candidates.extend([
            (self.zoom_status_due, Timer::ZoomStatus),
            (self.record_status_due, Timer::RecordStatus),
            (self.laser_due, Timer::Laser),
            (
                [
                    self.photo_job.map(|j| j.next_us),
                    self.single_shots.front().map(|s| s.0),
                ]
                .into_iter()
                .flatten()
                .min(),
                Timer::PhotoShot,
            ),
            (gps, Timer::GpsTimeout),
        ]);
        // The first of the earliest: candidates are in firing order.
        candidates
            .into_iter()
            .filter_map(|(due, timer)| due.map(|t| (t, timer)))
            .fold(None, |best: Option<(u64, Timer)>, c| match best {
                Some(b) if b.0 <= c.0 => Some(b),
                _ => Some(c),
            })
    }

    fn run_until(&mut self, now: u64) {
        while let Some((t, timer)) = self.next_timer() {
            if t > now {
                break;
            }
            self.integrate(t);
            self.fire(timer, t);
        }
        self.integrate(now);
    }

    /// Does the work of `timer`, due at `t`; always moves the timer past `t` or clears it.
    fn fire(&mut self, timer: Timer, t: u64) {
        match timer {
            Timer::RxIdle => {
                self.drain_deframer(t, true);
                self.prune_chunks();
            }
            Timer::Outbox => {
                while self.outbox.first().is_some_and(|q| q.due_us <= t) {
                    let q = self.outbox.remove(0);
                    self.emit(t, q.header, q.id, &q.payload);
                }
            }
            Timer::Report(i) => {
                let period = self.config.reports.as_array().get(i).copied().unwrap_or(0);
                if let Some(due) = self.report_due.get_mut(i) {
                    *due = (period > 0).then(|| t.saturating_add(period));
                }
                self.send_report(i, t);
            }
            Timer::ZoomStatus => {
                if let ZoomMotion::Target {
                    target,
                    hybrid: true,
                } = self.zoom
                {
                    self.send(
                        t,
                        &ZoomStatus {
                            state: ZoomState::Zooming,
                            reserved: 0,
                        },
                    );
                    let reach = self.zoom_reach_us(target);
                    self.zoom_status_due =
                        Some(t.saturating_add(ZOOM_STATUS_PERIOD_US.min(reach.max(1))));
                } else {
                    self.send(
                        t,
                        &ZoomStatus {
                            state: ZoomState::Done,
                            reserved: 0,
                        },
                    );
                    self.zoom_status_due = None;
                }
            }
            Timer::RecordStatus => match self.camera.recording {
                Some(rec) => {
                    self.send(t, &record_status(rec, RecordState::Recording, t));
                    self.record_status_due = Some(t.saturating_add(ONE_SECOND_US));
                }
                None => self.record_status_due = None,
            },
            Timer::Laser => {
                if self.camera.laser_periodic {
                    self.send(t, &LaserPeriodicStatus(self.laser_reading()));
                    self.laser_due = Some(t.saturating_add(ONE_SECOND_US));
                } else {
                    self.laser_due = None;
                }
            }
            Timer::PhotoShot => self.take_shot(t),
            Timer::GpsTimeout => {
                if let Some(i) = self.gps_open.pop_front() {
                    if let Some(r) = self.gps_requests.get_mut(i) {
                        r.timed_out = true;
                    }
                    self.gps_unanswered += 1;
                }
            }
        }
    }

    /// Moves the gimbal and zoom models to `t`.
    fn integrate(&mut self, t: u64) {
        if t <= self.model_us {
            return;
        }
        let dt = (t - self.model_us) as f64 / 1e6;
        self.model_us = t;
        let (yaw_dial, pitch_dial) = self.dial_dps();
        let slew = self.config.slew_speed_dps;
        self.yaw.advance(dt, yaw_dial, slew);
        self.pitch.advance(dt, pitch_dial, slew);

        let (min, max) = self.zoom_limits();
        let (lo, hi) = (min.ln(), max.ln());
        let ln_now = self.camera.zoom_x10.ln();
        let step = self.config.zoom_rate_per_s * dt;
        match self.zoom {
            ZoomMotion::Idle => {}
            ZoomMotion::Target { target, .. } => {
                let diff = target.ln() - ln_now;
                if diff.abs() <= step + ZOOM_EPSILON_LN {
                    self.camera.zoom_x10 = target;
                    self.zoom_finished(t);
                } else {
                    self.camera.zoom_x10 = (ln_now + step.copysign(diff)).exp();
                }
            }
            ZoomMotion::Continuous(dir) => {
                let ln_next = (ln_now + dir * step).clamp(lo, hi);
                self.camera.zoom_x10 = ln_next.exp();
                if ln_next <= lo || ln_next >= hi {
                    self.camera.zoom_x10 = if dir > 0.0 { max } else { min };
                    self.zoom_finished(t);
                }
            }
        }
        self.camera.zooming = self.zoom != ZoomMotion::Idle;
    }

    fn zoom_finished(&mut self, t: u64) {
        self.zoom = ZoomMotion::Idle;
        self.camera.zoom_target_x10 = None;
        if self.camera.af_after_zoom {
            self.focus_until_us = t.saturating_add(self.config.focus_duration_us);
        }
    }

    /// Microseconds until the zoom reaches `target` (rounded up).
    fn zoom_reach_us(&self, target: f64) -> u64 {
        let rate = self.config.zoom_rate_per_s.max(1e-9);
        let s = (target.ln() - self.camera.zoom_x10.ln()).abs() / rate;
        (s * 1e6).ceil() as u64
    }

    fn zoom_limits(&self) -> (f64, f64) {
        let min = f64::from(self.config.zoom_min_x10.max(1));
        (min, f64::from(self.config.zoom_max_x10).max(min))
    }

    fn dial_dps(&self) -> (f64, f64) {
        (
            f64::from(self.yaw_dial_x5) / 5.0,
            f64::from(self.pitch_dial_x5) / 5.0,
        )
    }

    // ----- receiving -----

    /// Drains the deframer's events (idle: gives up an incomplete candidate); returns
    /// whether any event came.
    fn drain_deframer(&mut self, now: u64, idle: bool) -> bool {
        let mut any = false;
        loop {
            let event = if idle {
                self.deframer.poll_idle()
            } else {
                self.deframer.poll()
            };
            let frame = match event {
                None => break,
                Some(Event::Frame(bytes)) => Some(bytes.to_vec()),
                Some(Event::Rejected { .. } | Event::Skipped(_)) => None,
            };
            any = true;
            if let Some(frame) = frame {
                // The bytes after the frame are what the deframer still holds.
                let end = self.rx_fed - self.deframer.buffered() as u64;
                let start = end.saturating_sub(frame.len() as u64);
                let start_us = self.arrival_of(start);
                let at_us = self.arrival_of(end.saturating_sub(1)).max(start_us);
                self.handle_frame(now, frame, start_us, at_us);
            }
        }
        any
    }

    /// When the byte at stream offset `offset` arrived.
    fn arrival_of(&self, offset: u64) -> u64 {
        self.rx_chunks
            .iter()
            .rev()
            .find(|&&(first, _)| first <= offset)
            .map_or(self.last_rx_us, |&(_, t)| t)
    }

    /// Forgets chunks no buffered byte belongs to.
    fn prune_chunks(&mut self) {
        let oldest_held = self.rx_fed - self.deframer.buffered() as u64;
        while self.rx_chunks.len() > 1 && self.rx_chunks.get(1).is_some_and(|c| c.0 <= oldest_held)
        {
            self.rx_chunks.pop_front();
        }
    }

    fn handle_frame(&mut self, now: u64, frame: Vec<u8>, start_us: u64, at_us: u64) {
        self.rx.frames += 1;
        let packet = match Packet::decode(&frame) {
            Ok(p) => p,
            Err(_) => {
                self.rx.malformed += 1;
                return;
            }
        };
        let header = packet.header;
        let id = packet.message.id();
        *self.rx_counts.entry(id.to_u32()).or_insert(0) += 1;
        let message = packet.message;
        if self.config.strict_destination
            && header.dst != self.config.gimbal_address
            && header.dst != self.config.camera_address
        {
            self.rx.misaddressed += 1;
            self.received.push(RxRecord {
                start_us,
                at_us,
                header,
                id,
                frame,
            });
            return;
        }
        let reply = message.get::<GpsReply>();
        let request = match message {
            Message::Request(r) => Some(r),
            _ => None,
        };
        let raw_request =
            matches!(message, Message::Raw(Raw { id, .. }) if id.kind == Kind::Request);
        self.received.push(RxRecord {
            start_us,
            at_us,
            header,
            id,
            frame,
        });
        if let Some(reply) = reply {
            self.handle_gps_reply(now, header, reply);
        } else if let Some(request) = request {
            self.handle_request(now, header, request, start_us);
        } else if raw_request && self.config.ack_unknown {
            let _ = self.ack(now, header, id.base, Ok(None));
        }
    }

    fn handle_request(&mut self, t: u64, header: Header, request: Request, start_us: u64) {
        let base = request.base();
        let mut record = RequestRecord {
            at_us: t,
            header,
            request,
            code: None,
            executed: false,
            ack_seq: None,
        };
        // The bridge has no business sending reports or GPS requests: no ACK.
        if matches!(base, 0x0001..=0x0008 | 0x0310) {
            self.requests.push(record);
            return;
        }
        if let Some(&code) = self.config.nak.get(&base) {
            record.code = Some(code);
            record.ack_seq = self.ack(t, header, base, Err(code));
            self.requests.push(record);
            return;
        }
        self.deferred.clear();
        let result = self.execute(t, request, start_us);
        record.code = Some(match &result {
            Ok(_) => AckCode::Ok,
            Err(code) => *code,
        });
        record.executed = result.is_ok();
        record.ack_seq = self.ack(t, header, base, result);
        self.requests.push(record);
        let deferred = std::mem::take(&mut self.deferred);
        for (id, payload) in deferred {
            self.send_payload(t.saturating_add(self.config.ack_delay_us), id, payload);
        }
    }

    /// Executes a request: `Ok(None)` bare OK, `Ok(Some(payload))` OK with the ACK's
    /// whole payload, `Err(code)` refused.
    fn execute(
        &mut self,
        t: u64,
        request: Request,
        start_us: u64,
    ) -> Result<Option<Vec<u8>>, AckCode> {
        let motion_blocked = self.camera.track.is_some() && self.config.track_blocks_motion;
        match request {
            Request::GimbalControl(c) => {
                self.motion(t, MotionCommand::Control(c), motion_blocked);
                if !motion_blocked {
                    self.gimbal_control(c);
                }
            }
            Request::GimbalAngle(a) => {
                self.motion(t, MotionCommand::Angle(a), motion_blocked);
                if !motion_blocked {
                    self.gimbal_angle(a);
                }
            }
            Request::DialSpeed(d) => {
                self.motion(t, MotionCommand::DialSpeed(d), false);
                self.pitch_dial_x5 = d.pitch_dps_x5.clamp(5, 150);
                self.yaw_dial_x5 = d.yaw_dps_x5.clamp(5, 150);
            }
            Request::PointToAim(p) => {
                self.motion(t, MotionCommand::PointToAim(p), motion_blocked);
                if !motion_blocked {
                    self.point_to_aim(p);
                }
            }
            Request::ServoOff(_) => {
                self.motion(t, MotionCommand::ServoOff, false);
                self.yaw.motion = AxisMotion::Hold;
                self.pitch.motion = AxisMotion::Hold;
            }
            Request::Stabilization(s) => self.stabilization = s.enable == OnOff::On,
            Request::GimbalVersion(_) => {
                return Ok(Some(payload(&GimbalVersionAck {
                    code: ResponseCode::OK,
                    hardware: self.config.gimbal_hardware,
                    software: self.config.gimbal_software,
                    reserved: 0,
                })));
            }
            Request::IrParams(_) => return Ok(Some(payload(&self.ir_params()))),
            Request::IrPalette(p) => self.camera.palette = p.palette,
            Request::IrMeasurement(m) => self.camera.ir_measuring = m.switch == MeasureSwitch::On,
            Request::VisibleParams(_) => return Ok(Some(payload(&self.visible_params()))),
            Request::Ev(e) => self.camera.ev = e.ev,
            Request::AeLock(l) => self.camera.ae_lock = l.lock,
            Request::CaptureMode(m) => self.camera.mode = m.mode,
            Request::PhotoParams(p) => {
                self.camera.photo_mode = p.mode;
                self.camera.timelapse_s = p.timelapse_s;
                self.camera.burst_count = p.burst_count;
            }
            Request::TakePhoto(p) => return self.take_photo(t, p).map(|()| None),
            Request::Record(r) => return self.record(t, r).map(|()| None),
            Request::HybridZoom(z) => {
                let (min, max) = self.zoom_limits();
                let target = f64::from(z.zoom_x10).clamp(min, max);
                self.zoom_to(target, true);
                self.deferred.push(message(&ZoomStatus {
                    state: ZoomState::Zooming,
                    reserved: 0,
                }));
                let after_ack = t.saturating_add(self.config.ack_delay_us);
                let reach = self.zoom_reach_us(target);
                self.zoom_status_due =
                    Some(after_ack.saturating_add(ZOOM_STATUS_PERIOD_US.min(reach.max(1))));
            }
            Request::ContinuousZoom(c) => self.continuous_zoom(c.control),
            Request::StreamBitrate(b) => self.camera.bitrate = b.bitrate,
            Request::OutputCodec(c) => self.camera.codec = c.codec,
            Request::ImageMode(m) => self.camera.image_mode = m.mode,
            Request::TimeSync(s) => self.time_sync(t, s, start_us),
            Request::GetIp(_) => {
                return Ok(Some(payload(&IpConfigAck {
                    code: ResponseCode::OK,
                    address: [192, 168, 144, 64],
                    netmask: [255, 255, 255, 0],
                    gateway: [192, 168, 144, 1],
                })));
            }
            Request::Focus(f) => self.focus(t, f.mode),
            Request::CameraVersion(_) => {
                return Ok(Some(payload(&CameraVersionAck {
                    code: ResponseCode::OK,
                    version: self.config.camera_version,
                })));
            }
            Request::AiRecognition(a) => {
                self.camera.ai = a.enable == Toggle::On;
            }
            Request::TargetGps(r) => return Ok(Some(payload(&self.target_gps(&r)))),
            Request::TrackBox(b) => match b.enable {
                Toggle::On if self.config.track_requires_ai && !self.camera.ai => {
                    return Err(AckCode::Failure);
                }
                Toggle::On => {
                    self.camera.track = Some(b);
                    self.yaw.motion = AxisMotion::Hold;
                    self.pitch.motion = AxisMotion::Hold;
                }
                _ => self.camera.track = None,
            },
            Request::LaserRange(l) => {
                let mut reading = self.laser_reading();
                if l.mode != LaserMode::Single {
                    reading.distance_dm = 0;
                }
                return Ok(Some(payload(&reading)));
            }
            Request::LaserPeriodic(p) => {
                let on = p.enable == OnOff::On;
                if on && !self.camera.laser_periodic {
                    self.deferred
                        .push(message(&LaserPeriodicStatus(self.laser_reading())));
                    self.laser_due = Some(
                        t.saturating_add(self.config.ack_delay_us)
                            .saturating_add(ONE_SECOND_US),
                    );
                }
                self.camera.laser_periodic = on;
            }
            Request::SbusConfig(_) => {
                return Ok(Some(payload(&SbusConfig {
                    code: ResponseCode::OK,
                    max: 1811,
                    min: 172,
                    channels: SbusChannelMap {
                        stream: 5,
                        zoom: 6,
                        photo: 7,
                        video: 8,
                        pitch: 1,
                        yaw: 3,
                        center: 9,
                    },
                    reserved: 0,
                })));
            }
            _ => {}
        }
        Ok(None)
    }

    fn motion(&mut self, t: u64, command: MotionCommand, blocked: bool) {
        self.motions.push(MotionRecord {
            at_us: t,
            command,
            applied: !blocked,
        });
    }

    fn gimbal_control(&mut self, c: GimbalControl) {
        match c.function {
            GimbalFunction::Center => {
                self.yaw.go_to(0.0);
                self.pitch.go_to(0.0);
            }
            GimbalFunction::LookDown => self.pitch.go_to(-90.0),
            _ => {
                self.yaw.motion = match c.yaw {
                    YawMotion::Left => AxisMotion::Rate(-1.0),
                    YawMotion::Right => AxisMotion::Rate(1.0),
                    _ => AxisMotion::Hold,
                };
                self.pitch.motion = match c.pitch {
                    PitchMotion::Up => AxisMotion::Rate(1.0),
                    PitchMotion::Down => AxisMotion::Rate(-1.0),
                    _ => AxisMotion::Hold,
                };
            }
        }
    }

    fn gimbal_angle(&mut self, a: GimbalAngle) {
        let pitch = f64::from(a.pitch_cdeg) / 100.0;
        match a.pitch_direction {
            PitchMotion::Up => self.pitch.go_to(pitch),
            PitchMotion::Down => self.pitch.go_to(-pitch),
            _ => {}
        }
        let yaw = f64::from(a.yaw_cdeg) / 100.0;
        match a.yaw_direction {
            YawMotion::Left => self.yaw.go_to(-yaw),
            YawMotion::Right => self.yaw.go_to(yaw),
            _ => {}
        }
    }

    fn point_to_aim(&mut self, p: PointToAim) {
        let zoom = (f64::from(p.zoom_x10) / 10.0).max(1.0);
        let half_h = (self.config.hfov_1x_deg.to_radians() / 2.0).tan() / zoom;
        let half_v = half_h * IMAGE_H / IMAGE_W;
        let dx = ((f64::from(p.x) - IMAGE_W / 2.0) / (IMAGE_W / 2.0) * half_h)
            .atan()
            .to_degrees();
        let dy = ((f64::from(p.y) - IMAGE_H / 2.0) / (IMAGE_H / 2.0) * half_v)
            .atan()
            .to_degrees();
        self.yaw.go_to(self.yaw.angle + dx);
        self.pitch.go_to(self.pitch.angle - dy);
        if p.lens == Lens::Telephoto {
            let (min, max) = self.zoom_limits();
            self.zoom_to(f64::from(p.zoom_x10).clamp(min, max), false);
        }
    }

    fn zoom_to(&mut self, target: f64, hybrid: bool) {
        self.zoom = ZoomMotion::Target { target, hybrid };
        self.camera.zoom_target_x10 = Some(target);
        self.camera.zooming = true;
    }

    fn continuous_zoom(&mut self, control: ZoomControl) {
        let (min, max) = self.zoom_limits();
        let step = f64::from(self.config.zoom_step_x10);
        match control {
            ZoomControl::In => {
                self.zoom = ZoomMotion::Continuous(1.0);
                self.camera.zoom_target_x10 = None;
                self.camera.zooming = true;
            }
            ZoomControl::Out => {
                self.zoom = ZoomMotion::Continuous(-1.0);
                self.camera.zoom_target_x10 = None;
                self.camera.zooming = true;
            }
            ZoomControl::StepIn => {
                self.zoom_to((self.camera.zoom_x10.round() + step).clamp(min, max), false);
            }
            ZoomControl::StepOut => {
                self.zoom_to((self.camera.zoom_x10.round() - step).clamp(min, max), false);
            }
            _ => {
                self.zoom = ZoomMotion::Idle;
                self.camera.zoom_target_x10 = None;
                self.camera.zooming = false;
            }
        }
    }

    fn focus(&mut self, t: u64, mode: FocusMode) {
        self.camera.focus = Some(mode);
        match mode {
            FocusMode::Auto | FocusMode::Area | FocusMode::OneTouch => {
                self.manual_focus = false;
                self.focus_until_us = t.saturating_add(self.config.focus_duration_us);
            }
            FocusMode::ManualPlus | FocusMode::ManualMinus => self.manual_focus = true,
            FocusMode::ManualStop => self.manual_focus = false,
            FocusMode::AfAfterZoomOn => self.camera.af_after_zoom = true,
            FocusMode::AfAfterZoomOff => self.camera.af_after_zoom = false,
            FocusMode::Other(_) => {}
        }
    }

    fn take_photo(&mut self, t: u64, p: k40t::TakePhoto) -> Result<(), AckCode> {
        if p.action == ShootAction::Stop {
            if let Some(job) = self.photo_job.take()
                && job.mode != PhotoMode::Single
            {
                self.deferred.push(message(&PhotoStatus {
                    sensors: job.sensors,
                    state: PhotoState::Stopped,
                    burst_count: job.done,
                    reserved: [0; 3],
                }));
            }
            return Ok(());
        }
        if self.photo_job.is_some() {
            return Err(AckCode::PhotoInProgress);
        }
        if self.config.enforce_capture_mode && self.camera.mode != CaptureMode::Photo {
            return Err(AckCode::Failure);
        }
        let mode = self.camera.photo_mode;
        let (total, interval_us) = match mode {
            PhotoMode::Burst => (
                Some(u16::from(self.camera.burst_count.max(1))),
                self.config.burst_interval_us,
            ),
            PhotoMode::TimeLapse => (
                None,
                u64::from(self.camera.timelapse_s.max(1)) * ONE_SECOND_US,
            ),
            _ => {
                // Every shutter press is a shot, even one behind a pending shot.
                let due = t.saturating_add(self.config.photo_gps_delay_us);
                self.single_shots.push_back((due, p.sensors));
                return Ok(());
            }
        };
        if !self.single_shots.is_empty() {
            return Err(AckCode::PhotoInProgress);
        }
        self.photo_job = Some(PhotoJob {
            sensors: p.sensors,
            mode,
            total,
            done: 0,
            next_us: t.saturating_add(self.config.photo_gps_delay_us),
            interval_us: interval_us.max(1),
        });
        Ok(())
    }

    fn take_shot(&mut self, t: u64) {
        let single = self.single_shots.front().filter(|s| s.0 <= t).map(|s| s.1);
        let mut job = match (single, self.photo_job) {
            (Some(sensors), _) => {
                self.single_shots.pop_front();
                PhotoJob {
                    sensors,
                    mode: PhotoMode::Single,
                    total: Some(1),
                    done: 0,
                    next_us: t,
                    interval_us: ONE_SECOND_US,
                }
            }
            (None, Some(job)) => job,
            (None, None) => return,
        };
        job.done = job.done.saturating_add(1);
        let pod_unix_ms = self.clock_unix_ms(t);
        let photo = self.photos.len();
        self.camera.photos_taken += 1;
        let gps_request = (self.clock.synced || self.config.gps_when_unsynced).then(|| {
            let (hour, minute, second, millisecond) = self.time_of_day(t);
            let request = GpsRequest {
                lens_enable: self.config.gps_lens_enable,
                hour,
                minute,
                second,
                millisecond,
            };
            let seq = self.send(t, &request);
            self.gps_requests.push(GpsRequestRecord {
                at_us: t,
                seq,
                request,
                pod_unix_ms,
                synced: self.clock.synced,
                photo,
                reply: None,
                timed_out: false,
                boot: self.boots.len().saturating_sub(1),
            });
            self.gps_open.push_back(self.gps_requests.len() - 1);
            self.gps_requests.len() - 1
        });
        self.photos.push(PhotoRecord {
            at_us: t,
            sensors: job.sensors,
            pod_unix_ms,
            shot: job.done,
            gps_request,
        });
        let progress = match job.mode {
            PhotoMode::Burst => Some(PhotoState::Burst),
            PhotoMode::TimeLapse => Some(PhotoState::TimeLapse),
            _ => self
                .config
                .single_shot_status
                .then_some(PhotoState::SingleShot),
        };
        let status = |state| PhotoStatus {
            sensors: job.sensors,
            state,
            burst_count: job.done,
            reserved: [0; 3],
        };
        if let Some(state) = progress {
            self.send(t, &status(state));
        }
        if job.total.is_some_and(|n| job.done >= n) {
            if single.is_none() {
                self.photo_job = None;
            }
            if progress.is_some() {
                self.send(t, &status(PhotoState::Taken));
            }
        } else {
            job.next_us = t.saturating_add(job.interval_us);
            self.photo_job = Some(job);
        }
    }

    fn record(&mut self, t: u64, r: k40t::Record) -> Result<(), AckCode> {
        match r.action {
            RecordAction::Start => {
                if self.config.enforce_capture_mode && self.camera.mode != CaptureMode::Video {
                    return Err(AckCode::Failure);
                }
                if self.camera.recording.is_none() {
                    let since_us = t.saturating_add(self.config.ack_delay_us);
                    self.camera.recording = Some(Recording {
                        sensors: r.sensors,
                        since_us,
                    });
                    self.camera.mode = CaptureMode::Video;
                    self.record_status_due = Some(since_us);
                }
            }
            RecordAction::Stop => {
                if let Some(rec) = self.camera.recording.take() {
                    let at = t.saturating_add(self.config.ack_delay_us);
                    self.deferred
                        .push(message(&record_status(rec, RecordState::Stopped, at)));
                    self.record_status_due = None;
                }
            }
            RecordAction::Other(_) => {}
        }
        Ok(())
    }

    fn time_sync(&mut self, t: u64, s: k40t::TimeSync, start_us: u64) {
        let edge = self.pending_edge.take();
        let outcome = match edge {
            None => SyncOutcome::NoEdge,
            Some(e) if e > start_us => SyncOutcome::EdgeAfterFrameStart,
            Some(e) if start_us - e > self.config.sync_window_us => SyncOutcome::EdgeTooOld,
            Some(_) => SyncOutcome::Applied,
        };
        if let (SyncOutcome::Applied, Some(e)) = (outcome, edge) {
            self.clock.base_us = e;
            self.clock.base_unix_us =
                i128::from(s.unix_ms) * 1000 + i128::from(self.config.sync_error_us);
            self.clock.synced = true;
            self.tz = (s.tz_minuteswest, s.tz_dsttime);
        }
        self.syncs.push(SyncRecord {
            edge_us: edge,
            frame_start_us: start_us,
            arrival_us: t,
            unix_ms: s.unix_ms,
            tz_minuteswest: s.tz_minuteswest,
            tz_dsttime: s.tz_dsttime,
            delay_us: edge.and_then(|e| start_us.checked_sub(e)),
            outcome,
        });
    }

    fn handle_gps_reply(&mut self, t: u64, header: Header, reply: GpsReply) {
        let index = self.gps_replies.len();
        let request = self.match_gps_reply(header.seq);
        let mut record = GpsReplyRecord {
            at_us: t,
            header,
            reply,
            request,
            seq_matches: false,
            latency_us: None,
            time_matches: false,
            late: false,
        };
        if let Some(i) = request {
            self.gps_open.retain(|&open| open != i);
            if let Some(r) = self.gps_requests.get_mut(i) {
                r.reply = Some(index);
                record.seq_matches = r.seq == header.seq;
                record.latency_us = Some(t.saturating_sub(r.at_us));
                record.late = r.timed_out;
                let q = r.request;
                record.time_matches = (q.hour, q.minute, q.second, q.millisecond)
                    == (reply.hour, reply.minute, reply.second, reply.millisecond);
            }
        }
        self.gps_replies.push(record);
    }

    /// The request a GPS reply with sequence number `seq` answers: a pending one with
    /// that number (the oldest), else the latest of this boot that timed out with it,
    /// else the oldest pending one.
    fn match_gps_reply(&self, seq: u8) -> Option<usize> {
        let boot = self.boots.len().saturating_sub(1);
        let seq_of = |i: usize| self.gps_requests.get(i).map(|r| r.seq);
        self.gps_open
            .iter()
            .copied()
            .find(|&i| seq_of(i) == Some(seq))
            .or_else(|| {
                self.gps_requests.iter().rposition(|r| {
                    r.boot == boot && r.timed_out && r.reply.is_none() && r.seq == seq
                })
            })
            .or_else(|| self.gps_open.front().copied())
    }

    // ----- answers and reports -----

    fn ir_params(&self) -> IrParams {
        IrParams {
            code: ResponseCode::OK,
            palette: self.camera.palette,
            // Bit 0 clear: measuring; bit 1 area; bit 2 radiometric core.
            measure: MeasureConfig((if self.camera.ir_measuring { 0x06 } else { 0x07 }) | (1 << 3)),
            sharpness: 50,
            gain: IrGain::High,
            brightness: 50,
            contrast: 50,
            denoise: SwitchLevel(0x80 | 50),
            enhancement: 0,
            high_warning_dc: -2732,
            low_warning_dc: -2732,
            diff_warning_dc: -2732,
            threshold_warning: OnOff::Off,
            threshold_ref_dc: 0,
            threshold_float_dc: 0,
            reserved: [0; 2],
        }
    }

    fn visible_params(&self) -> VisibleParams {
        VisibleParams {
            code: ResponseCode::OK,
            photo_resolution: PhotoResolution::R4000x3000,
            video_resolution: VideoResolution::R1080p,
            video_bitrate: 1,
            white_balance: WhiteBalance::Auto,
            reserved: [0; 2],
            ev: self.camera.ev,
            iso: k40t::Iso::Auto,
            shutter: Shutter::Auto,
            zoom_fine: 0,
            backlight: 0,
            strong_light: 0,
            ae_lock: self.camera.ae_lock,
            osd_flicker: k40t::OsdFlicker(0x40),
            metering: Metering::CenterWeighted,
        }
    }

    fn laser_reading(&self) -> LaserDistance {
        LaserDistance {
            code: ResponseCode::OK,
            distance_dm: self.camera.laser_distance_dm,
        }
    }

    /// The laser target's position, flat earth, from the aircraft's position and heading,
    /// the gimbal angles and the laser distance.
    fn target_gps(&self, r: &TargetGpsRequest) -> TargetGpsAck {
        let d = f64::from(self.camera.laser_distance_dm) / 10.0;
        let pitch = self.pitch.angle.to_radians();
        let horizontal = d * pitch.cos();
        let drop_mm = (-d * pitch.sin() * 1000.0).round() as i32;
        let bearing = (f64::from(r.heading_cdeg) / 100.0 + self.yaw.angle).to_radians();
        let lat = f64::from(r.lat_e7) / 1e7;
        let metres_per_deg = 111_320.0;
        let dlat = horizontal * bearing.cos() / metres_per_deg;
        let dlon = horizontal * bearing.sin() / (metres_per_deg * lat.to_radians().cos().max(1e-6));
        TargetGpsAck {
            code: ResponseCode::OK,
            mount: 0x1F,
            utc_ms: r.utc_ms,
            lon_e7: r.lon_e7.saturating_add((dlon * 1e7).round() as i32),
            lat_e7: r.lat_e7.saturating_add((dlat * 1e7).round() as i32),
            rel_alt_mm: r.rel_alt_mm.saturating_sub(drop_mm),
            alt_mm: r.alt_mm.saturating_sub(drop_mm),
        }
    }

    fn send_report(&mut self, index: usize, t: u64) {
        match REPORT_IDS.get(index) {
            Some(0x0001) => {
                let status = GimbalStatus {
                    links: Links(0),
                    upgrade: UpgradeState::Normal,
                    self_test: SelfTest(0x0F),
                    stabilization: if self.stabilization {
                        StabilizationState::Active
                    } else {
                        StabilizationState::Off
                    },
                    reserved: [0; 3],
                };
                self.send(t, &status);
            }
            Some(0x0002) => {
                let g = self.gimbal();
                let cdeg = |deg: f64| (deg * 100.0).round() as i16;
                let attitude = GimbalAttitude {
                    yaw_joint_cdeg: cdeg(g.yaw_deg),
                    roll_joint_cdeg: 0,
                    pitch_joint_cdeg: cdeg(g.pitch_deg),
                    yaw_cdeg: cdeg(g.yaw_deg),
                    roll_cdeg: 0,
                    pitch_cdeg: cdeg(g.pitch_deg),
                    yaw_rate_cdeg_s: cdeg(g.yaw_rate_dps),
                    pitch_rate_cdeg_s: cdeg(g.pitch_rate_dps),
                    roll_rate_cdeg_s: 0,
                    reserved: [0; 2],
                };
                self.send(t, &attitude);
            }
            Some(0x0003) => {
                let c = &self.camera;
                let status = SystemStatus {
                    mode: c.mode,
                    preview_resolution: PreviewResolution::P1080Fps30,
                    preview_codec: c.codec,
                    stream: c.image_mode,
                    preview_bitrate: c.bitrate,
                    photo_mode: c.photo_mode,
                    timelapse_s: c.timelapse_s,
                    burst_count: c.burst_count,
                    sd: SdState::Normal,
                    sd_total_10mb: 12_207,
                    sd_free_10mb: 11_007,
                    sd_used_10mb: 1_200,
                    reserved: 0,
                };
                self.send(t, &status);
            }
            Some(0x0004) if self.camera.ir_measuring => {
                self.send(t, &IR_STATUS);
            }
            Some(0x0005) => {
                let c = &self.camera;
                let optical = c.zoom_x10.min(OPTICAL_MAX_X10) / 10.0;
                let status = VisibleStatus {
                    zoom_state: if c.zooming {
                        ZoomState::Zooming
                    } else {
                        ZoomState::Done
                    },
                    focal_length_10um: (f64::from(self.config.focal_length_1x_10um) * optical)
                        .round() as u16,
                    zoom_x10: c.zoom_x10.round() as u16,
                    ev: c.ev,
                    iso_0p1db: 0,
                    shutter_us: 1000,
                    ae_lock: c.ae_lock,
                    focus: if self.manual_focus || self.focus_until_us > t {
                        FocusState::Focusing
                    } else {
                        FocusState::Done
                    },
                    accurate_focal_length: 0,
                    reserved: 0,
                };
                self.send(t, &status);
            }
            _ => {}
        }
    }

    /// The pod's clock at `t` as (hour, minute, second, millisecond) of the day.
    fn time_of_day(&self, t: u64) -> (u8, u8, u8, u16) {
        let mut ms = self.clock.unix_us(t).div_euclid(1000);
        if self.config.gps_local_time {
            ms -= i128::from(self.tz.0) * 60_000;
        }
        let of_day = ms.rem_euclid(DAY_MS);
        let part = |div: i128, modulo: i128| u16::try_from(of_day / div % modulo).unwrap_or(0);
        let byte = |v: u16| u8::try_from(v).unwrap_or(0);
        (
            byte(part(3_600_000, 24)),
            byte(part(60_000, 60)),
            byte(part(1000, 60)),
            part(1, 1000),
        )
    }

    // ----- sending -----

    fn source_for(&self, base: u16) -> Address {
        if matches!(base, 0x0001 | 0x0002 | 0x0010..=0x00FF) {
            self.config.gimbal_address
        } else {
            self.config.camera_address
        }
    }

    fn next_seq(&mut self, src: Address) -> u8 {
        let seq = self
            .seqs
            .entry((src.system, src.component))
            .or_insert(self.seq_base);
        let current = *seq;
        *seq = seq.wrapping_add(1);
        current
    }

    /// Sends a pod-originated message now; returns its sequence number.
    fn send<M: MessageData<Protocol = K40t>>(&mut self, t: u64, m: &M) -> u8 {
        let (id, bytes) = message(m);
        self.send_payload(t, id, bytes)
    }

    /// Sends a pod-originated frame at `due` (now if not later than `now_us`).
    fn send_payload(&mut self, due: u64, id: MsgId, payload: Vec<u8>) -> u8 {
        let src = self.source_for(id.base);
        let seq = self.next_seq(src);
        let header = Header {
            dst: self.config.fc_address,
            src,
            seq,
            coverage: self.config.coverage,
        };
        self.queue(due, header, id, payload);
        seq
    }

    fn queue(&mut self, due: u64, header: Header, id: MsgId, payload: Vec<u8>) {
        // Queued frames due by now have gone out already (the outbox timer ran first).
        if due <= self.model_us {
            self.emit(self.model_us, header, id, &payload);
        } else {
            let at = self.outbox.partition_point(|q| q.due_us <= due);
            self.outbox.insert(
                at,
                Queued {
                    due_us: due,
                    header,
                    id,
                    payload,
                },
            );
        }
    }

    /// Sends the ACK of a request (`result` as [`SimPod::execute`] returns it).
    /// Returns the ACK's sequence number (`None`: dropped).
    fn ack(
        &mut self,
        t: u64,
        request: Header,
        base: u16,
        result: Result<Option<Vec<u8>>, AckCode>,
    ) -> Option<u8> {
        let src = self.source_for(base);
        // A dropped ACK was sent and lost on the way: it used its number.
        let seq = match self.config.ack_seq {
            AckSeq::Echo => request.seq,
            AckSeq::OwnCounter => self.next_seq(src),
        };
        if let Some(left) = self.config.drop_acks.get_mut(&base).filter(|n| **n > 0) {
            *left -= 1;
            self.acks_dropped += 1;
            return None;
        }
        let (code, mut bytes) = match result {
            Ok(Some(bytes)) => (AckCode::Ok, bytes),
            Ok(None) => (AckCode::Ok, vec![0; 2]),
            Err(code) => {
                // The ACK's layout, data zeroed.
                let len = Ack::decode(base, &[])
                    .and_then(Result::ok)
                    .map_or(2, |a| a.payload_len());
                (code, vec![0; len.max(2)])
            }
        };
        let raw = if self.config.ack_code_le {
            code.value().to_le_bytes()
        } else {
            code.value().to_be_bytes()
        };
        if let Some(head) = bytes.get_mut(..2) {
            head.copy_from_slice(&raw);
        }
        let header = Header {
            dst: request.src,
            src,
            seq,
            coverage: self.config.coverage,
        };
        let due = t.saturating_add(self.config.ack_delay_us);
        self.queue(due, header, MsgId::new(Kind::Ack, base), bytes);
        Some(seq)
    }

    /// Puts a frame on the line (or loses it while silent), with output faults.
    fn emit(&mut self, t: u64, header: Header, id: MsgId, payload: &[u8]) {
        let packet = Packet {
            header,
            message: Message::Raw(Raw { id, payload }),
        };
        let mut buf = [0u8; MAX_FRAME_LEN];
        let Ok(n) = packet.emit(&mut buf) else {
            return;
        };
        let frame = buf.get(..n).unwrap_or_default().to_vec();
        if self.silent {
            self.lost_while_silent += 1;
            return;
        }
        *self.tx_counts.entry(id.to_u32()).or_insert(0) += 1;
        let faults = self.config.faults;
        if self.rng.chance(faults.garbage_probability) {
            let len = 1 + self.rng.below(faults.max_garbage_len.max(1));
            for _ in 0..len {
                self.out.push(self.rng.next_u64() as u8);
            }
            self.garbage_bursts += 1;
        }
        let mut wire = frame.clone();
        if self.rng.chance(faults.bit_flip_probability) {
            let bit = self.rng.below(wire.len() * 8);
            if let Some(b) = wire.get_mut(bit / 8) {
                *b ^= 1 << (bit % 8);
            }
            self.bit_flips += 1;
        }
        self.out.extend_from_slice(&wire);
        self.sent.push(TxRecord {
            at_us: t,
            header,
            id,
            frame,
        });
    }
}

/// The deframer's framing for `config`.
fn framing_of(config: &PodSimConfig) -> K40tFraming {
    if config.accept_any_coverage {
        K40tFraming::any()
    } else {
        K40tFraming::with(config.coverage)
    }
}

/// The camera as at power-up.
fn initial_camera(config: &PodSimConfig, laser_distance_dm: u16, photos_taken: u32) -> CameraState {
    CameraState {
        mode: CaptureMode::Photo,
        photo_mode: PhotoMode::Single,
        timelapse_s: 5,
        burst_count: 3,
        image_mode: ImageMode::Visible,
        codec: VideoCodec::H264,
        bitrate: StreamBitrate::M4,
        palette: Palette::WhiteHot,
        ir_measuring: true,
        zoom_x10: f64::from(config.zoom_min_x10),
        zoom_target_x10: None,
        zooming: false,
        focus: None,
        af_after_zoom: false,
        recording: None,
        photos_taken,
        laser_periodic: false,
        laser_distance_dm,
        ai: false,
        track: None,
        ev: Ev::Auto,
        ae_lock: AeLock::Off,
    }
}

/// The 0x020303 status of a recording at `t`.
fn record_status(rec: Recording, state: RecordState, t: u64) -> RecordStatus {
    RecordStatus {
        sensors: rec.sensors,
        state,
        elapsed_s: u16::try_from(t.saturating_sub(rec.since_us) / ONE_SECOND_US)
            .unwrap_or(u16::MAX),
        reserved: [0; 3],
    }
}

/// The payload bytes of a message.
fn payload<M: MessageData<Protocol = K40t>>(m: &M) -> Vec<u8> {
    let mut buf = vec![0; M::ENCODED_LEN];
    let mut w = Writer::new(&mut buf);
    // Cannot fail: the buffer has the message's encoded length.
    let _ = m.encode_payload(&mut w);
    buf
}

/// A message as (id, payload bytes).
fn message<M: MessageData<Protocol = K40t>>(m: &M) -> (MsgId, Vec<u8>) {
    (M::ID, payload(m))
}
