//! The report as one self-contained HTML page: the summary table, the time syncs, the
//! track with its photos and geotags, the links, and what could not be read. Every text
//! from the log is escaped; the plots are inline SVG; the page loads nothing.

use std::fmt::Write as _;

use serde_json::Value;

use super::figures::{Figures, MarkKind};
use super::log::Log;
use super::plots;
use crate::runner::output::{iso_utc, time_of_day_text};

/// Rows of the photo table at most (the rest are counted).
const PHOTO_ROWS: usize = 500;
/// Diagnostics listed at most (the rest are counted).
const DIAGNOSTICS: usize = 200;

/// `s` with `&`, `<`, `>`, `"` and `'` escaped.
#[must_use]
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// µs as text: ms from 1000 µs on, ns digits below 10 µs (PPS).
fn us(v: f64) -> String {
    if v.abs() >= 1000.0 {
        format!("{:.3} ms", v / 1000.0)
    } else if v.abs() >= 10.0 {
        format!("{v:.1} µs")
    } else {
        format!("{v:.3} µs")
    }
}

/// The summary table's rows: the figures `gimbal demo` prints in its summary, as far
/// as a log holds them.
#[must_use]
#[allow(clippy::too_many_lines, clippy::cast_precision_loss)]
pub fn summary_rows(f: &Figures) -> Vec<(&'static str, String)> {
    let fc = f.fc.clone().unwrap_or_else(|| "unknown".to_string());
    let mut rows = Vec::new();
    rows.push((
        "FC healthy at",
        match f.health {
            Some((Some(t), end)) => format!(
                "{t:.3} s ({} at the end)",
                if end { "still healthy" } else { "NOT healthy" }
            ),
            Some((None, _)) => "never".to_string(),
            None => "not in the log (the simulated FC's view only)".to_string(),
        },
    ));
    rows.push((
        "commands translated",
        format!("{} ({} kinds)", f.translated.0, f.translated.1),
    ));
    let applied = match &f.pod_syncs {
        Some((a, not)) => {
            let mut s = format!("{a} applied by the pod");
            for (why, n) in not {
                let _ = write!(s, ", {n} not ({why})");
            }
            s
        }
        None => "the pod's outcome not in the log (a real pod does not report it)".to_string(),
    };
    let error = match (f.error_p50_max_us, f.bound_p50_max_us) {
        (Some((p50, max)), _) => format!("; error p50 {}, max {}", us(p50), us(max)),
        (None, Some((p50, max))) => format!(
            "; no measured error in the log: bound p50 {}, max {}",
            us(p50 as f64),
            us(max as f64)
        ),
        (None, None) => String::new(),
    };
    rows.push((
        "time syncs",
        format!("{} sent, {applied}{error}", f.syncs.len()),
    ));
    rows.push((
        "PPS",
        f.pps_locked_at_s.map_or_else(
            || "not locked (the FC's UTC alone)".to_string(),
            |t| format!("locked at {t:.3} s"),
        ),
    ));
    rows.push((
        "time source",
        match f.sources.iter().find(|s| s.1) {
            Some((t, _)) => format!(
                "telemetry link from {t:.3} s ({} change{} in all)",
                f.sources.len(),
                if f.sources.len() == 1 { "" } else { "s" }
            ),
            None => format!("the FC link's own time ({fc})"),
        },
    ));
    rows.push((
        "first time sync",
        match (f.first_sync_at_s, f.utc_valid_at_s) {
            (Some(t), Some(u)) => format!(
                "{t:.3} s ({:.1} s after the bridge knew UTC at {u:.3} s){}",
                t - u,
                f.syncs
                    .first()
                    .and_then(|s| s.error_us)
                    .map_or_else(String::new, |e| format!(", error {}", us(e)))
            ),
            (Some(t), None) => format!("{t:.3} s"),
            _ => "none".to_string(),
        },
    ));
    rows.push((
        "UTC lost",
        format!(
            "{} time{}",
            f.utc_lost,
            if f.utc_lost == 1 { "" } else { "s" }
        ),
    ));
    rows.push((
        "RTC_IO edge → 0x00030E",
        f.edge_to_frame_max_us
            .map_or_else(|| "–".to_string(), |d| format!("max {}", us(d as f64))),
    ));
    let refused: Vec<String> = super::figures::Refusal::ALL
        .iter()
        .filter_map(|r| {
            let n = f.geotags.iter().filter(|g| g.refusal == Some(*r)).count();
            (n > 0).then(|| format!("{n} {}", r.text()))
        })
        .collect();
    rows.push((
        "geotags answered",
        format!(
            "{} of {}{}",
            f.geotags_answered(),
            f.geotags.len(),
            if refused.is_empty() {
                String::new()
            } else {
                format!(" (refused: {})", refused.join(", "))
            }
        ),
    ));
    rows.push((
        "photos",
        match f.photos_taken {
            Some(n) => format!("{n} taken by the pod; {} geotagged", f.geotags_answered()),
            None => format!(
                "{} geotagged (the pod's own count is not in the log)",
                f.geotags_answered()
            ),
        },
    ));
    for l in &f.links {
        let name = match l.link {
            super::log::Link::Fc => "FC link",
            super::log::Link::Pod => "pod link",
            // Its row is the time source's (above).
            super::log::Link::Telemetry => continue,
        };
        rows.push((
            name,
            format!("down {} time(s), {:.1} s in all", l.downs, l.down_s),
        ));
    }
    let count = |k: fn(&MarkKind) -> bool| f.marks_where(k).count();
    rows.push((
        "pod reboots / FC silence stops",
        format!(
            "{} / {}",
            count(|k| *k == MarkKind::PodReboot),
            count(|k| *k == MarkKind::SilenceStop)
        ),
    ));
    let c = |n: &str| {
        f.counter(n)
            .map_or_else(|| "–".to_string(), |v| v.to_string())
    };
    rows.push((
        "frames FC link",
        format!(
            "{} FC → bridge, {} bridge → FC ({} of kinds the bridge does not read, {} rejected, {} garbage bytes)",
            c("fc_frames"),
            c("fc_sent"),
            c("fc_unknown_frames"),
            c("fc_rejected"),
            c("fc_garbage_bytes")
        ),
    ));
    rows.push((
        "frames pod link",
        format!(
            "{} pod → bridge, {} bridge → pod ({} rejected, {} garbage bytes, {} retries)",
            c("pod_frames"),
            c("pod_sent"),
            c("pod_rejected"),
            c("pod_garbage_bytes"),
            c("pod_retries")
        ),
    ));
    rows.push((
        "dropped",
        format!("{} frames, {} events", c("dropped"), c("events_dropped")),
    ));
    rows
}

