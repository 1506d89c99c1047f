//! The flight-controller sides of the bridge, one per FC protocol. Each owns its
//! deframer, decodes what the FC sends, turns commands into [`Command`]s for the pod
//! driver, feeds the time discipline and the fix history, and answers the FC at once
//! from the pod's cached state.

use super::discipline::TimeDiscipline;
use super::event::Event;
use super::fixes::FixHistory;
use super::geotag::Geotagger;
use super::pod::{AckClaim, PodDriver, PodNotice, PodState};
use super::time::Instant;
use super::{Config, Outputs};
use crate::gimbal::Command;
use crate::k40t::{GpsRequest, Header, MsgId};
use crate::wire::Stats;

/// What an FC side may use of the engine during one call.
pub(crate) struct Ctx<'a> {
    /// The local instant of the call.
    pub(crate) now: Instant,
    pub(crate) config: &'a Config,
    pub(crate) pod: &'a mut PodDriver,
    pub(crate) time: &'a mut TimeDiscipline,
    pub(crate) fixes: &'a mut FixHistory,
    pub(crate) geotag: &'a mut Geotagger,
    pub(crate) out: &'a mut Outputs,
    /// Set when a valid FC frame was seen (the FC link is up).
    pub(crate) fc_seen: bool,
}

impl Ctx<'_> {
    /// A valid frame came from the FC.
    pub(crate) fn seen(&mut self) {
        self.fc_seen = true;
        self.out.counters.fc_frames = self.out.counters.fc_frames.saturating_add(1);
    }

    /// A valid FC frame the side could not use.
    pub(crate) fn ignored(&mut self) {
        self.out.counters.fc_ignored = self.out.counters.fc_ignored.saturating_add(1);
    }

    /// Sends `cmd` to the pod; `fc_id` is the FC protocol's id of the command (for the
    /// event). Returns the K40T base id used, `None` when the pod has no equivalent.
    pub(crate) fn command(&mut self, fc_id: u16, cmd: Command) -> Option<u16> {
        let base = self.pod.command(self.now, cmd, self.out)?;
        self.out.event(Event::Translated {
            fc_id,
            pod_base: base,
        });
        Some(base)
    }

    /// Answers the pod's GPS request from the fix history (now, or after the next fix).
    pub(crate) fn geotag(&mut self, header: Header, request: GpsRequest) {
        self.geotag.request(
            self.now, header, request, self.time, self.fixes, self.pod, self.out,
        );
    }

    /// Queues a frame for the FC.
    pub(crate) fn reply(&mut self, frame: &[u8]) -> bool {
        self.out.queue_fc(frame, false)
    }

    /// The pod's state.
    #[cfg_attr(
        not(any(feature = "siyi", feature = "viewlink", feature = "gcu")),
        allow(dead_code)
    )]
    pub(crate) fn pod(&self) -> &PodState {
        self.pod.state()
    }
}

#[cfg(feature = "gcu")]
mod gcu;
mod k40t;
#[cfg(feature = "siyi")]
mod siyi;
#[cfg(feature = "viewlink")]
mod viewlink;

/// The FC side in use.
// One side is in use, fixed at start-up; without an allocator to box it, the enum is as
// large as its largest side (the engine's size is fixed at compile time either way).
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone)]
pub(crate) enum FcSide {
    /// The configured protocol is not compiled in: FC bytes are ignored.
    Disabled,
    /// K40T: forwarding.
    K40t(k40t::K40tSide),
    /// SIYI.
    #[cfg(feature = "siyi")]
    Siyi(siyi::SiyiSide),
    /// Viewlink (Viewpro).
    #[cfg(feature = "viewlink")]
    Viewlink(viewlink::ViewlinkSide),
    /// XF Robot GCU.
    #[cfg(feature = "gcu")]
    Gcu(gcu::GcuSide),
}

/// Calls `$method` on the side in use; `Disabled` gives `$default`.
macro_rules! fc_dispatch {
    ($self:ident, $side:ident => $call:expr, $default:expr) => {
        match $self {
            FcSide::Disabled => $default,
            FcSide::K40t($side) => $call,
            #[cfg(feature = "siyi")]
            FcSide::Siyi($side) => $call,
            #[cfg(feature = "viewlink")]
            FcSide::Viewlink($side) => $call,
            #[cfg(feature = "gcu")]
            FcSide::Gcu($side) => $call,
        }
    };
}

