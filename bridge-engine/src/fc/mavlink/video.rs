//! The video stream (component 100): the pod's one RTSP stream, as
//! VIDEO_STREAM_INFORMATION and VIDEO_STREAM_STATUS (docs/src/bridge/mavlink.md, "Video
//! stream").
//!
//! - **Address.** `video.uri` when configured, else `rtsp://IP:558/live/single` (K40T
//!   external protocol, 2.3.2) with the IP the pod tells on 0x000312 (asked at every
//!   link-up). Until one is known there is no stream: CAMERA_INFORMATION has no
//!   HAS_VIDEO_STREAM, requests of the stream's messages are TEMPORARILY_REJECTED.
//! - **One stream**, id 1 of 1, named "K40T", type RTSP; its count and id stay, its
//!   fields follow the pod: flags RUNNING while the pod reports, THERMAL while it streams
//!   the thermal picture (0x000003 streaming mode, set by 0x000318) and
//!   THERMAL_RANGE_ENABLED while it also measures (0x000004 comes); resolution, frame
//!   rate (0x000003's preview resolution: 1080p or 720p, 30 fps), encoding (H.264/H.265)
//!   and bitrate (1 to 12 Mbit/s) from 0x000003; the horizontal field of view at the
//!   current zoom ([`super::fov`]; 0: unknown).
//! - **Requests:** REQUEST_MESSAGE(269 or 270) with param2 0 (or NaN: MAVSDK on PX4) for
//!   every stream or 1, and the deprecated MAV_CMD_REQUEST_VIDEO_STREAM_INFORMATION and
//!   _STATUS (2504, 2505, param1 the stream); another stream id is DENIED. A
//!   VIDEO_STREAM_INFORMATION goes out unasked when the address becomes known and when it
//!   changes (MAVSDK 4.1 never asks for it), a VIDEO_STREAM_STATUS when the flags, the
//!   resolution or the field of view change (at most two a second).
//! - **Commands:** VIDEO_START_STREAMING and VIDEO_STOP_STREAMING (2502, 2503) for stream
//!   1 (or 0, all) are ACCEPTED at once: an RTSP stream is connection-based, the pod
//!   always serves it; another id is DENIED. MAV_CMD_SET_CAMERA_SOURCE (534): param2
//!   primary source 0 (default) or 1 (RGB): the visible picture, 2 (IR): the thermal one;
//!   a non-zero param3 (a secondary source, picture in picture): split screen; 0x000318,
//!   ACK after the pod's. NDVI (3) is not the pod's: UNSUPPORTED.

use crate::config::URI_LEN;
use crate::event::{Decline, Event};
use crate::fc::Ctx;
use crate::gimbal::{Command, View};
use crate::time::{Duration, Instant};
use protocol_core::k40t::{PreviewResolution, StreamBitrate, VideoCodec};
use protocol_core::mavlink::MavMessage;
use protocol_core::mavlink::dialect::{
    CharArray, VIDEO_STREAM_INFORMATION_DATA, VIDEO_STREAM_STATUS_DATA, VideoStreamEncoding,
    VideoStreamStatusFlags, VideoStreamType,
};

use super::gimbal::name;
use super::{Cmd, Comp, MavlinkSide, cmd, fov, id, param_is, result};

/// The stream's id (the only one).
pub(super) const STREAM_ID: u8 = 1;
/// The stream's name (QGroundControl lists streams by name).
const STREAM_NAME: &[u8] = b"K40T";
/// Least time between two unasked VIDEO_STREAM_STATUS.
const STATUS_SPACING: Duration = Duration::from_millis(500);

/// What an unasked VIDEO_STREAM_STATUS follows: flags, resolution, field of view.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Told {
    flags: u16,
    resolution: (u16, u16),
    hfov: u16,
}

/// Where the stream's address comes from (what an unasked VIDEO_STREAM_INFORMATION
/// follows).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Address {
    /// `video.uri`.
    Configured,
    /// The pod's IP (0x000312).
    Pod([u8; 4]),
}

