//! The bridge engine without Embassy: one `service` pass of a super-loop over blocking
//! `embedded-io` UARTs (reads only when `ReadReady` says so), an `embedded-hal` output pin
//! and a monotonic clock. This is the shape of a bare-metal `main` loop or an RTIC `idle`
//! task; call [`Bridge::service`] as often as possible (or sleep until
//! [`Bridge::deadline`] with a timer interrupt, and on UART receive interrupts).
//!
//! Timing: the loop's reaction time is its longest pass, i.e. mostly the longest
//! blocking frame write. The RTC_IO edge is taken first in each pass, and a pod frame that
//! would still be on the wire at a planned edge is not started, so the 0x00030E follows
//! the edge within one pass. For tighter edges, raise the pin from a timer interrupt at
//! `Engine::pin()`'s instant and call `pin_done` there (the engine is `Send`; share it
//! behind a critical-section mutex).
//!
//! On the host it runs against in-memory UARTs, a simulated clock and a pod that sends
//! attitude reports:
//! `cargo run -p bridge-fw --example blocking --no-default-features --features host,fc-all`

use std::collections::VecDeque;
use std::convert::Infallible;

use bridge_engine::{Config, Duration, Engine, Instant, Level, MAX_FRAME_LEN, Port};
use embedded_hal::digital::OutputPin;
use embedded_io::{ErrorType, Read, ReadReady, Write};
use protocol_core::k40t::{self, Address, GimbalAttitude, Header};

/// A monotonic clock in microseconds (a 32-bit timer extended to 64 bits, DWT, SysTick...).
pub trait Monotonic {
    /// Now.
    fn now(&self) -> Instant;
}

/// Per-port line state: bytes arrived since the last idle, and when the last came.
#[derive(Default)]
struct Line {
    last: Option<Instant>,
}

/// The engine and what the loop keeps between passes.
pub struct Bridge {
    /// The engine.
    pub engine: Engine,
    fc: Line,
    pod: Line,
    /// Silence after which a line is idle (5 ms, as the firmware at 115200).
    idle: Duration,
    /// Time on the wire of one byte on the pod link, µs.
    pod_byte_us: u64,
}

impl Bridge {
    /// A bridge with `config`.
    pub fn new(config: Config) -> Self {
        Bridge {
            engine: Engine::new(config),
            fc: Line::default(),
            pod: Line::default(),
            idle: Duration::from_millis(5),
            pod_byte_us: 10_000_000u64.div_ceil(u64::from(config.pod_baud.max(1))),
        }
    }

    /// The latest instant the next pass is needed (without new input).
    pub fn deadline(&self) -> Option<Instant> {
        let pin = self.engine.pin().map(|a| a.at);
        let idle = [self.fc.last, self.pod.last]
            .into_iter()
            .flatten()
            .map(|t| t.saturating_add(self.idle));
        [self.engine.poll_at(), pin]
            .into_iter()
            .flatten()
            .chain(idle)
            .min()
    }

    /// One pass: RTC_IO, inputs, poll, outputs. UART errors are returned; the engine's
    /// state stays consistent whatever happens (a frame whose write failed is lost, as on
    /// a cable that dropped it).
    #[allow(clippy::too_many_arguments)]
    pub fn service<E, FR, FT, PR, PT, P, C>(
        &mut self,
        fc_rx: &mut FR,
        fc_tx: &mut FT,
        pod_rx: &mut PR,
        pod_tx: &mut PT,
        rtc_io: &mut P,
        clock: &C,
    ) -> Result<(), E>
    where
        FR: Read + ReadReady + ErrorType<Error = E>,
        FT: Write + ErrorType<Error = E>,
        PR: Read + ReadReady + ErrorType<Error = E>,
        PT: Write + ErrorType<Error = E>,
        P: OutputPin,
        C: Monotonic,
    {
        // 1. RTC_IO first: pin, clock, pin_done; the 0x00030E is then at the head of the
        // pod queue and goes out in step 4 of this very pass.
        if let Some(a) = self.engine.pin().filter(|a| a.at <= clock.now()) {
            let _ = match a.level {
                Level::High => rtc_io.set_high(),
                Level::Low => rtc_io.set_low(),
            };
            self.engine.pin_done(a.level, clock.now());
        }
        // 2. Inputs, and line idle after a silence.
        let mut buf = [0u8; 64];
        for port in [Port::Fc, Port::Pod] {
            let (ready, line) = match port {
                Port::Fc => (fc_rx.read_ready()?, &mut self.fc),
                Port::Pod | Port::Telemetry => (pod_rx.read_ready()?, &mut self.pod),
            };
            let now = clock.now();
            if ready {
                let n = match port {
                    Port::Fc => fc_rx.read(&mut buf)?,
                    Port::Pod | Port::Telemetry => pod_rx.read(&mut buf)?,
                };
                self.engine.receive(now, port, buf.get(..n).unwrap_or(&[]));
                line.last = Some(now);
            } else if line
                .last
                .is_some_and(|t| now.saturating_duration_since(t) >= self.idle)
            {
                line.last = None;
                self.engine.idle(now, port);
            }
        }
        // 3. Timers.
        let now = clock.now();
        if self.engine.poll_at().is_some_and(|t| t <= now) {
            self.engine.poll(now);
        }
        // 4. Outputs, whole frames. A pod frame that would still be on the wire at the
        // next rising edge waits for it.
        let mut frame = [0u8; MAX_FRAME_LEN];
        while let Some(len) = self.engine.pending(Port::Pod) {
            let wire = Duration::from_micros(self.pod_byte_us * (len as u64 + 2));
            let edge = self.engine.pin().filter(|a| a.level == Level::High);
            if edge.is_some_and(|a| clock.now().saturating_add(wire) >= a.at) {
                break;
            }
            let Some(n) = self.engine.transmit(Port::Pod, &mut frame) else {
                break;
            };
            pod_tx.write_all(frame.get(..n).unwrap_or(&[]))?;
        }
        while let Some(n) = self.engine.transmit(Port::Fc, &mut frame) {
            fc_tx.write_all(frame.get(..n).unwrap_or(&[]))?;
        }
        Ok(())
    }
}

