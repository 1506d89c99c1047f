//! The clock estimator: minimum-delay bins of `(local, local − remote)` points and the
//! rate of Moon's lower-hull fit over them, anchored on the last bins (see the
//! [discipline](super), "Estimator (per clock)").

use super::{BINS, DisciplineConfig};

/// A straight line `offset(x) = y0 + dy·(x − x0)/dx` (µs), `dx > 0`: the offset
/// `local − remote` as a function of local time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Line {
    pub(super) x0: i64,
    pub(super) y0: i64,
    pub(super) dy: i64,
    pub(super) dx: i64,
}

impl Line {
    pub(super) const fn flat(x0: i64, y0: i64) -> Self {
        Self {
            x0,
            y0,
            dy: 0,
            dx: 1,
        }
    }

    /// The offset at local `x`.
    pub(super) fn offset_at(&self, x: i64) -> Option<i64> {
        let num =
            i128::from(self.dy).checked_mul(i128::from(x).checked_sub(i128::from(self.x0))?)?;
        let q = num.checked_div_euclid(i128::from(self.dx))?;
        i64::try_from(i128::from(self.y0).checked_add(q)?).ok()
    }

    /// The remote time at local `x`.
    pub(super) fn remote_at(&self, x: i64) -> Option<i64> {
        x.checked_sub(self.offset_at(x)?)
    }

    /// The local `x` at which the remote time is `r` (inverse of `remote_at`):
    /// `x = x0 + (r − x0 + y0)·dx/(dx − dy)`.
    pub(super) fn local_at(&self, r: i64) -> Option<i64> {
        let den = i128::from(self.dx).checked_sub(i128::from(self.dy))?;
        if den <= 0 {
            return None;
        }
        let num = i128::from(r)
            .checked_sub(i128::from(self.x0))?
            .checked_add(i128::from(self.y0))?
            .checked_mul(i128::from(self.dx))?;
        // Round to nearest.
        let q = num.checked_add(den / 2)?.checked_div_euclid(den)?;
        i64::try_from(i128::from(self.x0).checked_add(q)?).ok()
    }

    /// The line with its offsets negated (for an estimator that keeps its points
    /// negated).
    fn negated(&self) -> Option<Self> {
        Some(Self {
            y0: self.y0.checked_neg()?,
            dy: self.dy.checked_neg()?,
            ..*self
        })
    }

    /// The same line shifted down by `c` (offset − c).
    #[cfg(test)]
    pub(super) fn shifted(&self, c: i64) -> Option<Self> {
        Some(Self {
            y0: self.y0.checked_sub(c)?,
            ..*self
        })
    }

    /// The local → UTC offset line of this local → FC-clock offset line (`x − fc(x)`)
    /// and `c`, the FC's UTC − FC clock as a line of the FC clock (`C(b)`):
    /// `utc(x) = fc(x) + C(fc(x))`, a straight line again. A flat `c` is [`Line::shifted`].
    pub(super) fn then_utc(&self, c: &Line) -> Option<Self> {
        // At x0 the FC clock reads x0 − y0.
        let fc0 = self.x0.checked_sub(self.y0)?;
        let y0 = self.y0.checked_sub(c.offset_at(fc0)?)?;
        // Slope: dy/dx − (cdy/cdx)·(1 − dy/dx), over dx·cdx.
        let dx = self.dx.checked_mul(c.dx)?;
        let dy = self
            .dy
            .checked_mul(c.dx.checked_add(c.dy)?)?
            .checked_sub(self.dx.checked_mul(c.dy)?)?;
        if dx <= 0 {
            return None;
        }
        Some(Self {
            x0: self.x0,
            y0,
            dy,
            dx,
        })
    }

    /// |slope| ≤ `ppm` parts per million.
    pub(super) fn rate_within(&self, ppm: u32) -> bool {
        let lhs = i128::from(self.dy).unsigned_abs().saturating_mul(1_000_000);
        let rhs = i128::from(self.dx)
            .unsigned_abs()
            .saturating_mul(u128::from(ppm));
        lhs <= rhs
    }
}

