//! SIYI: decoding arbitrary bytes in both directions (and with the direction guessed)
//! re-encodes exactly, with the bytes as received and with their CRC filled in; the
//! deframer with the default and a long payload limit.

use codec_cases::oracle::xmodem_bitwise;
use protocol_core::Direction;
use protocol_core::siyi::{
    CATALOG, DEFAULT_MAX_PAYLOAD_LEN, Frame, Header, Message, Packet, SiyiFraming,
};
use std::hint::black_box;

use crate::deframe::{self, Spec};
use crate::input::{Input, Plan};
use crate::is_frame_error;

const DIRECTIONS: [Direction; 2] = [Direction::ToGimbal, Direction::FromGimbal];

/// Target `siyi_decode`.
pub fn decode(data: &[u8]) {
    for direction in DIRECTIONS {
        if let Ok(p) = Packet::decode(data, direction) {
            assert_eq!(p.message.direction(), direction);
            round_trip(data, &p, Some(direction));
        }
    }
    if let Ok(p) = Packet::decode_auto(data) {
        round_trip(data, &p, None);
    }
    if let Ok(frame) = Frame::new_checked(data) {
        let mut fixed = data[..frame.total_len()].to_vec();
        Frame::new_unchecked(&mut fixed[..]).fill_checksum();
        for direction in DIRECTIONS {
            // `parse` does not verify the CRC: it must agree with decoding the fixed frame.
            let parsed = Packet::parse(&frame, direction);
            let decoded = Packet::decode(&fixed, direction);
            assert_eq!(
                parsed.map(|p| encoded_bytes(&p)),
                decoded.map(|p| encoded_bytes(&p)),
                "parse and decode disagree"
            );
            match decoded {
                Ok(p) => round_trip(&fixed, &p, Some(direction)),
                Err(e) => assert!(!is_frame_error(e), "{e:?} for a frame with a valid CRC"),
            }
        }
        match Packet::decode_auto(&fixed) {
            Ok(p) => round_trip(&fixed, &p, None),
            Err(e) => assert!(!is_frame_error(e), "{e:?} for a frame with a valid CRC"),
        }
    }
    let f = Frame::new_unchecked(data);
    let _ = black_box((
        f.check_len(),
        f.ctrl(),
        f.payload_len(),
        f.total_len(),
        f.seq(),
    ));
    let _ = black_box((f.id(), f.payload(), f.payload_ref(), f.checksum()));
    let _ = black_box((f.compute_checksum(), f.verify(), f.ctrl().direction()));
}

/// Re-encodes `p`, decoded from `data` in `direction` (`None`: guessed).
fn round_trip(data: &[u8], p: &Packet<'_>, direction: Option<Direction>) {
    let n = p.buffer_len();
    let mut out = vec![0u8; n];
    assert_eq!(p.emit(&mut out), Ok(n), "a decoded packet re-encodes");
    assert_eq!(&out[..], &data[..n], "re-encoding differs");
    let again = match direction {
        Some(d) => Packet::decode(&out, d),
        None => Packet::decode_auto(&out),
    };
    // (Compared through their bytes: a float field may be NaN.)
    assert_eq!(again.map(|p| encoded_bytes(&p)), Ok(out));
    crate::exact_buffers(n, |buf| p.emit(buf));
}

/// A packet's encoding (to compare packets whose float fields may be NaN).
fn encoded_bytes(p: &Packet<'_>) -> Vec<u8> {
    let mut out = vec![0u8; p.buffer_len()];
    let n = p.emit(&mut out).expect("a decoded packet re-encodes");
    out.truncate(n);
    out
}

/// The frame at the start of `b`, if valid with at most `max` payload bytes; written
/// from the document, without the codec.
#[must_use]
pub fn valid(b: &[u8], max: usize) -> Option<usize> {
    if b.len() < 5 || b[..2] != [0x55, 0x66] {
        return None;
    }
    let len = usize::from(u16::from_le_bytes([b[3], b[4]]));
    if len > max || b.len() < len + 10 {
        return None;
    }
    let crc = u16::from_le_bytes([b[len + 8], b[len + 9]]);
    (xmodem_bitwise(&b[..len + 8]) == crc).then_some(len + 10)
}

