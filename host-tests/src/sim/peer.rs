//! The simulated peers as async tasks on byte streams: a simulated FC ([`FcSim`]) or the
//! simulated pod ([`SimPod`]) talking to the bridge's tasks through any
//! `embedded_io_async` reader and writer (the host harness's pipes, a TCP socket, a
//! serial port), on `embassy_time`'s clock: virtual time for tests and the demo, real
//! time for the Linux runner's `sim` ports.
//!
//! Simulated true time is `embassy_time::Instant::now()` in microseconds. Bytes leave at
//! the line's rate: at most [`CHUNK`] bytes per write, the next write not before the
//! previous bytes would have left the wire (10 bits per byte at the baud rate), so the
//! bridge sees arrivals as a UART would deliver them.
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
use super::scenario::FcSim;

/// Simulated true time now, µs (the task clock).
#[must_use]
pub fn now_us() -> u64 {
    EmbassyInstant::now().as_micros()
}

/// A sans-IO peer the task loop drives.
pub trait Peer {
    /// Bytes from the bridge, the last of them arriving at `now_us`.
    fn peer_receive(&mut self, now_us: u64, bytes: &[u8]);
    /// Work due at `now_us`.
    fn peer_poll(&mut self, now_us: u64);
    /// When the next work is due (`u64::MAX`: never).
    fn peer_next_wakeup(&self) -> u64;
    /// Bytes to send, each batch with the instant it may start.
    fn peer_transmit(&mut self, now_us: u64) -> Vec<(u64, Vec<u8>)>;
}

impl<F: FcSim> Peer for F {
    fn peer_receive(&mut self, now_us: u64, bytes: &[u8]) {
        self.receive(now_us, bytes);
    }
    fn peer_poll(&mut self, now_us: u64) {
        self.poll(now_us);
    }
    fn peer_next_wakeup(&self) -> u64 {
        self.next_wakeup()
    }
    fn peer_transmit(&mut self, _now_us: u64) -> Vec<(u64, Vec<u8>)> {
        self.transmit()
    }
}

impl Peer for SimPod {
    fn peer_receive(&mut self, now_us: u64, bytes: &[u8]) {
        self.receive(now_us, bytes);
    }
    fn peer_poll(&mut self, now_us: u64) {
        self.poll(now_us);
    }
    fn peer_next_wakeup(&self) -> u64 {
        self.next_wakeup()
    }
    fn peer_transmit(&mut self, now_us: u64) -> Vec<(u64, Vec<u8>)> {
        let bytes = self.transmit();
        if bytes.is_empty() {
            Vec::new()
        } else {
            vec![(now_us, bytes)]
        }
    }
}

/// Runs `peer` against the bridge: what the bridge writes arrives through `from_bridge`,
/// what the peer sends goes out through `to_bridge`, paced at `baud`. Never returns
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
    let mut line_free_us = 0u64;
    let mut buf = [0u8; 256];
    loop {
        let now = now_us();
        {
            let mut p = peer.borrow_mut();
            if p.peer_next_wakeup() <= now {
                p.peer_poll(now);
            }
            out.extend(p.peer_transmit(now));
        }
        // Write what is due, one chunk at the line's pace.
        if let Some((at, bytes)) = out.front_mut()
            && *at <= now
            && line_free_us <= now
        {
            let n = bytes.len().min(CHUNK);
            to_bridge
                .write_all(bytes.get(..n).unwrap_or_default())
                .await
                .map_err(|_| PeerError::Write)?;
            bytes.drain(..n);
            if bytes.is_empty() {
                out.pop_front();
            }
            line_free_us = now.saturating_add(byte_us.saturating_mul(n as u64));
            continue;
        }
        let next_out = out.front().map(|(at, _)| (*at).max(line_free_us));
        let next = [Some(peer.borrow().peer_next_wakeup()), next_out]
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
                peer.borrow_mut()
                    .peer_receive(now_us(), buf.get(..n).unwrap_or_default());
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
