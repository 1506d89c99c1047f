//! MAVLink 2 message signing (the MAVLink specification's "Message Signing"): the
//! secret key, the signature of a frame and its check, the signature's timestamp.
//!
//! A signed frame carries, after its checksum, a link id, a 48-bit timestamp (10 µs
//! since 2015-01-01 00:00:00 UTC) and the first 48 bits of
//! SHA-256(secret key ‖ the frame from its STX to the timestamp). Which frames a receiver
//! accepts (the timestamp of each stream, the window of a new stream) is the receiver's
//! state, not the codec's: the bridge's is in the engine (see docs/src/security.md).
//!
//! SHA-256 is RustCrypto's `sha2` (no_std; on the MCU its portable software backend).

use core::fmt;

use super::frame::Frame;

/// Bytes of a secret key.
pub const KEY_LEN: usize = 32;
/// Bytes of the signature value (the first 48 bits of the SHA-256).
pub const VALUE_LEN: usize = 6;
/// 2015-01-01 00:00:00 UTC, the signing epoch, in Unix seconds.
pub const EPOCH_UNIX_S: u64 = 1_420_070_400;
/// The largest timestamp a signature carries (48 bits).
pub const MAX_TIMESTAMP: u64 = (1 << 48) - 1;
/// Timestamp units in one second (10 µs each).
pub const TIMESTAMP_PER_S: u64 = 100_000;

/// A 32-byte MAVLink signing key. Its `Debug` and `defmt` forms never show it.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct SecretKey([u8; KEY_LEN]);

impl SecretKey {
    /// The key of these bytes.
    #[must_use]
    pub const fn new(bytes: [u8; KEY_LEN]) -> Self {
        SecretKey(bytes)
    }

    /// The key from its 64 hexadecimal characters (either case; nothing else, no
    /// spaces).
    #[must_use]
    pub fn from_hex(text: &str) -> Option<Self> {
        let text = text.as_bytes();
        if text.len() != KEY_LEN.saturating_mul(2) {
            return None;
        }
        let mut key = [0u8; KEY_LEN];
        for (i, byte) in key.iter_mut().enumerate() {
            let at = i.saturating_mul(2);
            let (hi, lo) = (text.get(at)?, text.get(at.saturating_add(1))?);
            *byte = nibble(*hi)?.checked_mul(16)?.checked_add(nibble(*lo)?)?;
        }
        Some(SecretKey(key))
    }

    /// The key's bytes.
    #[must_use]
    pub const fn as_bytes(&self) -> &[u8; KEY_LEN] {
        &self.0
    }

    /// All 32 bytes zero (SETUP_SIGNING with such a key and timestamp 0 turns signing
    /// off).
    #[must_use]
    pub fn is_zero(&self) -> bool {
        self.0.iter().all(|b| *b == 0)
    }
}

/// The value of one hexadecimal digit.
fn nibble(c: u8) -> Option<u8> {
    match c {
        b'0'..=b'9' => c.checked_sub(b'0'),
        b'a'..=b'f' => c.checked_sub(b'a')?.checked_add(10),
        b'A'..=b'F' => c.checked_sub(b'A')?.checked_add(10),
        _ => None,
    }
}

impl fmt::Debug for SecretKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("SecretKey(..)")
    }
}

#[cfg(feature = "defmt")]
impl defmt::Format for SecretKey {
    fn format(&self, f: defmt::Formatter<'_>) {
        defmt::write!(f, "SecretKey(..)");
    }
}

#[cfg(feature = "serde")]
impl serde::Serialize for SecretKey {
    /// Never the key: `"(secret)"`.
    fn serialize<S: serde::Serializer>(&self, s: S) -> core::result::Result<S::Ok, S::Error> {
        s.serialize_str("(secret)")
    }
}

/// SHA-256's initial hash value (FIPS 180-4, 5.3.3).
const SHA256_IV: [u32; 8] = [
    0x6a09_e667,
    0xbb67_ae85,
    0x3c6e_f372,
    0xa54f_f53a,
    0x510e_527f,
    0x9b05_688c,
    0x1f83_d9ab,
    0x5be0_cd19,
];
/// SHA-256's block, bytes.
const BLOCK: usize = 64;
/// The longest message signed: the key and a whole signed frame but the value, padded
/// (at least 9 bytes: 0x80 and the 64-bit length) to whole blocks.
const PADDED_MAX: usize = (KEY_LEN + super::MAX_FRAME_LEN - VALUE_LEN + 9).div_ceil(BLOCK) * BLOCK;

