//! The PPS input of the Linux bridge (`--pps`): a GNSS module's pulse per second, each
//! edge at the instant the kernel time-stamped it, mapped to the runner's clock:
//!
//! - `gpiochipN:LINE[:active-low]`: a GPIO line's edge events (kernel character device,
//!   crate `gpiocdev`), time-stamped by the kernel in its interrupt handler;
//! - `/dev/ppsN`: the kernel's PPS interface (RFC 2783, `PPS_FETCH`; crate `pps-time`),
//!   the assert edge as the PPS driver (pps-gpio, pps-ldisc) stamped it;
//! - `tcp:HOST:PORT`, `tcp-listen:[HOST:]PORT`: a test source for emulators, one byte an
//!   edge, stamped when it arrives;
//! - `sim`: the simulated GNSS module (`gimbal::sim::gnss`) on the runner's clock, its UTC
//!   the host's (that of `--fc-port sim`).
//!
//! Both kernel sources stamp in CLOCK_REALTIME here (a `/dev/ppsN` can do nothing else);
//! each stamp is mapped to the runner's clock (CLOCK_MONOTONIC since its start) by a
//! pair of readings of both clocks taken when the edge is read, so that a step or slew of
//! the system time between edges does not move them. The kernel's stamp is within a few
//! microseconds of the edge (its interrupt latency); RTC_IO on Linux is a GPIO set by a
//! thread at the alarm, tens of microseconds late: see docs/src/linux-bridge.md.

use std::fmt;
use std::path::PathBuf;
use std::str::FromStr;
use std::time::{Duration as StdDuration, SystemTime, UNIX_EPOCH};

use bridge_engine::InstantNs;
use bridge_fw::PpsInput;
use bridge_fw::host::{self, HostPipe};
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_sync::channel::Channel;
use serde_json::json;

use super::event_name::EventName;
use super::output::Output;
use super::pin::GpioSpec;
use super::port::PortSpec;
use crate::sim::gnss::{Crystal, GnssPps, GnssPpsConfig};
use crate::sim::pps_io::{CapturedPps, PpsWiring};

/// Where PPS edges come from (`--pps`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PpsSpec {
    /// A GPIO line's edge events (active low: the module's on-time edge is the falling
    /// one).
    Gpio(GpioSpec),
    /// A kernel PPS device (`/dev/ppsN`).
    Device(PathBuf),
    /// One byte an edge over TCP, stamped on arrival (`tcp:` or `tcp-listen:`).
    Tcp(PortSpec),
    /// The simulated GNSS module.
    Sim,
}

impl FromStr for PpsSpec {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || {
            format!(
                "`{s}` is not a PPS source: expected gpiochipN:LINE[:active-low], /dev/ppsN, \
                 tcp:HOST:PORT, tcp-listen:[HOST:]PORT or sim"
            )
        };
        let rest = s.strip_prefix("/dev/").unwrap_or(s);
        match rest.strip_prefix("pps") {
            _ if s == "sim" => Ok(PpsSpec::Sim),
            _ if s.starts_with("tcp:") || s.starts_with("tcp-listen:") => {
                s.parse().map(PpsSpec::Tcp)
            }
            Some(n) if !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()) => {
                Ok(PpsSpec::Device(PathBuf::from(format!("/dev/{rest}"))))
            }
            Some(_) => Err(bad()),
            None => GpioSpec::parse(s).map(PpsSpec::Gpio).ok_or_else(bad),
        }
    }
}

impl PpsSpec {
    /// How far an edge of this source may stray from the line of the previous ones
    /// before it is an outlier, ns: the time stamp's own jitter with margin. A kernel's
    /// interrupt stamp: 200 µs (a busy single-board computer); the TCP test source,
    /// stamped on arrival by a user-space thread: 20 ms; the simulated module, captured
    /// as the board's timer would: the engine's 10 µs.
    #[must_use]
    pub const fn tolerance_ns(&self) -> u32 {
        match self {
            PpsSpec::Gpio(_) | PpsSpec::Device(_) => 200_000,
            PpsSpec::Tcp(_) => 20_000_000,
            PpsSpec::Sim => bridge_engine::discipline::PpsConfig::DEFAULT.tolerance_ns,
        }
    }
}