fn table(out: &mut String, head: &[&str], rows: impl IntoIterator<Item = Vec<String>>) {
    out.push_str("<table><thead><tr>");
    for h in head {
        let _ = write!(out, "<th>{}</th>", escape(h));
    }
    out.push_str("</tr></thead><tbody>\n");
    for r in rows {
        out.push_str("<tr>");
        for c in r {
            let _ = write!(out, "<td>{}</td>", escape(&c));
        }
        out.push_str("</tr>\n");
    }
    out.push_str("</tbody></table>\n");
}

fn plot(out: &mut String, svg: Result<String, String>) {
    match svg {
        Ok(s) => {
            out.push_str("<figure>");
            // The XML declaration plotters may write is not wanted inside HTML.
            out.push_str(s.trim_start_matches(|c| c != '<').trim_start());
            out.push_str("</figure>\n");
        }
        Err(e) => {
            let _ = writeln!(
                out,
                "<p class=\"warn\">this plot could not be drawn: {}</p>",
                escape(&e)
            );
        }
    }
}

const STYLE: &str = "body{font-family:sans-serif;max-width:1040px;margin:1em auto;padding:0 1em;color:#222}\
h1{font-size:1.5em}h2{border-bottom:1px solid #ccc;margin-top:2em}\
table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:2px 8px;text-align:left;vertical-align:top}\
th{background:#f0f0f0}.meta{color:#555}.warn{color:#a00}figure{margin:.5em 0}svg{max-width:100%;height:auto}\
details{margin:.5em 0}";

