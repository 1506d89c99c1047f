//! A QGroundControl-like ground station (camera and gimbal client), as
//! docs/src/autopilots/qgroundcontrol.md describes what QGroundControl sends and reads. It
//! talks to the device through an autopilot's
//! routing ([`super::ap_mavlink::ApMavlink::gcs`], [`super::px4::Px4::gcs`]): it gets
//! the device's messages the autopilot forwards and hands it frames to forward.
//!
//! - HEARTBEAT (type GCS) at 1 Hz, system 255, component 190.
//! - **Camera discovery**: a HEARTBEAT of the vehicle's system from component 100..=105;
//!   CAMERA_INFORMATION asked alternately with REQUEST_MESSAGE(259) and
//!   MAV_CMD_REQUEST_CAMERA_INFORMATION (521), 3 s per try, at most 10 tries. An empty
//!   `cam_definition_uri` is a basic camera: CAMERA_SETTINGS (260 / 522 alternately),
//!   after 2.5 s STORAGE_INFORMATION (261 with storage 0 / 525), after 2.75 s
//!   CAMERA_CAPTURE_STATUS with the deprecated 527, VIDEO_STREAM_INFORMATION (269 / 2504)
//!   only with HAS_VIDEO_STREAM; each until it comes. The camera is removed after 5 s
//!   without HEARTBEAT.
//! - **Gimbal**: MAV_CMD_REQUEST_MESSAGE(GIMBAL_MANAGER_INFORMATION) to every component of
//!   the vehicle it hears a HEARTBEAT from; GIMBAL_DEVICE_ATTITUDE_STATUS with
//!   `gimbal_device_id` 0 is matched by its source component and its yaw frame read from
//!   YAW_IN_VEHICLE_FRAME / YAW_IN_EARTH_FRAME, else YAW_LOCK.
//! - **Commands** one at a time per component, retried on no ACK within 1.5 s or on
//!   FAILED (3 tries at most); after an ACCEPTED IMAGE_START_CAPTURE the capture status
//!   is polled (527, every 0.5 s) until `image_status` is 0 again (the shutter stays
//!   busy until then); the video state flips on the ACCEPTED ACK of 2500/2501.
//! - **Camera definition**: a `cam_definition_uri` of `mftp://` is downloaded over MAVLink
//!   FTP and its parameters read ([`SettingsClient`], in QGroundControl's style or, with
//!   [`QgcConfig::client`], MAVSDK's); only once it is in are the camera's settings,
//!   streams, capture status and storage asked (REQUEST_LIST at once, then after 0.5, 1,
//!   1.5 and 2 s); a failed download leaves the camera there, asked nothing more (what
//!   QGroundControl's code read does).
//! - CAMERA_SETTINGS' mode, zoom and focus level (non-finite ignored), the storage's
//!   capacity only when READY, CAMERA_IMAGE_CAPTURED plotted as a map point only when
//!   `capture_result` is 1 (lat/lon degE7; alt kept in mm; `time_utc` unused).
//! - **Video streams**: VIDEO_STREAM_INFORMATION kept by stream id, asked until `count`
//!   streams came; switching streams is VIDEO_STOP_STREAMING (the old id), then
//!   VIDEO_START_STREAMING (the new), then REQUEST_MESSAGE(270, new id).
//! - **Field of view**: REQUEST_MESSAGE(271) after every CAMERA_SETTINGS; its `hfov`
//!   shown when 0 < hfov < 180.
//! - **Tracking**: MAV_CMD_CAMERA_TRACK_POINT (p1 x, p2 y, p3 radius) or _RECTANGLE
//!   (p1..p4), then SET_MESSAGE_INTERVAL(275, 500 ms); stop: MAV_CMD_CAMERA_STOP_TRACKING
//!   then SET_MESSAGE_INTERVAL(275, −1); the status kept.
//! - **Gimbal controls** through the autopilot (the manager, component 1):
//!   MAV_CMD_DO_GIMBAL_MANAGER_PITCHYAW (angles or rates, as QGC's controls and MAVSDK's
//!   `set_angles` / `set_angular_rates` with send mode Once send it) and
//!   MAV_CMD_DO_SET_ROI_LOCATION / _NONE as COMMAND_INT (MAVSDK's `set_roi_location`).
//! - **For tests** (QGC reads none of them): CAMERA_THERMAL_RANGE and DISTANCE_SENSOR are
//!   kept, and any message can be asked of the camera ([`Qgc::request_from_camera`],
//!   [`Qgc::message_interval`]) as a pymavlink script would.

