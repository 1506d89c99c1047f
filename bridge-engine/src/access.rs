//! Who may command the pod: the MAVLink signing configuration ([`SigningMode`],
//! [`SigningKey`]), the MAVLink systems whose commands are taken besides the autopilot's
//! ([`SystemIds`]), and the K40T FC side's allow-list of the pod's destructive requests
//! ([`Guarded`], [`K40tAllow`]). Why and what each link's attacker can do:
//! docs/src/security.md.

use core::fmt;

protocol_core::wire_derive! {
    [Eq, Hash, Default]
    /// MAVLink 2 signing on the MAVLink side and the telemetry link (configuration key
    /// `signing`: `"off"`, `"sign"`, `"require"`).
    #[cfg_attr(feature = "serde", derive(serde::Deserialize), serde(rename_all(deserialize = "lowercase")))]
    #[cfg_attr(feature = "bake", derive(databake::Bake), databake(path = bridge_engine::access))]
    pub enum SigningMode {
        /// Nothing signed, nothing checked (signed frames are read as they come).
        #[default]
        Off,
        /// Every frame the bridge sends is signed; a signed frame that does not check
        /// (wrong key, replayed, stale) is dropped; unsigned frames are read.
        Sign,
        /// As [`SigningMode::Sign`], and unsigned frames are refused: commands always,
        /// other messages unless `signing_unsigned_telemetry` is set.
        Require,
    }
}

/// The 32-byte MAVLink signing key (`signing_key`: 64 hexadecimal characters; `""`:
/// none). Its `Debug`, `defmt` and `Serialize` forms never show it.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct SigningKey(pub [u8; 32]);

impl SigningKey {
    /// The key from its text (`signing_key`): 64 hexadecimal characters, `""` for none.
    ///
    /// # Errors
    /// Any other text ([`Problem::Text`](crate::config::Problem::Text)).
    pub fn parse(text: &str) -> Result<Option<Self>, crate::config::ConfigError> {
        if text.is_empty() {
            return Ok(None);
        }
        let mut key = [0u8; 32];
        let bytes = text.as_bytes();
        let ok = bytes.len() == 64
            && key.iter_mut().enumerate().all(|(i, k)| {
                let at = i.saturating_mul(2);
                match bytes
                    .get(at..at.saturating_add(2))
                    .filter(|p| p.iter().all(u8::is_ascii_hexdigit))
                    .and_then(|p| core::str::from_utf8(p).ok())
                    .and_then(|p| u8::from_str_radix(p, 16).ok())
                {
                    Some(v) => {
                        *k = v;
                        true
                    }
                    None => false,
                }
            });
        if ok {
            Ok(Some(SigningKey(key)))
        } else {
            Err(crate::config::ConfigError::text(
                "signing_key",
                crate::config::TextRule::Hex(64),
            ))
        }
    }
}

impl fmt::Debug for SigningKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("SigningKey(..)")
    }
}

#[cfg(feature = "defmt")]
impl defmt::Format for SigningKey {
    fn format(&self, f: defmt::Formatter<'_>) {
        defmt::write!(f, "SigningKey(..)");
    }
}

#[cfg(feature = "serde")]
impl serde::Serialize for SigningKey {
    /// Never the key: `"(secret)"`.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str("(secret)")
    }
}

