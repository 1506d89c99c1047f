//! Encoders and decoders for four gimbal serial protocols: the K40T four-sensor pod,
//! the SIYI gimbal SDK, Viewlink (Viewpro) and the XF Robot GCU protocol.
//!
//! `no_std`, no allocation, no `unsafe`, and no panicking path on any input: every
//! failure is an [`Error`] value.
//!
//! # Shape of every codec (after smoltcp's `wire`)
//! - A checked zero-copy **frame view** over a byte buffer (`Frame<T: AsRef<[u8]>>`,
//!   `new_checked`, field accessors, checksum verification).
//! - A high-level **representation**: a `Message` enum of typed payload structs, with
//!   `parse` from a frame and `emit` into a buffer. Unknown ids decode to a raw variant
//!   that carries the payload, so a bridge can forward what it does not understand.
//! - A [`wire::Framing`] implementation, so the shared streaming [`wire::Deframer`]
//!   finds the protocol's frames in a byte stream and resynchronises after garbage.
//!
//! Units are part of field names (`yaw_cdeg`: 0.01 degree, `zoom_x10`: zoom ratio times
//! ten, `distance_dm`: decimetres). Enumerations keep values the documents do not list
//! in an `Other` variant, so decoding never loses information and every decoded frame
//! re-encodes byte for byte.
//!
//! # Cargo features
//! `k40t`, `siyi`, `viewlink`, `gcu` (all default) select the codecs; `defmt` derives
//! `defmt::Format` and `serde` derives `serde::Serialize` on the public types.
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
pub mod wire;

#[cfg(feature = "k40t")]
pub mod k40t;

#[cfg(feature = "siyi")]
pub mod siyi;

#[cfg(feature = "viewlink")]
pub mod viewlink;

#[cfg(feature = "gcu")]
pub mod gcu;

#[cfg(feature = "bridge")]
pub mod bridge;
#[cfg(feature = "bridge")]
pub mod gimbal;

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
