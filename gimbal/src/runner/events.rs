//! The bridge's log records as events: one name and a flat set of fields per engine
//! [`Event`] and per task record ([`LogKind`]). The match is exhaustive on purpose: a new
//! event of the engine does not compile until it has a name here, and a name is an
//! [`EventName`], which the book's event table (docs/src/linux-bridge.md) is checked
//! against.

use bridge_engine::fixes::Fix;
use bridge_engine::{Counters, Event, Refusal, SettingSource};
use bridge_fw::{Heartbeat, Level, LogKind, LogRecord, Port};
use protocol_core::k40t::{Address, CrcCoverage};
use serde_json::{Value, json};

use super::event_name::EventName;

/// The version of the JSON event log, in the first line's `log_version`
/// (`bridge_started`, `demo_started`): 1 is the log with `fix` events. A reader
/// (`gimbal report`) warns on another version and reads what it knows.
pub const LOG_VERSION: u64 = 1;

/// At most one `fix` event in this many µs (the track of the flight, not every fix).
pub const FIX_EVERY_US: u64 = 1_000_000;

/// The aircraft's newest fix as a `fix` event: its time (the fix's own local instant,
/// µs), name and fields (`lat_e7`, `lon_e7`, `alt_msl_dm`, `rel_alt_dm`, `yaw_cdeg`).
#[must_use]
pub fn fix_event(f: &Fix) -> (u64, EventName, Value) {
    (
        f.at.as_micros(),
        EventName::Fix,
        json!({"lat_e7": f.lat_e7, "lon_e7": f.lon_e7, "alt_msl_dm": f.alt_msl_dm,
               "rel_alt_dm": f.rel_alt_dm, "yaw_cdeg": f.yaw_cdeg}),
    )
}

/// Picks the fixes worth a `fix` event: a fix at least [`FIX_EVERY_US`] after the last
/// one logged (the first one at once).
#[derive(Debug, Default, Clone, Copy)]
pub struct FixSampler {
    last_us: Option<u64>,
}

impl FixSampler {
    /// The `fix` event for the engine's newest fix, when it is due.
    pub fn take(&mut self, newest: Option<Fix>) -> Option<(u64, EventName, Value)> {
        let f = newest?;
        let at = f.at.as_micros();
        if self
            .last_us
            .is_some_and(|last| at < last.saturating_add(FIX_EVERY_US))
        {
            return None;
        }
        self.last_us = Some(at);
        Some(fix_event(&f))
    }
}

/// `fc` or `pod`.
#[must_use]
pub const fn port_name(p: Port) -> &'static str {
    match p {
        Port::Fc => "fc",
        Port::Pod => "pod",
        Port::Telemetry => "telemetry",
    }
}

/// `high` or `low`.
#[must_use]
pub const fn level_name(l: Level) -> &'static str {
    match l {
        Level::High => "high",
        Level::Low => "low",
    }
}

fn refusal_name(r: Refusal) -> &'static str {
    match r {
        Refusal::BadSignature => "bad_signature",
        Refusal::Replayed => "replayed",
        Refusal::Stale => "stale",
        Refusal::Unsigned => "unsigned",
        Refusal::Sender => "sender",
        Refusal::Guarded => "guarded",
    }
}

fn address(a: Address) -> String {
    format!("{:02x}:{:02x}", a.system, a.component)
}

