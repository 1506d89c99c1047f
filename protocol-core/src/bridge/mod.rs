//! The sans-IO bridge engine: a K40T pod on one side, a flight controller (FC) speaking
//! SIYI, Viewlink, GCU or K40T on the other.
//!
//! No I/O, no clock reads, no allocation, a size fixed at compile time. Like smoltcp's
//! `Interface`, the [`Engine`] is driven by its caller:
//!
//! - **Inputs:** bytes from the FC ([`Engine::receive_fc`]) and from the pod
//!   ([`Engine::receive_pod`]), each with the local [`Instant`] the last byte arrived;
//!   "line idle" per port ([`Engine::fc_idle`], [`Engine::pod_idle`]); and
//!   [`Engine::poll`] at the instant [`Engine::poll_at`] names.
//! - **Outputs:** whole frames for the FC ([`Engine::fc_frame`] + [`Engine::fc_sent`])
//!   and for the pod ([`Engine::pod_frame`] + [`Engine::pod_sent`]); the RTC_IO pin
//!   ([`Engine::pin`], [`Engine::pin_done`]); [`Event`]s for logging and [`Counters`].
//!
//! # RTC_IO and time sync
//! While UTC is valid the engine plans a pulse every [`SyncConfig::period`](sync::SyncConfig)
//! on the UTC grid (10 s by default): [`Engine::pin`] names the local instant of the next
//! rising edge. The caller raises the pin **at** that instant (a timer alarm), reads its
//! clock, and calls [`Engine::pin_done`] with the instant it raised it: the engine puts a
//! 0x00030E carrying the UTC of that edge at the head of the pod queue, to be sent next,
//! and names the falling edge. No sync is ever sent while UTC is unknown.
//!
//! # Geotag
//! The pod's GPS request (0x000310, a UTC time of day) is answered (0x010310) from the
//! fix history, interpolated to the instant asked; a request for an instant after the
//! newest fix waits up to 250 ms for the next one, and is otherwise carried forward with
//! the aircraft's velocity for at most 1 s (see [`geotag`] and [`fixes`]). No fix, a
//! stale fix, or no UTC gives the failure code 0x0001 with the time echoed and zero
//! position and attitude: nothing is invented.

pub mod config;
pub mod discipline;
pub mod event;
pub(crate) mod fc;
pub mod fixes;
pub mod geotag;
pub mod pod;
pub mod queue;
pub mod sync;
pub mod time;

pub use config::{Config, FcProtocol, GcuIdentity, PodConfig, SiyiIdentity, ViewlinkIdentity};
pub use event::{Counters, Event, Port};
pub use pod::PodState;
pub use time::{Duration, Instant, UtcTime};

use discipline::{DisciplineState, TimeDiscipline};
use fc::{Ctx, FcSide};
use fixes::FixHistory;
use geotag::Geotagger;
use pod::{PodDriver, PodNotice};
use queue::FrameQueue;
use sync::{SyncEdge, SyncScheduler};

use crate::k40t::{self, Frame, K40tFraming};
use crate::wire::{Deframer, Event as DeframerEvent, Stats};
use event::EventQueue;

/// Bytes of the queue of frames for the FC. With the `mavlink` feature 512: a MAVLink
/// frame is up to 280 bytes; the largest the bridge sends, CAMERA_INFORMATION (250 bytes
/// with its record header), its ACK and a poll's routine frames (attitude status,
/// heartbeats) fit, and the line drains the queue in 45 ms at 115200 baud.
pub const FC_QUEUE: usize = if cfg!(feature = "mavlink") { 512 } else { 256 };
/// Bytes of the queue of frames for the pod.
pub const POD_QUEUE: usize = 384;

/// The level of the RTC_IO pin.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Level {
    /// Pin low (idle).
    Low,
    /// Pin high: the edge the pod time-stamps.
    High,
}

/// A change of the RTC_IO pin the caller must make at a local instant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct PinAction {
    /// The level to set.
    pub level: Level,
    /// When.
    pub at: Instant,
}

/// The engine's outputs, shared by its parts.
#[derive(Debug, Clone)]
pub(crate) struct Outputs {
    pub(crate) fc: FrameQueue<FC_QUEUE>,
    pub(crate) pod: FrameQueue<POD_QUEUE>,
    pub(crate) events: EventQueue,
    pub(crate) counters: Counters,
}

