//! Generates the dialect: the messages below, trimmed from the official MAVLink XML in
//! `xml/` (common.xml with the standard.xml and minimal.xml it includes, as shipped in the
//! `mavlink` 0.21.0 crate), then rust-mavlink's own generator (`mavlink-bindgen`) writes
//! the Rust code. Trimming keeps every listed message whole (extension fields included)
//! and the enumerations their fields name, plus the ones listed below.

use std::fmt::Write as _;
use std::path::PathBuf;

/// The message set: what a gimbal-v2 device + camera-v2 + time/position consumer sees
/// (see docs/src/protocols/mavlink.md; what the autopilots send:
/// docs/src/autopilots/ardupilot.md, docs/src/autopilots/px4.md).
const MESSAGES: &[&str] = &[
    "HEARTBEAT",
    "SYSTEM_TIME",
    "GPS_RAW_INT",
    "ATTITUDE",
    "GLOBAL_POSITION_INT",
    "REQUEST_DATA_STREAM",
    "COMMAND_INT",
    "COMMAND_LONG",
    "COMMAND_ACK",
    "TIMESYNC",
    "FILE_TRANSFER_PROTOCOL",
    "CAMERA_TRIGGER",
    "MESSAGE_INTERVAL",
    "STATUSTEXT",
    "CAMERA_INFORMATION",
    "CAMERA_SETTINGS",
    "STORAGE_INFORMATION",
    "CAMERA_CAPTURE_STATUS",
    "CAMERA_IMAGE_CAPTURED",
    "VIDEO_STREAM_INFORMATION",
    "VIDEO_STREAM_STATUS",
    "CAMERA_FOV_STATUS",
    "CAMERA_TRACKING_IMAGE_STATUS",
    "CAMERA_THERMAL_RANGE",
    "DISTANCE_SENSOR",
    "GIMBAL_MANAGER_INFORMATION",
    "GIMBAL_MANAGER_STATUS",
    "GIMBAL_DEVICE_INFORMATION",
    "GIMBAL_DEVICE_SET_ATTITUDE",
    "GIMBAL_DEVICE_ATTITUDE_STATUS",
    "AUTOPILOT_STATE_FOR_GIMBAL_DEVICE",
    "PARAM_EXT_REQUEST_READ",
    "PARAM_EXT_REQUEST_LIST",
    "PARAM_EXT_VALUE",
    "PARAM_EXT_SET",
    "PARAM_EXT_ACK",
    // The bridge's own settings as parameters (bridge-engine/src/fc/mavlink/bridge_params.rs).
    "PARAM_REQUEST_READ",
    "PARAM_REQUEST_LIST",
    "PARAM_VALUE",
    "PARAM_SET",
    // Signing: the autopilot's system gives the device a new key (docs/src/security.md).
    "SETUP_SIGNING",
    // The bridge's version, asked of its components (bridge-engine/src/version.rs).
    "AUTOPILOT_VERSION",
];

/// Enumerations no field names but the bridge needs (component ids, result and command
/// codes are named by fields too; listed for clarity).
const EXTRA_ENUMS: &[&str] = &[
    "MAV_COMPONENT",
    "MAV_CMD",
    "MAV_RESULT",
    "MAV_TYPE",
    "GIMBAL_DEVICE_FLAGS",
    "GIMBAL_DEVICE_CAP_FLAGS",
    "GIMBAL_DEVICE_ERROR_FLAGS",
    "CAMERA_CAP_FLAGS",
    "MAV_FRAME",
    "GPS_FIX_TYPE",
    "MAV_DATA_STREAM",
];

/// Every `<tag ...>...</tag>` block of `xml` whose opening starts with `open`.
fn blocks<'a>(xml: &'a str, open: &str, close: &str) -> Vec<&'a str> {
    let mut out = Vec::new();
    let mut rest = xml;
    while let Some(start) = rest.find(open) {
        let tail = &rest[start..];
        let end = tail.find(close).expect("unclosed element") + close.len();
        out.push(&tail[..end]);
        rest = &tail[end..];
    }
    out
}

