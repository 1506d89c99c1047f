//! `gimbal report`: the page of a demo flight and of a faulty flight (pod cable pulled,
//! pod rebooted, FC cable pulled while the pod turns) shows the figures the events
//! give (and, for the demo, those the demo's own summary prints); its plots are valid
//! SVG; it loads nothing; bad lines are reported with their numbers while the rest is
//! drawn.

use bridge_engine::{Config, Event, GeotagMiss};
use gimbal::demo::{self, DemoOptions};
use gimbal::report::figures::{MarkKind, Refusal};
use gimbal::report::log::Link;
use gimbal::report::{self, Report};
use gimbal::runner::bench_log::{BenchLog, to_text};
use gimbal::sim::ap_siyi::ApSiyi;
use gimbal::sim::pilot::{Pilot, Seeded};
use gimbal::sim::pod::{PodSimConfig, SimPod, SyncOutcome};
use gimbal::sim::tasks::{Bench, Cable, Outcome};
use quick_xml::Reader;
use quick_xml::events::Event as Xml;
use serde_json::Value;

const S: u64 = 1_000_000;

fn demo_log(seconds: u32) -> String {
    let mut out = Vec::new();
    demo::run_json(
        &DemoOptions {
            seconds,
            ..DemoOptions::default()
        },
        &mut out,
    )
    .expect("writes to a Vec");
    String::from_utf8(out).expect("UTF-8")
}

/// The log's events named `name`.
fn events<'a>(log: &'a str, name: &'a str) -> impl Iterator<Item = Value> + 'a {
    log.lines()
        .filter_map(|l| serde_json::from_str::<Value>(l).ok())
        .filter(move |v| v["event"] == name)
}

/// Every `<svg>…</svg>` of the page, each parsed as XML to its end; returns them.
fn svgs(html: &str) -> Vec<&str> {
    let mut found = Vec::new();
    let mut rest = html;
    while let Some(start) = rest.find("<svg") {
        let end = rest[start..].find("</svg>").expect("every <svg> is closed") + start + 6;
        let svg = &rest[start..end];
        let mut reader = Reader::from_str(svg);
        let mut depth = 0i32;
        let mut elements = 0;
        loop {
            match reader.read_event() {
                Ok(Xml::Start(_)) => {
                    depth += 1;
                    elements += 1;
                }
                Ok(Xml::End(_)) => depth -= 1,
                Ok(Xml::Empty(_)) => elements += 1,
                Ok(Xml::Eof) => break,
                Ok(_) => {}
                Err(e) => panic!("not XML at {}: {e}", reader.buffer_position()),
            }
        }
        assert_eq!(depth, 0, "unbalanced SVG");
        assert!(elements > 10, "an empty plot: {svg}");
        found.push(svg);
        rest = &rest[end..];
    }
    found
}

