//! The real firmware binary on QEMU's `b-l475e-iot01a` between the simulated peers, on
//! wall-clock time (the `qemu-e2e` binary; `scripts/qemu-e2e`).
//!
//! One [`run`] starts `qemu-system-arm` with the `qemu` flavour of bridge-fw (built with every
//! FC side), the FC side chosen through the strap levels on the semihosting command line
//! (`straps=AB` or `straps=ABC`, see `bridge-fw/src/board.rs`), UART4 (FC) and USART2 (pod) on Unix-socket
//! chardevs and QEMU's `stm32l4x5_gpio_write` trace in a file. Two threads per socket move
//! the bytes between the socket and the host pipes of `bridge_fw::host`; one executor on
//! real time runs the simulated FC driver and the simulated pod (`sim::peer::run_peer`)
//! and a script that drives the FC and checks, in order: the firmware boots as that side,
//! the FC simulator reaches healthy, a command reaches the pod with the right fields,
//! telemetry from the pod comes back to the FC simulator, [`SYNCS`] times an RTC_IO High
//! edge (GPIOD pin 14 in the trace) precedes a valid 0x00030E on the pod socket that
//! carries the FC's UTC at the edge within 30 ms, the bytes on both links were all valid
//! and QEMU still runs.
//!
//! The SIYI scenario also wires the telemetry link (LPUART1, the sixth `-serial`) to the
//! same autopilot's MAVLink 2 port (`ApMavlink`, no MAVLink mount or camera, the SIYI
//! simulator's clock): the firmware's HEARTBEAT (component 158) and TIMESYNC requests
//! must reach it and the firmware must take its time from it (its semihosting line
//! `time source telemetry`), so the time syncs checked are then the telemetry link's.
//!
//! RTC_IO reaches the simulated pod from the trace file: the file is read every few
//! milliseconds, and always just before bytes from the pod socket are handed to the pod.
//! QEMU writes (and flushes) the trace line while the guest stores to BSRR, before the
//! guest goes on to write the 0x00030E to the USART, so an edge is always delivered
//! before the frame that follows it. QEMU stamps each trace line with the wall clock
//! (`-msg timestamp=on`): that stamp, not the moment the watch read the line, is the
//! edge's instant the time check compares against.
//!
//! Emulated time runs slower than wall time when the host is busy: every wait is a
//! generous time-out, and no check is on a duration (the durations are reported). The
//! one check on time is the product's: no 0x00030E more than 30 ms off the FC's UTC.

use core::cell::RefCell;
use core::convert::Infallible;
use std::fmt::Write as _;
use std::fs::File;
use std::io::{Read as _, Write as _};
use std::os::unix::net::UnixStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration as StdDuration, Instant as StdInstant};

use bridge_fw::host::{self, Clock, HostLinks, HostPipe};
use embassy_futures::select::{Either, select, select3};
use embassy_time::{Duration, Timer, with_timeout};
use protocol_core::k40t::{
    AckCode, GimbalAngle, GimbalAttitude, HybridZoom, HybridZoomAck, MessageData, PitchMotion,
    YawMotion,
};

use gimbal::sim::Autopilot;
use gimbal::sim::ap_mavlink::{ApMavlink, ApMavlinkConfig, ApMountTarget};
use gimbal::sim::ap_siyi::{ApSiyi, ApSiyiConfig, MountTarget};
use gimbal::sim::ap_viewpro::{ApViewpro, ApViewproConfig};
use gimbal::sim::ap_xfrobot::{self, ApXfRobot, ApXfRobotConfig};
use gimbal::sim::fc_k40t::FcK40t;
use gimbal::sim::peer::{PeerError, now_us, run_peer};
use gimbal::sim::pilot::Pilot;
use gimbal::sim::pod::{MotionCommand, PodSimConfig, SimPod, SyncOutcome};

/// Both links' baud rate (bridge.toml's `fc_baud` and `pod_baud`; QEMU's chardevs ignore it,
/// the simulators pace their output with it).
pub const BAUD: u32 = 115_200;

