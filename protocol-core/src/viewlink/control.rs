//! Console-to-payload control blocks: A1/A2 (servo), C1/C2 (optics), E1/E2 (tracking)
//! and S1/S2 (target calculation, "TGCC").
//!
//! Angles in `_bam16` fields are 1 = 360/65536° (a signed 16-bit binary angle);
//! `_bam14` fields are 1 = 720/32768° (= 360/16384°).

use super::block::{bits_of, bits8, byte_of, put_bits, put_bits8};
use super::enums::{
    LrfCommand, OnOff, OperationCommand, Sensor, ServoCommand, TrackingCommand, TrackingSource,
};
use crate::Result;
use crate::wire::encoding::{Be, Field};
use crate::wire::{Reader, Writer};

// ---------------------------------------------------------------------------------- A1

code_enum! {
    /// A1 parameter 1 of the motor on/off command (0x00).
    pub enum MotorSwitch: u16 {
        /// 0x0100: motor on.
        On = 0x0100,
        /// 0x0001: motor off.
        Off = 0x0001,
    }
}

wire_struct! {
    Be;
    /// A1 command 0x00: motor on/off.
    pub struct MotorOnOff {
        /// Parameter 1: on or off.
        pub switch: MotorSwitch,
        /// Parameters 2..4 (bytes 4..9), meaningless.
        pub reserved: [u8; 6],
    }
}

wire_struct! {
    Be;
    /// A1 command 0x01: manual speed mode. The document's examples use +2000 for
    /// "right" and for "up" (20°/s).
    pub struct ManualSpeed {
        /// Parameter 1: azimuth (yaw) speed, 0.01°/s.
        pub yaw_cdeg_s: i16,
        /// Parameter 2: tilt (pitch) speed, 0.01°/s.
        pub pitch_cdeg_s: i16,
        /// Parameters 3..4, meaningless.
        pub reserved: [u8; 4],
    }
}

wire_struct! {
    Be;
    /// A1 command 0x05: azimuth scan (not supported yet by the gimbals). The meaning of
    /// the speeds and of parameter 4 depends on parameter 3 (see the methods).
    pub struct AzimuthScan {
        /// Parameter 1: azimuth speed; 0.01°/s when `range < 0x8000`, else 0.1°/s.
        pub yaw_speed: i16,
        /// Parameter 2: tilt speed; 0.01°/s when `range < 0x8000`, else 0.1°/s.
        pub pitch_speed: i16,
        /// Parameter 3: below 0x8000 the scan half width (360/65536°); from 0x8000 a
        /// circle scan: bit 14 the reference frame (0 vehicle, 1 earth), bits 0..7 the
        /// normalised tilt-scan gain (0x00 maximum, 0xFF no gain).
        pub range: u16,
        /// Parameter 4: the scan centre angle (`range < 0x8000`) or the follow-up angle
        /// orthogonal to the scan (360/65536°).
        pub angle_bam16: i16,
    }
}

impl AzimuthScan {
    /// True for a circle scan (parameter 3 ≥ 0x8000).
    #[must_use]
    pub const fn is_circle(&self) -> bool {
        self.range >= 0x8000
    }

    /// The azimuth speed in 0.01°/s, whatever the unit on the wire.
    #[must_use]
    pub const fn yaw_speed_cdeg_s(&self) -> i32 {
        self.scaled(self.yaw_speed)
    }

    /// The tilt speed in 0.01°/s, whatever the unit on the wire.
    #[must_use]
    pub const fn pitch_speed_cdeg_s(&self) -> i32 {
        self.scaled(self.pitch_speed)
    }

    const fn scaled(self, v: i16) -> i32 {
        // Widening casts (`i32::from` is not const).
        if self.is_circle() {
            (v as i32).saturating_mul(10)
        } else {
            v as i32
        }
    }

    /// Circle scan: the scan angles are relative to the earth (else to the vehicle).
    #[must_use]
    pub const fn earth_frame(&self) -> bool {
        self.is_circle() && self.range & 0x4000 != 0
    }

    /// Circle scan: the normalised tilt gain (bits 0..7).
    #[must_use]
    pub const fn tilt_gain(&self) -> u8 {
        byte_of(self.range, 0, 8)
    }
}

