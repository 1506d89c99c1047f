//! The deframer properties, for any framing: the same events whatever the chunking and
//! whichever way bytes go in (`push`, `feed` + `poll`, `spare_capacity_mut` +
//! `commit`), the same events as the capture [`Scanner`], the same frames as an
//! independent reference scan, consistent counters, and every frame passing the
//! protocol's checked parse.

use protocol_core::Error;
use protocol_core::wire::{Deframer, Event, Framing, Scanned, Scanner, Stats};

use crate::input::Plan;

/// An owned [`Event`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Ev {
    /// A frame.
    Frame(Vec<u8>),
    /// A rejected candidate.
    Rejected(Error, Vec<u8>),
    /// A frame the framing skips whole (MAVLink 1 on a MAVLink 2 link, a well-framed
    /// frame of an unknown id).
    Skipped(Vec<u8>),
}

impl Ev {
    fn of(event: Event<'_>) -> Ev {
        match event {
            Event::Frame(f) => Ev::Frame(f.to_vec()),
            Event::Rejected { error, raw } => Ev::Rejected(error, raw.to_vec()),
            Event::Skipped(f) => Ev::Skipped(f.to_vec()),
        }
    }

    /// The frame, if this is one.
    #[must_use]
    pub fn frame(&self) -> Option<&[u8]> {
        match self {
            Ev::Frame(f) => Some(f),
            Ev::Rejected(..) | Ev::Skipped(_) => None,
        }
    }
}

/// The events of `stream` pushed in the plan's pieces (whole with `None`), then
/// flushed, and the counters.
pub fn run_push<F: Framing, const N: usize>(
    framing: F,
    stream: &[u8],
    plan: Option<&Plan>,
) -> (Vec<Ev>, Stats) {
    let mut d = Deframer::<F, N>::new(framing);
    let mut out = Vec::new();
    match plan {
        Some(plan) => {
            for piece in plan.pieces(stream) {
                d.push(piece.bytes, |e| out.push(Ev::of(e)));
            }
        }
        None => d.push(stream, |e| out.push(Ev::of(e))),
    }
    d.flush(|e| out.push(Ev::of(e)));
    assert_eq!(d.buffered(), 0, "bytes left after flush");
    (out, d.stats())
}

/// The events of `stream` fed with [`Deframer::feed`] and drained with
/// [`Deframer::poll`], each with the stream offset of its first byte.
pub fn run_feed_poll<F: Framing, const N: usize>(
    framing: F,
    stream: &[u8],
    plan: &Plan,
) -> Vec<(usize, Ev)> {
    fn drain<F: Framing, const N: usize>(
        d: &mut Deframer<F, N>,
        fed: usize,
        out: &mut Vec<(usize, Ev)>,
        idle: bool,
    ) {
        loop {
            let event = if idle { d.poll_idle() } else { d.poll() };
            let Some(ev) = event.map(Ev::of) else { return };
            // The event's bytes are released from the buffer: a frame whole, a rejected
            // candidate by its first byte.
            let released = match &ev {
                Ev::Frame(f) | Ev::Skipped(f) => f.len(),
                Ev::Rejected(..) => 1,
            };
            let offset = fed - d.buffered() - released;
            out.push((offset, ev));
        }
    }
    let mut d = Deframer::<F, N>::new(framing);
    let mut out = Vec::new();
    let mut fed = 0;
    for piece in plan.pieces(stream) {
        let mut rest = piece.bytes;
        while !rest.is_empty() {
            let n = d.feed(rest);
            assert!(n > 0, "feed accepted nothing after the events were drained");
            fed += n;
            rest = &rest[n..];
            drain(&mut d, fed, &mut out, false);
            assert!(d.buffered() < N.max(1), "a full buffer yielded no event");
        }
    }
    drain(&mut d, fed, &mut out, true);
    assert_eq!(d.buffered(), 0, "bytes left after poll_idle");
    out
}

/// The events of a [`Scanner`] over the whole stream, with offsets (garbage left out; a
/// truncated tail is the deframer's idle rejection).
pub fn run_scanner<F: Framing>(framing: F, stream: &[u8]) -> Vec<(usize, Ev)> {
    let mut out = Vec::new();
    let mut next = 0;
    for item in Scanner::new(framing, stream) {
        // Each item's offset, how far scanning moves on, and the deframer's event.
        let (offset, advance, ev) = match item {
            Scanned::Frame { offset, bytes } => {
                (offset, bytes.len(), Some(Ev::Frame(bytes.to_vec())))
            }
            Scanned::Rejected {
                offset,
                bytes,
                error,
            } => (offset, 1, Some(Ev::Rejected(error, bytes.to_vec()))),
            Scanned::Truncated { offset, bytes } => (
                offset,
                1,
                Some(Ev::Rejected(Error::Truncated, bytes.to_vec())),
            ),
            Scanned::Skipped { offset, bytes } => {
                (offset, bytes.len(), Some(Ev::Skipped(bytes.to_vec())))
            }
            Scanned::Garbage { offset, bytes } => (offset, bytes.len(), None),
        };
        assert_eq!(offset, next, "scanner items are not contiguous");
        assert!(advance > 0, "the scanner did not move on");
        next = offset + advance;
        if let Some(ev) = ev {
            out.push((offset, ev));
        }
    }
    assert_eq!(next, stream.len(), "the scanner stopped early");
    out
}

