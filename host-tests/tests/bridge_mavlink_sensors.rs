//! The pod's four sensors through MAVLink: the bridge's camera (100) and gimbal device
//! (154) between the simulated ArduPilot and PX4, a QGroundControl-like client through
//! their routing, and the simulated K40T pod, in simulated time. Video stream, thermal
//! range, tracking, laser, field of view, pointing at a location, and MAVSDK's gimbal
//! calls through PX4's gimbal manager (docs/src/bridge/mavlink.md).

use crate::engine_scenarios;

use bridge_engine::{Config, Decline, Event, FcProtocol};
use gimbal::sim::Autopilot;
use gimbal::sim::ap_mavlink::{ApMavlink, ApMavlinkConfig, MountTarget};
use gimbal::sim::mav;
use gimbal::sim::pod::{PodSimConfig, SimPod};
use gimbal::sim::px4::{Px4, Px4Config, Px4Mode, Px4Target};
use gimbal::sim::qgc::{Qgc, QgcConfig};
use gimbal::sim::scenario::Scenario;

use engine_scenarios::S;
use protocol_core::k40t::{
    AckCode, AiRecognition, GimbalAngle, ImageMode, ImageModeSetting, IrStatus, LaserPeriodic,
    LaserRange, OnOff, TargetGpsAck, Toggle, TrackBox,
};
use protocol_core::mavlink::dialect::{
    CAMERA_FOV_STATUS_DATA, CAMERA_THERMAL_RANGE_DATA, CAMERA_TRACKING_IMAGE_STATUS_DATA,
    CameraCapFlags, CameraTrackingMode, CameraTrackingStatusFlags, DISTANCE_SENSOR_DATA,
    GimbalDeviceCapFlags, MavCmd, MavDistanceSensor, MavFrame, MavResult, MavSensorOrientation,
    VideoStreamEncoding, VideoStreamStatusFlags, VideoStreamType,
};

fn mavlink_config() -> Config {
    Config::for_fc(FcProtocol::Mavlink)
}

/// ArduPilot with a QGroundControl-like ground station on its routing.
fn ap_qgc(config: Config, ap: ApMavlinkConfig, pod: PodSimConfig) -> Scenario<ApMavlink> {
    let mut s = engine_scenarios::scenario_with(config, ApMavlink::new(ap), pod, 25);
    s.fc.gcs = Some(Qgc::new(QgcConfig::default()));
    s
}

fn ap_default() -> Scenario<ApMavlink> {
    ap_qgc(
        mavlink_config(),
        ApMavlinkConfig::default(),
        PodSimConfig::default(),
    )
}

fn qgc(s: &mut Scenario<ApMavlink>) -> &mut Qgc {
    s.fc.gcs.as_mut().expect("a ground station")
}

/// A NUL-padded text.
fn text(bytes: &[u8]) -> String {
    let n = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
    String::from_utf8_lossy(&bytes[..n]).into_owned()
}

/// The ACKs of `cmd` the ground station got.
fn acks(q: &Qgc, cmd: MavCmd) -> Vec<MavResult> {
    q.acks
        .iter()
        .filter(|(_, _, a)| a.command == cmd)
        .map(|(_, _, a)| a.result)
        .collect()
}

/// The angle of a quaternion's Euler angles (roll, pitch, yaw, degrees).
fn euler(q: [f32; 4]) -> (f64, f64, f64) {
    mav::euler_deg(q).expect("a quaternion")
}

#[test]
fn the_video_stream_is_the_pods_rtsp_address_or_the_configured_one() {
    let mut s = ap_default();
    s.run_until(10 * S);
    let q = qgc(&mut s);
    let cam = q.camera.as_ref().expect("camera").info.clone().unwrap();
    assert!(
        cam.flags
            .contains(CameraCapFlags::CAMERA_CAP_FLAGS_HAS_VIDEO_STREAM)
    );
    let st = q.streams.get(&1).expect("stream 1").clone();
    assert_eq!(q.streams.len(), 1);
    assert_eq!(text(&st.uri[..]), "rtsp://192.168.144.64:558/live/single");
    assert_eq!((st.stream_id, st.count), (1, 1));
    assert_eq!(st.mavtype, VideoStreamType::VIDEO_STREAM_TYPE_RTSP);
    assert_eq!(text(&st.name[..]), "K40T");
    assert_eq!((st.resolution_h, st.resolution_v), (1920, 1080));
    assert_eq!(st.framerate, 30.0);
    assert_eq!(st.bitrate, 4_000_000, "the pod's 4 Mbit/s");
    assert_eq!(st.encoding, VideoStreamEncoding::VIDEO_STREAM_ENCODING_H264);
    assert_eq!(
        st.flags,
        VideoStreamStatusFlags::VIDEO_STREAM_STATUS_FLAGS_RUNNING
    );
    assert_eq!(st.hfov, 0, "no lens facts: unknown");
    assert!(s.events.iter().any(|(_, e)| *e
        == Event::PodIp {
            address: [192, 168, 144, 64]
        }));

    // The pod reboots onto another address: asked again when its link is back.
    s.pod.set_ip([[10, 1, 2, 3], [255, 0, 0, 0], [10, 0, 0, 1]]);
    let now = s.now_us;
    s.pod.reboot(now, 3 * S);
    s.run_for(6 * S);
    qgc(&mut s).request_from_camera(269, 0.0);
    s.run_for(2 * S);
    let st = qgc(&mut s).streams[&1].clone();
    assert_eq!(text(&st.uri[..]), "rtsp://10.1.2.3:558/live/single");
    assert_eq!(s.pod.requests_received(0x0312), 2);

    // Another pod address: the stream follows it.
    let pod = PodSimConfig {
        ip: [[172, 16, 0, 9], [255, 255, 0, 0], [172, 16, 0, 1]],
        ..PodSimConfig::default()
    };
    let mut s = ap_qgc(mavlink_config(), ApMavlinkConfig::default(), pod);
    s.run_until(10 * S);
    assert_eq!(
        text(&qgc(&mut s).streams[&1].uri[..]),
        "rtsp://172.16.0.9:558/live/single"
    );

    // `video.uri` overrides the pod's address.
    let mut config = mavlink_config();
    config.video.uri =
        bridge_engine::config::VideoConfig::parse_uri("rtsp://10.9.9.9:8554/k40t").unwrap();
    let mut s = ap_qgc(config, ApMavlinkConfig::default(), PodSimConfig::default());
    s.run_until(10 * S);
    assert_eq!(
        text(&qgc(&mut s).streams[&1].uri[..]),
        "rtsp://10.9.9.9:8554/k40t"
    );
}

