//! K40T codec cases.
//!
//! The layout table below is written from the document's byte tables, not from the
//! codec: each entry is a payload as the document lays it out (distinct values per
//! field, little-endian) and the message it must decode to. Frames around the payloads
//! are built here with the document's own CRC routine, independently of the codec.

use crate::Outcome;
use crate::oracle::k40t_crc as doc_crc;
use protocol_core::Error;
use protocol_core::k40t::*;
use protocol_core::wire::{Deframer, Event};

type Bytes = heapless::Vec<u8, 255>;

/// A frame from the pod (0x04/0x01, seq 0x2A) to the flight controller (0x02/0x01).
fn frame(id: u32, payload: &[u8], coverage: CrcCoverage) -> Bytes {
    let mut f = Bytes::new();
    let id = id.to_le_bytes();
    let _ = f.extend_from_slice(&[
        0xFD,
        payload.len() as u8,
        0x02,
        0x01,
        0x2A,
        0x04,
        0x01,
        id[0],
        id[1],
        id[2],
    ]);
    let _ = f.extend_from_slice(payload);
    let covered = match coverage {
        CrcCoverage::ExcludeStx => &f[1..],
        CrcCoverage::IncludeStx => &f[..],
    };
    let crc = doc_crc(covered).to_le_bytes();
    let _ = f.extend_from_slice(&crc);
    f
}

/// A payload as laid out by the document and the message it means.
struct Layout {
    id: u32,
    payload: &'static [u8],
    expected: fn() -> Message<'static>,
}

fn req(r: Request) -> Message<'static> {
    Message::Request(r)
}
fn ack(a: Ack) -> Message<'static> {
    Message::Ack(a)
}
fn status(s: Status) -> Message<'static> {
    Message::Status(s)
}
fn text<const N: usize>(s: &str) -> Text<N> {
    Text::new(s).unwrap_or_default()
}

macro_rules! layouts {
    ($($id:literal [$($b:expr),* $(,)?] => $e:expr;)*) => {
        &[$( Layout { id: $id, payload: &[$($b),*], expected: || $e }, )*]
    };
}

const OK: ResponseCode = ResponseCode::OK;

