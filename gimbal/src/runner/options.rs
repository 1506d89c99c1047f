//! The options of the commands the runner carries out (`gimbal bridge`, `sim-fc`,
//! `sim-pod`), as `clap` derive types the command line ([`crate::cli`]) embeds; the
//! parsing of port specifications and option values lives with the types they produce
//! ([`PortSpec`], [`RtcSpec`], [`parse_hardware_id`], ...) so that it is unit-tested.
//!
//! The bridge's configuration options ([`ConfigArgs`]) are the keys of the configuration
//! file (`bridge_engine::Config`'s, as in `bridge-fw/bridge.toml`): each names
//! its key (`#[serde(rename)]`), is checked with the key's own parser or range
//! (`bridge_engine::config::Limit`), and serializes into the keys it overrides
//! (`runner::bridge::config_of`).

use std::path::PathBuf;

use bridge_engine::config::Limit;
use bridge_engine::config::VideoConfig;
use bridge_engine::{FcProtocol, SiyiIdentity, ViewlinkIdentity};
use clap::{Args, ValueEnum};
use serde::{Serialize, Serializer};

use crate::runner::pin::RtcSpec;
use crate::runner::port::PortSpec;
use crate::runner::pps::PpsSpec;
use crate::sim::faults::Faults;
use crate::sim::pod::AckSeq;

/// The flight controller's protocol on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
#[value(rename_all = "lower")]
pub enum Fc {
    /// SIYI SDK (ArduPilot MNT1_TYPE 8): the bridge acts as a SIYI gimbal.
    Siyi,
    /// Viewlink (ArduPilot MNT1_TYPE 11): the bridge acts as a Viewpro gimbal.
    Viewlink,
    /// XF Robot GCU (ArduPilot MNT1_TYPE 14): the bridge acts as a GCU.
    Gcu,
    /// K40T itself: the bridge forwards and owns RTC_IO.
    K40t,
    /// MAVLink 2 (ArduPilot MNT1_TYPE 6 + CAM1_TYPE 6, PX4 gimbal v2): the bridge is a
    /// gimbal device and a camera.
    Mavlink,
}

impl Fc {
    /// The engine's protocol.
    #[must_use]
    pub const fn protocol(self) -> FcProtocol {
        match self {
            Fc::Siyi => FcProtocol::Siyi,
            Fc::Viewlink => FcProtocol::Viewlink,
            Fc::Gcu => FcProtocol::Gcu,
            Fc::K40t => FcProtocol::K40t,
            Fc::Mavlink => FcProtocol::Mavlink,
        }
    }

    /// The name on the command line and in events.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Fc::Siyi => "siyi",
            Fc::Viewlink => "viewlink",
            Fc::Gcu => "gcu",
            Fc::K40t => "k40t",
            Fc::Mavlink => "mavlink",
        }
    }
}

/// How events are printed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Default)]
pub enum EventFormat {
    /// One line of text per event.
    #[default]
    Human,
    /// One JSON object per line: `{"t_us": ..., "event": "...", ...}`.
    Json,
}

/// The sequence number of the simulated pod's ACKs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Default)]
pub enum AckSeqArg {
    /// The request's sequence number, echoed (the counter does not move).
    Echo,
    /// The pod's own counter, as for every message it sends (the document's reading).
    #[default]
    Own,
}

impl AckSeqArg {
    /// The simulator's setting.
    #[must_use]
    pub const fn ack_seq(self) -> AckSeq {
        match self {
            AckSeqArg::Echo => AckSeq::Echo,
            AckSeqArg::Own => AckSeq::OwnCounter,
        }
    }
}

/// The help text after the options of the commands with ports: PORT, then FAULTS.
const PORT_AND_FAULTS_HELP: &str = concat!(
    "PORT: a serial device `/dev/ttyUSB0[:BAUD]` (or `serial:PATH[:BAUD]`), `tcp:HOST:PORT` \
(connect, reconnect when lost), `tcp-listen:[HOST:]PORT` (accept one connection at a time; \
port 0 picks a free one, printed in a `port_listening` event), `udp:HOST:PORT` (send there, \
knocking with an empty datagram each second until someone speaks; answer the peer that \
spoke last), `udp-listen:[HOST:]PORT` (bind; answer the peer that spoke last), or `sim`. \
UDP carries any FC protocol (a datagram is read as part of a byte stream)",
    "\n\n",
    "FAULTS: a faulty cable, `ber=RATE,drop=RATE,garbage=RATE,seed=N` (any subset): each bit \
flipped with probability ber, each byte lost with probability drop, a random byte inserted \
before a byte with probability garbage, reproducibly from the seed (default 1), in both \
directions (each with its own generator); `none`: a good cable"
);

