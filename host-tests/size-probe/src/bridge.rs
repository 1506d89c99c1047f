//! The bridge engine as firmware drives it: built from an opaque `Config` (so every
//! compiled-in FC side is reachable), fed opaque bytes on both ports, polled, its pin
//! actions taken and its queues and events drained.

use bridge_engine::{Config, Engine, Instant, Port};
use core::hint::black_box;

pub fn probe(input: &[u8], out: &mut [u8]) {
    let mut engine = Engine::new(black_box(Config::DEFAULT));
    let now = Instant::from_micros(black_box(0));
    let e = black_box(&mut engine);
    for port in [Port::Fc, Port::Pod] {
        let port = black_box(port);
        black_box(e.receive(now, port, input));
        black_box(e.idle(now, port));
    }
    black_box(e.poll(now));
    if let Some(p) = e.pin() {
        black_box(e.pin_done(p.level, p.at));
    }
    black_box(e.poll_at());
    for port in [Port::Fc, Port::Pod] {
        black_box(e.transmit(black_box(port), out));
    }
    while let Some(ev) = e.next_event() {
        black_box(ev);
    }
}
