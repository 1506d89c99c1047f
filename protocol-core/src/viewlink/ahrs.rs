//! M, the AHRS (flight controller) sensor packet of frame 0xB1.

use super::block::{Block, Date, TimeCs};
use crate::wire::encoding::{Be, Field};
use crate::wire::{Reader, Writer};
use crate::{Error, Result};

wire_struct! {
    Be;
    /// The attitude group of M (bytes 9..14 when every group is present). Order: roll,
    /// pitch, yaw (Viewlink serial command protocol V3.4.4, 3.19, labels bytes 9..10
    /// "tilt"; ArduPilot fixed the swap this typo caused; see
    /// docs/src/protocols/viewlink.md).
    pub struct MAttitude {
        /// Vehicle roll, 360/65536°, positive right.
        pub roll_bam16: i16,
        /// Vehicle pitch, 360/65536°, positive up.
        pub pitch_bam16: i16,
        /// Vehicle yaw, 360/65536°, 0 north, positive east.
        pub yaw_bam16: i16,
    }
}

wire_struct! {
    Be;
    /// The GPS group of M (bytes 15..42 when every group is present, 28 bytes).
    pub struct MGps {
        /// UTC date.
        pub date: Date,
        /// UTC time of day, 0.01 s.
        pub time: TimeCs,
        /// GPS yaw (course over ground), 360/65536°.
        pub gps_yaw_bam16: i16,
        /// Position mark bits (reserved): bit 0 new position, bit 1 clock fix, bit 2
        /// horizontal, bit 3 height calculated. ArduPilot sends 0x0F.
        pub position_mark: u8,
        /// Latitude, 1e-7°.
        pub lat_e7: i32,
        /// Longitude, 1e-7°.
        pub lon_e7: i32,
        /// Height, mm (ArduPilot sends altitude above mean sea level).
        pub height_mm: i32,
        /// Ground speed north, 0.01 m/s.
        pub vel_north_cm_s: i16,
        /// Ground speed east, 0.01 m/s.
        pub vel_east_cm_s: i16,
        /// Vertical dilution of precision times 100.
        pub vdop_x100: u16,
        /// Ground speed down, 0.01 m/s.
        pub vel_down_cm_s: i16,
    }
}

wire_derive! {
    [Eq, Hash, Default]
    /// M, AHRS sensor output (frame 0xB1, 8..=42 bytes).
    ///
    /// Byte 1 is the data type: bit 0 attitude, bit 1 GPS, bit 2 gyro; only the groups its
    /// bits select are present, in that order. The document defines no bytes for the gyro
    /// group, so bit 2 adds none; bits 3..7 add none either. Bytes 2..8 (reserved) are
    /// always present. The attitude and GPS bits follow from the groups present, so an M
    /// value cannot disagree with its own data type.
    pub struct M {
        /// Byte 1 without bits 0 and 1: bit 2 gyro, bits 3..7 reserved.
        pub type_bits: u8,
        /// Bytes 2..8, reserved.
        pub reserved: [u8; 7],
        /// The attitude group (data type bit 0).
        pub attitude: Option<MAttitude>,
        /// The GPS group (data type bit 1).
        pub gps: Option<MGps>,
    }
}

impl M {
    /// Data type bit 0: attitude group present.
    pub const ATTITUDE: u8 = 1 << 0;
    /// Data type bit 1: GPS group present.
    pub const GPS: u8 = 1 << 1;
    /// Data type bit 2: gyro data (no bytes defined).
    pub const GYRO: u8 = 1 << 2;
    /// Smallest M data (type byte and reserved bytes).
    pub const MIN_LEN: usize = 8;
    /// Largest M data (every group).
    pub const MAX_LEN: usize = 42;

    /// An M packet with the given groups and the gyro bit set, as ArduPilot sends it
    /// (data type 0x07 when both groups are present).
    #[must_use]
    pub const fn new(attitude: Option<MAttitude>, gps: Option<MGps>) -> Self {
        M {
            type_bits: Self::GYRO,
            reserved: [0; 7],
            attitude,
            gps,
        }
    }

    /// Byte 1 as sent: `type_bits` with the bits of the groups present.
    #[must_use]
    pub const fn data_type(&self) -> u8 {
        let mut t = self.type_bits & !(Self::ATTITUDE | Self::GPS);
        if self.attitude.is_some() {
            t |= Self::ATTITUDE;
        }
        if self.gps.is_some() {
            t |= Self::GPS;
        }
        t
    }
}

impl Block for M {
    const MAX_LEN: usize = Self::MAX_LEN;

    fn read_block(r: &mut Reader<'_>) -> Result<Self> {
        let t = r.u8()?;
        let reserved = r.array()?;
        let attitude = if t & Self::ATTITUDE != 0 {
            Some(MAttitude::read(r)?)
        } else {
            None
        };
        let gps = if t & Self::GPS != 0 {
            Some(MGps::read(r)?)
        } else {
            None
        };
        if !r.is_empty() {
            return Err(Error::BadLength);
        }
        Ok(M {
            type_bits: t & !(Self::ATTITUDE | Self::GPS),
            reserved,
            attitude,
            gps,
        })
    }

    fn write_block(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u8(self.data_type())?;
        w.put(&self.reserved)?;
        if let Some(a) = &self.attitude {
            a.write(w)?;
        }
        if let Some(g) = &self.gps {
            g.write(w)?;
        }
        Ok(())
    }

    fn block_len(&self) -> usize {
        let mut n = Self::MIN_LEN;
        if self.attitude.is_some() {
            n = n.saturating_add(<MAttitude as Field<Be>>::LEN);
        }
        if self.gps.is_some() {
            n = n.saturating_add(<MGps as Field<Be>>::LEN);
        }
        n
    }
}
