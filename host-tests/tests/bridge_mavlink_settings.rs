//! The camera's definition file and settings (docs/src/bridge/mavlink.md, "Settings and
//! the camera definition"; "Storage and reset"): the engine between a simulated autopilot
//! (ArduPilot's routing, PX4's), a ground station downloading the definition over MAVLink
//! FTP and setting parameters in QGroundControl's way or MAVSDK's
//! (`gimbal/src/sim/camera_settings.rs`), and the simulated pod, which keeps its settings
//! as the K40T document describes (`gimbal/src/sim/pod/settings.rs`).

use crate::engine_scenarios;
// The bridge's own settings as parameters (the engine alone).
mod bridge_params;

use bridge_engine::{Config, Event, FcProtocol};
use gimbal::sim::Autopilot;
use gimbal::sim::ap_mavlink::{ApMavlink, ApMavlinkConfig};
use gimbal::sim::camera_settings::{ClientStyle, SettingsClient, op};
use gimbal::sim::pilot::Pilot;
use gimbal::sim::pod::{PodSimConfig, SimPod};
use gimbal::sim::px4::{Px4, Px4Config};
use gimbal::sim::qgc::{Qgc, QgcConfig};
use gimbal::sim::scenario::Scenario;

use engine_scenarios::{MS, S};
use protocol_core::k40t::{
    self, AckCode, FactoryReset, FormatSd, IrParamsQuery, MessageData, VisibleParamsQuery,
};
use protocol_core::mavlink::MavMessage;
use protocol_core::mavlink::dialect::{
    CharArray, MavCmd, MavParamExtType, MavResult, PARAM_EXT_SET_DATA, ParamAck,
    STORAGE_INFORMATION_DATA, StorageStatus,
};

/// The file the bridge serves, and the XML it is made from.
const DEFINITION: &[u8] = include_bytes!("../../bridge-engine/camera/k40t.xml.xz");
const XML: &str = include_str!("../../bridge-engine/camera/k40t.xml");

fn client(style: ClientStyle, drop: Vec<usize>) -> Qgc {
    Qgc::new(QgcConfig {
        client: style,
        drop_burst_replies: drop,
        ..QgcConfig::default()
    })
}

/// ArduPilot routing a ground station of `style`; the bridge configured as `config`.
fn ap(style: ClientStyle, drop: Vec<usize>, config: Config) -> Scenario<ApMavlink> {
    let fc = ApMavlink::new(ApMavlinkConfig::default());
    let mut s = engine_scenarios::scenario_with(config, fc, PodSimConfig::default(), 25);
    s.fc.gcs = Some(client(style, drop));
    s
}

/// PX4 (gimbal v2 output, MAV_1_FORWARD) routing a ground station of `style`.
fn px4(style: ClientStyle) -> Scenario<Px4> {
    let fc = Px4::new(Px4Config::default());
    let mut s = engine_scenarios::scenario(fc, PodSimConfig::default(), -30);
    s.fc.gcs = Some(client(style, Vec::new()));
    s
}

fn mavlink() -> Config {
    Config::for_fc(FcProtocol::Mavlink)
}

/// The scenario's ground station.
trait Gcs {
    fn gcs(&mut self) -> &mut Qgc;
}

impl Gcs for Scenario<ApMavlink> {
    fn gcs(&mut self) -> &mut Qgc {
        self.fc.gcs.as_mut().unwrap()
    }
}

impl Gcs for Scenario<Px4> {
    fn gcs(&mut self) -> &mut Qgc {
        self.fc.gcs.as_mut().unwrap()
    }
}

fn definition<F: Pilot>(s: &mut Scenario<F>) -> &mut SettingsClient
where
    Scenario<F>: Gcs,
{
    s.gcs().definition().expect("a camera with a definition")
}

