//! The one table of the bridge's settings ([`SETTINGS`]): every key an integrator sets,
//! each with its configuration file key, its MAVLink parameter (when a number can carry
//! it), its form and range, and when it applies. The configuration file, the console, the
//! parameter protocol and the book's table all come from it (docs/src/firmware/
//! configuration.md; tests compare the book's table and the file's keys with it).
//!
//! - **Record.** Each setting is kept in the store under `0x0100 + id`; an id is never
//!   reused for another key (a removed key's id stays free).
//! - **Parameter.** `BRG_` and at most 12 characters (16 in all, MAVLink's limit); the
//!   type is the narrowest MAV_PARAM_TYPE that holds the range. The texts (the SIYI
//!   hardware id, the Viewlink model, the video address), the signing key and the list of
//!   ground stations are not parameters: the console and the file only. `k40t_allow` is a
//!   bit mask (`BRG_K40T_ALLOW`: bit i allows [`GUARDED`]`[i]`),
//!   `k40t_geotag_fallback_ms` 0 for `"off"`, the choices their index.
//! - **Applies.** [`Applies::Live`]: read by the engine where it is used, so a new value
//!   counts from the next input; [`Applies::Restart`]: built into the engine's parts at
//!   start (baud rates, the FC side, signing, the time discipline, the RTC_IO plan, the
//!   autopilot's pinning, the PPS edge), taken at the next start.

use core::fmt;

use super::value::{self, Value};
use crate::access::{GUARDED, K40tAllow, SigningKey, SigningMode, SystemIds};
use crate::config::{
    ConfigError, Form, Limit, Problem, SiyiIdentity, VideoConfig, ViewlinkIdentity,
};
use crate::{Config, Duration, FcProtocol};

/// When a new value takes effect.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Applies {
    /// At once: the engine reads it where it is used.
    Live,
    /// At the next start.
    Restart,
}

impl Applies {
    /// `live` or `restart` (the book's column).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Applies::Live => "live",
            Applies::Restart => "restart",
        }
    }
}

/// A MAVLink parameter's type (MAV_PARAM_TYPE).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ParamType {
    /// MAV_PARAM_TYPE_UINT8.
    Uint8,
    /// MAV_PARAM_TYPE_INT8.
    Int8,
    /// MAV_PARAM_TYPE_UINT16.
    Uint16,
    /// MAV_PARAM_TYPE_INT16.
    Int16,
    /// MAV_PARAM_TYPE_UINT32.
    Uint32,
    /// MAV_PARAM_TYPE_INT32.
    Int32,
}

impl ParamType {
    /// The narrowest signed type that holds `min..=max` (INT32 beyond INT16's range).
    /// Signed only, as ArduPilot's and PX4's parameters are: MAVSDK's parameter client
    /// lists INT8, INT16, INT32 and REAL32 and leaves the unsigned types out
    /// (docs/src/firmware/configuration.md, "The parameters").
    #[must_use]
    pub const fn holding(min: i64, max: i64) -> Self {
        if min >= -0x80 && max <= 0x7F {
            ParamType::Int8
        } else if min >= -0x8000 && max <= 0x7FFF {
            ParamType::Int16
        } else {
            ParamType::Int32
        }
    }

    /// Its MAV_PARAM_TYPE value.
    #[must_use]
    pub const fn code(self) -> u8 {
        match self {
            ParamType::Uint8 => 1,
            ParamType::Int8 => 2,
            ParamType::Uint16 => 3,
            ParamType::Int16 => 4,
            ParamType::Uint32 => 5,
            ParamType::Int32 => 6,
        }
    }

