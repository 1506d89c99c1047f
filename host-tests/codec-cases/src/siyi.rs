//! SIYI codec cases.
//!
//! The layout table is written from the document's tables (and `siyi-commands.md`
//! where the document lost an id), not from the codec: each entry is the data of one
//! command in one direction, with distinct values per field, little-endian, and the
//! message it must decode to. Frames around the data are built here with a bit-by-bit
//! CRC-16/XMODEM written for the tests, independently of the codec.

use crate::oracle::xmodem_bitwise as xmodem;
use crate::{Failure, Outcome};
use protocol_core::Error;
use protocol_core::siyi::*;
use protocol_core::wire::{Deframer, Event};

type Bytes = heapless::Vec<u8, 64>;

/// A frame `55 66 CTRL LEN SEQ CMD DATA CRC`.
fn frame(ctrl: u8, seq: u16, cmd: u8, data: &[u8]) -> Bytes {
    let mut f = Bytes::new();
    let len = (data.len() as u16).to_le_bytes();
    let seq = seq.to_le_bytes();
    let _ = f.extend_from_slice(&[0x55, 0x66, ctrl, len[0], len[1], seq[0], seq[1], cmd]);
    let _ = f.extend_from_slice(data);
    let crc = xmodem(&f).to_le_bytes();
    let _ = f.extend_from_slice(&crc);
    f
}

/// The CTRL a sender of this direction uses (ArduPilot: 1; SIYI gimbals: 2).
fn ctrl_of(dir: Direction) -> u8 {
    match dir {
        Direction::ToGimbal => 0x01,
        Direction::FromGimbal => 0x02,
    }
}

/// The data of one command in one direction, and the message it means.
struct Layout {
    dir: Direction,
    cmd: u8,
    data: &'static [u8],
    expected: fn() -> Message<'static>,
}

fn q(r: Request) -> Message<'static> {
    Message::Request(r)
}
fn p(r: Reply) -> Message<'static> {
    Message::Reply(r)
}

macro_rules! layouts {
    ($($dir:ident $cmd:literal [$($b:expr),* $(,)?] => $e:expr;)*) => {
        &[$( Layout { dir: Direction::$dir, cmd: $cmd, data: &[$($b),*], expected: || $e }, )*]
    };
}

const OK: SetStatus = SetStatus {
    status: AckStatus::Success,
};

fn fw(major: u8, minor: u8, patch: u8) -> FirmwareVersion {
    FirmwareVersion {
        patch,
        minor,
        major,
        ignored: 0,
    }
}

