//! Sync accuracy of the time discipline and the sync scheduler against simulated
//! ArduPilot traffic: one-hour flights, every 10 s an RTC_IO edge, error = |UTC stamped at
//! the edge − reference UTC of the edge|. Run with `--nocapture` to see the figures.
//!
//! The world:
//! - True time `t` (µs, f64). The bridge's clock runs at `1 + eb` (eb uniform ±50 ppm per
//!   flight); its `Instant` is the floor of it.
//! - The FC's clock (`micros64`) runs at `1 + efc` (uniform ±50 ppm per flight). Its mount
//!   update runs every 20 ms of FC time plus a loop jitter U(0, 0.5 ms); every value an
//!   update writes is read at that instant. The frames an update writes go out
//!   back-to-back at 115200 baud (86.8 µs/byte) after a jitter U(0, 10 ms) per update (or
//!   per frame, for SIYI's second case); the line is never used by two frames at once.
//! - The FC's UTC is ArduPilot's AP_RTC: `micros64 + shift`, the shift frozen in flight.
//!   For SIYI and Viewlink it is also the reference (the bridge cannot know better); for
//!   GCU the reference is GPS UTC (true time).
//! - The engine reports, as [`Sample::transit`], the serial time of the bytes it received
//!   back-to-back up to the frame's end (it cannot tell two merged bursts apart).
//!
//! Edges are measured from 60 s after the first sample.

use bridge_engine::discipline::{DisciplineConfig, Sample, TimeDiscipline, serial_time};
use bridge_engine::fixes::FixHistory;
use bridge_engine::sync::{SyncEdge, SyncScheduler};
use bridge_engine::time::{Duration, Instant};

/// SplitMix64: small, seeded, deterministic.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
}

const BYTE_US: f64 = 10.0 * 1e6 / 115_200.0;
const FLIGHT_US: f64 = 3_600e6;
const WARMUP_US: f64 = 60e6;
const UPDATE_US: f64 = 20_000.0;

#[derive(Debug, Clone, Copy, PartialEq)]
enum Model {
    /// Viewlink M_AHRS. `fc_utc_is_gps`: the FC's UTC follows GPS exactly (not ArduPilot;
    /// an idealised FC) instead of AP_RTC.
    Viewlink { fc_utc_is_gps: bool },
    /// GCU: GPS fixes at `gps_hz` on GPS-time boundaries, reaching the FC `latency_ms`
    /// after the epoch.
    Gcu { gps_hz: u32, latency_ms: f64 },
    /// SIYI: UTC (0x30) five times at start, time_boot_ms at 10 Hz.
    Siyi { per_frame_jitter: bool },
}

/// Per-flight random constants.
struct Flight {
    eb: f64,
    efc: f64,
    /// Bridge clock at t = 0.
    l0: f64,
    /// FC clock at t = 0.
    f0: f64,
    /// GPS UTC at t = 0.
    u0: f64,
    /// FC UTC − FC clock.
    shift: f64,
}

impl Flight {
    fn new(rng: &mut Rng) -> Self {
        let eb = rng.range(-50e-6, 50e-6);
        let efc = rng.range(-50e-6, 50e-6);
        let u0 = 1_767_225_600e6 + rng.range(0.0, 365.0 * 86_400e6);
        let f0 = rng.range(20e6, 120e6);
        // AP_RTC's shift, set from GPS with some error of its own.
        let shift = u0 - f0 + rng.range(-50e3, 50e3);
        Self {
            eb,
            efc,
            l0: rng.range(1e6, 100e6),
            f0,
            u0,
            shift,
        }
    }

    fn local(&self, t: f64) -> f64 {
        self.l0 + t * (1.0 + self.eb)
    }

    fn t_of_local(&self, l: f64) -> f64 {
        (l - self.l0) / (1.0 + self.eb)
    }

    fn fc(&self, t: f64) -> f64 {
        self.f0 + t * (1.0 + self.efc)
    }

    fn t_of_fc(&self, f: f64) -> f64 {
        (f - self.f0) / (1.0 + self.efc)
    }

    fn gps_utc(&self, t: f64) -> f64 {
        self.u0 + t
    }

    fn fc_utc(&self, t: f64) -> f64 {
        self.fc(t) + self.shift
    }
}

#[derive(Debug, Clone, Copy)]
enum Kind {
    Other,
    /// Direct UTC value (µs), resolution, held.
    Utc(u64, u32, bool),
    /// FC clock, ms.
    FcClock(u32),
    /// SIYI 0x30, µs.
    SiyiUtc(u64),
}