impl FcSide {
    pub(crate) fn new(config: &Config) -> Self {
        match config.fc {
            #[cfg(feature = "siyi")]
            super::FcProtocol::Siyi => {
                FcSide::Siyi(siyi::SiyiSide::new(crate::siyi::DEFAULT_MAX_PAYLOAD_LEN))
            }
            #[cfg(feature = "viewlink")]
            super::FcProtocol::Viewlink => FcSide::Viewlink(viewlink::ViewlinkSide::new()),
            #[cfg(feature = "gcu")]
            super::FcProtocol::Gcu => FcSide::Gcu(gcu::GcuSide::new()),
            super::FcProtocol::K40t => FcSide::K40t(k40t::K40tSide::new(config.fc_silence_stop)),
            #[allow(unreachable_patterns)] // the protocols whose feature is off
            _ => FcSide::Disabled,
        }
    }

    pub(crate) fn receive(&mut self, ctx: &mut Ctx<'_>, bytes: &[u8]) {
        fc_dispatch!(self, side => side.receive(ctx, bytes), {
            let _ = (ctx, bytes);
        });
    }

    pub(crate) fn new_burst(&mut self) {
        fc_dispatch!(self, side => side.new_burst(), {});
    }

    pub(crate) fn idle(&mut self, ctx: &mut Ctx<'_>) {
        fc_dispatch!(self, side => side.idle(ctx), {
            let _ = ctx;
        });
    }

    pub(crate) fn poll(&mut self, ctx: &mut Ctx<'_>) {
        fc_dispatch!(self, side => side.poll(ctx), {
            let _ = ctx;
        });
    }

    pub(crate) fn poll_at(&self) -> Option<Instant> {
        fc_dispatch!(self, side => side.poll_at(), None)
    }

    /// Every valid frame from the pod (the K40T side forwards them); `ack_claimed`: the
    /// frame is an ACK the engine gave to this side (see [`FcSide::ack_claim`]).
    pub(crate) fn pod_frame(
        &mut self,
        ctx: &mut Ctx<'_>,
        bytes: &[u8],
        id: MsgId,
        header: Header,
        ack_claimed: bool,
    ) {
        // Only the K40T side forwards pod frames.
        if let FcSide::K40t(side) = self {
            side.pod_frame(ctx, bytes, id, header, ack_claimed);
        }
    }

    /// This side's claim on a pod ACK (the K40T side: an FC request it forwarded).
    pub(crate) fn ack_claim(&self, now: Instant, base: u16, seq: u8) -> Option<AckClaim> {
        if let FcSide::K40t(side) = self {
            side.ack_claim(now, base, seq)
        } else {
            None
        }
    }

    pub(crate) fn pod_notice(&mut self, ctx: &mut Ctx<'_>, notice: PodNotice) {
        match self {
            #[cfg(feature = "siyi")]
            FcSide::Siyi(side) => side.pod_notice(ctx, notice),
            #[cfg(feature = "viewlink")]
            FcSide::Viewlink(side) => side.pod_notice(ctx, notice),
            #[cfg(feature = "gcu")]
            FcSide::Gcu(side) => side.pod_notice(ctx, notice),
            // The K40T side forwards the ACKs themselves.
            FcSide::K40t(_) | FcSide::Disabled => {
                let _ = (ctx, notice);
            }
        }
    }

    /// The pod asks for GPS: true when this side handles it (the K40T side forwards it
    /// to the FC); else the engine answers from its fix history.
    pub(crate) fn gps_request(
        &mut self,
        ctx: &mut Ctx<'_>,
        header: Header,
        request: GpsRequest,
    ) -> bool {
        // Only the K40T side forwards GPS requests.
        if let FcSide::K40t(side) = self {
            side.gps_request(ctx, header, request)
        } else {
            false
        }
    }

    pub(crate) fn deframer_stats(&self) -> Stats {
        fc_dispatch!(self, side => side.deframer_stats(), Stats::default())
    }
}
