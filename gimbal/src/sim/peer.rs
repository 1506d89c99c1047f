//! The simulated peers ([`Peer`]) and how they run as async tasks on byte streams: a
//! simulated FC or the simulated pod ([`SimPod`]) talking to the bridge's tasks through any
//! `embedded_io_async` reader and writer (the host harness's pipes, a TCP socket, a
//! serial port), on `embassy_time`'s clock: virtual time for tests and the demo, real
//! time for the Linux runner's `sim` ports.
//!
//! Simulated true time is `embassy_time::Instant::now()` in microseconds. Bytes travel
//! at the line's rate (10 bits per byte at the baud rate) in chunks of at most [`CHUNK`]
//! bytes, one after the other; each chunk is written to the stream when its last byte
//! has arrived, so the bridge sees arrivals as a UART would deliver them (a frame's last
//! byte one frame time after its first left the peer).
//!
//! The peers are shared with their observers through a [`RefCell`]: the executor runs
//! every task on one thread and no borrow is held across an `.await`.

use core::cell::RefCell;
use std::collections::VecDeque;

use embassy_futures::select::{Either, select};
use embassy_time::{Instant as EmbassyInstant, Timer};
use embedded_hal::digital::{ErrorType, OutputPin};
use embedded_io_async::{Read, Write};

use super::line::CHUNK;
use super::pod::SimPod;

/// Simulated true time now, µs (the task clock).
#[must_use]
pub fn now_us() -> u64 {
    EmbassyInstant::now().as_micros()
}

/// A simulated peer of the bridge, sans-IO, true time in microseconds: a flight
/// controller (every [`super::Autopilot`], [`super::scenario::SilentFc`]), the telemetry
/// link's autopilot port or the pod ([`SimPod`]). [`super::scenario::Scenario`] and
/// [`run_peer`] drive it.
pub trait Peer {
    /// Bytes from the bridge, the last of them arriving at `now_us`.
    fn receive(&mut self, now_us: u64, bytes: &[u8]);
    /// The work due up to `now_us`.
    fn poll(&mut self, now_us: u64);
    /// When [`Peer::poll`] is next due (`u64::MAX`: never).
    fn next_wakeup(&self) -> u64;
    /// Bytes to send, each batch with the instant it starts on the wire (not before
    /// the poll that produced it; the pod's: `now_us`).
    fn transmit(&mut self, now_us: u64) -> Vec<(u64, Vec<u8>)>;
}

impl Peer for SimPod {
    fn receive(&mut self, now_us: u64, bytes: &[u8]) {
        SimPod::receive(self, now_us, bytes);
    }
    fn poll(&mut self, now_us: u64) {
        SimPod::poll(self, now_us);
    }
    fn next_wakeup(&self) -> u64 {
        SimPod::next_wakeup(self)
    }
    fn transmit(&mut self, now_us: u64) -> Vec<(u64, Vec<u8>)> {
        let bytes = SimPod::transmit(self);
        if bytes.is_empty() {
            Vec::new()
        } else {
            vec![(now_us, bytes)]
        }
    }
}

