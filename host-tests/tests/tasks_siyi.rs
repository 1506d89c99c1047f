//! The firmware's own tasks (bridge-fw, on the host under virtual time) between the
//! simulated ArduPilot SIYI driver and the simulated pod, connected by pipes: what the
//! engine scenarios check, through the task code that runs on the MCU. The shared
//! scenarios (start-up, commands and telemetry, sync and geotag, FC silence, pod loss,
//! garbage) are in `task_scenarios/mod.rs`.

use core::cell::RefCell;

use bridge_engine::{Config, Engine, Event, FcProtocol, Level};
use bridge_fw::host::{self, Clock, HostLinks, HostShared};
use bridge_fw::{LogKind, LogRecord, Timing};
use embassy_futures::select::{Either3, select, select3};
use embassy_time::{Duration, Timer};
use gimbal::sim::Autopilot;
use gimbal::sim::ap_siyi::{ApSiyi, ApSiyiConfig, MountTarget};
use gimbal::sim::peer::{PodPin, run_peer};
use gimbal::sim::pilot::Pilot;
use gimbal::sim::pod::{PodSimConfig, SimPod, SyncOutcome};
use task_scenarios::{Bounds, S};

use crate::task_scenarios;

struct Run {
    fc: ApSiyi,
    pod: SimPod,
    records: Vec<LogRecord>,
}

/// Runs the bridge tasks for `secs` of virtual time; `script` acts on the FC at given
/// seconds.
fn run(secs: u64, mut script: impl FnMut(u64, &mut ApSiyi)) -> Run {
    let config = Config::for_fc(FcProtocol::Siyi);
    let shared = HostShared::new(Engine::new(config), Timing::from_config(&config));
    let links = HostLinks::new();
    let fc = RefCell::new(ApSiyi::new(ApSiyiConfig::default()));
    let pod = RefCell::new(SimPod::new(PodSimConfig::default()));
    let records = RefCell::new(Vec::new());
    host::run(Clock::Virtual, || async {
        let sink = |r: &LogRecord| records.borrow_mut().push(*r);
        let bridge = host::bridge(&shared, &links, PodPin::new(&pod), sink, || {});
        let peers = select(
            run_peer(&fc, &links.fc_tx, &links.fc_rx, config.fc_baud),
            run_peer(&pod, &links.pod_tx, &links.pod_rx, config.pod_baud),
        );
        let clock = async {
            for s in 0..secs {
                script(s, &mut fc.borrow_mut());
                Timer::after(Duration::from_secs(1)).await;
            }
        };
        match select3(bridge, peers, clock).await {
            Either3::First(never) => match never {},
            Either3::Second(ended) => panic!("a peer ended: {ended:?}"),
            Either3::Third(()) => {}
        }
    });
    Run {
        fc: fc.into_inner(),
        pod: pod.into_inner(),
        records: records.into_inner(),
    }
}

#[test]
fn ardupilot_is_healthy_commands_turn_the_pod_and_syncs_are_applied() {
    let r = run(75, |s, fc| {
        if s == 10 {
            fc.target = Some(MountTarget::Rate {
                yaw_dps: 20.0,
                pitch_dps: 0.0,
                yaw_is_ef: false,
            });
        }
        if s == 13 {
            fc.target = Some(MountTarget::Rate {
                yaw_dps: 0.0,
                pitch_dps: 0.0,
                yaw_is_ef: false,
            });
        }
        if s == 65 {
            fc.take_picture();
        }
    });
    // Healthy within the start-up, and stays so.
    assert!(r.fc.healthy(), "{:?}", r.fc.health_log());
    assert_eq!(r.fc.health_log().len(), 1);
    assert!(r.fc.health_log()[0].0 < 5_000_000);
    assert_eq!(r.fc.parse_errors(), 0);
    // The rate turned the pod, and it stopped.
    assert!(r.pod.motions().len() >= 2, "{:?}", r.pod.motions());
    assert_eq!(r.pod.gimbal().yaw_rate_dps, 0.0);
    let yaw = r.pod.gimbal().yaw_deg;
    assert!((40.0..=80.0).contains(&yaw.abs()), "yaw {yaw}");
    // Time syncs: one per 10 s once UTC is known, each applied, on the UTC grid, each
    // RTC_IO edge recorded by the pin task and followed by the 0x00030E.
    let syncs = r.pod.syncs();
    assert!(syncs.len() >= 2, "{syncs:?}");
    for s in syncs {
        assert_eq!(s.outcome, SyncOutcome::Applied, "{s:?}");
        assert_eq!(s.unix_ms % 10_000, 0);
        let truth = r.fc.fc_utc_us(s.edge_us.expect("edge"));
        assert!(
            (s.unix_ms * 1000).abs_diff(truth) < 10_000,
            "{s:?} vs {truth}"
        );
    }
    let highs = r
        .records
        .iter()
        .filter(|x| x.what == LogKind::Pin(Level::High))
        .count();
    assert_eq!(highs, syncs.len());
    let delays: Vec<u64> = r
        .records
        .iter()
        .filter_map(|x| match x.what {
            LogKind::EdgeToFrame { delay, len } => Some((delay.as_micros(), len)),
            _ => None,
        })
        .map(|(d, len)| {
            assert_eq!(len, 28, "the 0x00030E is the first frame after the edge");
            d
        })
        .collect();
    assert_eq!(delays.len(), syncs.len());
    // The photo is geotagged.
    assert_eq!(r.pod.photos().len(), 1);
    let reply = r.pod.gps_replies().last().expect("a GPS reply");
    assert_eq!(reply.reply.code.code(), protocol_core::k40t::AckCode::Ok);
    assert!(
        r.records
            .iter()
            .any(|x| matches!(x.what, LogKind::Engine(Event::Geotag { missed: None, .. })))
    );
}

const BOUNDS: Bounds = Bounds {
    healthy_within_us: 5 * S,
    sync_error_us: 5_000,
    unhealthy_after_pod_loss_us: 2_500_000,
    healthy_after_pod_back_us: 2 * S,
    silence_stop_event: true,
    bridge_geotags: true,
};

#[test]
fn startup_to_healthy() {
    task_scenarios::startup_to_healthy::<ApSiyi>(BOUNDS);
}

#[test]
fn commands_reach_the_pod_and_its_attitude_the_fc() {
    task_scenarios::commands_and_telemetry::<ApSiyi>();
}

#[test]
fn time_syncs_edge_then_frame_and_photos_geotagged() {
    task_scenarios::sync_and_geotag::<ApSiyi>(BOUNDS, "siyi");
}

#[test]
fn fc_silence_stops_the_pod_within_0_6_s() {
    let delay = task_scenarios::fc_silence_stops_motion::<ApSiyi>(BOUNDS);
    println!(
        "siyi: pod still {} ms after the FC cable was cut",
        delay / 1000
    );
}

#[test]
fn pod_loss_is_seen_as_a_lost_gimbal_then_recovery() {
    task_scenarios::pod_loss::<ApSiyi>(BOUNDS);
}

#[test]
fn garbage_on_both_lines_keeps_it_healthy() {
    task_scenarios::garbage_on_both_lines::<ApSiyi>();
}