wire_struct! {
    Be;
    /// A1 command 0x09: manual relative angle mode (the current position is 0).
    pub struct RelativeAngle {
        /// Parameter 1: yaw speed, 0.1°/s; 0 = the system default speed.
        pub yaw_speed_ddeg_s: i16,
        /// Parameter 2: yaw angle.
        pub yaw_bam16: i16,
        /// Parameter 3: pitch speed, 0.1°/s; 0 = the system default speed.
        pub pitch_speed_ddeg_s: i16,
        /// Parameter 4: pitch angle.
        pub pitch_bam16: i16,
    }
}

wire_struct! {
    Be;
    /// A1 command 0x0B: manual absolute angle mode (home position is 0). The document's
    /// example "yaw right 90°, tilt down 90°" is 0x3FFC, 0x3FFC.
    pub struct AbsoluteAngle {
        /// Parameter 1: yaw angle.
        pub yaw_bam16: i16,
        /// Parameter 2: pitch angle.
        pub pitch_bam16: i16,
        /// Parameters 3..4, meaningless.
        pub reserved: [u8; 4],
    }
}

wire_struct! {
    Be;
    /// A1 command 0x0D: manual RC mode.
    pub struct ManualRc {
        /// Parameter 1: yaw speed, 0.1°/s; 0 = the system default speed.
        pub yaw_speed_ddeg_s: u16,
        /// Parameter 2: yaw RC value, 1100..1900 µs.
        pub yaw_rc_us: u16,
        /// Parameter 3: pitch speed, 0.1°/s; 0 = the system default speed.
        pub pitch_speed_ddeg_s: u16,
        /// Parameter 4: pitch RC value, 1100..1900 µs.
        pub pitch_rc_us: u16,
    }
}

wire_struct! {
    Be;
    /// A1 command 0x0E: tracking follows a click/touch (3.3.1.7). The document calls the
    /// coordinates unsigned but gives them a signed range: they are read as signed.
    pub struct TrackClick {
        /// Parameter 1: yaw speed, 0.01°/s; 0 = the default speed.
        pub yaw_speed_cdeg_s: u16,
        /// Parameter 2: yaw coordinate, -960 (left) ..= 960 (right), 0 centre.
        pub yaw_px: i16,
        /// Parameter 3: pitch speed, 0.01°/s; 0 = the default speed.
        pub pitch_speed_cdeg_s: u16,
        /// Parameter 4: pitch coordinate, -540 (up) ..= 540 (down), 0 centre.
        pub pitch_px: i16,
    }
}

wire_struct! {
    Be;
    /// A1 command 0x10: manual yaw zero-bias (gyro heading) correction.
    pub struct GyroCorrection {
        /// Parameter 1: -20000..=20000, in 0.001 of the gyro sensor's unit (the document
        /// calls it unsigned but gives a signed range: read as signed).
        pub bias_milli: i16,
        /// Parameters 2..4, meaningless.
        pub reserved: [u8; 6],
    }
}

wire_struct! {
    Be;
    /// A1 command 0x11: use the frame heading angle servo system only.
    pub struct FrameHeadingAngle {
        /// Parameter 1: -1800..=1800 (0.1°); [`FrameHeadingAngle::DISABLE`] disables the
        /// correction.
        pub heading_ddeg: i16,
        /// Parameters 2..4, meaningless.
        pub reserved: [u8; 6],
    }
}

impl FrameHeadingAngle {
    /// The special value that disables the correction (0x7FFF).
    pub const DISABLE: i16 = 0x7FFF;
}

wire_struct! {
    Be;
    /// A1 command 0x1B: 720° manual absolute angle mode (home position is 0).
    pub struct AbsoluteAngle720 {
        /// Parameter 1: yaw angle, 720/32768° per bit.
        pub yaw_bam14: i16,
        /// Parameter 2: pitch angle, 720/32768° per bit.
        pub pitch_bam14: i16,
        /// Parameters 3..4, meaningless.
        pub reserved: [u8; 4],
    }
}

