//! The bridge between a simulated ArduPilot SIYI driver and a simulated K40T pod: the
//! scenarios of the bridge engine issue, in simulated time. The scenarios every FC side
//! runs are in `engine_scenarios/mod.rs`; the bounds and the SIYI side's own are here.

use crate::engine_scenarios;

use bridge_engine::{Event, Level};
use gimbal::sim::Autopilot;
use gimbal::sim::ap_siyi::{ApSiyi, ApSiyiConfig};
use gimbal::sim::pilot::Pilot;
use gimbal::sim::pod::{MotionCommand, PodSimConfig};
use gimbal::sim::scenario::Scenario;

use engine_scenarios::{
    MS, Noise, S, damage_counted, figures, healthy, healthy_within, one_photo_geotagged,
    one_sync_per_edge, pod_loss_then_recovery, stays_healthy, sync_errors_us, zoom_in_then_stop,
};
use protocol_core::k40t::{
    self, AckCode, DialSpeed, GimbalControl, HybridZoom, ImageModeSetting, IrGainMode, IrPalette,
    LaserPeriodic, MessageData, PitchMotion, Record, RecordAction, TakePhoto, YawMotion,
    ZoomControl,
};
use protocol_core::siyi::FeedbackInfo;

fn scenario(ap: ApSiyiConfig, pod: PodSimConfig, bridge_ppm: i64) -> Scenario<ApSiyi> {
    engine_scenarios::scenario(ApSiyi::new(ap), pod, bridge_ppm)
}

fn healthy_scenario() -> Scenario<ApSiyi> {
    healthy(
        scenario(ApSiyiConfig::default(), PodSimConfig::default(), 30),
        5 * S,
    )
}

#[test]
fn ardupilot_reaches_healthy_through_the_start_up_gates() {
    let mut s = scenario(ApSiyiConfig::default(), PodSimConfig::default(), -40);
    s.run_until(6 * S);
    let ap = &s.fc;
    assert_eq!(ap.model, Some(*b"7A"), "ZT30 identity");
    assert!(ap.initialised());
    // Healthy within the start-up: hardware id (1 Hz), firmware (1 Hz), codec specs, then
    // attitude at 20 Hz.
    healthy_within(&s, 4 * S);
    assert!(ap.healthy());
    // Replies come in the order of the gates.
    let first = |id: u8| ap.received.iter().find(|r| r.id == id).map(|r| r.at_us);
    assert!(first(0x02) < first(0x01));
    assert!(first(0x01) < first(0x20));
    assert!(first(0x20) < first(0x0D));
    // Firmware: 12 bytes, the bridge's version (patch, minor, major) as the camera's
    // (ArduPilot needs it non-zero), the gimbal's and the zoom's.
    let fw = ap.received.iter().find(|r| r.id == 0x01).unwrap();
    assert_eq!(fw.data.len(), 12);
    let v = bridge_engine::version::Version::parse(env!("CARGO_PKG_VERSION")).unwrap();
    let v = [v.patch, v.minor, v.major, 0];
    assert_eq!(fw.data, [v, v, v].concat());
    assert_ne!(&fw.data[..3], &[0, 0, 0]);
    // Every 0x0D is answered with exactly 12 bytes while the pod reports.
    let asked = ap
        .sent
        .iter()
        .filter(|(t, id)| *id == 0x0D && *t < 5_900_000)
        .count();
    let answered = ap.received.iter().filter(|r| r.id == 0x0D).count();
    assert!(asked > 30, "{asked}");
    assert!(answered + 1 >= asked, "{answered} of {asked}");
    assert!(
        ap.received
            .iter()
            .filter(|r| r.id == 0x0D)
            .all(|r| r.data.len() == 12)
    );
    // No reply longer than ArduPilot's 32 data bytes, none dropped by its parser.
    assert!(ap.received.iter().all(|r| r.data.len() <= 32));
    assert_eq!(ap.parse_errors(), 0);
    // And it stays healthy.
    stays_healthy(&mut s, 60 * S);
}

