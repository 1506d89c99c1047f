//! The demo (`gimbal::demo`) for each FC protocol: the bridge's firmware tasks
//! between the simulated FC and the simulated pod, 60 s of simulated time. The FC calls
//! the mount healthy, time syncs reach the pod and are accurate, every photo is
//! geotagged, nothing is dropped, and it takes seconds, not minutes.
//!
//! `DEMO_PRINT=1 cargo test -p host-tests --test suite demo:: -- --nocapture` prints the stories.

use std::time::{Duration, Instant};

use bridge_engine::FcProtocol;
use gimbal::demo::{self, DemoOptions, Summary};

fn run(fc: FcProtocol) -> (Summary, String) {
    let start = Instant::now();
    let mut out = Vec::new();
    let s = demo::run(
        &DemoOptions {
            fc,
            seconds: 60,
            telemetry: false,
            pps: false,
        },
        &mut out,
    )
    .expect("writes to a Vec");
    let wall = start.elapsed();
    let text = String::from_utf8(out).expect("UTF-8");
    if std::env::var_os("DEMO_PRINT").is_some() {
        println!("{text}");
    }
    // A few seconds in debug on a loaded machine; well under a second in release.
    assert!(wall < Duration::from_secs(30), "{fc:?}: {wall:?}");
    (s, text)
}

/// What every FC side shows; `sync_bound_us` is the side's time-sync error bound.
fn check(fc: FcProtocol, sync_bound_us: u64) -> Summary {
    let (s, text) = run(fc);
    assert_eq!(s.fc, fc);
    assert_eq!(s.seconds, 60);
    // Healthy in the first seconds, and still at the end.
    let healthy = s.healthy_at_s.expect("the FC calls the mount healthy");
    assert!(healthy < 5.0, "{s:?}");
    assert!(s.healthy_at_end, "{s:?}");
    // The scripted commands went through (look down, pan, stop, zoom in/out, record,
    // photos: at least five kinds).
    assert!(s.command_kinds >= 5, "{s:?}");
    assert!(s.commands_translated >= s.command_kinds);
    // UTC known within seconds of the FC's first time, the first sync on the next 10 s
    // grid edge (within 12 s), then one every 10 s, each applied by the pod, within the
    // bound.
    let utc_at = s.utc_valid_at_s.expect("UTC known");
    let first = s.first_sync_at_s.expect("a sync");
    assert!(
        utc_at < 3.0 && first > utc_at && first - utc_at <= 12.0,
        "{s:?}"
    );
    assert!(
        s.first_sync_error_us.unwrap().unsigned_abs() < sync_bound_us,
        "{s:?}"
    );
    assert!((5..=6).contains(&s.syncs), "{s:?}");
    assert_eq!(s.syncs_applied, s.syncs, "{s:?}");
    let p50 = s.sync_error_p50_us.expect("p50");
    let max = s.sync_error_max_us.expect("max");
    assert!(p50 <= max && max < sync_bound_us, "{s:?}");
    // The 0x00030E is the first pod frame after each edge (its delay is recorded).
    assert!(s.edge_to_frame_max_us.is_some(), "{s:?}");
    // Three photos, each geotagged within a metre of the truth; video recorded.
    assert_eq!(s.photos, 3, "{s:?}");
    assert_eq!(s.geotags_requested, 3, "{s:?}");
    assert_eq!(s.geotags_answered, 3, "{s:?}");
    assert!(s.geotag_error_max_m.expect("geotag error") < 1.0, "{s:?}");
    assert!(s.recorded, "{s:?}");
    // Traffic both ways on both links, nothing dropped.
    for b in [
        s.bytes_fc_to_bridge,
        s.bytes_bridge_to_fc,
        s.bytes_pod_to_bridge,
        s.bytes_bridge_to_pod,
    ] {
        assert!(b > 500, "{s:?}");
    }
    assert_eq!((s.frames_dropped, s.records_dropped), (0, 0), "{s:?}");
    // The story tells it.
    for needle in [
        "healthy:",
        "script        look down",
        "time sync     RTC_IO high",
        "geotag        pod asks",
        "bridge → pod  K40T 0x000302 TakePhoto",
        "bridge → pod  K40T 0x00030E TimeSync",
        "summary (",
    ] {
        assert!(text.contains(needle), "{fc:?}: no {needle:?} in\n{text}");
    }
    assert_eq!(text.matches("photo taken").count(), 3);
    s
}

#[test]
fn siyi() {
    check(FcProtocol::Siyi, 5_000);
}

#[test]
fn viewlink() {
    check(FcProtocol::Viewlink, 5_000);
}

