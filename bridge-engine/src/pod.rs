//! The K40T pod driver: the bridge acts as the flight controller (0x02/0x01).
//!
//! - **Commands.** A [`Command`] becomes one or two K40T requests. Settings and camera
//!   actions are tracked for their ACK. Idempotent ones (settings, absolute zoom, record
//!   start/stop, focus, views) are sent again when their ACK does not come
//!   ([`PodConfig::tries`], [`PodConfig::retry_interval`]); a newer command with the same
//!   base id supersedes a pending one. An action that counts (take photo, burst,
//!   time-lapse, single laser ranging) is **never sent twice for one FC command**: if its
//!   ACK does not come within the time the others get for all their tries, it is reported
//!   as timed out (the FC sides tell the FC it failed) rather than risk a second shot.
//!   Motion commands (0x000010, 0x000012, 0x000017) are never retried: the next one
//!   supersedes them.
//! - **Matching ACKs** (SPEC-NOTES): the K40T document has every component number the
//!   frames *it* sends, so a pod's ACK may carry the pod's own counter rather than the
//!   request's SEQ. An ACK is matched to the oldest outstanding request with the same base
//!   id, an exact SEQ match preferred but never required. A superseded request stays
//!   outstanding (not retried) so that its late ACK is not taken for its successor's.
//! - **Motion, never flooding the pod.** Rates and angles are edge-triggered: a target
//!   is sent when it differs from the last one sent by more than a dead-band, at most
//!   once per [`PodConfig::motion_interval`], and refreshed once per
//!   [`PodConfig::motion_refresh`] while the gimbal turns. A rate becomes a direction
//!   (0x000010) and a dial speed (0x000017, 1..30 °/s, clamped).
//! - **State cache.** Every report and status frame updates [`PodState`], which the FC
//!   sides answer from at once.
//! - **Learning.** The pod's gimbal and camera addresses and its CRC coverage are taken
//!   from its first reports ([`PodConfig::learn`]); until then the configured defaults
//!   apply.
//! - **Link.** The pod is lost when no report arrives for [`PodConfig::link_timeout`];
//!   while lost, a version query probes it every [`PodConfig::probe_interval`].

use super::Outputs;
use super::config::PodConfig;
use super::event::Event;
use super::time::{Duration, Instant};
use crate::gimbal::GimbalMode;
use crate::gimbal::{Command, Motion, Ranging, Target, View};
use protocol_core::k40t::{
    self, AckCode, Address, AiRecognition, CameraVersionAck, CameraVersionQuery, ContinuousZoom,
    CrcCoverage, Focus, FocusMode, Frame, GimbalAngle, GimbalAttitude, GimbalControl,
    GimbalFunction, GimbalStatus, GimbalVersionAck, GimbalVersionQuery, GpsReply, GpsRequest,
    Header, HybridZoom, ImageMode, ImageModeSetting, IrDigitalZoom, IrGain, IrGainMode, IrPalette,
    IrStatus, Kind, LaserDistance, LaserMode, LaserPeriodic, LaserPeriodicStatus, LaserRange, Lens,
    MessageData, OnOff, PhotoSensors, PhotoState, PhotoStatus, PitchMotion, PointToAim, Record,
    RecordAction, RecordSensors, RecordState, RecordStatus, Request, ResponseCode, ShootAction,
    SystemStatus, TakePhoto, Text, TimeSync, Toggle, TrackBox, UpgradeStatus, Version,
    VisibleStatus, YawMotion, ZoomControl, ZoomState, ZoomStatus,
};

/// Commands tracked for their ACK at once.
const PENDING: usize = 4;
/// Superseded commands whose ACK may still come (absorbed, so that a late ACK is not
/// taken for the command that superseded them).
const SUPERSEDED: usize = 4;

/// Slowest dial speed the pod accepts (0.2 °/s units: 1 °/s).
const MIN_DIAL_X5: u8 = 5;
/// Fastest dial speed (30 °/s).
const MAX_DIAL_X5: u8 = 150;

/// What the bridge knows of the pod, from its reports, status frames and ACKs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PodState {
    /// Reports arrive.
    pub link: bool,
    /// The last attitude report (0x000002) and when it came.
    pub attitude: Option<(GimbalAttitude, Instant)>,
    /// The last gimbal status (0x000001).
    pub gimbal_status: Option<GimbalStatus>,
    /// The last camera system status (0x000003): streamed image, SD card.
    pub system: Option<SystemStatus>,
    /// The last infrared measurements (0x000004) and when they came.
    pub ir: Option<(IrStatus, Instant)>,
    /// The last visible camera status (0x000005): zoom ratio, focus.
    pub visible: Option<VisibleStatus>,
    /// The last laser distance (0.1 m, 0 = none) and when it came.
    pub laser_dm: Option<(u16, Instant)>,
    /// Recording, from the 0x020303 status frames (1 Hz while recording) or the ACK of
    /// the last record command.
    pub recording: Option<RecordState>,
    /// The last photo progress (0x020302).
    pub photo: Option<PhotoState>,
    /// Zooming (0x020304).
    pub zoom: Option<ZoomState>,
    /// Gimbal versions (ACK of 0x000018).
    pub gimbal_version: Option<GimbalVersionAck>,
    /// Camera version (ACK of 0x000317).
    pub camera_version: Option<Version>,
    /// The yaw behaviour the FC last asked for (the K40T has no such setting: kept for
    /// the FC sides to report).
    pub mode: Option<GimbalMode>,
    /// The continuous ranging the bridge last switched on.
    pub ranging: bool,
    /// The pod acknowledged AI recognition on (0x000319), which its box tracking needs.
    pub ai: bool,
}

impl PodState {
    /// Recording now: the last record status (or ACK) says so.
    #[must_use]
    pub fn is_recording(&self) -> bool {
        matches!(
            self.recording,
            Some(RecordState::Recording | RecordState::TimeLapse | RecordState::TimeLapseWaiting)
        )
    }

    /// The hybrid zoom ratio times ten the pod last reported (1x when unknown).
    #[must_use]
    pub fn zoom_x10(&self) -> u16 {
        self.visible.map_or(10, |v| v.zoom_x10.max(10))
    }

    /// The streamed view, from the system status.
    #[must_use]
    pub fn view(&self) -> Option<View> {
        self.system.map(|s| match s.stream {
            ImageMode::Infrared => View::Thermal,
            ImageMode::Split => View::Split,
            _ => View::Visible,
        })
    }
}

/// The motion the pod was asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum MotionTarget {
    /// Directions and dial speeds (0.2 °/s units).
    Turn {
        yaw: YawMotion,
        pitch: PitchMotion,
        yaw_x5: u8,
        pitch_x5: u8,
        /// The rates asked, for the dead-band (0.01 °/s).
        yaw_cdeg_s: i32,
        pitch_cdeg_s: i32,
    },
    /// An absolute angle (0.01 °).
    Angle { yaw_cdeg: i32, pitch_cdeg: i32 },
    /// A quick function (centre, look down): sent once.
    Function(GimbalFunction),
}

impl MotionTarget {
    const STOP: Self = MotionTarget::Turn {
        yaw: YawMotion::Stop,
        pitch: PitchMotion::Stop,
        yaw_x5: 0,
        pitch_x5: 0,
        yaw_cdeg_s: 0,
        pitch_cdeg_s: 0,
    };

    fn is_turning(&self) -> bool {
        matches!(self, MotionTarget::Turn { yaw, pitch, .. }
            if *yaw != YawMotion::Stop || *pitch != PitchMotion::Stop)
    }

