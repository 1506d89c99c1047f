//! Who may command the pod (docs/src/security.md): MAVLink 2 signing on the MAVLink side
//! (a simulated ArduPilot on a signed link), commands only from the autopilot's system
//! and the listed ground stations, SETUP_SIGNING, and the K40T side's allow-list of the
//! pod's destructive requests.

use crate::engine_scenarios;
// Issue 33's promises, each as an attacker would try it (one test binary with these).
mod promises;

use bridge_engine::{
    Config, Engine, Event, FcProtocol, Instant, K40tAllow, MAX_FRAME_LEN, Port, Refusal,
    SigningKey, SigningMode,
};
use gimbal::sim::Autopilot;
use gimbal::sim::ap_mavlink::{ApMavlink, ApMavlinkConfig};
use gimbal::sim::pod::{PodSimConfig, SimPod};
use gimbal::sim::scenario::Scenario;
use gimbal::sim::signing::Signed;
use protocol_core::k40t::{self, AckCode, Address, FormatSd, Kind, MessageData};
use protocol_core::mavlink::dialect::{COMMAND_LONG_DATA, MavCmd, SETUP_SIGNING_DATA};
use protocol_core::mavlink::{self, Header, MavMessage};

use engine_scenarios::S;

const KEY: [u8; 32] = *b"the bridge's 32-byte signing key";

type SignedAp = Scenario<Signed<ApMavlink>>;

/// ArduPilot on a link signed with [`KEY`] (or unsigned: `ap_signs` false), the bridge
/// signing as `mode` says.
fn signed_ap(mode: SigningMode, ap_signs: bool, unsigned_telemetry: bool) -> SignedAp {
    let ap = ApMavlinkConfig::default();
    let mut fc = Signed::new(ApMavlink::new(ap.clone()), KEY, ap.utc_at_zero_us);
    fc.sign_outgoing = ap_signs;
    let mut c = Config::for_fc(FcProtocol::Mavlink);
    c.signing = mode;
    c.signing_key = Some(SigningKey(KEY));
    c.signing_unsigned_telemetry = unsigned_telemetry;
    Scenario::new(c, fc, SimPod::new(PodSimConfig::default()), 25)
}

/// A COMMAND_LONG IMAGE_START_CAPTURE (one photo) to the camera, from `from`.
fn photo_command(from: (u8, u8), seq: u8) -> Vec<u8> {
    let cmd = MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
        param1: 0.0,
        param2: 0.0,
        param3: 1.0,
        param4: 0.0,
        param5: 0.0,
        param6: 0.0,
        param7: 0.0,
        command: MavCmd::MAV_CMD_IMAGE_START_CAPTURE,
        target_system: 1,
        target_component: 100,
        confirmation: 0,
    });
    encode(&cmd, from, seq)
}

fn encode(m: &MavMessage, (system_id, component_id): (u8, u8), sequence: u8) -> Vec<u8> {
    let mut buf = [0u8; mavlink::MAX_FRAME_LEN];
    let header = Header {
        sequence,
        system_id,
        component_id,
    };
    let n = mavlink::encode(m, &header, &mut buf).unwrap();
    buf[..n].to_vec()
}

fn refusals(s: &SignedAp) -> Vec<(Refusal, u32, u8)> {
    s.events
        .iter()
        .filter_map(|(_, e)| match *e {
            Event::Refused {
                reason, id, sender, ..
            } => Some((reason, id, sender)),
            _ => None,
        })
        .collect()
}

/// ArduPilot and the bridge both sign with the key (the bridge requires it): the mount
/// is healthy, time syncs and photos go on, and every frame the bridge sent after its
/// first timestamp was signed with the key, its timestamps never going back.
#[test]
fn a_signed_link_carries_a_whole_flight() {
    let mut s = signed_ap(SigningMode::Require, true, false);
    s.run_until(25 * S);
    assert!(s.fc.healthy(), "{:?}", s.fc.health_log());
    assert!(!s.pod.syncs().is_empty());
    for _ in 0..2 {
        s.fc.take_picture();
        s.run_for(3 * S);
    }
    assert_eq!(s.pod.photo_requests(), 2);
    assert_eq!(s.fc.images.len(), 2);
    let st = s.fc.stats();
    assert!(st.good > 500, "{st:?}");
    assert_eq!((st.bad, st.unsigned, st.backwards), (0, 0, 0), "{st:?}");
    let c = s.engine.counters();
    assert_eq!((c.signature_failures, c.unsigned_refused), (0, 0), "{c:?}");
}

