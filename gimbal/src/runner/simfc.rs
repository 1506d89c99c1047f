//! Any of the simulated flight controllers behind one type, for `--fc-port sim` and
//! `gimbal sim-fc`: the ArduPilot SIYI, Viewpro, XF Robot and MAVLink (mount and camera)
//! drivers and the K40T FC, on the host's real UTC.

use serde_json::{Value, json};

use crate::runner::options::Fc;
use crate::sim::ap_mavlink::{ApMavlink, ApMavlinkConfig, MountTarget};
use crate::sim::ap_siyi::{self, ApSiyi, ApSiyiConfig};
use crate::sim::ap_viewpro::{ApViewpro, ApViewproConfig};
use crate::sim::ap_xfrobot::{ApXfRobot, ApXfRobotConfig};
use crate::sim::fc_k40t::FcK40t;
use crate::sim::ground::{GroundLink, GroundPipe};
use crate::sim::pilot::Pilot;
use crate::sim::px4::{Px4, Px4Config};
use crate::sim::{Autopilot, Peer};

/// The K40T FC counts as healthy while frames from the bridge arrived this recently.
const K40T_HEALTHY_US: u64 = 2_000_000;

/// A simulated flight controller of any protocol.
#[allow(clippy::large_enum_variant)]
pub enum AnyFc {
    /// ArduPilot `AP_Mount_Siyi`.
    Siyi(ApSiyi),
    /// ArduPilot `AP_Mount_Viewpro`.
    Viewlink(ApViewpro),
    /// ArduPilot `AP_Mount_XFRobot`.
    Gcu(ApXfRobot),
    /// A flight controller speaking K40T.
    K40t(FcK40t),
    /// ArduPilot `AP_Mount_MAVLink` + `AP_Camera_MAVLinkCamV2`.
    Mavlink(ApMavlink),
    /// PX4's gimbal v2 output (and, towards a ground app, its gimbal manager).
    Px4(Px4),
}

/// The host's UTC now, µs since the Unix epoch.
#[must_use]
pub fn system_utc_us() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| u64::try_from(d.as_micros()).unwrap_or(u64::MAX))
}

/// `$body` with `$f` bound to the simulator inside `$fc`, whichever it is.
macro_rules! each_fc {
    ($fc:expr, $f:ident => $body:expr) => {
        match $fc {
            AnyFc::Siyi($f) => $body,
            AnyFc::Viewlink($f) => $body,
            AnyFc::Gcu($f) => $body,
            AnyFc::K40t($f) => $body,
            AnyFc::Mavlink($f) => $body,
            AnyFc::Px4($f) => $body,
        }
    };
}

impl AnyFc {
    /// The simulator of `fc` whose UTC is the host's: at task time `now_us` it reads
    /// `utc_now_us`.
    #[must_use]
    pub fn new(fc: Fc, now_us: u64, utc_now_us: u64) -> Self {
        let utc_at_zero_us = utc_now_us.saturating_sub(now_us);
        match fc {
            Fc::Siyi => AnyFc::Siyi(ApSiyi::new(ApSiyiConfig {
                utc_at_zero_us,
                ..ApSiyiConfig::default()
            })),
            Fc::Viewlink => AnyFc::Viewlink(ApViewpro::new(ApViewproConfig {
                utc_at_zero_us,
                ..ApViewproConfig::default()
            })),
            Fc::Gcu => AnyFc::Gcu(ApXfRobot::new(ApXfRobotConfig {
                utc_at_zero_us,
                ..ApXfRobotConfig::default()
            })),
            Fc::K40t => AnyFc::K40t(FcK40t::new(utc_at_zero_us)),
            Fc::Mavlink => AnyFc::Mavlink(ApMavlink::new(ApMavlinkConfig {
                utc_at_zero_us,
                ..ApMavlinkConfig::default()
            })),
        }
    }

    /// A simulated PX4 (`config`'s clock settings but UTC: the host's) whose UTC is the
    /// host's: at task time `now_us` it reads `utc_now_us`.
    #[must_use]
    pub fn px4(config: Px4Config, now_us: u64, utc_now_us: u64) -> Self {
        AnyFc::Px4(Px4::new(Px4Config {
            utc_at_zero_us: utc_now_us.saturating_sub(now_us),
            ..config
        }))
    }

