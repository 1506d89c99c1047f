//! How the frames of each FC side read for people (the demo, traces): a frame decoded to
//! one line ([`Described`]), which traffic is routine, the name of a command. Per
//! protocol ([`SideFrames`]: [`SiyiFrames`], [`ViewlinkFrames`], [`GcuFrames`],
//! [`K40tFrames`], [`MavlinkFrames`]), whichever simulator speaks it.

use bridge_engine::FcProtocol;
use protocol_core::Direction;
use protocol_core::gcu::{self, GcuFraming};
use protocol_core::k40t::{self, K40tFraming, Kind, MessageData as _};
use protocol_core::mavlink::dialect::Message as _;
use protocol_core::mavlink::{MavlinkFraming, Message, Packet};
use protocol_core::siyi::{self, SiyiFraming};
use protocol_core::viewlink::{self, ViewlinkFraming};
use protocol_core::wire::Framing;
use serde::Serialize;
use serde_json::Value;

/// A frame decoded for display: `SIYI 0x07 GimbalRotation yaw=0 pitch=-100`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Described {
    /// Protocol label (`SIYI`, `Viewlink`, `K40T`).
    pub protocol: &'static str,
    /// Message id (K40T: the 24-bit id, kind included).
    pub id: u32,
    /// Hex digits of the id when printed.
    pub digits: usize,
    /// Message name.
    pub name: String,
    /// Payload fields as `key=value` pairs (headers, sequence numbers and reserved
    /// bytes left out, so that two frames with the same meaning print the same).
    pub fields: String,
}

impl Described {
    /// A message of `protocol` with its id (printed with `digits` hex digits), its name and
    /// the payload's fields ([`fields_text`]).
    fn message<T: Serialize + ?Sized>(
        protocol: &'static str,
        (id, digits): (u32, usize),
        name: &str,
        payload: &T,
    ) -> Self {
        Described {
            protocol,
            id,
            digits,
            name: name.to_string(),
            fields: fields_text(payload),
        }
    }
}

impl core::fmt::Display for Described {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "{} 0x{:0w$X} {}",
            self.protocol,
            self.id,
            self.name,
            w = self.digits
        )?;
        if !self.fields.is_empty() {
            write!(f, " {}", self.fields)?;
        }
        Ok(())
    }
}

/// How one FC protocol's frames read for people.
pub trait SideFrames {
    /// The FC protocol.
    const PROTOCOL: FcProtocol;
    /// The framing of the FC link.
    type Framing: Framing;
    /// Framing of the frames the FC sends (`from_fc`) or receives.
    fn framing(from_fc: bool) -> Self::Framing;
    /// One checksum-valid frame of the FC link, decoded for display.
    fn describe(frame: &[u8], from_fc: bool) -> Option<Described>;
    /// Periodic traffic (polls, telemetry, status) rather than a command: the demo shows
    /// only the first of these.
    fn routine(id: u32, from_fc: bool) -> bool;
    /// A name for the FC id of the engine's `Translated` event.
    fn command_name(fc_id: u16) -> String;
}

/// The SIYI side.
#[derive(Debug, Clone, Copy)]
pub struct SiyiFrames;
/// The Viewlink side.
#[derive(Debug, Clone, Copy)]
pub struct ViewlinkFrames;
/// The GCU side.
#[derive(Debug, Clone, Copy)]
pub struct GcuFrames;
/// The K40T side (an FC speaking K40T itself).
#[derive(Debug, Clone, Copy)]
pub struct K40tFrames;
/// The MAVLink side.
#[derive(Debug, Clone, Copy)]
pub struct MavlinkFrames;

