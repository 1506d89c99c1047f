//! The GCU package: `SYNC(2) LENGTH(u16 LE) VERSION MAIN(32) SUB(32) ORDER PARAMS CRC(u16 BE)`.

use crate::wire::{Framing, crc16_xmodem};
use crate::{Error, Result};

/// First two bytes of a package from the host computer (flight controller) to the GCU.
pub const HOST_SYNC: [u8; 2] = [0xA8, 0xE5];
/// First two bytes of a package from the GCU to the host computer.
pub const GCU_SYNC: [u8; 2] = [0x8A, 0x5E];
/// Offset of the main data frame (bytes 5..=36).
pub const MAIN_OFFSET: usize = 5;
/// Length of the main data frame.
pub const MAIN_LEN: usize = 32;
/// Offset of the sub data frame (bytes 37..=68).
pub const SUB_OFFSET: usize = 37;
/// Length of the sub data frame.
pub const SUB_LEN: usize = 32;
/// Offset of the command / feedback part: the order byte, then its parameters.
pub const ORDER_OFFSET: usize = 69;
/// Bytes after the command / feedback part (the CRC).
pub const CRC_LEN: usize = 2;
/// Smallest package: the fixed part, the order byte and the CRC (72 bytes).
pub const MIN_FRAME_LEN: usize = ORDER_OFFSET + 1 + CRC_LEN;
/// Largest package accepted: the document's CRC routine takes a `uint8_t` length, so
/// at most 255 bytes are covered and a package is at most 257 bytes.
pub const MAX_FRAME_LEN: usize = 255 + CRC_LEN;
/// Largest command / feedback part after the order byte.
pub const MAX_PARAMS_LEN: usize = MAX_FRAME_LEN - MIN_FRAME_LEN;
/// Protocol version byte of the document's examples.
pub const VERSION_DOC: u8 = 0x01;
/// Protocol version byte ArduPilot's `AP_Mount_XFRobot` sends.
pub const VERSION_ARDUPILOT: u8 = 0x02;

/// Which way a package goes; the sync bytes tell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Direction {
    /// Host computer (flight controller) to GCU: `A8 E5`, command part.
    Host,
    /// GCU to host computer: `8A 5E`, feedback part.
    Gcu,
}

impl Direction {
    /// The sync bytes of this direction.
    pub const fn sync(self) -> [u8; 2] {
        match self {
            Direction::Host => HOST_SYNC,
            Direction::Gcu => GCU_SYNC,
        }
    }

    /// The direction whose sync bytes these are.
    pub const fn from_sync(sync: [u8; 2]) -> Option<Self> {
        match sync {
            [0xA8, 0xE5] => Some(Direction::Host),
            [0x8A, 0x5E] => Some(Direction::Gcu),
            _ => None,
        }
    }
}

/// A read-only or read-write view of a GCU package in a byte buffer.
///
/// [`Frame::new_checked`] guarantees the buffer starts with either direction's sync
/// bytes, carries a length in `MIN_FRAME_LEN..=MAX_FRAME_LEN`, and holds that many
/// bytes. Accessors never panic (on an unchecked buffer they return zero or empty
/// values). Bytes after the package are ignored.
#[derive(Debug, Clone)]
pub struct Frame<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> Frame<T> {
    /// A view without checks. Use [`Frame::new_checked`] for received bytes.
    pub const fn new_unchecked(buffer: T) -> Self {
        Frame { buffer }
    }

    /// A view of a buffer that holds a whole package (the CRC is not verified; see
    /// [`Frame::verify`]).
    pub fn new_checked(buffer: T) -> Result<Self> {
        let frame = Frame { buffer };
        frame.check_len()?;
        Ok(frame)
    }

    /// Checks the sync bytes, the length field and that the buffer holds the package.
    pub fn check_len(&self) -> Result<()> {
        let b = self.buffer.as_ref();
        match b.first() {
            None => return Err(Error::Truncated),
            Some(&first) if first != HOST_SYNC[0] && first != GCU_SYNC[0] => {
                return Err(Error::BadSync);
            }
            Some(_) => {}
        }
        if b.len() < 2 {
            return Err(Error::Truncated);
        }
        if self.direction().is_none() {
            return Err(Error::BadSync);
        }
        if b.len() < 4 {
            return Err(Error::Truncated);
        }
        let len = self.total_len();
        if !(MIN_FRAME_LEN..=MAX_FRAME_LEN).contains(&len) {
            return Err(Error::BadLength);
        }
        if b.len() < len {
            return Err(Error::Truncated);
        }
        Ok(())
    }

    /// The underlying buffer.
    pub fn into_inner(self) -> T {
        self.buffer
    }

    fn byte(&self, i: usize) -> u8 {
        self.buffer.as_ref().get(i).copied().unwrap_or(0)
    }

    fn range(&self, start: usize, end: usize) -> &[u8] {
        self.buffer.as_ref().get(start..end).unwrap_or_default()
    }

    /// The direction the sync bytes name (`None` on an unchecked, invalid buffer).
    pub fn direction(&self) -> Option<Direction> {
        Direction::from_sync([self.byte(0), self.byte(1)])
    }

    /// The length field: the whole package, sync to CRC.
    pub fn total_len(&self) -> usize {
        usize::from(u16::from_le_bytes([self.byte(2), self.byte(3)]))
    }

    /// The protocol version byte.
    pub fn version(&self) -> u8 {
        self.byte(4)
    }

    /// The main data frame (bytes 5..=36).
    pub fn main(&self) -> &[u8] {
        self.range(MAIN_OFFSET, SUB_OFFSET)
    }

