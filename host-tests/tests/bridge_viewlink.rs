//! The bridge between a simulated ArduPilot Viewpro driver (`AP_Mount_Viewpro`) and a
//! simulated K40T pod: the Viewlink side's engine scenarios, in simulated time. The
//! scenarios every FC side runs are in `engine_scenarios/mod.rs`; the bounds and the
//! Viewlink side's own are here.

use crate::engine_scenarios;

use bridge_engine::Event;
use bridge_engine::gimbal::GimbalMode;
use gimbal::sim::Autopilot;
use gimbal::sim::ap_siyi::MountTarget;
use gimbal::sim::ap_viewpro::{ApViewpro, ApViewproConfig, Tracking, TrackingStatus};
use gimbal::sim::pilot::Pilot;
use gimbal::sim::pod::{OutputFaults, PodSimConfig};
use gimbal::sim::scenario::Scenario;

use engine_scenarios::{
    MS, Noise, S, damage_counted, healthy, healthy_within, one_photo_geotagged, one_sync_per_edge,
    pod_loss_then_recovery, stays_healthy, sync_errors_us, zoom_in_then_stop,
};
use protocol_core::k40t::{
    self, AckCode, ContinuousZoom, DialSpeed, Focus, FocusMode, GimbalAngle, GimbalControl,
    GimbalFunction, HybridZoom, ImageModeSetting, IrDigitalZoom, IrPalette, LaserPeriodic,
    LaserRange, MessageData as _, PitchMotion, PointToAim, Record, RecordAction, TakePhoto, Toggle,
    TrackBox, YawMotion, ZoomControl,
};
use protocol_core::viewlink::{
    A1, A2, AbsoluteAngle, C1, C2, Control, ControlTgcc, E1, E2, LaserCommand, LaserControl,
    LrfCommand, OperationCommand, RareControl, RareControlTgcc, RelativeAngle, S1, S2, S2Command,
    SdCommand, SdQuery, SdQueryItem, Sensor, ServoAction, ServoCommand, TrackingCommand,
    TrackingSource, Zoom,
};

fn scenario(ap: ApViewproConfig, pod: PodSimConfig, bridge_ppm: i64) -> Scenario<ApViewpro> {
    engine_scenarios::scenario(ApViewpro::new(ap), pod, bridge_ppm)
}

fn healthy_scenario_with(pod: PodSimConfig) -> Scenario<ApViewpro> {
    healthy(scenario(ApViewproConfig::default(), pod, 30), 3 * S)
}

fn healthy_scenario() -> Scenario<ApViewpro> {
    healthy_scenario_with(PodSimConfig::default())
}

/// A C1 block as a console sends it.
fn c1(sensor: Sensor, operation: OperationCommand, lrf: LrfCommand) -> C1 {
    C1 {
        sensor,
        zoom_speed: 0,
        operation,
        lrf,
    }
}

fn last_of<M: k40t::MessageData<Protocol = k40t::K40t>>(s: &Scenario<ApViewpro>) -> Option<M> {
    s.pod.received_of::<M>().last().map(|(_, _, m)| *m)
}

#[test]
fn ardupilot_is_healthy_within_a_second_and_reads_the_identity() {
    let mut s = scenario(ApViewproConfig::default(), PodSimConfig::default(), -40);
    s.run_until(3 * S);
    // The pod reports from t = 0: healthy at the driver's second run (it reads its UART
    // every 100 ms, so the 0x40 answering its first handshake is read at the next run).
    healthy_within(&s, S);
    let ap = &s.fc;
    assert_eq!(ap.model.as_deref(), Some("K40TBRIDGE"));
    // The bridge's version, as ArduPilot reads it from the 0xD0 text.
    let v = bridge_engine::version::Version::parse(env!("CARGO_PKG_VERSION")).unwrap();
    assert_eq!(ap.firmware, Some((v.major, v.minor, v.patch)));
    // The queries stop once answered (at the second run: one sent at each of the first
    // two runs at most).
    let queries = ap.sent.iter().filter(|(_, id, _)| *id == 0x01).count();
    assert!(queries <= 4, "{queries} U queries");
    // Replies: V 0xE4 (11 data bytes), V 0xD0 (21), and one 0x40 of 41 data bytes per
    // run of the driver.
    let v: Vec<_> = ap.received.iter().filter(|r| r.id == 0x02).collect();
    assert!(v.iter().any(|r| r.data[0] == 0xE4 && r.data.len() == 11));
    assert!(v.iter().any(|r| r.data[0] == 0xD0 && r.data.len() == 21));
    let status = ap.received.iter().filter(|r| r.id == 0x40).count();
    let handshakes = ap.sent.iter().filter(|(_, id, _)| *id == 0x00).count();
    assert!(
        status + 1 >= handshakes,
        "{status} 0x40 for {handshakes} handshakes"
    );
    assert!(
        ap.received
            .iter()
            .all(|r| r.id != 0x40 || r.data.len() == 41)
    );
    assert_eq!((ap.short_status, ap.parse_errors()), (0, 0));
    // The frame counter of a Viewlink sender: 1, 2, 3, 0, 1, ... over every reply.
    for (i, r) in ap.received.iter().enumerate() {
        assert_eq!(r.counter, ((i + 1) % 4) as u8, "reply {i}");
    }
    // It stays healthy.
    stays_healthy(&mut s, 60 * S);
    assert_eq!(s.fc.short_status, 0);
}

