//! Tracking (component 100): MAV_CMD_CAMERA_TRACK_POINT, _TRACK_RECTANGLE and
//! _STOP_TRACKING as the pod's box tracking, and CAMERA_TRACKING_IMAGE_STATUS from what
//! the pod reports (docs/src/bridge/mavlink.md, "Tracking").
//!
//! - **The box.** MAVLink's image coordinates are normalised, 0..1 from the top left; the
//!   pod's box (0x000324) is in pixels of a 1920 × 1080 picture: x = round(x·1920),
//!   y = round(y·1080), each clamped into the frame. A rectangle's corners (in either
//!   order) give the box; a point with a radius r (a fraction of the image width, the
//!   spec's "1 is full image width") gives the square of half side round(r·1920) around
//!   it, cut at the frame's edges; radius 0, "one pixel", gives a box of one pixel (the
//!   document names no smallest box). A parameter that is NaN (not given) is DENIED.
//! - **The pod's preconditions** (K40T external protocol, 3.2.4.25): AI recognition must
//!   be on, so the pod driver switches it on (0x000319) first; the box must lie in or
//!   overlap the recognition area, which the pod does not report: a box it refuses is
//!   FAILED and the status says ERROR; while it tracks, the bridge switches tracking off
//!   before it moves the gimbal for the autopilot.
//! - **ACK** after the pod's ACK of 0x000324: ACCEPTED, or FAILED.
//! - **CAMERA_TRACKING_IMAGE_STATUS.** The pod reports nothing of its tracking but its ACK,
//!   so the status is: ACTIVE with the point or rectangle asked (target data "in status")
//!   from an ACK OK; IDLE after STOP_TRACKING, a gimbal command that ended tracking, or
//!   the pod's link lost; ERROR after a refusal. Sent when it changes and at the interval
//!   SET_MESSAGE_INTERVAL(275) asks (QGroundControl: 500 ms while it tracks, −1 after;
//!   0: every second).

use crate::event::Decline;
use crate::fc::Ctx;
use crate::gimbal::{Command, Target};
use crate::time::{Duration, Instant};
use protocol_core::mavlink::MavMessage;
use protocol_core::mavlink::dialect::{
    CAMERA_TRACKING_IMAGE_STATUS_DATA, CameraTrackingMode, CameraTrackingStatusFlags,
    CameraTrackingTargetData,
};

use super::intervals::Every;
use super::{Cmd, Comp, MavlinkSide, cmd, param_is, result};

/// The pod's picture for box tracking, pixels (K40T external protocol, 3.2.4.25).
const WIDTH: u16 = 1920;
const HEIGHT: u16 = 1080;
/// K40T box tracking.
pub(super) const TRACK_BOX: u16 = 0x0324;
/// The status's default interval (SET_MESSAGE_INTERVAL param2 0) and the shortest.
const DEFAULT_INTERVAL: Duration = Duration::from_secs(1);
const LEAST_INTERVAL: Duration = Duration::from_millis(100);

/// What a client asked to track, normalised.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Asked {
    Point { x: f32, y: f32, radius: f32 },
    Rectangle { x0: f32, y0: f32, x1: f32, y1: f32 },
}

/// What the status says.
#[derive(Debug, Clone, Copy, PartialEq)]
enum State {
    Idle,
    Active(Asked),
    Error(Asked),
}

/// A command waiting for the pod's ACK of 0x000324.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Pending {
    Start(Asked),
    Stop,
}

/// Tracking on the MAVLink side.
#[derive(Debug, Clone, Copy)]
pub(super) struct Tracking {
    pending: Option<Pending>,
    state: State,
    /// The state the last status said.
    told: Option<State>,
    pub(super) every: Every,
}

impl Default for Tracking {
    fn default() -> Self {
        Tracking {
            pending: None,
            state: State::Idle,
            told: None,
            every: Every::OFF,
        }
    }
}

/// A normalised coordinate in pixels of a side of `len` pixels, rounded, in the frame.
#[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // clamped first
fn pixel(v: f32, len: u16) -> u16 {
    (v.clamp(0.0, 1.0) * f32::from(len) + 0.5) as u16
}

