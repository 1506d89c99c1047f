//! Proof at link time that protocol-core and bridge-engine cannot panic: this thumbv7em binary calls every
//! public decode, parse, emit, encode and deframe entry point of the codecs (MAVLink included) (and
//! the shared `wire` module), and every entry point of the bridge engine, with inputs the optimiser cannot see through
//! (`core::hint::black_box`), and its panic handler calls a function that exists
//! nowhere. Built in release (the firmware's profile: opt-level z, fat LTO), it links
//! only if every panicking branch (a slice index, an `unwrap`, a division, a failed
//! `copy_from_slice` length check...) was proven unreachable and removed. If one
//! survives, the link fails with an undefined reference to
//! `a_panicking_branch_survived_optimisation_see_host_tests_no_panic`; `scripts/no-panic`
//! then shows which function calls the panic.
//!
//! Covered entry points: docs/src/verification/no-panic.md.
#![no_std]
#![no_main]
// Results go to `black_box`, which keeps them (and the code computing them) alive.
#![allow(unused_must_use)]

mod bridge;
mod config;
mod constructors;
mod gcu;
mod k40t;
mod mavlink;
mod siyi;
mod viewlink;
mod wire;

use core::hint::black_box;

/// Bytes the optimiser cannot see through: any content, any length.
static INPUT: [u8; 1024] = [0; 1024];

/// Opaque input bytes.
fn input() -> &'static [u8] {
    black_box(&INPUT[..])
}

#[cortex_m_rt::entry]
fn main() -> ! {
    let mut out = [0u8; 512];
    loop {
        let out: &mut [u8] = black_box(&mut out[..]);
        wire::exercise(input(), out);
        k40t::exercise(input(), out);
        siyi::exercise(input(), out);
        viewlink::exercise(input(), out);
        gcu::exercise(input(), out);
        mavlink::exercise(input(), out);
        constructors::exercise(input(), out);
        bridge::exercise(input(), out);
        config::exercise(input(), out);
    }
}

#[cfg(not(feature = "report"))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    unsafe extern "Rust" {
        /// Defined nowhere: referencing it makes the link fail.
        fn a_panicking_branch_survived_optimisation_see_host_tests_no_panic() -> !;
    }
    // SAFETY: never executed: the binary links only when no call to the panic handler
    // is left, and then this reference is gone too.
    unsafe { a_panicking_branch_survived_optimisation_see_host_tests_no_panic() }
}

/// With the `report` feature the binary links whatever survives, so that
/// `scripts/no-panic` can list the functions that still call into `core::panicking`.
#[cfg(feature = "report")]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    loop {}
}
