//! embassy-time driver on the Cortex-M SysTick, for the emulated board (`qemu` feature).
//!
//! QEMU's `b-l475e-iot01a` machine models none of the STM32 timers (TIM1..17, LPTIM1/2 and
//! the RTC read as zero), so embassy-stm32's time drivers never tick there. SysTick belongs
//! to the Cortex-M4 core and QEMU clocks it from the RCC model's HCLK.
//!
//! The time base is the host's monotonic clock, read through semihosting (SYS_ELAPSED and
//! SYS_TICKFREQ: QEMU answers host nanoseconds since it started). SysTick interrupts
//! `IRQ_HZ` times a second only to serve the alarms: each is served on the first interrupt
//! at or after its deadline.
//!
//! Why not count the SysTick periods: the bridge's time discipline trusts a clock only
//! within 300 ppm of the FC's (two crystals), and the FC simulators run on the host's
//! clock. QEMU raises SysTick late when the host is busy, two expiries then fold into one
//! pending exception and a period is lost: a counted clock ran slow by tenths of a percent
//! on a loaded 2-core machine, so the UTC mapping never converged and no time sync was
//! ever sent. The host clock is what a crystal is to the board: it keeps time whatever
//! the CPU does. Emulated execution still lags when the host is busy (alarms are served
//! late), so the emulated tests use generous time-outs and check no durations.
//!
//! `unsafe`: none written here; `time_driver_impl!` registers the driver through two
//! `#[unsafe(no_mangle)]` functions (embassy-time's driver interface), which is why the
//! module allows `unsafe_code`.

use core::cell::{Cell, RefCell};
use core::task::Waker;

use cortex_m::peripheral::SYST;
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m_rt::exception;
use critical_section::{CriticalSection, Mutex};
use embassy_time_driver::{Driver, TICK_HZ};
use embassy_time_queue_utils::Queue;

/// SysTick interrupt rate: the alarms' resolution, and the pace at which QEMU hands the
/// guest received bytes. QEMU's USART model takes one byte at a time, and its main loop
/// offers the next one only when something else wakes it: in practice the SysTick timer.
/// At 1 kHz the FC link carried 1000 bytes a second, less than ArduPilot's XF Robot
/// driver sends (72 bytes at 50 Hz); at 10 kHz it keeps up with 115200 baud.
const IRQ_HZ: u32 = 10_000;

struct SysTickDriver {
    /// Host clock ticks per embassy tick (SYS_TICKFREQ / TICK_HZ; 0 before `init`).
    host_per_tick: Mutex<Cell<u64>>,
    /// The last time read (the clock never goes back, even if a read fails).
    last: Mutex<Cell<u64>>,
    /// Deadline (in ticks) of the earliest queued timer; `u64::MAX` when none.
    next_alarm: Mutex<Cell<u64>>,
    queue: Mutex<RefCell<Queue>>,
}

embassy_time_driver::time_driver_impl!(static DRIVER: SysTickDriver = SysTickDriver {
    host_per_tick: Mutex::new(Cell::new(0)),
    last: Mutex::new(Cell::new(0)),
    next_alarm: Mutex::new(Cell::new(u64::MAX)),
    queue: Mutex::new(RefCell::new(Queue::new())),
});

/// Starts the SysTick interrupt. `hclk_hz` is the core clock (SysTick runs from it).
pub fn init(mut syst: SYST, hclk_hz: u32) {
    // QEMU: 1 GHz (nanoseconds); a frequency below TICK_HZ would make a tick of 0.
    let freq = semihosting::sys::arm_compat::sys_tickfreq().map_or(0, |f| f as u64);
    let per_tick = (freq / TICK_HZ).max(1);
    critical_section::with(|cs| DRIVER.host_per_tick.borrow(cs).set(per_tick));
    let reload = hclk_hz / IRQ_HZ - 1;
    assert!(reload <= 0x00FF_FFFF, "SysTick reload is 24 bits");
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(reload);
    syst.clear_current();
    syst.enable_interrupt();
    syst.enable_counter();
}

impl SysTickDriver {
    fn now_cs(&self, cs: CriticalSection) -> u64 {
        let last = self.last.borrow(cs);
        let per_tick = self.host_per_tick.borrow(cs).get();
        if per_tick == 0 {
            return last.get();
        }
        let now = semihosting::sys::arm_compat::sys_elapsed()
            .map_or(last.get(), |host| (host / per_tick).max(last.get()));
        last.set(now);
        now
    }

    /// Wakes every expired timer and remembers the next deadline.
    fn serve_alarms(&self, cs: CriticalSection) {
        let now = self.now_cs(cs);
        let next = self.queue.borrow_ref_mut(cs).next_expiration(now);
        self.next_alarm.borrow(cs).set(next);
    }

    fn on_tick(&self) {
        critical_section::with(|cs| {
            if self.now_cs(cs) >= self.next_alarm.borrow(cs).get() {
                self.serve_alarms(cs);
            }
        });
    }
}

impl Driver for SysTickDriver {
    fn now(&self) -> u64 {
        critical_section::with(|cs| self.now_cs(cs))
    }

    fn schedule_wake(&self, at: u64, waker: &Waker) {
        critical_section::with(|cs| {
            if self.queue.borrow_ref_mut(cs).schedule_wake(at, waker) {
                self.serve_alarms(cs);
            }
        });
    }
}

#[exception]
fn SysTick() {
    DRIVER.on_tick();
}
