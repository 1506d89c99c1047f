//! Where the runner's events go: stdout, one JSON object per line or one line of text,
//! from any thread; and the status line on stderr.
//!
//! Every event is an object whose first two keys are `"t_us"` (the local monotonic
//! clock, µs since the process started: the bridge tasks' own clock) and `"event"` (a
//! snake_case name); the rest depends on the event (docs/src/linux-bridge.md, the JSON event table).

use std::io::{IsTerminal, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use serde_json::{Map, Value};

use crate::runner::event_name::EventName;
use crate::runner::options::EventFormat;

/// The local monotonic clock, µs: embassy-time's on this thread (real time outside a
/// virtual-time run), the clock of the bridge's tasks and records.
#[must_use]
pub fn now_us() -> u64 {
    embassy_time::Instant::now().as_micros()
}

/// An event object: `t_us`, `event`, then the fields of `fields` (an object; anything
/// else is put under `"value"`).
#[must_use]
pub fn event_object(t_us: u64, event: EventName, fields: Value) -> Map<String, Value> {
    let mut m = Map::new();
    m.insert("t_us".into(), Value::from(t_us));
    m.insert("event".into(), Value::from(event.as_str()));
    match fields {
        Value::Object(f) => {
            for (k, v) in f {
                if k != "t_us" && k != "event" {
                    m.insert(k, v);
                }
            }
        }
        Value::Null => {}
        other => {
            m.insert("value".into(), other);
        }
    }
    m
}

/// The text form of an event: seconds, the name, then `key=value` pairs (strings bare,
/// nested objects flattened with dots). A `frame` event shows its decoded line.
#[must_use]
pub fn human_line(obj: &Map<String, Value>) -> String {
    let t = obj.get("t_us").and_then(Value::as_u64).unwrap_or(0);
    let event = obj.get("event").and_then(Value::as_str).unwrap_or("?");
    let mut fields = Map::new();
    for (k, v) in obj {
        if k != "t_us" && k != "event" && k != "text" {
            fields.insert(k.clone(), v.clone());
        }
    }
    let mut rest = if let Some(Value::String(text)) = obj.get("text") {
        text.clone()
    } else {
        crate::tool::flat_pairs(&Value::Object(fields), false).join(" ")
    };
    if let Some(utc) = obj.get("utc_ms").and_then(Value::as_u64) {
        rest.push_str(&format!(" ({})", iso_utc(utc)));
    }
    format!(
        "{:>6}.{:06} {event:<16} {rest}",
        t / 1_000_000,
        t % 1_000_000
    )
    .trim_end()
    .to_string()
}

/// `2026-11-23T10:00:40.000Z` for ms since the Unix epoch.
#[must_use]
pub fn iso_utc(unix_ms: u64) -> String {
    let days = unix_ms / 86_400_000;
    let ms_of_day = unix_ms % 86_400_000;
    // Howard Hinnant's civil_from_days.
    let z = i64::try_from(days).unwrap_or(0) + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{}Z",
        time_of_day_text(u32::try_from(ms_of_day).unwrap_or_default())
    )
}

/// A time of day in ms as `10:00:40.000`.
#[must_use]
pub fn time_of_day_text(ms: u32) -> String {
    format!(
        "{:02}:{:02}:{:02}.{:03}",
        ms / 3_600_000,
        ms / 60_000 % 60,
        ms / 1000 % 60,
        ms % 1000
    )
}

/// The event output, shared by every thread of a run.
#[derive(Clone)]
pub struct Output {
    inner: Arc<Mutex<Inner>>,
    broken: Arc<AtomicBool>,
}

struct Inner {
    format: EventFormat,
    /// A status line is on stderr (cleared before the next line of output).
    status_shown: bool,
    /// Stdout is a terminal (the status line shares it: clear it before each line).
    stdout_tty: bool,
    /// Lines written so far (tests use a capture instead of stdout).
    capture: Option<Vec<Map<String, Value>>>,
}

impl std::fmt::Debug for Output {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Output")
    }
}

impl Output {
    /// Events to stdout in `format`.
    #[must_use]
    pub fn stdout(format: EventFormat) -> Self {
        Output {
            inner: Arc::new(Mutex::new(Inner {
                format,
                status_shown: false,
                stdout_tty: std::io::stdout().is_terminal(),
                capture: None,
            })),
            broken: Arc::new(AtomicBool::new(false)),
        }
    }

