//! The bridge's tasks, written once: on the STM32 (the `bridge-fw` binary, `src/main.rs`)
//! and on the host ([`host`], feature `host`).
//!
//! Everything that decides something lives in [`bridge_engine::Engine`]; these
//! tasks only move bytes, read the clock and drive pins. Each is a plain `async fn` that
//! takes its resources, generic over [`embedded_io_async::Read`]/[`Write`](embedded_io_async::Write),
//! [`embedded_hal::digital::OutputPin`] and `embassy_time`, and never returns:
//!
//! | task | what it does |
//! | --- | --- |
//! | [`link_reader`] | UART → [`Engine::receive`]; a silence of [`Timing::idle`] after bytes → [`Engine::idle`] (an input: what it means is the engine's decision) |
//! | [`link_writer`] | engine → UART, one whole frame at a time ([`Engine::transmit`]); on the pod link it holds a frame that would still be on the wire at a planned RTC_IO edge |
//! | [`link`] | both of the above for one port (FC, pod, and the optional MAVLink telemetry link) |
//! | [`engine_task`] | [`Engine::poll`] at [`poll_at`](Engine::poll_at); RTC_IO at the instant [`pin`](Engine::pin) names ([`RtcIo`]: a timer's output compare armed ahead, or a pin set at the timer alarm), then [`pin_done`](Engine::pin_done) with the instant it was made, in one critical section, then the pod writer is woken |
//! | [`pps_task`] | PPS edges ([`PpsInput`]: the instants a timer captured) → [`Engine::pps`] |
//! | [`watchdog_task`] | feeds the watchdog only while the engine task and every link loop (FC, pod and, where it runs, telemetry: reader and writer) make progress |
//! | [`led_task`] | boot, the FC side, then FC link, pod link, UTC and faults as blink codes ([`led::LED_CODES`]) |
//! | [`console_task`] | the console on the update port (the ST-LINK virtual COM port): bytes to [`Engine::console_receive`](bridge_engine::Engine::console_receive), its answers back; the port to the update protocol on `update` or an update frame's sync; returns for a restart once the store has written what waits |
//! | [`update_task`] | the update protocol on the update port (the ST-LINK virtual COM port) to the sans-IO [`bridge_update::Receiver`], and the confirmation of an image on trial |
//! | [`log_task`] | engine events and the tasks' own [`LogRecord`]s to an [`EventSink`] (defmt on the MCU, print/JSON on the host) |
//! | [`store_task`] | the engine's records to keep ([`Engine::take_record`](bridge_engine::Engine::take_record)) to a [`RecordStore`] (a flash range on the MCU, a state file on Linux); [`restore`] gives them back at start |
//!
//! The tasks share one [`Shared`]: the engine behind a blocking mutex (never held across
//! an `.await`), and [`Signal`](embassy_sync::signal::Signal)s that wake the writers, the
//! engine task and the logger. Each wakes only when the engine's [`Changes`] concern it
//! (its queue got a frame, the pin plan changed, events wait) or, the engine task, when an
//! input brings its next poll forward.
//!
//! # RTC_IO edge → first byte of the 0x00030E
//! On the board the edge is TIM2's output compare (CH3): the engine task arms it 1 ms
//! before the planned instant ([`RtcIo::arm`]) and the hardware raises the pin at the
//! compare, to the timer's tick, whatever the task does. Elsewhere ([`RtcIo`] for any
//! output pin) the task sleeps on a timer alarm set to the edge's instant and sets the
//! pin when it fires. Either way, at the instant, in one critical section: the edge is
//! completed ([`RtcIo::complete`]: the compare's instant, or the pin set and the clock
//! read), and [`Engine::pin_done`] puts the 0x00030E at the head of the pod queue.
//! Nothing that can wait lies between these.
//! The pod writer is then woken; its delay to the first byte is one executor hand-over
//! plus the frame already on the wire. The writer avoids the latter: it does not start a
//! frame that would still be on the wire at a planned edge ([`link_writer`]), and it waits
//! for each frame to leave the UART (`flush`) before taking the next, so at most one
//! frame is ever in the UART's buffer. Every first pod frame after an edge is logged with
//! its measured delay ([`LogKind::EdgeToFrame`]).
//!
//! [`Engine`]: bridge_engine::Engine
//! [`Engine::receive`]: bridge_engine::Engine::receive
//! [`Engine::idle`]: bridge_engine::Engine::idle
//! [`Engine::transmit`]: bridge_engine::Engine::transmit
//! [`Engine::pps`]: bridge_engine::Engine::pps
#![cfg_attr(not(feature = "host"), no_std)]

pub mod config;
mod console;
mod engine;
mod engine_task;
pub mod layout;
pub mod led;
mod link;
mod log;
mod pps;
pub mod ram_flash;
pub mod reset;
mod rtc_io;
mod shared;
pub mod store;
mod tick_clock;
mod update;
mod watchdog;

#[cfg(feature = "host")]
pub mod host;

pub use console::{ConsoleEnd, console, console_task};
pub use engine::{BridgeEngine, Status};
pub use engine_task::engine_task;
pub use led::{Blink, Fault, Faults, led_task, strap_error_led};
pub use link::{link, link_reader, link_writer};
pub use log::{EventSink, log_task};
pub use pps::{NoPps, PpsInput, pps_task};
pub use rtc_io::RtcIo;
pub use shared::{Heartbeat, LogKind, LogRecord, Shared, Timing};
pub use store::{FlashStore, RecordStore, restore, restore_settings, store_task};
pub use tick_clock::TickClock;
pub use update::{UpdateLog, update_task};
pub use watchdog::watchdog_task;

pub use bridge_engine::{
    Changes, Config, Engine, Event, Instant, InstantNs, Level, PinAction, Port,
};

/// The engine's clock: embassy-time's, in microseconds since boot.
#[must_use]
pub fn now() -> Instant {
    Instant::from_micros(embassy_time::Instant::now().as_micros())
}

/// An engine instant as an embassy-time instant (same origin, same unit).
#[must_use]
pub fn to_embassy(at: Instant) -> embassy_time::Instant {
    embassy_time::Instant::from_micros(at.as_micros())
}
