//! Frames of message ids outside the bridge's dialect, as an autopilot sends them: well
//! framed, their checksum uncheckable without the message's CRC_EXTRA. The deframer skips
//! them whole and counts them apart (`Stats::frames_unknown`, the engine's
//! `fc_unknown_frames`), neither as rejected candidates nor as garbage; a known id with a
//! bad checksum stays rejected, garbage stays garbage (docs/src/protocols/mavlink.md,
//! "Unknown ids"). The frames are built with the CRC_EXTRA of the official definitions
//! (the XML the dialect is generated from), checked here against the dialect's own.

use crate::px4_capture;

use std::collections::BTreeMap;

use bridge_engine::{Config, Engine, FcProtocol, Instant, MAX_FRAME_LEN as ENGINE_FRAME, Port};
use protocol_core::mavlink::{
    CATALOG, DEFRAMER_LEN, Frame, IFLAG_SIGNED, MAX_FRAME_LEN, MavlinkFraming, UnknownIds,
    checksum, message_info,
};
use protocol_core::wire::{Deframer, Event};
use quick_xml::Reader;
use quick_xml::events::Event as Xml;

use px4_capture::Capture;

/// One field of a message definition.
#[derive(Debug, Clone)]
struct Field {
    /// Its base type (`uint8_t` for `uint8_t_mavlink_version`, `char` for `char[16]`).
    base: String,
    name: String,
    /// Array length (0: not an array).
    array: u8,
    extension: bool,
}

impl Field {
    fn size(&self) -> usize {
        let one = match self.base.as_str() {
            "int8_t" | "uint8_t" | "char" => 1,
            "int16_t" | "uint16_t" => 2,
            "int32_t" | "uint32_t" | "float" => 4,
            "int64_t" | "uint64_t" | "double" => 8,
            t => panic!("type {t}"),
        };
        one * usize::from(self.array.max(1))
    }
}

/// The messages of the official definitions the dialect is generated from, by id.
fn definitions() -> BTreeMap<u32, (String, Vec<Field>)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../protocol-core/mavlink-dialect/xml");
    let mut out = BTreeMap::new();
    for file in ["minimal.xml", "standard.xml", "common.xml"] {
        let text = std::fs::read_to_string(dir.join(file)).expect("the dialect's XML");
        let mut reader = Reader::from_str(&text);
        let mut current: Option<(u32, String, Vec<Field>)> = None;
        let mut extension = false;
        loop {
            match reader.read_event().expect("XML") {
                Xml::Start(e) | Xml::Empty(e) => {
                    let attr = |k: &str| {
                        e.try_get_attribute(k).expect("attribute").map(|a| {
                            a.normalized_value(quick_xml::XmlVersion::Explicit1_0)
                                .expect("value")
                                .into_owned()
                        })
                    };
                    match e.name().as_ref() {
                        b"message" => {
                            let id = attr("id").expect("id").parse().expect("an id");
                            current = Some((id, attr("name").expect("name"), Vec::new()));
                            extension = false;
                        }
                        b"extensions" => extension = true,
                        b"field" => {
                            let t = attr("type").expect("type");
                            let (base, array) = match t.split_once('[') {
                                Some((b, n)) => {
                                    (b.to_string(), n.trim_end_matches(']').parse().expect("n"))
                                }
                                None => (t.replace("_mavlink_version", ""), 0),
                            };
                            if let Some((_, _, fields)) = current.as_mut() {
                                fields.push(Field {
                                    base,
                                    name: attr("name").expect("name"),
                                    array,
                                    extension,
                                });
                            }
                        }
                        _ => {}
                    }
                }
                Xml::End(e) if e.name().as_ref() == b"message" => {
                    if let Some((id, name, fields)) = current.take() {
                        out.insert(id, (name, fields));
                    }
                }
                Xml::Eof => break,
                _ => {}
            }
        }
    }
    out
}