#[cfg(feature = "bake")]
impl databake::Bake for SigningKey {
    fn bake(&self, env: &databake::CrateEnv) -> databake::TokenStream {
        env.insert("bridge_engine");
        let bytes = self.0.bake(env);
        databake::quote!(bridge_engine::access::SigningKey(#bytes))
    }
}

#[cfg(feature = "bake")]
impl databake::BakeSize for SigningKey {
    fn borrows_size(&self) -> usize {
        0
    }
}

/// Ground-station system ids [`SystemIds`] holds at most.
pub const MAX_GCS_IDS: usize = 8;

protocol_core::wire_derive! {
    [Eq, Hash]
    /// The MAVLink systems (besides the autopilot's own) whose commands the bridge takes
    /// (`gcs_ids`: a list of 1 to 8 ids, each 1..=255, or `[]` for the autopilot's
    /// only). Default 255 (QGroundControl, Mission Planner) and 245 (MAVSDK's ground
    /// station).
    #[cfg_attr(feature = "bake", derive(databake::Bake), databake(path = bridge_engine::access))]
    pub struct SystemIds {
        /// The ids; the first `len` count.
        pub ids: [u8; MAX_GCS_IDS],
        /// How many.
        pub len: u8,
    }
}

impl SystemIds {
    /// 255 and 245.
    pub const DEFAULT: Self = Self {
        ids: [255, 245, 0, 0, 0, 0, 0, 0],
        len: 2,
    };
    /// None: the autopilot's system only.
    pub const NONE: Self = Self {
        ids: [0; MAX_GCS_IDS],
        len: 0,
    };

    /// The ids of a list (at most [`MAX_GCS_IDS`]; 0, the broadcast id, is no sender).
    ///
    /// # Errors
    /// A list too long, or an id out of 1..=255 ([`crate::config::Limit::GCS_ID`]).
    pub fn from_list(list: &[i64]) -> Result<Self, crate::config::ConfigError> {
        let mut out = Self::NONE;
        if list.len() > MAX_GCS_IDS {
            return Err(crate::config::ConfigError {
                key: "gcs_ids",
                problem: crate::config::Problem::TooMany {
                    max: u8::try_from(MAX_GCS_IDS).unwrap_or(u8::MAX),
                },
            });
        }
        for (slot, id) in out.ids.iter_mut().zip(list) {
            crate::config::Limit::GCS_ID.check(*id)?;
            *slot = u8::try_from(*id).unwrap_or(0);
        }
        out.len = u8::try_from(list.len()).unwrap_or(0);
        Ok(out)
    }

    /// The ids.
    #[must_use]
    pub fn as_slice(&self) -> &[u8] {
        self.ids.get(..usize::from(self.len)).unwrap_or(&[])
    }

    /// `sysid` is one of them.
    #[must_use]
    pub fn contains(&self, sysid: u8) -> bool {
        self.as_slice().contains(&sysid)
    }
}

impl Default for SystemIds {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// The pod's destructive requests, which a K40T flight controller's frame reaches only
/// when [`K40tAllow`] lists it (K40T external protocol: section of each).
pub const GUARDED: [Guarded; 11] = [
    Guarded::new(0x030D, "TF card format (3.2.4.12)"),
    Guarded::new(0x030F, "factory reset (3.2.4.14)"),
    Guarded::new(0x0311, "camera IP address change (3.2.4.16)"),
    Guarded::new(0x0316, "camera shutdown (3.2.4.20)"),
    Guarded::new(0x030C, "TF card firmware upgrade (3.2.4.11)"),
    Guarded::new(0x002F, "gimbal soft restart (3.1.2.9)"),
    Guarded::new(0x0013, "gimbal drift calibration (3.1.2.3)"),
    Guarded::new(0x002E, "gimbal linear calibration (3.1.2.8)"),
    Guarded::new(0x0031, "gimbal acceleration offset calibration (3.1.2.11)"),
    Guarded::new(0x0500, "SBUS channel value range (3.2.6.1)"),
    Guarded::new(0x0501, "SBUS channel configuration (3.2.6.2)"),
];

/// One of the [`GUARDED`] requests.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Guarded {
    /// Its base id (the request is 0x00 followed by it).
    pub base: u16,
    /// What it does, and the document's section.
    pub what: &'static str,
}

impl Guarded {
    const fn new(base: u16, what: &'static str) -> Self {
        Guarded { base, what }
    }

    /// The index in [`GUARDED`] of the request of `base`, when it is guarded.
    #[must_use]
    pub fn index_of(base: u16) -> Option<usize> {
        GUARDED.iter().position(|g| g.base == base)
    }
}

protocol_core::wire_derive! {
    [Eq, Hash, Default]
    /// Which of the [`GUARDED`] requests reach the pod (`k40t_allow`: a list of their
    /// ids, e.g. `[0x00030D]`; default `[]`, none). Every other request passes. The rule
    /// holds for every FC side: a request a MAVLink command maps to (storage format) is
    /// refused the same way.
    #[cfg_attr(feature = "bake", derive(databake::Bake), databake(path = bridge_engine::access))]
    pub struct K40tAllow {
        /// Bit `i` allows `GUARDED[i]`.
        pub bits: u16,
    }
}

impl K40tAllow {
    /// None of the guarded requests.
    pub const NONE: Self = Self { bits: 0 };

    /// The allow-list of ids (each a guarded request: `0x00030D` or its base `0x030D`).
    ///
    /// # Errors
    /// An id that is not one of [`GUARDED`] ([`crate::config::Problem::NotGuarded`]).
    pub fn from_list(list: &[i64]) -> Result<Self, crate::config::ConfigError> {
        let mut bits = 0u16;
        for id in list {
            let i = u16::try_from(*id).ok().and_then(Guarded::index_of).ok_or(
                crate::config::ConfigError {
                    key: "k40t_allow",
                    problem: crate::config::Problem::NotGuarded { value: *id },
                },
            )?;
            bits |= 1u16
                .checked_shl(u32::try_from(i).unwrap_or(16))
                .unwrap_or(0);
        }
        Ok(Self { bits })
    }

    /// The request of `base` may reach the pod: it is not guarded, or the list allows it.
    #[must_use]
    pub fn allows(self, base: u16) -> bool {
        Guarded::index_of(base).is_none_or(|i| {
            let bit = 1u16
                .checked_shl(u32::try_from(i).unwrap_or(16))
                .unwrap_or(0);
            self.bits & bit != 0
        })
    }
}

/// A MAVLink message that changes something on the bridge or the pod: taken only from an
/// allowed sender (the autopilot's system or one of `gcs_ids`) and, while signing is
/// required, only signed ([`GATED`]; docs/src/security.md, "The gate").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Gated {
    /// The message id.
    pub id: u32,
    /// Its MAVLink name.
    pub name: &'static str,
    /// Where its target system lies in the payload (its target component follows).
    pub target_at: usize,
    /// The operations gated (`None`: every one): the MAVLink FTP opcodes that write,
    /// create, remove, truncate or rename (its reads and lists stay open).
    pub opcodes: Option<&'static [u8]>,
    /// What it changes.
    pub changes: &'static str,
}

/// Where a FILE_TRANSFER_PROTOCOL payload carries the opcode (after the target network,
/// system and component, the sequence number and the session).
const FTP_OPCODE_AT: usize = 6;

/// The MAVLink FTP opcodes that change files (MAVLink FTP: CreateFile 6, WriteFile 7,
/// RemoveFile 8, CreateDirectory 9, RemoveDirectory 10, OpenFileWO 11, TruncateFile 12,
/// Rename 13).
pub const FTP_WRITES: [u8; 8] = [6, 7, 8, 9, 10, 11, 12, 13];

/// Every MAVLink message that changes anything, on the MAVLink side and the telemetry link
/// alike: the one table the gate reads (and the security chapter lists; a test compares
/// them). Everything else reads or reports: heartbeats, time, positions, the parameter and
/// FTP reads.
pub const GATED: [Gated; 7] = [
    Gated {
        id: 76,
        name: "COMMAND_LONG",
        target_at: 30,
        opcodes: None,
        changes: "every command: the camera's (photos, video, zoom, focus, mode, SET_CAMERA_*), tracking, storage format and reset, ROI, message intervals, requests for messages",
    },
    Gated {
        id: 75,
        name: "COMMAND_INT",
        target_at: 30,
        opcodes: None,
        changes: "as COMMAND_LONG",
    },
    Gated {
        id: 284,
        name: "GIMBAL_DEVICE_SET_ATTITUDE",
        target_at: 30,
        opcodes: None,
        changes: "where the gimbal points",
    },
    Gated {
        id: 323,
        name: "PARAM_EXT_SET",
        target_at: 0,
        opcodes: None,
        changes: "a camera setting (a K40T set command at the pod)",
    },
    Gated {
        id: 23,
        name: "PARAM_SET",
        target_at: 4,
        opcodes: None,
        changes: "a parameter of the bridge",
    },
    Gated {
        id: 110,
        name: "FILE_TRANSFER_PROTOCOL",
        target_at: 1,
        opcodes: Some(&FTP_WRITES),
        changes: "a file: writes, opens for writing, creation, removal, truncation, renaming",
    },
    Gated {
        id: 256,
        name: "SETUP_SIGNING",
        target_at: 8,
        opcodes: None,
        changes: "the signing key",
    },
];

impl Gated {
    /// The entry of [`GATED`] that a message of `id` with `payload` (as sent: MAVLink 2
    /// trims trailing zeros) falls under, `None` when it changes nothing.
    #[must_use]
    pub fn of(id: u32, payload: &[u8]) -> Option<&'static Gated> {
        let g = GATED.iter().find(|g| g.id == id)?;
        match g.opcodes {
            None => Some(g),
            Some(ops) => {
                let op = payload.get(FTP_OPCODE_AT).copied().unwrap_or(0);
                ops.contains(&op).then_some(g)
            }
        }
    }

