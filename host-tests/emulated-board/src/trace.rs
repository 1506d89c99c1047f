//! RTC_IO and the LED as QEMU's GPIO trace shows them: the trace's lines read as pin
//! levels with QEMU's wall-clock stamps, handed to the simulated pod as they come.

use core::cell::RefCell;
use core::convert::Infallible;
use std::fs::File;
use std::io::Read as _;
use std::path::PathBuf;

use bridge_fw::host::HostPipe;
use gimbal::sim::peer::now_us;
use gimbal::sim::pod::SimPod;

/// The new level of `pin` if the traced write `line` sets it on `port` (QEMU's
/// `stm32l4x5_gpio_write <port> addr: 0x.. val: 0x..`): BSRR (0x18: set bits 0..15, reset
/// bits 16..31, set wins), BRR (0x28) and ODR (0x14). `None` for any other line or write.
#[must_use]
pub fn pin_write(line: &str, port: &str, pin: u32) -> Option<bool> {
    let rest = line.split("stm32l4x5_gpio_write ").nth(1)?;
    let mut words = rest.split_whitespace();
    if words.next()? != port || words.next()? != "addr:" {
        return None;
    }
    let addr = parse_hex(words.next()?)?;
    if words.next()? != "val:" {
        return None;
    }
    let val = parse_hex(words.next()?)?;
    let bit = |n: u32| n < 32 && val & (1 << n) != 0;
    match addr {
        0x18 if bit(pin) => Some(true),
        0x18 if bit(pin + 16) => Some(false),
        0x28 if bit(pin) => Some(false),
        0x14 => Some(bit(pin)),
        _ => None,
    }
}

/// The wall-clock instant (µs since the Unix epoch) QEMU stamped a trace line with
/// (`-msg timestamp=on`: `<pid>@<seconds>.<microseconds>:<event> ...`), if it has one.
#[must_use]
pub fn trace_stamp_us(line: &str) -> Option<u64> {
    let (head, _) = line.split_once(':')?;
    let (_, stamp) = head.split_once('@')?;
    let (secs, micros) = stamp.split_once('.')?;
    if micros.len() != 6 {
        return None;
    }
    let secs: u64 = secs.parse().ok()?;
    let micros: u64 = micros.parse().ok()?;
    secs.checked_mul(1_000_000)?.checked_add(micros)
}

/// The offset from the simulators' clock ([`now_us`]) to the wall clock (µs since the
/// Unix epoch), read back to back a few times, the tightest pair kept (to a few µs).
fn wall_offset_us() -> i128 {
    let mut best: Option<(u64, i128)> = None;
    for _ in 0..8 {
        let a = now_us();
        let wall = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_micros());
        let b = now_us();
        let spread = b.saturating_sub(a);
        let offset = i128::try_from(wall).unwrap_or(0) - i128::from(a / 2 + b / 2);
        if best.is_none_or(|(s, _)| spread < s) {
            best = Some((spread, offset));
        }
    }
    best.map_or(0, |(_, o)| o)
}

fn parse_hex(s: &str) -> Option<u32> {
    u32::from_str_radix(s.strip_prefix("0x")?, 16).ok()
}

/// RTC_IO (PA2: the board's TIM2 CH3, a GPIO in the `qemu` flavour) as QEMU's GPIO trace
/// shows it, handed to the simulated pod.
pub(crate) struct TraceWatch {
    path: PathBuf,
    file: Option<File>,
    pending: Vec<u8>,
    level: bool,
    /// Every level change: when the watch saw it, the instant QEMU traced it (both on the
    /// simulators' clock), the new level.
    edges: Vec<Edge>,
    /// The simulators' clock to the wall clock of QEMU's trace stamps, µs.
    wall_offset_us: i128,
    /// LED2 (PB14): its level and the wall µs of its changes.
    led: bool,
    led_edges: Vec<(u64, bool)>,
}