// QGroundControl uses the deprecated MAV_CMD_REQUEST_* commands, as the version read does.
#![allow(deprecated)]

use std::collections::VecDeque;

use std::collections::BTreeMap;

use protocol_core::mavlink::dialect::{
    CAMERA_CAPTURE_STATUS_DATA, CAMERA_FOV_STATUS_DATA, CAMERA_IMAGE_CAPTURED_DATA,
    CAMERA_INFORMATION_DATA, CAMERA_SETTINGS_DATA, CAMERA_THERMAL_RANGE_DATA,
    CAMERA_TRACKING_IMAGE_STATUS_DATA, COMMAND_ACK_DATA, CameraCapFlags, CameraMode,
    DISTANCE_SENSOR_DATA, GimbalDeviceFlags, HEARTBEAT_DATA, MavAutopilot, MavCmd, MavFrame,
    MavModeFlag, MavResult, MavState, MavType, MessageData as _, STORAGE_INFORMATION_DATA,
    StorageStatus, VIDEO_STREAM_INFORMATION_DATA, VIDEO_STREAM_STATUS_DATA,
};
use protocol_core::mavlink::{Header, MavMessage};

use super::camera_settings::{ClientStyle, SettingsClient};
use super::mav::{self, Endpoint, GCS};

/// Settings of the client.
#[derive(Debug, Clone)]
pub struct QgcConfig {
    /// Its system id.
    pub sysid: u8,
    /// The vehicle's system id.
    pub vehicle: u8,
    /// Seconds per try of a request or command before retrying.
    pub retry_us: u64,
    /// Tries of a command.
    pub command_tries: u8,
    /// How the camera definition and settings are handled (QGroundControl's way, or
    /// MAVSDK's).
    pub client: ClientStyle,
    /// Burst replies of the definition's download lost on the way (by number, from 0).
    pub drop_burst_replies: Vec<usize>,
    /// It asks for VIDEO_STREAM_INFORMATION (QGroundControl); MAVSDK 4.1 never does, and
    /// takes what comes.
    pub asks_for_streams: bool,
}

impl Default for QgcConfig {
    fn default() -> Self {
        QgcConfig {
            sysid: 255,
            vehicle: 1,
            retry_us: 1_500_000,
            command_tries: 3,
            client: ClientStyle::Qgc,
            drop_burst_replies: Vec::new(),
            asks_for_streams: true,
        }
    }
}

/// A discovered camera.
#[derive(Debug, Clone, Default)]
pub struct QgcCamera {
    /// Its component id.
    pub compid: u8,
    /// Last HEARTBEAT, true µs.
    pub last_heartbeat_us: u64,
    /// CAMERA_INFORMATION.
    pub info: Option<CAMERA_INFORMATION_DATA>,
    /// Tries of the information request.
    pub info_tries: u8,
    /// When it was discovered, true µs.
    pub found_us: u64,
    /// The last CAMERA_SETTINGS.
    pub settings: Option<CAMERA_SETTINGS_DATA>,
    /// The last STORAGE_INFORMATION.
    pub storage: Option<STORAGE_INFORMATION_DATA>,
    /// The last CAMERA_CAPTURE_STATUS.
    pub capture: Option<CAMERA_CAPTURE_STATUS_DATA>,
    /// The mode shown (from CAMERA_SETTINGS).
    pub video_mode: Option<bool>,
    /// Zoom level shown, %.
    pub zoom_pct: Option<f32>,
    /// Focus level shown.
    pub focus: Option<f32>,
    /// Capacity shown (MiB), only from a READY storage.
    pub capacity_mib: Option<f32>,
    /// Recording shown (flips on the ACK of video start/stop).
    pub recording: bool,
    /// The shutter is busy (after an accepted photo, until the status says idle).
    pub shutter_busy: bool,
    /// The camera definition and its settings (a camera with an `mftp://` definition).
    pub definition: Option<SettingsClient>,
    /// The requests that follow the definition's download are scheduled.
    initialised: bool,
    next_try: [u64; 4],
    tries: [u8; 4],
}

