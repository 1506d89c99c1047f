//! The PPS path of the discipline, edge by edge: labels and their check, the lock,
//! holdover and the hand-back to the FC's mapping.

use super::*;

/// 2026-01-01T00:00:03.250Z in µs: the FC's UTC at true time 0.
const U0: u64 = 1_767_225_603_250_000;
/// The first whole second after U0, µs of true time.
const FIRST_SECOND_T: u64 = 750_000;

/// The local clock, ns, at true time `t_ns`: 25 ppm fast, from 1 s.
fn local_ns(t_ns: u64) -> u64 {
    1_000_000_000 + t_ns + t_ns / 40_000
}

fn local(t_us: u64) -> Instant {
    InstantNs::from_nanos(local_ns(t_us * 1_000)).instant()
}

/// FC UTC samples every 100 ms from true `from` to `to` (µs), `bias_us` late.
fn feed_fc(d: &mut TimeDiscipline, from: u64, to: u64, bias_us: u64) {
    let mut t = from;
    while t < to {
        d.utc_sample(Sample::new(local(t), U0 + t - bias_us, 1));
        t += 100_000;
    }
}

/// The PPS edge of UTC second `k` after the first, `offset_ns` late.
fn edge(k: u64, offset_ns: u64) -> InstantNs {
    InstantNs::from_nanos(local_ns(
        (FIRST_SECOND_T + k * 1_000_000) * 1_000 + offset_ns,
    ))
}

/// UTC at the edge of second `k`, µs.
fn second_utc(k: u64) -> u64 {
    U0 + FIRST_SECOND_T + k * 1_000_000
}

#[test]
fn edges_are_labelled_from_the_fc_and_lock_the_clock() {
    let mut d = TimeDiscipline::default();
    // No UTC yet: no label.
    assert_eq!(d.pps_edge(edge(0, 37)), PpsVerdict::Unlabelled);
    // The FC's UTC, 3 ms late (a bias the FC path cannot see).
    feed_fc(&mut d, 1_000_000, 2_000_000, 3_000);
    assert!(d.state().is_usable());
    assert_eq!(d.pps_state(), PpsState::Off);
    assert_eq!(d.pps_edge(edge(2, 37)), PpsVerdict::Accepted);
    assert_eq!(d.pps_state(), PpsState::Off, "one edge gives no rate");
    assert_eq!(d.pps_edge(edge(3, 41)), PpsVerdict::Accepted);
    assert_eq!(d.pps_state(), PpsState::Locked);
    assert_eq!(d.poll_pps(), Some(PpsState::Locked));
    assert_eq!(d.poll_pps(), None);
    assert_eq!(d.pps_run_start(), Some(edge(2, 37)));
    for k in 4..20 {
        feed_fc(&mut d, k * 1_000_000, (k + 1) * 1_000_000, 3_000);
        assert_eq!(d.pps_edge(edge(k, 30 + k % 20)), PpsVerdict::Accepted);
    }
    // The mapping is the PPS line: to tens of nanoseconds, both ways, 10 s ahead.
    let utc = UtcTime::from_unix_micros(second_utc(30));
    let at = d.local_of_ns(utc).unwrap();
    let want = edge(30, 40).as_nanos();
    assert!(at.as_nanos().abs_diff(want) < 30, "{at:?} vs {want}");
    let back = d.utc_ns(at).unwrap();
    assert!(back.abs_diff(second_utc(30) * 1_000) <= 1);
    assert_eq!(
        d.local_of(utc),
        Some(InstantNs::from_nanos(want + 500).instant())
    );
    // 25 ppm, to the edges' jitter.
    assert!(
        d.drift_ppb().unwrap().abs_diff(25_000) <= 2,
        "{:?}",
        d.drift_ppb()
    );
    assert!(d.is_converged());
    let bound = d.error_bound(edge(19, 0).instant()).unwrap().as_micros();
    assert!(bound <= 1, "{bound} µs");
}

