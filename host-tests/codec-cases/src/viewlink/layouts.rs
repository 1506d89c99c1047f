//! Frame data written from the document's byte tables (big-endian, distinct values per
//! field), with the message each must decode to. Written from the document, not from
//! the codec.

use protocol_core::viewlink::*;

/// Frame data as laid out by the document and the message it means.
pub struct Layout {
    pub id: u8,
    pub data: &'static [u8],
    pub expected: fn() -> Message<'static>,
}

macro_rules! layouts {
    ($($id:literal [$($b:expr),* $(,)?] => $e:expr;)*) => {
        &[$( Layout { id: $id, data: &[$($b),*], expected: || $e }, )*]
    };
}

fn text<const N: usize>(s: &str) -> Text<N> {
    Text::new(s).unwrap_or_default()
}

fn bytes<const N: usize>(b: &[u8]) -> Bytes<N> {
    Bytes::new(b).unwrap_or_default()
}

const Z7: [u8; 7] = [0; 7];

fn s1<T>(value: T) -> Setting1<T> {
    Setting1::new(value)
}

fn u(u: U) -> Message<'static> {
    Message::U(u)
}

fn v(command: VCommand, data: VData) -> Message<'static> {
    Message::V(V::new(command, data))
}

pub const T1_BYTES: [u8; 22] = [
    0xB9, 0x7A, 0x12, 0x34, 0x56, 0x78, 0x01, 0x02, 0x03, 0x04, 0x01, 0xF4, 0x12, 0x34, 0x00, 0x00,
    0x01, 0x02, 0x00, 0x00, 0xFF, 0xF6,
];

pub fn t1() -> T1 {
    T1 {
        distance_source: DistanceSource::Laser,
        gps_stage: GpsStage::Locked3d,
        gps_h_quality: 5,
        gps_v_quality: 2,
        s2_ack: true,
        n_response: NResponse::GyroDriftCalibrating,
        lat_e7: 0x1234_5678,
        lon_e7: 0x0102_0304,
        alt_m: 500,
        target_lat_e7: 0x1234_0000,
        target_lon_e7: 0x0102_0000,
        target_alt_m: -10,
    }
}

pub const F1_BYTES: [u8; 1] = [0x11];

pub fn f1() -> F1 {
    F1 {
        sensor: TrackerSensor::Ir,
        state: TrackerState::Tracking,
        reserved: 0,
    }
}

pub const B1_BYTES: [u8; 6] = [0x37, 0xFF, 0x10, 0x00, 0xF0, 0x00];

pub fn b1() -> B1 {
    B1 {
        servo: ServoCommand::FollowYaw,
        roll_raw12: 0x7FF,
        yaw_bam16: 0x1000,
        pitch_bam16: -0x1000,
    }
}

pub const D1_BYTES: [u8; 12] = [
    0xA3, 0x51, 0x01, 0x45, 0x04, 0xD2, 0x0B, 0xB8, 0x11, 0x94, 0x00, 0xC8,
];

pub fn d1() -> D1 {
    D1 {
        source: VideoSource::IrEo1Pip,
        ir_dzoom_index: 4,
        black_hot: true,
        lrf_toggle: true,
        reserved_bit: false,
        lrf_latency_ms: 20,
        record: RecordStatus::Recording,
        ir_color: IrColorMode::Rainbow,
        eo_dzoom_index: 5,
        reserved: 0,
        lrf_dm: 1234,
        vfov_cdeg: 3000,
        hfov_cdeg: 4500,
        zoom_x10: 200,
    }
}

pub const T2_BYTES: [u8; 18] = [
    0x00, 0x79, 0x9A, 0x45, 0x1E, 0x0E, 0x20, 0x00, 0x10, 0x00, 0xFF, 0x00, 0x01, 0x00, 0xA1, 0xA2,
    0xA3, 0xA4,
];

pub fn t2() -> T2 {
    T2 {
        reserved: 0,
        date: Date((15 << 11) | (3 << 7) | 26),
        time: TimeCs(4_529_678),
        gps_yaw_bam16: 0x2000,
        yaw_bam16: 0x1000,
        pitch_bam16: -256,
        roll_bam16: 256,
        reserved2: [0xA1, 0xA2, 0xA3, 0xA4],
    }
}

pub const F2_BYTES: [u8; 15] = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 0xFF, 0x9C, 0x00, 0x32];

pub fn f2() -> F2 {
    F2 {
        reserved: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11],
        yaw_px: -100,
        pitch_px: 50,
    }
}

pub const B2_BYTES: [u8; 11] = [
    0x42, 0xFF, 0xF6, 0x02, 0x00, 0x00, 0x64, 0xFF, 0x38, 0x01, 0x2C,
];

