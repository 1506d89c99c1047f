//! The bridge's settings at run time: what an integrator sets through the console, the
//! MAVLink parameter protocol or the configuration file, checked, kept in the store and
//! applied live or at the next start (docs/src/firmware/configuration.md, "Settings";
//! docs/src/console.md).
//!
//! - **One table** ([`table::SETTINGS`]): each key's file name, parameter, form, range and
//!   when it applies. The console, the parameters, the records and the book's table come
//!   from it.
//! - **Defaults.** The configuration the bridge was built or started with (the firmware's
//!   `bridge.toml`, `gimbal bridge`'s file and options) is the defaults; the store keeps
//!   the settings that differ from them, one record each (a setting set back to its
//!   default is recorded as "default"). `defaults` puts every setting back and keeps that.
//! - **Checked as the file is.** A value passes its key's parser and range, then the whole
//!   configuration passes [`Config::validate`] with it, or nothing changes: `signing =
//!   "require"` without a key is refused as a whole.
//! - **Pending and running.** [`Settings::pending`] is the configuration as set: the next
//!   start runs it. A [live](table::Applies::Live) setting is also copied at once into the
//!   configuration the engine runs; a restart setting waits for the next start.
//! - **Restoring** ([`Restore`]): before the engine is made, the caller hands it the
//!   records the store holds; the result ([`Restored`]) gives the configuration to start
//!   with, and the engine reports what was wrong ([`Event::StoreRecord`](crate::Event)).
//!   A store without the settings' header record is blank (a first start, or erased): the
//!   bridge starts on its defaults, says so (key [`store::Key::WHOLE_STORE`], problem
//!   `Missing`), shows the store-reset LED code, and writes the header so the next start
//!   is not blank. A store that cannot be read, or whose settings are not valid together,
//!   is the same with problem `Unreadable` or `Value`.
//!
//! # Records
//! Key `0x0100` is the header (version 1: `[1]`). Setting `id` is `0x0100 + id`:
//! `[1, 0]` for "default", `[1, 1, text...]` for a value, its text as the console writes
//! it, texts unquoted (the signing key in hexadecimal: the store is the one place that
//! holds it, as it holds a key set by SETUP_SIGNING).

pub(crate) mod console;
pub mod table;
pub mod value;

use core::fmt;

use crate::Config;
use crate::config::ConfigError;
use crate::store::{self, Problem, Record};

pub use table::{Access, Applies, ParamType, SETTINGS, Setting, Sides};

/// The settings' header record.
pub const HEADER: u16 = 0x0100;
/// Longest record value: the version, the tag, a text.
pub const MAX_RECORD: usize = 2 + value::MAX_TEXT;
/// A record's tag: the default.
const TAG_DEFAULT: u8 = 0;
/// A record's tag: a value follows.
const TAG_VALUE: u8 = 1;

/// Settings, one bit each, by their index in [`SETTINGS`].
type Bits = u64;

const _: () = assert!(SETTINGS.len() <= Bits::BITS as usize);

fn bit(index: usize) -> Bits {
    1u64.checked_shl(u32::try_from(index).unwrap_or(64))
        .unwrap_or(0)
}

/// The settings whose values differ between `a` and `b`.
fn changed_bits(a: &Config, b: &Config) -> Bits {
    SETTINGS
        .iter()
        .enumerate()
        .filter(|(_, s)| !s.same(a, b))
        .fold(0, |bits, (i, _)| bits | bit(i))
}

/// A value accepted: when it applies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Accepted {
    /// The setting's index in [`SETTINGS`].
    pub index: usize,
    /// Applied now (a live setting), or at the next start.
    pub applies: Applies,
}

/// The settings' state in the engine (see the module documentation).
#[derive(Debug, Clone)]
pub struct Settings {
    defaults: Config,
    pending: Config,
    sides: Sides,
    /// Settings whose record in the store holds a value (not the default).
    stored: Bits,
    /// Settings set since the last save.
    unsaved: Bits,
    /// Records to hand to the store.
    to_write: Bits,
    /// The header record is to be written (the store was blank).
    header_due: bool,
    /// Live settings changed: the running configuration takes them.
    live_due: bool,
}