/// Runs until the ground station has the definition and every value (at most `limit`).
fn loaded<F: Pilot>(s: &mut Scenario<F>, limit: u64) -> u64
where
    Scenario<F>: Gcs,
{
    while s.now_us < limit {
        s.run_for(100 * MS);
        let done = s
            .gcs()
            .definition()
            .is_some_and(|d| d.loaded() && d.all_values());
        if done {
            return s.now_us;
        }
    }
    panic!("no definition by {} ms", limit / MS);
}

/// The opcodes of a download, runs of the same opcode as (opcode, count).
fn runs(ops: &[u8]) -> Vec<(u8, usize)> {
    let mut out: Vec<(u8, usize)> = Vec::new();
    for &o in ops {
        match out.last_mut() {
            Some((last, n)) if *last == o => *n += 1,
            _ => out.push((o, 1)),
        }
    }
    out
}

/// Every FILE_TRANSFER_PROTOCOL the autopilot got from the camera: (µs, data size).
fn ftp_replies(ap: &ApMavlink) -> Vec<u64> {
    ap.received
        .iter()
        .filter(|(_, h, id)| *id == 110 && h.component_id == 100)
        .map(|(t, _, _)| *t)
        .collect()
}

#[test]
fn qgroundcontrol_downloads_the_definition_in_bursts_byte_for_byte_through_ardupilot() {
    let mut s = ap(ClientStyle::Qgc, Vec::new(), mavlink());
    let at = loaded(&mut s, 10 * S);
    assert!(
        at < 4 * S,
        "the definition and every value by {} ms",
        at / MS
    );
    let d = definition(&mut s);
    assert_eq!(d.file.as_deref(), Some(DEFINITION));
    assert_eq!(d.definition.as_deref(), Some(XML));
    // 4, bursts of at most 8 replies (2112 bytes: 8 + 1), the burst at the end answered
    // NAK EOF, no hole to fill, then 2.
    let bursts = DEFINITION.len().div_ceil(239).div_ceil(8);
    assert_eq!(
        runs(&d.ops),
        [(op::OPEN, 1), (op::BURST, bursts + 1), (op::RESET, 1)]
    );
    assert_eq!(d.names.len(), 33);
    assert_eq!(d.names[0], "CAM_MODE");
    // The values, as the pod reports them (the simulated pod starts at the defaults).
    assert_eq!(d.value("CAM_PHOTORES"), Some(0x15));
    assert_eq!(d.value("IR_PALETTE"), Some(1));
    assert_eq!(d.value("CAM_STREAMBR"), Some(4));
    // Then QGroundControl asks the rest of the camera's state.
    s.run_for(4 * S);
    let cam = s.gcs().camera.clone().unwrap();
    assert_eq!(cam.video_mode, Some(false));
    assert_eq!(cam.capacity_mib, Some(122_070.0));
    assert!(cam.capture.is_some());
    // The pod was asked for its settings when its link came up.
    assert!(!s.pod.received_of::<IrParamsQuery>().is_empty());
    assert!(!s.pod.received_of::<VisibleParamsQuery>().is_empty());
}

#[test]
fn replies_are_paced_and_bounded_on_the_fc_link() {
    let mut s = ap(ClientStyle::Qgc, Vec::new(), mavlink());
    loaded(&mut s, 10 * S);
    let t = ftp_replies(&s.fc);
    let data: Vec<u64> = t.iter().copied().skip(1).take(9).collect();
    // A 266-byte reply is 23 ms of line at 115200 baud: 1.5 times that between two
    // (read at the autopilot's loop, within its few milliseconds).
    for w in data.windows(2) {
        assert!(w[1] - w[0] >= 30 * MS, "{} us apart", w[1] - w[0]);
    }
    // Paced 34.6 ms apart; each read at the autopilot's loop, up to ~5 ms late, which
    // moves the mean of 8 by up to 0.6 ms (measured 33.8 to 34.4 ms as the phase of the
    // device's other frames moves; unpaced replies would be 23 ms apart).
    let mean = (data[data.len() - 1] - data[0]) / (data.len() as u64 - 1);
    assert!(mean >= 33 * MS, "{mean} us apart on average");
    // The device's own traffic goes on: the attitude status at 10 Hz, nothing dropped.
    let (from, to) = (t[0], t[t.len() - 1] + 100 * MS);
    let statuses =
        s.fc.received
            .iter()
            .filter(|(at, h, id)| *id == 285 && h.component_id == 154 && (from..to).contains(at))
            .count() as u64;
    assert!(
        statuses + 1 >= (to - from) / (100 * MS),
        "{statuses} statuses"
    );
    assert!(
        s.events_where(|e| matches!(e, Event::Dropped { .. }))
            .is_empty()
    );
    assert_eq!(s.fc.parse_errors(), 0);
}