/// An engine event: its name and fields.
#[must_use]
pub fn engine_event(e: &Event) -> (EventName, Value) {
    match *e {
        Event::FcLinkUp => (EventName::FcLinkUp, json!({})),
        Event::FcLinkDown => (EventName::FcLinkDown, json!({})),
        Event::PodLinkUp => (EventName::PodLinkUp, json!({})),
        Event::PodLinkDown => (EventName::PodLinkDown, json!({})),
        Event::UtcValid {
            error_bound_us,
            converged,
        } => (
            EventName::UtcValid,
            json!({"error_bound_us": error_bound_us, "converged": converged}),
        ),
        Event::UtcLost => (EventName::UtcLost, json!({})),
        Event::TimeSource { telemetry } => (
            EventName::TimeSource,
            json!({"source": if telemetry { "telemetry" } else { "fc" }}),
        ),
        Event::TimeSync {
            edge,
            utc_ms,
            error_bound_us,
        } => (
            EventName::TimeSync,
            json!({"utc_ms": utc_ms, "edge_us": edge.as_micros(), "error_bound_us": error_bound_us}),
        ),
        Event::Geotag {
            time_of_day_ms,
            missed: None,
        } => (
            EventName::Geotag,
            json!({"time_of_day_ms": time_of_day_ms, "answered": true}),
        ),
        Event::Geotag {
            time_of_day_ms,
            missed: Some(why),
        } => (
            EventName::Geotag,
            json!({"time_of_day_ms": time_of_day_ms, "answered": false, "reason": why.name()}),
        ),
        Event::Photo(p) => (
            EventName::Photo,
            serde_json::to_value(p).unwrap_or(Value::Null),
        ),
        Event::PpsLocked { first_edge } => (
            EventName::PpsLocked,
            json!({"first_edge_us": first_edge.as_micros()}),
        ),
        Event::PpsHoldover => (EventName::PpsHoldover, json!({})),
        Event::PpsReleased => (EventName::PpsReleased, json!({})),
        Event::Translated { fc_id, pod_base } => (
            EventName::Translated,
            json!({"fc_id": fc_id, "pod_id": format!("0x{pod_base:06x}")}),
        ),
        Event::PodRefused { base, code } => (
            EventName::PodRefused,
            json!({"pod_id": format!("0x{base:06x}"), "code": serde_json::to_value(code).unwrap_or(Value::Null)}),
        ),
        Event::PodTimeout { base } => (
            EventName::PodTimeout,
            json!({"pod_id": format!("0x{base:06x}")}),
        ),
        Event::FcSilenceStop => (EventName::FcSilenceStop, json!({})),
        Event::NoTimeOrFixes { port } => (
            EventName::NoTimeOrFixes,
            json!({"port": port_name(port),
                   "remedy": "the autopilot's link gives no time and no position (PX4 1.16 in mode Gimbal): set it to mode Normal (PX4 MAV_n_MODE 0) or connect the autopilot's telemetry link"}),
        ),
        Event::RateClamped { requested_cdeg_s } => (
            EventName::RateClamped,
            json!({"requested_cdeg_s": requested_cdeg_s}),
        ),
        Event::PodAddresses { gimbal, camera } => (
            EventName::PodAddresses,
            json!({"gimbal": address(gimbal), "camera": address(camera)}),
        ),
        Event::PodCoverage(c) => (
            EventName::PodCoverage,
            json!({"crc": match c {
                CrcCoverage::IncludeStx => "include-stx",
                CrcCoverage::ExcludeStx => "exclude-stx",
            }}),
        ),
        Event::DestructiveDenied { command } => (
            EventName::DestructiveDenied,
            json!({"command": command, "key": "mavlink.allow_destructive"}),
        ),
        Event::PodIp {
            address: [a, b, c, d],
        } => (
            EventName::PodIp,
            json!({"address": format!("{a}.{b}.{c}.{d}")}),
        ),
        Event::Declined { fc_id, reason } => (
            EventName::Declined,
            json!({"fc_id": fc_id, "reason": reason.name()}),
        ),
        Event::Refused {
            port,
            reason,
            id,
            sender,
        } => (
            EventName::Refused,
            json!({"port": port_name(port), "reason": refusal_name(reason), "id": id, "sender": sender}),
        ),
        Event::SigningKeyChanged { port, on } => (
            EventName::SigningKeyChanged,
            json!({"port": port_name(port), "on": on}),
        ),
        Event::OtherAutopilot { port, sysid } => (
            EventName::OtherAutopilot,
            json!({"port": port_name(port), "sysid": sysid}),
        ),
        Event::StoreRecord { key, problem } => (
            EventName::StoreRecord,
            json!({"key": format!("0x{key:04x}"), "problem": problem.name()}),
        ),
        Event::Setting {
            key,
            source,
            outcome,
        } => (
            EventName::Setting,
            json!({
                "key": bridge_engine::settings::table::by_record(key).map_or("*", |s| s.key),
                "source": match source {
                    SettingSource::Console => "console",
                    SettingSource::Parameter(port) => port_name(port),
                },
                "outcome": outcome.name(),
            }),
        ),
        Event::Dropped { port, frames } => (
            EventName::Dropped,
            json!({"port": port_name(port), "frames": frames}),
        ),
    }
}

