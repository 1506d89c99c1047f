//! Build script: linker arguments of the firmware binary, and the bridge configuration
//! (`bridge.toml`, or the file named by `BRIDGE_CONFIG`) turned into Rust constants
//! (`$OUT_DIR/bridge_config.rs`, included by `src/config.rs`).
//!
//! Every key is optional (absent: `protocol_core::bridge::Config::DEFAULT`); an unknown
//! key, a wrong type or a value out of range stops the build with a message naming it.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::PathBuf;

use toml::{Table, Value};

fn main() {
    // memory.x (STM32L475VG) is found in the workspace root, where the linker runs.
    println!("cargo:rustc-link-arg-bins=--nmagic");
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");

    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap_or_default());
    println!("cargo:rerun-if-env-changed=BRIDGE_CONFIG");
    let path = match std::env::var("BRIDGE_CONFIG") {
        Ok(p) if !p.is_empty() => manifest.join(p),
        _ => manifest.join("bridge.toml"),
    };
    println!("cargo:rerun-if-changed={}", path.display());
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| fail(&format!("cannot read {}: {e}", path.display())));
    let code = generate(&text).unwrap_or_else(|e| fail(&format!("{}: {e}", path.display())));
    let out = PathBuf::from(std::env::var("OUT_DIR").unwrap_or_default()).join("bridge_config.rs");
    std::fs::write(&out, code)
        .unwrap_or_else(|e| fail(&format!("cannot write {}: {e}", out.display())));
}

fn fail(msg: &str) -> ! {
    eprintln!("bridge configuration: {msg}");
    println!("cargo:warning=bridge configuration: {msg}");
    std::process::exit(1);
}

const PROTOCOLS: [(&str, &str, &str); 5] = [
    ("siyi", "Siyi", "FC_SIYI"),
    ("viewlink", "Viewlink", "FC_VIEWLINK"),
    ("gcu", "Gcu", "FC_GCU"),
    ("k40t", "K40t", "FC_K40T"),
    ("mavlink", "Mavlink", "FC_MAVLINK"),
];

/// Reads a table's keys, refusing unknown ones.
struct Keys<'a> {
    table: &'a Table,
    section: &'a str,
    used: BTreeSet<&'a str>,
}

impl<'a> Keys<'a> {
    fn new(table: &'a Table, section: &'a str) -> Self {
        Keys {
            table,
            section,
            used: BTreeSet::new(),
        }
    }

    fn name(&self, key: &str) -> String {
        if self.section.is_empty() {
            key.to_string()
        } else {
            format!("{}.{key}", self.section)
        }
    }