/// On a required-signing link: an unsigned command, one signed with another key, one
/// replayed (a timestamp its stream already passed) and one opening a stream more than
/// a minute old are refused and reported; a correctly signed one from a new component
/// of the autopilot's system is taken.
#[test]
fn unsigned_forged_replayed_and_stale_commands_are_refused() {
    let mut s = signed_ap(SigningMode::Require, true, false);
    s.run_until(25 * S);
    let photos = s.pod.photo_requests();
    let now = s.now_us;
    let t = s.fc.timestamp_at(now);
    let unsigned = photo_command((1, 1), 200);
    let forged = Signed::<ApMavlink>::sign_with(&photo_command((1, 1), 201), [9; 32], t + 5);
    let replayed = Signed::<ApMavlink>::sign_with(&photo_command((1, 1), 202), KEY, t - 500);
    let stale = Signed::<ApMavlink>::sign_with(&photo_command((1, 77), 0), KEY, t - 6_100_000);
    for (i, f) in [unsigned, forged, replayed, stale].into_iter().enumerate() {
        s.fc.inject(now + i as u64 * 100_000, f);
    }
    s.run_for(2 * S);
    assert_eq!(
        s.pod.photo_requests(),
        photos,
        "none of them reached the pod"
    );
    assert_eq!(
        refusals(&s),
        vec![
            // The gate names a command by its MAV_CMD; a signature that does not check,
            // by the message id (the frame is not read).
            (Refusal::Unsigned, 2000, 1),
            (Refusal::BadSignature, 76, 1),
            (Refusal::Replayed, 76, 1),
            (Refusal::Stale, 76, 1),
        ]
    );
    let c = s.engine.counters();
    assert_eq!((c.unsigned_refused, c.signature_failures), (1, 3));
    // Signed with the key, fresh: taken (a MAVSDK-like component of the autopilot's
    // system, a stream of its own).
    let t = s.fc.timestamp_at(s.now_us);
    let good = Signed::<ApMavlink>::sign_with(&photo_command((1, 190), 0), KEY, t);
    s.fc.inject(s.now_us, good);
    s.run_for(3 * S);
    assert_eq!(s.pod.photo_requests(), photos + 1);
}

/// Required signing with an autopilot that does not sign: nothing it sends is read (its
/// heartbeat neither: the bridge never speaks); with `signing_unsigned_telemetry` its
/// telemetry is read (the bridge learns it, gets time) but its commands are refused.
/// "sign" reads it all, and signs once it has a timestamp (UTC).
#[test]
fn required_signing_refuses_an_unsigned_autopilot() {
    let mut s = signed_ap(SigningMode::Require, false, false);
    s.run_until(10 * S);
    assert!(
        s.fc.stats().good + s.fc.stats().unsigned == 0,
        "the bridge said nothing"
    );
    // Copter sends a new port its HEARTBEAT only, once a second.
    assert!(s.engine.counters().unsigned_refused >= 9);
    assert!(!s.fc.healthy());

    let mut s = signed_ap(SigningMode::Require, false, true);
    s.run_until(25 * S);
    assert!(!s.pod.syncs().is_empty(), "time from unsigned telemetry");
    let before = s.pod.photo_requests();
    let refused = s.engine.counters().unsigned_refused;
    s.fc.take_picture();
    s.run_for(3 * S);
    assert_eq!(
        s.pod.photo_requests(),
        before,
        "an unsigned command is refused"
    );
    // ArduPilot's own unsigned requests (REQUEST_MESSAGE) are refused too: one event a
    // second for the stream, every refusal counted.
    assert!(s.engine.counters().unsigned_refused > refused);
    let r = refusals(&s);
    assert!(r.contains(&(Refusal::Unsigned, 512, 1)), "{r:?}");
    // One a second for the stream at most (measured 22 in 25 s, bound 28).
    assert!(r.len() <= 25 + 3, "at most one a second: {}", r.len());

    let mut s = signed_ap(SigningMode::Sign, false, false);
    s.run_until(25 * S);
    assert!(s.fc.healthy());
    s.fc.take_picture();
    s.run_for(3 * S);
    assert_eq!(s.pod.photo_requests(), 1);
    let st = s.fc.stats();
    assert!(st.good > 100 && st.bad == 0 && st.backwards == 0, "{st:?}");
}

