//! The MAVLink 2 frame: `FD LEN INCOMPAT COMPAT SEQ SYSID COMPID MSGID(u24 LE) PAYLOAD
//! CRC(u16 LE) [SIGNATURE(13)]`, and the framing rules that also recognise MAVLink 1
//! frames (`FE LEN SEQ SYSID COMPID MSGID PAYLOAD CRC`) so as to skip them whole.

use crate::wire::{Framing, MCRF4XX};
use crate::{Error, Result};

use super::dialect::message_info;

/// Start byte of a MAVLink 2 frame.
pub const STX_V2: u8 = 0xFD;
/// Start byte of a MAVLink 1 frame (recognised and skipped, never delivered).
pub const STX_V1: u8 = 0xFE;
/// Bytes before the payload of a MAVLink 2 frame: STX to the message id.
pub const HEADER_LEN: usize = 10;
/// Bytes before the payload of a MAVLink 1 frame.
pub const V1_HEADER_LEN: usize = 6;
/// Bytes of the checksum.
pub const CHECKSUM_LEN: usize = 2;
/// Bytes of the signature of a signed frame: link id, 48-bit timestamp, 48-bit value.
pub const SIGNATURE_LEN: usize = 13;
/// Largest payload (the LEN byte).
pub const MAX_PAYLOAD_LEN: usize = 255;
/// Smallest MAVLink 2 frame (empty payload, unsigned).
pub const MIN_FRAME_LEN: usize = HEADER_LEN + CHECKSUM_LEN;
/// Largest MAVLink 2 frame (255 payload bytes, signed): 280 bytes.
pub const MAX_FRAME_LEN: usize = MIN_FRAME_LEN + MAX_PAYLOAD_LEN + SIGNATURE_LEN;
/// The deframer size for [`MavlinkFraming::new`] (561 bytes): a frame of an unknown id
/// (up to [`MAX_FRAME_LEN`]), a frame starting inside it at its last byte and running past
/// it (up to [`MAX_FRAME_LEN`] more), and the byte after. With it every frame of an
/// unknown id is judged on all the bytes that can decide it.
pub const DEFRAMER_LEN: usize = 2 * MAX_FRAME_LEN + 1;
/// Incompatibility flag: the frame carries a signature.
pub const IFLAG_SIGNED: u8 = 0x01;

/// Byte offsets of the MAVLink 2 header fields.
mod offset {
    pub const STX: usize = 0;
    pub const LEN: usize = 1;
    pub const INCOMPAT: usize = 2;
    pub const COMPAT: usize = 3;
    pub const SEQ: usize = 4;
    pub const SYSID: usize = 5;
    pub const COMPID: usize = 6;
    pub const MSGID: usize = 7;
    /// The MAVLink 1 message id.
    pub const V1_MSGID: usize = 5;
}

/// CRC-16/MCRF4XX over `covered` (the frame after STX, up to the checksum), then the
/// message's CRC_EXTRA byte.
#[must_use]
pub fn checksum(covered: &[u8], crc_extra: u8) -> u16 {
    let mut digest = MCRF4XX.digest();
    digest.update(covered);
    digest.update(&[crc_extra]);
    digest.finalize()
}

wire_derive! {
    [Eq, Hash]
    /// The signature of a signed MAVLink 2 frame (see
    /// [`signature_matches`](super::signature_matches) and [`Signer`](super::Signer)).
    pub struct Signature {
        /// The link id.
        pub link_id: u8,
        /// The timestamp: 48 bits, in 10 µs since 2015-01-01 00:00:00 UTC.
        pub timestamp: u64,
        /// The first 48 bits of the SHA-256 signature.
        pub value: [u8; 6],
    }
}

