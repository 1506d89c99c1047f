//! The demo: the bridge's firmware tasks (the `bridge-fw` crate on the host, in virtual
//! time) between a simulated flight controller and the simulated K40T pod, flying a
//! short scripted flight, told as a timeline a person can read, then a summary table.
//!
//! ```no_run
//! use gimbal::demo::{self, DemoOptions};
//! use bridge_engine::FcProtocol;
//!
//! let summary = demo::run(
//!     &DemoOptions { fc: FcProtocol::Siyi, seconds: 60, telemetry: false, pps: false },
//!     &mut std::io::stdout(),
//! )?;
//! assert!(summary.healthy_at_s.is_some());
//! # Ok::<(), std::io::Error>(())
//! ```
//!
//! What is shown:
//! - the FC reaching healthy (its driver's own rule), the links coming up or going down;
//! - each step of the script (look down, pan, zoom, record, photos), with the frames it
//!   caused on both links (decoded, one line each) and the commands the engine translated;
//! - the first frame of every kind on each link (routine traffic is shown once);
//! - each time sync: the RTC_IO edge, the UTC the 0x00030E carried, the delay from the
//!   edge to its first byte, and its error against the simulated FC's true UTC;
//! - each geotag request of the pod with the fix the bridge answered, and how far that
//!   fix is from where the aircraft really was when the photo was taken;
//! - a summary: healthy at, commands translated, syncs and their error (p50, max),
//!   geotags answered, bytes per link direction, frames and records dropped.
//!
//! With [`DemoOptions::pps`] a simulated GNSS module's pulse per second reaches the
//! bridge's PPS input and RTC_IO is the board's timer compare: the clock locks to the
//! pulses, and each sync's error is against the GNSS's UTC, in microseconds.

use crate::runner::output::time_of_day_text;
use std::io::{self, Write};
use std::time::Instant as WallInstant;

use bridge_engine::{Config, Event, FcProtocol, Level};
use protocol_core::k40t::K40tFraming;
use protocol_core::wire::{Deframer, Event as WireEvent, Framing};

use crate::report::figures::quantile;
use crate::runner::bench_log::BenchLog;
use crate::sim::Autopilot;
use crate::sim::ap_mavlink::ApMavlink;
use crate::sim::ap_siyi::ApSiyi;
use crate::sim::ap_viewpro::ApViewpro;
use crate::sim::ap_xfrobot::ApXfRobot;
use crate::sim::describe::{
    Described, MavlinkFrames, SideFrames, describe_k40t, k40t_name, k40t_routine,
};
use crate::sim::fc_k40t::FcK40t;
use crate::sim::gnss::{Crystal, GnssPps, GnssPpsConfig};
use crate::sim::pilot::Pilot;
use crate::sim::pps_io::PpsWiring;
use crate::sim::tasks::{Bench, Outcome, Wire};

/// What to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DemoOptions {
    /// The FC protocol (the simulated FC that speaks it is picked from it).
    pub fc: FcProtocol,
    /// Simulated seconds.
    pub seconds: u32,
    /// The same autopilot's MAVLink port on the bridge's telemetry link (SIYI,
    /// Viewlink, GCU: the simulated ArduPilots).
    pub telemetry: bool,
    /// A simulated GNSS module's PPS on the bridge's PPS input (any FC side).
    pub pps: bool,
}

impl Default for DemoOptions {
    fn default() -> Self {
        DemoOptions {
            fc: FcProtocol::Siyi,
            seconds: 60,
            telemetry: false,
            pps: false,
        }
    }
}

