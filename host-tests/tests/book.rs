//! The book's lists that the code also has, compared with the code's (one binary for all
//! of them; the LED table's test is bridge-fw's, `bridge-fw/tests/led_table.rs`):
//! - the option table of `gimbal bridge` (docs/src/linux-bridge.md, "Options") is clap's
//!   command: every option, in clap's order, with its value and its default;
//! - the event table (docs/src/linux-bridge.md, "Output and the JSON events") is
//!   `gimbal::runner::event_name::EventName::ALL`, every name the tool writes, in order;
//! - the counters table (docs/src/linux-bridge.md, "Counters") is the `counters` event's
//!   fields, the engine's `Counters` as the tool writes them, in order;
//! - the README's set-up table says, per FC side and autopilot, the parameters that
//!   the ArduPilot and PX4 pages' set-up tables say.
//!
//! On a difference each test prints the table's first columns as the code has them.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use clap::{Arg, ArgAction, CommandFactory};
use gimbal::cli::Cli;
use gimbal::runner::event_name::EventName;

const LINUX_BRIDGE: &str = include_str!("../../docs/src/linux-bridge.md");
const ARDUPILOT: &str = include_str!("../../docs/src/autopilots/ardupilot.md");
const PX4: &str = include_str!("../../docs/src/autopilots/px4.md");
const README: &str = include_str!("../../README.md");

/// A table row's cells, trimmed; `\|` inside a cell is a `|`.
fn cells(line: &str) -> Vec<String> {
    let inner = line.trim().trim_start_matches('|').trim_end_matches('|');
    let mut out = vec![String::new()];
    let mut chars = inner.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\\' if chars.peek() == Some(&'|') => {
                out.last_mut().unwrap().push('|');
                chars.next();
            }
            '|' => out.push(String::new()),
            c => out.last_mut().unwrap().push(c),
        }
    }
    out.iter().map(|c| c.trim().to_string()).collect()
}

/// The rows of the first table after the heading `heading` (any level) whose header row
/// starts with `header`, each as its cells.
fn table(page: &str, heading: &str, header: &str) -> Vec<Vec<String>> {
    let mut lines = page.lines();
    lines
        .by_ref()
        .find(|l| l.starts_with('#') && l.trim_start_matches('#').trim() == heading)
        .unwrap_or_else(|| panic!("a heading `{heading}`"));
    let rows: Vec<Vec<String>> = lines
        .skip_while(|l| !l.starts_with(header))
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .map(cells)
        .collect();
    assert!(!rows.is_empty(), "a table `{header}` under `{heading}`");
    rows
}

