//! Faults, through the firmware's tasks (virtual time, pipes as UARTs), for any simulated
//! FC ([`Pilot`]): a pod that numbers its ACKs either way, bit errors and lost bytes on
//! both cables, the pod cable pulled, the pod rebooting, the FC cable pulled, the FC
//! rebooting with another UTC. What must hold in every one: the bridge never stops (no
//! watchdog stall), never sends a time stamp off by more than 30 ms, never answers a
//! geotag with a wrong position (a failure code instead), never takes two photos for one
//! press, and the FC's mount is unhealthy only while the pod is away (plus the driver's
//! own time-out).

use bridge_engine::{Config, Event};
use bridge_fw::LogKind;
use gimbal::sim::FcReboot;
use gimbal::sim::faults::Faults;
use gimbal::sim::pilot::Pilot;
use gimbal::sim::pod::{AckSeq, PodSimConfig, SimPod, SyncOutcome};
use gimbal::sim::tasks::{Bench, Cable, Outcome};
use protocol_core::k40t::AckCode;

use super::{S, TICK, events};

/// The largest error a time stamp may have, µs.
pub const MAX_STAMP_ERROR_US: u64 = 30_000;
/// The farthest a geotag answered with a fix may be from the truth, m.
pub const MAX_GEOTAG_ERROR_M: f64 = 1.5;

/// A bench for `P` with the pod configured by `pod`.
pub fn bench_with<P: Pilot>(pod: PodSimConfig) -> Bench<P> {
    let b = Bench::with(
        Config::for_fc(P::PROTOCOL),
        P::with_seed(7),
        SimPod::new(pod),
    );
    b.wires.record_all();
    b
}

/// What every run must show, whatever the fault: no stall, every stamp within 30 ms of
/// `reference(edge)` (the FC's UTC the bridge could know at the edge), every geotag
/// answered with a fix within [`MAX_GEOTAG_ERROR_M`] of the truth, at most one photo per
/// press. Returns (syncs applied, geotags answered with a fix, geotags failed).
pub fn invariants<P: Pilot>(
    o: &Outcome<P>,
    presses: usize,
    reference: impl Fn(&P, u64) -> Vec<u64>,
) -> (usize, usize, usize) {
    let stalls: Vec<_> = o
        .records
        .iter()
        .filter(|r| matches!(r.what, LogKind::Stalled(_)))
        .collect();
    assert!(stalls.is_empty(), "the bridge stalled: {stalls:?}");
    assert_eq!(o.records_dropped, 0);
    // Every time stamp the engine sent, against the FC's UTC at its edge.
    let mut applied = 0;
    for (_, e) in o.events() {
        if let Event::TimeSync {
            edge,
            utc_ms,
            error_bound_us,
        } = e
        {
            assert!(u64::from(error_bound_us) <= MAX_STAMP_ERROR_US);
            let edge_us = edge.as_micros();
            let refs = reference(&o.fc, edge_us);
            let best = refs
                .iter()
                .map(|r| (utc_ms * 1000).abs_diff(*r))
                .min()
                .expect("a reference");
            assert!(
                best < MAX_STAMP_ERROR_US,
                "stamp at {edge_us} µs off by {best} µs (references {refs:?})"
            );
        }
    }
    for s in o.pod.syncs() {
        if s.outcome == SyncOutcome::Applied {
            applied += 1;
        }
    }
    // Geotags: a fix only where the aircraft was.
    let (mut fixes, mut failures) = (0, 0);
    for p in o.pod.photos() {
        let Some(req) = p.gps_request.map(|i| &o.pod.gps_requests()[i]) else {
            continue;
        };
        let Some(reply) = req.reply.map(|i| &o.pod.gps_replies()[i]) else {
            continue;
        };
        if reply.reply.code.code() != AckCode::Ok {
            failures += 1;
            continue;
        }
        fixes += 1;
        let (lat, lon) = o.fc.aircraft().position_e7(p.at_us);
        let north_m = f64::from(reply.reply.lat_e7 - lat) * 0.011_132;
        let east_m = f64::from(reply.reply.lon_e7 - lon)
            * 0.011_132
            * (f64::from(lat) * 1e-7).to_radians().cos();
        let off = north_m.hypot(east_m);
        assert!(
            off <= MAX_GEOTAG_ERROR_M,
            "photo at {} µs geotagged {off:.2} m from the truth",
            p.at_us
        );
    }
    // Never two photos for one press.
    assert!(
        o.pod.photos().len() <= presses,
        "{} photos for {presses} presses",
        o.pod.photos().len()
    );
    (applied, fixes, failures)
}