viewlink_command_block! {
    /// A1, servo control, commonly used (9 bytes): a [`ServoCommand`] and four 16-bit
    /// parameters whose meaning depends on it (3.3.1). Commands whose parameters are
    /// meaningless (follow yaw, home, tracking, ...) are `Plain`.
    pub enum A1: ServoCommand [8] {
        /// 0x00: motor on/off.
        MotorOnOff(MotorOnOff) = MotorOnOff,
        /// 0x01: manual speed.
        ManualSpeed(ManualSpeed) = ManualSpeed,
        /// 0x05: azimuth scan.
        AzimuthScan(AzimuthScan) = AzimuthScan,
        /// 0x09: relative angle.
        RelativeAngle(RelativeAngle) = RelativeAngle,
        /// 0x0B: absolute angle.
        AbsoluteAngle(AbsoluteAngle) = AbsoluteAngle,
        /// 0x0D: manual RC.
        ManualRc(ManualRc) = ManualRc,
        /// 0x0E: tracking follows a click.
        TrackClick(TrackClick) = TrackClick,
        /// 0x10: gyro heading correction.
        GyroCorrection(GyroCorrection) = GyroCorrection,
        /// 0x11: frame heading angle.
        FrameHeadingAngle(FrameHeadingAngle) = FrameHeadingAngle,
        /// 0x1B: 720° absolute angle.
        AbsoluteAngle720(AbsoluteAngle720) = AbsoluteAngle720,
    }
}

// ---------------------------------------------------------------------------------- A2

code_enum! {
    /// Servo action of A2 (byte 1, bits 0..4) and servo control of B2.
    pub enum ServoAction: u8 {
        /// No action.
        NoAction = 0x00,
        /// Manual error correction of the pitch angle in position calculation.
        PitchCorrection = 0x01,
        /// Manual error correction of the yaw angle in position calculation.
        YawCorrection = 0x02,
        /// Zero drift correction (B2 only, not supported yet).
        ZeroDriftCorrect = 0x08,
        /// Zero drift calibration (B2 only, reserved).
        ZeroDriftCalibrate = 0x09,
    }
}

wire_derive! {
    [Eq, Hash, Default]
    /// A2, servo control, infrequently used (2 bytes).
    pub struct A2 {
        /// Byte 1 bits 0..4: the servo action.
        pub action: ServoAction,
        /// Byte 1 bit 5: ask for one infrequently used status frame (0x41) in reply.
        pub request_status: bool,
        /// Byte 1 bits 6..7: the infrequently used frame counter (0..=3), echoed in B2.
        pub counter: u8,
        /// Byte 2: the adjustment, 0.001° (pitch: positive up; yaw: positive right).
        pub adjustment_mdeg: i8,
    }
}

impl Field<Be> for A2 {
    const LEN: usize = 2;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        let b = r.u8()?;
        Ok(A2 {
            action: ServoAction::from_value(bits8(b, 0, 5)),
            request_status: bits8(b, 5, 1) != 0,
            counter: bits8(b, 6, 2),
            adjustment_mdeg: r.i8()?,
        })
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        let b = put_bits8(0, self.action.value(), 0, 5)?;
        let b = put_bits8(b, u8::from(self.request_status), 5, 1)?;
        w.u8(put_bits8(b, self.counter, 6, 2)?)?;
        w.i8(self.adjustment_mdeg)
    }
}

// ---------------------------------------------------------------------------------- C1

wire_derive! {
    [Eq, Hash, Default]
    /// C1, optical control, commonly used: one big-endian `u16` of four bit fields
    /// (sensor bits 0..2, speed bits 3..5, operation bits 6..12, LRF bits 13..15).
    pub struct C1 {
        /// Bits 0..2: the image sensor to select.
        pub sensor: Sensor,
        /// Bits 3..5: the operation's speed (zoom or focus speed, 1 slowest ..= 7 fastest).
        pub zoom_speed: u8,
        /// Bits 6..12: the operation command.
        pub operation: OperationCommand,
        /// Bits 13..15: the laser rangefinder command.
        pub lrf: LrfCommand,
    }
}

impl C1 {
    /// The 16 bits on the wire.
    ///
    /// # Errors
    /// [`Error::OutOfRange`](crate::Error::OutOfRange) for a field that does not fit its
    /// bits.
    pub fn to_u16(&self) -> Result<u16> {
        let v = put_bits(0, u16::from(self.sensor.value()), 0, 3)?;
        let v = put_bits(v, u16::from(self.zoom_speed), 3, 3)?;
        let v = put_bits(v, u16::from(self.operation.value()), 6, 7)?;
        put_bits(v, u16::from(self.lrf.value()), 13, 3)
    }

    /// The fields of the 16 bits on the wire.
    #[must_use]
    pub const fn from_u16(v: u16) -> Self {
        C1 {
            sensor: Sensor::from_value(byte_of(v, 0, 3)),
            zoom_speed: byte_of(v, 3, 3),
            operation: OperationCommand::from_value(byte_of(v, 6, 7)),
            lrf: LrfCommand::from_value(byte_of(v, 13, 3)),
        }
    }
}