#[test]
fn rates_reach_the_pod_as_direction_and_dial_speed_and_come_back_in_0x0d() {
    let mut s = healthy_scenario();
    s.fc.turn(18.0, -9.0);
    s.run_for(S);
    // 18 deg/s -> SIYI 20 -> 18 deg/s = dial 90 (0.2 deg/s units); -9 -> -10 -> 9 deg/s.
    let dial = s.pod.received_of::<DialSpeed>();
    let (_, _, d) = dial.last().expect("a dial speed");
    assert_eq!((d.yaw_dps_x5, d.pitch_dps_x5), (90, 45));
    let ctl = s.pod.received_of::<GimbalControl>();
    let (_, _, c) = ctl.last().unwrap();
    assert_eq!((c.yaw, c.pitch), (YawMotion::Right, PitchMotion::Down));
    // The pod turns; ArduPilot sees it turn right and down, in its own convention.
    s.run_for(S);
    let (_, yaw, pitch, _) = s.fc.attitude.unwrap();
    let g = s.pod.gimbal();
    assert!(yaw > 20.0, "AP yaw {yaw}, pod {g:?}");
    assert!(pitch < -10.0, "AP pitch {pitch}");
    assert!((yaw - g.yaw_deg).abs() < 3.0, "AP {yaw} pod {}", g.yaw_deg);
    // ArduPilot repeats the same rates at 50 Hz; the pod gets no flood: at most a
    // refresh a second plus the changes.
    let before = s.pod.received_count(GimbalControl::ID.to_u32());
    s.run_for(5 * S);
    let during = s.pod.received_count(GimbalControl::ID.to_u32()) - before;
    assert!(during <= 6, "{during} motion frames in 5 s");
    // Stop: the rates go to zero and the pod stops.
    s.fc.turn(0.0, 0.0);
    s.run_for(S);
    let (_, _, c) = s
        .pod
        .received_of::<GimbalControl>()
        .last()
        .copied()
        .unwrap();
    assert_eq!((c.yaw, c.pitch), (YawMotion::Stop, PitchMotion::Stop));
}

#[test]
fn an_angle_target_converges_through_ardupilots_p_controller() {
    let mut s = healthy_scenario();
    s.fc.point(30.0, -45.0);
    s.run_for(15 * S);
    let g = s.pod.gimbal();
    assert!(
        (g.yaw_deg - 30.0).abs() < 3.0 && (g.pitch_deg + 45.0).abs() < 3.0,
        "pod at {g:?}"
    );
}

#[test]
fn fc_silence_stops_the_pod() {
    engine_scenarios::fc_silence_stops_the_turning_pod(&mut healthy_scenario());
}

#[test]
fn camera_commands_reach_the_pod_with_the_right_fields() {
    let mut s = healthy_scenario();
    s.fc.take_picture();
    s.run_for(S);
    let photo = s.pod.received_of::<TakePhoto>();
    assert_eq!(photo.len(), 1);
    assert_eq!(photo[0].2.action, k40t::ShootAction::Start);
    // Record: ArduPilot toggles only after reading the state from 0x0A.
    s.fc.record(true);
    s.run_for(3 * S);
    let rec = s.pod.received_of::<Record>();
    assert_eq!(rec.last().unwrap().2.action, RecordAction::Start);
    assert_eq!(s.fc.record_status, protocol_core::siyi::RecordStatus::On);
    s.fc.record(true); // already on: no toggle
    s.run_for(2 * S);
    assert_eq!(s.pod.received_of::<Record>().len(), 1);
    s.fc.record(false);
    s.run_for(3 * S);
    assert_eq!(
        s.pod.received_of::<Record>().last().unwrap().2.action,
        RecordAction::Stop
    );
    assert_eq!(s.fc.record_status, protocol_core::siyi::RecordStatus::Off);
    // Zoom rate, repeated by ArduPilot at 1 Hz: continuous zoom in, then stop.
    let z = zoom_in_then_stop(&mut s);
    assert_eq!(z.first(), Some(&ZoomControl::In));
    assert_eq!(z.last(), Some(&ZoomControl::Stop));
    assert!(
        s.fc.zoom_mult.unwrap() > 1.0,
        "zoom reply from the pod: {:?}",
        s.fc.zoom_mult
    );
    // Absolute zoom: 50 % of the ZT30's 30x = 15.5x.
    s.fc.set_zoom_pct(50.0);
    s.run_for(S);
    let (_, _, hz) = s.pod.received_of::<HybridZoom>().last().copied().unwrap();
    assert_eq!(hz.zoom_x10, 155);
    // Lens 2 on a ZT30 = thermal main.
    s.fc.set_lens(2);
    s.fc.set_thermal_palette(3); // ironbow
    s.fc.set_thermal_gain(1);
    s.run_for(S);
    assert_eq!(
        s.pod
            .received_of::<ImageModeSetting>()
            .last()
            .unwrap()
            .2
            .mode,
        k40t::ImageMode::Infrared
    );
    assert_eq!(
        s.pod.received_of::<IrPalette>().last().unwrap().2.palette,
        k40t::Palette::IronRed
    );
    assert_eq!(
        s.pod.received_of::<IrGainMode>().last().unwrap().2.gain,
        k40t::IrGain::High
    );
    // ArduPilot's 0x15 polling (ZT30) keeps the laser ranging; distances come back in dm.
    assert!(
        s.pod
            .received_of::<LaserPeriodic>()
            .iter()
            .any(|(_, _, l)| l.enable == k40t::OnOff::On)
    );
    let (_, d) = s.fc.rangefinder.unwrap();
    assert_eq!(d, s.pod.camera().laser_distance_dm);
}

