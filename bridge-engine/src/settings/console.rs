//! The console: a line protocol on a serial port (the board's ST-LINK virtual COM port,
//! `gimbal bridge --console-port`), for a terminal (picocom, screen) and for `gimbal
//! config`. Sans-IO: bytes in ([`Console::receive`]), bytes out ([`Console::transmit`]);
//! see docs/src/console.md.
//!
//! - **Line editing.** Printable characters are echoed; backspace (0x08 or 0x7F) takes the
//!   last one back; CR, LF or CR LF ends the line; Ctrl-C drops it. A line longer than
//!   [`LINE`] is refused whole.
//! - **Answers.** Each command's answer is its lines, then `ok` (or `ok: ...`) or
//!   `error: ...`, then the prompt `> `: a client reads up to the `ok` or `error` line.
//! - **Settings** are written as the configuration file writes them (`key = value`), so
//!   that `get` with no key is a configuration file; the signing key never: `# signing_key:
//!   write-only, set (fingerprint ...)`.
//! - **The update protocol.** `update`, or a line that starts with the update frames'
//!   first byte (0xB7, not ASCII: never typed), hands the port to the update receiver
//!   ([`Action::Update`]: the bytes from that one on are the receiver's); the caller gives
//!   it back after [`UPDATE_IDLE`] without an update frame.
//! - **Long answers** (`get`, `help`, `status`'s counters) are written a line at a time as
//!   the output drains, so the output buffer stays small.

use core::fmt::{self, Write as _};

use super::table::{self, SETTINGS, Setting};
use super::{Settings, Writer, value};
use crate::discipline::{DisciplineState, PpsState};
use crate::event::{Counters, SettingOutcome};
use crate::time::{Duration, UtcTime};
use crate::{BuildInfo, Config, FcProtocol};

/// Longest line (a `set` of a 160-character address with room to spare).
pub const LINE: usize = 224;
/// Bytes of the output buffer.
const OUT: usize = 512;
/// The longest line of output (a 160-character address quoted, each character escaped),
/// and the room a line of a long answer waits for.
const LINE_ROOM: usize = 352;
/// The first byte of an update frame (bridge-update's sync, 0xB7 0x4D).
pub const UPDATE_SYNC: u8 = 0xB7;
/// The update protocol gives the port back after this long without a frame.
pub const UPDATE_IDLE: Duration = Duration::from_secs(30);
/// The prompt.
const PROMPT: &[u8] = b"> ";

/// What the caller does after an input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Action {
    /// Restart the bridge (once the store has written what waits, and the answer has
    /// left).
    Reboot,
    /// Hand the port to the update protocol, from `at` in the bytes given.
    Update {
        /// Where the update protocol's bytes begin in the input.
        at: usize,
    },
}

/// What the bridge is doing, for `status`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Status {
    pub(crate) fc: FcProtocol,
    pub(crate) fc_link: bool,
    pub(crate) pod_link: bool,
    pub(crate) telemetry_source: bool,
    pub(crate) utc_state: DisciplineState,
    /// UTC now and the error believed, when known.
    pub(crate) utc: Option<(UtcTime, Duration)>,
    pub(crate) pps: PpsState,
    pub(crate) counters: Counters,
}

/// What a command may use of the engine.
pub(crate) struct Parts<'a> {
    pub(crate) settings: &'a mut Settings,
    /// The configuration running (a live setting reaches it at once).
    pub(crate) running: &'a mut Config,
    pub(crate) build: &'a BuildInfo,
    pub(crate) status: Status,
    /// The signing key's fingerprint in the running configuration (MAVLink builds).
    pub(crate) fingerprint: Option<[u8; 6]>,
}

/// A change a command made, for the engine's events.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Change {
    /// The setting's record key (the header's for every setting).
    pub(crate) key: u16,
    pub(crate) outcome: SettingOutcome,
}

/// A long answer being written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Job {
    None,
    /// `get` of every setting: the next one.
    Dump(u8),
    /// `help`: the next line.
    Help(u8),
    /// `status`: the next counter.
    Counters(u8),
}