impl Signature {
    /// The signature from its 13 bytes (`None` for another length).
    #[must_use]
    pub fn from_bytes(bytes: &[u8]) -> Option<Self> {
        let bytes: &[u8; SIGNATURE_LEN] = bytes.try_into().ok()?;
        let [link_id, t0, t1, t2, t3, t4, t5, v0, v1, v2, v3, v4, v5] = *bytes;
        Some(Signature {
            link_id,
            timestamp: u64::from_le_bytes([t0, t1, t2, t3, t4, t5, 0, 0]),
            value: [v0, v1, v2, v3, v4, v5],
        })
    }

    /// The 13 bytes (the timestamp's bits above 48 are not sent).
    #[must_use]
    pub fn to_bytes(&self) -> [u8; SIGNATURE_LEN] {
        let [t0, t1, t2, t3, t4, t5, _, _] = self.timestamp.to_le_bytes();
        let [v0, v1, v2, v3, v4, v5] = self.value;
        [self.link_id, t0, t1, t2, t3, t4, t5, v0, v1, v2, v3, v4, v5]
    }
}

frame_view! {
    /// A read-only or read-write view of a MAVLink 2 frame in a byte buffer.
    ///
    /// [`Frame::new_checked`] guarantees the buffer starts with STX 0xFD, has only known
    /// incompatibility flags and holds the whole frame (header, LEN payload bytes,
    /// checksum, and the signature when flagged); accessors never panic, even unchecked.
    /// Bytes after the frame are ignored.
}

impl<T: AsRef<[u8]>> Frame<T> {
    /// Checks STX, the incompatibility flags and that the buffer holds the whole frame.
    ///
    /// # Errors
    /// [`Error::BadSync`] when the buffer does not start with 0xFD (a MAVLink 1 frame
    /// too), [`Error::OutOfRange`] for an incompatibility flag other than
    /// [`IFLAG_SIGNED`] (the spec: drop what you do not understand),
    /// [`Error::Truncated`] when the buffer is shorter than the frame.
    pub fn check_len(&self) -> Result<()> {
        let b = self.buffer.as_ref();
        match b.first() {
            Some(&STX_V2) => {}
            Some(_) => return Err(Error::BadSync),
            None => return Err(Error::Truncated),
        }
        if b.len() < HEADER_LEN {
            return Err(Error::Truncated);
        }
        if self.incompat_flags() & !IFLAG_SIGNED != 0 {
            return Err(Error::OutOfRange);
        }
        if b.len() < self.total_len() {
            return Err(Error::Truncated);
        }
        Ok(())
    }

    /// The LEN byte: number of payload bytes.
    #[must_use]
    pub fn payload_len(&self) -> usize {
        usize::from(self.byte(offset::LEN))
    }

    /// The incompatibility flags.
    #[must_use]
    pub fn incompat_flags(&self) -> u8 {
        self.byte(offset::INCOMPAT)
    }

    /// The compatibility flags (ignored by receivers that do not know them).
    #[must_use]
    pub fn compat_flags(&self) -> u8 {
        self.byte(offset::COMPAT)
    }

    /// Whether the frame carries a signature.
    #[must_use]
    pub fn is_signed(&self) -> bool {
        self.incompat_flags() & IFLAG_SIGNED != 0
    }

    /// The sequence number.
    #[must_use]
    pub fn sequence(&self) -> u8 {
        self.byte(offset::SEQ)
    }

    /// The sender's system id.
    #[must_use]
    pub fn system_id(&self) -> u8 {
        self.byte(offset::SYSID)
    }

    /// The sender's component id.
    #[must_use]
    pub fn component_id(&self) -> u8 {
        self.byte(offset::COMPID)
    }

    /// The message id (24 bits).
    #[must_use]
    pub fn message_id(&self) -> u32 {
        u32::from_le_bytes([
            self.byte(offset::MSGID),
            self.byte(offset::MSGID.saturating_add(1)),
            self.byte(offset::MSGID.saturating_add(2)),
            0,
        ])
    }

    fn payload_range(&self) -> core::ops::Range<usize> {
        HEADER_LEN..HEADER_LEN.saturating_add(self.payload_len())
    }