/// The stream's state on the MAVLink side.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Video {
    /// The address the last VIDEO_STREAM_INFORMATION (asked or not) carried.
    told_address: Option<Address>,
    /// What the last VIDEO_STREAM_STATUS (asked or not) said.
    told: Option<Told>,
    /// When the last unasked one went.
    told_at: Option<Instant>,
    /// A change waits until then to be told.
    due: Option<Instant>,
}

/// The stream's fields now.
struct Stream {
    flags: VideoStreamStatusFlags,
    framerate: f32,
    resolution: (u16, u16),
    bitrate: u32,
    hfov: u16,
    encoding: VideoStreamEncoding,
}

/// A stream selector (param2 of REQUEST_MESSAGE, param1 of the others): 0 (all) or NaN
/// (not given) or the stream's id.
pub(super) fn is_our_stream(p: f32) -> bool {
    p.is_nan() || param_is(p, 0) || param_is(p, STREAM_ID)
}

/// Appends `bytes` at `len`.
fn put(uri: &mut [u8; URI_LEN], len: &mut usize, bytes: &[u8]) {
    for b in bytes {
        if let Some(slot) = uri.get_mut(*len) {
            *slot = *b;
            *len = len.saturating_add(1);
        }
    }
}

/// `rtsp://IP:558/live/single` (K40T external protocol, 2.3.2).
fn pod_uri(ip: [u8; 4]) -> [u8; URI_LEN] {
    let mut uri = [0u8; URI_LEN];
    let mut len = 0;
    put(&mut uri, &mut len, b"rtsp://");
    for (i, octet) in ip.into_iter().enumerate() {
        if i > 0 {
            put(&mut uri, &mut len, b".");
        }
        let digits = [octet / 100, octet / 10 % 10, octet % 10].map(|d| b'0'.wrapping_add(d));
        let skip = if octet >= 100 {
            0
        } else if octet >= 10 {
            1
        } else {
            2
        };
        put(&mut uri, &mut len, digits.get(skip..).unwrap_or_default());
    }
    put(&mut uri, &mut len, b":558/live/single");
    uri
}

impl MavlinkSide {
    /// Where the stream's address comes from, when known.
    fn stream_address(ctx: &Ctx<'_>) -> Option<Address> {
        if ctx.config.video.configured_uri().is_some() {
            return Some(Address::Configured);
        }
        ctx.pod().ip.map(Address::Pod)
    }

    /// The stream's address, when known.
    pub(super) fn stream_uri(ctx: &Ctx<'_>) -> Option<[u8; URI_LEN]> {
        match Self::stream_address(ctx)? {
            Address::Configured => Some(ctx.config.video.uri),
            Address::Pod(ip) => Some(pod_uri(ip)),
        }
    }

    fn stream(ctx: &Ctx<'_>) -> Stream {
        let pod = ctx.pod();
        let system = pod.system;
        let mut flags = VideoStreamStatusFlags::empty();
        if pod.link {
            flags |= VideoStreamStatusFlags::VIDEO_STREAM_STATUS_FLAGS_RUNNING;
        }
        if pod.view() == Some(View::Thermal) {
            flags |= VideoStreamStatusFlags::VIDEO_STREAM_STATUS_FLAGS_THERMAL;
            if Self::measuring(ctx) {
                flags |= VideoStreamStatusFlags::VIDEO_STREAM_STATUS_FLAGS_THERMAL_RANGE_ENABLED;
            }
        }
        let (resolution, framerate) = match system.map(|s| s.preview_resolution) {
            Some(PreviewResolution::P1080Fps30) => ((1920, 1080), 30.0),
            Some(PreviewResolution::P720Fps30) => ((1280, 720), 30.0),
            _ => ((0, 0), 0.0),
        };
        let bitrate = match system.map(|s| s.preview_bitrate) {
            Some(StreamBitrate::M1) => 1_000_000,
            Some(StreamBitrate::M1_5) => 1_500_000,
            Some(StreamBitrate::M2) => 2_000_000,
            Some(StreamBitrate::M4) => 4_000_000,
            Some(StreamBitrate::M8) => 8_000_000,
            Some(StreamBitrate::M12) => 12_000_000,
            _ => 0,
        };
        let encoding = match system.map(|s| s.preview_codec) {
            Some(VideoCodec::H264) => VideoStreamEncoding::VIDEO_STREAM_ENCODING_H264,
            Some(VideoCodec::H265) => VideoStreamEncoding::VIDEO_STREAM_ENCODING_H265,
            _ => VideoStreamEncoding::VIDEO_STREAM_ENCODING_UNKNOWN,
        };
        Stream {
            flags,
            framerate,
            resolution,
            bitrate,
            hfov: fov::current(&ctx.config.lens, pod).h_whole_deg(),
            encoding,
        }
    }