/// An FC side of the bridge.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// SIYI (ArduPilot `AP_Mount_Siyi`).
    Siyi,
    /// Viewlink (ArduPilot `AP_Mount_Viewpro`).
    Viewlink,
    /// XF Robot GCU (ArduPilot `AP_Mount_XFRobot`).
    Gcu,
    /// K40T spoken by the FC itself.
    K40t,
    /// MAVLink (ArduPilot `AP_Mount_MAVLink` + `AP_Camera_MAVLinkCamV2`).
    Mavlink,
}

impl Side {
    /// Every side, in the order the scenarios run.
    pub const ALL: [Side; 5] = [
        Side::Siyi,
        Side::Viewlink,
        Side::Gcu,
        Side::K40t,
        Side::Mavlink,
    ];

    /// The name the firmware prints and `bridge.toml` uses.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Side::Siyi => "siyi",
            Side::Viewlink => "viewlink",
            Side::Gcu => "gcu",
            Side::K40t => "k40t",
            Side::Mavlink => "mavlink",
        }
    }

    /// The side named `name`.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Side> {
        Side::ALL.into_iter().find(|s| s.name() == name)
    }

    /// The scenario also runs the MAVLink telemetry link (the SIYI side: one autopilot on
    /// its SIYI port and its MAVLink port).
    #[must_use]
    pub fn telemetry(self) -> bool {
        self == Side::Siyi
    }

    /// Checks of a complete scenario of this side.
    #[must_use]
    pub fn checks(self) -> usize {
        CHECKS + usize::from(self.telemetry())
    }

    /// The strap levels that select this side (A, B, then C when grounded; `0` grounded,
    /// `1` open: the firmware's `config::from_straps`).
    #[must_use]
    pub fn straps(self) -> &'static str {
        match self {
            Side::Siyi => "11",
            Side::Viewlink => "01",
            Side::Gcu => "10",
            Side::K40t => "00",
            Side::Mavlink => "110",
        }
    }
}

/// What a run needs.
#[derive(Debug, Clone)]
pub struct Options {
    /// The QEMU executable.
    pub qemu: PathBuf,
    /// The firmware (`qemu` flavour, every FC side).
    pub elf: PathBuf,
    /// The whole scenario's time-out (wall clock).
    pub timeout: StdDuration,
    /// Where the run's files go (sockets, trace, QEMU output); created.
    pub work: PathBuf,
}

/// One check of a scenario.
#[derive(Debug, Clone)]
pub struct Check {
    /// What was checked.
    pub name: &'static str,
    /// Every check of the scenario passed.
    pub ok: bool,
    /// The figures or the reason.
    pub detail: String,
}

/// The result of one scenario.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The side.
    pub side: Side,
    /// Every check, in order (a check not reached is absent).
    pub checks: Vec<Check>,
    /// Wall-clock duration of the scenario.
    pub wall: StdDuration,
    /// QEMU's output (semihosting lines, errors).
    pub qemu_out: PathBuf,
    /// The GPIO trace.
    pub trace: PathBuf,
}

impl Outcome {
    /// Every check passed and none is missing.
    #[must_use]
    pub fn passed(&self) -> bool {
        self.checks.len() == self.side.checks() && self.checks.iter().all(|c| c.ok)
    }
}

/// The 0x00030E's time against the FC's UTC at the edge, largest accepted error (the
/// product's: no time stamp off by 30 ms or more).
const MAX_UTC_ERROR_US: i128 = 30_000;

/// Time syncs each scenario checks (one every 10 s from the first).
pub const SYNCS: usize = 3;

/// How many checks a complete scenario has (one more with the telemetry link:
/// [`Side::telemetry`]).
pub const CHECKS: usize = 7;

/// The new level of `pin` if the traced write `line` sets it on `port` (QEMU's
/// `stm32l4x5_gpio_write <port> addr: 0x.. val: 0x..`): BSRR (0x18: set bits 0..15, reset
/// bits 16..31, set wins), BRR (0x28) and ODR (0x14). `None` for any other line or write.
#[must_use]
pub fn pin_write(line: &str, port: &str, pin: u32) -> Option<bool> {
    let rest = line.split("stm32l4x5_gpio_write ").nth(1)?;
    let mut words = rest.split_whitespace();
    if words.next()? != port || words.next()? != "addr:" {
        return None;
    }
    let addr = parse_hex(words.next()?)?;
    if words.next()? != "val:" {
        return None;
    }
    let val = parse_hex(words.next()?)?;
    let bit = |n: u32| n < 32 && val & (1 << n) != 0;
    match addr {
        0x18 if bit(pin) => Some(true),
        0x18 if bit(pin + 16) => Some(false),
        0x28 if bit(pin) => Some(false),
        0x14 => Some(bit(pin)),
        _ => None,
    }
}

