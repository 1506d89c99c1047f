//! Gimbal messages (document section 3.1, ids 0x000001..0x0000FF).

use super::payload::{ResponseCode, Version};

code_enum! {
    /// Upgrade state of the gimbal (0x000001 byte 2).
    pub enum UpgradeState: u8 {
        Normal = 0x00,
        /// Kernel upgrade not completed.
        KernelIncomplete = 0x01,
        /// Firmware upgrade not completed.
        FirmwareIncomplete = 0x02,
    }
}

code_enum! {
    /// Image stabilisation state (0x000001 byte 4).
    pub enum StabilizationState: u8 {
        /// Not enabled.
        Off = 0,
        /// In progress.
        Active = 1,
        Failed = 2,
        /// Feature lost.
        FeatureLost = 3,
    }
}

wire_newtype! {
    /// Connection flags (0x000001 byte 1): low nibble gimbal, high nibble camera; 0 = normal.
    pub struct Links(u8);
}

impl Links {
    /// The gimbal connection is normal.
    #[must_use]
    pub const fn gimbal_ok(self) -> bool {
        self.0.trailing_zeros() >= 4
    }
    /// The camera connection is normal.
    #[must_use]
    pub const fn camera_ok(self) -> bool {
        self.0 >> 4 == 0
    }
}

wire_newtype! {
    /// Self-test bits (0x000001 byte 3): 1 = sensor normal.
    pub struct SelfTest(u8);
}

impl SelfTest {
    /// Bit 0: infrared sensor normal.
    #[must_use]
    pub const fn infrared_ok(self) -> bool {
        self.0 & 0x01 != 0
    }
    /// Bit 1: telephoto visible sensor normal.
    #[must_use]
    pub const fn telephoto_ok(self) -> bool {
        self.0 & 0x02 != 0
    }
    /// Bit 2: wide-angle visible sensor normal.
    #[must_use]
    pub const fn wide_ok(self) -> bool {
        self.0 & 0x04 != 0
    }
    /// Bit 3: laser normal.
    #[must_use]
    pub const fn laser_ok(self) -> bool {
        self.0 & 0x08 != 0
    }
}

wire_struct! {
    Le;
    /// 0x000001, report (2 Hz): gimbal status.
    pub struct GimbalStatus {
        /// Connection state of gimbal and camera.
        pub links: Links,
        /// Upgrade state.
        pub upgrade: UpgradeState,
        /// Self-test results.
        pub self_test: SelfTest,
        /// Image stabilisation state.
        pub stabilization: StabilizationState,
        /// Reserved (bytes 5..7).
        pub reserved: [u8; 3],
    }
}

wire_struct! {
    Le;
    /// 0x000002, report (10 Hz): gimbal attitude. Angles 0.01°, rates 0.01°/s.
    pub struct GimbalAttitude {
        /// Yaw, joint angle.
        pub yaw_joint_cdeg: i16,
        /// Roll, joint angle.
        pub roll_joint_cdeg: i16,
        /// Pitch, joint angle.
        pub pitch_joint_cdeg: i16,
        /// Yaw, attitude angle.
        pub yaw_cdeg: i16,
        /// Roll, attitude angle.
        pub roll_cdeg: i16,
        /// Pitch, attitude angle.
        pub pitch_cdeg: i16,
        /// Yaw rate.
        pub yaw_rate_cdeg_s: i16,
        /// Pitch rate.
        pub pitch_rate_cdeg_s: i16,
        /// Roll rate.
        pub roll_rate_cdeg_s: i16,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: [u8; 2],
    }
}

code_enum! {
    /// Quick function of 0x000010 (byte 1). The document puts the mode in the upper four
    /// bits (`0001` centre, `0010` look down) with the lower four reserved: the wire
    /// bytes are 0x10 and 0x20.
    pub enum GimbalFunction: u8 {
        /// No operation.
        None = 0x00,
        /// Back to centre.
        Center = 0x10,
        /// Look down 90°.
        LookDown = 0x20,
    }
}