#[rustfmt::skip]
static LAYOUTS: &[Layout] = layouts! {
    ToGimbal 0x00 [0x00] => q(Request::Heartbeat(Heartbeat { byte: Some(0) }));
    ToGimbal 0x00 [] => q(Request::Heartbeat(Heartbeat { byte: None }));
    FromGimbal 0x00 [] => p(Reply::Heartbeat(HeartbeatReply {}));
    ToGimbal 0x01 [] => q(Request::FirmwareVersion(FirmwareVersionQuery {}));
    // The document's example word 0x6E030203 = v3.2.3, high byte ignored (and kept).
    FromGimbal 0x01 [0x03, 0x02, 0x03, 0x6E, 0x01, 0x02, 0x00, 0x00, 0x09, 0x04, 0x01, 0x00]
        => p(Reply::FirmwareVersion(FirmwareVersions {
            camera: FirmwareVersion { patch: 3, minor: 2, major: 3, ignored: 0x6E },
            gimbal: fw(0, 2, 1), zoom: Some(fw(1, 4, 9)) }));
    FromGimbal 0x01 [0x05, 0x01, 0x00, 0x00, 0x07, 0x03, 0x00, 0x00]
        => p(Reply::FirmwareVersion(FirmwareVersions { camera: fw(0, 1, 5), gimbal: fw(0, 3, 7), zoom: None }));
    ToGimbal 0x02 [] => q(Request::HardwareId(HardwareIdQuery {}));
    FromGimbal 0x02 [b'7', b'A', b'0', b'1', b'2', b'3', b'4', b'5', b'6', b'7', b'8', b'9']
        => p(Reply::HardwareId(HardwareId { raw: *b"7A0123456789" }));
    ToGimbal 0x04 [0x01, 0xC0, 0x03, 0x1C, 0x02] => q(Request::AutoFocus(AutoFocus { start: 1, x: 960, y: 540 }));
    FromGimbal 0x04 [0x01] => p(Reply::AutoFocus(AutoFocusAck(OK)));
    ToGimbal 0x05 [0xFF] => q(Request::ManualZoom(ManualZoom { direction: ZoomDirection::Out }));
    FromGimbal 0x05 [0x2D, 0x00] => p(Reply::ManualZoom(ZoomRatio { zoom_x10: 45 }));
    ToGimbal 0x06 [0x01] => q(Request::ManualFocus(ManualFocus { direction: FocusDirection::Far }));
    FromGimbal 0x06 [0x00] => p(Reply::ManualFocus(ManualFocusAck(SetStatus { status: AckStatus::Failed })));
    ToGimbal 0x07 [0x64, 0x9C] => q(Request::GimbalRotation(GimbalRotation { yaw: 100, pitch: -100 }));
    FromGimbal 0x07 [0x01] => p(Reply::GimbalRotation(GimbalRotationAck(OK)));
    ToGimbal 0x08 [0x02] => q(Request::Center(Center { position: CenterPosition::CenterDown }));
    FromGimbal 0x08 [0x01] => p(Reply::Center(CenterAck(OK)));
    ToGimbal 0x0A [] => q(Request::GimbalConfig(GimbalConfigQuery {}));
    FromGimbal 0x0A [0xA5, 0x01, 0x5A, 0x03, 0x02, 0x02, 0x01, 0x01] => p(Reply::GimbalConfig(GimbalConfig {
        reserved0: 0xA5, hdr: OnOff::On, reserved2: 0x5A, record: RecordStatus::DataLoss,
        motion: MotionMode::Fpv, mount: Some(MountDirection::UpsideDown),
        video_output: Some(VideoOutput::Cvbs), zoom_linkage: Some(1) }));
    ToGimbal 0x0B [] => q(Request::FunctionFeedback(FunctionFeedbackRequest {}));
    FromGimbal 0x0B [0x05] => p(Reply::FunctionFeedback(FunctionFeedback { info: FeedbackInfo::RecordStarted }));
    ToGimbal 0x0C [0x02] => q(Request::CameraFunction(CameraFunction { function: CameraFunctionType::RecordToggle }));
    FromGimbal 0x0C [] => p(Reply::CameraFunction(CameraFunctionReply {}));
    ToGimbal 0x0D [] => q(Request::GimbalAttitude(GimbalAttitudeQuery {}));
    FromGimbal 0x0D [0x77, 0xFC, 0xFA, 0x00, 0xF4, 0xFF, 0x2C, 0x01, 0xFF, 0xFF, 0x07, 0x00]
        => p(Reply::GimbalAttitude(GimbalAttitude {
            yaw_deg_x10: -905, pitch_deg_x10: 250, roll_deg_x10: -12,
            yaw_rate_dps_x10: 300, pitch_rate_dps_x10: -1, roll_rate_dps_x10: 7 }));
    ToGimbal 0x0E [0x5D, 0x02, 0x7C, 0xFC] => q(Request::SetAngles(SetAngles { yaw_deg_x10: 605, pitch_deg_x10: -900 }));
    FromGimbal 0x0E [0x5D, 0x02, 0x7C, 0xFC, 0x0A, 0x00]
        => p(Reply::SetAngles(SetAnglesAck(Angles { yaw_deg_x10: 605, pitch_deg_x10: -900, roll_deg_x10: 10 })));
    ToGimbal 0x0F [0x04, 0x05] => q(Request::AbsoluteZoom(AbsoluteZoom(ZoomLevel { integer: 4, tenths: 5 })));
    FromGimbal 0x0F [0x01] => p(Reply::AbsoluteZoom(AbsoluteZoomAck(OK)));
    ToGimbal 0x10 [] => q(Request::GetStitching(GetStitching {}));
    FromGimbal 0x10 [0x07] => p(Reply::GetStitching(Stitching { mode: StitchingMode::ThermalSubZoom }));
    ToGimbal 0x11 [0x03] => q(Request::SetStitching(SetStitching(Stitching { mode: StitchingMode::ZoomSubThermal })));
    FromGimbal 0x11 [0x08] => p(Reply::SetStitching(SetStitchingAck(Stitching { mode: StitchingMode::ThermalSubWide })));
    ToGimbal 0x12 [0x40, 0x01, 0x00, 0x01, 0x02] => q(Request::PointTemperature(PointTemperatureRequest {
        x: 320, y: 256, flag: MeasureFlag::Continuous }));
    FromGimbal 0x12 [0xC4, 0x09, 0x40, 0x01, 0x00, 0x01] => p(Reply::PointTemperature(PointTemperature {
        temp_c_x100: 2500, x: 320, y: 256 }));
    ToGimbal 0x13 [0x0A, 0x00, 0x14, 0x00, 0x1E, 0x00, 0x28, 0x00, 0x01] => q(Request::BoxTemperature(BoxTemperatureRequest {
        start_x: 10, start_y: 20, end_x: 30, end_y: 40, flag: MeasureFlag::Once }));
    FromGimbal 0x13 [0x0A, 0x00, 0x14, 0x00, 0x1E, 0x00, 0x28, 0x00, 0x10, 0x27, 0xE8, 0x03,
                0x0F, 0x00, 0x19, 0x00, 0x0B, 0x00, 0x15, 0x00] => p(Reply::BoxTemperature(BoxTemperature {
        start_x: 10, start_y: 20, end_x: 30, end_y: 40, max_c_x100: 10000, min_c_x100: 1000,
        max_x: 15, max_y: 25, min_x: 11, min_y: 21 }));
    ToGimbal 0x14 [0x02] => q(Request::GlobalTemperature(GlobalTemperatureRequest { flag: MeasureFlag::Continuous }));
    FromGimbal 0x14 [0x50, 0xC3, 0xD0, 0x07, 0x80, 0x02, 0x00, 0x02, 0x01, 0x00, 0x02, 0x00]
        => p(Reply::GlobalTemperature(GlobalTemperature {
            max_c_x100: 50000, min_c_x100: 2000, max_x: 640, max_y: 512, min_x: 1, min_y: 2 }));
    ToGimbal 0x15 [] => q(Request::LaserDistance(LaserDistanceQuery {}));
    FromGimbal 0x15 [0xF4, 0x01] => p(Reply::LaserDistance(LaserDistance { distance_dm: 500 }));
    ToGimbal 0x16 [] => q(Request::MaxZoom(MaxZoomQuery {}));
    FromGimbal 0x16 [0x1E, 0x00] => p(Reply::MaxZoom(MaxZoom(ZoomLevel { integer: 30, tenths: 0 })));
    ToGimbal 0x17 [] => q(Request::LaserTarget(LaserTargetQuery {}));
    FromGimbal 0x17 [0xC0, 0xB9, 0xA6, 0x43, 0x40, 0x3A, 0x69, 0x0D]
        => p(Reply::LaserTarget(LaserTarget { lon_e7: 1_135_000_000, lat_e7: 225_000_000 }));
    ToGimbal 0x18 [] => q(Request::CurrentZoom(CurrentZoomQuery {}));
    FromGimbal 0x18 [0x02, 0x03] => p(Reply::CurrentZoom(CurrentZoom(ZoomLevel { integer: 2, tenths: 3 })));
    ToGimbal 0x19 [] => q(Request::GimbalMode(GimbalModeQuery {}));
    FromGimbal 0x19 [0x01] => p(Reply::GimbalMode(GimbalMode { mode: MotionMode::Follow }));
    ToGimbal 0x1A [] => q(Request::GetThermalPalette(GetThermalPalette {}));
    FromGimbal 0x1A [0x03] => p(Reply::GetThermalPalette(ThermalPalette { palette: Palette::Ironbow }));
    ToGimbal 0x1B [0x0B] => q(Request::SetThermalPalette(SetThermalPalette(ThermalPalette { palette: Palette::GloryHot })));
    FromGimbal 0x1B [0x0A] => p(Reply::SetThermalPalette(SetThermalPaletteAck(ThermalPalette { palette: Palette::BlackHot })));
    ToGimbal 0x20 [0x01] => q(Request::GetCodec(CodecQuery { stream: StreamType::Main }));
    FromGimbal 0x20 [0x01, 0x02, 0x80, 0x07, 0x38, 0x04, 0xA0, 0x0F, 0x1E] => p(Reply::GetCodec(CodecSpecs {
        stream: StreamType::Main, encoding: VideoEncoding::H265, width: 1920, height: 1080,
        bitrate_kbps: 4000, fps: Some(30) }));
    FromGimbal 0x20 [0x00, 0x01, 0x00, 0x0F, 0x70, 0x08, 0x40, 0x1F] => p(Reply::GetCodec(CodecSpecs {
        stream: StreamType::Record, encoding: VideoEncoding::H264, width: 3840, height: 2160,
        bitrate_kbps: 8000, fps: None }));
    ToGimbal 0x21 [0x02, 0x01, 0x00, 0x05, 0xD0, 0x02, 0xE8, 0x03, 0x00] => q(Request::SetCodec(SetCodec {
        stream: StreamType::Sub, encoding: VideoEncoding::H264, width: 1280, height: 720,
        bitrate_kbps: 1000, reserved: 0 }));
    FromGimbal 0x21 [0x02, 0x01] => p(Reply::SetCodec(SetCodecAck { stream: StreamType::Sub, status: AckStatus::Success }));
    ToGimbal 0x22 [0x40, 0xE2, 0x01, 0x00, 0x00, 0x00, 0x00, 0x3F, 0x00, 0x00, 0x80, 0xBE, 0x00, 0x00, 0x40, 0x40,
                  0x00, 0x00, 0x00, 0x3E, 0x00, 0x00, 0x80, 0xBF, 0x00, 0x00, 0x00, 0x40] => q(Request::FcAttitude(FcAttitude {
        time_boot_ms: 123_456, roll_rad: 0.5, pitch_rad: -0.25, yaw_rad: 3.0,
        roll_rate_rad_s: 0.125, pitch_rate_rad_s: -1.0, yaw_rate_rad_s: 2.0 }));
    FromGimbal 0x22 [] => p(Reply::FcAttitude(FcAttitudeReply {}));
    ToGimbal 0x24 [0x01, 0x04] => q(Request::FcDataStream(FcStreamRequest {
        data_type: FcDataType::Attitude, frequency: StreamFrequency::Hz10 }));
    FromGimbal 0x24 [0x01] => p(Reply::FcDataStream(FcStreamAck { data_type: FcDataType::Attitude }));
    ToGimbal 0x25 [0x02, 0x07] => q(Request::GimbalDataStream(GimbalStreamRequest {
        data_type: GimbalDataType::Laser, frequency: StreamFrequency::Hz100 }));
    FromGimbal 0x25 [0x03] => p(Reply::GimbalDataStream(GimbalStreamAck { data_type: GimbalDataType::MagneticEncoder }));
    ToGimbal 0x26 [] => q(Request::MagneticEncoder(MagneticEncoderQuery {}));
    FromGimbal 0x26 [0xE8, 0x03, 0x38, 0xFF, 0x05, 0x00]
        => p(Reply::MagneticEncoder(MagneticEncoder(Angles { yaw_deg_x10: 1000, pitch_deg_x10: -200, roll_deg_x10: 5 })));
    ToGimbal 0x30 [0x00, 0x40, 0x20, 0x46, 0x48, 0x47, 0x06, 0x00]
        => q(Request::SetUtcTime(UtcTime { unix_us: 1_767_225_600_000_000 }));
    FromGimbal 0x30 [0x01] => p(Reply::SetUtcTime(TimeAck { result: 1 }));
    ToGimbal 0x31 [] => q(Request::GetLaserState(GetLaserState {}));
    FromGimbal 0x31 [0x01] => p(Reply::GetLaserState(LaserState { state: OnOff::On }));
    ToGimbal 0x32 [0x00] => q(Request::SetLaserState(SetLaserState(LaserState { state: OnOff::Off })));
    FromGimbal 0x32 [0x01] => p(Reply::SetLaserState(SetLaserStateAck(OK)));
    ToGimbal 0x33 [] => q(Request::GetThermalOutput(GetThermalOutput {}));
    FromGimbal 0x33 [0x01] => p(Reply::GetThermalOutput(ThermalOutputMode { mode: ThermalOutput::Fps25Temperature }));
    ToGimbal 0x34 [0x01] => q(Request::SetThermalOutput(SetThermalOutput(ThermalOutputMode { mode: ThermalOutput::Fps25Temperature })));
    FromGimbal 0x34 [0x00] => p(Reply::SetThermalOutput(SetThermalOutputAck(ThermalOutputMode { mode: ThermalOutput::Fps30 })));
    ToGimbal 0x35 [] => q(Request::TemperatureFrame(TemperatureFrame {}));
    FromGimbal 0x35 [0x01] => p(Reply::TemperatureFrame(TemperatureFrameAck(OK)));
    ToGimbal 0x37 [] => q(Request::GetThermalGain(GetThermalGain {}));
    FromGimbal 0x37 [0x01] => p(Reply::GetThermalGain(ThermalGain { gain: Gain::High }));
    ToGimbal 0x38 [0x00] => q(Request::SetThermalGain(SetThermalGain(ThermalGain { gain: Gain::Low })));
    FromGimbal 0x38 [0x00] => p(Reply::SetThermalGain(SetThermalGainAck(ThermalGain { gain: Gain::Low })));
    ToGimbal 0x39 [] => q(Request::GetThermalEnvironment(GetThermalEnvironment {}));
    FromGimbal 0x39 [0xE8, 0x03, 0x26, 0x25, 0x70, 0x17, 0xC4, 0x09, 0x08, 0x07]
        => p(Reply::GetThermalEnvironment(ThermalEnvironment {
            distance_m_x100: 1000, emissivity_pct_x100: 9510, humidity_pct_x100: 6000,
            air_temp_c_x100: 2500, reflected_temp_c_x100: 1800 }));
    ToGimbal 0x3A [0xE8, 0x03, 0x26, 0x25, 0x70, 0x17, 0xC4, 0x09, 0x08, 0x07]
        => q(Request::SetThermalEnvironment(SetThermalEnvironment(ThermalEnvironment {
            distance_m_x100: 1000, emissivity_pct_x100: 9510, humidity_pct_x100: 6000,
            air_temp_c_x100: 2500, reflected_temp_c_x100: 1800 })));
    FromGimbal 0x3A [0x01] => p(Reply::SetThermalEnvironment(SetThermalEnvironmentAck(OK)));
    ToGimbal 0x3B [] => q(Request::GetEnvCorrection(GetEnvCorrection {}));
    FromGimbal 0x3B [0x01] => p(Reply::GetEnvCorrection(EnvCorrection { state: OnOff::On }));
    ToGimbal 0x3C [0x00] => q(Request::SetEnvCorrection(SetEnvCorrection(EnvCorrection { state: OnOff::Off })));
    FromGimbal 0x3C [0x00] => p(Reply::SetEnvCorrection(SetEnvCorrectionAck(EnvCorrection { state: OnOff::Off })));
    ToGimbal 0x3E [0xE8, 0x03, 0x00, 0x00, 0x40, 0x3A, 0x69, 0x0D, 0xC0, 0xB9, 0xA6, 0x43, 0x39, 0x30, 0x00, 0x00,
                  0x69, 0x28, 0x00, 0x00, 0xDC, 0x05, 0x00, 0x00, 0x3C, 0xF6, 0xFF, 0xFF, 0x2C, 0x01, 0x00, 0x00]
        => q(Request::FcPosition(FcPosition {
            time_boot_ms: 1000, lat_e7: 225_000_000, lon_e7: 1_135_000_000, alt_msl_cm: 12345,
            alt_ellipsoid_cm: 10345, vel_north_mm_s: 1500, vel_east_mm_s: -2500, vel_down_mm_s: 300 }));
    FromGimbal 0x3E [] => p(Reply::FcPosition(FcPositionReply {}));
    ToGimbal 0x41 [0x5D, 0x02, 0x01] => q(Request::SingleAxisAngle(SingleAxisAngle { angle_deg_x10: 605, axis: Axis::Pitch }));
    FromGimbal 0x41 [0x5D, 0x02, 0x00, 0x00, 0xFF, 0xFF]
        => p(Reply::SingleAxisAngle(SingleAxisAngleAck(Angles { yaw_deg_x10: 605, pitch_deg_x10: 0, roll_deg_x10: -1 })));
    ToGimbal 0x48 [] => q(Request::FormatSd(FormatSd {}));
    FromGimbal 0x48 [0x01] => p(Reply::FormatSd(FormatSdAck(OK)));
    ToGimbal 0x80 [0x01, 0x00] => q(Request::SoftReboot(SoftReboot { camera: RebootAction::Reboot, gimbal: RebootAction::None }));
    FromGimbal 0x80 [0x00, 0x01] => p(Reply::SoftReboot(SoftRebootAck(SoftReboot { camera: RebootAction::None, gimbal: RebootAction::Reboot })));
};