#[test]
fn an_edge_off_the_second_is_no_second() {
    let mut d = TimeDiscipline::default();
    feed_fc(&mut d, 0, 2_000_000, 0);
    // A pulse of the wrong polarity: its other edge, 100 ms after the second; a module
    // before its fix, pulsing at 0.4 s.
    assert_eq!(d.pps_edge(edge(2, 100_000_000)), PpsVerdict::Unlabelled);
    feed_fc(&mut d, 2_000_000, 3_000_000, 0);
    assert_eq!(d.pps_edge(edge(3, 400_000_000)), PpsVerdict::Unlabelled);
    assert_eq!(d.pps_state(), PpsState::Off);
    // The second's own edge is taken.
    feed_fc(&mut d, 3_000_000, 4_000_000, 0);
    assert_eq!(d.pps_edge(edge(4, 0)), PpsVerdict::Accepted);
}

#[test]
fn a_missing_pulse_and_a_glitch_keep_the_lock() {
    let mut d = TimeDiscipline::default();
    feed_fc(&mut d, 0, 2_000_000, 0);
    for k in [2, 3, 4, 6, 7] {
        assert_eq!(d.pps_edge(edge(k, 0)), PpsVerdict::Accepted, "{k}");
        feed_fc(&mut d, k * 1_000_000, (k + 1) * 1_000_000, 0);
    }
    // A glitch 300 µs early: an outlier, the lock holds.
    assert_eq!(
        d.pps_edge(edge(8, 0).saturating_sub_ns(300_000)),
        PpsVerdict::Outlier
    );
    assert_eq!(d.pps_edge(edge(8, 0)), PpsVerdict::Accepted);
    assert_eq!(d.pps_state(), PpsState::Locked);
}

#[test]
fn without_edges_the_line_holds_over_then_hands_back_without_a_step() {
    let mut d = TimeDiscipline::default();
    // The FC's UTC 2 ms late.
    for k in 0..40 {
        feed_fc(&mut d, k * 1_000_000, (k + 1) * 1_000_000, 2_000);
        if k >= 2 {
            d.pps_edge(edge(k, 20));
        }
    }
    assert_eq!(d.pps_state(), PpsState::Locked);
    let _ = d.poll_pps();
    // The edges stop after second 39; the FC goes on.
    let mut prev: Option<i64> = None;
    let mut handed_back = None;
    let mut t = 40_000_000;
    while t < 1_000_000_000 {
        feed_fc(&mut d, t, t + 1_000_000, 2_000);
        t += 1_000_000;
        let at = local(t);
        d.poll(at);
        if let Some(p) = d.poll_pps() {
            if p == PpsState::Off {
                handed_back = Some(t);
            } else {
                assert_eq!(p, PpsState::Holdover, "at {t}");
            }
        }
        // UTC at this instant against the truth: continuous, never a step (the
        // slew moves it by 100 µs a second at most).
        let err = i64::try_from(d.utc(at).unwrap().as_unix_micros()).unwrap()
            - i64::try_from(U0 + t).unwrap();
        if let Some(p) = prev {
            assert!((err - p).abs() <= 101, "step at {t}: {p} → {err}");
        }
        prev = Some(err);
        if t == 100_000_000 {
            assert_eq!(d.pps_state(), PpsState::Holdover);
            assert!(err.abs() <= 1, "holdover error {err} µs after 60 s");
            // The bound grows at 2 ppm: 120 µs after 60 s.
            let b = d.error_bound(at).unwrap().as_micros();
            assert!((118..=125).contains(&b), "{b}");
        }
    }
    // The FC's bound (about 1 ms) beats the line's after about 500 s; then 20 s of slew.
    let h = handed_back.expect("handed back");
    assert!((400_000_000..700_000_000).contains(&h), "{h}");
    assert_eq!(d.pps_state(), PpsState::Off);
    assert!(
        (prev.unwrap() + 2_000).abs() <= 50,
        "the FC's mapping: {prev:?}"
    );
}
