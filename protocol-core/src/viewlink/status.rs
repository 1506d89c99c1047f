//! Payload-to-console status blocks: B1/B2 (servo), D1/D2 (optics), F1/F2 (tracker)
//! and T1/T2 (target calculation).

use super::block::{Date, TimeCs, bits8, byte_of, put_bits, put_bits8};
use super::control::ServoAction;
use super::enums::{ServoCommand, TrackerSensor, TrackerState, VideoSource};
use crate::Result;
use crate::wire::encoding::{Be, Field};
use crate::wire::{Reader, Writer};

// ---------------------------------------------------------------------------------- B1

wire_derive! {
    [Eq, Hash, Default]
    /// B1, servo status, commonly used (6 bytes).
    ///
    /// Roll is 12 bits (high 4 bits in byte 1 bits 0..3, low 8 bits in byte 2), 180/4095°
    /// per bit with 0 at -90° (ArduPilot reads `raw * 180 / 4095 - 90`; the document's
    /// prose is garbled): see [`B1::roll_cdeg`].
    pub struct B1 {
        /// Byte 1 bits 4..7: the servo status (a [`ServoCommand`] value 0..=15).
        pub servo: ServoCommand,
        /// The 12-bit roll value (0..=4095).
        pub roll_raw12: u16,
        /// Bytes 3..4: yaw, 360/65536° per bit.
        pub yaw_bam16: i16,
        /// Bytes 5..6: pitch, 360/65536° per bit (ArduPilot: positive down).
        pub pitch_bam16: i16,
    }
}

impl B1 {
    /// Roll in 0.01°: `roll_raw12 * 18000 / 4095 - 9000`.
    #[must_use]
    pub const fn roll_cdeg(&self) -> i32 {
        // Widening (`i32::from` is not const).
        ((self.roll_raw12 as i32).saturating_mul(18000) / 4095).saturating_sub(9000)
    }

    /// The 12-bit roll value for a roll in 0.01° (clamped to ±90°, rounded).
    #[must_use]
    pub const fn roll_raw_from_cdeg(cdeg: i32) -> u16 {
        let c = if cdeg < -9000 {
            -9000
        } else if cdeg > 9000 {
            9000
        } else {
            cdeg
        };
        let raw = (c
            .saturating_add(9000)
            .saturating_mul(4095)
            .saturating_add(9000))
            / 18000;
        // 0..=4095 after the clamp: the low two bytes hold it whole.
        let [low, high, _, _] = raw.to_le_bytes();
        u16::from_le_bytes([low, high])
    }
}

impl Field<Be> for B1 {
    const LEN: usize = 6;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        let [hi, lo] = r.array()?;
        Ok(B1 {
            servo: ServoCommand::from_value(bits8(hi, 4, 4)),
            roll_raw12: u16::from_be_bytes([bits8(hi, 0, 4), lo]),
            yaw_bam16: r.i16_be()?,
            pitch_bam16: r.i16_be()?,
        })
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        let v = put_bits(0, self.roll_raw12, 0, 12)?;
        let v = put_bits(v, u16::from(self.servo.value()), 12, 4)?;
        w.u16_be(v)?;
        w.i16_be(self.yaw_bam16)?;
        w.i16_be(self.pitch_bam16)
    }
}

// ---------------------------------------------------------------------------------- B2

wire_derive! {
    [Eq, Hash, Default]
    /// B2, servo status, infrequently used (11 bytes).
    pub struct B2 {
        /// Byte 1 bits 0..4: the servo control being reported.
        pub action: ServoAction,
        /// Byte 1 bit 5: reserved.
        pub reserved: bool,
        /// Byte 1 bits 6..7: the infrequently used frame counter of the last A2 received.
        pub counter: u8,
        /// Bytes 2..3: the position-calculation correction, 0.001° (pitch or yaw error, by
        /// the action).
        pub correction_mdeg: i16,
        /// Bytes 4..5: roll, 360/65536° per bit.
        pub roll_bam16: i16,
        /// Bytes 6..7: roll rate, 0.01°/s.
        pub roll_rate_cdeg_s: i16,
        /// Bytes 8..9: yaw rate, 0.01°/s.
        pub yaw_rate_cdeg_s: i16,
        /// Bytes 10..11: pitch rate, 0.01°/s.
        pub pitch_rate_cdeg_s: i16,
    }
}