#[test]
fn healthy_within_a_second_of_the_pod_reporting() {
    let mut s = scenario(ApViewproConfig::default(), PodSimConfig::default(), 20);
    s.pod.set_silent(true);
    s.run_until(4 * S);
    assert!(s.fc.health_log().is_empty(), "no pod, no 0x40");
    assert!(s.fc.received.iter().all(|r| r.id != 0x40));
    // The identity does not depend on the pod.
    assert!(s.fc.model.is_some() && s.fc.firmware.is_some());
    s.pod.set_silent(false);
    let on = s.now_us;
    s.run_for(2 * S);
    let (t, up) = s.fc.health_log()[0];
    assert!(up);
    assert!(
        t - on < S,
        "healthy {} ms after the pod's first report",
        (t - on) / MS
    );
}

#[test]
fn rates_reach_the_pod_and_the_attitude_comes_back_in_ardupilots_convention() {
    let mut s = healthy_scenario();
    s.fc.turn(18.0, -9.0);
    s.run_for(S);
    // 18 deg/s (1800 on the wire) -> dial 90 (0.2 deg/s units); pitch -9 deg/s is sent
    // as +900 (ArduPilot negates) -> down at 45.
    let d = last_of::<DialSpeed>(&s).expect("a dial speed");
    assert_eq!((d.yaw_dps_x5, d.pitch_dps_x5), (90, 45));
    let c = last_of::<GimbalControl>(&s).unwrap();
    assert_eq!((c.yaw, c.pitch), (YawMotion::Right, PitchMotion::Down));
    // The pod turns right and down; ArduPilot reads the same, in its convention.
    s.run_for(S);
    let a = s.fc.attitude.unwrap();
    let g = s.pod.gimbal();
    assert!(a.yaw_deg > 20.0, "AP yaw {}, pod {g:?}", a.yaw_deg);
    assert!(a.pitch_deg < -10.0, "AP pitch {}", a.pitch_deg);
    // ArduPilot's reading lags: the pod reports at 10 Hz, the driver reads at 10 Hz what
    // came during its last 100 ms: up to about 250 ms at 18 deg/s.
    assert!(
        (a.yaw_deg - g.yaw_deg).abs() < 5.0,
        "AP {} pod {}",
        a.yaw_deg,
        g.yaw_deg
    );
    assert!((a.pitch_deg - g.pitch_deg).abs() < 2.5);
    assert!(a.roll_deg.abs() < 0.1, "level: {}", a.roll_deg);
    // ArduPilot repeats the same rates at 10 Hz: no flood.
    let before = s.pod.received_count(GimbalControl::ID.to_u32());
    s.run_for(5 * S);
    let during = s.pod.received_count(GimbalControl::ID.to_u32()) - before;
    assert!(during <= 6, "{during} motion frames in 5 s");
    // Faster than the pod can turn: clamped to 30 deg/s, and said so.
    s.fc.turn(-60.0, 0.0);
    s.run_for(S);
    let d = last_of::<DialSpeed>(&s).unwrap();
    assert_eq!(d.yaw_dps_x5, 150);
    assert_eq!(last_of::<GimbalControl>(&s).unwrap().yaw, YawMotion::Left);
    assert!(
        !s.events_where(|e| matches!(
            e,
            Event::RateClamped {
                requested_cdeg_s: -6000
            }
        ))
        .is_empty()
    );
    // Zero rates stop the pod.
    s.fc.turn(0.0, 0.0);
    s.run_for(S);
    let c = last_of::<GimbalControl>(&s).unwrap();
    assert_eq!((c.yaw, c.pitch), (YawMotion::Stop, PitchMotion::Stop));
    assert_eq!(s.pod.gimbal().yaw_rate_dps, 0.0);
}

