//! The bridge's one configuration: `bridge_engine::Config` read from the
//! configuration file (`bridge-fw/bridge.toml`, as the firmware's `build.rs` reads it),
//! checked by `Config::validate`, overridden by `gimbal bridge`'s options; and the book's
//! key table (docs/src/firmware/configuration.md, its "Configuration" section) checked
//! against all three.

use std::collections::BTreeSet;
use std::process::Command;

use bridge_engine::config::{Limit, VideoConfig};
use bridge_engine::{Config, Duration, FcProtocol};
use clap::Parser;
use gimbal::cli::{Cli, Command as Sub};
use gimbal::runner::bridge::config_of;
use toml::{Table, Value};

const BRIDGE_TOML: &str = include_str!("../../bridge-fw/bridge.toml");
// The book page with the key table (the constant keeps its name from when the table was
// in the README).
const README: &str = include_str!("../../docs/src/firmware/configuration.md");

/// The file's text deserialized and validated, as `build.rs` does (`fc = "auto"` aside).
fn load(text: &str) -> Result<Config, String> {
    let mut keys: Table = text.parse().map_err(|e| format!("{e}"))?;
    if keys.get("fc").and_then(Value::as_str) == Some("auto") {
        keys.remove("fc");
    }
    let c: Config = keys
        .try_into()
        .map_err(|e| format!("{e}").trim_end().replace('\n', " "))?;
    c.validate().map_err(|e| e.to_string())?;
    Ok(c)
}

/// Every key of a table, sections flattened (`sync.period_ms`), in the file's order.
fn leaf_keys(t: &Table, prefix: &str, out: &mut Vec<(String, Value)>) {
    for (k, v) in t {
        match v {
            Value::Table(sub) => leaf_keys(sub, &format!("{prefix}{k}."), out),
            v => out.push((format!("{prefix}{k}"), v.clone())),
        }
    }
}

/// The keys `Config` deserializes at one level (`section` "" for the top), from serde's
/// own list in its unknown-field error.
fn accepted(section: &str) -> BTreeSet<String> {
    let text = if section.is_empty() {
        "no_such_key = 1".to_string()
    } else {
        format!("[{section}]\nno_such_key = 1")
    };
    let e = text
        .parse::<Table>()
        .unwrap()
        .try_into::<Config>()
        .unwrap_err();
    let e = e.to_string();
    let expected = &e[e.find("expected").expect(&e)..];
    let expected = expected.lines().next().unwrap();
    expected
        .split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_owned)
        .collect()
}

#[test]
fn bridge_toml_lists_every_key_with_its_default() {
    let file: Table = BRIDGE_TOML.parse().unwrap();
    assert_eq!(file["fc"].as_str(), Some("auto"));
    assert_eq!(load(BRIDGE_TOML), Ok(Config::DEFAULT));

    let sections: Vec<&String> = file
        .iter()
        .filter(|(_, v)| v.is_table())
        .map(|(k, _)| k)
        .collect();
    assert_eq!(
        accepted(""),
        file.keys().cloned().collect::<BTreeSet<_>>(),
        "top-level keys"
    );
    for section in sections {
        assert_eq!(
            accepted(section),
            file[section.as_str()]
                .as_table()
                .unwrap()
                .keys()
                .cloned()
                .collect::<BTreeSet<_>>(),
            "[{section}]"
        );
    }
}

#[test]
fn the_readme_table_is_the_configuration() {
    let section = &README[README.find("### Configuration\n").unwrap()..];
    let section = &section[..section.find("\n### ").unwrap()];
    let rows: Vec<Vec<&str>> = section
        .lines()
        .filter(|l| l.starts_with("| `"))
        .map(|l| l.trim_matches('|').split(" | ").map(str::trim).collect())
        .filter(|cells: &Vec<&str>| cells.len() == 5)
        .collect();
    let file: Table = BRIDGE_TOML.parse().unwrap();
    let mut keys = Vec::new();
    leaf_keys(&file, "", &mut keys);
    assert_eq!(
        rows.iter()
            .map(|r| r[0].trim_matches('`'))
            .collect::<Vec<_>>(),
        keys.iter().map(|(k, _)| k.as_str()).collect::<Vec<_>>(),
        "the README's keys, in bridge.toml's order"
    );
    for (row, (key, value)) in rows.iter().zip(&keys) {
        assert_eq!(row[1], format!("`{value}`"), "{key}: default");
        let option = format!("--{}", key.replace(['.', '_'], "-"));
        if key != "gcu.resync_mark" {
            assert!(
                row[4].starts_with(&format!("`{option}")),
                "{key}: {}",
                row[4]
            );
        }
    }
    for limit in Limit::ALL {
        let row = rows
            .iter()
            .find(|r| r[0] == format!("`{}`", limit.key))
            .unwrap_or_else(|| panic!("{}: no row", limit.key));
        assert!(
            row[2].contains(&format!("{}..={}", limit.min, limit.max)),
            "{}: {}",
            limit.key,
            row[2]
        );
    }
}

