//! Target `bridge`: the bridge engine ([`bridge_engine::Engine`]) driven by the
//! fuzzer, for each FC protocol.
//!
//! The input: byte 0 picks the FC protocol (SIYI, Viewlink, GCU, K40T); then a program
//! of operations, each an op byte and its arguments: FC bytes, pod bytes (a length byte
//! and that many bytes), time going on by up to 65 s and a poll, the FC or pod line
//! going idle, the RTC_IO edge the engine asked for, a drain of every output, and a
//! valid frame from the catalogue (an FC frame of the protocol, or a pod frame from the
//! pod's addresses), so that the fuzzer reaches the engine's states behind valid frames.
//! Bit 4 of the FC-bytes, FC-idle and frame ops sends them to the MAVLink telemetry link
//! instead (its frames: the autopilot's HEARTBEAT and the MAVLink catalogue).
//!
//! Properties:
//! - nothing panics (debug assertions on: no overflow either);
//! - the queues hold what they promise: between two drains the frames for the FC take at
//!   most [`FC_QUEUE`] bytes (each frame its length plus a 2-byte record header), those
//!   for the pod at most [`POD_QUEUE`], those for the telemetry link at most
//!   [`TELEMETRY_QUEUE`]; at most [`EVENTS`] events are waiting;
//! - every frame for the FC is a valid frame of its protocol (checked by the reference
//!   scans written from the documents), every frame for the pod a valid K40T frame,
//!   every frame for the telemetry link a valid MAVLink 2 frame;
//! - no frame of one of the pod's destructive requests' base ids
//!   ([`GUARDED`](bridge_engine::access::GUARDED)), whatever
//!   its kind, reaches the pod unless the configuration allows it (`k40t_allow`; the
//!   MAVLink camera's storage format and reset with `mavlink.allow_destructive`);
//! - every input's [`Changes`] say what it did, as the firmware's wake-ups rely on: a
//!   queue's frame bit exactly when the input queued a frame for that port, the events
//!   bit exactly when it queued an event, the pin bit whenever the RTC_IO plan
//!   ([`Engine::pin`]) changed;
//! - whatever came before, once the lines went idle, a valid FC request is answered:
//!   SIYI's firmware-version request (0x01) with the 0x01 reply of its sequence number;
//!   Viewlink's handshake (0x00) with a 0x40 status while the pod reports its attitude;
//!   a GCU host package with a GCU reply; a K40T request is forwarded to the pod.

use std::sync::OnceLock;

use bridge_engine::access::Guarded;
use bridge_engine::{
    Changes, Config, Duration, Engine, FC_QUEUE, FcProtocol, Instant, MAX_FRAME_LEN, POD_QUEUE,
    PinAction, Port, TELEMETRY_QUEUE,
};
use protocol_core::Direction;
use protocol_core::gcu::GCU_SYNC;
use protocol_core::k40t::{self, CrcCoverage, Kind, MessageData, MsgId};
use protocol_core::viewlink::{self, SyncOrder};

pub use crate::input::Input;

/// Events the engine keeps waiting (`bridge::event`'s queue: 16).
pub const EVENTS: usize = 16;
/// Operations at most per input (a longer input's tail is ignored).
const MAX_OPS: usize = 512;
/// The FC protocols, in the order byte 0 picks them.
pub const PROTOCOLS: [FcProtocol; 4] = [
    FcProtocol::Siyi,
    FcProtocol::Viewlink,
    FcProtocol::Gcu,
    FcProtocol::K40t,
];

