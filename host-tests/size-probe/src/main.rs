//! Code-size probe: a minimal thumbv7em binary that feeds opaque bytes through each
//! enabled protocol's deframer, decodes every message and encodes it again. Built once
//! per feature set by `scripts/size-report`; the difference to the build without any
//! protocol is that protocol's code size. With `bridge`, the engine is driven too: the
//! difference to the same codecs without it is the engine's code size.
#![no_std]
#![no_main]

use core::hint::black_box;
use panic_halt as _;

#[cfg(feature = "bridge")]
mod bridge;
#[cfg(feature = "gcu")]
mod gcu;
#[cfg(feature = "k40t")]
mod k40t;
#[cfg(feature = "mavlink")]
mod mavlink;
#[cfg(feature = "siyi")]
mod siyi;
#[cfg(feature = "viewlink")]
mod viewlink;

/// Bytes the optimiser cannot see through.
static INPUT: [u8; 512] = [0; 512];

#[cortex_m_rt::entry]
fn main() -> ! {
    let mut out = [0u8; 512];
    loop {
        let input: &[u8] = black_box(&INPUT[..]);
        #[cfg(feature = "k40t")]
        black_box(k40t::probe(input, &mut out));
        #[cfg(feature = "siyi")]
        black_box(siyi::probe(input, &mut out));
        #[cfg(feature = "viewlink")]
        black_box(viewlink::probe(input, &mut out));
        #[cfg(feature = "gcu")]
        black_box(gcu::probe(input, &mut out));
        #[cfg(feature = "mavlink")]
        black_box(mavlink::probe(input, &mut out));
        #[cfg(feature = "bridge")]
        bridge::probe(input, &mut out);
        black_box((input, &mut out));
    }
}
