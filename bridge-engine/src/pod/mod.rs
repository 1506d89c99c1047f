//! The K40T pod driver: the bridge acts as the flight controller (0x02/0x01).
//!
//! - **Commands.** A [`Command`](crate::gimbal::Command) becomes one or two K40T
//!   requests. Settings and camera actions are tracked for their ACK. Idempotent ones
//!   (settings, absolute zoom, record start/stop, focus, views) are sent again when their
//!   ACK does not come ([`PodConfig::tries`], [`PodConfig::retry_interval`]); a newer
//!   command with the same base id supersedes a pending one. An action that counts (take
//!   photo, burst, time-lapse, single laser ranging) is **never sent twice for one FC
//!   command**: if its ACK does not come within the time the others get for all their
//!   tries, it is reported as timed out (the FC sides tell the FC it failed) rather than
//!   risk a second shot. Motion commands (0x000010, 0x000012, 0x000017) are never
//!   retried: the next one supersedes them.
//! - **Matching ACKs** (see docs/src/bridge/engine.md): the K40T document has every
//!   component number the frames *it* sends (K40T external protocol, 2.1, SEQ), so a
//!   pod's ACK may carry the pod's own counter rather than the request's SEQ. An ACK is
//!   matched to the oldest outstanding request with the same base id, an exact SEQ match
//!   preferred but never required. A superseded request stays outstanding (not retried)
//!   so that its late ACK is not taken for its successor's.
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

mod ack;
mod command;
mod motion;
mod sensors;
#[cfg(feature = "mavlink")]
mod settings;
mod state;
#[cfg(test)]
mod tests;

pub(crate) use ack::AckClaim;
pub use state::PodState;

use super::Outputs;
use super::config::PodConfig;
use super::event::Event;
use super::time::{Duration, Instant};
use ack::{Outstanding, PENDING, Pending, SUPERSEDED};
use motion::{MotionState, MotionTarget};
use protocol_core::k40t::{
    self, AckCode, Address, CameraVersionQuery, CrcCoverage, FormatStatus, Frame, GimbalAttitude,
    GimbalStatus, GimbalVersionQuery, GpsReply, GpsRequest, Header, IrStatus, Kind,
    LaserPeriodicStatus, MessageData, PhotoState, PhotoStatus, RecordStatus, Request, SystemStatus,
    TimeSync, UpgradeStatus, VisibleStatus, ZoomStatus,
};

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
    /// A photo status frame (0x020302: a series in progress, a photo taken or failed).
    Photo(PhotoState),
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
    /// When to ask the pod's IP address again (its last query got no answer).
    ip_retry: Option<Instant>,
    /// Which of the pod's destructive requests an FC command may become.
    allow: crate::access::K40tAllow,
}

impl PodDriver {
    /// The driver with `allow` as the destructive requests FC commands may become (the
    /// default: none).
    pub(crate) const fn with_allow(mut self, allow: crate::access::K40tAllow) -> Self {
        self.allow = allow;
        self
    }

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
                ir_params: None,
                visible_params: None,
                format: None,
                ip: None,
                track: None,
                target: None,
                ir_zoom: None,
                ir_first: None,
            },
            ip_retry: None,
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
            allow: crate::access::K40tAllow::NONE,
        }
    }

    /// The settings the driver holds that apply live: the pod's axis conventions and
    /// the destructive requests FC commands may become.
    pub(crate) fn set_live(&mut self, pod: &PodConfig, allow: crate::access::K40tAllow) {
        self.cfg.yaw_positive_left = pod.yaw_positive_left;
        self.cfg.pitch_positive_down = pod.pitch_positive_down;
        self.allow = allow;
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
                if let Some(state) = self.on_status(now, frame) {
                    notices.push(PodNotice::Photo(state));
                }
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
                // Versions and the IP address, on every (re)connection.
                self.query_versions(now, out);
                self.query_ip(now, out);
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
            self.state.ir_first = self.state.ir_first.or(Some(now));
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

    /// A status frame into the state; a photo status is also returned (the camera
    /// counts photos by them).
    fn on_status(&mut self, now: Instant, frame: &Frame<&[u8]>) -> Option<PhotoState> {
        if let Some(p) = typed::<PhotoStatus>(frame) {
            self.state.photo = Some(p.state);
            return Some(p.state);
        } else if let Some(r) = typed::<RecordStatus>(frame) {
            self.state.recording = Some(r.state);
        } else if let Some(z) = typed::<ZoomStatus>(frame) {
            self.state.zoom = Some(z.state);
        } else if let Some(d) = typed::<LaserPeriodicStatus>(frame) {
            self.state.laser_dm = Some((d.0.distance_dm, now));
        } else if let Some(f) = typed::<FormatStatus>(frame) {
            self.state.format = Some(f.state);
        }
        None
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
            // What the pod may have forgotten (a reboot): asked again or re-learnt.
            self.state.ai = false;
            self.state.track = None;
            self.state.ranging = false;
            self.state.ir_first = None;
            self.ip_retry = None;
            notices.push(PodNotice::LinkDown);
        }
        if self.state.link && self.ip_retry.is_some_and(|t| now >= t) {
            self.query_ip(now, out);
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
        if let Some(t) = self.ip_retry.filter(|_| self.state.link) {
            consider(t);
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

/// The frame's payload as `M` when it carries `M` and decodes; `None` otherwise. The
/// driver decodes only the messages it uses, one layout each, so the firmware does not
/// carry the decoders of the hundred others (`Frame::decode_as`).
pub(super) fn typed<M: MessageData<Protocol = protocol_core::k40t::K40t>>(
    frame: &Frame<&[u8]>,
) -> Option<M> {
    frame.decode_as::<M>().and_then(Result::ok)
}
