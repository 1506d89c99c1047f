//! `qemu-e2e`: the real firmware binary (the `qemu` flavour of bridge-fw) on QEMU's
//! `b-l475e-iot01a`, one scenario per FC side, between the simulated ArduPilot drivers
//! (or the K40T FC) and the simulated pod, on wall-clock time. See the `emulated_board`
//! crate; `scripts/qemu-e2e` builds the firmware and runs this.
//!
//! ```text
//! qemu-e2e --image PATH --bootloader PATH [--qemu PATH] [--timeout SECS] [--work DIR] [--keep] [--jobs N] [SIDE...]
//! ```
//! Sides: siyi, viewlink, gcu, k40t (default: all, `--jobs` at a time, 2 by default),
//! each in a child process (`--single SIDE`, internal: see `run_child`). Prints one line
//! per scenario (`PASS`/`FAIL`, the side, its figures), the failed checks, and on a
//! failure the tail of QEMU's output and of its GPIO trace. Exit code 0 when every
//! scenario passed.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use emulated_board::{self as emulated, Options, Side};

const USAGE: &str = "usage: qemu-e2e --image PATH --bootloader PATH [--qemu PATH] [--timeout SECS] [--work DIR] [--keep] [--jobs N] [siyi|viewlink|gcu|k40t ...]";

struct Args {
    options: Options,
    sides: Vec<Side>,
    keep: bool,
    jobs: usize,
    single: bool,
}

fn parse(args: &[String]) -> Result<Args, String> {
    let mut image = None;
    let mut bootloader = None;
    let mut qemu = PathBuf::from("qemu-system-arm");
    let mut timeout = Duration::from_secs(180);
    let mut work = None;
    let mut keep = false;
    let mut jobs = 2;
    let mut single = false;
    let mut sides = Vec::new();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = || it.next().ok_or_else(|| format!("{a} needs a value"));
        match a.as_str() {
            "--image" => image = Some(PathBuf::from(value()?)),
            "--bootloader" => bootloader = Some(PathBuf::from(value()?)),
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
            "--single" => single = true,
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
        sides = vec![
            Side::Gcu,
            Side::K40t,
            Side::Mavlink,
            Side::Siyi,
            Side::Viewlink,
        ];
    }
    let work = work.unwrap_or_else(|| {
        std::env::temp_dir().join(format!("bridge-qemu-e2e.{}", std::process::id()))
    });
    Ok(Args {
        options: Options {
            qemu,
            image: image.ok_or("--image is required")?,
            bootloader: bootloader.ok_or("--bootloader is required")?,
            timeout,
            work,
        },
        sides,
        keep,
        jobs,
        single,
    })
}

/// Runs the scenario of `side` in a child process (this program with `--single`): the
/// simulators take true time 0 as their start, and the host harness's real clock starts
/// at its first use in a process, so each scenario needs a process of its own. Returns
/// the child's report and whether it passed.
fn run_child(side: Side, args: &Args) -> (String, bool) {
    let fail = |why: String| (format!("FAIL {:<8} {why}\n", side.name()), false);
    let exe = match std::env::current_exe() {
        Ok(e) => e,
        Err(e) => return fail(format!("cannot find this program: {e}")),
    };
    // The child's report goes to a file (no pipe to drain while waiting for it).
    let log_path = args.options.work.join(format!("{}.report", side.name()));
    let log = std::fs::create_dir_all(&args.options.work)
        .and_then(|()| std::fs::File::create(&log_path))
        .and_then(|f| Ok((f.try_clone()?, f)));
    let (out, err) = match log {
        Ok(f) => f,
        Err(e) => return fail(format!("{}: {e}", log_path.display())),
    };
    let child = std::process::Command::new(exe)
        .arg("--single")
        .arg("--image")
        .arg(&args.options.image)
        .arg("--bootloader")
        .arg(&args.options.bootloader)
        .arg("--qemu")
        .arg(&args.options.qemu)
        .arg("--timeout")
        .arg(args.options.timeout.as_secs().to_string())
        .arg("--work")
        .arg(&args.options.work)
        .arg(side.name())
        .stdin(std::process::Stdio::null())
        .stdout(out)
        .stderr(err)
        .spawn();
    let mut child = match child {
        Ok(c) => c,
        Err(e) => return fail(format!("cannot start the scenario: {e}")),
    };
    // The child bounds its own waits; this is the last resort (it then leaves its QEMU,
    // which the child would have ended, to the kill of the child's process).
    let deadline = std::time::Instant::now() + args.options.timeout + Duration::from_secs(30);
    let status = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Some(status),
            Ok(None) if std::time::Instant::now() < deadline => {
                std::thread::sleep(Duration::from_millis(200));
            }
            _ => {
                let _ = child.kill();
                let _ = child.wait();
                break None;
            }
        }
    };
    let text = std::fs::read(&log_path).unwrap_or_default();
    let text = String::from_utf8_lossy(&text).into_owned();
    match status {
        Some(s) if s.success() => (text, true),
        Some(_) if text.starts_with("FAIL") => (text, false),
        Some(s) => fail(format!("the scenario process ended: {s}\n{text}")),
        None => fail(format!("the scenario process hung and was killed\n{text}")),
    }
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
    if args.single {
        // One scenario in this process (see `run_child`).
        let mut ok = true;
        for &side in &args.sides {
            let options = Options {
                work: args.options.work.join(side.name()),
                ..args.options.clone()
            };
            ok &= emulated::run(side, &options).print();
        }
        return if ok {
            ExitCode::SUCCESS
        } else {
            ExitCode::FAILURE
        };
    }
    // Two at a time by default: each scenario mostly waits for its three time syncs (on
    // the 10 s UTC grid, the first about 10 s after start), and two emulated boards share a
    // 2-core machine without starving each other (four at once pass too since the GCU side
    // times each package from its own first byte, but each then waits longer for its CPU).
    // The heaviest side goes first, next to the lightest.
    let next = AtomicUsize::new(0);
    let order: Vec<Side> = args.sides.clone();
    let mut results: Vec<(Side, String, bool)> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..args.jobs.min(order.len()))
            .map(|_| {
                scope.spawn(|| {
                    let mut done = Vec::new();
                    while let Some(&side) = order.get(next.fetch_add(1, Ordering::Relaxed)) {
                        let (text, ok) = run_child(side, &args);
                        done.push((side, text, ok));
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
    results.sort_by_key(|(side, _, _)| Side::ALL.iter().position(|s| s == side));
    let mut failed = args.sides.len().saturating_sub(results.len());
    for (_, text, ok) in &results {
        print!("{text}");
        if !ok {
            failed += 1;
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
