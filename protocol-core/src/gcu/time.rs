//! GPS week + time of week to and from Unix time (the document's Appendix 5, with the
//! leap seconds it leaves out).
//!
//! GPS time started at 1980-01-06T00:00:00Z and has no leap seconds; UTC has had them,
//! so GPS time is ahead of UTC by the leap-second count (18 s since 2017-01-01). The
//! document's conversion ignores them; here the count is a parameter.

/// GPS − UTC in seconds since 2017-01-01 (the default leap-second count).
pub const DEFAULT_LEAP_SECONDS: u8 = 18;

/// Unix time of the GPS epoch (1980-01-06T00:00:00Z), in milliseconds.
pub const GPS_EPOCH_UNIX_MS: u64 = 315_964_800_000;

/// Milliseconds in a GPS week.
pub const WEEK_MS: u64 = 604_800_000;

wire_derive! {
    [Eq, Hash, Default]
    /// A GPS time: week number and milliseconds into the week (the host sub data frame's
    /// bytes 55..56 and 51..54).
    pub struct GpsTime {
        /// Weeks since the GPS epoch (S16 in the document).
        pub week: i16,
        /// Milliseconds into the week.
        pub tow_ms: u32,
    }
}

impl GpsTime {
    /// The GPS time of a UTC instant given in Unix milliseconds, with `leap_seconds`
    /// (GPS − UTC). `None` before the GPS epoch or past week 32767.
    #[must_use]
    pub fn from_unix_ms(unix_ms: u64, leap_seconds: u8) -> Option<GpsTime> {
        let gps_ms = unix_ms
            .checked_add(u64::from(leap_seconds).checked_mul(1000)?)?
            .checked_sub(GPS_EPOCH_UNIX_MS)?;
        let week = i16::try_from(gps_ms.checked_div(WEEK_MS)?).ok()?;
        let tow_ms = u32::try_from(gps_ms.checked_rem(WEEK_MS)?).ok()?;
        Some(GpsTime { week, tow_ms })
    }

    /// The UTC instant in Unix milliseconds, with `leap_seconds` (GPS − UTC). A time of
    /// week beyond one week carries into the next. `None` for a negative week or an
    /// instant before the Unix epoch.
    #[must_use]
    pub fn to_unix_ms(self, leap_seconds: u8) -> Option<u64> {
        let week = u64::try_from(self.week).ok()?;
        week.checked_mul(WEEK_MS)?
            .checked_add(u64::from(self.tow_ms))?
            .checked_add(GPS_EPOCH_UNIX_MS)?
            .checked_sub(u64::from(leap_seconds).checked_mul(1000)?)
    }
}
