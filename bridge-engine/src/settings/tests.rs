//! The settings' table, values, records and state.

use super::table::{Access, SIDES, find};
use super::value::Value;
use super::*;
use crate::FcProtocol;
use crate::access::SigningMode;
use crate::config::Problem as ConfigProblem;
use crate::store::Key;

extern crate std;
use std::string::String;
use std::vec::Vec;

/// A value of `s` other than `c`'s, as the console would type it.
pub(crate) fn other_value(s: &Setting, c: &Config) -> String {
    let mut current = String::new();
    let _ = s.write(c, &mut current);
    match s.access {
        Access::Int { limit, get, .. } => {
            let v = if get(c) == limit.max {
                limit.min
            } else {
                limit.max
            };
            std::format!("{v}")
        }
        Access::MsOrOff { get, limit, .. } => match get(c) {
            Some(_) => "off".into(),
            None => std::format!("{}", limit.max),
        },
        Access::Bool { get, .. } => std::format!("{}", !get(c)),
        Access::Choice { names, get, .. } => names[(get(c) + 1) % names.len()].into(),
        Access::Side => if c.fc == FcProtocol::K40t {
            "siyi"
        } else {
            "k40t"
        }
        .into(),
        Access::Text { .. } => match s.key {
            "siyi.hardware_id" => "6B0000000002".into(),
            "viewlink.model" => "\"A \\\"Q\\\" B\"".into(),
            _ => "\"rtsp://10.1.2.3:8554/a\\\\b\"".into(),
        },
        Access::SigningKey => "0f".repeat(32),
        Access::GcsIds => "[7, 9]".into(),
        Access::K40tAllow => "[0x00030D, 0x000501]".into(),
    }
}

fn set_text(
    st: &mut Settings,
    key: &str,
    text: &str,
) -> Result<Accepted, crate::config::ConfigError> {
    let mut scratch = [0u8; value::MAX_TEXT];
    let v = value::parse(text, &mut scratch).unwrap();
    st.set(Settings::index_of(key).unwrap(), &v)
}

fn record_text(s: &Setting, c: &Config) -> String {
    let mut t = String::new();
    s.write_record(c, &mut t).unwrap();
    t
}

#[test]
fn the_table_keeps_its_promises() {
    let mut ids = Vec::new();
    let mut names = Vec::new();
    for s in &SETTINGS {
        assert!(s.id > 0 && !ids.contains(&s.id), "{}: id {}", s.key, s.id);
        ids.push(s.id);
        assert_eq!(s.record(), 0x0100 + u16::from(s.id));
        assert!(Key::SETTINGS.contains(&s.record()));
        assert_eq!(find(s.key).map(|f| f.id), Some(s.id), "{} unique", s.key);
        match s.param {
            Some(p) => {
                assert!(p.starts_with("BRG_") && p.len() <= 16, "{p}");
                assert!(!names.contains(&p), "{p} twice");
                names.push(p);
                let (min, max) = s.param_range().unwrap();
                let ty = s.param_type().unwrap();
                // Signed, as MAVSDK's parameter client lists them (it leaves UINT* out).
                assert!(
                    matches!(ty, ParamType::Int8 | ParamType::Int16 | ParamType::Int32),
                    "{p}: {ty:?}"
                );
                for v in [min, max] {
                    assert_eq!(ty.from_bytes(ty.to_bytes(v)), v, "{p}: {v} in {ty:?}");
                }
                // Exact as a float (the C-cast encoding) and subnormal as bytes.
                assert!(max < 1 << 23 && min > -(1 << 15), "{p}");
            }
            None => assert!(
                matches!(
                    s.access,
                    Access::Text { .. } | Access::SigningKey | Access::GcsIds
                ),
                "{}: a number with no parameter",
                s.key
            ),
        }
    }
    assert_eq!(table::param_count(), names.len());
    for (i, name) in names.iter().enumerate() {
        assert_eq!(table::by_param(name.as_bytes()).map(|(j, _)| j), Some(i));
        let mut padded = [0u8; 16];
        padded[..name.len()].copy_from_slice(name.as_bytes());
        assert_eq!(table::by_param(&padded).map(|(j, _)| j), Some(i));
        assert_eq!(table::param_at(i).and_then(|s| s.param), Some(*name));
    }
    assert!(table::by_param(b"BRG_NO_SUCH").is_none());
    assert_eq!(find("signing_key").map(Setting::secret), Some(true));
    assert_eq!(SETTINGS.iter().filter(|s| s.secret()).count(), 1);
}

