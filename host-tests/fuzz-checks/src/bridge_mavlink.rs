//! Target `bridge_mavlink`: the bridge engine with its MAVLink FC side (gimbal device and
//! camera) driven by the fuzzer, with the properties of [`crate::bridge`]: no panic, the
//! queues within their bounds, every frame for the FC a valid MAVLink 2 frame (the
//! reference scan of [`crate::mavlink`], written from the spec), every frame for the pod a
//! valid K40T frame, and, whatever came before, a MAV_CMD_REQUEST_MESSAGE(HEARTBEAT) to the
//! gimbal after the autopilot's HEARTBEAT answered with its COMMAND_ACK.
//!
//! The frame op picks from what ArduPilot, PX4 and QGroundControl send a gimbal device and
//! camera (docs/src/bridge/mavlink.md): the autopilot's heartbeat and streams, every form
//! of GIMBAL_DEVICE_SET_ATTITUDE, the requests (new and deprecated, servable or not), the
//! camera commands, the sensors' commands and message intervals (video stream, camera
//! source, tracking, thermal range, laser, field of view), ROI to the device in its
//! frames, a MAV_CMD the dialect does not list, TIMESYNC, the camera definition's download
//! (MAVLink FTP in QGroundControl's and MAVSDK's sequences, and opcodes neither sends),
//! the extended parameters (list, read by name and index, sets of good and bad names,
//! types and values), and the catalogue's frames with arbitrary contents.

use std::sync::OnceLock;

use bridge_engine::FcProtocol;
use protocol_core::mavlink::dialect::{
    ATTITUDE_DATA, AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA, COMMAND_INT_DATA, COMMAND_LONG_DATA,
    CharArray, FILE_TRANSFER_PROTOCOL_DATA, GIMBAL_DEVICE_SET_ATTITUDE_DATA,
    GLOBAL_POSITION_INT_DATA, GPS_RAW_INT_DATA, GimbalDeviceFlags, GpsFixType, HEARTBEAT_DATA,
    MavAutopilot, MavCmd, MavFrame, MavModeFlag, MavParamExtType, MavState, MavType,
    PARAM_EXT_REQUEST_LIST_DATA, PARAM_EXT_REQUEST_READ_DATA, PARAM_EXT_SET_DATA, SYSTEM_TIME_DATA,
    TIMESYNC_DATA,
};
use protocol_core::mavlink::{Header, MAX_FRAME_LEN, MavMessage, Message, Packet, Raw, encode};

use crate::bridge::{Input, run_checked, run_config, run_with, seeds_with};
use protocol_core::k40t::{self, MessageData};

fn frame(sys: u8, comp: u8, seq: u8, msg: &MavMessage) -> Vec<u8> {
    let header = Header {
        sequence: seq,
        system_id: sys,
        component_id: comp,
    };
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = encode(msg, &header, &mut buf).expect("encode");
    buf[..n].to_vec()
}

fn long(cmd: MavCmd, p: [f32; 7], target: (u8, u8)) -> MavMessage {
    MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
        param1: p[0],
        param2: p[1],
        param3: p[2],
        param4: p[3],
        param5: p[4],
        param6: p[5],
        param7: p[6],
        command: cmd,
        target_system: target.0,
        target_component: target.1,
        confirmation: 0,
    })
}

/// The autopilot's HEARTBEAT (system 1, ArduPilot, quadrotor).
#[must_use]
pub fn autopilot_heartbeat() -> Vec<u8> {
    autopilot_heartbeat_of(1)
}

/// An ArduPilot quadrotor's HEARTBEAT from system `sys`.
#[must_use]
pub fn autopilot_heartbeat_of(sys: u8) -> Vec<u8> {
    frame(
        sys,
        1,
        0,
        &MavMessage::HEARTBEAT(HEARTBEAT_DATA {
            custom_mode: 0,
            mavtype: MavType::MAV_TYPE_QUADROTOR,
            autopilot: MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA,
            base_mode: MavModeFlag::empty(),
            system_status: MavState::MAV_STATE_STANDBY,
            mavlink_version: 3,
        }),
    )
}

