//! The K40T frame: `FD LEN DST_SYS DST_COMP SEQ SRC_SYS SRC_COMP MSGID(3, LE) PAYLOAD CRC(2, LE)`.

use crate::wire::{Framing, crc16_mcrf4xx};
use crate::{Error, Result};

/// Start-of-frame byte.
pub const STX: u8 = 0xFD;
/// Bytes before the payload.
pub const HEADER_LEN: usize = 10;
/// Bytes after the payload (the CRC).
pub const CRC_LEN: usize = 2;
/// Largest payload (LEN field): a frame is 12..=255 bytes.
pub const MAX_PAYLOAD_LEN: usize = 243;
/// Smallest frame (empty payload).
pub const MIN_FRAME_LEN: usize = HEADER_LEN + CRC_LEN;
/// Largest frame.
pub const MAX_FRAME_LEN: usize = MIN_FRAME_LEN + MAX_PAYLOAD_LEN;

/// Byte offsets of the header fields.
mod offset {
    pub const STX: usize = 0;
    pub const LEN: usize = 1;
    pub const DST_SYS: usize = 2;
    pub const DST_COMP: usize = 3;
    pub const SEQ: usize = 4;
    pub const SRC_SYS: usize = 5;
    pub const SRC_COMP: usize = 6;
    pub const MSG_ID: core::ops::Range<usize> = 7..10;
}

wire_derive! {
    [Eq, Hash, Default]
    /// A system/component address pair.
    #[cfg_attr(feature = "bake", derive(databake::Bake), databake(path = protocol_core::k40t))]
    pub struct Address {
        /// System id.
        pub system: u8,
        /// Component id.
        pub component: u8,
    }
}

impl Address {
    /// The APP (0x01/0x01).
    pub const APP: Address = Address::new(0x01, 0x01);
    /// The flight controller (0x02/0x01).
    pub const FLIGHT_CONTROLLER: Address = Address::new(0x02, 0x01);
    /// The gimbal, as section 3.1 of the document addresses it (0x03/0x01).
    pub const GIMBAL: Address = Address::new(0x03, 0x01);
    /// The four-sensor pod (camera), as section 2.1 and 3.2 address it (0x04/0x01).
    pub const POD: Address = Address::new(0x04, 0x01);

    /// An address from its two bytes.
    #[must_use]
    pub const fn new(system: u8, component: u8) -> Self {
        Address { system, component }
    }
}

code_enum! {
    /// What the high byte of a message id says the frame is.
    pub enum Kind: u8 {
        /// 0x00: a request or setting, or a periodic report.
        Request = 0x00,
        /// 0x01: the acknowledgement of a request.
        Ack = 0x01,
        /// 0x02: a status frame sent while a request executes.
        Status = 0x02,
    }
}

wire_derive! {
    [Eq, Hash]
    /// A 24-bit message id, seen as (kind, base id): 0x020304 is the status frame of 0x000304.
    pub struct MsgId {
        /// The high byte.
        pub kind: Kind,
        /// The low and middle bytes: the id of the request this frame belongs to.
        pub base: u16,
    }
}

impl MsgId {
    /// A message id from its parts.
    #[must_use]
    pub const fn new(kind: Kind, base: u16) -> Self {
        MsgId { kind, base }
    }

    /// The id as the 24-bit number the document prints (0x010304).
    #[must_use]
    pub const fn to_u32(self) -> u32 {
        ((self.kind.value() as u32) << 16) | self.base as u32
    }

    /// The id from a 24-bit number; bits above 23 are ignored.
    #[must_use]
    pub const fn from_u32(id: u32) -> Self {
        let [lo, mid, hi, _] = id.to_le_bytes();
        MsgId {
            kind: Kind::from_value(hi),
            base: u16::from_le_bytes([lo, mid]),
        }
    }

    /// The three bytes on the wire (low, middle, high).
    #[must_use]
    pub const fn to_bytes(self) -> [u8; 3] {
        let [lo, mid] = self.base.to_le_bytes();
        [lo, mid, self.kind.value()]
    }

    /// The id from its three wire bytes (low, middle, high).
    #[must_use]
    pub const fn from_bytes(b: [u8; 3]) -> Self {
        let [lo, mid, hi] = b;
        MsgId {
            kind: Kind::from_value(hi),
            base: u16::from_le_bytes([lo, mid]),
        }
    }
}

