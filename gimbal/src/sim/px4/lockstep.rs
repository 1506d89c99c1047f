//! PX4 SITL's boot clock in lockstep ([`Lockstep`]), as a capture of the real thing shows it
//! (PX4 v1.16 SITL, SIH, 150 s; host-tests/fixtures/px4-sitl-lockstep.jsonl, its facts in
//! docs/src/bridge/time.md "PX4 SITL in lockstep"):
//!
//! - The simulator advances PX4's clock in **4 ms steps** and paces itself against the host:
//!   every boot-clock reading is a multiple of 4 ms.
//! - The boot clock runs **0.87 % slow** against the host's clock (−8 746 ppm over the
//!   run), and **wanders** around that line: ±25 ms over tens of seconds, its rate over
//!   10 s windows from −10 425 to −6 498 ppm. Here three sines of seeded phase (20 ms over
//!   100 s, 5 ms over 25 s, 1.5 ms over 7 s: at most ±26.5 ms, their slopes 1 260 to
//!   1 350 ppm each) on top of the line.
//! - PX4's UTC (`time_unix_usec`) is the host's clock: no wander, no steps. So `UTC −
//!   boot` grows by 8.7 ms a second with the wander, where a real flight controller keeps
//!   it fixed.
//! - TIMESYNC's `tc1` reads the boot clock **one step behind** the `time_boot_ms` the
//!   streams carry at the same instant (every SYSTEM_TIME that arrived within 3 ms after a
//!   TIMESYNC reply carried `tc1` + 4 ms).

use std::f64::consts::TAU;

use crate::sim::XorShift;

/// The settings of a lockstep boot clock.
#[derive(Debug, Clone, PartialEq)]
pub struct LockstepConfig {
    /// The simulation's rate against the host's clock, ppm (negative: slow).
    pub rate_ppm: f64,
    /// The wander around that rate: (amplitude µs, period s) of each sine.
    pub wander: Vec<(f64, f64)>,
    /// The lockstep step, µs.
    pub step_us: u64,
    /// Steps by which TIMESYNC's `tc1` lags the streams' `time_boot_ms`.
    pub timesync_lag_steps: u64,
}

impl Default for LockstepConfig {
    /// The capture's figures (see the module documentation).
    fn default() -> Self {
        LockstepConfig {
            rate_ppm: -8_746.0,
            wander: vec![(20_000.0, 100.0), (5_000.0, 25.0), (1_500.0, 7.0)],
            step_us: 4_000,
            timesync_lag_steps: 1,
        }
    }
}

/// A lockstep boot clock: simulation time against the host's (true) time.
#[derive(Debug, Clone)]
pub struct Lockstep {
    config: LockstepConfig,
    /// Each sine's phase, rad.
    phases: Vec<f64>,
    /// The boot clock at true time 0, µs.
    boot_at_zero_us: f64,
}

