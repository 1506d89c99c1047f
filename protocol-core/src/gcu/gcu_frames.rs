//! The data frames of a package from the GCU: the main data frame (mode, camera
//! status, target miss, camera angles and rates) and the sub data frame (versions,
//! model, ranging and target position, zoom ratios), together [`GcuFrames`].

use super::host_frames::ControlMeaning;

code_enum! {
    /// Gimbal mode (GCU main data frame, byte 5).
    pub enum GimbalMode: u8 {
        /// FPV: the gimbal follows the carrier; control quantities are relative angles.
        Fpv = 0x10,
        /// Head lock: control quantities are angular rates; Euler angles are held.
        HeadLock = 0x11,
        /// Head follow: the heading follows the carrier when the yaw rate is 0.
        HeadFollow = 0x12,
        /// Orthoview: pitch locked at -90°.
        Orthoview = 0x13,
        /// Euler angle control: control quantities are Euler angles.
        EulerAngle = 0x14,
        Gaze = 0x16,
        Track = 0x17,
    }
}

impl GimbalMode {
    /// How the host's control quantities are read in this mode.
    #[must_use]
    pub const fn control_meaning(self) -> ControlMeaning {
        match self {
            GimbalMode::Fpv => ControlMeaning::RelativeAngle,
            GimbalMode::EulerAngle => ControlMeaning::EulerAngle,
            GimbalMode::HeadLock
            | GimbalMode::HeadFollow
            | GimbalMode::Orthoview
            | GimbalMode::Gaze => ControlMeaning::AngularRate,
            GimbalMode::Track | GimbalMode::Other(_) => ControlMeaning::Unused,
        }
    }
}

bit_set! {
    /// Camera status (GCU main data frame, bytes 6..7, u16). B1..B6, B11 and B13..B15
    /// are reserved (kept as received).
    pub struct CameraStatus(u16) {
        /// B0: tracking succeeds.
        0 => tracking, with_tracking;
        /// B7: the range and the target coordinates are valid.
        7 => range_valid, with_range_valid;
        /// B8: ranging is on.
        8 => ranging, with_ranging;
        /// B9: night vision is on.
        9 => night_vision, with_night_vision;
        /// B10: lighting is on.
        10 => lighting, with_lighting;
        /// B12: powered on upward (0: downward).
        12 => upward_power_on, with_upward_power_on;
    }
}

wire_struct! {
    Le;
    /// Main data frame from the GCU (package bytes 5..=36).
    pub struct GcuMain {
        /// Gimbal mode (byte 5).
        pub mode: GimbalMode,
        /// Camera status bits (bytes 6..7).
        pub camera_status: CameraStatus,
        /// Horizontal target miss, [-1000, 1000] from the screen centre, rightward
        /// positive (bytes 8..9).
        pub miss_horizontal: i16,
        /// Vertical target miss, [-1000, 1000] from the screen centre, downward positive
        /// (bytes 10..11).
        pub miss_vertical: i16,
        /// Camera X-axis angle relative to the carrier, 0.01° (bytes 12..13).
        pub rel_x_cdeg: i16,
        /// Camera Y-axis angle relative to the carrier, 0.01° (bytes 14..15).
        pub rel_y_cdeg: i16,
        /// Camera Z-axis angle relative to the carrier, 0.01° (bytes 16..17).
        pub rel_z_cdeg: i16,
        /// Camera absolute roll, Euler angle, [-9000, 9000], 0.01° (bytes 18..19).
        pub roll_cdeg: i16,
        /// Camera absolute pitch, Euler angle, [-18000, 18000), 0.01° (bytes 20..21).
        pub pitch_cdeg: i16,
        /// Camera absolute yaw, Euler angle, [0, 36000), 0.01° (bytes 22..23).
        pub yaw_cdeg: u16,
        /// Camera X-axis absolute angular velocity, 0.01°/s (bytes 24..25).
        pub rate_x_cdps: i16,
        /// Camera Y-axis absolute angular velocity, 0.01°/s (bytes 26..27).
        pub rate_y_cdps: i16,
        /// Camera Z-axis absolute angular velocity, 0.01°/s (bytes 28..29).
        pub rate_z_cdps: i16,
        /// Reserved (bytes 30..36), kept as received.
        pub reserved: [u8; 7],
    }
}

