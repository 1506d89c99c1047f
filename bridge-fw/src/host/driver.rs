//! The host's embassy-time driver: per thread, virtual or real time.
//!
//! Each thread that runs [`run`](super::run) has its own clock and alarm list (thread
//! local), so tests on parallel threads never see each other's time. Real time is the
//! process's monotonic clock (µs since its first use); virtual time starts at 0 and only
//! moves when the executor loop advances it to the next alarm.

use std::cell::RefCell;
use std::sync::OnceLock;
use std::task::Waker;

use super::Clock;

/// The process's real-time origin.
static ORIGIN: OnceLock<std::time::Instant> = OnceLock::new();

/// Microseconds of real time since the origin.
pub(super) fn real_now() -> u64 {
    let origin = ORIGIN.get_or_init(std::time::Instant::now);
    u64::try_from(origin.elapsed().as_micros()).unwrap_or(u64::MAX)
}

/// Nanoseconds of real time since the origin.
pub(super) fn real_now_ns() -> u64 {
    let origin = ORIGIN.get_or_init(std::time::Instant::now);
    u64::try_from(origin.elapsed().as_nanos()).unwrap_or(u64::MAX)
}

/// One thread's clock.
struct ThreadClock {
    clock: Clock,
    virtual_now: u64,
    /// Wake-ups asked for: (instant, waker), one entry per waker (the earliest instant).
    alarms: Vec<(u64, Waker)>,
}

impl ThreadClock {
    fn now(&self) -> u64 {
        match self.clock {
            Clock::Virtual => self.virtual_now,
            Clock::Real => real_now(),
        }
    }
}

thread_local! {
    static CLOCK: RefCell<ThreadClock> = const {
        RefCell::new(ThreadClock { clock: Clock::Real, virtual_now: 0, alarms: Vec::new() })
    };
}

/// Sets this thread's clock (virtual time restarts at 0); returns the previous one.
pub(super) fn set_clock(clock: Clock) -> Clock {
    CLOCK.with(|c| {
        let mut c = c.borrow_mut();
        c.alarms.clear();
        c.virtual_now = 0;
        core::mem::replace(&mut c.clock, clock)
    })
}

/// The earliest alarm of this thread.
pub(super) fn next_alarm() -> Option<u64> {
    CLOCK.with(|c| c.borrow().alarms.iter().map(|(t, _)| *t).min())
}

/// Virtual time only: moves this thread's clock forward to `to` (never back).
pub(super) fn advance_to(to: u64) {
    CLOCK.with(|c| {
        let mut c = c.borrow_mut();
        c.virtual_now = c.virtual_now.max(to);
    });
}

/// Wakes every alarm of this thread that is due.
pub(super) fn wake_due() {
    let due: Vec<Waker> = CLOCK.with(|c| {
        let mut c = c.borrow_mut();
        let now = c.now();
        let mut due = Vec::new();
        c.alarms.retain(|(t, w)| {
            if *t <= now {
                due.push(w.clone());
                false
            } else {
                true
            }
        });
        due
    });
    due.into_iter().for_each(Waker::wake);
}

struct HostDriver;

impl embassy_time_driver::Driver for HostDriver {
    fn now(&self) -> u64 {
        CLOCK.with(|c| c.borrow().now())
    }

    fn schedule_wake(&self, at: u64, waker: &Waker) {
        CLOCK.with(|c| {
            let mut c = c.borrow_mut();
            if let Some(entry) = c.alarms.iter_mut().find(|(_, w)| w.will_wake(waker)) {
                entry.0 = entry.0.min(at);
            } else {
                c.alarms.push((at, waker.clone()));
            }
        });
    }
}

// The driver is found by the linker through two `#[no_mangle]` functions (embassy-time's
// driver interface); the macro is the documented way to define them, and what it needs
// `unsafe` for is the `no_mangle` attribute only.
#[allow(unsafe_code)]
mod registration {
    embassy_time_driver::time_driver_impl!(static DRIVER: super::HostDriver = super::HostDriver);
}
