//! PX4 as its users run it, through the engine in simulated time: SITL in lockstep (its
//! boot clock 1.2 % slow against its UTC, which follows the host: the offset as a line
//! with a rate, docs/src/bridge/time.md), PX4 1.16's link in mode Gimbal (no time, no
//! fixes: said by an event, docs/src/autopilots/px4.md), mode Normal.

mod engine_scenarios;

use bridge_engine::Event;
use gimbal::sim::pilot::Pilot;
use gimbal::sim::pod::PodSimConfig;
use gimbal::sim::px4::{Px4, Px4Config};
use gimbal::sim::scenario::Scenario;

use engine_scenarios::{S, figures, one_sync_per_edge, sync_errors_us};
use protocol_core::k40t::AckCode;

fn px4_scenario(config: Px4Config) -> Scenario<Px4> {
    engine_scenarios::scenario(Px4::new(config), PodSimConfig::default(), 25)
}

/// UTC losses after it first became valid, and when it did.
fn utc_losses(s: &Scenario<Px4>) -> (Option<u64>, usize) {
    let first = s
        .events
        .iter()
        .find(|(_, e)| matches!(e, Event::UtcValid { .. }))
        .map(|(t, _)| *t);
    let lost = s
        .events
        .iter()
        .filter(|(t, e)| first.is_some_and(|f| *t > f) && matches!(e, Event::UtcLost))
        .count();
    (first, lost)
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

#[test]
fn px4_sitl_in_lockstep_keeps_utc_answers_geotags_and_syncs_within_bound() {
    let mut s = px4_scenario(Px4Config::sitl_lockstep());
    let codes = photos_every_10_s(&mut s, 20 * S, 125 * S);
    let (valid, lost) = utc_losses(&s);
    let failed = codes.iter().filter(|c| **c != AckCode::Ok).count();
    println!(
        "PX4 SITL lockstep: UTC valid at {valid:?} us, lost {lost} times after; {failed} of {} geotags failed",
        codes.len()
    );
    let valid = valid.expect("UTC valid");
    assert!(valid < 5 * S, "UTC valid at {} ms", valid / 1000);
    assert_eq!(lost, 0, "UTC lost after it became valid");
    assert!(codes.len() >= 10);
    assert!(codes.iter().all(|c| *c == AckCode::Ok), "{codes:?}");
    // Every edge synced, against the UTC PX4 reports (the host's).
    one_sync_per_edge(&s);
    let errors = sync_errors_us(&s, 10 * S);
    assert!(errors.len() >= 10, "{}", errors.len());
    let abs = figures("PX4 SITL lockstep (boot clock 1.2 % slow)", &errors);
    assert!(abs[abs.len() - 1] < 3_000, "max {} us", abs[abs.len() - 1]);
}

mod px4_capture;

use bridge_engine::{Config, FcProtocol};
use gimbal::sim::line::Line;
use gimbal::sim::pod::SimPod;
use px4_capture::{Capture, CapturedPx4, LINE_BAUD};

/// One time sync of a replay, against PX4's UTC.
#[derive(Debug, Clone, Copy)]
struct Checked {
    /// The edge, true µs (the capture's bridge clock).
    edge_us: u64,
    /// The UTC the pod was given minus PX4's at the edge, µs.
    error_us: f64,
    /// The bound the bridge believed, µs.
    bound_us: u32,
}

/// What a replay of the capture gave.
struct Replayed {
    s: Scenario<CapturedPx4>,
    valid_us: Vec<u64>,
    lost_us: Vec<u64>,
    syncs: Vec<Checked>,
}

/// The capture replayed through the engine (docs: `px4_capture`), configured as the
/// captured bridge was, its lines as fast as the capture's pseudo-terminal.
fn replay() -> Replayed {
    let capture = Capture::load();
    let end = capture.rx.last().expect("frames").t_us + 500_000;
    let config = Config::for_fc(FcProtocol::Mavlink);
    assert_eq!(config.fc_baud, 115_200, "as the captured bridge");
    let mut s = Scenario::new(
        config,
        CapturedPx4::new(capture),
        SimPod::new(PodSimConfig::default()),
        0,
    );
    s.fc_line = Line::new(LINE_BAUD);
    s.to_fc_line = Line::new(LINE_BAUD);
    s.run_until(end);
    let at = |e: &(u64, Event)| e.0;
    let valid_us = s
        .events_where(|e| matches!(e, Event::UtcValid { .. }))
        .iter()
        .map(at)
        .collect();
    let lost_us = s
        .events_where(|e| matches!(e, Event::UtcLost))
        .iter()
        .map(at)
        .collect();
    let capture = s.fc.capture();
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
                let truth = capture.reference_utc_us(edge_us as f64);
                Some(Checked {
                    edge_us,
                    error_us: (utc_ms * 1000) as f64 - truth,
                    bound_us: error_bound_us,
                })
            }
            _ => None,
        })
        .collect();
    // Every one of them applied by the pod, at its edge.
    let applied = s.pod.syncs();
    assert_eq!(applied.len(), syncs.len());
    for (a, c) in applied.iter().zip(&syncs) {
        assert_eq!(a.outcome, gimbal::sim::pod::SyncOutcome::Applied, "{a:?}");
        assert_eq!(a.edge_us, Some(c.edge_us));
    }
    Replayed {
        s,
        valid_us,
        lost_us,
        syncs,
    }
}

/// The capture of a real PX4 SITL in lockstep through the engine: UTC valid within a
/// second and never lost while PX4 sends time, every sync's bound at least its error
/// against PX4's own UTC, every stamp within 5 ms of it.
#[test]
fn the_captured_px4_sitl_keeps_utc_and_honest_bounds() {
    let r = replay();
    let first = *r.valid_us.first().expect("UTC valid");
    println!(
        "replay: UTC valid at {:.3} s, lost {} times ({:?}), {} TIMESYNC answered, {} syncs",
        first as f64 / 1e6,
        r.lost_us.len(),
        r.lost_us.iter().map(|t| *t as f64 / 1e6).collect::<Vec<_>>(),
        r.s.fc.answers.len(),
        r.syncs.len()
    );
    for c in &r.syncs {
        println!(
            "  edge {:8.3} s: error {:+8.0} us, bound {:6} us",
            c.edge_us as f64 / 1e6,
            c.error_us,
            c.bound_us
        );
    }
    let dishonest: Vec<&Checked> = r
        .syncs
        .iter()
        .filter(|c| c.error_us.abs() > f64::from(c.bound_us))
        .collect();
    assert!(r.lost_us.is_empty(), "UTC lost at {:?} us", r.lost_us);
    assert!(dishonest.is_empty(), "bound under the error: {dishonest:?}");
    // One sync per 10 s edge of the capture's 150 s from the first after UTC was valid.
    assert!(r.syncs.len() >= 14, "{} syncs", r.syncs.len());
    let errors: Vec<i64> = r.syncs.iter().map(|c| c.error_us.round() as i64).collect();
    let abs = figures("replay of the PX4 SITL capture", &errors);
    assert!(abs[abs.len() - 1] <= 5_000, "max {} us", abs[abs.len() - 1]);
}
