//! The firmware's own tasks (`bridge-fw`, feature `host`) between a simulated flight
//! controller ([`Pilot`]) and the simulated pod, on the host's pipes, in virtual time:
//! the bench of the task-level scenarios and of the demo.
//!
//! ```text
//!  Pilot ──(fc_in)──▶ FC link ─┐                     ┌─ pod link ──(pod_out)──▶ SimPod
//!        ◀─(fc_out)── task    ─┴─ engine task, RTC_IO ┴─ task    ◀──(pod_in)───
//! ```
//!
//! With [`Bench::with_telemetry`], a third peer (any [`Peer`]: an autopilot's MAVLink 2
//! port, `ap_mavlink::ApMavlink`) is on the bridge's telemetry link
//! ([`Port::Telemetry`](bridge_engine::Port::Telemetry)), through the same kind of
//! wire at `telemetry_baud` ([`Wires::tel_in`], [`Wires::tel_out`]).
//!
//! Each of the four directions passes through a [`Wire`] on the peer's side: it counts
//! the bytes, can record them (the demo decodes them), cut them (a cable pulled out, for
//! good or for a while: [`Wires::cut`], [`Wires::pull`]) or change them (a
//! [`super::faults::Corrupter`], or a seeded [`Faults`] model: [`Wires::set_faults`]), in
//! both directions, and can trickle them one byte at a
//! time at the line's pace or hold them up for a while (into the bridge). RTC_IO goes
//! to the pod through [`PodPin`]; every record of the tasks' log (engine events, pin
//! changes, edge-to-frame delays) is kept.
//!
//! With [`Bench::with_pps`] a simulated GNSS module's time pulse reaches the bridge's
//! PPS input and RTC_IO is the board's timer compare ([`super::pps_io`]): every edge is
//! recorded to the nanosecond ([`Outcome::rtc_edges_ns`]).
//!
//! A [`Bench`] runs once ([`Bench::run`]): virtual time starts at 0 with each run. A
//! script called every tick acts on the peers and the wires while the tasks run.

use core::cell::RefCell;
use core::convert::Infallible;

use bridge_engine::{Config, Engine, Event, InstantNs, Level};
use bridge_fw::host::{self, Clock, HostLinks, HostShared};
use bridge_fw::{LogKind, LogRecord, NoPps, RtcIo, Timing};
use embassy_futures::select::{Either3, select3};
use embassy_time::{Duration, Instant as EmbassyInstant, Timer};
use embedded_io_async::{ErrorType, Read, Write};

use super::faults::{Damage, Faults};
use super::peer::{Peer, PodPin, now_us, run_peer};
use super::pilot::Pilot;
use super::pod::{PodSimConfig, SimPod};
use super::pps_io::{CapturedPps, ComparePin, PpsWiring};
use super::scenario::SilentFc;

/// One direction of a link as the peer sees it: counts, records, cuts or changes bytes.
#[derive(Debug, Default)]
pub struct Wire {
    /// The cable is cut: bytes are lost (counted in [`Wire::lost`]).
    pub cut: bool,
    /// The cable is out until this instant (µs; [`Wire::pull_for`]).
    pub cut_until_us: u64,
    /// Bytes that went through (after any corruption).
    pub bytes: u64,
    /// Bytes lost while cut.
    pub lost: u64,
    /// Keep every chunk that went through in [`Wire::log`].
    pub recording: bool,
    /// The chunks that went through, with the instant (µs) they did.
    pub log: Vec<(u64, Vec<u8>)>,
    /// Write one byte at a time, this many µs apart (into the bridge only).
    pub trickle_us: Option<u64>,
    /// Hold every byte written before this instant (µs) until then (into the bridge
    /// only; [`Wire::hold_for`]).
    pub hold_until_us: u64,
    /// What the wire does to the bytes (nothing by default).
    pub damage: Damage,
}

impl Wire {
    /// Pulls the cable out for `duration_us` from `now_us`: bytes are lost until then.
    pub fn pull_for(&mut self, now_us: u64, duration_us: u64) {
        self.cut_until_us = now_us.saturating_add(duration_us);
    }

    /// Holds the bytes for `duration_us` from `now_us`: the sender's output backs up
    /// (an FC loop overrun, a UART held by flow control, a USB-serial adapter or a host
    /// that froze), nothing is lost, and what was held then goes out back to back, with
    /// whatever the sender writes meanwhile behind it (into the bridge only).
    pub fn hold_for(&mut self, now_us: u64, duration_us: u64) {
        self.hold_until_us = now_us.saturating_add(duration_us);
    }

