//! The SIYI side: the bridge acts as a SIYI gimbal (a ZT30 by default) towards
//! ArduPilot's `AP_Mount_Siyi`.
//!
//! What ArduPilot needs, and what the bridge does (the mapping table:
//! docs/src/bridge/siyi.md):
//! - **Identity** (0x02 hardware id, 0x01 firmware, 0x20 codec specs of streams 0 and 1,
//!   0x0A configuration) is answered from [`Config`](crate::Config), the bridge's
//!   version (camera, gimbal and zoom firmware: [`crate::version`]) and the pod's
//!   state, at once, in the same `poll`. The configuration reports the record status
//!   from the pod, the motion mode ArduPilot last set (else ArduPilot re-sends its mode
//!   at every update) and a normal mounting direction.
//! - **Health**: 0x0D (attitude) is answered only while the pod reports its attitude;
//!   while the pod is lost the bridge does not answer it, exactly as a SIYI gimbal whose
//!   camera died, so ArduPilot marks the mount unhealthy within 1 s.
//! - **Motion**: 0x07 rates (100 = 90 °/s; yaw positive right, pitch positive up) go to
//!   the pod as rates; 0x0E angles, 0x08 centre, 0x0C lock/follow/FPV and tilt down.
//! - **Camera**: 0x0C photo and record toggle (resolved against the pod's recording
//!   state, so a toggle never inverts it), 0x05/0x0F zoom, 0x06/0x04 focus, 0x11 lens,
//!   0x1B/0x38 palette and gain; failures come back as 0x0B function feedback.
//! - **Time and position**: 0x22/0x3E `time_boot_ms` feed the FC clock, 0x30 the UTC
//!   offset (paired with a 0x22/0x3E of the same burst when there is one), 0x3E + 0x22 the
//!   fix history. The relative altitude of a fix is the MSL altitude above that of the
//!   first position received (SIYI carries no home altitude).
//!
//! Replies use CTRL = 2 and echo the request's sequence number; every reply fits
//! ArduPilot's 32-byte data limit and has the exact length it checks.

use crate::discipline::Sample;
use crate::fixes::Velocity;
use crate::gimbal::{Command, GimbalMode, Motion, Target, View};
use crate::pod::PodNotice;
use crate::time::{Duration, Instant};
use protocol_core::Direction;
use protocol_core::k40t::{self, GimbalAttitude as PodAttitude};
use protocol_core::siyi::{
    self, Angles, CameraFunctionType, CenterPosition, CodecSpecs, CurrentZoom, FeedbackInfo,
    FirmwareVersion, FirmwareVersions, FocusDirection, FunctionFeedback, GimbalAttitude,
    GimbalConfig, GimbalDataType, GimbalMode as SiyiGimbalMode, GimbalStreamAck, GlobalTemperature,
    HardwareId, Header, LaserDistance, MaxZoom, MessageData, MotionMode, MountDirection, OnOff,
    Packet, Palette as SiyiPalette, RecordStatus, Request, SetAnglesAck, SetStatus,
    SetStitchingAck, SetThermalGainAck, SetThermalOutputAck, SetThermalPaletteAck, SiyiFraming,
    Stitching, StitchingMode, StreamFrequency, StreamType, ThermalOutputMode, ThermalPalette,
    TimeAck, VideoEncoding, VideoOutput, ZoomDirection, ZoomLevel, ZoomRatio,
};

use super::{Ctx, FcHandler, Home, TimedFrom, clamp_i16};

/// Deframer buffer: ArduPilot's frames carry at most 32 data bytes (42-byte frames);
/// longer frames are not ArduPilot's and are rejected.
pub(crate) const BUF: usize = 64;