/// The figures of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// The FC protocol.
    pub fc: FcProtocol,
    /// Simulated seconds run.
    pub seconds: u32,
    /// A telemetry link was attached.
    pub telemetry: bool,
    /// A GNSS PPS was on the bridge's PPS input.
    pub pps: bool,
    /// With PPS: when the clock locked to the pulses, s.
    pub pps_locked_at_s: Option<f64>,
    /// With PPS: the first labelled edge of the run that locked, s.
    pub pps_first_edge_at_s: Option<f64>,
    /// With PPS: the first sync after the lock, s.
    pub first_pps_sync_at_s: Option<f64>,
    /// When the bridge took UTC and fixes from the telemetry link, s.
    pub telemetry_source_at_s: Option<f64>,
    /// When the FC's driver first called the mount healthy, s.
    pub healthy_at_s: Option<f64>,
    /// Healthy at the end of the run.
    pub healthy_at_end: bool,
    /// FC commands the engine turned into pod commands (repeats included: a driver
    /// that streams its rate command 50 times a second is translated 50 times).
    pub commands_translated: u32,
    /// Distinct (FC command, pod command) pairs among them.
    pub command_kinds: u32,
    /// When the FC (with a telemetry link: the autopilot's MAVLink port) first sent a
    /// usable UTC, s.
    pub fc_first_utc_at_s: Option<f64>,
    /// When the bridge first knew UTC from the FC, s.
    pub utc_valid_at_s: Option<f64>,
    /// The first time sync's edge, s.
    pub first_sync_at_s: Option<f64>,
    /// The first time sync's error (UTC carried − the FC's true UTC at the edge; with a
    /// telemetry link, the UTC of the autopilot's MAVLink port), µs.
    pub first_sync_error_us: Option<i64>,
    /// Time syncs sent (RTC_IO edge + 0x00030E).
    pub syncs: u32,
    /// Of those, applied by the pod.
    pub syncs_applied: u32,
    /// Median of |UTC carried − the FC's true UTC at the edge|, µs.
    pub sync_error_p50_us: Option<u64>,
    /// Largest of those, µs.
    pub sync_error_max_us: Option<u64>,
    /// Median of |UTC carried − the true UTC at the edge|, ns (with PPS: the GNSS's UTC
    /// at the instant the compare put the edge).
    pub sync_error_p50_ns: Option<u64>,
    /// Largest of those, ns.
    pub sync_error_max_ns: Option<u64>,
    /// Largest delay from an RTC_IO rising edge to the first byte of its 0x00030E, µs.
    pub edge_to_frame_max_us: Option<u64>,
    /// Geotag requests from the pod.
    pub geotags_requested: u32,
    /// Of those, answered with a fix.
    pub geotags_answered: u32,
    /// Largest distance between an answered fix and the aircraft's true position when
    /// the photo was taken, m.
    pub geotag_error_max_m: Option<f64>,
    /// Photos the pod took.
    pub photos: u32,
    /// The pod recorded video at some point of the run.
    pub recorded: bool,
    /// Bytes FC → bridge.
    pub bytes_fc_to_bridge: u64,
    /// Bytes bridge → FC.
    pub bytes_bridge_to_fc: u64,
    /// Bytes pod → bridge.
    pub bytes_pod_to_bridge: u64,
    /// Bytes bridge → pod.
    pub bytes_bridge_to_pod: u64,
    /// Output frames the engine dropped (a queue was full).
    pub frames_dropped: u32,
    /// Log records the tasks could not hand over in time.
    pub records_dropped: u32,
}

/// One step of the scripted flight.
#[derive(Debug, Clone, Copy)]
enum Step {
    Point(f64, f64),
    Turn(f64, f64),
    Zoom(i8),
    Record(bool),
    Photo,
}

impl Step {
    fn say(self) -> String {
        match self {
            Step::Point(yaw, pitch) => {
                if pitch <= -89.0 {
                    format!("look down (yaw {yaw:.0}°, pitch {pitch:.0}°)")
                } else {
                    format!("point at yaw {yaw:.0}°, pitch {pitch:.0}°")
                }
            }
            Step::Turn(y, p) if y == 0.0 && p == 0.0 => "stop turning".to_string(),
            Step::Turn(y, p) => format!("pan at {y:.0}°/s (pitch {p:.0}°/s)"),
            Step::Zoom(r) if r > 0 => "zoom in".to_string(),
            Step::Zoom(r) if r < 0 => "zoom out".to_string(),
            Step::Zoom(_) => "stop zooming".to_string(),
            Step::Record(true) => "start recording".to_string(),
            Step::Record(false) => "stop recording".to_string(),
            Step::Photo => "take a photo".to_string(),
        }
    }

    fn apply<P: Pilot>(self, fc: &mut P) {
        match self {
            Step::Point(y, p) => fc.point(y, p),
            Step::Turn(y, p) => fc.turn(y, p),
            Step::Zoom(r) => fc.zoom(r),
            Step::Record(on) => fc.record(on),
            Step::Photo => fc.take_picture(),
        }
    }
}

/// The scripted flight: (second, step). The first photo comes two seconds after the
/// first time sync (UTC is known within a second or two of the FC's first time value,
/// the first sync goes out on the next 10 s UTC grid edge, about 10 s after start), so
/// that the pod's clock is UTC when it asks for its geotag; a longer run takes one more
/// photo every 15 s.
fn script(seconds: u32) -> Vec<(u64, Step)> {
    let mut s = vec![
        (5, Step::Point(0.0, -90.0)),
        (10, Step::Turn(20.0, 0.0)),
        (12, Step::Photo),
        (13, Step::Turn(0.0, 0.0)),
        (16, Step::Zoom(1)),
        (18, Step::Zoom(0)),
        (20, Step::Record(true)),
        (34, Step::Photo),
        (51, Step::Photo),
        (58, Step::Record(false)),
    ];
    let mut t = 65;
    while t < u64::from(seconds) {
        s.push((t, Step::Photo));
        t += 15;
    }
    s.retain(|&(t, _)| t < u64::from(seconds));
    s
}

/// Runs the demo and writes its story to `out`.
///
/// # Errors
/// Only those of writing to `out`.
pub fn run(opts: &DemoOptions, out: &mut dyn Write) -> io::Result<Summary> {
    match opts.fc {
        FcProtocol::Siyi => run_with::<ApSiyi>(opts, out),
        FcProtocol::Viewlink => run_with::<ApViewpro>(opts, out),
        FcProtocol::Gcu => run_with::<ApXfRobot>(opts, out),
        FcProtocol::K40t => run_with::<FcK40t>(opts, out),
        FcProtocol::Mavlink => run_with::<ApMavlink>(opts, out),
    }
}

