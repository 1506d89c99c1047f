//! The bridge as a MAVLink gimbal device (154) and camera (100) between simulated
//! autopilots (ArduPilot `MNT1_TYPE` 6 + `CAM1_TYPE` 6, PX4 gimbal v2 in mode Gimbal and
//! Normal), a QGroundControl-like client and the simulated K40T pod: the engine scenarios
//! of the MAVLink side, in simulated time. The simulators follow what
//! docs/src/autopilots/ardupilot.md, docs/src/autopilots/px4.md and
//! docs/src/autopilots/qgroundcontrol.md describe; where a source allows two readings
//! both are run. The scenarios every FC side runs are in `engine_scenarios/mod.rs`.

use crate::engine_scenarios;

use bridge_engine::Event;
use gimbal::sim::Autopilot;
use gimbal::sim::ap_mavlink::{ApMavlink, ApMavlinkConfig, ApVehicle, CameraTargets, MountTarget};
use gimbal::sim::pilot::Pilot;
use gimbal::sim::pod::{MotionCommand, PodSimConfig, SimPod, SyncOutcome};
use gimbal::sim::px4::{Px4, Px4Config, Px4Mode, Px4Target};
use gimbal::sim::qgc::{Qgc, QgcConfig};
use gimbal::sim::scenario::Scenario;

use engine_scenarios::{MS, S, Silence, healthy, pod_stops_when_the_fc_falls_silent};
use protocol_core::k40t::{
    self, AckCode, ContinuousZoom, Focus, FocusMode, GimbalAngle, GimbalControl, GimbalFunction,
    HybridZoom, MessageData, PitchMotion, RecordAction, TakePhoto, YawMotion, ZoomControl,
};
use protocol_core::mavlink::dialect::{
    ATTITUDE_DATA, CameraCapFlags, GIMBAL_DEVICE_SET_ATTITUDE_DATA, GLOBAL_POSITION_INT_DATA,
    GPS_RAW_INT_DATA, GimbalDeviceCapFlags, GimbalDeviceFlags, MavCmd, MavResult, MessageData as _,
    SYSTEM_TIME_DATA,
};

fn ap_scenario(ap: ApMavlinkConfig, pod: PodSimConfig) -> Scenario<ApMavlink> {
    engine_scenarios::scenario(ApMavlink::new(ap), pod, 25)
}

/// ArduPilot (booted before the bridge, its drivers searching), the pod, healthy.
fn healthy_ap() -> Scenario<ApMavlink> {
    let s = healthy(
        ap_scenario(ApMavlinkConfig::default(), PodSimConfig::default()),
        3 * S,
    );
    assert!(s.fc.camera_info.is_some());
    s
}

/// The pod's motion commands of type `M` after `after_us`.
fn motions_after(pod: &SimPod, after_us: u64) -> Vec<MotionCommand> {
    pod.motions()
        .iter()
        .filter(|m| m.at_us >= after_us)
        .map(|m| m.command)
        .collect()
}

fn last_angle(pod: &SimPod) -> GimbalAngle {
    pod.received_of::<GimbalAngle>()
        .last()
        .map(|(_, _, a)| *a)
        .expect("a 0x000012")
}

