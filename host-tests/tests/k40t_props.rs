//! Property tests of the K40T codec: lossless decoding of any payload of every message,
//! and deframing of noisy streams.

use crate::common;

use codec_cases::oracle::k40t_crc as doc_crc;
use common::{Piece, check_stream, piece};
use proptest::prelude::*;
use protocol_core::k40t::*;
use protocol_core::wire::Writer;

/// A frame with the given id and payload, CRC over LEN..payload.
fn frame(id: u32, payload: &[u8]) -> Vec<u8> {
    let id = id.to_le_bytes();
    let mut f = vec![
        0xFD,
        payload.len() as u8,
        0x04,
        0x01,
        0x11,
        0x02,
        0x01,
        id[0],
        id[1],
        id[2],
    ];
    f.extend_from_slice(payload);
    let crc = doc_crc(&f[1..]);
    f.extend_from_slice(&crc.to_le_bytes());
    f
}

/// Is there a valid frame at the start of `b`? (independent of the crate)
fn valid(b: &[u8]) -> Option<usize> {
    valid_with(b, CrcCoverage::ExcludeStx)
}

/// Is there a frame at the start of `b` whose CRC covers the bytes `coverage` names?
fn valid_with(b: &[u8], coverage: CrcCoverage) -> Option<usize> {
    if b.first() != Some(&0xFD) || b.len() < 12 {
        return None;
    }
    let len = usize::from(b[1]);
    if len > 243 || b.len() < len + 12 {
        return None;
    }
    let crc = u16::from_le_bytes([b[len + 10], b[len + 11]]);
    let start = match coverage {
        CrcCoverage::ExcludeStx => 1,
        CrcCoverage::IncludeStx => 0,
    };
    (doc_crc(&b[start..len + 10]) == crc).then_some(len + 12)
}

/// Every (kind, base) the catalogue defines, with its payload length.
fn known_ids() -> Vec<(u32, usize)> {
    let mut ids = Vec::new();
    for e in CATALOG {
        for (kind, has) in [(0u32, true), (1, e.ack), (2, e.status)] {
            if has {
                let id = MsgId::from_u32(kind << 16 | u32::from(e.base));
                let len = Message::decode(id, &[])
                    .expect("zero-extended")
                    .payload_len();
                ids.push((id.to_u32(), len));
            }
        }
    }
    ids
}

fn known_message() -> impl Strategy<Value = (u32, Vec<u8>)> {
    proptest::sample::select(known_ids())
        .prop_flat_map(|(id, len)| (Just(id), proptest::collection::vec(any::<u8>(), len)))
}

/// An id the catalogue does not define (it decodes to `Raw`), mostly near the known ones.
fn unknown_id() -> impl Strategy<Value = u32> + Clone {
    prop_oneof![0u32..0x03_0000, 0u32..0x0100_0000].prop_filter("a known id", |&id| {
        matches!(
            Message::decode(MsgId::from_u32(id), &[]),
            Ok(Message::Raw(_))
        )
    })
}

fn any_frame() -> impl Strategy<Value = Vec<u8>> + Clone {
    prop_oneof![
        known_message().prop_map(|(id, p)| frame(id, &p)),
        (
            unknown_id(),
            proptest::collection::vec(any::<u8>(), 0..=243)
        )
            .prop_map(|(id, p)| frame(id, &p)),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Any payload of a known message decodes, and re-encodes to the same bytes; the
    /// re-decoded message is equal.
    #[test]
    fn any_payload_round_trips((id, payload) in known_message()) {
        let msg = Message::decode(MsgId::from_u32(id), &payload).unwrap();
        prop_assert!(!matches!(msg, Message::Raw(_)), "{id:#08x} decoded as Raw");
        prop_assert_eq!(msg.id().to_u32(), id);
        let mut buf = [0u8; MAX_PAYLOAD_LEN];
        let mut w = Writer::new(&mut buf);
        msg.encode(&mut w).unwrap();
        prop_assert_eq!(w.written(), &payload[..]);
        prop_assert_eq!(Message::decode(MsgId::from_u32(id), &payload).unwrap(), msg);
    }

    /// Whole frames: decode then emit gives the frame back, for known and unknown ids.
    #[test]
    fn any_frame_round_trips(f in any_frame()) {
        let p = Packet::decode(&f).unwrap();
        prop_assert_eq!(p.header.coverage, CrcCoverage::ExcludeStx);
        let mut out = [0u8; MAX_FRAME_LEN];
        let n = p.emit(&mut out).unwrap();
        prop_assert_eq!(&out[..n], &f[..]);
    }

    /// Arbitrary bytes never panic the decoder, and what it accepts is a valid frame.
    #[test]
    fn arbitrary_bytes_never_panic(b in proptest::collection::vec(any::<u8>(), 0..300)) {
        if let Ok(p) = Packet::decode(&b) {
            prop_assert!(valid_with(&b, p.header.coverage).is_some());
            prop_assert!(p.buffer_len() <= b.len());
        }
    }

    /// Noisy streams, cut at random points: exactly the reference scan's frames come out.
    #[test]
    fn deframer_recovers_intact_frames(
        pieces in proptest::collection::vec(piece(any_frame()), 1..12),
        chunks in proptest::collection::vec(1usize..300, 1..8),
    ) {
        check_stream::<_, MAX_FRAME_LEN>(K40tFraming::with(CrcCoverage::ExcludeStx), &pieces, &chunks, valid)?;
    }
}

#[test]
fn corrupt_piece_is_never_accepted_even_alone() {
    let f = frame(0x000304, &[0, 0x2D, 0]);
    for bit in 0..f.len() * 8 {
        let pieces = [Piece::Corrupt(f.clone(), bit), Piece::Intact(f.clone())];
        let (stream, _, _) = common::build(&pieces);
        let got = common::deframe::<_, MAX_FRAME_LEN>(K40tFraming::default(), &stream, &[1]);
        assert_eq!(got, vec![f.clone()], "bit {bit}");
    }
}