#[test]
fn angles_reach_the_pod_as_0x000012_and_lock_and_follow_set_the_mode() {
    let mut s = healthy_scenario();
    s.fc.point(30.0, -45.0);
    s.run_for(S);
    let a = last_of::<GimbalAngle>(&s).expect("an angle command");
    assert_eq!(
        (a.yaw_direction, a.yaw_cdeg, a.pitch_direction, a.pitch_cdeg),
        (YawMotion::Right, 3000, PitchMotion::Down, 4500)
    );
    // Repeated at 10 Hz by ArduPilot: one command, not one per frame (issue 22892).
    s.run_for(5 * S);
    assert_eq!(s.pod.received_of::<GimbalAngle>().len(), 1);
    let g = s.pod.gimbal();
    assert!(
        (g.yaw_deg - 30.0).abs() < 0.1 && (g.pitch_deg + 45.0).abs() < 0.1,
        "{g:?}"
    );
    let r = s.fc.attitude.unwrap();
    assert!(
        (r.yaw_deg - 30.0).abs() < 0.1 && (r.pitch_deg + 45.0).abs() < 0.1,
        "{r:?}"
    );
    // Earth-frame rates: ArduPilot sends "follow yaw disabled" (lock) once first.
    s.fc.target = Some(MountTarget::Rate {
        yaw_dps: 5.0,
        pitch_dps: 0.0,
        yaw_is_ef: true,
    });
    s.run_for(2 * S);
    let locks =
        s.fc.sent
            .iter()
            .filter(|(_, id, d)| *id == 0x1A && d[0] == 0x0A)
            .count();
    assert_eq!(locks, 1);
    assert_eq!(s.engine.pod_state().mode, Some(GimbalMode::Lock));
    s.fc.turn(5.0, 0.0);
    s.run_for(S);
    assert_eq!(s.engine.pod_state().mode, Some(GimbalMode::Follow));
}

#[test]
fn fc_silence_stops_the_pod() {
    engine_scenarios::fc_silence_stops_the_turning_pod(&mut healthy_scenario());
}

#[test]
fn camera_commands_reach_the_pod_and_their_state_comes_back() {
    let mut s = healthy_scenario();
    // Photo.
    s.fc.take_picture();
    s.run_for(S);
    let photo = s.pod.received_of::<TakePhoto>();
    assert_eq!(photo.len(), 1);
    assert_eq!(photo[0].2.action, k40t::ShootAction::Start);
    assert_eq!(s.pod.photos().len(), 1);
    // Record start: the pod records, D1 says so, ArduPilot reads it.
    assert!(!s.fc.recording);
    s.fc.record(true);
    s.run_for(S);
    assert_eq!(last_of::<Record>(&s).unwrap().action, RecordAction::Start);
    assert!(s.pod.camera().recording.is_some());
    assert!(s.fc.recording, "D1 byte 32 & 7 == 1");
    s.fc.record(false);
    s.run_for(2 * S);
    assert_eq!(last_of::<Record>(&s).unwrap().action, RecordAction::Stop);
    assert!(!s.fc.recording);
    // Zoom rate: continuous zoom in, then stop; the ratio comes back x0.1 in D1.
    let z = zoom_in_then_stop(&mut s);
    assert_eq!(z, vec![ZoomControl::In, ZoomControl::Stop]);
    let pod_zoom = f64::from(s.engine.pod_state().zoom_x10()) / 10.0;
    assert!(pod_zoom > 2.0, "{pod_zoom}");
    assert!(
        (s.fc.zoom_times - pod_zoom).abs() < 0.05,
        "AP {} pod {pod_zoom}",
        s.fc.zoom_times
    );
    // Absolute zoom: ArduPilot's percentage of 10x (50 % = 5.0x).
    s.fc.set_zoom_pct(50.0);
    s.run_for(6 * S);
    assert_eq!(last_of::<HybridZoom>(&s).unwrap().zoom_x10, 50);
    assert!((s.fc.zoom_times - 5.0).abs() < 0.05, "{}", s.fc.zoom_times);
    // Focus: +, stop (a focus stop, not a zoom stop), -, autofocus.
    s.fc.set_focus_rate(1.0);
    s.run_for(S / 2);
    s.fc.set_focus_rate(0.0);
    s.run_for(S / 2);
    s.fc.set_focus_rate(-1.0);
    s.run_for(S / 2);
    s.fc.autofocus();
    s.run_for(S);
    let f: Vec<_> = s
        .pod
        .received_of::<Focus>()
        .into_iter()
        .map(|(_, _, f)| f.mode)
        .collect();
    assert_eq!(
        f,
        vec![
            FocusMode::ManualPlus,
            FocusMode::ManualStop,
            FocusMode::ManualMinus,
            FocusMode::Auto
        ]
    );
    assert_eq!(s.pod.received_of::<ContinuousZoom>().len(), 2);
    // Rangefinder: continuous ranging; the distance comes back in 0.1 m.
    s.pod.set_laser_distance_dm(4321);
    s.fc.set_rangefinder_enable(true);
    s.run_for(2 * S);
    assert_eq!(
        last_of::<LaserPeriodic>(&s).unwrap().enable,
        k40t::OnOff::On
    );
    assert!(
        (s.fc.rangefinder_m - 432.1).abs() < 0.01,
        "{}",
        s.fc.rangefinder_m
    );
    s.fc.set_rangefinder_enable(false);
    s.run_for(3 * S);
    assert_eq!(
        last_of::<LaserPeriodic>(&s).unwrap().enable,
        k40t::OnOff::Off
    );
    assert_eq!(s.fc.rangefinder_m, 0.0, "no fresh distance: 0 (invalid)");
}

