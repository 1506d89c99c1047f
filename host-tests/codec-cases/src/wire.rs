//! Shared machinery cases: checksums and cursors (run on Cortex-M too, where the CRC
//! tables and integer handling are the target's own code).

use crate::Outcome;
use protocol_core::Error;
use protocol_core::wire::{Reader, Writer, crc16_mcrf4xx, crc16_xmodem, sum8, xor8};

fn checksum_check_values() -> Outcome {
    ensure_eq!(crc16_mcrf4xx(b"123456789"), 0x6F91);
    ensure_eq!(crc16_xmodem(b"123456789"), 0x31C3);
    ensure_eq!(crc16_mcrf4xx(&[]), 0xFFFF);
    ensure_eq!(crc16_xmodem(&[]), 0x0000);
    ensure_eq!(xor8(&[0x0F, 0xF0, 0x01]), 0xFE);
    ensure_eq!(sum8(&[0x80, 0x80, 0x01]), 0x01);
    Ok(())
}

fn cursors_round_trip_every_width() -> Outcome {
    let mut buf = [0u8; 64];
    let mut w = Writer::new(&mut buf);
    check!(w.u8(0xFE));
    check!(w.i8(-2));
    check!(w.u16_le(0x1234));
    check!(w.u16_be(0x1234));
    check!(w.i16_le(-300));
    check!(w.i16_be(-300));
    check!(w.u24_le(0x00AB_CDEF));
    check!(w.u24_be(0x00AB_CDEF));
    check!(w.u32_le(0xDEAD_BEEF));
    check!(w.i32_be(-123_456_789));
    check!(w.u64_le(0x0102_0304_0506_0708));
    check!(w.i64_be(-1_767_225_600_000));
    check!(w.f32_le(1.5));
    let n = w.finish();
    ensure_eq!(n, 1 + 1 + 2 + 2 + 2 + 2 + 3 + 3 + 4 + 4 + 8 + 8 + 4);
    ensure_eq!(&buf[2..6], &[0x34, 0x12, 0x12, 0x34]);
    ensure_eq!(&buf[10..16], &[0xEF, 0xCD, 0xAB, 0xAB, 0xCD, 0xEF]);
    let mut r = Reader::new(&buf[..n]);
    ensure_eq!(check!(r.u8()), 0xFE);
    ensure_eq!(check!(r.i8()), -2);
    ensure_eq!(check!(r.u16_le()), 0x1234);
    ensure_eq!(check!(r.u16_be()), 0x1234);
    ensure_eq!(check!(r.i16_le()), -300);
    ensure_eq!(check!(r.i16_be()), -300);
    ensure_eq!(check!(r.u24_le()), 0x00AB_CDEF);
    ensure_eq!(check!(r.u24_be()), 0x00AB_CDEF);
    ensure_eq!(check!(r.u32_le()), 0xDEAD_BEEF);
    ensure_eq!(check!(r.i32_be()), -123_456_789);
    ensure_eq!(check!(r.u64_le()), 0x0102_0304_0506_0708);
    ensure_eq!(check!(r.i64_be()), -1_767_225_600_000);
    ensure_eq!(check!(r.f32_le()), 1.5);
    ensure!(r.finish().is_ok());
    Ok(())
}

fn cursors_refuse_overruns() -> Outcome {
    let mut r = Reader::new(&[1, 2, 3]);
    ensure_eq!(r.u32_le(), Err(Error::Truncated));
    ensure_eq!(r.take(4), Err(Error::Truncated));
    ensure_eq!(check!(r.u16_be()), 0x0102);
    ensure_eq!(r.clone().finish(), Err(Error::BadLength));
    ensure_eq!(r.rest(), &[3]);
    let mut buf = [0u8; 3];
    let mut w = Writer::new(&mut buf);
    ensure_eq!(w.u32_le(1), Err(Error::BufferTooSmall));
    ensure_eq!(w.u24_be(0x0100_0000), Err(Error::OutOfRange));
    ensure!(w.is_empty());
    Ok(())
}

cases!("wire": checksum_check_values, cursors_round_trip_every_width, cursors_refuse_overruns);