/// The probe: REQUEST_MESSAGE(HEARTBEAT) from QGroundControl to 1/154.
#[must_use]
pub fn probe_request() -> Vec<u8> {
    let p = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    frame(
        255,
        190,
        9,
        &long(MavCmd::MAV_CMD_REQUEST_MESSAGE, p, (1, 154)),
    )
}

/// `f` is the gimbal's COMMAND_ACK of the probe.
#[must_use]
pub fn answers_probe(f: &[u8]) -> bool {
    matches!(
        Packet::decode(f),
        Ok(Packet { header, message: Message::Known(MavMessage::COMMAND_ACK(a)), .. })
            if header.component_id == 154
                && a.command == MavCmd::MAV_CMD_REQUEST_MESSAGE
                && a.target_system == 255
    )
}

/// A COMMAND_LONG whose MAV_CMD the dialect does not list, to 1/100.
fn unknown_command() -> Vec<u8> {
    let mut payload = vec![0u8; 33];
    payload[..4].copy_from_slice(&1.0f32.to_le_bytes());
    payload[28..30].copy_from_slice(&42_006u16.to_le_bytes());
    payload[30] = 1;
    payload[31] = 100;
    let p = Packet::new(
        Header {
            sequence: 3,
            system_id: 255,
            component_id: 190,
        },
        Message::Raw(Raw {
            id: 76,
            payload: &payload,
        }),
    );
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = p.emit(&mut buf).expect("emit");
    buf[..n].to_vec()
}

/// A FILE_TRANSFER_PROTOCOL request from QGroundControl (255/190) to 1/100.
fn ftp(seq: u16, opcode: u8, size: u8, offset: u32, data: &[u8]) -> Vec<u8> {
    ftp_from(255, seq, opcode, size, offset, data)
}

/// A FILE_TRANSFER_PROTOCOL request from system `sys` (component 190) to 1/100.
#[must_use]
pub fn ftp_from(sys: u8, seq: u16, opcode: u8, size: u8, offset: u32, data: &[u8]) -> Vec<u8> {
    let mut payload = [0u8; 251];
    payload[..2].copy_from_slice(&seq.to_le_bytes());
    payload[3] = opcode;
    payload[4] = size;
    payload[8..12].copy_from_slice(&offset.to_le_bytes());
    payload[12..12 + data.len()].copy_from_slice(data);
    let msg = MavMessage::FILE_TRANSFER_PROTOCOL(FILE_TRANSFER_PROTOCOL_DATA {
        target_network: 0,
        target_system: 1,
        target_component: 100,
        payload,
    });
    frame(sys, 190, 11, &msg)
}

/// A PARAM_EXT_SET of `name` with `value` typed `ty`, to 1/100.
fn param_set(name: &str, value: u32, ty: MavParamExtType) -> Vec<u8> {
    param_set_from(255, name, value, ty)
}

/// A PARAM_EXT_SET of `name` with `value` typed `ty`, from system `sys` (component 190)
/// to 1/100.
#[must_use]
pub fn param_set_from(sys: u8, name: &str, value: u32, ty: MavParamExtType) -> Vec<u8> {
    let mut id = [0u8; 16];
    id[..name.len()].copy_from_slice(name.as_bytes());
    let mut v = [0u8; 128];
    v[..4].copy_from_slice(&value.to_le_bytes());
    let msg = MavMessage::PARAM_EXT_SET(PARAM_EXT_SET_DATA {
        target_system: 1,
        target_component: 100,
        param_id: CharArray::from(id),
        param_value: CharArray::from(v),
        param_type: ty,
    });
    frame(sys, 190, 12, &msg)
}

