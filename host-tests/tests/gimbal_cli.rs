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
    ] {
        let o = gimbal(args, None);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(!o.stderr.is_empty());
    }
}