#[test]
fn a_refused_photo_comes_back_as_function_feedback() {
    let mut pod = PodSimConfig::default();
    pod.nak.insert(0x0302, AckCode::NoSdCard);
    let mut s = scenario(ApSiyiConfig::default(), pod, 0);
    s.run_until(5 * S);
    s.fc.take_picture();
    s.run_for(S);
    assert_eq!(
        s.fc.feedback.iter().map(|(_, f)| *f).collect::<Vec<_>>(),
        vec![FeedbackInfo::PhotoFailed]
    );
    assert!(
        s.events_where(|e| matches!(
            e,
            Event::PodRefused {
                base: 0x0302,
                code: AckCode::NoSdCard
            }
        ))
        .len()
            == 1
    );
}

#[test]
fn pod_loss_makes_ardupilot_unhealthy_and_recovery_healthy_again() {
    let mut s = healthy_scenario();
    pod_loss_then_recovery(&mut s, 2_500 * MS, 4 * S, 2 * S, |_| {});
}

#[test]
fn time_syncs_follow_the_fc_utc_and_photos_are_geotagged() {
    let mut s = scenario(
        ApSiyiConfig {
            ppm: 35.0,
            ..ApSiyiConfig::default()
        },
        PodSimConfig::default(),
        -25,
    );
    s.run_until(120 * S);
    // Every edge is on a whole 10 s of UTC, followed by its 0x00030E, applied by the pod.
    let edges = one_sync_per_edge(&s);
    assert!(edges >= 6, "{edges} edges");
    for err_us in sync_errors_us(&s, 0) {
        assert!(err_us.abs() < 20_000, "error {err_us} us");
    }
    // Pulses are 50 ms wide.
    let highs: Vec<_> = s
        .pin_edges
        .iter()
        .filter(|e| e.level == Level::High)
        .copied()
        .collect();
    let lows: Vec<_> = s
        .pin_edges
        .iter()
        .filter(|e| e.level == Level::Low)
        .copied()
        .collect();
    for (h, l) in highs.iter().zip(&lows) {
        assert!((l.at_us - h.at_us).abs_diff(50_000) < 100);
    }
    // A photo: the pod asks for GPS at the photo's time of day; the answer is the
    // aircraft's position then.
    s.fc.take_picture();
    one_photo_geotagged(&mut s);
}