/// Every setting's value, written as the console writes it, reads back to the same; a
/// value set is the one written; its record restores it.
#[test]
fn every_value_round_trips_through_its_text_and_its_record() {
    let sides = Sides::COMPILED;
    for s in &SETTINGS {
        let defaults = Config::DEFAULT;
        let mut st = Settings::new(defaults, sides);
        let text = other_value(s, &defaults);
        let index = Settings::index_of(s.key).unwrap();
        let mut scratch = [0u8; value::MAX_TEXT];
        let v = value::parse(&text, &mut scratch).unwrap();
        let mut c = defaults;
        if s.key == "signing" {
            // `sign` needs a key (the whole configuration is checked).
            c.signing_key = Some(crate::SigningKey([1; 32]));
            st = Settings::new(c, sides);
        }
        st.set(index, &v)
            .unwrap_or_else(|e| panic!("{} = {text}: {e}", s.key));
        assert!(!s.same(st.pending(), &c), "{} = {text} changes it", s.key);
        let mut again = c;
        s.restore(&mut again, &record_text(s, st.pending()), sides)
            .unwrap_or_else(|e| panic!("{}: record {e}", s.key));
        assert!(s.same(&again, st.pending()), "{}: its record", s.key);
        if !s.secret() {
            let mut written = String::new();
            s.write(st.pending(), &mut written).unwrap();
            let mut back = c;
            let mut scratch = [0u8; value::MAX_TEXT];
            s.assign(
                &mut back,
                &value::parse(&written, &mut scratch).unwrap(),
                sides,
            )
            .unwrap();
            assert!(s.same(&back, st.pending()), "{}: {written}", s.key);
        }
        if let Some(n) = s.number(st.pending()) {
            let mut back = c;
            s.assign_number(&mut back, n, sides).unwrap();
            assert!(s.same(&back, st.pending()), "{}: parameter {n}", s.key);
        }
    }
}

#[test]
fn values_are_checked_by_the_files_rules() {
    let mut st = Settings::new(Config::DEFAULT, Sides::COMPILED);
    let e = set_text(&mut st, "fc_baud", "12").unwrap_err();
    assert_eq!(
        std::format!("{e}"),
        "fc_baud: 12 is out of range 1200..=4000000"
    );
    let e = set_text(&mut st, "fc_baud", "fast").unwrap_err();
    assert_eq!(std::format!("{e}"), "fc_baud: expected a whole number");
    let e = set_text(&mut st, "signing", "always").unwrap_err();
    assert_eq!(
        std::format!("{e}"),
        "signing: expected one of \"off\", \"sign\", \"require\""
    );
    let e = set_text(&mut st, "siyi.hardware_id", "7A").unwrap_err();
    assert_eq!(
        std::format!("{e}"),
        "siyi.hardware_id: expected 12 ASCII characters"
    );
    let e = set_text(&mut st, "gcs_ids", "255").unwrap_err();
    assert_eq!(e.problem, ConfigProblem::Form(crate::config::Form::List));
    let e = set_text(&mut st, "gcs_ids", "[0]").unwrap_err();
    assert_eq!(std::format!("{e}"), "gcs_ids: 0 is out of range 1..=255");
    let e = set_text(&mut st, "k40t_allow", "[0x000302]").unwrap_err();
    assert_eq!(e.key, "k40t_allow");
    let e = set_text(&mut st, "pod.yaw_positive_left", "yes").unwrap_err();
    assert_eq!(
        std::format!("{e}"),
        "pod.yaw_positive_left: expected true or false"
    );
    // The whole configuration: signing without a key is refused, and nothing changed.
    let e = set_text(&mut st, "signing", "require").unwrap_err();
    assert_eq!(std::format!("{e}"), "signing_key: needed (signing is on)");
    assert_eq!(st.pending(), &Config::DEFAULT);
    assert_eq!(st.unsaved(), 0);
    // With the key first, then the mode.
    set_text(&mut st, "signing_key", &"ab".repeat(32)).unwrap();
    set_text(&mut st, "signing", "require").unwrap();
    assert_eq!(st.pending().signing, SigningMode::Require);
    assert_eq!(st.unsaved(), 2);
    // A side this bridge does not have.
    let mut only = Settings::new(Config::DEFAULT, Sides::of(&[FcProtocol::Siyi]));
    let e = set_text(&mut only, "fc", "gcu").unwrap_err();
    assert_eq!(std::format!("{e}"), "fc: not an FC side of this bridge");
    let index = Settings::index_of("fc").unwrap();
    assert!(only.set_number(index, 2).is_err());
    // `auto`: the default.
    let mut st = Settings::new(Config::for_fc(FcProtocol::Gcu), Sides::COMPILED);
    set_text(&mut st, "fc", "k40t").unwrap();
    set_text(&mut st, "fc", "auto").unwrap();
    assert_eq!(st.pending().fc, FcProtocol::Gcu);
    // k40t_geotag_fallback_ms: a time or "off", 0 is off as a parameter.
    set_text(&mut st, "k40t_geotag_fallback_ms", "\"off\"").unwrap();
    assert_eq!(st.pending().k40t_geotag_fallback, None);
    let e = set_text(&mut st, "k40t_geotag_fallback_ms", "0").unwrap_err();
    assert_eq!(
        std::format!("{e}"),
        "k40t_geotag_fallback_ms: 0 is out of range 1..=10000"
    );
}

