//! K40T: decoding arbitrary bytes (and the same bytes with a valid CRC under either
//! coverage) re-encodes exactly, and the deframer under every framing variant.

use codec_cases::oracle::k40t_crc;
use protocol_core::k40t::{
    CrcCoverage, Frame, Header, K40tFraming, MAX_FRAME_LEN, Message, MsgId, Packet,
};
use std::hint::black_box;

use crate::deframe::{self, Spec};
use crate::input::{Input, Plan};
use crate::is_frame_error;

/// Target `k40t_decode`: `Packet::decode` of the input; the input with its CRC filled
/// in under each coverage must then pass every frame-level check.
pub fn decode(data: &[u8]) {
    if let Ok(p) = Packet::decode(data) {
        round_trip(data, &p);
    }
    if let Ok(frame) = Frame::new_checked(data) {
        for coverage in [CrcCoverage::ExcludeStx, CrcCoverage::IncludeStx] {
            let mut fixed = data[..frame.total_len()].to_vec();
            Frame::new_unchecked(&mut fixed[..]).fill_checksum(coverage);
            match Packet::decode(&fixed) {
                Ok(p) => {
                    // Both coverages can match (one frame in 65536): ExcludeStx is reported.
                    assert!(
                        p.header.coverage == coverage
                            || Frame::new_unchecked(&fixed[..])
                                .verify(CrcCoverage::ExcludeStx)
                                .is_ok(),
                        "coverage {:?} detected as {:?}",
                        coverage,
                        p.header.coverage
                    );
                    round_trip(&fixed, &p);
                }
                Err(e) => assert!(!is_frame_error(e), "{e:?} for a frame with a valid CRC"),
            }
        }
    }
    accessors(data);
}

/// Every accessor of an unchecked view (none may panic).
fn accessors(data: &[u8]) {
    let f = Frame::new_unchecked(data);
    let _ = black_box((
        f.check_len(),
        f.payload_len(),
        f.total_len(),
        f.dst(),
        f.src(),
    ));
    let _ = black_box((f.seq(), f.id(), f.payload(), f.payload_ref(), f.checksum()));
    let _ = black_box((
        f.compute_checksum(CrcCoverage::ExcludeStx),
        f.compute_checksum(CrcCoverage::IncludeStx),
        f.detect_coverage(),
    ));
}

/// Re-encodes `p` (decoded from `data`): byte for byte, except that a payload shorter
/// than its layout comes back zero-extended (MAVLink v2 truncation).
fn round_trip(data: &[u8], p: &Packet<'_>) {
    let len = usize::from(data[1]);
    let frame_len = len + 12;
    let mut out = [0u8; MAX_FRAME_LEN];
    let n = p.emit(&mut out).expect("a decoded packet re-encodes");
    assert_eq!(n, p.buffer_len());
    let out = &out[..n];
    if n == frame_len {
        assert_eq!(out, &data[..n], "re-encoding differs");
    } else {
        assert!(n > frame_len, "re-encoding lost payload bytes");
        assert_eq!(out[0], data[0]);
        assert_eq!(&out[2..10], &data[2..10], "re-encoded header differs");
        assert_eq!(&out[10..10 + len], &data[10..10 + len], "payload differs");
        assert!(
            out[10 + len..n - 2].iter().all(|&b| b == 0),
            "a short payload is not zero-extended"
        );
    }
    // Decoding the re-encoded frame gives the same packet (compared through its bytes:
    // a float field may be NaN).
    let again = Packet::decode(out).expect("the re-encoded frame decodes");
    let mut twice = [0u8; MAX_FRAME_LEN];
    assert_eq!(again.emit(&mut twice), Ok(n));
    assert_eq!(&twice[..n], out, "the re-encoded frame decodes differently");
    crate::exact_buffers(n, |buf| p.emit(buf));
}

/// The frame at the start of `b` if it is valid for `coverage` (`None`: either) and
/// fits a buffer of `cap` bytes; written from the document, without the codec.
#[must_use]
pub fn valid(b: &[u8], coverage: Option<CrcCoverage>, cap: usize) -> Option<usize> {
    if b.len() < 2 || b[0] != 0xFD {
        return None;
    }
    let len = usize::from(b[1]);
    if len > 243 || len + 12 > cap || b.len() < len + 12 {
        return None;
    }
    let crc = u16::from_le_bytes([b[len + 10], b[len + 11]]);
    let covered = |start: usize| k40t_crc(&b[start..len + 10]) == crc;
    let ok = match coverage {
        None => covered(1) || covered(0),
        Some(CrcCoverage::ExcludeStx) => covered(1),
        Some(CrcCoverage::IncludeStx) => covered(0),
    };
    ok.then_some(len + 12)
}

