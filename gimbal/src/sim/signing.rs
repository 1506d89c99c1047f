//! A signed MAVLink link around any simulated MAVLink peer ([`Signed`]): what the peer
//! sends leaves signed with the link's key (a signing autopilot, ArduPilot with a key
//! set up), what reaches it is checked (how many frames were signed with the key, badly,
//! or not at all); and an attacker's hand on the same wire ([`Signed::inject`]).
//!
//! The peer itself is unchanged: it reads signed frames as any MAVLink 2 receiver does.
//! The signature's timestamp is the peer's UTC (`utc_at_zero_us` plus true time) in the
//! signing units, one more than the last when that is not later.

use std::ops::{Deref, DerefMut};

use protocol_core::mavlink::{
    MAX_FRAME_LEN, MavlinkFraming, Packet, SecretKey, Signer, signature_matches,
    timestamp_of_unix_micros,
};
use protocol_core::wire::{Deframer, Event};

use super::peer::Peer;

/// What [`Signed`] saw of the frames that reached its peer.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SignedStats {
    /// Signed with the link's key.
    pub good: u64,
    /// Signed, not with the key.
    pub bad: u64,
    /// Not signed.
    pub unsigned: u64,
    /// Signed frames whose timestamp was not above the last one from the same sender.
    pub backwards: u64,
}

/// `P` on a signed link. Derefs to `P`.
pub struct Signed<P> {
    /// The peer.
    pub inner: P,
    key: SecretKey,
    /// Sign what the peer sends (false: an unsigned autopilot on the same wire).
    pub sign_outgoing: bool,
    utc_at_zero_us: u64,
    last_timestamp: u64,
    to_peer: Deframer<MavlinkFraming, MAX_FRAME_LEN>,
    from_peer: Deframer<MavlinkFraming, MAX_FRAME_LEN>,
    /// Last timestamp seen per (system, component) of signed frames to the peer.
    seen: std::collections::BTreeMap<(u8, u8), u64>,
    stats: SignedStats,
    injected: Vec<(u64, Vec<u8>)>,
    /// Every signed frame that reached the peer (an attacker's recording).
    pub recorded: Vec<Vec<u8>>,
}

impl<P> Signed<P> {
    /// `inner` on a link signed with `key`; its UTC is `utc_at_zero_us` at true time 0.
    pub fn new(inner: P, key: [u8; 32], utc_at_zero_us: u64) -> Self {
        Signed {
            inner,
            key: SecretKey::new(key),
            sign_outgoing: true,
            utc_at_zero_us,
            last_timestamp: 0,
            to_peer: Deframer::new(MavlinkFraming::delivering_unknown_ids()),
            from_peer: Deframer::new(MavlinkFraming::delivering_unknown_ids()),
            seen: std::collections::BTreeMap::new(),
            stats: SignedStats::default(),
            injected: Vec::new(),
            recorded: Vec::new(),
        }
    }

    /// What reached the peer so far.
    #[must_use]
    pub fn stats(&self) -> SignedStats {
        self.stats
    }

    /// Puts `bytes` on the wire to the bridge at `at_us`, as an attacker would.
    pub fn inject(&mut self, at_us: u64, bytes: Vec<u8>) {
        self.injected.push((at_us, bytes));
    }

    /// `frame` signed with `key` (the link's, or another) at timestamp `timestamp`.
    #[must_use]
    pub fn sign_with(frame: &[u8], key: [u8; 32], timestamp: u64) -> Vec<u8> {
        let key = SecretKey::new(key);
        let signer = Signer {
            key: &key,
            link_id: 0,
            timestamp,
        };
        let mut buf = [0u8; MAX_FRAME_LEN];
        Packet::decode(frame)
            .ok()
            .and_then(|p| p.emit_signed(&signer, &mut buf).ok())
            .map_or_else(Vec::new, |n| buf[..n].to_vec())
    }

    /// The peer's signing timestamp at true time `now_us`.
    #[must_use]
    pub fn timestamp_at(&self, now_us: u64) -> u64 {
        timestamp_of_unix_micros(self.utc_at_zero_us + now_us)
    }

    fn sign(&mut self, now_us: u64, bytes: &[u8]) -> Vec<u8> {
        let mut out = Vec::with_capacity(bytes.len() + 16);
        let mut frames = Vec::new();
        self.from_peer.push(bytes, |ev| {
            if let Event::Frame(f) = ev {
                frames.push(f.to_vec());
            }
        });
        for f in frames {
            let t = self.timestamp_at(now_us).max(self.last_timestamp + 1);
            self.last_timestamp = t;
            let mut buf = [0u8; MAX_FRAME_LEN];
            let signer = Signer {
                key: &self.key,
                link_id: 0,
                timestamp: t,
            };
            match Packet::decode(&f)
                .ok()
                .map(|p| p.emit_signed(&signer, &mut buf))
            {
                Some(Ok(n)) => out.extend_from_slice(&buf[..n]),
                _ => out.extend_from_slice(&f),
            }
        }
        out
    }
}

impl<P> Deref for Signed<P> {
    type Target = P;
    fn deref(&self) -> &P {
        &self.inner
    }
}

impl<P> DerefMut for Signed<P> {
    fn deref_mut(&mut self) -> &mut P {
        &mut self.inner
    }
}

impl<P: Peer> Peer for Signed<P> {
    fn receive(&mut self, now_us: u64, bytes: &[u8]) {
        let key = self.key;
        let (stats, seen, recorded) = (&mut self.stats, &mut self.seen, &mut self.recorded);
        self.to_peer.push(bytes, |ev| {
            let Event::Frame(f) = ev else { return };
            let view = protocol_core::mavlink::Frame::new_unchecked(f);
            let Some(sig) = view.signature() else {
                stats.unsigned += 1;
                return;
            };
            if signature_matches(f, &key) {
                stats.good += 1;
                recorded.push(f.to_vec());
            } else {
                stats.bad += 1;
            }
            let last = seen
                .entry((view.system_id(), view.component_id()))
                .or_insert(0);
            if sig.timestamp <= *last {
                stats.backwards += 1;
            }
            *last = (*last).max(sig.timestamp);
        });
        self.inner.receive(now_us, bytes);
    }

    fn poll(&mut self, now_us: u64) {
        self.inner.poll(now_us);
    }

    fn next_wakeup(&self) -> u64 {
        let injected = self.injected.iter().map(|(t, _)| *t).min();
        injected.map_or(self.inner.next_wakeup(), |t| {
            t.min(self.inner.next_wakeup())
        })
    }

    fn transmit(&mut self, now_us: u64) -> Vec<(u64, Vec<u8>)> {
        let mut out: Vec<(u64, Vec<u8>)> = self
            .inner
            .transmit(now_us)
            .into_iter()
            .map(|(at, bytes)| {
                if self.sign_outgoing {
                    (at, self.sign(at, &bytes))
                } else {
                    (at, bytes)
                }
            })
            .collect();
        let (due, later): (Vec<_>, Vec<_>) =
            self.injected.drain(..).partition(|(t, _)| *t <= now_us);
        self.injected = later;
        out.extend(due.into_iter().map(|(_, b)| (now_us, b)));
        out
    }
}