/// The operations of a program (op byte modulo 8).
pub mod op {
    /// FC bytes: a length byte, then the bytes.
    pub const FC_BYTES: u8 = 0;
    /// Pod bytes: a length byte, then the bytes.
    pub const POD_BYTES: u8 = 1;
    /// Time goes on by a 16-bit little-endian number of milliseconds; then a poll.
    pub const WAIT: u8 = 2;
    /// The FC line goes idle.
    pub const FC_IDLE: u8 = 3;
    /// The pod line goes idle.
    pub const POD_IDLE: u8 = 4;
    /// The RTC_IO change the engine asks for, made at its instant (or now, if later).
    pub const PIN: u8 = 5;
    /// Every output taken and checked.
    pub const DRAIN: u8 = 6;
    /// A valid frame: a selector byte; op bit 3 set: a pod frame, else an FC frame.
    pub const FRAME: u8 = 7;
    /// With [`FC_BYTES`], [`FC_IDLE`] or [`FRAME`] (bit 3 clear): the telemetry link.
    pub const TELEMETRY: u8 = 16;
}

/// Valid frames of each FC protocol (index as [`PROTOCOLS`]), and pod frames (every
/// message of the catalogue, from the pod's gimbal address).
struct Frames {
    fc: [Vec<Vec<u8>>; 4],
    pod: Vec<Vec<u8>>,
    /// For the telemetry link: the autopilot's HEARTBEAT, then the MAVLink catalogue.
    tel: Vec<Vec<u8>>,
}

fn frames() -> &'static Frames {
    static FRAMES: OnceLock<Frames> = OnceLock::new();
    FRAMES.get_or_init(|| {
        let fill: Vec<u8> = (0..=255u8).map(|i| i.wrapping_mul(151) ^ 0x5A).collect();
        let siyi = crate::siyi::catalogue_frames(&fill)
            .into_iter()
            .filter(|f| f.get(2) == Some(&0x01)) // CTRL: need ACK (what an FC sends)
            .collect();
        let viewlink = crate::viewlink::catalogue_frames(&fill, SyncOrder::Standard);
        let gcu = crate::gcu::catalogue_frames(&fill).0;
        let k40t = crate::k40t::catalogue_frames(&fill, CrcCoverage::ExcludeStx);
        let config = Config::DEFAULT;
        let pod = crate::k40t::known_ids()
            .into_iter()
            .enumerate()
            .map(|(i, id)| pod_frame(&config, id, &fill, i as u8))
            .collect();
        let mut tel = vec![crate::bridge_mavlink::autopilot_heartbeat()];
        tel.extend(crate::mavlink::catalogue_frames(&fill));
        Frames {
            fc: [siyi, viewlink, gcu, k40t],
            pod,
            tel,
        }
    })
}

/// A K40T frame as the pod sends it: from its gimbal address to the bridge.
fn pod_frame(config: &Config, id: MsgId, fill: &[u8], seq: u8) -> Vec<u8> {
    let len = k40t::Message::decode(id, &[]).map_or(0, |m| m.payload_len());
    let mut payload = fill[..len.min(fill.len())].to_vec();
    payload.resize(len, 0);
    let message = k40t::Message::decode(id, &payload).expect("a payload of the layout's length");
    let header = k40t::Header::new(config.pod.gimbal, config.pod.own, seq);
    let mut buf = [0u8; k40t::MAX_FRAME_LEN];
    let n = k40t::Packet { header, message }
        .emit(&mut buf)
        .expect("encode a pod frame");
    buf[..n].to_vec()
}

/// A check of every frame the pod gets, beyond validity (a target's own property).
pub type PodCheck = fn(&Config, &[u8]);

/// No frame of a destructive request's base id reaches the pod unless `config` allows it.
fn guarded_allowed(config: &Config, f: &[u8]) {
    let Ok(frame) = k40t::Frame::new_checked(f) else {
        return;
    };
    let base = frame.id().base;
    let mavlink_destructive = config.fc == FcProtocol::Mavlink
        && config.mavlink.allow_destructive
        && [0x030D, 0x030F].contains(&base);
    assert!(
        Guarded::index_of(base).is_none() || config.k40t_allow.allows(base) || mavlink_destructive,
        "a frame of the destructive request 0x{base:06X} reached the pod: {f:02X?}"
    );
}

