//! The bridge between a flight controller that speaks K40T itself and the simulated
//! pod: forwarding with consistent sequence numbers, RTC_IO owned by the bridge, the
//! geotag fallback, FC silence. The scenarios every FC side runs are in
//! `engine_scenarios/mod.rs`.

use crate::engine_scenarios;

use gimbal::sim::Autopilot;
use gimbal::sim::fc_k40t::FcK40t;
use gimbal::sim::pod::{MotionCommand, PodSimConfig};
use gimbal::sim::scenario::Scenario;

use engine_scenarios::{
    MS, S, Silence, one_sync_per_edge, pod_stops_when_the_fc_falls_silent, sync_errors_us,
};
use protocol_core::k40t::{
    AckCode, DialSpeed, GimbalAttitude, GimbalControl, GimbalFunction, HybridZoom, HybridZoomAck,
    PitchMotion, TakePhoto, TimeSync, TimeSyncAck, YawMotion,
};

fn scenario() -> Scenario<FcK40t> {
    engine_scenarios::scenario(FcK40t::default(), PodSimConfig::default(), 20)
}

#[test]
fn frames_are_forwarded_both_ways_with_consistent_sequence_numbers() {
    let mut s = scenario();
    s.run_until(2 * S);
    // Pod reports reach the FC unchanged.
    let reports = s.fc.received_of::<GimbalAttitude>();
    assert!(reports.len() >= 15, "{}", reports.len());
    let pod_sent = s.pod.sent_of::<GimbalAttitude>();
    assert_eq!(reports.last().unwrap().1, pod_sent[reports.len() - 1].1);
    // An FC command reaches the pod; its ACK comes back with the FC's own number.
    s.fc.send(&HybridZoom {
        start: 0,
        zoom_x10: 45,
    });
    let fc_seq = s.fc.sent.last().unwrap().1;
    s.run_for(S);
    let got = s.pod.received_of::<HybridZoom>();
    assert_eq!(got.len(), 1);
    assert_eq!(got[0].2.zoom_x10, 45);
    let acks = s.fc.received_of::<HybridZoomAck>();
    assert_eq!(acks.len(), 1);
    assert_eq!(acks[0].1.seq, fc_seq);
    assert_eq!(acks[0].2.code.code(), AckCode::Ok);
    // On the pod link the bridge numbers every frame it sends from one counter: the pod
    // sees no repeated number from the flight controller's address.
    let seqs: Vec<u8> = s.pod.received().iter().map(|r| r.header.seq).collect();
    for w in seqs.windows(2) {
        assert_eq!(w[1], w[0].wrapping_add(1), "{seqs:?}");
    }
}

#[test]
fn the_fc_time_sync_is_a_utc_sample_and_the_bridge_owns_rtc_io() {
    let mut s = scenario();
    s.run_until(120 * S);
    // The FC's own 0x00030E never reaches the pod as the FC sent it; the FC gets an ACK.
    assert!(s.fc.received_of::<TimeSyncAck>().len() >= 10);
    // One 0x00030E per edge, none from the FC.
    let edges = one_sync_per_edge(&s);
    assert!(edges >= 5, "{edges} edges");
    for err in sync_errors_us(&s, 0) {
        assert!(err.abs() < 5_000, "error {err} us");
    }
    assert_eq!(
        s.pod.received_of::<TimeSync>().len(),
        edges,
        "no FC time sync forwarded"
    );
}

/// The FC's 0x00030E right behind frames it wrote before its edge and that were still
/// going out (one burst on the line): it is timed from its own first byte, so the syncs
/// carry the FC's UTC within the 2 ms it waited for the line. Timed from the burst's
/// first byte (as the bridge did) it looked 15 ms early, and the discipline, which
/// trusts the earliest-looking sample, kept the syncs 15 ms ahead.
#[test]
fn a_time_sync_behind_other_frames_is_timed_from_its_own_first_byte() {
    let mut s = scenario();
    // The FC's first time sync goes out at 1 s of true time; 15 ms before, it writes
    // twelve frames (17 ms of line time): the 0x00030E follows them back to back.
    s.run_until(S - 15_000);
    for _ in 0..12 {
        s.fc.send(&HybridZoom {
            start: 0,
            zoom_x10: 10,
        });
    }
    s.run_for(1);
    assert!(
        s.fc_line.busy_until() > S,
        "the line is busy at the FC's edge"
    );
    s.run_until(40 * S);
    let errors = sync_errors_us(&s, 0);
    assert!(errors.len() >= 3, "{errors:?}");
    assert!(errors.iter().all(|e| e.abs() < 3_000), "{errors:?} us");
}