    /// Its name in the book (`UINT8`).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            ParamType::Uint8 => "UINT8",
            ParamType::Int8 => "INT8",
            ParamType::Uint16 => "UINT16",
            ParamType::Int16 => "INT16",
            ParamType::Uint32 => "UINT32",
            ParamType::Int32 => "INT32",
        }
    }

    /// The value of its bytes as MAVLink's byte-wise encoding carries them in
    /// `param_value` (the low bytes of the 32-bit word, little-endian).
    #[must_use]
    pub fn from_bytes(self, bits: u32) -> i64 {
        let [b0, b1, b2, b3] = bits.to_le_bytes();
        match self {
            ParamType::Uint8 => i64::from(b0),
            ParamType::Int8 => i64::from(i8::from_le_bytes([b0])),
            ParamType::Uint16 => i64::from(u16::from_le_bytes([b0, b1])),
            ParamType::Int16 => i64::from(i16::from_le_bytes([b0, b1])),
            ParamType::Uint32 => i64::from(bits),
            ParamType::Int32 => i64::from(i32::from_le_bytes([b0, b1, b2, b3])),
        }
    }

    /// `v` in MAVLink's byte-wise encoding (its low bytes, the rest zero).
    #[must_use]
    pub fn to_bytes(self, v: i64) -> u32 {
        let bytes = v.to_le_bytes();
        let [b0, b1, b2, b3, ..] = bytes;
        let n = match self {
            ParamType::Uint8 | ParamType::Int8 => 1,
            ParamType::Uint16 | ParamType::Int16 => 2,
            ParamType::Uint32 | ParamType::Int32 => 4,
        };
        let mut word = [b0, b1, b2, b3];
        for b in word.iter_mut().skip(n) {
            *b = 0;
        }
        u32::from_le_bytes(word)
    }
}

/// The FC sides, in the order of [`SIDE_NAMES`] (their parameter values).
pub const SIDES: [FcProtocol; 5] = [
    FcProtocol::Siyi,
    FcProtocol::Viewlink,
    FcProtocol::Gcu,
    FcProtocol::K40t,
    FcProtocol::Mavlink,
];
/// The FC sides' names (the configuration file's `fc` values).
pub const SIDE_NAMES: [&str; 5] = ["siyi", "viewlink", "gcu", "k40t", "mavlink"];
/// `fc`'s names: the sides and `"auto"` (the default: the build's side or the straps).
const FC_NAMES: [&str; 6] = ["siyi", "viewlink", "gcu", "k40t", "mavlink", "auto"];

/// The FC sides a bridge may be set to (a bit per [`SIDES`] index).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Sides(pub u8);

impl Sides {
    /// Every side compiled into this engine (the K40T side always is).
    pub const COMPILED: Self = Self(
        (cfg!(feature = "siyi") as u8)
            | ((cfg!(feature = "viewlink") as u8) << 1)
            | ((cfg!(feature = "gcu") as u8) << 2)
            | (1 << 3)
            | ((cfg!(feature = "mavlink") as u8) << 4),
    );

    /// The sides of a list.
    #[must_use]
    pub fn of(sides: &[FcProtocol]) -> Self {
        Self(sides.iter().fold(0, |bits, fc| bits | side_bit(*fc)))
    }

    /// `fc` is one of them.
    #[must_use]
    pub fn contains(self, fc: FcProtocol) -> bool {
        self.0 & side_bit(fc) != 0
    }
}

fn side_index(fc: FcProtocol) -> usize {
    SIDES.iter().position(|s| *s == fc).unwrap_or(0)
}

fn side_bit(fc: FcProtocol) -> u8 {
    1u8.checked_shl(u32::try_from(side_index(fc)).unwrap_or(8))
        .unwrap_or(0)
}

/// How a setting's value is read from a [`Config`], checked and written into one.
#[derive(Debug, Clone, Copy)]
pub enum Access {
    /// A whole number in `limit`'s range (a time: whole milliseconds).
    Int {
        /// Its range (and key, for errors).
        limit: Limit,
        /// Its value.
        get: fn(&Config) -> i64,
        /// Sets it (the value is in range).
        put: fn(&mut Config, i64),
    },
    /// Whole milliseconds in `limit`'s range, or `"off"` (`None`; parameter value 0).
    MsOrOff {
        /// Its range.
        limit: Limit,
        /// Its value.
        get: fn(&Config) -> Option<i64>,
        /// Sets it.
        put: fn(&mut Config, Option<i64>),
    },
    /// `true` or `false` (parameter 1 or 0).
    Bool {
        /// Its value.
        get: fn(&Config) -> bool,
        /// Sets it.
        put: fn(&mut Config, bool),
    },
    /// One of `names` (the parameter's value is its index).
    Choice {
        /// The names.
        names: &'static [&'static str],
        /// Its index.
        get: fn(&Config) -> usize,
        /// Sets it (the index is in range).
        put: fn(&mut Config, usize),
    },
    /// The FC side: one of [`SIDE_NAMES`] this bridge has ([`Sides`]), or `"auto"` (the
    /// default).
    Side,
    /// A text, through its key's parser.
    Text {
        /// Its bytes (without padding).
        get: fn(&Config) -> &[u8],
        /// Parses and sets it.
        put: fn(&mut Config, &str) -> Result<(), ConfigError>,
    },
    /// The signing key: written, never read back.
    SigningKey,
    /// `gcs_ids`: a list of system ids.
    GcsIds,
    /// `k40t_allow`: a list of the pod's destructive requests (parameter: a bit mask).
    K40tAllow,
}

