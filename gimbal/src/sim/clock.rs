//! The clock of a simulated flight controller: a crystal that runs fast or slow, restarted
//! at each power-on, and the UTC the FC keeps on it (ArduPilot's `AP_RTC`) or its GPS
//! keeps.

/// A simulated crystal clock (µs) at true time `t_us`: `ppm` fast, reading `boot_us` at
/// true time 0.
#[must_use]
fn crystal_us(t_us: u64, ppm: f64, boot_us: u64) -> u64 {
    (t_us as f64 * (1.0 + ppm * 1e-6)) as u64 + boot_us
}

/// True time at which the crystal clock of [`crystal_us`] reads `clock_us` (rounded up).
#[must_use]
fn true_of_crystal(clock_us: u64, ppm: f64, boot_us: u64) -> u64 {
    ((clock_us.saturating_sub(boot_us)) as f64 / (1.0 + ppm * 1e-6)).ceil() as u64
}

/// How a simulated flight controller reboots ([`super::Autopilot::reboot`]): it is dead for [`FcReboot::off_us`], then boots with its boot clock
/// near 0 and a UTC that may differ from the previous boot's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FcReboot {
    /// Without power (silent, deaf) this long, µs.
    pub off_us: u64,
    /// The FC's boot clock (`time_boot_ms`) reads this at power-on, µs.
    pub boot_clock_us: u64,
    /// The new boot's UTC minus the previous boot's UTC carried on, µs: a GPS or RTC
    /// that was wrong before the reboot and right after it, or the reverse.
    pub utc_shift_us: i64,
    /// The FC's UTC becomes valid this long after power-on (GPS fix), µs.
    pub utc_valid_after_us: u64,
}

impl Default for FcReboot {
    fn default() -> Self {
        FcReboot {
            off_us: 3_000_000,
            boot_clock_us: 0,
            utc_shift_us: 0,
            utc_valid_after_us: 0,
        }
    }
}

/// One power-on of a simulated FC.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FcBoot {
    /// True time the power went off before it (the first boot: its own instant).
    pub off_at_us: u64,
    /// True time of power-on.
    pub at_us: u64,
    /// The boot clock at power-on, µs.
    pub clock_us: u64,
    /// The FC's UTC at power-on, µs since the Unix epoch.
    pub utc_us: u64,
    /// True time from which the UTC is valid.
    pub utc_valid_at_us: u64,
    /// The UTC shift of this boot against the first, µs: every reboot's
    /// [`FcReboot::utc_shift_us`] so far.
    pub utc_shift_us: i64,
}

/// The clock of a simulated FC across reboots: a crystal `ppm` fast, restarted at each
/// power-on, and its UTC (ArduPilot's `AP_RTC`: the boot clock plus a shift fixed once
/// per boot).
#[derive(Debug, Clone, PartialEq)]
pub struct FcClock {
    ppm: f64,
    boots: Vec<FcBoot>,
}

impl FcClock {
    /// A clock powered on at true time 0, reading `clock_us` then, with UTC `utc_us`
    /// then, valid from true time `utc_valid_at_us`.
    #[must_use]
    pub fn new(ppm: f64, clock_us: u64, utc_us: u64, utc_valid_at_us: u64) -> Self {
        FcClock {
            ppm,
            boots: vec![FcBoot {
                off_at_us: 0,
                at_us: 0,
                clock_us,
                utc_us,
                utc_valid_at_us,
                utc_shift_us: 0,
            }],
        }
    }

    /// The crystal's error, ppm.
    #[must_use]
    pub fn ppm(&self) -> f64 {
        self.ppm
    }

    /// Every boot, the first at true time 0.
    #[must_use]
    pub fn boots(&self) -> &[FcBoot] {
        &self.boots
    }

    /// The boot in effect at true time `t_us` (before a power-on: the previous one).
    #[must_use]
    pub fn boot_at(&self, t_us: u64) -> &FcBoot {
        let i = self
            .boots
            .iter()
            .rposition(|b| b.at_us <= t_us)
            .unwrap_or(0);
        // Never empty: `new` puts the first boot.
        &self.boots[i]
    }

    /// The latest boot (possibly still to come).
    #[must_use]
    pub fn current(&self) -> &FcBoot {
        &self.boots[self.boots.len() - 1]
    }

    /// The boot clock (µs) at true time `t_us`.
    #[must_use]
    pub fn clock_us(&self, t_us: u64) -> u64 {
        let b = self.boot_at(t_us);
        crystal_us(t_us.saturating_sub(b.at_us), self.ppm, b.clock_us)
    }

    /// True time at which the latest boot's clock reads `clock_us`.
    #[must_use]
    pub fn true_of_clock(&self, clock_us: u64) -> u64 {
        let b = self.current();
        b.at_us + true_of_crystal(clock_us, self.ppm, b.clock_us)
    }

    /// The FC's UTC (µs) at true time `t_us`.
    #[must_use]
    pub fn utc_us(&self, t_us: u64) -> u64 {
        let b = self.boot_at(t_us);
        (self.clock_us(t_us) - b.clock_us) + b.utc_us
    }