#[test]
fn sensor_selection_and_thermal_zoom() {
    let mut s = healthy_scenario();
    assert_eq!(s.fc.image_sensor, 1, "EO1 at start");
    // Lens 1 = IR.
    s.fc.set_lens(1);
    s.run_for(2 * S);
    assert_eq!(
        last_of::<ImageModeSetting>(&s).unwrap().mode,
        k40t::ImageMode::Infrared
    );
    assert_eq!(s.fc.image_sensor, 2);
    assert_eq!(s.fc.zoom_times, 1.0, "IR zoom x1");
    // IR zoom in (0x1B with the IR sensor): thermal digital zoom x2, read back.
    s.fc.set_zoom_rate(1.0);
    s.run_for(S);
    assert_eq!(last_of::<IrDigitalZoom>(&s).unwrap().zoom_x, 2);
    assert_eq!(s.fc.zoom_times, 2.0);
    s.fc.set_zoom_rate(1.0);
    s.run_for(S);
    assert_eq!(last_of::<IrDigitalZoom>(&s).unwrap().zoom_x, 3);
    s.fc.set_zoom_rate(-1.0);
    s.run_for(S);
    assert_eq!(last_of::<IrDigitalZoom>(&s).unwrap().zoom_x, 2);
    assert_eq!(s.fc.zoom_times, 2.0);
    // A photo now carries the IR sensor, which is no change.
    let modes = s.pod.received_of::<ImageModeSetting>().len();
    s.fc.take_picture();
    s.run_for(S);
    assert_eq!(s.pod.received_of::<ImageModeSetting>().len(), modes);
    // Camera source RGB + IR picture in picture.
    assert!(s.fc.set_camera_source(1, 2));
    s.run_for(2 * S);
    assert_eq!(
        last_of::<ImageModeSetting>(&s).unwrap().mode,
        k40t::ImageMode::Split
    );
    assert_eq!(s.fc.image_sensor, 3);
    // Back to RGB.
    s.fc.set_lens(0);
    s.run_for(2 * S);
    assert_eq!(
        last_of::<ImageModeSetting>(&s).unwrap().mode,
        k40t::ImageMode::Visible
    );
    assert_eq!(s.fc.image_sensor, 1);
}

