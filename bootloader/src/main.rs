//! The bridge's bootloader: embassy-boot's `prepare` (a pending swap, a resumed swap or
//! revert after a power cut, a rollback of an image that did not confirm itself), then a
//! jump to the active slot. Every address comes from `bridge_update::layout`.
//!
//! It runs on the reset clock (MSI, 4 MHz): the flash needs no wait states there, and the
//! firmware starts from the clocks it expects. No watchdog runs here (a reset stops the
//! independent watchdog, and a swap of the whole slot takes some 20 s): a reset during a
//! swap or a revert resumes it at the next start.
#![no_std]
#![no_main]

use core::cell::RefCell;

use bridge_update::layout::{ACTIVE, BOOT_STATE, DFU, PAGE};
use cortex_m_rt::entry;
use defmt_rtt as _;
use embassy_boot_stm32::{BootLoader, BootLoaderConfig, State};
use embassy_embedded_hal::flash::partition::BlockingPartition;
use embassy_stm32::flash::{Blocking, Flash};
use embassy_sync::blocking_mutex::Mutex;
use embassy_sync::blocking_mutex::raw::NoopRawMutex;
#[cfg(feature = "hw")]
use panic_probe as _;

/// A page: the unit embassy-boot copies with (its buffer).
const BUFFER: usize = PAGE as usize;

#[entry]
fn main() -> ! {
    // The flash controller only: no clock or pin set-up, which the firmware does.
    // SAFETY: nothing else runs; the peripherals are used once, here.
    #[allow(unsafe_code)]
    let p = unsafe { embassy_stm32::Peripherals::steal() };
    let flash: Mutex<NoopRawMutex, RefCell<Flash<'_, Blocking>>> =
        Mutex::new(RefCell::new(Flash::new_blocking(p.FLASH)));
    let config = BootLoaderConfig {
        active: BlockingPartition::new(&flash, ACTIVE.offset(), ACTIVE.size),
        dfu: BlockingPartition::new(&flash, DFU.offset(), DFU.size),
        state: BlockingPartition::new(&flash, BOOT_STATE.offset(), BOOT_STATE.size),
    };
    let loader = BootLoader::prepare::<_, _, _, BUFFER>(config);
    report(&loader.state);
    // SAFETY: the active slot holds a complete image (a swap or a revert is finished
    // before `prepare` returns): its vector table is at its start.
    #[allow(unsafe_code)]
    unsafe {
        loader.load(ACTIVE.start)
    }
}

/// The emulated board's bootloader has no clock. Built beside the firmware's `qemu` flavour
/// (one cargo invocation), it shares its defmt timestamps (embassy-time's uptime), which
/// then read this driver: always 0. It never waits for anything.
#[cfg(feature = "qemu")]
mod no_clock {
    struct NoClock;

    impl embassy_time_driver::Driver for NoClock {
        fn now(&self) -> u64 {
            0
        }

        fn schedule_wake(&self, _at: u64, _waker: &core::task::Waker) {}
    }

    embassy_time_driver::time_driver_impl!(static DRIVER: NoClock = NoClock);
}

fn report(state: &State) {
    let what = match state {
        State::Boot => "boot",
        State::Swap => "swapped in the update (on trial)",
        State::Revert => "rolled back",
        State::DfuDetach => "dfu detach",
    };
    defmt::info!(
        "bootloader: {=str}, active slot at {=u32:#x}",
        what,
        ACTIVE.start
    );
    #[cfg(feature = "qemu")]
    semihosting::println!(
        "bootloader: {}, active slot at {:#010x}",
        what,
        ACTIVE.start
    );
}
