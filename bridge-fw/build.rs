//! Build script: linker arguments of the firmware binary (its `memory.x`: the active slot
//! of `bridge_update::layout`), the update key (`$OUT_DIR/update_key.rs`, see
//! [`update_key`]), the bridge configuration (`bridge.toml`, or the file named by
//! `BRIDGE_CONFIG`) turned into Rust constants (`$OUT_DIR/bridge_config.rs`, included by
//! `src/config.rs`), and what this build is (`BUILD`: the version, the commit from `git`,
//! the flavour and FC sides from the features).
//!
//! The file is deserialized into `bridge_engine::Config` (its `serde` feature:
//! every key optional, absent keys keep `Config::DEFAULT`, an unknown key or a wrong type
//! is an error naming the key), checked with `Config::validate` (the ranges, one place
//! for the firmware and `gimbal bridge`), and written out with `databake` (the `bake`
//! feature) as one `const` expression. Only `fc = "auto"` is the firmware's own: the one
//! FC side compiled in, or the straps. A key that was removed
//! (`bridge_engine::config::REMOVED_KEYS`) is an error naming what replaced it.
//!
//! The commit is `git rev-parse` of the checkout the crate is in (12 hexadecimal digits),
//! with `dirty` when `git status` shows changes to tracked files, and `unknown` outside a
//! checkout (a crate built from a package) or without `git`. The script runs again when
//! the commit, the index or the sources of the crates built into the firmware or `gimbal`
//! change, so a rebuilt image never carries a stale commit.

use std::path::{Path, PathBuf};
use std::process::Command;

use bridge_engine::{Config, FcProtocol};
use databake::{Bake, CrateEnv};
use serde::Deserialize as _;
use toml::{Table, Value};

fn main() {
    // The firmware links at the active slot, where the bootloader jumps.
    bridge_update::layout::build_script(bridge_update::layout::Image::Firmware);
    println!("cargo:rustc-link-arg-bins=--nmagic");
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");

    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap_or_default());
    let (build_code, build_line) = build_info(&manifest);
    update_key(&build_line);
    println!("cargo:rerun-if-env-changed=BRIDGE_CONFIG");
    let path = match std::env::var("BRIDGE_CONFIG") {
        Ok(p) if !p.is_empty() => manifest.join(p),
        _ => manifest.join("bridge.toml"),
    };
    println!("cargo:rerun-if-changed={}", path.display());
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| fail(&format!("cannot read {}: {e}", path.display())));
    let code = generate(&text).unwrap_or_else(|e| fail(&format!("{}: {e}", path.display())));
    let code = code + &build_code;
    let out = PathBuf::from(std::env::var("OUT_DIR").unwrap_or_default()).join("bridge_config.rs");
    std::fs::write(&out, code)
        .unwrap_or_else(|e| fail(&format!("cannot write {}: {e}", out.display())));
}