    fn get(&mut self, key: &'a str) -> Option<&'a Value> {
        self.used.insert(key);
        self.table.get(key)
    }

    fn int(&mut self, key: &'a str, min: i64, max: i64) -> Result<Option<i64>, String> {
        match self.get(key) {
            None => Ok(None),
            Some(Value::Integer(v)) if (min..=max).contains(v) => Ok(Some(*v)),
            Some(v) => Err(format!(
                "{} = {v}: expected an integer in {min}..={max}",
                self.name(key)
            )),
        }
    }

    fn boolean(&mut self, key: &'a str) -> Result<Option<bool>, String> {
        match self.get(key) {
            None => Ok(None),
            Some(Value::Boolean(v)) => Ok(Some(*v)),
            Some(v) => Err(format!("{} = {v}: expected true or false", self.name(key))),
        }
    }

    /// A string of exactly `len` ASCII characters.
    fn ascii(&mut self, key: &'a str, len: usize) -> Result<Option<String>, String> {
        match self.get(key) {
            None => Ok(None),
            Some(Value::String(s)) if s.len() == len && s.is_ascii() => Ok(Some(s.clone())),
            Some(v) => Err(format!(
                "{} = {v}: expected {len} ASCII characters",
                self.name(key)
            )),
        }
    }

    /// A version `[major, minor, patch]`.
    fn version(&mut self, key: &'a str) -> Result<Option<[u8; 3]>, String> {
        match self.get(key) {
            None => Ok(None),
            Some(Value::Array(a)) if a.len() == 3 => {
                let mut v = [0u8; 3];
                for (slot, x) in v.iter_mut().zip(a) {
                    *slot = x
                        .as_integer()
                        .and_then(|x| u8::try_from(x).ok())
                        .ok_or_else(|| {
                            format!(
                                "{}: expected [major, minor, patch], each 0..=255",
                                self.name(key)
                            )
                        })?;
                }
                Ok(Some(v))
            }
            Some(v) => Err(format!(
                "{} = {v}: expected [major, minor, patch]",
                self.name(key)
            )),
        }
    }

    fn table(&mut self, key: &'a str) -> Result<Option<&'a Table>, String> {
        match self.get(key) {
            None => Ok(None),
            Some(Value::Table(t)) => Ok(Some(t)),
            Some(v) => Err(format!(
                "{} = {v}: expected a [{key}] section",
                self.name(key)
            )),
        }
    }

    fn finish(self) -> Result<(), String> {
        for k in self.table.keys() {
            if !self.used.contains(k.as_str()) {
                return Err(format!("unknown key `{}`", self.name(k)));
            }
        }
        Ok(())
    }
}

fn bytes(s: &str) -> String {
    format!("*b{s:?}")
}

fn generate(text: &str) -> Result<String, String> {
    let root: Table = text.parse().map_err(|e| format!("{e}"))?;
    let mut c = String::new();
    let mut set = |field: &str, value: String| {
        let _ = writeln!(c, "    c.{field} = {value};");
    };
    let mut top = Keys::new(&root, "");

    let compiled: Vec<_> = PROTOCOLS
        .iter()
        .filter(|(_, _, feature)| std::env::var_os(format!("CARGO_FEATURE_{feature}")).is_some())
        .collect();
    if compiled.is_empty() {
        return Err("no FC side compiled in: enable at least one of the features fc-siyi, fc-viewlink, fc-gcu, fc-k40t, fc-mavlink (or fc-all)".into());
    }
    let fc = match top.get("fc") {
        None => "auto".to_string(),
        Some(Value::String(s)) => s.clone(),
        Some(v) => {
            return Err(format!(
                "fc = {v}: expected \"auto\", \"siyi\", \"viewlink\", \"gcu\", \"k40t\" or \"mavlink\""
            ));
        }
    };
    let choice = if fc == "auto" {
        match compiled.as_slice() {
            [(_, variant, _)] => format!("FcChoice::Fixed(FcProtocol::{variant})"),
            _ => "FcChoice::Straps".to_string(),
        }
    } else {
        let Some((name, variant, _)) = PROTOCOLS.iter().find(|(name, _, _)| *name == fc) else {
            return Err(format!(
                "fc = {fc:?}: expected \"auto\", \"siyi\", \"viewlink\", \"gcu\", \"k40t\" or \"mavlink\""
            ));
        };
        if !compiled.iter().any(|(n, _, _)| n == name) {
            return Err(format!(
                "fc = {fc:?} but the feature fc-{name} is not enabled"
            ));
        }
        format!("FcChoice::Fixed(FcProtocol::{variant})")
    };
    if let Some((_, variant, _)) = PROTOCOLS.iter().find(|(name, _, _)| *name == fc) {
        set("fc", format!("FcProtocol::{variant}"));
    } else if let [(_, variant, _)] = compiled.as_slice() {
        set("fc", format!("FcProtocol::{variant}"));
    }

    if let Some(v) = top.int("fc_baud", 1200, 4_000_000)? {
        set("fc_baud", v.to_string());
    }
    if let Some(v) = top.int("pod_baud", 1200, 4_000_000)? {
        set("pod_baud", v.to_string());
    }
    if let Some(v) = top.int("leap_seconds", 0, 255)? {
        set("leap_seconds", v.to_string());
    }
    if let Some(v) = top.int("tz_minuteswest", -1440, 1440)? {
        set("tz_minuteswest", v.to_string());
    }
    if let Some(v) = top.int("fc_link_timeout_ms", 100, 60_000)? {
        set("fc_link_timeout", format!("Duration::from_millis({v})"));
    }
    if let Some(v) = top.int("fc_silence_stop_ms", 50, 60_000)? {
        set("fc_silence_stop", format!("Duration::from_millis({v})"));
    }

    if let Some(t) = top.table("sync")? {
        let mut k = Keys::new(t, "sync");
        if let Some(v) = k.int("period_ms", 1000, 3_600_000)? {
            set("sync.period", format!("Duration::from_millis({v})"));
        }
        if let Some(v) = k.int("width_ms", 1, 900)? {
            set("sync.width", format!("Duration::from_millis({v})"));
        }
        k.finish()?;
    }
    if let Some(t) = top.table("siyi")? {
        let mut k = Keys::new(t, "siyi");
        if let Some(v) = k.ascii("hardware_id", 12)? {
            set("siyi.hardware_id", bytes(&v));
        }
        for (key, field) in [
            ("camera_version", "camera_version"),
            ("gimbal_version", "gimbal_version"),
            ("zoom_version", "zoom_version"),
        ] {
            if let Some(v) = k.version(key)? {
                set(&format!("siyi.{field}"), format!("{v:?}"));
            }
        }
        if let Some(v) = k.int("max_zoom_x10", 10, 65535)? {
            set("siyi.max_zoom_x10", v.to_string());
        }
        k.finish()?;
    }
    if let Some(t) = top.table("viewlink")? {
        let mut k = Keys::new(t, "viewlink");
        if let Some(v) = k.ascii("model", 10)? {
            set("viewlink.model", bytes(&v));
        }
        // Answered to 0xD0 as "S20MMmmpp" (a Viewpro date-like text; ArduPilot reads
        // bytes 3..9 as three two-digit numbers), padded to 20 bytes.
        if let Some([major, minor, patch]) = k.version("firmware")? {
            if major > 99 || minor > 99 || patch > 99 {
                return Err(
                    "viewlink.firmware: each of [major, minor, patch] must be 0..=99".into(),
                );
            }
            let text = format!("S20{major:02}{minor:02}{patch:02}");
            let padded: Vec<u8> = text.bytes().chain(core::iter::repeat(0)).take(20).collect();
            set("viewlink.firmware", format!("{padded:?}"));
        }
        k.finish()?;
    }
    if let Some(t) = top.table("gcu")? {
        let mut k = Keys::new(t, "gcu");
        if let Some(v) = k.int("hardware_x10", 0, 255)? {
            set("gcu.hardware_x10", v.to_string());
        }
        if let Some(v) = k.int("firmware_x10", 0, 255)? {
            set("gcu.firmware_x10", v.to_string());
        }
        if let Some(v) = k.int("gimbal_code", 0, 255)? {
            set("gcu.gimbal_code", v.to_string());
        }
        if let Some(v) = k.boolean("resync_mark")? {
            set("gcu.resync_mark", v.to_string());
        }
        k.finish()?;
    }
    if let Some(t) = top.table("pod")? {
        let mut k = Keys::new(t, "pod");
        if let Some(v) = k.boolean("yaw_positive_left")? {
            set("pod.yaw_positive_left", v.to_string());
        }
        if let Some(v) = k.boolean("pitch_positive_down")? {
            set("pod.pitch_positive_down", v.to_string());
        }
        k.finish()?;
    }
    top.finish()?;

    Ok(format!(
        "/// The configuration this build was made with (`bridge.toml` over `Config::DEFAULT`).\n\
         pub const CONFIG: Config = {{\n    #[allow(unused_mut)]\n    let mut c = Config::DEFAULT;\n{c}    c\n}};\n\
         /// How the FC protocol is chosen (`fc` in `bridge.toml` and the `fc-*` features).\n\
         pub const FC: FcChoice = {choice};\n"
    ))
}
