//! The bridge's own settings as MAVLink parameters (PARAM_REQUEST_LIST, PARAM_REQUEST_READ,
//! PARAM_SET, PARAM_VALUE) on the gimbal's component (154) on the MAVLink side and on 158
//! on the telemetry link: the engine alone, the frames written by hand as a ground station
//! sends them (docs/src/firmware/configuration.md, "Settings"; real clients:
//! host-tests/mavsdk/test_params.py).

use bridge_engine::settings::table::{self, ParamType};
use bridge_engine::{
    Config, Engine, Event, FcProtocol, Instant, MAX_FRAME_LEN, Port, Refusal, SettingOutcome,
    SettingSource,
};
use protocol_core::mavlink::dialect::{
    HEARTBEAT_DATA, MavAutopilot, MavModeFlag, MavState, MavType,
};
use protocol_core::mavlink::{self, Frame, Header, MavMessage, Message, Packet, Raw};

const GCS: (u8, u8) = (255, 190);
const REQUEST_READ: u32 = 20;
const REQUEST_LIST: u32 = 21;
const VALUE: u32 = 22;
const SET: u32 = 23;
const STATUSTEXT: u32 = 253;

fn raw(id: u32, payload: &[u8], (system_id, component_id): (u8, u8)) -> Vec<u8> {
    let mut buf = [0u8; mavlink::MAX_FRAME_LEN];
    let header = Header {
        sequence: 0,
        system_id,
        component_id,
    };
    let n = Packet::new(header, Message::Raw(Raw { id, payload }))
        .emit(&mut buf)
        .unwrap();
    buf[..n].to_vec()
}

fn heartbeat(autopilot: MavAutopilot) -> Vec<u8> {
    let hb = MavMessage::HEARTBEAT(HEARTBEAT_DATA {
        custom_mode: 0,
        mavtype: MavType::MAV_TYPE_QUADROTOR,
        autopilot,
        base_mode: MavModeFlag::empty(),
        system_status: MavState::MAV_STATE_ACTIVE,
        mavlink_version: 3,
    });
    let mut buf = [0u8; mavlink::MAX_FRAME_LEN];
    let h = Header {
        sequence: 0,
        system_id: 1,
        component_id: 1,
    };
    let n = mavlink::encode(&hb, &h, &mut buf).unwrap();
    buf[..n].to_vec()
}

fn name16(name: &str) -> [u8; 16] {
    let mut out = [0u8; 16];
    out[..name.len()].copy_from_slice(name.as_bytes());
    out
}

fn param_set(target: (u8, u8), name: &str, bits: u32, ty: ParamType) -> Vec<u8> {
    let mut p = Vec::new();
    p.extend_from_slice(&bits.to_le_bytes());
    p.extend_from_slice(&[target.0, target.1]);
    p.extend_from_slice(&name16(name));
    p.push(ty.code());
    p
}

fn request_read(target: (u8, u8), name: &str, index: i16) -> Vec<u8> {
    let mut p = index.to_le_bytes().to_vec();
    p.extend_from_slice(&[target.0, target.1]);
    p.extend_from_slice(&name16(name));
    p
}

/// One PARAM_VALUE as sent: its component, name, value bits, type, count and index.
#[derive(Debug, Clone, PartialEq)]
struct Value {
    comp: u8,
    name: String,
    bits: u32,
    ty: u8,
    count: u16,
    index: u16,
}

/// A bridge on one link (`port`), its autopilot heard.
struct Bridge {
    engine: Engine,
    port: Port,
    now_ms: u64,
    values: Vec<(u64, Value)>,
    texts: Vec<String>,
}

impl Bridge {
    fn new(config: Config, port: Port, autopilot: MavAutopilot) -> Self {
        let mut b = Bridge {
            engine: Engine::new(config),
            port,
            now_ms: 0,
            values: Vec::new(),
            texts: Vec::new(),
        };
        b.input(&heartbeat(autopilot));
        b.run(50);
        b.values.clear();
        b
    }

