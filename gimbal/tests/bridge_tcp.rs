//! `gimbal bridge` end to end over loopback TCP: the bridge process listens for the FC,
//! the pod and the RTC_IO line; `gimbal sim-fc siyi` (the simulated ArduPilot SIYI
//! driver) and `gimbal sim-pod` (the simulated K40T, its RTC_IO input over TCP) connect
//! as separate processes. The bridge's JSON events and the simulators' are checked.

use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use serde_json::Value;

/// Kills the process if the test fails before it ends.
struct Proc(Child);

impl Drop for Proc {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn gimbal(args: &[&str]) -> Proc {
    Proc(
        Command::new(env!("CARGO_BIN_EXE_gimbal"))
            .args(args)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("run gimbal"),
    )
}

/// The JSON lines of a process's stdout as they come.
fn lines(p: &mut Proc) -> mpsc::Receiver<Value> {
    let (tx, rx) = mpsc::channel();
    let stdout = p.0.stdout.take().expect("stdout");
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines() {
            let Ok(line) = line else { break };
            let v: Value = serde_json::from_str(&line)
                .unwrap_or_else(|e| panic!("not one JSON object per line: {e}: {line}"));
            if tx.send(v).is_err() {
                break;
            }
        }
    });
    rx
}

/// Waits for the process to end (at most `limit`) and returns its events and status.
fn finish(mut p: Proc, rx: &mpsc::Receiver<Value>, limit: Duration) -> (Vec<Value>, i32, String) {
    let end = Instant::now() + limit;
    let status = loop {
        if let Some(s) = p.0.try_wait().expect("wait") {
            break s;
        }
        assert!(Instant::now() < end, "gimbal did not stop in time");
        std::thread::sleep(Duration::from_millis(50));
    };
    let mut stderr = String::new();
    if let Some(mut e) = p.0.stderr.take() {
        let _ = std::io::Read::read_to_string(&mut e, &mut stderr);
    }
    let mut events = Vec::new();
    while let Ok(v) = rx.recv_timeout(Duration::from_secs(2)) {
        events.push(v);
    }
    (events, status.code().unwrap_or(-1), stderr)
}

fn named<'a>(events: &'a [Value], name: &str) -> Vec<&'a Value> {
    events.iter().filter(|e| e["event"] == name).collect()
}

#[test]
fn bridge_between_simulated_ardupilot_siyi_and_pod_processes_over_tcp() {
    end_to_end("siyi");
}

/// The GCU side takes its UTC from the GPS time held in 50 Hz packages: it needs the
/// line idle between them (a runner default above 12 ms once starved it of UTC).
#[test]
fn bridge_between_simulated_ardupilot_xfrobot_and_pod_processes_over_tcp() {
    end_to_end("gcu");
}