#[test]
fn the_bridge_answers_gps_requests_the_fc_leaves_unanswered() {
    let mut s = scenario();
    s.run_until(60 * S);
    // The FC answers: its reply is forwarded (and becomes a fix of the history).
    s.fc.send(&TakePhoto::default());
    s.run_for(S / 2);
    assert_eq!(s.pod.gps_replies().len(), 1);
    assert_eq!(s.pod.gps_replies()[0].reply.code.code(), AckCode::Ok);
    assert_eq!(s.engine.counters().geotags, 0, "the FC answered");
    // The FC stops answering: 200 ms later the bridge answers from its history. One fix
    // half a second old, and the K40T reply carries no velocity: held, it could be metres
    // off, so the failure code.
    s.fc.answer_gps = false;
    s.fc.send(&TakePhoto::default());
    s.run_for(S / 2);
    let replies = s.pod.gps_replies();
    assert_eq!(replies.len(), 2);
    assert_eq!(replies[1].reply.code.code(), AckCode::Failure);
    assert_eq!(s.engine.counters().geotags_failed, 1);
    // Two answers of the FC half a second apart give the aircraft's velocity: the next
    // photo, half a second later, unanswered by the FC, is carried forward with it.
    s.fc.answer_gps = true;
    for _ in 0..2 {
        s.fc.send(&TakePhoto::default());
        s.run_for(S / 2);
    }
    s.fc.answer_gps = false;
    s.fc.send(&TakePhoto::default());
    s.run_for(S / 2);
    let replies = s.pod.gps_replies();
    assert_eq!(replies.len(), 5);
    let last = &replies[4].reply;
    assert_eq!(last.code.code(), AckCode::Ok);
    let photo = s.pod.photos().last().expect("a photo").at_us;
    let (lat, lon) = s.fc.aircraft().position_e7(photo);
    assert!(
        (last.lat_e7 - lat).abs() < 50 && (last.lon_e7 - lon).abs() < 70,
        "{last:?} vs {lat} {lon}"
    );
    assert_eq!(s.engine.counters().geotags, 1);
    // Much later: no fix near the time asked, so a failure code and nothing invented.
    s.run_for(10 * S);
    s.fc.send(&TakePhoto::default());
    s.run_for(S);
    let replies = s.pod.gps_replies();
    assert_eq!(replies.len(), 6);
    assert_eq!(replies[5].reply.code.code(), AckCode::Failure);
    assert_eq!(replies[5].reply.lat_e7, 0);
    assert_eq!(s.engine.counters().geotags_failed, 2);
}

#[test]
fn fc_silence_stops_the_pod() {
    let mut s = scenario();
    s.run_until(3 * S);
    s.fc.send(&DialSpeed {
        pitch_dps_x5: 50,
        yaw_dps_x5: 50,
        reserved: 0,
    });
    s.fc.send(&GimbalControl {
        function: GimbalFunction::None,
        yaw: YawMotion::Right,
        pitch: PitchMotion::Stop,
        reserved: 0,
    });
    let (cut, _) =
        pod_stops_when_the_fc_falls_silent(&mut s, S / 10, 0.0, Silence::CableCut, 700 * MS, true);
    // The FC's own motion stopped on the yaw axis it turned.
    let stop = s
        .pod
        .motions()
        .iter()
        .find(|m| {
            m.at_us > cut
                && matches!(m.command, MotionCommand::Control(c) if c.yaw == YawMotion::Stop)
        })
        .expect("a stop")
        .at_us;
    assert!(stop - cut <= 700 * MS, "{} ms", (stop - cut) / MS);
}