/// One RTC_IO change seen in the trace.
#[derive(Debug, Clone, Copy)]
struct Edge {
    /// When the watch read it (µs, simulators' clock): what the simulated pod was told.
    seen_us: u64,
    /// When the guest wrote the pin, from QEMU's stamp on the trace line (µs, the
    /// simulators' clock; `None` for a line without a stamp). The reference instant of
    /// the time-sync check: the watch reads the file every 5 ms, later under load.
    traced_us: Option<u64>,
    level: bool,
}

impl TraceWatch {
    pub(crate) fn new(path: PathBuf) -> Self {
        TraceWatch {
            path,
            file: None,
            pending: Vec::new(),
            level: false,
            edges: Vec::new(),
            wall_offset_us: wall_offset_us(),
            led: false,
            led_edges: Vec::new(),
        }
    }

    /// The firmware's own view, from LED2's last blink pattern (`bridge_fw::led`: three
    /// flashes for the FC link, the pod link and UTC, long when up, short when down).
    pub(crate) fn led_status(&self) -> String {
        let flashes: Vec<u64> = self
            .led_edges
            .windows(2)
            .filter(|w| w[0].1 && !w[1].1)
            .map(|w| w[1].0.saturating_sub(w[0].0))
            .collect();
        let n = flashes.len();
        if n < 3 {
            return "LED: no full pattern".into();
        }
        // The pattern's first flash follows the longest dark gap (800 ms).
        let dark: Vec<(usize, u64)> = self
            .led_edges
            .windows(2)
            .filter(|w| !w[0].1 && w[1].1)
            .map(|w| w[1].0.saturating_sub(w[0].0))
            .enumerate()
            .collect();
        // Dark gap `i` comes before flash `i + 1`.
        let start = dark
            .iter()
            .rev()
            .skip_while(|(i, _)| i + 4 > n)
            .find(|(_, d)| *d > 500_000)
            .map_or(n - 3, |(i, _)| i + 1);
        let up = |i: usize| match flashes.get(i) {
            Some(&d) if d >= 150_000 => "up",
            Some(_) => "down",
            None => "?",
        };
        format!(
            "LED says FC {}, pod {}, UTC {}",
            up(start),
            up(start + 1),
            up(start + 2)
        )
    }

    /// When QEMU traced the High edge the pod was told of at `seen_us` (when it was seen,
    /// for a line without a stamp); `None`: no such edge.
    pub(crate) fn traced_high(&self, seen_us: u64) -> Option<u64> {
        self.edges
            .iter()
            .find(|e| e.level && e.seen_us == seen_us)
            .map(|e| e.traced_us.unwrap_or(seen_us))
    }

    /// Reads what QEMU appended and gives every RTC_IO change to `pod`, now.
    pub(crate) fn poll(&mut self, pod: &RefCell<SimPod>) {
        if self.file.is_none() {
            self.file = File::open(&self.path).ok();
        }
        let Some(file) = self.file.as_mut() else {
            return;
        };
        if file.read_to_end(&mut self.pending).is_err() {
            return;
        }
        while let Some(end) = self.pending.iter().position(|&b| b == b'\n') {
            let line: Vec<u8> = self.pending.drain(..=end).collect();
            let line = String::from_utf8_lossy(&line);
            if let Some(on) = pin_write(&line, "GPIOB", 14)
                && on != self.led
            {
                self.led = on;
                self.led_edges.push((now_us(), on));
            }
            if let Some(level) = pin_write(&line, "GPIOA", 2)
                && level != self.level
            {
                self.level = level;
                let t = now_us();
                // Traced before it was seen, by less than a second: else the wall clock
                // stepped since the offset was taken, and the stamp is not used.
                let traced_us = trace_stamp_us(&line)
                    .and_then(|wall| u64::try_from(i128::from(wall) - self.wall_offset_us).ok())
                    .filter(|&traced| traced <= t + 1_000 && t < traced + 1_000_000);
                self.edges.push(Edge {
                    seen_us: t,
                    traced_us,
                    level,
                });
                pod.borrow_mut().rtc_edge(t, level);
            }
        }
    }
}

/// The pod's end of the pod link: bytes from the bridge, RTC_IO changes first.
pub(crate) struct PodReader<'a> {
    pub(crate) pipe: &'a HostPipe,
    pub(crate) pod: &'a RefCell<SimPod>,
    pub(crate) trace: &'a RefCell<TraceWatch>,
}

