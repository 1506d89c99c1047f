//! What the security chapter promises (docs/src/security.md), each against the engine as
//! an attacker on the link would try it (issue 33): one gate for everything that changes
//! something (camera settings and file writes too), a pinned autopilot, no replay after a
//! restart or an eviction, the K40T guard on every frame kind, refusals that never push
//! out the time-sync and geotag events, and the chapter's gate table the code's.

use std::collections::BTreeMap;

use bridge_engine::access::{GATED, Gated};
use bridge_engine::{
    Config, Engine, Event, FcProtocol, Instant, MAX_FRAME_LEN, Port, Refusal, SigningKey,
    SigningMode,
};
use fuzz_checks::bridge_mavlink::{autopilot_heartbeat_of, ftp_from, param_set_from, signed};
use protocol_core::k40t::{self, Address, GimbalAttitude, GpsRequest, Kind, MsgId, TimeSync};
use protocol_core::mavlink::dialect::{COMMAND_LONG_DATA, HEARTBEAT_DATA, MavCmd, MavParamExtType};
use protocol_core::mavlink::{self, Header, MavMessage};

const KEY: [u8; 32] = *b"the bridge's 32-byte signing key";
/// A signing timestamp (10 µs units since 2015): 2026.
const T0: u64 = 3_500_000_000_000;

fn ms(t: u64) -> Instant {
    Instant::from_millis(t)
}

fn mav(sys: u8, comp: u8, msg: &MavMessage) -> Vec<u8> {
    let mut buf = [0u8; mavlink::MAX_FRAME_LEN];
    let header = Header {
        sequence: 0,
        system_id: sys,
        component_id: comp,
    };
    let n = mavlink::encode(msg, &header, &mut buf).unwrap();
    buf[..n].to_vec()
}

fn heartbeat(sys: u8) -> Vec<u8> {
    autopilot_heartbeat_of(sys)
}

/// IMAGE_START_CAPTURE (one photo) to the camera of system 1, from `(sys, comp)`.
fn photo(sys: u8, comp: u8) -> Vec<u8> {
    let cmd = MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
        param3: 1.0,
        command: MavCmd::MAV_CMD_IMAGE_START_CAPTURE,
        target_system: 1,
        target_component: 100,
        ..COMMAND_LONG_DATA::default()
    });
    mav(sys, comp, &cmd)
}

fn param_set(sys: u8, name: &str, value: u8) -> Vec<u8> {
    param_set_from(
        sys,
        name,
        u32::from(value),
        MavParamExtType::MAV_PARAM_EXT_TYPE_UINT8,
    )
}

fn ftp(sys: u8, opcode: u8, data: &[u8]) -> Vec<u8> {
    ftp_from(sys, 0, opcode, data.len() as u8, 0, data)
}

/// A pod report (its attitude), as the pod sends it.
fn pod_report(config: &Config, seq: u8) -> Vec<u8> {
    let header = k40t::Header::new(config.pod.gimbal, config.pod.own, seq);
    let mut buf = [0u8; k40t::MAX_FRAME_LEN];
    let n = k40t::encode(&GimbalAttitude::default(), &header, &mut buf).unwrap();
    buf[..n].to_vec()
}

fn drain(e: &mut Engine, port: Port) -> Vec<Vec<u8>> {
    let mut buf = [0u8; MAX_FRAME_LEN];
    std::iter::from_fn(|| e.transmit(port, &mut buf).map(|n| buf[..n].to_vec())).collect()
}

fn events(e: &mut Engine) -> Vec<Event> {
    std::iter::from_fn(|| e.next_event()).collect()
}

fn refusals(events: &[Event]) -> Vec<(Refusal, u32, u8)> {
    events
        .iter()
        .filter_map(|e| match *e {
            Event::Refused {
                reason, id, sender, ..
            } => Some((reason, id, sender)),
            _ => None,
        })
        .collect()
}