#[rustfmt::skip]
static LAYOUTS: &[Layout] = layouts! {
    // ---- 3.1 gimbal
    0x000001 [0x10, 0x02, 0x0B, 0x01, 0xA1, 0xA2, 0xA3] => req(Request::GimbalStatus(GimbalStatus {
        links: Links(0x10), upgrade: UpgradeState::FirmwareIncomplete, self_test: SelfTest(0x0B),
        stabilization: StabilizationState::Active, reserved: [0xA1, 0xA2, 0xA3] }));
    0x000002 [0x02, 0x01, 0x9C, 0xFF, 0x94, 0x11, 0xB0, 0xB9, 0xFA, 0x00, 0xD8, 0xDC, 0xE8, 0x03,
              0xFF, 0xFF, 0x02, 0x00, 0x00, 0x00] => req(Request::GimbalAttitude(GimbalAttitude {
        yaw_joint_cdeg: 0x0102, roll_joint_cdeg: -100, pitch_joint_cdeg: 4500, yaw_cdeg: -18000,
        roll_cdeg: 250, pitch_cdeg: -9000, yaw_rate_cdeg_s: 1000, pitch_rate_cdeg_s: -1,
        roll_rate_cdeg_s: 2, reserved: [0, 0] }));
    0x000010 [0x10, 0x01, 0x02, 0x00] => req(Request::GimbalControl(GimbalControl {
        function: GimbalFunction::Center, yaw: YawMotion::Right, pitch: PitchMotion::Stop, reserved: 0 }));
    0x010010 [0x00, 0x01] => ack(Ack::GimbalControl(GimbalControlAck { code: ResponseCode::new(AckCode::Failure) }));
    0x000012 [0x01, 0x28, 0x23, 0x00, 0x50, 0x46, 0x00] => req(Request::GimbalAngle(GimbalAngle {
        pitch_direction: PitchMotion::Down, pitch_cdeg: 9000, yaw_direction: YawMotion::Left,
        yaw_cdeg: 18000, reserved: 0 }));
    0x000013 [0x01, 0x00] => req(Request::DriftCalibration(DriftCalibration { command: 1, reserved: 0 }));
    0x000017 [0x05, 0x96, 0x00] => req(Request::DialSpeed(DialSpeed { pitch_dps_x5: 5, yaw_dps_x5: 150, reserved: 0 }));
    0x000018 [0x01, 0x00] => req(Request::GimbalVersion(GimbalVersionQuery { command: 1, reserved: 0 }));
    0x010018 [0x00, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x00] => ack(Ack::GimbalVersion(GimbalVersionAck {
        code: OK, hardware: Version { major: 1, minor: 2, patch: 3 },
        software: Version { major: 4, minor: 5, patch: 6 }, reserved: 0 }));
    0x00002C [0x02, 0x2D, 0x00, 0xC0, 0x03, 0x1C, 0x02] => req(Request::PointToAim(PointToAim {
        lens: Lens::Infrared, zoom_x10: 45, x: 960, y: 540 }));
    0x00002D [0x00, 0x00] => req(Request::ServoOff(ServoOff { command: 0, reserved: 0 }));
    0x00002E [0x01, 0x00] => req(Request::LinearCalibration(LinearCalibration { command: 1, reserved: 0 }));
    0x00002F [0x01, 0x00] => req(Request::SoftRestart(SoftRestart { command: 1, reserved: 0 }));
    0x000030 [0x01, 0x00] => req(Request::UseFcAttitude(UseFcAttitude { command: 1, reserved: 0 }));
    0x000031 [0x01, 0x00] => req(Request::AccelCalibration(AccelCalibration { command: 1, reserved: 0 }));
    0x000033 [0x01, 0x00] => req(Request::Stabilization(Stabilization { enable: OnOff::On, reserved: 0 }));
    // ---- 3.2.1 camera reports
    0x000003 [0x01, 0x00, 0x01, 0x07, 0x05, 0x02, 0x1E, 0x05, 0x04, 0x10, 0x27, 0xE8, 0x03, 0x28, 0x23, 0x00]
        => req(Request::SystemStatus(SystemStatus {
        mode: CaptureMode::Video, preview_resolution: PreviewResolution::P1080Fps30,
        preview_codec: VideoCodec::H265, stream: ImageMode::Split, preview_bitrate: StreamBitrate::M8,
        photo_mode: PhotoMode::TimeLapse, timelapse_s: 30, burst_count: 5, sd: SdState::Full,
        sd_total_10mb: 10000, sd_free_10mb: 1000, sd_used_10mb: 9000, reserved: 0 }));
    0x000004 [0x0B, 0x02, 0x97, 0xFF, 0xFA, 0x00, 0x2C, 0x01, 0xC8, 0x00,
              0x64, 0x00, 0xC8, 0x00, 0x2C, 0x01, 0x90, 0x01, 0x40, 0x01, 0x00, 0x01, 0x0A, 0x00, 0x14, 0x00,
              0x01, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00] => req(Request::IrStatus(IrStatus {
        max_temp_dc: 523, min_temp_dc: -105, center_temp_dc: 250, point_temp_dc: 300, avg_temp_dc: 200,
        max_x: 100, max_y: 200, min_x: 300, min_y: 400, center_x: 320, center_y: 256, point_x: 10,
        point_y: 20, high_warning: 1, low_warning: 0, diff_warning: 1, threshold_warning: 0, reserved: [0; 4] }));
    0x000005 [0x01, 0x2C, 0x01, 0xA0, 0x00, 0x1C, 0x64, 0x00, 0xE8, 0x03, 0x02, 0x01, 0x34, 0x12, 0x00]
        => req(Request::VisibleStatus(VisibleStatus {
        zoom_state: ZoomState::Zooming, focal_length_10um: 300, zoom_x10: 160, ev: Ev::Minus1,
        iso_0p1db: 100, shutter_us: 1000, ae_lock: AeLock::Off, focus: FocusState::Focusing,
        accurate_focal_length: 0x1234, reserved: 0 }));
    0x000008 [0x02, 0x37, 0x00] => req(Request::UpgradeStatus(UpgradeStatus {
        state: UpgradeProgressState::Upgrading, progress_pct: 55, reserved: 0 }));
    // ---- 3.2.2 infrared
    0x000100 [0x01, 0x00] => req(Request::IrParams(IrParamsQuery { command: 1, reserved: 0 }));
    0x010100 [0x00, 0x00, 0x05, 0x1A, 0x32, 0x02, 0x3C, 0x46, 0x85, 0x03, 0xE8, 0x03, 0x38, 0xFF,
              0x54, 0xF5, 0x01, 0xD4, 0xFE, 0x20, 0x03, 0x00, 0x00] => ack(Ack::IrParams(IrParams {
        code: OK, palette: Palette::IronRed, measure: MeasureConfig(0x1A), sharpness: 50,
        gain: IrGain::Auto, brightness: 60, contrast: 70, denoise: SwitchLevel(0x85), enhancement: 3,
        high_warning_dc: 1000, low_warning_dc: -200, diff_warning_dc: -2732,
        threshold_warning: OnOff::On, threshold_ref_dc: -300, threshold_float_dc: 800, reserved: [0, 0] }));
    0x000105 [0x04, 0x00] => req(Request::IrDigitalZoom(IrDigitalZoom { zoom_x: 4, reserved: 0 }));
    0x000106 [0x0D, 0x00] => req(Request::IrPalette(IrPalette { palette: Palette::IceFire, reserved: 0 }));
    0x000108 [0x01, 0x00] => req(Request::IrMeasurement(IrMeasurement { switch: MeasureSwitch::Off, reserved: 0 }));
    0x00010A [0x32, 0x00] => req(Request::IrSharpness(IrSharpness { sharpness: 50, reserved: 0 }));
    0x00010B [0x3C, 0x00] => req(Request::IrBrightness(IrBrightness { brightness: 60, reserved: 0 }));
    0x00010C [0x46, 0x00] => req(Request::IrContrast(IrContrast { contrast: 70, reserved: 0 }));
    0x00010D [0x01, 0x50, 0x00] => req(Request::IrDenoise(IrDenoise { enable: OnOff::On, level: 80, reserved: 0 }));
    0x00010E [0x0A, 0x00] => req(Request::IrEnhancement(IrEnhancement { level: 10, reserved: 0 }));
    0x00010F [0x40, 0x01, 0x00, 0x02, 0x00] => req(Request::IrPointMeasure(IrPointMeasure { x: 320, y: 512, reserved: 0 }));
    0x000110 [0x64, 0x00, 0x32, 0x00, 0x80, 0x02, 0x00, 0x02, 0x00] => req(Request::IrAreaMeasure(IrAreaMeasure {
        width: 100, height: 50, center_x: 640, center_y: 512, reserved: 0 }));
    0x000123 [0x02, 0x00] => req(Request::IrGainMode(IrGainMode { gain: IrGain::Auto, reserved: 0 }));
    0x000124 [0x88, 0x13, 0x18, 0xFC, 0x70, 0x17, 0x00, 0x00] => req(Request::IrTempWarning(IrTempWarning {
        high_dc: 5000, low_dc: -1000, diff_dc: 6000, reserved: [0, 0] }));
    0x000125 [0x01, 0x00] => req(Request::IrTempOverlay(IrTempOverlay { overlay: OnOff::On, reserved: 0 }));
    0x000126 [0x01, 0xD4, 0xFE, 0x20, 0x03, 0x00] => req(Request::IrThresholdWarning(IrThresholdWarning {
        enable: OnOff::On, reference_dc: -300, float_dc: 800, reserved: 0 }));
    // ---- 3.2.3 visible
    0x000200 [0x01, 0x00] => req(Request::VisibleParams(VisibleParamsQuery { command: 1, reserved: 0 }));
    0x010200 [0x00, 0x00, 0x15, 0x26, 0x02, 0x05, 0x00, 0x00, 0x10, 0x03, 0x09, 0x32, 0x94, 0x05, 0x02, 0x21, 0x03]
        => ack(Ack::VisibleParams(VisibleParams {
        code: OK, photo_resolution: PhotoResolution::R4000x3000, video_resolution: VideoResolution::R4k,
        video_bitrate: 2, white_balance: WhiteBalance::Daylight, reserved: [0, 0], ev: Ev::Plus1,
        iso: Iso::Iso400, shutter: Shutter::S1_1000, zoom_fine: 50, backlight: 0x94, strong_light: 0x05,
        ae_lock: AeLock::Off, osd_flicker: OsdFlicker(0x21), metering: Metering::Average }));
    0x000201 [0x00, 0x26] => req(Request::VideoResolution(VideoResolutionSetting { start: 0, resolution: VideoResolution::R4k }));
    0x000202 [0x00, 0x14] => req(Request::PhotoResolution(PhotoResolutionSetting { start: 0, resolution: PhotoResolution::R8000x6000 }));
    0x000203 [0x00, 0x07] => req(Request::Iso(IsoSetting { start: 0, iso: Iso::Iso6400 }));
    0x000204 [0x00, 0x0E] => req(Request::Shutter(ShutterSetting { start: 0, shutter: Shutter::S1_8000 }));
    0x000205 [0x00, 0x23] => req(Request::Ev(EvSetting { start: 0, ev: Ev::Minus2 }));
    0x000206 [0x00, 0x05, 0x00, 0x00] => req(Request::WhiteBalance(WhiteBalanceSetting {
        start: 0, white_balance: WhiteBalance::Daylight, reserved: [0, 0] }));
    0x000207 [0x00, 0x03] => req(Request::AntiFlicker(AntiFlickerSetting { start: 0, mode: AntiFlicker::Hz60 }));
    0x000208 [0x00, 0x01, 0x4B] => req(Request::StrongLight(StrongLightSetting { start: 0, enable: Toggle::On, value: 75 }));
    0x000209 [0x00, 0x02, 0x00] => req(Request::Backlight(BacklightSetting { start: 0, enable: Toggle::Off, value: 0 }));
    0x00020A [0x00, 0x01] => req(Request::AeLock(AeLockSetting { start: 0, lock: AeLock::On }));
    0x00020B [0x00, 0x02] => req(Request::Metering(MeteringSetting { start: 0, mode: Metering::Zone }));
    // ---- 3.2.4 common
    0x000300 [0x01, 0x00] => req(Request::CaptureMode(CaptureModeSetting { mode: CaptureMode::Video, reserved: 0 }));
    0x000301 [0x02, 0x07, 0x03, 0x00] => req(Request::PhotoParams(PhotoParams {
        mode: PhotoMode::TimeLapse, timelapse_s: 7, burst_count: 3, reserved: 0 }));
    0x000302 [0x03, 0x00,
              b's', b'u', b'r', b'v', b'e', b'y', 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
              b'I', b'M', b'G', b'_', b'0', b'0', b'0', b'1', 0, 0, 0, 0, 0, 0, 0, 0,
              0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0] => req(Request::TakePhoto(TakePhoto {
        sensors: PhotoSensors::Both, action: ShootAction::Start, folder: text("survey"), name: text("IMG_0001") }));
    0x020302 [0x02, 0x02, 0x05, 0x00, 0x00, 0x00, 0x00] => status(Status::TakePhoto(PhotoStatus {
        sensors: PhotoSensors::Visible, state: PhotoState::Burst, burst_count: 5, reserved: [0; 3] }));
    0x000303 [0x04, 0x01,
              0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
              b'c', b'l', b'i', b'p', 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
              0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0] => req(Request::Record(Record {
        sensors: RecordSensors::Stream, action: RecordAction::Start, folder: Text::default(), name: text("clip") }));
    0x020303 [0x01, 0x01, 0x3C, 0x00, 0x00, 0x00, 0x00] => status(Status::Record(RecordStatus {
        sensors: RecordSensors::Infrared, state: RecordState::Recording, elapsed_s: 60, reserved: [0; 3] }));
    0x000304 [0x00, 0x2D, 0x00] => req(Request::HybridZoom(HybridZoom { start: 0, zoom_x10: 45 }));
    0x010304 [0x00, 0x00] => ack(Ack::HybridZoom(HybridZoomAck { code: OK }));
    0x020304 [0x01, 0x00] => status(Status::HybridZoom(ZoomStatus { state: ZoomState::Zooming, reserved: 0 }));
    0x000306 [0x03, 0x00] => req(Request::ContinuousZoom(ContinuousZoom { control: ZoomControl::StepIn, reserved: 0 }));
    0x000307 [0x02, 0x17, 0x64, 0x00, 0x10, 0x27,
              b'a', 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
              b'b', 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
              0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0] => req(Request::AccurateShoot(AccurateShoot {
        sensors: PhotoSensors::Visible, resolution: PhotoResolution::R5664x4248, zoom_x10: 100,
        focal_length: 10000, folder: text("a"), name: text("b") }));
    0x020307 [0x02, 0x0C, 0x00, 0x00, 0x00, 0x00, 0x00] => status(Status::AccurateShoot(AccurateShootStatus {
        sensors: PhotoSensors::Visible, state: PhotoState::AccurateReshoot, reserved: [0; 5] }));
    0x000308 [0x06, 0x00] => req(Request::StreamBitrate(StreamBitrateSetting { bitrate: StreamBitrate::M12, reserved: 0 }));
    0x00030A [0x01, 0x00] => req(Request::OutputResolution(OutputResolutionSetting {
        resolution: OutputResolution::P1080Fps30, reserved: 0 }));
    0x00030B [0x01, 0x00] => req(Request::OutputCodec(OutputCodecSetting { codec: VideoCodec::H265, reserved: 0 }));
    0x00030C [0x01, 0x00] => req(Request::TfUpgrade(TfUpgrade { command: 1, reserved: 0 }));
    0x02030C [0x01, 0x00] => status(Status::TfUpgrade(TfUpgradeStatus { state: TfUpgradeState::Upgrading, reserved: 0 }));
    0x00030D [0x01, 0x00] => req(Request::FormatSd(FormatSd { command: 1, reserved: 0 }));
    0x02030D [0x03, 0x00, 0x00] => status(Status::FormatSd(FormatStatus { state: FormatState::Unavailable, reserved: [0, 0] }));
    0x00030E [0x00, 0xA8, 0xDA, 0x76, 0x9B, 0x01, 0x00, 0x00, 0x20, 0xFE, 0xFF, 0xFF, 0x00, 0x00, 0x00, 0x00]
        => req(Request::TimeSync(TimeSync { unix_ms: 1_767_225_600_000, tz_minuteswest: -480, tz_dsttime: 0 }));
    0x00030F [0x01, 0x00] => req(Request::FactoryReset(FactoryReset { command: 1, reserved: 0 }));
    0x000310 [0x01, 0x0D, 0x2D, 0x1E, 0xE7, 0x03] => req(Request::GpsRequest(GpsRequest {
        lens_enable: 1, hour: 13, minute: 45, second: 30, millisecond: 999 }));
    0x010310 [0x00, 0x00, 0x0D, 0x2D, 0x1E, 0xE7, 0x03, 0x70, 0xDA, 0x60, 0x45, 0x60, 0x96, 0xC9, 0x17,
              0xB5, 0x04, 0x0B, 0x02, 0xD8, 0xDC, 0x96, 0x00, 0xD4, 0xFE] => ack(Ack::GpsRequest(GpsReply {
        code: OK, hour: 13, minute: 45, second: 30, millisecond: 999, lon_e7: 1_163_975_280,
        lat_e7: 399_087_200, rel_alt_dm: 1205, alt_msl_dm: 523, yaw_cdeg: -9000, roll_cdeg: 150,
        pitch_cdeg: -300 }));
    0x000311 [0x00, 0xC0, 0xA8, 0x90, 0x40, 0xFF, 0xFF, 0xFF, 0x00, 0xC0, 0xA8, 0x90, 0x01] => req(Request::SetIp(SetIp {
        mode: IpMode::Static, address: [192, 168, 144, 64], netmask: [255, 255, 255, 0], gateway: [192, 168, 144, 1] }));
    0x000312 [0x01, 0x00] => req(Request::GetIp(IpQuery { command: 1, reserved: 0 }));
    0x010312 [0x00, 0x00, 0xC0, 0xA8, 0x90, 0x40, 0xFF, 0xFF, 0xFF, 0x00, 0xC0, 0xA8, 0x90, 0x01] => ack(Ack::GetIp(IpConfigAck {
        code: OK, address: [192, 168, 144, 64], netmask: [255, 255, 255, 0], gateway: [192, 168, 144, 1] }));
    0x000313 [0x04, 0x64, 0x00, 0xC8, 0x00, 0x2C, 0x01, 0x90, 0x01, 0x00] => req(Request::Focus(Focus {
        mode: FocusMode::Area, x0: 100, y0: 200, x1: 300, y1: 400, reserved: 0 }));
    0x000314 [0x01, 0x00, 0x00] => req(Request::Watermark(Watermark { enable: OnOff::On, reserved: [0, 0] }));
    0x000316 [0x01, 0x00] => req(Request::Shutdown(Shutdown { command: 1, reserved: 0 }));
    0x000317 [0x01, 0x00] => req(Request::CameraVersion(CameraVersionQuery { command: 1, reserved: 0 }));
    0x010317 [0x00, 0x00, 0x02, 0x01, 0x07] => ack(Ack::CameraVersion(CameraVersionAck {
        code: OK, version: Version { major: 2, minor: 1, patch: 7 } }));
    0x000318 [0x07, 0x00] => req(Request::ImageMode(ImageModeSetting { mode: ImageMode::Split, reserved: 0 }));
    0x000319 [0x01, 0x00, 0x00, 0x02, 0x05, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00] => req(Request::AiRecognition(AiRecognition {
        enable: Toggle::On, model: 0, classes: [0, 2, 5, 0, 0, 0, 0, 0, 0, 0] }));
    0x000320 [0x01, 0x06, 0x7B, 0xA8, 0xDA, 0x76, 0x9B, 0x01, 0x00, 0x00, 0x70, 0xDA, 0x60, 0x45, 0x60, 0x96,
              0xC9, 0x17, 0xB4, 0xD6, 0x01, 0x00, 0xF8, 0xFA, 0x07, 0x00, 0xD8, 0xDC, 0x96, 0x00, 0xD4, 0xFE,
              0xF0, 0x05, 0xD2, 0x05, 0x78, 0x69, 0x7C, 0x15, 0x06, 0xFF] => req(Request::TargetGps(TargetGpsRequest {
        mounts: 0x01, fix: GpsFix::RtkFixed, utc_ms: 1_767_225_600_123, lon_e7: 1_163_975_280,
        lat_e7: 399_087_200, rel_alt_mm: 120_500, alt_mm: 523_000, yaw_cdeg: -9000, roll_cdeg: 150,
        pitch_cdeg: -300, airspeed_cm_s: 1520, groundspeed_cm_s: 1490, heading_cdeg: 27000,
        throttle_cpct: 5500, climb_cm_s: -250 }));
    0x010320 [0x00, 0x00, 0x1F, 0xC8, 0xA9, 0xDA, 0x76, 0x9B, 0x01, 0x00, 0x00, 0xE0, 0xEC, 0x60, 0x45,
              0x50, 0xA1, 0xC9, 0x17, 0x24, 0xFA, 0xFF, 0xFF, 0x1C, 0xF5, 0x07, 0x00] => ack(Ack::TargetGps(TargetGpsAck {
        code: OK, mount: 0x1F, utc_ms: 1_767_225_600_456, lon_e7: 1_163_980_000, lat_e7: 399_090_000,
        rel_alt_mm: -1500, alt_mm: 521_500 }));
    0x000324 [0x01, 0x64, 0x00, 0xC8, 0x00, 0x40, 0x01, 0xF0, 0x00, 0x00] => req(Request::TrackBox(TrackBox {
        enable: Toggle::On, x: 100, y: 200, width: 320, height: 240, reserved: 0 }));
    // ---- 3.2.5 laser
    0x000400 [0x01, 0x00] => req(Request::LaserRange(LaserRange { mode: LaserMode::Single, reserved: 0 }));
    0x010400 [0x00, 0x00, 0x39, 0x30] => ack(Ack::LaserRange(LaserDistance { code: OK, distance_dm: 12345 }));
    0x000406 [0x01, 0x00] => req(Request::LaserPeriodic(LaserPeriodic { enable: OnOff::On, reserved: 0 }));
    0x020406 [0x00, 0x00, 0xF4, 0x01] => status(Status::LaserPeriodic(LaserPeriodicStatus(LaserDistance { code: OK, distance_dm: 500 })));
    // ---- 3.2.6 SBUS
    0x000500 [0xFF, 0x07, 0x00, 0x00, 0x00] => req(Request::SbusRange(SbusRange { max: 2047, min: 0, reserved: 0 }));
    0x000501 [0x00, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x00] => req(Request::SbusChannels(SbusChannels {
        channels: SbusChannelMap { stream: 0, zoom: 1, photo: 2, video: 3, pitch: 4, yaw: 5, center: 6 }, reserved: 0 }));
    0x000502 [0x01, 0x00] => req(Request::SbusConfig(SbusConfigQuery { command: 1, reserved: 0 }));
    0x010502 [0x00, 0x00, 0xD0, 0x07, 0x64, 0x00, 0x00, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x00] => ack(Ack::SbusConfig(SbusConfig {
        code: OK, max: 2000, min: 100,
        channels: SbusChannelMap { stream: 0, zoom: 1, photo: 2, video: 3, pitch: 4, yaw: 5, center: 6 }, reserved: 0 }));
};