/// The FC's UTC as `P` keeps it (one reference: no reboot).
pub fn fc_utc<P: Pilot>(fc: &P, edge_us: u64) -> Vec<u64> {
    vec![fc.true_utc_us(edge_us)]
}

/// The instants (µs) the FC's mount turned unhealthy after having been healthy.
pub fn unhealthy_spells<P: Pilot>(fc: &P) -> Vec<(u64, Option<u64>)> {
    let log = fc.health_log();
    let mut spells = Vec::new();
    let mut was_healthy = false;
    for (i, &(t, h)) in log.iter().enumerate() {
        if was_healthy && !h {
            let back = log
                .get(i + 1..)
                .and_then(|rest| rest.iter().find(|(_, h)| *h).map(|(t, _)| *t));
            spells.push((t, back));
        }
        was_healthy = h;
    }
    spells
}

/// One photo per press, whichever way the pod numbers its ACKs, and no retry on a clean
/// link: five presses, five photos, five geotags, no time-out, no failure reported.
pub fn one_photo_per_press<P: Pilot>(ack_seq: AckSeq) {
    let presses = [20 * S, 26 * S, 32 * S, 38 * S, 44 * S];
    let o = bench_with::<P>(PodSimConfig {
        ack_seq,
        ..PodSimConfig::default()
    })
    .run(50 * S, TICK, |b, t| {
        if presses.contains(&t) {
            b.fc.borrow_mut().take_picture();
        }
    });
    let (_, fixes, failures) = invariants(&o, presses.len(), fc_utc::<P>);
    assert_eq!(o.pod.photos().len(), presses.len(), "{ack_seq:?}");
    assert_eq!((fixes, failures), (presses.len(), 0), "{ack_seq:?}");
    let c = o.engine.counters();
    assert_eq!(c.pod_retries, 0, "{ack_seq:?}: {c:?}");
    assert!(
        events(&o, |e| matches!(e, Event::PodTimeout { .. })).is_empty(),
        "{ack_seq:?}"
    );
    assert!(o.fc.healthy());
    assert!(unhealthy_spells(&o.fc).is_empty());
}

/// Bit errors at `ber` per bit and lost bytes at `drop` per byte on both cables, both
/// directions, for two minutes of flying, turning and taking photos. Returns (syncs
/// applied, photos, geotags with a fix, geotags failed, unhealthy spells).
pub fn faulty_cables<P: Pilot>(ber: f64, drop: f64, seed: u64) -> [usize; 5] {
    let faults = Faults {
        bit_error_rate: ber,
        drop_rate: drop,
        ..Faults::bit_errors(ber, seed)
    };
    let presses: Vec<u64> = (3..=11).map(|i| i * 10 * S + 3 * S).collect();
    let o = bench_with::<P>(PodSimConfig::default()).run(120 * S, TICK, |b, t| {
        if t == 0 {
            b.wires.set_faults(Cable::Fc, Some(faults));
            b.wires.set_faults(Cable::Pod, Some(faults.derived(7)));
        }
        if t == 15 * S {
            b.fc.borrow_mut().turn(10.0, 0.0);
        }
        if t == 18 * S {
            b.fc.borrow_mut().turn(0.0, 0.0);
        }
        if presses.contains(&t) {
            b.fc.borrow_mut().take_picture();
        }
    });
    let (applied, fixes, failures) = invariants(&o, presses.len(), fc_utc::<P>);
    // The bridge kept syncing: at most a few edges lost to corrupted frames.
    assert!(applied >= 9, "{applied} syncs applied");
    [
        applied,
        o.pod.photos().len(),
        fixes,
        failures,
        unhealthy_spells(&o.fc).len(),
    ]
}

