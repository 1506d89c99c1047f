//! MAVLink 2: decoding arbitrary bytes never fails on content and re-encodes exactly what
//! a MAVLink 2 sender sends (payload truncated, no unknown extension); the deframer finds
//! exactly the frames an independent reference scan finds (written from the MAVLink
//! serialization spec, with the test oracle's CRC and the spec's CRC_EXTRA table),
//! skipping MAVLink 1 frames whole.

use std::hint::black_box;

use codec_cases::oracle::k40t_crc;
use protocol_core::mavlink::dialect::{self, MavMessage, Message as _};
use protocol_core::mavlink::{
    CATALOG, DEFRAMER_LEN, Frame, HEADER_LEN, Header, MAX_FRAME_LEN, MavlinkFraming, Message,
    Packet, UnknownIds, message_info,
};

use crate::deframe::{self, Spec};
use crate::input::{Input, Plan};

/// CRC_EXTRA of every message of the set, as the MAVLink C library's message tables list
/// them (`MAVLINK_MESSAGE_CRCS`), written down independently of the generator.
pub const SPEC_CRC_EXTRA: [(u32, u8); 42] = [
    (0, 50),
    (2, 137),
    (20, 214),
    (21, 159),
    (22, 220),
    (23, 168),
    (24, 24),
    (30, 39),
    (33, 104),
    (66, 148),
    (75, 158),
    (76, 152),
    (77, 143),
    (110, 84),
    (111, 34),
    (112, 174),
    (132, 85),
    (148, 178),
    (244, 95),
    (253, 83),
    (256, 71),
    (259, 92),
    (260, 146),
    (261, 179),
    (262, 12),
    (263, 133),
    (269, 109),
    (270, 59),
    (271, 22),
    (275, 126),
    (277, 62),
    (280, 70),
    (281, 48),
    (283, 74),
    (284, 99),
    (285, 137),
    (286, 210),
    (320, 243),
    (321, 88),
    (322, 243),
    (323, 78),
    (324, 132),
];

fn spec_crc_extra(id: u32) -> Option<u8> {
    SPEC_CRC_EXTRA
        .iter()
        .find(|(i, _)| *i == id)
        .map(|&(_, e)| e)
}

/// The spec's checksum: X.25 (CRC-16/MCRF4XX) over LEN..payload, then CRC_EXTRA.
#[must_use]
pub fn oracle_checksum(covered: &[u8], crc_extra: u8) -> u16 {
    let mut data = covered.to_vec();
    data.push(crc_extra);
    k40t_crc(&data)
}

/// The reference: the length of the valid MAVLink 2 frame at the start of `b`.
#[must_use]
pub fn valid_v2(b: &[u8]) -> Option<usize> {
    if b.len() < 12 || b[0] != 0xFD || b[2] & !1 != 0 {
        return None;
    }
    let len = usize::from(b[1]);
    let n = 12 + len + if b[2] & 1 == 1 { 13 } else { 0 };
    if b.len() < n {
        return None;
    }
    let id = u32::from_le_bytes([b[7], b[8], b[9], 0]);
    let extra = spec_crc_extra(id)?;
    let crc = u16::from_le_bytes([b[10 + len], b[11 + len]]);
    (oracle_checksum(&b[1..10 + len], extra) == crc).then_some(n)
}

/// The reference: the length of the valid MAVLink 1 frame at the start of `b`.
#[must_use]
pub fn valid_v1(b: &[u8]) -> Option<usize> {
    if b.len() < 8 || b[0] != 0xFE {
        return None;
    }
    let len = usize::from(b[1]);
    let n = 8 + len;
    if b.len() < n {
        return None;
    }
    let extra = spec_crc_extra(u32::from(b[5]))?;
    let crc = u16::from_le_bytes([b[6 + len], b[7 + len]]);
    (oracle_checksum(&b[1..6 + len], extra) == crc).then_some(n)
}

/// The reference: the length of the well-framed MAVLink 2 frame of an id outside the set
/// at the start of `b` (the rest of the stream): flags 0 or 1, no compatibility flag, an
/// id below 65 536, followed at once by 0xFD or 0xFE or by the end of the stream, and no
/// frame that checks starting inside it after its first byte: a MAVLink 2 frame whether
/// it ends inside it or after it (the deframer's 561 bytes hold both), a MAVLink 1 frame
/// (skipped anyway) ending inside it.
#[must_use]
pub fn unknown_frame(b: &[u8]) -> Option<usize> {
    if b.len() < 12 || b[0] != 0xFD || b[2] & !1 != 0 || b[3] != 0 || b[9] != 0 {
        return None;
    }
    let n = 12 + usize::from(b[1]) + if b[2] & 1 == 1 { 13 } else { 0 };
    let id = u32::from_le_bytes([b[7], b[8], b[9], 0]);
    if b.len() < n || spec_crc_extra(id).is_some() {
        return None;
    }
    let followed = b.get(n).is_none_or(|x| *x == 0xFD || *x == 0xFE);
    let hides = (1..n).any(|i| valid_v2(&b[i..]).or_else(|| valid_v1(&b[i..n])).is_some());
    (followed && !hides).then_some(n)
}