    /// The cable is out at `now_us`.
    #[must_use]
    pub fn is_cut(&self, now_us: u64) -> bool {
        self.cut || now_us < self.cut_until_us
    }

    /// What goes on the line for `bytes` now (`None`: lost to a cut).
    fn pass(&mut self, bytes: &[u8]) -> Option<Vec<u8>> {
        if self.is_cut(now_us()) {
            self.lost += bytes.len() as u64;
            return None;
        }
        let out = self.damage.apply(now_us(), bytes);
        self.bytes += out.len() as u64;
        if self.recording && !out.is_empty() {
            self.log.push((now_us(), out.clone()));
        }
        Some(out)
    }
}

/// The peer's writer (towards the bridge) through a [`Wire`].
pub struct WireTx<'a, W> {
    inner: W,
    wire: &'a RefCell<Wire>,
}

impl<'a, W> WireTx<'a, W> {
    /// `inner` through `wire`.
    pub const fn new(inner: W, wire: &'a RefCell<Wire>) -> Self {
        WireTx { inner, wire }
    }
}

impl<W: ErrorType> ErrorType for WireTx<'_, W> {
    type Error = W::Error;
}

impl<W: Write> Write for WireTx<'_, W> {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
        let hold = self.wire.borrow().hold_until_us;
        if now_us() < hold {
            Timer::at(EmbassyInstant::from_micros(hold)).await;
        }
        let (out, trickle) = {
            let mut w = self.wire.borrow_mut();
            (w.pass(buf), w.trickle_us)
        };
        if let Some(out) = out {
            match trickle {
                Some(gap) => {
                    for b in out {
                        self.inner.write_all(&[b]).await?;
                        Timer::after(Duration::from_micros(gap)).await;
                    }
                }
                None => self.inner.write_all(&out).await?,
            }
        }
        Ok(buf.len())
    }

    async fn flush(&mut self) -> Result<(), Self::Error> {
        self.inner.flush().await
    }
}

/// The peer's reader (from the bridge) through a [`Wire`].
pub struct WireRx<'a, R> {
    inner: R,
    wire: &'a RefCell<Wire>,
    /// Bytes that came out of the wire and did not fit the last read (garbage added).
    pending: std::collections::VecDeque<u8>,
}

impl<'a, R> WireRx<'a, R> {
    /// `inner` through `wire`.
    pub const fn new(inner: R, wire: &'a RefCell<Wire>) -> Self {
        WireRx {
            inner,
            wire,
            pending: std::collections::VecDeque::new(),
        }
    }
}

impl<R: ErrorType> ErrorType for WireRx<'_, R> {
    type Error = R::Error;
}

impl<R: Read> Read for WireRx<'_, R> {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
        loop {
            if !self.pending.is_empty() {
                let n = buf.len().min(self.pending.len());
                for (slot, b) in buf.iter_mut().zip(self.pending.drain(..n)) {
                    *slot = b;
                }
                return Ok(n);
            }
            if buf.is_empty() {
                return Ok(0);
            }
            let n = self.inner.read(buf).await?;
            if n == 0 {
                return Ok(0);
            }
            let got = buf.get(..n).unwrap_or_default();
            // Cut: lost; else what the wire makes of it (possibly nothing, or more).
            if let Some(out) = self.wire.borrow_mut().pass(got) {
                self.pending.extend(out);
            }
        }
    }
}

/// A cable between the bridge and a peer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cable {
    /// To the flight controller.
    Fc,
    /// To the pod (its UART; RTC_IO is apart).
    Pod,
    /// To the autopilot's MAVLink port on the telemetry link.
    Telemetry,
}

/// The four directions (six with a telemetry link), named from the bridge's side as
/// [`HostLinks`] is.
#[derive(Debug, Default)]
pub struct Wires<T = RefCell<Wire>> {
    /// FC → bridge.
    pub fc_in: T,
    /// Bridge → FC.
    pub fc_out: T,
    /// Pod → bridge.
    pub pod_in: T,
    /// Bridge → pod.
    pub pod_out: T,
    /// Telemetry peer → bridge (unused without a telemetry peer).
    pub tel_in: T,
    /// Bridge → telemetry peer.
    pub tel_out: T,
}

impl Wires {
    /// Records every direction.
    pub fn record_all(&self) {
        for w in [
            &self.fc_in,
            &self.fc_out,
            &self.pod_in,
            &self.pod_out,
            &self.tel_in,
            &self.tel_out,
        ] {
            w.borrow_mut().recording = true;
        }
    }

