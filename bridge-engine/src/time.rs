//! Time as the engine sees it: the caller's monotonic clock ([`Instant`], [`Duration`])
//! and Coordinated Universal Time ([`UtcTime`], [`TimeOfDay`]).
//!
//! Every quantity is an integer number of microseconds in a `u64` newtype: exact, `Copy`,
//! ordered, and never wrapping silently. Arithmetic is `checked_*` (returns `None` on
//! overflow or underflow) or `saturating_*` (clamps); nothing here panics.
//!
//! [`UtcTime`] counts microseconds since 1970-01-01T00:00:00Z without leap seconds (Unix
//! time, the time base of the K40T 0x00030E frame and of SIYI 0x30). Conversions from GPS
//! time take the leap-second count as an explicit argument: it belongs to the caller's
//! configuration, not to this module.

/// Microseconds in one millisecond.
const US_PER_MS: u64 = 1_000;
/// Microseconds in one second.
const US_PER_S: u64 = 1_000_000;
/// Nanoseconds in one microsecond.
const NS_PER_US: u64 = 1_000;
/// Milliseconds in one day.
const MS_PER_DAY: u32 = 86_400_000;
/// Microseconds in one day.
const US_PER_DAY: u64 = 86_400_000_000;
/// Seconds from the Unix epoch to the GPS epoch (1980-01-06T00:00:00Z).
const GPS_EPOCH_UNIX_S: u64 = 315_964_800;
/// Seconds in one GPS week.
const S_PER_WEEK: u64 = 604_800;

protocol_core::wire_derive! {
    [Eq, PartialOrd, Ord, Hash, Default]
    /// A span of time in microseconds (never negative).
    pub struct Duration(u64);
}

impl Duration {
    /// No time at all.
    pub const ZERO: Self = Self(0);
    /// The longest representable span (about 584 542 years).
    pub const MAX: Self = Self(u64::MAX);

    /// A span of `us` microseconds.
    #[must_use]
    pub const fn from_micros(us: u64) -> Self {
        Self(us)
    }

    /// A span of `ms` milliseconds (saturating at [`Duration::MAX`]).
    #[must_use]
    pub const fn from_millis(ms: u64) -> Self {
        Self(ms.saturating_mul(US_PER_MS))
    }

    /// A span of `s` seconds (saturating at [`Duration::MAX`]).
    #[must_use]
    pub const fn from_secs(s: u64) -> Self {
        Self(s.saturating_mul(US_PER_S))
    }

    /// The span in microseconds.
    #[must_use]
    pub const fn as_micros(self) -> u64 {
        self.0
    }

    /// The span in whole milliseconds (truncated).
    #[must_use]
    pub const fn as_millis(self) -> u64 {
        self.0 / US_PER_MS
    }

    /// `self + rhs`, or `None` on overflow.
    #[must_use]
    pub const fn checked_add(self, rhs: Self) -> Option<Self> {
        match self.0.checked_add(rhs.0) {
            Some(v) => Some(Self(v)),
            None => None,
        }
    }

    /// `self - rhs`, or `None` if `rhs` is longer than `self`.
    #[must_use]
    pub const fn checked_sub(self, rhs: Self) -> Option<Self> {
        match self.0.checked_sub(rhs.0) {
            Some(v) => Some(Self(v)),
            None => None,
        }
    }

    /// `self + rhs`, clamped at [`Duration::MAX`].
    #[must_use]
    pub const fn saturating_add(self, rhs: Self) -> Self {
        Self(self.0.saturating_add(rhs.0))
    }

    /// `self - rhs`, clamped at [`Duration::ZERO`].
    #[must_use]
    pub const fn saturating_sub(self, rhs: Self) -> Self {
        Self(self.0.saturating_sub(rhs.0))
    }
}

protocol_core::wire_derive! {
    [Eq, PartialOrd, Ord, Hash, Default]
    /// An instant of the caller's monotonic clock, in microseconds since an arbitrary origin
    /// (typically the MCU's boot).
    ///
    /// This is the local clock of the bridge: its rate differs from true time by the
    /// crystal's error (tens of ppm). [`TimeDiscipline`](super::discipline::TimeDiscipline)
    /// maps it to UTC and back.
    pub struct Instant(u64);
}