fn fail(check: &'static str, detail: core::fmt::Arguments<'_>) -> Failure {
    Failure::new(file!(), line!(), check, detail)
}

/// Every layout decodes (in its direction) to its message, and the message encodes to
/// the same frame.
fn layouts_decode_and_reencode() -> Outcome {
    for (i, l) in LAYOUTS.iter().enumerate() {
        let seq = 0x0100 + i as u16;
        let bytes = frame(ctrl_of(l.dir), seq, l.cmd, l.data);
        let pk = check!(Packet::decode(&bytes, l.dir));
        let expected = (l.expected)();
        ensure_eq!((l.cmd, pk.message), (l.cmd, expected));
        ensure_eq!(pk.message.id(), l.cmd);
        ensure_eq!(pk.message.direction(), l.dir);
        ensure_eq!(pk.header, Header::new(Ctrl(ctrl_of(l.dir)), seq));
        ensure_eq!((l.cmd, pk.message.payload_len()), (l.cmd, l.data.len()));
        // The CTRL flag alone finds the direction of these frames.
        ensure_eq!(check!(Packet::decode_auto(&bytes)), pk);
        // Built from scratch with the convenience constructors.
        let built = match expected {
            Message::Request(r) => Packet::request(seq, r),
            Message::Reply(r) => Packet::reply(seq, r),
            Message::Raw(_) => return Err(fail("raw layout", format_args!("{:#04x}", l.cmd))),
        };
        let mut out = [0u8; 64];
        let n = check!(built.emit(&mut out));
        ensure_eq!((l.cmd, &out[..n]), (l.cmd, &bytes[..]));
        ensure_eq!(built.buffer_len(), bytes.len());
    }
    Ok(())
}

