//! The TCP envelope: `EB 90 LEN BODY SUM`, SUM the low byte of the sum of the body.
//!
//! The document says the body is the serial command protocol, but its only example
//! carries a Sony VISCA command (`81 01 04 07 27 FF`, zoom in): the body is kept as
//! bytes, and [`Envelope::serial`] decodes it as a Viewlink frame when it is one.

use super::Packet;
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

/// A view of a TCP envelope in a byte buffer.
#[derive(Debug, Clone)]
pub struct TcpFrame<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> TcpFrame<T> {
    /// A view of a buffer holding a whole envelope (the checksum is not verified).
    pub fn new_checked(buffer: T) -> Result<Self> {
        let b = buffer.as_ref();
        let sync = b.get(..2).ok_or(Error::Truncated)?;
        if sync != SYNC {
            return Err(Error::BadSync);
        }
        let f = TcpFrame { buffer };
        if f.buffer.as_ref().len() < HEADER_LEN || f.buffer.as_ref().len() < f.total_len() {
            return Err(Error::Truncated);
        }
        Ok(f)
    }

    /// The body length.
    pub fn body_len(&self) -> u8 {
        self.buffer.as_ref().get(2).copied().unwrap_or(0)
    }

    /// Length of the envelope.
    pub fn total_len(&self) -> usize {
        usize::from(self.body_len()).saturating_add(HEADER_LEN + 1)
    }

    /// The body.
    pub fn body(&self) -> &[u8] {
        let end = HEADER_LEN.saturating_add(usize::from(self.body_len()));
        self.buffer
            .as_ref()
            .get(HEADER_LEN..end)
            .unwrap_or_default()
    }

    /// The checksum carried.
    pub fn checksum(&self) -> u8 {
        self.buffer
            .as_ref()
            .get(self.total_len().saturating_sub(1))
            .copied()
            .unwrap_or(0)
    }

    /// Verifies the checksum (sum of the body, low byte).
    pub fn verify(&self) -> Result<()> {
        let computed = sum8(self.body());
        let received = self.checksum();
        if computed == received {
            Ok(())
        } else {
            Err(Error::BadChecksum {
                computed: computed.into(),
                received: received.into(),
            })
        }
    }
}

impl<'a> TcpFrame<&'a [u8]> {
    /// The body, borrowed for the lifetime of the buffer.
    pub fn body_ref(&self) -> &'a [u8] {
        let end = HEADER_LEN.saturating_add(usize::from(self.body_len()));
        self.buffer.get(HEADER_LEN..end).unwrap_or_default()
    }
}

wire_derive! {
    [Eq, Hash]
    /// A decoded TCP envelope.
    pub struct Envelope<'a> {
        /// The body.
        pub body: &'a [u8],
    }
}

impl<'a> Envelope<'a> {
    /// Checks, verifies and parses an envelope.
    pub fn decode(bytes: &'a [u8]) -> Result<Self> {
        let f = TcpFrame::new_checked(bytes)?;
        f.verify()?;
        Ok(Envelope { body: f.body_ref() })
    }

    /// The body decoded as a Viewlink serial frame.
    pub fn serial(&self) -> Result<Packet<'a>> {
        Packet::decode(self.body)
    }

    /// Length of the encoded envelope.
    pub const fn buffer_len(&self) -> usize {
        self.body.len().saturating_add(HEADER_LEN + 1)
    }

    /// Encodes the envelope into `buf` and returns its length; a body longer than 255
    /// bytes is [`Error::BadLength`].
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
        let n = header.get(2).copied().ok_or(Error::Truncated)?;
        Ok(usize::from(n).saturating_add(HEADER_LEN + 1))
    }

    fn check(&self, frame: &[u8]) -> Result<()> {
        TcpFrame::new_checked(frame)?.verify()
    }
}
