//! Why the MCU last reset, from the STM32L4's reset flags (RCC_CSR bits 24..31; the
//! reference manual RM0351, "RCC clock control & status register"): read once at boot,
//! logged, shown on the LED when it was the watchdog ([`crate::Fault::WatchdogReset`]),
//! and kept for the console.

/// The cause of the last reset.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum ResetCause {
    /// The independent watchdog (a task stopped making progress) or the window watchdog.
    Watchdog,
    /// Software (SYSRESETREQ: a `reboot`, a debugger's reset, a panic handler's).
    Software,
    /// Power-on or brown-out (the supply rose, or dipped below the BOR level).
    PowerOn,
    /// The NRST pin (the board's reset button, a debug probe's reset line).
    Pin,
    /// Entering Standby or Stop with the low-power reset option set, an option-byte
    /// load or a firewall violation.
    Other,
    /// No flag set (the flags were cleared and nothing set them: an emulator).
    Unknown,
}

/// RCC_CSR's reset flags.
mod bit {
    pub(super) const LPWRRSTF: u32 = 1 << 31;
    pub(super) const WWDGRSTF: u32 = 1 << 30;
    pub(super) const IWDGRSTF: u32 = 1 << 29;
    pub(super) const SFTRSTF: u32 = 1 << 28;
    pub(super) const BORRSTF: u32 = 1 << 27;
    pub(super) const PINRSTF: u32 = 1 << 26;
    pub(super) const OBLRSTF: u32 = 1 << 25;
    pub(super) const FWRSTF: u32 = 1 << 24;
}

impl ResetCause {
    /// The cause RCC_CSR's flags give. Every internal reset also drives NRST low, so
    /// PINRSTF is set with the others: the more specific flag wins (watchdog, software,
    /// power-on, other), the pin only alone.
    #[must_use]
    pub const fn from_rcc_csr(csr: u32) -> Self {
        if csr & (bit::IWDGRSTF | bit::WWDGRSTF) != 0 {
            ResetCause::Watchdog
        } else if csr & bit::SFTRSTF != 0 {
            ResetCause::Software
        } else if csr & bit::BORRSTF != 0 {
            ResetCause::PowerOn
        } else if csr & (bit::LPWRRSTF | bit::OBLRSTF | bit::FWRSTF) != 0 {
            ResetCause::Other
        } else if csr & bit::PINRSTF != 0 {
            ResetCause::Pin
        } else {
            ResetCause::Unknown
        }
    }

    /// Its name in logs and on the console.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            ResetCause::Watchdog => "watchdog",
            ResetCause::Software => "software",
            ResetCause::PowerOn => "power-on",
            ResetCause::Pin => "pin",
            ResetCause::Other => "other",
            ResetCause::Unknown => "unknown",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_specific_flag_wins_over_the_pin() {
        let pin = bit::PINRSTF;
        for (flags, cause) in [
            (pin | bit::IWDGRSTF, ResetCause::Watchdog),
            (pin | bit::WWDGRSTF, ResetCause::Watchdog),
            (pin | bit::SFTRSTF, ResetCause::Software),
            // A power-on reset sets BORRSTF and PINRSTF (RM0351).
            (pin | bit::BORRSTF, ResetCause::PowerOn),
            (pin | bit::LPWRRSTF, ResetCause::Other),
            (pin, ResetCause::Pin),
        ] {
            assert_eq!(ResetCause::from_rcc_csr(flags), cause, "{flags:#010x}");
        }
        assert_eq!(ResetCause::from_rcc_csr(0), ResetCause::Unknown);
        // The reset value's other bits (LSI, MSI range) do not count.
        assert_eq!(ResetCause::from_rcc_csr(0x0C00_0600), ResetCause::PowerOn);
    }
}
