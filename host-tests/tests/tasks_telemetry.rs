//! The MAVLink telemetry link through the firmware's own tasks (bridge-fw on the host,
//! virtual time, pipes as UARTs): one simulated ArduPilot on two of its ports, the SIYI
//! driver on the FC link and a MAVLink 2 port (`SERIALn_PROTOCOL 2`, no MAVLink mount or
//! camera) on the telemetry link, the simulated pod on the pod link. Both simulators share
//! the autopilot's crystal, boot and clock, so the two links tell one time.

use bridge_fw::LogKind;
use gimbal::sim::ap_mavlink::ApMavlink;
use gimbal::sim::ap_siyi::{ApSiyi, ApSiyiConfig};
use gimbal::sim::pod::{PodSimConfig, SimPod, SyncOutcome};
use gimbal::sim::tasks::{Bench, Outcome};
use protocol_core::bridge::{Config, Event, FcProtocol};
use protocol_core::k40t::AckCode;

const S: u64 = 1_000_000;
const TICK: u64 = 10_000;
/// The bridge's component on the telemetry link (MAV_COMP_ID_PERIPHERAL).
const BRIDGE_COMPONENT: u8 = 158;
const HEARTBEAT: u32 = 0;
const TIMESYNC: u32 = 111;

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
    let peer = telemetry.then(|| ApMavlink::telemetry(fc.clock().clone(), fc.aircraft, 4, 1));
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
            .any(|(_, e)| matches!(e, Event::Geotag { answered: true, .. }))
    );
    assert!(o.fc.healthy(), "{:?}", o.fc.health_log);
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