impl Lockstep {
    /// A clock reading `boot_at_zero_us` at true time 0 (before its step), the wander's
    /// phases drawn from `seed`.
    ///
    /// # Panics
    /// When the wander could make the clock run backwards (its slopes and the rate beyond
    /// 100 %).
    #[must_use]
    pub fn new(config: LockstepConfig, boot_at_zero_us: u64, seed: u64) -> Self {
        let slopes: f64 = config.wander.iter().map(|(a, p)| TAU * a / (p * 1e6)).sum();
        assert!(
            1.0 + config.rate_ppm * 1e-6 - slopes > 0.0,
            "a clock that runs backwards: {config:?}"
        );
        let mut rng = XorShift::new(seed ^ 0x5157_4C4F_434B);
        let phases = config
            .wander
            .iter()
            .map(|_| (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64 * TAU)
            .collect();
        Lockstep {
            config,
            phases,
            boot_at_zero_us: boot_at_zero_us as f64,
        }
    }

    /// The settings.
    #[must_use]
    pub fn config(&self) -> &LockstepConfig {
        &self.config
    }

    /// The simulation's time before the step (µs) at true time `t_us`.
    fn continuous_us(&self, t_us: u64) -> f64 {
        let t = t_us as f64;
        let wander: f64 = self
            .config
            .wander
            .iter()
            .zip(&self.phases)
            .map(|((a, p), phi)| a * ((TAU * t / (p * 1e6) + phi).sin() - phi.sin()))
            .sum();
        self.boot_at_zero_us + t * (1.0 + self.config.rate_ppm * 1e-6) + wander
    }

    /// The boot clock (µs) at true time `t_us`: a whole number of steps.
    #[must_use]
    pub fn boot_us(&self, t_us: u64) -> u64 {
        let step = self.config.step_us.max(1);
        (self.continuous_us(t_us).max(0.0) as u64) / step * step
    }

    /// The boot clock TIMESYNC's `tc1` reads at true time `t_us` (µs).
    #[must_use]
    pub fn timesync_us(&self, t_us: u64) -> u64 {
        let lag = self.config.timesync_lag_steps * self.config.step_us;
        self.boot_us(t_us).saturating_sub(lag)
    }

    /// The true time of the first step after `t_us`: the first instant the boot clock
    /// reads more than at `t_us`.
    #[must_use]
    pub fn next_step_after(&self, t_us: u64) -> u64 {
        let now = self.boot_us(t_us);
        // The clock runs at 96 % of the host's at least (checked in `new`): the next step
        // comes within two steps of true time.
        let (mut lo, mut hi) = (t_us, t_us + 2 * self.config.step_us.max(1) + 1);
        while self.boot_us(hi) <= now {
            hi += self.config.step_us.max(1);
        }
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            if self.boot_us(mid) > now {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        hi
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Least-squares slope of `ys` against `xs`.
    fn slope(xs: &[f64], ys: &[f64]) -> f64 {
        let n = xs.len() as f64;
        let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
        let sxy: f64 = xs.iter().zip(ys).map(|(x, y)| (x - mx) * (y - my)).sum();
        let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
        sxy / sxx
    }

    /// The clock as the capture shows PX4's: whole steps, 0.87 % slow over 150 s, a
    /// wander of tens of ms around that line, 10 s rates within the capture's range with
    /// its margin, never backwards; the next step found exactly.
    #[test]
    fn the_lockstep_clock_behaves_as_the_capture() {
        for seed in 1..=8 {
            let c = Lockstep::new(LockstepConfig::default(), 5_000_000, seed);
            let ts: Vec<u64> = (0..150_000).map(|i| i * 1_000).collect();
            let boot: Vec<u64> = ts.iter().map(|&t| c.boot_us(t)).collect();
            assert!(boot.iter().all(|b| b % 4_000 == 0));
            assert!(boot.windows(2).all(|w| w[0] <= w[1]));
            let x: Vec<f64> = ts.iter().map(|&t| t as f64).collect();
            let y: Vec<f64> = boot.iter().map(|&b| b as f64).collect();
            let rate_ppm = (slope(&x, &y) - 1.0) * 1e6;
            // The capture: -8746 ppm; the wander moves a 150 s fit by a few hundred.
            assert!(
                (-9_600.0..=-7_900.0).contains(&rate_ppm),
                "seed {seed}: {rate_ppm}"
            );
            // Around the line: the capture's residual spans -21.7..+29.1 ms.
            let fit = |t: f64| 5_000_000.0 + t * (1.0 - 8_746e-6);
            let res: Vec<f64> = x.iter().zip(&y).map(|(t, b)| b - fit(*t)).collect();
            let (lo, hi) = res
                .iter()
                .fold((f64::MAX, f64::MIN), |(l, h), r| (l.min(*r), h.max(*r)));
            assert!(
                hi - lo > 15_000.0 && hi - lo < 60_000.0,
                "seed {seed}: {lo}..{hi}"
            );
            // 10 s windows: the capture's -10425..-6498 ppm, here within -11500..-6000.
            for w in (0..140).step_by(10) {
                let r = (w * 1_000..(w + 10) * 1_000).collect::<Vec<usize>>();
                let xs: Vec<f64> = r.iter().map(|&i| x[i]).collect();
                let ys: Vec<f64> = r.iter().map(|&i| y[i]).collect();
                let ppm = (slope(&xs, &ys) - 1.0) * 1e6;
                assert!(
                    (-11_500.0..=-6_000.0).contains(&ppm),
                    "seed {seed} {w} s: {ppm}"
                );
            }
            for t in [0, 1, 3_999, 1_234_567, 99_999_999] {
                let n = c.next_step_after(t);
                assert_eq!(c.boot_us(n), c.boot_us(t) + 4_000, "{t}");
                assert_eq!(c.boot_us(n - 1), c.boot_us(t), "{t}");
                assert_eq!(c.timesync_us(n), c.boot_us(n) - 4_000);
            }
        }
    }
}