wire_derive! {
    [Eq, Hash, Default]
    /// Which bytes the CRC covers. The document does not say (K40T external protocol, 2.1,
    /// names the checksum only; see docs/src/protocols/k40t.md).
    #[cfg_attr(feature = "bake", derive(databake::Bake), databake(path = protocol_core::k40t))]
    pub enum CrcCoverage {
        /// LEN through the last payload byte (as MAVLink v2, without CRC_EXTRA). The default.
        #[default]
        ExcludeStx,
        /// STX through the last payload byte.
        IncludeStx,
    }
}

frame_view! {
    /// A read-only or read-write view of a K40T frame in a byte buffer.
    ///
    /// [`Frame::new_checked`] guarantees the accessors never panic: the buffer starts with
    /// STX and holds at least the header, the LEN-byte payload and the CRC. Bytes after the
    /// frame are ignored.
}

impl<T: AsRef<[u8]>> Frame<T> {
    /// Checks STX, the LEN limit and that the buffer holds the whole frame.
    ///
    /// # Errors
    /// [`Error::Truncated`] for a buffer shorter than the frame (or empty),
    /// [`Error::BadSync`] when it does not start with STX, [`Error::BadLength`] for a LEN
    /// above 243.
    pub fn check_len(&self) -> Result<()> {
        let b = self.buffer.as_ref();
        match b.first() {
            None => return Err(Error::Truncated),
            Some(&STX) => {}
            Some(_) => return Err(Error::BadSync),
        }
        let len = b.get(offset::LEN).copied().ok_or(Error::Truncated)?;
        if usize::from(len) > MAX_PAYLOAD_LEN {
            return Err(Error::BadLength);
        }
        if b.len() < self.total_len() {
            return Err(Error::Truncated);
        }
        Ok(())
    }

    /// The LEN field: payload length.
    pub fn payload_len(&self) -> usize {
        usize::from(self.byte(offset::LEN))
    }

    /// Length of the whole frame, header to CRC.
    pub fn total_len(&self) -> usize {
        MIN_FRAME_LEN.saturating_add(self.payload_len())
    }

    /// Receiver address.
    pub fn dst(&self) -> Address {
        Address::new(self.byte(offset::DST_SYS), self.byte(offset::DST_COMP))
    }

    /// Packet sequence number.
    pub fn seq(&self) -> u8 {
        self.byte(offset::SEQ)
    }

    /// Sender address.
    pub fn src(&self) -> Address {
        Address::new(self.byte(offset::SRC_SYS), self.byte(offset::SRC_COMP))
    }

    /// The message id.
    pub fn id(&self) -> MsgId {
        let b = self.buffer.as_ref();
        let id = b
            .get(offset::MSG_ID)
            .and_then(|s| <[u8; 3]>::try_from(s).ok())
            .unwrap_or_default();
        MsgId::from_bytes(id)
    }

    /// The payload: the bytes between the message id and the CRC (empty when the buffer
    /// is shorter than LEN says).
    pub fn payload(&self) -> &[u8] {
        let end = HEADER_LEN.saturating_add(self.payload_len());
        self.buffer
            .as_ref()
            .get(HEADER_LEN..end)
            .unwrap_or_default()
    }

    /// The CRC the frame carries.
    pub fn checksum(&self) -> u16 {
        let at = self.total_len().saturating_sub(CRC_LEN);
        u16::from_le_bytes([self.byte(at), self.byte(at.saturating_add(1))])
    }

    /// The CRC computed over the frame with the given coverage.
    pub fn compute_checksum(&self, coverage: CrcCoverage) -> u16 {
        let start = match coverage {
            CrcCoverage::ExcludeStx => offset::LEN,
            CrcCoverage::IncludeStx => offset::STX,
        };
        let end = self.total_len().saturating_sub(CRC_LEN);
        crc16_mcrf4xx(self.buffer.as_ref().get(start..end).unwrap_or_default())
    }

    /// Verifies the CRC with the given coverage.
    ///
    /// # Errors
    /// [`Error::BadChecksum`] when the carried CRC differs from the computed one.
    pub fn verify(&self, coverage: CrcCoverage) -> Result<()> {
        let computed = self.compute_checksum(coverage);
        let received = self.checksum();
        if computed == received {
            Ok(())
        } else {
            Err(Error::BadChecksum { computed, received })
        }
    }

