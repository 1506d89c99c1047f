//! Prints the benchmark table from gungraun's JSON summaries (`cargo bench --bench codec --
//! --output-format=json`, one line per benchmark), one file per opt-level:
//! `bench-table z.json 3.json`. Used by `scripts/bench`.

use std::collections::HashMap;

use benchmarks::Stream;

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

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [z, o3] = [&args[0], &args[1]].map(|p| counts(p));
    let get = |m: &HashMap<String, u64>, k: &str| *m.get(k).unwrap_or_else(|| panic!("no {k}"));

    let streams: [(&str, &str, Stream); 5] = [
        ("k40t", "K40T", benchmarks::k40t_stream()),
        ("siyi", "SIYI", benchmarks::siyi_stream()),
        ("viewlink", "Viewlink", benchmarks::viewlink_stream()),
        ("gcu_host", "GCU host", benchmarks::gcu_host_stream()),
        ("gcu_reply", "GCU reply", benchmarks::gcu_reply_stream()),
    ];
    println!(
        "Instructions (Callgrind, x86-64), whole stream and per frame; opt-level z is the firmware's release profile."
    );
    println!();
    println!(
        "| {:<34} | {:>10} | {:>7} | {:>10} | {:>7} |",
        "stream / stage", "z", "/frame", "3", "/frame"
    );
    println!(
        "| {:-<34} | {:->10}:| {:->7}:| {:->10}:| {:->7}:|",
        "", "", "", "", ""
    );
    let row = |label: &str, key: &str, frames: usize| {
        let (a, b) = (get(&z, key), get(&o3, key));
        println!(
            "| {:<34} | {:>10} | {:>7} | {:>10} | {:>7} |",
            label,
            a,
            a / frames as u64,
            b,
            b / frames as u64
        );
    };
    let mut k40t_frames = 0;
    for (key, name, s) in &streams {
        let frames = s.frames.len();
        if *key == "k40t" {
            k40t_frames = frames;
        }
        println!(
            "| **{name}** ({frames} frames, {} bytes) | | | | |",
            s.bytes.len()
        );
        row("checksum alone (floor)", &format!("{key}_checksum"), frames);
        row("deframe", &format!("{key}_deframe"), frames);
        row("decode", &format!("{key}_decode"), frames);
        row("decode + encode", &format!("{key}_decode_encode"), frames);
        if *key == "k40t" {
            row("deframe, then decode", "k40t_deframe_decode", frames);
        }
    }
    println!(
        "| **rust-mavlink** (MAVLink v2, same frame count and payload lengths as K40T) | | | | |"
    );
    row("raw-frame reader", "mavlink_raw", k40t_frames);
    row("parse (frame + message)", "mavlink_parse", k40t_frames);
    let (mav, _) = benchmarks::mavlink_stream();
    let mav_frames = mav.frames.len();
    println!(
        "| **MAVLink 2**, protocol_core::mavlink (the bridge's {} messages, {mav_frames} frames, {} bytes) | | | | |",
        protocol_core::mavlink::CATALOG.len(),
        mav.bytes.len()
    );
    row("checksum alone (floor)", "mavlink_checksum", mav_frames);
    row("deframe", "mavlink_deframe", mav_frames);
    row("decode", "mavlink_decode", mav_frames);
    row("decode + encode", "mavlink_decode_encode", mav_frames);
    row(
        "encode (typed message to frame)",
        "mavlink_encode",
        mav_frames,
    );
    row(
        "encode, signed (SHA-256 included)",
        "mavlink_encode_signed",
        mav_frames,
    );
    println!("| **rust-mavlink 0.21** own reader/encoder, same stream and types | | | | |");
    row("reader + parse", "rmav_set_parse", mav_frames);
    row("serialize_message", "rmav_set_encode", mav_frames);
    println!("| **mavio 0.5 + mavspec 0.6** own receiver/builder, same stream | | | | |");
    row("receiver + decode", "mavio_set_parse", mav_frames);
    row("builder + serialize", "mavio_set_encode", mav_frames);
    let frames = benchmarks::BRIDGE_RUN_FRAMES;
    println!(
        "| **bridge engine** (SIYI and MAVLink FC sides, {frames} frames, outputs taken) | | | | |"
    );
    row(
        "SIYI 0x07 rate in, K40T control out",
        "bridge_siyi_rate",
        frames,
    );
    row(
        "MAVLink SET_ATTITUDE in, K40T angle out",
        "bridge_mavlink_set_attitude",
        frames,
    );
    row(
        "the same, signing required (in checked, out signed)",
        "bridge_mavlink_set_attitude_signed",
        frames,
    );
    row(
        "pod attitude report absorbed",
        "bridge_pod_attitude",
        frames,
    );

    println!();
    println!("| {:<48} | {:>5} | {:>5} |", "ratio", "z", "3");
    println!("| {:-<48} | {:->5}:| {:->5}:|", "", "", "");
    let ratio = |label: &str, num: &str, den: &str| {
        let r = |m: &HashMap<String, u64>| get(m, num) as f64 / get(m, den) as f64;
        println!("| {:<48} | {:>5.2} | {:>5.2} |", label, r(&z), r(&o3));
    };
    for (key, name, _) in &streams {
        ratio(
            &format!("{name}: deframe / checksum floor"),
            &format!("{key}_deframe"),
            &format!("{key}_checksum"),
        );
    }
    ratio(
        "K40T deframe / rust-mavlink raw reader",
        "k40t_deframe",
        "mavlink_raw",
    );
    ratio(
        "K40T decode / rust-mavlink parse",
        "k40t_decode",
        "mavlink_parse",
    );
    ratio(
        "K40T deframe + decode / rust-mavlink parse",
        "k40t_deframe_decode",
        "mavlink_parse",
    );
    ratio(
        "MAVLink: deframe / checksum floor",
        "mavlink_deframe",
        "mavlink_checksum",
    );
    ratio(
        "MAVLink encode: signed / unsigned",
        "mavlink_encode_signed",
        "mavlink_encode",
    );
    ratio(
        "MAVLink side per frame: signed / unsigned",
        "bridge_mavlink_set_attitude_signed",
        "bridge_mavlink_set_attitude",
    );
    ratio(
        "MAVLink: rust-mavlink reader + parse / mavio",
        "rmav_set_parse",
        "mavio_set_parse",
    );
    ratio(
        "MAVLink: rust-mavlink serialize / mavio",
        "rmav_set_encode",
        "mavio_set_encode",
    );
}