const POD_TO_FC: Header = Header::new(Address::POD, Address::FLIGHT_CONTROLLER, 0x2A);

/// Every document layout decodes to its message and the message encodes to the frame.
fn layouts_decode_and_reencode() -> Outcome {
    for l in LAYOUTS {
        let bytes = frame(l.id, l.payload, CrcCoverage::ExcludeStx);
        let p = check!(Packet::decode(&bytes));
        let expected = (l.expected)();
        ensure_eq!((l.id, p.message), (l.id, expected));
        ensure_eq!(p.message.id().to_u32(), l.id);
        ensure_eq!(p.header, POD_TO_FC);
        ensure_eq!(p.message.payload_len(), l.payload.len());
        let mut out = [0u8; MAX_FRAME_LEN];
        let n = check!(
            Packet {
                header: POD_TO_FC,
                message: expected
            }
            .emit(&mut out)
        );
        ensure_eq!((l.id, &out[..n]), (l.id, &bytes[..]));
    }
    Ok(())
}

/// The layout table covers every base id and every kind of the catalogue.
fn layouts_cover_the_catalog() -> Outcome {
    ensure_eq!(CATALOG.len(), 75);
    for e in CATALOG {
        let has = |kind: u32| {
            LAYOUTS
                .iter()
                .any(|l| l.id == (kind << 16 | u32::from(e.base)))
        };
        ensure!(has(0), "no request layout for {:#06x}", e.base);
        ensure!(
            !e.ack || has(1) || is_plain_ack(e.base),
            "no ack layout for {:#06x}",
            e.base
        );
        ensure!(!e.status || has(2), "no status layout for {:#06x}", e.base);
        ensure!(
            e.report != e.ack,
            "{:#06x}: a report has no ack, a request has one",
            e.base
        );
    }
    Ok(())
}