/// The pod cable is pulled for 3 s at 40 s: the mount is unhealthy only while the pod is
/// away plus `grace_us` (the bridge's link time-out and the driver's own), healthy again
/// within `back_us`; the bridge syncs the pod again on the next grid edge after it is
/// back. Returns (unhealthy from, healthy again) in µs after the pull.
pub fn pod_cable_pulled<P: Pilot>(grace_us: u64, back_us: u64) -> (u64, u64) {
    const PULL: u64 = 40 * S;
    const BACK: u64 = 43 * S;
    let o = bench_with::<P>(PodSimConfig::default()).run(70 * S, TICK, |b, t| {
        if t == PULL {
            b.wires.pull(Cable::Pod, t, BACK - PULL);
        }
        if t == 55 * S {
            b.fc.borrow_mut().take_picture();
        }
    });
    let (_, fixes, _) = invariants(&o, 1, fc_utc::<P>);
    assert_eq!(fixes, 1, "the photo after the pull is geotagged");
    let spells = unhealthy_spells(&o.fc);
    assert_eq!(spells.len(), 1, "{:?}", o.fc.health_log());
    let (down, up) = spells[0];
    let up = up.expect("healthy again");
    assert!(
        down >= PULL && down <= BACK + grace_us,
        "unhealthy at {down}"
    );
    assert!(up > BACK && up <= BACK + back_us, "healthy again at {up}");
    // The first edge after the pod is back is applied.
    let first_after = o
        .pod
        .syncs()
        .iter()
        .find(|s| s.edge_us.is_some_and(|e| e > BACK))
        .expect("a sync after the pull");
    assert_eq!(first_after.outcome, SyncOutcome::Applied);
    assert!(first_after.edge_us.unwrap() <= BACK + 10 * S);
    assert_eq!(o.engine.counters().pod_retries, 0);
    (down - PULL, up - BACK)
}

/// The pod reboots at 40 s (3 s without power, back with no clock, zoom 1x and a new
/// sequence counter): the bridge syncs it on the next grid edge after it is back, its
/// cache follows (zoom 1x), a photo after the reboot is one photo, acknowledged and
/// geotagged, and the mount was unhealthy only around the reboot.
pub fn pod_reboots<P: Pilot>(grace_us: u64, back_us: u64) {
    const REBOOT: u64 = 40 * S;
    const ON: u64 = 43 * S;
    let o = bench_with::<P>(PodSimConfig::default()).run(70 * S, TICK, |b, t| {
        if t == 25 * S {
            b.fc.borrow_mut().zoom(1);
        }
        if t == 28 * S {
            b.fc.borrow_mut().zoom(0);
        }
        if t == REBOOT {
            b.pod.borrow_mut().reboot_with(t, ON - REBOOT, Some(123));
        }
        if t == 55 * S {
            b.fc.borrow_mut().take_picture();
        }
    });
    let (_, fixes, failures) = invariants(&o, 1, fc_utc::<P>);
    assert_eq!((fixes, failures), (1, 0));
    assert_eq!(o.pod.photos().len(), 1);
    assert_eq!(o.pod.boots().len(), 2);
    // Synced on the first grid edge after power-on, right.
    let first_after = o
        .pod
        .syncs()
        .iter()
        .find(|s| s.edge_us.is_some_and(|e| e > ON))
        .expect("a sync after the reboot");
    let edge = first_after.edge_us.unwrap();
    assert!(edge <= ON + 10 * S, "first sync after the reboot at {edge}");
    assert_eq!(first_after.outcome, SyncOutcome::Applied);
    // The bridge's picture of the pod is the rebooted pod's: zoom 1x.
    assert_eq!(o.engine.pod_state().zoom_x10(), 10);
    // The photo's ACK came with the new counter and was matched: no time-out.
    assert!(events(&o, |e| matches!(e, Event::PodTimeout { base: 0x0302 })).is_empty());
    assert_eq!(o.engine.counters().pod_retries, 0);
    let spells = unhealthy_spells(&o.fc);
    assert!(spells.len() <= 1, "{:?}", o.fc.health_log());
    if let Some(&(down, up)) = spells.first() {
        assert!(
            down >= REBOOT && down <= ON + grace_us,
            "unhealthy at {down}"
        );
        let up = up.expect("healthy again");
        assert!(up <= ON + back_us, "healthy again at {up}");
    }
}

