//! The simulated ArduPilot's MAVLink port against a scripted device.

use super::*;
use crate::sim::FcReboot;
use crate::sim::ap_siyi::{ApSiyi, ApSiyiConfig};
use crate::sim::mav::testing::{Driver, byte_us, set_interval, timesync_request, uart_chunks};
use crate::sim::mav::{CAMERA, GIMBAL};
use protocol_core::mavlink::dialect::{
    AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA, GIMBAL_DEVICE_INFORMATION_DATA, HEARTBEAT_DATA,
    MavAutopilot, MavModeFlag, MavResult, MavState, MavType, MessageData as _, SYSTEM_TIME_DATA,
};

/// A simulated ArduPilot with its default settings but for what `set` changes.
fn ap_with(set: impl FnOnce(&mut ApMavlinkConfig)) -> ApMavlink {
    let mut config = ApMavlinkConfig::default();
    set(&mut config);
    ApMavlink::new(config)
}

/// The device: the FC's system, the gimbal's component.
fn device() -> Endpoint {
    Endpoint::new(1, GIMBAL)
}

fn heartbeat(mavtype: MavType) -> MavMessage {
    MavMessage::HEARTBEAT(HEARTBEAT_DATA {
        custom_mode: 0,
        mavtype,
        autopilot: MavAutopilot::MAV_AUTOPILOT_INVALID,
        base_mode: MavModeFlag::empty(),
        system_status: MavState::MAV_STATE_ACTIVE,
        mavlink_version: 3,
    })
}

/// One request on the wire from true `t0`, optionally followed at once by a
/// HEARTBEAT; checks the answer against the UART model and the true start, returns
/// the answer's error against the FC clock at the request's true start, µs.
fn timesync_trial(
    ap: &mut ApMavlink,
    d: &mut Driver,
    t0: u64,
    msg: &MavMessage,
    trailing: bool,
) -> f64 {
    let mut dev = device();
    let req = dev.frame(msg);
    let mut wire = req.clone();
    if trailing {
        wire.extend(dev.frame(&heartbeat(MavType::MAV_TYPE_GIMBAL)));
    }
    let baud = ap.config.baud;
    let chunks = uart_chunks(t0, baud, &wire);
    let req_end = chunks
        .iter()
        .scan(0, |n, (at, c)| {
            *n += c.len();
            Some((*n, *at))
        })
        .find(|(n, _)| *n >= req.len())
        .map(|(_, at)| at)
        .unwrap();
    let answers = ap.timesync_answers.len();
    d.deliver(ap, &chunks);
    d.run_until(ap, t0 + 30_000);
    assert_eq!(ap.timesync_answers.len(), answers + 1);
    let a = ap.timesync_answers.last().unwrap().clone();
    let MavMessage::TIMESYNC(t) = msg else {
        unreachable!()
    };
    assert_eq!((a.ts1, a.target), (t.ts1, (0, 0)));
    // Read by the first loop after the chunk that completed it, not at arrival.
    let first_loop = *d.wakeups.iter().find(|&&w| w >= req_end).unwrap();
    assert_eq!(a.handled_at_us, first_loop);
    // The UART model: the last chunk delivered by then, the bytes after the request.
    let delivered: Vec<_> = chunks.iter().filter(|(at, _)| *at <= first_loop).collect();
    let stamp = ap.fc_us(delivered.last().unwrap().0);
    let total: usize = delivered.iter().map(|(_, c)| c.len()).sum();
    let after = total - req.len();
    let len = match ap.config.timesync_len {
        TimesyncLen::Frame => req.len(),
        TimesyncLen::PayloadSize => TIMESYNC_PAYLOAD_SIZE,
    };
    let expected = stamp - 86 * (len + after) as u64;
    assert_eq!(a.tc1, (expected * 1000) as i64, "the UART estimate");
    // On the wire: in the burst of that loop (no transport jitter here), ts1 echoed.
    let on_wire: Vec<_> = d
        .frames()
        .into_iter()
        .filter(|(_, r)| matches!(&r.message, MavMessage::TIMESYNC(s) if s.ts1 == t.ts1))
        .collect();
    assert_eq!(on_wire.len(), 1);
    assert_eq!(on_wire[0].0, a.handled_at_us);
    assert_eq!(a.sent_at_us, a.handled_at_us);
    assert!(
        d.wakeups.contains(&on_wire[0].0),
        "leaves at a loop instant"
    );
    let MavMessage::TIMESYNC(reply) = &on_wire[0].1.message else {
        unreachable!()
    };
    assert_eq!(
        (reply.tc1, reply.target_system, reply.target_component),
        (a.tc1, 0, 0)
    );
    a.tc1 as f64 / 1000.0 - ap.fc_us(t0) as f64
}