impl Instant {
    /// The clock's origin.
    pub const ZERO: Self = Self(0);

    /// The instant `us` microseconds after the origin.
    #[must_use]
    pub const fn from_micros(us: u64) -> Self {
        Self(us)
    }

    /// The instant `ms` milliseconds after the origin (saturating).
    #[must_use]
    pub const fn from_millis(ms: u64) -> Self {
        Self(ms.saturating_mul(US_PER_MS))
    }

    /// Microseconds since the origin.
    #[must_use]
    pub const fn as_micros(self) -> u64 {
        self.0
    }

    /// Whole milliseconds since the origin (truncated).
    #[must_use]
    pub const fn as_millis(self) -> u64 {
        self.0 / US_PER_MS
    }

    /// `self + d`, or `None` on overflow.
    #[must_use]
    pub const fn checked_add(self, d: Duration) -> Option<Self> {
        match self.0.checked_add(d.0) {
            Some(v) => Some(Self(v)),
            None => None,
        }
    }

    /// `self - d`, or `None` before the origin.
    #[must_use]
    pub const fn checked_sub(self, d: Duration) -> Option<Self> {
        match self.0.checked_sub(d.0) {
            Some(v) => Some(Self(v)),
            None => None,
        }
    }

    /// `self + d`, clamped at the largest instant.
    #[must_use]
    pub const fn saturating_add(self, d: Duration) -> Self {
        Self(self.0.saturating_add(d.0))
    }

    /// `self - d`, clamped at the origin.
    #[must_use]
    pub const fn saturating_sub(self, d: Duration) -> Self {
        Self(self.0.saturating_sub(d.0))
    }

    /// The time elapsed from `earlier` to `self`, or `None` if `earlier` is later.
    #[must_use]
    pub const fn checked_duration_since(self, earlier: Self) -> Option<Duration> {
        match self.0.checked_sub(earlier.0) {
            Some(v) => Some(Duration(v)),
            None => None,
        }
    }

    /// The time elapsed from `earlier` to `self`, zero if `earlier` is later.
    #[must_use]
    pub const fn saturating_duration_since(self, earlier: Self) -> Duration {
        Duration(self.0.saturating_sub(earlier.0))
    }
}

protocol_core::wire_derive! {
    [Eq, PartialOrd, Ord, Hash, Default]
    /// An instant of the caller's monotonic clock in nanoseconds, same origin as
    /// [`Instant`]: a timer's input capture or output compare finer than a microsecond
    /// (the PPS path: a PPS edge in, the RTC_IO edge out; see docs/src/bridge/time.md).
    pub struct InstantNs(u64);
}

impl InstantNs {
    /// The clock's origin.
    pub const ZERO: Self = Self(0);

    /// The instant `ns` nanoseconds after the origin.
    #[must_use]
    pub const fn from_nanos(ns: u64) -> Self {
        Self(ns)
    }

    /// The instant `at`, to the nanosecond (saturating).
    #[must_use]
    pub const fn from_instant(at: Instant) -> Self {
        Self(at.0.saturating_mul(NS_PER_US))
    }

    /// Nanoseconds since the origin.
    #[must_use]
    pub const fn as_nanos(self) -> u64 {
        self.0
    }

    /// The microsecond this instant falls in (rounded down): what a microsecond clock
    /// reads at it.
    #[must_use]
    pub const fn instant(self) -> Instant {
        Instant(self.0 / NS_PER_US)
    }

    /// Nanoseconds after [`InstantNs::instant`] (0..1000).
    #[must_use]
    pub const fn sub_micros_ns(self) -> u16 {
        // Below 1000: fits.
        #[allow(clippy::cast_possible_truncation)]
        let ns = (self.0 % NS_PER_US) as u16;
        ns
    }

    /// `self + ns`, clamped at the largest instant.
    #[must_use]
    pub const fn saturating_add_ns(self, ns: u64) -> Self {
        Self(self.0.saturating_add(ns))
    }

    /// `self - ns`, clamped at the origin.
    #[must_use]
    pub const fn saturating_sub_ns(self, ns: u64) -> Self {
        Self(self.0.saturating_sub(ns))
    }
}

