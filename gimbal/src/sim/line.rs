//! A serial line in one direction, in simulated time: bytes written at an instant
//! leave one after the other (10 bits each at the baud rate: 8N1), after the bytes
//! already on their way, and are delivered to the receiver in chunks, as a UART with a
//! small receive FIFO and an idle interrupt delivers them.
//!
//! A line can be faulty ([`Line::damage`]): a [`super::faults::Corrupter`] changes each
//! write as it goes on the line, and a [`super::faults::Faults`] model flips bits, loses
//! bytes and inserts garbage after it, reproducibly (see [`super::faults`]).

use std::collections::VecDeque;

use super::faults::Damage;

/// Bytes a receiver is handed at most at once (a UART FIFO / DMA half-buffer).
pub const CHUNK: usize = 16;

/// One direction of a serial link.
#[derive(Debug)]
pub struct Line {
    baud: u32,
    /// When the transmitter is free again.
    busy_until_us: u64,
    /// Bytes on their way: (arrival of the byte's stop bit, byte).
    in_flight: VecDeque<(u64, u8)>,
    /// Arrival of the last byte delivered, while an idle event is owed.
    idle_owed_from: Option<u64>,
    /// Bytes written so far.
    pub bytes_sent: u64,
    /// What the line does to the bytes as they are written (nothing by default).
    pub damage: Damage,
}

impl Line {
    /// An idle line at `baud`.
    #[must_use]
    pub fn new(baud: u32) -> Self {
        Line {
            baud,
            busy_until_us: 0,
            in_flight: VecDeque::new(),
            idle_owed_from: None,
            bytes_sent: 0,
            damage: Damage::default(),
        }
    }

    /// Microseconds one byte takes (rounded).
    #[must_use]
    pub fn byte_us(&self) -> u64 {
        (10_000_000 + u64::from(self.baud) / 2) / u64::from(self.baud.max(1))
    }

    /// Writes `bytes` at `at_us` (or when the line is free).
    pub fn send(&mut self, at_us: u64, bytes: &[u8]) {
        let bytes = self.damage.apply(at_us, bytes);
        let per = self.byte_us();
        let mut t = at_us.max(self.busy_until_us);
        for b in bytes {
            t += per;
            self.in_flight.push_back((t, b));
            self.bytes_sent += 1;
        }
        self.busy_until_us = t;
    }

    /// The transmitter is busy until then.
    #[must_use]
    pub fn busy_until(&self) -> u64 {
        self.busy_until_us
    }

    /// When the receiver is next handed something: the end of the next chunk, or the
    /// idle event owed after the last delivered byte.
    #[must_use]
    pub fn next_event(&self) -> Option<u64> {
        let chunk = self.chunk_end();
        let idle = self.idle_owed_from.map(|t| t + 2 * self.byte_us());
        match (chunk, idle) {
            (Some(c), Some(i)) => Some(c.min(i)),
            (c, i) => c.or(i),
        }
    }

    /// Arrival of the last byte of the next chunk: up to [`CHUNK`] bytes that follow each
    /// other without a gap.
    fn chunk_end(&self) -> Option<u64> {
        let per = self.byte_us();
        let mut end = None;
        let mut prev: Option<u64> = None;
        for (i, &(t, _)) in self.in_flight.iter().enumerate() {
            if i >= CHUNK || prev.is_some_and(|p| t > p + per) {
                break;
            }
            end = Some(t);
            prev = Some(t);
        }
        end
    }

    /// The bytes delivered at `now_us` (those of the chunks that ended by then), and
    /// whether the line went idle (no byte for two byte times after the last delivered
    /// one).
    pub fn deliver(&mut self, now_us: u64) -> (Vec<u8>, bool) {
        let mut out = Vec::new();
        while let Some(end) = self.chunk_end().filter(|&e| e <= now_us) {
            while let Some(&(t, b)) = self.in_flight.front() {
                if t > end {
                    break;
                }
                out.push(b);
                self.in_flight.pop_front();
            }
            self.idle_owed_from = Some(end);
        }
        let idle = match self.idle_owed_from {
            Some(last) if now_us >= last + 2 * self.byte_us() => {
                // Bytes already arriving within the idle window keep the line busy.
                self.idle_owed_from = None;
                self.in_flight
                    .front()
                    .is_none_or(|&(t, _)| t > last + 2 * self.byte_us())
            }
            _ => false,
        };
        (out, idle)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::faults::Faults;

    #[test]
    fn bytes_arrive_after_their_serial_time_in_chunks_then_idle() {
        let mut l = Line::new(115_200);
        assert_eq!(l.byte_us(), 87);
        l.send(1_000, &[1; 20]);
        assert_eq!(l.busy_until(), 1_000 + 20 * 87);
        assert_eq!(l.next_event(), Some(1_000 + 16 * 87));
        let (b, idle) = l.deliver(1_000 + 16 * 87);
        assert_eq!((b.len(), idle), (16, false));
        assert_eq!(l.next_event(), Some(1_000 + 18 * 87), "idle owed");
        // The next bytes were already arriving: no idle.
        assert_eq!(l.deliver(1_000 + 18 * 87), (vec![], false));
        assert_eq!(l.next_event(), Some(1_000 + 20 * 87));
        let (b, idle) = l.deliver(1_000 + 20 * 87);
        assert_eq!((b.len(), idle), (4, false));
        let (b, idle) = l.deliver(1_000 + 22 * 87);
        assert_eq!((b.len(), idle), (0, true));
        assert_eq!(l.next_event(), None);
        // A write while busy waits for the line.
        l.send(0, &[2; 2]);
        assert_eq!(l.busy_until(), 1_000 + 22 * 87);
    }

    #[test]
    fn a_faulty_line_loses_and_changes_bytes_reproducibly() {
        let faults = Faults {
            bit_error_rate: 1e-2,
            drop_rate: 1e-2,
            garbage_rate: 0.0,
            seed: 5,
        };
        let data: Vec<u8> = (0..=255).cycle().take(20_000).collect();
        let run = || {
            let mut l = Line::new(1_000_000);
            l.damage.set_faults(Some(faults));
            for (i, chunk) in data.chunks(100).enumerate() {
                l.send(i as u64 * 10_000, chunk);
            }
            let (bytes, _) = l.deliver(u64::MAX / 2);
            (bytes, l.damage.fault_stats().unwrap())
        };
        let (a, stats) = run();
        assert_eq!(run().0, a, "same seed, same faults");
        assert_eq!(a.len() as u64, 20_000 - stats.bytes_dropped);
        assert!((150..=250).contains(&stats.bytes_dropped), "{stats:?}");
        assert!((1_300..=1_900).contains(&stats.bits_flipped), "{stats:?}");
        let mut l = Line::new(1_000_000);
        l.damage.set_faults(Some(Faults::NONE));
        assert_eq!(l.damage.fault_stats(), None, "no rates: no stage");
    }
}
