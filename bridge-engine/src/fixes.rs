//! History of the aircraft's position and attitude, to answer the pod's K40T 0x000310
//! ("where were you at hh:mm:ss.mmm?") for an instant in the recent past.
//!
//! # Decisions
//! - **Time base**: each [`Fix`] is stamped with the local [`Instant`] it refers to (the
//!   engine maps the pod's UTC time of day to local time with the time discipline, and
//!   stamps FC fixes with their arrival or, better, their own FC time mapped to local).
//! - **Capacity**: [`CAPACITY`] = 201 fixes, 20 s at 10 Hz, stored column-wise
//!   (structure of arrays: 22 bytes per fix, no padding; times as `u32` microseconds
//!   relative to the newest fix, so they never wrap within the history).
//! - **Decimation**: a fix less than [`FixConfig::min_interval`] (90 ms) after the last
//!   stored one is not stored; it is kept aside as the newest fix (one slot) until the
//!   next stored one replaces it, so the history is about 10 Hz whatever the input rate
//!   (GCU 50 Hz) and the latest fix is never lost.
//! - **Order**: a fix older than the newest is rejected; one at the same instant
//!   replaces it.
//! - **Inside the history**: linear interpolation between the two fixes around the
//!   instant, rounded to the nearest unit. Yaw, roll, pitch and longitude follow the
//!   shortest arc across the ±180° wrap (359.9° → 0.1° passes through 0°, not 180°).
//! - **Gaps**: two consecutive fixes more than [`FixConfig::max_gap`] (1 s) apart are not
//!   interpolated between (that would invent a path): within [`FixConfig::max_hold`] of
//!   one of them the nearest is held, further it is [`GeotagError::OutOfRange`].
//! - **After the newest fix** (the FC's fixes stopped, or the next one is late): within
//!   [`FixConfig::max_hold`] (100 ms) it is held; up to [`FixConfig::max_extrapolate`]
//!   (1 s) it is carried forward with the aircraft's velocity, the FC's own when it sends
//!   one ([`Fix::velocity`]), else that of the two newest fixes (when they are at most
//!   [`FixConfig::max_gap`] apart); attitude is held. A held fix would put a photo taken
//!   0.8 s after the last fix 4 m behind at 5 m/s; carried forward, the error is the
//!   change of velocity in that time (half the acceleration times the time squared:
//!   0.5 m at 1 m/s² over 1 s). Further, or with no velocity: [`GeotagError::OutOfRange`].
//! - **Before the oldest fix**: held within [`FixConfig::max_hold`], else
//!   [`GeotagError::OutOfRange`]. No fix at all: [`GeotagError::NoFix`]. A position is
//!   never invented: an answer is interpolated, carried forward with a known velocity
//!   for a bounded time, or the failure code.

use core::fmt;

use super::time::{Duration, Instant};

/// Fixes the history holds (20 s at 10 Hz, plus one).
pub const CAPACITY: usize = 201;

/// The longest silence after which the history is kept (the 16-bit millisecond times
/// wrap after 65.5 s).
const MAX_SPAN: Duration = Duration::from_secs(60);

/// The low 16 bits of an instant in milliseconds.
fn low16(at: Instant) -> u16 {
    u16::try_from(at.as_millis() % 65_536).unwrap_or(0)
}

protocol_core::wire_derive! {
    [Eq, Default]
    /// The aircraft's velocity over ground, north-east-down, cm/s.
    pub struct Velocity {
        /// Towards north, cm/s.
        pub north_cm_s: i16,
        /// Towards east, cm/s.
        pub east_cm_s: i16,
        /// Downwards, cm/s.
        pub down_cm_s: i16,
    }
}

