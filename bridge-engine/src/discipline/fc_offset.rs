//! The offset `C` = UTC − FC clock, for a flight controller whose time reaches the
//! bridge through its own clock (SIYI's 0x30 against 0x22/0x3E `time_boot_ms`, MAVLink
//! SYSTEM_TIME against TIMESYNC): `UTC = FC clock + C` (see the [discipline](super),
//! "Sources").

use super::MAX_UTC_VIA_FC;
use super::estimator::{Fed, Line, Point, lower_hull_fit};

/// What is known of `C` = UTC − FC clock: SIYI's 0x30 frames (unpaired, and paired with
/// an FC clock value), or MAVLink SYSTEM_TIME ([`Shift`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct FcOffset {
    /// Unpaired 0x30: (local x, UTC µs), the newest [`MAX_UTC_VIA_FC`] in a ring.
    unpaired: Ring<Point>,
    /// Pairs: `utc − fc_ms·1000`, the newest [`MAX_UTC_VIA_FC`] in a ring.
    pairs: Ring<i64>,
    /// `C` from MAVLink SYSTEM_TIME (when it feeds the offset: then the only source).
    pub(super) shift: Shift,
}

/// Bins of [`Shift`] (at most the estimator's [`BINS`](super::BINS)).
const SHIFT_BINS: u8 = 16;
/// FC clock time of one [`Shift`] bin, µs.
const SHIFT_BIN_US: i64 = 1_000_000;
/// The newest bins the line is moved to touch.
const SHIFT_ANCHOR_BINS: u8 = 4;
/// Samples above the band in a row that make a step.
const SHIFT_STEP_CONFIRM: u8 = 3;
/// Rate of `C` against the FC clock believed possible before the line has a rate, ppm:
/// the clock of a simulator in lockstep (PX4 SITL's runs 0.87 % slow against its
/// UTC, the host's) with a wide margin.
const SHIFT_MAX_RATE_PPM: i64 = 50_000;
/// The truncation of `time_boot_ms`: `d` lies up to this above the line, µs.
const SHIFT_TRUNCATION: i64 = 1_000;
/// FC time over which `d` must stay within [`SHIFT_IN_STEP_BAND`] for UTC to be in step
/// with the boot clock, µs: a drift of 1.5 ms a second (0.15 %) shows within it (PX4
/// SITL's shift grew by 5.7 ms in its slowest second of the capture).
const SHIFT_JUDGE_US: i64 = 1_000_000;
/// How far `d` may spread while UTC is judged in step: the truncation, and 0.5 ms for the
/// two reads of the FC's clocks (`time_unix_usec` and `time_boot_ms` are read one after
/// the other), µs.
const SHIFT_IN_STEP_BAND: i64 = SHIFT_TRUNCATION + 500;
/// Samples leaving [`SHIFT_IN_STEP_BAND`] in one direction, one after the other within
/// [`SHIFT_DRIFT_US`] of FC time, that make a drift ([`Pace::Apart`]): `d` moved by 4.5
/// ms at least in 3 s (1 500 ppm at least, five times a crystal's largest). A step of
/// the FC's UTC leaves the band once; PX4 SITL's shift (5.7 to 15 ms a second) leaves it
/// every 0.1 to 0.3 s.
const SHIFT_DRIFT_BREAKS: u8 = 4;
const SHIFT_DRIFT_US: i64 = 3_000_000;

/// What a flight controller's SYSTEM_TIMEs say of its UTC against its boot clock.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Pace {
    /// Not known yet: the shift has not been watched for [`SHIFT_JUDGE_US`].
    Unknown,
    /// In step: `d` stayed within [`SHIFT_IN_STEP_BAND`] for [`SHIFT_JUDGE_US`] (a real
    /// flight controller: its UTC is its boot clock plus a shift, or follows GPS at a
    /// crystal's ppm).
    InStep,
    /// Apart: `d` drifts at a rate no crystal has, [`SHIFT_DRIFT_BREAKS`] times out of its
    /// band in one direction within [`SHIFT_DRIFT_US`] (a simulator in lockstep: PX4
    /// SITL's boot clock is the simulation's, its UTC the host's). For good (until the
    /// discipline restarts).
    Apart,
}