#[test]
fn every_key_is_read_and_checked() {
    let c = load(
        r#"
        fc = "viewlink"
        fc_baud = 57600
        pod_baud = 921600
        leap_seconds = 19
        tz_minuteswest = -480
        fc_link_timeout_ms = 1500
        fc_silence_stop_ms = 300
        k40t_geotag_fallback_ms = "off"
        signing = "require"
        signing_key = "000102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f"
        signing_unsigned_telemetry = true
        gcs_ids = [7]
        k40t_allow = [0x00030D, 0x000501]
        [sync]
        period_ms = 2000
        width_ms = 20
        [siyi]
        hardware_id = "6B0000000002"
        max_zoom_x10 = 100
        [viewlink]
        model = "K40T"
        [gcu]
        hardware_x10 = 11
        gimbal_code = 13
        resync_mark = false
        [pod]
        yaw_positive_left = true
        pitch_positive_down = true
        [video]
        uri = "rtsp://10.1.2.3:8554/main"
        [lens]
        visible_hfov_1x_cdeg = 6200
        ir_hfov_cdeg = 4800
        focal_length_min_um = 4500
        focal_length_max_um = 49500
        sensor_width_um = 6170
        sensor_height_um = 4550
        resolution_h = 1920
        resolution_v = 1080
        [laser]
        periodic = true
        min_distance_cm = 500
        max_distance_cm = 60000
        [discipline]
        bin_ms = 1000
        min_bins = 3
        min_span_ms = 2000
        [mavlink]
        allow_destructive = true
        "#,
    )
    .unwrap();
    let mut want = Config::for_fc(FcProtocol::Viewlink);
    want.fc_baud = 57_600;
    want.pod_baud = 921_600;
    want.leap_seconds = 19;
    want.tz_minuteswest = -480;
    want.fc_link_timeout = Duration::from_millis(1500);
    want.fc_silence_stop = Duration::from_millis(300);
    want.k40t_geotag_fallback = None;
    want.sync.period = Duration::from_millis(2000);
    want.sync.width = Duration::from_millis(20);
    want.siyi.hardware_id = *b"6B0000000002";
    want.siyi.max_zoom_x10 = 100;
    want.viewlink.model = *b"K40T\0\0\0\0\0\0";
    want.gcu.hardware_x10 = 11;
    want.gcu.gimbal_code = 13;
    want.gcu.resync_mark = false;
    want.pod.yaw_positive_left = true;
    want.pod.pitch_positive_down = true;
    want.video.uri = VideoConfig::parse_uri("rtsp://10.1.2.3:8554/main").unwrap();
    want.lens.visible_hfov_1x_cdeg = 6200;
    want.lens.ir_hfov_cdeg = 4800;
    want.lens.focal_length_min_um = 4500;
    want.lens.focal_length_max_um = 49500;
    want.lens.sensor_width_um = 6170;
    want.lens.sensor_height_um = 4550;
    want.lens.resolution_h = 1920;
    want.lens.resolution_v = 1080;
    want.laser.periodic = true;
    want.laser.min_distance_cm = 500;
    want.laser.max_distance_cm = 60000;
    want.discipline.bin_len = Duration::from_millis(1000);
    want.discipline.min_bins = 3;
    want.discipline.min_span = Duration::from_millis(2000);
    want.mavlink.allow_destructive = true;
    want.signing = bridge_engine::SigningMode::Require;
    want.signing_key = Some(bridge_engine::SigningKey(std::array::from_fn(|i| i as u8)));
    want.signing_unsigned_telemetry = true;
    want.gcs_ids = bridge_engine::SystemIds::from_list(&[7]).unwrap();
    want.k40t_allow = bridge_engine::K40tAllow::from_list(&[0x030D, 0x0501]).unwrap();
    assert_eq!(c, want);
    assert_eq!(
        load("k40t_geotag_fallback_ms = 350")
            .unwrap()
            .k40t_geotag_fallback,
        Some(Duration::from_millis(350))
    );

    // Each range, from the file: the key and the range in the message.
    for limit in Limit::ALL {
        if limit.key == "gcs_ids" {
            // Each id of a list: below.
            continue;
        }
        let (section, key) = limit.key.split_once('.').unwrap_or(("", limit.key));
        let header = if section.is_empty() {
            String::new()
        } else {
            format!("[{section}]\n")
        };
        for (value, ok) in [
            (limit.min, true),
            (limit.max, true),
            (limit.min - 1, false),
            (limit.max + 1, false),
        ] {
            let got = load(&format!("{header}{key} = {value}"));
            if ok {
                assert!(got.is_ok(), "{} = {value}: {got:?}", limit.key);
            } else {
                let e = got.unwrap_err();
                // Beyond the field's type (below zero, a u8 above 255, a u16 above
                // 65535): the deserializer's message, with the key; else the key's own
                // range.
                let beyond_type = value < 0 && limit.min >= 0
                    || value > 255 && limit.max == 255
                    || value > 65_535 && key == "max_zoom_x10";
                let expected = if beyond_type {
                    format!("in `{}`", limit.key)
                } else {
                    format!(
                        "{}: {value} is out of range {}..={}",
                        limit.key, limit.min, limit.max
                    )
                };
                assert!(e.contains(&expected), "{} = {value}: {e}", limit.key);
            }
        }
    }
}

