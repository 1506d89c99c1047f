//! The pod's sensors as the camera (component 100) reports them (docs/src/bridge/mavlink.md,
//! "Thermal range", "Laser", "Where the camera looks"): the requests, commands and message
//! intervals of the video stream ([`super::video`]), tracking ([`super::tracking`]), and
//! here the thermal range, the laser distance and the field of view.
//!
//! - **CAMERA_THERMAL_RANGE** (277) from the pod's IR measurements (0x000004, 5 Hz while
//!   measurement is on): the region's maximum and minimum in °C (0.1 °C on the wire) and
//!   their positions normalised to the thermal picture, stream 1, camera_device_id 0. The
//!   pod's IR coordinates are those of 0x00010F and 0x000110: a 1920 × 1088 frame with a
//!   black border; the document gives the picture as x 320..1079 (0x00010F) or 320..1279
//!   (0x000110) and y 32..1023. Decision (docs/src/protocols/k40t.md): the 640 × 512
//!   thermal picture shown at twice its size, 1280 × 1024, centred: x 320..1599 and
//!   y 32..1055, the document's 320 and 32 being the borders and its 1279 and 1023 the
//!   last pixel of 1280 and 1024; x' = (x − 320) / 1280, y' = (y − 32) / 1024, clamped
//!   to 0..1. Sent once a second by default while the pod measures (nothing while it
//!   does not), at the interval SET_MESSAGE_INTERVAL(277) asks (at most the pod's 5 Hz;
//!   −1 stops; param3 the stream, 0 or 1; param4 the camera device, 0), and on
//!   REQUEST_MESSAGE(277) (TEMPORARILY_REJECTED while the pod does not measure).
//! - **DISTANCE_SENSOR** (132) with each new laser reading (0x000406 status frames every
//!   second while periodic ranging is on, the ACK of a single ranging 0x000400): type
//!   LASER, orientation MAV_SENSOR_ROTATION_CUSTOM with the gimbal's orientation in the
//!   vehicle body frame (the pod's joint angles, 0x000002), min and max distance from
//!   `laser.min_distance_cm` and `laser.max_distance_cm` (the document gives none), the
//!   reading in cm (0.1 m on the wire; at most the field's 65535; none for a reading of
//!   0, no return). The bridge ranges only when asked: SET_MESSAGE_INTERVAL(132) with an
//!   interval ≥ 0 switches periodic ranging on (0x000406; the pod's period is 1 s), −1
//!   switches it off and stops the messages, REQUEST_MESSAGE(132) ranges once (0x000400)
//!   and sends the reading after its ACK (FAILED for no return); `laser.periodic` ranges
//!   from every link-up.
//! - **CAMERA_FOV_STATUS** (271) on REQUEST_MESSAGE (QGroundControl asks after each
//!   CAMERA_SETTINGS) and at the interval SET_MESSAGE_INTERVAL(271) asks (at most 5 Hz):
//!   the camera's position from the aircraft's latest fix (INT32_MAX unknown); where it
//!   looks: the pod's laser target (0x000320, asked with the aircraft's state for each
//!   message, which waits up to 300 ms for the answer), else computed in
//!   a flat-earth frame ([`super::geo`]) from the laser's range along the camera's
//!   direction, else where that direction meets the ground at home's altitude; INT32_MIN
//!   when it looks at or above the horizon (or meets the ground beyond 10 km), INT32_MAX
//!   when the position or the attitude is unknown; the camera's orientation in the earth
//!   frame (the pod's roll and pitch, its yaw plus the aircraft's heading); the fields of
//!   view ([`super::fov`]).

use crate::event::Decline;
use crate::fc::Ctx;
use crate::gimbal::{Command, Ranging};
use crate::time::{Duration, Instant, UtcTime};
use protocol_core::k40t::IrStatus;
use protocol_core::mavlink::dialect::{
    CAMERA_FOV_STATUS_DATA, CAMERA_THERMAL_RANGE_DATA, CameraCapFlags, DISTANCE_SENSOR_DATA,
    MavDistanceSensor, MavSensorOrientation,
};
use protocol_core::mavlink::{Header, MavMessage};