/// The page loads nothing: no script, stylesheet, image or frame from elsewhere, no URL
/// but the SVG namespace.
fn self_contained(html: &str) {
    let without_ns = html.replace(r#"xmlns="http://www.w3.org/2000/svg""#, "");
    for bad in [
        "http:", "https:", "src=", "href=", "url(", "@import", "<script", "<link", "<img",
        "<iframe", "=\"//", "='//",
    ] {
        assert!(!without_ns.contains(bad), "the page has {bad:?}");
    }
    assert!(html.contains("xmlns=\"http://www.w3.org/2000/svg\""));
}

#[test]
fn a_demo_flight_report_shows_the_demo_s_figures() {
    let opts = DemoOptions {
        seconds: 120,
        ..DemoOptions::default()
    };
    let summary = demo::run(&opts, &mut std::io::sink()).expect("runs");
    let log = demo_log(120);
    let r = report::report("demo.jsonl", &log);
    let f = &r.figures;
    assert!(r.warnings().is_empty(), "{:?}", r.warnings());

    // The events' own counts.
    let syncs = events(&log, "time_sync").count();
    let applied = events(&log, "sim_pod_sync")
        .filter(|e| e["outcome"] == "applied")
        .count();
    let geotags = events(&log, "geotag").count();
    let answered = events(&log, "geotag")
        .filter(|e| e["answered"] == true)
        .count();
    let fixes = events(&log, "fix").count();
    assert_eq!(f.syncs.len(), syncs);
    assert_eq!(f.pod_syncs, Some((applied, vec![])));
    assert_eq!((f.geotags.len(), f.geotags_answered()), (geotags, answered));
    assert_eq!(f.track.len(), fixes);
    // 120 s: a fix a second once the FC sends them (from ~2 s on).
    assert!((110..=120).contains(&fixes), "{fixes}");

    // The demo's own summary, figure for figure.
    assert_eq!(syncs, summary.syncs as usize);
    assert_eq!(applied, summary.syncs_applied as usize);
    assert_eq!(geotags, summary.geotags_requested as usize);
    assert_eq!(answered, summary.geotags_answered as usize);
    assert_eq!(f.photos_taken, Some(summary.photos as usize));
    assert_eq!(
        (f.translated.0, f.translated.1),
        (
            summary.commands_translated as usize,
            summary.command_kinds as usize
        )
    );
    assert_eq!(f.first_sync_at_s, summary.first_sync_at_s);
    assert_eq!(f.utc_valid_at_s, summary.utc_valid_at_s);
    assert_eq!(f.edge_to_frame_max_us, summary.edge_to_frame_max_us);
    assert_eq!(f.health.and_then(|h| h.0), summary.healthy_at_s);
    // The quantiles, computed here from the log's own syncs (not through the report's
    // function, which the demo's summary shares): the median by nearest rank is the
    // value at index n/2 of the sorted values (n − 1 halves, rounded up), the maximum the
    // last.
    let mut errors: Vec<f64> = events(&log, "time_sync")
        .map(|e| {
            e["error_us"]
                .as_f64()
                .expect("the demo measures each error")
                .abs()
        })
        .collect();
    errors.sort_by(f64::total_cmp);
    let mut bounds: Vec<u64> = events(&log, "time_sync")
        .map(|e| e["error_bound_us"].as_u64().expect("a bound"))
        .collect();
    bounds.sort_unstable();
    let n = errors.len();
    assert_eq!(n, 12);
    let (p50, max) = (errors[n / 2], errors[n - 1]);
    assert!(p50 > 0.0 && p50 <= max, "{errors:?}");
    assert_eq!(f.error_p50_max_us, Some((p50, max)));
    assert_eq!(
        f.bound_p50_max_us,
        Some((bounds[bounds.len() / 2], bounds[bounds.len() - 1]))
    );
    assert_eq!(
        (
            summary.sync_error_p50_us.expect("p50"),
            summary.sync_error_max_us.expect("max")
        ),
        (p50.round() as u64, max.round() as u64)
    );
    assert_eq!(f.counter("time_syncs"), Some(syncs as u64));
    // The 120 s demo: 12 syncs, 7 photos, every one geotagged, nothing dropped.
    assert_eq!((syncs, applied, geotags, answered), (12, 12, 7, 7));
    assert_eq!(f.counter("dropped"), Some(0));

    // The page: the summary rows and the plots.
    let html = &r.html;
    assert!(html.contains("<td>time syncs</td><td>12 sent, 12 applied by the pod; error p50"));
    assert!(html.contains("<td>geotags answered</td><td>7 of 7</td>"));
    let plots = svgs(html);
    assert_eq!(plots.len(), 4, "time, histogram, track, links");
    // Every photo on the track: 7 green circles (and the legend's).
    let green = plots[2].matches(r##"fill="#2CA02C""##).count();
    assert_eq!(green, 8, "{}", plots[2]);
    self_contained(html);
}

/// The faulty flight: pod cable pulled at 40 s for 3 s, the pod rebooted at 60 s (3 s
/// off), the FC cable pulled at 80 s for 3 s while the pod turns, with a photo from the
/// pod's app 2 s into that pull (no fix then: refused); photos at 30, 50, 70 and 95 s.
fn faulty_flight() -> (Outcome<ApSiyi>, String) {
    let b = Bench::with(
        Config::for_fc(ApSiyi::PROTOCOL),
        ApSiyi::with_seed(7),
        SimPod::new(PodSimConfig::default()),
    );
    let mut log = BenchLog::new(
        gimbal::runner::event_name::EventName::DemoStarted,
        serde_json::json!({"fc": "siyi"}),
    );
    let o = b.run(110 * S, 10_000, |b, t| {
        match t {
            t if t == 40 * S => b.wires.pull(Cable::Pod, t, 3 * S),
            t if t == 60 * S => b.pod.borrow_mut().reboot_with(t, 3 * S, Some(99)),
            t if t == 78 * S => b.fc.borrow_mut().turn(15.0, 0.0),
            t if t == 80 * S => b.wires.pull(Cable::Fc, t, 3 * S),
            t if t == 82 * S => b.pod.borrow_mut().photo_from_app(t),
            t if t == 88 * S => b.fc.borrow_mut().turn(0.0, 0.0),
            t if [30 * S, 50 * S, 70 * S, 95 * S].contains(&t) => {
                b.fc.borrow_mut().take_picture();
            }
            _ => {}
        }
        log.sample(b, t);
    });
    let lines = log.finish(&o, |edge, utc_ms| {
        Some(i128::from(utc_ms) * 1_000_000 - i128::from(o.fc.true_utc_us(edge)) * 1_000)
    });
    (o, to_text(&lines))
}

fn count(o: &Outcome<ApSiyi>, f: impl Fn(&Event) -> bool) -> usize {
    o.events().filter(|(_, e)| f(e)).count()
}

#[test]
fn a_faulty_flight_report_shows_the_link_drops_reboots_and_refusals() {
    let (o, log) = faulty_flight();
    let r: Report = report::report("faulty.jsonl", &log);
    let f = &r.figures;
    assert!(r.warnings().is_empty(), "{:?}", r.warnings());

    let syncs = count(&o, |e| matches!(e, Event::TimeSync { .. }));
    let applied = o
        .pod
        .syncs()
        .iter()
        .filter(|s| s.outcome == SyncOutcome::Applied)
        .count();
    let geotags = count(&o, |e| matches!(e, Event::Geotag { .. }));
    let answered = count(&o, |e| matches!(e, Event::Geotag { missed: None, .. }));
    assert_eq!(f.syncs.len(), syncs);
    assert_eq!(f.pod_syncs.as_ref().map(|p| p.0), Some(applied));
    assert_eq!((f.geotags.len(), f.geotags_answered()), (geotags, answered));
    // Four photos from the FC and one from the pod's app: the app's is refused (the FC
    // has been away 2 s: no fix near it), with UTC known.
    assert_eq!((geotags, answered), (5, 4));
    let refused: Vec<_> = f.geotags.iter().filter(|g| g.refusal.is_some()).collect();
    assert_eq!(refused.len(), 1);
    assert_eq!(
        count(&o, |e| matches!(
            e,
            Event::Geotag {
                missed: Some(GeotagMiss::OutOfRange),
                ..
            }
        )),
        1
    );
    assert_eq!(refused[0].refusal, Some(Refusal::OutOfRange));
    assert!((82.0..83.0).contains(&refused[0].t_s), "{}", refused[0].t_s);
    assert!(refused[0].at_m.is_some(), "drawn on the track");

    // The links: each drop the engine reported, at its time.
    let downs = |l: Link| f.links.iter().find(|x| x.link == l).expect("drawn");
    let pod_downs = count(&o, |e| *e == Event::PodLinkDown);
    let fc_downs = count(&o, |e| *e == Event::FcLinkDown);
    assert_eq!(downs(Link::Pod).downs, pod_downs);
    assert_eq!(downs(Link::Fc).downs, fc_downs);
    assert_eq!(
        (pod_downs, fc_downs),
        (2, 1),
        "the pull and the reboot; the FC pull"
    );
    let down_at: Vec<f64> = o
        .events()
        .filter(|(_, e)| *e == Event::PodLinkDown)
        .map(|(t, _)| t as f64 / 1e6)
        .collect();
    let spans: Vec<f64> = downs(Link::Pod)
        .spans
        .iter()
        .filter(|s| s.state == gimbal::report::figures::State::Down)
        .map(|s| s.from_s)
        .collect();
    assert_eq!(spans, down_at);
    assert!((40.0..44.0).contains(&down_at[0]) && (60.0..64.0).contains(&down_at[1]));
    // One reboot (the first boot is not one), one silence stop, as the events.
    let reboots: Vec<f64> = f
        .marks_where(|k| *k == MarkKind::PodReboot)
        .map(|m| m.t_s)
        .collect();
    assert_eq!(reboots, [63.0]);
    assert_eq!(
        f.marks_where(|k| *k == MarkKind::SilenceStop).count(),
        count(&o, |e| *e == Event::FcSilenceStop)
    );
    assert_eq!(f.marks_where(|k| *k == MarkKind::SilenceStop).count(), 1);
    assert_eq!(f.counter("time_syncs"), Some(syncs as u64));

    let html = &r.html;
    assert!(html.contains("<td>pod link</td><td>down 2 time(s)"));
    assert!(html.contains("<td>pod reboots / FC silence stops</td><td>1 / 1</td>"));
    assert!(html.contains("refused: no fix near the instant"));
    assert_eq!(svgs(html).len(), 4);
    self_contained(html);
}

#[test]
fn bad_lines_are_reported_with_their_numbers_and_the_rest_is_drawn() {
    let good = demo_log(60);
    let full = report::report("good", &good).figures;
    let mut lines: Vec<String> = good.lines().map(str::to_string).collect();
    // Line 1: another version; a translated line cut off; an unknown event inserted.
    lines[0] = lines[0].replace("\"log_version\":1", "\"log_version\":2");
    let cut = lines
        .iter()
        .position(|l| l.contains("\"translated\""))
        .expect("a translation");
    let half = lines[cut].len() / 2;
    lines[cut].truncate(half);
    lines.insert(
        100,
        r#"{"t_us":30000000,"event":"teleported","to":"<b>moon</b>"}"#.into(),
    );
    let r = report::report("bad", &(lines.join("\n") + "\n"));
    let w = r.warnings();
    assert_eq!(w.len(), 3, "{w:?}");
    assert!(w[0].starts_with("line 1: log version 2, this report reads version 1"));
    assert!(
        w[1].starts_with(&format!("line {}: cut off", cut + 1)),
        "{w:?}"
    );
    assert_eq!(w[2], "line 101: unknown event `teleported` (1 line)");
    // The rest is drawn: everything but the cut line.
    let f = &r.figures;
    assert_eq!(f.syncs.len(), full.syncs.len());
    assert_eq!(f.geotags.len(), full.geotags.len());
    assert_eq!(f.track.len(), full.track.len());
    assert_eq!(f.translated.0, full.translated.0 - 1);
    let html = &r.html;
    assert!(
        html.contains("<td>101</td><td>1</td>"),
        "the unknown event's line"
    );
    assert!(html.contains(&format!("<tr><td>{}</td><td>cut off", cut + 1)));
    assert!(!html.contains("<b>moon"), "text from the log is escaped");
    assert_eq!(svgs(html).len(), 4);
    self_contained(html);
}

/// Values at the ends of their types (u64::MAX times, ±1e308 errors, coordinates out of
/// the globe, one instant for the whole flight) still give a page: plotters' axes are kept
/// finite and wide enough for their ticks (a range lost in rounding once made it loop).
#[test]
fn extreme_values_are_drawn() {
    let log = r#"{"t_us":0,"event":"bridge_started","fc":"siyi","log_version":1}
{"t_us":18446744073709551615,"event":"time_sync","utc_ms":18446744073709551615,"edge_us":18446744073709551615,"error_bound_us":18446744073709551615,"error_us":1e308}
{"t_us":10,"event":"time_sync","utc_ms":1,"edge_us":1,"error_bound_us":0,"error_us":-1e308}
{"t_us":5,"event":"fix","lat_e7":2147483647,"lon_e7":-2147483648,"alt_msl_dm":-2147483648}
{"t_us":6,"event":"fix","lat_e7":-2147483648,"lon_e7":2147483647,"alt_msl_dm":2147483647}
{"t_us":7,"event":"geotag","time_of_day_ms":99999999999,"answered":false,"reason":"<script>"}
{"t_us":8,"event":"photo","utc_us":0,"lat_e7":0,"lon_e7":0,"alt_msl_dm":0}
{"t_us":9,"event":"pod_link_down"}
{"t_us":3,"event":"pod_link_up"}
{"t_us":-5,"event":"fc_link_up"}
"#;
    let r = report::report("extreme", log);
    assert_eq!(r.warnings(), ["line 10: fc_link_up: no \"t_us\""]);
    assert_eq!(r.figures.syncs.len(), 2);
    assert_eq!(r.figures.track.len(), 2);
    assert_eq!(r.figures.geotags[0].refusal, Some(Refusal::NotGiven));
    assert_eq!(svgs(&r.html).len(), 4);
    self_contained(&r.html);
    // One instant for everything, far from zero.
    let one = r#"{"t_us":1000000000000000,"event":"time_sync","utc_ms":5,"edge_us":5,"error_bound_us":7,"error_us":3.0}
{"t_us":1000000000000000,"event":"fix","lat_e7":1,"lon_e7":1,"alt_msl_dm":1}
"#;
    let r = report::report("one instant", one);
    assert_eq!(r.figures.syncs.len(), 1);
    self_contained(&r.html);
    // A sync whose edge lies far after every line's time: the span covers it (a point
    // millions of widths off its axis overflowed plotters' pixel arithmetic).
    let late = r#"{"t_us":10,"event":"time_sync","utc_ms":5,"edge_us":3000000000000,"error_bound_us":7}
{"t_us":20,"event":"fix","lat_e7":1,"lon_e7":1,"alt_msl_dm":1}
"#;
    let r = report::report("late edge", late);
    assert!(
        (r.figures.end_s - 3_000_000.0).abs() < 1e-6,
        "{}",
        r.figures.end_s
    );
    assert_eq!(svgs(&r.html).len(), 4);
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
    /// Any mix of the events the report reads, with any values in their fields (and
    /// some lines cut), in any order: a page, every line accounted for, nothing loaded
    /// from elsewhere.
    #[test]
    fn any_values_in_any_order_give_a_page(
        lines in proptest::collection::vec(
            (0usize..16, proptest::prelude::any::<u64>(), proptest::prelude::any::<i32>(),
             proptest::prelude::any::<i32>(), proptest::num::f64::NORMAL, 0usize..200),
            1..120,
        )
    ) {
        const TEMPLATES: [&str; 16] = [
            r#"{"t_us":T,"event":"time_sync","utc_ms":U,"edge_us":U,"error_bound_us":U,"error_us":F}"#,
            r#"{"t_us":T,"event":"fix","lat_e7":A,"lon_e7":B,"alt_msl_dm":A}"#,
            r#"{"t_us":T,"event":"photo","utc_us":U,"lat_e7":B,"lon_e7":A,"alt_msl_dm":B}"#,
            r#"{"t_us":T,"event":"geotag","time_of_day_ms":U,"answered":false,"reason":"no_fix"}"#,
            r#"{"t_us":T,"event":"geotag","time_of_day_ms":U,"answered":true}"#,
            r#"{"t_us":T,"event":"pod_link_down"}"#,
            r#"{"t_us":T,"event":"pod_link_up"}"#,
            r#"{"t_us":T,"event":"fc_link_down"}"#,
            r#"{"t_us":T,"event":"fc_link_up"}"#,
            r#"{"t_us":T,"event":"utc_valid","error_bound_us":U,"converged":true}"#,
            r#"{"t_us":T,"event":"utc_lost"}"#,
            r#"{"t_us":T,"event":"edge_to_frame","delay_us":U,"len":28}"#,
            r#"{"t_us":T,"event":"sim_pod_sync","utc_ms":U,"outcome":"applied"}"#,
            r#"{"t_us":T,"event":"fc_silence_stop"}"#,
            r#"{"t_us":T,"event":"time_source","telemetry":true}"#,
            r#"{"t_us":T,"event":"counters","fc_garbage_bytes":U,"pod_rejected":A}"#,
        ];
        let mut text = String::from(r#"{"t_us":0,"event":"bridge_started","fc":"gcu","log_version":1}"#);
        text.push('\n');
        let mut blank = 0;
        for &(k, u, a, b, f, cut) in &lines {
            // Times within a day mostly, some anywhere.
            let t = if u % 4 == 0 { u } else { u % 86_400_000_000 };
            let line = TEMPLATES[k]
                .replace('T', &t.to_string())
                .replace('U', &(u / 3).to_string())
                .replace('A', &a.to_string())
                .replace('B', &b.to_string())
                .replace('F', &format!("{f:e}"));
            let line = line.get(..cut.min(line.len())).unwrap_or(&line);
            blank += usize::from(line.is_empty());
            text.push_str(line);
            text.push('\n');
        }
        let r = report::report("any", &text);
        proptest::prop_assert_eq!(svgs(&r.html).len(), 4);
        self_contained(&r.html);
        let unread = r.log.diagnostics.len();
        // Blank lines are passed over; every other one is read or reported.
        proptest::prop_assert_eq!(r.log.records.len() + unread, lines.len() - blank);
    }
}

#[test]
fn files_that_hold_no_log_are_errors() {
    let dir = std::env::temp_dir().join(format!("gimbal-report-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let missing = dir.join("missing.jsonl");
    let e = report::run(&missing, &dir.join("x.html")).unwrap_err();
    assert!(e.contains("missing.jsonl"), "{e}");
    let empty = dir.join("empty.jsonl");
    std::fs::write(&empty, "not json\n\n").expect("written");
    let e = report::run(&empty, &dir.join("x.html")).unwrap_err();
    assert!(e.contains("no event in it (2 line(s)"), "{e}");
    let log = dir.join("demo.jsonl");
    std::fs::write(&log, demo_log(30)).expect("written");
    let out = report::default_output(&log);
    assert_eq!(out, dir.join("demo.html"));
    let r = report::run(&log, &out).expect("a report");
    assert_eq!(std::fs::read_to_string(&out).expect("written"), r.html);
    let _ = std::fs::remove_dir_all(&dir);
}