#[test]
fn qgroundcontrol_fills_the_holes_of_lost_burst_replies_with_read_file() {
    let mut s = ap(ClientStyle::Qgc, vec![2, 5], mavlink());
    loaded(&mut s, 10 * S);
    let d = definition(&mut s);
    assert_eq!(d.file.as_deref(), Some(DEFINITION));
    let r = runs(&d.ops);
    assert_eq!(r.first(), Some(&(op::OPEN, 1)));
    assert_eq!(r.last(), Some(&(op::RESET, 1)));
    // The holes, each one ReadFile, after the bursts.
    let reads = d.ops.iter().filter(|o| **o == op::READ).count();
    assert_eq!(reads, 2);
    let first_read = d.ops.iter().position(|o| *o == op::READ).unwrap();
    assert!(d.ops[..first_read].iter().all(|o| *o != op::RESET));
}

#[test]
fn a_lost_burst_end_is_sent_again_when_qgroundcontrol_asks_again() {
    // The first burst's last reply (its `burst_complete`) lost: QGroundControl asks the
    // same burst again after its 1 s time-out, with the same seq, and gets it.
    let mut s = ap(ClientStyle::Qgc, vec![7], mavlink());
    loaded(&mut s, 10 * S);
    let d = definition(&mut s);
    assert_eq!(d.file.as_deref(), Some(DEFINITION));
    let bursts = d.ops.iter().filter(|o| **o == op::BURST).count();
    assert_eq!(bursts, DEFINITION.len().div_ceil(239).div_ceil(8) + 2);
    assert!(!d.ops.contains(&op::READ));
}

#[test]
fn mavsdk_downloads_with_read_file_and_terminates_through_px4() {
    let mut s = px4(ClientStyle::Mavsdk);
    loaded(&mut s, 15 * S);
    let d = definition(&mut s);
    assert_eq!(d.file.as_deref(), Some(DEFINITION));
    assert_eq!(d.definition.as_deref(), Some(XML));
    assert_eq!(
        runs(&d.ops),
        [
            (op::OPEN, 1),
            (op::READ, DEFINITION.len().div_ceil(239)),
            (op::TERMINATE, 1)
        ]
    );
    // Every parameter read by name.
    assert!(d.all_values());
}

/// A value other than the default for every setting the test sets, and where the
/// simulated pod keeps it (CAM_BACKLIGHT stays off: strong-light suppression is on).
const VALUES: [(&str, u64); 32] = [
    ("CAM_MODE", 1),
    ("CAM_IMAGEMODE", 7),
    ("CAM_PHOTOMODE", 2),
    ("CAM_BURST", 5),
    ("CAM_LAPSE", 30),
    ("CAM_PHOTORES", 0x14),
    ("CAM_VIDRES", 0x26),
    ("CAM_STREAMBR", 6),
    ("CAM_STREAMENC", 1),
    ("CAM_OSD", 1),
    ("CAM_STABILIZE", 1),
    ("CAM_ISO", 3),
    ("CAM_SHUTTERSPD", 13),
    ("CAM_EV", 0x10),
    ("CAM_WBMODE", 6),
    ("CAM_FLICKER", 2),
    ("CAM_METERING", 3),
    ("CAM_AELOCK", 1),
    ("CAM_HLSUPP", 1),
    ("CAM_HLSUPP_LV", 70),
    ("CAM_BACKLIGHT_LV", 30),
    ("IR_PALETTE", 5),
    ("IR_GAIN", 2),
    ("IR_MEASURE", 0),
    ("IR_TEMP_OSD", 1),
    ("IR_ZOOM", 4),
    ("IR_SHARPNESS", 80),
    ("IR_BRIGHTNESS", 20),
    ("IR_CONTRAST", 65),
    ("IR_DENOISE", 0),
    ("IR_DENOISE_LV", 30),
    ("IR_ENHANCE", 7),
];

