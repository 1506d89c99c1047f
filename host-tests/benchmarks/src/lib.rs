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

use std::ops::Range;

use bridge_engine::Port;
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

/// The bridge engine at work on a prepared input: an engine already running (pod link
/// up, FC link up), and the frames to give it, one at a time, `step` apart (more than
/// the pod driver's motion interval, so that every command goes out).
#[derive(Debug)]
pub struct BridgeRun {
    /// The engine.
    pub engine: bridge_engine::Engine,
    /// The frames, in order.
    pub frames: Vec<Vec<u8>>,
    /// They come from the FC (else from the pod).
    pub from_fc: bool,
    /// The local time.
    pub now: bridge_engine::Instant,
    /// Time between two frames.
    pub step: bridge_engine::Duration,
}

/// Rounds of bridge frames (each a frame per benchmark round).
const BRIDGE_FRAMES: usize = 64;

impl BridgeRun {
    /// Gives each frame to the engine at its instant, then takes every frame it queued
    /// (as a driver does). Returns (frames for the pod, frames for the FC).
    pub fn run(&mut self) -> (usize, usize) {
        let (mut pod, mut fc) = (0, 0);
        let mut buf = [0u8; 256];
        for f in &self.frames {
            self.now = self.now.saturating_add(self.step);
            let port = if self.from_fc { Port::Fc } else { Port::Pod };
            self.engine.receive(self.now, port, f);
            while self.engine.transmit(Port::Pod, &mut buf).is_some() {
                pod += 1;
            }
            while self.engine.transmit(Port::Fc, &mut buf).is_some() {
                fc += 1;
            }
            while self.engine.next_event().is_some() {}
        }
        (pod, fc)
    }
}

/// A K40T gimbal attitude report from the pod (yaw in 0.01°).
fn pod_attitude(seq: u8, yaw_cdeg: i16) -> Vec<u8> {
    use bridge_engine::Config;
    use protocol_core::k40t::*;
    let c = Config::DEFAULT.pod;
    let mut payload = [0u8; 32];
    payload[..2].copy_from_slice(&yaw_cdeg.to_le_bytes());
    let len = Message::decode(GimbalAttitude::ID, &[]).map_or(0, |m| m.payload_len());
    let message = Message::decode(GimbalAttitude::ID, &payload[..len]).expect("attitude");
    let p = Packet {
        header: Header::new(c.gimbal, c.own, seq),
        message,
    };
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = p.emit(&mut buf).expect("emit");
    buf[..n].to_vec()
}

/// A SIYI engine with the pod and FC links up (an attitude report, a heartbeat), its
/// queues empty.
fn siyi_engine() -> BridgeRun {
    use bridge_engine::{Config, Duration, Engine, FcProtocol, Instant};
    let mut run = BridgeRun {
        engine: Engine::new(Config {
            fc: FcProtocol::Siyi,
            ..Config::DEFAULT
        }),
        frames: vec![pod_attitude(0, 0)],
        from_fc: false,
        now: Instant::from_millis(1000),
        step: Duration::from_millis(150),
    };
    run.run();
    run.frames = vec![siyi_rate(0, 0)];
    run.from_fc = true;
    run.run();
    run
}

/// A SIYI 0x07 gimbal rotation request (speeds -100..100).
fn siyi_rate(seq: u16, speed: i8) -> Vec<u8> {
    use protocol_core::Direction;
    use protocol_core::siyi::*;
    let [s] = speed.to_le_bytes();
    let data = [s, s];
    let message = Message::decode(0x07, &data, Direction::ToGimbal).expect("0x07");
    let p = Packet {
        header: Header::request(seq),
        message,
    };
    let mut buf = [0u8; DEFAULT_MAX_FRAME_LEN];
    let n = p.emit(&mut buf).expect("emit");
    buf[..n].to_vec()
}

/// SIYI rate commands (0x07) from the FC, the speed changing every frame: each one
/// translated into a K40T gimbal control for the pod.
#[must_use]
pub fn bridge_siyi_rates() -> BridgeRun {
    let mut run = siyi_engine();
    run.frames = (0..BRIDGE_FRAMES)
        .map(|i| siyi_rate(i as u16 + 1, if i % 2 == 0 { 60 } else { -60 }))
        .collect();
    run
}

/// Gimbal attitude reports from the pod, absorbed into the pod state (the SIYI side
/// answers from it when asked).
#[must_use]
pub fn bridge_pod_attitudes() -> BridgeRun {
    let mut run = siyi_engine();
    run.frames = (0..BRIDGE_FRAMES)
        .map(|i| pod_attitude(i as u8 + 1, i as i16 * 10))
        .collect();
    run.from_fc = false;
    run.step = bridge_engine::Duration::from_millis(20);
    run
}

/// The key of the signed benchmarks.
pub const BENCH_KEY: [u8; 32] = [0x42; 32];