#[test]
fn ardupilot_discovers_both_components_and_calls_the_mount_healthy_within_2_s() {
    // ArduPilot boots with the bridge: its drivers look only from 10 s of uptime.
    let ap = ApMavlinkConfig {
        boot_us: 0,
        ..ApMavlinkConfig::default()
    };
    let mut s = ap_scenario(ap, PodSimConfig::default());
    s.run_until(9 * S);
    assert!(s.fc.mount_found.is_none() && !s.fc.healthy());
    s.run_until(70 * S);
    let ap = &s.fc;
    let found = ap.mount_found_at_us.expect("the gimbal found");
    assert!(
        (10 * S..10 * S + 1_100_000).contains(&found),
        "found at {found}"
    );
    let (t, up) = ap.health_log()[0];
    assert!(
        up && t - found <= 2 * S,
        "healthy {} ms after discovery",
        (t - found) / 1000
    );
    assert_eq!(
        ap.health_log().len(),
        1,
        "stays healthy: {:?}",
        ap.health_log()
    );
    assert!(ap.mount_initialised && !ap.mount_refused);
    assert_eq!(ap.parse_errors(), 0);
    // Both components, 1 Hz each, with the autopilot's system id; nothing before its
    // heartbeat, nothing from another component.
    let hb = |comp| {
        ap.received
            .iter()
            .filter(|(t, h, id)| *id == 0 && h.component_id == comp && *t > 50 * S && *t <= 60 * S)
            .count()
    };
    assert!((9..=11).contains(&hb(154)) && (9..=11).contains(&hb(100)));
    assert!(
        ap.received
            .iter()
            .all(|(_, h, _)| h.system_id == 1 && (h.component_id == 154 || h.component_id == 100))
    );
    // GIMBAL_DEVICE_ATTITUDE_STATUS at 10 Hz.
    let status = ap
        .received
        .iter()
        .filter(|(t, h, id)| *id == 285 && h.component_id == 154 && (50 * S..60 * S).contains(t))
        .count();
    assert!((99..=101).contains(&status), "{status} statuses in 10 s");
    // The information: the pod's limits (finite), versions, capabilities.
    let info = &ap.mount_info.as_ref().unwrap().data;
    let deg = |r: f32| f64::from(r).to_degrees();
    assert!((deg(info.pitch_min) + 90.0).abs() < 0.01 && (deg(info.pitch_max) - 30.0).abs() < 0.01);
    assert!((deg(info.yaw_min) + 180.0).abs() < 0.01 && (deg(info.yaw_max) - 180.0).abs() < 0.01);
    assert_eq!((info.roll_min, info.roll_max), (0.0, 0.0));
    // The bridge's version (byte 0 major); the pod's gimbal hardware 1.0.0.
    let v = bridge_engine::version::Version::parse(env!("CARGO_PKG_VERSION")).unwrap();
    assert_eq!(
        info.firmware_version.to_le_bytes(),
        [v.major, v.minor, v.patch, 0]
    );
    assert_eq!(info.hardware_version.to_le_bytes(), [1, 0, 0, 0]);
    let cap = info.cap_flags2;
    assert!(cap.contains(GimbalDeviceCapFlags::GIMBAL_DEVICE_CAP_FLAGS_HAS_PITCH_AXIS));
    assert!(cap.contains(GimbalDeviceCapFlags::GIMBAL_DEVICE_CAP_FLAGS_HAS_YAW_LOCK));
    assert!(!cap.contains(GimbalDeviceCapFlags::GIMBAL_DEVICE_CAP_FLAGS_HAS_ROLL_AXIS));
    assert_eq!(u32::from(info.cap_flags.bits()), cap.bits() & 0xFFFF);
    assert_eq!(&info.vendor_name[..4], b"K40T");
    // The camera too: a basic camera, photo, video, modes, zoom, focus; its stream (the
    // pod told its address), tracking, the thermal range (its IR camera measures); its
    // definition file served over MAVLink FTP.
    let cam = &ap.camera_info.as_ref().expect("camera information").data;
    let f = cam.flags;
    for flag in [
        CameraCapFlags::CAMERA_CAP_FLAGS_CAPTURE_IMAGE,
        CameraCapFlags::CAMERA_CAP_FLAGS_CAPTURE_VIDEO,
        CameraCapFlags::CAMERA_CAP_FLAGS_HAS_MODES,
        CameraCapFlags::CAMERA_CAP_FLAGS_HAS_BASIC_ZOOM,
        CameraCapFlags::CAMERA_CAP_FLAGS_HAS_BASIC_FOCUS,
    ] {
        assert!(f.contains(flag), "{flag:?}");
    }
    for flag in [
        CameraCapFlags::CAMERA_CAP_FLAGS_HAS_VIDEO_STREAM,
        CameraCapFlags::CAMERA_CAP_FLAGS_HAS_TRACKING_POINT,
        CameraCapFlags::CAMERA_CAP_FLAGS_HAS_TRACKING_RECTANGLE,
        CameraCapFlags::CAMERA_CAP_FLAGS_HAS_THERMAL_RANGE,
    ] {
        assert!(f.contains(flag), "{flag:?}");
    }
    assert!(!f.contains(CameraCapFlags::CAMERA_CAP_FLAGS_HAS_TRACKING_GEO_STATUS));
    assert_eq!((cam.resolution_h, cam.resolution_v), (4000, 3000));
    // The focal length the pod reports (0x000005: 4.50 mm at 1x); no sensor size
    // configured: unknown.
    assert!(
        (cam.focal_length - 4.5).abs() < 1e-6,
        "{}",
        cam.focal_length
    );
    assert!(cam.sensor_size_h.is_nan());
    assert_eq!(
        cam.firmware_version.to_le_bytes(),
        [v.major, v.minor, v.patch, 0]
    );
    assert_eq!(&cam.cam_definition_uri[..19], b"mftp://k40t.xml.xz\0");
    assert_eq!(cam.cam_definition_version, 1);
    assert_eq!(cam.gimbal_device_id, 154);
}