/// The protocol's name on the command line.
#[must_use]
pub const fn fc_name(fc: FcProtocol) -> &'static str {
    match fc {
        FcProtocol::Siyi => "siyi",
        FcProtocol::Viewlink => "viewlink",
        FcProtocol::Gcu => "gcu",
        FcProtocol::K40t => "k40t",
        FcProtocol::Mavlink => "mavlink",
    }
}

/// A line of the timeline.
struct Line {
    t_us: u64,
    /// Order among lines of the same instant.
    rank: u8,
    who: &'static str,
    text: String,
}

/// How long after a script step its frames and translations are shown.
const WINDOW_US: u64 = 1_000_000;
/// Frames shown per link direction within one step's window.
const PER_WINDOW: usize = 3;

/// The four link directions, for the frame lines.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Dir {
    FcIn,
    FcOut,
    PodIn,
    PodOut,
    TelIn,
    TelOut,
}

impl Dir {
    const fn label(self) -> &'static str {
        match self {
            Dir::FcIn => "FC → bridge",
            Dir::FcOut => "bridge → FC",
            Dir::PodIn => "pod → bridge",
            Dir::PodOut => "bridge → pod",
            Dir::TelIn => "AP MAVLink → bridge",
            Dir::TelOut => "bridge → AP MAVLink",
        }
    }
}

/// Pod-link frames shown whenever they are new: time syncs (0x00030E) and geotag
/// requests and replies (0x000310).
fn pod_anytime(id: u32) -> bool {
    matches!(id & 0xFFFF, 0x030E | 0x0310)
}

/// The frames of a recorded direction: (instant its last chunk went through, bytes).
fn frames_of<F: Framing>(framing: F, log: &[(u64, Vec<u8>)]) -> Vec<(u64, Vec<u8>)> {
    let mut d = Deframer::<F, 1024>::new(framing);
    let mut frames = Vec::new();
    for (t, chunk) in log {
        d.push(chunk, |ev| {
            if let WireEvent::Frame(f) = ev {
                frames.push((*t, f.to_vec()));
            }
        });
    }
    frames
}

/// Picks the frames worth a line: the first of every kind; within a script step's
/// window the commands (not routine traffic) that are new, i.e. changed since the
/// previous frame of their id or the first of their id for over a second (at most
/// [`PER_WINDOW`] per direction and window); new commands outside the windows too when
/// `anytime(id)` (on the pod link: time syncs, geotag requests and replies).
/// The frames of an FC-side link (`S`'s), into the FC (the first wire) and out of it.
fn fc_link_lines<S: SideFrames>(
    wires: [(Dir, &Wire); 2],
    steps: &[(u64, Step)],
    lines: &mut Vec<Line>,
) {
    for ((dir, wire), from_fc) in wires.into_iter().zip([true, false]) {
        frame_lines(
            dir,
            &frames_of(S::framing(from_fc), &wire.log),
            |f| S::describe(f, from_fc),
            |id| S::routine(id, from_fc),
            |_| false,
            steps,
            lines,
        );
    }
}

fn frame_lines(
    dir: Dir,
    frames: &[(u64, Vec<u8>)],
    describe: impl Fn(&[u8]) -> Option<Described>,
    routine: impl Fn(u32) -> bool,
    anytime: impl Fn(u32) -> bool,
    steps: &[(u64, Step)],
    lines: &mut Vec<Line>,
) {
    // Per id: the last description and when it was seen.
    let mut seen: Vec<(u32, String, u64)> = Vec::new();
    let mut shown_in_window: Vec<usize> = vec![0; steps.len()];
    for (t, f) in frames {
        let Some(d) = describe(f) else { continue };
        let text = d.to_string();
        let (first, new) = match seen.iter_mut().find(|(id, _, _)| *id == d.id) {
            None => {
                seen.push((d.id, text.clone(), *t));
                (true, true)
            }
            Some((_, prev, at)) => {
                let new = *prev != text || t.saturating_sub(*at) > 1_000_000;
                prev.clone_from(&text);
                *at = *t;
                (false, new)
            }
        };
        let command = !routine(d.id);
        let window = steps
            .iter()
            .position(|&(s, _)| (s * 1_000_000..s * 1_000_000 + WINDOW_US).contains(t));
        let show = first
            || (command
                && new
                && match window.and_then(|w| shown_in_window.get_mut(w)) {
                    Some(n) if *n < PER_WINDOW => {
                        *n += 1;
                        true
                    }
                    Some(_) => false,
                    None => anytime(d.id),
                });
        if show {
            let note = if first && !command {
                "  (routine; shown once)"
            } else {
                ""
            };
            lines.push(Line {
                t_us: *t,
                rank: 3,
                who: dir.label(),
                text: format!("{}{note}", short(&text, 130)),
            });
        }
    }
}

/// `s` cut at `max` characters.
fn short(s: &str, max: usize) -> String {
    if s.chars().count() <= max {
        s.to_string()
    } else {
        let mut t: String = s.chars().take(max - 1).collect();
        t.push('…');
        t
    }
}

