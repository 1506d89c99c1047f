//! The flight-controller sides of the bridge, one per FC protocol.
//!
//! Every side has the same shape: an [`FcLink`] owns what a serial FC link needs whatever
//! its protocol (the protocol's deframer, the FC's bursts and each frame's serial
//! time), and hands each valid frame to the side's [`FcHandler`], which holds only its
//! protocol's decisions: it decodes the frame, turns commands into [`Command`]s for the
//! pod driver, feeds the time discipline and the fix history, and answers the FC at once
//! from the pod's cached state. The handler's other methods (periodic work, pod notices,
//! pod frames, GPS requests, ACK claims) default to nothing.

use super::discipline::{TimeDiscipline, serial_time};
use super::event::Event;
use super::fixes::{Fix, FixHistory, Velocity};
use super::geotag::Geotagger;
use super::pod::{AckClaim, PodDriver, PodNotice, PodState};
use super::time::{Duration, Instant};
use super::{Config, Outputs};
use crate::gimbal::Command;
use protocol_core::k40t::{GimbalAttitude, GpsRequest, Header, MsgId};
use protocol_core::wire::{Deframer, Event as DeframerEvent, Framing, Stats};

/// What an FC side may use of the engine during one call.
pub(crate) struct Ctx<'a> {
    /// The local instant of the call.
    pub(crate) now: Instant,
    pub(crate) config: &'a Config,
    /// What this image is (the version replies; the K40T side has none).
    #[cfg_attr(
        not(any(
            feature = "siyi",
            feature = "viewlink",
            feature = "gcu",
            feature = "mavlink"
        )),
        allow(dead_code)
    )]
    pub(crate) build: &'a crate::BuildInfo,
    pub(crate) pod: &'a mut PodDriver,
    pub(crate) time: &'a mut TimeDiscipline,
    pub(crate) fixes: &'a mut FixHistory,
    pub(crate) geotag: &'a mut Geotagger,
    pub(crate) out: &'a mut Outputs,
    /// The settings (the parameter protocol sets them).
    #[cfg_attr(not(feature = "mavlink"), allow(dead_code))]
    pub(crate) settings: &'a mut crate::settings::Settings,
    /// Set when a valid FC frame was seen (the FC link is up).
    pub(crate) fc_seen: bool,
    /// The serial time from the first byte written after the FC read the current frame's
    /// values (its burst's or its own, [`FcHandler::TIMED_FROM`]) to `now`, set by
    /// [`FcLink`] for each frame: the least transit of a time value in it.
    pub(crate) transit: Duration,
    /// The link's baud rate (frames' serial times).
    pub(crate) baud: u32,
    /// The link this side answers on ([`Ctx::reply`]): the FC's, or the telemetry link.
    pub(crate) to: super::Port,
    /// This link is the source of UTC and fixes: feed [`Ctx::time`] and [`Ctx::fixes`]
    /// only when set (a SIYI, Viewlink, GCU or K40T side stops while a telemetry link
    /// gives them; the telemetry link feeds only while it does).
    pub(crate) feeds: bool,
}