/// The simulated pod's own state of setting `name` (as the parameter codes it).
fn on_the_pod(pod: &SimPod, name: &str) -> u64 {
    let c = pod.camera();
    let st = &c.settings;
    let b = |v: bool| u64::from(v);
    u64::from(match name {
        "CAM_MODE" => c.mode.value(),
        "CAM_IMAGEMODE" => c.image_mode.value(),
        "CAM_PHOTOMODE" => c.photo_mode.value(),
        "CAM_BURST" => c.burst_count,
        "CAM_LAPSE" => c.timelapse_s,
        "CAM_PHOTORES" => st.photo_resolution.value(),
        "CAM_VIDRES" => st.video_resolution.value(),
        "CAM_STREAMBR" => c.bitrate.value(),
        "CAM_STREAMENC" => c.codec.value(),
        "CAM_OSD" => return b(st.watermark),
        "CAM_STABILIZE" => return b(pod.gimbal().stabilization),
        "CAM_ISO" => st.iso.value(),
        "CAM_SHUTTERSPD" => st.shutter.value(),
        "CAM_EV" => c.ev.value(),
        "CAM_WBMODE" => st.white_balance.value(),
        "CAM_FLICKER" => st.anti_flicker.value(),
        "CAM_METERING" => st.metering.value(),
        "CAM_AELOCK" => return b(c.ae_lock == k40t::AeLock::On),
        "CAM_HLSUPP" => return b(st.strong_light.0),
        "CAM_HLSUPP_LV" => st.strong_light.1,
        "CAM_BACKLIGHT_LV" => st.backlight.1,
        "IR_PALETTE" => c.palette.value(),
        "IR_GAIN" => st.ir_gain.value(),
        "IR_MEASURE" => return b(c.ir_measuring),
        "IR_TEMP_OSD" => return b(st.ir_temp_overlay),
        "IR_ZOOM" => st.ir_zoom,
        "IR_SHARPNESS" => st.ir_sharpness,
        "IR_BRIGHTNESS" => st.ir_brightness,
        "IR_CONTRAST" => st.ir_contrast,
        "IR_DENOISE" => return b(st.ir_denoise.0),
        "IR_DENOISE_LV" => st.ir_denoise.1,
        "IR_ENHANCE" => st.ir_enhancement,
        other => panic!("{other}"),
    })
}

/// Sets every value of [`VALUES`], one at a time; each ACCEPTED after an IN_PROGRESS,
/// applied by the pod; then asks every value again (after the accepted values' hold: the
/// values are the pod's reports) and finds them.
fn every_setting_set_and_read_back<F: Pilot>(s: &mut Scenario<F>, relist: bool)
where
    Scenario<F>: Gcs,
{
    for (name, value) in VALUES {
        definition(s).set(name, value);
        s.run_for(1500 * MS);
        let d = definition(s);
        assert_eq!(
            d.set_results.last(),
            Some(&(name.to_owned(), ParamAck::PARAM_ACK_ACCEPTED)),
            "{name}"
        );
        let acks: Vec<ParamAck> = d
            .acks
            .iter()
            .filter(|(n, _, _)| n == name)
            .map(|(_, r, _)| *r)
            .collect();
        assert_eq!(
            acks,
            [
                ParamAck::PARAM_ACK_IN_PROGRESS,
                ParamAck::PARAM_ACK_ACCEPTED
            ],
            "{name}"
        );
        assert_eq!(d.value(name), Some(value), "{name}");
        assert_eq!(on_the_pod(&s.pod, name), value, "{name} on the pod");
    }
    s.run_for(3 * S);
    if relist {
        definition(s).request_list();
    }
    let before = definition(s).values_received;
    s.run_for(3 * S);
    let d = definition(s);
    assert!(d.values_received >= before + 33 || !relist);
    for (name, value) in VALUES {
        assert_eq!(d.value(name), Some(value), "{name} read back");
    }
}