impl Outputs {
    pub(crate) fn event(&mut self, e: Event) {
        if !self.events.push(e) {
            self.counters.events_dropped = self.counters.events_dropped.saturating_add(1);
        }
    }

    fn pushed(&mut self, port: Port, p: queue::Pushed) -> bool {
        let dropped = u32::from(p.dropped).saturating_add(u32::from(!p.queued));
        if dropped > 0 {
            self.counters.dropped = self.counters.dropped.saturating_add(dropped);
            self.event(Event::Dropped {
                port,
                frames: u8::try_from(dropped).unwrap_or(u8::MAX),
            });
        }
        if p.queued {
            let sent = match port {
                Port::Fc => &mut self.counters.fc_sent,
                Port::Pod => &mut self.counters.pod_sent,
            };
            *sent = sent.saturating_add(1);
        }
        p.queued
    }

    /// Queues a frame for the FC.
    #[cfg_attr(
        not(any(feature = "siyi", feature = "viewlink", feature = "gcu")),
        allow(dead_code)
    )]
    pub(crate) fn queue_fc(&mut self, frame: &[u8], critical: bool) -> bool {
        let p = self.fc.push_back(frame, critical);
        self.pushed(Port::Fc, p)
    }

    /// Queues a frame for the pod (at the head with `front`).
    pub(crate) fn queue_pod(&mut self, frame: &[u8], critical: bool, front: bool) -> bool {
        let p = if front {
            self.pod.push_front(frame, critical)
        } else {
            self.pod.push_back(frame, critical)
        };
        self.pushed(Port::Pod, p)
    }
}

/// Largest pod frame the engine takes (a K40T frame is at most 255 bytes).
const POD_FRAME: usize = k40t::MAX_FRAME_LEN;

/// The bridge engine. See the [module documentation](self).
#[derive(Debug, Clone)]
pub struct Engine {
    /// Apart from the rest, so that each frame it yields is handled with all the rest.
    pod_deframer: Deframer<K40tFraming, POD_FRAME>,
    core: Core,
}

/// Everything of the engine but the pod deframer.
#[derive(Debug, Clone)]
struct Core {
    config: Config,
    fc: FcSide,
    pod: PodDriver,
    time: TimeDiscipline,
    sync: SyncScheduler,
    fixes: FixHistory,
    geotag: Geotagger,
    /// The next rising edge, as planned.
    edge: Option<SyncEdge>,
    /// The planned edge is within the sync lead: kept as it is (the caller may have armed
    /// its timer), and no more polls are wanted for it.
    edge_settled: bool,
    /// The falling edge due after a rising one.
    pin_low: Option<Instant>,
    out: Outputs,
    fc_last: Option<Instant>,
    fc_link: bool,
}

impl Engine {
    /// An engine with `config`, nothing received yet.
    #[must_use]
    pub fn new(config: Config) -> Self {
        Engine {
            pod_deframer: Deframer::new(K40tFraming::any()),
            core: Core {
                fc: FcSide::new(&config),
                pod: PodDriver::new(config.pod),
                time: TimeDiscipline::new(config.discipline),
                sync: SyncScheduler::new(config.sync),
                fixes: FixHistory::new(config.fixes),
                geotag: Geotagger::default(),
                edge: None,
                edge_settled: false,
                pin_low: None,
                out: Outputs {
                    fc: FrameQueue::new(),
                    pod: FrameQueue::new(),
                    events: EventQueue::new(),
                    counters: Counters::default(),
                },
                fc_last: None,
                fc_link: false,
                config,
            },
        }
    }

    /// The configuration.
    #[must_use]
    pub const fn config(&self) -> &Config {
        &self.core.config
    }

    /// What the bridge knows of the pod.
    #[must_use]
    pub const fn pod_state(&self) -> &PodState {
        self.core.pod.state()
    }

    /// The UTC of a local instant, when known.
    #[must_use]
    pub fn utc(&self, at: Instant) -> Option<UtcTime> {
        self.core.time.utc(at)
    }

    /// Where the UTC discipline stands.
    #[must_use]
    pub const fn utc_state(&self) -> DisciplineState {
        self.core.time.state()
    }