    /// Both directions of `cable`: (into the bridge, out of it).
    #[must_use]
    pub fn cable(&self, cable: Cable) -> [&RefCell<Wire>; 2] {
        match cable {
            Cable::Fc => [&self.fc_in, &self.fc_out],
            Cable::Pod => [&self.pod_in, &self.pod_out],
            Cable::Telemetry => [&self.tel_in, &self.tel_out],
        }
    }

    /// Cuts (or mends) both directions of `cable` (for the pod: not RTC_IO, use
    /// [`SimPod::set_silent`] for the whole cable).
    pub fn cut(&self, cable: Cable, cut: bool) {
        for w in self.cable(cable) {
            w.borrow_mut().cut = cut;
        }
    }

    /// Pulls `cable` out for `duration_us` from `now_us` (both directions; it is back by
    /// itself then).
    pub fn pull(&self, cable: Cable, now_us: u64, duration_us: u64) {
        for w in self.cable(cable) {
            w.borrow_mut().pull_for(now_us, duration_us);
        }
    }

    /// A faulty `cable`: `faults` in both directions, each with its own seed derived from
    /// `faults.seed` ([`Faults::derived`]: 0 into the bridge, 1 out of it).
    pub fn set_faults(&self, cable: Cable, faults: Option<Faults>) {
        for (i, w) in (0..).zip(self.cable(cable)) {
            w.borrow_mut()
                .damage
                .set_faults(faults.map(|f| f.derived(i)));
        }
    }

    fn into_inner(self) -> Wires<Wire> {
        Wires {
            fc_in: self.fc_in.into_inner(),
            fc_out: self.fc_out.into_inner(),
            pod_in: self.pod_in.into_inner(),
            pod_out: self.pod_out.into_inner(),
            tel_in: self.tel_in.into_inner(),
            tel_out: self.tel_out.into_inner(),
        }
    }
}

/// The bridge's tasks, a simulated FC and the simulated pod (and optionally a telemetry
/// peer `T`), ready to run.
pub struct Bench<P: Pilot, T: Peer = SilentFc> {
    /// The bridge's configuration.
    pub config: Config,
    /// The flight controller.
    pub fc: RefCell<P>,
    /// The pod.
    pub pod: RefCell<SimPod>,
    /// The peer on the telemetry link ([`Bench::with_telemetry`]; `None`: no telemetry
    /// link, as the firmware built without `telemetry`).
    pub telemetry: Option<RefCell<T>>,
    /// The four directions (six with a telemetry peer).
    pub wires: Wires,
    /// The GNSS module on the PPS input ([`Bench::with_pps`]; `None`: no PPS, RTC_IO a
    /// pin set at the alarm).
    pub pps: Option<PpsWiring>,
    records: RefCell<Vec<LogRecord>>,
    rtc_edges: RefCell<Vec<(Level, InstantNs)>>,
    shared: HostShared,
    links: HostLinks,
}

/// What a run leaves: the peers, the wires, the tasks' records and the engine.
pub struct Outcome<P, T = SilentFc> {
    /// The flight controller.
    pub fc: P,
    /// The pod.
    pub pod: SimPod,
    /// The telemetry peer, when the bench had one.
    pub telemetry: Option<T>,
    /// The four directions (with their logs when recorded).
    pub wires: Wires<Wire>,
    /// Every record of the tasks' log task, in order.
    pub records: Vec<LogRecord>,
    /// Records the log task could not take in time (must be 0).
    pub records_dropped: u32,
    /// The engine at the end.
    pub engine: Engine,
    /// Virtual time at the end, µs.
    pub end_us: u64,
    /// The GNSS module and crystal of a bench with PPS.
    pub pps: Option<PpsWiring>,
    /// With PPS: every RTC_IO change at the bridge's local instant the timer compare made
    /// it (ns).
    pub rtc_edges_ns: Vec<(Level, InstantNs)>,
}

impl<P: Pilot> Bench<P> {
    /// The bridge configured for `P`'s protocol, `fc`, and the pod with its defaults.
    pub fn new(fc: P) -> Self {
        Self::with(
            Config::for_fc(P::PROTOCOL),
            fc,
            SimPod::new(PodSimConfig::default()),
        )
    }

    /// A bench of these parts, no telemetry link.
    pub fn with(config: Config, fc: P, pod: SimPod) -> Self {
        Self::of(config, fc, pod, None)
    }
}