/// Takes every output and checks it; returns the frames for the FC and for the pod.
fn drain(engine: &mut Engine, check: PodCheck) -> (Vec<Vec<u8>>, Vec<Vec<u8>>) {
    let config = *engine.config();
    let protocol = config.fc;
    let mut take = |port| {
        let mut frames = Vec::new();
        let mut buf = [0u8; MAX_FRAME_LEN];
        while let Some(len) = engine.pending(port) {
            assert_eq!(engine.transmit(port, &mut buf), Some(len), "{port:?}");
            frames.push(buf[..len].to_vec());
        }
        frames
    };
    let fc = take(Port::Fc);
    let pod = take(Port::Pod);
    let tel = take(Port::Telemetry);
    let mut events = 0;
    while engine.next_event().is_some() {
        events += 1;
    }
    assert!(events <= EVENTS, "{events} events waiting");
    let used = |frames: &[Vec<u8>]| frames.iter().map(|f| f.len() + 2).sum::<usize>();
    assert!(used(&fc) <= FC_QUEUE, "FC queue: {} bytes", used(&fc));
    assert!(used(&pod) <= POD_QUEUE, "pod queue: {} bytes", used(&pod));
    assert!(
        used(&tel) <= TELEMETRY_QUEUE,
        "telemetry queue: {} bytes",
        used(&tel)
    );
    for f in &tel {
        assert_eq!(
            crate::mavlink::valid_v2(f),
            Some(f.len()),
            "invalid frame for the telemetry link {f:02X?}"
        );
    }
    for f in &fc {
        // GCU replies are followed by the resync mark `8A 00` (GcuIdentity::resync_mark).
        let f = match protocol {
            FcProtocol::Gcu => f
                .strip_suffix(&[0x8A, 0x00])
                .expect("a GCU reply ends with 8A 00"),
            _ => f.as_slice(),
        };
        let valid = match protocol {
            FcProtocol::Siyi => crate::siyi::valid(f, 255),
            FcProtocol::Viewlink => crate::viewlink::valid(f, SyncOrder::Standard.bytes()),
            FcProtocol::Gcu => crate::gcu::valid(f, GCU_SYNC),
            FcProtocol::K40t => crate::k40t::valid(f, None, k40t::MAX_FRAME_LEN),
            FcProtocol::Mavlink => crate::mavlink::valid_v2(f),
        };
        assert_eq!(
            valid,
            Some(f.len()),
            "{protocol:?}: invalid frame for the FC {f:02X?}"
        );
    }
    for f in &pod {
        assert_eq!(
            crate::k40t::valid(f, None, k40t::MAX_FRAME_LEN),
            Some(f.len()),
            "invalid frame for the pod {f:02X?}"
        );
        guarded_allowed(&config, f);
        check(&config, f);
    }
    (fc, pod)
}

/// What a caller sees of the engine, taken before and after an input to check the
/// [`Changes`] it returned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Seen {
    /// Frames queued so far, for the FC and for the pod.
    fc_queued: u32,
    pod_queued: u32,
    tel_queued: u32,
    /// Events queued so far: those waiting and those dropped for newer ones.
    events: usize,
    pin: Option<PinAction>,
}

impl Seen {
    fn of(engine: &Engine) -> Self {
        let counters = engine.counters();
        let mut copy = engine.clone();
        let waiting = std::iter::from_fn(|| copy.next_event()).count();
        Seen {
            fc_queued: counters.fc_sent,
            pod_queued: counters.pod_sent,
            tel_queued: counters.telemetry_sent,
            events: waiting + counters.events_dropped as usize,
            pin: engine.pin(),
        }
    }

