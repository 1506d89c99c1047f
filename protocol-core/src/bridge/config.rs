//! The bridge's configuration: one `Copy` struct with documented defaults
//! ([`Config::DEFAULT`]). Firmware picks it at build time; the Linux runner from its
//! command line.

use super::discipline::DisciplineConfig;
use super::fixes::FixConfig;
use super::sync::SyncConfig;
use super::time::Duration;
use crate::k40t::{Address, CrcCoverage};

wire_derive! {
    [Eq, Hash]
    /// The protocol the flight controller speaks.
    pub enum FcProtocol {
        /// SIYI SDK (ArduPilot `MNT1_TYPE` 8): the bridge acts as a SIYI gimbal.
        Siyi,
        /// Viewlink (ArduPilot `MNT1_TYPE` 11): the bridge acts as a Viewpro gimbal.
        Viewlink,
        /// XF Robot GCU (ArduPilot `MNT1_TYPE` 14): the bridge acts as a GCU.
        Gcu,
        /// K40T itself: the bridge forwards, and owns RTC_IO.
        K40t,
        /// MAVLink 2 (ArduPilot `MNT1_TYPE` 6 + `CAM1_TYPE` 6, PX4 gimbal v2): the bridge is
        /// a gimbal device (component 154) and a camera (component 100). Needs the
        /// `mavlink` feature.
        Mavlink,
    }
}

/// How the bridge presents itself to a SIYI flight controller.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SiyiIdentity {
    /// The 12-character hardware id (0x02). Its first two characters select the model
    /// in ArduPilot: "7A" is the ZT30, for which ArduPilot enables 30x zoom, the laser
    /// rangefinder, lens selection and thermal min/max.
    pub hardware_id: [u8; 12],
    /// Camera firmware (major, minor, patch); ArduPilot needs it non-zero.
    pub camera_version: [u8; 3],
    /// Gimbal firmware (major, minor, patch).
    pub gimbal_version: [u8; 3],
    /// Zoom firmware (major, minor, patch).
    pub zoom_version: [u8; 3],
    /// Largest zoom reported by 0x16, times ten (the ZT30 reports 30x).
    pub max_zoom_x10: u16,
}

impl SiyiIdentity {
    /// A ZT30 ("7A"), firmware 0.3.1 / 0.3.1 / 0.1.0, zoom up to 30x.
    pub const DEFAULT: Self = Self {
        hardware_id: *b"7A0000000001",
        camera_version: [0, 3, 1],
        gimbal_version: [0, 3, 1],
        zoom_version: [0, 1, 0],
        max_zoom_x10: 300,
    };
}

/// How the bridge presents itself to a Viewlink flight controller.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ViewlinkIdentity {
    /// Model text answered to the 0xE4 query (10 bytes, padded with 0x00; ArduPilot
    /// prints it).
    pub model: [u8; 10],
    /// Firmware text answered to the 0xD0 query (20 bytes, padded with 0x00). Viewpro
    /// gimbals send "S" and a date (`Syyyymmdd`); ArduPilot reads bytes 3..9 as three
    /// two-digit numbers, major, minor and patch.
    pub firmware: [u8; 20],
}

impl ViewlinkIdentity {
    /// Model "K40TBRIDGE"; firmware "S20000100", which ArduPilot reads as 0.1.0 (the
    /// bridge's version).
    pub const DEFAULT: Self = Self {
        model: *b"K40TBRIDGE",
        firmware: *b"S20000100\0\0\0\0\0\0\0\0\0\0\0",
    };
}

/// How the bridge presents itself to a GCU flight controller (the sub data frame of
/// every reply).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GcuIdentity {
    /// Hardware version times ten (reply byte 38; ArduPilot prints it divided by 10).
    pub hardware_x10: u8,
    /// Firmware version times ten (reply byte 39).
    pub firmware_x10: u8,
    /// Gimbal code (reply byte 40, the document's "Gimbal Code" table). The K40T is none
    /// of the listed models: 0xFF by default, which no table entry uses.
    pub gimbal_code: u8,
    /// Send `8A 00` after every reply (default true): ArduPilot's XF Robot parser keeps
    /// skipped bytes in its buffer and, after one corrupted reply, can lose step with
    /// the replies for good; the pair puts it back in step at the end of every reply.
    pub resync_mark: bool,
}

impl GcuIdentity {
    /// Hardware 1.0, firmware 1.0, gimbal code 0xFF (not a listed model), resync mark
    /// on.
    pub const DEFAULT: Self = Self {
        hardware_x10: 10,
        firmware_x10: 10,
        gimbal_code: 0xFF,
        resync_mark: true,
    };
}