#[test]
fn the_bridge_asks_copter_for_time_and_position_and_syncs_the_pod() {
    let mut s = healthy_ap();
    // Copter streams nothing by default: what comes is what the bridge asked for.
    let ap = &s.fc;
    for (id, us) in [
        (SYSTEM_TIME_DATA::ID, 100_000),
        (GLOBAL_POSITION_INT_DATA::ID, 100_000),
        (ATTITUDE_DATA::ID, 100_000),
        (GPS_RAW_INT_DATA::ID, 500_000),
    ] {
        assert_eq!(ap.intervals.get(&id), Some(&us), "message {id}");
    }
    s.run_until(45 * S);
    let syncs = s.pod.syncs();
    assert!(syncs.len() >= 3, "{syncs:?}");
    for sync in syncs {
        assert_eq!(sync.outcome, SyncOutcome::Applied);
        assert_eq!(sync.unix_ms % 10_000, 0);
        let truth = s.fc.fc_utc_us(sync.edge_us.unwrap());
        let err = (sync.unix_ms * 1000).abs_diff(truth);
        assert!(err < 5_000, "{err} µs: {sync:?}");
    }
    // The requests are not repeated while the streams come.
    let requests = s.fc.received.iter().filter(|(_, _, id)| *id == 76).count();
    assert!(requests <= 6, "{requests} COMMAND_LONGs");
}

#[test]
fn vehicle_relative_angles_reach_the_pod_and_ardupilot_reads_the_pods_attitude() {
    let mut s = healthy_ap();
    s.fc.set_target(MountTarget::body_angles(-45.0, 30.0));
    s.run_for(3 * S);
    let set = &s.fc.set_attitudes.last().unwrap().1;
    assert_eq!(set.flags, GimbalDeviceFlags::empty());
    assert!(set.angular_velocity_z.is_nan());
    let a = last_angle(&s.pod);
    assert_eq!((a.yaw_direction, a.yaw_cdeg), (YawMotion::Right, 3000));
    assert_eq!((a.pitch_direction, a.pitch_cdeg), (PitchMotion::Down, 4500));
    let g = s.pod.gimbal();
    assert!(
        (g.yaw_deg - 30.0).abs() < 0.5 && (g.pitch_deg + 45.0).abs() < 0.5,
        "{g:?}"
    );
    // ArduPilot reads yaw relative to the vehicle, pitch against the horizon.
    let (_, _, pitch, yaw, earth) = s.fc.attitude.unwrap();
    assert!(
        (yaw - 30.0).abs() < 0.6 && (pitch + 45.0).abs() < 0.6,
        "{yaw} {pitch}"
    );
    // delta_yaw is the aircraft's heading (45°).
    let earth = earth.expect("delta_yaw set");
    assert!((earth - 75.0).abs() < 0.6, "earth yaw {earth}");
    // 50 Hz of the same target: the pod is not flooded.
    let before = s.pod.received_count(GimbalAngle::ID.to_u32());
    s.run_for(5 * S);
    assert!(s.pod.received_count(GimbalAngle::ID.to_u32()) - before <= 6);
}

#[test]
fn an_earth_frame_yaw_becomes_the_vehicle_relative_yaw_of_the_pod() {
    let mut s = healthy_ap();
    // Yaw 90° from north, aircraft heading 45°: 45° right of the nose.
    s.fc.set_target(MountTarget::Angle {
        roll_deg: 0.0,
        pitch_deg: -20.0,
        yaw_deg: 90.0,
        yaw_is_ef: true,
    });
    s.run_for(3 * S);
    assert_eq!(s.fc.set_attitudes.last().unwrap().1.flags.bits(), 28);
    let a = last_angle(&s.pod);
    assert_eq!(a.yaw_direction, YawMotion::Right);
    assert!(a.yaw_cdeg.abs_diff(4500) <= 2, "{a:?}");
    assert_eq!((a.pitch_direction, a.pitch_cdeg), (PitchMotion::Down, 2000));
    // The status says the yaw is locked and in the vehicle frame.
    let st = &s.fc.status.as_ref().unwrap().data;
    assert!(
        st.flags
            .contains(GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_YAW_LOCK)
    );
    assert!(
        st.flags
            .contains(GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_YAW_IN_VEHICLE_FRAME)
    );
    // Yaw 0° from north: 45° left of the nose.
    s.fc.set_target(MountTarget::Angle {
        roll_deg: 0.0,
        pitch_deg: -20.0,
        yaw_deg: 0.0,
        yaw_is_ef: true,
    });
    s.run_for(2 * S);
    let a = last_angle(&s.pod);
    assert_eq!(a.yaw_direction, YawMotion::Left);
    assert!(a.yaw_cdeg.abs_diff(4500) <= 2, "{a:?}");
}

