//! `gimbal sim-fc` and `gimbal sim-pod`: a simulator on a real port (serial or TCP), in
//! real time, printing what it observes and a summary. `--faults` makes the cable to the
//! bridge faulty, both ways (the summary's `faults`: `in` towards the simulator, `out`
//! from it).

use core::cell::RefCell;
use std::sync::atomic::AtomicBool;

use bridge_fw::host::{self, Clock, HostPipe};
use embassy_futures::select::{Either, Either3, select, select3};
use serde_json::{Value, json};

use super::bridge::{Ended, until_stopped};
use super::output::{Output, now_us};
use super::port::{self, CableFaults, PortSpec, Pump, link_baud};
use super::simfc::{AnyFc, system_utc_us};
use super::watch::{FcWatcher, PodWatcher};
use crate::runner::options::{AutopilotArg, Fc, Px4ModeArg, SimFcArgs, SimPodArgs};
use crate::sim::ground::GroundPipe;
use crate::sim::peer::{PeerError, run_peer};
use crate::sim::pod::{PodSimConfig, SimPod};
use crate::sim::px4::{Px4Config, Px4Mode};

fn pipe() -> &'static HostPipe {
    Box::leak(Box::new(HostPipe::new()))
}

fn secs_to_us(s: f64) -> u64 {
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let us = (s * 1e6) as u64;
    us
}

/// Starts the threads of `spec` feeding `to_sim` and sending `from_sim`, through a
/// faulty cable when `faults` is given.
fn open(
    spec: &PortSpec,
    baud: u32,
    out: &Output,
    faults: Option<&CableFaults>,
) -> Result<(&'static HostPipe, &'static HostPipe), String> {
    let (to_sim, from_sim) = (pipe(), pipe());
    port::start(Pump {
        label: "bridge",
        spec: spec.clone(),
        baud,
        out: out.clone(),
        incoming: Some(to_sim),
        outgoing: Some(from_sim),
        tap_in: None,
        tap_out: None,
        faults: faults.cloned(),
    })?;
    Ok((to_sim, from_sim))
}

fn finish(
    ended: Result<Ended, PeerError>,
    start_us: u64,
    mut summary: Value,
    out: &Output,
) -> Result<Value, String> {
    let ended = ended.map_err(|e| format!("the simulator stopped: {e:?}"))?;
    summary["reason"] = json!(ended.name());
    summary["seconds"] = json!((now_us() - start_us) as f64 / 1e6);
    out.emit("summary", summary.clone());
    Ok(summary)
}

/// The simulated flight controller of `args`.
fn new_fc(args: &SimFcArgs, start_us: u64) -> Result<AnyFc, String> {
    let utc = system_utc_us();
    let px4 = args.autopilot == AutopilotArg::Px4;
    if args.fc != Fc::Mavlink && (px4 || args.px4_lockstep) {
        return Err("--autopilot px4 and --px4-lockstep are for `sim-fc mavlink`".into());
    }
    if !px4 {
        return Ok(AnyFc::new(args.fc, start_us, utc));
    }
    let mut config = match args.px4_mode {
        Px4ModeArg::Normal => Px4Config {
            mode: Px4Mode::Normal,
            ..Px4Config::default()
        },
        Px4ModeArg::Onboard => Px4Config {
            mode: Px4Mode::Onboard,
            ..Px4Config::default()
        },
        Px4ModeArg::Gimbal => Px4Config::px4_1_16_gimbal_mode(),
    };
    if args.px4_lockstep {
        let lockstep = Px4Config::sitl_lockstep();
        config.sitl_lockstep = true;
        config.lockstep = lockstep.lockstep;
        config.timesync_targets = lockstep.timesync_targets;
    }
    Ok(AnyFc::px4(config, start_us, utc))
}