#[test]
fn camera_source_switches_the_pods_picture_and_the_stream_status_follows() {
    let mut config = mavlink_config();
    config.lens.visible_hfov_1x_cdeg = 6000;
    config.lens.ir_hfov_cdeg = 4800;
    let mut s = ap_qgc(config, ApMavlinkConfig::default(), PodSimConfig::default());
    s.run_until(10 * S);
    assert_eq!(qgc(&mut s).streams[&1].hfov, 60, "60° at 1x");
    // IR (primary 2): 0x000318 infrared; the status says THERMAL, the range enabled.
    qgc(&mut s).command(MavCmd::MAV_CMD_SET_CAMERA_SOURCE, [0.0, 2.0, 0.0, 0.0]);
    s.run_for(3 * S);
    let (_, _, m) = *s.pod.received_of::<ImageModeSetting>().last().unwrap();
    assert_eq!(m.mode, ImageMode::Infrared);
    let q = qgc(&mut s);
    assert_eq!(
        acks(q, MavCmd::MAV_CMD_SET_CAMERA_SOURCE),
        [MavResult::MAV_RESULT_ACCEPTED]
    );
    let (_, last) = q.stream_statuses.last().expect("an unasked status").clone();
    assert_eq!(
        last.flags,
        VideoStreamStatusFlags::VIDEO_STREAM_STATUS_FLAGS_RUNNING
            | VideoStreamStatusFlags::VIDEO_STREAM_STATUS_FLAGS_THERMAL
            | VideoStreamStatusFlags::VIDEO_STREAM_STATUS_FLAGS_THERMAL_RANGE_ENABLED
    );
    assert_eq!(last.hfov, 48, "the thermal camera's 48°");
    // Measurement off: the flag goes.
    s.pod.set_ir_measuring(false);
    s.run_for(3 * S);
    let (_, last) = qgc(&mut s).stream_statuses.last().unwrap().clone();
    assert_eq!(
        last.flags,
        VideoStreamStatusFlags::VIDEO_STREAM_STATUS_FLAGS_RUNNING
            | VideoStreamStatusFlags::VIDEO_STREAM_STATUS_FLAGS_THERMAL
    );
    // RGB with a secondary source: split screen (field of view unknown).
    qgc(&mut s).command(MavCmd::MAV_CMD_SET_CAMERA_SOURCE, [0.0, 1.0, 2.0, 0.0]);
    s.run_for(3 * S);
    assert_eq!(
        s.pod
            .received_of::<ImageModeSetting>()
            .last()
            .unwrap()
            .2
            .mode,
        ImageMode::Split
    );
    let (_, last) = qgc(&mut s).stream_statuses.last().unwrap().clone();
    assert_eq!(
        (last.flags, last.hfov),
        (VideoStreamStatusFlags::VIDEO_STREAM_STATUS_FLAGS_RUNNING, 0)
    );
    // Back to RGB, zoomed to 2x: 2·atan(tan 30° / 2) = 32°.
    qgc(&mut s).command(MavCmd::MAV_CMD_SET_CAMERA_SOURCE, [0.0, 1.0, 0.0, 0.0]);
    qgc(&mut s).zoom(2, 100.0 * 10.0 / 1590.0);
    s.run_for(4 * S);
    assert_eq!(s.engine.pod_state().zoom_x10(), 20);
    let (_, last) = qgc(&mut s).stream_statuses.last().unwrap().clone();
    assert_eq!(last.hfov, 32);
    assert_eq!(
        s.pod
            .received_of::<ImageModeSetting>()
            .last()
            .unwrap()
            .2
            .mode,
        ImageMode::Visible
    );
    // NDVI is not the pod's; a primary not given is refused.
    qgc(&mut s).command(MavCmd::MAV_CMD_SET_CAMERA_SOURCE, [0.0, 3.0, 0.0, 0.0]);
    qgc(&mut s).command(MavCmd::MAV_CMD_SET_CAMERA_SOURCE, [0.0, f32::NAN, 0.0, 0.0]);
    // Streaming commands: stream 1 accepted, another denied.
    qgc(&mut s).switch_stream(1, 1);
    qgc(&mut s).command(MavCmd::MAV_CMD_VIDEO_START_STREAMING, [2.0, 0.0, 0.0, 0.0]);
    s.run_for(4 * S);
    let q = qgc(&mut s);
    assert_eq!(
        acks(q, MavCmd::MAV_CMD_SET_CAMERA_SOURCE)[3..],
        [
            MavResult::MAV_RESULT_UNSUPPORTED,
            MavResult::MAV_RESULT_DENIED
        ]
    );
    assert_eq!(
        acks(q, MavCmd::MAV_CMD_VIDEO_STOP_STREAMING),
        [MavResult::MAV_RESULT_ACCEPTED]
    );
    assert_eq!(
        acks(q, MavCmd::MAV_CMD_VIDEO_START_STREAMING),
        [MavResult::MAV_RESULT_ACCEPTED, MavResult::MAV_RESULT_DENIED]
    );
    assert!(s.events.iter().any(|(_, e)| *e
        == Event::Declined {
            fc_id: 534,
            reason: Decline::NotGiven
        }));
}