/// `gimbal bridge`.
#[derive(Debug, Args)]
#[command(after_long_help = PORT_AND_FAULTS_HELP)]
pub struct BridgeArgs {
    /// The flight controller's protocol.
    #[arg(long, value_enum, ignore_case = true)]
    pub fc: Fc,
    /// The flight controller's port (`sim`: the simulated ArduPilot driver of --fc).
    #[arg(long, value_name = "PORT", value_parser = parse_port)]
    pub fc_port: PortSpec,
    /// The pod's port (`sim`: the simulated K40T pod, with RTC_IO wired to it).
    #[arg(long, value_name = "PORT", value_parser = parse_port)]
    pub pod_port: PortSpec,
    /// The autopilot's MAVLink 2 telemetry port (ArduPilot `SERIALn_PROTOCOL 2`, PX4
    /// `MAV_n_CONFIG`), beside the FC link of any --fc (with mavlink: when the FC link
    /// gives no time, as PX4 1.16's in mode Gimbal): time (TIMESYNC, SYSTEM_TIME) and
    /// fixes come from it while it gives them. A serial device, TCP or UDP port (not
    /// `sim`; on a companion computer, a UDP endpoint of mavlink-router or MAVProxy).
    /// Default: no telemetry link.
    #[arg(long, value_name = "PORT", value_parser = parse_telemetry_port)]
    pub telemetry_port: Option<PortSpec>,
    /// The RTC_IO output: `gpiochip0:LINE[:active-low]` (a GPIO line through the
    /// kernel's character device), `log` (no pin; the edges are events),
    /// `tcp:HOST:PORT` or `tcp-listen:[HOST:]PORT` (each edge as one byte, `1` rising,
    /// `0` falling: for `gimbal sim-pod --rtc-io` and emulators). Edges are always
    /// printed as `rtc_io` events.
    #[arg(long, value_name = "RTC", default_value = "log", value_parser = parse_rtc)]
    pub rtc_io: RtcSpec,
    /// A GNSS module's pulse per second (its timepulse) to discipline the bridge's clock:
    /// `gpiochipN:LINE[:active-low]` (a GPIO line's edge events, time-stamped by the
    /// kernel), `/dev/ppsN` (the kernel PPS interface), `tcp:HOST:PORT` or
    /// `tcp-listen:[HOST:]PORT` (a test source for emulators: one byte an edge), or `sim`
    /// (the simulated GNSS module, with --fc-port sim). The FC's UTC names the seconds.
    /// Default: no PPS.
    #[arg(long, value_name = "SOURCE", value_parser = parse_pps)]
    pub pps: Option<PpsSpec>,
    /// Write a photo event file: one CSV row per photo the pod geotagged (UTC, GPS week
    /// and seconds of week, latitude, longitude, altitude, attitude), for PPK and
    /// photogrammetry tools (docs/src/linux-bridge.md).
    #[arg(long, value_name = "FILE")]
    pub photo_events: Option<PathBuf>,
    /// Event output format.
    #[arg(long, value_enum, default_value_t = EventFormat::Human)]
    pub events: EventFormat,
    /// Also print every frame in both directions, decoded as `gimbal decode --json`
    /// prints it (event `frame`).
    #[arg(long)]
    pub trace: bool,
    /// Stop after this many seconds (default: run until Ctrl-C).
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    pub seconds: Option<f64>,
    /// Print the counters (event `counters`) every this many seconds (default: only at
    /// the end).
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    pub counters_every: Option<f64>,
    /// A line is idle (a burst ends, a broken frame is given up) after this silence, ms
    /// [default: 8]. Keep it below the FC's gap between bursts (GCU: 12 ms); for a USB
    /// adapter, lower its latency timer (FTDI: `echo 1 >
    /// /sys/bus/usb-serial/devices/ttyUSB0/latency_timer`).
    #[arg(long, value_name = "MS", value_parser = clap::value_parser!(u64).range(1..=1000))]
    pub idle_ms: Option<u64>,
    /// With `--fc-port sim`: the simulated flight controller takes a picture every this
    /// many seconds (each one is geotagged by the bridge).
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    pub sim_photo_every: Option<f64>,
    /// With `--pod-port sim`: the sequence number of the simulated pod's ACKs.
    #[arg(long, value_enum, value_name = "SEQ", default_value_t = AckSeqArg::Own)]
    pub sim_pod_ack_seq: AckSeqArg,
    /// Make the FC cable faulty (see FAULTS below), whatever the port (`sim` too).
    #[arg(long, value_name = "FAULTS", value_parser = parse_faults)]
    pub fc_faults: Option<Faults>,
    /// Make the pod cable faulty (see FAULTS below; not RTC_IO).
    #[arg(long, value_name = "FAULTS", value_parser = parse_faults)]
    pub pod_faults: Option<Faults>,
    /// Where the bridge keeps what it must remember across restarts (the settings set on
    /// its console or by PARAM_SET, the MAVLink signing timestamp, a key set by
    /// SETUP_SIGNING): the file DIR/state.bin, written atomically
    /// [default: $XDG_STATE_HOME/k40t-bridge, else ~/.local/state/k40t-bridge].
    #[arg(long, value_name = "DIR")]
    pub state_dir: Option<PathBuf>,
    /// Serve the bridge's console (docs/src/console.md; `gimbal config --port`) on this
    /// port: a serial device, `tcp:HOST:PORT` or `tcp-listen:[HOST:]PORT`. What it sets
    /// is kept in --state-dir and overrides --config and the options at the next start.
    #[arg(long, value_name = "PORT", value_parser = parse_port)]
    pub console: Option<PortSpec>,
    /// The bridge's configuration from a file: the firmware's TOML
    /// (`bridge-fw/bridge.toml`, every key optional). The options below, a port's
    /// `:BAUD` and --fc override its keys (its `fc` is not used).
    #[arg(long = "config", value_name = "FILE")]
    pub config_file: Option<PathBuf>,
    /// The bridge's configuration (the keys of bridge-fw/bridge.toml).
    #[command(flatten)]
    pub config: ConfigArgs,
}

