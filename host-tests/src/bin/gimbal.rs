//! `gimbal`: decode gimbal-protocol serial captures and list the supported messages.
//!
//! ```text
//! cargo gimbal decode <protocol> [--json] [HEX... | --file PATH]   (stdin if neither)
//! cargo gimbal messages <protocol>
//! ```
//! Protocols: k40t, siyi, viewlink, gcu. A capture is hex text (any separators, `0x`
//! prefixes allowed) or raw binary bytes.

use std::io::{Read, Write};
use std::process::ExitCode;

use host_tests::tool::{self, looks_like_hex, parse_hex};

const USAGE: &str = "usage:
  gimbal decode <protocol> [--json] [HEX... | --file PATH]   decode a capture (stdin if no HEX/--file)
  gimbal messages <protocol>                                list every message id the codec supports
protocols: k40t, siyi, viewlink, gcu";

fn read_capture(hex_args: &[String], file: Option<&str>) -> Result<Vec<u8>, String> {
    if !hex_args.is_empty() {
        return parse_hex(&hex_args.join(" "));
    }
    let bytes = match file {
        Some(path) => std::fs::read(path).map_err(|e| format!("{path}: {e}"))?,
        None => {
            let mut b = Vec::new();
            std::io::stdin()
                .read_to_end(&mut b)
                .map_err(|e| format!("stdin: {e}"))?;
            b
        }
    };
    if looks_like_hex(&bytes) {
        parse_hex(&String::from_utf8_lossy(&bytes))
    } else {
        Ok(bytes)
    }
}

fn run(args: &[String]) -> Result<(), String> {
    let (command, rest) = args.split_first().ok_or(USAGE)?;
    let (name, rest) = rest.split_first().ok_or(USAGE)?;
    let protocol =
        tool::protocol(name).ok_or_else(|| format!("unknown protocol {name:?}\n{USAGE}"))?;
    let mut out = std::io::stdout().lock();
    match command.as_str() {
        "messages" => {
            for line in protocol.messages() {
                writeln!(out, "{line}").map_err(|e| e.to_string())?;
            }
            Ok(())
        }
        "decode" => {
            let mut json = false;
            let mut file = None;
            let mut hex_args = Vec::new();
            let mut it = rest.iter();
            while let Some(a) = it.next() {
                match a.as_str() {
                    "--json" => json = true,
                    "--file" => file = Some(it.next().ok_or("--file needs a path")?.as_str()),
                    _ => hex_args.push(a.clone()),
                }
            }
            let capture = read_capture(&hex_args, file)?;
            let items = protocol.scan(&capture);
            for item in &items {
                writeln!(out, "{}", tool::render(protocol.as_ref(), item, json))
                    .map_err(|e| e.to_string())?;
            }
            eprintln!("{}", tool::summary(&items));
            Ok(())
        }
        _ => Err(USAGE.to_string()),
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("gimbal: {e}");
            ExitCode::from(2)
        }
    }
}
