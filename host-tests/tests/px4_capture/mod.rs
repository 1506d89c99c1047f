//! The capture of a real PX4 SITL in lockstep (`fixtures/px4-sitl-lockstep.jsonl`, what
//! it holds: `fixtures/px4-sitl-lockstep.md`, its facts: docs/src/bridge/time.md "PX4
//! SITL in lockstep") and a flight controller that replays it to the engine
//! ([`CapturedPx4`]).
//!
//! **How the replay pairs the bridge's TIMESYNC requests.** The bridge under test sends
//! its requests when its own plan says, not at the instants the captured bridge did, so
//! the captured replies cannot be replayed as they are. PX4's boot clock is rebuilt from
//! the capture instead: the 611 captured exchanges give its reading `tc1` when the
//! captured bridge sent each request (PX4 read it within the round trip, 238 µs at the
//! median), and between two exchanges (at most 350 ms apart) the clock is taken as the
//! straight line between them, floored to PX4's 4 ms lockstep step, as PX4's own readings
//! are. A request of the replay is answered with that clock at the instant it started,
//! after the round trip of the captured exchange nearest in time (so the round trips'
//! spread, 27 ms once, comes back), with that exchange's target fields and sequence number
//! (PX4 1.16 fills only tc1 and ts1). Every other frame PX4 sent (HEARTBEAT, SYSTEM_TIME,
//! ATTITUDE, GLOBAL_POSITION_INT, GPS_RAW_INT) reaches the engine byte for byte at the
//! instant the captured bridge read it.
//!
//! **The link.** The capture ran over a pseudo-terminal: bytes take no serial time. The
//! replay's lines run at 4 Mbaud (a 30-byte frame in 75 µs) and each frame is put on the
//! line so that its last byte arrives at its captured instant; the engine is configured as
//! the captured bridge was (115 200 baud), so it must find out by itself that the link is
//! faster than that.
//!
//! **The reference.** PX4's own UTC on its ground link (`gcs_ref` lines: `time_unix_usec`
//! and the kernel's receive time), placed on the bridge's clock by the capture's
//! `bridge_t0_wall_min`; PX4's UTC at a bridge instant is the line between the two
//! neighbouring ground-link messages, plus their median stamp-to-receipt delay (20.5 µs;
//! p99 68.6 µs, the reference's own uncertainty).

#![allow(dead_code)]

use std::collections::VecDeque;
use std::path::Path;

use protocol_core::mavlink::dialect::TIMESYNC_DATA;
use protocol_core::mavlink::{Header, MAX_FRAME_LEN, MavMessage, MavlinkFraming, Packet};
use protocol_core::wire::{Deframer, Event as DeframerEvent};
use serde_json::Value;

use gimbal::sim::peer::Peer;

/// The line rate of the replay: a pseudo-terminal's bytes, almost no serial time.
pub const LINE_BAUD: u32 = 4_000_000;
/// PX4's lockstep step: its boot clock moves by this much at a time, µs.
pub const LOCKSTEP_STEP_US: i64 = 4_000;
/// The ground link's median delay from PX4's stamp to the kernel's receipt, µs.
const GCS_STAMP_DELAY_US: f64 = 20.5;

/// One frame PX4 sent to the bridge.
#[derive(Debug, Clone)]
pub struct RxFrame {
    /// The bridge's clock when it read the frame, µs.
    pub t_us: u64,
    /// The message's name.
    pub msg: String,
    /// The frame's bytes.
    pub raw: Vec<u8>,
}

/// One TIMESYNC exchange of the captured bridge.
#[derive(Debug, Clone, Copy)]
pub struct Exchange {
    /// The request sent, bridge µs.
    pub sent_us: u64,
    /// The reply received, bridge µs.
    pub received_us: u64,
    /// PX4's boot clock in the reply, ns.
    pub tc1_ns: i64,
    /// The reply's target fields (PX4 1.16 leaves them unset: arbitrary).
    pub target: (u8, u8),
    /// The reply's sequence number.
    pub seq: u8,
}

