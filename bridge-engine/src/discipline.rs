//! Time discipline: the mapping between the bridge's local clock ([`Instant`]) and UTC,
//! learnt from the time values the flight controller (FC) sends.
//!
//! # Model
//! A remote clock (UTC, or the FC's own `time_boot_ms`) is read by the sender, the value
//! is truncated to the sender's resolution, put in a frame, and the frame reaches the
//! bridge after a transport delay that is unknown but never negative. So for every
//! [`Sample`] the remote time at the sample's arrival is **at least** the value carried:
//! `remote(arrival) ≥ value`. The bridge writes each sample as a point
//! `(x, y) = (local, local − value)` on the local time axis; `y` is the clock offset plus
//! the sample's delay plus its truncation phase, all non-negative, so the true offset line
//! lies **under** every point and the least-delayed points touch it.
//!
//! # Estimator (per clock)
//! Minimum-delay filtering, then a skew fit, after Moon, Skelly and Towsley ("Estimation
//! and removal of clock skew from network delay measurements", 1999):
//! - Samples are grouped in bins of [`DisciplineConfig::bin_len`] of local time (8 s by
//!   default); each bin keeps only its least-delayed point (the minimum of `y`).
//! - The last [`BINS`] bins (256 s by default) form the window. The rate is that of the
//!   solution of Moon's linear programme over the bin minima: the line under all points
//!   that minimises the summed distance to them, i.e. the edge of their lower convex hull
//!   above their mean local time. The line is then moved to touch the lowest of the last
//!   [`DisciplineConfig::anchor_bins`] bins (4), so that a rate error is extrapolated
//!   over a few bins, not over half the window. Integer arithmetic only (`i64`, `i128`
//!   products); the fit is recomputed only when a bin minimum changes (a few times per
//!   bin), not per sample.
//! - The window length is a trade-off measured in the simulation (`host-tests/tests/
//!   timesync_sim.rs`): 4 s bins (128 s) gave rate errors of tens of ppm when the
//!   least delays are noisy (SIYI's 0x22 behind other frames); 8 s bins (256 s) assume
//!   the crystals' rates stay stable over about four minutes.
//! - The state is fixed-size: [`BINS`] points of 16 bytes per clock.
//!
//! # Truncation
//! A value truncated to a resolution `r` was read up to `r` before it says, and the
//! sender's read instant is often phase-locked to its truncation grid (ArduPilot reads
//! its UTC on a 50 Hz loop paced by the same crystal as that UTC), so the minimum over
//! samples does **not** remove the truncation error: it stays a constant in `[0, r)` for
//! the whole flight. With [`DisciplineConfig::center_truncation`] (default on) the
//! discipline reads a value as `value + r/2`, halving the worst case to `±r/2`
//! (Viewlink, 10 ms resolution: ±5 ms). The same holds for a held value (GCU: the time
//! of the last GPS fix): the first sample after a fix was read up to one sender update
//! after the fix, so its "resolution" is the sender's update period (ArduPilot: 20 ms),
//! read phase-locked too (the FC loop against the GPS epochs slides only by the FC
//! crystal's error): ±10 ms.
//!
//! # Sources
//! - Direct UTC ([`TimeDiscipline::utc_sample`]): Viewlink M_AHRS, GCU GPS week and time of
//!   week (the caller converts GPS time to UTC, leap seconds included), the K40T FC's
//!   0x00030E.
//! - Through the FC clock (SIYI): [`TimeDiscipline::fc_clock_sample`] feeds a second
//!   estimator with `time_boot_ms`; the UTC − FC-clock offset `C` comes from SIYI 0x30
//!   frames. [`TimeDiscipline::utc_fc_pair`] takes a 0x30 and a 0x22/0x3E written in the
//!   same FC update (same burst): `C = utc − fc_ms·1000 − u`, `u ∈ [0, 1000)` µs. The
//!   discipline takes `C = min(utc − fc_ms·1000)` over the pairs, the upper end of their
//!   intersection, which has the same "floor" convention as the FC-clock estimator (both
//!   are late by the FC's sub-millisecond read phase, which cancels in `UTC = FC + C`).
//!   [`TimeDiscipline::utc_via_fc_sample`] takes a 0x30 alone: `C ≥ utc − fc(arrival)`,
//!   the maximum over such samples is a lower bound; pairs below that bound (minus
//!   [`DisciplineConfig::pair_tolerance`]) are rejected as inconsistent. Without any
//!   pair, `C` is that lower bound.
//!
//! One estimator serves the path the flight controller uses (the first sample decides;
//! an FC protocol has one path).
//!
//! # Validity rule: a first mapping at once, then the fit
//! A clock estimator is *converged* when its window holds at least
//! [`DisciplineConfig::min_bins`] bins spanning at least [`DisciplineConfig::min_span`]
//! and the fitted rate is within [`DisciplineConfig::max_drift_ppm`] (about 32 s of
//! samples). Before that it gives a **first mapping** as soon as it has accepted
//! [`DisciplineConfig::quick_samples`] samples (8: under a second of a 10 Hz source), or
//! one [prompt](Sample::prompt) sample (the K40T FC's 0x00030E): a flat line (equal
//! clock rates assumed) through the least-delayed recent sample. Its error grows with
//! the time since that sample by the crystals' possible rate difference
//! ([`DisciplineConfig::quick_drift_ppm`], 100 ppm: 1 ms in 10 s), so the first time sync
//! can go out on the first 10 s grid edge after the FC's first usable time, within a few
//! milliseconds, and the fit takes over, seamlessly, once it converges.
//!
//! The UTC mapping is [`DisciplineState::Valid`] while its path gives one (for SIYI: the
//! FC clock's mapping and `C` known) and a fresh sample arrived within
//! [`DisciplineConfig::sample_timeout`]. A held value counts as fresh only when it changes
//! (a GCU repeating the last fix of a lost GPS is not fresh).
//! [`TimeDiscipline::error_bound`] says what error the discipline believes the mapping has
//! at an instant; the engine sends no time sync whose bound exceeds its limit.
//!
//! # Jumps of the source
//! A sample further from the current fit than [`DisciplineConfig::jump_tolerance`] (15 ms)
//! plus its resolution contradicts it: it is not used. One such sample *below* the fit's
//! floor (impossible for a delay: the source jumped forward), or three in a row above it,
//! make the direct mapping [`DisciplineState::Suspect`]: no UTC, no sync, until a
//! consistent sample comes. When [`DisciplineConfig::step_confirm`] (5) consecutive
//! contradicting samples agree with each other, the source has stepped: the estimator
//! restarts from them and gives a first mapping again after
//! [`DisciplineConfig::quick_samples`]. A wrong stamp is worse than none.
//! - A UTC step (GPS time jump, an FC rebooted with another UTC) discards the UTC
//!   mapping.
//! - An FC clock step (FC reboot: `time_boot_ms` going backwards, or jumping) only
//!   invalidates the FC clock and `C`; the local→UTC mapping, which did not change, stays
//!   usable in holdover until the new FC clock and `C` are learnt; if they then disagree
//!   with it by more than the jump tolerance, the new mapping replaces it (reported as
//!   UTC lost and valid again, [`Transition::replaced`]).
//!
//! Smaller steps are taken as ordinary samples: a forward step lowers the bin minima at
//! once, a backward step is absorbed as the anchor bins (the last 32 s) renew.
//!
//! # Holdover
//! When fresh samples stop, the last mapping stays usable
//! ([`DisciplineState::Holdover`]) for [`DisciplineConfig::holdover`] (60 s) after the
//! last fresh sample, extrapolated with the fitted rate; then the state becomes
//! [`DisciplineState::Lost`], the estimators restart, and [`TimeDiscipline::utc`] returns
//! `None`. [`TimeDiscipline::utc`] and [`TimeDiscipline::local_of`] also refuse instants
//! beyond that horizon.
//!
//! # Known limits
//! - A constant delay the caller does not report ([`Sample::transit`]) appears as a
//!   constant bias: e.g. a GPS receiver's output latency before the GCU's time of week
//!   reaches the FC (tens of ms), which this discipline cannot see.
//! - The read-phase limit above: a source truncated to `r` and read phase-locked is only
//!   known to `±r/2`.
//! - For SIYI the result is the FC's UTC (ArduPilot: boot-time clock plus a shift set
//!   from GPS, frozen while armed), so the FC crystal's error accumulates against GPS UTC
//!   over the flight; SIYI gives no later UTC to correct it.

