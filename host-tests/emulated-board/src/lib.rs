//! The emulated-board driver: the real firmware binary on QEMU's `b-l475e-iot01a` between
//! the simulated peers, on wall-clock time (the `qemu-e2e` binary; `scripts/qemu-e2e`;
//! docs/src/firmware/emulated-board.md).
//!
//! One [`run`] starts `qemu-system-arm` with the `qemu` flavour of bridge-fw (built with every
//! FC side), the FC side chosen through the strap levels on the semihosting command line
//! (`straps=AB` or `straps=ABC`, see `bridge-fw/src/board.rs`), UART4 (FC) and USART2
//! (pod) on Unix-socket chardevs and QEMU's `stm32l4x5_gpio_write` trace in a file. Two threads per socket move
//! the bytes between the socket and the host pipes of `bridge_fw::host`; one executor on
//! real time runs the simulated FC driver and the simulated pod (`sim::peer::run_peer`)
//! and a script that drives the FC and checks, in order: the firmware boots as that side,
//! the FC simulator reaches healthy, a command reaches the pod with the right fields,
//! telemetry from the pod comes back to the FC simulator, [`SYNCS`] times an RTC_IO High
//! edge (GPIOA pin 2 in the trace) precedes a valid 0x00030E on the pod socket that
//! carries the FC's UTC at the edge within 30 ms, the bytes on both links were all valid
//! and QEMU still runs.
//!
//! The SIYI scenario also wires the telemetry link (LPUART1, the sixth `-serial`) to the
//! same autopilot's MAVLink 2 port (`ApMavlink`, no MAVLink mount or camera, the SIYI
//! simulator's clock): the firmware's HEARTBEAT (component 158) and TIMESYNC requests
//! must reach it and the firmware must take its time from it (its semihosting line
//! `time source telemetry`), so the time syncs checked are then the telemetry link's.
//!
//! RTC_IO reaches the simulated pod from the trace file: the file is read every few
//! milliseconds, and always just before bytes from the pod socket are handed to the pod.
//! QEMU writes (and flushes) the trace line while the guest stores to BSRR, before the
//! guest goes on to write the 0x00030E to the USART, so an edge is always delivered
//! before the frame that follows it. QEMU stamps each trace line with the wall clock
//! (`-msg timestamp=on`): that stamp, not the moment the watch read the line, is the
//! edge's instant the time check compares against.
//!
//! Emulated time runs slower than wall time when the host is busy: every wait is a
//! generous time-out, and no check is on a duration (the durations are reported). The
//! one check on time is the product's: no 0x00030E more than 30 ms off the FC's UTC.
//!
//! The parts: [`qemu`] starts QEMU and moves the bytes between its sockets and the host
//! pipes, [`trace`] reads RTC_IO and the LED from its GPIO trace, [`script`] runs the
//! simulators and checks the scenario, [`report`] holds what a run found.

pub mod qemu;
pub mod report;
pub mod script;
pub mod trace;

use std::path::PathBuf;
use std::time::Duration as StdDuration;

use gimbal::sim::ap_mavlink::ApMavlink;
use gimbal::sim::ap_siyi::ApSiyi;
use gimbal::sim::ap_viewpro::ApViewpro;
use gimbal::sim::ap_xfrobot::ApXfRobot;
use gimbal::sim::fc_k40t::FcK40t;

pub use report::{Check, Outcome};

/// Both links' baud rate (bridge.toml's `fc_baud` and `pod_baud`; QEMU's chardevs ignore it,
/// the simulators pace their output with it).
pub const BAUD: u32 = 115_200;

/// An FC side of the bridge.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// SIYI (ArduPilot `AP_Mount_Siyi`).
    Siyi,
    /// Viewlink (ArduPilot `AP_Mount_Viewpro`).
    Viewlink,
    /// XF Robot GCU (ArduPilot `AP_Mount_XFRobot`).
    Gcu,
    /// K40T spoken by the FC itself.
    K40t,
    /// MAVLink (ArduPilot `AP_Mount_MAVLink` + `AP_Camera_MAVLinkCamV2`).
    Mavlink,
}

