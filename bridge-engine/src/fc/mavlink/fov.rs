//! The cameras' fields of view, from the lens facts of the configuration (`[lens]`: the
//! K40T's vendor publishes none, so each is 0, unknown, until configured) and what the
//! pod reports (docs/src/bridge/mavlink.md, "Fields of view"):
//!
//! - **Visible**, at hybrid zoom z (0x000005): with the sensor width and a focal length,
//!   2·atan(w / (2·f·d)), f the focal length the pod reports (0x000005; else the
//!   configured range's f_min·z, at most f_max) and d the digital part of the zoom, z
//!   over the optical ratio f / f_min (without f_min: z / 11, the K40T external protocol
//!   saying zooms above 11x are electronic, 3.2.1.3); else from the configured 1x field
//!   of view, 2·atan(tan(hfov₁ₓ/2) / z); else unknown (NaN).
//! - **Thermal**: the configured field of view over the IR digital zoom (0x000105), the
//!   same way; else unknown.
//! - **Split screen**: unknown (the document does not say how the two pictures share the
//!   frame).
//!
//! Vertical fields of view follow from the picture's aspect: the stream's (0x000003,
//! 16:9) for the visible camera, 640 × 512 for the thermal one (3.2.4.3).

use super::math;
use crate::config::LensConfig;
use crate::gimbal::View;
use crate::pod::PodState;
use core::f32::consts::PI;
use protocol_core::k40t::VisibleStatus;

/// The zoom above which the hybrid zoom is digital when the lens range is not known.
const OPTICAL_MAX_X: f32 = 11.0;
/// The thermal picture's height over its width (640 × 512).
const IR_ASPECT: f32 = 512.0 / 640.0;

/// Horizontal and vertical fields of view, degrees (NaN: unknown).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Fov {
    pub(super) h: f32,
    pub(super) v: f32,
}

impl Fov {
    const UNKNOWN: Self = Self {
        h: f32::NAN,
        v: f32::NAN,
    };

    /// The horizontal field of view in whole degrees (VIDEO_STREAM_* `hfov`; 0: unknown).
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // 0..180
    pub(super) fn h_whole_deg(self) -> u16 {
        if self.h.is_finite() && self.h > 0.0 {
            (self.h + 0.5) as u16
        } else {
            0
        }
    }
}

fn tan(x: f32) -> f32 {
    math::sin(x) / math::cos(x)
}

fn deg(rad: f32) -> f32 {
    rad * 180.0 / PI
}

fn rad(deg: f32) -> f32 {
    deg * PI / 180.0
}

/// A field of view (degrees) narrowed by a digital zoom `z` (a crop: tangents scale).
fn zoomed(fov_deg: f32, z: f32) -> f32 {
    deg(2.0 * math::atan2(tan(rad(fov_deg) / 2.0), z.max(1.0)))
}

/// The other side's field of view of a picture whose height over width is `aspect`.
fn across(fov_deg: f32, aspect: f32) -> f32 {
    deg(2.0 * math::atan2(tan(rad(fov_deg) / 2.0) * aspect, 1.0))
}

#[allow(clippy::cast_precision_loss)] // µm and 0.01 mm below 2^24
fn um(v: u32) -> f32 {
    v as f32
}

/// The visible camera's horizontal field of view, degrees (NaN: unknown).
pub(super) fn visible_hfov(lens: &LensConfig, status: Option<VisibleStatus>) -> f32 {
    let z = status.map_or(1.0, |s| f32::from(s.zoom_x10.max(10)) / 10.0);
    let reported = status.map_or(0.0, |s| f32::from(s.focal_length_10um) * 10.0);
    let (w, f_min, f_max) = (
        um(lens.sensor_width_um),
        um(lens.focal_length_min_um),
        um(lens.focal_length_max_um),
    );
    if w > 0.0 && (reported > 0.0 || f_min > 0.0) {
        let f = if reported > 0.0 {
            reported
        } else if f_max > 0.0 {
            (f_min * z).min(f_max)
        } else {
            f_min * z
        };
        let optical = if f_min > 0.0 {
            f / f_min
        } else {
            z.min(OPTICAL_MAX_X)
        };
        let digital = (z / optical).max(1.0);
        return deg(2.0 * math::atan2(w, 2.0 * f * digital));
    }
    if lens.visible_hfov_1x_cdeg > 0 {
        return zoomed(um(lens.visible_hfov_1x_cdeg) / 100.0, z);
    }
    f32::NAN
}

