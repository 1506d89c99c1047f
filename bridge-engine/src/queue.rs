//! A bounded queue of whole frames in a fixed byte buffer.
//!
//! Frames go in and come out whole: the caller takes one frame at a time
//! ([`FrameQueue::front`] + [`FrameQueue::pop`]) and writes all of it before taking the
//! next, so no frame is ever half-written. A frame is *critical* (time-sync frames, ACKs
//! the pod waits for) or not. When a frame does not fit, the oldest non-critical frames
//! are dropped to make room; a critical frame is never dropped to make room. A frame that
//! still does not fit is refused (counted by the caller).

/// Bytes of a record header: the frame length (bits 0..14) and the critical flag (bit 15).
const HEADER: usize = 2;
/// The critical flag of a record header.
const CRITICAL: u16 = 0x8000;

protocol_core::wire_derive! {
    custom_serde [Eq, Default]
    /// What a push did.
    pub struct Pushed {
        /// The frame was queued.
        pub queued: bool,
        /// Older non-critical frames dropped to make room.
        pub dropped: u8,
    }
}

/// A queue of frames in `N` bytes (each frame takes its length plus two bytes).
#[derive(Debug, Clone)]
pub struct FrameQueue<const N: usize> {
    buf: [u8; N],
    used: usize,
}

impl<const N: usize> Default for FrameQueue<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> FrameQueue<N> {
    /// An empty queue.
    #[must_use]
    pub const fn new() -> Self {
        FrameQueue {
            buf: [0; N],
            used: 0,
        }
    }

    /// True when no frame is queued.
    #[must_use]
    pub const fn is_empty(&self) -> bool {
        self.used == 0
    }

    /// Bytes in use (frames and their record headers).
    #[must_use]
    pub const fn used(&self) -> usize {
        self.used
    }

    /// Number of frames queued.
    #[must_use]
    pub fn len(&self) -> usize {
        self.records().count()
    }

    /// The record at `at`: (critical, frame length).
    fn record(&self, at: usize) -> Option<(bool, usize)> {
        let h = self.buf.get(at..at.checked_add(HEADER)?)?;
        let h = u16::from_le_bytes([*h.first()?, *h.get(1)?]);
        Some((h & CRITICAL != 0, usize::from(h & !CRITICAL)))
    }