/// The pod's IR reports sent before true time `t_us`.
fn ir_sent_before(pod: &SimPod, t_us: u64) -> Vec<IrStatus> {
    pod.sent_of::<IrStatus>()
        .into_iter()
        .filter(|(at, ..)| *at < t_us)
        .map(|(_, _, s)| s)
        .collect()
}

/// A thermal range is the pod's measurement: °C, and positions on the thermal picture
/// (x 320..1599, y 32..1055 of the pod's 1920 × 1088 frame).
fn is_measurement(m: &CAMERA_THERMAL_RANGE_DATA, s: &IrStatus) -> bool {
    let n = |v: u16, o: f32, l: f32| ((f32::from(v) - o) / l).clamp(0.0, 1.0);
    m.max == f32::from(s.max_temp_dc) / 10.0
        && m.min == f32::from(s.min_temp_dc) / 10.0
        && m.max_point_x == n(s.max_x, 320.0, 1280.0)
        && m.max_point_y == n(s.max_y, 32.0, 1024.0)
        && m.min_point_x == n(s.min_x, 320.0, 1280.0)
        && m.min_point_y == n(s.min_y, 32.0, 1024.0)
}

#[test]
fn thermal_range_from_the_pods_measurements_at_the_interval_asked() {
    let mut s = ap_default();
    s.run_until(12 * S);
    // By default once a second while the pod measures.
    let q = qgc(&mut s);
    let cam = q.camera.as_ref().unwrap().info.clone().unwrap();
    assert!(
        cam.flags
            .contains(CameraCapFlags::CAMERA_CAP_FLAGS_HAS_THERMAL_RANGE)
    );
    let first: Vec<_> = q.thermal_ranges.clone();
    assert!((9..=12).contains(&first.len()), "{}", first.len());
    for (t, m) in &first {
        assert_eq!((m.stream_id, m.camera_device_id), (1, 0));
        // The pod's latest measurement before the message left.
        let sent = ir_sent_before(&s.pod, *t);
        assert!(
            sent.iter().rev().take(3).any(|ir| is_measurement(m, ir)),
            "{m:?}"
        );
    }
    // The spots move.
    let xs: std::collections::BTreeSet<u32> =
        first.iter().map(|(_, m)| m.max_point_x.to_bits()).collect();
    assert!(xs.len() >= 5);
    // 5 Hz asked (faster is clamped to the pod's 5 Hz).
    qgc(&mut s).message_interval(277, 50_000.0, 0.0, 0.0);
    s.run_for(S);
    let n0 = qgc(&mut s).thermal_ranges.len();
    s.run_for(4 * S);
    let n = qgc(&mut s).thermal_ranges.len() - n0;
    assert!((19..=21).contains(&n), "{n} in 4 s");
    // Stopped; a request still answers.
    qgc(&mut s).message_interval(277, -1.0, 0.0, 0.0);
    s.run_for(S);
    let n0 = qgc(&mut s).thermal_ranges.len();
    s.run_for(3 * S);
    assert_eq!(qgc(&mut s).thermal_ranges.len(), n0);
    qgc(&mut s).request_from_camera(277, 0.0);
    s.run_for(S);
    assert_eq!(qgc(&mut s).thermal_ranges.len(), n0 + 1);
    // Another stream or camera: DENIED.
    qgc(&mut s).message_interval(277, 0.0, 2.0, 0.0);
    qgc(&mut s).message_interval(277, 0.0, 0.0, 3.0);
    s.run_for(2 * S);
    // Measurement off: none, and a request is rejected for now.
    s.pod.set_ir_measuring(false);
    qgc(&mut s).message_interval(277, 0.0, 0.0, 0.0);
    s.run_for(3 * S);
    let n0 = qgc(&mut s).thermal_ranges.len();
    qgc(&mut s).request_from_camera(277, 0.0);
    s.run_for(3 * S);
    assert_eq!(qgc(&mut s).thermal_ranges.len(), n0);
    let q = qgc(&mut s);
    let intervals = acks(q, MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL);
    assert_eq!(
        intervals,
        [
            MavResult::MAV_RESULT_ACCEPTED,
            MavResult::MAV_RESULT_ACCEPTED,
            MavResult::MAV_RESULT_DENIED,
            MavResult::MAV_RESULT_DENIED,
            MavResult::MAV_RESULT_ACCEPTED,
        ]
    );
    assert_eq!(
        acks(q, MavCmd::MAV_CMD_REQUEST_MESSAGE).last(),
        Some(&MavResult::MAV_RESULT_TEMPORARILY_REJECTED)
    );
}