use super::geo::{LookAt, Position, look_at};
use super::gimbal::boot_ms;
use super::intervals::Every;
use super::video::is_our_stream;
use super::{Cmd, Comp, MavlinkSide, cmd, fov, id, math, param_id, param_is, result, tracking};

/// The thermal picture in the pod's IR coordinates: left and top borders, size (see the
/// module documentation).
const IR_LEFT: f32 = 320.0;
const IR_TOP: f32 = 32.0;
const IR_WIDTH: f32 = 1280.0;
const IR_HEIGHT: f32 = 1024.0;
/// CAMERA_THERMAL_RANGE's default interval, and the shortest (the pod's 5 Hz).
const THERMAL_DEFAULT: Duration = Duration::from_secs(1);
const THERMAL_LEAST: Duration = Duration::from_millis(200);
/// CAMERA_FOV_STATUS's default interval (param2 0), and the shortest.
const FOV_DEFAULT: Duration = Duration::from_secs(1);
const FOV_LEAST: Duration = Duration::from_millis(200);
/// A CAMERA_FOV_STATUS waits this long at most for the pod's laser target.
const TARGET_WAIT: Duration = Duration::from_millis(300);
/// K40T single ranging, the laser target's position.
const LASER_RANGE: u16 = 0x0400;
const TARGET_GPS: u16 = 0x0320;

/// The sensors' state on the MAVLink side.
#[derive(Debug, Clone, Copy)]
pub(super) struct Sensors {
    thermal: Every,
    fov: Every,
    /// DISTANCE_SENSOR is sent with each reading (until SET_MESSAGE_INTERVAL −1).
    distance_on: bool,
    /// A client asked DISTANCE_SENSOR at an interval: periodic ranging kept on.
    ranging: bool,
    /// The instant of the reading last reported.
    distance_told: Option<Instant>,
    /// A REQUEST_MESSAGE(132) waiting for the pod's single ranging.
    distance_asked: Option<Header>,
    /// A CAMERA_FOV_STATUS waits for the laser target asked at this instant (until
    /// [`TARGET_WAIT`] after it).
    fov_waits: Option<Instant>,
}

impl Default for Sensors {
    fn default() -> Self {
        Sensors {
            thermal: Every::at_interval(THERMAL_DEFAULT),
            fov: Every::OFF,
            distance_on: true,
            ranging: false,
            distance_told: None,
            distance_asked: None,
            fov_waits: None,
        }
    }
}

/// A command of the sensors this component acts on.
pub(super) fn is_sensor_command(c: u16) -> bool {
    matches!(
        c,
        cmd::SET_CAMERA_SOURCE
            | cmd::CAMERA_TRACK_POINT
            | cmd::CAMERA_TRACK_RECTANGLE
            | cmd::CAMERA_STOP_TRACKING
            | cmd::VIDEO_START_STREAMING
            | cmd::VIDEO_STOP_STREAMING
    )
}

/// A message of the sensors the camera sends.
pub(super) fn is_sensor_message(m: u32) -> bool {
    matches!(
        m,
        id::VIDEO_STREAM_INFORMATION
            | id::VIDEO_STREAM_STATUS
            | id::CAMERA_FOV_STATUS
            | id::CAMERA_TRACKING_IMAGE_STATUS
            | id::CAMERA_THERMAL_RANGE
            | id::DISTANCE_SENSOR
    )
}

/// A position in the pod's IR coordinates, normalised to the thermal picture.
fn ir_normalised(x: u16, y: u16) -> (f32, f32) {
    (
        ((f32::from(x) - IR_LEFT) / IR_WIDTH).clamp(0.0, 1.0),
        ((f32::from(y) - IR_TOP) / IR_HEIGHT).clamp(0.0, 1.0),
    )
}