use super::time::{Duration, Instant, UtcTime};

/// Number of bins in each clock estimator's window.
pub const BINS: usize = 32;

/// Most SIYI 0x30 frames (unpaired, and paired) remembered for the UTC − FC offset.
pub const MAX_UTC_VIA_FC: usize = 6;

/// One time value received from the flight controller.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Sample {
    /// Local instant at which the frame's last byte arrived.
    pub local: Instant,
    /// The time the frame carries, in microseconds (UTC: since the Unix epoch; FC clock:
    /// `time_boot_ms × 1000`).
    pub value_us: u64,
    /// Truncation step of the value: the true remote time at reading was in
    /// `[value, value + resolution)`. 1 µs for SIYI 0x30, 1000 for `time_boot_ms` and
    /// millisecond fields (K40T), 10 000 for Viewlink's hundredths of a second. For a
    /// held value: the sender's update period (GCU under ArduPilot: 20 000), the most by
    /// which the first sample after an event was read late.
    pub resolution_us: u32,
    /// The sender holds this value between events and repeats it (GCU: the time of the
    /// last GPS fix, sent at 50 Hz, stepping at 5-10 Hz). Such a value is the exact time
    /// of the event, only the first sample after each change carries information, and
    /// a value that stops changing is not fresh.
    pub held: bool,
    /// The part of the delay between the sender's read and `local` that is known: the
    /// serial time of this frame and of the bytes the sender wrote before it in the same
    /// burst ([`serial_time`]). Subtracted from `local`.
    pub transit: Duration,
    /// The sender writes this value at once after the instant it carries, by protocol
    /// (the K40T FC's 0x00030E follows its own RTC_IO edge): a single such sample is
    /// enough for a first mapping.
    pub prompt: bool,
    /// The remote clock read `value_us` at or *after* `local` (here the instant the
    /// bridge started sending a request the remote stamped on arrival: ArduPilot's
    /// TIMESYNC tc1, its UART's estimate of the request's start, never earlier), not
    /// before it: the point lies on or under the offset line, and the least-advanced
    /// samples are the tight ones. An estimator takes one kind (the first sample's).
    pub lower: bool,
}

impl Sample {
    /// A sample of a running clock (not held) with no known transit time.
    #[must_use]
    pub const fn new(local: Instant, value_us: u64, resolution_us: u32) -> Self {
        Self {
            local,
            value_us,
            resolution_us,
            held: false,
            transit: Duration::ZERO,
            prompt: false,
            lower: false,
        }
    }

    /// The same sample, read by the remote at or after `local` ([`Sample::lower`]).
    #[must_use]
    pub const fn lower_bound(mut self) -> Self {
        self.lower = true;
        self
    }

    /// The same sample, marked as sent at once after the instant it carries
    /// ([`Sample::prompt`]).
    #[must_use]
    pub const fn prompt(mut self) -> Self {
        self.prompt = true;
        self
    }

    /// The same sample, marked as a held value ([`Sample::held`]).
    #[must_use]
    pub const fn held(mut self) -> Self {
        self.held = true;
        self
    }

    /// The same sample with a known transit time ([`Sample::transit`]).
    #[must_use]
    pub const fn with_transit(mut self, transit: Duration) -> Self {
        self.transit = transit;
        self
    }
}

/// Time to send `bytes` bytes on an 8N1 serial line at `baud` bits per second (10 bits
/// per byte), rounded to the nearest microsecond. Zero if `baud` is zero.
#[must_use]
pub const fn serial_time(bytes: u32, baud: u32) -> Duration {
    if baud == 0 {
        return Duration::ZERO;
    }
    let bits = (bytes as u64).saturating_mul(10_000_000);
    let half = (baud as u64) / 2;
    match bits.saturating_add(half).checked_div(baud as u64) {
        Some(us) => Duration::from_micros(us),
        None => Duration::ZERO,
    }
}

/// Settings of the [`TimeDiscipline`]. Leap seconds are not here: the caller converts
/// GPS time to UTC ([`UtcTime::from_gps`]). The configuration file sets three
/// (`[discipline] bin_ms`, `min_bins`, `min_span_ms`, for tests and demos).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
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
pub struct DisciplineConfig {
    /// Local time covered by one bin of the estimator (default 8 s; the window is
    /// [`BINS`] bins, 256 s).
    #[cfg_attr(
        feature = "serde",
        serde(
            rename(deserialize = "bin_ms"),
            deserialize_with = "super::config::de::ms"
        )
    )]
    pub bin_len: Duration,
    /// Bins needed before a clock estimate is trusted (default 5).
    #[cfg_attr(feature = "serde", serde(deserialize_with = "super::config::de::int"))]
    pub min_bins: u8,
    /// Local time the trusted bins must span (default 16 s).
    #[cfg_attr(
        feature = "serde",
        serde(
            rename(deserialize = "min_span_ms"),
            deserialize_with = "super::config::de::ms"
        )
    )]
    pub min_span: Duration,
    /// Largest plausible rate difference between the local and the remote clock, in ppm
    /// (default 300: two ±50 ppm crystals with a wide margin). A fit beyond it is not
    /// trusted.
    #[cfg_attr(feature = "serde", serde(skip_deserializing))]
    pub max_drift_ppm: u32,
    /// A converged mapping is `Valid` while its last fresh sample is at most this old
    /// (default 3 s); then `Holdover`.
    #[cfg_attr(feature = "serde", serde(skip_deserializing))]
    pub sample_timeout: Duration,
    /// How long after the last fresh sample the mapping stays usable (default 60 s);
    /// then `Lost`.
    #[cfg_attr(feature = "serde", serde(skip_deserializing))]
    pub holdover: Duration,
    /// Consecutive mutually consistent outliers that make a step (default 5).
    #[cfg_attr(feature = "serde", serde(skip_deserializing))]
    pub step_confirm: u8,
    /// The same for [prompt](Sample::prompt) samples (default 2: the K40T FC sends one
    /// every 10 s, and one is trusted enough to start a mapping).
    #[cfg_attr(feature = "serde", serde(skip_deserializing))]
    pub prompt_step_confirm: u8,
    /// The line's offset is anchored on this many most recent bins (default 4): the
    /// rate comes from the whole window, the offset from the lowest of these bins, so
    /// that a rate error is extrapolated over a few bins only, not over half the
    /// window. 0: Moon's line as it is (offset at the window's mean time).
    #[cfg_attr(feature = "serde", serde(skip_deserializing))]
    pub anchor_bins: u8,
    /// Read a non-held value as the middle of its truncation interval (default true;
    /// see the module documentation).
    #[cfg_attr(feature = "serde", serde(skip_deserializing))]
    pub center_truncation: bool,
    /// Margin when checking a SIYI pair against the unpaired lower bound (default 2 ms).
    #[cfg_attr(feature = "serde", serde(skip_deserializing))]
    pub pair_tolerance: Duration,
    /// Accepted samples after which a first mapping is given, before the fit converges
    /// (default 8: under a second of a 10 Hz source). It assumes equal clock rates and
    /// takes the least-delayed sample; [`DisciplineConfig::quick_drift_ppm`] bounds its
    /// error as it ages. A [prompt](Sample::prompt) sample is enough on its own.
    #[cfg_attr(feature = "serde", serde(skip_deserializing))]
    pub quick_samples: u8,
    /// Rate difference between the local clock and UTC believed possible before the fit
    /// converges, in ppm (default 100: two ±50 ppm crystals).
    #[cfg_attr(feature = "serde", serde(skip_deserializing))]
    pub quick_drift_ppm: u32,
    /// Rate error believed left once the fit has converged, in ppm (default 5).
    #[cfg_attr(feature = "serde", serde(skip_deserializing))]
    pub fit_drift_ppm: u32,
    /// Least uncertainty believed for the delay of the least-delayed sample (default
    /// 1 ms): part of [`TimeDiscipline::error_bound`].
    #[cfg_attr(feature = "serde", serde(skip_deserializing))]
    pub delay_margin: Duration,
    /// Uncertainty of a SIYI UTC − FC-clock offset known only from unpaired 0x30 frames
    /// (default 10 ms: ArduPilot's transport jitter).
    #[cfg_attr(feature = "serde", serde(skip_deserializing))]
    pub unpaired_margin: Duration,
    /// A sample further than this plus its resolution from the current fit contradicts
    /// it (default 15 ms): one below the fit's floor, or three in a row above it, suspend
    /// UTC ([`DisciplineState::Suspect`]) until a consistent sample comes or
    /// [`DisciplineConfig::step_confirm`] of them agree on a jump (the source stepped:
    /// the fit restarts from them). A time stamp off by more than 30 ms is worse than
    /// none; this keeps a jump of the FC's UTC (a reboot with another time) out of them.
    #[cfg_attr(feature = "serde", serde(skip_deserializing))]
    pub jump_tolerance: Duration,
    /// UTC values before this are rejected (default 2020-01-01T00:00:00Z): an FC without
    /// time sends zeros or year 2000.
    #[cfg_attr(feature = "serde", serde(skip_deserializing))]
    pub min_utc: UtcTime,
}

