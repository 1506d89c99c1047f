//! Scenarios through the firmware's own tasks (`bridge-fw` on the host, virtual time,
//! pipes as UARTs, the RTC_IO pin wired to the simulated pod), written once for any
//! simulated FC ([`Pilot`]); each `tasks_<side>.rs` runs them with its side's bounds.
//!
//! Each scenario is one [`Bench`] run: a script called every 10 ms of virtual time acts
//! on the FC and the wires (cut a cable, send garbage) and samples the peers.
#![allow(dead_code)]

pub mod faults;

use bridge_engine::{Event, Level};
use bridge_fw::LogKind;
use gimbal::sim::describe::describe_k40t;
use gimbal::sim::pilot::Pilot;
use gimbal::sim::pod::SyncOutcome;
use gimbal::sim::tasks::{Bench, Cable, Outcome};
use protocol_core::k40t::{self, AckCode, K40tFraming, MessageData};
use protocol_core::wire::{Deframer, Event as WireEvent};

/// One second, µs.
pub const S: u64 = 1_000_000;
/// The script's tick.
pub const TICK: u64 = 10_000;

/// What a side must meet.
#[derive(Debug, Clone, Copy)]
pub struct Bounds {
    /// The FC's driver calls the mount healthy within this of start.
    pub healthy_within_us: u64,
    /// |UTC carried − the FC's true UTC at the edge| below this.
    pub sync_error_us: u64,
    /// After the pod cable is cut, the FC's driver turns unhealthy within this.
    pub unhealthy_after_pod_loss_us: u64,
    /// After it is mended, healthy again within this.
    pub healthy_after_pod_back_us: u64,
    /// The engine reports an `FcSilenceStop` when the FC falls silent during a pan
    /// (false: the FC steers by angles, the pod stops at the last one by itself).
    pub silence_stop_event: bool,
    /// The engine answers the pod's geotag requests itself (false: K40T, the FC does).
    pub bridge_geotags: bool,
}

/// The bench for `P`, every direction recorded.
pub fn bench<P: Pilot>() -> Bench<P> {
    let b = Bench::new(P::with_seed(7));
    b.wires.record_all();
    b
}

/// The engine events of a run that match `f`, with their instants.
pub fn events<P>(o: &Outcome<P>, f: impl Fn(&Event) -> bool) -> Vec<(u64, Event)> {
    o.events().filter(|(_, e)| f(e)).collect()
}

/// Start-up: the FC's driver calls the mount healthy within the bound and stays so; both
/// links come up; no frame of either link is rejected; replies flow to the FC.
pub fn startup_to_healthy<P: Pilot>(b: Bounds) {
    let o = bench::<P>().run(10 * S, TICK, |_, _| {});
    let log = o.fc.health_log();
    assert_eq!(log.len(), 1, "{log:?}");
    assert!(log[0].1 && log[0].0 <= b.healthy_within_us, "{log:?}");
    assert!(o.fc.healthy());
    assert_eq!(o.fc.parse_errors(), 0);
    assert_eq!(events(&o, |e| *e == Event::PodLinkUp).len(), 1);
    assert_eq!(events(&o, |e| *e == Event::FcLinkUp).len(), 1);
    assert!(events(&o, |e| *e == Event::PodLinkDown).is_empty());
    if P::STREAMS {
        assert!(events(&o, |e| *e == Event::FcLinkDown).is_empty());
    }
    let c = o.engine.counters();
    assert_eq!((c.fc_rejected, c.pod_rejected), (0, 0), "{c:?}");
    assert_eq!((c.fc_garbage_bytes, c.pod_garbage_bytes), (0, 0), "{c:?}");
    assert!(
        c.fc_frames > 0 && c.pod_frames > 50 && c.fc_sent > 0,
        "{c:?}"
    );
    assert!(o.wires.fc_out.bytes > 100);
    assert_eq!(o.records_dropped, 0);
}