impl Side {
    /// Every side, in the order the scenarios run.
    pub const ALL: [Side; 5] = [
        Side::Siyi,
        Side::Viewlink,
        Side::Gcu,
        Side::K40t,
        Side::Mavlink,
    ];

    /// The name the firmware prints and `bridge.toml` uses.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Side::Siyi => "siyi",
            Side::Viewlink => "viewlink",
            Side::Gcu => "gcu",
            Side::K40t => "k40t",
            Side::Mavlink => "mavlink",
        }
    }

    /// The side named `name`.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Side> {
        Side::ALL.into_iter().find(|s| s.name() == name)
    }

    /// The scenario also runs the MAVLink telemetry link (the SIYI side: one autopilot on
    /// its SIYI port and its MAVLink port).
    #[must_use]
    pub fn telemetry(self) -> bool {
        self == Side::Siyi
    }

    /// The scenario also feeds the PPS test source (a byte on USART1, QEMU's first
    /// `-serial`, at each whole second of the FC's UTC; the firmware takes it for an edge):
    /// the GCU side, whose own time is the coarsest.
    #[must_use]
    pub fn pps(self) -> bool {
        self == Side::Gcu
    }

    /// Checks of a complete scenario of this side.
    #[must_use]
    pub fn checks(self) -> usize {
        CHECKS + usize::from(self.telemetry()) + usize::from(self.pps())
    }

    /// The strap levels that select this side (A, B, then C when grounded; `0` grounded,
    /// `1` open: the firmware's `config::from_straps`).
    #[must_use]
    pub fn straps(self) -> &'static str {
        match self {
            Side::Siyi => "11",
            Side::Viewlink => "01",
            Side::Gcu => "10",
            Side::K40t => "00",
            Side::Mavlink => "110",
        }
    }
}

/// What a run needs.
#[derive(Debug, Clone)]
pub struct Options {
    /// The QEMU executable.
    pub qemu: PathBuf,
    /// The firmware (`qemu` flavour, every FC side) as an Intel HEX file of its flash
    /// contents (at the active slot): QEMU loads it there.
    pub image: PathBuf,
    /// The bootloader (`qemu` flavour): QEMU starts it, it jumps to the firmware.
    pub bootloader: PathBuf,
    /// The whole scenario's time-out (wall clock).
    pub timeout: StdDuration,
    /// Where the run's files go (sockets, trace, QEMU output); created.
    pub work: PathBuf,
}

/// Time syncs each scenario checks (one every 10 s from the first).
pub const SYNCS: usize = 3;

/// How many checks a complete scenario has (one more with the telemetry link,
/// [`Side::telemetry`], and one more with the PPS source, [`Side::pps`]).
pub const CHECKS: usize = 7;

/// Runs the scenario of `side`. Never panics on what QEMU or the firmware do: every
/// failure is a failed check.
#[must_use]
pub fn run(side: Side, options: &Options) -> Outcome {
    match side {
        Side::Siyi => qemu::run_with::<ApSiyi>(side, options),
        Side::Viewlink => qemu::run_with::<ApViewpro>(side, options),
        Side::Gcu => qemu::run_with::<ApXfRobot>(side, options),
        Side::K40t => qemu::run_with::<FcK40t>(side, options),
        Side::Mavlink => qemu::run_with::<ApMavlink>(side, options),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_sides_straps_select_it_in_the_firmware() {
        use bridge_engine::FcProtocol;
        for (side, protocol) in Side::ALL.into_iter().zip([
            FcProtocol::Siyi,
            FcProtocol::Viewlink,
            FcProtocol::Gcu,
            FcProtocol::K40t,
            FcProtocol::Mavlink,
        ]) {
            let grounded: Vec<bool> = side.straps().chars().map(|c| c == '0').collect();
            let c = grounded.get(2).copied().unwrap_or(false);
            assert_eq!(
                bridge_fw::config::from_straps(grounded[0], grounded[1], c),
                Ok(protocol),
                "{side:?}"
            );
            assert_eq!(Side::from_name(side.name()), Some(side));
        }
        assert_eq!(Side::from_name("px4"), None);
    }
}
