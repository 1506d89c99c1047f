//! Where the camera looks and where a point is from the aircraft, in a flat-earth local
//! frame (north, east, up, metres) around the aircraft: on the mean sphere (R =
//! 6 371 008.8 m) the error of the frame is below 0.1 % of the distance up to a few
//! kilometres, which is the laser's and the camera's reach (docs/src/bridge/mavlink.md,
//! "Where the camera looks"). Used by the MAVLink side and the GCU side's target position.
#![cfg_attr(not(feature = "mavlink"), allow(dead_code))]

use super::math;
use core::f32::consts::PI;

/// Metres per degree of latitude (and of longitude at the equator) on the mean sphere.
const M_PER_DEG: f32 = 6_371_008.8 * PI / 180.0;
/// 1e-7 degree per metre of latitude.
const E7_PER_M: f32 = 1.0e7 / M_PER_DEG;
/// Beyond this, the look-at point is "at infinity" (the flat frame no longer holds).
pub(super) const FLAT_REACH_M: f32 = 10_000.0;

/// A position: latitude and longitude (1e-7 degree), altitude above mean sea level (mm).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Position {
    pub(super) lat_e7: i32,
    pub(super) lon_e7: i32,
    pub(super) alt_mm: i32,
}

/// cos(latitude) of a latitude in 1e-7 degree (at least 1e-6: the poles).
#[allow(clippy::cast_precision_loss)] // ±9e8 in an f32: 1e-7 relative
fn cos_lat(lat_e7: i32) -> f32 {
    let c = math::cos(lat_e7 as f32 * 1.0e-7 * PI / 180.0);
    if c < 1.0e-6 { 1.0e-6 } else { c }
}

/// `to` from `from`: metres north, east and up.
#[allow(clippy::cast_precision_loss)] // differences of a few km: exact enough
pub(super) fn local(from: Position, to: Position) -> [f32; 3] {
    let d = |a: i32, b: i32| i64::from(b).saturating_sub(i64::from(a)) as f32;
    let north = d(from.lat_e7, to.lat_e7) / E7_PER_M;
    let east = d(from.lon_e7, to.lon_e7) / E7_PER_M * cos_lat(from.lat_e7);
    let up = d(from.alt_mm, to.alt_mm) / 1000.0;
    [north, east, up]
}

/// The point `north`, `east`, `up` metres from `from`.
#[allow(clippy::cast_possible_truncation)] // rounded offsets of a few km, saturating
pub(super) fn offset(from: Position, [north, east, up]: [f32; 3]) -> Position {
    let e7 = |m: f32| {
        let v = m * E7_PER_M;
        (if v < 0.0 { v - 0.5 } else { v + 0.5 }) as i32
    };
    let mm = (up * 1000.0) as i32;
    Position {
        lat_e7: from.lat_e7.saturating_add(e7(north)),
        lon_e7: from.lon_e7.saturating_add(e7(east / cos_lat(from.lat_e7))),
        alt_mm: from.alt_mm.saturating_add(mm),
    }
}

/// The unit vector (north, east, up) of a direction: `pitch` above the horizon, `yaw`
/// from north to the right (radians).
pub(super) fn direction(pitch: f32, yaw: f32) -> [f32; 3] {
    let h = math::cos(pitch);
    [h * math::cos(yaw), h * math::sin(yaw), math::sin(pitch)]
}

/// Bearing from north (radians, to the right) and elevation above the horizon (radians)
/// of a local vector.
pub(super) fn bearing_elevation([north, east, up]: [f32; 3]) -> (f32, f32) {
    let horizontal = math::sqrt(north * north + east * east);
    (math::atan2(east, north), math::atan2(up, horizontal))
}

/// Where the camera looks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum LookAt {
    /// At this point.
    At(Position),
    /// At or above the horizon, or beyond the flat frame's reach.
    Sky,
    /// Not known (no position or attitude).
    Unknown,
}

/// Where a camera at `here`, `height` m above the ground, looking `pitch` above the
/// horizon and `yaw` from north (radians) looks: `range` m along that direction when the
/// laser gives one, else where it meets the ground.
pub(super) fn look_at(
    here: Position,
    pitch: f32,
    yaw: f32,
    range: Option<f32>,
    height: f32,
) -> LookAt {
    let d = direction(pitch, yaw);
    let reach = match range {
        Some(r) => r,
        None if pitch >= 0.0 => return LookAt::Sky,
        None if height <= 0.0 => return LookAt::Unknown,
        // Along the direction until `height` is lost.
        None => height / -math::sin(pitch),
    };
    if reach > FLAT_REACH_M {
        return LookAt::Sky;
    }
    LookAt::At(offset(here, d.map(|c| c * reach)))
}

#[cfg(test)]
#[allow(clippy::float_cmp)]
mod tests {
    use super::*;

    #[test]
    fn a_point_and_its_offset_agree() {
        let home = Position {
            lat_e7: 473_977_420,
            lon_e7: 85_455_940,
            alt_mm: 488_000,
        };
        for v in [
            [100.0, 0.0, 0.0],
            [0.0, -250.0, 30.0],
            [1500.0, 2000.0, -400.0],
        ] {
            let p = offset(home, v);
            let back = local(home, p);
            for (a, b) in back.iter().zip(v) {
                assert!((a - b).abs() < 0.05, "{v:?} -> {back:?}");
            }
        }
        // 1 km north is 1/111.195 of a degree.
        let p = offset(home, [1000.0, 0.0, 0.0]);
        assert!((p.lat_e7 - home.lat_e7 - 89_932).abs() <= 1, "{p:?}");
        let (b, e) = bearing_elevation([0.0, 100.0, -100.0]);
        assert!((b - PI / 2.0).abs() < 1e-4 && (e + PI / 4.0).abs() < 1e-4);
        let d = direction(-PI / 2.0, 1.0);
        assert!(d[0].abs() < 1e-6 && d[1].abs() < 1e-6 && (d[2] + 1.0).abs() < 1e-6);
    }

    #[test]
    fn the_look_at_point_from_range_or_the_ground() {
        let here = Position {
            lat_e7: 473_977_420,
            lon_e7: 85_455_940,
            alt_mm: 588_000,
        };
        // 45° down, facing east, 100 m up: 100 m east, on the ground.
        let LookAt::At(p) = look_at(here, -PI / 4.0, PI / 2.0, None, 100.0) else {
            panic!()
        };
        let [n, e, u] = local(here, p);
        assert!(n.abs() < 0.1 && (e - 100.0).abs() < 0.1 && (u + 100.0).abs() < 0.1);
        // With the laser's 50 m.
        let LookAt::At(p) = look_at(here, -PI / 4.0, PI / 2.0, Some(50.0), 100.0) else {
            panic!()
        };
        let [_, e, u] = local(here, p);
        assert!((e - 35.36).abs() < 0.1 && (u + 35.36).abs() < 0.1);
        // Level without range: the horizon; far below it: beyond the flat frame.
        assert_eq!(look_at(here, 0.0, 0.0, None, 100.0), LookAt::Sky);
        assert_eq!(look_at(here, -0.001, 0.0, None, 100.0), LookAt::Sky);
        // Above the horizon with a range: the laser hit something.
        assert!(matches!(
            look_at(here, 0.2, 0.0, Some(80.0), 100.0),
            LookAt::At(_)
        ));
        assert_eq!(look_at(here, -0.5, 0.0, None, 0.0), LookAt::Unknown);
    }
}
