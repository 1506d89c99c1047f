//! Property tests of the Viewlink codec: lossless decoding of any data of every frame
//! id (M with every data type), frame counters and sync orders, and deframing of noisy
//! streams (serial frames and TCP envelopes).

use crate::common;

use common::{Piece, check_stream, piece};
use proptest::prelude::*;
use protocol_core::viewlink::tcp::{self, Envelope, TcpFraming};
use protocol_core::viewlink::*;
use protocol_core::wire::Writer;

/// A frame built by the document's rule (independent of the crate).
fn frame(sync: [u8; 3], id: u8, counter: u8, data: &[u8]) -> Vec<u8> {
    let mut f = sync.to_vec();
    f.push((data.len() as u8 + 3) | (counter << 6));
    f.push(id);
    f.extend_from_slice(data);
    let cs = f[3..].iter().fold(0, |a, b| a ^ b);
    f.push(cs);
    f
}

/// Is there a valid `55 AA DC` frame at the start of `b`? (independent of the crate)
fn valid(b: &[u8]) -> Option<usize> {
    if b.len() < 7 || b[..3] != [0x55, 0xAA, 0xDC] {
        return None;
    }
    let n = usize::from(b[3] & 0x3F);
    if n < 4 || b.len() < n + 3 {
        return None;
    }
    let cs = b[3..n + 2].iter().fold(0, |a, x| a ^ x);
    (cs == b[n + 2]).then_some(n + 3)
}

/// Is there a valid TCP envelope at the start of `b`?
fn valid_tcp(b: &[u8]) -> Option<usize> {
    if b.len() < 4 || b[..2] != [0xEB, 0x90] {
        return None;
    }
    let n = usize::from(b[2]);
    if b.len() < n + 4 {
        return None;
    }
    let sum = b[3..3 + n].iter().fold(0u8, |a, x| a.wrapping_add(*x));
    (sum == b[3 + n]).then_some(n + 4)
}

/// The data lengths each known id accepts (with zero data; M is generated apart).
fn known_lengths() -> Vec<(u8, Vec<usize>)> {
    CATALOG
        .iter()
        .filter(|e| e.id != 0xB1)
        .map(|e| {
            let lens = (1..=MAX_PAYLOAD_LEN)
                .filter(|&n| Message::decode(e.id, &vec![0u8; n]).is_ok())
                .collect::<Vec<_>>();
            assert!(!lens.is_empty(), "{:#04x} accepts no length", e.id);
            (e.id, lens)
        })
        .collect()
}

/// M data: any data-type byte, the reserved bytes, and the groups its bits select.
fn m_data() -> impl Strategy<Value = Vec<u8>> {
    any::<u8>().prop_flat_map(|t| {
        let len = 7 + if t & 1 != 0 { 6 } else { 0 } + if t & 2 != 0 { 28 } else { 0 };
        proptest::collection::vec(any::<u8>(), len).prop_map(move |mut rest| {
            rest.insert(0, t);
            rest
        })
    })
}

/// (id, data) of a known frame id, with random contents.
fn known_message() -> impl Strategy<Value = (u8, Vec<u8>)> {
    prop_oneof![
        proptest::sample::select(known_lengths()).prop_flat_map(|(id, lens)| {
            proptest::sample::select(lens)
                .prop_flat_map(move |n| (Just(id), proptest::collection::vec(any::<u8>(), n)))
        }),
        m_data().prop_map(|d| (0xB1, d)),
    ]
}

fn any_frame() -> impl Strategy<Value = Vec<u8>> + Clone {
    prop_oneof![
        4 => (known_message(), 0u8..4).prop_map(|((id, d), c)| frame(SYNC, id, c, &d)),
        1 => (any::<u8>(), 0u8..4, proptest::collection::vec(any::<u8>(), 1..=MAX_PAYLOAD_LEN))
            .prop_filter("unknown id", |(id, _, _)| CATALOG.iter().all(|e| e.id != *id))
            .prop_map(|(id, c, d)| frame(SYNC, id, c, &d)),
    ]
}