/// One SYSTEM_TIME on PX4's ground link.
#[derive(Debug, Clone, Copy)]
pub struct GcsRef {
    /// Its receipt by the kernel, on the bridge's clock, µs.
    pub at_us: f64,
    /// PX4's UTC in it, µs.
    pub utc_us: u64,
    /// PX4's boot clock in it, ms.
    pub boot_ms: u64,
}

/// One event of the captured bridge.
#[derive(Debug, Clone)]
pub struct CapturedEvent {
    /// Bridge µs.
    pub t_us: u64,
    /// `utc_valid`, `utc_lost`, `time_sync`.
    pub event: String,
    /// The line.
    pub fields: Value,
}

/// The capture, parsed.
#[derive(Debug, Clone)]
pub struct Capture {
    /// Host time (Unix µs) at the bridge's clock 0, the least the capture allows.
    pub t0_wall_us: f64,
    /// Every frame PX4 sent, in order.
    pub rx: Vec<RxFrame>,
    /// The bridge's TIMESYNC requests and PX4's replies, in order.
    pub exchanges: Vec<Exchange>,
    /// PX4's ground link.
    pub gcs: Vec<GcsRef>,
    /// The captured bridge's time events.
    pub events: Vec<CapturedEvent>,
}

fn hex(s: &str) -> Vec<u8> {
    (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&s[i..i + 2], 16).expect("hex"))
        .collect()
}

fn u(v: &Value, key: &str) -> u64 {
    v[key].as_u64().unwrap_or_else(|| panic!("{key} in {v}"))
}

impl Capture {
    /// Reads `fixtures/px4-sitl-lockstep.jsonl`.
    pub fn load() -> Capture {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/px4-sitl-lockstep.jsonl");
        let text = std::fs::read_to_string(&path).expect("the PX4 capture");
        let lines: Vec<Value> = text
            .lines()
            .map(|l| serde_json::from_str(l).expect("a JSON line"))
            .collect();
        let header = &lines[0];
        assert_eq!(header["kind"], "header");
        let t0_wall_us = header["bridge_t0_wall_min"].as_f64().expect("t0") * 1e6;
        let mut requests = std::collections::HashMap::new();
        let (mut rx, mut exchanges, mut gcs, mut events) = (vec![], vec![], vec![], vec![]);
        for l in &lines[1..] {
            match l["kind"].as_str().expect("kind") {
                "fc_tx" if l["msg"] == "TIMESYNC" => {
                    requests.insert(l["ts1"].as_i64().expect("ts1"), u(l, "t_us"));
                }
                "fc_rx" if l["msg"] == "TIMESYNC" => {
                    let sent_us = requests[&l["ts1"].as_i64().expect("ts1")];
                    exchanges.push(Exchange {
                        sent_us,
                        received_us: u(l, "t_us"),
                        tc1_ns: l["tc1"].as_i64().expect("tc1"),
                        target: (u(l, "target_system") as u8, u(l, "target_component") as u8),
                        seq: u(l, "seq") as u8,
                    });
                }
                "fc_rx" => rx.push(RxFrame {
                    t_us: u(l, "t_us"),
                    msg: l["msg"].as_str().expect("msg").to_string(),
                    raw: hex(l["raw"].as_str().expect("raw")),
                }),
                "gcs_ref" => gcs.push(GcsRef {
                    at_us: l["wall_kernel"].as_f64().expect("wall_kernel") * 1e6 - t0_wall_us,
                    utc_us: u(l, "time_unix_usec"),
                    boot_ms: u(l, "time_boot_ms"),
                }),
                "bridge_event" => events.push(CapturedEvent {
                    t_us: u(l, "t_us"),
                    event: l["event"].as_str().expect("event").to_string(),
                    fields: l.clone(),
                }),
                _ => {}
            }
        }
        Capture {
            t0_wall_us,
            rx,
            exchanges,
            gcs,
            events,
        }
    }

