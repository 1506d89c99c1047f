//! TIM2's 32-bit count and the engine's clock (the board's `src/tim2.rs` reads the pair
//! and drives the timer; the arithmetic is here, so that it runs and is tested on the
//! host).
//!
//! TIM2 counts at 80 MHz (12.5 ns a tick) and wraps every 2^32 ticks: 53.687 s. The
//! engine's clock (embassy-time, µs, 64 bits) and TIM2 come from the same 80 MHz and are
//! read together once ([`TickClock::from_reading`]); from then on a count maps to the
//! engine's clock in nanoseconds by that pair: `ns = us0·1000 + (ticks − ticks0)·12.5`.
//! A count (a capture, a compare value) is extended to 64 bits with the engine's clock
//! read near it: the difference between the count and the one the clock expects is taken
//! as a signed 32-bit number, so the count must lie within 2^31 ticks (26.8 s) of the
//! clock; the firmware reads the clock microseconds after a capture and arms a compare
//! 1 ms ahead.

use bridge_engine::InstantNs;

/// TIM2 ticks per microsecond (80 MHz).
const TICKS_PER_US: u64 = 80;

/// The relation between TIM2's count and the engine's clock, read once.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TickClock {
    /// The engine's clock (µs) and TIM2's count, read together.
    us0: u64,
    ticks0: u32,
}

impl TickClock {
    /// The relation given by the engine's clock `us0` (µs) and TIM2's count `ticks0`
    /// read together.
    #[must_use]
    pub const fn from_reading(us0: u64, ticks0: u32) -> Self {
        TickClock { us0, ticks0 }
    }

    /// The count `ticks` (32 bits, within 2^31 ticks, 26.8 s, of `now_us`) extended to
    /// 64 bits, as ticks since `ticks0`.
    fn extend(&self, ticks: u32, now_us: u64) -> i64 {
        let expected = now_us.saturating_sub(self.us0).saturating_mul(TICKS_PER_US);
        // The low 32 bits of the expected count since ticks0; the difference to the
        // value read is small and signed.
        #[allow(clippy::cast_possible_truncation)]
        let expected_low = (expected as u32).wrapping_add(self.ticks0);
        #[allow(clippy::cast_possible_wrap)]
        let delta = ticks.wrapping_sub(expected_low) as i32;
        i64::try_from(expected)
            .unwrap_or(i64::MAX)
            .saturating_add(i64::from(delta))
    }

    /// The engine's instant (ns) of the count `ticks` read near `now_us` (within 26.8 s).
    #[must_use]
    pub fn instant_of(&self, ticks: u32, now_us: u64) -> InstantNs {
        // 12.5 ns a tick: ×25/2.
        let since = self.extend(ticks, now_us).saturating_mul(25) / 2;
        let ns = i64::try_from(self.us0.saturating_mul(1_000))
            .unwrap_or(i64::MAX)
            .saturating_add(since);
        InstantNs::from_nanos(u64::try_from(ns).unwrap_or(0))
    }