protocol_core::wire_derive! {
    [Eq, PartialOrd, Ord, Hash, Default]
    /// A UTC time of day with millisecond resolution, as the K40T 0x000310 request carries it.
    pub struct TimeOfDay {
        hour: u8,
        minute: u8,
        second: u8,
        millisecond: u16,
    }
}

impl TimeOfDay {
    /// Midnight, 00:00:00.000.
    pub const MIDNIGHT: Self = Self {
        hour: 0,
        minute: 0,
        second: 0,
        millisecond: 0,
    };

    /// `hour:minute:second.millisecond`, or `None` unless hour ≤ 23, minute ≤ 59,
    /// second ≤ 59 and millisecond ≤ 999 (Unix time has no leap second 60).
    #[must_use]
    pub const fn new(hour: u8, minute: u8, second: u8, millisecond: u16) -> Option<Self> {
        if hour > 23 || minute > 59 || second > 59 || millisecond > 999 {
            return None;
        }
        Some(Self {
            hour,
            minute,
            second,
            millisecond,
        })
    }

    /// The time of day `ms` milliseconds after midnight, or `None` if `ms` is a day or
    /// more.
    #[must_use]
    pub const fn from_millis_of_day(ms: u32) -> Option<Self> {
        if ms >= MS_PER_DAY {
            return None;
        }
        // All four results are below 256 / 1000 by the check above: no truncation.
        #[allow(clippy::cast_possible_truncation)]
        Some(Self {
            hour: (ms / 3_600_000) as u8,
            minute: ((ms / 60_000) % 60) as u8,
            second: ((ms / 1_000) % 60) as u8,
            millisecond: (ms % 1_000) as u16,
        })
    }

    /// Milliseconds since midnight (0..86 400 000).
    #[must_use]
    pub const fn millis_of_day(self) -> u32 {
        // At most 23*3_600_000 + 59*60_000 + 59*1_000 + 999 < 2^32: no overflow.
        (self.hour as u32)
            .saturating_mul(3_600_000)
            .saturating_add((self.minute as u32).saturating_mul(60_000))
            .saturating_add((self.second as u32).saturating_mul(1_000))
            .saturating_add(self.millisecond as u32)
    }

    /// Hour, 0..=23.
    #[must_use]
    pub const fn hour(self) -> u8 {
        self.hour
    }

    /// Minute, 0..=59.
    #[must_use]
    pub const fn minute(self) -> u8 {
        self.minute
    }

    /// Second, 0..=59.
    #[must_use]
    pub const fn second(self) -> u8 {
        self.second
    }

    /// Millisecond, 0..=999.
    #[must_use]
    pub const fn millisecond(self) -> u16 {
        self.millisecond
    }
}

protocol_core::wire_derive! {
    [Eq, PartialOrd, Ord, Hash, Default]
    /// A UTC instant: microseconds since 1970-01-01T00:00:00Z, leap seconds not counted
    /// (Unix time).
    pub struct UtcTime(u64);
}

impl UtcTime {
    /// The Unix epoch, 1970-01-01T00:00:00Z.
    pub const UNIX_EPOCH: Self = Self(0);

    /// The instant `us` microseconds after the Unix epoch.
    #[must_use]
    pub const fn from_unix_micros(us: u64) -> Self {
        Self(us)
    }

    /// The instant `ms` milliseconds after the Unix epoch, or `None` on overflow.
    #[must_use]
    pub const fn from_unix_millis(ms: u64) -> Option<Self> {
        match ms.checked_mul(US_PER_MS) {
            Some(v) => Some(Self(v)),
            None => None,
        }
    }

    /// Microseconds since the Unix epoch.
    #[must_use]
    pub const fn as_unix_micros(self) -> u64 {
        self.0
    }

    /// Whole milliseconds since the Unix epoch, truncated (what a millisecond field
    /// such as K40T 0x00030E `unix_ms` carries).
    #[must_use]
    pub const fn as_unix_millis(self) -> u64 {
        self.0 / US_PER_MS
    }

    /// Milliseconds since the Unix epoch, rounded to the nearest millisecond.
    #[must_use]
    pub const fn as_unix_millis_rounded(self) -> u64 {
        self.0.saturating_add(US_PER_MS / 2) / US_PER_MS
    }

