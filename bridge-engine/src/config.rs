//! The bridge's configuration: one `Copy` struct with documented defaults
//! ([`Config::DEFAULT`]), its checks ([`Config::validate`], [`Limit`], [`ConfigError`])
//! and, with the `serde` feature, its configuration file.
//!
//! The firmware reads it at build time from `bridge-fw/bridge.toml` (its `build.rs`
//! deserializes the file into a [`Config`], validates it and writes it out as Rust
//! source); `gimbal bridge` reads the same file (`--config`) and lets its options
//! override the keys.
//!
//! # The configuration file
//! With the `serde` feature, [`Config`] implements `serde::Deserialize` from the file's
//! keys: every key is optional (absent: [`Config::DEFAULT`]'s value), an unknown key is
//! an error, times are whole milliseconds (`fc_link_timeout_ms`), texts are strings
//! (`siyi.hardware_id`). Fields without a key keep their default. The keys and their
//! ranges:
//!
//! | key | field | allowed |
//! | --- | --- | --- |
//! | `fc` | [`Config::fc`] | `"siyi"`, `"viewlink"`, `"gcu"`, `"k40t"` |
//! | `fc_baud`, `pod_baud`, `telemetry_baud` | [`Config::fc_baud`], [`Config::pod_baud`], [`Config::telemetry_baud`] | [`Limit::FC_BAUD`], [`Limit::POD_BAUD`], [`Limit::TELEMETRY_BAUD`] |
//! | `leap_seconds` | [`Config::leap_seconds`] | 0..=255 |
//! | `tz_minuteswest` | [`Config::tz_minuteswest`] | [`Limit::TZ_MINUTESWEST`] |
//! | `fc_link_timeout_ms` | [`Config::fc_link_timeout`] | [`Limit::FC_LINK_TIMEOUT_MS`] |
//! | `fc_silence_stop_ms` | [`Config::fc_silence_stop`] | [`Limit::FC_SILENCE_STOP_MS`] |
//! | `k40t_geotag_fallback_ms` | [`Config::k40t_geotag_fallback`] | [`Limit::K40T_GEOTAG_FALLBACK_MS`] or `"off"` |
//! | `[sync] period_ms`, `width_ms` | [`SyncConfig::period`], [`SyncConfig::width`] | [`Limit::SYNC_PERIOD_MS`], [`Limit::SYNC_WIDTH_MS`] |
//! | `[siyi] hardware_id` | [`SiyiIdentity::hardware_id`] | 12 ASCII characters ([`SiyiIdentity::parse_hardware_id`]) |
//! | `[siyi] max_zoom_x10` | [`SiyiIdentity::max_zoom_x10`] | [`Limit::SIYI_MAX_ZOOM_X10`] |
//! | `[viewlink] model` | [`ViewlinkIdentity::model`] | 1 to 10 printable ASCII characters ([`ViewlinkIdentity::parse_model`]) |
//! | `[gcu] hardware_x10`, `gimbal_code` | [`GcuIdentity`] | 0..=255 |
//! | `[gcu] resync_mark` | [`GcuIdentity::resync_mark`] | `true`, `false` |
//! | `[pod] yaw_positive_left`, `pitch_positive_down` | [`PodConfig`] | `true`, `false` |
//! | `[video] uri` | [`VideoConfig::uri`] | 0 to 160 printable ASCII characters ([`VideoConfig::parse_uri`]) |
//! | `[lens] visible_hfov_1x_cdeg`, `ir_hfov_cdeg`, `focal_length_min_um`, `focal_length_max_um`, `sensor_width_um`, `sensor_height_um`, `resolution_h`, `resolution_v` | [`LensConfig`] | [`Limit::LENS_HFOV_CDEG`] .. [`Limit::LENS_RESOLUTION_V`] |
//! | `[laser] periodic` | [`LaserConfig::periodic`] | `true`, `false` |
//! | `[laser] min_distance_cm`, `max_distance_cm` | [`LaserConfig`] | [`Limit::LASER_MIN_DISTANCE_CM`], [`Limit::LASER_MAX_DISTANCE_CM`] |
//! | `[discipline] bin_ms`, `min_bins`, `min_span_ms` | [`DisciplineConfig`] | [`Limit::DISCIPLINE_BIN_MS`], [`Limit::DISCIPLINE_MIN_BINS`], [`Limit::DISCIPLINE_MIN_SPAN_MS`] |
//! | `[mavlink] allow_destructive` | [`MavlinkConfig::allow_destructive`] | `true`, `false` |
//! | `signing` | [`Config::signing`] | `"off"`, `"sign"`, `"require"` ([`SigningMode`]) |
//! | `signing_key` | [`Config::signing_key`] | 64 hexadecimal characters, `""` for none ([`SigningKey::parse`]); needed unless `signing` is `"off"` |
//! | `signing_unsigned_telemetry` | [`Config::signing_unsigned_telemetry`] | `true`, `false` |
//! | `gcs_ids` | [`Config::gcs_ids`] | up to 8 ids, each [`Limit::GCS_ID`] ([`SystemIds`]) |
//! | `k40t_allow` | [`Config::k40t_allow`] | ids of [`GUARDED`](crate::access::GUARDED) requests ([`K40tAllow`]) |
//! | `autopilot_sysid` | [`Config::autopilot_sysid`] | [`Limit::AUTOPILOT_SYSID`] (0: learn) |
//! | `autopilot_forget_ms` | [`Config::autopilot_forget`] | [`Limit::AUTOPILOT_FORGET_MS`] |
//!
//! Deserializing checks types and texts; [`Config::validate`] checks the ranges. The keys
//! that were removed ([`REMOVED_KEYS`]: the firmware versions the legacy sides reported,
//! now the bridge's own, [`crate::version`]) are found by [`removed_key`], which the
//! readers of the file call first, so that an old file gets an error naming the key and
//! what replaced it. (The `Serialize` form of the nested configurations, for JSON output, keeps
//! the Rust field names and microseconds.)

use core::fmt;

mod sensors;

pub use sensors::{LaserConfig, LensConfig, URI_LEN, VideoConfig};

use super::access::{K40tAllow, SigningKey, SigningMode, SystemIds};
use super::discipline::{DisciplineConfig, PpsConfig};
use super::fixes::FixConfig;
use super::sync::SyncConfig;
use super::time::Duration;
use protocol_core::k40t::{Address, CrcCoverage};

