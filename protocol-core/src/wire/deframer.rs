//! Finding frames in a byte stream.
//!
//! Every protocol describes its framing once, by implementing [`Framing`]: its sync
//! bytes, how many header bytes tell the total length, and how to check a complete
//! frame. Two scanners share one step function over that description:
//!
//! - [`Deframer`]: streaming and bounded (a const-generic buffer of `N` bytes), for
//!   firmware. Bytes go in with [`Deframer::push`] (a slice of any length) or with
//!   [`Deframer::feed`] + [`Deframer::poll`]; complete, checksum-valid frames come out.
//! - [`Scanner`]: over a complete capture held in memory, reporting frames, rejected
//!   candidates, garbage and a truncated tail with their offsets (the `gimbal` tool).
//!
//! Streaming input has no end, so a frame whose length field was corrupted to claim
//! more bytes keeps the deframer waiting; when the line goes idle (a UART idle
//! interrupt, a read timeout), call [`Deframer::poll_idle`] or [`Deframer::flush`] to
//! give up on the incomplete candidate and rescan what follows it.
//!
//! Resynchronisation: when a candidate frame fails (bad length field or bad checksum),
//! scanning resumes at the byte after the failed sync position, not after the claimed
//! frame. A false sync inside garbage, or a frame cut short by a following frame, can
//! therefore never hide a valid frame that starts inside the failed candidate.
//!
//! Frames whose checksum cannot be checked (a MAVLink message id outside the dialect:
//! its CRC_EXTRA is unknown, [`Framing::uncheckable`]) are **well framed** when the byte
//! right after them starts a frame, or the line went idle right after them, and no frame
//! that checks lies inside them: they are skipped whole ([`Event::Skipped`], counted in
//! [`Stats::frames_unknown`]), neither rejected nor garbage. Any other such candidate is
//! rejected like one with a bad checksum. The byte after a frame is waited for, so a
//! deframer needs one byte more than the protocol's largest frame to see it (a frame that
//! fills the buffer cannot be seen followed: it is rejected).

use crate::Error;

/// The framing rules of one protocol.
///
/// Implementations are small values (they may carry configuration, e.g. a maximum
/// payload length or a CRC coverage). The methods must not panic for any input.
pub trait Framing {
    /// The bytes every frame starts with (at least one).
    fn sync(&self) -> &[u8];

    /// How many bytes, sync included, are needed to know the total frame length.
    fn header_len(&self) -> usize;

    /// Total length of the frame whose first [`Framing::header_len`] bytes are `header`
    /// (sync included). An impossible length field is [`Error::BadLength`].
    /// The returned length must be at least `header_len()`.
    ///
    /// # Errors
    /// [`Error::BadLength`] for an impossible length field.
    fn frame_len(&self, header: &[u8]) -> Result<usize, Error>;

    /// Verifies a complete frame of the length [`Framing::frame_len`] gave (normally its
    /// checksum: [`Error::BadChecksum`]).
    ///
    /// # Errors
    /// Why the frame is not valid (normally [`Error::BadChecksum`]).
    fn check(&self, frame: &[u8]) -> Result<(), Error>;

    /// Whether `buf` (not empty) may be the start of a frame: by default, whether it
    /// starts with [`Framing::sync`] or a prefix of it. A framing with more than one
    /// start byte (MAVLink 2 and 1) overrides this.
    fn starts_like_frame(&self, buf: &[u8]) -> bool {
        starts_like_sync(buf, self.sync())
    }

    /// Whether a complete frame that passed [`Framing::check`] is one the framing
    /// recognises but does not deliver (a MAVLink 1 frame on a MAVLink 2 link): the
    /// deframer then consumes it whole as [`Event::Skipped`] and counts it in
    /// [`Stats::frames_skipped`]. By default, never.
    fn skip(&self, frame: &[u8]) -> bool {
        let _ = frame;
        false
    }