/// The checked parse every delivered frame must pass.
pub fn checked(framing: K40tFraming, f: &[u8]) {
    let frame = Frame::new_checked(f).expect("a delivered frame passes new_checked");
    assert_eq!(frame.total_len(), f.len());
    match framing.coverage {
        Some(c) => frame.verify(c).expect("a delivered frame has a valid CRC"),
        None => assert!(frame.detect_coverage().is_some()),
    }
    if let Err(e) = Packet::decode(f) {
        assert!(!is_frame_error(e), "{e:?} for a delivered frame");
    }
}

/// The framing variant a selector names: coverage any, ExcludeStx or IncludeStx.
#[must_use]
pub fn framing(selector: u8) -> K40tFraming {
    match selector % 3 {
        0 => K40tFraming::any(),
        1 => K40tFraming::with(CrcCoverage::ExcludeStx),
        _ => K40tFraming::with(CrcCoverage::IncludeStx),
    }
}

/// Target `k40t_deframe`: selector bits 0..1 the coverage, bit 2 a 64-byte buffer
/// (shorter than the largest frame) instead of a full one.
pub fn deframe(data: &[u8]) {
    let mut input = Input::new(data);
    let (selector, plan) = Plan::read(&mut input);
    let framing = framing(selector & 3);
    let checked = move |f: &[u8]| checked(framing, f);
    if selector & 4 == 0 {
        let valid = |b: &[u8]| valid(b, framing.coverage, MAX_FRAME_LEN);
        let spec = Spec {
            valid: &valid,
            skipped: &|_| None,
            checked: &checked,
            compare_scanner: true,
        };
        deframe::check::<_, MAX_FRAME_LEN>(&framing, input.rest(), &plan, &spec);
    } else {
        let valid = |b: &[u8]| valid(b, framing.coverage, 64);
        let spec = Spec {
            valid: &valid,
            skipped: &|_| None,
            checked: &checked,
            compare_scanner: false,
        };
        deframe::check::<_, 64>(&framing, input.rest(), &plan, &spec);
    }
}

/// Every message id the catalogue defines (request, ACK, status).
#[must_use]
pub fn known_ids() -> Vec<MsgId> {
    use protocol_core::k40t::{CATALOG, Kind};
    let mut ids = Vec::new();
    for e in CATALOG {
        for (kind, has) in [
            (Kind::Request, true),
            (Kind::Ack, e.ack),
            (Kind::Status, e.status),
        ] {
            if has {
                ids.push(MsgId::new(kind, e.base));
            }
        }
    }
    ids
}

/// A frame built by the encoder: message `id` with the payload `fill` (zero-extended to
/// the layout), the header's fields from `input`.
#[must_use]
pub fn encoded(id: MsgId, fill: &[u8], seq: u8, coverage: CrcCoverage) -> Vec<u8> {
    let len = Message::decode(id, &[]).map_or(0, |m| m.payload_len());
    let mut payload = fill[..len.min(fill.len())].to_vec();
    payload.resize(len, 0);
    let message = Message::decode(id, &payload).expect("a payload of the layout's length");
    let header = Header {
        coverage,
        ..Header::new(
            protocol_core::k40t::Address::FLIGHT_CONTROLLER,
            protocol_core::k40t::Address::POD,
            seq,
        )
    };
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = Packet { header, message }
        .emit(&mut buf)
        .expect("encode a catalogue message");
    buf[..n].to_vec()
}

/// The K40T frame of the resync target: `choice` picks the message (bytes 1..2) and
/// the sequence number (byte 3); `fill` is the payload.
pub(crate) fn resync_frame(choice: [u8; 6], fill: &[u8], coverage: CrcCoverage) -> Vec<u8> {
    let ids = known_ids();
    let pick = usize::from(u16::from_le_bytes([choice[1], choice[2]])) % ids.len();
    encoded(ids[pick], fill, choice[3], coverage)
}

/// Every message of the catalogue, built by the encoder (seeds).
#[must_use]
pub fn catalogue_frames(fill: &[u8], coverage: CrcCoverage) -> Vec<Vec<u8>> {
    known_ids()
        .into_iter()
        .enumerate()
        .map(|(i, id)| encoded(id, fill, i as u8, coverage))
        .collect()
}