impl fmt::Display for PpsSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PpsSpec::Gpio(g) => write!(f, "{g}"),
            PpsSpec::Device(p) => write!(f, "{}", p.display()),
            PpsSpec::Tcp(p) => write!(f, "{p}"),
            PpsSpec::Sim => f.write_str("sim"),
        }
    }
}

/// Edges from the reading threads to the bridge's PPS task.
pub type EdgeChannel = Channel<CriticalSectionRawMutex, InstantNs, 4>;

/// Edges time-stamped by a thread ([`start`]).
#[derive(Clone, Copy)]
pub struct ChannelPps(pub &'static EdgeChannel);

impl PpsInput for ChannelPps {
    async fn edge(&mut self) -> InstantNs {
        self.0.receive().await
    }
}

/// One byte an edge on a pipe (the TCP test source), stamped when the task reads it.
#[derive(Clone, Copy)]
pub struct PipePps(pub &'static HostPipe);

impl PpsInput for PipePps {
    async fn edge(&mut self) -> InstantNs {
        let mut buf = [0u8; 8];
        loop {
            if self.0.read(&mut buf).await > 0 {
                return InstantNs::from_instant(bridge_fw::now());
            }
        }
    }
}

/// The runner's PPS input, whichever `--pps` names.
pub enum RunnerPps {
    /// No `--pps`.
    None,
    /// A kernel source's thread ([`start`]).
    Kernel(ChannelPps),
    /// The TCP test source.
    Pipe(PipePps),
    /// The simulated GNSS module.
    Sim(CapturedPps<'static>),
}

impl PpsInput for RunnerPps {
    async fn edge(&mut self) -> InstantNs {
        match self {
            RunnerPps::None => core::future::pending().await,
            RunnerPps::Kernel(k) => k.edge().await,
            RunnerPps::Pipe(p) => p.edge().await,
            RunnerPps::Sim(s) => s.edge().await,
        }
    }
}

/// The simulated GNSS module on the runner's clock: fixed from the start, its UTC the
/// host's (`utc_at_zero_us`, the UTC at the runner's clock 0, as `--fc-port sim`'s),
/// the host's clock its crystal.
#[must_use]
pub fn sim_wiring(utc_at_zero_us: u64, active_low: bool) -> PpsWiring {
    PpsWiring {
        gnss: GnssPps::new(GnssPpsConfig {
            utc_at_zero_us,
            active_low,
            ..GnssPpsConfig::default()
        }),
        crystal: Crystal {
            ppm: 0.0,
            wander_ppm: 0.0,
            wander_period_s: 600.0,
            offset_ns: 0,
        },
        bridge_active_low: active_low,
    }
}

/// The runner's clock (ns) at the CLOCK_REALTIME instant `realtime_ns`, by a pair of
/// readings of both clocks now.
fn local_of_realtime(realtime_ns: i128) -> InstantNs {
    let now_rt = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| i128::try_from(d.as_nanos()).unwrap_or(i128::MAX));
    let now_local = i128::from(host::real_now_ns());
    let local = now_local - (now_rt - realtime_ns);
    InstantNs::from_nanos(u64::try_from(local.max(0)).unwrap_or(0))
}

/// Starts the thread that reads a kernel source's edges into `edges`.
///
/// # Errors
/// The GPIO line or PPS device cannot be had, in words.
pub fn start(
    spec: &PpsSpec,
    edges: &'static EdgeChannel,
    config_active_low: bool,
    out: &Output,
) -> Result<(), String> {
    match spec {
        PpsSpec::Gpio(GpioSpec {
            chip,
            line,
            active_low,
        }) => {
            let mut b = gpiocdev::Request::builder();
            b.on_chip(chip.as_str())
                .with_consumer("gimbal-bridge-pps")
                .with_line(*line)
                .as_input()
                .with_edge_detection(gpiocdev::line::EdgeDetection::RisingEdge)
                .with_event_clock(gpiocdev::line::EventClock::Realtime);
            if *active_low || config_active_low {
                b.as_active_low();
            }
            let request = b.request().map_err(|e| {
                let hint = if std::path::Path::new(chip).exists() {
                    ""
                } else {
                    " (no such GPIO chip: see `ls /dev/gpiochip*`)"
                };
                format!("PPS {chip} line {line}: {e}{hint}")
            })?;
            let out = out.clone();
            std::thread::spawn(move || {
                loop {
                    match request.read_edge_event() {
                        Ok(e) => {
                            let at = local_of_realtime(i128::from(e.timestamp_ns));
                            let _ = edges.try_send(at);
                        }
                        Err(e) => {
                            out.emit(
                                EventName::PpsError,
                                json!({"source": "gpio", "error": e.to_string()}),
                            );
                            std::thread::sleep(StdDuration::from_secs(1));
                        }
                    }
                }
            });
            Ok(())
        }
        PpsSpec::Device(path) => {
            let device = pps_time::PpsDevice::new(path.clone())
                .map_err(|e| format!("PPS {}: {e}", path.display()))?;
            let out = out.clone();
            let path = path.display().to_string();
            std::thread::spawn(move || {
                let mut last = None;
                loop {
                    // Waits for the next assert edge, at most 3 s.
                    match device.fetch_timeout(3, 0) {
                        Ok(data) => {
                            let info = data.info;
                            if last != Some(info.assert_sequence) && info.assert_sequence != 0 {
                                last = Some(info.assert_sequence);
                                let ts = i128::from(info.assert_tu.sec) * 1_000_000_000
                                    + i128::from(info.assert_tu.nsec);
                                let _ = edges.try_send(local_of_realtime(ts));
                            }
                        }
                        Err(e) if e.raw_os_error() == Some(libc_etimedout()) => {}
                        Err(e) => {
                            out.emit(
                                EventName::PpsError,
                                json!({"source": path, "error": e.to_string()}),
                            );
                            std::thread::sleep(StdDuration::from_secs(1));
                        }
                    }
                }
            });
            Ok(())
        }
        PpsSpec::Tcp(_) | PpsSpec::Sim => Ok(()),
    }
}

/// ETIMEDOUT on Linux (a `PPS_FETCH` that saw no edge within its time-out).
const fn libc_etimedout() -> i32 {
    110
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pps_specs() {
        let p = |s: &str| s.parse::<PpsSpec>();
        assert_eq!(
            p("gpiochip0:17:active-low"),
            Ok(PpsSpec::Gpio(GpioSpec::new("/dev/gpiochip0", 17, true)))
        );
        assert_eq!(p("/dev/pps0"), Ok(PpsSpec::Device("/dev/pps0".into())));
        assert_eq!(p("pps12"), Ok(PpsSpec::Device("/dev/pps12".into())));
        assert_eq!(p("sim"), Ok(PpsSpec::Sim));
        assert!(matches!(p("tcp-listen:0"), Ok(PpsSpec::Tcp(_))));
        for bad in [
            "",
            "pps",
            "ppsx",
            "/dev/ttyS0",
            "gpiochip0",
            "gpiochip0:1:x",
            "log",
        ] {
            assert!(p(bad).is_err(), "{bad}");
        }
        assert_eq!(p("pps3").unwrap().to_string(), "/dev/pps3");
    }

    #[test]
    fn a_missing_pps_source_is_a_clear_error() {
        let edges: &'static EdgeChannel = Box::leak(Box::new(EdgeChannel::new()));
        let out = Output::capture();
        let e = start(&"/dev/pps999".parse().unwrap(), edges, false, &out).unwrap_err();
        assert!(e.starts_with("PPS /dev/pps999:"), "{e}");
        let e = start(&"gpiochip99:1".parse().unwrap(), edges, false, &out).unwrap_err();
        assert!(e.contains("no such GPIO chip"), "{e}");
    }
}
