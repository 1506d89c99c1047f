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