impl Ctx<'_> {
    /// A valid frame came from the FC.
    pub(crate) fn seen(&mut self) {
        if self.to == super::Port::Telemetry {
            let n = &mut self.out.counters.telemetry_frames;
            *n = n.saturating_add(1);
            return;
        }
        self.fc_seen = true;
        self.out.counters.fc_frames = self.out.counters.fc_frames.saturating_add(1);
    }

    /// A valid FC frame the side could not use.
    pub(crate) fn ignored(&mut self) {
        if self.to == super::Port::Telemetry {
            return;
        }
        self.out.counters.fc_ignored = self.out.counters.fc_ignored.saturating_add(1);
    }

    /// Refuses a frame or command of `id` from `from` (MAVLink system and component;
    /// K40T: 0, 0): counted by `reason`, reported at most once per reason and stream a
    /// second (see `Outputs::refuse`).
    pub(crate) fn refuse(&mut self, reason: crate::access::Refusal, id: u32, from: (u8, u8)) {
        self.out.refuse(self.now, self.to, reason, id, from);
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

    /// Nothing is queued for this side's link: a frame queued now goes out at once.
    #[cfg_attr(not(feature = "mavlink"), allow(dead_code))]
    pub(crate) fn link_idle(&self) -> bool {
        match self.to {
            super::Port::Telemetry => self.out.tel.front().is_none(),
            super::Port::Fc | super::Port::Pod => self.out.fc.front().is_none(),
        }
    }

    /// Puts `fix` in the history when this link feeds it ([`Ctx::feeds`]).
    pub(crate) fn push_fix(&mut self, fix: Fix) {
        if self.feeds {
            self.fixes.push(fix);
        }
    }

    /// Queues a frame for the link this side serves ([`Ctx::to`]).
    pub(crate) fn reply(&mut self, frame: &[u8]) -> bool {
        self.out.queue_to(self.to, frame)
    }

    /// The pod's state.
    #[cfg_attr(
        not(any(feature = "siyi", feature = "viewlink", feature = "gcu")),
        allow(dead_code)
    )]
    pub(crate) fn pod(&self) -> &PodState {
        self.pod.state()
    }

    /// The pod's attitude when it reports and the report is at most
    /// [`ATTITUDE_FRESH`] old (`None` while the pod is lost or silent: a gimbal whose
    /// attitude stopped).
    #[cfg_attr(
        not(any(feature = "siyi", feature = "viewlink", feature = "gcu")),
        allow(dead_code)
    )]
    pub(crate) fn fresh_attitude(&self) -> Option<GimbalAttitude> {
        let pod = self.pod();
        let (a, at) = pod.attitude.filter(|_| pod.link)?;
        (self.now.saturating_duration_since(at) <= ATTITUDE_FRESH).then_some(a)
    }

    /// A reading of the pod (laser distance, thermal measurement) taken at `at` is at most
    /// [`READING_FRESH`] old.
    #[cfg_attr(
        not(any(feature = "siyi", feature = "viewlink", feature = "gcu")),
        allow(dead_code)
    )]
    pub(crate) fn is_fresh(&self, at: Instant) -> bool {
        self.now.saturating_duration_since(at) <= READING_FRESH
    }
}

/// The pod's attitude older than this is not reported to the FC (the pod reports it at
/// 10 Hz).
pub(crate) const ATTITUDE_FRESH: Duration = Duration::from_millis(500);
/// Thermal and laser readings older than this are not reported.
pub(crate) const READING_FRESH: Duration = Duration::from_secs(1);

/// A quiet FC line for longer than this before bytes starts a new burst (ArduPilot's
/// drivers leave 10 ms or more between their bursts; the firmware reports a line idle
/// after 20 byte times, at least 5 ms). See [`FcLink::receive`].
const BURST_GAP: Duration = Duration::from_millis(5);

/// An `i32` saturated to `i16`.
#[cfg_attr(
    not(any(feature = "siyi", feature = "viewlink", feature = "gcu")),
    allow(dead_code)
)]
pub(crate) fn clamp_i16(v: i32) -> i16 {
    i16::try_from(v).unwrap_or(if v < 0 { i16::MIN } else { i16::MAX })
}

/// A valid frame from the pod, as an FC side sees it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PodFrame<'a> {
    /// The whole frame.
    pub(crate) bytes: &'a [u8],
    /// Its message id.
    pub(crate) id: MsgId,
    /// Its header.
    pub(crate) header: Header,
    /// The frame is an ACK the engine gave to this side (see [`FcHandler::ack_claim`]).
    pub(crate) ack_claimed: bool,
}

/// The relative altitude of fixes from FCs that send no home altitude (SIYI, Viewlink):
/// above the first MSL altitude received.
#[derive(Debug, Clone, Copy, Default)]
#[cfg_attr(not(any(feature = "siyi", feature = "viewlink")), allow(dead_code))]
pub(crate) struct Home {
    msl_dm: Option<i32>,
}

