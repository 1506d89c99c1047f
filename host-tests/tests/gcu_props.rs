//! Property tests of the GCU codec: lossless decoding of any package of either
//! direction, and deframing of noisy streams (one framing per direction).

use crate::common;

use codec_cases::oracle::gcu_crc as doc_crc;
use common::{Piece, build, check_stream, deframe, oracle, piece};
use proptest::prelude::*;
use protocol_core::Direction;
use protocol_core::gcu::*;

const HOST: [u8; 2] = [0xA8, 0xE5];
const GCU: [u8; 2] = [0x8A, 0x5E];

/// A package: sync, length, version, 64 bytes of data frames, order, parameters, CRC.
fn package(sync: [u8; 2], version: u8, frames: &[u8], order: u8, params: &[u8]) -> Vec<u8> {
    let len = (72 + params.len()) as u16;
    let mut f = sync.to_vec();
    f.extend_from_slice(&len.to_le_bytes());
    f.push(version);
    f.extend_from_slice(frames);
    f.push(order);
    f.extend_from_slice(params);
    let crc = doc_crc(&f);
    f.extend_from_slice(&crc.to_be_bytes());
    f
}

/// Is there a valid package of the direction `sync` at the start of `b`? (independent
/// of the crate)
fn valid(sync: [u8; 2], b: &[u8]) -> Option<usize> {
    if b.len() < 4 || b[..2] != sync {
        return None;
    }
    let len = usize::from(u16::from_le_bytes([b[2], b[3]]));
    if !(72..=257).contains(&len) || b.len() < len {
        return None;
    }
    let crc = u16::from_be_bytes([b[len - 2], b[len - 1]]);
    (doc_crc(&b[..len - 2]) == crc).then_some(len)
}

/// A known order with parameters of its length.
fn known_command() -> impl Strategy<Value = (u8, Vec<u8>)> {
    proptest::sample::select(CATALOG.to_vec()).prop_flat_map(|e| {
        (
            Just(e.id),
            proptest::collection::vec(any::<u8>(), e.payload_len),
        )
    })
}

fn host_package() -> impl Strategy<Value = Vec<u8>> + Clone {
    let command = prop_oneof![
        3 => known_command(),
        1 => (any::<u8>(), proptest::collection::vec(any::<u8>(), 0..=40)),
    ];
    (
        any::<u8>(),
        proptest::collection::vec(any::<u8>(), 64),
        command,
    )
        .prop_map(|(v, frames, (order, params))| package(HOST, v, &frames, order, &params))
}

fn gcu_package() -> impl Strategy<Value = Vec<u8>> + Clone {
    (
        any::<u8>(),
        proptest::collection::vec(any::<u8>(), 64),
        any::<u8>(),
        proptest::collection::vec(any::<u8>(), 0..=3),
    )
        .prop_map(|(v, frames, order, data)| package(GCU, v, &frames, order, &data))
}

