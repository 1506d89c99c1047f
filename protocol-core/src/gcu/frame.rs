//! The GCU package: `SYNC(2) LENGTH(u16 LE) VERSION MAIN(32) SUB(32) ORDER PAYLOAD CRC(u16 BE)`.

use crate::wire::{Framing, crc16_xmodem};
use crate::{Direction, Error, Result};

/// First two bytes of a package from the host computer (flight controller) to the GCU.
pub const HOST_SYNC: [u8; 2] = [0xA8, 0xE5];
/// First two bytes of a package from the GCU to the host computer.
pub const GCU_SYNC: [u8; 2] = [0x8A, 0x5E];
/// Length of the main data frame.
pub const MAIN_LEN: usize = 32;
/// Length of the sub data frame.
pub const SUB_LEN: usize = 32;
/// Bytes before the payload: sync, length, version, the two data frames and the order
/// byte.
pub const HEADER_LEN: usize = offset::PAYLOAD;
/// Bytes after the payload (the CRC).
pub const CRC_LEN: usize = 2;
/// Smallest package: the fixed part, the order byte and the CRC (72 bytes).
pub const MIN_FRAME_LEN: usize = HEADER_LEN + CRC_LEN;
/// Largest package accepted: the document's CRC routine takes a `uint8_t` length, so
/// at most 255 bytes are covered and a package is at most 257 bytes.
pub const MAX_FRAME_LEN: usize = 255 + CRC_LEN;
/// Largest payload (the parameters or execution state after the order byte).
pub const MAX_PAYLOAD_LEN: usize = MAX_FRAME_LEN - MIN_FRAME_LEN;
/// Protocol version byte of the document's examples.
pub const VERSION_DOC: u8 = 0x01;
/// Protocol version byte ArduPilot's `AP_Mount_XFRobot` sends.
pub const VERSION_ARDUPILOT: u8 = 0x02;

/// Byte offsets of the package fields.
mod offset {
    pub const SYNC: usize = 0;
    pub const LENGTH: usize = 2;
    pub const VERSION: usize = 4;
    /// The main data frame, bytes 5..=36.
    pub const MAIN: usize = 5;
    /// The sub data frame, bytes 37..=68.
    pub const SUB: usize = MAIN + super::MAIN_LEN;
    /// The order byte (69): the message id.
    pub const ORDER: usize = SUB + super::SUB_LEN;
    /// The parameters (host) or execution state (GCU) after the order byte.
    pub const PAYLOAD: usize = ORDER + 1;
}

/// The sync bytes of the packages going `direction`: [`HOST_SYNC`] to the gimbal,
/// [`GCU_SYNC`] from it.
#[must_use]
pub const fn sync_of(direction: Direction) -> [u8; 2] {
    match direction {
        Direction::ToGimbal => HOST_SYNC,
        Direction::FromGimbal => GCU_SYNC,
    }
}

/// The direction whose sync bytes these are (`None` for other bytes).
#[must_use]
pub const fn direction_of(sync: [u8; 2]) -> Option<Direction> {
    match sync {
        HOST_SYNC => Some(Direction::ToGimbal),
        GCU_SYNC => Some(Direction::FromGimbal),
        _ => None,
    }
}

frame_view! {
    /// A read-only or read-write view of a GCU package in a byte buffer.
    ///
    /// [`Frame::new_checked`] guarantees the buffer starts with either direction's sync
    /// bytes, carries a length in `MIN_FRAME_LEN..=MAX_FRAME_LEN`, and holds that many
    /// bytes. Accessors never panic (on an unchecked buffer they return zero or empty
    /// values). Bytes after the package are ignored.
}