/// The layout table covers both directions of all 48 catalogue ids, and the catalogue's
/// "empty" flags agree with the layouts.
fn layouts_cover_the_catalog() -> Outcome {
    ensure_eq!(CATALOG.len(), 48);
    let ids: [u8; 48] = [
        0x00, 0x01, 0x02, 0x04, 0x05, 0x06, 0x07, 0x08, 0x0A, 0x0B, 0x0C, 0x0D, 0x0E, 0x0F, 0x10,
        0x11, 0x12, 0x13, 0x14, 0x15, 0x16, 0x17, 0x18, 0x19, 0x1A, 0x1B, 0x20, 0x21, 0x22, 0x24,
        0x25, 0x26, 0x30, 0x31, 0x32, 0x33, 0x34, 0x35, 0x37, 0x38, 0x39, 0x3A, 0x3B, 0x3C, 0x3E,
        0x41, 0x48, 0x80,
    ];
    for (e, id) in CATALOG.iter().zip(ids) {
        ensure_eq!(e.id, id);
        for dir in [Direction::ToGimbal, Direction::FromGimbal] {
            let mut any = false;
            for l in LAYOUTS.iter().filter(|l| l.cmd == id && l.dir == dir) {
                any = true;
                ensure_eq!((l.expected)().name(), e.name);
            }
            ensure!(any, "no {:?} layout for {:#04x}", dir, id);
            let empty = match dir {
                Direction::ToGimbal => e.request_empty,
                Direction::FromGimbal => e.reply_empty,
            };
            // An empty direction decodes from no data and refuses one byte.
            let none = Message::decode(id, &[], dir);
            let one = Message::decode(id, &[0x01], dir);
            if empty {
                ensure!(none.is_ok(), "{:#04x} {:?}", id, dir);
                ensure_eq!((id, one.err()), (id, Some(Error::BadLength)));
            }
        }
    }
    // The ids whose one direction carries no data.
    let empty_requests: heapless::Vec<u8, 48> = CATALOG
        .iter()
        .filter(|e| e.request_empty)
        .map(|e| e.id)
        .collect();
    let empty_replies: heapless::Vec<u8, 48> = CATALOG
        .iter()
        .filter(|e| e.reply_empty)
        .map(|e| e.id)
        .collect();
    ensure_eq!(
        &empty_requests[..],
        &[
            0x01, 0x02, 0x0A, 0x0B, 0x0D, 0x10, 0x15, 0x16, 0x17, 0x18, 0x19, 0x1A, 0x26, 0x31,
            0x33, 0x35, 0x37, 0x39, 0x3B, 0x48
        ]
    );
    ensure_eq!(&empty_replies[..], &[0x00, 0x0C, 0x22, 0x3E]);
    Ok(())
}

/// The typed payload of every command in each direction, written from the document (id,
/// request, reply), not taken from the codec's table.
macro_rules! typed {
    ($($id:literal $req:ident $rep:ident;)*) => {
        /// How many of the typed payloads `m` is (`get::<T>()` hits): exactly one for a
        /// known message, none for a raw one.
        fn typed_hits(m: &Message<'_>) -> usize {
            0 $( + usize::from(m.get::<$req>().is_some()) + usize::from(m.get::<$rep>().is_some()) )*
        }

        /// Every typed payload knows its id, direction and name, and matches the layouts
        /// of its (id, direction).
        fn typed_messages() -> Outcome {
            let ids = [$($id),*];
            ensure_eq!(ids.len(), CATALOG.len());
            for (e, id) in CATALOG.iter().zip(ids) {
                ensure_eq!(e.id, id);
            }
            $(
                check_typed::<$req, $rep>($id, Direction::ToGimbal)?;
                check_typed::<$rep, $req>($id, Direction::FromGimbal)?;
            )*
            Ok(())
        }
    };
}

#[rustfmt::skip]
typed! {
    0x00 Heartbeat HeartbeatReply;
    0x01 FirmwareVersionQuery FirmwareVersions;
    0x02 HardwareIdQuery HardwareId;
    0x04 AutoFocus AutoFocusAck;
    0x05 ManualZoom ZoomRatio;
    0x06 ManualFocus ManualFocusAck;
    0x07 GimbalRotation GimbalRotationAck;
    0x08 Center CenterAck;
    0x0A GimbalConfigQuery GimbalConfig;
    0x0B FunctionFeedbackRequest FunctionFeedback;
    0x0C CameraFunction CameraFunctionReply;
    0x0D GimbalAttitudeQuery GimbalAttitude;
    0x0E SetAngles SetAnglesAck;
    0x0F AbsoluteZoom AbsoluteZoomAck;
    0x10 GetStitching Stitching;
    0x11 SetStitching SetStitchingAck;
    0x12 PointTemperatureRequest PointTemperature;
    0x13 BoxTemperatureRequest BoxTemperature;
    0x14 GlobalTemperatureRequest GlobalTemperature;
    0x15 LaserDistanceQuery LaserDistance;
    0x16 MaxZoomQuery MaxZoom;
    0x17 LaserTargetQuery LaserTarget;
    0x18 CurrentZoomQuery CurrentZoom;
    0x19 GimbalModeQuery GimbalMode;
    0x1A GetThermalPalette ThermalPalette;
    0x1B SetThermalPalette SetThermalPaletteAck;
    0x20 CodecQuery CodecSpecs;
    0x21 SetCodec SetCodecAck;
    0x22 FcAttitude FcAttitudeReply;
    0x24 FcStreamRequest FcStreamAck;
    0x25 GimbalStreamRequest GimbalStreamAck;
    0x26 MagneticEncoderQuery MagneticEncoder;
    0x30 UtcTime TimeAck;
    0x31 GetLaserState LaserState;
    0x32 SetLaserState SetLaserStateAck;
    0x33 GetThermalOutput ThermalOutputMode;
    0x34 SetThermalOutput SetThermalOutputAck;
    0x35 TemperatureFrame TemperatureFrameAck;
    0x37 GetThermalGain ThermalGain;
    0x38 SetThermalGain SetThermalGainAck;
    0x39 GetThermalEnvironment ThermalEnvironment;
    0x3A SetThermalEnvironment SetThermalEnvironmentAck;
    0x3B GetEnvCorrection EnvCorrection;
    0x3C SetEnvCorrection SetEnvCorrectionAck;
    0x3E FcPosition FcPositionReply;
    0x41 SingleAxisAngle SingleAxisAngleAck;
    0x48 FormatSd FormatSdAck;
    0x80 SoftReboot SoftRebootAck;
}

