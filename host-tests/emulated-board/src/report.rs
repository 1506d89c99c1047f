//! What a scenario found: its checks in order, and the report printed for people.

use std::path::{Path, PathBuf};
use std::time::Duration as StdDuration;

use crate::Side;

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

    /// Prints the report of the scenario (one line, and on a failure the failed checks
    /// and the tails of QEMU's output and GPIO trace); true when it passed.
    pub fn print(&self) -> bool {
        let ok = self.passed();
        let figures: Vec<String> = self
            .checks
            .iter()
            .map(|c| format!("{}: {}", c.name, c.detail))
            .collect();
        println!(
            "{} {:<8} ({:.0} s) {}",
            if ok { "PASS" } else { "FAIL" },
            self.side.name(),
            self.wall.as_secs_f64(),
            figures.join(" | ")
        );
        if !ok {
            for c in self.checks.iter().filter(|c| !c.ok) {
                println!("    failed: {}: {}", c.name, c.detail);
            }
            if self.checks.len() < self.side.checks() {
                println!(
                    "    {} of {} checks reached",
                    self.checks.len(),
                    self.side.checks()
                );
            }
            println!(
                "    --- QEMU output ({}), last lines:",
                self.qemu_out.display()
            );
            println!("{}", tail(&self.qemu_out, 20));
            println!("    --- GPIO trace ({}), last lines:", self.trace.display());
            println!("{}", tail(&self.trace, 10));
        }
        ok
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