    /// Whether `frame`, which [`Framing::check`] failed with `error`, is a frame whose
    /// checksum cannot be checked (a MAVLink 2 message id outside the dialect, its header
    /// otherwise plausible). Such a candidate is skipped whole ([`Event::Skipped`],
    /// counted in [`Stats::frames_unknown`]) when it is well framed: the byte right after
    /// it starts a frame, or the line went idle right after it, and no frame that checks
    /// lies wholly inside it after its first byte; otherwise it is rejected like one with
    /// a bad checksum. The byte after it is waited for, so the deframer needs one byte
    /// more than the protocol's largest frame. By default, never.
    fn uncheckable(&self, frame: &[u8], error: &Error) -> bool {
        let _ = (frame, error);
        false
    }
}

/// The outcome of looking at the front of a buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Step {
    /// A valid frame of this length starts at the front.
    Frame(usize),
    /// A valid frame of this length that the framing does not deliver starts at the front.
    Skipped(usize),
    /// A well-framed frame of this length whose checksum cannot be checked starts at the
    /// front.
    Unknown(usize),
    /// The candidate at the front (this many bytes of it) failed.
    Rejected(Error, usize),
    /// This many bytes at the front cannot start a frame.
    Skip(usize),
    /// The front may be the start of a frame; more bytes are needed.
    NeedMore,
}

/// Does `buf` start with (a prefix of) `sync`?
fn starts_like_sync(buf: &[u8], sync: &[u8]) -> bool {
    buf.iter().zip(sync).all(|(a, b)| a == b)
}

/// Looks at the front of `buf`; frames longer than `capacity` are rejected. `idle`: no
/// byte follows `buf` for now (the line went idle, or the capture ends).
fn step<F: Framing + ?Sized>(framing: &F, buf: &[u8], capacity: usize, idle: bool) -> Step {
    let sync = framing.sync();
    if buf.is_empty() {
        return Step::NeedMore;
    }
    if sync.is_empty() || !framing.starts_like_frame(buf) {
        // The next position that could start a frame (possibly a partial sync at the end).
        let next = (1..buf.len())
            .find(|&i| {
                buf.get(i..)
                    .is_some_and(|tail| framing.starts_like_frame(tail))
            })
            .unwrap_or(buf.len());
        return Step::Skip(next.max(1));
    }
    let header_len = framing.header_len().max(sync.len());
    let Some(header) = buf.get(..header_len) else {
        return Step::NeedMore;
    };
    let len = match framing.frame_len(header) {
        Ok(len) if len < header_len || len > capacity => {
            return Step::Rejected(Error::BadLength, header_len);
        }
        Ok(len) => len,
        Err(e) => return Step::Rejected(e, header_len),
    };
    let Some(frame) = buf.get(..len) else {
        return Step::NeedMore;
    };
    match framing.check(frame) {
        Ok(()) if framing.skip(frame) => Step::Skipped(len),
        Ok(()) => Step::Frame(len),
        Err(e) if framing.uncheckable(frame, &e) => {
            let next = buf.get(len..).unwrap_or_default();
            let room = buf.len() < capacity;
            // Its following byte is waited for, if the buffer has room for it.
            if next.is_empty() && !idle && room {
                return Step::NeedMore;
            }
            if !(framing.starts_like_frame(next) || next.is_empty() && idle) {
                return Step::Rejected(e, len);
            }
            // An incomplete frame inside is waited for while the line runs and the buffer
            // has room; at idle it cannot complete; with the buffer full it cannot be ruled
            // out, and rescanning loses nothing.
            let found = inside(framing, buf, len, capacity);
            let incomplete = found == Inside::Incomplete && !idle;
            if incomplete && room {
                Step::NeedMore
            } else if incomplete || found == Inside::Checks {
                Step::Rejected(e, len)
            } else {
                Step::Unknown(len)
            }
        }
        Err(e) => Step::Rejected(e, len),
    }
}

/// What starts inside a candidate whose checksum cannot be checked, after its first byte.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Inside {
    /// No frame that checks.
    Nothing,
    /// A frame that checks (delivered or skipped), wholly inside the candidate or running
    /// past its end: the candidate is no frame but a false start, or a frame cut short.
    Checks,
    /// A candidate the framing would deliver whose bytes are not all buffered yet.
    Incomplete,
}