/// A pod state sample: (time, yaw, pitch, yaw rate, zoom ×10, recording).
#[derive(Debug, Clone, Copy)]
struct Sample {
    t: u64,
    yaw: f64,
    pitch: f64,
    yaw_rate: f64,
    zoom_x10: f64,
    recording: bool,
    fc_sees: Option<(f64, f64)>,
}

fn sample<P: Pilot>(b: &Bench<P>, t: u64) -> Sample {
    let pod = b.pod.borrow();
    let g = pod.gimbal();
    Sample {
        t,
        yaw: g.yaw_deg,
        pitch: g.pitch_deg,
        yaw_rate: g.yaw_rate_dps,
        zoom_x10: pod.camera().zoom_x10,
        recording: pod.camera().recording.is_some(),
        fc_sees: b.fc.borrow().mount_angles(),
    }
}

/// Commands reach the pod with the right meaning (look down to −90°, pan right at
/// 20 °/s for 3 s then stop, zoom in then stop, record start/stop, a photo), and the
/// pod's attitude goes back to the FC (what its driver reads matches the pod).
pub fn commands_and_telemetry<P: Pilot>() {
    let mut samples = Vec::new();
    let o = bench::<P>().run(26 * S, TICK, |b, t| {
        {
            let mut fc = b.fc.borrow_mut();
            match t {
                t if t == 3 * S => fc.point(0.0, -90.0),
                t if t == 8 * S => fc.turn(20.0, 0.0),
                t if t == 11 * S => fc.turn(0.0, 0.0),
                t if t == 14 * S => fc.zoom(1),
                t if t == 16 * S => fc.zoom(0),
                t if t == 18 * S => fc.record(true),
                t if t == 20 * S => fc.take_picture(),
                t if t == 22 * S => fc.record(false),
                _ => {}
            }
        }
        if t % (S / 2) == 0 {
            samples.push(sample(b, t));
        }
    });
    let at = |t: u64| {
        *samples
            .iter()
            .find(|s| s.t == t)
            .unwrap_or_else(|| panic!("no sample at {t}"))
    };
    // Looking down: pitch −90°, yaw 0; ArduPilot reads the same.
    let s = at(7 * S + S / 2);
    assert!((s.pitch + 90.0).abs() < 1.0 && s.yaw.abs() < 1.0, "{s:?}");
    let (fc_yaw, fc_pitch) = s.fc_sees.expect("the FC reads the mount's attitude");
    assert!(
        (fc_pitch - s.pitch).abs() < 1.0 && (fc_yaw - s.yaw).abs() < 1.0,
        "{s:?}"
    );
    // Panning right at about 20 °/s.
    let (a, c) = (at(9 * S), at(10 * S));
    let rate = c.yaw - a.yaw;
    assert!((16.0..=24.0).contains(&rate), "{rate} °/s: {a:?} {c:?}");
    // Stopped after about 3 s of it, pitch held; the FC reads the new yaw.
    let s = at(13 * S);
    assert!((45.0..=75.0).contains(&s.yaw), "{s:?}");
    assert_eq!(s.yaw_rate, 0.0, "{s:?}");
    assert!((at(13 * S + S / 2).yaw - s.yaw).abs() < 0.1);
    assert!((s.pitch + 90.0).abs() < 1.0, "{s:?}");
    let (fc_yaw, _) = s.fc_sees.expect("attitude");
    assert!((fc_yaw - s.yaw).abs() < 1.0, "{s:?}");
    // Zoomed in, then stopped.
    let (z0, z1, z2) = (
        at(13 * S).zoom_x10,
        at(16 * S).zoom_x10,
        at(17 * S).zoom_x10,
    );
    assert!(z1 > z0 + 5.0, "zoom {z0} -> {z1}");
    assert!((z2 - at(18 * S).zoom_x10).abs() < 0.01, "zoom still moving");
    // Recording from 18 s to 22 s, one photo at 20 s.
    assert!(!at(17 * S + S / 2).recording);
    assert!(at(19 * S).recording && at(21 * S + S / 2).recording);
    assert!(!at(23 * S).recording);
    let photos = o.pod.photos();
    assert_eq!(photos.len(), 1, "{photos:?}");
    assert!(photos[0].at_us > 20 * S && photos[0].at_us < 20 * S + S / 5);
    assert_eq!(
        o.pod.received_count(k40t::Record::ID.to_u32()),
        2,
        "one start, one stop"
    );
    assert!(o.fc.healthy());
    assert_eq!(o.fc.parse_errors(), 0);
}