/// A command waiting for its ACK.
#[derive(Debug, Clone)]
struct Pending {
    msg: MavMessage,
    command: MavCmd,
    compid: u8,
    tries: u8,
    sent_us: u64,
}

/// The ground station.
#[derive(Debug)]
pub struct Qgc {
    /// Settings.
    pub config: QgcConfig,
    me: Endpoint,
    now_us: u64,
    last_heartbeat_us: Option<u64>,
    out: Vec<Vec<u8>>,
    /// The camera, once discovered.
    pub camera: Option<QgcCamera>,
    /// Components asked for GIMBAL_MANAGER_INFORMATION.
    pub manager_asked: Vec<u8>,
    queue: VecDeque<(MavMessage, MavCmd, u8)>,
    pending: Option<Pending>,
    /// Every COMMAND_ACK received: (true µs, from component, ACK).
    pub acks: Vec<(u64, u8, COMMAND_ACK_DATA)>,
    /// Commands given up (no ACK or FAILED after every try).
    pub given_up: Vec<MavCmd>,
    /// CAMERA_IMAGE_CAPTURED received.
    pub images: Vec<(u64, CAMERA_IMAGE_CAPTURED_DATA)>,
    /// Map points plotted: (lat, lon degE7, alt mm).
    pub map_points: Vec<(i32, i32, i32)>,
    /// The gimbal's attitude shown: (true µs, source component, roll, pitch, yaw °,
    /// yaw in the earth frame).
    pub gimbal: Option<(u64, u8, f64, f64, f64, bool)>,
    /// GIMBAL_DEVICE_ATTITUDE_STATUS received.
    pub gimbal_statuses: u32,
    /// Every message received: (true µs, header, id).
    pub received: Vec<(u64, Header, u32)>,
    /// VIDEO_STREAM_INFORMATION by stream id (the last of each).
    pub streams: BTreeMap<u8, VIDEO_STREAM_INFORMATION_DATA>,
    /// VIDEO_STREAM_STATUS received.
    pub stream_statuses: Vec<(u64, VIDEO_STREAM_STATUS_DATA)>,
    /// CAMERA_FOV_STATUS received.
    pub fov_statuses: Vec<(u64, CAMERA_FOV_STATUS_DATA)>,
    /// The camera's horizontal field of view shown (from CAMERA_FOV_STATUS).
    pub hfov: Option<f32>,
    /// CAMERA_TRACKING_IMAGE_STATUS received.
    pub tracking: Vec<(u64, CAMERA_TRACKING_IMAGE_STATUS_DATA)>,
    /// CAMERA_THERMAL_RANGE received (for tests).
    pub thermal_ranges: Vec<(u64, CAMERA_THERMAL_RANGE_DATA)>,
    /// DISTANCE_SENSOR received, with their sender (for tests).
    pub distances: Vec<(u64, Header, DISTANCE_SENSOR_DATA)>,
}

/// Request slots of a camera: settings, storage, capture status, video streams.
const SETTINGS: usize = 0;
const STORAGE: usize = 1;
const CAPTURE: usize = 2;

impl Qgc {
    /// A ground station.
    #[must_use]
    pub fn new(config: QgcConfig) -> Self {
        Qgc {
            me: Endpoint::new(config.sysid, GCS),
            config,
            now_us: 0,
            last_heartbeat_us: None,
            out: Vec::new(),
            camera: None,
            manager_asked: Vec::new(),
            queue: VecDeque::new(),
            pending: None,
            acks: Vec::new(),
            given_up: Vec::new(),
            images: Vec::new(),
            map_points: Vec::new(),
            gimbal: None,
            gimbal_statuses: 0,
            received: Vec::new(),
            streams: BTreeMap::new(),
            stream_statuses: Vec::new(),
            fov_statuses: Vec::new(),
            hfov: None,
            tracking: Vec::new(),
            thermal_ranges: Vec::new(),
            distances: Vec::new(),
        }
    }

    fn send(&mut self, msg: &MavMessage) {
        let f = self.me.frame(msg);
        self.out.push(f);
    }

