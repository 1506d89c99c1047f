//! A simulated K40T four-sensor pod (as the K40T external protocol document describes
//! it; docs/src/protocols/k40t.md for its ambiguities), sans-IO, in simulated time, for
//! the bridge's host tests and the demo.
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
//! exchange (docs/src/protocols/k40t.md) happens to do (tests run the bridge against
//! both). A requester that
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
//! 0x000033 on, `Off` otherwise; IR measurements from a moving scene ([`ir_scene`]: a
//! hot and a cold spot going round the thermal picture, [`IR_STATUS`] at power-up, in
//! the IR coordinates of 0x00010F, [`IR_PICTURE`]); visible status carries the zoom
//! model, its state and focus state.
//!
//! **ACKs.** Every request gets its ACK at once (after [`PodSimConfig::ack_delay_us`],
//! 0 by default) with a sequence number as [`PodSimConfig::ack_seq`] says, response code
//! OK, and the data the document defines: versions (0x000018, 0x000317), all IR parameters (0x000100), all
//! visible parameters (0x000200), the IP configuration (0x000312, [`PodSimConfig::ip`]:
//! 192.168.144.64/24, gateway 192.168.144.1, the document's default address), the laser
//! target's position (0x000320: from the aircraft's position, heading and altitude in the
//! request, the gimbal's yaw and pitch and the laser distance, flat earth; code Failure
//! without a laser distance), the laser distance
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
//! - 0x000012 moves to absolute joint angles (unit 0.01°, docs/src/protocols/k40t.md; direction byte
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
//!   0x000108 show in the 0x000100 ACK. Every other set command of 3.2.2 and 3.2.3, the
//!   watermark 0x000314, the format 0x00030D and the factory reset 0x00030F: see
//!   `settings.rs` ([`PodSettings`]); the all-settings ACKs 0x000100 and 0x000200 report
//!   them all.
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
//! **GPS.** A request precedes each photo (the document's note); with
//! [`PodSimConfig::gps_periodic`] the pod also asks periodically, or while recording, with
//! [`PodSimConfig::gps_periodic_lens_enable`] (0) as its lens byte, as a real pod
//! plausibly does. Each 0x000310 is recorded ([`SimPod::gps_requests`]); every 0x010310 received
//! is recorded ([`SimPod::gps_replies`]) and matched to a request of the current boot as
//! the bridge matches ACKs (docs/src/bridge/engine.md; the reply is the FC's message, so it may carry the FC's own
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
//! [`SimPod::transmit`] returns everything generated so far), SD card space and errors
//! (a fixed card, emptied by a format),
//! upgrades, the soft restart command (0x00002F: ACKed, nothing restarts; a power
//! cycle is [`SimPod::reboot`]), a boot time before the first report (the pod reports at
//! the instant it is powered), IR image content, electronic zoom of the wide and IR
//! lenses (recorded only).

mod answers;
mod camera;
mod config;
mod frames;
mod motion;
mod records;
mod schedule;
mod settings;
mod time;

use camera::{PhotoJob, initial_camera, record_status};
pub use config::{
    AckSeq, IR_PICTURE, IR_STATUS, OutputFaults, PeriodicGps, PodSimConfig, ReportPeriods, ir_scene,
};
use frames::{Queued, framing_of, message, payload};
use motion::{Axis, AxisMotion, OPTICAL_MAX_X10, ZoomMotion};
pub use records::{
    CameraState, GimbalState, GpsReplyRecord, GpsRequestRecord, MotionCommand, MotionRecord,
    PhotoRecord, Recording, RequestRecord, RtcEdge, RxRecord, RxStats, SyncOutcome, SyncRecord,
    TxRecord,
};
use schedule::{ONE_SECOND_US, ZOOM_STATUS_PERIOD_US};
pub use settings::{FORMAT_US, PodSettings};
use time::PodClock;

use super::XorShift;
use std::collections::{BTreeMap, VecDeque};