/// UTC (ms since the Unix epoch) as `2026-11-23T10:00:40.000Z`.
#[must_use]
pub fn utc_text(unix_ms: u64) -> String {
    crate::runner::output::iso_utc(unix_ms)
}

/// Distance between two positions in 1e-7 degrees, m (flat earth: metres apart).
fn metres_apart(a: (i32, i32), b: (i32, i32)) -> f64 {
    let lat = f64::from(a.0) * 1e-7;
    let dn = f64::from(a.0 - b.0) * 1e-7 * 111_320.0;
    let de = f64::from(a.1 - b.1) * 1e-7 * 111_320.0 * lat.to_radians().cos();
    dn.hypot(de)
}

/// The demo's GNSS module: fixed from the start (the FC's UTC comes later: the pulses
/// before it are unlabelled), its UTC the FC's at true time 0 (`utc_at_zero_us`), 30 ns
/// of jitter, 1 % of pulses missing; the bridge's crystal 20 ppm fast.
fn demo_pps(utc_at_zero_us: u64) -> PpsWiring {
    PpsWiring {
        gnss: GnssPps::new(GnssPpsConfig {
            seed: 7,
            utc_at_zero_us,
            ..GnssPpsConfig::default()
        }),
        crystal: Crystal::new(20.0),
        bridge_active_low: false,
    }
}

/// A demo flight flown: what the run left and what the story needs besides.
struct Flown<P> {
    o: Outcome<P, ApMavlink>,
    steps: Vec<(u64, Step)>,
    recorded: bool,
    fc_baud: u32,
    pod_baud: u32,
}

/// Flies the scripted flight with `P`; `each(bench, now_us)` runs every 100 ms of it.
fn fly<P: Pilot>(
    opts: &DemoOptions,
    mut each: impl FnMut(&Bench<P, ApMavlink>, u64),
) -> io::Result<Flown<P>> {
    let steps = script(opts.seconds);
    let fc = P::with_seed(1);
    let telemetry = if opts.telemetry {
        let Some(clock) = fc.board_clock() else {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                "--telemetry needs a simulated ArduPilot FC (siyi, viewlink or gcu)",
            ));
        };
        Some(ApMavlink::telemetry(clock.clone(), *fc.aircraft(), 2, 1))
    } else {
        None
    };
    let pps = opts.pps.then(|| demo_pps(fc.clock().boots()[0].utc_us));
    let pod = crate::sim::pod::SimPod::new(crate::sim::pod::PodSimConfig::default());
    let mut bench = Bench::of(Config::for_fc(P::PROTOCOL), fc, pod, telemetry);
    if let Some(w) = pps {
        bench = bench.with_pps(w);
    }
    bench.wires.record_all();
    let (fc_baud, pod_baud) = (bench.config.fc_baud, bench.config.pod_baud);
    let end_us = u64::from(opts.seconds) * 1_000_000;
    let mut next = 0;
    let mut recorded = false;
    let o = bench.run(end_us, 100_000, |b, t| {
        recorded |= b.pod.borrow().camera().recording.is_some();
        while let Some(&(s, step)) = steps.get(next) {
            if s * 1_000_000 > t {
                break;
            }
            step.apply(&mut *b.fc.borrow_mut());
            next += 1;
        }
        each(b, t);
    });
    Ok(Flown {
        o,
        steps,
        recorded,
        fc_baud,
        pod_baud,
    })
}

/// Runs the demo and writes its events to `out` as `gimbal bridge --events json`
/// writes them ([`crate::runner::bench_log`]), each `time_sync` with its measured error
/// (`error_us`, against the truth the story's errors are measured against), after a
/// `demo_started` line (`fc`, `seconds`, `telemetry`, `pps`, `log_version`).
///
/// # Errors
/// Those of writing to `out`; `--telemetry` with an FC that has no MAVLink port.
pub fn run_json(opts: &DemoOptions, out: &mut dyn Write) -> io::Result<()> {
    match opts.fc {
        FcProtocol::Siyi => json_with::<ApSiyi>(opts, out),
        FcProtocol::Viewlink => json_with::<ApViewpro>(opts, out),
        FcProtocol::Gcu => json_with::<ApXfRobot>(opts, out),
        FcProtocol::K40t => json_with::<FcK40t>(opts, out),
        FcProtocol::Mavlink => json_with::<ApMavlink>(opts, out),
    }
}

fn json_with<P: Pilot>(opts: &DemoOptions, out: &mut dyn Write) -> io::Result<()> {
    let mut log = BenchLog::new(
        crate::runner::event_name::EventName::DemoStarted,
        serde_json::json!({"fc": fc_name(opts.fc), "seconds": opts.seconds,
                           "telemetry": opts.telemetry, "pps": opts.pps}),
    );
    let f = fly::<P>(opts, |b, t| log.sample(b, t))?;
    let lines = log.finish(&f.o, |edge_us, utc_ms| {
        Some(i128::from(utc_ms) * 1_000_000 - truth_ns(&f.o, edge_us))
    });
    for l in lines {
        writeln!(out, "{}", serde_json::Value::Object(l))?;
    }
    Ok(())
}