/// The loops a [`Heartbeat`] names.
#[must_use]
pub fn loops(h: Heartbeat) -> Vec<&'static str> {
    [
        (Heartbeat::ENGINE, "engine"),
        (Heartbeat::FC_RX, "fc_rx"),
        (Heartbeat::FC_TX, "fc_tx"),
        (Heartbeat::POD_RX, "pod_rx"),
        (Heartbeat::POD_TX, "pod_tx"),
        (Heartbeat::TEL_RX, "telemetry_rx"),
        (Heartbeat::TEL_TX, "telemetry_tx"),
    ]
    .into_iter()
    .filter(|(bit, _)| h.0 & bit.0 != 0)
    .map(|(_, name)| name)
    .collect()
}

/// A record of the bridge's tasks: its time (µs), name and fields.
#[must_use]
pub fn record_event(r: &LogRecord) -> (u64, EventName, Value) {
    let (name, fields) = match r.what {
        LogKind::Engine(e) => engine_event(&e),
        LogKind::Pin(l) => (EventName::RtcIo, json!({"level": level_name(l)})),
        LogKind::PinError(l) => (EventName::RtcIoError, json!({"level": level_name(l)})),
        LogKind::EdgeToFrame { delay, len } => (
            EventName::EdgeToFrame,
            json!({"delay_us": delay.as_micros(), "len": len}),
        ),
        LogKind::ReadError(p) => (EventName::ReadError, json!({"port": port_name(p)})),
        LogKind::WriteError(p) => (EventName::WriteError, json!({"port": port_name(p)})),
        LogKind::Stalled(h) => (EventName::Stalled, json!({"loops": loops(h)})),
        LogKind::StoreError(key) => (
            EventName::StoreError,
            json!({"key": format!("0x{key:04x}")}),
        ),
        // The update port is the board's (the Linux bridge has none), so a host log
        // only shows these in a test; their fields are serde's.
        LogKind::Update(u) => (
            EventName::Update,
            serde_json::to_value(u).unwrap_or(Value::Null),
        ),
    };
    (r.at.as_micros(), name, fields)
}

/// The engine's counters as event fields.
#[must_use]
pub fn counters(c: &Counters) -> Value {
    serde_json::to_value(c).unwrap_or(Value::Null)
}

#[cfg(test)]
mod tests {
    use super::*;
    use bridge_engine::{Duration, GeotagMiss, Instant};
    use protocol_core::k40t::AckCode;

    fn ev(what: LogKind) -> (u64, EventName, Value) {
        record_event(&LogRecord {
            at: Instant::from_micros(42),
            what,
        })
    }

