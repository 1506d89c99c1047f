//! The figures of a log: what the page shows, computed once from the records
//! ([`super::log`]). Times are seconds of the log's own clock (`t_us`: since the bridge
//! started); positions metres east and north of the first fix, by the equirectangular
//! approximation (a flight's extent: centimetres of error over kilometres).

use serde_json::{Map, Value};

use super::log::{Link, Log, Pos, Rec};

/// Metres per degree of latitude (and of longitude at the equator).
const M_PER_DEG: f64 = 111_320.0;

/// One time sync.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SyncPoint {
    /// Its edge, s.
    pub t_s: f64,
    /// The error bound believed, µs.
    pub bound_us: u64,
    /// The measured error (UTC carried − the truth), µs, where the log has it.
    pub error_us: Option<f64>,
}

/// Why a geotag was answered without a fix: the `reason` of the bridge's `geotag` event.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refusal {
    /// `utc_unknown`: the bridge did not know UTC (or the time of day asked was not one).
    UtcUnknown,
    /// `no_fix`: no fix had been received.
    NoFix,
    /// `out_of_range`: no fix kept was near enough the instant asked.
    OutOfRange,
    /// The event gave no reason the report knows.
    NotGiven,
}

impl Refusal {
    /// Every reason, in the order the page lists them.
    pub const ALL: [Refusal; 4] = [
        Refusal::UtcUnknown,
        Refusal::NoFix,
        Refusal::OutOfRange,
        Refusal::NotGiven,
    ];

    /// The event's `reason`.
    #[must_use]
    pub fn from_reason(reason: Option<&str>) -> Self {
        match reason {
            Some("utc_unknown") => Refusal::UtcUnknown,
            Some("no_fix") => Refusal::NoFix,
            Some("out_of_range") => Refusal::OutOfRange,
            _ => Refusal::NotGiven,
        }
    }

    /// The reason, for the page.
    #[must_use]
    pub const fn text(self) -> &'static str {
        match self {
            Refusal::UtcUnknown => "UTC unknown",
            Refusal::NoFix => "no fix received",
            Refusal::OutOfRange => "no fix near the instant",
            Refusal::NotGiven => "reason not in the log",
        }
    }
}

/// A geotag request of the pod and its answer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GeotagPoint {
    /// When the bridge answered, s.
    pub t_s: f64,
    /// Its line in the log.
    pub line: usize,
    /// The time of day asked, ms.
    pub time_of_day_ms: u64,
    /// The photo's UTC and fix (answered), µs since the Unix epoch.
    pub photo: Option<(u64, Pos)>,
    /// Why not (refused).
    pub refusal: Option<Refusal>,
    /// Where it is drawn, m east and north of the origin: the fix given, or the track
    /// nearest in time for a refusal (none without fixes).
    pub at_m: Option<(f64, f64)>,
}

/// A link's state over a span of the flight.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum State {
    /// No event yet.
    Unknown,
    /// Up.
    Up,
    /// Down.
    Down,
}

/// A span of one link's state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span {
    /// From, s.
    pub from_s: f64,
    /// To, s.
    pub to_s: f64,
    /// The state.
    pub state: State,
}

/// Something that happened on a link at an instant.
#[derive(Debug, Clone, PartialEq)]
pub enum MarkKind {
    /// The simulated pod booted again.
    PodReboot,
    /// The pod was stopped: the FC went silent while it turned.
    SilenceStop,
    /// Bytes the deframer discarded, or frames rejected, since the previous counters.
    Garbage(u64),
    /// A real port's connection or device was lost.
    PortLost,
    /// Trouble inside the bridge (dropped frames, read and write errors, stalls).
    Trouble(String),
}

/// A mark on a link's timeline.
#[derive(Debug, Clone, PartialEq)]
pub struct Mark {
    /// When, s.
    pub t_s: f64,
    /// The link.
    pub link: Link,
    /// What.
    pub kind: MarkKind,
}

/// One link's timeline.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkLine {
    /// The link.
    pub link: Link,
    /// Its states, from 0 to the end.
    pub spans: Vec<Span>,
    /// Times it went down.
    pub downs: usize,
    /// Seconds down in all.
    pub down_s: f64,
}