/// The true UTC at a sync's rising edge, ns since the Unix epoch: the GNSS's UTC at the
/// compare's edge with PPS, else the FC's (with a telemetry link: its MAVLink port's).
fn truth_ns<P: Pilot>(o: &Outcome<P, ApMavlink>, edge_us: u64) -> i128 {
    let edge = bridge_engine::Instant::from_micros(edge_us);
    let edge_ns = o
        .rtc_edges_ns
        .iter()
        .find(|(l, at)| *l == Level::High && at.instant() == edge)
        .map_or(i128::from(edge_us) * 1_000, |(_, at)| {
            i128::from(at.as_nanos())
        });
    match (&o.pps, &o.telemetry) {
        (Some(w), _) => w.utc_ns_at_local(edge_ns),
        (None, Some(t)) => i128::from(t.fc_utc_us(edge_us)) * 1_000,
        (None, None) => i128::from(o.fc.true_utc_us(edge_us)) * 1_000,
    }
}

fn run_with<P: Pilot>(opts: &DemoOptions, out: &mut dyn Write) -> io::Result<Summary> {
    let wall = WallInstant::now();
    let Flown {
        o,
        steps,
        recorded,
        fc_baud,
        pod_baud,
    } = fly::<P>(opts, |_, _| {})?;
    let wall = wall.elapsed();

    let mut lines = Vec::new();
    for &(s, step) in &steps {
        lines.push(Line {
            t_us: s * 1_000_000,
            rank: 0,
            who: "script",
            text: step.say(),
        });
    }
    // The FC's view: healthy or not.
    for &(t, healthy) in o.fc.health_log() {
        lines.push(Line {
            t_us: t,
            rank: 1,
            who: "FC",
            text: if healthy {
                format!("healthy: {} calls the mount healthy", P::DRIVER)
            } else {
                format!("NOT healthy: {} lost the mount", P::DRIVER)
            },
        });
    }
    let summary = story(&o, &steps, opts, recorded, &mut lines);

    // Frames on both links.
    let fc = [(Dir::FcIn, &o.wires.fc_in), (Dir::FcOut, &o.wires.fc_out)];
    fc_link_lines::<P::Frames>(fc, &steps, &mut lines);
    for (dir, from_pod, wire) in [
        (Dir::PodOut, false, &o.wires.pod_out),
        (Dir::PodIn, true, &o.wires.pod_in),
    ] {
        frame_lines(
            dir,
            &frames_of(K40tFraming::any(), &wire.log),
            describe_k40t,
            |id| k40t_routine(id, from_pod),
            pod_anytime,
            &steps,
            &mut lines,
        );
    }
    if o.telemetry.is_some() {
        let telemetry = [
            (Dir::TelIn, &o.wires.tel_in),
            (Dir::TelOut, &o.wires.tel_out),
        ];
        fc_link_lines::<MavlinkFrames>(telemetry, &steps, &mut lines);
    }
    lines.sort_by_key(|l| (l.t_us, l.rank));

    writeln!(
        out,
        "gimbal demo: {} ⇄ the bridge's firmware tasks (fc = {}) ⇄ K40T pod (simulated)",
        P::DRIVER,
        fc_name(P::PROTOCOL)
    )?;
    writeln!(
        out,
        "{} s of simulated time; FC link {} baud, pod link {} baud{}; time in simulated seconds\n",
        opts.seconds,
        fc_baud,
        pod_baud,
        if o.telemetry.is_some() {
            "; the same ArduPilot's MAVLink port on the telemetry link"
        } else {
            ""
        }
    )?;
    for l in &lines {
        writeln!(
            out,
            "{:>8.3}  {:<13} {}",
            l.t_us as f64 / 1e6,
            l.who,
            l.text
        )?;
    }
    write_summary(out, &summary, wall)?;
    Ok(summary)
}

