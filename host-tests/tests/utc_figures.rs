//! UTC at the RTC_IO edge through the firmware's tasks (virtual time, pipes), per FC
//! side, with and without a MAVLink telemetry link: the first sync's delay after the
//! autopilot's first valid UTC and its error, and the steady-state error (p50, p99,
//! max). The simulated autopilots follow docs/src/autopilots/ardupilot.md and
//! docs/src/autopilots/px4.md (ArduPilot's 400 Hz loop on its IMU, TIMESYNC answered
//! from the UART's receive-time estimate, SYSTEM_TIME read in one call); FC crystals
//! ±25 ppm against the bridge's, serial jitter 0–10 ms per burst. The error is the
//! UTC the pod was given for an edge minus the autopilot's own UTC at that edge (the
//! bridge cannot be better than the autopilot's clock). Run with `--nocapture` for the
//! figures (docs/src/figures.md).
//!
//! Required (issue "Sub-millisecond UTC"): with MAVLink time (the MAVLink side, or a
//! telemetry link) p99 < 1 ms and max < 2 ms in steady state, the first sync within
//! 12 s of the autopilot's first valid SYSTEM_TIME with an error under 5 ms; with PX4
//! SITL in lockstep (issue 33) within 5 ms of PX4's UTC. Each row's bounds are those or
//! about three times what the row measured, whichever is tighter (measured and bound side
//! by side at each row).

use bridge_engine::Config;
use gimbal::sim::Autopilot;
use gimbal::sim::ap_mavlink::{ApMavlink, ApMavlinkConfig};
use gimbal::sim::ap_siyi::{ApSiyi, ApSiyiConfig};
use gimbal::sim::ap_viewpro::{ApViewpro, ApViewproConfig};
use gimbal::sim::ap_xfrobot::{ApXfRobot, ApXfRobotConfig};
use gimbal::sim::pilot::Pilot;
use gimbal::sim::pod::{PodSimConfig, SimPod, SyncOutcome};
use gimbal::sim::px4::{Px4, Px4Config, Px4Mode};
use gimbal::sim::tasks::{Bench, Outcome};

use crate::spread;
use spread::{abs_spread, range};

const S: u64 = 1_000_000;
/// Steady state: syncs from this instant on (the fit converges about 32 s after the
/// first samples).
const STEADY_FROM: u64 = 90 * S;
/// Length of each flight.
const FLIGHT: u64 = 330 * S;

/// (seed, FC ppm, UTC phase against the 10 s grid µs, when the FC's UTC becomes valid).
const FLIGHTS: [(u64, f64, u64, u64); 6] = [
    (41, 25.0, 3_217_000, 20 * S),
    (42, -25.0, 7_901_234, 25 * S),
    (43, 10.0, 123_456, 21 * S),
    (44, -15.0, 5_555_555, 30 * S),
    (45, 0.0, 9_876_543, 22 * S),
    (46, 20.0, 1_010_101, 27 * S),
];

/// What one flight gave.
#[derive(Debug, Default)]
struct Flight {
    /// From the FC's first valid UTC to the first edge, µs.
    first_delay_us: u64,
    /// The first sync's error, µs.
    first_error_us: i64,
    /// Steady-state errors, µs.
    steady_us: Vec<i64>,
}

/// The syncs' errors of a run against the FC's UTC (with a telemetry link: the UTC of
/// the autopilot's MAVLink port, what that link gives).
fn flight<P: Pilot>(out: &Outcome<P, ApMavlink>) -> Flight {
    let (first_utc, truth): (u64, Box<dyn Fn(u64) -> u64 + '_>) = match &out.telemetry {
        Some(t) => (
            t.first_utc_sent_us().expect("the autopilot sent UTC"),
            Box::new(|e| t.fc_utc_us(e)),
        ),
        None => (
            out.fc.first_utc_sent_us().expect("the FC sent UTC"),
            Box::new(|e| out.fc.true_utc_us(e)),
        ),
    };
    let mut f = Flight::default();
    for (i, sync) in out.pod.syncs().iter().enumerate() {
        assert_eq!(sync.outcome, SyncOutcome::Applied, "{sync:?}");
        let edge = sync.edge_us.expect("edge before frame");
        let err = i64::try_from(sync.unix_ms * 1000).unwrap() - i64::try_from(truth(edge)).unwrap();
        if i == 0 {
            f.first_delay_us = edge.saturating_sub(first_utc);
            f.first_error_us = err;
        }
        if edge >= STEADY_FROM {
            f.steady_us.push(err);
        }
    }
    f
}