/// CRC_EXTRA as the MAVLink generators compute it: the X.25 checksum of the message's
/// name and its base fields (ordered by type size, largest first, stably) with their
/// types and array lengths, folded to a byte.
fn crc_extra(name: &str, fields: &[Field]) -> u8 {
    let mut base: Vec<&Field> = fields.iter().filter(|f| !f.extension).collect();
    base.sort_by_key(|f| std::cmp::Reverse(f.size() / usize::from(f.array.max(1))));
    let mut text = format!("{name} ").into_bytes();
    for f in base {
        text.extend(format!("{} {} ", f.base, f.name).bytes());
        if f.array > 0 {
            text.push(f.array);
        }
    }
    // `checksum` appends its extra byte: compute over all but the last, then fold.
    let (last, rest) = text.split_last().expect("a name");
    let crc = checksum(rest, *last);
    (crc & 0xFF) as u8 ^ (crc >> 8) as u8
}

/// The dialect's CRC_EXTRA, as the XML gives it for every id of the dialect: the
/// computation the frames below are built with is the generator's.
#[test]
fn crc_extra_from_the_definitions_is_the_dialect_s() {
    let defs = definitions();
    for &id in CATALOG {
        let (name, fields) = &defs[&id];
        assert_eq!(
            crc_extra(name, fields),
            message_info(id).expect("an id of the dialect").crc_extra,
            "{name}"
        );
    }
}

/// A frame of message `name` from PX4 (system 6, component 1), its payload `fill`ed and
/// trailing zeros trimmed as MAVLink 2 senders do; MAVLink 1 when `v1`.
struct Builder {
    defs: BTreeMap<u32, (String, Vec<Field>)>,
    seq: u8,
}

impl Builder {
    fn id(&self, name: &str) -> u32 {
        *self
            .defs
            .iter()
            .find(|(_, (n, _))| n == name)
            .unwrap_or_else(|| panic!("{name}"))
            .0
    }

    fn frame(&mut self, name: &str, fill: u8, v1: bool, signed: bool) -> Vec<u8> {
        let id = self.id(name);
        let (_, fields) = &self.defs[&id];
        let extra = crc_extra(name, fields);
        let len = fields
            .iter()
            .filter(|f| !v1 || !f.extension)
            .map(Field::size)
            .sum();
        // Bytes of the payload that never start a frame (no 0xFD, 0xFE), a few zeros.
        let mut payload: Vec<u8> = (0..len)
            .map(|i| match (i * 37 + usize::from(fill)) % 251 {
                b if b % 9 == 0 => 0,
                b => b as u8,
            })
            .collect();
        if !v1 {
            while payload.len() > 1 && payload.last() == Some(&0) {
                payload.pop();
            }
        }
        self.seq = self.seq.wrapping_add(1);
        let mut f = if v1 {
            vec![0xFE, payload.len() as u8, self.seq, 6, 1, id as u8]
        } else {
            let [a, b, c, _] = id.to_le_bytes();
            let flags = if signed { IFLAG_SIGNED } else { 0 };
            vec![0xFD, payload.len() as u8, flags, 0, self.seq, 6, 1, a, b, c]
        };
        f.extend(&payload);
        let crc = checksum(&f[1..], extra);
        f.extend(crc.to_le_bytes());
        if signed {
            f.extend([1, 0x10, 0x20, 0x30, 0x40, 0x50, 0x01, 9, 8, 7, 6, 5, 4]);
        }
        f
    }

    /// [`Builder::frame`] whose bytes after its start hold no 0xFD or 0xFE (its checksum
    /// included), so that a deframer rescanning it finds no false start in it.
    fn clean(&mut self, name: &str, v1: bool, signed: bool) -> Vec<u8> {
        (0..=255)
            .map(|fill| self.frame(name, fill, v1, signed))
            .find(|f| !f[1..].iter().any(|b| *b == 0xFD || *b == 0xFE))
            .expect("a clean frame")
    }
}

