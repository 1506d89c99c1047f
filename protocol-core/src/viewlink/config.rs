//! U (communication configuration control, frame 0x01) and V (its feedback, frame 0x02),
//! with the parameter table of the document's appendix.

use super::block::{Block, Bytes};
use super::enums::OnOff;
use crate::Text;
use crate::wire::encoding::{Be, Field};
use crate::wire::{Reader, Writer};
use crate::{Error, Result};

/// A one-byte switch of the protocol-control command: 0x00 off, a protocol-specific
/// value on.
macro_rules! viewlink_switch {
    ($($(#[$m:meta])* $name:ident: $on:literal;)*) => {$(
        code_enum! {
            $(#[$m])*
            pub enum $name: u8 {
                /// 0x00: disabled.
                Off = 0x00,
                #[doc = concat!("`", stringify!($on), "`: enabled.")]
                On = $on,
            }
        }
    )*};
}

viewlink_switch! {
    /// GPS NMEA-0183 protocol switch (U 0x02 byte 3).
    GpsProtocol: 0x24;
    /// "3E" gimbal control protocol switch (byte 4).
    Gimbal3eProtocol: 0x3E;
    /// "7E" target tracking protocol switch (byte 5).
    Tracking7eProtocol: 0x7E;
    /// Sony VISCA protocol switch (byte 6).
    ViscaProtocol: 0x81;
    /// Target position calculation protocol switch (byte 7).
    TargetPositionProtocol: 0xF9;
    /// MAVLink v1/v2 switch (byte 8).
    MavlinkProtocol: 0xED;
    /// PELCO-D protocol switch (byte 9; the document prints "0x00 Enable", a typo).
    PelcoProtocol: 0xFF;
}

code_enum! {
    /// Laser rangefinder protocol (U 0x02 byte 2).
    pub enum LrfProtocol: u8 {
        /// 0x00: disabled.
        Off = 0x00,
        /// 0x10: the 1800 m rangefinder protocol.
        M1800 = 0x10,
        /// 0x3F: the 3000 m rangefinder protocol.
        M3000 = 0x3F,
    }
}

code_enum! {
    /// Feedback packaging (U 0x02 byte 10).
    pub enum FeedbackWrapping: u8 {
        /// 0x00: feedback protocols are output directly.
        Direct = 0x00,
        /// 0x01: feedback protocols are wrapped in Viewlink frames.
        Wrapped = 0x01,
    }
}

wire_struct! {
    Be;
    /// U 0x02 (and V 0x02/0x82): protocol control, 9 bytes.
    pub struct ProtocolControl {
        /// Byte 2: laser rangefinder protocol.
        pub lrf: LrfProtocol,
        /// Byte 3: GPS NMEA-0183.
        pub gps: GpsProtocol,
        /// Byte 4: 3E gimbal control.
        pub gimbal_3e: Gimbal3eProtocol,
        /// Byte 5: 7E target tracking.
        pub tracking_7e: Tracking7eProtocol,
        /// Byte 6: Sony VISCA.
        pub visca: ViscaProtocol,
        /// Byte 7: target position calculation.
        pub target_position: TargetPositionProtocol,
        /// Byte 8: MAVLink.
        pub mavlink: MavlinkProtocol,
        /// Byte 9: PELCO-D.
        pub pelco_d: PelcoProtocol,
        /// Byte 10: feedback packaging.
        pub feedback: FeedbackWrapping,
    }
}

wire_struct! {
    Be;
    /// U 0x04: time zone.
    pub struct TimeZone {
        /// Byte 2: hours (signed, -12..=12).
        pub hours: i8,
        /// Byte 3: minutes (signed).
        pub minutes: i8,
        /// Bytes 4..10: no meaning.
        pub reserved: [u8; 7],
    }
}

bit_set! {
    /// OSD_1 bits (U 0x05, appendix table A); a set bit hides the item.
    pub struct OsdFlags(u8) {
        /// Bit 0: hide all OSD.
        0 => hide_all, with_hide_all;
        /// Bit 1: hide the cross.
        1 => hide_cross, with_hide_cross;
        /// Bit 2: hide pitch and yaw.
        2 => hide_angles, with_hide_angles;
        /// Bit 3: hide the tracking offset (T series).
        3 => hide_offset, with_hide_offset;
        /// Bit 4: hide GPS.
        4 => hide_gps, with_hide_gps;
        /// Bit 5: hide the time.
        5 => hide_time, with_hide_time;
        /// Bit 6: hide the EO FOV / zoom level.
        6 => hide_zoom, with_hide_zoom;
        /// Bit 7: big font (T series) / hide identification boxes (A series).
        7 => big_font, with_big_font;
    }
}

bit_set! {
    /// OSD_2 / OSD type bits (U 0x07, appendix table B). Sections 3.1 and the appendix
    /// disagree on the polarity of bits 1, 2, 4, 5 and 6; the bits are kept as received.
    pub struct OsdTypeFlags(u8) {
        /// Bit 0: save the OSD settings.
        0 => save, with_save;
        /// Bit 1: IR item (3.1: display IR; table B: hide IR digital zoom).
        1 => ir, with_ir;
        /// Bit 2: LRF item (3.1: display; table B: hide).
        2 => lrf, with_lrf;
        /// Bit 3: GPS as MGRS (else geographic coordinates).
        3 => mgrs, with_mgrs;
        /// Bit 4: TF item.
        4 => tf, with_tf;
        /// Bit 5: target GPS item.
        5 => target_gps, with_target_gps;
        /// Bit 6: FOV (else zoom level) / font colour.
        6 => fov, with_fov;
        /// Bit 7: GPS in decimal degrees (else degrees, minutes, seconds).
        7 => decimal, with_decimal;
    }
}

wire_newtype! {
    /// Two RC channel numbers packed in one byte (`0xAB`: A in the high nibble, B in the
    /// low one), e.g. yaw `0xYW`: Y yaw right (1900 µs), W yaw left (1100 µs).
    pub struct ChannelPair(u8);
}

bit_set! {
    /// YPMZ (yaw, pitch, mode, zoom) channel reverse bits (U 0x10 byte 9, appendix
    /// table E): a set bit moves the command to the other end of the RC range (the
    /// stop stays at 1500 µs). Default 0xFF.
    pub struct YpmzInvert(u8) {
        /// Bit 0: zoom out at 1100 µs (else 1900 µs).
        0 => zoom_out, with_zoom_out;
        /// Bit 1: zoom in at 1900 µs (else 1100 µs).
        1 => zoom_in, with_zoom_in;
        /// Bit 2: slowest speed at 1100 µs (else 1900 µs).
        2 => speed, with_speed;
        /// Bit 3: recentre at 1900 µs (else 1100 µs).
        3 => recenter, with_recenter;
        /// Bit 4: pitch up at 1100 µs (else 1900 µs).
        4 => pitch_up, with_pitch_up;
        /// Bit 5: pitch down at 1900 µs (else 1100 µs).
        5 => pitch_down, with_pitch_down;
        /// Bit 6: yaw left at 1100 µs (else 1900 µs).
        6 => yaw_left, with_yaw_left;
        /// Bit 7: yaw right at 1900 µs (else 1100 µs).
        7 => yaw_right, with_yaw_right;
    }
}

bit_set! {
    /// PRM / FRM (focus, record, multi) channel reverse bits (U 0x10 byte 10, appendix
    /// table F): a set bit moves the command to the other end of the RC range; bits 0
    /// and 1 reserved. Default 0xFF.
    pub struct PrmInvert(u8) {
        /// Bit 2: slowest speed at 1100 µs (else 1900 µs).
        2 => speed, with_speed;
        /// Bit 3: recentre at 1900 µs (else 1100 µs).
        3 => recenter, with_recenter;
        /// Bit 4: shoot at 1100 µs (else 1900 µs).
        4 => shoot, with_shoot;
        /// Bit 5: record start/stop at 1900 µs (else 1100 µs).
        5 => record, with_record;
        /// Bit 6: picture in picture at 1100 µs (else 1900 µs).
        6 => picture_in_picture, with_picture_in_picture;
        /// Bit 7: IR colour at 1900 µs (else 1100 µs).
        7 => ir_color, with_ir_color;
    }
}

bit_set! {
    /// Target position calculation byte (appendix table C): bits 1..3 reserved, bits
    /// 5..7 the serial output format ([`TargetCalcFlags::output_format`]).
    pub struct TargetCalcFlags(u8) {
        /// Bit 0: the OSD shows the object's GPS (else the UAV's).
        0 => osd_object_gps, with_osd_object_gps;
        /// Bit 4: serial output enabled.
        4 => serial_output, with_serial_output;
    }
}

impl TargetCalcFlags {
    /// Bits 5..7: the serial output format (0 v1, 1 v2, 2 v3).
    #[must_use]
    pub const fn output_format(self) -> u8 {
        self.0 >> 5
    }
}

bit_set! {
    /// Output control (appendix 0x20).
    pub struct OutputControl(u8) {
        /// Bit 0: reset the IP address to 192.168.2.119.
        0 => reset_ip, with_reset_ip;
        /// Bit 1: tracking data on the serial port.
        1 => serial_tracking, with_serial_tracking;
        /// Bit 2: MAVLink on TCP/UDP.
        2 => network_mavlink, with_network_mavlink;
        /// Bit 3: MAVLink on the serial port.
        3 => serial_mavlink, with_serial_mavlink;
    }
}

bit_set! {
    /// Flip control (appendix 0x2E).
    pub struct FlipControl(u8) {
        /// Bit 0: EO flip off.
        0 => eo_flip_off, with_eo_flip_off;
        /// Bit 1: EO flip on.
        1 => eo_flip_on, with_eo_flip_on;
        /// Bit 4: IR flip off.
        4 => ir_flip_off, with_ir_flip_off;
        /// Bit 5: IR flip on.
        5 => ir_flip_on, with_ir_flip_on;
    }
}

bit_set! {
    /// IR raw data record (appendix 0x2F).
    pub struct IrRawRecord(u8) {
        /// Bit 0: recording on.
        0 => on, with_on;
        /// Bit 1: use the encoder angles (else the IMU's).
        1 => encoder_angles, with_encoder_angles;
    }
}

impl ChannelPair {
    /// The channel in the high nibble.
    #[must_use]
    pub const fn high(self) -> u8 {
        self.0 >> 4
    }
    /// The channel in the low nibble.
    #[must_use]
    pub const fn low(self) -> u8 {
        self.0 & 0x0F
    }
    /// Two channels (0..=15 each).
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for a channel above 15.
    pub const fn new(high: u8, low: u8) -> Result<Self> {
        if high > 15 || low > 15 {
            return Err(Error::OutOfRange);
        }
        Ok(ChannelPair((high << 4) | low))
    }
}

code_enum! {
    /// Serial baud rate (U 0x08, appendix table D).
    pub enum BaudRate: u8 {
        /// 0: default (115200).
        Default = 0,
        /// 4800 bps.
        B4800 = 1,
        /// 9600 bps.
        B9600 = 2,
        /// 19200 bps.
        B19200 = 3,
        /// 38400 bps.
        B38400 = 4,
        /// 57600 bps.
        B57600 = 5,
        /// 115200 bps.
        B115200 = 6,
        Sbus = 7,
        /// 2400 bps.
        B2400 = 8,
        /// 500000 bps.
        B500000 = 9,
    }
}

code_enum! {
    /// LRF default mode (appendix 0x0D).
    pub enum LrfMode: u8 {
        Stop = 0,
        /// Continuous (models with a rangefinder).
        Continuous = 1,
    }
}

code_enum! {
    /// Record resolution (appendix 0x0E, Z40K only).
    pub enum RecordResolution: u8 {
        P1080 = 0,
        /// 4K.
        K4 = 1,
    }
}

code_enum! {
    /// Tracking mode (appendix 0x2D).
    pub enum TrackMode: u8 {
        /// Slow-speed tracking.
        Slow = 0,
        /// High-speed tracking.
        Fast = 1,
    }
}

wire_struct! {
    Be;
    /// U 0x10 (and V 0x10/0x90): RC channel mapping, 9 bytes.
    pub struct RcMapping {
        /// Byte 2: yaw right / yaw left channels.
        pub yaw: ChannelPair,
        /// Byte 3: pitch down / pitch up channels.
        pub pitch: ChannelPair,
        /// Byte 4: recentre / slow speed channels.
        pub mode: ChannelPair,
        /// Byte 5: zoom in / zoom out channels.
        pub zoom: ChannelPair,
        /// Byte 6: focus in (colour bar) / focus out (picture in picture) channels.
        pub focus: ChannelPair,
        /// Byte 7: record / shoot channels.
        pub record: ChannelPair,
        /// Byte 8: track / stop track channels.
        pub multi: ChannelPair,
        /// Byte 9: YPMZ reverse bits.
        pub ypmz_invert: YpmzInvert,
        /// Byte 10: PRM reverse bits.
        pub prm_invert: PrmInvert,
    }
}

wire_derive! {
    [Eq, Hash, Default]
    /// A U setting with a one-byte value (byte 2); bytes 3..10 have no meaning.
    pub struct Setting1<T> {
        /// The setting's value, as the command defines it.
        pub value: T,
        /// Bytes 3..10.
        pub reserved: [u8; 8],
    }
}

impl<T> Setting1<T> {
    /// The setting with zero reserved bytes.
    pub const fn new(value: T) -> Self {
        Setting1 {
            value,
            reserved: [0; 8],
        }
    }
}

wire_derive! {
    [Eq, Hash, Default]
    /// A U setting with a two-byte value (bytes 2..3, big-endian); bytes 4..10 have no
    /// meaning.
    pub struct Setting2<T> {
        /// The setting's value, as the command defines it.
        pub value: T,
        /// Bytes 4..10.
        pub reserved: [u8; 7],
    }
}

impl<T> Setting2<T> {
    /// The setting with zero reserved bytes.
    pub const fn new(value: T) -> Self {
        Setting2 {
            value,
            reserved: [0; 7],
        }
    }
}

impl<T: Field<Be>> Field<Be> for Setting1<T> {
    const LEN: usize = 9;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        const { assert!(T::LEN == 1) };
        Ok(Setting1 {
            value: T::read(r)?,
            reserved: r.array()?,
        })
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        self.value.write(w)?;
        w.put(&self.reserved)
    }
}

impl<T: Field<Be>> Field<Be> for Setting2<T> {
    const LEN: usize = 9;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        const { assert!(T::LEN == 2) };
        Ok(Setting2 {
            value: T::read(r)?,
            reserved: r.array()?,
        })
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        self.value.write(w)?;
        w.put(&self.reserved)
    }
}

