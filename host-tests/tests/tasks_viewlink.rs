//! The Viewlink side through the firmware's tasks (virtual time, pipes): start-up to healthy,
//! commands and telemetry, time sync with the RTC_IO edge before the 0x00030E, geotag,
//! FC silence, pod loss, garbage on both lines. The scenarios are in
//! `task_scenarios/mod.rs`; the bounds here are this side's.

use crate::task_scenarios;

use gimbal::sim::ap_viewpro::ApViewpro;
use task_scenarios::{Bounds, S};

const BOUNDS: Bounds = Bounds {
    healthy_within_us: S,
    sync_error_us: 5_000,
    unhealthy_after_pod_loss_us: 1_800_000,
    healthy_after_pod_back_us: S,
    silence_stop_event: true,
    bridge_geotags: true,
};

#[test]
fn startup_to_healthy() {
    task_scenarios::startup_to_healthy::<ApViewpro>(BOUNDS);
}

#[test]
fn commands_reach_the_pod_and_its_attitude_the_fc() {
    task_scenarios::commands_and_telemetry::<ApViewpro>();
}

#[test]
fn time_syncs_edge_then_frame_and_photos_geotagged() {
    task_scenarios::sync_and_geotag::<ApViewpro>(BOUNDS, "viewlink");
}

#[test]
fn fc_silence_stops_the_pod_within_0_6_s() {
    let delay = task_scenarios::fc_silence_stops_motion::<ApViewpro>(BOUNDS);
    println!(
        "viewlink: pod still {} ms after the FC cable was cut",
        delay / 1000
    );
}

#[test]
fn pod_loss_is_seen_as_a_lost_gimbal_then_recovery() {
    task_scenarios::pod_loss::<ApViewpro>(BOUNDS);
}

#[test]
fn garbage_on_both_lines_keeps_it_healthy() {
    task_scenarios::garbage_on_both_lines::<ApViewpro>();
}