/// One setting (see the module documentation).
#[derive(Debug, Clone, Copy)]
pub struct Setting {
    /// Its record is `0x0100 + id` (never reused).
    pub id: u8,
    /// The configuration file's key (`sync.period_ms`).
    pub key: &'static str,
    /// Its MAVLink parameter's name, when it has one.
    pub param: Option<&'static str>,
    /// Its form.
    pub access: Access,
    /// When a new value takes effect.
    pub applies: Applies,
}

/// Bits of `k40t_allow`'s parameter: one per [`GUARDED`] request.
const ALLOW_MASK: i64 = (1 << GUARDED.len()) - 1;

impl Setting {
    /// Its record's key in the store.
    #[must_use]
    pub const fn record(&self) -> u16 {
        0x0100 | self.id as u16
    }

    /// Written only: never read back through any interface.
    #[must_use]
    pub const fn secret(&self) -> bool {
        matches!(self.access, Access::SigningKey)
    }

    /// The range of its parameter's value (`None`: not a parameter).
    #[must_use]
    pub const fn param_range(&self) -> Option<(i64, i64)> {
        if self.param.is_none() {
            return None;
        }
        match self.access {
            Access::Int { limit, .. } => Some((limit.min, limit.max)),
            Access::MsOrOff { limit, .. } => Some((0, limit.max)),
            Access::Bool { .. } => Some((0, 1)),
            Access::Choice { names, .. } => Some((0, last_index(names.len()))),
            Access::Side => Some((0, last_index(SIDES.len()))),
            Access::K40tAllow => Some((0, ALLOW_MASK)),
            Access::Text { .. } | Access::SigningKey | Access::GcsIds => None,
        }
    }

    /// Its parameter's MAV_PARAM_TYPE (`None`: not a parameter).
    #[must_use]
    pub const fn param_type(&self) -> Option<ParamType> {
        match self.param_range() {
            Some((min, max)) => Some(ParamType::holding(min, max)),
            None => None,
        }
    }

    fn error(&self, problem: Problem) -> ConfigError {
        ConfigError {
            key: self.key,
            problem,
        }
    }

    fn form(&self, form: Form) -> ConfigError {
        self.error(Problem::Form(form))
    }

    /// Sets the value given as text (the console, the store) into `config`, checked by the
    /// key's own rule (its range, its parser). The whole configuration is not checked here:
    /// see [`Config::validate`].
    ///
    /// # Errors
    /// The value's form or range is not the key's.
    pub fn assign(
        &self,
        config: &mut Config,
        v: &Value<'_>,
        sides: Sides,
    ) -> Result<(), ConfigError> {
        let word = |form| v.text().ok_or(self.form(form));
        match self.access {
            Access::Int { .. } | Access::MsOrOff { .. } => {
                let text = word(Form::Number)?;
                let off = matches!(self.access, Access::MsOrOff { .. }) && text == "off";
                if off {
                    return self.assign_number(config, 0, sides);
                }
                let n = value::int(text).ok_or(self.form(match self.access {
                    Access::MsOrOff { .. } => Form::NumberOrOff,
                    _ => Form::Number,
                }))?;
                if let Access::MsOrOff { limit, put, .. } = self.access {
                    limit.check(n)?;
                    put(config, Some(n));
                    return Ok(());
                }
                self.assign_number(config, n, sides)
            }
            Access::Bool { put, .. } => match word(Form::Bool)? {
                "true" => {
                    put(config, true);
                    Ok(())
                }
                "false" => {
                    put(config, false);
                    Ok(())
                }
                _ => Err(self.form(Form::Bool)),
            },
            Access::Choice { names, put, .. } => {
                let name = word(Form::OneOf(names))?;
                let i = names
                    .iter()
                    .position(|n| *n == name)
                    .ok_or(self.form(Form::OneOf(names)))?;
                put(config, i);
                Ok(())
            }
            Access::Side => {
                let name = word(Form::OneOf(&FC_NAMES))?;
                let i = FC_NAMES
                    .iter()
                    .position(|n| *n == name)
                    .ok_or(self.form(Form::OneOf(&FC_NAMES)))?;
                match SIDES.get(i) {
                    Some(fc) => self.set_side(config, *fc, sides),
                    // "auto": the caller puts the default back.
                    None => Err(self.error(Problem::NoSuchSide)),
                }
            }
            Access::Text { put, .. } => put(config, word(Form::Text)?),
            Access::SigningKey => {
                config.signing_key = SigningKey::parse(word(Form::Text)?)?;
                Ok(())
            }
            Access::GcsIds => {
                let Value::List(list) = v else {
                    return Err(self.form(Form::List));
                };
                config.gcs_ids = SystemIds::from_list(list.as_slice())?;
                Ok(())
            }
            Access::K40tAllow => {
                let Value::List(list) = v else {
                    return Err(self.form(Form::List));
                };
                config.k40t_allow = K40tAllow::from_list(list.as_slice())?;
                Ok(())
            }
        }
    }