#[test]
fn errors_name_the_key() {
    for (text, wanted) in [
        ("fc_baud = 12", "fc_baud: 12 is out of range 1200..=4000000"),
        ("no_such = 1", "unknown field `no_such`"),
        ("[sync]\nlead_ms = 1", "unknown field `lead_ms`"),
        (
            "leap_seconds = 300",
            "300 is out of range 0..=255 in `leap_seconds`",
        ),
        (
            "[gcu]\ngimbal_code = -1",
            "-1 is out of range 0..=255 in `gcu.gimbal_code`",
        ),
        (
            "fc_link_timeout_ms = -1",
            "expected a time in ms in `fc_link_timeout_ms`",
        ),
        ("fc = \"mavlink1\"", "unknown variant `mavlink1`"),
        (
            "[siyi]\nhardware_id = \"7A\"",
            "expected 12 ASCII characters",
        ),
        (
            "[viewlink]\nmodel = \"ELEVENCHARS\"",
            "expected 1 to 10 printable ASCII",
        ),
        (
            "k40t_geotag_fallback_ms = \"never ever\"",
            "k40t_geotag_fallback_ms",
        ),
        ("[gcu]\nresync_mark = 1", "resync_mark"),
        (
            "[video]\nuri = \"rtsp://a b\"",
            "expected up to 160 printable ASCII characters, no space",
        ),
        (
            "[lens]\nir_hfov_cdeg = 18000",
            "lens.ir_hfov_cdeg: 18000 is out of range 0..=17999",
        ),
        ("gcs_ids = [0]", "0 is out of range 1..=255 in `gcs_ids`"),
        (
            "gcs_ids = [256]",
            "256 is out of range 1..=255 in `gcs_ids`",
        ),
        (
            "gcs_ids = [1, 2, 3, 4, 5, 6, 7, 8, 9]",
            "more than 8 values",
        ),
        (
            "k40t_allow = [0x000302]",
            "is not one of the pod's destructive requests",
        ),
        ("signing = \"sometimes\"", "unknown variant `sometimes`"),
        (
            "signing_key = \"abc\"",
            "expected 64 hexadecimal characters",
        ),
        ("signing = \"sign\"", "signing_key: needed"),
    ] {
        let e = load(text).unwrap_err();
        assert!(e.contains(wanted), "{text:?}: {e}");
    }
}