#[test]
fn console_commands_and_combined_frames() {
    let mut s = healthy_scenario();
    let send_c1 = |s: &mut Scenario<ApViewpro>, op, lrf| {
        s.fc.send_raw(&c1(Sensor::NoAction, op, lrf));
        s.run_for(S / 2);
    };
    // Palettes: the three named ones and the first extension.
    send_c1(&mut s, OperationCommand::IrBlackHot, LrfCommand::NoAction);
    assert_eq!(
        last_of::<IrPalette>(&s).unwrap().palette,
        k40t::Palette::BlackHot
    );
    send_c1(&mut s, OperationCommand::IrRainbow, LrfCommand::NoAction);
    assert_eq!(
        last_of::<IrPalette>(&s).unwrap().palette,
        k40t::Palette::Rainbow
    );
    send_c1(&mut s, OperationCommand::IrColorExt1, LrfCommand::NoAction);
    assert_eq!(
        last_of::<IrPalette>(&s).unwrap().palette,
        k40t::Palette::HighContrastRed
    );
    send_c1(&mut s, OperationCommand::IrWhiteHot, LrfCommand::NoAction);
    assert_eq!(
        last_of::<IrPalette>(&s).unwrap().palette,
        k40t::Palette::WhiteHot
    );
    // Manual focus mode, single ranging.
    send_c1(&mut s, OperationCommand::ManualFocus, LrfCommand::Single);
    assert_eq!(last_of::<Focus>(&s).unwrap().mode, FocusMode::ManualStop);
    assert_eq!(
        last_of::<LaserRange>(&s).unwrap().mode,
        k40t::LaserMode::Single
    );
    // C2: thermal zoom 4.0x, laser on and off.
    s.fc.send_raw(&C2::SetIrZoom(Zoom { zoom_x10: 40 }));
    s.run_for(S / 2);
    assert_eq!(last_of::<IrDigitalZoom>(&s).unwrap().zoom_x, 4);
    s.fc.send_raw(&C2::Laser(LaserControl {
        command: LaserCommand::On,
        reserved: 0,
    }));
    s.run_for(S / 2);
    assert_eq!(
        last_of::<LaserPeriodic>(&s).unwrap().enable,
        k40t::OnOff::On
    );
    // A1 actions: look down, home; a relative angle from where the gimbal is.
    s.fc.send_raw(&A1::plain(ServoCommand::LookDown));
    s.run_for(3 * S);
    assert_eq!(
        last_of::<GimbalControl>(&s).unwrap().function,
        GimbalFunction::LookDown
    );
    assert!((s.pod.gimbal().pitch_deg + 90.0).abs() < 0.1);
    s.fc.send_raw(&A1::plain(ServoCommand::Home));
    s.run_for(3 * S);
    assert_eq!(
        last_of::<GimbalControl>(&s).unwrap().function,
        GimbalFunction::Center
    );
    assert!(s.pod.gimbal().pitch_deg.abs() < 0.1);
    // Relative: 20 deg right, 10 deg down (positive down), repeated by a console at
    // 10 Hz: it moves once, not 20 deg per frame.
    for _ in 0..10 {
        s.fc.send_raw(&A1::RelativeAngle(RelativeAngle {
            yaw_speed_ddeg_s: 0,
            yaw_bam16: (20.0 * 65536.0 / 360.0) as i16,
            pitch_speed_ddeg_s: 0,
            pitch_bam16: (10.0 * 65536.0 / 360.0) as i16,
        }));
        s.run_for(100 * MS);
    }
    s.run_for(2 * S);
    let g = s.pod.gimbal();
    assert!(
        (g.yaw_deg - 20.0).abs() < 0.1 && (g.pitch_deg + 10.0).abs() < 0.1,
        "{g:?}"
    );
    // 0x30, A1 + C1 + E1 in one frame, the document's layout: angles and a photo.
    let photos = s.pod.photos().len();
    s.fc.send_raw(&Control {
        a1: A1::AbsoluteAngle(AbsoluteAngle {
            yaw_bam16: 0x3FFC,
            pitch_bam16: 0x1000,
            reserved: [0; 4],
        }),
        c1: c1(
            Sensor::NoAction,
            OperationCommand::TakePicture,
            LrfCommand::NoAction,
        ),
        e1: E1::new(TrackingSource::NoAction, TrackingCommand::NoAction),
    });
    s.run_for(3 * S);
    let a = last_of::<GimbalAngle>(&s).unwrap();
    assert_eq!(
        (a.yaw_direction, a.yaw_cdeg, a.pitch_direction, a.pitch_cdeg),
        (YawMotion::Right, 8998, PitchMotion::Down, 2250)
    );
    assert_eq!(s.pod.photos().len(), photos + 1);
    // 0x31 with A2 asking for the infrequent status: one 0x41 in reply, with the
    // A2 counter echoed in B2; its C2 zooms to 3.0x.
    s.fc.send_raw(&RareControl {
        a2: A2 {
            action: ServoAction::NoAction,
            request_status: true,
            counter: 2,
            adjustment_mdeg: 0,
        },
        c2: C2::SetEoZoom(Zoom { zoom_x10: 30 }),
        e2: E2::default(),
    });
    s.run_for(S);
    assert_eq!(last_of::<HybridZoom>(&s).unwrap().zoom_x10, 30);
    let rare: Vec<_> = s.fc.received.iter().filter(|r| r.id == 0x41).collect();
    assert_eq!(rare.len(), 1);
    assert_eq!(rare[0].data.len(), 49);
    assert_eq!(rare[0].data[33] >> 6, 2, "B2 counter");
    // 0x32 and 0x33 carry S1 / S2 behind: the control blocks act, S1/S2 do nothing.
    s.fc.send_raw(&ControlTgcc {
        a1: A1::plain(ServoCommand::NoChange),
        c1: c1(
            Sensor::NoAction,
            OperationCommand::TakePicture,
            LrfCommand::NoAction,
        ),
        e1: E1::default(),
        s1: S1::default(),
    });
    s.fc.send_raw(&RareControlTgcc {
        a2: A2::default(),
        c2: C2::SetEoZoom(Zoom { zoom_x10: 20 }),
        e2: E2::default(),
        s2: S2 {
            command: S2Command::NoAction,
            params: [0; 4],
        },
    });
    s.run_for(S);
    assert_eq!(s.pod.photos().len(), photos + 2);
    assert_eq!(last_of::<HybridZoom>(&s).unwrap().zoom_x10, 20);
    // A frame the K40T cannot serve (SD card query) is counted, not answered.
    let ignored = s.engine.counters().fc_ignored;
    s.fc.send_raw(&SdQuery {
        command: SdCommand::Query,
        item: SdQueryItem::Status,
    });
    s.run_for(S / 2);
    assert_eq!(s.engine.counters().fc_ignored, ignored + 1);
    assert!(s.fc.received.iter().all(|r| r.id != 0xD5));
}