    /// The target system and component of a message of this kind (zero when trimmed).
    #[must_use]
    pub fn target(&self, payload: &[u8]) -> (u8, u8) {
        let at = |i: usize| payload.get(i).copied().unwrap_or(0);
        (at(self.target_at), at(self.target_at.saturating_add(1)))
    }

    /// A command (COMMAND_LONG, COMMAND_INT): its MAV_CMD names it in reports.
    #[must_use]
    pub fn is_command(&self) -> bool {
        matches!(self.id, 75 | 76)
    }
}

protocol_core::wire_derive! {
    [Eq, Hash]
    /// Why the bridge refused a frame or a command ([`Event::Refused`](crate::Event)).
    pub enum Refusal {
        /// A signed MAVLink frame whose signature is not the key's.
        BadSignature,
        /// A signed MAVLink frame whose timestamp is not newer than its stream's last
        /// (a replay).
        Replayed,
        /// A signed MAVLink frame opening a stream with a timestamp over a minute older
        /// than the bridge's.
        Stale,
        /// An unsigned MAVLink command (or, without `signing_unsigned_telemetry`, any
        /// unsigned frame) while signing is required.
        Unsigned,
        /// A MAVLink command from a system that is neither the autopilot's nor a listed
        /// ground station's.
        Sender,
        /// One of the pod's destructive requests ([`GUARDED`]) not in `k40t_allow`.
        Guarded,
    }
}