fn last_tracking(q: &Qgc) -> CAMERA_TRACKING_IMAGE_STATUS_DATA {
    q.tracking.last().expect("a tracking status").1.clone()
}

#[test]
fn tracking_a_rectangle_and_a_point_as_the_pods_exact_boxes() {
    let mut s = ap_default();
    s.fc.set_target(MountTarget::body_angles(-20.0, 0.0));
    s.run_until(10 * S);
    let cam = qgc(&mut s).camera.as_ref().unwrap().info.clone().unwrap();
    assert!(cam.flags.contains(
        CameraCapFlags::CAMERA_CAP_FLAGS_HAS_TRACKING_POINT
            | CameraCapFlags::CAMERA_CAP_FLAGS_HAS_TRACKING_RECTANGLE
    ));
    // A rectangle: AI recognition on first, then the box in the pod's 1920 × 1080 pixels.
    qgc(&mut s).track_rectangle(0.25, 0.25, 0.75, 0.75);
    s.run_for(3 * S);
    let ai = s.pod.received_of::<AiRecognition>();
    assert_eq!(ai.len(), 1);
    assert_eq!(ai[0].2.enable, Toggle::On);
    let boxes = s.pod.received_of::<TrackBox>();
    assert!(ai[0].0 <= boxes[0].0);
    let b = boxes.last().unwrap().2;
    assert_eq!(
        (b.enable, b.x, b.y, b.width, b.height),
        (Toggle::On, 480, 270, 960, 540)
    );
    let q = qgc(&mut s);
    assert_eq!(
        acks(q, MavCmd::MAV_CMD_CAMERA_TRACK_RECTANGLE),
        [MavResult::MAV_RESULT_ACCEPTED]
    );
    let t = last_tracking(q);
    assert_eq!(
        t.tracking_status,
        CameraTrackingStatusFlags::CAMERA_TRACKING_STATUS_FLAGS_ACTIVE
    );
    assert_eq!(
        t.tracking_mode,
        CameraTrackingMode::CAMERA_TRACKING_MODE_RECTANGLE
    );
    assert_eq!(
        (t.rec_top_x, t.rec_top_y, t.rec_bottom_x, t.rec_bottom_y),
        (0.25, 0.25, 0.75, 0.75)
    );
    assert!(t.point_x.is_nan());
    // Twice a second, as QGroundControl asked.
    let n0 = q.tracking.len();
    s.run_for(2 * S);
    let n = qgc(&mut s).tracking.len() - n0;
    assert!((3..=5).contains(&n), "{n}");
    // The autopilot moves the gimbal: tracking is switched off first, the status IDLE.
    let t0 = s.now_us;
    s.fc.set_target(MountTarget::body_angles(-40.0, 0.0));
    s.run_for(3 * S);
    let off = s
        .pod
        .received_of::<TrackBox>()
        .into_iter()
        .find(|(t, _, b)| *t > t0 && b.enable == Toggle::Off)
        .expect("tracking switched off")
        .0;
    let angle = s
        .pod
        .received_of::<GimbalAngle>()
        .into_iter()
        .find(|(t, ..)| *t > t0)
        .expect("the new angle")
        .0;
    assert!(off <= angle);
    assert!((s.pod.gimbal().pitch_deg + 40.0).abs() < 0.5);
    assert_eq!(
        last_tracking(qgc(&mut s)).tracking_status,
        CameraTrackingStatusFlags::CAMERA_TRACKING_STATUS_FLAGS_IDLE
    );
    // A point with a radius of a tenth of the width: a 384 px square around it.
    qgc(&mut s).track_point(0.5, 0.5, 0.1);
    s.run_for(3 * S);
    let b = s.pod.received_of::<TrackBox>().last().unwrap().2;
    assert_eq!(
        (b.enable, b.x, b.y, b.width, b.height),
        (Toggle::On, 768, 348, 384, 384)
    );
    let t = last_tracking(qgc(&mut s));
    assert_eq!(
        t.tracking_mode,
        CameraTrackingMode::CAMERA_TRACKING_MODE_POINT
    );
    assert_eq!((t.point_x, t.point_y, t.radius), (0.5, 0.5, 0.1));
    // Stopped: 0x000324 off, IDLE, the status interval stopped by the client.
    qgc(&mut s).stop_tracking();
    s.run_for(3 * S);
    assert_eq!(
        s.pod.received_of::<TrackBox>().last().unwrap().2.enable,
        Toggle::Off
    );
    let n0 = qgc(&mut s).tracking.len();
    s.run_for(3 * S);
    let q = qgc(&mut s);
    assert_eq!(q.tracking.len(), n0, "no status after −1");
    assert_eq!(
        last_tracking(q).tracking_status,
        CameraTrackingStatusFlags::CAMERA_TRACKING_STATUS_FLAGS_IDLE
    );
    assert_eq!(
        acks(q, MavCmd::MAV_CMD_CAMERA_STOP_TRACKING),
        [MavResult::MAV_RESULT_ACCEPTED]
    );
    // A coordinate not given: DENIED, nothing sent.
    let sent = s.pod.received_of::<TrackBox>().len();
    qgc(&mut s).command(
        MavCmd::MAV_CMD_CAMERA_TRACK_POINT,
        [f32::NAN, 0.5, 0.1, 0.0],
    );
    s.run_for(2 * S);
    assert_eq!(s.pod.received_of::<TrackBox>().len(), sent);
    assert_eq!(
        acks(qgc(&mut s), MavCmd::MAV_CMD_CAMERA_TRACK_POINT).last(),
        Some(&MavResult::MAV_RESULT_DENIED)
    );
}