    /// PX4's boot clock (ns) at bridge instant `t_us`, rebuilt from the exchanges: the
    /// line between the two around it (the first or last two outside), floored to the
    /// lockstep step.
    pub fn boot_ns_at(&self, t_us: f64) -> i64 {
        let ex = &self.exchanges;
        let i = ex
            .partition_point(|e| (e.sent_us as f64) <= t_us)
            .clamp(1, ex.len() - 1);
        let (a, b) = (ex[i - 1], ex[i]);
        let (ta, tb) = (a.sent_us as f64, b.sent_us as f64);
        let us =
            a.tc1_ns as f64 / 1e3 + (b.tc1_ns - a.tc1_ns) as f64 / 1e3 * (t_us - ta) / (tb - ta);
        let step = LOCKSTEP_STEP_US as f64;
        ((us / step).floor() * step) as i64 * 1000
    }

    /// The captured exchange nearest to bridge instant `t_us`.
    pub fn nearest_exchange(&self, t_us: u64) -> Exchange {
        let ex = &self.exchanges;
        let i = ex.partition_point(|e| e.sent_us <= t_us);
        [i.checked_sub(1), Some(i).filter(|&i| i < ex.len())]
            .into_iter()
            .flatten()
            .map(|i| ex[i])
            .min_by_key(|e| e.sent_us.abs_diff(t_us))
            .expect("exchanges")
    }

    /// PX4's UTC (µs) at bridge instant `t_us` (see the module documentation).
    pub fn reference_utc_us(&self, t_us: f64) -> f64 {
        let g = &self.gcs;
        let i = g.partition_point(|r| r.at_us <= t_us).clamp(1, g.len() - 1);
        let (a, b) = (g[i - 1], g[i]);
        let utc = a.utc_us as f64
            + (b.utc_us as f64 - a.utc_us as f64) * (t_us - a.at_us) / (b.at_us - a.at_us);
        utc + GCS_STAMP_DELAY_US
    }

    /// The host's clock (Unix µs) at bridge instant `t_us`, as the capture's least start.
    pub fn host_us(&self, t_us: f64) -> f64 {
        self.t0_wall_us + t_us
    }

    /// The captured bridge's events named `event`.
    pub fn events_named(&self, event: &str) -> Vec<&CapturedEvent> {
        self.events.iter().filter(|e| e.event == event).collect()
    }
}

/// Serial time of `bytes` at `baud` (8N1), µs, rounded up.
pub fn serial_us(bytes: usize, baud: u32) -> u64 {
    (bytes as u64 * 10_000_000).div_ceil(u64::from(baud))
}

/// A TIMESYNC request of the bridge, and how it was answered.
#[derive(Debug, Clone, Copy)]
pub struct Answer {
    /// The request's start on the line (true time = the capture's bridge µs).
    pub started_us: u64,
    /// The tc1 given, ns.
    pub tc1_ns: i64,
    /// When the reply starts on the line.
    pub reply_at_us: u64,
}

/// PX4 as the capture shows it, replayed to the engine (see the module documentation).
/// True time is the capture's bridge clock (µs).
pub struct CapturedPx4 {
    capture: Capture,
    /// The next captured frame to send (TIMESYNC replies are made, not replayed).
    next: usize,
    deframer: Deframer<MavlinkFraming, MAX_FRAME_LEN>,
    replies: VecDeque<(u64, Vec<u8>)>,
    /// Every request answered.
    pub answers: Vec<Answer>,
    /// Frames from the bridge PX4 read, by message id.
    pub received: Vec<(u64, u32)>,
}

impl CapturedPx4 {
    /// The replay of `capture`.
    pub fn new(capture: Capture) -> Self {
        CapturedPx4 {
            capture,
            next: 0,
            deframer: Deframer::new(MavlinkFraming::new()),
            replies: VecDeque::new(),
            answers: Vec::new(),
            received: Vec::new(),
        }
    }