impl Field<Be> for C1 {
    const LEN: usize = 2;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        r.u16_be().map(C1::from_u16)
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u16_be(self.to_u16()?)
    }
}

// ---------------------------------------------------------------------------------- C2

code_enum! {
    /// Command of C2 (byte 1).
    pub enum C2Command: u8 {
        /// No action.
        NoAction = 0x00,
        /// Timed non-uniformity correction on (reserved).
        TimedNucOn = 0x04,
        /// Timed non-uniformity correction off (reserved).
        TimedNucOff = 0x05,
        /// EO digital zoom on.
        EoDzoomOn = 0x06,
        /// EO digital zoom off.
        EoDzoomOff = 0x07,
        /// Set the maximum EO digital zoom (3.8.1.1; parameter 0.1x).
        MaxEoDzoom = 0x08,
        /// Image enhancement on.
        EnhanceOn = 0x10,
        /// Image enhancement off.
        EnhanceOff = 0x11,
        /// IR colour bar on (thermometry version).
        IrColorBarOn = 0x12,
        /// IR colour bar off (thermometry version).
        IrColorBarOff = 0x13,
        /// Set the IR alarm temperature (parameter °C).
        AlarmTemperature = 0x14,
        /// EO image upside up/down.
        EoFlip = 0x15,
        /// Defog off.
        DefogOff = 0x16,
        /// Defog on.
        DefogOn = 0x17,
        /// Sensor built-in characters (OSD) on.
        OsdOn = 0x18,
        /// Sensor built-in characters (OSD) off.
        OsdOff = 0x19,
        /// IR image upside up.
        IrUpright = 0x1A,
        /// IR image upside down.
        IrFlipped = 0x1B,
        /// Auto brightness on (reserved).
        AutoBrightness = 0x1C,
        /// Output temperature data once.
        TemperatureOnce = 0x1D,
        /// Output temperature data every `parameter` frames.
        TemperatureInterval = 0x1E,
        /// Stop the periodic temperature output.
        TemperatureStop = 0x1F,
        /// Focus auto (reserved).
        FocusAuto = 0x28,
        /// Stop focus (reserved).
        FocusStop = 0x2B,
        /// Near-infrared mode on.
        NearInfraredOn = 0x4A,
        /// Near-infrared mode off.
        NearInfraredOff = 0x4B,
        /// Reboot / auto-check (reserved).
        Reboot = 0x4E,
        /// Set brightness to the parameter (reserved).
        SetBrightness = 0x50,
        /// Set contrast to the parameter (reserved).
        SetContrast = 0x51,
        /// Set aperture to the parameter (reserved).
        SetAperture = 0x52,
        /// Set the EO zoom to the parameter (0.1x).
        SetEoZoom = 0x53,
        /// Set focus to the parameter (reserved).
        SetFocus = 0x54,
        /// Set gain/ISO to the parameter (reserved).
        SetGain = 0x55,
        /// Set the thermal digital zoom to the parameter (0.1x).
        SetIrZoom = 0x56,
        /// Laser control command.
        Laser = 0x74,
        /// Optical power control (reserved).
        Power = 0x75,
        /// Set the recording segment length (minutes).
        RecordSegment = 0x76,
    }
}

wire_struct! {
    Be;
    /// C2 parameter in 0.1 zoom steps (0x08, 0x53, 0x56): 200 = 20x.
    pub struct Zoom {
        /// Zoom ratio times ten.
        pub zoom_x10: u16,
    }
}

wire_struct! {
    Be;
    /// C2 0x14: IR alarm temperature.
    pub struct AlarmTemperature {
        /// Alarm temperature, °C.
        pub celsius: u16,
    }
}

wire_struct! {
    Be;
    /// C2 0x1E: temperature output interval.
    pub struct TemperatureInterval {
        /// Interval in video frames (the document gives no unit; "data frame interval").
        pub frames: u16,
    }
}

wire_struct! {
    Be;
    /// C2 0x50..0x55: a raw setting value (brightness, contrast, aperture, focus, gain).
    pub struct SettingValue {
        /// The value (no unit given).
        pub value: u16,
    }
}