protocol_core::wire_derive! {
    [Eq, Hash]
    /// The protocol the flight controller speaks (in the configuration file: `"siyi"`,
    /// `"viewlink"`, `"gcu"`, `"k40t"`).
    #[cfg_attr(feature = "serde", derive(serde::Deserialize), serde(rename_all(deserialize = "lowercase")))]
    #[cfg_attr(feature = "bake", derive(databake::Bake), databake(path = bridge_engine))]
    pub enum FcProtocol {
        /// SIYI SDK (ArduPilot `MNT1_TYPE` 8): the bridge acts as a SIYI gimbal.
        Siyi,
        /// Viewlink (ArduPilot `MNT1_TYPE` 11): the bridge acts as a Viewpro gimbal.
        Viewlink,
        /// GCU (ArduPilot `MNT1_TYPE` 14): the bridge acts as a gimbal control unit.
        Gcu,
        /// K40T itself: the bridge forwards, and owns RTC_IO.
        K40t,
        /// MAVLink 2 (ArduPilot `MNT1_TYPE` 6 + `CAM1_TYPE` 6, PX4 gimbal v2): the bridge is
        /// a gimbal device (component 154) and a camera (component 100). Needs the
        /// `mavlink` feature.
        Mavlink,
    }
}

protocol_core::wire_derive! {
    custom_serde [Eq]
    /// How the bridge presents itself to a SIYI flight controller.
    #[cfg_attr(
        feature = "serde",
        derive(serde::Deserialize),
        serde(default, deny_unknown_fields)
    )]
    #[cfg_attr(feature = "bake", derive(databake::Bake), databake(path = bridge_engine))]
    pub struct SiyiIdentity {
        /// The 12-character hardware id (0x02). Its first two characters select the model
        /// in ArduPilot: "7A" is the ZT30, for which ArduPilot enables 30x zoom, the laser
        /// rangefinder, lens selection and thermal min/max.
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::hardware_id"))]
        pub hardware_id: [u8; 12],
        /// Largest zoom reported by 0x16, times ten (the ZT30 reports 30x).
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::int"))]
        pub max_zoom_x10: u16,
    }
}

impl SiyiIdentity {
    /// A ZT30 ("7A"), zoom up to 30x. (Its firmware versions are the bridge's:
    /// [`crate::version`].)
    pub const DEFAULT: Self = Self {
        hardware_id: *b"7A0000000001",
        max_zoom_x10: 300,
    };

    /// The hardware id from its text (`siyi.hardware_id`): exactly 12 ASCII characters.
    ///
    /// # Errors
    /// Any other text ([`Problem::Text`]).
    pub fn parse_hardware_id(text: &str) -> Result<[u8; 12], ConfigError> {
        let bad = ConfigError::text("siyi.hardware_id", TextRule::Ascii(12));
        if text.is_ascii() {
            text.as_bytes().try_into().map_err(|_| bad)
        } else {
            Err(bad)
        }
    }
}

impl Default for SiyiIdentity {
    fn default() -> Self {
        Self::DEFAULT
    }
}

protocol_core::wire_derive! {
    custom_serde [Eq]
    /// How the bridge presents itself to a Viewlink flight controller.
    #[cfg_attr(
        feature = "serde",
        derive(serde::Deserialize),
        serde(default, deny_unknown_fields)
    )]
    #[cfg_attr(feature = "bake", derive(databake::Bake), databake(path = bridge_engine))]
    pub struct ViewlinkIdentity {
        /// Model text answered to the 0xE4 query (10 bytes, padded with 0x00; ArduPilot
        /// prints it).
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::model"))]
        pub model: [u8; 10],
    }
}

impl ViewlinkIdentity {
    /// Model "K40TBRIDGE". (The 0xD0 firmware text is the bridge's version:
    /// [`Version::viewlink_text`](crate::version::Version::viewlink_text).)
    pub const DEFAULT: Self = Self {
        model: *b"K40TBRIDGE",
    };

    /// The model from its text (`viewlink.model`): 1 to 10 printable ASCII characters
    /// (space included), padded with zeros.
    ///
    /// # Errors
    /// Any other text ([`Problem::Text`]).
    pub fn parse_model(text: &str) -> Result<[u8; 10], ConfigError> {
        let mut model = [0u8; 10];
        if text.len() > model.len() {
            return Err(ConfigError::text("viewlink.model", TextRule::Printable(10)));
        }
        for (slot, b) in model.iter_mut().zip(text.bytes()) {
            *slot = b;
        }
        if model_is_valid(&model) && !text.bytes().any(|b| b == 0) {
            Ok(model)
        } else {
            Err(ConfigError::text("viewlink.model", TextRule::Printable(10)))
        }
    }
}

impl Default for ViewlinkIdentity {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// 1 to 10 printable ASCII characters, then zeros.
fn model_is_valid(model: &[u8; 10]) -> bool {
    let len = model.iter().position(|&b| b == 0).unwrap_or(model.len());
    len > 0
        && model
            .iter()
            .take(len)
            .all(|&b| b.is_ascii_graphic() || b == b' ')
        && model.iter().skip(len).all(|&b| b == 0)
}

protocol_core::wire_derive! {
    custom_serde [Eq]
    /// How the bridge presents itself to a GCU flight controller (the sub data frame of
    /// every reply).
    #[cfg_attr(
        feature = "serde",
        derive(serde::Deserialize),
        serde(default, deny_unknown_fields)
    )]
    #[cfg_attr(feature = "bake", derive(databake::Bake), databake(path = bridge_engine))]
    pub struct GcuIdentity {
        /// Hardware version times ten (reply byte 38; ArduPilot prints it divided by 10).
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::int"))]
        pub hardware_x10: u8,
        /// Gimbal code (reply byte 40, the document's "Gimbal Code" table). The K40T is none
        /// of the listed models: 0xFF by default, which no table entry uses.
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::int"))]
        pub gimbal_code: u8,
        /// Send `8A 00` after every reply (default true): `AP_Mount_XFRobot`'s parser keeps
        /// skipped bytes in its buffer and, after one corrupted reply, can lose step with
        /// the replies for good; the pair puts it back in step at the end of every reply.
        pub resync_mark: bool,
    }
}

impl GcuIdentity {
    /// Hardware 1.0, gimbal code 0xFF (not a listed model), resync mark on. (The
    /// firmware version, byte 39, is the bridge's:
    /// [`Version::gcu_x10`](crate::version::Version::gcu_x10).)
    pub const DEFAULT: Self = Self {
        hardware_x10: 10,
        gimbal_code: 0xFF,
        resync_mark: true,
    };
}

impl Default for GcuIdentity {
    fn default() -> Self {
        Self::DEFAULT
    }
}

