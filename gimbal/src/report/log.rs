//! Reading a bridge log: the JSON lines of `gimbal bridge --events json` (or `gimbal demo
//! --events json`) into typed records, each with its line number, and a diagnostic for
//! every line that cannot be read (cut off, not an object, a field missing) or that
//! says something this reader does not know (another log version, an unknown event).
//! Nothing here stops the reading: a bad line is reported and skipped.

use serde_json::{Map, Value};

use crate::runner::event_name::EventName;
use crate::runner::events::LOG_VERSION;

/// A link of the bridge.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Link {
    /// The flight controller's.
    Fc,
    /// The pod's.
    Pod,
    /// The autopilot's telemetry link.
    Telemetry,
}

impl Link {
    /// Every link, in the order drawn.
    pub const ALL: [Link; 3] = [Link::Fc, Link::Pod, Link::Telemetry];

    /// Its name in the events.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Link::Fc => "fc",
            Link::Pod => "pod",
            Link::Telemetry => "telemetry",
        }
    }

    fn of(name: &str) -> Option<Self> {
        Link::ALL.into_iter().find(|l| l.name() == name)
    }
}

/// What one line says, as far as the report uses it.
#[derive(Debug, Clone, PartialEq)]
pub enum Rec {
    /// `fc_link_up`, `pod_link_up`.
    LinkUp(Link),
    /// `fc_link_down`, `pod_link_down`.
    LinkDown(Link),
    /// `port_closed`, `port_error`: a real port lost its connection or device.
    PortLost(Link),
    /// `utc_valid`.
    UtcValid {
        /// The error bound the discipline believes, µs.
        bound_us: u64,
    },
    /// `utc_lost`.
    UtcLost,
    /// `time_source`: the telemetry link (true) or the FC link.
    TimeSource {
        /// The telemetry link is the source.
        telemetry: bool,
    },
    /// `time_sync`.
    TimeSync {
        /// The rising edge, µs of the log's clock.
        edge_us: u64,
        /// The UTC carried, ms since the Unix epoch.
        utc_ms: u64,
        /// The error bound believed, µs.
        bound_us: u64,
        /// The measured error (the demo, the simulators), µs.
        error_us: Option<f64>,
    },
    /// `edge_to_frame`.
    EdgeToFrame {
        /// Edge to the first byte of the 0x00030E, µs.
        delay_us: u64,
    },
    /// `geotag`: the pod asked for a photo's position.
    Geotag {
        /// The time of day asked, ms.
        time_of_day_ms: u64,
        /// A fix was given.
        answered: bool,
        /// Why not (`reason`), when the log says.
        reason: Option<String>,
    },
    /// `photo`: a geotag answered with a fix.
    Photo {
        /// The photo's UTC, µs since the Unix epoch.
        utc_us: u64,
        /// The fix given.
        pos: Pos,
    },
    /// `fix`: the aircraft's position.
    Fix(Pos),
    /// `fc_silence_stop`.
    FcSilenceStop,
    /// `pod_refused` / `pod_timeout`: the pod refused a command or never answered.
    PodRefused {
        /// `"0x000302"`.
        pod_id: String,
        /// The code's name, or `timeout`.
        code: String,
    },
    /// `translated`.
    Translated {
        /// The FC's command id.
        fc_id: u64,
        /// The pod's.
        pod_id: String,
    },
    /// `dropped`, `read_error`, `write_error`, `stalled`, `rtc_io_error`: trouble inside
    /// the bridge.
    Trouble(String),
    /// `counters`.
    Counters(Map<String, Value>),
    /// `stopped`.
    Stopped,
    /// `pps_locked`.
    PpsLocked,
    /// `sim_fc_health`.
    FcHealth(bool),
    /// `sim_pod_boot`.
    PodBoot,
    /// `sim_pod_sync`: the simulated pod's outcome for a sync.
    PodSync {
        /// `applied`, or why not.
        outcome: String,
    },
    /// `sim_pod_photo`.
    PodPhoto,
    /// Another event this reader knows and does not draw.
    Other,
}

/// A position as the events give it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pos {
    /// Latitude, 1e-7 degree.
    pub lat_e7: i64,
    /// Longitude, 1e-7 degree.
    pub lon_e7: i64,
    /// Altitude above mean sea level, 0.1 m.
    pub alt_msl_dm: i64,
}

/// A record: its line, its time (µs of the log's clock) and what it says.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// Line number, from 1.
    pub line: usize,
    /// `t_us`.
    pub t_us: u64,
    /// What it says.
    pub rec: Rec,
}

