//! The Viewlink serial frame: `55 AA DC LEN ID DATA XOR`.
//!
//! LEN bits 0..5 count the bytes from LEN through the checksum (4..=63); bits 6..7 are
//! a frame counter. The checksum is the XOR of LEN (counter bits included) through the
//! last data byte.

use super::Header;
use crate::wire::{Framing, xor8};
use crate::{Error, Result};

/// The sync bytes of section 2.1.
pub const SYNC: [u8; 3] = [0x55, 0xAA, 0xDC];
/// The sync bytes as the document prints its ACK example (first two swapped).
pub const SYNC_SWAPPED: [u8; 3] = [0xAA, 0x55, 0xDC];
/// Bytes before the payload (sync, LEN, frame id).
pub const HEADER_LEN: usize = 5;
/// Smallest body length (LEN, id, one data byte, checksum).
pub const MIN_BODY_LEN: usize = 4;
/// Largest body length (6 bits).
pub const MAX_BODY_LEN: usize = 63;
/// Most payload (data) bytes in a frame.
pub const MAX_PAYLOAD_LEN: usize = MAX_BODY_LEN - 3;
/// Largest frame, sync to checksum.
pub const MAX_FRAME_LEN: usize = MAX_BODY_LEN + 3;
/// Smallest frame.
pub const MIN_FRAME_LEN: usize = MIN_BODY_LEN + 3;

/// Byte offsets of the header fields.
mod offset {
    pub const LEN: usize = 3;
    pub const ID: usize = 4;
    pub const PAYLOAD: usize = super::HEADER_LEN;
}

wire_derive! {
    [Eq, Hash, Default]
    /// Which sync bytes a frame starts with.
    pub enum SyncOrder {
        /// `55 AA DC`, as section 2.1 and ArduPilot (the default, and what to send).
        #[default]
        Standard,
        /// `AA 55 DC`, as the document prints its ACK example. Decoded, never chosen by
        /// this crate unless asked.
        Swapped,
    }
}

impl SyncOrder {
    /// The three sync bytes.
    #[must_use]
    pub const fn bytes(self) -> [u8; 3] {
        match self {
            SyncOrder::Standard => SYNC,
            SyncOrder::Swapped => SYNC_SWAPPED,
        }
    }

    /// The order of three sync bytes, if they are either.
    #[must_use]
    pub fn of(bytes: &[u8]) -> Option<Self> {
        match bytes.get(..3)? {
            b if b == SYNC => Some(SyncOrder::Standard),
            b if b == SYNC_SWAPPED => Some(SyncOrder::Swapped),
            _ => None,
        }
    }
}

/// The LEN byte: a body length (bits 0..5) and a frame counter (bits 6..7).
#[must_use]
pub const fn len_byte(body_len: u8, counter: u8) -> u8 {
    (body_len & 0x3F) | ((counter & 0x03) << 6)
}

/// `Ok` when a one-byte checksum received is the one computed, else
/// [`Error::BadChecksum`] (serial frames and TCP envelopes).
pub(super) fn compare_checksums(computed: u8, received: u8) -> Result<()> {
    if computed == received {
        Ok(())
    } else {
        Err(Error::BadChecksum {
            computed: computed.into(),
            received: received.into(),
        })
    }
}

frame_view! {
    /// A read-only or read-write view of a Viewlink frame in a byte buffer.
    ///
    /// [`Frame::new_checked`] guarantees the buffer starts with either sync order, has a
    /// body length in 4..=63 and holds the whole frame. Accessors never panic, also on an
    /// unchecked view (they return zeros). Bytes after the frame are ignored.
}

impl<T: AsRef<[u8]>> Frame<T> {
    /// Checks the sync bytes, the body length and that the buffer holds the frame.
    ///
    /// # Errors
    /// [`Error::BadSync`] when the buffer starts with neither sync order,
    /// [`Error::BadLength`] for a body length below 4, [`Error::Truncated`] when the
    /// buffer ends inside the frame.
    pub fn check_len(&self) -> Result<()> {
        let b = self.buffer.as_ref();
        let sync = b.get(..3).ok_or(Error::Truncated)?;
        if SyncOrder::of(sync).is_none() {
            return Err(Error::BadSync);
        }
        let n = usize::from(self.body_len());
        if b.len() <= offset::LEN {
            return Err(Error::Truncated);
        }
        if n < MIN_BODY_LEN {
            return Err(Error::BadLength);
        }
        if b.len() < self.total_len() {
            return Err(Error::Truncated);
        }
        Ok(())
    }

    /// The sync order (standard when the view is not a checked frame).
    #[must_use]
    pub fn sync_order(&self) -> SyncOrder {
        SyncOrder::of(self.buffer.as_ref()).unwrap_or_default()
    }

    /// The LEN byte as on the wire.
    #[must_use]
    pub fn len_field(&self) -> u8 {
        self.byte(offset::LEN)
    }

    /// Body length: bytes from LEN through the checksum (LEN bits 0..5).
    #[must_use]
    pub fn body_len(&self) -> u8 {
        self.len_field() & 0x3F
    }

    /// Frame counter (LEN bits 6..7).
    #[must_use]
    pub fn counter(&self) -> u8 {
        self.len_field() >> 6
    }