/// Target `mavlink_decode`.
pub fn decode(data: &[u8]) {
    if let Ok(p) = Packet::decode(data) {
        round_trip(data, &p);
    }
    if let Ok(frame) = Frame::new_checked(data) {
        // The same bytes with the checksum of the set's CRC_EXTRA filled in.
        let mut fixed = data[..frame.total_len()].to_vec();
        let id = frame.message_id();
        if let Some(extra) = spec_crc_extra(id) {
            Frame::new_unchecked(&mut fixed[..]).fill_checksum(extra);
            assert_eq!(Frame::new_unchecked(&fixed[..]).verify(), Ok(()));
            let parsed = Packet::parse(&frame).expect("parse of a checked frame");
            let decoded = Packet::decode(&fixed).expect("a frame with a valid checksum decodes");
            assert_eq!(
                encoded_bytes(&parsed),
                encoded_bytes(&decoded),
                "parse and decode disagree"
            );
            round_trip(&fixed, &decoded);
        } else {
            // Outside the set: raw, whatever the checksum.
            let p = Packet::decode(data).expect("an unknown id decodes unverified");
            assert!(matches!(p.message, Message::Raw(_)));
        }
    }
    let f = Frame::new_unchecked(data);
    let _ = black_box((f.check_len(), f.payload_len(), f.total_len(), f.sequence()));
    let _ = black_box((f.message_id(), f.payload(), f.checksum(), f.signature()));
    let _ = black_box((f.verify(), f.compute_checksum(0)));
}

/// Re-encodes `p`, decoded from `data`.
fn round_trip(data: &[u8], p: &Packet<'_>) {
    let frame = Frame::new_checked(data).expect("decoded bytes hold a frame");
    let id = frame.message_id();
    let Some(info) = message_info(id) else {
        assert!(matches!(p.message, Message::Raw(_)));
        let mut out = [0u8; MAX_FRAME_LEN];
        assert_eq!(p.emit(&mut out), Err(protocol_core::Error::UnknownId));
        return;
    };
    let n = p.buffer_len();
    let mut out = vec![0u8; n];
    assert_eq!(p.emit(&mut out), Ok(n), "a decoded packet re-encodes");
    let payload = frame.payload();
    // As a MAVLink 2 sender sends it: trailing zeros dropped, one byte kept (an empty
    // payload comes back as one zero byte).
    let truncated = payload.len() == 1 || payload.last().is_some_and(|&b| b != 0);
    let exact = match p.message {
        // Typed: what a MAVLink 2 sender sends comes back byte for byte.
        Message::Known(_) => truncated && payload.len() <= usize::from(info.max_len),
        Message::Raw(_) => true,
    };
    if exact {
        assert_eq!(&out[..], &data[..frame.total_len()], "re-encoding differs");
    }
    let again = Packet::decode(&out).expect("a re-encoded packet decodes");
    assert_eq!(again.header, p.header);
    assert_eq!(again.signature, p.signature);
    assert_eq!(encoded_bytes(&again), out, "decode(encode(p)) differs");
    crate::exact_buffers(n, |buf| p.emit(buf));
}

/// A packet's encoding (to compare packets whose float fields may be NaN).
fn encoded_bytes(p: &Packet<'_>) -> Vec<u8> {
    let mut out = vec![0u8; p.buffer_len()];
    let n = p.emit(&mut out).expect("encode");
    out.truncate(n);
    out
}

/// The checked parse every delivered frame must pass.
pub fn checked(f: &[u8]) {
    let frame = Frame::new_checked(f).expect("a delivered frame passes new_checked");
    assert_eq!(frame.total_len(), f.len());
    frame
        .verify()
        .expect("a delivered frame has a valid checksum");
    match Packet::decode(f) {
        Ok(p) => round_trip(f, &p),
        Err(e) => panic!("{e:?} for a delivered frame"),
    }
}

/// The deframer of the engine's MAVLink links.
const DEFRAMER: usize = DEFRAMER_LEN;