/// The Siyi side (its link, deframer and bursts, is [`FcLink`](super::FcLink)).
#[derive(Debug, Clone)]
pub(crate) struct SiyiSide {
    /// A 0x30 UTC value seen in the current burst, waiting for a 0x22/0x3E to pair with.
    burst_utc_us: Option<u64>,
    /// The motion mode ArduPilot last set (reported in 0x0A and 0x19).
    mode: MotionMode,
    /// The last aircraft attitude (0x22): roll, pitch, yaw in 0.01°.
    aircraft: Option<[i16; 3]>,
    /// MSL altitude of the first position, 0.1 m (the relative altitude's zero).
    home: Home,
    /// The attitude stream ArduPilot asked for with 0x25, and when it is next due.
    stream: Option<(Duration, Instant)>,
    /// Thermal raw output mode (accepted and reported; the K40T has no equivalent).
    thermal_output: ThermalOutputMode,
    /// Photo and record commands waiting for their pod ACK (for 0x0B on failure).
    photo_pending: bool,
    record_pending: bool,
    /// Sequence number of pushed frames (0x0B, streamed 0x0D).
    push_seq: u16,
    /// The FC's `time_boot_ms`, unwrapped across 2^32 ms (49.7 days).
    boot_ms: crate::time::BootMs,
}

impl SiyiSide {
    pub(crate) fn new() -> Self {
        SiyiSide {
            burst_utc_us: None,
            mode: MotionMode::Follow,
            aircraft: None,
            home: Home::default(),
            stream: None,
            thermal_output: ThermalOutputMode::default(),
            photo_pending: false,
            record_pending: false,
            push_seq: 0,
            boot_ms: crate::time::BootMs::default(),
        }
    }
}

impl FcHandler for SiyiSide {
    type Framing = SiyiFraming;
    const TIMED_FROM: TimedFrom = TimedFrom::Burst;

    fn frame(&mut self, ctx: &mut Ctx<'_>, f: &[u8]) {
        self.fc_frame(ctx, f);
    }

    /// The 0x30 waiting for a 0x22/0x3E to pair with belongs to the burst that ended.
    fn burst_started(&mut self) {
        self.burst_utc_us = None;
    }

    fn poll(&mut self, ctx: &mut Ctx<'_>) {
        if let Some((period, due)) = self.stream
            && ctx.now >= due
        {
            self.stream = Some((period, ctx.now.saturating_add(period)));
            let seq = self.next_push_seq();
            if let Some(a) = attitude(ctx) {
                send(ctx, &a, seq);
            }
        }
    }

    fn poll_at(&self) -> Option<Instant> {
        self.stream.map(|(_, due)| due)
    }

    fn pod_notice(&mut self, ctx: &mut Ctx<'_>, notice: PodNotice) {
        let (base, failed) = match notice {
            PodNotice::Acked { base, code } => (base, code != k40t::AckCode::Ok),
            PodNotice::TimedOut { base } => (base, true),
            _ => return,
        };
        let info = match base {
            0x0302 if core::mem::take(&mut self.photo_pending) => {
                failed.then_some(FeedbackInfo::PhotoFailed)
            }
            0x0303 if core::mem::take(&mut self.record_pending) => {
                failed.then_some(FeedbackInfo::RecordFailed)
            }
            _ => None,
        };
        if let Some(info) = info {
            let seq = self.next_push_seq();
            send(ctx, &FunctionFeedback { info }, seq);
        }
    }
}

/// Encodes a reply (CTRL = 2) and queues it for the FC.
fn send<M: MessageData<Protocol = protocol_core::siyi::Siyi>>(
    ctx: &mut Ctx<'_>,
    message: &M,
    seq: u16,
) {
    let mut buf = [0u8; BUF];
    if let Ok(n) = siyi::encode(message, &Header::reply(seq), &mut buf) {
        ctx.reply(buf.get(..n).unwrap_or_default());
    }
}

/// The 0x0D reply from the pod's attitude: yaw relative to the aircraft in SIYI's sign
/// convention (positive left), pitch and roll against the horizon; `None` when the pod
/// does not report its attitude.
fn attitude(ctx: &Ctx<'_>) -> Option<GimbalAttitude> {
    let a: PodAttitude = ctx.fresh_attitude()?;
    // 0.01° -> 0.1°.
    let d = |v: i16| v / 10;
    Some(GimbalAttitude {
        yaw_deg_x10: d(a.yaw_joint_cdeg).saturating_neg(),
        pitch_deg_x10: d(a.pitch_cdeg),
        roll_deg_x10: d(a.roll_cdeg),
        yaw_rate_dps_x10: d(a.yaw_rate_cdeg_s).saturating_neg(),
        pitch_rate_dps_x10: d(a.pitch_rate_cdeg_s),
        roll_rate_dps_x10: d(a.roll_rate_cdeg_s),
    })
}