    /// `changes`, returned by the input from `self` to `after`, say what it did.
    fn check(&self, after: &Self, changes: Changes) {
        let said = |c| changes.contains(c);
        let what = format!("{changes:?} from {self:?} to {after:?}");
        assert_eq!(
            said(Changes::FC_FRAME),
            after.fc_queued != self.fc_queued,
            "{what}"
        );
        assert_eq!(
            said(Changes::POD_FRAME),
            after.pod_queued != self.pod_queued,
            "{what}"
        );
        assert_eq!(
            said(Changes::TELEMETRY_FRAME),
            after.tel_queued != self.tel_queued,
            "{what}"
        );
        assert_eq!(said(Changes::EVENTS), after.events != self.events, "{what}");
        assert!(said(Changes::PIN) || after.pin == self.pin, "{what}");
    }
}

/// Runs one program; panics when a property fails.
pub fn run(data: &[u8]) {
    let mut input = Input::new(data);
    let which = usize::from(input.byte()) % PROTOCOLS.len();
    run_with(PROTOCOLS[which], &frames().fc[which], input);
}

/// Target `bridge_k40t_allow`: the K40T side with the allow-list of the pod's destructive
/// requests the first two bytes give (bit `i` allows `GUARDED[i]`), its FC frames every
/// K40T request (the destructive ones among them), with the properties of [`run`]: no
/// frame of a request not allowed reaches the pod, whatever its kind, and every frame the
/// FC gets (the failure ACK of a refused request among them) is a valid K40T frame.
pub fn run_k40t_allow(data: &[u8]) {
    let mut input = Input::new(data);
    let bits = u16::from_le_bytes([input.byte(), input.byte()]);
    let config = Config {
        fc: FcProtocol::K40t,
        k40t_allow: bridge_engine::K40tAllow { bits },
        ..Config::DEFAULT
    };
    run_config(config, &frames().fc[3], input);
}

/// Seeds of `bridge_k40t_allow`: the K40T seeds of [`seeds`] with no, some and every
/// destructive request allowed.
#[must_use]
pub fn k40t_allow_seeds() -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    for bits in [0u16, 0x0155, 0xFFFF] {
        for s in seeds_with(&[], &frames().fc[3]).into_iter().step_by(3) {
            let mut v = bits.to_le_bytes().to_vec();
            v.extend(s);
            out.push(v);
        }
    }
    out
}

/// Runs the program in `input` with the FC side `protocol`, whose valid frames are
/// `fc_frames` (the frame op picks from them).
pub fn run_with(protocol: FcProtocol, fc_frames: &[Vec<u8>], input: Input<'_>) {
    let config = Config {
        fc: protocol,
        ..Config::DEFAULT
    };
    run_config(config, fc_frames, input);
}

/// [`run_with`] with the engine configured as `config` (its FC side the protocol).
pub fn run_config(config: Config, fc_frames: &[Vec<u8>], input: Input<'_>) {
    run_checked(config, fc_frames, input, |_, _| {});
}

