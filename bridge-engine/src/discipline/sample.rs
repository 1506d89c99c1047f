//! What the discipline is fed: one time value from the flight controller ([`Sample`]),
//! and the serial time that is part of its delay ([`serial_time`]).

use super::estimator::Point;
use crate::time::{Duration, Instant};

protocol_core::wire_derive! {
    [Eq]
    /// One time value received from the flight controller.
    // Independent properties of one time value, each its own flag.
    #[allow(clippy::struct_excessive_bools)]
    pub struct Sample {
        /// Local instant at which the frame's last byte arrived.
        pub local: Instant,
        /// The time the frame carries, in microseconds (UTC: since the Unix epoch; FC clock:
        /// `time_boot_ms × 1000`).
        pub value_us: u64,
        /// Truncation step of the value: the true remote time at reading was in
        /// `[value, value + resolution)`. 1 µs for SIYI 0x30, 1000 for `time_boot_ms` and
        /// millisecond fields (K40T), 10 000 for Viewlink's hundredths of a second. For a
        /// held value: the sender's update period (GCU under ArduPilot: 20 000), the most by
        /// which the first sample after an event was read late.
        pub resolution_us: u32,
        /// The sender holds this value between events and repeats it (GCU: the time of the
        /// last GPS fix, sent at 50 Hz, stepping at 5-10 Hz). Such a value is the exact time
        /// of the event, only the first sample after each change carries information, and
        /// a value that stops changing is not fresh.
        pub held: bool,
        /// The part of the delay between the sender's read and `local` that is known: the
        /// serial time of this frame and of the bytes the sender wrote before it in the same
        /// burst ([`serial_time`]). Subtracted from `local`.
        pub transit: Duration,
        /// The sender writes this value at once after the instant it carries, by protocol
        /// (the K40T FC's 0x00030E follows its own RTC_IO edge): a single such sample is
        /// enough for a first mapping.
        pub prompt: bool,
        /// The remote clock read `value_us` at or *after* `local` (here the instant the
        /// bridge started sending a request the remote stamped on arrival: ArduPilot's
        /// TIMESYNC tc1, its UART's estimate of the request's start, never earlier), not
        /// before it: the point lies on or under the offset line, and the least-advanced
        /// samples are the tight ones. An estimator takes one kind (the first sample's).
        pub lower: bool,
        /// The remote clock may run at any rate against the local one, not only a
        /// crystal's ppm: a MAVLink autopilot's boot clock may be a simulator's (PX4 SITL
        /// in lockstep runs 0.87 % slow). An estimator takes it from its first sample.
        pub any_rate: bool,
    }
}

impl Sample {
    /// A sample of a running clock (not held) with no known transit time.
    #[must_use]
    pub const fn new(local: Instant, value_us: u64, resolution_us: u32) -> Self {
        Self {
            local,
            value_us,
            resolution_us,
            held: false,
            transit: Duration::ZERO,
            prompt: false,
            lower: false,
            any_rate: false,
        }
    }

    /// The same sample, of a clock that may run at any rate ([`Sample::any_rate`]).
    #[must_use]
    pub const fn any_rate(mut self) -> Self {
        self.any_rate = true;
        self
    }

    /// The same sample, read by the remote at or after `local` ([`Sample::lower`]).
    #[must_use]
    pub const fn lower_bound(mut self) -> Self {
        self.lower = true;
        self
    }

    /// The same sample, marked as sent at once after the instant it carries
    /// ([`Sample::prompt`]).
    #[must_use]
    pub const fn prompt(mut self) -> Self {
        self.prompt = true;
        self
    }

    /// The same sample, marked as a held value ([`Sample::held`]).
    #[must_use]
    pub const fn held(mut self) -> Self {
        self.held = true;
        self
    }

    /// The same sample with a known transit time ([`Sample::transit`]).
    #[must_use]
    pub const fn with_transit(mut self, transit: Duration) -> Self {
        self.transit = transit;
        self
    }
}

/// Time to send `bytes` bytes on an 8N1 serial line at `baud` bits per second (10 bits
/// per byte), rounded to the nearest microsecond. Zero if `baud` is zero.
#[must_use]
pub const fn serial_time(bytes: u32, baud: u32) -> Duration {
    if baud == 0 {
        return Duration::ZERO;
    }
    let bits = (bytes as u64).saturating_mul(10_000_000);
    let half = (baud as u64) / 2;
    match bits.saturating_add(half).checked_div(baud as u64) {
        Some(us) => Duration::from_micros(us),
        None => Duration::ZERO,
    }
}

/// Local time of a sample with its known transit removed, as `i64`.
pub(super) fn local_x(s: Sample) -> Option<i64> {
    i64::try_from(s.local.as_micros().checked_sub(s.transit.as_micros())?).ok()
}

/// The estimator point of a sample: `(x, x − (value + center))`.
pub(super) fn point(s: Sample, center: u32) -> Option<Point> {
    let x = local_x(s)?;
    let r = i64::try_from(s.value_us)
        .ok()?
        .checked_add(i64::from(center))?;
    Some(Point {
        x,
        y: x.checked_sub(r)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn serial_times() {
        assert_eq!(serial_time(1, 115_200).as_micros(), 87);
        assert_eq!(serial_time(72, 115_200).as_micros(), 6_250);
        assert_eq!(serial_time(10, 0), Duration::ZERO);
    }
}