/// Checks payload type `T` of command `id` in `dir` (`O`: the other direction's type):
/// its constants, and for every layout of (`id`, `dir`): `get::<T>()` hits (and no
/// other type does), `encode` of the typed value gives the layout's frame, byte for
/// byte the enum path's, and `ENCODED_LEN` is the longest layout.
fn check_typed<T, O>(id: u8, dir: Direction) -> Outcome
where
    T: MessageData<Protocol = Siyi> + Directed + Payload,
    O: MessageData<Protocol = Siyi> + Directed,
{
    ensure_eq!((id, T::ID, T::DIRECTION), (id, id, dir));
    ensure_eq!((id, O::ID, O::DIRECTION), (id, id, dir.reverse()));
    let entry = check!(CATALOG.iter().find(|e| e.id == id));
    ensure_eq!((id, T::NAME), (id, entry.name));
    let mut longest = None;
    for (i, l) in LAYOUTS.iter().enumerate() {
        if l.cmd != id || l.dir != dir {
            continue;
        }
        let header = Header::new(Ctrl(ctrl_of(dir)), 0x0200 + i as u16);
        let bytes = frame(header.ctrl.0, header.seq, id, l.data);
        let pk = check!(Packet::decode(&bytes, dir));
        let value = check!(pk.message.get::<T>());
        ensure!(pk.message.get::<O>().is_none(), "{id:#04x} {dir:?}");
        ensure_eq!((id, typed_hits(&pk.message)), (id, 1));
        ensure_eq!(value.into_message(), (l.expected)());
        ensure_eq!(value.into_message(), pk.message);
        ensure_eq!((id, Payload::encoded_len(&value)), (id, l.data.len()));
        let mut typed = [0u8; 64];
        let n = check!(encode(&value, &header, &mut typed));
        ensure_eq!((id, &typed[..n]), (id, &bytes[..]));
        let mut via_enum = [0u8; 64];
        let m = check!(
            Packet {
                header,
                message: (l.expected)()
            }
            .emit(&mut via_enum)
        );
        ensure_eq!(&typed[..n], &via_enum[..m]);
        // Too small a buffer is an error, not a panic.
        ensure_eq!(
            encode(&value, &header, &mut typed[..n - 1]),
            Err(Error::BufferTooSmall)
        );
        longest = longest.max(Some(l.data.len()));
    }
    ensure_eq!((id, dir, Some(T::ENCODED_LEN)), (id, dir, longest));
    Ok(())
}

/// Expected fields of one seed vector (from its `decoded` object in the fixture).
struct Expect {
    name: &'static str,
    payload_len: usize,
    seq: u16,
    cmd: u8,
    data: &'static [u8],
    crc: u16,
    message: fn() -> Message<'static>,
}

static SEED: &[Expect] = &[
    Expect {
        name: "TCP heartbeat",
        payload_len: 1,
        seq: 0,
        cmd: 0x00,
        data: &[0x00],
        crc: 0x8B59,
        message: || q(Request::Heartbeat(Heartbeat { byte: Some(0) })),
    },
    Expect {
        name: "Request gimbal camera current working mode (0x19)",
        payload_len: 0,
        seq: 0,
        cmd: 0x19,
        data: &[],
        crc: 0x575D,
        message: || q(Request::GimbalMode(GimbalModeQuery {})),
    },
    Expect {
        name: "Manual zoom: zoom in (zoom=1)",
        payload_len: 1,
        seq: 0,
        cmd: 0x05,
        data: &[0x01],
        crc: 0x648D,
        message: || {
            q(Request::ManualZoom(ManualZoom {
                direction: ZoomDirection::In,
            }))
        },
    },
    Expect {
        name: "Manual zoom: zoom out (zoom=-1)",
        payload_len: 1,
        seq: 0,
        cmd: 0x05,
        data: &[0xFF],
        crc: 0x6A5C,
        message: || {
            q(Request::ManualZoom(ManualZoom {
                direction: ZoomDirection::Out,
            }))
        },
    },
    Expect {
        name: "Absolute zoom to 4.5x (0x0F)",
        payload_len: 2,
        seq: 16,
        cmd: 0x0F,
        data: &[0x04, 0x05],
        crc: 0x156B,
        message: || {
            q(Request::AbsoluteZoom(AbsoluteZoom(ZoomLevel {
                integer: 4,
                tenths: 5,
            })))
        },
    },
    Expect {
        name: "Request zoom camera max zoom value in current state (0x16)",
        payload_len: 0,
        seq: 0,
        cmd: 0x16,
        data: &[],
        crc: 0xA6B2,
        message: || q(Request::MaxZoom(MaxZoomQuery {})),
    },
    Expect {
        name: "Request zoom camera current zoom value (0x18)",
        payload_len: 0,
        seq: 0,
        cmd: 0x18,
        data: &[],
        crc: 0x477C,
        message: || q(Request::CurrentZoom(CurrentZoomQuery {})),
    },
];