/// SIYI thermal palettes and the K40T ones closest to them.
const PALETTES: [(SiyiPalette, k40t::Palette); 11] = [
    (SiyiPalette::WhiteHot, k40t::Palette::WhiteHot),
    (SiyiPalette::Sepia, k40t::Palette::GrayRed),
    (SiyiPalette::Ironbow, k40t::Palette::IronRed),
    (SiyiPalette::Rainbow, k40t::Palette::Rainbow),
    (SiyiPalette::Night, k40t::Palette::MediumGray),
    (SiyiPalette::Aurora, k40t::Palette::PurpleOrange),
    (SiyiPalette::RedHot, k40t::Palette::HighContrastRed),
    (SiyiPalette::Jungle, k40t::Palette::GradientGreen),
    (SiyiPalette::Medical, k40t::Palette::Magma),
    (SiyiPalette::BlackHot, k40t::Palette::BlackHot),
    (SiyiPalette::GloryHot, k40t::Palette::IceFire),
];

impl SiyiSide {
    fn next_push_seq(&mut self) -> u16 {
        let s = self.push_seq;
        self.push_seq = self.push_seq.wrapping_add(1);
        s
    }

    /// One valid frame from the FC.
    fn fc_frame(&mut self, ctx: &mut Ctx<'_>, f: &[u8]) {
        let Ok(packet) = Packet::decode(f, Direction::ToGimbal) else {
            ctx.seen();
            ctx.ignored();
            return;
        };
        ctx.seen();
        let Some(request) = (match packet.message {
            siyi::Message::Request(r) => Some(r),
            _ => None,
        }) else {
            ctx.ignored();
            return;
        };
        self.request(ctx, request, packet.header.seq);
    }

    /// The sample of a time value that came with this frame: read before its burst's
    /// first byte went out, `now` minus the burst's serial time so far.
    fn sample(ctx: &Ctx<'_>, value_us: u64, resolution_us: u32) -> Sample {
        Sample::new(ctx.now, value_us, resolution_us).with_transit(ctx.transit)
    }

    fn fc_clock(&mut self, ctx: &mut Ctx<'_>, time_boot_ms: u32) {
        let utc = self.burst_utc_us.take();
        if !ctx.feeds {
            return;
        }
        let boot_ms = self.boot_ms.unwrap(time_boot_ms, ctx.now);
        let s = Self::sample(ctx, boot_ms.saturating_mul(1000), 1000);
        ctx.time.fc_clock_sample(s);
        if let Some(utc) = utc {
            ctx.time.utc_fc_pair(utc, boot_ms);
        }
    }

