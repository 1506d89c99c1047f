//! Laser rangefinder messages (ZT30): distance (0x15), target position (0x17) and the
//! laser switch (0x31, 0x32).

use super::payload::OnOff;

wire_struct! {
    Le;
    /// Reply of 0x15: laser distance.
    pub struct LaserDistance {
        /// Distance in decimetres (minimum 50; 0 = no valid reading).
        pub distance_dm: u16,
    }
}

wire_struct! {
    Le;
    /// Reply of 0x17: position of the laser target (longitude first).
    pub struct LaserTarget {
        /// Longitude, 1e-7 degree (WGS84).
        pub lon_e7: i32,
        /// Latitude, 1e-7 degree (WGS84).
        pub lat_e7: i32,
    }
}

wire_struct! {
    Le;
    /// Reply of 0x31: laser ranging on or off (also the layout of the 0x32 request,
    /// [`SetLaserState`](super::SetLaserState)).
    pub struct LaserState {
        /// Laser ranging on or off.
        pub state: OnOff,
    }
}