wire_struct! {
    Be;
    /// The parameters of a U query (0x82..0xEE): no meaning.
    pub struct QueryParams {
        /// Bytes 2..10.
        pub reserved: [u8; 9],
    }
}

code_enum! {
    /// Control command of U (byte 1): the settings of section 3.1 and of the appendix
    /// parameter table, and the queries.
    pub enum UCommand: u8 {
        /// 0x00: meaningless.
        None = 0x00,
        /// 0x02: protocol control.
        ProtocolControl = 0x02,
        /// 0x04: time zone.
        TimeZone = 0x04,
        /// 0x05: OSD_1 (OSD hide).
        Osd1 = 0x05,
        /// 0x06: magnetic declination (appendix).
        MagneticDeclination = 0x06,
        /// 0x07: OSD_2 (OSD type).
        Osd2 = 0x07,
        /// 0x08: serial baud rate.
        BaudRate = 0x08,
        /// 0x09: EO digital zoom (appendix).
        EoDigitalZoom = 0x09,
        /// 0x0A: thermal alarm temperature.
        AlarmTemperature = 0x0A,
        /// 0x0B: alarm temperature high byte (appendix, "temperature door 0xpq").
        AlarmTemperatureHigh = 0x0B,
        /// 0x0C: tracking (appendix).
        Tracking = 0x0C,
        /// 0x0D: LRF default mode (appendix).
        LrfDefaultMode = 0x0D,
        /// 0x0E: record resolution (appendix).
        RecordResolution = 0x0E,
        /// 0x0F: target position calculation (appendix).
        TargetPosition = 0x0F,
        /// 0x10: RC channel mapping (section 3.1; the appendix calls 0x10 the map mode).
        RcMapping = 0x10,
        /// 0x11: yaw channels (appendix).
        YawChannel = 0x11,
        /// 0x12: pitch channels (appendix).
        PitchChannel = 0x12,
        /// 0x13: recentre / speed channels (appendix).
        CenterSpeedChannel = 0x13,
        /// 0x14: zoom channels (appendix).
        ZoomChannel = 0x14,
        /// 0x15: picture-in-picture / IR colour channels (appendix).
        PipColorChannel = 0x15,
        /// 0x16: record / shoot channels (appendix).
        RecordShootChannel = 0x16,
        /// 0x17: tracking start / exit channels (appendix).
        TrackingChannel = 0x17,
        /// 0x18: focus hold mode (appendix; Z5S, Z6KA7).
        FocusHold = 0x18,
        /// 0x19: camera type (appendix; T series).
        CameraType = 0x19,
        /// 0x1A: YPMZ reverse control (appendix).
        YpmzInvert = 0x1A,
        /// 0x1B: PRM reverse control (appendix).
        PrmInvert = 0x1B,
        /// 0x1E: tracker template size (appendix).
        TemplateSize = 0x1E,
        /// 0x1F: pitch declination (appendix).
        PitchDeclination = 0x1F,
        /// 0x20: output control (appendix).
        OutputControl = 0x20,
        /// 0x21: Z40K resolution OSD (appendix).
        Z40kResolutionOsd = 0x21,
        /// 0x22: Z40K date OSD (appendix).
        Z40kDateOsd = 0x22,
        /// 0x23: Z40K all OSD (appendix).
        Z40kAllOsd = 0x23,
        /// 0x24: Z40K SD remaining OSD (appendix).
        Z40kSdOsd = 0x24,
        /// 0x25: Z40K record time OSD (appendix).
        Z40kRecordTimeOsd = 0x25,
        /// 0x26: Z40K record mode OSD (appendix).
        Z40kRecordModeOsd = 0x26,
        /// 0x27: tracking pitch P (appendix).
        TrackPitchP = 0x27,
        /// 0x28: tracking pitch I (appendix).
        TrackPitchI = 0x28,
        /// 0x29: tracking pitch D (appendix).
        TrackPitchD = 0x29,
        /// 0x2A: tracking yaw P (appendix).
        TrackYawP = 0x2A,
        /// 0x2B: tracking yaw I (appendix).
        TrackYawI = 0x2B,
        /// 0x2C: tracking yaw D (appendix).
        TrackYawD = 0x2C,
        /// 0x2D: tracking mode (appendix).
        TrackMode = 0x2D,
        /// 0x2E: flip control (appendix).
        Flip = 0x2E,
        /// 0x2F: IR raw data record (appendix).
        IrRawRecord = 0x2F,
        /// 0x30: attitude output interval (appendix, "0xpqrs").
        AttitudeInterval = 0x30,
        /// 0x31: attitude output interval high byte (appendix, "0xpq").
        AttitudeIntervalHigh = 0x31,
        /// 0x32: MAVLink system id (appendix).
        MavlinkSystemId = 0x32,
        /// 0x33: shooting interval (appendix).
        ShootInterval = 0x33,
        /// 0x34: time zone minutes (appendix).
        TimeZoneMinute = 0x34,
        /// 0x82: query the protocol control setting.
        QueryProtocolControl = 0x82,
        /// 0x84: query the time zone.
        QueryTimeZone = 0x84,
        /// 0x85: query the OSD setting.
        QueryOsd = 0x85,
        /// 0x88: query the baud rate.
        QueryBaudRate = 0x88,
        /// 0x8A: query the thermal alarm temperature.
        QueryAlarmTemperature = 0x8A,
        /// 0x90: query the RC channel mapping.
        QueryRcMapping = 0x90,
        /// 0xD0: query the gimbal firmware version.
        QueryFirmware = 0xD0,
        /// 0xE4: query the gimbal model.
        QueryModel = 0xE4,
        /// 0xEE: query the gimbal serial number.
        QuerySerialNumber = 0xEE,
    }
}

