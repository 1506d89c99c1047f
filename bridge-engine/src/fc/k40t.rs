//! The K40T side: the flight controller speaks the pod's own protocol; the bridge
//! forwards both ways and owns RTC_IO.
//!
//! - **Forwarding.** Every valid FC frame goes to the pod with its message bytes
//!   unchanged (no decoding and re-encoding: unknown messages pass too), but a frame of
//!   any kind whose base id is one of the pod's destructive requests not in `k40t_allow`
//!   (docs/src/security.md); every valid pod frame goes to the FC unchanged.
//! - **Sequence numbers stay consistent on the pod link.** The bridge sends frames of
//!   its own to the pod as the flight controller (time syncs, version probes, GPS
//!   answers), so it numbers every frame it sends there from one counter: a forwarded FC
//!   frame gets the next sequence number (and its CRC, in the frame's own coverage, is
//!   computed again). A pod's ACK carries that number or (as the K40T document has each
//!   component number its own frames: K40T external protocol, 2.1) the pod's own
//!   counter: it is matched to the oldest forwarded request of its base id, an exact
//!   number preferred, never required (see docs/src/bridge/k40t.md), and the bridge gives
//!   it the FC's own number before forwarding it. ACKs of the bridge's own frames are not
//!   forwarded.
//! - **RTC_IO.** The FC's 0x00030E is not forwarded: it is a UTC sample for the
//!   discipline (the FC sends it right after its own pulse, which is not wired to the
//!   pod), ACKed by the bridge; the bridge sends its own pulse and 0x00030E.
//! - **Geotag.** The pod's GPS request (0x000310) is forwarded; the FC's answer
//!   (0x010310) is forwarded and becomes a fix of the history. When the FC has not
//!   answered within [`Config::k40t_geotag_fallback`](crate::Config) (200 ms),
//!   the bridge answers from its fix history (or with the failure code).
//! - **FC silence.** When the FC's last motion command (0x000010) turns the pod and the
//!   FC sends nothing for [`Config::fc_silence_stop`](crate::Config), the bridge
//!   stops the pod.

use super::{Ctx, FcHandler, PodFrame, TimedFrom};
use crate::discipline::Sample;
use crate::fixes::Fix;
use crate::gimbal::Command;
use crate::pod::AckClaim;
use crate::time::{Duration, Instant};
use protocol_core::k40t::{
    self, Frame, GimbalControl, GpsReply, GpsRequest, Header, K40tFraming, Kind, MessageData,
    PitchMotion, ResponseCode, TimeSync, YawMotion,
};

/// FC sequence numbers remembered for the ACKs of forwarded requests.
const SEQ_MAP: usize = 8;
/// A forwarded request whose ACK has not come within this time gets none: its entry no
/// longer claims ACKs (a later ACK of the same base belongs to a later request).
const ACK_WAIT: Duration = Duration::from_secs(1);

/// A forwarded request: the base id, the number the pod sees and the FC's own.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Forwarded {
    base: u16,
    pod_seq: u8,
    fc_seq: u8,
    /// When it was forwarded (an ACK goes to the oldest).
    sent: Instant,
}

/// A GPS request of the pod, forwarded to the FC and not yet answered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct GpsPending {
    header: Header,
    request: GpsRequest,
    /// When the bridge answers it itself.
    due: Instant,
}

/// The K40T side.
#[derive(Debug, Clone)]
pub(crate) struct K40tSide {
    /// [`Config::fc_silence_stop`](crate::Config), for `poll_at`.
    silence: Duration,
    forwarded: [Option<Forwarded>; SEQ_MAP],
    next_slot: usize,
    gps: Option<GpsPending>,
    /// The FC's last motion turns the pod.
    turning: bool,
    last_frame: Option<Instant>,
}

impl K40tSide {
    pub(crate) fn new(silence: Duration) -> Self {
        K40tSide {
            silence,
            forwarded: [None; SEQ_MAP],
            next_slot: 0,
            gps: None,
            turning: false,
            last_frame: None,
        }
    }
}

impl FcHandler for K40tSide {
    type Framing = K40tFraming;
    const TIMED_FROM: TimedFrom = TimedFrom::Frame;

    fn frame(&mut self, ctx: &mut Ctx<'_>, f: &[u8]) {
        self.fc_frame(ctx, f);
    }

    fn poll(&mut self, ctx: &mut Ctx<'_>) {
        if let Some(g) = self.gps.filter(|g| ctx.now >= g.due) {
            self.gps = None;
            ctx.geotag(g.header, g.request);
        }
        let silent = self
            .last_frame
            .is_none_or(|t| ctx.now.saturating_duration_since(t) >= ctx.config.fc_silence_stop);
        if self.turning && silent {
            self.turning = false;
            ctx.command(
                0x0010,
                Command::Rates {
                    yaw_cdeg_s: 0,
                    pitch_cdeg_s: 0,
                },
            );
            ctx.out.event(crate::Event::FcSilenceStop);
        }
    }

