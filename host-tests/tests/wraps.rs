//! The points where clocks and counters wrap or jump, each run through (the scenarios'
//! clocks started just before it; docs/src/reliability.md lists them): the bridge's
//! millisecond count at 2^32 ms (49.7 days), the FC's `time_boot_ms` at the same, the
//! sequence numbers of every link, a photo at 23:59:59.9 UTC answered after midnight,
//! Viewlink's time of day across midnight, the GPS week rollover on the GCU side, a UTC
//! step and a leap second from the autopilot. Through each: every time sync right, every
//! geotag right, no stall.

use crate::engine_scenarios;

use bridge_engine::Event;
use gimbal::sim::Autopilot;
use gimbal::sim::ap_mavlink::{ApMavlink, ApMavlinkConfig};
use gimbal::sim::ap_siyi::{ApSiyi, ApSiyiConfig};
use gimbal::sim::ap_viewpro::{ApViewpro, ApViewproConfig};
use gimbal::sim::ap_xfrobot::{ApXfRobot, ApXfRobotConfig};
use gimbal::sim::pilot::Pilot;
use gimbal::sim::pod::PodSimConfig;
use gimbal::sim::scenario::Scenario;
use protocol_core::k40t::AckCode;

use engine_scenarios::{MS, S, one_sync_per_edge, scenario, sync_errors_us};

/// 2^32 ms in µs: where a `u32` millisecond count wraps (49.7 days).
const WRAP_US: u64 = (1 << 32) * 1000;
/// A day in µs.
const DAY_US: u64 = 86_400_000_000;
/// 2026-11-23 00:00:00 UTC, µs.
const MIDNIGHT_US: u64 = 1_795_392_000_000_000;

/// Every time sync so far (after `warmup_us`) within `bound_us` of the FC's true UTC,
/// one per edge, at least `min` of them.
fn syncs_right<F: Pilot>(s: &Scenario<F>, warmup_us: u64, bound_us: i64, min: usize) {
    one_sync_per_edge(s);
    let errors = sync_errors_us(s, warmup_us);
    assert!(errors.len() >= min, "{} syncs", errors.len());
    for e in &errors {
        assert!(e.abs() < bound_us, "a sync {e} us off: {errors:?}");
    }
}

/// A photo now: geotagged OK where the aircraft was.
fn photo_geotagged<F: Pilot>(s: &mut Scenario<F>) {
    let before = s.pod.photos().len();
    s.fc.take_picture();
    s.run_for(3 * S);
    assert_eq!(s.pod.photos().len(), before + 1);
    let p = s.pod.photos()[before];
    let req = &s.pod.gps_requests()[p.gps_request.expect("asked")];
    let r = &s.pod.gps_replies()[req.reply.expect("answered")];
    assert_eq!(r.reply.code.code(), AckCode::Ok, "{r:?}");
    assert!(r.time_matches && !r.late, "{r:?}");
    let (lat, lon) = s.fc.aircraft().position_e7(p.at_us);
    assert!(
        (r.reply.lat_e7 - lat).abs() < 70,
        "{} vs {lat}",
        r.reply.lat_e7
    );
    assert!(
        (r.reply.lon_e7 - lon).abs() < 70,
        "{} vs {lon}",
        r.reply.lon_e7
    );
}

/// UTC never lost once valid (no step seen where there was none).
fn utc_never_lost<F: Pilot>(s: &Scenario<F>) {
    let lost = s.events_where(|e| *e == Event::UtcLost);
    assert!(lost.is_empty(), "{lost:?}");
}

/// The bridge's millisecond count passes 2^32 (49.7 days of uptime) mid-flight: the
/// `time_boot_ms` of its MAVLink messages wraps, ArduPilot keeps the mount healthy and
/// reads every status, time syncs and geotags stay right.
#[test]
fn the_bridges_millisecond_count_wraps_mid_flight() {
    for old_gremsy in [false, true] {
        let ap = ApMavlinkConfig {
            old_gremsy,
            ..ApMavlinkConfig::default()
        };
        let mut s = scenario(ApMavlink::new(ap), PodSimConfig::default(), 25);
        s.bridge_start_us = WRAP_US - 40 * S;
        s.run_until(30 * S);
        assert!(s.fc.healthy());
        let before = s.fc.status.as_ref().unwrap().data.time_boot_ms;
        assert!(before > u32::MAX - 15_000, "{before}");
        photo_geotagged(&mut s);
        s.run_until(80 * S);
        // Wrapped: 40 s past 2^32 ms; the driver still reads the statuses.
        let after = s.fc.status.as_ref().unwrap();
        assert!(
            (39_000..41_000).contains(&after.data.time_boot_ms),
            "{after:?}"
        );
        let (read_at, ..) = s.fc.attitude.unwrap();
        assert!(s.now_us - read_at < 200 * MS);
        assert_eq!(s.fc.health_log().len(), 1, "{:?}", s.fc.health_log());
        photo_geotagged(&mut s);
        syncs_right(&s, 0, 20 * MS as i64, 5);
        utc_never_lost(&s);
    }
}