viewlink_command_block! {
    /// U, communication configuration control (frame 0x01, 10 bytes): a [`UCommand`]
    /// and nine parameter bytes laid out by it. Variant names carry the unit of their
    /// value.
    pub enum U: UCommand [9] {
        /// 0x02: protocol control.
        ProtocolControl(ProtocolControl) = ProtocolControl,
        /// 0x04: time zone.
        TimeZone(TimeZone) = TimeZone,
        /// 0x05: OSD_1 bits.
        Osd1(Setting1<OsdFlags>) = Osd1,
        /// 0x06: magnetic declination, 0.1°.
        MagneticDeclinationDdeg(Setting1<i8>) = MagneticDeclination,
        /// 0x07: OSD_2 bits.
        Osd2(Setting1<OsdTypeFlags>) = Osd2,
        /// 0x08: serial baud rate.
        BaudRate(Setting1<BaudRate>) = BaudRate,
        /// 0x09: EO digital zoom.
        EoDigitalZoom(Setting1<OnOff>) = EoDigitalZoom,
        /// 0x0A: thermal alarm temperature, °C (int16, bytes 2..3).
        AlarmTemperatureC(Setting2<i16>) = AlarmTemperature,
        /// 0x0B: high byte of the alarm temperature.
        AlarmTemperatureHigh(Setting1<u8>) = AlarmTemperatureHigh,
        /// 0x0C: tracking.
        Tracking(Setting1<OnOff>) = Tracking,
        /// 0x0D: LRF default mode.
        LrfDefaultMode(Setting1<LrfMode>) = LrfDefaultMode,
        /// 0x0E: record resolution.
        RecordResolution(Setting1<RecordResolution>) = RecordResolution,
        /// 0x0F: target position calculation bits.
        TargetPosition(Setting1<TargetCalcFlags>) = TargetPosition,
        /// 0x10: RC channel mapping.
        RcMapping(RcMapping) = RcMapping,
        /// 0x11: yaw channels (R right, L left).
        YawChannel(Setting1<ChannelPair>) = YawChannel,
        /// 0x12: pitch channels (U up, D down).
        PitchChannel(Setting1<ChannelPair>) = PitchChannel,
        /// 0x13: recentre / speed channels.
        CenterSpeedChannel(Setting1<ChannelPair>) = CenterSpeedChannel,
        /// 0x14: zoom in / zoom out channels.
        ZoomChannel(Setting1<ChannelPair>) = ZoomChannel,
        /// 0x15: picture-in-picture / colour channels.
        PipColorChannel(Setting1<ChannelPair>) = PipColorChannel,
        /// 0x16: record / shoot channels.
        RecordShootChannel(Setting1<ChannelPair>) = RecordShootChannel,
        /// 0x17: start / exit tracking channels.
        TrackingChannel(Setting1<ChannelPair>) = TrackingChannel,
        /// 0x18: focus hold mode.
        FocusHold(Setting1<u8>) = FocusHold,
        /// 0x19: camera type.
        CameraType(Setting1<u8>) = CameraType,
        /// 0x1A: YPMZ reverse bits.
        YpmzInvert(Setting1<YpmzInvert>) = YpmzInvert,
        /// 0x1B: PRM reverse bits.
        PrmInvert(Setting1<PrmInvert>) = PrmInvert,
        /// 0x1E: tracker template size (0x3C auto).
        TemplateSize(Setting1<u8>) = TemplateSize,
        /// 0x1F: pitch declination, 0.01° (int16, bytes 2..3).
        PitchDeclinationCdeg(Setting2<i16>) = PitchDeclination,
        /// 0x20: output control bits.
        OutputControl(Setting1<OutputControl>) = OutputControl,
        /// 0x21: Z40K resolution OSD (0x10 on, 0x20 off).
        Z40kResolutionOsd(Setting1<u8>) = Z40kResolutionOsd,
        /// 0x22: Z40K date OSD (0x80 on, 0x90 off).
        Z40kDateOsd(Setting1<u8>) = Z40kDateOsd,
        /// 0x23: Z40K all OSD (0x40 on, 0x30 off).
        Z40kAllOsd(Setting1<u8>) = Z40kAllOsd,
        /// 0x24: Z40K SD remaining OSD (0xB0 on, 0xA0 off).
        Z40kSdOsd(Setting1<u8>) = Z40kSdOsd,
        /// 0x25: Z40K record time OSD (0xC0 on, 0xD0 off).
        Z40kRecordTimeOsd(Setting1<u8>) = Z40kRecordTimeOsd,
        /// 0x26: Z40K record mode OSD (0x01 shoot mode, 0x00 record mode).
        Z40kRecordModeOsd(Setting1<u8>) = Z40kRecordModeOsd,
        /// 0x27: tracking pitch P, 0.1.
        TrackPitchPX10(Setting1<u8>) = TrackPitchP,
        /// 0x28: tracking pitch I, 0.001.
        TrackPitchIX1000(Setting1<u8>) = TrackPitchI,
        /// 0x29: tracking pitch D, 0.1.
        TrackPitchDX10(Setting1<u8>) = TrackPitchD,
        /// 0x2A: tracking yaw P, 0.1.
        TrackYawPX10(Setting1<u8>) = TrackYawP,
        /// 0x2B: tracking yaw I, 0.001.
        TrackYawIX1000(Setting1<u8>) = TrackYawI,
        /// 0x2C: tracking yaw D, 0.1.
        TrackYawDX10(Setting1<u8>) = TrackYawD,
        /// 0x2D: tracking mode.
        TrackMode(Setting1<TrackMode>) = TrackMode,
        /// 0x2E: flip control bits.
        Flip(Setting1<FlipControl>) = Flip,
        /// 0x2F: IR raw data record bits.
        IrRawRecord(Setting1<IrRawRecord>) = IrRawRecord,
        /// 0x30: attitude output interval, ms (uint16, bytes 2..3).
        AttitudeIntervalMs(Setting2<u16>) = AttitudeInterval,
        /// 0x31: high byte of the attitude output interval.
        AttitudeIntervalHigh(Setting1<u8>) = AttitudeIntervalHigh,
        /// 0x32: MAVLink system id (default 1).
        MavlinkSystemId(Setting1<u8>) = MavlinkSystemId,
        /// 0x33: shooting interval, 100 ms.
        ShootInterval100ms(Setting1<u8>) = ShootInterval,
        /// 0x34: time zone minutes.
        TimeZoneMinute(Setting1<i8>) = TimeZoneMinute,
        /// 0x82: query protocol control.
        QueryProtocolControl(QueryParams) = QueryProtocolControl,
        /// 0x84: query the time zone.
        QueryTimeZone(QueryParams) = QueryTimeZone,
        /// 0x85: query the OSD.
        QueryOsd(QueryParams) = QueryOsd,
        /// 0x88: query the baud rate.
        QueryBaudRate(QueryParams) = QueryBaudRate,
        /// 0x8A: query the alarm temperature.
        QueryAlarmTemperature(QueryParams) = QueryAlarmTemperature,
        /// 0x90: query the RC mapping.
        QueryRcMapping(QueryParams) = QueryRcMapping,
        /// 0xD0: query the firmware version (ArduPilot sends this).
        QueryFirmware(QueryParams) = QueryFirmware,
        /// 0xE4: query the model (ArduPilot sends this).
        QueryModel(QueryParams) = QueryModel,
        /// 0xEE: query the serial number.
        QuerySerialNumber(QueryParams) = QuerySerialNumber,
    }
}