impl Velocity {
    /// A velocity in cm/s from one in another unit, saturating at ±327 m/s.
    #[must_use]
    pub fn from_cm_s(north: i32, east: i32, down: i32) -> Self {
        let c = |v: i32| i16::try_from(v).unwrap_or(if v < 0 { i16::MIN } else { i16::MAX });
        Self {
            north_cm_s: c(north),
            east_cm_s: c(east),
            down_cm_s: c(down),
        }
    }
}

protocol_core::wire_derive! {
    [Eq, Default]
    /// Position and attitude of the aircraft at a local instant, in the units of the K40T
    /// 0x010310 reply.
    pub struct Fix {
        /// Local instant the fix refers to.
        pub at: Instant,
        /// Latitude, 1e-7 degree.
        pub lat_e7: i32,
        /// Longitude, 1e-7 degree.
        pub lon_e7: i32,
        /// Altitude above mean sea level, 0.1 m.
        pub alt_msl_dm: i16,
        /// Height relative to home, 0.1 m.
        pub rel_alt_dm: i16,
        /// Yaw (heading), 0.01°, −18000..=18000.
        pub yaw_cdeg: i16,
        /// Roll, 0.01°.
        pub roll_cdeg: i16,
        /// Pitch, 0.01°.
        pub pitch_cdeg: i16,
        /// The aircraft's velocity at that instant, when the FC sends one (to carry the
        /// newest fix forward; see the module documentation).
        pub velocity: Option<Velocity>,
    }
}

protocol_core::wire_derive! {
    [Eq, Hash]
    /// Why no fix can be given for an instant.
    pub enum GeotagError {
        /// The history holds no fix.
        NoFix,
        /// The instant is further than the hold limit from any fix the history can use.
        OutOfRange,
    }
}

impl fmt::Display for GeotagError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NoFix => f.write_str("no fix received"),
            Self::OutOfRange => f.write_str("instant out of the fix history's range"),
        }
    }
}

impl core::error::Error for GeotagError {}

protocol_core::wire_derive! {
    [Eq]
    /// Settings of the [`FixHistory`].
    #[cfg_attr(feature = "bake", derive(databake::Bake), databake(path = bridge_engine::fixes))]
    pub struct FixConfig {
        /// Least time between two stored fixes (default 90 ms: about 10 Hz).
        pub min_interval: Duration,
        /// How far from a fix it is held unchanged (default 100 ms: 1 m at 10 m/s).
        pub max_hold: Duration,
        /// How far after the newest fix it is carried forward with the aircraft's velocity
        /// (default 1 s).
        pub max_extrapolate: Duration,
        /// Widest gap between two fixes that is interpolated (default 1 s).
        pub max_gap: Duration,
        /// How long a GPS request for an instant after the newest fix waits for the next
        /// fix (default 250 ms; zero: answer at once). See [`geotag`](super::geotag).
        pub max_wait: Duration,
    }
}

impl FixConfig {
    /// The documented defaults.
    pub const DEFAULT: Self = Self {
        min_interval: Duration::from_millis(90),
        max_hold: Duration::from_millis(100),
        max_extrapolate: Duration::from_secs(1),
        max_gap: Duration::from_secs(1),
        max_wait: Duration::from_millis(250),
    };
}

impl Default for FixConfig {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// A fixed-capacity ring of recent fixes, queried by local instant.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FixHistory {
    config: FixConfig,
    /// The fix's local instant in milliseconds, low 16 bits: differences to the newest
    /// fix are exact while the history spans less than 65 s ([`FixHistory::push`] clears
    /// it after a longer silence).
    t_ms: [u16; CAPACITY],
    lat_e7: [i32; CAPACITY],
    lon_e7: [i32; CAPACITY],
    alt_msl_dm: [i16; CAPACITY],
    rel_alt_dm: [i16; CAPACITY],
    yaw_cdeg: [i16; CAPACITY],
    roll_cdeg: [i16; CAPACITY],
    pitch_cdeg: [i16; CAPACITY],
    /// Physical index of the oldest stored fix.
    start: u16,
    /// Stored fixes.
    len: u16,
    /// Instant of the newest stored fix (the time base of `t_ms`).
    newest: Instant,
    /// The newest fix when it was too close to the last stored one to be stored.
    tail: Option<Fix>,
    /// How fast the newest fix moves: from the velocity the FC sent with it, else from
    /// the fix before it.
    rate: Option<Rate>,
}