/// `key=value` pairs of a serialised payload: objects are flattened with dotted keys,
/// enumerations (`{"name", "code"}`) print their name, reserved fields are left out.
#[must_use]
pub fn fields_text<T: Serialize + ?Sized>(value: &T) -> String {
    fn walk(prefix: &str, v: &Value, out: &mut Vec<String>) {
        let key = |k: &str| {
            if prefix.is_empty() {
                k.to_string()
            } else {
                format!("{prefix}.{k}")
            }
        };
        match v {
            Value::Object(m) if m.len() == 2 && m.get("name").is_some_and(Value::is_string) => {
                let name = m.get("name").and_then(Value::as_str).unwrap_or_default();
                out.push(if prefix.is_empty() {
                    name.to_string()
                } else {
                    format!("{prefix}={name}")
                });
            }
            Value::Object(m) => {
                for (k, v) in m {
                    if !k.starts_with("reserved") {
                        walk(&key(k), v, out);
                    }
                }
            }
            Value::Array(a) if a.iter().all(Value::is_number) => {
                // Byte strings (names, folders): as text when printable, else their length.
                let bytes: Vec<u8> = a
                    .iter()
                    .filter_map(Value::as_u64)
                    .filter_map(|b| u8::try_from(b).ok())
                    .collect();
                let text: String = bytes
                    .iter()
                    .take_while(|&&b| b != 0)
                    .map(|&b| char::from(b))
                    .collect();
                if bytes.len() == a.len()
                    && bytes.len() > 4
                    && text.chars().all(|c| c.is_ascii_graphic() || c == ' ')
                {
                    if !text.is_empty() {
                        out.push(format!("{prefix}={text:?}"));
                    }
                } else if a.len() <= 6 {
                    let s: Vec<String> = a.iter().map(Value::to_string).collect();
                    out.push(format!("{prefix}=[{}]", s.join(",")));
                } else {
                    out.push(format!("{prefix}=[{} bytes]", a.len()));
                }
            }
            Value::Null => {}
            other => out.push(if prefix.is_empty() {
                other.to_string()
            } else {
                format!("{prefix}={other}")
            }),
        }
    }
    let mut out = Vec::new();
    if let Ok(v) = serde_json::to_value(value) {
        walk("", &untag(v), &mut out);
    }
    out.join(" ")
}

/// Strips enum tags (`{"Request": {"GimbalRotation": {...}}}` → `{...}`).
fn untag(mut v: Value) -> Value {
    loop {
        match v {
            Value::Object(m)
                if m.len() == 1
                    && m.keys()
                        .next()
                        .is_some_and(|k| k.starts_with(|c: char| c.is_ascii_uppercase())) =>
            {
                v = m.into_iter().next().map(|(_, v)| v).unwrap_or_default();
            }
            other => return other,
        }
    }
}

/// A K40T frame decoded for display.
#[must_use]
pub fn describe_k40t(frame: &[u8]) -> Option<Described> {
    let p = k40t::Packet::decode(frame).ok()?;
    let id = p.message.id();
    let name = p.message.name();
    Some(Described::message(
        "K40T",
        (id.to_u32(), 6),
        name,
        &p.message,
    ))
}

/// K40T periodic traffic: reports, status frames, the pod's ACKs (`from_pod`) and
/// (from the FC) its 0x00030E.
#[must_use]
pub fn k40t_routine(id: u32, from_pod: bool) -> bool {
    let kind = (id >> 16) & 0xFF;
    let base = id & 0xFFFF;
    let report = k40t::CATALOG
        .iter()
        .any(|e| u32::from(e.base) == base && e.report);
    report
        || kind == u32::from(Kind::Status.value())
        || (from_pod && kind == u32::from(Kind::Ack.value()))
}

/// The name of a K40T base id.
#[must_use]
pub fn k40t_name(base: u16) -> &'static str {
    k40t::CATALOG
        .iter()
        .find(|e| e.base == base)
        .map_or("?", |e| e.name)
}

impl SideFrames for SiyiFrames {
    const PROTOCOL: FcProtocol = FcProtocol::Siyi;
    type Framing = SiyiFraming;

    fn framing(_from_fc: bool) -> SiyiFraming {
        SiyiFraming::new(siyi::MAX_PAYLOAD_LEN)
    }

    fn describe(frame: &[u8], from_fc: bool) -> Option<Described> {
        let direction = if from_fc {
            Direction::ToGimbal
        } else {
            Direction::FromGimbal
        };
        let p = siyi::Packet::decode(frame, direction).ok()?;
        let (id, name) = (u32::from(p.message.id()), p.message.name());
        Some(Described::message("SIYI", (id, 2), name, &p.message))
    }

