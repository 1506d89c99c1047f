//! Viewlink: serial frames (both sync orders) and the TCP envelope decode and re-encode
//! exactly; the deframer for each sync order and for the envelope.

use protocol_core::viewlink::tcp::{self, Envelope, TcpFrame, TcpFraming};
use protocol_core::viewlink::{
    CATALOG, Frame, Header, MAX_FRAME_LEN, MAX_PAYLOAD_LEN, Message, Packet, SyncOrder,
    ViewlinkFraming,
};
use protocol_core::wire::sum8;
use std::hint::black_box;

use crate::deframe::{self, Spec};
use crate::input::{Input, Plan};
use crate::is_frame_error;

/// Target `viewlink_decode`.
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
        match decoded {
            Ok(p) => round_trip(&fixed, &p),
            Err(e) => assert!(
                !is_frame_error(e),
                "{e:?} for a frame with a valid checksum"
            ),
        }
    }
    let f = Frame::new_unchecked(data);
    let _ = black_box((
        f.check_len(),
        f.sync_order(),
        f.len_field(),
        f.body_len(),
        f.counter(),
    ));
    let _ = black_box((
        f.total_len(),
        f.id(),
        f.payload_len(),
        f.payload(),
        f.payload_ref(),
    ));
    let _ = black_box((f.checksum(), f.compute_checksum(), f.verify()));
}

fn round_trip(data: &[u8], p: &Packet<'_>) {
    let n = p.buffer_len();
    let mut out = vec![0u8; n];
    assert_eq!(p.emit(&mut out), Ok(n), "a decoded packet re-encodes");
    assert_eq!(&out[..], &data[..n], "re-encoding differs");
    // (Compared through their bytes: a float field may be NaN.)
    assert_eq!(Packet::decode(&out).map(|p| encoded_bytes(&p)), Ok(out));
    crate::exact_buffers(n, |buf| p.emit(buf));
}

/// A packet's encoding (to compare packets whose float fields may be NaN).
fn encoded_bytes(p: &Packet<'_>) -> Vec<u8> {
    let mut out = vec![0u8; p.buffer_len()];
    let n = p.emit(&mut out).expect("a decoded packet re-encodes");
    out.truncate(n);
    out
}

/// The serial frame at the start of `b` if valid with sync bytes `sync`; written from
/// the document, without the codec.
#[must_use]
pub fn valid(b: &[u8], sync: [u8; 3]) -> Option<usize> {
    if b.len() < 4 || b[..3] != sync {
        return None;
    }
    let n = usize::from(b[3] & 0x3F);
    if n < 4 || b.len() < n + 3 {
        return None;
    }
    let xor = b[3..n + 2].iter().fold(0, |a, x| a ^ x);
    (xor == b[n + 2]).then_some(n + 3)
}

/// The checked parse every delivered serial frame must pass.
pub fn checked(framing: ViewlinkFraming, f: &[u8]) {
    let frame = Frame::new_checked(f).expect("a delivered frame passes new_checked");
    assert_eq!(frame.total_len(), f.len());
    assert_eq!(frame.sync_order(), framing.sync);
    frame
        .verify()
        .expect("a delivered frame has a valid checksum");
    if let Err(e) = Packet::decode(f) {
        assert!(!is_frame_error(e), "{e:?} for a delivered frame");
    }
}

/// Target `viewlink_deframe`: selector bit 0 the swapped sync order.
pub fn deframe(data: &[u8]) {
    let mut input = Input::new(data);
    let (selector, plan) = Plan::read(&mut input);
    let framing = if selector & 1 == 0 {
        ViewlinkFraming::new()
    } else {
        ViewlinkFraming::swapped()
    };
    let valid = |b: &[u8]| valid(b, framing.sync.bytes());
    let checked = move |f: &[u8]| checked(framing, f);
    let spec = Spec {
        valid: &valid,
        skipped: &|_| None,
        checked: &checked,
        compare_scanner: true,
    };
    deframe::check::<_, MAX_FRAME_LEN>(&framing, input.rest(), &plan, &spec);
}

/// Target `viewlink_tcp`: the first byte chooses between decoding the rest as an
/// envelope (even) and deframing it as a stream of envelopes (odd).
pub fn tcp(data: &[u8]) {
    let Some((&mode, rest)) = data.split_first() else {
        return;
    };
    if mode & 1 == 0 {
        tcp_decode(rest);
    } else {
        tcp_deframe(rest);
    }
}

fn tcp_decode(data: &[u8]) {
    if let Ok(env) = Envelope::decode(data) {
        tcp_round_trip(data, &env);
    }
    if let Ok(frame) = TcpFrame::new_checked(data) {
        let mut fixed = data[..frame.total_len()].to_vec();
        let sum_at = fixed.len() - 1;
        fixed[sum_at] = sum8(&fixed[tcp::HEADER_LEN..sum_at]);
        let decoded = Envelope::decode(&fixed);
        assert_eq!(
            Envelope::parse(&frame),
            decoded,
            "parse and decode disagree"
        );
        let env = decoded.expect("an envelope with a valid checksum decodes");
        tcp_round_trip(&fixed, &env);
    }
    let f = TcpFrame::new_unchecked(data);
    let _ = black_box((
        f.check_len(),
        f.body_len(),
        f.total_len(),
        f.body(),
        f.body_ref(),
    ));
    let _ = black_box((f.checksum(), f.compute_checksum(), f.verify()));
}

