//! The scenario: the simulated FC and pod on an executor on real time against the
//! firmware, and the script that drives the FC and checks, in order, what the crate's
//! documentation lists.

use core::cell::RefCell;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant as StdInstant;

use bridge_fw::host::{self, Clock, HostLinks, HostPipe};
use embassy_futures::select::{Either, select, select3};
use embassy_time::{Duration, Timer};
use protocol_core::k40t::{
    AckCode, GimbalAngle, GimbalAttitude, HybridZoom, HybridZoomAck, MessageData, PitchMotion,
    YawMotion,
};

use gimbal::sim::Autopilot;
use gimbal::sim::ap_mavlink::ApMavlink;
use gimbal::sim::ap_siyi::{ApSiyi, ApSiyiConfig};
use gimbal::sim::ap_viewpro::ApViewpro;
use gimbal::sim::ap_xfrobot::ApXfRobot;
use gimbal::sim::fc_k40t::FcK40t;
use gimbal::sim::peer::{PeerError, now_us, run_peer};
use gimbal::sim::pilot::Pilot;
use gimbal::sim::pod::{MotionCommand, PodSimConfig, SimPod, SyncOutcome};

use crate::qemu::Qemu;
use crate::trace::{PodReader, TraceWatch};
use crate::{BAUD, Check, SYNCS, Side};

/// The 0x00030E's time against the FC's UTC at the edge, largest accepted error (the
/// product's: no time stamp off by 30 ms or more).
const MAX_UTC_ERROR_US: i128 = 30_000;

/// A step's verdict: not yet, not yet (with what was seen so far), passed (figures),
/// failed (why).
pub(crate) enum Step {
    Pending,
    Waiting(String),
    Pass(String),
    Fail(String),
}

/// What the script needs from an FC simulator. By default: the simulator with its
/// default settings, ready when its driver calls the mount healthy, commanded to turn
/// right at 20°/s (a 0x000010 yaw Right, pitch Stop at the pod), its telemetry the yaw it
/// reads back once the pod has turned right by [`FcUnderTest::TELEMETRY_YAW_DEG`].
pub(crate) trait FcUnderTest: Pilot + Sized {
    /// The yaw (degrees) the FC must read back.
    const TELEMETRY_YAW_DEG: f64 = 5.0;

    /// The simulator with its default settings (seed 1).
    fn make() -> Self {
        Self::with_seed(1)
    }
    /// Healthy (the driver's own notion; for a K40T FC: pod reports arrive).
    fn ready(&self) -> bool {
        self.healthy()
    }
    /// Issues the command.
    fn command(&mut self) {
        self.turn(20.0, 0.0);
    }
    /// Whether the command reached the pod with the right fields.
    fn command_reached(&self, pod: &SimPod, since_us: u64) -> Step {
        control_step(pod, YawMotion::Right, since_us)
    }
    /// Whether telemetry from the pod came back.
    fn telemetry(&self, _pod: &SimPod) -> Step {
        yaw_step(
            self.mount_angles().map(|(yaw, _)| yaw),
            Self::TELEMETRY_YAW_DEG,
        )
    }
}

fn control_step(pod: &SimPod, yaw: YawMotion, since_us: u64) -> Step {
    let controls: Vec<_> = pod
        .motions()
        .iter()
        .filter(|m| m.at_us >= since_us)
        .filter_map(|m| match m.command {
            MotionCommand::Control(c) => Some(c),
            _ => None,
        })
        .collect();
    if controls
        .iter()
        .any(|c| c.yaw == yaw && c.pitch == PitchMotion::Stop)
    {
        Step::Pass(format!("0x000010 yaw {yaw:?} pitch Stop"))
    } else if let Some(c) = controls
        .iter()
        .find(|c| c.yaw != YawMotion::Stop && c.yaw != yaw)
    {
        Step::Fail(format!("0x000010 yaw {:?}, expected {yaw:?}", c.yaw))
    } else {
        controls
            .last()
            .map_or(Step::Pending, |c| Step::Waiting(format!("0x000010 {c:?}")))
    }
}

/// Yaw read back, degrees: telemetry once the pod has turned right by `min`.
fn yaw_step(yaw: Option<f64>, min: f64) -> Step {
    match yaw {
        Some(y) if y >= min => Step::Pass(format!("FC reads yaw {y:.1} deg")),
        _ => Step::Pending,
    }
}

impl FcUnderTest for ApSiyi {}

impl FcUnderTest for ApViewpro {}

impl FcUnderTest for ApMavlink {}