#[test]
fn the_store_keeps_what_differs_from_the_defaults() {
    let mut st = Settings::new(Config::DEFAULT, Sides::COMPILED);
    set_text(&mut st, "fc_baud", "57600").unwrap();
    set_text(&mut st, "video.uri", "rtsp://10.0.0.9/x").unwrap();
    assert!(st.take_record().is_none(), "nothing kept before save");
    assert_eq!(st.save(), 2);
    let r = st.take_record().unwrap();
    assert_eq!(r.key.0, 0x0102);
    assert_eq!(r.value(), b"\x01\x0157600");
    let r = st.take_record().unwrap();
    assert_eq!(r.key.0, 0x011B);
    assert_eq!(r.value(), b"\x01\x01rtsp://10.0.0.9/x");
    assert!(st.take_record().is_none());
    // Set back to the default: recorded as "default".
    set_text(&mut st, "fc_baud", "115200").unwrap();
    st.save();
    let r = st.take_record().unwrap();
    assert_eq!((r.key.0, r.value()), (0x0102, &[1u8, 0][..]));
    // `defaults`: every setting the store holds back to "default", at once.
    set_text(&mut st, "leap_seconds", "19").unwrap();
    let restart = st.reset(&Config::DEFAULT);
    assert_eq!(restart, 0);
    assert_eq!(st.pending(), &Config::DEFAULT);
    let keys: Vec<_> = core::iter::from_fn(|| st.take_record())
        .map(|r| (r.key.0, r.value().to_vec()))
        .collect();
    assert_eq!(keys, [(0x0105, std::vec![1, 0]), (0x011B, std::vec![1, 0])]);
    // PARAM_SET keeps its one setting at once.
    let i = Settings::index_of("pod_baud").unwrap();
    st.set_number(i, 9600).unwrap();
    set_text(&mut st, "tz_minuteswest", "60").unwrap();
    st.keep(i);
    let r = st.take_record().unwrap();
    assert_eq!((r.key.0, r.value()), (0x0103, &b"\x01\x019600"[..]));
    assert!(st.take_record().is_none());
    assert_eq!(st.unsaved(), 1, "tz_minuteswest waits for save");
}

#[test]
fn live_settings_reach_the_running_configuration_and_restart_ones_wait() {
    let mut st = Settings::new(Config::DEFAULT, Sides::COMPILED);
    let mut running = Config::DEFAULT;
    set_text(&mut st, "tz_minuteswest", "-60").unwrap();
    set_text(&mut st, "fc_baud", "57600").unwrap();
    assert!(st.apply_live(&mut running));
    assert_eq!(running.tz_minuteswest, -60);
    assert_eq!(running.fc_baud, 115_200, "a restart setting waits");
    assert_eq!(st.restart_pending(&running), 1);
    assert!(!st.apply_live(&mut running), "nothing new");
}

fn restore_of(records: &[(u16, &[u8])], defaults: &Config) -> Restored {
    let mut r = Restore::new(*defaults, Sides::COMPILED);
    for (k, v) in records {
        r.record(*k, v);
    }
    r.finish()
}