fn tcp_round_trip(data: &[u8], env: &Envelope<'_>) {
    let n = env.buffer_len();
    let mut out = vec![0u8; n];
    assert_eq!(env.emit(&mut out), Ok(n), "a decoded envelope re-encodes");
    assert_eq!(&out[..], &data[..n], "re-encoding differs");
    crate::exact_buffers(n, |buf| env.emit(buf));
    // A body that is a serial frame re-encodes too.
    if let Ok(p) = env.serial() {
        round_trip(env.body, &p);
    }
}

/// The envelope at the start of `b`, if valid; written without the codec.
#[must_use]
pub fn tcp_valid(b: &[u8]) -> Option<usize> {
    if b.len() < 3 || b[..2] != [0xEB, 0x90] {
        return None;
    }
    let n = usize::from(b[2]);
    if b.len() < n + 4 {
        return None;
    }
    let sum = b[3..3 + n].iter().fold(0u8, |a, x| a.wrapping_add(*x));
    (sum == b[3 + n]).then_some(n + 4)
}

/// The checked parse every delivered envelope must pass.
pub fn tcp_checked(f: &[u8]) {
    let frame = TcpFrame::new_checked(f).expect("a delivered envelope passes new_checked");
    assert_eq!(frame.total_len(), f.len());
    frame
        .verify()
        .expect("a delivered envelope has a valid checksum");
    Envelope::decode(f).expect("a delivered envelope decodes");
}

fn tcp_deframe(data: &[u8]) {
    let mut input = Input::new(data);
    let (_, plan) = Plan::read(&mut input);
    let spec = Spec {
        valid: &tcp_valid,
        skipped: &|_| None,
        checked: &tcp_checked,
        compare_scanner: true,
    };
    deframe::check::<_, { tcp::MAX_FRAME_LEN }>(&TcpFraming, input.rest(), &plan, &spec);
}

/// Every payload length (1..=60) frame `id` decodes from a prefix of `fill`.
fn lengths(id: u8, fill: &[u8]) -> Vec<usize> {
    (1..=MAX_PAYLOAD_LEN)
        .filter(|&n| Message::decode(id, &fill[..n]).is_ok())
        .collect()
}

/// A frame built by the encoder: frame `id` with the payload of the `pick`-th length it
/// accepts (a prefix of `fill`, zero-padded to 60 bytes).
#[must_use]
pub fn encoded(id: u8, fill: &[u8], pick: usize, header: Header) -> Option<Vec<u8>> {
    let mut padded = fill.to_vec();
    padded.resize(MAX_PAYLOAD_LEN, 0);
    let lens = lengths(id, &padded);
    let len = *lens.get(pick % lens.len().max(1))?;
    let message = Message::decode(id, &padded[..len]).ok()?;
    let p = Packet::new(header, message);
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = p.emit(&mut buf).expect("encode a catalogue message");
    Some(buf[..n].to_vec())
}

/// The Viewlink serial frame of the resync target: `choice` picks the frame id and
/// payload length (bytes 1..2) and the counter (byte 3); the payload is a prefix of
/// `fill`.
pub(crate) fn resync_frame(choice: [u8; 6], fill: &[u8], sync: SyncOrder) -> Vec<u8> {
    let pick = usize::from(u16::from_le_bytes([choice[1], choice[2]]));
    let entry = &CATALOG[pick % CATALOG.len()];
    let header = Header {
        sync,
        counter: choice[3] & 3,
    };
    let fill = &fill[..fill.len().min(MAX_PAYLOAD_LEN)];
    encoded(entry.id, fill, pick / CATALOG.len(), header)
        .or_else(|| encoded(entry.id, &[], 0, header))
        .expect("every catalogue frame id accepts a zero payload of some length")
}

/// An envelope around `body`.
#[must_use]
pub fn envelope(body: &[u8]) -> Vec<u8> {
    let env = Envelope { body };
    let mut out = vec![0u8; env.buffer_len()];
    let n = env.emit(&mut out).expect("a body of at most 255 bytes");
    out.truncate(n);
    out
}

/// Every frame id of the catalogue, built by the encoder (seeds).
#[must_use]
pub fn catalogue_frames(fill: &[u8], sync: SyncOrder) -> Vec<Vec<u8>> {
    CATALOG
        .iter()
        .enumerate()
        .filter_map(|(i, e)| {
            let header = Header {
                sync,
                counter: (i % 4) as u8,
            };
            encoded(e.id, fill, i, header)
        })
        .collect()
}