#[test]
fn tracking_a_point_and_a_box() {
    let mut s = healthy_scenario_with(PodSimConfig {
        track_requires_ai: false,
        ..PodSimConfig::default()
    });
    s.fc.turn(0.0, 0.0);
    s.run_for(S);
    // A point a quarter from the left, three quarters down: pixel (480, 810).
    s.fc.set_tracking(Tracking::Point(0.25, 0.75));
    s.run_for(S);
    let t = last_of::<TrackBox>(&s).expect("a track box");
    assert_eq!(t.enable, Toggle::On);
    assert_eq!((t.x + t.width / 2, t.y + t.height / 2), (480, 810));
    assert!(s.pod.camera().track.is_some());
    // The tracker state comes back; ArduPilot stops sending targets while tracking.
    assert_eq!(s.fc.tracking, TrackingStatus::Tracking);
    let a1_before = s.fc.sent.iter().filter(|(_, id, _)| *id == 0x1A).count();
    s.run_for(2 * S);
    let a1_after = s.fc.sent.iter().filter(|(_, id, _)| *id == 0x1A).count();
    assert_eq!(a1_before, a1_after, "no targets while tracking");
    assert!(s.events_where(|e| *e == Event::FcSilenceStop).is_empty());
    // Stop.
    s.fc.set_tracking(Tracking::None);
    s.run_for(S);
    assert_eq!(last_of::<TrackBox>(&s).unwrap().enable, Toggle::Off);
    assert_eq!(s.fc.tracking, TrackingStatus::Stopped);
    assert!(s.fc.sent.iter().filter(|(_, id, _)| *id == 0x1A).count() > a1_after);
    // A rectangle: top-left (0.25, 0.25), bottom-right (0.75, 0.5).
    s.fc.set_tracking(Tracking::Rectangle((0.25, 0.25), (0.75, 0.5)));
    s.run_for(S);
    let t = last_of::<TrackBox>(&s).unwrap();
    assert_eq!(
        (t.enable, t.x, t.y, t.width, t.height),
        (Toggle::On, 480, 270, 960, 270)
    );
    assert_eq!(s.fc.tracking, TrackingStatus::Tracking);
    s.fc.set_tracking(Tracking::None);
    s.run_for(S);
    // A tracking start alone (a console's E1): the centre of the picture.
    s.fc.send_raw(&E1::new(TrackingSource::Eo1, TrackingCommand::Start));
    s.run_for(S);
    let t = last_of::<TrackBox>(&s).unwrap();
    assert_eq!(
        (t.enable, t.x + t.width / 2, t.y + t.height / 2),
        (Toggle::On, 960, 540)
    );
    s.fc.set_tracking(Tracking::None);
    s.run_for(S);
    // A point without a tracking start: point to aim.
    s.fc.send_raw(&E2::TrackPoint(protocol_core::viewlink::Point {
        x_px: 480,
        y_px: -270,
    }));
    s.run_for(S);
    let p = last_of::<PointToAim>(&s).expect("point to aim");
    assert_eq!((p.x, p.y), (1440, 270));
    assert_eq!(s.fc.tracking, TrackingStatus::Stopped);
}

#[test]
fn tracking_switches_ai_recognition_on_first() {
    // The K40T tracks a box only with AI recognition on (0x000324's note): the bridge
    // switches it on before the first box, once.
    let mut s = healthy_scenario();
    s.fc.set_tracking(Tracking::Point(0.5, 0.5));
    s.run_for(2 * S);
    let ai = s.pod.received_of::<k40t::AiRecognition>();
    let boxes = s.pod.received_of::<TrackBox>();
    assert_eq!(ai.len(), 1);
    assert_eq!(ai[0].2.enable, Toggle::On);
    assert_eq!(ai[0].2.classes, [0, 1, 2, 3, 4, 5, 6, 7, 8, 9]);
    assert!(ai[0].0 <= boxes[0].0, "AI on before the box");
    assert!(s.pod.camera().track.is_some());
    assert_eq!(s.fc.tracking, TrackingStatus::Tracking);
    assert!(s.engine.pod_state().ai);
    // Stop and track again: AI is already on.
    s.fc.set_tracking(Tracking::None);
    s.run_for(S);
    s.fc.set_tracking(Tracking::Point(0.25, 0.25));
    s.run_for(S);
    assert_eq!(s.pod.received_of::<k40t::AiRecognition>().len(), 1);
    assert_eq!(s.fc.tracking, TrackingStatus::Tracking);
}

#[test]
fn tracking_refused_by_the_pod_is_reported_stopped() {
    let mut nak = std::collections::BTreeMap::new();
    nak.insert(0x0324, AckCode::Failure);
    let mut s = healthy_scenario_with(PodSimConfig {
        nak,
        ..PodSimConfig::default()
    });
    s.fc.set_tracking(Tracking::Point(0.5, 0.5));
    s.run_for(2 * S);
    assert_eq!(last_of::<TrackBox>(&s).unwrap().enable, Toggle::On);
    assert!(
        !s.events_where(|e| matches!(e, Event::PodRefused { base: 0x0324, .. }))
            .is_empty()
    );
    assert_eq!(s.fc.tracking, TrackingStatus::Stopped);
}

