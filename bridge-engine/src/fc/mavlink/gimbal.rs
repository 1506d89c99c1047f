//! The gimbal device (component 154).
//!
//! **GIMBAL_DEVICE_SET_ATTITUDE** (addressed to this device's system and component 154, or
//! 0): the yaw frame follows the message's rules: YAW_IN_EARTH_FRAME (64) or
//! YAW_IN_VEHICLE_FRAME (32) when set, else YAW_LOCK (16) means earth frame (ArduPilot:
//! 28 = roll, pitch and yaw lock for a yaw from north, 0 for a vehicle-relative one; PX4:
//! YAW_LOCK per axis set "absolute"). Then, in this order:
//! - RETRACT (1): the pod looks down (it has no stowed position; looking down keeps the
//!   lens out of the way); NEUTRAL (2): the pod centres.
//! - A quaternion with every component finite: an angle. Roll is not commanded (the pod
//!   stabilises it); pitch is against the horizon (the pod's pitch always is); yaw is
//!   relative to the vehicle, an earth-frame yaw minus the aircraft's heading (from
//!   AUTOPILOT_STATE_FOR_GIMBAL_DEVICE or ATTITUDE, at most 1 s old: without it an
//!   earth-frame angle is not acted on). Straight up or down (|pitch| within 0.1° of
//!   90°) the yaw is taken as `2·atan2(z, w)`.
//! - Else angular velocities (NaN components as 0): rates, an earth-frame yaw rate less
//!   the aircraft's own yaw rate. ArduPilot's rate form (quaternion NaN) and PX4's
//!   (quaternion of the integrated angle, with the velocity as feed-forward) both work.
//! - Else (everything NaN): nothing.
//!
//! **GIMBAL_DEVICE_ATTITUDE_STATUS**, broadcast (target 0/0) at 10 Hz: the pod's attitude
//! as ArduPilot reads it whatever the flags say (roll and pitch against the horizon, yaw
//! relative to the vehicle), flagged ROLL_LOCK | PITCH_LOCK | YAW_IN_VEHICLE_FRAME (plus
//! YAW_LOCK while the autopilot holds an earth-frame yaw, ACCEPTS_YAW_IN_EARTH_FRAME
//! while the aircraft's heading is known), as QGroundControl reads the frame from them.
//! `delta_yaw` is the aircraft's heading and `delta_yaw_velocity` its yaw rate when known,
//! else 0 (ArduPilot uses both once either is non-zero; NaN would count as non-zero).
//! Pitch is shown at most 89.95° from the horizon: straight down a quaternion holds yaw
//! and roll as one rotation, which ArduPilot reads as yaw 0.
//! While the pod does not report its attitude: the last attitude (or none) with
//! COMMS_ERROR, one of the failure flags that make ArduPilot call the mount unhealthy.
//! AT_PITCH_LIMIT and AT_YAW_LIMIT are set at the pod's limits.
//!
//! **GIMBAL_DEVICE_INFORMATION** on request, once the pod is known: limits from the K40T
//! document (0x000012: pitch 30° up, 90° down; yaw 180° either way; roll not commanded:
//! 0..0), finite as older ArduPilot needs; firmware and hardware versions from the pod's
//! 0x000018 (byte 0 major, 1 minor, 2 patch, as the spec and ArduPilot read them).

use crate::fc::Ctx;
use crate::gimbal::Command;
use crate::time::Duration;
use protocol_core::mavlink::dialect::{
    GIMBAL_DEVICE_ATTITUDE_STATUS_DATA, GIMBAL_DEVICE_INFORMATION_DATA,
    GIMBAL_DEVICE_SET_ATTITUDE_DATA, GimbalDeviceCapFlags, GimbalDeviceCapFlagsU16,
    GimbalDeviceErrorFlags, GimbalDeviceFlags,
};
use protocol_core::mavlink::{MavMessage, dialect::CharArray};

use super::{Cmd, Comp, MavlinkSide, math, result};

