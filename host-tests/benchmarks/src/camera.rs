//! The MAVLink camera's requests (component 100) as the bridge engine handles them: its
//! settings (PARAM_EXT_*), its definition file over MAVLink FTP, tracking and the video
//! stream's information. Each run is [`CAMERA_REQUESTS`] requests from the autopilot,
//! [`CAMERA_STEP`] apart (all within the pod link's time-out of a second after the pod's
//! last report, so the pod stays up without more reports to absorb), recorded and
//! replayed as [`crate::bridge`] describes; its setup checks that every request got the
//! answer the run is named for.

use bridge_engine::{Config, Duration};
use protocol_core::mavlink::MavMessage;
use protocol_core::mavlink::dialect::{
    COMMAND_LONG_DATA, CharArray, FILE_TRANSFER_PROTOCOL_DATA, MavCmd, MavParamExtType, MavResult,
    PARAM_EXT_REQUEST_READ_DATA, PARAM_EXT_SET_DATA, ParamAck,
};

use crate::bridge::{BridgeRun, mavlink_config, mavlink_frame, mavlink_run};

/// Requests in each camera benchmark.
pub const CAMERA_REQUESTS: usize = 16;
/// Time between two camera requests: more than the 35 ms the bridge leaves between two
/// paced replies (1.5 times a 266-byte FTP reply at 115200 baud), so that each request's
/// answer goes out at once.
const CAMERA_STEP: Duration = Duration::from_millis(40);

/// The bridge's camera component.
const CAMERA: u8 = 100;

/// The camera definition the bridge serves over FTP (its length sets the reads' offsets).
const DEFINITION: &[u8] = include_bytes!("../../../bridge-engine/camera/k40t.xml.xz");
/// Data bytes of one FTP read.
const FTP_CHUNK: usize = 239;

/// Parameters of the camera definition the settings runs read and set (any index reads;
/// IR_PALETTE takes 1 to 20).
const PARAMS: i16 = 33;
const SET_PARAM: &[u8] = b"IR_PALETTE";

/// A NUL-padded char array of `text`.
fn chars<const N: usize>(text: &[u8]) -> CharArray<N> {
    let mut a = [0u8; N];
    a[..text.len()].copy_from_slice(text);
    CharArray::from(a)
}

/// The camera run of `frames`: recorded (the pod ACKing, with `pod_acks`), then checked
/// that at least one FC frame per request satisfies `answer`.
fn camera_run(
    name: &str,
    frames: Vec<Vec<u8>>,
    signing: bool,
    config: Config,
    pod_acks: bool,
    answer: impl Fn(&MavMessage) -> bool,
) -> BridgeRun {
    let run = mavlink_run(frames, signing, config, CAMERA_STEP, pod_acks);
    let answers = run
        .fc_messages()
        .filter(|m| m.as_ref().is_some_and(&answer))
        .count();
    assert!(
        answers >= run.requests,
        "{name}: {answers} answers to {} requests",
        run.requests
    );
    run
}

/// A COMMAND_LONG to the camera.
fn command(seq: usize, command: MavCmd, params: [f32; 7]) -> Vec<u8> {
    let [param1, param2, param3, param4, param5, param6, param7] = params;
    let m = MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
        param1,
        param2,
        param3,
        param4,
        param5,
        param6,
        param7,
        command,
        target_system: 1,
        target_component: CAMERA,
        confirmation: 0,
    });
    mavlink_frame(seq as u8, &m)
}

/// The camera's COMMAND_ACK of `cmd`, ACCEPTED.
fn accepted(cmd: MavCmd) -> impl Fn(&MavMessage) -> bool {
    move |m| {
        matches!(m, MavMessage::COMMAND_ACK(a)
            if a.command == cmd && a.result == MavResult::MAV_RESULT_ACCEPTED)
    }
}

/// PARAM_EXT_REQUEST_READ by index, every parameter in turn: each answered with its
/// PARAM_EXT_VALUE.
#[must_use]
pub fn settings_reads() -> BridgeRun {
    let frames = (0..CAMERA_REQUESTS)
        .map(|i| {
            let m = MavMessage::PARAM_EXT_REQUEST_READ(PARAM_EXT_REQUEST_READ_DATA {
                param_index: i as i16 % PARAMS,
                target_system: 1,
                target_component: CAMERA,
                param_id: chars(b""),
            });
            mavlink_frame(i as u8, &m)
        })
        .collect();
    camera_run(
        "PARAM_EXT_REQUEST_READ",
        frames,
        false,
        mavlink_config(false),
        false,
        |m| matches!(m, MavMessage::PARAM_EXT_VALUE(_)),
    )
}

