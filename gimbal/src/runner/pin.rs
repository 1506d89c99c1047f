//! The RTC_IO output of the Linux bridge: a GPIO line (kernel character device, crate
//! `gpiocdev`), a byte stream over TCP (for the simulated pod in another process and
//! emulators), the simulated pod's own pin (`--pod-port sim`), or none (`log`: the edges
//! are events only). One [`RunnerPin`] drives all that apply.

use std::fmt;
use std::io::Write;
use std::str::FromStr;

use embedded_hal::digital::{ErrorKind, ErrorType, OutputPin};

use super::port::{PortSpec, SharedWriter};
use crate::sim::peer::PodPin;

/// Where RTC_IO goes (`--rtc-io`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RtcSpec {
    /// No pin: the edges are events.
    Log,
    /// A GPIO line.
    Gpio(GpioSpec),
    /// One byte per edge over TCP (`tcp:` or `tcp-listen:`).
    Tcp(PortSpec),
}

/// A GPIO line written `[/dev/]gpiochipN:LINE[:active-low]` (`--rtc-io`, `--pps`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GpioSpec {
    /// The chip's device (`/dev/gpiochip0`).
    pub chip: String,
    /// The line's offset on the chip.
    pub line: u32,
    /// High on the wire is the line's inactive level.
    pub active_low: bool,
}

impl GpioSpec {
    /// Line `line` of `chip`.
    #[must_use]
    pub fn new(chip: &str, line: u32, active_low: bool) -> Self {
        GpioSpec {
            chip: chip.to_string(),
            line,
            active_low,
        }
    }

    /// The line `s` names, if it is one.
    #[must_use]
    pub fn parse(s: &str) -> Option<Self> {
        let rest = s.strip_prefix("/dev/").unwrap_or(s);
        let mut parts = rest.split(':');
        let chip = parts
            .next()
            .filter(|c| c.strip_prefix("gpiochip").is_some_and(|n| !n.is_empty()))?;
        let line = parts.next()?.parse::<u32>().ok()?;
        let active_low = match parts.next() {
            None => false,
            Some("active-low") => true,
            Some(_) => return None,
        };
        if parts.next().is_some() {
            return None;
        }
        Some(GpioSpec::new(&format!("/dev/{chip}"), line, active_low))
    }
}

impl fmt::Display for GpioSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let low = if self.active_low { ":active-low" } else { "" };
        write!(f, "{}:{}{low}", self.chip, self.line)
    }
}

impl FromStr for RtcSpec {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        if s == "log" || s == "none" {
            return Ok(RtcSpec::Log);
        }
        if s.starts_with("tcp:") || s.starts_with("tcp-listen:") {
            return s.parse().map(RtcSpec::Tcp);
        }
        let bad = || {
            format!(
                "`{s}` is not an RTC_IO output: expected gpiochipN:LINE[:active-low], log, \
                 tcp:HOST:PORT or tcp-listen:[HOST:]PORT"
            )
        };
        GpioSpec::parse(s).map(RtcSpec::Gpio).ok_or_else(bad)
    }
}

impl fmt::Display for RtcSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RtcSpec::Log => f.write_str("log"),
            RtcSpec::Gpio(g) => write!(f, "{g}"),
            RtcSpec::Tcp(p) => write!(f, "{p}"),
        }
    }
}

/// A GPIO line as an output.
pub struct GpioLine {
    request: gpiocdev::Request,
    line: u32,
}

impl GpioLine {
    /// Requests `line` of `chip` as an output, low (inactive) to begin with.
    ///
    /// # Errors
    /// The chip or line cannot be had, in words.
    pub fn open(chip: &str, line: u32, active_low: bool) -> Result<Self, String> {
        let mut b = gpiocdev::Request::builder();
        b.on_chip(chip)
            .with_consumer("gimbal-bridge-rtc-io")
            .with_line(line)
            .as_output(gpiocdev::line::Value::Inactive);
        if active_low {
            b.as_active_low();
        }
        let request = b.request().map_err(|e| {
            let hint = if !std::path::Path::new(chip).exists() {
                " (no such GPIO chip: see `ls /dev/gpiochip*`)"
            } else {
                ""
            };
            format!("RTC_IO {chip} line {line}: {e}{hint}")
        })?;
        Ok(GpioLine { request, line })
    }