/// GIMBAL_DEVICE_ATTITUDE_STATUS period (10 Hz).
pub(super) const STATUS_PERIOD: Duration = Duration::from_millis(100);

/// The pod's limits, 0.01° (K40T 0x000012: up 30°, down 90°, yaw ±180°).
const PITCH_MIN: i32 = -9_000;
const PITCH_MAX: i32 = 3_000;
const YAW_LIMIT: i32 = 18_000;
/// Within this of a limit, the status says the gimbal is at it (0.01°).
const AT_LIMIT: i32 = 50;
/// The largest pitch the status shows (0.01°): straight down or up a quaternion holds
/// yaw and roll as one rotation, and a reader (ArduPilot's `to_euler`) gets yaw 0; at
/// 89.95° the yaw stays readable to 0.02° in an f32 quaternion.
pub(super) const PITCH_SHOWN: i32 = 8_995;

/// Vendor and model names in GIMBAL_DEVICE_INFORMATION and CAMERA_INFORMATION.
pub(super) const VENDOR: &[u8] = b"K40T";
pub(super) const MODEL: &[u8] = b"K40T four-sensor pod";

/// The gimbal's state as the autopilot set it.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Gimbal {
    /// The last attitude command held an earth-frame yaw.
    earth: bool,
}

/// A name in a fixed-size, zero-padded field.
pub(super) fn name<const N: usize>(text: &[u8]) -> [u8; N] {
    let mut out = [0u8; N];
    for (d, s) in out.iter_mut().zip(text) {
        *d = *s;
    }
    out
}

/// A version as MAVLink packs it: byte 0 major, 1 minor, 2 patch.
pub(super) fn version(v: Option<protocol_core::k40t::Version>) -> u32 {
    v.map_or(0, |v| u32::from_le_bytes([v.major, v.minor, v.patch, 0]))
}

impl MavlinkSide {
    /// GIMBAL_DEVICE_SET_ATTITUDE (see the module documentation).
    pub(super) fn set_attitude(&mut self, ctx: &mut Ctx<'_>, s: &GIMBAL_DEVICE_SET_ATTITUDE_DATA) {
        const ID: u16 = 284;
        if !self.addressed(s.target_system, s.target_component, Comp::Gimbal) {
            ctx.ignored();
            return;
        }
        let f = s.flags;
        let moves = f.intersects(
            GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_RETRACT
                | GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_NEUTRAL,
        ) || s.q.iter().all(|c| c.is_finite())
            || [s.angular_velocity_y, s.angular_velocity_z]
                .iter()
                .any(|r| r.is_finite());
        if moves {
            // The autopilot points the gimbal itself: a location it pointed at ends.
            self.roi.target = None;
        }
        if f.contains(GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_RETRACT) {
            ctx.command(ID, Command::LookDown);
            return;
        }
        if f.contains(GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_NEUTRAL) {
            ctx.command(ID, Command::Center);
            return;
        }
        let earth = if f.contains(GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_YAW_IN_EARTH_FRAME) {
            true
        } else if f.contains(GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_YAW_IN_VEHICLE_FRAME) {
            false
        } else {
            f.contains(GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_YAW_LOCK)
        };
        self.gimbal.earth = earth;
        let vehicle = self.vehicle(ctx.now);
        if let Some([pitch, yaw]) = angles(s.q) {
            let yaw = if earth {
                let Some(v) = vehicle else {
                    // An earth-frame yaw needs the aircraft's heading.
                    ctx.ignored();
                    return;
                };
                math::wrap_cdeg(yaw.saturating_sub(v.yaw))
            } else {
                yaw
            };
            ctx.command(
                ID,
                Command::Angles {
                    yaw_cdeg: yaw,
                    pitch_cdeg: pitch,
                },
            );
            return;
        }
        let rates = [s.angular_velocity_y, s.angular_velocity_z];
        if rates.iter().all(|r| !r.is_finite()) {
            ctx.ignored();
            return;
        }
        let [pitch_rate, yaw_rate] = rates.map(|r| math::cdeg(r).unwrap_or(0));
        let own = if earth {
            vehicle.and_then(|v| v.yaw_rate).unwrap_or(0)
        } else {
            0
        };
        ctx.command(
            ID,
            Command::Rates {
                yaw_cdeg_s: yaw_rate.saturating_sub(own),
                pitch_cdeg_s: pitch_rate,
            },
        );
    }

