//! `gimbal` adapter for the GCU protocol (XF Robot gimbals).
//!
//! A capture may hold both directions (host `A8 E5` and GCU `8A 5E` packages). The codec
//! deframes one direction per framing, so the capture is scanned once per direction and
//! the two scans are merged: every package of either direction, the rejected candidates
//! that do not lie inside a valid package of the other direction, and as garbage only
//! the bytes that neither scan could place.

use protocol_core::gcu::{
    CATALOG, FeedbackKind, Frame, GcuFraming, GcuSub, HostSub, Message, Packet,
};
use serde_json::{Map, Value, json};

use super::{Decoded, Item, Protocol, as_object, hex, scan_with, untag};

/// The GCU protocol.
pub struct Gcu;

fn to_value<T: serde::Serialize>(v: &T) -> Result<Value, String> {
    serde_json::to_value(v).map_err(|e| e.to_string())
}

/// The parameters of a command as a JSON object (`{}` for an order without any).
fn command_fields(message: &Message<'_>) -> Result<Value, String> {
    match message {
        Message::Raw(r) => Ok(json!({ "order": r.id, "params": hex(r.payload) })),
        Message::Command(c) => Ok(as_object(untag(to_value(c)?).1, "value")),
    }
}

/// A package's direction, version, main frame and sub frame (when present) as fields.
fn head(
    fields: &mut Map<String, Value>,
    direction: &str,
    version: u8,
    main: Value,
    sub: Option<Value>,
) {
    fields.insert("direction".into(), json!(direction));
    fields.insert("version".into(), json!(version));
    fields.insert("main".into(), main);
    if let Some(sub) = sub {
        fields.insert("sub".into(), sub);
    }
}

/// Decodes one checksum-valid package of either direction.
pub fn decode(bytes: &[u8]) -> Result<Decoded, String> {
    let frame = Frame::new_checked(bytes).map_err(|e| e.to_string())?;
    let packet = Packet::parse(&frame).map_err(|e| e.to_string())?;
    let mut fields = Map::new();
    let (name, msg_id) = match packet {
        Packet::Host(p) => {
            let sub = p.frames.sub != HostSub::ABSENT;
            let sub = sub.then(|| to_value(&p.frames.sub)).transpose()?;
            let main = to_value(&p.frames.main)?;
            head(&mut fields, "host", p.header.version, main, sub);
            fields.insert("command".into(), command_fields(&p.message)?);
            (p.message.name().to_string(), p.message.id())
        }
        Packet::Gcu(p) => {
            let sub = p.frames.sub != GcuSub::ABSENT;
            let sub = sub.then(|| to_value(&p.frames.sub)).transpose()?;
            let main = to_value(&p.frames.main)?;
            head(&mut fields, "gcu", p.header.version, main, sub);
            fields.insert("execution".into(), to_value(&p.feedback.execution)?);
            if !p.feedback.extra.is_empty() {
                fields.insert("extra".into(), json!(hex(p.feedback.extra)));
            }
            (
                format!("{} feedback", p.feedback.order.name()),
                p.feedback.order.value(),
            )
        }
    };
    Ok(Decoded {
        msg_id: u64::from(msg_id),
        name,
        fields: Value::Object(fields),
    })
}

fn offset_of(item: &Item) -> usize {
    match item {
        Item::Frame { offset, .. }
        | Item::Rejected { offset, .. }
        | Item::Garbage { offset, .. }
        | Item::Truncated { offset, .. } => *offset,
    }
}

/// Merges the scans of the two directions (see the module documentation).
fn merge(capture: &[u8], scans: [Vec<Item>; 2]) -> Vec<Item> {
    let frames: Vec<(usize, usize)> = scans
        .iter()
        .flatten()
        .filter_map(|i| match i {
            Item::Frame { offset, raw, .. } => Some((*offset, offset + raw.len())),
            _ => None,
        })
        .collect();
    let inside_frame = |at: usize| frames.iter().any(|&(s, e)| s < at && at < e);
    let mut garbage = [vec![false; capture.len()], vec![false; capture.len()]];
    let mut items = Vec::new();
    for (scan, marks) in scans.into_iter().zip(garbage.iter_mut()) {
        for item in scan {
            match item {
                Item::Garbage { offset, raw } => {
                    marks[offset..offset + raw.len()].fill(true);
                }
                Item::Frame { .. } => items.push(item),
                Item::Rejected { offset, .. } | Item::Truncated { offset, .. } => {
                    if !inside_frame(offset) {
                        items.push(item);
                    }
                }
            }
        }
    }
    let mut start = None;
    for i in 0..=capture.len() {
        let both = i < capture.len() && garbage[0][i] && garbage[1][i];
        match (both, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                items.push(Item::Garbage {
                    offset: s,
                    raw: capture[s..i].to_vec(),
                });
                start = None;
            }
            _ => {}
        }
    }
    items.sort_by_key(offset_of);
    items
}

