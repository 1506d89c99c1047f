//! The photo event file (`gimbal bridge --photo-events FILE`): one CSV row per photo the
//! pod geotagged (the engine's `photo` event), for post-processing (PPK) and
//! photogrammetry tools.
//!
//! ```text
//! # gimbal bridge photo events (docs/src/linux-bridge.md, "Photo event file")
//! label,utc,gps_week,gps_tow_s,lat_deg,lon_deg,alt_msl_m,rel_alt_m,yaw_deg,pitch_deg,roll_deg
//! photo_0001,2026-11-23T10:00:12.345Z,2446,122430.345,47.3977419,8.5455938,488.0,50.0,12.50,-0.25,0.10
//! ```
//!
//! The time is the photo's UTC as the pod named it in its geotag request (to the
//! millisecond, on the disciplined clock) and the same instant as GPS week and seconds of
//! week (GPS time = UTC + the configured leap seconds): what a PPK tool interpolates its
//! post-processed trajectory at (the camera events of a GNSS receiver's event input are
//! GPS time too). Position and attitude are the FC's fix interpolated to that instant
//! (what the pod was told); the altitude is above mean sea level, as the autopilot
//! reports it. The columns after `utc` are those a photogrammetry tool's reference
//! import maps (Agisoft Metashape: label, latitude, longitude, altitude, yaw, pitch,
//! roll; Pix4D: the same with its own angle names).

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use bridge_engine::PhotoEvent;

use super::output::iso_utc;

/// Seconds from the Unix epoch to the GPS epoch (1980-01-06T00:00:00Z).
const GPS_EPOCH_UNIX_S: i64 = 315_964_800;
/// Seconds in a GPS week.
const WEEK_S: i64 = 604_800;

/// The GPS week and seconds of week of a UTC instant (µs), `leap_seconds` being GPS −
/// UTC.
#[must_use]
pub fn gps_week_tow(utc_us: u64, leap_seconds: u8) -> (i64, f64) {
    let us = i64::try_from(utc_us).unwrap_or(i64::MAX) - GPS_EPOCH_UNIX_S * 1_000_000
        + i64::from(leap_seconds) * 1_000_000;
    let week = us.div_euclid(WEEK_S * 1_000_000);
    let tow_us = us.rem_euclid(WEEK_S * 1_000_000);
    (week, tow_us as f64 / 1e6)
}

/// The file, written row by row (flushed after each).
pub struct PhotoEvents {
    file: BufWriter<File>,
    leap_seconds: u8,
    count: u32,
}

impl PhotoEvents {
    /// Creates `path` (replacing it) and writes the header.
    ///
    /// # Errors
    /// The file cannot be created or written.
    pub fn create(path: &Path, leap_seconds: u8) -> io::Result<Self> {
        let mut file = BufWriter::new(File::create(path)?);
        writeln!(
            file,
            "# gimbal bridge photo events (docs/src/linux-bridge.md, \"Photo event file\")"
        )?;
        writeln!(
            file,
            "label,utc,gps_week,gps_tow_s,lat_deg,lon_deg,alt_msl_m,rel_alt_m,yaw_deg,pitch_deg,roll_deg"
        )?;
        file.flush()?;
        Ok(PhotoEvents {
            file,
            leap_seconds,
            count: 0,
        })
    }

    /// Appends `p`.
    ///
    /// # Errors
    /// The file cannot be written.
    pub fn push(&mut self, p: &PhotoEvent) -> io::Result<()> {
        self.count += 1;
        let (week, tow) = gps_week_tow(p.utc_us, self.leap_seconds);
        writeln!(
            self.file,
            "photo_{:04},{},{week},{tow:.3},{:.7},{:.7},{:.1},{:.1},{:.2},{:.2},{:.2}",
            self.count,
            iso_utc(p.utc_us / 1_000),
            f64::from(p.lat_e7) * 1e-7,
            f64::from(p.lon_e7) * 1e-7,
            f64::from(p.alt_msl_dm) / 10.0,
            f64::from(p.rel_alt_dm) / 10.0,
            f64::from(p.yaw_cdeg) / 100.0,
            f64::from(p.pitch_cdeg) / 100.0,
            f64::from(p.roll_cdeg) / 100.0,
        )?;
        self.file.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gps_time_of_utc() {
        // 2026-11-23T10:00:12.345Z (a Monday): GPS week 2446, 1 day 10:00:30.345 into
        // it with 18 leap seconds.
        let utc_us = 1_795_428_012_345_000;
        let (week, tow) = gps_week_tow(utc_us, 18);
        assert_eq!(week, 2446);
        assert!((tow - (86_400.0 + 36_030.345)).abs() < 1e-6, "{tow}");
    }

    #[test]
    fn rows_are_csv_with_the_header() {
        let path = std::env::temp_dir().join(format!("photos-{}.csv", std::process::id()));
        let mut f = PhotoEvents::create(&path, 18).unwrap();
        f.push(&PhotoEvent {
            utc_us: 1_795_428_012_345_000,
            lat_e7: 473_977_419,
            lon_e7: 85_455_938,
            alt_msl_dm: 4880,
            rel_alt_dm: 500,
            yaw_cdeg: 1250,
            pitch_cdeg: -25,
            roll_cdeg: 10,
        })
        .unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let _ = std::fs::remove_file(&path);
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[0].starts_with("# gimbal bridge photo events"));
        assert!(lines[1].starts_with("label,utc,gps_week,gps_tow_s,"));
        assert_eq!(
            lines[2],
            "photo_0001,2026-11-23T10:00:12.345Z,2446,122430.345,47.3977419,8.5455938,488.0,50.0,12.50,-0.25,0.10"
        );
    }
}