wire_struct! {
    Be;
    /// C2 0x76: recording segment ("package") length.
    pub struct RecordSegment {
        /// Length of a recording segment, in minutes.
        pub minutes: u16,
    }
}

code_enum! {
    /// C2 0x4E parameter bits 0..1.
    pub enum RebootAction: u8 {
        /// No action.
        NoAction = 0,
        Reboot = 1,
        AutoCheck = 2,
    }
}

wire_derive! {
    [Eq, Hash, Default]
    /// C2 0x4E: reboot / auto-check.
    pub struct Reboot {
        /// Bits 0..1.
        pub action: RebootAction,
        /// Bits 2..15, reserved (kept, shifted down by 2).
        pub reserved: u16,
    }
}

impl Field<Be> for Reboot {
    const LEN: usize = 2;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        let v = r.u16_be()?;
        Ok(Reboot {
            action: RebootAction::from_value(byte_of(v, 0, 2)),
            reserved: bits_of(v, 2, 14),
        })
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        let v = put_bits(0, u16::from(self.action.value()), 0, 2)?;
        w.u16_be(put_bits(v, self.reserved, 2, 14)?)
    }
}

code_enum! {
    /// C2 0x74 laser command (byte 2).
    pub enum LaserCommand: u8 {
        /// No action.
        NoAction = 0x00,
        /// Laser on.
        On = 0x01,
        /// Laser off.
        Off = 0x02,
        /// Laser system auto-check (not supported yet).
        AutoCheck = 0x03,
        /// Laser zoom out.
        ZoomOut = 0x04,
        /// Laser zoom in.
        ZoomIn = 0x05,
        /// Laser zoom synchronised with the EO zoom.
        ZoomSyncEo = 0x06,
        /// Laser zoom under manual control.
        ZoomManual = 0x07,
        /// Laser elevation protection off (not supported yet).
        ElevationProtectionOff = 0x0E,
        /// Laser elevation protection on (not supported yet).
        ElevationProtectionOn = 0x0F,
    }
}

wire_struct! {
    Be;
    /// C2 0x74: laser control.
    pub struct LaserControl {
        /// Byte 2: the laser command.
        pub command: LaserCommand,
        /// Byte 3: not described by the document.
        pub reserved: u8,
    }
}

code_enum! {
    /// A power switch of C2 0x75 (two bits).
    pub enum PowerSwitch: u8 {
        /// No change.
        NoChange = 0,
        /// Power on.
        On = 1,
        /// Power off.
        Off = 2,
    }
}

wire_newtype! {
    /// C2 0x75: optical power control bits: EO 1 bits 0..1, IR bits 2..3, EO 2 bits
    /// 4..5, laser bits 14..15 (each a [`PowerSwitch`]); the rest reserved.
    pub struct PowerControl(u16);
}

impl PowerControl {
    /// EO 1 power (bits 0..1).
    #[must_use]
    pub const fn eo1(self) -> PowerSwitch {
        PowerSwitch::from_value(byte_of(self.0, 0, 2))
    }
    /// IR power (bits 2..3).
    #[must_use]
    pub const fn ir(self) -> PowerSwitch {
        PowerSwitch::from_value(byte_of(self.0, 2, 2))
    }
    /// EO 2 power (bits 4..5).
    #[must_use]
    pub const fn eo2(self) -> PowerSwitch {
        PowerSwitch::from_value(byte_of(self.0, 4, 2))
    }
    /// Laser power (bits 14..15).
    #[must_use]
    pub const fn laser(self) -> PowerSwitch {
        PowerSwitch::from_value(byte_of(self.0, 14, 2))
    }
    /// The bits for four switches.
    ///
    /// # Errors
    /// [`Error::OutOfRange`](crate::Error::OutOfRange) for a switch value above 3.
    pub fn new(
        eo1: PowerSwitch,
        ir: PowerSwitch,
        eo2: PowerSwitch,
        laser: PowerSwitch,
    ) -> Result<Self> {
        let v = put_bits(0, u16::from(eo1.value()), 0, 2)?;
        let v = put_bits(v, u16::from(ir.value()), 2, 2)?;
        let v = put_bits(v, u16::from(eo2.value()), 4, 2)?;
        put_bits(v, u16::from(laser.value()), 14, 2).map(PowerControl)
    }
}