/// `C` = UTC − FC clock, **a line of the FC clock** `C(b)`, from samples `d = utc −
/// fc_ms·1000` read from one clock in one call (MAVLink SYSTEM_TIME): `d ∈ [C(b), C(b) +
/// 1000)` µs at `b = fc_ms·1000`, the excess being the FC clock's sub-millisecond phase
/// when it was read, so the line under the samples is `C`. A real autopilot's UTC drifts
/// against its boot clock by its crystal's ppm (when GPS keeps it), a simulator's in
/// lockstep by a percent or so (PX4 SITL: UTC follows the host, the boot clock the
/// simulation); a constant `C` is the line of rate 0.
///
/// The least `d` of each [`SHIFT_BIN_US`] bin of FC time (least against the current line:
/// a bin's points are compared with the rate removed), over the last [`SHIFT_BINS`] bins
/// (16 s); the line is flat through the least of them while they all lie within the
/// truncation of it (a constant `C` as far as 16 s tell: the least `d`, as before lines),
/// else the lower-hull fit of the estimator (Moon's LP) over them, moved to touch the
/// lowest of the newest [`SHIFT_ANCHOR_BINS`]. A sample is on the line
/// when within `[−tolerance, 1000 + tolerance]` of it, widened by what the rate's
/// uncertainty makes of the distance to the anchor (before a second bin, the rate can be
/// anything up to [`SHIFT_MAX_RATE_PPM`]; then the truncation over the bins' span). A
/// sample below that band, or [`SHIFT_STEP_CONFIRM`] in a row above it, are a step of the
/// FC's UTC: the line restarts from them; the first contradicting sample makes it suspect
/// (no UTC) until the step is confirmed or a consistent sample comes.
///
/// It also judges the [`Pace`] of the FC's UTC against its boot clock, which a step does
/// not change.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Shift {
    /// Bin minima `(b, d)`, oldest first from `start` (a ring of `len`).
    bins: [Point; SHIFT_BINS as usize],
    start: u8,
    len: u8,
    /// The line through them.
    line: Option<Line>,
    /// Consecutive samples above the band, and the least of them.
    above: u8,
    above_min: Point,
    pub(super) suspect: bool,
    pace: Pace,
    /// The samples watched for [`Pace::InStep`]: the first's FC time, the least and the
    /// greatest `d` since.
    watched_from: Option<i64>,
    watched_lo: i64,
    watched_hi: i64,
    /// The samples that left the band in a row in one direction (up: 1, down: −1), and
    /// the FC time of the first.
    drift_dir: i8,
    drift_breaks: u8,
    drift_from: i64,
}

impl Shift {
    const fn new() -> Self {
        Shift {
            bins: [Point { x: 0, y: 0 }; SHIFT_BINS as usize],
            start: 0,
            len: 0,
            line: None,
            above: 0,
            above_min: Point { x: 0, y: i64::MAX },
            suspect: false,
            pace: Pace::Unknown,
            watched_from: None,
            watched_lo: 0,
            watched_hi: 0,
            drift_dir: 0,
            drift_breaks: 0,
            drift_from: 0,
        }
    }

    /// What the samples say of the FC's UTC against its boot clock.
    pub(super) const fn pace(&self) -> Pace {
        self.pace
    }

    /// The line restarts from `p` (a step of the FC's UTC): the pace stays as judged.
    fn restart(&mut self, p: Point) {
        let kept = Shift {
            pace: self.pace,
            watched_from: self.watched_from,
            watched_lo: self.watched_lo,
            watched_hi: self.watched_hi,
            drift_dir: self.drift_dir,
            drift_breaks: self.drift_breaks,
            drift_from: self.drift_from,
            ..Shift::new()
        };
        *self = kept;
        self.put(p);
    }

    /// Judges the pace with sample `p`.
    fn judge(&mut self, p: Point) {
        if self.pace == Pace::Apart {
            return;
        }
        // In step: `d` within its band for long enough; watching starts again from any
        // sample that leaves it (a step, or a drift).
        let (lo, hi) = (self.watched_lo.min(p.y), self.watched_hi.max(p.y));
        match self.watched_from {
            Some(from) if hi.saturating_sub(lo) <= SHIFT_IN_STEP_BAND => {
                (self.watched_lo, self.watched_hi) = (lo, hi);
                if p.x.saturating_sub(from) >= SHIFT_JUDGE_US {
                    self.pace = Pace::InStep;
                }
                return;
            }
            Some(_) => self.left_band(p),
            None => {}
        }
        (self.watched_from, self.watched_lo, self.watched_hi) = (Some(p.x), p.y, p.y);
    }

    /// Sample `p` left the band: a drift when it is the latest of
    /// [`SHIFT_DRIFT_BREAKS`] in one direction within [`SHIFT_DRIFT_US`].
    fn left_band(&mut self, p: Point) {
        let dir = if p.y > self.watched_hi { 1 } else { -1 };
        if dir == self.drift_dir && p.x.saturating_sub(self.drift_from) <= SHIFT_DRIFT_US {
            self.drift_breaks = self.drift_breaks.saturating_add(1);
        } else {
            (self.drift_dir, self.drift_breaks, self.drift_from) = (dir, 1, p.x);
        }
        if self.drift_breaks >= SHIFT_DRIFT_BREAKS {
            self.pace = Pace::Apart;
        }
    }