/// The bridge's configuration: every key of `bridge-fw/bridge.toml` (serialized under
/// that key: what `--config FILE` says is overridden), same ranges, same defaults
/// (`bridge_engine::Config::DEFAULT`).
#[derive(Debug, Args, Default, Serialize)]
#[command(next_help_heading = "Bridge configuration (the keys of bridge-fw/bridge.toml)")]
pub struct ConfigArgs {
    /// FC link baud rate, 8N1 [default: the FC port's :BAUD, else 115200].
    #[arg(long, value_name = "BAUD", value_parser = ranged::<u32>(Limit::FC_BAUD))]
    #[serde(skip)] // with the port's :BAUD (runner::bridge::config_of)
    pub fc_baud: Option<u32>,
    /// Pod link baud rate, 8N1 [default: the pod port's :BAUD, else 115200].
    #[arg(long, value_name = "BAUD", value_parser = ranged::<u32>(Limit::POD_BAUD))]
    #[serde(skip)]
    pub pod_baud: Option<u32>,
    /// Telemetry link baud rate, 8N1 [default: the telemetry port's :BAUD, else 115200].
    #[arg(long, value_name = "BAUD", value_parser = ranged::<u32>(Limit::TELEMETRY_BAUD))]
    #[serde(skip)]
    pub telemetry_baud: Option<u32>,
    /// GPS time minus UTC, seconds [default: 18].
    #[arg(long, value_name = "S", value_parser = clap::value_parser!(u8))]
    #[serde(rename = "leap_seconds")]
    pub leap_seconds: Option<u8>,
    /// Time zone sent to the pod in 0x00030E, minutes west of Greenwich (0: the pod
    /// keeps UTC) [default: 0].
    #[arg(long, value_name = "MIN", allow_negative_numbers = true,
          value_parser = ranged::<i32>(Limit::TZ_MINUTESWEST))]
    #[serde(rename = "tz_minuteswest")]
    pub tz_minuteswest: Option<i32>,
    /// The FC link is down after this long without a valid frame, ms [default: 2000].
    #[arg(long, value_name = "MS", value_parser = ranged::<u64>(Limit::FC_LINK_TIMEOUT_MS))]
    #[serde(rename = "fc_link_timeout_ms")]
    pub fc_link_timeout_ms: Option<u64>,
    /// The pod is stopped when the FC sends no motion for this long while it turns, ms
    /// [default: 500].
    #[arg(long, value_name = "MS", value_parser = ranged::<u64>(Limit::FC_SILENCE_STOP_MS))]
    #[serde(rename = "fc_silence_stop_ms")]
    pub fc_silence_stop_ms: Option<u64>,
    /// K40T FC: the bridge answers the pod's GPS request itself when the FC has not
    /// within this time, ms, or `off` [default: 200].
    #[arg(long, value_name = "MS|off", value_parser = parse_fallback)]
    #[serde(rename = "k40t_geotag_fallback_ms")]
    pub k40t_geotag_fallback_ms: Option<Fallback>,
    /// RTC_IO pulse period, ms: one edge every period, on the UTC grid [default: 10000].
    #[arg(long, value_name = "MS", value_parser = ranged::<u64>(Limit::SYNC_PERIOD_MS))]
    #[serde(rename = "sync.period_ms")]
    pub sync_period_ms: Option<u64>,
    /// RTC_IO pulse width, ms [default: 50].
    #[arg(long, value_name = "MS", value_parser = ranged::<u64>(Limit::SYNC_WIDTH_MS))]
    #[serde(rename = "sync.width_ms")]
    pub sync_width_ms: Option<u64>,
    /// SIYI: the 12-character hardware id; its first two characters pick the model in
    /// ArduPilot ("7A" = ZT30: 30x zoom, laser, lens, thermal) [default: 7A0000000001].
    #[arg(long, value_name = "ID", value_parser = checked(parse_hardware_id))]
    #[serde(rename = "siyi.hardware_id")]
    pub siyi_hardware_id: Option<String>,
    /// SIYI: largest zoom reported, times ten [default: 300].
    #[arg(long, value_name = "X10", value_parser = ranged::<u16>(Limit::SIYI_MAX_ZOOM_X10))]
    #[serde(rename = "siyi.max_zoom_x10")]
    pub siyi_max_zoom_x10: Option<u16>,
    /// Viewlink: the model text answered to the 0xE4 query, up to 10 ASCII characters
    /// [default: K40TBRIDGE].
    #[arg(long, value_name = "TEXT", value_parser = checked(parse_model))]
    #[serde(rename = "viewlink.model")]
    pub viewlink_model: Option<String>,
    /// GCU: hardware version times ten [default: 10].
    #[arg(long, value_name = "X10", value_parser = clap::value_parser!(u8))]
    #[serde(rename = "gcu.hardware_x10")]
    pub gcu_hardware_x10: Option<u8>,
    /// GCU: gimbal code, reply byte 40 (the document's "Gimbal Code" table; the K40T is
    /// none of its models) [default: 255].
    #[arg(long, value_name = "CODE", value_parser = clap::value_parser!(u8))]
    #[serde(rename = "gcu.gimbal_code")]
    pub gcu_gimbal_code: Option<u8>,
    /// GCU: send no `8A 00` after each reply (it puts ArduPilot's XF Robot parser back in
    /// step after a corrupted reply).
    #[arg(long)]
    #[serde(
        rename = "gcu.resync_mark",
        serialize_with = "negated",
        skip_serializing_if = "is_false"
    )]
    pub gcu_no_resync_mark: bool,
    /// The pod reports yaw positive to the left.
    #[arg(long)]
    #[serde(rename = "pod.yaw_positive_left", skip_serializing_if = "is_false")]
    pub pod_yaw_positive_left: bool,
    /// The pod reports pitch positive down.
    #[arg(long)]
    #[serde(rename = "pod.pitch_positive_down", skip_serializing_if = "is_false")]
    pub pod_pitch_positive_down: bool,
    /// MAVLink side: carry out the commands that erase (storage format: the pod's SD card;
    /// camera reset: the pod's factory reset, its IP address included); without it they
    /// are refused (DENIED).
    #[arg(long)]
    #[serde(rename = "mavlink.allow_destructive", skip_serializing_if = "is_false")]
    pub mavlink_allow_destructive: bool,
    /// MAVLink: the video stream's address, up to 160 printable ASCII characters
    /// [default: empty, `rtsp://IP:558/live/single` with the IP the pod reports].
    #[arg(long, value_name = "URI", value_parser = checked(parse_uri))]
    #[serde(rename = "video.uri")]
    pub video_uri: Option<String>,
    /// The visible camera's horizontal field of view at 1x, 0.01° [default: 0, unknown].
    #[arg(long, value_name = "CDEG", value_parser = ranged::<u32>(Limit::LENS_HFOV_CDEG))]
    #[serde(rename = "lens.visible_hfov_1x_cdeg")]
    pub lens_visible_hfov_1x_cdeg: Option<u32>,
    /// The thermal camera's horizontal field of view without digital zoom, 0.01°
    /// [default: 0, unknown].
    #[arg(long, value_name = "CDEG", value_parser = ranged::<u32>(Limit::LENS_IR_HFOV_CDEG))]
    #[serde(rename = "lens.ir_hfov_cdeg")]
    pub lens_ir_hfov_cdeg: Option<u32>,
    /// The visible camera's shortest focal length, µm [default: 0, unknown].
    #[arg(long, value_name = "UM", value_parser = ranged::<u32>(Limit::LENS_FOCAL_LENGTH_MIN_UM))]
    #[serde(rename = "lens.focal_length_min_um")]
    pub lens_focal_length_min_um: Option<u32>,
    /// Its longest optical focal length, µm [default: 0, unknown].
    #[arg(long, value_name = "UM", value_parser = ranged::<u32>(Limit::LENS_FOCAL_LENGTH_MAX_UM))]
    #[serde(rename = "lens.focal_length_max_um")]
    pub lens_focal_length_max_um: Option<u32>,
    /// The visible sensor's width, µm [default: 0, unknown].
    #[arg(long, value_name = "UM", value_parser = ranged::<u32>(Limit::LENS_SENSOR_WIDTH_UM))]
    #[serde(rename = "lens.sensor_width_um")]
    pub lens_sensor_width_um: Option<u32>,
    /// The visible sensor's height, µm [default: 0, unknown].
    #[arg(long, value_name = "UM", value_parser = ranged::<u32>(Limit::LENS_SENSOR_HEIGHT_UM))]
    #[serde(rename = "lens.sensor_height_um")]
    pub lens_sensor_height_um: Option<u32>,
    /// The visible photo width, pixels [default: 4000].
    #[arg(long, value_name = "PX", value_parser = ranged::<u32>(Limit::LENS_RESOLUTION_H))]
    #[serde(rename = "lens.resolution_h")]
    pub lens_resolution_h: Option<u32>,
    /// The visible photo height, pixels [default: 3000].
    #[arg(long, value_name = "PX", value_parser = ranged::<u32>(Limit::LENS_RESOLUTION_V))]
    #[serde(rename = "lens.resolution_v")]
    pub lens_resolution_v: Option<u32>,
    /// Switch the pod's 1 s periodic laser ranging on at every link-up.
    #[arg(long)]
    #[serde(rename = "laser.periodic", skip_serializing_if = "is_false")]
    pub laser_periodic: bool,
    /// The laser's shortest distance, cm [default: 0, unknown].
    #[arg(long, value_name = "CM", value_parser = ranged::<u32>(Limit::LASER_MIN_DISTANCE_CM))]
    #[serde(rename = "laser.min_distance_cm")]
    pub laser_min_distance_cm: Option<u32>,
    /// The laser's longest distance, cm [default: 65535, unknown].
    #[arg(long, value_name = "CM", value_parser = ranged::<u32>(Limit::LASER_MAX_DISTANCE_CM))]
    #[serde(rename = "laser.max_distance_cm")]
    pub laser_max_distance_cm: Option<u32>,
    /// The GNSS module's pulse is active low: its on-time edge is the falling one (the
    /// edge --pps takes).
    #[arg(long)]
    #[serde(rename = "pps.active_low", skip_serializing_if = "is_false")]
    pub pps_active_low: bool,
    /// Advanced (tests, demos): local time covered by one bin of the UTC estimator, ms
    /// [default: 8000]. Smaller bins make UTC valid sooner after start, on fewer samples.
    #[arg(long, value_name = "MS", help_heading = "Time discipline (advanced)",
          value_parser = ranged::<u64>(Limit::DISCIPLINE_BIN_MS))]
    #[serde(rename = "discipline.bin_ms")]
    pub discipline_bin_ms: Option<u64>,
    /// Advanced: bins needed before a clock estimate is trusted [default: 5].
    #[arg(long, value_name = "N", help_heading = "Time discipline (advanced)",
          value_parser = ranged::<u8>(Limit::DISCIPLINE_MIN_BINS))]
    #[serde(rename = "discipline.min_bins")]
    pub discipline_min_bins: Option<u8>,
    /// Advanced: local time the trusted bins must span, ms [default: 16000].
    #[arg(long, value_name = "MS", help_heading = "Time discipline (advanced)",
          value_parser = ranged::<u64>(Limit::DISCIPLINE_MIN_SPAN_MS))]
    #[serde(rename = "discipline.min_span_ms")]
    pub discipline_min_span_ms: Option<u64>,
    /// MAVLink 2 signing on the MAVLink side and the telemetry link: `off`, `sign` (every
    /// frame sent signed, signed frames checked) or `require` (unsigned frames refused
    /// too) [default: off]. See the book's security chapter.
    #[arg(long, value_enum, value_name = "MODE", help_heading = "Security")]
    #[serde(rename = "signing", skip_serializing_if = "Option::is_none")]
    pub signing: Option<SigningArg>,
    /// The MAVLink signing key: a file holding its 64 hexadecimal characters (the
    /// configuration file's `signing_key`).
    #[arg(long, value_name = "FILE", help_heading = "Security")]
    #[serde(skip)] // read by runner::bridge::config_of
    pub signing_key_file: Option<PathBuf>,
    /// With `--signing require`: still read unsigned frames that command nothing
    /// (heartbeats, time, positions).
    #[arg(long, help_heading = "Security")]
    #[serde(
        rename = "signing_unsigned_telemetry",
        skip_serializing_if = "is_false"
    )]
    pub signing_unsigned_telemetry: bool,
    /// MAVLink systems whose commands are taken besides the autopilot's, comma-separated
    /// (`none`: the autopilot's only) [default: 255,245].
    #[arg(long, value_name = "IDS", help_heading = "Security", value_parser = parse_ids)]
    #[serde(rename = "gcs_ids", skip_serializing_if = "Option::is_none")]
    pub gcs_ids: Option<Ids>,
    /// The pod's destructive requests a K40T FC (or a command that maps to one) may send,
    /// comma-separated K40T ids such as `0x00030D` [default: none].
    #[arg(long, value_name = "IDS", help_heading = "Security", value_parser = parse_ids)]
    #[serde(rename = "k40t_allow", skip_serializing_if = "Option::is_none")]
    pub k40t_allow: Option<Ids>,
    /// The autopilot's MAVLink system id (0: the first autopilot heard after start, then
    /// kept) [default: 0].
    #[arg(long, value_name = "ID", help_heading = "Security",
          value_parser = ranged::<u8>(Limit::AUTOPILOT_SYSID))]
    #[serde(rename = "autopilot_sysid", skip_serializing_if = "Option::is_none")]
    pub autopilot_sysid: Option<u8>,
    /// With --autopilot-sysid 0: the autopilot learnt is forgotten after this long
    /// without its HEARTBEAT, ms [default: 30000].
    #[arg(long, value_name = "MS", help_heading = "Security",
          value_parser = ranged::<u64>(Limit::AUTOPILOT_FORGET_MS))]
    #[serde(
        rename = "autopilot_forget_ms",
        skip_serializing_if = "Option::is_none"
    )]
    pub autopilot_forget_ms: Option<u64>,
}

