//! `gimbal bridge`: the firmware's own tasks (`bridge_fw::host::bridge`: both links, the
//! engine/timer task with the RTC_IO pin, the log and watchdog tasks) on the host's real
//! clock, with std threads pumping serial devices and TCP connections into their pipes,
//! or the simulators on the same executor for `sim` ports. `--fc-faults` and
//! `--pod-faults` make a cable faulty (a seeded fault model in both directions): in the
//! port's threads for a real port, in a [`Wire`] between the simulator and the bridge
//! for `sim`.

use core::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};

use bridge_engine::{Config, Duration, Engine, Event};
use bridge_fw::host::{self, Clock, HostLinks, HostShared};
use bridge_fw::{ConsoleEnd, LogKind, LogRecord, Timing};
use embassy_futures::select::{Either, Either4, select, select4};
use embassy_time::{Duration as EmbassyDuration, Timer};
use serde_json::{Value, json};
use toml::Table;

use super::event_name::EventName;
use super::events;
use super::output::{Output, now_us, wants_status_line};
use super::photos::PhotoEvents;
use super::pin::{GpioLine, RtcSpec, RunnerPin};
use super::port::{self, CableFaults, Pump, port_baud, stats_json};
use super::pps::{self as pps_in, ChannelPps, EdgeChannel, PipePps, PpsSpec, RunnerPps};
use super::simfc::{AnyFc, system_utc_us};
use super::state::{self, StateFile};
use super::trace::{TapRead, TapWrite, tap};
use super::watch::{FcWatcher, PodWatcher};
use crate::runner::options::{BridgeArgs, ConfigArgs};
use crate::sim::faults::Faults;
use crate::sim::peer::{PodPin, run_peer};
use crate::sim::pod::{PodSimConfig, SimPod};
use crate::sim::tasks::{Wire, WireRx, WireTx};

/// How often the run checks for Ctrl-C, the end, the simulators and the status line.
pub const TICK: EmbassyDuration = EmbassyDuration::from_millis(50);

/// Line idle, ms, unless `--idle-ms`: above the MCU's 5 ms (USB adapters and TCP deliver
/// bytes in bursts, a busy host runs threads late), and below the shortest silence
/// between two FC bursts that the engine must see (ArduPilot's XF Robot driver sends a
/// package every 20 ms, ~8 ms long at 115200: 12 ms of silence; at 20 ms the GCU side
/// never sees a burst end and its GPS time samples are unusable).
pub const DEFAULT_IDLE_MS: u64 = 8;

/// The bridge's configuration from the command line: the `--config` file's keys (none:
/// `Config::DEFAULT`), overridden by the options given ([`ConfigArgs`] serializes into
/// the keys it sets), a port's `:BAUD` and `--fc`; deserialized into one
/// `bridge_engine::Config` and checked with `Config::validate`, as the firmware's
/// `build.rs` does with `bridge.toml`. Also the task timing (`idle_ms`).
///
/// # Errors
/// A configuration file that cannot be read or is not valid, a value out of range
/// (naming its key), options that contradict each other (a port's `:BAUD` and
/// `--fc-baud`).
pub fn config_of(args: &BridgeArgs) -> Result<(Config, Timing), String> {
    let mut keys = match &args.config_file {
        Some(path) => std::fs::read_to_string(path)
            .map_err(|e| e.to_string())
            .and_then(|text| text.parse::<Table>().map_err(|e| e.to_string()))
            .map_err(|e| format!("--config {}: {e}", path.display()))?,
        None => Table::new(),
    };
    if let Some(path) = &args.config_file {
        bridge_engine::config::removed_key(|section, key| {
            let within = if section.is_empty() {
                Some(&keys)
            } else {
                keys.get(section).and_then(toml::Value::as_table)
            };
            within.is_some_and(|t| t.contains_key(key))
        })
        .map_err(|e| format!("--config {}: {e}", path.display()))?;
    }
    let options = Table::try_from(&args.config).map_err(|e| e.to_string())?;
    for (key, value) in options {
        set(&mut keys, &key, value);
    }
    let a: &ConfigArgs = &args.config;
    let no_port = port::PortSpec::Sim;
    for (key, port, option, what) in [
        ("fc_baud", &args.fc_port, a.fc_baud, "--fc-port"),
        ("pod_baud", &args.pod_port, a.pod_baud, "--pod-port"),
        (
            "telemetry_baud",
            args.telemetry_port.as_ref().unwrap_or(&no_port),
            a.telemetry_baud,
            "--telemetry-port",
        ),
    ] {
        if let Some(baud) = port_baud(port, option, what)? {
            set(&mut keys, key, toml::Value::Integer(baud.into()));
        }
    }
    set(&mut keys, "fc", toml::Value::String(args.fc.name().into()));
    if let Some(path) = &a.signing_key_file {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("--signing-key-file {}: {e}", path.display()))?;
        set(
            &mut keys,
            "signing_key",
            toml::Value::String(text.trim().to_owned()),
        );
    }

    let source = match &args.config_file {
        Some(path) => format!("--config {}: ", path.display()),
        None => String::new(),
    };
    let c: Config = keys
        .try_into()
        .map_err(|e| format!("{source}{}", e.to_string().trim_end().replace('\n', " ")))?;
    c.validate().map_err(|e| format!("{source}{e}"))?;
    let mut timing = Timing::from_config(&c);
    timing.idle_min = Duration::from_millis(args.idle_ms.unwrap_or(DEFAULT_IDLE_MS));
    Ok((c, timing))
}