viewlink_command_block! {
    /// C2, optical control, infrequently used (3 bytes): a [`C2Command`] and a 16-bit
    /// parameter whose meaning depends on it (3.8.1).
    pub enum C2: C2Command [2] {
        /// 0x08: maximum EO digital zoom.
        MaxEoDzoom(Zoom) = MaxEoDzoom,
        /// 0x14: IR alarm temperature.
        AlarmTemperature(AlarmTemperature) = AlarmTemperature,
        /// 0x1E: temperature output interval.
        TemperatureInterval(TemperatureInterval) = TemperatureInterval,
        /// 0x4E: reboot / auto-check.
        Reboot(Reboot) = Reboot,
        /// 0x50: brightness.
        SetBrightness(SettingValue) = SetBrightness,
        /// 0x51: contrast.
        SetContrast(SettingValue) = SetContrast,
        /// 0x52: aperture.
        SetAperture(SettingValue) = SetAperture,
        /// 0x53: EO zoom (ArduPilot's absolute zoom).
        SetEoZoom(Zoom) = SetEoZoom,
        /// 0x54: focus.
        SetFocus(SettingValue) = SetFocus,
        /// 0x55: gain/ISO.
        SetGain(SettingValue) = SetGain,
        /// 0x56: thermal digital zoom.
        SetIrZoom(Zoom) = SetIrZoom,
        /// 0x74: laser control.
        Laser(LaserControl) = Laser,
        /// 0x75: power control.
        Power(PowerControl) = Power,
        /// 0x76: recording segment length.
        RecordSegment(RecordSegment) = RecordSegment,
    }
}

// ---------------------------------------------------------------------------------- E1

wire_derive! {
    [Eq, Hash, Default]
    /// E1, tracking command, commonly used (3 bytes). The parameters' meaning depends on
    /// the command (3.11.1): [`TrackingCommand::Search`] moves the cross (parameter 1: 1..15
    /// right, 16..31 left; parameter 2: 1..15 down, 16..31 up); `AiDetection` takes 0/1 in
    /// parameter 2; `TrackingSpeed` 0.2°/s and `SpeedCoefficient` 0.1 in parameter 2
    /// (0 = the system default).
    pub struct E1 {
        /// Byte 1 bits 0..2: tracking source (reserved by the document; ArduPilot sets it).
        pub source: TrackingSource,
        /// Byte 1 bits 3..7: parameter 1 (5 bits).
        pub param1: u8,
        /// Byte 2: the basic command.
        pub command: TrackingCommand,
        /// Byte 3: parameter 2.
        pub param2: u8,
    }
}

impl E1 {
    /// A command with zero parameters.
    #[must_use]
    pub const fn new(source: TrackingSource, command: TrackingCommand) -> Self {
        E1 {
            source,
            param1: 0,
            command,
            param2: 0,
        }
    }

    /// Search: move the cross at the given speeds (0..=31 each).
    #[must_use]
    pub const fn search(source: TrackingSource, yaw: u8, pitch: u8) -> Self {
        E1 {
            source,
            param1: yaw,
            command: TrackingCommand::Search,
            param2: pitch,
        }
    }

    /// AI detection on or off.
    #[must_use]
    pub const fn ai_detection(source: TrackingSource, on: OnOff) -> Self {
        E1 {
            source,
            param1: 0,
            command: TrackingCommand::AiDetection,
            param2: on.value(),
        }
    }

    /// Tracking speed in 0.2°/s (0 = default); `None` for another command.
    #[must_use]
    pub const fn tracking_speed_5th_dps(&self) -> Option<u8> {
        match self.command {
            TrackingCommand::TrackingSpeed => Some(self.param2),
            _ => None,
        }
    }

    /// Tracking speed coefficient times ten (0 = default); `None` for another command.
    #[must_use]
    pub const fn speed_coefficient_x10(&self) -> Option<u8> {
        match self.command {
            TrackingCommand::SpeedCoefficient => Some(self.param2),
            _ => None,
        }
    }
}

impl Field<Be> for E1 {
    const LEN: usize = 3;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        let b = r.u8()?;
        Ok(E1 {
            source: TrackingSource::from_value(bits8(b, 0, 3)),
            param1: bits8(b, 3, 5),
            command: TrackingCommand::from_value(r.u8()?),
            param2: r.u8()?,
        })
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        let b = put_bits8(0, self.source.value(), 0, 3)?;
        w.u8(put_bits8(b, self.param1, 3, 5)?)?;
        w.u8(self.command.value())?;
        w.u8(self.param2)
    }
}