protocol_core::wire_derive! {
    custom_serde [Eq]
    /// The pod link: addresses, CRC coverage, retries, time-outs and rate limits. The
    /// configuration file sets the axis conventions only (`[pod] yaw_positive_left`,
    /// `pitch_positive_down`).
    #[cfg_attr(
        feature = "serde",
        derive(serde::Deserialize),
        serde(default, deny_unknown_fields)
    )]
    #[cfg_attr(feature = "bake", derive(databake::Bake), databake(path = bridge_engine))]
    pub struct PodConfig {
        /// The bridge's own address on the pod link: the flight controller's (0x02/0x01).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub own: Address,
        /// Where gimbal-class requests (0x000010..0x0000FF) go until the pod's reports
        /// show its address (default 0x03/0x01, section 3.1 of the document).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub gimbal: Address,
        /// Where camera requests go until learnt (default 0x04/0x01).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub camera: Address,
        /// CRC coverage until the pod's first report shows its own (default: MAVLink's).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub coverage: CrcCoverage,
        /// Learn addresses and coverage from the pod's reports (default true).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub learn: bool,
        /// Tries of a setting or camera action before giving up (default 3).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub tries: u8,
        /// Time between tries (default 200 ms).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub retry_interval: Duration,
        /// The pod is lost when no report arrives for this long (default 1 s).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub link_timeout: Duration,
        /// While lost, a version query is sent this often (default 1 s).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub probe_interval: Duration,
        /// A motion command is refreshed this often while the gimbal turns (default 1 s).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub motion_refresh: Duration,
        /// Least time between two motion commands (default 100 ms): a flight controller's
        /// 50 Hz control loop becomes at most 10 motion commands a second.
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub motion_interval: Duration,
        /// A rate change smaller than this (0.01 °/s) is no new command (default 50: 0.5 °/s).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub rate_deadband_cdeg_s: u16,
        /// An angle change smaller than this (0.01 °) is no new command (default 20).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
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
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub ai_classes: [u8; 10],
    }
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

impl Default for PodConfig {
    fn default() -> Self {
        Self::DEFAULT
    }
}

protocol_core::wire_derive! {
    custom_serde [Eq]
    /// The MAVLink side's choices.
    #[cfg_attr(
        feature = "serde",
        derive(serde::Deserialize),
        serde(default, deny_unknown_fields)
    )]
    #[cfg_attr(feature = "bake", derive(databake::Bake), databake(path = bridge_engine))]
    pub struct MavlinkConfig {
        /// Carry out the commands that erase (MAV_CMD_STORAGE_FORMAT: the pod's SD card;
        /// MAV_CMD_RESET_CAMERA_SETTINGS: the pod's factory reset, which also resets its IP
        /// address). Default false: they are DENIED, with an event.
        pub allow_destructive: bool,
    }
}

impl MavlinkConfig {
    /// Destructive commands refused.
    pub const DEFAULT: Self = Self {
        allow_destructive: false,
    };
}

impl Default for MavlinkConfig {
    fn default() -> Self {
        Self::DEFAULT
    }
}

protocol_core::wire_derive! {
    custom_serde [Eq]
    /// Everything the bridge can be told.
    #[cfg_attr(
        feature = "serde",
        derive(serde::Deserialize),
        serde(default, deny_unknown_fields)
    )]
    #[cfg_attr(feature = "bake", derive(databake::Bake), databake(path = bridge_engine))]
    pub struct Config {
        /// The flight controller's protocol (default SIYI).
        pub fc: FcProtocol,
        /// Baud rate of the FC link (default 115200; used to time bursts).
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::int"))]
        pub fc_baud: u32,
        /// Baud rate of the pod link (default 115200).
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::int"))]
        pub pod_baud: u32,
        /// Baud rate of the optional MAVLink telemetry link (default 115200; used to time
        /// its frames). The link needs no switch: it is used once an autopilot speaks on it.
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::int"))]
        pub telemetry_baud: u32,
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
        /// The MAVLink side.
        pub mavlink: MavlinkConfig,
        /// The pod's video stream (`[video]`).
        pub video: VideoConfig,
        /// The cameras' lens facts (`[lens]`).
        pub lens: LensConfig,
        /// The laser rangefinder (`[laser]`).
        pub laser: LaserConfig,
        /// The PPS input (a GNSS receiver's pulse per second): its polarity; the rest
        /// is fixed.
        pub pps: PpsConfig,
        /// The fix history (no key in the configuration file).
        #[cfg_attr(feature = "serde", serde(skip_deserializing))]
        pub fixes: FixConfig,
        /// GPS time minus UTC, seconds (default 18, since 2017).
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::int"))]
        pub leap_seconds: u8,
        /// The bridge stops the pod when the FC sends no motion for this long while the pod
        /// turns (default 500 ms): a cut FC cable must not leave the pod spinning.
        #[cfg_attr(
            feature = "serde",
            serde(rename = "fc_silence_stop_ms", deserialize_with = "de::ms")
        )]
        pub fc_silence_stop: Duration,
        /// The FC link is down when no valid frame arrives for this long (default 2 s).
        #[cfg_attr(
            feature = "serde",
            serde(rename = "fc_link_timeout_ms", deserialize_with = "de::ms")
        )]
        pub fc_link_timeout: Duration,
        /// K40T side: the bridge answers the pod's GPS request itself when the FC has not
        /// within this time (default 200 ms; `None`: never, `"off"` in the file).
        #[cfg_attr(
            feature = "serde",
            serde(
                rename = "k40t_geotag_fallback_ms",
                deserialize_with = "de::fallback_ms"
            )
        )]
        pub k40t_geotag_fallback: Option<Duration>,
        /// Send the K40T 0x00030E with this time zone (minutes west of Greenwich; default 0:
        /// the pod keeps UTC).
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::int"))]
        pub tz_minuteswest: i32,
        /// MAVLink 2 signing on the MAVLink side and the telemetry link (default off; see
        /// docs/src/security.md).
        pub signing: SigningMode,
        /// The signing key (default none; needed unless `signing` is off).
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::access::de::signing_key")
        )]
        pub signing_key: Option<SigningKey>,
        /// With `signing = "require"`: unsigned frames that command nothing (heartbeats,
        /// time, positions) are still read (default false: refused).
        pub signing_unsigned_telemetry: bool,
        /// MAVLink systems whose commands are taken besides the autopilot's (default 255
        /// and 245).
        #[cfg_attr(feature = "serde", serde(deserialize_with = "crate::access::de::gcs_ids"))]
        pub gcs_ids: SystemIds,
        /// The pod's destructive requests that may reach it (default none).
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::access::de::k40t_allow")
        )]
        pub k40t_allow: K40tAllow,
        /// The autopilot's MAVLink system id on the MAVLink side and the telemetry link
        /// (default 0: learnt from the first autopilot-type HEARTBEAT after power-on, then
        /// pinned; see docs/src/security.md).
        #[cfg_attr(feature = "serde", serde(deserialize_with = "de::int"))]
        pub autopilot_sysid: u8,
        /// With `autopilot_sysid` 0: a learnt autopilot is forgotten (the next
        /// autopilot-type HEARTBEAT is learnt) after this long without its HEARTBEAT
        /// (default 30 s).
        #[cfg_attr(
            feature = "serde",
            serde(rename = "autopilot_forget_ms", deserialize_with = "de::ms")
        )]
        pub autopilot_forget: Duration,
    }
}