#[test]
fn every_setting_is_set_and_read_back_through_ardupilot_as_qgroundcontrol_does() {
    let mut s = ap(ClientStyle::Qgc, Vec::new(), mavlink());
    loaded(&mut s, 10 * S);
    every_setting_set_and_read_back(&mut s, true);
    // Each set became one K40T command (no repeats: each ACK came).
    let translated = s.events_where(|e| matches!(e, Event::Translated { fc_id: 323, .. }));
    assert_eq!(translated.len(), VALUES.len());
}

#[test]
fn every_setting_is_set_and_read_back_through_px4_as_mavsdk_does() {
    let mut s = px4(ClientStyle::Mavsdk);
    loaded(&mut s, 15 * S);
    // MAVSDK reads every parameter again after each accepted set.
    every_setting_set_and_read_back(&mut s, false);
}

#[test]
fn a_refused_set_fails_with_the_current_value_and_the_same_value_is_accepted_at_once() {
    let mut s = ap(ClientStyle::Qgc, Vec::new(), mavlink());
    loaded(&mut s, 10 * S);
    // The pod refuses palettes: FAILED, retried by QGroundControl, FAILED again.
    s.pod.set_nak(0x0106, Some(AckCode::Failure));
    definition(&mut s).set("IR_PALETTE", 9);
    s.run_for(6 * S);
    let d = definition(&mut s);
    assert_eq!(
        d.set_results.last(),
        Some(&("IR_PALETTE".to_owned(), ParamAck::PARAM_ACK_FAILED))
    );
    let failed: Vec<u64> = d
        .acks
        .iter()
        .filter(|(n, r, _)| n == "IR_PALETTE" && *r == ParamAck::PARAM_ACK_FAILED)
        .map(|(_, _, v)| *v)
        .collect();
    assert_eq!(
        failed,
        [1, 1, 1],
        "QGroundControl's three tries, the current value"
    );
    assert_eq!(s.pod.camera().palette.value(), 1);
    // The document's own refusal: backlight compensation while strong-light
    // suppression is on.
    definition(&mut s).set("CAM_HLSUPP", 1);
    s.run_for(2 * S);
    definition(&mut s).set("CAM_BACKLIGHT", 1);
    s.run_for(6 * S);
    let d = definition(&mut s);
    assert_eq!(
        d.set_results.last(),
        Some(&("CAM_BACKLIGHT".to_owned(), ParamAck::PARAM_ACK_FAILED))
    );
    assert_eq!(d.value("CAM_BACKLIGHT"), Some(0));
    // The value it already has: ACCEPTED at once, nothing sent to the pod.
    let sent = s.pod.requests().len();
    definition(&mut s).set("CAM_ISO", 0);
    s.run_for(S);
    let d = definition(&mut s);
    assert_eq!(
        d.acks.last().map(|(n, r, v)| (n.as_str(), *r, *v)),
        Some(("CAM_ISO", ParamAck::PARAM_ACK_ACCEPTED, 0))
    );
    assert_eq!(s.pod.requests().len(), sent);
}