    fn request(&mut self, compid: u8, cmd: MavCmd, p1: f32, p2: f32) {
        let msg = mav::command_long(
            cmd,
            [p1, p2, 0.0, 0.0, 0.0, 0.0, 0.0],
            (self.config.vehicle, compid),
            0,
        );
        self.send(&msg);
    }

    /// Sends `msg` as it is (tests: what no ground station sends).
    pub fn send_message(&mut self, msg: &MavMessage) {
        self.send(msg);
    }

    /// Queues a camera command (sent when the one before it is answered).
    pub fn command(&mut self, cmd: MavCmd, p: [f32; 4]) {
        let Some(compid) = self.camera.as_ref().map(|c| c.compid) else {
            return;
        };
        let msg = mav::command_long(
            cmd,
            [p[0], p[1], p[2], p[3], 0.0, 0.0, 0.0],
            (self.config.vehicle, compid),
            0,
        );
        self.queue.push_back((msg, cmd, compid));
    }

    /// The photo button (single shot).
    pub fn take_photo(&mut self) {
        self.command(MavCmd::MAV_CMD_IMAGE_START_CAPTURE, [0.0, 0.0, 1.0, 0.0]);
    }

    /// Time-lapse: a photo every `interval_s`, `count` photos (0: until stopped).
    pub fn start_interval(&mut self, interval_s: f32, count: f32) {
        self.command(
            MavCmd::MAV_CMD_IMAGE_START_CAPTURE,
            [0.0, interval_s, count, 0.0],
        );
    }

    /// Stops an interval capture.
    pub fn stop_capture(&mut self) {
        self.command(MavCmd::MAV_CMD_IMAGE_STOP_CAPTURE, [0.0; 4]);
    }

    /// Video start (all streams, no status stream) or stop.
    pub fn record(&mut self, on: bool) {
        self.command(mav::video_capture(on), [0.0; 4]);
    }

    /// The photo/video switch (only with HAS_MODES).
    pub fn set_mode(&mut self, video: bool) {
        if self.has(CameraCapFlags::CAMERA_CAP_FLAGS_HAS_MODES) {
            let mode = if video { 1.0 } else { 0.0 };
            self.command(MavCmd::MAV_CMD_SET_CAMERA_MODE, [0.0, mode, 0.0, 0.0]);
        }
    }

    /// Zoom slider: `kind` 0 step (±1), 1 continuous (−1, 0, 1), 2 range (0–100 %).
    pub fn zoom(&mut self, kind: u8, value: f32) {
        self.command(
            MavCmd::MAV_CMD_SET_CAMERA_ZOOM,
            [f32::from(kind), value, 0.0, 0.0],
        );
    }

    /// Focus slider (range, 0–100 %).
    pub fn focus_range(&mut self, pct: f32) {
        self.command(MavCmd::MAV_CMD_SET_CAMERA_FOCUS, [2.0, pct, 0.0, 0.0]);
    }

    /// Storage format.
    pub fn format_storage(&mut self) {
        self.command(MavCmd::MAV_CMD_STORAGE_FORMAT, [1.0, 1.0, 0.0, 0.0]);
    }

    /// Queues a command to component `compid` of the vehicle (the camera, the gimbal, the
    /// autopilot).
    pub fn command_to(&mut self, compid: u8, msg: MavMessage) {
        let command = match &msg {
            MavMessage::COMMAND_LONG(c) => c.command,
            MavMessage::COMMAND_INT(c) => c.command,
            _ => return,
        };
        self.queue.push_back((msg, command, compid));
    }

    /// Tracking a point of the video (a click): TRACK_POINT, then the status every 500 ms.
    pub fn track_point(&mut self, x: f32, y: f32, radius: f32) {
        self.command(MavCmd::MAV_CMD_CAMERA_TRACK_POINT, [x, y, radius, 0.0]);
        self.tracking_interval(500_000.0);
    }

    /// Tracking a rectangle drawn on the video (top left, bottom right).
    pub fn track_rectangle(&mut self, x0: f32, y0: f32, x1: f32, y1: f32) {
        self.command(MavCmd::MAV_CMD_CAMERA_TRACK_RECTANGLE, [x0, y0, x1, y1]);
        self.tracking_interval(500_000.0);
    }

