//! Scenarios of the bridge engine (simulated lines and clocks, [`Scenario`]), written once
//! for any FC side ([`Pilot`]); each `bridge_<side>.rs` runs them with its side's setup
//! and bounds and keeps the scenarios that are its own.
//!
//! The shared scenarios: the FC's driver healthy and staying so, the pod stopped when
//! the FC falls silent, the pod lost then back (the driver unhealthy then healthy), time
//! syncs (one per RTC_IO edge, applied, on the 10 s grid, their error against the FC's
//! true UTC, over whole flights), a photo geotagged where the aircraft was, damage on
//! both lines seen and counted.
#![allow(dead_code)]

use bridge_engine::{Config, Counters, Event, Level};
use gimbal::sim::pilot::Pilot;
use gimbal::sim::pod::{PodSimConfig, SimPod, SyncOutcome};
use gimbal::sim::scenario::Scenario;
use protocol_core::k40t::{AckCode, ContinuousZoom, GpsReply, ZoomControl};

/// One second, µs.
pub const S: u64 = 1_000_000;
/// One millisecond, µs.
pub const MS: u64 = 1_000;

/// The engine configured for `F`'s side between `fc` and a pod with `pod`, the bridge's
/// clock `bridge_ppm` fast.
pub fn scenario<F: Pilot>(fc: F, pod: PodSimConfig, bridge_ppm: i64) -> Scenario<F> {
    scenario_with(Config::for_fc(F::PROTOCOL), fc, pod, bridge_ppm)
}

/// [`scenario`] with the bridge configured as `config`.
pub fn scenario_with<F: Pilot>(
    config: Config,
    fc: F,
    pod: PodSimConfig,
    bridge_ppm: i64,
) -> Scenario<F> {
    Scenario::new(config, fc, SimPod::new(pod), bridge_ppm)
}

/// `s` run to `until_us`, when the FC's driver calls the mount healthy.
pub fn healthy<F: Pilot>(mut s: Scenario<F>, until_us: u64) -> Scenario<F> {
    s.run_until(until_us);
    assert!(s.fc.healthy(), "health log {:?}", s.fc.health_log());
    s
}

/// The first change of the driver's health: healthy, before `within_us`.
pub fn healthy_within<F: Pilot>(s: &Scenario<F>, within_us: u64) {
    let (t, up) = s.fc.health_log()[0];
    assert!(up);
    assert!(t < within_us, "healthy at {} ms", t / MS);
}

/// Run on to `until_us`: the driver never changed its mind (one entry in its log).
pub fn stays_healthy<F: Pilot>(s: &mut Scenario<F>, until_us: u64) {
    s.run_until(until_us);
    assert_eq!(s.fc.health_log().len(), 1, "{:?}", s.fc.health_log());
}

/// How the FC falls silent.
#[derive(Debug, Clone, Copy)]
pub enum Silence {
    /// Its cable cut for good.
    CableCut,
    /// Its cable pulled out for this long, µs.
    CablePulled(u64),
}

/// The FC falls silent while the pod pans (the side set the pan going): after `pan_us`
/// the pod turns faster than `min_rate_dps`; after the silence the bridge stops it
/// within `within_us` (a 0x000010 stopping both axes). With `stopped_once`, the pod
/// holds still and the engine reported one `FcSilenceStop`. Returns the instants of the
/// silence and of the stop.
pub fn pod_stops_when_the_fc_falls_silent<F: Pilot>(
    s: &mut Scenario<F>,
    pan_us: u64,
    min_rate_dps: f64,
    silence: Silence,
    within_us: u64,
    stopped_once: bool,
) -> (u64, u64) {
    s.run_for(pan_us);
    assert!(s.pod.gimbal().yaw_rate_dps > min_rate_dps);
    let cut = s.now_us;
    match silence {
        Silence::CableCut => s.fc_cut = true,
        Silence::CablePulled(us) => s.pull_fc_cable(us),
    }
    s.run_for(2 * S);
    let stop = s.pod.first_stop_after(cut).expect("a stop");
    assert!(
        stop - cut <= within_us,
        "stopped {} ms after the cut",
        (stop - cut) / MS
    );
    if stopped_once {
        assert_eq!(s.pod.gimbal().yaw_rate_dps, 0.0);
        assert_eq!(s.events_where(|e| *e == Event::FcSilenceStop).len(), 1);
    }
    (cut, stop)
}

/// The FC turns the pod right at 20°/s, then its cable is cut: the bridge stops the pod
/// within 0.6 s (the FC's last frame came up to one of its updates before the cut; the
/// bridge waits 0.5 s), once.
pub fn fc_silence_stops_the_turning_pod<F: Pilot>(s: &mut Scenario<F>) {
    s.fc.turn(20.0, 0.0);
    pod_stops_when_the_fc_falls_silent(s, 2 * S, 0.0, Silence::CableCut, 600 * MS, true);
}

/// The FC zooms in for 1.5 s, then stops: the pod's continuous zooms, in order.
pub fn zoom_in_then_stop<F: Pilot>(s: &mut Scenario<F>) -> Vec<ZoomControl> {
    s.fc.zoom(1);
    s.run_for(S + S / 2);
    s.fc.zoom(0);
    s.run_for(S);
    s.pod
        .received_of::<ContinuousZoom>()
        .into_iter()
        .map(|(_, _, z)| z.control)
        .collect()
}

