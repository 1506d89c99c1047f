//! The bridge's version over MAVLink (docs/src/firmware/configuration.md#versions):
//! AUTOPILOT_VERSION from the gimbal (154) and the camera (100) on the MAVLink side and
//! from component 158 on the telemetry link, asked with MAV_CMD_REQUEST_MESSAGE(148) or
//! MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES addressed to the component; a broadcast request
//! is left to the autopilot; a sender that may not command is refused. The legacy sides'
//! versions are checked against the simulated ArduPilot drivers (`bridge_siyi.rs`,
//! `bridge_viewlink.rs`, `bridge_gcu.rs`), the information messages in `bridge_mavlink.rs`.

// MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES is deprecated, and still what MAVProxy's
// `version` and older ground stations send.
#![allow(deprecated)]

use bridge_engine::version::Version;
use bridge_engine::{BuildInfo, Config, Engine, FcProtocol, Instant, MAX_FRAME_LEN, Port};
use gimbal::sim::mav;
use protocol_core::mavlink::dialect::{
    AUTOPILOT_VERSION_DATA, MavAutopilot, MavCmd, MavProtocolCapability, MavResult, MavType,
};
use protocol_core::mavlink::{self, Header, MavMessage, Message, Packet};

/// A build other than the engine's own, so that what is reported is seen to come from
/// the build the engine was given.
const BUILD: BuildInfo = BuildInfo {
    version: Version {
        major: 3,
        minor: 14,
        patch: 15,
        pre_release: false,
    },
    semver: "3.14.15",
    commit: "0123456789ab",
    dirty: false,
    flavour: "hw",
    features: "fc-mavlink",
};

fn frame(system_id: u8, component_id: u8, m: &MavMessage) -> Vec<u8> {
    let h = Header {
        sequence: 0,
        system_id,
        component_id,
    };
    let mut buf = [0u8; 300];
    let n = mavlink::encode(m, &h, &mut buf).unwrap();
    buf[..n].to_vec()
}

fn heartbeat() -> MavMessage {
    mav::autopilot_heartbeat(
        MavType::MAV_TYPE_QUADROTOR,
        MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA,
    )
}