/// Frames queued for the pod by `f`'s input.
fn pod_sent_by<R>(e: &mut Engine, f: impl FnOnce(&mut Engine) -> R) -> u32 {
    let before = e.counters().pod_sent;
    let _ = f(e);
    e.counters().pod_sent - before
}

/// The MAVLink side with its autopilot (system 1) heard and the pod reporting.
fn mavlink_side(config: Config, sign: impl Fn(Vec<u8>) -> Vec<u8>) -> Engine {
    let mut e = Engine::new(config);
    e.receive(ms(10), Port::Fc, &sign(heartbeat(1)));
    for i in 0..20u8 {
        e.receive(
            ms(20 + u64::from(i) * 100),
            Port::Pod,
            &pod_report(&config, i),
        );
        e.poll(ms(20 + u64::from(i) * 100));
    }
    drain(&mut e, Port::Fc);
    drain(&mut e, Port::Pod);
    events(&mut e);
    e
}

/// A camera setting (PARAM_EXT_SET) and a file write (MAVLink FTP WriteFile) pass the
/// gate as commands do: from a system that may not command they are refused and never
/// reach the pod; unsigned under required signing too; a listed ground station's set
/// becomes the pod's set command; the camera definition's reads stay open to anyone.
/// (Issue 33, defect 1: on 9e3aa0d system 77's set reached the pod.)
#[test]
fn camera_settings_and_file_writes_pass_the_gate() {
    let config = Config::for_fc(FcProtocol::Mavlink);
    let mut e = mavlink_side(config, |f| f);
    let t = ms(3000);
    let sent = pod_sent_by(&mut e, |e| {
        e.receive(t, Port::Fc, &param_set(77, "CAM_ISO", 3));
    });
    assert_eq!(sent, 0, "system 77's setting never reaches the pod");
    // A second later (one report a second per reason and sender).
    let write = ftp(77, 7, b"data");
    e.receive(ms(4000), Port::Fc, &write);
    assert_eq!(
        refusals(&events(&mut e)),
        vec![(Refusal::Sender, 323, 77), (Refusal::Sender, 110, 77)]
    );
    assert_eq!(e.counters().refused_sender, 2);
    // Reads stay open: OpenFileRO of the camera definition is answered (ACK, opcode 128).
    drain(&mut e, Port::Fc);
    e.receive(t, Port::Fc, &ftp(77, 4, b"k40t.xml.xz"));
    let answered = drain(&mut e, Port::Fc).iter().any(|f| {
        matches!(mavlink::Packet::decode(f), Ok(p) if matches!(
            p.message,
            mavlink::Message::Known(MavMessage::FILE_TRANSFER_PROTOCOL(ref d)) if d.payload[3] == 128
        ))
    });
    assert!(answered, "the camera definition is open to read");
    // QGroundControl (255, listed) sets it: the pod's set command goes out.
    let sent = pod_sent_by(&mut e, |e| {
        e.receive(t, Port::Fc, &param_set(255, "CAM_ISO", 3));
    });
    assert!(
        sent >= 1,
        "the listed ground station's setting reaches the pod"
    );

    // Required signing, unsigned telemetry read: an unsigned set from the autopilot's own
    // system is refused as unsigned; signed, it is taken.
    let mut c = config;
    c.signing = SigningMode::Require;
    c.signing_key = Some(SigningKey(KEY));
    c.signing_unsigned_telemetry = true;
    let mut e = mavlink_side(c, |f| f);
    let sent = pod_sent_by(&mut e, |e| {
        e.receive(t, Port::Fc, &param_set(1, "CAM_ISO", 3));
    });
    assert_eq!(sent, 0);
    assert_eq!(refusals(&events(&mut e)), vec![(Refusal::Unsigned, 323, 1)]);
    let sent = pod_sent_by(&mut e, |e| {
        e.receive(t, Port::Fc, &signed(&param_set(1, "CAM_ISO", 3), KEY, T0));
    });
    assert!(sent >= 1, "signed, the autopilot's setting reaches the pod");
}