code_enum! {
    /// Gimbal model (GCU sub data frame, byte 40; table "Gimbal Code").
    pub enum GimbalCode: u8 {
        Z6a = 0,
        Z6c = 2,
        M2400g2 = 3,
        Z8ta = 21,
        Z8tb = 22,
        Z8ra = 24,
        Z8rb = 25,
        Z8rc = 26,
        Z8la = 27,
        Z9a = 30,
        Z9b = 31,
        D80ai = 40,
        D90ai = 41,
        D80pro = 44,
    }
}

impl GimbalCode {
    /// The model name as the document prints it (`None` for an unlisted code).
    #[must_use]
    pub const fn model(self) -> Option<&'static str> {
        Some(match self {
            GimbalCode::Z6a => "Z-6A",
            GimbalCode::Z6c => "Z-6C",
            GimbalCode::M2400g2 => "M-2400G2",
            GimbalCode::Z8ta => "Z-8TA",
            GimbalCode::Z8tb => "Z-8TB",
            GimbalCode::Z8ra => "Z-8RA",
            GimbalCode::Z8rb => "Z-8RB",
            GimbalCode::Z8rc => "Z-8RC",
            GimbalCode::Z8la => "Z-8LA",
            GimbalCode::Z9a => "Z-9A",
            GimbalCode::Z9b => "Z-9B",
            GimbalCode::D80ai => "D-80AI",
            GimbalCode::D90ai => "D-90AI",
            GimbalCode::D80pro => "D-80Pro",
            GimbalCode::Other(_) => return None,
        })
    }
}

wire_struct! {
    Le;
    /// Sub data frame from the GCU (package bytes 37..=68). All bytes are 0x00 when the
    /// host requested an unknown sub frame header ([`GcuSub::ABSENT`]).
    pub struct GcuSub {
        /// Header (byte 37): 0x01.
        pub header: u8,
        /// Hardware version (byte 38; ArduPilot shows it divided by 10).
        pub hardware_version: u8,
        /// Firmware version (byte 39; ArduPilot shows it divided by 10).
        pub firmware_version: u8,
        /// Gimbal model (byte 40).
        pub gimbal_code: GimbalCode,
        /// Error code (bytes 41..42, "reserved" in the document).
        pub error_code: u16,
        /// Distance to the target from the range finder, 0.1 m; -1 m (-10) or 0 means
        /// no valid measurement (bytes 43..46).
        pub distance_dm: i32,
        /// Target longitude, 1e-7° (bytes 47..50).
        pub target_lon_e7: i32,
        /// Target latitude, 1e-7° (bytes 51..54).
        pub target_lat_e7: i32,
        /// Target altitude, mm (bytes 55..58).
        pub target_alt_mm: i32,
        /// Zoom ratio of camera 1 (visible-light zoom camera by default), 0.1x
        /// (bytes 59..60).
        pub zoom1_x10: u16,
        /// Zoom ratio of camera 2 (thermal camera by default), 0.1x (bytes 61..62).
        pub zoom2_x10: u16,
        /// Reserved (bytes 63..68), kept as received.
        pub reserved: [u8; 6],
    }
}

impl GcuSub {
    /// No sub frame data: every byte 0x00.
    pub const ABSENT: GcuSub = GcuSub {
        header: 0,
        hardware_version: 0,
        firmware_version: 0,
        gimbal_code: GimbalCode::Z6a,
        error_code: 0,
        distance_dm: 0,
        target_lon_e7: 0,
        target_lat_e7: 0,
        target_alt_mm: 0,
        zoom1_x10: 0,
        zoom2_x10: 0,
        reserved: [0; 6],
    };

    /// True when the header announces data (non-zero).
    #[must_use]
    pub const fn is_present(&self) -> bool {
        self.header != 0
    }

    /// The range measurement in 0.1 m when it is valid (positive).
    #[must_use]
    pub const fn distance(&self) -> Option<i32> {
        if self.distance_dm > 0 {
            Some(self.distance_dm)
        } else {
            None
        }
    }
}

wire_struct! {
    Le;
    /// The two data frames of a GCU package (bytes 5..=68). The default is a zero main
    /// frame and no sub frame ([`GcuSub::ABSENT`]).
    pub struct GcuFrames {
        /// Main data frame (bytes 5..=36).
        pub main: GcuMain,
        /// Sub data frame (bytes 37..=68).
        pub sub: GcuSub,
    }
}