#[test]
fn a_box_the_pod_refuses_is_failed_and_the_status_says_error() {
    // The pod's AI recognition does not come on: it refuses the box (3.2.4.25).
    let mut s = ap_default();
    s.pod.set_nak(0x0319, Some(AckCode::Failure));
    s.run_until(10 * S);
    qgc(&mut s).track_rectangle(0.1, 0.1, 0.2, 0.3);
    s.run_for(8 * S);
    let q = qgc(&mut s);
    assert_eq!(
        acks(q, MavCmd::MAV_CMD_CAMERA_TRACK_RECTANGLE)[0],
        MavResult::MAV_RESULT_FAILED
    );
    let t = last_tracking(q);
    assert_eq!(
        t.tracking_status,
        CameraTrackingStatusFlags::CAMERA_TRACKING_STATUS_FLAGS_ERROR
    );
    let b = s.pod.received_of::<TrackBox>()[0].2;
    assert_eq!((b.x, b.y, b.width, b.height), (192, 108, 192, 216));
}

fn distances_after(q: &Qgc, t0: u64) -> Vec<DISTANCE_SENSOR_DATA> {
    q.distances
        .iter()
        .filter(|(t, ..)| *t > t0)
        .map(|(_, _, d)| d.clone())
        .collect()
}

#[test]
fn distance_sensor_with_the_gimbals_orientation_when_asked() {
    let mut s = ap_default();
    s.fc.set_target(MountTarget::body_angles(-45.0, 30.0));
    s.run_until(10 * S);
    // Not ranging by itself.
    assert!(qgc(&mut s).distances.is_empty());
    assert!(s.pod.received_of::<LaserPeriodic>().is_empty());
    // Asked at an interval: periodic ranging, one reading a second.
    qgc(&mut s).message_interval(132, 0.0, 0.0, 0.0);
    s.run_for(S);
    let t0 = s.now_us;
    s.run_for(5 * S);
    assert_eq!(s.pod.received_of::<LaserPeriodic>()[0].2.enable, OnOff::On);
    let d = distances_after(qgc(&mut s), t0);
    assert!((4..=6).contains(&d.len()), "{}", d.len());
    for m in &d {
        assert_eq!(m.current_distance, 12_340, "123.4 m");
        assert_eq!((m.min_distance, m.max_distance), (0, 65_535));
        assert_eq!(m.mavtype, MavDistanceSensor::MAV_DISTANCE_SENSOR_LASER);
        assert_eq!(
            m.orientation,
            MavSensorOrientation::MAV_SENSOR_ROTATION_CUSTOM
        );
        // The gimbal in the body frame: 30° right, 45° down.
        let (roll, pitch, yaw) = euler(m.quaternion);
        assert!(
            roll.abs() < 0.2 && (pitch + 45.0).abs() < 0.2 && (yaw - 30.0).abs() < 0.2,
            "{roll} {pitch} {yaw}"
        );
        assert_eq!(m.covariance, u8::MAX);
    }
    assert!(
        qgc(&mut s)
            .distances
            .iter()
            .all(|(_, h, _)| h.component_id == 100)
    );
    // Stopped: the laser too.
    qgc(&mut s).message_interval(132, -1.0, 0.0, 0.0);
    s.run_for(S);
    let t0 = s.now_us;
    s.run_for(3 * S);
    assert_eq!(
        s.pod
            .received_of::<LaserPeriodic>()
            .last()
            .unwrap()
            .2
            .enable,
        OnOff::Off
    );
    assert!(distances_after(qgc(&mut s), t0).is_empty());
    // One reading on request: the ACK, then the reading.
    s.pod.set_laser_distance_dm(567);
    qgc(&mut s).request_from_camera(132, 0.0);
    s.run_for(2 * S);
    assert_eq!(s.pod.received_of::<LaserRange>().len(), 1);
    let q = qgc(&mut s);
    let d = distances_after(q, t0);
    assert_eq!(d.len(), 1);
    assert_eq!(d[0].current_distance, 5_670);
    let ack_at = q
        .acks
        .iter()
        .rfind(|(_, _, a)| a.command == MavCmd::MAV_CMD_REQUEST_MESSAGE)
        .unwrap();
    assert_eq!(ack_at.2.result, MavResult::MAV_RESULT_ACCEPTED);
    assert!(ack_at.0 <= q.distances.last().unwrap().0);
    // No return: FAILED.
    s.pod.set_laser_distance_dm(0);
    qgc(&mut s).request_from_camera(132, 0.0);
    s.run_for(2 * S);
    assert_eq!(
        acks(qgc(&mut s), MavCmd::MAV_CMD_REQUEST_MESSAGE).last(),
        Some(&MavResult::MAV_RESULT_FAILED)
    );

    // `laser.periodic`: ranging from the link-up, with the configured range.
    let mut config = mavlink_config();
    config.laser.periodic = true;
    config.laser.min_distance_cm = 500;
    config.laser.max_distance_cm = 60_000;
    let mut s = ap_qgc(config, ApMavlinkConfig::default(), PodSimConfig::default());
    s.run_until(8 * S);
    let d = distances_after(qgc(&mut s), 0);
    assert!(d.len() >= 5, "{}", d.len());
    assert_eq!((d[0].min_distance, d[0].max_distance), (500, 60_000));
}

