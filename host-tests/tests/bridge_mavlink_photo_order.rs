//! Photos that overlap (docs/src/bridge/mavlink.md, "Captures"): several photos in flight
//! at once, their ACKs slow or lost, their GPS requests late and out of order, the pod's
//! bookkeeping slots reused. Every photo the pod took is reported once, with its own UTC
//! and position, and the image indices follow the order the photos were taken.

use crate::engine_scenarios;

use std::collections::BTreeMap;

use gimbal::sim::Autopilot;
use gimbal::sim::ap_mavlink::{ApMavlink, ApMavlinkConfig};
use gimbal::sim::pod::PodSimConfig;
use gimbal::sim::scenario::Scenario;
use protocol_core::k40t::{AckCode, PhotoMode};

use engine_scenarios::{MS, S, healthy};

/// K40T base id of a photo.
const PHOTO: u16 = 0x0302;

fn scenario(pod: PodSimConfig) -> Scenario<ApMavlink> {
    healthy(
        engine_scenarios::scenario(ApMavlink::new(ApMavlinkConfig::default()), pod, 25),
        3 * S,
    )
}

/// Photos the pod takes 400 ms after the command, its ACKs 250 ms late: a photo
/// commanded every 150 ms has two or three photos in flight at once.
fn slow_pod() -> PodSimConfig {
    PodSimConfig {
        photo_gps_delay_us: 400 * MS,
        ack_delay_us: 250 * MS,
        ..PodSimConfig::default()
    }
}

/// The autopilot's captures: (index, result, UTC µs, latitude, longitude).
fn captures(s: &Scenario<ApMavlink>) -> Vec<(i32, i8, u64, i32, i32)> {
    s.fc.images
        .iter()
        .map(|i| {
            let d = &i.data;
            (
                d.image_index,
                d.capture_result.bits(),
                d.time_utc,
                d.lat,
                d.lon,
            )
        })
        .collect()
}

/// Every photo the pod took (from `first` on) is reported once, successful, with its own
/// UTC (within 2 ms of the autopilot's) and its own position (within 30e-7°), and the
/// indices count them in the order they were taken, from `index0`. Returns how many.
fn each_photo_once_in_order(s: &Scenario<ApMavlink>, first: usize, index0: i32) -> usize {
    let photos = &s.pod.photos()[first..];
    let got: Vec<_> = captures(s).into_iter().filter(|c| c.0 >= index0).collect();
    assert_eq!(
        got.len(),
        photos.len(),
        "one capture per photo: {got:?} for photos at {:?}",
        photos.iter().map(|p| p.at_us).collect::<Vec<_>>()
    );
    for (n, (c, p)) in got.iter().zip(photos).enumerate() {
        let truth = s.fc.fc_utc_us(p.at_us);
        let (lat, lon) = s.fc.aircraft().position_e7(p.at_us);
        let index = index0 + i32::try_from(n).unwrap();
        assert_eq!((c.0, c.1), (index, 1), "capture {n}: {got:?}");
        assert!(
            c.2.abs_diff(truth) < 2_000,
            "capture {n} at {} for photo at {truth}: {got:?}",
            c.2
        );
        assert!(
            c.3.abs_diff(lat) < 30 && c.4.abs_diff(lon) < 30,
            "capture {n}'s position is another photo's: {got:?}"
        );
    }
    photos.len()
}

/// Commands `n` photos `every_us` apart.
fn photos(s: &mut Scenario<ApMavlink>, n: usize, every_us: u64) {
    for _ in 0..n {
        s.fc.take_picture();
        s.run_for(every_us);
    }
}

#[test]
fn overlapping_photos_with_slow_acks_are_reported_in_the_order_taken() {
    let mut s = scenario(slow_pod());
    s.run_until(25 * S);
    // Three rounds of three photos 150 ms apart, 200 ms between rounds: the bookkeeping
    // slots of one round are still busy when the next round starts, and are reused.
    for _ in 0..3 {
        photos(&mut s, 3, 150 * MS);
        s.run_for(200 * MS);
    }
    s.run_for(5 * S);
    assert_eq!(s.pod.photos().len(), 9);
    assert_eq!(each_photo_once_in_order(&s, 0, 0), 9);
}

#[test]
fn a_gps_request_out_of_order_gives_the_photo_its_own_time_and_index() {
    // Photo 1's request comes 300 ms late: after photo 2's, naming an instant before it.
    let mut pod = slow_pod();
    pod.photo_gps_late_us = BTreeMap::from([(1, 300 * MS), (4, 400 * MS)]);
    let mut s = scenario(pod);
    s.run_until(25 * S);
    photos(&mut s, 3, 150 * MS);
    s.run_for(100 * MS);
    photos(&mut s, 3, 150 * MS);
    s.run_for(5 * S);
    assert_eq!(s.pod.photos().len(), 6);
    // The photos whose requests reached the bridge, in the order they came.
    let mut sent: Vec<(u64, usize)> = s
        .pod
        .gps_requests()
        .iter()
        .filter_map(|r| Some((r.at_us, r.photo?)))
        .collect();
    sent.sort_unstable();
    let asked: Vec<usize> = sent.iter().map(|r| r.1).collect();
    assert_eq!(asked, [0, 2, 1, 3, 5, 4], "the requests came out of order");
    assert_eq!(each_photo_once_in_order(&s, 0, 0), 6);
}

#[test]
fn lost_and_refused_acks_fail_only_their_own_photo() {
    let mut s = scenario(slow_pod());
    s.run_until(25 * S);
    // Two photos overlapping, the first's ACK lost on the way.
    s.pod.drop_acks(PHOTO, 1);
    photos(&mut s, 2, 150 * MS);
    s.run_for(3 * S);
    assert_eq!(each_photo_once_in_order(&s, 0, 0), 2);
    // A refused photo between two taken ones, all three in flight at once: the refusal
    // is its own (index -1), the two photos keep theirs.
    s.fc.take_picture();
    s.run_for(100 * MS);
    s.pod.set_nak(PHOTO, Some(AckCode::Failure));
    s.fc.take_picture();
    s.run_for(100 * MS);
    s.pod.set_nak(PHOTO, None);
    s.fc.take_picture();
    s.run_for(4 * S);
    let refused: Vec<_> = captures(&s).into_iter().filter(|c| c.0 < 0).collect();
    assert_eq!(refused.len(), 1, "{:?}", captures(&s));
    assert_eq!(refused[0].1, 0);
    assert_eq!(s.pod.photos().len(), 4);
    assert_eq!(each_photo_once_in_order(&s, 2, 2), 2);
}

#[test]
fn a_burst_with_a_late_request_keeps_the_order_taken() {
    // A commanded burst of three (300 ms apart, the first 400 ms after the command, the
    // ACK 250 ms late); the second photo's request comes after the third's.
    let mut pod = slow_pod();
    pod.photo_gps_late_us = BTreeMap::from([(1, 450 * MS)]);
    let mut s = scenario(pod);
    s.run_until(25 * S);
    s.pod.set_photo_mode(PhotoMode::Burst, 3, 5);
    s.run_for(2 * S);
    photos(&mut s, 1, 5 * S);
    assert_eq!(s.pod.photos().len(), 3);
    assert_eq!(each_photo_once_in_order(&s, 0, 0), 3);
    // Single photos overlapping again after it: indices go on from 3.
    s.pod.set_photo_mode(PhotoMode::Single, 3, 5);
    s.run_for(2 * S);
    photos(&mut s, 3, 150 * MS);
    s.run_for(4 * S);
    assert_eq!(each_photo_once_in_order(&s, 3, 3), 3);
}
