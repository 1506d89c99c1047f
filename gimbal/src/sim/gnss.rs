//! A GNSS receiver's time pulse (PPS, u-blox "timepulse") as the bridge's PPS input sees
//! it, and the bridge's crystal that measures it.
//!
//! [`GnssPps`] is the module: once it has its fix, one pulse a second whose on-time edge
//! is within [`GnssPpsConfig::jitter_ns`] (Gaussian, standard deviation) of the UTC
//! second; before its fix, pulses at its own free-running phase, on no UTC second; a
//! pulse goes missing with [`GnssPpsConfig::missing`]; none at all during an
//! [`GnssPpsConfig::outages`] span (a cut cable, an antenna lost). The pulse is
//! [`GnssPpsConfig::pulse_us`] long and active high or low; the bridge captures the edge
//! its configuration names (`[pps] active_low`), so a polarity mismatch puts the
//! captured edge one pulse length after the second. Each pulse is a pure function of its
//! second and the seed: no state, any order.
//!
//! [`Crystal`] is the bridge's clock against true time: its rate error
//! ([`Crystal::ppm`]) and a slow wander of its rate ([`Crystal::wander_ppm`] over
//! [`Crystal::wander_period_s`], a temperature swing), in nanoseconds both ways. In the task
//! bench the bridge's clock is the virtual time, so the GNSS's seconds are placed on it
//! through the crystal; the FC simulators keep their UTC on the virtual clock (their own
//! crystal against it), which is all a label needs (the nearest second).

use super::XorShift;

/// The module's time pulse.
#[derive(Debug, Clone, PartialEq)]
pub struct GnssPpsConfig {
    /// The noise's seed.
    pub seed: u64,
    /// UTC at true time 0, µs.
    pub utc_at_zero_us: u64,
    /// The on-time edge's jitter against the UTC second, ns (standard deviation; u-blox
    /// M8: about 30 ns, F9: about 5 ns).
    pub jitter_ns: f64,
    /// Probability that a pulse is missing.
    pub missing: f64,
    /// True time of the module's fix, µs: its pulses before it are at its own phase.
    pub fix_at_us: u64,
    /// Where the pulses before the fix fall within the second, µs after the UTC second.
    pub unlocked_phase_us: u64,
    /// Pulse length, µs (u-blox default 100 ms).
    pub pulse_us: u64,
    /// The pulse is active low: its on-time edge is the falling one.
    pub active_low: bool,
    /// True-time spans (µs, start..end) without pulses.
    pub outages: Vec<(u64, u64)>,
}

impl Default for GnssPpsConfig {
    fn default() -> Self {
        GnssPpsConfig {
            seed: 1,
            utc_at_zero_us: 1_795_428_000_000_000,
            jitter_ns: 30.0,
            missing: 0.01,
            fix_at_us: 0,
            unlocked_phase_us: 377_000,
            pulse_us: 100_000,
            active_low: false,
            outages: Vec::new(),
        }
    }
}

/// The module: see the [module documentation](self).
#[derive(Debug, Clone, PartialEq)]
pub struct GnssPps {
    /// Its settings.
    pub config: GnssPpsConfig,
}

/// Nanoseconds in a second.
const NS_PER_S: i128 = 1_000_000_000;

impl GnssPps {
    /// The module of `config`.
    #[must_use]
    pub fn new(config: GnssPpsConfig) -> Self {
        GnssPps { config }
    }

    /// UTC (ns since the Unix epoch) at true time `t_ns`.
    #[must_use]
    pub fn utc_ns(&self, t_ns: i128) -> i128 {
        i128::from(self.config.utc_at_zero_us) * 1_000 + t_ns
    }

    /// True time (ns) of UTC second `second` (Unix seconds).
    fn true_of_second(&self, second: i64) -> i128 {
        i128::from(second) * NS_PER_S - i128::from(self.config.utc_at_zero_us) * 1_000
    }

    /// The UTC second of the pulse nearest true time `t_ns`.
    fn second_at(&self, t_ns: i128) -> i64 {
        let utc = self.utc_ns(t_ns);
        i64::try_from((utc + NS_PER_S / 2).div_euclid(NS_PER_S)).unwrap_or(0)
    }

