//! The small packets: handshake, heartbeat, ACK, SD card query and feedback, IP query,
//! set and feedback, AI identification feedback (0xF3), KLV (0xF4) and transparent
//! data (0xFF).

use super::block::{Block, Bytes, FixedBlock};
use super::frame::MAX_PAYLOAD_LEN;
use crate::wire::encoding::Field;
use crate::wire::{Reader, Writer};
use crate::{Error, Result};

wire_struct! {
    Be;
    /// Handshake (frame 0x00, 1 byte). ArduPilot sends `0x00` and expects a 0x40 status
    /// frame in reply.
    pub struct Handshake {
        /// The byte (0x00).
        pub value: u8,
    }
}

wire_struct! {
    Be;
    /// Heartbeat (frame 0x10, 1 byte). A heartbeat asks for a 0x40 status frame.
    pub struct Heartbeat {
        /// The data byte (the document gives it no meaning; ArduPilot sends 0).
        pub value: u8,
    }
}

wire_struct! {
    Be;
    /// ACK (frame 0xAC, 1 byte): the gimbal received a frame. The document's example is
    /// `AA 55 DC 04 AC 1A B2` (ACK of an A1 frame, printed with swapped sync bytes).
    pub struct Ack {
        /// The id of the frame acknowledged.
        pub acked_id: u8,
    }
}

code_enum! {
    /// SD card query command (frame 0x5D byte 1).
    pub enum SdCommand: u8 {
        /// No action.
        NoAction = 0x00,
        /// Format the SD card.
        Format = 0x8A,
        /// Query the SD card (byte 2 says what).
        Query = 0x8B,
    }
}

code_enum! {
    /// What an SD card query asks (frame 0x5D byte 2). Note: the feedback (0xD5) numbers
    /// the same items one lower.
    pub enum SdQueryItem: u8 {
        None = 0x00,
        /// Card status.
        Status = 0x02,
        /// Total capacity.
        TotalCapacity = 0x03,
        /// Remaining capacity.
        RemainingCapacity = 0x04,
        /// Remaining number of pictures.
        RemainingPictures = 0x05,
        /// Remaining recording time.
        RemainingVideo = 0x06,
    }
}

wire_struct! {
    Be;
    /// SD card query (frame 0x5D, 2 bytes).
    pub struct SdQuery {
        /// Byte 1: the command.
        pub command: SdCommand,
        /// Byte 2: the item queried (with [`SdCommand::Query`]).
        pub item: SdQueryItem,
    }
}

code_enum! {
    /// SD card feedback command (frame 0xD5 byte 1).
    pub enum SdFeedbackCommand: u8 {
        /// No meaning.
        None = 0x00,
        /// Card status.
        Status = 0x01,
        /// Total capacity (MB).
        TotalCapacity = 0x02,
        /// Remaining capacity (MB).
        RemainingCapacity = 0x03,
        /// Remaining number of pictures.
        RemainingPictures = 0x04,
        /// Remaining recording time (s).
        RemainingVideo = 0x05,
    }
}

bit_set! {
    /// SD card state bits (0xD5 status, byte 2).
    pub struct SdStateFlags(u8) {
        /// Bit 0: inserted.
        0 => inserted, with_inserted;
        /// Bit 1: initialising.
        1 => initializing, with_initializing;
        /// Bit 2: read only.
        2 => read_only, with_read_only;
        /// Bit 3: formatted.
        3 => formatted, with_formatted;
        /// Bit 4: formatting.
        4 => formatting, with_formatting;
        /// Bit 5: full.
        5 => full, with_full;
        /// Bit 6: verified.
        6 => verified, with_verified;
        /// Bit 7: invalid format.
        7 => invalid_format, with_invalid_format;
    }
}

bit_set! {
    /// SD card activity bits (0xD5 status, byte 3); bits 2..7 reserved.
    pub struct SdActivityFlags(u8) {
        /// Bit 0: error.
        0 => error, with_error;
        /// Bit 1: recording.
        1 => recording, with_recording;
    }
}

wire_struct! {
    Be;
    /// SD card status feedback (0xD5 command 0x01).
    pub struct SdStatus {
        /// Byte 2: state bits.
        pub state: SdStateFlags,
        /// Byte 3: activity bits.
        pub activity: SdActivityFlags,
        /// Bytes 4..5: reserved.
        pub reserved: [u8; 2],
    }
}

wire_struct! {
    Be;
    /// An SD capacity in MB (0xD5 commands 0x02, 0x03).
    pub struct SdCapacity {
        /// The capacity, in MB.
        pub mb: u32,
    }
}

