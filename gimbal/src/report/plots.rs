//! The report's plots, drawn by `plotters` into SVG text (its SVG backend: no fonts, no
//! bitmaps, nothing fetched; the text is the browser's sans-serif). Each plot draws a
//! bounded number of elements ([`super::thin`]), whatever the flight's length.

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::figures::{Figures, MarkKind, State};
use super::log::Link;
use super::thin;

/// Points per time series (twice this at most: the low and high of each bucket).
const SERIES_BUCKETS: usize = 600;
/// Points of the track.
const TRACK_POINTS: usize = 1500;
/// Columns of a link's timeline.
const LINK_COLUMNS: usize = 1000;
/// Marks drawn per kind (the rest are counted in the tables).
const MARKS: usize = 400;
/// Photos and geotags drawn on the track.
const GEOTAGS: usize = 2000;

const WIDTH: u32 = 1000;
const FONT: &str = "sans-serif";
const BOUND: RGBColor = RGBColor(31, 119, 180);
const ERROR: RGBColor = RGBColor(214, 39, 40);
const GOOD: RGBColor = RGBColor(44, 160, 44);
const UP: RGBColor = RGBColor(152, 223, 138);
const DOWN: RGBColor = RGBColor(214, 39, 40);
const UNKNOWN: RGBColor = RGBColor(220, 220, 220);
const MARK: RGBColor = RGBColor(255, 127, 14);

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// Draws into an SVG string; a drawing error is the plot's text instead.
fn svg(
    size: (u32, u32),
    draw: impl FnOnce(&Area<'_>) -> Result<(), String>,
) -> Result<String, String> {
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        draw(&root)?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(out)
}

/// A chart with a caption of `size` points, its axes' labels `y_area` pixels wide.
fn builder<'a, 'b>(
    root: &'a Area<'b>,
    caption: &str,
    size: u32,
    y_area: u32,
) -> ChartBuilder<'a, 'b, SVGBackend<'b>> {
    let mut b = ChartBuilder::on(root);
    b.caption(caption, (FONT, size))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(y_area);
    b
}

/// A chart over two f64 ranges.
type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Draws the chart's legend at `position`.
fn legend<'a, 'b: 'a>(
    chart: &mut Chart<'a, 'b>,
    position: SeriesLabelPosition,
) -> Result<(), String> {
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.3))
        .label_font((FONT, 13))
        .draw()
        .map_err(|e| e.to_string())
}

/// The largest magnitude drawn: values beyond it (a log can hold 1e308) are drawn at it.
const AXIS_LIMIT: f64 = 1e15;

/// A range that is never empty, with a margin.
///
/// Whatever the log holds, the axis is one plotters can place its ticks on: finite, within
/// ±1e15, and at least a millionth of its magnitude wide (plotters steps from one tick to
/// the next, and a step lost in rounding would never end).
fn range(lo: f64, hi: f64) -> std::ops::Range<f64> {
    let sane = |v: f64| {
        if v.is_finite() {
            v.clamp(-AXIS_LIMIT, AXIS_LIMIT)
        } else {
            0.0
        }
    };
    let (lo, hi) = (sane(lo.min(hi)), sane(lo.max(hi)));
    let least = (lo.abs().max(hi.abs()) * 1e-6).max(1.0);
    let (lo, hi) = if hi - lo >= least {
        (lo, hi)
    } else {
        let mid = lo / 2.0 + hi / 2.0;
        (mid - least / 2.0, mid + least / 2.0)
    };
    let m = (hi - lo) * 0.03;
    (lo - m)..(hi + m)
}

/// Seconds or minutes, whichever reads better for the flight's length.
fn time_unit(end_s: f64) -> (f64, &'static str) {
    if end_s > 1200.0 {
        (60.0, "flight time (min of the log's clock)")
    } else {
        (1.0, "flight time (s of the log's clock)")
    }
}