impl Settings {
    /// Settings with nothing stored: `config` is the defaults, pending and running;
    /// `sides` the FC sides `fc` may be set to.
    #[must_use]
    pub fn new(config: Config, sides: Sides) -> Self {
        Settings {
            defaults: config,
            pending: config,
            sides,
            stored: 0,
            unsaved: 0,
            to_write: 0,
            header_due: false,
            live_due: false,
        }
    }

    /// The configuration as set (the next start runs it).
    #[must_use]
    pub const fn pending(&self) -> &Config {
        &self.pending
    }

    /// The defaults (the configuration built or started with).
    #[must_use]
    pub const fn defaults(&self) -> &Config {
        &self.defaults
    }

    /// Settings set since the last save.
    #[must_use]
    pub const fn unsaved(&self) -> u32 {
        self.unsaved.count_ones()
    }

    /// Records wait to be written to the store.
    #[must_use]
    pub const fn records_due(&self) -> bool {
        self.to_write != 0 || self.header_due
    }

    /// Sets setting `index` to a value given as text (the console), checked by its rule
    /// and then the whole configuration ([`Config::validate`]); nothing changes on an error.
    ///
    /// # Errors
    /// What is wrong, naming the key.
    pub fn set(&mut self, index: usize, v: &value::Value<'_>) -> Result<Accepted, ConfigError> {
        let s = SETTINGS.get(index).ok_or(NO_SUCH)?;
        let mut c = self.pending;
        if s.is_auto(v) {
            s.copy(&self.defaults, &mut c);
        } else {
            s.assign(&mut c, v, self.sides)?;
        }
        self.commit(index, s, &c)
    }

    /// Sets setting `index` to its parameter's number (PARAM_SET), checked as
    /// [`Settings::set`] does.
    ///
    /// # Errors
    /// What is wrong, naming the key.
    pub fn set_number(&mut self, index: usize, n: i64) -> Result<Accepted, ConfigError> {
        let s = SETTINGS.get(index).ok_or(NO_SUCH)?;
        let mut c = self.pending;
        s.assign_number(&mut c, n, self.sides)?;
        self.commit(index, s, &c)
    }

    fn commit(&mut self, index: usize, s: &Setting, c: &Config) -> Result<Accepted, ConfigError> {
        c.validate()?;
        self.pending = *c;
        self.unsaved |= bit(index);
        if s.applies == Applies::Live {
            self.live_due = true;
        }
        Ok(Accepted {
            index,
            applies: s.applies,
        })
    }

    /// Keeps every setting set since the last save: their records are handed to the store
    /// ([`Settings::take_record`]). Returns how many.
    pub fn save(&mut self) -> u32 {
        let n = self.unsaved.count_ones();
        self.to_write |= self.unsaved;
        self.unsaved = 0;
        n
    }

    /// Keeps setting `index` at once (a PARAM_SET: the parameter protocol has no save
    /// step).
    pub fn keep(&mut self, index: usize) {
        self.to_write |= bit(index) & self.unsaved;
        self.unsaved &= !bit(index);
    }

    /// Every setting back to its default, kept at once (each one the store holds is
    /// recorded as "default"). Returns how many of them apply at the next start and
    /// differ from `running` then.
    pub fn reset(&mut self, running: &Config) -> u32 {
        let changed = changed_bits(&self.defaults, &self.pending) | self.stored;
        self.pending = self.defaults;
        self.to_write |= changed;
        self.unsaved = 0;
        self.live_due = true;
        self.restart_pending(running)
    }

    /// Restart settings whose pending value differs from `running`.
    #[must_use]
    pub fn restart_pending(&self, running: &Config) -> u32 {
        let mut n = 0u32;
        for s in &SETTINGS {
            if s.applies == Applies::Restart && !s.same(&self.pending, running) {
                n = n.saturating_add(1);
            }
        }
        n
    }

    /// Copies the live settings into `running` when some changed; returns whether it did.
    pub fn apply_live(&mut self, running: &mut Config) -> bool {
        if !core::mem::take(&mut self.live_due) {
            return false;
        }
        for s in SETTINGS.iter().filter(|s| s.applies == Applies::Live) {
            s.copy(&self.pending, running);
        }
        true
    }