/// ArduPilot's XF Robot driver steers by angles: pointed at yaw 30°, pitch −45°.
impl FcUnderTest for ApXfRobot {
    const TELEMETRY_YAW_DEG: f64 = 10.0;

    fn command(&mut self) {
        self.point(30.0, -45.0);
    }
    fn command_reached(&self, pod: &SimPod, since_us: u64) -> Step {
        // ArduPilot sends its target from the start (0, 0 before this one).
        let angles: Vec<_> = pod
            .received_of::<GimbalAngle>()
            .into_iter()
            .filter(|(t, _, _)| *t >= since_us)
            .map(|(_, _, a)| (a.yaw_direction, a.yaw_cdeg, a.pitch_direction, a.pitch_cdeg))
            .collect();
        if angles.contains(&(YawMotion::Right, 3000, PitchMotion::Down, 4500)) {
            Step::Pass("0x000012 yaw Right 30.00 deg, pitch Down 45.00 deg".into())
        } else {
            angles
                .last()
                .map_or(Step::Pending, |a| Step::Waiting(format!("0x000012 {a:?}")))
        }
    }
}

/// The zoom the K40T FC asks for (×10).
const K40T_ZOOM_X10: u16 = 45;

impl FcUnderTest for FcK40t {
    fn ready(&self) -> bool {
        self.received_of::<GimbalAttitude>().len() >= 5
    }
    fn command(&mut self) {
        self.send(&HybridZoom {
            start: 0,
            zoom_x10: K40T_ZOOM_X10,
        });
    }
    fn command_reached(&self, pod: &SimPod, _since_us: u64) -> Step {
        match pod.received_of::<HybridZoom>().last() {
            None => Step::Pending,
            Some((_, _, z)) if z.zoom_x10 == K40T_ZOOM_X10 => {
                Step::Pass(format!("0x{:06X} zoom 4.5x", HybridZoom::ID.to_u32()))
            }
            Some((_, _, z)) => Step::Fail(format!("zoom_x10 {}", z.zoom_x10)),
        }
    }
    fn telemetry(&self, _pod: &SimPod) -> Step {
        let Some(&(_, seq, _)) = self
            .sent
            .iter()
            .rfind(|(_, _, id)| *id == HybridZoom::ID.to_u32())
        else {
            return Step::Pending;
        };
        match self.received_of::<HybridZoomAck>().last() {
            None => Step::Pending,
            Some((_, h, a)) if h.seq == seq && a.code.code() == AckCode::Ok => Step::Pass(format!(
                "ACK OK with the FC's seq {seq}, {} attitude reports",
                self.received_of::<GimbalAttitude>().len()
            )),
            Some((_, h, a)) => Step::Fail(format!("ACK seq {} code {:?}", h.seq, a.code)),
        }
    }
}

/// The simulated pod, with the generous time-outs emulated time needs: QEMU may spread a
/// frame's bytes over tens of milliseconds, and the edge-to-frame window is widened (the
/// delay is reported, not checked).
fn pod_config() -> PodSimConfig {
    PodSimConfig {
        rx_idle_timeout_us: 1_000_000,
        sync_window_us: 2_000_000,
        ..PodSimConfig::default()
    }
}