impl Config {
    /// The documented defaults (SIYI flight controller, ZT30 identity).
    pub const DEFAULT: Self = Self {
        fc: FcProtocol::Siyi,
        fc_baud: 115_200,
        pod_baud: 115_200,
        telemetry_baud: 115_200,
        siyi: SiyiIdentity::DEFAULT,
        viewlink: ViewlinkIdentity::DEFAULT,
        gcu: GcuIdentity::DEFAULT,
        pod: PodConfig::DEFAULT,
        sync: SyncConfig::DEFAULT,
        discipline: DisciplineConfig::DEFAULT,
        mavlink: MavlinkConfig::DEFAULT,
        video: VideoConfig::DEFAULT,
        lens: LensConfig::DEFAULT,
        laser: LaserConfig::DEFAULT,
        pps: PpsConfig::DEFAULT,
        fixes: FixConfig::DEFAULT,
        leap_seconds: 18,
        fc_silence_stop: Duration::from_millis(500),
        fc_link_timeout: Duration::from_secs(2),
        k40t_geotag_fallback: Some(Duration::from_millis(200)),
        tz_minuteswest: 0,
        signing: SigningMode::Off,
        signing_key: None,
        signing_unsigned_telemetry: false,
        gcs_ids: SystemIds::DEFAULT,
        k40t_allow: K40tAllow::NONE,
        autopilot_sysid: 0,
        autopilot_forget: Duration::from_secs(30),
    };

    /// The defaults with another FC protocol.
    #[must_use]
    pub const fn for_fc(fc: FcProtocol) -> Self {
        let mut c = Self::DEFAULT;
        c.fc = fc;
        c
    }

    /// Checks every value that has a key in the configuration file against its range
    /// ([`Limit`]) and the texts against their rules. [`Config::DEFAULT`] passes. (The
    /// RTC_IO pulse is shorter than its period by the ranges alone.)
    ///
    /// # Errors
    /// The first key whose value is not allowed, with what is.
    pub fn validate(&self) -> Result<(), ConfigError> {
        Limit::FC_BAUD.check(self.fc_baud.into())?;
        Limit::POD_BAUD.check(self.pod_baud.into())?;
        Limit::TELEMETRY_BAUD.check(self.telemetry_baud.into())?;
        Limit::TZ_MINUTESWEST.check(self.tz_minuteswest.into())?;
        Limit::FC_LINK_TIMEOUT_MS.check_ms(self.fc_link_timeout)?;
        Limit::FC_SILENCE_STOP_MS.check_ms(self.fc_silence_stop)?;
        if let Some(after) = self.k40t_geotag_fallback {
            Limit::K40T_GEOTAG_FALLBACK_MS.check_ms(after)?;
        }
        Limit::SYNC_PERIOD_MS.check_ms(self.sync.period)?;
        Limit::SYNC_WIDTH_MS.check_ms(self.sync.width)?;
        Limit::AUTOPILOT_SYSID.check(self.autopilot_sysid.into())?;
        Limit::AUTOPILOT_FORGET_MS.check_ms(self.autopilot_forget)?;
        if !self.siyi.hardware_id.is_ascii() {
            return Err(ConfigError::text("siyi.hardware_id", TextRule::Ascii(12)));
        }
        Limit::SIYI_MAX_ZOOM_X10.check(self.siyi.max_zoom_x10.into())?;
        if !model_is_valid(&self.viewlink.model) {
            return Err(ConfigError::text("viewlink.model", TextRule::Printable(10)));
        }
        Limit::DISCIPLINE_BIN_MS.check_ms(self.discipline.bin_len)?;
        Limit::DISCIPLINE_MIN_BINS.check(self.discipline.min_bins.into())?;
        Limit::DISCIPLINE_MIN_SPAN_MS.check_ms(self.discipline.min_span)?;
        if !self.video.is_valid() {
            return Err(ConfigError::text("video.uri", TextRule::Uri));
        }
        let l = &self.lens;
        for (limit, value) in [
            (Limit::LENS_HFOV_CDEG, l.visible_hfov_1x_cdeg),
            (Limit::LENS_IR_HFOV_CDEG, l.ir_hfov_cdeg),
            (Limit::LENS_FOCAL_LENGTH_MIN_UM, l.focal_length_min_um),
            (Limit::LENS_FOCAL_LENGTH_MAX_UM, l.focal_length_max_um),
            (Limit::LENS_SENSOR_WIDTH_UM, l.sensor_width_um),
            (Limit::LENS_SENSOR_HEIGHT_UM, l.sensor_height_um),
            (Limit::LENS_RESOLUTION_H, l.resolution_h),
            (Limit::LENS_RESOLUTION_V, l.resolution_v),
            (Limit::LASER_MIN_DISTANCE_CM, self.laser.min_distance_cm),
            (Limit::LASER_MAX_DISTANCE_CM, self.laser.max_distance_cm),
        ] {
            limit.check(value.into())?;
        }
        if self.signing != SigningMode::Off && self.signing_key.is_none() {
            return Err(ConfigError {
                key: "signing_key",
                problem: Problem::Missing,
            });
        }
        for id in self.gcs_ids.as_slice() {
            Limit::GCS_ID.check((*id).into())?;
        }
        if usize::from(self.gcs_ids.len) > crate::access::MAX_GCS_IDS {
            return Err(ConfigError {
                key: "gcs_ids",
                problem: Problem::TooMany {
                    max: u8::try_from(crate::access::MAX_GCS_IDS).unwrap_or(u8::MAX),
                },
            });
        }
        Ok(())
    }
}