/// Looks for frames starting inside the first `len` bytes of `buf`, after the first
/// byte. A candidate the framing would deliver counts whether it ends inside or past
/// `len` (its bytes are waited for); one it would not deliver ([`Framing::skip`], judged
/// on its first byte) counts only when it ends inside: waiting for it could only find a
/// frame that is dropped anyway.
fn inside<F: Framing + ?Sized>(framing: &F, buf: &[u8], len: usize, capacity: usize) -> Inside {
    let header_len = framing.header_len().max(framing.sync().len());
    let mut found = Inside::Nothing;
    for i in 1..len {
        let Some(rest) = buf.get(i..) else {
            break;
        };
        if !framing.starts_like_frame(rest) {
            continue;
        }
        let delivered = !framing.skip(rest);
        let Some(header) = rest.get(..header_len) else {
            if delivered {
                found = Inside::Incomplete;
            }
            continue;
        };
        let Some(n) = framing
            .frame_len(header)
            .ok()
            .filter(|&n| n >= header_len && n <= capacity)
            .filter(|&n| delivered || i.saturating_add(n) <= len)
        else {
            continue;
        };
        match rest.get(..n) {
            Some(f) if framing.check(f).is_ok() => return Inside::Checks,
            Some(_) => {}
            None => found = Inside::Incomplete,
        }
    }
    found
}