/// The camera definition's download and the extended parameters, as QGroundControl and
/// MAVSDK send them, and what neither sends.
fn settings_frames() -> Vec<Vec<u8>> {
    let mut out = vec![
        // QGroundControl: open (no NUL), bursts, a hole, reset.
        ftp(1, 4, 12, 0, b"/k40t.xml.xz"),
        ftp(3, 15, 239, 0, &[]),
        ftp(13, 15, 239, 1912, &[]),
        ftp(15, 15, 239, 9999, &[]),
        ftp(17, 5, 239, 478, &[]),
        ftp(19, 2, 0, 0, &[]),
        // MAVSDK: open (with its NUL), reads, terminate.
        ftp(0, 4, 12, 0, b"k40t.xml.xz\0"),
        ftp(1, 5, 239, 239, &[]),
        ftp(2, 5, 100, 2100, &[]),
        ftp(3, 1, 0, 0, &[]),
        // A wrong path, listing, writing, a reply routed onto the link.
        ftp(5, 4, 9, 0, b"/etc/none"),
        ftp(6, 3, 1, 0, b"/"),
        ftp(7, 7, 4, 0, b"data"),
        ftp(8, 128, 0, 0, &[]),
    ];
    let gcs = |msg: MavMessage| frame(255, 190, 13, &msg);
    out.push(gcs(MavMessage::PARAM_EXT_REQUEST_LIST(
        PARAM_EXT_REQUEST_LIST_DATA {
            target_system: 1,
            target_component: 100,
        },
    )));
    for (name, index) in [("CAM_EV", -1), ("", 7), ("", 200), ("NO_SUCH", -1)] {
        let mut id = [0u8; 16];
        id[..name.len()].copy_from_slice(name.as_bytes());
        out.push(gcs(MavMessage::PARAM_EXT_REQUEST_READ(
            PARAM_EXT_REQUEST_READ_DATA {
                param_index: index,
                target_system: 1,
                target_component: 100,
                param_id: CharArray::from(id),
            },
        )));
    }
    let u8t = MavParamExtType::MAV_PARAM_EXT_TYPE_UINT8;
    let u32t = MavParamExtType::MAV_PARAM_EXT_TYPE_UINT32;
    for (name, value, ty) in [
        ("CAM_ISO", 3, u8t),
        ("CAM_ISO", 0, u8t),
        ("CAM_MODE", 1, u32t),
        ("CAM_PHOTOMODE", 1, u8t),
        ("CAM_BURST", 5, u8t),
        ("IR_DENOISE_LV", 70, u8t),
        ("CAM_HLSUPP", 1, u8t),
        ("CAM_BACKLIGHT", 1, u8t),
        ("IR_TEMP_OSD", 1, u8t),
        ("CAM_ISO", 3, u32t),
        ("CAM_ISO", 99, u8t),
        ("NO_SUCH", 1, u8t),
        ("CAM_MODE", 0x1_0000, u32t),
    ] {
        out.push(param_set(name, value, ty));
    }
    out
}