impl<P: Pilot, T: Peer> Bench<P, T> {
    /// A bench of these parts with `telemetry` on the bridge's telemetry link (at
    /// `config.telemetry_baud`): an autopilot's MAVLink 2 port beside its FC port.
    pub fn with_telemetry(config: Config, fc: P, pod: SimPod, telemetry: T) -> Self {
        Self::of(config, fc, pod, Some(telemetry))
    }

    /// A bench of these parts, with a telemetry peer or not.
    pub fn of(config: Config, fc: P, pod: SimPod, telemetry: Option<T>) -> Self {
        let links = if telemetry.is_some() {
            HostLinks::with_telemetry()
        } else {
            HostLinks::new()
        };
        Bench {
            config,
            fc: RefCell::new(fc),
            pod: RefCell::new(pod),
            telemetry: telemetry.map(RefCell::new),
            wires: Wires::default(),
            pps: None,
            records: RefCell::new(Vec::new()),
            rtc_edges: RefCell::new(Vec::new()),
            shared: HostShared::new(
                Engine::with_build(config, bridge_fw::config::BUILD),
                Timing::from_config(&config),
            ),
            links,
        }
    }

    /// The same bench with `wiring`'s GNSS module on the bridge's PPS input and RTC_IO
    /// driven as the board's timer compare drives it.
    #[must_use]
    pub fn with_pps(mut self, wiring: PpsWiring) -> Self {
        self.pps = Some(wiring);
        self
    }

    /// Runs `f` on the engine (for a script: read its state, its counters).
    pub fn engine<R>(&self, f: impl FnOnce(&mut Engine) -> R) -> R {
        self.shared.with(f)
    }

    /// The records so far.
    pub fn records(&self) -> core::cell::Ref<'_, Vec<LogRecord>> {
        self.records.borrow()
    }

    /// Runs every task of the bridge (but the LED) and the peers until `end_us` of
    /// virtual time; `script(bench, now_us)` is called at 0 and then every `tick_us`.
    ///
    /// # Panics
    /// When a peer's stream fails (it never does on pipes).
    pub fn run(self, end_us: u64, tick_us: u64, script: impl FnMut(&Self, u64)) -> Outcome<P, T> {
        match &self.pps {
            Some(wiring) => {
                let wiring = wiring.clone();
                let pin = ComparePin::new(PodPin::new(&self.pod), &self.rtc_edges);
                self.run_with(pin, CapturedPps::new(&wiring), end_us, tick_us, script);
            }
            None => {
                let pin = PodPin::new(&self.pod);
                self.run_with(pin, NoPps, end_us, tick_us, script);
            }
        }
        let engine = self.shared.with(|e| e.clone());
        let records_dropped = self.shared.records_dropped();
        Outcome {
            fc: self.fc.into_inner(),
            pod: self.pod.into_inner(),
            telemetry: self.telemetry.map(RefCell::into_inner),
            wires: self.wires.into_inner(),
            records: self.records.into_inner(),
            records_dropped,
            engine,
            end_us,
            pps: self.pps,
            rtc_edges_ns: self.rtc_edges.into_inner(),
        }
    }

    /// [`Bench::run`] with this RTC_IO output and PPS input.
    fn run_with(
        &self,
        rtc_io: impl RtcIo,
        pps: impl bridge_fw::PpsInput,
        end_us: u64,
        tick_us: u64,
        mut script: impl FnMut(&Self, u64),
    ) {
        let baud = (
            self.config.fc_baud,
            self.config.pod_baud,
            self.config.telemetry_baud,
        );
        host::run(Clock::Virtual, || async {
            let sink = |r: &LogRecord| self.records.borrow_mut().push(*r);
            let bridge = host::bridge_with_pps(&self.shared, &self.links, rtc_io, pps, sink, || {});
            let fc = run_peer(
                &self.fc,
                WireRx::new(&self.links.fc_tx, &self.wires.fc_out),
                WireTx::new(&self.links.fc_rx, &self.wires.fc_in),
                baud.0,
            );
            let pod = run_peer(
                &self.pod,
                WireRx::new(&self.links.pod_tx, &self.wires.pod_out),
                WireTx::new(&self.links.pod_rx, &self.wires.pod_in),
                baud.1,
            );
            let telemetry = async {
                match (&self.telemetry, &self.links.telemetry) {
                    (Some(peer), Some(link)) => {
                        run_peer(
                            peer,
                            WireRx::new(&link.tx, &self.wires.tel_out),
                            WireTx::new(&link.rx, &self.wires.tel_in),
                            baud.2,
                        )
                        .await
                    }
                    _ => core::future::pending().await,
                }
            };
            let clock = async {
                let mut t = 0;
                while t < end_us {
                    script(self, t);
                    t = (t + tick_us.max(1)).min(end_us);
                    Timer::at(EmbassyInstant::from_micros(t)).await;
                }
            };
            match select3(bridge, select3(fc, pod, telemetry), clock).await {
                Either3::First(never) => match never {},
                Either3::Second(ended) => {
                    let e: Result<Infallible, _> = match ended {
                        Either3::First(r) | Either3::Second(r) | Either3::Third(r) => r,
                    };
                    #[allow(clippy::panic)]
                    {
                        panic!("a peer ended: {e:?}");
                    }
                }
                Either3::Third(()) => {}
            }
        });
    }
}