impl MavlinkSide {
    /// CAMERA_INFORMATION's flags for the sensors: the video stream while its address is
    /// known, tracking (point and rectangle), the thermal range while the pod's IR camera
    /// measures.
    pub(super) fn sensor_flags(ctx: &Ctx<'_>) -> CameraCapFlags {
        let mut f = CameraCapFlags::CAMERA_CAP_FLAGS_HAS_TRACKING_POINT
            | CameraCapFlags::CAMERA_CAP_FLAGS_HAS_TRACKING_RECTANGLE;
        if Self::stream_uri(ctx).is_some() {
            f |= CameraCapFlags::CAMERA_CAP_FLAGS_HAS_VIDEO_STREAM;
        }
        if ctx.pod().ir_first.is_some() {
            f |= CameraCapFlags::CAMERA_CAP_FLAGS_HAS_THERMAL_RANGE;
        }
        f
    }

    /// A sensor command (see [`is_sensor_command`]).
    pub(super) fn sensor_command(&mut self, ctx: &mut Ctx<'_>, c: &Cmd) {
        let streaming = matches!(
            c.command,
            cmd::VIDEO_START_STREAMING | cmd::VIDEO_STOP_STREAMING
        );
        if !ctx.pod().link && !streaming {
            self.refused(ctx, c.command, Decline::PodLost);
            self.ack(
                ctx,
                Comp::Camera,
                c.command,
                result::TEMPORARILY_REJECTED,
                c.from,
            );
            return;
        }
        match c.command {
            cmd::CAMERA_TRACK_POINT | cmd::CAMERA_TRACK_RECTANGLE | cmd::CAMERA_STOP_TRACKING => {
                self.tracking_command(ctx, c);
            }
            _ => self.video_command(ctx, c),
        }
    }

    /// A request of a sensor message (REQUEST_MESSAGE, or the deprecated video stream
    /// requests): false when addressed to the gimbal.
    pub(super) fn sensor_request(
        &mut self,
        ctx: &mut Ctx<'_>,
        c: &Cmd,
        to: Option<Comp>,
        msg: u32,
    ) -> bool {
        if to == Some(Comp::Gimbal) {
            return false;
        }
        let arg = c.message_param();
        match msg {
            id::VIDEO_STREAM_INFORMATION | id::VIDEO_STREAM_STATUS => {
                self.video_request(ctx, c, msg, arg);
            }
            id::CAMERA_FOV_STATUS => {
                self.ack(ctx, Comp::Camera, c.command, result::ACCEPTED, c.from);
                self.fov_status(ctx);
            }
            id::CAMERA_TRACKING_IMAGE_STATUS => {
                self.ack(ctx, Comp::Camera, c.command, result::ACCEPTED, c.from);
                self.tracking_status(ctx);
            }
            id::CAMERA_THERMAL_RANGE => {
                let r = if !is_our_stream(arg) {
                    self.refused(ctx, c.command, Decline::OtherDevice);
                    result::DENIED
                } else if Self::measuring(ctx) {
                    result::ACCEPTED
                } else {
                    self.refused(ctx, c.command, Decline::NoMeasurement);
                    result::TEMPORARILY_REJECTED
                };
                self.ack(ctx, Comp::Camera, c.command, r, c.from);
                if r == result::ACCEPTED {
                    self.thermal_range(ctx);
                }
            }
            _ => {
                // DISTANCE_SENSOR: one ranging, answered after the pod's ACK.
                if ctx.pod().link && self.sensors.distance_asked.is_none() {
                    let single = Command::Laser(Ranging::Single);
                    if ctx.command(c.command, single).is_some() {
                        self.sensors.distance_asked = Some(c.from);
                        return true;
                    }
                }
                self.refused(ctx, c.command, Decline::PodLost);
                self.ack(
                    ctx,
                    Comp::Camera,
                    c.command,
                    result::TEMPORARILY_REJECTED,
                    c.from,
                );
            }
        }
        true
    }