/// A bin minimum: local time and offset of the least-delayed sample of the bin.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(super) struct Point {
    pub(super) x: i64,
    pub(super) y: i64,
}

/// A pending step: consecutive outliers agreeing with each other.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct StepCandidate {
    point: Point,
    count: u8,
}

/// Minimum-delay, lower-hull clock estimator over a fixed window of bins.
// Independent properties of the estimator's state, each its own flag.
#[allow(clippy::struct_excessive_bools)]
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct ClockEstimator {
    bins: [Point; BINS],
    /// Physical index of the oldest bin.
    start: u8,
    /// Bins in use.
    len: u8,
    /// Local start of the newest bin.
    bin_start: i64,
    line: Option<Line>,
    candidate: StepCandidate,
    /// Last held value seen (to recognise repeats).
    pub(super) last_held: Option<u64>,
    /// Samples accepted since the estimator (re)started.
    pub(super) accepted: u16,
    /// A [prompt](super::Sample::prompt) sample was accepted.
    prompt: bool,
    /// The last samples contradict the fit (see [`DisciplineConfig::jump_tolerance`]).
    pub(super) suspect: bool,
    /// Largest truncation step of the accepted samples, µs.
    resolution: u32,
    /// The samples are lower bounds ([`Sample::lower`](super::Sample::lower)): points
    /// are kept negated (so that the least-advanced are the minima) and the line is
    /// negated back when given.
    pub(super) negated: bool,
    /// The remote clock may run at any rate ([`Sample::any_rate`](super::Sample::any_rate)):
    /// a fit up to [`ANY_RATE_MAX_PPM`] converges, and a rate beyond
    /// [`DisciplineConfig::max_drift_ppm`] is followed (see [`ClockEstimator::fast`]).
    pub(super) any_rate: bool,
}

/// The largest rate of a clock that may run at any rate, ppm: a simulator in lockstep.
const ANY_RATE_MAX_PPM: u32 = 50_000;

/// A mapping an estimator can give, and what is believed of its error.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Fit {
    pub(super) line: Line,
    /// From a converged fit (else a first mapping that assumes equal rates).
    pub(super) converged: bool,
    /// Error believed at the line's anchor `x0`, µs: half the truncation step plus the
    /// delay uncertainty of the least-delayed sample.
    pub(super) base_us: u64,
}

/// Result of feeding a point to a [`ClockEstimator`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Fed {
    Accepted,
    Outlier,
    Step,
}

impl ClockEstimator {
    pub(super) const fn new() -> Self {
        Self {
            bins: [Point { x: 0, y: 0 }; BINS],
            start: 0,
            len: 0,
            bin_start: 0,
            line: None,
            candidate: StepCandidate {
                point: Point { x: 0, y: 0 },
                count: 0,
            },
            last_held: None,
            accepted: 0,
            prompt: false,
            suspect: false,
            resolution: 0,
            negated: false,
            any_rate: false,
        }
    }

    pub(super) fn reset(&mut self) {
        let (negated, any_rate) = (self.negated, self.any_rate);
        *self = Self::new();
        self.negated = negated;
        self.any_rate = any_rate;
    }

    /// The remote clock runs at a rate no crystal has (a simulator's, [`Self::any_rate`]),
    /// as two bins or more say: a bin keeps its least point *against the line* (the rate
    /// removed, else it would keep the newest point whatever its delay), and the first
    /// mapping follows the fitted line rather than assuming equal rates.
    fn fast(&self, cfg: &DisciplineConfig) -> bool {
        self.any_rate
            && self.len >= 2
            && self.line.is_some_and(|l| !l.rate_within(cfg.max_drift_ppm))
    }

    pub(super) fn is_empty(&self) -> bool {
        self.len == 0
    }

    fn bin(&self, i: u8) -> Option<Point> {
        let idx = usize::from(self.start).checked_add(usize::from(i))? % BINS;
        self.bins.get(idx).copied()
    }

    fn bin_mut(&mut self, i: u8) -> Option<&mut Point> {
        let idx = usize::from(self.start).checked_add(usize::from(i))? % BINS;
        self.bins.get_mut(idx)
    }