impl U {
    /// The V command that answers this U packet: the same code. ArduPilot matches a
    /// reply to its query by the query code (0xD0 firmware, 0xE4 model).
    #[must_use]
    pub const fn reply_command(&self) -> VCommand {
        VCommand::from_value(self.command().value())
    }
}

// ----------------------------------------------------------------------------------- V

code_enum! {
    /// Control command of V (byte 1). The document lists the setting codes and
    /// 0xFC/0xFD/0xFE; ArduPilot matches the reply to its query by the query code
    /// (0xD0, 0xE4), so both sets are known and carry the same parameters.
    pub enum VCommand: u8 {
        /// 0x00: no meaning.
        None = 0x00,
        /// 0x02: protocol control (9 bytes).
        ProtocolControl = 0x02,
        /// 0x04: time zone (2 bytes).
        TimeZone = 0x04,
        /// 0x05: OSD (2 bytes).
        Osd = 0x05,
        /// 0x08: baud rate (1 byte).
        BaudRate = 0x08,
        /// 0x0A: IR alarm value (4 bytes).
        AlarmTemperature = 0x0A,
        /// 0x10: RC channel mapping (9 bytes).
        RcMapping = 0x10,
        /// 0xFC: firmware version (20 bytes).
        Firmware = 0xFC,
        /// 0xFD: model (10 bytes).
        Model = 0xFD,
        /// 0xFE: serial number (22 bytes).
        SerialNumber = 0xFE,
        /// 0x82: reply to the protocol control query.
        QueryProtocolControl = 0x82,
        /// 0x84: reply to the time zone query.
        QueryTimeZone = 0x84,
        /// 0x85: reply to the OSD query.
        QueryOsd = 0x85,
        /// 0x88: reply to the baud rate query.
        QueryBaudRate = 0x88,
        /// 0x8A: reply to the alarm temperature query.
        QueryAlarmTemperature = 0x8A,
        /// 0x90: reply to the RC mapping query.
        QueryRcMapping = 0x90,
        /// 0xD0: reply to the firmware query (what ArduPilot reads).
        QueryFirmware = 0xD0,
        /// 0xE4: reply to the model query (what ArduPilot reads).
        QueryModel = 0xE4,
        /// 0xEE: reply to the serial number query.
        QuerySerialNumber = 0xEE,
    }
}