#[test]
fn rates_retract_and_neutral_reach_the_pod() {
    let mut s = healthy_ap();
    let t0 = s.now_us;
    s.fc.turn(20.0, 0.0);
    s.run_for(2 * S);
    let set = &s.fc.set_attitudes.last().unwrap().1;
    assert!(set.q.iter().all(|c| c.is_nan()));
    let (_, _, c) = *s.pod.received_of::<GimbalControl>().last().unwrap();
    assert_eq!((c.yaw, c.pitch), (YawMotion::Right, PitchMotion::Stop));
    let (_, _, d) = *s.pod.received_of::<k40t::DialSpeed>().last().unwrap();
    assert_eq!(d.yaw_dps_x5, 100, "20 °/s");
    assert!((s.pod.gimbal().yaw_rate_dps - 20.0).abs() < 1.0);
    // A rate from a MAVLink command stops after 3 s without another (ArduPilot's rule).
    s.fc.set_target(MountTarget::Rate {
        pitch_dps: -10.0,
        yaw_dps: 0.0,
        yaw_is_ef: false,
        from_mavlink: true,
    });
    s.run_for(5 * S);
    assert_eq!(s.pod.gimbal().pitch_rate_dps, 0.0);
    // Retract: the pod looks down; neutral: it centres (an angle of 0, 0).
    s.fc.set_target(MountTarget::Retract);
    s.run_for(S);
    let (_, _, c) = *s.pod.received_of::<GimbalControl>().last().unwrap();
    assert_eq!(c.function, GimbalFunction::LookDown);
    assert_eq!(s.fc.set_attitudes.last().unwrap().1.flags.bits(), 1);
    s.run_for(3 * S);
    assert!((s.pod.gimbal().pitch_deg + 90.0).abs() < 0.5);
    s.fc.set_target(MountTarget::Neutral);
    s.run_for(4 * S);
    let a = last_angle(&s.pod);
    assert_eq!((a.pitch_cdeg, a.yaw_cdeg), (0, 0));
    assert!(s.pod.gimbal().pitch_deg.abs() < 0.5);
    assert!(motions_after(&s.pod, t0).len() >= 4);
}

#[test]
fn photos_carry_utc_and_the_geotag_the_pod_got_both_camera_target_readings() {
    for targets in [CameraTargets::Broadcast, CameraTargets::Addressed] {
        let ap = ApMavlinkConfig {
            camera_targets: targets,
            ..ApMavlinkConfig::default()
        };
        let mut s = ap_scenario(ap, PodSimConfig::default());
        s.run_until(25 * S);
        assert!(!s.pod.syncs().is_empty(), "synced before the photos");
        for _ in 0..3 {
            s.fc.take_picture();
            s.run_for(4 * S);
        }
        assert_eq!(
            s.pod.photo_requests(),
            3,
            "{targets:?}: one photo per command"
        );
        let replies = s.pod.gps_replies();
        assert_eq!(replies.len(), 3);
        let images = &s.fc.images;
        assert_eq!(images.len(), 3, "{targets:?}");
        for (i, (img, reply)) in images.iter().zip(replies).enumerate() {
            let c = &img.data;
            assert_eq!(img.header.component_id, 100);
            assert_eq!(c.capture_result.bits(), 1);
            assert_eq!(c.image_index, i as i32);
            assert_eq!(reply.reply.code.code(), AckCode::Ok);
            // The position is the geotag the pod got.
            assert_eq!((c.lat, c.lon), (reply.reply.lat_e7, reply.reply.lon_e7));
            assert_eq!(c.alt, i32::from(reply.reply.alt_msl_dm) * 100);
            assert_eq!(c.relative_alt, i32::from(reply.reply.rel_alt_dm) * 100);
            // And it is where the aircraft was at the photo's UTC.
            let photo = s.pod.photos()[i];
            let (lat, lon) = s.fc.aircraft().position_e7(photo.at_us);
            assert!(
                lat.abs_diff(c.lat) < 30 && lon.abs_diff(c.lon) < 30,
                "{c:?}"
            );
            let truth = s.fc.fc_utc_us(photo.at_us);
            assert!(
                c.time_utc.abs_diff(truth) < 10_000,
                "{} vs {truth}",
                c.time_utc
            );
            assert!(c.q.iter().all(|v| v.is_finite()));
        }
        // Each IMAGE_START_CAPTURE was ACKed (ArduPilot does not look, but it comes).
        let acks =
            s.fc.acks
                .iter()
                .filter(|a| a.data.command == MavCmd::MAV_CMD_IMAGE_START_CAPTURE)
                .collect::<Vec<_>>();
        assert_eq!(acks.len(), 3);
        assert!(
            acks.iter()
                .all(|a| a.data.result == MavResult::MAV_RESULT_ACCEPTED
                    && a.header.component_id == 100
                    && a.data.target_system == 1
                    && a.data.target_component == 1)
        );
    }
}