fn emit(p: &Packet<'_>) -> Vec<u8> {
    let mut out = [0u8; MAX_FRAME_LEN];
    let n = p.emit(&mut out).unwrap();
    out[..n].to_vec()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Any data frames and any known order with parameters of its length decode to the
    /// typed command, and re-encode to the same bytes.
    #[test]
    fn known_host_packages_are_typed_and_lossless(
        v in any::<u8>(),
        frames in proptest::collection::vec(any::<u8>(), 64),
        (order, params) in known_command(),
    ) {
        let f = package(HOST, v, &frames, order, &params);
        let p = HostPacket::decode(&f).unwrap();
        prop_assert!(matches!(p.message, Message::Command(_)), "{order:#04x} decoded as Raw");
        prop_assert_eq!(p.message.id(), order);
        prop_assert_eq!(p.message.order().value(), order);
        prop_assert_eq!(p.header.version, v);
        prop_assert_eq!(&p.frames.main.sub_request, &frames[25]);
        prop_assert_eq!(p.buffer_len(), f.len());
        prop_assert_eq!(emit(&Packet::Host(p)), f);
    }

    /// Packages of both directions, known or not: decode then emit gives them back.
    #[test]
    fn any_package_round_trips(f in prop_oneof![host_package(), gcu_package()]) {
        let p = Packet::decode(&f).unwrap();
        prop_assert_eq!(p.direction() == Direction::ToGimbal, f[0] == 0xA8);
        prop_assert_eq!(p.id(), f[69]);
        prop_assert_eq!(p.header().version, f[4]);
        let again = emit(&p);
        prop_assert_eq!(&again, &f);
        prop_assert_eq!(Packet::decode(&again).unwrap(), p);
    }

    /// GCU feedback reads per the order's kind and keeps every byte.
    #[test]
    fn feedback_is_lossless(order in any::<u8>(), state in any::<u8>()) {
        let data = [state];
        let fb = Feedback::decode(order, &data);
        let e = fb.execution.unwrap();
        prop_assert_eq!(e.value(), state);
        prop_assert_eq!(e.is_success(), state == 0);
        if Order::from_value(order).feedback_kind() == FeedbackKind::Cameras && state != 0 {
            prop_assert_eq!(e, Execution::FailedCameras(CameraSet(state)));
        }
    }

    /// Arbitrary bytes never panic the decoder, and what it accepts is a valid package.
    #[test]
    fn arbitrary_bytes_never_panic(b in proptest::collection::vec(any::<u8>(), 0..300)) {
        if let Ok(p) = Packet::decode(&b) {
            let sync = if b[0] == 0xA8 { HOST } else { GCU };
            prop_assert_eq!(valid(sync, &b), Some(p.buffer_len()));
        }
        let unchecked = Frame::new_unchecked(&b[..]);
        let _ = (unchecked.payload(), unchecked.checksum(), unchecked.direction());
        let _ = (unchecked.id(), unchecked.payload_len(), unchecked.main(), unchecked.sub());
    }

    /// Noisy host streams, cut at random points: exactly the reference scan's packages.
    #[test]
    fn host_deframer_recovers_intact_packages(
        pieces in proptest::collection::vec(piece(host_package()), 1..10),
        chunks in proptest::collection::vec(1usize..300, 1..8),
    ) {
        check_stream::<_, MAX_FRAME_LEN>(GcuFraming::host(), &pieces, &chunks, |b| valid(HOST, b))?;
    }

    /// Noisy GCU streams, likewise.
    #[test]
    fn gcu_deframer_recovers_intact_packages(
        pieces in proptest::collection::vec(piece(gcu_package()), 1..10),
        chunks in proptest::collection::vec(1usize..300, 1..8),
    ) {
        check_stream::<_, MAX_FRAME_LEN>(GcuFraming::gcu(), &pieces, &chunks, |b| valid(GCU, b))?;
    }

    /// A stream with both directions: each framing gives exactly its direction's
    /// reference scan, and every intact package of its direction.
    #[test]
    fn mixed_directions_are_separated(
        pieces in proptest::collection::vec(piece(prop_oneof![host_package(), gcu_package()]), 1..12),
        chunks in proptest::collection::vec(1usize..300, 1..8),
    ) {
        let (stream, intact, _) = build(&pieces);
        for (framing, sync) in [(GcuFraming::host(), HOST), (GcuFraming::gcu(), GCU)] {
            let got = deframe::<_, MAX_FRAME_LEN>(framing, &stream, &chunks);
            let reference = oracle(&stream, |b| valid(sync, b));
            prop_assert_eq!(&got, &reference);
            let mine: Vec<_> = intact.iter().filter(|f| f[..2] == sync).cloned().collect();
            if reference.iter().all(|f| mine.contains(f)) {
                prop_assert_eq!(&got, &mine, "an intact package was lost");
            }
        }
    }

    /// Any host package is answered with a GCU package that echoes its version and
    /// order, decodes as such, and carries the given frames.
    #[test]
    fn any_host_package_is_answered(f in host_package(), gcu_frames in proptest::collection::vec(any::<u8>(), 64)) {
        let request = HostPacket::decode(&f).unwrap();
        let frames = GcuPacket::decode(&package(GCU, 0, &gcu_frames, 0, &[0])).unwrap().frames;
        let reply = request.answer(frames, Execution::Success);
        let bytes = emit(&Packet::Gcu(reply));
        prop_assert_eq!(bytes.len(), 73);
        prop_assert_eq!(&bytes[..2], &GCU);
        prop_assert_eq!((bytes[4], bytes[69], bytes[70]), (f[4], f[69], 0x00));
        prop_assert_eq!(&bytes[5..37], &gcu_frames[..32]);
        let back = GcuPacket::decode(&bytes).unwrap();
        prop_assert_eq!(back, reply);
        if f[30] == SUB_HEADER {
            prop_assert_eq!(&bytes[37..69], &gcu_frames[32..]);
        } else {
            prop_assert_eq!(back.frames.sub, GcuSub::ABSENT);
        }
    }

    /// GPS time: Unix ms → (week, tow) → Unix ms is the identity from the GPS epoch on.
    #[test]
    fn gps_time_round_trips(ms in GPS_EPOCH_UNIX_MS..(1u64 << 44), leap in 0u8..40) {
        let g = GpsTime::from_unix_ms(ms, leap).unwrap();
        prop_assert!(u64::from(g.tow_ms) < WEEK_MS);
        prop_assert_eq!(g.to_unix_ms(leap), Some(ms));
    }
}

#[test]
fn corrupt_package_is_never_accepted_even_alone() {
    let f = package(
        HOST,
        1,
        &[0x11; 64],
        0x17,
        &[1, 1, 100, 0, 100, 0, 105, 0, 105, 0],
    );
    for bit in 0..f.len() * 8 {
        let pieces = [Piece::Corrupt(f.clone(), bit), Piece::Intact(f.clone())];
        let (stream, _, _) = build(&pieces);
        let got = deframe::<_, MAX_FRAME_LEN>(GcuFraming::host(), &stream, &[1]);
        assert_eq!(got, vec![f.clone()], "bit {bit}");
    }
}
