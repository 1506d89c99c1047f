//! The thread-mode executor of the emulated board (`qemu` feature): embassy's, idling with
//! WFI instead of WFE.
//!
//! QEMU implements WFE as a no-op on M-profile cores, so embassy's thread executor (poll,
//! WFE, poll, ...) keeps a host core busy all the time; with four emulated boards side
//! by side on a 2-core machine they starved each other. WFI halts QEMU's CPU until an
//! interrupt. A task woken by an interrupt between the end of a poll and the WFI waits
//! for the next interrupt: SysTick comes every 100 µs (`systick_driver`), so that is the
//! worst added latency. On silicon WFE is the right choice (it also wakes on SEV from a
//! task woken in thread mode), which is why the hardware build keeps embassy's executor.
//!
//! `unsafe`: `raw::Executor::poll` is unsafe because it must not be called reentrantly;
//! only this loop calls it.

use embassy_executor::{Spawner, raw};
use static_cell::StaticCell;

/// embassy's thread-mode pender context (its `__pender` answers it with SEV, harmless here).
const THREAD_PENDER: usize = usize::MAX;

/// Runs `init` with a spawner, then the tasks, forever.
pub fn run(init: impl FnOnce(Spawner)) -> ! {
    static EXECUTOR: StaticCell<raw::Executor> = StaticCell::new();
    let executor: &'static raw::Executor =
        EXECUTOR.init(raw::Executor::new(THREAD_PENDER as *mut ()));
    init(executor.spawner());
    loop {
        // SAFETY: not reentrant: this loop is the only caller, in thread mode.
        unsafe { executor.poll() };
        cortex_m::asm::wfi();
    }
}