#[derive(Debug, Clone, Copy)]
struct Frame {
    bytes: u32,
    kind: Kind,
}

/// The FC's sender state (ArduPilot drivers' timers).
#[derive(Default)]
struct Sender {
    last_1hz_ms: Option<u64>,
    sent_time: u32,
    last_0d_ms: u64,
    last_15_ms: u64,
    last_att_ms: u64,
}

impl Sender {
    /// Frames written by update `k`, read at true time `t`.
    fn update(&mut self, model: Model, fl: &Flight, k: u64, t: f64, out: &mut Vec<Frame>) {
        out.clear();
        match model {
            Model::Viewlink { fc_utc_is_gps } => {
                if !k.is_multiple_of(5) {
                    return;
                }
                let utc = if fc_utc_is_gps {
                    fl.gps_utc(t)
                } else {
                    fl.fc_utc(t)
                };
                let v = (utc / 10_000.0).floor() as u64 * 10_000;
                out.push(Frame {
                    bytes: 7,
                    kind: Kind::Other,
                });
                out.push(Frame {
                    bytes: 50,
                    kind: Kind::Utc(v, 10_000, false),
                });
                out.push(Frame {
                    bytes: 20,
                    kind: Kind::Other,
                });
            }
            Model::Gcu { gps_hz, latency_ms } => {
                let period = 1e6 / f64::from(gps_hz);
                let epoch = ((fl.gps_utc(t) - latency_ms * 1e3) / period).floor() * period;
                // Whole milliseconds (GPS epochs are).
                let v = (epoch / 1e3).round() as u64 * 1_000;
                out.push(Frame {
                    bytes: 72,
                    kind: Kind::Utc(v, 20_000, true),
                });
            }
            Model::Siyi { .. } => {
                let now_ms = (fl.fc(t) / 1e3).floor() as u64;
                if self.last_1hz_ms.is_none_or(|l| now_ms - l >= 1000) {
                    self.last_1hz_ms = Some(now_ms);
                    out.push(Frame {
                        bytes: 10,
                        kind: Kind::Other,
                    });
                    if self.sent_time < 5 {
                        self.sent_time += 1;
                        out.push(Frame {
                            bytes: 18,
                            kind: Kind::SiyiUtc(fl.fc_utc(t).floor() as u64),
                        });
                    }
                }
                if now_ms - self.last_0d_ms >= 50 {
                    self.last_0d_ms = now_ms;
                    out.push(Frame {
                        bytes: 10,
                        kind: Kind::Other,
                    });
                }
                if now_ms - self.last_15_ms > 100 {
                    self.last_15_ms = now_ms;
                    out.push(Frame {
                        bytes: 10,
                        kind: Kind::Other,
                    });
                }
                if now_ms - self.last_att_ms > 100 {
                    self.last_att_ms = now_ms;
                    let ms = now_ms as u32;
                    out.push(Frame {
                        bytes: 38,
                        kind: Kind::FcClock(ms),
                    });
                    out.push(Frame {
                        bytes: 42,
                        kind: Kind::FcClock(ms),
                    });
                }
                out.push(Frame {
                    bytes: 12,
                    kind: Kind::Other,
                });
            }
        }
    }
}

#[derive(Default)]
struct Stats {
    /// |error| of each measured edge, µs.
    errors: Vec<f64>,
    /// Signed error of each edge, µs.
    signed: Vec<f64>,
    /// Edges expected in the measured span but not fired.
    missed: u32,
    /// Edges fired before the measured span.
    early: u32,
}

impl Stats {
    fn merge(&mut self, o: Stats) {
        self.errors.extend(o.errors);
        self.signed.extend(o.signed);
        self.missed += o.missed;
        self.early += o.early;
    }

    fn quantile(&self, q: f64) -> f64 {
        let mut v = self.errors.clone();
        v.sort_by(f64::total_cmp);
        if v.is_empty() {
            return f64::NAN;
        }
        let i = ((v.len() as f64 - 1.0) * q).round() as usize;
        v[i]
    }

    fn max(&self) -> f64 {
        self.errors.iter().copied().fold(0.0, f64::max)
    }
}

