//! What the simulated pod records for assertions, and its state as observed.

use super::*;

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
    /// The other settings of 0x000100 and 0x000200, and the card's format.
    pub settings: PodSettings,
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
    /// Index of the photo in [`SimPod::photos`] (`None`: a periodic request,
    /// [`super::PeriodicGps`]).
    pub photo: Option<usize>,
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

impl SimPod {
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
        let frames = self.received.iter();
        messages_of(frames.map(|r| (r.at_us, r.header, r.id, r.frame.as_slice())))
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
        let frames = self.sent.iter();
        messages_of(frames.map(|r| (r.at_us, r.header, r.id, r.frame.as_slice())))
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
}

/// The frames (instant, header, message id, bytes) that carry message `M`, decoded.
fn messages_of<'a, M: MessageData<Protocol = K40t>>(
    frames: impl Iterator<Item = (u64, Header, MsgId, &'a [u8])>,
) -> Vec<(u64, Header, M)> {
    frames
        .filter(|f| f.2 == M::ID)
        .filter_map(|(at_us, header, _, frame)| {
            let p = Packet::decode(frame).ok()?;
            Some((at_us, header, p.message.get::<M>()?))
        })
        .collect()
}
