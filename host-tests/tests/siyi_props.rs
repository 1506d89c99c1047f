//! Property tests of the SIYI codec: lossless decoding of any data of every message in
//! both directions, exact length rules, and deframing of noisy streams.

use crate::common;

use codec_cases::oracle::xmodem_bitwise as xmodem;
use common::{Piece, check_stream, piece};
use proptest::prelude::*;
use protocol_core::siyi::*;
use protocol_core::wire::Writer;
use protocol_core::{Direction, Error};

/// A frame `55 66 CTRL LEN SEQ CMD DATA CRC`.
fn frame(ctrl: u8, seq: u16, cmd: u8, data: &[u8]) -> Vec<u8> {
    let mut f = vec![0x55, 0x66, ctrl];
    f.extend_from_slice(&(data.len() as u16).to_le_bytes());
    f.extend_from_slice(&seq.to_le_bytes());
    f.push(cmd);
    f.extend_from_slice(data);
    let crc = xmodem(&f);
    f.extend_from_slice(&crc.to_le_bytes());
    f
}

/// Is there a valid frame of at most `max` data bytes at the start of `b`?
/// (independent of the crate)
fn valid_with(b: &[u8], max: usize) -> Option<usize> {
    if b.len() < 10 || b[0] != 0x55 || b[1] != 0x66 {
        return None;
    }
    let len = usize::from(u16::from_le_bytes([b[3], b[4]]));
    if len > max || b.len() < len + 10 {
        return None;
    }
    let crc = u16::from_le_bytes([b[len + 8], b[len + 9]]);
    (xmodem(&b[..len + 8]) == crc).then_some(len + 10)
}

fn valid(b: &[u8]) -> Option<usize> {
    valid_with(b, 32)
}

/// Data lengths each id allows, request then reply, from the document and
/// siyi-commands.md (written here, not taken from the codec).
#[rustfmt::skip]
const LENGTHS: &[(u8, &[usize], &[usize])] = &[
    (0x00, &[0, 1], &[0]), (0x01, &[0], &[8, 12]), (0x02, &[0], &[12]), (0x04, &[5], &[1]),
    (0x05, &[1], &[2]), (0x06, &[1], &[1]), (0x07, &[2], &[1]), (0x08, &[1], &[1]),
    (0x0A, &[0], &[5, 6, 7, 8]), (0x0B, &[0], &[1]), (0x0C, &[1], &[0]), (0x0D, &[0], &[12]),
    (0x0E, &[4], &[6]), (0x0F, &[2], &[1]), (0x10, &[0], &[1]), (0x11, &[1], &[1]),
    (0x12, &[5], &[6]), (0x13, &[9], &[20]), (0x14, &[1], &[12]), (0x15, &[0], &[2]),
    (0x16, &[0], &[2]), (0x17, &[0], &[8]), (0x18, &[0], &[2]), (0x19, &[0], &[1]),
    (0x1A, &[0], &[1]), (0x1B, &[1], &[1]), (0x20, &[1], &[8, 9]), (0x21, &[9], &[2]),
    (0x22, &[28], &[0]), (0x24, &[2], &[1]), (0x25, &[2], &[1]), (0x26, &[0], &[6]),
    (0x30, &[8], &[1]), (0x31, &[0], &[1]), (0x32, &[1], &[1]), (0x33, &[0], &[1]),
    (0x34, &[1], &[1]), (0x35, &[0], &[1]), (0x37, &[0], &[1]), (0x38, &[1], &[1]),
    (0x39, &[0], &[10]), (0x3A, &[10], &[1]), (0x3B, &[0], &[1]), (0x3C, &[1], &[1]),
    (0x3E, &[32], &[0]), (0x41, &[3], &[6]), (0x48, &[0], &[1]), (0x80, &[2], &[2]),
];

/// Every (direction, id, allowed length).
fn known() -> Vec<(Direction, u8, usize)> {
    let mut v = Vec::new();
    for &(cmd, req, rep) in LENGTHS {
        v.extend(req.iter().map(|&n| (Direction::ToGimbal, cmd, n)));
        v.extend(rep.iter().map(|&n| (Direction::FromGimbal, cmd, n)));
    }
    v
}