/// The page of a log read from `name`.
#[must_use]
#[allow(clippy::too_many_lines)]
pub fn page(name: &str, log: &Log, f: &Figures) -> String {
    let mut out = String::with_capacity(256 * 1024);
    let _ = write!(
        out,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>Flight report: {}</title><style>{STYLE}</style></head><body>\n",
        escape(name)
    );
    let _ = writeln!(out, "<h1>Flight report: {}</h1>", escape(name));
    let h = log.header.clone().unwrap_or_default();
    let _ = writeln!(
        out,
        "<p class=\"meta\">{} · FC side {} · written by gimbal {} · log version {} · {} lines, {} records · {:.1} s of the log's clock ({:.1} min)</p>",
        escape(if h.event.is_empty() {
            "no start line"
        } else {
            &h.event
        }),
        escape(f.fc.as_deref().unwrap_or("unknown")),
        escape(h.version.as_deref().unwrap_or("unknown")),
        h.log_version
            .map_or_else(|| "none".to_string(), |v| v.to_string()),
        log.lines,
        f.records,
        f.end_s,
        f.end_s / 60.0
    );
    if !log.diagnostics.is_empty() || !log.unknown.is_empty() {
        out.push_str("<h2 class=\"warn\">Lines not read or not understood</h2>\n");
        let _ = writeln!(
            out,
            "<p>{} line(s) could not be read; {} unknown event name(s). The rest of the log is drawn.</p>",
            log.diagnostics.len(),
            log.unknown.len()
        );
        table(
            &mut out,
            &["line", "what"],
            log.diagnostics
                .iter()
                .take(DIAGNOSTICS)
                .map(|d| vec![d.line.to_string(), d.text.clone()]),
        );
        if log.diagnostics.len() > DIAGNOSTICS {
            let _ = writeln!(
                out,
                "<p>… and {} more.</p>",
                log.diagnostics.len() - DIAGNOSTICS
            );
        }
        if !log.unknown.is_empty() {
            table(
                &mut out,
                &["unknown event", "first line", "lines"],
                log.unknown.iter().map(|u| {
                    vec![
                        u.name.clone(),
                        u.first_line.to_string(),
                        u.count.to_string(),
                    ]
                }),
            );
        }
    }

    out.push_str("<h2>Summary</h2>\n");
    table(
        &mut out,
        &["figure", "value"],
        summary_rows(f)
            .into_iter()
            .map(|(k, v)| vec![k.to_string(), v]),
    );

    out.push_str("<h2>1. Time</h2>\n");
    out.push_str("<p>Each sync's RTC_IO edge over the flight: the error bound the bridge believed (the band drawn ±), and the measured error (UTC carried − the true UTC at the edge) where the log has it (the demo and the simulators know the truth; a real flight does not). Vertical lines: the time source changed.</p>\n");
    plot(&mut out, plots::time(f));
    plot(&mut out, plots::bound_histogram(f));

    out.push_str("<h2>2. Photos and geotags</h2>\n");
    out.push_str("<p>The track is the aircraft's position from the bridge's <code>fix</code> events (once a second), in metres east and north of the first fix (equirectangular: fine over a flight's few kilometres). A photo is drawn at the fix the bridge gave the pod; a refused geotag at the track's point nearest in time, with the reason the bridge logged.</p>\n");
    plot(&mut out, plots::track(f));
    let rows = f.geotags.iter().take(PHOTO_ROWS).map(|g| {
        let (utc, lat, lon) = match g.photo {
            Some((utc_us, p)) => (
                iso_utc(utc_us / 1000),
                format!("{:.7}", p.lat_e7 as f64 * 1e-7),
                format!("{:.7}", p.lon_e7 as f64 * 1e-7),
            ),
            None => (String::new(), String::new(), String::new()),
        };
        vec![
            g.line.to_string(),
            format!("{:.3}", g.t_s),
            time_of_day_text(u32::try_from(g.time_of_day_ms).unwrap_or(0)),
            utc,
            lat,
            lon,
            g.at_m
                .map_or_else(String::new, |(e, n)| format!("{e:.1} E, {n:.1} N")),
            g.refusal.map_or_else(
                || "answered".to_string(),
                |r| format!("refused: {}", r.text()),
            ),
        ]
    });
    let _ = writeln!(
        out,
        "<details><summary>Every geotag request ({})</summary>",
        f.geotags.len()
    );
    table(
        &mut out,
        &[
            "line",
            "t, s",
            "time asked",
            "photo UTC",
            "lat",
            "lon",
            "m from start",
            "answer",
        ],
        rows,
    );
    if f.geotags.len() > PHOTO_ROWS {
        let _ = writeln!(out, "<p>… and {} more.</p>", f.geotags.len() - PHOTO_ROWS);
    }
    out.push_str("</details>\n");

    out.push_str("<h2>3. Links</h2>\n");
    out.push_str("<p>Each link's state as the engine reported it (a long flight is drawn in columns, each showing the worst state within it). Garbage: bytes discarded or frames rejected between two <code>counters</code> events. A pod reboot is only known where the log has the simulated pod's <code>sim_pod_boot</code>: to the bridge a real pod's reboot is a link down and up.</p>\n");
    plot(&mut out, plots::links(f));
    if f.marks.is_empty() {
        out.push_str("<p>No reboot, silence stop, garbage or lost port in the log.</p>\n");
    } else {
        table(
            &mut out,
            &["t, s", "link", "what"],
            f.marks.iter().take(DIAGNOSTICS).map(|m| {
                vec![
                    format!("{:.3}", m.t_s),
                    m.link.name().to_string(),
                    match &m.kind {
                        MarkKind::PodReboot => "pod rebooted".to_string(),
                        MarkKind::SilenceStop => {
                            "FC silent while the pod turned: pod stopped".to_string()
                        }
                        MarkKind::Garbage(n) => format!("{n} garbage bytes or rejected frames"),
                        MarkKind::PortLost => "port lost (connection or device)".to_string(),
                        MarkKind::Trouble(t) => t.clone(),
                    },
                ]
            }),
        );
    }
    if !f.pod_refusals.is_empty() {
        table(
            &mut out,
            &["pod command", "refused with", "times"],
            f.pod_refusals
                .iter()
                .map(|((id, code), n)| vec![id.clone(), code.clone(), n.to_string()]),
        );
    }
    if let Some(c) = &f.counters {
        out.push_str("<details><summary>Counters at the end</summary>");
        table(
            &mut out,
            &["counter", "value"],
            c.iter()
                .filter(|(k, _)| *k != "t_us" && *k != "event")
                .map(|(k, v)| {
                    vec![
                        k.clone(),
                        match v {
                            Value::String(s) => s.clone(),
                            other => other.to_string(),
                        },
                    ]
                }),
        );
        out.push_str("</details>\n");
    }
    out.push_str("<p class=\"meta\">Written by <code>gimbal report</code> (docs/src/report.md).</p>\n</body></html>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_escaped() {
        assert_eq!(
            escape(r#"<script src="//x">'&'</script>"#),
            "&lt;script src=&quot;//x&quot;&gt;&#39;&amp;&#39;&lt;/script&gt;"
        );
    }
}
