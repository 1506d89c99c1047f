//! The streams and stages the instruction-count benchmarks (`benches/codec.rs`, run by
//! `scripts/bench`) measure, and the table `scripts/bench` prints (`bench-table`).
//!
//! Per protocol, one fixed mixed stream of valid frames (K40T and SIYI: every catalogue
//! message, eight rounds, deterministic pseudo-random payloads; Viewlink and GCU: the
//! documents' example frames, eight rounds, and the GCU's answers to them), measured at
//! four stages:
//! - **checksum**: the protocol's checksum over each frame's covered bytes, the frames
//!   located by a precomputed table: the floor under any deframer;
//! - **deframe**: a [`Deframer`] fed 64-byte chunks, as a UART DMA buffer delivers them;
//! - **decode**: `Packet::decode` of each frame (checksum verified again);
//! - **decode + encode**: decode, then `Packet::emit`.
//!
//! And side by side, rust-mavlink (`mavlink` crate, common dialect, as a dev-dependency of
//! the benchmark) reading a MAVLink v2 stream with the K40T stream's frame count and
//! payload lengths, through the same 64-byte reads: its raw-frame reader
//! (`MavlinkReader::read_raw_message`) and its full parse (`read_message`). The MAVLink
//! stream is built in `benches/codec.rs`, where the dev-dependency is.
//!
//! The bridge engine's runs are in [`bridge`] and [`camera`], the floor under signing in
//! [`signing`].

pub mod bridge;
pub mod camera;
pub mod signing;

use std::ops::Range;

use protocol_core::wire::{Deframer, Event, Framing};

/// UART-sized pieces: the deframer is fed, and rust-mavlink reads, at most this many
/// bytes at a time.
pub const CHUNK: usize = 64;

/// Rounds of each protocol's frame set in its stream.
const ROUNDS: usize = 8;

/// A byte stream of valid frames, with where each frame is and which bytes its
/// checksum covers.
#[derive(Debug, Clone)]
pub struct Stream {
    /// The bytes.
    pub bytes: Vec<u8>,
    /// Each frame's range in `bytes`.
    pub frames: Vec<Range<usize>>,
    /// Each frame's checksummed bytes, as a range in `bytes`.
    pub covered: Vec<Range<usize>>,
}

impl Stream {
    fn new(frames: &[Vec<u8>], covered: impl Fn(&[u8]) -> Range<usize>) -> Self {
        let mut s = Stream {
            bytes: Vec::new(),
            frames: Vec::new(),
            covered: Vec::new(),
        };
        for f in frames {
            let at = s.bytes.len();
            let c = covered(f);
            s.frames.push(at..at + f.len());
            s.covered.push(at + c.start..at + c.end);
            s.bytes.extend_from_slice(f);
        }
        s
    }

    /// The frames, each as a slice.
    pub fn frames(&self) -> impl Iterator<Item = &[u8]> {
        self.frames.iter().map(|r| &self.bytes[r.clone()])
    }

    /// Each frame's payload length (K40T: the LEN byte).
    pub fn payload_lens(&self) -> impl Iterator<Item = usize> + '_ {
        self.frames().map(|f| usize::from(f[1]))
    }
}

/// A deterministic byte generator (xorshift), so that every run measures the same bytes.
struct Rng(u64);

impl Rng {
    fn byte(&mut self) -> u8 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 24) as u8
    }

    fn fill(&mut self, n: usize) -> Vec<u8> {
        (0..n).map(|_| self.byte()).collect()
    }
}

/// Counts the frames a deframer finds in `stream`, fed in [`CHUNK`]-byte pieces.
#[inline(always)]
pub fn deframe<F: Framing, const N: usize>(framing: F, stream: &[u8]) -> usize {
    let mut d = Deframer::<F, N>::new(framing);
    let mut n = 0;
    for chunk in stream.chunks(CHUNK) {
        d.push(chunk, |e| n += usize::from(matches!(e, Event::Frame(_))));
    }
    n
}

/// The K40T stream: every message of the catalogue (request, ACK, status), eight rounds,
/// pseudo-random payloads of each layout's length.
#[must_use]
pub fn k40t_stream() -> Stream {
    use protocol_core::k40t::*;
    let mut rng = Rng(0x4B34_3054);
    let mut frames = Vec::new();
    for round in 0..ROUNDS as u8 {
        for e in CATALOG {
            for (kind, has) in [
                (Kind::Request, true),
                (Kind::Ack, e.ack),
                (Kind::Status, e.status),
            ] {
                if !has {
                    continue;
                }
                let id = MsgId::new(kind, e.base);
                let len = Message::decode(id, &[]).map_or(0, |m| m.payload_len());
                let payload = rng.fill(len);
                let message = Message::decode(id, &payload).expect("a payload of its length");
                let p = Packet {
                    header: Header::new(Address::FLIGHT_CONTROLLER, Address::POD, round),
                    message,
                };
                let mut buf = [0u8; MAX_FRAME_LEN];
                let n = p.emit(&mut buf).expect("emit");
                frames.push(buf[..n].to_vec());
            }
        }
    }
    Stream::new(&frames, |f| 1..f.len() - 2)
}