impl<T: AsRef<[u8]>> Frame<T> {
    /// Checks the sync bytes, the length field and that the buffer holds the package.
    ///
    /// # Errors
    /// [`Error::BadSync`] when the buffer starts with neither direction's sync bytes,
    /// [`Error::BadLength`] for a length field outside `MIN_FRAME_LEN..=MAX_FRAME_LEN`,
    /// [`Error::Truncated`] when the buffer is shorter than the package.
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
        if b.len() < offset::VERSION {
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

    fn range(&self, start: usize, end: usize) -> &[u8] {
        self.buffer.as_ref().get(start..end).unwrap_or_default()
    }

    /// The direction the sync bytes name (`None` on an unchecked, invalid buffer).
    #[must_use]
    pub fn direction(&self) -> Option<Direction> {
        direction_of([self.byte(offset::SYNC), self.byte(offset::SYNC + 1)])
    }

    /// The length field: the whole package, sync to CRC.
    #[must_use]
    pub fn total_len(&self) -> usize {
        usize::from(u16::from_le_bytes([
            self.byte(offset::LENGTH),
            self.byte(offset::LENGTH + 1),
        ]))
    }

    /// The protocol version byte.
    #[must_use]
    pub fn version(&self) -> u8 {
        self.byte(offset::VERSION)
    }

    /// The main data frame (bytes 5..=36).
    #[must_use]
    pub fn main(&self) -> &[u8] {
        self.range(offset::MAIN, offset::SUB)
    }

    /// The sub data frame (bytes 37..=68).
    #[must_use]
    pub fn sub(&self) -> &[u8] {
        self.range(offset::SUB, offset::ORDER)
    }

    /// The message id: the order byte (69).
    #[must_use]
    pub fn id(&self) -> u8 {
        self.byte(offset::ORDER)
    }

    fn payload_end(&self) -> usize {
        self.total_len().saturating_sub(CRC_LEN)
    }

    /// Length of the payload: the length field less [`MIN_FRAME_LEN`].
    #[must_use]
    pub fn payload_len(&self) -> usize {
        self.total_len().saturating_sub(MIN_FRAME_LEN)
    }

    /// The payload: the parameters (host) or the execution state (GCU) after the
    /// order byte.
    #[must_use]
    pub fn payload(&self) -> &[u8] {
        self.range(offset::PAYLOAD, self.payload_end())
    }

    /// The CRC the package carries (big-endian on the wire).
    #[must_use]
    pub fn checksum(&self) -> u16 {
        let at = self.payload_end();
        u16::from_be_bytes([self.byte(at), self.byte(at.saturating_add(1))])
    }

    /// CRC-16/XMODEM over bytes 0..=S-3.
    #[must_use]
    pub fn compute_checksum(&self) -> u16 {
        crc16_xmodem(self.range(0, self.payload_end()))
    }

    /// Verifies the CRC.
    ///
    /// # Errors
    /// [`Error::BadChecksum`] when the CRC carried differs from the one computed.
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
    #[must_use]
    pub fn main_ref(&self) -> &'a [u8] {
        self.buffer
            .get(offset::MAIN..offset::SUB)
            .unwrap_or_default()
    }

    /// The sub data frame, borrowed for the lifetime of the buffer.
    #[must_use]
    pub fn sub_ref(&self) -> &'a [u8] {
        self.buffer
            .get(offset::SUB..offset::ORDER)
            .unwrap_or_default()
    }

    /// The payload, borrowed for the lifetime of the buffer.
    #[must_use]
    pub fn payload_ref(&self) -> &'a [u8] {
        let end = self.payload_end();
        self.buffer.get(offset::PAYLOAD..end).unwrap_or_default()
    }
}

impl<T: AsRef<[u8]> + AsMut<[u8]>> Frame<T> {
    /// Writes the sync bytes of `direction` and the length field (the whole package).
    pub fn set_start(&mut self, direction: Direction, total_len: u16) {
        let [s0, s1] = sync_of(direction);
        let [l0, l1] = total_len.to_le_bytes();
        self.set_byte(offset::SYNC, s0);
        self.set_byte(offset::SYNC + 1, s1);
        self.set_byte(offset::LENGTH, l0);
        self.set_byte(offset::LENGTH + 1, l1);
    }

    /// Sets the version byte.
    pub fn set_version(&mut self, version: u8) {
        self.set_byte(offset::VERSION, version);
    }

    /// Sets the message id (the order byte).
    pub fn set_id(&mut self, id: u8) {
        self.set_byte(offset::ORDER, id);
    }

    /// The main data frame, writable.
    pub fn main_mut(&mut self) -> &mut [u8] {
        self.buffer
            .as_mut()
            .get_mut(offset::MAIN..offset::SUB)
            .unwrap_or_default()
    }

    /// The sub data frame, writable.
    pub fn sub_mut(&mut self) -> &mut [u8] {
        self.buffer
            .as_mut()
            .get_mut(offset::SUB..offset::ORDER)
            .unwrap_or_default()
    }

