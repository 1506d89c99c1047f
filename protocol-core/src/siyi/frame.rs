//! The SIYI frame: `55 66 CTRL LEN(u16 LE) SEQ(u16 LE) CMD DATA CRC16(LE)`.

use crate::wire::{Framing, crc16_xmodem};
use crate::{Direction, Error, Result};

/// The two start bytes (the document's STX 0x6655, low byte first).
pub const STX: [u8; 2] = [0x55, 0x66];
/// Bytes before the payload: STX, CTRL, LEN, SEQ, CMD.
pub const HEADER_LEN: usize = 8;
/// Bytes after the payload (the CRC).
pub const CRC_LEN: usize = 2;
/// Smallest frame (no payload).
pub const MIN_FRAME_LEN: usize = HEADER_LEN + CRC_LEN;
/// Largest payload length the LEN field can express.
pub const MAX_PAYLOAD_LEN: usize = 0xFFFF;
/// Default payload limit of [`SiyiFraming`]: the longest message of the catalogue
/// (0x3E, 32 bytes), which is also the most ArduPilot's `AP_Mount_Siyi` accepts (it drops
/// a frame with more data).
pub const DEFAULT_MAX_PAYLOAD_LEN: usize = 32;
/// Largest frame under [`DEFAULT_MAX_PAYLOAD_LEN`] (42 bytes): a good deframer buffer
/// size.
pub const DEFAULT_MAX_FRAME_LEN: usize = MIN_FRAME_LEN + DEFAULT_MAX_PAYLOAD_LEN;

/// Byte offsets of the header fields.
mod offset {
    pub const STX: core::ops::Range<usize> = 0..2;
    pub const CTRL: usize = 2;
    pub const LEN: core::ops::Range<usize> = 3..5;
    pub const SEQ: core::ops::Range<usize> = 5..7;
    pub const CMD: usize = 7;
}

bit_set! {
    /// The CTRL byte: bit 0 `need_ack`, bit 1 `is_ack` (`ack_pack`), bits 2..7 reserved.
    ///
    /// Kept as the byte received (reserved bits included), so re-encoding is exact.
    pub struct Ctrl(u8) {
        /// Bit 0: the sender wants an acknowledgement.
        0 => need_ack, with_need_ack;
        /// Bit 1: this packet is an acknowledgement.
        1 => is_ack, with_is_ack;
    }
}

impl Ctrl {
    /// Bit 0: the sender wants an acknowledgement.
    pub const NEED_ACK_BIT: u8 = 0x01;
    /// Bit 1: this packet is an acknowledgement.
    pub const IS_ACK_BIT: u8 = 0x02;
    /// CTRL = 1, what ArduPilot sends with every request.
    pub const NEED_ACK: Ctrl = Ctrl(Self::NEED_ACK_BIT);
    /// CTRL = 2, what SIYI gimbals send with their replies.
    pub const IS_ACK: Ctrl = Ctrl(Self::IS_ACK_BIT);

    /// A CTRL byte from its two flags (reserved bits zero).
    #[must_use]
    pub const fn new(need_ack: bool, is_ack: bool) -> Self {
        Ctrl(0).with_need_ack(need_ack).with_is_ack(is_ack)
    }

    /// Bits 2..7, shifted down (reserved; zero in every known sender).
    #[must_use]
    pub const fn reserved(self) -> u8 {
        self.0 >> 2
    }

    /// The direction this CTRL byte suggests: [`Direction::FromGimbal`] when `is_ack` is
    /// set, else [`Direction::ToGimbal`]. A hint only: gimbals push data with other CTRL
    /// values (see the module documentation).
    #[must_use]
    pub const fn direction(self) -> Direction {
        if self.is_ack() {
            Direction::FromGimbal
        } else {
            Direction::ToGimbal
        }
    }
}

frame_view! {
    /// A read-only or read-write view of a SIYI frame in a byte buffer.
    ///
    /// [`Frame::new_checked`] guarantees the buffer starts with STX and holds the whole
    /// frame (header, LEN payload bytes, CRC); accessors never panic, even unchecked. Bytes
    /// after the frame are ignored.
}

impl<T: AsRef<[u8]>> Frame<T> {
    /// Checks STX and that the buffer holds the whole frame.
    ///
    /// # Errors
    /// [`Error::BadSync`] when the buffer does not start with STX, [`Error::Truncated`]
    /// when it is shorter than the frame (or than STX, if what it holds is a prefix of
    /// STX).
    pub fn check_len(&self) -> Result<()> {
        let b = self.buffer.as_ref();
        match b.get(offset::STX) {
            Some(s) if s == STX => {}
            _ if b.len() >= 2 || !STX.starts_with(b) => return Err(Error::BadSync),
            _ => return Err(Error::Truncated),
        }
        if b.len() < HEADER_LEN || b.len() < self.total_len() {
            return Err(Error::Truncated);
        }
        Ok(())
    }

    fn u16_at(&self, r: core::ops::Range<usize>) -> u16 {
        u16::from_le_bytes([self.byte(r.start), self.byte(r.start.saturating_add(1))])
    }

    /// The CTRL byte.
    #[must_use]
    pub fn ctrl(&self) -> Ctrl {
        Ctrl(self.byte(offset::CTRL))
    }

    /// The LEN field: number of payload (data) bytes.
    #[must_use]
    pub fn payload_len(&self) -> usize {
        usize::from(self.u16_at(offset::LEN))
    }

