//! The console's port: bytes between a serial port (the ST-LINK virtual COM port on the
//! board) and the engine's sans-IO console ([`Engine::console_receive`],
//! [`Engine::console_transmit`]; docs/src/console.md). The engine parses and answers;
//! this task only moves the bytes, hands the port to the update protocol when the engine
//! says so ([`ConsoleAction::Update`]), and returns when a restart is due
//! ([`ConsoleAction::Reboot`], or the update client's reset), once the store has written
//! what waits.
//!
//! [`Engine::console_receive`]: bridge_engine::Engine::console_receive
//! [`Engine::console_transmit`]: bridge_engine::Engine::console_transmit

use core::sync::atomic::Ordering;

use bridge_engine::ConsoleAction;
use bridge_update::{Receiver, Slot};
use embassy_futures::select::{Either3, select3};
use embassy_sync::blocking_mutex::raw::RawMutex;
use embassy_time::{Duration, Timer};
use embedded_io_async::{Read, Write};

use crate::engine::BridgeEngine;
use crate::now;
use crate::shared::Shared;
use crate::update::{TRIAL_CHECK, UpdatePort, check_trial, start_trial};

/// How long a restart waits, at most, for the store to write what waits (a record is a
/// few flash words: milliseconds; a page erase about 22 ms).
const STORE_WAIT: Duration = Duration::from_secs(2);

/// Serves the console on `rx`/`tx` (and the update protocol when it hands the port over,
/// confirming an image on trial as [`update_task`](crate::update_task) does); returns
/// when the bridge is to restart (the caller resets once the last answer has left).
pub async fn console_task<M: RawMutex, E: BridgeEngine, R: Read, W: Write, S: Slot>(
    shared: &Shared<M, E>,
    rx: &mut R,
    tx: &mut W,
    slot: &mut S,
    receiver: &mut Receiver<'_>,
) {
    let mut trial = start_trial(shared, slot);
    let mut buf = [0u8; 64];
    loop {
        let end = console(shared, rx, tx, &mut buf, || {
            check_trial(shared, slot, &mut trial);
        })
        .await;
        let first = match end {
            ConsoleEnd::Restart => return,
            ConsoleEnd::Update(first) => first,
        };
        let mut port = UpdatePort {
            rx: &mut *rx,
            tx: &mut *tx,
            slot: &mut *slot,
            receiver: &mut *receiver,
        };
        let idle = Duration::from_micros(bridge_engine::UPDATE_IDLE.as_micros());
        if port.serve(shared, first, Some(idle), &mut trial).await {
            store_written(shared).await;
            return;
        }
        shared.input(BridgeEngine::console_resume);
    }
}

/// Why [`console`] returned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConsoleEnd<'a> {
    /// The bridge is to restart (`reboot`); the store has written what waited.
    Restart,
    /// The port is the update protocol's, these bytes its first.
    Update(&'a [u8]),
}

/// The console on `rx`/`tx` until it hands the port to the update protocol or asks for a
/// restart (once the store has written what waits); `tick` runs every second (the image
/// trial's check). `buf` holds the bytes read (an update's first ones when it returns).
pub async fn console<'b, M: RawMutex, E: BridgeEngine, R: Read, W: Write>(
    shared: &Shared<M, E>,
    rx: &mut R,
    tx: &mut W,
    buf: &'b mut [u8; 64],
    mut tick: impl FnMut(),
) -> ConsoleEnd<'b> {
    loop {
        drain(shared, tx).await;
        let read = match select3(
            rx.read(buf),
            shared.wake_console.wait(),
            Timer::after(TRIAL_CHECK),
        )
        .await
        {
            Either3::First(Ok(n)) => n,
            Either3::First(Err(_)) | Either3::Second(()) => continue,
            Either3::Third(()) => {
                tick();
                continue;
            }
        };
        let bytes = buf.get(..read).unwrap_or_default();
        let action = shared.console_input(|e| e.console_receive(now(), bytes));
        drain(shared, tx).await;
        match action {
            None => {}
            Some(ConsoleAction::Reboot) => {
                store_written(shared).await;
                return ConsoleEnd::Restart;
            }
            Some(ConsoleAction::Update { at }) => {
                let bytes = buf.get(..read).unwrap_or_default();
                return ConsoleEnd::Update(bytes.get(at..).unwrap_or_default());
            }
        }
    }
}

/// Writes what the console has to say, a piece at a time, until it has nothing more.
async fn drain<M: RawMutex, E: BridgeEngine, W: Write>(shared: &Shared<M, E>, tx: &mut W) {
    let mut out = [0u8; 64];
    loop {
        let n = shared.with(|e| e.console_transmit(&mut out));
        let Some(bytes) = out.get(..n).filter(|b| !b.is_empty()) else {
            break;
        };
        if tx.write_all(bytes).await.is_err() {
            break;
        }
    }
    let _ = tx.flush().await;
}

/// Waits (at most [`STORE_WAIT`]) until the store has written every record that waits.
async fn store_written<M: RawMutex, E: BridgeEngine>(shared: &Shared<M, E>) {
    let start = embassy_time::Instant::now();
    while (shared.with(|e| e.records_due()) || shared.store_busy.load(Ordering::Acquire))
        && start.elapsed() < STORE_WAIT
    {
        Timer::after_millis(5).await;
    }
}