    fn set(&self, high: bool) -> Result<(), gpiocdev::Error> {
        let v = if high {
            gpiocdev::line::Value::Active
        } else {
            gpiocdev::line::Value::Inactive
        };
        self.request.set_value(self.line, v).map(|_| ())
    }
}

/// The RTC_IO pin of the runner: every output that applies, set together.
#[derive(Default)]
pub struct RunnerPin<'a> {
    /// The simulated pod's pin (`--pod-port sim`).
    pub pod: Option<PodPin<'a>>,
    /// A GPIO line.
    pub gpio: Option<GpioLine>,
    /// A TCP byte stream (the connection's writer; none while nobody is connected).
    pub tcp: Option<SharedWriter>,
}

/// Setting the GPIO line failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PinFailed;

impl embedded_hal::digital::Error for PinFailed {
    fn kind(&self) -> ErrorKind {
        ErrorKind::Other
    }
}

impl RunnerPin<'_> {
    fn set(&mut self, high: bool) -> Result<(), PinFailed> {
        if let Some(p) = self.pod.as_mut() {
            let _ = if high { p.set_high() } else { p.set_low() };
        }
        if let Some(w) = &self.tcp
            && let Ok(mut g) = w.lock()
            && let Some(c) = g.as_mut()
        {
            // One byte into a socket with room: never waits. A failed write is the
            // end of that connection; its reader notices and reports it.
            let _ = c.write_all(if high { b"1" } else { b"0" });
        }
        match &self.gpio {
            Some(g) => g.set(high).map_err(|_| PinFailed),
            None => Ok(()),
        }
    }
}

impl ErrorType for RunnerPin<'_> {
    type Error = PinFailed;
}

impl OutputPin for RunnerPin<'_> {
    fn set_low(&mut self) -> Result<(), PinFailed> {
        self.set(false)
    }

    fn set_high(&mut self) -> Result<(), PinFailed> {
        self.set(true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rtc_specs() {
        let p = |s: &str| s.parse::<RtcSpec>();
        let gpio = |chip: &str, line, low| Ok(RtcSpec::Gpio(GpioSpec::new(chip, line, low)));
        let listen = RtcSpec::Tcp(PortSpec::TcpListen {
            host: None,
            port: 0,
        });
        for (text, want) in [
            ("log", Ok(RtcSpec::Log)),
            ("gpiochip0:17", gpio("/dev/gpiochip0", 17, false)),
            (
                "/dev/gpiochip4:3:active-low",
                gpio("/dev/gpiochip4", 3, true),
            ),
            ("tcp-listen:0", Ok(listen)),
        ] {
            assert_eq!(p(text), want, "{text}");
        }
        for bad in [
            "",
            "gpio",
            "gpiochip:1",
            "gpiochip0",
            "gpiochip0:x",
            "gpiochip0:1:2",
            "/dev/ttyS0",
            "sim",
            "tcp:x",
        ] {
            assert!(p(bad).is_err(), "{bad}");
        }
        assert_eq!(
            p("gpiochip4:3:active-low").unwrap().to_string(),
            "/dev/gpiochip4:3:active-low"
        );
    }

    #[test]
    fn a_missing_gpio_chip_is_a_clear_error() {
        let Err(e) = GpioLine::open("/dev/gpiochip-none", 3, false) else {
            panic!("opened a missing chip")
        };
        assert!(e.starts_with("RTC_IO /dev/gpiochip-none line 3:"), "{e}");
        assert!(e.contains("no such GPIO chip"), "{e}");
    }
}