wire_derive! {
    [Eq, Hash]
    /// What the parameters of a V packet are, by its command.
    pub enum VKind {
        /// Protocol control, 9 bytes.
        ProtocolControl,
        /// Time zone, 2 bytes.
        TimeZone,
        /// OSD, 2 bytes.
        Osd,
        /// Baud rate, 1 byte.
        BaudRate,
        /// Alarm temperature, 4 bytes.
        AlarmTemperature,
        /// RC channel mapping, 9 bytes.
        RcMapping,
        /// Firmware version, 20 bytes.
        Firmware,
        /// Model, 10 bytes.
        Model,
        /// Serial number, 22 bytes.
        SerialNumber,
        /// Not defined: the parameters are kept as bytes.
        Other,
    }
}

impl VKind {
    /// The effective parameter length the document gives (0 for `Other`).
    #[must_use]
    pub const fn len(self) -> usize {
        match self {
            VKind::ProtocolControl | VKind::RcMapping => 9,
            VKind::TimeZone | VKind::Osd => 2,
            VKind::BaudRate => 1,
            VKind::AlarmTemperature => 4,
            VKind::Firmware => 20,
            VKind::Model => 10,
            VKind::SerialNumber => 22,
            VKind::Other => 0,
        }
    }

    /// True for `Other` (no defined parameters).
    #[must_use]
    pub const fn is_empty(self) -> bool {
        matches!(self, VKind::Other)
    }
}

