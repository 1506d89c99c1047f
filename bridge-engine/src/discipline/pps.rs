//! The PPS estimator: the local clock fitted to a GNSS receiver's pulse-per-second edges,
//! each labelled with its UTC second (see the [discipline](super), "PPS").
//!
//! Every accepted edge is a point `(second, local ns)`: the local instant (a timer's
//! capture, in nanoseconds) at which UTC was that whole second, to within the module's
//! jitter (tens of nanoseconds) and the capture's resolution. A least-squares line over the
//! last [`PpsConfig::window`] edges gives the local clock's rate and phase against UTC;
//! integer arithmetic only (`i128` sums), no allocation, [`PPS_EDGES`] points of 16 bytes.

use crate::time::Duration;

/// Most edges the estimator keeps (the fit's window is at most this).
pub const PPS_EDGES: usize = 16;

/// Nanoseconds in one second.
const NS_PER_S: i128 = 1_000_000_000;

protocol_core::wire_derive! {
    [Eq]
    /// Settings of the PPS path (configuration file: `[pps] active_low`; the others are
    /// fixed).
    #[cfg_attr(
        feature = "serde",
        derive(serde::Deserialize),
        serde(default, deny_unknown_fields)
    )]
    #[cfg_attr(
        feature = "bake",
        derive(databake::Bake),
        databake(path = bridge_engine::discipline)
    )]
    pub struct PpsConfig {
        /// The GNSS module's pulse is active low: its on-time edge is the falling one
        /// (default false: a u-blox time pulse rises at the second). The firmware
        /// captures that edge. Configuration file: `[pps] active_low`.
        pub active_low: bool,
        /// Edges in the line fit (default 16, at most [`PPS_EDGES`]).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub window: u8,
        /// Consecutive consistent labelled edges before the clock is locked to them
        /// (default 2: the second edge gives the rate).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub lock_edges: u8,
        /// Least distance from the fitted line at which an edge is an outlier, ns (default
        /// 10 µs; the tolerance grows with the spread of the recent edges and with the
        /// time since the last one).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub tolerance_ns: u32,
        /// Error believed of one edge, ns (default 100: a module's jitter and a timer's
        /// capture resolution, with margin): the least error bound of a locked clock.
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub edge_error_ns: u32,
        /// No edge for this long: the lock is lost and the clock runs on its last rate
        /// (holdover; default 2.5 s: one missing pulse is not a loss).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub timeout: Duration,
        /// The error bound grows at this rate from the last edge, ppm (default 2: a
        /// crystal's drift from the rate learnt, over a few degrees; an RC oscillator
        /// needs far more).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub holdover_ppm: u32,
        /// Longest holdover on the PPS line after the last edge (default 20 min).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub holdover: Duration,
        /// An edge labelled from the FC's UTC must lie within this, plus the error the FC's
        /// mapping believes it has, of a whole second (default 50 ms): a pulse before the
        /// module's fix or of the wrong polarity is not taken for a second.
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub label_tolerance: Duration,
        /// Rate at which the mapping slews from the PPS line to the FC's when the FC's
        /// becomes the better one, ppm (default 100: 1 ms in 10 s).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub handback_slew_ppm: u32,
    }
}

impl PpsConfig {
    /// The documented defaults.
    pub const DEFAULT: Self = Self {
        active_low: false,
        window: 16,
        lock_edges: 2,
        tolerance_ns: 10_000,
        edge_error_ns: 100,
        timeout: Duration::from_millis(2500),
        holdover_ppm: 2,
        holdover: Duration::from_secs(1200),
        label_tolerance: Duration::from_millis(50),
        handback_slew_ppm: 100,
    };
}

impl Default for PpsConfig {
    fn default() -> Self {
        Self::DEFAULT
    }
}

protocol_core::wire_derive! {
    [Eq, Hash]
    /// What the discipline did with one PPS edge.
    pub enum PpsVerdict {
        /// Labelled and used.
        Accepted,
        /// No UTC second could be named for it (no UTC from the FC, or the FC's UTC at the
        /// edge is not near enough a whole second): not used.
        Unlabelled,
        /// Too far from the line of the previous edges: not used (a glitch); three in a
        /// row restart the estimator.
        Outlier,
        /// The FC's UTC names another second than the PPS line does: the line's label is
        /// used; five in a row restart the estimator from the FC's label.
        Conflict,
        /// Earlier than the last edge taken, or beyond the arithmetic's range.
        Rejected,
    }
}