/// The FC frames the frame op picks from.
#[must_use]
pub fn fc_frames() -> &'static [Vec<u8>] {
    static FRAMES: OnceLock<Vec<Vec<u8>>> = OnceLock::new();
    FRAMES.get_or_init(|| {
        let mut out = vec![autopilot_heartbeat()];
        let ap = |msg: MavMessage| frame(1, 1, 5, &msg);
        out.push(ap(MavMessage::SYSTEM_TIME(SYSTEM_TIME_DATA {
            time_unix_usec: 1_795_428_000_123_456,
            time_boot_ms: 60_000,
        })));
        out.push(ap(MavMessage::SYSTEM_TIME(SYSTEM_TIME_DATA {
            time_unix_usec: 0,
            time_boot_ms: 61_000,
        })));
        for fix in [
            GpsFixType::GPS_FIX_TYPE_3D_FIX,
            GpsFixType::GPS_FIX_TYPE_NO_FIX,
        ] {
            out.push(ap(MavMessage::GPS_RAW_INT(GPS_RAW_INT_DATA {
                fix_type: fix,
                lat: 473_977_420,
                lon: 85_455_940,
                ..GPS_RAW_INT_DATA::default()
            })));
        }
        out.push(ap(MavMessage::GLOBAL_POSITION_INT(
            GLOBAL_POSITION_INT_DATA {
                time_boot_ms: 60_100,
                lat: 473_977_420,
                lon: 85_455_940,
                alt: 488_000,
                relative_alt: 58_000,
                vx: 565,
                vy: 565,
                vz: 0,
                hdg: 4500,
            },
        )));
        out.push(ap(MavMessage::ATTITUDE(ATTITUDE_DATA {
            time_boot_ms: 60_100,
            roll: 0.1,
            pitch: -0.05,
            yaw: 0.785,
            rollspeed: 0.0,
            pitchspeed: 0.0,
            yawspeed: 0.2,
        })));
        out.push(ap(MavMessage::AUTOPILOT_STATE_FOR_GIMBAL_DEVICE(
            AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA {
                q: [0.92, 0.0, 0.0, 0.38],
                angular_velocity_z: f32::NAN,
                ..AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA::default()
            },
        )));
        let nan = f32::NAN;
        let lock = GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_ROLL_LOCK
            | GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_PITCH_LOCK
            | GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_YAW_LOCK;
        let forms = [
            (
                [0.7072, 0.0, -0.7072, 0.0],
                [nan; 3],
                GimbalDeviceFlags::empty(),
            ),
            ([0.92, 0.0, -0.1, 0.38], [nan; 3], lock),
            ([nan; 4], [0.0, 0.1, -0.3], GimbalDeviceFlags::empty()),
            ([nan; 4], [0.0, nan, 0.3], lock),
            (
                [nan; 4],
                [0.0; 3],
                GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_RETRACT,
            ),
            (
                [1.0, 0.0, 0.0, 0.0],
                [nan; 3],
                GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_NEUTRAL,
            ),
            ([nan; 4], [nan; 3], GimbalDeviceFlags::empty()),
            (
                [0.92, 0.0, 0.0, 0.38],
                [0.0, 0.0, 0.1],
                GimbalDeviceFlags::GIMBAL_DEVICE_FLAGS_YAW_IN_EARTH_FRAME,
            ),
        ];
        for (q, w, flags) in forms {
            out.push(ap(MavMessage::GIMBAL_DEVICE_SET_ATTITUDE(
                GIMBAL_DEVICE_SET_ATTITUDE_DATA {
                    q,
                    angular_velocity_x: w[0],
                    angular_velocity_y: w[1],
                    angular_velocity_z: w[2],
                    flags,
                    target_system: 1,
                    target_component: 154,
                },
            )));
        }
        let gcs = |msg: MavMessage| frame(255, 190, 7, &msg);
        for id in [
            0.0, 283.0, 285.0, 259.0, 260.0, 261.0, 262.0, 263.0, 269.0, 280.0, 270.0, 271.0,
            275.0, 277.0, 132.0,
        ] {
            for comp in [154, 100, 0] {
                let p = [id, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
                out.push(gcs(long(MavCmd::MAV_CMD_REQUEST_MESSAGE, p, (1, comp))));
            }
        }
        #[allow(deprecated)]
        let old = [
            MavCmd::MAV_CMD_REQUEST_CAMERA_INFORMATION,
            MavCmd::MAV_CMD_REQUEST_CAMERA_SETTINGS,
            MavCmd::MAV_CMD_REQUEST_STORAGE_INFORMATION,
            MavCmd::MAV_CMD_REQUEST_CAMERA_CAPTURE_STATUS,
            MavCmd::MAV_CMD_REQUEST_CAMERA_IMAGE_CAPTURE,
            MavCmd::MAV_CMD_REQUEST_VIDEO_STREAM_INFORMATION,
            MavCmd::MAV_CMD_REQUEST_VIDEO_STREAM_STATUS,
            MavCmd::MAV_CMD_STORAGE_FORMAT,
            MavCmd::MAV_CMD_RESET_CAMERA_SETTINGS,
            MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
        ];
        for cmd in old {
            out.push(gcs(long(
                cmd,
                [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
                (1, 100),
            )));
        }
        let camera = [
            (MavCmd::MAV_CMD_IMAGE_START_CAPTURE, [0.0, 0.0, 1.0, 7.0]),
            (MavCmd::MAV_CMD_IMAGE_START_CAPTURE, [0.0, 2.0, 3.0, 0.0]),
            (MavCmd::MAV_CMD_IMAGE_START_CAPTURE, [0.0, 0.2, 0.0, 0.0]),
            (MavCmd::MAV_CMD_IMAGE_STOP_CAPTURE, [0.0; 4]),
            (MavCmd::MAV_CMD_VIDEO_START_CAPTURE, [0.0; 4]),
            (MavCmd::MAV_CMD_VIDEO_STOP_CAPTURE, [0.0; 4]),
            (MavCmd::MAV_CMD_SET_CAMERA_MODE, [0.0, 1.0, 0.0, 0.0]),
            (MavCmd::MAV_CMD_SET_CAMERA_MODE, [0.0, 0.0, 0.0, 0.0]),
            (MavCmd::MAV_CMD_SET_CAMERA_ZOOM, [0.0, 1.0, 0.0, 0.0]),
            (MavCmd::MAV_CMD_SET_CAMERA_ZOOM, [1.0, -1.0, 0.0, 0.0]),
            (MavCmd::MAV_CMD_SET_CAMERA_ZOOM, [2.0, 50.0, 0.0, 0.0]),
            (MavCmd::MAV_CMD_SET_CAMERA_ZOOM, [3.0, 24.0, 0.0, 0.0]),
            (MavCmd::MAV_CMD_SET_CAMERA_FOCUS, [0.0, -1.0, 0.0, 0.0]),
            (MavCmd::MAV_CMD_SET_CAMERA_FOCUS, [1.0, 1.0, 0.0, 0.0]),
            (MavCmd::MAV_CMD_SET_CAMERA_FOCUS, [2.0, 30.0, 0.0, 0.0]),
            (MavCmd::MAV_CMD_SET_CAMERA_FOCUS, [4.0, 0.0, 0.0, 0.0]),
        ];
        for (cmd, p) in camera {
            let p = [p[0], p[1], p[2], p[3], 0.0, 0.0, 0.0];
            out.push(ap(long(cmd, p, (0, 0))));
            out.push(gcs(long(cmd, p, (1, 100))));
        }
        let sensors = [
            (MavCmd::MAV_CMD_SET_CAMERA_SOURCE, [0.0, 2.0, 0.0, 0.0, 0.0]),
            (
                MavCmd::MAV_CMD_SET_CAMERA_SOURCE,
                [100.0, 1.0, 2.0, 0.0, 0.0],
            ),
            (MavCmd::MAV_CMD_SET_CAMERA_SOURCE, [0.0, 3.0, 0.0, 0.0, 0.0]),
            (MavCmd::MAV_CMD_SET_CAMERA_SOURCE, [0.0, nan, 0.0, 0.0, 0.0]),
            (
                MavCmd::MAV_CMD_CAMERA_TRACK_POINT,
                [0.5, 0.5, 0.1, 0.0, 0.0],
            ),
            (
                MavCmd::MAV_CMD_CAMERA_TRACK_POINT,
                [1.5, -0.5, 0.0, nan, 0.0],
            ),
            (
                MavCmd::MAV_CMD_CAMERA_TRACK_POINT,
                [nan, 0.5, 0.1, 0.0, 0.0],
            ),
            (
                MavCmd::MAV_CMD_CAMERA_TRACK_RECTANGLE,
                [0.1, 0.2, 0.9, 0.8, 0.0],
            ),
            (
                MavCmd::MAV_CMD_CAMERA_TRACK_RECTANGLE,
                [0.9, 0.8, 0.1, 0.2, 7.0],
            ),
            (MavCmd::MAV_CMD_CAMERA_STOP_TRACKING, [0.0; 5]),
            (
                MavCmd::MAV_CMD_VIDEO_START_STREAMING,
                [1.0, 0.0, 0.0, 0.0, 0.0],
            ),
            (
                MavCmd::MAV_CMD_VIDEO_START_STREAMING,
                [2.0, 0.0, 0.0, 0.0, 0.0],
            ),
            (
                MavCmd::MAV_CMD_VIDEO_STOP_STREAMING,
                [1.0, 0.0, 0.0, 0.0, 0.0],
            ),
            (
                MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
                [277.0, 200_000.0, 0.0, 0.0, 0.0],
            ),
            (
                MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
                [277.0, 1.0, 2.0, 0.0, 0.0],
            ),
            (
                MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
                [277.0, -1.0, 0.0, 0.0, 0.0],
            ),
            (
                MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
                [275.0, 500_000.0, 0.0, 0.0, 0.0],
            ),
            (
                MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
                [271.0, 0.0, 0.0, 0.0, 0.0],
            ),
            (
                MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
                [132.0, 0.0, 0.0, 0.0, 0.0],
            ),
            (
                MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
                [132.0, -1.0, 0.0, 0.0, 0.0],
            ),
            (
                MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
                [132.0, nan, 0.0, 0.0, 0.0],
            ),
        ];
        for (cmd, p) in sensors {
            let p = [p[0], p[1], p[2], p[3], p[4], 0.0, 0.0];
            out.push(ap(long(cmd, p, (0, 0))));
            out.push(gcs(long(cmd, p, (1, 100))));
        }
        let roi = [1.0, 0.0, 0.0, 0.0, 47.398, 8.546, 500.0];
        out.push(gcs(long(
            MavCmd::MAV_CMD_DO_SET_ROI_LOCATION,
            roi,
            (1, 154),
        )));
        out.push(gcs(long(
            MavCmd::MAV_CMD_DO_SET_ROI_NONE,
            [0.0; 7],
            (1, 154),
        )));
        for (frame_of, z) in [
            (MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT, 40.0),
            (MavFrame::MAV_FRAME_LOCAL_NED, 10.0),
            (MavFrame::MAV_FRAME_GLOBAL, f32::INFINITY),
        ] {
            out.push(ap(MavMessage::COMMAND_INT(COMMAND_INT_DATA {
                command: MavCmd::MAV_CMD_DO_SET_ROI_LOCATION,
                target_system: 1,
                target_component: 154,
                frame: frame_of,
                x: 473_987_420,
                y: -85_455_940,
                z,
                ..COMMAND_INT_DATA::default()
            })));
        }
        out.push(gcs(MavMessage::COMMAND_INT(COMMAND_INT_DATA {
            command: MavCmd::MAV_CMD_DO_SET_ROI_LOCATION,
            target_system: 1,
            target_component: 154,
            frame: MavFrame::MAV_FRAME_GLOBAL,
            x: 473_977_420,
            y: 85_455_940,
            ..COMMAND_INT_DATA::default()
        })));
        out.push(unknown_command());
        out.push(ap(MavMessage::TIMESYNC(TIMESYNC_DATA {
            tc1: 0,
            ts1: 60_000_000_001,
            target_system: 0,
            target_component: 0,
        })));
        out.push(gcs(MavMessage::HEARTBEAT(HEARTBEAT_DATA {
            mavtype: MavType::MAV_TYPE_GCS,
            autopilot: MavAutopilot::MAV_AUTOPILOT_INVALID,
            ..HEARTBEAT_DATA::default()
        })));
        out.extend(settings_frames());
        let fill: Vec<u8> = (0..=255u8).map(|i| i.wrapping_mul(151) ^ 0x5A).collect();
        out.extend(
            crate::mavlink::catalogue_frames(&fill)
                .into_iter()
                .filter(|f| f.len() <= 255),
        );
        out
    })
}

/// Runs one program; panics when a property fails.
pub fn run(data: &[u8]) {
    run_with(FcProtocol::Mavlink, fc_frames(), Input::new(data));
}

/// The key the signing target's engine holds.
pub const FUZZ_KEY: [u8; 32] = *b"fuzzing the bridge's signing key";

/// `frame` signed with `key` at `timestamp` (its 48 bits); unchanged when it does not
/// decode.
#[must_use]
pub fn signed(frame: &[u8], key: [u8; 32], timestamp: u64) -> Vec<u8> {
    let key = protocol_core::mavlink::SecretKey::new(key);
    let signer = protocol_core::mavlink::Signer {
        key: &key,
        link_id: 0,
        timestamp: timestamp.min(protocol_core::mavlink::MAX_TIMESTAMP),
    };
    let mut buf = [0u8; MAX_FRAME_LEN];
    match Packet::decode(frame).map(|p| p.emit_signed(&signer, &mut buf)) {
        Ok(Ok(n)) => buf[..n].to_vec(),
        _ => frame.to_vec(),
    }
}

/// The signing target's FC frames: each of [`fc_frames`] signed with the key at growing
/// timestamps (the fuzzer's repeats are replays), then with another key, then a minute
/// and more too old, and SETUP_SIGNING from the autopilot signed and unsigned.
#[must_use]
pub fn signed_frames() -> &'static [Vec<u8>] {
    static FRAMES: OnceLock<Vec<Vec<u8>>> = OnceLock::new();
    FRAMES.get_or_init(|| {
        const T0: u64 = 3_500_000_000_000;
        let plain = fc_frames();
        let mut out: Vec<Vec<u8>> = Vec::new();
        for (i, f) in plain.iter().enumerate().take(120) {
            let t = T0 + i as u64 * 1_000;
            out.push(signed(f, FUZZ_KEY, t));
        }
        out.push(signed(&plain[0], [7; 32], T0));
        out.push(signed(&plain[1], FUZZ_KEY, T0 - 7_000_000));
        let setup = |key: [u8; 32], t: u64| {
            MavMessage::SETUP_SIGNING(protocol_core::mavlink::dialect::SETUP_SIGNING_DATA {
                initial_timestamp: t,
                target_system: 1,
                target_component: 154,
                secret_key: key,
            })
        };
        let rotate = frame(1, 1, 9, &setup(FUZZ_KEY, T0));
        out.push(signed(&rotate, FUZZ_KEY, T0 + 500_000));
        out.push(rotate);
        out.push(signed(
            &frame(1, 1, 9, &setup([0; 32], 0)),
            FUZZ_KEY,
            T0 + 600_000,
        ));
        out.push(plain[0].clone());
        out
    })
}

