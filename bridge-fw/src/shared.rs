//! What the tasks share: the engine, the wake-ups between tasks, the heartbeat.

use core::cell::RefCell;
use core::sync::atomic::{AtomicBool, AtomicU8, AtomicU32, Ordering};

use bridge_engine::{Changes, Config, Duration, Event, Instant, Level, Port};
use embassy_sync::blocking_mutex::Mutex;
use embassy_sync::blocking_mutex::raw::RawMutex;
use embassy_sync::channel::Channel;
use embassy_sync::signal::Signal;

use crate::engine::BridgeEngine;

/// What a [`LogRecord`] reports: an engine event or one of the tasks' own happenings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum LogKind {
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
    /// The persistent store could not write the record of this key.
    StoreError(u16),
    /// The update port or the trial of a new image ([`update_task`](crate::update_task)).
    Update(crate::UpdateLog),
}

/// One entry for the log task, from the engine or a task, with its instant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct LogRecord {
    /// The local instant it happened (or was logged, for engine events).
    pub at: Instant,
    /// What happened.
    pub what: LogKind,
}

/// Records (pin edges, link errors, delays) waiting for the log task.
const RECORDS: usize = 8;

/// Time constants of the tasks (none of them a protocol decision: line timing and
/// supervision only). [`Timing::from_config`] derives them from the baud rates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Timing {
    /// FC link baud rate (8N1: ten bits a byte).
    pub fc_baud: u32,
    /// Pod link baud rate.
    pub pod_baud: u32,
    /// The telemetry link's baud rate.
    pub telemetry_baud: u32,
    /// A line is idle after this many byte times without a byte...
    pub idle_bytes: u32,
    /// ... and never sooner than this (the embassy-time alarm's granularity, the
    /// sender's own gaps).
    pub idle_min: Duration,
    /// Longest sleep of a task that the watchdog supervises: each marks its heartbeat at
    /// least this often while it is healthy.
    pub heartbeat: Duration,
}

impl Timing {
    /// 20 byte times (1.7 ms at 115200), at least 5 ms; heartbeat every 100 ms.
    ///
    /// A line idle flushes a broken candidate (a complete frame is handled on its last
    /// byte) and, on the FC link, is one input to the engine's burst rule (which also sees
    /// quiet gaps itself), while a false idle in the middle of a frame loses that frame:
    /// so the floor is generous. A host runner reading USB serial adapters (which deliver bytes
    /// in bursts, milliseconds apart) should raise [`Timing::idle_min`] to 20 ms or more.
    #[must_use]
    pub const fn from_config(config: &Config) -> Self {
        Timing {
            fc_baud: config.fc_baud,
            pod_baud: config.pod_baud,
            telemetry_baud: config.telemetry_baud,
            idle_bytes: 20,
            idle_min: Duration::from_millis(5),
            heartbeat: Duration::from_millis(100),
        }
    }

    /// The baud rate of `port`.
    #[must_use]
    pub const fn baud(&self, port: Port) -> u32 {
        match port {
            Port::Fc => self.fc_baud,
            Port::Pod => self.pod_baud,
            Port::Telemetry => self.telemetry_baud,
        }
    }

    /// Time on the wire of `bytes` bytes on `port` (8N1), rounded up.
    #[must_use]
    pub const fn wire_time(&self, port: Port, bytes: usize) -> Duration {
        let baud = self.baud(port);
        let baud = if baud == 0 { 1 } else { baud as u64 };
        let bits = (bytes as u64).saturating_mul(10).saturating_mul(1_000_000);
        Duration::from_micros(bits.div_ceil(baud))
    }

    /// Silence after which `port`'s line counts as idle.
    #[must_use]
    pub const fn idle(&self, port: Port) -> Duration {
        let t = self.wire_time(port, self.idle_bytes as usize);
        if t.as_micros() < self.idle_min.as_micros() {
            self.idle_min
        } else {
            t
        }
    }
}

/// One bit per supervised loop; [`Heartbeat::ALL`] when every one ran since the last check.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Heartbeat(pub u8);