/// The FC's `time_boot_ms` passes 2^32 ms: SIYI (its clock is the FC clock of the
/// time path) and MAVLink (SYSTEM_TIME's `time_boot_ms` against TIMESYNC's 64-bit
/// clock); and an autopilot already up for longer when the bridge starts.
#[test]
fn the_fcs_boot_clock_wraps_at_49_7_days() {
    let siyi = ApSiyiConfig {
        boot_us: WRAP_US - 40 * S,
        ..ApSiyiConfig::default()
    };
    let mut s = scenario(ApSiyi::new(siyi), PodSimConfig::default(), -20);
    s.run_until(100 * S);

    syncs_right(&s, 0, 20 * MS as i64, 6);
    utc_never_lost(&s);
    photo_geotagged(&mut s);

    for boot_us in [WRAP_US - 40 * S, WRAP_US + 100 * S] {
        let ap = ApMavlinkConfig {
            boot_us,
            ..ApMavlinkConfig::default()
        };
        let mut s = scenario(ApMavlink::new(ap), PodSimConfig::default(), 25);
        s.run_until(100 * S);
        syncs_right(&s, 0, 20 * MS as i64, 6);
        utc_never_lost(&s);
        photo_geotagged(&mut s);
    }
}

/// Every link's sequence numbers wrap in a few minutes (MAVLink's and K40T's 8 bits,
/// from the pod's counters started at 250): ACKs still match their requests (every
/// photo answered), nothing is refused or dropped for it.
#[test]
fn sequence_numbers_wrap_on_every_link() {
    let pod = PodSimConfig {
        seq_start: 250,
        ..PodSimConfig::default()
    };
    let mut s = scenario(ApMavlink::new(ApMavlinkConfig::default()), pod, 25);
    s.run_until(30 * S);
    for _ in 0..6 {
        photo_geotagged(&mut s);
        s.run_for(20 * S);
    }
    let c = s.engine.counters();
    assert!(c.fc_frames > 3 * 256 && c.fc_sent > 3 * 256, "{c:?}");
    // The bridge's own K40T counter towards the pod wraps in the long run
    // (tests/long_run.rs), where it sends thousands of frames.
    assert!(c.pod_frames > 3 * 256 && c.pod_sent > 20, "{c:?}");
    assert_eq!(
        (c.dropped, c.fc_rejected, c.pod_rejected),
        (0, 0, 0),
        "{c:?}"
    );
    assert_eq!(s.pod.photos().len(), 6);
    assert!(
        s.events_where(|e| matches!(e, Event::PodTimeout { .. }))
            .is_empty()
    );
}

/// A photo taken at 23:59:59.9 UTC whose GPS request (a time of day only) is answered
/// after midnight: the answer is for the day before, where the aircraft was. (The FC's
/// command is tried at 10 ms steps until the pod's shot falls in 23:59:59.900..999 and
/// the bridge's answer, which waits for the fix after the shot, after 00:00.)
#[test]
fn a_photo_at_23_59_59_9_is_answered_after_midnight() {
    for step in 0..30u64 {
        // The FC's UTC reads 23:59:00 at true time 0.
        let ap = ApSiyiConfig {
            utc_at_zero_us: MIDNIGHT_US + DAY_US - 60 * S,
            ..ApSiyiConfig::default()
        };
        let mut s = scenario(ApSiyi::new(ap), PodSimConfig::default(), 20);
        s.run_until(59 * S + 840 * MS + step * 10 * MS);
        s.fc.take_picture();
        s.run_for(3 * S);
        let Some(p) = s.pod.photos().first().copied() else {
            continue;
        };
        let tod_ms = p.pod_unix_ms % 86_400_000;
        let req = &s.pod.gps_requests()[p.gps_request.expect("asked")];
        let r = &s.pod.gps_replies()[req.reply.expect("answered")];
        let answered_tod = s.fc.true_utc_us(r.at_us) % DAY_US;
        if !(86_399_900..86_400_000).contains(&tod_ms) || answered_tod > DAY_US / 2 {
            continue;
        }
        assert_eq!(r.reply.code.code(), AckCode::Ok, "{r:?}");
        assert!(r.time_matches && !r.late);
        let (lat, lon) = s.fc.aircraft().position_e7(p.at_us);
        assert!((r.reply.lat_e7 - lat).abs() < 50 && (r.reply.lon_e7 - lon).abs() < 70);
        assert_eq!(s.engine.counters().geotags, 1);
        syncs_right(&s, 0, 20 * MS as i64, 5);
        return;
    }
    panic!("no shot at 23:59:59.9 answered after midnight");
}

