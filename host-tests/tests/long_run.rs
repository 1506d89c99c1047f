//! A long life, per FC side (docs/src/reliability.md): seven days of the bridge's
//! uptime in virtual time, a flight every four hours, faults between and during them,
//! through the engine-level scenario (simulated lines and clocks).
//!
//! Each four-hour cycle: the autopilot and the pod power on, the aircraft flies for
//! three minutes (the gimbal turning, a photo every 20 s), one fault in turn at its third
//! photo (the FC cable pulled for 5 s, the pod rebooted, the FC silent for 30 s, bit
//! errors on both lines for the flight's last 80 s), then both power off for the rest of
//! the cycle while the bridge runs on alone (the ground hours cost nothing to simulate;
//! the bridge's clock, counters and state live through them). Checked, per side against
//! bounds about 3 times the measured worst case: every time sync the bridge sent within
//! the side's bound of the FC's true UTC at its edge; every geotag the pod got OK where
//! the aircraft was; at most the side's bound of photos not geotagged; no time-out of a
//! request (a command to the pod unACKed after its tries, a GPS request of the pod
//! unanswered) outside a fault; no dropped event; the counters sane at the end. The wall
//! time, the simulated time and the figures are printed.

use crate::engine_scenarios;

use std::time::Instant as WallClock;

use bridge_engine::Event;
use gimbal::sim::FcReboot;
use gimbal::sim::ap_mavlink::ApMavlink;
use gimbal::sim::ap_siyi::ApSiyi;
use gimbal::sim::ap_viewpro::ApViewpro;
use gimbal::sim::ap_xfrobot::ApXfRobot;
use gimbal::sim::faults::Faults;
use gimbal::sim::fc_k40t::FcK40t;
use gimbal::sim::pilot::Pilot;
use gimbal::sim::pod::PodSimConfig;
use gimbal::sim::scenario::Scenario;
use protocol_core::k40t::AckCode;

use engine_scenarios::{S, scenario};

/// An hour, µs.
const HOUR: u64 = 3_600 * S;
/// Days of uptime.
const DAYS: u64 = 7;
/// A flight every this long.
const CYCLE: u64 = 4 * HOUR;
/// Each flight's length.
const FLIGHT: u64 = 180 * S;
/// A fault starts this far into each flight (its third photo).
const FAULT_AT: u64 = 80 * S;
/// A request may still time out this long after its fault ended (a photo's ACK wait, a
/// GPS request's time-out).
const FAULT_TAIL: u64 = 5 * S;

/// A side's bounds, about 3 times its measured worst case (the runs are deterministic:
/// the figures are the same on every run).
#[derive(Debug, Clone, Copy)]
struct Bounds {
    /// A time sync this far from the FC's true UTC is wrong.
    sync_us: i64,
    /// Photos not geotagged (a fault's) in the week, at most.
    missed_geotags: usize,
}

/// What one long run found.
#[derive(Debug, Default)]
struct Found {
    syncs: usize,
    worst_sync_us: i64,
    photos: usize,
    geotags_ok: usize,
    /// Commands to the pod that got no ACK after all their tries (`Event::PodTimeout`).
    pod_timeouts: usize,
    /// The pod's GPS requests that timed out unanswered.
    gps_unanswered: usize,
}

fn long_run<F: Pilot>(label: &str, seed: u64, bounds: Bounds) -> Found {
    let wall = WallClock::now();
    let mut s = scenario(F::with_seed(seed), PodSimConfig::default(), 18);
    let mut found = Found::default();
    for cycle in 0..DAYS * 24 * HOUR / CYCLE {
        let start = cycle * CYCLE;
        // Up, then UTC and the first syncs.
        s.run_until(start + 40 * S);
        s.fc.turn(8.0, 0.0);
        for shot in 0..6 {
            if shot == 2 {
                fault(&mut s, cycle);
            }
            s.fc.take_picture();
            s.run_for(20 * S);
        }
        s.set_fc_faults(None);
        s.set_pod_faults(None);
        s.fc.turn(0.0, 0.0);
        s.run_until(start + FLIGHT);
        // Both power off until the next flight; the bridge runs on alone.
        let now = s.now_us;
        let off = start + CYCLE - now - 2 * S;
        s.fc.reboot(
            now,
            FcReboot {
                off_us: off,
                ..FcReboot::default()
            },
        );
        s.pod.reboot(now, off);
        // Nothing reaches a powered-off FC: the line carries nothing either way (the
        // bridge still writes its MAVLink frames into it: they cost the run's time only).
        s.pull_fc_cable(off);
        s.run_until(start + CYCLE);
        check_flight(&s, &mut found, label, cycle, bounds);
        // The simulators' and the scenario's records of the cycle are checked: keep
        // the run's memory flat.
        s.events.clear();
        s.pin_edges.clear();
    }
    let c = s.engine.counters();
    println!(
        "{label}: {DAYS} days simulated in {:.1} s of wall time; {} syncs (worst {} us), {}/{} photos geotagged; {} pod time-outs, {} GPS requests unanswered, all in faults; {c:?}",
        wall.elapsed().as_secs_f64(),
        found.syncs,
        found.worst_sync_us,
        found.geotags_ok,
        found.photos,
        found.pod_timeouts,
        found.gps_unanswered
    );
    // Counters sane: every kind of traffic counted, nothing saturated, nothing lost.
    for n in [
        c.fc_frames,
        c.fc_sent,
        c.pod_frames,
        c.pod_sent,
        c.time_syncs,
    ] {
        assert!(n > 1_000 && n < u32::MAX / 2, "{c:?}");
    }
    assert_eq!(c.events_dropped, 0, "{c:?}");
    if F::PROTOCOL != bridge_engine::FcProtocol::K40t {
        // The bridge answered these (some answers lost on a noisy line); a K40T FC
        // answers the pod itself.
        assert!(c.geotags as usize >= found.geotags_ok, "{c:?}");
    }
    assert!(
        found.photos - found.geotags_ok <= bounds.missed_geotags,
        "{found:?}, {bounds:?}"
    );
    assert!(found.syncs >= 42 * 8, "{found:?}");
    found
}