impl Heartbeat {
    /// The engine/timer task.
    pub const ENGINE: Self = Self(1);
    /// The FC reader.
    pub const FC_RX: Self = Self(2);
    /// The FC writer.
    pub const FC_TX: Self = Self(4);
    /// The pod reader.
    pub const POD_RX: Self = Self(8);
    /// The pod writer.
    pub const POD_TX: Self = Self(16);
    /// The telemetry reader (supervised only where a telemetry link runs).
    pub const TEL_RX: Self = Self(32);
    /// The telemetry writer.
    pub const TEL_TX: Self = Self(64);
    /// Every loop of the FC and pod links and the engine.
    pub const ALL: Self = Self(31);
    /// Both loops of the telemetry link.
    pub const TELEMETRY: Self = Self(Self::TEL_RX.0 | Self::TEL_TX.0);

    /// The loops the watchdog supervises: [`Heartbeat::ALL`], and the telemetry link's
    /// two when one runs (the firmware built with `telemetry`, a host bench with a
    /// telemetry peer).
    #[must_use]
    pub const fn supervised(telemetry: bool) -> Self {
        if telemetry {
            Self(Self::ALL.0 | Self::TELEMETRY.0)
        } else {
            Self::ALL
        }
    }

    /// Whether every loop of `other` is in `self`.
    #[must_use]
    pub const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// The reader's bit of `port`.
    #[must_use]
    pub const fn rx(port: Port) -> Self {
        match port {
            Port::Fc => Self::FC_RX,
            Port::Pod => Self::POD_RX,
            Port::Telemetry => Self::TEL_RX,
        }
    }

    /// The writer's bit of `port`.
    #[must_use]
    pub const fn tx(port: Port) -> Self {
        match port {
            Port::Fc => Self::FC_TX,
            Port::Pod => Self::POD_TX,
            Port::Telemetry => Self::TEL_TX,
        }
    }
}

/// The engine and the task-side state around it.
pub(crate) struct State<E> {
    pub(crate) engine: E,
    /// The last rising edge not yet followed by a pod frame (for [`LogKind::EdgeToFrame`]).
    pub(crate) edge: Option<Instant>,
    /// When the engine task wakes by itself (its timer, set before it sleeps): an input
    /// after which the engine wants a poll sooner wakes it.
    pub(crate) engine_wakes_at: Instant,
}

/// Everything the tasks share. `M` is the mutex kind: `CriticalSectionRawMutex` on the
/// MCU (one core, interrupt-safe) and on the host (threads may feed the pipes).
pub struct Shared<M: RawMutex, E> {
    state: Mutex<M, RefCell<State<E>>>,
    timing: Timing,
    pub(crate) wake_engine: Signal<M, ()>,
    pub(crate) wake_fc_tx: Signal<M, ()>,
    pub(crate) wake_tel_tx: Signal<M, ()>,
    pub(crate) wake_pod_tx: Signal<M, ()>,
    pub(crate) wake_log: Signal<M, ()>,
    pub(crate) wake_store: Signal<M, ()>,
    pub(crate) wake_console: Signal<M, ()>,
    pub(crate) records: Channel<M, LogRecord, RECORDS>,
    /// The store task is writing a record it took.
    pub(crate) store_busy: AtomicBool,
    alive: AtomicU8,
    records_dropped: AtomicU32,
}

impl<M: RawMutex, E: BridgeEngine> Shared<M, E> {
    /// The shared state around `engine`.
    pub const fn new(engine: E, timing: Timing) -> Self {
        Shared {
            state: Mutex::new(RefCell::new(State {
                engine,
                edge: None,
                engine_wakes_at: Instant::ZERO,
            })),
            timing,
            wake_engine: Signal::new(),
            wake_fc_tx: Signal::new(),
            wake_tel_tx: Signal::new(),
            wake_pod_tx: Signal::new(),
            wake_log: Signal::new(),
            wake_store: Signal::new(),
            wake_console: Signal::new(),
            records: Channel::new(),
            store_busy: AtomicBool::new(false),
            alive: AtomicU8::new(0),
            records_dropped: AtomicU32::new(0),
        }
    }