/// The autopilot's system id is pinned: another autopilot's HEARTBEAT on the link
/// (system 2) changes nothing (the device keeps system 1, its TIMESYNC requests keep
/// asking system 1, system 2's command is refused), is counted each time and reported
/// once. Once system 1 has been silent for `autopilot_forget_ms`, the next autopilot
/// heard is learnt. A configured `autopilot_sysid` takes none other. (Issue 33, defect 2:
/// on 9e3aa0d each heartbeat flipped the system id.)
#[test]
fn the_autopilot_is_pinned() {
    let config = Config::for_fc(FcProtocol::Mavlink);
    let mut e = mavlink_side(config, |f| f);
    let mut frames = Vec::new();
    for k in 0..10u64 {
        let t = 3000 + k * 1000;
        e.receive(ms(t), Port::Fc, &heartbeat(2));
        e.receive(ms(t + 500), Port::Fc, &heartbeat(1));
        for step in (0..1000).step_by(50) {
            e.poll(ms(t + step));
            frames.extend(drain(&mut e, Port::Fc));
        }
    }
    let refused = pod_sent_by(&mut e, |e| e.receive(ms(13_100), Port::Fc, &photo(2, 1)));
    assert_eq!(refused, 0, "system 2 may not command");
    assert!(frames.len() > 100);
    for f in &frames {
        let p = mavlink::Packet::decode(f).unwrap();
        assert_eq!(p.header.system_id, 1, "the device stays system 1");
        if let mavlink::Message::Known(MavMessage::TIMESYNC(t)) = p.message {
            assert!(t.tc1 != 0 || t.target_system == 1, "TIMESYNC asks system 1");
        }
    }
    let ev = events(&mut e);
    let others: Vec<_> = ev
        .iter()
        .filter(|e| matches!(e, Event::OtherAutopilot { .. }))
        .collect();
    assert_eq!(
        others,
        vec![&Event::OtherAutopilot {
            port: Port::Fc,
            sysid: 2
        }]
    );
    assert_eq!(e.counters().other_autopilots, 10);
    assert!(refusals(&ev).contains(&(Refusal::Sender, 2000, 2)));

    // System 1 falls silent: after 30 s (the default) system 2 is learnt, not before.
    let last_one = 12_500u64;
    let mut learnt_at = None;
    for t in (13_000..50_000u64).step_by(1000) {
        e.receive(ms(t), Port::Fc, &heartbeat(2));
        e.poll(ms(t));
        let twos = drain(&mut e, Port::Fc)
            .iter()
            .any(|f| mavlink::Packet::decode(f).unwrap().header.system_id == 2);
        if twos && learnt_at.is_none() {
            learnt_at = Some(t);
        }
    }
    let learnt_at = learnt_at.expect("system 2 learnt once system 1 is forgotten");
    assert!(
        (last_one + 30_000..last_one + 31_000).contains(&learnt_at),
        "{learnt_at}"
    );

    // Configured: system 5 only.
    let mut c = config;
    c.autopilot_sysid = 5;
    let mut e = Engine::new(c);
    e.receive(ms(10), Port::Fc, &heartbeat(1));
    e.poll(ms(20));
    assert!(
        drain(&mut e, Port::Fc).is_empty(),
        "system 1 is not the autopilot"
    );
    e.receive(ms(30), Port::Fc, &heartbeat(5));
    e.poll(ms(40));
    let f = drain(&mut e, Port::Fc);
    assert!(!f.is_empty());
    assert!(
        f.iter()
            .all(|f| mavlink::Packet::decode(f).unwrap().header.system_id == 5)
    );
}

fn signing_config() -> Config {
    let mut c = Config::for_fc(FcProtocol::Mavlink);
    c.signing = SigningMode::Require;
    c.signing_key = Some(SigningKey(KEY));
    c
}