/// One labelled edge.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(super) struct Edge {
    /// Its UTC second (Unix seconds).
    pub(super) second: i64,
    /// Its local instant, ns.
    pub(super) local_ns: i64,
}

/// `local_ns(s) = y_ref + (c + b·(s − s_ref))/den`, `s` in (fractional) UTC seconds,
/// `b/den` the local nanoseconds per UTC second (> 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct PpsLine {
    s_ref: i64,
    y_ref: i64,
    c: i128,
    b: i128,
    den: i128,
}

impl PpsLine {
    /// The local instant (ns) at which UTC is `utc_ns`, rounded to the nearest.
    pub(super) fn local_ns(&self, utc_ns: i128) -> Option<i128> {
        let k_ns = utc_ns.checked_sub(i128::from(self.s_ref).checked_mul(NS_PER_S)?)?;
        let num = self
            .c
            .checked_mul(NS_PER_S)?
            .checked_add(self.b.checked_mul(k_ns)?)?;
        let den = self.den.checked_mul(NS_PER_S)?;
        i128::from(self.y_ref).checked_add(div_round(num, den)?)
    }

    /// UTC (ns since the Unix epoch) at local `local_ns`, rounded to the nearest.
    pub(super) fn utc_ns(&self, local_ns: i128) -> Option<i128> {
        let dy = local_ns.checked_sub(i128::from(self.y_ref))?;
        let num = dy
            .checked_mul(self.den)?
            .checked_sub(self.c)?
            .checked_mul(NS_PER_S)?;
        i128::from(self.s_ref)
            .checked_mul(NS_PER_S)?
            .checked_add(div_round(num, self.b)?)
    }

    /// The local clock's rate error against UTC, parts per billion (positive: fast).
    pub(super) fn drift_ppb(&self) -> Option<i64> {
        // b/den ns per s: (b/den − 1e9) ppb.
        let v = self.b.checked_sub(self.den.checked_mul(NS_PER_S)?)?;
        i64::try_from(v.checked_div(self.den)?).ok()
    }
}

/// `num/den` rounded to the nearest (`den > 0`).
fn div_round(num: i128, den: i128) -> Option<i128> {
    if den <= 0 {
        return None;
    }
    num.checked_add(den / 2)?.checked_div_euclid(den)
}

/// The estimator's state; [`super::TimeDiscipline`] labels the edges and uses its line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct PpsEstimator {
    edges: [Edge; PPS_EDGES],
    /// Physical index of the oldest edge.
    start: u8,
    /// Edges in use.
    len: u8,
    pub(super) line: Option<PpsLine>,
    /// Consecutive consistent edges make it locked; the timeout ends it.
    pub(super) locked: bool,
    /// The first edge of the current run (since the estimator started or was restarted).
    pub(super) run_start: Option<i64>,
    /// Mean |residual| of the recent edges, ns.
    pub(super) spread_ns: u64,
    /// Consecutive outliers.
    outliers: u8,
    /// Consecutive label conflicts.
    conflicts: u8,
}

/// Consecutive outliers that restart the estimator.
const OUTLIER_RESTART: u8 = 3;
/// Consecutive label conflicts that restart it from the FC's label.
const CONFLICT_RESTART: u8 = 5;
/// An edge further than this from the newest is dropped from the fit (the crystal's rate
/// wanders; a fit over a long gap would mix two rates).
const MAX_SPAN_S: i64 = 64;
/// Largest rate error of a local clock that is taken for one, ppm (the discipline's
/// `max_drift_ppm` is for two clocks).
const MAX_RATE_PPM: i128 = 300;

impl PpsEstimator {
    pub(super) const fn new() -> Self {
        Self {
            edges: [Edge {
                second: 0,
                local_ns: 0,
            }; PPS_EDGES],
            start: 0,
            len: 0,
            line: None,
            locked: false,
            run_start: None,
            spread_ns: 0,
            outliers: 0,
            conflicts: 0,
        }
    }

    pub(super) fn restart(&mut self) {
        *self = Self::new();
    }

    fn edge(&self, i: u8) -> Option<Edge> {
        let idx = usize::from(self.start).checked_add(usize::from(i))? % PPS_EDGES;
        self.edges.get(idx).copied()
    }

