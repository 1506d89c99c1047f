//! `gimbal`: decode gimbal-protocol serial captures, list the supported messages, run
//! the bridge on Linux and the simulators on real ports. `gimbal --help` and
//! `gimbal <command> --help` say how; the command line is defined in
//! `gimbal::cli`.
//!
//! Exit status: 0 on success, 1 on a run-time failure (a port that cannot be opened,
//! a simulator's expectation not met), 2 for bad arguments.

use std::io::{Read, Write};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};

use clap::error::ErrorKind;
use clap::{CommandFactory, Parser};
use gimbal::cli::{Cli, Command, DecodeArgs, EventFormat};
use gimbal::demo;
use gimbal::report;
use gimbal::runner::output::Output;
use gimbal::runner::{bridge, sims};
use gimbal::tool::{self, looks_like_hex, parse_hex};

/// Set by Ctrl-C (SIGINT) or SIGTERM: the run stops cleanly.
static STOP: AtomicBool = AtomicBool::new(false);

/// A failure: bad arguments found after parsing (exit 2) or a run-time error (exit 1).
enum Failure {
    Usage(String),
    Runtime(String),
}

fn read_capture(args: &DecodeArgs) -> Result<Vec<u8>, Failure> {
    if !args.hex.is_empty() {
        return parse_hex(&args.hex.join(" ")).map_err(Failure::Usage);
    }
    let bytes = match &args.file {
        Some(path) => {
            std::fs::read(path).map_err(|e| Failure::Runtime(format!("{}: {e}", path.display())))?
        }
        None => {
            let mut b = Vec::new();
            std::io::stdin()
                .read_to_end(&mut b)
                .map_err(|e| Failure::Runtime(format!("stdin: {e}")))?;
            b
        }
    };
    if looks_like_hex(&bytes) {
        parse_hex(&String::from_utf8_lossy(&bytes)).map_err(Failure::Usage)
    } else {
        Ok(bytes)
    }
}

fn write_lines(lines: impl IntoIterator<Item = String>) -> Result<(), Failure> {
    let mut out = std::io::stdout().lock();
    for line in lines {
        if let Err(e) = writeln!(out, "{line}") {
            // `| head`: not an error of ours.
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                return Ok(());
            }
            return Err(Failure::Runtime(e.to_string()));
        }
    }
    Ok(())
}

/// Ctrl-C and SIGTERM stop the run; a second Ctrl-C exits at once.
fn install_stop_handler() {
    let result = ctrlc::set_handler(|| {
        if STOP.swap(true, Ordering::Relaxed) {
            std::process::exit(130);
        }
    });
    if let Err(e) = result {
        eprintln!("gimbal: cannot handle Ctrl-C ({e}); stop with SIGKILL");
    }
}

fn expectation(met: bool, what: &str) -> Result<(), Failure> {
    if met {
        Ok(())
    } else {
        Err(Failure::Runtime(format!(
            "{what}: expectation not met (see the summary)"
        )))
    }
}