/// PX4's streams in mode Normal that the dialect does not know, with their rates (Hz),
/// as PX4's `mavlink_main.cpp` configures them (the SITL capture's link counted 5,768 such
/// frames in 150 s: 38 a second, as these sum).
const PX4_NORMAL_UNKNOWN: [(&str, f64); 23] = [
    ("SYS_STATUS", 1.0),
    ("LINK_NODE_STATUS", 1.0),
    ("SCALED_PRESSURE", 1.0),
    ("ATTITUDE_QUATERNION", 10.0),
    ("LOCAL_POSITION_NED", 1.0),
    ("SERVO_OUTPUT_RAW", 1.0),
    ("GPS_GLOBAL_ORIGIN", 1.0),
    ("NAV_CONTROLLER_OUTPUT", 1.0),
    ("RC_CHANNELS", 5.0),
    ("VFR_HUD", 4.0),
    ("ATTITUDE_TARGET", 2.0),
    ("POSITION_TARGET_LOCAL_NED", 1.5),
    ("POSITION_TARGET_GLOBAL_INT", 1.0),
    ("ALTITUDE", 1.0),
    ("BATTERY_STATUS", 0.5),
    ("ESTIMATOR_STATUS", 0.5),
    ("WIND_COV", 0.5),
    ("HOME_POSITION", 0.5),
    ("EXTENDED_SYS_STATE", 1.0),
    ("CURRENT_MODE", 0.5),
    ("OPEN_DRONE_ID_LOCATION", 1.0),
    ("OPEN_DRONE_ID_SYSTEM", 1.0),
    ("OPEN_DRONE_ID_ARM_STATUS", 1.0),
];

/// Bytes of noise that never start a frame.
fn noise(n: usize, seed: u8) -> Vec<u8> {
    (0..n)
        .map(|i| match (i as u8).wrapping_mul(73).wrapping_add(seed) {
            0xFD | 0xFE => 0x55,
            b => b,
        })
        .collect()
}

