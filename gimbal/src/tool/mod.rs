//! The `gimbal` command-line tool: decode serial captures and list the messages each
//! codec supports.
//!
//! Each protocol has one adapter module that provides [`Protocol::scan`] (frames of a
//! capture, decoded) and [`Protocol::messages`] (the catalogue).

use std::fmt::Write as _;

use protocol_core::wire::{Framing, Scanned, Scanner};
use serde_json::{Map, Value, json};

pub mod gcu;
pub mod k40t;
pub mod mavlink;
pub mod siyi;
pub mod viewlink;

/// A frame decoded for display.
#[derive(Debug, Clone, PartialEq)]
pub struct Decoded {
    /// The message id as an integer (K40T: the 24-bit id; others: their command id).
    pub msg_id: u64,
    /// Message name.
    pub name: String,
    /// Typed fields (a JSON object; numbers are JSON numbers).
    pub fields: Value,
}

impl Decoded {
    /// A message: the header's fields first, then the payload's (both JSON objects).
    #[must_use]
    pub fn new(msg_id: u64, name: String, header: Value, payload: Value) -> Self {
        let mut fields = header;
        if let (Value::Object(f), Value::Object(p)) = (&mut fields, payload) {
            f.extend(p);
        }
        Decoded {
            msg_id,
            name,
            fields,
        }
    }
}

/// One item of a capture.
#[derive(Debug, Clone, PartialEq)]
pub enum Item {
    /// A frame with a valid checksum, decoded or with the decoding error.
    Frame {
        offset: usize,
        raw: Vec<u8>,
        decoded: Result<Decoded, String>,
    },
    /// A candidate frame that failed its length or checksum check.
    Rejected {
        offset: usize,
        raw: Vec<u8>,
        error: String,
    },
    /// Bytes that are not part of any frame.
    Garbage { offset: usize, raw: Vec<u8> },
    /// A frame cut off by the end of the capture.
    Truncated { offset: usize, raw: Vec<u8> },
}

/// A protocol the tool can decode.
pub trait Protocol {
    /// The name on the command line.
    fn name(&self) -> &'static str;
    /// Every item of a capture, in order.
    fn scan(&self, capture: &[u8]) -> Vec<Item>;
    /// One line per message id: `0x000304 HybridZoom request,ack,status`.
    fn messages(&self) -> Vec<String>;
    /// Hex digits of a message id in human-readable output (K40T ids have six).
    fn id_digits(&self) -> usize {
        2
    }
}

/// The protocols, by command-line name.
pub fn protocols() -> Vec<Box<dyn Protocol>> {
    vec![
        Box::new(k40t::K40t),
        Box::new(siyi::Siyi),
        Box::new(viewlink::Viewlink),
        Box::new(gcu::Gcu),
        Box::new(mavlink::Mavlink),
    ]
}

/// The protocol called `name` (case-insensitive).
pub fn protocol(name: &str) -> Option<Box<dyn Protocol>> {
    protocols()
        .into_iter()
        .find(|p| p.name().eq_ignore_ascii_case(name))
}

/// Scans `capture` with `framing` and decodes each valid frame with `decode`.
///
/// Garbage bytes that lie inside a candidate already reported as rejected are not
/// reported again (the scanner rescans them after a failure, byte by byte).
pub fn scan_with<F: Framing>(
    framing: F,
    capture: &[u8],
    decode: impl Fn(&[u8]) -> Result<Decoded, String>,
) -> Vec<Item> {
    let mut items: Vec<Item> = Vec::new();
    let mut covered_until = 0usize;
    for scanned in Scanner::new(framing, capture) {
        match scanned {
            Scanned::Frame { offset, bytes } => {
                items.push(Item::Frame {
                    offset,
                    raw: bytes.to_vec(),
                    decoded: decode(bytes),
                });
            }
            Scanned::Rejected {
                offset,
                bytes,
                error,
            } => {
                covered_until = covered_until.max(offset + bytes.len());
                items.push(Item::Rejected {
                    offset,
                    raw: bytes.to_vec(),
                    error: error.to_string(),
                });
            }
            // No framing of the tool skips frames (only MAVLink does): shown as garbage.
            Scanned::Skipped { offset, bytes } | Scanned::Garbage { offset, bytes } => {
                let end = offset + bytes.len();
                if end <= covered_until {
                    continue;
                }
                let start = offset.max(covered_until);
                let raw = capture[start..end].to_vec();
                match items.last_mut() {
                    Some(Item::Garbage { offset: o, raw: r }) if *o + r.len() == start => {
                        r.extend(raw)
                    }
                    _ => items.push(Item::Garbage { offset: start, raw }),
                }
            }
            Scanned::Truncated { offset, bytes } => {
                covered_until = covered_until.max(offset + bytes.len());
                items.push(Item::Truncated {
                    offset,
                    raw: bytes.to_vec(),
                });
            }
        }
    }
    items
}

