//! GCU: host and GCU packages decode and re-encode exactly; a package with a valid CRC
//! always decodes (the GCU can always answer) and the answer to a host package
//! decodes as the GCU package of its order; the deframer for each direction.

use codec_cases::oracle::gcu_crc;
use protocol_core::Direction;
use protocol_core::gcu::{
    CATALOG, Execution, Frame, GcuFrames, GcuFraming, GcuPacket, Header, HostFrames, HostPacket,
    MAX_FRAME_LEN, Message, Packet,
};
use protocol_core::wire::Reader;
use protocol_core::wire::encoding::{Field, Le};
use std::hint::black_box;

use crate::deframe::{self, Spec};
use crate::input::{Input, Plan};

/// Target `gcu_decode`.
pub fn decode(data: &[u8]) {
    if let Ok(p) = Packet::decode(data) {
        round_trip(data, &p);
    }
    if let Ok(frame) = Frame::new_checked(data) {
        let mut fixed = data[..frame.total_len()].to_vec();
        Frame::new_unchecked(&mut fixed[..]).fill_checksum();
        let decoded = Packet::decode(&fixed);
        assert_eq!(
            Packet::parse(&frame).map(|p| encoded_bytes(&p)),
            decoded.map(|p| encoded_bytes(&p)),
            "parse and decode disagree"
        );
        let p = decoded.expect("a package with a valid CRC always decodes");
        round_trip(&fixed, &p);
    }
    let f = Frame::new_unchecked(data);
    let _ = black_box((
        f.check_len(),
        f.direction(),
        f.total_len(),
        f.version(),
        f.main(),
    ));
    let _ = black_box((f.sub(), f.id(), f.payload_len(), f.payload(), f.checksum()));
    let _ = black_box((
        f.main_ref(),
        f.sub_ref(),
        f.payload_ref(),
        f.compute_checksum(),
        f.verify(),
    ));
}

/// Re-encodes `p`, decoded from `data`, through each of the three decoders; a host
/// package's answer must decode as the GCU package of its order.
fn round_trip(data: &[u8], p: &Packet<'_>) {
    let n = p.buffer_len();
    let mut out = vec![0u8; n];
    assert_eq!(p.emit(&mut out), Ok(n), "a decoded package re-encodes");
    assert_eq!(&out[..], &data[..n], "re-encoding differs");
    // (Compared through their bytes: a float field may be NaN.)
    assert_eq!(Packet::decode(&out).map(|p| encoded_bytes(&p)), Ok(out));
    crate::exact_buffers(n, |buf| p.emit(buf));
    match p {
        Packet::Host(host) => {
            assert_eq!(
                HostPacket::decode(data).map(|h| encoded_bytes(&Packet::Host(h))),
                Ok(encoded_bytes(p))
            );
            assert!(GcuPacket::decode(data).is_err());
            assert_eq!(p.direction(), Direction::ToGimbal);
            for execution in [Execution::Success, Execution::Fail] {
                let answer = host.answer(GcuFrames::default(), execution);
                let mut buf = [0u8; MAX_FRAME_LEN];
                let m = answer.emit(&mut buf).expect("the answer encodes");
                let back = GcuPacket::decode(&buf[..m]).expect("the answer decodes");
                // (`Fail` for an order whose feedback is a camera set reads back as that
                // set: compare the bytes.)
                let mut again = [0u8; MAX_FRAME_LEN];
                assert_eq!(back.emit(&mut again), Ok(m));
                assert_eq!(&again[..m], &buf[..m]);
                assert_eq!(back.feedback.order, host.message.order());
                assert_eq!(back.header, host.header);
            }
        }
        Packet::Gcu(_) => {
            assert_eq!(
                GcuPacket::decode(data).map(|g| encoded_bytes(&Packet::Gcu(g))),
                Ok(encoded_bytes(p))
            );
            assert!(HostPacket::decode(data).is_err());
            assert_eq!(p.direction(), Direction::FromGimbal);
        }
    }
}

/// A package's encoding (to compare packages whose float fields may be NaN).
fn encoded_bytes(p: &Packet<'_>) -> Vec<u8> {
    let mut out = vec![0u8; p.buffer_len()];
    let n = p.emit(&mut out).expect("a decoded package re-encodes");
    out.truncate(n);
    out
}