    /// Converged per the validity rule.
    fn converged(&self, cfg: &DisciplineConfig) -> bool {
        let Some(line) = self.line else {
            return false;
        };
        let max_ppm = if self.any_rate {
            ANY_RATE_MAX_PPM
        } else {
            cfg.max_drift_ppm
        };
        if self.len < cfg.min_bins.max(2) || !line.rate_within(max_ppm) {
            return false;
        }
        let (Some(first), Some(last)) = (self.bin(0), self.bin(self.len.saturating_sub(1))) else {
            return false;
        };
        let span = last.x.saturating_sub(first.x);
        u64::try_from(span).is_ok_and(|s| s >= cfg.min_span.as_micros())
    }

    /// The mapping this estimator gives: its fit once converged, else (after
    /// [`DisciplineConfig::quick_samples`] samples, or one prompt sample) a flat line
    /// through the least-delayed recent sample. `None` while suspect.
    pub(super) fn usable(&self, cfg: &DisciplineConfig) -> Option<Fit> {
        if self.suspect {
            return None;
        }
        let converged = self.converged(cfg);
        let line = if converged || (self.fast(cfg) && self.accepted >= u16::from(cfg.quick_samples))
        {
            self.line?
        } else if self.prompt || self.accepted >= u16::from(cfg.quick_samples.max(1)) {
            let first = self.bin(0)?;
            self.anchor(Line::flat(first.x, first.y), cfg.anchor_bins.max(1))?
        } else {
            return None;
        };
        let half = if cfg.center_truncation {
            self.resolution / 2
        } else {
            self.resolution
        };
        // Bin minima spread by the truncation phase are already within `half`; what
        // spreads them further is delay the minima did not remove.
        let delay = self
            .spread(&line, cfg.anchor_bins.max(1))
            .saturating_sub(u64::from(half))
            .max(cfg.delay_margin.as_micros());
        let line = if self.negated { line.negated()? } else { line };
        Some(Fit {
            line,
            converged,
            base_us: u64::from(half).saturating_add(delay),
        })
    }

    /// How far above `line` the last `k` bin minima lie at most, µs: how consistent the
    /// least delay is from bin to bin.
    fn spread(&self, line: &Line, k: u8) -> u64 {
        let from = self.len.saturating_sub(k);
        (from..self.len)
            .filter_map(|i| {
                let p = self.bin(i)?;
                p.y.checked_sub(line.offset_at(p.x)?)
            })
            .map(i64::unsigned_abs)
            .max()
            .unwrap_or(0)
    }

    /// Feeds the point `(x, y)` of a sample with truncation step `resolution_us`.
    pub(super) fn feed(
        &mut self,
        p: Point,
        resolution_us: u32,
        prompt: bool,
        cfg: &DisciplineConfig,
    ) -> Fed {
        let p = if self.negated {
            Point {
                x: p.x,
                y: p.y.saturating_neg(),
            }
        } else {
            p
        };
        if let Some(line) = self.line {
            let tol = i64::try_from(
                cfg.jump_tolerance
                    .as_micros()
                    .saturating_add(u64::from(resolution_us)),
            )
            .unwrap_or(i64::MAX);
            let residual = line.offset_at(p.x).and_then(|pred| p.y.checked_sub(pred));
            if residual.is_none_or(|r| r < tol.saturating_neg() || r > tol) {
                let c = &mut self.candidate;
                let agrees = c.count > 0
                    && p.y
                        .checked_sub(c.point.y)
                        .is_some_and(|d| d.saturating_abs() <= tol);
                if agrees {
                    c.count = c.count.saturating_add(1);
                    if p.y < c.point.y {
                        c.point = p;
                    }
                } else {
                    *c = StepCandidate { point: p, count: 1 };
                }
                // Below the fit's floor (no delay explains it) at once; above it, three
                // times in a row (a late frame, even two on a busy host, is ordinary), or
                // once for a prompt sample (sent at once: never that late).
                let high_runs = if prompt { 1 } else { 3 };
                self.suspect = residual.is_none_or(|r| r < 0) || c.count >= high_runs;
                let confirm = if prompt {
                    cfg.prompt_step_confirm
                } else {
                    cfg.step_confirm
                };
                if c.count >= confirm.max(1) {
                    let seed = c.point;
                    self.reset();
                    self.push_bin(seed);
                    self.accepted = 1;
                    self.prompt = prompt;
                    self.resolution = resolution_us;
                    self.refit(cfg);
                    return Fed::Step;
                }
                return Fed::Outlier;
            }
        }
        self.candidate.count = 0;
        self.suspect = false;
        self.accepted = self.accepted.saturating_add(1);
        self.prompt |= prompt;
        self.resolution = self.resolution.max(resolution_us);
        self.add(p, cfg);
        Fed::Accepted
    }