#[test]
fn edge_trigger_a_repeated_control_value_is_not_a_new_action() {
    let mut s = healthy_scenario();
    // A console repeats "zoom in" at 10 Hz for a second: one zoom command.
    for _ in 0..10 {
        s.fc.send_raw(&C1 {
            zoom_speed: 7,
            ..c1(
                Sensor::NoAction,
                OperationCommand::ZoomIn,
                LrfCommand::NoAction,
            )
        });
        s.run_for(100 * MS);
    }
    assert_eq!(s.pod.received_of::<ContinuousZoom>().len(), 1);
    // "No action" re-arms: the next zoom in acts at once.
    s.fc.send_raw(&c1(
        Sensor::NoAction,
        OperationCommand::NoAction,
        LrfCommand::NoAction,
    ));
    s.run_for(100 * MS);
    s.fc.send_raw(&c1(
        Sensor::NoAction,
        OperationCommand::ZoomIn,
        LrfCommand::NoAction,
    ));
    s.run_for(100 * MS);
    assert_eq!(s.pod.received_of::<ContinuousZoom>().len(), 2);
    s.fc.send_raw(&c1(
        Sensor::NoAction,
        OperationCommand::StopZoomFocus,
        LrfCommand::NoAction,
    ));
    s.run_for(S);
    assert_eq!(
        last_of::<ContinuousZoom>(&s).unwrap().control,
        ZoomControl::Stop
    );
    // A console streams 0x30 with "take picture" held for 2 s: one photo.
    let photos = s.pod.photos().len();
    let frame = Control {
        a1: A1::plain(ServoCommand::NoChange),
        c1: c1(
            Sensor::NoAction,
            OperationCommand::TakePicture,
            LrfCommand::NoAction,
        ),
        e1: E1::default(),
    };
    for _ in 0..20 {
        s.fc.send_raw(&frame);
        s.run_for(100 * MS);
    }
    s.run_for(S);
    assert_eq!(s.pod.photos().len(), photos + 1);
    // ArduPilot's photos, one per user action, a second apart: each one a photo; two
    // within the repeat window (300 ms): one.
    s.fc.take_picture();
    s.run_for(S);
    s.fc.take_picture();
    s.run_for(S);
    assert_eq!(s.pod.received_of::<TakePhoto>().len(), photos + 3);
    s.fc.take_picture();
    s.run_for(100 * MS);
    s.fc.take_picture();
    s.run_for(S);
    assert_eq!(s.pod.received_of::<TakePhoto>().len(), photos + 4);
}

#[test]
fn pod_loss_makes_ardupilot_unhealthy_and_recovery_healthy_again() {
    let mut s = healthy_scenario();
    // Attitude older than 0.5 s is not reported, the driver waits 1 s more (down within
    // 1.8 s); back within 1 s.
    pod_loss_then_recovery(&mut s, 1_800 * MS, 3 * S, S, |_| {});
}

#[test]
fn photos_are_geotagged_with_the_position_and_attitude_of_m_ahrs() {
    let mut s = scenario(
        ApViewproConfig {
            ppm: 30.0,
            ..ApViewproConfig::default()
        },
        PodSimConfig::default(),
        -20,
    );
    s.run_until(90 * S);
    assert!(s.pod.is_synced(), "a time sync was applied");
    s.fc.take_picture();
    let (r, photo_t) = one_photo_geotagged(&mut s);
    // Heading 45 deg (M carries whole degrees), pitch -3 deg (sent negated, read back),
    // roll 5 sin(t/2) deg; MSL 488 m, relative 0 (level flight from the first fix).
    assert!((r.pitch_cdeg + 300).abs() <= 1, "{}", r.pitch_cdeg);
    let (roll, ..) = s.fc.aircraft().attitude_deg(photo_t);
    assert!(
        (f64::from(r.roll_cdeg) / 100.0 - roll).abs() < 0.5,
        "{} vs {roll}",
        r.roll_cdeg
    );
    assert_eq!((r.alt_msl_dm, r.rel_alt_dm), (4880, 0));
}

/// |UTC of the 0x00030E the pod applied − the FC's UTC at the edge's true time|, over
/// every edge from 60 s after start, for one flight.
fn sync_errors(seed: u64) -> Vec<f64> {
    let ap = ApViewproConfig {
        ppm: [35.0, -42.0, 12.0, -8.0, 49.0, -27.0][(seed % 6) as usize],
        seed,
        // Vary the FC's UTC phase against its loop from flight to flight.
        utc_at_zero_us: 1_795_428_000_000_000 + seed * 1_777_777,
        ..ApViewproConfig::default()
    };
    let bridge_ppm = [-25, 40, -48, 15, 3, -33][(seed % 6) as usize];
    let mut s = scenario(ap, PodSimConfig::default(), bridge_ppm);
    s.run_until(600 * S);
    let edges = one_sync_per_edge(&s);
    assert!(edges >= 50, "{edges} edges in 10 min");
    sync_errors_us(&s, 60 * S)
        .into_iter()
        .map(|e| e as f64 / 1000.0)
        .collect()
}