    fn input(&mut self, frame: &[u8]) {
        self.engine
            .receive(Instant::from_millis(self.now_ms), self.port, frame);
        self.drain();
    }

    /// Runs `ms` milliseconds: polls when asked, takes every frame the link sends.
    fn run(&mut self, ms: u64) {
        let end = self.now_ms + ms;
        while self.now_ms < end {
            self.now_ms += 1;
            let now = Instant::from_millis(self.now_ms);
            if self.engine.poll_at().is_some_and(|t| t <= now) {
                self.engine.poll(now);
            }
            self.drain();
        }
    }

    fn drain(&mut self) {
        let mut buf = [0u8; MAX_FRAME_LEN];
        while let Some(n) = self.engine.transmit(self.port, &mut buf) {
            let f = Frame::new_checked(&buf[..n]).unwrap();
            let p = f.payload_ref();
            let mut payload = [0u8; 64];
            payload[..p.len().min(64)].copy_from_slice(&p[..p.len().min(64)]);
            match f.message_id() {
                VALUE => {
                    let name = payload[8..24]
                        .iter()
                        .take_while(|b| **b != 0)
                        .map(|b| *b as char);
                    self.values.push((
                        self.now_ms,
                        Value {
                            comp: f.component_id(),
                            name: name.collect(),
                            bits: u32::from_le_bytes(payload[..4].try_into().unwrap()),
                            ty: payload[24],
                            count: u16::from_le_bytes([payload[4], payload[5]]),
                            index: u16::from_le_bytes([payload[6], payload[7]]),
                        },
                    ));
                }
                STATUSTEXT => self.texts.push(
                    payload[1..51]
                        .iter()
                        .take_while(|b| **b != 0)
                        .map(|b| *b as char)
                        .collect(),
                ),
                _ => {}
            }
        }
    }

    fn events(&mut self) -> Vec<Event> {
        core::iter::from_fn(|| self.engine.next_event()).collect()
    }
}

fn cast(v: &Value) -> f32 {
    f32::from_bits(v.bits)
}

/// PARAM_REQUEST_LIST to the vehicle's every component: the gimbal's answers with every
/// parameter, paced, each with the count and its index, named and typed as the table
/// says, valued as the configuration; the camera does not answer.
#[test]
fn the_mavlink_side_lists_every_parameter_paced() {
    let mut b = Bridge::new(
        Config::for_fc(FcProtocol::Mavlink),
        Port::Fc,
        MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA,
    );
    let start = b.now_ms;
    b.input(&raw(REQUEST_LIST, &[1, 0], GCS));
    b.run(2_000);
    let n = table::param_count();
    assert_eq!(b.values.len(), n, "one PARAM_VALUE each");
    for ((_, v), (i, s)) in b.values.iter().zip(table::params().enumerate()) {
        assert_eq!(v.comp, 154, "from the gimbal's component");
        assert_eq!((v.index as usize, v.count as usize), (i, n));
        assert_eq!(Some(v.name.as_str()), s.param);
        assert_eq!(v.ty, s.param_type().unwrap().code(), "{}", v.name);
        let want = s.number(&Config::for_fc(FcProtocol::Mavlink)).unwrap();
        assert_eq!(
            cast(v),
            want as f32,
            "{}: cast (ArduPilot's encoding)",
            v.name
        );
    }
    // Paced: three times each frame's serial time apart at least (37 bytes at 115200
    // baud: 3.2 ms), beside the side's own traffic. Measured 370 ms for the 38; bound 1 s.
    let last = b.values.last().unwrap().0;
    let gaps = b.values.windows(2).map(|w| w[1].0 - w[0].0);
    assert!(
        gaps.clone().all(|g| g >= 9),
        "{:?}",
        gaps.collect::<Vec<_>>()
    );
    println!("list of {n} in {} ms", last - start);
    assert!(last - start <= 1_000, "{} ms", last - start);

    // A request to the camera's component is not the gimbal's.
    b.values.clear();
    b.input(&raw(REQUEST_LIST, &[1, 100], GCS));
    b.run(500);
    assert!(b.values.is_empty());
}

