//! `gimbal bridge --pps` end to end in real time: the simulated FC and pod (`sim`, their
//! UTC the host's), a PPS test source over TCP (this test sends one byte at each whole
//! second of the host's UTC), and the photo event file. The bridge labels the edges from
//! the FC's UTC, locks its clock to them, and writes a row per geotagged photo.

use std::io::{BufRead, BufReader, Write};
use std::net::TcpStream;
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use serde_json::Value;

#[test]
fn a_tcp_pps_source_locks_the_clock_and_photos_go_to_the_event_file() {
    let file = std::env::temp_dir().join(format!("gimbal-photos-{}.csv", std::process::id()));
    let mut child = Command::new(env!("CARGO_BIN_EXE_gimbal"))
        .args([
            "bridge",
            "--fc",
            "gcu",
            "--fc-port",
            "sim",
            "--pod-port",
            "sim",
            "--pps",
            "tcp-listen:127.0.0.1:0",
            "--photo-events",
            file.to_str().unwrap(),
            "--sim-photo-every",
            "3",
            // A sync every 2 s: the pod's clock is UTC before its first photo.
            "--sync-period-ms",
            "2000",
            "--seconds",
            "12",
            "--events",
            "json",
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("run gimbal");
    let (tx, rx) = mpsc::channel::<Value>();
    let stdout = child.stdout.take().unwrap();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            if let Ok(v) = serde_json::from_str(&line)
                && tx.send(v).is_err()
            {
                break;
            }
        }
    });
    let mut events = Vec::new();
    let address = loop {
        let e = rx
            .recv_timeout(Duration::from_secs(10))
            .expect("the bridge says where the PPS source connects");
        let found = (e["event"] == "port_listening" && e["port"] == "pps")
            .then(|| e["address"].as_str().unwrap().to_string());
        events.push(e);
        if let Some(a) = found {
            break a;
        }
    };
    let mut source = TcpStream::connect(&address).expect("connect the PPS source");
    // One byte at each whole second of the host's UTC, for 10 s.
    for _ in 0..10 {
        let now = SystemTime::now().duration_since(UNIX_EPOCH).unwrap();
        std::thread::sleep(Duration::from_nanos(
            1_000_000_000 - u64::from(now.subsec_nanos()),
        ));
        let _ = source.write_all(b"P");
    }
    let status = child.wait().expect("wait");
    assert!(status.success());
    while let Ok(e) = rx.recv_timeout(Duration::from_secs(2)) {
        events.push(e);
    }
    let named = |n: &str| events.iter().filter(|e| e["event"] == n).count();
    assert_eq!(named("pps_locked"), 1, "{events:?}");
    let counters = events.iter().rfind(|e| e["event"] == "counters").unwrap();
    assert!(counters["pps_edges"].as_u64().unwrap() >= 8, "{counters}");
    assert_eq!(counters["pps_rejected"], 0, "{counters}");
    // Every photo the pod geotagged is a row.
    let photos = named("photo");
    assert!(photos >= 2, "{events:?}");
    let text = std::fs::read_to_string(&file).unwrap();
    let _ = std::fs::remove_file(&file);
    let rows: Vec<&str> = text.lines().skip(2).collect();
    assert_eq!(rows.len(), photos, "{text}");
    assert!(rows[0].starts_with("photo_0001,20"), "{text}");
    assert_eq!(rows[0].split(',').count(), 11, "{text}");
}