    /// The instant given as a calendar date and a time of day, or `None` for an
    /// invalid date (month 1..=12, day within the month) or a year outside 1970..=9999.
    #[must_use]
    pub fn from_date_time(year: u16, month: u8, day: u8, time: TimeOfDay) -> Option<Self> {
        let days = days_from_civil(year, month, day)?;
        let day_us = days.checked_mul(US_PER_DAY)?;
        let tod_us = u64::from(time.millis_of_day()).checked_mul(US_PER_MS)?;
        Some(Self(day_us.checked_add(tod_us)?))
    }

    /// The UTC instant of a GPS time (week number counted from 1980-01-06 without
    /// roll-over, time of week in milliseconds), with `leap_seconds` the current
    /// GPS − UTC difference (18 s since 2017). `None` on overflow or if the result would
    /// precede the Unix epoch.
    #[must_use]
    pub fn from_gps(week: u16, tow_ms: u32, leap_seconds: u8) -> Option<Self> {
        let week_s = u64::from(week).checked_mul(S_PER_WEEK)?;
        let s = GPS_EPOCH_UNIX_S
            .checked_add(week_s)?
            .checked_sub(u64::from(leap_seconds))?;
        let us = s
            .checked_mul(US_PER_S)?
            .checked_add(u64::from(tow_ms).checked_mul(US_PER_MS)?)?;
        Some(Self(us))
    }

    /// The time of day (UTC) of this instant, milliseconds truncated.
    #[must_use]
    pub const fn time_of_day(self) -> TimeOfDay {
        let ms = (self.0 % US_PER_DAY) / US_PER_MS;
        // ms < 86_400_000 fits u32 and is a valid time of day.
        match TimeOfDay::from_millis_of_day(ms as u32) {
            Some(t) => t,
            None => TimeOfDay::MIDNIGHT,
        }
    }

    /// The UTC calendar date of this instant: year, month (1..=12), day (1..=31).
    #[must_use]
    pub fn date(self) -> (u64, u8, u8) {
        civil_from_days(self.0 / US_PER_DAY)
    }

    /// The start (00:00:00.000) of this instant's UTC day.
    #[must_use]
    pub const fn start_of_day(self) -> Self {
        Self(self.0.saturating_sub(self.0 % US_PER_DAY))
    }

    /// The instant nearest to `self` whose UTC time of day is `time` (exactly, with
    /// zero microseconds): the one on `self`'s day, the day before or the day after.
    ///
    /// This resolves a time of day without a date (K40T 0x000310, Viewlink M_AHRS
    /// without date) across midnight: asked at 00:00:00.300 for 23:59:59.900, it returns
    /// the previous day's 23:59:59.900. `None` only near the ends of the representable
    /// range.
    #[must_use]
    pub fn nearest_with_time_of_day(self, time: TimeOfDay) -> Option<Self> {
        let tod_us = u64::from(time.millis_of_day()).checked_mul(US_PER_MS)?;
        let same_day = self.start_of_day().0.checked_add(tod_us)?;
        let mut best = same_day;
        let mut best_dist = same_day.abs_diff(self.0);
        for candidate in [
            same_day.checked_sub(US_PER_DAY),
            same_day.checked_add(US_PER_DAY),
        ]
        .into_iter()
        .flatten()
        {
            let dist = candidate.abs_diff(self.0);
            if dist < best_dist {
                best = candidate;
                best_dist = dist;
            }
        }
        Some(Self(best))
    }

    /// `self + d`, or `None` on overflow.
    #[must_use]
    pub const fn checked_add(self, d: Duration) -> Option<Self> {
        match self.0.checked_add(d.0) {
            Some(v) => Some(Self(v)),
            None => None,
        }
    }

    /// `self - d`, or `None` before the Unix epoch.
    #[must_use]
    pub const fn checked_sub(self, d: Duration) -> Option<Self> {
        match self.0.checked_sub(d.0) {
            Some(v) => Some(Self(v)),
            None => None,
        }
    }

