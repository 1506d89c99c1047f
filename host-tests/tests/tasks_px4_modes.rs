//! PX4's MAVLink port modes through the firmware's tasks (virtual time): PX4 1.16's link
//! in mode Gimbal gives no time and no position, which the bridge says once
//! (`Event::NoTimeOrFixes`); with PX4's telemetry link beside it (a port in mode Normal),
//! time and geotags come from that link; mode Normal alone gives both and no warning
//! (docs/src/autopilots/px4.md).

use bridge_engine::{Config, Event, Port};
use gimbal::sim::Autopilot;
use gimbal::sim::pilot::Pilot;
use gimbal::sim::pod::{PodSimConfig, SimPod, SyncOutcome};
use gimbal::sim::px4::{Px4, Px4Config, Px4Mode};
use gimbal::sim::tasks::{Bench, Outcome};
use protocol_core::k40t::AckCode;

const S: u64 = 1_000_000;

fn events<T>(o: &Outcome<Px4, T>, f: impl Fn(&Event) -> bool) -> Vec<(u64, Event)> {
    o.events().filter(|(_, e)| f(e)).collect()
}

/// A photo at 40 s and 50 s.
fn photos(b: &Bench<Px4, Px4>, now: u64) {
    if now == 40 * S || now == 50 * S {
        b.fc.borrow_mut().take_picture();
    }
}

fn run(fc: Px4Config, telemetry: Option<Px4Config>) -> Outcome<Px4, Px4> {
    let config = Config::for_fc(Px4::PROTOCOL);
    let pod = SimPod::new(PodSimConfig::default());
    let bench = Bench::<Px4, Px4>::of(config, Px4::new(fc), pod, telemetry.map(Px4::new));
    bench.run(60 * S, S, photos)
}

/// The geotag replies' codes.
fn geotags<T>(o: &Outcome<Px4, T>) -> Vec<AckCode> {
    o.pod
        .gps_replies()
        .iter()
        .map(|r| r.reply.code.code())
        .collect()
}

#[test]
fn px4_1_16_gimbal_mode_gives_no_time_and_the_bridge_says_so_once() {
    let o = run(Px4Config::px4_1_16_gimbal_mode(), None);
    let said = events(&o, |e| matches!(e, Event::NoTimeOrFixes { .. }));
    assert_eq!(said.len(), 1, "{said:?}");
    let (at, e) = said[0];
    assert_eq!(e, Event::NoTimeOrFixes { port: Port::Fc });
    // 10 s after PX4 was heard (its first heartbeat within the first second).
    assert!((10 * S..12 * S).contains(&at), "said at {} ms", at / 1000);
    assert!(events(&o, |e| matches!(e, Event::UtcValid { .. })).is_empty());
    assert!(o.pod.syncs().is_empty());
    // The gimbal works all the same, and the photos are taken, without geotags.
    assert!(o.fc.healthy());
    assert_eq!(o.pod.photos().len(), 2);
    assert!(geotags(&o).iter().all(|c| *c != AckCode::Ok));
}

#[test]
fn px4_gimbal_mode_with_the_telemetry_link_takes_time_and_fixes_from_it() {
    // The same PX4 (same clock: the default settings), its telemetry port in mode Normal.
    let telemetry = Px4Config {
        mode: Px4Mode::Normal,
        ..Px4Config::default()
    };
    let o = run(Px4Config::px4_1_16_gimbal_mode(), Some(telemetry));
    // The FC link still gives nothing, and says so; the telemetry link is the source.
    let said = events(&o, |e| matches!(e, Event::NoTimeOrFixes { .. }));
    assert_eq!(said.len(), 1, "{said:?}");
    assert_eq!(said[0].1, Event::NoTimeOrFixes { port: Port::Fc });
    assert!(!events(&o, |e| matches!(e, Event::TimeSource { telemetry: true })).is_empty());
    assert!(events(&o, |e| matches!(e, Event::UtcLost)).is_empty());
    let syncs = o.pod.syncs();
    assert!(syncs.len() >= 4, "{syncs:?}");
    let truth = o.telemetry.as_ref().unwrap();
    for s in syncs {
        assert_eq!(s.outcome, SyncOutcome::Applied, "{s:?}");
        let edge = s.edge_us.unwrap();
        let err = (s.unix_ms * 1000) as i64 - truth.true_utc_us(edge) as i64;
        assert!(err.unsigned_abs() < 2_000, "{err} µs");
    }
    assert_eq!(geotags(&o), [AckCode::Ok, AckCode::Ok]);
}

#[test]
fn px4_normal_mode_gives_time_and_fixes_and_no_warning() {
    let normal = Px4Config {
        mode: Px4Mode::Normal,
        ..Px4Config::default()
    };
    let o = run(normal, None);
    assert!(events(&o, |e| matches!(e, Event::NoTimeOrFixes { .. })).is_empty());
    assert!(!events(&o, |e| matches!(e, Event::UtcValid { .. })).is_empty());
    assert!(o.pod.syncs().len() >= 4);
    assert_eq!(geotags(&o), [AckCode::Ok, AckCode::Ok]);
}
