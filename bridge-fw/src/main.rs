//! Bridge firmware for the STM32L475VG (B-L475E-IOT01A).
//!
//! Placeholder until the bridge issue lands: it brings the chip up with Embassy, logs
//! over defmt/RTT and blinks LED2 (PB14) at 1 Hz, proving that the toolchain, memory map,
//! linker scripts and protocol-core build for the target.
#![no_std]
#![no_main]

use embassy_executor::Spawner;
use embassy_stm32::gpio::{Level, Output, Speed};
use embassy_time::Timer;
use {defmt_rtt as _, panic_probe as _};

#[embassy_executor::main]
async fn main(_spawner: Spawner) {
    let p = embassy_stm32::init(Default::default());
    let mut led = Output::new(p.PB14, Level::Low, Speed::Low);
    defmt::info!(
        "bridge-fw placeholder; K40T codec knows {} message ids",
        protocol_core::k40t::CATALOG.len()
    );
    loop {
        led.toggle();
        Timer::after_millis(500).await;
    }
}