/// PX4's link as the capture shows it (its frames at their instants) with PX4's other
/// streams of mode Normal, MAVLink 1 frames (a known id and an unknown one), one damaged
/// SYSTEM_TIME and three runs of noise, through the engine's MAVLink side: the ordinary
/// messages are counted apart, exactly; rejected is the damaged frame alone, garbage its
/// bytes and the noise alone. On the engine before this change the same link counted
/// every unknown frame rejected and its bytes garbage.
#[test]
fn px4_s_ordinary_messages_are_counted_apart_not_as_rejected_or_garbage() {
    let capture = Capture::load();
    let mut b = Builder {
        defs: definitions(),
        seq: 0,
    };
    for (name, _) in PX4_NORMAL_UNKNOWN {
        assert!(
            message_info(b.id(name)).is_none(),
            "{name} is in the dialect"
        );
    }
    let end = capture.rx.last().expect("frames").t_us;
    // (instant, bytes, what it is).
    let mut link: Vec<(u64, Vec<u8>, &str)> = capture
        .rx
        .iter()
        .map(|f| (f.t_us, f.raw.clone(), "known"))
        .collect();
    for (k, (name, hz)) in PX4_NORMAL_UNKNOWN.iter().enumerate() {
        let period = (1e6 / hz) as u64;
        let mut t = 3_000 + 1_731 * k as u64;
        while t < end {
            let signed = name == &"ESTIMATOR_STATUS";
            link.push((t, b.frame(name, (t % 200) as u8, false, signed), "unknown"));
            t += period;
        }
    }
    for t in (5_000_000..end).step_by(10_000_000) {
        link.push((t, b.frame("HEARTBEAT", 1, true, false), "v1"));
        link.push((t + 1_000, b.clean("VFR_HUD", true, false), "v1 unknown"));
    }
    // A SYSTEM_TIME with a bad checksum (one whose bytes hold no start byte after its own,
    // so that it is one rejected candidate and the rest garbage).
    let damaged = capture
        .rx
        .iter()
        .find(|f| f.msg == "SYSTEM_TIME" && !f.raw[1..].iter().any(|b| *b == 0xFD || *b == 0xFE))
        .expect("a SYSTEM_TIME");
    let mut bad = damaged.raw.clone();
    let n = bad.len();
    bad[n - 1] ^= 0x40;
    link.push((60_000_000, bad.clone(), "damaged"));
    for (i, t) in [20_000_000u64, 70_000_000, 120_000_000]
        .into_iter()
        .enumerate()
    {
        link.push((t, noise(7 + 5 * i, i as u8), "noise"));
    }
    link.sort_by_key(|(t, _, _)| *t);
    let count = |what: &str| link.iter().filter(|(_, _, w)| *w == what).count() as u32;
    let bytes = |what: &str| {
        link.iter()
            .filter(|(_, _, w)| *w == what)
            .map(|(_, b, _)| b.len() as u32)
            .sum::<u32>()
    };

    let mut e = Engine::new(Config::for_fc(FcProtocol::Mavlink));
    let mut out = [0u8; ENGINE_FRAME];
    let mut last = 0;
    for (t, frame, what) in &link {
        let at = Instant::from_micros(1_000_000 + t);
        // A burst gap: the line went idle before (before noise too, so that no frame of an
        // unknown id waits for its next byte and gets noise).
        if t - last > 2_000 || matches!(*what, "noise" | "damaged" | "v1 unknown") {
            e.idle(Instant::from_micros(1_000_000 + last + 1_000), Port::Fc);
        }
        e.receive(at, Port::Fc, frame);
        e.poll(at);
        while e.transmit(Port::Fc, &mut out).is_some() {}
        while e.next_event().is_some() {}
        last = *t;
    }
    e.idle(Instant::from_micros(1_000_000 + last + 1_000), Port::Fc);
    let c = e.counters();
    println!(
        "{} known, {} unknown, {} MAVLink 1 frames of a known id and {} of an unknown one, \
         one damaged, {} noise bytes: {c:?}",
        count("known"),
        count("unknown"),
        count("v1"),
        count("v1 unknown"),
        bytes("noise")
    );
    assert!(count("unknown") > 5_500, "{}", count("unknown"));
    assert_eq!(c.fc_frames, count("known"));
    assert_eq!(c.fc_unknown_frames, count("unknown") + count("v1"));
    // A MAVLink 1 frame of an unknown id has nothing to check: rejected, as noise would be.
    assert_eq!(c.fc_rejected, 1 + count("v1 unknown"));
    assert_eq!(
        c.fc_garbage_bytes,
        bytes("noise") + bytes("damaged") + bytes("v1 unknown")
    );
}