use protocol_core::k40t::{
    self, Ack, AckCode, Address, AeLock, CameraVersionAck, CaptureMode, CrcCoverage, Ev, FocusMode,
    FocusState, FormatStatus, GimbalAngle, GimbalAttitude, GimbalControl, GimbalFunction,
    GimbalStatus, GimbalVersionAck, GpsReply, GpsRequest, Header, ImageMode, IpConfigAck, IrGain,
    IrParams, IrStatus, K40t, K40tFraming, Kind, LaserDistance, LaserMode, LaserPeriodicStatus,
    Lens, Links, MAX_FRAME_LEN, MeasureConfig, MeasureSwitch, Message, MessageData, Metering,
    MsgId, OnOff, Packet, Palette, PhotoMode, PhotoResolution, PhotoSensors, PhotoState,
    PhotoStatus, PitchMotion, PointToAim, PreviewResolution, Raw, RecordAction, RecordSensors,
    RecordState, RecordStatus, Request, ResponseCode, SbusChannelMap, SbusConfig, SdState,
    SelfTest, ShootAction, Shutter, StabilizationState, StreamBitrate, SwitchLevel, SystemStatus,
    TargetGpsAck, TargetGpsRequest, Toggle, TrackBox, UpgradeState, Version, VideoCodec,
    VideoResolution, VisibleParams, VisibleStatus, WhiteBalance, YawMotion, ZoomControl, ZoomState,
    ZoomStatus,
};
use protocol_core::wire::{Deframer, Event, Stats, Writer};

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
    gps_periodic_due: Option<u64>,

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
            gps_periodic_due: None,
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

    /// A photo asked at `now_us` by the pod's own app (K40T address 0x01/0x01, a
    /// 0x000302 of its own), whatever the FC does.
    pub fn photo_from_app(&mut self, now_us: u64) {
        let header = Header {
            dst: Address::POD,
            src: Address::APP,
            seq: 0,
            coverage: CrcCoverage::ExcludeStx,
        };
        let mut buf = [0u8; MAX_FRAME_LEN];
        if let Ok(n) = k40t::encode(
            &protocol_core::k40t::TakePhoto::default(),
            &header,
            &mut buf,
        ) {
            self.receive(now_us, buf.get(..n).unwrap_or_default());
        }
    }

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
        self.gps_periodic_due = match self.config.gps_periodic {
            PeriodicGps::Always { period_us } => Some(t.saturating_add(period_us.max(1))),
            _ => None,
        };
        self.model_us = t;
        for (due, period) in self
            .report_due
            .iter_mut()
            .zip(self.config.reports.as_array())
        {
            *due = (period > 0).then_some(t);
        }
    }

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

    /// Sets the photo mode (as a 0x000003 photo-parameter command would): single,
    /// burst of `burst_count`, or time-lapse every `timelapse_s`.
    pub fn set_photo_mode(&mut self, mode: PhotoMode, burst_count: u8, timelapse_s: u8) {
        self.camera.photo_mode = mode;
        self.camera.burst_count = burst_count;
        self.camera.timelapse_s = timelapse_s;
    }

    /// The pod shoots by itself at `now_us` (its own shutter, another app on its LAN),
    /// as its photo mode says: the bridge sent no command. `stop` ends a series.
    pub fn shoot_by_itself(&mut self, now_us: u64, stop: bool) {
        let t = self.enter(now_us);
        let p = k40t::TakePhoto {
            sensors: PhotoSensors::Default,
            action: if stop {
                ShootAction::Stop
            } else {
                ShootAction::Start
            },
            folder: Default::default(),
            name: Default::default(),
        };
        let _ = self.take_photo(t, p);
    }

    /// Sets the IP configuration the pod answers 0x000312 with (address, subnet mask,
    /// gateway), as a network change would: in effect at once.
    pub fn set_ip(&mut self, ip: [[u8; 4]; 3]) {
        self.config.ip = ip;
    }

    /// Switches the IR temperature measurement as 0x000108 would (0x000004 stops while
    /// it is off), e.g. from the vendor's app.
    pub fn set_ir_measuring(&mut self, on: bool) {
        self.camera.ir_measuring = on;
    }
}
