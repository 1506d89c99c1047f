//! The bridge engine between a simulated flight controller and a simulated pod, on
//! simulated serial lines, in simulated time.
//!
//! True time is `u64` microseconds. The bridge's clock drifts against it by
//! [`Scenario::bridge_ppm`] (the engine only ever sees its own clock); the peers run on
//! true time (an FC simulator models its own clock). Every line carries bytes at the baud
//! rate and delivers them in chunks with an idle event after each burst, as the
//! firmware's UART does. The RTC_IO pin is applied exactly at the instant the engine
//! names (the firmware's timer alarm) and seen by the pod at the same instant.
//!
//! With [`Scenario::with_pps`] a GNSS module's time pulse reaches the engine's PPS input
//! ([`Engine::pps`](bridge_engine::Engine::pps)): each captured edge at the bridge's
//! clock reading of its true instant, to the nanosecond; [`Scenario::pin_edges`] then
//! hold the RTC_IO edges to the nanosecond too (the planned compare instant).
//!
//! Cables can fail: [`Scenario::fc_cut`] for good, [`Scenario::pull_fc_cable`] and
//! [`Scenario::pull_pod_cable`] for a while, [`Scenario::set_fc_faults`] and
//! [`Scenario::set_pod_faults`] for a noisy cable (a seeded [`Faults`] model in both
//! directions).

use bridge_engine::{Config, Engine, Event, Instant, InstantNs, Level, MAX_FRAME_LEN, Port};

use super::faults::Faults;
use super::gnss::GnssPps;
use super::line::Line;
use super::peer::Peer;
use super::pod::SimPod;

/// A flight controller that says nothing.
#[derive(Debug, Default)]
pub struct SilentFc {
    /// Bytes received from the bridge.
    pub received: Vec<u8>,
}

impl Peer for SilentFc {
    fn receive(&mut self, _now_us: u64, bytes: &[u8]) {
        self.received.extend_from_slice(bytes);
    }
    fn poll(&mut self, _now_us: u64) {}
    fn next_wakeup(&self) -> u64 {
        u64::MAX
    }
    fn transmit(&mut self, _now_us: u64) -> Vec<(u64, Vec<u8>)> {
        Vec::new()
    }
}

/// One RTC_IO change, as applied.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PinEdge {
    /// True time.
    pub at_us: u64,
    /// The level set.
    pub level: Level,
    /// True time, ns: the planned instant to the nanosecond (a timer's compare).
    pub at_ns: i128,
}

/// The engine, its peers and the four lines.
pub struct Scenario<F: Peer> {
    /// True time now.
    pub now_us: u64,
    /// The bridge's clock error against true time, parts per million.
    pub bridge_ppm: i64,
    /// The bridge's clock at true time 0, µs (1 s by default, so it is never 0; a
    /// scenario may start it anywhere, e.g. just before its millisecond count passes
    /// 2^32: docs/src/reliability.md).
    pub bridge_start_us: u64,
    /// The engine under test.
    pub engine: Engine,
    /// The flight controller.
    pub fc: F,
    /// The pod.
    pub pod: SimPod,
    /// FC -> bridge.
    pub fc_line: Line,
    /// Bridge -> FC.
    pub to_fc_line: Line,
    /// Pod -> bridge.
    pub pod_line: Line,
    /// Bridge -> pod.
    pub to_pod_line: Line,
    /// Every RTC_IO change.
    pub pin_edges: Vec<PinEdge>,
    /// Every engine event, with the true time it was drained.
    pub events: Vec<(u64, Event)>,
    /// Cut the FC cable (no bytes either way).
    pub fc_cut: bool,
    /// The FC cable is out until this true time (µs).
    pub fc_cut_until_us: u64,
    /// The pod cable (UART both ways and RTC_IO) is out until this true time (µs).
    pub pod_cut_until_us: u64,
    /// Never tell the engine the FC line went idle (a caller without idle detection, or
    /// one whose idle signal comes too late).
    pub fc_idle_off: bool,
    /// The GNSS module on the PPS input ([`Scenario::with_pps`]).
    pub pps: Option<GnssPps>,
    /// True time (ns) of the last PPS edge handed to the engine.
    pps_last_ns: Option<i128>,
}