impl DisciplineConfig {
    /// The documented defaults.
    pub const DEFAULT: Self = Self {
        bin_len: Duration::from_secs(8),
        min_bins: 5,
        min_span: Duration::from_secs(16),
        max_drift_ppm: 300,
        sample_timeout: Duration::from_secs(3),
        holdover: Duration::from_secs(60),
        step_confirm: 5,
        prompt_step_confirm: 2,
        anchor_bins: 4,
        center_truncation: true,
        pair_tolerance: Duration::from_millis(2),
        quick_samples: 8,
        quick_drift_ppm: 100,
        fit_drift_ppm: 5,
        delay_margin: Duration::from_millis(1),
        unpaired_margin: Duration::from_millis(10),
        jump_tolerance: Duration::from_millis(15),
        min_utc: UtcTime::from_unix_micros(1_577_836_800_000_000),
    };
}

impl Default for DisciplineConfig {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Where the UTC mapping stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum DisciplineState {
    /// No time sample yet.
    Unknown,
    /// Samples arrive but the mapping has not converged (or re-converges after a step).
    Converging,
    /// Fed, and either converged or giving a first mapping (see
    /// [`DisciplineConfig::quick_samples`]): `utc()` is trustworthy within
    /// [`TimeDiscipline::error_bound`].
    Valid,
    /// The last samples contradict the mapping (the source may have jumped): no UTC
    /// until a consistent sample comes, or the jump is confirmed and the mapping
    /// restarts from the new samples.
    Suspect,
    /// Samples stopped (or the FC clock restarted); the last mapping is extrapolated, for
    /// at most [`DisciplineConfig::holdover`].
    Holdover,
    /// The holdover expired; no UTC until the mapping converges again.
    Lost,
}

impl DisciplineState {
    /// `utc()` gives a value in this state (`Valid` or `Holdover`).
    #[must_use]
    pub const fn is_usable(self) -> bool {
        matches!(self, Self::Valid | Self::Holdover)
    }
}

/// A change of [`DisciplineState`], reported once by [`TimeDiscipline::poll`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Transition {
    /// State before.
    pub from: DisciplineState,
    /// State now.
    pub to: DisciplineState,
    /// The mapping was replaced by one that disagrees with it (the FC's UTC jumped, e.g.
    /// after an FC reboot), though UTC may have stayed usable across: the old one was
    /// lost and the new one is valid.
    pub replaced: bool,
}

impl Transition {
    /// UTC became usable, or was replaced (the engine's `UtcValid` event).
    #[must_use]
    pub const fn utc_became_valid(self) -> bool {
        self.to.is_usable() && (!self.from.is_usable() || self.replaced)
    }

    /// UTC stopped being usable, or was replaced (the engine's `UtcLost` event).
    #[must_use]
    pub const fn utc_lost(self) -> bool {
        self.from.is_usable() && (!self.to.is_usable() || self.replaced)
    }
}

/// What the discipline did with one sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Verdict {
    /// Used (it may or may not have improved the estimate).
    Accepted,
    /// A held value repeated: nothing new.
    Repeated,
    /// Too far from the current estimate: ignored (a step candidate).
    Outlier,
    /// This sample confirmed a step; the clock's estimator restarted.
    Step,
    /// Not usable at all (arithmetic range, UTC before [`DisciplineConfig::min_utc`],
    /// a pair inconsistent with the unpaired bound, no FC clock yet for an unpaired 0x30).
    Rejected,
}

/// A straight line `offset(x) = y0 + dy·(x − x0)/dx` (µs), `dx > 0`: the offset
/// `local − remote` as a function of local time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Line {
    x0: i64,
    y0: i64,
    dy: i64,
    dx: i64,
}

impl Line {
    const fn flat(x0: i64, y0: i64) -> Self {
        Self {
            x0,
            y0,
            dy: 0,
            dx: 1,
        }
    }

    /// The offset at local `x`.
    fn offset_at(&self, x: i64) -> Option<i64> {
        let num =
            i128::from(self.dy).checked_mul(i128::from(x).checked_sub(i128::from(self.x0))?)?;
        let q = num.checked_div_euclid(i128::from(self.dx))?;
        i64::try_from(i128::from(self.y0).checked_add(q)?).ok()
    }

    /// The remote time at local `x`.
    fn remote_at(&self, x: i64) -> Option<i64> {
        x.checked_sub(self.offset_at(x)?)
    }

    /// The local `x` at which the remote time is `r` (inverse of `remote_at`):
    /// `x = x0 + (r − x0 + y0)·dx/(dx − dy)`.
    fn local_at(&self, r: i64) -> Option<i64> {
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
    fn shifted(&self, c: i64) -> Option<Self> {
        Some(Self {
            y0: self.y0.checked_sub(c)?,
            ..*self
        })
    }

    /// |slope| ≤ `ppm` parts per million.
    fn rate_within(&self, ppm: u32) -> bool {
        let lhs = i128::from(self.dy).unsigned_abs().saturating_mul(1_000_000);
        let rhs = i128::from(self.dx)
            .unsigned_abs()
            .saturating_mul(u128::from(ppm));
        lhs <= rhs
    }
}

/// The path that produced the UTC mapping.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Path {
    /// Direct UTC samples.
    Direct,
    /// FC clock plus `C`.
    ViaFc,
}

/// A bin minimum: local time and offset of the least-delayed sample of the bin.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct Point {
    x: i64,
    y: i64,
}

/// A pending step: consecutive outliers agreeing with each other.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct StepCandidate {
    point: Point,
    count: u8,
}

/// Minimum-delay, lower-hull clock estimator over a fixed window of bins.
#[derive(Debug, Clone, PartialEq, Eq)]
struct ClockEstimator {
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
    last_held: Option<u64>,
    /// Samples accepted since the estimator (re)started.
    accepted: u16,
    /// A [prompt](Sample::prompt) sample was accepted.
    prompt: bool,
    /// The last samples contradict the fit (see [`DisciplineConfig::jump_tolerance`]).
    suspect: bool,
    /// Largest truncation step of the accepted samples, µs.
    resolution: u32,
    /// The samples are lower bounds ([`Sample::lower`]): points are kept negated (so that
    /// the least-advanced are the minima) and the line is negated back when given.
    negated: bool,
}

/// A mapping an estimator can give, and what is believed of its error.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Fit {
    line: Line,
    /// From a converged fit (else a first mapping that assumes equal rates).
    converged: bool,
    /// Error believed at the line's anchor `x0`, µs: half the truncation step plus the
    /// delay uncertainty of the least-delayed sample.
    base_us: u64,
}

/// Result of feeding a point to a [`ClockEstimator`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Fed {
    Accepted,
    Outlier,
    Step,
}

