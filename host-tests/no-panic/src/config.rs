//! The bridge's configuration checks: `Config::validate` on an opaque configuration,
//! every `Limit`, the texts' parsers on opaque text, `ConfigError`'s message, the removed
//! keys' check and message, and the version's parser, protocol forms and line.

use bridge_engine::config::{ConfigError, Limit, removed_key};
use bridge_engine::version::Version;
use bridge_engine::{
    BuildInfo, Config, K40tAllow, SigningKey, SiyiIdentity, SystemIds, ViewlinkIdentity,
};
use core::fmt::{self, Write};
use core::hint::black_box;

/// A `fmt::Write` that keeps nothing (but the optimiser cannot see that).
struct Sink;

impl Write for Sink {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        black_box(s);
        Ok(())
    }
}

fn show(e: Result<impl Sized, ConfigError>) {
    if let Err(e) = e {
        black_box(write!(black_box(&mut Sink), "{e}"));
    }
}

pub fn exercise(input: &[u8], _out: &mut [u8]) {
    show(black_box(Config::DEFAULT).validate());
    for limit in Limit::ALL {
        show(black_box(limit).check(black_box(0)));
    }
    let text = core::str::from_utf8(input).unwrap_or_default();
    show(SiyiIdentity::parse_hardware_id(text));
    show(ViewlinkIdentity::parse_model(text));
    if let Some(v) = Version::parse(text) {
        black_box((v.viewlink_text(), v.gcu_x10(), v.mavlink()));
    }
    let build = black_box(BuildInfo::ENGINE);
    black_box((build.flight_sw_version(), build.custom_version()));
    black_box(write!(black_box(&mut Sink), "{build}"));
    if let Err(e) = removed_key(|section, key| black_box(section.len() == key.len())) {
        black_box(write!(black_box(&mut Sink), "{e}"));
    }
    show(SigningKey::parse(text));
    let ids: [i64; 12] = black_box([0; 12]);
    let n = black_box(0usize);
    show(SystemIds::from_list(ids.get(..n).unwrap_or_default()));
    show(K40tAllow::from_list(ids.get(..n).unwrap_or_default()));
    let allow = black_box(K40tAllow::NONE);
    black_box(allow.allows(black_box(0)));
}
