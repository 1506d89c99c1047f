//! The `gimbal` command line, as `clap` derive types: the subcommands and the options of
//! the decoder and the demo. The binary (`src/main.rs`) parses [`Cli`] and dispatches.
//! The options of the commands the runner carries out (bridge, simulators) are the
//! runner's own types ([`crate::runner::options`], re-exported here): the command line
//! depends on the runner, never the reverse.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

pub use crate::runner::options::{
    AckSeqArg, BridgeArgs, ConfigArgs, EventFormat, Fallback, Fc, SimFcArgs, SimPodArgs,
    parse_hardware_id, parse_model, parse_seconds,
};

/// Decode gimbal-protocol captures, list the messages, run the K40T bridge on Linux and
/// the simulated flight controller and pod on real ports.
///
/// Exit status: 0 on success, 1 on a run-time failure (a port that cannot be opened, an
/// expectation of a simulator not met), 2 for bad arguments.
#[derive(Debug, Parser)]
#[command(
    name = "gimbal",
    version = version_line(),
    propagate_version = true,
    arg_required_else_help = true
)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// What `gimbal --version` prints after the name: the version, the commit and the
/// features of the bridge it runs ([`bridge_fw::config::BUILD`]: the host flavour of the
/// firmware's tasks, with every FC side).
#[must_use]
pub fn version_line() -> &'static str {
    static LINE: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    LINE.get_or_init(|| bridge_fw::config::BUILD.to_string())
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Decode a capture: hex text or raw bytes, from arguments, a file or stdin.
    ///
    /// One line per frame (or bad frame, garbage, truncated frame) on stdout; a summary
    /// line on stderr. A capture is hex text (any separators, `0x` prefixes allowed) or
    /// raw binary bytes.
    Decode(DecodeArgs),
    /// List every message id the codec of a protocol supports.
    Messages(MessagesArgs),
    /// Run the bridge (the firmware's own tasks) between a flight controller and a K40T
    /// pod on real ports: serial devices, TCP, or the built-in simulators.
    ///
    /// Prints every engine event, RTC_IO edge and time sync (and with --trace every
    /// frame) on stdout, as text or one JSON object per line (--events json). Stops on
    /// Ctrl-C or after --seconds, with a `stopped` and a `counters` event.
    Bridge(Box<BridgeArgs>),
    /// Run a simulated ArduPilot mount driver (the flight controller's side) on a port,
    /// in real time, printing what it observes as JSON lines.
    SimFc(SimFcArgs),
    /// Run the simulated K40T pod on a port, in real time, printing what it observes as
    /// JSON lines.
    SimPod(SimPodArgs),
    /// The bridge working, without hardware: the firmware's tasks between a simulated
    /// ArduPilot driver and a simulated K40T pod, in accelerated simulated time.
    ///
    /// Prints the FC reaching healthy, a scripted flight (look down, pan, zoom, record,
    /// photos) with the frames it causes on both links, each time sync with its UTC and
    /// error, each geotag with the interpolated fix, and a summary table.
    Demo(DemoArgs),
    /// Write a flight's bridge log as one self-contained HTML page: time syncs and their
    /// error, the track with every photo and geotag, the links, and a summary.
    ///
    /// Reads the JSON lines of `gimbal bridge --events json` (or `gimbal demo --events
    /// json`). A bad line (cut off, an unknown event, another log version) is reported
    /// with its line number, on stderr and in the page, and the rest is drawn. Exit 1
    /// only when the log cannot be read or holds no event at all.
    Report(ReportArgs),
    /// Send a signed firmware image to a board over its update port, with a progress bar;
    /// the board checks the signature, swaps the image in at its reset, and the version
    /// that then runs is printed.
    ///
    /// The port is the board's ST-LINK virtual COM port (e.g. /dev/ttyACM0). The signature
    /// is IMAGE.sig (scripts/release writes one beside every image; `gimbal sign` makes
    /// one). A lost link resumes where the board stopped. Exit 1 when the board refuses
    /// the image, does not come back, or rolls the image back.
    Update(UpdateArgs),
    /// The bridge's settings through its console (docs/src/console.md): on a board's
    /// ST-LINK virtual COM port, or `gimbal bridge --console`'s port.
    ///
    /// `get` prints one setting or every one; `set` checks and sets one (kept by `save` on
    /// the console, or `load`); `dump` prints every setting as a configuration file
    /// (the signing key as a comment: it is write-only); `load FILE` sets each setting of
    /// such a file, then saves them. Exit 1 when the console refuses a value.
    Config(ConfigCommandArgs),
    /// Sign a firmware image for `gimbal update`: writes IMAGE.sig (the ed25519 signature of
    /// the image's SHA-512 and the signer's public key).
    ///
    /// Without --key, the development key (made on first use in
    /// ~/.config/k40t-bridge/update-key-dev.pem): boards built without BRIDGE_UPDATE_KEY
    /// accept it; never for the field.
    Sign(SignArgs),
    /// What the release manifest says of a firmware image, as one JSON object: size,
    /// SHA-256, the slot it must fit and the room left, its signer and whether the
    /// signature (IMAGE.sig) holds, and its update's time at 115200 baud.
    ImageInfo {
        /// The image (`.bin`).
        image: PathBuf,
    },
    /// Make a new update signing key: KEY (PKCS#8 PEM, private) and KEY.pub.pem (its public
    /// half, what the firmware is built with: BRIDGE_UPDATE_KEY=KEY.pub.pem).
    UpdateKey(UpdateKeyArgs),
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell).
    ///
    /// For example: `gimbal completions bash > ~/.local/share/bash-completion/completions/gimbal`.
    Completions {
        /// The shell.
        shell: clap_complete::Shell,
    },
}

