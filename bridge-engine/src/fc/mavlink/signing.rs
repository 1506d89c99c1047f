//! MAVLink 2 signing on one link (the MAVLink side's, or the telemetry link), after the
//! MAVLink specification's "Message Signing": the key in use, the timestamp the bridge
//! signs with, and the last timestamp of each stream that signed to it (see
//! docs/src/security.md).
//!
//! - **Checking.** A signed frame counts only if its signature is the key's and its
//!   timestamp is newer than the last of its stream (link id, system, component); a new
//!   stream's first timestamp may be at most a minute older than the bridge's own. The
//!   streams are a fixed table of [`STREAMS`]: when it is full the stream with the oldest
//!   timestamp makes room, and its last timestamp becomes a floor that every new stream's
//!   first must pass, so that an evicted stream is no fresh one (its captured frames stay
//!   replays).
//! - **Signing.** Every frame is signed with a timestamp above the last one used and at
//!   least the bridge's UTC (once known) and the newest accepted from the link, so it never
//!   goes back.
//! - **Across restarts** (the specification's timestamp handling). The timestamp is saved
//!   in the bridge's store ([`crate::store`]) whenever it has gone [`SAVE_STEP`] past the
//!   last one saved, at most once every [`SAVE_MIN_INTERVAL`], and restored at start plus
//!   [`RESTORE_MARGIN`] (more than it can have moved since its last save): the bridge's
//!   timestamps never go below a previous run's, and a frame older than the saved
//!   timestamp is stale or a replay after a restart. A key set by SETUP_SIGNING is saved at
//!   once. With nothing restored (a blank store), before UTC is known and before a signed
//!   frame was accepted on the link, the bridge has no timestamp it can vouch for and
//!   sends its frames unsigned; it speaks only after the autopilot's HEARTBEAT, whose
//!   signature carries the autopilot's timestamp.

use crate::Config;
use crate::access::{Refusal, SigningMode};
use crate::store::{self, Key, Problem, Record};
use crate::time::{Duration, Instant, UtcTime};
use protocol_core::mavlink::{
    Frame, SecretKey, Signer, TIMESTAMP_PER_S, signature_matches, timestamp_of_unix_micros,
};

/// Streams whose timestamps are kept.
pub(super) const STREAMS: usize = 8;
/// How much older than the bridge's timestamp a new stream's first may be: a minute.
const NEW_STREAM_WINDOW: u64 = 60 * TIMESTAMP_PER_S;
/// The timestamp is saved when it has gone this far past the last one saved (the
/// specification: at least once a minute while it moves).
pub(crate) const SAVE_STEP: u64 = 30 * TIMESTAMP_PER_S;
/// Saves of the timestamp are at least this far apart (a bound on the store's wear,
/// whatever the link does).
pub(crate) const SAVE_MIN_INTERVAL: Duration = Duration::from_secs(5);
/// Added to the restored timestamp at start: more than the timestamp can have moved
/// since it was last saved ([`SAVE_STEP`], and what 5 s add).
pub(crate) const RESTORE_MARGIN: u64 = 60 * TIMESTAMP_PER_S;
/// The label of a configured key's fingerprint ([`LinkSigning::fingerprint`]).
const FINGERPRINT_LABEL: &[u8] = b"k40t bridge: the configured signing key";

/// One stream (link id, system, component) and its last accepted timestamp, packed
/// (48 bits, little-endian; all zero: a free slot).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct Stream {
    ids: [u8; 3],
    timestamp: [u8; 6],
}

impl Stream {
    fn new(ids: [u8; 3], timestamp: u64) -> Self {
        let [t0, t1, t2, t3, t4, t5, _, _] = timestamp.to_le_bytes();
        Stream {
            ids,
            timestamp: [t0, t1, t2, t3, t4, t5],
        }
    }

    fn timestamp(&self) -> u64 {
        let [t0, t1, t2, t3, t4, t5] = self.timestamp;
        u64::from_le_bytes([t0, t1, t2, t3, t4, t5, 0, 0])
    }

    fn is_free(&self) -> bool {
        *self == Stream::default()
    }
}

/// What a received frame is, as far as signing goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Check {
    /// Signed with the key, newer than its stream's last: taken.
    Signed,
    /// Unsigned, or signing is off: the caller decides by the mode.
    Unsigned,
    /// Signed, and not to be taken.
    Refused(Refusal),
}

