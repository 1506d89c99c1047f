//! Event logging: the engine's [`Event`]s and the tasks' own records, to a sink.

use embassy_sync::blocking_mutex::raw::RawMutex;

use crate::engine::BridgeEngine;
use crate::shared::{LogKind, LogRecord, Shared};

/// Where the log task puts records: defmt on the MCU, stdout or JSON on the host, a
/// `Vec` in tests. Any `FnMut(&LogRecord)` is a sink.
pub trait EventSink {
    /// Takes one record; must not block for long (the log task shares the executor).
    fn record(&mut self, record: &LogRecord);
}

impl<F: FnMut(&LogRecord)> EventSink for F {
    fn record(&mut self, record: &LogRecord) {
        self(record);
    }
}

/// Drains the task records and the engine's events into `sink`, oldest first, forever.
pub async fn log_task<M: RawMutex, E: BridgeEngine, S: EventSink>(
    shared: &Shared<M, E>,
    mut sink: S,
) -> ! {
    loop {
        while let Ok(r) = shared.records.try_receive() {
            sink.record(&r);
        }
        while let Some(e) = shared.with_state(|s| s.engine.next_event()) {
            sink.record(&LogRecord {
                at: crate::now(),
                what: LogKind::Engine(e),
            });
        }
        shared.wake_log.wait().await;
    }
}