    #[test]
    fn the_required_events_have_their_fields() {
        assert_eq!(
            ev(LogKind::Pin(Level::High)),
            (42, EventName::RtcIo, json!({"level": "high"}))
        );
        assert_eq!(
            ev(LogKind::Pin(Level::Low)),
            (42, EventName::RtcIo, json!({"level": "low"}))
        );
        assert_eq!(
            ev(LogKind::Engine(Event::TimeSync {
                edge: Instant::from_micros(40),
                utc_ms: 1_795_428_040_000,
                error_bound_us: 1_250,
            })),
            (
                42,
                EventName::TimeSync,
                json!({"utc_ms": 1_795_428_040_000u64, "edge_us": 40, "error_bound_us": 1_250})
            )
        );
        assert_eq!(
            ev(LogKind::Engine(Event::UtcValid {
                error_bound_us: 2_100,
                converged: false,
            })),
            (
                42,
                EventName::UtcValid,
                json!({"error_bound_us": 2_100, "converged": false})
            )
        );
        assert_eq!(
            ev(LogKind::Engine(Event::Geotag {
                time_of_day_ms: 36_000_000,
                missed: None
            })),
            (
                42,
                EventName::Geotag,
                json!({"time_of_day_ms": 36_000_000, "answered": true})
            )
        );
        assert_eq!(
            ev(LogKind::Engine(Event::Geotag {
                time_of_day_ms: 36_000_000,
                missed: Some(GeotagMiss::OutOfRange)
            })),
            (
                42,
                EventName::Geotag,
                json!({"time_of_day_ms": 36_000_000, "answered": false, "reason": "out_of_range"})
            )
        );
        for (e, name) in [
            (Event::FcLinkUp, EventName::FcLinkUp),
            (Event::FcLinkDown, EventName::FcLinkDown),
            (Event::PodLinkUp, EventName::PodLinkUp),
            (Event::PodLinkDown, EventName::PodLinkDown),
            (Event::UtcLost, EventName::UtcLost),
            (Event::FcSilenceStop, EventName::FcSilenceStop),
        ] {
            assert_eq!(ev(LogKind::Engine(e)), (42, name, json!({})));
        }
    }

    #[test]
    fn fixes_are_logged_once_a_second() {
        let fix = |us: u64| Fix {
            at: Instant::from_micros(us),
            lat_e7: 473_977_419,
            lon_e7: 85_455_938,
            alt_msl_dm: 4_880,
            rel_alt_dm: 500,
            yaw_cdeg: 1_250,
            roll_cdeg: 0,
            pitch_cdeg: 0,
            velocity: None,
        };
        let mut s = FixSampler::default();
        assert_eq!(s.take(None), None);
        let first = s.take(Some(fix(2_000_000)));
        assert_eq!(
            first,
            Some((
                2_000_000,
                EventName::Fix,
                json!({"lat_e7": 473_977_419, "lon_e7": 85_455_938, "alt_msl_dm": 4_880,
                       "rel_alt_dm": 500, "yaw_cdeg": 1_250})
            ))
        );
        assert_eq!(s.take(Some(fix(2_900_000))), None);
        assert_eq!(s.take(Some(fix(3_000_000))).map(|e| e.0), Some(3_000_000));
    }

    #[test]
    fn the_other_events() {
        assert_eq!(
            ev(LogKind::EdgeToFrame {
                delay: Duration::from_micros(12),
                len: 28
            })
            .2,
            json!({"delay_us": 12, "len": 28})
        );
        assert_eq!(
            ev(LogKind::Stalled(Heartbeat(
                Heartbeat::ENGINE.0 | Heartbeat::POD_TX.0
            )))
            .2,
            json!({"loops": ["engine", "pod_tx"]})
        );
        assert_eq!(ev(LogKind::WriteError(Port::Pod)).2, json!({"port": "pod"}));
        assert_eq!(
            ev(LogKind::Engine(Event::Translated {
                fc_id: 7,
                pod_base: 0x10
            }))
            .2,
            json!({"fc_id": 7, "pod_id": "0x000010"})
        );
        let (_, name, f) = ev(LogKind::Engine(Event::PodRefused {
            base: 0x302,
            code: AckCode::Failure,
        }));
        assert_eq!(name, EventName::PodRefused);
        assert_eq!(f["pod_id"], "0x000302");
        assert_eq!(f["code"]["name"], "Failure");
        assert_eq!(
            ev(LogKind::Engine(Event::PodAddresses {
                gimbal: Address::GIMBAL,
                camera: Address::POD
            }))
            .2,
            json!({"gimbal": "03:01", "camera": "04:01"})
        );
        assert_eq!(
            ev(LogKind::Engine(Event::Dropped {
                port: Port::Fc,
                frames: 2
            })),
            (42, EventName::Dropped, json!({"port": "fc", "frames": 2}))
        );
        let c = counters(&Counters {
            time_syncs: 3,
            ..Counters::default()
        });
        assert_eq!(c["time_syncs"], 3);
        assert_eq!(c["fc_frames"], 0);
    }
}
