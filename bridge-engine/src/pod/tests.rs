//! The pod driver, frame by frame: motion, retries and time-outs, learning, ACK matching.

use super::*;
use crate::gimbal::Command;
use protocol_core::k40t::{
    CameraVersionAck, DialSpeed, GimbalAngle, GimbalAttitude, GimbalControl, GimbalFunction,
    HybridZoom, HybridZoomAck, Kind, MessageData, MsgId, PitchMotion, TakePhotoAck, Version,
    YawMotion,
};
use protocol_core::k40t::{Message, Packet};

fn outputs() -> Outputs {
    Outputs::new()
}

fn ms(t: u64) -> Instant {
    Instant::from_millis(t)
}

/// The frames queued for the pod, decoded, oldest first, without the version
/// queries that probe a pod not heard from.
fn sent(out: &mut Outputs) -> Vec<(Header, Request)> {
    let mut v = sent_all(out);
    v.retain(|(_, r)| !matches!(r, Request::GimbalVersion(_) | Request::CameraVersion(_)));
    v
}

/// Every frame queued for the pod.
fn sent_all(out: &mut Outputs) -> Vec<(Header, Request)> {
    let mut v = vec![];
    while let Some(f) = out.pod.front() {
        let p = Packet::decode(f).unwrap();
        match p.message {
            Message::Request(r) => v.push((p.header, r)),
            Message::Ack(a) => panic!("ack {a:?}"),
            other => panic!("{other:?}"),
        }
        out.pod.pop();
    }
    v
}

fn events(out: &mut Outputs) -> Vec<Event> {
    let mut v = vec![];
    while let Some(e) = out.events.pop() {
        v.push(e);
    }
    v
}

/// A frame from the pod.
fn from_pod<M: MessageData<Protocol = protocol_core::k40t::K40t>>(
    m: M,
    src: Address,
    seq: u8,
    coverage: CrcCoverage,
) -> Vec<u8> {
    let header = Header {
        dst: Address::FLIGHT_CONTROLLER,
        src,
        seq,
        coverage,
    };
    let mut buf = [0u8; k40t::MAX_FRAME_LEN];
    let n = k40t::encode(&m, &header, &mut buf).unwrap();
    buf[..n].to_vec()
}

fn feed(pod: &mut PodDriver, now: Instant, frame: &[u8], out: &mut Outputs) -> Vec<PodNotice> {
    let f = Frame::new_checked(frame).unwrap();
    let header = f.header().unwrap();
    let claimed = pod.ack_claim(f.id().base, header.seq).is_some();
    pod.handle(now, &f, header, claimed, out).iter().collect()
}

fn rates(yaw: i32, pitch: i32) -> Command {
    Command::Rates {
        yaw_cdeg_s: yaw,
        pitch_cdeg_s: pitch,
    }
}

#[test]
fn rates_become_direction_and_dial_speed_edge_triggered() {
    let mut pod = PodDriver::new(PodConfig::DEFAULT);
    let mut out = outputs();
    // 45 deg/s right is clamped to 30 deg/s; 9 deg/s down.
    assert_eq!(
        pod.command(ms(0), rates(4500, -900), &mut out),
        Some(0x0010)
    );
    let s = sent(&mut out);
    assert_eq!(s.len(), 2);
    assert_eq!(
        s[0].1,
        Request::DialSpeed(DialSpeed {
            pitch_dps_x5: 45,
            yaw_dps_x5: 150,
            reserved: 0
        })
    );
    assert_eq!(s[0].0.dst, Address::GIMBAL);
    assert_eq!(
        s[1].1,
        Request::GimbalControl(GimbalControl {
            function: GimbalFunction::None,
            yaw: YawMotion::Right,
            pitch: PitchMotion::Down,
            reserved: 0
        })
    );
    assert_eq!(s[1].0.seq, s[0].0.seq.wrapping_add(1));
    assert!(events(&mut out).contains(&Event::RateClamped {
        requested_cdeg_s: 4500
    }));

    // The FC repeats the same rates at 50 Hz: nothing new for the pod.
    for t in (20..1000).step_by(20) {
        pod.command(ms(t), rates(4500, -900), &mut out);
        pod.poll(ms(t), Duration::from_millis(500), &mut out);
    }
    assert!(sent(&mut out).is_empty());
    // ... until the refresh, once a second.
    pod.command(ms(1000), rates(4500, -900), &mut out);
    pod.poll(ms(1000), Duration::from_millis(500), &mut out);
    let s = sent(&mut out);
    assert_eq!(s.len(), 1, "{s:?}");
    assert!(matches!(s[0].1, Request::GimbalControl(_)));

    // A change within the dead-band (0.4 deg/s) is no new command; beyond it, a new
    // dial speed and direction, but not before the motion interval.
    pod.command(ms(1020), rates(4500, -940), &mut out);
    assert!(sent(&mut out).is_empty());
    pod.command(ms(1040), rates(4500, -1000), &mut out);
    assert!(sent(&mut out).is_empty(), "within 100 ms of the last");
    pod.poll(ms(1100), Duration::from_millis(500), &mut out);
    let s = sent(&mut out);
    assert_eq!(s.len(), 2, "{s:?}");
    assert_eq!(
        s[0].1,
        Request::DialSpeed(DialSpeed {
            pitch_dps_x5: 50,
            yaw_dps_x5: 150,
            reserved: 0
        })
    );
}

