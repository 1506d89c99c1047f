//! The MAVLink telemetry link through the firmware's own tasks (bridge-fw on the host,
//! virtual time, pipes as UARTs): one simulated ArduPilot on two of its ports, the SIYI
//! driver on the FC link and a MAVLink 2 port (`SERIALn_PROTOCOL 2`, no MAVLink mount or
//! camera) on the telemetry link, the simulated pod on the pod link. Both simulators share
//! the autopilot's crystal, boot and clock, so the two links tell one time.

use bridge_engine::{Config, Event, FcProtocol};
use bridge_fw::LogKind;
use gimbal::sim::Autopilot;
use gimbal::sim::ap_mavlink::ApMavlink;
use gimbal::sim::ap_siyi::{ApSiyi, ApSiyiConfig};
use gimbal::sim::pilot::Pilot;
use gimbal::sim::pod::{PodSimConfig, SimPod, SyncOutcome};
use gimbal::sim::tasks::{Bench, Cable, Outcome};
use protocol_core::k40t::AckCode;

const S: u64 = 1_000_000;
const TICK: u64 = 10_000;
/// The bridge's component on the telemetry link (MAV_COMP_ID_PERIPHERAL).
const BRIDGE_COMPONENT: u8 = 158;
const HEARTBEAT: u32 = 0;
const TIMESYNC: u32 = 111;
const CAMERA_IMAGE_CAPTURED: u32 = 263;

/// The SIYI port's settings.
fn autopilot() -> ApSiyiConfig {
    ApSiyiConfig {
        ppm: 25.0,
        seed: 3,
        ..ApSiyiConfig::default()
    }
}

/// 75 s of the bridge with or without the telemetry port; a photo at 65 s.
fn run(telemetry: bool) -> Outcome<ApSiyi, ApMavlink> {
    let config = Config::for_fc(FcProtocol::Siyi);
    let pod = SimPod::new(PodSimConfig::default());
    let fc = ApSiyi::new(autopilot());
    // The same autopilot's MAVLink port: its clock and aircraft.
    let peer = telemetry.then(|| ApMavlink::telemetry(fc.clock().clone(), *fc.aircraft(), 4, 1));
    let bench = Bench::of(config, fc, pod, peer);
    bench.wires.record_all();
    bench.run(75 * S, TICK, |b, t| {
        if t == 65 * S {
            b.fc.borrow_mut().take_picture();
        }
    })
}

/// Time syncs applied on the UTC grid within 10 ms of the autopilot's UTC at the edge,
/// and the photo geotagged.
fn syncs_and_geotag(o: &Outcome<ApSiyi, ApMavlink>) {
    let syncs = o.pod.syncs();
    assert!(syncs.len() >= 2, "{syncs:?}");
    for s in syncs {
        assert_eq!(s.outcome, SyncOutcome::Applied, "{s:?}");
        assert_eq!(s.unix_ms % 10_000, 0);
        let truth = o.fc.fc_utc_us(s.edge_us.expect("edge"));
        assert!(
            (s.unix_ms * 1000).abs_diff(truth) < 10_000,
            "{s:?} vs {truth}"
        );
    }
    assert_eq!(o.pod.photos().len(), 1);
    let reply = o.pod.gps_replies().last().expect("a GPS reply");
    assert_eq!(reply.reply.code.code(), AckCode::Ok);
    assert!(
        o.events()
            .any(|(_, e)| matches!(e, Event::Geotag { missed: None, .. }))
    );
    assert!(o.fc.healthy(), "{:?}", o.fc.health_log());
    assert_eq!(o.records_dropped, 0);
    // The watchdog task saw every supervised loop (the telemetry link's too) run.
    assert!(
        !o.records
            .iter()
            .any(|r| matches!(r.what, LogKind::Stalled(_)))
    );
}

#[test]
fn the_telemetry_link_comes_up_and_becomes_the_time_source() {
    let o = run(true);
    let c = o.engine.counters();
    assert!(c.telemetry_frames > 0 && c.telemetry_sent > 0, "{c:?}");
    let sources: Vec<_> = o
        .events()
        .filter(|(_, e)| matches!(e, Event::TimeSource { .. }))
        .collect();
    assert!(
        sources.contains(&(sources[0].0, Event::TimeSource { telemetry: true })),
        "{sources:?}"
    );
    assert_eq!(
        sources.last().map(|(_, e)| *e),
        Some(Event::TimeSource { telemetry: true }),
        "the telemetry link stays the source: {sources:?}"
    );
    // The autopilot hears the bridge's HEARTBEAT (component 158) after its own, and
    // its TIMESYNC requests.
    let ap = o.telemetry.as_ref().expect("the telemetry peer");
    let from_bridge = |id: u32| {
        ap.received
            .iter()
            .filter(move |(_, h, i)| h.component_id == BRIDGE_COMPONENT && *i == id)
    };
    let first_hb = from_bridge(HEARTBEAT).next().expect("a bridge HEARTBEAT").0;
    assert!(from_bridge(HEARTBEAT).count() >= 60, "1 Hz for 75 s");
    let ap_first_hb = o.wires.tel_in.log.first().expect("autopilot bytes").0;
    assert!(ap_first_hb < first_hb);
    assert!(from_bridge(TIMESYNC).count() > 0, "TIMESYNC requests");
    assert!(o.wires.tel_out.bytes > 1_000 && o.wires.tel_in.bytes > 1_000);
    // The photo, as the autopilot can forward and log it: one CAMERA_IMAGE_CAPTURED
    // after the engine's photo event.
    let photo_at = o
        .events()
        .find_map(|(t, e)| matches!(e, Event::Photo(_)).then_some(t))
        .expect("a photo event");
    let captured: Vec<u64> = from_bridge(CAMERA_IMAGE_CAPTURED)
        .map(|(t, _, _)| *t)
        .collect();
    assert_eq!(captured.len(), 1, "{captured:?}");
    assert!(captured[0] >= photo_at && captured[0] < photo_at + S);
    syncs_and_geotag(&o);
}

