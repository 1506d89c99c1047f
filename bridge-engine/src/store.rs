//! The records the bridge keeps across restarts, and their encodings (see
//! docs/src/security.md, "Across restarts").
//!
//! The engine decides what to save and when; its caller only moves the bytes (the
//! firmware to a flash store, `gimbal bridge` to a state file):
//!
//! - **Saving.** When a record should be written the engine's input returns
//!   [`Changes::STORE`](crate::Changes::STORE); [`Engine::take_record`](crate::Engine::take_record)
//!   then gives the records to write, one at a time, each with its key and its current
//!   value. A record asked again before it was taken is written once, with its newest
//!   value.
//! - **Restoring.** Before its first input the engine takes each record the caller found
//!   ([`Engine::restore`](crate::Engine::restore)), or the news that the store could not be
//!   read ([`Engine::restore_failed`](crate::Engine::restore_failed)). A record that does not
//!   decode is discarded with [`Event::StoreRecord`](crate::Event::StoreRecord) saying what
//!   was wrong; a record the bridge needs and did not get (a blank store) is reported the
//!   same way at its first input. Either way the bridge starts on that record's defaults.
//!
//! # Keys
//! A key is a `u16`:
//!
//! | keys | what |
//! | --- | --- |
//! | 0x0001, 0x0002 | the signing timestamp of the MAVLink side's link, of the telemetry link ([`Key::SIGNING_FC`], [`Key::SIGNING_TELEMETRY`]) |
//! | 0x0011, 0x0012 | the signing key set by SETUP_SIGNING on those links ([`Key::SIGNING_KEY_FC`], [`Key::SIGNING_KEY_TELEMETRY`]) |
//! | 0x0100 | the settings' header: the store holds the bridge's settings ([`crate::settings::HEADER`]) |
//! | 0x0101..=0x01FF | each setting kept at run time, `0x0100 + id` ([`crate::settings`], [`Key::SETTINGS`]) |
//! | 0xFFFF | no record: the whole store, in [`Event::StoreRecord`](crate::Event::StoreRecord) ([`Key::WHOLE_STORE`]) |
//!
//! # Values
//! Every value starts with its format's version (a byte; version 1 below); decoding never
//! panics and says what was wrong ([`Problem`]).
//!
//! | record | version 1 |
//! | --- | --- |
//! | signing timestamp | 1, the 48-bit timestamp (10 µs since 2015-01-01 UTC), 6 bytes little-endian: 7 bytes |
//! | signing key | 1, a state byte (0: signing off on the link, 1: a key), the key (32 bytes; zero when off), the fingerprint of the configured key it replaced (6 bytes): 40 bytes |
//! | setting | 1, then 0 ("default") or 1 and the value's text (up to 160 bytes: [`crate::settings`]) |

use crate::event::Port;

/// A record's key (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Key(pub u16);

impl Key {
    /// The signing timestamp of the MAVLink side's link.
    pub const SIGNING_FC: Self = Self(0x0001);
    /// The signing timestamp of the telemetry link.
    pub const SIGNING_TELEMETRY: Self = Self(0x0002);
    /// The signing key set by SETUP_SIGNING on the MAVLink side's link.
    pub const SIGNING_KEY_FC: Self = Self(0x0011);
    /// The signing key set by SETUP_SIGNING on the telemetry link.
    pub const SIGNING_KEY_TELEMETRY: Self = Self(0x0012);
    /// The settings kept at run time: the header and each setting ([`crate::settings`]).
    pub const SETTINGS: core::ops::RangeInclusive<u16> = 0x0100..=0x01FF;
    /// Not a record: the whole store ([`Event::StoreRecord`](crate::Event::StoreRecord)).
    pub const WHOLE_STORE: Self = Self(0xFFFF);
    /// Every record this version of the bridge writes.
    pub const ALL: [Self; 4] = [
        Self::SIGNING_FC,
        Self::SIGNING_TELEMETRY,
        Self::SIGNING_KEY_FC,
        Self::SIGNING_KEY_TELEMETRY,
    ];

    /// The signing timestamp's record of the link `port`.
    #[must_use]
    pub const fn signing(port: Port) -> Self {
        match port {
            Port::Telemetry => Self::SIGNING_TELEMETRY,
            Port::Fc | Port::Pod => Self::SIGNING_FC,
        }
    }

    /// The signing key's record of the link `port`.
    #[must_use]
    pub const fn signing_key(port: Port) -> Self {
        match port {
            Port::Telemetry => Self::SIGNING_KEY_TELEMETRY,
            Port::Fc | Port::Pod => Self::SIGNING_KEY_FC,
        }
    }