/// PARAM_REQUEST_READ by name (index −1) and by index; an unknown name gets nothing.
#[test]
fn one_parameter_by_name_or_index() {
    let mut b = Bridge::new(
        Config::for_fc(FcProtocol::Mavlink),
        Port::Fc,
        MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA,
    );
    b.input(&raw(
        REQUEST_READ,
        &request_read((1, 154), "BRG_SYNC_PERIOD", -1),
        GCS,
    ));
    b.input(&raw(REQUEST_READ, &request_read((1, 0), "", 0), GCS));
    b.input(&raw(
        REQUEST_READ,
        &request_read((1, 154), "BRG_NO_SUCH", -1),
        GCS,
    ));
    b.run(200);
    let got: Vec<(String, f32)> = b
        .values
        .iter()
        .map(|(_, v)| (v.name.clone(), cast(v)))
        .collect();
    assert_eq!(
        got,
        [
            ("BRG_SYNC_PERIOD".to_string(), 10_000.0),
            ("BRG_FC".to_string(), 4.0)
        ],
        "BRG_FC is the first parameter: MAVLink, 4"
    );
}

/// PARAM_SET: checked as the file is, kept at once, answered with the value in force as
/// set (a restart setting's new value; a live one in force at once); refused: the old
/// value and a STATUSTEXT saying why; from a system that may not command: the gate.
#[test]
fn parameters_are_set_checked_and_kept() {
    let mut b = Bridge::new(
        Config::for_fc(FcProtocol::Mavlink),
        Port::Fc,
        MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA,
    );
    let u32t = ParamType::Uint32;
    b.input(&raw(
        SET,
        &param_set((1, 154), "BRG_FC_BAUD", 57_600f32.to_bits(), u32t),
        GCS,
    ));
    b.run(50);
    assert_eq!(
        b.values.last().map(|(_, v)| (v.name.as_str(), cast(v))),
        Some(("BRG_FC_BAUD", 57_600.0))
    );
    assert_eq!(b.engine.settings().pending().fc_baud, 57_600);
    assert_eq!(b.engine.config().fc_baud, 115_200, "at the next start");
    let kept = b.engine.take_record().unwrap();
    assert_eq!((kept.key.0, kept.value()), (0x0102, &b"\x01\x0157600"[..]));
    assert!(b.engine.take_record().is_none());

    // Live: the running configuration at once (INT16, negative).
    let i16t = ParamType::Int16;
    b.input(&raw(
        SET,
        &param_set((1, 0), "BRG_TZ_MIN_WEST", (-60f32).to_bits(), i16t),
        GCS,
    ));
    assert_eq!(b.engine.config().tz_minuteswest, -60);

    // Out of range: the value as it was, and why.
    b.values.clear();
    b.input(&raw(
        SET,
        &param_set((1, 154), "BRG_FC_BAUD", 12f32.to_bits(), u32t),
        GCS,
    ));
    b.run(50);
    assert_eq!(
        b.values.iter().map(|(_, v)| cast(v)).collect::<Vec<_>>(),
        [57_600.0]
    );
    assert_eq!(b.texts, ["BRG_FC_BAUD: 12 is out of range 1200..=4000000"]);
    // The whole configuration: signing without a key, refused as a whole.
    b.input(&raw(
        SET,
        &param_set((1, 154), "BRG_SIGNING", 2f32.to_bits(), ParamType::Uint8),
        GCS,
    ));
    b.run(50);
    assert_eq!(
        b.texts.last().map(String::as_str),
        Some("BRG_SIGNING: signing_key: needed (signing is on)")
    );
    assert_eq!(
        b.engine.settings().pending().signing,
        bridge_engine::SigningMode::Off
    );
    // Not a whole number.
    b.input(&raw(
        SET,
        &param_set(
            (1, 154),
            "BRG_LEAP_SEC",
            18.5f32.to_bits(),
            ParamType::Uint8,
        ),
        GCS,
    ));
    b.run(50);
    assert_eq!(
        b.texts.last().map(String::as_str),
        Some("BRG_LEAP_SEC: expected a whole number")
    );

    // From a system that may not command (not the autopilot's, not a listed ground
    // station's): refused at the gate, nothing answered.
    b.values.clear();
    b.input(&raw(
        SET,
        &param_set((1, 154), "BRG_FC_BAUD", 9_600f32.to_bits(), u32t),
        (42, 1),
    ));
    b.run(50);
    assert!(b.values.is_empty());
    assert_eq!(b.engine.settings().pending().fc_baud, 57_600);

    let events = b.events();
    let setting = |key, outcome| Event::Setting {
        key,
        source: SettingSource::Parameter(Port::Fc),
        outcome,
    };
    for e in [
        setting(0x0102, SettingOutcome::AtRestart),
        setting(0x0106, SettingOutcome::Applied),
        setting(0x0102, SettingOutcome::Refused),
        setting(0x010A, SettingOutcome::Refused),
    ] {
        assert!(events.contains(&e), "{e:?} in {events:?}");
    }
    assert!(events.iter().any(|e| matches!(
        e,
        Event::Refused {
            reason: Refusal::Sender,
            id: 23,
            sender: 42,
            ..
        }
    )));
}

