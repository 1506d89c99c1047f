//! The offset `C` = UTC − FC clock, for a flight controller whose time reaches the
//! bridge through its own clock (SIYI's 0x30 against 0x22/0x3E `time_boot_ms`, MAVLink
//! SYSTEM_TIME against TIMESYNC): `UTC = FC clock + C` (see the [discipline](super),
//! "Sources").

use super::MAX_UTC_VIA_FC;
use super::estimator::{Fed, Line, Point};

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

/// Bins of [`Shift`].
const SHIFT_BINS: usize = 4;
/// Local time of one [`Shift`] bin, µs.
const SHIFT_BIN_US: i64 = 4_000_000;
/// Samples above the shift's band in a row that make it a step.
const SHIFT_STEP_CONFIRM: u8 = 3;

/// `C` = UTC − FC clock from samples `d = utc − fc_ms·1000` read from one clock in one
/// call (MAVLink SYSTEM_TIME): `d ∈ [C, C + 1000)` µs, the excess being the FC clock's
/// sub-millisecond phase when it was read, so the least `d` is `C`. The least `d` of
/// each [`SHIFT_BIN_US`] bin, over the last [`SHIFT_BINS`] bins (16 s: a shift the FC
/// slews slowly is followed). A `d` below the least by more than the tolerance, or
/// [`SHIFT_STEP_CONFIRM`] in a row above its band, are a step of the FC's UTC: the
/// shift restarts from them; the first contradicting sample makes it suspect (no UTC)
/// until the step is confirmed or a consistent sample comes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Shift {
    /// (bin index, least `d`) per bin, newest last.
    bins: [Option<(i64, i64)>; SHIFT_BINS],
    /// Consecutive samples above the band, and the least of them.
    above: u8,
    above_min: i64,
    pub(super) suspect: bool,
}

impl Shift {
    const fn new() -> Self {
        Shift {
            bins: [None; SHIFT_BINS],
            above: 0,
            above_min: i64::MAX,
            suspect: false,
        }
    }

    /// The shift: the least `d` of the window.
    fn value(&self) -> Option<i64> {
        self.bins.iter().flatten().map(|(_, d)| *d).min()
    }

    fn put(&mut self, x: i64, d: i64) {
        let bin = x.div_euclid(SHIFT_BIN_US);
        let newest = self.bins.iter().flatten().map(|(b, _)| *b).max();
        match newest {
            Some(b) if b == bin => {
                for (b, m) in self.bins.iter_mut().flatten() {
                    if *b == bin {
                        *m = (*m).min(d);
                    }
                }
            }
            Some(b) if bin < b => {}
            _ => {
                self.bins.rotate_left(1);
                if let Some(last) = self.bins.last_mut() {
                    *last = Some((bin, d));
                }
                // Bins older than the window go.
                let oldest = bin.saturating_sub(i64::try_from(SHIFT_BINS).unwrap_or(0));
                for slot in &mut self.bins {
                    if slot.is_some_and(|(b, _)| b <= oldest) {
                        *slot = None;
                    }
                }
            }
        }
    }

    /// Takes `d` at local `x`; returns whether the shift restarted (a step).
    pub(super) fn push(&mut self, x: i64, d: i64, tolerance: i64) -> Fed {
        let Some(c) = self.value() else {
            self.put(x, d);
            return Fed::Accepted;
        };
        let band_top = c.saturating_add(1_000).saturating_add(tolerance);
        if d < c.saturating_sub(tolerance) || d > band_top {
            self.suspect = true;
            if d > band_top {
                self.above = self.above.saturating_add(1);
                self.above_min = self.above_min.min(d);
            }
            if d < c.saturating_sub(tolerance) || self.above >= SHIFT_STEP_CONFIRM {
                let start = if d > band_top { self.above_min } else { d };
                *self = Shift::new();
                self.put(x, start);
                return Fed::Step;
            }
            return Fed::Outlier;
        }
        self.above = 0;
        self.above_min = i64::MAX;
        self.suspect = false;
        self.put(x, d);
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

    /// `C`: the SYSTEM_TIME shift when there is one; else the least pair consistent
    /// with the unpaired bound (`true`), else the bound (`false`).
    pub(super) fn value(&self, fc: Option<&Line>, tolerance: i64) -> Option<(i64, bool)> {
        if let Some(c) = self.shift.value() {
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
        best_pair.map(|c| (c, true)).or(bound.map(|c| (c, false)))
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
        assert_eq!(o.value(None, 0), Some((994, true)));
    }
}
