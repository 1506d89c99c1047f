//! The status LED (LED2): one table of codes ([`LED_CODES`]), each a blink pattern an
//! integrator tells apart by eye, documented as the same table in the book
//! (docs/src/firmware/wiring.md#led2; a test compares the two).
//!
//! What it shows, in order:
//! 1. **Boot**: on from reset (the board turns it on first thing) until the tasks run,
//!    then 1 s more, then 1 s dark.
//! 2. **The FC side selected**, once: 1 to 5 flashes (SIYI, Viewlink, GCU, K40T,
//!    MAVLink), then 1 s dark. Or, when the straps select a side this image does not
//!    have, the **strap error** code forever: no FC side runs.
//! 3. **The status cycle**, forever: three flashes, the FC link, the pod link and UTC,
//!    each long when up and short when down (UTC: a double flash when a PPS input
//!    disciplines it), 800 ms dark; then each fault raised since boot ([`Faults`]: a
//!    watchdog reset, a store reset), each its code and 800 ms dark.

use core::sync::atomic::{AtomicU8, Ordering};

use bridge_engine::FcProtocol;
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

const fn on(ms: u16) -> Blink {
    Blink { on: true, ms }
}

const fn off(ms: u16) -> Blink {
    Blink { on: false, ms }
}

/// How often a code's group is shown.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Times {
    /// This many times, then [`LedCode::then`].
    N(u8),
    /// Forever (nothing follows).
    Forever,
}

/// One code of the LED: its group of steps, repeated, then a tail.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LedCode {
    /// Its name (the book's first column).
    pub name: &'static str,
    /// When it shows.
    pub when: &'static str,
    /// The group of steps.
    pub group: &'static [Blink],
    /// How often the group is shown.
    pub times: Times,
    /// What follows the groups.
    pub then: &'static [Blink],
}

impl LedCode {
    const fn once(name: &'static str, when: &'static str, group: &'static [Blink]) -> Self {
        LedCode {
            name,
            when,
            group,
            times: Times::N(1),
            then: &[],
        }
    }

    /// Every step, in order (a [`Times::Forever`] code: its group once).
    pub fn steps(&self) -> impl Iterator<Item = Blink> + '_ {
        let n = match self.times {
            Times::N(n) => usize::from(n),
            Times::Forever => 1,
        };
        core::iter::repeat_n(self.group, n)
            .flatten()
            .chain(self.then)
            .copied()
    }

    /// The pattern as the book writes it: `on 300 ms, off 100 ms`, `3 × (on 200 ms, off
    /// 300 ms), off 1000 ms` (a group with a tail always in parentheses), `(on 100 ms,
    /// off 100 ms) forever`.
    pub fn describe(&self, out: &mut impl core::fmt::Write) -> core::fmt::Result {
        let list = |out: &mut dyn core::fmt::Write, steps: &[Blink]| -> core::fmt::Result {
            for (i, s) in steps.iter().enumerate() {
                let sep = if i == 0 { "" } else { ", " };
                let what = if s.on { "on" } else { "off" };
                write!(out, "{sep}{what} {} ms", s.ms)?;
            }
            Ok(())
        };
        match self.times {
            Times::N(1) if self.then.is_empty() => list(out, self.group)?,
            Times::N(n) => {
                write!(out, "{n} × (")?;
                list(out, self.group)?;
                out.write_str(")")?;
            }
            Times::Forever => {
                out.write_str("(")?;
                list(out, self.group)?;
                out.write_str(") forever")?;
            }
        }
        if !self.then.is_empty() {
            out.write_str(", ")?;
            list(out, self.then)?;
        }
        Ok(())
    }
}

/// A flash of the status cycle: up.
const LONG: &[Blink] = &[on(300), off(100)];
/// Down.
const SHORT: &[Blink] = &[on(40), off(360)];
/// The FC side's flash.
const SIDE_FLASH: &[Blink] = &[on(200), off(300)];
/// After the side's flashes.
const SIDE_END: &[Blink] = &[off(1000)];

const fn side(name: &'static str, n: u8) -> LedCode {
    LedCode {
        name,
        when: "once after boot: the FC side selected (build or straps)",
        group: SIDE_FLASH,
        times: Times::N(n),
        then: SIDE_END,
    }
}

/// From reset, then 1 s more.
pub const BOOT: LedCode = LedCode::once(
    "boot",
    "from reset until the tasks run (on throughout: a board stuck starting up), then 1 s more and 1 s dark",
    &[on(1000), off(1000)],
);
/// The straps select a side this image does not have.
pub const STRAP_ERROR: LedCode = LedCode {
    name: "strap error",
    when: "instead of the side: the straps select a side this image does not have; no FC side runs",
    group: &[on(100), off(100)],
    times: Times::Forever,
    then: &[],
};
const SIYI: LedCode = side("SIYI", 1);
const VIEWLINK: LedCode = side("Viewlink", 2);
const GCU: LedCode = side("GCU", 3);
const K40T: LedCode = side("K40T", 4);
const MAVLINK: LedCode = side("MAVLink", 5);
const FC_UP: LedCode = LedCode::once("FC link up", "status cycle, 1st flash", LONG);
const FC_DOWN: LedCode = LedCode::once("FC link down", "status cycle, 1st flash", SHORT);
const POD_UP: LedCode = LedCode::once("pod link up", "status cycle, 2nd flash", LONG);
const POD_DOWN: LedCode = LedCode::once("pod link down", "status cycle, 2nd flash", SHORT);
const UTC: LedCode = LedCode::once(
    "UTC",
    "status cycle, 3rd flash: UTC known, time syncs sent",
    LONG,
);
const UTC_PPS: LedCode = LedCode::once(
    "UTC, PPS lock",
    "status cycle, 3rd flash: UTC known and disciplined by the PPS input",
    &[on(100), off(100), on(100), off(100)],
);
const NO_UTC: LedCode = LedCode::once("no UTC", "status cycle, 3rd flash", SHORT);
const WATCHDOG_RESET: LedCode = LedCode {
    name: "watchdog reset",
    when: "after the status flashes, until the next reset: the last reset was the watchdog's",
    group: &[on(50), off(50)],
    times: Times::N(6),
    then: &[off(800)],
};
const STORE_RESET: LedCode = LedCode::once(
    "store reset",
    "after the status flashes, until the next reset: the settings store was blank or corrupt \
     and the defaults were loaded",
    &[on(1200), off(800)],
);