/// Captured at the start of a flight and replayed after the bridge restarts: the
/// autopilot's heartbeat and a photo command, both signed. Without what the store keeps
/// (a bridge that remembers nothing: 9e3aa0d) they are taken and the photo reaches the pod;
/// with the records the first run saved they are refused (stale: older than the restored
/// timestamp by more than the new-stream minute). (Issue 33, defect 3.)
#[test]
fn a_captured_frame_does_not_replay_after_a_restart() {
    let config = signing_config();
    let captured = [
        signed(&heartbeat(1), KEY, T0),
        signed(&photo(1, 190), KEY, T0 + 100),
    ];
    // The first run: the flight's first frames (captured), then five minutes of the
    // autopilot's heartbeats; the store task writes each record it is given.
    let mut e = Engine::new(config);
    let mut kept: BTreeMap<u16, Vec<u8>> = BTreeMap::new();
    for (i, f) in captured.iter().enumerate() {
        e.receive(ms(i as u64), Port::Fc, f);
    }
    for k in 1..=300u64 {
        e.receive(
            ms(k * 1000),
            Port::Fc,
            &signed(&heartbeat(1), KEY, T0 + k * 100_000),
        );
        e.poll(ms(k * 1000));
        while let Some(r) = e.take_record() {
            kept.insert(r.key.0, r.value().to_vec());
        }
        drain(&mut e, Port::Fc);
    }
    assert!(kept.contains_key(&bridge_engine::store::Key::SIGNING_FC.0));

    let replay = |restore: bool| {
        let mut e = Engine::new(config);
        if restore {
            for (k, v) in &kept {
                e.restore(*k, v);
            }
        }
        for i in 0..5u8 {
            e.receive(ms(u64::from(i) * 10), Port::Pod, &pod_report(&config, i));
        }
        drain(&mut e, Port::Pod);
        let sent = pod_sent_by(&mut e, |e| {
            for f in &captured {
                e.receive(ms(100), Port::Fc, f);
            }
        });
        (sent, e.counters().refused_stale)
    };
    let (sent, stale) = replay(false);
    assert!(
        sent >= 1,
        "a bridge that remembers nothing takes the replay"
    );
    assert_eq!(stale, 0);
    let (sent, stale) = replay(true);
    assert_eq!(sent, 0, "the photo command never reaches the pod");
    assert_eq!(stale, 2, "both frames refused as stale");
}

/// A stream evicted from the eight-stream table is not a fresh stream: its captured
/// command replayed after eight newer streams pushed it out is refused as a replay.
/// (Issue 33, defect 3: on 9e3aa0d it was taken as a new stream within the minute.)
#[test]
fn a_captured_frame_does_not_replay_after_its_stream_is_evicted() {
    let config = signing_config();
    let mut e = mavlink_side(config, |f| signed(&f, KEY, T0));
    let command = signed(&photo(1, 190), KEY, T0 + 10);
    let sent = pod_sent_by(&mut e, |e| e.receive(ms(3000), Port::Fc, &command));
    assert!(sent >= 1, "taken once");
    // Eight other components of system 1 sign later: the table's eight slots.
    for comp in 191..=198u8 {
        let hb = mav(1, comp, &MavMessage::HEARTBEAT(HEARTBEAT_DATA::default()));
        e.receive(
            ms(3100),
            Port::Fc,
            &signed(&hb, KEY, T0 + 20 + u64::from(comp)),
        );
    }
    let sent = pod_sent_by(&mut e, |e| e.receive(ms(5000), Port::Fc, &command));
    assert_eq!(sent, 0, "the replay never reaches the pod");
    assert_eq!(e.counters().refused_replayed, 1);
}