/// The first change of the driver's health to `healthy` after `after_us`.
pub fn health_change_after<F: Pilot>(s: &Scenario<F>, after_us: u64, healthy: bool) -> u64 {
    s.fc.health_log()
        .iter()
        .find(|(t, h)| *t > after_us && *h == healthy)
        .unwrap_or_else(|| panic!("no change to {healthy} after {after_us} us"))
        .0
}

/// The pod falls silent for 4 s: the driver calls the mount unhealthy within
/// `down_within_us` and the engine says the pod link is down; `while_lost` checks the
/// side's own; the pod speaks again: healthy within `up_within_us` of it, in a run of
/// `back_run_us`.
pub fn pod_loss_then_recovery<F: Pilot>(
    s: &mut Scenario<F>,
    down_within_us: u64,
    back_run_us: u64,
    up_within_us: u64,
    while_lost: impl FnOnce(&mut Scenario<F>),
) {
    s.pod.set_silent(true);
    let cut = s.now_us;
    s.run_for(4 * S);
    let down = health_change_after(s, cut, false);
    assert!(down - cut <= down_within_us, "{} ms", (down - cut) / MS);
    assert!(!s.engine.pod_state().link);
    while_lost(s);
    s.pod.set_silent(false);
    let back = s.now_us;
    s.run_for(back_run_us);
    let up = health_change_after(s, back, true);
    assert!(up - back <= up_within_us, "{} ms", (up - back) / MS);
}

/// The rising RTC_IO edges so far, one 0x00030E applied by the pod for each (the syncs
/// and the edges paired in order).
pub fn one_sync_per_edge<F: Pilot>(s: &Scenario<F>) -> usize {
    let highs = s
        .pin_edges
        .iter()
        .filter(|e| e.level == Level::High)
        .count();
    assert_eq!(s.pod.syncs().len(), highs, "one 0x00030E per edge");
    highs
}

/// The error of each time sync from `warmup_us` on: the UTC of the 0x00030E the pod
/// applied (on the 10 s grid) less the FC's true UTC at its edge's true instant, µs.
pub fn sync_errors_us<F: Pilot>(s: &Scenario<F>, warmup_us: u64) -> Vec<i64> {
    s.pin_edges
        .iter()
        .filter(|e| e.level == Level::High)
        .zip(s.pod.syncs())
        .filter(|(e, _)| e.at_us >= warmup_us)
        .map(|(e, sync)| {
            assert_eq!(sync.outcome, SyncOutcome::Applied, "{sync:?}");
            assert_eq!(sync.unix_ms % 10_000, 0, "on the 10 s grid");
            sync.unix_ms as i64 * 1000 - s.fc.true_utc_us(e.at_us) as i64
        })
        .collect()
}

/// The `q` quantile of sorted values.
pub fn quantile<T: Copy>(sorted: &[T], q: f64) -> T {
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

/// |errors| sorted, µs, printed as `label: n edges, p50, p99, max`.
pub fn figures(label: &str, errors_us: &[i64]) -> Vec<u64> {
    let mut abs: Vec<u64> = errors_us.iter().map(|e| e.unsigned_abs()).collect();
    abs.sort_unstable();
    println!(
        "{label}: {} edges, p50 {} us, p99 {} us, max {} us",
        abs.len(),
        quantile(&abs, 0.5),
        quantile(&abs, 0.99),
        abs[abs.len() - 1]
    );
    abs
}

/// The photo just taken (its 0x000302 on its way): within 2 s the pod asks for its
/// position and gets it, OK, where the aircraft was at the shot (within 0.5 m: 1e-7°
/// is 1.1 cm of latitude at 8 m/s) and heading 45°; the engine counts one geotag.
/// Returns the reply and the shot's instant, for the side's own fields.
pub fn one_photo_geotagged<F: Pilot>(s: &mut Scenario<F>) -> (GpsReply, u64) {
    s.run_for(2 * S);
    let replies = s.pod.gps_replies();
    assert_eq!(replies.len(), 1, "{replies:?}");
    let r = replies[0].reply;
    assert_eq!(r.code.code(), AckCode::Ok);
    let photo_t = s.pod.photos()[0].at_us;
    let (lat, lon) = s.fc.aircraft().position_e7(photo_t);
    assert!((r.lat_e7 - lat).abs() < 50, "{} vs {lat}", r.lat_e7);
    assert!((r.lon_e7 - lon).abs() < 70, "{} vs {lon}", r.lon_e7);
    assert_eq!(r.yaw_cdeg, 4500);
    assert_eq!(s.engine.counters().geotags, 1);
    (r, photo_t)
}

/// Damage on both lines into the bridge since `before` was seen and counted: rejected
/// candidates or garbage from the FC, rejected candidates and garbage from the pod.
pub fn damage_counted(before: &Counters, after: &Counters) {
    let c = after;
    assert!(c.fc_rejected + c.fc_garbage_bytes > before.fc_rejected + before.fc_garbage_bytes);
    assert!(c.pod_rejected > before.pod_rejected, "{c:?}");
    assert!(c.pod_garbage_bytes > before.pod_garbage_bytes);
}

/// Reproducible noise for damaged lines (xorshift64).
pub struct Noise(pub u64);

impl Noise {
    /// The next value.
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// True with probability `per_million` / 1 000 000.
    pub fn chance(&mut self, per_million: u64) -> bool {
        self.next() % 1_000_000 < per_million
    }

    /// `n` random bytes.
    pub fn bytes(&mut self, n: usize) -> Vec<u8> {
        (0..n).map(|_| self.next() as u8).collect()
    }
}