/// The error bound of each sync over the flight, ± (the band the true error is believed
/// in), the measured error where the log has it, and the time source's changes.
///
/// # Errors
/// Plotters' drawing error, as text.
pub fn time(f: &Figures) -> Result<String, String> {
    let (unit, x_desc) = time_unit(f.end_s);
    #[allow(clippy::cast_precision_loss)]
    let bound: Vec<(f64, f64)> = f
        .syncs
        .iter()
        .map(|s| (s.t_s / unit, (s.bound_us as f64).min(AXIS_LIMIT)))
        .collect();
    let bound = thin::min_max(&bound, SERIES_BUCKETS);
    let errors: Vec<(f64, f64)> = f
        .syncs
        .iter()
        .filter_map(|s| Some((s.t_s / unit, s.error_us?.clamp(-AXIS_LIMIT, AXIS_LIMIT))))
        .collect();
    let errors = thin::min_max(&errors, SERIES_BUCKETS);
    let top = bound
        .iter()
        .map(|p| p.1)
        .chain(errors.iter().map(|p| p.1.abs()))
        .fold(1.0_f64, f64::max);
    svg((WIDTH, 360), |root| {
        let mut chart = builder(
            root,
            "Time syncs: error bound (±) and measured error, µs",
            18,
            70,
        )
        .build_cartesian_2d(range(0.0, f.end_s / unit), range(-top, top))
        .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc("µs")
            .draw()
            .map_err(|e| e.to_string())?;
        for sign in [1.0, -1.0] {
            let line = chart
                .draw_series(LineSeries::new(
                    bound.iter().map(|&(t, b)| (t, sign * b)),
                    BOUND.stroke_width(2),
                ))
                .map_err(|e| e.to_string())?;
            if sign > 0.0 {
                line.label("error bound believed (±)").legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], BOUND.stroke_width(2))
                });
            }
        }
        if !errors.is_empty() {
            chart
                .draw_series(errors.iter().map(|&p| Circle::new(p, 3, ERROR.filled())))
                .map_err(|e| e.to_string())?
                .label("measured error")
                .legend(|(x, y)| Circle::new((x + 10, y), 3, ERROR.filled()));
        }
        for &(t, telemetry) in &f.sources {
            let x = t / unit;
            chart
                .draw_series(LineSeries::new(
                    [(x, -top), (x, top)],
                    BLACK.mix(0.4).stroke_width(1),
                ))
                .map_err(|e| e.to_string())?;
            chart
                .draw_series(std::iter::once(Text::new(
                    if telemetry {
                        "→ telemetry time"
                    } else {
                        "→ FC time"
                    },
                    (x, top),
                    (FONT, 13),
                )))
                .map_err(|e| e.to_string())?;
        }
        legend(&mut chart, SeriesLabelPosition::LowerRight)
    })
}

/// A histogram of the syncs' error bounds.
///
/// # Errors
/// Plotters' drawing error, as text.
pub fn bound_histogram(f: &Figures) -> Result<String, String> {
    const BINS: u32 = 24;
    let max = f.syncs.iter().map(|s| s.bound_us).max().unwrap_or(0).max(1);
    let width = max.div_ceil(u64::from(BINS)).max(1);
    let mut counts = [0u32; BINS as usize];
    for s in &f.syncs {
        let b = usize::try_from(s.bound_us / width)
            .unwrap_or(usize::MAX)
            .min(counts.len() - 1);
        if let Some(c) = counts.get_mut(b) {
            *c = c.saturating_add(1);
        }
    }
    let top = counts.iter().copied().max().unwrap_or(0).max(1);
    svg((WIDTH, 300), |root| {
        let mut chart = builder(
            root,
            "Error bound of the syncs: how many in each band (µs)",
            18,
            60,
        )
        .build_cartesian_2d((0u32..BINS).into_segmented(), 0u32..top.saturating_add(1))
        .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_desc("error bound, µs (lower edge of the band)")
            .y_desc("syncs")
            .x_label_formatter(&|v| match v {
                SegmentValue::Exact(b) | SegmentValue::CenterOf(b) => {
                    format!("{}", u64::from(*b).saturating_mul(width))
                }
                SegmentValue::Last => String::new(),
            })
            .draw()
            .map_err(|e| e.to_string())?;
        chart
            .draw_series(
                Histogram::vertical(&chart)
                    .style(BOUND.filled())
                    .margin(2)
                    .data((0u32..).zip(counts)),
            )
            .map_err(|e| e.to_string())?;
        Ok(())
    })
}