    fn poll_at(&self) -> Option<Instant> {
        let gps = self.gps.map(|g| g.due);
        let stop = self
            .last_frame
            .filter(|_| self.turning)
            .map(|t| t.saturating_add(self.silence));
        gps.into_iter().chain(stop).min()
    }

    /// A valid pod frame: forwarded to the FC; an ACK only when the engine gave it to
    /// this side, with the FC's own number.
    fn pod_frame(&mut self, ctx: &mut Ctx<'_>, frame: PodFrame<'_>) {
        let PodFrame {
            bytes,
            id,
            header,
            ack_claimed,
        } = frame;
        if id.kind == Kind::Ack {
            // Not claimed: the ACK of one of the bridge's own frames, not forwarded.
            if !ack_claimed {
                return;
            }
            let Some(claim) = self.ack_claim(ctx.now, id.base, header.seq) else {
                return;
            };
            let found = self.forwarded.iter_mut().find(|f| {
                f.is_some_and(|f| {
                    f.base == id.base
                        && f.sent == claim.sent
                        && (!claim.exact || f.pod_seq == header.seq)
                })
            });
            if let Some(slot) = found {
                let fc_seq = slot.map_or(0, |f| f.fc_seq);
                *slot = None;
                forward_with_seq(bytes, fc_seq, |f| ctx.reply(f));
            }
            return;
        }
        ctx.reply(bytes);
    }

    /// The claim of the FC's forwarded requests on a pod ACK of `base` carrying `seq`.
    fn ack_claim(&self, now: Instant, base: u16, seq: u8) -> Option<AckClaim> {
        self.forwarded
            .iter()
            .flatten()
            .filter(|f| f.base == base && now.saturating_duration_since(f.sent) <= ACK_WAIT)
            .map(|f| AckClaim {
                exact: f.pod_seq == seq,
                sent: f.sent,
            })
            .fold(None, |best, c| AckClaim::best(best, Some(c)))
    }

    /// The pod asks for GPS: forwarded to the FC, answered by the bridge on time-out.
    fn gps_request(&mut self, ctx: &mut Ctx<'_>, header: Header, request: GpsRequest) -> bool {
        // The frame itself was forwarded by `pod_frame`.
        self.gps = ctx.config.k40t_geotag_fallback.map(|wait| GpsPending {
            header,
            request,
            due: ctx.now.saturating_add(wait),
        });
        true
    }
}

impl K40tSide {
    /// One valid frame from the FC.
    fn fc_frame(&mut self, ctx: &mut Ctx<'_>, f: &[u8]) {
        ctx.seen();
        self.last_frame = Some(ctx.now);
        let Some((frame, header)) = Frame::new_checked(f)
            .ok()
            .and_then(|frame| frame.header().map(|header| (frame, header)))
        else {
            ctx.ignored();
            return;
        };
        // Only the three messages the side acts on are decoded; every other valid frame
        // is forwarded as it is (the pod judges its payload).
        if let Some(t) = typed::<TimeSync>(&frame) {
            Self::time_sync(ctx, t, header);
            return;
        }
        if let Some(c) = typed::<GimbalControl>(&frame) {
            self.turning = turns(c);
        }
        if let Some(reply) = typed::<GpsReply>(&frame) {
            self.gps_reply(ctx, reply);
        }
        let id = frame.id();
        if !ctx.config.k40t_allow.allows(id.base) {
            // A frame of one of the pod's destructive requests' base ids, not in
            // `k40t_allow`, whatever its kind (a request, an ACK, a status or a kind the
            // document does not name: the pod's firmware may act on any of them): never
            // forwarded; a request is answered with the document's failure ACK
            // (docs/src/security.md).
            ctx.refuse(crate::access::Refusal::Guarded, id.to_u32(), (0, 0));
            if id.kind == Kind::Request {
                refusal_ack(&frame, header, |ack| ctx.reply(ack));
            }
            return;
        }
        if id.kind != Kind::Request {
            // An ACK of a pod request (0x010310): it carries the pod's own number.
            ctx.out.queue_pod(f, true, false);
            return;
        }
        // A request: forwarded with the bridge's sequence number on the pod link.
        let pod_seq = ctx.pod.next_seq();
        let slot = self.next_slot % SEQ_MAP;
        self.next_slot = self.next_slot.wrapping_add(1);
        if let Some(s) = self.forwarded.get_mut(slot) {
            *s = Some(Forwarded {
                base: id.base,
                pod_seq,
                fc_seq: header.seq,
                sent: ctx.now,
            });
        }
        forward_with_seq(f, pod_seq, |out| ctx.out.queue_pod(out, false, false));
        ctx.out.event(crate::Event::Translated {
            fc_id: id.base,
            pod_base: id.base,
        });
    }