/// Signing on one link.
#[derive(Debug, Clone)]
pub(crate) struct LinkSigning {
    mode: SigningMode,
    key: Option<SecretKey>,
    /// The configured key's fingerprint (a key set by SETUP_SIGNING is kept under it).
    configured: [u8; 6],
    /// The link id the bridge's signatures name.
    link_id: u8,
    /// The last timestamp the bridge used or accepted (0: none yet).
    timestamp: u64,
    /// A new stream's first timestamp must be above this: the last timestamp of every
    /// stream the table evicted, and the timestamp restored at start.
    floor: u64,
    streams: [Stream; STREAMS],
    /// The timestamp last handed to the store, and when.
    saved: u64,
    saved_at: Option<Instant>,
    /// A timestamp was restored, or its absence reported.
    restore_seen: bool,
}

impl LinkSigning {
    /// Signing as `config` says, signatures naming `link_id`.
    pub(super) fn new(config: &Config, link_id: u8) -> Self {
        let key = config.signing_key.map(|k| SecretKey::new(k.0));
        LinkSigning {
            mode: config.signing,
            key,
            configured: Self::fingerprint(key.as_ref()),
            link_id,
            timestamp: 0,
            floor: 0,
            streams: [Stream::default(); STREAMS],
            saved: 0,
            saved_at: None,
            restore_seen: false,
        }
    }

    /// A key's fingerprint: 48 bits of SHA-256 over it and a label, which tell keys apart
    /// and say nothing of them (no key: the zero key's).
    fn fingerprint(key: Option<&SecretKey>) -> [u8; 6] {
        let zero = SecretKey::new([0; 32]);
        protocol_core::mavlink::signature_value(key.unwrap_or(&zero), FINGERPRINT_LABEL)
    }

    /// The fingerprint of a configured key (`None`: no key), as the console shows it.
    pub(crate) fn key_fingerprint(key: Option<&crate::access::SigningKey>) -> Option<[u8; 6]> {
        key.map(|k| Self::fingerprint(Some(&SecretKey::new(k.0))))
    }

    /// The link signs or checks: its timestamp is worth keeping.
    pub(crate) fn active(&self) -> bool {
        self.mode != SigningMode::Off && self.key.is_some()
    }

    /// Whether the timestamp is due to be saved at `now` (see the module documentation);
    /// when it is, it counts as saved from now.
    pub(crate) fn save_due(&mut self, now: Instant) -> bool {
        let due = self.active()
            && self.timestamp >= self.saved.saturating_add(SAVE_STEP)
            && self
                .saved_at
                .is_none_or(|t| now.saturating_duration_since(t) >= SAVE_MIN_INTERVAL);
        if due {
            self.saved = self.timestamp;
            self.saved_at = Some(now);
        }
        due
    }

    /// The record of `key` (the timestamp's or the key's) as it stands.
    pub(crate) fn record(&self, key: Key) -> Record {
        if key == Key::SIGNING_KEY_FC || key == Key::SIGNING_KEY_TELEMETRY {
            let k = self.key.filter(|_| self.mode != SigningMode::Off);
            Record::signing_key(key, k.map(|k| *k.as_bytes()), self.configured)
        } else {
            Record::timestamp(key, self.timestamp.max(self.saved))
        }
    }

    /// A stored signing timestamp: the bridge's own from now on is above it by
    /// [`RESTORE_MARGIN`], and no new stream may start at or below it.
    pub(crate) fn restore_timestamp(&mut self, value: &[u8]) -> Result<(), Problem> {
        self.restore_seen = true;
        let stored = store::decode_timestamp(value)?;
        if stored > protocol_core::mavlink::MAX_TIMESTAMP {
            return Err(Problem::Value);
        }
        self.timestamp = self.timestamp.max(stored.saturating_add(RESTORE_MARGIN));
        self.floor = self.floor.max(stored);
        self.saved = stored;
        Ok(())
    }

    /// A stored key (set by SETUP_SIGNING, or signing turned off by it): used when it was
    /// written under the key configured now.
    pub(crate) fn restore_key(&mut self, value: &[u8]) -> Result<(), Problem> {
        let (key, under) = store::decode_signing_key(value)?;
        if under != self.configured {
            return Err(Problem::Superseded);
        }
        match key {
            Some(k) => {
                self.key = Some(SecretKey::new(k));
                if self.mode == SigningMode::Off {
                    self.mode = SigningMode::Sign;
                }
            }
            None => self.key = None,
        }
        Ok(())
    }

    /// Whether a missing timestamp record is to be reported (once; only while the link
    /// signs or checks).
    pub(crate) fn restore_missing(&mut self) -> bool {
        let missing = !self.restore_seen && self.active();
        self.restore_seen = true;
        missing
    }

    /// Unsigned frames are refused (commands always, the rest unless configured).
    pub(crate) fn required(&self) -> bool {
        self.mode == SigningMode::Require && self.key.is_some()
    }

