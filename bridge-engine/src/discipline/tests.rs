//! The time discipline's behaviour, sample by sample: first mapping, fit, holdover,
//! outliers and steps, held and prompt values, SIYI's FC clock and offset.

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
            assert_eq!(d.utc_fc_pair(utc, ms.into()), Verdict::Accepted);
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
        d.utc_fc_pair(C + fc_us(0) - 5_000, fc_ms(0).into()),
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
    assert_eq!(
        d.utc_fc_pair(utc, fc_ms(3_000_000).into()),
        Verdict::Accepted
    );
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
            d.utc_fc_pair(utc, fc_new_us / 1000);
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

/// An FC that sends its UTC with its clock all the time: more than 255 pairs (their ring
/// once stopped advancing there, one slot overwritten for good and five stale pairs
/// kept), the FC's crystal 30 ppm slow, so `C` = UTC − FC clock grows 30 µs a second:
/// UTC stays within 1 ms after 1000 pairs.
#[test]
fn more_than_255_pairs_keep_utc_right() {
    let mut d = TimeDiscipline::default();
    let mut t = 0u64;
    while t <= 1_000_000_000 {
        let ms = fc_ms(t);
        let s = Sample::new(local(t), u64::from(ms) * 1000, 1000);
        d.fc_clock_sample(s);
        if t.is_multiple_of(1_000_000) {
            // True UTC (the FC's GPS) against the slow FC clock: the pair of one update.
            d.utc_fc_pair(U0 + t, ms.into());
        }
        t += 100_000;
    }
    assert_eq!(d.state(), DisciplineState::Valid);
    let got = d.utc(local(1_000_000_000)).unwrap().as_unix_micros();
    let want = U0 + 1_000_000_000;
    assert!(
        got.abs_diff(want) <= 1_000,
        "{got} vs {want}: {} us",
        got.abs_diff(want)
    );
}