/// A serde value of an enum of newtype variants (`{"Variant": inner}`) without its tag.
pub fn untag(v: Value) -> (String, Value) {
    match v {
        Value::Object(map) if map.len() == 1 => {
            let (k, v) = map.into_iter().next().unwrap_or_default();
            (k, v)
        }
        other => (String::new(), other),
    }
}

/// Makes sure fields are an object (a bare value becomes `{"value": v}`).
pub fn as_object(v: Value, key: &str) -> Value {
    match v {
        Value::Object(_) => v,
        other => {
            let mut m = Map::new();
            m.insert(key.to_string(), other);
            Value::Object(m)
        }
    }
}

/// Lower-case hex without separators.
pub fn hex(bytes: &[u8]) -> String {
    bytes
        .iter()
        .fold(String::with_capacity(bytes.len() * 2), |mut s, b| {
            let _ = write!(s, "{b:02x}");
            s
        })
}

/// Upper-case hex with spaces (human output).
pub fn spaced_hex(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Parses hex text: bytes as hex digit pairs, separated or not by whitespace, commas,
/// colons or dashes, each token optionally prefixed `0x`.
pub fn parse_hex(text: &str) -> Result<Vec<u8>, String> {
    let mut digits = String::new();
    for token in text.split(|c: char| c.is_whitespace() || matches!(c, ',' | ':' | '-' | ';')) {
        let t = token
            .strip_prefix("0x")
            .or_else(|| token.strip_prefix("0X"))
            .unwrap_or(token);
        if let Some(bad) = t.chars().find(|c| !c.is_ascii_hexdigit()) {
            return Err(format!("not a hex digit: {bad:?} in {token:?}"));
        }
        digits.push_str(t);
    }
    if !digits.len().is_multiple_of(2) {
        return Err(format!("odd number of hex digits ({})", digits.len()));
    }
    (0..digits.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&digits[i..i + 2], 16).map_err(|e| e.to_string()))
        .collect()
}

/// True when `bytes` look like hex text rather than a binary capture.
pub fn looks_like_hex(bytes: &[u8]) -> bool {
    !bytes.is_empty()
        && bytes
            .iter()
            .all(|&b| b.is_ascii_hexdigit() || b.is_ascii_whitespace() || b"xX,:-;".contains(&b))
}

/// An enumeration value as protocol-core serialises it (`{"name": "ZoomIn", "code": 9}`),
/// shown as `ZoomIn(0x09)`: the name and the wire code, as the documents' tables print
/// it (two hex digits per byte the code needs).
pub fn enum_text(v: &Value) -> Option<String> {
    let Value::Object(m) = v else { return None };
    let (Some(Value::String(name)), Some(code), 2) = (m.get("name"), m.get("code"), m.len()) else {
        return None;
    };
    let code = code.as_u64()?;
    let digits = match code {
        0..=0xFF => 2,
        0x100..=0xFFFF => 4,
        _ => 8,
    };
    Some(format!("{name}(0x{code:0digits$X})"))
}

/// Flattens fields to `key=value` pairs for the human-readable line.
pub fn flat_fields(v: &Value) -> String {
    flat_pairs(v, true).join(" ")
}

/// Flattens a JSON value to `key=value` pairs, nested keys joined with dots, the
/// enumerations as [`enum_text`], arrays of numbers compact; strings quoted or not.
pub fn flat_pairs(v: &Value, quote_strings: bool) -> Vec<String> {
    fn walk(prefix: &str, v: &Value, quote: bool, out: &mut Vec<String>) {
        let text = match (enum_text(v), v) {
            (Some(text), _) => text,
            (None, Value::Object(m)) => {
                for (k, v) in m {
                    let key = if prefix.is_empty() {
                        k.clone()
                    } else {
                        format!("{prefix}.{k}")
                    };
                    walk(&key, v, quote, out);
                }
                return;
            }
            (None, Value::Array(a)) if a.iter().all(Value::is_number) => {
                let s = a.iter().map(Value::to_string).collect::<Vec<_>>().join(",");
                format!("[{s}]")
            }
            (None, Value::String(s)) if !quote => s.clone(),
            (None, other) => other.to_string(),
        };
        out.push(if prefix.is_empty() {
            text
        } else {
            format!("{prefix}={text}")
        });
    }
    let mut out = Vec::new();
    walk("", v, quote_strings, &mut out);
    out
}