fn known_message() -> impl Strategy<Value = (Direction, u8, Vec<u8>)> {
    proptest::sample::select(known()).prop_flat_map(|(dir, cmd, len)| {
        (
            Just(dir),
            Just(cmd),
            proptest::collection::vec(any::<u8>(), len),
        )
    })
}

fn ctrl_of(dir: Direction) -> u8 {
    match dir {
        Direction::ToGimbal => 1,
        Direction::FromGimbal => 2,
    }
}

/// Frames of known messages (random CTRL reserved bits and SEQ) and of any id with any
/// data up to 32 bytes.
fn any_frame() -> impl Strategy<Value = Vec<u8>> + Clone {
    prop_oneof![
        (known_message(), any::<u16>(), 0u8..64).prop_map(|((dir, cmd, d), seq, hi)| frame(
            ctrl_of(dir) | hi << 2,
            seq,
            cmd,
            &d
        )),
        (
            any::<u8>(),
            any::<u16>(),
            any::<u8>(),
            proptest::collection::vec(any::<u8>(), 0..=32)
        )
            .prop_map(|(ctrl, seq, cmd, d)| frame(ctrl, seq, cmd, &d)),
    ]
}

fn encoded(msg: &Message<'_>) -> Vec<u8> {
    let mut buf = [0u8; 64];
    let mut w = Writer::new(&mut buf);
    msg.encode(&mut w).unwrap();
    w.written().to_vec()
}

#[test]
fn the_length_table_matches_the_catalog() {
    assert_eq!(LENGTHS.len(), CATALOG.len());
    for (&(cmd, req, rep), e) in LENGTHS.iter().zip(CATALOG) {
        assert_eq!(cmd, e.id);
        assert_eq!(req == [0], e.request_empty, "{cmd:#04x}");
        assert_eq!(rep == [0], e.reply_empty, "{cmd:#04x}");
    }
}