    /// MAV_CMD_SET_MESSAGE_INTERVAL addressed to the camera for one of its sensor
    /// messages; false for any other (UNSUPPORTED when addressed to this device).
    pub(super) fn set_interval(&mut self, ctx: &mut Ctx<'_>, c: &Cmd, to: Option<Comp>) -> bool {
        let Some(msg) = param_id(c.param(1)) else {
            return false;
        };
        let ours = matches!(
            msg,
            id::CAMERA_THERMAL_RANGE
                | id::CAMERA_TRACKING_IMAGE_STATUS
                | id::CAMERA_FOV_STATUS
                | id::DISTANCE_SENSOR
        );
        if to != Some(Comp::Camera) || !ours {
            return false;
        }
        let (now, us) = (ctx.now, c.param(2));
        let ok = match msg {
            id::CAMERA_THERMAL_RANGE => {
                let device = c.param(4);
                if is_our_stream(c.param(3)) && (device.is_nan() || param_is(device, 0)) {
                    self.sensors
                        .thermal
                        .set(now, us, THERMAL_DEFAULT, THERMAL_LEAST)
                } else {
                    self.refused(ctx, c.command, Decline::OtherDevice);
                    self.ack(ctx, Comp::Camera, c.command, result::DENIED, c.from);
                    return true;
                }
            }
            id::CAMERA_TRACKING_IMAGE_STATUS => self.tracking_interval(now, us),
            id::CAMERA_FOV_STATUS => self.sensors.fov.set(now, us, FOV_DEFAULT, FOV_LEAST),
            _ => return self.distance_interval(ctx, c, us),
        };
        let r = if ok {
            result::ACCEPTED
        } else {
            self.refused(ctx, c.command, Decline::NotGiven);
            result::DENIED
        };
        self.ack(ctx, Comp::Camera, c.command, r, c.from);
        true
    }

    /// SET_MESSAGE_INTERVAL(132): ranging on (interval ≥ 0) or off (−1), ACK after the
    /// pod's.
    fn distance_interval(&mut self, ctx: &mut Ctx<'_>, c: &Cmd, us: f32) -> bool {
        if us.is_nan() {
            self.refused(ctx, c.command, Decline::NotGiven);
            self.ack(ctx, Comp::Camera, c.command, result::DENIED, c.from);
            return true;
        }
        if !ctx.pod().link {
            self.refused(ctx, c.command, Decline::PodLost);
            self.ack(
                ctx,
                Comp::Camera,
                c.command,
                result::TEMPORARILY_REJECTED,
                c.from,
            );
            return true;
        }
        let on = us >= 0.0;
        self.sensors.distance_on = on;
        self.sensors.ranging = on;
        if !on && ctx.config.laser.periodic {
            // `laser.periodic` keeps the laser ranging; only the messages stop.
            self.ack(ctx, Comp::Camera, c.command, result::ACCEPTED, c.from);
            return true;
        }
        let ranging = if on {
            Ranging::Continuous
        } else {
            Ranging::Off
        };
        let base = ctx.command(c.command, Command::Laser(ranging));
        self.await_pod(ctx, c, base);
        true
    }

    /// The pod reports again: the ranging a client asked is switched on again.
    pub(super) fn sensors_link_up(&mut self, ctx: &mut Ctx<'_>) {
        if self.sensors.ranging && !ctx.config.laser.periodic {
            ctx.command(
                cmd::SET_MESSAGE_INTERVAL,
                Command::Laser(Ranging::Continuous),
            );
        }
    }

    /// The pod answered (or never did) a request of base `base`.
    pub(super) fn sensors_pod_answer(&mut self, ctx: &mut Ctx<'_>, base: u16, ok: bool) {
        match base {
            tracking::TRACK_BOX => self.tracking_pod_answer(ctx, ok),
            TARGET_GPS if self.sensors.fov_waits.is_some() => self.send_fov_status(ctx),
            LASER_RANGE => {
                let Some(from) = self.sensors.distance_asked.take() else {
                    return;
                };
                let reading = ctx.pod().laser_dm.filter(|(dm, _)| ok && *dm > 0);
                let c = cmd::REQUEST_MESSAGE;
                if let Some((dm, at)) = reading {
                    self.ack(ctx, Comp::Camera, c, result::ACCEPTED, from);
                    self.sensors.distance_told = Some(at);
                    self.distance_sensor(ctx, dm);
                } else {
                    if ok {
                        self.refused(ctx, c, Decline::NoLaserReturn);
                    }
                    self.ack(ctx, Comp::Camera, c, result::FAILED, from);
                }
            }
            _ => {}
        }
    }