#[test]
fn ardupilot_answers_timesync_with_the_uart_receive_estimate_of_the_request_start() {
    let mut ap = ap_with(|c| {
        c.ppm = 23.0;
        c.jitter_us = 0;
    });
    assert_eq!(ap.loop_rate_hz(), 400);
    let mut d = Driver::new();
    let byte = byte_us(115_200);
    for i in 0..40u64 {
        let t0 = 1_000_000 + i * 123_457;
        // Targeted at the autopilot: a full 30-byte frame.
        let msg = timesync_request(7_000_000_000_000 + i as i64, (1, AUTOPILOT));
        let err = timesync_trial(&mut ap, &mut d, t0, &msg, i % 2 == 1);
        // Late by the whole-µs byte time's 0.8 µs a byte, at most one byte time
        // plus the chunk stamp's rounding; never early.
        assert!((-1.0..=byte + 1.0).contains(&err), "trial {i}: {err} µs");
    }
    // A broadcast request is answered too; one for another component is not.
    let t0 = 7_000_000;
    let err = timesync_trial(&mut ap, &mut d, t0, &timesync_request(5, (0, 0)), false);
    assert!((-1.0..=byte + 1.0).contains(&err));
    let n = ap.timesync_answers.len();
    let mut dev = device();
    d.send(
        &mut ap,
        8_000_000,
        &mut dev,
        &timesync_request(6, (1, CAMERA)),
    );
    d.run_until(&mut ap, 8_100_000);
    assert_eq!(ap.timesync_answers.len(), n);
}

#[test]
fn ardupilot_timesync_estimate_with_payload_size_reading() {
    let mut ap = ap_with(|c| {
        c.jitter_us = 0;
        c.timesync_len = TimesyncLen::PayloadSize;
    });
    let mut d = Driver::new();
    let byte = byte_us(115_200);
    // No targets and a small ts1: MAVLink 2 trims the frame to 24 bytes; the driver
    // still counts 30, so the estimate is 6 bytes early.
    for i in 0..10u64 {
        let msg = timesync_request(3_000_000_000 + i as i64, (0, 0));
        assert_eq!(device().frame(&msg).len(), 24);
        let err = timesync_trial(&mut ap, &mut d, 2_000_000 + i * 77_777, &msg, i % 2 == 0);
        let early = -6.0 * 86.0;
        assert!(
            (early - 1.0..=early + byte + 1.0).contains(&err),
            "trial {i}: {err} µs"
        );
    }
    // The frame reading on the same request is within a byte.
    let mut ap = ap_with(|c| {
        c.jitter_us = 0;
    });
    let mut d = Driver::new();
    let msg = timesync_request(3_000_000_000, (0, 0));
    let err = timesync_trial(&mut ap, &mut d, 2_000_000, &msg, true);
    assert!((-1.0..=byte + 1.0).contains(&err), "{err} µs");
}

#[test]
fn ardupilot_loop_phase_sweeps_the_ms_grid_and_system_time_gives_the_utc_shift() {
    let mut ap = ap_with(|c| {
        c.ppm = 11.0;
        c.utc_valid_at_us = 1_000_000;
    });
    let mut d = Driver::new();
    let mut dev = device();
    let system_time_at_10_hz = set_interval(SYSTEM_TIME_DATA::ID, 100_000.0);
    d.send(&mut ap, 10_000, &mut dev, &system_time_at_10_hz);
    d.run_until(&mut ap, 31_000_000);
    assert!(ap.acks.is_empty());
    let frames = d.frames();
    assert!(frames.iter().any(|(_, r)| matches!(&r.message,
        MavMessage::COMMAND_ACK(a) if a.result == MavResult::MAV_RESULT_ACCEPTED)));

    // Loops: 400 Hz on the IMU, their phase against the FC's ms grid not locked.
    let first_3s: Vec<u64> = d
        .wakeups
        .iter()
        .copied()
        .filter(|&w| w < 3_000_000)
        .collect();
    assert!(
        (1195..=1205).contains(&first_3s.len()),
        "{}",
        first_3s.len()
    );
    let mut bins = [0u32; 10];
    for &w in &first_3s {
        bins[(ap.fc_us(w) % 1000 / 100) as usize] += 1;
    }
    assert!(bins.iter().all(|&b| b > 0), "{bins:?}");

    // SYSTEM_TIME at 10 Hz; the Unix time 0 until set; both fields from one reading.
    let times: Vec<SYSTEM_TIME_DATA> = frames
        .iter()
        .filter_map(|(_, r)| match &r.message {
            MavMessage::SYSTEM_TIME(s) => Some(s.clone()),
            _ => None,
        })
        .collect();
    assert!((305..=312).contains(&times.len()), "{}", times.len());
    // Due every 100 ms of the FC clock, sent by the first loop after (a 2.5 ms
    // loop, up to 0.5 ms late), the ms truncated.
    for w in times.windows(2) {
        let dt = w[1].time_boot_ms - w[0].time_boot_ms;
        assert!((97..=103).contains(&dt), "{dt}");
    }
    let shift = ap.fc_utc_us(5_000_000) as i64 - ap.fc_us(5_000_000) as i64;
    let set: Vec<i64> = times
        .iter()
        .filter(|s| s.time_unix_usec != 0)
        .map(|s| s.time_unix_usec as i64 - 1000 * i64::from(s.time_boot_ms) - shift)
        .collect();
    assert!(set.len() >= 295 && set.len() < times.len(), "{}", set.len());
    assert!(set.iter().all(|d| (0..1000).contains(d)));
    let min = *set.iter().min().unwrap();
    assert!((0..=50).contains(&min), "min d - shift = {min} µs");
    // No Unix time before the clock was set.
    let first_set = ap.first_utc_sent_us().unwrap();
    assert!((1_000_000..1_110_000).contains(&first_set));
}