    /// Running totals.
    #[must_use]
    pub fn counters(&self) -> Counters {
        let mut c = self.core.out.counters;
        let pod: Stats = self.pod_deframer.stats();
        c.pod_rejected = pod.checksum_errors.saturating_add(pod.length_errors);
        c.pod_garbage_bytes = pod.bytes_discarded;
        let fc = self.core.fc.deframer_stats();
        c.fc_rejected = fc.checksum_errors.saturating_add(fc.length_errors);
        c.fc_garbage_bytes = fc.bytes_discarded;
        c
    }

    /// The FC link is up (a valid frame within the FC link time-out).
    #[must_use]
    pub const fn fc_link(&self) -> bool {
        self.core.fc_link
    }

    /// The next event, oldest first.
    pub fn next_event(&mut self) -> Option<Event> {
        self.core.out.events.pop()
    }

    /// The next frame for the FC: write all of it, then call [`Engine::fc_sent`].
    #[must_use]
    pub fn fc_frame(&self) -> Option<&[u8]> {
        self.core.out.fc.front()
    }

    /// The frame [`Engine::fc_frame`] gave is on its way.
    pub fn fc_sent(&mut self) {
        self.core.out.fc.pop();
    }

    /// Copies the next frame for the FC into `buf` and takes it off the queue; returns
    /// its length (`None`: nothing queued, or `buf` too small and the frame kept). For
    /// a caller that writes asynchronously: take the frame, then write it.
    pub fn take_fc_frame(&mut self, buf: &mut [u8]) -> Option<usize> {
        self.core.out.fc.pop_into(buf)
    }

    /// As [`Engine::take_fc_frame`], for the pod. A time-sync frame put at the head of the
    /// queue while a taken frame is being written comes next.
    pub fn take_pod_frame(&mut self, buf: &mut [u8]) -> Option<usize> {
        self.core.out.pod.pop_into(buf)
    }

    /// The next frame for the pod: write all of it, then call [`Engine::pod_sent`]. A
    /// time-sync frame comes first, after the frame being written.
    #[must_use]
    pub fn pod_frame(&self) -> Option<&[u8]> {
        self.core.out.pod.front()
    }

    /// The frame [`Engine::pod_frame`] gave is on its way.
    pub fn pod_sent(&mut self) {
        self.core.out.pod.pop();
    }

    /// Bytes from the FC; `now` is the local instant the last of them arrived.
    pub fn receive_fc(&mut self, now: Instant, bytes: &[u8]) {
        let core = &mut self.core;
        let (fc, mut ctx) = core.ctx(now);
        fc.receive(&mut ctx, bytes);
        let seen = ctx.fc_seen;
        core.fc_frame_seen(now, seen);
        core.after_input(now);
    }

    /// The FC line has gone idle (a UART idle interrupt, a read time-out): frames are
    /// complete, and an incomplete candidate will not be (see
    /// [`Deframer::poll_idle`](crate::wire::Deframer::poll_idle)).
    pub fn fc_idle(&mut self, now: Instant) {
        let core = &mut self.core;
        let (fc, mut ctx) = core.ctx(now);
        fc.idle(&mut ctx);
        let seen = ctx.fc_seen;
        core.fc_frame_seen(now, seen);
        core.after_input(now);
    }

    /// Bytes from the pod; `now` is the local instant the last of them arrived.
    pub fn receive_pod(&mut self, now: Instant, bytes: &[u8]) {
        let core = &mut self.core;
        self.pod_deframer.push(bytes, |ev| {
            if let DeframerEvent::Frame(f) = ev {
                core.pod_frame(now, f);
            }
        });
        core.after_input(now);
    }

    /// The pod line has gone idle.
    pub fn pod_idle(&mut self, now: Instant) {
        let core = &mut self.core;
        self.pod_deframer.flush(|ev| {
            if let DeframerEvent::Frame(f) = ev {
                core.pod_frame(now, f);
            }
        });
        core.after_input(now);
    }

    /// Does the work due at `now`: retries and time-outs, link supervision, the FC
    /// silence stop, streamed replies, the UTC discipline and the sync plan.
    pub fn poll(&mut self, now: Instant) {
        self.core.poll(now);
    }

    /// The next RTC_IO change: the planned rising edge, or the falling edge after it.
    /// Apply it at its instant and report it with [`Engine::pin_done`].
    #[must_use]
    pub fn pin(&self) -> Option<PinAction> {
        match (self.core.pin_low, self.core.edge) {
            (Some(at), _) => Some(PinAction {
                level: Level::Low,
                at,
            }),
            (None, Some(e)) => Some(PinAction {
                level: Level::High,
                at: e.at,
            }),
            (None, None) => None,
        }
    }