/// PARAM_EXT_SET of IR_PALETTE, 2 and 3 in turn: each the K40T set command to the pod,
/// the pod's ACK, PARAM_EXT_ACK IN_PROGRESS then ACCEPTED (and whatever the bridge asks
/// the pod after an accepted set, answered too).
#[must_use]
pub fn settings_sets() -> BridgeRun {
    let frames = (0..CAMERA_REQUESTS)
        .map(|i| {
            let m = MavMessage::PARAM_EXT_SET(PARAM_EXT_SET_DATA {
                target_system: 1,
                target_component: CAMERA,
                param_id: chars(SET_PARAM),
                param_value: chars(&[2 + (i % 2) as u8]),
                param_type: MavParamExtType::MAV_PARAM_EXT_TYPE_UINT8,
            });
            mavlink_frame(i as u8, &m)
        })
        .collect();
    camera_run(
        "PARAM_EXT_SET",
        frames,
        false,
        mavlink_config(false),
        true,
        |m| matches!(m, MavMessage::PARAM_EXT_ACK(a) if a.param_result == ParamAck::PARAM_ACK_ACCEPTED),
    )
}

/// A FILE_TRANSFER_PROTOCOL request to the camera: `opcode` at `offset` with `data`.
fn ftp(seq: usize, opcode: u8, offset: u32, data: &[u8]) -> Vec<u8> {
    let mut payload = [0u8; 251];
    payload[..2].copy_from_slice(&(seq as u16).to_le_bytes());
    payload[3] = opcode;
    payload[4] = if data.is_empty() {
        FTP_CHUNK as u8
    } else {
        data.len() as u8
    };
    payload[8..12].copy_from_slice(&offset.to_le_bytes());
    payload[12..12 + data.len()].copy_from_slice(data);
    let m = MavMessage::FILE_TRANSFER_PROTOCOL(FILE_TRANSFER_PROTOCOL_DATA {
        target_network: 0,
        target_system: 1,
        target_component: CAMERA,
        payload,
    });
    mavlink_frame(seq as u8, &m)
}

/// MAVLink FTP opcodes (the MAVLink FTP protocol's).
const OPEN_FILE_RO: u8 = 4;
const READ_FILE: u8 = 5;
const FTP_ACK: u8 = 128;

/// The camera definition downloaded over MAVLink FTP: OpenFileRO, then ReadFile of each
/// 239-byte piece in turn (from the start again at the end): each answered with its
/// data. With `signing`, on a link that requires signing (each request and reply
/// signed).
#[must_use]
pub fn definition_reads(signing: bool) -> BridgeRun {
    let pieces = DEFINITION.len().div_ceil(FTP_CHUNK);
    let mut frames = vec![ftp(0, OPEN_FILE_RO, 0, b"k40t.xml.xz")];
    frames.extend((0..CAMERA_REQUESTS).map(|i| {
        let offset = (i % pieces * FTP_CHUNK) as u32;
        ftp(i + 1, READ_FILE, offset, &[])
    }));
    let mut run = camera_run(
        "FTP ReadFile",
        frames,
        signing,
        mavlink_config(signing),
        false,
        |m| {
            matches!(m, MavMessage::FILE_TRANSFER_PROTOCOL(f)
                if f.payload[3] == FTP_ACK && f.payload[4] > 0)
        },
    );
    // The open is part of the download, not one of the reads counted.
    run.requests -= 1;
    run
}

/// MAV_CMD_CAMERA_TRACK_RECTANGLE, two boxes in turn: each the K40T box (0x000324; AI
/// recognition switched on before the first) to the pod, the pod's ACK, COMMAND_ACK
/// ACCEPTED and CAMERA_TRACKING_IMAGE_STATUS.
#[must_use]
pub fn tracking_rectangles() -> BridgeRun {
    let frames = (0..CAMERA_REQUESTS)
        .map(|i| {
            let d = if i % 2 == 0 { 0.0 } else { 0.1 };
            let params = [0.4 + d, 0.4, 0.6 + d, 0.6, 0.0, 0.0, 0.0];
            command(i, MavCmd::MAV_CMD_CAMERA_TRACK_RECTANGLE, params)
        })
        .collect();
    camera_run(
        "CAMERA_TRACK_RECTANGLE",
        frames,
        false,
        mavlink_config(false),
        true,
        accepted(MavCmd::MAV_CMD_CAMERA_TRACK_RECTANGLE),
    )
}

/// MAV_CMD_REQUEST_MESSAGE of VIDEO_STREAM_INFORMATION (every stream): each answered with
/// COMMAND_ACK and the stream's information (the stream's address configured, as
/// `video.uri`).
#[must_use]
pub fn video_information_requests() -> BridgeRun {
    let mut config = mavlink_config(false);
    let uri = b"rtsp://192.168.144.108:558/live/single";
    config.video.uri[..uri.len()].copy_from_slice(uri);
    let frames = (0..CAMERA_REQUESTS)
        .map(|i| {
            command(
                i,
                MavCmd::MAV_CMD_REQUEST_MESSAGE,
                [269.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            )
        })
        .collect();
    camera_run(
        "REQUEST_MESSAGE(VIDEO_STREAM_INFORMATION)",
        frames,
        false,
        config,
        false,
        |m| matches!(m, MavMessage::VIDEO_STREAM_INFORMATION(_)),
    )
}
