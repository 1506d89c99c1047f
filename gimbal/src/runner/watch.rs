//! What the simulators observed, as events: each watcher remembers how much of a
//! simulator's logs it has printed and prints the rest.

use protocol_core::k40t::AckCode;
use serde_json::{Value, json};

use super::event_name::EventName;
use super::output::Output;
use super::simfc::AnyFc;
use crate::sim::pod::{GpsReplyRecord, PhotoRecord, SimPod, SyncOutcome, SyncRecord};

/// snake_case name of a sync outcome.
#[must_use]
pub const fn outcome_name(o: SyncOutcome) -> &'static str {
    match o {
        SyncOutcome::Applied => "applied",
        SyncOutcome::NoEdge => "no_edge",
        SyncOutcome::EdgeTooOld => "edge_too_old",
        SyncOutcome::EdgeAfterFrameStart => "edge_after_frame_start",
    }
}

/// A 0x00030E the simulated pod handled, as a `sim_pod_sync` event's fields.
#[must_use]
pub fn pod_sync_fields(s: &SyncRecord) -> Value {
    json!({"utc_ms": s.unix_ms, "outcome": outcome_name(s.outcome),
           "edge_to_frame_us": s.delay_us})
}

/// A photo the simulated pod took, as a `sim_pod_photo` event's fields.
#[must_use]
pub fn pod_photo_fields(p: &PhotoRecord) -> Value {
    json!({"pod_utc_ms": p.pod_unix_ms, "shot": p.shot})
}

/// A GPS reply the simulated pod got, as a `sim_pod_gps_reply` event's fields.
#[must_use]
pub fn pod_gps_reply_fields(r: &GpsReplyRecord) -> Value {
    json!({"code": format!("{:?}", r.reply.code.code()),
           "time_matches": r.time_matches, "latency_us": r.latency_us})
}

/// The simulated FC's health changes (`sim_fc_health`).
#[derive(Debug, Default)]
pub struct FcWatcher {
    healthy: bool,
    /// Times the driver became healthy.
    pub became_healthy: u32,
    /// Pictures taken.
    pub photos: u32,
}

impl FcWatcher {
    /// Prints a `sim_fc_health` event when health changed.
    pub fn check(&mut self, fc: &AnyFc, now_us: u64, out: &Output) {
        let h = fc.healthy(now_us);
        if h != self.healthy {
            self.healthy = h;
            self.became_healthy += u32::from(h);
            out.emit(EventName::SimFcHealth, json!({"healthy": h}));
        }
    }

    /// Takes a picture and prints `sim_fc_photo`.
    pub fn photo(&mut self, fc: &mut AnyFc, out: &Output) {
        let taken = fc.take_picture();
        self.photos += u32::from(taken);
        out.emit(EventName::SimFcPhoto, json!({"sent": taken}));
    }

    /// The summary fields.
    #[must_use]
    pub fn summary(&self, fc: &AnyFc, now_us: u64) -> Value {
        let mut s = fc.summary(now_us);
        s["became_healthy"] = json!(self.became_healthy);
        s["photos"] = json!(self.photos);
        s
    }
}

/// The simulated pod's syncs, photos and GPS replies (`sim_pod_sync`,
/// `sim_pod_photo`, `sim_pod_gps_reply`).
#[derive(Debug, Default)]
pub struct PodWatcher {
    syncs: usize,
    photos: usize,
    replies: usize,
}

impl PodWatcher {
    /// Prints what is new.
    pub fn check(&mut self, pod: &SimPod, out: &Output) {
        for s in pod.syncs().get(self.syncs..).unwrap_or_default() {
            out.emit(EventName::SimPodSync, pod_sync_fields(s));
        }
        self.syncs = pod.syncs().len();
        for p in pod.photos().get(self.photos..).unwrap_or_default() {
            out.emit(EventName::SimPodPhoto, pod_photo_fields(p));
        }
        self.photos = pod.photos().len();
        for r in pod.gps_replies().get(self.replies..).unwrap_or_default() {
            out.emit(EventName::SimPodGpsReply, pod_gps_reply_fields(r));
        }
        self.replies = pod.gps_replies().len();
    }

    /// The summary fields.
    #[must_use]
    pub fn summary(pod: &SimPod) -> Value {
        let applied = pod
            .syncs()
            .iter()
            .filter(|s| s.outcome == SyncOutcome::Applied)
            .count();
        let geotags = pod
            .gps_replies()
            .iter()
            .filter(|r| r.reply.code.code() == AckCode::Ok)
            .count();
        json!({
            "syncs": pod.syncs().len(),
            "syncs_applied": applied,
            "photos": pod.photos().len(),
            "geotags": geotags,
        })
    }
}