#[test]
fn a_set_the_pod_never_answers_fails_after_its_time_out() {
    let mut s = ap(ClientStyle::Mavsdk, Vec::new(), mavlink());
    loaded(&mut s, 10 * S);
    s.pod.drop_acks(0x0203, 100);
    definition(&mut s).set("CAM_ISO", 5);
    s.run_for(3 * S);
    let d = definition(&mut s);
    let isos: Vec<(ParamAck, u64)> = d
        .acks
        .iter()
        .filter(|(n, _, _)| n == "CAM_ISO")
        .map(|(_, r, v)| (*r, *v))
        .collect();
    assert_eq!(
        isos,
        [
            (ParamAck::PARAM_ACK_IN_PROGRESS, 5),
            (ParamAck::PARAM_ACK_FAILED, 0)
        ]
    );
    // The pod's retries, then the time-out event.
    assert_eq!(s.pod.received_of::<k40t::IsoSetting>().len(), 3);
    assert!(
        !s.events_where(|e| matches!(e, Event::PodTimeout { base: 0x0203 }))
            .is_empty()
    );
}

#[test]
fn an_unknown_name_a_wrong_type_or_value_is_value_unsupported() {
    let mut s = ap(ClientStyle::Qgc, Vec::new(), mavlink());
    loaded(&mut s, 10 * S);
    let set = |name: &str, value: u32, ty| {
        let mut id = [0u8; 16];
        id[..name.len()].copy_from_slice(name.as_bytes());
        let mut v = [0u8; 128];
        v[..4].copy_from_slice(&value.to_le_bytes());
        MavMessage::PARAM_EXT_SET(PARAM_EXT_SET_DATA {
            target_system: 1,
            target_component: 100,
            param_id: CharArray::from(id),
            param_value: CharArray::from(v),
            param_type: ty,
        })
    };
    let u8t = MavParamExtType::MAV_PARAM_EXT_TYPE_UINT8;
    let u32t = MavParamExtType::MAV_PARAM_EXT_TYPE_UINT32;
    for m in [
        set("NO_SUCH_PARAM", 1, u8t),
        set("CAM_ISO", 3, u32t),
        set("CAM_ISO", 9, u8t),
        set("CAM_MODE", 1, u8t),
    ] {
        s.gcs().send_message(&m);
    }
    s.run_for(S);
    let d = definition(&mut s);
    let got: Vec<(&str, ParamAck, u64)> = d
        .acks
        .iter()
        .map(|(n, r, v)| (n.as_str(), *r, *v))
        .collect();
    let unsupported = ParamAck::PARAM_ACK_VALUE_UNSUPPORTED;
    assert_eq!(
        got,
        [
            ("NO_SUCH_PARAM", unsupported, 0),
            ("CAM_ISO", unsupported, 0),
            ("CAM_ISO", unsupported, 0),
            ("CAM_MODE", unsupported, 0),
        ]
    );
    assert!(s.pod.received_of::<k40t::IsoSetting>().is_empty());
}

fn storage(q: &mut Qgc) -> Option<STORAGE_INFORMATION_DATA> {
    q.camera.as_ref().and_then(|c| c.storage.clone())
}

#[test]
fn storage_format_and_reset_are_denied_unless_the_configuration_allows_them() {
    let mut s = ap(ClientStyle::Qgc, Vec::new(), mavlink());
    loaded(&mut s, 10 * S);
    s.run_for(3 * S);
    s.gcs().format_storage();
    s.gcs()
        .command(MavCmd::MAV_CMD_RESET_CAMERA_SETTINGS, [1.0, 0.0, 0.0, 0.0]);
    s.run_for(3 * S);
    let q = s.gcs();
    assert_eq!(
        q.ack_of(MavCmd::MAV_CMD_STORAGE_FORMAT),
        Some(MavResult::MAV_RESULT_DENIED)
    );
    assert_eq!(
        q.ack_of(MavCmd::MAV_CMD_RESET_CAMERA_SETTINGS),
        Some(MavResult::MAV_RESULT_DENIED)
    );
    let denied: Vec<u16> = s
        .events_where(|e| matches!(e, Event::DestructiveDenied { .. }))
        .iter()
        .map(|(_, e)| match e {
            Event::DestructiveDenied { command } => *command,
            _ => 0,
        })
        .collect();
    assert_eq!(denied, [526, 529]);
    assert!(s.pod.received_of::<FormatSd>().is_empty());
    assert!(s.pod.received_of::<FactoryReset>().is_empty());
}