// ---------------------------------------------------------------------------------- E2

code_enum! {
    /// Extended tracking command of E2 (byte 1).
    pub enum TrackingCommand2: u8 {
        /// No meaning.
        NoAction = 0x00,
        /// Set the OSD.
        SetOsd = 0x01,
        /// Move the tracking point to a position.
        TrackPoint = 0x0A,
        /// Rectangular tracking area: top-left corner.
        RectTopLeft = 0x0B,
        /// Rectangular tracking area: bottom-right corner.
        RectBottomRight = 0x0C,
        /// Set the OSD colour.
        OsdColor = 0x1F,
        /// Turn on the identification output (0xF3 packets).
        IdentifyOn = 0x20,
        /// Turn off the identification output.
        IdentifyOff = 0x21,
    }
}

wire_newtype! {
    /// E2 0x01 parameter 1: OSD bits. Bits 0..7 as [`OsdFlags`](super::OsdFlags) (U
    /// 0x05), bits 8..15 as [`OsdTypeFlags`](super::OsdTypeFlags) (U 0x07).
    pub struct OsdWord(u16);
}

impl OsdWord {
    /// Bits 0..7.
    #[must_use]
    pub const fn osd1(self) -> super::OsdFlags {
        super::OsdFlags(self.0.to_be_bytes()[1])
    }
    /// Bits 8..15.
    #[must_use]
    pub const fn osd2(self) -> super::OsdTypeFlags {
        super::OsdTypeFlags(self.0.to_be_bytes()[0])
    }
}

wire_struct! {
    Be;
    /// E2 0x01: OSD settings.
    pub struct E2Osd {
        /// Parameter 1: OSD bits.
        pub flags: OsdWord,
        /// Parameter 2: bit 0 hides the hotspot-tracking OSD; bits 1..15 reserved.
        pub hotspot: u16,
    }
}

wire_struct! {
    Be;
    /// E2 0x0A, 0x0B, 0x0C: an image position in pixels, 0 at the centre.
    pub struct Point {
        /// Parameter 1: x, -960 (left) ..= 960 (right).
        pub x_px: i16,
        /// Parameter 2: y, -540 (top) ..= 540 (bottom).
        pub y_px: i16,
    }
}

wire_struct! {
    Be;
    /// E2 0x1F: OSD colour.
    pub struct OsdColor {
        /// Parameters 1 (high 16 bits) and 2 (low 16 bits).
        pub color: u32,
    }
}

viewlink_command_block! {
    /// E2, tracking command, infrequently used (5 bytes): a [`TrackingCommand2`] and two
    /// 16-bit parameters (3.12.1).
    pub enum E2: TrackingCommand2 [4] {
        /// 0x01: OSD settings.
        SetOsd(E2Osd) = SetOsd,
        /// 0x0A: move the tracking point.
        TrackPoint(Point) = TrackPoint,
        /// 0x0B: top-left corner of a tracking rectangle.
        RectTopLeft(Point) = RectTopLeft,
        /// 0x0C: bottom-right corner of a tracking rectangle.
        RectBottomRight(Point) = RectBottomRight,
        /// 0x1F: OSD colour.
        OsdColor(OsdColor) = OsdColor,
    }
}

// ---------------------------------------------------------------------------------- S1

code_enum! {
    /// Calculation control command of S1 (byte 1).
    pub enum TgccCommand: u8 {
        /// No action.
        NoAction = 0x00,
        /// Point the gimbal at a coordinate.
        FixedPoint = 0x01,
        /// Manual, air to ground (not supported yet).
        Manual = 0x02,
        /// Follow the current geographic location (not supported yet).
        FollowGeographic = 0x03,
        /// Follow a space angle.
        SpaceAngle = 0x04,
        /// Calibrate the calculated target to a given coordinate.
        Calibrate = 0x05,
    }
}

wire_struct! {
    Be;
    /// S1 0x01: point at a coordinate (WGS-84).
    pub struct FixedPoint {
        /// Byte 2: not described for this command.
        pub reserved: u8,
        /// Latitude, 1e-7°, positive north.
        pub lat_e7: i32,
        /// Longitude, 1e-7°, positive east.
        pub lon_e7: i32,
        /// Height, mm (0 = altitude 0 m).
        pub height_mm: i32,
    }
}

