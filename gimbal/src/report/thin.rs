//! Long logs summarised for drawing: a bounded number of points per plot, whatever the
//! flight's length, keeping what a reader must not miss (the extremes of a series, the
//! ends of a track, every state of a link).

use super::figures::{Span, State};

/// A bucket of [`min_max`]: its index, its lowest and its highest point.
type Bucket = (usize, (f64, f64), (f64, f64));

/// Points of a time series, at most `2 × buckets`: the smallest and the largest value of
/// each of `buckets` equal spans of time (in time order), so no peak is lost. A series
/// that is short enough is returned as it is.
#[must_use]
pub fn min_max(points: &[(f64, f64)], buckets: usize) -> Vec<(f64, f64)> {
    if points.len() <= buckets.saturating_mul(2) || buckets == 0 {
        return points.to_vec();
    }
    let (Some(first), Some(last)) = (points.first(), points.last()) else {
        return Vec::new();
    };
    let span = (last.0 - first.0).max(f64::MIN_POSITIVE);
    #[allow(clippy::cast_precision_loss)]
    let width = span / buckets as f64;
    let mut out = Vec::with_capacity(buckets.saturating_mul(2));
    let mut current: Option<Bucket> = None;
    for &p in points {
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let b = (((p.0 - first.0) / width) as usize).min(buckets - 1);
        current = match current {
            Some((cb, lo, hi)) if cb == b => Some((
                cb,
                if p.1 < lo.1 { p } else { lo },
                if p.1 > hi.1 { p } else { hi },
            )),
            other => {
                push_pair(&mut out, other);
                Some((b, p, p))
            }
        };
    }
    push_pair(&mut out, current);
    out
}

/// A bucket's low and high points, in time order (one when they are the same).
fn push_pair(out: &mut Vec<(f64, f64)>, bucket: Option<Bucket>) {
    if let Some((_, lo, hi)) = bucket {
        if lo == hi {
            out.push(lo);
        } else if lo.0 <= hi.0 {
            out.extend([lo, hi]);
        } else {
            out.extend([hi, lo]);
        }
    }
}

/// At most `max` points of a track (every k-th one, and always the last).
#[must_use]
pub fn stride<T: Copy>(points: &[T], max: usize) -> Vec<T> {
    if points.len() <= max || max < 2 {
        return points.to_vec();
    }
    let k = points.len().div_ceil(max - 1);
    let mut out: Vec<T> = points.iter().step_by(k).copied().collect();
    if points.len() % k != 1
        && let Some(&last) = points.last()
    {
        out.push(last);
    }
    out
}

/// A link's spans as at most `columns` spans: the flight cut in `columns` equal
/// columns, each taking the worst state within it (down over unknown over up), equal
/// neighbours merged. Spans that fit are returned as they are.
#[must_use]
pub fn spans(spans: &[Span], end_s: f64, columns: usize) -> Vec<Span> {
    if spans.len() <= columns || columns == 0 || end_s <= 0.0 {
        return spans.to_vec();
    }
    let rank = |s: State| match s {
        State::Up => 0,
        State::Unknown => 1,
        State::Down => 2,
    };
    #[allow(clippy::cast_precision_loss)]
    let width = end_s / columns as f64;
    let mut out: Vec<Span> = Vec::new();
    let mut i = 0;
    for c in 0..columns {
        #[allow(clippy::cast_precision_loss)]
        let (from, to) = (c as f64 * width, (c + 1) as f64 * width);
        let mut worst: Option<State> = None;
        while let Some(s) = spans.get(i) {
            if s.from_s >= to {
                break;
            }
            if s.to_s > from && worst.is_none_or(|w| rank(s.state) > rank(w)) {
                worst = Some(s.state);
            }
            if s.to_s > to {
                break;
            }
            i += 1;
        }
        let Some(state) = worst else { continue };
        match out.last_mut() {
            Some(last) if last.state == state && (last.to_s - from).abs() < width * 1e-6 => {
                last.to_s = to;
            }
            _ => out.push(Span {
                from_s: from,
                to_s: to,
                state,
            }),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_long_series_keeps_its_peaks() {
        let points: Vec<(f64, f64)> = (0..10_000)
            .map(|i| (f64::from(i), if i == 4321 { 99.0 } else { 1.0 }))
            .collect();
        let thin = min_max(&points, 100);
        assert!(thin.len() <= 200, "{}", thin.len());
        assert!(thin.contains(&(4321.0, 99.0)));
        assert!(thin.windows(2).all(|w| w[0].0 < w[1].0));
        let short = [(0.0, 1.0), (1.0, 2.0)];
        assert_eq!(min_max(&short, 100), short);
    }

    #[test]
    fn a_long_track_keeps_its_ends() {
        let points: Vec<u32> = (0..10_001).collect();
        let thin = stride(&points, 1000);
        assert!(thin.len() <= 1000, "{}", thin.len());
        assert_eq!(thin.first(), Some(&0));
        assert_eq!(thin.last(), Some(&10_000));
    }

    #[test]
    fn flapping_links_are_summarised_worst_first() {
        // 0..100 s: up, with a 0.01 s drop every second.
        let mut s = Vec::new();
        for i in 0..100 {
            let t = f64::from(i);
            s.push(Span {
                from_s: t,
                to_s: t + 0.99,
                state: State::Up,
            });
            s.push(Span {
                from_s: t + 0.99,
                to_s: t + 1.0,
                state: State::Down,
            });
        }
        let thin = spans(&s, 100.0, 50);
        assert_eq!(thin.len(), 1, "{thin:?}");
        assert_eq!(thin[0].state, State::Down);
        assert!((thin[0].to_s - 100.0).abs() < 1e-9);
    }
}
