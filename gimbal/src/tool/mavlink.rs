//! `gimbal` adapter for MAVLink 2 (the bridge's message set): frames of every id are
//! delivered (an id outside the set cannot have its checksum verified: shown raw), MAVLink
//! 1 frames are skipped (shown as garbage bytes).

use protocol_core::mavlink::dialect::Message as _;
use protocol_core::mavlink::{CATALOG, MavlinkFraming, Message, Packet, message_info};
use serde_json::{Value, json};

use super::{Decoded, Item, Protocol, scan_with, untag};

/// MAVLink 2.
pub struct Mavlink;

/// Decodes one frame.
pub fn decode(bytes: &[u8]) -> Result<Decoded, String> {
    let packet = Packet::decode(bytes).map_err(|e| e.to_string())?;
    let (id, name, payload) = match &packet.message {
        Message::Known(m) => (
            m.message_id(),
            m.message_name().to_string(),
            untag(serde_json::to_value(m).map_err(|e| e.to_string())?).1,
        ),
        Message::Raw(r) => (
            r.id,
            r.info().map_or("Raw", |i| i.name).to_string(),
            json!({ "payload": super::hex(r.payload) }),
        ),
    };
    let h = packet.header;
    let header = json!({
        "sys": h.system_id,
        "comp": h.component_id,
        "seq": h.sequence,
        "signed": packet.signature.is_some(),
    });
    let mut payload = payload;
    if let Value::Object(p) = &mut payload {
        // The message's own name is the item's name already.
        p.remove("type");
    }
    Ok(Decoded::new(u64::from(id), name, header, payload))
}

impl Protocol for Mavlink {
    fn name(&self) -> &'static str {
        "mavlink"
    }

    fn scan(&self, capture: &[u8]) -> Vec<Item> {
        scan_with(MavlinkFraming::delivering_unknown_ids(), capture, decode)
    }

    fn id_digits(&self) -> usize {
        3
    }

    fn messages(&self) -> Vec<String> {
        CATALOG
            .iter()
            .filter_map(|&id| message_info(id))
            .map(|i| format!("0x{:03X} ({}) {}", i.id, i.id, i.name))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol_core::mavlink::dialect::SYSTEM_TIME_DATA;
    use protocol_core::mavlink::{Header, MavMessage, encode};

    #[test]
    fn decodes_a_system_time_among_garbage() {
        let msg = MavMessage::SYSTEM_TIME(SYSTEM_TIME_DATA {
            time_unix_usec: 1_795_428_000_123_456,
            time_boot_ms: 12_345,
        });
        let header = Header {
            sequence: 3,
            system_id: 1,
            component_id: 1,
        };
        let mut buf = [0u8; 64];
        let n = encode(&msg, &header, &mut buf).unwrap();
        let mut capture = vec![0x00, 0x11];
        capture.extend_from_slice(&buf[..n]);
        let items = Mavlink.scan(&capture);
        assert!(matches!(items[0], Item::Garbage { offset: 0, .. }));
        let Item::Frame {
            offset, decoded, ..
        } = &items[1]
        else {
            panic!("{items:?}");
        };
        assert_eq!(*offset, 2);
        let d = decoded.as_ref().unwrap();
        assert_eq!((d.msg_id, d.name.as_str()), (2, "SYSTEM_TIME"));
        assert_eq!(d.fields["time_boot_ms"], json!(12_345));
        assert_eq!(d.fields["sys"], json!(1));
        assert_eq!(Mavlink.messages().len(), CATALOG.len());
    }
}