/// Time-sync accuracy through the whole engine, over one-hour flights: the FC's crystal
/// and the bridge's each off by up to ±25 ppm (±50 ppm between them), transport jitter
/// uniform in 0..10 ms per FC update, ArduPilot's sending pattern. Error = |UTC in the
/// 0x00030E the pod applied − the FC's UTC at the edge's true instant|, after 60 s.
///
/// SIYI gives UTC only in the five 0x30 frames at start-up; the bridge carries it
/// forward on the FC's `time_boot_ms`. The offset is exact to the FC's millisecond when
/// a 0x30 shares an FC update with a 0x22/0x3E (ArduPilot's 1 Hz and 120 ms schedules
/// meet at some phases only); otherwise it is the least-delayed of the five arrivals,
/// late by up to the transport jitter.
#[test]
fn time_sync_accuracy_over_one_hour_flights() {
    let mut all = Vec::new();
    for (seed, fc_ppm, bridge_ppm) in [
        (11, 25.0, -25),
        (12, -25.0, 25),
        (13, 10.0, 0),
        (14, -5.0, 15),
    ] {
        let ap = ApSiyiConfig {
            ppm: fc_ppm,
            seed,
            ..ApSiyiConfig::default()
        };
        let mut s = scenario(ap, PodSimConfig::default(), bridge_ppm);
        s.run_until(3600 * S);
        // One edge every 10 s once UTC is valid (about 50 s after start).
        let edges = one_sync_per_edge(&s);
        assert!(edges >= 354, "seed {seed}: {edges} edges");
        let label = format!("SIYI seed {seed} (FC {fc_ppm:+} ppm, bridge {bridge_ppm:+} ppm)");
        let errs = figures(&label, &sync_errors_us(&s, 60 * S));
        // The bound the five start-up samples allow: the transport jitter (10 ms).
        assert!(*errs.last().unwrap() < 10_000);
        all.extend(errs.iter().map(|&e| e as i64));
    }
    figures("SIYI, all flights", &all);
}

/// Both lines damaged for a minute: the FC's bytes with one flipped bit per ~1000 bytes
/// and a random burst before ~1 % of writes, the pod's frames with garbage before 5 %
/// and a flipped bit in 2 %. Every damaged frame is rejected and counted; the frames
/// around it still pass, so ArduPilot never loses health, the pod follows the rate, and
/// the pod never receives a frame the bridge did not mean to send.
#[test]
fn damaged_lines_cost_frames_not_health_or_control() {
    let mut s = healthy_scenario();
    let mut noise = Noise(0x5eed_1234_abcd_0001);
    s.fc_line
        .damage
        .set_corrupter(Box::new(move |_, bytes: &[u8]| {
            let mut out = Vec::with_capacity(bytes.len() + 8);
            if noise.chance(10_000) {
                let n = 1 + noise.next() % 12;
                out.extend((0..n).map(|_| noise.next() as u8));
            }
            for &b in bytes {
                let flip = if noise.chance(1_000) {
                    1 << (noise.next() % 8)
                } else {
                    0
                };
                out.push(b ^ flip);
            }
            out
        }));
    s.pod.set_output_faults(gimbal::sim::pod::OutputFaults {
        seed: 77,
        garbage_probability: 0.05,
        max_garbage_len: 16,
        bit_flip_probability: 0.02,
    });
    s.fc.turn(15.0, -5.0);
    let before = s.engine.counters();
    s.run_for(8 * S);
    // The pod turns as asked (checked before the yaw reaches its limit).
    let g = s.pod.gimbal();
    assert!(g.yaw_rate_dps > 10.0 && g.pitch_rate_dps < -2.0, "{g:?}");
    // Then holds still when asked.
    s.fc.turn(0.0, 0.0);
    s.run_for(52 * S);
    let g = s.pod.gimbal();
    assert!(g.yaw_rate_dps == 0.0 && g.pitch_rate_dps == 0.0, "{g:?}");
    let c = s.engine.counters();
    let (bursts, flips) = s.pod.faults_injected();
    assert!(bursts > 50 && flips > 20, "faults {bursts} {flips}");
    // Damage is seen and counted on both ports.
    damage_counted(&before, &c);
    println!("{c:?} pod faults {bursts} bursts {flips} flips");
    // Valid frames keep flowing: at most a few percent lost.
    let fc_frames = c.fc_frames - before.fc_frames;
    let sent = s.fc.sent.iter().filter(|(t, _)| *t > 5 * S).count() as u32;
    assert!(fc_frames * 100 >= sent * 95, "{fc_frames} of {sent}");
    // ArduPilot stays healthy throughout, its parser never sees a bad frame from us.
    assert_eq!(s.fc.health_log().len(), 1, "{:?}", s.fc.health_log());
    assert_eq!(s.fc.parse_errors(), 0);
    // The pod got only well-formed frames.
    let rx = s.pod.rx_stats();
    assert_eq!(rx.deframer.checksum_errors, 0);
    assert_eq!(rx.malformed, 0);
}

