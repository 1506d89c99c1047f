//! The engine's MAVLink telemetry link (`Port::Telemetry`) beside a SIYI FC link, and the
//! TIMESYNC + SYSTEM_TIME time path (docs/src/bridge/time.md), against a small autopilot
//! that does what docs/src/autopilots/ardupilot.md and docs/src/autopilots/px4.md say
//! of their time messages: it answers TIMESYNC with its boot clock (in ns) at
//! the request's start (ArduPilot) or at its parse (PX4), sends SYSTEM_TIME with both
//! fields read from one clock reading, and HEARTBEAT at 1 Hz. Serial time is modelled
//! (115200 baud); each reply leaves after a loop latency. The full simulators run
//! through the firmware's tasks in `tasks_telemetry.rs` and `first_sync.rs`.

use bridge_engine::discipline::serial_time;
use bridge_engine::{Config, Engine, Event, FcProtocol, Instant, MAX_FRAME_LEN, Port};
use protocol_core::mavlink::dialect::{
    HEARTBEAT_DATA, MavAutopilot, MavModeFlag, MavState, MavType, SYSTEM_TIME_DATA, TIMESYNC_DATA,
};
use protocol_core::mavlink::{self, Header, MavMessage, Message, Packet};

const BAUD: u32 = 115_200;

/// Where the autopilot reads tc1.
#[derive(Clone, Copy, PartialEq)]
enum Stamp {
    /// ArduPilot: its UART's estimate of the request's first byte.
    RequestStart,
    /// PX4: when its receive thread parses it (after the last byte).
    Parse,
}

/// A minimal autopilot on one MAVLink port, on true time (µs).
struct Autopilot {
    stamp: Stamp,
    /// Boot clock = true time + this; UTC = boot clock + `shift`.
    boot_offset_us: u64,
    shift_us: u64,
    /// The FC's UTC steps by this much (µs) at this true instant.
    step: Option<(u64, u64)>,
    /// Crystal error (ppm): the boot clock runs this much fast.
    ppm: i64,
    /// Loop period: replies leave on the next loop instant after the request.
    loop_us: u64,
    /// Frames to the bridge: (true start on the wire, bytes).
    out: Vec<(u64, Vec<u8>)>,
    /// The line to the bridge is free from this true instant.
    line_free: u64,
    seq: u8,
    next_hb: u64,
    next_time: u64,
    timesync_replies: u32,
}

impl Autopilot {
    fn new(stamp: Stamp) -> Self {
        Autopilot {
            stamp,
            boot_offset_us: 7_345_678,
            // 2026-11-24T12:00:00Z minus the boot clock's zero.
            shift_us: 1_795_996_800_000_000,
            step: None,
            ppm: 20,
            loop_us: 2_500,
            out: Vec::new(),
            line_free: 0,
            seq: 0,
            next_hb: 0,
            next_time: 0,
            timesync_replies: 0,
        }
    }

    fn boot_us(&self, t: u64) -> u64 {
        let drift = i64::try_from(t).unwrap() * self.ppm / 1_000_000;
        u64::try_from(i64::try_from(t + self.boot_offset_us).unwrap() + drift).unwrap()
    }

    fn shift_at(&self, t: u64) -> u64 {
        match self.step {
            Some((at, by)) if t >= at => self.shift_us + by,
            _ => self.shift_us,
        }
    }

    fn utc_us(&self, t: u64) -> u64 {
        self.boot_us(t) + self.shift_at(t)
    }

    /// Queues `m` to leave at true `t` (after what is already on the line).
    fn send(&mut self, t: u64, m: &MavMessage) {
        let h = Header {
            sequence: self.seq,
            system_id: 1,
            component_id: 1,
        };
        self.seq = self.seq.wrapping_add(1);
        let mut buf = [0u8; 300];
        let n = mavlink::encode(m, &h, &mut buf).unwrap();
        let start = t.max(self.line_free);
        self.line_free = start + serial_time(u32::try_from(n).unwrap(), BAUD).as_micros();
        self.out.push((start, buf[..n].to_vec()));
    }

