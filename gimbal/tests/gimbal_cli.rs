//! The `gimbal` command-line tool, run as a process.

use std::io::Write;
use std::process::{Command, Output, Stdio};

use serde_json::Value;

const ZOOM: &str = "FD 03 04 01 07 02 01 04 03 00 00 2D 00 CE 89";
const ZOOM_ACK: &str = "FD 02 02 01 07 04 01 04 03 01 00 00 E8 EB";
const SYNC: &str =
    "FD 10 04 01 09 02 01 0E 03 00 00 A8 DA 76 9B 01 00 00 20 FE FF FF 00 00 00 00 7D E5";

fn gimbal(args: &[&str], stdin: Option<&[u8]>) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_gimbal"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run gimbal");
    let mut input = child.stdin.take().expect("stdin");
    input
        .write_all(stdin.unwrap_or_default())
        .expect("write stdin");
    drop(input);
    child.wait_with_output().expect("gimbal output")
}

fn stdout_lines(o: &Output) -> Vec<String> {
    assert!(
        o.status.success(),
        "gimbal failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8(o.stdout.clone())
        .expect("utf-8")
        .lines()
        .map(str::to_owned)
        .collect()
}

fn hex_bytes(s: &str) -> Vec<u8> {
    s.split_whitespace()
        .map(|t| u8::from_str_radix(t, 16).expect("hex"))
        .collect()
}

#[test]
fn messages_k40t_lists_all_75_base_ids() {
    let lines = stdout_lines(&gimbal(&["messages", "k40t"], None));
    assert_eq!(lines.len(), 75);
    assert!(lines.contains(&"0x000304 HybridZoom request,ack,status".to_string()));
    assert!(lines.contains(&"0x000001 GimbalStatus report".to_string()));
    assert!(lines.contains(&"0x000310 GpsRequest request,ack".to_string()));
    assert!(lines.contains(&"0x000502 SbusConfig request,ack".to_string()));
}

#[test]
fn decode_json_reports_frames_garbage_and_bad_frames() {
    let bad = ZOOM.replace("CE 89", "CE 88");
    let capture = format!("00 13 {ZOOM} {ZOOM_ACK} {bad} {SYNC} FD 05 04");
    let args: Vec<&str> = ["decode", "k40t", "--json"]
        .into_iter()
        .chain(capture.split(' '))
        .collect();
    let lines = stdout_lines(&gimbal(&args, None));
    let objs: Vec<Value> = lines
        .iter()
        .map(|l| serde_json::from_str(l).expect("json line"))
        .collect();
    assert_eq!(objs.len(), 6, "{lines:#?}");

    assert_eq!(objs[0]["protocol"], "k40t");
    assert_eq!(objs[0]["raw"], "0013");
    assert!(objs[0]["error"].as_str().unwrap().starts_with("garbage"));

    assert_eq!(objs[1]["msg_id"], 0x000304);
    assert_eq!(objs[1]["name"], "HybridZoom");
    assert_eq!(objs[1]["fields"]["zoom_x10"], 45);
    assert_eq!(objs[1]["fields"]["seq"], 7);
    assert_eq!(objs[1]["fields"]["kind"], "request");
    assert_eq!(objs[1]["raw"], ZOOM.replace(' ', "").to_lowercase());

    assert_eq!(objs[2]["msg_id"], 0x010304);
    assert_eq!(objs[2]["fields"]["code"]["name"], "Ok");
    assert_eq!(objs[2]["fields"]["code"]["code"], 0);

    assert!(
        objs[3]["error"].as_str().unwrap().contains("checksum"),
        "{}",
        objs[3]
    );
    assert_eq!(objs[3]["raw"], bad.replace(' ', "").to_lowercase());
    assert!(objs[3].get("msg_id").is_none());

    assert_eq!(objs[4]["msg_id"], 0x00030E);
    assert_eq!(objs[4]["fields"]["unix_ms"], 1_767_225_600_000u64);
    assert_eq!(objs[4]["fields"]["tz_minuteswest"], -480);

    assert_eq!(objs[5]["raw"], "fd0504");
    assert!(
        objs[5]["error"].as_str().unwrap().starts_with("truncated"),
        "{}",
        objs[5]
    );
}

#[test]
fn decode_reads_binary_and_hex_files_and_stdin() {
    let dir = std::env::temp_dir().join(format!("gimbal-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bin = dir.join("capture.bin");
    let mut bytes = hex_bytes(ZOOM);
    bytes.extend(hex_bytes(SYNC));
    std::fs::write(&bin, &bytes).unwrap();
    let txt = dir.join("capture.txt");
    std::fs::write(&txt, format!("{ZOOM}\n{SYNC}\n")).unwrap();

    for args in [
        vec!["decode", "k40t", "--file", bin.to_str().unwrap()],
        vec!["decode", "k40t", "--file", txt.to_str().unwrap()],
    ] {
        let lines = stdout_lines(&gimbal(&args, None));
        assert_eq!(lines.len(), 2, "{lines:?}");
        assert!(
            lines[0].contains("0x000304 HybridZoom") && lines[0].contains("zoom_x10=45"),
            "{}",
            lines[0]
        );
        assert!(
            lines[1].contains("0x00030e TimeSync") && lines[1].contains("unix_ms=1767225600000"),
            "{}",
            lines[1]
        );
    }
    let lines = stdout_lines(&gimbal(&["decode", "k40t"], Some(&bytes)));
    assert_eq!(lines.len(), 2);
    let o = gimbal(
        &["decode", "k40t"],
        Some(format!("{ZOOM_ACK}\n").as_bytes()),
    );
    let lines = stdout_lines(&o);
    assert!(lines[0].contains("code=Ok(0x00)"), "{}", lines[0]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("1 frames decoded"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_usage_is_an_error_with_status_2() {
    for args in [
        &["decode", "nosuch", "00"][..],
        &["frobnicate", "k40t"],
        &[],
        &["decode", "k40t", "0"],
        &["decode", "k40t", "--json", "--nosuch"],
        &["messages"],
        &["bridge", "--fc", "siyi", "--fc-port", "sim"],
        &[
            "bridge",
            "--fc",
            "px4",
            "--fc-port",
            "sim",
            "--pod-port",
            "sim",
        ],
        &[
            "bridge",
            "--fc",
            "siyi",
            "--fc-port",
            "ttyUSB0",
            "--pod-port",
            "sim",
        ],
        &[
            "bridge",
            "--fc",
            "siyi",
            "--fc-port",
            "tcp:host",
            "--pod-port",
            "sim",
        ],
        &[
            "bridge",
            "--fc",
            "siyi",
            "--fc-port",
            "sim",
            "--pod-port",
            "sim",
            "--rtc-io",
            "gpio17",
        ],
        &[
            "bridge",
            "--fc",
            "siyi",
            "--fc-port",
            "sim",
            "--pod-port",
            "sim",
            "--seconds",
            "-1",
        ],
        &[
            "bridge",
            "--fc",
            "siyi",
            "--fc-port",
            "sim",
            "--pod-port",
            "sim",
            "--sync-period-ms",
            "999",
        ],
        // Two different rates for one link: found after parsing, still a usage error.
        &[
            "bridge",
            "--fc",
            "siyi",
            "--fc-port",
            "/dev/null:9600",
            "--fc-baud",
            "57600",
            "--pod-port",
            "sim",
        ],
        &["sim-fc", "siyi", "--port", "sim"],
        &["sim-pod"],
        &["completions", "tcsh"],
    ] {
        let o = gimbal(args, None);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(!o.stderr.is_empty());
    }
}

#[test]
fn every_subcommand_has_help_and_completions_are_generated() {
    let top = stdout_lines(&gimbal(&["--help"], None)).join("\n");
    let subcommands = [
        "decode",
        "messages",
        "bridge",
        "sim-fc",
        "sim-pod",
        "report",
        "completions",
    ];
    for sub in subcommands {
        assert!(top.contains(sub), "{sub} missing from --help:\n{top}");
        let help = stdout_lines(&gimbal(&[sub, "--help"], None)).join("\n");
        assert!(
            help.contains(&format!("Usage: gimbal {sub}")),
            "{sub} --help:\n{help}"
        );
    }
    let bridge = stdout_lines(&gimbal(&["bridge", "--help"], None)).join("\n");
    for option in [
        "--fc-port",
        "--pod-port",
        "--rtc-io",
        "--events",
        "--trace",
        "--seconds",
        "--sync-period-ms",
        "--sync-width-ms",
        "--leap-seconds",
        "--siyi-hardware-id",
        "--viewlink-model",
        "--gcu-hardware-x10",
        "--k40t-geotag-fallback-ms",
        "--tz-minuteswest",
        "tcp-listen:",
        "udp:HOST:PORT",
        "udp-listen:",
    ] {
        assert!(bridge.contains(option), "{option} missing:\n{bridge}");
    }
    for (shell, marker) in [
        ("bash", "_gimbal()"),
        ("zsh", "#compdef gimbal"),
        ("fish", "complete -c gimbal"),
    ] {
        let script = stdout_lines(&gimbal(&["completions", shell], None)).join("\n");
        assert!(script.contains(marker), "{shell}: {marker} missing");
        assert!(
            script.contains("sim-pod") && script.contains("--fc-port"),
            "{shell}"
        );
    }
}

#[test]
fn a_missing_serial_device_is_a_clear_runtime_error() {
    let o = gimbal(
        &[
            "bridge",
            "--fc",
            "gcu",
            "--fc-port",
            "/dev/no-such-gimbal-tty:57600",
            "--pod-port",
            "sim",
        ],
        None,
    );
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("fc port /dev/no-such-gimbal-tty") && err.contains("no such device"),
        "{err}"
    );
    let o = gimbal(
        &[
            "bridge",
            "--fc",
            "siyi",
            "--fc-port",
            "sim",
            "--pod-port",
            "sim",
            "--rtc-io",
            "gpiochip99:4",
        ],
        None,
    );
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("RTC_IO /dev/gpiochip99 line 4"), "{err}");
}

#[test]
fn bridge_with_simulated_ports_traces_decoded_frames_both_ways() {
    let o = gimbal(
        &[
            "bridge",
            "--fc",
            "viewlink",
            "--fc-port",
            "sim",
            "--pod-port",
            "sim",
            "--events",
            "json",
            "--trace",
            "--seconds",
            "2.5",
        ],
        None,
    );
    let events: Vec<Value> = stdout_lines(&o)
        .iter()
        .map(|l| serde_json::from_str(l).expect("one JSON object per line"))
        .collect();
    for e in &events {
        assert!(e["t_us"].is_u64(), "{e}");
        assert!(e["event"].is_string(), "{e}");
    }
    let names: Vec<&str> = events
        .iter()
        .map(|e| e["event"].as_str().unwrap())
        .collect();
    assert_eq!(names[0], "bridge_started");
    assert_eq!(events[0]["fc"], "viewlink");
    assert_eq!(events[0]["log_version"], 1);
    // The track: a fix at most once a second, with its position.
    let fixes: Vec<&Value> = events.iter().filter(|e| e["event"] == "fix").collect();
    assert!((1..=3).contains(&fixes.len()), "{} fixes", fixes.len());
    assert!(
        fixes[0]["lat_e7"].as_i64().is_some_and(|l| l != 0),
        "{}",
        fixes[0]
    );
    let at: Vec<u64> = fixes.iter().map(|f| f["t_us"].as_u64().unwrap()).collect();
    assert!(at.windows(2).all(|w| w[1] >= w[0] + 1_000_000), "{at:?}");
    assert!(
        names.contains(&"fc_link_up") && names.contains(&"pod_link_up"),
        "{names:?}"
    );
    assert_eq!(names[names.len() - 2..], ["stopped", "counters"]);
    assert_eq!(events[names.len() - 2]["reason"], "seconds_elapsed");
    let frames: Vec<&Value> = events.iter().filter(|e| e["event"] == "frame").collect();
    for (port, protocol) in [("fc", "viewlink"), ("pod", "k40t")] {
        for dir in ["rx", "tx"] {
            let decoded: Vec<&&Value> = frames
                .iter()
                .filter(|f| f["port"] == port && f["dir"] == dir && f["name"].is_string())
                .collect();
            assert!(!decoded.is_empty(), "no decoded {port} {dir} frame");
            for f in &decoded {
                assert_eq!(f["protocol"], protocol, "{f}");
                assert!(f["raw"].as_str().is_some_and(|r| r.len() >= 8), "{f}");
                assert!(f.get("text").is_none(), "{f}");
            }
        }
    }
    // Frames the bridge received are the engine's counts.
    let counters = &events[names.len() - 1];
    let fc_rx = frames
        .iter()
        .filter(|f| f["port"] == "fc" && f["dir"] == "rx" && f["name"].is_string())
        .count() as u64;
    let counted = counters["fc_frames"].as_u64().unwrap();
    assert!(
        fc_rx.abs_diff(counted) <= 2,
        "{fc_rx} traced, {counted} counted"
    );
}

#[test]
fn bridge_prints_a_human_log_without_json() {
    let o = gimbal(
        &[
            "bridge",
            "--fc",
            "siyi",
            "--fc-port",
            "sim",
            "--pod-port",
            "sim",
            "--seconds",
            "1.5",
        ],
        None,
    );
    let lines = stdout_lines(&o);
    assert!(lines.iter().all(|l| !l.starts_with('{')), "{lines:?}");
    let link = lines
        .iter()
        .find(|l| l.contains("fc_link_up"))
        .expect("fc_link_up line");
    // `    0.001773 fc_link_up`: seconds with microseconds, then the name.
    let (secs, rest) = link.trim_start().split_once(' ').unwrap();
    assert!(secs.parse::<f64>().is_ok_and(|s| s < 1.5), "{link}");
    assert_eq!(rest.trim(), "fc_link_up");
    assert!(
        lines
            .iter()
            .any(|l| l.contains("stopped") && l.contains("reason=seconds_elapsed")),
        "{lines:?}"
    );
}

#[test]
fn ctrl_c_stops_the_bridge_cleanly() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_gimbal"))
        .args([
            "bridge",
            "--fc",
            "gcu",
            "--fc-port",
            "sim",
            "--pod-port",
            "sim",
            "--events",
            "json",
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run gimbal");
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill");
    assert!(kill.success());
    let start = std::time::Instant::now();
    while child.try_wait().expect("wait").is_none() {
        if start.elapsed() > std::time::Duration::from_secs(5) {
            let _ = child.kill();
            panic!("still running 5 s after SIGINT");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let o = child.wait_with_output().expect("output");
    let events: Vec<Value> = stdout_lines(&o)
        .iter()
        .map(|l| serde_json::from_str(l).expect("JSON"))
        .collect();
    let stopped = events
        .iter()
        .find(|e| e["event"] == "stopped")
        .expect("a stopped event");
    assert_eq!(stopped["reason"], "interrupted");
    let secs = stopped["seconds"].as_f64().unwrap();
    assert!((1.0..5.0).contains(&secs), "{secs}");
    assert_eq!(events.last().unwrap()["event"], "counters");
    assert!(events.iter().any(|e| e["event"] == "fc_link_up"));
}

#[test]
fn report_writes_a_page_and_lists_the_lines_it_could_not_read() {
    let dir = std::env::temp_dir().join(format!("gimbal-cli-report-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let log = dir.join("flight.jsonl");
    let o = gimbal(&["demo", "--seconds", "30", "--events", "json"], None);
    let mut lines = stdout_lines(&o);
    assert!(
        lines[0].starts_with(r#"{"t_us":0,"event":"demo_started""#),
        "{}",
        lines[0]
    );
    lines[2].truncate(10);
    std::fs::write(&log, lines.join("\n")).expect("written");
    let o = gimbal(&["report", log.to_str().expect("UTF-8")], None);
    assert!(o.status.success());
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("flight.jsonl: line 3: cut off (truncated JSON)"),
        "{stderr}"
    );
    assert!(stderr.contains("wrote "), "{stderr}");
    let page = std::fs::read_to_string(dir.join("flight.html")).expect("the page, beside the log");
    assert!(page.starts_with("<!DOCTYPE html>") && page.contains("<svg"));
    let o = gimbal(
        &["report", "/nonexistent/flight.jsonl", "-o", "x.html"],
        None,
    );
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("/nonexistent/flight.jsonl"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `gimbal --version`: the workspace's version, the commit of this checkout (`-dirty`
/// when its tracked files have changes) and the features of the bridge it runs; the same
/// line as `bridge_started`'s `build` (docs/src/firmware/configuration.md#versions).
#[test]
fn version_names_the_release_the_commit_and_the_features() {
    let line = stdout_lines(&gimbal(&["--version"], None)).join("\n");
    let git = |args: &[&str]| {
        Command::new("git")
            .args(args)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .env("GIT_OPTIONAL_LOCKS", "0")
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    let commit = git(&["rev-parse", "--short=12", "HEAD"]);
    let commit = match commit {
        // Built in this checkout: its commit; dirty as git says now (a change after the
        // build would rebuild `gimbal` before this test runs).
        Some(c) => {
            let dirty = git(&["status", "--porcelain", "--untracked-files=no"])
                .is_some_and(|s| !s.is_empty());
            format!("{c}{}", if dirty { "-dirty" } else { "" })
        }
        None => "unknown".to_string(),
    };
    assert_eq!(
        line,
        format!(
            "gimbal {} commit {commit}, host: fc-siyi fc-viewlink fc-gcu fc-k40t fc-mavlink telemetry",
            env!("CARGO_PKG_VERSION")
        )
    );
}