    /// The time elapsed from `earlier` to `self`, or `None` if `earlier` is later.
    #[must_use]
    pub const fn checked_duration_since(self, earlier: Self) -> Option<Duration> {
        match self.0.checked_sub(earlier.0) {
            Some(v) => Some(Duration(v)),
            None => None,
        }
    }

    /// `self - other` in microseconds, signed, or `None` if it does not fit an `i64`.
    #[must_use]
    pub const fn signed_micros_since(self, other: Self) -> Option<i64> {
        let magnitude = self.0.abs_diff(other.0);
        if magnitude > i64::MAX.unsigned_abs() {
            return None;
        }
        // Checked just above: it fits.
        #[allow(clippy::cast_possible_wrap)]
        let m = magnitude as i64;
        if self.0 >= other.0 {
            Some(m)
        } else {
            Some(m.wrapping_neg())
        }
    }

    /// The first instant at or after `self` that is a whole multiple of `period` since
    /// the Unix epoch (`self` itself if it is one). `None` if `period` is zero or on
    /// overflow.
    #[must_use]
    pub const fn next_multiple_of(self, period: Duration) -> Option<Self> {
        match self.0.checked_next_multiple_of(period.0) {
            Some(v) => Some(Self(v)),
            None => None,
        }
    }
}

/// Days from 1970-01-01 to the given date (proleptic Gregorian), for years 1970..=9999.
/// After H. Hinnant's `days_from_civil`, restricted to non-negative results.
/// The date of `days` days after 1970-01-01 (the inverse of [`days_from_civil`], by the
/// same shift of the year to March).
fn civil_from_days(days: u64) -> (u64, u8, u8) {
    // 1970-03-01 is day 60 of the era that starts 0000-03-01 at day 719 468 before the
    // epoch; no step below overflows for any u64 day count divided this way.
    let z = days.saturating_add(719_468);
    let era = z / 146_097;
    let doe = z % 146_097;
    let yoe = doe
        .saturating_sub(doe / 1_460)
        .saturating_add(doe / 36_524)
        .saturating_sub(doe / 146_096)
        / 365;
    let y = yoe.saturating_add(era.saturating_mul(400));
    let doy = doe.saturating_sub(
        yoe.saturating_mul(365)
            .saturating_add(yoe / 4)
            .saturating_sub(yoe / 100),
    );
    let mp = doy.saturating_mul(5).saturating_add(2) / 153;
    let day = doy
        .saturating_sub(mp.saturating_mul(153).saturating_add(2) / 5)
        .saturating_add(1);
    let month = if mp < 10 {
        mp.saturating_add(3)
    } else {
        mp.saturating_sub(9)
    };
    let year = y.saturating_add(u64::from(month <= 2));
    (
        year,
        u8::try_from(month).unwrap_or(1),
        u8::try_from(day).unwrap_or(1),
    )
}

fn days_from_civil(year: u16, month: u8, day: u8) -> Option<u64> {
    if !(1970..=9999).contains(&year) || !(1..=12).contains(&month) || day < 1 {
        return None;
    }
    let leap = (year.is_multiple_of(4) && !year.is_multiple_of(100)) || year.is_multiple_of(400);
    let month_len: u8 = match month {
        2 if leap => 29,
        2 => 28,
        4 | 6 | 9 | 11 => 30,
        _ => 31,
    };
    if day > month_len {
        return None;
    }
    // Shift the year to start in March so that the leap day is the last of the year.
    let y = u64::from(year).checked_sub(u64::from(month <= 2))?;
    let era = y / 400;
    let yoe = y % 400;
    let m = u64::from(month);
    let mp = if m > 2 {
        m.checked_sub(3)?
    } else {
        m.checked_add(9)?
    };
    let doy = mp
        .checked_mul(153)?
        .checked_add(2)?
        .checked_div(5)?
        .checked_add(u64::from(day))?
        .checked_sub(1)?;
    let doe = yoe
        .checked_mul(365)?
        .checked_add(yoe / 4)?
        .checked_sub(yoe / 100)?
        .checked_add(doy)?;
    era.checked_mul(146_097)?
        .checked_add(doe)?
        .checked_sub(719_468)
}