/// One fault in turn, a third into the flight.
fn fault<F: Pilot>(s: &mut Scenario<F>, cycle: u64) {
    match cycle % 4 {
        0 => s.pull_fc_cable(5 * S),
        1 => {
            let now = s.now_us;
            s.pod.reboot(now, 3 * S);
        }
        2 => s.pull_fc_cable(30 * S),
        _ => {
            s.set_fc_faults(Some(Faults::bit_errors(2e-4, cycle)));
            s.set_pod_faults(Some(Faults::bit_errors(2e-4, cycle + 1)));
        }
    }
}

/// How long the cycle's fault lasts ([`fault`]).
fn fault_length(cycle: u64) -> u64 {
    match cycle % 4 {
        0 => 5 * S,
        1 => 3 * S,
        2 => 30 * S,
        // From the third photo to the flight's end.
        _ => 80 * S,
    }
}

/// The cycle's time syncs (every one the bridge sent, against the FC's true UTC at its
/// edge), geotags (every OK one where the aircraft was at the shot) and time-outs (each
/// within the cycle's fault).
fn check_flight<F: Pilot>(
    s: &Scenario<F>,
    found: &mut Found,
    label: &str,
    cycle: u64,
    bounds: Bounds,
) {
    let fault_from = cycle * CYCLE + FAULT_AT;
    let in_fault =
        |t: u64| (fault_from..=fault_from + fault_length(cycle) + FAULT_TAIL).contains(&t);
    for (t, e) in &s.events {
        if let Event::PodTimeout { base } = *e {
            assert!(
                in_fault(*t),
                "{label}, cycle {cycle}: 0x{base:04x} timed out at {t} us, outside the fault"
            );
            found.pod_timeouts += 1;
        }
        let Event::TimeSync { edge, utc_ms, .. } = *e else {
            continue;
        };
        let at = s.true_of(edge);
        let err = i64::try_from(utc_ms * 1000).unwrap() - s.fc.true_utc_us(at) as i64;
        assert!(
            err.abs() < bounds.sync_us,
            "{label}, cycle {cycle}: a sync {err} us off at {at} us"
        );
        found.syncs += 1;
        found.worst_sync_us = found.worst_sync_us.max(err.abs());
    }
    let asked = s.pod.gps_requests();
    let first = asked.partition_point(|r| r.at_us < cycle * CYCLE);
    for r in asked[first..].iter().filter(|r| r.timed_out) {
        assert!(
            in_fault(r.at_us),
            "{label}, cycle {cycle}: a GPS request at {} us unanswered, outside the fault",
            r.at_us
        );
        found.gps_unanswered += 1;
    }
    let photos = s.pod.photos();
    let from = photos.partition_point(|p| p.at_us < cycle * CYCLE);
    for p in &photos[from..] {
        found.photos += 1;
        let Some(r) = p
            .gps_request
            .and_then(|i| s.pod.gps_requests()[i].reply)
            .map(|i| &s.pod.gps_replies()[i])
        else {
            continue;
        };
        if r.reply.code.code() != AckCode::Ok {
            continue;
        }
        let (lat, lon) = s.fc.aircraft().position_e7(p.at_us);
        assert!(
            (r.reply.lat_e7 - lat).abs() < 70 && (r.reply.lon_e7 - lon).abs() < 70,
            "{label}, cycle {cycle}: a geotag at ({}, {}) for ({lat}, {lon})",
            r.reply.lat_e7,
            r.reply.lon_e7
        );
        assert!(r.time_matches);
        found.geotags_ok += 1;
    }
}

// Measured (deterministic runs): worst sync 5.4 ms, 1 photo of 202 not geotagged.
#[test]
fn seven_days_siyi() {
    long_run::<ApSiyi>(
        "SIYI",
        1,
        Bounds {
            sync_us: 16_000,
            missed_geotags: 3,
        },
    );
}

// Measured: worst sync 2.0 ms, 1 of 203 not geotagged.
#[test]
fn seven_days_viewlink() {
    long_run::<ApViewpro>(
        "Viewlink",
        2,
        Bounds {
            sync_us: 6_000,
            missed_geotags: 3,
        },
    );
}

// Measured: worst sync 7.0 ms, 5 of 199 not geotagged.
#[test]
fn seven_days_gcu() {
    long_run::<ApXfRobot>(
        "GCU",
        3,
        Bounds {
            sync_us: 21_000,
            missed_geotags: 15,
        },
    );
}

// Measured: worst sync 0.74 ms, 6 of 202 not geotagged.
#[test]
fn seven_days_k40t() {
    long_run::<FcK40t>(
        "K40T",
        4,
        Bounds {
            sync_us: 2_200,
            missed_geotags: 18,
        },
    );
}

// Measured: worst sync 0.28 ms, 1 of 204 not geotagged.
#[test]
fn seven_days_mavlink() {
    long_run::<ApMavlink>(
        "MAVLink",
        5,
        Bounds {
            sync_us: 850,
            missed_geotags: 3,
        },
    );
}