pub fn b2() -> B2 {
    B2 {
        action: ServoAction::YawCorrection,
        reserved: false,
        counter: 1,
        correction_mdeg: -10,
        roll_bam16: 0x200,
        roll_rate_cdeg_s: 100,
        yaw_rate_cdeg_s: -200,
        pitch_rate_cdeg_s: 300,
    }
}

pub const D2_BYTES: [u8; 5] = [0x29, 0x83, 0x01, 0x00, 0x14];

pub fn d2() -> D2 {
    D2 {
        sensor: D2Sensor::Ir,
        fault: 5,
        pixels: PixelFormat::K4,
        not_main: true,
        extend: ExtendKind::DigitalZoom,
        extend_value: 20,
    }
}

pub fn m_attitude() -> MAttitude {
    MAttitude {
        roll_bam16: 0x0100,
        pitch_bam16: -0x0100,
        yaw_bam16: 0x4000,
    }
}

pub fn m_gps() -> MGps {
    MGps {
        date: Date(0x799A),
        time: TimeCs(4_529_678),
        gps_yaw_bam16: 0x2000,
        position_mark: 0x0F,
        lat_e7: 0x1234_5678,
        lon_e7: -252_645_136,
        height_mm: 123_456,
        vel_north_cm_s: 500,
        vel_east_cm_s: -500,
        vdop_x100: 150,
        vel_down_cm_s: -50,
    }
}

pub const M_ATTITUDE_BYTES: [u8; 6] = [0x01, 0x00, 0xFF, 0x00, 0x40, 0x00];

pub const M_GPS_BYTES: [u8; 28] = [
    0x79, 0x9A, 0x45, 0x1E, 0x0E, 0x20, 0x00, 0x0F, 0x12, 0x34, 0x56, 0x78, 0xF0, 0xF0, 0xF0, 0xF0,
    0x00, 0x01, 0xE2, 0x40, 0x01, 0xF4, 0xFE, 0x0C, 0x00, 0x96, 0xFF, 0xCE,
];

fn ai_targets() -> AiTargets {
    AiTargets::new(
        5,
        2,
        1,
        &[
            AiTarget {
                class: TargetClass::Human,
                number: 7,
                x_px: -100,
                y_px: 50,
                length_px: 64,
                width_px: 32,
                confidence_e4: 9900,
            },
            AiTarget {
                class: TargetClass::Car,
                number: 999,
                x_px: 256,
                y_px: -256,
                length_px: 16,
                width_px: 8,
                confidence_e4: 5000,
            },
        ],
    )
    .unwrap_or_default()
}

fn rc_mapping() -> RcMapping {
    RcMapping {
        yaw: ChannelPair(0x12),
        pitch: ChannelPair(0x34),
        mode: ChannelPair(0x56),
        zoom: ChannelPair(0x78),
        focus: ChannelPair(0x9A),
        record: ChannelPair(0xBC),
        multi: ChannelPair(0xDE),
        ypmz_invert: YpmzInvert(0xFF),
        prm_invert: PrmInvert(0x7F),
    }
}

fn q() -> QueryParams {
    QueryParams { reserved: [0; 9] }
}