/// The executor on real time: the peers, the trace watch and the script.
pub(crate) fn drive<F: FcUnderTest>(
    side: Side,
    links: &HostLinks,
    pps: Option<&HostPipe>,
    qemu: &RefCell<Qemu>,
    qemu_out: &Path,
    trace_path: &Path,
    deadline: StdInstant,
) -> Vec<Check> {
    let fc = RefCell::new(F::make());
    let pod = RefCell::new(SimPod::new(pod_config()));
    let tel = RefCell::new(telemetry_peer());
    let trace = RefCell::new(TraceWatch::new(trace_path.to_path_buf()));
    let checks = RefCell::new(Vec::new());
    let peers_ended = host::run(Clock::Real, || async {
        let pod_reader = PodReader {
            pipe: &links.pod_tx,
            pod: &pod,
            trace: &trace,
        };
        let watch = async {
            loop {
                trace.borrow_mut().poll(&pod);
                Timer::after(Duration::from_millis(5)).await;
            }
        };
        let telemetry = async {
            match &links.telemetry {
                Some(t) => run_peer(&tel, &t.tx, &t.rx, BAUD).await,
                None => core::future::pending().await,
            }
        };
        // The PPS test source: a byte at each whole second of the FC's UTC.
        let pps_source = async {
            let Some(pipe) = pps else {
                return core::future::pending().await;
            };
            loop {
                let utc = fc.borrow().true_utc_us(now_us());
                let to_next = 1_000_000 - utc % 1_000_000;
                Timer::after(Duration::from_micros(to_next)).await;
                pipe.write_all(b"P").await;
            }
        };
        let watch = select(watch, pps_source);
        let peers = select3(
            run_peer(&fc, &links.fc_tx, &links.fc_rx, BAUD),
            run_peer(&pod, pod_reader, &links.pod_rx, BAUD),
            select(watch, telemetry),
        );
        let script = script(
            side, &fc, &pod, &tel, &trace, qemu, qemu_out, deadline, &checks,
        );
        match select(peers, script).await {
            Either::First(ended) => Some(ended),
            Either::Second(()) => None,
        }
    });
    let mut checks = checks.into_inner();
    if let Some(ended) = peers_ended {
        let why: Result<(), PeerError> = match ended {
            embassy_futures::select::Either3::First(Err(e))
            | embassy_futures::select::Either3::Second(Err(e))
            | embassy_futures::select::Either3::Third(Either::Second(Err(e))) => Err(e),
            _ => Ok(()),
        };
        checks.push(Check {
            name: "links",
            ok: false,
            detail: format!("a socket ended: {why:?} (QEMU ended?)"),
        });
    }
    checks
}

/// The time syncs so far: each must be applied by the pod (a traced High edge before its
/// first byte, within the window), in time zone 0, and carry the FC's UTC at the edge
/// within [`MAX_UTC_ERROR_US`]; [`SYNCS`] of them pass. The reference instant is the
/// edge as QEMU stamped it in the trace (the watch that tells the pod may see it
/// milliseconds later).
fn sync_step<F: FcUnderTest>(fc: &F, pod: &SimPod, trace: &TraceWatch, qemu_out: &Path) -> Step {
    let syncs = pod.syncs();
    if syncs.is_empty() {
        return Step::Waiting(trace.led_status());
    }
    let bounds = firmware_bounds(qemu_out);
    let mut errors = Vec::new();
    let mut delays = Vec::new();
    for (i, s) in syncs.iter().enumerate() {
        let traced = s.edge_us.and_then(|seen| trace.traced_high(seen));
        let (SyncOutcome::Applied, Some(edge)) = (s.outcome, traced) else {
            return Step::Fail(format!("sync {}: {s:?}", i + 1));
        };
        if s.tz_minuteswest != 0 {
            return Step::Fail(format!("sync {}: time zone {}", i + 1, s.tz_minuteswest));
        }
        let err_us = i128::from(s.unix_ms) * 1000 - i128::from(fc.true_utc_us(edge));
        let bound = bounds
            .iter()
            .find(|(ms, _)| *ms == s.unix_ms)
            .map_or(String::new(), |(_, b)| {
                format!(" (bound {:.1})", f64::from(*b) / 1000.0)
            });
        errors.push(format!("{:+.1}{bound}", err_us as f64 / 1000.0));
        if err_us.abs() >= MAX_UTC_ERROR_US {
            return Step::Fail(format!(
                "sync {}: UTC {:+.1} ms off the FC's at the edge (limit {} ms); so far {} ms",
                i + 1,
                err_us as f64 / 1000.0,
                MAX_UTC_ERROR_US / 1000,
                errors.join(", ")
            ));
        }
        delays.push(s.delay_us.unwrap_or(0));
    }
    let figures = format!(
        "{} sync(s), a traced High edge before each; UTC off the FC's at the edge by {} ms; \
         edge to frame at most {:.1} ms",
        syncs.len(),
        errors.join(", "),
        delays.iter().max().copied().unwrap_or(0) as f64 / 1000.0
    );
    if syncs.len() >= SYNCS {
        Step::Pass(figures)
    } else {
        Step::Waiting(figures)
    }
}

/// The error bounds the firmware believed for its time syncs, from its semihosting lines
/// (`... time sync, edge .. us, UTC <ms> ms, bound <µs> us`): (UTC ms, bound µs).
fn firmware_bounds(qemu_out: &Path) -> Vec<(u64, u32)> {
    let text = std::fs::read(qemu_out).unwrap_or_default();
    String::from_utf8_lossy(&text)
        .lines()
        .filter_map(|l| {
            let rest = l.split("time sync, edge ").nth(1)?;
            let utc = rest.split("UTC ").nth(1)?.split(' ').next()?.parse().ok()?;
            let bound = rest
                .split("bound ")
                .nth(1)?
                .split(' ')
                .next()?
                .parse()
                .ok()?;
            Some((utc, bound))
        })
        .collect()
}