#[test]
fn fc_silence_stops_the_pod() {
    let mut pod = PodDriver::new(PodConfig::DEFAULT);
    let mut out = outputs();
    pod.command(ms(0), rates(1000, 0), &mut out);
    sent(&mut out);
    events(&mut out);
    let silence = Duration::from_millis(500);
    pod.poll(ms(0), silence, &mut out); // probes the pod: due again in 1 s
    assert_eq!(pod.poll_at(silence), Some(ms(500)));
    pod.poll(ms(499), silence, &mut out);
    assert!(sent(&mut out).is_empty());
    pod.poll(ms(500), silence, &mut out);
    let s = sent(&mut out);
    assert_eq!(
        s.iter().map(|(_, r)| *r).collect::<Vec<_>>(),
        vec![Request::GimbalControl(GimbalControl {
            function: GimbalFunction::None,
            yaw: YawMotion::Stop,
            pitch: PitchMotion::Stop,
            reserved: 0
        })]
    );
    assert_eq!(events(&mut out), vec![Event::FcSilenceStop]);
    // Stopped: no more stops, no refresh.
    pod.poll(ms(5000), silence, &mut out);
    assert!(sent(&mut out).is_empty());
    assert_eq!(pod.poll_at(silence), Some(ms(6000)), "probing the lost pod");
}

#[test]
fn settings_are_retried_then_time_out_and_acks_stop_them() {
    let mut pod = PodDriver::new(PodConfig::DEFAULT);
    let mut out = outputs();
    let silence = Duration::from_millis(500);
    assert_eq!(
        pod.command(ms(0), Command::Record(true), &mut out),
        Some(0x0303)
    );
    let first = sent(&mut out);
    assert_eq!(first.len(), 1);
    assert_eq!(first[0].0.dst, Address::POD);
    let seq = first[0].0.seq;
    pod.poll(ms(199), silence, &mut out);
    assert!(sent(&mut out).iter().all(|(_, r)| r.base() != 0x0303));
    pod.poll(ms(200), silence, &mut out);
    let retry: Vec<_> = sent(&mut out)
        .into_iter()
        .filter(|(_, r)| r.base() == 0x0303)
        .collect();
    assert_eq!(retry.len(), 1);
    assert_eq!(retry[0].0.seq, seq, "a retry keeps its sequence number");
    pod.poll(ms(400), silence, &mut out);
    let notices: Vec<_> = pod.poll(ms(600), silence, &mut out).iter().collect();
    assert_eq!(notices, vec![PodNotice::TimedOut { base: 0x0303 }]);
    assert!(events(&mut out).contains(&Event::PodTimeout { base: 0x0303 }));
    assert_eq!(out.counters.pod_retries, 2);

    // Acknowledged at once: no retry.
    pod.command(ms(1000), Command::ZoomTo { zoom_x10: 45 }, &mut out);
    let s = sent(&mut out);
    let (h, r) = s.iter().find(|(_, r)| r.base() == 0x0304).unwrap();
    assert_eq!(
        *r,
        Request::HybridZoom(HybridZoom {
            start: 0,
            zoom_x10: 45
        })
    );
    let ack = from_pod(
        HybridZoomAck {
            code: k40t::ResponseCode::OK,
        },
        Address::POD,
        h.seq,
        CrcCoverage::ExcludeStx,
    );
    let n = feed(&mut pod, ms(1050), &ack, &mut out);
    assert_eq!(
        n,
        vec![PodNotice::Acked {
            base: 0x0304,
            code: AckCode::Ok
        }]
    );
    pod.poll(ms(1300), silence, &mut out);
    assert!(sent(&mut out).iter().all(|(_, r)| r.base() != 0x0304));

    // A refusal is an event.
    pod.command(ms(2000), Command::TakePhoto, &mut out);
    let s = sent(&mut out);
    let seq = s.iter().find(|(_, r)| r.base() == 0x0302).unwrap().0.seq;
    let nak = from_pod(
        TakePhotoAck {
            code: k40t::ResponseCode::new(AckCode::NoSdCard),
        },
        Address::POD,
        seq,
        CrcCoverage::ExcludeStx,
    );
    feed(&mut pod, ms(2010), &nak, &mut out);
    assert!(events(&mut out).contains(&Event::PodRefused {
        base: 0x0302,
        code: AckCode::NoSdCard
    }));
}