/// [`run_config`] with `check` run on every frame the pod gets.
pub fn run_checked(config: Config, fc_frames: &[Vec<u8>], mut input: Input<'_>, check: PodCheck) {
    let protocol = config.fc;
    let mut engine = Engine::new(config);
    let mut now = Instant::from_millis(1);
    let frames = frames();
    for _ in 0..MAX_OPS {
        if input.rest().is_empty() {
            break;
        }
        let op = input.byte();
        let before = Seen::of(&engine);
        let changes = match op % 8 {
            op::FC_BYTES => {
                let n = usize::from(input.byte());
                let port = if op & op::TELEMETRY == 0 {
                    Port::Fc
                } else {
                    Port::Telemetry
                };
                engine.receive(now, port, input.bytes(n))
            }
            op::POD_BYTES => {
                let n = usize::from(input.byte());
                engine.receive(now, Port::Pod, input.bytes(n))
            }
            op::WAIT => {
                let ms = u16::from_le_bytes([input.byte(), input.byte()]);
                now = now.saturating_add(Duration::from_millis(ms.into()));
                engine.poll(now)
            }
            op::FC_IDLE if op & op::TELEMETRY != 0 => engine.idle(now, Port::Telemetry),
            op::FC_IDLE => engine.idle(now, Port::Fc),
            op::POD_IDLE => engine.idle(now, Port::Pod),
            op::PIN => match engine.pin() {
                Some(p) => {
                    now = now.max(p.at);
                    engine.pin_done(p.level, now)
                }
                None => Changes::NONE,
            },
            op::DRAIN => {
                drain(&mut engine, check);
                continue;
            }
            _ => {
                let pick = usize::from(input.byte());
                if op & 8 == 0 && op & op::TELEMETRY != 0 {
                    engine.receive(now, Port::Telemetry, &frames.tel[pick % frames.tel.len()])
                } else if op & 8 == 0 {
                    engine.receive(now, Port::Fc, &fc_frames[pick % fc_frames.len()])
                } else {
                    engine.receive(now, Port::Pod, &frames.pod[pick % frames.pod.len()])
                }
            }
        };
        before.check(&Seen::of(&engine), changes);
        // The read-only views never fail either.
        let _ = (engine.poll_at(), engine.counters(), engine.utc(now));
        let _ = (engine.pod_state(), engine.utc_state(), engine.fc_link());
    }
    probe(&mut engine, protocol, now, check);
}

/// The lines go idle, a second passes, and a valid request comes from the FC: it is
/// answered (see the module documentation).
fn probe(engine: &mut Engine, protocol: FcProtocol, mut now: Instant, check: PodCheck) {
    drain(engine, check);
    engine.idle(now, Port::Fc);
    engine.idle(now, Port::Pod);
    now = now.saturating_add(Duration::from_secs(1));
    engine.poll(now);
    drain(engine, check);
    let config = *engine.config();
    let request = match protocol {
        FcProtocol::Siyi => crate::siyi::encoded(
            0x01,
            Direction::ToGimbal,
            &[],
            protocol_core::siyi::Header::request(0x4A3B),
        ),
        FcProtocol::Viewlink => {
            // The status carries the pod's attitude: the pod reports it first.
            let attitude = pod_frame(&config, k40t::GimbalAttitude::ID, &[1; 32], 0);
            engine.receive(now, Port::Pod, &attitude);
            drain(engine, check);
            crate::viewlink::encoded(
                viewlink::Handshake::ID,
                &[0],
                0,
                viewlink::Header {
                    sync: SyncOrder::Standard,
                    counter: 0,
                },
            )
        }
        FcProtocol::Gcu => Some(crate::gcu::encoded(
            protocol_core::gcu::CATALOG[0].id,
            &[],
            &[],
            0x02,
        )),
        FcProtocol::K40t => Some(crate::k40t::encoded(
            K40T_FORWARDED,
            &[0x2D],
            0x77,
            CrcCoverage::ExcludeStx,
        )),
        FcProtocol::Mavlink => {
            // The autopilot is heard first (the device takes its system id).
            // Signed when the engine signs (with the key the fuzz target gives it, at a
            // timestamp newer than any it was fed).
            let sign = |f: Vec<u8>| match config.signing {
                bridge_engine::SigningMode::Off => f,
                _ => crate::bridge_mavlink::signed(&f, crate::bridge_mavlink::FUZZ_KEY, u64::MAX),
            };
            engine.receive(
                now,
                Port::Fc,
                &sign(crate::bridge_mavlink::autopilot_heartbeat()),
            );
            drain(engine, check);
            Some(sign(crate::bridge_mavlink::probe_request()))
        }
    }
    .expect("the probe request encodes");
    engine.receive(now, Port::Fc, &request);
    engine.idle(now, Port::Fc);
    let (fc, pod) = drain(engine, check);
    let answered = match protocol {
        // 55 66 CTRL LEN(2) SEQ(2) CMD: the firmware versions, same sequence number.
        FcProtocol::Siyi => fc.iter().any(|f| f[5..8] == [0x3B, 0x4A, 0x01]),
        FcProtocol::Viewlink => fc.iter().any(|f| {
            viewlink::Frame::new_checked(&f[..]).is_ok_and(|fr| fr.id() == viewlink::Status::ID)
        }),
        FcProtocol::Gcu => fc.iter().any(|f| f.starts_with(&GCU_SYNC)),
        FcProtocol::K40t => pod
            .iter()
            .any(|f| k40t::Frame::new_checked(&f[..]).is_ok_and(|fr| fr.id() == K40T_FORWARDED)),
        FcProtocol::Mavlink => fc.iter().any(|f| crate::bridge_mavlink::answers_probe(f)),
    };
    assert!(
        answered,
        "{protocol:?}: request {request:02X?} not answered; FC got {fc:02X?}, pod got {pod:02X?}"
    );
}