/// `--signing`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SigningArg {
    /// Nothing signed or checked.
    Off,
    /// Frames sent signed; signed frames checked.
    Sign,
    /// As `sign`, and unsigned frames refused.
    Require,
}

/// A list of ids (`--gcs-ids`, `--k40t-allow`): decimal or `0x` hexadecimal numbers,
/// comma-separated, or `none` (serialized as the file's list).
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
#[serde(transparent)]
pub struct Ids(pub Vec<i64>);

fn parse_ids(s: &str) -> Result<Ids, String> {
    if s.eq_ignore_ascii_case("none") {
        return Ok(Ids(Vec::new()));
    }
    s.split(',')
        .map(|part| {
            let part = part.trim();
            match part.strip_prefix("0x").or_else(|| part.strip_prefix("0X")) {
                Some(hex) => i64::from_str_radix(hex, 16),
                None => part.parse::<i64>(),
            }
            .map_err(|_| format!("{part:?} is not a number"))
        })
        .collect::<Result<Vec<_>, _>>()
        .map(Ids)
}

/// `--k40t-geotag-fallback-ms`: a time or `off` (serialized as the file has it: ms or
/// `"off"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fallback {
    /// Answer after this many ms.
    Ms(u64),
    /// Never answer in the FC's place.
    Off,
}