/// Random bytes at the full line rate from the FC for 5 s (a baud-rate mismatch, a
/// shorted line): no valid frame arrives, so the bridge treats it as silence and stops
/// the pod; when the FC speaks again ArduPilot is healthy within seconds.
#[test]
fn a_garbage_flood_from_the_fc_is_silence_and_stops_the_pod() {
    let mut s = healthy_scenario();
    s.fc.turn(20.0, 0.0);
    s.run_for(2 * S);
    assert!(s.pod.gimbal().yaw_rate_dps > 0.0);
    let start = s.now_us;
    let end = start + 5 * S;
    let mut noise = Noise(0x0bad_cafe_0000_0001);
    s.fc_line
        .damage
        .set_corrupter(Box::new(move |at, bytes: &[u8]| {
            if at < end {
                // Every write replaced by twice as many random bytes: the line stays full.
                (0..bytes.len() * 2).map(|_| noise.next() as u8).collect()
            } else {
                bytes.to_vec()
            }
        }));
    let garbage_before = s.engine.counters().fc_garbage_bytes;
    s.run_for(5 * S);
    assert!(s.engine.counters().fc_garbage_bytes - garbage_before > 5_000);
    let stop = s.pod.first_stop_after(start).expect("a stop");
    assert!(stop - start <= 700_000, "{} ms", (stop - start) / 1000);
    assert_eq!(s.pod.gimbal().yaw_rate_dps, 0.0);
    // Random bytes that happen to form a valid SIYI frame (a 16-bit CRC lets one in
    // 65 536 candidates through) must not restart the motion: the pod stays stopped.
    assert!(
        s.pod
            .motions()
            .iter()
            .filter(|m| m.at_us > stop)
            .all(|m| !matches!(m.command, MotionCommand::Control(c)
                if c.yaw != YawMotion::Stop))
    );
    s.fc_line.damage.clear_corrupter();
    s.run_for(3 * S);
    assert!(s.fc.healthy());
    assert!(s.pod.gimbal().yaw_rate_dps > 0.0, "moving again");
}

/// The pod's side floods: random bytes only for 5 s. The bridge reports the pod lost
/// (ArduPilot unhealthy), keeps answering the FC without stale attitude, and recovers.
#[test]
fn a_garbage_flood_from_the_pod_is_pod_loss_then_recovery() {
    let mut s = healthy_scenario();
    s.pod.set_output_faults(gimbal::sim::pod::OutputFaults {
        seed: 5,
        garbage_probability: 1.0,
        max_garbage_len: 64,
        bit_flip_probability: 1.0,
    });
    let start = s.now_us;
    s.run_for(5 * S);
    assert!(!s.engine.pod_state().link);
    assert!(
        s.fc.health_log().iter().any(|(t, h)| *t > start && !h),
        "{:?}",
        s.fc.health_log()
    );
    s.pod
        .set_output_faults(gimbal::sim::pod::OutputFaults::default());
    let back = s.now_us;
    s.run_for(4 * S);
    assert!(s.engine.pod_state().link);
    let up =
        s.fc.health_log()
            .iter()
            .find(|(t, h)| *t > back && *h)
            .expect("healthy again")
            .0;
    assert!(up - back <= 3 * S);
}

/// Checks a GPS reply against the aircraft at the photo's instant.
fn assert_geotag_matches(s: &Scenario<ApSiyi>, photo: usize) {
    let p = &s.pod.photos()[photo];
    let req = &s.pod.gps_requests()[p.gps_request.expect("asked")];
    let r = &s.pod.gps_replies()[req.reply.expect("answered")];
    assert_eq!(r.reply.code.code(), AckCode::Ok, "photo {photo}: {r:?}");
    assert!(r.time_matches && !r.late);
    let (lat, lon) = s.fc.aircraft().position_e7(p.at_us);
    assert!(
        (r.reply.lat_e7 - lat).abs() < 50,
        "photo {photo}: lat {} vs {lat}",
        r.reply.lat_e7
    );
    assert!(
        (r.reply.lon_e7 - lon).abs() < 70,
        "photo {photo}: lon {} vs {lon}",
        r.reply.lon_e7
    );
    assert_eq!(r.reply.yaw_cdeg, 4500);
}

