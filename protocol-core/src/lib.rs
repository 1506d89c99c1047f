//! Encoders and decoders for the K40T four-sensor pod's protocol, three gimbal serial
//! protocols (the SIYI gimbal SDK, Viewlink (Viewpro gimbals) and GCU (XF Robot gimbals))
//! and MAVLink 2: the codecs, and nothing else. The bridge built on them is the
//! `bridge-engine` crate.
//!
//! `no_std`, no allocation, no `unsafe`, and no panicking path on any input: every
//! failure is an [`Error`] value.
//!
//! # A tour: which type to reach for, in which order
//! Every protocol module (`k40t`, `siyi`, `viewlink`, `gcu`) has the same shape:
//!
//! 1. **Bytes in:** a [`wire::Deframer`] with the protocol's framing (`K40tFraming`,
//!    `SiyiFraming`, `ViewlinkFraming`, `GcuFraming`) finds checksum-valid frames in a
//!    byte stream: [`push`](wire::Deframer::push) a slice, or let a UART driver write
//!    into [`spare_capacity_mut`](wire::Deframer::spare_capacity_mut) and
//!    [`commit`](wire::Deframer::commit); on line idle, [`flush`](wire::Deframer::flush).
//! 2. **A frame:** `Frame<T: AsRef<[u8]>>` is the checked zero-copy view (`new_checked`,
//!    `id()`, `payload()`, `verify()`), smoltcp's `Packet<T>`.
//! 3. **Its meaning:** `Packet::decode(bytes)` (or `Packet::parse(&frame)`) gives a
//!    `Packet { header: Header, message: Message }`, smoltcp's `Repr`. `Message` is an enum
//!    over every message id, with a `Raw` variant for unknown ids (never an error).
//! 4. **One message:** every payload type implements [`wire::MessageData`] (its `ID`,
//!    `NAME`, `ENCODED_LEN`) with its protocol's marker (`MessageData<Protocol = K40t>`),
//!    from the protocol's message table: recognise one with
//!    `message.get::<HybridZoom>()`.
//! 5. **Bytes out:** `encode(&message, &header, &mut buf)` writes one typed message as a
//!    whole frame; `Packet::emit(&mut buf)` writes a decoded packet back, byte for byte.
//! 6. **Catalogue:** `CATALOG` lists every id the codec knows.
//!
//! Units are part of field names (`yaw_cdeg`: 0.01 degree, `zoom_x10`: zoom ratio times
//! ten, `distance_dm`: decimetres). Enumerations keep values the documents do not list
//! in an `Other` variant, so decoding never loses information and every decoded frame
//! re-encodes byte for byte. Where a message id means different things in the two
//! directions (SIYI, GCU), decoding takes the [`Direction`].
//!
//! # Cargo features
//! | feature | default | what it adds |
//! | --- | --- | --- |
//! | `k40t`, `siyi`, `viewlink`, `gcu` | yes | the codec of that protocol |
//! | `mavlink` | no | [`mavlink`]: MAVLink 2 over rust-mavlink's generated types (a build-time generator, about 11.6 KB of flash) |
//! | `defmt` | no | `defmt::Format` on every public type |
//! | `serde` | no | `serde::Serialize` on every public type |
//! | `bake` | no | `databake::Bake` on the K40T address types (host only: a build script that writes a configuration out as Rust source) |
#![cfg_attr(not(test), no_std)]
#![cfg_attr(
    test,
    allow(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::indexing_slicing,
        clippy::arithmetic_side_effects
    )
)]

// Each macro serves some of the codecs: a build with one codec leaves others unused.
#[allow(unused_macros)]
#[macro_use]
mod macros;
mod error;
#[cfg(any(feature = "k40t", feature = "viewlink"))]
mod text;
#[macro_use]
pub mod wire;

#[cfg(feature = "k40t")]
pub mod k40t;

#[cfg(feature = "siyi")]
pub mod siyi;

#[cfg(feature = "viewlink")]
pub mod viewlink;

#[cfg(feature = "gcu")]
pub mod gcu;

#[cfg(feature = "mavlink")]
pub mod mavlink;

pub use error::{Error, Result};

wire_derive! {
    [Eq, Hash]
    /// Which way a frame travels between a flight controller (or ground station) and a
    /// gimbal. The SIYI, Viewlink and GCU codecs use it where the same id means different
    /// things in the two directions (a K40T message id carries its own kind).
    pub enum Direction {
        /// Flight controller to gimbal: commands and queries (SIYI requests, GCU host
        /// packages, Viewlink console and AHRS frames).
        ToGimbal,
        /// Gimbal to flight controller: replies, pushed data and status.
        FromGimbal,
    }
}

impl Direction {
    /// The other direction.
    #[must_use]
    pub const fn reverse(self) -> Self {
        match self {
            Direction::ToGimbal => Direction::FromGimbal,
            Direction::FromGimbal => Direction::ToGimbal,
        }
    }
}
#[cfg(any(feature = "k40t", feature = "viewlink"))]
pub use text::Text;