impl Serialize for Fallback {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match *self {
            Fallback::Ms(ms) => s.serialize_u64(ms),
            Fallback::Off => s.serialize_str("off"),
        }
    }
}

#[allow(clippy::trivially_copy_pass_by_ref)] // serde's signature
fn is_false(b: &bool) -> bool {
    !b
}

#[allow(clippy::trivially_copy_pass_by_ref)] // serde's signature
fn negated<S: Serializer>(b: &bool, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_bool(!b)
}

/// An integer option checked against its key's range (`Config::validate`'s [`Limit`]).
fn ranged<T>(limit: Limit) -> impl Fn(&str) -> Result<T, String> + Clone + Send + Sync + 'static
where
    T: TryFrom<i64> + Clone + Send + Sync + 'static,
{
    move |s| {
        let v: i64 = s.parse().map_err(|_| format!("`{s}` is not an integer"))?;
        limit.check(v).map_err(|e| e.problem.to_string())?;
        T::try_from(v).map_err(|_| format!("{v} is out of range"))
    }
}

/// A text option, kept as text once `parse` (the configuration's own parser) takes it.
fn checked<T: 'static>(
    parse: fn(&str) -> Result<T, String>,
) -> impl Fn(&str) -> Result<String, String> + Clone + Send + Sync + 'static {
    move |s| parse(s).map(|_| s.to_owned())
}