code_enum! {
    /// Yaw motion of 0x000010.
    pub enum YawMotion: u8 {
        /// Move left.
        Left = 0,
        /// Move right.
        Right = 1,
        Stop = 2,
    }
}

code_enum! {
    /// Pitch motion of 0x000010.
    pub enum PitchMotion: u8 {
        /// Move up.
        Up = 0,
        /// Move down.
        Down = 1,
        Stop = 2,
    }
}

wire_struct! {
    Le;
    /// 0x000010: gimbal control (quick function and continuous motion).
    pub struct GimbalControl {
        /// Working mode / quick function.
        pub function: GimbalFunction,
        /// Yaw motion.
        pub yaw: YawMotion,
        /// Pitch motion.
        pub pitch: PitchMotion,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

wire_struct! {
    Le;
    /// 0x000012: move to an angle. Direction bytes use the codes of [`PitchMotion`] and
    /// [`YawMotion`] (2 = no movement). The document gives no unit for the angles: this
    /// crate assumes 0.01°, like the attitude report (pitch: up to 30° up, 90° down; yaw
    /// ±180°).
    pub struct GimbalAngle {
        /// Pitch direction.
        pub pitch_direction: PitchMotion,
        /// Pitch angle magnitude.
        pub pitch_cdeg: u16,
        /// Yaw direction.
        pub yaw_direction: YawMotion,
        /// Yaw angle magnitude.
        pub yaw_cdeg: u16,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

trigger! {
    /// 0x000013: one-key drift calibration (command 0x01 = start).
    DriftCalibration;
    /// 0x000018: get the gimbal version (command 0x01).
    GimbalVersionQuery;
    /// 0x00002D: turn the servo off (command 0x00).
    ServoOff;
    /// 0x00002E: linear calibration (command 0x01).
    LinearCalibration;
    /// 0x00002F: soft restart (command 0x01).
    SoftRestart;
    /// 0x000030: use the flight controller's attitude (command 0x01).
    UseFcAttitude;
    /// 0x000031: calibrate the motion acceleration offset (command 0x01).
    AccelCalibration;
}

wire_struct! {
    Le;
    /// 0x000017: maximum dial speed. Range 5..=150 maps to 1..=30 °/s: the unit is
    /// 0.2 °/s (degrees per second times five).
    pub struct DialSpeed {
        /// Pitch dial speed.
        pub pitch_dps_x5: u8,
        /// Yaw dial speed.
        pub yaw_dps_x5: u8,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

wire_struct! {
    Le;
    /// ACK of 0x000018: response code and the hardware and software versions.
    pub struct GimbalVersionAck {
        /// Response code.
        pub code: ResponseCode,
        /// Hardware version.
        pub hardware: Version,
        /// Software version.
        pub software: Version,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

code_enum! {
    /// A lens of the pod.
    pub enum Lens: u8 {
        /// Telephoto visible lens.
        Telephoto = 0x00,
        /// Wide-angle visible lens.
        Wide = 0x01,
        /// Infrared lens.
        Infrared = 0x02,
    }
}

wire_struct! {
    Le;
    /// 0x00002C: point to aim (point at an image coordinate with a zoom).
    pub struct PointToAim {
        /// Lens the coordinates refer to.
        pub lens: Lens,
        /// Hybrid zoom ratio (telephoto 3.5..160, wide and IR 1..8 integer steps).
        pub zoom_x10: u16,
        /// X coordinate, 1..=1920 (centre 960).
        pub x: u16,
        /// Y coordinate, 1..=1080 (centre 540).
        pub y: u16,
    }
}

code_enum! {
    /// A two-state switch encoded 0 = off, 1 = on.
    pub enum OnOff: u8 {
        Off = 0,
        On = 1,
    }
}

wire_struct! {
    Le;
    /// 0x000033: image stabilisation on or off.
    pub struct Stabilization {
        /// Stabilisation switch.
        pub enable: OnOff,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}