// --- Host stand-ins -------------------------------------------------------------------

/// An in-memory UART: bytes to read, bytes written.
#[derive(Default)]
struct MemUart {
    rx: VecDeque<u8>,
    tx: Vec<u8>,
}

impl ErrorType for MemUart {
    type Error = Infallible;
}

impl Read for MemUart {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
        let n = buf.len().min(self.rx.len());
        for (slot, b) in buf.iter_mut().zip(self.rx.drain(..n)) {
            *slot = b;
        }
        Ok(n)
    }
}

impl ReadReady for MemUart {
    fn read_ready(&mut self) -> Result<bool, Infallible> {
        Ok(!self.rx.is_empty())
    }
}

impl Write for MemUart {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Infallible> {
        self.tx.extend_from_slice(buf);
        Ok(buf.len())
    }

    fn flush(&mut self) -> Result<(), Infallible> {
        Ok(())
    }
}

/// A simulated clock.
struct SimClock(std::cell::Cell<u64>);

impl Monotonic for SimClock {
    fn now(&self) -> Instant {
        Instant::from_micros(self.0.get())
    }
}

/// A pin that prints its edges.
struct PrintPin;

impl embedded_hal::digital::ErrorType for PrintPin {
    type Error = Infallible;
}

impl OutputPin for PrintPin {
    fn set_low(&mut self) -> Result<(), Infallible> {
        println!("RTC_IO low");
        Ok(())
    }

    fn set_high(&mut self) -> Result<(), Infallible> {
        println!("RTC_IO high");
        Ok(())
    }
}

fn main() {
    let mut bridge = Bridge::new(Config::DEFAULT);
    let (mut fc_rx, mut fc_tx, mut pod_rx, mut pod_tx) = (
        MemUart::default(),
        MemUart::default(),
        MemUart::default(),
        MemUart::default(),
    );
    let clock = SimClock(std::cell::Cell::new(0));
    let mut pin = PrintPin;
    let mut seq = 0u8;
    // Three seconds, a pass every 500 µs; the pod reports its attitude at 10 Hz from 1 s on.
    for step in 0..6000u64 {
        let t = step * 500;
        clock.0.set(t);
        if t >= 1_000_000 && t % 100_000 == 0 {
            seq = seq.wrapping_add(1);
            let mut frame = [0u8; k40t::MAX_FRAME_LEN];
            let header = Header::new(Address::GIMBAL, Address::FLIGHT_CONTROLLER, seq);
            if let Ok(n) = k40t::encode(&GimbalAttitude::default(), &header, &mut frame) {
                pod_rx.rx.extend(frame.iter().take(n));
            }
        }
        let Ok(()) = bridge.service(
            &mut fc_rx,
            &mut fc_tx,
            &mut pod_rx,
            &mut pod_tx,
            &mut pin,
            &clock,
        );
        while let Some(e) = bridge.engine.next_event() {
            println!("{:>8} µs  {e:?}", t);
        }
    }
    let c = bridge.engine.counters();
    println!(
        "pod link {}, {} frames from the pod, {} bytes to the pod, {} to the FC",
        if bridge.engine.pod_state().link {
            "up"
        } else {
            "down"
        },
        c.pod_frames,
        pod_tx.tx.len(),
        fc_tx.tx.len()
    );
    println!("next pass needed by {:?}", bridge.deadline());
    assert!(bridge.engine.pod_state().link);
}