/// Behind PX4 the values are byte-wise (as QGroundControl reads every component of a PX4
/// vehicle), and a byte-wise PARAM_SET is read as such.
#[test]
fn behind_px4_the_values_are_bytewise() {
    let mut b = Bridge::new(
        Config::for_fc(FcProtocol::Mavlink),
        Port::Fc,
        MavAutopilot::MAV_AUTOPILOT_PX4,
    );
    b.input(&raw(
        SET,
        &param_set((1, 154), "BRG_TZ_MIN_WEST", 0x0000_FE20, ParamType::Int16),
        GCS,
    ));
    b.run(50);
    let v = &b.values.last().unwrap().1;
    assert_eq!((v.name.as_str(), v.bits), ("BRG_TZ_MIN_WEST", 0x0000_FE20));
    assert_eq!(b.engine.config().tz_minuteswest, -480);
    // A cast value is read too (a client that casts, whatever the autopilot).
    b.input(&raw(
        SET,
        &param_set(
            (1, 154),
            "BRG_FC_BAUD",
            57_600f32.to_bits(),
            ParamType::Uint32,
        ),
        GCS,
    ));
    b.run(50);
    assert_eq!(b.values.last().unwrap().1.bits, 57_600, "byte-wise back");
}

/// The telemetry link: the same parameters on component 158.
#[test]
fn the_telemetry_link_serves_them_on_158() {
    let mut b = Bridge::new(
        Config::for_fc(FcProtocol::Siyi),
        Port::Telemetry,
        MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA,
    );
    b.input(&raw(REQUEST_LIST, &[1, 158], GCS));
    b.run(2_000);
    assert_eq!(b.values.len(), table::param_count());
    assert!(b.values.iter().all(|(_, v)| v.comp == 158));
    assert_eq!(cast(&b.values[0].1), 0.0, "BRG_FC: SIYI");
    b.input(&raw(
        SET,
        &param_set(
            (1, 158),
            "BRG_POD_YAW_LEFT",
            1f32.to_bits(),
            ParamType::Uint8,
        ),
        GCS,
    ));
    assert!(b.engine.config().pod.yaw_positive_left, "live");
    let kept = b.engine.take_record().unwrap();
    assert_eq!((kept.key.0, kept.value()), (0x0119, &b"\x01\x01true"[..]));
    assert!(b.events().contains(&Event::Setting {
        key: 0x0119,
        source: SettingSource::Parameter(Port::Telemetry),
        outcome: SettingOutcome::Applied
    }));
}