impl B2 {
    /// The document's fault code 0xEE does not fit the 5-bit field: it is byte 1 as a
    /// whole (action 0x0E, reserved bit set, counter 3).
    #[must_use]
    pub const fn is_fault(&self) -> bool {
        matches!(self.action, ServoAction::Other(0x0E)) && self.reserved && self.counter == 3
    }
}

impl Field<Be> for B2 {
    const LEN: usize = 11;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        let b = r.u8()?;
        Ok(B2 {
            action: ServoAction::from_value(bits8(b, 0, 5)),
            reserved: bits8(b, 5, 1) != 0,
            counter: bits8(b, 6, 2),
            correction_mdeg: r.i16_be()?,
            roll_bam16: r.i16_be()?,
            roll_rate_cdeg_s: r.i16_be()?,
            yaw_rate_cdeg_s: r.i16_be()?,
            pitch_rate_cdeg_s: r.i16_be()?,
        })
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        let b = put_bits8(0, self.action.value(), 0, 5)?;
        let b = put_bits8(b, u8::from(self.reserved), 5, 1)?;
        w.u8(put_bits8(b, self.counter, 6, 2)?)?;
        w.i16_be(self.correction_mdeg)?;
        w.i16_be(self.roll_bam16)?;
        w.i16_be(self.roll_rate_cdeg_s)?;
        w.i16_be(self.yaw_rate_cdeg_s)?;
        w.i16_be(self.pitch_rate_cdeg_s)
    }
}

// ---------------------------------------------------------------------------------- D1

code_enum! {
    /// Recording status of D1 (bytes 3..4 bits 0..1).
    pub enum RecordStatus: u8 {
        /// Not recording.
        Stopped = 0,
        Recording = 1,
        /// Picture mode.
        PictureMode = 2,
    }
}

code_enum! {
    /// IR thermal status extension of D1 (bytes 3..4 bits 2..5).
    pub enum IrColorMode: u8 {
        Grayscale = 0,
        Rainbow = 1,
    }
}

wire_derive! {
    [Eq, Hash, Default]
    /// D1, optical status, commonly used (12 bytes).
    ///
    /// ArduPilot reads the recording status as `byte 4 & 0x07`, so it sees "recording"
    /// only while [`D1::ir_color`] is [`IrColorMode::Grayscale`].
    pub struct D1 {
        /// Byte 1 bits 0..2: the current video stream.
        pub source: VideoSource,
        /// Byte 1 bits 3..6: IR digital zoom, as the document's index (0 = x1 ..= 15 = x16).
        pub ir_dzoom_index: u8,
        /// Byte 1 bit 7: IR black hot (else white hot).
        pub black_hot: bool,
        /// Byte 2 bit 0: the rangefinder counter, toggled at every new ranging result.
        pub lrf_toggle: bool,
        /// Byte 2 bit 1: reserved.
        pub reserved_bit: bool,
        /// Byte 2 bits 2..7: rangefinder latency relative to the servo command, ms (0..=63).
        pub lrf_latency_ms: u8,
        /// Bytes 3..4 bits 0..1: recording status.
        pub record: RecordStatus,
        /// Bytes 3..4 bits 2..5: IR colour mode.
        pub ir_color: IrColorMode,
        /// Bytes 3..4 bits 6..9: EO digital zoom index (0 = x1 ..= 11 = x12).
        pub eo_dzoom_index: u8,
        /// Bytes 3..4 bits 10..15: reserved (0..=63).
        pub reserved: u8,
        /// Bytes 5..6: rangefinder distance, 0.1 m; 0 = invalid.
        pub lrf_dm: u16,
        /// Bytes 7..8: current vertical field of view, 0.01°.
        pub vfov_cdeg: u16,
        /// Bytes 9..10: current horizontal field of view, 0.01°.
        pub hfov_cdeg: u16,
        /// Bytes 11..12: current optical zoom, 0.1x.
        pub zoom_x10: u16,
    }
}