/// A line that could not be read, or said something unexpected.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Diagnostic {
    /// Line number, from 1.
    pub line: usize,
    /// What is wrong.
    pub text: String,
}

/// An event name this reader does not know: how often, and its first line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Unknown {
    /// The event's name.
    pub name: String,
    /// Its first line.
    pub first_line: usize,
    /// Lines with it.
    pub count: usize,
}

/// The log's first line (`bridge_started`, `demo_started`).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Header {
    /// `bridge_started` or `demo_started`.
    pub event: String,
    /// The FC side.
    pub fc: Option<String>,
    /// The gimbal tool's version that wrote it.
    pub version: Option<String>,
    /// The log's version (none: before version 1).
    pub log_version: Option<u64>,
}

/// A log read.
#[derive(Debug, Clone, Default)]
pub struct Log {
    /// The first line, when it is a start line.
    pub header: Option<Header>,
    /// Every record read, in the order of the lines.
    pub records: Vec<Record>,
    /// Lines not read or not understood.
    pub diagnostics: Vec<Diagnostic>,
    /// Events not known, by first appearance.
    pub unknown: Vec<Unknown>,
    /// Lines in the file (empty ones included).
    pub lines: usize,
}

/// Reads a log's text. Never fails: what cannot be read is a diagnostic.
#[must_use]
pub fn read(text: &str) -> Log {
    let mut log = Log::default();
    let mut first = true;
    for (i, raw) in text.lines().enumerate() {
        let line = i.saturating_add(1);
        log.lines = line;
        let raw = raw.trim();
        if raw.is_empty() {
            continue;
        }
        let obj = match serde_json::from_str::<Value>(raw) {
            Ok(Value::Object(m)) => m,
            Ok(_) => {
                log.diag(line, "not a JSON object".to_string());
                continue;
            }
            Err(e) => {
                let what = if e.is_eof() {
                    "cut off (truncated JSON)"
                } else {
                    "not JSON"
                };
                log.diag(line, format!("{what}: {e}"));
                continue;
            }
        };
        let Some(event) = obj.get("event").and_then(Value::as_str) else {
            log.diag(line, "no \"event\" name".to_string());
            continue;
        };
        let Some(t_us) = obj.get("t_us").and_then(Value::as_u64) else {
            log.diag(line, format!("{event}: no \"t_us\""));
            continue;
        };
        if std::mem::take(&mut first) {
            log.header_of(line, event, &obj);
        }
        match record(event, &obj) {
            Parsed::Rec(rec) => log.records.push(Record { line, t_us, rec }),
            Parsed::Start => {}
            Parsed::Bad(field) => log.diag(line, format!("{event}: no valid \"{field}\"")),
            Parsed::Unknown => log.unknown_event(line, event),
        }
    }
    log
}

impl Log {
    fn diag(&mut self, line: usize, text: String) {
        self.diagnostics.push(Diagnostic { line, text });
    }

    fn unknown_event(&mut self, line: usize, name: &str) {
        match self.unknown.iter_mut().find(|u| u.name == name) {
            Some(u) => u.count = u.count.saturating_add(1),
            None => self.unknown.push(Unknown {
                name: name.to_string(),
                first_line: line,
                count: 1,
            }),
        }
    }

    /// The first line: a start line, with a log version this reader knows.
    fn header_of(&mut self, line: usize, event: &str, obj: &Map<String, Value>) {
        if event != "bridge_started" && event != "demo_started" {
            self.diag(
                line,
                format!(
                    "the log starts with `{event}`, not `bridge_started`: its beginning is missing (version unknown)"
                ),
            );
            return;
        }
        let text = |k: &str| obj.get(k).and_then(Value::as_str).map(str::to_string);
        let log_version = obj.get("log_version").and_then(Value::as_u64);
        match log_version {
            Some(LOG_VERSION) => {}
            Some(v) => self.diag(
                line,
                format!(
                    "log version {v}, this report reads version {LOG_VERSION}: what it knows is drawn"
                ),
            ),
            None => self.diag(
                line,
                format!(
                    "no log_version: a log from before version {LOG_VERSION} (no `fix` events: no track)"
                ),
            ),
        }
        self.header = Some(Header {
            event: event.to_string(),
            fc: text("fc"),
            version: text("version"),
            log_version,
        });
    }
}