/// Sets a key of the configuration (`sync.period_ms`: `period_ms` in `[sync]`). A section
/// the file gives as something else than a table is left to the deserializer's error.
fn set(keys: &mut Table, key: &str, value: toml::Value) {
    match key.split_once('.') {
        Some((section, rest)) => {
            let section = keys
                .entry(section)
                .or_insert_with(|| toml::Value::Table(Table::new()));
            if let toml::Value::Table(t) = section {
                set(t, rest, value);
            }
        }
        None => {
            keys.insert(key.to_owned(), value);
        }
    }
}

/// What the status line shows, from the events.
#[derive(Debug, Default)]
struct StatusState {
    fc: bool,
    pod: bool,
    utc: bool,
    syncs: u32,
    geotags: u32,
    errors: u32,
}

impl StatusState {
    fn note(&mut self, event: EventName) {
        match event {
            EventName::FcLinkUp => self.fc = true,
            EventName::FcLinkDown => self.fc = false,
            EventName::PodLinkUp => self.pod = true,
            EventName::PodLinkDown => self.pod = false,
            EventName::UtcValid => self.utc = true,
            EventName::UtcLost => self.utc = false,
            EventName::TimeSync => self.syncs += 1,
            EventName::Geotag => self.geotags += 1,
            EventName::ReadError
            | EventName::WriteError
            | EventName::RtcIoError
            | EventName::Stalled => self.errors += 1,
            _ => {}
        }
    }

    fn line(&self, secs: u64) -> String {
        let ud = |b: bool| if b { "up" } else { "down" };
        format!(
            "[{secs}s] fc {} | pod {} | utc {} | syncs {} | geotags {} | errors {}",
            ud(self.fc),
            ud(self.pod),
            if self.utc { "valid" } else { "unknown" },
            self.syncs,
            self.geotags,
            self.errors
        )
    }
}

/// Why a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ended {
    /// `--seconds` elapsed.
    Time,
    /// Ctrl-C (or SIGTERM).
    Interrupted,
    /// Stdout was closed.
    OutputClosed,
    /// The console's `reboot` (a service manager starts the bridge again: the settings
    /// that apply at restart then run).
    Reboot,
}

impl Ended {
    /// snake_case name for the `stopped` event.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Ended::Time => "seconds_elapsed",
            Ended::Interrupted => "interrupted",
            Ended::OutputClosed => "output_closed",
            Ended::Reboot => "reboot",
        }
    }
}