impl<P, T> Outcome<P, T> {
    /// The engine events, with the local instant the log task took them (µs).
    pub fn events(&self) -> impl Iterator<Item = (u64, Event)> + '_ {
        self.records.iter().filter_map(|r| match r.what {
            LogKind::Engine(e) => Some((r.at.as_micros(), e)),
            _ => None,
        })
    }

    /// RTC_IO changes to `level`, as the pin task made them (µs).
    #[must_use]
    pub fn pin_changes(&self, level: Level) -> Vec<u64> {
        self.records
            .iter()
            .filter(|r| r.what == LogKind::Pin(level))
            .map(|r| r.at.as_micros())
            .collect()
    }

    /// Every `EdgeToFrame` record: (edge instant µs, delay µs, frame length).
    #[must_use]
    pub fn edge_to_frame(&self) -> Vec<(u64, u64, u16)> {
        self.records
            .iter()
            .filter_map(|r| match r.what {
                LogKind::EdgeToFrame { delay, len } => {
                    Some((r.at.as_micros() - delay.as_micros(), delay.as_micros(), len))
                }
                _ => None,
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bridge_fw::host::HostPipe;
    use embassy_futures::select::select;

    #[test]
    fn a_wire_corrupts_and_cuts_both_directions() {
        let from_bridge = HostPipe::new();
        let to_bridge = HostPipe::new();
        let (rx, tx) = (RefCell::new(Wire::default()), RefCell::new(Wire::default()));
        // Every bit flipped on the way from the bridge, one garbage byte before each
        // byte on the way to it.
        rx.borrow_mut()
            .damage
            .set_faults(Some(Faults::bit_errors(1.0, 1)));
        tx.borrow_mut().damage.set_faults(Some(Faults {
            garbage_rate: 1.0,
            ..Faults::NONE
        }));
        let (got, sent) = host::run(Clock::Virtual, || async {
            let mut peer_rx = WireRx::new(&from_bridge, &rx);
            let mut peer_tx = WireTx::new(&to_bridge, &tx);
            from_bridge.write_all(&[0x00, 0xF0, 0x3C]).await;
            // A read smaller than what came: the rest waits for the next one.
            let mut one = [0u8; 1];
            let mut got = Vec::new();
            while got.len() < 3 {
                let n = peer_rx.read(&mut one).await.unwrap();
                got.extend_from_slice(&one[..n]);
            }
            peer_tx.write_all(&[1, 2]).await.unwrap();
            let mut buf = [0u8; 8];
            let n = to_bridge.read(&mut buf).await;
            // Pulled out for 1 s: what the bridge writes then is lost.
            rx.borrow_mut().pull_for(now_us(), 1_000_000);
            from_bridge.write_all(&[0x55]).await;
            // The peer reads on: the byte is taken from the bridge and lost.
            let _ = select(
                peer_rx.read(&mut one),
                Timer::after(Duration::from_micros(10)),
            )
            .await;
            assert!(rx.borrow().is_cut(now_us()));
            Timer::after(Duration::from_millis(1_000)).await;
            from_bridge.write_all(&[0x0F]).await;
            let n2 = peer_rx.read(&mut one).await.unwrap();
            got.extend_from_slice(&one[..n2]);
            (got, buf[..n].to_vec())
        });
        assert_eq!(got, [0xFF, 0x0F, 0xC3, 0xF0], "0x55 lost to the pull");
        assert_eq!(sent.len(), 4);
        assert_eq!((sent[1], sent[3]), (1, 2));
        let (r, t) = (rx.into_inner(), tx.into_inner());
        assert_eq!(r.lost, 1);
        assert_eq!(r.damage.fault_stats().unwrap().bits_flipped, 32);
        assert_eq!(t.damage.fault_stats().unwrap().garbage_bytes, 2);
        assert_eq!(t.bytes, 4);
    }
}