    /// Both data frames (bytes 5..=68), writable.
    pub(super) fn frames_mut(&mut self) -> &mut [u8] {
        self.buffer
            .as_mut()
            .get_mut(offset::MAIN..offset::ORDER)
            .unwrap_or_default()
    }

    /// The payload, writable (the length field must be set first).
    pub fn payload_mut(&mut self) -> &mut [u8] {
        let end = self.payload_end();
        self.buffer
            .as_mut()
            .get_mut(offset::PAYLOAD..end)
            .unwrap_or_default()
    }

    /// Computes and stores the CRC (everything it covers must be set first).
    pub fn fill_checksum(&mut self) {
        let [hi, lo] = self.compute_checksum().to_be_bytes();
        let at = self.payload_end();
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
    /// Packages going `direction`.
    #[must_use]
    pub const fn new(direction: Direction) -> Self {
        GcuFraming { direction }
    }

    /// Packages from the host computer (`A8 E5`, [`Direction::ToGimbal`]): what a GCU,
    /// or a bridge acting as one, receives.
    #[must_use]
    pub const fn host() -> Self {
        GcuFraming::new(Direction::ToGimbal)
    }

    /// Packages from the GCU (`8A 5E`, [`Direction::FromGimbal`]): what the host
    /// computer receives.
    #[must_use]
    pub const fn gcu() -> Self {
        GcuFraming::new(Direction::FromGimbal)
    }
}

impl Framing for GcuFraming {
    fn sync(&self) -> &[u8] {
        match self.direction {
            Direction::ToGimbal => &HOST_SYNC,
            Direction::FromGimbal => &GCU_SYNC,
        }
    }

    fn header_len(&self) -> usize {
        offset::VERSION
    }

    fn frame_len(&self, header: &[u8]) -> Result<usize> {
        let lo = header
            .get(offset::LENGTH)
            .copied()
            .ok_or(Error::Truncated)?;
        let hi = header
            .get(offset::LENGTH + 1)
            .copied()
            .ok_or(Error::Truncated)?;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn setters_and_accessors_agree_on_the_offsets() {
        let mut buf = [0u8; 80];
        let mut f = Frame::new_unchecked(&mut buf[..]);
        f.set_start(Direction::FromGimbal, 75);
        f.set_version(0x02);
        f.main_mut().fill(0x11);
        f.sub_mut().fill(0x22);
        f.set_id(0x25);
        f.payload_mut().copy_from_slice(&[0x01, 0x02, 0x03]);
        f.fill_checksum();
        let bytes = f.into_inner();
        assert_eq!(&bytes[..5], &[0x8A, 0x5E, 75, 0, 0x02]);
        assert!(bytes[5..37].iter().all(|&b| b == 0x11));
        assert!(bytes[37..69].iter().all(|&b| b == 0x22));
        assert_eq!(&bytes[69..73], &[0x25, 0x01, 0x02, 0x03]);
        let f = Frame::new_checked(&bytes[..]).unwrap();
        f.verify().unwrap();
        assert_eq!(f.direction(), Some(Direction::FromGimbal));
        assert_eq!((f.total_len(), f.version(), f.id()), (75, 0x02, 0x25));
        assert_eq!(
            (f.payload_len(), f.payload(), f.payload_ref()),
            (3, &[1u8, 2, 3][..], &[1u8, 2, 3][..])
        );
        assert_eq!((f.main(), f.main_ref()), (&bytes[5..37], &bytes[5..37]));
        assert_eq!((f.sub(), f.sub_ref()), (&bytes[37..69], &bytes[37..69]));
        assert_eq!(f.checksum(), u16::from_be_bytes([bytes[73], bytes[74]]));
        assert_eq!((HEADER_LEN, MIN_FRAME_LEN, MAX_PAYLOAD_LEN), (70, 72, 185));
    }

    #[test]
    fn sync_bytes_name_the_direction() {
        for d in [Direction::ToGimbal, Direction::FromGimbal] {
            assert_eq!(direction_of(sync_of(d)), Some(d));
            assert_eq!(GcuFraming::new(d).sync(), &sync_of(d));
        }
        assert_eq!(sync_of(Direction::ToGimbal), HOST_SYNC);
        assert_eq!(GcuFraming::host(), GcuFraming::new(Direction::ToGimbal));
        assert_eq!(GcuFraming::gcu(), GcuFraming::new(Direction::FromGimbal));
        assert_eq!(direction_of([0xA8, 0x5E]), None);
    }
}