/// Viewlink's UTC is a date and a time of day truncated to 10 ms: across midnight the
/// syncs stay right and a photo after it is geotagged.
#[test]
fn viewlink_utc_across_midnight() {
    let ap = ApViewproConfig {
        utc_at_zero_us: MIDNIGHT_US + DAY_US - 60 * S,
        ..ApViewproConfig::default()
    };
    let mut s = scenario(ApViewpro::new(ap), PodSimConfig::default(), -15);
    s.run_until(120 * S);
    syncs_right(&s, 0, 20 * MS as i64, 8);
    utc_never_lost(&s);
    photo_geotagged(&mut s);
}

/// The GCU's time is GPS week + time of week: across the week's rollover (Sunday
/// 00:00:00 GPS, 18 s before midnight UTC) the syncs stay right and a photo after it is
/// geotagged.
#[test]
fn the_gps_week_rolls_over_on_the_gcu_side() {
    // GPS epoch 1980-01-06 in Unix seconds; the week boundary after MIDNIGHT_US.
    const GPS_EPOCH_S: u64 = 315_964_800;
    let week_s = 604_800;
    let after = MIDNIGHT_US / 1_000_000 + 18 - GPS_EPOCH_S;
    let boundary_unix_s = GPS_EPOCH_S + after.div_ceil(week_s) * week_s - 18;
    let ap = ApXfRobotConfig {
        utc_at_zero_us: boundary_unix_s * 1_000_000 - 60 * S,
        ..ApXfRobotConfig::default()
    };
    let mut s = scenario(ApXfRobot::new(ap), PodSimConfig::default(), 10);
    s.run_until(120 * S);
    syncs_right(&s, 0, 20 * MS as i64, 8);
    utc_never_lost(&s);
    photo_geotagged(&mut s);
}

/// The autopilot's UTC steps (a leap second inserted: 1 s back; a GPS correcting its
/// time: 30 s on) between two edges: no sync carries the old UTC after the step (the
/// bridge drops its mapping and learns the new one), none is wrong, syncs resume.
#[test]
fn a_utc_step_and_a_leap_second_from_the_autopilot() {
    for shift_us in [-1_000_000i64, 30_000_000] {
        let mut s = scenario(
            ApMavlink::new(ApMavlinkConfig::default()),
            PodSimConfig::default(),
            25,
        );
        s.run_until(43 * S + 500 * MS);
        let synced = s.pod.syncs().len();
        assert!(synced >= 2);
        let now = s.now_us;
        s.fc.board_mut().step_utc(now, shift_us);
        s.run_until(150 * S);
        syncs_right(&s, 0, 20 * MS as i64, synced + 5);
        assert!(
            !s.events_where(|e| *e == Event::UtcLost).is_empty(),
            "the step was seen"
        );
        photo_geotagged(&mut s);
    }
}

/// An ordinary flight through every MAVLink wrap at once refuses nothing: the bridge's
/// millisecond count and ArduPilot's `time_boot_ms` pass 2^32 ms, the pod's sequence
/// numbers pass 255, with photos and time syncs throughout. Nothing the autopilot or the
/// pod sends is refused, declined or unanswered (the default configuration: no signing,
/// every K40T request allowed).
#[test]
fn no_refusal_in_ordinary_flights() {
    let ap = ApMavlinkConfig {
        boot_us: WRAP_US - 50 * S,
        ..ApMavlinkConfig::default()
    };
    let pod = PodSimConfig {
        seq_start: 250,
        ..PodSimConfig::default()
    };
    let mut s = scenario(ApMavlink::new(ap), pod, 0);
    s.bridge_start_us = WRAP_US - 40 * S;
    s.run_until(30 * S);
    photo_geotagged(&mut s);
    s.run_until(80 * S);
    // The wraps happened: the bridge's count is 40 s past 2^32 ms.
    let after = s.fc.status.as_ref().expect("a status").data.time_boot_ms;
    assert!((39_000..41_000).contains(&after), "{after}");
    photo_geotagged(&mut s);
    // Measured 43 us at worst, bound 130 us.
    syncs_right(&s, 0, 130, 5);
    let c = s.engine.counters();
    assert_eq!(
        (c.commands_refused, c.signature_failures, c.unsigned_refused),
        (0, 0, 0)
    );
    let refused = s.events_where(|e| {
        matches!(
            e,
            Event::Refused { .. }
                | Event::Declined { .. }
                | Event::PodRefused { .. }
                | Event::PodTimeout { .. }
        )
    });
    assert!(refused.is_empty(), "{refused:?}");
    assert_eq!(s.fc.health_log().len(), 1, "{:?}", s.fc.health_log());
}