/// The public key the firmware accepts update images signed by: the file `BRIDGE_UPDATE_KEY`
/// names (an SPKI public key PEM, or the integrator's PKCS#8 private key PEM, of which only
/// the public half is used), else the development key (made on first use in the user's
/// configuration directory, never in the tree: `bridge_update::keys::dev_key_path`).
/// Written as `UPDATE_KEY` and `UPDATE_KEY_IS_DEV`, with `FIRMWARE_VERSION` (the build's
/// line, as `BUILD` prints it: version, commit, flavour and FC sides) that the update port
/// reports.
fn update_key(build_line: &str) {
    use bridge_update::keys;
    println!("cargo:rerun-if-env-changed=BRIDGE_UPDATE_KEY");
    let (public, dev) = match std::env::var_os("BRIDGE_UPDATE_KEY").filter(|v| !v.is_empty()) {
        Some(path) => {
            let path = PathBuf::from(path);
            println!("cargo:rerun-if-changed={}", path.display());
            let key = keys::read_public_key(&path)
                .unwrap_or_else(|e| fail(&format!("BRIDGE_UPDATE_KEY: {e}")));
            (key, keys::is_dev_key(&key))
        }
        None => {
            let (key, made) = keys::dev_key()
                .unwrap_or_else(|e| fail(&format!("the development update key: {e}")));
            if made {
                println!(
                    "cargo:warning=made the DEVELOPMENT update key {} (set BRIDGE_UPDATE_KEY to your own for the field)",
                    keys::dev_key_path().display()
                );
            }
            println!("cargo:rerun-if-changed={}", keys::dev_key_path().display());
            (key.verifying_key(), true)
        }
    };
    let code = format!(
        "/// The ed25519 public key update images must be signed by.\n\
         pub const UPDATE_KEY: [u8; 32] = {:?};\n\
         /// Whether it is the development key.\n\
         pub const UPDATE_KEY_IS_DEV: bool = {dev};\n\
         /// The version the update port reports: this build's line (`BUILD`).\n\
         pub const FIRMWARE_VERSION: &str = {build_line:?};\n",
        public.as_bytes(),
    );
    let out = PathBuf::from(std::env::var("OUT_DIR").unwrap_or_default()).join("update_key.rs");
    std::fs::write(&out, code)
        .unwrap_or_else(|e| fail(&format!("cannot write {}: {e}", out.display())));
}

fn fail(msg: &str) -> ! {
    eprintln!("bridge configuration: {msg}");
    println!("cargo:warning=bridge configuration: {msg}");
    std::process::exit(1);
}

/// Each FC side and the cargo feature that compiles it in.
const SIDES: [(FcProtocol, &str); 5] = [
    (FcProtocol::Siyi, "fc-siyi"),
    (FcProtocol::Viewlink, "fc-viewlink"),
    (FcProtocol::Gcu, "fc-gcu"),
    (FcProtocol::K40t, "fc-k40t"),
    (FcProtocol::Mavlink, "fc-mavlink"),
];

fn compiled(feature: &str) -> bool {
    let var = format!("CARGO_FEATURE_{}", feature.to_uppercase().replace('-', "_"));
    std::env::var_os(var).is_some()
}

fn generate(text: &str) -> Result<String, String> {
    let mut table: Table = text.parse().map_err(|e| format!("{e}"))?;
    bridge_engine::config::removed_key(|section, key| {
        let within = if section.is_empty() {
            Some(&table)
        } else {
            table.get(section).and_then(Value::as_table)
        };
        within.is_some_and(|t| t.contains_key(key))
    })
    .map_err(|e| e.to_string())?;
    let compiled: Vec<FcProtocol> = SIDES
        .iter()
        .filter(|(_, feature)| compiled(feature))
        .map(|(fc, _)| *fc)
        .collect();
    if compiled.is_empty() {
        return Err("no FC side compiled in: enable at least one of the features fc-siyi, fc-viewlink, fc-gcu, fc-k40t, fc-mavlink (or fc-all)".into());
    }
    // `fc = "auto"` (or no `fc`): the FC side compiled in, or with several, the straps.
    // Any other value names one protocol (`FcProtocol`'s names), which must be compiled in.
    let named = match table.remove("fc") {
        Some(Value::String(s)) if s == "auto" => None,
        Some(v) => match FcProtocol::deserialize(v.clone()) {
            Ok(fc) => Some((fc, v)),
            Err(_) => {
                return Err(format!(
                    "fc = {v}: expected \"auto\", \"siyi\", \"viewlink\", \"gcu\", \"k40t\" or \"mavlink\""
                ));
            }
        },
        None => None,
    };

    let mut config: Config = table
        .try_into()
        .map_err(|e| format!("{e}").trim_end().replace('\n', " "))?;
    config.validate().map_err(|e| e.to_string())?;

    let straps = match (named, compiled.as_slice()) {
        (Some((fc, _)), _) if compiled.contains(&fc) => {
            config.fc = fc;
            false
        }
        (Some((fc, v)), _) => {
            let feature = SIDES.iter().find(|(side, _)| *side == fc);
            let feature = feature.map_or("fc-*", |(_, f)| f);
            return Err(format!("fc = {v} but the feature {feature} is not enabled"));
        }
        (None, [only]) => {
            config.fc = *only;
            false
        }
        (None, _) => true,
    };

    let env = CrateEnv::default();
    let choice = if straps {
        "FcChoice::Straps".to_string()
    } else {
        format!("FcChoice::Fixed({})", config.fc.bake(&env))
    };
    Ok(format!(
        "/// The configuration this build was made with (`bridge.toml` over `Config::DEFAULT`).\n\
         pub const CONFIG: Config = {};\n\
         /// How the FC protocol is chosen (`fc` in `bridge.toml` and the `fc-*` features).\n\
         pub const FC: FcChoice = {choice};\n",
        config.bake(&env)
    ))
}