    /// Its bit in [`Pending`].
    fn bit(self) -> u8 {
        Self::ALL
            .iter()
            .position(|k| *k == self)
            .and_then(|i| 1u8.checked_shl(u32::try_from(i).unwrap_or(8)))
            .unwrap_or(0)
    }
}

protocol_core::wire_derive! {
    [Eq, Hash]
    /// Why a record was not restored ([`Event::StoreRecord`](crate::Event::StoreRecord)).
    pub enum Problem {
        /// The store holds no such record (a blank store, or never written).
        Missing,
        /// The store could not be read (the caller's storage failed, or its own framing
        /// of the records is corrupt).
        Unreadable,
        /// The value is empty.
        Empty,
        /// The value's format version is not one this bridge reads.
        Version {
            /// The version found.
            found: u8,
        },
        /// The value's length is not its format's.
        Length {
            /// The format's length.
            expected: u8,
            /// The length found (255: longer).
            found: u8,
        },
        /// A field holds a value its format does not allow.
        Value,
        /// A key this bridge does not know.
        UnknownKey,
        /// The record was written under another configured signing key: the
        /// configuration's key is used (a new key in the configuration replaces one set by
        /// SETUP_SIGNING).
        Superseded,
    }
}

impl Problem {
    /// The problem as a word, for logs.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Problem::Missing => "missing",
            Problem::Unreadable => "unreadable",
            Problem::Empty => "empty",
            Problem::Version { .. } => "version",
            Problem::Length { .. } => "length",
            Problem::Value => "value",
            Problem::UnknownKey => "unknown_key",
            Problem::Superseded => "superseded",
        }
    }
}

/// The longest value of a record (a setting's: [`crate::settings::MAX_RECORD`]).
pub const MAX_VALUE: usize = crate::settings::MAX_RECORD;
/// The format version this bridge writes.
pub const VERSION: u8 = 1;
/// Bytes of a signing timestamp's value.
const TIMESTAMP_LEN: usize = 7;
/// Bytes of a signing key's value.
const KEY_RECORD_LEN: usize = 40;

/// One record to write: its key and its value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Record {
    /// The key.
    pub key: Key,
    len: u8,
    bytes: [u8; MAX_VALUE],
}

impl Record {
    /// A record of `key` with `value` as it is (at most [`MAX_VALUE`] bytes: the rest is
    /// cut).
    #[must_use]
    pub fn raw(key: Key, value: &[u8]) -> Self {
        Self::new(key, value)
    }

    fn new(key: Key, value: &[u8]) -> Self {
        let mut bytes = [0u8; MAX_VALUE];
        let n = value.len().min(MAX_VALUE);
        protocol_core::wire::copy(&mut bytes, value.get(..n).unwrap_or_default());
        Record {
            key,
            len: u8::try_from(n).unwrap_or(0),
            bytes,
        }
    }

    /// The value (with its version byte).
    #[must_use]
    pub fn value(&self) -> &[u8] {
        self.bytes.get(..usize::from(self.len)).unwrap_or_default()
    }

    /// A signing timestamp's record (version 1).
    #[must_use]
    pub fn timestamp(key: Key, timestamp: u64) -> Self {
        let [t0, t1, t2, t3, t4, t5, _, _] = timestamp.to_le_bytes();
        Self::new(key, &[VERSION, t0, t1, t2, t3, t4, t5])
    }

    /// A signing key's record (version 1): `key` (`None`: signing off on the link) and
    /// the fingerprint of the configured key it replaced.
    #[must_use]
    pub fn signing_key(record: Key, key: Option<[u8; 32]>, configured: [u8; 6]) -> Self {
        let mut v = [0u8; KEY_RECORD_LEN];
        let (head, rest) = v.split_at_mut(2);
        protocol_core::wire::copy(head, &[VERSION, u8::from(key.is_some())]);
        let (k, f) = rest.split_at_mut(32);
        protocol_core::wire::copy(k, &key.unwrap_or_default());
        protocol_core::wire::copy(f, &configured);
        Self::new(record, &v)
    }
}

/// The payload of a version-1 value of `len` bytes.
fn versioned(value: &[u8], len: usize) -> Result<&[u8], Problem> {
    let (&version, rest) = value.split_first().ok_or(Problem::Empty)?;
    if version != VERSION {
        return Err(Problem::Version { found: version });
    }
    if value.len() != len {
        return Err(Problem::Length {
            expected: u8::try_from(len).unwrap_or(u8::MAX),
            found: u8::try_from(value.len()).unwrap_or(u8::MAX),
        });
    }
    Ok(rest)
}