    /// After every pod frame: a new laser reading, the end of tracking, a change of the
    /// stream.
    pub(super) fn sensors_frame(&mut self, ctx: &mut Ctx<'_>) {
        if let Some((dm, at)) = ctx.pod().laser_dm
            && self.sensors.distance_told != Some(at)
            && self.sensors.distance_asked.is_none()
        {
            self.sensors.distance_told = Some(at);
            if dm > 0 && self.sensors.distance_on {
                self.distance_sensor(ctx, dm);
            }
        }
        self.tracking_check(ctx);
        self.video_poll(ctx);
    }

    /// Periodic work of the sensors: the messages at their intervals, changes.
    pub(super) fn sensors_poll(&mut self, ctx: &mut Ctx<'_>) {
        if self.sensors.thermal.due(ctx.now) && Self::measuring(ctx) {
            self.thermal_range(ctx);
        }
        if self.sensors.fov.due(ctx.now) {
            self.fov_status(ctx);
        }
        if self
            .sensors
            .fov_waits
            .is_some_and(|t| ctx.now >= t.saturating_add(TARGET_WAIT))
        {
            // The pod did not say where its laser points in time: computed.
            self.send_fov_status(ctx);
        }
        self.tracking_poll(ctx);
        self.sensors_frame(ctx);
    }

    /// When the sensors have work.
    pub(super) fn sensors_poll_at(&self) -> Option<Instant> {
        [
            self.sensors.thermal.at(),
            self.sensors.fov.at(),
            self.sensors
                .fov_waits
                .map(|t| t.saturating_add(TARGET_WAIT)),
            self.tracking.every.at(),
            self.video_poll_at(),
        ]
        .into_iter()
        .flatten()
        .min()
    }

    /// CAMERA_THERMAL_RANGE from the pod's last IR measurements.
    pub(super) fn thermal_range(&mut self, ctx: &mut Ctx<'_>) {
        let Some((ir, _)) = ctx.pod().ir else {
            return;
        };
        let IrStatus {
            max_temp_dc,
            min_temp_dc,
            max_x,
            max_y,
            min_x,
            min_y,
            ..
        } = ir;
        let (max_point_x, max_point_y) = ir_normalised(max_x, max_y);
        let (min_point_x, min_point_y) = ir_normalised(min_x, min_y);
        let msg = MavMessage::CAMERA_THERMAL_RANGE(CAMERA_THERMAL_RANGE_DATA {
            time_boot_ms: boot_ms(ctx),
            max: f32::from(max_temp_dc) / 10.0,
            max_point_x,
            max_point_y,
            min: f32::from(min_temp_dc) / 10.0,
            min_point_x,
            min_point_y,
            stream_id: super::video::STREAM_ID,
            camera_device_id: 0,
        });
        self.send(ctx, Comp::Camera, &msg);
    }

    /// DISTANCE_SENSOR of a reading (0.1 m).
    fn distance_sensor(&mut self, ctx: &mut Ctx<'_>, dm: u16) {
        let laser = ctx.config.laser;
        let cm = |v: u32| u16::try_from(v).unwrap_or(u16::MAX);
        // The gimbal's orientation against the body: its joint angles.
        let quaternion = ctx.fresh_attitude().map_or([0.0; 4], |a| {
            let r = |v: i16| math::rad(i32::from(v));
            math::quaternion([
                r(a.roll_joint_cdeg),
                r(a.pitch_joint_cdeg),
                r(a.yaw_joint_cdeg),
            ])
        });
        let msg = MavMessage::DISTANCE_SENSOR(DISTANCE_SENSOR_DATA {
            time_boot_ms: boot_ms(ctx),
            min_distance: cm(laser.min_distance_cm),
            max_distance: cm(laser.max_distance_cm),
            current_distance: cm(u32::from(dm).saturating_mul(10)),
            mavtype: MavDistanceSensor::MAV_DISTANCE_SENSOR_LASER,
            id: 0,
            orientation: MavSensorOrientation::MAV_SENSOR_ROTATION_CUSTOM,
            covariance: u8::MAX,
            horizontal_fov: 0.0,
            vertical_fov: 0.0,
            quaternion,
            signal_quality: 0,
        });
        self.send(ctx, Comp::Camera, &msg);
    }