/// The figures of a log.
#[derive(Debug, Clone, Default)]
pub struct Figures {
    /// The FC side (the start line's).
    pub fc: Option<String>,
    /// The last instant of the log, s.
    pub end_s: f64,
    /// Records read.
    pub records: usize,
    /// Every time sync.
    pub syncs: Vec<SyncPoint>,
    /// Median and largest error bound, µs.
    pub bound_p50_max_us: Option<(u64, u64)>,
    /// Median and largest |measured error|, µs.
    pub error_p50_max_us: Option<(f64, f64)>,
    /// Syncs the simulated pod applied, and those it did not by outcome (none: no pod
    /// reports in the log, as with a real pod, which does not say).
    pub pod_syncs: Option<(usize, Vec<(String, usize)>)>,
    /// UTC first known, s.
    pub utc_valid_at_s: Option<f64>,
    /// Times UTC was lost.
    pub utc_lost: usize,
    /// The first sync's edge, s.
    pub first_sync_at_s: Option<f64>,
    /// The time source's changes: (s, the telemetry link).
    pub sources: Vec<(f64, bool)>,
    /// The clock locked to PPS, s.
    pub pps_locked_at_s: Option<f64>,
    /// Largest delay from an edge to its 0x00030E, µs.
    pub edge_to_frame_max_us: Option<u64>,
    /// The first fix (or photo), the origin of the metres.
    pub origin: Option<Pos>,
    /// The track: (s, m east, m north), every fix.
    pub track: Vec<(f64, f64, f64)>,
    /// Every geotag request.
    pub geotags: Vec<GeotagPoint>,
    /// Photos the simulated pod took (none: not in the log).
    pub photos_taken: Option<usize>,
    /// Every link's timeline.
    pub links: Vec<LinkLine>,
    /// The marks on them.
    pub marks: Vec<Mark>,
    /// The last `counters` event.
    pub counters: Option<Map<String, Value>>,
    /// Commands translated, and distinct (FC command, pod command) pairs.
    pub translated: (usize, usize),
    /// The simulated FC first healthy, s, and healthy at the end.
    pub health: Option<(Option<f64>, bool)>,
    /// Pod refusals and time-outs: (pod id, code) and how many.
    pub pod_refusals: Vec<((String, String), usize)>,
}

impl Figures {
    /// Geotags answered with a fix.
    #[must_use]
    pub fn geotags_answered(&self) -> usize {
        self.geotags.iter().filter(|g| g.photo.is_some()).count()
    }

    /// A counter at the end.
    #[must_use]
    pub fn counter(&self, name: &str) -> Option<u64> {
        self.counters.as_ref()?.get(name)?.as_u64()
    }

    /// The marks of a kind.
    pub fn marks_where(&self, f: impl Fn(&MarkKind) -> bool) -> impl Iterator<Item = &Mark> {
        self.marks.iter().filter(move |m| f(&m.kind))
    }
}

/// Seconds of a `t_us`.
#[allow(clippy::cast_precision_loss)]
fn secs(t_us: u64) -> f64 {
    t_us as f64 / 1e6
}

/// Metres east and north of `origin`.
#[allow(clippy::cast_precision_loss)]
#[must_use]
pub fn metres(origin: Pos, p: Pos) -> (f64, f64) {
    let lat0 = (origin.lat_e7 as f64 * 1e-7).to_radians();
    let north = p.lat_e7.saturating_sub(origin.lat_e7) as f64 * 1e-7 * M_PER_DEG;
    let east = p.lon_e7.saturating_sub(origin.lon_e7) as f64 * 1e-7 * M_PER_DEG * lat0.cos();
    (east, north)
}

/// The value at quantile `q` of sorted values (nearest rank); the demo's summary uses it
/// too, so that the page and the summary agree.
pub(crate) fn quantile<T: Copy>(sorted: &[T], q: f64) -> Option<T> {
    #[allow(
        clippy::cast_precision_loss,
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss
    )]
    let i = (sorted.len().checked_sub(1)? as f64 * q).round() as usize;
    sorted.get(i).copied()
}

/// What the links' records say, step by step.
#[derive(Default)]
struct LinkBuilder {
    /// Per link: state changes (s, state).
    changes: Vec<(Link, f64, State)>,
    /// The garbage counters last seen, per link.
    last_garbage: [u64; 2],
}

impl LinkBuilder {
    fn set(&mut self, link: Link, t: f64, state: State) {
        self.changes.push((link, t, state));
    }

    fn lines(&self, end_s: f64) -> Vec<LinkLine> {
        let mut out = Vec::new();
        for link in Link::ALL {
            let changes: Vec<(f64, State)> = self
                .changes
                .iter()
                .filter(|c| c.0 == link)
                .map(|c| (c.1, c.2))
                .collect();
            if changes.is_empty() {
                continue;
            }
            let mut spans = Vec::new();
            let mut from = 0.0;
            let mut state = State::Unknown;
            let mut downs = 0;
            for (t, s) in changes {
                if s == state {
                    continue;
                }
                if t > from {
                    spans.push(Span {
                        from_s: from,
                        to_s: t,
                        state,
                    });
                }
                downs += usize::from(s == State::Down);
                from = t;
                state = s;
            }
            spans.push(Span {
                from_s: from,
                to_s: end_s.max(from),
                state,
            });
            let down_s = spans
                .iter()
                .filter(|s| s.state == State::Down)
                .fold(0.0, |sum, s| sum + (s.to_s - s.from_s));
            out.push(LinkLine {
                link,
                spans,
                downs,
                down_s,
            });
        }
        out
    }
}