/// The aircraft's track, metres from its first fix, with every photo (answered geotag)
/// and every refused geotag (marked with its reason).
///
/// # Errors
/// Plotters' drawing error, as text.
pub fn track(f: &Figures) -> Result<String, String> {
    let track: Vec<(f64, f64)> = thin::stride(&f.track, TRACK_POINTS)
        .into_iter()
        .map(|(_, e, n)| (e, n))
        .collect();
    let shown = thin::stride(&f.geotags, GEOTAGS);
    let photos: Vec<(f64, f64)> = shown
        .iter()
        .filter(|g| g.photo.is_some())
        .filter_map(|g| g.at_m)
        .collect();
    let refused: Vec<((f64, f64), &str)> = shown
        .iter()
        .filter_map(|g| Some((g.at_m?, g.refusal?.text())))
        .collect();
    let all = track
        .iter()
        .chain(&photos)
        .chain(refused.iter().map(|r| &r.0));
    let (mut x0, mut x1, mut y0, mut y1) = (0.0_f64, 0.0_f64, 0.0_f64, 0.0_f64);
    for &(x, y) in all {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    // One metre is as long east as north: the plot area is about 900 × 560 px.
    let (w, h) = (900.0, 560.0);
    let scale = ((x1 - x0) / w).max((y1 - y0) / h).max(0.01);
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    let (hx, hy) = (scale * w / 2.0, scale * h / 2.0);
    svg((WIDTH, 660), |root| {
        let mut chart = builder(
            root,
            "Track (m east and north of the first fix), photos and geotags",
            18,
            70,
        )
        .build_cartesian_2d(range(cx - hx, cx + hx), range(cy - hy, cy + hy))
        .map_err(|e| e.to_string())?;
        chart
            .configure_mesh()
            .x_desc("m east")
            .y_desc("m north")
            .draw()
            .map_err(|e| e.to_string())?;
        chart
            .draw_series(LineSeries::new(
                track.iter().copied(),
                BOUND.stroke_width(2),
            ))
            .map_err(|e| e.to_string())?
            .label("track (fix events)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BOUND.stroke_width(2)));
        if let Some(&start) = track.first() {
            chart
                .draw_series([
                    EmptyElement::at(start) + TriangleMarker::new((0, 0), 7, BLACK.filled())
                ])
                .map_err(|e| e.to_string())?
                .label("start")
                .legend(|(x, y)| TriangleMarker::new((x + 10, y), 6, BLACK.filled()));
        }
        chart
            .draw_series(photos.iter().map(|&p| Circle::new(p, 4, GOOD.filled())))
            .map_err(|e| e.to_string())?
            .label("photo geotagged (the fix given)")
            .legend(|(x, y)| Circle::new((x + 10, y), 4, GOOD.filled()));
        if !refused.is_empty() {
            chart
                .draw_series(refused.iter().map(|&(p, why)| {
                    EmptyElement::at(p)
                        + Cross::new((0, 0), 6, ERROR.stroke_width(3))
                        + Text::new(
                            why.to_string(),
                            (8, -6),
                            (FONT, 12).into_font().color(&ERROR),
                        )
                }))
                .map_err(|e| e.to_string())?
                .label("geotag refused (reason; drawn on the track nearest in time)")
                .legend(|(x, y)| Cross::new((x + 10, y), 5, ERROR.stroke_width(3)));
        }
        legend(&mut chart, SeriesLabelPosition::UpperLeft)
    })
}

/// One row per link (up, down, unknown), with the pod's reboots, the FC silence stops,
/// garbage and lost ports marked.
///
/// # Errors
/// Plotters' drawing error, as text.
pub fn links(f: &Figures) -> Result<String, String> {
    let (unit, x_desc) = time_unit(f.end_s);
    let rows: Vec<Link> = f.links.iter().map(|l| l.link).collect();
    let rows = if rows.is_empty() {
        vec![Link::Fc, Link::Pod]
    } else {
        rows
    };
    #[allow(clippy::cast_precision_loss)]
    let row_of = |link: Link| rows.iter().position(|l| *l == link).map(|i| i as f64);
    #[allow(clippy::cast_precision_loss)]
    let n = rows.len() as f64;
    let labels = rows.clone();
    svg(
        (WIDTH, 110 + 70 * u32::try_from(rows.len()).unwrap_or(3)),
        |root| {
            let mut chart = builder(root, "Links: up (green), down (red), not yet known (grey); marks: ▲ pod reboot, ✕ FC silence stop, ● garbage, ■ port lost or trouble", 15, 90)
            .build_cartesian_2d(range(0.0, f.end_s / unit), 0.0..n)
            .map_err(|e| e.to_string())?;
            chart
                .configure_mesh()
                .disable_y_mesh()
                .y_labels(rows.len().saturating_mul(2).saturating_add(1))
                .y_label_formatter(&|y| {
                    let frac = y.fract();
                    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
                    let i = y.floor().max(0.0) as usize;
                    if (frac - 0.5).abs() < 0.01 {
                        labels
                            .get(i)
                            .map_or(String::new(), |l| format!("{} link", l.name()))
                    } else {
                        String::new()
                    }
                })
                .x_desc(x_desc)
                .draw()
                .map_err(|e| e.to_string())?;
            for line in &f.links {
                let Some(y) = row_of(line.link) else { continue };
                let spans = thin::spans(&line.spans, f.end_s, LINK_COLUMNS);
                chart
                    .draw_series(spans.iter().map(|s| {
                        let color = match s.state {
                            State::Up => UP,
                            State::Down => DOWN,
                            State::Unknown => UNKNOWN,
                        };
                        Rectangle::new(
                            [(s.from_s / unit, y + 0.2), (s.to_s / unit, y + 0.8)],
                            color.filled(),
                        )
                    }))
                    .map_err(|e| e.to_string())?;
            }
            let marks = |kind: fn(&MarkKind) -> bool| -> Vec<(f64, f64)> {
                f.marks
                    .iter()
                    .filter(|m| kind(&m.kind))
                    .filter_map(|m| Some((m.t_s / unit, row_of(m.link)? + 0.5)))
                    .take(MARKS)
                    .collect()
            };
            let reboots = marks(|k| *k == MarkKind::PodReboot);
            chart
                .draw_series(
                    reboots
                        .iter()
                        .map(|&p| TriangleMarker::new(p, 8, BLACK.filled())),
                )
                .map_err(|e| e.to_string())?;
            let stops = marks(|k| *k == MarkKind::SilenceStop);
            chart
                .draw_series(
                    stops
                        .iter()
                        .map(|&p| Cross::new(p, 7, BLACK.stroke_width(3))),
                )
                .map_err(|e| e.to_string())?;
            let garbage = marks(|k| matches!(k, MarkKind::Garbage(_)));
            chart
                .draw_series(garbage.iter().map(|&p| Circle::new(p, 4, MARK.filled())))
                .map_err(|e| e.to_string())?;
            let lost = marks(|k| matches!(k, MarkKind::PortLost | MarkKind::Trouble(_)));
            chart
                .draw_series(lost.iter().map(|&p| {
                    EmptyElement::at(p) + Rectangle::new([(-4, -4), (4, 4)], BLACK.filled())
                }))
                .map_err(|e| e.to_string())?;
            Ok(())
        },
    )
}