    fn bin(&self, i: u8) -> Option<Point> {
        let idx = usize::from(self.start)
            .checked_add(usize::from(i))?
            .checked_rem(usize::from(SHIFT_BINS))?;
        self.bins.get(idx).copied()
    }

    fn bin_mut(&mut self, i: u8) -> Option<&mut Point> {
        let idx = usize::from(self.start)
            .checked_add(usize::from(i))?
            .checked_rem(usize::from(SHIFT_BINS))?;
        self.bins.get_mut(idx)
    }

    /// `C` as a line of the FC clock.
    pub(super) fn line(&self) -> Option<Line> {
        self.line
    }

    /// How far `d` at `b` lies above the line (`None`: no line).
    fn residual(&self, p: Point) -> Option<i64> {
        p.y.checked_sub(self.line?.offset_at(p.x)?)
    }

    /// What the rate's uncertainty makes of the distance from the anchor to `b`, µs.
    fn allowance(&self, b: i64) -> i64 {
        let Some(line) = self.line else {
            return 0;
        };
        let far = b.saturating_sub(line.x0).saturating_abs();
        let span = match (self.bin(0), self.bin(self.len.saturating_sub(1))) {
            (Some(first), Some(last)) if self.len >= 2 => last.x.saturating_sub(first.x),
            _ => 0,
        };
        if span > 0 {
            far.saturating_mul(SHIFT_TRUNCATION)
                .checked_div(span)
                .unwrap_or(i64::MAX)
        } else {
            far.saturating_mul(SHIFT_MAX_RATE_PPM) / 1_000_000
        }
    }

    fn put(&mut self, p: Point) {
        let bin = p.x.div_euclid(SHIFT_BIN_US);
        let newest = self
            .bin(self.len.saturating_sub(1))
            .filter(|_| self.len > 0);
        match newest.map(|n| n.x.div_euclid(SHIFT_BIN_US)) {
            Some(b) if b == bin => {
                // The least in the bin, with the rate removed.
                let lower = match (self.residual(p), newest.and_then(|n| self.residual(n))) {
                    (Some(r), Some(n)) => r < n,
                    _ => newest.is_some_and(|n| p.y < n.y),
                };
                if lower && let Some(slot) = self.bin_mut(self.len.saturating_sub(1)) {
                    *slot = p;
                }
            }
            Some(b) if bin < b => return,
            _ => {
                // Bins older than the window go.
                let oldest = bin.saturating_sub(i64::from(SHIFT_BINS));
                while self.len > 0
                    && self
                        .bin(0)
                        .is_some_and(|f| f.x.div_euclid(SHIFT_BIN_US) <= oldest)
                {
                    self.start = self
                        .start
                        .saturating_add(1)
                        .checked_rem(SHIFT_BINS)
                        .unwrap_or(0);
                    self.len = self.len.saturating_sub(1);
                }
                if self.len >= SHIFT_BINS {
                    self.start = self
                        .start
                        .saturating_add(1)
                        .checked_rem(SHIFT_BINS)
                        .unwrap_or(0);
                } else {
                    self.len = self.len.saturating_add(1);
                }
                if let Some(slot) = self.bin_mut(self.len.saturating_sub(1)) {
                    *slot = p;
                }
            }
        }
        self.refit();
    }

    /// The line through the bin minima: flat through the least when every minimum lies
    /// within the truncation of it (a constant `C`, as far as the window tells: a rate
    /// from noise alone would only add error), else the hull fit, moved to touch the
    /// lowest of the newest bins.
    fn refit(&mut self) {
        let least = (0..self.len)
            .filter_map(|i| self.bin(i))
            .min_by_key(|p| p.y);
        if let Some(least) = least
            && (0..self.len)
                .filter_map(|i| self.bin(i))
                .all(|p| p.y.saturating_sub(least.y) <= SHIFT_TRUNCATION)
        {
            self.line = Some(Line::flat(least.x, least.y));
            return;
        }
        let Some(line) = lower_hull_fit(self.len, |i| self.bin(i)) else {
            self.line = None;
            return;
        };
        let from = self.len.saturating_sub(SHIFT_ANCHOR_BINS);
        let anchor = (from..self.len)
            .filter_map(|i| {
                let p = self.bin(i)?;
                Some((p.y.checked_sub(line.offset_at(p.x)?)?, p))
            })
            .min_by_key(|(r, _)| *r)
            .map(|(_, p)| p);
        self.line = Some(match anchor {
            Some(p) => Line {
                x0: p.x,
                y0: p.y,
                ..line
            },
            None => line,
        });
    }

    /// Takes `d` at FC clock `b`; returns whether it was on the line, an outlier or a
    /// step (the line restarted). Judges the [`Pace`].
    pub(super) fn push(&mut self, b: i64, d: i64, tolerance: i64) -> Fed {
        let fed = self.take(b, d, tolerance);
        self.judge(Point { x: b, y: d });
        fed
    }