/// Waits for the end of a run: `stop` set, `deadline_us` passed, or stdout closed;
/// `tick` runs every [`TICK`] meanwhile.
pub async fn until_stopped(
    stop: &AtomicBool,
    deadline_us: Option<u64>,
    out: &Output,
    mut tick: impl FnMut(u64),
) -> Ended {
    loop {
        let now = now_us();
        if stop.load(Ordering::Relaxed) {
            return Ended::Interrupted;
        }
        if out.is_broken() {
            return Ended::OutputClosed;
        }
        if deadline_us.is_some_and(|d| now >= d) {
            return Ended::Time;
        }
        tick(now);
        Timer::after(TICK).await;
    }
}

fn secs_to_us(s: f64) -> u64 {
    // Within a year (checked when parsed): no overflow.
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let us = (s * 1e6) as u64;
    us
}

/// Runs the bridge until Ctrl-C (`stop`), `--seconds` or a closed stdout. Prints a
/// `bridge_started` event first and `stopped` and `counters` last.
///
/// # Errors
/// A port or the RTC_IO output cannot be opened (a peer that is not there yet is no
/// error: it is retried), or the options contradict each other.
#[allow(clippy::too_many_lines)]
pub fn run(args: &BridgeArgs, out: &Output, stop: &AtomicBool) -> Result<Value, String> {
    let (mut config, timing) = config_of(args)?;
    if let Some(p) = &args.pps {
        config.pps.tolerance_ns = p.tolerance_ns();
    }
    let links: &'static HostLinks = Box::leak(Box::new(if args.telemetry_port.is_some() {
        HostLinks::with_telemetry()
    } else {
        HostLinks::new()
    }));
    // The settings kept in the state directory, before the engine: the configuration
    // file and the options are their defaults, as bridge.toml is the firmware's.
    let state_dir = args
        .state_dir
        .clone()
        .or_else(state::default_dir)
        .ok_or("--state-dir: neither XDG_STATE_HOME nor HOME is set; give a directory")?;
    let (mut state_file, set_aside) = StateFile::open(&state_dir)?;
    let sides = bridge_engine::Sides::COMPILED;
    let mut restored = if set_aside.is_some() {
        let mut r = bridge_engine::Restore::new(config, sides);
        r.unreadable();
        r.finish()
    } else {
        embassy_futures::block_on(bridge_fw::restore_settings(&mut state_file, config, sides)).0
    };
    // `--fc` names the side (its simulator, its codec in the events): a kept `fc` waits.
    if restored.config().fc != config.fc {
        restored.fall_back("fc");
    }
    let config = *restored.config();
    let timing = Timing {
        idle_min: timing.idle_min,
        ..Timing::from_config(&config)
    };
    let shared = HostShared::new(Engine::restored(restored, bridge_fw::config::BUILD), timing);
    let fc_codec = args.fc.name();
    let trace = |port: &'static str, dir: &'static str| {
        let codec = match port {
            "fc" => fc_codec,
            "telemetry" => "mavlink",
            _ => "k40t",
        };
        args.trace.then(|| tap(out, codec, port, dir))
    };

    out.emit(
        EventName::BridgeStarted,
        json!({
            "fc": fc_codec, "fc_port": args.fc_port.to_string(),
            "pod_port": args.pod_port.to_string(), "rtc_io": args.rtc_io.to_string(),
            "telemetry_port": args.telemetry_port.as_ref().map(ToString::to_string),
            "fc_baud": config.fc_baud, "pod_baud": config.pod_baud,
            "telemetry_baud": args.telemetry_port.as_ref().map(|_| config.telemetry_baud),
            "sync_period_ms": config.sync.period.as_millis(),
            "sync_width_ms": config.sync.width.as_millis(),
            "pps": args.pps.as_ref().map(ToString::to_string),
            "photo_events": args.photo_events.as_ref().map(|p| p.display().to_string()),
            "fc_faults": args.fc_faults.map(|f| f.to_string()),
            "pod_faults": args.pod_faults.map(|f| f.to_string()),
            "version": env!("CARGO_PKG_VERSION"),
            "build": bridge_fw::config::BUILD.to_string(),
            "log_version": events::LOG_VERSION,
        }),
    );

    // The other records kept across restarts (the signing state) go to the engine before
    // its first input (a file set aside: the engine said so, restoring the settings).
    if let Some(bad) = &set_aside {
        out.emit(
            EventName::StateFileSetAside,
            json!({"file": state_file.path().display().to_string(), "problem": bad.problem,
                   "aside": bad.aside.as_ref().map(|p| p.display().to_string())}),
        );
    } else {
        embassy_futures::block_on(bridge_fw::restore(&shared, &mut state_file));
    }
    // The console on a port of its own (docs/src/console.md).
    let console_pipes = match &args.console {
        Some(spec) => {
            let rx: &'static host::HostPipe = Box::leak(Box::new(host::HostPipe::new()));
            let tx: &'static host::HostPipe = Box::leak(Box::new(host::HostPipe::new()));
            port::start(Pump {
                label: "console",
                spec: spec.clone(),
                baud: 115_200,
                out: out.clone(),
                incoming: Some(rx),
                outgoing: Some(tx),
                tap_in: None,
                tap_out: None,
                faults: None,
            })?;
            Some((rx, tx))
        }
        None => None,
    };

    // The RTC_IO outputs: opened first, so that a missing GPIO line is an error before
    // any connection is made.
    let gpio = match &args.rtc_io {
        RtcSpec::Gpio(g) => Some(GpioLine::open(&g.chip, g.line, g.active_low)?),
        _ => None,
    };
    let rtc_tcp = match &args.rtc_io {
        RtcSpec::Tcp(spec) => Some(
            port::start(Pump {
                label: "rtc_io",
                spec: spec.clone(),
                baud: 115_200,
                out: out.clone(),
                incoming: None,
                outgoing: None,
                tap_in: None,
                tap_out: None,
                faults: None,
            })?
            .writer,
        ),
        _ => None,
    };

    // The PPS input: a kernel source's thread, the TCP test source's pump, or the
    // simulated module; opened before any connection, as the RTC_IO outputs.
    let pps = match &args.pps {
        None => RunnerPps::None,
        Some(PpsSpec::Sim) => {
            let utc_at_zero = system_utc_us().saturating_sub(now_us());
            let wiring = Box::leak(Box::new(pps_in::sim_wiring(
                utc_at_zero,
                config.pps.active_low,
            )));
            RunnerPps::Sim(crate::sim::pps_io::CapturedPps::new(wiring))
        }
        Some(PpsSpec::Tcp(spec)) => {
            let pipe: &'static host::HostPipe = Box::leak(Box::new(host::HostPipe::new()));
            port::start(Pump {
                label: "pps",
                spec: spec.clone(),
                baud: 115_200,
                out: out.clone(),
                incoming: Some(pipe),
                outgoing: None,
                tap_in: None,
                tap_out: None,
                faults: None,
            })?;
            RunnerPps::Pipe(PipePps(pipe))
        }
        Some(spec) => {
            let edges: &'static EdgeChannel = Box::leak(Box::new(EdgeChannel::new()));
            pps_in::start(spec, edges, config.pps.active_low, out)?;
            RunnerPps::Kernel(ChannelPps(edges))
        }
    };
    let photos = match &args.photo_events {
        Some(path) => Some(RefCell::new(
            PhotoEvents::create(path, config.leap_seconds)
                .map_err(|e| format!("--photo-events {}: {e}", path.display()))?,
        )),
        None => None,
    };

    // A faulty cable: threads' stages for a real port, wires for a simulator.
    let real_faults = |spec: &port::PortSpec, f: Option<Faults>| {
        f.filter(|_| !spec.is_sim()).map(CableFaults::new)
    };
    let (fc_cable, pod_cable) = (
        real_faults(&args.fc_port, args.fc_faults),
        real_faults(&args.pod_port, args.pod_faults),
    );
    let sim_wire = |f: Option<Faults>, index: u64| {
        let mut w = Wire::default();
        w.damage.set_faults(f.map(|f| f.derived(index)));
        RefCell::new(w)
    };
    // Into the bridge: 0, out of it: 1 (as `CableFaults` and `Wires::set_faults`).
    let (fc_in, fc_out) = (sim_wire(args.fc_faults, 0), sim_wire(args.fc_faults, 1));
    let (pod_in, pod_out) = (sim_wire(args.pod_faults, 0), sim_wire(args.pod_faults, 1));
    for (label, spec, baud, rx, tx, cable) in [
        (
            "fc",
            &args.fc_port,
            config.fc_baud,
            &links.fc_rx,
            &links.fc_tx,
            &fc_cable,
        ),
        (
            "pod",
            &args.pod_port,
            config.pod_baud,
            &links.pod_rx,
            &links.pod_tx,
            &pod_cable,
        ),
    ] {
        if !spec.is_sim() {
            port::start(Pump {
                label,
                spec: spec.clone(),
                baud,
                out: out.clone(),
                incoming: Some(rx),
                outgoing: Some(tx),
                tap_in: trace(label, "rx"),
                tap_out: trace(label, "tx"),
                faults: cable.clone(),
            })?;
        }
    }

    // The telemetry link: a real port only (its threads feed the pipes).
    if let (Some(spec), Some(link)) = (&args.telemetry_port, &links.telemetry) {
        port::start(Pump {
            label: "telemetry",
            spec: spec.clone(),
            baud: config.telemetry_baud,
            out: out.clone(),
            incoming: Some(&link.rx),
            outgoing: Some(&link.tx),
            tap_in: trace("telemetry", "rx"),
            tap_out: trace("telemetry", "tx"),
            faults: None,
        })?;
    }

    let fc_sim = RefCell::new(AnyFc::new(args.fc, now_us(), system_utc_us()));
    let pod_sim = RefCell::new(SimPod::new(PodSimConfig {
        ack_seq: args.sim_pod_ack_seq.ack_seq(),
        ..PodSimConfig::default()
    }));
    let status = RefCell::new(StatusState::default());
    let show_status = wants_status_line();
    let start_us = now_us();
    let deadline = args.seconds.map(|s| start_us + secs_to_us(s));
    let photo_every = args.sim_photo_every.map(secs_to_us);
    let counters_every = args.counters_every.map(secs_to_us);

    let mut fixes = events::FixSampler::default();
    let mut fc_watch = FcWatcher::default();
    let mut pod_watch = PodWatcher::default();
    let ended = host::run(Clock::Real, || async {
        let pin = RunnerPin {
            pod: args.pod_port.is_sim().then(|| PodPin::new(&pod_sim)),
            gpio,
            tcp: rtc_tcp,
        };
        let sink = |r: &LogRecord| {
            if let Some(file) = &photos
                && let LogKind::Engine(Event::Photo(p)) = &r.what
                && let Err(e) = file.borrow_mut().push(p)
            {
                out.emit(EventName::PhotoEventsError, json!({"error": e.to_string()}));
            }
            let (t, name, fields) = events::record_event(r);
            status.borrow_mut().note(name);
            out.emit_at(t, name, fields);
        };
        let bridge = select(
            host::bridge_with_pps(&shared, links, pin, pps, sink, || {}),
            bridge_fw::store_task(&shared, state_file),
        );
        // `reboot` ends the run once the state file holds what waited; `update` (no
        // update protocol here) gives the console back at once.
        let console = async {
            let Some((rx, tx)) = console_pipes else {
                return core::future::pending().await;
            };
            let mut buf = [0u8; 64];
            loop {
                match bridge_fw::console(&shared, &mut &*rx, &mut &*tx, &mut buf, || {}).await {
                    ConsoleEnd::Restart => {
                        // The answer leaves before the run ends (the port's writer thread
                        // takes it from the pipe).
                        for _ in 0..50 {
                            if tx.is_empty() {
                                break;
                            }
                            Timer::after(EmbassyDuration::from_millis(10)).await;
                        }
                        Timer::after(EmbassyDuration::from_millis(50)).await;
                        return Ended::Reboot;
                    }
                    ConsoleEnd::Update(_) => {
                        shared.input(Engine::console_resume);
                    }
                }
            }
        };
        // A simulated peer on its side's wires (the bridge's output and input, their
        // sinks), traced both ways; or nothing.
        macro_rules! sim_peer {
            ($on:expr, $sim:expr, $side:literal, $wires:expr, $baud:expr) => {
                async {
                    if $on {
                        let (bridge_tx, bridge_rx, out, into) = $wires;
                        let rx = TapRead {
                            inner: bridge_tx,
                            tap: trace($side, "tx"),
                        };
                        let tx = TapWrite {
                            inner: bridge_rx,
                            tap: trace($side, "rx"),
                        };
                        run_peer($sim, WireRx::new(rx, out), WireTx::new(tx, into), $baud).await
                    } else {
                        core::future::pending().await
                    }
                }
            };
        }
        let (fc_on, pod_on) = (args.fc_port.is_sim(), args.pod_port.is_sim());
        let fc_wires = (&links.fc_tx, &links.fc_rx, &fc_out, &fc_in);
        let fc_peer = sim_peer!(fc_on, &fc_sim, "fc", fc_wires, config.fc_baud);
        let pod_wires = (&links.pod_tx, &links.pod_rx, &pod_out, &pod_in);
        let pod_peer = sim_peer!(pod_on, &pod_sim, "pod", pod_wires, config.pod_baud);
        let mut next_photo = photo_every.map(|p| start_us + p);
        let mut next_counters = counters_every.map(|p| start_us + p);
        let mut next_status = start_us;
        let monitor = until_stopped(stop, deadline, out, |now| {
            if args.fc_port.is_sim() {
                fc_watch.check(&fc_sim.borrow(), now, out);
                if let (Some(at), Some(every)) = (next_photo, photo_every)
                    && now >= at
                {
                    fc_watch.photo(&mut fc_sim.borrow_mut(), out);
                    next_photo = Some(at + every);
                }
            }
            if args.pod_port.is_sim() {
                pod_watch.check(&pod_sim.borrow(), out);
            }
            if let Some((t, name, fields)) =
                fixes.take(shared.with(|e: &mut Engine| e.latest_fix()))
            {
                out.emit_at(t, name, fields);
            }
            if let (Some(at), Some(every)) = (next_counters, counters_every)
                && now >= at
            {
                out.emit(
                    EventName::Counters,
                    events::counters(&shared.with(|e: &mut Engine| e.counters())),
                );
                next_counters = Some(at + every);
            }
            if show_status && now >= next_status {
                out.status(&status.borrow().line((now - start_us) / 1_000_000));
                next_status = now + 500_000;
            }
        });
        let monitor = async {
            match select(monitor, console).await {
                Either::First(ended) | Either::Second(ended) => ended,
            }
        };
        match select4(bridge, fc_peer, pod_peer, monitor).await {
            Either4::First(Either::First(never) | Either::Second(never)) => match never {},
            Either4::Second(Err(e)) | Either4::Third(Err(e)) => {
                Err(format!("a simulator stopped: {e:?}"))
            }
            Either4::Second(Ok(never)) | Either4::Third(Ok(never)) => match never {},
            Either4::Fourth(ended) => Ok(ended),
        }
    })?;
    out.clear_status();
    let counters = events::counters(&shared.with(|e: &mut Engine| e.counters()));
    let mut stopped = json!({
        "reason": ended.name(),
        "seconds": (now_us() - start_us) as f64 / 1e6,
    });
    if args.fc_port.is_sim() {
        stopped["sim_fc"] = fc_watch.summary(&fc_sim.borrow(), now_us());
    }
    if args.pod_port.is_sim() {
        stopped["sim_pod"] = PodWatcher::summary(&pod_sim.borrow());
    }
    for (label, given, cable, wires) in [
        ("fc_faults", args.fc_faults, &fc_cable, (&fc_in, &fc_out)),
        (
            "pod_faults",
            args.pod_faults,
            &pod_cable,
            (&pod_in, &pod_out),
        ),
    ] {
        if given.is_none_or(|f| f.is_none()) {
            continue;
        }
        stopped[label] = match cable {
            Some(c) => c.stats_json(),
            None => {
                let stats = |w: &RefCell<Wire>| w.borrow().damage.fault_stats().unwrap_or_default();
                json!({"in": stats_json(&stats(wires.0)), "out": stats_json(&stats(wires.1))})
            }
        };
    }
    out.emit(EventName::Stopped, stopped);
    out.emit(EventName::Counters, counters.clone());
    Ok(counters)
}
