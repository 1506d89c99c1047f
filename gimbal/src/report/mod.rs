//! `gimbal report`: a flight's bridge log (the JSON lines of `gimbal bridge --events
//! json`, or `gimbal demo --events json`) as one self-contained HTML page: the time
//! syncs and their error, the track with every photo and geotag, the links, and the
//! summary the demo prints. The log is read line by line ([`log`]), its figures computed
//! once ([`figures`]), the plots drawn by `plotters` into inline SVG ([`plots`], a
//! bounded number of points whatever the length: [`thin`]) and the page written
//! ([`page`]). See docs/src/report.md.

pub mod figures;
pub mod log;
pub mod page;
pub mod plots;
pub mod thin;

use std::path::{Path, PathBuf};

/// A report made.
#[derive(Debug, Clone)]
pub struct Report {
    /// The page.
    pub html: String,
    /// The log as read (its diagnostics and unknown events).
    pub log: log::Log,
    /// Its figures.
    pub figures: figures::Figures,
}

impl Report {
    /// What was not read, one line each (`line N: ...`), for stderr.
    #[must_use]
    pub fn warnings(&self) -> Vec<String> {
        let mut w: Vec<String> = self
            .log
            .diagnostics
            .iter()
            .map(|d| format!("line {}: {}", d.line, d.text))
            .collect();
        w.extend(self.log.unknown.iter().map(|u| {
            format!(
                "line {}: unknown event `{}` ({} line{})",
                u.first_line,
                u.name,
                u.count,
                if u.count == 1 { "" } else { "s" }
            )
        }));
        w
    }
}

/// The report of a log's text; `name` titles the page.
#[must_use]
pub fn report(name: &str, text: &str) -> Report {
    let log = log::read(text);
    let figures = figures::figures(&log);
    let html = page::page(name, &log, &figures);
    Report { html, log, figures }
}

/// Where the page of `log` goes by default: the log's path with `.html`.
#[must_use]
pub fn default_output(log: &Path) -> PathBuf {
    log.with_extension("html")
}

/// Reads `log`, writes its page to `output`; returns the report.
///
/// # Errors
/// The log cannot be read, holds no event at all, or the page cannot be written.
pub fn run(log: &Path, output: &Path) -> Result<Report, String> {
    let bytes = std::fs::read(log).map_err(|e| format!("{}: {e}", log.display()))?;
    let text = String::from_utf8_lossy(&bytes);
    let name = log.file_name().map_or_else(
        || log.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let r = report(&name, &text);
    if r.log.records.is_empty() && r.log.header.is_none() {
        return Err(format!(
            "{}: no event in it ({} line(s); is it `gimbal bridge --events json` output?)",
            log.display(),
            r.log.lines
        ));
    }
    if output == log {
        return Err(format!(
            "{}: the page would overwrite the log (give -o)",
            output.display()
        ));
    }
    std::fs::write(output, &r.html).map_err(|e| format!("{}: {e}", output.display()))?;
    Ok(r)
}