#[test]
fn without_the_telemetry_peer_nothing_changes() {
    let o = run(false);
    assert!(o.telemetry.is_none());
    let c = o.engine.counters();
    assert_eq!((c.telemetry_frames, c.telemetry_sent), (0, 0), "{c:?}");
    assert!(
        !o.events()
            .any(|(_, e)| matches!(e, Event::TimeSource { .. }))
    );
    assert_eq!((o.wires.tel_in.bytes, o.wires.tel_out.bytes), (0, 0));
    syncs_and_geotag(&o);
}

/// The autopilot's MAVLink port says its GPS has no 3D fix (GPS_RAW_INT), while it still
/// sends positions: the history gets no fix from it, and the SIYI link's positions are
/// not used while the telemetry link is the source. The photo's geotag is the failure
/// code (nothing invented); the time still comes.
#[test]
fn without_a_3d_fix_on_the_telemetry_link_the_geotag_is_the_failure_code() {
    let config = Config::for_fc(FcProtocol::Siyi);
    let pod = SimPod::new(PodSimConfig::default());
    let fc = ApSiyi::new(autopilot());
    let mut peer = ApMavlink::telemetry(fc.clock().clone(), *fc.aircraft(), 4, 1);
    peer.config.gps_fix = false;
    let bench = Bench::of(config, fc, pod, Some(peer));
    let o = bench.run(75 * S, TICK, |b, t| {
        if t == 65 * S {
            b.fc.borrow_mut().take_picture();
        }
    });
    assert!(
        o.events()
            .any(|(_, e)| e == Event::TimeSource { telemetry: true })
    );
    assert!(o.pod.syncs().len() >= 2);
    assert_eq!(o.pod.photos().len(), 1);
    let reply = o.pod.gps_replies().last().expect("a GPS reply");
    assert_ne!(reply.reply.code.code(), AckCode::Ok, "{reply:?}");
    assert_eq!((reply.reply.lat_e7, reply.reply.lon_e7), (0, 0));
}

/// The telemetry cable is pulled for 20 s: after 3 s without SYSTEM_TIME the FC link is
/// the source again (its own time, the discipline restarted, the mapping in holdover
/// meanwhile); back, the telemetry link is the source again. No sync is wrong by more
/// than the SIYI link's own accuracy, and none is skipped.
#[test]
fn a_pulled_telemetry_cable_gives_time_back_to_the_fc_link_and_takes_it_again() {
    let config = Config::for_fc(FcProtocol::Siyi);
    let pod = SimPod::new(PodSimConfig::default());
    let fc = ApSiyi::new(autopilot());
    let peer = ApMavlink::telemetry(fc.clock().clone(), *fc.aircraft(), 4, 1);
    let bench = Bench::of(config, fc, pod, Some(peer));
    let o = bench.run(120 * S, TICK, |b, t| {
        if t == 40 * S {
            b.wires.pull(Cable::Telemetry, t, 20 * S);
        }
    });
    let sources: Vec<(u64, Event)> = o
        .events()
        .filter(|(_, e)| matches!(e, Event::TimeSource { .. }))
        .collect();
    let to = |telemetry| Event::TimeSource { telemetry };
    assert_eq!(sources.len(), 3, "{sources:?}");
    assert_eq!(sources[0].1, to(true));
    assert_eq!(sources[1].1, to(false));
    assert!((42 * S..45 * S).contains(&sources[1].0), "{sources:?}");
    assert_eq!(sources[2].1, to(true));
    assert!((60 * S..63 * S).contains(&sources[2].0), "{sources:?}");
    let syncs = o.pod.syncs();
    // One sync every 10 s from the first: none skipped across both changes.
    assert!(syncs.len() >= 11, "{syncs:?}");
    for s in syncs {
        assert_eq!(s.outcome, SyncOutcome::Applied, "{s:?}");
        let truth = o.fc.fc_utc_us(s.edge_us.expect("edge"));
        assert!(
            (s.unix_ms * 1000).abs_diff(truth) < 10_000,
            "{s:?} vs {truth}"
        );
    }
}