/// A file with a key that was removed: an error naming the key and what replaced it, from
/// `gimbal bridge --config` as from the firmware's build (its `build.rs` calls the same
/// `removed_key` first).
#[test]
fn removed_keys_name_what_replaced_them() {
    let dir = std::env::temp_dir().join(format!("gimbal-removed-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (section, key, value) in [
        ("siyi", "camera_version", "[0, 3, 1]"),
        ("siyi", "gimbal_version", "[0, 3, 1]"),
        ("siyi", "zoom_version", "[0, 1, 0]"),
        ("viewlink", "firmware", "[0, 1, 0]"),
        ("gcu", "firmware_x10", "10"),
    ] {
        let path = dir.join(format!("{section}-{key}.toml"));
        std::fs::write(&path, format!("[{section}]\n{key} = {value}\n")).unwrap();
        let e = config_of(&bridge_args(&["--config", path.to_str().unwrap()])).unwrap_err();
        assert!(
            e.ends_with(&format!(
                "{section}.{key}: removed in 0.2.0: the bridge reports its own version \
                 (see docs/src/firmware/configuration.md#versions)"
            )),
            "{e}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

fn bridge_args(extra: &[&str]) -> Box<gimbal::cli::BridgeArgs> {
    let mut args = vec![
        "gimbal",
        "bridge",
        "--fc",
        "gcu",
        "--fc-port",
        "sim",
        "--pod-port",
        "sim",
    ];
    args.extend_from_slice(extra);
    match Cli::try_parse_from(args).unwrap().command {
        Sub::Bridge(b) => b,
        _ => unreachable!(),
    }
}

#[test]
fn the_command_line_overrides_the_file() {
    let dir = std::env::temp_dir().join(format!("gimbal-config-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("mine.toml");
    std::fs::write(
        &path,
        "fc = \"siyi\"\nfc_baud = 57600\n[sync]\nperiod_ms = 2000\nwidth_ms = 100\n\
         [gcu]\nresync_mark = false\n[pod]\nyaw_positive_left = true\n",
    )
    .unwrap();
    let file = path.to_str().unwrap();

    // Without options: the file, with --fc's protocol.
    let (c, _) = config_of(&bridge_args(&["--config", file])).unwrap();
    assert_eq!(c.fc, FcProtocol::Gcu);
    assert_eq!(c.fc_baud, 57_600);
    assert_eq!(c.sync.period, Duration::from_millis(2000));
    assert_eq!(c.sync.width, Duration::from_millis(100));
    assert!(!c.gcu.resync_mark);
    assert!(c.pod.yaw_positive_left);
    assert_eq!(c.pod_baud, 115_200);

    // Options over the file; flags not given leave the file's value.
    let (c, _) = config_of(&bridge_args(&[
        "--config",
        file,
        "--fc-baud",
        "9600",
        "--sync-width-ms",
        "30",
        "--pod-pitch-positive-down",
        "--siyi-hardware-id",
        "6B0000000002",
        "--k40t-geotag-fallback-ms",
        "off",
        "--gcu-gimbal-code",
        "7",
        "--video-uri",
        "rtsp://192.168.1.7:558/live/single",
        "--lens-visible-hfov-1x-cdeg",
        "6000",
        "--laser-periodic",
    ]))
    .unwrap();
    assert_eq!(c.fc_baud, 9600);
    assert_eq!(c.sync.period, Duration::from_millis(2000));
    assert_eq!(c.sync.width, Duration::from_millis(30));
    assert!(c.pod.yaw_positive_left && c.pod.pitch_positive_down);
    assert!(!c.gcu.resync_mark);
    assert_eq!(c.gcu.gimbal_code, 7);
    assert_eq!(c.siyi.hardware_id, *b"6B0000000002");
    assert_eq!(c.k40t_geotag_fallback, None);
    assert_eq!(
        c.video.configured_uri(),
        Some(&b"rtsp://192.168.1.7:558/live/single"[..])
    );
    assert_eq!(c.lens.visible_hfov_1x_cdeg, 6000);
    assert!(c.laser.periodic);

    // A port's :BAUD overrides the file too.
    let args = bridge_args(&["--config", file]);
    let mut args = *args;
    args.fc_port = "/dev/ttyS9:19200".parse().unwrap();
    assert_eq!(config_of(&args).unwrap().0.fc_baud, 19_200);

    // Without a file: the defaults, as before.
    let (c, _) = config_of(&bridge_args(&[])).unwrap();
    assert_eq!(c, Config::for_fc(FcProtocol::Gcu));

    // A bad file: a usage error (exit 2) naming the file and the key.
    std::fs::write(&path, "[sync]\nperiod_ms = 10\n").unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_gimbal"))
        .args([
            "bridge",
            "--fc",
            "siyi",
            "--fc-port",
            "sim",
            "--pod-port",
            "sim",
            "--config",
            file,
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("mine.toml: sync.period_ms: 10 is out of range 1000..=3600000"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_security_options_set_their_keys() {
    let dir = std::env::temp_dir().join(format!("gimbal-signing-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let key = dir.join("key.hex");
    std::fs::write(&key, format!("{}\n", "ab".repeat(32))).unwrap();
    let (c, _) = config_of(&bridge_args(&[
        "--signing",
        "require",
        "--signing-key-file",
        key.to_str().unwrap(),
        "--signing-unsigned-telemetry",
        "--gcs-ids",
        "none",
        "--k40t-allow",
        "0x00030D,0x000316",
    ]))
    .unwrap();
    assert_eq!(c.signing, bridge_engine::SigningMode::Require);
    assert_eq!(c.signing_key, Some(bridge_engine::SigningKey([0xAB; 32])));
    assert!(c.signing_unsigned_telemetry);
    assert_eq!(c.gcs_ids, bridge_engine::SystemIds::NONE);
    assert!(c.k40t_allow.allows(0x030D) && c.k40t_allow.allows(0x0316));
    assert!(!c.k40t_allow.allows(0x030F));
    // Signing without a key, or a key file that is not one: refused, naming the key.
    let e = config_of(&bridge_args(&["--signing", "sign"])).unwrap_err();
    assert!(e.contains("signing_key: needed"), "{e}");
    std::fs::write(&key, "not a key").unwrap();
    let e = config_of(&bridge_args(&["--signing-key-file", key.to_str().unwrap()])).unwrap_err();
    assert!(e.contains("expected 64 hexadecimal characters"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

/// `gimbal bridge --console` and its client `gimbal config`: settings set through the
/// console, dumped, loaded back (the same settings again), saved in the state directory;
/// `reboot` ends the run, and the next run starts with them.
#[test]
fn gimbal_config_through_the_bridges_console_and_a_setting_kept_across_a_restart() {
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;
    use std::time::Duration as StdDuration;

    let dir = std::env::temp_dir().join(format!("k40t-console-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let state = dir.join("state");
    let state = state.to_str().unwrap();
    // A bridge with its console on a free port; returns it and the console's address.
    let start = || {
        let mut child = Command::new(env!("CARGO_BIN_EXE_gimbal"))
            .args([
                "bridge",
                "--fc",
                "siyi",
                "--fc-port",
                "sim",
                "--pod-port",
                "sim",
            ])
            .args(["--console", "tcp-listen:127.0.0.1:0", "--state-dir", state])
            .args(["--events", "json", "--seconds", "60"])
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
        let address = loop {
            let line = lines
                .next()
                .expect("the bridge says where it listens")
                .unwrap();
            let v: serde_json::Value = serde_json::from_str(&line).unwrap();
            if v["event"] == "port_listening" && v["port"] == "console" {
                break v["address"].as_str().unwrap().to_owned();
            }
        };
        (child, lines, format!("tcp:{address}"))
    };
    let config = |port: &str, args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_gimbal"))
            .args(["config", "--port", port])
            .args(args)
            .output()
            .unwrap();
        let text = String::from_utf8(out.stdout).unwrap();
        let err = String::from_utf8(out.stderr).unwrap();
        (out.status.success(), text, err)
    };

    let (mut bridge, mut events, port) = start();
    let (ok, said, err) = config(&port, &["set", "leap_seconds", "19"]);
    assert!(ok, "{said} {err}");
    assert!(said.contains("leap_seconds = 19"), "{said}");
    let (ok, _, err) = config(&port, &["set", "video.uri", "rtsp://10.0.0.9:554/live"]);
    assert!(ok, "{err}");
    // A refusal: the value's reason, exit 1, nothing changed.
    let (ok, _, err) = config(&port, &["set", "leap_seconds", "300"]);
    assert!(!ok && err.contains("error"), "{err}");
    let (ok, said, _) = config(&port, &["get", "leap_seconds"]);
    assert!(ok && said.trim() == "leap_seconds = 19", "{said}");

    let (ok, dump, err) = config(&port, &["dump"]);
    assert!(ok, "{err}");
    assert!(dump.contains("leap_seconds = 19\n"), "{dump}");
    assert!(
        dump.contains("video.uri = \"rtsp://10.0.0.9:554/live\""),
        "{dump}"
    );
    assert!(dump.contains("# signing_key: write-only"), "{dump}");
    let file = dir.join("dump.toml");
    std::fs::write(&file, &dump).unwrap();
    // Changed after the dump; the dump loads back to the same settings (and saves them).
    let (ok, _, _) = config(&port, &["set", "leap_seconds", "25"]);
    assert!(ok);
    let (ok, said, err) = config(&port, &["load", file.to_str().unwrap()]);
    assert!(ok, "{said} {err}");
    assert!(said.contains("settings kept"), "{said}");
    let (_, again, _) = config(&port, &["dump"]);
    assert_eq!(again, dump, "a dump loads back to the same settings");

    // `reboot`: the run ends (a service manager starts it again).
    let mut console = gimbal::console_client::ConsolePort::open(&port, 115_200).unwrap();
    let a = console.command("reboot").unwrap();
    assert!(a.ok(), "{a:?}");
    let status = bridge.wait().unwrap();
    assert!(status.success());
    let stopped = events
        .by_ref()
        .map_while(Result::ok)
        .find(|l| l.contains("\"stopped\""))
        .unwrap();
    assert!(stopped.contains("\"reboot\""), "{stopped}");

    // The next start: the settings kept in the state directory.
    let (mut bridge, _, port) = start();
    let (ok, said, _) = config(&port, &["get", "leap_seconds"]);
    assert!(ok && said.trim() == "leap_seconds = 19", "{said}");
    let (_, again, _) = config(&port, &["dump"]);
    assert_eq!(again, dump, "every setting kept");
    let _ = bridge.kill();
    let _ = bridge.wait();
    std::thread::sleep(StdDuration::from_millis(10));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The settings table's row of `s`, as the book writes it (docs/src/firmware/
/// configuration.md, "Settings at run time").
fn settings_row(s: &bridge_engine::settings::Setting) -> String {
    use bridge_engine::settings::table::{Access, SIDE_NAMES};
    let param = s.param.map_or("—".to_owned(), |p| format!("`{p}`"));
    let ty = s
        .param_type()
        .map_or("console, file".to_owned(), |t| t.name().to_owned());
    let range = match (s.access, s.param_range()) {
        (_, None) => "—".to_owned(),
        (Access::Bool { .. }, _) => "0, 1 (`false`, `true`)".to_owned(),
        (Access::Choice { names, .. }, Some((a, b))) => format!("{a}..={b}: {}", names.join(", ")),
        (Access::Side, Some((a, b))) => format!("{a}..={b}: {}", SIDE_NAMES.join(", ")),
        (Access::MsOrOff { limit, .. }, _) => {
            format!("{}..={}, 0 for `\"off\"`", limit.min, limit.max)
        }
        (Access::K40tAllow, Some((a, b))) => format!("{a}..={b}: a bit per request"),
        (_, Some((a, b))) => format!("{a}..={b}"),
    };
    let default = if s.secret() {
        "none".to_owned()
    } else if matches!(s.access, Access::Side) {
        "`auto`".to_owned()
    } else {
        let mut d = String::new();
        s.write(&Config::DEFAULT, &mut d).unwrap();
        format!("`{d}`")
    };
    let secret = if s.secret() { "write-only" } else { "" };
    format!(
        "| `{}` | {param} | {ty} | {range} | {default} | {} | {secret} |",
        s.key,
        s.applies.name()
    )
}

/// The book's settings table is the engine's one table of keys, row for row.
#[test]
fn the_books_settings_table_is_the_engines() {
    let start = README
        .find("### The settings\n")
        .expect("the book's settings section");
    let section = &README[start..];
    let book: Vec<&str> = section
        .lines()
        .skip_while(|l| !l.starts_with("| `"))
        .take_while(|l| l.starts_with("| `"))
        .collect();
    let code: Vec<String> = bridge_engine::settings::SETTINGS
        .iter()
        .map(settings_row)
        .collect();
    assert_eq!(
        book.join("\n"),
        code.join("\n"),
        "docs/src/firmware/configuration.md's settings table differs from \
         bridge_engine::SETTINGS; the table as the code has it:\n{}",
        code.join("\n")
    );
}