#[cfg_attr(not(any(feature = "siyi", feature = "viewlink")), allow(dead_code))]
impl Home {
    /// A fix at `at` from a position with its MSL altitude (0.1 m), the aircraft's roll,
    /// pitch and yaw (0.01°) and its velocity.
    pub(crate) fn fix(
        &mut self,
        at: Instant,
        (lat_e7, lon_e7, msl_dm): (i32, i32, i32),
        [roll, pitch, yaw]: [i16; 3],
        velocity: Velocity,
    ) -> Fix {
        let home = *self.msl_dm.get_or_insert(msl_dm);
        Fix {
            at,
            lat_e7,
            lon_e7,
            alt_msl_dm: clamp_i16(msl_dm),
            rel_alt_dm: clamp_i16(msl_dm.saturating_sub(home)),
            yaw_cdeg: yaw,
            roll_cdeg: roll,
            pitch_cdeg: pitch,
            velocity: Some(velocity),
        }
    }
}

/// The decisions of one FC protocol, over the [`FcLink`] that finds its frames.
pub(crate) trait FcHandler {
    /// The protocol's framing.
    type Framing: Framing;

    /// Where the FC read the values of a frame: at its burst's first byte (the FC writes
    /// all the frames of one update at once, as `AP_Mount_Siyi` and `AP_Mount_Viewpro`
    /// do: the UART's buffer then sends them back to back), or at the frame's own first
    /// byte (one frame per update, or one written after an event: `AP_Mount_XFRobot`, a
    /// K40T FC's 0x00030E after its edge). See [`Ctx::transit`].
    const TIMED_FROM: TimedFrom;

    /// One valid frame from the FC; [`Ctx::transit`] is its serial time as
    /// [`FcHandler::TIMED_FROM`] says.
    fn frame(&mut self, ctx: &mut Ctx<'_>, frame: &[u8]);

    /// The FC starts a new burst (the line went idle, or was quiet, before these bytes).
    fn burst_started(&mut self) {}

    /// Periodic work due at `ctx.now`.
    fn poll(&mut self, ctx: &mut Ctx<'_>) {
        let _ = ctx;
    }

    /// When [`FcHandler::poll`] has work (`None`: only on input).
    fn poll_at(&self) -> Option<Instant> {
        None
    }

    /// A notice of the pod driver (link, ACKs, time-outs).
    fn pod_notice(&mut self, ctx: &mut Ctx<'_>, notice: PodNotice) {
        let _ = (ctx, notice);
    }

    /// Every valid frame from the pod. Only a side that forwards needs it.
    fn pod_frame(&mut self, ctx: &mut Ctx<'_>, frame: PodFrame<'_>) {
        let _ = (ctx, frame);
    }

    /// This side's claim on a pod ACK (requests it forwarded for the FC).
    fn ack_claim(&self, now: Instant, base: u16, seq: u8) -> Option<AckClaim> {
        let _ = (now, base, seq);
        None
    }

    /// The pod asks for GPS: true when this side handles it (the K40T side forwards it to
    /// the FC); else the engine answers from its fix history.
    fn gps_request(&mut self, ctx: &mut Ctx<'_>, header: Header, request: GpsRequest) -> bool {
        let _ = (ctx, header, request);
        false
    }
}

/// The first byte written after an FC read the values of a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum TimedFrom {
    /// The first byte of the frame's burst.
    #[cfg_attr(
        not(any(feature = "siyi", feature = "viewlink")),
        allow(
            dead_code,
            reason = "only the SIYI and Viewlink sides time from the burst"
        )
    )]
    Burst,
    /// The frame's own first byte. Never early: a frame queued behind others (an FC loop
    /// overrun, a USB-serial adapter or a host that froze, then the backlog back to back)
    /// was read after its burst began, and timed from the burst it would look early,
    /// which the discipline's minimum-delay filter trusts.
    Frame,
}

