//! A task bench's run ([`Outcome`]) as the bridge's JSON event log: the tasks' records
//! through the mapping `gimbal bridge --events json` uses ([`events::record_event`]), the
//! fixes and counters sampled while it ran (as the bridge logs them), and what the
//! simulators observed (`sim_fc_health`, `sim_pod_*`, as [`super::watch`] prints them).
//! What `gimbal demo --events json` prints, and what the report's tests read.

use serde_json::{Map, Value, json};

use super::event_name::EventName;
use super::events::{self, FixSampler, LOG_VERSION};
use super::output::event_object;
use super::watch::{pod_gps_reply_fields, pod_photo_fields, pod_sync_fields};
use crate::sim::peer::Peer;
use crate::sim::pilot::Pilot;
use crate::sim::tasks::{Bench, Outcome};

/// A `counters` event every this many µs of the run (as `gimbal bridge --counters-every 10`).
pub const COUNTERS_EVERY_US: u64 = 10_000_000;

/// The events sampled while a bench runs; [`BenchLog::finish`] adds the rest.
#[derive(Debug)]
pub struct BenchLog {
    header: Map<String, Value>,
    fixes: FixSampler,
    next_counters_us: u64,
    sampled: Vec<Map<String, Value>>,
}

impl BenchLog {
    /// A log whose first line is `event` (`demo_started`) with `fields` and the log's
    /// version (`log_version`, `version`).
    #[must_use]
    pub fn new(event: EventName, fields: Value) -> Self {
        let mut header = event_object(0, event, fields);
        header.insert("version".into(), json!(env!("CARGO_PKG_VERSION")));
        header.insert("log_version".into(), json!(LOG_VERSION));
        BenchLog {
            header,
            fixes: FixSampler::default(),
            next_counters_us: COUNTERS_EVERY_US,
            sampled: Vec::new(),
        }
    }

    /// Samples the engine at `now_us` (call it from the bench's script): its newest fix
    /// (a `fix` event at most once a second) and its counters every
    /// [`COUNTERS_EVERY_US`].
    pub fn sample<P: Pilot, T: Peer>(&mut self, bench: &Bench<P, T>, now_us: u64) {
        if let Some((t, name, fields)) = self.fixes.take(bench.engine(|e| e.latest_fix())) {
            self.sampled.push(event_object(t, name, fields));
        }
        if now_us >= self.next_counters_us {
            let c = bench.engine(|e| e.counters());
            self.sampled.push(event_object(
                now_us,
                EventName::Counters,
                events::counters(&c),
            ));
            self.next_counters_us = now_us.saturating_add(COUNTERS_EVERY_US);
        }
    }

    /// The whole log, in time order: the header, every record, the samples, the
    /// simulators' observations, then `stopped` and the final `counters`. Each
    /// `time_sync` gets `error_us` (the UTC it carried minus the truth at its edge, µs)
    /// where `sync_error_ns(edge_us, utc_ms)` knows it.
    #[must_use]
    pub fn finish<P: Pilot, T>(
        self,
        o: &Outcome<P, T>,
        sync_error_ns: impl Fn(u64, u64) -> Option<i128>,
    ) -> Vec<Map<String, Value>> {
        let mut lines: Vec<Map<String, Value>> = self.sampled;
        for r in &o.records {
            let (t, name, fields) = events::record_event(r);
            let mut obj = event_object(t, name, fields);
            if name == EventName::TimeSync
                && let (Some(edge), Some(utc)) = (
                    obj.get("edge_us").and_then(Value::as_u64),
                    obj.get("utc_ms").and_then(Value::as_u64),
                )
                && let Some(ns) = sync_error_ns(edge, utc)
            {
                // The error as µs with ns digits (an f64 holds them exactly here).
                #[allow(clippy::cast_precision_loss)]
                let us = ns as f64 / 1000.0;
                obj.insert("error_us".into(), json!(us));
            }
            lines.push(obj);
        }
        for &(t, healthy) in o.fc.health_log() {
            lines.push(event_object(
                t,
                EventName::SimFcHealth,
                json!({"healthy": healthy}),
            ));
        }
        for (i, &t) in o.pod.boots().iter().enumerate() {
            lines.push(event_object(
                t,
                EventName::SimPodBoot,
                json!({"boot": i + 1}),
            ));
        }
        for s in o.pod.syncs() {
            lines.push(event_object(
                s.arrival_us,
                EventName::SimPodSync,
                pod_sync_fields(s),
            ));
        }
        for p in o.pod.photos() {
            lines.push(event_object(
                p.at_us,
                EventName::SimPodPhoto,
                pod_photo_fields(p),
            ));
        }
        for r in o.pod.gps_replies() {
            lines.push(event_object(
                r.at_us,
                EventName::SimPodGpsReply,
                pod_gps_reply_fields(r),
            ));
        }
        let at = |m: &Map<String, Value>| m.get("t_us").and_then(Value::as_u64).unwrap_or(0);
        lines.sort_by_key(at);
        let end = o.end_us;
        #[allow(clippy::cast_precision_loss)]
        let seconds = end as f64 / 1e6;
        lines.push(event_object(
            end,
            EventName::Stopped,
            json!({"reason": "seconds_elapsed", "seconds": seconds}),
        ));
        lines.push(event_object(
            end,
            EventName::Counters,
            events::counters(&o.engine.counters()),
        ));
        let mut all = Vec::with_capacity(lines.len().saturating_add(1));
        all.push(self.header);
        all.extend(lines);
        all
    }
}

/// The lines as text: one JSON object per line.
#[must_use]
pub fn to_text(lines: &[Map<String, Value>]) -> String {
    let mut s = String::new();
    for l in lines {
        s.push_str(&Value::Object(l.clone()).to_string());
        s.push('\n');
    }
    s
}
