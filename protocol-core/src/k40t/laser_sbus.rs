//! Laser range finder (document section 3.2.5) and SBUS configuration (3.2.6).

use super::gimbal::OnOff;
use super::payload::ResponseCode;

code_enum! {
    /// Single ranging command of 0x000400.
    pub enum LaserMode: u8 {
        Off = 0,
        /// One measurement.
        Single = 1,
    }
}

wire_struct! {
    Le;
    /// 0x000400: laser ranging.
    pub struct LaserRange {
        /// One measurement, or off.
        pub mode: LaserMode,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

wire_struct! {
    Le;
    /// ACK of 0x000400, and status frame of 0x000406: the measured distance.
    pub struct LaserDistance {
        /// Response code.
        pub code: ResponseCode,
        /// Distance, 0.1 m (0 = no value).
        pub distance_dm: u16,
    }
}

wire_struct! {
    Le;
    /// 0x000406: periodic (1 s) ranging.
    pub struct LaserPeriodic {
        /// Ranging every second on or off.
        pub enable: OnOff,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

wire_struct! {
    Le;
    /// 0x000500: SBUS channel value range (0..=2047; takes effect after a power cycle).
    pub struct SbusRange {
        /// Maximum channel value.
        pub max: u16,
        /// Minimum channel value (below the maximum).
        pub min: u16,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

wire_struct! {
    Le, bytes;
    /// The SBUS channel (0..=15 = channel 1..16) of each function.
    pub struct SbusChannelMap {
        /// Stream selection (cycles infrared, visible, split).
        pub stream: u8,
        /// Zoom (middle stop, maximum out, minimum in).
        pub zoom: u8,
        /// Taking a photo.
        pub photo: u8,
        /// Starting and stopping video recording.
        pub video: u8,
        /// Gimbal pitch.
        pub pitch: u8,
        /// Gimbal yaw.
        pub yaw: u8,
        /// Gimbal recentre.
        pub center: u8,
    }
}

wire_struct! {
    Le;
    /// 0x000501: SBUS channel of each function (bytes 1..7; byte 8 reserved; takes
    /// effect after a power cycle).
    pub struct SbusChannels {
        /// The SBUS channel of each function.
        pub channels: SbusChannelMap,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

wire_struct! {
    Le;
    /// 0x000502: get the SBUS configuration (command 0x01); the ACK is [`SbusConfig`].
    pub struct SbusConfigQuery {
        /// The command byte.
        pub command: u8,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

wire_struct! {
    Le;
    /// ACK of 0x000502: range and channel map.
    pub struct SbusConfig {
        /// Response code.
        pub code: ResponseCode,
        /// Maximum channel value.
        pub max: u16,
        /// Minimum channel value.
        pub min: u16,
        /// The SBUS channel of each function.
        pub channels: SbusChannelMap,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}