/// The GPS request carries only a time of day: photos either side of UTC midnight are
/// matched to the right day and geotagged from the fix history.
#[test]
fn photos_across_utc_midnight_are_geotagged() {
    // 2026-11-23T23:58:50.123456Z at true time 0: midnight at 69.88 s.
    let ap = ApSiyiConfig {
        utc_at_zero_us: 1_795_478_330_123_456,
        ..ApSiyiConfig::default()
    };
    let mut s = scenario(ap, PodSimConfig::default(), 20);
    s.run_until(66 * S);
    assert!(s.pod.is_synced());
    for _ in 0..8 {
        s.fc.take_picture();
        s.run_for(S);
    }
    s.run_for(2 * S);
    let photos = s.pod.photos().len();
    assert_eq!(photos, 8);
    let tods: Vec<u64> = s
        .pod
        .photos()
        .iter()
        .map(|p| p.pod_unix_ms % 86_400_000)
        .collect();
    assert!(tods.iter().any(|t| *t > 86_390_000), "{tods:?}");
    assert!(tods.iter().any(|t| *t < 10_000), "{tods:?}");
    for i in 0..photos {
        assert_geotag_matches(&s, i);
    }
    assert_eq!(s.engine.counters().geotags, 8);
    assert_eq!(s.engine.counters().geotags_failed, 0);
}

/// Without a position the bridge says so (0x00030F with the failure code, the asked time
/// echoed) instead of sending zeros or a stale place; a fix held past its second is not
/// used; a request for a moment older than the history is refused.
#[test]
fn geotags_fail_cleanly_without_a_fix_with_a_lost_fix_and_out_of_range() {
    // No GPS position at all.
    let ap = ApSiyiConfig {
        position: false,
        ..ApSiyiConfig::default()
    };
    let mut s = scenario(ap, PodSimConfig::default(), 0);
    s.run_until(60 * S);
    s.fc.take_picture();
    s.run_for(2 * S);
    let r = *s.pod.gps_replies().last().expect("a reply");
    assert_eq!(r.reply.code.code(), AckCode::Failure);
    assert!(r.time_matches && !r.late);
    assert_eq!((r.reply.lat_e7, r.reply.lon_e7), (0, 0));
    assert_eq!(s.engine.counters().geotags_failed, 1);
    assert_eq!(s.engine.counters().geotags, 0);

    // A fix that is lost in flight: held for a photo 0.5 s later, refused 3 s later.
    let mut s = scenario(ApSiyiConfig::default(), PodSimConfig::default(), 0);
    s.run_until(60 * S);
    s.fc.config.position = false;
    s.run_for(S / 2);
    s.fc.take_picture();
    s.run_for(3 * S);
    s.fc.take_picture();
    s.run_for(2 * S);
    assert_eq!(s.pod.photos().len(), 2);
    let first = &s.pod.gps_replies()[0];
    assert_eq!(first.reply.code.code(), AckCode::Ok);
    let second = &s.pod.gps_replies()[1];
    assert_eq!(second.reply.code.code(), AckCode::Failure);
    assert_eq!(
        (
            s.engine.counters().geotags,
            s.engine.counters().geotags_failed
        ),
        (1, 1)
    );

    // Requests for instants outside the history: 45 s ago (it keeps 201 fixes: 30 s of
    // ArduPilot's SIYI positions, sent every 150 ms) and 3 s
    // ahead (a fix is never extrapolated). Put on the pod's line as the pod would.
    let pod = s.pod.config().clone();
    let now_utc_ms = s.fc.fc_utc_us(s.now_us) / 1000;
    let replies_before = s.pod.gps_replies().len();
    for (i, utc_ms) in [now_utc_ms - 45_000, now_utc_ms + 3_000]
        .into_iter()
        .enumerate()
    {
        let tod = utc_ms % 86_400_000;
        let request = k40t::GpsRequest {
            lens_enable: 1,
            hour: (tod / 3_600_000) as u8,
            minute: (tod / 60_000 % 60) as u8,
            second: (tod / 1000 % 60) as u8,
            millisecond: (tod % 1000) as u16,
        };
        let header = k40t::Header {
            dst: pod.fc_address,
            src: pod.camera_address,
            seq: 200 + i as u8,
            coverage: pod.coverage,
        };
        let mut buf = [0u8; 64];
        let n = k40t::encode(&request, &header, &mut buf).unwrap();
        let at = s.now_us;
        s.pod_line.send(at, &buf[..n]);
        s.run_for(S / 2);
        let r = s.pod.gps_replies().last().expect("a reply");
        assert_eq!(s.pod.gps_replies().len(), replies_before + i + 1);
        assert_eq!(r.header.seq, 200 + i as u8);
        assert_eq!(r.reply.code.code(), AckCode::Failure, "{r:?}");
        assert_eq!(
            (
                r.reply.hour,
                r.reply.minute,
                r.reply.second,
                r.reply.millisecond
            ),
            (
                request.hour,
                request.minute,
                request.second,
                request.millisecond
            )
        );
    }
}

