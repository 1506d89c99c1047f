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
//! - MAVLink: TIMESYNC feeds the FC-clock estimator, SYSTEM_TIME the offset `C` as a line
//!   of the FC clock ([`TimeDiscipline::system_time`]), used once SYSTEM_TIME shows UTC in
//!   step with the FC clock; a simulator whose UTC runs apart from its boot clock (PX4
//!   SITL in lockstep) has its SYSTEM_TIME taken as direct UTC samples instead
//!   (docs/src/bridge/time.md, "In step, or apart").
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
//! # PPS
//! With a GNSS receiver's pulse-per-second on the bridge ([`TimeDiscipline::pps_edge`],
//! each edge the local instant a timer captured, in nanoseconds), the samples above only
//! *name* the seconds: each edge is labelled with the UTC second of the FC's mapping at
//! it, checked (the mapping must put the edge within [`PpsConfig::label_tolerance`] plus
//! its own error bound of a whole second, and that bound plus the distance under half a
//! second, so that no edge is given a neighbouring second), or, once edges are taken,
//! with the second the PPS line names (a missing pulse keeps the count; an FC whose UTC
//! names another second is a conflict, and five in a row restart the PPS estimator from
//! the FC's label). A least-squares line over the last 16 edges (`pps.rs`) gives rate
//! and phase; after [`PpsConfig::lock_edges`] consistent edges the mapping is that line
//! (locked), and `utc`, `local_of` and the sync plan follow it to the nanosecond
//! ([`TimeDiscipline::local_of_ns`]).
//!
//! Without an edge for [`PpsConfig::timeout`] the lock is lost: the line runs on
//! (holdover), its error bound growing at [`PpsConfig::holdover_ppm`] from the last edge,
//! for at most [`PpsConfig::holdover`]. When the FC's mapping believes itself better than
//! that bound, the mapping hands back to it without a step: it slews from the PPS line to
//! the FC's at [`PpsConfig::handback_slew_ppm`]. Without any PPS edge nothing of this
//! runs and the discipline is the one above.
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

mod config;
mod estimator;
mod fc_offset;
mod pps;
mod pps_path;
#[cfg(test)]
mod pps_tests;
mod sample;
#[cfg(test)]
mod system_time_tests;
#[cfg(test)]
mod tests;

pub use config::DisciplineConfig;
pub use pps::{PPS_EDGES, PpsConfig, PpsVerdict};
pub use sample::{Sample, serial_time};

use super::time::{Duration, Instant, InstantNs, UtcTime};
use estimator::{ClockEstimator, Fed, Fit, Line, Point};
use fc_offset::{FcOffset, Pace};
use pps::PpsEstimator;
use sample::{local_x, point};

/// Number of bins in each clock estimator's window.
pub const BINS: usize = 32;

/// Most SIYI 0x30 frames (unpaired, and paired) remembered for the UTC − FC offset.
pub const MAX_UTC_VIA_FC: usize = 6;

protocol_core::wire_derive! {
    [Eq, Hash]
    /// Where the UTC mapping stands.
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
}

impl DisciplineState {
    /// `utc()` gives a value in this state (`Valid` or `Holdover`).
    #[must_use]
    pub const fn is_usable(self) -> bool {
        matches!(self, Self::Valid | Self::Holdover)
    }
}

protocol_core::wire_derive! {
    [Eq, Hash]
    /// A change of [`DisciplineState`], reported once by [`TimeDiscipline::poll`].
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

protocol_core::wire_derive! {
    [Eq, Hash]
    /// What the discipline did with one sample.
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
}

/// The path that produced the UTC mapping.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Path {
    /// Direct UTC samples.
    Direct,
    /// FC clock plus `C`.
    ViaFc,
}

protocol_core::wire_derive! {
    [Eq, Hash]
    /// Where the PPS path stands.
    pub enum PpsState {
        /// No PPS edges (or their line is no longer used): the FC's mapping.
        Off,
        /// Locked to the edges: the mapping is the PPS line.
        Locked,
        /// The edges stopped: the PPS line runs on at its last rate.
        Holdover,
    }
}

/// The hand-back from the PPS line to the FC's mapping: the offset (local − UTC, µs) is
/// the FC's plus what is left of `d0`, which shrinks at the slew rate from `x0`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Slew {
    x0: i64,
    d0: i64,
}