/// All 7 SIYI frames of the fixture decode to the fields of their `decoded` object and
/// re-encode byte for byte.
fn seed_vectors() -> Outcome {
    let mut seen = 0;
    for v in crate::vectors("SIYI") {
        ensure!(v.verified, "{}", v.name);
        let Some(x) = SEED.iter().find(|x| x.name == v.name) else {
            return Err(fail("known vector", format_args!("{}", v.name)));
        };
        seen += 1;
        if let Some(doc) = v.doc_bytes {
            ensure_eq!(doc, v.bytes);
        }
        // The frame fields.
        let f = check!(Frame::new_checked(v.bytes));
        ensure_eq!(&v.bytes[..2], &[0x55, 0x66]); // stx 0x6655, low byte first
        ensure_eq!(f.ctrl(), Ctrl(0x01));
        ensure!(f.ctrl().need_ack() && !f.ctrl().is_ack(), "{}", v.name);
        ensure_eq!((v.name, f.payload_len()), (v.name, x.payload_len));
        ensure_eq!((v.name, f.seq()), (v.name, x.seq));
        ensure_eq!((v.name, f.id()), (v.name, x.cmd));
        ensure_eq!((v.name, f.payload()), (v.name, x.data));
        ensure_eq!((v.name, f.checksum()), (v.name, x.crc));
        ensure!(f.verify().is_ok(), "{}", v.name);
        ensure_eq!(f.total_len(), v.bytes.len());
        // The typed message, in the request direction and by the CTRL flag.
        let pk = check!(Packet::decode(v.bytes, Direction::ToGimbal));
        ensure_eq!((v.name, pk.message), (v.name, (x.message)()));
        ensure_eq!(pk.header, Header::new(Ctrl::NEED_ACK, x.seq));
        ensure_eq!(check!(Packet::decode_auto(v.bytes)), pk);
        // Re-encoding.
        let mut out = [0u8; 64];
        let n = check!(pk.emit(&mut out));
        ensure_eq!((v.name, &out[..n]), (v.name, v.bytes));
    }
    ensure_eq!(seen, 7);
    // The values the vectors carry, by meaning (data_signed_int8, zoom 4.5x).
    let zoom = |name: &str| {
        crate::vectors("SIYI")
            .find(|v| v.name == name)
            .and_then(|v| Packet::decode(v.bytes, Direction::ToGimbal).ok())
            .map(|p| p.message)
    };
    let Some(Message::Request(Request::ManualZoom(out))) = zoom("Manual zoom: zoom out (zoom=-1)")
    else {
        return Err(fail("zoom out", format_args!("")));
    };
    ensure_eq!(out.direction.value(), -1);
    let Some(Message::Request(Request::AbsoluteZoom(abs))) = zoom("Absolute zoom to 4.5x (0x0F)")
    else {
        return Err(fail("absolute zoom", format_args!("")));
    };
    ensure_eq!(abs.0.zoom_x10(), 45);
    Ok(())
}

/// Two attitude replies captured from a SIYI gimbal (published in public projects):
/// CTRL = 2 (is_ack), SEQ counting on the gimbal's side.
fn captured_gimbal_replies() -> Outcome {
    let a = [
        0x55, 0x66, 0x02, 0x0C, 0x00, 0x06, 0x00, 0x0D, 0xF7, 0xFF, 0x90, 0xFC, 0x00, 0x00, 0xFD,
        0xFF, 0x7F, 0xFF, 0x00, 0x00, 0x89, 0x4B,
    ];
    let b = [
        0x55, 0x66, 0x02, 0x0C, 0x00, 0x44, 0x00, 0x0D, 0x1A, 0x00, 0xF9, 0xF8, 0x00, 0x00, 0xFC,
        0xFF, 0xFF, 0xFF, 0xFD, 0xFF, 0x19, 0x88,
    ];
    let pa = check!(Packet::decode_auto(&a));
    ensure_eq!(pa.header, Header::new(Ctrl::IS_ACK, 6));
    ensure_eq!(
        pa.message,
        p(Reply::GimbalAttitude(GimbalAttitude {
            yaw_deg_x10: -9,
            pitch_deg_x10: -880,
            roll_deg_x10: 0,
            yaw_rate_dps_x10: -3,
            pitch_rate_dps_x10: -129,
            roll_rate_dps_x10: 0,
        }))
    );
    let pb = check!(Packet::decode(&b, Direction::FromGimbal));
    ensure_eq!(pb.header, Header::reply(0x44));
    ensure_eq!(
        pb.message,
        p(Reply::GimbalAttitude(GimbalAttitude {
            yaw_deg_x10: 26,
            pitch_deg_x10: -1799,
            roll_deg_x10: 0,
            yaw_rate_dps_x10: -4,
            pitch_rate_dps_x10: -1,
            roll_rate_dps_x10: -3,
        }))
    );
    for (f, pk) in [(&a[..], pa), (&b[..], pb)] {
        let mut out = [0u8; 64];
        let n = check!(pk.emit(&mut out));
        ensure_eq!(&out[..n], f);
    }
    Ok(())
}

/// Direction matters: the same id is a request one way and a reply the other.
fn direction_selects_the_layout() -> Outcome {
    let attitude = [
        0x77, 0xFC, 0xFA, 0x00, 0xF4, 0xFF, 0x2C, 0x01, 0xFF, 0xFF, 0x07, 0x00,
    ];
    // 0x0D: empty as a request, 12 bytes as a reply.
    ensure_eq!(
        Message::decode(0x0D, &[], Direction::ToGimbal),
        Ok(q(Request::GimbalAttitude(GimbalAttitudeQuery {})))
    );
    ensure_eq!(
        Message::decode(0x0D, &attitude, Direction::ToGimbal),
        Err(Error::BadLength)
    );
    ensure_eq!(
        Message::decode(0x0D, &[], Direction::FromGimbal),
        Err(Error::BadLength)
    );
    // decode_auto: a 12-byte 0x0D with CTRL = 1 (not is_ack) still decodes as the reply.
    let odd = frame(0x01, 9, 0x0D, &attitude);
    let pk = check!(Packet::decode_auto(&odd));
    ensure_eq!(pk.message.direction(), Direction::FromGimbal);
    ensure_eq!(pk.header.ctrl, Ctrl(0x01));
    // ... and an empty 0x0D with CTRL = 2 as the request.
    let empty = frame(0x02, 9, 0x0D, &[]);
    ensure_eq!(
        check!(Packet::decode_auto(&empty)).message,
        q(Request::GimbalAttitude(GimbalAttitudeQuery {}))
    );
    // 0x11 has one byte both ways: CTRL decides.
    let req = frame(0x01, 1, 0x11, &[0x04]);
    let rep = frame(0x02, 1, 0x11, &[0x04]);
    let mode = Stitching {
        mode: StitchingMode::ZoomSubWide,
    };
    ensure_eq!(
        check!(Packet::decode_auto(&req)).message,
        q(Request::SetStitching(SetStitching(mode)))
    );
    ensure_eq!(
        check!(Packet::decode_auto(&rep)).message,
        p(Reply::SetStitching(SetStitchingAck(mode)))
    );
    // A length neither direction allows is an error, also for decode_auto.
    let bad = frame(0x01, 1, 0x0E, &[1, 2, 3]);
    ensure_eq!(Packet::decode_auto(&bad), Err(Error::BadLength));
    ensure_eq!(Ctrl::new(true, true).direction(), Direction::FromGimbal);
    ensure_eq!(Ctrl(0).direction(), Direction::ToGimbal);
    ensure_eq!(Direction::ToGimbal.reverse(), Direction::FromGimbal);
    Ok(())
}