/// The wall-clock instant (µs since the Unix epoch) QEMU stamped a trace line with
/// (`-msg timestamp=on`: `<pid>@<seconds>.<microseconds>:<event> ...`), if it has one.
#[must_use]
pub fn trace_stamp_us(line: &str) -> Option<u64> {
    let (head, _) = line.split_once(':')?;
    let (_, stamp) = head.split_once('@')?;
    let (secs, micros) = stamp.split_once('.')?;
    if micros.len() != 6 {
        return None;
    }
    let secs: u64 = secs.parse().ok()?;
    let micros: u64 = micros.parse().ok()?;
    secs.checked_mul(1_000_000)?.checked_add(micros)
}

/// The offset from the simulators' clock ([`now_us`]) to the wall clock (µs since the
/// Unix epoch), read back to back a few times, the tightest pair kept (to a few µs).
fn wall_offset_us() -> i128 {
    let mut best: Option<(u64, i128)> = None;
    for _ in 0..8 {
        let a = now_us();
        let wall = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_micros());
        let b = now_us();
        let spread = b.saturating_sub(a);
        let offset = i128::try_from(wall).unwrap_or(0) - i128::from(a / 2 + b / 2);
        if best.is_none_or(|(s, _)| spread < s) {
            best = Some((spread, offset));
        }
    }
    best.map_or(0, |(_, o)| o)
}

fn parse_hex(s: &str) -> Option<u32> {
    u32::from_str_radix(s.strip_prefix("0x")?, 16).ok()
}

/// RTC_IO (PD14) as QEMU's GPIO trace shows it, handed to the simulated pod.
struct TraceWatch {
    path: PathBuf,
    file: Option<File>,
    pending: Vec<u8>,
    level: bool,
    /// Every level change: when the watch saw it, the instant QEMU traced it (both on the
    /// simulators' clock), the new level.
    edges: Vec<Edge>,
    /// The simulators' clock to the wall clock of QEMU's trace stamps, µs.
    wall_offset_us: i128,
    /// LED2 (PB14): its level and the wall µs of its changes.
    led: bool,
    led_edges: Vec<(u64, bool)>,
}

/// One RTC_IO change seen in the trace.
#[derive(Debug, Clone, Copy)]
struct Edge {
    /// When the watch read it (µs, simulators' clock): what the simulated pod was told.
    seen_us: u64,
    /// When the guest wrote the pin, from QEMU's stamp on the trace line (µs, the
    /// simulators' clock; `None` for a line without a stamp). The reference instant of
    /// the time-sync check: the watch reads the file every 5 ms, later under load.
    traced_us: Option<u64>,
    level: bool,
}

impl TraceWatch {
    fn new(path: PathBuf) -> Self {
        TraceWatch {
            path,
            file: None,
            pending: Vec::new(),
            level: false,
            edges: Vec::new(),
            wall_offset_us: wall_offset_us(),
            led: false,
            led_edges: Vec::new(),
        }
    }

    /// The firmware's own view, from LED2's last blink pattern (`bridge_fw::led`: three
    /// flashes for the FC link, the pod link and UTC, long when up, short when down).
    fn led_status(&self) -> String {
        let flashes: Vec<u64> = self
            .led_edges
            .windows(2)
            .filter(|w| w[0].1 && !w[1].1)
            .map(|w| w[1].0.saturating_sub(w[0].0))
            .collect();
        let n = flashes.len();
        if n < 3 {
            return "LED: no full pattern".into();
        }
        // The pattern's first flash follows the longest dark gap (800 ms).
        let dark: Vec<(usize, u64)> = self
            .led_edges
            .windows(2)
            .filter(|w| !w[0].1 && w[1].1)
            .map(|w| w[1].0.saturating_sub(w[0].0))
            .enumerate()
            .collect();
        // Dark gap `i` comes before flash `i + 1`.
        let start = dark
            .iter()
            .rev()
            .skip_while(|(i, _)| i + 4 > n)
            .find(|(_, d)| *d > 500_000)
            .map_or(n - 3, |(i, _)| i + 1);
        let up = |i: usize| match flashes.get(i) {
            Some(&d) if d >= 150_000 => "up",
            Some(_) => "down",
            None => "?",
        };
        format!(
            "LED says FC {}, pod {}, UTC {}",
            up(start),
            up(start + 1),
            up(start + 2)
        )
    }