#[test]
fn restoring_takes_each_record_and_reports_the_rest() {
    // Blank: the defaults, the store reset (LED), the header written.
    let mut r = restore_of(&[], &Config::DEFAULT);
    assert_eq!(r.reset, Some(Problem::Missing));
    assert!(r.store_reset());
    assert_eq!(r.config(), &Config::DEFAULT);
    let header = r.settings.take_record().unwrap();
    assert_eq!((header.key.0, header.value()), (HEADER, &[1u8][..]));
    assert!(r.settings.take_record().is_none());

    // Kept values over the defaults; a bad record keeps its default, said and rewritten.
    let r = restore_of(
        &[
            (HEADER, &[1]),
            (0x0102, b"\x01\x0157600"),
            (0x0105, b"\x01\x0119"),
            (0x0106, b"\x01\x01-99999"),
            (0x0107, b"\x02\x0110"),
            (0x011B, b"\x01\x01rtsp://x/y"),
            (0x0103, b"\x01\x00"),
            (0x01F0, b"\x01\x00"),
        ],
        &Config::DEFAULT,
    );
    assert_eq!(r.reset, None);
    let c = r.config();
    assert_eq!((c.fc_baud, c.leap_seconds), (57_600, 19));
    assert_eq!(c.video.configured_uri(), Some(&b"rtsp://x/y"[..]));
    assert_eq!(c.tz_minuteswest, 0);
    let problems: Vec<_> = r.problems.iter().flatten().copied().collect();
    assert_eq!(
        problems,
        [
            Found {
                key: 0x0106,
                problem: Problem::Value
            },
            Found {
                key: 0x0107,
                problem: Problem::Version { found: 2 }
            },
            Found {
                key: 0x01F0,
                problem: Problem::UnknownKey
            },
        ]
    );
    let mut st = r.settings.clone();
    let rewritten: Vec<_> = core::iter::from_fn(|| st.take_record())
        .map(|r| r.key.0)
        .collect();
    assert_eq!(rewritten, [0x0106, 0x0107]);

    // Each record valid, not all together: the defaults, and they are written.
    let r = restore_of(
        &[(HEADER, &[1]), (0x010A, b"\x01\x01\"require\"")],
        &Config::DEFAULT,
    );
    assert_eq!(r.reset, Some(Problem::Value));
    assert_eq!(r.config(), &Config::DEFAULT);

    // Unreadable: the defaults, nothing written but the header.
    let mut rs = Restore::new(Config::DEFAULT, Sides::COMPILED);
    rs.record(0x0102, b"\x01\x0157600");
    rs.unreadable();
    let mut r = rs.finish();
    assert_eq!(r.reset, Some(Problem::Unreadable));
    assert_eq!(r.config(), &Config::DEFAULT);
    assert_eq!(r.settings.take_record().map(|r| r.key.0), Some(HEADER));
    assert!(r.settings.take_record().is_none());

    // Garbage in every record: never a panic, each one reported or taken.
    for len in 0..MAX_RECORD + 3 {
        for fill in [0u8, 1, b'9', 0xFF] {
            let v = std::vec![fill; len];
            let mut rs = Restore::new(Config::DEFAULT, Sides::COMPILED);
            for key in Restore::keys() {
                rs.record(key, &v);
            }
            let r = rs.finish();
            assert!(r.config().validate().is_ok());
        }
    }
}

#[test]
fn the_signing_key_is_never_written_back() {
    let mut c = Config::DEFAULT;
    c.signing_key = Some(crate::SigningKey([0xAB; 32]));
    let s = find("signing_key").unwrap();
    let mut out = String::new();
    assert_eq!(
        s.write(&c, &mut out).map_err(|e| e.problem),
        Err(ConfigProblem::WriteOnly)
    );
    assert!(out.is_empty());
    assert!(s.number(&c).is_none() && s.param.is_none());
    // Only its record holds it (the store is the one place that does).
    assert_eq!(record_text(s, &c), "ab".repeat(32));
}

#[test]
fn written_values_are_the_files() {
    let mut c = Config::DEFAULT;
    c.k40t_allow = crate::K40tAllow::from_list(&[0x030D, 0x0501]).unwrap();
    let mut out = String::new();
    find("k40t_allow").unwrap().write(&c, &mut out).unwrap();
    assert_eq!(out, "[0x00030D, 0x000501]");
    out.clear();
    find("gcs_ids").unwrap().write(&c, &mut out).unwrap();
    assert_eq!(out, "[255, 245]");
    out.clear();
    find("sync.period_ms").unwrap().write(&c, &mut out).unwrap();
    assert_eq!(out, "10000");
    out.clear();
    find("viewlink.model").unwrap().write(&c, &mut out).unwrap();
    assert_eq!(out, "\"K40TBRIDGE\"");
    out.clear();
    find("fc").unwrap().write(&c, &mut out).unwrap();
    assert_eq!(out, "\"siyi\"");
    let _ = Value::Word("");
    assert_eq!(SIDES.len(), table::SIDE_NAMES.len());
}