/// The checked parse every delivered frame must pass.
pub fn checked(framing: SiyiFraming, f: &[u8]) {
    let frame = Frame::new_checked(f).expect("a delivered frame passes new_checked");
    assert_eq!(frame.total_len(), f.len());
    assert!(frame.payload_len() <= framing.max_payload_len);
    frame.verify().expect("a delivered frame has a valid CRC");
    for direction in DIRECTIONS {
        if let Err(e) = Packet::decode(f, direction) {
            assert!(!is_frame_error(e), "{e:?} for a delivered frame");
        }
    }
    if let Err(e) = Packet::decode_auto(f) {
        assert!(!is_frame_error(e), "{e:?} for a delivered frame");
    }
}

/// Target `siyi_deframe`: selector bit 0 raises the payload limit from 32 to 255 bytes.
pub fn deframe(data: &[u8]) {
    const LONG: usize = 255;
    let mut input = Input::new(data);
    let (selector, plan) = Plan::read(&mut input);
    if selector & 1 == 0 {
        let framing = SiyiFraming::default();
        let valid = |b: &[u8]| valid(b, DEFAULT_MAX_PAYLOAD_LEN);
        let checked = move |f: &[u8]| checked(framing, f);
        let spec = Spec {
            valid: &valid,
            skipped: &|_| None,
            checked: &checked,
            compare_scanner: true,
        };
        deframe::check::<_, { DEFAULT_MAX_PAYLOAD_LEN + 10 }>(&framing, input.rest(), &plan, &spec);
    } else {
        let framing = SiyiFraming::new(LONG);
        let valid = |b: &[u8]| valid(b, LONG);
        let checked = move |f: &[u8]| checked(framing, f);
        let spec = Spec {
            valid: &valid,
            skipped: &|_| None,
            checked: &checked,
            compare_scanner: true,
        };
        deframe::check::<_, { LONG + 10 }>(&framing, input.rest(), &plan, &spec);
    }
}

/// The shortest payload (a prefix of `fill`) command `id` accepts in `direction`, as a
/// frame built by the encoder; `None` when no prefix decodes.
#[must_use]
pub fn encoded(id: u8, direction: Direction, fill: &[u8], header: Header) -> Option<Vec<u8>> {
    let mut padded = fill.to_vec();
    padded.resize(DEFAULT_MAX_PAYLOAD_LEN, 0);
    let message = (0..=DEFAULT_MAX_PAYLOAD_LEN)
        .find_map(|len| Message::decode(id, &padded[..len], direction).ok())?;
    let p = Packet { header, message };
    let mut buf = vec![0u8; p.buffer_len()];
    let n = p.emit(&mut buf).expect("encode a catalogue message");
    buf.truncate(n);
    Some(buf)
}

/// The header a sender of `direction` uses.
#[must_use]
pub fn header(direction: Direction, seq: u16) -> Header {
    match direction {
        Direction::ToGimbal => Header::request(seq),
        Direction::FromGimbal => Header::reply(seq),
    }
}

/// The SIYI frame of the resync target: `choice` picks the command and direction
/// (bytes 1..2), CTRL (byte 3) and the sequence number (bytes 4..5); the payload is the
/// shortest prefix of `fill` the command accepts.
pub(crate) fn resync_frame(choice: [u8; 6], fill: &[u8]) -> Vec<u8> {
    let pick = usize::from(u16::from_le_bytes([choice[1], choice[2]]));
    let entry = &CATALOG[pick / 2 % CATALOG.len()];
    let direction = DIRECTIONS[pick % 2];
    let header = Header::new(
        protocol_core::siyi::Ctrl(choice[3]),
        u16::from_le_bytes([choice[4], choice[5]]),
    );
    encoded(entry.id, direction, fill, header)
        .or_else(|| encoded(entry.id, direction, &[], header))
        .expect("every catalogue command has a layout in each direction")
}

/// Every command of the catalogue in both directions, built by the encoder (seeds).
#[must_use]
pub fn catalogue_frames(fill: &[u8]) -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    for (i, e) in CATALOG.iter().enumerate() {
        for direction in DIRECTIONS {
            if let Some(f) = encoded(e.id, direction, fill, header(direction, i as u16)) {
                out.push(f);
            }
        }
    }
    out
}
