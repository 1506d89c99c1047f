//! The Viewlink seed vectors against the fields the fixture documents for each (its
//! `decoded` objects, written independently of this codec), and the `gimbal` tool's
//! Viewlink adapter.

use gimbal::tool::{self, Item};
use protocol_core::viewlink::tcp::Envelope;
use protocol_core::viewlink::*;
use serde_json::Value;

fn vectors() -> Vec<Value> {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/seed_vectors.json"),
    )
    .expect("fixture");
    let all: Vec<Value> = serde_json::from_str(&text).expect("json");
    all.into_iter()
        .filter(|v| v["protocol"] == "Viewlink")
        .collect()
}

fn hex(s: &str) -> Vec<u8> {
    tool::parse_hex(s).expect("hex")
}

/// `"0x1A"` or a number.
fn num(v: &Value) -> i64 {
    match v {
        Value::String(s) => i64::from_str_radix(s.trim_start_matches("0x"), 16).expect("hex"),
        other => other.as_i64().expect("number"),
    }
}

/// The four A1 parameters as this codec types them (signed where the type says so).
fn a1_params(a1: &A1) -> [i64; 4] {
    match *a1 {
        A1::MotorOnOff(m) => [i64::from(m.switch.value()), 0, 0, 0],
        A1::ManualSpeed(m) => [m.yaw_cdeg_s.into(), m.pitch_cdeg_s.into(), 0, 0],
        A1::AbsoluteAngle(m) => [m.yaw_bam16.into(), m.pitch_bam16.into(), 0, 0],
        A1::Plain { params, .. } => {
            let w = |i: usize| i64::from(i16::from_be_bytes([params[i], params[i + 1]]));
            [w(0), w(2), w(4), w(6)]
        }
        other => panic!("unexpected A1 in a vector: {other:?}"),
    }
}

fn check_a1(a1: &A1, doc: &Value) {
    assert_eq!(i64::from(a1.command().value()), num(&doc["servo_cmd"]));
    let p = a1_params(a1);
    for (i, key) in ["param1", "param2", "param3", "param4"].iter().enumerate() {
        assert_eq!(p[i], num(&doc[key]), "A1 {key}");
    }
}

fn check_c1(c1: &C1, doc: &Value) {
    assert_eq!(i64::from(c1.to_u16().unwrap()), num(&doc["raw"]));
    assert_eq!(i64::from(c1.sensor.value()), num(&doc["sensor"]));
    assert_eq!(i64::from(c1.zoom_speed), num(&doc["zoom_speed"]));
    assert_eq!(i64::from(c1.operation.value()), num(&doc["operation_cmd"]));
    assert_eq!(i64::from(c1.lrf.value()), num(&doc["lrf"]));
}

fn check_e1(e1: &E1, doc: &Value) {
    assert_eq!(i64::from(e1.source.value()), num(&doc["tracking_source"]));
    assert_eq!(i64::from(e1.param1), num(&doc["param1"]));
    assert_eq!(i64::from(e1.command.value()), num(&doc["basic_cmd"]));
    assert_eq!(i64::from(e1.param2), num(&doc["param2"]));
}

fn check_a2(a2: &A2, doc: &Value) {
    assert_eq!(i64::from(a2.action.value()), num(&doc["servo_action"]));
    assert_eq!(i64::from(a2.request_status), num(&doc["infreq_feedback"]));
    assert_eq!(i64::from(a2.counter), num(&doc["infreq_counter"]));
    assert_eq!(i64::from(a2.adjustment_mdeg), num(&doc["adjustment"]));
}

fn check_c2(c2: &C2, doc: &Value) {
    assert_eq!(i64::from(c2.command().value()), num(&doc["cmd"]));
    let param = match *c2 {
        C2::SetEoZoom(z) => i64::from(z.zoom_x10),
        C2::Plain { params, .. } => i64::from(u16::from_be_bytes(params)),
        other => panic!("unexpected C2 in a vector: {other:?}"),
    };
    assert_eq!(param, num(&doc["param"]));
}

fn check_e2(e2: &E2, doc: &Value) {
    assert_eq!(i64::from(e2.command().value()), num(&doc["ext_cmd"]));
    let (p1, p2) = match *e2 {
        E2::TrackPoint(p) => (i64::from(p.x_px), i64::from(p.y_px)),
        E2::Plain { params, .. } => (
            i64::from(i16::from_be_bytes([params[0], params[1]])),
            i64::from(i16::from_be_bytes([params[2], params[3]])),
        ),
        other => panic!("unexpected E2 in a vector: {other:?}"),
    };
    assert_eq!((p1, p2), (num(&doc["param1"]), num(&doc["param2"])));
}