/// What every serial FC link has, whatever its protocol: the protocol's deframer (`N`
/// bytes) and the FC's bursts, over the side's [`FcHandler`].
///
/// Bursts are decided here and nowhere else, by one rule ([`FcLink::receive`]): bytes
/// start a new burst when the line was idle before them, because the caller said so
/// ([`FcLink::idle`], its UART's idle detection: an input, not a rule of its own) or
/// because they came more than [`BURST_GAP`] after the last bytes.
#[derive(Debug, Clone)]
pub(crate) struct FcLink<H: FcHandler, const N: usize> {
    deframer: Deframer<H::Framing, N>,
    /// When the last bytes arrived; `None` before any and after the caller's idle.
    last_rx: Option<Instant>,
    /// Bytes received since the current burst began.
    burst_bytes: u32,
    pub(crate) handler: H,
}

impl<H: FcHandler, const N: usize> FcLink<H, N> {
    fn new(framing: H::Framing, handler: H) -> Self {
        FcLink {
            deframer: Deframer::new(framing),
            last_rx: None,
            burst_bytes: 0,
            handler,
        }
    }

    /// Bytes from the FC, the last of them arriving at `ctx.now`. They start a new burst
    /// when the line was idle before them: the caller said so, or (when its idle signal
    /// did not come: a late thread, a busy host, a UART without idle detection) the line
    /// was quiet for over [`BURST_GAP`] before their first byte.
    pub(crate) fn receive(&mut self, ctx: &mut Ctx<'_>, bytes: &[u8]) {
        let n = u32::try_from(bytes.len()).unwrap_or(u32::MAX);
        let first_byte = ctx.now.saturating_sub(serial_time(n, ctx.baud));
        if self.last_rx.is_none_or(|last| {
            last.checked_add(BURST_GAP)
                .is_some_and(|quiet_until| first_byte > quiet_until)
        }) {
            self.burst_bytes = 0;
            self.handler.burst_started();
        }
        self.last_rx = Some(ctx.now);
        self.burst_bytes = self.burst_bytes.saturating_add(n);
        let burst_bytes = self.burst_bytes;
        let handler = &mut self.handler;
        self.deframer.push_counting_after(bytes, |ev, after| {
            if let DeframerEvent::Frame(f) = ev {
                // The frame (or its burst) and what came after it in this reception came
                // at most at the line's rate: its first byte arrived at least their
                // serial time before `ctx.now`.
                let bytes = match H::TIMED_FROM {
                    TimedFrom::Burst => burst_bytes,
                    TimedFrom::Frame => {
                        u32::try_from(f.len().saturating_add(after)).unwrap_or(u32::MAX)
                    }
                };
                ctx.transit = serial_time(bytes, ctx.baud);
                handler.frame(ctx, f);
            }
        });
    }

    /// The FC line has gone idle: frames are complete, the burst is over (the next bytes
    /// start one, [`FcLink::receive`]).
    pub(crate) fn idle(&mut self, ctx: &mut Ctx<'_>) {
        let burst_bytes = self.burst_bytes;
        let handler = &mut self.handler;
        self.deframer.flush(|ev| {
            if let DeframerEvent::Frame(f) = ev {
                // Completed by the idle, its last byte came at least the idle time ago:
                // its own serial time (or its burst's) only makes it look later.
                let bytes = match H::TIMED_FROM {
                    TimedFrom::Burst => burst_bytes,
                    TimedFrom::Frame => u32::try_from(f.len()).unwrap_or(u32::MAX),
                };
                ctx.transit = serial_time(bytes, ctx.baud);
                handler.frame(ctx, f);
            }
        });
        self.last_rx = None;
    }
}