/// `gimbal sim-fc`.
#[derive(Debug, Args)]
#[command(after_long_help = PORT_AND_FAULTS_HELP)]
pub struct SimFcArgs {
    /// The flight controller to simulate (ArduPilot's SIYI, Viewpro or XF Robot
    /// driver, or a K40T-speaking FC).
    #[arg(value_enum, ignore_case = true)]
    pub fc: Fc,
    /// Where the bridge is (not `sim`).
    #[arg(long, value_name = "PORT", value_parser = parse_peer_port)]
    pub port: PortSpec,
    /// Line rate for pacing and serial devices [default: the port's :BAUD, else 115200].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1200..=4_000_000))]
    pub baud: Option<u32>,
    /// Stop after this many seconds (default: run until Ctrl-C).
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    pub seconds: Option<f64>,
    /// Take a picture every this many seconds (from the start).
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    pub photo_every: Option<f64>,
    /// Turn the mount at this yaw rate from the start, °/s (positive right).
    #[arg(long, value_name = "DPS", allow_negative_numbers = true)]
    pub yaw_rate: Option<f64>,
    /// Turn the mount at this pitch rate from the start, °/s (positive up).
    #[arg(long, value_name = "DPS", allow_negative_numbers = true)]
    pub pitch_rate: Option<f64>,
    /// Exit with status 1 unless the driver is healthy at the end.
    #[arg(long)]
    pub expect_healthy: bool,
    /// Make the cable to the bridge faulty (see FAULTS below).
    #[arg(long, value_name = "FAULTS", value_parser = parse_faults)]
    pub faults: Option<Faults>,
    /// Output format (JSON lines by default).
    #[arg(long, value_enum, default_value_t = EventFormat::Json)]
    pub events: EventFormat,
    /// MAVLink: the autopilot behind the port.
    #[arg(long, value_enum, default_value_t = AutopilotArg::Ardupilot)]
    pub autopilot: AutopilotArg,
    /// MAVLink, PX4: the port's mode (`MAV_n_MODE`); `gimbal` is PX4 1.16's, whose link
    /// answers no SET_MESSAGE_INTERVAL and no TIMESYNC.
    #[arg(long, value_enum, default_value_t = Px4ModeArg::Normal)]
    pub px4_mode: Px4ModeArg,
    /// MAVLink, PX4: SITL in lockstep (its boot clock in 4 ms steps, 0.87 % slow against
    /// UTC, which follows the host's clock, and wandering by tens of ms).
    #[arg(long)]
    pub px4_lockstep: bool,
    /// MAVLink: a ground app's link on UDP, `udp:HOST:PORT` (the app listens there, e.g.
    /// MAVSDK `udpin://HOST:PORT`; the simulator answers where the app's datagrams come
    /// from). The autopilot routes between it and the bridge as it does, and (PX4) is
    /// the gimbal manager of the bridge's gimbal.
    #[arg(long, value_name = "udp:HOST:PORT", value_parser = parse_udp)]
    pub gcs: Option<std::net::SocketAddr>,
}