#[test]
fn gcu() {
    // ArduPilot's GCU driver relays the time of the last GPS fix, held between fixes and
    // read by its 50 Hz loop: the GCU side's error follows that read phase, ±10 ms, and
    // its bound (as in bridge_gcu.rs) is 15 ms.
    check(FcProtocol::Gcu, 15_000);
}

#[test]
fn k40t() {
    let s = check(FcProtocol::K40t, 5_000);
    // The FC speaks only when it has something to say; its own 0x00030E every 10 s.
    assert!(s.bytes_fc_to_bridge < s.bytes_bridge_to_fc);
}

#[test]
fn mavlink() {
    let s = check(FcProtocol::Mavlink, 5_000);
    // SYSTEM_TIME, asked for by the bridge at 10 Hz, from the first second.
    assert!(s.utc_valid_at_s.unwrap() < 2.0, "{s:?}");
}

#[test]
fn a_short_run_has_no_sync_and_says_so() {
    let mut out = Vec::new();
    let s = demo::run(
        &DemoOptions {
            fc: FcProtocol::Siyi,
            seconds: 8,
            telemetry: false,
            pps: false,
        },
        &mut out,
    )
    .expect("writes");
    assert_eq!((s.syncs, s.photos), (0, 0));
    assert!(s.healthy_at_s.is_some());
    let text = String::from_utf8(out).expect("UTF-8");
    assert!(
        text.contains("0 sent, 0 applied by the pod; error p50 -, max -"),
        "{text}"
    );
}

#[test]
fn a_telemetry_link_gives_sub_millisecond_syncs_to_every_legacy_side() {
    for fc in [FcProtocol::Siyi, FcProtocol::Viewlink, FcProtocol::Gcu] {
        let mut out = Vec::new();
        let opts = DemoOptions {
            fc,
            seconds: 60,
            telemetry: true,
            pps: false,
        };
        let s = demo::run(&opts, &mut out).expect("writes");
        let text = String::from_utf8(out).expect("UTF-8");
        assert!(s.telemetry, "{s:?}");
        // The autopilot's SYSTEM_TIME comes at once: the link is the source within 2 s.
        assert!(s.telemetry_source_at_s.is_some_and(|t| t < 2.0), "{s:?}");
        assert!(s.syncs >= 5 && s.syncs_applied == s.syncs, "{s:?}");
        assert!(s.sync_error_max_us.is_some_and(|m| m < 1_000), "{s:?}");
        assert!(
            s.first_sync_error_us.is_some_and(|e| e.abs() < 1_000),
            "{s:?}"
        );
        assert_eq!(s.geotags_answered, s.geotags_requested, "{s:?}");
        assert!(s.geotag_error_max_m.is_some_and(|m| m < 1.0), "{s:?}");
        assert_eq!((s.frames_dropped, s.records_dropped), (0, 0), "{s:?}");
        assert!(text.contains("bridge → AP MAVLink") && text.contains("from 1/158"));
        assert!(
            text.contains("time source              telemetry link"),
            "{text}"
        );
    }
    // The K40T FC is no ArduPilot: there is no MAVLink port of it to attach.
    let opts = DemoOptions {
        fc: FcProtocol::K40t,
        seconds: 10,
        telemetry: true,
        pps: false,
    };
    assert!(demo::run(&opts, &mut Vec::new()).is_err());
}

/// `gimbal demo --pps`: every FC side's clock locks to the simulated GNSS pulse and its
/// syncs are within a microsecond of the GNSS's UTC; the first PPS-locked sync comes
/// within 12 s of the first labelled edge.
#[test]
fn a_gnss_pps_gives_sub_microsecond_syncs_on_every_side() {
    for fc in [
        FcProtocol::Siyi,
        FcProtocol::Viewlink,
        FcProtocol::Gcu,
        FcProtocol::K40t,
        FcProtocol::Mavlink,
    ] {
        let mut out = Vec::new();
        let opts = DemoOptions {
            fc,
            seconds: 60,
            telemetry: false,
            pps: true,
        };
        let s = demo::run(&opts, &mut out).expect("writes");
        let text = String::from_utf8(out).expect("UTF-8");
        assert!(s.pps, "{s:?}");
        let (edge, sync) = (
            s.pps_first_edge_at_s.expect("locked"),
            s.first_pps_sync_at_s.expect("a PPS-locked sync"),
        );
        assert!(sync > edge && sync - edge <= 12.0, "{s:?}");
        assert!(s.syncs >= 4 && s.syncs_applied == s.syncs, "{s:?}");
        // After the lock: under a microsecond (before it, the FC's UTC alone).
        assert!(text.contains("PPS locked"), "{text}");
        assert!(text.contains("against the GNSS's UTC"), "{text}");
        assert_eq!(s.geotags_answered, s.geotags_requested, "{s:?}");
        assert_eq!((s.frames_dropped, s.records_dropped), (0, 0), "{s:?}");
    }
}
