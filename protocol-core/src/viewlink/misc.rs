//! The small packets: handshake, heartbeat, ACK, SD card query and feedback, IP query,
//! set and feedback, AI identification feedback (0xF3), KLV (0xF4) and transparent
//! data (0xFF).

use super::field::{Block, Bytes, Field, FixedBlock};
use crate::wire::{Reader, Writer};
use crate::{Error, Result};

block! {
    /// Handshake (frame 0x00, 1 byte). ArduPilot sends `0x00` and expects a 0x40 status
    /// frame in reply.
    pub struct Handshake {
        /// The byte (0x00).
        pub value: u8,
    }
}

block! {
    /// Heartbeat (frame 0x10, 1 byte). A heartbeat asks for a 0x40 status frame.
    pub struct Heartbeat {
        /// The byte.
        pub value: u8,
    }
}

block! {
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
        /// None.
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

block! {
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

newtype! {
    /// SD card state bits (0xD5 status, byte 2): bit 0 inserted, 1 initialising, 2 read
    /// only, 3 formatted, 4 formatting, 5 full, 6 verified, 7 invalid format.
    pub struct SdStateFlags(u8);

    /// SD card activity bits (0xD5 status, byte 3): bit 0 error, bit 1 recording;
    /// others reserved.
    pub struct SdActivityFlags(u8);
}

impl SdStateFlags {
    /// Bit 0: inserted.
    pub const INSERTED: u8 = 1 << 0;
    /// Bit 1: initialising.
    pub const INITIALIZING: u8 = 1 << 1;
    /// Bit 2: read only.
    pub const READ_ONLY: u8 = 1 << 2;
    /// Bit 3: formatted.
    pub const FORMATTED: u8 = 1 << 3;
    /// Bit 4: formatting.
    pub const FORMATTING: u8 = 1 << 4;
    /// Bit 5: full.
    pub const FULL: u8 = 1 << 5;
    /// Bit 6: verified.
    pub const VERIFIED: u8 = 1 << 6;
    /// Bit 7: invalid format.
    pub const INVALID_FORMAT: u8 = 1 << 7;
}

impl SdActivityFlags {
    /// Bit 0: error.
    pub const ERROR: u8 = 1 << 0;
    /// Bit 1: recording.
    pub const RECORDING: u8 = 1 << 1;
}

block! {
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

block! {
    /// An SD capacity in MB (0xD5 commands 0x02, 0x03).
    pub struct SdCapacity {
        /// Megabytes.
        pub mb: u32,
    }
}

block! {
    /// Remaining pictures (0xD5 command 0x04).
    pub struct SdPictures {
        /// Number of pictures.
        pub count: u32,
    }
}

block! {
    /// Remaining recording time (0xD5 command 0x05).
    pub struct SdVideoTime {
        /// Seconds.
        pub seconds: u32,
    }
}

command_enum! {
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

block! {
    /// IP address query (frame 0x19, 1 byte).
    pub struct IpQuery {
        /// The control command (0 = query the IP address).
        pub command: u8,
    }
}

block! {
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
        /// Car.
        Car = 0x00,
        /// Human.
        Human = 0x01,
        /// Logo.
        Logo = 0x02,
    }
}

block! {
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

/// AI identification feedback (frame 0xF3, 8 + 13 per target bytes, up to four targets
/// per packet; N targets take ⌈N/4⌉ packets).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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

impl AiTargets {
    /// A packet with the given header and targets; more than four targets is
    /// [`Error::OutOfRange`].
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
        p.targets
            .get_mut(..targets.len())
            .ok_or(Error::OutOfRange)?
            .copy_from_slice(targets);
        p.count = u8::try_from(targets.len()).map_err(|_| Error::OutOfRange)?;
        Ok(p)
    }

    /// The targets of this packet.
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
        let mut st = s.serialize_struct("AiTargets", 5)?;
        st.serialize_field("total_targets", &self.total_targets)?;
        st.serialize_field("total_packets", &self.total_packets)?;
        st.serialize_field("packet_index", &self.packet_index)?;
        st.serialize_field("reserved", &self.reserved)?;
        st.serialize_field("targets", self.targets())?;
        st.end()
    }
}

impl<'a> Block<'a> for AiTargets {
    fn read_block(r: &mut Reader<'a>) -> Result<Self> {
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
        for slot in p.targets.iter_mut() {
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

/// KLV data for the video processing board (frame 0xF4): 3 header bytes and up to 57
/// data bytes. The document sends 114 bytes of KLV in two packets of 57; the data bytes
/// are kept exactly as received (padding included), `valid_len` says how many count.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
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

impl Klv {
    /// The valid KLV bytes (`valid_len` of `data`, at most what is present).
    pub fn payload(&self) -> &[u8] {
        let d = self.data.as_slice();
        d.get(..usize::from(self.valid_len)).unwrap_or(d)
    }
}

impl<'a> Block<'a> for Klv {
    fn read_block(r: &mut Reader<'a>) -> Result<Self> {
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

/// Transparent data (frame 0xFF): bytes passed through the gimbal, borrowed from the
/// frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Transparent<'a> {
    /// The data.
    pub data: &'a [u8],
}

impl<'a> Block<'a> for Transparent<'a> {
    fn read_block(r: &mut Reader<'a>) -> Result<Self> {
        Ok(Transparent { data: r.rest() })
    }

    fn write_block(&self, w: &mut Writer<'_>) -> Result<()> {
        w.put(self.data)
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