    /// The capture replayed.
    pub fn capture(&self) -> &Capture {
        &self.capture
    }

    /// The next captured frame to put on the line and the instant it starts: its last
    /// byte arrives at its captured instant.
    fn next_frame(&mut self) -> Option<(u64, Vec<u8>)> {
        loop {
            let f = self.capture.rx.get(self.next)?;
            if f.msg == "TIMESYNC" {
                self.next += 1;
                continue;
            }
            let start = f.t_us.saturating_sub(serial_us(f.raw.len(), LINE_BAUD));
            return Some((start, f.raw.clone()));
        }
    }

    fn answer(&mut self, now_us: u64, ts1: i64, len: usize) {
        let started_us = now_us.saturating_sub(serial_us(len, LINE_BAUD));
        let nearest = self.capture.nearest_exchange(started_us);
        let tc1_ns = self.capture.boot_ns_at(started_us as f64);
        let reply = MavMessage::TIMESYNC(TIMESYNC_DATA {
            tc1: tc1_ns,
            ts1,
            target_system: nearest.target.0,
            target_component: nearest.target.1,
        });
        let header = Header {
            sequence: nearest.seq,
            system_id: 6,
            component_id: 1,
        };
        let mut buf = [0u8; MAX_FRAME_LEN];
        let n = protocol_core::mavlink::encode(&reply, &header, &mut buf).expect("encode");
        // The captured round trip, from the request's start to the reply's last byte.
        let rtt = nearest.received_us - nearest.sent_us;
        let reply_at_us = (started_us + rtt)
            .saturating_sub(serial_us(n, LINE_BAUD))
            .max(now_us);
        self.answers.push(Answer {
            started_us,
            tc1_ns,
            reply_at_us,
        });
        let i = self.replies.partition_point(|(at, _)| *at <= reply_at_us);
        self.replies.insert(i, (reply_at_us, buf[..n].to_vec()));
    }
}

impl Peer for CapturedPx4 {
    fn receive(&mut self, now_us: u64, bytes: &[u8]) {
        let mut requests = Vec::new();
        let mut received = Vec::new();
        self.deframer.push(bytes, |ev| {
            if let DeframerEvent::Frame(f) = ev
                && let Ok(p) = Packet::decode(f)
            {
                received.push(protocol_core::mavlink::Frame::new_unchecked(f).message_id());
                if let protocol_core::mavlink::Message::Known(MavMessage::TIMESYNC(t)) = p.message
                    && t.tc1 == 0
                {
                    requests.push((t.ts1, f.len()));
                }
            }
        });
        self.received
            .extend(received.into_iter().map(|id| (now_us, id)));
        for (ts1, len) in requests {
            self.answer(now_us, ts1, len);
        }
    }

    fn poll(&mut self, _now_us: u64) {}

    fn next_wakeup(&self) -> u64 {
        let frame = self
            .capture
            .rx
            .iter()
            .skip(self.next)
            .find(|f| f.msg != "TIMESYNC")
            .map(|f| f.t_us.saturating_sub(serial_us(f.raw.len(), LINE_BAUD)));
        let reply = self.replies.front().map(|(at, _)| *at);
        [frame, reply]
            .into_iter()
            .flatten()
            .min()
            .unwrap_or(u64::MAX)
    }

    fn transmit(&mut self, now_us: u64) -> Vec<(u64, Vec<u8>)> {
        let mut out = Vec::new();
        loop {
            let frame = self.next_frame().filter(|(at, _)| *at <= now_us);
            let reply = self
                .replies
                .front()
                .filter(|(at, _)| *at <= now_us)
                .cloned();
            match (frame, reply) {
                (Some(f), Some(r)) if r.0 < f.0 => {
                    self.replies.pop_front();
                    out.push(r);
                }
                (Some(f), _) => {
                    self.next += 1;
                    out.push(f);
                }
                (None, Some(r)) => {
                    self.replies.pop_front();
                    out.push(r);
                }
                (None, None) => return out,
            }
        }
    }
}