    /// `"auto"` given for `fc`: the caller puts the default side back.
    #[must_use]
    pub fn is_auto(&self, v: &Value<'_>) -> bool {
        matches!(self.access, Access::Side) && v.text() == Some("auto")
    }

    fn set_side(
        &self,
        config: &mut Config,
        fc: FcProtocol,
        sides: Sides,
    ) -> Result<(), ConfigError> {
        if sides.contains(fc) {
            config.fc = fc;
            Ok(())
        } else {
            Err(self.error(Problem::NoSuchSide))
        }
    }

    /// Sets the value given as its parameter's number.
    ///
    /// # Errors
    /// Not a parameter, or the number is out of its range.
    pub fn assign_number(
        &self,
        config: &mut Config,
        n: i64,
        sides: Sides,
    ) -> Result<(), ConfigError> {
        let (min, max) = match (self.param_range(), self.access) {
            (Some(range), _) => range,
            // A number for a key that is not a parameter.
            (None, Access::Int { limit, .. }) => (limit.min, limit.max),
            (None, _) => return Err(self.form(Form::Text)),
        };
        if let Access::Int { limit, .. } = self.access {
            limit.check(n)?;
        } else if n < min || n > max {
            return Err(self.error(Problem::OutOfRange { value: n, min, max }));
        }
        let index = usize::try_from(n).unwrap_or(0);
        match self.access {
            Access::Int { put, .. } => put(config, n),
            Access::MsOrOff { put, .. } => put(config, (n != 0).then_some(n)),
            Access::Bool { put, .. } => put(config, n != 0),
            Access::Choice { put, .. } => put(config, index),
            Access::Side => {
                let fc = SIDES.get(index).copied().unwrap_or(FcProtocol::Siyi);
                self.set_side(config, fc, sides)?;
            }
            Access::K40tAllow => {
                config.k40t_allow = K40tAllow {
                    bits: u16::try_from(n).unwrap_or(0),
                };
            }
            Access::Text { .. } | Access::SigningKey | Access::GcsIds => {
                return Err(self.form(Form::Text));
            }
        }
        Ok(())
    }

    /// Its value as its parameter's number (`None`: not a parameter).
    #[must_use]
    pub fn number(&self, config: &Config) -> Option<i64> {
        self.param?;
        Some(match self.access {
            Access::Int { get, .. } => get(config),
            Access::MsOrOff { get, .. } => get(config).unwrap_or(0),
            Access::Bool { get, .. } => i64::from(get(config)),
            Access::Choice { get, .. } => i64::try_from(get(config)).unwrap_or(0),
            Access::Side => i64::try_from(side_index(config.fc)).unwrap_or(0),
            Access::K40tAllow => i64::from(config.k40t_allow.bits),
            Access::Text { .. } | Access::SigningKey | Access::GcsIds => return None,
        })
    }

    /// Writes its value in `config` as the configuration file writes it (a TOML value).
    /// The signing key is never written: [`Problem::WriteOnly`].
    ///
    /// # Errors
    /// [`Problem::WriteOnly`] for the signing key (nothing written); the writer's errors
    /// as [`Problem::Form`] never occur with a writer that takes everything.
    pub fn write(&self, config: &Config, out: &mut impl fmt::Write) -> Result<(), ConfigError> {
        self.write_as(config, out, false)
    }

    /// Writes the value as its record keeps it: a text as it is (not quoted), the
    /// signing key in hexadecimal (the store is the one place that holds it), anything
    /// else as [`Setting::write`] does.
    ///
    /// # Errors
    /// As [`Setting::write`], but the signing key is written.
    pub fn write_record(
        &self,
        config: &Config,
        out: &mut impl fmt::Write,
    ) -> Result<(), ConfigError> {
        self.write_as(config, out, true)
    }