impl<F: Peer> Scenario<F> {
    /// A scenario at true time 0 with a bridge clock `bridge_ppm` off.
    pub fn new(config: Config, fc: F, pod: SimPod, bridge_ppm: i64) -> Self {
        Scenario {
            now_us: 0,
            bridge_ppm,
            bridge_start_us: 1_000_000,
            fc_line: Line::new(config.fc_baud),
            to_fc_line: Line::new(config.fc_baud),
            pod_line: Line::new(config.pod_baud),
            to_pod_line: Line::new(config.pod_baud),
            engine: Engine::new(config),
            fc,
            pod,
            pin_edges: Vec::new(),
            events: Vec::new(),
            fc_cut: false,
            fc_cut_until_us: 0,
            pod_cut_until_us: 0,
            fc_idle_off: false,
            pps: None,
            pps_last_ns: None,
        }
    }

    /// The same scenario with `gnss`'s time pulse on the bridge's PPS input (the edge
    /// the bridge's configuration names, `[pps] active_low`).
    #[must_use]
    pub fn with_pps(mut self, gnss: GnssPps) -> Self {
        self.pps = Some(gnss);
        self
    }

    /// The bridge's clock (ns) at true time `t_ns`.
    #[must_use]
    pub fn local_ns(&self, t_ns: i128) -> i128 {
        t_ns + t_ns * i128::from(self.bridge_ppm) / 1_000_000
            + i128::from(self.bridge_start_us) * 1_000
    }

    /// The true time (ns) at which the bridge's clock reads `local_ns`.
    #[must_use]
    pub fn true_of_ns(&self, local_ns: i128) -> i128 {
        (local_ns - i128::from(self.bridge_start_us) * 1_000) * 1_000_000
            / (1_000_000 + i128::from(self.bridge_ppm))
    }

    /// The next PPS edge the bridge captures: (true µs it is handed over, its local ns,
    /// its true ns).
    fn next_pps(&self) -> Option<(u64, InstantNs, i128)> {
        let g = self.pps.as_ref()?;
        let from = self.pps_last_ns.map_or(0, |t| t + 1);
        let (_, t) = g.next_edge(from, self.engine.config().pps.active_low)?;
        let local = u64::try_from(self.local_ns(t)).ok()?;
        let due = u64::try_from(t.div_euclid(1_000) + 1).ok()?;
        Some((due, InstantNs::from_nanos(local), t))
    }

    /// The bridge's clock at true time `t_us` (from [`Scenario::bridge_start_us`]).
    pub fn local(&self, t_us: u64) -> Instant {
        let drift = i128::from(t_us) * i128::from(self.bridge_ppm) / 1_000_000;
        let l = i128::from(t_us) + drift + i128::from(self.bridge_start_us);
        Instant::from_micros(u64::try_from(l.max(0)).unwrap_or(0))
    }

    /// The true time at which the bridge's clock reads `at`.
    pub fn true_of(&self, at: Instant) -> u64 {
        let l = i128::from(at.as_micros()) - i128::from(self.bridge_start_us);
        let t = l * 1_000_000 / (1_000_000 + i128::from(self.bridge_ppm));
        // Round up so that the bridge's clock has reached `at`.
        let mut t = u64::try_from(t.max(0)).unwrap_or(0);
        while self.local(t) < at {
            t += 1;
        }
        t
    }