/// One output line for an item.
pub fn render(protocol: &dyn Protocol, item: &Item, as_json: bool) -> String {
    let digits = protocol.id_digits();
    let protocol = protocol.name();
    match (item, as_json) {
        (Item::Frame { offset, raw, decoded: Ok(d) }, true) => json!({
            "protocol": protocol, "offset": offset, "msg_id": d.msg_id, "name": d.name,
            "fields": d.fields, "raw": hex(raw),
        })
        .to_string(),
        (Item::Frame { offset, raw, decoded: Err(e) }, true)
        | (Item::Rejected { offset, raw, error: e }, true) => {
            json!({ "protocol": protocol, "offset": offset, "error": e, "raw": hex(raw) }).to_string()
        }
        (Item::Garbage { offset, raw }, true) => json!({
            "protocol": protocol, "offset": offset, "error": format!("garbage: {} byte{} outside any frame", raw.len(), if raw.len() == 1 { "" } else { "s" }),
            "raw": hex(raw),
        })
        .to_string(),
        (Item::Truncated { offset, raw }, true) => json!({
            "protocol": protocol, "offset": offset, "error": "truncated: capture ends inside a frame", "raw": hex(raw),
        })
        .to_string(),
        (Item::Frame { offset, decoded: Ok(d), .. }, false) => {
            format!("@{offset:06} 0x{:0digits$x} {} {}", d.msg_id, d.name, flat_fields(&d.fields))
        }
        (Item::Frame { offset, raw, decoded: Err(e) }, false) => {
            format!("@{offset:06} undecodable frame ({e}): {}", spaced_hex(raw))
        }
        (Item::Rejected { offset, raw, error }, false) => {
            format!("@{offset:06} bad frame ({error}): {}", spaced_hex(raw))
        }
        (Item::Garbage { offset, raw }, false) => {
            format!("@{offset:06} garbage, {} byte{}: {}", raw.len(), if raw.len() == 1 { "" } else { "s" }, spaced_hex(raw))
        }
        (Item::Truncated { offset, raw }, false) => {
            format!("@{offset:06} truncated frame at end of capture: {}", spaced_hex(raw))
        }
    }
}

/// Counts for the summary line (stderr).
pub fn summary(items: &[Item]) -> String {
    let frames = items
        .iter()
        .filter(|i| matches!(i, Item::Frame { decoded: Ok(_), .. }))
        .count();
    let bad = items.len()
        - frames
        - items
            .iter()
            .filter(|i| matches!(i, Item::Garbage { .. }))
            .count();
    let garbage: usize = items
        .iter()
        .map(|i| {
            if let Item::Garbage { raw, .. } = i {
                raw.len()
            } else {
                0
            }
        })
        .sum();
    format!("{frames} frames decoded, {bad} bad or truncated, {garbage} garbage bytes")
}

/// A stub adapter for a protocol whose codec has not landed yet.
pub fn not_yet(name: &str) -> Vec<Item> {
    vec![Item::Rejected {
        offset: 0,
        raw: Vec::new(),
        error: format!("the {name} codec is not implemented yet"),
    }]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hex_forms() {
        assert_eq!(
            parse_hex("FD 03 0x04,05:06-0708"),
            Ok(vec![0xFD, 3, 4, 5, 6, 7, 8])
        );
        assert!(parse_hex("F").is_err());
        assert!(parse_hex("GG").is_err());
        assert!(looks_like_hex(b"fd 03\n"));
        assert!(!looks_like_hex(&[0xFD, 0x03]));
    }

    #[test]
    fn flattening() {
        let v = json!({"a": 1, "b": {"c": "X", "d": [1, 2]}});
        assert_eq!(flat_fields(&v), "a=1 b.c=\"X\" b.d=[1,2]");
        let v = json!({"op": {"name": "ZoomIn", "code": 9}, "ack": {"name": "Recording", "code": 0x201}});
        assert_eq!(flat_fields(&v), "op=ZoomIn(0x09) ack=Recording(0x0201)");
        // An ordinary struct that happens to have a `name` field is not an enumeration.
        let v = json!({"s": {"name": "x", "code": 1, "more": 2}});
        assert_eq!(flat_fields(&v), "s.name=\"x\" s.code=1 s.more=2");
    }
}
