//! `gimbal` adapter for the SIYI SDK protocol.
//!
//! A capture does not say which way each frame travelled, so frames are decoded with
//! [`Packet::decode_auto`]: the direction the CTRL `is_ack` flag suggests, or the other
//! one when only that fits the data length. The direction used is in the fields.

use protocol_core::Direction;
use protocol_core::siyi::{CATALOG, MAX_PAYLOAD_LEN, Message, Packet, SiyiFraming};
use serde_json::json;

use super::{Decoded, Item, Protocol, scan_with, untag};

/// The SIYI SDK protocol.
pub struct Siyi;

/// Decodes one checksum-valid frame.
pub fn decode(bytes: &[u8]) -> Result<Decoded, String> {
    let packet = Packet::decode_auto(bytes).map_err(|e| e.to_string())?;
    let message = packet.message;
    let payload = match message {
        Message::Request(m) => untag(serde_json::to_value(m).map_err(|e| e.to_string())?).1,
        Message::Reply(m) => untag(serde_json::to_value(m).map_err(|e| e.to_string())?).1,
        Message::Raw(r) => json!({ "data": super::hex(r.payload) }),
    };
    let direction = match message.direction() {
        Direction::ToGimbal => "request",
        Direction::FromGimbal => "reply",
    };
    let h = packet.header;
    let header = json!({
        "direction": direction,
        "ctrl": h.ctrl.0,
        "need_ack": h.ctrl.need_ack(),
        "is_ack": h.ctrl.is_ack(),
        "seq": h.seq,
    });
    let name = message.name().to_string();
    Ok(Decoded::new(u64::from(message.id()), name, header, payload))
}

impl Protocol for Siyi {
    fn name(&self) -> &'static str {
        "siyi"
    }

    fn scan(&self, capture: &[u8]) -> Vec<Item> {
        // A capture may hold frames of any length the LEN field allows.
        scan_with(SiyiFraming::new(MAX_PAYLOAD_LEN), capture, decode)
    }

    fn messages(&self) -> Vec<String> {
        CATALOG
            .iter()
            .map(|e| {
                let empty = match (e.request_empty, e.reply_empty) {
                    (true, true) => " (empty: request, reply)",
                    (true, false) => " (empty: request)",
                    (false, true) => " (empty: reply)",
                    (false, false) => "",
                };
                format!("0x{:02X} {} request,reply{}", e.id, e.name, empty)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decodes_the_document_heartbeat() {
        let d = decode(&[
            0x55, 0x66, 0x01, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x59, 0x8B,
        ])
        .unwrap();
        assert_eq!(d.msg_id, 0);
        assert_eq!(d.name, "Heartbeat");
        assert_eq!(
            d.fields,
            json!({"direction": "request", "ctrl": 1, "need_ack": true, "is_ack": false, "seq": 0, "byte": 0})
        );
    }

    #[test]
    fn lists_48_ids_with_both_directions() {
        let lines = Siyi.messages();
        assert_eq!(lines.len(), 48);
        assert!(lines.contains(&"0x0D GimbalAttitude request,reply (empty: request)".to_string()));
        assert!(lines.contains(&"0x22 FcAttitude request,reply (empty: reply)".to_string()));
        assert!(lines.contains(&"0x80 SoftReboot request,reply".to_string()));
        assert!(lines.iter().all(|l| l.contains(" request,reply")));
    }
}