/// The SIYI stream: every command in both directions (the shortest data length each
/// accepts), eight rounds.
#[must_use]
pub fn siyi_stream() -> Stream {
    use protocol_core::Direction;
    use protocol_core::siyi::*;
    let mut rng = Rng(0x5349_5949);
    let mut frames = Vec::new();
    for round in 0..ROUNDS as u16 {
        for e in CATALOG {
            for direction in [Direction::ToGimbal, Direction::FromGimbal] {
                let data = rng.fill(DEFAULT_MAX_PAYLOAD_LEN);
                let Some(message) = (0..=DEFAULT_MAX_PAYLOAD_LEN)
                    .find_map(|len| Message::decode(e.id, &data[..len], direction).ok())
                else {
                    continue;
                };
                let header = match direction {
                    Direction::ToGimbal => Header::request(round),
                    Direction::FromGimbal => Header::reply(round),
                };
                let p = Packet { header, message };
                let mut buf = [0u8; DEFAULT_MAX_FRAME_LEN];
                let n = p.emit(&mut buf).expect("emit");
                frames.push(buf[..n].to_vec());
            }
        }
    }
    Stream::new(&frames, |f| 0..f.len() - 2)
}

/// The verified example frames of a protocol's document that start with `sync`, eight
/// rounds.
fn vectors(protocol: &'static str, sync: &[u8]) -> Vec<Vec<u8>> {
    let frames: Vec<Vec<u8>> = codec_cases::vectors(protocol)
        .filter(|v| v.verified && v.bytes.starts_with(sync))
        .map(|v| v.bytes.to_vec())
        .collect();
    assert!(!frames.is_empty(), "no {protocol} vectors");
    frames
        .iter()
        .cycle()
        .take(frames.len() * ROUNDS)
        .cloned()
        .collect()
}

/// The Viewlink stream: the document's serial frames (`55 AA DC`), eight rounds.
#[must_use]
pub fn viewlink_stream() -> Stream {
    Stream::new(&vectors("Viewlink", &[0x55, 0xAA, 0xDC]), |f| {
        3..f.len() - 1
    })
}

/// The GCU host stream: the document's host packages, eight rounds.
#[must_use]
pub fn gcu_host_stream() -> Stream {
    use protocol_core::gcu::HOST_SYNC;
    Stream::new(&vectors("GCU", &HOST_SYNC), |f| 0..f.len() - 2)
}

/// The GCU reply stream: the GCU's answer to each host package.
#[must_use]
pub fn gcu_reply_stream() -> Stream {
    use protocol_core::gcu::*;
    let host = gcu_host_stream();
    let replies: Vec<Vec<u8>> = host
        .frames()
        .map(|f| {
            let request = HostPacket::decode(f).expect("host package");
            let frames = GcuFrames {
                main: GcuMain {
                    mode: GimbalMode::from_value(0x11),
                    ..GcuMain::default()
                },
                sub: GcuSub::ABSENT,
            };
            let reply = request.answer(frames, Execution::Success);
            let mut buf = [0u8; MAX_FRAME_LEN];
            let n = reply.emit(&mut buf).expect("emit reply");
            buf[..n].to_vec()
        })
        .collect();
    Stream::new(&replies, |f| 0..f.len() - 2)
}

/// The MAVLink 2 stream: every message of the bridge's set (`protocol_core::mavlink::
/// CATALOG`), eight rounds, pseudo-random field values (enumerations among their listed
/// values), encoded by `protocol_core::mavlink::encode` (payload truncated as MAVLink 2
/// sends it); and the messages with their headers, for the encoders.
#[must_use]
pub fn mavlink_stream() -> (
    Stream,
    Vec<(
        protocol_core::mavlink::Header,
        protocol_core::mavlink::MavMessage,
    )>,
) {
    use fuzz_checks::mavlink::{enum_runs, typed_payload};
    use protocol_core::mavlink::{self, CATALOG, Header, MAX_FRAME_LEN, dialect};
    let mut rng = Rng(0x4D41_564C);
    let mut frames = Vec::new();
    let mut messages = Vec::new();
    for round in 0..ROUNDS as u8 {
        for (k, &id) in CATALOG.iter().enumerate() {
            let bytes = rng.fill(255);
            let payload = typed_payload(id, &bytes, enum_runs(id));
            let message = dialect::decode(id, &payload).expect("a typed payload");
            let header = Header {
                sequence: round.wrapping_mul(32).wrapping_add(k as u8),
                system_id: 1,
                component_id: 154,
            };
            let mut buf = [0u8; MAX_FRAME_LEN];
            let n = mavlink::encode(&message, &header, &mut buf).expect("encode");
            frames.push(buf[..n].to_vec());
            messages.push((header, message));
        }
    }
    // CRC covers LEN to the end of the payload.
    let stream = Stream::new(&frames, |f| 1..f.len() - 2);
    (stream, messages)
}