/// The thermal camera's horizontal field of view, degrees (NaN: unknown).
pub(super) fn ir_hfov(lens: &LensConfig, ir_zoom: Option<u8>) -> f32 {
    if lens.ir_hfov_cdeg == 0 {
        return f32::NAN;
    }
    zoomed(
        um(lens.ir_hfov_cdeg) / 100.0,
        f32::from(ir_zoom.unwrap_or(1)),
    )
}

/// The streamed picture's height over its width: both preview resolutions of 0x000003
/// (1080p, 720p) are 16:9.
const STREAM_ASPECT: f32 = 9.0 / 16.0;

/// The field of view of the picture the pod streams now.
pub(super) fn current(lens: &LensConfig, pod: &PodState) -> Fov {
    let (h, aspect) = match pod.view() {
        Some(View::Visible) => (visible_hfov(lens, pod.visible), STREAM_ASPECT),
        Some(View::Thermal) => (ir_hfov(lens, pod.ir_zoom), IR_ASPECT),
        Some(View::Split) | None => return Fov::UNKNOWN,
    };
    Fov {
        h,
        v: if h.is_finite() {
            across(h, aspect)
        } else {
            f32::NAN
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn status(zoom_x10: u16, focal_length_10um: u16) -> VisibleStatus {
        VisibleStatus {
            zoom_x10,
            focal_length_10um,
            ..VisibleStatus::default()
        }
    }

    #[test]
    fn fields_of_view_from_the_lens_facts() {
        let mut lens = LensConfig::DEFAULT;
        assert!(visible_hfov(&lens, Some(status(10, 450))).is_nan());
        assert!(ir_hfov(&lens, Some(2)).is_nan());
        // A 60° camera at 2x: 2·atan(tan 30° / 2) = 32.2°.
        lens.visible_hfov_1x_cdeg = 6000;
        let h = visible_hfov(&lens, Some(status(20, 0)));
        assert!((h - 32.204).abs() < 0.01, "{h}");
        assert!((visible_hfov(&lens, None) - 60.0).abs() < 0.01);
        // A 6.4 mm wide sensor behind 4.5 mm at 1x: 2·atan(3.2/4.5) = 70.85°; the pod's
        // focal length wins over the configured 1x field of view.
        lens.sensor_width_um = 6400;
        lens.focal_length_min_um = 4500;
        let h = visible_hfov(&lens, Some(status(10, 450)));
        assert!((h - 70.85).abs() < 0.02, "{h}");
        // 22x with the optics at 11x (49.5 mm): a digital 2x on top.
        let h = visible_hfov(&lens, Some(status(220, 4950)));
        let want = 2.0 * (3.2f32 / (49.5 * 2.0)).atan().to_degrees();
        assert!((h - want).abs() < 0.01, "{h} {want}");
        // Without the pod's focal length: f_min·z up to f_max.
        lens.focal_length_max_um = 49_500;
        let h = visible_hfov(&lens, Some(status(220, 0)));
        assert!((h - want).abs() < 0.01, "{h} {want}");
        // Thermal: 48° over a digital 4x.
        lens.ir_hfov_cdeg = 4800;
        let h = ir_hfov(&lens, Some(4));
        let want = 2.0 * ((24f32).to_radians().tan() / 4.0).atan().to_degrees();
        assert!((h - want).abs() < 0.01, "{h} {want}");
        assert!((across(90.0, 0.5) - 53.13).abs() < 0.01);
        let f = Fov { h: 59.6, v: 0.0 };
        assert_eq!(f.h_whole_deg(), 60);
        assert_eq!(Fov::UNKNOWN.h_whole_deg(), 0);
    }
}