/// Time-sync figures of a run: per sync, (error µs signed, edge-to-frame delay µs).
#[derive(Debug, Default)]
pub struct SyncFigures {
    /// UTC carried − true UTC at the edge, µs.
    pub errors_us: Vec<i64>,
    /// From the RTC_IO rising edge to the first byte of the 0x00030E, µs.
    pub delays_us: Vec<u64>,
}

impl SyncFigures {
    /// (p50, max) of |error|, µs.
    pub fn error_p50_max(&self) -> (u64, u64) {
        let mut a: Vec<u64> = self.errors_us.iter().map(|e| e.unsigned_abs()).collect();
        a.sort_unstable();
        (a[(a.len() - 1) / 2], a[a.len() - 1])
    }
}

/// Time sync and geotag: every RTC_IO rising edge is followed by the 0x00030E as the
/// first frame on the pod line, its delay recorded by the pin task; the pod applies each
/// one, on the 10 s UTC grid, within the bound of the FC's true UTC; photos after the
/// first sync are geotagged with the aircraft's position.
pub fn sync_and_geotag<P: Pilot>(b: Bounds, label: &str) -> SyncFigures {
    let o = bench::<P>().run(95 * S, TICK, |b, t| {
        if t == 72 * S || t == 83 * S {
            b.fc.borrow_mut().take_picture();
        }
    });
    let highs = o.pin_changes(Level::High);
    let lows = o.pin_changes(Level::Low);
    let edge_to_frame = o.edge_to_frame();
    let syncs = o.pod.syncs();
    assert!(highs.len() >= 5, "{highs:?}");
    assert_eq!(highs.len(), syncs.len(), "{syncs:?}");
    assert_eq!(highs.len(), lows.len());
    assert_eq!(edge_to_frame.len(), highs.len(), "{edge_to_frame:?}");
    // The pod-bound line's frames, with the instant their first chunk went out.
    let pod_frames = frames_with_start(&o.wires.pod_out.log);
    let mut fig = SyncFigures::default();
    for (i, &edge) in highs.iter().enumerate() {
        // The pulse: high, then low after the pulse width.
        assert!(
            lows[i] > edge && lows[i] - edge <= 50_000,
            "{edge} {}",
            lows[i]
        );
        // The tasks' record of the edge and its frame: the 0x00030E (28 bytes).
        let (at, delay, len) = edge_to_frame[i];
        assert_eq!((at, len), (edge, 28));
        // On the wire: the first frame started after the edge is that 0x00030E.
        let (start, frame) = pod_frames
            .iter()
            .find(|(s, _)| *s >= edge)
            .expect("a frame after the edge");
        let d = describe_k40t(frame).expect("a K40T frame");
        assert_eq!(d.id, k40t::TimeSync::ID.to_u32(), "{d}");
        assert!(start - edge <= delay.max(1_000), "{start} vs {edge}");
        // The pod matched it with this edge and applied it.
        let s = &syncs[i];
        assert_eq!(s.edge_us, Some(edge));
        assert_eq!(s.outcome, SyncOutcome::Applied, "{s:?}");
        assert_eq!(s.unix_ms % 10_000, 0);
        let err = (s.unix_ms * 1000) as i64 - o.fc.true_utc_us(edge) as i64;
        assert!(
            err.unsigned_abs() < b.sync_error_us,
            "sync {i}: error {err} µs"
        );
        let ev = events(
            &o,
            |e| matches!(e, Event::TimeSync { edge: x, utc_ms, .. } if x.as_micros() == edge && *utc_ms == s.unix_ms),
        );
        assert_eq!(ev.len(), 1);
        fig.errors_us.push(err);
        fig.delays_us.push(delay);
    }
    // Geotags: both photos asked for, answered with the aircraft's position.
    let photos = o.pod.photos();
    assert_eq!(photos.len(), 2, "{photos:?}");
    for p in photos {
        let req = &o.pod.gps_requests()[p.gps_request.expect("a geotag request")];
        assert!(req.synced);
        let reply = &o.pod.gps_replies()[req.reply.expect("a reply")];
        assert_eq!(reply.reply.code.code(), AckCode::Ok);
        assert!(reply.time_matches);
        let (lat, lon) = o.fc.aircraft().position_e7(p.at_us);
        // 1e-7° is about 1.1 cm: within half a metre.
        assert!(
            (reply.reply.lat_e7 - lat).abs() < 50 && (reply.reply.lon_e7 - lon).abs() < 70,
            "{:?} vs {lat} {lon}",
            reply.reply
        );
    }
    if b.bridge_geotags {
        let answered = events(&o, |e| matches!(e, Event::Geotag { missed: None, .. }));
        assert_eq!(answered.len(), 2);
    }
    assert_eq!(o.records_dropped, 0);
    let (p50, max) = fig.error_p50_max();
    let dmax = fig.delays_us.iter().max().copied().unwrap_or_default();
    println!(
        "{label}: {} syncs through the tasks, |error| p50 {p50} µs, max {max} µs; RTC_IO edge -> first 0x00030E byte {dmax} µs max (virtual time)",
        fig.errors_us.len()
    );
    fig
}