/// Engine events, time syncs, geotags and photos as lines; the summary's figures.
fn story<P: Pilot>(
    o: &Outcome<P, ApMavlink>,
    steps: &[(u64, Step)],
    opts: &DemoOptions,
    recorded: bool,
    lines: &mut Vec<Line>,
) -> Summary {
    let mut translated = 0u32;
    let mut translated_seen: Vec<(u16, u16)> = Vec::new();
    let mut shown_in_window: Vec<Vec<(u16, u16)>> = vec![Vec::new(); steps.len()];
    let mut clamped_shown = false;
    let edge_to_frame = o.edge_to_frame();
    let mut errors = Vec::new();
    let mut syncs = 0u32;
    let mut utc_valid_at_s = None;
    let mut telemetry_source_at_s = None;
    let mut first_sync: Option<(f64, i64)> = None;
    let mut pps_locked_at: Option<u64> = None;
    let mut pps_first_edge: Option<u64> = None;
    let mut first_pps_sync: Option<f64> = None;
    for (t, e) in o.events() {
        let text = match e {
            Event::Translated { fc_id, pod_base } => {
                translated += 1;
                let pair = (fc_id, pod_base);
                let first = !translated_seen.contains(&pair);
                if first {
                    translated_seen.push(pair);
                }
                let window = steps
                    .iter()
                    .position(|&(s, _)| (s * 1_000_000..s * 1_000_000 + WINDOW_US).contains(&t))
                    .and_then(|w| shown_in_window.get_mut(w));
                let in_window = match window {
                    Some(w) if !w.contains(&pair) => {
                        w.push(pair);
                        true
                    }
                    _ => false,
                };
                if !first && !in_window {
                    continue;
                }
                format!(
                    "translated {} → K40T 0x{pod_base:04X} {}",
                    P::Frames::command_name(fc_id),
                    k40t_name(pod_base)
                )
            }
            Event::RateClamped { requested_cdeg_s } => {
                if core::mem::replace(&mut clamped_shown, true) {
                    continue;
                }
                format!(
                    "rate clamped to the pod's 30 °/s (asked {:.1} °/s; shown once)",
                    f64::from(requested_cdeg_s) / 100.0
                )
            }
            Event::TimeSync {
                edge,
                utc_ms,
                error_bound_us,
            } => {
                syncs += 1;
                let edge_us = edge.as_micros();
                let err_ns = i128::from(utc_ms) * 1_000_000 - truth_ns(o, edge_us);
                let err = err_ns / 1_000;
                errors.push(u64::try_from(err_ns.unsigned_abs()).unwrap_or(u64::MAX));
                if pps_locked_at.is_some_and(|l| t >= l) {
                    first_pps_sync.get_or_insert(edge_us as f64 / 1e6);
                }
                first_sync
                    .get_or_insert((edge_us as f64 / 1e6, i64::try_from(err).unwrap_or(i64::MAX)));
                let delay = edge_to_frame
                    .iter()
                    .find(|(at, _, _)| *at == edge_us)
                    .map_or_else(
                        || "no frame recorded after the edge".to_string(),
                        |(_, d, len)| format!("{len} B, first byte {d} µs after the edge"),
                    );
                let pod = o
                    .pod
                    .syncs()
                    .iter()
                    .find(|s| s.edge_us == Some(edge_us) && s.unix_ms == utc_ms)
                    .map_or_else(
                        || "not seen by the pod".to_string(),
                        |s| format!("pod: {:?}", s.outcome),
                    );
                lines.push(Line {
                    t_us: edge_us,
                    rank: 2,
                    who: "time sync",
                    text: if o.pps.is_some() {
                        format!(
                            "RTC_IO high (timer compare), then 0x00030E ({delay}) carrying {}; error vs the GNSS's UTC {:+.3} µs (bound believed {} µs); {pod}",
                            utc_text(utc_ms),
                            err_ns as f64 / 1000.0,
                            error_bound_us
                        )
                    } else {
                        format!(
                            "RTC_IO high, then 0x00030E ({delay}) carrying {}; error vs the FC's true UTC {:+.3} ms (bound believed {:.1} ms); {pod}",
                            utc_text(utc_ms),
                            err as f64 / 1000.0,
                            f64::from(error_bound_us) / 1000.0
                        )
                    },
                });
                continue;
            }
            Event::Geotag { .. } | Event::Photo(_) => continue,
            Event::PpsLocked { first_edge } => {
                pps_locked_at.get_or_insert(t);
                pps_first_edge.get_or_insert(first_edge.as_micros());
                format!(
                    "PPS locked: the clock follows the GNSS module's pulse per second (first labelled edge at {:.3} s; the FC's UTC names the seconds)",
                    first_edge.as_micros() as f64 / 1e6
                )
            }
            Event::PpsHoldover => {
                "PPS lost: the clock runs on at the pulses' last rate (holdover)".to_string()
            }
            Event::PpsReleased => "PPS released: the clock follows the FC's UTC again".to_string(),
            Event::FcLinkUp => "FC link up (first valid frame from the FC)".to_string(),
            Event::FcLinkDown => "FC link DOWN (no valid frame from the FC)".to_string(),
            Event::PodLinkUp => "pod link up (first report from the pod)".to_string(),
            Event::PodLinkDown => "pod link DOWN (no report from the pod)".to_string(),
            Event::UtcValid {
                error_bound_us,
                converged,
            } => {
                utc_valid_at_s.get_or_insert(t as f64 / 1e6);
                format!(
                    "UTC known ({}, error bound {:.1} ms): time syncs on the 10 s grid",
                    if converged {
                        "converged fit"
                    } else {
                        "first mapping, refined as samples come"
                    },
                    f64::from(error_bound_us) / 1000.0
                )
            }
            Event::UtcLost => "UTC lost: no more time syncs".to_string(),
            Event::TimeSource { telemetry } => {
                if telemetry {
                    telemetry_source_at_s.get_or_insert(t as f64 / 1e6);
                    "time and fixes now from the telemetry link (TIMESYNC + SYSTEM_TIME, GLOBAL_POSITION_INT): the FC link's own time is no longer used".to_string()
                } else {
                    "time and fixes from the FC link again (the telemetry link stopped giving time)"
                        .to_string()
                }
            }
            Event::FcSilenceStop => {
                "the FC went silent while the pod turned: pod stopped".to_string()
            }
            Event::NoTimeOrFixes { .. } => "the autopilot's link gives no time and no \
                position (PX4 1.16 in mode Gimbal): no time syncs, no geotags; set it to mode \
                Normal or connect the telemetry link"
                .to_string(),
            other => format!("{other:?}"),
        };
        lines.push(Line {
            t_us: t,
            rank: 2,
            who: "bridge",
            text,
        });
    }

    // Photos and their geotags, from the pod's records.
    let mut geotag_error_max_m: Option<f64> = None;
    let mut answered = 0u32;
    for p in o.pod.photos() {
        lines.push(Line {
            t_us: p.at_us,
            rank: 2,
            who: "pod",
            text: format!("photo taken (pod clock {})", utc_text(p.pod_unix_ms)),
        });
    }
    for req in o.pod.gps_requests() {
        let tod = u32::try_from(req.pod_unix_ms % 86_400_000).unwrap_or_default();
        let reply = req.reply.and_then(|i| o.pod.gps_replies().get(i));
        let text = match reply {
            Some(r) if r.reply.code.code() == protocol_core::k40t::AckCode::Ok => {
                answered += 1;
                let fix = (r.reply.lat_e7, r.reply.lon_e7);
                let at = req
                    .photo
                    .and_then(|i| o.pod.photos().get(i))
                    .map_or(req.at_us, |p| p.at_us);
                let off = metres_apart(fix, o.fc.aircraft().position_e7(at));
                geotag_error_max_m = Some(geotag_error_max_m.map_or(off, |m| m.max(off)));
                format!(
                    "pod asks where the aircraft was at {}: lat {:.7} lon {:.7} alt {:.1} m ({}; {:.2} m from the true position), answered {} ms later",
                    time_of_day_text(tod),
                    f64::from(fix.0) * 1e-7,
                    f64::from(fix.1) * 1e-7,
                    f64::from(r.reply.alt_msl_dm) / 10.0,
                    if P::PROTOCOL == FcProtocol::K40t {
                        "the FC's answer, forwarded"
                    } else {
                        "interpolated between the FC's fixes"
                    },
                    off,
                    r.latency_us.unwrap_or_default() / 1000
                )
            }
            Some(r) => format!(
                "pod asks where the aircraft was at {}: no fix ({:?})",
                time_of_day_text(tod),
                r.reply.code.code()
            ),
            None => format!(
                "pod asks where the aircraft was at {}: no answer",
                time_of_day_text(tod)
            ),
        };
        lines.push(Line {
            t_us: req.at_us,
            rank: 2,
            who: "geotag",
            text,
        });
    }

    errors.sort_unstable();
    let c = o.engine.counters();
    Summary {
        fc: P::PROTOCOL,
        seconds: opts.seconds,
        telemetry: o.telemetry.is_some(),
        pps: o.pps.is_some(),
        pps_locked_at_s: pps_locked_at.map(|t| t as f64 / 1e6),
        pps_first_edge_at_s: pps_first_edge.map(|t| t as f64 / 1e6),
        first_pps_sync_at_s: first_pps_sync,
        telemetry_source_at_s,
        healthy_at_s: o
            .fc
            .health_log()
            .iter()
            .find(|(_, h)| *h)
            .map(|(t, _)| *t as f64 / 1e6),
        healthy_at_end: o.fc.healthy(),
        commands_translated: translated,
        command_kinds: translated_seen.len() as u32,
        fc_first_utc_at_s: match &o.telemetry {
            Some(t) => t.first_utc_sent_us(),
            None => o.fc.first_utc_sent_us(),
        }
        .map(|t| t as f64 / 1e6),
        utc_valid_at_s,
        first_sync_at_s: first_sync.map(|(t, _)| t),
        first_sync_error_us: first_sync.map(|(_, e)| e),
        syncs,
        syncs_applied: o
            .pod
            .syncs()
            .iter()
            .filter(|s| s.outcome == crate::sim::pod::SyncOutcome::Applied)
            .count() as u32,
        sync_error_p50_us: quantile(&errors, 0.5).map(|ns| (ns + 500) / 1_000),
        sync_error_max_us: errors.last().map(|ns| (ns + 500) / 1_000),
        sync_error_p50_ns: quantile(&errors, 0.5),
        sync_error_max_ns: errors.last().copied(),
        edge_to_frame_max_us: edge_to_frame.iter().map(|(_, d, _)| *d).max(),
        geotags_requested: o.pod.gps_requests().len() as u32,
        geotags_answered: answered,
        geotag_error_max_m,
        photos: o.pod.photos().len() as u32,
        recorded,
        bytes_fc_to_bridge: o.wires.fc_in.bytes,
        bytes_bridge_to_fc: o.wires.fc_out.bytes,
        bytes_pod_to_bridge: o.wires.pod_in.bytes,
        bytes_bridge_to_pod: o.wires.pod_out.bytes,
        frames_dropped: c.dropped,
        records_dropped: o.records_dropped,
    }
}

