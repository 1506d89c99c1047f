//! The floor under MAVLink 2 signing: the SHA-256 compressions a signed frame needs.
//!
//! A signature is the first 48 bits of SHA-256(secret key ‖ the frame from its STX to
//! its timestamp) (the MAVLink specification's "Message Signing"): the key (32 bytes),
//! the header (10), the payload, the checksum (2), the link id (1) and the timestamp (6).
//! SHA-256 pads that message with 0x80 and its 64-bit length to whole 64-byte blocks
//! (FIPS 180-4, 5.1.1) and compresses each block once: no signing code can do less, so
//! the compressions a run's frames need (each frame checked in, each signed out), times
//! what one compression costs ([`compress_input`], the `sha256_compress` benchmark), is
//! the floor its signing rows are compared with.

use bridge_engine::Port;
use protocol_core::mavlink::{
    CHECKSUM_LEN, HEADER_LEN, IFLAG_SIGNED, KEY_LEN, SIGNATURE_LEN, STX_V2, VALUE_LEN,
};

use crate::bridge::BridgeRun;

/// SHA-256's block, bytes.
pub const BLOCK: usize = 64;
/// SHA-256's padding adds at least 9 bytes: 0x80 and the message's length in bits.
const PADDING_MIN: usize = 9;

/// Blocks the `sha256_compress` benchmark compresses, one a call.
pub const COMPRESS_BLOCKS: usize = 64;

/// Compressions SHA-256 makes of a `len`-byte message.
#[must_use]
pub const fn sha256_blocks(len: usize) -> usize {
    (len + PADDING_MIN).div_ceil(BLOCK)
}

/// Bytes a frame's signature hashes: the key, then the frame from STX to the end of its
/// timestamp (the header, `payload_len` bytes of payload, the checksum, the link id and
/// the timestamp).
#[must_use]
pub const fn signed_bytes(payload_len: usize) -> usize {
    let link_id_and_timestamp = SIGNATURE_LEN - VALUE_LEN;
    KEY_LEN + HEADER_LEN + payload_len + CHECKSUM_LEN + link_id_and_timestamp
}

/// Compressions the signature of `frame` needs (to make it or to check it): 0 for
/// anything but a signed MAVLink 2 frame.
#[must_use]
pub fn frame_compressions(frame: &[u8]) -> usize {
    match frame {
        [STX_V2, len, flags, ..] if flags & IFLAG_SIGNED != 0 => {
            sha256_blocks(signed_bytes(usize::from(*len)))
        }
        _ => 0,
    }
}

/// Compressions the signatures of a bridge run need: each signed frame the FC sent
/// checked, each signed frame the bridge sent the FC made.
#[must_use]
pub fn run_compressions(run: &BridgeRun) -> usize {
    let checked = run
        .inputs
        .iter()
        .filter(|i| i.port == Port::Fc)
        .map(|i| frame_compressions(&i.bytes));
    let signed = run
        .outputs
        .iter()
        .filter(|(p, _)| *p == Port::Fc)
        .map(|(_, f)| frame_compressions(f));
    checked.chain(signed).sum()
}

/// Compressions the `mavlink_encode_signed` benchmark's frames need: each message of
/// `messages` encoded signed (with [`BENCH_KEY`](crate::bridge::BENCH_KEY), as that
/// benchmark signs them).
#[must_use]
pub fn encode_compressions(
    messages: &[(
        protocol_core::mavlink::Header,
        protocol_core::mavlink::MavMessage,
    )],
) -> usize {
    use protocol_core::mavlink::{MAX_FRAME_LEN, SecretKey, Signer, encode_signed};
    let key = SecretKey::new(crate::bridge::BENCH_KEY);
    let mut buf = [0u8; MAX_FRAME_LEN];
    messages
        .iter()
        .map(|(header, message)| {
            let signer = Signer {
                key: &key,
                link_id: 0,
                timestamp: 1,
            };
            let n = encode_signed(message, header, &signer, &mut buf).expect("a signed frame");
            frame_compressions(&buf[..n])
        })
        .sum()
}

/// The `sha256_compress` benchmark's blocks: [`COMPRESS_BLOCKS`] of pseudo-random bytes
/// (SHA-256's work does not depend on them).
#[must_use]
pub fn compress_input() -> Vec<[u8; BLOCK]> {
    let mut x = 0x5348_4132_u64;
    (0..COMPRESS_BLOCKS)
        .map(|_| {
            std::array::from_fn(|_| {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                (x >> 24) as u8
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Where the blocks change: a message of 55 bytes pads into one block, 56 into two
    /// (FIPS 180-4, 5.1.1); a signed frame of 4 payload bytes hashes 55, of 5 hashes 56.
    #[test]
    fn blocks_change_where_the_padding_no_longer_fits() {
        assert_eq!([0, 55, 56, 119, 120].map(sha256_blocks), [1, 1, 2, 2, 3]);
        assert_eq!(signed_bytes(4), 55);
        assert_eq!(signed_bytes(5), 56);
    }

    /// The compressions of real frames: a signed heartbeat (9 payload bytes: 60 bytes
    /// hashed, 2 blocks), a signed 255-byte payload (306 bytes, 5 blocks), an unsigned
    /// frame (none).
    #[test]
    fn signed_frames_need_their_blocks_and_unsigned_none() {
        use protocol_core::mavlink::dialect::{
            HEARTBEAT_DATA, MavAutopilot, MavModeFlag, MavState, MavType,
        };
        let hb = protocol_core::mavlink::MavMessage::HEARTBEAT(HEARTBEAT_DATA {
            custom_mode: 7,
            mavtype: MavType::MAV_TYPE_GIMBAL,
            autopilot: MavAutopilot::MAV_AUTOPILOT_INVALID,
            base_mode: MavModeFlag::empty(),
            system_status: MavState::MAV_STATE_ACTIVE,
            mavlink_version: 3,
        });
        let unsigned = crate::bridge::mavlink_frame(0, &hb);
        let signed = crate::bridge::signed(&unsigned, 1);
        assert_eq!(unsigned[1], 9);
        assert_eq!(frame_compressions(&unsigned), 0);
        assert_eq!(frame_compressions(&signed), 2);
        let mut long = signed.clone();
        long[1] = 255;
        assert_eq!(frame_compressions(&long), 5);
    }
}