#[test]
fn addresses_coverage_and_link_are_learnt_from_reports() {
    let mut pod = PodDriver::new(PodConfig::DEFAULT);
    let mut out = outputs();
    let silence = Duration::from_millis(500);
    // Lost at start: probing.
    pod.poll(ms(0), silence, &mut out);
    assert!(matches!(
        sent_all(&mut out)[..],
        [(_, Request::GimbalVersion(_))]
    ));
    let gimbal_src = Address::new(0x04, 0x01);
    let att = GimbalAttitude {
        yaw_cdeg: 1234,
        pitch_cdeg: -4500,
        ..GimbalAttitude::default()
    };
    let report = from_pod(att, gimbal_src, 1, CrcCoverage::IncludeStx);
    let notices = feed(&mut pod, ms(10), &report, &mut out);
    assert_eq!(notices, vec![PodNotice::LinkUp]);
    assert_eq!(pod.state().attitude, Some((att, ms(10))));
    assert!(pod.state().link);
    let ev = events(&mut out);
    assert!(
        ev.contains(&Event::PodCoverage(CrcCoverage::IncludeStx)),
        "{ev:?}"
    );
    // Versions are asked on connection, with the learnt coverage and address.
    let s = sent_all(&mut out);
    assert!(s.iter().any(|(h, r)| matches!(r, Request::GimbalVersion(_))
        && h.dst == gimbal_src
        && h.coverage == CrcCoverage::IncludeStx));
    assert!(
        s.iter()
            .any(|(_, r)| matches!(r, Request::CameraVersion(_)))
    );
    let (g, c, cov) = pod.link_params();
    assert_eq!(
        (g, c, cov),
        (gimbal_src, Address::POD, CrcCoverage::IncludeStx)
    );
    // Reports stop: lost after 1 s, probing again every second.
    pod.poll(ms(1009), silence, &mut out);
    assert!(pod.state().link);
    let notices: Vec<_> = pod.poll(ms(1010), silence, &mut out).iter().collect();
    assert_eq!(notices, vec![PodNotice::LinkDown]);
    assert!(!pod.state().link);
    let ack = from_pod(
        CameraVersionAck {
            code: k40t::ResponseCode::OK,
            version: Version {
                major: 2,
                minor: 1,
                patch: 7,
            },
        },
        Address::POD,
        0,
        CrcCoverage::IncludeStx,
    );
    feed(&mut pod, ms(1100), &ack, &mut out);
    assert_eq!(
        pod.state().camera_version,
        Some(Version {
            major: 2,
            minor: 1,
            patch: 7
        })
    );
    assert_eq!(MsgId::new(Kind::Ack, 0x0317), CameraVersionAck::ID);
}

#[test]
fn angles_and_quick_functions() {
    let mut pod = PodDriver::new(PodConfig::DEFAULT);
    let mut out = outputs();
    pod.command(
        ms(0),
        Command::Angles {
            yaw_cdeg: -9000,
            pitch_cdeg: -12000,
        },
        &mut out,
    );
    assert_eq!(
        sent(&mut out)[0].1,
        Request::GimbalAngle(GimbalAngle {
            pitch_direction: PitchMotion::Down,
            pitch_cdeg: 9000,
            yaw_direction: YawMotion::Left,
            yaw_cdeg: 9000,
            reserved: 0
        })
    );
    // Repeated: nothing; centre: at once after the interval.
    pod.command(
        ms(50),
        Command::Angles {
            yaw_cdeg: -9005,
            pitch_cdeg: -9000,
        },
        &mut out,
    );
    assert!(sent(&mut out).is_empty());
    pod.command(ms(150), Command::Center, &mut out);
    assert_eq!(
        sent(&mut out)[0].1,
        Request::GimbalControl(GimbalControl {
            function: GimbalFunction::Center,
            yaw: YawMotion::Stop,
            pitch: PitchMotion::Stop,
            reserved: 0
        })
    );
}