/// `gimbal update`.
#[derive(Debug, clap::Args)]
pub struct UpdateArgs {
    /// The board's update port: a serial device, or `tcp:HOST:PORT` (one forwarded over
    /// the network).
    #[arg(long)]
    pub port: String,
    /// The port's baud rate.
    #[arg(long, default_value_t = 115_200)]
    pub baud: u32,
    /// The signature file [default: IMAGE.sig].
    #[arg(long)]
    pub sig: Option<PathBuf>,
    /// Seconds to wait for the board to answer after its reset (the swap takes some 20 s).
    #[arg(long, default_value_t = 120)]
    pub wait: u64,
    /// The image (a `.bin` of the release folder).
    pub image: PathBuf,
}

/// `gimbal config`.
#[derive(Debug, clap::Args)]
pub struct ConfigCommandArgs {
    /// The console's port: a serial device (the board's ST-LINK virtual COM port), or
    /// `tcp:HOST:PORT` (`gimbal bridge --console tcp-listen:PORT`).
    #[arg(long)]
    pub port: String,
    /// The serial device's baud rate.
    #[arg(long, default_value_t = 115_200)]
    pub baud: u32,
    /// What to do.
    #[command(subcommand)]
    pub action: ConfigAction,
}

/// `gimbal config`'s actions.
#[derive(Debug, Subcommand)]
pub enum ConfigAction {
    /// Print a setting, or every one.
    Get {
        /// The setting's key (as in the configuration file: `fc_baud`, `video.uri`).
        key: Option<String>,
    },
    /// Set a setting (checked as the configuration file is; kept by `save` or `load`).
    Set {
        /// The setting's key.
        key: String,
        /// Its value, as the configuration file writes it (texts in quotes or not).
        value: String,
    },
    /// Print every setting as a configuration file (`load` takes it back).
    Dump,
    /// Set every setting of FILE (a dump, or a configuration file of flat keys), then save.
    Load {
        /// The file.
        file: PathBuf,
    },
}

/// `gimbal sign`.
#[derive(Debug, clap::Args)]
pub struct SignArgs {
    /// The private key (PKCS#8 PEM) [default: the development key].
    #[arg(long)]
    pub key: Option<PathBuf>,
    /// The image.
    pub image: PathBuf,
}

/// `gimbal update-key`.
#[derive(Debug, clap::Args)]
pub struct UpdateKeyArgs {
    /// Where to write the private key (never overwritten).
    pub key: PathBuf,
}

