//! The camera definition (`bridge-engine/camera/k40t.xml`) against what the bridge serves
//! and answers: the `.xz` it serves is the XML, the version it announces is the XML's,
//! and the parameters are [`settings::ALL`](super::settings::ALL) with their names, types,
//! values and defaults, in the rules QGroundControl and MAVSDK hold a definition to
//! (docs/src/bridge/mavlink.md, "Settings and the camera definition").

use super::ftp::{DEFINITION, DEFINITION_URI, DEFINITION_VERSION};
use super::settings::{ALL, Values};

const XML: &str = include_str!("../../../camera/k40t.xml");

/// The value of `attr="..."` in `tag` (the text of one start tag).
fn attr<'a>(tag: &'a str, attr: &str) -> Option<&'a str> {
    let key = format!(" {attr}=\"");
    let start = tag.find(&key)? + key.len();
    Some(&tag[start..start + tag[start..].find('"')?])
}

/// Every `<parameter ...>...</parameter>` block, from the space before its first
/// attribute.
fn parameters() -> Vec<&'static str> {
    XML.match_indices("<parameter ")
        .map(|(at, tag)| {
            let p = &XML[at + tag.len() - 1..];
            &p[..p.find("</parameter>").expect("closed")]
        })
        .collect()
}

#[test]
fn the_served_file_is_the_xml_compressed_with_xz() {
    let mut out = Vec::new();
    lzma_rs::xz_decompress(&mut &DEFINITION[..], &mut out).expect("an xz stream");
    assert_eq!(
        String::from_utf8(out).expect("UTF-8"),
        XML,
        "k40t.xml.xz is not k40t.xml: regenerate it (docs/src/bridge/mavlink.md)"
    );
    assert_eq!(DEFINITION_URI, b"mftp://k40t.xml.xz");
}

#[test]
fn the_announced_version_is_the_definitions() {
    let tag = &XML[XML.find("<definition").unwrap()..];
    let tag = &tag[..tag.find('>').unwrap()];
    assert_eq!(
        attr(tag, "version"),
        Some(DEFINITION_VERSION.to_string().as_str())
    );
    assert!(XML.contains("<model>K40T four-sensor pod</model>"));
    assert!(XML.contains("<vendor>K40T</vendor>"));
}

#[test]
fn the_parameters_are_the_settings_table_and_both_ground_stations_accept_them() {
    let params = parameters();
    assert_eq!(params.len(), ALL.len());
    for (p, s) in params.iter().zip(ALL) {
        let tag = &p[..p.find('>').unwrap()];
        let name = attr(tag, "name").unwrap();
        assert_eq!(name, s.name());
        assert!(name.len() <= 16, "{name}: longer than 16");
        // Every parameter described (MAVSDK drops a file with one that is not).
        assert!(p.contains("<description>"), "{name}");
        let ty = if s.wide() { "uint32" } else { "uint8" };
        assert_eq!(attr(tag, "type"), Some(ty), "{name}");
        let default: u8 = attr(tag, "default").unwrap().parse().unwrap();
        assert_eq!(default, s.default_value(), "{name}: default");
        // The default among the values (MAVSDK rejects the whole file otherwise).
        assert!(s.allows(default), "{name}: default");
        match s.values() {
            Values::Options(values) => {
                let listed: Vec<u8> = p
                    .split("<option ")
                    .skip(1)
                    .map(|o| attr(o, "value").unwrap().parse().unwrap())
                    .collect();
                assert_eq!(listed, values, "{name}: options");
                assert!(attr(tag, "min").is_none(), "{name}");
            }
            Values::Range(min, max) => {
                // A numeric parameter without options needs min and max (MAVSDK).
                assert!(!p.contains("<options>"), "{name}");
                assert_eq!(attr(tag, "min"), Some(min.to_string().as_str()), "{name}");
                assert_eq!(attr(tag, "max"), Some(max.to_string().as_str()), "{name}");
                assert_eq!(attr(tag, "step"), Some("1"), "{name}");
            }
        }
        // Exclusions name parameters of the file.
        for ex in p.split("<exclude>").skip(1) {
            let other = &ex[..ex.find("</exclude>").unwrap()];
            assert!(
                ALL.iter().any(|o| o.name() == other),
                "{name} excludes {other}"
            );
        }
    }
    // The mode parameter (QGroundControl's photo/video switch), hidden from the list.
    let mode = params[0];
    assert!(mode.starts_with(" name=\"CAM_MODE\"") && mode.contains("control=\"0\""));
}