    /// UTC as a GPS receiver keeps it (µs) at true time `t_us`: the first boot's UTC
    /// carried on at the true rate (the crystal's error does not enter), shifted as each
    /// reboot before `t_us` shifted the FC's UTC.
    #[must_use]
    pub fn gps_utc_us(&self, t_us: u64) -> u64 {
        let first = self.boots.first().map_or(0, |b| b.utc_us);
        let utc =
            i128::from(first) + i128::from(t_us) + i128::from(self.boot_at(t_us).utc_shift_us);
        u64::try_from(utc.max(0)).unwrap_or(0)
    }

    /// The FC knows UTC at true time `t_us`.
    #[must_use]
    pub fn utc_valid(&self, t_us: u64) -> bool {
        t_us >= self.boot_at(t_us).utc_valid_at_us
    }

    /// The FC is without power at true time `t_us`.
    #[must_use]
    pub fn is_off(&self, t_us: u64) -> bool {
        self.boots
            .iter()
            .any(|b| b.off_at_us <= t_us && t_us < b.at_us)
    }

    /// The FC's UTC steps by `shift_us` at true time `now_us`, its boot clock running on
    /// (a GPS that corrects a wrong time, a leap second inserted: -1 s): the step is a
    /// boot of no power-off, whose UTC is the old one carried on, shifted.
    pub fn step_utc(&mut self, now_us: u64, shift_us: i64) {
        let carried = i128::from(self.utc_us(now_us));
        let current = *self.current();
        self.boots.push(FcBoot {
            off_at_us: now_us,
            at_us: now_us,
            clock_us: self.clock_us(now_us),
            utc_us: u64::try_from((carried + i128::from(shift_us)).max(0)).unwrap_or(0),
            utc_valid_at_us: current.utc_valid_at_us.min(now_us),
            utc_shift_us: current.utc_shift_us + shift_us,
        });
    }

    /// The power goes off at `now_us`; returns the instant of power-on.
    pub fn reboot(&mut self, now_us: u64, r: FcReboot) -> u64 {
        let at_us = now_us.saturating_add(r.off_us);
        let carried = i128::from(self.utc_us(at_us));
        let utc_us = u64::try_from((carried + i128::from(r.utc_shift_us)).max(0)).unwrap_or(0);
        let utc_shift_us = self.current().utc_shift_us + r.utc_shift_us;
        self.boots.push(FcBoot {
            off_at_us: now_us,
            at_us,
            clock_us: r.boot_clock_us,
            utc_us,
            utc_valid_at_us: at_us.saturating_add(r.utc_valid_after_us),
            utc_shift_us,
        });
        at_us
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_fc_clock_restarts_at_each_boot_with_its_utc_shifted() {
        let mut c = FcClock::new(0.0, 3_000_000, 1_000_000_000_000, 500_000);
        assert_eq!(c.clock_us(1_000_000), 4_000_000);
        assert_eq!(c.utc_us(1_000_000), 1_000_001_000_000);
        assert!(!c.utc_valid(0) && c.utc_valid(500_000));
        assert_eq!(c.true_of_clock(4_000_000), 1_000_000);
        let on = c.reboot(
            10_000_000,
            FcReboot {
                off_us: 3_000_000,
                boot_clock_us: 2_000,
                utc_shift_us: -250_000,
                utc_valid_after_us: 1_000_000,
            },
        );
        assert_eq!(on, 13_000_000);
        assert!(c.is_off(10_000_000) && c.is_off(12_999_999) && !c.is_off(on));
        // Before power-on the old boot's clock goes on (nobody reads it).
        assert_eq!(c.clock_us(12_000_000), 15_000_000);
        assert_eq!(c.clock_us(on), 2_000);
        assert_eq!(c.clock_us(on + 1_000_000), 1_002_000);
        // The old boot's UTC carried on to the power-on, shifted.
        let carried = 1_000_000_000_000 + 13_000_000;
        assert_eq!(c.utc_us(on), carried - 250_000);
        assert_eq!(c.utc_us(on + 1_000_000), carried - 250_000 + 1_000_000);
        assert!(!c.utc_valid(on + 999_999) && c.utc_valid(on + 1_000_000));
        assert_eq!(c.true_of_clock(1_002_000), on + 1_000_000);
        assert_eq!(c.boots().len(), 2);
        // The GPS's UTC runs at the true rate, shifted from power-on.
        assert_eq!(c.gps_utc_us(on - 1), 1_000_000_000_000 + on - 1);
        assert_eq!(c.gps_utc_us(on + 5), carried - 250_000 + 5);

        // A UTC step: the boot clock runs on, UTC jumps.
        let before = c.clock_us(20_000_000);
        c.step_utc(20_000_000, -1_000_000);
        assert_eq!(c.clock_us(20_000_000), before);
        assert_eq!(
            c.utc_us(20_000_001),
            carried - 250_000 + 7_000_001 - 1_000_000
        );
        assert!(!c.is_off(20_000_000));

        // A fast crystal runs fast in every boot.
        let mut c = FcClock::new(100.0, 0, 0, 0);
        let on = c.reboot(5_000_000, FcReboot::default());
        assert!(c.clock_us(on + 10_000_000).abs_diff(10_001_000) <= 1);
        assert!(c.true_of_clock(10_001_000).abs_diff(on + 10_000_000) <= 1);
    }
}
