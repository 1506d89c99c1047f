//! The motion models: the gimbal's two axes (rates, targets, limits) and the hybrid zoom.

use super::*;

/// Image size point-to-aim coordinates refer to (the document's 1..=1920 x 1..=1080).
pub(super) const IMAGE_W: f64 = 1920.0;

pub(super) const IMAGE_H: f64 = 1080.0;

/// Optical part of the hybrid zoom (the document: above 11x is electronic).
pub(super) const OPTICAL_MAX_X10: f64 = 110.0;

/// Rounding tolerance of target moves: 1e-9 degree, 1e-12 of the zoom's logarithm.
pub(super) const ANGLE_EPSILON_DEG: f64 = 1e-9;

pub(super) const ZOOM_EPSILON_LN: f64 = 1e-12;

/// One axis of the gimbal.
#[derive(Debug, Clone, Copy)]
pub(super) enum AxisMotion {
    Hold,
    /// Direction −1, 0 or +1 at the dial speed.
    Rate(f64),
    /// Target angle at the slew speed.
    Target(f64),
}

#[derive(Debug, Clone, Copy)]
pub(super) struct Axis {
    pub(super) angle: f64,
    pub(super) motion: AxisMotion,
    pub(super) min: f64,
    pub(super) max: f64,
}

impl Axis {
    pub(super) fn new((min, max): (f64, f64)) -> Self {
        Axis {
            angle: 0.0,
            motion: AxisMotion::Hold,
            min,
            max,
        }
    }

    pub(super) fn advance(&mut self, dt_s: f64, dial_dps: f64, slew_dps: f64) {
        match self.motion {
            AxisMotion::Hold => {}
            AxisMotion::Rate(dir) => {
                self.angle = (self.angle + dir * dial_dps * dt_s).clamp(self.min, self.max);
            }
            AxisMotion::Target(target) => {
                let diff = target - self.angle;
                let step = slew_dps * dt_s;
                // The tolerance absorbs rounding over many steps: a move that should end
                // at an instant ends there.
                if diff.abs() <= step + ANGLE_EPSILON_DEG {
                    self.angle = target;
                    self.motion = AxisMotion::Hold;
                } else {
                    self.angle += step.copysign(diff);
                }
            }
        }
    }

    pub(super) fn rate(&self, dial_dps: f64, slew_dps: f64) -> f64 {
        match self.motion {
            AxisMotion::Hold => 0.0,
            AxisMotion::Rate(dir) => {
                let blocked =
                    (dir > 0.0 && self.angle >= self.max) || (dir < 0.0 && self.angle <= self.min);
                if blocked { 0.0 } else { dir * dial_dps }
            }
            AxisMotion::Target(target) if target > self.angle => slew_dps,
            AxisMotion::Target(target) if target < self.angle => -slew_dps,
            AxisMotion::Target(_) => 0.0,
        }
    }

