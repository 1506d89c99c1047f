//! The first time sync, for every FC side, through the whole engine (simulated ArduPilot
//! driver or K40T FC, simulated pod, serial lines at 115200 baud): it goes out on the
//! first 10 s UTC grid edge after the FC's first usable UTC (within 12 s of it), and the
//! UTC it carries is within 10 ms of the FC's at the edge (GCU: its GPS time is held
//! between fixes and read on a 20 ms loop, so within the same ±10 ms plus jitter as in
//! steady state, 15 ms). Eight flights per side, FC and bridge crystals up to ±25 ppm,
//! different boot phases. Run with `--nocapture` for the figures.

use bridge_engine::{Config, Event, Level};
use gimbal::sim::Autopilot;
use gimbal::sim::ap_siyi::{ApSiyi, ApSiyiConfig};
use gimbal::sim::ap_viewpro::{ApViewpro, ApViewproConfig};
use gimbal::sim::ap_xfrobot::{ApXfRobot, ApXfRobotConfig};
use gimbal::sim::fc_k40t::FcK40t;
use gimbal::sim::pilot::Pilot;
use gimbal::sim::pod::{PodSimConfig, SimPod, SyncOutcome};
use gimbal::sim::scenario::Scenario;

const S: u64 = 1_000_000;

/// (seed, FC ppm, bridge ppm).
const FLIGHTS: [(u64, f64, i64); 8] = [
    (31, 25.0, -25),
    (32, -25.0, 25),
    (33, 10.0, 0),
    (34, -5.0, 15),
    (35, 0.0, -10),
    (36, 20.0, 20),
    (37, -15.0, -5),
    (38, 5.0, 25),
];

/// A UTC phase against the 10 s grid for a flight, µs (0..10 s).
fn phase(seed: u64) -> u64 {
    seed * 1_234_567 % 10_000_000
}

/// One flight's first sync: (delay from the FC's first UTC to the edge, µs; its error,
/// µs; the bound the engine believed, µs).
fn first_sync<P: Pilot>(fc: P, bridge_ppm: i64) -> (u64, i64, u32) {
    let mut s = Scenario::new(
        Config::for_fc(P::PROTOCOL),
        fc,
        SimPod::new(PodSimConfig::default()),
        bridge_ppm,
    );
    s.run_until(30 * S);
    let first_utc = s.fc.first_utc_sent_us().expect("the FC sent UTC");
    let edge = s
        .pin_edges
        .iter()
        .find(|e| e.level == Level::High)
        .expect("a sync within 30 s")
        .at_us;
    let sync = &s.pod.syncs()[0];
    assert_eq!(sync.edge_us, Some(edge));
    assert_eq!(sync.outcome, SyncOutcome::Applied);
    let err = (sync.unix_ms * 1000) as i64 - s.fc.true_utc_us(edge) as i64;
    let bound = s
        .events
        .iter()
        .find_map(|(_, e)| match e {
            Event::TimeSync { error_bound_us, .. } => Some(*error_bound_us),
            _ => None,
        })
        .expect("a time_sync event");
    (edge - first_utc, err, bound)
}

fn check(label: &str, results: &[(u64, i64, u32)], max_err_us: u64) {
    let mut errs: Vec<u64> = results.iter().map(|r| r.1.unsigned_abs()).collect();
    errs.sort_unstable();
    let delays: Vec<u64> = results.iter().map(|r| r.0).collect();
    println!(
        "{label}: first sync {:.1}..{:.1} s after the FC's first UTC; |error| p50 {} µs, max {} µs; bound believed {}..{} µs",
        *delays.iter().min().unwrap() as f64 / 1e6,
        *delays.iter().max().unwrap() as f64 / 1e6,
        errs[errs.len() / 2],
        errs[errs.len() - 1],
        results.iter().map(|r| r.2).min().unwrap(),
        results.iter().map(|r| r.2).max().unwrap(),
    );
    for &(delay, err, bound) in results {
        assert!(
            delay <= 12 * S,
            "{label}: first sync {delay} µs after the FC's UTC"
        );
        assert!(err.unsigned_abs() < max_err_us, "{label}: error {err} µs");
        assert!(
            err.unsigned_abs() <= u64::from(bound),
            "{label}: error {err} µs beyond the bound believed, {bound} µs"
        );
    }
}

#[test]
fn siyi() {
    let r: Vec<_> = FLIGHTS
        .iter()
        .map(|&(seed, ppm, bridge)| {
            let fc = ApSiyi::new(ApSiyiConfig {
                ppm,
                seed,
                boot_us: 3_000_000 + seed * 7_777,
                utc_at_zero_us: ApSiyiConfig::default().utc_at_zero_us + phase(seed),
                ..ApSiyiConfig::default()
            });
            first_sync(fc, bridge)
        })
        .collect();
    check("siyi", &r, 10_000);
}

#[test]
fn viewlink() {
    let r: Vec<_> = FLIGHTS
        .iter()
        .map(|&(seed, ppm, bridge)| {
            let fc = ApViewpro::new(ApViewproConfig {
                ppm,
                seed,
                boot_us: 3_000_000 + seed * 7_777,
                utc_at_zero_us: ApViewproConfig::default().utc_at_zero_us + phase(seed),
                ..ApViewproConfig::default()
            });
            first_sync(fc, bridge)
        })
        .collect();
    check("viewlink", &r, 10_000);
}

#[test]
fn gcu() {
    let r: Vec<_> = FLIGHTS
        .iter()
        .map(|&(seed, ppm, bridge)| {
            let fc = ApXfRobot::new(ApXfRobotConfig {
                ppm,
                seed,
                boot_us: 3_000_000 + seed * 7_777,
                gps_hz: if seed % 2 == 0 { 5 } else { 10 },
                ..ApXfRobotConfig::default()
            });
            first_sync(fc, bridge)
        })
        .collect();
    check("gcu", &r, 15_000);
}

#[test]
fn k40t() {
    let r: Vec<_> = FLIGHTS
        .iter()
        .map(|&(seed, _, bridge)| {
            let fc = FcK40t::new(FcK40t::default().fc_utc_us(0) + phase(seed));
            first_sync(fc, bridge)
        })
        .collect();
    check("k40t", &r, 10_000);
}