    /// Checks a received frame's signature and timestamp (a frame taken updates its
    /// stream and the bridge's timestamp).
    pub(super) fn check(&mut self, frame: &[u8], utc: Option<UtcTime>) -> Check {
        let view = Frame::new_unchecked(frame);
        let (Some(key), Some(sig)) = (
            self.key.filter(|_| self.mode != SigningMode::Off),
            view.signature(),
        ) else {
            return Check::Unsigned;
        };
        if !signature_matches(frame, &key) {
            return Check::Refused(Refusal::BadSignature);
        }
        let ids = [sig.link_id, view.system_id(), view.component_id()];
        let slot = self
            .streams
            .iter()
            .position(|s| !s.is_free() && s.ids == ids);
        match slot.and_then(|i| self.streams.get(i)) {
            Some(s) if sig.timestamp <= s.timestamp() => {
                return Check::Refused(Refusal::Replayed);
            }
            Some(_) => {}
            None => {
                let local = self.local_timestamp(utc);
                if sig.timestamp.saturating_add(NEW_STREAM_WINDOW) < local {
                    return Check::Refused(Refusal::Stale);
                }
                // Not above an evicted stream's last (or the restored timestamp): it
                // may be that stream's, replayed.
                if sig.timestamp <= self.floor {
                    return Check::Refused(Refusal::Replayed);
                }
            }
        }
        let i = slot.unwrap_or_else(|| self.room());
        if let Some(s) = self.streams.get_mut(i) {
            if !s.is_free() && slot.is_none() {
                self.floor = self.floor.max(s.timestamp());
            }
            *s = Stream::new(ids, sig.timestamp);
        }
        self.timestamp = self.timestamp.max(sig.timestamp);
        Check::Signed
    }

    /// A free slot, or the one whose stream signed longest ago.
    fn room(&self) -> usize {
        self.streams
            .iter()
            .enumerate()
            .min_by_key(|(_, s)| {
                if s.is_free() {
                    0
                } else {
                    s.timestamp().saturating_add(1)
                }
            })
            .map_or(0, |(i, _)| i)
    }

    /// The bridge's timestamp now: the last used or accepted, and its UTC.
    fn local_timestamp(&self, utc: Option<UtcTime>) -> u64 {
        let from_utc = utc.map_or(0, |u| timestamp_of_unix_micros(u.as_unix_micros()));
        self.timestamp.max(from_utc)
    }