    fn write_as(
        &self,
        config: &Config,
        out: &mut impl fmt::Write,
        record: bool,
    ) -> Result<(), ConfigError> {
        let r = match self.access {
            Access::Int { get, .. } => write!(out, "{}", get(config)),
            Access::MsOrOff { get, .. } => match get(config) {
                Some(ms) => write!(out, "{ms}"),
                None => out.write_str("\"off\""),
            },
            Access::Bool { get, .. } => out.write_str(if get(config) { "true" } else { "false" }),
            Access::Choice { names, get, .. } => {
                let name = names.get(get(config)).copied().unwrap_or("");
                write!(out, "\"{name}\"")
            }
            Access::Side => {
                let name = SIDE_NAMES.get(side_index(config.fc)).copied().unwrap_or("");
                write!(out, "\"{name}\"")
            }
            Access::Text { get, .. } if record => get(config)
                .iter()
                .try_for_each(|b| out.write_char(char::from(*b))),
            Access::Text { get, .. } => value::write_quoted(out, get(config)),
            Access::SigningKey if record => config.signing_key.map_or(Ok(()), |k| {
                k.0.iter().try_for_each(|b| write!(out, "{b:02x}"))
            }),
            Access::SigningKey => return Err(self.error(Problem::WriteOnly)),
            Access::GcsIds => write_list(
                out,
                config.gcs_ids.as_slice().iter().map(|id| (*id).into()),
                false,
            ),
            Access::K40tAllow => write_list(
                out,
                GUARDED
                    .iter()
                    .filter(|g| config.k40t_allow.allows(g.base))
                    .map(|g| i64::from(g.base)),
                true,
            ),
        };
        r.map_err(|_| self.form(Form::Text))
    }

    /// Sets the value its record kept (see [`Setting::write_record`]).
    ///
    /// # Errors
    /// The record's text is not a value of the key.
    pub fn restore(
        &self,
        config: &mut Config,
        text: &str,
        sides: Sides,
    ) -> Result<(), ConfigError> {
        match self.access {
            Access::Text { .. } | Access::SigningKey => {
                self.assign(config, &Value::Quoted(text), sides)
            }
            _ => {
                let mut scratch = [0u8; value::MAX_TEXT];
                let v = value::parse(text, &mut scratch).map_err(|e| self.form(Form::Syntax(e)))?;
                self.assign(config, &v, sides)
            }
        }
    }

    /// `a` and `b` hold the same value of this setting.
    #[must_use]
    pub fn same(&self, a: &Config, b: &Config) -> bool {
        match self.access {
            Access::Int { get, .. } => get(a) == get(b),
            Access::MsOrOff { get, .. } => get(a) == get(b),
            Access::Bool { get, .. } => get(a) == get(b),
            Access::Choice { get, .. } => get(a) == get(b),
            Access::Side => a.fc == b.fc,
            Access::Text { get, .. } => get(a) == get(b),
            Access::SigningKey => a.signing_key == b.signing_key,
            Access::GcsIds => a.gcs_ids.as_slice() == b.gcs_ids.as_slice(),
            Access::K40tAllow => a.k40t_allow == b.k40t_allow,
        }
    }

    /// Copies this setting's value from `from` into `to`.
    pub fn copy(&self, from: &Config, to: &mut Config) {
        match self.access {
            Access::Int { get, put, .. } => put(to, get(from)),
            Access::MsOrOff { get, put, .. } => put(to, get(from)),
            Access::Bool { get, put } => put(to, get(from)),
            Access::Choice { get, put, .. } => put(to, get(from)),
            Access::Side => to.fc = from.fc,
            Access::Text { get, put } => {
                // A valid configuration's text parses again.
                if let Ok(text) = core::str::from_utf8(get(from)) {
                    let _ = put(to, text);
                }
            }
            Access::SigningKey => to.signing_key = from.signing_key,
            Access::GcsIds => to.gcs_ids = from.gcs_ids,
            Access::K40tAllow => to.k40t_allow = from.k40t_allow,
        }
    }
}

/// The last index of a list of `n` (a few names: no wrap).
#[allow(clippy::cast_possible_wrap)]
const fn last_index(n: usize) -> i64 {
    (n as i64).saturating_sub(1)
}