#[cfg(feature = "serde")]
pub(crate) mod de {
    use serde::de::{Deserializer, Error};

    use super::{K40tAllow, SigningKey, SystemIds};

    pub(crate) fn signing_key<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<SigningKey>, D::Error> {
        struct Key;
        impl serde::de::Visitor<'_> for Key {
            type Value = Option<SigningKey>;
            fn expecting(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
                f.write_str("64 hexadecimal characters")
            }
            fn visit_str<E: Error>(self, v: &str) -> Result<Self::Value, E> {
                SigningKey::parse(v).map_err(|e| E::custom(e.problem))
            }
        }
        d.deserialize_str(Key)
    }

    /// A list of integers, at most 16 (more is an error of the caller's type).
    fn ints<'de, D: Deserializer<'de>>(d: D) -> Result<([i64; 16], usize), D::Error> {
        struct Ints;
        impl<'de> serde::de::Visitor<'de> for Ints {
            type Value = ([i64; 16], usize);
            fn expecting(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
                f.write_str("a list of integers")
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<Self::Value, A::Error> {
                let mut out = [0i64; 16];
                let mut n = 0usize;
                while let Some(v) = seq.next_element::<i64>()? {
                    let slot = out
                        .get_mut(n)
                        .ok_or_else(|| A::Error::custom("more than 16 values"))?;
                    *slot = v;
                    n = n.saturating_add(1);
                }
                Ok((out, n))
            }
        }
        d.deserialize_seq(Ints)
    }

    pub(crate) fn gcs_ids<'de, D: Deserializer<'de>>(d: D) -> Result<SystemIds, D::Error> {
        let (list, n) = ints(d)?;
        SystemIds::from_list(list.get(..n).unwrap_or(&[])).map_err(|e| D::Error::custom(e.problem))
    }

    pub(crate) fn k40t_allow<'de, D: Deserializer<'de>>(d: D) -> Result<K40tAllow, D::Error> {
        let (list, n) = ints(d)?;
        K40tAllow::from_list(list.get(..n).unwrap_or(&[])).map_err(|e| D::Error::custom(e.problem))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_parse_from_hex_only() {
        let hex = "00112233445566778899aabbccddeeff00112233445566778899AABBCCDDEEFF";
        let k = SigningKey::parse(hex).unwrap().unwrap();
        assert_eq!(k.0[1], 0x11);
        assert_eq!(k.0[31], 0xFF);
        assert_eq!(SigningKey::parse(""), Ok(None));
        let plus = format!("+{}", &hex[1..]);
        for bad in [&hex[1..], "zz", &hex.replace('0', "g"), &plus] {
            assert_eq!(SigningKey::parse(bad).unwrap_err().key, "signing_key");
        }
        assert_eq!(format!("{k:?}"), "SigningKey(..)");
    }

    #[test]
    fn the_destructive_requests_are_denied_unless_listed() {
        let none = K40tAllow::default();
        for g in GUARDED {
            assert!(!none.allows(g.base), "{}", g.what);
        }
        for open in [0x0010, 0x0302, 0x030E, 0x0310, 0x0312] {
            assert!(none.allows(open));
        }
        let some = K40tAllow::from_list(&[0x0000_030D, 0x0316]).unwrap();
        assert!(some.allows(0x030D) && some.allows(0x0316) && !some.allows(0x030F));
        assert_eq!(
            K40tAllow::from_list(&[0x0302]).unwrap_err().key,
            "k40t_allow"
        );
        assert_eq!(
            K40tAllow::from_list(&[0x0001_030D]).unwrap_err().key,
            "k40t_allow"
        );
    }

    #[test]
    fn gcs_ids_are_up_to_eight_non_zero_ids() {
        assert!(SystemIds::DEFAULT.contains(255) && SystemIds::DEFAULT.contains(245));
        assert!(!SystemIds::DEFAULT.contains(1));
        let ids = SystemIds::from_list(&[7, 9]).unwrap();
        assert_eq!(ids.as_slice(), &[7, 9]);
        assert_eq!(SystemIds::from_list(&[0]).unwrap_err().key, "gcs_ids");
        assert_eq!(SystemIds::from_list(&[256]).unwrap_err().key, "gcs_ids");
        assert_eq!(SystemIds::from_list(&[1; 9]).unwrap_err().key, "gcs_ids");
        assert_eq!(SystemIds::from_list(&[]).unwrap(), SystemIds::NONE);
    }
}