    /// Runs until true time `end_us`.
    pub fn run_until(&mut self, end_us: u64) {
        while self.now_us < end_us {
            let next = self
                .next_event()
                .unwrap_or(end_us)
                .clamp(self.now_us, end_us);
            self.now_us = next;
            self.step();
            if self.next_event().is_some_and(|t| t <= self.now_us) {
                // Work that became due at the same instant: run it, but never loop
                // forever on a peer that keeps asking for `now`.
                self.step();
                if self.next_event().is_some_and(|t| t <= self.now_us) {
                    self.now_us += 1;
                }
            }
        }
    }

    /// Runs for `us` more microseconds.
    pub fn run_for(&mut self, us: u64) {
        self.run_until(self.now_us + us);
    }

    /// Pulls the FC cable out now for `duration_us` (nothing either way; back by itself).
    pub fn pull_fc_cable(&mut self, duration_us: u64) {
        self.fc_cut_until_us = self.now_us.saturating_add(duration_us);
    }

    /// Pulls the pod cable out now for `duration_us`: nothing either way, no RTC_IO edge
    /// reaches the pod (it keeps running).
    pub fn pull_pod_cable(&mut self, duration_us: u64) {
        self.pod_cut_until_us = self.now_us.saturating_add(duration_us);
    }

    /// A noisy FC cable from now on: `faults` in both directions, each with its own seed
    /// ([`Faults::derived`]: 0 into the bridge, 1 out of it); `None`: a good cable.
    pub fn set_fc_faults(&mut self, faults: Option<Faults>) {
        self.fc_line.damage.set_faults(faults.map(|f| f.derived(0)));
        self.to_fc_line
            .damage
            .set_faults(faults.map(|f| f.derived(1)));
    }

    /// A noisy pod cable, as [`Scenario::set_fc_faults`].
    pub fn set_pod_faults(&mut self, faults: Option<Faults>) {
        self.pod_line
            .damage
            .set_faults(faults.map(|f| f.derived(0)));
        self.to_pod_line
            .damage
            .set_faults(faults.map(|f| f.derived(1)));
    }

    fn fc_is_cut(&self) -> bool {
        self.fc_cut || self.now_us < self.fc_cut_until_us
    }

    fn pod_is_cut(&self) -> bool {
        self.now_us < self.pod_cut_until_us
    }

    fn next_event(&self) -> Option<u64> {
        let engine_poll = self.engine.poll_at().map(|t| self.true_of(t));
        let pin = self.engine.pin().map(|p| self.true_of(p.at));
        [
            engine_poll,
            pin,
            Some(self.fc.next_wakeup()).filter(|&t| t != u64::MAX),
            Some(self.pod.next_wakeup()).filter(|&t| t != u64::MAX),
            self.fc_line.next_event(),
            self.to_fc_line.next_event(),
            self.pod_line.next_event(),
            self.to_pod_line.next_event(),
            self.engine
                .pending(Port::Pod)
                .map(|_| self.to_pod_line.busy_until()),
            self.next_pps().map(|(due, _, _)| due),
        ]
        .into_iter()
        .flatten()
        .min()
    }

