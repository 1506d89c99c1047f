//! The PPS input: a GNSS receiver's pulse per second, each on-time edge at the instant a
//! timer captured it ([`PpsInput`]), handed to the engine by [`pps_task`]
//! ([`Engine::pps`](bridge_engine::Engine::pps)). On the board TIM2 CH1 captures it
//! (`src/tim2.rs`); the emulated board takes a byte on USART1 for an edge (QEMU models
//! no timer and cannot drive a GPIO input); on the host, the Linux runner's kernel
//! time stamps and the simulated GNSS receiver (`gimbal::sim::gnss`).

use core::future::Future;

use bridge_engine::InstantNs;
use embassy_sync::blocking_mutex::raw::RawMutex;

use crate::engine::BridgeEngine;
use crate::shared::Shared;

/// A source of PPS edges.
pub trait PpsInput {
    /// Waits for the next on-time edge and returns the local instant it was captured at
    /// (the capture register's, not the clock read when the task runs).
    fn edge(&mut self) -> impl Future<Output = InstantNs>;
}

/// No PPS input: waits for ever.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoPps;

impl PpsInput for NoPps {
    async fn edge(&mut self) -> InstantNs {
        core::future::pending().await
    }
}

/// Feeds every edge of `input` to the engine, waking whom the change concerns (the engine
/// task: the planned RTC_IO edge moves with the clock). Not supervised by the watchdog:
/// it waits as long as no pulse comes.
pub async fn pps_task<M: RawMutex, E: BridgeEngine>(
    shared: &Shared<M, E>,
    mut input: impl PpsInput,
) -> ! {
    loop {
        let edge = input.edge().await;
        shared.input(|e| e.pps(edge));
    }
}
