//! `protocol_core::wire`: checksums, cursors, and (generic over the framing) every
//! entry point of the deframer and the capture scanner.

use core::hint::black_box;
use protocol_core::wire::{
    Deframer, Event, Framing, MCRF4XX, Reader, Scanner, Writer, XMODEM, crc16_mcrf4xx,
    crc16_xmodem, sum8, xor8,
};

/// Every deframer and scanner entry point, for one framing and buffer size.
pub fn deframe<F: Framing + Copy, const N: usize>(framing: F, input: &[u8]) {
    let mut d = Deframer::<F, N>::new(black_box(framing));
    let sink = |e: Event<'_>| {
        black_box(e);
    };
    d.push(input, sink);
    black_box(d.feed(input));
    while let Some(e) = d.poll() {
        black_box(e);
    }
    let spare = d.spare_capacity_mut();
    let n = spare.len().min(input.len());
    // (Not `copy_from_slice`: it keeps a panicking length check at opt-level z.)
    for (d, s) in spare.iter_mut().zip(input) {
        *d = *s;
    }
    d.commit(black_box(n));
    while let Some(e) = d.poll_idle() {
        black_box(e);
    }
    d.push(input, sink);
    d.flush(sink);
    black_box((d.stats(), d.buffered(), d.framing()));
    black_box(d.framing_mut());
    d.clear();
    black_box(&d);
    for item in Scanner::new(black_box(framing), input) {
        black_box(item);
    }
}

pub fn exercise(input: &[u8], out: &mut [u8]) {
    black_box((
        crc16_mcrf4xx(input),
        crc16_xmodem(input),
        xor8(input),
        sum8(input),
    ));
    black_box((MCRF4XX.checksum(input), XMODEM.checksum(input)));

    let n = black_box(0usize);
    let mut r = Reader::new(input);
    black_box((
        r.remaining(),
        r.is_empty(),
        r.take(n),
        r.skip(n),
        r.array::<7>(),
    ));
    black_box((
        r.u8(),
        r.i8(),
        r.u16_le(),
        r.u16_be(),
        r.i16_le(),
        r.i16_be(),
    ));
    black_box((
        r.u32_le(),
        r.u32_be(),
        r.i32_le(),
        r.i32_be(),
        r.u64_le(),
        r.u64_be(),
    ));
    black_box((
        r.i64_le(),
        r.i64_be(),
        r.f32_le(),
        r.f32_be(),
        r.u24_le(),
        r.u24_be(),
    ));
    black_box((r.clone().rest(), r.finish()));

    let v = black_box(0x0123_4567_89AB_CDEFu64);
    let mut w = Writer::new(out);
    black_box((
        w.put(input),
        w.zeros(n),
        w.set_u8(n, v as u8),
        w.len(),
        w.is_empty(),
    ));
    black_box((
        w.u8(v as u8),
        w.i8(v as i8),
        w.u16_le(v as u16),
        w.u16_be(v as u16),
    ));
    black_box((
        w.i16_le(v as i16),
        w.i16_be(v as i16),
        w.u32_le(v as u32),
        w.u32_be(v as u32),
    ));
    black_box((
        w.i32_le(v as i32),
        w.i32_be(v as i32),
        w.u64_le(v),
        w.u64_be(v),
    ));
    black_box((
        w.i64_le(v as i64),
        w.i64_be(v as i64),
        w.f32_le(v as f32),
        w.f32_be(v as f32),
    ));
    black_box((w.u24_le(v as u32), w.u24_be(v as u32), w.written().len()));
    black_box(w.finish());
}