impl Protocol for Gcu {
    fn name(&self) -> &'static str {
        "gcu"
    }

    fn scan(&self, capture: &[u8]) -> Vec<Item> {
        merge(
            capture,
            [
                scan_with(GcuFraming::host(), capture, decode),
                scan_with(GcuFraming::gcu(), capture, decode),
            ],
        )
    }

    fn messages(&self) -> Vec<String> {
        CATALOG
            .iter()
            .map(|e| {
                let feedback = match e.feedback {
                    FeedbackKind::Status => "status",
                    FeedbackKind::Cameras => "cameras",
                };
                format!(
                    "{:#04x} {} params={} feedback={}",
                    e.id, e.name, e.payload_len, feedback
                )
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol_core::gcu::{
        CameraSet, Execution, Feedback, GcuFrames, GcuMain, GcuPacket, Header, HostPacket, Neutral,
        Order, Shutter,
    };

    fn host(message: impl Into<Message<'static>>) -> Vec<u8> {
        let mut out = [0u8; 300];
        let n = HostPacket::new(message).emit(&mut out).unwrap();
        out[..n].to_vec()
    }

    fn reply(order: Order) -> Vec<u8> {
        let p = GcuPacket {
            header: Header { version: 2 },
            frames: GcuFrames {
                main: GcuMain::default(),
                sub: GcuSub::ABSENT,
            },
            feedback: Feedback::new(order, Execution::Success),
        };
        let mut out = [0u8; 300];
        let n = p.emit(&mut out).unwrap();
        out[..n].to_vec()
    }

    #[test]
    fn both_directions_in_one_capture() {
        let mut capture = vec![0x00, 0x8A];
        let shutter = host(Shutter(CameraSet::CAMERA_1));
        capture.extend(&shutter);
        capture.extend(reply(Order::Shutter));
        let mut bad = host(Neutral {});
        bad[50] ^= 1;
        capture.extend(&bad);
        capture.extend([0x11, 0x22]);
        let items = Gcu.scan(&capture);
        let frames: Vec<_> = items
            .iter()
            .filter_map(|i| match i {
                Item::Frame {
                    offset,
                    decoded: Ok(d),
                    ..
                } => Some((*offset, d.name.clone(), d.msg_id)),
                _ => None,
            })
            .collect();
        assert_eq!(
            frames,
            vec![
                (2, "Shutter".to_string(), 0x20),
                (75, "Shutter feedback".to_string(), 0x20)
            ]
        );
        let rejected: Vec<_> = items
            .iter()
            .filter_map(|i| match i {
                Item::Rejected { offset, .. } => Some(*offset),
                _ => None,
            })
            .collect();
        assert_eq!(rejected, vec![148]);
        let garbage: Vec<_> = items
            .iter()
            .filter_map(|i| match i {
                Item::Garbage { offset, raw } => Some((*offset, raw.len())),
                _ => None,
            })
            .collect();
        assert_eq!(garbage, vec![(0, 2), (220, 2)]);
        let Item::Frame { decoded: Ok(d), .. } = &items[1] else {
            panic!("{:?}", items[1]);
        };
        assert_eq!(d.fields["command"], json!({ "value": 1 }));
        assert_eq!(d.fields["direction"], json!("host"));
        assert_eq!(d.fields["main"]["status"]["ins_valid"], json!(false));
        assert_eq!(d.fields["main"]["status"]["raw"], json!(0));
        let Item::Frame { decoded: Ok(r), .. } = &items[2] else {
            panic!("{:?}", items[2]);
        };
        assert_eq!(r.fields["direction"], json!("gcu"));
        assert_eq!(r.fields["version"], json!(2));
        assert_eq!(r.fields["main"]["camera_status"]["tracking"], json!(false));
        // The execution state shows its name and its wire code, as enumerations do.
        assert_eq!(
            r.fields["execution"],
            json!({ "name": "Success", "code": 0 })
        );
        assert!(super::super::flat_fields(&r.fields).contains("execution=Success(0x00)"));
    }

    #[test]
    fn messages_lists_26_orders() {
        let lines = Gcu.messages();
        assert_eq!(lines.len(), 26);
        assert_eq!(lines[0], "0x00 Null params=0 feedback=status");
        assert!(lines.contains(&"0x17 Track params=10 feedback=cameras".to_string()));
    }
}