    /// Sends GIMBAL_DEVICE_ATTITUDE_STATUS (see the module documentation).
    pub(super) fn attitude_status(&mut self, ctx: &mut Ctx<'_>) {
        let fresh = ctx.fresh_attitude();
        let a = fresh.or_else(|| ctx.pod().attitude.map(|(a, _)| a));
        let mut failure = GimbalDeviceErrorFlags::empty();
        if fresh.is_none() {
            failure |= GimbalDeviceErrorFlags::GIMBAL_DEVICE_ERROR_FLAGS_COMMS_ERROR;
        }
        let (q, rates) = match a {
            Some(a) => {
                let pitch = i32::from(a.pitch_cdeg);
                let yaw = i32::from(a.yaw_joint_cdeg);
                if pitch <= PITCH_MIN.saturating_add(AT_LIMIT)
                    || pitch >= PITCH_MAX.saturating_sub(AT_LIMIT)
                {
                    failure |= GimbalDeviceErrorFlags::GIMBAL_DEVICE_ERROR_FLAGS_AT_PITCH_LIMIT;
                }
                if yaw.saturating_abs() >= YAW_LIMIT.saturating_sub(AT_LIMIT) {
                    failure |= GimbalDeviceErrorFlags::GIMBAL_DEVICE_ERROR_FLAGS_AT_YAW_LIMIT;
                }
                let r = |v: i16| math::rad(i32::from(v));
                (
                    math::quaternion([
                        r(a.roll_cdeg),
                        math::rad(pitch.clamp(-PITCH_SHOWN, PITCH_SHOWN)),
                        r(a.yaw_joint_cdeg),
                    ]),
                    [
                        r(a.roll_rate_cdeg_s),
                        r(a.pitch_rate_cdeg_s),
                        r(a.yaw_rate_cdeg_s),
                    ],
                )
            }
            None => ([1.0, 0.0, 0.0, 0.0], [0.0; 3]),
        };
        let mut flags = GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_ROLL_LOCK
            | GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_PITCH_LOCK
            | GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_YAW_IN_VEHICLE_FRAME;
        if self.gimbal.earth {
            flags |= GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_YAW_LOCK;
        }
        let vehicle = self.vehicle(ctx.now);
        if vehicle.is_some() {
            flags |= GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_ACCEPTS_YAW_IN_EARTH_FRAME;
        }
        let [roll_rate, pitch_rate, yaw_rate] = rates;
        let status =
            MavMessage::GIMBAL_DEVICE_ATTITUDE_STATUS(GIMBAL_DEVICE_ATTITUDE_STATUS_DATA {
                time_boot_ms: boot_ms(ctx),
                q,
                angular_velocity_x: roll_rate,
                angular_velocity_y: pitch_rate,
                angular_velocity_z: yaw_rate,
                failure_flags: failure,
                flags,
                target_system: 0,
                target_component: 0,
                delta_yaw: vehicle.map_or(0.0, |v| math::rad(v.yaw)),
                delta_yaw_velocity: vehicle.and_then(|v| v.yaw_rate).map_or(0.0, math::rad),
                gimbal_device_id: 0,
            });
        self.send(ctx, Comp::Gimbal, &status);
    }

