//! The TCP envelope: `EB 90 LEN BODY SUM`, SUM the low byte of the sum of the body.
//!
//! The document says the body is the serial command protocol, but its only example
//! carries a Sony VISCA command (`81 01 04 07 27 FF`, zoom in): the body is kept as
//! bytes, and [`Envelope::serial`] decodes it as a Viewlink frame when it is one.
//! [`TcpFrame`] is the checked view and [`Envelope`] the representation, shaped as the
//! serial [`Frame`](super::Frame) and [`Packet`].

use super::Packet;
use super::frame::compare_checksums;
use crate::wire::{Framing, Writer, sum8};
use crate::{Error, Result};

/// The two sync bytes ("STX" and "CMD ID").
pub const SYNC: [u8; 2] = [0xEB, 0x90];
/// Bytes before the body.
pub const HEADER_LEN: usize = 3;
/// Largest body.
pub const MAX_BODY_LEN: usize = 255;
/// Largest envelope.
pub const MAX_FRAME_LEN: usize = HEADER_LEN + MAX_BODY_LEN + 1;

/// Byte offset of the body length.
const LEN_OFFSET: usize = 2;

/// A read-only view of a TCP envelope in a byte buffer. Accessors never panic, also on
/// an unchecked view (they return zeros). Bytes after the envelope are ignored.
#[derive(Debug, Clone)]
pub struct TcpFrame<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> TcpFrame<T> {
    /// A view without checks.
    pub const fn new_unchecked(buffer: T) -> Self {
        TcpFrame { buffer }
    }

    /// A view of a buffer holding a whole envelope (the checksum is not verified; see
    /// [`TcpFrame::verify`]).
    ///
    /// # Errors
    /// As [`TcpFrame::check_len`].
    pub fn new_checked(buffer: T) -> Result<Self> {
        let f = TcpFrame { buffer };
        f.check_len()?;
        Ok(f)
    }

    /// Checks the sync bytes and that the buffer holds the whole envelope.
    ///
    /// # Errors
    /// [`Error::BadSync`] when the buffer does not start `EB 90`, [`Error::Truncated`]
    /// when it ends inside the envelope.
    pub fn check_len(&self) -> Result<()> {
        let b = self.buffer.as_ref();
        if b.get(..2).ok_or(Error::Truncated)? != SYNC {
            return Err(Error::BadSync);
        }
        if b.len() < HEADER_LEN || b.len() < self.total_len() {
            return Err(Error::Truncated);
        }
        Ok(())
    }

    /// The underlying buffer.
    pub fn into_inner(self) -> T {
        self.buffer
    }

    /// The body length.
    #[must_use]
    pub fn body_len(&self) -> u8 {
        self.buffer.as_ref().get(LEN_OFFSET).copied().unwrap_or(0)
    }

    /// Length of the envelope.
    #[must_use]
    pub fn total_len(&self) -> usize {
        usize::from(self.body_len()).saturating_add(HEADER_LEN + 1)
    }

    fn body_range(&self) -> core::ops::Range<usize> {
        HEADER_LEN..HEADER_LEN.saturating_add(usize::from(self.body_len()))
    }

    /// The bytes between the length byte and the checksum (a Viewlink frame).
    #[must_use]
    pub fn body(&self) -> &[u8] {
        self.buffer
            .as_ref()
            .get(self.body_range())
            .unwrap_or_default()
    }

    /// The checksum carried.
    #[must_use]
    pub fn checksum(&self) -> u8 {
        self.buffer
            .as_ref()
            .get(self.total_len().saturating_sub(1))
            .copied()
            .unwrap_or(0)
    }

    /// The checksum computed over the body (sum of its bytes, low byte).
    #[must_use]
    pub fn compute_checksum(&self) -> u8 {
        sum8(self.body())
    }

    /// Verifies the checksum.
    ///
    /// # Errors
    /// [`Error::BadChecksum`] when the checksum carried is not the one computed.
    pub fn verify(&self) -> Result<()> {
        compare_checksums(self.compute_checksum(), self.checksum())
    }
}

impl<'a> TcpFrame<&'a [u8]> {
    /// The body, borrowed for the lifetime of the buffer.
    #[must_use]
    pub fn body_ref(&self) -> &'a [u8] {
        self.buffer.get(self.body_range()).unwrap_or_default()
    }
}

wire_derive! {
    [Eq, Hash]
    /// A decoded TCP envelope: its body.
    pub struct Envelope<'a> {
        /// The bytes between the length byte and the checksum (a Viewlink frame).
        pub body: &'a [u8],
    }
}

impl<'a> Envelope<'a> {
    /// Parses an envelope view (its checksum is not verified here).
    ///
    /// # Errors
    /// As [`TcpFrame::check_len`].
    pub fn parse(frame: &TcpFrame<&'a [u8]>) -> Result<Self> {
        frame.check_len()?;
        Ok(Envelope {
            body: frame.body_ref(),
        })
    }

    /// Checks, verifies and parses an envelope.
    ///
    /// # Errors
    /// As [`TcpFrame::new_checked`] and [`TcpFrame::verify`].
    pub fn decode(bytes: &'a [u8]) -> Result<Self> {
        let f = TcpFrame::new_checked(bytes)?;
        f.verify()?;
        Envelope::parse(&f)
    }

    /// The body decoded as a Viewlink serial frame.
    ///
    /// # Errors
    /// As [`Packet::decode`] (a body that is not a Viewlink frame is an error).
    pub fn serial(&self) -> Result<Packet<'a>> {
        Packet::decode(self.body)
    }

    /// Length of the encoded envelope.
    #[must_use]
    pub const fn buffer_len(&self) -> usize {
        self.body.len().saturating_add(HEADER_LEN + 1)
    }

    /// Encodes the envelope into `buf` and returns its length.
    ///
    /// # Errors
    /// [`Error::BadLength`] for a body longer than 255 bytes,
    /// [`Error::BufferTooSmall`] when `buf` is shorter than [`Envelope::buffer_len`].
    pub fn emit(&self, buf: &mut [u8]) -> Result<usize> {
        let len = u8::try_from(self.body.len()).map_err(|_| Error::BadLength)?;
        let mut w = Writer::new(buf);
        w.put(&SYNC)?;
        w.u8(len)?;
        w.put(self.body)?;
        w.u8(sum8(self.body))?;
        Ok(w.finish())
    }
}

/// TCP envelope framing rules for the [`Deframer`](crate::wire::Deframer).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TcpFraming;

impl Framing for TcpFraming {
    fn sync(&self) -> &[u8] {
        &SYNC
    }

    fn header_len(&self) -> usize {
        HEADER_LEN
    }

    fn frame_len(&self, header: &[u8]) -> Result<usize> {
        let n = header.get(LEN_OFFSET).copied().ok_or(Error::Truncated)?;
        Ok(usize::from(n).saturating_add(HEADER_LEN + 1))
    }

    fn check(&self, frame: &[u8]) -> Result<()> {
        TcpFrame::new_checked(frame)?.verify()
    }
}