/// The console's state.
#[derive(Debug, Clone)]
pub(crate) struct Console {
    line: [u8; LINE],
    len: usize,
    /// The line grew past [`LINE`]: refused at its end.
    overflow: bool,
    /// The last byte was a CR (an LF right after it ends nothing).
    after_cr: bool,
    out: [u8; OUT],
    out_start: usize,
    out_end: usize,
    job: Job,
    /// The status for `status`'s counters (taken when asked).
    counters: Counters,
}

/// The commands and what they do (`help`).
const HELP: [&str; 10] = [
    "help              this list",
    "version           the firmware's version, commit and features",
    "status            links, UTC, PPS and the counters",
    "get [KEY]         a setting, or every one (a configuration file)",
    "set KEY VALUE     a setting, checked as the configuration file is ('auto' for fc)",
    "save              keeps the settings set since the last save",
    "defaults          every setting back to its default, kept at once",
    "reboot            restarts the bridge (restart settings take effect)",
    "update            hands this port to the update protocol (gimbal update)",
    "settings: docs/src/firmware/configuration.md; the console: docs/src/console.md",
];

impl Console {
    pub(crate) fn new() -> Self {
        Console {
            line: [0; LINE],
            len: 0,
            overflow: false,
            after_cr: false,
            out: [0; OUT],
            out_start: 0,
            out_end: 0,
            job: Job::None,
            counters: Counters::default(),
        }
    }

    /// Output waits.
    pub(crate) fn has_output(&self) -> bool {
        self.out_end > self.out_start || self.job != Job::None
    }

    /// Bytes from the port. Returns what the caller must do, and each change a command
    /// made (at most one per line; `changes` gets them).
    pub(crate) fn receive(
        &mut self,
        bytes: &[u8],
        parts: &mut Parts<'_>,
        mut changes: impl FnMut(Change),
    ) -> Option<Action> {
        for (i, &b) in bytes.iter().enumerate() {
            let after_cr = core::mem::take(&mut self.after_cr);
            match b {
                UPDATE_SYNC if self.len == 0 && !self.overflow => {
                    return Some(Action::Update { at: i });
                }
                b'\r' | b'\n' => {
                    if b == b'\n' && after_cr {
                        continue;
                    }
                    self.after_cr = b == b'\r';
                    self.put(b"\r\n");
                    match self.end_line(parts, &mut changes) {
                        // Typed: the update protocol's bytes come after this line.
                        Some(Action::Update { .. }) => {
                            return Some(Action::Update {
                                at: i.saturating_add(1),
                            });
                        }
                        Some(action) => return Some(action),
                        None => {}
                    }
                }
                0x08 | 0x7F if self.len > 0 && !self.overflow => {
                    self.len = self.len.saturating_sub(1);
                    self.put(b"\x08 \x08");
                }
                0x03 => {
                    self.len = 0;
                    self.overflow = false;
                    self.put(b"^C\r\n");
                    self.put(PROMPT);
                }
                0x20..=0x7E => match self.line.get_mut(self.len) {
                    Some(slot) if !self.overflow => {
                        *slot = b;
                        self.len = self.len.saturating_add(1);
                        self.put(&[b]);
                    }
                    _ => self.overflow = true,
                },
                _ => {}
            }
        }
        None
    }

    /// The next output: copies up to `buf.len()` bytes, writing the lines of a long
    /// answer as room comes.
    pub(crate) fn transmit(&mut self, buf: &mut [u8], parts: &Parts<'_>) -> usize {
        while self.job != Job::None && self.room() >= LINE_ROOM {
            self.job_line(parts);
        }
        let pending = self
            .out
            .get(self.out_start..self.out_end)
            .unwrap_or_default();
        let n = pending.len().min(buf.len());
        protocol_core::wire::copy(buf, pending);
        self.out_start = self.out_start.saturating_add(n);
        if self.out_start >= self.out_end {
            self.out_start = 0;
            self.out_end = 0;
        }
        n
    }