impl VCommand {
    /// The kind of parameters this command carries.
    #[must_use]
    pub const fn kind(self) -> VKind {
        match self {
            VCommand::ProtocolControl | VCommand::QueryProtocolControl => VKind::ProtocolControl,
            VCommand::TimeZone | VCommand::QueryTimeZone => VKind::TimeZone,
            VCommand::Osd | VCommand::QueryOsd => VKind::Osd,
            VCommand::BaudRate | VCommand::QueryBaudRate => VKind::BaudRate,
            VCommand::AlarmTemperature | VCommand::QueryAlarmTemperature => VKind::AlarmTemperature,
            VCommand::RcMapping | VCommand::QueryRcMapping => VKind::RcMapping,
            VCommand::Firmware | VCommand::QueryFirmware => VKind::Firmware,
            VCommand::Model | VCommand::QueryModel => VKind::Model,
            VCommand::SerialNumber | VCommand::QuerySerialNumber => VKind::SerialNumber,
            VCommand::None | VCommand::Other(_) => VKind::Other,
        }
    }
}

wire_struct! {
    Be;
    /// V time zone parameters.
    pub struct VTimeZone {
        /// Hours of the offset from UTC (signed).
        pub hours: i8,
        /// Minutes of the offset from UTC (signed).
        pub minutes: i8,
    }
}