#[cfg(feature = "gcu")]
mod gcu;
#[cfg(any(feature = "mavlink", feature = "gcu"))]
mod geo;
mod k40t;
#[cfg(any(feature = "mavlink", feature = "gcu"))]
mod math;
#[cfg(feature = "mavlink")]
mod mavlink;
#[cfg(feature = "siyi")]
mod siyi;
#[cfg(feature = "viewlink")]
mod viewlink;

#[cfg(feature = "mavlink")]
pub(crate) use mavlink::LinkSigning;

/// Without the MAVLink links there is no signing ([`FcSide::link_signing`] is `None`).
#[cfg(not(feature = "mavlink"))]
pub(crate) enum LinkSigning {}

#[cfg(not(feature = "mavlink"))]
impl LinkSigning {
    pub(crate) fn restore_missing(&mut self) -> bool {
        match *self {}
    }
    pub(crate) fn restore_timestamp(&mut self, _: &[u8]) -> Result<(), crate::store::Problem> {
        match *self {}
    }
    pub(crate) fn restore_key(&mut self, _: &[u8]) -> Result<(), crate::store::Problem> {
        match *self {}
    }
    pub(crate) fn record(&self, _: crate::store::Key) -> crate::store::Record {
        match *self {}
    }
}

/// The MAVLink telemetry link beside another FC side.
#[cfg(feature = "telemetry")]
pub(crate) type TelemetryLink = FcLink<mavlink::TelemetrySide, { mavlink::BUF }>;

#[cfg(feature = "telemetry")]
impl TelemetryLink {
    /// The link, beside any FC side: beside the MAVLink side too, whose own link may give
    /// no time or fixes (PX4 1.16 in mode Gimbal); signed as `config` says.
    pub(crate) fn telemetry(config: &Config) -> Self {
        FcLink::new(
            protocol_core::mavlink::MavlinkFraming::new(),
            mavlink::TelemetrySide::new(config),
        )
    }
}

/// The FC side in use.
// One side is in use, fixed at start-up; without an allocator to box it, the enum is as
// large as its largest side (the engine's size is fixed at compile time either way).
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone)]
pub(crate) enum FcSide {
    /// The configured protocol is not compiled in: FC bytes are ignored.
    Disabled,
    /// K40T: forwarding.
    K40t(FcLink<k40t::K40tSide, { protocol_core::k40t::MAX_FRAME_LEN }>),
    /// SIYI: the bridge as a ZT30 towards `AP_Mount_Siyi`.
    #[cfg(feature = "siyi")]
    Siyi(FcLink<siyi::SiyiSide, { siyi::BUF }>),
    /// Viewlink: the bridge as a Viewpro gimbal towards `AP_Mount_Viewpro`.
    #[cfg(feature = "viewlink")]
    Viewlink(FcLink<viewlink::ViewlinkSide, { viewlink::BUF }>),
    /// GCU: the bridge as a gimbal control unit towards `AP_Mount_XFRobot`.
    #[cfg(feature = "gcu")]
    Gcu(FcLink<gcu::GcuSide, { gcu::BUF }>),
    /// MAVLink 2: gimbal device and camera.
    #[cfg(feature = "mavlink")]
    Mavlink(FcLink<mavlink::MavlinkSide, { mavlink::BUF }>),
}

/// Calls `$call` with `$link` bound to the side in use; `Disabled` gives `$default`.
macro_rules! fc_dispatch {
    ($self:ident, $link:ident => $call:expr, $default:expr) => {
        match $self {
            FcSide::Disabled => $default,
            FcSide::K40t($link) => $call,
            #[cfg(feature = "siyi")]
            FcSide::Siyi($link) => $call,
            #[cfg(feature = "viewlink")]
            FcSide::Viewlink($link) => $call,
            #[cfg(feature = "gcu")]
            FcSide::Gcu($link) => $call,
            #[cfg(feature = "mavlink")]
            FcSide::Mavlink($link) => $call,
        }
    };
}

