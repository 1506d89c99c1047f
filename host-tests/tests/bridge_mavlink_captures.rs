//! One CAMERA_IMAGE_CAPTURED per photo the pod takes (docs/src/bridge/mavlink.md,
//! "Captures"): the engine between the simulated ArduPilot (`AP_Camera_MAVLinkCamV2`) and
//! the simulated pod, in simulated time. GPS requests that are no photo's (periodic, or
//! while recording) are answered and not reported; a burst gives one capture per photo;
//! the pod's own burst is reported from its status frames; a photo whose geotag could not
//! be answered is reported with `capture_result` 0 and no position.

use crate::engine_scenarios;

use gimbal::sim::Autopilot;
use gimbal::sim::ap_mavlink::{ApMavlink, ApMavlinkConfig};
use gimbal::sim::pod::{PeriodicGps, PodSimConfig};
use gimbal::sim::scenario::Scenario;

use engine_scenarios::{S, healthy};
use protocol_core::k40t::{AckCode, PhotoMode};

fn scenario(ap: ApMavlinkConfig, pod: PodSimConfig) -> Scenario<ApMavlink> {
    healthy(
        engine_scenarios::scenario(ApMavlink::new(ap), pod, 25),
        3 * S,
    )
}

/// The indices and results of the captures the autopilot got.
fn captures(s: &Scenario<ApMavlink>) -> Vec<(i32, i8)> {
    s.fc.images
        .iter()
        .map(|i| (i.data.image_index, i.data.capture_result.bits()))
        .collect()
}

/// Requests the pod sent for no photo, and how many of them were answered OK.
fn periodic_requests(s: &Scenario<ApMavlink>) -> (usize, usize) {
    let reqs = s.pod.gps_requests();
    let periodic: Vec<usize> = (0..reqs.len())
        .filter(|&i| reqs[i].photo.is_none())
        .collect();
    let answered = periodic
        .iter()
        .filter(|&&i| {
            reqs[i]
                .reply
                .is_some_and(|r| s.pod.gps_replies()[r].reply.code.code() == AckCode::Ok)
        })
        .count();
    (periodic.len(), answered)
}

#[test]
fn periodic_gps_requests_are_answered_and_not_taken_for_photos() {
    let pod = PodSimConfig {
        gps_periodic: PeriodicGps::Always { period_us: S },
        ..PodSimConfig::default()
    };
    let mut s = scenario(ApMavlinkConfig::default(), pod);
    s.run_until(45 * S);
    let (periodic, answered) = periodic_requests(&s);
    assert!(periodic >= 40, "{periodic}");
    // Answered once the pod's clock is synced (its first edge, by 12 s); before, it asks
    // with its free-running time, which names no instant the bridge has a fix for.
    assert!(answered >= periodic - 12, "{answered} of {periodic}");
    assert!(s.fc.images.is_empty(), "{:?}", captures(&s));
    // One photo among them, half a period from the periodic requests (one coming between
    // the command and the photo's own request would be taken for it: nothing tells them
    // apart): one capture, successful, index 0, at the photo's UTC.
    s.run_for(S / 2);
    s.fc.take_picture();
    s.run_for(5 * S);
    assert_eq!(captures(&s), [(0, 1)]);
    let photo = s.pod.photos()[0];
    let img = &s.fc.images[0].data;
    let truth = s.fc.fc_utc_us(photo.at_us);
    assert!(
        img.time_utc.abs_diff(truth) < 2_000,
        "{} vs {truth}",
        img.time_utc
    );
    let (lat, lon) = s.fc.aircraft().position_e7(photo.at_us);
    assert!(lat.abs_diff(img.lat) < 30 && lon.abs_diff(img.lon) < 30);
}

#[test]
fn requests_while_recording_are_no_photos_and_photos_while_recording_are() {
    let pod = PodSimConfig {
        gps_periodic: PeriodicGps::WhileRecording { period_us: 500_000 },
        ..PodSimConfig::default()
    };
    let mut s = scenario(ApMavlinkConfig::default(), pod);
    s.run_until(25 * S);
    s.fc.record_video(true);
    s.run_for(10 * S);
    assert!(s.pod.camera().recording.is_some());
    let (periodic, answered) = periodic_requests(&s);
    assert!(
        periodic >= 15 && answered == periodic,
        "{answered} of {periodic}"
    );
    assert!(s.fc.images.is_empty());
    for _ in 0..2 {
        s.fc.take_picture();
        s.run_for(3 * S);
    }
    s.fc.record_video(false);
    s.run_for(5 * S);
    assert_eq!(s.pod.photos().len(), 2);
    assert_eq!(captures(&s), [(0, 1), (1, 1)]);
    let (after, _) = periodic_requests(&s);
    assert!(after > periodic + 8, "requests went on while recording");
}