    /// The next record to write: the header first (after a blank store), then each kept
    /// setting.
    pub fn take_record(&mut self) -> Option<Record> {
        if core::mem::take(&mut self.header_due) {
            return Some(Record::raw(store::Key(HEADER), &[store::VERSION]));
        }
        let index = usize::try_from(self.to_write.trailing_zeros()).ok()?;
        let s = SETTINGS.get(index)?;
        self.to_write &= !bit(index);
        let mut buf = [0u8; MAX_RECORD];
        let mut w = Writer::new(&mut buf);
        let at_default = s.same(&self.pending, &self.defaults);
        let head = if at_default { TAG_DEFAULT } else { TAG_VALUE };
        let _ = w.push(&[store::VERSION, head]);
        if at_default {
            self.stored &= !bit(index);
        } else {
            self.stored |= bit(index);
            // Every value a valid configuration holds fits MAX_RECORD.
            let _ = s.write_record(&self.pending, &mut w);
        }
        let n = w.len();
        Some(Record::raw(
            store::Key(s.record()),
            buf.get(..n).unwrap_or_default(),
        ))
    }

    /// The index of a setting by its file key.
    #[must_use]
    pub fn index_of(key: &str) -> Option<usize> {
        SETTINGS.iter().position(|s| s.key == key)
    }
}

/// An index past the table (never given by the engine itself).
const NO_SUCH: ConfigError = ConfigError {
    key: "",
    problem: crate::config::Problem::Missing,
};

/// What restoring found wrong with one record, reported by the engine as it starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Found {
    /// The record's key.
    pub key: u16,
    /// What was wrong.
    pub problem: Problem,
}

/// Problems reported at most (more are counted in [`Restored::more_problems`]).
const PROBLEMS: usize = 4;

/// The settings being restored from the store (see the module documentation).
#[derive(Debug, Clone)]
pub struct Restore {
    settings: Settings,
    header: bool,
    unreadable: bool,
    problems: [Option<Found>; PROBLEMS],
    more: u8,
}

impl Restore {
    /// Restoring over `defaults`, `fc` among `sides`.
    #[must_use]
    pub fn new(defaults: Config, sides: Sides) -> Self {
        Restore {
            settings: Settings::new(defaults, sides),
            header: false,
            unreadable: false,
            problems: [None; PROBLEMS],
            more: 0,
        }
    }

    /// The record keys to read: the header, then each setting's.
    pub fn keys() -> impl Iterator<Item = u16> {
        core::iter::once(HEADER).chain(SETTINGS.iter().map(Setting::record))
    }

    fn problem(&mut self, key: u16, problem: Problem) {
        match self.problems.iter_mut().find(|p| p.is_none()) {
            Some(slot) => *slot = Some(Found { key, problem }),
            None => self.more = self.more.saturating_add(1),
        }
    }

    /// A record the store holds (one of [`Restore::keys`]): taken, or noted as wrong
    /// (that setting keeps its default, and its record is written again as "default").
    pub fn record(&mut self, key: u16, value: &[u8]) {
        if key == HEADER {
            match value.first() {
                Some(&store::VERSION) => self.header = true,
                Some(&v) => self.problem(key, Problem::Version { found: v }),
                None => self.problem(key, Problem::Empty),
            }
            return;
        }
        let Some((index, s)) = SETTINGS.iter().enumerate().find(|(_, s)| s.record() == key) else {
            self.problem(key, Problem::UnknownKey);
            return;
        };
        match restore_value(s, &mut self.settings.pending, self.settings.sides, value) {
            Ok(true) => self.settings.stored |= bit(index),
            Ok(false) => {}
            Err(problem) => {
                self.problem(key, problem);
                self.settings.to_write |= bit(index);
            }
        }
    }

    /// The store could not be read: every setting keeps its default.
    pub fn unreadable(&mut self) {
        self.unreadable = true;
    }