fn command(cmd: MavCmd, param1: f32, to_component: u8) -> MavMessage {
    let p = [param1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    mav::command_long(cmd, p, (1, to_component), 0)
}

/// What the engine answers on `port` to `m` from (system, component): every
/// (component, message) it sends within 50 ms, HEARTBEATs and routine traffic left out.
fn ask(
    e: &mut Engine,
    at_ms: u64,
    port: Port,
    from: (u8, u8),
    m: &MavMessage,
) -> Vec<(u8, MavMessage)> {
    let mut buf = [0u8; MAX_FRAME_LEN];
    while e.transmit(port, &mut buf).is_some() {}
    e.receive(Instant::from_millis(at_ms), port, &frame(from.0, from.1, m));
    let mut out = Vec::new();
    for ms in at_ms..at_ms + 50 {
        e.poll(Instant::from_millis(ms));
        while let Some(n) = e.transmit(port, &mut buf) {
            let p = Packet::decode(&buf[..n]).unwrap();
            if let Message::Known(
                m @ (MavMessage::COMMAND_ACK(_) | MavMessage::AUTOPILOT_VERSION(_)),
            ) = p.message
            {
                out.push((p.header.component_id, m));
            }
        }
    }
    out
}

/// An engine for `fc` with `build` whose autopilot (system 1) was heard on `port`, its
/// first frames for the autopilot (stream requests, TIMESYNC) sent, as a writer would.
fn engine(fc: FcProtocol, port: Port, build: BuildInfo) -> Engine {
    let mut e = Engine::with_build(Config::for_fc(fc), build);
    e.receive(Instant::from_millis(10), port, &frame(1, 1, &heartbeat()));
    let mut buf = [0u8; MAX_FRAME_LEN];
    for ms in 10..1_000 {
        e.poll(Instant::from_millis(ms));
        while e.transmit(port, &mut buf).is_some() {}
    }
    e
}

fn ack(result: MavResult, cmd: MavCmd) -> MavMessage {
    let gcs = Header {
        sequence: 0,
        system_id: 255,
        component_id: 190,
    };
    mav::command_ack(cmd, result, &gcs)
}

fn version_message() -> MavMessage {
    MavMessage::AUTOPILOT_VERSION(AUTOPILOT_VERSION_DATA {
        capabilities: MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_MAVLINK2
            | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_COMMAND_INT,
        uid: 0,
        // 3.14.15, OFFICIAL (255).
        flight_sw_version: 0x030E_0FFF,
        middleware_sw_version: 0,
        os_sw_version: 0,
        board_version: 0,
        flight_custom_version: *b"01234567",
        middleware_custom_version: [0; 8],
        os_custom_version: [0; 8],
        vendor_id: 0,
        product_id: 0,
        uid2: [0; 18],
    })
}

#[test]
fn each_component_of_the_mavlink_side_reports_the_build_it_was_given() {
    const GCS: (u8, u8) = (255, 190);
    let mut e = engine(FcProtocol::Mavlink, Port::Fc, BUILD);
    let mut t = 1_000;
    for comp in [154u8, 100] {
        for (cmd, p1) in [
            (MavCmd::MAV_CMD_REQUEST_MESSAGE, 148.0),
            (MavCmd::MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES, 1.0),
        ] {
            let got = ask(&mut e, t, Port::Fc, GCS, &command(cmd, p1, comp));
            t += 100;
            assert_eq!(
                got,
                vec![
                    (comp, ack(MavResult::MAV_RESULT_ACCEPTED, cmd)),
                    (comp, version_message())
                ],
                "{comp} {cmd:?}"
            );
        }
    }
    // A broadcast request is the autopilot's.
    let got = ask(
        &mut e,
        t,
        Port::Fc,
        GCS,
        &command(MavCmd::MAV_CMD_REQUEST_MESSAGE, 148.0, 0),
    );
    assert_eq!(got, vec![]);
    // A system not allowed to command: DENIED, no version.
    let got = ask(
        &mut e,
        t + 100,
        Port::Fc,
        (77, 1),
        &command(MavCmd::MAV_CMD_REQUEST_MESSAGE, 148.0, 154),
    );
    assert_eq!(got.len(), 1);
    assert!(
        matches!(&got[0], (154, MavMessage::COMMAND_ACK(a)) if a.result == MavResult::MAV_RESULT_DENIED)
    );
}

#[test]
fn the_telemetry_link_reports_the_build_and_refuses_other_commands() {
    const GCS: (u8, u8) = (255, 190);
    let mut e = engine(FcProtocol::Siyi, Port::Telemetry, BUILD);
    for (i, (cmd, p1)) in [
        (MavCmd::MAV_CMD_REQUEST_MESSAGE, 148.0),
        (MavCmd::MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES, 1.0),
    ]
    .into_iter()
    .enumerate()
    {
        let got = ask(
            &mut e,
            1_000 + 100 * i as u64,
            Port::Telemetry,
            GCS,
            &command(cmd, p1, 158),
        );
        assert_eq!(
            got,
            vec![
                (158, ack(MavResult::MAV_RESULT_ACCEPTED, cmd)),
                (158, version_message())
            ]
        );
    }
    // Another command addressed to it: UNSUPPORTED; another message asked: the same.
    let cmd = MavCmd::MAV_CMD_IMAGE_START_CAPTURE;
    let got = ask(&mut e, 2_000, Port::Telemetry, GCS, &command(cmd, 0.0, 158));
    assert_eq!(
        got,
        vec![(158, ack(MavResult::MAV_RESULT_UNSUPPORTED, cmd))]
    );
    let cmd = MavCmd::MAV_CMD_REQUEST_MESSAGE;
    let got = ask(
        &mut e,
        2_100,
        Port::Telemetry,
        GCS,
        &command(cmd, 259.0, 158),
    );
    assert_eq!(
        got,
        vec![(158, ack(MavResult::MAV_RESULT_UNSUPPORTED, cmd))]
    );
    // Broadcast, or addressed to another component: not its business.
    for comp in [0, 1, 154] {
        let got = ask(
            &mut e,
            2_200,
            Port::Telemetry,
            GCS,
            &command(cmd, 148.0, comp),
        );
        assert_eq!(got, vec![], "to {comp}");
    }
    // A sender that may not command the bridge: DENIED.
    let got = ask(
        &mut e,
        2_300,
        Port::Telemetry,
        (77, 1),
        &command(cmd, 148.0, 158),
    );
    assert!(
        matches!(&got[..], [(158, MavMessage::COMMAND_ACK(a))] if a.result == MavResult::MAV_RESULT_DENIED),
        "{got:?}"
    );
}

/// A dirty build is a development build (FIRMWARE_VERSION_TYPE_DEV), and a build from
/// outside a checkout carries no commit.
#[test]
fn a_dirty_or_unknown_build_says_so() {
    let dirty = BuildInfo {
        dirty: true,
        commit: "unknown",
        ..BUILD
    };
    let mut e = engine(FcProtocol::Siyi, Port::Telemetry, dirty);
    let got = ask(
        &mut e,
        1_000,
        Port::Telemetry,
        (255, 190),
        &command(MavCmd::MAV_CMD_REQUEST_MESSAGE, 148.0, 158),
    );
    let Some((_, MavMessage::AUTOPILOT_VERSION(v))) = got.get(1) else {
        panic!("{got:?}");
    };
    assert_eq!(v.flight_sw_version, 0x030E_0F00);
    assert_eq!(v.flight_custom_version, [0; 8]);
    assert_eq!(e.build(), &dirty);
}
