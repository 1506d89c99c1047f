//! `gimbal` adapter for the K40T pod protocol.

use protocol_core::k40t::{CATALOG, CrcCoverage, Frame, K40tFraming, Kind, Message, Packet};
use serde_json::json;

use super::{Decoded, Item, Protocol, scan_with, untag};

/// The K40T pod protocol.
pub struct K40t;

/// Decodes one checksum-valid frame.
pub fn decode(bytes: &[u8]) -> Result<Decoded, String> {
    let frame = Frame::new_checked(bytes).map_err(|e| e.to_string())?;
    let packet = Packet::parse(&frame).map_err(|e| e.to_string())?;
    let id = packet.message.id();
    let kind = match id.kind {
        Kind::Request => "request",
        Kind::Ack => "ack",
        Kind::Status => "status",
        Kind::Other(_) => "other",
    };
    let payload = match packet.message {
        Message::Request(m) => untag(serde_json::to_value(m).map_err(|e| e.to_string())?).1,
        Message::Ack(m) => untag(serde_json::to_value(m).map_err(|e| e.to_string())?).1,
        Message::Status(m) => untag(serde_json::to_value(m).map_err(|e| e.to_string())?).1,
        Message::Raw(r) => json!({ "payload": super::hex(r.payload) }),
    };
    let h = packet.header;
    let header = json!({
        "kind": kind,
        "src": format!("{:02x}:{:02x}", h.src.system, h.src.component),
        "dst": format!("{:02x}:{:02x}", h.dst.system, h.dst.component),
        "seq": h.seq,
        "crc": match h.coverage {
            CrcCoverage::IncludeStx => "include-stx",
            CrcCoverage::ExcludeStx => "exclude-stx",
        },
    });
    let name = packet.message.name().to_string();
    Ok(Decoded::new(u64::from(id.to_u32()), name, header, payload))
}

impl Protocol for K40t {
    fn name(&self) -> &'static str {
        "k40t"
    }

    fn scan(&self, capture: &[u8]) -> Vec<Item> {
        scan_with(K40tFraming::any(), capture, decode)
    }

    fn id_digits(&self) -> usize {
        6
    }

    fn messages(&self) -> Vec<String> {
        CATALOG
            .iter()
            .map(|e| {
                let mut kinds = vec![if e.report { "report" } else { "request" }];
                if e.ack {
                    kinds.push("ack");
                }
                if e.status {
                    kinds.push("status");
                }
                format!("{:#08x} {} {}", e.base, e.name, kinds.join(","))
            })
            .collect()
    }
}