/// The pod link: addresses, CRC coverage, retries, time-outs and rate limits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PodConfig {
    /// The bridge's own address on the pod link: the flight controller's (0x02/0x01).
    pub own: Address,
    /// Where gimbal-class requests (0x000010..0x0000FF) go until the pod's reports
    /// show its address (default 0x03/0x01, section 3.1 of the document).
    pub gimbal: Address,
    /// Where camera requests go until learnt (default 0x04/0x01).
    pub camera: Address,
    /// CRC coverage until the pod's first report shows its own (default: MAVLink's).
    pub coverage: CrcCoverage,
    /// Learn addresses and coverage from the pod's reports (default true).
    pub learn: bool,
    /// Tries of a setting or camera action before giving up (default 3).
    pub tries: u8,
    /// Time between tries (default 200 ms).
    pub retry_interval: Duration,
    /// The pod is lost when no report arrives for this long (default 1 s).
    pub link_timeout: Duration,
    /// While lost, a version query is sent this often (default 1 s).
    pub probe_interval: Duration,
    /// A motion command is refreshed this often while the gimbal turns (default 1 s).
    pub motion_refresh: Duration,
    /// Least time between two motion commands (default 100 ms): a flight controller's
    /// 50 Hz control loop becomes at most 10 motion commands a second.
    pub motion_interval: Duration,
    /// A rate change smaller than this (0.01 °/s) is no new command (default 50: 0.5 °/s).
    pub rate_deadband_cdeg_s: u16,
    /// An angle change smaller than this (0.01 °) is no new command (default 20).
    pub angle_deadband_cdeg: u16,
    /// The pod reports yaw positive to the left (the document does not say; default
    /// false: positive right, the aerospace convention).
    pub yaw_positive_left: bool,
    /// The pod reports pitch positive down (default false: positive up).
    pub pitch_positive_down: bool,
    /// Target categories of the AI recognition the bridge switches on before box
    /// tracking (0x000319 bytes 3..12: ids of the pod model's label file; the document
    /// names none). Default 0..=9, the first ten (with the usual YOLO labels: person,
    /// bicycle, car, motorcycle, aeroplane, bus, train, truck, boat, traffic light).
    pub ai_classes: [u8; 10],
}

impl PodConfig {
    /// The documented defaults.
    pub const DEFAULT: Self = Self {
        own: Address::FLIGHT_CONTROLLER,
        gimbal: Address::GIMBAL,
        camera: Address::POD,
        coverage: CrcCoverage::ExcludeStx,
        learn: true,
        tries: 3,
        retry_interval: Duration::from_millis(200),
        link_timeout: Duration::from_secs(1),
        probe_interval: Duration::from_secs(1),
        motion_refresh: Duration::from_secs(1),
        motion_interval: Duration::from_millis(100),
        rate_deadband_cdeg_s: 50,
        angle_deadband_cdeg: 20,
        yaw_positive_left: false,
        pitch_positive_down: false,
        ai_classes: [0, 1, 2, 3, 4, 5, 6, 7, 8, 9],
    };
}

/// Everything the bridge can be told.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Config {
    /// The flight controller's protocol (default SIYI).
    pub fc: FcProtocol,
    /// Baud rate of the FC link (default 115200; used to time bursts).
    pub fc_baud: u32,
    /// Baud rate of the pod link (default 115200).
    pub pod_baud: u32,
    /// SIYI identity.
    pub siyi: SiyiIdentity,
    /// Viewlink identity.
    pub viewlink: ViewlinkIdentity,
    /// GCU identity.
    pub gcu: GcuIdentity,
    /// The pod link.
    pub pod: PodConfig,
    /// RTC_IO pulses: period (10 s), width (50 ms).
    pub sync: SyncConfig,
    /// The UTC discipline.
    pub discipline: DisciplineConfig,
    /// The fix history.
    pub fixes: FixConfig,
    /// GPS time minus UTC, seconds (default 18, since 2017).
    pub leap_seconds: u8,
    /// The bridge stops the pod when the FC sends no motion for this long while the pod
    /// turns (default 500 ms): a cut FC cable must not leave the pod spinning.
    pub fc_silence_stop: Duration,
    /// The FC link is down when no valid frame arrives for this long (default 2 s).
    pub fc_link_timeout: Duration,
    /// K40T side: the bridge answers the pod's GPS request itself when the FC has not
    /// within this time (default 200 ms; `None`: never).
    pub k40t_geotag_fallback: Option<Duration>,
    /// Send the K40T 0x00030E with this time zone (minutes west of Greenwich; default 0:
    /// the pod keeps UTC).
    pub tz_minuteswest: i32,
}

impl Config {
    /// The documented defaults (SIYI flight controller, ZT30 identity).
    pub const DEFAULT: Self = Self {
        fc: FcProtocol::Siyi,
        fc_baud: 115_200,
        pod_baud: 115_200,
        siyi: SiyiIdentity::DEFAULT,
        viewlink: ViewlinkIdentity::DEFAULT,
        gcu: GcuIdentity::DEFAULT,
        pod: PodConfig::DEFAULT,
        sync: SyncConfig::DEFAULT,
        discipline: DisciplineConfig::DEFAULT,
        fixes: FixConfig::DEFAULT,
        leap_seconds: 18,
        fc_silence_stop: Duration::from_millis(500),
        fc_link_timeout: Duration::from_secs(2),
        k40t_geotag_fallback: Some(Duration::from_millis(200)),
        tz_minuteswest: 0,
    };

    /// The defaults with another FC protocol.
    #[must_use]
    pub const fn for_fc(fc: FcProtocol) -> Self {
        let mut c = Self::DEFAULT;
        c.fc = fc;
        c
    }
}

impl Default for Config {
    fn default() -> Self {
        Self::DEFAULT
    }
}