/// The variable-length layouts decode every length seen in the wild and re-encode to it;
/// other lengths are errors.
fn variable_lengths_round_trip() -> Outcome {
    let config = [0xA5, 0x01, 0x5A, 0x03, 0x02, 0x02, 0x01, 0x01];
    for n in 0..=10usize {
        let data = &[0x11u8; 12][..n.min(12)];
        let data = if n <= 8 { &config[..n] } else { data };
        let got = Message::decode(0x0A, data, Direction::FromGimbal);
        if (5..=8).contains(&n) {
            let m = check!(got);
            ensure_eq!(m.payload_len(), n);
            let Message::Reply(Reply::GimbalConfig(c)) = m else {
                return Err(fail("config", format_args!("{m:?}")));
            };
            ensure_eq!(c.motion, MotionMode::Fpv);
            ensure_eq!(c.mount.is_some(), n >= 6);
            ensure_eq!(c.video_output.is_some(), n >= 7);
            ensure_eq!(c.zoom_linkage.is_some(), n >= 8);
            let bytes = frame(0x02, 3, 0x0A, data);
            let pk = check!(Packet::decode(&bytes, Direction::FromGimbal));
            let mut out = [0u8; 64];
            let k = check!(pk.emit(&mut out));
            ensure_eq!(&out[..k], &bytes[..]);
        } else {
            ensure_eq!((n, got.err()), (n, Some(Error::BadLength)));
        }
    }
    // 0x01: 8 or 12 bytes.
    let fw_data = [3, 2, 3, 0x6E, 1, 2, 0, 0, 9, 4, 1, 0, 0];
    for n in 0..=13usize {
        let got = Message::decode(0x01, &fw_data[..n], Direction::FromGimbal);
        if n == 8 || n == 12 {
            let m = check!(got);
            ensure_eq!(m.payload_len(), n);
            let mut out = [0u8; 16];
            let mut w = protocol_core::wire::Writer::new(&mut out);
            check!(m.encode(&mut w));
            ensure_eq!(w.written(), &fw_data[..n]);
        } else {
            ensure_eq!((n, got.err()), (n, Some(Error::BadLength)));
        }
    }
    // 0x20: 8 or 9 bytes; 0x00: 0 or 1 byte.
    for (cmd, dir, ok) in [
        (0x20u8, Direction::FromGimbal, &[8usize, 9][..]),
        (0x00, Direction::ToGimbal, &[0, 1][..]),
    ] {
        for n in 0..=10usize {
            let got = Message::decode(cmd, &[0x01; 10][..n], dir);
            if ok.contains(&n) {
                ensure_eq!((cmd, n, check!(got).payload_len()), (cmd, n, n));
            } else {
                ensure_eq!((cmd, n, got.err()), (cmd, n, Some(Error::BadLength)));
            }
        }
    }
    // A present field after a missing one cannot be encoded.
    let broken = GimbalConfig {
        mount: None,
        video_output: Some(VideoOutput::Hdmi),
        ..GimbalConfig::default()
    };
    ensure_eq!(Payload::encoded_len(&broken), 5);
    let mut out = [0u8; 64];
    ensure_eq!(
        Packet::reply(0, Reply::GimbalConfig(broken)).emit(&mut out),
        Err(Error::OutOfRange)
    );
    Ok(())
}

/// Replies encode exactly what ArduPilot's AP_Mount_Siyi parses: CTRL = 2, at most 32
/// data bytes (it drops longer frames), and the lengths it checks.
fn replies_fit_ardupilot() -> Outcome {
    for l in LAYOUTS.iter().filter(|l| l.dir == Direction::FromGimbal) {
        let Message::Reply(r) = (l.expected)() else {
            return Err(fail("reply", format_args!("{:#04x}", l.cmd)));
        };
        let pk = Packet::reply(7, r);
        let mut out = [0u8; 64];
        let n = check!(pk.emit(&mut out));
        ensure!(n <= 42, "{:#04x}: {n} bytes", l.cmd);
        ensure_eq!(out[2], 0x02);
        // Lengths ArduPilot requires.
        let need: &[usize] = match l.cmd {
            0x01 => &[8, 12],
            0x05 => &[2],
            0x0B => &[1],
            0x0D | 0x14 => &[12],
            0x20 => &[8, 9],
            0x02 => &[12],
            _ => &[],
        };
        ensure!(
            need.is_empty() || need.contains(&(n - 10)),
            "{:#04x}: {} data bytes",
            l.cmd,
            n - 10
        );
    }
    // The requests ArduPilot sends have CTRL = 1 and fit its 42-byte buffer too.
    for l in LAYOUTS.iter().filter(|l| l.dir == Direction::ToGimbal) {
        let Message::Request(r) = (l.expected)() else {
            return Err(fail("request", format_args!("{:#04x}", l.cmd)));
        };
        let mut out = [0u8; 64];
        let n = check!(Packet::request(1, r).emit(&mut out));
        ensure!(n <= DEFAULT_MAX_FRAME_LEN, "{:#04x}", l.cmd);
        ensure_eq!(out[2], 0x01);
    }
    // A hardware id the bridge announces is recognised from its first two characters.
    let id = check!(HardwareId::for_product(Product::Zt30, "0123456789"));
    ensure_eq!(&id.raw[..2], b"7A");
    ensure_eq!(id.product(), Product::Zt30);
    ensure_eq!(
        check!(HardwareId::for_product(Product::Zt6, "")).raw[..2],
        *b"83"
    );
    Ok(())
}

/// Hardware ids name their product from the hex prefix (either case); versions split.
fn hardware_id_and_versions() -> Outcome {
    let table = [
        (b"6B", Product::Zr10, "ZR10"),
        (b"73", Product::A8Mini, "A8 mini"),
        (b"75", Product::A2Mini, "A2 mini"),
        (b"78", Product::Zr30, "ZR30"),
        (b"82", Product::Zt6, "ZT6"),
        (b"83", Product::Zt6, "ZT6"),
        (b"7A", Product::Zt30, "ZT30"),
        (b"7a", Product::Zt30, "ZT30"),
        (b"68", Product::Unknown, "unknown"),
        (b"G1", Product::Unknown, "unknown"),
    ];
    for (prefix, product, name) in table {
        let mut raw = *b"000000000000";
        raw[..2].copy_from_slice(prefix);
        let id = HardwareId { raw };
        ensure_eq!(id.product(), product);
        ensure_eq!(id.product().name(), name);
    }
    let padded = HardwareId {
        raw: *b"7A01234567\0\0",
    };
    ensure_eq!(padded.as_str(), Some("7A01234567"));
    ensure_eq!(padded.product_id(), Some(0x7A));
    ensure_eq!(check!(HardwareId::from_text("7A01234567")), padded);
    ensure!(HardwareId::from_text("0123456789ABC").is_err());
    let v = FirmwareVersion::from_u32(0x6E03_0203);
    ensure_eq!((v.major, v.minor, v.patch, v.ignored), (3, 2, 3, 0x6E));
    ensure_eq!(
        check!(ZoomLevel::from_zoom_x10(45)),
        ZoomLevel {
            integer: 4,
            tenths: 5
        }
    );
    ensure_eq!(ZoomLevel::from_zoom_x10(2560), Err(Error::OutOfRange));
    ensure_eq!(Ctrl::new(true, false), Ctrl::NEED_ACK);
    ensure_eq!(Ctrl::new(false, true), Ctrl::IS_ACK);
    ensure_eq!(Ctrl(0xFD).reserved(), 0x3F);
    Ok(())
}

