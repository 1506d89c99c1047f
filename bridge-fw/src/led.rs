//! The status LED: FC link, pod link and UTC as one blink pattern.

use embassy_sync::blocking_mutex::raw::RawMutex;
use embassy_time::{Duration, Timer};
use embedded_hal::digital::OutputPin;

use crate::engine::{BridgeEngine, Status};
use crate::shared::Shared;

/// One step of a blink pattern: the LED on or off for a while.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Blink {
    /// LED on.
    pub on: bool,
    /// For how long, ms.
    pub ms: u16,
}

const fn b(on: bool, ms: u16) -> Blink {
    Blink { on, ms }
}

/// The pattern for `status`, repeated every 2 s: three slots of 400 ms for the FC link,
/// the pod link and UTC, in that order, each a long flash (300 ms) when up and a short
/// one (40 ms) when down, then 800 ms dark. Three long flashes: all is well; three
/// short ones: nothing connected yet.
#[must_use]
pub fn led_pattern(status: Status) -> [Blink; 7] {
    let slot = |up: bool| {
        if up {
            (b(true, 300), b(false, 100))
        } else {
            (b(true, 40), b(false, 360))
        }
    };
    let (fc_on, fc_off) = slot(status.fc_link);
    let (pod_on, pod_off) = slot(status.pod_link);
    let (utc_on, utc_off) = slot(status.utc);
    [
        fc_on,
        fc_off,
        pod_on,
        pod_off,
        utc_on,
        utc_off,
        b(false, 800),
    ]
}

/// Shows the engine's [`Status`] on `led` forever ([`led_pattern`]). Pin errors are
/// ignored: the LED is a courtesy.
pub async fn led_task<M: RawMutex, E: BridgeEngine, P: OutputPin>(
    shared: &Shared<M, E>,
    mut led: P,
) -> ! {
    loop {
        let status = shared.with_state(|s| s.engine.status());
        for step in led_pattern(status) {
            let _ = if step.on {
                led.set_high()
            } else {
                led.set_low()
            };
            Timer::after(Duration::from_millis(u64::from(step.ms))).await;
        }
    }
}