impl Default for Config {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// The configuration file's keys that were removed, each with what took its place.
pub const REMOVED_KEYS: [RemovedKey; 5] = {
    const BRIDGE: &str = "removed in 0.2.0: the bridge reports its own version";
    [
        RemovedKey::new("siyi", "camera_version", BRIDGE),
        RemovedKey::new("siyi", "gimbal_version", BRIDGE),
        RemovedKey::new("siyi", "zoom_version", BRIDGE),
        RemovedKey::new("viewlink", "firmware", BRIDGE),
        RemovedKey::new("gcu", "firmware_x10", BRIDGE),
    ]
};

protocol_core::wire_derive! {
    [Eq]
    /// A key the configuration file no longer has ([`REMOVED_KEYS`]). Displays as
    /// `siyi.camera_version: removed in 0.2.0: the bridge reports its own version (see
    /// docs/src/firmware/configuration.md#versions)`.
    pub struct RemovedKey {
        /// Its section (`siyi`), empty for a top-level key.
        pub section: &'static str,
        /// The key in its section (`camera_version`).
        pub key: &'static str,
        /// What took its place.
        pub replaced_by: &'static str,
    }
}

impl RemovedKey {
    const fn new(section: &'static str, key: &'static str, replaced_by: &'static str) -> Self {
        Self {
            section,
            key,
            replaced_by,
        }
    }
}

impl fmt::Display for RemovedKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if !self.section.is_empty() {
            write!(f, "{}.", self.section)?;
        }
        write!(
            f,
            "{}: {} (see docs/src/firmware/configuration.md#versions)",
            self.key, self.replaced_by
        )
    }
}

/// The first removed key a configuration file has: `has(section, key)` says whether the
/// file sets `key` in `section` (`""`: the top level). A reader of the file calls it
/// before deserializing, so that an old file gets the key and what replaced it rather
/// than "unknown field".
///
/// # Errors
/// The first removed key the file sets.
pub fn removed_key(has: impl Fn(&str, &str) -> bool) -> Result<(), RemovedKey> {
    REMOVED_KEYS
        .into_iter()
        .find(|r| has(r.section, r.key))
        .map_or(Ok(()), Err)
}

/// A time in whole milliseconds, as the configuration file gives it.
pub(crate) fn millis(d: Duration) -> i64 {
    i64::try_from(d.as_millis()).unwrap_or(i64::MAX)
}

protocol_core::wire_derive! {
    custom_serde [Eq]
    /// The integers a key of the configuration file allows: `min..=max`. [`Config::validate`]
    /// checks a [`Config`] against these; `gimbal bridge` checks its options with them.
    pub struct Limit {
        /// The key (`sync.period_ms`).
        pub key: &'static str,
        /// The least value allowed.
        pub min: i64,
        /// The greatest value allowed.
        pub max: i64,
    }
}

impl Limit {
    /// `fc_baud`: 1200..=4000000.
    pub const FC_BAUD: Self = Self::new("fc_baud", 1200, 4_000_000);
    /// `pod_baud`: 1200..=4000000.
    pub const POD_BAUD: Self = Self::new("pod_baud", 1200, 4_000_000);
    /// `telemetry_baud`: 1200..=4000000.
    pub const TELEMETRY_BAUD: Self = Self::new("telemetry_baud", 1200, 4_000_000);
    /// `tz_minuteswest`: -1440..=1440 (a day either way).
    pub const TZ_MINUTESWEST: Self = Self::new("tz_minuteswest", -1440, 1440);
    /// `fc_link_timeout_ms`: 100..=60000.
    pub const FC_LINK_TIMEOUT_MS: Self = Self::new("fc_link_timeout_ms", 100, 60_000);
    /// `fc_silence_stop_ms`: 50..=60000.
    pub const FC_SILENCE_STOP_MS: Self = Self::new("fc_silence_stop_ms", 50, 60_000);
    /// `k40t_geotag_fallback_ms`: 1..=10000 (or `"off"`).
    pub const K40T_GEOTAG_FALLBACK_MS: Self = Self::new("k40t_geotag_fallback_ms", 1, 10_000);
    /// `sync.period_ms`: 1000..=3600000 (1 s to an hour).
    pub const SYNC_PERIOD_MS: Self = Self::new("sync.period_ms", 1000, 3_600_000);
    /// `sync.width_ms`: 1..=900 (shorter than any period).
    pub const SYNC_WIDTH_MS: Self = Self::new("sync.width_ms", 1, 900);
    /// `siyi.max_zoom_x10`: 10..=65535.
    pub const SIYI_MAX_ZOOM_X10: Self = Self::new("siyi.max_zoom_x10", 10, 65_535);
    /// `discipline.bin_ms`: 500..=60000.
    pub const DISCIPLINE_BIN_MS: Self = Self::new("discipline.bin_ms", 500, 60_000);
    /// `discipline.min_bins`: 2..=32.
    pub const DISCIPLINE_MIN_BINS: Self = Self::new("discipline.min_bins", 2, 32);
    /// `discipline.min_span_ms`: 1000..=600000.
    pub const DISCIPLINE_MIN_SPAN_MS: Self = Self::new("discipline.min_span_ms", 1000, 600_000);
    /// Each of `gcs_ids`: 1..=255 (0 is MAVLink's broadcast id, no sender's).
    pub const GCS_ID: Self = Self::new("gcs_ids", 1, 255);
    /// `autopilot_sysid`: 0..=255 (0: learn the first autopilot heard).
    pub const AUTOPILOT_SYSID: Self = Self::new("autopilot_sysid", 0, 255);
    /// `autopilot_forget_ms`: 3000..=3600000 (3 s, the heartbeat's own time-out, to an
    /// hour).
    pub const AUTOPILOT_FORGET_MS: Self = Self::new("autopilot_forget_ms", 3000, 3_600_000);