/// The signature value: the first 48 bits of SHA-256(`key` ‖ `signed`), `signed` being
/// the frame from its STX to the end of the signature's timestamp (longer input is cut
/// at a whole frame's length).
///
/// The message is padded here (FIPS 180-4, 5.1.1) into one fixed buffer and given to
/// `sha2`'s compression function block by block: two blocks for a frame of up to 87
/// bytes signed, the usual case.
#[must_use]
pub fn signature_value(key: &SecretKey, signed: &[u8]) -> [u8; VALUE_LEN] {
    let mut buf = [0u8; PADDED_MAX];
    let signed = signed
        .get(..super::MAX_FRAME_LEN.saturating_sub(VALUE_LEN))
        .unwrap_or(signed);
    let len = KEY_LEN.saturating_add(signed.len());
    let (head, rest) = buf.split_at_mut(KEY_LEN);
    crate::wire::copy(head, key.as_bytes());
    crate::wire::copy(rest, signed);
    if let Some(b) = buf.get_mut(len) {
        *b = 0x80;
    }
    let padded = len.saturating_add(9).div_ceil(BLOCK).saturating_mul(BLOCK);
    let bits = u64::try_from(len)
        .unwrap_or(0)
        .saturating_mul(8)
        .to_be_bytes();
    if let Some(dst) = buf.get_mut(padded.saturating_sub(8)..padded) {
        crate::wire::copy(dst, &bits);
    }
    let mut state = SHA256_IV;
    for block in buf.get(..padded).unwrap_or_default().chunks_exact(BLOCK) {
        if let Ok(block) = <[u8; BLOCK]>::try_from(block) {
            sha2::compress256(&mut state, &[block.into()]);
        }
    }
    let [a, b, ..] = state;
    let [v0, v1, v2, v3] = a.to_be_bytes();
    let [v4, v5, _, _] = b.to_be_bytes();
    [v0, v1, v2, v3, v4, v5]
}

/// The signature timestamp of a UTC instant (µs since the Unix epoch): 10 µs units since
/// 2015-01-01 (0 before it, [`MAX_TIMESTAMP`] after 2104).
#[must_use]
pub const fn timestamp_of_unix_micros(us: u64) -> u64 {
    let since = us.saturating_sub(EPOCH_UNIX_S.saturating_mul(1_000_000));
    let t = since / 10;
    if t > MAX_TIMESTAMP { MAX_TIMESTAMP } else { t }
}

/// The bytes the signature of `frame` covers: STX to the end of the timestamp (`None`
/// for an unsigned or truncated frame).
fn signed_part(frame: &[u8]) -> Option<&[u8]> {
    let view = Frame::new_unchecked(frame);
    if !view.is_signed() {
        return None;
    }
    let end = view.total_len().checked_sub(VALUE_LEN)?;
    frame.get(..end).filter(|_| frame.len() >= view.total_len())
}

/// `frame` (a whole MAVLink 2 frame) is signed and its signature is `key`'s (the 6
/// bytes compared in full; the timestamp's freshness is the receiver's to judge).
#[must_use]
pub fn signature_matches(frame: &[u8], key: &SecretKey) -> bool {
    let (Some(signed), Some(sig)) = (signed_part(frame), Frame::new_unchecked(frame).signature())
    else {
        return false;
    };
    signature_value(key, signed) == sig.value
}

/// Computes the signature value of `frame` with `key` and writes it in place (the SIGNED
/// flag, the checksum, the link id and the timestamp must be there: a frame emitted with
/// a [`Signature`](super::Signature) whose value is to be filled). Nothing for an
/// unsigned or truncated frame.
pub fn fill_signature(frame: &mut [u8], key: &SecretKey) {
    let Some((end, value)) = signed_part(frame).map(|s| (s.len(), signature_value(key, s))) else {
        return;
    };
    if let Some(dst) = frame.get_mut(end..end.saturating_add(VALUE_LEN)) {
        crate::wire::copy(dst, &value);
    }
}

/// What a signed frame is signed with: the key, the link id and the timestamp.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Signer<'a> {
    /// The secret key.
    pub key: &'a SecretKey,
    /// The link id the signature names.
    pub link_id: u8,
    /// The timestamp (48 bits; see [`timestamp_of_unix_micros`]).
    pub timestamp: u64,
}

