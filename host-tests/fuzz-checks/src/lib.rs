//! The properties the fuzz targets check, written once for three runners: the
//! cargo-fuzz targets (`fuzz/`, nightly, libFuzzer), the replay of their seeds and of
//! every crash found so far as native tests (`host-tests/tests/fuzz_replay.rs`,
//! stable), and the seed generator (`fuzz-seeds`).
//!
//! Each target is a function of the fuzzer's bytes that panics when a property fails;
//! [`TARGETS`] lists them. The properties:
//! - **decode** (`*_decode`, `viewlink_tcp` even first byte): whatever decodes re-encodes
//!   byte for byte (K40T: a short payload comes back zero-extended), decodes again to
//!   the same value, and encodes into a buffer of exactly its length but not one byte
//!   less. The same bytes with their checksum filled in never fail on the frame level
//!   (only on the content), and `parse` (which does not verify) agrees with `decode`.
//! - **deframe** (`*_deframe`, `viewlink_tcp` odd first byte): the fuzzer also chooses
//!   the chunk sizes ([`input::Plan`]). The events are the same whatever the chunking
//!   and whichever way the bytes go in, the same as the capture scanner's, and the
//!   frames the same as an independent reference scan's (written from the documents,
//!   with the test oracle's CRCs); every frame passes the protocol's checked parse; the
//!   counters add up.
//! - **resync**: a frame built by the encoder, between garbage the fuzzer chooses, comes
//!   out unless a valid frame of the garbage overlaps it.
//!
//! - **bridge**: the bridge engine fed arbitrary FC and pod bytes and times, for each FC
//!   protocol: no panic, the queues within their bounds, every output frame valid, a
//!   valid FC request answered (see [`bridge`]); **bridge_mavlink** the same with the
//!   MAVLink side (see [`bridge_mavlink`]); **bridge_signed** the MAVLink side signing,
//!   its FC frames signed with the key, another key, stale, SETUP_SIGNING
//!   ([`bridge_mavlink::run_signed`]); **bridge_k40t_allow** the K40T side with an
//!   allow-list of the pod's destructive requests the fuzzer picks
//!   ([`bridge::run_k40t_allow`]); **bridge_forged** the MAVLink side requiring signing,
//!   everything that changes something only unsigned, forged, replayed or from a system
//!   that may not command: none of it reaches the pod ([`bridge_mavlink::run_forged`]).
//!   Every bridge target checks that no frame of a destructive request the configuration
//!   does not allow reaches the pod, whatever its kind.
//! - **console**: the engine's console fed arbitrary bytes: the signing key never leaves
//!   through it, both configurations stay valid, and what it keeps restores to what was
//!   set (see [`console`]).

pub mod bridge;
pub mod bridge_mavlink;
pub mod console;
pub mod deframe;
pub mod gcu;
pub mod input;
pub mod k40t;
pub mod mavlink;
pub mod resync;
pub mod seeds;
pub mod siyi;
pub mod viewlink;

use protocol_core::Error;

/// One fuzz target: its name (the cargo-fuzz target's) and its check.
#[derive(Clone, Copy)]
pub struct Target {
    /// The target's name.
    pub name: &'static str,
    /// Runs the checks on one input; panics when a property fails.
    pub run: fn(&[u8]),
}

/// Every target.
pub const TARGETS: &[Target] = &[
    Target {
        name: "k40t_decode",
        run: k40t::decode,
    },
    Target {
        name: "k40t_deframe",
        run: k40t::deframe,
    },
    Target {
        name: "siyi_decode",
        run: siyi::decode,
    },
    Target {
        name: "siyi_deframe",
        run: siyi::deframe,
    },
    Target {
        name: "viewlink_decode",
        run: viewlink::decode,
    },
    Target {
        name: "viewlink_deframe",
        run: viewlink::deframe,
    },
    Target {
        name: "viewlink_tcp",
        run: viewlink::tcp,
    },
    Target {
        name: "gcu_decode",
        run: gcu::decode,
    },
    Target {
        name: "bridge",
        run: bridge::run,
    },
    Target {
        name: "bridge_mavlink",
        run: bridge_mavlink::run,
    },
    Target {
        name: "bridge_signed",
        run: bridge_mavlink::run_signed,
    },
    Target {
        name: "bridge_k40t_allow",
        run: bridge::run_k40t_allow,
    },
    Target {
        name: "bridge_forged",
        run: bridge_mavlink::run_forged,
    },
    Target {
        name: "console",
        run: console::run,
    },
    Target {
        name: "gcu_deframe",
        run: gcu::deframe,
    },
    Target {
        name: "mavlink_decode",
        run: mavlink::decode,
    },
    Target {
        name: "mavlink_deframe",
        run: mavlink::deframe,
    },
    Target {
        name: "resync",
        run: resync::resync,
    },
];

/// The target called `name`.
#[must_use]
pub fn target(name: &str) -> Option<&'static Target> {
    TARGETS.iter().find(|t| t.name == name)
}

/// Errors about the frame rather than its content: a frame with a valid checksum (or
/// one the deframer delivered) must never fail with these.
#[must_use]
pub fn is_frame_error(e: Error) -> bool {
    matches!(
        e,
        Error::Truncated | Error::BadSync | Error::BadChecksum { .. }
    )
}

/// An encoder whose output is `n` bytes writes into a buffer of exactly `n` bytes, and
/// reports [`Error::BufferTooSmall`] for one byte less and for none.
pub fn exact_buffers(n: usize, emit: impl Fn(&mut [u8]) -> protocol_core::Result<usize>) {
    let mut buf = vec![0u8; n];
    assert_eq!(emit(&mut buf), Ok(n), "encoding into an exact buffer");
    assert_eq!(
        emit(&mut buf[..n - 1]),
        Err(Error::BufferTooSmall),
        "encoding into a buffer one byte short"
    );
    assert_eq!(emit(&mut []), Err(Error::BufferTooSmall));
}