impl Default for FixHistory {
    fn default() -> Self {
        Self::new(FixConfig::DEFAULT)
    }
}

impl FixHistory {
    /// An empty history.
    #[must_use]
    pub const fn new(config: FixConfig) -> Self {
        Self {
            config,
            t_ms: [0; CAPACITY],
            lat_e7: [0; CAPACITY],
            lon_e7: [0; CAPACITY],
            alt_msl_dm: [0; CAPACITY],
            rel_alt_dm: [0; CAPACITY],
            yaw_cdeg: [0; CAPACITY],
            roll_cdeg: [0; CAPACITY],
            pitch_cdeg: [0; CAPACITY],
            start: 0,
            len: 0,
            newest: Instant::ZERO,
            tail: None,
            rate: None,
        }
    }

    /// The settings.
    #[must_use]
    pub const fn config(&self) -> &FixConfig {
        &self.config
    }

    /// Forgets every fix.
    pub fn clear(&mut self) {
        self.start = 0;
        self.len = 0;
        self.tail = None;
        self.rate = None;
    }

    /// Fixes usable by [`at`](Self::at) (stored ones plus the newest kept aside).
    #[must_use]
    pub fn len(&self) -> usize {
        usize::from(self.len).saturating_add(usize::from(self.tail.is_some()))
    }

    /// No fix at all.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The newest fix.
    #[must_use]
    pub fn latest(&self) -> Option<Fix> {
        self.get(self.len().checked_sub(1)?)
    }

    /// Adds a fix. Returns `false` (and ignores it) if it is older than the newest fix.
    pub fn push(&mut self, fix: Fix) -> bool {
        let latest = self.latest().map(|l| l.at);
        if latest.is_some_and(|l| fix.at < l) {
            return false;
        }
        self.rate = match fix.velocity {
            Some(v) => per_second(v, fix.lat_e7),
            None => self
                .latest()
                .and_then(|prev| self.rate_between(&prev, &fix)),
        };
        if latest == Some(fix.at) {
            if self.tail.is_some() {
                self.tail = Some(fix);
            } else {
                // Replace the newest stored fix.
                let _ = self.store(self.len.saturating_sub(1), fix);
            }
            return true;
        }
        let far_enough = self.len == 0
            || fix.at.saturating_duration_since(self.newest) >= self.config.min_interval;
        if far_enough {
            self.append(fix);
            self.tail = None;
        } else {
            self.tail = Some(fix);
        }
        true
    }

    fn physical(&self, i: u16) -> usize {
        usize::from(self.start).saturating_add(usize::from(i)) % CAPACITY
    }

    fn append(&mut self, fix: Fix) {
        // The 16-bit millisecond times need a history shorter than 65 s: after a longer
        // silence the old fixes are of no use anyway (a gap over `max_gap` is not
        // interpolated), so they go.
        if fix.at.saturating_duration_since(self.newest) > MAX_SPAN {
            self.len = 0;
            self.start = 0;
        }
        if usize::from(self.len) >= CAPACITY {
            self.start = u16::try_from(self.physical(1)).unwrap_or(0);
        } else {
            self.len = self.len.saturating_add(1);
        }
        self.newest = fix.at;
        let _ = self.store(self.len.saturating_sub(1), fix);
    }