    /// The tasks' time constants.
    pub const fn timing(&self) -> &Timing {
        &self.timing
    }

    /// Runs `f` on the engine (a blocking lock: `f` must not wait), waking nobody: for
    /// readers of the engine's state (a status display, a test) and for taking its
    /// outputs. An input goes through [`Shared::input`].
    pub fn with<R>(&self, f: impl FnOnce(&mut E) -> R) -> R {
        self.with_state(|s| f(&mut s.engine))
    }

    /// Runs an input `f` on the engine ([`BridgeEngine::receive`],
    /// [`BridgeEngine::idle`]) and wakes the tasks it concerns, by the [`Changes`] it
    /// returns: the writer of each port whose queue got a frame, the pod writer also when
    /// the pin plan changed (it may hold a frame for a planned edge), the log task when
    /// events wait; and the engine task when the pin plan changed or the engine now wants
    /// a poll before the task's timer.
    pub fn input(&self, f: impl FnOnce(&mut E) -> Changes) -> Changes {
        let (changes, poll_sooner) = self.with_state(|s| {
            let changes = f(&mut s.engine);
            let sooner = s.engine.poll_at().is_some_and(|t| t < s.engine_wakes_at);
            (changes, sooner)
        });
        if poll_sooner || changes.contains(Changes::PIN) {
            self.wake_engine.signal(());
        }
        self.wake(changes);
        changes
    }

    /// An input of the console ([`BridgeEngine::console_receive`]): wakes the tasks it
    /// concerns as [`Shared::input`] does; returns what the console asks of its task.
    pub fn console_input(
        &self,
        f: impl FnOnce(&mut E) -> (Changes, Option<bridge_engine::ConsoleAction>),
    ) -> Option<bridge_engine::ConsoleAction> {
        let mut action = None;
        self.input(|e| {
            let (changes, a) = f(e);
            action = a;
            changes
        });
        action
    }

    /// Runs `f` on the state, waking nobody.
    pub(crate) fn with_state<R>(&self, f: impl FnOnce(&mut State<E>) -> R) -> R {
        self.state.lock(|s| f(&mut s.borrow_mut()))
    }

    /// Wakes the output tasks that `changes` concern (see [`Shared::input`]); the engine
    /// task is the caller's.
    pub(crate) fn wake(&self, changes: Changes) {
        if changes.contains(Changes::FC_FRAME) {
            self.wake_fc_tx.signal(());
        }
        if changes.contains(Changes::TELEMETRY_FRAME) {
            self.wake_tel_tx.signal(());
        }
        if changes.intersects(Changes::POD_FRAME | Changes::PIN) {
            self.wake_pod_tx.signal(());
        }
        if changes.contains(Changes::EVENTS) {
            self.wake_log.signal(());
        }
        if changes.contains(Changes::STORE) {
            self.wake_store.signal(());
        }
        if changes.contains(Changes::CONSOLE) {
            self.wake_console.signal(());
        }
    }

    /// The writer of `port`'s wake-up.
    pub(crate) fn wake_tx(&self, port: Port) -> &Signal<M, ()> {
        match port {
            Port::Fc => &self.wake_fc_tx,
            Port::Pod => &self.wake_pod_tx,
            Port::Telemetry => &self.wake_tel_tx,
        }
    }

    /// Marks progress of one supervised loop.
    pub fn alive(&self, bit: Heartbeat) {
        self.alive.fetch_or(bit.0, Ordering::Relaxed);
    }

    /// The loops that made progress since the last call (and starts counting again).
    pub fn take_alive(&self) -> Heartbeat {
        Heartbeat(self.alive.swap(0, Ordering::Relaxed))
    }

    /// Queues a record for the log task (never waits: counted and dropped when full).
    pub fn record(&self, at: Instant, what: LogKind) {
        if self.records.try_send(LogRecord { at, what }).is_err() {
            self.records_dropped.fetch_add(1, Ordering::Relaxed);
        }
        self.wake_log.signal(());
    }

    /// Records dropped because the log task lagged.
    pub fn records_dropped(&self) -> u32 {
        self.records_dropped.load(Ordering::Relaxed)
    }
}