    #[allow(clippy::too_many_lines)] // one arm per command id, each short
    fn request(&mut self, ctx: &mut Ctx<'_>, request: Request, seq: u16) {
        let id = u16::from(request.id());
        match request {
            Request::Heartbeat(_) => {}
            Request::FirmwareVersion(_) => {
                // The bridge's version as the camera's, the gimbal's and the zoom's.
                let v = ctx.build.version;
                let v = FirmwareVersion::new(v.major, v.minor, v.patch);
                let versions = FirmwareVersions {
                    camera: v,
                    gimbal: v,
                    zoom: Some(v),
                };
                send(ctx, &versions, seq);
            }
            Request::HardwareId(_) => {
                let id = HardwareId {
                    raw: ctx.config.siyi.hardware_id,
                };
                send(ctx, &id, seq);
            }
            Request::GetCodec(q) => {
                let h265 = ctx
                    .pod()
                    .system
                    .is_some_and(|s| s.preview_codec == k40t::VideoCodec::H265);
                let specs = CodecSpecs {
                    stream: q.stream,
                    encoding: if h265 {
                        VideoEncoding::H265
                    } else {
                        VideoEncoding::H264
                    },
                    width: 1920,
                    height: 1080,
                    bitrate_kbps: if q.stream == StreamType::Record {
                        8000
                    } else {
                        4000
                    },
                    fps: Some(30),
                };
                send(ctx, &specs, seq);
            }
            Request::GimbalConfig(_) => {
                let pod = ctx.pod();
                let record = if pod.is_recording() {
                    RecordStatus::On
                } else if pod.system.is_some_and(|s| s.sd == k40t::SdState::Missing) {
                    RecordStatus::NoCard
                } else {
                    RecordStatus::Off
                };
                let config = GimbalConfig {
                    reserved0: 0,
                    hdr: OnOff::Off,
                    reserved2: 0,
                    record,
                    motion: self.mode,
                    mount: Some(MountDirection::Normal),
                    video_output: Some(VideoOutput::Hdmi),
                    zoom_linkage: None,
                };
                send(ctx, &config, seq);
            }
            Request::GimbalAttitude(_) => {
                if let Some(a) = attitude(ctx) {
                    send(ctx, &a, seq);
                }
            }
            Request::GimbalRotation(r) => {
                // 100 = 90 °/s: one unit is 90 (0.01 °/s).
                ctx.command(
                    id,
                    Command::Rates {
                        yaw_cdeg_s: i32::from(r.yaw.clamp(-100, 100)).saturating_mul(90),
                        pitch_cdeg_s: i32::from(r.pitch.clamp(-100, 100)).saturating_mul(90),
                    },
                );
            }
            Request::SetAngles(a) => {
                // The angles are in 0x0D's convention: yaw positive left.
                ctx.command(
                    id,
                    Command::Angles {
                        yaw_cdeg: i32::from(a.yaw_deg_x10).saturating_mul(-10),
                        pitch_cdeg: i32::from(a.pitch_deg_x10).saturating_mul(10),
                    },
                );
                let now = attitude(ctx).map_or(Angles::default(), |g| Angles {
                    yaw_deg_x10: g.yaw_deg_x10,
                    pitch_deg_x10: g.pitch_deg_x10,
                    roll_deg_x10: g.roll_deg_x10,
                });
                send(ctx, &SetAnglesAck(now), seq);
            }
            Request::Center(c) => {
                let cmd = match c.position {
                    CenterPosition::CenterDown | CenterPosition::Down => Command::LookDown,
                    _ => Command::Center,
                };
                ctx.command(id, cmd);
                send(ctx, &siyi::CenterAck(SetStatus::SUCCESS), seq);
            }
            Request::CameraFunction(f) => self.camera_function(ctx, id, f.function),
            Request::ManualZoom(z) => {
                let m = match z.direction {
                    ZoomDirection::In => Motion::In,
                    ZoomDirection::Out => Motion::Out,
                    _ => Motion::Stop,
                };
                ctx.command(id, Command::Zoom(m));
                let zoom = ZoomRatio {
                    zoom_x10: ctx.pod().zoom_x10().min(ctx.config.siyi.max_zoom_x10),
                };
                send(ctx, &zoom, seq);
            }
            Request::AbsoluteZoom(z) => {
                ctx.command(
                    id,
                    Command::ZoomTo {
                        zoom_x10: z.0.zoom_x10(),
                    },
                );
                send(ctx, &siyi::AbsoluteZoomAck(SetStatus::SUCCESS), seq);
            }
            Request::MaxZoom(_) => {
                let max =
                    ZoomLevel::from_zoom_x10(ctx.config.siyi.max_zoom_x10).unwrap_or_default();
                send(ctx, &MaxZoom(max), seq);
            }
            Request::CurrentZoom(_) => {
                let now = ZoomLevel::from_zoom_x10(ctx.pod().zoom_x10()).unwrap_or_default();
                send(ctx, &CurrentZoom(now), seq);
            }
            Request::ManualFocus(f) => {
                let m = match f.direction {
                    FocusDirection::Far => Motion::In,
                    FocusDirection::Near => Motion::Out,
                    _ => Motion::Stop,
                };
                ctx.command(id, Command::Focus(m));
                send(ctx, &siyi::ManualFocusAck(SetStatus::SUCCESS), seq);
            }
            Request::AutoFocus(a) => {
                let target = (a.start == 1).then_some(Target::Point { x: a.x, y: a.y });
                ctx.command(id, Command::AutoFocus(target));
                send(ctx, &siyi::AutoFocusAck(SetStatus::SUCCESS), seq);
            }
            Request::GetStitching(_) => {
                send(ctx, &stitching(ctx), seq);
            }
            Request::SetStitching(s) => {
                let view = match s.0.mode {
                    StitchingMode::PipZoomThermalSubWide | StitchingMode::PipWideThermalSubZoom => {
                        View::Split
                    }
                    StitchingMode::ThermalSubZoom | StitchingMode::ThermalSubWide => View::Thermal,
                    _ => View::Visible,
                };
                ctx.command(id, Command::View(view));
                send(ctx, &SetStitchingAck(s.0), seq);
            }
            Request::GlobalTemperature(_) => {
                if let Some(t) = thermal(ctx) {
                    send(ctx, &t, seq);
                }
            }
            Request::LaserDistance(_) => {
                // ArduPilot polls this at 10 Hz on a ZT30: keep the pod ranging (asked
                // again once its link is back: a rebooted pod has forgotten it).
                if !ctx.pod().ranging && ctx.pod().link {
                    ctx.command(id, Command::Laser(crate::gimbal::Ranging::Continuous));
                }
                let fresh = ctx.pod().laser_dm.filter(|(_, at)| ctx.is_fresh(*at));
                let distance_dm = fresh.map_or(0, |(d, _)| d);
                send(ctx, &LaserDistance { distance_dm }, seq);
            }
            Request::GimbalMode(_) => {
                send(ctx, &SiyiGimbalMode { mode: self.mode }, seq);
            }
            Request::GetThermalPalette(_) => {
                send(
                    ctx,
                    &ThermalPalette {
                        palette: SiyiPalette::WhiteHot,
                    },
                    seq,
                );
            }
            Request::SetThermalPalette(p) => {
                if let Some(&(_, k)) = PALETTES.iter().find(|(s, _)| *s == p.0.palette) {
                    ctx.command(id, Command::Palette(k));
                }
                send(ctx, &SetThermalPaletteAck(p.0), seq);
            }
            Request::SetThermalGain(g) => {
                ctx.command(id, Command::ThermalHighGain(g.0.gain == siyi::Gain::High));
                send(ctx, &SetThermalGainAck(g.0), seq);
            }
            Request::SetThermalOutput(m) => {
                // Raw temperature frames: the K40T has no such output; accepted.
                self.thermal_output = m.0;
                send(ctx, &SetThermalOutputAck(m.0), seq);
            }
            Request::GetThermalOutput(_) => {
                send(ctx, &self.thermal_output, seq);
            }
            Request::FcAttitude(a) => {
                self.fc_clock(ctx, a.time_boot_ms);
                self.aircraft = Some([
                    rad_to_cdeg(a.roll_rad),
                    rad_to_cdeg(a.pitch_rad),
                    rad_to_cdeg(a.yaw_rad),
                ]);
            }
            Request::FcPosition(p) => {
                self.fc_clock(ctx, p.time_boot_ms);
                let velocity = Velocity::from_cm_s(
                    p.vel_north_mm_s / 10,
                    p.vel_east_mm_s / 10,
                    p.vel_down_mm_s / 10,
                );
                let fix = self.home.fix(
                    ctx.now.saturating_sub(ctx.transit),
                    (p.lat_e7, p.lon_e7, p.alt_msl_cm / 10),
                    self.aircraft.unwrap_or_default(),
                    velocity,
                );
                ctx.push_fix(fix);
            }
            Request::SetUtcTime(t) => {
                if ctx.feeds {
                    let s = Self::sample(ctx, t.unix_us, 1);
                    ctx.time.utc_via_fc_sample(s);
                }
                self.burst_utc_us = Some(t.unix_us);
                send(ctx, &TimeAck { result: 1 }, seq);
            }
            Request::GimbalDataStream(r) => {
                if r.data_type == GimbalDataType::Attitude {
                    self.stream = stream_period(r.frequency).map(|p| (p, ctx.now));
                }
                send(
                    ctx,
                    &GimbalStreamAck {
                        data_type: r.data_type,
                    },
                    seq,
                );
            }
            _ => {
                // The K40T has no equivalent, and ArduPilot does not send it: ignored,
                // as SIYI gimbals ignore what they do not support.
                ctx.ignored();
            }
        }
    }