/// The K40T side's guard holds for every frame kind of a guarded base id: an ACK, a
/// status frame and a kind the document does not name, each for the TF card format
/// (0x030D), are never forwarded and each is refused; the request itself gets the failure
/// ACK. (Issue 33, defect 4: on 9e3aa0d only requests were guarded.)
#[test]
fn the_k40t_guard_holds_for_every_frame_kind() {
    let config = Config::for_fc(FcProtocol::K40t);
    let mut e = Engine::new(config);
    e.poll(ms(0));
    drain(&mut e, Port::Pod);
    let header = k40t::Header::new(Address::FLIGHT_CONTROLLER, Address::POD, 9);
    let ids = [0x00_030D, 0x01_030D, 0x02_030D, 0x05_030D, 0xFF_030D];
    let mut logged = Vec::new();
    for (i, id) in ids.into_iter().enumerate() {
        let id = MsgId::from_u32(id);
        let payload = [0u8; 64];
        let message = k40t::Message::decode(
            id,
            &payload[..k40t::Message::decode(id, &[]).map_or(0, |m| m.payload_len())],
        )
        .unwrap();
        let mut buf = [0u8; k40t::MAX_FRAME_LEN];
        let n = k40t::Packet { header, message }.emit(&mut buf).unwrap();
        // A second apart: each is reported (one report a second per reason and link).
        e.receive(ms(10 + i as u64 * 1000), Port::Fc, &buf[..n]);
        logged.extend(events(&mut e));
    }
    assert!(drain(&mut e, Port::Pod).is_empty(), "none forwarded");
    let acks = drain(&mut e, Port::Fc);
    assert_eq!(acks.len(), 1, "the request alone is answered");
    assert_eq!(
        k40t::Frame::new_checked(&acks[0][..]).unwrap().id(),
        MsgId::new(Kind::Ack, 0x030D)
    );
    let expected: Vec<_> = ids.iter().map(|id| (Refusal::Guarded, *id, 0)).collect();
    assert_eq!(refusals(&logged), expected);
    assert_eq!(e.counters().refused_guarded, 5);
}