    fn push_bin(&mut self, p: Point) {
        if usize::from(self.len) >= BINS {
            self.start =
                u8::try_from((usize::from(self.start).saturating_add(1)) % BINS).unwrap_or(0);
        } else {
            self.len = self.len.saturating_add(1);
        }
        if let Some(slot) = self.bin_mut(self.len.saturating_sub(1)) {
            *slot = p;
        }
        self.bin_start = p.x;
    }

    fn add(&mut self, p: Point, cfg: &DisciplineConfig) {
        let bin_len = i64::try_from(cfg.bin_len.as_micros()).unwrap_or(i64::MAX);
        let new_bin = self.len == 0 || p.x.saturating_sub(self.bin_start) >= bin_len;
        if new_bin {
            self.push_bin(p);
            self.refit(cfg);
            return;
        }
        let fast = self.fast(cfg);
        let line = self.line;
        let Some(last) = self.bin_mut(self.len.saturating_sub(1)) else {
            return;
        };
        let lower = match line.filter(|_| fast) {
            // The least against the line (the rate removed).
            Some(l) => match (l.offset_at(p.x), l.offset_at(last.x)) {
                (Some(a), Some(b)) => p.y.saturating_sub(a) < last.y.saturating_sub(b),
                _ => p.y < last.y,
            },
            None => p.y < last.y,
        };
        if lower {
            *last = p;
            self.refit(cfg);
        }
    }

    /// Moon's LP over the bin minima: the lower-hull edge above the mean local time.
    fn refit(&mut self, cfg: &DisciplineConfig) {
        self.line = self
            .fit()
            .map(|l| self.anchor(l, cfg.anchor_bins).unwrap_or(l));
    }

    /// The line with the same rate, moved to touch the lowest of the last `k` bins.
    fn anchor(&self, line: Line, k: u8) -> Option<Line> {
        if k == 0 {
            return Some(line);
        }
        let from = self.len.saturating_sub(k);
        let mut best: Option<(i64, Point)> = None;
        for i in from..self.len {
            let p = self.bin(i)?;
            let r = p.y.checked_sub(line.offset_at(p.x)?)?;
            if best.is_none_or(|(b, _)| r < b) {
                best = Some((r, p));
            }
        }
        let (_, p) = best?;
        Some(Line {
            x0: p.x,
            y0: p.y,
            ..line
        })
    }

    fn fit(&self) -> Option<Line> {
        lower_hull_fit(self.len, |i| self.bin(i))
    }
}