    /// Attaches a ground app's link (MAVLink autopilots only); false for the others.
    pub fn attach_ground(&mut self, pipe: GroundPipe) -> bool {
        match self {
            AnyFc::Mavlink(f) => {
                f.ground = Some(GroundLink::new(pipe, f.config.sysid));
                true
            }
            AnyFc::Px4(f) => {
                f.ground = Some(GroundLink::new(pipe, f.config.sysid));
                true
            }
            _ => false,
        }
    }

    fn sim(&mut self) -> &mut dyn Peer {
        each_fc!(self, f => f)
    }

    fn sim_ref(&self) -> &dyn Peer {
        each_fc!(self, f => f)
    }

    /// The driver's `healthy()` (K40T: a frame from the bridge within 2 s).
    #[must_use]
    pub fn healthy(&self, now_us: u64) -> bool {
        match self {
            AnyFc::Siyi(f) => f.healthy(),
            AnyFc::Viewlink(f) => f.healthy(),
            AnyFc::Gcu(f) => f.healthy(),
            AnyFc::Mavlink(f) => f.healthy(),
            AnyFc::Px4(f) => f.healthy(),
            AnyFc::K40t(f) => f
                .received
                .last()
                .is_some_and(|r| now_us.saturating_sub(r.at_us) < K40T_HEALTHY_US),
        }
    }

    /// Takes a picture. False when this simulator cannot (the K40T FC sends no camera
    /// command) or the driver refused (busy).
    pub fn take_picture(&mut self) -> bool {
        match self {
            AnyFc::Siyi(f) => {
                f.take_picture();
                true
            }
            AnyFc::Viewlink(f) => {
                f.take_picture();
                true
            }
            AnyFc::Gcu(f) => f.take_picture(),
            AnyFc::Mavlink(f) => {
                f.take_picture();
                true
            }
            AnyFc::Px4(f) => {
                Pilot::take_picture(f);
                true
            }
            AnyFc::K40t(_) => false,
        }
    }

    /// Turns the mount at these rates, °/s (yaw positive right, pitch positive up).
    /// False for the K40T FC (it sends no motion).
    pub fn set_rates(&mut self, yaw_dps: f64, pitch_dps: f64) -> bool {
        let siyi = ap_siyi::MountTarget::body_rate(yaw_dps, pitch_dps);
        let rate = MountTarget::Rate {
            pitch_dps,
            yaw_dps,
            yaw_is_ef: false,
            from_mavlink: false,
        };
        match self {
            AnyFc::Siyi(f) => f.target = Some(siyi),
            AnyFc::Viewlink(f) => f.target = Some(siyi),
            AnyFc::Gcu(f) => f.target = Some(rate),
            AnyFc::Mavlink(f) => f.set_target(rate),
            AnyFc::Px4(f) => f.turn(yaw_dps, pitch_dps),
            AnyFc::K40t(_) => return false,
        }
        true
    }

    /// Frames the driver could not parse.
    #[must_use]
    pub fn parse_errors(&self) -> u32 {
        match self {
            AnyFc::Siyi(f) => f.parse_errors(),
            AnyFc::Viewlink(f) => f.parse_errors(),
            AnyFc::Gcu(f) => f.parse_errors(),
            AnyFc::Mavlink(f) => f.parse_errors(),
            AnyFc::Px4(f) => f.parse_errors(),
            AnyFc::K40t(_) => 0,
        }
    }

    /// A summary of the run.
    #[must_use]
    pub fn summary(&self, now_us: u64) -> Value {
        json!({
            "healthy": self.healthy(now_us),
            "parse_errors": self.parse_errors(),
        })
    }
}

impl Peer for AnyFc {
    fn receive(&mut self, now_us: u64, bytes: &[u8]) {
        self.sim().receive(now_us, bytes);
    }
    fn poll(&mut self, now_us: u64) {
        self.sim().poll(now_us);
    }
    fn next_wakeup(&self) -> u64 {
        self.sim_ref().next_wakeup()
    }
    fn transmit(&mut self, now_us: u64) -> Vec<(u64, Vec<u8>)> {
        self.sim().transmit(now_us)
    }
}
