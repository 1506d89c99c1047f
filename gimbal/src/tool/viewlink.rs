//! `gimbal` adapter for the Viewlink protocol (Viewpro gimbals): serial frames (`55 AA DC`, and
//! `AA 55 DC` as the document prints its ACK) and TCP envelopes (`EB 90`).

use protocol_core::viewlink::tcp::{Envelope, TcpFraming};
use protocol_core::viewlink::{
    CATALOG, CatalogEntry, Direction, Frame, Message, Packet, SyncOrder, ViewlinkFraming,
};
use serde_json::{Value, json};

use super::{Decoded, Item, Protocol, hex, scan_with, untag};

/// The Viewlink protocol.
pub struct Viewlink;

/// The message id the tool reports for a TCP envelope (its two sync bytes).
pub const TCP_MSG_ID: u64 = 0xEB90;

fn fields_of(packet: &Packet<'_>) -> Result<Value, String> {
    let body = match packet.message {
        Message::Raw(r) => json!({ "data": hex(r.payload) }),
        Message::Transparent(t) => json!({ "data": hex(t.data.as_slice()) }),
        m => {
            let v = untag(serde_json::to_value(m).map_err(|e| e.to_string())?).1;
            match v {
                Value::Object(_) => v,
                // Single-block frames of enum blocks (A1, C2, ...) serialise as
                // {"Variant": {...}}; keep that shape under the block name.
                other => json!({ "value": other }),
            }
        }
    };
    let blocks = CATALOG
        .iter()
        .find(|e| e.id == packet.message.id())
        .map_or("unknown", |e| e.blocks);
    let mut fields = json!({
        "header": match packet.header.sync {
            SyncOrder::Standard => "55 AA DC",
            SyncOrder::Swapped => "AA 55 DC",
        },
        "counter": packet.header.counter,
        "frame_id": format!("{:#04x}", packet.message.id()),
        "blocks": blocks,
    });
    if let (Value::Object(f), Value::Object(b)) = (&mut fields, body) {
        f.extend(b);
    }
    Ok(fields)
}

/// Who sends a frame to whom, in the document's words.
fn route(e: &CatalogEntry) -> &'static str {
    match (e.direction, e.from_ahrs) {
        (Direction::FromGimbal, _) => "payload->console",
        (Direction::ToGimbal, true) => "ahrs->payload",
        (Direction::ToGimbal, false) => "console->payload",
    }
}

/// Decodes one checksum-valid serial frame.
pub fn decode(bytes: &[u8]) -> Result<Decoded, String> {
    let frame = Frame::new_checked(bytes).map_err(|e| e.to_string())?;
    let packet = Packet::parse(&frame).map_err(|e| e.to_string())?;
    Ok(Decoded {
        msg_id: u64::from(packet.message.id()),
        name: packet.message.name().to_string(),
        fields: fields_of(&packet)?,
    })
}

/// Decodes one checksum-valid TCP envelope (and the serial frame in its body, if any).
pub fn decode_tcp(bytes: &[u8]) -> Result<Decoded, String> {
    let env = Envelope::decode(bytes).map_err(|e| e.to_string())?;
    let serial = match env.serial() {
        Ok(p) => json!({
            "name": p.message.name(),
            "fields": fields_of(&p)?,
        }),
        Err(e) => Value::String(format!("not a serial frame: {e}")),
    };
    Ok(Decoded {
        msg_id: TCP_MSG_ID,
        name: "TcpEnvelope".to_string(),
        fields: json!({ "body": hex(env.body), "serial": serial }),
    })
}

/// Rescans a garbage run with another framing; `None` unless that finds a frame.
fn rescan(offset: usize, raw: &[u8], scan: impl Fn(&[u8]) -> Vec<Item>) -> Option<Vec<Item>> {
    let items = scan(raw);
    if !items.iter().any(|i| matches!(i, Item::Frame { .. })) {
        return None;
    }
    Some(
        items
            .into_iter()
            .map(|i| match i {
                Item::Frame {
                    offset: o,
                    raw,
                    decoded,
                } => Item::Frame {
                    offset: o + offset,
                    raw,
                    decoded,
                },
                Item::Rejected {
                    offset: o,
                    raw,
                    error,
                } => Item::Rejected {
                    offset: o + offset,
                    raw,
                    error,
                },
                Item::Garbage { offset: o, raw } => Item::Garbage {
                    offset: o + offset,
                    raw,
                },
                Item::Truncated { offset: o, raw } => Item::Truncated {
                    offset: o + offset,
                    raw,
                },
            })
            .collect(),
    )
}

/// Replaces each garbage run in which `scan` finds a frame by what `scan` reports.
fn refine(items: Vec<Item>, scan: impl Fn(&[u8]) -> Vec<Item>) -> Vec<Item> {
    let mut out = Vec::new();
    for item in items {
        match item {
            Item::Garbage { offset, raw } => match rescan(offset, &raw, &scan) {
                Some(found) => out.extend(found),
                None => out.push(Item::Garbage { offset, raw }),
            },
            other => out.push(other),
        }
    }
    out
}

impl Protocol for Viewlink {
    fn name(&self) -> &'static str {
        "viewlink"
    }

    fn scan(&self, capture: &[u8]) -> Vec<Item> {
        let items = scan_with(ViewlinkFraming::new(), capture, decode);
        // Garbage may hold frames of the other sync order or TCP envelopes.
        let items = refine(items, |b| scan_with(ViewlinkFraming::swapped(), b, decode));
        refine(items, |b| scan_with(TcpFraming, b, decode_tcp))
    }

    fn messages(&self) -> Vec<String> {
        CATALOG
            .iter()
            .map(|e| format!("{:#04x} {} {} {}", e.id, e.name, route(e), e.blocks))
            .collect()
    }
}
