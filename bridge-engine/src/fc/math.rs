//! The few float functions the MAVLink side (and the GCU side's target position) needs
//! (quaternions to and from Euler angles, the flat-earth frame of `geo`),
//! written out: `core` has no `sqrt`, `atan2` or `sin` without `std`, and a maths
//! library's range reduction (e.g. `libm`'s `rem_pio2_large`) keeps indexing the
//! no-panic proof cannot see through. Accuracy: atan2 within 1e-5 rad, sin/cos within
//! 1e-6, far below the 0.01° (1.7e-4 rad) the bridge carries angles in.

#![cfg_attr(not(feature = "mavlink"), allow(dead_code))]

use core::f32::consts::{FRAC_PI_2, PI, TAU};

/// |x|.
fn fabs(x: f32) -> f32 {
    if x < 0.0 { -x } else { x }
}

/// Square root (Newton's method from the exponent halved); 0 for x ≤ 0 or NaN.
pub(super) fn sqrt(x: f32) -> f32 {
    if x.is_nan() || x <= 0.0 {
        return 0.0;
    }
    if x.is_infinite() {
        return x;
    }
    let mut g = f32::from_bits((x.to_bits() >> 1).wrapping_add(0x1FBD_1DF5));
    for _ in 0..4 {
        g = 0.5 * (g + x / g);
    }
    g
}

/// atan(x) for |x| ≤ 1 (Abramowitz and Stegun 4.4.49, error ≤ 1e-5).
fn atan_unit(x: f32) -> f32 {
    let x2 = x * x;
    x * (0.999_866 + x2 * (-0.330_299_5 + x2 * (0.180_141 + x2 * (-0.085_133 + x2 * 0.020_835_1))))
}

/// atan2(y, x) in (−π, π]; 0 for (0, 0).
pub(super) fn atan2(y: f32, x: f32) -> f32 {
    let (ax, ay) = (fabs(x), fabs(y));
    if ax < f32::MIN_POSITIVE && ay < f32::MIN_POSITIVE {
        return 0.0;
    }
    let a = if ax >= ay {
        atan_unit(ay / ax)
    } else {
        FRAC_PI_2 - atan_unit(ax / ay)
    };
    let a = if x < 0.0 { PI - a } else { a };
    if y < 0.0 { -a } else { a }
}

/// An angle brought into [−π, π].
#[allow(clippy::cast_possible_truncation, clippy::cast_precision_loss)] // angles are small
fn reduce(a: f32) -> f32 {
    let turns = a / TAU;
    let k = (if turns < 0.0 {
        turns - 0.5
    } else {
        turns + 0.5
    }) as i32;
    a - k as f32 * TAU
}

/// sin(x) for |x| ≤ π/2 (Taylor to x¹¹: error below 1e-7).
fn sin_half(x: f32) -> f32 {
    let x2 = x * x;
    x * (1.0
        + x2 * (-1.0 / 6.0
            + x2 * (1.0 / 120.0
                + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362_880.0 + x2 * (-1.0 / 39_916_800.0))))))
}

/// sin(a).
pub(super) fn sin(a: f32) -> f32 {
    let a = reduce(a);
    if a > FRAC_PI_2 {
        sin_half(PI - a)
    } else if a < -FRAC_PI_2 {
        sin_half(-PI - a)
    } else {
        sin_half(a)
    }
}

/// cos(a).
pub(super) fn cos(a: f32) -> f32 {
    sin(reduce(a) + FRAC_PI_2)
}

/// Roll, pitch and yaw (radians, ZYX: yaw, then pitch, then roll) of a quaternion
/// `[w, x, y, z]` (normalised here); `None` when a component is not finite or it is zero.
#[allow(clippy::many_single_char_names)] // the quaternion's own names
pub(super) fn euler(q: [f32; 4]) -> Option<[f32; 3]> {
    if q.iter().any(|c| !c.is_finite()) {
        return None;
    }
    let [w, x, y, z] = q;
    let n = sqrt(w * w + x * x + y * y + z * z);
    if n < 1e-6 {
        return None;
    }
    let (w, x, y, z) = (w / n, x / n, y / n, z / n);
    let (a, b) = (2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y));
    let roll = atan2(a, b);
    // cos(pitch) as the length of (a, b) = cos(pitch)·(sin(roll), cos(roll)): exact near
    // ±90°, where sqrt(1 − sin²) is not in f32.
    let pitch = atan2(2.0 * (w * y - z * x), sqrt(a * a + b * b));
    let yaw = atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
    Some([roll, pitch, yaw])
}