    /// Length of the whole frame, sync to checksum.
    #[must_use]
    pub fn total_len(&self) -> usize {
        usize::from(self.body_len()).saturating_add(3)
    }

    /// The frame id.
    #[must_use]
    pub fn id(&self) -> u8 {
        self.byte(offset::ID)
    }

    /// The payload length (the frame's data bytes: body length minus LEN, id and
    /// checksum).
    #[must_use]
    pub fn payload_len(&self) -> usize {
        usize::from(self.body_len()).saturating_sub(3)
    }

    fn payload_range(&self) -> core::ops::Range<usize> {
        offset::PAYLOAD..offset::PAYLOAD.saturating_add(self.payload_len())
    }

    /// The payload: the data bytes after the id, before the checksum.
    #[must_use]
    pub fn payload(&self) -> &[u8] {
        self.buffer
            .as_ref()
            .get(self.payload_range())
            .unwrap_or_default()
    }

    /// The checksum the frame carries.
    #[must_use]
    pub fn checksum(&self) -> u8 {
        self.byte(self.total_len().saturating_sub(1))
    }

    /// The checksum computed over LEN through the last payload byte.
    #[must_use]
    pub fn compute_checksum(&self) -> u8 {
        let end = self.total_len().saturating_sub(1).max(offset::LEN);
        xor8(
            self.buffer
                .as_ref()
                .get(offset::LEN..end)
                .unwrap_or_default(),
        )
    }

    /// Verifies the checksum.
    ///
    /// # Errors
    /// [`Error::BadChecksum`] when the checksum carried is not the one computed.
    pub fn verify(&self) -> Result<()> {
        compare_checksums(self.compute_checksum(), self.checksum())
    }
}

impl<'a> Frame<&'a [u8]> {
    /// The payload, borrowed for the lifetime of the underlying buffer.
    #[must_use]
    pub fn payload_ref(&self) -> &'a [u8] {
        self.buffer.get(self.payload_range()).unwrap_or_default()
    }
}

impl<T: AsRef<[u8]> + AsMut<[u8]>> Frame<T> {
    /// Writes the sync bytes.
    pub fn set_sync_order(&mut self, order: SyncOrder) {
        for (i, b) in order.bytes().into_iter().enumerate() {
            self.set_byte(i, b);
        }
    }

    /// Writes the LEN byte (body length 4..=63 and counter 0..=3).
    pub fn set_len(&mut self, body_len: u8, counter: u8) {
        self.set_byte(offset::LEN, len_byte(body_len, counter));
    }

    /// Sets the frame id.
    pub fn set_id(&mut self, id: u8) {
        self.set_byte(offset::ID, id);
    }

    /// The payload, writable (LEN must be set first).
    pub fn payload_mut(&mut self) -> &mut [u8] {
        let range = self.payload_range();
        self.buffer.as_mut().get_mut(range).unwrap_or_default()
    }

    /// Computes and stores the checksum (LEN, id and payload must be set first).
    pub fn fill_checksum(&mut self) {
        let cs = self.compute_checksum();
        let at = self.total_len().saturating_sub(1);
        self.set_byte(at, cs);
    }
}

/// Viewlink framing rules for the [`Deframer`](crate::wire::Deframer): one sync order
/// (standard by default; [`ViewlinkFraming::swapped`] for the document's `AA 55 DC`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ViewlinkFraming {
    /// The sync bytes accepted.
    pub sync: SyncOrder,
}

impl ViewlinkFraming {
    /// Frames starting `55 AA DC`.
    #[must_use]
    pub const fn new() -> Self {
        ViewlinkFraming {
            sync: SyncOrder::Standard,
        }
    }

    /// Frames starting `AA 55 DC`.
    #[must_use]
    pub const fn swapped() -> Self {
        ViewlinkFraming {
            sync: SyncOrder::Swapped,
        }
    }
}

impl Framing for ViewlinkFraming {
    fn sync(&self) -> &[u8] {
        match self.sync {
            SyncOrder::Standard => &SYNC,
            SyncOrder::Swapped => &SYNC_SWAPPED,
        }
    }

    fn header_len(&self) -> usize {
        4
    }

    fn frame_len(&self, header: &[u8]) -> Result<usize> {
        let len = header.get(offset::LEN).copied().ok_or(Error::Truncated)?;
        let n = usize::from(len & 0x3F);
        if n < MIN_BODY_LEN {
            return Err(Error::BadLength);
        }
        Ok(n.saturating_add(3))
    }

    fn check(&self, frame: &[u8]) -> Result<()> {
        Frame::new_checked(frame)?.verify()
    }
}

wire_derive! {
    [Eq, Default]
    /// The frame counter a sender keeps: 1, 2, 3, 0, 1, ... (ArduPilot increments before
    /// each frame it sends).
    pub struct FrameCounter {
        last: u8,
    }
}

impl FrameCounter {
    /// A counter whose next value is 1.
    #[must_use]
    pub const fn new() -> Self {
        FrameCounter { last: 0 }
    }

    /// The counter for the next frame.
    pub fn next_value(&mut self) -> u8 {
        self.last = self.last.wrapping_add(1) & 0x03;
        self.last
    }

    /// The header of the next frame: standard sync bytes and the next counter value.
    pub fn next_header(&mut self) -> Header {
        Header::new(self.next_value())
    }
}