/// Time sync accuracy through the whole engine: six 10-minute flights with drifting FC
/// and bridge clocks, ArduPilot's 10 Hz M_AHRS (UTC truncated to 10 ms and read in
/// phase with its loop), 0..10 ms transport jitter. The discipline centres the
/// truncation, so each flight's error is a constant within ±5 ms (its read phase):
/// the 1 ms goal is out of reach with this source (see `timesync_sim.rs`); the test
/// asserts that bound and prints the figures.
#[test]
fn time_sync_accuracy_over_several_flights() {
    let mut all = Vec::new();
    let mut per_flight = Vec::new();
    for seed in 1..=6 {
        let e = sync_errors(seed);
        let spread =
            e.iter().copied().fold(f64::MIN, f64::max) - e.iter().copied().fold(f64::MAX, f64::min);
        per_flight.push(format!(
            "{:+.2}..{:+.2}",
            e.iter().copied().fold(f64::MAX, f64::min),
            e.iter().copied().fold(f64::MIN, f64::max)
        ));
        assert!(
            spread < 2.0,
            "seed {seed}: error spread {spread} ms within a flight"
        );
        all.extend(e);
    }
    let mut abs: Vec<f64> = all.iter().map(|e| e.abs()).collect();
    abs.sort_by(f64::total_cmp);
    let q = |p: f64| abs[((abs.len() - 1) as f64 * p).round() as usize];
    println!(
        "Viewlink time sync, engine scenarios: {} edges, |err| p50 {:.3} ms, p99 {:.3} ms, \
         max {:.3} ms; per-flight signed range (ms) [{}]",
        abs.len(),
        q(0.5),
        q(0.99),
        q(1.0),
        per_flight.join(" ")
    );
    assert!(q(1.0) < 6.0, "max {} ms", q(1.0));
}

#[test]
fn garbage_and_bit_flips_on_both_ports() {
    let mut s = healthy_scenario();
    let mut noise = Noise(0x9E37_79B9_7F4A_7C15);
    // FC to bridge: garbage before 30 % of the bursts, a bit flipped in 20 %.
    s.fc_line
        .damage
        .set_corrupter(Box::new(move |_, bytes: &[u8]| {
            let mut out = Vec::new();
            if noise.next() % 10 < 3 {
                let n = (noise.next() % 24) as usize + 1;
                out.extend(noise.bytes(n));
            }
            let mut b = bytes.to_vec();
            if noise.next() % 10 < 2 && !b.is_empty() {
                let i = (noise.next() % b.len() as u64) as usize;
                b[i] ^= 1 << (noise.next() % 8);
            }
            out.extend(b);
            out
        }));
    // Pod to bridge: garbage before 30 % of the frames, a bit flipped in 10 %.
    s.pod.set_output_faults(OutputFaults {
        seed: 7,
        garbage_probability: 0.3,
        max_garbage_len: 24,
        bit_flip_probability: 0.1,
    });
    let before = s.engine.counters();
    s.run_for(60 * S);
    // ArduPilot stays healthy throughout; commands still go through.
    assert_eq!(s.fc.health_log().len(), 1, "{:?}", s.fc.health_log());
    let c = s.engine.counters();
    damage_counted(&before, &c);
    assert_eq!(c.dropped, 0, "no output dropped");
    let (garbage, flips) = s.pod.faults_injected();
    assert!(garbage > 100 && flips > 50, "{garbage} {flips}");
    s.fc_line.damage.clear_corrupter();
    s.fc.take_picture();
    s.run_for(S);
    assert!(!s.pod.received_of::<TakePhoto>().is_empty());
}

#[test]
fn floods_on_both_ports() {
    let mut s = healthy_scenario();
    let mut noise = Noise(12345);
    let before = s.engine.counters();
    // 10 s of random bytes at 87 % of the baud rate on both lines into the bridge,
    // around the driver's and the pod's own traffic.
    for _ in 0..1000 {
        let now = s.now_us;
        s.fc_line.send(now, &noise.bytes(100));
        s.pod_line.send(now, &noise.bytes(100));
        s.run_for(10 * MS);
    }
    assert_eq!(s.fc.health_log().len(), 1, "{:?}", s.fc.health_log());
    let c = s.engine.counters();
    assert!(
        c.fc_garbage_bytes - before.fc_garbage_bytes > 50_000,
        "{c:?}"
    );
    assert!(
        c.pod_garbage_bytes - before.pod_garbage_bytes > 50_000,
        "{c:?}"
    );
    // A flood of valid frames: the same "zoom in" back to back at 90 % of the baud rate
    // for 3 s. One pod command; one status reply per 50 ms at most; no queue
    // overflows.
    let zooms = s.pod.received_of::<ContinuousZoom>().len();
    let status_before = s.fc.received.iter().filter(|r| r.id == 0x40).count();
    let mut frame = [0u8; 16];
    let n = protocol_core::viewlink::encode(
        &c1(
            Sensor::NoAction,
            OperationCommand::ZoomIn,
            LrfCommand::NoAction,
        ),
        &protocol_core::viewlink::Header::new(1),
        &mut frame,
    )
    .unwrap();
    let burst: Vec<u8> = frame[..n].repeat(104 / n);
    for _ in 0..300 {
        let now = s.now_us;
        s.fc_line.send(now, &burst);
        s.run_for(10 * MS);
    }
    s.run_for(S);
    assert_eq!(s.pod.received_of::<ContinuousZoom>().len(), zooms + 1);
    let status = s.fc.received.iter().filter(|r| r.id == 0x40).count() - status_before;
    assert!(status <= 4 * 20 + 10, "{status} status frames in 4 s");
    assert!(s.fc.healthy());
    assert_eq!(s.engine.counters().dropped, 0);
}