    /// Events kept in memory (for tests): see [`Output::captured`].
    #[must_use]
    pub fn capture() -> Self {
        let o = Self::stdout(EventFormat::Json);
        if let Ok(mut i) = o.inner.lock() {
            i.capture = Some(Vec::new());
        }
        o
    }

    /// The events captured so far.
    #[must_use]
    pub fn captured(&self) -> Vec<Map<String, Value>> {
        self.inner
            .lock()
            .ok()
            .and_then(|i| i.capture.clone())
            .unwrap_or_default()
    }

    /// Prints an event stamped now.
    pub fn emit(&self, event: EventName, fields: Value) {
        self.emit_at(now_us(), event, fields);
    }

    /// Prints an event stamped `t_us`.
    pub fn emit_at(&self, t_us: u64, event: EventName, fields: Value) {
        self.write(event_object(t_us, event, fields));
    }

    /// Prints an event object.
    pub fn write(&self, obj: Map<String, Value>) {
        let Ok(mut inner) = self.inner.lock() else {
            return;
        };
        if let Some(c) = inner.capture.as_mut() {
            c.push(obj);
            return;
        }
        if inner.status_shown && inner.stdout_tty {
            let mut err = std::io::stderr().lock();
            let _ = write!(err, "\r\x1b[2K");
            let _ = err.flush();
            inner.status_shown = false;
        }
        let line = match inner.format {
            EventFormat::Json => Value::Object(obj).to_string(),
            EventFormat::Human => human_line(&obj),
        };
        let mut out = std::io::stdout().lock();
        if writeln!(out, "{line}").and_then(|()| out.flush()).is_err() {
            // Stdout closed (`| head`): the run stops (see `Output::is_broken`).
            self.broken.store(true, Ordering::Relaxed);
        }
    }

    /// Events are JSON lines.
    #[must_use]
    pub fn is_json(&self) -> bool {
        self.inner
            .lock()
            .is_ok_and(|i| i.format == EventFormat::Json)
    }

    /// Stdout could not be written (closed): the run should stop.
    #[must_use]
    pub fn is_broken(&self) -> bool {
        self.broken.load(Ordering::Relaxed)
    }

    /// Shows `text` as the status line on stderr (replacing the previous one).
    pub fn status(&self, text: &str) {
        let Ok(mut inner) = self.inner.lock() else {
            return;
        };
        let mut err = std::io::stderr().lock();
        let _ = write!(err, "\r\x1b[2K{text}");
        let _ = err.flush();
        inner.status_shown = true;
    }

    /// Removes the status line.
    pub fn clear_status(&self) {
        let Ok(mut inner) = self.inner.lock() else {
            return;
        };
        if inner.status_shown {
            let mut err = std::io::stderr().lock();
            let _ = write!(err, "\r\x1b[2K");
            let _ = err.flush();
            inner.status_shown = false;
        }
    }
}

/// Whether a status line belongs on stderr: stderr is a terminal (whether the events go
/// to the same terminal or to a pipe).
#[must_use]
pub fn wants_status_line() -> bool {
    std::io::stderr().is_terminal()
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn objects_start_with_time_and_name() {
        let o = event_object(12, EventName::TimeSync, json!({"utc_ms": 5, "event": "x"}));
        let keys: Vec<&str> = o.keys().map(String::as_str).collect();
        assert_eq!(keys, ["t_us", "event", "utc_ms"]);
        assert_eq!(o["event"], "time_sync");
        let o = event_object(1, EventName::Counters, json!(3));
        assert_eq!(o["value"], 3);
    }

    #[test]
    fn human_lines() {
        let o = event_object(
            12_345_678,
            EventName::TimeSync,
            json!({"utc_ms": 1_795_428_040_000u64, "edge_us": 3}),
        );
        assert_eq!(
            human_line(&o),
            "    12.345678 time_sync        utc_ms=1795428040000 edge_us=3 (2026-11-23T10:00:40.000Z)"
        );
        let o = event_object(
            0,
            EventName::PodRefused,
            json!({"base": 16, "code": {"name": "Busy", "code": 2}, "port": "pod"}),
        );
        assert_eq!(
            human_line(&o),
            "     0.000000 pod_refused      base=16 code=Busy(0x02) port=pod"
        );
    }

    #[test]
    fn iso_dates() {
        assert_eq!(iso_utc(0), "1970-01-01T00:00:00.000Z");
        assert_eq!(iso_utc(951_782_400_123), "2000-02-29T00:00:00.123Z");
        assert_eq!(iso_utc(1_795_428_040_000), "2026-11-23T10:00:40.000Z");
    }
}