/// The pod's box (left, top, right, bottom) of a point with a radius.
fn point_box(x: f32, y: f32, radius: f32) -> Target {
    let half = pixel(radius, WIDTH);
    let (cx, cy) = (pixel(x, WIDTH), pixel(y, HEIGHT));
    if half == 0 {
        let (x0, y0) = (
            cx.min(WIDTH.saturating_sub(1)),
            cy.min(HEIGHT.saturating_sub(1)),
        );
        return Target::Box {
            x0,
            y0,
            x1: x0.saturating_add(1),
            y1: y0.saturating_add(1),
        };
    }
    Target::Box {
        x0: cx.saturating_sub(half),
        y0: cy.saturating_sub(half),
        x1: cx.saturating_add(half).min(WIDTH),
        y1: cy.saturating_add(half).min(HEIGHT),
    }
}

/// The pod's box of a rectangle (corners in either order; at least one pixel).
fn rectangle_box(x0: f32, y0: f32, x1: f32, y1: f32) -> Target {
    let (a, b) = (pixel(x0, WIDTH), pixel(x1, WIDTH));
    let (c, d) = (pixel(y0, HEIGHT), pixel(y1, HEIGHT));
    let (left, top) = (
        a.min(b).min(WIDTH.saturating_sub(1)),
        c.min(d).min(HEIGHT.saturating_sub(1)),
    );
    Target::Box {
        x0: left,
        y0: top,
        x1: a.max(b).max(left.saturating_add(1)),
        y1: c.max(d).max(top.saturating_add(1)),
    }
}

/// A target camera parameter: 0 (all), NaN (not given) or this camera's component id.
fn ours(p: f32) -> bool {
    p.is_nan() || param_is(p, 0) || param_is(p, Comp::Camera.id())
}

impl MavlinkSide {
    /// CAMERA_TRACK_POINT, _TRACK_RECTANGLE, _STOP_TRACKING (see the module documentation).
    pub(super) fn tracking_command(&mut self, ctx: &mut Ctx<'_>, c: &Cmd) {
        let (asked, camera) = match c.command {
            cmd::CAMERA_TRACK_POINT => (
                Some(Asked::Point {
                    x: c.param(1),
                    y: c.param(2),
                    radius: c.param(3),
                }),
                c.param(4),
            ),
            cmd::CAMERA_TRACK_RECTANGLE => (
                Some(Asked::Rectangle {
                    x0: c.param(1),
                    y0: c.param(2),
                    x1: c.param(3),
                    y1: c.param(4),
                }),
                c.param(5),
            ),
            _ => (None, c.param(1)),
        };
        if !ours(camera) {
            self.refused(ctx, c.command, Decline::OtherDevice);
            self.ack(ctx, Comp::Camera, c.command, result::DENIED, c.from);
            return;
        }
        let target = match asked {
            Some(Asked::Point { x, y, radius }) => [x, y, radius]
                .iter()
                .all(|v| !v.is_nan())
                .then(|| point_box(x, y, radius)),
            Some(Asked::Rectangle { x0, y0, x1, y1 }) => [x0, y0, x1, y1]
                .iter()
                .all(|v| !v.is_nan())
                .then(|| rectangle_box(x0, y0, x1, y1)),
            None => None,
        };
        if asked.is_some() && target.is_none() {
            self.refused(ctx, c.command, Decline::NotGiven);
            self.ack(ctx, Comp::Camera, c.command, result::DENIED, c.from);
            return;
        }
        if target.is_some() {
            // Tracking moves the gimbal: a location the gimbal pointed at is given up.
            self.roi.target = None;
        }
        let base = ctx.command(c.command, Command::Track(target));
        self.tracking.pending = match asked {
            Some(a) => Some(Pending::Start(a)),
            None => Some(Pending::Stop),
        };
        self.await_pod(ctx, c, base);
    }

    /// The pod answered (or never did) its 0x000324.
    pub(super) fn tracking_pod_answer(&mut self, ctx: &mut Ctx<'_>, ok: bool) {
        match self.tracking.pending.take() {
            Some(Pending::Start(a)) => {
                self.tracking.state = if ok {
                    State::Active(a)
                } else {
                    State::Error(a)
                };
            }
            Some(Pending::Stop) if ok => self.tracking.state = State::Idle,
            _ => {}
        }
        self.tracking_changed(ctx);
    }

    /// Tracking ended without a STOP_TRACKING (a gimbal command, a lost link): IDLE.
    pub(super) fn tracking_check(&mut self, ctx: &mut Ctx<'_>) {
        if matches!(self.tracking.state, State::Active(_))
            && self.tracking.pending.is_none()
            && (ctx.pod().track.is_none() || !ctx.pod().link)
        {
            self.tracking.state = State::Idle;
        }
        self.tracking_changed(ctx);
    }

