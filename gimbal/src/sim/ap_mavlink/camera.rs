//! The camera driver, `AP_Camera_MAVLinkCamV2`, as ArduPilot runs it:
//!
//! - **Camera.** Looks for a HEARTBEAT of type 30 from component 100 in the same window;
//!   REQUEST_MESSAGE(CAMERA_INFORMATION) to it every second until it comes; its flags
//!   gate what the driver sends (photo CAPTURE_IMAGE, video CAPTURE_VIDEO, zoom
//!   HAS_BASIC_ZOOM, focus HAS_BASIC_FOCUS: a missing flag refuses locally). Commands
//!   to 0/0 (4.5/4.6) or to system/100 (newest), [`CameraTargets`]: one photo as
//!   IMAGE_START_CAPTURE (0, 0, 1, counter + 1), video start/stop, zoom continuous or
//!   range, focus continuous, range or auto. Camera ACKs are recorded, not consumed.
//!   [`ApMavlinkConfig::capture_status_requests`] (newest source): CAMERA_CAPTURE_STATUS
//!   asked at 1 Hz, every 10 s after three misses.

use protocol_core::mavlink::Header;
use protocol_core::mavlink::dialect::{
    CAMERA_CAPTURE_STATUS_DATA, CAMERA_INFORMATION_DATA, CameraCapFlags, MavCmd, MessageData as _,
};

use super::{ApMavlink, CameraTargets, Heard, from_device};
use crate::sim::mav::{self, CAMERA};

impl ApMavlink {
    /// Take one picture (through the camera driver).
    pub fn take_picture(&mut self) {
        if !self.camera_can(CameraCapFlags::CAMERA_CAP_FLAGS_CAPTURE_IMAGE) {
            return;
        }
        self.image_counter += 1;
        let n = self.image_counter as f32;
        self.camera_command(MavCmd::MAV_CMD_IMAGE_START_CAPTURE, [0.0, 0.0, 1.0, n]);
    }

    /// Start or stop recording.
    pub fn record_video(&mut self, on: bool) {
        if !self.camera_can(CameraCapFlags::CAMERA_CAP_FLAGS_CAPTURE_VIDEO) {
            return;
        }
        self.camera_command(mav::video_capture(on), [0.0; 4]);
    }

    /// Continuous zoom: -1 out, 0 stop, 1 in.
    pub fn zoom_rate(&mut self, rate: i8) {
        if self.camera_can(CameraCapFlags::CAMERA_CAP_FLAGS_HAS_BASIC_ZOOM) {
            let r = f32::from(rate.signum());
            self.camera_command(MavCmd::MAV_CMD_SET_CAMERA_ZOOM, [1.0, r, 0.0, 0.0]);
        }
    }

    /// Zoom to a percentage of the range.
    pub fn zoom_pct(&mut self, pct: f32) {
        if self.camera_can(CameraCapFlags::CAMERA_CAP_FLAGS_HAS_BASIC_ZOOM) {
            self.camera_command(MavCmd::MAV_CMD_SET_CAMERA_ZOOM, [2.0, pct, 0.0, 0.0]);
        }
    }

    /// Focus: `kind` 1 continuous (`value` -1/0/1), 2 range (%), 4 auto.
    pub fn focus(&mut self, kind: u8, value: f32) {
        if self.camera_can(CameraCapFlags::CAMERA_CAP_FLAGS_HAS_BASIC_FOCUS) {
            let k = f32::from(kind);
            self.camera_command(MavCmd::MAV_CMD_SET_CAMERA_FOCUS, [k, value, 0.0, 0.0]);
        }
    }

    /// CAMERA_INFORMATION: the first from the camera found.
    pub(super) fn camera_information(&mut self, h: Header, info: CAMERA_INFORMATION_DATA) {
        if from_device(self.camera_found, &h, CAMERA) && self.camera_info.is_none() {
            self.camera_info = Some(Heard::new(self.board.now_us(), h, info));
        }
    }

    fn camera_can(&mut self, flag: CameraCapFlags) -> bool {
        let ok = self
            .camera_info
            .as_ref()
            .is_some_and(|i| i.data.flags.contains(flag));
        if !ok {
            self.refused_locally += 1;
        }
        ok
    }

    fn camera_command(&mut self, cmd: MavCmd, p: [f32; 4]) {
        let target = match self.config.camera_targets {
            CameraTargets::Broadcast => (0, 0),
            CameraTargets::Addressed => (self.camera_found.unwrap_or(0), CAMERA),
        };
        self.send(&mav::camera_command(cmd, p, target));
    }

    pub(super) fn camera_update(&mut self) {
        let Some(sysid) = self.camera_found else {
            return;
        };
        // Nothing but the information request until the camera has answered it.
        if self.camera_info.is_none() {
            let (last, id) = (self.last_cam_req_ms, CAMERA_INFORMATION_DATA::ID);
            self.last_cam_req_ms = self.ask_every_second(last, id, (sysid, CAMERA));
            return;
        }
        let ms = self.board.fc_ms();
        if self.config.capture_status_requests {
            let (last, misses) = self.capture_req;
            let wait = if misses >= 3 { 10_000 } else { 1_000 };
            if last.is_none_or(|l| ms - l >= wait) {
                self.capture_req = (Some(ms), misses.saturating_add(1));
                self.send(&mav::request_message(
                    CAMERA_CAPTURE_STATUS_DATA::ID,
                    (sysid, CAMERA),
                ));
            }
        }
    }
}