/// Moon's LP over `n` points in increasing x (`point(0..n)`): the line under all of them
/// that minimises the summed distance to them, i.e. the edge of their lower convex hull
/// above their mean x (one point, or all on a vertical: a flat line).
// The names are those of the fit's formulas (x, y, n, a, b).
#[allow(clippy::many_single_char_names)]
pub(super) fn lower_hull_fit(n: u8, point: impl Fn(u8) -> Option<Point>) -> Option<Line> {
    if n == 0 {
        return None;
    }
    let first = point(0)?;
    if n == 1 {
        return Some(Line::flat(first.x, first.y));
    }
    // Lower convex hull (Andrew's monotone chain; the points are in increasing x).
    let mut hull = [0u8; BINS];
    let mut h: usize = 0;
    let mut sum_x: i128 = 0;
    for i in 0..n.min(u8::try_from(BINS).unwrap_or(u8::MAX)) {
        let p = point(i)?;
        sum_x = sum_x.checked_add(i128::from(p.x))?;
        while h >= 2 {
            let a = point(*hull.get(h.checked_sub(2)?)?)?;
            let b = point(*hull.get(h.checked_sub(1)?)?)?;
            if cross(a, b, p)? <= 0 {
                h = h.checked_sub(1)?;
            } else {
                break;
            }
        }
        *hull.get_mut(h)? = i;
        h = h.checked_add(1)?;
    }
    if h < 2 {
        let p = point(*hull.first()?)?;
        return Some(Line::flat(p.x, p.y));
    }
    let mean_x = i64::try_from(sum_x.checked_div(i128::from(n))?).ok()?;
    // The hull edge whose span contains the mean (first or last edge outside).
    let mut k = 0usize;
    while k.checked_add(2)? < h {
        let right = point(*hull.get(k.checked_add(1)?)?)?;
        if right.x >= mean_x {
            break;
        }
        k = k.checked_add(1)?;
    }
    let a = point(*hull.get(k)?)?;
    let b = point(*hull.get(k.checked_add(1)?)?)?;
    let dx = b.x.checked_sub(a.x)?;
    if dx <= 0 {
        return Some(Line::flat(a.x, a.y));
    }
    Some(Line {
        x0: a.x,
        y0: a.y,
        dy: b.y.checked_sub(a.y)?,
        dx,
    })
}

/// Cross product `(a − o) × (b − o)`: positive when o → a → b turns left.
fn cross(o: Point, a: Point, b: Point) -> Option<i128> {
    let ax = i128::from(a.x).checked_sub(i128::from(o.x))?;
    let ay = i128::from(a.y).checked_sub(i128::from(o.y))?;
    let bx = i128::from(b.x).checked_sub(i128::from(o.x))?;
    let by = i128::from(b.y).checked_sub(i128::from(o.y))?;
    ax.checked_mul(by)?.checked_sub(ay.checked_mul(bx)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_inverse_round_trips() {
        let l = Line {
            x0: 1_000_000,
            y0: -1_767_225_599_000_000,
            dy: 37,
            dx: 1_000_000,
        };
        for x in [0i64, 1_000_000, 3_600_000_000, 86_400_000_000] {
            let r = l.remote_at(x).unwrap();
            let back = l.local_at(r).unwrap();
            assert!((back - x).abs() <= 1, "{x} {back}");
        }
        assert!(l.rate_within(37));
        assert!(!l.rate_within(36));
    }

    #[test]
    fn a_clock_line_then_a_shift_line_is_the_utc_line() {
        // The FC clock runs 1.2 % slow against local: x − fc(x) grows 12 ms/s; UTC runs
        // 1.2 % fast against the FC clock (C grows by 12 000/988 000 of the FC clock):
        // UTC runs at the local rate.
        let fc = Line {
            x0: 5_000_000,
            y0: 1_000_000,
            dy: 12_000,
            dx: 1_000_000,
        };
        let c = Line {
            x0: 4_000_000,
            y0: 1_700_000_000_000_000,
            dy: 12_000,
            dx: 988_000,
        };
        let utc = fc.then_utc(&c).unwrap();
        for x in [5_000_000i64, 65_000_000, 3_605_000_000] {
            let f = fc.remote_at(x).unwrap();
            let want = f + c.offset_at(f).unwrap();
            let got = utc.remote_at(x).unwrap();
            assert!((got - want).abs() <= 1, "{x}: {got} vs {want}");
        }
        assert!(utc.rate_within(1));
        // A flat C is a shift.
        let flat = Line::flat(0, 1_700_000_000_000_000);
        assert_eq!(
            fc.then_utc(&flat).unwrap().offset_at(9_000_000),
            fc.shifted(1_700_000_000_000_000)
                .unwrap()
                .offset_at(9_000_000)
        );
    }
}