/// The quaternion `[w, x, y, z]` of roll, pitch and yaw (radians, ZYX).
pub(super) fn quaternion([roll, pitch, yaw]: [f32; 3]) -> [f32; 4] {
    let (sr, cr) = (sin(roll * 0.5), cos(roll * 0.5));
    let (sp, cp) = (sin(pitch * 0.5), cos(pitch * 0.5));
    let (sy, cy) = (sin(yaw * 0.5), cos(yaw * 0.5));
    [
        cr * cp * cy + sr * sp * sy,
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
    ]
}

/// Radians per 0.01°.
const RAD_PER_CDEG: f32 = PI / 18_000.0;

/// Radians to 0.01°, rounded (saturating); `None` when not finite.
#[allow(clippy::cast_possible_truncation)] // a float-to-int `as` saturates
pub(super) fn cdeg(rad: f32) -> Option<i32> {
    if !rad.is_finite() {
        return None;
    }
    let v = rad / RAD_PER_CDEG;
    Some((if v < 0.0 { v - 0.5 } else { v + 0.5 }) as i32)
}

/// 0.01° to radians.
#[allow(clippy::cast_precision_loss)] // ±36000 is exact in an f32
pub(super) fn rad(cdeg: i32) -> f32 {
    cdeg as f32 * RAD_PER_CDEG
}

/// An angle in 0.01° wrapped to (−18000, 18000].
pub(super) fn wrap_cdeg(v: i32) -> i32 {
    let w = v.rem_euclid(36_000);
    if w > 18_000 {
        w.saturating_sub(36_000)
    } else {
        w
    }
}

#[cfg(test)]
#[allow(
    clippy::cast_precision_loss,
    clippy::cast_possible_truncation,
    clippy::float_cmp
)]
mod tests {
    use super::*;

    fn close(a: f32, b: f32, tol: f32) -> bool {
        (a - b).abs() <= tol
    }

    #[test]
    fn functions_agree_with_std() {
        for i in -2000..=2000 {
            let a = i as f32 * 0.005;
            assert!(close(sin(a), a.sin(), 1e-6), "sin {a}");
            assert!(close(cos(a), a.cos(), 1e-6), "cos {a}");
            let x = i as f32 * 0.37;
            assert!(close(
                sqrt(x.abs()),
                x.abs().sqrt(),
                1e-5 * x.abs().max(1.0)
            ));
            for j in [-3.0f32, -0.5, 0.0, 0.25, 7.0] {
                let (y, x) = (a, j);
                if x != 0.0 || y != 0.0 {
                    assert!(close(atan2(y, x), y.atan2(x), 2e-5), "atan2 {y} {x}");
                }
            }
        }
        assert_eq!(atan2(0.0, 0.0), 0.0);
        assert_eq!(sqrt(-1.0), 0.0);
        assert_eq!(sqrt(f32::NAN), 0.0);
    }

    #[test]
    fn euler_and_quaternion_round_trip() {
        for roll in [-20.0f32, 0.0, 5.0] {
            for pitch in [-90.0f32, -89.0, -45.0, 0.0, 30.0] {
                for yaw in [-179.0f32, -90.0, 0.0, 45.0, 180.0] {
                    let q = quaternion([roll.to_radians(), pitch.to_radians(), yaw.to_radians()]);
                    let [r, p, y] = euler(q).unwrap();
                    assert!(close(p.to_degrees(), pitch, 0.01), "{pitch} -> {p}");
                    if pitch > -89.5 {
                        assert!(close(r.to_degrees(), roll, 0.01), "{roll} -> {r}");
                        let dy = wrap_cdeg(cdeg(y).unwrap() - (yaw * 100.0) as i32);
                        assert!(dy.abs() <= 1, "{yaw} -> {}", y.to_degrees());
                    }
                }
            }
        }
        assert_eq!(euler([f32::NAN; 4]), None);
        assert_eq!(euler([0.0; 4]), None);
        // Not normalised: the same angles.
        let q = quaternion([0.0, 0.5, 1.0]).map(|c| c * 3.0);
        let [_, p, y] = euler(q).unwrap();
        assert!(close(p, 0.5, 1e-4) && close(y, 1.0, 1e-4));
    }

    #[test]
    fn units() {
        assert_eq!(cdeg(PI), Some(18_000));
        assert_eq!(cdeg(-FRAC_PI_2), Some(-9_000));
        assert_eq!(cdeg(f32::NAN), None);
        assert_eq!(cdeg(1e30), Some(i32::MAX));
        assert!(close(rad(9_000), FRAC_PI_2, 1e-6));
        assert_eq!(wrap_cdeg(18_000), 18_000);
        assert_eq!(wrap_cdeg(-18_000), 18_000);
        assert_eq!(wrap_cdeg(27_000), -9_000);
        assert_eq!(wrap_cdeg(i32::MIN), wrap_cdeg(i32::MIN % 36_000));
    }
}
