//! The bridge's tasks on the host (feature `host`): the same `async fn`s as the firmware,
//! with in-memory pipes as UARTs, a recording fake pin, and a small executor loop that
//! runs on virtual or real time.
//!
//! ```
//! use bridge_fw::host::{self, Clock, HostLinks, HostShared, PinRecorder};
//! use bridge_fw::{Config, Engine, Timing};
//! use embassy_futures::select::select;
//! use embassy_time::{Duration, Timer};
//!
//! let config = Config::DEFAULT;
//! let shared = HostShared::new(Engine::new(config), Timing::from_config(&config));
//! let links = HostLinks::new();
//! let rtc_io = PinRecorder::new();
//! // One minute of virtual time takes milliseconds: time jumps to the next alarm
//! // whenever every task waits.
//! host::run(Clock::Virtual, || select(
//!     host::bridge(&shared, &links, rtc_io.clone(), |r: &bridge_fw::LogRecord| println!("{r:?}"), || {}),
//!     Timer::after(Duration::from_secs(60)),
//! ));
//! assert!(rtc_io.edges().is_empty(), "no UTC, no RTC_IO pulse");
//! ```
//!
//! # Clocks
//! - [`Clock::Virtual`]: deterministic and fast, like tokio's paused clock. Time starts at
//!   0 and stands still while any task can run; when every task waits, it jumps to the
//!   next timer. Everything must run inside the one [`run`] (simulated peers are futures
//!   joined with [`bridge`]); no other thread may feed the pipes.
//! - [`Clock::Real`]: the process's monotonic clock. Other threads may feed and drain the
//!   pipes (serial ports, TCP): from a plain thread use [`block_on`] with the pipe's
//!   async `write`/`read`, or its `try_write`/`try_read`. This is what the Linux runner
//!   uses.
//!
//! The clock is per thread: tests on parallel threads are independent. The time driver
//! is this crate's (do not enable embassy-time's `std` feature next to it), so a program
//! linking `bridge-fw` with `host` gets embassy-time from here.

mod driver;

use std::convert::Infallible;
use std::future::Future;
use std::pin::pin;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::task::{Context, Poll, Wake, Waker};
use std::thread::Thread;

use bridge_engine::{Engine, Instant, Level, Port};
use embassy_futures::join::{join3, join5};
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_sync::pipe::Pipe;
use embassy_time::Duration;
use embedded_hal::digital::{ErrorType, OutputPin};

use crate::{
    BridgeEngine, EventSink, Heartbeat, NoPps, PpsInput, RtcIo, Shared, engine_task, link,
    log_task, pps_task, watchdog_task,
};

/// Which time the executor loop runs on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Clock {
    /// Simulated time: jumps to the next timer when every task waits.
    Virtual,
    /// The process's monotonic clock.
    Real,
}

/// Bytes each pipe holds (a writer waits when it is full: no byte is ever lost).
pub const PIPE_BYTES: usize = 1024;

/// One direction of a host "UART".
pub type HostPipe = Pipe<CriticalSectionRawMutex, PIPE_BYTES>;

/// The shared state of the tasks on the host.
pub type HostShared<E = Engine> = Shared<CriticalSectionRawMutex, E>;

/// One serial link as two pipes, named from the bridge's side.
pub struct HostLink {
    /// Peer → bridge: the peer writes here.
    pub rx: HostPipe,
    /// Bridge → peer: the peer reads here.
    pub tx: HostPipe,
}

impl HostLink {
    /// Two empty pipes.
    #[must_use]
    pub const fn new() -> Self {
        HostLink {
            rx: Pipe::new(),
            tx: Pipe::new(),
        }
    }
}

impl Default for HostLink {
    fn default() -> Self {
        Self::new()
    }
}

/// The bridge's serial links as pipes, named from the bridge's side: the FC and pod links,
/// and the optional MAVLink telemetry link ([`Port::Telemetry`]).
pub struct HostLinks {
    /// FC → bridge: the FC (or whatever stands for it) writes here.
    pub fc_rx: HostPipe,
    /// Bridge → FC: the FC reads here.
    pub fc_tx: HostPipe,
    /// Pod → bridge.
    pub pod_rx: HostPipe,
    /// Bridge → pod.
    pub pod_tx: HostPipe,
    /// The telemetry link, when there is one: [`bridge`] then runs its reader and writer
    /// and the watchdog supervises them.
    pub telemetry: Option<HostLink>,
}

impl HostLinks {
    /// Four empty pipes, no telemetry link.
    #[must_use]
    pub const fn new() -> Self {
        HostLinks {
            fc_rx: Pipe::new(),
            fc_tx: Pipe::new(),
            pod_rx: Pipe::new(),
            pod_tx: Pipe::new(),
            telemetry: None,
        }
    }

    /// Four empty pipes and the telemetry link's two.
    #[must_use]
    pub const fn with_telemetry() -> Self {
        HostLinks {
            fc_rx: Pipe::new(),
            fc_tx: Pipe::new(),
            pod_rx: Pipe::new(),
            pod_tx: Pipe::new(),
            telemetry: Some(HostLink::new()),
        }
    }
}

impl Default for HostLinks {
    fn default() -> Self {
        Self::new()
    }
}

/// The watchdog check period of [`bridge`] (as on the MCU).
pub const WATCHDOG_PERIOD: Duration = Duration::from_millis(250);