    /// Periodic traffic due at true `t`: HEARTBEAT 1 Hz, SYSTEM_TIME 10 Hz (read when
    /// written; 1 ms after the loop instant).
    fn poll(&mut self, t: u64) {
        if t >= self.next_hb {
            self.next_hb += 1_000_000;
            self.send(
                t,
                &MavMessage::HEARTBEAT(HEARTBEAT_DATA {
                    custom_mode: 0,
                    mavtype: MavType::MAV_TYPE_QUADROTOR,
                    autopilot: if self.stamp == Stamp::RequestStart {
                        MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA
                    } else {
                        MavAutopilot::MAV_AUTOPILOT_PX4
                    },
                    base_mode: MavModeFlag::empty(),
                    system_status: MavState::MAV_STATE_STANDBY,
                    mavlink_version: 3,
                }),
            );
        }
        if t >= self.next_time {
            // 100 ms and a loop phase that slides against the millisecond grid.
            self.next_time += 100_000 + 373;
            let boot = self.boot_us(t);
            self.send(
                t,
                &MavMessage::SYSTEM_TIME(SYSTEM_TIME_DATA {
                    time_unix_usec: boot + self.shift_at(t),
                    time_boot_ms: u32::try_from(boot / 1000).unwrap(),
                }),
            );
        }
    }

    /// A frame from the bridge: started on the wire at true `start`, ended at `end`.
    fn receive(&mut self, start: u64, end: u64, frame: &[u8]) {
        let Ok(p) = Packet::decode(frame) else {
            return;
        };
        if let Message::Known(MavMessage::TIMESYNC(ts)) = p.message
            && ts.tc1 == 0
        {
            let read_at = match self.stamp {
                Stamp::RequestStart => start,
                Stamp::Parse => end + 150,
            };
            let tc1 = i64::try_from(self.boot_us(read_at)).unwrap() * 1000;
            // Answered in the next loop after the whole frame arrived.
            let reply_at = (end / self.loop_us + 1) * self.loop_us;
            self.timesync_replies += 1;
            self.send(
                reply_at,
                &MavMessage::TIMESYNC(TIMESYNC_DATA {
                    tc1,
                    ts1: ts.ts1,
                    target_system: 0,
                    target_component: 0,
                }),
            );
        }
    }
}

/// UTC errors (µs, one per second), events with their true instants, the component ids
/// of the bridge's telemetry frames, and the autopilot.
type Flight = (Vec<i64>, Vec<(u64, Event)>, Vec<u8>, Autopilot);

/// A flight of `seconds` with the bridge's clock `bridge_ppm` fast: the engine's UTC
/// error at each second after `from_s` (µs), the events, and the telemetry frames the
/// bridge sent (component ids).
fn fly(stamp: Stamp, bridge_ppm: i64, seconds: u64, from_s: u64) -> Flight {
    fly_with(Autopilot::new(stamp), bridge_ppm, seconds, from_s)
}

