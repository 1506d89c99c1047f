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
pub use cursor::{Reader, Writer};
pub use deframer::{Deframer, Event, Framing, Scanned, Scanner, Stats};