impl ClockEstimator {
    const fn new() -> Self {
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
        }
    }

    fn reset(&mut self) {
        let negated = self.negated;
        *self = Self::new();
        self.negated = negated;
    }

    fn is_empty(&self) -> bool {
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
        if self.len < cfg.min_bins.max(2) || !line.rate_within(cfg.max_drift_ppm) {
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
    fn usable(&self, cfg: &DisciplineConfig) -> Option<Fit> {
        if self.suspect {
            return None;
        }
        let converged = self.converged(cfg);
        let line = if converged {
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
    fn feed(&mut self, p: Point, resolution_us: u32, prompt: bool, cfg: &DisciplineConfig) -> Fed {
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
        } else if let Some(last) = self.bin_mut(self.len.saturating_sub(1))
            && p.y < last.y
        {
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

    // The names are those of the fit's formulas (x, y, n, a, b).
    #[allow(clippy::many_single_char_names)]
    fn fit(&self) -> Option<Line> {
        let n = self.len;
        if n == 0 {
            return None;
        }
        let first = self.bin(0)?;
        if n == 1 {
            return Some(Line::flat(first.x, first.y));
        }
        // Lower convex hull (Andrew's monotone chain; bins are in increasing x).
        let mut hull = [0u8; BINS];
        let mut h: usize = 0;
        let mut sum_x: i128 = 0;
        for i in 0..n {
            let p = self.bin(i)?;
            sum_x = sum_x.checked_add(i128::from(p.x))?;
            while h >= 2 {
                let a = self.bin(*hull.get(h.checked_sub(2)?)?)?;
                let b = self.bin(*hull.get(h.checked_sub(1)?)?)?;
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
            let p = self.bin(*hull.first()?)?;
            return Some(Line::flat(p.x, p.y));
        }
        let mean_x = i64::try_from(sum_x.checked_div(i128::from(n))?).ok()?;
        // The hull edge whose span contains the mean (first or last edge outside).
        let mut k = 0usize;
        while k.checked_add(2)? < h {
            let right = self.bin(*hull.get(k.checked_add(1)?)?)?;
            if right.x >= mean_x {
                break;
            }
            k = k.checked_add(1)?;
        }
        let a = self.bin(*hull.get(k)?)?;
        let b = self.bin(*hull.get(k.checked_add(1)?)?)?;
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
}

/// Cross product `(a − o) × (b − o)`: positive when o → a → b turns left.
fn cross(o: Point, a: Point, b: Point) -> Option<i128> {
    let ax = i128::from(a.x).checked_sub(i128::from(o.x))?;
    let ay = i128::from(a.y).checked_sub(i128::from(o.y))?;
    let bx = i128::from(b.x).checked_sub(i128::from(o.x))?;
    let by = i128::from(b.y).checked_sub(i128::from(o.y))?;
    ax.checked_mul(by)?.checked_sub(ay.checked_mul(bx)?)
}

/// What is known of `C` = UTC − FC clock (SIYI).
#[derive(Debug, Clone, PartialEq, Eq)]
struct FcLink {
    /// Unpaired 0x30: (local x, UTC µs).
    unpaired: [Point; MAX_UTC_VIA_FC],
    unpaired_len: u8,
    /// Pairs: `utc − fc_ms·1000`.
    pairs: [i64; MAX_UTC_VIA_FC],
    pairs_len: u8,
    /// `C` from MAVLink SYSTEM_TIME (when it feeds the link: then the only source).
    shift: Shift,
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
struct Shift {
    /// (bin index, least `d`) per bin, newest last.
    bins: [Option<(i64, i64)>; SHIFT_BINS],
    /// Consecutive samples above the band, and the least of them.
    above: u8,
    above_min: i64,
    suspect: bool,
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
    fn push(&mut self, x: i64, d: i64, tolerance: i64) -> Fed {
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

impl FcLink {
    const fn new() -> Self {
        Self {
            unpaired: [Point { x: 0, y: 0 }; MAX_UTC_VIA_FC],
            unpaired_len: 0,
            pairs: [0; MAX_UTC_VIA_FC],
            pairs_len: 0,
            shift: Shift::new(),
        }
    }

    fn push_unpaired(&mut self, p: Point) {
        let idx = usize::from(self.unpaired_len) % MAX_UTC_VIA_FC;
        if let Some(slot) = self.unpaired.get_mut(idx) {
            *slot = p;
        }
        self.unpaired_len = self.unpaired_len.saturating_add(1);
    }

    fn push_pair(&mut self, m: i64) {
        let idx = usize::from(self.pairs_len) % MAX_UTC_VIA_FC;
        if let Some(slot) = self.pairs.get_mut(idx) {
            *slot = m;
        }
        self.pairs_len = self.pairs_len.saturating_add(1);
    }

    fn unpaired(&self) -> &[Point] {
        let n = usize::from(self.unpaired_len).min(MAX_UTC_VIA_FC);
        self.unpaired.get(..n).unwrap_or(&[])
    }

    fn pairs(&self) -> &[i64] {
        let n = usize::from(self.pairs_len).min(MAX_UTC_VIA_FC);
        self.pairs.get(..n).unwrap_or(&[])
    }

    /// The lower bound of `C` from unpaired 0x30 frames and the FC clock fit.
    fn lower_bound(&self, fc: &Line) -> Option<i64> {
        self.unpaired()
            .iter()
            .filter_map(|p| p.y.checked_sub(fc.remote_at(p.x)?))
            .max()
    }

    /// `C`: the SYSTEM_TIME shift when there is one; else the least pair consistent
    /// with the unpaired bound (`true`), else the bound (`false`).
    fn offset(&self, fc: Option<&Line>, tolerance: i64) -> Option<(i64, bool)> {
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

/// The local clock ↔ UTC mapping: see the [module documentation](self).
///
/// Fixed size, no allocation (`size_of::<TimeDiscipline>()`: about 1.5 KB on a 64-bit
/// host).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TimeDiscipline {
    config: DisciplineConfig,
    /// The one clock estimator: direct UTC samples, or the FC clock (SIYI
    /// `time_boot_ms`), whichever path the flight controller uses ([`Self::path`]).
    clock: ClockEstimator,
    /// The path of the samples in `clock` (set by the first sample; an FC protocol has
    /// one path, and one estimator keeps the engine small).
    path: Option<Path>,
    link: FcLink,
    /// The current local → UTC offset line, with what is believed of its error.
    output: Option<Fit>,
    /// Which path produced `output`.
    source: Option<Path>,
    /// Local time of the last fresh sample that updated `output`.
    last_fresh: Option<Instant>,
    /// The output was replaced by one that disagrees with it, since the last report.
    replaced: bool,
    /// State as of the last evaluation.
    state: DisciplineState,
    /// State as last reported by `poll`.
    reported: DisciplineState,
    /// Latest local instant seen (sample or poll).
    now: Instant,
}

impl Default for TimeDiscipline {
    fn default() -> Self {
        Self::new(DisciplineConfig::DEFAULT)
    }
}

impl TimeDiscipline {
    /// An empty discipline ([`DisciplineState::Unknown`]).
    #[must_use]
    pub const fn new(config: DisciplineConfig) -> Self {
        Self {
            config,
            clock: ClockEstimator::new(),
            path: None,
            link: FcLink::new(),
            output: None,
            source: None,
            last_fresh: None,
            replaced: false,
            state: DisciplineState::Unknown,
            reported: DisciplineState::Unknown,
            now: Instant::ZERO,
        }
    }

    /// The settings.
    #[must_use]
    pub const fn config(&self) -> &DisciplineConfig {
        &self.config
    }

    /// The state as of the last sample or [`poll`](Self::poll).
    #[must_use]
    pub const fn state(&self) -> DisciplineState {
        self.state
    }

    /// The mapping comes from a converged fit (else it is a first mapping, or there is
    /// none).
    #[must_use]
    pub fn is_converged(&self) -> bool {
        self.output.is_some_and(|o| o.converged)
    }

    /// A direct UTC sample (Viewlink M_AHRS, GCU GPS time converted to UTC, K40T FC
    /// 0x00030E): `value_us` is Unix microseconds.
    pub fn utc_sample(&mut self, s: Sample) -> Verdict {
        let verdict = self.utc_sample_inner(s);
        self.advance(s.local);
        verdict
    }

    fn utc_sample_inner(&mut self, s: Sample) -> Verdict {
        if s.lower
            || s.value_us < self.config.min_utc.as_unix_micros()
            || !self.take_path(Path::Direct)
        {
            return Verdict::Rejected;
        }
        if s.held {
            if self.clock.last_held == Some(s.value_us) {
                return Verdict::Repeated;
            }
            self.clock.last_held = Some(s.value_us);
        }
        let center = if self.config.center_truncation {
            s.resolution_us / 2
        } else {
            0
        };
        let Some(p) = point(s, center) else {
            return Verdict::Rejected;
        };
        match self.clock.feed(p, s.resolution_us, s.prompt, &self.config) {
            Fed::Outlier => Verdict::Outlier,
            Fed::Step => {
                // UTC itself jumped: the old mapping cannot be trusted any more; the new
                // one starts from the samples that agreed on the jump.
                self.output = None;
                self.source = None;
                self.last_fresh = None;
                self.use_direct(s.local);
                Verdict::Step
            }
            Fed::Accepted => {
                self.use_direct(s.local);
                Verdict::Accepted
            }
        }
    }

    /// Takes the direct estimator's mapping, when it gives one.
    fn use_direct(&mut self, local: Instant) {
        if let Some(fit) = self.clock.usable(&self.config) {
            self.output = Some(fit);
            self.source = Some(Path::Direct);
            self.last_fresh = Some(local);
        }
    }

    /// An FC clock sample (SIYI 0x22/0x3E `time_boot_ms`: `value_us` = ms × 1000,
    /// resolution 1000).
    pub fn fc_clock_sample(&mut self, s: Sample) -> Verdict {
        let verdict = self.fc_clock_sample_inner(s);
        self.advance(s.local);
        verdict
    }

    fn fc_clock_sample_inner(&mut self, s: Sample) -> Verdict {
        if !self.take_path(Path::ViaFc) {
            return Verdict::Rejected;
        }
        // The first sample sets the kind of the estimator's points.
        if self.clock.is_empty() && self.clock.accepted == 0 {
            self.clock.negated = s.lower;
        }
        if s.lower != self.clock.negated {
            return Verdict::Rejected;
        }
        if s.held {
            if self.clock.last_held == Some(s.value_us) {
                return Verdict::Repeated;
            }
            self.clock.last_held = Some(s.value_us);
        }
        // Floor convention (no centring): see the module documentation.
        let Some(p) = point(s, 0) else {
            return Verdict::Rejected;
        };
        match self.clock.feed(p, 0, s.prompt, &self.config) {
            Fed::Outlier => Verdict::Outlier,
            Fed::Step => {
                // FC reboot: its clock and C are gone; the UTC mapping stays in holdover
                // until the new clock and C are known (and replace it if they disagree).
                self.link = FcLink::new();
                Verdict::Step
            }
            Fed::Accepted => {
                self.refresh_via_fc(s.local);
                Verdict::Accepted
            }
        }
    }

    /// A SIYI 0x30 (UTC, Unix µs, resolution 1) not paired with an FC clock value:
    /// gives the lower bound `C ≥ utc − fc(arrival)`.
    pub fn utc_via_fc_sample(&mut self, s: Sample) -> Verdict {
        let verdict = if s.value_us < self.config.min_utc.as_unix_micros() {
            Verdict::Rejected
        } else {
            let x = local_x(s);
            match (x, i64::try_from(s.value_us).ok()) {
                (Some(x), Some(y)) => {
                    self.link.push_unpaired(Point { x, y });
                    self.refresh_via_fc(s.local);
                    Verdict::Accepted
                }
                _ => Verdict::Rejected,
            }
        };
        self.advance(s.local);
        verdict
    }

    /// A SIYI 0x30 UTC value and a 0x22/0x3E `time_boot_ms` written in the same FC
    /// update (the same burst on the wire): `C ∈ (utc − fc_ms·1000 − 1000, utc −
    /// fc_ms·1000]`. Rejected if it contradicts the unpaired lower bound (pairs are
    /// checked again each time `C` is computed). Feed the same 0x30 to
    /// [`utc_via_fc_sample`](Self::utc_via_fc_sample) too: it gives the bound.
    pub fn utc_fc_pair(&mut self, utc_us: u64, fc_ms: u32) -> Verdict {
        if utc_us < self.config.min_utc.as_unix_micros() {
            return Verdict::Rejected;
        }
        let Some(m) = i64::try_from(utc_us)
            .ok()
            .and_then(|u| u.checked_sub(i64::from(fc_ms).checked_mul(1000)?))
        else {
            return Verdict::Rejected;
        };
        let tol = i64::try_from(self.config.pair_tolerance.as_micros()).unwrap_or(i64::MAX);
        if let Some(bound) = self.fc_line().and_then(|l| self.link.lower_bound(&l))
            && m < bound.saturating_sub(tol)
        {
            return Verdict::Rejected;
        }
        self.link.push_pair(m);
        let now = self.now;
        self.refresh_via_fc(now);
        Verdict::Accepted
    }

    /// A MAVLink SYSTEM_TIME received at `local`: `utc_us` (`time_unix_usec`) and
    /// `fc_ms` (`time_boot_ms`) read from one clock in one call, so `C` is the least
    /// `utc − fc_ms·1000` (see `Shift`); the FC clock comes from
    /// [`fc_clock_sample`](Self::fc_clock_sample) (TIMESYNC). `utc_us` 0 or before
    /// [`DisciplineConfig::min_utc`] is rejected; a step of the FC's UTC makes UTC
    /// suspect, then restarts `C` (reported as a replaced mapping when it disagrees).
    pub fn system_time(&mut self, local: Instant, utc_us: u64, fc_ms: u32) -> Verdict {
        self.advance(local);
        if utc_us < self.config.min_utc.as_unix_micros() || !self.take_path(Path::ViaFc) {
            return Verdict::Rejected;
        }
        let Some(d) = i64::try_from(utc_us)
            .ok()
            .and_then(|u| u.checked_sub(i64::from(fc_ms).checked_mul(1000)?))
        else {
            return Verdict::Rejected;
        };
        let Ok(x) = i64::try_from(local.as_micros()) else {
            return Verdict::Rejected;
        };
        let tol = i64::try_from(self.config.pair_tolerance.as_micros()).unwrap_or(i64::MAX);
        let verdict = match self.link.shift.push(x, d, tol) {
            Fed::Outlier => Verdict::Outlier,
            Fed::Step => Verdict::Step,
            Fed::Accepted => Verdict::Accepted,
        };
        if verdict != Verdict::Outlier {
            self.refresh_via_fc(local);
        }
        self.advance(local);
        verdict
    }

    /// The source of time changes (the engine takes UTC from another link): the clock
    /// estimator and `C` start again, for whichever path the new source takes; the
    /// current mapping stays usable in holdover until the new one replaces it (reported
    /// as replaced when they disagree).
    pub fn switch_source(&mut self) {
        self.clock.reset();
        self.path = None;
        self.link = FcLink::new();
        // No path is fresh now: the next mapping, from either path, takes over.
        self.source = None;
    }

    /// Updates the output from the FC path when it gives one. A new mapping that
    /// disagrees with the current one by more than the jump tolerance replaces it (the
    /// FC's UTC jumped, e.g. after a reboot) and is reported as such.
    fn refresh_via_fc(&mut self, local: Instant) {
        if self.direct_valid() {
            return;
        }
        let Some(fc) = self.clock.usable(&self.config) else {
            return;
        };
        let tol = i64::try_from(self.config.pair_tolerance.as_micros()).unwrap_or(i64::MAX);
        let Some((c, paired)) = self.link.offset(Some(&fc.line), tol) else {
            return;
        };
        let Some(line) = fc.line.shifted(c) else {
            return;
        };
        // C from a pair is known to the FC clock's millisecond; from the unpaired bound
        // only to the 0x30 frames' transport delay.
        let c_margin = if paired {
            1_000
        } else {
            self.config.unpaired_margin.as_micros()
        };
        let new = Fit {
            line,
            converged: fc.converged,
            base_us: fc.base_us.saturating_add(c_margin),
        };
        if let Some(old) = self.output
            && self.state.is_usable()
        {
            let x = i64::try_from(local.as_micros()).unwrap_or(i64::MAX);
            let jump = i64::try_from(self.config.jump_tolerance.as_micros()).unwrap_or(i64::MAX);
            let disagree = match (old.line.offset_at(x), line.offset_at(x)) {
                (Some(a), Some(b)) => b.checked_sub(a).is_none_or(|d| d.saturating_abs() > jump),
                _ => true,
            };
            if disagree {
                self.replaced = true;
            }
        }
        self.output = Some(new);
        self.source = Some(Path::ViaFc);
        self.last_fresh = Some(local);
    }

    /// Uses `path` for the estimator: true when it is the estimator's path (or the
    /// estimator is free and takes it).
    fn take_path(&mut self, path: Path) -> bool {
        *self.path.get_or_insert(path) == path
    }

    /// The FC clock's line, when the estimator holds the FC clock and gives a mapping.
    fn fc_line(&self) -> Option<Line> {
        self.clock
            .usable(&self.config)
            .map(|f| f.line)
            .filter(|_| self.path == Some(Path::ViaFc))
    }

    /// The output comes from the direct path, which is fresh.
    fn direct_valid(&self) -> bool {
        self.source == Some(Path::Direct)
            && self.last_fresh.is_some_and(|t| {
                self.now.saturating_duration_since(t) <= self.config.sample_timeout
            })
    }

    /// Re-evaluates the state at `now` (time-outs) and reports a change since the last
    /// report, once. Call it at least at [`poll_at`](Self::poll_at).
    pub fn poll(&mut self, now: Instant) -> Option<Transition> {
        self.advance(now);
        if self.state == self.reported && !self.replaced {
            return None;
        }
        let t = Transition {
            from: self.reported,
            to: self.state,
            replaced: core::mem::take(&mut self.replaced),
        };
        self.reported = self.state;
        Some(t)
    }

    /// The next instant at which the state changes by itself (Valid → Holdover →
    /// Lost), if any.
    #[must_use]
    pub fn poll_at(&self) -> Option<Instant> {
        let fresh = self.last_fresh?;
        match self.state {
            DisciplineState::Valid => Some(fresh.saturating_add(self.config.sample_timeout)),
            DisciplineState::Holdover => Some(fresh.saturating_add(self.config.holdover)),
            _ => None,
        }
    }

    fn advance(&mut self, now: Instant) {
        if now > self.now {
            self.now = now;
        }
        let now = self.now;
        let mut expired = false;
        let state = match (self.output, self.last_fresh) {
            (Some(_), Some(fresh)) => {
                let age = now.saturating_duration_since(fresh);
                if (self.source == Some(Path::Direct) && self.clock.suspect)
                    || (self.source == Some(Path::ViaFc) && self.link.shift.suspect)
                {
                    Some(DisciplineState::Suspect)
                } else if age <= self.config.sample_timeout {
                    Some(DisciplineState::Valid)
                } else if age <= self.config.holdover {
                    Some(DisciplineState::Holdover)
                } else {
                    expired = true;
                    None
                }
            }
            _ => None,
        };
        if expired {
            // Holdover expired: forget everything, start again.
            self.clock.reset();
            self.path = None;
            self.link = FcLink::new();
            self.output = None;
            self.source = None;
            self.last_fresh = None;
        }
        let state = state.unwrap_or_else(|| {
            if !self.clock.is_empty() {
                DisciplineState::Converging
            } else if expired || self.state != DisciplineState::Unknown {
                DisciplineState::Lost
            } else {
                DisciplineState::Unknown
            }
        });
        self.state = state;
    }

    /// The furthest local instant the mapping may be used at.
    fn horizon(&self) -> Option<i64> {
        let fresh = self.last_fresh?;
        i64::try_from(fresh.saturating_add(self.config.holdover).as_micros()).ok()
    }

    /// UTC at local instant `local`, or `None` unless the state is usable and `local`
    /// is within the holdover horizon of the last fresh sample.
    pub fn utc(&self, local: Instant) -> Option<UtcTime> {
        if !self.state.is_usable() {
            return None;
        }
        let x = i64::try_from(local.as_micros()).ok()?;
        if x > self.horizon()? {
            return None;
        }
        let r = self.output?.line.remote_at(x)?;
        u64::try_from(r).ok().map(UtcTime::from_unix_micros)
    }

    /// The local instant at which UTC is `utc` (the inverse of [`utc`](Self::utc)),
    /// with the same validity conditions.
    pub fn local_of(&self, utc: UtcTime) -> Option<Instant> {
        if !self.state.is_usable() {
            return None;
        }
        let r = i64::try_from(utc.as_unix_micros()).ok()?;
        let x = self.output?.line.local_at(r)?;
        if x > self.horizon()? {
            return None;
        }
        u64::try_from(x).ok().map(Instant::from_micros)
    }

    /// The error this discipline believes [`utc`](Self::utc) has at `local`: half the
    /// sources' truncation step, plus the delay uncertainty of the least-delayed sample
    /// (how consistent the least delays are, at least
    /// [`DisciplineConfig::delay_margin`]), plus (SIYI) that of the UTC − FC-clock
    /// offset, plus the rate uncertainty ([`DisciplineConfig::fit_drift_ppm`] once
    /// converged, [`DisciplineConfig::quick_drift_ppm`] before) times the time from the
    /// mapping's anchor. `None` when there is no usable UTC at `local`.
    #[must_use]
    pub fn error_bound(&self, local: Instant) -> Option<Duration> {
        self.utc(local)?;
        let fit = self.output?;
        let x = i64::try_from(local.as_micros()).ok()?;
        let age = x.checked_sub(fit.line.x0)?.unsigned_abs();
        let ppm = if fit.converged {
            self.config.fit_drift_ppm
        } else {
            self.config.quick_drift_ppm
        };
        let drift = age.saturating_mul(u64::from(ppm)) / 1_000_000;
        Some(Duration::from_micros(fit.base_us.saturating_add(drift)))
    }

    /// The current estimate of the local clock's rate error against UTC, in parts per
    /// billion (positive: the local clock runs fast), if a mapping exists.
    #[must_use]
    pub fn drift_ppb(&self) -> Option<i64> {
        let l = self.output?.line;
        let v = i128::from(l.dy)
            .checked_mul(1_000_000_000)?
            .checked_div(i128::from(l.dx))?;
        i64::try_from(v).ok()
    }
}

/// Local time of a sample with its known transit removed, as `i64`.
fn local_x(s: Sample) -> Option<i64> {
    i64::try_from(s.local.as_micros().checked_sub(s.transit.as_micros())?).ok()
}

/// The estimator point of a sample: `(x, x − (value + center))`.
fn point(s: Sample, center: u32) -> Option<Point> {
    let x = local_x(s)?;
    let r = i64::try_from(s.value_us)
        .ok()?
        .checked_add(i64::from(center))?;
    Some(Point {
        x,
        y: x.checked_sub(r)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 2026-01-01T00:00:00Z in µs.
    const U0: u64 = 1_767_225_600_000_000;

    /// Local clock 20 ppm fast, starting at 5 s: local = 5e6 + t·(1 + 20e-6).
    fn local(t_us: u64) -> Instant {
        Instant::from_micros(5_000_000 + t_us + t_us / 50_000)
    }

    /// Exact UTC samples every 100 ms from `from` to `to` (µs of true time).
    fn feed_exact(d: &mut TimeDiscipline, from: u64, to: u64) {
        let mut t = from;
        while t < to {
            let v = d.utc_sample(Sample::new(local(t), U0 + t, 1));
            assert_eq!(v, Verdict::Accepted, "at {t}");
            t += 100_000;
        }
    }

    fn err_us(d: &TimeDiscipline, t: u64) -> i64 {
        let utc = d.utc(local(t)).expect("usable");
        utc.signed_micros_since(UtcTime::from_unix_micros(U0 + t))
            .unwrap()
    }

    #[test]
    fn a_first_mapping_at_once_then_the_fit_with_the_rate() {
        let mut d = TimeDiscipline::default();
        assert_eq!(d.state(), DisciplineState::Unknown);
        assert_eq!(d.utc(local(0)), None);
        // Seven samples: not yet.
        feed_exact(&mut d, 0, 700_000);
        assert_eq!(d.state(), DisciplineState::Converging);
        assert_eq!(d.utc(local(700_000)), None);
        assert_eq!(d.error_bound(local(700_000)), None);
        let t = d.poll(local(700_000)).unwrap();
        assert_eq!(t.to, DisciplineState::Converging);
        assert!(!t.utc_became_valid());
        // The eighth: a first mapping (equal rates assumed), valid at once.
        feed_exact(&mut d, 700_000, 800_000);
        assert_eq!(d.state(), DisciplineState::Valid);
        assert!(!d.is_converged());
        assert!(d.poll(local(800_000)).unwrap().utc_became_valid());
        assert!(err_us(&d, 700_000).abs() <= 20);
        // 10 s later (the first grid edge at the latest): the local clock's 20 ppm have
        // added 200 µs, within the bound believed (1 ms + 100 ppm over 10 s).
        let e = err_us(&d, 10_700_000);
        assert!((150..=250).contains(&e.abs()), "{e}");
        let bound = d.error_bound(local(10_700_000)).unwrap().as_micros();
        assert!((1_900..=2_100).contains(&bound), "{bound}");
        assert!(e.unsigned_abs() < bound);
        // Samples go on: still the first mapping at 20 s (fewer than 5 bins of 8 s),
        // anchored on the least-delayed recent sample.
        feed_exact(&mut d, 800_000, 20_000_000);
        assert!(!d.is_converged());
        assert!(err_us(&d, 20_000_000).abs() <= 700);
        feed_exact(&mut d, 20_000_000, 60_000_000);
        assert_eq!(d.state(), DisciplineState::Valid);
        assert!(d.is_converged());
        assert_eq!(d.poll(local(60_000_000)), None, "valid all along");
        // Converged: the bound is the delay margin plus 5 ppm from the anchor.
        let bound = d.error_bound(local(60_000_000)).unwrap().as_micros();
        assert!((1_000..=1_200).contains(&bound), "{bound}");
        // Exact samples: the mapping is exact to a few µs, also 2 s ahead.
        assert!(err_us(&d, 59_900_000).abs() <= 2);
        assert!(err_us(&d, 62_000_000).abs() <= 2);
        // Local runs 20 ppm fast.
        let ppb = d.drift_ppb().unwrap();
        assert!((19_900..=20_100).contains(&ppb), "{ppb}");
        // The inverse.
        let want = UtcTime::from_unix_micros(U0 + 61_000_000);
        let at = d.local_of(want).unwrap();
        assert!(at.as_micros().abs_diff(local(61_000_000).as_micros()) <= 2);
    }

    #[test]
    fn minimum_delay_wins_and_truncation_is_centred() {
        let mut d = TimeDiscipline::default();
        // Viewlink-like: 10 ms truncation, read phase 3 ms after the boundary, delays
        // cycling 0..9 ms, plus 57 bytes of known transit.
        let transit = serial_time(57, 115_200);
        assert_eq!(transit.as_micros(), 4_948);
        for i in 0..600u64 {
            let t = 3_000 + i * 100_000;
            let v = (U0 + t) / 10_000 * 10_000;
            let arrival = t + (i % 10) * 1_000 + transit.as_micros();
            let s = Sample::new(local(arrival), v, 10_000).with_transit(transit);
            assert_eq!(d.utc_sample(s), Verdict::Accepted);
        }
        assert_eq!(d.state(), DisciplineState::Valid);
        // Read 3 ms after the boundary, centred at 5 ms: 2 ms ahead, the delays gone.
        let e = err_us(&d, 60_000_000);
        assert!((1_990..=2_010).contains(&e), "{e}");
    }

    #[test]
    fn holdover_then_lost() {
        let mut d = TimeDiscipline::default();
        feed_exact(&mut d, 0, 60_000_000);
        d.poll(local(60_000_000));
        let last = local(59_900_000);
        assert_eq!(
            d.poll_at(),
            Some(last.saturating_add(Duration::from_secs(3)))
        );
        assert_eq!(d.poll(local(62_000_000)), None);
        let t = d.poll(local(63_000_000)).unwrap();
        assert_eq!(t.to, DisciplineState::Holdover);
        assert!(!t.utc_lost());
        // Extrapolated with the rate: still exact.
        assert!(err_us(&d, 100_000_000).abs() <= 3);
        assert_eq!(
            d.poll_at(),
            Some(last.saturating_add(Duration::from_secs(60)))
        );
        // Beyond the horizon, even in holdover: no UTC.
        assert_eq!(d.utc(local(121_000_000)), None);
        let t = d.poll(local(120_000_000)).unwrap();
        assert_eq!(t.to, DisciplineState::Lost);
        assert!(t.utc_lost());
        assert_eq!(d.utc(local(120_000_000)), None);
        assert_eq!(
            d.local_of(UtcTime::from_unix_micros(U0 + 120_000_000)),
            None
        );
        // Samples again: converging, then a first mapping within a second.
        feed_exact(&mut d, 130_000_000, 130_700_000);
        assert_eq!(d.state(), DisciplineState::Converging);
        feed_exact(&mut d, 130_700_000, 131_000_000);
        assert_eq!(d.state(), DisciplineState::Valid);
        assert!(!d.is_converged());
        feed_exact(&mut d, 131_000_000, 180_000_000);
        assert!(d.is_converged());
    }

    #[test]
    fn outliers_ignored_steps_restart() {
        let mut d = TimeDiscipline::default();
        feed_exact(&mut d, 0, 60_000_000);
        assert!(d.poll(local(60_000_000)).unwrap().utc_became_valid());
        // One frame 10 s behind: ignored.
        let s = Sample::new(local(60_000_000), U0 + 50_000_000, 1);
        assert_eq!(d.utc_sample(s), Verdict::Outlier);
        assert!(err_us(&d, 60_000_000).abs() <= 2);
        // UTC jumps by 10 s for good: 4 outliers, the 5th is a step.
        for i in 1..=5u64 {
            let t = 60_000_000 + i * 100_000;
            let v = d.utc_sample(Sample::new(local(t), U0 + t + 10_000_000, 1));
            let want = if i < 5 {
                Verdict::Outlier
            } else {
                Verdict::Step
            };
            assert_eq!(v, want);
        }
        assert_eq!(d.state(), DisciplineState::Converging);
        assert_eq!(d.utc(local(60_600_000)), None);
        assert!(d.poll(local(60_600_000)).unwrap().utc_lost());
    }

    #[test]
    fn rejects_and_repeats() {
        let mut d = TimeDiscipline::default();
        // Year 2000 (an FC without time).
        let s = Sample::new(local(0), 946_684_800_000_000, 10_000);
        assert_eq!(d.utc_sample(s), Verdict::Rejected);
        assert_eq!(d.state(), DisciplineState::Unknown);
        // Held values: only changes count.
        let s = Sample::new(local(0), U0, 20_000).held();
        assert_eq!(d.utc_sample(s), Verdict::Accepted);
        let s = Sample::new(local(20_000), U0, 20_000).held();
        assert_eq!(d.utc_sample(s), Verdict::Repeated);
        let s = Sample::new(local(100_000), U0 + 100_000, 20_000).held();
        assert_eq!(d.utc_sample(s), Verdict::Accepted);
    }

    #[test]
    fn held_value_that_stops_changing_is_not_fresh() {
        let mut d = TimeDiscipline::default();
        // GCU-like: 50 Hz, fix every 100 ms, read 4 ms after the fix.
        let mut t = 0u64;
        while t < 60_000_000 {
            let fix = t / 100_000 * 100_000;
            d.utc_sample(Sample::new(local(t + 4_000), U0 + fix, 20_000).held());
            t += 20_000;
        }
        assert_eq!(d.state(), DisciplineState::Valid);
        // Read 4 ms after the fix, centred at 10 ms: 6 ms early.
        let e = err_us(&d, 60_000_000);
        assert!((5_990..=6_010).contains(&e), "{e}");
        // GPS lost: the same fix repeated for 5 s: holdover.
        while t < 65_000_000 {
            d.utc_sample(Sample::new(local(t), U0 + 59_900_000, 20_000).held());
            t += 20_000;
        }
        assert_eq!(d.state(), DisciplineState::Holdover);
    }

    /// SIYI: FC clock (boot 30 s before, 30 ppm slow against true time), UTC = FC + C.
    fn fc_ms(t: u64) -> u32 {
        u32::try_from((30_000_000 + t - t * 3 / 100_000) / 1000).unwrap()
    }

    const C: u64 = U0 - 30_000_000;

    fn fc_us(t: u64) -> u64 {
        30_000_000 + t - t * 3 / 100_000
    }

    #[test]
    fn siyi_pairs_and_fc_reboot() {
        let mut d = TimeDiscipline::default();
        let mut t = 0u64;
        while t < 60_000_000 {
            let ms = fc_ms(t);
            let s = Sample::new(local(t), u64::from(ms) * 1000, 1000);
            assert_eq!(d.fc_clock_sample(s), Verdict::Accepted);
            if t < 5_000_000 && t.is_multiple_of(1_000_000) {
                let utc = C + fc_us(t);
                let s = Sample::new(local(t), utc, 1);
                assert_eq!(d.utc_via_fc_sample(s), Verdict::Accepted);
                assert_eq!(d.utc_fc_pair(utc, ms), Verdict::Accepted);
            }
            t += 100_000;
        }
        assert_eq!(d.state(), DisciplineState::Valid);
        // The FC's UTC: FC clock + C.
        let want = C + fc_us(60_000_000);
        let got = d.utc(local(60_000_000)).unwrap().as_unix_micros();
        assert!(got.abs_diff(want) <= 1_000, "{got} {want}");
        // A pair 5 ms below the unpaired bound: rejected.
        assert_eq!(
            d.utc_fc_pair(C + fc_us(0) - 5_000, fc_ms(0)),
            Verdict::Rejected
        );
        // FC reboot: time_boot_ms restarts near 0.
        let mut verdicts = [Verdict::Accepted; 5];
        for (i, v) in verdicts.iter_mut().enumerate() {
            let i = i as u64;
            let tt = 60_000_000 + i * 100_000;
            *v = d.fc_clock_sample(Sample::new(local(tt), 1_000_000 + i * 100_000, 1000));
        }
        assert_eq!(verdicts[..4], [Verdict::Outlier; 4]);
        assert_eq!(verdicts[4], Verdict::Step);
        // The local→UTC mapping did not change: still usable in holdover.
        d.poll(local(64_000_000));
        assert_eq!(d.state(), DisciplineState::Holdover);
        let want = C + fc_us(64_000_000);
        let got = d.utc(local(64_000_000)).unwrap().as_unix_micros();
        assert!(got.abs_diff(want) <= 1_000);
    }

    #[test]
    fn serial_times() {
        assert_eq!(serial_time(1, 115_200).as_micros(), 87);
        assert_eq!(serial_time(72, 115_200).as_micros(), 6_250);
        assert_eq!(serial_time(10, 0), Duration::ZERO);
    }

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
    fn a_jump_of_the_source_suspends_utc_at_once_then_restarts_from_it() {
        for jump_us in [-200_000i64, -40_000, 40_000, 1_000_000] {
            let mut d = TimeDiscipline::default();
            feed_exact(&mut d, 0, 60_000_000);
            assert!(d.is_converged());
            // The FC's UTC jumps by `jump_us`: the first sample below the floor (a
            // forward jump) suspends UTC at once; above it (backward), the third does.
            let at = |i: u64| 60_000_000 + i * 100_000;
            let value = |i: u64| (U0 + at(i)).checked_add_signed(jump_us).unwrap();
            let mut suspended_at = None;
            let mut restarted_at = None;
            for i in 0..30u64 {
                let v = d.utc_sample(Sample::new(local(at(i)), value(i), 1));
                if suspended_at.is_none() && d.state() == DisciplineState::Suspect {
                    suspended_at = Some(i);
                    assert_eq!(d.utc(local(at(i))), None);
                }
                if v == Verdict::Step {
                    restarted_at = Some(i);
                }
                if d.state() == DisciplineState::Valid && restarted_at.is_some() {
                    // The new mapping: right for the new UTC.
                    let got = d.utc(local(at(i))).unwrap().as_unix_micros();
                    // The local clock's 20 ppm over the first mapping's second.
                    assert!(got.abs_diff(value(i)) <= 50, "{jump_us}: {got}");
                    break;
                }
            }
            let first = if jump_us > 0 { 0 } else { 2 };
            assert_eq!(suspended_at, Some(first), "{jump_us}");
            assert_eq!(restarted_at, Some(4), "{jump_us}");
            // A first mapping again after eight samples (seven after the step's).
            assert_eq!(d.state(), DisciplineState::Valid, "{jump_us}");
        }
    }

    #[test]
    fn one_late_sample_is_no_jump() {
        let mut d = TimeDiscipline::default();
        feed_exact(&mut d, 0, 60_000_000);
        // 30 ms late: not used, UTC stays valid; the next sample is in line.
        let s = Sample::new(local(60_030_000), U0 + 60_000_000, 1);
        assert_eq!(d.utc_sample(s), Verdict::Outlier);
        assert_eq!(d.state(), DisciplineState::Valid);
        feed_exact(&mut d, 60_100_000, 61_000_000);
        assert_eq!(d.state(), DisciplineState::Valid);
        assert!(err_us(&d, 61_000_000).abs() <= 2);
    }

    #[test]
    fn one_prompt_sample_is_enough() {
        let mut d = TimeDiscipline::default();
        // The K40T FC's 0x00030E: its edge's UTC, sent at once, 1 ms resolution.
        let s = Sample::new(local(2_000_000), U0 + 2_000_000, 1000).prompt();
        assert_eq!(d.utc_sample(s), Verdict::Accepted);
        assert_eq!(d.state(), DisciplineState::Valid);
        assert!(err_us(&d, 2_000_000).abs() <= 500);
        let bound = d.error_bound(local(12_000_000)).unwrap().as_micros();
        assert!((2_400..=2_600).contains(&bound), "{bound}");
    }

    #[test]
    fn siyi_first_mapping_from_one_pair_and_a_rebooted_fc_with_another_utc() {
        let mut d = TimeDiscipline::default();
        let mut t = 0u64;
        // 0x22 at 10 Hz from the start; the first 0x30 (with its pair) at 3 s.
        while t <= 3_000_000 {
            let ms = fc_ms(t);
            d.fc_clock_sample(Sample::new(local(t), u64::from(ms) * 1000, 1000));
            t += 100_000;
        }
        assert_eq!(d.state(), DisciplineState::Converging, "no UTC yet");
        let utc = C + fc_us(3_000_000);
        d.utc_via_fc_sample(Sample::new(local(3_000_000), utc, 1));
        assert_eq!(d.utc_fc_pair(utc, fc_ms(3_000_000)), Verdict::Accepted);
        assert_eq!(d.state(), DisciplineState::Valid);
        // 10 s on: the clocks' 50 ppm and the millisecond truncation.
        let want = C + fc_us(13_000_000);
        let got = d.utc(local(13_000_000)).unwrap().as_unix_micros();
        assert!(got.abs_diff(want) <= 2_000, "{}", got.abs_diff(want));
        assert!(d.error_bound(local(13_000_000)).unwrap().as_micros() < 5_000);
        // The FC reboots at 60 s; its new clock restarts near 0 and, 5 s later, its new
        // 0x30 says UTC is 300 ms earlier than before.
        while t < 60_000_000 {
            d.fc_clock_sample(Sample::new(local(t), u64::from(fc_ms(t)) * 1000, 1000));
            t += 100_000;
        }
        d.poll(local(t));
        let boot = 60_000_000u64;
        let mut replaced = false;
        while t < 70_000_000 {
            let fc_new_us = t - boot;
            d.fc_clock_sample(Sample::new(local(t), fc_new_us / 1000 * 1000, 1000));
            if t == 65_000_000 {
                let utc = C + fc_us(t) - 300_000;
                d.utc_via_fc_sample(Sample::new(local(t), utc, 1));
                d.utc_fc_pair(utc, u32::try_from(fc_new_us / 1000).unwrap());
                let tr = d.poll(local(t)).unwrap();
                assert!(
                    tr.replaced && tr.utc_lost() && tr.utc_became_valid(),
                    "{tr:?}"
                );
                replaced = true;
            }
            if t < 65_000_000 {
                // Until then the old mapping holds over.
                let got = d.utc(local(t)).unwrap().as_unix_micros();
                assert!(got.abs_diff(C + fc_us(t)) <= 1_500);
            }
            t += 100_000;
        }
        assert!(replaced);
        let got = d.utc(local(t)).unwrap().as_unix_micros();
        assert!(got.abs_diff(C + fc_us(t) - 300_000) <= 1_500);
    }
}