/// `[a, b]`, each in hexadecimal as a K40T id (`0x00030D`) or in decimal.
fn write_list(
    out: &mut impl fmt::Write,
    items: impl Iterator<Item = i64>,
    hex: bool,
) -> fmt::Result {
    out.write_char('[')?;
    for (i, v) in items.enumerate() {
        if i > 0 {
            out.write_str(", ")?;
        }
        if hex {
            write!(out, "{v:#08X}")?;
        } else {
            write!(out, "{v}")?;
        }
    }
    out.write_char(']')
}

/// Whole milliseconds of a time.
fn ms(d: Duration) -> i64 {
    crate::config::millis(d)
}

/// A time of `v` whole milliseconds (in range: not negative).
fn from_ms(v: i64) -> Duration {
    Duration::from_millis(u64::try_from(v).unwrap_or(0))
}

/// `v` as the field's type (in range by its limit).
fn narrow<T: TryFrom<i64> + Copy>(v: i64, old: T) -> T {
    T::try_from(v).unwrap_or(old)
}

const SIGNING_MODES: [&str; 3] = ["off", "sign", "require"];

fn signing_index(m: SigningMode) -> usize {
    match m {
        SigningMode::Off => 0,
        SigningMode::Sign => 1,
        SigningMode::Require => 2,
    }
}

const fn limit(key: &'static str, min: i64, max: i64) -> Limit {
    Limit::new(key, min, max)
}

const fn setting(
    id: u8,
    key: &'static str,
    param: Option<&'static str>,
    access: Access,
    applies: Applies,
) -> Setting {
    Setting {
        id,
        key,
        param,
        access,
        applies,
    }
}

/// [`Access::Int`] over a field of an integer type.
macro_rules! int {
    ($limit:expr, $($f:ident).+) => {
        Access::Int {
            limit: $limit,
            get: |c| i64::from(c.$($f).+),
            put: |c, v| c.$($f).+ = narrow(v, c.$($f).+),
        }
    };
}

/// [`Access::Int`] over a time, in whole milliseconds.
macro_rules! millis {
    ($limit:expr, $($f:ident).+) => {
        Access::Int {
            limit: $limit,
            get: |c| ms(c.$($f).+),
            put: |c, v| c.$($f).+ = from_ms(v),
        }
    };
}

/// [`Access::Bool`] over a field.
macro_rules! flag {
    ($($f:ident).+) => {
        Access::Bool {
            get: |c| c.$($f).+,
            put: |c, v| c.$($f).+ = v,
        }
    };
}

use Applies::{Live, Restart};