/// `frame` signed with [`BENCH_KEY`] at `timestamp`, link 0.
fn signed(frame: &[u8], timestamp: u64) -> Vec<u8> {
    use protocol_core::mavlink::{MAX_FRAME_LEN, Packet, SecretKey, Signer};
    let key = SecretKey::new(BENCH_KEY);
    let signer = Signer {
        key: &key,
        link_id: 0,
        timestamp,
    };
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = Packet::decode(frame)
        .expect("a frame")
        .emit_signed(&signer, &mut buf)
        .expect("signed");
    buf[..n].to_vec()
}

/// A MAVLink engine with the pod and FC links up (an attitude report, the autopilot's
/// HEARTBEAT: the device knows its system id), its queues empty.
fn mavlink_engine() -> BridgeRun {
    mavlink_engine_with(false)
}

/// [`mavlink_engine`]; with `signing`, the engine requires signing with [`BENCH_KEY`] and
/// the autopilot's heartbeat comes signed.
fn mavlink_engine_with(signing: bool) -> BridgeRun {
    use bridge_engine::{Config, Duration, Engine, FcProtocol, Instant};
    use protocol_core::mavlink::dialect::{
        HEARTBEAT_DATA, MavAutopilot, MavModeFlag, MavState, MavType,
    };
    let mut config = Config {
        fc: FcProtocol::Mavlink,
        ..Config::DEFAULT
    };
    if signing {
        config.signing = bridge_engine::SigningMode::Require;
        config.signing_key = Some(bridge_engine::SigningKey(BENCH_KEY));
    }
    let mut run = BridgeRun {
        engine: Engine::new(config),
        frames: vec![pod_attitude(0, 0)],
        from_fc: false,
        now: Instant::from_millis(1000),
        step: Duration::from_millis(150),
    };
    run.run();
    let heartbeat = protocol_core::mavlink::MavMessage::HEARTBEAT(HEARTBEAT_DATA {
        custom_mode: 0,
        mavtype: MavType::MAV_TYPE_QUADROTOR,
        autopilot: MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA,
        base_mode: MavModeFlag::empty(),
        system_status: MavState::MAV_STATE_STANDBY,
        mavlink_version: 3,
    });
    let hb = mavlink_frame(0, &heartbeat);
    run.frames = vec![if signing { signed(&hb, SIGNED_T0) } else { hb }];
    run.from_fc = true;
    run.run();
    run
}

/// The first timestamp of the signed benchmarks' frames (2026).
const SIGNED_T0: u64 = 3_500_000_000_000;

/// A MAVLink 2 frame from the autopilot (1/1).
fn mavlink_frame(seq: u8, m: &protocol_core::mavlink::MavMessage) -> Vec<u8> {
    use protocol_core::mavlink::{self, Header, MAX_FRAME_LEN};
    let header = Header {
        sequence: seq,
        system_id: 1,
        component_id: 1,
    };
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = mavlink::encode(m, &header, &mut buf).expect("encode");
    buf[..n].to_vec()
}

/// GIMBAL_DEVICE_SET_ATTITUDE from ArduPilot (an angle: quaternion, rates NaN, yaw
/// relative to the vehicle), the angle changing every frame: each one translated into a
/// K40T angle command for the pod.
#[must_use]
pub fn bridge_mavlink_set_attitudes() -> BridgeRun {
    use protocol_core::mavlink::MavMessage;
    use protocol_core::mavlink::dialect::{GIMBAL_DEVICE_SET_ATTITUDE_DATA, GimbalDeviceFlags};
    let mut run = mavlink_engine();
    run.frames = (0..BRIDGE_FRAMES)
        .map(|i| {
            let (pitch, yaw) = if i % 2 == 0 {
                (-20f32, 30f32)
            } else {
                (-40.0, -30.0)
            };
            let (sp, cp) = (pitch.to_radians() / 2.0).sin_cos();
            let (sy, cy) = (yaw.to_radians() / 2.0).sin_cos();
            let set = MavMessage::GIMBAL_DEVICE_SET_ATTITUDE(GIMBAL_DEVICE_SET_ATTITUDE_DATA {
                q: [cp * cy, -sp * sy, sp * cy, cp * sy],
                angular_velocity_x: f32::NAN,
                angular_velocity_y: f32::NAN,
                angular_velocity_z: f32::NAN,
                flags: GimbalDeviceFlags::empty(),
                target_system: 1,
                target_component: 154,
            });
            mavlink_frame(i as u8 + 1, &set)
        })
        .collect();
    run
}

/// [`bridge_mavlink_set_attitudes`] on a link that requires signing: each frame signed
/// (its timestamp one above the last), checked by the engine, and every frame the engine
/// sends signed.
#[must_use]
pub fn bridge_mavlink_set_attitudes_signed() -> BridgeRun {
    let frames = bridge_mavlink_set_attitudes().frames;
    let mut run = mavlink_engine_with(true);
    run.frames = frames
        .iter()
        .enumerate()
        .map(|(i, f)| signed(f, SIGNED_T0 + 1 + i as u64))
        .collect();
    run
}

/// Frames each bridge benchmark gives the engine.
pub const BRIDGE_RUN_FRAMES: usize = BRIDGE_FRAMES;

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