/// Every code of the LED, in the book's order.
pub const LED_CODES: [&LedCode; 16] = [
    &BOOT,
    &SIYI,
    &VIEWLINK,
    &GCU,
    &K40T,
    &MAVLINK,
    &STRAP_ERROR,
    &FC_UP,
    &FC_DOWN,
    &POD_UP,
    &POD_DOWN,
    &UTC,
    &UTC_PPS,
    &NO_UTC,
    &WATCHDOG_RESET,
    &STORE_RESET,
];

/// The dark gap after the status flashes.
const GAP: &[Blink] = &[off(800)];

/// The code of the FC side selected.
#[must_use]
pub const fn side_code(fc: FcProtocol) -> &'static LedCode {
    match fc {
        FcProtocol::Siyi => &SIYI,
        FcProtocol::Viewlink => &VIEWLINK,
        FcProtocol::Gcu => &GCU,
        FcProtocol::K40t => &K40T,
        FcProtocol::Mavlink => &MAVLINK,
    }
}

/// Faults the LED shows after the status flashes until the next reset, raised by
/// whoever finds them ([`Faults::raise`]).
#[derive(Debug, Default)]
pub struct Faults(AtomicU8);

/// A fault the LED shows ([`Faults`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Fault {
    /// The last reset was the independent watchdog's (the board reads RCC_CSR at boot).
    WatchdogReset,
    /// The settings store was found blank or corrupt at boot and the defaults were
    /// loaded (raised by the store's owner).
    StoreReset,
}

impl Fault {
    const fn bit(self) -> u8 {
        match self {
            Fault::WatchdogReset => 1,
            Fault::StoreReset => 2,
        }
    }

    /// Its LED code.
    #[must_use]
    pub const fn code(self) -> &'static LedCode {
        match self {
            Fault::WatchdogReset => &WATCHDOG_RESET,
            Fault::StoreReset => &STORE_RESET,
        }
    }
}

impl Faults {
    /// None raised.
    #[must_use]
    pub const fn new() -> Self {
        Faults(AtomicU8::new(0))
    }

    /// Shows `fault` from the next status cycle on.
    pub fn raise(&self, fault: Fault) {
        self.0.fetch_or(fault.bit(), Ordering::Relaxed);
    }

    /// `fault` was raised.
    #[must_use]
    pub fn contains(&self, fault: Fault) -> bool {
        self.0.load(Ordering::Relaxed) & fault.bit() != 0
    }
}

/// The codes of one status cycle: the three flashes for `status`, then the codes of the
/// faults raised (`watchdog`, `store`).
#[must_use]
pub fn status_codes(status: Status, watchdog: bool, store: bool) -> [Option<&'static LedCode>; 5] {
    let pick = |up: bool, yes, no| if up { yes } else { no };
    let utc = match (status.utc, status.pps_locked) {
        (true, true) => &UTC_PPS,
        (true, false) => &UTC,
        (false, _) => &NO_UTC,
    };
    [
        Some(pick(status.fc_link, &FC_UP, &FC_DOWN)),
        Some(pick(status.pod_link, &POD_UP, &POD_DOWN)),
        Some(utc),
        watchdog.then_some(Fault::WatchdogReset.code()),
        store.then_some(Fault::StoreReset.code()),
    ]
}

/// Shows `steps` on `led`. Pin errors are ignored: the LED is a courtesy.
async fn play<P: OutputPin>(led: &mut P, steps: impl Iterator<Item = Blink>) {
    for step in steps {
        let _ = if step.on {
            led.set_high()
        } else {
            led.set_low()
        };
        Timer::after(Duration::from_millis(u64::from(step.ms))).await;
    }
}

/// The boot code, the side's code once, then the status cycle of the engine's
/// [`Status`] and the `faults` raised, forever.
pub async fn led_task<M: RawMutex, E: BridgeEngine, P: OutputPin>(
    shared: &Shared<M, E>,
    faults: &Faults,
    fc: FcProtocol,
    mut led: P,
) -> ! {
    play(&mut led, BOOT.steps()).await;
    play(&mut led, side_code(fc).steps()).await;
    loop {
        let status = shared.with_state(|s| s.engine.status());
        let codes = status_codes(
            status,
            faults.contains(Fault::WatchdogReset),
            faults.contains(Fault::StoreReset),
        );
        let [fc_link, pod_link, utc, faults @ ..] = codes;
        for c in [fc_link, pod_link, utc].into_iter().flatten() {
            play(&mut led, c.steps()).await;
        }
        play(&mut led, GAP.iter().copied()).await;
        for c in faults.into_iter().flatten() {
            play(&mut led, c.steps()).await;
        }
    }
}

/// The boot code, then the strap error code forever (no engine runs).
pub async fn strap_error_led<P: OutputPin>(mut led: P) -> ! {
    play(&mut led, BOOT.steps()).await;
    loop {
        play(&mut led, STRAP_ERROR.steps()).await;
    }
}
