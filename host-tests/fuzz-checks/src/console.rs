//! The console (`console` target): the engine's console fed arbitrary bytes, in chunks
//! the fuzzer chooses, on a MAVLink-side engine with a signing key set. Properties:
//! - the signing key never leaves through the console: no 16 hexadecimal digits of it
//!   (either case) appear in its output unless they were typed;
//! - the configuration running and the one set (the next start's) are always valid;
//! - after a `save`, the records the engine handed to the store, restored over the same
//!   defaults, give back exactly the configuration set (nothing kept half, nothing lost).

use std::collections::BTreeMap;

use bridge_engine::{
    BuildInfo, Config, ConsoleAction, Engine, FcProtocol, Instant, Restore, Sides, SigningKey,
};

use crate::input::Input;

/// The key the engine starts with.
pub const CONSOLE_KEY: [u8; 32] = [
    0x5a, 0x17, 0xc3, 0x88, 0x01, 0xfe, 0x42, 0x9d, 0x6b, 0x20, 0xe7, 0x3c, 0xa9, 0x54, 0x0f, 0xb2,
    0x71, 0xd8, 0x36, 0xcb, 0x95, 0x4e, 0x0a, 0xf3, 0x27, 0x8c, 0x61, 0xbd, 0x13, 0xe0, 0x79, 0xa4,
];

fn defaults() -> Config {
    let mut config = Config::for_fc(FcProtocol::Mavlink);
    config.signing_key = Some(SigningKey(CONSOLE_KEY));
    config
}

/// Every 16-digit window of the key's hexadecimal, lower case.
fn key_windows() -> Vec<String> {
    let hex: String = CONSOLE_KEY.iter().map(|b| format!("{b:02x}")).collect();
    (0..=hex.len() - 16)
        .map(|i| hex[i..i + 16].to_string())
        .collect()
}

fn drain(engine: &mut Engine, out: &mut Vec<u8>, store: &mut BTreeMap<u16, Vec<u8>>) {
    let mut buf = [0u8; 64];
    loop {
        let n = engine.console_transmit(&mut buf);
        if n == 0 {
            break;
        }
        out.extend_from_slice(&buf[..n]);
    }
    while let Some(r) = engine.take_record() {
        store.insert(r.key.0, r.value().to_vec());
    }
    while engine.next_event().is_some() {}
}

/// Target `console`.
pub fn run(data: &[u8]) {
    let mut input = Input::new(data);
    // As the board starts on a blank store: the defaults, and the store's header due.
    let mut engine = Engine::restored(
        Restore::new(defaults(), Sides::COMPILED).finish(),
        BuildInfo::ENGINE,
    );
    let mut out = Vec::new();
    let mut store = BTreeMap::new();
    let mut now = 0u64;
    // Chunks of 1 to 64 bytes, each chunk's size the fuzzer's first byte of it.
    let mut typed: Vec<u8> = Vec::new();
    loop {
        let size = usize::from(input.byte() % 64) + 1;
        let chunk = input.bytes(size);
        if chunk.is_empty() {
            break;
        }
        typed.extend_from_slice(chunk);
        now += 10_000;
        let (_, action) = engine.console_receive(Instant::from_micros(now), chunk);
        if let Some(ConsoleAction::Update { .. }) = action {
            // The update protocol would take the port; it gives it back.
            engine.console_resume();
        }
        drain(&mut engine, &mut out, &mut store);
        assert!(
            engine.config().validate().is_ok(),
            "the running configuration"
        );
        assert!(
            engine.settings().pending().validate().is_ok(),
            "the configuration set"
        );
    }
    // End whatever line was typed, then save.
    engine.console_receive(Instant::from_micros(now + 10_000), b"\x03\r\nsave\r\n");
    drain(&mut engine, &mut out, &mut store);

    let typed = String::from_utf8_lossy(&typed).to_ascii_lowercase();
    let said = String::from_utf8_lossy(&out).to_ascii_lowercase();
    for w in key_windows() {
        assert!(
            !said.contains(&w) || typed.contains(&w),
            "the signing key's digits {w} left through the console"
        );
    }

    let mut restore = Restore::new(defaults(), Sides::COMPILED);
    for key in Restore::keys() {
        if let Some(v) = store.get(&key) {
            restore.record(key, v);
        }
    }
    let restored = restore.finish();
    assert!(!restored.store_reset(), "the header was written");
    assert_eq!(
        restored.config(),
        engine.settings().pending(),
        "the settings kept are the settings set"
    );
}

/// Seeds: the console's commands, good and bad.
#[must_use]
pub fn seeds() -> Vec<Vec<u8>> {
    let lines: &[&[u8]] = &[
        b"help\r\n",
        b"version\r\nstatus\r\n",
        b"get signing_key\r\nget fc_baud\r\n",
        b"set fc_baud 57600\r\nsave\r\n",
        b"set signing require\r\nset signing_key \"\"\r\nsave\r\n",
        b"set gcs_ids [255, 245]\r\nset video.uri \"rtsp://10.0.0.2/x\"\r\n",
        b"dump\r\ndefaults\r\n",
        b"set fc_baud 12\r\nset no_such 1\r\nset\r\n\x7f\x08\r\n",
        b"update\r\n\xb7\x4d\x01\x00\x00",
        b"set leap_seconds 19\nset autopilot_sysid 1\nsave\nreboot\n",
    ];
    lines
        .iter()
        .map(|l| {
            // One chunk per byte-size selector: the whole line at once.
            let mut v = vec![63u8];
            v.extend_from_slice(l);
            v
        })
        .collect()
}