/// Unknown ids decode to Raw in either direction and re-encode unchanged.
fn unknown_ids_are_raw() -> Outcome {
    for cmd in [0x03u8, 0x09, 0x1C, 0x23, 0x36, 0x40, 0x81, 0xFF] {
        for dir in [Direction::ToGimbal, Direction::FromGimbal] {
            let data = [1, 2, 3, 4, 5];
            let bytes = frame(ctrl_of(dir), 0xBEEF, cmd, &data);
            let pk = check!(Packet::decode(&bytes, dir));
            ensure_eq!(
                pk.message,
                Message::Raw(Raw {
                    id: cmd,
                    payload: &data,
                    direction: dir,
                })
            );
            ensure_eq!(pk.message.name(), "Raw");
            let mut out = [0u8; 64];
            let n = check!(pk.emit(&mut out));
            ensure_eq!(&out[..n], &bytes[..]);
        }
    }
    Ok(())
}

/// Malformed input is an error value for every prefix and every bit flip.
fn malformed_frames_are_errors() -> Outcome {
    let good = frame(0x01, 0x1234, 0x3E, &[0x5A; 32]);
    for n in 0..good.len() {
        ensure!(
            Packet::decode(&good[..n], Direction::ToGimbal).is_err(),
            "prefix {n} accepted"
        );
    }
    ensure_eq!(
        Packet::decode(&good[..1], Direction::ToGimbal).err(),
        Some(Error::Truncated)
    );
    ensure_eq!(
        Packet::decode(&good[1..], Direction::ToGimbal).err(),
        Some(Error::BadSync)
    );
    ensure_eq!(
        Packet::decode(&[0x55, 0x67, 0, 0, 0, 0, 0, 0, 0, 0], Direction::ToGimbal).err(),
        Some(Error::BadSync)
    );
    for i in 0..good.len() {
        for bit in 0..8 {
            let mut bad = good.clone();
            bad[i] ^= 1 << bit;
            ensure!(
                Packet::decode(&bad, Direction::ToGimbal).is_err(),
                "flip {i}.{bit} accepted"
            );
        }
    }
    // A valid CRC over a data length the layout does not allow.
    let short = frame(0x01, 0, 0x3E, &[0x5A; 31]);
    ensure_eq!(
        Packet::decode(&short, Direction::ToGimbal),
        Err(Error::BadLength)
    );
    let mut wrong_crc = good.clone();
    let last = wrong_crc.len() - 1;
    wrong_crc[last] ^= 0x80;
    ensure!(matches!(
        Packet::decode(&wrong_crc, Direction::ToGimbal),
        Err(Error::BadChecksum { .. })
    ));
    // Output buffer too small.
    let pk = check!(Packet::decode(&good, Direction::ToGimbal));
    let mut small = [0u8; 41];
    ensure_eq!(pk.emit(&mut small), Err(Error::BufferTooSmall));
    Ok(())
}

/// A stream of every layout frame, with garbage, false syncs and corrupted frames, fed
/// in pieces of several sizes, yields every intact frame in order.
fn deframer_recovers_every_frame() -> Outcome {
    for chunk in [1usize, 5, 42, 4096] {
        let mut d = Deframer::<SiyiFraming, DEFAULT_MAX_FRAME_LEN>::new(SiyiFraming::default());
        let mut stream = heapless::Vec::<u8, 8192>::new();
        for (i, l) in LAYOUTS.iter().enumerate() {
            let f = frame(ctrl_of(l.dir), i as u16, l.cmd, l.data);
            match i % 4 {
                0 => {
                    // garbage and a false sync with a huge LEN
                    ensure!(
                        stream
                            .extend_from_slice(&[0x00, 0x55, 0x55, 0x66, 0x01, 0xFF, 0xFF])
                            .is_ok()
                    );
                }
                1 => {
                    let mut bad = f.clone();
                    let at = 8.min(bad.len() - 3);
                    bad[at] ^= 0x10;
                    ensure!(stream.extend_from_slice(&bad).is_ok());
                }
                _ => {}
            }
            ensure!(stream.extend_from_slice(&f).is_ok());
        }
        let mut next = 0usize;
        let mut ok = true;
        let mut rejected = 0usize;
        for part in stream.chunks(chunk) {
            d.push(part, |ev| match ev {
                Event::Frame(f) => {
                    let l = &LAYOUTS[next.min(LAYOUTS.len() - 1)];
                    let want = frame(ctrl_of(l.dir), next as u16, l.cmd, l.data);
                    ok &= f == &want[..];
                    next += 1;
                }
                Event::Rejected { .. } | Event::Skipped(_) => rejected += 1,
            });
        }
        ensure!(ok, "frames out of order or altered (chunk {chunk})");
        ensure_eq!(next, LAYOUTS.len());
        ensure!(
            rejected >= LAYOUTS.len() / 2,
            "chunk {chunk}: {rejected} rejected"
        );
        ensure_eq!(d.stats().frames_ok as usize, LAYOUTS.len());
    }
    Ok(())
}

/// The maximum data length is configurable; longer frames are refused at once.
fn framing_max_data_len() -> Outcome {
    let five = frame(0x01, 0, 0x40, &[1, 2, 3, 4, 5]);
    let two = frame(0x01, 0, 0x0F, &[4, 5]);
    let mut stream = heapless::Vec::<u8, 64>::new();
    ensure!(stream.extend_from_slice(&five).is_ok());
    ensure!(stream.extend_from_slice(&two).is_ok());
    let mut d = Deframer::<SiyiFraming, 16>::new(SiyiFraming::new(4));
    let (mut frames, mut length_errors) = (0, 0);
    d.push(&stream, |ev| match ev {
        Event::Frame(f) => {
            // Only the 2-byte frame comes out.
            frames += if f == &two[..] { 1 } else { 100 };
        }
        Event::Rejected { error, .. } => {
            if error == Error::BadLength {
                length_errors += 1;
            }
        }
        Event::Skipped(_) => frames += 100,
    });
    ensure_eq!((frames, length_errors), (1, 1));
    ensure_eq!(SiyiFraming::default().max_payload_len, 32);
    ensure_eq!(SiyiFraming::new(1 << 20).max_payload_len, MAX_PAYLOAD_LEN);
    // 32 data bytes pass the default framing, 33 do not.
    let mut d = Deframer::<SiyiFraming, 64>::new(SiyiFraming::default());
    let (mut ok32, mut bad33) = (false, false);
    d.push(&frame(0x01, 0, 0x3E, &[0; 32]), |ev| {
        ok32 |= matches!(ev, Event::Frame(_))
    });
    d.push(&frame(0x01, 0, 0x99, &[0; 33]), |ev| {
        bad33 |= matches!(
            ev,
            Event::Rejected {
                error: Error::BadLength,
                ..
            }
        )
    });
    ensure!(ok32 && bad33);
    Ok(())
}

cases!("siyi":
    seed_vectors,
    layouts_decode_and_reencode,
    layouts_cover_the_catalog,
    typed_messages,
    captured_gimbal_replies,
    direction_selects_the_layout,
    variable_lengths_round_trip,
    replies_fit_ardupilot,
    hardware_id_and_versions,
    unknown_ids_are_raw,
    malformed_frames_are_errors,
    deframer_recovers_every_frame,
    framing_max_data_len,
);