/// The figures of a log.
#[must_use]
#[allow(clippy::too_many_lines)]
pub fn figures(log: &Log) -> Figures {
    let mut f = Figures {
        fc: log.header.as_ref().and_then(|h| h.fc.clone()),
        records: log.records.len(),
        ..Figures::default()
    };
    let mut links = LinkBuilder::default();
    let mut pending_photo: Option<(u64, Pos)> = None;
    let mut applied = 0usize;
    let mut not_applied: Vec<(String, usize)> = Vec::new();
    let mut pod_reports = false;
    let mut photos_taken: Option<usize> = None;
    let mut pod_boots = 0usize;
    let mut kinds: Vec<(u64, String)> = Vec::new();
    let mut first_healthy: Option<f64> = None;
    let mut healthy: Option<bool> = None;
    let mut geotags: Vec<(GeotagPoint, Option<Pos>)> = Vec::new();
    let mut fixes: Vec<(f64, Pos)> = Vec::new();
    for r in &log.records {
        let t = secs(r.t_us);
        f.end_s = f.end_s.max(t);
        match &r.rec {
            Rec::LinkUp(l) => links.set(*l, t, State::Up),
            Rec::LinkDown(l) => links.set(*l, t, State::Down),
            Rec::PortLost(l) => f.marks.push(Mark {
                t_s: t,
                link: *l,
                kind: MarkKind::PortLost,
            }),
            Rec::UtcValid { .. } => {
                f.utc_valid_at_s.get_or_insert(t);
            }
            Rec::UtcLost => f.utc_lost += 1,
            Rec::TimeSource { telemetry } => {
                f.sources.push((t, *telemetry));
                // The telemetry link's row: up while it is the time source (grey else:
                // the engine says no more of it).
                links.set(
                    Link::Telemetry,
                    t,
                    if *telemetry {
                        State::Up
                    } else {
                        State::Unknown
                    },
                );
            }
            Rec::TimeSync {
                edge_us,
                bound_us,
                error_us,
                ..
            } => {
                // The edge's own instant: the flight's span covers it (the plots' axes
                // are drawn over the span).
                let at = secs(*edge_us);
                f.end_s = f.end_s.max(at);
                f.first_sync_at_s.get_or_insert(at);
                f.syncs.push(SyncPoint {
                    t_s: at,
                    bound_us: *bound_us,
                    error_us: *error_us,
                });
            }
            Rec::EdgeToFrame { delay_us } => {
                f.edge_to_frame_max_us = f.edge_to_frame_max_us.max(Some(*delay_us));
            }
            Rec::Photo { utc_us, pos } => {
                f.origin.get_or_insert(*pos);
                pending_photo = Some((*utc_us, *pos));
            }
            Rec::Geotag {
                time_of_day_ms,
                answered,
                reason,
            } => {
                let photo = if *answered {
                    pending_photo.take()
                } else {
                    None
                };
                let refusal = (!answered).then(|| Refusal::from_reason(reason.as_deref()));
                geotags.push((
                    GeotagPoint {
                        t_s: t,
                        line: r.line,
                        time_of_day_ms: *time_of_day_ms,
                        photo,
                        refusal,
                        at_m: None,
                    },
                    photo.map(|p| p.1),
                ));
            }
            Rec::Fix(p) => {
                f.origin.get_or_insert(*p);
                fixes.push((t, *p));
            }
            Rec::FcSilenceStop => f.marks.push(Mark {
                t_s: t,
                link: Link::Fc,
                kind: MarkKind::SilenceStop,
            }),
            Rec::PodRefused { pod_id, code } => {
                let key = (pod_id.clone(), code.clone());
                match f.pod_refusals.iter_mut().find(|(k, _)| *k == key) {
                    Some((_, n)) => *n += 1,
                    None => f.pod_refusals.push((key, 1)),
                }
            }
            Rec::Translated { fc_id, pod_id } => {
                f.translated.0 += 1;
                if !kinds.iter().any(|(a, b)| a == fc_id && b == pod_id) {
                    kinds.push((*fc_id, pod_id.clone()));
                }
            }
            Rec::Trouble(what) => {
                let link = if what.contains("(fc)") {
                    Link::Fc
                } else if what.contains("(telemetry)") {
                    Link::Telemetry
                } else {
                    Link::Pod
                };
                f.marks.push(Mark {
                    t_s: t,
                    link,
                    kind: MarkKind::Trouble(what.clone()),
                });
            }
            Rec::Counters(c) => {
                for (i, (link, names)) in [
                    (Link::Fc, ["fc_garbage_bytes", "fc_rejected"]),
                    (Link::Pod, ["pod_garbage_bytes", "pod_rejected"]),
                ]
                .into_iter()
                .enumerate()
                {
                    let now: u64 = names
                        .iter()
                        .filter_map(|n| c.get(*n).and_then(Value::as_u64))
                        .sum();
                    if let Some(last) = links.last_garbage.get_mut(i) {
                        if now > *last {
                            f.marks.push(Mark {
                                t_s: t,
                                link,
                                kind: MarkKind::Garbage(now - *last),
                            });
                        }
                        *last = now;
                    }
                }
                f.counters = Some(c.clone());
            }
            Rec::PpsLocked => {
                f.pps_locked_at_s.get_or_insert(t);
            }
            Rec::FcHealth(h) => {
                if *h {
                    first_healthy.get_or_insert(t);
                }
                healthy = Some(*h);
            }
            Rec::PodBoot => {
                pod_boots += 1;
                if pod_boots > 1 {
                    f.marks.push(Mark {
                        t_s: t,
                        link: Link::Pod,
                        kind: MarkKind::PodReboot,
                    });
                }
            }
            Rec::PodSync { outcome } => {
                pod_reports = true;
                if outcome == "applied" {
                    applied += 1;
                } else {
                    match not_applied.iter_mut().find(|(o, _)| o == outcome) {
                        Some((_, n)) => *n += 1,
                        None => not_applied.push((outcome.clone(), 1)),
                    }
                }
            }
            Rec::PodPhoto => *photos_taken.get_or_insert(0) += 1,
            Rec::Stopped | Rec::Other => {}
        }
    }
    f.translated.1 = kinds.len();
    f.health = healthy.map(|h| (first_healthy, h));
    f.photos_taken = photos_taken;
    f.pod_syncs = pod_reports.then_some((applied, not_applied));
    f.links = links.lines(f.end_s);
    // Fixes logged from the engine's tick can be a little out of order with the rest.
    fixes.sort_by(|a, b| a.0.total_cmp(&b.0));
    if let Some(origin) = f.origin {
        f.track = fixes
            .iter()
            .map(|&(t, p)| {
                let (e, n) = metres(origin, p);
                (t, e, n)
            })
            .collect();
    }
    f.geotags = geotags
        .into_iter()
        .map(|(mut g, fix)| {
            g.at_m = match (fix, f.origin) {
                (Some(p), Some(o)) => Some(metres(o, p)),
                _ => nearest(&f.track, g.t_s),
            };
            g
        })
        .collect();
    let mut bounds: Vec<u64> = f.syncs.iter().map(|s| s.bound_us).collect();
    bounds.sort_unstable();
    f.bound_p50_max_us = quantile(&bounds, 0.5).zip(bounds.last().copied());
    let mut errors: Vec<f64> = f
        .syncs
        .iter()
        .filter_map(|s| s.error_us.map(f64::abs))
        .collect();
    errors.sort_by(f64::total_cmp);
    f.error_p50_max_us = quantile(&errors, 0.5).zip(errors.last().copied());
    f
}

