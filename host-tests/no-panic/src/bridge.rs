//! The bridge engine: every public entry point of `Engine` (new, the settings and the
//! records restored from the store, the FC and pod inputs, the console, idle, poll, the
//! RTC_IO pin, the output queues, the records to store, events, the read-only views) with an
//! opaque configuration (so every FC side, SIYI, Viewlink, GCU, K40T and MAVLink, the
//! telemetry link (the port is opaque too), and every
//! configured behaviour is reachable), opaque bytes and instants, and the engine's state
//! made opaque between calls (`black_box(&mut engine)`: any state a previous call could
//! have left).

use bridge_engine::store::Problem;
use bridge_engine::{BuildInfo, Config, Engine, Instant, Level, Port, Restore, Sides};
use core::hint::black_box;

pub fn exercise(input: &[u8], out: &mut [u8]) {
    // The settings from opaque records (any key, any value), or an unreadable store.
    let mut restore = Restore::new(black_box(Config::DEFAULT), black_box(Sides::COMPILED));
    for key in Restore::keys() {
        black_box(&mut restore).record(black_box(key), input);
    }
    black_box(&mut restore).record(black_box(0), input);
    if black_box(false) {
        black_box(&mut restore).unreadable();
    }
    let mut engine = Engine::restored(black_box(restore).finish(), black_box(BuildInfo::ENGINE));
    black_box(black_box(&mut engine).restore(black_box(0), input));
    black_box(black_box(&mut engine).restore_failed(black_box(Problem::Unreadable)));
    let now = || Instant::from_micros(black_box(0));
    let port = || black_box(Port::Fc);
    black_box(black_box(&mut engine).receive(now(), port(), input));
    black_box(black_box(&mut engine).idle(now(), port()));
    black_box(black_box(&mut engine).receive(now(), black_box(Port::Pod), input));
    black_box(black_box(&mut engine).idle(now(), black_box(Port::Pod)));
    black_box(black_box(&mut engine).poll(now()));
    // The console: opaque bytes in (any command, any value), its answer out.
    black_box(black_box(&mut engine).console_receive(now(), input));
    black_box(black_box(&mut engine).console_resume());
    black_box(black_box(&mut engine).console_transmit(out));
    black_box(black_box(&engine).records_due());
    if let Some(p) = black_box(&mut engine).pin() {
        black_box(p);
    }
    black_box(black_box(&mut engine).pin_done(black_box(Level::High), now()));
    black_box(black_box(&mut engine).pin_done(black_box(Level::Low), now()));
    let e = black_box(&mut engine);
    black_box((e.pending(port()), e.poll_at(), e.fc_link()));
    black_box((e.counters(), e.utc(now()), e.utc_state(), e.pod_state()));
    black_box(e.config());
    black_box(e.transmit(port(), out));
    black_box(e.transmit(black_box(Port::Pod), out));
    while let Some(r) = black_box(&mut *e).take_record() {
        black_box(r.value());
    }
    while let Some(ev) = black_box(&mut *e).next_event() {
        black_box(ev);
    }
}