/// The deframer's rule, case by case: an unknown id's frame followed by a frame, by the
/// idle line, signed, and a MAVLink 1 frame of a known id (skipped, counted apart, their
/// bytes not garbage); an unknown id's frame followed by noise, hiding a frame that
/// checks, or in MAVLink 1 (rejected, the hidden frame delivered); a known id with a bad
/// checksum (rejected); the other two framings (rejected, delivered).
#[test]
fn the_deframer_skips_well_framed_unknown_ids_whole() {
    let mut b = Builder {
        defs: definitions(),
        seq: 0,
    };
    let good = b.clean("HEARTBEAT", false, false);
    let unknown = b.clean("VFR_HUD", false, false);
    let signed = b.clean("ESTIMATOR_STATUS", false, true);
    let v1 = b.clean("HEARTBEAT", true, false);
    let v1_unknown = b.clean("SYS_STATUS", true, false);
    let mut bad = b.clean("SYSTEM_TIME", false, false);
    let last = bad.len() - 1;
    bad[last] ^= 1;
    // (stream, framing, frames delivered, frames_unknown, rejected, garbage bytes).
    type Case = (Vec<u8>, UnknownIds, Vec<Vec<u8>>, u32, u32, usize);
    let ids = UnknownIds::Skip;
    // A false start: FD with a length whose end lands on the next frame's FD, hiding a
    // whole valid frame (an id outside the dialect: 0x0B0C).
    let hidden = {
        let mut f = vec![0xFD, good.len() as u8 + 2, 0, 0, 0, 1, 1, 0x0C, 0x0B, 0];
        f.extend(&good);
        f.extend([0x11, 0x22]);
        f.extend([0x33, 0x44]);
        f
    };
    // A frame cut short after six bytes, then a valid frame whose component id is 0xFD.
    // The cut frame's header reads on into that frame (its component id that frame's STX,
    // its message id that frame's LEN and flags: an id outside the dialect, its checksum
    // uncheckable), and its length (0) ends it on that frame's 0xFD, a frame start. Not a
    // frame: a valid frame starts inside it and runs past its end (CI found the case,
    // 2026-12-06; before, it was skipped whole and the valid frame lost).
    let cut = [0xFD, 0, 0, 0, 0x71, 1];
    let after_cut = {
        let mut f = good.clone();
        f[6] = 0xFD;
        let n = f.len();
        let crc = checksum(&f[1..n - 2], message_info(0).expect("HEARTBEAT").crc_extra);
        f[n - 2..].copy_from_slice(&crc.to_le_bytes());
        f
    };
    let cut_id = u32::from_le_bytes([after_cut[1], after_cut[2], after_cut[3], 0]);
    assert!(
        message_info(cut_id).is_none(),
        "id {cut_id} is in the dialect"
    );
    let cases: Vec<Case> = vec![
        (
            [&cut[..], &after_cut, &good].concat(),
            ids,
            vec![after_cut.clone(), good.clone()],
            0,
            1,
            cut.len(),
        ),
        (
            [&unknown[..], &good].concat(),
            ids,
            vec![good.clone()],
            1,
            0,
            0,
        ),
        (
            [&good[..], &unknown].concat(),
            ids,
            vec![good.clone()],
            1,
            0,
            0,
        ),
        (
            [&signed[..], &v1, &good].concat(),
            ids,
            vec![good.clone()],
            2,
            0,
            0,
        ),
        (
            [&v1_unknown[..], &good].concat(),
            ids,
            vec![good.clone()],
            0,
            1,
            v1_unknown.len(),
        ),
        (
            [&unknown[..], &noise(5, 9), &good].concat(),
            ids,
            vec![good.clone()],
            0,
            1,
            unknown.len() + 5,
        ),
        (
            [&hidden[..], &good].concat(),
            ids,
            vec![good.clone(), good.clone()],
            0,
            1,
            hidden.len() - good.len(),
        ),
        (
            [&bad[..], &good].concat(),
            ids,
            vec![good.clone()],
            0,
            1,
            bad.len(),
        ),
        (
            [&unknown[..], &good].concat(),
            UnknownIds::Reject,
            vec![good.clone()],
            0,
            1,
            unknown.len(),
        ),
        (
            [&unknown[..], &good].concat(),
            UnknownIds::Deliver,
            vec![unknown.clone(), good.clone()],
            0,
            0,
            0,
        ),
    ];
    for (i, (stream, unknown_ids, want, skipped, rejected, want_garbage)) in
        cases.into_iter().enumerate()
    {
        let mut d = Deframer::<_, DEFRAMER_LEN>::new(MavlinkFraming { unknown_ids });
        let mut frames = Vec::new();
        let mut take = |e: Event<'_>| {
            if let Event::Frame(f) = e {
                frames.push(f.to_vec());
            }
        };
        d.push(&stream, &mut take);
        d.flush(&mut take);
        let s = d.stats();
        assert_eq!(frames, want, "case {i}");
        assert_eq!(
            s.frames_unknown + s.frames_skipped,
            skipped,
            "case {i}: {s:?}"
        );
        assert_eq!(
            s.checksum_errors + s.length_errors,
            rejected,
            "case {i}: {s:?}"
        );
        let garbage = (s.bytes_discarded - s.bytes_skipped) as usize;
        assert_eq!(garbage, want_garbage, "case {i}: {s:?}");
        let all = frames.iter().map(Vec::len).sum::<usize>() + s.bytes_discarded as usize;
        assert_eq!(all, stream.len(), "case {i}");
        for f in &frames {
            Frame::new_checked(&f[..]).expect("a frame");
        }
    }
}