/// Every setting, in the configuration file's order (`bridge-fw/bridge.toml`).
pub const SETTINGS: [Setting; 43] = [
    setting(1, "fc", Some("BRG_FC"), Access::Side, Restart),
    setting(
        2,
        "fc_baud",
        Some("BRG_FC_BAUD"),
        int!(Limit::FC_BAUD, fc_baud),
        Restart,
    ),
    setting(
        3,
        "pod_baud",
        Some("BRG_POD_BAUD"),
        int!(Limit::POD_BAUD, pod_baud),
        Restart,
    ),
    setting(
        4,
        "telemetry_baud",
        Some("BRG_TEL_BAUD"),
        int!(Limit::TELEMETRY_BAUD, telemetry_baud),
        Restart,
    ),
    setting(
        5,
        "leap_seconds",
        Some("BRG_LEAP_SEC"),
        int!(limit("leap_seconds", 0, 255), leap_seconds),
        Live,
    ),
    setting(
        6,
        "tz_minuteswest",
        Some("BRG_TZ_MIN_WEST"),
        int!(Limit::TZ_MINUTESWEST, tz_minuteswest),
        Live,
    ),
    setting(
        7,
        "fc_link_timeout_ms",
        Some("BRG_FC_TIMEOUT"),
        millis!(Limit::FC_LINK_TIMEOUT_MS, fc_link_timeout),
        Live,
    ),
    setting(
        8,
        "fc_silence_stop_ms",
        Some("BRG_FC_SIL_STOP"),
        millis!(Limit::FC_SILENCE_STOP_MS, fc_silence_stop),
        Restart,
    ),
    setting(
        9,
        "k40t_geotag_fallback_ms",
        Some("BRG_K40T_GEO_FB"),
        Access::MsOrOff {
            limit: Limit::K40T_GEOTAG_FALLBACK_MS,
            get: |c| c.k40t_geotag_fallback.map(ms),
            put: |c, v| c.k40t_geotag_fallback = v.map(from_ms),
        },
        Live,
    ),
    setting(
        10,
        "signing",
        Some("BRG_SIGNING"),
        Access::Choice {
            names: &SIGNING_MODES,
            get: |c| signing_index(c.signing),
            put: |c, i| {
                c.signing = match i {
                    1 => SigningMode::Sign,
                    2 => SigningMode::Require,
                    _ => SigningMode::Off,
                }
            },
        },
        Restart,
    ),
    setting(11, "signing_key", None, Access::SigningKey, Restart),
    setting(
        12,
        "signing_unsigned_telemetry",
        Some("BRG_SIGN_UNS_TEL"),
        flag!(signing_unsigned_telemetry),
        Live,
    ),
    setting(13, "gcs_ids", None, Access::GcsIds, Live),
    setting(
        14,
        "k40t_allow",
        Some("BRG_K40T_ALLOW"),
        Access::K40tAllow,
        Live,
    ),
    setting(
        15,
        "autopilot_sysid",
        Some("BRG_AP_SYSID"),
        int!(Limit::AUTOPILOT_SYSID, autopilot_sysid),
        Restart,
    ),
    setting(
        16,
        "autopilot_forget_ms",
        Some("BRG_AP_FORGET"),
        millis!(Limit::AUTOPILOT_FORGET_MS, autopilot_forget),
        Live,
    ),
    setting(
        17,
        "sync.period_ms",
        Some("BRG_SYNC_PERIOD"),
        millis!(Limit::SYNC_PERIOD_MS, sync.period),
        Restart,
    ),
    setting(
        18,
        "sync.width_ms",
        Some("BRG_SYNC_WIDTH"),
        millis!(Limit::SYNC_WIDTH_MS, sync.width),
        Restart,
    ),
    setting(
        19,
        "siyi.hardware_id",
        None,
        Access::Text {
            get: |c| &c.siyi.hardware_id,
            put: |c, t| {
                c.siyi.hardware_id = SiyiIdentity::parse_hardware_id(t)?;
                Ok(())
            },
        },
        Live,
    ),
    setting(
        20,
        "siyi.max_zoom_x10",
        Some("BRG_SIYI_ZOOM"),
        int!(Limit::SIYI_MAX_ZOOM_X10, siyi.max_zoom_x10),
        Live,
    ),
    setting(
        21,
        "viewlink.model",
        None,
        Access::Text {
            get: |c| {
                let n = c.viewlink.model.iter().position(|b| *b == 0);
                let n = n.unwrap_or(c.viewlink.model.len());
                c.viewlink.model.get(..n).unwrap_or_default()
            },
            put: |c, t| {
                c.viewlink.model = ViewlinkIdentity::parse_model(t)?;
                Ok(())
            },
        },
        Live,
    ),
    setting(
        22,
        "gcu.hardware_x10",
        Some("BRG_GCU_HW"),
        int!(limit("gcu.hardware_x10", 0, 255), gcu.hardware_x10),
        Live,
    ),
    setting(
        23,
        "gcu.gimbal_code",
        Some("BRG_GCU_CODE"),
        int!(limit("gcu.gimbal_code", 0, 255), gcu.gimbal_code),
        Live,
    ),
    setting(
        24,
        "gcu.resync_mark",
        Some("BRG_GCU_RESYNC"),
        flag!(gcu.resync_mark),
        Live,
    ),
    setting(
        25,
        "pod.yaw_positive_left",
        Some("BRG_POD_YAW_LEFT"),
        flag!(pod.yaw_positive_left),
        Live,
    ),
    setting(
        26,
        "pod.pitch_positive_down",
        Some("BRG_POD_PITCH_DN"),
        flag!(pod.pitch_positive_down),
        Live,
    ),
    setting(
        27,
        "video.uri",
        None,
        Access::Text {
            get: |c| c.video.configured_uri().unwrap_or_default(),
            put: |c, t| {
                c.video.uri = VideoConfig::parse_uri(t)?;
                Ok(())
            },
        },
        Live,
    ),
    setting(
        28,
        "lens.visible_hfov_1x_cdeg",
        Some("BRG_LENS_HFOV"),
        int!(Limit::LENS_HFOV_CDEG, lens.visible_hfov_1x_cdeg),
        Live,
    ),
    setting(
        29,
        "lens.ir_hfov_cdeg",
        Some("BRG_LENS_IR_HFOV"),
        int!(Limit::LENS_IR_HFOV_CDEG, lens.ir_hfov_cdeg),
        Live,
    ),
    setting(
        30,
        "lens.focal_length_min_um",
        Some("BRG_LENS_FL_MIN"),
        int!(Limit::LENS_FOCAL_LENGTH_MIN_UM, lens.focal_length_min_um),
        Live,
    ),
    setting(
        31,
        "lens.focal_length_max_um",
        Some("BRG_LENS_FL_MAX"),
        int!(Limit::LENS_FOCAL_LENGTH_MAX_UM, lens.focal_length_max_um),
        Live,
    ),
    setting(
        32,
        "lens.sensor_width_um",
        Some("BRG_LENS_SENS_W"),
        int!(Limit::LENS_SENSOR_WIDTH_UM, lens.sensor_width_um),
        Live,
    ),
    setting(
        33,
        "lens.sensor_height_um",
        Some("BRG_LENS_SENS_H"),
        int!(Limit::LENS_SENSOR_HEIGHT_UM, lens.sensor_height_um),
        Live,
    ),
    setting(
        34,
        "lens.resolution_h",
        Some("BRG_LENS_RES_H"),
        int!(Limit::LENS_RESOLUTION_H, lens.resolution_h),
        Live,
    ),
    setting(
        35,
        "lens.resolution_v",
        Some("BRG_LENS_RES_V"),
        int!(Limit::LENS_RESOLUTION_V, lens.resolution_v),
        Live,
    ),
    setting(
        36,
        "laser.periodic",
        Some("BRG_LASER_PERIOD"),
        flag!(laser.periodic),
        Restart,
    ),
    setting(
        37,
        "laser.min_distance_cm",
        Some("BRG_LASER_MIN"),
        int!(Limit::LASER_MIN_DISTANCE_CM, laser.min_distance_cm),
        Live,
    ),
    setting(
        38,
        "laser.max_distance_cm",
        Some("BRG_LASER_MAX"),
        int!(Limit::LASER_MAX_DISTANCE_CM, laser.max_distance_cm),
        Live,
    ),
    setting(
        39,
        "discipline.bin_ms",
        Some("BRG_DISC_BIN"),
        millis!(Limit::DISCIPLINE_BIN_MS, discipline.bin_len),
        Restart,
    ),
    setting(
        40,
        "discipline.min_bins",
        Some("BRG_DISC_BINS"),
        int!(Limit::DISCIPLINE_MIN_BINS, discipline.min_bins),
        Restart,
    ),
    setting(
        41,
        "discipline.min_span_ms",
        Some("BRG_DISC_SPAN"),
        millis!(Limit::DISCIPLINE_MIN_SPAN_MS, discipline.min_span),
        Restart,
    ),
    setting(
        42,
        "mavlink.allow_destructive",
        Some("BRG_MAV_DESTRUCT"),
        flag!(mavlink.allow_destructive),
        Live,
    ),
    setting(
        43,
        "pps.active_low",
        Some("BRG_PPS_ACT_LOW"),
        flag!(pps.active_low),
        Restart,
    ),
];

