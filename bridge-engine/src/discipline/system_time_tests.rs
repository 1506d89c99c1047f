//! MAVLink time, sample by sample: TIMESYNC (the boot clock) and SYSTEM_TIME (UTC and
//! the boot clock in one reading), from a flight controller whose UTC is in step with its
//! boot clock and from a simulator in lockstep whose UTC is apart from it (the
//! [`Pace`] of the shift).

use super::*;

/// 2026-01-01T00:00:00Z in µs.
const U0: u64 = 1_767_225_600_000_000;

/// The bridge's clock, 20 ppm fast, from 3 s: local = 3e6 + t·(1 + 20e-6).
fn local(t_us: u64) -> Instant {
    Instant::from_micros(3_000_000 + t_us + t_us / 50_000)
}

/// A MAVLink flight controller at true time (µs): its boot clock as TIMESYNC reads it, as
/// SYSTEM_TIME carries it, and its UTC.
struct Fc {
    boot: fn(u64) -> u64,
    stream_boot: fn(u64) -> u64,
    utc: fn(u64) -> u64,
}

/// What feeding an [`Fc`] gave at each SYSTEM_TIME: (true time, UTC error at the bridge
/// then µs, the bound believed µs), or `None` while there was no UTC.
type Seen = Vec<(u64, Option<(i64, u64)>)>;

impl Fc {
    /// TIMESYNC every 100 ms (its tc1 read 300 µs after the request started) and a
    /// SYSTEM_TIME every 100 ms, read 50 to 51 ms after each TIMESYNC (its phase against
    /// the FC's millisecond covers the millisecond) and `delay_us(k)` before it arrives;
    /// from true time `from` to `to`.
    fn feed(&self, d: &mut TimeDiscipline, from: u64, to: u64, delay_us: fn(u64) -> u64) -> Seen {
        let mut seen = Vec::new();
        let mut t = from;
        while t < to {
            let tc1 = (self.boot)(t + 300);
            d.fc_clock_sample(Sample::new(local(t), tc1, 1).lower_bound().any_rate());
            let k = t / 100_000;
            let read = t + 50_000 + (k * 7_919) % 1_000;
            let at = read + delay_us(k);
            let sample = Sample::new(local(at), (self.utc)(read), 1);
            d.system_time(sample, (self.stream_boot)(read) / 1000);
            let utc = d.utc(local(at)).map(|given| {
                let error = i128::from(given.as_unix_micros()) - i128::from((self.utc)(at));
                let bound = d.error_bound(local(at)).map_or(0, Duration::as_micros);
                (i64::try_from(error).unwrap(), bound)
            });
            seen.push((at, utc));
            t += 100_000;
        }
        seen
    }
}

impl Fc {
    /// A flight controller whose SYSTEM_TIME carries the boot clock TIMESYNC reads.
    fn of(boot: fn(u64) -> u64, utc: fn(u64) -> u64) -> Self {
        Fc {
            boot,
            stream_boot: boot,
            utc,
        }
    }

    /// A fresh discipline fed by this FC from true time 0 to `to`.
    fn flown(&self, to: u64, delay_us: fn(u64) -> u64) -> (TimeDiscipline, Seen) {
        let mut d = TimeDiscipline::default();
        let seen = self.feed(&mut d, 0, to, delay_us);
        (d, seen)
    }
}

/// Every error under its bound, and the worst from `steady` on at most `worst_max` µs;
/// returns the first instant with UTC.
fn assert_within(seen: &Seen, steady: u64, worst_max: i64) -> u64 {
    let (first, worst, over) = first_and_worst(seen, steady);
    assert!(worst <= worst_max, "{worst}");
    assert!(over < 0, "a bound under the error by {over} µs");
    first
}

/// UTC, once it was there, was there at every SYSTEM_TIME after.
fn never_lost(seen: &Seen) -> bool {
    seen.iter()
        .skip_while(|(_, u)| u.is_none())
        .all(|(_, u)| u.is_some())
}

/// The first instant with UTC, the worst error from `steady` on, and the worst error less
/// bound.
fn first_and_worst(seen: &Seen, steady: u64) -> (u64, i64, i64) {
    let first = seen.iter().find(|(_, u)| u.is_some()).expect("UTC").0;
    let usable: Vec<(i64, u64)> = seen.iter().filter_map(|(_, u)| *u).collect();
    let worst = seen
        .iter()
        .filter(|(t, _)| *t >= steady)
        .filter_map(|(_, u)| u.map(|(e, _)| e.abs()))
        .max()
        .unwrap();
    let over = usable
        .iter()
        .map(|(e, b)| e.abs() - i64::try_from(*b).unwrap())
        .max()
        .unwrap();
    (first, worst, over)
}

/// A real flight controller: a crystal 30 ppm slow, its UTC its boot clock plus a fixed
/// shift; SYSTEM_TIME 2 to 5 ms late (a busy link: the boot clock's mapping does not
/// care).
fn crystal_boot(t: u64) -> u64 {
    7_000_000 + t - t * 3 / 100_000
}
fn in_step_utc(t: u64) -> u64 {
    U0 + 123_456 + crystal_boot(t) - 7_000_000
}
fn late(k: u64) -> u64 {
    2_000 + (k * 7_919) % 3_000
}