    /// True when `self` is a new command compared with `sent`.
    fn differs(&self, sent: &Self, cfg: &PodConfig) -> bool {
        match (self, sent) {
            (
                MotionTarget::Turn {
                    yaw,
                    pitch,
                    yaw_cdeg_s,
                    pitch_cdeg_s,
                    ..
                },
                MotionTarget::Turn {
                    yaw: y0,
                    pitch: p0,
                    yaw_cdeg_s: yr0,
                    pitch_cdeg_s: pr0,
                    ..
                },
            ) => {
                let band = u32::from(cfg.rate_deadband_cdeg_s);
                yaw != y0
                    || pitch != p0
                    || yaw_cdeg_s.abs_diff(*yr0) >= band
                    || pitch_cdeg_s.abs_diff(*pr0) >= band
            }
            (
                MotionTarget::Angle {
                    yaw_cdeg,
                    pitch_cdeg,
                },
                MotionTarget::Angle {
                    yaw_cdeg: y0,
                    pitch_cdeg: p0,
                },
            ) => {
                let band = u32::from(cfg.angle_deadband_cdeg);
                yaw_cdeg.abs_diff(*y0) >= band || pitch_cdeg.abs_diff(*p0) >= band
            }
            (a, b) => a != b,
        }
    }
}

/// The motion state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct MotionState {
    /// What the FC wants.
    target: MotionTarget,
    /// What was sent last, and when.
    sent: Option<(MotionTarget, Instant)>,
    /// Dial speeds last sent (0.2 °/s units).
    dial: Option<(u8, u8)>,
    /// The FC's last motion command.
    fc_at: Option<Instant>,
}

/// A command waiting for its ACK.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Pending {
    request: Request,
    seq: u8,
    /// When it was first sent (ACKs go to the oldest outstanding request).
    sent: Instant,
    /// Tries left after the one in flight.
    tries_left: u8,
    /// When to send again (or give up).
    due: Instant,
}

/// A superseded command whose ACK may still come.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Outstanding {
    base: u16,
    seq: u8,
    sent: Instant,
    /// Forgotten after this.
    until: Instant,
}

/// How well an ACK matches an outstanding request: an exact sequence number beats
/// none, then the older request wins (SPEC-NOTES: oldest pending first, exact SEQ
/// preferred, never required).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct AckClaim {
    /// The ACK's SEQ is the request's.
    pub(crate) exact: bool,
    /// When the request was first sent.
    pub(crate) sent: Instant,
}

impl AckClaim {
    /// `self` has the better claim on an ACK than `other`.
    pub(crate) fn beats(self, other: Self) -> bool {
        match (self.exact, other.exact) {
            (true, false) => true,
            (false, true) => false,
            _ => self.sent <= other.sent,
        }
    }

    /// The better of two optional claims (`self` on a tie).
    pub(crate) fn best(a: Option<Self>, b: Option<Self>) -> Option<Self> {
        match (a, b) {
            (Some(x), Some(y)) => Some(if y.beats(x) && !x.beats(y) { y } else { x }),
            (x, y) => x.or(y),
        }
    }
}

/// A request the FC cannot ask twice without consequence: a second copy takes a second
/// photo (or burst, or ranging). Never retried.
fn counts(request: &Request) -> bool {
    match request {
        Request::TakePhoto(p) => p.action != ShootAction::Stop,
        Request::LaserRange(_) => true,
        _ => false,
    }
}

/// Something the engine acts on, from the pod side.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum PodNotice {
    /// The first report after silence.
    LinkUp,
    /// Reports stopped.
    LinkDown,
    /// A tracked command was acknowledged with this code.
    Acked { base: u16, code: AckCode },
    /// A tracked command got no ACK after all its tries.
    TimedOut { base: u16 },
    /// The pod asks for GPS at a time of day.
    GpsRequest { header: Header, request: GpsRequest },
}

/// Up to a few notices from one call.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Notices {
    items: [Option<PodNotice>; 4],
}

impl Notices {
    fn push(&mut self, n: PodNotice) {
        if let Some(slot) = self.items.iter_mut().find(|s| s.is_none()) {
            *slot = Some(n);
        }
    }

    pub(crate) fn iter(&self) -> impl Iterator<Item = PodNotice> + '_ {
        self.items.iter().flatten().copied()
    }
}

/// The K40T pod driver.
#[derive(Debug, Clone)]
pub(crate) struct PodDriver {
    cfg: PodConfig,
    gimbal: Address,
    camera: Address,
    coverage: CrcCoverage,
    learned_gimbal: bool,
    learned_camera: bool,
    learned_coverage: bool,
    seq: u8,
    state: PodState,
    last_report: Option<Instant>,
    next_probe: Option<Instant>,
    pending: [Option<Pending>; PENDING],
    superseded: [Option<Outstanding>; SUPERSEDED],
    motion: MotionState,
}

impl PodDriver {
    pub(crate) fn new(cfg: PodConfig) -> Self {
        PodDriver {
            cfg,
            gimbal: cfg.gimbal,
            camera: cfg.camera,
            coverage: cfg.coverage,
            learned_gimbal: false,
            learned_camera: false,
            learned_coverage: false,
            seq: 0,
            state: PodState {
                link: false,
                attitude: None,
                gimbal_status: None,
                system: None,
                ir: None,
                visible: None,
                laser_dm: None,
                recording: None,
                photo: None,
                zoom: None,
                gimbal_version: None,
                camera_version: None,
                mode: None,
                ranging: false,
                ai: false,
            },
            last_report: None,
            next_probe: None,
            pending: [None; PENDING],
            superseded: [None; SUPERSEDED],
            motion: MotionState {
                target: MotionTarget::STOP,
                sent: None,
                dial: None,
                fc_at: None,
            },
        }
    }

    pub(crate) const fn state(&self) -> &PodState {
        &self.state
    }

    /// The addresses and coverage in use.
    #[cfg(test)]
    pub(crate) const fn link_params(&self) -> (Address, Address, CrcCoverage) {
        (self.gimbal, self.camera, self.coverage)
    }

    /// The next sequence number.
    pub(crate) fn next_seq(&mut self) -> u8 {
        let s = self.seq;
        self.seq = self.seq.wrapping_add(1);
        s
    }

    /// A header from the bridge to the part of the pod that handles `base`: gimbal-class
    /// ids (0x000010..0x0000FF) to the gimbal, the others to the camera.
    fn header(&self, base: u16, seq: u8) -> Header {
        let dst = if (0x0010..=0x00FF).contains(&base) {
            self.gimbal
        } else {
            self.camera
        };
        Header {
            dst,
            src: self.cfg.own,
            seq,
            coverage: self.coverage,
        }
    }

    /// A header with the next sequence number.
    fn header_for(&mut self, base: u16) -> Header {
        let seq = self.next_seq();
        self.header(base, seq)
    }

    /// Encodes and queues a request; returns its sequence number.
    fn send(&mut self, request: Request, critical: bool, out: &mut Outputs) -> Option<u8> {
        let header = self.header_for(request.base());
        let seq = header.seq;
        Self::queue(header, request, critical, false, out).then_some(seq)
    }

    fn queue(
        header: Header,
        request: Request,
        critical: bool,
        front: bool,
        out: &mut Outputs,
    ) -> bool {
        let mut buf = [0u8; k40t::MAX_FRAME_LEN];
        match request.emit(&header, &mut buf) {
            Ok(n) => out.queue_pod(buf.get(..n).unwrap_or_default(), critical, front),
            Err(_) => false,
        }
    }