    /// `lens.visible_hfov_1x_cdeg`: 0..=17999 (0: unknown).
    pub const LENS_HFOV_CDEG: Self = Self::new("lens.visible_hfov_1x_cdeg", 0, 17_999);
    /// `lens.ir_hfov_cdeg`: 0..=17999 (0: unknown).
    pub const LENS_IR_HFOV_CDEG: Self = Self::new("lens.ir_hfov_cdeg", 0, 17_999);
    /// `lens.focal_length_min_um`: 0..=1000000 (0: unknown).
    pub const LENS_FOCAL_LENGTH_MIN_UM: Self = Self::new("lens.focal_length_min_um", 0, 1_000_000);
    /// `lens.focal_length_max_um`: 0..=1000000 (0: unknown).
    pub const LENS_FOCAL_LENGTH_MAX_UM: Self = Self::new("lens.focal_length_max_um", 0, 1_000_000);
    /// `lens.sensor_width_um`: 0..=100000 (0: unknown).
    pub const LENS_SENSOR_WIDTH_UM: Self = Self::new("lens.sensor_width_um", 0, 100_000);
    /// `lens.sensor_height_um`: 0..=100000 (0: unknown).
    pub const LENS_SENSOR_HEIGHT_UM: Self = Self::new("lens.sensor_height_um", 0, 100_000);
    /// `lens.resolution_h`: 0..=65535 pixels (0: unknown).
    pub const LENS_RESOLUTION_H: Self = Self::new("lens.resolution_h", 0, 65_535);
    /// `lens.resolution_v`: 0..=65535 pixels (0: unknown).
    pub const LENS_RESOLUTION_V: Self = Self::new("lens.resolution_v", 0, 65_535);
    /// `laser.min_distance_cm`: 0..=65535.
    pub const LASER_MIN_DISTANCE_CM: Self = Self::new("laser.min_distance_cm", 0, 65_535);
    /// `laser.max_distance_cm`: 0..=65535.
    pub const LASER_MAX_DISTANCE_CM: Self = Self::new("laser.max_distance_cm", 0, 65_535);

    /// Every limit above.
    pub const ALL: [Self; 25] = [
        Self::FC_BAUD,
        Self::POD_BAUD,
        Self::TZ_MINUTESWEST,
        Self::FC_LINK_TIMEOUT_MS,
        Self::FC_SILENCE_STOP_MS,
        Self::K40T_GEOTAG_FALLBACK_MS,
        Self::SYNC_PERIOD_MS,
        Self::SYNC_WIDTH_MS,
        Self::SIYI_MAX_ZOOM_X10,
        Self::DISCIPLINE_BIN_MS,
        Self::DISCIPLINE_MIN_BINS,
        Self::DISCIPLINE_MIN_SPAN_MS,
        Self::LENS_HFOV_CDEG,
        Self::LENS_IR_HFOV_CDEG,
        Self::LENS_FOCAL_LENGTH_MIN_UM,
        Self::LENS_FOCAL_LENGTH_MAX_UM,
        Self::LENS_SENSOR_WIDTH_UM,
        Self::LENS_SENSOR_HEIGHT_UM,
        Self::LENS_RESOLUTION_H,
        Self::LENS_RESOLUTION_V,
        Self::LASER_MIN_DISTANCE_CM,
        Self::LASER_MAX_DISTANCE_CM,
        Self::GCS_ID,
        Self::AUTOPILOT_SYSID,
        Self::AUTOPILOT_FORGET_MS,
    ];

    pub(crate) const fn new(key: &'static str, min: i64, max: i64) -> Self {
        Self { key, min, max }
    }

    /// Whether `value` is in `min..=max`.
    ///
    /// # Errors
    /// [`Problem::OutOfRange`] when it is not.
    pub const fn check(self, value: i64) -> Result<(), ConfigError> {
        if value >= self.min && value <= self.max {
            Ok(())
        } else {
            Err(ConfigError {
                key: self.key,
                problem: Problem::OutOfRange {
                    value,
                    min: self.min,
                    max: self.max,
                },
            })
        }
    }

    /// Whether a time is in range, in whole milliseconds (a key ending in `_ms`).
    ///
    /// # Errors
    /// [`Problem::OutOfRange`] when it is not.
    pub fn check_ms(self, d: Duration) -> Result<(), ConfigError> {
        self.check(millis(d))
    }
}

// Every RTC_IO pulse the ranges allow is shorter than every period they allow.
const _: () = assert!(Limit::SYNC_WIDTH_MS.max < Limit::SYNC_PERIOD_MS.min);

protocol_core::wire_derive! {
    custom_serde [Eq]
    /// A value of the configuration that is not allowed: its key (as in the configuration
    /// file, `sync.period_ms`; `gimbal bridge`'s option is `--sync-period-ms`) and what is
    /// wrong. Displays as `fc_baud: 12 is out of range 1200..=4000000`.
    pub struct ConfigError {
        /// The key.
        pub key: &'static str,
        /// What is wrong with its value.
        pub problem: Problem,
    }
}

impl ConfigError {
    pub(crate) const fn text(key: &'static str, rule: TextRule) -> Self {
        Self {
            key,
            problem: Problem::Text(rule),
        }
    }
}

protocol_core::wire_derive! {
    custom_serde [Eq]
    /// What is wrong with a value of the configuration.
    pub enum Problem {
        /// A number outside `min..=max`.
        OutOfRange {
            /// The value given.
            value: i64,
            /// The least value allowed.
            min: i64,
            /// The greatest value allowed.
            max: i64,
        },
        /// A text that breaks its rule.
        Text(TextRule),
        /// A value needed by another key's value is absent.
        Missing,
        /// A list longer than allowed.
        TooMany {
            /// The most allowed.
            max: u8,
        },
        /// An id that is not one of the pod's destructive requests.
        NotGuarded {
            /// The id given.
            value: i64,
        },
        /// A value of another form than the key's (a setting given at run time: a text
        /// where a number is wanted, a list where a word is).
        Form(Form),
        /// An FC side this bridge does not have (not compiled in; `gimbal bridge`: not its
        /// `--fc`).
        NoSuchSide,
        /// A value that cannot be read back (the signing key is write-only).
        WriteOnly,
    }
}

protocol_core::wire_derive! {
    custom_serde [Eq]
    /// The form a setting's value must have ([`Problem::Form`]).
    pub enum Form {
        /// A whole number.
        Number,
        /// A whole number, or `"off"`.
        NumberOrOff,
        /// `true` or `false`.
        Bool,
        /// One of these names.
        OneOf(&'static [&'static str]),
        /// A text (quoted, or a word).
        Text,
        /// A list of whole numbers, `[a, b]`.
        List,
        /// The value's text itself is malformed.
        Syntax(crate::settings::value::ValueError),
    }
}