    /// The newest edge taken.
    pub(super) fn last(&self) -> Option<Edge> {
        self.edge(self.len.checked_sub(1)?)
    }

    /// The second the line names for an edge at `local_ns` (`None`: no line).
    pub(super) fn label(&self, local_ns: i64) -> Option<i64> {
        let utc = self.line?.utc_ns(i128::from(local_ns))?;
        i64::try_from(div_round(utc, NS_PER_S)?).ok()
    }

    /// How far an edge labelled `second` at `local_ns` may lie from the line, ns:
    /// the configured least, four times the recent spread, and the drift the clock may
    /// have taken since the last edge (before the rate is known: any plausible rate).
    fn tolerance(&self, second: i64, cfg: &super::PpsConfig) -> i128 {
        let gap = self
            .last()
            .map_or(0, |l| i128::from(second.saturating_sub(l.second)).abs());
        let ppm = if self.len >= 2 {
            i128::from(cfg.holdover_ppm).max(1)
        } else {
            MAX_RATE_PPM
        };
        i128::from(cfg.tolerance_ns)
            .saturating_add(i128::from(self.spread_ns).saturating_mul(4))
            .saturating_add(gap.saturating_mul(ppm).saturating_mul(1_000))
    }

    /// Takes an edge labelled `second` at `local_ns`; `Outlier` when it is too far from
    /// the line. Returns whether it was taken.
    pub(super) fn take(&mut self, e: Edge, cfg: &super::PpsConfig) -> Result<(), PpsVerdict> {
        if self
            .last()
            .is_some_and(|l| e.second <= l.second || e.local_ns <= l.local_ns)
        {
            return Err(PpsVerdict::Rejected);
        }
        let residual = match self.line {
            Some(line) => {
                let predicted = line
                    .local_ns(i128::from(e.second).saturating_mul(NS_PER_S))
                    .ok_or(PpsVerdict::Rejected)?;
                i128::from(e.local_ns).saturating_sub(predicted)
            }
            None => 0,
        };
        if residual.abs() > self.tolerance(e.second, cfg) {
            self.outliers = self.outliers.saturating_add(1);
            if self.outliers >= OUTLIER_RESTART {
                // The pulse moved for good (the module re-acquired): start again from it.
                self.restart();
                self.push(e, cfg);
            }
            return Err(PpsVerdict::Outlier);
        }
        self.outliers = 0;
        let r = u64::try_from(residual.unsigned_abs()).unwrap_or(u64::MAX);
        if self.len >= 2 {
            // Mean of |residual| over about eight edges.
            let s = i128::from(self.spread_ns);
            let next = s.saturating_add((i128::from(r).saturating_sub(s)) / 8);
            self.spread_ns = u64::try_from(next.max(0)).unwrap_or(u64::MAX);
        }
        self.push(e, cfg);
        Ok(())
    }

    /// A label conflict with the FC's UTC: counts it; true when the estimator must
    /// restart from the FC's label.
    pub(super) fn conflict(&mut self) -> bool {
        self.conflicts = self.conflicts.saturating_add(1);
        self.conflicts >= CONFLICT_RESTART
    }

    /// The labels agreed.
    pub(super) fn agreed(&mut self) {
        self.conflicts = 0;
    }

    fn push(&mut self, e: Edge, cfg: &super::PpsConfig) {
        let window = u8::try_from(usize::from(cfg.window).clamp(2, PPS_EDGES)).unwrap_or(2);
        // Edges beyond the span or the window go first.
        while self.len > 0
            && (self.len >= window
                || self
                    .edge(0)
                    .is_some_and(|o| e.second.saturating_sub(o.second) > MAX_SPAN_S))
        {
            self.start =
                u8::try_from(usize::from(self.start).saturating_add(1) % PPS_EDGES).unwrap_or(0);
            self.len = self.len.saturating_sub(1);
        }
        let idx = usize::from(self.start).saturating_add(usize::from(self.len)) % PPS_EDGES;
        if let Some(slot) = self.edges.get_mut(idx) {
            *slot = e;
            self.len = self.len.saturating_add(1);
        }
        if self.run_start.is_none() {
            self.run_start = Some(e.local_ns);
        }
        self.line = self.fit();
        if self.len >= cfg.lock_edges.max(2) && self.rate_plausible() {
            self.locked = true;
        }
    }