/// What a [`Deframer`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Event<'a> {
    /// A complete frame whose length and checksum are valid, sync bytes to checksum.
    Frame(&'a [u8]),
    /// A complete, valid frame of a kind the framing recognises but does not deliver (a
    /// MAVLink 1 frame on a MAVLink 2 link, see [`Framing::skip`]), or a well-framed frame
    /// whose checksum cannot be checked ([`Framing::uncheckable`]), consumed whole.
    Skipped(&'a [u8]),
    /// A candidate that started with the sync bytes but failed: `raw` is the candidate
    /// (its header, or its full claimed length when the checksum failed). Its first byte
    /// is discarded and the rest is scanned again.
    Rejected {
        /// Why the candidate failed.
        error: Error,
        /// The candidate's bytes.
        raw: &'a [u8],
    },
}

wire_derive! {
    [Eq, Default]
    /// Counters kept by a [`Deframer`] (saturating).
    pub struct Stats {
        /// Valid frames delivered.
        pub frames_ok: u32,
        /// Valid frames recognised and skipped whole ([`Event::Skipped`]: MAVLink 1).
        pub frames_skipped: u32,
        /// Well-framed frames whose checksum cannot be checked, skipped whole
        /// ([`Event::Skipped`]: MAVLink message ids outside the dialect; see
        /// [`Framing::uncheckable`]).
        pub frames_unknown: u32,
        /// Candidates rejected for their checksum, or whose checksum cannot be checked and
        /// that are not well framed (a MAVLink message id outside the dialect:
        /// [`Error::UnknownId`]).
        pub checksum_errors: u32,
        /// Candidates rejected for an impossible length (or longer than the buffer), or
        /// left incomplete when the line went idle.
        pub length_errors: u32,
        /// Bytes that were not part of any delivered frame (skipped frames included).
        pub bytes_discarded: u32,
        /// The bytes of the frames skipped whole (part of `bytes_discarded`; the rest of
        /// it is garbage).
        pub bytes_skipped: u32,
    }
}

fn bump(counter: &mut u32, by: usize) {
    *counter = counter.saturating_add(u32::try_from(by).unwrap_or(u32::MAX));
}

/// A streaming, bounded frame finder for the protocol described by `F`.
///
/// `N` is the buffer size; it should be at least the protocol's largest frame (frames
/// longer than `N` are rejected as [`Error::BadLength`]). No byte is lost while the
/// caller drains events: [`Deframer::feed`] only accepts what fits, and a full buffer
/// always holds a complete candidate.
///
/// Three ways in, all giving the same events in the same order:
/// - [`Deframer::push`]: a slice of any length.
/// - [`Deframer::feed`] + [`Deframer::poll`]: copy what fits, then drain events.
/// - [`Deframer::spare_capacity_mut`] + [`Deframer::commit`] + [`Deframer::poll`]: a
///   UART or DMA driver writes received bytes straight into the deframer's buffer.
///
/// The buffer is read through a moving start index; bytes are moved to the front only
/// when the free space at the end has become smaller than the space already consumed.
///
/// ```
/// use protocol_core::wire::{Deframer, Event, Framing};
/// # struct Demo;
/// # impl Framing for Demo {
/// #     fn sync(&self) -> &[u8] { &[0xAA] }
/// #     fn header_len(&self) -> usize { 2 }
/// #     fn frame_len(&self, h: &[u8]) -> Result<usize, protocol_core::Error> {
/// #         Ok(2 + usize::from(h[1]))
/// #     }
/// #     fn check(&self, _: &[u8]) -> Result<(), protocol_core::Error> { Ok(()) }
/// # }
/// let mut d = Deframer::<_, 64>::new(Demo);
/// let mut frames = 0;
/// d.push(&[0x00, 0xAA, 0x01, 0x42, 0xAA], |ev| {
///     if let Event::Frame(f) = ev {
///         assert_eq!(f, &[0xAA, 0x01, 0x42]);
///         frames += 1;
///     }
/// });
/// assert_eq!(frames, 1);
/// assert_eq!(d.stats().bytes_discarded, 1);
/// assert_eq!(d.buffered(), 1); // the trailing 0xAA may start the next frame
///
/// // A driver receiving straight into the buffer:
/// let spare = d.spare_capacity_mut();
/// spare[..2].copy_from_slice(&[0x00, 0x07]);
/// d.commit(2);
/// assert_eq!(d.poll(), Some(Event::Frame(&[0xAA, 0x00])));
/// ```
#[derive(Debug, Clone)]
pub struct Deframer<F, const N: usize> {
    framing: F,
    buf: [u8; N],
    /// First byte not yet consumed.
    start: usize,
    /// One past the last byte received.
    end: usize,
    /// Bytes after `start` to consume before the next step (the event last returned).
    release: usize,
    stats: Stats,
}

impl<F: Framing, const N: usize> Deframer<F, N> {
    /// An empty deframer.
    pub const fn new(framing: F) -> Self {
        Deframer {
            framing,
            buf: [0; N],
            start: 0,
            end: 0,
            release: 0,
            stats: Stats {
                frames_ok: 0,
                frames_skipped: 0,
                frames_unknown: 0,
                checksum_errors: 0,
                length_errors: 0,
                bytes_discarded: 0,
                bytes_skipped: 0,
            },
        }
    }

    /// The framing rules in use.
    pub const fn framing(&self) -> &F {
        &self.framing
    }

    /// Mutable access to the framing rules (e.g. to change a configured coverage).
    pub fn framing_mut(&mut self) -> &mut F {
        &mut self.framing
    }

    /// The counters so far.
    pub const fn stats(&self) -> Stats {
        self.stats
    }

    /// Bytes held, waiting for the rest of a frame.
    pub const fn buffered(&self) -> usize {
        self.end
            .saturating_sub(self.start)
            .saturating_sub(self.release)
    }

    /// Drops every buffered byte (counted as discarded) and keeps the counters.
    pub fn clear(&mut self) {
        let held = self.buffered();
        bump(&mut self.stats.bytes_discarded, held);
        self.start = 0;
        self.end = 0;
        self.release = 0;
    }

    /// Consumes the bytes of the event last returned.
    fn apply_release(&mut self) {
        let release = core::mem::take(&mut self.release);
        self.start = self.start.saturating_add(release).min(self.end);
        if self.start == self.end {
            self.start = 0;
            self.end = 0;
        }
    }

    /// The free space at the end of the buffer, for a driver to receive into; call
    /// [`Deframer::commit`] with the number of bytes written. Bytes already buffered are
    /// moved to the front first when that gives more room than it costs (the free space
    /// at the end is smaller than the consumed space at the front). Empty only when the
    /// buffer holds `N` bytes of one incomplete candidate, which cannot happen while
    /// events are drained with [`Deframer::poll`] (a full buffer always yields one).
    pub fn spare_capacity_mut(&mut self) -> &mut [u8] {
        self.apply_release();
        if self.start > N.saturating_sub(self.end) {
            self.move_to_front();
        }
        self.buf.get_mut(self.end..).unwrap_or_default()
    }

    /// Moves the held bytes to the front of the buffer, in pieces of at most `start`
    /// bytes so that each piece's source and destination are disjoint (a `memcpy` each;
    /// one piece unless more is held than was consumed). `copy_within` would do it in one
    /// call but keeps a panicking bounds check at opt-level z.
    fn move_to_front(&mut self) {
        let step = self.start;
        let (mut from, mut to) = (self.start, 0);
        while from < self.end && step > 0 {
            let Some((head, tail)) = self.buf.split_at_mut_checked(from) else {
                break;
            };
            let n = self.end.saturating_sub(from).min(step);
            super::copy(
                head.get_mut(to..).unwrap_or_default(),
                tail.get(..n).unwrap_or_default(),
            );
            from = from.saturating_add(n);
            to = to.saturating_add(n);
        }
        self.end = self.end.saturating_sub(self.start);
        self.start = 0;
    }

    /// Marks `n` bytes written into [`Deframer::spare_capacity_mut`] as received (at
    /// most the spare capacity). Then call [`Deframer::poll`] until it returns `None`.
    pub fn commit(&mut self, n: usize) {
        self.end = self.end.saturating_add(n).min(N);
    }

    /// Copies as many bytes of `input` as fit into the buffer and returns how many.
    /// Call [`Deframer::poll`] until it returns `None`, then feed the rest.
    pub fn feed(&mut self, input: &[u8]) -> usize {
        let spare = self.spare_capacity_mut();
        let n = spare.len().min(input.len());
        if let (Some(dst), Some(src)) = (spare.get_mut(..n), input.get(..n)) {
            super::copy(dst, src);
        }
        self.commit(n);
        n
    }

    /// The next event from the buffered bytes, or `None` when more bytes are needed.
    /// The returned frame stays valid until the next call on the deframer.
    pub fn poll(&mut self) -> Option<Event<'_>> {
        self.next_event(false).map(|(event, _)| event)
    }

    /// Like [`Deframer::poll`], for when the line has gone idle (e.g. a UART idle
    /// interrupt or a read timeout): the buffered bytes will not be completed, so an
    /// incomplete candidate at the front is rejected ([`Error::Truncated`]) and the bytes
    /// after its sync are scanned again. Without this, a corrupted length field that
    /// claims a longer frame holds back the valid frames behind it until enough further
    /// bytes arrive. Returns `None` once the buffer is empty.
    pub fn poll_idle(&mut self) -> Option<Event<'_>> {
        self.next_event(true).map(|(event, _)| event)
    }

    /// The next event and the number of bytes held behind the bytes it covers.
    fn next_event(&mut self, idle: bool) -> Option<(Event<'_>, usize)> {
        self.apply_release();
        let reported = loop {
            let held = self.end.saturating_sub(self.start);
            let window = self.buf.get(self.start..self.end).unwrap_or_default();
            match step(&self.framing, window, N, idle) {
                Step::NeedMore if held == 0 => return None,
                Step::NeedMore if idle => break Step::Rejected(Error::Truncated, held),
                Step::NeedMore if held < N => return None,
                // Only possible if N is smaller than the header: never stall.
                Step::NeedMore => self.skip(1),
                Step::Skip(n) => self.skip(n),
                other => break other,
            }
        };
        let window = self.buf.get(self.start..self.end).unwrap_or_default();
        let behind = |n: usize| window.len().saturating_sub(n);
        match reported {
            Step::Rejected(error, n) => {
                match error {
                    Error::BadChecksum { .. } | Error::UnknownId => {
                        bump(&mut self.stats.checksum_errors, 1);
                    }
                    _ => bump(&mut self.stats.length_errors, 1),
                }
                bump(&mut self.stats.bytes_discarded, 1);
                self.release = 1;
                let raw = window.get(..n).unwrap_or(window);
                Some((Event::Rejected { error, raw }, behind(n)))
            }
            Step::Frame(n) => {
                bump(&mut self.stats.frames_ok, 1);
                self.release = n;
                Some((Event::Frame(window.get(..n).unwrap_or(window)), behind(n)))
            }
            Step::Skipped(n) | Step::Unknown(n) => {
                let counter = match reported {
                    Step::Unknown(_) => &mut self.stats.frames_unknown,
                    _ => &mut self.stats.frames_skipped,
                };
                bump(counter, 1);
                bump(&mut self.stats.bytes_discarded, n);
                bump(&mut self.stats.bytes_skipped, n);
                self.release = n;
                Some((Event::Skipped(window.get(..n).unwrap_or(window)), behind(n)))
            }
            Step::NeedMore | Step::Skip(_) => None,
        }
    }

    /// Discards `n` bytes that cannot start a frame.
    fn skip(&mut self, n: usize) {
        bump(&mut self.stats.bytes_discarded, n);
        self.release = n;
        self.apply_release();
    }

    /// The line is idle: delivers every frame still hidden in the buffer (see
    /// [`Deframer::poll_idle`]) and empties it.
    pub fn flush(&mut self, mut sink: impl FnMut(Event<'_>)) {
        while let Some(event) = self.poll_idle() {
            sink(event);
        }
    }

    /// Feeds all of `input` and hands every resulting event to `sink`, in stream order.
    pub fn push(&mut self, input: &[u8], mut sink: impl FnMut(Event<'_>)) {
        self.push_counting_after(input, |event, _| sink(event));
    }

    /// [`Deframer::push`], also telling `sink` with each event how many bytes of the
    /// stream came after the bytes it covers, up to the end of `input` (those held
    /// behind it and the rest of `input`). A frame's own bytes and these are the serial
    /// time between its first byte and the last byte of `input`, at the line's rate:
    /// what a receiver that stamps `input` with the arrival of its last byte needs to
    /// time the frame's start, whatever came before it.
    pub fn push_counting_after(
        &mut self,
        mut input: &[u8],
        mut sink: impl FnMut(Event<'_>, usize),
    ) {
        loop {
            let n = self.feed(input);
            input = input.get(n..).unwrap_or_default();
            while let Some((event, behind)) = self.next_event(false) {
                sink(event, behind.saturating_add(input.len()));
            }
            if input.is_empty() {
                return;
            }
        }
    }
}

/// One item found by a [`Scanner`], with its offset in the capture.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scanned<'a> {
    /// A complete, valid frame.
    Frame {
        /// Offset of its first sync byte.
        offset: usize,
        /// The frame, sync bytes to checksum.
        bytes: &'a [u8],
    },
    /// A candidate that failed; scanning resumed at `offset + 1`.
    Rejected {
        /// Offset of its first sync byte.
        offset: usize,
        /// The candidate's bytes (header only for a bad length).
        bytes: &'a [u8],
        /// Why it failed.
        error: Error,
    },
    /// A valid frame the framing does not deliver, or a well-framed one whose checksum
    /// cannot be checked ([`Event::Skipped`]).
    Skipped {
        /// Offset of its first sync byte.
        offset: usize,
        /// The frame.
        bytes: &'a [u8],
    },
    /// Bytes that cannot start a frame.
    Garbage {
        /// Offset of the first byte.
        offset: usize,
        /// The bytes skipped.
        bytes: &'a [u8],
    },
    /// The capture ends inside a candidate frame; scanning resumed at `offset + 1`.
    Truncated {
        /// Offset of its first sync byte.
        offset: usize,
        /// The bytes present.
        bytes: &'a [u8],
    },
}

/// Iterates over the frames, rejected candidates and garbage of a complete capture.
///
/// Uses the same rules as [`Deframer`]; consecutive garbage bytes are reported as one
/// item.
#[derive(Debug, Clone)]
pub struct Scanner<'a, F> {
    framing: F,
    data: &'a [u8],
    pos: usize,
}