/// The track's point nearest in time to `t_s`.
fn nearest(track: &[(f64, f64, f64)], t_s: f64) -> Option<(f64, f64)> {
    let i = track.partition_point(|p| p.0 < t_s);
    let after = track.get(i);
    let before = i.checked_sub(1).and_then(|j| track.get(j));
    let p = match (before, after) {
        (Some(b), Some(a)) => {
            if t_s - b.0 <= a.0 - t_s {
                b
            } else {
                a
            }
        }
        (Some(p), None) | (None, Some(p)) => p,
        (None, None) => return None,
    };
    Some((p.1, p.2))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::log::read;

    const FLIGHT: &str = r#"{"t_us":0,"event":"bridge_started","fc":"siyi","log_version":1}
{"t_us":1000000,"event":"pod_link_up"}
{"t_us":1100000,"event":"fc_link_up"}
{"t_us":2000000,"event":"fix","lat_e7":473977419,"lon_e7":85455938,"alt_msl_dm":4880}
{"t_us":2500000,"event":"geotag","time_of_day_ms":1000,"answered":false,"reason":"utc_unknown"}
{"t_us":3000000,"event":"utc_valid","error_bound_us":11000,"converged":false}
{"t_us":3000000,"event":"fix","lat_e7":473978319,"lon_e7":85455938,"alt_msl_dm":4880}
{"t_us":10000000,"event":"time_sync","utc_ms":1795428040000,"edge_us":10000000,"error_bound_us":3000,"error_us":-40.0}
{"t_us":12000000,"event":"photo","utc_us":1795428042000000,"lat_e7":473977419,"lon_e7":85457256,"alt_msl_dm":4880}
{"t_us":12000000,"event":"geotag","time_of_day_ms":36042000,"answered":true}
{"t_us":14000000,"event":"geotag","time_of_day_ms":36044000,"answered":false,"reason":"out_of_range"}
{"t_us":15000000,"event":"pod_link_down"}
{"t_us":18000000,"event":"pod_link_up"}
{"t_us":20000000,"event":"time_sync","utc_ms":1795428050000,"edge_us":20000000,"error_bound_us":1000,"error_us":20.0}
{"t_us":20000000,"event":"sim_pod_sync","utc_ms":1795428050000,"outcome":"applied"}
{"t_us":20000000,"event":"sim_pod_sync","utc_ms":1795428050000,"outcome":"no_edge"}
{"t_us":21000000,"event":"counters","fc_garbage_bytes":0,"pod_garbage_bytes":7,"pod_rejected":1}
{"t_us":22000000,"event":"translated","fc_id":14,"pod_id":"0x000302"}
{"t_us":22000000,"event":"translated","fc_id":14,"pod_id":"0x000302"}
{"t_us":25000000,"event":"fc_silence_stop"}
"#;

    #[test]
    fn the_figures_of_a_small_flight() {
        let f = figures(&read(FLIGHT));
        assert_eq!(f.fc.as_deref(), Some("siyi"));
        assert!((f.end_s - 25.0).abs() < 1e-9);
        assert_eq!(f.syncs.len(), 2);
        assert_eq!(f.bound_p50_max_us, Some((3000, 3000)));
        assert_eq!(f.error_p50_max_us, Some((40.0, 40.0)));
        assert_eq!(f.first_sync_at_s, Some(10.0));
        assert_eq!(f.utc_valid_at_s, Some(3.0));
        assert_eq!(f.pod_syncs, Some((1, vec![("no_edge".to_string(), 1)])));
        // 0.00009° of latitude north: 10.02 m; 0.0001318° of longitude at 47.4° east: 9.93 m.
        assert_eq!(f.track.len(), 2);
        assert!((f.track[1].2 - 10.0188).abs() < 1e-3, "{:?}", f.track);
        assert_eq!(f.geotags.len(), 3);
        assert_eq!(f.geotags_answered(), 1);
        assert_eq!(f.geotags[0].refusal, Some(Refusal::UtcUnknown));
        assert_eq!(f.geotags[1].refusal, None);
        let (e, n) = f.geotags[1].at_m.expect("drawn");
        assert!((e - 9.9315).abs() < 1e-3 && n.abs() < 1e-9, "{e} {n}");
        assert_eq!(f.geotags[2].refusal, Some(Refusal::OutOfRange));
        assert_eq!(f.geotags[2].line, 11);
        // A refusal is drawn on the track nearest in time: the fix at 3 s.
        assert_eq!(f.geotags[2].at_m, Some((f.track[1].1, f.track[1].2)));
        let pod = f.links.iter().find(|l| l.link == Link::Pod).expect("pod");
        assert_eq!(pod.downs, 1);
        assert!((pod.down_s - 3.0).abs() < 1e-9);
        assert_eq!(
            pod.spans.iter().map(|s| s.state).collect::<Vec<_>>(),
            [State::Unknown, State::Up, State::Down, State::Up]
        );
        assert_eq!(
            f.marks
                .iter()
                .map(|m| (m.link, m.kind.clone()))
                .collect::<Vec<_>>(),
            [
                (Link::Pod, MarkKind::Garbage(8)),
                (Link::Fc, MarkKind::SilenceStop)
            ]
        );
        assert_eq!(f.translated, (2, 1));
        assert_eq!(f.counter("pod_garbage_bytes"), Some(7));
    }

    #[test]
    fn quantiles_take_the_nearest_rank() {
        assert_eq!(quantile::<u64>(&[], 0.5), None);
        assert_eq!(quantile(&[1, 2, 3, 4], 0.5), Some(3));
        assert_eq!(quantile(&[5], 0.5), Some(5));
    }
}