/// One three-process run at a time (the machine's cores are few).
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn end_to_end(fc_protocol: &str) {
    let _one = ONE_AT_A_TIME
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let started = Instant::now();
    let mut bridge = gimbal(&[
        "bridge",
        "--fc",
        fc_protocol,
        "--fc-port",
        "tcp-listen:127.0.0.1:0",
        "--pod-port",
        "tcp-listen:127.0.0.1:0",
        "--rtc-io",
        "tcp-listen:127.0.0.1:0",
        "--events",
        "json",
        "--seconds",
        "10",
        // Syncs every second and a UTC estimate trusted after 2 s of samples: the run
        // shows several syncs in seconds instead of minutes.
        "--sync-period-ms",
        "1000",
        "--discipline-bin-ms",
        "1000",
        "--discipline-min-bins",
        "2",
        "--discipline-min-span-ms",
        "2000",
    ]);
    let bridge_rx = lines(&mut bridge);
    // The listening addresses (port 0: the system picked free ones).
    let mut early = Vec::new();
    let address = |label: &str, early: &mut Vec<Value>| -> String {
        loop {
            if let Some(e) = early
                .iter()
                .find(|e| e["event"] == "port_listening" && e["port"] == label)
            {
                return e["address"].as_str().expect("address").to_string();
            }
            let e = bridge_rx
                .recv_timeout(Duration::from_secs(10))
                .expect("the bridge says where it listens");
            early.push(e);
        }
    };
    let fc_addr = format!("tcp:{}", address("fc", &mut early));
    let pod_addr = format!("tcp:{}", address("pod", &mut early));
    let rtc_addr = format!("tcp:{}", address("rtc_io", &mut early));

    let mut fc = gimbal(&[
        "sim-fc",
        fc_protocol,
        "--port",
        &fc_addr,
        "--seconds",
        "9",
        "--photo-every",
        "4",
        "--expect-healthy",
    ]);
    let fc_rx = lines(&mut fc);
    let mut pod = gimbal(&[
        "sim-pod",
        "--port",
        &pod_addr,
        "--rtc-io",
        &rtc_addr,
        "--seconds",
        "9",
    ]);
    let pod_rx = lines(&mut pod);

    let (fc_events, fc_code, fc_err) = finish(fc, &fc_rx, Duration::from_secs(20));
    let (pod_events, pod_code, pod_err) = finish(pod, &pod_rx, Duration::from_secs(20));
    let (rest, bridge_code, bridge_err) = finish(bridge, &bridge_rx, Duration::from_secs(20));
    let mut events = early;
    events.extend(rest);
    assert_eq!(bridge_code, 0, "bridge: {bridge_err}");
    assert_eq!(fc_code, 0, "sim-fc: {fc_err}");
    assert_eq!(
        pod_code,
        0,
        "sim-pod: {pod_err}\npod: {pod_events:?}\nbridge: {:?}",
        events
            .iter()
            .filter(|e| e["event"] != "translated")
            .collect::<Vec<_>>()
    );
    assert!(
        started.elapsed() < Duration::from_secs(25),
        "{:?}",
        started.elapsed()
    );

    for e in events.iter().chain(&fc_events).chain(&pod_events) {
        assert!(e["t_us"].is_u64(), "{e}");
        let name = e["event"].as_str().expect("event name");
        assert!(
            !name.is_empty() && name.bytes().all(|b| b.is_ascii_lowercase() || b == b'_'),
            "{name}"
        );
    }

    // The three connections were accepted, both links came up.
    for port in ["fc", "pod", "rtc_io"] {
        assert!(
            events
                .iter()
                .any(|e| e["event"] == "port_connected" && e["port"] == port),
            "{port} never connected"
        );
    }
    assert_eq!(named(&events, "fc_link_up").len(), 1);
    assert_eq!(named(&events, "pod_link_up").len(), 1);
    assert_eq!(named(&events, "utc_valid").len(), 1);

    // Time syncs: the UTC they carry is the host's (the simulated FC reads the system
    // clock), on the 1 s grid, each right after its RTC_IO rising edge.
    let syncs = named(&events, "time_sync");
    assert!(syncs.len() >= 2, "{syncs:?}");
    let now_ms = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .unwrap()
        .as_millis() as u64;
    for (i, s) in syncs.iter().enumerate() {
        let utc = s["utc_ms"].as_u64().expect("utc_ms");
        // On the 1 s grid; a pin raised late (a loaded machine) is re-stamped with the
        // UTC of the instant it rose: within milliseconds of the grid.
        let off_grid = (utc % 1000).min(1000 - utc % 1000);
        assert!(off_grid < 50, "{s}");
        assert!(now_ms.abs_diff(utc) < 30_000, "{utc} vs now {now_ms}");
        // Later each time, by whole periods (a loaded machine has been seen to leave
        // one period without a sync).
        if i > 0 {
            let step = utc - syncs[i - 1]["utc_ms"].as_u64().unwrap();
            assert!(step > 900 && (step + 100) % 1000 < 200, "{step}");
        }
        let at = events.iter().position(|e| std::ptr::eq(e, *s)).unwrap();
        let edge = events[..at]
            .iter()
            .rev()
            .find(|e| e["event"] == "rtc_io")
            .expect("an rtc_io event before the time_sync");
        assert_eq!(edge["level"], "high", "{edge}");
        assert_eq!(
            s["edge_us"], edge["t_us"],
            "the sync carries its edge's instant"
        );
        assert!(edge["t_us"].as_u64() <= s["t_us"].as_u64());
    }
    let highs = events
        .iter()
        .filter(|e| e["event"] == "rtc_io" && e["level"] == "high")
        .count();
    let lows = events
        .iter()
        .filter(|e| e["event"] == "rtc_io" && e["level"] == "low")
        .count();
    assert_eq!(highs, syncs.len());
    assert!(
        lows + 1 >= highs && lows <= highs,
        "{highs} high, {lows} low"
    );
    for d in named(&events, "edge_to_frame") {
        assert_eq!(
            d["len"], 28,
            "the 0x00030E is the first frame after the edge"
        );
        assert!(d["delay_us"].as_u64().unwrap() < 20_000, "{d}");
    }
    let stopped = named(&events, "stopped");
    assert_eq!(stopped.len(), 1);
    assert_eq!(stopped[0]["reason"], "seconds_elapsed");
    let counters = named(&events, "counters");
    assert_eq!(counters[0]["time_syncs"].as_u64(), Some(syncs.len() as u64));
    // No frame lost on the way (a loaded machine may delay a thread past the idle
    // time in the middle of a frame: at most 1 %).
    let fc_frames = counters[0]["fc_frames"].as_u64().unwrap();
    assert!(fc_frames > 100, "{fc_frames}");
    assert!(
        counters[0]["fc_rejected"].as_u64().unwrap() * 100 <= fc_frames,
        "{}",
        counters[0]
    );

    // The simulated ArduPilot became healthy and stayed so.
    let health = named(&fc_events, "sim_fc_health");
    assert_eq!(health.len(), 1, "{health:?}");
    assert_eq!(health[0]["healthy"], true);
    let summary = named(&fc_events, "summary");
    assert_eq!(summary[0]["healthy"], true);
    assert_eq!(summary[0]["parse_errors"], 0);

    // The pod received the syncs the bridge sent (the last may be cut off by the end),
    // with the same UTC. Whether it applied them depends on its RTC_IO byte arriving
    // before the frame over a second TCP connection, threads of another process: on a
    // loaded machine it may not, so that is counted, not required.
    let pod_syncs = named(&pod_events, "sim_pod_sync");
    assert!(pod_syncs.len() + 1 >= syncs.len(), "{pod_syncs:?}");
    for (p, s) in pod_syncs.iter().zip(&syncs) {
        assert_eq!(p["utc_ms"], s["utc_ms"], "{p} vs {s}");
        let outcome = p["outcome"].as_str().unwrap();
        assert!(
            [
                "applied",
                "no_edge",
                "edge_too_old",
                "edge_after_frame_start"
            ]
            .contains(&outcome),
            "{p}"
        );
    }
    let applied = pod_syncs
        .iter()
        .filter(|p| p["outcome"] == "applied")
        .count();
    // A photo the pod took once its clock was set (a sync applied) is geotagged; before
    // that its time of day is its own free-running clock and the bridge rightly refuses.
    let first_applied = pod_events
        .iter()
        .position(|e| e["event"] == "sim_pod_sync" && e["outcome"] == "applied");
    let photo_after_sync = first_applied.is_some_and(|i| {
        pod_events
            .iter()
            .skip(i)
            .any(|e| e["event"] == "sim_pod_photo")
    });
    let geotags = named(&events, "geotag");
    if photo_after_sync {
        assert!(geotags.iter().any(|e| e["answered"] == true), "{geotags:?}");
    } else {
        println!("{fc_protocol}: no photo after an applied sync; geotags {geotags:?}");
    }
    println!(
        "{fc_protocol}: the pod applied {applied} of {} syncs",
        pod_syncs.len()
    );
}

