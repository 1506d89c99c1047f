//! RTC_IO sync scheduling: when to raise the pod's RTC_IO pin and which UTC the
//! following K40T 0x00030E frame carries.
//!
//! Edges fall on UTC instants that are whole multiples of the period since the Unix
//! epoch (every 10 s by default: …:00, …:10, …:20), so the stamped value is exact in
//! milliseconds and carries no rounding error; the discipline maps that UTC instant to
//! the local [`Instant`] at which the pin must rise. An edge is always planned at least
//! [`SyncConfig::lead`] after the current time, so that the caller can arm a timer for it.
//!
//! No edge is ever planned unless the [`TimeDiscipline`] gives UTC, i.e. it is
//! [`Valid`](super::discipline::DisciplineState::Valid) or in
//! [`Holdover`](super::discipline::DisciplineState::Holdover) (an extrapolation of a
//! converged fit, limited to [`DisciplineConfig::holdover`](super::discipline::DisciplineConfig::holdover),
//! 60 s by default). `Unknown`, `Converging` and `Lost` give no edge.

use super::discipline::TimeDiscipline;
use super::time::{Duration, Instant, UtcTime};

protocol_core::wire_derive! {
    [Eq]
    /// Settings of the [`SyncScheduler`].
    #[cfg_attr(
        feature = "serde",
        derive(serde::Deserialize),
        serde(default, deny_unknown_fields)
    )]
    #[cfg_attr(feature = "bake", derive(databake::Bake), databake(path = bridge_engine::sync))]
    pub struct SyncConfig {
        /// Time between edges; edges fall on whole multiples of it in UTC (default 10 s).
        /// Configuration file: `[sync] period_ms`.
        #[cfg_attr(
            feature = "serde",
            serde(
                rename(deserialize = "period_ms"),
                deserialize_with = "super::config::de::ms"
            )
        )]
        pub period: Duration,
        /// How long the pin stays high (default 50 ms; the K40T document does not say).
        /// Configuration file: `[sync] width_ms`.
        #[cfg_attr(
            feature = "serde",
            serde(
                rename(deserialize = "width_ms"),
                deserialize_with = "super::config::de::ms"
            )
        )]
        pub width: Duration,
        /// Least time between planning an edge and the edge (default 2 ms).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub lead: Duration,
        /// How late the pin may rise and still carry the planned UTC (default 20 µs); later
        /// than that, [`SyncScheduler::stamp`] re-stamps it from the discipline.
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub late_tolerance: Duration,
        /// No edge is planned, and no 0x00030E sent, while the discipline believes its UTC
        /// at the edge may be off by more than this (default 30 ms): a wrong stamp is worse
        /// than none.
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub max_error: Duration,
    }
}

impl SyncConfig {
    /// The documented defaults.
    pub const DEFAULT: Self = Self {
        period: Duration::from_secs(10),
        width: Duration::from_millis(50),
        lead: Duration::from_millis(2),
        late_tolerance: Duration::from_micros(20),
        max_error: Duration::from_millis(30),
    };
}

impl Default for SyncConfig {
    fn default() -> Self {
        Self::DEFAULT
    }
}

protocol_core::wire_derive! {
    [Eq]
    /// One planned RTC_IO pulse.
    pub struct SyncEdge {
        /// Local instant at which the pin rises (the microsecond it falls in).
        pub at: Instant,
        /// Nanoseconds after `at` (0..1000) at which it rises: the PPS-locked mapping's
        /// resolution, for a timer's output compare (0 from the FC's mapping).
        pub sub_us_ns: u16,
        /// UTC of the rising edge: the value of 0x00030E (`utc.as_unix_millis()`, exact).
        pub utc: UtcTime,
        /// Local instant at which the pin falls (`at + width`).
        pub low_at: Instant,
    }
}

/// Plans RTC_IO edges on the UTC grid.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SyncScheduler {
    config: SyncConfig,
    /// UTC of the last edge reported by [`fired`](Self::fired).
    last: Option<UtcTime>,
}

impl Default for SyncScheduler {
    fn default() -> Self {
        Self::new(SyncConfig::DEFAULT)
    }
}

impl SyncScheduler {
    /// A scheduler that has fired no edge yet.
    #[must_use]
    pub const fn new(config: SyncConfig) -> Self {
        Self { config, last: None }
    }

    /// The settings.
    #[must_use]
    pub const fn config(&self) -> &SyncConfig {
        &self.config
    }

    /// UTC of the last edge reported fired.
    #[must_use]
    pub const fn last_fired(&self) -> Option<UtcTime> {
        self.last
    }