fn is_plain_ack(base: u16) -> bool {
    let bytes = frame(
        0x010000 | u32::from(base),
        &[0x00, 0x00],
        CrcCoverage::ExcludeStx,
    );
    matches!(Packet::decode(&bytes), Ok(Packet { message: Message::Ack(a), .. }) if a.payload_len() == 2)
}

/// Every request of the catalogue has an ACK: a bare code decodes as that id's ACK.
fn every_request_has_an_ack() -> Outcome {
    for e in CATALOG.iter().filter(|e| e.ack) {
        let id = 0x010000 | u32::from(e.base);
        let bytes = frame(id, &[0x02, 0x04], CrcCoverage::ExcludeStx);
        let p = check!(Packet::decode(&bytes));
        let Message::Ack(a) = p.message else {
            return Err(crate::Failure::new(
                file!(),
                line!(),
                "ack",
                format_args!("{id:#08x}: {:?}", p.message),
            ));
        };
        ensure_eq!(a.base(), e.base);
        ensure_eq!(a.code().code(), AckCode::NoSdCard);
        ensure_eq!(a.name(), e.name);
    }
    Ok(())
}

/// The three K40T reference frames of docs/src/protocols/k40t.md (zoom, its ACK, a gimbal
/// attitude report; built by an independent encoder).
fn reference_frames() -> Outcome {
    let zoom = [
        0xFD, 0x03, 0x04, 0x01, 0x07, 0x02, 0x01, 0x04, 0x03, 0x00, 0x00, 0x2D, 0x00, 0xCE, 0x89,
    ];
    let zoom_ack = [
        0xFD, 0x02, 0x02, 0x01, 0x07, 0x04, 0x01, 0x04, 0x03, 0x01, 0x00, 0x00, 0xE8, 0xEB,
    ];
    let sync = [
        0xFD, 0x10, 0x04, 0x01, 0x09, 0x02, 0x01, 0x0E, 0x03, 0x00, 0x00, 0xA8, 0xDA, 0x76, 0x9B,
        0x01, 0x00, 0x00, 0x20, 0xFE, 0xFF, 0xFF, 0x00, 0x00, 0x00, 0x00, 0x7D, 0xE5,
    ];
    let p = check!(Packet::decode(&zoom));
    ensure_eq!(
        p.header,
        Header::new(Address::FLIGHT_CONTROLLER, Address::POD, 7)
    );
    ensure_eq!(
        p.message,
        Message::Request(Request::HybridZoom(HybridZoom {
            start: 0,
            zoom_x10: 45
        }))
    );
    let a = check!(Packet::decode(&zoom_ack));
    ensure_eq!(
        a.header,
        Header::new(Address::POD, Address::FLIGHT_CONTROLLER, 7)
    );
    ensure_eq!(
        a.message,
        Message::Ack(Ack::HybridZoom(HybridZoomAck {
            code: ResponseCode::new(AckCode::Ok)
        }))
    );
    let s = check!(Packet::decode(&sync));
    ensure_eq!(s.header.seq, 9);
    ensure_eq!(
        s.message,
        Message::Request(Request::TimeSync(TimeSync {
            unix_ms: 1_767_225_600_000,
            tz_minuteswest: -480,
            tz_dsttime: 0
        }))
    );
    for f in [&zoom[..], &zoom_ack[..], &sync[..]] {
        let p = check!(Packet::decode(f));
        let mut out = [0u8; MAX_FRAME_LEN];
        let n = check!(p.emit(&mut out));
        ensure_eq!(&out[..n], f);
        ensure_eq!(p.buffer_len(), f.len());
    }
    Ok(())
}

