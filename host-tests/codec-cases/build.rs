//! Turns the seed-vector fixture (JSON) into a Rust table, so the no_std test cases
//! can use it on Cortex-M too.

use std::fmt::Write as _;
use std::path::Path;

fn hex_bytes(hex: &str) -> Vec<u8> {
    hex.split_whitespace()
        .map(|t| u8::from_str_radix(t, 16).unwrap_or_else(|_| panic!("bad hex byte {t:?}")))
        .collect()
}

fn slice(bytes: &[u8]) -> String {
    let mut s = String::from("&[");
    for b in bytes {
        write!(s, "0x{b:02X},").unwrap();
    }
    s.push(']');
    s
}

fn main() {
    let fixture = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/seed_vectors.json");
    println!("cargo:rerun-if-changed={}", fixture.display());
    let text = std::fs::read_to_string(&fixture).expect("read seed_vectors.json");
    let vectors: serde_json::Value = serde_json::from_str(&text).expect("parse seed_vectors.json");
    let mut out = String::from(
        "/// Every frame of `fixtures/seed_vectors.json`, in file order.\npub static VECTORS: &[Vector] = &[\n",
    );
    for v in vectors.as_array().expect("array") {
        let s = |k: &str| v.get(k).and_then(|x| x.as_str());
        let bytes = hex_bytes(s("hex").expect("hex"));
        let opt = |k: &str| match s(k) {
            Some(h) => format!("Some({})", slice(&hex_bytes(h))),
            None => "None".to_string(),
        };
        // doc_hex of OCR'd GCU frames is not clean hex; keep it only where it parses.
        let doc = match s("doc_hex") {
            Some(h)
                if h.split_whitespace()
                    .all(|t| t.len() == 2 && u8::from_str_radix(t, 16).is_ok()) =>
            {
                format!("Some({})", slice(&hex_bytes(h)))
            }
            _ => "None".to_string(),
        };
        writeln!(
            out,
            "    Vector {{ protocol: {:?}, name: {:?}, bytes: {}, verified: {}, doc_bytes: {}, alt_semantic: {} }},",
            s("protocol").expect("protocol"),
            s("name").expect("name"),
            slice(&bytes),
            v.get("verified").and_then(|x| x.as_bool()).expect("verified"),
            doc,
            opt("alt_semantic_hex"),
        )
        .unwrap();
    }
    out.push_str("];\n");
    let dest = Path::new(&std::env::var("OUT_DIR").expect("OUT_DIR")).join("vectors.rs");
    std::fs::write(dest, out).expect("write vectors.rs");
}