fn fly_with(mut ap: Autopilot, bridge_ppm: i64, seconds: u64, from_s: u64) -> Flight {
    let mut e = Engine::new(Config::for_fc(FcProtocol::Siyi));
    let local = |t: u64| {
        let drift = i64::try_from(t).unwrap() * bridge_ppm / 1_000_000;
        Instant::from_micros(u64::try_from(i64::try_from(t).unwrap() + drift).unwrap())
    };
    let mut errors = Vec::new();
    let mut events = Vec::new();
    let mut from = Vec::new();
    let mut bridge_line_free = 0u64;
    let mut buf = [0u8; MAX_FRAME_LEN];
    let step = 100;
    let mut t = 0;
    while t <= seconds * 1_000_000 {
        ap.poll(t);
        // The autopilot's frames arrive whole (their last byte at start + serial time).
        let due: Vec<_> = ap
            .out
            .iter()
            .filter(|(s, f)| {
                s + serial_time(u32::try_from(f.len()).unwrap(), BAUD).as_micros() <= t
            })
            .cloned()
            .collect();
        ap.out.retain(|x| !due.contains(x));
        for (_, f) in due {
            e.receive(local(t), Port::Telemetry, &f);
            e.idle(local(t), Port::Telemetry);
        }
        if e.poll_at().is_some_and(|p| p <= local(t)) {
            e.poll(local(t));
        }
        while let Some(n) = e.transmit(Port::Telemetry, &mut buf) {
            let start = t.max(bridge_line_free);
            let end = start + serial_time(u32::try_from(n).unwrap(), BAUD).as_micros();
            bridge_line_free = end;
            if let Ok(p) = Packet::decode(&buf[..n]) {
                from.push(p.header.component_id);
            }
            ap.receive(start, end, &buf[..n]);
        }
        while e.transmit(Port::Pod, &mut buf).is_some() {}
        while e.transmit(Port::Fc, &mut buf).is_some() {}
        while let Some(ev) = e.next_event() {
            events.push((t, ev));
        }
        if t % 1_000_000 == 0 && t >= from_s * 1_000_000 {
            let utc = e.utc(local(t)).map(|u| u.as_unix_micros());
            let truth = ap.utc_us(t);
            errors.push(utc.map_or(i64::MAX, |u| {
                i64::try_from(u).unwrap() - i64::try_from(truth).unwrap()
            }));
        }
        t += step;
    }
    (errors, events, from, ap)
}

#[test]
fn ardupilot_telemetry_gives_utc_to_the_tens_of_microseconds_through_timesync() {
    for ppm in [-25, 0, 25] {
        let (errors, events, from, ap) = fly(Stamp::RequestStart, ppm, 60, 15);
        // The telemetry link is the source from its first SYSTEM_TIME.
        let source: Vec<_> = events
            .iter()
            .filter_map(|(t, e)| match e {
                Event::TimeSource { telemetry } => Some((*t, *telemetry)),
                _ => None,
            })
            .collect();
        assert_eq!(source.len(), 1, "{source:?}");
        assert!(source[0].1 && source[0].0 < 2_000_000, "{source:?}");
        // The bridge is component 158 there, and asks TIMESYNC several times a second.
        assert!(from.iter().all(|c| *c == 158), "{from:?}");
        assert!(ap.timesync_replies > 200, "{}", ap.timesync_replies);
        let worst = errors.iter().map(|e| e.abs()).max().unwrap();
        println!("ppm {ppm}: worst {worst} µs");
        // The first mapping assumes equal rates until the fit converges (32 s of
        // samples): the clocks are up to 45 ppm apart here; then only ArduPilot's
        // estimate of the request's start and this test's 100 µs step remain.
        assert!(worst < 2_000, "ppm {ppm}: errors {errors:?}");
        let late = errors.iter().skip(25).map(|e| e.abs()).max().unwrap();
        println!("ppm {ppm}: converged worst {late} µs");
        assert!(late < 150, "ppm {ppm}: converged errors {errors:?}");
    }
}

#[test]
fn px4_stamping_at_parse_is_read_as_such() {
    let (errors, _, _, _) = fly(Stamp::Parse, 10, 40, 15);
    let worst = errors.iter().map(|e| e.abs()).max().unwrap();
    println!("PX4: worst {worst} µs");
    assert!(worst < 400, "errors {errors:?}");
}