wire_struct! {
    Be;
    /// V OSD parameters (OSD_1 then OSD_2).
    pub struct VOsd {
        /// OSD_1 bits.
        pub osd1: OsdFlags,
        /// OSD_2 bits.
        pub osd2: OsdTypeFlags,
    }
}

wire_struct! {
    Be;
    /// V alarm temperature parameters (4 bytes; the document gives no layout: the
    /// int16 of U 0x0A, then two bytes kept as received).
    pub struct VAlarmTemperature {
        /// Alarm temperature, °C.
        pub celsius: i16,
        /// Bytes 4..5.
        pub reserved: [u8; 2],
    }
}

wire_derive! {
    [Eq, Hash]
    /// The parameters of a V packet.
    pub enum VData {
        /// Protocol control.
        ProtocolControl(ProtocolControl),
        /// Time zone.
        TimeZone(VTimeZone),
        /// The on-screen display settings.
        Osd(VOsd),
        /// Baud rate.
        BaudRate(BaudRate),
        /// Alarm temperature.
        AlarmTemperature(VAlarmTemperature),
        /// RC channel mapping.
        RcMapping(RcMapping),
        /// Firmware version text.
        Firmware(Text<20>),
        /// Model text.
        Model(Text<10>),
        /// Serial number text.
        SerialNumber(Text<22>),
        /// Undefined parameters (or fewer bytes than the command's layout), as received.
        Other(Bytes<22>),
    }
}

