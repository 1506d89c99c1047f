//! The MAVLink side through the firmware's tasks (virtual time, pipes): start-up to
//! healthy, commands and telemetry, time sync with the RTC_IO edge before the 0x00030E,
//! geotag, FC silence, pod loss, garbage on both lines, with the simulated ArduPilot
//! (`MNT1_TYPE` 6 + `CAM1_TYPE` 6) and, for start-up, commands and time, PX4's gimbal v2
//! output in mode Gimbal. The scenarios are in `task_scenarios/mod.rs`; the bounds here
//! are this side's.

use crate::task_scenarios;

use gimbal::sim::ap_mavlink::ApMavlink;
use gimbal::sim::px4::Px4;
use task_scenarios::{Bounds, S};

const BOUNDS: Bounds = Bounds {
    // ArduPilot's drivers search already (it booted before the bridge): healthy once the
    // pod's versions are known and the first attitude status went out.
    healthy_within_us: S,
    sync_error_us: 5_000,
    // COMMS_ERROR once the pod's attitude is 0.5 s old, in the next 10 Hz status.
    unhealthy_after_pod_loss_us: S,
    healthy_after_pod_back_us: S,
    silence_stop_event: true,
    bridge_geotags: true,
};

#[test]
fn startup_to_healthy() {
    task_scenarios::startup_to_healthy::<ApMavlink>(BOUNDS);
}

#[test]
fn commands_reach_the_pod_and_its_attitude_the_fc() {
    task_scenarios::commands_and_telemetry::<ApMavlink>();
}

#[test]
fn time_syncs_edge_then_frame_and_photos_geotagged() {
    task_scenarios::sync_and_geotag::<ApMavlink>(BOUNDS, "mavlink");
}

#[test]
fn fc_silence_stops_the_pod_within_0_6_s() {
    let delay = task_scenarios::fc_silence_stops_motion::<ApMavlink>(BOUNDS);
    println!(
        "mavlink: pod still {} ms after the FC cable was cut",
        delay / 1000
    );
}

#[test]
fn pod_loss_is_seen_as_a_lost_gimbal_then_recovery() {
    task_scenarios::pod_loss::<ApMavlink>(BOUNDS);
}

#[test]
fn garbage_on_both_lines_keeps_it_healthy() {
    task_scenarios::garbage_on_both_lines::<ApMavlink>();
}

/// PX4 (mode Gimbal; the bridge's SET_MESSAGE_INTERVAL honoured): its own health rule is
/// the information and a status within 1 s.
const PX4: Bounds = Bounds {
    healthy_within_us: 2 * S,
    ..BOUNDS
};

#[test]
fn px4_startup_to_healthy() {
    task_scenarios::startup_to_healthy::<Px4>(PX4);
}

#[test]
fn px4_commands_reach_the_pod_and_its_attitude_the_fc() {
    task_scenarios::commands_and_telemetry::<Px4>();
}

#[test]
fn px4_time_syncs_and_photos_geotagged() {
    task_scenarios::sync_and_geotag::<Px4>(PX4, "mavlink (PX4)");
}