/// Coverage: the detector names the coverage a frame was built with.
fn crc_coverage_detector() -> Outcome {
    for coverage in [CrcCoverage::ExcludeStx, CrcCoverage::IncludeStx] {
        for l in LAYOUTS {
            let bytes = frame(l.id, l.payload, coverage);
            let f = check!(Frame::new_checked(&bytes[..]));
            ensure_eq!(f.detect_coverage(), Some(coverage));
            ensure_eq!(check!(Packet::decode(&bytes)).header.coverage, coverage);
            let other = match coverage {
                CrcCoverage::ExcludeStx => CrcCoverage::IncludeStx,
                CrcCoverage::IncludeStx => CrcCoverage::ExcludeStx,
            };
            ensure!(f.verify(coverage).is_ok());
            ensure!(matches!(f.verify(other), Err(Error::BadChecksum { .. })));
            // A corrupted frame matches neither.
            let mut bad = bytes.clone();
            bad[10] ^= 0x40;
            ensure_eq!(check!(Frame::new_checked(&bad[..])).detect_coverage(), None);
        }
    }
    // Emitting with a coverage produces frames the detector attributes to it.
    let p = Packet {
        header: Header {
            coverage: CrcCoverage::IncludeStx,
            ..Header::new(Address::FLIGHT_CONTROLLER, Address::POD, 1)
        },
        message: (LAYOUTS[0].expected)(),
    };
    let mut out = [0u8; MAX_FRAME_LEN];
    let n = check!(p.emit(&mut out));
    ensure_eq!(
        check!(Frame::new_checked(&out[..n])).detect_coverage(),
        Some(CrcCoverage::IncludeStx)
    );
    Ok(())
}

