//! TIM2, the board's 32-bit timer, at the timer clock (80 MHz, 12.5 ns a tick): the PPS
//! input capture (CH1, PA15) and the RTC_IO output compare (CH3, PA2) on one counter, so
//! that the edge out is placed on the same ticks as the edges in were measured
//! (docs/src/bridge/time.md, "PPS").
//!
//! **Ticks and the engine's clock.** The engine's clock is embassy-time's (TIM15, 1 MHz,
//! from the same 80 MHz as TIM2: the two never drift apart). At start-up both counters
//! are read in one critical section ([`read_tick_clock`]); from then on a TIM2 count maps
//! to the engine's clock in nanoseconds by that pair, and a capture or compare value is
//! extended across the count's 32-bit wrap (every 53.7 s) with the engine's clock: that
//! arithmetic is [`TickClock`]'s, in the library, tested on the host. The pair is read a
//! few cycles apart, so the mapping may be off by up to a microsecond; that offset is the
//! same for every capture and every compare (both are converted by it), so it cancels
//! between a PPS edge in and the RTC_IO edge out, and only the engine's millisecond-scale
//! inputs (serial time stamps) see it.
//!
//! **Capture.** embassy-stm32's [`InputCapture`] (its interrupt wakes the task; the value
//! is the capture register's, latched by the edge itself). **Compare.** The registers
//! of CH3 through the PAC (embassy-stm32's timer drivers own a whole timer each): mode
//! "active on match" for the rising edge, "inactive on match" for the falling one; the
//! pin changes at the compare, whatever the CPU does then. An action armed too late (the
//! counter past it) is forced at once and reported with the clock's instant.

use bridge_engine::{Duration, Instant, InstantNs, Level, PinAction};
use bridge_fw::{PpsInput, RtcIo, TickClock};
use embassy_stm32::pac;
use embassy_stm32::pac::timer::vals::Ocm;
use embassy_stm32::peripherals::TIM2;
use embassy_stm32::timer::Channel;
use embassy_stm32::timer::input_capture::InputCapture;
use embassy_stm32::timer::simple_pwm::PwmPin;

/// How long before an edge the compare is armed: the engine keeps a planned edge as it is
/// within its sync lead (2 ms), and a compare needs only its registers written.
const ARM_LEAD: Duration = Duration::from_millis(1);
/// CH3's index (0-based) in the PAC's per-channel fields, and its CCMR register.
const CH3: usize = 2;

/// Reads TIM2's count and the engine's clock in one critical section. TIM2 must be
/// counting at 80 MHz.
pub fn read_tick_clock() -> TickClock {
    critical_section::with(|_| {
        let ticks0 = pac::TIM2.cnt().read();
        let us0 = embassy_time::Instant::now().as_micros();
        TickClock::from_reading(us0, ticks0)
    })
}

/// The PPS input: TIM2 CH1's capture of the configured edge.
pub struct PpsCapture {
    pub capture: InputCapture<'static, TIM2>,
    pub clock: TickClock,
    /// The on-time edge is the falling one (`[pps] active_low`).
    pub falling: bool,
}

impl PpsInput for PpsCapture {
    async fn edge(&mut self) -> InstantNs {
        let ticks = if self.falling {
            self.capture.wait_for_falling_edge(Channel::Ch1).await
        } else {
            self.capture.wait_for_rising_edge(Channel::Ch1).await
        };
        self.clock
            .instant_of(ticks, embassy_time::Instant::now().as_micros())
    }
}

/// RTC_IO on TIM2 CH3's output compare.
pub struct RtcCompare {
    /// The pin in its timer function (kept: dropping it would give the pin back).
    pub _pin: PwmPin<'static, TIM2, embassy_stm32::timer::Ch3>,
    pub clock: TickClock,
    /// The action the compare is armed for.
    armed: Option<PinAction>,
}

impl RtcCompare {
    /// CH3 as an output, low, its compare frozen (the pin's timer function is set by
    /// `pin`). TIM2 must be counting (the PPS capture starts it).
    pub fn new(pin: PwmPin<'static, TIM2, embassy_stm32::timer::Ch3>, clock: TickClock) -> Self {
        set_mode(Ocm::FORCE_INACTIVE);
        pac::TIM2.ccer().modify(|w| {
            w.set_ccp(CH3, false);
            w.set_cce(CH3, true);
        });
        RtcCompare {
            _pin: pin,
            clock,
            armed: None,
        }
    }
}

/// CH3's output compare mode.
fn set_mode(mode: Ocm) {
    pac::TIM2
        .ccmr_output(CH3 / 2)
        .modify(|w| w.set_ocm(CH3 % 2, mode));
}

impl RtcIo for RtcCompare {
    fn lead(&self) -> Duration {
        ARM_LEAD
    }

    fn arm(&mut self, action: PinAction) {
        let at = InstantNs::from_instant(action.at).saturating_add_ns(u64::from(action.sub_us_ns));
        let target = self.clock.ticks_at(at);
        critical_section::with(|_| {
            pac::TIM2.ccr(CH3).write_value(target);
            // Still ahead of the counter (by more than a microsecond): armed. Else it is
            // forced when the instant comes (`complete`).
            #[allow(clippy::cast_possible_wrap)]
            let ahead = target.wrapping_sub(pac::TIM2.cnt().read()) as i32;
            if ahead > 80 {
                set_mode(match action.level {
                    Level::High => Ocm::ACTIVE_ON_MATCH,
                    Level::Low => Ocm::INACTIVE_ON_MATCH,
                });
                self.armed = Some(action);
            } else {
                self.armed = None;
            }
        });
    }

    fn complete(&mut self, action: PinAction) -> (Instant, bool) {
        if self.armed.take() == Some(action) {
            // The compare made it at its instant (the task is at or after it).
            return (action.at, true);
        }
        set_mode(match action.level {
            Level::High => Ocm::FORCE_ACTIVE,
            Level::Low => Ocm::FORCE_INACTIVE,
        });
        (bridge_fw::now(), true)
    }
}
