//! `gimbal config`: the console's client (docs/src/console.md). It types commands on the
//! console's port (the board's ST-LINK virtual COM port, or `gimbal bridge --console`'s)
//! and reads each answer up to its `ok` or `error` line: `get` and `set` as typed, `dump`
//! (every setting, as a configuration file) and `load` (a dump's settings set one by one,
//! then saved).

use std::path::Path;
use std::time::{Duration, Instant};

use crate::client_port;

/// How long an answer may take (a `get` of every setting is some 2 KiB: 0.2 s at 115200
/// baud).
const ANSWER_TIMEOUT: Duration = Duration::from_secs(5);

/// A console's port: a serial device, or `tcp:HOST:PORT`.
pub struct ConsolePort {
    io: Box<dyn client_port::ReadWrite>,
    /// Read but not yet taken.
    pending: Vec<u8>,
}

/// One answer: its lines (without the echo, the final line and the prompt), and whether
/// it ended `ok`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Answer {
    /// The lines between the echoed command and the final line.
    pub lines: Vec<String>,
    /// The final line (`ok`, `ok: ...` or `error: ...`).
    pub last: String,
}

impl Answer {
    /// The command succeeded.
    #[must_use]
    pub fn ok(&self) -> bool {
        self.last.starts_with("ok")
    }
}

impl ConsolePort {
    /// Opens `port` (a serial device at `baud`, or `tcp:HOST:PORT`) and drops any line
    /// half typed on it (Ctrl-C), reading up to the prompt.
    ///
    /// # Errors
    /// The port cannot be opened, or the console does not answer.
    pub fn open(port: &str, baud: u32) -> Result<Self, String> {
        let io = client_port::open(port, baud, Duration::from_millis(100))?;
        let mut c = ConsolePort {
            io,
            pending: Vec::new(),
        };
        c.io.write_all(b"\x03")
            .map_err(|e| format!("{port}: {e}"))?;
        c.read_until(|text| text.ends_with("> "))
            .map_err(|e| format!("{port}: {e}"))?;
        c.pending.clear();
        Ok(c)
    }

    /// Reads until `done` holds for what was read (kept in `pending`).
    fn read_until(&mut self, done: impl Fn(&str) -> bool) -> Result<(), String> {
        let deadline = Instant::now() + ANSWER_TIMEOUT;
        let mut buf = [0u8; 512];
        while !done(&String::from_utf8_lossy(&self.pending)) {
            if Instant::now() > deadline {
                return Err(format!(
                    "no answer from the console within {} s (read {:?})",
                    ANSWER_TIMEOUT.as_secs(),
                    String::from_utf8_lossy(&self.pending)
                ));
            }
            match self.io.read(&mut buf) {
                Ok(0) => return Err("the console's port closed".into()),
                Ok(n) => self
                    .pending
                    .extend_from_slice(buf.get(..n).unwrap_or_default()),
                Err(e) if client_port::timed_out(&e) => {}
                Err(e) => return Err(e.to_string()),
            }
        }
        Ok(())
    }

    /// Types `command` and reads its answer.
    ///
    /// # Errors
    /// The port fails, or no answer comes.
    pub fn command(&mut self, command: &str) -> Result<Answer, String> {
        if command.contains(['\r', '\n']) {
            return Err(format!("{command:?}: one line only"));
        }
        self.io
            .write_all(format!("{command}\r").as_bytes())
            .and_then(|()| self.io.flush())
            .map_err(|e| e.to_string())?;
        self.read_until(|text| {
            text.ends_with("> ") && {
                let last = text.trim_end_matches("> ").trim_end();
                last.lines()
                    .last()
                    .is_some_and(|l| l.starts_with("ok") || l.starts_with("error"))
            }
        })?;
        let text = String::from_utf8_lossy(&std::mem::take(&mut self.pending)).into_owned();
        let mut lines: Vec<String> = text
            .trim_end_matches("> ")
            .lines()
            .map(|l| l.trim_end_matches('\r').to_owned())
            .collect();
        // The echo first (what was typed), the final line last.
        if lines.first().is_some_and(|l| l == command) {
            lines.remove(0);
        }
        let last = lines.pop().unwrap_or_default();
        Ok(Answer { lines, last })
    }
}

/// A dump's line as `set`'s argument: `key = value` (a trailing `# comment` dropped, `#`
/// inside quotes kept); `None` for a blank line or a comment.
#[must_use]
pub fn setting_of(line: &str) -> Option<(String, String)> {
    let mut in_quotes = false;
    let mut escaped = false;
    let mut end = line.len();
    for (i, c) in line.char_indices() {
        match c {
            _ if escaped => escaped = false,
            '\\' if in_quotes => escaped = true,
            '"' => in_quotes = !in_quotes,
            '#' if !in_quotes => {
                end = i;
                break;
            }
            _ => {}
        }
    }
    let (key, value) = line.get(..end)?.split_once('=')?;
    let (key, value) = (key.trim(), value.trim());
    (!key.is_empty() && !value.is_empty()).then(|| (key.to_owned(), value.to_owned()))
}

/// `gimbal config ... load FILE`: every setting of the file set, then kept (`save`);
/// the first refusal stops it before the save (nothing kept; what was set before it stays
/// set until a restart or `defaults`). Returns what the console said, a line each.
///
/// # Errors
/// The file cannot be read, a line is not `key = value`, or the console refuses one.
pub fn load(port: &mut ConsolePort, file: &Path) -> Result<Vec<String>, String> {
    let text = std::fs::read_to_string(file).map_err(|e| format!("{}: {e}", file.display()))?;
    let mut said = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        let Some((key, value)) = setting_of(trimmed) else {
            return Err(format!(
                "{}:{}: not `key = value`: {trimmed}",
                file.display(),
                n + 1
            ));
        };
        let a = port.command(&format!("set {key} {value}"))?;
        if !a.ok() {
            return Err(format!(
                "{}:{}: {key}: {} (nothing saved)",
                file.display(),
                n + 1,
                a.last
            ));
        }
        said.extend(a.lines);
    }
    let a = port.command("save")?;
    if !a.ok() {
        return Err(format!("save: {}", a.last));
    }
    said.push(a.last);
    Ok(said)
}

#[cfg(test)]
mod tests {
    use super::setting_of;

    #[test]
    fn a_dump_line_is_a_key_and_its_value_without_the_comment() {
        let kv = |k: &str, v: &str| Some((k.to_owned(), v.to_owned()));
        assert_eq!(
            setting_of("pod_baud = 230400  # at the next start (now 115200)"),
            kv("pod_baud", "230400")
        );
        assert_eq!(
            setting_of(r#"video.uri = "rtsp://a/#b\"c"  # x"#),
            kv("video.uri", r#""rtsp://a/#b\"c""#)
        );
        assert_eq!(setting_of("# signing_key: write-only, none"), None);
        assert_eq!(
            setting_of("gcs_ids = [255, 190]"),
            kv("gcs_ids", "[255, 190]")
        );
        assert_eq!(setting_of("no value ="), None);
    }
}