protocol_core::wire_derive! {
    custom_serde [Eq]
    /// What a text of the configuration must be.
    pub enum TextRule {
        /// Exactly this many ASCII characters.
        Ascii(u8),
        /// 1 to this many printable ASCII characters (space included).
        Printable(u8),
        /// 0 to 160 printable ASCII characters, no space (an address).
        Uri,
        /// Exactly this many hexadecimal characters.
        Hex(u8),
    }
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Problem::OutOfRange { value, min, max } => {
                write!(f, "{value} is out of range {min}..={max}")
            }
            Problem::Text(TextRule::Ascii(n)) => write!(f, "expected {n} ASCII characters"),
            Problem::Text(TextRule::Printable(n)) => {
                write!(f, "expected 1 to {n} printable ASCII characters")
            }
            Problem::Text(TextRule::Uri) => {
                write!(
                    f,
                    "expected up to {URI_LEN} printable ASCII characters, no space"
                )
            }
            Problem::Text(TextRule::Hex(n)) => write!(f, "expected {n} hexadecimal characters"),
            Problem::Missing => f.write_str("needed (signing is on)"),
            Problem::TooMany { max } => write!(f, "more than {max} values"),
            Problem::NotGuarded { value } => write!(
                f,
                "{value:#08x} is not one of the pod's destructive requests (docs/src/security.md)"
            ),
            Problem::Form(form) => form.fmt(f),
            Problem::NoSuchSide => f.write_str("not an FC side of this bridge"),
            Problem::WriteOnly => f.write_str("write-only: never read back"),
        }
    }
}

impl fmt::Display for Form {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Form::Number => f.write_str("expected a whole number"),
            Form::NumberOrOff => f.write_str("expected a whole number or \"off\""),
            Form::Bool => f.write_str("expected true or false"),
            Form::OneOf(names) => {
                f.write_str("expected one of")?;
                for (i, n) in names.iter().enumerate() {
                    let sep = if i == 0 { " " } else { ", " };
                    write!(f, "{sep}\"{n}\"")?;
                }
                Ok(())
            }
            Form::Text => f.write_str("expected a text"),
            Form::List => f.write_str("expected a list of whole numbers, [a, b]"),
            Form::Syntax(e) => e.fmt(f),
        }
    }
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.key, self.problem)
    }
}

impl core::error::Error for ConfigError {}

/// The configuration file's forms of the fields that differ from the Rust types: times
/// in ms, texts.
#[cfg(feature = "serde")]
pub(crate) mod de {
    use core::fmt;

    use serde::Deserialize as _;
    use serde::de::{Deserializer, Error, Unexpected, Visitor};

    use super::{ConfigError, Duration, Problem, SiyiIdentity, VideoConfig, ViewlinkIdentity};

    /// An integer type's range.
    pub(crate) trait Int: TryFrom<i64> {
        const MIN: i64;
        const MAX: i64;
    }

    macro_rules! int {
        ($($t:ty),*) => {$(
            impl Int for $t {
                const MIN: i64 = <$t>::MIN as i64;
                const MAX: i64 = <$t>::MAX as i64;
            }
        )*};
    }
    int!(u8, u16, u32, i32);

    /// An integer, out of the field type's range an error that names the range
    /// (`300 is out of range 0..=255`; [`Config::validate`](super::Config::validate)
    /// checks the narrower ranges of the keys that have a [`Limit`](super::Limit)).
    pub(crate) fn int<'de, D: Deserializer<'de>, T: Int>(d: D) -> Result<T, D::Error> {
        let value = i64::deserialize(d)?;
        T::try_from(value).map_err(|_| {
            D::Error::custom(Problem::OutOfRange {
                value,
                min: T::MIN,
                max: T::MAX,
            })
        })
    }

    /// Whole milliseconds.
    pub(crate) fn ms<'de, D: Deserializer<'de>>(d: D) -> Result<Duration, D::Error> {
        let value = i64::deserialize(d)?;
        u64::try_from(value)
            .map(Duration::from_millis)
            .map_err(|_| D::Error::invalid_value(Unexpected::Signed(value), &"a time in ms"))
    }