    /// Sends a setting or camera action and tracks it for its ACK.
    fn send_tracked(&mut self, now: Instant, request: Request, out: &mut Outputs) {
        let base = request.base();
        let Some(seq) = self.send(request, false, out) else {
            return;
        };
        // A one-shot action gets one try, and waits for its ACK as long as the others
        // wait for all of theirs.
        let (tries_left, wait) = if counts(&request) {
            (0, self.ack_wait())
        } else {
            (self.cfg.tries.saturating_sub(1), self.cfg.retry_interval)
        };
        let pending = Pending {
            request,
            seq,
            sent: now,
            tries_left,
            due: now.saturating_add(wait),
        };
        // A newer command with the same base id supersedes the pending one (which stays
        // outstanding for its ACK, not retried); else take a free slot, else the oldest.
        let slot = match self
            .pending
            .iter()
            .position(|p| p.is_some_and(|p| p.request.base() == base))
        {
            Some(i) => {
                if let Some(old) = self.pending.get(i).copied().flatten() {
                    self.supersede(now, old);
                }
                Some(i)
            }
            None => self.pending.iter().position(Option::is_none).or_else(|| {
                self.pending
                    .iter()
                    .enumerate()
                    .min_by_key(|(_, p)| p.map(|p| p.sent))
                    .map(|(i, _)| i)
            }),
        };
        if let Some(s) = slot.and_then(|i| self.pending.get_mut(i)) {
            *s = Some(pending);
        }
    }

    /// The longest a tracked request waits for its ACK, over all its tries.
    fn ack_wait(&self) -> Duration {
        Duration::from_micros(
            self.cfg
                .retry_interval
                .as_micros()
                .saturating_mul(u64::from(self.cfg.tries.max(1))),
        )
    }

    /// Keeps a superseded request outstanding until its ACK comes or it is too old
    /// (a free slot, else the oldest one goes).
    fn supersede(&mut self, now: Instant, old: Pending) {
        let entry = Outstanding {
            base: old.request.base(),
            seq: old.seq,
            sent: old.sent,
            until: now.saturating_add(self.ack_wait()),
        };
        let slot = self
            .superseded
            .iter()
            .position(|o| o.is_none_or(|o| now >= o.until))
            .or_else(|| {
                self.superseded
                    .iter()
                    .enumerate()
                    .min_by_key(|(_, o)| o.map(|o| o.sent))
                    .map(|(i, _)| i)
            });
        if let Some(s) = slot.and_then(|i| self.superseded.get_mut(i)) {
            *s = Some(entry);
        }
    }

    /// This driver's claim on an ACK of `base` carrying `seq`: its oldest outstanding
    /// request of that base, or one with that exact sequence number (see [`AckClaim`]).
    pub(crate) fn ack_claim(&self, base: u16, seq: u8) -> Option<AckClaim> {
        let tracked = self
            .pending
            .iter()
            .flatten()
            .filter(|p| p.request.base() == base)
            .map(|p| AckClaim {
                exact: p.seq == seq,
                sent: p.sent,
            });
        let superseded = self
            .superseded
            .iter()
            .flatten()
            .filter(|o| o.base == base)
            .map(|o| AckClaim {
                exact: o.seq == seq,
                sent: o.sent,
            });
        tracked
            .chain(superseded)
            .fold(None, |best, c| AckClaim::best(best, Some(c)))
    }

    /// Translates one FC command. Returns the K40T base id of the request sent (or to
    /// be sent, for edge-triggered motion), `None` when the command has no K40T
    /// equivalent.
    pub(crate) fn command(&mut self, now: Instant, cmd: Command, out: &mut Outputs) -> Option<u16> {
        match cmd {
            Command::Rates {
                yaw_cdeg_s,
                pitch_cdeg_s,
            } => {
                self.motion.fc_at = Some(now);
                let (yaw, yaw_x5) = split_rate(
                    yaw_cdeg_s,
                    YawMotion::Right,
                    YawMotion::Left,
                    YawMotion::Stop,
                );
                let (pitch, pitch_x5) = split_rate(
                    pitch_cdeg_s,
                    PitchMotion::Up,
                    PitchMotion::Down,
                    PitchMotion::Stop,
                );
                for r in [yaw_cdeg_s, pitch_cdeg_s] {
                    if r.unsigned_abs() > u32::from(MAX_DIAL_X5).saturating_mul(20) {
                        out.event(Event::RateClamped {
                            requested_cdeg_s: r,
                        });
                    }
                }
                self.set_motion(
                    now,
                    MotionTarget::Turn {
                        yaw,
                        pitch,
                        yaw_x5,
                        pitch_x5,
                        yaw_cdeg_s,
                        pitch_cdeg_s,
                    },
                    out,
                );
                Some(0x0010)
            }
            Command::Angles {
                yaw_cdeg,
                pitch_cdeg,
            } => {
                self.motion.fc_at = Some(now);
                self.set_motion(
                    now,
                    MotionTarget::Angle {
                        yaw_cdeg: yaw_cdeg.clamp(-18000, 18000),
                        pitch_cdeg: pitch_cdeg.clamp(-9000, 3000),
                    },
                    out,
                );
                Some(0x0012)
            }
            Command::Center => {
                self.set_motion(now, MotionTarget::Function(GimbalFunction::Center), out);
                Some(0x0010)
            }
            Command::LookDown => {
                self.set_motion(now, MotionTarget::Function(GimbalFunction::LookDown), out);
                Some(0x0010)
            }
            Command::Mode(mode) => {
                self.state.mode = Some(mode);
                None
            }
            other => {
                // "AI detection must be turned on to perform frame selection target
                // tracking" (0x000324): switched on first, once; it stays on.
                if let Command::Track(Some(_)) = other
                    && !self.state.ai
                {
                    let ai = Request::AiRecognition(AiRecognition {
                        enable: Toggle::On,
                        model: 0,
                        classes: self.cfg.ai_classes,
                    });
                    self.send_tracked(now, ai, out);
                }
                let request = camera_request(other, &self.state)?;
                if let Command::Laser(r) = other {
                    self.state.ranging = r == Ranging::Continuous;
                }
                let base = request.base();
                self.send_tracked(now, request, out);
                Some(base)
            }
        }
    }

    fn set_motion(&mut self, now: Instant, target: MotionTarget, out: &mut Outputs) {
        self.motion.target = target;
        let due = match self.motion.sent {
            None => true,
            Some((sent, at)) => {
                target.differs(&sent, &self.cfg)
                    && now.saturating_duration_since(at) >= self.cfg.motion_interval
            }
        };
        if due {
            self.send_motion(now, out);
        }
    }