impl Signer<'_> {
    /// The signature to emit, its value still to be filled.
    pub(super) const fn unfilled(&self) -> super::Signature {
        super::Signature {
            link_id: self.link_id,
            timestamp: self.timestamp,
            value: [0; VALUE_LEN],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_read_from_hex_and_never_show() {
        let text = "000102030405060708090a0b0c0d0e0f101112131415161718191A1B1C1D1E1F";
        let key = SecretKey::from_hex(text).unwrap();
        assert_eq!(key.as_bytes()[31], 0x1F);
        assert_eq!(key.as_bytes()[10], 0x0A);
        assert_eq!(std::format!("{key:?}"), "SecretKey(..)");
        for bad in [
            "",
            "00",
            &text[1..],
            "g0".repeat(32).as_str(),
            &std::format!("{text}0"),
        ] {
            assert_eq!(SecretKey::from_hex(bad), None, "{bad}");
        }
        assert!(SecretKey::default().is_zero() && !key.is_zero());
    }

    #[test]
    fn timestamps_count_10_us_from_2015() {
        assert_eq!(timestamp_of_unix_micros(0), 0);
        assert_eq!(timestamp_of_unix_micros(EPOCH_UNIX_S * 1_000_000), 0);
        assert_eq!(
            timestamp_of_unix_micros(EPOCH_UNIX_S * 1_000_000 + 1_000_019),
            100_001
        );
        assert_eq!(timestamp_of_unix_micros(u64::MAX), MAX_TIMESTAMP);
    }

    /// The padding where block boundaries fall (key + message of 55, 56, 119, 120
    /// bytes...): the first 48 bits of SHA-256 as Python's hashlib computes them.
    #[test]
    fn the_padding_at_every_block_boundary() {
        let key = SecretKey::new([0x5A; 32]);
        let hashlib = [
            (0, "60bf07c488aa"),
            (1, "e755e8731761"),
            (22, "070b8bcf1edc"),
            (23, "b69ca2e41dd9"),
            (24, "56388157fcda"),
            (31, "b22aad57203b"),
            (32, "32606111ebe8"),
            (55, "c36f8851bc15"),
            (56, "2ccd2ac3a31f"),
            (87, "387614153dc0"),
            (88, "e9cca160a67b"),
            (119, "f664751bd29e"),
            (120, "bf047a4a937d"),
            (200, "bc83878c0a9e"),
            (267, "f7e8e0cb3566"),
        ];
        for (n, want) in hashlib {
            let data: std::vec::Vec<u8> = (0..n)
                .map(|i: u32| u8::try_from(i * 7 % 256).unwrap())
                .collect();
            let got =
                signature_value(&key, &data)
                    .iter()
                    .fold(std::string::String::new(), |mut s, b| {
                        let _ = core::fmt::Write::write_fmt(&mut s, format_args!("{b:02x}"));
                        s
                    });
            assert_eq!(got, want, "{n} bytes");
        }
    }

    extern crate std;

    /// A heartbeat signed by pymavlink 2.4.50 (key 00..1F, link 3, timestamp 123456789):
    /// the same bytes from [`encode_signed`](super::super::encode_signed), and the check
    /// finds any changed byte.

    #[test]
    fn signatures_are_pymavlink_s() {
        use super::super::dialect::{HEARTBEAT_DATA, MavAutopilot, MavModeFlag, MavState, MavType};
        use super::super::{Header, MavMessage, encode_signed};
        let pymavlink = "fd09010000019a000000000000001a08000403fd370315cd5b070000bb16f13d6c43";
        let expected: std::vec::Vec<u8> = (0..pymavlink.len() / 2)
            .map(|i| u8::from_str_radix(&pymavlink[2 * i..2 * i + 2], 16).unwrap())
            .collect();
        let mut bytes = [0u8; 32];
        for (i, b) in bytes.iter_mut().enumerate() {
            *b = u8::try_from(i).unwrap();
        }
        let key = SecretKey::new(bytes);
        let hb = MavMessage::HEARTBEAT(HEARTBEAT_DATA {
            custom_mode: 0,
            mavtype: MavType::MAV_TYPE_GIMBAL,
            autopilot: MavAutopilot::MAV_AUTOPILOT_INVALID,
            base_mode: MavModeFlag::empty(),
            system_status: MavState::MAV_STATE_ACTIVE,
            mavlink_version: 3,
        });
        let header = Header {
            sequence: 0,
            system_id: 1,
            component_id: 154,
        };
        let signer = Signer {
            key: &key,
            link_id: 3,
            timestamp: 123_456_789,
        };
        let mut buf = [0u8; 300];
        let n = encode_signed(&hb, &header, &signer, &mut buf).unwrap();
        assert_eq!(&buf[..n], &expected[..]);
        assert!(signature_matches(&buf[..n], &key));
        for i in 0..n {
            let mut spoilt = buf;
            spoilt[i] ^= 0x20;
            assert!(!signature_matches(&spoilt[..n], &key), "byte {i}");
        }
        assert!(!signature_matches(&buf[..n], &SecretKey::default()));
        // Unsigned and truncated frames never match.
        assert!(!signature_matches(&buf[..n - 1], &key));
        let n = super::super::encode(&hb, &header, &mut buf).unwrap();
        assert!(!signature_matches(&buf[..n], &key));
    }
}
