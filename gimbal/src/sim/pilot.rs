//! One interface over the simulated flight controllers, for the demo and the task-level
//! scenarios: a [`Pilot`] is a simulated autopilot ([`Autopilot`]: its board says whether
//! its driver calls the mount healthy, reboots it) that flies the mount (point, turn,
//! zoom, photo, record), knows the true UTC and the aircraft's true position (the
//! references of time sync and geotag), and names how its protocol's frames read for
//! people ([`SideFrames`]).
//!
//! Each simulator implements it once, in its own file: [`super::ap_siyi::ApSiyi`]
//! (ArduPilot `AP_Mount_Siyi`), [`super::ap_viewpro::ApViewpro`] (ArduPilot
//! `AP_Mount_Viewpro`, the Viewlink side), [`super::ap_xfrobot::ApXfRobot`] (ArduPilot
//! `AP_Mount_XFRobot`, the GCU side), [`super::fc_k40t::FcK40t`] (an FC speaking K40T
//! itself), and on the MAVLink side [`super::ap_mavlink::ApMavlink`] and
//! [`super::px4::Px4`]. A new side adds one `impl Pilot` and one match arm where the demo
//! picks the simulator by [`FcProtocol`].

use bridge_engine::FcProtocol;

use super::FcClock;
use super::ap_mavlink::{ApMavlink, ApMavlinkConfig};
use super::ap_siyi::{ApSiyi, ApSiyiConfig};
use super::ap_viewpro::{ApViewpro, ApViewproConfig};
use super::ap_xfrobot::{ApXfRobot, ApXfRobotConfig};
use super::board::Autopilot;
use super::describe::SideFrames;
use super::fc_k40t::FcK40t;
use super::px4::{Px4, Px4Config};

/// A simulated flight controller the demo and the task scenarios can fly.
///
/// Angles are degrees, yaw positive right (body frame), pitch positive up; rates in
/// degrees per second. Time is simulated true time in microseconds.
pub trait Pilot: Autopilot + Seeded {
    /// How the frames of the FC protocol this simulator speaks read for people.
    type Frames: SideFrames;
    /// The FC protocol this simulator speaks.
    const PROTOCOL: FcProtocol = <Self::Frames as SideFrames>::PROTOCOL;
    /// Who is on the FC side, for people.
    const DRIVER: &'static str;
    /// The FC sends frames continuously (several a second) while it runs, so the
    /// bridge's FC link stays up; a K40T FC speaks only when it has something to say.
    const STREAMS: bool = true;
    /// A simulated ArduPilot whose MAVLink port can be attached as the telemetry link
    /// ([`super::ap_mavlink::ApMavlink::telemetry`] on its [`Pilot::board_clock`]).
    const TELEMETRY_PORT: bool = false;

    /// The FC's UTC at true time `t_us` (µs since the Unix epoch): what a time sync should
    /// carry for an edge at that instant.
    fn true_utc_us(&self, t_us: u64) -> u64 {
        self.fc_utc_us(t_us)
    }
    /// True time the FC first sent a usable UTC (SIYI 0x30, Viewlink M_AHRS with a valid
    /// date, GCU a GPS time, K40T 0x00030E), µs.
    fn first_utc_sent_us(&self) -> Option<u64>;
    /// The autopilot's clock when it is a simulated ArduPilot whose MAVLink port can be
    /// attached as the telemetry link ([`Pilot::TELEMETRY_PORT`]).
    fn board_clock(&self) -> Option<&FcClock> {
        Self::TELEMETRY_PORT.then(|| self.clock())
    }
    /// What the FC last read of the mount's angles: (yaw, pitch) in degrees.
    fn mount_angles(&self) -> Option<(f64, f64)>;

    /// Point the mount at these angles (body-frame yaw).
    fn point(&mut self, yaw_deg: f64, pitch_deg: f64);
    /// Turn the mount at these rates (body-frame yaw); zeros stop it.
    fn turn(&mut self, yaw_dps: f64, pitch_dps: f64);
    /// Zoom: > 0 in, < 0 out, 0 stop.
    fn zoom(&mut self, rate: i8);
    /// Take one picture.
    fn take_picture(&mut self);
    /// Start or stop recording.
    fn record(&mut self, on: bool);
}

/// A simulator that can be made with its default settings and a seed for its random
/// jitter.
pub trait Seeded {
    /// The simulator with its default settings and this seed.
    fn with_seed(seed: u64) -> Self;
}

macro_rules! seeded {
    ($($sim:ident($config:ident)),*) => {$(
        impl Seeded for $sim {
            fn with_seed(seed: u64) -> Self {
                $sim::new($config { seed, ..$config::default() })
            }
        }
    )*};
}
seeded!(
    ApSiyi(ApSiyiConfig),
    ApViewpro(ApViewproConfig),
    ApXfRobot(ApXfRobotConfig),
    ApMavlink(ApMavlinkConfig),
    Px4(Px4Config)
);

/// The K40T FC simulator has no randomness.
impl Seeded for FcK40t {
    fn with_seed(_seed: u64) -> Self {
        FcK40t::default()
    }
}

/// Settings that describe an FC's clock (crystal error, boot, UTC).
pub trait ClockSettings {
    /// The FC's clock.
    fn clock(&self) -> FcClock;
}

macro_rules! clock_settings {
    ($($config:ident: $utc_valid_at_us:ident),*) => {$(
        impl ClockSettings for $config {
            fn clock(&self) -> FcClock {
                FcClock::new(self.ppm, self.boot_us, self.utc_at_zero_us, self.$utc_valid_at_us)
            }
        }
    )*};
}
clock_settings!(
    ApSiyiConfig: utc_valid_at_us,
    ApViewproConfig: utc_valid_at_us,
    ApXfRobotConfig: gps_valid_at_us
);
