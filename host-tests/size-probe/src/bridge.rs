//! The bridge engine as firmware drives it: built from an opaque `Config` (so every
//! compiled-in FC side is reachable), fed opaque bytes on both ports, polled, its pin
//! actions taken and its queues and events drained.

use core::hint::black_box;
use protocol_core::bridge::{Config, Engine, Instant};

pub fn probe(input: &[u8], out: &mut [u8]) {
    let mut engine = Engine::new(black_box(Config::DEFAULT));
    let now = Instant::from_micros(black_box(0));
    let e = black_box(&mut engine);
    e.receive_fc(now, input);
    e.fc_idle(now);
    e.receive_pod(now, input);
    e.pod_idle(now);
    e.poll(now);
    if let Some(p) = e.pin() {
        e.pin_done(p.level, p.at);
    }
    black_box(e.poll_at());
    black_box(e.take_fc_frame(out));
    black_box(e.take_pod_frame(out));
    while let Some(ev) = e.next_event() {
        black_box(ev);
    }
}