/// A signing timestamp's value decoded.
///
/// # Errors
/// What is wrong with it.
pub fn decode_timestamp(value: &[u8]) -> Result<u64, Problem> {
    let p = versioned(value, TIMESTAMP_LEN)?;
    let mut t = [0u8; 8];
    protocol_core::wire::copy(&mut t, p);
    Ok(u64::from_le_bytes(t))
}

/// A signing key's value decoded: the key (`None`: signing off) and the configured key's
/// fingerprint it was written under.
///
/// # Errors
/// What is wrong with it (a state byte other than 0 and 1, a key with state 0).
pub fn decode_signing_key(value: &[u8]) -> Result<(Option<[u8; 32]>, [u8; 6]), Problem> {
    let p = versioned(value, KEY_RECORD_LEN)?;
    let (&state, rest) = p.split_first().ok_or(Problem::Empty)?;
    let (k, f) = rest.split_at_checked(32).ok_or(Problem::Empty)?;
    let mut key = [0u8; 32];
    protocol_core::wire::copy(&mut key, k);
    let mut fingerprint = [0u8; 6];
    protocol_core::wire::copy(&mut fingerprint, f);
    match state {
        0 if key == [0; 32] => Ok((None, fingerprint)),
        1 => Ok((Some(key), fingerprint)),
        _ => Err(Problem::Value),
    }
}

/// The records waiting to be taken (a bit each, [`Key::ALL`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct Pending(u8);

impl Pending {
    /// `key` is to be written.
    pub(crate) fn mark(&mut self, key: Key) {
        self.0 |= key.bit();
    }

    /// A record waits.
    pub(crate) const fn is_pending(self) -> bool {
        self.0 != 0
    }

    /// The next record to write, taken off.
    pub(crate) fn take(&mut self) -> Option<Key> {
        let key = Key::ALL.into_iter().find(|k| self.0 & k.bit() != 0)?;
        self.0 &= !key.bit();
        Some(key)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_round_trip() {
        let t = Record::timestamp(Key::SIGNING_FC, 0x0000_1234_5678_9ABC);
        assert_eq!(t.value().len(), 7);
        assert_eq!(decode_timestamp(t.value()), Ok(0x1234_5678_9ABC));
        let k = Record::signing_key(Key::SIGNING_KEY_FC, Some([7; 32]), [1, 2, 3, 4, 5, 6]);
        assert_eq!(k.value().len(), 40);
        assert_eq!(
            decode_signing_key(k.value()),
            Ok((Some([7; 32]), [1, 2, 3, 4, 5, 6]))
        );
        let off = Record::signing_key(Key::SIGNING_KEY_FC, None, [9; 6]);
        assert_eq!(decode_signing_key(off.value()), Ok((None, [9; 6])));
    }

    /// Every bad value says what is wrong; none panics.
    #[test]
    fn bad_values_say_what_is_wrong() {
        assert_eq!(decode_timestamp(&[]), Err(Problem::Empty));
        assert_eq!(
            decode_timestamp(&[2, 0, 0, 0, 0, 0, 0]),
            Err(Problem::Version { found: 2 })
        );
        assert_eq!(
            decode_timestamp(&[1, 0, 0]),
            Err(Problem::Length {
                expected: 7,
                found: 3
            })
        );
        let mut k = Record::signing_key(Key::SIGNING_KEY_FC, Some([7; 32]), [0; 6])
            .value()
            .to_vec();
        k[1] = 2;
        assert_eq!(decode_signing_key(&k), Err(Problem::Value));
        k[1] = 0;
        assert_eq!(
            decode_signing_key(&k),
            Err(Problem::Value),
            "a key marked off"
        );
        for len in 0..64 {
            for fill in [0u8, 1, 0xFF] {
                let v = vec![fill; len];
                let _ = (decode_timestamp(&v), decode_signing_key(&v));
            }
        }
    }

    #[test]
    fn pending_records_come_once_each_in_key_order() {
        let mut p = Pending::default();
        p.mark(Key::SIGNING_KEY_TELEMETRY);
        p.mark(Key::SIGNING_FC);
        p.mark(Key::SIGNING_FC);
        assert_eq!(p.take(), Some(Key::SIGNING_FC));
        assert_eq!(p.take(), Some(Key::SIGNING_KEY_TELEMETRY));
        assert_eq!(p.take(), None);
    }
}
