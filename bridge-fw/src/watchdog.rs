//! Watchdog feed: only while every supervised loop makes progress.

use embassy_sync::blocking_mutex::raw::RawMutex;
use embassy_time::{Duration, Ticker};

use crate::engine::BridgeEngine;
use crate::now;
use crate::shared::LogKind;
use crate::shared::{Heartbeat, Shared};

/// Every `period`, feeds the watchdog (`feed`) if every loop of `supervised` (the
/// engine task and the four link loops, FC and pod, reader and writer: [`Heartbeat::ALL`];
/// with a telemetry link also its two: [`Heartbeat::supervised`]) has marked its
/// heartbeat since the last check; else logs which did not ([`LogKind::Stalled`]) and
/// does not feed.
///
/// Each loop marks its heartbeat at least every [`Timing::heartbeat`](crate::Timing::heartbeat)
/// (100 ms) while healthy, so `period` must be longer than that (the firmware uses
/// 250 ms) and the watchdog's time-out longer than two periods (the firmware's: 750 ms;
/// a stall then resets the MCU within 0.75 to 1 s of the last feed, at most 1 s).
pub async fn watchdog_task<M: RawMutex, E: BridgeEngine, F: FnMut()>(
    shared: &Shared<M, E>,
    period: Duration,
    supervised: Heartbeat,
    mut feed: F,
) -> ! {
    let mut ticker = Ticker::every(period);
    loop {
        ticker.next().await;
        let alive = shared.take_alive();
        if alive.contains(supervised) {
            feed();
        } else {
            shared.record(now(), LogKind::Stalled(Heartbeat(supervised.0 & !alive.0)));
        }
    }
}