impl<'a, F: Framing> Scanner<'a, F> {
    /// A scanner over `data` from its first byte.
    pub const fn new(framing: F, data: &'a [u8]) -> Self {
        Scanner {
            framing,
            data,
            pos: 0,
        }
    }
}

impl<'a, F: Framing> Iterator for Scanner<'a, F> {
    type Item = Scanned<'a>;

    fn next(&mut self) -> Option<Scanned<'a>> {
        let offset = self.pos;
        let rest = self.data.get(offset..).filter(|r| !r.is_empty())?;
        let (item, advance) = match step(&self.framing, rest, usize::MAX, true) {
            Step::Frame(n) => (
                Scanned::Frame {
                    offset,
                    bytes: rest.get(..n)?,
                },
                n,
            ),
            Step::Skipped(n) | Step::Unknown(n) => (
                Scanned::Skipped {
                    offset,
                    bytes: rest.get(..n)?,
                },
                n,
            ),
            Step::Rejected(error, n) => {
                let bytes = rest.get(..n)?;
                (
                    Scanned::Rejected {
                        offset,
                        bytes,
                        error,
                    },
                    1,
                )
            }
            Step::Skip(n) => (
                Scanned::Garbage {
                    offset,
                    bytes: rest.get(..n)?,
                },
                n,
            ),
            // The capture ends inside a candidate: report it, then rescan after its sync
            // (a false length may be hiding frames).
            Step::NeedMore => (
                Scanned::Truncated {
                    offset,
                    bytes: rest,
                },
                1,
            ),
        };
        self.pos = offset.saturating_add(advance);
        Some(item)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A toy framing: `AA 55 LEN PAYLOAD SUM`, SUM = wrapping sum of the payload.
    struct Toy;
    impl Framing for Toy {
        fn sync(&self) -> &[u8] {
            &[0xAA, 0x55]
        }
        fn header_len(&self) -> usize {
            3
        }
        fn frame_len(&self, h: &[u8]) -> Result<usize, Error> {
            match h.get(2) {
                Some(&l) if l <= 8 => Ok(4 + usize::from(l)),
                _ => Err(Error::BadLength),
            }
        }
        fn check(&self, f: &[u8]) -> Result<(), Error> {
            let (body, sum) = f.split_at(f.len() - 1);
            let computed = crate::wire::sum8(&body[3..]);
            if computed == sum[0] {
                Ok(())
            } else {
                Err(Error::BadChecksum {
                    computed: computed.into(),
                    received: sum[0].into(),
                })
            }
        }
    }

