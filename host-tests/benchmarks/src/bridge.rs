//! The bridge engine at work, as the instruction-count benchmarks measure it: an engine
//! already running, and a recorded exchange to replay on it.
//!
//! Each run is recorded in the benchmark's setup (not measured): the requests are given
//! to a copy of the engine one at a time, `step` apart, every frame it queues is taken as
//! a driver takes it, and, where the run says so, the pod answers every request the
//! bridge sends it with an OK ACK at once (a K40T pod that accepts everything). The
//! measured [`BridgeRun::run`] replays the same inputs (the requests and the pod's
//! answers) on the engine as it was before the recording, so it measures the bridge's
//! work alone, and it must give what the recording gave ([`BridgeRun::expected`]).

use std::collections::VecDeque;

use bridge_engine::{Config, Duration, Engine, FcProtocol, Instant, Port};
use protocol_core::mavlink::{self, MavMessage};

/// The largest frame any port sends (a signed MAVLink 2 frame of 255 payload bytes).
const OUT_LEN: usize = mavlink::MAX_FRAME_LEN;

/// Requests in each bridge benchmark of the SIYI and set-attitude kind.
pub const BRIDGE_RUN_FRAMES: usize = 64;

/// One input of a run.
#[derive(Debug, Clone)]
pub struct Input {
    /// Time since the previous input.
    pub after: Duration,
    /// Where it comes from.
    pub port: Port,
    /// The bytes (one frame).
    pub bytes: Vec<u8>,
}

/// A recorded exchange with the engine, to replay.
#[derive(Debug, Clone)]
pub struct BridgeRun {
    /// The engine, as it was before the recording.
    pub engine: Engine,
    /// The inputs, in order: the requests and the pod's answers.
    pub inputs: Vec<Input>,
    /// The local time before the first input.
    pub now: Instant,
    /// Requests the run is counted per (frames from the FC, or reports of the pod).
    pub requests: usize,
    /// Every frame the engine sent in the recording, in order.
    pub outputs: Vec<(Port, Vec<u8>)>,
}