    /// VIDEO_STREAM_INFORMATION of the stream (its address known).
    pub(super) fn video_information(&mut self, ctx: &mut Ctx<'_>) {
        let Some(uri) = Self::stream_uri(ctx) else {
            return;
        };
        self.video.told_address = Self::stream_address(ctx);
        let s = Self::stream(ctx);
        let msg = MavMessage::VIDEO_STREAM_INFORMATION(VIDEO_STREAM_INFORMATION_DATA {
            framerate: s.framerate,
            bitrate: s.bitrate,
            flags: s.flags,
            resolution_h: s.resolution.0,
            resolution_v: s.resolution.1,
            rotation: 0,
            hfov: s.hfov,
            stream_id: STREAM_ID,
            count: 1,
            mavtype: VideoStreamType::VIDEO_STREAM_TYPE_RTSP,
            name: CharArray::from(name::<32>(STREAM_NAME)),
            uri: CharArray::from(uri),
            encoding: s.encoding,
            camera_device_id: 0,
        });
        self.send(ctx, Comp::Camera, &msg);
    }

    /// VIDEO_STREAM_STATUS of the stream.
    pub(super) fn video_status(&mut self, ctx: &mut Ctx<'_>) {
        let s = Self::stream(ctx);
        self.video.told = Some(Told {
            flags: s.flags.bits(),
            resolution: s.resolution,
            hfov: s.hfov,
        });
        let msg = MavMessage::VIDEO_STREAM_STATUS(VIDEO_STREAM_STATUS_DATA {
            framerate: s.framerate,
            bitrate: s.bitrate,
            flags: s.flags,
            resolution_h: s.resolution.0,
            resolution_v: s.resolution.1,
            rotation: 0,
            hfov: s.hfov,
            stream_id: STREAM_ID,
            camera_device_id: 0,
        });
        self.send(ctx, Comp::Camera, &msg);
    }

    /// A request of VIDEO_STREAM_INFORMATION or _STATUS (`arg`: the stream selector):
    /// the result, and the message after an ACCEPTED ACK.
    pub(super) fn video_request(&mut self, ctx: &mut Ctx<'_>, c: &Cmd, msg: u32, arg: f32) {
        let r = if !is_our_stream(arg) {
            self.refused(ctx, c.command, Decline::OtherDevice);
            result::DENIED
        } else if Self::stream_uri(ctx).is_none() {
            self.refused(ctx, c.command, Decline::NoStreamAddress);
            result::TEMPORARILY_REJECTED
        } else {
            result::ACCEPTED
        };
        self.ack(ctx, Comp::Camera, c.command, r, c.from);
        if r == result::ACCEPTED {
            if msg == id::VIDEO_STREAM_INFORMATION {
                self.video_information(ctx);
            } else {
                self.video_status(ctx);
            }
        }
    }