    /// The caller set RTC_IO to `level` at the local instant `at`. For a rising edge,
    /// the 0x00030E of that edge goes to the head of the pod queue (send it next) and
    /// the falling edge is planned.
    pub fn pin_done(&mut self, level: Level, at: Instant) {
        self.core.pin_done(level, at);
    }

    /// When the engine wants [`Engine::poll`] called next (`None`: only on input).
    /// The RTC_IO edges have their own instants ([`Engine::pin`]); this is never later
    /// than the planned rising edge minus the sync lead, so that a re-planned edge is
    /// seen in time.
    #[must_use]
    pub fn poll_at(&self) -> Option<Instant> {
        let c = &self.core;
        let fc_down = c
            .fc_last
            .filter(|_| c.fc_link)
            .map(|t| t.saturating_add(c.config.fc_link_timeout));
        [
            c.pod.poll_at(c.config.fc_silence_stop),
            c.fc.poll_at(),
            c.time.poll_at(),
            c.geotag.poll_at(),
            fc_down,
            // Re-plan the edge once more just before it; a settled edge needs no poll.
            c.edge
                .filter(|_| !c.edge_settled)
                .map(|e| e.at.saturating_sub(c.config.sync.lead)),
        ]
        .into_iter()
        .flatten()
        .min()
    }
}

impl Core {
    fn ctx(&mut self, now: Instant) -> (&mut FcSide, Ctx<'_>) {
        (
            &mut self.fc,
            Ctx {
                now,
                config: &self.config,
                pod: &mut self.pod,
                time: &mut self.time,
                fixes: &mut self.fixes,
                geotag: &mut self.geotag,
                out: &mut self.out,
                fc_seen: false,
                transit: Duration::ZERO,
            },
        )
    }

    fn fc_frame_seen(&mut self, now: Instant, seen: bool) {
        if seen {
            self.fc_last = Some(now);
            if !self.fc_link {
                self.fc_link = true;
                self.out.event(Event::FcLinkUp);
            }
        }
    }

    /// One valid frame from the pod. An ACK goes to whoever has the better claim on it: the pod driver's own outstanding requests, or (K40T side) the FC's
    /// forwarded ones; see `pod::AckClaim`.
    fn pod_frame(&mut self, now: Instant, f: &[u8]) {
        self.out.counters.pod_frames = self.out.counters.pod_frames.saturating_add(1);
        let Ok(frame) = Frame::new_checked(f) else {
            return;
        };
        let Some(header) = frame.header() else {
            return;
        };
        let id = frame.id();
        let (driver_claimed, fc_claimed) = if id.kind == k40t::Kind::Ack {
            let driver = self.pod.ack_claim(id.base, header.seq);
            let fc = self.fc.ack_claim(now, id.base, header.seq);
            match (driver, fc) {
                (Some(d), Some(f)) => (!f.beats(d) || d.beats(f), f.beats(d) && !d.beats(f)),
                (d, f) => (d.is_some(), f.is_some()),
            }
        } else {
            (false, false)
        };
        let notices = self
            .pod
            .handle(now, &frame, header, driver_claimed, &mut self.out);
        {
            let (fc, mut ctx) = self.ctx(now);
            fc.pod_frame(
                &mut ctx,
                fc::PodFrame {
                    bytes: f,
                    id,
                    header,
                    ack_claimed: fc_claimed,
                },
            );
        }
        for n in notices.iter() {
            self.notice(now, n);
        }
    }

    fn notice(&mut self, now: Instant, n: PodNotice) {
        match n {
            PodNotice::LinkUp => self.out.event(Event::PodLinkUp),
            PodNotice::LinkDown => self.out.event(Event::PodLinkDown),
            PodNotice::Acked { .. } | PodNotice::TimedOut { .. } => {}
            PodNotice::GpsRequest { header, request } => {
                let (fc, mut ctx) = self.ctx(now);
                if !fc.gps_request(&mut ctx, header, request) {
                    ctx.geotag(header, request);
                }
                return;
            }
        }
        let (fc, mut ctx) = self.ctx(now);
        fc.pod_notice(&mut ctx, n);
    }

