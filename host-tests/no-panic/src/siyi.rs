//! SIYI: the frame view, packet decode (both directions and guessed), parse and emit,
//! message decoding and encoding, `encode::<M>` for every message type of both
//! directions, and the deframer with an opaque payload limit.

use core::hint::black_box;
use protocol_core::Direction;
use protocol_core::siyi::*;
use protocol_core::wire::Writer;

macro_rules! typed {
    ($message:expr, $header:expr, $out:expr; $($t:ty),* $(,)?) => {$(
        if let Some(m) = $message.get::<$t>() {
            black_box(encode(&m, $header, $out));
        }
    )*};
}

pub fn exercise(input: &[u8], out: &mut [u8]) {
    let direction = black_box(Direction::ToGimbal);
    let f = Frame::new_unchecked(input);
    black_box((
        f.check_len(),
        f.ctrl(),
        f.payload_len(),
        f.total_len(),
        f.seq(),
        f.id(),
    ));
    black_box((
        f.payload(),
        f.payload_ref(),
        f.checksum(),
        f.compute_checksum(),
        f.verify(),
    ));
    black_box((f.ctrl().direction(), f.ctrl().reserved(), f.ctrl().is_ack()));
    if let Ok(f) = Frame::new_checked(input) {
        black_box(Packet::parse(&f, direction));
    }

    let mut fm = Frame::new_unchecked(&mut *out);
    let b = black_box(0u8);
    fm.set_start(u16::from(b));
    fm.set_ctrl(Ctrl(b));
    fm.set_seq(u16::from(b));
    fm.set_id(b);
    black_box(fm.payload_mut());
    fm.fill_checksum();
    black_box(fm.into_inner());

    black_box((Request::decode(b, input), Reply::decode(b, input)));
    if let Ok(m) = Message::decode(b, input, direction) {
        black_box((m.id(), m.name(), m.payload_len(), m.direction()));
        black_box(m.encode(&mut Writer::new(&mut *out)));
    }
    black_box(Packet::decode_auto(input).map(|p| p.emit(&mut *out)));
    if let Ok(p) = Packet::decode(input, direction) {
        black_box((p.buffer_len(), p.emit(&mut *out)));
        let header = &p.header;
        typed!(p.message, header, &mut *out;
        Heartbeat, HeartbeatReply, FirmwareVersionQuery, FirmwareVersions,
        HardwareIdQuery, HardwareId, AutoFocus, AutoFocusAck, ManualZoom, ZoomRatio,
        ManualFocus, ManualFocusAck, GimbalRotation, GimbalRotationAck, Center,
        CenterAck, GimbalConfigQuery, GimbalConfig, FunctionFeedbackRequest,
        FunctionFeedback, CameraFunction, CameraFunctionReply, GimbalAttitudeQuery,
        GimbalAttitude, SetAngles, SetAnglesAck, AbsoluteZoom, AbsoluteZoomAck,
        GetStitching, Stitching, SetStitching, SetStitchingAck, PointTemperatureRequest,
        PointTemperature, BoxTemperatureRequest, BoxTemperature,
        GlobalTemperatureRequest, GlobalTemperature, LaserDistanceQuery, LaserDistance,
        MaxZoomQuery, MaxZoom, LaserTargetQuery, LaserTarget, CurrentZoomQuery,
        CurrentZoom, GimbalModeQuery, GimbalMode, GetThermalPalette, ThermalPalette,
        SetThermalPalette, SetThermalPaletteAck, CodecQuery, CodecSpecs, SetCodec,
        SetCodecAck, FcAttitude, FcAttitudeReply, FcStreamRequest, FcStreamAck,
        GimbalStreamRequest, GimbalStreamAck, MagneticEncoderQuery, MagneticEncoder,
        UtcTime, TimeAck, GetLaserState, LaserState, SetLaserState, SetLaserStateAck,
        GetThermalOutput, ThermalOutputMode, SetThermalOutput, SetThermalOutputAck,
        TemperatureFrame, TemperatureFrameAck, GetThermalGain, ThermalGain,
        SetThermalGain, SetThermalGainAck, GetThermalEnvironment, ThermalEnvironment,
        SetThermalEnvironment, SetThermalEnvironmentAck, GetEnvCorrection,
        EnvCorrection, SetEnvCorrection, SetEnvCorrectionAck, FcPosition,
        FcPositionReply, SingleAxisAngle, SingleAxisAngleAck, FormatSd, FormatSdAck,
        SoftReboot, SoftRebootAck        );
    }

    let max = black_box(DEFAULT_MAX_PAYLOAD_LEN);
    crate::wire::deframe::<_, DEFAULT_MAX_FRAME_LEN>(SiyiFraming::new(max), input);
    crate::wire::deframe::<_, 265>(SiyiFraming::new(max), input);
}