/// A thread between the ground app at `addr` (UDP) and `pipe`: datagrams from the app
/// into the pipe, the pipe's frames to where the app's last datagram came from (else to
/// `addr`). Returns the local address.
fn start_ground(
    addr: std::net::SocketAddr,
    pipe: GroundPipe,
) -> Result<std::net::SocketAddr, String> {
    use std::net::UdpSocket;
    let local = match (addr.ip().is_loopback(), addr.is_ipv4()) {
        (true, true) => "127.0.0.1:0",
        (true, false) => "[::1]:0",
        (false, true) => "0.0.0.0:0",
        (false, false) => "[::]:0",
    };
    let socket = UdpSocket::bind(local).map_err(|e| format!("--gcs: {e}"))?;
    socket
        .set_read_timeout(Some(std::time::Duration::from_millis(5)))
        .map_err(|e| format!("--gcs: {e}"))?;
    let bound = socket.local_addr().map_err(|e| format!("--gcs: {e}"))?;
    std::thread::Builder::new()
        .name("gcs".into())
        .spawn(move || {
            let mut peer = addr;
            let mut buf = [0u8; 2048];
            loop {
                if let Ok((n, from)) = socket.recv_from(&mut buf) {
                    peer = from;
                    pipe.push_from_ground(buf.get(..n).unwrap_or_default());
                }
                for frame in pipe.take_for_ground() {
                    // A ground app not listening yet: the datagram is lost, as on a radio.
                    let _ = socket.send_to(&frame, peer);
                }
            }
        })
        .map_err(|e| format!("--gcs: {e}"))?;
    Ok(bound)
}

/// Runs a simulated flight controller. Returns the summary and whether the
/// expectations (`--expect-healthy`) were met.
///
/// # Errors
/// The port cannot be opened.
pub fn run_fc(args: &SimFcArgs, out: &Output, stop: &AtomicBool) -> Result<(Value, bool), String> {
    let baud = link_baud(&args.port, args.baud, "--port")?;
    let cable = args.faults.filter(|f| !f.is_none()).map(CableFaults::new);
    let (to_sim, from_sim) = open(&args.port, baud, out, cable.as_ref())?;
    let start_us = now_us();
    let fc = RefCell::new(new_fc(args, start_us)?);
    let gcs = match args.gcs {
        Some(addr) => {
            let pipe = GroundPipe::default();
            if !fc.borrow_mut().attach_ground(pipe.clone()) {
                return Err("--gcs: only a MAVLink autopilot has a ground link".into());
            }
            Some(start_ground(addr, pipe)?)
        }
        None => None,
    };
    out.emit(
        "sim_fc_started",
        json!({"fc": args.fc.name(), "port": args.port.to_string(), "baud": baud,
               "faults": args.faults.map(|f| f.to_string()),
               "autopilot": (args.fc == Fc::Mavlink)
                   .then(|| format!("{:?}", args.autopilot).to_lowercase()),
               "gcs": args.gcs.map(|a| a.to_string()),
               "gcs_local": gcs.map(|a| a.to_string())}),
    );
    if args.yaw_rate.is_some() || args.pitch_rate.is_some() {
        let turned = fc
            .borrow_mut()
            .set_rates(args.yaw_rate.unwrap_or(0.0), args.pitch_rate.unwrap_or(0.0));
        out.emit(
            "sim_fc_rates",
            json!({"yaw_dps": args.yaw_rate, "pitch_dps": args.pitch_rate, "sent": turned}),
        );
    }
    let deadline = args.seconds.map(|s| start_us + secs_to_us(s));
    let photo_every = args.photo_every.map(secs_to_us);
    let mut watch = FcWatcher::default();
    let ended = host::run(Clock::Real, || async {
        let mut next_photo = photo_every.map(|p| start_us + p);
        let monitor = until_stopped(stop, deadline, out, |now| {
            watch.check(&fc.borrow(), now, out);
            if let (Some(at), Some(every)) = (next_photo, photo_every)
                && now >= at
            {
                watch.photo(&mut fc.borrow_mut(), out);
                next_photo = Some(at + every);
            }
        });
        match select(run_peer(&fc, to_sim, from_sim, baud), monitor).await {
            Either::First(Err(e)) => Err(e),
            Either::First(Ok(never)) => match never {},
            Either::Second(ended) => Ok(ended),
        }
    });
    let mut summary = watch.summary(&fc.borrow(), now_us());
    if let Some(c) = &cable {
        summary["faults"] = c.stats_json();
    }
    let healthy = fc.borrow().healthy(now_us());
    let summary = finish(ended, start_us, summary, out)?;
    Ok((summary, !args.expect_healthy || healthy))
}

