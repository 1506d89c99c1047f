//! Pointing at a location (component 154): MAV_CMD_DO_SET_ROI_LOCATION and
//! MAV_CMD_DO_SET_ROI_NONE as the newest ArduPilot sends them to a MAVLink gimbal device
//! (COMMAND_INT to the gimbal, frame GLOBAL, latitude and longitude in 1e-7 degree,
//! altitude in metres above mean sea level; re-sent while the target holds; ROI_NONE when
//! it ends). The device advertises it with GIMBAL_DEVICE_CAP_FLAGS_CAN_POINT_LOCATION_GLOBAL
//! (docs/src/bridge/mavlink.md, "Pointing at a location").
//!
//! - **Frames.** GLOBAL and GLOBAL_INT: the altitude is above mean sea level;
//!   GLOBAL_RELATIVE_ALT and _INT: above home (the fix's MSL less its relative
//!   altitude). Any other frame is DENIED. A COMMAND_LONG carries latitude and longitude
//!   in degrees in param5 and param6 and the MSL altitude in param7.
//! - **Angles.** From the aircraft's latest fix and heading to the location, in a
//!   flat-earth frame ([`super::geo`]): the earth-frame bearing less the heading is the
//!   pod's yaw, the elevation its pitch (0x000012, through the pod driver's dead-band).
//!   Refreshed ten times a second as the aircraft moves.
//! - **ACK** from 154: ACCEPTED when the aircraft's position and heading are known (the
//!   pod then turns), TEMPORARILY_REJECTED (nothing stored) when not; DENIED for a frame
//!   it does not take or a location out of range. ROI_NONE: ACCEPTED, the gimbal holds
//!   where it is. A GIMBAL_DEVICE_SET_ATTITUDE that moves the gimbal, or tracking, ends
//!   the pointing.

use crate::event::{Decline, Event};
use crate::fc::Ctx;
use crate::gimbal::Command;
use crate::time::Duration;

use super::geo::{self, Position};
use super::{Cmd, Comp, MavlinkSide, cmd, math, result};

/// A fix older than this does not point the gimbal.
const FIX_FRESH: Duration = Duration::from_secs(2);

/// MAV_FRAME values DO_SET_ROI_LOCATION takes.
mod frame {
    pub(super) const GLOBAL: u8 = 0;
    pub(super) const GLOBAL_RELATIVE_ALT: u8 = 3;
    pub(super) const GLOBAL_INT: u8 = 5;
    pub(super) const GLOBAL_RELATIVE_ALT_INT: u8 = 6;
}

/// The location the gimbal points at.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Roi {
    pub(super) target: Option<Position>,
}

impl MavlinkSide {
    /// The aircraft's position (its latest fix, when fresh).
    pub(super) fn aircraft(ctx: &Ctx<'_>) -> Option<(Position, i32)> {
        let f = ctx
            .fixes
            .latest()
            .filter(|f| ctx.now.saturating_duration_since(f.at) <= FIX_FRESH)?;
        let p = Position {
            lat_e7: f.lat_e7,
            lon_e7: f.lon_e7,
            alt_mm: i32::from(f.alt_msl_dm).saturating_mul(100),
        };
        Some((p, i32::from(f.rel_alt_dm).saturating_mul(100)))
    }

    /// MAV_CMD_DO_SET_ROI_LOCATION, MAV_CMD_DO_SET_ROI_NONE (see the module documentation).
    #[allow(clippy::cast_possible_truncation)] // degrees and metres, checked ranges
    pub(super) fn roi_command(&mut self, ctx: &mut Ctx<'_>, c: &Cmd) {
        if c.command == cmd::DO_SET_ROI_NONE {
            self.roi.target = None;
            self.ack(ctx, Comp::Gimbal, c.command, result::ACCEPTED, c.from);
            return;
        }
        let alt_m = c.param(7);
        let e7 = |deg: f32| (deg * 1.0e7) as i32;
        let (lat_e7, lon_e7, frame) =
            c.int
                .unwrap_or((e7(c.param(5)), e7(c.param(6)), frame::GLOBAL));
        let relative = match frame {
            frame::GLOBAL | frame::GLOBAL_INT => false,
            frame::GLOBAL_RELATIVE_ALT | frame::GLOBAL_RELATIVE_ALT_INT => true,
            _ => {
                self.refused(ctx, c.command, Decline::Frame);
                self.ack(ctx, Comp::Gimbal, c.command, result::DENIED, c.from);
                return;
            }
        };
        let valid = alt_m.is_finite()
            && lat_e7.unsigned_abs() <= 900_000_000
            && lon_e7.unsigned_abs() <= 1_800_000_000
            && alt_m > -100_000.0
            && alt_m < 100_000.0;
        if !valid {
            self.refused(ctx, c.command, Decline::OutOfRange);
            self.ack(ctx, Comp::Gimbal, c.command, result::DENIED, c.from);
            return;
        }
        let Some((here, rel_mm)) = Self::aircraft(ctx).filter(|_| self.vehicle(ctx.now).is_some())
        else {
            self.refused(ctx, c.command, Decline::NoPosition);
            self.ack(
                ctx,
                Comp::Gimbal,
                c.command,
                result::TEMPORARILY_REJECTED,
                c.from,
            );
            return;
        };
        let mut alt_mm = (alt_m * 1000.0) as i32;
        if relative {
            // Home's MSL altitude: the fix's less its height above home.
            alt_mm = alt_mm.saturating_add(here.alt_mm.saturating_sub(rel_mm));
        }
        self.roi.target = Some(Position {
            lat_e7,
            lon_e7,
            alt_mm,
        });
        self.ack(ctx, Comp::Gimbal, c.command, result::ACCEPTED, c.from);
        self.roi_refresh(ctx);
        ctx.out.event(Event::Translated {
            fc_id: c.command,
            pod_base: 0x0012,
        });
    }

    /// Turns the pod towards the location from where the aircraft is now.
    pub(super) fn roi_refresh(&mut self, ctx: &mut Ctx<'_>) {
        let Some(target) = self.roi.target else {
            return;
        };
        let (Some((here, _)), Some(v)) = (Self::aircraft(ctx), self.vehicle(ctx.now)) else {
            return;
        };
        let (bearing, elevation) = geo::bearing_elevation(geo::local(here, target));
        let (Some(bearing), Some(pitch)) = (math::cdeg(bearing), math::cdeg(elevation)) else {
            return;
        };
        // Through the pod driver's dead-band; one event per command, not per refresh.
        let angles = Command::Angles {
            yaw_cdeg: math::wrap_cdeg(bearing.saturating_sub(v.yaw)),
            pitch_cdeg: pitch,
        };
        ctx.pod.command(ctx.now, angles, ctx.out);
    }
}