impl VData {
    /// The kind of these parameters.
    #[must_use]
    pub const fn kind(&self) -> VKind {
        match self {
            VData::ProtocolControl(_) => VKind::ProtocolControl,
            VData::TimeZone(_) => VKind::TimeZone,
            VData::Osd(_) => VKind::Osd,
            VData::BaudRate(_) => VKind::BaudRate,
            VData::AlarmTemperature(_) => VKind::AlarmTemperature,
            VData::RcMapping(_) => VKind::RcMapping,
            VData::Firmware(_) => VKind::Firmware,
            VData::Model(_) => VKind::Model,
            VData::SerialNumber(_) => VKind::SerialNumber,
            VData::Other(_) => VKind::Other,
        }
    }

    /// Encoded length.
    #[must_use]
    pub const fn len(&self) -> usize {
        match self {
            VData::Other(b) => b.len(),
            other => other.kind().len(),
        }
    }

    /// True when no byte is encoded.
    #[must_use]
    pub const fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Most parameter bytes a V packet carries (bytes 2..23).
pub const V_MAX_PARAMS: usize = 22;

wire_derive! {
    [Eq, Hash]
    /// V, communication configuration status (frame 0x02, 1 + up to 22 bytes): the reply to
    /// a U packet. The parameters are typed when the packet holds at least the command's
    /// effective length; bytes beyond it are kept in `trailing`.
    pub struct V {
        /// Byte 1: the control command.
        pub command: VCommand,
        /// The parameters of the configuration command (typed, or raw: see [`VData`]).
        pub data: VData,
        /// Parameter bytes after the effective length.
        pub trailing: Bytes<22>,
    }
}

impl V {
    /// A reply with typed parameters and nothing after them.
    #[must_use]
    pub fn new(command: VCommand, data: VData) -> Self {
        V {
            command,
            data,
            trailing: Bytes::default(),
        }
    }
}

impl Block for V {
    const MAX_LEN: usize = 1 + V_MAX_PARAMS;

    fn read_block(r: &mut Reader<'_>) -> Result<Self> {
        let command = VCommand::from_value(r.u8()?);
        let rest = r.rest();
        if rest.len() > V_MAX_PARAMS {
            return Err(Error::BadLength);
        }
        let kind = command.kind();
        if kind.is_empty() || rest.len() < kind.len() {
            return Ok(V {
                command,
                data: VData::Other(Bytes::new(rest)?),
                trailing: Bytes::default(),
            });
        }
        let mut p = Reader::new(rest);
        let data = match kind {
            VKind::ProtocolControl => VData::ProtocolControl(Field::<Be>::read(&mut p)?),
            VKind::TimeZone => VData::TimeZone(Field::<Be>::read(&mut p)?),
            VKind::Osd => VData::Osd(Field::<Be>::read(&mut p)?),
            VKind::BaudRate => VData::BaudRate(Field::<Be>::read(&mut p)?),
            VKind::AlarmTemperature => VData::AlarmTemperature(Field::<Be>::read(&mut p)?),
            VKind::RcMapping => VData::RcMapping(Field::<Be>::read(&mut p)?),
            VKind::Firmware => VData::Firmware(Field::<Be>::read(&mut p)?),
            VKind::Model => VData::Model(Field::<Be>::read(&mut p)?),
            VKind::SerialNumber => VData::SerialNumber(Field::<Be>::read(&mut p)?),
            VKind::Other => VData::Other(Bytes::default()),
        };
        Ok(V {
            command,
            data,
            trailing: Bytes::new(p.rest())?,
        })
    }

    fn write_block(&self, w: &mut Writer<'_>) -> Result<()> {
        if !self.data.kind().is_empty() && self.data.kind() != self.command.kind() {
            return Err(Error::OutOfRange);
        }
        if self.data.len().saturating_add(self.trailing.len()) > V_MAX_PARAMS {
            return Err(Error::BadLength);
        }
        w.u8(self.command.value())?;
        match &self.data {
            VData::ProtocolControl(v) => v.write(w)?,
            VData::TimeZone(v) => v.write(w)?,
            VData::Osd(v) => v.write(w)?,
            VData::BaudRate(v) => Field::<Be>::write(v, w)?,
            VData::AlarmTemperature(v) => v.write(w)?,
            VData::RcMapping(v) => v.write(w)?,
            VData::Firmware(v) => Field::<Be>::write(v, w)?,
            VData::Model(v) => Field::<Be>::write(v, w)?,
            VData::SerialNumber(v) => Field::<Be>::write(v, w)?,
            VData::Other(b) => w.put(b.as_slice())?,
        }
        w.put(self.trailing.as_slice())
    }

    fn block_len(&self) -> usize {
        1usize
            .saturating_add(self.data.len())
            .saturating_add(self.trailing.len())
    }
}