/// Runs `peer` against the bridge: what the bridge writes arrives through `from_bridge`,
/// what the peer sends goes out through `to_bridge`, both paced at `baud` (each write of
/// the bridge reaches the peer when its last byte would have, after what was already on
/// the line, as a UART receiver delivers it). Never returns
/// (select it against the end of a run); a read or write error ends it with that error.
///
/// # Errors
/// The first read or write error of the streams.
pub async fn run_peer<P, R, W>(
    peer: &RefCell<P>,
    mut from_bridge: R,
    mut to_bridge: W,
    baud: u32,
) -> Result<core::convert::Infallible, PeerError>
where
    P: Peer,
    R: Read,
    W: Write,
{
    let byte_us = 10_000_000 / u64::from(baud.max(1));
    let mut out: VecDeque<(u64, Vec<u8>)> = VecDeque::new();
    // The chunk on the wire, and when its last byte reaches the bridge.
    let mut on_wire: Option<(u64, Vec<u8>)> = None;
    // What the bridge wrote, each write with the instant its last byte reaches the peer
    // (the line carries it at `baud` after what is already on it), and when the line
    // from the bridge is free.
    let mut incoming: VecDeque<(u64, Vec<u8>)> = VecDeque::new();
    let mut in_free = 0u64;
    let mut buf = [0u8; 256];
    loop {
        let now = now_us();
        {
            let mut p = peer.borrow_mut();
            while let Some((due, bytes)) = incoming.front()
                && *due <= now
            {
                p.receive(*due, bytes);
                incoming.pop_front();
            }
            if p.next_wakeup() <= now {
                p.poll(now);
            }
            out.extend(p.transmit(now));
        }
        // A chunk is handed over when its last byte has arrived, as a UART receiver
        // delivers it; the next one starts on the wire then.
        if let Some((due, chunk)) = on_wire.take() {
            if due <= now {
                to_bridge
                    .write_all(&chunk)
                    .await
                    .map_err(|_| PeerError::Write)?;
                continue;
            }
            on_wire = Some((due, chunk));
        }
        if on_wire.is_none()
            && let Some((at, bytes)) = out.front_mut()
            && *at <= now
        {
            let n = bytes.len().min(CHUNK);
            let chunk: Vec<u8> = bytes.drain(..n).collect();
            if bytes.is_empty() {
                out.pop_front();
            }
            if !chunk.is_empty() {
                on_wire = Some((now.saturating_add(byte_us.saturating_mul(n as u64)), chunk));
            }
            continue;
        }
        let next_out = match &on_wire {
            Some((due, _)) => Some(*due),
            None => out.front().map(|(at, _)| *at),
        };
        let next_in = incoming.front().map(|(due, _)| *due);
        let next = [Some(peer.borrow().next_wakeup()), next_out, next_in]
            .into_iter()
            .flatten()
            .min()
            .unwrap_or(u64::MAX);
        let timer = Timer::at(if next == u64::MAX {
            EmbassyInstant::MAX
        } else {
            EmbassyInstant::from_micros(next)
        });
        match select(from_bridge.read(&mut buf), timer).await {
            Either::First(Ok(0)) => return Err(PeerError::Closed),
            Either::First(Ok(n)) => {
                let start = now_us().max(in_free);
                in_free = start.saturating_add(byte_us.saturating_mul(n as u64));
                incoming.push_back((in_free, buf.get(..n).unwrap_or_default().to_vec()));
            }
            Either::First(Err(_)) => return Err(PeerError::Read),
            Either::Second(()) => {}
        }
    }
}

/// Why a peer task ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PeerError {
    /// The stream from the bridge ended.
    Closed,
    /// Reading failed.
    Read,
    /// Writing failed.
    Write,
}

/// The bridge's RTC_IO pin wired to the simulated pod: each change reaches the pod at
/// the instant it is made.
#[derive(Clone, Copy)]
pub struct PodPin<'a> {
    pod: &'a RefCell<SimPod>,
}

impl core::fmt::Debug for PodPin<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("PodPin")
    }
}

impl<'a> PodPin<'a> {
    /// The pin of `pod`.
    #[must_use]
    pub const fn new(pod: &'a RefCell<SimPod>) -> Self {
        PodPin { pod }
    }
}

impl ErrorType for PodPin<'_> {
    type Error = core::convert::Infallible;
}

impl OutputPin for PodPin<'_> {
    fn set_low(&mut self) -> Result<(), Self::Error> {
        self.pod.borrow_mut().rtc_edge(now_us(), false);
        Ok(())
    }
    fn set_high(&mut self) -> Result<(), Self::Error> {
        self.pod.borrow_mut().rtc_edge(now_us(), true);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bridge_fw::host::{self, Clock, HostPipe};
    use embassy_futures::select::select;

    /// Sends one burst of `len` bytes at true time `at`.
    struct Burst {
        at: u64,
        len: usize,
        sent: bool,
    }

    impl Peer for Burst {
        fn receive(&mut self, _now_us: u64, _bytes: &[u8]) {}
        fn poll(&mut self, _now_us: u64) {}
        fn next_wakeup(&self) -> u64 {
            u64::MAX
        }
        fn transmit(&mut self, _now_us: u64) -> Vec<(u64, Vec<u8>)> {
            if core::mem::replace(&mut self.sent, true) {
                Vec::new()
            } else {
                vec![(self.at, (0..self.len as u8).collect())]
            }
        }
    }

    #[test]
    fn bytes_reach_the_bridge_when_their_last_bit_has_arrived() {
        let peer = RefCell::new(Burst {
            at: 1_000,
            len: 40,
            sent: false,
        });
        let to_peer = HostPipe::new();
        let from_peer = HostPipe::new();
        let mut arrivals = Vec::new();
        host::run(Clock::Virtual, || {
            let reader = async {
                let mut buf = [0u8; 64];
                let mut total = 0;
                while total < 40 {
                    let n = from_peer.read(&mut buf).await;
                    total += n;
                    arrivals.push((now_us(), n));
                }
            };
            select(run_peer(&peer, &to_peer, &from_peer, 115_200), reader)
        });
        // 86 µs a byte at 115200 baud; chunks of 16: each is handed over when its last
        // byte is in, never before.
        assert_eq!(
            arrivals,
            vec![
                (1_000 + 16 * 86, 16),
                (1_000 + 32 * 86, 16),
                (1_000 + 40 * 86, 8)
            ]
        );
    }
}