/// Target `mavlink_deframe`: the default framing (frames of unknown ids skipped when well
/// framed) against the reference; selector bit 1 also rejecting unknown ids; bit 0
/// delivering them (no reference: it cannot tell them from noise).
pub fn deframe(data: &[u8]) {
    let mut input = Input::new(data);
    let (selector, plan) = Plan::read(&mut input);
    let stream = input.rest();
    let valid = |b: &[u8]| valid_v2(b);
    let skipped = |b: &[u8]| valid_v1(b).or_else(|| unknown_frame(b));
    let spec = Spec {
        valid: &valid,
        skipped: &skipped,
        checked: &checked,
        compare_scanner: true,
    };
    let framing = MavlinkFraming::new();
    deframe::check::<_, DEFRAMER>(&framing, stream, &plan, &spec);
    if selector & 2 == 2 {
        let skipped = |b: &[u8]| valid_v1(b);
        let spec = Spec {
            skipped: &skipped,
            ..spec
        };
        let framing = MavlinkFraming {
            unknown_ids: UnknownIds::Reject,
        };
        deframe::check::<_, DEFRAMER>(&framing, stream, &plan, &spec);
    }
    if selector & 1 == 1 {
        // Delivering unknown ids: no panic, every frame of the set still valid.
        let framing = MavlinkFraming {
            unknown_ids: UnknownIds::Deliver,
        };
        let (events, _) = deframe::run_push::<_, DEFRAMER>(framing, stream, Some(&plan));
        for f in events.iter().filter_map(deframe::Ev::frame) {
            let frame = Frame::new_checked(f).expect("a delivered frame passes new_checked");
            if message_info(frame.message_id()).is_some() {
                checked(f);
            }
        }
    }
}

/// A run of payload bytes holding enumerations: start, end, and every valid value of
/// each field of the run (as (offset, width, values)).
pub type EnumRun = (usize, usize, Vec<(usize, usize, Vec<Vec<u8>>)>);

/// Byte runs of message `id`'s full payload that hold enumerations (a value outside the
/// enumeration makes decoding fail), with every valid value of each field: found by
/// trying values on the default message's payload, so nothing here is written per
/// message. Computed once per id.
#[must_use]
pub fn enum_runs(id: u32) -> &'static [EnumRun] {
    static RUNS: std::sync::OnceLock<std::collections::HashMap<u32, Vec<EnumRun>>> =
        std::sync::OnceLock::new();
    RUNS.get_or_init(|| CATALOG.iter().map(|&id| (id, find_enum_runs(id))).collect())
        .get(&id)
        .map_or(&[], Vec::as_slice)
}

fn find_enum_runs(id: u32) -> Vec<EnumRun> {
    let info = message_info(id).expect("an id of the set");
    let len = usize::from(info.max_len);
    let default = MavMessage::default_message_from_id(id).expect("a default message");
    let mut base = [0u8; 255];
    dialect::encode(&default, &mut base);
    let ok = |p: &[u8]| dialect::decode(id, p).is_ok();
    let sensitive: Vec<bool> = (0..len)
        .map(|i| {
            let mut p = base;
            p[i] = 0xFF;
            !ok(&p[..len]) || {
                p[i] = 0x7F;
                !ok(&p[..len])
            }
        })
        .collect();
    // Every valid value of the field at `start..end`, the rest of the payload default.
    let values = |start: usize, end: usize| -> Vec<Vec<u8>> {
        let width = end - start;
        (0..(1u32 << (8 * width)))
            .filter_map(|v| {
                let mut p = base;
                p[start..end].copy_from_slice(&v.to_le_bytes()[..width]);
                ok(&p[..len]).then(|| v.to_le_bytes()[..width].to_vec())
            })
            .collect()
    };
    let mut runs = Vec::new();
    let mut i = 0;
    while i < len {
        if !sensitive[i] {
            i += 1;
            continue;
        }
        let start = i;
        while i < len && sensitive[i] {
            i += 1;
        }
        // Adjacent enumeration fields (COMMAND_ACK: command u16, result u8): split the
        // run into fields of one or two bytes whose valid values combine freely.
        let fields = segmentations(start, i)
            .into_iter()
            .map(|seg| {
                seg.iter()
                    .map(|&(s, e)| (s, e - s, values(s, e)))
                    .collect::<Vec<_>>()
            })
            .find(|fields| {
                fields.iter().all(|(_, _, v)| !v.is_empty())
                    && (0..64).all(|k| {
                        let mut p = base;
                        for (j, (s, w, v)) in fields.iter().enumerate() {
                            p[*s..*s + *w].copy_from_slice(&v[(k * 7 + j * 13) % v.len()]);
                        }
                        ok(&p[..len])
                    })
            })
            .unwrap_or_else(|| panic!("message {id}: no field split of bytes {start}..{i}"));
        runs.push((start, i, fields));
    }
    runs
}

