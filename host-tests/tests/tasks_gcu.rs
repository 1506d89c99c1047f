//! The GCU side through the firmware's tasks (virtual time, pipes): start-up to healthy,
//! commands and telemetry, time sync with the RTC_IO edge before the 0x00030E, geotag,
//! FC silence, pod loss, garbage on both lines. The scenarios are in
//! `task_scenarios/mod.rs`; the bounds here are this side's.

use crate::task_scenarios;

use bridge_engine::{Event, Level};
use gimbal::sim::Autopilot;
use gimbal::sim::ap_xfrobot::ApXfRobot;
use gimbal::sim::pod::SyncOutcome;
use gimbal::sim::tasks::Cable;
use task_scenarios::{Bounds, S};

const BOUNDS: Bounds = Bounds {
    healthy_within_us: S,
    sync_error_us: 15_000,
    unhealthy_after_pod_loss_us: 2 * S,
    healthy_after_pod_back_us: S,
    silence_stop_event: false,
    bridge_geotags: true,
};

#[test]
fn startup_to_healthy() {
    task_scenarios::startup_to_healthy::<ApXfRobot>(BOUNDS);
}

#[test]
fn commands_reach_the_pod_and_its_attitude_the_fc() {
    task_scenarios::commands_and_telemetry::<ApXfRobot>();
}

#[test]
fn time_syncs_edge_then_frame_and_photos_geotagged() {
    task_scenarios::sync_and_geotag::<ApXfRobot>(BOUNDS, "gcu");
}

#[test]
fn fc_silence_stops_the_pod_within_0_6_s() {
    let delay = task_scenarios::fc_silence_stops_motion::<ApXfRobot>(BOUNDS);
    println!(
        "gcu: pod still {} ms after the FC cable was cut",
        delay / 1000
    );
}

#[test]
fn pod_loss_is_seen_as_a_lost_gimbal_then_recovery() {
    task_scenarios::pod_loss::<ApXfRobot>(BOUNDS);
}

#[test]
fn garbage_on_both_lines_keeps_it_healthy() {
    task_scenarios::garbage_on_both_lines::<ApXfRobot>();
}

/// While the pod is lost the bridge still answers every package, in the short form
/// (72 bytes, hardware-error bit) that ArduPilot ignores, as a GCU whose gimbal stopped
/// reporting would: ArduPilot refuses a picture then.
#[test]
fn pod_loss_replies_are_short_with_the_hardware_error_bit() {
    let mut refused = None;
    let o = task_scenarios::bench::<ApXfRobot>().run(14 * S, task_scenarios::TICK, |b, t| {
        if t == 6 * S {
            b.wires.cut(Cable::Pod, true);
        }
        if t == 10 * S {
            refused = Some(!b.fc.borrow_mut().take_picture());
        }
        if t == 12 * S {
            b.wires.cut(Cable::Pod, false);
        }
    });
    assert_eq!(refused, Some(true));
    let during: Vec<_> =
        o.fc.replies
            .iter()
            .filter(|r| r.at_us > 9 * S && r.at_us < 12 * S)
            .collect();
    assert!(during.len() > 100, "{}", during.len());
    for r in &during {
        assert_eq!(r.bytes.len(), 72);
        assert_ne!(r.error_code() & 1 << 7, 0);
    }
    let last = o.fc.replies.last().expect("replies");
    assert_eq!(last.bytes.len(), 73);
    assert!(o.fc.healthy());
}

/// The FC's packages backed up behind each other: its output held for 60 ms every
/// second (an FC loop overrun, a USB-serial adapter or host that froze), then the held
/// packages and those written meanwhile go out back to back, at 10 kB/s (QEMU's USART
/// pace on the emulated board, a little under 115200 baud). A package written while
/// the ones before it were still going out had its values read after the burst's first
/// byte: timed from that byte it looks early, and the discipline trusts the
/// earliest-looking samples (so did the bridge: syncs 11 to 12 ms ahead of the same run
/// without the holds, and UTC lost and back 23 times in a minute). Timed from its own
/// first byte, a package can only look late: the syncs are those of the run without
/// holds, within 2 ms, and UTC is never lost.
#[test]
fn packages_backed_up_behind_each_other_do_not_move_the_syncs() {
    let run = |hold: bool| {
        let o = task_scenarios::bench::<ApXfRobot>().run(65 * S, task_scenarios::TICK, |b, t| {
            if t == 0 {
                b.wires.fc_in.borrow_mut().trickle_us = Some(100);
            }
            if hold && t % S == S / 2 {
                b.wires.fc_in.borrow_mut().hold_for(t, 60_000);
            }
        });
        let lost = task_scenarios::events(&o, |e| matches!(e, Event::UtcLost)).len();
        let highs = o.pin_changes(Level::High);
        assert_eq!(highs.len(), o.pod.syncs().len());
        let errors: Vec<i64> = o
            .pod
            .syncs()
            .iter()
            .zip(&highs)
            .map(|(s, &edge)| {
                assert_eq!(s.outcome, SyncOutcome::Applied, "{s:?}");
                (s.unix_ms * 1000) as i64 - o.fc.gps_utc_us(edge) as i64
            })
            .collect();
        println!("gcu, packages held: {hold}: sync errors {errors:?} µs, UTC lost {lost} times");
        (errors, lost)
    };
    let (free, free_lost) = run(false);
    let (held, held_lost) = run(true);
    assert_eq!(free_lost, 0);
    assert_eq!(held_lost, 0, "UTC lost while packages backed up");
    assert!(
        held.len() >= 6 && held.len() == free.len(),
        "{held:?} vs {free:?}"
    );
    for (h, f) in held.iter().zip(&free) {
        assert!((h - f).abs() < 2_000, "held {held:?} vs free {free:?} µs");
        assert!(h.unsigned_abs() < BOUNDS.sync_error_us);
    }
}
