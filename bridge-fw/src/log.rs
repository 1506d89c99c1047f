//! Event logging: the engine's [`Event`]s and the tasks' own records, to a sink.

use embassy_sync::blocking_mutex::raw::RawMutex;
use protocol_core::bridge::{Duration, Event, Instant, Level, Port};

use crate::engine::BridgeEngine;
use crate::shared::{Heartbeat, Shared};

/// What happened.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum What {
    /// An engine event (stamped when the log task took it).
    Engine(Event),
    /// RTC_IO was set to this level (stamped with the instant read right after).
    Pin(Level),
    /// RTC_IO could not be set to this level (the engine was told it was).
    PinError(Level),
    /// The first pod frame after a rising edge started: `delay` after the edge.
    EdgeToFrame {
        /// From the edge to the first byte handed to the pod UART.
        delay: Duration,
        /// Length of that frame (the 0x00030E, unless the engine had none to send).
        len: u16,
    },
    /// A UART error (framing, noise, overrun...) on a read.
    ReadError(Port),
    /// A write failed: the frame was dropped.
    WriteError(Port),
    /// The watchdog was not fed: these loops made no progress in the last period.
    Stalled(Heartbeat),
}

/// One logged happening.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Record {
    /// Local instant.
    pub at: Instant,
    /// What.
    pub what: What,
}

/// Where the log task puts records: defmt on the MCU, stdout or JSON on the host, a
/// `Vec` in tests. Any `FnMut(&Record)` is a sink.
pub trait EventSink {
    /// Takes one record; must not block for long (the log task shares the executor).
    fn record(&mut self, record: &Record);
}

impl<F: FnMut(&Record)> EventSink for F {
    fn record(&mut self, record: &Record) {
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
            sink.record(&Record {
                at: crate::now(),
                what: What::Engine(e),
            });
        }
        shared.wake_log.wait().await;
    }
}