/// Waits for the first event matching `f`, keeping every event seen in `seen`.
fn wait_for(
    rx: &mpsc::Receiver<Value>,
    seen: &mut Vec<Value>,
    what: &str,
    f: impl Fn(&Value) -> bool,
) -> Value {
    let end = Instant::now() + Duration::from_secs(10);
    loop {
        let left = end.saturating_duration_since(Instant::now());
        let e = rx
            .recv_timeout(left)
            .unwrap_or_else(|_| panic!("no {what} within 10 s; saw {seen:?}"));
        seen.push(e.clone());
        if f(&e) {
            return e;
        }
    }
}

#[test]
fn a_lost_flight_controller_is_retried_with_backoff_and_reconnected() {
    // A port nothing listens on yet.
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port();
    let mut bridge = gimbal(&[
        "bridge",
        "--fc",
        "gcu",
        "--fc-port",
        &format!("tcp:127.0.0.1:{port}"),
        "--pod-port",
        "sim",
        "--events",
        "json",
        "--seconds",
        "20",
    ]);
    let rx = lines(&mut bridge);
    let mut seen = Vec::new();
    let is = |name: &'static str| move |e: &Value| e["event"] == name;
    // Refused: retried after 250 ms, then 500 ms.
    let first = wait_for(&rx, &mut seen, "port_error", is("port_error"));
    assert_eq!(first["port"], "fc");
    assert!(
        first["error"]
            .as_str()
            .unwrap()
            .contains("connection refused"),
        "{first}"
    );
    assert_eq!(first["retry_ms"], 250);
    let second = wait_for(&rx, &mut seen, "port_error", is("port_error"));
    assert_eq!(second["retry_ms"], 500);

    let listen = format!("tcp-listen:127.0.0.1:{port}");
    let sim_args = ["sim-fc", "gcu", "--port", &listen, "--seconds", "30"];
    let fc = gimbal(&sim_args);
    wait_for(&rx, &mut seen, "port_connected", is("port_connected"));
    wait_for(&rx, &mut seen, "fc_link_up", is("fc_link_up"));
    // The simulated FC goes away: the bridge sees the close, then the link time out.
    drop(fc);
    let closed = wait_for(&rx, &mut seen, "port_closed", is("port_closed"));
    assert_eq!(closed["port"], "fc");
    let down = wait_for(&rx, &mut seen, "fc_link_down", is("fc_link_down"));
    let gap = down["t_us"].as_u64().unwrap() - closed["t_us"].as_u64().unwrap();
    assert!(
        (1_000_000..3_500_000).contains(&gap),
        "link down {gap} µs after close"
    );
    // It comes back: reconnected (after refused retries) and the link is up again.
    let fc = gimbal(&sim_args);
    let again = wait_for(&rx, &mut seen, "port_connected", is("port_connected"));
    assert_eq!(again["port"], "fc");
    wait_for(&rx, &mut seen, "fc_link_up", is("fc_link_up"));
    drop(fc);
    drop(bridge);
    let ups = seen.iter().filter(|e| e["event"] == "fc_link_up").count();
    assert_eq!(ups, 2);
}