/// `gimbal demo`.
#[derive(Debug, Clone, Args)]
pub struct DemoArgs {
    /// The flight controller's protocol (its simulated ArduPilot driver is used).
    #[arg(long, value_enum, ignore_case = true, default_value = "siyi")]
    pub fc: Fc,
    /// Simulated seconds to fly (a photo every 15 s after 51 s).
    #[arg(long, default_value_t = 60, value_parser = clap::value_parser!(u32).range(10..=7200))]
    pub seconds: u32,
    /// Attach the same simulated ArduPilot's MAVLink port to the bridge's telemetry
    /// link (SIYI, Viewlink, GCU): UTC and fixes from TIMESYNC, SYSTEM_TIME and the
    /// position streams.
    #[arg(long)]
    pub telemetry: bool,
    /// A simulated GNSS module's pulse per second on the bridge's PPS input (any FC
    /// side): the clock locks to it, RTC_IO is the board's timer compare, and the syncs'
    /// errors are shown in µs against the GNSS's UTC.
    #[arg(long)]
    pub pps: bool,
    /// `human`: the story and the summary; `json`: the run's events as `gimbal bridge
    /// --events json` prints them (each time sync with its measured error, `error_us`),
    /// for `gimbal report`.
    #[arg(long, value_enum, default_value_t = EventFormat::Human)]
    pub events: EventFormat,
}

/// `gimbal report`.
#[derive(Debug, Clone, Args)]
pub struct ReportArgs {
    /// The log: the JSON lines of `gimbal bridge --events json` (or `gimbal demo --events
    /// json`).
    #[arg(value_name = "LOG")]
    pub log: PathBuf,
    /// The page to write [default: LOG with the extension `.html`].
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,
}

/// A protocol the capture decoder knows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
#[value(rename_all = "lower")]
pub enum Codec {
    /// The K40T pod protocol.
    K40t,
    /// The SIYI SDK.
    Siyi,
    /// Viewlink (Viewpro).
    Viewlink,
    /// XF Robot GCU.
    Gcu,
    /// MAVLink 2 (the bridge's message set).
    Mavlink,
}

impl Codec {
    /// The name the tool's adapters use.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Codec::K40t => "k40t",
            Codec::Siyi => "siyi",
            Codec::Viewlink => "viewlink",
            Codec::Gcu => "gcu",
            Codec::Mavlink => "mavlink",
        }
    }
}

/// `gimbal decode`.
#[derive(Debug, Args)]
pub struct DecodeArgs {
    /// The protocol of the capture.
    #[arg(value_enum, ignore_case = true)]
    pub protocol: Codec,
    /// One JSON object per line instead of text.
    #[arg(long)]
    pub json: bool,
    /// Read the capture from this file (hex text or raw bytes).
    #[arg(long, value_name = "PATH", conflicts_with = "hex")]
    pub file: Option<PathBuf>,
    /// The capture as hex bytes (stdin is read when neither HEX nor --file is given).
    #[arg(value_name = "HEX")]
    pub hex: Vec<String>,
}

/// `gimbal messages`.
#[derive(Debug, Args)]
pub struct MessagesArgs {
    /// The protocol.
    #[arg(value_enum, ignore_case = true)]
    pub protocol: Codec,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::runner::pin::{GpioSpec, RtcSpec};
    use crate::runner::port::PortSpec;
    use crate::sim::faults::Faults;
    use crate::sim::pod::AckSeq;
    use clap::CommandFactory;