#[test]
fn ardupilot_mount_updates_at_50_hz_in_the_400_hz_loop() {
    let mut ap = ap_with(|c| {
        c.camera = false;
    });
    let mut d = Driver::new();
    let mut dev = device();
    let gimbal_heartbeat = heartbeat(MavType::MAV_TYPE_GIMBAL);
    d.send(&mut ap, 50_000, &mut dev, &gimbal_heartbeat);
    d.run_until(&mut ap, 100_000);
    assert_eq!(ap.mount_found, Some(1));
    let info = MavMessage::GIMBAL_DEVICE_INFORMATION(GIMBAL_DEVICE_INFORMATION_DATA {
        pitch_min: -1.5,
        pitch_max: 0.5,
        yaw_min: -3.0,
        yaw_max: 3.0,
        ..GIMBAL_DEVICE_INFORMATION_DATA::default()
    });
    d.send(&mut ap, 150_000, &mut dev, &info);
    d.run_until(&mut ap, 200_000);
    assert!(ap.mount_initialised);
    ap.set_target(MountTarget::body_angles(-30.0, 10.0));
    d.run_until(&mut ap, 2_200_000);
    let times: Vec<u64> = ap.set_attitudes.iter().map(|(t, _)| *t).collect();
    assert!((99..=101).contains(&times.len()), "{}", times.len());
    for w in times.windows(2) {
        // Eight loops of 2 500 µs, each up to 500 µs late.
        let dt = w[1] - w[0];
        assert!((19_499..=20_501).contains(&dt), "{dt}");
    }
    assert!(times.iter().all(|t| d.wakeups.contains(t)));
    // AUTOPILOT_STATE at the enabled 50 Hz, from the loop's stream sender.
    let states = ap
        .sent_of(AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA::ID)
        .count();
    assert!((98..=103).contains(&states), "{states}");

    // Plane's 50 Hz loop refuses the 50 Hz AUTOPILOT_STATE: never initialised.
    let mut plane = ap_with(|c| {
        c.vehicle = ApVehicle::Plane;
        c.camera = false;
    });
    let mut d = Driver::new();
    let mut dev = device();
    let hb = dev.frame(&heartbeat(MavType::MAV_TYPE_GIMBAL));
    d.deliver(&mut plane, &uart_chunks(50_000, 115_200, &hb));
    d.send(&mut plane, 150_000, &mut dev, &info);
    d.run_until(&mut plane, 1_000_000);
    assert!(plane.mount_refused && !plane.mount_initialised);
    let loops = d.wakeups.iter().filter(|&&w| w < 1_000_000).count();
    assert!((49..=51).contains(&loops), "{loops}");
}

#[test]
fn telemetry_port_shares_the_clock_and_aircraft_of_the_board() {
    let mut siyi = ApSiyi::new(ApSiyiConfig {
        ppm: 17.0,
        ..ApSiyiConfig::default()
    });
    let mut tel = ApMavlink::telemetry(siyi.clock().clone(), *siyi.aircraft(), 9, 1);
    assert!(!tel.config.mount && !tel.config.camera);
    for t in [0, 1_234_567, 20_000_000] {
        assert_eq!(tel.fc_us(t), siyi.fc_us(t));
        assert_eq!(tel.fc_utc_us(t), siyi.fc_utc_us(t));
        assert_eq!(
            tel.aircraft().position_e7(t),
            siyi.aircraft().position_e7(t)
        );
    }
    // Both ports reboot together: the clocks stay equal.
    let r = FcReboot {
        boot_clock_us: 1_500,
        utc_shift_us: 40_000,
        ..FcReboot::default()
    };
    siyi.reboot(5_000_000, r);
    tel.reboot(5_000_000, r);
    assert_eq!(tel.clock(), siyi.clock());
    let on = tel.boots()[1].at_us;
    let mut d = Driver::new();
    d.run_until(&mut tel, on + 2_000_000);
    assert!(d.wakeups.iter().all(|&w| w < 5_000_000 || w >= on));
    assert_eq!(tel.fc_us(on + 1_000_000), siyi.fc_us(on + 1_000_000));
    assert_eq!(
        tel.fc_utc_us(on + 1_000_000),
        siyi.fc_utc_us(on + 1_000_000)
    );
    // The telemetry port streams on request; no mount or camera traffic.
    assert!(tel.set_attitudes.is_empty());
    assert!(
        tel.sent
            .iter()
            .all(|(_, m)| matches!(m, MavMessage::HEARTBEAT(_) | MavMessage::TIMESYNC(_)))
    );
}