/// Runs the simulated pod. Returns the summary and whether the expectations
/// (`--expect-syncs`, `--expect-geotags`) were met.
///
/// # Errors
/// A port cannot be opened.
pub fn run_pod(
    args: &SimPodArgs,
    out: &Output,
    stop: &AtomicBool,
) -> Result<(Value, bool), String> {
    let baud = link_baud(&args.port, args.baud, "--port")?;
    let cable = args.faults.filter(|f| !f.is_none()).map(CableFaults::new);
    let (to_sim, from_sim) = open(&args.port, baud, out, cable.as_ref())?;
    let rtc = match &args.rtc_io {
        Some(spec) => {
            let edges = pipe();
            port::start(Pump {
                label: "rtc_io",
                spec: spec.clone(),
                baud: 115_200,
                out: out.clone(),
                incoming: Some(edges),
                outgoing: None,
                tap_in: None,
                tap_out: None,
                faults: None,
            })?;
            Some(edges)
        }
        None => None,
    };
    let start_us = now_us();
    let pod = RefCell::new(SimPod::new(PodSimConfig {
        ack_seq: args.ack_seq.ack_seq(),
        ..PodSimConfig::default()
    }));
    out.emit(
        "sim_pod_started",
        json!({"port": args.port.to_string(), "baud": baud,
               "rtc_io": args.rtc_io.as_ref().map(ToString::to_string),
               "ack_seq": format!("{:?}", args.ack_seq).to_lowercase(),
               "faults": args.faults.map(|f| f.to_string())}),
    );
    let deadline = args.seconds.map(|s| start_us + secs_to_us(s));
    let mut watch = PodWatcher::default();
    let ended = host::run(Clock::Real, || async {
        // The RTC_IO input: one byte per edge, applied when it arrives. Polled before
        // the pod's link so that an edge and the 0x00030E that follows it, arriving
        // together, reach the pod in that order.
        let edges = async {
            let Some(edges) = rtc else {
                return core::future::pending().await;
            };
            let mut buf = [0u8; 64];
            loop {
                let n = edges.read(&mut buf).await;
                for &b in buf.get(..n).unwrap_or_default() {
                    let level = match b {
                        b'1' | b'H' | 1 => Some(true),
                        b'0' | b'L' | 0 => Some(false),
                        _ => None,
                    };
                    if let Some(high) = level {
                        pod.borrow_mut().rtc_edge(now_us(), high);
                        out.emit(
                            "sim_pod_rtc_io",
                            json!({"level": if high { "high" } else { "low" }}),
                        );
                    }
                }
            }
        };
        let monitor = until_stopped(stop, deadline, out, |_| watch.check(&pod.borrow(), out));
        match select3(edges, run_peer(&pod, to_sim, from_sim, baud), monitor).await {
            Either3::First(never) => match never {},
            Either3::Second(Err(e)) => Err(e),
            Either3::Second(Ok(never)) => match never {},
            Either3::Third(ended) => Ok(ended),
        }
    });
    watch.check(&pod.borrow(), out);
    let mut summary = PodWatcher::summary(&pod.borrow());
    if let Some(c) = &cable {
        summary["faults"] = c.stats_json();
    }
    let num = |k: &str| summary[k].as_u64().unwrap_or(0);
    let met = args
        .expect_syncs
        .is_none_or(|n| num("syncs_applied") >= u64::from(n))
        && args
            .expect_geotags
            .is_none_or(|n| num("geotags") >= u64::from(n));
    let summary = finish(ended, start_us, summary, out)?;
    Ok((summary, met))
}