/// The PPS test source locked the firmware's clock: its semihosting lines say `PPS
/// locked`, and a time sync followed (its bound is reported: what the firmware believes
/// of a PPS stamped by a task under QEMU, milliseconds).
fn pps_step(qemu_out: &Path) -> Step {
    let text = std::fs::read(qemu_out).unwrap_or_default();
    let text = String::from_utf8_lossy(&text);
    let Some(locked) = text.lines().position(|l| l.contains(": PPS locked")) else {
        return Step::Pending;
    };
    let after: Vec<&str> = text
        .lines()
        .skip(locked)
        .filter(|l| l.contains("time sync, edge "))
        .filter_map(|l| l.split("bound ").nth(1))
        .collect();
    match after.first() {
        Some(bound) => Step::Pass(format!(
            "locked; {} sync(s) since, the first with a bound of {}",
            after.len(),
            bound.trim()
        )),
        None => Step::Waiting("locked, no sync since yet".into()),
    }
}

/// The autopilot's MAVLink port on the telemetry link: the same autopilot as the SIYI
/// simulator (`ApSiyiConfig::default()`: its clock and aircraft), no MAVLink mount or
/// camera.
fn telemetry_peer() -> ApMavlink {
    let siyi = ApSiyi::new(ApSiyiConfig::default());
    ApMavlink::telemetry(siyi.clock().clone(), *siyi.aircraft(), 1, 1)
}

/// The telemetry link works: the autopilot heard the firmware's HEARTBEAT (component
/// 158) and TIMESYNC requests, answered none wrongly, and the firmware says its time
/// source is the telemetry link (semihosting `time source telemetry`).
fn telemetry_step(ap: &ApMavlink, qemu_out: &Path) -> Step {
    const BRIDGE: u8 = 158;
    let from_bridge = |id: u32| {
        ap.received
            .iter()
            .filter(|(_, h, i)| h.component_id == BRIDGE && *i == id)
            .count()
    };
    let (heartbeats, timesyncs) = (from_bridge(0), from_bridge(111));
    let text = std::fs::read(qemu_out).unwrap_or_default();
    let source = String::from_utf8_lossy(&text)
        .lines()
        .rfind(|l| l.contains("time source "))
        .map(str::to_owned);
    let figures = format!(
        "{heartbeats} HEARTBEAT and {timesyncs} TIMESYNC from component 158 at the autopilot, \
         {} frames in all; {}",
        ap.received.len(),
        source.as_deref().map_or("no time source line", |l| l
            .split("bridge-fw (qemu): ")
            .nth(1)
            .unwrap_or(l))
    );
    let telemetry_source = source.is_some_and(|l| l.ends_with("time source telemetry"));
    if heartbeats > 0 && timesyncs > 0 && telemetry_source {
        Step::Pass(figures)
    } else {
        Step::Waiting(figures)
    }
}

/// Waits (polling every 100 ms) until `f` decides, QEMU ends or the deadline passes.
async fn wait_for(
    qemu: &RefCell<Qemu>,
    deadline: StdInstant,
    mut f: impl FnMut() -> Step,
) -> Result<String, String> {
    let mut seen = String::new();
    loop {
        match f() {
            Step::Pass(s) => return Ok(s),
            Step::Fail(s) => return Err(s),
            Step::Pending => {}
            Step::Waiting(s) => seen = s,
        }
        let suffix = if seen.is_empty() {
            String::new()
        } else {
            format!(" (last seen: {seen})")
        };
        if !qemu.borrow_mut().running() {
            return Err(format!("QEMU ended{suffix}"));
        }
        if StdInstant::now() > deadline {
            return Err(format!("time-out{suffix}"));
        }
        Timer::after(Duration::from_millis(100)).await;
    }
}

fn secs_since(t0_us: u64) -> f64 {
    now_us().saturating_sub(t0_us) as f64 / 1e6
}