/// The package at the start of `b` if valid with sync bytes `sync`; written from the
/// document, without the codec.
#[must_use]
pub fn valid(b: &[u8], sync: [u8; 2]) -> Option<usize> {
    if b.len() < 4 || b[..2] != sync {
        return None;
    }
    let len = usize::from(u16::from_le_bytes([b[2], b[3]]));
    if !(72..=257).contains(&len) || b.len() < len {
        return None;
    }
    let crc = u16::from_be_bytes([b[len - 2], b[len - 1]]);
    (gcu_crc(&b[..len - 2]) == crc).then_some(len)
}

/// The checked parse every delivered package must pass.
pub fn checked(framing: GcuFraming, f: &[u8]) {
    let frame = Frame::new_checked(f).expect("a delivered package passes new_checked");
    assert_eq!(frame.total_len(), f.len());
    assert_eq!(frame.direction(), Some(framing.direction));
    frame.verify().expect("a delivered package has a valid CRC");
    let p = Packet::decode(f).expect("a delivered package decodes");
    assert_eq!(p.direction(), framing.direction);
}

/// Target `gcu_deframe`: selector bit 0 reads GCU packages instead of host packages.
pub fn deframe(data: &[u8]) {
    let mut input = Input::new(data);
    let (selector, plan) = Plan::read(&mut input);
    let framing = if selector & 1 == 0 {
        GcuFraming::host()
    } else {
        GcuFraming::gcu()
    };
    let sync = protocol_core::gcu::sync_of(framing.direction);
    let valid = |b: &[u8]| valid(b, sync);
    let checked = move |f: &[u8]| checked(framing, f);
    let spec = Spec {
        valid: &valid,
        skipped: &|_| None,
        checked: &checked,
        compare_scanner: true,
    };
    deframe::check::<_, MAX_FRAME_LEN>(&framing, input.rest(), &plan, &spec);
}

/// A host package built by the encoder: the order of `entry` with parameters from
/// `fill`, data frames read from `frames` (zeros where they do not decode).
#[must_use]
pub fn encoded(id: u8, fill: &[u8], frames: &[u8], version: u8) -> Vec<u8> {
    let len = CATALOG
        .iter()
        .find(|e| e.id == id)
        .map_or(0, |e| e.payload_len);
    let mut payload = fill[..len.min(fill.len())].to_vec();
    payload.resize(len, 0);
    let frames = <HostFrames as Field<Le>>::read(&mut Reader::new(frames)).unwrap_or_default();
    let p = HostPacket {
        header: Header::new(version),
        frames,
        message: Message::decode(id, &payload),
    };
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = p.emit(&mut buf).expect("encode a catalogue command");
    buf[..n].to_vec()
}

/// The GCU's answer to a host package.
#[must_use]
pub fn answer(host: &[u8], frames: &[u8], execution: u8) -> Vec<u8> {
    let p = HostPacket::decode(host).expect("a host package");
    let frames = <GcuFrames as Field<Le>>::read(&mut Reader::new(frames)).unwrap_or_default();
    let execution = match execution % 3 {
        0 => Execution::Success,
        1 => Execution::Fail,
        _ => Execution::Operating,
    };
    let answer = p.answer(frames, execution);
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = answer.emit(&mut buf).expect("encode an answer");
    buf[..n].to_vec()
}

/// The GCU package (host, or the GCU's answer) of the resync target: `choice` picks
/// the order (byte 1), the version (byte 2) and the answer's execution state (byte 3);
/// `fill` holds the host's data frames (64 bytes), the parameters, and the GCU's data
/// frames.
pub(crate) fn resync_frame(choice: [u8; 6], fill: &[u8], direction: Direction) -> Vec<u8> {
    let entry = &CATALOG[usize::from(choice[1]) % CATALOG.len()];
    let mut input = Input::new(fill);
    let frames = input.bytes(64);
    let params = input.bytes(entry.payload_len);
    let host = encoded(entry.id, params, frames, choice[2]);
    match direction {
        Direction::ToGimbal => host,
        Direction::FromGimbal => answer(&host, input.bytes(64), choice[3]),
    }
}

/// Every order of the catalogue as a host package, and each one's answer (seeds).
#[must_use]
pub fn catalogue_frames(fill: &[u8]) -> (Vec<Vec<u8>>, Vec<Vec<u8>>) {
    let host: Vec<Vec<u8>> = CATALOG
        .iter()
        .map(|e| encoded(e.id, fill, fill, 0x02))
        .collect();
    let answers = host.iter().map(|h| answer(h, fill, 0)).collect();
    (host, answers)
}