/// ACK response codes decode from both byte orders; encoding is big-endian.
fn ack_code_byte_order() -> Outcome {
    let codes = [
        (0x0000, AckCode::Ok),
        (0x0001, AckCode::Failure),
        (0x0002, AckCode::UnknownError),
        (0x0003, AckCode::VerificationFailed),
        (0x0004, AckCode::Timeout),
        (0x0005, AckCode::Md5Failed),
        (0x0006, AckCode::NoSpace),
        (0x0007, AckCode::LengthMismatch),
        (0x0008, AckCode::InProgress),
        (0x0009, AckCode::FileNotFound),
        (0x000A, AckCode::MergeFailed),
        (0x0201, AckCode::Recording),
        (0x0202, AckCode::CameraOpenFailed),
        (0x0203, AckCode::PhotoInProgress),
        (0x0204, AckCode::NoSdCard),
    ];
    for (value, code) in codes {
        let v: u16 = value;
        for raw in [v.to_be_bytes(), v.to_le_bytes()] {
            let bytes = frame(0x010304, &raw, CrcCoverage::ExcludeStx);
            let p = check!(Packet::decode(&bytes));
            let Message::Ack(a) = p.message else {
                return Err(crate::Failure::new(
                    file!(),
                    line!(),
                    "ack",
                    format_args!("{:?}", p.message),
                ));
            };
            ensure_eq!(a.code().code(), code);
            // Lossless: the bytes received are the bytes sent on.
            let mut out = [0u8; MAX_FRAME_LEN];
            let n = check!(p.emit(&mut out));
            ensure_eq!(&out[..n], &bytes[..]);
        }
        ensure_eq!(ResponseCode::new(code).raw, v.to_be_bytes());
    }
    ensure_eq!(
        ResponseCode { raw: [0xAB, 0xCD] }.code(),
        AckCode::Other(0xABCD)
    );
    Ok(())
}