/// Which mapping `utc` and `local_of` give.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Using {
    Fc,
    Pps,
    Slew(Slew),
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
    fc_offset: FcOffset,
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
    pps_config: PpsConfig,
    pps: PpsEstimator,
    using: Using,
    /// The PPS state as last reported by [`TimeDiscipline::poll_pps`].
    pps_reported: PpsState,
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
            fc_offset: FcOffset::new(),
            output: None,
            source: None,
            last_fresh: None,
            replaced: false,
            state: DisciplineState::Unknown,
            reported: DisciplineState::Unknown,
            now: Instant::ZERO,
            pps_config: PpsConfig::DEFAULT,
            pps: PpsEstimator::new(),
            using: Using::Fc,
            pps_reported: PpsState::Off,
        }
    }

    /// The same discipline with the PPS path's settings `pps`.
    #[must_use]
    pub const fn with_pps(mut self, pps: PpsConfig) -> Self {
        self.pps_config = pps;
        self
    }

    /// The settings.
    #[must_use]
    pub const fn config(&self) -> &DisciplineConfig {
        &self.config
    }

    /// The state as of the last sample, edge or [`poll`](Self::poll).
    #[must_use]
    pub fn state(&self) -> DisciplineState {
        match self.using {
            Using::Pps if self.pps.locked || self.state == DisciplineState::Valid => {
                DisciplineState::Valid
            }
            Using::Pps => DisciplineState::Holdover,
            Using::Fc | Using::Slew(_) => self.state,
        }
    }

    /// The mapping comes from a converged fit or the PPS line (else it is a first
    /// mapping, or there is none).
    #[must_use]
    pub fn is_converged(&self) -> bool {
        self.using == Using::Pps || self.output.is_some_and(|o| o.converged)
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
            self.clock.any_rate = s.any_rate;
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
                self.fc_offset = FcOffset::new();
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
                    self.fc_offset.push_unpaired(Point { x, y });
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
    ///
    /// `fc_ms` is the FC clock's whole count of milliseconds: `time_boot_ms`, a `u32`
    /// that wraps every 49.7 days, unwrapped by the caller as its FC clock samples are
    /// (see docs/src/reliability.md).
    pub fn utc_fc_pair(&mut self, utc_us: u64, fc_ms: u64) -> Verdict {
        if utc_us < self.config.min_utc.as_unix_micros() {
            return Verdict::Rejected;
        }
        let Some(m) = i64::try_from(utc_us)
            .ok()
            .zip(i64::try_from(fc_ms).ok())
            .and_then(|(u, ms)| u.checked_sub(ms.checked_mul(1000)?))
        else {
            return Verdict::Rejected;
        };
        let tol = i64::try_from(self.config.pair_tolerance.as_micros()).unwrap_or(i64::MAX);
        if let Some(bound) = self.fc_line().and_then(|l| self.fc_offset.lower_bound(&l))
            && m < bound.saturating_sub(tol)
        {
            return Verdict::Rejected;
        }
        self.fc_offset.push_pair(m);
        let now = self.now;
        self.refresh_via_fc(now);
        Verdict::Accepted
    }

    /// A MAVLink SYSTEM_TIME: `s` its `time_unix_usec` received at `s.local` (with the
    /// serial time of the frame and what followed it, [`Sample::transit`]), `fc_ms` its
    /// `time_boot_ms`, both read from one clock in one call, so `C` is the line under the
    /// points `(fc_ms·1000, utc − fc_ms·1000)` (see `Shift`: a line with a rate, since an
    /// FC's UTC drifts against its boot clock); the FC clock comes from
    /// [`fc_clock_sample`](Self::fc_clock_sample) (TIMESYNC). `utc_us` 0 or before
    /// [`DisciplineConfig::min_utc`] is rejected; a step of the FC's UTC makes UTC
    /// suspect, then restarts `C` (reported as a replaced mapping when it disagrees).
    ///
    /// The boot-clock mapping is used only once the shift has stayed within its band for
    /// a second (UTC in step with the boot clock). A shift that runs at a rate no crystal
    /// has (UTC apart from the boot clock: a simulator in lockstep) makes the boot
    /// clock useless for UTC: from then on each SYSTEM_TIME is a direct UTC sample,
    /// timed by its arrival less its transit, as [`utc_sample`](Self::utc_sample), and
    /// TIMESYNC samples are rejected.
    ///
    /// `fc_ms` is `time_boot_ms` unwrapped to the FC clock of the TIMESYNC samples (it
    /// wraps every 49.7 days; see docs/src/reliability.md).
    pub fn system_time(&mut self, s: Sample, fc_ms: u64) -> Verdict {
        let (local, utc_us) = (s.local, s.value_us);
        self.advance(local);
        if utc_us < self.config.min_utc.as_unix_micros() {
            return Verdict::Rejected;
        }
        if self.fc_offset.shift.pace() == Pace::Apart {
            return self.utc_sample(s);
        }
        if !self.take_path(Path::ViaFc) {
            return Verdict::Rejected;
        }
        let Some((d, b)) = i64::try_from(utc_us)
            .ok()
            .zip(
                i64::try_from(fc_ms)
                    .ok()
                    .and_then(|ms| ms.checked_mul(1000)),
            )
            .and_then(|(u, b)| Some((u.checked_sub(b)?, b)))
        else {
            return Verdict::Rejected;
        };
        let tol = i64::try_from(self.config.pair_tolerance.as_micros()).unwrap_or(i64::MAX);
        let fed = self.fc_offset.shift.push(b, d, tol);
        if self.fc_offset.shift.pace() == Pace::Apart {
            self.system_time_alone();
            return self.utc_sample(s);
        }
        let verdict = match fed {
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

    /// The FC's UTC is apart from its boot clock ([`Pace::Apart`]): the estimator starts
    /// again on SYSTEM_TIME's UTC alone; a mapping through the boot clock is dropped (its
    /// error is the boot clock's wander, which no bound covers).
    fn system_time_alone(&mut self) {
        self.clock = ClockEstimator::new();
        self.path = Some(Path::Direct);
        if self.source == Some(Path::ViaFc) {
            self.output = None;
            self.source = None;
            self.last_fresh = None;
        }
    }

    /// The source of time changes (the engine takes UTC from another link): the clock
    /// estimator and `C` start again, for whichever path the new source takes; the
    /// current mapping stays usable in holdover until the new one replaces it (reported
    /// as replaced when they disagree).
    pub fn switch_source(&mut self) {
        self.clock.reset();
        self.path = None;
        self.fc_offset = FcOffset::new();
        // No path is fresh now: the next mapping, from either path, takes over.
        self.source = None;
    }

    /// Updates the output from the FC path when it gives one. A new mapping that
    /// disagrees with the current one by more than the jump tolerance replaces it (the
    /// FC's UTC jumped, e.g. after a reboot) and is reported as such.
    fn refresh_via_fc(&mut self, local: Instant) {
        // Not before SYSTEM_TIME showed UTC in step with the boot clock.
        if self.direct_valid()
            || (self.fc_offset.shift.line().is_some()
                && self.fc_offset.shift.pace() != Pace::InStep)
        {
            return;
        }
        let Some(fc) = self.clock.usable(&self.config) else {
            return;
        };
        let tol = i64::try_from(self.config.pair_tolerance.as_micros()).unwrap_or(i64::MAX);
        let Some((c, paired)) = self.fc_offset.value(Some(&fc.line), tol) else {
            return;
        };
        let Some(line) = fc.line.then_utc(&c) else {
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
        let state = self.state();
        // A replaced FC mapping is no news while the PPS line is the mapping.
        let replaced = core::mem::take(&mut self.replaced) && self.using == Using::Fc;
        if state == self.reported && !replaced {
            return None;
        }
        let t = Transition {
            from: self.reported,
            to: state,
            replaced,
        };
        self.reported = state;
        Some(t)
    }

    /// The next instant at which the state changes by itself (Valid → Holdover →
    /// Lost), if any.
    #[must_use]
    pub fn poll_at(&self) -> Option<Instant> {
        let fc = self.last_fresh.and_then(|fresh| match self.state {
            DisciplineState::Valid => Some(fresh.saturating_add(self.config.sample_timeout)),
            DisciplineState::Holdover => Some(fresh.saturating_add(self.config.holdover)),
            _ => None,
        });
        [fc, self.pps_poll_at()].into_iter().flatten().min()
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
                    || (self.source == Some(Path::ViaFc) && self.fc_offset.shift.suspect)
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
            self.fc_offset = FcOffset::new();
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
        self.advance_pps();
    }

    /// The furthest local instant the mapping may be used at.
    fn horizon(&self) -> Option<i64> {
        let fresh = self.last_fresh?;
        i64::try_from(fresh.saturating_add(self.config.holdover).as_micros()).ok()
    }

    /// UTC at local instant `local`, or `None` unless the state is usable and `local`
    /// is within the holdover horizon of the last fresh sample (of the last PPS edge,
    /// while the PPS line is the mapping).
    #[must_use]
    pub fn utc(&self, local: Instant) -> Option<UtcTime> {
        let x = i64::try_from(local.as_micros()).ok()?;
        match self.using {
            Using::Fc => self.fc_utc(local),
            Using::Pps => {
                let ns = self.pps_utc_ns(x.checked_mul(1_000)?)?;
                u64::try_from(div_round_i128(ns, 1_000)?)
                    .ok()
                    .map(UtcTime::from_unix_micros)
            }
            Using::Slew(s) => {
                let fc = self.fc_utc(local)?.as_unix_micros();
                let left = self.slew_left(s, x);
                u64::try_from(i128::from(fc).checked_sub(i128::from(left))?)
                    .ok()
                    .map(UtcTime::from_unix_micros)
            }
        }
    }

    /// The FC's mapping: UTC at `local`.
    fn fc_utc(&self, local: Instant) -> Option<UtcTime> {
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
    #[must_use]
    pub fn local_of(&self, utc: UtcTime) -> Option<Instant> {
        match self.using {
            Using::Fc => self.fc_local_of(utc),
            Using::Pps => self.local_of_ns(utc).map(|at| {
                // To the nearest microsecond.
                InstantNs::from_nanos(at.as_nanos().saturating_add(500)).instant()
            }),
            Using::Slew(s) => {
                // x = fc⁻¹(utc + left(x)): the slew moves `left` by 100 µs a second at most,
                // so three rounds settle it.
                let mut x = self.fc_local_of(utc)?;
                for _ in 0..3 {
                    let left = self.slew_left(s, i64::try_from(x.as_micros()).ok()?);
                    let r = i128::from(utc.as_unix_micros()).checked_add(i128::from(left))?;
                    let r = UtcTime::from_unix_micros(u64::try_from(r).ok()?);
                    x = self.fc_local_of(r)?;
                }
                Some(x)
            }
        }
    }

    /// The FC's mapping: the local instant at which UTC is `utc`.
    fn fc_local_of(&self, utc: UtcTime) -> Option<Instant> {
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
    /// mapping's anchor; while the PPS line is the mapping, its own bound (see
    /// [`PpsConfig::holdover_ppm`]), rounded up to the microsecond; while slewing back,
    /// the FC's plus what is left of the slew. `None` when there is no usable UTC at
    /// `local`.
    #[must_use]
    pub fn error_bound(&self, local: Instant) -> Option<Duration> {
        self.utc(local)?;
        let x = i64::try_from(local.as_micros()).ok()?;
        match self.using {
            Using::Fc => self.fc_error_bound(local),
            Using::Pps => {
                let ns = self.pps_error_bound_ns(x)?;
                let us = u64::try_from(ns.div_ceil(1_000)).ok()?;
                Some(Duration::from_micros(us))
            }
            Using::Slew(s) => {
                let left = self.slew_left(s, x).unsigned_abs();
                Some(
                    self.fc_error_bound(local)?
                        .saturating_add(Duration::from_micros(left)),
                )
            }
        }
    }

    /// The error bound of the FC's mapping at `local`.
    fn fc_error_bound(&self, local: Instant) -> Option<Duration> {
        self.fc_utc(local)?;
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
        if self.using == Using::Pps {
            return self.pps.line?.drift_ppb();
        }
        let l = self.output?.line;
        let v = i128::from(l.dy)
            .checked_mul(1_000_000_000)?
            .checked_div(i128::from(l.dx))?;
        i64::try_from(v).ok()
    }
}

/// `num/den` rounded to the nearest (`den > 0`).
fn div_round_i128(num: i128, den: i128) -> Option<i128> {
    if den <= 0 {
        return None;
    }
    num.checked_add(den / 2)?.checked_div_euclid(den)
}