    /// The FC's time sync: a UTC sample, ACKed by the bridge, not forwarded.
    fn time_sync(ctx: &mut Ctx<'_>, t: TimeSync, header: Header) {
        // The FC sends it at once after its own RTC_IO edge (the document's procedure):
        // one is enough for a first mapping.
        let s = Sample::new(ctx.now, t.unix_ms.saturating_mul(1000), 1000)
            .with_transit(ctx.transit)
            .prompt();
        if ctx.feeds {
            ctx.time.utc_sample(s);
        }
        let ack = k40t::TimeSyncAck {
            code: ResponseCode::OK,
        };
        let reply = Header {
            dst: header.src,
            src: header.dst,
            ..header
        };
        let mut buf = [0u8; k40t::MAX_FRAME_LEN];
        if let Ok(n) = k40t::encode(&ack, &reply, &mut buf) {
            ctx.reply(buf.get(..n).unwrap_or_default());
        }
    }

    /// The FC answers the pod's GPS request: the answer is a fix, and the request is no
    /// longer pending.
    fn gps_reply(&mut self, ctx: &mut Ctx<'_>, reply: GpsReply) {
        // One request waits at a time: the FC's reply answers it, whatever its SEQ (the
        // FC may number its replies with its own counter, as the document reads).
        self.gps = None;
        if !reply.code.is_ok() {
            return;
        }
        let asked =
            crate::time::TimeOfDay::new(reply.hour, reply.minute, reply.second, reply.millisecond);
        let at = asked
            .and_then(|tod| ctx.time.utc(ctx.now)?.nearest_with_time_of_day(tod))
            .and_then(|utc| ctx.time.local_of(utc));
        if let Some(at) = at {
            ctx.push_fix(Fix {
                at,
                lat_e7: reply.lat_e7,
                lon_e7: reply.lon_e7,
                alt_msl_dm: reply.alt_msl_dm,
                rel_alt_dm: reply.rel_alt_dm,
                yaw_cdeg: reply.yaw_cdeg,
                roll_cdeg: reply.roll_cdeg,
                pitch_cdeg: reply.pitch_cdeg,
                // The K40T reply carries none: the history derives it from the fixes.
                velocity: None,
            });
        }
    }
}

/// Hands `out` the ACK of `request` (from its addressee, to its sender, with its
/// sequence number and CRC coverage) carrying the failure code 0x0001 (K40T external
/// protocol, table 3.3).
fn refusal_ack(request: &Frame<&[u8]>, header: Header, out: impl FnOnce(&[u8]) -> bool) {
    const CODE: [u8; 2] = k40t::ResponseCode::new(k40t::AckCode::Failure).raw;
    let mut buf = [0u8; k40t::MIN_FRAME_LEN + CODE.len()];
    let mut ack = Frame::new_unchecked(buf.as_mut_slice());
    ack.set_start(2);
    ack.set_dst(header.src);
    ack.set_src(header.dst);
    ack.set_seq(header.seq);
    ack.set_id(k40t::MsgId::new(Kind::Ack, request.id().base));
    protocol_core::wire::copy(ack.payload_mut(), &CODE);
    ack.fill_checksum(request.detect_coverage().unwrap_or_default());
    out(&buf);
}

/// A motion command that turns the gimbal.
fn turns(c: GimbalControl) -> bool {
    c.yaw != YawMotion::Stop || c.pitch != PitchMotion::Stop
}

/// Hands `f` to `out` with its sequence number set to `seq` and its CRC computed again
/// in the frame's own coverage.
fn forward_with_seq(f: &[u8], seq: u8, out: impl FnOnce(&[u8]) -> bool) {
    let mut buf = [0u8; k40t::MAX_FRAME_LEN];
    let Some(dst) = buf.get_mut(..f.len()) else {
        return;
    };
    protocol_core::wire::copy(dst, f);
    let mut frame = Frame::new_unchecked(&mut *dst);
    let coverage = Frame::new_unchecked(f)
        .detect_coverage()
        .unwrap_or_default();
    frame.set_seq(seq);
    frame.fill_checksum(coverage);
    out(dst);
}

/// The frame's payload as `M` when it carries `M` and decodes.
fn typed<M: MessageData<Protocol = protocol_core::k40t::K40t>>(frame: &Frame<&[u8]>) -> Option<M> {
    frame.decode_as::<M>().and_then(Result::ok)
}
