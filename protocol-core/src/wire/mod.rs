//! Codec machinery shared by the four protocols: bounds-checked cursors, checksums, field
//! encodings, the message-table generator and its traits, and the streaming deframer.

mod checksum;
mod cursor;
mod deframer;
#[cfg(any(
    feature = "k40t",
    feature = "siyi",
    feature = "viewlink",
    feature = "gcu"
))]
pub mod encoding;
#[cfg(any(
    feature = "k40t",
    feature = "siyi",
    feature = "viewlink",
    feature = "gcu"
))]
#[macro_use]
pub(crate) mod table;

pub use checksum::{MCRF4XX, XMODEM, crc16_mcrf4xx, crc16_xmodem, sum8, xor8};

/// Copies `src` into `dst` (slices of equal length; with unequal ones, the shorter
/// length), like `dst.copy_from_slice(src)` without its panicking path: at opt-level z
/// `copy_from_slice` stays out of line with its length check, and the link-time
/// no-panic check (`host-tests/no-panic`) would fail. Sixteen elements at a time as
/// array moves (a plain element loop is not turned into a `memcpy` at opt-level z:
/// this halves the deframer's copying cost), then the rest one by one.
pub fn copy<T: Copy>(dst: &mut [T], src: &[T]) {
    let n = dst.len().min(src.len());
    let (Some(dst), Some(src)) = (dst.get_mut(..n), src.get(..n)) else {
        return;
    };
    let mut to = dst.chunks_exact_mut(16);
    let mut from = src.chunks_exact(16);
    for (d, s) in (&mut to).zip(&mut from) {
        if let (Ok(d), Ok(s)) = (<&mut [T; 16]>::try_from(d), <&[T; 16]>::try_from(s)) {
            *d = *s;
        }
    }
    for (d, s) in to.into_remainder().iter_mut().zip(from.remainder()) {
        *d = *s;
    }
}
pub use cursor::{Reader, Writer};
pub use deframer::{Deframer, Event, Framing, Scanned, Scanner, Stats};
#[cfg(any(
    feature = "k40t",
    feature = "siyi",
    feature = "viewlink",
    feature = "gcu"
))]
pub use table::{MessageData, Protocol};

/// Moves `buf[src]` to start at `dest`, like `buf.copy_within(src, dest)` without its
/// panicking path (it stays out of line at opt-level z; see [`copy`]): parts out of
/// range are not copied. In pieces whose source and destination are disjoint (a
/// `memcpy` each), front first when moving left, back first when moving right.
pub fn copy_within(buf: &mut [u8], src: core::ops::Range<usize>, dest: usize) {
    if dest <= src.start {
        let step = src.start.saturating_sub(dest);
        let (mut from, mut to) = (src.start, dest);
        while from < src.end && step > 0 {
            let Some((head, tail)) = buf.split_at_mut_checked(from) else {
                return;
            };
            let n = src.end.saturating_sub(from).min(step);
            copy(
                head.get_mut(to..).unwrap_or_default(),
                tail.get(..n).unwrap_or_default(),
            );
            from = from.saturating_add(n);
            to = to.saturating_add(n);
        }
    } else {
        let step = dest.saturating_sub(src.start);
        let mut end = src.end;
        while end > src.start {
            let n = end.saturating_sub(src.start).min(step);
            let from = end.saturating_sub(n);
            // `from + step >= end`: the destination piece lies after the source piece.
            let Some((head, tail)) = buf.split_at_mut_checked(from.saturating_add(step)) else {
                return;
            };
            copy(
                tail.get_mut(..n).unwrap_or_default(),
                head.get(from..end).unwrap_or_default(),
            );
            end = from;
        }
    }
}

#[cfg(test)]
mod tests {
    /// `copy_within` does what `<[u8]>::copy_within` does, for every in-range move of a
    /// 12-byte buffer, overlapping or not, either way.
    #[test]
    fn copy_within_matches_core() {
        let start: Vec<u8> = (1..=12).collect();
        for a in 0..=12 {
            for b in a..=12 {
                for dest in 0..=12 - (b - a) {
                    let mut ours = start.clone();
                    let mut core = start.clone();
                    super::copy_within(&mut ours, a..b, dest);
                    core.copy_within(a..b, dest);
                    assert_eq!(ours, core, "{a}..{b} to {dest}");
                }
            }
        }
    }
}