    /// The sub data frame (bytes 37..=68).
    pub fn sub(&self) -> &[u8] {
        self.range(SUB_OFFSET, ORDER_OFFSET)
    }

    /// The order byte (69).
    pub fn order(&self) -> u8 {
        self.byte(ORDER_OFFSET)
    }

    fn params_end(&self) -> usize {
        self.total_len().saturating_sub(CRC_LEN)
    }

    /// The parameters (host) or execution state (GCU) after the order byte.
    pub fn params(&self) -> &[u8] {
        self.range(ORDER_OFFSET.saturating_add(1), self.params_end())
    }

    /// The CRC the package carries (big-endian on the wire).
    pub fn checksum(&self) -> u16 {
        let at = self.params_end();
        u16::from_be_bytes([self.byte(at), self.byte(at.saturating_add(1))])
    }

    /// CRC-16/XMODEM over bytes 0..=S-3.
    pub fn compute_checksum(&self) -> u16 {
        crc16_xmodem(self.range(0, self.params_end()))
    }

    /// Verifies the CRC.
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
    /// The main data frame, borrowed for the lifetime of the buffer.
    pub fn main_ref(&self) -> &'a [u8] {
        self.buffer.get(MAIN_OFFSET..SUB_OFFSET).unwrap_or_default()
    }

    /// The sub data frame, borrowed for the lifetime of the buffer.
    pub fn sub_ref(&self) -> &'a [u8] {
        self.buffer
            .get(SUB_OFFSET..ORDER_OFFSET)
            .unwrap_or_default()
    }

    /// The parameters after the order byte, borrowed for the lifetime of the buffer.
    pub fn params_ref(&self) -> &'a [u8] {
        let end = self.params_end();
        self.buffer
            .get(ORDER_OFFSET.saturating_add(1)..end)
            .unwrap_or_default()
    }
}

impl<T: AsRef<[u8]> + AsMut<[u8]>> Frame<T> {
    fn set_byte(&mut self, i: usize, v: u8) {
        if let Some(b) = self.buffer.as_mut().get_mut(i) {
            *b = v;
        }
    }

    /// Writes the sync bytes of `direction` and the length field.
    pub fn set_header(&mut self, direction: Direction, total_len: u16) {
        let [s0, s1] = direction.sync();
        let [l0, l1] = total_len.to_le_bytes();
        self.set_byte(0, s0);
        self.set_byte(1, s1);
        self.set_byte(2, l0);
        self.set_byte(3, l1);
    }

    /// Sets the version byte.
    pub fn set_version(&mut self, version: u8) {
        self.set_byte(4, version);
    }

    /// Sets the order byte.
    pub fn set_order(&mut self, order: u8) {
        self.set_byte(ORDER_OFFSET, order);
    }

    /// The main data frame, writable.
    pub fn main_mut(&mut self) -> &mut [u8] {
        self.buffer
            .as_mut()
            .get_mut(MAIN_OFFSET..SUB_OFFSET)
            .unwrap_or_default()
    }

    /// The sub data frame, writable.
    pub fn sub_mut(&mut self) -> &mut [u8] {
        self.buffer
            .as_mut()
            .get_mut(SUB_OFFSET..ORDER_OFFSET)
            .unwrap_or_default()
    }

    /// The parameters after the order byte, writable (the length field must be set).
    pub fn params_mut(&mut self) -> &mut [u8] {
        let end = self.params_end();
        self.buffer
            .as_mut()
            .get_mut(ORDER_OFFSET.saturating_add(1)..end)
            .unwrap_or_default()
    }

    /// Computes and stores the CRC (everything it covers must be set first).
    pub fn fill_checksum(&mut self) {
        let [hi, lo] = self.compute_checksum().to_be_bytes();
        let at = self.params_end();
        self.set_byte(at, hi);
        self.set_byte(at.saturating_add(1), lo);
    }
}

/// GCU framing rules for the [`Deframer`](crate::wire::Deframer), for one direction.
///
/// The two directions have different sync bytes and the shared deframer looks for one
/// sync pattern, so a link is deframed per direction: a device that answers as the GCU
/// reads [`GcuFraming::host`] packages, one that drives a GCU reads
/// [`GcuFraming::gcu`] packages. (Each UART wire carries one direction.)
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GcuFraming {
    /// The direction whose packages are accepted.
    pub direction: Direction,
}

impl GcuFraming {
    /// Packages from the host computer (`A8 E5`): what a GCU, or a bridge acting as one,
    /// receives.
    pub const fn host() -> Self {
        GcuFraming {
            direction: Direction::Host,
        }
    }

    /// Packages from the GCU (`8A 5E`): what the host computer receives.
    pub const fn gcu() -> Self {
        GcuFraming {
            direction: Direction::Gcu,
        }
    }
}

impl Framing for GcuFraming {
    fn sync(&self) -> &[u8] {
        match self.direction {
            Direction::Host => &HOST_SYNC,
            Direction::Gcu => &GCU_SYNC,
        }
    }

    fn header_len(&self) -> usize {
        4
    }

    fn frame_len(&self, header: &[u8]) -> Result<usize> {
        let lo = header.get(2).copied().ok_or(Error::Truncated)?;
        let hi = header.get(3).copied().ok_or(Error::Truncated)?;
        let len = usize::from(u16::from_le_bytes([lo, hi]));
        if (MIN_FRAME_LEN..=MAX_FRAME_LEN).contains(&len) {
            Ok(len)
        } else {
            Err(Error::BadLength)
        }
    }

    fn check(&self, frame: &[u8]) -> Result<()> {
        let f = Frame::new_checked(frame)?;
        if f.direction() != Some(self.direction) {
            return Err(Error::BadSync);
        }
        f.verify()
    }
}