    /// Stops tracking, then the status.
    pub fn stop_tracking(&mut self) {
        self.command(MavCmd::MAV_CMD_CAMERA_STOP_TRACKING, [0.0; 4]);
        self.tracking_interval(-1.0);
    }

    fn tracking_interval(&mut self, us: f32) {
        self.message_interval(CAMERA_TRACKING_IMAGE_STATUS_DATA::ID, us, 0.0, 0.0);
    }

    /// Switching the video from stream `from` to stream `to`.
    pub fn switch_stream(&mut self, from: u8, to: u8) {
        let p = |id: u8| [f32::from(id), 0.0, 0.0, 0.0];
        self.command(MavCmd::MAV_CMD_VIDEO_STOP_STREAMING, p(from));
        self.command(MavCmd::MAV_CMD_VIDEO_START_STREAMING, p(to));
        self.request_from_camera(VIDEO_STREAM_STATUS_DATA::ID, f32::from(to));
    }

    /// MAV_CMD_REQUEST_MESSAGE of message `id` to the camera, param2 `p2` (as a script
    /// sends it).
    pub fn request_from_camera(&mut self, id: u32, p2: f32) {
        self.command(MavCmd::MAV_CMD_REQUEST_MESSAGE, [id as f32, p2, 0.0, 0.0]);
    }

    /// MAV_CMD_SET_MESSAGE_INTERVAL of message `id` to the camera: `us` (0 default, −1
    /// stop), param3 and param4 as given.
    pub fn message_interval(&mut self, id: u32, us: f32, p3: f32, p4: f32) {
        self.command(
            MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
            [id as f32, us, p3, p4],
        );
    }

    /// MAV_CMD_DO_GIMBAL_MANAGER_PITCHYAW to the autopilot (the gimbal manager): angles
    /// (degrees; NaN rates) or rates (deg/s; NaN angles), `flags` GIMBAL_MANAGER_FLAGS
    /// (16: yaw locked to north), for gimbal device `device` (param7).
    pub fn gimbal_pitchyaw(&mut self, angles: [f32; 2], rates: [f32; 2], flags: u32, device: u8) {
        let p = [
            angles[0],
            angles[1],
            rates[0],
            rates[1],
            flags as f32,
            0.0,
            f32::from(device),
        ];
        let target = (self.config.vehicle, super::mav::AUTOPILOT);
        let msg = mav::command_long(MavCmd::MAV_CMD_DO_GIMBAL_MANAGER_PITCHYAW, p, target, 0);
        self.command_to(super::mav::AUTOPILOT, msg);
    }

    /// MAV_CMD_DO_SET_ROI_LOCATION (`Some`: latitude, longitude degE7, altitude m AMSL) or
    /// _NONE to the autopilot, as COMMAND_INT (MAVSDK's `set_roi_location`).
    pub fn gimbal_roi(&mut self, location: Option<(i32, i32, f32)>) {
        let target = (self.config.vehicle, super::mav::AUTOPILOT);
        let msg = match location {
            Some(xyz) => mav::command_int(
                MavCmd::MAV_CMD_DO_SET_ROI_LOCATION,
                [0.0; 4],
                xyz,
                MavFrame::MAV_FRAME_GLOBAL,
                target,
            ),
            None => mav::command_int(
                MavCmd::MAV_CMD_DO_SET_ROI_NONE,
                [0.0; 4],
                (0, 0, 0.0),
                MavFrame::MAV_FRAME_GLOBAL,
                target,
            ),
        };
        self.command_to(super::mav::AUTOPILOT, msg);
    }

    fn has(&self, flag: CameraCapFlags) -> bool {
        self.camera
            .as_ref()
            .and_then(|c| c.info.as_ref())
            .is_some_and(|i| i.flags.contains(flag))
    }

    /// The last ACK of `cmd` from the camera.
    #[must_use]
    pub fn ack_of(&self, cmd: MavCmd) -> Option<MavResult> {
        self.acks
            .iter()
            .rev()
            .find(|(_, _, a)| a.command == cmd)
            .map(|(_, _, a)| a.result)
    }