    /// A command line's words.
    fn words(line: &str) -> std::str::SplitWhitespace<'_> {
        line.split_whitespace()
    }

    #[test]
    fn the_command_line_definition_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn a_bridge_command_line_parses_into_its_options() {
        let cli = Cli::try_parse_from(words("gimbal bridge --fc SIYI --fc-port /dev/ttyAMA0:921600 --pod-port tcp:127.0.0.1:5000 --rtc-io gpiochip0:17 --tz-minuteswest -480 --sync-period-ms 2000 --events json"))
        .unwrap();
        let Command::Bridge(b) = cli.command else {
            panic!("not bridge")
        };
        assert_eq!(b.fc, Fc::Siyi);
        assert_eq!(
            b.fc_port,
            PortSpec::Serial {
                path: "/dev/ttyAMA0".into(),
                baud: Some(921_600)
            }
        );
        assert_eq!(
            b.pod_port,
            PortSpec::Tcp {
                host: "127.0.0.1".into(),
                port: 5000
            }
        );
        assert_eq!(
            b.rtc_io,
            RtcSpec::Gpio(GpioSpec::new("/dev/gpiochip0", 17, false))
        );
        assert_eq!(b.config.tz_minuteswest, Some(-480));
        assert_eq!(b.config.sync_period_ms, Some(2000));
        assert_eq!(b.events, EventFormat::Json);
        assert!(!b.trace);
        assert_eq!((b.fc_faults, b.pod_faults), (None, None));
        assert_eq!(b.sim_pod_ack_seq, AckSeqArg::Own);

        let cli = Cli::try_parse_from(words("gimbal bridge --fc siyi --fc-port sim --pod-port sim --fc-faults ber=1e-4,drop=1e-5,seed=3 --pod-faults garbage=0.001 --sim-pod-ack-seq own"))
        .unwrap();
        let Command::Bridge(b) = cli.command else {
            panic!("not bridge")
        };
        assert_eq!(
            b.fc_faults,
            Some(Faults {
                bit_error_rate: 1e-4,
                drop_rate: 1e-5,
                garbage_rate: 0.0,
                seed: 3
            })
        );
        assert_eq!(
            b.pod_faults.map(|f| (f.garbage_rate, f.seed)),
            Some((0.001, 1))
        );
        assert_eq!(b.sim_pod_ack_seq.ack_seq(), AckSeq::OwnCounter);
        let cli = Cli::try_parse_from(words(
            "gimbal sim-pod --port tcp:a:1 --faults drop=0.5 --ack-seq own",
        ))
        .unwrap();
        let Command::SimPod(p) = cli.command else {
            panic!("not sim-pod")
        };
        assert_eq!(p.faults.map(|f| f.drop_rate), Some(0.5));
        assert_eq!(p.ack_seq, AckSeqArg::Own);
        let cli =
            Cli::try_parse_from(words("gimbal sim-fc siyi --port tcp:a:1 --faults none")).unwrap();
        let Command::SimFc(f) = cli.command else {
            panic!("not sim-fc")
        };
        assert_eq!(f.faults, Some(Faults::NONE));
    }

    #[test]
    fn report_and_demo_json_command_lines() {
        let cli = Cli::try_parse_from(words("gimbal report flight.jsonl -o page.html")).unwrap();
        let Command::Report(r) = cli.command else {
            panic!("not report")
        };
        assert_eq!(r.log, PathBuf::from("flight.jsonl"));
        assert_eq!(r.output, Some(PathBuf::from("page.html")));
        let cli = Cli::try_parse_from(words("gimbal demo --seconds 7200 --events json")).unwrap();
        let Command::Demo(d) = cli.command else {
            panic!("not demo")
        };
        assert_eq!((d.seconds, d.events), (7200, EventFormat::Json));
        assert!(Cli::try_parse_from(words("gimbal demo --seconds 7201")).is_err());
    }

    #[test]
    fn bad_values_are_usage_errors() {
        for args in [
            "gimbal bridge --fc nosuch --fc-port sim --pod-port sim",
            "gimbal bridge --fc siyi --fc-port nowhere --pod-port sim",
            "gimbal bridge --fc siyi --fc-port sim",
            "gimbal bridge --fc siyi --fc-port sim --pod-port sim --sync-period-ms 10",
            "gimbal sim-pod --port tcp:localhost:99999",
            "gimbal sim-pod --port sim",
            "gimbal sim-pod --port tcp:a:1 --faults ber=2",
            "gimbal sim-fc siyi --port tcp:a:1 --faults noise=1",
            "gimbal sim-pod --port tcp:a:1 --rtc-io /dev/ttyS0",
        ] {
            let e = Cli::try_parse_from(words(args)).unwrap_err();
            assert_eq!(e.exit_code(), 2, "{args:?}: {e}");
        }
    }
}