    /// The next edge: the first UTC multiple of the period, later than the last fired
    /// edge, whose local instant is at least `lead` after `now`. `None` while the
    /// discipline gives no UTC, or believes it off by more than
    /// [`SyncConfig::max_error`] at the edge (or the period is zero).
    ///
    /// Pure: call it again after new samples to refine `at`; once the caller has armed
    /// its timer (within `lead` of the edge) it keeps the edge it has.
    #[must_use]
    pub fn next_edge(&self, now: Instant, discipline: &TimeDiscipline) -> Option<SyncEdge> {
        let earliest = now.checked_add(self.config.lead)?;
        let utc_earliest = discipline.utc(earliest)?;
        let mut target = utc_earliest.next_multiple_of(self.config.period)?;
        if let Some(last) = self.last
            && target <= last
        {
            target = last.checked_add(self.config.period)?;
        }
        // Two tries: local_of may round the edge a microsecond before `earliest`.
        for _ in 0..2 {
            let at_ns = discipline.local_of_ns(target)?;
            let at = at_ns.instant();
            if at >= earliest {
                if discipline.error_bound(at)? > self.config.max_error {
                    return None;
                }
                return Some(SyncEdge {
                    at,
                    sub_us_ns: at_ns.sub_micros_ns(),
                    utc: target,
                    low_at: at.checked_add(self.config.width)?,
                });
            }
            target = target.checked_add(self.config.period)?;
        }
        None
    }

    /// Records that `edge` was raised, so that it is not planned again.
    pub fn fired(&mut self, edge: &SyncEdge) {
        if self.last.is_none_or(|l| edge.utc > l) {
            self.last = Some(edge.utc);
        }
    }

    /// The UTC to send for `edge` when the pin actually rose at `raised_at`: the planned
    /// `edge.utc` if it rose within [`SyncConfig::late_tolerance`] of `edge.at`, else the
    /// discipline's UTC of `raised_at` (`None` if the discipline has none, or believes
    /// it off by more than [`SyncConfig::max_error`]: send no 0x00030E then).
    #[must_use]
    pub fn stamp(
        &self,
        edge: &SyncEdge,
        raised_at: Instant,
        discipline: &TimeDiscipline,
    ) -> Option<UtcTime> {
        let off = raised_at.as_micros().abs_diff(edge.at.as_micros());
        if discipline.error_bound(raised_at)? > self.config.max_error {
            None
        } else if off <= self.config.late_tolerance.as_micros() {
            Some(edge.utc)
        } else {
            discipline.utc(raised_at)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::discipline::{DisciplineConfig, Sample};

    const U0: u64 = 1_767_225_603_250_000; // …:03.250

    /// A discipline fed exact UTC (local = t + 1 s, no drift) for 60 s.
    fn valid() -> TimeDiscipline {
        let mut d = TimeDiscipline::new(DisciplineConfig::DEFAULT);
        let mut t = 0u64;
        while t < 60_000_000 {
            d.utc_sample(Sample::new(Instant::from_micros(1_000_000 + t), U0 + t, 1));
            t += 100_000;
        }
        d
    }

    #[test]
    fn no_edge_without_utc() {
        let d = TimeDiscipline::new(DisciplineConfig::DEFAULT);
        let s = SyncScheduler::default();
        assert_eq!(s.next_edge(Instant::from_micros(1), &d), None);
    }

    #[test]
    fn edges_on_the_utc_grid() {
        let d = valid();
        let mut s = SyncScheduler::default();
        // Now: local 61 s = UTC …:03.250 + 60 s = …:63.250 → next multiple …:70.000.
        let now = Instant::from_micros(61_000_000);
        let e = s.next_edge(now, &d).unwrap();
        assert_eq!(e.utc.as_unix_micros() % 10_000_000, 0);
        assert_eq!(e.utc.as_unix_micros(), 1_767_225_670_000_000);
        assert_eq!(e.at.as_micros(), 1_000_000 + 1_767_225_670_000_000 - U0);
        assert_eq!(e.low_at.as_micros(), e.at.as_micros() + 50_000);
        // Asked again before firing: the same edge; after firing: 10 s later.
        assert_eq!(s.next_edge(now, &d), Some(e));
        s.fired(&e);
        assert_eq!(s.last_fired(), Some(e.utc));
        let e2 = s.next_edge(e.at, &d).unwrap();
        assert_eq!(e2.utc.as_unix_micros(), e.utc.as_unix_micros() + 10_000_000);
        // Stamping: on time → the planned value; 1 ms late → re-stamped.
        assert_eq!(s.stamp(&e, e.at, &d), Some(e.utc));
        let late = e.at.checked_add(Duration::from_millis(1)).unwrap();
        assert_eq!(
            s.stamp(&e, late, &d).map(UtcTime::as_unix_micros),
            Some(e.utc.as_unix_micros() + 1_000)
        );
    }

    #[test]
    fn edge_respects_the_lead() {
        let d = valid();
        let s = SyncScheduler::default();
        // 1 ms before an edge (…:70.000 at local 1 s + 66.75 s): too close, the next one.
        let at70 = 1_000_000 + 1_767_225_670_000_000 - U0;
        let e = s.next_edge(Instant::from_micros(at70 - 1_000), &d).unwrap();
        assert_eq!(e.utc.as_unix_micros(), 1_767_225_680_000_000);
        let e = s.next_edge(Instant::from_micros(at70 - 2_000), &d).unwrap();
        assert_eq!(e.utc.as_unix_micros(), 1_767_225_670_000_000);
    }
}
