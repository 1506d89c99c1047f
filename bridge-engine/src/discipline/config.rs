//! The settings of the time discipline ([`DisciplineConfig`]).

use crate::time::{Duration, UtcTime};

protocol_core::wire_derive! {
    [Eq]
    /// Settings of the [`TimeDiscipline`](super::TimeDiscipline). Leap seconds are not
    /// here: the caller converts GPS time to UTC ([`UtcTime::from_gps`]). The
    /// configuration file sets three (`[discipline] bin_ms`, `min_bins`, `min_span_ms`,
    /// for tests and demos).
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
        /// [`BINS`](super::BINS) bins, 256 s).
        #[cfg_attr(
            feature = "serde",
            serde(
                rename(deserialize = "bin_ms"),
                deserialize_with = "crate::config::de::ms"
            )
        )]
        pub bin_len: Duration,
        /// Bins needed before a clock estimate is trusted (default 5).
        #[cfg_attr(feature = "serde", serde(deserialize_with = "crate::config::de::int"))]
        pub min_bins: u8,
        /// Local time the trusted bins must span (default 16 s).
        #[cfg_attr(
            feature = "serde",
            serde(
                rename(deserialize = "min_span_ms"),
                deserialize_with = "crate::config::de::ms"
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
        /// The same for [prompt](super::Sample::prompt) samples (default 2: the K40T FC sends one
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
        /// see the [discipline](super), "Truncation").
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub center_truncation: bool,
        /// Margin when checking a SIYI pair against the unpaired lower bound (default 2 ms).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub pair_tolerance: Duration,
        /// Accepted samples after which a first mapping is given, before the fit converges
        /// (default 8: under a second of a 10 Hz source). It assumes equal clock rates and
        /// takes the least-delayed sample; [`DisciplineConfig::quick_drift_ppm`] bounds its
        /// error as it ages. A [prompt](super::Sample::prompt) sample is enough on its own.
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
        /// 1 ms): part of [`TimeDiscipline::error_bound`](super::TimeDiscipline::error_bound).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub delay_margin: Duration,
        /// Uncertainty of a SIYI UTC − FC-clock offset known only from unpaired 0x30 frames
        /// (default 10 ms: ArduPilot's transport jitter).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub unpaired_margin: Duration,
        /// A sample further than this plus its resolution from the current fit contradicts
        /// it (default 15 ms): one below the fit's floor, or three in a row above it,
        /// suspend UTC ([`DisciplineState::Suspect`](super::DisciplineState::Suspect))
        /// until a consistent sample comes or [`DisciplineConfig::step_confirm`] of them
        /// agree on a jump (the source stepped: the fit restarts from them). A time stamp
        /// off by more than 30 ms is worse than none; this keeps a jump of the FC's UTC (a
        /// reboot with another time) out of them.
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub jump_tolerance: Duration,
        /// UTC values before this are rejected (default 2020-01-01T00:00:00Z): an FC without
        /// time sends zeros or year 2000.
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub min_utc: UtcTime,
    }
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