/// Frames of a recorded direction with the instant their first byte went through.
fn frames_with_start(log: &[(u64, Vec<u8>)]) -> Vec<(u64, Vec<u8>)> {
    let mut d = Deframer::<_, 1024>::new(K40tFraming::any());
    let mut out = Vec::new();
    // Bytes buffered (not yet in a frame) and when the oldest of them went through.
    let mut pending_since: Option<u64> = None;
    for (t, chunk) in log {
        if d.buffered() == 0 {
            pending_since = Some(*t);
        }
        let start = pending_since.unwrap_or(*t);
        let mut got = Vec::new();
        d.push(chunk, |ev| {
            if let WireEvent::Frame(f) = ev {
                got.push(f.to_vec());
            }
        });
        for f in got {
            out.push((start, f));
        }
        pending_since = (d.buffered() > 0).then_some(*t);
    }
    out
}

/// The FC falls silent (its cable is cut) while the pod pans: the pod's motion stops
/// within 0.6 s. Returns the delay from the cut to the pod standing still, µs.
pub fn fc_silence_stops_motion<P: Pilot>(b: Bounds) -> u64 {
    const CUT: u64 = 6 * S;
    let mut samples = Vec::new();
    let o = bench::<P>().run(9 * S, TICK, |bench, t| {
        if t == 3 * S {
            bench.fc.borrow_mut().turn(20.0, 0.0);
        }
        if t == CUT {
            bench.wires.cut(Cable::Fc, true);
        }
        if t >= CUT - S {
            samples.push(sample(bench, t));
        }
    });
    let before = samples.first().expect("samples");
    assert!(before.yaw_rate > 0.0 || !b.silence_stop_event, "{before:?}");
    // Still from some instant on: the first sample after which the yaw never changes.
    let last = samples.last().expect("samples");
    let still = samples
        .iter()
        .rev()
        .take_while(|s| (s.yaw - last.yaw).abs() < 1e-6 && s.yaw_rate == 0.0)
        .last()
        .expect("standing still at the end");
    assert!(still.t > CUT - S, "the pod was not moving before the cut");
    let delay = still.t.saturating_sub(CUT);
    assert!(delay <= 600_000, "moving {} ms after the cut", delay / 1000);
    if b.silence_stop_event {
        assert_eq!(events(&o, |e| *e == Event::FcSilenceStop).len(), 1);
        let stop = o.pod.first_stop_after(CUT).expect("a stop command");
        assert!(stop - CUT <= 600_000);
    }
    delay
}