#[test]
fn video_zoom_and_focus_reach_the_pod() {
    let mut s = healthy_ap();
    s.fc.record_video(true);
    s.run_for(2 * S);
    let rec = s.pod.received_of::<k40t::Record>();
    assert_eq!(rec.last().unwrap().2.action, RecordAction::Start);
    assert!(s.pod.camera().recording.is_some());
    let st =
        s.fc.capture_statuses
            .last()
            .expect("capture status")
            .data
            .clone();
    assert_eq!(st.video_status, 1);
    s.fc.record_video(false);
    s.run_for(2 * S);
    assert_eq!(
        s.pod.received_of::<k40t::Record>().last().unwrap().2.action,
        RecordAction::Stop
    );
    assert_eq!(s.fc.capture_statuses.last().unwrap().data.video_status, 0);
    // Zoom: continuous in, stop; a range.
    s.fc.zoom_rate(1);
    s.run_for(S);
    s.fc.zoom_rate(0);
    s.run_for(S);
    let z: Vec<ZoomControl> = s
        .pod
        .received_of::<ContinuousZoom>()
        .iter()
        .map(|(_, _, z)| z.control)
        .collect();
    assert_eq!(z, [ZoomControl::In, ZoomControl::Stop]);
    s.fc.zoom_pct(50.0);
    s.run_for(S);
    let (_, _, h) = *s.pod.received_of::<HybridZoom>().last().unwrap();
    assert_eq!(h.zoom_x10, 805, "50 % of 1x..160x");
    // Focus: continuous far, stop, auto; range is not the pod's.
    s.fc.focus(1, 1.0);
    s.run_for(S / 2);
    s.fc.focus(1, 0.0);
    s.run_for(S / 2);
    s.fc.focus(4, 0.0);
    s.run_for(S / 2);
    let modes: Vec<FocusMode> = s
        .pod
        .received_of::<Focus>()
        .iter()
        .map(|(_, _, f)| f.mode)
        .collect();
    assert_eq!(
        modes,
        [
            FocusMode::ManualPlus,
            FocusMode::ManualStop,
            FocusMode::Auto
        ]
    );
    s.fc.focus(2, 40.0);
    s.run_for(S / 2);
    let last = s.fc.acks.last().unwrap();
    assert_eq!(last.data.command, MavCmd::MAV_CMD_SET_CAMERA_FOCUS);
    assert_eq!(last.data.result, MavResult::MAV_RESULT_UNSUPPORTED);
    assert_eq!(s.pod.received_of::<Focus>().len(), 3);
    // Every command was answered, after the pod's own ACK.
    let answered: Vec<MavResult> =
        s.fc.acks
            .iter()
            .filter(|a| a.data.command != MavCmd::MAV_CMD_REQUEST_MESSAGE)
            .map(|a| a.data.result)
            .collect();
    assert_eq!(answered.len(), 9, "{answered:?}");
    assert!(
        answered[..8]
            .iter()
            .all(|r| *r == MavResult::MAV_RESULT_ACCEPTED)
    );
}

#[test]
fn pod_lost_sets_failure_flags_and_ardupilot_calls_the_mount_unhealthy() {
    let mut s = healthy_ap();
    let cut = s.now_us;
    s.pull_pod_cable(4 * S);
    s.run_for(8 * S);
    let log = &s.fc.health_log();
    assert_eq!(log.len(), 3, "{log:?}");
    let (down, up) = (log[1], log[2]);
    assert!(
        !down.1 && down.0 - cut <= 1_600_000,
        "unhealthy {} ms after",
        (down.0 - cut) / 1000
    );
    assert!(up.1 && up.0 - (cut + 4 * S) <= 1_500_000);
    assert!(s.fc.healthy());
    // While lost: COMMS_ERROR in the status.
    let flags = s.fc.status.as_ref().unwrap().data.failure_flags.bits();
    assert_eq!(flags & 128, 0, "clear again");
    assert!(s.events.iter().any(|(_, e)| *e == Event::PodLinkDown));
}