/// The FC cable is pulled for 3 s at 30 s while the pod turns: the pod stops within
/// 0.6 s (FC sides that steer by rates), syncs go on in holdover within 30 ms, photos the
/// pod takes (from its app) 0.8 s into the pull get the newest fix carried forward with
/// the aircraft's velocity (within 1.5 m), those 2 s into it the failure code; after the
/// cable is back the mount is healthy again.
pub fn fc_cable_pulled<P: Pilot>(stops: bool) {
    const PULL: u64 = 30 * S;
    const BACK: u64 = 33 * S;
    let mut turning_at = Vec::new();
    let o = bench_with::<P>(PodSimConfig::default()).run(60 * S, TICK, |b, t| {
        if t == 28 * S {
            b.fc.borrow_mut().turn(15.0, 0.0);
        }
        if t == PULL {
            b.wires.pull(Cable::Fc, t, BACK - PULL);
        }
        if t == PULL + 800_000 || t == PULL + 2 * S {
            b.pod.borrow_mut().photo_from_app(t);
        }
        if t == 40 * S {
            b.fc.borrow_mut().turn(0.0, 0.0);
        }
        if (PULL..BACK).contains(&t) && b.pod.borrow().gimbal().yaw_rate_dps != 0.0 {
            turning_at.push(t);
        }
        if t == 50 * S {
            b.fc.borrow_mut().take_picture();
        }
    });
    if stops {
        let last = turning_at.last().copied().unwrap_or(PULL);
        assert!(
            last - PULL <= 600_000,
            "turning {} ms after the pull",
            (last - PULL) / 1000
        );
    }
    let (applied, fixes, failures) = invariants(&o, 3, fc_utc::<P>);
    assert!(applied >= 5, "{applied}");
    // The K40T FC answers the pod's requests itself and it is away: the bridge answers
    // after 200 ms from what the FC told it, no fix at all here (its only fixes are its
    // answers to earlier photos): failure codes, not a guess.
    let want = if P::PROTOCOL == bridge_engine::FcProtocol::K40t {
        (1, 2)
    } else {
        (2, 1)
    };
    assert_eq!(
        (fixes, failures),
        want,
        "0.8 s: carried forward; 2 s: failure"
    );
    // Syncs at 30..33 s went on (holdover): no edge skipped.
    let highs = o.pin_changes(bridge_engine::Level::High);
    assert!(
        highs.windows(2).all(|w| w[1] - w[0] < 10 * S + S / 10),
        "{highs:?}"
    );
    assert!(o.fc.healthy());
}

/// The FC reboots at 40 s (3 s off) and comes back with its UTC shifted by `shift_us`:
/// no stamp is ever more than 30 ms from the UTC the FC had told the bridge at the edge
/// (the old one until the FC sends its new UTC, the new one once it has), and syncs
/// follow the new UTC within a few seconds of it.
pub fn fc_reboots<P: Pilot>(shift_us: i64) {
    const OFF: u64 = 40 * S;
    const ON: u64 = 43 * S;
    const VALID_AFTER: u64 = 2 * S;
    let mut old_at_off = None;
    let o = bench_with::<P>(PodSimConfig::default()).run(90 * S, TICK, |b, t| {
        if t == OFF {
            old_at_off = Some(b.fc.borrow().true_utc_us(t));
            b.fc.borrow_mut().reboot(
                t,
                FcReboot {
                    off_us: ON - OFF,
                    utc_shift_us: shift_us,
                    utc_valid_after_us: VALID_AFTER,
                    ..FcReboot::default()
                },
            );
        }
        if t == 75 * S {
            b.fc.borrow_mut().take_picture();
        }
    });
    let old_at_off = old_at_off.expect("rebooted");
    // The FC's new UTC reaches the bridge a few seconds after it is valid (the driver's
    // start-up gating first): until then the old one is the FC's word.
    let told_by = ON + VALID_AFTER + 6 * S;
    let reference = |fc: &P, edge: u64| {
        let new = fc.true_utc_us(edge);
        if (OFF..told_by).contains(&edge) {
            vec![old_at_off + (edge - OFF), new]
        } else {
            vec![new]
        }
    };
    let (applied, fixes, _) = invariants(&o, 1, reference);
    assert!(applied >= 6, "{applied}");
    assert_eq!(fixes, 1, "the photo after the reboot is geotagged");
    // After the new UTC: every stamp on it.
    let late: Vec<_> = o
        .pod
        .syncs()
        .iter()
        .filter(|s| s.edge_us.is_some_and(|e| e >= told_by))
        .collect();
    assert!(late.len() >= 2, "{late:?}");
    for s in late {
        let err = (s.unix_ms * 1000).abs_diff(o.fc.true_utc_us(s.edge_us.unwrap()));
        assert!(err < MAX_STAMP_ERROR_US, "{s:?}");
    }
    assert!(o.fc.healthy());
}