/// (north, east, up) metres of `to` from `from` (lat, lon degE7, alt mm), flat earth on
/// the mean sphere.
fn local(from: (i32, i32, i32), to: (i32, i32, i32)) -> (f64, f64, f64) {
    let m = 6_371_008.8 * std::f64::consts::PI / 180.0 / 1e7;
    (
        f64::from(to.0 - from.0) * m,
        f64::from(to.1 - from.1) * m * (f64::from(from.0) / 1e7).to_radians().cos(),
        f64::from(to.2 - from.2) / 1000.0,
    )
}

fn fov_after(q: &Qgc, t0: u64) -> Vec<(u64, CAMERA_FOV_STATUS_DATA)> {
    q.fov_statuses
        .iter()
        .filter(|(t, _)| *t > t0)
        .cloned()
        .collect()
}

#[test]
fn fov_status_says_where_the_camera_looks() {
    let mut config = mavlink_config();
    config.lens.visible_hfov_1x_cdeg = 6000;
    let mut s = ap_qgc(config, ApMavlinkConfig::default(), PodSimConfig::default());
    s.fc.set_target(MountTarget::body_angles(-45.0, 30.0));
    s.run_until(10 * S);
    // QGroundControl asked after CAMERA_SETTINGS: its hfov shown.
    let hfov = qgc(&mut s).hfov.expect("a field of view");
    assert!((hfov - 60.0).abs() < 0.01, "{hfov}");
    // Once a second from now on; the pod's laser target (0x000320) where it gives one.
    qgc(&mut s).message_interval(271, 0.0, 0.0, 0.0);
    s.run_for(5 * S);
    let heading = s.fc.aircraft().heading_deg;
    let targets = s.pod.sent_of::<TargetGpsAck>();
    assert!(targets.len() >= 3);
    let f = fov_after(qgc(&mut s), 11 * S);
    assert!((4..=6).contains(&f.len()), "{}", f.len());
    let mut from_pod = 0;
    for (t, m) in &f {
        // The camera where the aircraft is.
        let (lat, lon) = s.fc.aircraft().position_e7(*t);
        let (n, e, _) = local((lat, lon, 0), (m.lat_camera, m.lon_camera, 0));
        assert!(n.hypot(e) < 3.0, "{n} {e}");
        assert_eq!(m.alt_camera, 488_000);
        let (roll, pitch, yaw) = euler(m.q);
        assert!(roll.abs() < 0.3 && (pitch + 45.0).abs() < 0.3);
        assert!((yaw - (heading + 30.0)).abs() < 0.3, "{yaw}");
        assert!((m.hfov - 60.0).abs() < 0.01);
        let vfov = 2.0
            * ((30f32.to_radians()).tan() * 9.0 / 16.0)
                .atan()
                .to_degrees();
        assert!((m.vfov - vfov).abs() < 0.01);
        // Where it looks: 123.4 m along pitch −45°, bearing 75°.
        let (n, e, u) = local(
            (m.lat_camera, m.lon_camera, m.alt_camera),
            (m.lat_image, m.lon_image, m.alt_image),
        );
        let (h, b) = (n.hypot(e), e.atan2(n).to_degrees());
        assert!(
            (h - 87.26).abs() < 1.5 && (u + 87.26).abs() < 1.5,
            "{h} {u}"
        );
        assert!((b - 75.0).abs() < 1.0, "{b}");
        from_pod += usize::from(targets.iter().any(|(_, _, a)| {
            (a.lat_e7, a.lon_e7, a.alt_mm) == (m.lat_image, m.lon_image, m.alt_image)
        }));
    }
    assert!(from_pod >= f.len() - 1, "{from_pod} of {}", f.len());

    // Without the pod's target: computed from the laser's range (ranging asked), the
    // same point.
    s.pod.set_nak(0x0320, Some(AckCode::Failure));
    qgc(&mut s).message_interval(132, 0.0, 0.0, 0.0);
    s.run_for(3 * S);
    let t0 = s.now_us;
    s.run_for(3 * S);
    for (_, m) in fov_after(qgc(&mut s), t0) {
        let (n, e, u) = local(
            (m.lat_camera, m.lon_camera, m.alt_camera),
            (m.lat_image, m.lon_image, m.alt_image),
        );
        assert!(
            (n.hypot(e) - 87.26).abs() < 0.5 && (u + 87.26).abs() < 0.5,
            "{n} {e} {u}"
        );
        assert!((e.atan2(n).to_degrees() - 75.0).abs() < 0.5);
    }
    // No laser reading: where the camera's axis meets the ground at home's altitude
    // (58 m below): 58 m ahead.
    s.pod.set_laser_distance_dm(0);
    s.run_for(3 * S);
    let t0 = s.now_us;
    s.run_for(3 * S);
    let f = fov_after(qgc(&mut s), t0);
    assert!(!f.is_empty());
    for (_, m) in f {
        let (n, e, u) = local(
            (m.lat_camera, m.lon_camera, m.alt_camera),
            (m.lat_image, m.lon_image, m.alt_image),
        );
        assert!(
            (n.hypot(e) - 58.0).abs() < 0.5 && (u + 58.0).abs() < 0.5,
            "{n} {e} {u}"
        );
    }
    // Above the horizon without a range: at infinity.
    s.fc.set_target(MountTarget::body_angles(10.0, 0.0));
    s.run_for(3 * S);
    let t0 = s.now_us;
    s.run_for(2 * S);
    for (_, m) in fov_after(qgc(&mut s), t0) {
        assert_eq!(
            (m.lat_image, m.lon_image, m.alt_image),
            (i32::MIN, i32::MIN, i32::MIN)
        );
    }
    // Stopped.
    qgc(&mut s).message_interval(271, -1.0, 0.0, 0.0);
    s.run_for(S);
    let t0 = s.now_us;
    s.run_for(3 * S);
    assert!(fov_after(qgc(&mut s), t0).is_empty());
}