#[test]
fn fc_silence_stops_the_pod() {
    let mut s = healthy_ap();
    s.fc.turn(15.0, 0.0);
    let pulled = Silence::CablePulled(3 * S);
    let (cut, _) = pod_stops_when_the_fc_falls_silent(&mut s, 2 * S, 10.0, pulled, 600 * MS, false);
    assert!(
        s.events
            .iter()
            .any(|(t, e)| *t > cut && matches!(e, Event::FcSilenceStop))
    );
}

#[test]
fn a_refused_photo_is_failed_in_its_ack_and_captured_with_result_0() {
    let mut s = healthy_ap();
    s.pod.set_nak(TakePhoto::ID.base, Some(AckCode::Failure));
    s.fc.take_picture();
    s.run_for(3 * S);
    let ack = s.fc.acks.last().unwrap();
    assert_eq!(ack.data.command, MavCmd::MAV_CMD_IMAGE_START_CAPTURE);
    assert_eq!(ack.data.result, MavResult::MAV_RESULT_FAILED);
    let img = s.fc.images.last().unwrap();
    assert_eq!(img.data.capture_result.bits(), 0);
    assert_eq!((img.data.lat, img.data.lon), (0, 0));
}

#[test]
fn ardupilot_old_gremsy_driver_and_timesync() {
    let ap = ApMavlinkConfig {
        old_gremsy: true,
        ..ApMavlinkConfig::default()
    };
    let mut s = ap_scenario(ap, PodSimConfig::default());
    s.run_until(25 * S);
    assert!(s.fc.healthy());
    assert_eq!(s.fc.health_log().len(), 1);
    // ArduPilot's TIMESYNC requests (every 10 s) are answered with the bridge's clock.
    let replies = &s.fc.timesync_replies;
    assert!(replies.len() >= 2, "{replies:?}");
    for (t, tc1) in replies {
        // The bridge's clock when the request came: before the reply reached ArduPilot.
        let local = s.local(*t).as_micros() as i64 * 1000;
        assert!(
            *tc1 <= local && local - tc1 < 50_000_000,
            "{tc1} vs {local}"
        );
    }
}

#[test]
fn a_plane_at_50_hz_refuses_the_autopilot_state_and_its_driver_never_moves_the_mount() {
    let ap = ApMavlinkConfig {
        vehicle: ApVehicle::Plane,
        ..ApMavlinkConfig::default()
    };
    let mut s = ap_scenario(ap, PodSimConfig::default());
    s.run_until(4 * S);
    s.fc.set_target(MountTarget::body_angles(-30.0, 0.0));
    s.run_until(20 * S);
    assert!(s.fc.mount_refused && !s.fc.mount_initialised);
    assert!(
        s.fc.sent_of(GIMBAL_DEVICE_SET_ATTITUDE_DATA::ID)
            .next()
            .is_none()
    );
    assert!(s.pod.received_of::<GimbalAngle>().is_empty());
    // The bridge's own streams (10 Hz) are within Plane's 40 Hz and come; UTC works.
    assert_eq!(s.fc.intervals.get(&SYSTEM_TIME_DATA::ID), Some(&100_000));
    assert!(!s.pod.syncs().is_empty());
}

fn px4_scenario(px4: Px4Config) -> Scenario<Px4> {
    engine_scenarios::scenario(Px4::new(px4), PodSimConfig::default(), -30)
}

#[test]
fn px4_sees_the_device_and_its_attitude_both_initial_target_readings() {
    for initial in [0, 1] {
        let px4 = Px4Config {
            initial_target_component: initial,
            ..Px4Config::default()
        };
        let mut s = px4_scenario(px4);
        s.fc.target = Some(Px4Target::Angle {
            pitch_deg: -30.0,
            yaw_deg: -20.0,
            yaw_absolute: false,
        });
        s.run_until(6 * S);
        assert_eq!(
            s.fc.gimbal_compid,
            Some(154),
            "from the information's source"
        );
        let [pmin, pmax, ymin, ymax] = s.fc.limits.unwrap();
        assert!((pmin + 90.0).abs() < 0.01 && (pmax - 30.0).abs() < 0.01);
        assert!((ymin + 180.0).abs() < 0.01 && (ymax - 180.0).abs() < 0.01);
        // Only the gimbal answered the broadcast request.
        assert!(
            s.fc.received
                .iter()
                .filter(|(_, _, id)| *id == 283)
                .all(|(_, h, _)| h.component_id == 154)
        );
        let a = last_angle(&s.pod);
        assert_eq!((a.yaw_direction, a.yaw_cdeg), (YawMotion::Left, 2000));
        assert_eq!((a.pitch_direction, a.pitch_cdeg), (PitchMotion::Down, 3000));
        let (_, pitch, yaw) = s.fc.mount_angles().unwrap();
        assert!(
            (pitch + 30.0).abs() < 0.6 && (yaw + 20.0).abs() < 0.6,
            "{pitch} {yaw}"
        );
        assert!(s.fc.healthy());
        let statuses = s.fc.statuses.iter().filter(|(t, ..)| *t >= 5 * S).count();
        assert!(statuses >= 9, "{statuses}");
        // A rate input, integrated by PX4 into its angle setpoint.
        s.fc.target = Some(Px4Target::Rate {
            pitch_dps: 0.0,
            yaw_dps: 10.0,
        });
        s.run_for(3 * S);
        let g = s.pod.gimbal();
        assert!((g.yaw_deg - 10.0).abs() < 3.0, "{g:?}");
    }
}

