//! What an ArduPilot mount driver is told to do (`AP_Mount_Backend`'s `MountTarget` and
//! modes), shared by the simulated ArduPilot drivers that take more than angles and rates
//! from their FC code: [`super::ap_mavlink`] (every variant) and [`super::ap_xfrobot`]
//! (angles and rates; the others are held at neutral).

/// What the mount is told to do.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MountTarget {
    /// Hold these angles (degrees): roll and pitch against the horizon, yaw from north
    /// (`yaw_is_ef`) or from the nose.
    Angle {
        /// Roll.
        roll_deg: f64,
        /// Pitch, positive up.
        pitch_deg: f64,
        /// Yaw, positive right.
        yaw_deg: f64,
        /// Yaw from north.
        yaw_is_ef: bool,
    },
    /// Turn at these rates (deg/s).
    Rate {
        /// Pitch rate.
        pitch_dps: f64,
        /// Yaw rate.
        yaw_dps: f64,
        /// Earth-frame yaw rate.
        yaw_is_ef: bool,
        /// Set by a MAVLink command (zeroed after 3 s without another), else RC.
        from_mavlink: bool,
    },
    /// Retracted.
    Retract,
    /// Neutral (`MNT1_NEUTRAL_*`: 0, 0, 0).
    Neutral,
    /// Point at a location (a region of interest): latitude, longitude (degE7),
    /// altitude above mean sea level (m).
    Location {
        /// Latitude.
        lat_e7: i32,
        /// Longitude.
        lon_e7: i32,
        /// Altitude, m AMSL.
        alt_m: f64,
    },
}

impl MountTarget {
    /// Hold these angles (degrees) without roll, yaw from the nose: what a pilot's or a
    /// ground station's angle command usually is.
    #[must_use]
    pub const fn body_angles(pitch_deg: f64, yaw_deg: f64) -> Self {
        Self::Angle {
            roll_deg: 0.0,
            pitch_deg,
            yaw_deg,
            yaw_is_ef: false,
        }
    }
}
