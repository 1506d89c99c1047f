//! embassy-time driver on the Cortex-M SysTick, for the emulated board (`qemu` feature).
//!
//! QEMU's `b-l475e-iot01a` machine models none of the STM32 timers (TIM1..17, LPTIM1/2 and
//! the RTC read as zero), so embassy-stm32's time drivers never tick there. SysTick belongs
//! to the Cortex-M4 core and QEMU clocks it from the RCC model's HCLK.
//!
//! SysTick interrupts `IRQ_HZ` times a second and the handler counts the periods; `now()` is
//! that count in embassy ticks. It deliberately ignores the counter value inside the current
//! period: QEMU updates the counter and the pending bit at different moments, and an
//! interpolated `now()` could step backwards. A 1 ms resolution is ample for the emulated
//! tests. Alarms are served on the first interrupt at or after their deadline.
//!
//! Emulated time runs slow when the host is busy: QEMU then raises SysTick late, two
//! expiries can fold into one pending exception, and that period is lost.
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

/// SysTick interrupt rate.
const IRQ_HZ: u32 = 1000;
const TICKS_PER_IRQ: u64 = TICK_HZ / IRQ_HZ as u64;
const _: () = assert!(
    TICK_HZ.is_multiple_of(IRQ_HZ as u64),
    "embassy-time's tick rate must be a multiple of the SysTick rate"
);

struct SysTickDriver {
    /// SysTick periods since `init`, counted by the handler.
    periods: Mutex<Cell<u64>>,
    /// Deadline (in ticks) of the earliest queued timer; `u64::MAX` when none.
    next_alarm: Mutex<Cell<u64>>,
    queue: Mutex<RefCell<Queue>>,
}

embassy_time_driver::time_driver_impl!(static DRIVER: SysTickDriver = SysTickDriver {
    periods: Mutex::new(Cell::new(0)),
    next_alarm: Mutex::new(Cell::new(u64::MAX)),
    queue: Mutex::new(RefCell::new(Queue::new())),
});

/// Starts the SysTick interrupt. `hclk_hz` is the core clock (SysTick runs from it).
pub fn init(mut syst: SYST, hclk_hz: u32) {
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
        self.periods.borrow(cs).get() * TICKS_PER_IRQ
    }

    /// Wakes every expired timer and remembers the next deadline.
    fn serve_alarms(&self, cs: CriticalSection) {
        let now = self.now_cs(cs);
        let next = self.queue.borrow_ref_mut(cs).next_expiration(now);
        self.next_alarm.borrow(cs).set(next);
    }

    fn on_tick(&self) {
        critical_section::with(|cs| {
            let periods = self.periods.borrow(cs);
            periods.set(periods.get() + 1);
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
