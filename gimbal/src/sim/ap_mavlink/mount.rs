//! The mount driver, `AP_Mount_MAVLink`, as ArduPilot runs it:
//!
//! - **Mount.** Looks for a HEARTBEAT of type 26 from component 154 from 10 s of uptime
//!   until uptime > 60 s and armed; then asks GIMBAL_DEVICE_INFORMATION from that
//!   system/154 every second until it comes (ACKs not looked at); then enables
//!   AUTOPILOT_STATE_FOR_GIMBAL_DEVICE at 20 000 µs on the port: refused (a 50 Hz
//!   interval above 0.8 × the loop rate), the driver never initialises and no
//!   GIMBAL_DEVICE_SET_ATTITUDE is ever sent (Plane's 50 Hz loop). Initialised: SET_ATTITUDE every
//!   mount update: an angle as a quaternion (rates NaN) with flags 28 for an earth-frame
//!   yaw, 0 for a vehicle-relative one; a rate with the quaternion NaN (same flag rule;
//!   a rate from a MAVLink command zeroed after 3 s); retract as flags 1 with the
//!   quaternion NaN and rates 0; neutral as the angle of `MNT1_NEUTRAL_*` (0, 0, 0).
//!   Health: information received, an attitude status within 1 s, none of the failure
//!   flags 8..128. The status's quaternion is read as roll and pitch against the
//!   horizon and yaw relative to the vehicle whatever its flags; `delta_yaw`, once
//!   non-zero, gives the earth yaw. [`ApMavlinkConfig::old_gremsy`]: the older driver,
//!   which takes a status only when its `time_boot_ms` changed.
//! - **A location** ([`MountTarget::Location`], ROI): released ArduPilot turns it into an
//!   angle with an earth-frame yaw from the aircraft's position (flat earth) every update;
//!   the newest source ([`ApMavlinkConfig::roi_to_device`]) sends COMMAND_INT
//!   MAV_CMD_DO_SET_ROI_LOCATION to the gimbal instead (frame GLOBAL, degE7, altitude m
//!   above mean sea level) when its information's `cap_flags2` says
//!   CAN_POINT_LOCATION_GLOBAL, when the target changes and again every second, and
//!   MAV_CMD_DO_SET_ROI_NONE once when the location target ends.

use protocol_core::mavlink::dialect::{
    AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA, GIMBAL_DEVICE_ATTITUDE_STATUS_DATA,
    GIMBAL_DEVICE_INFORMATION_DATA, GIMBAL_DEVICE_SET_ATTITUDE_DATA, GimbalDeviceCapFlags,
    GimbalDeviceFlags, MavCmd, MavFrame, MavResult, MessageData as _,
};
use protocol_core::mavlink::{Header, MavMessage};

use super::{ApMavlink, Heard, MountTarget, from_device};
use crate::sim::mav::{self, GIMBAL};

impl ApMavlink {
    pub(super) fn mount_update(&mut self) {
        let ms = self.board.fc_ms();
        let Some(sysid) = self.mount_found else {
            return;
        };
        if self.mount_info.is_none() {
            let id = GIMBAL_DEVICE_INFORMATION_DATA::ID;
            self.last_info_req_ms =
                self.ask_every_second(self.last_info_req_ms, id, (sysid, GIMBAL));
            return;
        }
        if !self.mount_initialised {
            return;
        }
        let Some(mut target) = self.target else {
            return;
        };
        if let MountTarget::Location {
            lat_e7,
            lon_e7,
            alt_m,
        } = target
        {
            if self.roi_to_device() {
                self.send_roi(sysid, Some((lat_e7, lon_e7, alt_m as f32)));
                return;
            }
            // Released ArduPilot: the angles to the location, yaw from north.
            let now = self.board.now_us();
            let (lat, lon) = self.board.aircraft().position_e7(now);
            let here = (lat, lon, self.board.aircraft().alt_msl_m);
            let (bearing, elevation) = mav::bearing_elevation(here, (lat_e7, lon_e7, alt_m));
            target = MountTarget::Angle {
                roll_deg: 0.0,
                pitch_deg: elevation,
                yaw_deg: bearing,
                yaw_is_ef: true,
            };
        } else if self.roi_sent.is_some() {
            // The location target ended.
            self.send_roi(sysid, None);
        }
        let nan = [f32::NAN; 4];
        let ef_flags = |ef: bool| {
            if ef {
                GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_ROLL_LOCK
                    | GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_PITCH_LOCK
                    | GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_YAW_LOCK
            } else {
                GimbalDeviceFlags::empty()
            }
        };
        let (q, rates, flags) = match target {
            MountTarget::Angle {
                roll_deg,
                pitch_deg,
                yaw_deg,
                yaw_is_ef,
            } => (
                mav::quat_deg(roll_deg, pitch_deg, yaw_deg),
                [f32::NAN; 3],
                ef_flags(yaw_is_ef),
            ),
            MountTarget::Rate {
                pitch_dps,
                yaw_dps,
                yaw_is_ef,
                from_mavlink,
            } => {
                let stale = from_mavlink && ms.saturating_sub(self.rate_set_ms) > 3_000;
                let r = |dps: f64| if stale { 0.0 } else { dps.to_radians() as f32 };
                (nan, [0.0, r(pitch_dps), r(yaw_dps)], ef_flags(yaw_is_ef))
            }
            MountTarget::Retract => (
                nan,
                [0.0; 3],
                GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_RETRACT,
            ),
            MountTarget::Neutral => (
                mav::quat_deg(0.0, 0.0, 0.0),
                [f32::NAN; 3],
                GimbalDeviceFlags::empty(),
            ),
            MountTarget::Location { .. } => return,
        };
        let set = GIMBAL_DEVICE_SET_ATTITUDE_DATA {
            q,
            angular_velocity_x: rates[0],
            angular_velocity_y: rates[1],
            angular_velocity_z: rates[2],
            flags,
            target_system: sysid,
            target_component: GIMBAL,
        };
        self.set_attitudes.push((self.board.now_us(), set.clone()));
        self.send(&MavMessage::GIMBAL_DEVICE_SET_ATTITUDE(set));
    }

