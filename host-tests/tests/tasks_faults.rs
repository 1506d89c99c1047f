//! Faults through the firmware's tasks, for every FC side (the scenarios are in
//! `task_scenarios/faults.rs`): a pod numbering its ACKs with its own counter or echoing
//! the request's, bit errors (1e-5 and 1e-4 per bit) and lost bytes on both cables, the
//! pod cable pulled for 3 s, the pod rebooting, the FC cable pulled, the FC rebooting with
//! another UTC. Run with `--nocapture` for the figures.

use crate::task_scenarios;

use gimbal::sim::ap_siyi::ApSiyi;
use gimbal::sim::ap_viewpro::ApViewpro;
use gimbal::sim::ap_xfrobot::ApXfRobot;
use gimbal::sim::fc_k40t::FcK40t;
use gimbal::sim::pilot::Pilot;
use gimbal::sim::pod::AckSeq;
use task_scenarios::S;
use task_scenarios::faults;

/// Each side's grace for the pod's absence to show at the FC (the bridge's 1 s link
/// time-out plus the driver's own 1 s) and for the mount to be healthy again.
const GRACE: u64 = 2_500_000;
const BACK: u64 = 2 * S;

fn every_fault<P: Pilot>(label: &str, stops: bool, checks_health: bool) {
    for ack in [AckSeq::OwnCounter, AckSeq::Echo] {
        faults::one_photo_per_press::<P>(ack);
    }
    for (ber, drop) in [(1e-5, 1e-6), (1e-4, 1e-5)] {
        let [syncs, photos, fixes, failures, spells] = faults::faulty_cables::<P>(ber, drop, 11);
        println!(
            "{label}: BER {ber:e}, byte loss {drop:e}: {syncs} syncs applied, {photos} photos of 9 presses, {fixes} geotags with a fix, {failures} failure codes, {spells} unhealthy spells"
        );
    }
    if checks_health {
        let (down, up) = faults::pod_cable_pulled::<P>(GRACE, BACK);
        println!(
            "{label}: pod cable pulled 3 s: unhealthy {} ms after the pull, healthy {} ms after it is back",
            down / 1000,
            up / 1000
        );
    }
    faults::pod_reboots::<P>(GRACE, BACK + S);
    faults::fc_cable_pulled::<P>(stops);
    for shift in [1_500_000, -300_000] {
        faults::fc_reboots::<P>(shift);
    }
}

#[test]
fn siyi() {
    every_fault::<ApSiyi>("siyi", true, true);
}

#[test]
fn viewlink() {
    every_fault::<ApViewpro>("viewlink", true, true);
}

#[test]
fn gcu() {
    every_fault::<ApXfRobot>("gcu", false, true);
}

#[test]
fn k40t() {
    every_fault::<FcK40t>("k40t", true, false);
}