/// `git` in `dir` with `args`: its output, trimmed, when it ran and succeeded.
fn git(dir: &Path, args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .args(args)
        .current_dir(dir)
        // `git status` must not refresh the index (that would run this script again).
        .env("GIT_OPTIONAL_LOCKS", "0")
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// The `BUILD` constant (version, commit, flavour, features) and its line as
/// `BuildInfo`'s `Display` writes it.
fn build_info(manifest: &Path) -> (String, String) {
    let semver = std::env::var("CARGO_PKG_VERSION").unwrap_or_default();
    let version = bridge_engine::version::Version::parse(&semver).unwrap_or_else(|| {
        fail(&format!(
            "version {semver:?} (Cargo.toml): expected MAJOR.MINOR.PATCH, each 0..=255"
        ))
    });
    let commit = git(manifest, &["rev-parse", "--short=12", "HEAD"]);
    let dirty = commit.is_some()
        && git(manifest, &["status", "--porcelain", "--untracked-files=no"])
            .is_some_and(|s| !s.is_empty());
    // Run again when the commit or the index moves, or a source built in changes.
    for path in ["HEAD", "index", "packed-refs"] {
        if let Some(p) = git(
            manifest,
            &["rev-parse", "--path-format=absolute", "--git-path", path],
        ) {
            println!("cargo:rerun-if-changed={p}");
        }
    }
    if let Some(head) = git(manifest, &["symbolic-ref", "-q", "HEAD"])
        && let Some(p) = git(
            manifest,
            &["rev-parse", "--path-format=absolute", "--git-path", &head],
        )
    {
        println!("cargo:rerun-if-changed={p}");
    }
    let root = manifest.join("..");
    for dir in [
        "protocol-core/src",
        "protocol-core/mavlink-dialect",
        "bridge-engine/src",
        "bridge-fw/src",
        "gimbal/src",
        "Cargo.toml",
        "Cargo.lock",
    ] {
        println!("cargo:rerun-if-changed={}", root.join(dir).display());
    }
    let flavour = ["hw", "qemu", "host"]
        .into_iter()
        .find(|f| compiled(f))
        .unwrap_or("");
    let features: Vec<&str> = SIDES
        .iter()
        .map(|(_, f)| *f)
        .chain(["telemetry"])
        .filter(|f| compiled(f))
        .collect();
    let v = version;
    let commit_text = commit.as_deref().unwrap_or("unknown");
    let features = features.join(" ");
    // BuildInfo holds 'static texts (the firmware's are constants): leaked here, once per
    // build script run.
    let line = bridge_engine::BuildInfo {
        version,
        semver: Box::leak(semver.clone().into_boxed_str()),
        commit: Box::leak(commit_text.to_owned().into_boxed_str()),
        dirty,
        flavour,
        features: Box::leak(features.clone().into_boxed_str()),
    }
    .to_string();
    let code = format!(
        "/// What this build is: version, commit, flavour and FC sides (`build.rs`).\n\
         pub const BUILD: BuildInfo = BuildInfo {{ version: Version {{ major: {}, minor: {}, \
         patch: {}, pre_release: {} }}, semver: {semver:?}, commit: {:?}, dirty: {dirty}, \
         flavour: {flavour:?}, features: {:?} }};\n",
        v.major, v.minor, v.patch, v.pre_release, commit_text, features,
    );
    (code, line)
}