/// Frames of a MAVLink 2 byte stream: (header, message id).
fn mavlink_frames(bytes: &[u8]) -> Vec<(protocol_core::mavlink::Header, u32)> {
    use protocol_core::mavlink::{MavlinkFraming, Packet};
    use protocol_core::wire::{Deframer, Event};
    let mut d = Deframer::<_, 512>::new(MavlinkFraming::new());
    let mut out = Vec::new();
    d.push(bytes, |ev| {
        if let Event::Frame(f) = ev
            && let Ok(p) = Packet::decode(f)
        {
            out.push((p.header, p.message.id()));
        }
    });
    out
}

/// An autopilot's HEARTBEAT (system 1, component 1, a quadrotor running ArduPilot).
fn autopilot_heartbeat(sequence: u8) -> Vec<u8> {
    use protocol_core::mavlink::dialect::{
        HEARTBEAT_DATA, MavAutopilot, MavModeFlag, MavState, MavType,
    };
    use protocol_core::mavlink::{Header, MavMessage, encode};
    let hb = MavMessage::HEARTBEAT(HEARTBEAT_DATA {
        custom_mode: 0,
        mavtype: MavType::MAV_TYPE_QUADROTOR,
        autopilot: MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA,
        base_mode: MavModeFlag::empty(),
        system_status: MavState::MAV_STATE_STANDBY,
        mavlink_version: 3,
    });
    let header = Header {
        sequence,
        system_id: 1,
        component_id: 1,
    };
    let mut buf = [0u8; 64];
    let n = encode(&hb, &header, &mut buf).expect("encode HEARTBEAT");
    buf[..n].to_vec()
}