    /// A message the autopilot routed to it.
    pub fn receive(&mut self, now_us: u64, h: Header, msg: &MavMessage) {
        self.now_us = self.now_us.max(now_us);
        self.received.push((now_us, h, mav::id_of(msg)));
        if h.system_id != self.config.vehicle {
            return;
        }
        if let Some(client) = self.camera_of(h).and_then(|c| c.definition.as_mut()) {
            client.receive(now_us, h, msg);
        }
        match msg {
            MavMessage::HEARTBEAT(hb) => self.heartbeat(now_us, h, hb),
            MavMessage::CAMERA_INFORMATION(i) => {
                let (style, drop) = (self.config.client, self.config.drop_burst_replies.clone());
                if let Some(c) = self.camera_of(h) {
                    c.info = Some(i.clone());
                    let basic = i.cam_definition_uri.first().is_none_or(|b| *b == 0);
                    let uri = String::from_utf8_lossy(&i.cam_definition_uri[..])
                        .trim_end_matches('\0')
                        .to_owned();
                    if uri.starts_with("mftp://") && c.definition.is_none() {
                        let target = (h.system_id, h.component_id);
                        c.definition = Some(SettingsClient::new(style, target, &uri, drop));
                    } else if basic {
                        c.next_try = [now_us, now_us + 2_500_000, now_us + 2_750_000, u64::MAX];
                        if i.flags
                            .contains(CameraCapFlags::CAMERA_CAP_FLAGS_HAS_VIDEO_STREAM)
                        {
                            c.next_try[3] = now_us;
                        }
                    }
                }
            }
            MavMessage::CAMERA_SETTINGS(s) => {
                if self.camera_of(h).is_some() {
                    // The field of view after every CAMERA_SETTINGS.
                    let id = CAMERA_FOV_STATUS_DATA::ID as f32;
                    self.request(h.component_id, MavCmd::MAV_CMD_REQUEST_MESSAGE, id, 0.0);
                }
                if let Some(c) = self.camera_of(h) {
                    c.settings = Some(s.clone());
                    c.next_try[SETTINGS] = u64::MAX;
                    c.video_mode = Some(s.mode_id == CameraMode::CAMERA_MODE_VIDEO);
                    if s.zoomLevel.is_finite() {
                        c.zoom_pct = Some(s.zoomLevel);
                    }
                    if s.focusLevel.is_finite() {
                        c.focus = Some(s.focusLevel);
                    }
                }
            }
            MavMessage::STORAGE_INFORMATION(s) => {
                if let Some(c) = self.camera_of(h) {
                    c.storage = Some(s.clone());
                    c.next_try[STORAGE] = u64::MAX;
                    if s.status == StorageStatus::STORAGE_STATUS_READY {
                        c.capacity_mib = Some(s.total_capacity);
                    }
                }
            }
            MavMessage::CAMERA_CAPTURE_STATUS(s) => {
                if let Some(c) = self.camera_of(h) {
                    c.capture = Some(s.clone());
                    if c.next_try[CAPTURE] != u64::MAX && !c.shutter_busy {
                        c.next_try[CAPTURE] = u64::MAX;
                    }
                    if s.image_status == 0 {
                        c.shutter_busy = false;
                        c.next_try[CAPTURE] = u64::MAX;
                    }
                }
            }
            MavMessage::CAMERA_IMAGE_CAPTURED(i) => {
                self.images.push((now_us, i.clone()));
                if i.capture_result.bits() == 1 {
                    self.map_points.push((i.lat, i.lon, i.alt));
                }
            }
            MavMessage::COMMAND_ACK(a) => self.ack(now_us, h, a),
            MavMessage::VIDEO_STREAM_INFORMATION(i) => {
                self.streams.insert(i.stream_id, i.clone());
                let all = self.streams.len() >= usize::from(i.count);
                if let Some(c) = self.camera_of(h)
                    && all
                {
                    c.next_try[3] = u64::MAX;
                }
            }
            MavMessage::VIDEO_STREAM_STATUS(s) => self.stream_statuses.push((now_us, s.clone())),
            MavMessage::CAMERA_FOV_STATUS(f) => {
                if f.hfov > 0.0 && f.hfov < 180.0 {
                    self.hfov = Some(f.hfov);
                }
                self.fov_statuses.push((now_us, f.clone()));
            }
            MavMessage::CAMERA_TRACKING_IMAGE_STATUS(t) => self.tracking.push((now_us, t.clone())),
            MavMessage::CAMERA_THERMAL_RANGE(t) => self.thermal_ranges.push((now_us, t.clone())),
            MavMessage::DISTANCE_SENSOR(d) => self.distances.push((now_us, h, d.clone())),
            MavMessage::GIMBAL_DEVICE_ATTITUDE_STATUS(s) => {
                self.gimbal_statuses += 1;
                if s.gimbal_device_id == 0
                    && let Some((roll, pitch, yaw)) = mav::euler_deg(s.q)
                {
                    let f = s.flags;
                    let earth = if f
                        .contains(GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_YAW_IN_VEHICLE_FRAME)
                    {
                        false
                    } else {
                        f.contains(GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_YAW_IN_EARTH_FRAME)
                            || f.contains(GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_YAW_LOCK)
                    };
                    self.gimbal = Some((now_us, h.component_id, roll, pitch, yaw, earth));
                }
            }
            _ => {}
        }
    }