/// Prints and checks a side's flights.
fn report(label: &str, flights: &[Flight], p99_max_us: i64, max_us: i64, first_max_us: i64) {
    let all: Vec<i64> = flights.iter().flat_map(|f| f.steady_us.clone()).collect();
    let s = abs_spread(&all).expect("syncs");
    assert!(s.count > 100, "{label}: {} syncs", s.count);
    let (delay_min, delay_max) = range(flights.iter().map(|f| f.first_delay_us as f64 / 1e6));
    let firsts: Vec<i64> = flights.iter().map(|f| f.first_error_us).collect();
    println!(
        "{label}: steady |error| p50 {:.2} ms, p99 {:.2} ms, max {:.2} ms over {} syncs; \
         first sync {delay_min:.1}–{delay_max:.1} s after the first UTC, error {firsts:?} µs",
        s.p50 as f64 / 1e3,
        s.p99 as f64 / 1e3,
        s.max as f64 / 1e3,
        s.count,
    );
    assert!(s.p99 < p99_max_us, "{label}: p99 {} µs", s.p99);
    assert!(s.max < max_us, "{label}: max {} µs", s.max);
    for f in flights {
        // Measured 8.9 s at most (the 10 s grid's phase); required 12 s.
        assert!(
            f.first_delay_us <= 12 * S,
            "{label}: first sync after {f:?}"
        );
        assert!(
            f.first_error_us.abs() < first_max_us,
            "{label}: first sync {f:?}"
        );
    }
}

fn ap_mavlink(seed: u64, ppm: f64, phase_us: u64, utc_valid_at_us: u64) -> ApMavlinkConfig {
    ApMavlinkConfig {
        seed,
        ppm,
        jitter_us: 10_000,
        // 2026-11-23T10:00:00Z plus the flight's phase against the 10 s grid.
        utc_at_zero_us: 1_795_428_000_000_000 + phase_us,
        utc_valid_at_us,
        ..ApMavlinkConfig::default()
    }
}

#[test]
fn mavlink_side_with_ardupilot() {
    let flights: Vec<Flight> = FLIGHTS
        .iter()
        .map(|&(seed, ppm, phase, valid)| {
            let ap = ApMavlink::new(ap_mavlink(seed, ppm, phase, valid));
            let config = Config::for_fc(ApMavlink::PROTOCOL);
            let pod = SimPod::new(PodSimConfig::default());
            let bench = Bench::<ApMavlink, ApMavlink>::of(config, ap, pod, None);
            let out = bench.run(FLIGHT, S, |_, _| {});
            flight(&out)
        })
        .collect();
    // Measured p99 280 µs, max 340 µs, first |error| 554 µs; bounds 840, 1 020, 1 700.
    report("mavlink (ArduPilot)", &flights, 840, 1_020, 1_700);
}

/// The flights of a PX4 on the MAVLink side, each configured by `config` from the
/// flight's (seed, FC ppm, UTC phase, UTC valid at).
fn px4_flights(config: impl Fn(u64, f64, u64, u64) -> Px4Config) -> Vec<Flight> {
    FLIGHTS
        .iter()
        .map(|&(seed, ppm, phase, valid)| {
            let px4 = Px4::new(config(seed, ppm, utc_at_zero(phase), valid));
            let pod = SimPod::new(PodSimConfig::default());
            let bench = Bench::<Px4, ApMavlink>::of(Config::for_fc(Px4::PROTOCOL), px4, pod, None);
            flight(&bench.run(FLIGHT, S, |_, _| {}))
        })
        .collect()
}

#[test]
fn mavlink_side_with_px4() {
    let flights = px4_flights(|seed, ppm, utc_at_zero_us, utc_valid_at_us| Px4Config {
        seed,
        ppm,
        jitter_us: 10_000,
        mode: Px4Mode::Normal,
        utc_at_zero_us,
        utc_valid_at_us,
        ..Px4Config::default()
    });
    // Measured p99 820 µs, max 830 µs, first |error| 451 µs; bounds 1 000 (required),
    // 2 000 (required), 1 360.
    report("mavlink (PX4, mode Normal)", &flights, 1_000, 2_000, 1_360);
}

/// PX4 SITL in lockstep (its clocks as a real one's capture shows them: boot clock in
/// 4 ms steps, 0.87 % slow against its UTC, the host's, wandering by tens of ms) on the
/// MAVLink side through a serial line: SYSTEM_TIME's UTC alone gives the time (the boot
/// clock is apart from UTC), timed by its arrival less its serial time. The error is
/// against PX4's UTC (the host's clock).
#[test]
fn mavlink_side_with_px4_sitl_in_lockstep() {
    let flights = px4_flights(|seed, _, utc_at_zero_us, utc_valid_at_us| Px4Config {
        seed,
        utc_at_zero_us,
        utc_valid_at_us,
        ..Px4Config::sitl_lockstep()
    });
    // Measured p99 22 µs, max 31 µs, first |error| 18 µs; bounds 66, 93, 54 (the
    // requirement: 5 ms).
    report("mavlink (PX4 SITL in lockstep)", &flights, 66, 93, 54);
}