/// Unknown ids and kinds decode to Raw and re-encode unchanged.
fn unknown_ids_are_raw() -> Outcome {
    for id in [
        0x000009u32,
        0x000315,
        0x010001,
        0x020010,
        0x030304,
        0xFF0304,
        0x00FFFF,
    ] {
        let payload = [1, 2, 3, 4, 5];
        let bytes = frame(id, &payload, CrcCoverage::ExcludeStx);
        let p = check!(Packet::decode(&bytes));
        ensure_eq!(
            p.message,
            Message::Raw(Raw {
                id: MsgId::from_u32(id),
                payload: &payload
            })
        );
        ensure_eq!(p.message.name(), "Raw");
        let mut out = [0u8; MAX_FRAME_LEN];
        let n = check!(p.emit(&mut out));
        ensure_eq!(&out[..n], &bytes[..]);
    }
    Ok(())
}

/// Short payloads are zero-extended (MAVLink v2 truncation), long ones refused.
fn payload_length_rules() -> Outcome {
    // 0x000124 with the 7-byte layout of the document's table.
    let seven = frame(
        0x000124,
        &[0x88, 0x13, 0x18, 0xFC, 0x70, 0x17, 0x00],
        CrcCoverage::ExcludeStx,
    );
    let p = check!(Packet::decode(&seven));
    ensure_eq!(
        p.message,
        Message::Request(Request::IrTempWarning(IrTempWarning {
            high_dc: 5000,
            low_dc: -1000,
            diff_dc: 6000,
            reserved: [0, 0]
        }))
    );
    // Truncated trailing zeros: a 0x000304 request with zoom 0x0100 sent as 2 bytes.
    let short = frame(0x000304, &[0x00, 0x00], CrcCoverage::ExcludeStx);
    ensure_eq!(
        check!(Packet::decode(&short)).message,
        Message::Request(Request::HybridZoom(HybridZoom {
            start: 0,
            zoom_x10: 0
        }))
    );
    let empty_ack = frame(0x010018, &[], CrcCoverage::ExcludeStx);
    ensure_eq!(
        check!(Packet::decode(&empty_ack)).message,
        Message::Ack(Ack::GimbalVersion(GimbalVersionAck::default()))
    );
    let long = frame(0x000304, &[0x00, 0x2D, 0x00, 0x00], CrcCoverage::ExcludeStx);
    ensure_eq!(Packet::decode(&long), Err(Error::BadLength));
    Ok(())
}