    /// The camera's definition and settings client.
    pub fn definition(&mut self) -> Option<&mut SettingsClient> {
        self.camera.as_mut().and_then(|c| c.definition.as_mut())
    }

    fn camera_of(&mut self, h: Header) -> Option<&mut QgcCamera> {
        self.camera.as_mut().filter(|c| c.compid == h.component_id)
    }

    fn heartbeat(&mut self, now_us: u64, h: Header, hb: &HEARTBEAT_DATA) {
        let _ = hb;
        if !self.manager_asked.contains(&h.component_id) {
            self.manager_asked.push(h.component_id);
            self.request(
                h.component_id,
                MavCmd::MAV_CMD_REQUEST_MESSAGE,
                protocol_core::mavlink::dialect::GIMBAL_MANAGER_INFORMATION_DATA::ID as f32,
                0.0,
            );
        }
        if (100..=105).contains(&h.component_id) {
            match self.camera.as_mut() {
                Some(c) if c.compid == h.component_id => c.last_heartbeat_us = now_us,
                Some(_) => {}
                None => {
                    self.camera = Some(QgcCamera {
                        compid: h.component_id,
                        last_heartbeat_us: now_us,
                        found_us: now_us,
                        next_try: [u64::MAX; 4],
                        ..QgcCamera::default()
                    });
                }
            }
        }
    }

    fn ack(&mut self, now_us: u64, h: Header, a: &COMMAND_ACK_DATA) {
        self.acks.push((now_us, h.component_id, a.clone()));
        let Some(p) = self.pending.as_ref() else {
            return;
        };
        if p.command != a.command || p.compid != h.component_id {
            return;
        }
        let p = self.pending.take().expect("pending");
        match a.result {
            MavResult::MAV_RESULT_FAILED => self.retry(p),
            MavResult::MAV_RESULT_ACCEPTED => {
                let now = self.now_us;
                if let Some(c) = self.camera.as_mut() {
                    match a.command {
                        MavCmd::MAV_CMD_IMAGE_START_CAPTURE => {
                            c.shutter_busy = true;
                            c.next_try[CAPTURE] = now + 500_000;
                        }
                        MavCmd::MAV_CMD_VIDEO_START_CAPTURE => c.recording = true,
                        MavCmd::MAV_CMD_VIDEO_STOP_CAPTURE => c.recording = false,
                        _ => {}
                    }
                }
            }
            _ => {}
        }
    }

    fn retry(&mut self, mut p: Pending) {
        if p.tries >= self.config.command_tries {
            self.given_up.push(p.command);
            return;
        }
        p.tries += 1;
        p.sent_us = self.now_us;
        let msg = p.msg.clone();
        self.send(&msg);
        self.pending = Some(p);
    }