#[test]
fn ardupilot_points_the_gimbal_at_a_location_through_the_device() {
    for to_device in [true, false] {
        let ap = ApMavlinkConfig {
            roi_to_device: to_device,
            ..ApMavlinkConfig::default()
        };
        let mut s = ap_qgc(mavlink_config(), ap, PodSimConfig::default());
        s.run_until(6 * S);
        let info = &s.fc.mount_info.as_ref().unwrap().data;
        assert!(
            info.cap_flags2
                .contains(GimbalDeviceCapFlags::GIMBAL_DEVICE_CAP_FLAGS_CAN_POINT_LOCATION_GLOBAL)
        );
        // 300 m north and 100 m east of the aircraft's start, on the ground (430 m).
        let a = *s.fc.aircraft();
        let (lat0, lon0) = a.position_e7(0);
        let target = (
            lat0 + (300.0 / 111_320.0 * 1e7) as i32,
            lon0 + (100.0 / (111_320.0 * a.lat0_deg.to_radians().cos()) * 1e7) as i32,
        );
        s.fc.set_target(MountTarget::Location {
            lat_e7: target.0,
            lon_e7: target.1,
            alt_m: 430.0,
        });
        for _ in 0..3 {
            s.run_for(3 * S);
            let (lat, lon) = a.position_e7(s.now_us);
            let (bearing, elevation) =
                mav::bearing_elevation((lat, lon, a.alt_msl_m), (target.0, target.1, 430.0));
            let g = s.pod.gimbal();
            let yaw = (bearing - a.heading_deg + 540.0) % 360.0 - 180.0;
            assert!(
                (g.yaw_deg - yaw).abs() < 1.5 && (g.pitch_deg - elevation).abs() < 1.5,
                "{to_device}: {g:?} vs {yaw} {elevation}"
            );
        }
        let rois =
            s.fc.acks
                .iter()
                .filter(|a| a.data.command == MavCmd::MAV_CMD_DO_SET_ROI_LOCATION)
                .collect::<Vec<_>>();
        if to_device {
            assert!(rois.len() >= 8, "{}", rois.len());
            assert!(
                rois.iter().all(|a| a.header.component_id == 154
                    && a.data.result == MavResult::MAV_RESULT_ACCEPTED)
            );
        } else {
            assert!(rois.is_empty());
        }
        // The location ends: the gimbal centres.
        s.fc.set_target(MountTarget::Neutral);
        s.run_for(5 * S);
        let g = s.pod.gimbal();
        assert!(g.yaw_deg.abs() < 0.5 && g.pitch_deg.abs() < 0.5, "{g:?}");
    }
    // A frame the device does not take: DENIED.
    let mut s = ap_default();
    s.run_until(6 * S);
    let msg = mav::command_int(
        MavCmd::MAV_CMD_DO_SET_ROI_LOCATION,
        [0.0; 4],
        (473_977_420, 85_455_940, 10.0),
        MavFrame::MAV_FRAME_LOCAL_NED,
        (1, 154),
    );
    qgc(&mut s).command_to(154, msg);
    s.run_for(2 * S);
    let q = qgc(&mut s);
    assert_eq!(
        acks(q, MavCmd::MAV_CMD_DO_SET_ROI_LOCATION),
        [MavResult::MAV_RESULT_DENIED]
    );
}