    fn camera_function(&mut self, ctx: &mut Ctx<'_>, id: u16, f: CameraFunctionType) {
        match f {
            CameraFunctionType::TakePhoto => {
                self.photo_pending = ctx.command(id, Command::TakePhoto).is_some();
            }
            CameraFunctionType::RecordToggle => {
                // A toggle against the pod's own state: it never inverts it.
                let start = !ctx.pod().is_recording();
                self.record_pending = ctx.command(id, Command::Record(start)).is_some();
            }
            CameraFunctionType::LockMode => self.set_mode(ctx, id, MotionMode::Lock),
            CameraFunctionType::FollowMode => self.set_mode(ctx, id, MotionMode::Follow),
            CameraFunctionType::FpvMode => self.set_mode(ctx, id, MotionMode::Fpv),
            CameraFunctionType::TiltDownward => {
                ctx.command(id, Command::LookDown);
            }
            _ => ctx.ignored(),
        }
    }

    fn set_mode(&mut self, ctx: &mut Ctx<'_>, id: u16, mode: MotionMode) {
        self.mode = mode;
        let m = match mode {
            MotionMode::Lock => GimbalMode::Lock,
            MotionMode::Fpv => GimbalMode::Fpv,
            _ => GimbalMode::Follow,
        };
        ctx.command(id, Command::Mode(m));
    }
}