/// `--telemetry-port`: the bridge listens for the autopilot's MAVLink port beside its FC
/// and pod links (both simulated here); this test is the autopilot, one that sends its
/// HEARTBEAT and nothing else. The bridge says nothing there until it hears it, then
/// sends its own HEARTBEAT (component 158, MAV_COMP_ID_PERIPHERAL, with the autopilot's
/// system id), TIMESYNC requests and SET_MESSAGE_INTERVAL for the streams it wants.
///
/// While the bridge asks for the streams once a second (its first five tries), its
/// HEARTBEAT, four COMMAND_LONG and a TIMESYNC go out together: they fit the 256-byte
/// telemetry queue (a 192-byte queue dropped the HEARTBEAT, found by this test), so a
/// HEARTBEAT comes every second and nothing is dropped.
#[test]
fn the_telemetry_port_carries_the_bridges_heartbeat_after_the_autopilots() {
    use std::io::{Read, Write};
    let _one = ONE_AT_A_TIME
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let mut bridge = gimbal(&[
        "bridge",
        "--fc",
        "siyi",
        "--fc-port",
        "sim",
        "--pod-port",
        "sim",
        "--telemetry-port",
        "tcp-listen:127.0.0.1:0",
        "--telemetry-baud",
        "57600",
        "--events",
        "json",
        "--seconds",
        "12",
    ]);
    let rx = lines(&mut bridge);
    let mut seen = Vec::new();
    let started = wait_for(&rx, &mut seen, "bridge_started", |e| {
        e["event"] == "bridge_started"
    });
    assert_eq!(
        started["telemetry_port"], "tcp-listen:127.0.0.1:0",
        "{started}"
    );
    assert_eq!(started["telemetry_baud"], 57_600, "{started}");
    let listening = wait_for(&rx, &mut seen, "port_listening", |e| {
        e["event"] == "port_listening" && e["port"] == "telemetry"
    });
    let address = listening["address"].as_str().expect("address");
    let mut ap = std::net::TcpStream::connect(address).expect("connect to the telemetry port");
    ap.set_read_timeout(Some(Duration::from_millis(100)))
        .unwrap();
    let mut writer = ap.try_clone().unwrap();
    let mut read_for = |d: Duration, got: &mut Vec<u8>| {
        let end = Instant::now() + d;
        let mut buf = [0u8; 1024];
        while Instant::now() < end {
            match ap.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => got.extend_from_slice(&buf[..n]),
                Err(e)
                    if matches!(
                        e.kind(),
                        std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                    ) => {}
                Err(e) => panic!("telemetry read: {e}"),
            }
        }
    };
    // Silence until the autopilot is heard.
    let mut before = Vec::new();
    read_for(Duration::from_millis(1500), &mut before);
    assert!(before.is_empty(), "the bridge spoke first: {before:02x?}");
    // The autopilot's HEARTBEAT at 1 Hz for 8 s.
    let mut after = Vec::new();
    for seq in 0..8u8 {
        writer.write_all(&autopilot_heartbeat(seq)).unwrap();
        read_for(Duration::from_secs(1), &mut after);
    }
    let frames = mavlink_frames(&after);
    let heartbeats: Vec<_> = frames
        .iter()
        .filter(|(h, id)| *id == 0 && h.component_id == 158)
        .collect();
    assert!(heartbeats.len() >= 6, "{frames:?}");
    assert!(
        heartbeats.iter().all(|(h, _)| h.system_id == 1),
        "{frames:?}"
    );
    drop(writer);

    let (rest, code, err) = finish(bridge, &rx, Duration::from_secs(20));
    assert_eq!(code, 0, "bridge: {err}");
    seen.extend(rest);
    assert!(
        seen.iter()
            .any(|e| e["event"] == "port_connected" && e["port"] == "telemetry"),
        "{seen:?}"
    );
    let counters = named(&seen, "counters");
    let c = counters.last().expect("counters");
    assert!(c["telemetry_frames"].as_u64().unwrap() >= 8, "{c}");
    assert!(c["telemetry_sent"].as_u64().unwrap() >= 8, "{c}");
    assert_eq!(c["dropped"], 0, "{c}");
    println!("telemetry: counters {c}");
    // The SIYI side ran as without the telemetry port.
    assert_eq!(named(&seen, "fc_link_up").len(), 1);
    assert_eq!(named(&seen, "pod_link_up").len(), 1);
}
