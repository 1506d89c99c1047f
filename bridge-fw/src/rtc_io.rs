//! RTC_IO as the engine task drives it ([`RtcIo`]): a GPIO set when the task's timer alarm
//! fires (any [`OutputPin`]: the host harness, the emulated board), or a timer's output
//! compare that the hardware fires at the planned instant itself (the board: TIM2 CH3,
//! `src/tim2.rs`).

use bridge_engine::{Duration, Instant, Level, PinAction};
use embedded_hal::digital::OutputPin;

use crate::now;

/// The RTC_IO output.
///
/// The engine task calls [`RtcIo::arm`] once an action is within [`RtcIo::lead`] of its
/// instant (the engine keeps a planned edge as it is within its sync lead, 2 ms, so the
/// lead must be shorter), then [`RtcIo::complete`] at or after the instant, and tells the
/// engine the instant it returns ([`Engine::pin_done`](bridge_engine::Engine::pin_done)).
pub trait RtcIo {
    /// How long before an action's instant it must be armed (zero: set at the instant).
    fn lead(&self) -> Duration {
        Duration::ZERO
    }

    /// Prepares `action`: a compare's register and mode, for the hardware to apply at
    /// `action.at` plus `action.sub_us_ns`. Nothing for a pin set at the alarm. Called
    /// again if the plan changed since.
    fn arm(&mut self, action: PinAction) {
        let _ = action;
    }

    /// At or after `action.at`: makes sure the change is made and returns the local
    /// instant it was made (a compare that fired: its planned instant; a pin set now: the
    /// clock read right after), and whether the pin could be set at all.
    fn complete(&mut self, action: PinAction) -> (Instant, bool);
}

/// A GPIO set when the alarm fires: the instant is the clock read right after.
impl<P: OutputPin> RtcIo for P {
    fn complete(&mut self, action: PinAction) -> (Instant, bool) {
        let ok = match action.level {
            Level::High => self.set_high(),
            Level::Low => self.set_low(),
        }
        .is_ok();
        (now(), ok)
    }
}