    fn routine(id: u32, from_fc: bool) -> bool {
        if from_fc {
            // Identity, configuration, attitude, laser, thermal, codec polls and the
            // aircraft's attitude and position.
            matches!(
                id,
                0x00 | 0x01 | 0x02 | 0x0A | 0x0D | 0x14 | 0x15 | 0x20 | 0x22 | 0x3E
            )
        } else {
            // Every reply but the function feedback (photo/record failures).
            id != 0x0B
        }
    }

    fn command_name(fc_id: u16) -> String {
        let names = siyi::CATALOG.iter().map(|e| (u16::from(e.id), e.name));
        format!("SIYI 0x{fc_id:02X} {}", name_in(names, fc_id))
    }
}

impl SideFrames for ViewlinkFrames {
    const PROTOCOL: FcProtocol = FcProtocol::Viewlink;
    type Framing = ViewlinkFraming;

    fn framing(_from_fc: bool) -> ViewlinkFraming {
        ViewlinkFraming::new()
    }

    fn describe(frame: &[u8], _from_fc: bool) -> Option<Described> {
        let p = viewlink::Packet::decode(frame).ok()?;
        let (id, name) = (u32::from(p.message.id()), p.message.name());
        Some(Described::message("Viewlink", (id, 2), name, &p.message))
    }

    fn routine(id: u32, from_fc: bool) -> bool {
        if from_fc {
            // Handshake, identity queries (U) and M_AHRS.
            matches!(id, 0x00 | 0x01 | 0xB1)
        } else {
            // Status (0x40) and identity (V) replies.
            true
        }
    }

    fn command_name(fc_id: u16) -> String {
        let [frame, command] = fc_id.to_be_bytes();
        let names = viewlink::CATALOG.iter().map(|e| (u16::from(e.id), e.name));
        let name = name_in(names, u16::from(frame));
        format!("Viewlink 0x{frame:02X} {name} (command 0x{command:02X})")
    }
}

/// Centidegrees as degrees with two decimals, for display.
fn deg2(cdeg: i32) -> String {
    format!("{:.2}", f64::from(cdeg) / 100.0)
}

impl SideFrames for GcuFrames {
    const PROTOCOL: FcProtocol = FcProtocol::Gcu;
    type Framing = GcuFraming;

    fn framing(from_fc: bool) -> GcuFraming {
        if from_fc {
            GcuFraming::host()
        } else {
            GcuFraming::gcu()
        }
    }

    fn describe(frame: &[u8], _from_fc: bool) -> Option<Described> {
        // The control quantities or the gimbal's angles of the main frame, then the
        // order's parameters or its feedback.
        let (id, name, fields) = match gcu::Packet::decode(frame).ok()? {
            gcu::Packet::Host(p) => {
                let m = p.frames.main;
                // The control quantities' unit follows the order (the gimbal mode).
                let unit = match p.message.id() {
                    0x10 | 0x14 => " (0.01°)",
                    0x11..=0x13 | 0x16 => " (0.1°/s)",
                    _ => "",
                };
                let control = format!(
                    "control roll={} pitch={} yaw={}{unit}",
                    m.roll_control, m.pitch_control, m.yaw_control
                );
                let params = fields_text(&p.message);
                let fields = if params.is_empty() || matches!(p.message, gcu::Message::Raw(_)) {
                    control
                } else {
                    format!("{control} {params}")
                };
                (p.message.id(), p.message.name(), fields)
            }
            gcu::Packet::Gcu(p) => {
                let m = p.frames.main;
                let mut fields = format!(
                    "mode={} roll={} pitch={} yaw={}",
                    fields_text(&m.mode),
                    deg2(i32::from(m.rel_x_cdeg)),
                    deg2(i32::from(m.rel_y_cdeg)),
                    deg2(i32::from(m.rel_z_cdeg)),
                );
                if let Some(e) = p.feedback.execution {
                    fields.push_str(" feedback=");
                    fields.push_str(e.name());
                }
                (p.feedback.id(), p.feedback.order.name(), fields)
            }
        };
        Some(Described {
            protocol: "GCU",
            id: u32::from(id),
            digits: 2,
            name: name.to_string(),
            fields,
        })
    }