/// The autopilot of `gimbal sim-fc mavlink`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Default)]
pub enum AutopilotArg {
    /// ArduPilot: `AP_Mount_MAVLink` and `AP_Camera_MAVLinkCamV2` (Copter).
    #[default]
    Ardupilot,
    /// PX4: the gimbal v2 output, and the gimbal manager towards a ground app.
    Px4,
}

/// The mode of the simulated PX4's port.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Default)]
pub enum Px4ModeArg {
    /// 0: Normal (positions streamed; SYSTEM_TIME on request).
    #[default]
    Normal,
    /// 2: Onboard (time and positions streamed, TIMESYNC requests).
    Onboard,
    /// 10: Gimbal as PX4 1.16 runs it (only the gimbal messages: no time, no position).
    Gimbal,
}

/// `udp:HOST:PORT`.
fn parse_udp(s: &str) -> Result<std::net::SocketAddr, String> {
    use std::net::ToSocketAddrs;
    let rest = s
        .strip_prefix("udp:")
        .ok_or_else(|| format!("`{s}`: expected udp:HOST:PORT"))?;
    rest.to_socket_addrs()
        .ok()
        .and_then(|mut a| a.next())
        .ok_or_else(|| format!("`{s}`: expected udp:HOST:PORT"))
}

/// `gimbal sim-pod`.
#[derive(Debug, Args)]
#[command(after_long_help = PORT_AND_FAULTS_HELP)]
pub struct SimPodArgs {
    /// Where the bridge's pod link is (not `sim`).
    #[arg(long, value_name = "PORT", value_parser = parse_peer_port)]
    pub port: PortSpec,
    /// Where the bridge's RTC_IO edges come from: `tcp:HOST:PORT` or
    /// `tcp-listen:[HOST:]PORT`, one byte per edge (`1`/`H`/0x01 rising, `0`/`L`/0x00
    /// falling), as `gimbal bridge --rtc-io tcp...` sends them. Without it the pod sees
    /// no edge and applies no time sync (outcome `no_edge`).
    #[arg(long, value_name = "PORT", value_parser = parse_rtc_input)]
    pub rtc_io: Option<PortSpec>,
    /// Line rate for pacing and serial devices [default: the port's :BAUD, else 115200].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1200..=4_000_000))]
    pub baud: Option<u32>,
    /// Stop after this many seconds (default: run until Ctrl-C).
    #[arg(long, value_name = "SECONDS", value_parser = parse_seconds)]
    pub seconds: Option<f64>,
    /// Exit with status 1 unless at least this many time syncs were applied.
    #[arg(long, value_name = "N")]
    pub expect_syncs: Option<u32>,
    /// Exit with status 1 unless at least this many photos were geotagged (a GPS reply
    /// with code OK).
    #[arg(long, value_name = "N")]
    pub expect_geotags: Option<u32>,
    /// The sequence number of the pod's ACKs.
    #[arg(long, value_enum, value_name = "SEQ", default_value_t = AckSeqArg::Own)]
    pub ack_seq: AckSeqArg,
    /// Make the cable to the bridge faulty (see FAULTS below; not RTC_IO).
    #[arg(long, value_name = "FAULTS", value_parser = parse_faults)]
    pub faults: Option<Faults>,
    /// Output format (JSON lines by default).
    #[arg(long, value_enum, default_value_t = EventFormat::Json)]
    pub events: EventFormat,
}