/// The pod's cable is cut for 5 s: the FC's driver sees what it would see of a real
/// gimbal that went away (it turns unhealthy), then healthy again once mended.
pub fn pod_loss<P: Pilot>(b: Bounds) {
    const CUT: u64 = 10 * S;
    const BACK: u64 = 15 * S;
    let o = bench::<P>().run(20 * S, TICK, |bench, t| {
        if t == CUT {
            bench.wires.cut(Cable::Pod, true);
        }
        if t == BACK {
            bench.wires.cut(Cable::Pod, false);
        }
    });
    let log = o.fc.health_log();
    let down = log
        .iter()
        .find(|(t, h)| *t > CUT && !h)
        .unwrap_or_else(|| panic!("still healthy: {log:?}"))
        .0;
    assert!(
        down - CUT <= b.unhealthy_after_pod_loss_us,
        "unhealthy {} ms after the cut",
        (down - CUT) / 1000
    );
    assert!(down < BACK);
    let up = log
        .iter()
        .find(|(t, h)| *t > BACK && *h)
        .unwrap_or_else(|| panic!("not healthy again: {log:?}"))
        .0;
    assert!(
        up - BACK <= b.healthy_after_pod_back_us,
        "healthy {} ms after the mend",
        (up - BACK) / 1000
    );
    assert!(o.fc.healthy());
    let down_ev = events(&o, |e| *e == Event::PodLinkDown);
    let up_ev = events(&o, |e| *e == Event::PodLinkUp);
    assert_eq!(down_ev.len(), 1);
    assert!(down_ev[0].0 > CUT && down_ev[0].0 < BACK);
    assert_eq!(up_ev.len(), 2, "{up_ev:?}");
    assert!(up_ev[1].0 >= BACK);
}

/// A pseudo-random garbage maker: every `every`-th write gets `n` bytes in front.
fn garbage(seed: u64, every: u32, n: usize) -> Box<gimbal::sim::faults::Corrupter> {
    let mut x = seed | 1;
    let mut count = 0u32;
    Box::new(move |_t, bytes: &[u8]| {
        count += 1;
        let mut out = Vec::with_capacity(bytes.len() + n);
        if count.is_multiple_of(every) {
            for _ in 0..n {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                out.push((x >> 24) as u8);
            }
        }
        out.extend_from_slice(bytes);
        out
    })
}

/// Garbage on both lines into the bridge (a few random bytes before every 10th chunk
/// from the FC and every 20th from the pod): the FC stays healthy, commands still turn
/// the pod, time syncs are still applied, and the engine counts the garbage.
pub fn garbage_on_both_lines<P: Pilot>() {
    let o = bench::<P>().run(65 * S, TICK, |b, t| {
        if t == 2 * S {
            b.wires
                .fc_in
                .borrow_mut()
                .damage
                .set_corrupter(garbage(11, 10, 5));
            b.wires
                .pod_in
                .borrow_mut()
                .damage
                .set_corrupter(garbage(29, 20, 5));
        }
        if t == 10 * S {
            b.fc.borrow_mut().point(0.0, -90.0);
        }
    });
    let log = o.fc.health_log();
    assert_eq!(log.len(), 1, "{log:?}");
    assert!(o.fc.healthy());
    let c = o.engine.counters();
    assert!(c.fc_garbage_bytes > 0 && c.pod_garbage_bytes > 100, "{c:?}");
    assert!((o.pod.gimbal().pitch_deg + 90.0).abs() < 1.0);
    let syncs = o.pod.syncs();
    assert!(!syncs.is_empty());
    assert!(
        syncs.iter().all(|s| s.outcome == SyncOutcome::Applied),
        "{syncs:?}"
    );
    assert!(events(&o, |e| *e == Event::PodLinkDown).is_empty());
    assert!(o.records.iter().all(|r| !matches!(
        r.what,
        LogKind::ReadError(_) | LogKind::WriteError(_) | LogKind::Stalled(_)
    )));
}