#[test]
fn serial_vectors_match_the_documented_fields() {
    let mut checked = 0;
    for v in vectors() {
        let name = v["name"].as_str().unwrap();
        let bytes = hex(v["hex"].as_str().unwrap());
        let d = &v["decoded"];
        if bytes[0] == 0xEB {
            continue;
        }
        let p = Packet::decode(&bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
        let f = Frame::new_checked(&bytes[..]).unwrap();
        assert_eq!(i64::from(f.body_len()), num(&d["length_n"]), "{name}");
        assert_eq!(i64::from(p.header.counter), num(&d["counter"]), "{name}");
        assert_eq!(i64::from(p.message.id()), num(&d["frame_id"]), "{name}");
        assert_eq!(i64::from(f.checksum()), num(&d["checksum"]), "{name}");
        assert_eq!(
            hex(d["header"].as_str().unwrap()),
            p.header.sync.bytes(),
            "{name}"
        );
        match p.message {
            Message::Control(c) => {
                check_a1(&c.a1, &d["A1"]);
                check_c1(&c.c1, &d["C1"]);
                check_e1(&c.e1, &d["E1"]);
            }
            Message::RareControl(c) => {
                check_a2(&c.a2, &d["A2"]);
                check_c2(&c.c2, &d["C2"]);
                check_e2(&c.e2, &d["E2"]);
            }
            Message::E2(e2) => check_e2(&e2, &d["E2"]),
            Message::Ack(a) => {
                assert_eq!(i64::from(a.acked_id), num(&d["acked_frame_id"]));
            }
            other => panic!("{name}: unexpected {other:?}"),
        }
        checked += 1;
    }
    assert_eq!(checked, 32);
}

#[test]
fn tcp_vector_matches_the_documented_fields() {
    let v = vectors()
        .into_iter()
        .find(|v| v["hex"].as_str().unwrap().starts_with("EB 90"))
        .unwrap();
    let bytes = hex(v["hex"].as_str().unwrap());
    let env = Envelope::decode(&bytes).unwrap();
    let d = &v["decoded"];
    assert_eq!(env.body, &hex(d["data_body"].as_str().unwrap())[..]);
    assert_eq!(env.body.len() as i64, num(&d["data_len"]));
}

#[test]
fn tool_decodes_every_vector_in_one_capture() {
    let mut capture = Vec::new();
    let vs = vectors();
    for v in &vs {
        capture.extend(hex(v["hex"].as_str().unwrap()));
    }
    let p = tool::protocol("viewlink").unwrap();
    let items = p.scan(&capture);
    let frames: Vec<_> = items
        .iter()
        .filter_map(|i| match i {
            Item::Frame { decoded: Ok(d), .. } => Some(d),
            _ => None,
        })
        .collect();
    assert_eq!(frames.len(), vs.len(), "{items:#?}");
    assert!(!items.iter().any(|i| !matches!(i, Item::Frame { .. })));
    assert_eq!(frames[0].name, "Control");
    assert_eq!(frames[0].fields["a1"]["ManualSpeed"]["yaw_cdeg_s"], -2000);
    let ack = frames.iter().find(|d| d.name == "Ack").unwrap();
    assert_eq!(ack.fields["header"], "AA 55 DC");
    assert_eq!(ack.fields["acked_id"], 0x1A);
    let tcp = frames.last().unwrap();
    assert_eq!(tcp.name, "TcpEnvelope");
    assert_eq!(tcp.fields["body"], "8101040727ff");
}

#[test]
fn tool_lists_the_37_frame_ids() {
    let lines = tool::protocol("viewlink").unwrap().messages();
    assert_eq!(lines.len(), 37);
    assert!(
        lines
            .iter()
            .any(|l| l == "0x40 Status payload->console T1+F1+B1+D1")
    );
    assert!(lines.iter().any(|l| l.starts_with("0xb1 M ahrs->payload")));
}

#[test]
fn tool_reports_printed_errata_as_bad_frames() {
    let p = tool::protocol("viewlink").unwrap();
    for v in vectors() {
        let (Some(doc), Some(h)) = (v["doc_hex"].as_str(), v["hex"].as_str()) else {
            continue;
        };
        if doc == h {
            continue;
        }
        let items = p.scan(&hex(doc));
        assert!(
            !items.iter().any(|i| matches!(i, Item::Frame { .. })),
            "{}",
            v["name"]
        );
    }
}

#[test]
fn tool_shows_newtype_frames_as_their_layout() {
    // 0x92 and 0x42 have types of their own (IpFeedback, StatusOsd) that serialise as
    // the layout they wrap, as the shared type did.
    let mut capture = Vec::new();
    for (id, data) in [
        (0x92u8, vec![0xC0, 0xA8, 0x90, 0x40]),
        (0x42, vec![0u8; 41]),
    ] {
        let mut f = vec![0x55, 0xAA, 0xDC, data.len() as u8 + 3, id];
        f.extend(&data);
        let cs = f[3..].iter().fold(0, |a, b| a ^ b);
        f.push(cs);
        capture.extend(f);
    }
    let items = tool::protocol("viewlink").unwrap().scan(&capture);
    let decoded: Vec<_> = items
        .iter()
        .filter_map(|i| match i {
            Item::Frame { decoded: Ok(d), .. } => Some(d),
            _ => None,
        })
        .collect();
    assert_eq!(decoded.len(), 2, "{items:#?}");
    assert_eq!(decoded[0].name, "IpFeedback");
    assert_eq!(
        decoded[0].fields["octets"],
        serde_json::json!([192, 168, 144, 64])
    );
    assert_eq!(decoded[1].name, "StatusOsd");
    assert_eq!(decoded[1].fields["b1"]["roll_raw12"], 0);
    assert_eq!(decoded[1].fields["f1"]["state"]["name"], "Stop");
}