    /// Writes `fix` at logical index `i`.
    fn store(&mut self, i: u16, fix: Fix) -> Option<()> {
        let p = self.physical(i);
        *self.t_ms.get_mut(p)? = low16(fix.at);
        *self.lat_e7.get_mut(p)? = fix.lat_e7;
        *self.lon_e7.get_mut(p)? = fix.lon_e7;
        *self.alt_msl_dm.get_mut(p)? = fix.alt_msl_dm;
        *self.rel_alt_dm.get_mut(p)? = fix.rel_alt_dm;
        *self.yaw_cdeg.get_mut(p)? = fix.yaw_cdeg;
        *self.roll_cdeg.get_mut(p)? = fix.roll_cdeg;
        *self.pitch_cdeg.get_mut(p)? = fix.pitch_cdeg;
        Some(())
    }

    /// The `i`-th usable fix, oldest first (the kept-aside newest last).
    fn get(&self, i: usize) -> Option<Fix> {
        let stored = usize::from(self.len);
        if i >= stored {
            return if i == stored { self.tail } else { None };
        }
        let p = self.physical(u16::try_from(i).ok()?);
        let before_newest = low16(self.newest).wrapping_sub(*self.t_ms.get(p)?);
        let at = Instant::from_millis(
            self.newest
                .as_millis()
                .checked_sub(u64::from(before_newest))?,
        );
        Some(Fix {
            at,
            lat_e7: *self.lat_e7.get(p)?,
            lon_e7: *self.lon_e7.get(p)?,
            alt_msl_dm: *self.alt_msl_dm.get(p)?,
            rel_alt_dm: *self.rel_alt_dm.get(p)?,
            yaw_cdeg: *self.yaw_cdeg.get(p)?,
            roll_cdeg: *self.roll_cdeg.get(p)?,
            pitch_cdeg: *self.pitch_cdeg.get(p)?,
            velocity: None,
        })
    }

