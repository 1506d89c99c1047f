//! Codec machinery shared by the four protocols: bounds-checked cursors, checksums and
//! the streaming deframer.

mod checksum;
mod cursor;
mod deframer;
#[cfg(any(
    feature = "k40t",
    feature = "siyi",
    feature = "viewlink",
    feature = "gcu"
))]
pub mod encoding;

pub use checksum::{MCRF4XX, XMODEM, crc16_mcrf4xx, crc16_xmodem, sum8, xor8};

/// Copies `src` into `dst` (slices of equal length; with unequal ones, the shorter
/// length), like `dst.copy_from_slice(src)` without its panicking path: at opt-level z
/// `copy_from_slice` stays out of line with its length check, and the link-time
/// no-panic check (`host-tests/no-panic`) would fail. LLVM still makes the loop a
/// `memcpy`.
#[inline]
pub(crate) fn copy<T: Copy>(dst: &mut [T], src: &[T]) {
    for (d, s) in dst.iter_mut().zip(src) {
        *d = *s;
    }
}
pub use cursor::{Reader, Writer};
pub use deframer::{Deframer, Event, Framing, Scanned, Scanner, Stats};