#[rustfmt::skip]
pub static LAYOUTS: &[Layout] = layouts! {
    // ---- 0x30 A1+C1+E1: relative angle, C1 IR / speed 5 / focus+ / single ranging, E1 search
    0x30 [0x09, 0x00, 0x64, 0x20, 0x00, 0xFF, 0x38, 0xE0, 0x00,  0x22, 0xAA,  0x1A, 0x02, 0x11]
        => Message::Control(Control {
            a1: A1::RelativeAngle(RelativeAngle { yaw_speed_ddeg_s: 100, yaw_bam16: 0x2000,
                pitch_speed_ddeg_s: -200, pitch_bam16: -0x2000 }),
            c1: C1 { sensor: Sensor::Ir, zoom_speed: 5, operation: OperationCommand::FocusUp, lrf: LrfCommand::Single },
            e1: E1 { source: TrackingSource::Ir, param1: 3, command: TrackingCommand::Search, param2: 0x11 } });
    // ---- 0x32 A1+C1+E1+S1: 720° angle, take picture + stop ranging, AI on, fixed point
    0x32 [0x1B, 0x10, 0x00, 0xF0, 0x00, 0x00, 0x00, 0x00, 0x00,  0xA4, 0xC1,  0x01, 0x05, 0x01,
          0x01, 0x00, 0x12, 0x34, 0x56, 0x78, 0xFF, 0x00, 0x00, 0x00, 0x00, 0x01, 0xE2, 0x40]
        => Message::ControlTgcc(ControlTgcc {
            a1: A1::AbsoluteAngle720(AbsoluteAngle720 { yaw_bam14: 4096, pitch_bam14: -4096, reserved: [0; 4] }),
            c1: C1 { sensor: Sensor::Eo1, zoom_speed: 0, operation: OperationCommand::TakePicture, lrf: LrfCommand::Stop },
            e1: E1 { source: TrackingSource::Eo1, param1: 0, command: TrackingCommand::AiDetection, param2: 1 },
            s1: S1::FixedPoint(FixedPoint { reserved: 0, lat_e7: 0x1234_5678, lon_e7: -0x0100_0000, height_mm: 123_456 }) });
    // ---- 0x1A A1 alone: every command with parameters, and plain ones
    0x1A [0x00, 0x01, 0x00, 0xAA, 0xBB, 0xCC, 0xDD, 0xEE, 0xFF]
        => Message::A1(A1::MotorOnOff(MotorOnOff { switch: MotorSwitch::On, reserved: [0xAA, 0xBB, 0xCC, 0xDD, 0xEE, 0xFF] }));
    0x1A [0x00, 0x00, 0x01, 0, 0, 0, 0, 0, 0]
        => Message::A1(A1::MotorOnOff(MotorOnOff { switch: MotorSwitch::Off, reserved: [0; 6] }));
    0x1A [0x01, 0xF8, 0x30, 0x07, 0xD0, 0x00, 0x00, 0x00, 0x00]
        => Message::A1(A1::ManualSpeed(ManualSpeed { yaw_cdeg_s: -2000, pitch_cdeg_s: 2000, reserved: [0; 4] }));
    0x1A [0x05, 0x00, 0x32, 0xFF, 0xCE, 0xC0, 0x12, 0x40, 0x00]
        => Message::A1(A1::AzimuthScan(AzimuthScan { yaw_speed: 50, pitch_speed: -50, range: 0xC012, angle_bam16: 0x4000 }));
    0x1A [0x0B, 0x3F, 0xFC, 0xC0, 0x04, 0x01, 0x02, 0x03, 0x04]
        => Message::A1(A1::AbsoluteAngle(AbsoluteAngle { yaw_bam16: 16380, pitch_bam16: -16380, reserved: [1, 2, 3, 4] }));
    0x1A [0x0D, 0x00, 0x0A, 0x07, 0x6C, 0x00, 0x14, 0x04, 0x4C]
        => Message::A1(A1::ManualRc(ManualRc { yaw_speed_ddeg_s: 10, yaw_rc_us: 1900, pitch_speed_ddeg_s: 20, pitch_rc_us: 1100 }));
    0x1A [0x0E, 0x00, 0x00, 0xFC, 0x40, 0x00, 0x05, 0x02, 0x1C]
        => Message::A1(A1::TrackClick(TrackClick { yaw_speed_cdeg_s: 0, yaw_px: -960, pitch_speed_cdeg_s: 5, pitch_px: 540 }));
    0x1A [0x10, 0xB1, 0xE0, 0, 0, 0, 0, 0, 0]
        => Message::A1(A1::GyroCorrection(GyroCorrection { bias_milli: -20000, reserved: [0; 6] }));
    0x1A [0x11, 0xF8, 0xF8, 0, 0, 0, 0, 0, 0]
        => Message::A1(A1::FrameHeadingAngle(FrameHeadingAngle { heading_ddeg: -1800, reserved: [0; 6] }));
    0x1A [0x12, 0, 0, 0, 0, 0, 0, 0, 0x09]
        => Message::A1(A1::Plain { command: ServoCommand::LookDown, params: [0, 0, 0, 0, 0, 0, 0, 9] });
    0x1A [0x20, 1, 2, 3, 4, 5, 6, 7, 8]
        => Message::A1(A1::Plain { command: ServoCommand::Other(0x20), params: [1, 2, 3, 4, 5, 6, 7, 8] });
    // ---- 0x1C C1 alone: IR2 52 mm, speed 1, thermal RAW record stop (0x55), LPCL ranging
    0x1C [0x75, 0x4F]
        => Message::C1(C1 { sensor: Sensor::Ir2_52mm, zoom_speed: 1, operation: OperationCommand::IrRawRecordStop, lrf: LrfCommand::LpclContinuous });
    // ---- 0x1E E1 alone: EO2, tracking speed 10 (2°/s)
    0x1E [0x03, 0x06, 0x0A]
        => Message::E1(E1 { source: TrackingSource::Eo2, param1: 0, command: TrackingCommand::TrackingSpeed, param2: 10 });
    // ---- 0x16 S1 alone
    0x16 [0x04, 0x00, 0x00, 0x00, 0x40, 0x00, 0xFF, 0xFF, 0xF0, 0x00, 0x01, 0x02, 0x03, 0x04]
        => Message::S1(S1::SpaceAngle(SpaceAngle { reserved: 0, yaw_bam16: 0x4000, pitch_bam16: -0x1000, reserved2: [1, 2, 3, 4] }));
    0x16 [0x05, 0x0D, 0x12, 0x34, 0x56, 0x78, 0xED, 0xCB, 0xA9, 0x88, 0xFF, 0x9C, 0x00, 0x96]
        => Message::S1(S1::Calibrate(Calibrate { sources: CalibrationSources(0x0D), lat_e7: 0x1234_5678,
            lon_e7: -0x1234_5678, yaw_error_mdeg: -100, pitch_value: 150 }));
    0x16 [0x02, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13]
        => Message::S1(S1::Plain { command: TgccCommand::Manual, params: [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13] });
    // ---- 0x31 A2+C2+E2: yaw correction with status request, laser zoom in, OSD
    0x31 [0xA2, 0xFB,  0x74, 0x05, 0x00,  0x01, 0x81, 0x05, 0x00, 0x01]
        => Message::RareControl(RareControl {
            a2: A2 { action: ServoAction::YawCorrection, request_status: true, counter: 2, adjustment_mdeg: -5 },
            c2: C2::Laser(LaserControl { command: LaserCommand::ZoomIn, reserved: 0 }),
            e2: E2::SetOsd(E2Osd { flags: OsdWord(0x8105), hotspot: 1 }) });
    // ---- 0x33 A2+C2+E2+S2: pitch correction, power control, rectangle corner, S2
    0x33 [0xC1, 0x07,  0x75, 0x40, 0x09,  0x0B, 0xFC, 0x40, 0xFD, 0xE4,  0x01, 0xAA, 0xBB, 0xCC, 0xDD]
        => Message::RareControlTgcc(RareControlTgcc {
            a2: A2 { action: ServoAction::PitchCorrection, request_status: false, counter: 3, adjustment_mdeg: 7 },
            c2: C2::Power(PowerControl(0x4009)),
            e2: E2::RectTopLeft(Point { x_px: -960, y_px: -540 }),
            s2: S2 { command: S2Command::SetTakeoffAltitude, params: [0xAA, 0xBB, 0xCC, 0xDD] } });
    // ---- 0x2A A2 alone
    0x2A [0x41, 0x9C]
        => Message::A2(A2 { action: ServoAction::PitchCorrection, request_status: false, counter: 1, adjustment_mdeg: -100 });
    // ---- 0x2C C2 alone: every command with a parameter, and a plain one
    0x2C [0x08, 0x00, 0x78] => Message::C2(C2::MaxEoDzoom(Zoom { zoom_x10: 120 }));
    0x2C [0x14, 0x00, 0x55] => Message::C2(C2::AlarmTemperature(AlarmTemperature { celsius: 85 }));
    0x2C [0x1E, 0x00, 0x19] => Message::C2(C2::TemperatureInterval(TemperatureInterval { frames: 25 }));
    0x2C [0x4E, 0x00, 0x05] => Message::C2(C2::Reboot(Reboot { action: RebootAction::Reboot, reserved: 1 }));
    0x2C [0x50, 0x01, 0x02] => Message::C2(C2::SetBrightness(SettingValue { value: 0x0102 }));
    0x2C [0x51, 0x03, 0x04] => Message::C2(C2::SetContrast(SettingValue { value: 0x0304 }));
    0x2C [0x52, 0x05, 0x06] => Message::C2(C2::SetAperture(SettingValue { value: 0x0506 }));
    0x2C [0x53, 0x00, 0xC8] => Message::C2(C2::SetEoZoom(Zoom { zoom_x10: 200 }));
    0x2C [0x54, 0x07, 0x08] => Message::C2(C2::SetFocus(SettingValue { value: 0x0708 }));
    0x2C [0x55, 0x09, 0x0A] => Message::C2(C2::SetGain(SettingValue { value: 0x090A }));
    0x2C [0x56, 0x00, 0x28] => Message::C2(C2::SetIrZoom(Zoom { zoom_x10: 40 }));
    0x2C [0x74, 0x06, 0x00] => Message::C2(C2::Laser(LaserControl { command: LaserCommand::ZoomSyncEo, reserved: 0 }));
    0x2C [0x76, 0x00, 0x0F] => Message::C2(C2::RecordSegment(RecordSegment { minutes: 15 }));
    0x2C [0x17, 0x00, 0x00] => Message::C2(C2::Plain { command: C2Command::DefogOn, params: [0, 0] });
    // ---- 0x2E E2 alone
    0x2E [0x0C, 0x03, 0xC0, 0x02, 0x1C] => Message::E2(E2::RectBottomRight(Point { x_px: 960, y_px: 540 }));
    0x2E [0x0A, 0x00, 0x10, 0xFF, 0xF0] => Message::E2(E2::TrackPoint(Point { x_px: 16, y_px: -16 }));
    0x2E [0x1F, 0x00, 0xFF, 0x80, 0x00] => Message::E2(E2::OsdColor(OsdColor { color: 0x00FF_8000 }));
    0x2E [0x21, 0x00, 0x00, 0x00, 0x00] => Message::E2(E2::Plain { command: TrackingCommand2::IdentifyOff, params: [0; 4] });
    // ---- 0x26 S2 alone
    0x26 [0x03, 0x01, 0x02, 0x03, 0x04]
        => Message::S2(S2 { command: S2Command::SaveTargetAltitude, params: [1, 2, 3, 4] });
    // ---- 0x01 U: every command of 3.1 and of the appendix table
    0x01 [0x02, 0x10, 0x24, 0x3E, 0x7E, 0x81, 0xF9, 0xED, 0xFF, 0x01] => u(U::ProtocolControl(ProtocolControl {
        lrf: LrfProtocol::M1800, gps: GpsProtocol::On, gimbal_3e: Gimbal3eProtocol::On,
        tracking_7e: Tracking7eProtocol::On, visca: ViscaProtocol::On, target_position: TargetPositionProtocol::On,
        mavlink: MavlinkProtocol::On, pelco_d: PelcoProtocol::On, feedback: FeedbackWrapping::Wrapped }));
    0x01 [0x02, 0x3F, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::ProtocolControl(ProtocolControl {
        lrf: LrfProtocol::M3000, gps: GpsProtocol::Off, gimbal_3e: Gimbal3eProtocol::Off,
        tracking_7e: Tracking7eProtocol::Off, visca: ViscaProtocol::Off, target_position: TargetPositionProtocol::Off,
        mavlink: MavlinkProtocol::Off, pelco_d: PelcoProtocol::Off, feedback: FeedbackWrapping::Direct }));
    0x01 [0x04, 0xF8, 0x1E, 0, 0, 0, 0, 0, 0, 0] => u(U::TimeZone(TimeZone { hours: -8, minutes: 30, reserved: Z7 }));
    0x01 [0x05, 0xA5, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::Osd1(s1(OsdFlags(0xA5))));
    0x01 [0x06, 0xE2, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::MagneticDeclinationDdeg(s1(-30)));
    0x01 [0x07, 0x81, 0, 0, 0, 0, 0, 0, 0, 1] => u(U::Osd2(Setting1 { value: OsdTypeFlags(0x81), reserved: [0, 0, 0, 0, 0, 0, 0, 1] }));
    0x01 [0x08, 0x09, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::BaudRate(s1(BaudRate::B500000)));
    0x01 [0x09, 0x01, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::EoDigitalZoom(s1(OnOff::On)));
    0x01 [0x0A, 0xFF, 0xEC, 0, 0, 0, 0, 0, 0, 0] => u(U::AlarmTemperatureC(Setting2 { value: -20, reserved: Z7 }));
    0x01 [0x0B, 0x12, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::AlarmTemperatureHigh(s1(0x12)));
    0x01 [0x0C, 0x00, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::Tracking(s1(OnOff::Off)));
    0x01 [0x0D, 0x01, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::LrfDefaultMode(s1(LrfMode::Continuous)));
    0x01 [0x0E, 0x01, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::RecordResolution(s1(RecordResolution::K4)));
    0x01 [0x0F, 0x31, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::TargetPosition(s1(TargetCalcFlags(0x31))));
    0x01 [0x10, 0x12, 0x34, 0x56, 0x78, 0x9A, 0xBC, 0xDE, 0xFF, 0x7F] => u(U::RcMapping(rc_mapping()));
    0x01 [0x11, 0x21, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::YawChannel(s1(ChannelPair(0x21))));
    0x01 [0x12, 0x43, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::PitchChannel(s1(ChannelPair(0x43))));
    0x01 [0x13, 0x65, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::CenterSpeedChannel(s1(ChannelPair(0x65))));
    0x01 [0x14, 0x87, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::ZoomChannel(s1(ChannelPair(0x87))));
    0x01 [0x15, 0xA9, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::PipColorChannel(s1(ChannelPair(0xA9))));
    0x01 [0x16, 0xCB, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::RecordShootChannel(s1(ChannelPair(0xCB))));
    0x01 [0x17, 0xED, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::TrackingChannel(s1(ChannelPair(0xED))));
    0x01 [0x18, 0x02, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::FocusHold(s1(2)));
    0x01 [0x19, 0x03, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::CameraType(s1(3)));
    0x01 [0x1A, 0xFE, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::YpmzInvert(s1(YpmzInvert(0xFE))));
    0x01 [0x1B, 0xFC, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::PrmInvert(s1(PrmInvert(0xFC))));
    0x01 [0x1E, 0x3C, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::TemplateSize(s1(0x3C)));
    0x01 [0x1F, 0xFC, 0x18, 0, 0, 0, 0, 0, 0, 0] => u(U::PitchDeclinationCdeg(Setting2 { value: -1000, reserved: Z7 }));
    0x01 [0x20, 0x0A, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::OutputControl(s1(OutputControl(0x0A))));
    0x01 [0x21, 0x10, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::Z40kResolutionOsd(s1(0x10)));
    0x01 [0x22, 0x80, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::Z40kDateOsd(s1(0x80)));
    0x01 [0x23, 0x40, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::Z40kAllOsd(s1(0x40)));
    0x01 [0x24, 0xB0, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::Z40kSdOsd(s1(0xB0)));
    0x01 [0x25, 0xC0, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::Z40kRecordTimeOsd(s1(0xC0)));
    0x01 [0x26, 0x01, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::Z40kRecordModeOsd(s1(0x01)));
    0x01 [0x27, 0x0F, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::TrackPitchPX10(s1(15)));
    0x01 [0x28, 0x05, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::TrackPitchIX1000(s1(5)));
    0x01 [0x29, 0x02, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::TrackPitchDX10(s1(2)));
    0x01 [0x2A, 0x14, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::TrackYawPX10(s1(20)));
    0x01 [0x2B, 0x03, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::TrackYawIX1000(s1(3)));
    0x01 [0x2C, 0x01, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::TrackYawDX10(s1(1)));
    0x01 [0x2D, 0x01, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::TrackMode(s1(TrackMode::Fast)));
    0x01 [0x2E, 0x22, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::Flip(s1(FlipControl(0x22))));
    0x01 [0x2F, 0x03, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::IrRawRecord(s1(IrRawRecord(0x03))));
    0x01 [0x30, 0x03, 0xE8, 0, 0, 0, 0, 0, 0, 0] => u(U::AttitudeIntervalMs(Setting2 { value: 1000, reserved: Z7 }));
    0x01 [0x31, 0x03, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::AttitudeIntervalHigh(s1(3)));
    0x01 [0x32, 0x01, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::MavlinkSystemId(s1(1)));
    0x01 [0x33, 0x0A, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::ShootInterval100ms(s1(10)));
    0x01 [0x34, 0xE2, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::TimeZoneMinute(s1(-30)));
    0x01 [0x82, 0, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::QueryProtocolControl(q()));
    0x01 [0x84, 0, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::QueryTimeZone(q()));
    0x01 [0x85, 0, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::QueryOsd(q()));
    0x01 [0x88, 0, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::QueryBaudRate(q()));
    0x01 [0x8A, 0, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::QueryAlarmTemperature(q()));
    0x01 [0x90, 0, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::QueryRcMapping(q()));
    0x01 [0xD0, 0, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::QueryFirmware(q()));
    0x01 [0xE4, 0, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::QueryModel(q()));
    0x01 [0xEE, 0, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::QuerySerialNumber(q()));
    0x01 [0x00, 0, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::Plain { command: UCommand::None, params: [0; 9] });
    0x01 [0x1C, 1, 0, 0, 0, 0, 0, 0, 0, 0] => u(U::Plain { command: UCommand::Other(0x1C), params: [1, 0, 0, 0, 0, 0, 0, 0, 0] });
    // ---- 0x02 V: every parameter kind, both command sets, trailing and short data
    0x02 [0x02, 0x10, 0x24, 0x00, 0x00, 0x00, 0x00, 0xED, 0x00, 0x01] => v(VCommand::ProtocolControl, VData::ProtocolControl(ProtocolControl {
        lrf: LrfProtocol::M1800, gps: GpsProtocol::On, gimbal_3e: Gimbal3eProtocol::Off,
        tracking_7e: Tracking7eProtocol::Off, visca: ViscaProtocol::Off, target_position: TargetPositionProtocol::Off,
        mavlink: MavlinkProtocol::On, pelco_d: PelcoProtocol::Off, feedback: FeedbackWrapping::Wrapped }));
    0x02 [0x84, 0xF8, 0x00] => v(VCommand::QueryTimeZone, VData::TimeZone(VTimeZone { hours: -8, minutes: 0 }));
    0x02 [0x05, 0xA5, 0x81] => v(VCommand::Osd, VData::Osd(VOsd { osd1: OsdFlags(0xA5), osd2: OsdTypeFlags(0x81) }));
    0x02 [0x88, 0x06] => v(VCommand::QueryBaudRate, VData::BaudRate(BaudRate::B115200));
    0x02 [0x0A, 0x00, 0x3C, 0x00, 0x00] => v(VCommand::AlarmTemperature, VData::AlarmTemperature(VAlarmTemperature { celsius: 60, reserved: [0, 0] }));
    0x02 [0x90, 0x12, 0x34, 0x56, 0x78, 0x9A, 0xBC, 0xDE, 0xFF, 0x7F] => v(VCommand::QueryRcMapping, VData::RcMapping(rc_mapping()));
    0x02 [0xD0, b'S', b'2', b'0', b'2', b'3', b'0', b'4', b'1', b'5', 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]
        => v(VCommand::QueryFirmware, VData::Firmware(text("S20230415")));
    0x02 [0xFC, b'V', b'3', b'.', b'4', b'.', b'4', 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]
        => v(VCommand::Firmware, VData::Firmware(text("V3.4.4")));
    0x02 [0xE4, b'Z', b'4', b'0', b'K', 0, 0, 0, 0, 0, 0] => v(VCommand::QueryModel, VData::Model(text("Z40K")));
    0x02 [0xFD, b'A', b'4', b'0', b'T', b'R', 0, 0, 0, 0, 0] => v(VCommand::Model, VData::Model(text("A40TR")));
    0x02 [0xFE, b'V', b'P', b'2', b'0', b'2', b'3', b'-', b'0', b'0', b'0', b'1', 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]
        => v(VCommand::SerialNumber, VData::SerialNumber(text("VP2023-0001")));
    0x02 [0xEE, b'S', b'N', b'1', 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]
        => v(VCommand::QuerySerialNumber, VData::SerialNumber(text("SN1")));
    0x02 [0x08, 0x02, 0xAB, 0xCD] => Message::V(V { command: VCommand::BaudRate,
        data: VData::BaudRate(BaudRate::B9600), trailing: bytes(&[0xAB, 0xCD]) });
    0x02 [0xE4, b'Z', b'4'] => v(VCommand::QueryModel, VData::Other(bytes(b"Z4")));
    0x02 [0x00, 1, 2, 3] => v(VCommand::None, VData::Other(bytes(&[1, 2, 3])));
    0x02 [0x77] => v(VCommand::Other(0x77), VData::Other(Bytes::default()));
    // ---- 0x40 / 0x42 T1+F1+B1+D1, 0x41 T2+F2+B2+D2
    0x40 [0xB9, 0x7A, 0x12, 0x34, 0x56, 0x78, 0x01, 0x02, 0x03, 0x04, 0x01, 0xF4, 0x12, 0x34, 0x00,
          0x00, 0x01, 0x02, 0x00, 0x00, 0xFF, 0xF6,  0x11,  0x37, 0xFF, 0x10, 0x00, 0xF0, 0x00,
          0xA3, 0x51, 0x01, 0x45, 0x04, 0xD2, 0x0B, 0xB8, 0x11, 0x94, 0x00, 0xC8]
        => Message::Status(Status { t1: t1(), f1: f1(), b1: b1(), d1: d1() });
    0x42 [0xB9, 0x7A, 0x12, 0x34, 0x56, 0x78, 0x01, 0x02, 0x03, 0x04, 0x01, 0xF4, 0x12, 0x34, 0x00,
          0x00, 0x01, 0x02, 0x00, 0x00, 0xFF, 0xF6,  0x11,  0x37, 0xFF, 0x10, 0x00, 0xF0, 0x00,
          0xA3, 0x51, 0x01, 0x45, 0x04, 0xD2, 0x0B, 0xB8, 0x11, 0x94, 0x00, 0xC8]
        => Message::StatusOsd(StatusOsd(Status { t1: t1(), f1: f1(), b1: b1(), d1: d1() }));
    0x41 [0x00, 0x79, 0x9A, 0x45, 0x1E, 0x0E, 0x20, 0x00, 0x10, 0x00, 0xFF, 0x00, 0x01, 0x00, 0xA1,
          0xA2, 0xA3, 0xA4,  1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 0xFF, 0x9C, 0x00, 0x32,
          0x42, 0xFF, 0xF6, 0x02, 0x00, 0x00, 0x64, 0xFF, 0x38, 0x01, 0x2C,  0x29, 0x83, 0x01, 0x00, 0x14]
        => Message::RareStatus(RareStatus { t2: t2(), f2: f2(), b2: b2(), d2: d2() });
    // ---- single status blocks
    0x17 [0xB9, 0x7A, 0x12, 0x34, 0x56, 0x78, 0x01, 0x02, 0x03, 0x04, 0x01, 0xF4, 0x12, 0x34, 0x00,
          0x00, 0x01, 0x02, 0x00, 0x00, 0xFF, 0xF6] => Message::T1(t1());
    0x1F [0x11] => Message::F1(f1());
    0x1B [0x37, 0xFF, 0x10, 0x00, 0xF0, 0x00] => Message::B1(b1());
    0x1D [0xA3, 0x51, 0x01, 0x45, 0x04, 0xD2, 0x0B, 0xB8, 0x11, 0x94, 0x00, 0xC8] => Message::D1(d1());
    0x27 [0x00, 0x79, 0x9A, 0x45, 0x1E, 0x0E, 0x20, 0x00, 0x10, 0x00, 0xFF, 0x00, 0x01, 0x00, 0xA1,
          0xA2, 0xA3, 0xA4] => Message::T2(t2());
    0x2F [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 0xFF, 0x9C, 0x00, 0x32] => Message::F2(f2());
    0x2B [0x42, 0xFF, 0xF6, 0x02, 0x00, 0x00, 0x64, 0xFF, 0x38, 0x01, 0x2C] => Message::B2(b2());
    0x2D [0x29, 0x83, 0x01, 0x00, 0x14] => Message::D2(d2());
    // ---- 0xB1 M: every group, attitude only, GPS only, none
    0xB1 [0x07, 0, 0, 0, 0, 0, 0, 0,  0x01, 0x00, 0xFF, 0x00, 0x40, 0x00,
          0x79, 0x9A, 0x45, 0x1E, 0x0E, 0x20, 0x00, 0x0F, 0x12, 0x34, 0x56, 0x78, 0xF0, 0xF0, 0xF0,
          0xF0, 0x00, 0x01, 0xE2, 0x40, 0x01, 0xF4, 0xFE, 0x0C, 0x00, 0x96, 0xFF, 0xCE]
        => Message::M(M { type_bits: 0x04, reserved: Z7, attitude: Some(m_attitude()), gps: Some(m_gps()) });
    0xB1 [0x01, 1, 2, 3, 4, 5, 6, 7,  0x01, 0x00, 0xFF, 0x00, 0x40, 0x00]
        => Message::M(M { type_bits: 0, reserved: [1, 2, 3, 4, 5, 6, 7], attitude: Some(m_attitude()), gps: None });
    0xB1 [0x06, 0, 0, 0, 0, 0, 0, 0,
          0x79, 0x9A, 0x45, 0x1E, 0x0E, 0x20, 0x00, 0x0F, 0x12, 0x34, 0x56, 0x78, 0xF0, 0xF0, 0xF0,
          0xF0, 0x00, 0x01, 0xE2, 0x40, 0x01, 0xF4, 0xFE, 0x0C, 0x00, 0x96, 0xFF, 0xCE]
        => Message::M(M { type_bits: 0x04, reserved: Z7, attitude: None, gps: Some(m_gps()) });
    0xB1 [0xE0, 0, 0, 0, 0, 0, 0, 0] => Message::M(M { type_bits: 0xE0, reserved: Z7, attitude: None, gps: None });
    // ---- 0xF3 AI, 0xF4 KLV
    0xF3 [0x05, 0x02, 0x01, 0, 0, 0, 0, 0,
          0x01, 0x00, 0x07, 0xFF, 0x9C, 0x00, 0x32, 0x00, 0x40, 0x00, 0x20, 0x26, 0xAC,
          0x00, 0x03, 0xE7, 0x01, 0x00, 0xFF, 0x00, 0x00, 0x10, 0x00, 0x08, 0x13, 0x88]
        => Message::AiTargets(ai_targets());
    0xF3 [0x00, 0x00, 0x00, 0, 0, 0, 0, 0] => Message::AiTargets(AiTargets::default());
    0xF4 [0x02, 0x01, 0x05, 0x06, 0x0E, 0x2B, 0x34, 0x02]
        => Message::Klv(Klv { total_packets: 2, packet_index: 1, valid_len: 5, data: bytes(&[0x06, 0x0E, 0x2B, 0x34, 0x02]) });
    // ---- small packets
    0x00 [0x00] => Message::Handshake(Handshake { value: 0 });
    0x10 [0x00] => Message::Heartbeat(Heartbeat { value: 0 });
    0xAC [0x30] => Message::Ack(Ack { acked_id: 0x30 });
    0xFF [0x01, 0x02, 0x03] => Message::Transparent(Transparent { data: bytes(&[1, 2, 3]) });
    0x5D [0x8B, 0x04] => Message::SdQuery(SdQuery { command: SdCommand::Query, item: SdQueryItem::RemainingCapacity });
    0x5D [0x8A, 0x00] => Message::SdQuery(SdQuery { command: SdCommand::Format, item: SdQueryItem::None });
    0xD5 [0x01, 0x0B, 0x02, 0x00, 0x00] => Message::SdFeedback(SdFeedback::Status(SdStatus {
        state: SdStateFlags(0x0B), activity: SdActivityFlags(0x02), reserved: [0, 0] }));
    0xD5 [0x02, 0x00, 0x00, 0x76, 0xC0] => Message::SdFeedback(SdFeedback::TotalCapacity(SdCapacity { mb: 30400 }));
    0xD5 [0x03, 0x00, 0x00, 0x27, 0x10] => Message::SdFeedback(SdFeedback::RemainingCapacity(SdCapacity { mb: 10000 }));
    0xD5 [0x04, 0x00, 0x01, 0x00, 0x00] => Message::SdFeedback(SdFeedback::RemainingPictures(SdPictures { count: 65536 }));
    0xD5 [0x05, 0x00, 0x00, 0x0E, 0x10] => Message::SdFeedback(SdFeedback::RemainingVideo(SdVideoTime { seconds: 3600 }));
    0x19 [0x00] => Message::IpQuery(IpQuery { command: 0 });
    0x29 [0xC0, 0xA8, 0x02, 0x77] => Message::IpSet(IpAddress { octets: [192, 168, 2, 119] });
    0x92 [0xC0, 0xA8, 0x90, 0x40] => Message::IpFeedback(IpFeedback(IpAddress { octets: [192, 168, 144, 64] }));
};
