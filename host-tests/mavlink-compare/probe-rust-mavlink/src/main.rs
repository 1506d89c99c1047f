//! rust-mavlink 0.21: its own frame reader (`MavlinkReader` over a byte slice), its
//! parser into the generated `MavMessage`, and its own raw-frame encoder
//! (`MAVLinkV2MessageRaw::serialize_message`), over every message of the bridge's set.
#![no_std]
#![no_main]

use core::hint::black_box;
use gimbal_mavlink_dialect::MavMessage;
use mavlink_core::{MAVLinkV2MessageRaw, MavlinkReader, MavlinkVersion};

static INPUT: [u8; 1024] = [0; 1024];

fn probe(input: &[u8], out: &mut [u8]) -> usize {
    let mut reader = MavlinkReader::new(input);
    let mut n = 0;
    while let Ok((header, msg)) = reader.read_message::<MavMessage>(MavlinkVersion::V2) {
        let mut raw = MAVLinkV2MessageRaw::new();
        raw.serialize_message(header, &msg);
        for (d, s) in out.iter_mut().zip(raw.raw_bytes()) {
            *d = *s;
        }
        n += raw.raw_bytes().len();
    }
    n
}

#[cortex_m_rt::entry]
fn main() -> ! {
    let mut out = [0u8; 512];
    loop {
        let input: &[u8] = black_box(&INPUT[..]);
        black_box(probe(input, black_box(&mut out[..])));
    }
}

#[cfg(feature = "nopanic")]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    unsafe extern "Rust" {
        fn a_panicking_branch_survived_optimisation() -> !;
    }
    // SAFETY: never executed: the binary links only if no call to the handler is left.
    unsafe { a_panicking_branch_survived_optimisation() }
}

#[cfg(not(feature = "nopanic"))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    loop {}
}