wire_struct! {
    Be;
    /// Remaining pictures (0xD5 command 0x04).
    pub struct SdPictures {
        /// Number of pictures.
        pub count: u32,
    }
}

wire_struct! {
    Be;
    /// Remaining recording time (0xD5 command 0x05).
    pub struct SdVideoTime {
        /// The recording time left, in seconds.
        pub seconds: u32,
    }
}

viewlink_command_block! {
    /// SD card feedback (frame 0xD5, 5 bytes).
    pub enum SdFeedback: SdFeedbackCommand [4] {
        /// 0x01: status.
        Status(SdStatus) = Status,
        /// 0x02: total capacity.
        TotalCapacity(SdCapacity) = TotalCapacity,
        /// 0x03: remaining capacity.
        RemainingCapacity(SdCapacity) = RemainingCapacity,
        /// 0x04: remaining pictures.
        RemainingPictures(SdPictures) = RemainingPictures,
        /// 0x05: remaining recording time.
        RemainingVideo(SdVideoTime) = RemainingVideo,
    }
}

wire_struct! {
    Be;
    /// IP address query (frame 0x19, 1 byte).
    pub struct IpQuery {
        /// The control command (0 = query the IP address).
        pub command: u8,
    }
}

wire_struct! {
    Be;
    /// An IPv4 address (frames 0x29 set and 0x92 feedback, 4 bytes), first part first
    /// (192.168.2.119 is `C0 A8 02 77`).
    pub struct IpAddress {
        /// The four parts.
        pub octets: [u8; 4],
    }
}

code_enum! {
    /// Class of an identified target (0xF3). The document gives only bits 0..1 a
    /// meaning; the byte is kept whole.
    pub enum TargetClass: u8 {
        Car = 0x00,
        Human = 0x01,
        Logo = 0x02,
    }
}

wire_struct! {
    Be;
    /// One identified target of an 0xF3 packet (13 bytes).
    pub struct AiTarget {
        /// Target class.
        pub class: TargetClass,
        /// Target number (1..=999).
        pub number: u16,
        /// Horizontal offset of the target from the centre, px (negative left).
        pub x_px: i16,
        /// Vertical offset of the target from the centre, px (negative up).
        pub y_px: i16,
        /// Length of the target box, px.
        pub length_px: u16,
        /// Width of the target box, px.
        pub width_px: u16,
        /// Confidence, 0.0001 (max 10000 = 1).
        pub confidence_e4: u16,
    }
}

/// Most targets in one 0xF3 packet.
pub const MAX_AI_TARGETS: usize = 4;

wire_derive! {
    custom_serde [Eq, Hash, Default]
    /// AI identification feedback (frame 0xF3, 8 + 13 per target bytes, up to four targets
    /// per packet; N targets take ⌈N/4⌉ packets).
    pub struct AiTargets {
        /// Byte 1: total number of targets identified.
        pub total_targets: u8,
        /// Byte 2: total number of packets.
        pub total_packets: u8,
        /// Byte 3: number of this packet (0, 1, ...).
        pub packet_index: u8,
        /// Bytes 4..8: reserved.
        pub reserved: [u8; 5],
        count: u8,
        targets: [AiTarget; MAX_AI_TARGETS],
    }
}

impl AiTargets {
    /// A packet with the given header and targets.
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for more than four targets.
    pub fn new(
        total_targets: u8,
        total_packets: u8,
        packet_index: u8,
        targets: &[AiTarget],
    ) -> Result<Self> {
        let mut p = AiTargets {
            total_targets,
            total_packets,
            packet_index,
            ..AiTargets::default()
        };
        let dst = p
            .targets
            .get_mut(..targets.len())
            .ok_or(Error::OutOfRange)?;
        crate::wire::copy(dst, targets);
        p.count = u8::try_from(targets.len()).map_err(|_| Error::OutOfRange)?;
        Ok(p)
    }

    /// The targets of this packet.
    #[must_use]
    pub fn targets(&self) -> &[AiTarget] {
        self.targets
            .get(..usize::from(self.count))
            .unwrap_or_default()
    }
}

#[cfg(feature = "serde")]
impl serde::Serialize for AiTargets {
    fn serialize<S: serde::Serializer>(&self, s: S) -> core::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut out = s.serialize_struct("AiTargets", 5)?;
        out.serialize_field("total_targets", &self.total_targets)?;
        out.serialize_field("total_packets", &self.total_packets)?;
        out.serialize_field("packet_index", &self.packet_index)?;
        out.serialize_field("reserved", &self.reserved)?;
        out.serialize_field("targets", self.targets())?;
        out.end()
    }
}

impl Block for AiTargets {
    const MAX_LEN: usize = 8 + MAX_AI_TARGETS * <AiTarget as FixedBlock>::LEN;