    /// The payload as sent (MAVLink 2 senders drop trailing zero bytes).
    #[must_use]
    pub fn payload(&self) -> &[u8] {
        self.buffer
            .as_ref()
            .get(self.payload_range())
            .unwrap_or_default()
    }

    /// Offset of the checksum.
    fn checksum_at(&self) -> usize {
        HEADER_LEN.saturating_add(self.payload_len())
    }

    /// The checksum the frame carries.
    #[must_use]
    pub fn checksum(&self) -> u16 {
        let at = self.checksum_at();
        u16::from_le_bytes([self.byte(at), self.byte(at.saturating_add(1))])
    }

    /// The signature, when the frame is signed.
    #[must_use]
    pub fn signature(&self) -> Option<Signature> {
        if !self.is_signed() {
            return None;
        }
        let at = self.checksum_at().saturating_add(CHECKSUM_LEN);
        let bytes = self
            .buffer
            .as_ref()
            .get(at..at.saturating_add(SIGNATURE_LEN))?;
        Signature::from_bytes(bytes)
    }

    /// Length of the whole frame, STX to checksum (and signature).
    #[must_use]
    pub fn total_len(&self) -> usize {
        let signature = if self.is_signed() { SIGNATURE_LEN } else { 0 };
        MIN_FRAME_LEN
            .saturating_add(self.payload_len())
            .saturating_add(signature)
    }

    /// The checksum computed over LEN..payload with `crc_extra`.
    #[must_use]
    pub fn compute_checksum(&self, crc_extra: u8) -> u16 {
        let covered = self
            .buffer
            .as_ref()
            .get(1..self.checksum_at())
            .unwrap_or_default();
        checksum(covered, crc_extra)
    }

    /// Verifies the checksum with the CRC_EXTRA of the message id.
    ///
    /// # Errors
    /// [`Error::UnknownId`] for an id outside the dialect (its CRC_EXTRA is unknown, so
    /// the checksum cannot be checked); [`Error::BadChecksum`].
    pub fn verify(&self) -> Result<()> {
        let info = message_info(self.message_id()).ok_or(Error::UnknownId)?;
        self.verify_with(info.crc_extra)
    }