/// The link budget under ArduPilot's full traffic: a pilot sweeping the gimbal with the
/// sticks (rates changing every 300 ms), zooming, a photo every 2 s, for two minutes.
/// Every byte rate stays far below the 115 200-baud line (11 520 bytes/s).
#[test]
fn link_budget_under_full_ardupilot_traffic() {
    let mut s = healthy_scenario();
    // After UTC is known (photos before it cannot be geotagged).
    s.run_until(60 * S);
    let start = s.now_us;
    let bytes = |s: &Scenario<ApSiyi>| {
        [
            s.fc_line.bytes_sent,
            s.to_fc_line.bytes_sent,
            s.pod_line.bytes_sent,
            s.to_pod_line.bytes_sent,
        ]
    };
    let before = bytes(&s);
    let mut noise = Noise(42);
    for step in 0..400u64 {
        let yaw = (noise.next() % 61) as f64 - 30.0;
        let pitch = (noise.next() % 41) as f64 - 20.0;
        s.fc.turn(yaw, pitch);
        if step % 7 == 0 {
            s.fc.take_picture();
        }
        s.run_for(300_000);
    }
    let secs = (s.now_us - start) as f64 / 1e6;
    let after = bytes(&s);
    let rate = |i: usize| (after[i] - before[i]) as f64 / secs;
    let names = [
        "FC -> bridge",
        "bridge -> FC",
        "pod -> bridge",
        "bridge -> pod",
    ];
    for (i, name) in names.iter().enumerate() {
        println!(
            "{name}: {:.0} bytes/s ({:.1} % of 115200 baud)",
            rate(i),
            rate(i) / 115.2
        );
    }
    let c = s.engine.counters();
    println!(
        "pod frames sent {} (retries {}), dropped {}",
        c.pod_sent, c.pod_retries, c.dropped
    );
    // The bridge never loads the pod line past a tenth of its capacity, nor the FC line.
    assert!(rate(3) < 1_152.0, "bridge -> pod {:.0} B/s", rate(3));
    assert!(rate(1) < 2_304.0, "bridge -> FC {:.0} B/s", rate(1));
    assert_eq!(c.dropped, 0);
    assert!(s.fc.healthy());
    assert_eq!(c.geotags_failed, 0);
    assert_eq!(c.geotags, 58);
}

#[test]
fn zt30_thermal_min_max_come_from_the_pods_ir_measurements() {
    // ArduPilot asks a ZT30 for 0x14 every second; the reply is the pod's last 0x000004:
    // 0.01 °C (ArduPilot reads an i16), positions in the ZT30's 640 × 512 thermal pixels.
    let mut s = healthy_scenario();
    let mut seen = Vec::new();
    for _ in 0..6 {
        s.run_for(S);
        let t = s.fc.thermal.expect("a 0x14 reply");
        if seen.last() != Some(&t) {
            seen.push(t);
        }
    }
    assert!(seen.len() >= 4, "{seen:?}");
    let ir = s.pod.sent_of::<k40t::IrStatus>();
    for t in &seen {
        let matched = ir
            .iter()
            .filter(|(at, ..)| *at < t.at_us)
            .rev()
            .take(3)
            .any(|(_, _, m)| {
                let px = |v: u16, border: u16| (v - border) / 2;
                (t.max_c - f64::from(m.max_temp_dc) / 10.0).abs() < 1e-9
                    && (t.min_c - f64::from(m.min_temp_dc) / 10.0).abs() < 1e-9
                    && t.max_pos == (px(m.max_x, 320), px(m.max_y, 32))
                    && t.min_pos == (px(m.min_x, 320), px(m.min_y, 32))
            });
        assert!(matched, "{t:?}");
        assert!(t.max_pos.0 < 640 && t.max_pos.1 < 512);
    }
}