    /// Reads what QEMU appended and gives every RTC_IO change to `pod`, now.
    fn poll(&mut self, pod: &RefCell<SimPod>) {
        if self.file.is_none() {
            self.file = File::open(&self.path).ok();
        }
        let Some(file) = self.file.as_mut() else {
            return;
        };
        if file.read_to_end(&mut self.pending).is_err() {
            return;
        }
        while let Some(end) = self.pending.iter().position(|&b| b == b'\n') {
            let line: Vec<u8> = self.pending.drain(..=end).collect();
            let line = String::from_utf8_lossy(&line);
            if let Some(on) = pin_write(&line, "GPIOB", 14)
                && on != self.led
            {
                self.led = on;
                self.led_edges.push((now_us(), on));
            }
            if let Some(level) = pin_write(&line, "GPIOD", 14)
                && level != self.level
            {
                self.level = level;
                let t = now_us();
                // Traced before it was seen, by less than a second: else the wall clock
                // stepped since the offset was taken, and the stamp is not used.
                let traced_us = trace_stamp_us(&line)
                    .and_then(|wall| u64::try_from(i128::from(wall) - self.wall_offset_us).ok())
                    .filter(|&traced| traced <= t + 1_000 && t < traced + 1_000_000);
                self.edges.push(Edge {
                    seen_us: t,
                    traced_us,
                    level,
                });
                pod.borrow_mut().rtc_edge(t, level);
            }
        }
    }
}

/// The pod's end of the pod link: bytes from the bridge, RTC_IO changes first.
struct PodReader<'a> {
    pipe: &'a HostPipe,
    pod: &'a RefCell<SimPod>,
    trace: &'a RefCell<TraceWatch>,
}

impl embedded_io_async::ErrorType for PodReader<'_> {
    type Error = Infallible;
}

impl embedded_io_async::Read for PodReader<'_> {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
        let n = self.pipe.read(buf).await;
        // The edge that precedes these bytes is in the trace by now (see the module doc).
        self.trace.borrow_mut().poll(self.pod);
        Ok(n)
    }
}

/// Socket to pipe, until `stop` or the socket closes.
fn pump_in(sock: &UnixStream, pipe: &HostPipe, stop: &AtomicBool) {
    let mut sock = sock;
    let mut buf = [0u8; 256];
    while !stop.load(Ordering::Relaxed) {
        match sock.read(&mut buf) {
            Ok(0) => return,
            Ok(n) => {
                let mut rest = buf.get(..n).unwrap_or_default();
                while !rest.is_empty() && !stop.load(Ordering::Relaxed) {
                    match pipe.try_write(rest) {
                        Ok(k) => rest = rest.get(k..).unwrap_or_default(),
                        Err(_) => std::thread::sleep(StdDuration::from_millis(1)),
                    }
                }
            }
            Err(e)
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock
                        | std::io::ErrorKind::TimedOut
                        | std::io::ErrorKind::Interrupted
                ) => {}
            Err(_) => return,
        }
    }
}

/// Pipe to socket, until `stop` or the socket fails.
fn pump_out(sock: &UnixStream, pipe: &HostPipe, stop: &AtomicBool) {
    let mut sock = sock;
    let mut buf = [0u8; 256];
    while !stop.load(Ordering::Relaxed) {
        let read = host::block_on(with_timeout(
            Duration::from_millis(100),
            pipe.read(&mut buf),
        ));
        if let Ok(n) = read
            && sock.write_all(buf.get(..n).unwrap_or_default()).is_err()
        {
            return;
        }
    }
}

/// Sets the flag when dropped.
struct StopOnDrop<'a>(&'a AtomicBool);

impl Drop for StopOnDrop<'_> {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Relaxed);
    }
}

