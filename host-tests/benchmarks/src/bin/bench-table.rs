//! Prints the book's instruction-count tables (docs/src/verification/benchmarks.md) from
//! gungraun's JSON summaries (`cargo bench --bench codec -- --output-format=json`, one
//! line per benchmark), one file per opt-level: `bench-table z.json 3.json
//! baseline.tsv`. Each row per frame (or per request) beside its figure of the baseline
//! (2026-11-27), its changes at z and at 3 marked `**` beyond ±10 %; then the ratios, and
//! the signing rows against their floor (SHA-256 compressions). Used by `scripts/bench`.

use std::collections::HashMap;

use benchmarks::bridge::BridgeRun;
use benchmarks::signing::{self, COMPRESS_BLOCKS};
use benchmarks::{Stream, bridge, camera};

/// Instruction counts by benchmark function name.
fn counts(path: &str) -> HashMap<String, u64> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    text.lines()
        .filter(|l| l.starts_with('{'))
        .map(|line| {
            let v: serde_json::Value = serde_json::from_str(line).expect("gungraun JSON");
            let name = v["function_name"]
                .as_str()
                .expect("function_name")
                .to_string();
            let ir = v["profiles"][0]["data"]["total"]["metrics"]["Ir"]["values"]["new"]
                .as_u64()
                .expect("Ir");
            (name, ir)
        })
        .collect()
}

/// The baseline's instructions per frame at z and at 3, by benchmark.
fn baseline(path: &str) -> HashMap<String, (f64, f64)> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|line| {
            let f: Vec<&str> = line.split('\t').collect();
            let num = |i: usize| {
                f[i].parse::<f64>()
                    .unwrap_or_else(|e| panic!("{line}: {e}"))
            };
            (f[0].to_string(), (num(2) / num(1), num(3) / num(1)))
        })
        .collect()
}

/// The measured counts, at z and at 3, and the baseline.
struct Figures {
    z: HashMap<String, u64>,
    o3: HashMap<String, u64>,
    before: HashMap<String, (f64, f64)>,
}

impl Figures {
    fn get(m: &HashMap<String, u64>, key: &str) -> u64 {
        *m.get(key)
            .unwrap_or_else(|| panic!("no benchmark {key} in the results"))
    }

    /// Instructions per unit of `key` at (z, 3).
    fn per(&self, key: &str, units: usize) -> (f64, f64) {
        let u = units as f64;
        (
            Self::get(&self.z, key) as f64 / u,
            Self::get(&self.o3, key) as f64 / u,
        )
    }

    /// One row: totals, per unit, the baseline's per unit at z and the changes at z and 3.
    fn row(&self, label: &str, key: &str, units: usize) {
        let (a, b) = (Self::get(&self.z, key), Self::get(&self.o3, key));
        let (pz, p3) = (a as f64 / units as f64, b as f64 / units as f64);
        let change = |now: f64, was: f64| {
            let c = (now / was - 1.0) * 100.0;
            let mark = if c.abs() > 10.0 { "**" } else { "" };
            format!("{mark}{c:+.1} %{mark}")
        };
        let (was, cz, c3) = match self.before.get(key) {
            Some(&(wz, w3)) => (format!("{wz:.0}"), change(pz, wz), change(p3, w3)),
            None => ("—".to_string(), "new".to_string(), "new".to_string()),
        };
        println!(
            "| {label:<44} | {a:>9} | {pz:>6.0} | {b:>9} | {p3:>6.0} | {was:>7} | {cz:>10} | {c3:>10} |"
        );
    }

    /// The ratio of two benchmarks at z and 3.
    fn ratio(&self, label: &str, num: &str, den: &str) {
        let r = |m: &HashMap<String, u64>| Self::get(m, num) as f64 / Self::get(m, den) as f64;
        println!(
            "| {:<48} | {:>5.2} | {:>5.2} |",
            label,
            r(&self.z),
            r(&self.o3)
        );
    }
}