impl embedded_io_async::ErrorType for PodReader<'_> {
    type Error = Infallible;
}

impl embedded_io_async::Read for PodReader<'_> {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
        let n = self.pipe.read(buf).await;
        // The edge that precedes these bytes is in the trace by now (see the module doc).
        self.trace.borrow_mut().poll(self.pod);
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gpio_trace_lines_give_the_pin_level_they_set() {
        let line = |addr: u32, val: u32| {
            format!("stm32l4x5_gpio_write GPIOD addr: {addr:#x} val: {val:#x}")
        };
        // BSRR: set (bit 14), reset (bit 30), both (set wins), another pin.
        assert_eq!(pin_write(&line(0x18, 0x4000), "GPIOD", 14), Some(true));
        assert_eq!(
            pin_write(&line(0x18, 0x4000_0000), "GPIOD", 14),
            Some(false)
        );
        assert_eq!(pin_write(&line(0x18, 0x4000_4000), "GPIOD", 14), Some(true));
        assert_eq!(pin_write(&line(0x18, 0x2000), "GPIOD", 14), None);
        // BRR and ODR.
        assert_eq!(pin_write(&line(0x28, 0x4000), "GPIOD", 14), Some(false));
        assert_eq!(pin_write(&line(0x14, 0x4001), "GPIOD", 14), Some(true));
        assert_eq!(pin_write(&line(0x14, 0x0001), "GPIOD", 14), Some(false));
        // Configuration writes, other ports, a timestamped line, garbage.
        assert_eq!(pin_write(&line(0x0, 0xffff_ffff), "GPIOD", 14), None);
        assert_eq!(
            pin_write(
                "stm32l4x5_gpio_write GPIOB addr: 0x18 val: 0x4000",
                "GPIOD",
                14
            ),
            None
        );
        assert_eq!(
            pin_write(
                "1234@1700000000.000001:stm32l4x5_gpio_write GPIOD addr: 0x18 val: 0x4000",
                "GPIOD",
                14
            ),
            Some(true)
        );
        assert_eq!(
            pin_write(
                "stm32l4x5_gpio_write GPIOD addr: zz val: 0x4000",
                "GPIOD",
                14
            ),
            None
        );
        assert_eq!(pin_write("", "GPIOD", 14), None);
    }

    #[test]
    fn trace_stamps_read_as_wall_clock_microseconds() {
        let line = "11054@1795551751.337070:stm32l4x5_gpio_write GPIOD addr: 0x18 val: 0x4000";
        assert_eq!(trace_stamp_us(line), Some(1_795_551_751_337_070));
        assert_eq!(pin_write(line, "GPIOD", 14), Some(true));
        // No stamp (QEMU without `-msg timestamp=on`), a malformed one.
        assert_eq!(
            trace_stamp_us("stm32l4x5_gpio_write GPIOD addr: 0x18 val: 0x4000"),
            None
        );
        assert_eq!(trace_stamp_us("1@17.5:stm32l4x5_gpio_write GPIOD"), None);
        assert_eq!(
            trace_stamp_us("1@x.000001:stm32l4x5_gpio_write GPIOD"),
            None
        );
    }

    #[test]
    fn the_led_pattern_reads_as_the_firmwares_status() {
        let mut t = TraceWatch::new(PathBuf::new());
        // Two patterns (FC up, pod down, UTC up): flashes of 300, 40, 300 ms, 100/360 ms
        // apart, 800 ms dark before each.
        let mut at = 0u64;
        for _ in 0..2 {
            at += 800_000;
            for (on, off) in [(300_000, 100_000), (40_000, 360_000), (300_000, 100_000)] {
                t.led_edges.push((at, true));
                at += on;
                t.led_edges.push((at, false));
                at += off;
            }
        }
        assert_eq!(t.led_status(), "LED says FC up, pod down, UTC up");
        assert_eq!(
            TraceWatch::new(PathBuf::new()).led_status(),
            "LED: no full pattern"
        );
    }
}
