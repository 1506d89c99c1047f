//! PX4 SITL in lockstep through the engine in simulated time (docs/src/bridge/time.md,
//! "PX4 SITL in lockstep"): the capture of a real PX4 v1.16 SITL replayed (`px4_capture`),
//! and the simulated PX4 whose clocks behave as the capture shows (boot clock in 4 ms
//! steps, 0.87 % slow against its UTC, the host's, wandering by tens of ms). UTC must stay
//! valid while PX4 sends time, every sync's error bound must be at least its error against
//! PX4's own UTC, and every stamp within 5 ms of it.

use crate::engine_scenarios;
use crate::px4_capture;

use bridge_engine::{Config, Event, FcProtocol};
use gimbal::sim::line::Line;
use gimbal::sim::peer::Peer;
use gimbal::sim::pilot::Pilot;
use gimbal::sim::pod::{PodSimConfig, SimPod, SyncOutcome};
use gimbal::sim::px4::{Px4, Px4Config};
use gimbal::sim::scenario::Scenario;
use protocol_core::k40t::AckCode;

use engine_scenarios::{S, figures, one_sync_per_edge};
use px4_capture::{Capture, CapturedPx4, LINE_BAUD};

/// One time sync, against PX4's UTC.
#[derive(Debug, Clone, Copy)]
struct Checked {
    /// The edge, true µs.
    edge_us: u64,
    /// The UTC the pod was given minus PX4's at the edge, µs.
    error_us: f64,
    /// The bound the bridge believed, µs.
    bound_us: u32,
}

/// Every time sync of `s` (each applied by the pod at its edge) against `truth`, PX4's
/// UTC (µs) at a true instant.
fn checked_syncs<F: Peer>(s: &Scenario<F>, truth: impl Fn(u64) -> f64) -> Vec<Checked> {
    let syncs: Vec<Checked> = s
        .events
        .iter()
        .filter_map(|(_, e)| match *e {
            Event::TimeSync {
                edge,
                utc_ms,
                error_bound_us,
            } => {
                let edge_us = s.true_of(edge);
                Some(Checked {
                    edge_us,
                    error_us: (utc_ms * 1000) as f64 - truth(edge_us),
                    bound_us: error_bound_us,
                })
            }
            _ => None,
        })
        .collect();
    let applied = s.pod.syncs();
    assert_eq!(applied.len(), syncs.len());
    for (a, c) in applied.iter().zip(&syncs) {
        assert_eq!(a.outcome, SyncOutcome::Applied, "{a:?}");
        assert_eq!(a.edge_us, Some(c.edge_us));
        assert_eq!(a.unix_ms % 10_000, 0, "on the 10 s grid");
    }
    syncs
}

/// When UTC first became valid, and every loss after it (true µs).
fn utc_valid_and_losses<F: Peer>(s: &Scenario<F>) -> (Option<u64>, Vec<u64>) {
    let first = s
        .events
        .iter()
        .find(|(_, e)| matches!(e, Event::UtcValid { .. }))
        .map(|(t, _)| *t);
    let lost = s
        .events
        .iter()
        .filter(|(t, e)| first.is_some_and(|f| *t > f) && matches!(e, Event::UtcLost))
        .map(|(t, _)| *t)
        .collect();
    (first, lost)
}

/// The syncs whose bound is under their error.
fn dishonest(syncs: &[Checked]) -> Vec<Checked> {
    syncs
        .iter()
        .copied()
        .filter(|c| c.error_us.abs() > f64::from(c.bound_us))
        .collect()
}

fn print_syncs(label: &str, syncs: &[Checked]) {
    for c in syncs {
        println!(
            "  {label}: edge {:8.3} s, error {:+7.0} us, bound {:5} us",
            c.edge_us as f64 / 1e6,
            c.error_us,
            c.bound_us
        );
    }
}

/// A scenario whose FC link is a pseudo-terminal (bytes take no serial time: lines at 4
/// Mbaud) while the engine is configured for 115 200 baud, as a user runs `gimbal bridge`
/// on SITL's pty.
fn over_a_pty<F: Peer>(fc: F, bridge_ppm: i64) -> Scenario<F> {
    let config = Config::for_fc(FcProtocol::Mavlink);
    assert_eq!(config.fc_baud, 115_200);
    let mut s = Scenario::new(config, fc, SimPod::new(PodSimConfig::default()), bridge_ppm);
    s.fc_line = Line::new(LINE_BAUD);
    s.to_fc_line = Line::new(LINE_BAUD);
    s
}