    /// Verifies the checksum with a given CRC_EXTRA (for a message outside the dialect).
    ///
    /// # Errors
    /// [`Error::BadChecksum`].
    pub fn verify_with(&self, crc_extra: u8) -> Result<()> {
        let computed = self.compute_checksum(crc_extra);
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
    /// Writes STX, LEN and the incompatibility flags.
    pub fn set_start(&mut self, payload_len: u8, incompat_flags: u8) {
        self.set_byte(offset::STX, STX_V2);
        self.set_byte(offset::LEN, payload_len);
        self.set_byte(offset::INCOMPAT, incompat_flags);
    }

    /// Sets the compatibility flags.
    pub fn set_compat_flags(&mut self, flags: u8) {
        self.set_byte(offset::COMPAT, flags);
    }

    /// Sets the sequence number.
    pub fn set_sequence(&mut self, sequence: u8) {
        self.set_byte(offset::SEQ, sequence);
    }

    /// Sets the sender's system id.
    pub fn set_system_id(&mut self, id: u8) {
        self.set_byte(offset::SYSID, id);
    }

    /// Sets the sender's component id.
    pub fn set_component_id(&mut self, id: u8) {
        self.set_byte(offset::COMPID, id);
    }

    /// Sets the message id (its low 24 bits).
    pub fn set_message_id(&mut self, id: u32) {
        let [a, b, c, _] = id.to_le_bytes();
        self.set_byte(offset::MSGID, a);
        self.set_byte(offset::MSGID.saturating_add(1), b);
        self.set_byte(offset::MSGID.saturating_add(2), c);
    }

    /// The payload, writable (LEN must be set first).
    pub fn payload_mut(&mut self) -> &mut [u8] {
        let r = self.payload_range();
        self.buffer.as_mut().get_mut(r).unwrap_or_default()
    }

    /// Computes and stores the checksum with `crc_extra` (everything before it must be
    /// set first).
    pub fn fill_checksum(&mut self, crc_extra: u8) {
        let [lo, hi] = self.compute_checksum(crc_extra).to_le_bytes();
        let at = self.checksum_at();
        self.set_byte(at, lo);
        self.set_byte(at.saturating_add(1), hi);
    }

    /// Writes the signature after the checksum (the SIGNED flag must be set first).
    pub fn set_signature(&mut self, signature: &Signature) {
        let at = self.checksum_at().saturating_add(CHECKSUM_LEN);
        for (i, b) in signature.to_bytes().into_iter().enumerate() {
            self.set_byte(at.saturating_add(i), b);
        }
    }
}

wire_derive! {
    [Eq, Default]
    /// What the deframer does with a frame whose message id is outside the dialect: its
    /// checksum cannot be verified (CRC_EXTRA is per message).
    pub enum UnknownIds {
        /// Skip a MAVLink 2 frame of an unknown id whole when its header is plausible (no
        /// compatibility flag, an id below 65 536) and it is well framed: the byte right
        /// after it starts a frame (0xFD or 0xFE) or the line went idle right after it, and
        /// no frame that checks starts inside it ([`Event::Skipped`](crate::wire::Event::Skipped),
        /// counted in `frames_unknown`: an autopilot's ordinary messages the dialect does
        /// not know are neither errors nor garbage); reject any other (and every MAVLink 1
        /// frame of an unknown id) as [`UnknownIds::Reject`] does. A frame starting inside
        /// it counts whether it ends inside it or past its end (a frame cut short whose
        /// header reads on into the next frame's bytes hides nothing): see
        /// [`DEFRAMER_LEN`]. The default.
        #[default]
        Skip,
        /// Reject it as a candidate ([`Error::UnknownId`], counted with the checksum
        /// errors) and scan on from the byte after its STX: an unverifiable "frame" can
        /// then never swallow a valid frame behind it, and its bytes count as garbage.
        Reject,
        /// Deliver it unverified (for a router or a capture tool that forwards what it does
        /// not know). A false STX in noise with a plausible length is then delivered as a
        /// frame too, hiding up to 280 bytes behind it.
        Deliver,
    }
}

wire_derive! {
    [Eq, Default]
    /// MAVLink framing rules for the [`Deframer`](crate::wire::Deframer): MAVLink 2 frames
    /// (STX 0xFD, length from LEN and the SIGNED flag, checksum with the message's
    /// CRC_EXTRA) are delivered; MAVLink 1 frames (STX 0xFE) whose checksum checks are
    /// skipped whole ([`Event::Skipped`](crate::wire::Event::Skipped), counted in
    /// `frames_skipped`), so that neither their bytes nor a 0xFD inside them are scanned
    /// as MAVLink 2. A MAVLink 1 candidate that does not check is rejected like any other,
    /// so a 0xFE inside noise or a corrupted MAVLink 2 frame cannot hide what follows it.
    ///
    /// Use a deframer of [`DEFRAMER_LEN`] (561) bytes:
    /// `Deframer::<MavlinkFraming, DEFRAMER_LEN>::new(MavlinkFraming::new())`. A frame of
    /// an unknown id is judged by the byte after it and by every frame starting inside it,
    /// which may run up to [`MAX_FRAME_LEN`] bytes past its end. With a smaller buffer
    /// (at least [`MAX_FRAME_LEN`] + 1), no valid frame is lost either, but a frame of an
    /// unknown id whose deciding bytes do not fit is rejected and its bytes scanned again
    /// (counted as a checksum error and garbage).
    pub struct MavlinkFraming {
        /// What to do with message ids outside the dialect.
        pub unknown_ids: UnknownIds,
    }
}

impl MavlinkFraming {
    /// Framing that skips well-framed frames of ids outside the dialect
    /// ([`UnknownIds::Skip`]).
    #[must_use]
    pub const fn new() -> Self {
        MavlinkFraming {
            unknown_ids: UnknownIds::Skip,
        }
    }