    /// The signer of the next frame (`None`: unsigned, signing off or no timestamp the
    /// bridge can vouch for yet; see the module documentation). Each call uses a new
    /// timestamp.
    pub(super) fn next_signer(&mut self, utc: Option<UtcTime>) -> Option<Signer<'_>> {
        if self.mode == SigningMode::Off {
            return None;
        }
        let key = self.key.as_ref()?;
        let local = self
            .timestamp
            .max(utc.map_or(0, |u| timestamp_of_unix_micros(u.as_unix_micros())));
        if local == 0 {
            return None;
        }
        let timestamp = self.timestamp.saturating_add(1).max(local);
        self.timestamp = timestamp;
        Some(Signer {
            key,
            link_id: self.link_id,
            timestamp,
        })
    }

    /// SETUP_SIGNING: a new key from now (all zero with timestamp 0: signing off on this
    /// link until the next reboot), the timestamp at least `initial`, every stream
    /// forgotten. Returns whether a key is in use.
    pub(super) fn set_key(&mut self, key: [u8; 32], initial: u64) -> bool {
        let key = SecretKey::new(key);
        if key.is_zero() && initial == 0 {
            self.key = None;
        } else {
            self.key = Some(key);
            if self.mode == SigningMode::Off {
                self.mode = SigningMode::Sign;
            }
        }
        self.timestamp = self.timestamp.max(initial);
        self.streams = [Stream::default(); STREAMS];
        self.key.is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::access::SigningKey;
    use protocol_core::mavlink::dialect::{
        HEARTBEAT_DATA, MavAutopilot, MavModeFlag, MavState, MavType,
    };
    use protocol_core::mavlink::{self, Header, MAX_FRAME_LEN, MavMessage, encode_signed};

    const KEY: [u8; 32] = [7; 32];

    fn signing(mode: SigningMode) -> LinkSigning {
        let mut c = Config::DEFAULT;
        c.signing = mode;
        c.signing_key = Some(SigningKey(KEY));
        LinkSigning::new(&c, 0)
    }

    fn frame(key: [u8; 32], link_id: u8, sysid: u8, timestamp: u64) -> Vec<u8> {
        let hb = MavMessage::HEARTBEAT(HEARTBEAT_DATA {
            custom_mode: 0,
            mavtype: MavType::MAV_TYPE_QUADROTOR,
            autopilot: MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA,
            base_mode: MavModeFlag::empty(),
            system_status: MavState::MAV_STATE_ACTIVE,
            mavlink_version: 3,
        });
        let header = Header {
            sequence: 0,
            system_id: sysid,
            component_id: 1,
        };
        let key = SecretKey::new(key);
        let signer = Signer {
            key: &key,
            link_id,
            timestamp,
        };
        let mut buf = [0u8; MAX_FRAME_LEN];
        let n = encode_signed(&hb, &header, &signer, &mut buf).unwrap();
        buf[..n].to_vec()
    }

    const T0: u64 = 3_500_000_000_000;

    #[test]
    fn frames_are_taken_once_in_order_within_the_window() {
        let mut s = signing(SigningMode::Require);
        assert!(s.required());
        assert_eq!(s.check(&frame(KEY, 0, 1, T0), None), Check::Signed);
        // Replayed, or older: refused; newer: taken.
        assert_eq!(
            s.check(&frame(KEY, 0, 1, T0), None),
            Check::Refused(Refusal::Replayed)
        );
        assert_eq!(
            s.check(&frame(KEY, 0, 1, T0 - 1), None),
            Check::Refused(Refusal::Replayed)
        );
        assert_eq!(s.check(&frame(KEY, 0, 1, T0 + 1), None), Check::Signed);
        // Another key: refused.
        assert_eq!(
            s.check(&frame([8; 32], 0, 1, T0 + 2), None),
            Check::Refused(Refusal::BadSignature)
        );
        // A new stream (another link id) within the minute: taken; older: stale.
        assert_eq!(
            s.check(&frame(KEY, 1, 1, T0 - 59 * TIMESTAMP_PER_S), None),
            Check::Signed
        );
        assert_eq!(
            s.check(&frame(KEY, 2, 1, T0 - 61 * TIMESTAMP_PER_S), None),
            Check::Refused(Refusal::Stale)
        );
        // Unsigned frames: the caller's to judge.
        let mut buf = [0u8; MAX_FRAME_LEN];
        let signed = frame(KEY, 0, 1, T0);
        let hb = mavlink::Packet::decode(&signed).unwrap();
        let n = mavlink::Packet::new(hb.header, hb.message)
            .emit(&mut buf)
            .unwrap();
        assert_eq!(s.check(&buf[..n], None), Check::Unsigned);
    }

    #[test]
    fn a_full_table_makes_room_for_new_streams() {
        let mut s = signing(SigningMode::Sign);
        for sysid in 1..=20u8 {
            let t = T0 + u64::from(sysid);
            assert_eq!(s.check(&frame(KEY, 0, sysid, t), None), Check::Signed);
        }
        // The newest streams are remembered.
        assert_eq!(
            s.check(&frame(KEY, 0, 20, T0 + 20), None),
            Check::Refused(Refusal::Replayed)
        );
    }

    #[test]
    fn the_timestamp_never_goes_back() {
        let mut s = signing(SigningMode::Sign);
        // No UTC, nothing accepted: nothing to vouch for.
        assert!(s.next_signer(None).is_none());
        let utc = UtcTime::from_unix_micros(1_767_225_600_000_000);
        let from_utc = timestamp_of_unix_micros(utc.as_unix_micros());
        let a = s.next_signer(Some(utc)).unwrap().timestamp;
        assert_eq!(a, from_utc);
        let b = s.next_signer(Some(utc)).unwrap().timestamp;
        assert_eq!(b, a + 1);
        // UTC steps back a second (a leap second, a corrected clock): still forward.
        let back = UtcTime::from_unix_micros(utc.as_unix_micros() - 1_000_000);
        assert_eq!(s.next_signer(Some(back)).unwrap().timestamp, b + 1);
        // An accepted frame from the future pulls it forward.
        let ahead = from_utc + 500 * TIMESTAMP_PER_S;
        assert_eq!(s.check(&frame(KEY, 0, 1, ahead), None), Check::Signed);
        assert_eq!(s.next_signer(None).unwrap().timestamp, ahead + 1);
        // Off: nothing signed, nothing checked.
        let mut off = signing(SigningMode::Off);
        assert!(off.next_signer(Some(utc)).is_none());
        assert_eq!(off.check(&frame([9; 32], 0, 1, 5), None), Check::Unsigned);
    }

    #[test]
    fn setup_signing_changes_the_key_or_turns_it_off() {
        let mut s = signing(SigningMode::Require);
        assert_eq!(s.check(&frame(KEY, 0, 1, T0), None), Check::Signed);
        assert!(s.set_key([3; 32], T0 + 10));
        assert_eq!(
            s.check(&frame(KEY, 0, 1, T0 + 20), None),
            Check::Refused(Refusal::BadSignature)
        );
        assert_eq!(s.check(&frame([3; 32], 0, 1, T0 + 20), None), Check::Signed);
        assert!(!s.set_key([0; 32], 0));
        assert!(!s.required());
        assert!(s.next_signer(None).is_none());
    }
}