    fn tracking_changed(&mut self, ctx: &mut Ctx<'_>) {
        if self.tracking.told.is_some_and(|t| t != self.tracking.state)
            || (self.tracking.told.is_none() && self.tracking.state != State::Idle)
        {
            self.tracking_status(ctx);
        }
    }

    /// Sends the status at its interval.
    pub(super) fn tracking_poll(&mut self, ctx: &mut Ctx<'_>) {
        if self.tracking.every.due(ctx.now) {
            self.tracking_status(ctx);
        }
    }

    /// Applies SET_MESSAGE_INTERVAL(275); false for a value that is not a number.
    pub(super) fn tracking_interval(&mut self, now: Instant, us: f32) -> bool {
        self.tracking
            .every
            .set(now, us, DEFAULT_INTERVAL, LEAST_INTERVAL)
    }

    /// CAMERA_TRACKING_IMAGE_STATUS (see the module documentation).
    pub(super) fn tracking_status(&mut self, ctx: &mut Ctx<'_>) {
        let state = self.tracking.state;
        self.tracking.told = Some(state);
        let nan = f32::NAN;
        let (status, asked) = match state {
            State::Idle => (
                CameraTrackingStatusFlags::CAMERA_TRACKING_STATUS_FLAGS_IDLE,
                None,
            ),
            State::Active(a) => (
                CameraTrackingStatusFlags::CAMERA_TRACKING_STATUS_FLAGS_ACTIVE,
                Some(a),
            ),
            State::Error(a) => (
                CameraTrackingStatusFlags::CAMERA_TRACKING_STATUS_FLAGS_ERROR,
                Some(a),
            ),
        };
        let (mode, point, rect) = match asked {
            Some(Asked::Point { x, y, radius }) => (
                CameraTrackingMode::CAMERA_TRACKING_MODE_POINT,
                [x, y, radius],
                [nan; 4],
            ),
            Some(Asked::Rectangle { x0, y0, x1, y1 }) => (
                CameraTrackingMode::CAMERA_TRACKING_MODE_RECTANGLE,
                [nan; 3],
                [x0, y0, x1, y1],
            ),
            None => (
                CameraTrackingMode::CAMERA_TRACKING_MODE_NONE,
                [nan; 3],
                [nan; 4],
            ),
        };
        let [point_x, point_y, radius] = point;
        let [rec_top_x, rec_top_y, rec_bottom_x, rec_bottom_y] = rect;
        let msg = MavMessage::CAMERA_TRACKING_IMAGE_STATUS(CAMERA_TRACKING_IMAGE_STATUS_DATA {
            point_x,
            point_y,
            radius,
            rec_top_x,
            rec_top_y,
            rec_bottom_x,
            rec_bottom_y,
            tracking_status: status,
            tracking_mode: mode,
            target_data: if asked.is_some() {
                CameraTrackingTargetData::CAMERA_TRACKING_TARGET_DATA_IN_STATUS
            } else {
                CameraTrackingTargetData::empty()
            },
            camera_device_id: 0,
        });
        self.send(ctx, Comp::Camera, &msg);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn b(t: Target) -> (u16, u16, u16, u16) {
        match t {
            Target::Box { x0, y0, x1, y1 } => (x0, y0, x1, y1),
            Target::Point { .. } => panic!("not a box"),
        }
    }

    #[test]
    fn normalised_coordinates_become_the_pods_pixels() {
        assert_eq!(
            b(rectangle_box(0.25, 0.25, 0.75, 0.75)),
            (480, 270, 1440, 810)
        );
        // Corners in either order; clamped into the frame.
        assert_eq!(b(rectangle_box(1.2, 1.0, -0.5, 0.5)), (0, 540, 1920, 1080));
        // A point with a radius of a tenth of the width: a 384 px square.
        assert_eq!(b(point_box(0.5, 0.5, 0.1)), (768, 348, 1152, 732));
        // Cut at the frame.
        assert_eq!(b(point_box(0.02, 0.99, 0.05)), (0, 973, 134, 1080));
        // Radius 0: one pixel, inside the frame even at the far edge.
        assert_eq!(b(point_box(0.5, 0.5, 0.0)), (960, 540, 961, 541));
        assert_eq!(b(point_box(1.0, 1.0, 0.0)), (1919, 1079, 1920, 1080));
        // A rectangle of no size: one pixel.
        assert_eq!(b(rectangle_box(0.5, 0.5, 0.5, 0.5)), (960, 540, 961, 541));
        assert!(ours(f32::NAN) && ours(0.0) && ours(100.0) && !ours(101.0));
    }
}