#[test]
fn every_other_length_is_refused() {
    for &(cmd, req, rep) in LENGTHS {
        for (dir, ok) in [(Direction::ToGimbal, req), (Direction::FromGimbal, rep)] {
            for n in 0..=40 {
                let data = vec![0u8; n];
                let got = Message::decode(cmd, &data, dir);
                if ok.contains(&n) {
                    let m = got.unwrap();
                    assert_eq!(m.direction(), dir);
                    assert_eq!(m.payload_len(), n, "{cmd:#04x}");
                } else {
                    assert_eq!(got, Err(Error::BadLength), "{cmd:#04x} {dir:?} {n}");
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    /// Any data of a known message decodes to a typed message and re-encodes to the same
    /// bytes; decoding those again gives the same bytes (f32 NaNs make struct equality
    /// the wrong test).
    #[test]
    fn any_data_round_trips((dir, cmd, data) in known_message()) {
        let msg = Message::decode(cmd, &data, dir).unwrap();
        prop_assert!(!matches!(msg, Message::Raw(_)), "{cmd:#04x} decoded as Raw");
        prop_assert_eq!(msg.id(), cmd);
        prop_assert_eq!(msg.direction(), dir);
        prop_assert_eq!(msg.payload_len(), data.len());
        let bytes = encoded(&msg);
        prop_assert_eq!(&bytes, &data);
        let again = Message::decode(cmd, &bytes, dir).unwrap();
        prop_assert_eq!(encoded(&again), data);
    }

    /// The header is written as given, whatever the message's direction: any CTRL and
    /// SEQ around any known message give the frame built independently.
    #[test]
    fn any_header_is_emitted_as_given(
        (dir, cmd, data) in known_message(),
        ctrl in any::<u8>(),
        seq in any::<u16>(),
    ) {
        let message = Message::decode(cmd, &data, dir).unwrap();
        let p = Packet { header: Header::new(Ctrl(ctrl), seq), message };
        let mut out = [0u8; 64];
        let n = p.emit(&mut out).unwrap();
        prop_assert_eq!(&out[..n], &frame(ctrl, seq, cmd, &data)[..]);
    }

    /// The bridge's reply path: `encode` of a typed attitude with any header gives the
    /// frame built from the fields (little-endian i16s), and decodes back to it.
    #[test]
    fn typed_attitude_reply_encodes(
        angles in proptest::array::uniform6(any::<i16>()),
        ctrl in any::<u8>(),
        seq in any::<u16>(),
    ) {
        let [yaw, pitch, roll, yaw_rate, pitch_rate, roll_rate] = angles;
        let attitude = GimbalAttitude {
            yaw_deg_x10: yaw,
            pitch_deg_x10: pitch,
            roll_deg_x10: roll,
            yaw_rate_dps_x10: yaw_rate,
            pitch_rate_dps_x10: pitch_rate,
            roll_rate_dps_x10: roll_rate,
        };
        let header = Header::new(Ctrl(ctrl), seq);
        let mut out = [0u8; 64];
        let n = encode(&attitude, &header, &mut out).unwrap();
        let data: Vec<u8> = angles.iter().flat_map(|a| a.to_le_bytes()).collect();
        prop_assert_eq!(&out[..n], &frame(ctrl, seq, 0x0D, &data)[..]);
        let p = Packet::decode(&out[..n], Direction::FromGimbal).unwrap();
        prop_assert_eq!(p.header, header);
        prop_assert_eq!(p.message.get::<GimbalAttitude>(), Some(attitude));
        prop_assert_eq!(p.message.get::<GimbalAttitudeQuery>(), None);
    }

    /// Whole frames: decode (with the direction of the CTRL flag, falling back to the
    /// other) then emit gives the frame back, for known and unknown ids.
    #[test]
    fn any_frame_round_trips(f in any_frame()) {
        match Packet::decode_auto(&f) {
            Ok(p) => {
                let mut out = [0u8; 64];
                let n = p.emit(&mut out).unwrap();
                prop_assert_eq!(&out[..n], &f[..]);
                prop_assert_eq!(p.buffer_len(), f.len());
            }
            // A known id with random data of a length neither direction allows.
            Err(e) => {
                prop_assert_eq!(e, Error::BadLength);
                prop_assert!(CATALOG.iter().any(|c| c.id == f[7]));
            }
        }
    }

    /// Arbitrary bytes never panic the decoders, and what they accept is a valid frame.
    #[test]
    fn arbitrary_bytes_never_panic(b in proptest::collection::vec(any::<u8>(), 0..80)) {
        let accepted = [
            Packet::decode(&b, Direction::ToGimbal),
            Packet::decode(&b, Direction::FromGimbal),
            Packet::decode_auto(&b),
        ];
        for p in accepted.into_iter().flatten() {
            prop_assert!(valid_with(&b, usize::MAX).is_some());
            prop_assert!(p.buffer_len() <= b.len());
        }
    }

    /// Noisy streams, cut at random points: exactly the reference scan's frames come out.
    #[test]
    fn deframer_recovers_intact_frames(
        pieces in proptest::collection::vec(piece(any_frame()), 1..12),
        chunks in proptest::collection::vec(1usize..100, 1..8),
    ) {
        check_stream::<_, DEFAULT_MAX_FRAME_LEN>(SiyiFraming::default(), &pieces, &chunks, valid)?;
    }

    /// The same with a larger configured data limit and long frames.
    #[test]
    fn deframer_with_a_larger_limit(
        pieces in proptest::collection::vec(piece(
            (any::<u8>(), any::<u8>(), proptest::collection::vec(any::<u8>(), 0..=200))
                .prop_map(|(ctrl, cmd, d)| frame(ctrl, 0x0102, cmd, &d))
        ), 1..8),
        chunks in proptest::collection::vec(1usize..300, 1..8),
    ) {
        check_stream::<_, 210>(SiyiFraming::new(200), &pieces, &chunks, |b| valid_with(b, 200))?;
    }
}

#[test]
fn corrupt_piece_is_never_accepted_even_alone() {
    let f = frame(0x01, 0x10, 0x0F, &[4, 5]);
    for bit in 0..f.len() * 8 {
        let pieces = [Piece::Corrupt(f.clone(), bit), Piece::Intact(f.clone())];
        let (stream, _, _) = common::build(&pieces);
        let got =
            common::deframe::<_, DEFAULT_MAX_FRAME_LEN>(SiyiFraming::default(), &stream, &[1]);
        assert_eq!(got, vec![f.clone()], "bit {bit}");
    }
}