    /// MAV_CMD_REQUEST_MESSAGE(GIMBAL_DEVICE_INFORMATION): ACK and the information once
    /// the pod is known, else TEMPORARILY_REJECTED (the autopilots ask again every second).
    pub(super) fn serve_device_information(&mut self, ctx: &mut Ctx<'_>, c: &Cmd) {
        let versions = ctx.pod().gimbal_version;
        if !self.pod_identified(ctx, versions.is_some()) {
            self.ack(
                ctx,
                Comp::Gimbal,
                c.command,
                result::TEMPORARILY_REJECTED,
                c.from,
            );
            return;
        }
        self.ack(ctx, Comp::Gimbal, c.command, result::ACCEPTED, c.from);
        let cap = GimbalDeviceCapFlags::GIMBAL_DEVICE_CAP_FLAGS_HAS_RETRACT
            | GimbalDeviceCapFlags::GIMBAL_DEVICE_CAP_FLAGS_HAS_NEUTRAL
            | GimbalDeviceCapFlags::GIMBAL_DEVICE_CAP_FLAGS_HAS_ROLL_LOCK
            | GimbalDeviceCapFlags::GIMBAL_DEVICE_CAP_FLAGS_HAS_PITCH_AXIS
            | GimbalDeviceCapFlags::GIMBAL_DEVICE_CAP_FLAGS_HAS_PITCH_LOCK
            | GimbalDeviceCapFlags::GIMBAL_DEVICE_CAP_FLAGS_HAS_YAW_AXIS
            | GimbalDeviceCapFlags::GIMBAL_DEVICE_CAP_FLAGS_HAS_YAW_FOLLOW
            | GimbalDeviceCapFlags::GIMBAL_DEVICE_CAP_FLAGS_HAS_YAW_LOCK
            | GimbalDeviceCapFlags::GIMBAL_DEVICE_CAP_FLAGS_SUPPORTS_YAW_IN_EARTH_FRAME
            // DO_SET_ROI_LOCATION to the device (roi.rs); only in cap_flags2.
            | GimbalDeviceCapFlags::GIMBAL_DEVICE_CAP_FLAGS_CAN_POINT_LOCATION_GLOBAL;
        let info = MavMessage::GIMBAL_DEVICE_INFORMATION(GIMBAL_DEVICE_INFORMATION_DATA {
            uid: 0,
            time_boot_ms: boot_ms(ctx),
            // The bridge's version; the hardware is the pod's gimbal's.
            firmware_version: ctx.build.version.mavlink(),
            hardware_version: version(versions.map(|v| v.hardware)),
            roll_min: 0.0,
            roll_max: 0.0,
            pitch_min: math::rad(PITCH_MIN),
            pitch_max: math::rad(PITCH_MAX),
            yaw_min: math::rad(-YAW_LIMIT),
            yaw_max: math::rad(YAW_LIMIT),
            cap_flags: GimbalDeviceCapFlagsU16::from_bits_truncate(
                u16::try_from(cap.bits() & 0xFFFF).unwrap_or(0),
            ),
            custom_cap_flags: 0,
            vendor_name: CharArray::from(name::<32>(VENDOR)),
            model_name: CharArray::from(name::<32>(MODEL)),
            custom_name: CharArray::from([0u8; 32]),
            gimbal_device_id: 0,
            cap_flags2: cap,
        });
        self.send(ctx, Comp::Gimbal, &info);
    }
}

/// Pitch and vehicle-or-earth yaw (0.01°) of an attitude quaternion; `None` when it is
/// not a quaternion (NaN: the rate form).
fn angles(q: [f32; 4]) -> Option<[i32; 2]> {
    let [_, pitch, yaw] = math::euler(q)?;
    let pitch = math::cdeg(pitch)?;
    let yaw = if pitch.saturating_abs() >= 8_990 {
        // Looking straight up or down: yaw and roll are one rotation; roll is ~0.
        let [w, _, _, z] = q;
        math::cdeg(2.0 * math::atan2(z, w))?
    } else {
        math::cdeg(yaw)?
    };
    Some([pitch, math::wrap_cdeg(yaw)])
}

/// The bridge's clock in ms, as `time_boot_ms` (wrapping).
pub(super) fn boot_ms(ctx: &Ctx<'_>) -> u32 {
    u32::try_from(ctx.now.as_millis() % (1u64 << 32)).unwrap_or(0)
}
