//! The board's two timer channels in the task bench ([`super::tasks::Bench::with_pps`]):
//! the PPS input capture ([`CapturedPps`], a [`PpsInput`] fed by the simulated GNSS
//! module through the bridge's crystal) and the RTC_IO output compare ([`ComparePin`],
//! an [`RtcIo`] that records each edge at the nanosecond the compare puts it). Both
//! quantize to the board's timer tick (TIM2 at 80 MHz: 12.5 ns).

use core::cell::RefCell;

use bridge_engine::{Instant, InstantNs, Level, PinAction};
use bridge_fw::{PpsInput, RtcIo};
use embassy_time::{Instant as EmbassyInstant, Timer};

use super::gnss::{Crystal, GnssPps};
use super::peer::PodPin;

/// The board's timer tick, ps (80 MHz).
const TICK_PS: i128 = 12_500;
/// From the capture to the task reading it, µs (an interrupt and a task hand-over).
const CAPTURE_READ_US: u64 = 3;

/// `ns` down to the timer's tick.
fn to_tick(ns: i128) -> i128 {
    (ns * 1_000).div_euclid(TICK_PS) * TICK_PS / 1_000
}

/// The GNSS module wired to the bridge's PPS input, as the bench runs it.
#[derive(Debug, Clone, PartialEq)]
pub struct PpsWiring {
    /// The module.
    pub gnss: GnssPps,
    /// The bridge's crystal against true time (the bench's virtual time is the bridge's
    /// clock).
    pub crystal: Crystal,
    /// The bridge captures the falling edge (`[pps] active_low`).
    pub bridge_active_low: bool,
}

impl PpsWiring {
    /// The true UTC (ns since the Unix epoch) at the bridge's local instant `local_ns`.
    #[must_use]
    pub fn utc_ns_at_local(&self, local_ns: i128) -> i128 {
        self.gnss.utc_ns(self.crystal.true_ns(local_ns))
    }
}

/// TIM2 CH1's capture of the simulated module's pulses.
#[derive(Debug)]
pub struct CapturedPps<'a> {
    wiring: &'a PpsWiring,
    /// The last capture, true ns.
    last: Option<i128>,
}

impl<'a> CapturedPps<'a> {
    /// The capture of `wiring`'s pulses from the start of the run.
    #[must_use]
    pub const fn new(wiring: &'a PpsWiring) -> Self {
        CapturedPps { wiring, last: None }
    }
}

impl PpsInput for CapturedPps<'_> {
    async fn edge(&mut self) -> InstantNs {
        let w = self.wiring;
        let from = self.last.map_or(0, |t| t + 1);
        let Some((_, t)) = w.gnss.next_edge(from, w.bridge_active_low) else {
            return core::future::pending().await;
        };
        self.last = Some(t);
        let local = to_tick(w.crystal.local_ns(t)).max(0);
        let read_at = u64::try_from(local / 1_000).unwrap_or(0) + CAPTURE_READ_US;
        Timer::at(EmbassyInstant::from_micros(read_at)).await;
        InstantNs::from_nanos(u64::try_from(local).unwrap_or(0))
    }
}

/// TIM2 CH3's compare driving the simulated pod's RTC_IO: each change at the instant
/// planned, to the tick, recorded.
pub struct ComparePin<'a> {
    pin: PodPin<'a>,
    edges: &'a RefCell<Vec<(Level, InstantNs)>>,
}

impl<'a> ComparePin<'a> {
    /// `pin` driven by the compare, its edges recorded in `edges`.
    #[must_use]
    pub const fn new(pin: PodPin<'a>, edges: &'a RefCell<Vec<(Level, InstantNs)>>) -> Self {
        ComparePin { pin, edges }
    }
}

impl RtcIo for ComparePin<'_> {
    fn complete(&mut self, action: PinAction) -> (Instant, bool) {
        let at = InstantNs::from_instant(action.at).saturating_add_ns(u64::from(action.sub_us_ns));
        let at =
            InstantNs::from_nanos(u64::try_from(to_tick(i128::from(at.as_nanos()))).unwrap_or(0));
        // The pod sees the edge at the task's instant, which is the compare's microsecond.
        let (_, ok) = self.pin.complete(action);
        self.edges.borrow_mut().push((action.level, at));
        (action.at, ok)
    }
}