    /// Position and attitude at local instant `at`: interpolated inside the history,
    /// carried forward with the velocity after the newest fix, held within
    /// [`FixConfig::max_hold`] of a fix otherwise, an error beyond (see the module
    /// documentation).
    ///
    /// # Errors
    /// [`GeotagError::NoFix`] when the history is empty, [`GeotagError::OutOfRange`] when
    /// `at` is too far from every usable fix, or after the newest with no velocity.
    pub fn at(&self, at: Instant) -> Result<Fix, GeotagError> {
        let n = self.len();
        let first = self.get(0).ok_or(GeotagError::NoFix)?;
        let last = self.get(n.saturating_sub(1)).ok_or(GeotagError::NoFix)?;
        if at < first.at {
            return self.hold(first, at);
        }
        if at >= last.at {
            return self.forward(last, at);
        }
        // Binary search: the last fix at or before `at` (index lo), first after (lo + 1).
        let (mut lo, mut hi) = (0usize, n.saturating_sub(1));
        while hi.saturating_sub(lo) > 1 {
            let mid = lo.saturating_add(hi.saturating_sub(lo) / 2);
            let m = self.get(mid).ok_or(GeotagError::NoFix)?;
            if m.at <= at {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let a = self.get(lo).ok_or(GeotagError::NoFix)?;
        let b = self.get(hi).ok_or(GeotagError::NoFix)?;
        let gap = b.at.saturating_duration_since(a.at);
        if gap > self.config.max_gap {
            let to_a = at.saturating_duration_since(a.at);
            let to_b = b.at.saturating_duration_since(at);
            let nearest = if to_a <= to_b { a } else { b };
            return self.hold(nearest, at);
        }
        interpolate(&a, &b, at).ok_or(GeotagError::OutOfRange)
    }

    fn hold(&self, fix: Fix, at: Instant) -> Result<Fix, GeotagError> {
        let d = at.as_micros().abs_diff(fix.at.as_micros());
        if d <= self.config.max_hold.as_micros() {
            Ok(fix)
        } else {
            Err(GeotagError::OutOfRange)
        }
    }

    /// The newest fix carried forward to `at` (not before it).
    fn forward(&self, last: Fix, at: Instant) -> Result<Fix, GeotagError> {
        let dt = at.saturating_duration_since(last.at);
        if dt <= self.config.max_hold {
            return Ok(last);
        }
        if dt > self.config.max_extrapolate {
            return Err(GeotagError::OutOfRange);
        }
        let us = i64::try_from(dt.as_micros()).map_err(|_| GeotagError::OutOfRange)?;
        self.rate
            .and_then(|r| r.scaled(us).apply(&last, at))
            .ok_or(GeotagError::OutOfRange)
    }

    /// How fast the aircraft went from `a` to `b`, when they are at most `max_gap` apart.
    fn rate_between(&self, a: &Fix, b: &Fix) -> Option<Rate> {
        let span = b.at.checked_duration_since(a.at)?;
        if span > self.config.max_gap {
            return None;
        }
        let den = i64::try_from(span.as_micros()).ok().filter(|d| *d > 0)?;
        // |difference| ≤ 3.6e9 (1e-7°), times 1e9: no product saturates.
        let per_s = |d: i64| d.saturating_mul(RATE_SCALE).checked_div(den);
        let diff = |x: i32, y: i32| i64::from(y).saturating_sub(i64::from(x));
        Some(Rate {
            lat_e7: per_s(diff(a.lat_e7, b.lat_e7))?,
            lon_e7: per_s(wrap(diff(a.lon_e7, b.lon_e7), 1_800_000_000)?)?,
            up_dm: per_s(diff(i32::from(a.alt_msl_dm), i32::from(b.alt_msl_dm)))?,
        })
    }
}

/// How far a fix is carried forward: 1e-7° north and east, 0.1 m up.
#[derive(Debug, Clone, Copy)]
struct Step {
    lat_e7: i64,
    lon_e7: i64,
    up_dm: i64,
}

/// The rate of a [`Step`]: its units per microsecond, times [`RATE_SCALE`] (1e-3 unit per
/// second).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Rate {
    lat_e7: i64,
    lon_e7: i64,
    up_dm: i64,
}

/// The scale of a [`Rate`]: 1e9 per unit per microsecond.
const RATE_SCALE: i64 = 1_000_000_000;

impl Rate {
    /// The step this rate makes in `us` microseconds.
    fn scaled(self, us: i64) -> Step {
        // A rate of at most 3e7 (330 m/s) times a few seconds of µs: no product saturates.
        let s = |v: i64| v.saturating_mul(us) / RATE_SCALE;
        Step {
            lat_e7: s(self.lat_e7),
            lon_e7: s(self.lon_e7),
            up_dm: s(self.up_dm),
        }
    }
}

impl Step {
    /// `fix` moved by this step, at `at`, attitude unchanged.
    fn apply(self, fix: &Fix, at: Instant) -> Option<Fix> {
        let lat = i64::from(fix.lat_e7).saturating_add(self.lat_e7);
        let lon = wrap(
            i64::from(fix.lon_e7).saturating_add(self.lon_e7),
            1_800_000_000,
        )?;
        let up = |a: i16| i16::try_from(i64::from(a).saturating_add(self.up_dm)).ok();
        Some(Fix {
            at,
            lat_e7: i32::try_from(lat).ok()?,
            lon_e7: i32::try_from(lon).ok()?,
            alt_msl_dm: up(fix.alt_msl_dm)?,
            rel_alt_dm: up(fix.rel_alt_dm)?,
            ..*fix
        })
    }
}

/// Micrometres per 1e-7° of latitude (WGS-84 mean: 111 319.49 m per degree), times 100.
const UM_PER_E7_DEG_X100: i64 = 1_113_195;

/// A velocity at latitude `lat_e7` as a [`Rate`].
fn per_second(v: Velocity, lat_e7: i32) -> Option<Rate> {
    // Longitude degrees are shorter by cos(latitude) (parts per 65536); within 0.06° of a
    // pole longitude is no direction to carry a fix along.
    let cos = cos_q16(lat_e7);
    if cos < 64 {
        return None;
    }
    // cm/s = 1e4 µm/s; 1e-7°/s × 1e3 = µm/s × 1e5 / UM_PER_E7_DEG_X100.
    let scaled = |cm_s: i16| i64::from(cm_s).saturating_mul(1_000_000_000);
    Some(Rate {
        lat_e7: scaled(v.north_cm_s) / UM_PER_E7_DEG_X100,
        lon_e7: scaled(v.east_cm_s)
            .saturating_mul(65_536)
            .checked_div(UM_PER_E7_DEG_X100.saturating_mul(cos))?,
        // cm/s down → 0.1 m/s up, × 1e3.
        up_dm: i64::from(v.down_cm_s).saturating_mul(-100),
    })
}

/// cos(latitude) in parts per 65536 for a latitude in 1e-7°, by a degree-8 polynomial
/// (error below 1e-4 over ±90°).
fn cos_q16(lat_e7: i32) -> i64 {
    // In f32: the polynomial is short and exact enough; no panicking operation.
    #[allow(clippy::cast_precision_loss)]
    let x = (lat_e7.unsigned_abs().min(900_000_000) as f32) * (core::f32::consts::PI / 1.8e9);
    let x2 = x * x;
    let c = 1.0 - x2 / 2.0 * (1.0 - x2 / 12.0 * (1.0 - x2 / 30.0 * (1.0 - x2 / 56.0)));
    // 0..=65536 fits an i32.
    #[allow(clippy::cast_possible_truncation)]
    let q = (c.clamp(0.0, 1.0) * 65_536.0) as i32;
    i64::from(q)
}

/// `a + (b − a)·num/den`, rounded to nearest (half away from zero).
fn lerp(a: i64, diff: i64, num: i64, den: i64) -> Option<i64> {
    let p = i128::from(diff).checked_mul(i128::from(num))?;
    let half = i128::from(den) / 2;
    let q = if p >= 0 {
        p.checked_add(half)?.checked_div(i128::from(den))?
    } else {
        p.checked_sub(half)?.checked_div(i128::from(den))?
    };
    i64::try_from(i128::from(a).checked_add(q)?).ok()
}

/// `v` wrapped into `(−half, half]` for a circle of `2·half` units.
fn wrap(v: i64, half: i64) -> Option<i64> {
    let full = half.checked_mul(2)?;
    let r = v
        .checked_add(half)?
        .checked_rem_euclid(full)?
        .checked_sub(half)?;
    // rem_euclid gives [−half, half); move −half to +half.
    if r == half.checked_neg()? {
        Some(half)
    } else {
        Some(r)
    }
}

/// Interpolates an angle along the shortest arc, result in `(−half, half]`.
fn lerp_angle(a: i64, b: i64, num: i64, den: i64, half: i64) -> Option<i64> {
    let diff = wrap(b.checked_sub(a)?, half)?;
    wrap(lerp(a, diff, num, den)?, half)
}

fn interpolate(a: &Fix, b: &Fix, at: Instant) -> Option<Fix> {
    const HALF_CDEG: i64 = 18_000;
    const HALF_E7: i64 = 1_800_000_000;
    let den = i64::try_from(b.at.checked_duration_since(a.at)?.as_micros()).ok()?;
    let num = i64::try_from(at.checked_duration_since(a.at)?.as_micros()).ok()?;
    if den <= 0 {
        return Some(*a);
    }
    let linear = |x: i64, y: i64| lerp(x, y.checked_sub(x)?, num, den);
    let angle_i16 = |x: i16, y: i16| {
        i16::try_from(lerp_angle(i64::from(x), i64::from(y), num, den, HALF_CDEG)?).ok()
    };
    Some(Fix {
        at,
        lat_e7: i32::try_from(linear(i64::from(a.lat_e7), i64::from(b.lat_e7))?).ok()?,
        lon_e7: i32::try_from(lerp_angle(
            i64::from(a.lon_e7),
            i64::from(b.lon_e7),
            num,
            den,
            HALF_E7,
        )?)
        .ok()?,
        alt_msl_dm: i16::try_from(linear(i64::from(a.alt_msl_dm), i64::from(b.alt_msl_dm))?)
            .ok()?,
        rel_alt_dm: i16::try_from(linear(i64::from(a.rel_alt_dm), i64::from(b.rel_alt_dm))?)
            .ok()?,
        yaw_cdeg: angle_i16(a.yaw_cdeg, b.yaw_cdeg)?,
        roll_cdeg: angle_i16(a.roll_cdeg, b.roll_cdeg)?,
        pitch_cdeg: angle_i16(a.pitch_cdeg, b.pitch_cdeg)?,
        velocity: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fix(ms: u64, lat: i32, lon: i32, yaw: i16) -> Fix {
        Fix {
            at: Instant::from_millis(ms),
            lat_e7: lat,
            lon_e7: lon,
            alt_msl_dm: 1000,
            rel_alt_dm: 500,
            yaw_cdeg: yaw,
            roll_cdeg: 0,
            pitch_cdeg: -100,
            velocity: None,
        }
    }

    #[test]
    fn empty_history() {
        let h = FixHistory::default();
        assert!(h.is_empty());
        assert_eq!(h.at(Instant::from_millis(5)), Err(GeotagError::NoFix));
    }

    #[test]
    fn interpolates_and_wraps_angles() {
        let mut h = FixHistory::default();
        assert!(h.push(fix(1_000, 100, 1_799_999_990, 17_900)));
        assert!(h.push(fix(1_100, 200, -1_799_999_990, -17_900)));
        let f = h.at(Instant::from_millis(1_050)).unwrap();
        assert_eq!(f.at, Instant::from_millis(1_050));
        assert_eq!(f.lat_e7, 150);
        // Across the antimeridian and the ±180° yaw wrap: through 180°, not 0°.
        assert_eq!(f.lon_e7, 1_800_000_000);
        assert_eq!(f.yaw_cdeg, 18_000);
        assert_eq!(f.alt_msl_dm, 1000);
        assert_eq!(f.pitch_cdeg, -100);
        let f = h.at(Instant::from_millis(1_075)).unwrap();
        assert_eq!(f.yaw_cdeg, -17_950);
        assert_eq!(f.lon_e7, -1_799_999_995);
        // Exactly on a fix.
        assert_eq!(h.at(Instant::from_millis(1_000)).unwrap().lat_e7, 100);
        // Rounded to nearest: 1/3 of the way from 100 to 200.
        let f = h.at(Instant::from_micros(1_033_333)).unwrap();
        assert_eq!(f.lat_e7, 133);
    }

    #[test]
    fn holds_briefly_then_carries_the_newest_fix_forward_with_its_velocity() {
        let mut h = FixHistory::default();
        h.push(fix(10_000, 1, 2, 3));
        h.push(fix(10_100, 5, 6, 7));
        // Within 100 ms: held.
        let f = h.at(Instant::from_millis(10_200)).unwrap();
        assert_eq!((f.at, f.lat_e7), (Instant::from_millis(10_100), 5));
        // Beyond: carried forward at the two newest fixes' velocity (no FC velocity).
        let f = h.at(Instant::from_millis(10_600)).unwrap();
        assert_eq!(
            (f.at, f.lat_e7, f.lon_e7),
            (Instant::from_millis(10_600), 25, 26)
        );
        assert_eq!(f.yaw_cdeg, 7, "attitude held");
        assert!(h.at(Instant::from_millis(11_100)).is_ok());
        assert_eq!(
            h.at(Instant::from_millis(11_101)),
            Err(GeotagError::OutOfRange)
        );
        // Before the oldest: held within 100 ms only.
        let f = h.at(Instant::from_millis(9_900)).unwrap();
        assert_eq!(f.lat_e7, 1);
        assert_eq!(
            h.at(Instant::from_millis(9_899)),
            Err(GeotagError::OutOfRange)
        );
        // One fix and no velocity: nothing to carry it forward with.
        let mut h = FixHistory::default();
        h.push(fix(10_000, 1, 2, 3));
        assert!(h.at(Instant::from_millis(10_100)).is_ok());
        assert_eq!(
            h.at(Instant::from_millis(10_101)),
            Err(GeotagError::OutOfRange)
        );
    }

    #[test]
    fn the_fcs_velocity_carries_a_photo_0_8_s_after_the_last_fix_to_where_it_was() {
        // 47° N, 5 m/s north and 5 m/s east, climbing 1 m/s: 0.8 s after the last fix the
        // aircraft is 4 m north, 4 m east, 0.8 m higher. Held, the fix would be 5.7 m off.
        let mut h = FixHistory::default();
        let mut f = fix(10_000, 470_000_000, 85_000_000, 4500);
        f.velocity = Some(Velocity::from_cm_s(500, 500, -100));
        h.push(f);
        let g = h.at(Instant::from_millis(10_800)).unwrap();
        // 4 m of latitude: 4 / 111 319.49 m per degree = 359.3e-7°.
        assert_eq!(g.lat_e7 - 470_000_000, 359);
        // 4 m of longitude at 47°: 4 / (111 319.49 × cos 47°) = 526.9e-7°.
        assert!(
            (526..=527).contains(&(g.lon_e7 - 85_000_000)),
            "{}",
            g.lon_e7
        );
        assert_eq!((g.alt_msl_dm, g.rel_alt_dm), (1008, 508));
        assert_eq!(g.yaw_cdeg, 4500);
    }

    #[test]
    fn decimates_and_keeps_twenty_seconds() {
        let mut h = FixHistory::default();
        // 50 Hz for 30 s; latitude = time in ms.
        for i in 0..1_500u64 {
            let ms = i * 20;
            assert!(h.push(fix(ms, i32::try_from(ms).unwrap(), 0, 0)));
        }
        // 201 stored (every 100 ms) plus the newest aside.
        assert_eq!(h.len(), CAPACITY + 1);
        assert_eq!(h.latest().unwrap().at, Instant::from_millis(29_980));
        let oldest = h.get(0).unwrap();
        assert_eq!(oldest.at, Instant::from_millis(9_900));
        assert!(oldest.velocity.is_none());
        // Interpolated between stored fixes 100 ms apart: exact for a linear input.
        assert_eq!(h.at(Instant::from_millis(15_030)).unwrap().lat_e7, 15_030);
        // Between the last stored and the newest aside.
        assert_eq!(h.at(Instant::from_millis(29_950)).unwrap().lat_e7, 29_950);
        // An older fix is refused; one at the same instant replaces the newest.
        assert!(!h.push(fix(29_000, 0, 0, 0)));
        assert!(h.push(fix(29_980, 7, 0, 0)));
        assert_eq!(h.latest().unwrap().lat_e7, 7);
        h.clear();
        assert!(h.is_empty());
    }

    #[test]
    fn cosine_of_latitude() {
        for (deg, want_q16) in [
            (0, 65_536),
            (30, 56_756),
            (47, 44_695),
            (60, 32_768),
            (89, 1_144),
        ] {
            let lat = deg * 10_000_000;
            let got = cos_q16(lat);
            assert!((got - want_q16).abs() <= 8, "{deg}: {got}");
            assert_eq!(cos_q16(-lat), got);
        }
        assert!(cos_q16(900_000_000) <= 2);
        let v = Velocity::from_cm_s(0, 500, 0);
        assert!(per_second(v, 899_999_000).is_none());
    }
}