    fn read_block(r: &mut Reader<'_>) -> Result<Self> {
        let mut p = AiTargets {
            total_targets: r.u8()?,
            total_packets: r.u8()?,
            packet_index: r.u8()?,
            reserved: r.array()?,
            ..AiTargets::default()
        };
        let rest = r.rest();
        if !rest.len().is_multiple_of(<AiTarget as FixedBlock>::LEN) {
            return Err(Error::BadLength);
        }
        let mut t = Reader::new(rest);
        for slot in &mut p.targets {
            if t.is_empty() {
                break;
            }
            *slot = AiTarget::read(&mut t)?;
            p.count = p.count.saturating_add(1);
        }
        if !t.is_empty() {
            return Err(Error::BadLength);
        }
        Ok(p)
    }

    fn write_block(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u8(self.total_targets)?;
        w.u8(self.total_packets)?;
        w.u8(self.packet_index)?;
        w.put(&self.reserved)?;
        if usize::from(self.count) > MAX_AI_TARGETS {
            return Err(Error::OutOfRange);
        }
        for t in self.targets() {
            t.write(w)?;
        }
        Ok(())
    }

    fn block_len(&self) -> usize {
        <AiTarget as FixedBlock>::LEN
            .saturating_mul(usize::from(self.count).min(MAX_AI_TARGETS))
            .saturating_add(8)
    }
}

/// Most KLV data bytes in one 0xF4 packet.
pub const KLV_CHUNK: usize = 57;

wire_derive! {
    [Eq, Hash, Default]
    /// KLV data for the video processing board (frame 0xF4): 3 header bytes and up to 57
    /// data bytes. The document sends 114 bytes of KLV in two packets of 57; the data bytes
    /// are kept exactly as received (padding included), `valid_len` says how many count.
    pub struct Klv {
        /// Byte 1: total number of packets (2).
        pub total_packets: u8,
        /// Byte 2: number of this packet (0 or 1).
        pub packet_index: u8,
        /// Byte 3: number of valid data bytes in this packet (1..=57).
        pub valid_len: u8,
        /// Bytes 4..: the data bytes on the wire.
        pub data: Bytes<KLV_CHUNK>,
    }
}

impl Klv {
    /// The valid KLV bytes (`valid_len` of `data`, at most what is present).
    #[must_use]
    pub fn payload(&self) -> &[u8] {
        let d = self.data.as_slice();
        d.get(..usize::from(self.valid_len)).unwrap_or(d)
    }
}

impl Block for Klv {
    const MAX_LEN: usize = 3 + KLV_CHUNK;

    fn read_block(r: &mut Reader<'_>) -> Result<Self> {
        Ok(Klv {
            total_packets: r.u8()?,
            packet_index: r.u8()?,
            valid_len: r.u8()?,
            data: Bytes::read_rest(r)?,
        })
    }

    fn write_block(&self, w: &mut Writer<'_>) -> Result<()> {
        w.put(&[self.total_packets, self.packet_index, self.valid_len])?;
        w.put(self.data.as_slice())
    }

    fn block_len(&self) -> usize {
        3usize.saturating_add(self.data.len())
    }
}

wire_derive! {
    [Eq, Hash, Default]
    /// Transparent data (frame 0xFF): bytes passed through the gimbal, 1..=60 of them,
    /// kept as received.
    pub struct Transparent {
        /// The bytes passed through, as received.
        pub data: Bytes<MAX_PAYLOAD_LEN>,
    }
}

impl Transparent {
    /// Transparent data of `data`; more than 60 bytes is [`Error::OutOfRange`].
    ///
    /// # Errors
    /// [`Error::OutOfRange`] when `data` does not fit one frame.
    pub fn new(data: &[u8]) -> Result<Self> {
        Bytes::new(data).map(|data| Transparent { data })
    }
}

impl Block for Transparent {
    const MAX_LEN: usize = MAX_PAYLOAD_LEN;

    fn read_block(r: &mut Reader<'_>) -> Result<Self> {
        Bytes::read_rest(r).map(|data| Transparent { data })
    }

    fn write_block(&self, w: &mut Writer<'_>) -> Result<()> {
        w.put(self.data.as_slice())
    }

    fn block_len(&self) -> usize {
        self.data.len()
    }
}

// Every fixed-size packet here is what the document says.
const _: () = {
    assert!(<SdQuery as FixedBlock>::LEN == 2);
    assert!(<SdFeedback as FixedBlock>::LEN == 5);
    assert!(<IpAddress as FixedBlock>::LEN == 4);
    assert!(<AiTarget as FixedBlock>::LEN == 13);
};