    /// Which coverage makes this frame's CRC valid, if any. When both do (one frame in
    /// 65536), the default [`CrcCoverage::ExcludeStx`] is reported.
    pub fn detect_coverage(&self) -> Option<CrcCoverage> {
        [CrcCoverage::ExcludeStx, CrcCoverage::IncludeStx]
            .into_iter()
            .find(|&c| self.verify(c).is_ok())
    }
}

impl<'a> Frame<&'a [u8]> {
    /// The payload, borrowed for the lifetime of the underlying buffer.
    #[must_use]
    pub fn payload_ref(&self) -> &'a [u8] {
        let end = HEADER_LEN.saturating_add(self.payload_len());
        self.buffer.get(HEADER_LEN..end).unwrap_or_default()
    }
}

impl<T: AsRef<[u8]> + AsMut<[u8]>> Frame<T> {
    /// Writes STX and the LEN field.
    pub fn set_start(&mut self, payload_len: u8) {
        self.set_byte(offset::STX, STX);
        self.set_byte(offset::LEN, payload_len);
    }

    /// Sets the receiver address.
    pub fn set_dst(&mut self, a: Address) {
        self.set_byte(offset::DST_SYS, a.system);
        self.set_byte(offset::DST_COMP, a.component);
    }

    /// Sets the sequence number.
    pub fn set_seq(&mut self, seq: u8) {
        self.set_byte(offset::SEQ, seq);
    }

    /// Sets the sender address.
    pub fn set_src(&mut self, a: Address) {
        self.set_byte(offset::SRC_SYS, a.system);
        self.set_byte(offset::SRC_COMP, a.component);
    }

    /// Sets the message id.
    pub fn set_id(&mut self, id: MsgId) {
        for (i, b) in offset::MSG_ID.zip(id.to_bytes()) {
            self.set_byte(i, b);
        }
    }

    /// The payload, writable (LEN must be set first).
    pub fn payload_mut(&mut self) -> &mut [u8] {
        let end = HEADER_LEN.saturating_add(self.payload_len());
        self.buffer
            .as_mut()
            .get_mut(HEADER_LEN..end)
            .unwrap_or_default()
    }

    /// Computes and stores the CRC (LEN and everything it covers must be set first).
    pub fn fill_checksum(&mut self, coverage: CrcCoverage) {
        let crc = self.compute_checksum(coverage).to_le_bytes();
        let at = self.total_len().saturating_sub(CRC_LEN);
        self.set_byte(at, crc[0]);
        self.set_byte(at.saturating_add(1), crc[1]);
    }
}

/// K40T framing rules for the [`Deframer`](crate::wire::Deframer).
///
/// `coverage: None` accepts a frame valid under either CRC coverage (use
/// [`Frame::detect_coverage`] to learn which one the peer uses); `Some(c)` accepts only `c`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct K40tFraming {
    /// The accepted CRC coverage.
    pub coverage: Option<CrcCoverage>,
}

impl K40tFraming {
    /// Accept only frames with the given coverage.
    #[must_use]
    pub const fn with(coverage: CrcCoverage) -> Self {
        K40tFraming {
            coverage: Some(coverage),
        }
    }

    /// Accept frames with either coverage.
    #[must_use]
    pub const fn any() -> Self {
        K40tFraming { coverage: None }
    }
}

impl Framing for K40tFraming {
    fn sync(&self) -> &[u8] {
        &[STX]
    }

    fn header_len(&self) -> usize {
        2
    }

    fn frame_len(&self, header: &[u8]) -> Result<usize> {
        let len = usize::from(header.get(offset::LEN).copied().ok_or(Error::Truncated)?);
        if len > MAX_PAYLOAD_LEN {
            return Err(Error::BadLength);
        }
        Ok(MIN_FRAME_LEN.saturating_add(len))
    }

    fn check(&self, frame: &[u8]) -> Result<()> {
        let frame = Frame::new_checked(frame)?;
        match self.coverage {
            Some(c) => frame.verify(c),
            None => match frame.detect_coverage() {
                Some(_) => Ok(()),
                None => frame.verify(CrcCoverage::default()),
            },
        }
    }
}
