//! PX4 towards its ground app ([`super::Px4::ground`]): its other MAVLink link (a GCS
//! port in mode Normal, as PX4 SITL's UDP 14550 link), where PX4 is the **gimbal
//! manager** of the MAVLink gimbal device it discovered, as docs/src/autopilots/px4.md
//! and docs/src/autopilots/qgroundcontrol.md describe what PX4 sends and what MAVSDK
//! and QGroundControl read:
//!
//! - HEARTBEAT (QUADROTOR, autopilot PX4) at 1 Hz, ATTITUDE at 5 Hz (MAVSDK's gimbal
//!   plugin turns a vehicle-relative yaw into a yaw from north with it).
//! - **GIMBAL_MANAGER_INFORMATION** on REQUEST_MESSAGE(280) once a gimbal device is
//!   discovered (TEMPORARILY_REJECTED before): `gimbal_device_id` = the device's component
//!   (154), pitch ±90°, yaw ±180° (PX4's fixed limits), the device's capability flags.
//!   **GIMBAL_MANAGER_STATUS** at 5 Hz after discovery: the control owner.
//! - **Inputs**: MAV_CMD_DO_GIMBAL_MANAGER_PITCHYAW (1000: p1 pitch, p2 yaw in degrees,
//!   p3/p4 rates in °/s, NaN unset; p5 flags, YAW_LOCK = yaw from north), the
//!   GIMBAL_MANAGER_SET_ATTITUDE message (282: quaternion, or NaN and rates) and
//!   MAV_CMD_DO_GIMBAL_MANAGER_CONFIGURE (1001: who has control) become the gimbal input
//!   ([`super::Px4Target`]), which the GIMBAL_DEVICE_SET_ATTITUDE stream carries to the
//!   device. Any other command addressed to the autopilot is answered UNSUPPORTED.
//! - **Forwarding** both ways ([`crate::sim::ground`]).

use protocol_core::mavlink::MavMessage;
use protocol_core::mavlink::dialect::{
    GIMBAL_MANAGER_INFORMATION_DATA, GIMBAL_MANAGER_STATUS_DATA, GimbalManagerCapFlags,
    GimbalManagerFlags, MavAutopilot, MavCmd, MavResult, MavType, MessageData as _,
};

use super::{Px4, Px4Target};
use crate::sim::ground::{GroundFrame, GroundLink, Route};
use crate::sim::mav::{self, AircraftState};

/// GIMBAL_MANAGER_SET_ATTITUDE (outside the project's dialect: read from its payload).
const GIMBAL_MANAGER_SET_ATTITUDE: u32 = 282;
/// GIMBAL_MANAGER_FLAGS_YAW_LOCK.
const YAW_LOCK: u32 = 16;
/// GIMBAL_MANAGER_STATUS period.
const STATUS_US: u64 = 200_000;
/// ATTITUDE period on the ground link.
const ATTITUDE_US: u64 = 200_000;

/// What PX4 keeps of its ground link.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Manager {
    /// Who has primary control (system, component).
    primary: (u8, u8),
    last_heartbeat_us: Option<u64>,
    last_status_us: Option<u64>,
    last_attitude_us: Option<u64>,
}

impl Px4 {
    /// One run of the ground link: the ground app's frames, then what is due.
    pub(super) fn ground_run(&mut self, now: u64) {
        let Some(mut g) = self.ground.take() else {
            return;
        };
        for f in g.take() {
            let route = Route::of(&f, self.config.sysid);
            if route.forward && !self.board.is_off() {
                self.board.write_in_order(now, f.bytes.clone());
            }
            if route.local {
                self.ground_message(&mut g, &f);
            }
        }
        self.ground_streams(&mut g, now);
        self.ground = Some(g);
    }

    fn ground_streams(&mut self, g: &mut GroundLink, now: u64) {
        let due = |last: Option<u64>, period: u64| last.is_none_or(|l| now - l >= period);
        if due(self.manager.last_heartbeat_us, 1_000_000) {
            self.manager.last_heartbeat_us = Some(now);
            g.send(&mav::autopilot_heartbeat(
                MavType::MAV_TYPE_QUADROTOR,
                MavAutopilot::MAV_AUTOPILOT_PX4,
            ));
        }
        if due(self.manager.last_attitude_us, ATTITUDE_US) {
            self.manager.last_attitude_us = Some(now);
            let a = AircraftState::of(self.board.aircraft(), now, self.board.fc_us(now));
            g.send(&a.attitude());
        }
        if self.gimbal_compid.is_some() && due(self.manager.last_status_us, STATUS_US) {
            self.manager.last_status_us = Some(now);
            let status = self.manager_status(now);
            g.send(&status);
        }
    }

    fn manager_status(&self, now: u64) -> MavMessage {
        let flags = match self.target {
            Some(Px4Target::Angle {
                yaw_absolute: true, ..
            }) => GimbalManagerFlags::GIMBAL_MANAGER_FLAGS_YAW_LOCK,
            _ => GimbalManagerFlags::empty(),
        } | GimbalManagerFlags::GIMBAL_MANAGER_FLAGS_ROLL_LOCK
            | GimbalManagerFlags::GIMBAL_MANAGER_FLAGS_PITCH_LOCK;
        MavMessage::GIMBAL_MANAGER_STATUS(GIMBAL_MANAGER_STATUS_DATA {
            time_boot_ms: (self.board.fc_us(now) / 1000) as u32,
            flags,
            gimbal_device_id: self.gimbal_compid.unwrap_or(0),
            primary_control_sysid: self.manager.primary.0,
            primary_control_compid: self.manager.primary.1,
            secondary_control_sysid: 0,
            secondary_control_compid: 0,
        })
    }