impl Field<Be> for D1 {
    const LEN: usize = 12;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        let b1 = r.u8()?;
        let b2 = r.u8()?;
        let s = r.u16_be()?;
        Ok(D1 {
            source: VideoSource::from_value(bits8(b1, 0, 3)),
            ir_dzoom_index: bits8(b1, 3, 4),
            black_hot: bits8(b1, 7, 1) != 0,
            lrf_toggle: bits8(b2, 0, 1) != 0,
            reserved_bit: bits8(b2, 1, 1) != 0,
            lrf_latency_ms: bits8(b2, 2, 6),
            record: RecordStatus::from_value(byte_of(s, 0, 2)),
            ir_color: IrColorMode::from_value(byte_of(s, 2, 4)),
            eo_dzoom_index: byte_of(s, 6, 4),
            reserved: byte_of(s, 10, 6),
            lrf_dm: r.u16_be()?,
            vfov_cdeg: r.u16_be()?,
            hfov_cdeg: r.u16_be()?,
            zoom_x10: r.u16_be()?,
        })
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        let b1 = put_bits8(0, self.source.value(), 0, 3)?;
        let b1 = put_bits8(b1, self.ir_dzoom_index, 3, 4)?;
        w.u8(put_bits8(b1, u8::from(self.black_hot), 7, 1)?)?;
        let b2 = put_bits8(0, u8::from(self.lrf_toggle), 0, 1)?;
        let b2 = put_bits8(b2, u8::from(self.reserved_bit), 1, 1)?;
        w.u8(put_bits8(b2, self.lrf_latency_ms, 2, 6)?)?;
        let s = put_bits(0, u16::from(self.record.value()), 0, 2)?;
        let s = put_bits(s, u16::from(self.ir_color.value()), 2, 4)?;
        let s = put_bits(s, u16::from(self.eo_dzoom_index), 6, 4)?;
        w.u16_be(put_bits(s, u16::from(self.reserved), 10, 6)?)?;
        w.u16_be(self.lrf_dm)?;
        w.u16_be(self.vfov_cdeg)?;
        w.u16_be(self.hfov_cdeg)?;
        w.u16_be(self.zoom_x10)
    }
}

// ---------------------------------------------------------------------------------- D2

code_enum! {
    /// Current sensor type of D2 (byte 1 bits 0..2).
    pub enum D2Sensor: u8 {
        /// EO 1 only.
        Eo1 = 0x00,
        /// IR only.
        Ir = 0x01,
        /// EO 1 main, IR picture-in-picture.
        Eo1IrPip = 0x02,
        /// IR main, EO 1 picture-in-picture.
        IrEo1Pip = 0x03,
        /// EO 2 only.
        Eo2 = 0x04,
    }
}

code_enum! {
    /// Optical sensor pixel format of D2 (byte 2 bits 0..6).
    pub enum PixelFormat: u8 {
        P1080 = 1,
        /// 2K.
        K2 = 2,
        /// 4K.
        K4 = 3,
        P960 = 4,
        P720 = 5,
        P640 = 6,
    }
}

code_enum! {
    /// Type of the extended parameter of D2 (byte 3).
    pub enum ExtendKind: u8 {
        None = 0x00,
        /// Digital zoom (bytes 4..5 in 0.1x).
        DigitalZoom = 0x01,
    }
}

wire_derive! {
    [Eq, Hash, Default]
    /// D2, optical status, infrequently used (5 bytes).
    pub struct D2 {
        /// Byte 1 bits 0..2: the current sensor.
        pub sensor: D2Sensor,
        /// Byte 1 bits 3..7: device failure code (0 none, 1..=3 laser, then four codes per
        /// sensor).
        pub fault: u8,
        /// Byte 2 bits 0..6: the sensor's pixel format.
        pub pixels: PixelFormat,
        /// Byte 2 bit 7: the current sensor is not the main sensor (reserved).
        pub not_main: bool,
        /// Byte 3: what bytes 4..5 are.
        pub extend: ExtendKind,
        /// Bytes 4..5: the extended parameter (digital zoom: 0.1x).
        pub extend_value: i16,
    }
}