/// Commands come from the autopilot's system or a listed ground station's: one from
/// system 77 is refused (a DENIED ACK, an event), one from QGroundControl's 255 is
/// taken; with `gcs_ids` empty, 255 is refused too.
#[test]
fn commands_only_from_the_autopilot_and_listed_ground_stations() {
    for (gcs_ids, from_255_taken) in [(None, true), (Some(&[][..]), false)] {
        let ap = ApMavlinkConfig::default();
        let mut c = Config::for_fc(FcProtocol::Mavlink);
        if let Some(ids) = gcs_ids {
            c.gcs_ids = bridge_engine::SystemIds::from_list(ids).unwrap();
        }
        let fc = Signed::new(ApMavlink::new(ap.clone()), KEY, ap.utc_at_zero_us);
        let mut s = Scenario::new(c, fc, SimPod::new(PodSimConfig::default()), 0);
        s.fc.sign_outgoing = false;
        s.run_until(25 * S);
        let photos = s.pod.photo_requests();
        s.fc.inject(s.now_us, photo_command((77, 190), 0));
        s.run_for(2 * S);
        assert_eq!(s.pod.photo_requests(), photos);
        assert_eq!(refusals(&s), vec![(Refusal::Sender, 2000, 77)]);
        assert_eq!(s.engine.counters().commands_refused, 1);
        s.fc.inject(s.now_us, photo_command((255, 190), 0));
        s.run_for(3 * S);
        assert_eq!(
            s.pod.photo_requests(),
            photos + usize::from(from_255_taken),
            "{gcs_ids:?}"
        );
    }
}

/// SETUP_SIGNING from the autopilot's system, signed with the key in use, changes the
/// key (the bridge's frames then check only with the new one); unsigned, it is refused.
#[test]
fn setup_signing_rotates_the_key_only_when_signed_with_the_old_one() {
    let mut s = signed_ap(SigningMode::Sign, true, false);
    s.run_until(20 * S);
    let new_key = [5u8; 32];
    let setup = |t: u64| {
        MavMessage::SETUP_SIGNING(SETUP_SIGNING_DATA {
            initial_timestamp: t,
            target_system: 1,
            target_component: 154,
            secret_key: new_key,
        })
    };
    let t = s.fc.timestamp_at(s.now_us);
    s.fc.inject(s.now_us, encode(&setup(t), (1, 190), 0));
    s.run_for(S);
    assert_eq!(refusals(&s), vec![(Refusal::Unsigned, 256, 1)]);
    assert_eq!(s.fc.stats().bad, 0);
    let signed = Signed::<ApMavlink>::sign_with(&encode(&setup(t), (1, 190), 1), KEY, t + 10);
    s.fc.inject(s.now_us, signed);
    s.run_for(S);
    assert!(
        s.events
            .iter()
            .any(|(_, e)| matches!(e, Event::SigningKeyChanged { on: true, .. }))
    );
    // The link's peer still checks with the old key: the bridge's frames no longer pass.
    let bad = s.fc.stats().bad;
    s.run_for(S);
    assert!(s.fc.stats().bad > bad + 10);
}

/// The K40T side forwards every request but the pod's destructive ones: a TF card
/// format from the FC is answered with the failure ACK and never reaches the pod, unless
/// `k40t_allow` lists it.
#[test]
fn the_k40t_side_refuses_destructive_requests_unless_allowed() {
    let fc = Address::FLIGHT_CONTROLLER;
    let format = FormatSd::default();
    let mut frame = [0u8; k40t::MAX_FRAME_LEN];
    let n = k40t::encode(
        &format,
        &k40t::Header::new(fc, Address::POD, 42),
        &mut frame,
    )
    .unwrap();
    for allow in [
        K40tAllow::NONE,
        K40tAllow::from_list(&[0x0000_030D]).unwrap(),
    ] {
        let mut c = Config::for_fc(FcProtocol::K40t);
        c.k40t_allow = allow;
        let mut e = Engine::new(c);
        let mut buf = [0u8; MAX_FRAME_LEN];
        e.poll(Instant::from_millis(0));
        while e.transmit(Port::Pod, &mut buf).is_some() {}
        e.receive(Instant::from_millis(10), Port::Fc, &frame[..n]);
        let to_pod = e.transmit(Port::Pod, &mut buf).map(|n| buf[..n].to_vec());
        let to_fc = e.transmit(Port::Fc, &mut buf).map(|n| buf[..n].to_vec());
        if allow == K40tAllow::NONE {
            assert_eq!(to_pod, None, "not forwarded");
            let ack = k40t::Frame::new_checked(to_fc.as_deref().unwrap()).unwrap();
            assert_eq!(ack.id().kind, Kind::Ack);
            assert_eq!(ack.id().base, FormatSd::ID.base);
            assert_eq!(ack.seq(), 42);
            assert_eq!(ack.dst(), fc);
            let code = k40t::ResponseCode {
                raw: ack.payload().try_into().unwrap(),
            };
            assert_eq!(code.code(), AckCode::Failure);
            assert_eq!(e.counters().commands_refused, 1);
            assert_eq!(
                e.next_event(),
                Some(Event::Refused {
                    port: Port::Fc,
                    reason: Refusal::Guarded,
                    id: 0x0000_030D,
                    sender: 0
                })
            );
        } else {
            let f = to_pod.expect("forwarded");
            assert_eq!(k40t::Frame::new_checked(&f[..]).unwrap().id().base, 0x030D);
            assert_eq!(to_fc, None);
        }
    }
}