    /// Sends the motion target now.
    fn send_motion(&mut self, now: Instant, out: &mut Outputs) {
        let target = self.motion.target;
        let request = match target {
            MotionTarget::Turn {
                yaw,
                pitch,
                yaw_x5,
                pitch_x5,
                ..
            } => {
                let turning = target.is_turning();
                if turning && self.motion.dial != Some((pitch_x5, yaw_x5)) {
                    let dial = Request::DialSpeed(k40t::DialSpeed {
                        pitch_dps_x5: pitch_x5.max(MIN_DIAL_X5),
                        yaw_dps_x5: yaw_x5.max(MIN_DIAL_X5),
                        reserved: 0,
                    });
                    if self.send(dial, false, out).is_some() {
                        self.motion.dial = Some((pitch_x5, yaw_x5));
                    }
                }
                Request::GimbalControl(GimbalControl {
                    function: GimbalFunction::None,
                    yaw,
                    pitch,
                    reserved: 0,
                })
            }
            MotionTarget::Angle {
                yaw_cdeg,
                pitch_cdeg,
            } => Request::GimbalAngle(GimbalAngle {
                pitch_direction: if pitch_cdeg >= 0 {
                    PitchMotion::Up
                } else {
                    PitchMotion::Down
                },
                pitch_cdeg: u16::try_from(pitch_cdeg.unsigned_abs()).unwrap_or(u16::MAX),
                yaw_direction: if yaw_cdeg >= 0 {
                    YawMotion::Right
                } else {
                    YawMotion::Left
                },
                yaw_cdeg: u16::try_from(yaw_cdeg.unsigned_abs()).unwrap_or(u16::MAX),
                reserved: 0,
            }),
            MotionTarget::Function(function) => Request::GimbalControl(GimbalControl {
                function,
                yaw: YawMotion::Stop,
                pitch: PitchMotion::Stop,
                reserved: 0,
            }),
        };
        self.send(request, false, out);
        self.motion.sent = Some((target, now));
    }

    /// Stops the gimbal (the FC fell silent).
    fn stop(&mut self, now: Instant, out: &mut Outputs) {
        self.motion.target = MotionTarget::STOP;
        self.send_motion(now, out);
    }

    /// Handles one valid frame from the pod. An ACK is matched to one of this driver's
    /// outstanding requests only when `claimed` (the engine weighs this driver's
    /// [`ack_claim`](Self::ack_claim) against the FC side's forwarded requests); its data
    /// (versions, distances) is taken in any case.
    pub(crate) fn handle(
        &mut self,
        now: Instant,
        frame: &Frame<&[u8]>,
        header: Header,
        claimed: bool,
        out: &mut Outputs,
    ) -> Notices {
        let mut notices = Notices::default();
        let report = match frame.id().kind {
            Kind::Request => self.on_report(now, frame, header, &mut notices, out),
            Kind::Ack => {
                self.on_ack(now, frame, header.seq, claimed, &mut notices, out);
                false
            }
            Kind::Status => {
                self.on_status(now, frame);
                false
            }
            Kind::Other(_) => false,
        };
        if report {
            if self.cfg.learn && !self.learned_coverage {
                self.learned_coverage = true;
                if self.coverage != header.coverage {
                    self.coverage = header.coverage;
                }
                out.event(Event::PodCoverage(self.coverage));
            }
            self.last_report = Some(now);
            if !self.state.link {
                self.state.link = true;
                notices.push(PodNotice::LinkUp);
                // Versions, on every (re)connection.
                self.query_versions(now, out);
            }
        }
        notices
    }

    fn query_versions(&mut self, now: Instant, out: &mut Outputs) {
        let q = Request::GimbalVersion(GimbalVersionQuery {
            command: 1,
            reserved: 0,
        });
        self.send_tracked(now, q, out);
        let q = Request::CameraVersion(CameraVersionQuery {
            command: 1,
            reserved: 0,
        });
        self.send_tracked(now, q, out);
    }

    /// A kind-0x00 frame from the pod: a periodic report, or a request to the FC.
    /// Returns true for a report.
    fn on_report(
        &mut self,
        now: Instant,
        frame: &Frame<&[u8]>,
        header: Header,
        notices: &mut Notices,
        out: &mut Outputs,
    ) -> bool {
        let src = header.src;
        // Only the messages the bridge uses are decoded (see `typed`).
        let gimbal_report = if let Some(s) = typed::<GimbalStatus>(frame) {
            self.state.gimbal_status = Some(s);
            true
        } else if let Some(a) = typed::<GimbalAttitude>(frame) {
            self.state.attitude = Some((self.normalise(a), now));
            true
        } else if let Some(s) = typed::<SystemStatus>(frame) {
            self.state.system = Some(s);
            false
        } else if let Some(s) = typed::<IrStatus>(frame) {
            self.state.ir = Some((s, now));
            false
        } else if let Some(s) = typed::<VisibleStatus>(frame) {
            self.state.visible = Some(s);
            false
        } else if typed::<UpgradeStatus>(frame).is_some() {
            false
        } else {
            if let Some(request) = typed::<GpsRequest>(frame) {
                notices.push(PodNotice::GpsRequest { header, request });
            }
            return false;
        };
        if self.cfg.learn {
            let (learned, addr) = if gimbal_report {
                (&mut self.learned_gimbal, &mut self.gimbal)
            } else {
                (&mut self.learned_camera, &mut self.camera)
            };
            if !*learned {
                *learned = true;
                *addr = src;
                if self.learned_gimbal && self.learned_camera {
                    out.event(Event::PodAddresses {
                        gimbal: self.gimbal,
                        camera: self.camera,
                    });
                }
            }
        }
        true
    }

    /// The attitude report in the bridge's sign convention (yaw right, pitch up).
    fn normalise(&self, mut a: GimbalAttitude) -> GimbalAttitude {
        if self.cfg.yaw_positive_left {
            a.yaw_cdeg = a.yaw_cdeg.saturating_neg();
            a.yaw_joint_cdeg = a.yaw_joint_cdeg.saturating_neg();
            a.yaw_rate_cdeg_s = a.yaw_rate_cdeg_s.saturating_neg();
        }
        if self.cfg.pitch_positive_down {
            a.pitch_cdeg = a.pitch_cdeg.saturating_neg();
            a.pitch_joint_cdeg = a.pitch_joint_cdeg.saturating_neg();
            a.pitch_rate_cdeg_s = a.pitch_rate_cdeg_s.saturating_neg();
        }
        a
    }

    fn on_ack(
        &mut self,
        now: Instant,
        frame: &Frame<&[u8]>,
        seq: u8,
        claimed: bool,
        notices: &mut Notices,
        out: &mut Outputs,
    ) {
        let base = frame.id().base;
        // Every ACK opens with its response code (a shorter payload is zero-extended).
        let p = frame.payload();
        let code = ResponseCode {
            raw: [
                p.first().copied().unwrap_or(0),
                p.get(1).copied().unwrap_or(0),
            ],
        }
        .code();
        if let Some(v) = typed::<GimbalVersionAck>(frame) {
            self.state.gimbal_version = Some(v);
        } else if let Some(v) = typed::<CameraVersionAck>(frame) {
            self.state.camera_version = Some(v.version);
        } else if let Some(d) = typed::<LaserDistance>(frame) {
            self.state.laser_dm = Some((d.distance_dm, now));
        }
        let acked = if claimed {
            self.take_outstanding(now, base, seq)
        } else {
            None
        };
        if let Some(request) = acked {
            if code == AckCode::Ok {
                match request {
                    Request::Record(r) => {
                        self.state.recording = Some(match r.action {
                            RecordAction::Start => RecordState::Recording,
                            _ => RecordState::Stopped,
                        });
                    }
                    Request::AiRecognition(a) => self.state.ai = a.enable == Toggle::On,
                    _ => {}
                }
            } else {
                out.event(Event::PodRefused { base, code });
            }
            notices.push(PodNotice::Acked { base, code });
        } else if code != AckCode::Ok && matches!(base, 0x0010 | 0x0012 | 0x0017) {
            out.event(Event::PodRefused { base, code });
        }
    }