    /// The configuration to start with, and what to report.
    #[must_use]
    pub fn finish(mut self) -> Restored {
        let s = &mut self.settings;
        let reset = if self.unreadable {
            Some(Problem::Unreadable)
        } else if s.pending.validate().is_err() {
            // Each value passed, not all of them together: start on the defaults, and
            // write them.
            Some(Problem::Value)
        } else if !self.header {
            Some(Problem::Missing)
        } else {
            None
        };
        if reset.is_some() {
            s.to_write |= s.stored;
            if self.unreadable {
                // The store starts blank: nothing of it is kept.
                s.to_write = 0;
            }
            s.stored = 0;
            s.pending = s.defaults;
            s.header_due = true;
        }
        Restored {
            settings: self.settings,
            reset,
            problems: self.problems,
            more_problems: self.more,
        }
    }
}

/// A setting's record taken into `config`: `true` for a value, `false` for "default".
fn restore_value(
    s: &Setting,
    config: &mut Config,
    sides: Sides,
    value: &[u8],
) -> Result<bool, Problem> {
    let (&version, rest) = value.split_first().ok_or(Problem::Empty)?;
    if version != store::VERSION {
        return Err(Problem::Version { found: version });
    }
    match rest.split_first() {
        Some((&TAG_DEFAULT, [])) => Ok(false),
        Some((&TAG_VALUE, text)) => {
            let text = core::str::from_utf8(text).map_err(|_| Problem::Value)?;
            let mut c = *config;
            s.restore(&mut c, text, sides).map_err(|_| Problem::Value)?;
            *config = c;
            Ok(true)
        }
        Some(_) => Err(Problem::Value),
        None => Err(Problem::Length {
            expected: 2,
            found: 1,
        }),
    }
}

/// The settings as restored: the configuration to start with ([`Restored::config`]) and
/// what the engine reports.
#[derive(Debug, Clone)]
pub struct Restored {
    pub(crate) settings: Settings,
    /// The store as a whole: blank (`Missing`), unreadable, or its settings not valid
    /// together (`Value`): started on the defaults.
    pub reset: Option<Problem>,
    /// The records found wrong (each setting kept its default).
    pub problems: [Option<Found>; PROBLEMS],
    /// Records found wrong beyond those.
    pub more_problems: u8,
}

impl Restored {
    /// Nothing restored: `config` as defaults and running (an engine without a store).
    #[must_use]
    pub fn fresh(config: Config, sides: Sides) -> Self {
        Restored {
            settings: Settings::new(config, sides),
            reset: None,
            problems: [None; PROBLEMS],
            more_problems: 0,
        }
    }

    /// The configuration to start with: the defaults with the settings kept.
    #[must_use]
    pub const fn config(&self) -> &Config {
        &self.settings.pending
    }

    /// The defaults it was restored over.
    #[must_use]
    pub const fn defaults(&self) -> &Config {
        &self.settings.defaults
    }

    /// The store was reset (blank, unreadable, or invalid as a whole): the LED shows the
    /// store-reset code.
    #[must_use]
    pub const fn store_reset(&self) -> bool {
        self.reset.is_some()
    }

    /// Replaces the starting value of setting `key` by its default: the board cannot run
    /// it (a baud rate its UART cannot make). The setting stays as set.
    pub fn fall_back(&mut self, key: &str) -> Option<&'static str> {
        let s = table::find(key)?;
        s.copy(&self.settings.defaults, &mut self.settings.pending);
        Some(s.key)
    }
}

/// A `core::fmt::Write` into a byte buffer; what does not fit is an error, never a panic.
pub(crate) struct Writer<'a> {
    buf: &'a mut [u8],
    len: usize,
}

impl<'a> Writer<'a> {
    pub(crate) fn new(buf: &'a mut [u8]) -> Self {
        Writer { buf, len: 0 }
    }

    pub(crate) fn len(&self) -> usize {
        self.len
    }

    pub(crate) fn push(&mut self, bytes: &[u8]) -> fmt::Result {
        let end = self.len.checked_add(bytes.len()).ok_or(fmt::Error)?;
        let dst = self.buf.get_mut(self.len..end).ok_or(fmt::Error)?;
        protocol_core::wire::copy(dst, bytes);
        self.len = end;
        Ok(())
    }
}

impl fmt::Write for Writer<'_> {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        self.push(s.as_bytes())
    }
}

#[cfg(test)]
mod tests;