    fn frames_of<const N: usize>(d: &mut Deframer<Toy, N>, input: &[u8]) -> usize {
        let mut n = 0;
        d.push(input, |e| n += usize::from(matches!(e, Event::Frame(_))));
        n
    }

    #[test]
    fn frame_inside_a_false_sync_is_found() {
        // A false sync claims 8 bytes and swallows the start of a real frame.
        let real = [0xAA, 0x55, 0x01, 0x07, 0x07];
        let mut input = vec![0xAA, 0x55, 0x08, 0x00];
        input.extend_from_slice(&real);
        input.extend_from_slice(&[0, 0, 0]);
        let mut d = Deframer::<Toy, 16>::new(Toy);
        let found: usize = input.chunks(1).map(|c| frames_of(&mut d, c)).sum();
        assert_eq!(found, 1);
        let mut d = Deframer::<Toy, 16>::new(Toy);
        let mut seen = vec![];
        d.push(&input, |e| match e {
            Event::Frame(f) => seen.push(f.to_vec()),
            Event::Rejected { error, .. } => {
                assert!(matches!(error, Error::BadChecksum { .. }));
            }
            Event::Skipped(_) => panic!("the toy framing skips nothing"),
        });
        assert_eq!(seen, vec![real.to_vec()]);
        assert_eq!(d.stats().checksum_errors, 1);
        assert_eq!(d.stats().bytes_discarded, 4 + 3);
    }