impl Field<Be> for D2 {
    const LEN: usize = 5;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        let b1 = r.u8()?;
        let b2 = r.u8()?;
        Ok(D2 {
            sensor: D2Sensor::from_value(bits8(b1, 0, 3)),
            fault: bits8(b1, 3, 5),
            pixels: PixelFormat::from_value(bits8(b2, 0, 7)),
            not_main: bits8(b2, 7, 1) != 0,
            extend: ExtendKind::from_value(r.u8()?),
            extend_value: r.i16_be()?,
        })
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        let b1 = put_bits8(0, self.sensor.value(), 0, 3)?;
        w.u8(put_bits8(b1, self.fault, 3, 5)?)?;
        let b2 = put_bits8(0, self.pixels.value(), 0, 7)?;
        w.u8(put_bits8(b2, u8::from(self.not_main), 7, 1)?)?;
        w.u8(self.extend.value())?;
        w.i16_be(self.extend_value)
    }
}

// ---------------------------------------------------------------------------------- F1

wire_derive! {
    [Eq, Hash, Default]
    /// F1, tracking status, commonly used (1 byte).
    pub struct F1 {
        /// Bits 0..2: the tracking sensor.
        pub sensor: TrackerSensor,
        /// Bits 3..4: the tracker state.
        pub state: TrackerState,
        /// Bits 5..7: reserved.
        pub reserved: u8,
    }
}

impl Field<Be> for F1 {
    const LEN: usize = 1;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        let b = r.u8()?;
        Ok(F1 {
            sensor: TrackerSensor::from_value(bits8(b, 0, 3)),
            state: TrackerState::from_value(bits8(b, 3, 2)),
            reserved: bits8(b, 5, 3),
        })
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        let b = put_bits8(0, self.sensor.value(), 0, 3)?;
        let b = put_bits8(b, self.state.value(), 3, 2)?;
        w.u8(put_bits8(b, self.reserved, 5, 3)?)
    }
}

// ---------------------------------------------------------------------------------- F2

wire_struct! {
    Be;
    /// F2, tracking status, infrequently used (15 bytes).
    pub struct F2 {
        /// Bytes 1..11: reserved.
        pub reserved: [u8; 11],
        /// Bytes 12..13: azimuth pixel difference to the target.
        pub yaw_px: i16,
        /// Bytes 14..15: tilt pixel difference to the target.
        pub pitch_px: i16,
    }
}

// ---------------------------------------------------------------------------------- T1

code_enum! {
    /// Target distance source of T1 (byte 1 bits 0..2).
    pub enum DistanceSource: u8 {
        /// No target.
        None = 0,
        /// Laser rangefinder.
        Laser = 1,
        /// Height estimate.
        HeightEstimate = 2,
        /// Radio frequency (reserved).
        RadioFrequency = 3,
    }
}

code_enum! {
    /// GPS signal capture stage of T1 (byte 1 bits 3..4).
    pub enum GpsStage: u8 {
        /// No signal.
        NoSignal = 0,
        /// Time locked.
        TimeLocked = 1,
        /// 2D locked.
        Locked2d = 2,
        /// 3D locked.
        Locked3d = 3,
    }
}

code_enum! {
    /// N packet command response of T1 (byte 2 bits 4..7).
    pub enum NResponse: u8 {
        None = 0,
        /// Gyro offset auto-adjusting.
        GyroOffsetAdjusting = 1,
        /// Gyro offset saving.
        GyroOffsetSaving = 2,
        /// Gyro offset restored to the factory default.
        GyroOffsetReset = 3,
        /// AHRS zero-angle position adjusted.
        AhrsZeroAdjusted = 4,
        /// AHRS attitude offset saving.
        AhrsOffsetSaving = 5,
        /// AHRS attitude offset reset.
        AhrsOffsetReset = 6,
        /// Calibrating the gyro temperature drift.
        GyroDriftCalibrating = 7,
        /// Gyro temperature drift calibration done.
        GyroDriftCalibrated = 8,
    }
}