    /// Reports a change of the UTC discipline's state (samples arrive with the input)
    /// and plans the next edge.
    fn after_input(&mut self, now: Instant) {
        self.utc_transition(now);
        // A fix may have come in for a waiting GPS request.
        self.geotag
            .poll(now, &self.fixes, &mut self.pod, &mut self.out);
        self.plan_sync(now);
    }

    fn utc_transition(&mut self, now: Instant) {
        if let Some(t) = self.time.poll(now) {
            if t.utc_lost() {
                self.out.event(Event::UtcLost);
            }
            if t.utc_became_valid() {
                let bound = self.time.error_bound(now).unwrap_or(Duration::ZERO);
                self.out.event(Event::UtcValid {
                    error_bound_us: u32::try_from(bound.as_micros()).unwrap_or(u32::MAX),
                    converged: self.time.is_converged(),
                });
            }
        }
    }

    fn poll(&mut self, now: Instant) {
        self.utc_transition(now);
        let notices = self
            .pod
            .poll(now, self.config.fc_silence_stop, &mut self.out);
        for n in notices.iter() {
            self.notice(now, n);
        }
        {
            let (fc, mut ctx) = self.ctx(now);
            fc.poll(&mut ctx);
        }
        self.geotag
            .poll(now, &self.fixes, &mut self.pod, &mut self.out);
        if self.fc_link
            && self
                .fc_last
                .is_none_or(|t| now.saturating_duration_since(t) >= self.config.fc_link_timeout)
        {
            self.fc_link = false;
            self.out.event(Event::FcLinkDown);
        }
        self.plan_sync(now);
    }

    /// Plans (or re-plans, or cancels) the next rising edge.
    fn plan_sync(&mut self, now: Instant) {
        if self.pin_low.is_some() {
            return;
        }
        // An edge within `lead` is kept as planned: the caller may have armed its timer.
        let lead_start = now.saturating_add(self.config.sync.lead);
        self.edge_settled = self.edge.is_some_and(|e| e.at <= lead_start);
        if self.edge_settled {
            return;
        }
        // Holdover is still usable: the local clock carries UTC between sparse samples
        // (the K40T FC sends one every 10 s) and after the FC falls silent, for a while.
        self.edge = if self.time.state().is_usable() {
            self.sync.next_edge(now, &self.time)
        } else {
            None
        };
        self.edge_settled = self.edge.is_some_and(|e| e.at <= lead_start);
    }

    fn pin_done(&mut self, level: Level, at: Instant) {
        match level {
            Level::Low => self.pin_low = None,
            Level::High => {
                self.pin_low = Some(at.saturating_add(self.config.sync.width));
                self.edge_settled = false;
                let Some(edge) = self.edge.take() else {
                    return;
                };
                self.sync.fired(&edge);
                let Some(utc) = self.sync.stamp(&edge, at, &self.time) else {
                    return;
                };
                let utc_ms = utc.as_unix_millis_rounded();
                let bound = self.time.error_bound(at).unwrap_or(Duration::ZERO);
                if self
                    .pod
                    .send_time_sync(utc_ms, self.config.tz_minuteswest, &mut self.out)
                {
                    self.out.counters.time_syncs = self.out.counters.time_syncs.saturating_add(1);
                    self.out.event(Event::TimeSync {
                        edge: at,
                        utc_ms,
                        error_bound_us: u32::try_from(bound.as_micros()).unwrap_or(u32::MAX),
                    });
                }
            }
        }
    }
}

#[cfg(test)]
mod size_tests {
    use super::*;

    /// The engine's size is fixed at compile time; with every FC side compiled in it
    /// stays under 9 KiB on the 64-bit host (7.9 KB before ACK matching kept superseded
    /// requests and their send instants, and the discipline its error bound).
    #[test]
    fn the_engine_fits_in_9_kib() {
        let size = core::mem::size_of::<Engine>();
        println!(
            "engine {size} B: pod driver {}, discipline {}, fixes {}, outputs {}, FC side {}",
            core::mem::size_of::<PodDriver>(),
            core::mem::size_of::<TimeDiscipline>(),
            core::mem::size_of::<FixHistory>(),
            core::mem::size_of::<Outputs>(),
            core::mem::size_of::<FcSide>(),
        );
        assert!(size <= 9 * 1024, "{size} bytes");
    }
}