#[allow(clippy::too_many_arguments)]
async fn script<F: FcUnderTest>(
    side: Side,
    fc: &RefCell<F>,
    pod: &RefCell<SimPod>,
    tel: &RefCell<ApMavlink>,
    trace: &RefCell<TraceWatch>,
    qemu: &RefCell<Qemu>,
    qemu_out: &Path,
    deadline: StdInstant,
    checks: &RefCell<Vec<Check>>,
) {
    let push = |name: &'static str, r: Result<String, String>| -> bool {
        let ok = r.is_ok();
        let detail = r.unwrap_or_else(|e| e);
        checks.borrow_mut().push(Check { name, ok, detail });
        ok
    };
    let t0 = now_us();
    // 1. The bootloader's line, then the firmware's boot line naming the side the straps
    //    select.
    let boot = wait_for(qemu, deadline, || {
        let text = std::fs::read(qemu_out).unwrap_or_default();
        // Whole lines only: QEMU may be writing the boot line while it is read.
        let whole = text.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
        let text = String::from_utf8_lossy(text.get(..whole).unwrap_or_default());
        match text.lines().find(|l| l.contains("bridge-fw (qemu): up")) {
            None => Step::Pending,
            Some(_) if !text.contains("bootloader: boot, active slot at 0x0800a000") => {
                Step::Fail("the firmware ran without the bootloader's line before it".into())
            }
            Some(l) if l.contains(&format!("FC \"{}\"", side.name())) => Step::Pass(format!(
                "{:.1} s, through the bootloader, {}",
                secs_since(t0),
                l.trim()
            )),
            Some(l) => Step::Fail(l.trim().to_string()),
        }
    })
    .await;
    if !push("boots as the side", boot) {
        return;
    }
    // 2. The FC simulator reaches healthy.
    let healthy = wait_for(qemu, deadline, || {
        if fc.borrow().ready() {
            Step::Pass(format!("{:.1} s", secs_since(t0)))
        } else {
            Step::Pending
        }
    })
    .await;
    if !push("FC healthy", healthy) {
        return;
    }
    // 3. A command reaches the pod with the right fields.
    fc.borrow_mut().command();
    let t_cmd = now_us();
    let command = wait_for(qemu, deadline, || {
        match fc.borrow().command_reached(&pod.borrow(), t_cmd) {
            Step::Pass(s) => Step::Pass(format!("{s} after {:.2} s", secs_since(t_cmd))),
            other => other,
        }
    })
    .await;
    if !push("command reaches the pod", command) {
        return;
    }
    // 4. Telemetry comes back.
    let telemetry = wait_for(qemu, deadline, || fc.borrow().telemetry(&pod.borrow())).await;
    if !push("telemetry back to the FC", telemetry) {
        return;
    }
    // 5. RTC_IO High edges, each followed by a valid 0x00030E carrying the FC's UTC at
    // the edge, SYNCS times.
    let sync = wait_for(qemu, deadline, || {
        sync_step(&*fc.borrow(), &pod.borrow(), &trace.borrow(), qemu_out)
    })
    .await;
    if !push("RTC_IO High, then 0x00030E", sync) {
        return;
    }
    // (GCU) The PPS test source: the firmware labelled its edges from the FC's UTC, locked
    // its clock to them, and a time sync followed the lock (the syncs' UTC is checked
    // above, to 30 ms of the FC's, as on every side).
    if side.pps() {
        let locked = wait_for(qemu, deadline, || pps_step(qemu_out)).await;
        if !push("PPS locked", locked) {
            return;
        }
    }
    // (SIYI) The telemetry link: the firmware's HEARTBEAT and TIMESYNC requests reached
    // the autopilot's MAVLink port and the firmware took its time from it.
    if side.telemetry() {
        let link = wait_for(qemu, deadline, || telemetry_step(&tel.borrow(), qemu_out)).await;
        if !push("telemetry link", link) {
            return;
        }
    }
    // 6. Every byte on every link made valid frames.
    let errors = fc.borrow().parse_errors() + tel.borrow().parse_errors();
    let rx = pod.borrow().rx_stats();
    let d = rx.deframer;
    let mut detail = String::new();
    let _ = write!(
        detail,
        "FC parser errors {errors}; pod: {} frames, {} checksum / {} length errors, {} \
         stray bytes, {} malformed",
        rx.frames, d.checksum_errors, d.length_errors, d.bytes_discarded, rx.malformed
    );
    let clean = errors == 0
        && d.checksum_errors == 0
        && d.length_errors == 0
        && d.bytes_discarded == 0
        && rx.malformed == 0;
    push(
        "frames all valid",
        if clean { Ok(detail) } else { Err(detail) },
    );
    // 7. QEMU still runs (no fault, no panic: both end it).
    let running = qemu.borrow_mut().running();
    push(
        "still running",
        if running {
            Ok(format!("{:.1} s of wall time", secs_since(t0)))
        } else {
            Err("QEMU ended".into())
        },
    );
}