    /// Does everything due at `now_us`.
    fn step(&mut self) {
        let now = self.now_us;
        let local = self.local(now);
        // Lines into the bridge.
        let (bytes, idle) = self.fc_line.deliver(now);
        if !bytes.is_empty() && !self.fc_is_cut() {
            self.engine.receive(local, Port::Fc, &bytes);
        }
        if idle && !self.fc_idle_off {
            self.engine.idle(local, Port::Fc);
        }
        let (bytes, idle) = self.pod_line.deliver(now);
        if !bytes.is_empty() && !self.pod_is_cut() {
            self.engine.receive(local, Port::Pod, &bytes);
        }
        if idle {
            self.engine.idle(local, Port::Pod);
        }
        // Lines out of the bridge.
        let (bytes, _) = self.to_fc_line.deliver(now);
        if !bytes.is_empty() && !self.fc_is_cut() {
            self.fc.receive(now, &bytes);
        }
        let (bytes, _) = self.to_pod_line.deliver(now);
        if !bytes.is_empty() && !self.pod_is_cut() {
            self.pod.receive(now, &bytes);
        }
        // The PPS edges captured up to now.
        while let Some((_, edge, t)) = self.next_pps().filter(|(due, _, _)| *due <= now) {
            self.pps_last_ns = Some(t);
            self.engine.pps(edge);
            self.drain_engine();
        }
        // RTC_IO at the instant the engine names.
        while let Some(p) = self.engine.pin().filter(|p| p.at <= local) {
            let at = self.true_of(p.at);
            let at_ns =
                self.true_of_ns(i128::from(p.at.as_micros()) * 1_000 + i128::from(p.sub_us_ns));
            if !self.pod_is_cut() {
                self.pod.rtc_edge(at, p.level == Level::High);
            }
            self.pin_edges.push(PinEdge {
                at_us: at,
                level: p.level,
                at_ns,
            });
            self.engine.pin_done(p.level, p.at);
            self.drain_engine();
        }
        if self.engine.poll_at().is_some_and(|t| t <= local) {
            self.engine.poll(local);
        }
        if self.fc.next_wakeup() <= now {
            self.fc.poll(now);
        }
        if self.pod.next_wakeup() <= now {
            self.pod.poll(now);
        }
        self.drain_engine();
        for (at, bytes) in self.fc.transmit(now) {
            if !self.fc_is_cut() {
                self.fc_line.send(at.max(now), &bytes);
            }
        }
        let bytes = self.pod.transmit();
        if !bytes.is_empty() && !self.pod_is_cut() {
            self.pod_line.send(now, &bytes);
        }
    }

    /// Moves the engine's output frames onto the lines and collects its events.
    fn drain_engine(&mut self) {
        let now = self.now_us;
        let mut f = [0u8; MAX_FRAME_LEN];
        while let Some(n) = self.engine.transmit(Port::Fc, &mut f) {
            if !self.fc_is_cut() {
                self.to_fc_line.send(now, &f[..n]);
            }
        }
        // One frame at a time, when the line is free (the firmware writes a frame and
        // waits for it to leave before taking the next): a time-sync frame put at the
        // head of the queue goes next.
        if self.to_pod_line.busy_until() <= now
            && let Some(n) = self.engine.transmit(Port::Pod, &mut f)
        {
            self.to_pod_line.send(now, &f[..n]);
        }
        while let Some(e) = self.engine.next_event() {
            self.events.push((now, e));
        }
    }