/// A peer with the wrong key floods the telemetry link for a simulated minute (500
/// frames a second from 200 system ids) while a K40T FC gives time and the pod asks for
/// geotags, and the log drains the events only once a second: every time-sync and geotag
/// event is there, every refusal is counted, and the refusals that are reported are few.
/// (Issue 33, defect 5: on 9e3aa0d the flood pushed them out of the 16-event queue.)
#[test]
fn a_minute_of_wrong_key_frames_displaces_no_sync_or_geotag_event() {
    let mut config = Config::for_fc(FcProtocol::K40t);
    config.signing = SigningMode::Require;
    config.signing_key = Some(SigningKey(KEY));
    let mut e = Engine::new(config);
    let utc0: u64 = 1_767_225_600_000; // 2026-01-01T00:00:00Z, ms
    let mut logged = Vec::new();
    let mut flood = 0u32;
    let mut seq = 0u8;
    for t in (0..60_000u64).step_by(10) {
        let now = ms(t);
        // The flood: five frames every 10 ms, signed with another key.
        for j in 0..5u64 {
            let sys = ((t / 10 * 5 + j) % 200 + 1) as u8;
            let f = signed(&heartbeat(sys), [9; 32], T0 + t * 100 + j);
            e.receive(now, Port::Telemetry, &f);
            flood += 1;
        }
        seq = seq.wrapping_add(1);
        if t % 1000 == 0 {
            // The FC's time, once a second (K40T 0x00030E: a UTC sample).
            let sync = TimeSync {
                unix_ms: utc0 + t,
                tz_minuteswest: 0,
                tz_dsttime: 0,
            };
            let h = k40t::Header::new(Address::FLIGHT_CONTROLLER, Address::POD, seq);
            let mut buf = [0u8; k40t::MAX_FRAME_LEN];
            let n = k40t::encode(&sync, &h, &mut buf).unwrap();
            e.receive(now, Port::Fc, &buf[..n]);
        }
        if t % 2000 == 1000 {
            // The pod asks where a photo was taken (answered after the FC's 200 ms).
            let s = (t / 1000) as u8;
            let request = GpsRequest {
                hour: 0,
                minute: s / 60,
                second: s % 60,
                millisecond: 0,
                ..GpsRequest::default()
            };
            let h = k40t::Header::new(config.pod.gimbal, config.pod.own, seq);
            let mut buf = [0u8; k40t::MAX_FRAME_LEN];
            let n = k40t::encode(&request, &h, &mut buf).unwrap();
            e.receive(now, Port::Pod, &buf[..n]);
        }
        if let Some(p) = e.pin().filter(|p| p.at <= now) {
            e.pin_done(p.level, p.at);
        }
        if e.poll_at().is_some_and(|at| at <= now) {
            e.poll(now);
        }
        drain(&mut e, Port::Fc);
        drain(&mut e, Port::Pod);
        drain(&mut e, Port::Telemetry);
        // A slow logger: the events once a second.
        if t % 1000 == 990 {
            logged.extend(events(&mut e));
        }
    }
    logged.extend(events(&mut e));
    let c = e.counters();
    let syncs = logged
        .iter()
        .filter(|e| matches!(e, Event::TimeSync { .. }))
        .count();
    let geotags = logged
        .iter()
        .filter(|e| matches!(e, Event::Geotag { .. }))
        .count();
    // Measured: 5 syncs (one every 10 s once UTC is known) and 30 geotag requests.
    assert!(syncs >= 4, "{syncs} syncs");
    assert_eq!(syncs, c.time_syncs as usize, "every sync event logged");
    assert_eq!(geotags, 30, "every geotag event logged");
    assert_eq!(
        geotags,
        (c.geotags + c.geotags_failed) as usize,
        "every geotag answered is logged"
    );
    assert_eq!(c.events_dropped, 0);
    assert_eq!(c.refused_bad_signature, flood, "every refusal counted");
    let reported = refusals(&logged).len() as u32;
    assert_eq!(reported + c.refusals_unreported, flood);
    // At most four wait at a time, drained once a second: at most 4 a second (measured
    // 240 of 30,000, bound 244: the queue's cap, the reason it holds).
    assert!(reported <= 4 * 61, "{reported} refusals reported");
}

/// The security chapter's table of gated messages is the code's (`access::GATED`): the
/// same messages, ids, and FTP opcodes.
#[test]
fn the_chapter_lists_the_gated_messages_of_the_code() {
    let chapter = include_str!("../../../docs/src/security.md");
    let start = chapter
        .find("| id | message | what it changes |")
        .expect("the gate's table in docs/src/security.md");
    let rows: Vec<Vec<String>> = chapter[start..]
        .lines()
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .map(|l| {
            l.trim_matches('|')
                .split('|')
                .map(|c| c.trim().to_owned())
                .collect()
        })
        .collect();
    assert_eq!(rows.len(), GATED.len(), "{rows:?}");
    for (row, g) in rows.iter().zip(GATED.iter()) {
        let id: u32 = row[0].parse().unwrap();
        assert_eq!((id, row[1].trim_matches('`')), (g.id, g.name), "{row:?}");
        // FTP: the gated opcodes, as the numbers the row starts its third cell with.
        let opcodes: Vec<u8> = row[2]
            .strip_prefix("opcodes ")
            .map(|rest| {
                rest.split('(')
                    .next()
                    .unwrap()
                    .split(|c: char| !c.is_ascii_digit())
                    .filter(|s| !s.is_empty())
                    .map(|s| s.parse().unwrap())
                    .collect()
            })
            .unwrap_or_default();
        assert_eq!(opcodes.as_slice(), g.opcodes.unwrap_or(&[]), "{row:?}");
    }
    // And the lookup follows the table.
    assert!(Gated::of(110, &[0, 1, 100, 0, 0, 0, 7]).is_some());
    assert!(Gated::of(110, &[0, 1, 100, 0, 0, 0, 5]).is_none());
    assert!(Gated::of(0, &[]).is_none());
}
