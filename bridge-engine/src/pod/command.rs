//! The command mapping: an FC [`Command`] as K40T requests (a motion target, or a
//! camera request tracked for its ACK).

use super::PodDriver;
use super::motion::{MAX_DIAL_X5, MotionTarget, split_rate};
use super::state::PodState;
use crate::Outputs;
use crate::event::Event;
use crate::gimbal::{Command, Motion, Ranging, Target, View};
use crate::time::Instant;
use protocol_core::k40t::{
    self, AiRecognition, ContinuousZoom, Focus, FocusMode, GimbalFunction, HybridZoom, ImageMode,
    ImageModeSetting, IrDigitalZoom, IrGain, IrGainMode, IrPalette, LaserMode, LaserPeriodic,
    LaserRange, Lens, OnOff, PhotoSensors, PitchMotion, PointToAim, Record, RecordAction,
    RecordSensors, Request, ShootAction, TakePhoto, Text, Toggle, TrackBox, YawMotion, ZoomControl,
};

impl PodDriver {
    /// Translates one FC command. Returns the K40T base id of the request sent (or to
    /// be sent, for edge-triggered motion), `None` when the command has no K40T
    /// equivalent.
    pub(crate) fn command(&mut self, now: Instant, cmd: Command, out: &mut Outputs) -> Option<u16> {
        match cmd {
            Command::Rates {
                yaw_cdeg_s,
                pitch_cdeg_s,
            } => {
                self.motion.fc_at = Some(now);
                let (yaw, yaw_x5) = split_rate(
                    yaw_cdeg_s,
                    YawMotion::Right,
                    YawMotion::Left,
                    YawMotion::Stop,
                );
                let (pitch, pitch_x5) = split_rate(
                    pitch_cdeg_s,
                    PitchMotion::Up,
                    PitchMotion::Down,
                    PitchMotion::Stop,
                );
                for r in [yaw_cdeg_s, pitch_cdeg_s] {
                    if r.unsigned_abs() > u32::from(MAX_DIAL_X5).saturating_mul(20) {
                        out.event(Event::RateClamped {
                            requested_cdeg_s: r,
                        });
                    }
                }
                self.set_motion(
                    now,
                    MotionTarget::Turn {
                        yaw,
                        pitch,
                        yaw_x5,
                        pitch_x5,
                        yaw_cdeg_s,
                        pitch_cdeg_s,
                    },
                    out,
                );
                Some(0x0010)
            }
            Command::Angles {
                yaw_cdeg,
                pitch_cdeg,
            } => {
                self.motion.fc_at = Some(now);
                self.set_motion(
                    now,
                    MotionTarget::Angle {
                        yaw_cdeg: yaw_cdeg.clamp(-18000, 18000),
                        pitch_cdeg: pitch_cdeg.clamp(-9000, 3000),
                    },
                    out,
                );
                Some(0x0012)
            }
            Command::Center => {
                self.set_motion(now, MotionTarget::Function(GimbalFunction::Center), out);
                Some(0x0010)
            }
            Command::LookDown => {
                self.set_motion(now, MotionTarget::Function(GimbalFunction::LookDown), out);
                Some(0x0010)
            }
            Command::Mode(mode) => {
                self.state.mode = Some(mode);
                None
            }
            other => {
                // "AI detection must be turned on to perform frame selection target
                // tracking" (0x000324): switched on first, once; it stays on.
                if let Command::Track(Some(_)) = other
                    && !self.state.ai
                {
                    let ai = Request::AiRecognition(AiRecognition {
                        enable: Toggle::On,
                        model: 0,
                        classes: self.cfg.ai_classes,
                    });
                    self.send_tracked(now, ai, out);
                }
                let request = camera_request(other, &self.state)?;
                let base = request.base();
                if !self.allow.allows(base) {
                    // One of the pod's destructive requests, not allowed (see
                    // docs/src/security.md).
                    out.refuse(
                        now,
                        crate::Port::Fc,
                        crate::access::Refusal::Guarded,
                        u32::from(base),
                        (0, 0),
                    );
                    return None;
                }
                if let Command::Laser(r) = other {
                    self.state.ranging = r == Ranging::Continuous;
                }
                self.send_tracked(now, request, out);
                Some(base)
            }
        }
    }
}

