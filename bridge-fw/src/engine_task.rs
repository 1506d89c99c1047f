//! The engine/timer task: `poll` when the engine asks, RTC_IO at the instants it names.

use bridge_engine::{Changes, Instant, Level, PinAction};
use embassy_futures::select::select;
use embassy_sync::blocking_mutex::raw::RawMutex;
use embassy_time::Timer;

use crate::engine::BridgeEngine;
use crate::rtc_io::RtcIo;
use crate::shared::LogKind;
use crate::shared::{Heartbeat, Shared};
use crate::{now, to_embassy};

/// Drives the engine's clock and the RTC_IO pin forever.
///
/// Each turn: [`poll`](bridge_engine::Engine::poll) if
/// [`poll_at`](bridge_engine::Engine::poll_at) is due (waking the writers and the
/// log task its changes concern), then sleep until the earliest of the next poll, the
/// next pin change ([`pin`](bridge_engine::Engine::pin)),
/// [`Timing::heartbeat`](crate::Timing::heartbeat), or an input that changed the pin plan
/// or wants a poll sooner ([`Shared::input`](crate::Shared::input)). An action within
/// the pin's [`lead`](RtcIo::lead) is armed ([`RtcIo::arm`]: a timer's output compare).
/// When the pin's instant comes (a timer alarm), in one critical section with nothing
/// that can wait in between: the change is completed ([`RtcIo::complete`]: the
/// compare's instant, or the pin set and the clock read) and
/// [`pin_done`](bridge_engine::Engine::pin_done) told that instant (for a rising
/// edge the engine puts the 0x00030E at the head of the pod queue); then the pod writer
/// is woken.
///
/// A `poll_at` that is not later than the poll just made (the engine keeps naming the
/// sync lead while a settled edge approaches) waits for the edge or for input instead of
/// spinning.
pub async fn engine_task<M: RawMutex, E: BridgeEngine, P: RtcIo>(
    shared: &Shared<M, E>,
    mut pin: P,
) -> ! {
    let heartbeat = shared.timing().heartbeat;
    let lead = pin.lead();
    // The action last armed.
    let mut armed: Option<PinAction> = None;
    loop {
        let start = now();
        let (action, wake, changes) = shared.with_state(|s| {
            let changes = if s.engine.poll_at().is_some_and(|t| t <= start) {
                s.engine.poll(start)
            } else {
                Changes::NONE
            };
            let action = s.engine.pin();
            let mut wake = start.saturating_add(heartbeat);
            if let Some(t) = s.engine.poll_at().filter(|&t| t > start) {
                wake = wake.min(t);
            }
            if let Some(a) = action {
                let arm_at = a.at.saturating_sub(lead);
                wake = wake.min(if armed != Some(a) && arm_at > start {
                    arm_at
                } else {
                    a.at
                });
            }
            // Set under the lock with what it derives from: an input after it that wants
            // a poll sooner wakes this task (`Shared::input`).
            s.engine_wakes_at = wake;
            (action, wake, changes)
        });
        shared.wake(changes);
        shared.alive(Heartbeat::ENGINE);

        if let Some(a) = action
            && armed != Some(a)
            && a.at.saturating_sub(lead) <= start
        {
            pin.arm(a);
            armed = Some(a);
        }
        if action.is_some_and(|a| a.at <= start) {
            fire(shared, &mut pin);
            armed = None;
            continue;
        }
        select(Timer::at(to_embassy(wake)), shared.wake_engine.wait()).await;
        if action.is_some_and(|a| a.at <= now()) {
            fire(shared, &mut pin);
            armed = None;
        }
    }
}

/// Completes the engine's pin action if it is due, and `pin_done` with its instant, under
/// the lock; then wakes whom the change concerns (the pod writer: the 0x00030E at the
/// head of its queue after a rising edge).
fn fire<M: RawMutex, E: BridgeEngine, P: RtcIo>(shared: &Shared<M, E>, pin: &mut P) {
    let done: Option<(Level, Instant, bool, Changes)> = shared.with_state(|s| {
        let a = s.engine.pin().filter(|a| a.at <= now())?;
        let (at, ok) = pin.complete(a);
        // The engine has no "edge failed": a pin that cannot be set (none of the
        // supported ones can fail) is reported as set, and logged below.
        let changes = s.engine.pin_done(a.level, at);
        if a.level == Level::High {
            s.edge = Some(at);
        }
        Some((a.level, at, ok, changes))
    });
    let Some((level, at, ok, changes)) = done else {
        return;
    };
    shared.wake(changes);
    if !ok {
        shared.record(at, LogKind::PinError(level));
    }
    shared.record(at, LogKind::Pin(level));
}