#[test]
fn the_device_is_no_gimbal_manager() {
    let mut s = ap_default();
    s.run_until(15 * S);
    // QGroundControl asked both components for GIMBAL_MANAGER_INFORMATION: UNSUPPORTED.
    let nacks: Vec<u8> = qgc(&mut s)
        .acks
        .iter()
        .filter(|(_, _, a)| {
            a.command == MavCmd::MAV_CMD_REQUEST_MESSAGE
                && a.result == MavResult::MAV_RESULT_UNSUPPORTED
        })
        .map(|(_, c, _)| *c)
        .collect();
    assert!(nacks.contains(&154) && nacks.contains(&100), "{nacks:?}");
    // And it never sends a gimbal manager's message.
    assert!(
        s.fc.received
            .iter()
            .all(|(_, _, id)| !matches!(*id, 280 | 281))
    );
}

fn px4_qgc(mode: Px4Mode) -> Scenario<Px4> {
    let px4 = Px4Config {
        mode,
        ..Px4Config::default()
    };
    let mut s = engine_scenarios::scenario(Px4::new(px4), PodSimConfig::default(), -30);
    s.fc.gcs = Some(Qgc::new(QgcConfig::default()));
    s
}

fn px4_gcs(s: &mut Scenario<Px4>) -> &mut Qgc {
    s.fc.gcs.as_mut().expect("a ground station")
}

#[test]
fn mavsdks_gimbal_calls_through_px4s_manager_reach_the_pod() {
    let mut s = px4_qgc(Px4Mode::Normal);
    s.run_until(10 * S);
    // set_angles (send mode Once): DO_GIMBAL_MANAGER_PITCHYAW to the manager, PX4's
    // GIMBAL_DEVICE_SET_ATTITUDE to the device.
    px4_gcs(&mut s).gimbal_pitchyaw([-30.0, 20.0], [f32::NAN; 2], 0, 154);
    s.run_for(4 * S);
    let g = s.pod.gimbal();
    assert!(
        (g.pitch_deg + 30.0).abs() < 0.5 && (g.yaw_deg - 20.0).abs() < 0.5,
        "{g:?}"
    );
    // set_angular_rates: 10 °/s of yaw.
    px4_gcs(&mut s).gimbal_pitchyaw([f32::NAN; 2], [0.0, 10.0], 0, 154);
    s.run_for(2 * S);
    let before = s.pod.gimbal().yaw_deg;
    s.run_for(2 * S);
    let turned = s.pod.gimbal().yaw_deg - before;
    assert!((15.0..25.0).contains(&turned), "{turned}");
    // set_roi_location: PX4 points the gimbal itself (yaw from north), the bridge turns it
    // into the pod's yaw from the nose.
    let a = *s.fc.aircraft();
    let (lat0, lon0) = a.position_e7(0);
    let target = (lat0 - (200.0 / 111_320.0 * 1e7) as i32, lon0);
    px4_gcs(&mut s).gimbal_roi(Some((target.0, target.1, 430.0)));
    s.run_for(4 * S);
    let (lat, lon) = a.position_e7(s.now_us);
    let (bearing, elevation) =
        mav::bearing_elevation((lat, lon, a.alt_msl_m), (target.0, target.1, 430.0));
    let yaw = (bearing - a.heading_deg + 540.0) % 360.0 - 180.0;
    let g = s.pod.gimbal();
    assert!(
        (g.yaw_deg - yaw).abs() < 2.0 && (g.pitch_deg - elevation).abs() < 2.0,
        "{g:?} vs {yaw} {elevation}"
    );
    assert_eq!(
        acks(px4_gcs(&mut s), MavCmd::MAV_CMD_DO_GIMBAL_MANAGER_PITCHYAW),
        [MavResult::MAV_RESULT_ACCEPTED; 2]
    );
    assert_eq!(
        acks(px4_gcs(&mut s), MavCmd::MAV_CMD_DO_SET_ROI_LOCATION),
        [MavResult::MAV_RESULT_ACCEPTED]
    );
    assert!(matches!(s.fc.target, Some(Px4Target::Location { .. })));
}

#[test]
fn px4s_routing_carries_the_stream_the_thermal_range_and_tracking() {
    let mut s = px4_qgc(Px4Mode::Normal);
    s.run_until(12 * S);
    let q = px4_gcs(&mut s);
    let cam = q.camera.as_ref().expect("camera").info.clone().unwrap();
    assert!(
        cam.flags
            .contains(CameraCapFlags::CAMERA_CAP_FLAGS_HAS_VIDEO_STREAM)
    );
    assert_eq!(
        text(&q.streams[&1].uri[..]),
        "rtsp://192.168.144.64:558/live/single"
    );
    assert!(q.thermal_ranges.len() >= 8);
    q.track_point(0.25, 0.75, 0.0);
    s.run_for(3 * S);
    let b = s.pod.received_of::<TrackBox>().last().unwrap().2;
    assert_eq!((b.x, b.y, b.width, b.height), (480, 810, 1, 1));
    let q = px4_gcs(&mut s);
    assert_eq!(
        acks(q, MavCmd::MAV_CMD_CAMERA_TRACK_POINT),
        [MavResult::MAV_RESULT_ACCEPTED]
    );
    assert_eq!(
        q.tracking.last().unwrap().1.tracking_status,
        CameraTrackingStatusFlags::CAMERA_TRACKING_STATUS_FLAGS_ACTIVE
    );
    // Nothing the bridge sent was dropped on the way.
    assert!(
        !s.events
            .iter()
            .any(|(_, e)| matches!(e, Event::Dropped { .. }))
    );
}