/// Feeds the stream the way a UART/DMA driver does ([`Deframer::spare_capacity_mut`] +
/// [`Deframer::commit`]), going idle or clearing the deframer where the plan says, and
/// checks every frame with `checked`. Returns the frames.
pub fn run_driver<F: Framing, const N: usize>(
    framing: F,
    stream: &[u8],
    plan: &Plan,
    checked: &impl Fn(&[u8]),
) -> usize {
    let mut d = Deframer::<F, N>::new(framing);
    let mut frames = 0;
    let mut on_event = |e: Event<'_>| {
        if let Event::Frame(f) = e {
            checked(f);
            frames += 1;
        }
    };
    for piece in plan.pieces(stream) {
        let mut rest = piece.bytes;
        while !rest.is_empty() {
            let spare = d.spare_capacity_mut();
            let n = spare.len().min(rest.len());
            assert!(n > 0, "no spare capacity after the events were drained");
            spare[..n].copy_from_slice(&rest[..n]);
            d.commit(n);
            rest = &rest[n..];
            while let Some(e) = d.poll() {
                on_event(e);
            }
            assert!(d.buffered() <= N);
        }
        if piece.idle {
            while let Some(e) = d.poll_idle() {
                on_event(e);
            }
            assert_eq!(d.buffered(), 0, "bytes left after poll_idle");
        }
        if piece.clear {
            d.clear();
            assert_eq!(d.buffered(), 0);
        }
    }
    d.flush(on_event);
    assert_eq!(d.buffered(), 0);
    frames
}

/// How one framing is checked.
pub struct Spec<'a> {
    /// The reference scan's test: the length of the valid frame at the start of the
    /// bytes, if one is there (written without the deframer; it must know the buffer
    /// size limit).
    pub valid: &'a dyn Fn(&[u8]) -> Option<usize>,
    /// The reference scan's test for a frame the framing skips whole (MAVLink 1 on a
    /// MAVLink 2 link, a well-framed frame of an unknown id): its length, if one is at the
    /// start of the bytes (the rest of the stream).
    pub skipped: &'a dyn Fn(&[u8]) -> Option<usize>,
    /// The protocol's checked parse of a delivered frame (panics when it fails).
    pub checked: &'a dyn Fn(&[u8]),
    /// Whether the deframer's buffer holds the protocol's largest frame, so that the
    /// capture scanner (unbounded) must agree with it.
    pub compare_scanner: bool,
}

/// The reference scan: at each position take the frame `valid` finds there, else skip
/// the frame `skipped` finds there, else move on by one byte.
pub fn reference(
    stream: &[u8],
    valid: &dyn Fn(&[u8]) -> Option<usize>,
    skipped: &dyn Fn(&[u8]) -> Option<usize>,
) -> Vec<(usize, Vec<u8>)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < stream.len() {
        if let Some(n) = valid(&stream[i..]) {
            out.push((i, stream[i..i + n].to_vec()));
            i += n;
        } else if let Some(n) = skipped(&stream[i..]) {
            i += n;
        } else {
            i += 1;
        }
    }
    out
}

/// Every deframer property for one framing over one stream.
pub fn check<F: Framing + Clone, const N: usize>(
    framing: &F,
    stream: &[u8],
    plan: &Plan,
    spec: &Spec<'_>,
) {
    let (chunked, stats) = run_push::<F, N>(framing.clone(), stream, Some(plan));
    let (whole, whole_stats) = run_push::<F, N>(framing.clone(), stream, None);
    assert_eq!(chunked, whole, "the events depend on the chunking");
    assert_eq!(stats, whole_stats, "the counters depend on the chunking");

    let located = run_feed_poll::<F, N>(framing.clone(), stream, plan);
    let events: Vec<Ev> = located.iter().map(|(_, e)| e.clone()).collect();
    assert_eq!(events, chunked, "feed + poll differs from push");
    if spec.compare_scanner {
        assert_eq!(
            run_scanner(framing.clone(), stream),
            located,
            "the capture scanner and the deframer disagree"
        );
    }

    let frames: Vec<(usize, Vec<u8>)> = located
        .iter()
        .filter_map(|(o, e)| e.frame().map(|f| (*o, f.to_vec())))
        .collect();
    assert_eq!(
        frames,
        reference(stream, spec.valid, spec.skipped),
        "the deframer and the reference scan disagree"
    );
    for (offset, f) in &frames {
        assert_eq!(&stream[*offset..*offset + f.len()], &f[..]);
        (spec.checked)(f);
    }

    let skipped = chunked
        .iter()
        .filter(|e| matches!(e, Ev::Skipped(_)))
        .count();
    let rejected = chunked.len() - frames.len() - skipped;
    let framed: usize = frames.iter().map(|(_, f)| f.len()).sum();
    assert_eq!(stats.frames_ok as usize, frames.len());
    assert_eq!(
        (stats.frames_skipped + stats.frames_unknown) as usize,
        skipped
    );
    let skipped_bytes: usize = chunked
        .iter()
        .map(|e| match e {
            Ev::Skipped(f) => f.len(),
            _ => 0,
        })
        .sum();
    assert_eq!(stats.bytes_skipped as usize, skipped_bytes);
    assert_eq!(
        (stats.checksum_errors + stats.length_errors) as usize,
        rejected
    );
    assert_eq!(
        framed + stats.bytes_discarded as usize,
        stream.len(),
        "every byte is in a frame or discarded"
    );

    let driven = run_driver::<F, N>(framing.clone(), stream, plan, &spec.checked);
    if !plan_has_markers(plan, stream) {
        assert_eq!(driven, frames.len());
    }
}

/// Whether the plan goes idle or clears anywhere in the stream (which changes the
/// events: the driver run then checks only the frames it gets).
fn plan_has_markers(plan: &Plan, stream: &[u8]) -> bool {
    plan.pieces(stream).any(|p| p.idle || p.clear)
}