    /// Offsets of the records, front first.
    fn records(&self) -> impl Iterator<Item = usize> + '_ {
        let mut at = 0usize;
        core::iter::from_fn(move || {
            if at >= self.used {
                return None;
            }
            let this = at;
            let (_, len) = self.record(at)?;
            at = at.checked_add(HEADER)?.checked_add(len)?;
            Some(this)
        })
    }

    /// The frame at the front, if any.
    #[must_use]
    pub fn front(&self) -> Option<&[u8]> {
        let (_, len) = self.record(0).filter(|_| self.used > 0)?;
        self.buf.get(HEADER..HEADER.checked_add(len)?)
    }

    /// Removes the frame at the front.
    pub fn pop(&mut self) {
        if let Some((_, len)) = self.record(0).filter(|_| self.used > 0) {
            self.remove(0, HEADER.saturating_add(len));
        }
    }

    /// Copies the front frame into `out` and removes it; returns its length. `None` when
    /// the queue is empty or `out` is too small (the frame then stays queued).
    pub fn pop_into(&mut self, out: &mut [u8]) -> Option<usize> {
        let frame = self.front()?;
        let n = frame.len();
        protocol_core::wire::copy(out.get_mut(..n)?, frame);
        self.pop();
        Some(n)
    }

    /// Drops every frame.
    pub fn clear(&mut self) {
        self.used = 0;
    }

    /// Queues `frame` at the back.
    pub fn push_back(&mut self, frame: &[u8], critical: bool) -> Pushed {
        self.push(frame, critical, false)
    }

    /// Queues `frame` at the front: it is the next frame taken.
    pub fn push_front(&mut self, frame: &[u8], critical: bool) -> Pushed {
        self.push(frame, critical, true)
    }

    fn push(&mut self, frame: &[u8], critical: bool, front: bool) -> Pushed {
        let mut pushed = Pushed::default();
        let Some(need) = HEADER
            .checked_add(frame.len())
            .filter(|&n| n <= N && frame.len() < usize::from(CRITICAL))
        else {
            return pushed;
        };
        while N.saturating_sub(self.used) < need {
            // The oldest non-critical frame goes first.
            let victim = self
                .records()
                .find(|&at| self.record(at).is_some_and(|(c, _)| !c));
            let Some(at) = victim else {
                return pushed;
            };
            let len = self.record(at).map_or(0, |(_, len)| len);
            self.remove(at, HEADER.saturating_add(len));
            pushed.dropped = pushed.dropped.saturating_add(1);
        }
        let at = if front { 0 } else { self.used };
        let end = self.used;
        protocol_core::wire::copy_within(&mut self.buf, at..end, at.saturating_add(need));
        // The length fits 15 bits (checked above).
        let header = u16::try_from(frame.len()).unwrap_or(0) | if critical { CRITICAL } else { 0 };
        if let Some(slot) = self.buf.get_mut(at..at.saturating_add(need)) {
            let (h, body) = slot.split_at_mut_checked(HEADER).unwrap_or_default();
            protocol_core::wire::copy(h, &header.to_le_bytes());
            protocol_core::wire::copy(body, frame);
        }
        self.used = self.used.saturating_add(need);
        pushed.queued = true;
        pushed
    }

    /// Removes `n` bytes at `at`.
    fn remove(&mut self, at: usize, n: usize) {
        let end = self.used;
        let from = at.saturating_add(n).min(end);
        protocol_core::wire::copy_within(&mut self.buf, from..end, at);
        self.used = self.used.saturating_sub(from.saturating_sub(at));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drain<const N: usize>(q: &mut FrameQueue<N>) -> Vec<Vec<u8>> {
        let mut out = vec![];
        while let Some(f) = q.front() {
            out.push(f.to_vec());
            q.pop();
        }
        out
    }

    #[test]
    fn frames_come_out_whole_in_order_and_front_first() {
        let mut q = FrameQueue::<32>::new();
        assert!(q.push_back(&[1, 2, 3], false).queued);
        assert!(q.push_back(&[4], false).queued);
        assert!(q.push_front(&[9, 9], true).queued);
        assert_eq!(q.len(), 3);
        assert_eq!(q.used(), 3 * 2 + 6);
        let mut buf = [0u8; 8];
        assert_eq!(q.pop_into(&mut buf), Some(2));
        assert_eq!(&buf[..2], &[9, 9]);
        assert_eq!(drain(&mut q), vec![vec![1, 2, 3], vec![4]]);
        assert!(q.is_empty());
        assert_eq!(q.pop_into(&mut buf), None);
    }

    #[test]
    fn full_queue_drops_the_oldest_non_critical_frames_only() {
        let mut q = FrameQueue::<16>::new();
        assert!(q.push_back(&[1; 4], true).queued); // 6 bytes, critical
        assert!(q.push_back(&[2; 2], false).queued); // 4
        assert!(q.push_back(&[3; 2], false).queued); // 4 -> 14 used
        let p = q.push_back(&[4; 4], false); // needs 6, 2 free: drops [2;2] only
        assert_eq!(
            p,
            Pushed {
                queued: true,
                dropped: 1
            }
        );
        let p = q.push_front(&[5; 6], true); // needs 8, 0 free: drops [3;2] and [4;4]
        assert_eq!(
            p,
            Pushed {
                queued: true,
                dropped: 2
            }
        );
        assert_eq!(drain(&mut q), vec![vec![5; 6], vec![1; 4]]);

        // Only critical frames left: a frame that does not fit is refused.
        let mut q = FrameQueue::<12>::new();
        assert!(q.push_back(&[1; 8], true).queued);
        let p = q.push_back(&[2; 4], false);
        assert_eq!(
            p,
            Pushed {
                queued: false,
                dropped: 0
            }
        );
        assert_eq!(drain(&mut q), vec![vec![1; 8]]);
        // Larger than the whole queue: refused at once.
        assert!(!q.push_back(&[0; 11], true).queued);
    }

    #[test]
    fn a_too_small_output_keeps_the_frame() {
        let mut q = FrameQueue::<16>::new();
        q.push_back(&[1, 2, 3], false);
        let mut small = [0u8; 2];
        assert_eq!(q.pop_into(&mut small), None);
        assert_eq!(q.front(), Some(&[1, 2, 3][..]));
    }
}
