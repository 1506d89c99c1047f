//! When a new image confirms itself: the rollback rule.
//!
//! An image the bootloader has just swapped in is on trial: if the board resets before the
//! image confirms itself (the watchdog bites a hung image, power is cut, it crashes), the
//! bootloader swaps the previous image back. The image confirms itself when it is healthy:
//! its FC link and its pod link are both up (the engine's status), or it has run for
//! [`CONFIRM_AFTER_S`] seconds with every supervised loop alive (the watchdog resets it
//! otherwise), so that a board on the bench without a pod or an FC keeps a good update.

/// The bounded time after which a running image confirms itself without its links: 60 s.
pub const CONFIRM_AFTER_S: u64 = 60;

/// The trial of a freshly swapped-in image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Trial {
    started_us: u64,
}

impl Trial {
    /// A trial that started at `now_us` (microseconds of the firmware's clock).
    #[must_use]
    pub fn new(now_us: u64) -> Self {
        Trial { started_us: now_us }
    }

    /// Whether the image should confirm itself now: both links up, or
    /// [`CONFIRM_AFTER_S`] seconds of running.
    #[must_use]
    pub fn healthy(&self, now_us: u64, fc_link: bool, pod_link: bool) -> bool {
        let ran_us = now_us.saturating_sub(self.started_us);
        (fc_link && pod_link) || ran_us >= CONFIRM_AFTER_S.saturating_mul(1_000_000)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn confirms_when_both_links_are_up_or_after_the_bounded_time() {
        let t = Trial::new(5_000_000);
        assert!(!t.healthy(5_000_000, false, false));
        assert!(
            !t.healthy(6_000_000, true, false),
            "the FC link alone is not enough"
        );
        assert!(
            !t.healthy(6_000_000, false, true),
            "the pod link alone is not enough"
        );
        assert!(t.healthy(6_000_000, true, true));
        assert!(
            !t.healthy(64_999_999, false, false),
            "59.999999 s after the start"
        );
        assert!(t.healthy(65_000_000, false, false), "60 s after the start");
        // A clock read before the start (never on the firmware): not healthy by time.
        assert!(!t.healthy(0, false, false));
    }
}