wire_derive! {
    [Eq, Hash, Default]
    /// T1, target calculation status, commonly used (22 bytes). The document's "vehicle
    /// attitude" and "target attitude" (Int16, 1 m) are altitudes.
    pub struct T1 {
        /// Byte 1 bits 0..2: the target distance source.
        pub distance_source: DistanceSource,
        /// Byte 1 bits 3..4: the GPS capture stage.
        pub gps_stage: GpsStage,
        /// Byte 1 bits 5..7: GPS horizontal signal quality (reserved).
        pub gps_h_quality: u8,
        /// Byte 2 bits 0..2: GPS vertical signal quality (reserved).
        pub gps_v_quality: u8,
        /// Byte 2 bit 3: an S2 command was answered (set for one frame).
        pub s2_ack: bool,
        /// Byte 2 bits 4..7: N packet command response.
        pub n_response: NResponse,
        /// Bytes 3..6: vehicle latitude, 1e-7°.
        pub lat_e7: i32,
        /// Bytes 7..10: vehicle longitude, 1e-7°.
        pub lon_e7: i32,
        /// Bytes 11..12: vehicle altitude, m.
        pub alt_m: i16,
        /// Bytes 13..16: target latitude, 1e-7°.
        pub target_lat_e7: i32,
        /// Bytes 17..20: target longitude, 1e-7°.
        pub target_lon_e7: i32,
        /// Bytes 21..22: target altitude, m.
        pub target_alt_m: i16,
    }
}

impl Field<Be> for T1 {
    const LEN: usize = 22;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        let b1 = r.u8()?;
        let b2 = r.u8()?;
        Ok(T1 {
            distance_source: DistanceSource::from_value(bits8(b1, 0, 3)),
            gps_stage: GpsStage::from_value(bits8(b1, 3, 2)),
            gps_h_quality: bits8(b1, 5, 3),
            gps_v_quality: bits8(b2, 0, 3),
            s2_ack: bits8(b2, 3, 1) != 0,
            n_response: NResponse::from_value(bits8(b2, 4, 4)),
            lat_e7: r.i32_be()?,
            lon_e7: r.i32_be()?,
            alt_m: r.i16_be()?,
            target_lat_e7: r.i32_be()?,
            target_lon_e7: r.i32_be()?,
            target_alt_m: r.i16_be()?,
        })
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        let b1 = put_bits8(0, self.distance_source.value(), 0, 3)?;
        let b1 = put_bits8(b1, self.gps_stage.value(), 3, 2)?;
        w.u8(put_bits8(b1, self.gps_h_quality, 5, 3)?)?;
        let b2 = put_bits8(0, self.gps_v_quality, 0, 3)?;
        let b2 = put_bits8(b2, u8::from(self.s2_ack), 3, 1)?;
        w.u8(put_bits8(b2, self.n_response.value(), 4, 4)?)?;
        w.i32_be(self.lat_e7)?;
        w.i32_be(self.lon_e7)?;
        w.i16_be(self.alt_m)?;
        w.i32_be(self.target_lat_e7)?;
        w.i32_be(self.target_lon_e7)?;
        w.i16_be(self.target_alt_m)
    }
}

// ---------------------------------------------------------------------------------- T2

wire_struct! {
    Be;
    /// T2, target calculation status, infrequently used (18 bytes). The document labels
    /// both bytes 11..12 and 13..14 "pitch": the second is taken as roll.
    pub struct T2 {
        /// Byte 1: reserved.
        pub reserved: u8,
        /// Bytes 2..3: UTC date.
        pub date: Date,
        /// Bytes 4..6: UTC time of day, 0.01 s.
        pub time: TimeCs,
        /// Bytes 7..8: GPS yaw (course), 360/65536°.
        pub gps_yaw_bam16: i16,
        /// Bytes 9..10: vehicle yaw, 360/65536°.
        pub yaw_bam16: i16,
        /// Bytes 11..12: vehicle pitch, 360/65536°.
        pub pitch_bam16: i16,
        /// Bytes 13..14: vehicle roll, 360/65536°.
        pub roll_bam16: i16,
        /// Bytes 15..18: reserved.
        pub reserved2: [u8; 4],
    }
}