    #[test]
    fn byte_by_byte_equals_all_at_once() {
        let input = [
            0x01, 0xAA, 0x55, 0x00, 0x00, 0xAA, 0xAA, 0x55, 0x02, 1, 2, 3, 0xAA,
        ];
        let mut whole = Deframer::<Toy, 12>::new(Toy);
        let mut a = vec![];
        whole.push(&input, |e| a.push(format!("{e:?}")));
        let mut bytes = Deframer::<Toy, 12>::new(Toy);
        let mut b = vec![];
        for byte in input {
            bytes.push(&[byte], |e| b.push(format!("{e:?}")));
        }
        assert_eq!(a, b);
        assert_eq!(whole.stats(), bytes.stats());
        assert_eq!(whole.stats().frames_ok, 2);
        assert_eq!(whole.buffered(), 1);
    }

    #[test]
    fn each_frame_is_told_the_bytes_that_came_after_it() {
        // Garbage, two frames and the start of a third in one input, through a buffer
        // smaller than the input (fed in two parts); then the third completed.
        let a = [0xAA, 0x55, 0x01, 0x07, 0x07];
        let b = [0xAA, 0x55, 0x02, 0x01, 0x02, 0x03];
        let mut input = vec![0x00, 0x11];
        input.extend_from_slice(&a);
        input.extend_from_slice(&b);
        input.extend_from_slice(&[0xAA, 0x55, 0x00]);
        let mut d = Deframer::<Toy, 8>::new(Toy);
        let mut seen = vec![];
        d.push_counting_after(&input, |e, after| {
            if let Event::Frame(f) = e {
                seen.push((f.to_vec(), after));
            }
        });
        assert_eq!(seen, vec![(a.to_vec(), 6 + 3), (b.to_vec(), 3)]);
        seen.clear();
        d.push_counting_after(&[0x00, 0x99], |e, after| {
            if let Event::Frame(f) = e {
                seen.push((f.to_vec(), after));
            }
        });
        assert_eq!(seen, vec![(vec![0xAA, 0x55, 0x00, 0x00], 1)]);
    }