fn section(title: &str) {
    println!("| {title} | | | | | | | |");
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [z, o3, before] = [&args[0], &args[1], &args[2]];
    let f = Figures {
        z: counts(z),
        o3: counts(o3),
        before: baseline(before),
    };

    let streams: [(&str, &str, Stream); 5] = [
        ("k40t", "K40T", benchmarks::k40t_stream()),
        ("siyi", "SIYI", benchmarks::siyi_stream()),
        ("viewlink", "Viewlink", benchmarks::viewlink_stream()),
        ("gcu_host", "GCU host", benchmarks::gcu_host_stream()),
        ("gcu_reply", "GCU reply", benchmarks::gcu_reply_stream()),
    ];
    println!(
        "Instructions (Callgrind, x86-64), whole run and per frame (per request for the bridge \
         engine); opt-level z is the firmware's release profile. 2026-11-27 z: per frame then; \
         change: per frame since, at z and at 3, ** beyond ±10 %."
    );
    println!();
    println!(
        "| {:<44} | {:>9} | {:>6} | {:>9} | {:>6} | {:>7} | {:>10} | {:>10} |",
        "stream / stage", "z", "/frame", "3", "/frame", "2026-11-27 z", "change z", "change 3"
    );
    println!(
        "| {:-<44} | {:->9}:| {:->6}:| {:->9}:| {:->6}:| {:->7}:| {:->10}:| {:->10}:|",
        "", "", "", "", "", "", "", ""
    );
    let k40t_frames = streams[0].2.frames.len();
    for (key, name, s) in &streams {
        let frames = s.frames.len();
        section(&format!(
            "**{name}** ({frames} frames, {} bytes)",
            s.bytes.len()
        ));
        f.row("checksum alone (floor)", &format!("{key}_checksum"), frames);
        f.row("deframe", &format!("{key}_deframe"), frames);
        f.row("decode", &format!("{key}_decode"), frames);
        f.row("decode + encode", &format!("{key}_decode_encode"), frames);
        if *key == "k40t" {
            f.row("deframe, then decode", "k40t_deframe_decode", frames);
        }
    }
    section("**rust-mavlink** (MAVLink v2, same frame count and payload lengths as K40T)");
    f.row("raw-frame reader", "mavlink_raw", k40t_frames);
    f.row("parse (frame + message)", "mavlink_parse", k40t_frames);
    let (mav, messages) = benchmarks::mavlink_stream();
    let mav_frames = mav.frames.len();
    section(&format!(
        "**MAVLink 2**, protocol_core::mavlink (the bridge's {} messages, {mav_frames} frames, {} bytes)",
        protocol_core::mavlink::CATALOG.len(),
        mav.bytes.len()
    ));
    f.row("checksum alone (floor)", "mavlink_checksum", mav_frames);
    f.row("deframe", "mavlink_deframe", mav_frames);
    f.row("decode", "mavlink_decode", mav_frames);
    f.row("decode + encode", "mavlink_decode_encode", mav_frames);
    f.row(
        "encode (typed message to frame)",
        "mavlink_encode",
        mav_frames,
    );
    f.row(
        "encode, signed (SHA-256 included)",
        "mavlink_encode_signed",
        mav_frames,
    );
    section("**rust-mavlink 0.21** own reader/encoder, same stream and types");
    f.row("reader + parse", "rmav_set_parse", mav_frames);
    f.row("serialize_message", "rmav_set_encode", mav_frames);
    section("**mavio 0.5 + mavspec 0.6** own receiver/builder, same stream");
    f.row("receiver + decode", "mavio_set_parse", mav_frames);
    f.row("builder + serialize", "mavio_set_encode", mav_frames);

    let runs: [(&str, &str, BridgeRun); 10] = [
        (
            "SIYI 0x07 rate in, K40T control out",
            "bridge_siyi_rate",
            bridge::bridge_siyi_rates(),
        ),
        (
            "MAVLink SET_ATTITUDE in, K40T angle out",
            "bridge_mavlink_set_attitude",
            bridge::bridge_mavlink_set_attitudes(false),
        ),
        (
            "the same, signing required (each frame in checked)",
            "bridge_mavlink_set_attitude_signed",
            bridge::bridge_mavlink_set_attitudes(true),
        ),
        (
            "pod attitude report absorbed",
            "bridge_pod_attitude",
            bridge::bridge_pod_attitudes(),
        ),
        (
            "PARAM_EXT_REQUEST_READ in, PARAM_EXT_VALUE out",
            "camera_param_read",
            camera::settings_reads(),
        ),
        (
            "PARAM_EXT_SET in, K40T set + pod ACK, PARAM_EXT_ACK out",
            "camera_param_set",
            camera::settings_sets(),
        ),
        (
            "FTP ReadFile in, 239 bytes of the definition out",
            "camera_ftp_read",
            camera::definition_reads(false),
        ),
        (
            "the same, signing required",
            "camera_ftp_read_signed",
            camera::definition_reads(true),
        ),
        (
            "TRACK_RECTANGLE in, K40T box + pod ACK, ACK + status out",
            "camera_track_rectangle",
            camera::tracking_rectangles(),
        ),
        (
            "REQUEST_MESSAGE(269) in, ACK + VIDEO_STREAM_INFORMATION out",
            "camera_video_information",
            camera::video_information_requests(),
        ),
    ];
    section(&format!(
        "**bridge engine** (SIYI and MAVLink FC sides, {} requests; camera, {} requests; outputs taken)",
        bridge::BRIDGE_RUN_FRAMES,
        camera::CAMERA_REQUESTS
    ));
    for (label, key, run) in &runs {
        f.row(label, key, run.requests);
    }
    section("**SHA-256** (sha2 0.10, software), one 64-byte block a call");
    f.row("one compression", "sha256_compress", COMPRESS_BLOCKS);

    println!();
    println!("| {:<48} | {:>5} | {:>5} |", "ratio", "z", "3");
    println!("| {:-<48} | {:->5}:| {:->5}:|", "", "", "");
    for (key, name, _) in &streams {
        f.ratio(
            &format!("{name}: deframe / checksum floor"),
            &format!("{key}_deframe"),
            &format!("{key}_checksum"),
        );
    }
    f.ratio(
        "K40T deframe / rust-mavlink raw reader",
        "k40t_deframe",
        "mavlink_raw",
    );
    f.ratio(
        "K40T decode / rust-mavlink parse",
        "k40t_decode",
        "mavlink_parse",
    );
    f.ratio(
        "K40T deframe + decode / rust-mavlink parse",
        "k40t_deframe_decode",
        "mavlink_parse",
    );
    f.ratio(
        "MAVLink: deframe / checksum floor",
        "mavlink_deframe",
        "mavlink_checksum",
    );
    f.ratio(
        "MAVLink encode: signed / unsigned",
        "mavlink_encode_signed",
        "mavlink_encode",
    );
    f.ratio(
        "MAVLink side per frame: signed / unsigned",
        "bridge_mavlink_set_attitude_signed",
        "bridge_mavlink_set_attitude",
    );
    f.ratio(
        "MAVLink: rust-mavlink reader + parse / mavio",
        "rmav_set_parse",
        "mavio_set_parse",
    );
    f.ratio(
        "MAVLink: rust-mavlink serialize / mavio",
        "rmav_set_encode",
        "mavio_set_encode",
    );

    // Signing against its floor: what signing adds per frame, over the compressions its
    // frames need times one compression.
    let (compress_z, compress_3) = f.per("sha256_compress", COMPRESS_BLOCKS);
    let signing_rows = [
        (
            "encode a typed message (signed − unsigned)",
            "mavlink_encode_signed",
            "mavlink_encode",
            signing::encode_compressions(&messages),
            mav_frames,
        ),
        (
            "MAVLink SET_ATTITUDE in, K40T angle out",
            "bridge_mavlink_set_attitude_signed",
            "bridge_mavlink_set_attitude",
            signing::run_compressions(&runs[2].2),
            runs[2].2.requests,
        ),
        (
            "FTP ReadFile in, 239 bytes out",
            "camera_ftp_read_signed",
            "camera_ftp_read",
            signing::run_compressions(&runs[7].2),
            runs[7].2.requests,
        ),
    ];
    println!();
    println!(
        "Signing against its floor: one SHA-256 compression {compress_z:.0} instructions at z, \
         {compress_3:.0} at 3; the floor of a row is its compressions (each signed frame in \
         checked, each frame out signed) times that; ** above the goal of 1.2 × the floor."
    );
    println!();
    println!(
        "| {:<44} | {:>6} | {:>7} | {:>7} | {:>5} | {:>7} | {:>7} | {:>5} |",
        "signing row (per frame or request)",
        "blocks",
        "floor z",
        "added z",
        "× z",
        "floor 3",
        "added 3",
        "× 3"
    );
    println!(
        "| {:-<44} | {:->6}:| {:->7}:| {:->7}:| {:->5}:| {:->7}:| {:->7}:| {:->5}:|",
        "", "", "", "", "", "", "", ""
    );
    for (label, signed, unsigned, blocks, units) in signing_rows {
        let per_unit = blocks as f64 / units as f64;
        let (sz, s3) = f.per(signed, units);
        let (uz, u3) = f.per(unsigned, units);
        let (floor_z, floor_3) = (per_unit * compress_z, per_unit * compress_3);
        // The goal: at most 1.2 times the floor; a row above it is marked.
        let times = |r: f64| {
            let mark = if r > 1.2 { "**" } else { "" };
            format!("{mark}{r:.2}{mark}")
        };
        println!(
            "| {:<44} | {:>6.2} | {:>7.0} | {:>7.0} | {:>5} | {:>7.0} | {:>7.0} | {:>5} |",
            label,
            per_unit,
            floor_z,
            sz - uz,
            times((sz - uz) / floor_z),
            floor_3,
            s3 - u3,
            times((s3 - u3) / floor_3)
        );
    }
}