    /// Whole milliseconds, or `"off"`: `None`.
    pub(crate) fn fallback_ms<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<Duration>, D::Error> {
        struct Fallback;
        impl Visitor<'_> for Fallback {
            type Value = Option<Duration>;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a time in ms or \"off\"")
            }
            fn visit_u64<E: Error>(self, v: u64) -> Result<Self::Value, E> {
                Ok(Some(Duration::from_millis(v)))
            }
            fn visit_i64<E: Error>(self, v: i64) -> Result<Self::Value, E> {
                u64::try_from(v)
                    .map(|v| Some(Duration::from_millis(v)))
                    .map_err(|_| E::invalid_value(Unexpected::Signed(v), &self))
            }
            fn visit_str<E: Error>(self, v: &str) -> Result<Self::Value, E> {
                if v.eq_ignore_ascii_case("off") {
                    Ok(None)
                } else {
                    Err(E::invalid_value(Unexpected::Str(v), &self))
                }
            }
        }
        d.deserialize_any(Fallback)
    }

    /// A text, turned into the field's bytes by `parse` (its error without the key: the
    /// deserializer names where it is).
    struct Text<F>(F, &'static str);

    impl<T, F: FnOnce(&str) -> Result<T, ConfigError>> Visitor<'_> for Text<F> {
        type Value = T;
        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str(self.1)
        }
        fn visit_str<E: Error>(self, v: &str) -> Result<T, E> {
            (self.0)(v).map_err(|e| E::custom(e.problem))
        }
    }

    pub(crate) fn hardware_id<'de, D: Deserializer<'de>>(d: D) -> Result<[u8; 12], D::Error> {
        d.deserialize_str(Text(SiyiIdentity::parse_hardware_id, "12 ASCII characters"))
    }

    pub(crate) fn uri<'de, D: Deserializer<'de>>(d: D) -> Result<[u8; super::URI_LEN], D::Error> {
        d.deserialize_str(Text(
            VideoConfig::parse_uri,
            "up to 160 printable ASCII characters, no space",
        ))
    }

    pub(crate) fn model<'de, D: Deserializer<'de>>(d: D) -> Result<[u8; 10], D::Error> {
        d.deserialize_str(Text(
            ViewlinkIdentity::parse_model,
            "1 to 10 printable ASCII characters",
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    extern crate std;
    use std::string::ToString;

    #[test]
    fn the_defaults_are_valid_and_their_texts_parse_back() {
        assert_eq!(Config::DEFAULT.validate(), Ok(()));
        assert_eq!(
            ViewlinkIdentity::parse_model("K40TBRIDGE"),
            Ok(ViewlinkIdentity::DEFAULT.model)
        );
        assert_eq!(
            SiyiIdentity::parse_hardware_id("7A0000000001"),
            Ok(SiyiIdentity::DEFAULT.hardware_id)
        );
    }

    #[test]
    fn limits_name_the_key_and_the_range() {
        for limit in Limit::ALL {
            assert_eq!(limit.check(limit.min), Ok(()));
            assert_eq!(limit.check(limit.max), Ok(()));
            for bad in [limit.min - 1, limit.max + 1] {
                let e = limit.check(bad).unwrap_err();
                assert_eq!(e.key, limit.key);
                assert_eq!(
                    e.to_string(),
                    std::format!(
                        "{}: {bad} is out of range {}..={}",
                        limit.key,
                        limit.min,
                        limit.max
                    )
                );
            }
        }
        let mut c = Config::DEFAULT;
        c.fc_baud = 12;
        assert_eq!(
            c.validate().unwrap_err().to_string(),
            "fc_baud: 12 is out of range 1200..=4000000"
        );
    }

    #[test]
    // One spoilt Config per key, on the test thread's stack.
    #[allow(clippy::large_stack_arrays)]
    fn validate_checks_every_key() {
        fn spoilt(spoil: impl FnOnce(&mut Config)) -> Config {
            let mut c = Config::DEFAULT;
            spoil(&mut c);
            c
        }
        let cases = [
            ("fc_baud", spoilt(|c| c.fc_baud = 1199)),
            ("pod_baud", spoilt(|c| c.pod_baud = 4_000_001)),
            ("telemetry_baud", spoilt(|c| c.telemetry_baud = 1199)),
            ("tz_minuteswest", spoilt(|c| c.tz_minuteswest = -1441)),
            ("fc_link_timeout_ms", spoilt(|c| c.fc_link_timeout = ms(99))),
            (
                "fc_silence_stop_ms",
                spoilt(|c| c.fc_silence_stop = ms(60_001)),
            ),
            (
                "k40t_geotag_fallback_ms",
                spoilt(|c| c.k40t_geotag_fallback = Some(ms(0))),
            ),
            ("sync.period_ms", spoilt(|c| c.sync.period = ms(999))),
            ("sync.width_ms", spoilt(|c| c.sync.width = ms(0))),
            ("siyi.hardware_id", spoilt(|c| c.siyi.hardware_id[3] = 0xB0)),
            ("siyi.max_zoom_x10", spoilt(|c| c.siyi.max_zoom_x10 = 9)),
            ("viewlink.model", spoilt(|c| c.viewlink.model = [0; 10])),
            (
                "discipline.bin_ms",
                spoilt(|c| c.discipline.bin_len = ms(499)),
            ),
            (
                "discipline.min_bins",
                spoilt(|c| c.discipline.min_bins = 33),
            ),
            (
                "discipline.min_span_ms",
                spoilt(|c| c.discipline.min_span = ms(600_001)),
            ),
            ("video.uri", spoilt(|c| c.video.uri[0] = b' ')),
            (
                "lens.visible_hfov_1x_cdeg",
                spoilt(|c| c.lens.visible_hfov_1x_cdeg = 18_000),
            ),
            (
                "lens.ir_hfov_cdeg",
                spoilt(|c| c.lens.ir_hfov_cdeg = 18_000),
            ),
            (
                "lens.focal_length_min_um",
                spoilt(|c| c.lens.focal_length_min_um = 1_000_001),
            ),
            (
                "lens.focal_length_max_um",
                spoilt(|c| c.lens.focal_length_max_um = 1_000_001),
            ),
            (
                "lens.sensor_width_um",
                spoilt(|c| c.lens.sensor_width_um = 100_001),
            ),
            (
                "lens.sensor_height_um",
                spoilt(|c| c.lens.sensor_height_um = 100_001),
            ),
            (
                "lens.resolution_h",
                spoilt(|c| c.lens.resolution_h = 65_536),
            ),
            (
                "lens.resolution_v",
                spoilt(|c| c.lens.resolution_v = 65_536),
            ),
            (
                "laser.min_distance_cm",
                spoilt(|c| c.laser.min_distance_cm = 65_536),
            ),
            (
                "laser.max_distance_cm",
                spoilt(|c| c.laser.max_distance_cm = 65_536),
            ),
        ];
        for (key, c) in cases {
            assert_eq!(c.validate().map_err(|e| e.key), Err(key));
        }
        let c = spoilt(|c| c.k40t_geotag_fallback = None);
        assert_eq!(c.validate(), Ok(()));
    }

    fn ms(ms: u64) -> Duration {
        Duration::from_millis(ms)
    }

    #[test]
    fn the_video_uri_is_printable_ascii_without_spaces() {
        let uri = VideoConfig::parse_uri("rtsp://10.0.0.9:558/live/single").unwrap();
        let v = VideoConfig { uri };
        assert_eq!(
            v.configured_uri(),
            Some(&b"rtsp://10.0.0.9:558/live/single"[..])
        );
        assert_eq!(VideoConfig::DEFAULT.configured_uri(), None);
        assert_eq!(VideoConfig::parse_uri(""), Ok([0; URI_LEN]));
        for bad in ["rtsp://a b", "caf\u{e9}", &"x".repeat(161)] {
            assert_eq!(
                VideoConfig::parse_uri(bad).unwrap_err().to_string(),
                "video.uri: expected up to 160 printable ASCII characters, no space"
            );
        }
        let full = "x".repeat(160);
        assert_eq!(VideoConfig::parse_uri(&full).map(|u| u[159]), Ok(b'x'));
    }

    #[test]
    fn a_removed_key_names_what_replaced_it() {
        assert_eq!(removed_key(|_, _| false), Ok(()));
        let e = removed_key(|section, key| (section, key) == ("viewlink", "firmware"));
        assert_eq!(
            e.map_err(|e| e.to_string()),
            Err(
                "viewlink.firmware: removed in 0.2.0: the bridge reports its own version \
                 (see docs/src/firmware/configuration.md#versions)"
                    .into()
            )
        );
    }

    #[test]
    fn texts() {
        assert_eq!(
            ViewlinkIdentity::parse_model("A B"),
            Ok(*b"A B\0\0\0\0\0\0\0")
        );
        for bad in ["", "ELEVENCHARS", "tab\there", "nul\0", "caf\u{e9}"] {
            assert_eq!(
                ViewlinkIdentity::parse_model(bad).unwrap_err().to_string(),
                "viewlink.model: expected 1 to 10 printable ASCII characters",
                "{bad:?}"
            );
        }
        for bad in ["7A", "7A00000000012", "7A000000000\u{e9}"] {
            assert_eq!(
                SiyiIdentity::parse_hardware_id(bad)
                    .unwrap_err()
                    .to_string(),
                "siyi.hardware_id: expected 12 ASCII characters",
                "{bad:?}"
            );
        }
    }
}