/// One flight; returns the edge errors.
fn fly(model: Model, seed: u64) -> Stats {
    let mut rng = Rng(seed.wrapping_mul(0x2545_F491_4F6C_DD1D) ^ 0x5EED);
    let fl = Flight::new(&mut rng);
    let per_frame = matches!(
        model,
        Model::Siyi {
            per_frame_jitter: true
        }
    );
    let reference = |t: f64| match model {
        Model::Gcu { .. }
        | Model::Viewlink {
            fc_utc_is_gps: true,
        } => fl.gps_utc(t),
        _ => fl.fc_utc(t),
    };
    let mut disc = TimeDiscipline::new(DisciplineConfig::default());
    let mut sched = SyncScheduler::default();
    let lead = sched.config().lead;
    let mut planned: Option<SyncEdge> = None;
    let mut sender = Sender::default();
    let mut frames = Vec::new();
    let mut stats = Stats::default();
    // The FC's first update after t = 0, on its 20 ms grid.
    let first_k = (fl.f0 / UPDATE_US).ceil() as u64;
    let mut line_free = f64::MIN;
    let mut run_start = 0.0;
    let mut first_sample: Option<f64> = None;
    let mut fired_measured = 0u32;
    let mut last_arrival = 0.0;
    for k in first_k.. {
        let f = k as f64 * UPDATE_US + rng.range(0.0, 500.0);
        let t = fl.t_of_fc(f);
        if t > FLIGHT_US {
            break;
        }
        sender.update(model, &fl, k, t, &mut frames);
        let burst_jitter = rng.range(0.0, 10_000.0);
        let mut pending_pair: (Option<u64>, Option<u32>) = (None, None);
        for fr in &frames {
            let ready = t + if per_frame {
                rng.range(0.0, 10_000.0)
            } else {
                burst_jitter
            };
            let start = if ready > line_free {
                run_start = ready;
                ready
            } else {
                line_free
            };
            let end = start + f64::from(fr.bytes) * BYTE_US;
            line_free = end;
            let contiguous_bytes = ((end - run_start) / BYTE_US).round() as u32;
            let local = Instant::from_micros(fl.local(end).floor() as u64);
            last_arrival = end;

            // Fire the planned edge if its time has come.
            if let Some(e) = planned
                && e.at <= local
            {
                sched.fired(&e);
                planned = None;
                let te = fl.t_of_local(e.at.as_micros() as f64);
                let err = e.utc.as_unix_micros() as f64 - reference(te);
                match first_sample {
                    Some(t0) if te >= t0 + WARMUP_US => {
                        stats.errors.push(err.abs());
                        stats.signed.push(err);
                        fired_measured += 1;
                    }
                    _ => stats.early += 1,
                }
            }

            let transit = serial_time(contiguous_bytes, 115_200);
            match fr.kind {
                Kind::Other => {}
                Kind::Utc(v, res, held) => {
                    let mut s = Sample::new(local, v, res).with_transit(transit);
                    if held {
                        s = s.held();
                    }
                    disc.utc_sample(s);
                    first_sample.get_or_insert(end);
                }
                Kind::FcClock(ms) => {
                    disc.fc_clock_sample(
                        Sample::new(local, u64::from(ms) * 1000, 1000).with_transit(transit),
                    );
                    pending_pair.1 = Some(ms);
                    first_sample.get_or_insert(end);
                }
                Kind::SiyiUtc(us) => {
                    disc.utc_via_fc_sample(Sample::new(local, us, 1).with_transit(transit));
                    pending_pair.0 = Some(us);
                }
            }
            if let (Some(us), Some(ms)) = pending_pair {
                disc.utc_fc_pair(us, ms.into());
                pending_pair = (None, None);
            }
            disc.poll(local);
            // Plan (or refine) the next edge until it is within the lead.
            let refine = planned.is_none_or(|e| {
                e.at.checked_duration_since(local)
                    .is_some_and(|d| d > lead.saturating_add(Duration::from_millis(20)))
            });
            if refine {
                planned = sched.next_edge(local, &disc);
            }
        }
    }
    // Edges that should have been measured: every 10 s from warm-up to the end.
    if let Some(t0) = first_sample {
        let expected = ((last_arrival - (t0 + WARMUP_US)) / 10e6).floor() as u32;
        stats.missed = expected.saturating_sub(fired_measured);
    }
    stats
}