/// Ways to cut `start..end` into pieces of one or two bytes, two-byte pieces first.
fn segmentations(start: usize, end: usize) -> Vec<Vec<(usize, usize)>> {
    if start == end {
        return vec![vec![]];
    }
    let mut out = Vec::new();
    for w in [2, 1] {
        if start + w <= end {
            for mut rest in segmentations(start + w, end) {
                rest.insert(0, (start, start + w));
                out.push(rest);
            }
        }
    }
    out
}

/// `bytes` (any length) made into a full payload of message `id` that decodes as a
/// typed message: enumeration runs take the valid value `bytes` selects.
#[must_use]
pub fn typed_payload(id: u32, bytes: &[u8], runs: &[EnumRun]) -> Vec<u8> {
    let len = usize::from(message_info(id).expect("an id of the set").max_len);
    let mut p: Vec<u8> = bytes.iter().copied().cycle().take(len).collect();
    p.resize(len, 0);
    for (_, _, fields) in runs {
        for (start, width, values) in fields {
            let pick = usize::from(p[*start]) * 31 + usize::from(p[*start + *width - 1]);
            p[*start..*start + *width].copy_from_slice(&values[pick % values.len()]);
        }
    }
    p
}

/// Frames the encoder builds for every message of the set from `fill`, with a header
/// derived from the fill; and a signed copy of each.
#[must_use]
pub fn catalogue_frames(fill: &[u8]) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    for (k, &id) in CATALOG.iter().enumerate() {
        let runs = enum_runs(id);
        let payload = typed_payload(id, &fill[k % fill.len()..], runs);
        let message = dialect::decode(id, &payload).expect("a typed payload decodes");
        assert_eq!(message.message_id(), id);
        let header = Header {
            sequence: fill[k % fill.len()],
            system_id: 1,
            component_id: [1, 154, 100][k % 3],
        };
        let mut buf = [0u8; MAX_FRAME_LEN];
        let n = protocol_core::mavlink::encode(&message, &header, &mut buf).expect("encode");
        out.push(buf[..n].to_vec());
        let mut p = Packet::new(header, message);
        p.signature = protocol_core::mavlink::Signature::from_bytes(&[
            1, 0x10, 0x20, 0x30, 0x40, 0x50, 0x06, 0xA1, 0xA2, 0xA3, 0xA4, 0xA5, 0xA6,
        ]);
        let n = p.emit(&mut buf).expect("emit signed");
        out.push(buf[..n].to_vec());
    }
    out
}

/// A MAVLink 1 frame (for the streams: recognised and skipped).
#[must_use]
pub fn v1_frame(seq: u8, id: u8, payload: &[u8]) -> Vec<u8> {
    let mut f = vec![0xFE, payload.len() as u8, seq, 1, 1, id];
    f.extend_from_slice(payload);
    let extra = spec_crc_extra(u32::from(id)).expect("a v1 id of the set");
    let crc = oracle_checksum(&f[1..], extra);
    f.extend_from_slice(&crc.to_le_bytes());
    f
}

/// Every seed frame: the catalogue from three fills, MAVLink 1 heartbeats (one with 0xFD
/// in its payload), and a frame of an id outside the set.
#[must_use]
pub fn frames() -> Vec<Vec<u8>> {
    let fills: [Vec<u8>; 3] = [
        vec![0; 256],
        (0..=255u8).collect(),
        (0..=255u8).map(|i| i.wrapping_mul(151) ^ 0x5A).collect(),
    ];
    let mut out: Vec<Vec<u8>> = fills.iter().flat_map(|f| catalogue_frames(f)).collect();
    out.push(v1_frame(3, 0, &[0, 0, 0, 0, 26, 8, 0, 4, 3]));
    out.push(v1_frame(4, 0, &[0xFD, 0x09, 0, 0, 26, 0xFD, 0, 4, 3]));
    let mut unknown = vec![0xFD, 2, 0, 0, 9, 1, 1, 0x2C, 0x01, 0x00, 0xAA, 0xBB];
    let crc = oracle_checksum(&unknown[1..], 0x42);
    unknown.extend_from_slice(&crc.to_le_bytes());
    out.push(unknown);
    debug_assert!(out.iter().all(|f| f.len() >= HEADER_LEN));
    out
}