    /// Removes the outstanding request an ACK of `base` with `seq` answers (the best
    /// [`AckClaim`]); returns it when it was a tracked one (`None` for a superseded
    /// request, whose ACK is only absorbed, or none at all).
    fn take_outstanding(&mut self, now: Instant, base: u16, seq: u8) -> Option<Request> {
        let claim = self.ack_claim(base, seq)?;
        let matches = |b: u16, s: u8, sent: Instant| {
            b == base && sent == claim.sent && (!claim.exact || s == seq)
        };
        if let Some(slot) = self
            .pending
            .iter_mut()
            .find(|p| p.is_some_and(|p| matches(p.request.base(), p.seq, p.sent)))
        {
            return slot.take().map(|p| p.request);
        }
        if let Some(slot) = self
            .superseded
            .iter_mut()
            .find(|o| o.is_some_and(|o| matches(o.base, o.seq, o.sent)))
        {
            *slot = None;
        }
        // Forget superseded requests too old for their ACK to come.
        for o in &mut self.superseded {
            if o.is_some_and(|o| now >= o.until) {
                *o = None;
            }
        }
        None
    }

    fn on_status(&mut self, now: Instant, frame: &Frame<&[u8]>) {
        if let Some(p) = typed::<PhotoStatus>(frame) {
            self.state.photo = Some(p.state);
        } else if let Some(r) = typed::<RecordStatus>(frame) {
            self.state.recording = Some(r.state);
        } else if let Some(z) = typed::<ZoomStatus>(frame) {
            self.state.zoom = Some(z.state);
        } else if let Some(d) = typed::<LaserPeriodicStatus>(frame) {
            self.state.laser_dm = Some((d.0.distance_dm, now));
        }
    }

    /// Periodic duties: retries and time-outs, the link, motion refresh and the FC
    /// silence stop.
    pub(crate) fn poll(
        &mut self,
        now: Instant,
        fc_silence: Duration,
        out: &mut Outputs,
    ) -> Notices {
        let mut notices = Notices::default();
        for o in &mut self.superseded {
            if o.is_some_and(|o| now >= o.until) {
                *o = None;
            }
        }
        // Retries and time-outs.
        for i in 0..PENDING {
            let Some(p) = self.pending.get(i).copied().flatten() else {
                continue;
            };
            if now < p.due {
                continue;
            }
            if p.tries_left == 0 {
                if let Some(slot) = self.pending.get_mut(i) {
                    *slot = None;
                }
                out.event(Event::PodTimeout {
                    base: p.request.base(),
                });
                notices.push(PodNotice::TimedOut {
                    base: p.request.base(),
                });
                continue;
            }
            // Same sequence number: the pod can tell a repeat from a new command.
            let header = self.header(p.request.base(), p.seq);
            Self::queue(header, p.request, false, false, out);
            out.counters.pod_retries = out.counters.pod_retries.saturating_add(1);
            if let Some(Some(slot)) = self.pending.get_mut(i) {
                slot.tries_left = slot.tries_left.saturating_sub(1);
                slot.due = now.saturating_add(self.cfg.retry_interval);
            }
        }
        // The link.
        let lost = self
            .last_report
            .is_none_or(|t| now.saturating_duration_since(t) >= self.cfg.link_timeout);
        if self.state.link && lost {
            self.state.link = false;
            notices.push(PodNotice::LinkDown);
        }
        if !self.state.link && self.next_probe.is_none_or(|t| now >= t) {
            let q = Request::GimbalVersion(GimbalVersionQuery {
                command: 1,
                reserved: 0,
            });
            self.send(q, false, out);
            self.next_probe = Some(now.saturating_add(self.cfg.probe_interval));
        }
        // Motion: FC silence stop, deferred sends, refresh.
        if let Some((sent, at)) = self.motion.sent {
            let silent = self
                .motion
                .fc_at
                .is_none_or(|t| now.saturating_duration_since(t) >= fc_silence);
            if sent.is_turning() && self.motion.target.is_turning() && silent {
                self.stop(now, out);
                out.event(Event::FcSilenceStop);
            } else {
                let elapsed = now.saturating_duration_since(at);
                let changed = self.motion.target.differs(&sent, &self.cfg)
                    && elapsed >= self.cfg.motion_interval;
                let refresh = sent.is_turning() && elapsed >= self.cfg.motion_refresh;
                if changed || refresh {
                    self.send_motion(now, out);
                }
            }
        }
        notices
    }

    /// When [`PodDriver::poll`] has work.
    pub(crate) fn poll_at(&self, fc_silence: Duration) -> Option<Instant> {
        let mut at: Option<Instant> = None;
        let mut consider = |t: Instant| at = Some(at.map_or(t, |a| a.min(t)));
        for p in self.pending.iter().flatten() {
            consider(p.due);
        }
        if let Some(t) = self.last_report.filter(|_| self.state.link) {
            consider(t.saturating_add(self.cfg.link_timeout));
        }
        if !self.state.link {
            consider(self.next_probe.unwrap_or_default());
        }
        if let Some((sent, t)) = self.motion.sent {
            if sent.is_turning() {
                consider(t.saturating_add(self.cfg.motion_refresh));
                if let Some(fc) = self.motion.fc_at {
                    consider(fc.saturating_add(fc_silence));
                }
            }
            if self.motion.target.differs(&sent, &self.cfg) {
                consider(t.saturating_add(self.cfg.motion_interval));
            }
        }
        at
    }

    /// Queues a 0x00030E at the head of the pod queue.
    pub(crate) fn send_time_sync(
        &mut self,
        unix_ms: u64,
        tz_minuteswest: i32,
        out: &mut Outputs,
    ) -> bool {
        let header = self.header_for(0x030E);
        let sync = Request::TimeSync(TimeSync {
            unix_ms,
            tz_minuteswest,
            tz_dsttime: 0,
        });
        Self::queue(header, sync, true, true, out)
    }

    /// Queues the ACK of a GPS request (critical: never dropped).
    pub(crate) fn send_gps_reply(
        &mut self,
        request: Header,
        reply: GpsReply,
        out: &mut Outputs,
    ) -> bool {
        let header = Header {
            dst: request.src,
            src: self.cfg.own,
            seq: request.seq,
            coverage: self.coverage,
        };
        let mut buf = [0u8; k40t::MAX_FRAME_LEN];
        match k40t::encode(&reply, &header, &mut buf) {
            Ok(n) => out.queue_pod(buf.get(..n).unwrap_or_default(), true, false),
            Err(_) => false,
        }
    }
}

/// A signed rate as a direction and a dial speed (0.2 °/s units, 5..=150 when moving).
fn split_rate<D: Copy>(rate_cdeg_s: i32, positive: D, negative: D, stop: D) -> (D, u8) {
    if rate_cdeg_s == 0 {
        return (stop, 0);
    }
    // 0.01 °/s -> 0.2 °/s: divide by 20.
    let x5 =
        (rate_cdeg_s.unsigned_abs() / 20).clamp(u32::from(MIN_DIAL_X5), u32::from(MAX_DIAL_X5));
    let x5 = u8::try_from(x5).unwrap_or(MAX_DIAL_X5);
    (if rate_cdeg_s > 0 { positive } else { negative }, x5)
}