fn parse_port(s: &str) -> Result<PortSpec, String> {
    s.parse()
}

fn parse_faults(s: &str) -> Result<Faults, String> {
    s.parse()
}

/// A port of a simulator: anything but `sim`.
fn parse_peer_port(s: &str) -> Result<PortSpec, String> {
    match s.parse::<PortSpec>()? {
        PortSpec::Sim => Err(
            "`sim` is for `gimbal bridge`; a simulator needs a serial device or TCP port".into(),
        ),
        p => Ok(p),
    }
}

/// The telemetry port: anything but `sim` (no simulated autopilot runs there).
fn parse_telemetry_port(s: &str) -> Result<PortSpec, String> {
    match s.parse::<PortSpec>()? {
        PortSpec::Sim => Err(
            "the telemetry port is a serial device, TCP or UDP port (`gimbal sim-fc --fc \
mavlink` can stand for the autopilot's MAVLink port)"
                .into(),
        ),
        p => Ok(p),
    }
}

fn parse_rtc(s: &str) -> Result<RtcSpec, String> {
    s.parse()
}

fn parse_pps(s: &str) -> Result<PpsSpec, String> {
    s.parse()
}

/// An RTC_IO input of the simulated pod: a TCP port (connect or listen).
fn parse_rtc_input(s: &str) -> Result<PortSpec, String> {
    match s.parse::<PortSpec>()? {
        p @ (PortSpec::Tcp { .. } | PortSpec::TcpListen { .. }) => Ok(p),
        _ => Err(format!(
            "`{s}`: the pod's RTC_IO input is `tcp:HOST:PORT` or `tcp-listen:[HOST:]PORT`"
        )),
    }
}

/// A positive number of seconds (fractions allowed).
///
/// # Errors
/// Not a number, not positive, or more than a year.
pub fn parse_seconds(s: &str) -> Result<f64, String> {
    let v: f64 = s
        .parse()
        .map_err(|_| format!("`{s}` is not a number of seconds"))?;
    if v.is_finite() && v > 0.0 && v <= 366.0 * 86_400.0 {
        Ok(v)
    } else {
        Err(format!(
            "`{s}`: expected a positive number of seconds (at most a year)"
        ))
    }
}

/// Exactly 12 ASCII characters (`SiyiIdentity::parse_hardware_id`).
///
/// # Errors
/// Anything else.
pub fn parse_hardware_id(s: &str) -> Result<[u8; 12], String> {
    SiyiIdentity::parse_hardware_id(s)
        .map_err(|e| format!("`{s}`: {} (e.g. 7A0000000001)", e.problem))
}

/// 1 to 10 printable ASCII characters, padded with zeros
/// (`ViewlinkIdentity::parse_model`).
///
/// # Errors
/// Anything else.
pub fn parse_model(s: &str) -> Result<[u8; 10], String> {
    ViewlinkIdentity::parse_model(s).map_err(|e| format!("`{s}`: {}", e.problem))
}

/// Up to 160 printable ASCII characters, no space (`VideoConfig::parse_uri`).
///
/// # Errors
/// Anything else.
pub fn parse_uri(s: &str) -> Result<[u8; 160], String> {
    VideoConfig::parse_uri(s).map_err(|e| format!("`{s}`: {}", e.problem))
}

fn parse_fallback(s: &str) -> Result<Fallback, String> {
    if s.eq_ignore_ascii_case("off") || s.eq_ignore_ascii_case("never") {
        return Ok(Fallback::Off);
    }
    let limit = Limit::K40T_GEOTAG_FALLBACK_MS;
    match s.parse::<i64>() {
        Ok(ms) if limit.check(ms).is_ok() => Ok(Fallback::Ms(ms.unsigned_abs())),
        _ => Err(format!(
            "`{s}`: expected a time in ms ({}..={}) or `off`",
            limit.min, limit.max
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values() {
        assert_eq!(parse_hardware_id("7A0000000001"), Ok(*b"7A0000000001"));
        assert!(parse_hardware_id("7A").is_err());
        assert_eq!(parse_model("ABC"), Ok(*b"ABC\0\0\0\0\0\0\0"));
        assert!(parse_model("ELEVENCHARS").is_err());
        assert_eq!(parse_fallback("off"), Ok(Fallback::Off));
        assert_eq!(parse_fallback("250"), Ok(Fallback::Ms(250)));
        assert!(parse_fallback("0").is_err());
        assert_eq!(parse_seconds("2.5"), Ok(2.5));
        assert!(parse_seconds("0").is_err());
        assert!(parse_seconds("-1").is_err());
        assert!(parse_seconds("nan").is_err());
    }
}