    /// Work due at `now_us`.
    pub fn poll(&mut self, now_us: u64) {
        self.now_us = self.now_us.max(now_us);
        let now = self.now_us;
        if self.last_heartbeat_us.is_none_or(|l| now - l >= 1_000_000) {
            self.last_heartbeat_us = Some(now);
            self.send(&MavMessage::HEARTBEAT(HEARTBEAT_DATA {
                custom_mode: 0,
                mavtype: MavType::MAV_TYPE_GCS,
                autopilot: MavAutopilot::MAV_AUTOPILOT_INVALID,
                base_mode: MavModeFlag::empty(),
                system_status: MavState::MAV_STATE_ACTIVE,
                mavlink_version: 3,
            }));
        }
        if self
            .camera
            .as_ref()
            .is_some_and(|c| now - c.last_heartbeat_us > 5_000_000)
        {
            self.camera = None;
        }
        self.camera_requests(now);
        if let Some(p) = self.pending.take() {
            if now - p.sent_us >= self.config.retry_us {
                self.retry(p);
            } else {
                self.pending = Some(p);
            }
        }
        if self.pending.is_none()
            && let Some((msg, command, compid)) = self.queue.pop_front()
        {
            self.send(&msg);
            self.pending = Some(Pending {
                msg,
                command,
                compid,
                tries: 1,
                sent_us: now,
            });
        }
    }

    fn camera_requests(&mut self, now: u64) {
        let Some(mut c) = self.camera.take() else {
            return;
        };
        if let Some(client) = c.definition.as_mut() {
            client.poll(now);
            for m in client.transmit() {
                self.send(&m);
            }
            if !c.initialised && client.loaded() {
                c.initialised = true;
                // QGroundControl's initialisation once the definition is in.
                let video = c.info.as_ref().is_some_and(|i| {
                    i.flags
                        .contains(CameraCapFlags::CAMERA_CAP_FLAGS_HAS_VIDEO_STREAM)
                });
                c.next_try = [
                    now + 500_000,
                    now + 2_000_000,
                    now + 1_500_000,
                    if video { now + 1_000_000 } else { u64::MAX },
                ];
            }
        }
        let retry = 3_000_000;
        if c.info.is_none() {
            let due = c.found_us + u64::from(c.info_tries) * retry;
            if c.info_tries < 10 && now >= due {
                let (cmd, p1) = if c.info_tries % 2 == 0 {
                    (
                        MavCmd::MAV_CMD_REQUEST_MESSAGE,
                        CAMERA_INFORMATION_DATA::ID as f32,
                    )
                } else {
                    (MavCmd::MAV_CMD_REQUEST_CAMERA_INFORMATION, 1.0)
                };
                c.info_tries += 1;
                self.request(c.compid, cmd, p1, 0.0);
            }
            self.camera = Some(c);
            return;
        }
        for slot in 0..4 {
            if now < c.next_try[slot] || (slot == 3 && !self.config.asks_for_streams) {
                continue;
            }
            let alt = c.tries[slot] % 2 == 1;
            c.tries[slot] = c.tries[slot].saturating_add(1);
            let (cmd, p1, p2, period) = match (slot, alt) {
                (SETTINGS, false) => (MavCmd::MAV_CMD_REQUEST_MESSAGE, 260.0, 0.0, retry),
                (SETTINGS, true) => (MavCmd::MAV_CMD_REQUEST_CAMERA_SETTINGS, 0.0, 0.0, retry),
                (STORAGE, false) => (MavCmd::MAV_CMD_REQUEST_MESSAGE, 261.0, 0.0, retry),
                (STORAGE, true) => (MavCmd::MAV_CMD_REQUEST_STORAGE_INFORMATION, 0.0, 0.0, retry),
                // The deprecated command, as the QGC version read; polled while busy.
                (CAPTURE, _) => (
                    MavCmd::MAV_CMD_REQUEST_CAMERA_CAPTURE_STATUS,
                    0.0,
                    0.0,
                    if c.shutter_busy { 500_000 } else { retry },
                ),
                (_, false) => (MavCmd::MAV_CMD_REQUEST_MESSAGE, 269.0, 0.0, retry),
                (_, true) => (
                    MavCmd::MAV_CMD_REQUEST_VIDEO_STREAM_INFORMATION,
                    0.0,
                    0.0,
                    retry,
                ),
            };
            c.next_try[slot] = now + period;
            self.request(c.compid, cmd, p1, p2);
        }
        self.camera = Some(c);
    }

    /// Frames to send (the autopilot routes them).
    pub fn transmit(&mut self) -> Vec<Vec<u8>> {
        std::mem::take(&mut self.out)
    }
}