    pub(super) fn go_to(&mut self, angle: f64) {
        self.motion = AxisMotion::Target(angle.clamp(self.min, self.max));
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum ZoomMotion {
    Idle,
    /// Towards a ratio; `hybrid`: a 0x000304 move (with status frames).
    Target {
        target: f64,
        hybrid: bool,
    },
    /// Continuous, direction −1 or +1.
    Continuous(f64),
}

impl SimPod {
    /// Moves the gimbal and zoom models to `t`.
    pub(super) fn integrate(&mut self, t: u64) {
        if t <= self.model_us {
            return;
        }
        let dt = (t - self.model_us) as f64 / 1e6;
        self.model_us = t;
        let (yaw_dial, pitch_dial) = self.dial_dps();
        let slew = self.config.slew_speed_dps;
        self.yaw.advance(dt, yaw_dial, slew);
        self.pitch.advance(dt, pitch_dial, slew);

        let (min, max) = self.zoom_limits();
        let (lo, hi) = (min.ln(), max.ln());
        let ln_now = self.camera.zoom_x10.ln();
        let step = self.config.zoom_rate_per_s * dt;
        match self.zoom {
            ZoomMotion::Idle => {}
            ZoomMotion::Target { target, .. } => {
                let diff = target.ln() - ln_now;
                if diff.abs() <= step + ZOOM_EPSILON_LN {
                    self.camera.zoom_x10 = target;
                    self.zoom_finished(t);
                } else {
                    self.camera.zoom_x10 = (ln_now + step.copysign(diff)).exp();
                }
            }
            ZoomMotion::Continuous(dir) => {
                let ln_next = (ln_now + dir * step).clamp(lo, hi);
                self.camera.zoom_x10 = ln_next.exp();
                if ln_next <= lo || ln_next >= hi {
                    self.camera.zoom_x10 = if dir > 0.0 { max } else { min };
                    self.zoom_finished(t);
                }
            }
        }
        self.camera.zooming = self.zoom != ZoomMotion::Idle;
    }

    pub(super) fn zoom_finished(&mut self, t: u64) {
        self.zoom = ZoomMotion::Idle;
        self.camera.zoom_target_x10 = None;
        if self.camera.af_after_zoom {
            self.focus_until_us = t.saturating_add(self.config.focus_duration_us);
        }
    }

    /// Microseconds until the zoom reaches `target` (rounded up).
    pub(super) fn zoom_reach_us(&self, target: f64) -> u64 {
        let rate = self.config.zoom_rate_per_s.max(1e-9);
        let s = (target.ln() - self.camera.zoom_x10.ln()).abs() / rate;
        (s * 1e6).ceil() as u64
    }

    pub(super) fn zoom_limits(&self) -> (f64, f64) {
        let min = f64::from(self.config.zoom_min_x10.max(1));
        (min, f64::from(self.config.zoom_max_x10).max(min))
    }

    pub(super) fn dial_dps(&self) -> (f64, f64) {
        (
            f64::from(self.yaw_dial_x5) / 5.0,
            f64::from(self.pitch_dial_x5) / 5.0,
        )
    }

    pub(super) fn motion(&mut self, t: u64, command: MotionCommand, blocked: bool) {
        self.motions.push(MotionRecord {
            at_us: t,
            command,
            applied: !blocked,
        });
    }

    pub(super) fn gimbal_control(&mut self, c: GimbalControl) {
        match c.function {
            GimbalFunction::Center => {
                self.yaw.go_to(0.0);
                self.pitch.go_to(0.0);
            }
            GimbalFunction::LookDown => self.pitch.go_to(-90.0),
            _ => {
                self.yaw.motion = match c.yaw {
                    YawMotion::Left => AxisMotion::Rate(-1.0),
                    YawMotion::Right => AxisMotion::Rate(1.0),
                    _ => AxisMotion::Hold,
                };
                self.pitch.motion = match c.pitch {
                    PitchMotion::Up => AxisMotion::Rate(1.0),
                    PitchMotion::Down => AxisMotion::Rate(-1.0),
                    _ => AxisMotion::Hold,
                };
            }
        }
    }

    pub(super) fn gimbal_angle(&mut self, a: GimbalAngle) {
        let pitch = f64::from(a.pitch_cdeg) / 100.0;
        match a.pitch_direction {
            PitchMotion::Up => self.pitch.go_to(pitch),
            PitchMotion::Down => self.pitch.go_to(-pitch),
            _ => {}
        }
        let yaw = f64::from(a.yaw_cdeg) / 100.0;
        match a.yaw_direction {
            YawMotion::Left => self.yaw.go_to(-yaw),
            YawMotion::Right => self.yaw.go_to(yaw),
            _ => {}
        }
    }

    pub(super) fn point_to_aim(&mut self, p: PointToAim) {
        let zoom = (f64::from(p.zoom_x10) / 10.0).max(1.0);
        let half_h = (self.config.hfov_1x_deg.to_radians() / 2.0).tan() / zoom;
        let half_v = half_h * IMAGE_H / IMAGE_W;
        let dx = ((f64::from(p.x) - IMAGE_W / 2.0) / (IMAGE_W / 2.0) * half_h)
            .atan()
            .to_degrees();
        let dy = ((f64::from(p.y) - IMAGE_H / 2.0) / (IMAGE_H / 2.0) * half_v)
            .atan()
            .to_degrees();
        self.yaw.go_to(self.yaw.angle + dx);
        self.pitch.go_to(self.pitch.angle - dy);
        if p.lens == Lens::Telephoto {
            let (min, max) = self.zoom_limits();
            self.zoom_to(f64::from(p.zoom_x10).clamp(min, max), false);
        }
    }

    pub(super) fn zoom_to(&mut self, target: f64, hybrid: bool) {
        self.zoom = ZoomMotion::Target { target, hybrid };
        self.camera.zoom_target_x10 = Some(target);
        self.camera.zooming = true;
    }

    pub(super) fn continuous_zoom(&mut self, control: ZoomControl) {
        let (min, max) = self.zoom_limits();
        let step = f64::from(self.config.zoom_step_x10);
        match control {
            ZoomControl::In => {
                self.zoom = ZoomMotion::Continuous(1.0);
                self.camera.zoom_target_x10 = None;
                self.camera.zooming = true;
            }
            ZoomControl::Out => {
                self.zoom = ZoomMotion::Continuous(-1.0);
                self.camera.zoom_target_x10 = None;
                self.camera.zooming = true;
            }
            ZoomControl::StepIn => {
                self.zoom_to((self.camera.zoom_x10.round() + step).clamp(min, max), false);
            }
            ZoomControl::StepOut => {
                self.zoom_to((self.camera.zoom_x10.round() - step).clamp(min, max), false);
            }
            _ => {
                self.zoom = ZoomMotion::Idle;
                self.camera.zoom_target_x10 = None;
                self.camera.zooming = false;
            }
        }
    }
}