wire_struct! {
    Be;
    /// S1 0x04: follow a space angle (32-bit fields, 360/65536° per bit).
    pub struct SpaceAngle {
        /// Byte 2: not described for this command.
        pub reserved: u8,
        /// Optical-axis yaw from true north, positive east.
        pub yaw_bam16: i32,
        /// Optical-axis pitch from the horizontal, positive up.
        pub pitch_bam16: i32,
        /// Bytes 11..14, reserved.
        pub reserved2: [u8; 4],
    }
}

code_enum! {
    /// S1 0x05: source of the yaw error calibration (bits 0..1 of byte 2).
    pub enum YawCalibration: u8 {
        /// No meaning.
        None = 0,
        /// Yaw error entered manually (bytes 11..12).
        Manual = 1,
        /// Yaw error calibrated from the given latitude and longitude.
        FromPosition = 2,
    }
}

code_enum! {
    /// S1 0x05: source of the pitch error calibration (bits 2..3 of byte 2); it also
    /// gives the meaning of bytes 13..14.
    pub enum PitchCalibration: u8 {
        /// No meaning.
        None = 0,
        /// Pitch error entered manually (bytes 13..14 in 0.001°).
        Manual = 1,
        /// From the position and the rangefinder value (bytes 13..14 in m).
        FromRange = 2,
        /// From the position and the target's height above sea level (bytes 13..14 in m).
        FromHeight = 3,
    }
}

wire_newtype! {
    /// S1 0x05 byte 2: calibration sources (yaw bits 0..1, pitch bits 2..3, bits 4..7
    /// reserved).
    pub struct CalibrationSources(u8);
}

impl CalibrationSources {
    /// Bits 0..1.
    #[must_use]
    pub const fn yaw(self) -> YawCalibration {
        YawCalibration::from_value(bits8(self.0, 0, 2))
    }
    /// Bits 2..3.
    #[must_use]
    pub const fn pitch(self) -> PitchCalibration {
        PitchCalibration::from_value(bits8(self.0, 2, 2))
    }
    /// The byte for two sources (bits 4..7 zero).
    ///
    /// # Errors
    /// [`Error::OutOfRange`](crate::Error::OutOfRange) for a source above 3.
    pub fn new(yaw: YawCalibration, pitch: PitchCalibration) -> Result<Self> {
        let b = put_bits8(0, yaw.value(), 0, 2)?;
        put_bits8(b, pitch.value(), 2, 2).map(CalibrationSources)
    }
}

wire_struct! {
    Be;
    /// S1 0x05: calibrate the calculated target to a given coordinate.
    pub struct Calibrate {
        /// Byte 2: which errors are calibrated, and how.
        pub sources: CalibrationSources,
        /// Given latitude, 1e-7°.
        pub lat_e7: i32,
        /// Given longitude, 1e-7°.
        pub lon_e7: i32,
        /// Manual yaw error, 0.001° (positive right), when the yaw source is manual.
        pub yaw_error_mdeg: i16,
        /// Pitch value, by the pitch source: manual error in 0.001° (positive up),
        /// rangefinder distance in m, or target height above sea level in m.
        pub pitch_value: i16,
    }
}

viewlink_command_block! {
    /// S1, target calculation control, commonly used (14 bytes).
    pub enum S1: TgccCommand [13] {
        /// 0x01: point at a coordinate.
        FixedPoint(FixedPoint) = FixedPoint,
        /// 0x04: follow a space angle.
        SpaceAngle(SpaceAngle) = SpaceAngle,
        /// 0x05: calibration.
        Calibrate(Calibrate) = Calibrate,
    }
}

// ---------------------------------------------------------------------------------- S2

code_enum! {
    /// Configuration command of S2 (byte 1); all but 0x00 reserved.
    pub enum S2Command: u8 {
        /// No action.
        NoAction = 0x00,
        /// Set the current altitude as the take-off altitude (reserved).
        SetTakeoffAltitude = 0x01,
        /// Give the current target coordinate altitude (reserved).
        GiveTargetAltitude = 0x02,
        /// Save the current target altitude (reserved).
        SaveTargetAltitude = 0x03,
    }
}

wire_struct! {
    Be;
    /// S2, target calculation control, infrequently used (5 bytes).
    pub struct S2 {
        /// Byte 1: the command.
        pub command: S2Command,
        /// Bytes 2..5: the configuration parameter (not described).
        pub params: [u8; 4],
    }
}