/// A millisecond clock sent as a `u32` (an FC's `time_boot_ms`), unwrapped across its
/// wrap at 2^32 ms (49.7 days) by continuity: a value below the last one is a wrap when
/// the wrap's span matches the local time since the last within [`BootMs::TOLERANCE`]
/// (else it is a reboot, which starts again from the value, and the discipline sees the
/// step).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct BootMs {
    /// The last value and the local instant it came.
    last: Option<(u32, Instant)>,
    /// Wraps so far.
    wraps: u64,
}

impl BootMs {
    /// How far a wrap's span may be from the local time between its two values: a
    /// frame's transport and the two clocks' drift over the gap, never an FC reboot
    /// (seconds of silence).
    pub(crate) const TOLERANCE: Duration = Duration::from_millis(500);

    /// The whole count of milliseconds of `raw`, received at `now`.
    #[cfg_attr(not(feature = "siyi"), allow(dead_code))]
    pub(crate) fn unwrap(&mut self, raw: u32, now: Instant) -> u64 {
        if let Some((last, at)) = self.last
            && raw < last
        {
            let span = u64::from(raw)
                .saturating_add(1 << 32)
                .saturating_sub(u64::from(last));
            let elapsed = now.saturating_duration_since(at).as_millis();
            if span.abs_diff(elapsed) <= Self::TOLERANCE.as_millis() {
                self.wraps = self.wraps.saturating_add(1);
            }
        }
        self.last = Some((raw, now));
        self.wraps
            .saturating_mul(1 << 32)
            .saturating_add(u64::from(raw))
    }
}

/// `raw` (a `u32` millisecond count that wraps every 2^32 ms) as the whole count nearest
/// `expected_ms` (the same clock known another way: MAVLink SYSTEM_TIME's
/// `time_boot_ms` against TIMESYNC's 64-bit clock).
#[cfg_attr(not(feature = "mavlink"), allow(dead_code))]
pub(crate) fn nearest_wrap_ms(raw: u32, expected_ms: u64) -> u64 {
    const WRAP: u64 = 1 << 32;
    let wraps = expected_ms
        .saturating_sub(u64::from(raw))
        .saturating_add(WRAP / 2)
        / WRAP;
    wraps.saturating_mul(WRAP).saturating_add(u64::from(raw))
}

/// `Duration` and `UtcTime` bake as their `const` constructors (their field is private).
#[cfg(feature = "bake")]
mod bake {
    use databake::{Bake, BakeSize, CrateEnv, TokenStream, quote};

    use super::{Duration, UtcTime};