    /// The events so far that match `f`.
    pub fn events_where(&self, f: impl Fn(&Event) -> bool) -> Vec<(u64, Event)> {
        self.events.iter().copied().filter(|(_, e)| f(e)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::pod::PodSimConfig;
    use protocol_core::k40t::{CameraVersionQuery, GimbalVersionQuery, MessageData};

    /// The engine between a silent FC and the default pod, the bridge `bridge_ppm` fast.
    fn silent_fc(bridge_ppm: i64) -> Scenario<SilentFc> {
        let pod = SimPod::new(PodSimConfig::default());
        Scenario::new(Config::default(), SilentFc::default(), pod, bridge_ppm)
    }

    #[test]
    fn the_pod_link_comes_up_and_versions_are_asked_once_connected() {
        let mut s = silent_fc(40);
        s.run_until(3_000_000);
        assert!(s.engine.pod_state().link);
        assert!(s.engine.pod_state().gimbal_version.is_some());
        assert!(s.engine.pod_state().camera_version.is_some());
        assert!(s.engine.pod_state().attitude.is_some());
        assert_eq!(s.pod.received_count(CameraVersionQuery::ID.to_u32()), 1);
        // Probe at start, then the query on connection.
        assert!(s.pod.received_count(GimbalVersionQuery::ID.to_u32()) <= 2);
        assert_eq!(s.events_where(|e| matches!(e, Event::PodLinkUp)).len(), 1);
        assert!(s.pin_edges.is_empty(), "no UTC: no sync");
        // The cable is cut: the link goes down, probing resumes at 1 Hz.
        s.pod.set_silent(true);
        let before = s.pod.received_count(GimbalVersionQuery::ID.to_u32());
        s.run_for(5_000_000);
        assert!(!s.engine.pod_state().link);
        assert_eq!(s.events_where(|e| matches!(e, Event::PodLinkDown)).len(), 1);
        s.pod.set_silent(false);
        s.run_for(2_000_000);
        assert!(s.engine.pod_state().link);
        assert!(s.pod.received_count(GimbalVersionQuery::ID.to_u32()) > before);
    }

    /// A GNSS PPS on the engine's input: the clock locks, and the RTC_IO edges are
    /// within a microsecond of the GNSS's UTC they carry.
    #[test]
    fn a_pps_locks_the_edges_to_the_gnss_seconds() {
        use crate::sim::ap_xfrobot::{ApXfRobot, ApXfRobotConfig};
        use crate::sim::gnss::GnssPpsConfig;
        let utc0 = 1_795_428_000_123_456;
        let fc = ApXfRobot::new(ApXfRobotConfig {
            utc_at_zero_us: utc0,
            ..ApXfRobotConfig::default()
        });
        let gnss = GnssPps::new(GnssPpsConfig {
            utc_at_zero_us: utc0,
            ..GnssPpsConfig::default()
        });
        let pod = SimPod::new(PodSimConfig::default());
        let mut s = Scenario::new(Config::for_fc(bridge_engine::FcProtocol::Gcu), fc, pod, -25)
            .with_pps(gnss.clone());
        s.run_until(60_000_000);
        assert!(
            s.events_where(|e| matches!(e, Event::PpsLocked { .. }))
                .len()
                == 1
        );
        let syncs = s.pod.syncs();
        assert!(syncs.len() >= 4, "{syncs:?}");
        for sync in &syncs[1..] {
            let edge = s
                .pin_edges
                .iter()
                .find(|p| p.level == Level::High && Some(p.at_us) == sync.edge_us)
                .unwrap();
            let err = i128::from(sync.unix_ms) * 1_000_000 - gnss.utc_ns(edge.at_ns);
            assert!(err.abs() < 1_000, "{err} ns");
        }
        assert!(s.engine.counters().pps_edges >= 55);
    }

    #[test]
    fn a_pulled_pod_cable_carries_nothing_until_it_is_back() {
        let mut s = silent_fc(0);
        s.run_until(3_000_000);
        let (pod_rx, pod_tx) = (s.pod.rx_stats().bytes, s.pod_line.bytes_sent);
        let edges = s.pod.rtc_edges().len();
        s.pull_pod_cable(5_000_000);
        s.run_for(4_999_999);
        assert_eq!(s.pod.rx_stats().bytes, pod_rx, "nothing reaches the pod");
        assert_eq!(s.pod_line.bytes_sent, pod_tx, "nothing leaves it");
        assert_eq!(s.pod.rtc_edges().len(), edges);
        assert!(s.pod.sent_count(0x00_0002) > 70, "the pod runs on");
        s.run_for(1_000_000);
        assert!(s.pod_line.bytes_sent > pod_tx);

        // A noisy cable: both directions through their own fault stage.
        s.set_pod_faults(Some(Faults::bit_errors(1e-3, 4)));
        s.run_for(2_000_000);
        let (a, b) = (
            s.pod_line.damage.fault_stats(),
            s.to_pod_line.damage.fault_stats(),
        );
        assert!(a.is_some_and(|a| a.bytes_in > 1_000), "{a:?}");
        assert!(b.is_some());
        assert_eq!(s.fc_line.damage.fault_stats(), None);
        s.set_pod_faults(None);
        assert_eq!(s.pod_line.damage.fault_stats(), None);
    }
}