impl FcSide {
    pub(crate) fn new(config: &Config) -> Self {
        match config.fc {
            #[cfg(feature = "siyi")]
            super::FcProtocol::Siyi => FcSide::Siyi(FcLink::new(
                protocol_core::siyi::SiyiFraming::new(protocol_core::siyi::DEFAULT_MAX_PAYLOAD_LEN),
                siyi::SiyiSide::new(),
            )),
            #[cfg(feature = "viewlink")]
            super::FcProtocol::Viewlink => FcSide::Viewlink(FcLink::new(
                protocol_core::viewlink::ViewlinkFraming::new(),
                viewlink::ViewlinkSide::new(),
            )),
            #[cfg(feature = "gcu")]
            super::FcProtocol::Gcu => FcSide::Gcu(FcLink::new(
                protocol_core::gcu::GcuFraming::host(),
                gcu::GcuSide::new(),
            )),
            #[cfg(feature = "mavlink")]
            super::FcProtocol::Mavlink => FcSide::Mavlink(FcLink::new(
                protocol_core::mavlink::MavlinkFraming::new(),
                mavlink::MavlinkSide::new(config),
            )),
            super::FcProtocol::K40t => FcSide::K40t(FcLink::new(
                protocol_core::k40t::K40tFraming::any(),
                k40t::K40tSide::new(config.fc_silence_stop),
            )),
            #[allow(unreachable_patterns)] // the protocols whose feature is off
            _ => FcSide::Disabled,
        }
    }

    pub(crate) fn receive(&mut self, ctx: &mut Ctx<'_>, bytes: &[u8]) {
        fc_dispatch!(self, link => link.receive(ctx, bytes), {
            let _ = (ctx, bytes);
        });
    }

    pub(crate) fn idle(&mut self, ctx: &mut Ctx<'_>) {
        fc_dispatch!(self, link => link.idle(ctx), {
            let _ = ctx;
        });
    }

    pub(crate) fn poll(&mut self, ctx: &mut Ctx<'_>) {
        fc_dispatch!(self, link => link.handler.poll(ctx), {
            let _ = ctx;
        });
    }

    pub(crate) fn poll_at(&self) -> Option<Instant> {
        fc_dispatch!(self, link => link.handler.poll_at(), None)
    }

    /// Every valid frame from the pod (see [`FcHandler::pod_frame`]).
    pub(crate) fn pod_frame(&mut self, ctx: &mut Ctx<'_>, frame: PodFrame<'_>) {
        fc_dispatch!(self, link => link.handler.pod_frame(ctx, frame), {
            let _ = (ctx, frame);
        });
    }

    /// This side's claim on a pod ACK (see [`FcHandler::ack_claim`]).
    pub(crate) fn ack_claim(&self, now: Instant, base: u16, seq: u8) -> Option<AckClaim> {
        fc_dispatch!(self, link => link.handler.ack_claim(now, base, seq), {
            let _ = (now, base, seq);
            None
        })
    }

    pub(crate) fn pod_notice(&mut self, ctx: &mut Ctx<'_>, notice: PodNotice) {
        fc_dispatch!(self, link => link.handler.pod_notice(ctx, notice), {
            let _ = (ctx, notice);
        });
    }

    /// The pod asks for GPS (see [`FcHandler::gps_request`]).
    pub(crate) fn gps_request(
        &mut self,
        ctx: &mut Ctx<'_>,
        header: Header,
        request: GpsRequest,
    ) -> bool {
        fc_dispatch!(self, link => link.handler.gps_request(ctx, header, request), {
            let _ = (ctx, header, request);
            false
        })
    }

    /// The MAVLink side's signing (`None`: another side).
    pub(crate) fn link_signing(&mut self) -> Option<&mut LinkSigning> {
        match self {
            #[cfg(feature = "mavlink")]
            FcSide::Mavlink(link) => Some(link.handler.signing()),
            _ => None,
        }
    }

    pub(crate) fn deframer_stats(&self) -> Stats {
        fc_dispatch!(self, link => link.deframer.stats(), Stats::default())
    }
}