/// The 0x10 reply from the streamed view.
fn stitching(ctx: &Ctx<'_>) -> Stitching {
    let mode = match ctx.pod().view() {
        Some(View::Thermal) => StitchingMode::ThermalSubZoom,
        Some(View::Split) => StitchingMode::PipZoomThermalSubWide,
        _ => StitchingMode::ZoomSubThermal,
    };
    Stitching { mode }
}

/// The 0x14 reply from the pod's infrared measurements, when fresh: temperatures from
/// 0.1 °C to 0.01 °C, as the i16 `AP_Mount_Siyi` reads (saturated at ±327.67 °C, sent as
/// the u16 of the document); positions as a ZT30 gives them, in pixels of its 640 × 512
/// thermal picture: the pod's IR coordinates less the picture's border (320, 32), halved
/// (the 1920 × 1088 frame shows the 640 × 512 picture at twice its size:
/// docs/src/protocols/k40t.md).
fn thermal(ctx: &Ctx<'_>) -> Option<GlobalTemperature> {
    let (ir, _) = ctx.pod().ir.filter(|(_, at)| ctx.is_fresh(*at))?;
    let c = |dc: i16| u16::from_ne_bytes(dc.saturating_mul(10).to_ne_bytes());
    let px =
        |v: u16, border: u16, len: u16| (v.saturating_sub(border) / 2).min(len.saturating_sub(1));
    Some(GlobalTemperature {
        max_c_x100: c(ir.max_temp_dc),
        min_c_x100: c(ir.min_temp_dc),
        max_x: px(ir.max_x, 320, 640),
        max_y: px(ir.max_y, 32, 512),
        min_x: px(ir.min_x, 320, 640),
        min_y: px(ir.min_y, 32, 512),
    })
}

/// The period of a 0x25 stream frequency (`None`: off).
fn stream_period(f: StreamFrequency) -> Option<Duration> {
    let ms = match f {
        StreamFrequency::Hz2 => 500,
        StreamFrequency::Hz4 => 250,
        StreamFrequency::Hz5 => 200,
        StreamFrequency::Hz10 => 100,
        StreamFrequency::Hz20 => 50,
        StreamFrequency::Hz50 => 20,
        StreamFrequency::Hz100 => 10,
        _ => return None,
    };
    Some(Duration::from_millis(ms))
}

/// Radians to 0.01°, wrapped to ±180°.
#[allow(clippy::cast_possible_truncation)] // a float-to-int `as` saturates; then wrapped
fn rad_to_cdeg(rad: f32) -> i16 {
    if !rad.is_finite() {
        return 0;
    }
    let cdeg = (rad * (18_000.0 / core::f32::consts::PI)) as i32;
    clamp_i16(
        cdeg.saturating_add(18_000)
            .rem_euclid(36_000)
            .saturating_sub(18_000),
    )
}