/// Target `bridge_signed`: the MAVLink side signing (the first byte: `"sign"` when even,
/// `"require"` when odd, with unsigned telemetry read when its bit 1 is set) with the
/// properties of [`run`]; the probe then comes signed.
pub fn run_signed(data: &[u8]) {
    let Some((&mode, rest)) = data.split_first() else {
        return;
    };
    let mut config = bridge_engine::Config::for_fc(FcProtocol::Mavlink);
    config.signing = if mode & 1 == 0 {
        bridge_engine::SigningMode::Sign
    } else {
        bridge_engine::SigningMode::Require
    };
    config.signing_key = Some(bridge_engine::SigningKey(FUZZ_KEY));
    config.signing_unsigned_telemetry = mode & 2 != 0;
    run_config(config, signed_frames(), Input::new(rest));
}

/// Seeds of the signing target: [`seeds`] over the signed frames, in both modes.
#[must_use]
pub fn signed_seeds() -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    for mode in [0u8, 1, 3] {
        for s in seeds_with(&[], signed_frames()).into_iter().step_by(4) {
            let mut v = vec![mode];
            v.extend(s);
            out.push(v);
        }
    }
    out
}

/// `frame` as system `sys` sent it (unchanged when it does not decode).
fn as_system(frame: &[u8], sys: u8) -> Vec<u8> {
    let mut buf = [0u8; MAX_FRAME_LEN];
    match Packet::decode(frame).map(|mut p| {
        p.header.system_id = sys;
        p.emit(&mut buf)
    }) {
        Ok(Ok(n)) => buf[..n].to_vec(),
        _ => frame.to_vec(),
    }
}