/// The value of `attr="..."` in the first tag of `block`.
fn attr<'a>(block: &'a str, attr: &str) -> &'a str {
    let tag = &block[..block.find('>').expect("tag")];
    let key = format!(" {attr}=\"");
    let start = tag.find(&key).expect("attribute") + key.len();
    &tag[start..start + tag[start..].find('"').expect("quote")]
}

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap());
    let out = PathBuf::from(std::env::var("OUT_DIR").unwrap());
    let mut enums = Vec::new();
    let mut messages = Vec::new();
    for file in ["minimal.xml", "standard.xml", "common.xml"] {
        let path = manifest.join("xml").join(file);
        println!("cargo:rerun-if-changed={}", path.display());
        let xml = std::fs::read_to_string(&path).unwrap();
        enums.extend(
            blocks(&xml, "<enum name=\"", "</enum>")
                .into_iter()
                .map(str::to_owned),
        );
        messages.extend(
            blocks(&xml, "<message id=\"", "</message>")
                .into_iter()
                .map(str::to_owned),
        );
    }
    let kept: Vec<&String> = MESSAGES
        .iter()
        .map(|name| {
            messages
                .iter()
                .find(|m| attr(m, "name") == *name)
                .unwrap_or_else(|| panic!("{name} is not in the XML"))
        })
        .collect();
    let mut wanted: Vec<String> = EXTRA_ENUMS.iter().map(|e| (*e).to_owned()).collect();
    for m in &kept {
        for piece in m.split(" enum=\"").skip(1) {
            wanted.push(piece[..piece.find('"').unwrap()].to_owned());
        }
    }
    wanted.sort();
    wanted.dedup();
    let mut xml = String::from(
        "<?xml version=\"1.0\"?>\n<mavlink>\n<version>3</version>\n<dialect>0</dialect>\n<enums>\n",
    );
    for name in &wanted {
        // An enumeration may be extended in a later file (MAV_CMD, MAV_TYPE): keep every part.
        let parts: Vec<&String> = enums.iter().filter(|e| attr(e, "name") == name).collect();
        assert!(!parts.is_empty(), "enum {name} is not in the XML");
        for part in parts {
            writeln!(xml, "{part}").unwrap();
        }
    }
    xml.push_str("</enums>\n<messages>\n");
    for m in &kept {
        writeln!(xml, "{m}").unwrap();
    }
    xml.push_str("</messages>\n</mavlink>\n");
    let dir = out.join("xml");
    std::fs::create_dir_all(&dir).unwrap();
    let trimmed = dir.join("gimbal.xml");
    std::fs::write(&trimmed, xml).unwrap();

    let rust = out.join("mavlink");
    std::fs::create_dir_all(&rust).unwrap();
    mavlink_bindgen::generate(mavlink_bindgen::XmlDefinitions::Files(vec![trimmed]), &rust)
        .unwrap();
    // The generator gates the module behind a `dialect-<name>` cargo feature (the mavlink
    // crate's convention); this crate has one dialect, always on.
    let mod_rs = rust.join("mod.rs");
    let text = std::fs::read_to_string(&mod_rs).unwrap();
    let ungated = text.replace("# [cfg (feature = \"dialect-gimbal\")]", "");
    assert_ne!(text, ungated, "the generated mod.rs changed shape");
    std::fs::write(&mod_rs, ungated).unwrap();

    // `From<X_DATA> for MavMessage` for every message, so that one non-generic encoder
    // (compiled here, see lib.rs) serves every type.
    let mut from = String::new();
    for name in MESSAGES {
        writeln!(
            from,
            "impl From<{name}_DATA> for MavMessage {{ fn from(m: {name}_DATA) -> Self {{ MavMessage::{name}(m) }} }}"
        )
        .unwrap();
    }
    // The dialect's ids with their CRC_EXTRA, payload length and name, as one lookup.
    from.push_str("/// The message set's CRC_EXTRA, largest payload length and name of `id`; `None` for an id outside it.\n");
    from.push_str(
        "#[must_use]\npub fn message_info(id: u32) -> Option<MessageInfo> {\n    match id {\n",
    );
    for name in MESSAGES {
        writeln!(
            from,
            "        {name}_DATA::ID => Some(MessageInfo {{ id, crc_extra: {name}_DATA::EXTRA_CRC, max_len: {name}_DATA::ENCODED_LEN as u8, name: {name}_DATA::NAME }}),"
        )
        .unwrap();
    }
    from.push_str("        _ => None,\n    }\n}\n");
    // Decoding from a zero-extended 255-byte payload: each message's deserialiser sees a
    // slice whose length (255) is known, so its "shorter than the message" branch (a
    // copy_from_slice) is provably dead.
    from.push_str("pub(crate) fn decode_full(id: u32, full: &[u8; 255]) -> Result<MavMessage, ParserError> {\n    match id {\n");
    for name in MESSAGES {
        writeln!(
            from,
            "        {name}_DATA::ID => <{name}_DATA as MessageData>::deser(MavlinkVersion::V2, full).map(MavMessage::{name}),"
        )
        .unwrap();
    }
    from.push_str("        _ => Err(ParserError::UnknownMessage { id }),\n    }\n}\n");
    std::fs::write(out.join("from.rs"), from).unwrap();
}