    fn take(&mut self, b: i64, d: i64, tolerance: i64) -> Fed {
        let p = Point { x: b, y: d };
        let Some(r) = self.residual(p) else {
            self.put(p);
            return Fed::Accepted;
        };
        let slack = tolerance.saturating_add(self.allowance(b));
        let below = r < slack.saturating_neg();
        let above = r > SHIFT_TRUNCATION.saturating_add(slack);
        if below || above {
            self.suspect = true;
            if above {
                self.above = self.above.saturating_add(1);
                if self.above_min.y == i64::MAX || p.y < self.above_min.y {
                    self.above_min = p;
                }
            }
            if below || self.above >= SHIFT_STEP_CONFIRM {
                let start = if below { p } else { self.above_min };
                self.restart(start);
                return Fed::Step;
            }
            return Fed::Outlier;
        }
        self.above = 0;
        self.above_min = Point { x: 0, y: i64::MAX };
        self.suspect = false;
        self.put(p);
        Fed::Accepted
    }
}

/// The newest [`MAX_UTC_VIA_FC`] values: the next slot to write goes round for ever (a
/// count that saturated once stopped it, and one slot was then overwritten for good;
/// see docs/src/reliability.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Ring<T: Copy> {
    items: [T; MAX_UTC_VIA_FC],
    /// Values held (at most the capacity).
    len: u8,
    /// The slot the next value goes to.
    next: u8,
}

impl<T: Copy> Ring<T> {
    const fn new(fill: T) -> Self {
        Ring {
            items: [fill; MAX_UTC_VIA_FC],
            len: 0,
            next: 0,
        }
    }

    fn push(&mut self, v: T) {
        if let Some(slot) = self.items.get_mut(usize::from(self.next)) {
            *slot = v;
        }
        let next = usize::from(self.next).saturating_add(1) % MAX_UTC_VIA_FC;
        self.next = u8::try_from(next).unwrap_or(0);
        if usize::from(self.len) < MAX_UTC_VIA_FC {
            self.len = self.len.saturating_add(1);
        }
    }

    fn as_slice(&self) -> &[T] {
        self.items.get(..usize::from(self.len)).unwrap_or(&[])
    }
}

impl FcOffset {
    pub(super) const fn new() -> Self {
        Self {
            unpaired: Ring::new(Point { x: 0, y: 0 }),
            pairs: Ring::new(0),
            shift: Shift::new(),
        }
    }

    pub(super) fn push_unpaired(&mut self, p: Point) {
        self.unpaired.push(p);
    }

    pub(super) fn push_pair(&mut self, m: i64) {
        self.pairs.push(m);
    }

    fn unpaired(&self) -> &[Point] {
        self.unpaired.as_slice()
    }

    fn pairs(&self) -> &[i64] {
        self.pairs.as_slice()
    }

    /// The lower bound of `C` from unpaired 0x30 frames and the FC clock fit.
    pub(super) fn lower_bound(&self, fc: &Line) -> Option<i64> {
        self.unpaired()
            .iter()
            .filter_map(|p| p.y.checked_sub(fc.remote_at(p.x)?))
            .max()
    }

    /// `C` as a line of the FC clock: the SYSTEM_TIME shift when there is one; else
    /// (constant) the least pair consistent with the unpaired bound (`true`), else the
    /// bound (`false`).
    pub(super) fn value(&self, fc: Option<&Line>, tolerance: i64) -> Option<(Line, bool)> {
        if let Some(c) = self.shift.line() {
            return Some((c, true));
        }
        let bound = fc.and_then(|l| self.lower_bound(l));
        let floor = bound.map(|b| b.saturating_sub(tolerance));
        let best_pair = self
            .pairs()
            .iter()
            .copied()
            .filter(|m| floor.is_none_or(|f| *m >= f))
            .min();
        best_pair
            .map(|c| (Line::flat(0, c), true))
            .or(bound.map(|c| (Line::flat(0, c), false)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// More than 255 values (the count that once saturated): the ring keeps the newest
    /// six, every slot in turn.
    #[test]
    fn the_rings_keep_the_newest_values_for_ever() {
        let mut o = FcOffset::new();
        for m in 0..1_000i64 {
            o.push_pair(m);
            o.push_unpaired(Point { x: m, y: m });
            let mut held: Vec<i64> = o.pairs().to_vec();
            held.sort_unstable();
            let first = (m - 5).max(0);
            assert_eq!(held, (first..=m).collect::<Vec<_>>(), "after {m}");
            assert!(o.unpaired().iter().any(|p| p.x == m));
        }
        // The least pair is the newest six's least.
        assert_eq!(o.value(None, 0), Some((Line::flat(0, 994), true)));
    }
}