#[test]
fn a_step_of_the_autopilots_utc_makes_utc_invalid_then_valid_at_the_new_time() {
    let mut ap = Autopilot::new(Stamp::RequestStart);
    // A GPS time correction of +1.2 s at 40 s.
    ap.step = Some((40_000_000, 1_200_000));
    let (errors, events, _, _) = fly_with(ap, 0, 70, 20);
    let lost: Vec<u64> = events
        .iter()
        .filter(|(_, e)| matches!(e, Event::UtcLost))
        .map(|(t, _)| *t)
        .collect();
    assert_eq!(lost.len(), 1, "{events:?}");
    assert!((40_000_000..40_200_000).contains(&lost[0]), "{lost:?}");
    let valid_again = events
        .iter()
        .find(|(t, e)| *t > lost[0] && matches!(e, Event::UtcValid { .. }))
        .map(|(t, _)| *t)
        .expect("valid again");
    assert!(valid_again - lost[0] < 1_000_000, "{valid_again}");
    // Every second of UTC it gave was right, before and after the step (40 s itself:
    // the step is not known yet; until 35 s the first mapping assumes equal rates).
    for (i, e) in errors.iter().enumerate() {
        let second = 20 + i;
        let bound = match second {
            40 => continue,
            ..35 => 2_000,
            _ => 150,
        };
        assert!(e.abs() < bound, "at {second} s: {errors:?}");
    }
}

#[test]
fn without_a_telemetry_link_nothing_is_sent_on_it() {
    let mut e = Engine::new(Config::for_fc(FcProtocol::Siyi));
    let mut buf = [0u8; MAX_FRAME_LEN];
    for ms in 0..5_000 {
        e.poll(Instant::from_millis(ms));
        assert!(e.transmit(Port::Telemetry, &mut buf).is_none());
    }
    while let Some(ev) = e.next_event() {
        assert!(!matches!(ev, Event::TimeSource { .. }), "{ev:?}");
    }
}

/// The autopilot falls silent (its cable pulled) on the telemetry link and, on the
/// MAVLink FC side, on the FC link: the engine keeps naming a future `poll_at` after each
/// poll (a caller that polls when it is due never spins), and the telemetry link stops
/// being the time source 3 s after the last HEARTBEAT (4 s) or SYSTEM_TIME (4.9 s), at
/// the latest by the next poll.
#[test]
fn a_silent_autopilot_leaves_no_deadline_in_the_past() {
    for (fc, port) in [
        (FcProtocol::Siyi, Port::Telemetry),
        (FcProtocol::Mavlink, Port::Fc),
    ] {
        let mut e = Engine::new(Config::for_fc(fc));
        let mut ap = Autopilot::new(Stamp::RequestStart);
        let mut buf = [0u8; MAX_FRAME_LEN];
        let mut polls_after_silence = 0;
        let mut left_at = None;
        for ms in 0..20_000u64 {
            let t = ms * 1000;
            let now = Instant::from_micros(t);
            // The autopilot speaks for 5 s, then nothing.
            if t < 5_000_000 {
                ap.poll(t);
                for (_, f) in std::mem::take(&mut ap.out) {
                    e.receive(now, port, &f);
                }
            }
            if e.poll_at().is_some_and(|p| p <= now) {
                e.poll(now);
                if t >= 5_000_000 {
                    polls_after_silence += 1;
                }
                assert!(
                    e.poll_at().is_none_or(|p| p > now),
                    "{fc:?}: poll_at {:?} at {now:?}",
                    e.poll_at()
                );
            }
            for p in [Port::Fc, Port::Pod, Port::Telemetry] {
                while e.transmit(p, &mut buf).is_some() {}
            }
            while let Some(ev) = e.next_event() {
                if ev == (Event::TimeSource { telemetry: false }) {
                    left_at = Some(t);
                }
            }
        }
        // TIMESYNC and stream requests go on (3 to 7 a second), and on the MAVLink side
        // the gimbal's 10 Hz attitude status: polls as often as that, no more.
        let per_second = if port == Port::Fc { 20 } else { 10 };
        assert!(
            polls_after_silence < 15 * per_second,
            "{fc:?}: {polls_after_silence} polls"
        );
        if port == Port::Telemetry {
            let left = left_at.expect("the FC link is the source again");
            assert!((7_000_000..8_200_000).contains(&left), "{left}");
        }
    }
}