    /// Framing that delivers ids outside the dialect unverified ([`UnknownIds::Deliver`]).
    #[must_use]
    pub const fn delivering_unknown_ids() -> Self {
        MavlinkFraming {
            unknown_ids: UnknownIds::Deliver,
        }
    }

    /// Checks `covered` (LEN to the end of the payload) against `received` with the
    /// CRC_EXTRA of `id`, or by the unknown-id rule.
    fn check_crc(self, id: u32, covered: &[u8], received: u16) -> Result<()> {
        let Some(info) = message_info(id) else {
            return match self.unknown_ids {
                UnknownIds::Skip | UnknownIds::Reject => Err(Error::UnknownId),
                UnknownIds::Deliver => Ok(()),
            };
        };
        let computed = checksum(covered, info.crc_extra);
        if computed == received {
            Ok(())
        } else {
            Err(Error::BadChecksum { computed, received })
        }
    }
}

impl Framing for MavlinkFraming {
    fn sync(&self) -> &[u8] {
        &[STX_V2]
    }

    fn starts_like_frame(&self, buf: &[u8]) -> bool {
        matches!(buf.first(), Some(&(STX_V2 | STX_V1)))
    }

    /// STX, LEN and the incompatibility flags (MAVLink 1: its sequence number).
    fn header_len(&self) -> usize {
        3
    }

    fn frame_len(&self, header: &[u8]) -> Result<usize> {
        let (Some(&stx), Some(&len), Some(&flags)) = (header.first(), header.get(1), header.get(2))
        else {
            return Err(Error::Truncated);
        };
        let len = usize::from(len);
        match stx {
            STX_V2 if flags & !IFLAG_SIGNED != 0 => Err(Error::OutOfRange),
            STX_V2 if flags & IFLAG_SIGNED != 0 => Ok(MIN_FRAME_LEN
                .saturating_add(len)
                .saturating_add(SIGNATURE_LEN)),
            STX_V2 => Ok(MIN_FRAME_LEN.saturating_add(len)),
            STX_V1 => Ok(V1_HEADER_LEN
                .saturating_add(len)
                .saturating_add(CHECKSUM_LEN)),
            _ => Err(Error::BadSync),
        }
    }

    fn check(&self, frame: &[u8]) -> Result<()> {
        let (header_len, id) = match frame.first() {
            Some(&STX_V2) => (HEADER_LEN, Frame::new_unchecked(frame).message_id()),
            Some(&STX_V1) => (
                V1_HEADER_LEN,
                u32::from(frame.get(offset::V1_MSGID).copied().unwrap_or(0)),
            ),
            _ => return Err(Error::BadSync),
        };
        let len = usize::from(frame.get(offset::LEN).copied().unwrap_or(0));
        let end = header_len.saturating_add(len);
        let (Some(covered), Some(&[lo, hi])) = (
            frame.get(1..end),
            frame.get(end..end.saturating_add(CHECKSUM_LEN)),
        ) else {
            return Err(Error::Truncated);
        };
        self.check_crc(id, covered, u16::from_le_bytes([lo, hi]))
    }

    fn skip(&self, frame: &[u8]) -> bool {
        frame.first() == Some(&STX_V1)
    }

    /// A MAVLink 2 frame of an unknown id whose header is otherwise as every MAVLink 2
    /// sender writes it: no compatibility flag (none is defined) and an id below 65 536
    /// (every dialect's). A MAVLink 1 header has nothing more to check: a MAVLink 1 frame
    /// of an unknown id stays rejected (a 0xFE in noise would pass too often).
    fn uncheckable(&self, frame: &[u8], error: &Error) -> bool {
        let view = Frame::new_unchecked(frame);
        self.unknown_ids == UnknownIds::Skip
            && matches!(error, Error::UnknownId)
            && frame.first() == Some(&STX_V2)
            && view.compat_flags() == 0
            && view.message_id() <= 0xFFFF
    }
}