#[test]
fn a_commanded_burst_of_three_is_three_captures_with_three_indices() {
    let mut s = scenario(ApMavlinkConfig::default(), PodSimConfig::default());
    s.run_until(25 * S);
    s.pod.set_photo_mode(PhotoMode::Burst, 3, 5);
    s.run_for(2 * S); // the system status (0x000003) tells the bridge
    s.fc.take_picture();
    s.run_for(5 * S);
    assert_eq!(s.pod.photo_requests(), 1);
    assert_eq!(s.pod.photos().len(), 3);
    assert_eq!(captures(&s), [(0, 1), (1, 1), (2, 1)]);
    // Each at its own photo's UTC.
    for (img, photo) in s.fc.images.iter().zip(s.pod.photos()) {
        let truth = s.fc.fc_utc_us(photo.at_us);
        assert!(img.data.time_utc.abs_diff(truth) < 2_000);
    }
}

#[test]
fn the_pods_own_burst_is_reported_from_its_status_frames_a_single_shot_is_not() {
    let mut s = scenario(ApMavlinkConfig::default(), PodSimConfig::default());
    s.run_until(25 * S);
    s.pod.set_photo_mode(PhotoMode::Burst, 5, 5);
    s.run_for(2 * S);
    let t = s.pod.now_us();
    s.pod.shoot_by_itself(t, false);
    s.run_for(5 * S);
    assert_eq!(s.pod.photos().len(), 5);
    assert_eq!(captures(&s), [(0, 1), (1, 1), (2, 1), (3, 1), (4, 1)]);
    // A single shot the pod takes alone sends no status frame: nothing tells its request
    // from a periodic one (answered, not reported).
    s.pod.set_photo_mode(PhotoMode::Single, 3, 5);
    s.run_for(2 * S);
    let t = s.pod.now_us();
    s.pod.shoot_by_itself(t, false);
    s.run_for(3 * S);
    assert_eq!(s.pod.photos().len(), 6);
    assert_eq!(s.fc.images.len(), 5);
    let last = s.pod.gps_replies().last().unwrap();
    assert_eq!(last.reply.code.code(), AckCode::Ok);
}

#[test]
fn a_photo_without_a_geotag_is_reported_failed_with_no_position_and_keeps_its_index() {
    // The GPS has no fix: UTC is known, positions are no fixes.
    let ap = ApMavlinkConfig {
        gps_fix: false,
        ..ApMavlinkConfig::default()
    };
    let mut s = scenario(ap, PodSimConfig::default());
    s.run_until(25 * S);
    s.fc.take_picture();
    s.run_for(4 * S);
    assert_eq!(captures(&s), [(0, 0)]);
    let img = &s.fc.images[0].data;
    assert_eq!((img.lat, img.lon, img.alt), (0, 0, 0));
    let photo = s.pod.photos()[0];
    let truth = s.fc.fc_utc_us(photo.at_us);
    assert!(img.time_utc.abs_diff(truth) < 2_000, "the time is known");
    let reply = s.pod.gps_replies().last().unwrap().reply;
    assert_eq!(reply.code.code(), AckCode::Failure);
    // A refused command makes no photo: result 0, index -1; the next photo is index 1.
    s.pod.set_nak(0x0302, Some(AckCode::Failure));
    s.fc.take_picture();
    s.run_for(3 * S);
    s.pod.set_nak(0x0302, None);
    s.fc.take_picture();
    s.run_for(4 * S);
    assert_eq!(captures(&s), [(0, 0), (-1, 0), (1, 0)]);
}

#[test]
fn a_photo_before_utc_is_reported_failed_with_time_0() {
    // ArduPilot's clock is set from GPS late: no UTC, so the request cannot be mapped.
    let ap = ApMavlinkConfig {
        utc_valid_at_us: 60 * S,
        ..ApMavlinkConfig::default()
    };
    let mut s = scenario(ap, PodSimConfig::default());
    s.run_until(10 * S);
    s.fc.take_picture();
    s.run_for(4 * S);
    assert_eq!(captures(&s), [(0, 0)]);
    let img = &s.fc.images[0].data;
    assert_eq!((img.time_utc, img.lat, img.lon), (0, 0, 0));
}