/// The K40T request for a camera command (`None`: no equivalent).
#[allow(clippy::too_many_lines)] // one short arm per command
fn camera_request(cmd: Command, state: &PodState) -> Option<Request> {
    let empty = Text::default();
    Some(match cmd {
        Command::TakePhoto => Request::TakePhoto(TakePhoto {
            sensors: PhotoSensors::Default,
            action: ShootAction::Start,
            folder: empty,
            name: Text::default(),
        }),
        Command::Record(start) => Request::Record(Record {
            sensors: RecordSensors::Default,
            action: if start {
                RecordAction::Start
            } else {
                RecordAction::Stop
            },
            folder: empty,
            name: Text::default(),
        }),
        Command::VideoMode(video) => Request::CaptureMode(k40t::CaptureModeSetting {
            mode: if video {
                k40t::CaptureMode::Video
            } else {
                k40t::CaptureMode::Photo
            },
            reserved: 0,
        }),
        Command::Zoom(m) => Request::ContinuousZoom(ContinuousZoom {
            control: match m {
                Motion::In => ZoomControl::In,
                Motion::Out => ZoomControl::Out,
                Motion::Stop => ZoomControl::Stop,
            },
            reserved: 0,
        }),
        Command::ZoomTo { zoom_x10 } => Request::HybridZoom(HybridZoom {
            start: 0,
            zoom_x10: zoom_x10.clamp(10, 1600),
        }),
        Command::ThermalZoom { ratio } => Request::IrDigitalZoom(IrDigitalZoom {
            zoom_x: ratio.clamp(1, 8),
            reserved: 0,
        }),
        Command::Focus(m) => Request::Focus(Focus {
            mode: match m {
                Motion::In => FocusMode::ManualPlus,
                Motion::Out => FocusMode::ManualMinus,
                Motion::Stop => FocusMode::ManualStop,
            },
            ..Focus::default()
        }),
        Command::AutoFocus(target) => {
            let (mode, (x0, y0, x1, y1)) = match target {
                None => (FocusMode::Auto, (0, 0, 0, 0)),
                Some(t) => (FocusMode::Area, target_box(t)),
            };
            Request::Focus(Focus {
                mode,
                x0,
                y0,
                x1,
                y1,
                reserved: 0,
            })
        }
        Command::ManualFocus(on) => Request::Focus(Focus {
            mode: if on {
                FocusMode::ManualStop
            } else {
                FocusMode::Auto
            },
            ..Focus::default()
        }),
        Command::View(v) => Request::ImageMode(ImageModeSetting {
            mode: match v {
                View::Visible => ImageMode::Visible,
                View::Thermal => ImageMode::Infrared,
                View::Split => ImageMode::Split,
            },
            reserved: 0,
        }),
        Command::Palette(palette) => Request::IrPalette(IrPalette {
            palette,
            reserved: 0,
        }),
        Command::ThermalHighGain(high) => Request::IrGainMode(IrGainMode {
            gain: if high { IrGain::High } else { IrGain::Low },
            reserved: 0,
        }),
        Command::Laser(Ranging::Single) => Request::LaserRange(LaserRange {
            mode: LaserMode::Single,
            reserved: 0,
        }),
        Command::Laser(r) => Request::LaserPeriodic(LaserPeriodic {
            enable: if r == Ranging::Continuous {
                OnOff::On
            } else {
                OnOff::Off
            },
            reserved: 0,
        }),
        Command::Track(target) => {
            let (x0, y0, x1, y1) = target.map_or((0, 0, 0, 0), target_box);
            Request::TrackBox(TrackBox {
                enable: if target.is_some() {
                    Toggle::On
                } else {
                    Toggle::Off
                },
                x: x0,
                y: y0,
                width: x1.saturating_sub(x0),
                height: y1.saturating_sub(y0),
                reserved: 0,
            })
        }
        Command::Aim(t) => {
            let (x0, y0, x1, y1) = target_box(t);
            Request::PointToAim(PointToAim {
                lens: if state.view() == Some(View::Thermal) {
                    Lens::Infrared
                } else {
                    Lens::Telephoto
                },
                zoom_x10: state.zoom_x10(),
                x: x0.saturating_add(x1.saturating_sub(x0) / 2).clamp(1, 1920),
                y: y0.saturating_add(y1.saturating_sub(y0) / 2).clamp(1, 1080),
            })
        }
        Command::Rates { .. }
        | Command::Angles { .. }
        | Command::Center
        | Command::LookDown
        | Command::Mode(_) => return None,
    })
}

/// Half the side of the box drawn around a point target (pixels).
const POINT_BOX_HALF: u16 = 64;

/// A target as a box inside the 1920 x 1080 picture (a point becomes a small box).
fn target_box(t: Target) -> (u16, u16, u16, u16) {
    let (x0, y0, x1, y1) = match t {
        Target::Point { x, y } => (
            x.saturating_sub(POINT_BOX_HALF),
            y.saturating_sub(POINT_BOX_HALF),
            x.saturating_add(POINT_BOX_HALF),
            y.saturating_add(POINT_BOX_HALF),
        ),
        Target::Box { x0, y0, x1, y1 } => (x0.min(x1), y0.min(y1), x0.max(x1), y0.max(y1)),
    };
    (x0.min(1920), y0.min(1080), x1.min(1920), y1.min(1080))
}