    /// The update protocol gave the port back: a fresh prompt.
    pub(crate) fn resume(&mut self) {
        self.len = 0;
        self.overflow = false;
        self.put(b"\r\nconsole\r\n");
        self.put(PROMPT);
    }

    fn room(&self) -> usize {
        OUT.saturating_sub(self.out_end.saturating_sub(self.out_start))
    }

    /// Queues output; what does not fit is dropped (a reader that does not read).
    fn put(&mut self, bytes: &[u8]) {
        if self.out_end.saturating_add(bytes.len()) > OUT && self.out_start > 0 {
            protocol_core::wire::copy_within(&mut self.out, self.out_start..self.out_end, 0);
            self.out_end = self.out_end.saturating_sub(self.out_start);
            self.out_start = 0;
        }
        let end = self.out_end.saturating_add(bytes.len()).min(OUT);
        if let Some(dst) = self.out.get_mut(self.out_end..end) {
            protocol_core::wire::copy(dst, bytes);
        }
        self.out_end = end;
    }

    /// One line of output, built with `write` (cut at [`LINE_ROOM`]), then CR LF.
    fn line(&mut self, write: impl FnOnce(&mut Writer<'_>) -> fmt::Result) {
        let mut buf = [0u8; LINE_ROOM];
        let mut w = Writer::new(&mut buf);
        let _ = write(&mut w);
        let n = w.len();
        self.put(buf.get(..n).unwrap_or_default());
        self.put(b"\r\n");
    }

    fn ok(&mut self, note: impl FnOnce(&mut Writer<'_>) -> fmt::Result) {
        self.line(|w| {
            w.write_str("ok")?;
            note(w)
        });
        self.put(PROMPT);
    }

    fn error(&mut self, what: &dyn fmt::Display) {
        self.line(|w| write!(w, "error: {what}"));
        self.put(PROMPT);
    }

    fn end_line(
        &mut self,
        parts: &mut Parts<'_>,
        changes: &mut impl FnMut(Change),
    ) -> Option<Action> {
        let len = core::mem::take(&mut self.len);
        if core::mem::take(&mut self.overflow) {
            self.error(&"the line is longer than 224 characters");
            return None;
        }
        // A new command ends a long answer still being written.
        self.job = Job::None;
        let line = self.line;
        let text = line
            .get(..len)
            .and_then(|l| core::str::from_utf8(l).ok())
            .unwrap_or("");
        let text = text.trim();
        let (command, rest) = text.split_once(value::is_space).unwrap_or((text, ""));
        let rest = rest.trim();
        match command {
            "" => self.put(PROMPT),
            "help" => self.job = Job::Help(0),
            "version" => {
                let build = parts.build;
                self.line(|w| write!(w, "{build}"));
                self.ok(|_| Ok(()));
            }
            "status" => self.status(parts),
            "get" if rest.is_empty() => {
                let build = parts.build;
                self.line(|w| write!(w, "# the bridge's settings ({build})"));
                self.job = Job::Dump(0);
            }
            "get" => match table::find(rest) {
                Some(s) => {
                    self.setting_line(s, parts);
                    self.ok(|_| Ok(()));
                }
                None => self.unknown_key(rest),
            },
            "set" => self.set(rest, parts, changes),
            "save" => {
                let n = parts.settings.save();
                changes(Change {
                    key: super::HEADER,
                    outcome: SettingOutcome::Saved,
                });
                let restart = parts.settings.restart_pending(parts.running);
                self.ok(|w| {
                    write!(w, ": {n} settings kept")?;
                    if restart > 0 {
                        write!(w, "; {restart} apply at the next start (reboot)")?;
                    }
                    Ok(())
                });
            }
            "defaults" => {
                let restart = parts.settings.reset(parts.running);
                parts.settings.apply_live(parts.running);
                changes(Change {
                    key: super::HEADER,
                    outcome: SettingOutcome::Defaults,
                });
                self.ok(|w| {
                    write!(w, ": every setting at its default, kept")?;
                    if restart > 0 {
                        write!(w, "; {restart} apply at the next start (reboot)")?;
                    }
                    Ok(())
                });
            }
            "reboot" => {
                let lost = parts.settings.unsaved();
                self.ok(|w| {
                    w.write_str(": rebooting")?;
                    if lost > 0 {
                        write!(w, " ({lost} settings set and not saved are lost)")?;
                    }
                    Ok(())
                });
                return Some(Action::Reboot);
            }
            "update" => {
                self.ok(|w| {
                    w.write_str(
                        ": this port is the update protocol's now (gimbal update); the console \
                         comes back after 30 s without an update frame",
                    )
                });
                return Some(Action::Update { at: 0 });
            }
            other => {
                let other = Name(other);
                self.error(&format_args!("unknown command {other} (help lists them)"));
            }
        }
        None
    }

    fn unknown_key(&mut self, key: &str) {
        let key = Name(key);
        self.error(&format_args!("no setting {key} (get lists them)"));
    }

    fn set(&mut self, rest: &str, parts: &mut Parts<'_>, changes: &mut impl FnMut(Change)) {
        let (key, text) = rest.split_once(value::is_space).unwrap_or((rest, ""));
        let Some(index) = Settings::index_of(key) else {
            self.unknown_key(key);
            return;
        };
        let Some(s) = SETTINGS.get(index) else {
            return;
        };
        let mut scratch = [0u8; value::MAX_TEXT];
        let v = match value::parse(text, &mut scratch) {
            Ok(v) => v,
            Err(e) => {
                self.error(&format_args!("{}: {e}", s.key));
                return;
            }
        };
        match parts.settings.set(index, &v) {
            Ok(_) => {
                parts.settings.apply_live(parts.running);
                let outcome = if s.applies == table::Applies::Live {
                    SettingOutcome::Applied
                } else {
                    SettingOutcome::AtRestart
                };
                changes(Change {
                    key: s.record(),
                    outcome,
                });
                self.setting_line(s, parts);
                self.ok(|w| w.write_str(": not kept until save"));
            }
            Err(e) => {
                changes(Change {
                    key: s.record(),
                    outcome: SettingOutcome::Refused,
                });
                self.error(&e);
            }
        }
    }

    /// `key = value` as set, with a comment when it waits for the next start; the
    /// signing key as whether one is set and its fingerprint.
    fn setting_line(&mut self, s: &Setting, parts: &Parts<'_>) {
        let pending = parts.settings.pending();
        if s.secret() {
            let fingerprint = parts.fingerprint;
            let set = pending.signing_key.is_some();
            let waits = !s.same(pending, parts.running);
            self.line(|w| {
                write!(w, "# {}: write-only, ", s.key)?;
                if !set {
                    w.write_str("none")?;
                } else if let Some(f) = fingerprint.filter(|_| !waits) {
                    w.write_str("set (fingerprint ")?;
                    f.iter().try_for_each(|b| write!(w, "{b:02x}"))?;
                    w.write_char(')')?;
                } else {
                    w.write_str("set")?;
                }
                if waits {
                    w.write_str(", at the next start")?;
                }
                Ok(())
            });
            return;
        }
        let running = &*parts.running;
        self.line(|w| {
            write!(w, "{} = ", s.key)?;
            s.write(pending, w).map_err(|_| fmt::Error)?;
            if !s.same(pending, running) {
                w.write_str("  # at the next start (now ")?;
                s.write(running, w).map_err(|_| fmt::Error)?;
                w.write_char(')')?;
            }
            Ok(())
        });
    }

    fn status(&mut self, parts: &Parts<'_>) {
        let st = parts.status;
        let up = |b: bool| if b { "up" } else { "down" };
        let side = table::SIDE_NAMES
            .get(table::SIDES.iter().position(|s| *s == st.fc).unwrap_or(0))
            .copied()
            .unwrap_or("");
        self.line(|w| write!(w, "fc link: {} ({side})", up(st.fc_link)));
        self.line(|w| write!(w, "pod link: {}", up(st.pod_link)));
        self.line(|w| {
            let source = if st.telemetry_source {
                "telemetry link"
            } else {
                "fc link"
            };
            write!(w, "time source: {source}")
        });
        self.line(|w| {
            w.write_str("utc: ")?;
            match st.utc {
                Some((utc, bound)) => {
                    let (y, mo, d) = utc.date();
                    let t = utc.time_of_day();
                    write!(
                        w,
                        "{y:04}-{mo:02}-{d:02}T{:02}:{:02}:{:02}.{:03}Z, bound {} us ({:?})",
                        t.hour(),
                        t.minute(),
                        t.second(),
                        t.millisecond(),
                        bound.as_micros(),
                        st.utc_state
                    )
                }
                None => write!(w, "unknown ({:?})", st.utc_state),
            }
        });
        self.line(|w| write!(w, "pps: {:?}", st.pps));
        self.counters = st.counters;
        self.job = Job::Counters(0);
    }

    /// Writes the next line of the long answer under way.
    fn job_line(&mut self, parts: &Parts<'_>) {
        match self.job {
            Job::None => {}
            Job::Help(i) => {
                if let Some(text) = HELP.get(usize::from(i)) {
                    self.line(|w| w.write_str(text));
                    self.job = Job::Help(i.saturating_add(1));
                } else {
                    self.end_job();
                }
            }
            Job::Dump(i) => {
                if let Some(s) = SETTINGS.get(usize::from(i)) {
                    self.setting_line(s, parts);
                    self.job = Job::Dump(i.saturating_add(1));
                } else {
                    self.end_job();
                }
            }
            Job::Counters(i) => {
                if let Some(&(name, v)) = self.counters.named().get(usize::from(i)) {
                    self.line(|w| write!(w, "{name}: {v}"));
                    self.job = Job::Counters(i.saturating_add(1));
                } else {
                    self.end_job();
                }
            }
        }
    }
}

impl Console {
    fn end_job(&mut self) {
        self.job = Job::None;
        self.ok(|_| Ok(()));
    }
}

/// A word of the line in quotes, cut at 40 characters.
struct Name<'a>(&'a str);

impl fmt::Display for Name<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let n = self
            .0
            .char_indices()
            .nth(40)
            .map_or(self.0.len(), |(i, _)| i);
        write!(f, "\"{}\"", self.0.get(..n).unwrap_or(""))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Changes, Engine, Event, Instant};

    extern crate std;
    use std::string::String;
    use std::vec::Vec;

    /// Types `input`; returns everything the console wrote (drained 64 bytes at a time)
    /// and its action.
    fn type_in(e: &mut Engine, input: &[u8]) -> (String, Option<Action>) {
        let (changes, action) = e.console_receive(Instant::from_millis(5), input);
        let mut out = Vec::new();
        let mut buf = [0u8; 64];
        loop {
            let n = e.console_transmit(&mut buf);
            if n == 0 {
                break;
            }
            out.extend_from_slice(&buf[..n]);
        }
        assert!(out.is_empty() || changes.contains(Changes::CONSOLE));
        (String::from_utf8(out).unwrap(), action)
    }

    fn answer(e: &mut Engine, line: &str) -> String {
        let (out, action) = type_in(e, std::format!("{line}\r\n").as_bytes());
        assert_eq!(action, None, "{line}");
        let echo = std::format!("{line}\r\n");
        assert!(out.starts_with(&echo), "{out:?}");
        assert!(out.ends_with("> "), "{out:?}");
        out[echo.len()..out.len() - 2].into()
    }

    #[test]
    fn a_terminal_edits_its_line() {
        let mut e = Engine::new(Config::DEFAULT);
        // A typo taken back, CR LF ending one line.
        let (out, _) = type_in(&mut e, b"gex\x7ft fc_baud\r\n");
        assert_eq!(out, "gex\x08 \x08t fc_baud\r\nfc_baud = 115200\r\nok\r\n> ");
        // The LF of a CR LF pair ends nothing more, in the next input too; a lone LF ends
        // a line.
        let (out, _) = type_in(&mut e, b"\r");
        assert_eq!(out, "\r\n> ");
        let (out, _) = type_in(&mut e, b"\n");
        assert_eq!(out, "");
        let (out, _) = type_in(&mut e, b"\n");
        assert_eq!(out, "\r\n> ");
        // Ctrl-C drops the line; a backspace on an empty line does nothing.
        let (out, _) = type_in(&mut e, b"\x08reb\x03");
        assert_eq!(out, "reb^C\r\n> ");
        // Bytes that are not printable are not taken.
        let (out, _) = type_in(&mut e, b"ver\x01\x1bsion\r");
        assert!(
            out.starts_with("version\r\n0.2.0 commit unknown\r\nok\r\n"),
            "{out:?}"
        );
        // A line past LINE characters: refused whole.
        let long = std::format!("set video.uri {}\r", "x".repeat(LINE));
        let (out, _) = type_in(&mut e, long.as_bytes());
        assert!(
            out.ends_with("error: the line is longer than 224 characters\r\n> "),
            "{out:?}"
        );
        assert_eq!(e.settings().pending(), &Config::DEFAULT);
    }

    #[test]
    fn settings_are_got_set_kept_and_reset() {
        let mut e = Engine::new(Config::DEFAULT);
        assert_eq!(
            answer(&mut e, "set fc_baud 57600"),
            "fc_baud = 57600  # at the next start (now 115200)\r\nok: not kept until save\r\n"
        );
        assert_eq!(
            answer(&mut e, "set tz_minuteswest -60"),
            "tz_minuteswest = -60\r\nok: not kept until save\r\n"
        );
        assert_eq!(e.config().tz_minuteswest, -60, "live");
        assert_eq!(e.config().fc_baud, 115_200, "at the next start");
        assert_eq!(
            answer(&mut e, "set fc_baud 12"),
            "error: fc_baud: 12 is out of range 1200..=4000000\r\n"
        );
        assert_eq!(
            answer(&mut e, "set signing require"),
            "error: signing_key: needed (signing is on)\r\n"
        );
        assert_eq!(
            answer(&mut e, "set video.uri \"rtsp://a b\""),
            "error: video.uri: expected up to 160 printable ASCII characters, no space\r\n"
        );
        assert_eq!(
            answer(&mut e, "set video.uri \"open"),
            "error: video.uri: a quoted text without its closing quote\r\n"
        );
        assert_eq!(
            answer(&mut e, "get nothing"),
            "error: no setting \"nothing\" (get lists them)\r\n"
        );
        assert_eq!(
            answer(&mut e, "fly"),
            "error: unknown command \"fly\" (help lists them)\r\n"
        );
        assert!(e.take_record().is_none(), "nothing kept before save");
        assert_eq!(
            answer(&mut e, "save"),
            "ok: 2 settings kept; 1 apply at the next start (reboot)\r\n"
        );
        let kept: Vec<u16> = core::iter::from_fn(|| e.take_record())
            .map(|r| r.key.0)
            .collect();
        assert_eq!(kept, [0x0102, 0x0106]);
        assert_eq!(
            answer(&mut e, "defaults"),
            "ok: every setting at its default, kept\r\n"
        );
        assert_eq!(e.config().tz_minuteswest, 0);
        let kept: Vec<Vec<u8>> = core::iter::from_fn(|| e.take_record())
            .map(|r| r.value().to_vec())
            .collect();
        assert_eq!(kept, [std::vec![1, 0], std::vec![1, 0]]);
        let events: Vec<Event> = core::iter::from_fn(|| e.next_event()).collect();
        assert!(events.contains(&Event::Setting {
            key: 0x0102,
            source: crate::SettingSource::Console,
            outcome: SettingOutcome::AtRestart
        }));
        assert!(events.contains(&Event::Setting {
            key: 0x0102,
            source: crate::SettingSource::Console,
            outcome: SettingOutcome::Refused
        }));
        assert!(events.contains(&Event::Setting {
            key: super::super::HEADER,
            source: crate::SettingSource::Console,
            outcome: SettingOutcome::Defaults
        }));
    }

    /// `get` with no key writes every setting, a line at a time as the output drains, as a
    /// configuration file: the signing key only as a comment.
    #[test]
    fn every_setting_as_a_file_and_the_key_never() {
        let mut e = Engine::new(Config::DEFAULT);
        let key = "0123456789abcdef".repeat(4);
        answer(&mut e, &std::format!("set signing_key {key}"));
        let dump = answer(&mut e, "get");
        let lines: Vec<&str> = dump.lines().collect();
        assert!(
            lines[0].starts_with("# the bridge's settings (0.2.0"),
            "{}",
            lines[0]
        );
        assert_eq!(lines.len(), SETTINGS.len() + 2, "{dump}");
        assert_eq!(*lines.last().unwrap(), "ok");
        for (line, s) in lines[1..].iter().zip(&SETTINGS) {
            if s.secret() {
                assert_eq!(*line, "# signing_key: write-only, set, at the next start");
            } else {
                assert!(line.starts_with(&std::format!("{} = ", s.key)), "{line}");
            }
        }
        assert!(
            !dump.to_lowercase().contains(&key[..16]),
            "the key never comes back"
        );
        assert_eq!(
            answer(&mut e, "get signing_key"),
            "# signing_key: write-only, set, at the next start\r\nok\r\n"
        );
    }

    #[test]
    fn reboot_and_update_are_the_callers() {
        let mut e = Engine::new(Config::DEFAULT);
        answer(&mut e, "set leap_seconds 19");
        let (out, action) = type_in(&mut e, b"reboot\r");
        assert_eq!(action, Some(Action::Reboot));
        assert!(
            out.contains("ok: rebooting (1 settings set and not saved are lost)"),
            "{out}"
        );
        // `update` hands over what follows its line.
        let (out, action) = type_in(&mut e, b"update\r\n\xB7\x4D");
        assert_eq!(action, Some(Action::Update { at: 7 }));
        assert!(
            out.contains("ok: this port is the update protocol's"),
            "{out}"
        );
        // An update frame's first byte at a line's start: at once, not echoed.
        let (out, action) = type_in(&mut e, b"\xB7\x4D\x01\x00");
        assert_eq!(action, Some(Action::Update { at: 0 }));
        assert_eq!(out, "");
        let (out, action) = type_in(&mut e, b"ab\xB7");
        assert_eq!(
            (out.as_str(), action),
            ("ab", None),
            "inside a line: not a frame"
        );
        type_in(&mut e, b"\x03");
        let (c, _) = e.console_receive(Instant::ZERO, b"");
        assert!(!c.contains(Changes::CONSOLE));
        assert!(e.console_resume().contains(Changes::CONSOLE));
        let (out, _) = type_in(&mut e, b"");
        assert_eq!(out, "\r\nconsole\r\n> ");
    }

    #[test]
    fn status_help_and_version() {
        let mut e = Engine::new(Config::for_fc(FcProtocol::Gcu));
        let status = answer(&mut e, "status");
        for want in [
            "fc link: down (gcu)\r\n",
            "pod link: down\r\n",
            "time source: fc link\r\n",
            "utc: unknown (Unknown)\r\n",
            "pps: Off\r\n",
            "fc_frames: 0\r\n",
            "other_autopilots: 0\r\nok\r\n",
        ] {
            assert!(status.contains(want), "{want:?} in {status}");
        }
        let help = answer(&mut e, "help");
        assert_eq!(help.lines().count(), HELP.len() + 1);
        for c in [
            "help", "version", "status", "get", "set", "save", "defaults", "reboot", "update",
        ] {
            assert!(
                help.contains(&std::format!("\n{c} ")) || help.starts_with(c),
                "{c}"
            );
        }
        assert_eq!(answer(&mut e, "version"), "0.2.0 commit unknown\r\nok\r\n");
    }
}