/// Encodes `msg` through its typed payload (`viewlink::encode`), whichever frame id it
/// is; `None` for a raw message.
fn encode_typed(msg: &Message<'_>, header: &Header, out: &mut [u8]) -> Option<usize> {
    macro_rules! first_type {
        ($($t:ty),* $(,)?) => {
            $( if let Some(m) = msg.get::<$t>() {
                assert_eq!(<$t as MessageData>::ID, msg.id());
                assert!(m.block_len() <= <$t as MessageData>::ENCODED_LEN);
                return Some(encode(&m, header, out).unwrap());
            } )*
        };
    }
    first_type!(
        Control,
        ControlTgcc,
        A1,
        C1,
        E1,
        S1,
        RareControl,
        RareControlTgcc,
        A2,
        C2,
        E2,
        S2,
        U,
        V,
        Status,
        StatusOsd,
        RareStatus,
        M,
        AiTargets,
        Klv,
        Handshake,
        Heartbeat,
        Ack,
        D1,
        B1,
        F1,
        T1,
        T2,
        F2,
        B2,
        D2,
        Transparent,
        SdQuery,
        SdFeedback,
        IpQuery,
        IpAddress,
        IpFeedback,
    );
    None
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1024))]

    /// Any known message encodes to the same frame through its typed payload
    /// (`viewlink::encode`) as through the enum (`Packet::emit`).
    #[test]
    fn typed_encode_matches_the_enum_path((id, data) in known_message(), c in 0u8..4, swapped in any::<bool>()) {
        let msg = Message::decode(id, &data).unwrap();
        let header = Header {
            sync: if swapped { SyncOrder::Swapped } else { SyncOrder::Standard },
            counter: c,
        };
        let mut a = [0u8; MAX_FRAME_LEN];
        let mut b = [0u8; MAX_FRAME_LEN];
        let n = Packet::new(header, msg).emit(&mut a).unwrap();
        let m = encode_typed(&msg, &header, &mut b);
        prop_assert_eq!(m, Some(n));
        prop_assert_eq!(&a[..n], &b[..n]);
    }

    /// Any data of a known id decodes to a typed message that re-encodes to the same
    /// bytes and decodes again to the same message.
    #[test]
    fn any_known_data_round_trips((id, data) in known_message()) {
        let msg = Message::decode(id, &data).unwrap();
        prop_assert!(!matches!(msg, Message::Raw(_)), "{id:#04x} decoded as Raw");
        prop_assert_eq!(msg.id(), id);
        prop_assert_eq!(msg.payload_len(), data.len());
        let mut buf = [0u8; MAX_PAYLOAD_LEN];
        let mut w = Writer::new(&mut buf);
        msg.encode(&mut w).unwrap();
        prop_assert_eq!(w.written(), &data[..]);
        prop_assert_eq!(Message::decode(id, &data).unwrap(), msg);
    }

    /// Whole frames, every counter, both sync orders, known and unknown ids: decode then
    /// emit gives the frame back.
    #[test]
    fn any_frame_round_trips(f in any_frame(), swapped in any::<bool>()) {
        let mut f = f;
        if swapped {
            f[..3].copy_from_slice(&SYNC_SWAPPED);
        }
        let p = Packet::decode(&f).unwrap();
        prop_assert_eq!(p.header.counter, f[3] >> 6);
        prop_assert_eq!(p.header.sync == SyncOrder::Swapped, swapped);
        prop_assert_eq!(p.buffer_len(), f.len());
        let mut out = [0u8; MAX_FRAME_LEN];
        let n = p.emit(&mut out).unwrap();
        prop_assert_eq!(&out[..n], &f[..]);
    }

    /// Changing only the counter of a packet changes only LEN bits 6..7 and the
    /// checksum.
    #[test]
    fn counter_changes_only_len_and_checksum((id, data) in known_message(), c in 0u8..4) {
        let msg = Message::decode(id, &data).unwrap();
        let mut a = [0u8; MAX_FRAME_LEN];
        let mut b = [0u8; MAX_FRAME_LEN];
        let n = Packet::new(Header::new(0), msg).emit(&mut a).unwrap();
        let m = Packet::new(Header::new(c), msg).emit(&mut b).unwrap();
        prop_assert_eq!(n, m);
        prop_assert_eq!(b[3], a[3] | (c << 6));
        prop_assert_eq!(b[n - 1], a[n - 1] ^ (c << 6));
        prop_assert_eq!(&a[4..n - 1], &b[4..n - 1]);
        prop_assert_eq!(&b[..n], &frame(SYNC, id, c, &data)[..]);
    }

    /// C1 packs any 16 bits losslessly.
    #[test]
    fn c1_is_lossless(v in any::<u16>()) {
        prop_assert_eq!(C1::from_u16(v).to_u16(), Ok(v));
    }

    /// Arbitrary bytes never panic the decoder, and what it accepts is a valid frame.
    #[test]
    fn arbitrary_bytes_never_panic(b in proptest::collection::vec(any::<u8>(), 0..80)) {
        if let Ok(p) = Packet::decode(&b) {
            let mut std = b.clone();
            if std.len() >= 3 {
                std[..3].copy_from_slice(&SYNC);
            }
            prop_assert!(valid(&std).is_some());
            prop_assert!(p.buffer_len() <= b.len());
        }
        let _ = Envelope::decode(&b);
    }

    /// Arbitrary data of arbitrary ids never panics and, when accepted, round-trips.
    #[test]
    fn arbitrary_data_round_trips(id in any::<u8>(), d in proptest::collection::vec(any::<u8>(), 1..=MAX_PAYLOAD_LEN)) {
        if let Ok(msg) = Message::decode(id, &d) {
            let mut buf = [0u8; MAX_PAYLOAD_LEN];
            let mut w = Writer::new(&mut buf);
            msg.encode(&mut w).unwrap();
            prop_assert_eq!(w.written(), &d[..]);
        }
    }

    /// Noisy streams, cut at random points: exactly the reference scan's frames come out.
    #[test]
    fn deframer_recovers_intact_frames(
        pieces in proptest::collection::vec(piece(any_frame()), 1..12),
        chunks in proptest::collection::vec(1usize..80, 1..8),
    ) {
        check_stream::<_, MAX_FRAME_LEN>(ViewlinkFraming::new(), &pieces, &chunks, valid)?;
    }

    /// The same for TCP envelopes.
    #[test]
    fn tcp_deframer_recovers_intact_envelopes(
        pieces in proptest::collection::vec(
            piece(proptest::collection::vec(any::<u8>(), 0..40).prop_map(|body| {
                let mut out = vec![0u8; body.len() + 4];
                let n = Envelope { body: &body }.emit(&mut out).unwrap();
                out.truncate(n);
                out
            })),
            1..10,
        ),
        chunks in proptest::collection::vec(1usize..80, 1..8),
    ) {
        check_stream::<_, { tcp::MAX_FRAME_LEN }>(TcpFraming, &pieces, &chunks, valid_tcp)?;
    }
}

#[test]
fn corrupt_piece_is_never_accepted_even_alone() {
    let f = frame(SYNC, 0x1C, 2, &[0x02, 0x78]);
    for bit in 0..f.len() * 8 {
        let pieces = [Piece::Corrupt(f.clone(), bit), Piece::Intact(f.clone())];
        let (stream, _, _) = common::build(&pieces);
        let got = common::deframe::<_, MAX_FRAME_LEN>(ViewlinkFraming::new(), &stream, &[1]);
        assert_eq!(got, vec![f.clone()], "bit {bit}");
    }
}

#[test]
fn every_catalog_id_has_lengths() {
    let lens = known_lengths();
    assert_eq!(lens.len(), 36);
    for (id, l) in &lens {
        let fixed = !matches!(id, 0x02 | 0xF3 | 0xF4 | 0xFF);
        assert_eq!(fixed, l.len() == 1, "{id:#04x}: {l:?}");
    }
}