#[test]
fn a_photo_is_never_sent_twice_and_a_lost_ack_times_out() {
    let mut pod = PodDriver::new(PodConfig::DEFAULT);
    let mut out = outputs();
    let silence = Duration::from_millis(500);
    pod.command(ms(0), Command::TakePhoto, &mut out);
    let photos = |v: &[(Header, Request)]| v.iter().filter(|(_, r)| r.base() == 0x0302).count();
    assert_eq!(photos(&sent(&mut out)), 1);
    let mut notices = vec![];
    for t in (20..=1000).step_by(20) {
        notices.extend(pod.poll(ms(t), silence, &mut out).iter());
        assert_eq!(photos(&sent(&mut out)), 0, "resent at {t} ms");
    }
    // It waits as long as a setting waits for all its tries (3 x 200 ms).
    assert_eq!(notices, vec![PodNotice::TimedOut { base: 0x0302 }]);
    assert_eq!(out.counters.pod_retries, 0);
    assert!(events(&mut out).contains(&Event::PodTimeout { base: 0x0302 }));
}

#[test]
fn acks_numbered_by_the_pods_own_counter_match_the_oldest_request() {
    let mut pod = PodDriver::new(PodConfig::DEFAULT);
    let mut out = outputs();
    let silence = Duration::from_millis(500);
    pod.command(ms(0), Command::TakePhoto, &mut out);
    pod.command(ms(5), Command::Record(true), &mut out);
    let s = sent(&mut out);
    let photo_seq = s.iter().find(|(_, r)| r.base() == 0x0302).unwrap().0.seq;
    // The pod numbers its ACKs with its own counter: 200, 201 (never the request's).
    for (seq, ack) in [
        (
            200u8,
            from_pod(
                TakePhotoAck {
                    code: k40t::ResponseCode::OK,
                },
                Address::POD,
                200,
                CrcCoverage::ExcludeStx,
            ),
        ),
        (
            201,
            from_pod(
                k40t::RecordAck {
                    code: k40t::ResponseCode::OK,
                },
                Address::POD,
                201,
                CrcCoverage::ExcludeStx,
            ),
        ),
    ] {
        assert_ne!(seq, photo_seq);
        let n = feed(&mut pod, ms(30), &ack, &mut out);
        assert_eq!(n.len(), 1, "{n:?}");
    }
    assert!(pod.state().is_recording());
    for t in (40..=2000).step_by(20) {
        pod.poll(ms(t), silence, &mut out);
    }
    assert!(sent(&mut out).is_empty());
    assert_eq!(out.counters.pod_retries, 0);
    assert!(
        !events(&mut out)
            .iter()
            .any(|e| matches!(e, Event::PodTimeout { .. }))
    );
}

#[test]
fn a_late_ack_of_a_superseded_request_is_not_taken_for_its_successor() {
    let mut pod = PodDriver::new(PodConfig::DEFAULT);
    let mut out = outputs();
    let silence = Duration::from_millis(500);
    let zoom = |z| Command::ZoomTo { zoom_x10: z };
    pod.command(ms(0), zoom(20), &mut out);
    pod.command(ms(50), zoom(40), &mut out);
    let s = sent(&mut out);
    assert_eq!(s.len(), 2);
    let ack = |seq| {
        from_pod(
            HybridZoomAck {
                code: k40t::ResponseCode::OK,
            },
            Address::POD,
            seq,
            CrcCoverage::ExcludeStx,
        )
    };
    // The first request's ACK (own counter): absorbed by the superseded request, so
    // the second one is still pending and is retried when its own ACK is lost.
    assert!(feed(&mut pod, ms(60), &ack(77), &mut out).is_empty());
    pod.poll(ms(250), silence, &mut out);
    let s = sent(&mut out);
    assert_eq!(s.len(), 1);
    assert_eq!(
        s[0].1,
        Request::HybridZoom(HybridZoom {
            start: 0,
            zoom_x10: 40
        })
    );
    // Its ACK (exact number, as an echoing pod sends it) ends it.
    let n = feed(&mut pod, ms(260), &ack(s[0].0.seq), &mut out);
    assert_eq!(
        n,
        vec![PodNotice::Acked {
            base: 0x0304,
            code: AckCode::Ok
        }]
    );
}