/// QEMU, killed when dropped.
struct Qemu(Child);

impl Qemu {
    fn running(&mut self) -> bool {
        matches!(self.0.try_wait(), Ok(None))
    }
}

impl Drop for Qemu {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn connect(path: &Path, qemu: &mut Qemu, deadline: StdInstant) -> Result<UnixStream, String> {
    loop {
        match UnixStream::connect(path) {
            Ok(s) => return Ok(s),
            Err(e) => {
                if !qemu.running() {
                    return Err(format!("QEMU ended before {} was up", path.display()));
                }
                if StdInstant::now() > deadline {
                    return Err(format!("{}: {e}", path.display()));
                }
                std::thread::sleep(StdDuration::from_millis(50));
            }
        }
    }
}

/// The last `lines` lines of a file (for a failure report).
#[must_use]
pub fn tail(path: &Path, lines: usize) -> String {
    let text = std::fs::read(path).unwrap_or_default();
    let text = String::from_utf8_lossy(&text);
    let all: Vec<&str> = text.lines().collect();
    all.get(all.len().saturating_sub(lines)..)
        .unwrap_or_default()
        .join("\n")
}

/// A step's verdict: not yet, not yet (with what was seen so far), passed (figures),
/// failed (why).
enum Step {
    Pending,
    Waiting(String),
    Pass(String),
    Fail(String),
}

/// What the script needs from an FC simulator.
trait FcUnderTest: Pilot {
    /// Settings for `side`.
    fn make() -> Self;
    /// Healthy (the driver's own notion; for a K40T FC: pod reports arrive).
    fn ready(&self) -> bool;
    /// Issues the command.
    fn command(&mut self);
    /// Whether the command reached the pod with the right fields.
    fn command_reached(&self, pod: &SimPod, since_us: u64) -> Step;
    /// Whether telemetry from the pod came back.
    fn telemetry(&self, pod: &SimPod) -> Step;
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

const TURN: MountTarget = MountTarget::Rate {
    yaw_dps: 20.0,
    pitch_dps: 0.0,
    yaw_is_ef: false,
};

/// Yaw read back, degrees: telemetry once the pod has turned right by `min`.
fn yaw_step(yaw: Option<f64>, min: f64) -> Step {
    match yaw {
        Some(y) if y >= min => Step::Pass(format!("FC reads yaw {y:.1} deg")),
        _ => Step::Pending,
    }
}

impl FcUnderTest for ApSiyi {
    fn make() -> Self {
        ApSiyi::new(ApSiyiConfig::default())
    }
    fn ready(&self) -> bool {
        self.healthy()
    }
    fn command(&mut self) {
        self.target = Some(TURN);
    }
    fn command_reached(&self, pod: &SimPod, since_us: u64) -> Step {
        control_step(pod, YawMotion::Right, since_us)
    }
    fn telemetry(&self, _pod: &SimPod) -> Step {
        yaw_step(self.attitude.map(|(_, yaw, _, _)| yaw), 5.0)
    }
}

impl FcUnderTest for ApViewpro {
    fn make() -> Self {
        ApViewpro::new(ApViewproConfig::default())
    }
    fn ready(&self) -> bool {
        self.healthy()
    }
    fn command(&mut self) {
        self.target = Some(TURN);
    }
    fn command_reached(&self, pod: &SimPod, since_us: u64) -> Step {
        control_step(pod, YawMotion::Right, since_us)
    }
    fn telemetry(&self, _pod: &SimPod) -> Step {
        yaw_step(self.attitude.map(|a| a.yaw_deg), 5.0)
    }
}

impl FcUnderTest for ApXfRobot {
    fn make() -> Self {
        ApXfRobot::new(ApXfRobotConfig::default())
    }
    fn ready(&self) -> bool {
        self.healthy()
    }
    fn command(&mut self) {
        self.target = Some(ap_xfrobot::MountTarget::Angle {
            roll_deg: 0.0,
            pitch_deg: -45.0,
            yaw_deg: 30.0,
            yaw_is_ef: false,
        });
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
    fn telemetry(&self, _pod: &SimPod) -> Step {
        yaw_step(self.attitude.map(|(_, _, _, yaw)| yaw), 10.0)
    }
}

impl FcUnderTest for ApMavlink {
    fn make() -> Self {
        ApMavlink::new(ApMavlinkConfig::default())
    }
    fn ready(&self) -> bool {
        self.healthy()
    }
    fn command(&mut self) {
        self.set_target(ApMountTarget::Rate {
            pitch_dps: 0.0,
            yaw_dps: 20.0,
            yaw_is_ef: false,
            from_mavlink: false,
        });
    }
    fn command_reached(&self, pod: &SimPod, since_us: u64) -> Step {
        control_step(pod, YawMotion::Right, since_us)
    }
    fn telemetry(&self, _pod: &SimPod) -> Step {
        yaw_step(self.attitude.map(|(_, _, _, yaw, _)| yaw), 5.0)
    }
}

/// The zoom the K40T FC asks for (×10).
const K40T_ZOOM_X10: u16 = 45;

impl FcUnderTest for FcK40t {
    fn make() -> Self {
        FcK40t::default()
    }
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

/// Runs the scenario of `side`. Never panics on what QEMU or the firmware do: every
/// failure is a failed check.
#[must_use]
pub fn run(side: Side, options: &Options) -> Outcome {
    match side {
        Side::Siyi => run_with::<ApSiyi>(side, options),
        Side::Viewlink => run_with::<ApViewpro>(side, options),
        Side::Gcu => run_with::<ApXfRobot>(side, options),
        Side::K40t => run_with::<FcK40t>(side, options),
        Side::Mavlink => run_with::<ApMavlink>(side, options),
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

fn run_with<F: FcUnderTest>(side: Side, o: &Options) -> Outcome {
    let start = StdInstant::now();
    let qemu_out = o.work.join("qemu.out");
    let trace = o.work.join("trace.log");
    let mut outcome = Outcome {
        side,
        checks: Vec::new(),
        wall: StdDuration::ZERO,
        qemu_out: qemu_out.clone(),
        trace: trace.clone(),
    };
    let fail = |outcome: &mut Outcome, name: &'static str, detail: String| {
        outcome.checks.push(Check {
            name,
            ok: false,
            detail,
        });
        outcome.wall = start.elapsed();
    };
    if let Err(e) = std::fs::create_dir_all(&o.work) {
        fail(&mut outcome, "boots", format!("{}: {e}", o.work.display()));
        return outcome;
    }
    let (fc_sock, pod_sock) = (o.work.join("fc.sock"), o.work.join("pod.sock"));
    let tel_sock = o.work.join("telemetry.sock");
    let _ = std::fs::remove_file(&fc_sock);
    let _ = std::fs::remove_file(&pod_sock);
    let _ = std::fs::remove_file(&tel_sock);
    let _ = std::fs::remove_file(&trace);
    let out = match File::create(&qemu_out).and_then(|f| Ok((f.try_clone()?, f))) {
        Ok(f) => f,
        Err(e) => {
            fail(
                &mut outcome,
                "boots",
                format!("{}: {e}", qemu_out.display()),
            );
            return outcome;
        }
    };
    let chardev =
        |id: &str, p: &Path| format!("socket,id={id},path={},server=on,wait=off", p.display());
    // -serial maps in order to USART1, USART2 (pod), USART3, UART4 (FC), UART5 and
    // LPUART1 (telemetry).
    let mut qemu_cmd = Command::new(&o.qemu);
    qemu_cmd
        .args([
            "-machine",
            "b-l475e-iot01a",
            "-nographic",
            "-monitor",
            "none",
        ])
        .arg("-semihosting-config")
        .arg(format!(
            "enable=on,target=native,arg=bridge-fw,arg=straps={}",
            side.straps()
        ))
        .arg("-chardev")
        .arg(chardev("pod", &pod_sock))
        .arg("-chardev")
        .arg(chardev("fc", &fc_sock))
        .args(["-serial", "null", "-serial", "chardev:pod"])
        .args(["-serial", "null", "-serial", "chardev:fc"]);
    if side.telemetry() {
        qemu_cmd
            .arg("-chardev")
            .arg(chardev("tel", &tel_sock))
            .args(["-serial", "null", "-serial", "chardev:tel"]);
    }
    let child = qemu_cmd
        .args(["-msg", "timestamp=on"])
        .args(["-trace", "enable=stm32l4x5_gpio_write", "-D"])
        .arg(&trace)
        .arg("-kernel")
        .arg(&o.elf)
        .stdin(Stdio::null())
        .stdout(out.0)
        .stderr(out.1)
        .spawn();
    let mut qemu = match child {
        Ok(c) => Qemu(c),
        Err(e) => {
            fail(&mut outcome, "boots", format!("{}: {e}", o.qemu.display()));
            return outcome;
        }
    };
    let deadline = start + o.timeout;
    let socks = connect(&pod_sock, &mut qemu, deadline)
        .and_then(|p| Ok((p, connect(&fc_sock, &mut qemu, deadline)?)));
    let (pod_stream, fc_stream) = match socks {
        Ok(s) => s,
        Err(e) => {
            fail(&mut outcome, "boots", e);
            return outcome;
        }
    };
    let tel_stream = if side.telemetry() {
        match connect(&tel_sock, &mut qemu, deadline) {
            Ok(s) => Some(s),
            Err(e) => {
                fail(&mut outcome, "boots", e);
                return outcome;
            }
        }
    } else {
        None
    };
    for s in [&pod_stream, &fc_stream].into_iter().chain(&tel_stream) {
        let _ = s.set_read_timeout(Some(StdDuration::from_millis(100)));
    }

    let links = if side.telemetry() {
        HostLinks::with_telemetry()
    } else {
        HostLinks::new()
    };
    let stop = AtomicBool::new(false);
    let qemu = RefCell::new(qemu);
    let checks = std::thread::scope(|scope| {
        let (l, st) = (&links, &stop);
        let (fs, ps) = (&fc_stream, &pod_stream);
        scope.spawn(move || pump_in(fs, &l.fc_tx, st));
        scope.spawn(move || pump_out(fs, &l.fc_rx, st));
        scope.spawn(move || pump_in(ps, &l.pod_tx, st));
        scope.spawn(move || pump_out(ps, &l.pod_rx, st));
        if let (Some(ts), Some(t)) = (&tel_stream, &l.telemetry) {
            scope.spawn(move || pump_in(ts, &t.tx, st));
            scope.spawn(move || pump_out(ts, &t.rx, st));
        }
        // The pumps stop however `drive` ends (a panic too: the scope joins them).
        let _stop = StopOnDrop(st);
        drive::<F>(side, &links, &qemu, &qemu_out, &trace, deadline)
    });
    outcome.checks = checks;
    outcome.wall = start.elapsed();
    outcome
}

/// The executor on real time: the peers, the trace watch and the script.
fn drive<F: FcUnderTest>(
    side: Side,
    links: &HostLinks,
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
        let traced = s.edge_us.and_then(|seen| {
            trace
                .edges
                .iter()
                .find(|e| e.level && e.seen_us == seen)
                .map(|e| e.traced_us.unwrap_or(seen))
        });
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

/// The autopilot's MAVLink port on the telemetry link: the same autopilot as the SIYI
/// simulator (`ApSiyiConfig::default()`: its clock and aircraft), no MAVLink mount or
/// camera.
fn telemetry_peer() -> ApMavlink {
    let siyi = ApSiyi::new(ApSiyiConfig::default());
    ApMavlink::telemetry(siyi.clock().clone(), siyi.aircraft, 1, 1)
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
    // 1. The boot line names the side the straps select.
    let boot = wait_for(qemu, deadline, || {
        let text = std::fs::read(qemu_out).unwrap_or_default();
        // Whole lines only: QEMU may be writing the boot line while it is read.
        let whole = text.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
        let text = String::from_utf8_lossy(text.get(..whole).unwrap_or_default());
        match text.lines().find(|l| l.contains("bridge-fw (qemu): up")) {
            None => Step::Pending,
            Some(l) if l.contains(&format!("FC \"{}\"", side.name())) => {
                Step::Pass(format!("{:.1} s, {}", secs_since(t0), l.trim()))
            }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gpio_trace_lines_give_the_pin_level_they_set() {
        let line = |addr: u32, val: u32| {
            format!("stm32l4x5_gpio_write GPIOD addr: {addr:#x} val: {val:#x}")
        };
        // BSRR: set (bit 14), reset (bit 30), both (set wins), another pin.
        assert_eq!(pin_write(&line(0x18, 0x4000), "GPIOD", 14), Some(true));
        assert_eq!(
            pin_write(&line(0x18, 0x4000_0000), "GPIOD", 14),
            Some(false)
        );
        assert_eq!(pin_write(&line(0x18, 0x4000_4000), "GPIOD", 14), Some(true));
        assert_eq!(pin_write(&line(0x18, 0x2000), "GPIOD", 14), None);
        // BRR and ODR.
        assert_eq!(pin_write(&line(0x28, 0x4000), "GPIOD", 14), Some(false));
        assert_eq!(pin_write(&line(0x14, 0x4001), "GPIOD", 14), Some(true));
        assert_eq!(pin_write(&line(0x14, 0x0001), "GPIOD", 14), Some(false));
        // Configuration writes, other ports, a timestamped line, garbage.
        assert_eq!(pin_write(&line(0x0, 0xffff_ffff), "GPIOD", 14), None);
        assert_eq!(
            pin_write(
                "stm32l4x5_gpio_write GPIOB addr: 0x18 val: 0x4000",
                "GPIOD",
                14
            ),
            None
        );
        assert_eq!(
            pin_write(
                "1234@1700000000.000001:stm32l4x5_gpio_write GPIOD addr: 0x18 val: 0x4000",
                "GPIOD",
                14
            ),
            Some(true)
        );
        assert_eq!(
            pin_write(
                "stm32l4x5_gpio_write GPIOD addr: zz val: 0x4000",
                "GPIOD",
                14
            ),
            None
        );
        assert_eq!(pin_write("", "GPIOD", 14), None);
    }

    #[test]
    fn trace_stamps_read_as_wall_clock_microseconds() {
        let line = "11054@1795551751.337070:stm32l4x5_gpio_write GPIOD addr: 0x18 val: 0x4000";
        assert_eq!(trace_stamp_us(line), Some(1_795_551_751_337_070));
        assert_eq!(pin_write(line, "GPIOD", 14), Some(true));
        // No stamp (QEMU without `-msg timestamp=on`), a malformed one.
        assert_eq!(
            trace_stamp_us("stm32l4x5_gpio_write GPIOD addr: 0x18 val: 0x4000"),
            None
        );
        assert_eq!(trace_stamp_us("1@17.5:stm32l4x5_gpio_write GPIOD"), None);
        assert_eq!(
            trace_stamp_us("1@x.000001:stm32l4x5_gpio_write GPIOD"),
            None
        );
    }

    #[test]
    fn the_led_pattern_reads_as_the_firmwares_status() {
        let mut t = TraceWatch::new(PathBuf::new());
        // Two patterns (FC up, pod down, UTC up): flashes of 300, 40, 300 ms, 100/360 ms
        // apart, 800 ms dark before each.
        let mut at = 0u64;
        for _ in 0..2 {
            at += 800_000;
            for (on, off) in [(300_000, 100_000), (40_000, 360_000), (300_000, 100_000)] {
                t.led_edges.push((at, true));
                at += on;
                t.led_edges.push((at, false));
                at += off;
            }
        }
        assert_eq!(t.led_status(), "LED says FC up, pod down, UTC up");
        assert_eq!(
            TraceWatch::new(PathBuf::new()).led_status(),
            "LED: no full pattern"
        );
    }

    #[test]
    fn each_sides_straps_select_it_in_the_firmware() {
        use bridge_engine::FcProtocol;
        for (side, protocol) in Side::ALL.into_iter().zip([
            FcProtocol::Siyi,
            FcProtocol::Viewlink,
            FcProtocol::Gcu,
            FcProtocol::K40t,
            FcProtocol::Mavlink,
        ]) {
            let grounded: Vec<bool> = side.straps().chars().map(|c| c == '0').collect();
            let c = grounded.get(2).copied().unwrap_or(false);
            assert_eq!(
                bridge_fw::config::from_straps(grounded[0], grounded[1], c),
                Some(protocol),
                "{side:?}"
            );
            assert_eq!(Side::from_name(side.name()), Some(side));
        }
        assert_eq!(Side::from_name("px4"), None);
    }
}