/// Malformed input is an error value, never a panic, for every prefix and every byte.
fn malformed_frames_are_errors() -> Outcome {
    let good = frame(0x00030E, &[0x55; 16], CrcCoverage::ExcludeStx);
    for n in 0..good.len() {
        ensure!(Packet::decode(&good[..n]).is_err(), "prefix {n} accepted");
    }
    ensure_eq!(Packet::decode(&good[1..]).err(), Some(Error::BadSync));
    ensure_eq!(Packet::decode(&[]).err(), Some(Error::Truncated));
    let mut too_long = [0u8; 16];
    too_long[0] = 0xFD;
    too_long[1] = 244;
    ensure_eq!(Packet::decode(&too_long).err(), Some(Error::BadLength));
    for i in 0..good.len() {
        for bit in 0..8 {
            let mut bad = good.clone();
            bad[i] ^= 1 << bit;
            ensure!(Packet::decode(&bad).is_err(), "flip {i}.{bit} accepted");
        }
    }
    // Output buffer too small.
    let p = check!(Packet::decode(&good));
    let mut small = [0u8; 27];
    ensure_eq!(p.emit(&mut small), Err(Error::BufferTooSmall));
    Ok(())
}

/// A stream of every layout frame, with garbage, a false sync and a corrupted frame,
/// fed one byte at a time and in one piece, yields every intact frame.
fn deframer_recovers_every_frame() -> Outcome {
    for chunk in [1usize, 7, 64, 4096] {
        let mut d = Deframer::<K40tFraming, { MAX_FRAME_LEN }>::new(K40tFraming::default());
        let mut found = 0usize;
        let mut rejected = 0usize;
        let mut expected = 0usize;
        let mut stream = heapless::Vec::<u8, 12288>::new();
        for (i, l) in LAYOUTS.iter().enumerate() {
            let f = frame(l.id, l.payload, CrcCoverage::ExcludeStx);
            match i % 4 {
                0 => {
                    let _ = stream.extend_from_slice(&[0x00, 0x13, 0xFD]);
                } // garbage + false sync
                1 => {
                    let mut bad = f.clone();
                    let last = bad.len() - 1;
                    bad[last] ^= 0xFF;
                    let _ = stream.extend_from_slice(&bad);
                }
                _ => {}
            }
            ensure!(stream.extend_from_slice(&f).is_ok());
            expected += 1;
        }
        let mut next = 0usize;
        let mut ok = true;
        for part in stream.chunks(chunk) {
            d.push(part, |ev| match ev {
                Event::Frame(f) => {
                    let want = frame(
                        LAYOUTS[next.min(LAYOUTS.len() - 1)].id,
                        LAYOUTS[next.min(LAYOUTS.len() - 1)].payload,
                        CrcCoverage::ExcludeStx,
                    );
                    ok &= f == &want[..];
                    next += 1;
                    found += 1;
                }
                Event::Rejected { .. } | Event::Skipped(_) => rejected += 1,
            });
        }
        ensure!(ok, "frames out of order or altered (chunk {chunk})");
        ensure_eq!(found, expected);
        ensure!(
            rejected >= LAYOUTS.len() / 4,
            "chunk {chunk}: {rejected} rejected"
        );
        ensure_eq!(d.stats().frames_ok as usize, expected);
    }
    Ok(())
}

/// Accessors of the bit-field types follow the document.
fn bit_fields() -> Outcome {
    let links = Links(0x10);
    ensure!(links.gimbal_ok() && !links.camera_ok());
    let t = SelfTest(0x0B);
    ensure!(t.infrared_ok() && t.telephoto_ok() && !t.wide_ok() && t.laser_ok());
    let m = MeasureConfig(0x1A);
    ensure!(m.measuring() && m.area() && !m.radiometric());
    ensure_eq!(m.digital_zoom(), 3);
    let d = SwitchLevel(0x85);
    ensure!(d.on());
    ensure_eq!(d.level(), 5);
    ensure_eq!(OsdFlicker(0x21).anti_flicker(), AntiFlicker::Hz50);
    ensure_eq!(OsdFlicker(0x21).watermark(), 1);
    ensure_eq!(MsgId::from_u32(0x020304), MsgId::new(Kind::Status, 0x0304));
    ensure_eq!(MsgId::new(Kind::Ack, 0x0310).to_bytes(), [0x10, 0x03, 0x01]);
    Ok(())
}

cases!("k40t":
    layouts_decode_and_reencode,
    layouts_cover_the_catalog,
    every_request_has_an_ack,
    reference_frames,
    crc_coverage_detector,
    ack_code_byte_order,
    unknown_ids_are_raw,
    payload_length_rules,
    malformed_frames_are_errors,
    deframer_recovers_every_frame,
    bit_fields,
);
