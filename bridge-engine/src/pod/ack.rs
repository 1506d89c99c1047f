//! Matching ACKs: the requests waiting for their ACK ([`Pending`]: retried when
//! idempotent, timed out otherwise), the superseded ones whose late ACK is absorbed
//! ([`Outstanding`]), and the claim an ACK is matched by ([`AckClaim`]).

use super::{Notices, PodDriver, PodNotice, typed};
use crate::Outputs;
use crate::event::Event;
use crate::time::{Duration, Instant};
use protocol_core::k40t::{
    AckCode, CameraVersionAck, Frame, GimbalVersionAck, IpConfigAck, IrParams, LaserDistance,
    RecordAction, RecordState, Request, ResponseCode, ShootAction, TargetGpsAck, Toggle,
    VisibleParams,
};

/// Commands tracked for their ACK at once.
pub(super) const PENDING: usize = 6;
/// Superseded commands whose ACK may still come (absorbed, so that a late ACK is not
/// taken for the command that superseded them).
pub(super) const SUPERSEDED: usize = 4;

/// A command waiting for its ACK.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Pending {
    pub(super) request: Request,
    pub(super) seq: u8,
    /// When it was first sent (ACKs go to the oldest outstanding request).
    pub(super) sent: Instant,
    /// Tries left after the one in flight.
    pub(super) tries_left: u8,
    /// When to send again (or give up).
    pub(super) due: Instant,
}

/// A superseded command whose ACK may still come.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Outstanding {
    pub(super) base: u16,
    pub(super) seq: u8,
    pub(super) sent: Instant,
    /// Forgotten after this.
    pub(super) until: Instant,
}

/// How well an ACK matches an outstanding request: an exact sequence number beats
/// none, then the older request wins (oldest pending first, exact SEQ preferred, never
/// required: see docs/src/bridge/engine.md).
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

impl PodDriver {
    /// Sends a setting or camera action and tracks it for its ACK.
    pub(super) fn send_tracked(&mut self, now: Instant, request: Request, out: &mut Outputs) {
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

    pub(super) fn on_ack(
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
        } else if let Some(p) = typed::<IrParams>(frame).filter(|_| code == AckCode::Ok) {
            self.state.ir_params = Some(p);
        } else if let Some(p) = typed::<VisibleParams>(frame).filter(|_| code == AckCode::Ok) {
            self.state.visible_params = Some(p);
        } else if let Some(ip) = typed::<IpConfigAck>(frame) {
            self.ip_answered(ip.code.code(), ip.address, out);
        } else if let Some(t) = typed::<TargetGpsAck>(frame) {
            self.target_answered(now, t);
        }
        let acked = if claimed {
            self.take_outstanding(now, base, seq)
        } else {
            None
        };
        if let Some(request) = acked {
            self.sensor_acked(request, code);
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
}