/// The frame's payload as `M` when it carries `M` and decodes; `None` otherwise. The
/// driver decodes only the messages it uses, one layout each, so the firmware does not
/// carry the decoders of the hundred others (`Frame::decode_as`).
fn typed<M: MessageData<Protocol = protocol_core::k40t::K40t>>(frame: &Frame<&[u8]>) -> Option<M> {
    frame.decode_as::<M>().and_then(Result::ok)
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol_core::k40t::{
        CameraVersionAck, DialSpeed, GimbalAttitude, HybridZoomAck, Kind, MessageData, MsgId,
        TakePhotoAck,
    };
    use protocol_core::k40t::{Message, Packet};

    fn outputs() -> Outputs {
        Outputs::new()
    }

    fn ms(t: u64) -> Instant {
        Instant::from_millis(t)
    }

    /// The frames queued for the pod, decoded, oldest first, without the version
    /// queries that probe a pod not heard from.
    fn sent(out: &mut Outputs) -> Vec<(Header, Request)> {
        let mut v = sent_all(out);
        v.retain(|(_, r)| !matches!(r, Request::GimbalVersion(_) | Request::CameraVersion(_)));
        v
    }

    /// Every frame queued for the pod.
    fn sent_all(out: &mut Outputs) -> Vec<(Header, Request)> {
        let mut v = vec![];
        while let Some(f) = out.pod.front() {
            let p = Packet::decode(f).unwrap();
            match p.message {
                Message::Request(r) => v.push((p.header, r)),
                Message::Ack(a) => panic!("ack {a:?}"),
                other => panic!("{other:?}"),
            }
            out.pod.pop();
        }
        v
    }

    fn events(out: &mut Outputs) -> Vec<Event> {
        let mut v = vec![];
        while let Some(e) = out.events.pop() {
            v.push(e);
        }
        v
    }

    /// A frame from the pod.
    fn from_pod<M: MessageData<Protocol = protocol_core::k40t::K40t>>(
        m: M,
        src: Address,
        seq: u8,
        coverage: CrcCoverage,
    ) -> Vec<u8> {
        let header = Header {
            dst: Address::FLIGHT_CONTROLLER,
            src,
            seq,
            coverage,
        };
        let mut buf = [0u8; k40t::MAX_FRAME_LEN];
        let n = k40t::encode(&m, &header, &mut buf).unwrap();
        buf[..n].to_vec()
    }

    fn feed(pod: &mut PodDriver, now: Instant, frame: &[u8], out: &mut Outputs) -> Vec<PodNotice> {
        let f = Frame::new_checked(frame).unwrap();
        let header = f.header().unwrap();
        let claimed = pod.ack_claim(f.id().base, header.seq).is_some();
        pod.handle(now, &f, header, claimed, out).iter().collect()
    }

    fn rates(yaw: i32, pitch: i32) -> Command {
        Command::Rates {
            yaw_cdeg_s: yaw,
            pitch_cdeg_s: pitch,
        }
    }

    #[test]
    fn rates_become_direction_and_dial_speed_edge_triggered() {
        let mut pod = PodDriver::new(PodConfig::DEFAULT);
        let mut out = outputs();
        // 45 deg/s right is clamped to 30 deg/s; 9 deg/s down.
        assert_eq!(
            pod.command(ms(0), rates(4500, -900), &mut out),
            Some(0x0010)
        );
        let s = sent(&mut out);
        assert_eq!(s.len(), 2);
        assert_eq!(
            s[0].1,
            Request::DialSpeed(DialSpeed {
                pitch_dps_x5: 45,
                yaw_dps_x5: 150,
                reserved: 0
            })
        );
        assert_eq!(s[0].0.dst, Address::GIMBAL);
        assert_eq!(
            s[1].1,
            Request::GimbalControl(GimbalControl {
                function: GimbalFunction::None,
                yaw: YawMotion::Right,
                pitch: PitchMotion::Down,
                reserved: 0
            })
        );
        assert_eq!(s[1].0.seq, s[0].0.seq.wrapping_add(1));
        assert!(events(&mut out).contains(&Event::RateClamped {
            requested_cdeg_s: 4500
        }));

        // The FC repeats the same rates at 50 Hz: nothing new for the pod.
        for t in (20..1000).step_by(20) {
            pod.command(ms(t), rates(4500, -900), &mut out);
            pod.poll(ms(t), Duration::from_millis(500), &mut out);
        }
        assert!(sent(&mut out).is_empty());
        // ... until the refresh, once a second.
        pod.command(ms(1000), rates(4500, -900), &mut out);
        pod.poll(ms(1000), Duration::from_millis(500), &mut out);
        let s = sent(&mut out);
        assert_eq!(s.len(), 1, "{s:?}");
        assert!(matches!(s[0].1, Request::GimbalControl(_)));

        // A change within the dead-band (0.4 deg/s) is no new command; beyond it, a new
        // dial speed and direction, but not before the motion interval.
        pod.command(ms(1020), rates(4500, -940), &mut out);
        assert!(sent(&mut out).is_empty());
        pod.command(ms(1040), rates(4500, -1000), &mut out);
        assert!(sent(&mut out).is_empty(), "within 100 ms of the last");
        pod.poll(ms(1100), Duration::from_millis(500), &mut out);
        let s = sent(&mut out);
        assert_eq!(s.len(), 2, "{s:?}");
        assert_eq!(
            s[0].1,
            Request::DialSpeed(DialSpeed {
                pitch_dps_x5: 50,
                yaw_dps_x5: 150,
                reserved: 0
            })
        );
    }

    #[test]
    fn fc_silence_stops_the_pod() {
        let mut pod = PodDriver::new(PodConfig::DEFAULT);
        let mut out = outputs();
        pod.command(ms(0), rates(1000, 0), &mut out);
        sent(&mut out);
        events(&mut out);
        let silence = Duration::from_millis(500);
        pod.poll(ms(0), silence, &mut out); // probes the pod: due again in 1 s
        assert_eq!(pod.poll_at(silence), Some(ms(500)));
        pod.poll(ms(499), silence, &mut out);
        assert!(sent(&mut out).is_empty());
        pod.poll(ms(500), silence, &mut out);
        let s = sent(&mut out);
        assert_eq!(
            s.iter().map(|(_, r)| *r).collect::<Vec<_>>(),
            vec![Request::GimbalControl(GimbalControl {
                function: GimbalFunction::None,
                yaw: YawMotion::Stop,
                pitch: PitchMotion::Stop,
                reserved: 0
            })]
        );
        assert_eq!(events(&mut out), vec![Event::FcSilenceStop]);
        // Stopped: no more stops, no refresh.
        pod.poll(ms(5000), silence, &mut out);
        assert!(sent(&mut out).is_empty());
        assert_eq!(pod.poll_at(silence), Some(ms(6000)), "probing the lost pod");
    }

    #[test]
    fn settings_are_retried_then_time_out_and_acks_stop_them() {
        let mut pod = PodDriver::new(PodConfig::DEFAULT);
        let mut out = outputs();
        let silence = Duration::from_millis(500);
        assert_eq!(
            pod.command(ms(0), Command::Record(true), &mut out),
            Some(0x0303)
        );
        let first = sent(&mut out);
        assert_eq!(first.len(), 1);
        assert_eq!(first[0].0.dst, Address::POD);
        let seq = first[0].0.seq;
        pod.poll(ms(199), silence, &mut out);
        assert!(sent(&mut out).iter().all(|(_, r)| r.base() != 0x0303));
        pod.poll(ms(200), silence, &mut out);
        let retry: Vec<_> = sent(&mut out)
            .into_iter()
            .filter(|(_, r)| r.base() == 0x0303)
            .collect();
        assert_eq!(retry.len(), 1);
        assert_eq!(retry[0].0.seq, seq, "a retry keeps its sequence number");
        pod.poll(ms(400), silence, &mut out);
        let notices: Vec<_> = pod.poll(ms(600), silence, &mut out).iter().collect();
        assert_eq!(notices, vec![PodNotice::TimedOut { base: 0x0303 }]);
        assert!(events(&mut out).contains(&Event::PodTimeout { base: 0x0303 }));
        assert_eq!(out.counters.pod_retries, 2);

        // Acknowledged at once: no retry.
        pod.command(ms(1000), Command::ZoomTo { zoom_x10: 45 }, &mut out);
        let s = sent(&mut out);
        let (h, r) = s.iter().find(|(_, r)| r.base() == 0x0304).unwrap();
        assert_eq!(
            *r,
            Request::HybridZoom(HybridZoom {
                start: 0,
                zoom_x10: 45
            })
        );
        let ack = from_pod(
            HybridZoomAck {
                code: k40t::ResponseCode::OK,
            },
            Address::POD,
            h.seq,
            CrcCoverage::ExcludeStx,
        );
        let n = feed(&mut pod, ms(1050), &ack, &mut out);
        assert_eq!(
            n,
            vec![PodNotice::Acked {
                base: 0x0304,
                code: AckCode::Ok
            }]
        );
        pod.poll(ms(1300), silence, &mut out);
        assert!(sent(&mut out).iter().all(|(_, r)| r.base() != 0x0304));

        // A refusal is an event.
        pod.command(ms(2000), Command::TakePhoto, &mut out);
        let s = sent(&mut out);
        let seq = s.iter().find(|(_, r)| r.base() == 0x0302).unwrap().0.seq;
        let nak = from_pod(
            TakePhotoAck {
                code: k40t::ResponseCode::new(AckCode::NoSdCard),
            },
            Address::POD,
            seq,
            CrcCoverage::ExcludeStx,
        );
        feed(&mut pod, ms(2010), &nak, &mut out);
        assert!(events(&mut out).contains(&Event::PodRefused {
            base: 0x0302,
            code: AckCode::NoSdCard
        }));
    }

    #[test]
    fn addresses_coverage_and_link_are_learnt_from_reports() {
        let mut pod = PodDriver::new(PodConfig::DEFAULT);
        let mut out = outputs();
        let silence = Duration::from_millis(500);
        // Lost at start: probing.
        pod.poll(ms(0), silence, &mut out);
        assert!(matches!(
            sent_all(&mut out)[..],
            [(_, Request::GimbalVersion(_))]
        ));
        let gimbal_src = Address::new(0x04, 0x01);
        let att = GimbalAttitude {
            yaw_cdeg: 1234,
            pitch_cdeg: -4500,
            ..GimbalAttitude::default()
        };
        let report = from_pod(att, gimbal_src, 1, CrcCoverage::IncludeStx);
        let notices = feed(&mut pod, ms(10), &report, &mut out);
        assert_eq!(notices, vec![PodNotice::LinkUp]);
        assert_eq!(pod.state().attitude, Some((att, ms(10))));
        assert!(pod.state().link);
        let ev = events(&mut out);
        assert!(
            ev.contains(&Event::PodCoverage(CrcCoverage::IncludeStx)),
            "{ev:?}"
        );
        // Versions are asked on connection, with the learnt coverage and address.
        let s = sent_all(&mut out);
        assert!(s.iter().any(|(h, r)| matches!(r, Request::GimbalVersion(_))
            && h.dst == gimbal_src
            && h.coverage == CrcCoverage::IncludeStx));
        assert!(
            s.iter()
                .any(|(_, r)| matches!(r, Request::CameraVersion(_)))
        );
        let (g, c, cov) = pod.link_params();
        assert_eq!(
            (g, c, cov),
            (gimbal_src, Address::POD, CrcCoverage::IncludeStx)
        );
        // Reports stop: lost after 1 s, probing again every second.
        pod.poll(ms(1009), silence, &mut out);
        assert!(pod.state().link);
        let notices: Vec<_> = pod.poll(ms(1010), silence, &mut out).iter().collect();
        assert_eq!(notices, vec![PodNotice::LinkDown]);
        assert!(!pod.state().link);
        let ack = from_pod(
            CameraVersionAck {
                code: k40t::ResponseCode::OK,
                version: Version {
                    major: 2,
                    minor: 1,
                    patch: 7,
                },
            },
            Address::POD,
            0,
            CrcCoverage::IncludeStx,
        );
        feed(&mut pod, ms(1100), &ack, &mut out);
        assert_eq!(
            pod.state().camera_version,
            Some(Version {
                major: 2,
                minor: 1,
                patch: 7
            })
        );
        assert_eq!(MsgId::new(Kind::Ack, 0x0317), CameraVersionAck::ID);
    }

    #[test]
    fn angles_and_quick_functions() {
        let mut pod = PodDriver::new(PodConfig::DEFAULT);
        let mut out = outputs();
        pod.command(
            ms(0),
            Command::Angles {
                yaw_cdeg: -9000,
                pitch_cdeg: -12000,
            },
            &mut out,
        );
        assert_eq!(
            sent(&mut out)[0].1,
            Request::GimbalAngle(GimbalAngle {
                pitch_direction: PitchMotion::Down,
                pitch_cdeg: 9000,
                yaw_direction: YawMotion::Left,
                yaw_cdeg: 9000,
                reserved: 0
            })
        );
        // Repeated: nothing; centre: at once after the interval.
        pod.command(
            ms(50),
            Command::Angles {
                yaw_cdeg: -9005,
                pitch_cdeg: -9000,
            },
            &mut out,
        );
        assert!(sent(&mut out).is_empty());
        pod.command(ms(150), Command::Center, &mut out);
        assert_eq!(
            sent(&mut out)[0].1,
            Request::GimbalControl(GimbalControl {
                function: GimbalFunction::Center,
                yaw: YawMotion::Stop,
                pitch: PitchMotion::Stop,
                reserved: 0
            })
        );
    }

    #[test]
    fn a_photo_is_never_sent_twice_and_a_lost_ack_times_out() {
        let mut pod = PodDriver::new(PodConfig::DEFAULT);
        let mut out = outputs();
        let silence = Duration::from_millis(500);
        pod.command(ms(0), Command::TakePhoto, &mut out);
        let photos = |v: &[(Header, Request)]| v.iter().filter(|(_, r)| r.base() == 0x0302).count();
        assert_eq!(photos(&sent(&mut out)), 1);
        let mut notices = vec![];
        for t in (20..=1000).step_by(20) {
            notices.extend(pod.poll(ms(t), silence, &mut out).iter());
            assert_eq!(photos(&sent(&mut out)), 0, "resent at {t} ms");
        }
        // It waits as long as a setting waits for all its tries (3 x 200 ms).
        assert_eq!(notices, vec![PodNotice::TimedOut { base: 0x0302 }]);
        assert_eq!(out.counters.pod_retries, 0);
        assert!(events(&mut out).contains(&Event::PodTimeout { base: 0x0302 }));
    }

    #[test]
    fn acks_numbered_by_the_pods_own_counter_match_the_oldest_request() {
        let mut pod = PodDriver::new(PodConfig::DEFAULT);
        let mut out = outputs();
        let silence = Duration::from_millis(500);
        pod.command(ms(0), Command::TakePhoto, &mut out);
        pod.command(ms(5), Command::Record(true), &mut out);
        let s = sent(&mut out);
        let photo_seq = s.iter().find(|(_, r)| r.base() == 0x0302).unwrap().0.seq;
        // The pod numbers its ACKs with its own counter: 200, 201 (never the request's).
        for (seq, ack) in [
            (
                200u8,
                from_pod(
                    TakePhotoAck {
                        code: k40t::ResponseCode::OK,
                    },
                    Address::POD,
                    200,
                    CrcCoverage::ExcludeStx,
                ),
            ),
            (
                201,
                from_pod(
                    k40t::RecordAck {
                        code: k40t::ResponseCode::OK,
                    },
                    Address::POD,
                    201,
                    CrcCoverage::ExcludeStx,
                ),
            ),
        ] {
            assert_ne!(seq, photo_seq);
            let n = feed(&mut pod, ms(30), &ack, &mut out);
            assert_eq!(n.len(), 1, "{n:?}");
        }
        assert!(pod.state().is_recording());
        for t in (40..=2000).step_by(20) {
            pod.poll(ms(t), silence, &mut out);
        }
        assert!(sent(&mut out).is_empty());
        assert_eq!(out.counters.pod_retries, 0);
        assert!(
            !events(&mut out)
                .iter()
                .any(|e| matches!(e, Event::PodTimeout { .. }))
        );
    }

    #[test]
    fn a_late_ack_of_a_superseded_request_is_not_taken_for_its_successor() {
        let mut pod = PodDriver::new(PodConfig::DEFAULT);
        let mut out = outputs();
        let silence = Duration::from_millis(500);
        let zoom = |z| Command::ZoomTo { zoom_x10: z };
        pod.command(ms(0), zoom(20), &mut out);
        pod.command(ms(50), zoom(40), &mut out);
        let s = sent(&mut out);
        assert_eq!(s.len(), 2);
        let ack = |seq| {
            from_pod(
                HybridZoomAck {
                    code: k40t::ResponseCode::OK,
                },
                Address::POD,
                seq,
                CrcCoverage::ExcludeStx,
            )
        };
        // The first request's ACK (own counter): absorbed by the superseded request, so
        // the second one is still pending and is retried when its own ACK is lost.
        assert!(feed(&mut pod, ms(60), &ack(77), &mut out).is_empty());
        pod.poll(ms(250), silence, &mut out);
        let s = sent(&mut out);
        assert_eq!(s.len(), 1);
        assert_eq!(
            s[0].1,
            Request::HybridZoom(HybridZoom {
                start: 0,
                zoom_x10: 40
            })
        );
        // Its ACK (exact number, as an echoing pod sends it) ends it.
        let n = feed(&mut pod, ms(260), &ack(s[0].0.seq), &mut out);
        assert_eq!(
            n,
            vec![PodNotice::Acked {
                base: 0x0304,
                code: AckCode::Ok
            }]
        );
    }
}
