//! The systemd unit and its environment file (gimbal/dist/, docs/src/deployment.md): the
//! unit restarts the bridge when it fails, runs it as its own user with the serial and
//! GPIO groups, keeps its state in a `StateDirectory=` and its events in the journal; and
//! its command line, with each `GIMBAL_BRIDGE_ARGS` the environment file gives (the line
//! in force and the commented examples), is one `gimbal` parses.

use clap::Parser;
use gimbal::cli::{Cli, Command};

const UNIT: &str = include_str!("../dist/gimbal-bridge.service");
const ENV: &str = include_str!("../dist/gimbal-bridge.env");

/// The values of `key` in `section` of the unit, in order.
fn directive(section: &str, key: &str) -> Vec<String> {
    let mut current = "";
    let mut values = Vec::new();
    for line in UNIT.lines().map(str::trim) {
        if line.starts_with('[') {
            current = line;
        } else if current == format!("[{section}]")
            && let Some((k, v)) = line.split_once('=')
            && k.trim() == key
        {
            values.push(v.trim().to_string());
        }
    }
    values
}

fn one(section: &str, key: &str) -> String {
    let v = directive(section, key);
    assert_eq!(v.len(), 1, "{section} {key}: {v:?}");
    v[0].clone()
}

#[test]
fn the_unit_restarts_runs_as_its_user_keeps_state_and_logs_to_the_journal() {
    assert_eq!(one("Service", "Restart"), "on-failure");
    assert_eq!(one("Unit", "StartLimitIntervalSec"), "0", "never gives up");
    let user = one("Service", "User");
    assert!(!user.is_empty() && user != "root");
    let groups = one("Service", "SupplementaryGroups");
    let groups: Vec<&str> = groups.split_whitespace().collect();
    assert!(
        groups.contains(&"dialout") && groups.contains(&"gpio"),
        "{groups:?}"
    );
    assert_eq!(one("Service", "StateDirectory"), "gimbal-bridge");
    assert_eq!(one("Service", "WorkingDirectory"), "%S/gimbal-bridge");
    assert_eq!(one("Service", "StandardOutput"), "journal");
    assert_eq!(one("Service", "StandardError"), "journal");
    assert_eq!(one("Install", "WantedBy"), "multi-user.target");
    assert_eq!(
        one("Service", "EnvironmentFile"),
        "/etc/gimbal-bridge/bridge.env"
    );
}

#[test]
fn the_units_command_lines_parse() {
    let exec = one("Service", "ExecStart").replace("%S", "/var/lib");
    let examples: Vec<&str> = ENV
        .lines()
        .filter_map(|l| {
            l.trim_start_matches("# ")
                .strip_prefix("GIMBAL_BRIDGE_ARGS=")
        })
        .collect();
    assert!(examples.len() >= 2, "{examples:?}");
    for args in examples {
        let line = exec.replace("$GIMBAL_BRIDGE_ARGS", args);
        let mut words = line.split_whitespace();
        assert_eq!(words.next(), Some("/usr/local/bin/gimbal"));
        let cli = Cli::try_parse_from(std::iter::once("gimbal").chain(words))
            .unwrap_or_else(|e| panic!("{line}: {e}"));
        let Command::Bridge(b) = cli.command else {
            panic!("{line}: not `gimbal bridge`");
        };
        assert_eq!(
            b.photo_events.as_deref(),
            Some(std::path::Path::new("/var/lib/gimbal-bridge/photos.csv"))
        );
        // The state kept across restarts in the StateDirectory: the default (under the
        // home directory) is hidden by ProtectHome, and the bridge would not start.
        assert_eq!(
            b.state_dir.as_deref(),
            Some(std::path::Path::new("/var/lib/gimbal-bridge"))
        );
        assert_eq!(
            b.config_file.as_deref(),
            Some(std::path::Path::new("/etc/gimbal-bridge/bridge.toml"))
        );
    }
}