/// What a line is.
enum Parsed {
    Rec(Rec),
    /// A start line (read by [`Log::header_of`]).
    Start,
    /// A known event without this field.
    Bad(&'static str),
    Unknown,
}

fn record(event: &str, o: &Map<String, Value>) -> Parsed {
    let u = |k: &'static str| o.get(k).and_then(Value::as_u64).ok_or(k);
    let i = |k: &'static str| o.get(k).and_then(Value::as_i64).ok_or(k);
    let s = |k: &'static str| o.get(k).and_then(Value::as_str).ok_or(k);
    let b = |k: &'static str| o.get(k).and_then(Value::as_bool).ok_or(k);
    let pos = |alt: &'static str| -> Result<Pos, &'static str> {
        Ok(Pos {
            lat_e7: i("lat_e7")?,
            lon_e7: i("lon_e7")?,
            alt_msl_dm: i(alt)?,
        })
    };
    let link = || s("port").ok().and_then(Link::of).ok_or("port");
    let rec: Result<Rec, &'static str> = match event {
        "bridge_started" | "demo_started" => return Parsed::Start,
        "fc_link_up" => Ok(Rec::LinkUp(Link::Fc)),
        "fc_link_down" => Ok(Rec::LinkDown(Link::Fc)),
        "pod_link_up" => Ok(Rec::LinkUp(Link::Pod)),
        "pod_link_down" => Ok(Rec::LinkDown(Link::Pod)),
        // The RTC_IO and PPS ports have no link of their own.
        "port_closed" | "port_error" => match s("port") {
            Ok("rtc_io" | "pps") => Ok(Rec::Other),
            _ => link().map(Rec::PortLost),
        },
        "utc_valid" => u("error_bound_us").map(|bound_us| Rec::UtcValid { bound_us }),
        "utc_lost" => Ok(Rec::UtcLost),
        "time_source" => s("source").map(|src| Rec::TimeSource {
            telemetry: src == "telemetry",
        }),
        "time_sync" => (|| {
            Ok(Rec::TimeSync {
                edge_us: u("edge_us")?,
                utc_ms: u("utc_ms")?,
                bound_us: u("error_bound_us")?,
                error_us: o.get("error_us").and_then(Value::as_f64),
            })
        })(),
        "edge_to_frame" => u("delay_us").map(|delay_us| Rec::EdgeToFrame { delay_us }),
        "geotag" => (|| {
            Ok(Rec::Geotag {
                time_of_day_ms: u("time_of_day_ms")?,
                answered: b("answered")?,
                reason: s("reason").ok().map(str::to_string),
            })
        })(),
        "photo" => (|| {
            Ok(Rec::Photo {
                utc_us: u("utc_us")?,
                pos: pos("alt_msl_dm")?,
            })
        })(),
        "fix" => pos("alt_msl_dm").map(Rec::Fix),
        "fc_silence_stop" => Ok(Rec::FcSilenceStop),
        "pod_refused" => (|| {
            let code = o
                .get("code")
                .and_then(|c| c.get("name"))
                .and_then(Value::as_str)
                .unwrap_or("?");
            Ok(Rec::PodRefused {
                pod_id: s("pod_id")?.to_string(),
                code: code.to_string(),
            })
        })(),
        "pod_timeout" => s("pod_id").map(|p| Rec::PodRefused {
            pod_id: p.to_string(),
            code: "timeout".to_string(),
        }),
        "translated" => (|| {
            Ok(Rec::Translated {
                fc_id: u("fc_id")?,
                pod_id: s("pod_id")?.to_string(),
            })
        })(),
        "dropped" | "read_error" | "write_error" | "stalled" | "rtc_io_error" => {
            let port = o.get("port").and_then(Value::as_str);
            Ok(Rec::Trouble(match port {
                Some(p) => format!("{event} ({p})"),
                None => event.to_string(),
            }))
        }
        "counters" => Ok(Rec::Counters(o.clone())),
        "stopped" => Ok(Rec::Stopped),
        "pps_locked" => Ok(Rec::PpsLocked),
        "sim_fc_health" => b("healthy").map(Rec::FcHealth),
        "sim_pod_boot" => Ok(Rec::PodBoot),
        "sim_pod_sync" => s("outcome").map(|x| Rec::PodSync {
            outcome: x.to_string(),
        }),
        "sim_pod_photo" => Ok(Rec::PodPhoto),
        // Every other event the tool writes is known and not drawn.
        other if EventName::from_name(other).is_some() => Ok(Rec::Other),
        _ => return Parsed::Unknown,
    };
    match rec {
        Ok(r) => Parsed::Rec(r),
        Err(field) => Parsed::Bad(field),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn good_lines_become_records() {
        let log = read(concat!(
            r#"{"t_us":0,"event":"bridge_started","fc":"siyi","version":"0.1.0","log_version":1}"#,
            "\n",
            r#"{"t_us":5,"event":"pod_link_up"}"#,
            "\n\n",
            r#"{"t_us":9,"event":"time_sync","utc_ms":1795428040000,"edge_us":8,"error_bound_us":1250,"error_us":-12.5}"#,
            "\n",
            r#"{"t_us":10,"event":"fix","lat_e7":473977419,"lon_e7":85455938,"alt_msl_dm":4880,"rel_alt_dm":500,"yaw_cdeg":0}"#,
            "\n",
            r#"{"t_us":11,"event":"rtc_io","level":"low"}"#,
        ));
        assert!(log.diagnostics.is_empty(), "{:?}", log.diagnostics);
        assert_eq!(log.lines, 6);
        let h = log.header.expect("header");
        assert_eq!((h.fc.as_deref(), h.log_version), (Some("siyi"), Some(1)));
        assert_eq!(
            log.records
                .iter()
                .map(|r| (r.line, r.t_us))
                .collect::<Vec<_>>(),
            [(2, 5), (4, 9), (5, 10), (6, 11)]
        );
        assert_eq!(log.records[0].rec, Rec::LinkUp(Link::Pod));
        assert_eq!(
            log.records[1].rec,
            Rec::TimeSync {
                edge_us: 8,
                utc_ms: 1_795_428_040_000,
                bound_us: 1250,
                error_us: Some(-12.5)
            }
        );
        assert_eq!(
            log.records[2].rec,
            Rec::Fix(Pos {
                lat_e7: 473_977_419,
                lon_e7: 85_455_938,
                alt_msl_dm: 4880
            })
        );
        assert_eq!(log.records[3].rec, Rec::Other);
    }

    /// Every event the tool writes is known to the reader (drawn, or known and not
    /// drawn): a log of the newest bridge gets no "unknown event" line.
    #[test]
    fn every_event_the_tool_writes_is_known() {
        let text: String = EventName::ALL
            .iter()
            .map(|e| format!("{{\"t_us\":1,\"event\":\"{e}\"}}\n"))
            .collect();
        let log = read(&text);
        assert!(log.unknown.is_empty(), "{:?}", log.unknown);
        assert_eq!(log.lines, EventName::ALL.len());
    }

    #[test]
    fn bad_lines_are_diagnosed_with_their_number() {
        let log = read(concat!(
            r#"{"t_us":0,"event":"bridge_started","fc":"siyi","log_version":7}"#,
            "\n",
            r#"{"t_us":5,"event":"pod_link_up"}"#,
            "\n",
            r#"{"t_us":9,"event":"time_sync","utc_ms":17954"#,
            "\n",
            r#"{"t_us":9,"event":"warp_drive"}"#,
            "\n",
            r#"{"t_us":12,"event":"warp_drive"}"#,
            "\n",
            r#"{"t_us":13,"event":"geotag","answered":true}"#,
            "\n",
            r#"[1,2]"#,
            "\n",
            r#"{"event":"utc_lost"}"#,
            "\n",
            r#"{"t_us":14,"event":"utc_lost"}"#,
        ));
        let lines: Vec<(usize, &str)> = log
            .diagnostics
            .iter()
            .map(|d| (d.line, d.text.as_str()))
            .collect();
        assert_eq!(lines.len(), 5, "{lines:?}");
        assert_eq!(lines[0].0, 1);
        assert!(lines[0].1.starts_with("log version 7"), "{}", lines[0].1);
        assert_eq!(lines[1].0, 3);
        assert!(lines[1].1.starts_with("cut off"), "{}", lines[1].1);
        assert_eq!(lines[2], (6, "geotag: no valid \"time_of_day_ms\""));
        assert_eq!(lines[3], (7, "not a JSON object"));
        assert_eq!(lines[4], (8, "utc_lost: no \"t_us\""));
        assert_eq!(
            log.unknown,
            [Unknown {
                name: "warp_drive".into(),
                first_line: 4,
                count: 2
            }]
        );
        assert_eq!(
            log.records.iter().map(|r| r.line).collect::<Vec<_>>(),
            [2, 9]
        );
    }

    #[test]
    fn a_log_without_its_start_or_version_is_read_all_the_same() {
        let log = read("{\"t_us\":5,\"event\":\"pod_link_up\"}\n");
        assert_eq!(log.diagnostics.len(), 1);
        assert!(log.diagnostics[0].text.contains("beginning is missing"));
        assert_eq!(log.records.len(), 1);
        let log = read("{\"t_us\":0,\"event\":\"bridge_started\",\"fc\":\"gcu\"}\n");
        assert_eq!(log.diagnostics[0].line, 1);
        assert!(log.diagnostics[0].text.starts_with("no log_version"));
        assert_eq!(log.header.and_then(|h| h.fc), Some("gcu".to_string()));
    }
}
