//! Motion, never flooding the pod: the target the FC asks for ([`MotionTarget`]), sent
//! when it differs from the last one sent by more than a dead-band, at most once per
//! motion interval, refreshed while the gimbal turns; a rate becomes a direction
//! (0x000010) and a dial speed (0x000017).

use super::PodDriver;
use crate::Outputs;
use crate::config::PodConfig;
use crate::time::Instant;
use protocol_core::k40t::{
    self, GimbalAngle, GimbalControl, GimbalFunction, PitchMotion, Request, YawMotion,
};

/// Slowest dial speed the pod accepts (0.2 °/s units: 1 °/s).
pub(super) const MIN_DIAL_X5: u8 = 5;
/// Fastest dial speed (30 °/s).
pub(super) const MAX_DIAL_X5: u8 = 150;

/// The motion the pod was asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum MotionTarget {
    /// Directions and dial speeds (0.2 °/s units).
    Turn {
        yaw: YawMotion,
        pitch: PitchMotion,
        yaw_x5: u8,
        pitch_x5: u8,
        /// The rates asked, for the dead-band (0.01 °/s).
        yaw_cdeg_s: i32,
        pitch_cdeg_s: i32,
    },
    /// An absolute angle (0.01 °).
    Angle { yaw_cdeg: i32, pitch_cdeg: i32 },
    /// A quick function (centre, look down): sent once.
    Function(GimbalFunction),
}

impl MotionTarget {
    pub(super) const STOP: Self = MotionTarget::Turn {
        yaw: YawMotion::Stop,
        pitch: PitchMotion::Stop,
        yaw_x5: 0,
        pitch_x5: 0,
        yaw_cdeg_s: 0,
        pitch_cdeg_s: 0,
    };

    pub(super) fn is_turning(&self) -> bool {
        matches!(self, MotionTarget::Turn { yaw, pitch, .. }
            if *yaw != YawMotion::Stop || *pitch != PitchMotion::Stop)
    }

    /// True when `self` is a new command compared with `sent`.
    pub(super) fn differs(&self, sent: &Self, cfg: &PodConfig) -> bool {
        match (self, sent) {
            (
                MotionTarget::Turn {
                    yaw,
                    pitch,
                    yaw_cdeg_s,
                    pitch_cdeg_s,
                    ..
                },
                MotionTarget::Turn {
                    yaw: y0,
                    pitch: p0,
                    yaw_cdeg_s: yr0,
                    pitch_cdeg_s: pr0,
                    ..
                },
            ) => {
                let band = u32::from(cfg.rate_deadband_cdeg_s);
                yaw != y0
                    || pitch != p0
                    || yaw_cdeg_s.abs_diff(*yr0) >= band
                    || pitch_cdeg_s.abs_diff(*pr0) >= band
            }
            (
                MotionTarget::Angle {
                    yaw_cdeg,
                    pitch_cdeg,
                },
                MotionTarget::Angle {
                    yaw_cdeg: y0,
                    pitch_cdeg: p0,
                },
            ) => {
                let band = u32::from(cfg.angle_deadband_cdeg);
                yaw_cdeg.abs_diff(*y0) >= band || pitch_cdeg.abs_diff(*p0) >= band
            }
            (a, b) => a != b,
        }
    }
}

/// The motion state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct MotionState {
    /// What the FC wants.
    pub(super) target: MotionTarget,
    /// What was sent last, and when.
    pub(super) sent: Option<(MotionTarget, Instant)>,
    /// Dial speeds last sent (0.2 °/s units).
    pub(super) dial: Option<(u8, u8)>,
    /// The FC's last motion command.
    pub(super) fc_at: Option<Instant>,
}

impl PodDriver {
    pub(super) fn set_motion(&mut self, now: Instant, target: MotionTarget, out: &mut Outputs) {
        self.motion.target = target;
        let due = match self.motion.sent {
            None => true,
            Some((sent, at)) => {
                target.differs(&sent, &self.cfg)
                    && now.saturating_duration_since(at) >= self.cfg.motion_interval
            }
        };
        if due {
            self.send_motion(now, out);
        }
    }

    /// Sends the motion target now (ending the pod's box tracking first).
    pub(super) fn send_motion(&mut self, now: Instant, out: &mut Outputs) {
        self.end_tracking(now, out);
        let target = self.motion.target;
        let request = match target {
            MotionTarget::Turn {
                yaw,
                pitch,
                yaw_x5,
                pitch_x5,
                ..
            } => {
                let turning = target.is_turning();
                if turning && self.motion.dial != Some((pitch_x5, yaw_x5)) {
                    let dial = Request::DialSpeed(k40t::DialSpeed {
                        pitch_dps_x5: pitch_x5.max(MIN_DIAL_X5),
                        yaw_dps_x5: yaw_x5.max(MIN_DIAL_X5),
                        reserved: 0,
                    });
                    if self.send(dial, false, out).is_some() {
                        self.motion.dial = Some((pitch_x5, yaw_x5));
                    }
                }
                Request::GimbalControl(GimbalControl {
                    function: GimbalFunction::None,
                    yaw,
                    pitch,
                    reserved: 0,
                })
            }
            MotionTarget::Angle {
                yaw_cdeg,
                pitch_cdeg,
            } => Request::GimbalAngle(GimbalAngle {
                pitch_direction: if pitch_cdeg >= 0 {
                    PitchMotion::Up
                } else {
                    PitchMotion::Down
                },
                pitch_cdeg: u16::try_from(pitch_cdeg.unsigned_abs()).unwrap_or(u16::MAX),
                yaw_direction: if yaw_cdeg >= 0 {
                    YawMotion::Right
                } else {
                    YawMotion::Left
                },
                yaw_cdeg: u16::try_from(yaw_cdeg.unsigned_abs()).unwrap_or(u16::MAX),
                reserved: 0,
            }),
            MotionTarget::Function(function) => Request::GimbalControl(GimbalControl {
                function,
                yaw: YawMotion::Stop,
                pitch: PitchMotion::Stop,
                reserved: 0,
            }),
        };
        self.send(request, false, out);
        self.motion.sent = Some((target, now));
    }

    /// Stops the gimbal (the FC fell silent).
    pub(super) fn stop(&mut self, now: Instant, out: &mut Outputs) {
        self.motion.target = MotionTarget::STOP;
        self.send_motion(now, out);
    }
}

/// A signed rate as a direction and a dial speed (0.2 °/s units, 5..=150 when moving).
pub(super) fn split_rate<D: Copy>(rate_cdeg_s: i32, positive: D, negative: D, stop: D) -> (D, u8) {
    if rate_cdeg_s == 0 {
        return (stop, 0);
    }
    // 0.01 °/s -> 0.2 °/s: divide by 20.
    let x5 =
        (rate_cdeg_s.unsigned_abs() / 20).clamp(u32::from(MIN_DIAL_X5), u32::from(MAX_DIAL_X5));
    let x5 = u8::try_from(x5).unwrap_or(MAX_DIAL_X5);
    (if rate_cdeg_s > 0 { positive } else { negative }, x5)
}