/// The capture of a real PX4 v1.16 SITL in lockstep, replayed through the engine
/// (`px4_capture`: PX4's frames at their captured instants, the bridge's TIMESYNC requests
/// answered from PX4's boot clock rebuilt from the capture), the engine configured as the
/// captured bridge was: UTC valid within a second and never lost while PX4 sends time,
/// every sync's bound at least its error against PX4's UTC on its ground link, every
/// stamp within 5 ms of it. On the engine of the capture (before the fix) the replay gave
/// what the real bridge gave: UTC lost 21 times (the capture: 22, the first four at the
/// same instants), stamps 4–31 ms early under 2–23 ms bounds.
#[test]
fn the_captured_px4_sitl_keeps_utc_and_honest_bounds() {
    let capture = Capture::load();
    let end = capture.rx.last().expect("frames").t_us + 500_000;
    let mut s = over_a_pty(CapturedPx4::new(capture), 0);
    s.run_until(end);
    let capture = s.fc.capture();
    let syncs = checked_syncs(&s, |t| capture.reference_utc_us(t as f64));
    let (valid, lost) = utc_valid_and_losses(&s);
    let valid = valid.expect("UTC valid");
    println!(
        "replay: UTC valid at {:.3} s, lost {} times after, {} TIMESYNC answered, {} syncs",
        valid as f64 / 1e6,
        lost.len(),
        s.fc.answers.len(),
        syncs.len()
    );
    print_syncs("replay", &syncs);
    // Measured 2.22 s (the boot clock is judged apart from UTC, then eight SYSTEM_TIMEs);
    // bound 6.7 s.
    assert!(valid < 6_700_000, "UTC valid at {valid} us");
    assert!(lost.is_empty(), "UTC lost at {lost:?} us");
    assert!(dishonest(&syncs).is_empty(), "{:?}", dishonest(&syncs));
    // The capture's 150 s: an edge every 10 s from the first after UTC became valid.
    assert_eq!(syncs.len(), 15, "{syncs:?}");
    let errors: Vec<i64> = syncs.iter().map(|c| c.error_us.round() as i64).collect();
    let abs = figures("replay of the PX4 SITL capture", &errors);
    // Required: within 5 ms. Measured max 100 µs (p50 34, p99 100); bound 300.
    assert!(abs[abs.len() - 1] <= 300, "max {} us", abs[abs.len() - 1]);
}

/// Photos every 10 s from `from_us` to `until_us`; returns the geotag replies' codes.
fn photos_every_10_s(s: &mut Scenario<Px4>, from_us: u64, until_us: u64) -> Vec<AckCode> {
    s.run_until(from_us);
    while s.now_us + 10 * S <= until_us {
        s.fc.take_picture();
        s.run_for(10 * S);
    }
    s.pod
        .gps_replies()
        .iter()
        .map(|r| r.reply.code.code())
        .collect()
}

/// The simulated PX4 SITL in lockstep (its clocks as the capture shows them), over a
/// pseudo-terminal, four seeds of its wander, the bridge's crystal 25 ppm off the host's:
/// UTC valid within seconds and never lost, every geotag answered, a sync at every edge
/// with its bound at least its error against PX4's UTC, within 5 ms of it. On the engine
/// before the fix: UTC lost 11 times in 125 s (seed 1), stamps 5–20 ms early under 2–10 ms
/// bounds.
#[test]
fn px4_sitl_in_lockstep_keeps_utc_answers_geotags_and_syncs_within_bound() {
    let mut all = Vec::new();
    for seed in 1..=4 {
        let mut s = over_a_pty(
            Px4::new(Px4Config {
                seed,
                ..Px4Config::sitl_lockstep()
            }),
            25,
        );
        let codes = photos_every_10_s(&mut s, 20 * S, 125 * S);
        let (valid, lost) = utc_valid_and_losses(&s);
        let valid = valid.expect("UTC valid");
        let syncs = checked_syncs(&s, |t| s.fc.true_utc_us(t) as f64);
        println!(
            "seed {seed}: UTC valid at {:.3} s, lost {} times after; {} geotags",
            valid as f64 / 1e6,
            lost.len(),
            codes.len()
        );
        print_syncs(&format!("seed {seed}"), &syncs);
        // Measured 1.52 s; bound 4.6 s.
        assert!(valid < 4_600_000, "UTC valid at {} ms", valid / 1000);
        assert!(lost.is_empty(), "seed {seed}: UTC lost at {lost:?} us");
        assert!(dishonest(&syncs).is_empty(), "{:?}", dishonest(&syncs));
        assert!(codes.len() >= 10);
        assert!(codes.iter().all(|c| *c == AckCode::Ok), "{codes:?}");
        one_sync_per_edge(&s);
        assert!(syncs.len() >= 12, "{}", syncs.len());
        all.extend(syncs);
    }
    let errors: Vec<i64> = all.iter().map(|c| c.error_us.round() as i64).collect();
    let abs = figures("simulated PX4 SITL in lockstep", &errors);
    // Required: within 5 ms. Measured max 613 µs (the first syncs, before the fit has the
    // bridge's 25 ppm; p50 82, p99 613); bound 1 840.
    assert!(abs[abs.len() - 1] <= 1_840, "max {} us", abs[abs.len() - 1]);
}