fn write_summary(out: &mut dyn Write, s: &Summary, wall: std::time::Duration) -> io::Result<()> {
    let ms = |us: Option<u64>| {
        us.map_or_else(
            || "-".to_string(),
            |v| format!("{:.3} ms", v as f64 / 1000.0),
        )
    };
    writeln!(
        out,
        "\nsummary ({}, {} s simulated in {:.2} s of wall time)",
        fc_name(s.fc),
        s.seconds,
        wall.as_secs_f64()
    )?;
    let rows: Vec<(&str, String)> = vec![
        (
            "FC healthy at",
            match s.healthy_at_s {
                Some(t) => format!(
                    "{t:.3} s ({} at the end)",
                    if s.healthy_at_end {
                        "still healthy"
                    } else {
                        "NOT healthy"
                    }
                ),
                None => "never".to_string(),
            },
        ),
        (
            "commands translated",
            format!("{} ({} kinds)", s.commands_translated, s.command_kinds),
        ),
        (
            "time syncs",
            if s.pps {
                let us = |ns: Option<u64>| {
                    ns.map_or_else(|| "-".to_string(), |v| format!("{:.3} µs", v as f64 / 1e3))
                };
                format!(
                    "{} sent, {} applied by the pod; error p50 {}, max {} (against the GNSS's UTC)",
                    s.syncs,
                    s.syncs_applied,
                    us(s.sync_error_p50_ns),
                    us(s.sync_error_max_ns)
                )
            } else {
                format!(
                    "{} sent, {} applied by the pod; error p50 {}, max {}",
                    s.syncs,
                    s.syncs_applied,
                    ms(s.sync_error_p50_us),
                    ms(s.sync_error_max_us)
                )
            },
        ),
        (
            "PPS",
            match (s.pps, s.pps_locked_at_s, s.pps_first_edge_at_s) {
                (false, _, _) => "none (the FC's UTC alone)".to_string(),
                (true, Some(l), Some(e)) => format!(
                    "locked at {l:.3} s (first labelled edge at {e:.3} s); first PPS-locked sync at {}",
                    s.first_pps_sync_at_s.map_or_else(
                        || "-".to_string(),
                        |t| format!("{t:.3} s ({:.1} s after the first labelled edge)", t - e)
                    )
                ),
                (true, _, _) => "never locked".to_string(),
            },
        ),
        (
            "time source",
            if s.telemetry {
                format!(
                    "telemetry link (MAVLink TIMESYNC + SYSTEM_TIME) from {}",
                    s.telemetry_source_at_s
                        .map_or_else(|| "never".to_string(), |t| format!("{t:.3} s"))
                )
            } else {
                format!("the FC link's own time ({})", fc_name(s.fc))
            },
        ),
        (
            "first time sync",
            match (s.first_sync_at_s, s.first_sync_error_us) {
                (Some(t), Some(e)) => format!(
                    "{t:.3} s ({} after the FC's first UTC at {}; the bridge knew UTC at {}), error {:+.3} ms",
                    s.fc_first_utc_at_s
                        .map_or_else(|| "-".to_string(), |u| format!("{:.1} s", t - u)),
                    s.fc_first_utc_at_s
                        .map_or_else(|| "-".to_string(), |u| format!("{u:.3} s")),
                    s.utc_valid_at_s
                        .map_or_else(|| "-".to_string(), |u| format!("{u:.3} s")),
                    e as f64 / 1000.0
                ),
                _ => "none".to_string(),
            },
        ),
        (
            "RTC_IO edge → 0x00030E",
            format!("max {}", ms(s.edge_to_frame_max_us)),
        ),
        (
            "geotags answered",
            format!(
                "{} of {}{}",
                s.geotags_answered,
                s.geotags_requested,
                s.geotag_error_max_m.map_or_else(String::new, |m| format!(
                    " (fix within {m:.2} m of the truth)"
                ))
            ),
        ),
        (
            "photos / recording",
            format!(
                "{} photos taken by the pod; {}",
                s.photos,
                if s.recorded {
                    "video recorded"
                } else {
                    "no video"
                }
            ),
        ),
        (
            "bytes FC link",
            format!(
                "{} FC → bridge, {} bridge → FC",
                s.bytes_fc_to_bridge, s.bytes_bridge_to_fc
            ),
        ),
        (
            "bytes pod link",
            format!(
                "{} pod → bridge, {} bridge → pod",
                s.bytes_pod_to_bridge, s.bytes_bridge_to_pod
            ),
        ),
        (
            "dropped",
            format!(
                "{} frames, {} log records",
                s.frames_dropped, s.records_dropped
            ),
        ),
    ];
    for (k, v) in rows {
        writeln!(out, "  {k:<24} {v}")?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn utc_text_reads_as_a_calendar_date() {
        assert_eq!(utc_text(0), "1970-01-01T00:00:00.000Z");
        assert_eq!(utc_text(1_795_428_040_000), "2026-11-23T10:00:40.000Z");
        assert_eq!(utc_text(951_782_400_123), "2000-02-29T00:00:00.123Z");
    }

    #[test]
    fn the_script_fits_the_run() {
        assert!(script(30).iter().all(|&(t, _)| t < 30));
        assert_eq!(script(60).len(), 10);
        assert!(
            script(60)
                .iter()
                .filter(|(_, s)| matches!(s, Step::Photo))
                .all(|&(t, _)| t > 10)
        );
        assert_eq!(script(100).len(), 13);
    }
}