/// The gate's message of `frame` ([`bridge_engine::access::GATED`]), if any.
fn gated(frame: &[u8]) -> bool {
    protocol_core::mavlink::Frame::new_checked(frame)
        .is_ok_and(|f| bridge_engine::access::Gated::of(f.message_id(), f.payload_ref()).is_some())
}

/// The forged target's FC frames: everything that changes nothing (heartbeats, time,
/// positions, the reads) correctly signed, at growing timestamps; and every message of the
/// gate only as an attacker without the key, or a system that may not command, can send
/// it: unsigned, signed with another key, signed with the key but older than its
/// stream's last (a replay), and correctly signed by system 77 (not the autopilot's, not a
/// ground station's).
#[must_use]
pub fn forged_frames() -> &'static [Vec<u8>] {
    static FRAMES: OnceLock<Vec<Vec<u8>>> = OnceLock::new();
    FRAMES.get_or_init(|| {
        const T0: u64 = 3_500_000_000_000;
        let mut out: Vec<Vec<u8>> = Vec::new();
        let rotate = frame(
            1,
            1,
            9,
            &MavMessage::SETUP_SIGNING(protocol_core::mavlink::dialect::SETUP_SIGNING_DATA {
                initial_timestamp: 0,
                target_system: 1,
                target_component: 154,
                secret_key: [0; 32],
            }),
        );
        for (i, f) in fc_frames().iter().chain([&rotate]).enumerate() {
            let t = T0 + i as u64 * 1_000;
            if gated(f) {
                out.push(f.clone());
                out.push(signed(f, [7; 32], t));
                out.push(signed(f, FUZZ_KEY, T0 - 1));
                out.push(signed(&as_system(f, 77), FUZZ_KEY, t));
            } else {
                out.push(signed(f, FUZZ_KEY, t));
            }
        }
        out
    })
}