/// The flights of ArduPilot with its SIYI, Viewpro or XFRobot mount driver, with the same
/// autopilot's MAVLink port on the telemetry link or without.
fn legacy<P: Pilot>(make: impl Fn(u64, f64, u64, u64) -> P, telemetry: bool) -> Vec<Flight> {
    FLIGHTS
        .iter()
        .map(|&(seed, ppm, phase, valid)| {
            let fc = make(seed, ppm, phase, valid);
            let peer = telemetry.then(|| {
                let clock = fc.board_clock().expect("an ArduPilot with a MAVLink port");
                let mut ap = ApMavlink::telemetry(clock.clone(), *fc.aircraft(), seed + 100, 1);
                ap.config.jitter_us = 10_000;
                ap
            });
            let pod = SimPod::new(PodSimConfig::default());
            let bench = Bench::of(Config::for_fc(P::PROTOCOL), fc, pod, peer);
            flight(&bench.run(FLIGHT, S, |_, _| {}))
        })
        .collect()
}

/// 2026-11-23T10:00:00Z plus a flight's phase against the 10 s grid.
const fn utc_at_zero(phase_us: u64) -> u64 {
    1_795_428_000_000_000 + phase_us
}

fn siyi(seed: u64, ppm: f64, phase: u64, valid: u64) -> ApSiyi {
    ApSiyi::new(ApSiyiConfig {
        seed,
        ppm,
        jitter_us: 10_000,
        utc_at_zero_us: utc_at_zero(phase),
        utc_valid_at_us: valid,
        ..ApSiyiConfig::default()
    })
}

fn viewpro(seed: u64, ppm: f64, phase: u64, valid: u64) -> ApViewpro {
    ApViewpro::new(ApViewproConfig {
        seed,
        ppm,
        jitter_us: 10_000,
        utc_at_zero_us: utc_at_zero(phase),
        utc_valid_at_us: valid,
        ..ApViewproConfig::default()
    })
}

fn xfrobot(seed: u64, ppm: f64, phase: u64, valid: u64) -> ApXfRobot {
    ApXfRobot::new(ApXfRobotConfig {
        seed,
        ppm,
        jitter_us: 10_000,
        utc_at_zero_us: utc_at_zero(phase),
        gps_valid_at_us: valid,
        ..ApXfRobotConfig::default()
    })
}

#[test]
fn siyi_with_telemetry() {
    let f = legacy(siyi, true);
    // Measured p99 280 µs, max 380 µs, first |error| 665 µs; bounds 840, 1 140, 2 000.
    report("SIYI + telemetry", &f, 840, 1_140, 2_000);
}

#[test]
fn viewlink_with_telemetry() {
    let f = legacy(viewpro, true);
    // Measured p99 280 µs, max 380 µs, first |error| 665 µs; bounds 840, 1 140, 2 000.
    report("Viewlink + telemetry", &f, 840, 1_140, 2_000);
}

#[test]
fn gcu_with_telemetry() {
    let f = legacy(xfrobot, true);
    // Measured p99 280 µs, max 380 µs, first |error| 665 µs; bounds 840, 1 140, 2 000.
    report("GCU + telemetry", &f, 840, 1_140, 2_000);
}

// Without the telemetry link: the legacy protocols' own time, as before (the bounds of
// docs/src/figures.md for these sides: what ArduPilot sends them is coarser).

#[test]
fn siyi_alone() {
    let f = legacy(siyi, false);
    // Measured p99 2.68 ms, max 2.69 ms, first |error| 2.55 ms; bounds 8.0, 8.07, 7.65.
    report("SIYI alone", &f, 8_000, 8_070, 7_650);
}

#[test]
fn viewlink_alone() {
    let f = legacy(viewpro, false);
    // Measured p99 4.92 ms, max 4.92 ms, first |error| 3.78 ms; bounds 8, 10, 10.
    report("Viewlink alone", &f, 8_000, 10_000, 10_000);
}

#[test]
fn gcu_alone() {
    let f = legacy(xfrobot, false);
    // Measured p99 11.37 ms, max 12.09 ms, first |error| 7.71 ms; bounds 15, 20, 15.
    report("GCU alone", &f, 15_000, 20_000, 15_000);
}