    /// Length of the whole frame, STX to CRC.
    #[must_use]
    pub fn total_len(&self) -> usize {
        MIN_FRAME_LEN.saturating_add(self.payload_len())
    }

    /// The sequence number.
    #[must_use]
    pub fn seq(&self) -> u16 {
        self.u16_at(offset::SEQ)
    }

    /// The message id (the CMD byte).
    #[must_use]
    pub fn id(&self) -> u8 {
        self.byte(offset::CMD)
    }

    fn payload_range(&self) -> core::ops::Range<usize> {
        HEADER_LEN..HEADER_LEN.saturating_add(self.payload_len())
    }

    /// The payload (the document's "data").
    #[must_use]
    pub fn payload(&self) -> &[u8] {
        self.buffer
            .as_ref()
            .get(self.payload_range())
            .unwrap_or_default()
    }

    /// The CRC the frame carries.
    #[must_use]
    pub fn checksum(&self) -> u16 {
        let at = self.total_len().saturating_sub(CRC_LEN);
        self.u16_at(at..at.saturating_add(CRC_LEN))
    }

    /// CRC-16/XMODEM over STX..payload (the whole packet before the CRC).
    #[must_use]
    pub fn compute_checksum(&self) -> u16 {
        let end = self.total_len().saturating_sub(CRC_LEN);
        crc16_xmodem(self.buffer.as_ref().get(..end).unwrap_or_default())
    }

    /// Verifies the CRC.
    ///
    /// # Errors
    /// [`Error::BadChecksum`] when the carried CRC differs from the computed one.
    pub fn verify(&self) -> Result<()> {
        let computed = self.compute_checksum();
        let received = self.checksum();
        if computed == received {
            Ok(())
        } else {
            Err(Error::BadChecksum { computed, received })
        }
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
    fn set_u16(&mut self, r: core::ops::Range<usize>, v: u16) {
        let [lo, hi] = v.to_le_bytes();
        self.set_byte(r.start, lo);
        self.set_byte(r.start.saturating_add(1), hi);
    }

    /// Writes STX and the LEN field.
    pub fn set_start(&mut self, payload_len: u16) {
        for (i, b) in offset::STX.zip(STX) {
            self.set_byte(i, b);
        }
        self.set_u16(offset::LEN, payload_len);
    }

    /// Sets the CTRL byte.
    pub fn set_ctrl(&mut self, ctrl: Ctrl) {
        self.set_byte(offset::CTRL, ctrl.0);
    }

    /// Sets the sequence number.
    pub fn set_seq(&mut self, seq: u16) {
        self.set_u16(offset::SEQ, seq);
    }

    /// Sets the message id (the CMD byte).
    pub fn set_id(&mut self, id: u8) {
        self.set_byte(offset::CMD, id);
    }

    /// The payload, writable (LEN must be set first).
    pub fn payload_mut(&mut self) -> &mut [u8] {
        let r = self.payload_range();
        self.buffer.as_mut().get_mut(r).unwrap_or_default()
    }

    /// Computes and stores the CRC (everything before it must be set first).
    pub fn fill_checksum(&mut self) {
        let crc = self.compute_checksum();
        let at = self.total_len().saturating_sub(CRC_LEN);
        self.set_u16(at..at.saturating_add(CRC_LEN), crc);
    }
}

/// SIYI framing rules for the [`Deframer`](crate::wire::Deframer): sync `55 66`, total
/// length from LEN, CRC-16/XMODEM check.
///
/// A frame whose LEN exceeds `max_payload_len` is rejected ([`Error::BadLength`]) without
/// waiting for its bytes, which bounds the damage of a corrupted LEN field. The default
/// is [`DEFAULT_MAX_PAYLOAD_LEN`] (32); use [`SiyiFraming::new`] to accept longer frames
/// (up to [`MAX_PAYLOAD_LEN`]), with a deframer buffer of `max_payload_len + 10` bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SiyiFraming {
    /// The largest accepted LEN.
    pub max_payload_len: usize,
}

impl SiyiFraming {
    /// Framing that accepts up to `max_payload_len` payload bytes (capped at
    /// [`MAX_PAYLOAD_LEN`]).
    #[must_use]
    pub const fn new(max_payload_len: usize) -> Self {
        SiyiFraming {
            max_payload_len: if max_payload_len > MAX_PAYLOAD_LEN {
                MAX_PAYLOAD_LEN
            } else {
                max_payload_len
            },
        }
    }
}

impl Default for SiyiFraming {
    fn default() -> Self {
        SiyiFraming::new(DEFAULT_MAX_PAYLOAD_LEN)
    }
}

impl Framing for SiyiFraming {
    fn sync(&self) -> &[u8] {
        &STX
    }

    fn header_len(&self) -> usize {
        offset::LEN.end
    }

    fn frame_len(&self, header: &[u8]) -> Result<usize> {
        let len = match header.get(offset::LEN) {
            Some(&[lo, hi]) => usize::from(u16::from_le_bytes([lo, hi])),
            _ => return Err(Error::Truncated),
        };
        if len > self.max_payload_len {
            return Err(Error::BadLength);
        }
        Ok(MIN_FRAME_LEN.saturating_add(len))
    }

    fn check(&self, frame: &[u8]) -> Result<()> {
        Frame::new_checked(frame)?.verify()
    }
}