/// The words in backticks in a cell, in order.
fn quoted(cell: &str) -> Vec<String> {
    cell.split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

/// Fails unless the book's names are the code's, in the code's order, naming what is
/// missing and what is extra.
fn assert_same_names(table: &str, code_list: &str, book: &[String], code: &[String]) {
    let missing: Vec<&String> = code.iter().filter(|n| !book.contains(n)).collect();
    let extra: Vec<&String> = book.iter().filter(|n| !code.contains(n)).collect();
    assert!(
        book == code,
        "docs/src/linux-bridge.md's {table} differs from {code_list}: missing {missing:?}, \
         not in the code {extra:?}; the code's order:\n{}",
        code.join("\n")
    );
}

/// An option's value cell as the book writes it: `—` for a flag, its possible values in
/// backticks, or its value name in backticks.
fn value_cell(a: &Arg) -> String {
    if matches!(a.get_action(), ArgAction::SetTrue) {
        return "—".into();
    }
    let values: Vec<String> = a
        .get_possible_values()
        .iter()
        .filter(|v| !v.is_hide_set())
        .map(|v| format!("`{}`", v.get_name()))
        .collect();
    if !values.is_empty() {
        return values.join(", ");
    }
    a.get_value_names()
        .map(|n| {
            n.iter()
                .map(|n| format!("`{n}`"))
                .collect::<Vec<_>>()
                .join(" ")
        })
        .unwrap_or_else(|| format!("`{}`", a.get_id().as_str().to_uppercase()))
}

/// An option's default cell: `required`, its default in backticks, or `—`.
fn default_cell(a: &Arg) -> String {
    if a.is_required_set() {
        return "required".into();
    }
    if matches!(a.get_action(), ArgAction::SetTrue) {
        return "—".into();
    }
    let defaults: Vec<String> = a
        .get_default_values()
        .iter()
        .map(|d| format!("`{}`", d.to_string_lossy()))
        .collect();
    if defaults.is_empty() {
        "—".into()
    } else {
        defaults.join(", ")
    }
}

/// `gimbal bridge`'s options as clap has them: (option, value, default), in order.
fn code_options() -> Vec<[String; 3]> {
    let mut cli = Cli::command();
    cli.build();
    let bridge = cli
        .find_subcommand("bridge")
        .expect("a `bridge` subcommand");
    bridge
        .get_arguments()
        .filter(|a| !matches!(a.get_id().as_str(), "help" | "version"))
        .map(|a| {
            let long = a
                .get_long()
                .unwrap_or_else(|| panic!("{}: not a long option", a.get_id()));
            [format!("`--{long}`"), value_cell(a), default_cell(a)]
        })
        .collect()
}

#[test]
fn the_books_option_table_is_gimbal_bridges() {
    let book: Vec<[String; 3]> = table(LINUX_BRIDGE, "Options", "| option | value | default |")
        .into_iter()
        .map(|r| {
            assert_eq!(r.len(), 4, "four cells: {r:?}");
            [r[0].clone(), r[1].clone(), r[2].clone()]
        })
        .collect();
    let code = code_options();
    let as_table: String = code
        .iter()
        .map(|[o, v, d]| format!("| {o} | {v} | {d} | … |\n"))
        .collect();
    assert!(
        book == code,
        "docs/src/linux-bridge.md's option table differs from `gimbal bridge`'s options; \
         the code's (option, value, default):\n{as_table}"
    );
}

#[test]
fn the_books_event_table_is_every_event_the_tool_writes() {
    let book: Vec<String> = table(
        LINUX_BRIDGE,
        "Output and the JSON events",
        "| event | fields | when |",
    )
    .iter()
    .flat_map(|r| quoted(&r[0]))
    .collect();
    let code: Vec<String> = EventName::ALL
        .iter()
        .map(|e| e.as_str().to_string())
        .collect();
    assert_same_names("event table", "EventName::ALL", &book, &code);
}

#[test]
fn the_books_counters_are_the_engines() {
    let book: Vec<String> = table(LINUX_BRIDGE, "Counters", "| counter | counts |")
        .iter()
        .flat_map(|r| quoted(&r[0]))
        .collect();
    let written = gimbal::runner::events::counters(&bridge_engine::Counters::default());
    let code: Vec<String> = written
        .as_object()
        .expect("the counters are an object")
        .keys()
        .cloned()
        .collect();
    assert_same_names("counters table", "the counters event", &book, &code);
}

/// The parameters of a set-up row: every `NAME` = VALUE pair in its cells.
fn parameters(row: &[String]) -> Vec<String> {
    let mut out = Vec::new();
    for cell in row {
        let parts: Vec<&str> = cell.split('`').collect();
        for (i, p) in parts.iter().enumerate().skip(1).step_by(2) {
            let after = parts.get(i + 1).copied().unwrap_or("");
            if let Some(rest) = after.trim_start().strip_prefix('=') {
                let value: String = rest
                    .trim_start()
                    .chars()
                    .take_while(|c| c.is_ascii_digit())
                    .collect();
                if !value.is_empty() {
                    out.push(format!("{p}={value}"));
                }
            }
        }
    }
    out.sort();
    out
}

/// The README's set-up table says, per FC side, the parameters the autopilot pages say:
/// ArduPilot's (docs/src/autopilots/ardupilot.md, "Set-up") and PX4's
/// (docs/src/autopilots/px4.md, "Set-up").
#[test]
fn the_readmes_set_up_is_the_autopilot_pages() {
    let readme = table(README, "Autopilot set-up", "| FC side | ArduPilot |");
    let ardupilot = table(ARDUPILOT, "Set-up", "| FC side | ArduPilot parameters |");
    let px4 = table(PX4, "Set-up", "| | MAVLink FC side |");
    for row in &ardupilot {
        let side = &row[0];
        let readme_row = readme
            .iter()
            .find(|r| &r[0] == side)
            .unwrap_or_else(|| panic!("the README's set-up has no row `{side}`"));
        assert_eq!(
            parameters(&readme_row[1..2]),
            parameters(&row[1..2]),
            "ArduPilot, {side}"
        );
    }
    // PX4: the MAVLink side's and the telemetry link's parameters.
    let px4_column = |col: usize| -> Vec<String> {
        let cells: Vec<String> = px4.iter().map(|r| r[col].clone()).collect();
        parameters(&cells)
    };
    let readme_px4 = |side_starts: &str| -> Vec<String> {
        let r = readme
            .iter()
            .find(|r| r[0].starts_with(side_starts))
            .unwrap_or_else(|| panic!("the README's set-up has no row `{side_starts}…`"));
        parameters(&r[2..3])
    };
    assert_eq!(
        readme_px4("MAVLink"),
        px4_column(1),
        "PX4, the MAVLink side"
    );
    assert_eq!(
        readme_px4("telemetry link"),
        px4_column(2),
        "PX4, the telemetry link"
    );
}

#[test]
fn cells_and_parameters_are_read_as_written() {
    assert_eq!(
        cells("| `a` \\| `b` | x |"),
        ["`a` | `b`".to_string(), "x".to_string()]
    );
    assert_eq!(
        quoted("`fc_link_up` / `fc_link_down`"),
        ["fc_link_up", "fc_link_down"]
    );
    assert_eq!(
        parameters(&["`MNT1_TYPE` = 8 (Siyi), `CAM1_TYPE` = 4, `SERIALn_BAUD` = 115".into()]),
        ["CAM1_TYPE=4", "MNT1_TYPE=8", "SERIALn_BAUD=115"]
    );
}