    /// The line's rate is a plausible local clock's.
    fn rate_plausible(&self) -> bool {
        self.line
            .and_then(|l| l.drift_ppb())
            .is_some_and(|ppb| i128::from(ppb).abs() <= MAX_RATE_PPM.saturating_mul(1_000))
    }

    /// The least-squares line over the edges (one edge: the nominal rate through it).
    // The names are those of the fit's formulas.
    #[allow(clippy::many_single_char_names)]
    fn fit(&self) -> Option<PpsLine> {
        let newest = self.last()?;
        let n = i128::from(self.len);
        if n < 2 {
            return Some(PpsLine {
                s_ref: newest.second,
                y_ref: newest.local_ns,
                c: 0,
                b: NS_PER_S,
                den: 1,
            });
        }
        let (mut sk, mut sy, mut skk, mut sky) = (0i128, 0i128, 0i128, 0i128);
        for i in 0..self.len {
            let e = self.edge(i)?;
            let k = i128::from(e.second.checked_sub(newest.second)?);
            let y = i128::from(e.local_ns.checked_sub(newest.local_ns)?);
            sk = sk.checked_add(k)?;
            sy = sy.checked_add(y)?;
            skk = skk.checked_add(k.checked_mul(k)?)?;
            sky = sky.checked_add(k.checked_mul(y)?)?;
        }
        let den0 = n.checked_mul(skk)?.checked_sub(sk.checked_mul(sk)?)?;
        if den0 <= 0 {
            return None;
        }
        let b_num = n.checked_mul(sky)?.checked_sub(sk.checked_mul(sy)?)?;
        if b_num <= 0 {
            return None;
        }
        Some(PpsLine {
            s_ref: newest.second,
            y_ref: newest.local_ns,
            c: sy.checked_mul(den0)?.checked_sub(b_num.checked_mul(sk)?)?,
            b: b_num.checked_mul(n)?,
            den: n.checked_mul(den0)?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const S0: i64 = 1_767_225_600;

    #[test]
    fn the_line_fits_edges_of_a_fast_clock() {
        let cfg = PpsConfig::DEFAULT;
        let mut p = PpsEstimator::new();
        // 25 ppm fast: 1 000 025 000 ns a second, from local 5 s.
        for k in 0..10i64 {
            let e = Edge {
                second: S0 + k,
                local_ns: 5_000_000_000 + k * 1_000_025_000,
            };
            assert_eq!(p.take(e, &cfg), Ok(()));
            assert_eq!(p.locked, k >= 1);
        }
        let l = p.line.unwrap();
        assert_eq!(l.drift_ppb(), Some(25_000));
        // Half a second after the last edge, both ways.
        let local = 5_000_000_000 + 9 * 1_000_025_000 + 500_012_500;
        let utc = l.utc_ns(local).unwrap();
        assert_eq!(utc, i128::from(S0 + 9) * NS_PER_S + 500_000_000);
        assert_eq!(l.local_ns(utc), Some(local));
        assert_eq!(
            p.label(i64::try_from(local - 400_000_000).unwrap()),
            Some(S0 + 9)
        );
        // A glitch 50 µs off is an outlier; three in a row restart the estimator.
        let off = |k: i64| Edge {
            second: S0 + k,
            local_ns: 5_000_000_000 + k * 1_000_025_000 + 50_000,
        };
        assert_eq!(p.take(off(10), &cfg), Err(PpsVerdict::Outlier));
        assert_eq!(p.take(off(11), &cfg), Err(PpsVerdict::Outlier));
        assert!(p.locked);
        assert_eq!(p.take(off(12), &cfg), Err(PpsVerdict::Outlier));
        assert!(!p.locked && p.len == 1);
        assert_eq!(p.take(off(13), &cfg), Ok(()));
        assert!(p.locked);
        // An edge earlier than the last is rejected.
        assert_eq!(p.take(off(12), &cfg), Err(PpsVerdict::Rejected));
    }

    #[test]
    fn a_missing_pulse_keeps_the_labels() {
        let cfg = PpsConfig::DEFAULT;
        let mut p = PpsEstimator::new();
        for k in [0i64, 1, 2, 4, 7] {
            let e = Edge {
                second: S0 + k,
                local_ns: k * 999_990_000,
            };
            assert_eq!(p.take(e, &cfg), Ok(()));
        }
        assert_eq!(p.label(8 * 999_990_000 + 3_000), Some(S0 + 8));
        assert_eq!(p.line.unwrap().drift_ppb(), Some(-10_000));
    }
}