    /// The count (low 32 bits) at the engine's instant `at`, to the nearest tick.
    #[must_use]
    pub fn ticks_at(&self, at: InstantNs) -> u32 {
        let since_ns = i128::from(at.as_nanos()) - i128::from(self.us0) * 1_000;
        // ×2/25, rounded.
        let ticks = (since_ns * 2 + 12).div_euclid(25);
        // The low 32 bits: wrapping is the counter's own.
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let low = ticks as u32;
        low.wrapping_add(self.ticks0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One wrap of the 32-bit count, ns: 2^32 × 12.5 ns = 53.687 s.
    const WRAP_NS: u64 = (1 << 32) * 25 / 2;

    /// The counter of a TIM2 started so that it read `ticks0` at `us0`, at instant `ns`
    /// (exact: 2 ticks every 25 ns, the count at or before `ns`).
    fn count_at(us0: u64, ticks0: u32, ns: u64) -> u32 {
        let since = i128::from(ns) - i128::from(us0) * 1_000;
        let ticks = (since * 2).div_euclid(25);
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        let low = ticks as u32;
        low.wrapping_add(ticks0)
    }

    /// Pairs read at start-up: the count near its wrap, at 0, anywhere; the clock at 0 and
    /// after days.
    const READINGS: [(u64, u32); 4] = [
        (1_000, 0xFFFF_FF00),
        (2_500_000, 0),
        (86_400_000_000, 0x8000_0000),
        (3_123_456, 0x1234_5678),
    ];

    #[test]
    fn the_wrap_is_every_53_7_s() {
        assert_eq!(WRAP_NS, 53_687_091_200);
        // A count one wrap later reads the same 32 bits, and maps to an instant one wrap
        // later when read then.
        let c = TickClock::from_reading(1_000, 7);
        let at = InstantNs::from_nanos(10_000_000_000);
        let later = InstantNs::from_nanos(at.as_nanos() + WRAP_NS);
        assert_eq!(c.ticks_at(at), c.ticks_at(later));
        let now_us = later.as_nanos() / 1_000;
        assert_eq!(c.instant_of(c.ticks_at(later), now_us), later);
        assert_eq!(c.instant_of(c.ticks_at(at), at.as_nanos() / 1_000), at);
    }

    #[test]
    fn counts_across_many_wraps_map_to_their_instants() {
        for (us0, ticks0) in READINGS {
            let c = TickClock::from_reading(us0, ticks0);
            // Around the first 1,000 wraps of the count (15 hours) and one after 49 days,
            // from 2 µs before each wrap to 2 µs after it, every 12.5 ns there.
            let wraps = (1..=1_000u64).chain([80_000]);
            for k in wraps {
                // The instant the count goes from 0xFFFF_FFFF to 0.
                let ticks_to_wrap = u64::from(u32::MAX - ticks0) + 1;
                let wrap_ns = us0 * 1_000 + ticks_to_wrap * 25 / 2 + (k - 1) * WRAP_NS;
                for step in 0..320u64 {
                    let ns = wrap_ns - 2_000 + step * 25 / 2;
                    let ticks = count_at(us0, ticks0, ns);
                    // The clock is read 3 µs after the capture.
                    let got = c.instant_of(ticks, ns / 1_000 + 3).as_nanos();
                    // The count names the tick at or before the instant: within 12.5 ns,
                    // and 0.5 ns of integer division.
                    assert!(
                        got <= ns && ns - got <= 13,
                        "reading {us0} µs/{ticks0:#x}, wrap {k}: {ns} ns read as {got}"
                    );
                    // The compare value for an instant is the count there (to the
                    // nearest tick) and maps back to it within half a tick.
                    let at = InstantNs::from_nanos(ns);
                    let target = c.ticks_at(at);
                    assert!(
                        target.wrapping_sub(ticks) <= 1,
                        "{ns} ns: compare {target:#x}, count {ticks:#x}"
                    );
                    let back = c.instant_of(target, ns / 1_000 - 1_000).as_nanos();
                    assert!(back.abs_diff(ns) <= 7, "{ns} ns → {target:#x} → {back}");
                }
            }
        }
    }

    #[test]
    fn ticks_at_rounds_to_the_nearest_tick() {
        let c = TickClock::from_reading(0, 0xFFFF_FFFE);
        let at = |ns| c.ticks_at(InstantNs::from_nanos(ns));
        assert_eq!(at(0), 0xFFFF_FFFE);
        assert_eq!(at(6), 0xFFFF_FFFE);
        assert_eq!(at(7), 0xFFFF_FFFF);
        assert_eq!(at(12), 0xFFFF_FFFF);
        assert_eq!(at(19), 0);
        assert_eq!(at(25), 0);
        assert_eq!(at(32), 1);
    }

    #[test]
    fn an_instant_before_the_reading_maps_to_the_count_before_it() {
        // Reading at 5 s, count 10: 1 µs before is 80 ticks before, across the wrap.
        let c = TickClock::from_reading(5_000_000, 10);
        let before = InstantNs::from_nanos(4_999_999_000);
        assert_eq!(c.ticks_at(before), 10u32.wrapping_sub(80));
        assert_eq!(c.instant_of(10u32.wrapping_sub(80), 5_000_000), before);
    }

    #[test]
    fn the_valid_offset_range_is_2_pow_31_ticks_either_side_of_the_clock() {
        for (us0, ticks0) in READINGS {
            let c = TickClock::from_reading(us0, ticks0);
            // The clock a few wraps on; counts as far from it as the range allows.
            let now_us = us0 + 3 * WRAP_NS / 1_000 + 12_345;
            let now_ns = now_us * 1_000;
            let now_ticks = count_at(us0, ticks0, now_ns);
            // 2^31 − 1 ticks ahead (26.84 s): still ahead.
            let ahead = now_ticks.wrapping_add(0x7FFF_FFFF);
            let got = c.instant_of(ahead, now_us).as_nanos();
            let want = now_ns + (0x7FFF_FFFFu64 * 25 / 2);
            assert!(got.abs_diff(want) <= 13, "{got} vs {want}");
            // 2^31 ticks behind: still behind.
            let behind = now_ticks.wrapping_sub(0x8000_0000);
            let got = c.instant_of(behind, now_us).as_nanos();
            let want = now_ns - (0x8000_0000u64 * 25 / 2);
            assert!(got.abs_diff(want) <= 13, "{got} vs {want}");
            // One tick further ahead is past the range: taken for a count one wrap
            // earlier (behind the clock), as the signed difference says.
            let past = now_ticks.wrapping_add(0x8000_0000);
            let got = c.instant_of(past, now_us).as_nanos();
            let want = now_ns - (0x8000_0000u64 * 25 / 2);
            assert!(got.abs_diff(want) <= 13, "{got} vs {want}");
        }
    }

    #[test]
    fn a_clock_before_the_reading_or_far_on_saturates_instead_of_wrapping() {
        let c = TickClock::from_reading(1_000_000, 0);
        // The clock read before the pair (never on the board): the count is taken near
        // the reading, and an instant before 0 is 0.
        assert_eq!(c.instant_of(0, 0).as_nanos(), 1_000_000_000);
        assert_eq!(c.instant_of(u32::MAX - 79_999_999, 0).as_nanos(), 0);
        // The engine's clock at its end (584,000 years): no overflow.
        let far = c.instant_of(0, u64::MAX);
        assert!(far.as_nanos() > 0);
    }
}