    /// MAV_CMD_SET_CAMERA_SOURCE, VIDEO_START_STREAMING and VIDEO_STOP_STREAMING (see the
    /// module documentation).
    pub(super) fn video_command(&mut self, ctx: &mut Ctx<'_>, c: &Cmd) {
        if c.command != cmd::SET_CAMERA_SOURCE {
            let r = if !is_our_stream(c.param(1)) {
                self.refused(ctx, c.command, Decline::OtherDevice);
                result::DENIED
            } else if Self::stream_uri(ctx).is_none() {
                self.refused(ctx, c.command, Decline::NoStreamAddress);
                result::DENIED
            } else {
                result::ACCEPTED
            };
            self.ack(ctx, Comp::Camera, c.command, r, c.from);
            return;
        }
        // param1: the camera (0 all, NaN not given, or this one).
        let device = c.param(1);
        if !(device.is_nan() || param_is(device, 0) || param_is(device, Comp::Camera.id())) {
            self.refused(ctx, c.command, Decline::OtherDevice);
            self.ack(ctx, Comp::Camera, c.command, result::DENIED, c.from);
            return;
        }
        let (primary, secondary) = (c.param(2), c.param(3));
        let split = secondary.is_finite() && !param_is(secondary, 0);
        let view = if param_is(primary, 0) || param_is(primary, 1) {
            Some(View::Visible)
        } else if param_is(primary, 2) {
            Some(View::Thermal)
        } else {
            None
        };
        let view = match view {
            Some(_) if split => View::Split,
            Some(v) => v,
            None if primary.is_nan() => {
                self.refused(ctx, c.command, Decline::NotGiven);
                self.ack(ctx, Comp::Camera, c.command, result::DENIED, c.from);
                return;
            }
            None => {
                self.ack(ctx, Comp::Camera, c.command, result::UNSUPPORTED, c.from);
                return;
            }
        };
        let base = ctx.command(c.command, Command::View(view));
        self.await_pod(ctx, c, base);
    }

    /// Tells unasked the stream's address when it becomes known or changes
    /// (VIDEO_STREAM_INFORMATION: MAVSDK 4.1 never asks for it, and builds its stream
    /// information from VIDEO_STREAM_STATUS, which has no address), and a change of its
    /// flags, resolution or field of view (VIDEO_STREAM_STATUS).
    pub(super) fn video_poll(&mut self, ctx: &mut Ctx<'_>) {
        let Some(address) = Self::stream_address(ctx) else {
            return;
        };
        if self.video.told_address != Some(address) {
            self.video_information(ctx);
        }
        let s = Self::stream(ctx);
        let now = Told {
            flags: s.flags.bits(),
            resolution: s.resolution,
            hfov: s.hfov,
        };
        match self.video.told {
            None => self.video.told = Some(now),
            Some(told) if told != now => {
                let at = self
                    .video
                    .told_at
                    .map_or(ctx.now, |t| t.saturating_add(STATUS_SPACING))
                    .max(ctx.now);
                if ctx.now >= at {
                    self.video.told_at = Some(ctx.now);
                    self.video.due = None;
                    self.video_status(ctx);
                } else {
                    self.video.due = Some(at);
                }
            }
            Some(_) => self.video.due = None,
        }
    }

    /// When a change waits to be told.
    pub(super) fn video_poll_at(&self) -> Option<Instant> {
        self.video.due
    }

    /// The thermal camera measures now (its 0x000004 comes).
    pub(super) fn measuring(ctx: &Ctx<'_>) -> bool {
        ctx.pod().link && ctx.pod().ir.is_some_and(|(_, at)| ctx.is_fresh(at))
    }

    /// An event saying the bridge refused `command`.
    pub(super) fn refused(&mut self, ctx: &mut Ctx<'_>, command: u16, reason: Decline) {
        let _ = self;
        ctx.out.event(Event::Declined {
            fc_id: command,
            reason,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pods_address_makes_the_rtsp_uri() {
        let uri = pod_uri([192, 168, 144, 64]);
        let len = uri.iter().position(|&b| b == 0).unwrap();
        assert_eq!(&uri[..len], b"rtsp://192.168.144.64:558/live/single");
        let uri = pod_uri([10, 0, 7, 255]);
        let len = uri.iter().position(|&b| b == 0).unwrap();
        assert_eq!(&uri[..len], b"rtsp://10.0.7.255:558/live/single");
        assert!(is_our_stream(f32::NAN) && is_our_stream(0.0) && is_our_stream(1.0));
        assert!(!is_our_stream(2.0));
    }
}