    /// Asks the pod where its laser points, with the aircraft's state from its latest
    /// fix; false when it cannot be asked (no link, no position).
    fn ask_target(ctx: &mut Ctx<'_>) -> bool {
        let Some(f) = ctx.fixes.latest() else {
            return false;
        };
        if !ctx.pod().link || Self::aircraft(ctx).is_none() {
            return false;
        }
        let utc_ms = ctx
            .time
            .utc(f.at)
            .map_or(0, UtcTime::as_unix_millis_rounded);
        ctx.pod.request_target(ctx.now, &f, utc_ms, ctx.out);
        true
    }

    /// Where the camera looks, and whether it is known ([`look_at`]).
    fn looks_at(&self, ctx: &Ctx<'_>) -> LookAt {
        if let Some((t, at)) = ctx.pod().target
            && self.sensors.fov_waits.is_some_and(|asked| at >= asked)
        {
            return LookAt::At(Position {
                lat_e7: t.lat_e7,
                lon_e7: t.lon_e7,
                alt_mm: t.alt_mm,
            });
        }
        let (Some((here, rel_mm)), Some(a), Some(v)) = (
            Self::aircraft(ctx),
            ctx.fresh_attitude(),
            self.vehicle(ctx.now),
        ) else {
            return LookAt::Unknown;
        };
        let pitch = math::rad(i32::from(a.pitch_cdeg));
        let yaw = math::rad(math::wrap_cdeg(
            v.yaw.saturating_add(i32::from(a.yaw_joint_cdeg)),
        ));
        let range = ctx
            .pod()
            .laser_dm
            .filter(|(dm, at)| *dm > 0 && ctx.is_fresh(*at))
            .map(|(dm, _)| f32::from(dm) / 10.0);
        #[allow(clippy::cast_precision_loss)] // mm of height: exact enough
        let height = rel_mm as f32 / 1000.0;
        look_at(here, pitch, yaw, range, height)
    }

    /// CAMERA_FOV_STATUS (see the module documentation): the pod is asked where its laser
    /// points first, and the message waits for its answer.
    pub(super) fn fov_status(&mut self, ctx: &mut Ctx<'_>) {
        if self.sensors.fov_waits.is_some() {
            return;
        }
        if Self::ask_target(ctx) {
            self.sensors.fov_waits = Some(ctx.now);
        } else {
            self.send_fov_status(ctx);
        }
    }

    fn send_fov_status(&mut self, ctx: &mut Ctx<'_>) {
        let camera = Self::aircraft(ctx).map(|(p, _)| p);
        let image = match self.looks_at(ctx) {
            LookAt::At(p) => [p.lat_e7, p.lon_e7, p.alt_mm],
            LookAt::Sky => [i32::MIN; 3],
            LookAt::Unknown => [i32::MAX; 3],
        };
        let [lat_image, lon_image, alt_image] = image;
        let f = fov::current(&ctx.config.lens, ctx.pod());
        let msg = MavMessage::CAMERA_FOV_STATUS(CAMERA_FOV_STATUS_DATA {
            time_boot_ms: boot_ms(ctx),
            lat_camera: camera.map_or(i32::MAX, |p| p.lat_e7),
            lon_camera: camera.map_or(i32::MAX, |p| p.lon_e7),
            alt_camera: camera.map_or(i32::MAX, |p| p.alt_mm),
            lat_image,
            lon_image,
            alt_image,
            q: self.camera_attitude(ctx),
            hfov: f.h,
            vfov: f.v,
            camera_device_id: 0,
        });
        self.send(ctx, Comp::Camera, &msg);
        self.sensors.fov_waits = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ir_positions_are_normalised_to_the_thermal_picture() {
        assert_eq!(ir_normalised(320, 32), (0.0, 0.0));
        assert_eq!(ir_normalised(960, 544), (0.5, 0.5));
        assert_eq!(ir_normalised(1600, 1056), (1.0, 1.0));
        // In the black border: at the picture's edge.
        assert_eq!(ir_normalised(0, 1088), (0.0, 1.0));
        assert_eq!(ir_normalised(1280, 288), (0.75, 0.25));
    }
}