    #[test]
    fn bad_length_and_small_buffer_never_stall() {
        let mut d = Deframer::<Toy, 4>::new(Toy);
        // LEN 9 is invalid; LEN 2 needs 6 bytes > N = 4.
        let n = frames_of(
            &mut d,
            &[
                0xAA, 0x55, 0x09, 0xAA, 0x55, 0x02, 0, 0, 0, 0xAA, 0x55, 0x00, 0x00,
            ],
        );
        assert_eq!(n, 1);
        assert_eq!(d.stats().length_errors, 2);
        assert_eq!(d.buffered(), 0);
    }

    #[test]
    fn idle_flush_finds_a_frame_behind_a_false_length() {
        // The first candidate claims 8 payload bytes; only a 5-byte frame follows.
        let input = [0xAA, 0x55, 0x08, 0xAA, 0x55, 0x01, 0x07, 0x07];
        let mut d = Deframer::<Toy, 16>::new(Toy);
        assert_eq!(frames_of(&mut d, &input), 0);
        assert_eq!(d.buffered(), input.len());
        let mut frames = vec![];
        d.flush(|e| {
            if let Event::Frame(f) = e {
                frames.push(f.to_vec());
            }
        });
        assert_eq!(frames, vec![input[3..].to_vec()]);
        assert_eq!(d.buffered(), 0);
        assert_eq!(d.stats().length_errors, 1);
    }

    #[test]
    fn scanner_reports_offsets() {
        let data = [0x00, 0x01, 0xAA, 0x55, 0x00, 0x00, 0xAA, 0x55, 0x03, 0x01];
        let items: Vec<_> = Scanner::new(Toy, &data).collect();
        assert_eq!(
            items,
            vec![
                Scanned::Garbage {
                    offset: 0,
                    bytes: &data[..2]
                },
                Scanned::Frame {
                    offset: 2,
                    bytes: &data[2..6]
                },
                Scanned::Truncated {
                    offset: 6,
                    bytes: &data[6..]
                },
                Scanned::Garbage {
                    offset: 7,
                    bytes: &data[7..]
                },
            ]
        );
    }
}