    /// GIMBAL_DEVICE_INFORMATION: the first from the gimbal found initialises the driver,
    /// when the port takes AUTOPILOT_STATE_FOR_GIMBAL_DEVICE at 50 Hz.
    pub(super) fn mount_information(&mut self, h: Header, info: GIMBAL_DEVICE_INFORMATION_DATA) {
        if !from_device(self.mount_found, &h, GIMBAL) || self.mount_info.is_some() {
            return;
        }
        self.mount_info = Some(Heard::new(self.board.now_us(), h, info));
        // Enable AUTOPILOT_STATE_FOR_GIMBAL_DEVICE at 50 Hz on this port.
        let r = self.set_interval(AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA::ID, 20_000.0);
        self.mount_initialised = r == MavResult::MAV_RESULT_ACCEPTED;
        self.mount_refused = !self.mount_initialised;
    }

    /// GIMBAL_DEVICE_ATTITUDE_STATUS from the gimbal found: the mount's attitude (the old
    /// driver: only a status whose `time_boot_ms` changed).
    pub(super) fn mount_status(&mut self, h: Header, s: GIMBAL_DEVICE_ATTITUDE_STATUS_DATA) {
        if !from_device(self.mount_found, &h, GIMBAL) {
            return;
        }
        let now_us = self.board.now_us();
        self.statuses += 1;
        let repeated = self.config.old_gremsy
            && self
                .status
                .as_ref()
                .is_some_and(|p| p.data.time_boot_ms == s.time_boot_ms);
        if !repeated {
            if let Some((roll, pitch, yaw)) = mav::euler_deg(s.q) {
                let earth = (s.delta_yaw != 0.0 || s.delta_yaw_velocity != 0.0)
                    .then(|| yaw + f64::from(s.delta_yaw).to_degrees());
                self.attitude = Some((now_us, roll, pitch, yaw, earth));
            }
            self.status = Some(Heard::new(now_us, h, s));
        }
    }

    /// The newest source sends a location to a device that can point at one.
    fn roi_to_device(&self) -> bool {
        self.config.roi_to_device
            && self.mount_info.as_ref().is_some_and(|i| {
                i.data.cap_flags2.contains(
                    GimbalDeviceCapFlags::GIMBAL_DEVICE_CAP_FLAGS_CAN_POINT_LOCATION_GLOBAL,
                )
            })
    }

    /// `send_target_location`: DO_SET_ROI_LOCATION (`Some`) when it changed or a second
    /// after the last, DO_SET_ROI_NONE (`None`) once.
    fn send_roi(&mut self, sysid: u8, location: Option<(i32, i32, f32)>) {
        let ms = self.board.fc_ms();
        let resend = match (self.roi_sent, location) {
            (Some((sent, at)), Some(l)) => sent != l || ms.saturating_sub(at) >= 1_000,
            _ => true,
        };
        if !resend {
            return;
        }
        let (command, xyz) = match location {
            Some(xyz) => (MavCmd::MAV_CMD_DO_SET_ROI_LOCATION, xyz),
            None => (MavCmd::MAV_CMD_DO_SET_ROI_NONE, (0, 0, 0.0)),
        };
        let msg = mav::command_int(
            command,
            [0.0; 4],
            xyz,
            MavFrame::MAV_FRAME_GLOBAL,
            (sysid, GIMBAL),
        );
        self.roi_sent = location.map(|l| (l, ms));
        self.send(&msg);
    }

    /// Sets the mount target; a MAVLink rate command restarts its 3 s.
    pub fn set_target(&mut self, target: MountTarget) {
        if matches!(
            target,
            MountTarget::Rate {
                from_mavlink: true,
                ..
            }
        ) {
            self.rate_set_ms = self.board.fc_ms();
        }
        self.target = Some(target);
    }
}