    /// The edge the bridge captures for the pulse of UTC second `second`, true time ns,
    /// with its jitter, or `None` (missing, an outage, before true time 0).
    #[must_use]
    pub fn captured_edge(&self, second: i64, bridge_active_low: bool) -> Option<i128> {
        let c = &self.config;
        let on_time = self.true_of_second(second);
        let mut rng = XorShift::new(c.seed ^ (second as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        let _ = rng.next_u64();
        if rng.chance(c.missing) {
            return None;
        }
        let before_fix = on_time < i128::from(c.fix_at_us) * 1_000;
        let mut t = on_time + (gauss(&mut rng) * c.jitter_ns).round() as i128;
        if before_fix {
            t += i128::from(c.unlocked_phase_us) * 1_000;
        }
        if bridge_active_low != c.active_low {
            // The bridge takes the pulse's other edge.
            t += i128::from(c.pulse_us) * 1_000;
        }
        let t_us = u64::try_from(t.max(0) / 1_000).unwrap_or(0);
        if t < 0 || c.outages.iter().any(|&(a, b)| (a..b).contains(&t_us)) {
            return None;
        }
        Some(t)
    }

    /// The first captured edge at or after true time `t_ns`: (its second, true ns).
    #[must_use]
    pub fn next_edge(&self, t_ns: i128, bridge_active_low: bool) -> Option<(i64, i128)> {
        let first = self.second_at(t_ns) - 1;
        // Pulses go missing and outages are finite: look a day ahead at most.
        (first..first + 86_400).find_map(|s| {
            self.captured_edge(s, bridge_active_low)
                .filter(|&t| t >= t_ns)
                .map(|t| (s, t))
        })
    }
}

/// A standard normal draw (Box–Muller).
fn gauss(rng: &mut XorShift) -> f64 {
    let u = |r: &mut XorShift| ((r.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
    let (a, b) = (u(rng), u(rng));
    (-2.0 * a.ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos()
}

/// The bridge's crystal against true time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crystal {
    /// Rate error, ppm (positive: fast).
    pub ppm: f64,
    /// Amplitude of the rate's wander, ppm.
    pub wander_ppm: f64,
    /// Period of the wander, s.
    pub wander_period_s: f64,
    /// The bridge's clock at true time 0, ns.
    pub offset_ns: i128,
}

impl Crystal {
    /// A crystal `ppm` fast with a 0.2 ppm wander over 10 minutes (a few degrees of
    /// temperature), reading 0 at true time 0.
    #[must_use]
    pub fn new(ppm: f64) -> Self {
        Crystal {
            ppm,
            wander_ppm: 0.2,
            wander_period_s: 600.0,
            offset_ns: 0,
        }
    }

    /// The bridge's clock (ns) at true time `t_ns`.
    #[must_use]
    pub fn local_ns(&self, t_ns: i128) -> i128 {
        let t = t_ns as f64;
        let w = 2.0 * std::f64::consts::PI / (self.wander_period_s * 1e9);
        // ∫ wander·cos(w t) dt = wander/w · sin(w t).
        let wander = if self.wander_ppm == 0.0 {
            0.0
        } else {
            self.wander_ppm * 1e-6 / w * (w * t).sin()
        };
        self.offset_ns + t_ns + (t * self.ppm * 1e-6 + wander).round() as i128
    }

    /// True time (ns) at which the bridge's clock reads `local_ns` (to the nanosecond).
    #[must_use]
    pub fn true_ns(&self, local_ns: i128) -> i128 {
        let mut t = ((local_ns - self.offset_ns) as f64 / (1.0 + self.ppm * 1e-6)) as i128;
        for _ in 0..4 {
            let err = self.local_ns(t) - local_ns;
            if err == 0 {
                break;
            }
            t -= ((err as f64) / (1.0 + self.ppm * 1e-6)).round() as i128;
        }
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pulses_fall_on_utc_seconds_after_the_fix() {
        let g = GnssPps::new(GnssPpsConfig {
            fix_at_us: 10_000_000,
            missing: 0.0,
            utc_at_zero_us: 1_795_428_000_250_000,
            ..GnssPpsConfig::default()
        });
        // UTC …:12.25 at true 12 s: the next second, …:13, at true 12.75 s (to the
        // jitter).
        let (s, t) = g.next_edge(12_000_000_000, false).unwrap();
        assert_eq!(s, 1_795_428_013);
        assert!((t - 12_750_000_000).abs() < 200, "{t}");
        assert_eq!(g.utc_ns(12_750_000_000), 1_795_428_013 * NS_PER_S);
        // Before the fix: at its own phase, 377 ms after the second.
        let (_, t) = g.next_edge(2_000_000_000, false).unwrap();
        assert!((t - (1_750_000_000 + 377_000_000)).abs() < 200, "{t}");
        // The wrong polarity: the pulse's other edge, 100 ms after the second.
        let (_, t) = g.next_edge(12_000_000_000, true).unwrap();
        assert!((t - 12_850_000_000).abs() < 200, "{t}");
    }

    #[test]
    fn the_crystal_maps_both_ways() {
        let c = Crystal::new(-25.0);
        for t in [0i128, 1_000_000_007, 600_000_000_000, 3_600_000_000_123] {
            let l = c.local_ns(t);
            assert!((c.true_ns(l) - t).abs() <= 1, "{t}");
        }
        // 25 ppm slow: 25 µs short after a second, to the wander.
        let l = c.local_ns(1_000_000_000);
        assert!((l - 999_975_000).abs() < 2_000, "{l}");
    }
}
