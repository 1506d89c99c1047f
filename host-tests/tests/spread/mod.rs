//! The spread of a set of errors as the figures tests print it: |error| at the 50th and
//! 99th percentiles and the largest, and the range of a set of delays.

/// |error| percentiles of a set of signed errors (any unit).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Spread {
    /// Median |error|.
    pub p50: i64,
    /// 99th percentile |error|.
    pub p99: i64,
    /// Largest |error|.
    pub max: i64,
    /// How many errors.
    pub count: usize,
}

/// The spread of `errors` (nearest-rank percentiles of the absolute values); `None` when
/// there are none.
pub fn abs_spread(errors: &[i64]) -> Option<Spread> {
    let mut abs: Vec<i64> = errors.iter().map(|e| e.abs()).collect();
    abs.sort_unstable();
    let at = |p: usize| {
        abs.get((abs.len() * p / 100).min(abs.len().checked_sub(1)?))
            .copied()
    };
    Some(Spread {
        p50: at(50)?,
        p99: at(99)?,
        max: *abs.last()?,
        count: abs.len(),
    })
}

/// The smallest and largest of `values` (`(inf, -inf)` when there are none).
pub fn range(values: impl IntoIterator<Item = f64>) -> (f64, f64) {
    values
        .into_iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        })
}

#[test]
fn spread_of_known_errors() {
    let errors: Vec<i64> = (1..=100).map(|v| if v % 2 == 0 { v } else { -v }).collect();
    let s = abs_spread(&errors).unwrap();
    assert_eq!((s.p50, s.p99, s.max, s.count), (51, 100, 100, 100));
    assert_eq!(abs_spread(&[]), None);
    assert_eq!(range([3.0, -1.5, 2.0]), (-1.5, 3.0));
}