/// Least-squares slope of `ys` against `xs`, and the range of the residuals.
fn fit(xs: &[f64], ys: &[f64]) -> (f64, f64, f64) {
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    let slope = sxy / sxx;
    let res = xs.iter().zip(ys).map(|(x, y)| y - my - slope * (x - mx));
    let (lo, hi) = res.fold((f64::MAX, f64::MIN), |(l, h), r| (l.min(r), h.max(r)));
    (slope, lo, hi)
}

/// The q quantile (nearest rank) of `v`.
fn q(v: &mut [f64], q: f64) -> f64 {
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}

/// The capture's facts as docs/src/bridge/time.md states them ("PX4 SITL in lockstep"),
/// computed from the fixture: PX4's boot clock 0.87 % slow with tens of ms of wander and
/// 4 ms steps, its UTC the host's clock, SYSTEM_TIME on simulation time, TIMESYNC's tc1 a
/// step behind, replies with unset targets, the pty's delays; and what the bridge of the
/// capture did with it.
#[test]
fn the_capture_shows_what_the_book_says() {
    let c = Capture::load();
    let field = |f: &px4_capture::RxFrame, off: usize, n: usize| {
        // The payload's little-endian field at `off` (zeros trimmed off the end).
        let p = &f.raw[10..f.raw.len() - 2];
        (0..n).fold(0u64, |a, i| {
            a | u64::from(*p.get(off + i).unwrap_or(&0)) << (8 * i)
        })
    };
    // TIMESYNC: 611 exchanges, tc1 in whole 4 ms steps; the boot clock against the
    // bridge's (the host's) 0.87 % slow, its residual spanning about 53 ms.
    let ex = &c.exchanges;
    assert_eq!(ex.len(), 611);
    assert!(ex.iter().all(|e| e.tc1_ns % 4_000_000 == 0));
    let x: Vec<f64> = ex.iter().map(|e| e.sent_us as f64).collect();
    let y: Vec<f64> = ex.iter().map(|e| e.tc1_ns as f64 / 1e3).collect();
    let (slope, lo, hi) = fit(&x, &y);
    let ppm = (slope - 1.0) * 1e6;
    println!(
        "boot clock {ppm:.0} ppm, residual {:.1}..{:.1} ms",
        lo / 1e3,
        hi / 1e3
    );
    assert!((-8_760.0..=-8_730.0).contains(&ppm), "{ppm}");
    assert!(
        lo < -20_000.0 && hi > 25_000.0 && hi - lo < 60_000.0,
        "{lo} {hi}"
    );
    // Replies: targets never the requester's 6/154 (PX4 1.16 fills only tc1 and ts1),
    // 208/17 in 607; round trips p50 238 µs, max 27 ms.
    assert!(ex.iter().all(|e| e.target != (6, 154)));
    assert_eq!(ex.iter().filter(|e| e.target == (208, 17)).count(), 607);
    let mut rtt: Vec<f64> = ex
        .iter()
        .map(|e| (e.received_us - e.sent_us) as f64)
        .collect();
    assert_eq!(q(&mut rtt, 0.5), 238.0);
    assert!((27_000.0..28_000.0).contains(&q(&mut rtt, 1.0)));
    // SYSTEM_TIME on the bridge's link: its boot ms advances by exactly 100 (scheduled on
    // simulation time), its UTC by 99.5 to 102.6 ms, at the host's rate (within 1 ppm of
    // the bridge's clock); the least-delay receipt p50 144 µs, p99 814 µs, max 3.4 ms.
    let st: Vec<_> = c.rx.iter().filter(|f| f.msg == "SYSTEM_TIME").collect();
    assert_eq!(st.len(), 1486);
    let (utc, boot): (Vec<f64>, Vec<u64>) = st
        .iter()
        .map(|f| (field(f, 0, 8) as f64, field(f, 8, 4)))
        .unzip();
    for w in boot.windows(2) {
        assert_eq!(w[1] - w[0], 100);
    }
    for w in utc.windows(2) {
        assert!(
            (99_500.0..=102_600.0).contains(&(w[1] - w[0])),
            "{}",
            w[1] - w[0]
        );
    }
    let t: Vec<f64> = st.iter().map(|f| f.t_us as f64).collect();
    let (slope, _, _) = fit(&t, &utc);
    assert!(((slope - 1.0) * 1e6).abs() < 1.0, "{slope}");
    let mut delay: Vec<f64> = t.iter().zip(&utc).map(|(t, u)| c.host_us(*t) - u).collect();
    let (p50, p99, max) = (q(&mut delay, 0.5), q(&mut delay, 0.99), q(&mut delay, 1.0));
    println!("SYSTEM_TIME receipt delay p50 {p50:.0} p99 {p99:.0} max {max:.0} us");
    assert!(delay[0] >= 0.0 && (140.0..150.0).contains(&p50), "{p50}");
    assert!((800.0..830.0).contains(&p99) && (3_300.0..3_400.0).contains(&max));
    // ATTITUDE and GLOBAL_POSITION_INT: boot ms in whole 4 ms steps.
    for f in
        c.rx.iter()
            .filter(|f| f.msg == "ATTITUDE" || f.msg == "GLOBAL_POSITION_INT")
    {
        assert_eq!(field(f, 0, 4) % 4, 0, "{}", f.msg);
    }
    // TIMESYNC's tc1 one step behind the streams: every SYSTEM_TIME that arrived within
    // 3 ms after a reply carries tc1 + 4 ms.
    let mut after = 0;
    for e in ex {
        if let Some(i) = st.iter().position(|f| f.t_us >= e.received_us)
            && st[i].t_us - e.received_us < 3_000
        {
            assert_eq!(boot[i] * 1_000_000, e.tc1_ns as u64 + 4_000_000);
            after += 1;
        }
    }
    assert!(after >= 20, "{after}");
    // The ground link: the same boot clock rate against the host's receipt, UTC the host's
    // clock within 0.1 ppm, advancing by 100.1 to 102.5 ms a message.
    let gx: Vec<f64> = c.gcs.iter().map(|g| g.at_us).collect();
    let gb: Vec<f64> = c.gcs.iter().map(|g| g.boot_ms as f64 * 1e3).collect();
    let gu: Vec<f64> = c.gcs.iter().map(|g| g.utc_us as f64).collect();
    assert!(
        gu.windows(2)
            .all(|w| (100_100.0..=102_500.0).contains(&(w[1] - w[0])))
    );
    assert!((((fit(&gx, &gb).0) - 1.0) * 1e6 + 8_746.0).abs() < 5.0);
    assert!(((fit(&gx, &gu).0 - 1.0) * 1e6).abs() < 0.1);
    // What the bridge of the capture did: 22 losses of UTC, 15 syncs, each stamp early by
    // more than the bound it believed in most of them.
    assert_eq!(c.events_named("utc_lost").len(), 22);
    let syncs = c.events_named("time_sync");
    assert_eq!(syncs.len(), 15);
    let dishonest = syncs
        .iter()
        .filter(|e| {
            let err = e.fields["utc_ms"].as_f64().unwrap() * 1e3
                - c.reference_utc_us(e.fields["edge_us"].as_f64().unwrap());
            err.abs() > e.fields["error_bound_us"].as_f64().unwrap()
        })
        .count();
    assert!(dishonest >= 12, "{dishonest}");
}