    fn routine(id: u32, from_fc: bool) -> bool {
        // Every package from ArduPilot carries the control quantities (its commands):
        // none is routine; every reply is.
        let _ = id;
        !from_fc
    }

    fn command_name(fc_id: u16) -> String {
        let names = gcu::CATALOG.iter().map(|e| (u16::from(e.id), e.name));
        format!("GCU 0x{fc_id:02X} {}", name_in(names, fc_id))
    }
}

impl SideFrames for K40tFrames {
    const PROTOCOL: FcProtocol = FcProtocol::K40t;
    type Framing = K40tFraming;

    fn framing(_from_fc: bool) -> K40tFraming {
        K40tFraming::any()
    }

    fn describe(frame: &[u8], _from_fc: bool) -> Option<Described> {
        describe_k40t(frame)
    }

    fn routine(id: u32, from_fc: bool) -> bool {
        if from_fc {
            // Its own 0x00030E every 10 s.
            id == k40t::TimeSync::ID.to_u32()
        } else {
            // What the bridge forwards from the pod, but the pod's GPS requests.
            id != k40t::GpsRequest::ID.to_u32()
        }
    }

    fn command_name(fc_id: u16) -> String {
        format!("K40T 0x{fc_id:06X} {}", k40t_name(fc_id))
    }
}

impl SideFrames for MavlinkFrames {
    const PROTOCOL: FcProtocol = FcProtocol::Mavlink;
    type Framing = MavlinkFraming;

    fn framing(_from_fc: bool) -> MavlinkFraming {
        MavlinkFraming::new()
    }

    fn describe(frame: &[u8], _from_fc: bool) -> Option<Described> {
        describe_mavlink(frame)
    }

    fn routine(id: u32, from_fc: bool) -> bool {
        mavlink_routine(id, from_fc)
    }

    fn command_name(fc_id: u16) -> String {
        mavlink_command_name(fc_id)
    }
}

/// The name of message `id` in a protocol's catalogue of (id, name), "?" if it has none.
fn name_in(mut names: impl Iterator<Item = (u16, &'static str)>, id: u16) -> &'static str {
    names.find(|(i, _)| *i == id).map_or("?", |(_, name)| name)
}

/// A MAVLink frame decoded for display (the demo and traces).
#[must_use]
pub fn describe_mavlink(frame: &[u8]) -> Option<Described> {
    let p = Packet::decode(frame).ok()?;
    let Message::Known(m) = &p.message else {
        return None;
    };
    let id = m.message_id();
    Some(Described {
        protocol: "MAVLink",
        id,
        digits: 0,
        name: m.message_name().to_string(),
        fields: format!(
            "from {}/{} {}",
            p.header.system_id,
            p.header.component_id,
            fields_text(m)
        ),
    })
}

/// MAVLink periodic traffic: heartbeats, streams, time and state from the FC; from the
/// device everything but its ACKs and captured images.
#[must_use]
pub fn mavlink_routine(id: u32, from_fc: bool) -> bool {
    if from_fc {
        matches!(id, 0 | 2 | 24 | 30 | 33 | 111 | 286)
    } else {
        !matches!(id, 77 | 263)
    }
}

/// The name of the FC id of the engine's `Translated` event on the MAVLink side: a
/// MAV_CMD number, or 284 for GIMBAL_DEVICE_SET_ATTITUDE.
#[must_use]
pub fn mavlink_command_name(fc_id: u16) -> String {
    let name = match fc_id {
        284 => "GIMBAL_DEVICE_SET_ATTITUDE",
        530 => "MAV_CMD_SET_CAMERA_MODE",
        531 => "MAV_CMD_SET_CAMERA_ZOOM",
        532 => "MAV_CMD_SET_CAMERA_FOCUS",
        2000 => "MAV_CMD_IMAGE_START_CAPTURE",
        2001 => "MAV_CMD_IMAGE_STOP_CAPTURE",
        2500 => "MAV_CMD_VIDEO_START_CAPTURE",
        2501 => "MAV_CMD_VIDEO_STOP_CAPTURE",
        _ => "?",
    };
    format!("MAVLink {fc_id} {name}")
}