/// The deframer's buffer decides how an unknown frame with a frame starting inside it and
/// running past its end is judged, never whether a valid frame is lost
/// (`mavlink::DEFRAMER_LEN`, docs/src/protocols/mavlink.md "Unknown message ids"). The
/// unknown frame (200 bytes, an id outside the dialect) holds the first 50 bytes of a
/// CAMERA_INFORMATION frame (152 bytes) as its last 50, and that frame's 51st byte is a
/// 0xFD, so the unknown one looks well framed. With 561 bytes the deframer sees the frame
/// inside check and rejects the unknown one; with 281 it cannot hold both, rejects it all
/// the same, and finds the frame. With the frame inside damaged, 561 bytes skip the unknown
/// frame whole, while 281 bytes reject it (the trade-off the codec's page states).
#[test]
fn a_frame_running_past_an_unknown_one_is_found_whatever_the_buffer() {
    fn run<const N: usize>(stream: &[u8]) -> (Vec<Vec<u8>>, protocol_core::wire::Stats) {
        let mut d = Deframer::<_, N>::new(MavlinkFraming::new());
        let mut frames = Vec::new();
        let mut take = |e: Event<'_>| {
            if let Event::Frame(f) = e {
                frames.push(f.to_vec());
            }
        };
        d.push(stream, &mut take);
        d.flush(&mut take);
        (frames, d.stats())
    }
    /// Payload bytes that never start a frame.
    fn clean(n: usize, seed: usize) -> Vec<u8> {
        (0..n).map(|i| ((i * 31 + seed) % 200) as u8).collect()
    }
    let inside = {
        let info = message_info(259).expect("CAMERA_INFORMATION");
        let mut payload = clean(140, 3);
        payload[40] = 0xFD;
        let mut f = vec![0xFD, 140, 0, 0, 9, 1, 100, 0x03, 0x01, 0x00];
        f.extend(&payload);
        let crc = checksum(&f[1..], info.crc_extra);
        f.extend(crc.to_le_bytes());
        let starts = f[1..].iter().filter(|b| matches!(b, 0xFD | 0xFE)).count();
        assert_eq!(starts, 1, "a frame start inside it but the one at byte 50");
        f
    };
    assert_eq!(inside.len(), 152);
    assert_eq!(inside[50], 0xFD);
    let mut unknown = vec![0xFD, 188, 0, 0, 7, 1, 1, 0x0C, 0x0B, 0];
    assert!(message_info(0x0B0C).is_none());
    unknown.extend(clean(140, 5));
    let good = {
        let info = message_info(0).expect("HEARTBEAT");
        let mut f = vec![
            0xFD, 9, 0, 0, 1, 1, 154, 0, 0, 0, 0, 0, 0, 0, 26, 8, 0, 4, 3,
        ];
        let crc = checksum(&f[1..], info.crc_extra);
        f.extend(crc.to_le_bytes());
        f
    };
    let stream = [&unknown[..], &inside, &good].concat();
    for (frames, stats) in [
        run::<DEFRAMER_LEN>(&stream),
        run::<{ MAX_FRAME_LEN + 1 }>(&stream),
    ] {
        assert_eq!(frames, vec![inside.clone(), good.clone()], "{stats:?}");
        assert_eq!(stats.frames_unknown, 0, "{stats:?}");
        assert_eq!(stats.checksum_errors, 1, "{stats:?}");
    }
    let mut damaged = inside.clone();
    *damaged.last_mut().unwrap() ^= 1;
    let stream = [&unknown[..], &damaged, &good].concat();
    let (frames, judged) = run::<DEFRAMER_LEN>(&stream);
    assert_eq!(frames, vec![good.clone()], "{judged:?}");
    assert_eq!(judged.frames_unknown, 1, "{judged:?}");
    let (frames, rejected) = run::<{ MAX_FRAME_LEN + 1 }>(&stream);
    assert_eq!(frames, vec![good.clone()], "{rejected:?}");
    assert_eq!(rejected.frames_unknown, 0, "{rejected:?}");
}