/// The K40T request for a camera command (`None`: no equivalent).
#[allow(clippy::too_many_lines)] // one short arm per command
fn camera_request(cmd: Command, state: &PodState) -> Option<Request> {
    let empty = Text::default();
    Some(match cmd {
        Command::TakePhoto => Request::TakePhoto(TakePhoto {
            sensors: PhotoSensors::Default,
            action: ShootAction::Start,
            folder: empty,
            name: Text::default(),
        }),
        Command::Record(start) => Request::Record(Record {
            sensors: RecordSensors::Default,
            action: if start {
                RecordAction::Start
            } else {
                RecordAction::Stop
            },
            folder: empty,
            name: Text::default(),
        }),
        Command::VideoMode(video) => Request::CaptureMode(k40t::CaptureModeSetting {
            mode: if video {
                k40t::CaptureMode::Video
            } else {
                k40t::CaptureMode::Photo
            },
            reserved: 0,
        }),
        Command::Zoom(m) => Request::ContinuousZoom(ContinuousZoom {
            control: match m {
                Motion::In => ZoomControl::In,
                Motion::Out => ZoomControl::Out,
                Motion::Stop => ZoomControl::Stop,
            },
            reserved: 0,
        }),
        Command::ZoomTo { zoom_x10 } => Request::HybridZoom(HybridZoom {
            start: 0,
            zoom_x10: zoom_x10.clamp(10, 1600),
        }),
        Command::ThermalZoom { ratio } => Request::IrDigitalZoom(IrDigitalZoom {
            zoom_x: ratio.clamp(1, 8),
            reserved: 0,
        }),
        Command::Focus(m) => Request::Focus(Focus {
            mode: match m {
                Motion::In => FocusMode::ManualPlus,
                Motion::Out => FocusMode::ManualMinus,
                Motion::Stop => FocusMode::ManualStop,
            },
            ..Focus::default()
        }),
        Command::AutoFocus(target) => {
            let (mode, (x0, y0, x1, y1)) = match target {
                None => (FocusMode::Auto, (0, 0, 0, 0)),
                Some(t) => (FocusMode::Area, target_box(t)),
            };
            Request::Focus(Focus {
                mode,
                x0,
                y0,
                x1,
                y1,
                reserved: 0,
            })
        }
        Command::ManualFocus(on) => Request::Focus(Focus {
            mode: if on {
                FocusMode::ManualStop
            } else {
                FocusMode::Auto
            },
            ..Focus::default()
        }),
        Command::View(v) => Request::ImageMode(ImageModeSetting {
            mode: match v {
                View::Visible => ImageMode::Visible,
                View::Thermal => ImageMode::Infrared,
                View::Split => ImageMode::Split,
            },
            reserved: 0,
        }),
        Command::Palette(palette) => Request::IrPalette(IrPalette {
            palette,
            reserved: 0,
        }),
        Command::ThermalHighGain(high) => Request::IrGainMode(IrGainMode {
            gain: if high { IrGain::High } else { IrGain::Low },
            reserved: 0,
        }),
        Command::Laser(Ranging::Single) => Request::LaserRange(LaserRange {
            mode: LaserMode::Single,
            reserved: 0,
        }),
        Command::Laser(r) => Request::LaserPeriodic(LaserPeriodic {
            enable: if r == Ranging::Continuous {
                OnOff::On
            } else {
                OnOff::Off
            },
            reserved: 0,
        }),
        Command::Track(target) => {
            let (x0, y0, x1, y1) = target.map_or((0, 0, 0, 0), target_box);
            Request::TrackBox(TrackBox {
                enable: if target.is_some() {
                    Toggle::On
                } else {
                    Toggle::Off
                },
                x: x0,
                y: y0,
                width: x1.saturating_sub(x0),
                height: y1.saturating_sub(y0),
                reserved: 0,
            })
        }
        Command::Aim(t) => {
            let (x0, y0, x1, y1) = target_box(t);
            Request::PointToAim(PointToAim {
                lens: if state.view() == Some(View::Thermal) {
                    Lens::Infrared
                } else {
                    Lens::Telephoto
                },
                zoom_x10: state.zoom_x10(),
                x: x0.saturating_add(x1.saturating_sub(x0) / 2).clamp(1, 1920),
                y: y0.saturating_add(y1.saturating_sub(y0) / 2).clamp(1, 1080),
            })
        }
        Command::Rates { .. }
        | Command::Angles { .. }
        | Command::Center
        | Command::LookDown
        | Command::Mode(_) => return None,
    })
}

/// Half the side of the box drawn around a point target (pixels).
const POINT_BOX_HALF: u16 = 64;

/// A target as a box inside the 1920 x 1080 picture (a point becomes a small box).
fn target_box(t: Target) -> (u16, u16, u16, u16) {
    let (x0, y0, x1, y1) = match t {
        Target::Point { x, y } => (
            x.saturating_sub(POINT_BOX_HALF),
            y.saturating_sub(POINT_BOX_HALF),
            x.saturating_add(POINT_BOX_HALF),
            y.saturating_add(POINT_BOX_HALF),
        ),
        Target::Box { x0, y0, x1, y1 } => (x0.min(x1), y0.min(y1), x0.max(x1), y0.max(y1)),
    };
    (x0.min(1920), y0.min(1080), x1.min(1920), y1.min(1080))
}