/// The setting of a file key (`sync.period_ms`).
#[must_use]
pub fn find(key: &str) -> Option<&'static Setting> {
    SETTINGS.iter().find(|s| s.key == key)
}

/// The setting of a record key.
#[must_use]
pub fn by_record(record: u16) -> Option<&'static Setting> {
    SETTINGS.iter().find(|s| s.record() == record)
}

/// The settings that are MAVLink parameters, in order (a parameter's index).
pub fn params() -> impl Iterator<Item = &'static Setting> {
    SETTINGS.iter().filter(|s| s.param.is_some())
}

/// How many settings are parameters.
#[must_use]
pub fn param_count() -> usize {
    params().count()
}

/// The parameter of a name (as PARAM_SET and PARAM_REQUEST_READ carry it: up to 16 bytes,
/// zero-padded) and its index.
#[must_use]
pub fn by_param(name: &[u8]) -> Option<(usize, &'static Setting)> {
    let len = name.iter().position(|b| *b == 0).unwrap_or(name.len());
    let name = name.get(..len)?;
    params()
        .enumerate()
        .find(|(_, s)| s.param.is_some_and(|p| p.as_bytes() == name))
}

/// The parameter of an index.
#[must_use]
pub fn param_at(index: usize) -> Option<&'static Setting> {
    params().nth(index)
}