    fn manager_information(&self, now: u64) -> Option<MavMessage> {
        let device = self.gimbal_compid?;
        let cap = self
            .info
            .as_ref()
            .map_or(0, |i| u32::from(i.cap_flags.bits()));
        Some(MavMessage::GIMBAL_MANAGER_INFORMATION(
            GIMBAL_MANAGER_INFORMATION_DATA {
                time_boot_ms: (self.board.fc_us(now) / 1000) as u32,
                cap_flags: GimbalManagerCapFlags::from_bits_truncate(cap),
                gimbal_device_id: device,
                roll_min: 0.0,
                roll_max: 0.0,
                pitch_min: -90f32.to_radians(),
                pitch_max: 90f32.to_radians(),
                yaw_min: -180f32.to_radians(),
                yaw_max: 180f32.to_radians(),
            },
        ))
    }

    /// A frame of the ground app PX4 handles itself.
    fn ground_message(&mut self, g: &mut GroundLink, f: &GroundFrame) {
        let now = self.board.now_us();
        if f.id == GIMBAL_MANAGER_SET_ATTITUDE {
            self.manager_set_attitude(f);
            return;
        }
        let c = match &f.message {
            Some(MavMessage::COMMAND_LONG(c)) => c.clone(),
            _ => return,
        };
        if c.target_component != mav::AUTOPILOT {
            return;
        }
        let result = match c.command {
            MavCmd::MAV_CMD_REQUEST_MESSAGE
                if c.param1 as u32 == GIMBAL_MANAGER_INFORMATION_DATA::ID =>
            {
                match self.manager_information(now) {
                    Some(info) => {
                        g.send(&mav::command_ack(
                            c.command,
                            MavResult::MAV_RESULT_ACCEPTED,
                            &f.header,
                        ));
                        g.send(&info);
                        return;
                    }
                    None => MavResult::MAV_RESULT_TEMPORARILY_REJECTED,
                }
            }
            MavCmd::MAV_CMD_DO_GIMBAL_MANAGER_PITCHYAW => {
                match pitchyaw_target([c.param1, c.param2, c.param3, c.param4, c.param5]) {
                    Some(t) => {
                        self.target = Some(t);
                        MavResult::MAV_RESULT_ACCEPTED
                    }
                    None => MavResult::MAV_RESULT_DENIED,
                }
            }
            MavCmd::MAV_CMD_DO_GIMBAL_MANAGER_CONFIGURE => {
                // p1/p2: primary control (-1 leave, -2 release, -3 take for the sender).
                self.manager.primary = match c.param1 as i32 {
                    -3 => (f.header.system_id, f.header.component_id),
                    -2 => (0, 0),
                    -1 => self.manager.primary,
                    s => (s.clamp(0, 255) as u8, c.param2.clamp(0.0, 255.0) as u8),
                };
                MavResult::MAV_RESULT_ACCEPTED
            }
            MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL => MavResult::MAV_RESULT_ACCEPTED,
            _ => MavResult::MAV_RESULT_UNSUPPORTED,
        };
        g.send(&mav::command_ack(c.command, result, &f.header));
    }

    /// GIMBAL_MANAGER_SET_ATTITUDE: flags u32, q[4], angular velocity x, y, z (f32),
    /// target system, component, gimbal device id.
    fn manager_set_attitude(&mut self, f: &GroundFrame) {
        let [ts, tc] = f.bytes_at::<2>(32);
        if (ts != 0 && ts != self.config.sysid) || (tc != 0 && tc != mav::AUTOPILOT) {
            return;
        }
        let flags = u32::from_le_bytes(f.bytes_at(0));
        let q = [f.f32_at(4), f.f32_at(8), f.f32_at(12), f.f32_at(16)];
        if q.iter().all(|v| v.is_finite()) {
            if let Some((_, pitch, yaw)) = mav::euler_deg(q) {
                self.target = Some(Px4Target::Angle {
                    pitch_deg: pitch,
                    yaw_deg: yaw,
                    yaw_absolute: flags & YAW_LOCK != 0,
                });
            }
            return;
        }
        let rate = |v: f32| {
            if v.is_finite() {
                f64::from(v).to_degrees()
            } else {
                0.0
            }
        };
        self.target = Some(Px4Target::Rate {
            pitch_dps: rate(f.f32_at(24)),
            yaw_dps: rate(f.f32_at(28)),
        });
    }
}

/// MAV_CMD_DO_GIMBAL_MANAGER_PITCHYAW's parameters 1 to 5 as the gimbal input: angles when
/// p1 and p2 are given, else rates when p3 or p4 is (NaN is unset, an unset rate 0);
/// `None` when neither.
pub(super) fn pitchyaw_target(p: [f32; 5]) -> Option<Px4Target> {
    let [pitch, yaw, pitch_rate, yaw_rate, flags] = p;
    if pitch.is_finite() && yaw.is_finite() {
        Some(Px4Target::Angle {
            pitch_deg: f64::from(pitch),
            yaw_deg: f64::from(yaw),
            yaw_absolute: (flags as u32) & YAW_LOCK != 0,
        })
    } else if pitch_rate.is_finite() || yaw_rate.is_finite() {
        let r = |v: f32| if v.is_finite() { f64::from(v) } else { 0.0 };
        Some(Px4Target::Rate {
            pitch_dps: r(pitch_rate),
            yaw_dps: r(yaw_rate),
        })
    } else {
        None
    }
}
