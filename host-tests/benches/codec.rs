//! Codec throughput on the host: for each protocol, a stream of valid frames (K40T and
//! SIYI: every catalogue message; Viewlink and GCU: the documents' example frames) is
//! deframed (64-byte chunks, as a UART DMA buffer would deliver them),
//! decoded, and encoded again. Run with `cargo bench -p host-tests` (release profile,
//! opt-level z: the code the firmware runs, compiled for the host).
//!
//! Prints one line per protocol and stage: ns per frame and MB/s of wire bytes.

use std::hint::black_box;
use std::time::{Duration, Instant};

use protocol_core::wire::{Deframer, Event, Framing};

/// A deterministic byte generator (xorshift), so runs are comparable.
struct Bytes(u64);

impl Bytes {
    fn next(&mut self) -> u8 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 24) as u8
    }
    fn fill(&mut self, n: usize) -> Vec<u8> {
        (0..n).map(|_| self.next()).collect()
    }
}

/// Runs `f` repeatedly for about `budget` and returns the time per call.
fn time(budget: Duration, mut f: impl FnMut() -> usize) -> Duration {
    black_box(f());
    let start = Instant::now();
    let mut calls = 0u32;
    while start.elapsed() < budget {
        black_box(f());
        calls += 1;
    }
    start.elapsed() / calls.max(1)
}

fn report(protocol: &str, stage: &str, per_stream: Duration, frames: usize, bytes: usize) {
    let ns_per_frame = per_stream.as_nanos() as f64 / frames as f64;
    let mb_s = bytes as f64 / per_stream.as_secs_f64() / 1e6;
    println!("{protocol:<9} {stage:<24} {ns_per_frame:>9.0} ns/frame {mb_s:>9.1} MB/s");
}

fn deframe_count<F: Framing, const N: usize>(framing: F, stream: &[u8]) -> usize {
    let mut d = Deframer::<F, N>::new(framing);
    let mut n = 0;
    for chunk in stream.chunks(64) {
        d.push(chunk, |e| n += usize::from(matches!(e, Event::Frame(_))));
    }
    n
}

/// Benchmarks one protocol given its valid frames and its per-frame decode and
/// decode+encode functions.
fn bench<F: Framing + Copy, const N: usize>(
    protocol: &str,
    framing: F,
    frames: &[Vec<u8>],
    decode: impl Fn(&[u8]) -> bool,
    round_trip: impl Fn(&[u8], &mut [u8]) -> usize,
) {
    let stream: Vec<u8> = frames.concat();
    let budget = Duration::from_millis(300);
    assert_eq!(
        deframe_count::<F, N>(framing, &stream),
        frames.len(),
        "{protocol}: deframer lost frames"
    );
    assert!(
        frames.iter().all(|f| decode(f)),
        "{protocol}: a frame did not decode"
    );
    let t = time(budget, || {
        deframe_count::<F, N>(framing, black_box(&stream))
    });
    report(protocol, "deframe", t, frames.len(), stream.len());
    let t = time(budget, || {
        frames.iter().filter(|f| decode(black_box(f))).count()
    });
    report(protocol, "decode", t, frames.len(), stream.len());
    let mut out = vec![0u8; 70_000];
    let t = time(budget, || {
        frames
            .iter()
            .map(|f| round_trip(black_box(f), &mut out))
            .sum()
    });
    report(protocol, "decode + encode", t, frames.len(), stream.len());
}

fn k40t() {
    use protocol_core::k40t::*;
    let mut rng = Bytes(0x4B34_3054);
    let mut frames = Vec::new();
    for round in 0..8u8 {
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
                let len = Message::decode(id, &[])
                    .map(|m| m.payload_len())
                    .unwrap_or(0);
                let payload = rng.fill(len);
                let message = Message::decode(id, &payload).expect("payload of its own length");
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
    bench::<_, MAX_FRAME_LEN>(
        "k40t",
        K40tFraming::with(CrcCoverage::ExcludeStx),
        &frames,
        |f| Packet::decode(f).is_ok(),
        |f, out| Packet::decode(f).and_then(|p| p.emit(out)).unwrap_or(0),
    );
}

fn siyi() {
    use protocol_core::Direction;
    use protocol_core::siyi::*;
    let mut rng = Bytes(0x5349_5949);
    let mut frames = Vec::new();
    for round in 0..8u16 {
        for e in CATALOG {
            for direction in [Direction::ToGimbal, Direction::FromGimbal] {
                // The shortest payload length the command accepts in this direction.
                let Some(message) = (0..=DEFAULT_MAX_PAYLOAD_LEN).find_map(|len| {
                    let payload: &'static [u8] = rng.fill(len).leak();
                    Message::decode(e.id, payload, direction).ok()
                }) else {
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
    bench::<_, DEFAULT_MAX_FRAME_LEN>(
        "siyi",
        SiyiFraming::default(),
        &frames,
        |f| Packet::decode_auto(f).is_ok(),
        |f, out| {
            Packet::decode_auto(f)
                .and_then(|p| p.emit(out))
                .unwrap_or(0)
        },
    );
}

/// The verified seed vectors of a protocol (the documents' example frames) that start
/// with `sync`, repeated to make a longer stream.
fn vectors(protocol: &'static str, sync: &[u8]) -> Vec<Vec<u8>> {
    let frames: Vec<Vec<u8>> = codec_cases::vectors(protocol)
        .filter(|v| v.verified && v.bytes.starts_with(sync))
        .map(|v| v.bytes.to_vec())
        .collect();
    assert!(!frames.is_empty(), "no {protocol} vectors");
    frames
        .iter()
        .cycle()
        .take(frames.len() * 8)
        .cloned()
        .collect()
}

fn viewlink() {
    use protocol_core::viewlink::*;
    bench::<_, MAX_FRAME_LEN>(
        "viewlink",
        ViewlinkFraming::new(),
        &vectors("Viewlink", &[0x55, 0xAA, 0xDC]),
        |f| Packet::decode(f).is_ok(),
        |f, out| Packet::decode(f).and_then(|p| p.emit(out)).unwrap_or(0),
    );
}

fn gcu() {
    use protocol_core::gcu::*;
    let host = vectors("GCU", &HOST_SYNC);
    // The documents print no GCU replies: answer each host package as the GCU would.
    let replies: Vec<Vec<u8>> = host
        .iter()
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
    for (name, framing, frames) in [
        ("gcu host", GcuFraming::host(), &host),
        ("gcu reply", GcuFraming::gcu(), &replies),
    ] {
        bench::<_, MAX_FRAME_LEN>(
            name,
            framing,
            frames,
            |f| Packet::decode(f).is_ok(),
            |f, out| Packet::decode(f).and_then(|p| p.emit(out)).unwrap_or(0),
        );
    }
}

fn main() {
    // `cargo test --all-targets` runs benches as tests: one quick pass then.
    if std::env::args().any(|a| a == "--bench") {
        println!(
            "{:<9} {:<24} {:>18} {:>14}",
            "protocol", "stage", "time", "throughput"
        );
    }
    k40t();
    siyi();
    viewlink();
    gcu();
}