#[test]
fn px4_gimbal_mode_gets_time_only_when_it_honours_set_message_interval() {
    for honours in [true, false] {
        let px4 = Px4Config {
            honours_interval: honours,
            ..Px4Config::default()
        };
        let mut s = px4_scenario(px4);
        s.run_until(30 * S);
        s.fc.take_picture();
        s.run_until(33 * S);
        let syncs = s.pod.syncs().len();
        let replies = s.pod.gps_replies();
        let asked = s.fc.received.iter().filter(|(_, _, id)| *id == 76).count();
        if honours {
            assert!(syncs >= 1, "synced");
            assert_eq!(s.fc.intervals.get(&SYSTEM_TIME_DATA::ID), Some(&100_000));
            assert!(asked <= 6, "{asked}");
            let img =
                s.fc.acks
                    .iter()
                    .any(|(_, _, a)| a.command == MavCmd::MAV_CMD_IMAGE_START_CAPTURE);
            assert!(img);
            assert_eq!(replies.last().unwrap().reply.code.code(), AckCode::Ok);
        } else {
            // Mode Gimbal streams no time: no sync, nothing invented; the bridge keeps
            // asking, slowly.
            assert_eq!(syncs, 0);
            assert!(replies.iter().all(|r| r.reply.code.code() != AckCode::Ok));
            assert!((20..=40).contains(&asked), "{asked} requests in 30 s");
        }
    }
}

#[test]
fn px4_normal_mode_streams_positions_at_5_hz_and_set_attitude_at_5_hz() {
    let px4 = Px4Config {
        mode: Px4Mode::Normal,
        ..Px4Config::default()
    };
    let mut s = px4_scenario(px4);
    s.fc.target = Some(Px4Target::Angle {
        pitch_deg: -60.0,
        yaw_deg: 0.0,
        yaw_absolute: false,
    });
    s.run_until(30 * S);
    assert!((s.pod.gimbal().pitch_deg + 60.0).abs() < 0.5);
    assert!(!s.pod.syncs().is_empty());
    // The pod is never stopped between PX4's 5 Hz setpoints.
    assert!(
        !s.events
            .iter()
            .any(|(_, e)| matches!(e, Event::FcSilenceStop))
    );
}

fn ap_with_qgc() -> Scenario<ApMavlink> {
    let mut s = ap_scenario(ApMavlinkConfig::default(), PodSimConfig::default());
    s.fc.gcs = Some(Qgc::new(QgcConfig::default()));
    s
}

fn qgc(s: &mut Scenario<ApMavlink>) -> &mut Qgc {
    s.fc.gcs.as_mut().unwrap()
}

#[test]
fn qgroundcontrol_discovers_the_camera_reads_its_state_and_is_refused_the_manager() {
    let mut s = ap_with_qgc();
    s.run_until(8 * S);
    let q = qgc(&mut s);
    let cam = q.camera.as_ref().expect("camera discovered");
    assert_eq!(cam.compid, 100);
    assert!(cam.info.is_some());
    assert_eq!(cam.video_mode, Some(false));
    assert_eq!(cam.zoom_pct, Some(0.0));
    assert_eq!(cam.focus, None, "focus level unknown (NaN)");
    // The simulated pod's card: 12,207 × 10 MB.
    assert_eq!(cam.capacity_mib, Some(122_070.0));
    let cap = cam.capture.as_ref().expect("capture status");
    assert_eq!((cap.image_status, cap.video_status), (0, 0));
    // GIMBAL_MANAGER_INFORMATION asked of 154 and 100: both say UNSUPPORTED.
    let nacks: Vec<u8> = q
        .acks
        .iter()
        .filter(|(_, _, a)| {
            a.command == MavCmd::MAV_CMD_REQUEST_MESSAGE
                && a.result == MavResult::MAV_RESULT_UNSUPPORTED
        })
        .map(|(_, c, _)| *c)
        .collect();
    assert!(nacks.contains(&154) && nacks.contains(&100), "{nacks:?}");
    // The gimbal's attitude, its yaw read in the vehicle frame.
    let (_, comp, _, _, _, earth) = q.gimbal.expect("gimbal status");
    assert_eq!((comp, earth), (154, false));
}

