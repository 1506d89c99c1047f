//! `qemu-e2e`: the real firmware binary (the `qemu` flavour of bridge-fw) on QEMU's
//! `b-l475e-iot01a`, one scenario per FC side, between the simulated ArduPilot drivers
//! (or the K40T FC) and the simulated pod, on wall-clock time. See
//! `host_tests::emulated`; `scripts/qemu-e2e` builds the firmware and runs this.
//!
//! ```text
//! qemu-e2e --elf PATH [--qemu PATH] [--timeout SECS] [--work DIR] [--keep] [--jobs N] [SIDE...]
//! ```
//! Sides: siyi, viewlink, gcu, k40t (default: all, `--jobs` at a time, 2 by
//! default). Prints one line
//! per scenario (`PASS`/`FAIL`, the side, its figures), the failed checks, and on a
//! failure the tail of QEMU's output and of its GPIO trace. Exit code 0 when every
//! scenario passed.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use host_tests::emulated::{self, Options, Side};

const USAGE: &str = "usage: qemu-e2e --elf PATH [--qemu PATH] [--timeout SECS] [--work DIR] [--keep] [--jobs N] [siyi|viewlink|gcu|k40t ...]";

struct Args {
    options: Options,
    sides: Vec<Side>,
    keep: bool,
    jobs: usize,
}

fn parse(args: &[String]) -> Result<Args, String> {
    let mut elf = None;
    let mut qemu = PathBuf::from("qemu-system-arm");
    let mut timeout = Duration::from_secs(180);
    let mut work = None;
    let mut keep = false;
    let mut jobs = 2;
    let mut sides = Vec::new();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = || it.next().ok_or_else(|| format!("{a} needs a value"));
        match a.as_str() {
            "--elf" => elf = Some(PathBuf::from(value()?)),
            "--qemu" => qemu = PathBuf::from(value()?),
            "--timeout" => {
                let v = value()?;
                let secs: u64 = v
                    .parse()
                    .ok()
                    .filter(|s| (1..=3600).contains(s))
                    .ok_or_else(|| format!("--timeout {v}: seconds, 1..=3600"))?;
                timeout = Duration::from_secs(secs);
            }
            "--work" => work = Some(PathBuf::from(value()?)),
            "--keep" => keep = true,
            "--jobs" => {
                let v = value()?;
                jobs = v
                    .parse()
                    .ok()
                    .filter(|j| (1..=4).contains(j))
                    .ok_or_else(|| format!("--jobs {v}: 1..=4"))?;
            }
            name => sides.push(Side::from_name(name).ok_or_else(|| format!("unknown: {name}"))?),
        }
    }
    if sides.is_empty() {
        // The heaviest FC traffic first, next to the lightest (see `main`).
        sides = vec![Side::Gcu, Side::K40t, Side::Siyi, Side::Viewlink];
    }
    let work = work.unwrap_or_else(|| {
        std::env::temp_dir().join(format!("bridge-qemu-e2e.{}", std::process::id()))
    });
    Ok(Args {
        options: Options {
            qemu,
            elf: elf.ok_or("--elf is required")?,
            timeout,
            work,
        },
        sides,
        keep,
        jobs,
    })
}

fn main() -> ExitCode {
    let argv: Vec<String> = std::env::args().skip(1).collect();
    let args = match parse(&argv) {
        Ok(a) => a,
        Err(e) => {
            eprintln!("qemu-e2e: {e}\n{USAGE}");
            return ExitCode::from(2);
        }
    };
    let run = |side: Side| {
        let options = Options {
            work: args.options.work.join(side.name()),
            ..args.options.clone()
        };
        emulated::run(side, &options)
    };
    // Two at a time by default: each scenario mostly waits for the bridge's time discipline
    // (some 30 s of samples before the first sync), and two emulated boards share a
    // 2-core machine without starving each other (four did: the XF Robot driver's 3.6 kB/s
    // then backed up and its UTC never converged). The heaviest side goes first, next to
    // the lightest.
    let next = AtomicUsize::new(0);
    let order: Vec<Side> = args.sides.clone();
    let mut outcomes: Vec<_> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..args.jobs.min(order.len()))
            .map(|_| {
                scope.spawn(|| {
                    let mut done = Vec::new();
                    while let Some(&side) = order.get(next.fetch_add(1, Ordering::Relaxed)) {
                        done.push(run(side));
                    }
                    done
                })
            })
            .collect();
        workers
            .into_iter()
            .filter_map(|w| w.join().ok())
            .flatten()
            .collect()
    });
    outcomes.sort_by_key(|o| Side::ALL.iter().position(|s| *s == o.side));
    let mut failed = args.sides.len().saturating_sub(outcomes.len());
    for o in &outcomes {
        let side = o.side;
        let ok = o.passed();
        let figures: Vec<String> = o
            .checks
            .iter()
            .map(|c| format!("{}: {}", c.name, c.detail))
            .collect();
        println!(
            "{} {:<8} ({:.0} s) {}",
            if ok { "PASS" } else { "FAIL" },
            side.name(),
            o.wall.as_secs_f64(),
            figures.join(" | ")
        );
        if !ok {
            failed += 1;
            for c in o.checks.iter().filter(|c| !c.ok) {
                println!("    failed: {}: {}", c.name, c.detail);
            }
            if o.checks.len() < emulated::CHECKS {
                println!(
                    "    {} of {} checks reached",
                    o.checks.len(),
                    emulated::CHECKS
                );
            }
            println!(
                "    --- QEMU output ({}), last lines:",
                o.qemu_out.display()
            );
            println!("{}", emulated::tail(&o.qemu_out, 20));
            println!("    --- GPIO trace ({}), last lines:", o.trace.display());
            println!("{}", emulated::tail(&o.trace, 10));
        }
    }
    if args.keep || failed > 0 {
        println!("work directory kept: {}", args.options.work.display());
    } else {
        let _ = std::fs::remove_dir_all(&args.options.work);
    }
    println!(
        "qemu e2e: {} passed, {failed} failed",
        args.sides.len() - failed
    );
    if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