/// Runs `seeds` flights and prints the figures.
fn run(name: &str, model: Model, seeds: std::ops::Range<u64>) -> Stats {
    let mut all = Stats::default();
    let mut worst = Vec::new();
    for seed in seeds {
        let s = fly(model, seed);
        worst.push(format!("{:.1}", s.max() / 1e3));
        all.merge(s);
    }
    let mean = all.signed.iter().sum::<f64>() / all.signed.len().max(1) as f64;
    let goal = all.quantile(0.99) < 1_000.0 && all.max() < 2_000.0;
    println!(
        "{name:<40} edges {:>5} missed {}  |err| p50 {:>6.3} ms  p99 {:>6.3} ms  max {:>6.3} ms  \
         mean signed {:>7.3} ms  goal (p99<1, max<2 ms) {}  per-flight max ms [{}]",
        all.errors.len(),
        all.missed,
        all.quantile(0.5) / 1e3,
        all.quantile(0.99) / 1e3,
        all.max() / 1e3,
        mean / 1e3,
        if goal { "met" } else { "NOT met" },
        worst.join(" "),
    );
    assert_eq!(all.missed, 0, "{name}: an edge every 10 s once valid");
    assert!(!all.errors.is_empty());
    all
}

/// Eight deterministic flights per case.
const SEEDS: std::ops::Range<u64> = 0..8;

#[test]
fn sizes() {
    let d = core::mem::size_of::<TimeDiscipline>();
    let f = core::mem::size_of::<FixHistory>();
    let s = core::mem::size_of::<SyncScheduler>();
    println!("size_of: TimeDiscipline {d} B, FixHistory {f} B, SyncScheduler {s} B");
    // 1,712 B: the FC offset's rate line and the PPS path's 16 edges and line included.
    assert!(d <= 1792, "{d}");
    assert!(d + f + s <= 6 * 1024);
}

/// Viewlink under ArduPilot: M_AHRS carries AP_RTC's UTC truncated to 10 ms, read on
/// the FC loop, which is paced by the same crystal as AP_RTC: the read phase is constant
/// for the flight, the truncation cannot be averaged out, and the discipline centres it:
/// the error is a per-flight constant within ±5 ms. The goal (p99 < 1 ms) is out of reach
/// for any estimator with this input; the test asserts the ±5 ms bound.
#[test]
fn viewlink() {
    let s = run(
        "Viewlink (ArduPilot, AP_RTC UTC)",
        Model::Viewlink {
            fc_utc_is_gps: false,
        },
        SEEDS,
    );
    assert!(s.max() < 5_500.0);
    // An FC whose UTC follows GPS: the read phase slides by the FC crystal's error, the
    // centring then costs up to 5 ms when the phase is near a boundary.
    let s = run(
        "Viewlink (FC UTC locked to GPS)",
        Model::Viewlink {
            fc_utc_is_gps: true,
        },
        SEEDS,
    );
    assert!(s.max() < 10_000.0);
}

/// GCU: the GPS time of the last fix, read by the 50 Hz FC loop: the first frame after a
/// fix was read 0..20 ms after it, a phase that slides only by the FC crystal's error
/// against GPS. Centred (resolution 20 ms): within about ±10 ms. A receiver latency is a
/// constant bias the bridge cannot see (second case: −40 ms).
#[test]
fn gcu() {
    for (name, hz) in [
        ("GCU, 10 Hz GPS, latency 0", 10),
        ("GCU, 5 Hz GPS, latency 0", 5),
    ] {
        let s = run(
            name,
            Model::Gcu {
                gps_hz: hz,
                latency_ms: 0.0,
            },
            SEEDS,
        );
        assert!(s.max() < 15_000.0);
    }
    let s = run(
        "GCU, 10 Hz GPS, latency 40 ms",
        Model::Gcu {
            gps_hz: 10,
            latency_ms: 40.0,
        },
        SEEDS,
    );
    let mean = s.signed.iter().sum::<f64>() / s.signed.len() as f64;
    assert!((mean + 40_000.0).abs() < 5_000.0, "a -40 ms bias: {mean}");
}

/// SIYI: the FC clock at 10 Hz, UTC five times at start (some of them paired with a
/// 0x22 of the same update). Reference: the FC's UTC.
#[test]
fn siyi() {
    let s = run(
        "SIYI, per-update jitter",
        Model::Siyi {
            per_frame_jitter: false,
        },
        SEEDS,
    );
    assert!(s.quantile(0.5) < 500.0);
    assert!(s.max() < 10_000.0);
    let s = run(
        "SIYI, per-frame jitter",
        Model::Siyi {
            per_frame_jitter: true,
        },
        SEEDS,
    );
    assert!(s.max() < 50_000.0);
}
