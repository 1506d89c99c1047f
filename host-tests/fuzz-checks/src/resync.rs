//! The resynchronisation differential: a valid frame built by the encoder, embedded in
//! garbage the fuzzer chooses, must come out of the deframer, unless the garbage holds a
//! valid frame of its own that overlaps it (then the reference scan takes that one too,
//! and the deframer must agree with the reference scan).

use protocol_core::Direction;
use protocol_core::gcu::{self, GcuFraming};
use protocol_core::k40t;
use protocol_core::siyi::{self, SiyiFraming};
use protocol_core::viewlink::{self, SyncOrder, ViewlinkFraming, tcp};
use protocol_core::wire::Framing;

use crate::deframe::{self, Spec};
use crate::input::{Input, Plan};

/// Which framing a resync input uses (its first byte, modulo the count).
const FRAMINGS: u8 = 8;

/// Target `resync`. Input: the framing (byte 0, modulo the count), five bytes the
/// protocol's builder uses to choose the message and header (framing variant,
/// message, header fields), a chunk plan, the lengths of the garbage before and after
/// the frame (one byte each), the garbage before, the garbage after, and the rest: the
/// payload bytes of the frame.
pub fn resync(data: &[u8]) {
    let mut input = Input::new(data);
    let mut choice = [0u8; 6];
    for c in &mut choice {
        *c = input.byte();
    }
    let (_, plan) = Plan::read(&mut input);
    let before_len = usize::from(input.byte());
    let after_len = usize::from(input.byte());
    let garbage = Garbage {
        before: input.bytes(before_len),
        after: input.bytes(after_len),
        plan,
    };
    let fill = input.rest();
    match choice[0] % FRAMINGS {
        0 => {
            // Byte 4: the framing's coverage, and the frame's where the framing takes
            // either.
            let framing = crate::k40t::framing(choice[4]);
            let coverage = framing.coverage.unwrap_or(if choice[4] & 0x80 == 0 {
                k40t::CrcCoverage::ExcludeStx
            } else {
                k40t::CrcCoverage::IncludeStx
            });
            let frame = crate::k40t::resync_frame(choice, fill, coverage);
            let valid = |b: &[u8]| crate::k40t::valid(b, framing.coverage, k40t::MAX_FRAME_LEN);
            let checked = move |f: &[u8]| crate::k40t::checked(framing, f);
            embed::<_, { k40t::MAX_FRAME_LEN }>(&framing, &frame, &garbage, &valid, &checked);
        }
        1 => {
            let framing = SiyiFraming::default();
            let frame = crate::siyi::resync_frame(choice, fill);
            let valid = |b: &[u8]| crate::siyi::valid(b, siyi::DEFAULT_MAX_PAYLOAD_LEN);
            let checked = move |f: &[u8]| crate::siyi::checked(framing, f);
            embed::<_, { siyi::DEFAULT_MAX_FRAME_LEN }>(
                &framing, &frame, &garbage, &valid, &checked,
            );
        }
        n @ (2 | 3) => {
            let framing = if n == 2 {
                ViewlinkFraming::new()
            } else {
                ViewlinkFraming::swapped()
            };
            let frame = crate::viewlink::resync_frame(choice, fill, framing.sync);
            let valid = |b: &[u8]| crate::viewlink::valid(b, framing.sync.bytes());
            let checked = move |f: &[u8]| crate::viewlink::checked(framing, f);
            embed::<_, { viewlink::MAX_FRAME_LEN }>(&framing, &frame, &garbage, &valid, &checked);
        }
        4 => {
            // A serial frame inside an envelope.
            let serial = crate::viewlink::resync_frame(choice, fill, SyncOrder::Standard);
            let frame = crate::viewlink::envelope(&serial);
            embed::<_, { tcp::MAX_FRAME_LEN }>(
                &tcp::TcpFraming,
                &frame,
                &garbage,
                &crate::viewlink::tcp_valid,
                &crate::viewlink::tcp_checked,
            );
        }
        n => {
            let direction = if n == 5 {
                Direction::ToGimbal
            } else {
                Direction::FromGimbal
            };
            let framing = GcuFraming::new(direction);
            let frame = crate::gcu::resync_frame(choice, fill, direction);
            let sync = gcu::sync_of(direction);
            let valid = |b: &[u8]| crate::gcu::valid(b, sync);
            let checked = move |f: &[u8]| crate::gcu::checked(framing, f);
            embed::<_, { gcu::MAX_FRAME_LEN }>(&framing, &frame, &garbage, &valid, &checked);
        }
    }
}

/// What surrounds the frame, and how the stream is cut.
struct Garbage<'a> {
    before: &'a [u8],
    after: &'a [u8],
    plan: Plan,
}

/// Embeds `frame` between the garbage, deframes the stream, and checks that the frame
/// comes out unless a valid frame of the garbage overlaps it.
fn embed<F: Framing + Clone, const N: usize>(
    framing: &F,
    frame: &[u8],
    garbage: &Garbage<'_>,
    valid: &dyn Fn(&[u8]) -> Option<usize>,
    checked: &dyn Fn(&[u8]),
) {
    assert_eq!(
        valid(frame),
        Some(frame.len()),
        "the encoder built an invalid frame"
    );
    checked(frame);
    let at = garbage.before.len();
    let stream = [garbage.before, frame, garbage.after].concat();
    let spec = Spec {
        valid,
        skipped: &|_| None,
        checked,
        compare_scanner: true,
    };
    deframe::check::<F, N>(framing, &stream, &garbage.plan, &spec);

    let located = deframe::run_feed_poll::<F, N>(framing.clone(), &stream, &garbage.plan);
    let frames: Vec<(usize, &[u8])> = located
        .iter()
        .filter_map(|(o, e)| e.frame().map(|f| (*o, f)))
        .collect();
    let overlapped = frames
        .iter()
        .any(|&(o, f)| o != at && o < at + frame.len() && at < o + f.len());
    if !overlapped {
        assert!(
            frames.contains(&(at, frame)),
            "the embedded frame at {at} was lost ({} frames out)",
            frames.len()
        );
    }
}

/// Seeds: for each framing, a few catalogue messages between short garbage holding
/// other protocols' sync bytes.
#[must_use]
pub fn seeds() -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    for framing in 0..FRAMINGS {
        for pick in [0u8, 7, 23] {
            let mut s = vec![framing, pick, 0, 2, 1, 0];
            s.extend(Plan::encode(0, &[7, 63]));
            let before = [0xFD, 0x55, 0x66, 0xAA, 0x55, 0xDC, 0xEB, 0x90, 0xA8, 0xE5];
            let after = [0x8A, 0x5E, 0x48, 0x00, 0xFD, 0x05];
            s.extend([before.len() as u8, after.len() as u8]);
            s.extend(before);
            s.extend(after);
            s.extend((0..64u8).map(|i| i.wrapping_mul(37)));
            out.push(s);
        }
    }
    out
}