/// The boot-clock mapping waits until the shift has stayed within its band for a second
/// (the TIMESYNC fit had a first mapping long before), then is used: errors of the
/// TIMESYNC read (300 µs), not of SYSTEM_TIME's 2–5 ms delays; in step for good.
#[test]
fn an_fc_whose_utc_is_in_step_is_used_through_its_boot_clock() {
    let (d, seen) = Fc::of(crystal_boot, in_step_utc).flown(120_000_000, late);
    // Steady once the fit has the rates (about 32 s; before, the first mapping's error
    // grows with the clocks' 50 ppm, inside its bound).
    let first = assert_within(&seen, 40_000_000, 400);
    // The first SYSTEM_TIME at 50 ms, watched for a second of boot time.
    assert!((1_000_000..1_300_000).contains(&first), "{first}");
    assert_eq!(d.fc_offset.shift.pace(), Pace::InStep);
    assert_eq!(d.path, Some(Path::ViaFc));
    assert!(never_lost(&seen));
}

/// PX4 SITL in lockstep: its boot clock 0.87 % slow against its UTC (the host's), with a
/// wander (here 20 ms over 20 s: up to 6 300 ppm, three times the capture's) and 4 ms
/// steps; SYSTEM_TIME goes out at a step, so its `time_boot_ms` is the step's and its
/// `time_unix_usec` the host's then. The shift runs apart within two seconds; from then
/// SYSTEM_TIME alone gives UTC, TIMESYNC is not used, and the mapping is never one
/// through the boot clock (whose error would be its wander).
#[test]
fn a_simulator_whose_utc_runs_apart_gives_utc_from_system_time_alone() {
    // Microseconds of a few minutes: exact in an f64, positive.
    #[allow(
        clippy::cast_precision_loss,
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss
    )]
    fn simulation(t: u64) -> u64 {
        let seconds = t as f64 / 1e6;
        (5e6 + t as f64 * (1.0 - 8_746e-6) + 20_000.0 * (seconds * 0.314).sin()) as u64
    }
    fn lockstep_boot(t: u64) -> u64 {
        simulation(t) / 4_000 * 4_000
    }
    fn host(t: u64) -> u64 {
        U0 + t
    }
    fn pty(k: u64) -> u64 {
        20 + (k * 7_919) % 800
    }
    let fc = Fc {
        boot: lockstep_boot,
        stream_boot: simulation,
        utc: host,
    };
    let (mut d, seen) = fc.flown(3_000_000, pty);
    assert_eq!(d.fc_offset.shift.pace(), Pace::Apart);
    assert_eq!(d.path, Some(Path::Direct));
    let v = d.fc_clock_sample(
        Sample::new(local(3_000_000), 9_999, 1)
            .lower_bound()
            .any_rate(),
    );
    assert_eq!(v, Verdict::Rejected, "TIMESYNC no longer used");
    let seen: Seen = seen
        .into_iter()
        .chain(fc.feed(&mut d, 3_000_000, 120_000_000, pty))
        .collect();
    // Errors of the least SYSTEM_TIME delay (20 µs here); never lost once valid.
    let first = assert_within(&seen, 40_000_000, 300);
    assert!(first < 3_000_000, "{first}");
    assert!(never_lost(&seen));
}

/// An FC in step whose UTC steps by 40 ms (a GPS time correction): a step, not a
/// simulator's drift: the boot-clock mapping restarts from it and stays in use.
#[test]
fn a_step_of_an_in_step_utc_stays_in_step() {
    fn stepped_utc(t: u64) -> u64 {
        in_step_utc(t) + if t >= 30_000_000 { 40_000 } else { 0 }
    }
    let (d, seen) = Fc::of(crystal_boot, stepped_utc).flown(90_000_000, late);
    assert_eq!(d.fc_offset.shift.pace(), Pace::InStep);
    assert_eq!(d.path, Some(Path::ViaFc));
    // The new UTC within a second of the step, then right, within its bound.
    let after: Seen = seen.into_iter().filter(|(t, _)| *t > 31_000_000).collect();
    assert!(after.iter().all(|(_, u)| u.is_some()));
    assert_within(&after, 0, 400);
}

/// An FC whose UTC follows GPS while its boot clock is a crystal 200 ppm off: a drift a
/// crystal has, in step over twenty minutes.
#[test]
fn a_crystal_s_drift_of_utc_against_the_boot_clock_stays_in_step() {
    fn gps_utc(t: u64) -> u64 {
        U0 + 7_000_000 + t
    }
    fn boot_200_ppm(t: u64) -> u64 {
        7_000_000 + t + t / 5_000
    }
    let (d, seen) = Fc::of(boot_200_ppm, gps_utc).flown(1_200_000_000, late);
    assert_eq!(d.fc_offset.shift.pace(), Pace::InStep);
    assert_within(&seen, 40_000_000, 400);
}