/// The K40T requests the bridge makes by itself: its version queries, the settings'
/// and the IP queries at each link-up, the time syncs.
const OWN_REQUESTS: [u16; 6] = [
    k40t::GimbalVersionQuery::ID.base,
    k40t::CameraVersionQuery::ID.base,
    k40t::IrParamsQuery::ID.base,
    k40t::VisibleParamsQuery::ID.base,
    k40t::IpQuery::ID.base,
    k40t::TimeSync::ID.base,
];

/// Target `bridge_forged`: the MAVLink side requiring signing (unsigned telemetry read
/// when the first byte is odd) with [`forged_frames`], and the properties of [`run`]:
/// no command, setting or file write reaches the pod (the pod gets the bridge's own
/// requests and its answers to the pod's GPS requests only), and the probe, signed by an
/// allowed ground station, is still answered.
pub fn run_forged(data: &[u8]) {
    let Some((&mode, rest)) = data.split_first() else {
        return;
    };
    let mut config = bridge_engine::Config::for_fc(FcProtocol::Mavlink);
    config.signing = bridge_engine::SigningMode::Require;
    config.signing_key = Some(bridge_engine::SigningKey(FUZZ_KEY));
    config.signing_unsigned_telemetry = mode & 1 != 0;
    run_checked(config, forged_frames(), Input::new(rest), |_, f| {
        let Ok(frame) = k40t::Frame::new_checked(f) else {
            return;
        };
        let id = frame.id();
        let own = match id.kind {
            k40t::Kind::Request => OWN_REQUESTS.contains(&id.base),
            // The answer to the pod's GPS request.
            k40t::Kind::Ack => id.base == k40t::GpsRequest::ID.base,
            _ => false,
        };
        assert!(
            own,
            "0x{:06X} reached the pod, and no allowed sender signed a command: {f:02X?}",
            id.to_u32()
        );
    });
}

/// Seeds of the forged target: [`seeds`] over the forged frames.
#[must_use]
pub fn forged_seeds() -> Vec<Vec<u8>> {
    let mut out = Vec::new();
    for mode in [0u8, 1] {
        for s in seeds_with(&[], forged_frames()).into_iter().step_by(2) {
            let mut v = vec![mode];
            v.extend(s);
            out.push(v);
        }
    }
    out
}

/// Seeds: the frames in raw bytes and as frame ops, between pod reports, waits and drains.
#[must_use]
pub fn seeds() -> Vec<Vec<u8>> {
    let mut out = seeds_with(&[], fc_frames());
    // The autopilot first, then everything: the device answers once it knows its system.
    let mut s = vec![crate::bridge::op::FRAME, 0];
    for i in 0..fc_frames().len().min(255) {
        s.extend([
            crate::bridge::op::FRAME,
            i as u8,
            crate::bridge::op::FRAME | 8,
            i as u8,
        ]);
        s.extend([crate::bridge::op::WAIT, 30, 0, crate::bridge::op::DRAIN]);
    }
    out.push(s);
    out
}