#[test]
fn an_allowed_format_empties_the_card_and_storage_information_follows() {
    let mut config = mavlink();
    config.mavlink.allow_destructive = true;
    let mut s = ap(ClientStyle::Qgc, Vec::new(), config);
    loaded(&mut s, 10 * S);
    s.run_for(3 * S);
    let before = storage(s.gcs()).expect("storage information");
    assert_eq!(before.used_capacity, 12_000.0);
    // Not while recording: the pod refuses, the command FAILED.
    s.gcs().record(true);
    s.run_for(2 * S);
    s.gcs().format_storage();
    s.run_for(3 * S);
    assert_eq!(
        s.gcs().ack_of(MavCmd::MAV_CMD_STORAGE_FORMAT),
        Some(MavResult::MAV_RESULT_FAILED)
    );
    s.gcs().record(false);
    s.run_for(2 * S);
    let t0 = s.now_us;
    s.gcs().format_storage();
    s.run_for(4 * S);
    let q = s.gcs();
    assert_eq!(
        q.ack_of(MavCmd::MAV_CMD_STORAGE_FORMAT),
        Some(MavResult::MAV_RESULT_ACCEPTED)
    );
    let after = storage(q).unwrap();
    assert_eq!(after.status, StorageStatus::STORAGE_STATUS_READY);
    assert_eq!(after.used_capacity, 0.0);
    assert_eq!(after.available_capacity, after.total_capacity);
    // STORAGE_INFORMATION unasked: at the ACK and when the card shows empty.
    let unasked =
        s.fc.received
            .iter()
            .filter(|(t, h, id)| *id == 261 && h.component_id == 100 && *t > t0)
            .count();
    assert!(unasked >= 2, "{unasked}");
    assert!(!s.pod.received_of::<FormatSd>().is_empty());
}

#[test]
fn an_allowed_reset_restores_the_pods_settings_and_they_are_read_again() {
    let mut config = mavlink();
    config.mavlink.allow_destructive = true;
    let mut s = ap(ClientStyle::Qgc, Vec::new(), config);
    loaded(&mut s, 10 * S);
    definition(&mut s).set("IR_PALETTE", 12);
    definition(&mut s).set("IR_TEMP_OSD", 1);
    s.run_for(4 * S);
    assert_eq!(definition(&mut s).value("IR_PALETTE"), Some(12));
    s.gcs()
        .command(MavCmd::MAV_CMD_RESET_CAMERA_SETTINGS, [1.0, 0.0, 0.0, 0.0]);
    s.run_for(4 * S);
    assert_eq!(
        s.gcs().ack_of(MavCmd::MAV_CMD_RESET_CAMERA_SETTINGS),
        Some(MavResult::MAV_RESULT_ACCEPTED)
    );
    assert_eq!(s.pod.received_of::<FactoryReset>().len(), 1);
    // The values come back unasked (the client asked for parameters before).
    let d = definition(&mut s);
    assert_eq!(d.value("IR_PALETTE"), Some(1));
    assert_eq!(d.value("IR_TEMP_OSD"), Some(0));
}

#[test]
fn a_change_made_elsewhere_is_announced() {
    let mut s = ap(ClientStyle::Qgc, Vec::new(), mavlink());
    loaded(&mut s, 10 * S);
    // QGroundControl's photo/video switch (SET_CAMERA_MODE): CAM_MODE follows.
    s.gcs().set_mode(true);
    s.run_for(3 * S);
    assert_eq!(definition(&mut s).value("CAM_MODE"), Some(1));
    assert_eq!(
        s.pod
            .received_of::<k40t::CaptureModeSetting>()
            .last()
            .map(|(_, _, m)| m.mode),
        Some(k40t::CaptureMode::Video)
    );
    // The encoded id of the frames the pod got: every one a K40T frame it decoded.
    assert_eq!(k40t::CaptureModeSetting::ID.base, 0x0300);
}
