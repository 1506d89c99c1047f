//! K40T: the frame view (checked and unchecked, every accessor and setter), packet
//! decode/parse/emit, message and per-kind decoding and encoding, `encode::<M>` for
//! every message type, and the deframer under an opaque coverage.

use core::hint::black_box;
use protocol_core::k40t::*;
use protocol_core::wire::Writer;

/// `encode::<M>` and `Message::get::<M>` for every listed type.
macro_rules! typed {
    ($message:expr, $header:expr, $out:expr; $($t:ty),* $(,)?) => {$(
        if let Some(m) = $message.get::<$t>() {
            black_box(encode(&m, $header, $out));
        }
    )*};
}

pub fn exercise(input: &[u8], out: &mut [u8]) {
    let coverage = black_box(CrcCoverage::ExcludeStx);
    let f = Frame::new_unchecked(input);
    black_box((
        f.check_len(),
        f.payload_len(),
        f.total_len(),
        f.dst(),
        f.src(),
        f.seq(),
    ));
    black_box((f.id(), f.payload(), f.payload_ref(), f.checksum()));
    black_box((
        f.compute_checksum(coverage),
        f.verify(coverage),
        f.detect_coverage(),
    ));
    if let Ok(f) = Frame::new_checked(input) {
        black_box(Packet::parse(&f));
    }

    let mut fm = Frame::new_unchecked(&mut *out);
    let b = black_box(0u8);
    fm.set_start(b);
    fm.set_dst(Address::new(b, b));
    fm.set_seq(b);
    fm.set_src(Address::new(b, b));
    fm.set_id(MsgId::from_u32(black_box(0)));
    black_box(fm.payload_mut());
    fm.fill_checksum(coverage);
    black_box(fm.into_inner());

    let id = MsgId::from_bytes(black_box([0; 3]));
    black_box((
        MsgId::from_u32(id.to_u32()),
        id.to_bytes(),
        Kind::from_value(b),
    ));
    black_box((Request::decode(id.base, input), Ack::decode(id.base, input)));
    black_box(Status::decode(id.base, input));
    if let Ok(m) = Message::decode(id, input) {
        black_box((m.id(), m.name(), m.payload_len()));
        black_box(m.encode(&mut Writer::new(&mut *out)));
    }

    if let Ok(p) = Packet::decode(input) {
        black_box((p.buffer_len(), p.emit(&mut *out)));
        if let Message::Ack(a) = p.message {
            black_box((a.code(), a.code().code()));
        }
        let header = &p.header;
        typed!(p.message, header, &mut *out;
        GimbalStatus, GimbalAttitude, GimbalControl, GimbalControlAck, GimbalAngle,
        GimbalAngleAck, DriftCalibration, DriftCalibrationAck, DialSpeed, DialSpeedAck,
        GimbalVersionQuery, GimbalVersionAck, PointToAim, PointToAimAck, ServoOff,
        ServoOffAck, LinearCalibration, LinearCalibrationAck, SoftRestart,
        SoftRestartAck, UseFcAttitude, UseFcAttitudeAck, AccelCalibration,
        AccelCalibrationAck, Stabilization, StabilizationAck, SystemStatus, IrStatus,
        VisibleStatus, UpgradeStatus, IrParamsQuery, IrParams, IrDigitalZoom,
        IrDigitalZoomAck, IrPalette, IrPaletteAck, IrMeasurement, IrMeasurementAck,
        IrSharpness, IrSharpnessAck, IrBrightness, IrBrightnessAck, IrContrast,
        IrContrastAck, IrDenoise, IrDenoiseAck, IrEnhancement, IrEnhancementAck,
        IrPointMeasure, IrPointMeasureAck, IrAreaMeasure, IrAreaMeasureAck, IrGainMode,
        IrGainModeAck, IrTempWarning, IrTempWarningAck, IrTempOverlay, IrTempOverlayAck,
        IrThresholdWarning, IrThresholdWarningAck, VisibleParamsQuery, VisibleParams,
        VideoResolutionSetting, VideoResolutionAck, PhotoResolutionSetting,
        PhotoResolutionAck, IsoSetting, IsoAck, ShutterSetting, ShutterAck, EvSetting,
        EvAck, WhiteBalanceSetting, WhiteBalanceAck, AntiFlickerSetting, AntiFlickerAck,
        StrongLightSetting, StrongLightAck, BacklightSetting, BacklightAck,
        AeLockSetting, AeLockAck, MeteringSetting, MeteringAck, CaptureModeSetting,
        CaptureModeAck, PhotoParams, PhotoParamsAck, TakePhoto, TakePhotoAck,
        PhotoStatus, Record, RecordAck, RecordStatus, HybridZoom, HybridZoomAck,
        ZoomStatus, ContinuousZoom, ContinuousZoomAck, AccurateShoot, AccurateShootAck,
        AccurateShootStatus, StreamBitrateSetting, StreamBitrateAck,
        OutputResolutionSetting, OutputResolutionAck, OutputCodecSetting,
        OutputCodecAck, TfUpgrade, TfUpgradeAck, TfUpgradeStatus, FormatSd, FormatSdAck,
        FormatStatus, TimeSync, TimeSyncAck, FactoryReset, FactoryResetAck, GpsRequest,
        GpsReply, SetIp, SetIpAck, IpQuery, IpConfigAck, Focus, FocusAck, Watermark,
        WatermarkAck, Shutdown, ShutdownAck, CameraVersionQuery, CameraVersionAck,
        ImageModeSetting, ImageModeAck, AiRecognition, AiRecognitionAck,
        TargetGpsRequest, TargetGpsAck, TrackBox, TrackBoxAck, LaserRange,
        LaserDistance, LaserPeriodic, LaserPeriodicAck, LaserPeriodicStatus, SbusRange,
        SbusRangeAck, SbusChannels, SbusChannelsAck, SbusConfigQuery, SbusConfig        );
    }

    crate::wire::deframe::<_, MAX_FRAME_LEN>(black_box(K40tFraming::any()), input);
    crate::wire::deframe::<_, 64>(black_box(K40tFraming::any()), input);
}