impl BridgeRun {
    /// Gives each input to the engine at its instant, then takes every frame it queued
    /// (as a driver does) and its events. Returns (frames for the pod, frames for the FC).
    pub fn run(&mut self) -> (usize, usize) {
        let (mut pod, mut fc) = (0, 0);
        let mut buf = [0u8; OUT_LEN];
        for input in &self.inputs {
            self.now = self.now.saturating_add(input.after);
            self.engine.receive(self.now, input.port, &input.bytes);
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

    /// What [`BridgeRun::run`] returns: the recording's (frames for the pod, for the FC).
    #[must_use]
    pub fn expected(&self) -> (usize, usize) {
        let pod = self.outputs.iter().filter(|(p, _)| *p == Port::Pod).count();
        (pod, self.outputs.len() - pod)
    }

    /// The MAVLink frames the engine sent the FC, decoded (`None`: not a message of the
    /// dialect).
    pub fn fc_messages(&self) -> impl Iterator<Item = Option<MavMessage>> + '_ {
        self.outputs
            .iter()
            .filter(|(p, _)| *p == Port::Fc)
            .map(
                |(_, f)| match mavlink::Packet::decode(f).map(|p| p.message) {
                    Ok(mavlink::Message::Known(m)) => Some(m),
                    _ => None,
                },
            )
    }
}

/// A recording: the run, and the engine and time after it (the next run's start).
struct Recorded {
    run: BridgeRun,
    engine: Engine,
    now: Instant,
}

/// Records `requests` given to `engine` from `port`, `step` apart from `now`; with
/// `pod_acks`, the pod ACKs every request of the bridge (see the module documentation).
fn record(
    engine: Engine,
    now: Instant,
    port: Port,
    requests: Vec<Vec<u8>>,
    step: Duration,
    pod_acks: bool,
) -> Recorded {
    let before = engine.clone();
    let mut engine = engine;
    let count = requests.len();
    let mut queue: VecDeque<Input> = requests
        .into_iter()
        .map(|bytes| Input {
            after: step,
            port,
            bytes,
        })
        .collect();
    let (mut inputs, mut outputs) = (Vec::new(), Vec::new());
    let mut t = now;
    let mut buf = [0u8; OUT_LEN];
    while let Some(input) = queue.pop_front() {
        t = t.saturating_add(input.after);
        engine.receive(t, input.port, &input.bytes);
        let mut answers = Vec::new();
        while let Some(n) = engine.transmit(Port::Pod, &mut buf) {
            let frame = buf[..n].to_vec();
            if pod_acks {
                answers.extend(pod_ack(&frame));
            }
            outputs.push((Port::Pod, frame));
        }
        while let Some(n) = engine.transmit(Port::Fc, &mut buf) {
            outputs.push((Port::Fc, buf[..n].to_vec()));
        }
        while engine.next_event().is_some() {}
        inputs.push(input);
        for bytes in answers.into_iter().rev() {
            queue.push_front(Input {
                after: Duration::from_millis(0),
                port: Port::Pod,
                bytes,
            });
        }
    }
    Recorded {
        run: BridgeRun {
            engine: before,
            inputs,
            now,
            requests: count,
            outputs,
        },
        engine,
        now: t,
    }
}

/// The K40T pod's OK ACK of a request the bridge sent it, from the address it went to,
/// with its sequence number and CRC coverage (the ACK payload all zero: response code
/// OK, any data zero); `None` for anything else.
fn pod_ack(frame: &[u8]) -> Option<Vec<u8>> {
    use protocol_core::k40t::*;
    let request = Packet::decode(frame).ok()?;
    let id = request.message.id();
    if id.kind != Kind::Request {
        return None;
    }
    let ack = MsgId::new(Kind::Ack, id.base);
    let len = Message::decode(ack, &[]).ok()?.payload_len();
    let zeros = vec![0u8; len];
    let message = Message::decode(ack, &zeros).ok()?;
    let to = request.header;
    let p = Packet {
        header: Header {
            dst: to.src,
            src: to.dst,
            ..to
        },
        message,
    };
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = p.emit(&mut buf).ok()?;
    Some(buf[..n].to_vec())
}

/// A K40T gimbal attitude report from the pod (yaw in 0.01°).
fn pod_attitude(seq: u8, yaw_cdeg: i16) -> Vec<u8> {
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

/// The instant every engine starts from.
const START: Instant = Instant::from_millis(1000);
/// Time between two requests of the SIYI and set-attitude runs: more than the pod
/// driver's motion interval, so that every command goes out.
const COMMAND_STEP: Duration = Duration::from_millis(150);

/// An engine of `config` with the pod link up (an attitude report), then `fc_hello` from
/// the FC (the link up), its queues empty: the engine and the time.
fn running(config: Config, fc_hello: Vec<u8>, pod_acks: bool) -> (Engine, Instant) {
    let pod = record(
        Engine::new(config),
        START,
        Port::Pod,
        vec![pod_attitude(0, 0)],
        COMMAND_STEP,
        pod_acks,
    );
    let fc = record(
        pod.engine,
        pod.now,
        Port::Fc,
        vec![fc_hello],
        COMMAND_STEP,
        pod_acks,
    );
    (fc.engine, fc.now)
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

/// A SIYI engine with the pod and FC links up (an attitude report, a rate command).
fn siyi_engine() -> (Engine, Instant) {
    let config = Config {
        fc: FcProtocol::Siyi,
        ..Config::DEFAULT
    };
    running(config, siyi_rate(0, 0), false)
}

/// SIYI rate commands (0x07) from the FC, the speed changing every frame: each one
/// translated into a K40T gimbal control for the pod.
#[must_use]
pub fn bridge_siyi_rates() -> BridgeRun {
    let (engine, now) = siyi_engine();
    let frames = (0..BRIDGE_RUN_FRAMES)
        .map(|i| siyi_rate(i as u16 + 1, if i % 2 == 0 { 60 } else { -60 }))
        .collect();
    record(engine, now, Port::Fc, frames, COMMAND_STEP, false).run
}

/// Gimbal attitude reports from the pod, absorbed into the pod state (the SIYI side
/// answers from it when asked).
#[must_use]
pub fn bridge_pod_attitudes() -> BridgeRun {
    let (engine, now) = siyi_engine();
    let frames = (0..BRIDGE_RUN_FRAMES)
        .map(|i| pod_attitude(i as u8 + 1, i as i16 * 10))
        .collect();
    let step = Duration::from_millis(20);
    record(engine, now, Port::Pod, frames, step, false).run
}

/// The key of the signed benchmarks.
pub const BENCH_KEY: [u8; 32] = [0x42; 32];

/// The first timestamp of the signed benchmarks' frames (2026).
const SIGNED_T0: u64 = 3_500_000_000_000;

/// `frame` signed with [`BENCH_KEY`] at `timestamp`, link 0.
#[must_use]
pub fn signed(frame: &[u8], timestamp: u64) -> Vec<u8> {
    use protocol_core::mavlink::{Packet, SecretKey, Signer};
    let key = SecretKey::new(BENCH_KEY);
    let signer = Signer {
        key: &key,
        link_id: 0,
        timestamp,
    };
    let mut buf = [0u8; OUT_LEN];
    let n = Packet::decode(frame)
        .expect("a frame")
        .emit_signed(&signer, &mut buf)
        .expect("signed");
    buf[..n].to_vec()
}

/// The FC's frames, signed with timestamps one apart after the heartbeat's.
fn signed_all(frames: Vec<Vec<u8>>) -> Vec<Vec<u8>> {
    frames
        .iter()
        .enumerate()
        .map(|(i, f)| signed(f, SIGNED_T0 + 1 + i as u64))
        .collect()
}

/// A MAVLink 2 frame from the autopilot (1/1).
#[must_use]
pub fn mavlink_frame(seq: u8, m: &MavMessage) -> Vec<u8> {
    use protocol_core::mavlink::Header;
    let header = Header {
        sequence: seq,
        system_id: 1,
        component_id: 1,
    };
    let mut buf = [0u8; OUT_LEN];
    let n = mavlink::encode(m, &header, &mut buf).expect("encode");
    buf[..n].to_vec()
}

/// The MAVLink side's configuration; with `signing`, signing required with
/// [`BENCH_KEY`].
pub(crate) fn mavlink_config(signing: bool) -> Config {
    let mut config = Config {
        fc: FcProtocol::Mavlink,
        ..Config::DEFAULT
    };
    if signing {
        config.signing = bridge_engine::SigningMode::Require;
        config.signing_key = Some(bridge_engine::SigningKey(BENCH_KEY));
    }
    config
}

/// A MAVLink engine of `config` with the pod and FC links up (an attitude report, the
/// autopilot's HEARTBEAT, signed when the configuration signs: the device knows its
/// system id), its queues empty.
pub(crate) fn mavlink_engine(config: Config, pod_acks: bool) -> (Engine, Instant) {
    let hb = fuzz_checks::bridge_mavlink::autopilot_heartbeat();
    let signing = config.signing_key.is_some();
    let hb = if signing { signed(&hb, SIGNED_T0) } else { hb };
    running(config, hb, pod_acks)
}

/// `frames` from the autopilot to a MAVLink engine (signed, on a link that requires
/// signing, with `signing`), `step` apart; with `pod_acks`, the pod ACKs the bridge's
/// requests.
pub(crate) fn mavlink_run(
    frames: Vec<Vec<u8>>,
    signing: bool,
    config: Config,
    step: Duration,
    pod_acks: bool,
) -> BridgeRun {
    let (engine, now) = mavlink_engine(config, pod_acks);
    let frames = if signing { signed_all(frames) } else { frames };
    record(engine, now, Port::Fc, frames, step, pod_acks).run
}

/// GIMBAL_DEVICE_SET_ATTITUDE from ArduPilot (an angle: quaternion, rates NaN, yaw
/// relative to the vehicle), the angle changing every frame: each one translated into a
/// K40T angle command for the pod. With `signing`, on a link that requires signing: each
/// frame signed (its timestamp one above the last), checked by the engine, and every
/// frame the engine sends signed.
#[must_use]
pub fn bridge_mavlink_set_attitudes(signing: bool) -> BridgeRun {
    use protocol_core::mavlink::dialect::{GIMBAL_DEVICE_SET_ATTITUDE_DATA, GimbalDeviceFlags};
    let frames = (0..BRIDGE_RUN_FRAMES)
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
    let config = mavlink_config(signing);
    mavlink_run(frames, signing, config, COMMAND_STEP, false)
}
