//! The data frames of a package from the host computer (flight controller): the main
//! data frame (control quantities, carrier attitude and motion) and the sub data frame
//! (carrier position and GNSS time), together [`HostFrames`].

use super::time::GpsTime;

bit_set! {
    /// Status byte of the host main data frame (byte 11). B1 and B3..B7 are reserved
    /// (kept as received).
    pub struct HostStatus(u8) {
        /// B0: the carrier's INS data (bytes 12..29) are valid.
        0 => ins_valid, with_ins_valid;
        /// B2: the control quantities (bytes 5..10) are valid.
        2 => control_valid, with_control_valid;
    }
}

wire_derive! {
    [Eq, Hash]
    /// How the control quantities of the host main data frame are read, which depends on
    /// the gimbal's mode (main data frame table and the Command & Feedback table).
    pub enum ControlMeaning {
        /// Desired angular velocity, [-1500, 1500], in 0.1 °/s divided by the current zoom
        /// ratio of the main screen (head lock, head follow, orthoview yaw, gaze lock).
        AngularRate,
        /// Desired Euler angle, [-18000, 18000], 0.01° (Euler angle control mode).
        EulerAngle,
        /// Desired angle relative to the carrier, [-18000, 18000], 0.01° (FPV mode).
        RelativeAngle,
        /// The mode takes no control quantities (track, gaze with geo-coordinates guide, or
        /// a mode the document does not list).
        Unused,
    }
}

wire_struct! {
    Le;
    /// Main data frame from the host computer (package bytes 5..=36).
    ///
    /// The three control quantities are read according to the gimbal's mode (see
    /// [`ControlMeaning`] and [`GimbalMode::control_meaning`](super::GimbalMode::control_meaning));
    /// roll only acts in FPV and Euler angle control mode. Bytes 12..29 (carrier
    /// attitude, acceleration, velocity) matter for the gimbal's attitude estimate.
    pub struct HostMain {
        /// Roll control quantity (bytes 5..6).
        pub roll_control: i16,
        /// Pitch control quantity (bytes 7..8).
        pub pitch_control: i16,
        /// Yaw control quantity (bytes 9..10).
        pub yaw_control: i16,
        /// Status bits (byte 11).
        pub status: HostStatus,
        /// Carrier absolute roll, Euler angle, [-18000, 18000), 0.01° (bytes 12..13).
        pub carrier_roll_cdeg: i16,
        /// Carrier absolute pitch, Euler angle, [-9000, 9000], 0.01° (bytes 14..15).
        pub carrier_pitch_cdeg: i16,
        /// Carrier absolute yaw, Euler angle, [0, 36000), 0.01° (bytes 16..17). ArduPilot
        /// sends -18000..18000 as an i16 here: see [`HostMain::carrier_yaw_0_36000_cdeg`].
        pub carrier_yaw_cdeg: u16,
        /// Northward acceleration, 0.01 m/s² (bytes 18..19).
        pub accel_north_cmps2: i16,
        /// Eastward acceleration, 0.01 m/s² (bytes 20..21).
        pub accel_east_cmps2: i16,
        /// Upward acceleration, 0.01 m/s² (bytes 22..23); all three are 0 in straight
        /// flight at constant speed.
        pub accel_up_cmps2: i16,
        /// Northward velocity, 0.1 m/s (bytes 24..25).
        pub vel_north_dmps: i16,
        /// Eastward velocity, 0.1 m/s (bytes 26..27).
        pub vel_east_dmps: i16,
        /// Upward velocity, 0.1 m/s (bytes 28..29).
        pub vel_up_dmps: i16,
        /// Request code of the sub frame: the header of the sub data frame the GCU should
        /// return (byte 30; 0x01 is the one defined).
        pub sub_request: u8,
        /// Reserved (bytes 31..36), kept as received.
        pub reserved: [u8; 6],
    }
}

impl HostMain {
    /// The carrier yaw in [0, 36000) 0.01°: a value of 36000 or more is read as the
    /// negative i16 it is (ArduPilot sends -18000..18000) and gets 36000 added. Values
    /// the document allows are returned as they are.
    #[must_use]
    pub const fn carrier_yaw_0_36000_cdeg(&self) -> u16 {
        let v = self.carrier_yaw_cdeg;
        if v < 36000 {
            v
        } else {
            // v is the i16 `v - 65536` in -29536..=-1; adding 36000 gives 6464..=35999.
            v.wrapping_add(36000)
        }
    }
}

/// Header byte of the sub data frame the document defines.
pub const SUB_HEADER: u8 = 0x01;

wire_struct! {
    Le;
    /// Sub data frame from the host computer (package bytes 37..=68). All bytes are 0x00
    /// when there is no sub frame data ([`HostSub::ABSENT`]).
    pub struct HostSub {
        /// Header (byte 37): 0x01 with data, 0x00 without.
        pub header: u8,
        /// Carrier longitude, 1e-7° (bytes 38..41; longitude comes first).
        pub lon_e7: i32,
        /// Carrier latitude, 1e-7° (bytes 42..45).
        pub lat_e7: i32,
        /// Carrier altitude, mm (bytes 46..49).
        pub alt_mm: i32,
        /// Satellites in use (byte 50).
        pub satellites: u8,
        /// GPS time of week in milliseconds (bytes 51..54; the document calls it "GNSS
        /// microsecond", its own conversion code and ArduPilot use ms).
        pub gps_tow_ms: u32,
        /// GPS week number (bytes 55..56, S16 in the document).
        pub gps_week: i16,
        /// Height relative to home, mm; 0 if not needed (bytes 57..60).
        pub rel_height_mm: i32,
        /// Reserved (bytes 61..68), kept as received.
        pub reserved: [u8; 8],
    }
}

impl HostSub {
    /// No sub frame data: every byte 0x00.
    pub const ABSENT: HostSub = HostSub {
        header: 0,
        lon_e7: 0,
        lat_e7: 0,
        alt_mm: 0,
        satellites: 0,
        gps_tow_ms: 0,
        gps_week: 0,
        rel_height_mm: 0,
        reserved: [0; 8],
    };

    /// True when the header announces data (non-zero).
    #[must_use]
    pub const fn is_present(&self) -> bool {
        self.header != 0
    }

    /// The GPS week and time of week of this frame.
    #[must_use]
    pub const fn gps_time(&self) -> GpsTime {
        GpsTime {
            week: self.gps_week,
            tow_ms: self.gps_tow_ms,
        }
    }
}

wire_struct! {
    Le;
    /// The two data frames of a host package (bytes 5..=68). The default is a zero main
    /// frame and no sub frame ([`HostSub::ABSENT`]).
    pub struct HostFrames {
        /// Main data frame (bytes 5..=36).
        pub main: HostMain,
        /// Sub data frame (bytes 37..=68).
        pub sub: HostSub,
    }
}