fn run(cli: Cli) -> Result<(), Failure> {
    match cli.command {
        Command::Messages(a) => {
            let p = tool::protocol(a.protocol.name())
                .ok_or_else(|| Failure::Usage(format!("no codec {}", a.protocol.name())))?;
            write_lines(p.messages())
        }
        Command::Decode(a) => {
            let p = tool::protocol(a.protocol.name())
                .ok_or_else(|| Failure::Usage(format!("no codec {}", a.protocol.name())))?;
            let capture = read_capture(&a)?;
            let items = p.scan(&capture);
            write_lines(items.iter().map(|i| tool::render(p.as_ref(), i, a.json)))?;
            eprintln!("{}", tool::summary(&items));
            Ok(())
        }
        Command::Demo(a) => {
            let opts = demo::DemoOptions {
                fc: a.fc.protocol(),
                seconds: a.seconds,
                telemetry: a.telemetry,
                pps: a.pps,
            };
            let mut out = std::io::stdout().lock();
            match a.events {
                EventFormat::Human => demo::run(&opts, &mut out).map(|_| ()),
                EventFormat::Json => demo::run_json(&opts, &mut out),
            }
            .map_err(|e| Failure::Runtime(format!("demo: {e}")))?;
            Ok(())
        }
        Command::Report(a) => {
            let output = a
                .output
                .clone()
                .unwrap_or_else(|| report::default_output(&a.log));
            let r = report::run(&a.log, &output).map_err(Failure::Runtime)?;
            for w in r.warnings() {
                eprintln!("gimbal report: {}: {w}", a.log.display());
            }
            eprintln!(
                "gimbal report: wrote {} ({} KiB; {} lines read, {} not understood)",
                output.display(),
                r.html.len().div_ceil(1024),
                r.log.lines,
                r.warnings().len()
            );
            Ok(())
        }
        Command::Update(a) => {
            let opts = gimbal::update::UpdateOptions {
                port: a.port,
                baud: a.baud,
                image: a.image,
                sig: a.sig,
                wait: std::time::Duration::from_secs(a.wait),
                give_up: std::time::Duration::from_secs(30),
            };
            gimbal::update::update(&opts, &mut std::io::stdout().lock())
                .map(|_| ())
                .map_err(|e| Failure::Runtime(format!("update: {e}")))
        }
        Command::Config(a) => {
            write_lines(config(&a).map_err(|e| Failure::Runtime(format!("config: {e}")))?)
        }
        Command::Sign(a) => {
            gimbal::update::sign(a.key.as_deref(), &a.image, &mut std::io::stdout().lock())
                .map(|_| ())
                .map_err(|e| Failure::Runtime(format!("sign: {e}")))
        }
        Command::ImageInfo { image } => {
            let info = gimbal::update::image_info(&image).map_err(Failure::Runtime)?;
            write_lines([info.to_string()])
        }
        Command::UpdateKey(a) => gimbal::update::new_key(&a.key, &mut std::io::stdout().lock())
            .map_err(|e| Failure::Runtime(format!("update-key: {e}"))),
        Command::Completions { shell } => {
            clap_complete::generate(shell, &mut Cli::command(), "gimbal", &mut std::io::stdout());
            Ok(())
        }
        Command::Bridge(a) => {
            // Contradicting options are usage errors, found before any port is opened.
            bridge::config_of(&a).map_err(Failure::Usage)?;
            install_stop_handler();
            let out = Output::stdout(a.events);
            bridge::run(&a, &out, &STOP).map_err(Failure::Runtime)?;
            Ok(())
        }
        Command::SimFc(a) => {
            install_stop_handler();
            let out = Output::stdout(a.events);
            let (_, met) = sims::run_fc(&a, &out, &STOP).map_err(Failure::Runtime)?;
            expectation(met, "sim-fc")
        }
        Command::SimPod(a) => {
            install_stop_handler();
            let out = Output::stdout(a.events);
            let (_, met) = sims::run_pod(&a, &out, &STOP).map_err(Failure::Runtime)?;
            expectation(met, "sim-pod")
        }
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Usage(e)) => Cli::command().error(ErrorKind::ValueValidation, e).exit(),
        Err(Failure::Runtime(e)) => {
            eprintln!("gimbal: {e}");
            ExitCode::FAILURE
        }
    }
}

/// `gimbal config`: the console's client.
fn config(a: &gimbal::cli::ConfigCommandArgs) -> Result<Vec<String>, String> {
    use gimbal::cli::ConfigAction;
    use gimbal::console_client::{ConsolePort, load};
    let mut port = ConsolePort::open(&a.port, a.baud)?;
    let lines = match &a.action {
        ConfigAction::Get { key } => {
            let answer = port.command(&format!("get {}", key.as_deref().unwrap_or("")))?;
            if !answer.ok() {
                return Err(answer.last);
            }
            answer.lines
        }
        ConfigAction::Dump => {
            let answer = port.command("get")?;
            if !answer.ok() {
                return Err(answer.last);
            }
            answer.lines
        }
        ConfigAction::Set { key, value } => {
            let answer = port.command(&format!("set {key} {value}"))?;
            if !answer.ok() {
                return Err(answer.last);
            }
            answer.lines.into_iter().chain([answer.last]).collect()
        }
        ConfigAction::Load { file } => load(&mut port, file)?,
    };
    Ok(lines)
}