    impl Bake for Duration {
        fn bake(&self, env: &CrateEnv) -> TokenStream {
            env.insert("protocol_core");
            let us = self.0;
            quote!(bridge_engine::Duration::from_micros(#us))
        }
    }

    impl BakeSize for Duration {
        fn borrows_size(&self) -> usize {
            0
        }
    }

    impl Bake for UtcTime {
        fn bake(&self, env: &CrateEnv) -> TokenStream {
            env.insert("protocol_core");
            let us = self.0;
            quote!(bridge_engine::UtcTime::from_unix_micros(#us))
        }
    }

    impl BakeSize for UtcTime {
        fn borrows_size(&self) -> usize {
            0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The date of an instant is the one it was made from, every day from 1970 to 2400
    /// (leap years, their centuries, the year's ends).
    #[test]
    fn dates_round_trip() {
        let mut day = 0u64;
        for year in 1970u16..2400 {
            for month in 1u8..=12 {
                for d in 1u8..=31 {
                    if let Some(t) = UtcTime::from_date_time(year, month, d, TimeOfDay::MIDNIGHT) {
                        assert_eq!(t.as_unix_micros() / US_PER_DAY, day, "{year}-{month}-{d}");
                        assert_eq!(t.date(), (u64::from(year), month, d));
                        day += 1;
                    }
                }
            }
        }
        let (_, month, day) = UtcTime::from_unix_micros(u64::MAX).date();
        assert!((1..=12).contains(&month) && (1..=31).contains(&day));
    }

    #[test]
    fn the_nearest_wrap() {
        let w = 1u64 << 32;
        assert_eq!(nearest_wrap_ms(5, 0), 5);
        assert_eq!(nearest_wrap_ms(5, 4), 5);
        assert_eq!(nearest_wrap_ms(5, w + 3), w + 5);
        assert_eq!(nearest_wrap_ms(u32::MAX, w + 3), u64::from(u32::MAX));
        assert_eq!(nearest_wrap_ms(10, 3 * w - 2), 3 * w + 10);
    }

    #[test]
    fn boot_ms_unwraps_across_2_pow_32_and_not_across_a_reboot() {
        let mut b = BootMs::default();
        let at = |ms: u64| Instant::from_millis(1_000_000 + ms);
        assert_eq!(b.unwrap(u32::MAX - 99, at(0)), u64::from(u32::MAX) - 99);
        // 150 ms later the clock reads 49: wrapped.
        assert_eq!(b.unwrap(49, at(150)), (1 << 32) + 49);
        assert_eq!(b.unwrap(149, at(250)), (1 << 32) + 149);
        // A reboot: 3 s of silence, then a clock near 0.
        assert_eq!(b.unwrap(20, at(3_250)), (1 << 32) + 20);
        // Near the wrap again, a value that does not match the local time: no wrap.
        let mut b = BootMs::default();
        b.unwrap(u32::MAX - 10, at(0));
        assert_eq!(b.unwrap(5_000, at(100)), 5_000);
    }

    #[test]
    fn instant_and_duration_arithmetic() {
        let t = Instant::from_millis(1_500);
        assert_eq!(t.as_micros(), 1_500_000);
        assert_eq!(t.as_millis(), 1_500);
        let later = t.checked_add(Duration::from_millis(250)).unwrap();
        assert_eq!(later.as_micros(), 1_750_000);
        assert_eq!(
            later.checked_duration_since(t),
            Some(Duration::from_micros(250_000))
        );
        assert_eq!(t.checked_duration_since(later), None);
        assert_eq!(t.saturating_duration_since(later), Duration::ZERO);
        assert_eq!(Instant::ZERO.checked_sub(Duration::from_micros(1)), None);
        assert_eq!(
            Instant::from_micros(u64::MAX).checked_add(Duration::from_micros(1)),
            None
        );
        assert_eq!(Duration::from_secs(u64::MAX), Duration::MAX);
        assert_eq!(Duration::from_secs(10).as_millis(), 10_000);
    }

    #[test]
    fn unix_millis_round_trip_and_rounding() {
        // 2026-01-01T00:00:00Z, the K40T reference frame's value.
        let t = UtcTime::from_unix_millis(1_767_225_600_000).unwrap();
        assert_eq!(t.as_unix_micros(), 1_767_225_600_000_000);
        assert_eq!(t.as_unix_millis(), 1_767_225_600_000);
        let t = UtcTime::from_unix_micros(1_767_225_600_000_499);
        assert_eq!(t.as_unix_millis(), 1_767_225_600_000);
        assert_eq!(t.as_unix_millis_rounded(), 1_767_225_600_000);
        let t = UtcTime::from_unix_micros(1_767_225_600_000_500);
        assert_eq!(t.as_unix_millis_rounded(), 1_767_225_600_001);
        assert_eq!(UtcTime::from_unix_millis(u64::MAX), None);
    }

    #[test]
    fn calendar_dates() {
        assert_eq!(
            UtcTime::from_date_time(1970, 1, 1, TimeOfDay::MIDNIGHT),
            Some(UtcTime::UNIX_EPOCH)
        );
        assert_eq!(
            UtcTime::from_date_time(2026, 1, 1, TimeOfDay::MIDNIGHT)
                .unwrap()
                .as_unix_millis(),
            1_767_225_600_000
        );
        // 2024-02-29T12:34:56.789Z = 1709210096789 ms.
        let tod = TimeOfDay::new(12, 34, 56, 789).unwrap();
        assert_eq!(
            UtcTime::from_date_time(2024, 2, 29, tod)
                .unwrap()
                .as_unix_millis(),
            1_709_210_096_789
        );
        assert_eq!(UtcTime::from_date_time(2023, 2, 29, tod), None);
        assert_eq!(UtcTime::from_date_time(2023, 13, 1, tod), None);
        assert_eq!(UtcTime::from_date_time(1969, 12, 31, tod), None);
        // 2000-03-01 (a leap century).
        assert_eq!(
            UtcTime::from_date_time(2000, 3, 1, TimeOfDay::MIDNIGHT)
                .unwrap()
                .as_unix_millis(),
            951_868_800_000
        );
    }

    #[test]
    fn gps_time_to_utc() {
        // GPS week 2400, TOW 0 = 2026-01-04T00:00:00 GPS = 2026-01-03T23:59:42Z (18 s).
        let t = UtcTime::from_gps(2400, 0, 18).unwrap();
        let expected = UtcTime::from_date_time(2026, 1, 3, TimeOfDay::new(23, 59, 42, 0).unwrap());
        assert_eq!(Some(t), expected);
        let t = UtcTime::from_gps(2400, 86_400_123, 18).unwrap();
        assert_eq!(t.time_of_day(), TimeOfDay::new(23, 59, 42, 123).unwrap());
        assert_eq!(
            UtcTime::from_gps(0, 0, 0).unwrap().as_unix_millis(),
            315_964_800_000
        );
    }

    #[test]
    fn time_of_day_fields() {
        let t = UtcTime::from_unix_micros(1_709_210_096_789_999);
        let tod = t.time_of_day();
        assert_eq!(
            (tod.hour(), tod.minute(), tod.second(), tod.millisecond()),
            (12, 34, 56, 789)
        );
        assert_eq!(tod.millis_of_day(), 45_296_789);
        assert_eq!(TimeOfDay::from_millis_of_day(45_296_789), Some(tod));
        assert_eq!(TimeOfDay::from_millis_of_day(86_400_000), None);
        assert_eq!(TimeOfDay::new(24, 0, 0, 0), None);
        assert_eq!(TimeOfDay::new(0, 0, 60, 0), None);
        assert_eq!(TimeOfDay::new(0, 0, 0, 1000), None);
    }

    #[test]
    fn nearest_time_of_day_across_midnight() {
        let midnight = UtcTime::from_date_time(2026, 1, 2, TimeOfDay::MIDNIGHT).unwrap();
        let now = midnight.checked_add(Duration::from_millis(300)).unwrap();
        // Asked just after midnight for a time just before it: yesterday.
        let t = now
            .nearest_with_time_of_day(TimeOfDay::new(23, 59, 59, 900).unwrap())
            .unwrap();
        assert_eq!(t, midnight.checked_sub(Duration::from_millis(100)).unwrap());
        // Asked just before midnight for a time just after it: tomorrow.
        let now = midnight.checked_sub(Duration::from_millis(200)).unwrap();
        let t = now
            .nearest_with_time_of_day(TimeOfDay::new(0, 0, 0, 50).unwrap())
            .unwrap();
        assert_eq!(t, midnight.checked_add(Duration::from_millis(50)).unwrap());
        // Same day.
        let now = midnight.checked_add(Duration::from_secs(3_600)).unwrap();
        let t = now
            .nearest_with_time_of_day(TimeOfDay::new(0, 59, 58, 0).unwrap())
            .unwrap();
        assert_eq!(t, midnight.checked_add(Duration::from_secs(3_598)).unwrap());
        // Near the epoch the previous day does not exist; the same day still works.
        let t = UtcTime::from_unix_micros(10)
            .nearest_with_time_of_day(TimeOfDay::MIDNIGHT)
            .unwrap();
        assert_eq!(t, UtcTime::UNIX_EPOCH);
    }

    #[test]
    fn multiples_and_differences() {
        let t = UtcTime::from_unix_micros(1_767_225_603_000_001);
        assert_eq!(
            t.next_multiple_of(Duration::from_secs(10)),
            Some(UtcTime::from_unix_micros(1_767_225_610_000_000))
        );
        let exact = UtcTime::from_unix_micros(1_767_225_610_000_000);
        assert_eq!(exact.next_multiple_of(Duration::from_secs(10)), Some(exact));
        assert_eq!(t.next_multiple_of(Duration::ZERO), None);
        assert_eq!(exact.signed_micros_since(t), Some(6_999_999));
        assert_eq!(t.signed_micros_since(exact), Some(-6_999_999));
        assert_eq!(
            UtcTime::from_unix_micros(u64::MAX).signed_micros_since(UtcTime::UNIX_EPOCH),
            None
        );
    }
}