#[test]
fn qgroundcontrol_photo_interval_mode_and_zoom() {
    let mut s = ap_with_qgc();
    s.run_until(25 * S);
    qgc(&mut s).take_photo();
    s.run_for(3 * S);
    {
        let q = qgc(&mut s);
        assert_eq!(
            q.ack_of(MavCmd::MAV_CMD_IMAGE_START_CAPTURE),
            Some(MavResult::MAV_RESULT_ACCEPTED)
        );
        let cam = q.camera.as_ref().unwrap();
        assert!(!cam.shutter_busy, "the status said idle again");
        assert_eq!(q.map_points.len(), 1);
    }
    assert_eq!(s.pod.photo_requests(), 1);
    let reply = s.pod.gps_replies().last().unwrap().reply;
    assert_eq!(
        qgc(&mut s).map_points[0],
        (
            reply.lat_e7,
            reply.lon_e7,
            i32::from(reply.alt_msl_dm) * 100
        )
    );
    // Three photos two seconds apart.
    qgc(&mut s).start_interval(2.0, 3.0);
    s.run_for(8 * S);
    assert_eq!(s.pod.photo_requests(), 4);
    assert_eq!(qgc(&mut s).map_points.len(), 4);
    let indices: Vec<i32> = qgc(&mut s)
        .images
        .iter()
        .map(|(_, i)| i.image_index)
        .collect();
    assert_eq!(indices, [0, 1, 2, 3]);
    let cap = qgc(&mut s)
        .camera
        .as_ref()
        .unwrap()
        .capture
        .clone()
        .unwrap();
    assert_eq!((cap.image_status, cap.image_count), (0, 4));
    // An open-ended interval, stopped.
    qgc(&mut s).start_interval(1.0, 0.0);
    s.run_for(S * 5 / 2);
    qgc(&mut s).stop_capture();
    s.run_for(3 * S);
    let n = s.pod.photo_requests();
    assert!((6..=8).contains(&n), "{n}");
    s.run_for(3 * S);
    assert_eq!(s.pod.photo_requests(), n, "stopped");
    // Mode, step and range zoom.
    qgc(&mut s).set_mode(true);
    qgc(&mut s).zoom(2, 25.0);
    s.run_for(6 * S);
    assert_eq!(s.pod.camera().mode, k40t::CaptureMode::Video);
    let now_x10 = s.engine.pod_state().zoom_x10();
    assert!((400..=408).contains(&now_x10), "{now_x10}");
    qgc(&mut s).zoom(0, 1.0);
    s.run_for(2 * S);
    let zooms: Vec<u16> = s
        .pod
        .received_of::<HybridZoom>()
        .iter()
        .map(|(_, _, z)| z.zoom_x10)
        .collect();
    assert_eq!(
        zooms,
        [408, now_x10 * 2],
        "25 %, then one step: twice the pod's zoom"
    );
    assert_eq!(
        qgc(&mut s).ack_of(MavCmd::MAV_CMD_SET_CAMERA_MODE),
        Some(MavResult::MAV_RESULT_ACCEPTED)
    );
    // Storage format erases: DENIED unless the configuration allows it, not retried
    // (bridge_mavlink_settings.rs has the rest).
    qgc(&mut s).format_storage();
    s.run_for(3 * S);
    assert_eq!(
        qgc(&mut s).ack_of(MavCmd::MAV_CMD_STORAGE_FORMAT),
        Some(MavResult::MAV_RESULT_DENIED)
    );
    // A retransmitted capture (same sequence number) is one photo.
    let before = s.pod.photo_requests();
    s.fc.set_target(MountTarget::Neutral);
    qgc(&mut s).command(MavCmd::MAV_CMD_IMAGE_START_CAPTURE, [0.0, 0.0, 1.0, 42.0]);
    qgc(&mut s).command(MavCmd::MAV_CMD_IMAGE_START_CAPTURE, [0.0, 0.0, 1.0, 42.0]);
    s.run_for(4 * S);
    assert_eq!(s.pod.photo_requests(), before + 1);
    let accepted = qgc(&mut s)
        .acks
        .iter()
        .filter(|(t, _, a)| *t > 40 * S && a.command == MavCmd::MAV_CMD_IMAGE_START_CAPTURE)
        .count();
    assert!(accepted >= 2);
}
