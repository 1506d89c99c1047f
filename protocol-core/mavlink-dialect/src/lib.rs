//! The MAVLink 2 message set of the K40T gimbal bridge, generated at build time by
//! rust-mavlink's own generator (`mavlink-bindgen` 0.21) from the official XML in `xml/`
//! (common.xml, standard.xml, minimal.xml), trimmed by `build.rs` to the messages the
//! bridge sees and the enumerations they use. The types are rust-mavlink's: one
//! `*_DATA` struct per message, [`MavMessage`] over all of them, and the enumerations
//! (`MavCmd`, `MavResult`, `GimbalDeviceFlags`, ...).
//!
//! `protocol_core::mavlink` is the way in (framing, header, checksum, packets); this
//! crate holds the generated code on its own so that it can be compiled at opt-level s
//! inside an opt-level-z firmware (the workspace's `[profile.release.package.
//! gimbal-mavlink-dialect]`). At opt-level z, mavlink-core's byte cursors
//! (`Bytes::get_*`, `BytesMut::put_*`) stay out of line with their length assertions
//! and `copy_from_slice` checks, so panicking branches would stay reachable;
//! compiled at opt-level s they are inlined into each message's (de)serialiser, where
//! every length is known, and `host-tests/no-panic` links (`scripts/no-panic`). The two
//! functions below are the way in for that reason: they are compiled here, each
//! deserialiser sees a 255-byte zero-extended payload (so its "payload shorter than the
//! message" copy is provably dead) and each serialiser a 255-byte buffer.
#![no_std]
#![forbid(unsafe_code)]

#[allow(
    warnings,
    unexpected_cfgs,
    clippy::all,
    clippy::pedantic,
    missing_docs,
    rustdoc::all
)]
mod generated {
    include!(concat!(env!("OUT_DIR"), "/mavlink/mod.rs"));
}

pub use generated::gimbal::*;
pub use mavlink_core::error::ParserError;
pub use mavlink_core::types::CharArray;
/// The generated serde attributes name `crate::utils` (the mavlink crate's layout).
#[doc(hidden)]
pub use mavlink_core::utils;
pub use mavlink_core::{MavlinkVersion, Message, MessageData};

#[allow(clippy::cast_possible_truncation, deprecated)]
mod lookup {
    use super::*;
    include!(concat!(env!("OUT_DIR"), "/from.rs"));
}
pub use lookup::message_info;

/// What the dialect knows of one message id.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MessageInfo {
    /// The message id.
    pub id: u32,
    /// CRC_EXTRA, the seed byte of the frame checksum computed from the message's definition.
    pub crc_extra: u8,
    /// The payload length with every field, extensions included (senders may send fewer
    /// bytes: MAVLink 2 drops trailing zeros).
    pub max_len: u8,
    /// The message name, as in the XML.
    pub name: &'static str,
}

/// Decodes the MAVLink 2 payload of message `id` (fewer bytes than the message's length
/// are zero-extended; bytes past it, extensions of a newer definition, are ignored).
///
/// # Errors
/// [`ParserError::UnknownMessage`] for an id outside the dialect,
/// [`ParserError::InvalidEnum`] for an enumeration value the XML does not list.
#[inline(never)]
pub fn decode(id: u32, payload: &[u8]) -> Result<MavMessage, ParserError> {
    let mut full = [0u8; 255];
    for (d, s) in full.iter_mut().zip(payload) {
        *d = *s;
    }
    lookup::decode_full(id, &full)
}

/// Writes the MAVLink 2 payload of `message` into `payload` and returns its length with
/// trailing zero bytes removed (at least one byte), as MAVLink 2 sends it.
#[inline(never)]
pub fn encode(message: &MavMessage, payload: &mut [u8; 255]) -> usize {
    message.ser(MavlinkVersion::V2, payload)
}