/// The K40T request the probe sends: zoom (0x000307), forwarded as it is.
const K40T_FORWARDED: MsgId = MsgId::new(Kind::Request, 0x0307);

/// Seeds: for each protocol, the catalogue's FC frames and pod reports, in raw bytes
/// and as frame ops, with waits, idles, pin changes and drains.
#[must_use]
pub fn seeds() -> Vec<Vec<u8>> {
    let frames = frames();
    let mut out = Vec::new();
    for (p, fc) in frames.fc.iter().enumerate() {
        out.extend(seeds_with(&[p as u8], fc));
    }
    out
}

/// Seeds of one FC side: `prefix` (the bytes that pick it), then its FC frames `fc` and
/// the pod's reports, in raw bytes and as frame ops, with waits, idles, pin changes and
/// drains.
#[must_use]
pub fn seeds_with(prefix: &[u8], fc: &[Vec<u8>]) -> Vec<Vec<u8>> {
    let frames = frames();
    let mut out = Vec::new();
    // Each FC frame as raw bytes, then idle, a pod report, a wait and a drain.
    for (i, f) in fc.iter().enumerate().step_by(3) {
        let mut s = prefix.to_vec();
        s.extend([op::FC_BYTES, f.len() as u8]);
        s.extend_from_slice(f);
        s.extend([op::FC_IDLE, op::FRAME | 8, i as u8, op::WAIT, 20, 0]);
        s.extend([op::PIN, op::WAIT, 0, 4, op::PIN, op::DRAIN]);
        out.push(s);
    }
    // The autopilot on the telemetry link, then MAVLink frames there, with FC frames.
    let mut s = prefix.to_vec();
    s.extend([op::FRAME | op::TELEMETRY, 0, op::WAIT, 0, 4]);
    for i in 1..frames.tel.len().min(64) {
        s.extend([op::FRAME | op::TELEMETRY, i as u8, op::FRAME, i as u8]);
        s.extend([op::FC_IDLE | op::TELEMETRY, op::WAIT, 100, 0]);
        if i % 8 == 7 {
            s.extend([op::PIN, op::DRAIN]);
        }
    }
    out.push(s);
    // Every frame of the catalogue through the frame op, between pod reports.
    let mut s = prefix.to_vec();
    for i in 0..fc.len().min(255) {
        s.extend([op::FRAME, i as u8, op::FRAME | 8, i as u8, op::WAIT, 50, 0]);
        if i % 8 == 7 {
            s.extend([op::PIN, op::DRAIN]);
        }
    }
    out.push(s);
    // Pod bytes in pieces, with garbage.
    let mut s = prefix.to_vec();
    for f in frames.pod.iter().take(12) {
        let (a, b) = f.split_at(f.len() / 2);
        s.extend([op::POD_BYTES, a.len() as u8 + 1, 0xFD]);
        s.extend_from_slice(a);
        s.extend([op::POD_BYTES, b.len() as u8]);
        s.extend_from_slice(b);
        s.extend([op::POD_IDLE, op::WAIT, 0xE8, 0x03]);
    }
    out.push(s);
    out
}