/// Every task of the firmware but the LED, on `links`: the FC and pod links (and the
/// telemetry link when `links` has one), the engine task with `rtc_io`, the log task into
/// `sink`, and the watchdog task calling `feed` (supervising the telemetry link's loops
/// too when it runs, as the firmware built with `telemetry` does).
pub async fn bridge<E, P, S, F>(
    shared: &HostShared<E>,
    links: &HostLinks,
    rtc_io: P,
    sink: S,
    feed: F,
) -> !
where
    E: BridgeEngine,
    P: RtcIo,
    S: EventSink,
    F: FnMut(),
{
    bridge_with_pps(shared, links, rtc_io, NoPps, sink, feed).await
}

/// [`bridge`] with a PPS input: its edges go to the engine ([`pps_task`]).
pub async fn bridge_with_pps<E, P, Q, S, F>(
    shared: &HostShared<E>,
    links: &HostLinks,
    rtc_io: P,
    pps: Q,
    sink: S,
    feed: F,
) -> !
where
    E: BridgeEngine,
    P: RtcIo,
    Q: PpsInput,
    S: EventSink,
    F: FnMut(),
{
    let supervised = Heartbeat::supervised(links.telemetry.is_some());
    let telemetry = async {
        match &links.telemetry {
            Some(t) => link(shared, Port::Telemetry, &t.rx, &t.tx).await,
            None => core::future::pending::<()>().await,
        }
    };
    let ((never, _, _, _, _), (), _) = join3(
        join5(
            link(shared, Port::Fc, &links.fc_rx, &links.fc_tx),
            link(shared, Port::Pod, &links.pod_rx, &links.pod_tx),
            engine_task(shared, rtc_io),
            log_task(shared, sink),
            watchdog_task(shared, WATCHDOG_PERIOD, supervised, feed),
        ),
        telemetry,
        pps_task(shared, pps),
    )
    .await;
    never
}

/// Wakes the executor loop.
struct Notify {
    woken: AtomicBool,
    thread: Thread,
}

impl Wake for Notify {
    fn wake(self: Arc<Self>) {
        self.wake_by_ref();
    }

    fn wake_by_ref(self: &Arc<Self>) {
        self.woken.store(true, Ordering::Release);
        self.thread.unpark();
    }
}

/// Sets this thread's clock to `clock`, builds the future with `make` (so that timers it
/// creates at once, such as `Timer::after`, count on that clock) and runs it to
/// completion: polls it whenever it is woken; when it waits, virtual time jumps to the
/// next timer, real time sleeps until then (or until another thread wakes it).
///
/// # Panics
/// On virtual time, when the future waits with no timer set: nothing could ever wake it.
pub fn run<F: Future>(clock: Clock, make: impl FnOnce() -> F) -> F::Output {
    let previous = driver::set_clock(clock);
    let fut = make();
    let notify = Arc::new(Notify {
        woken: AtomicBool::new(true),
        thread: std::thread::current(),
    });
    let waker = Waker::from(notify.clone());
    let mut cx = Context::from_waker(&waker);
    let mut fut = pin!(fut);
    let out = loop {
        if notify.woken.swap(false, Ordering::AcqRel) {
            if let Poll::Ready(v) = fut.as_mut().poll(&mut cx) {
                break v;
            }
            continue;
        }
        match clock {
            Clock::Virtual => {
                let Some(next) = driver::next_alarm() else {
                    #[allow(clippy::panic)]
                    {
                        panic!("virtual time: every task waits and no timer is set (deadlock)");
                    }
                };
                driver::advance_to(next);
            }
            Clock::Real => match driver::next_alarm() {
                Some(next) => {
                    let wait = next.saturating_sub(driver::real_now());
                    if wait > 0 {
                        std::thread::park_timeout(std::time::Duration::from_micros(wait));
                    }
                }
                None => std::thread::park(),
            },
        }
        driver::wake_due();
    };
    driver::set_clock(previous);
    out
}

/// The process's real clock (what [`Clock::Real`] runs on), in nanoseconds since its
/// first use: to map another clock's time stamps (the kernel's) to it.
#[must_use]
pub fn real_now_ns() -> u64 {
    driver::real_now_ns()
}

/// [`run`] on real time: for plain threads that feed or drain the pipes.
pub fn block_on<F: Future>(fut: F) -> F::Output {
    run(Clock::Real, || fut)
}

/// A fake output pin that records every change with the instant it was made.
#[derive(Debug, Clone, Default)]
pub struct PinRecorder {
    edges: Arc<Mutex<Vec<(Level, Instant)>>>,
}

impl PinRecorder {
    /// A pin with no change yet (low).
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Every change so far, oldest first.
    #[must_use]
    pub fn edges(&self) -> Vec<(Level, Instant)> {
        self.edges.lock().map(|e| e.clone()).unwrap_or_default()
    }

    fn set(&self, level: Level) {
        if let Ok(mut e) = self.edges.lock() {
            e.push((level, crate::now()));
        }
    }
}

impl ErrorType for PinRecorder {
    type Error = Infallible;
}

impl OutputPin for PinRecorder {
    fn set_low(&mut self) -> Result<(), Infallible> {
        self.set(Level::Low);
        Ok(())
    }

    fn set_high(&mut self) -> Result<(), Infallible> {
        self.set(Level::High);
        Ok(())
    }
}
