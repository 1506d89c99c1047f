//! One interface over the simulated flight controllers, for the demo and the task-level
//! scenarios: a [`Pilot`] flies the mount (point, turn, zoom, photo, record), says whether
//! its driver calls the mount healthy, knows the true UTC and the aircraft's true
//! position (the references of time sync and geotag), and describes the frames of its
//! protocol for people.
//!
//! Each FC side implements it once: [`ApSiyi`] (ArduPilot `AP_Mount_Siyi`), [`ApViewpro`]
//! (ArduPilot `AP_Mount_Viewpro`), [`ApXfRobot`] (ArduPilot `AP_Mount_XFRobot`, the GCU
//! side) and [`FcK40t`] (an FC speaking K40T itself). A new side
//! adds one `impl Pilot` (in its simulator's file or here) and one match arm where the
//! demo picks the simulator by [`FcProtocol`].

use bridge_engine::FcProtocol;
use protocol_core::Direction;
use protocol_core::gcu::{self, GcuFraming};
use protocol_core::k40t::{
    self, ContinuousZoom, DialSpeed, GimbalAngle, GimbalAttitude, GimbalControl, GimbalFunction,
    K40tFraming, Kind, MessageData, PitchMotion, RecordAction, ShootAction, TakePhoto, YawMotion,
    ZoomControl,
};
use protocol_core::siyi::{self, SiyiFraming};
use protocol_core::viewlink::{self, ViewlinkFraming};
use protocol_core::wire::Framing;
use serde::Serialize;
use serde_json::Value;

use super::FcReboot;
use super::ap_siyi::{Aircraft, ApSiyi, ApSiyiConfig, MountTarget};
use super::ap_viewpro::{ApViewpro, ApViewproConfig};
use super::ap_xfrobot::{self, ApXfRobot, ApXfRobotConfig};
use super::fc_k40t::FcK40t;
use super::scenario::FcSim;

/// A frame decoded for display: `SIYI 0x07 GimbalRotation yaw=0 pitch=-100`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Described {
    /// Protocol label (`SIYI`, `Viewlink`, `K40T`).
    pub protocol: &'static str,
    /// Message id (K40T: the 24-bit id, kind included).
    pub id: u32,
    /// Hex digits of the id when printed.
    pub digits: usize,
    /// Message name.
    pub name: String,
    /// Payload fields as `key=value` pairs (headers, sequence numbers and reserved
    /// bytes left out, so that two frames with the same meaning print the same).
    pub fields: String,
}

impl core::fmt::Display for Described {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "{} 0x{:0w$X} {}",
            self.protocol,
            self.id,
            self.name,
            w = self.digits
        )?;
        if !self.fields.is_empty() {
            write!(f, " {}", self.fields)?;
        }
        Ok(())
    }
}

/// A simulated flight controller the demo and the task scenarios can fly.
///
/// Angles are degrees, yaw positive right (body frame), pitch positive up; rates in
/// degrees per second. Time is simulated true time in microseconds.
pub trait Pilot: FcSim {
    /// The FC protocol this simulator speaks.
    const PROTOCOL: FcProtocol;
    /// Who is on the FC side, for people.
    const DRIVER: &'static str;
    /// The FC sends frames continuously (several a second) while it runs, so the
    /// bridge's FC link stays up; a K40T FC speaks only when it has something to say.
    const STREAMS: bool = true;
    /// The framing of the FC link.
    type Framing: Framing;

    /// The simulator with its default settings and this seed for its random jitter.
    fn with_seed(seed: u64) -> Self;
    /// Framing of the frames the FC sends (`from_fc`) or receives.
    fn framing(from_fc: bool) -> Self::Framing;
    /// One checksum-valid frame of the FC link, decoded for display.
    fn describe(frame: &[u8], from_fc: bool) -> Option<Described>;
    /// Periodic traffic (polls, telemetry, status) rather than a command: the demo shows
    /// only the first of these.
    fn routine(id: u32, from_fc: bool) -> bool;
    /// A name for the FC id of the engine's `Translated` event.
    fn command_name(fc_id: u16) -> String;

    /// The driver calls the mount healthy.
    fn healthy(&self) -> bool;
    /// Every change of [`Pilot::healthy`]: (true time, new value).
    fn health_log(&self) -> &[(u64, bool)];
    /// The FC's UTC at true time `t_us` (µs since the Unix epoch): what a time sync should
    /// carry for an edge at that instant.
    fn true_utc_us(&self, t_us: u64) -> u64;
    /// True time the FC first sent a usable UTC (SIYI 0x30, Viewlink M_AHRS with a valid
    /// date, GCU a GPS time, K40T 0x00030E), µs.
    fn first_utc_sent_us(&self) -> Option<u64>;
    /// The aircraft (its true position at any instant).
    fn aircraft(&self) -> &Aircraft;
    /// The autopilot's clock when it is a simulated ArduPilot whose MAVLink port can be
    /// attached as the telemetry link ([`super::ap_mavlink::ApMavlink::telemetry`]).
    fn board_clock(&self) -> Option<&super::FcClock> {
        None
    }
    /// Frames the FC's parser dropped.
    fn parse_errors(&self) -> u32;
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
    /// The FC loses power at `now_us` and boots again as `reboot` says (its UTC, and
    /// [`Pilot::true_utc_us`], shifted by [`FcReboot::utc_shift_us`] from power-on).
    fn reboot(&mut self, now_us: u64, reboot: FcReboot);
}

/// `key=value` pairs of a serialised payload: objects are flattened with dotted keys,
/// enumerations (`{"name", "code"}`) print their name, reserved fields are left out.
#[must_use]
pub fn fields_text<T: Serialize + ?Sized>(value: &T) -> String {
    fn walk(prefix: &str, v: &Value, out: &mut Vec<String>) {
        let key = |k: &str| {
            if prefix.is_empty() {
                k.to_string()
            } else {
                format!("{prefix}.{k}")
            }
        };
        match v {
            Value::Object(m) if m.len() == 2 && m.get("name").is_some_and(Value::is_string) => {
                let name = m.get("name").and_then(Value::as_str).unwrap_or_default();
                out.push(if prefix.is_empty() {
                    name.to_string()
                } else {
                    format!("{prefix}={name}")
                });
            }
            Value::Object(m) => {
                for (k, v) in m {
                    if !k.starts_with("reserved") {
                        walk(&key(k), v, out);
                    }
                }
            }
            Value::Array(a) if a.iter().all(Value::is_number) => {
                // Byte strings (names, folders): as text when printable, else their length.
                let bytes: Vec<u8> = a
                    .iter()
                    .filter_map(Value::as_u64)
                    .filter_map(|b| u8::try_from(b).ok())
                    .collect();
                let text: String = bytes
                    .iter()
                    .take_while(|&&b| b != 0)
                    .map(|&b| char::from(b))
                    .collect();
                if bytes.len() == a.len()
                    && bytes.len() > 4
                    && text.chars().all(|c| c.is_ascii_graphic() || c == ' ')
                {
                    if !text.is_empty() {
                        out.push(format!("{prefix}={text:?}"));
                    }
                } else if a.len() <= 6 {
                    let s: Vec<String> = a.iter().map(Value::to_string).collect();
                    out.push(format!("{prefix}=[{}]", s.join(",")));
                } else {
                    out.push(format!("{prefix}=[{} bytes]", a.len()));
                }
            }
            Value::Null => {}
            other => out.push(if prefix.is_empty() {
                other.to_string()
            } else {
                format!("{prefix}={other}")
            }),
        }
    }
    let mut out = Vec::new();
    if let Ok(v) = serde_json::to_value(value) {
        walk("", &untag(v), &mut out);
    }
    out.join(" ")
}

/// Strips enum tags (`{"Request": {"GimbalRotation": {...}}}` → `{...}`).
fn untag(mut v: Value) -> Value {
    loop {
        match v {
            Value::Object(m)
                if m.len() == 1
                    && m.keys()
                        .next()
                        .is_some_and(|k| k.starts_with(|c: char| c.is_ascii_uppercase())) =>
            {
                v = m.into_iter().next().map(|(_, v)| v).unwrap_or_default();
            }
            other => return other,
        }
    }
}

/// A K40T frame decoded for display.
#[must_use]
pub fn describe_k40t(frame: &[u8]) -> Option<Described> {
    let p = k40t::Packet::decode(frame).ok()?;
    let id = p.message.id();
    Some(Described {
        protocol: "K40T",
        id: id.to_u32(),
        digits: 6,
        name: p.message.name().to_string(),
        fields: fields_text(&p.message),
    })
}

/// K40T periodic traffic: reports, status frames, the pod's ACKs (`from_pod`) and
/// (from the FC) its 0x00030E.
#[must_use]
pub fn k40t_routine(id: u32, from_pod: bool) -> bool {
    let kind = (id >> 16) & 0xFF;
    let base = id & 0xFFFF;
    let report = k40t::CATALOG
        .iter()
        .any(|e| u32::from(e.base) == base && e.report);
    report
        || kind == u32::from(Kind::Status.value())
        || (from_pod && kind == u32::from(Kind::Ack.value()))
}

/// The name of a K40T base id.
#[must_use]
pub fn k40t_name(base: u16) -> &'static str {
    k40t::CATALOG
        .iter()
        .find(|e| e.base == base)
        .map_or("?", |e| e.name)
}

impl Pilot for ApSiyi {
    const PROTOCOL: FcProtocol = FcProtocol::Siyi;
    const DRIVER: &'static str = "ArduPilot AP_Mount_Siyi (simulated)";
    type Framing = SiyiFraming;

    fn with_seed(seed: u64) -> Self {
        ApSiyi::new(ApSiyiConfig {
            seed,
            ..ApSiyiConfig::default()
        })
    }

    fn framing(_from_fc: bool) -> SiyiFraming {
        SiyiFraming::new(siyi::MAX_PAYLOAD_LEN)
    }

    fn describe(frame: &[u8], from_fc: bool) -> Option<Described> {
        let direction = if from_fc {
            Direction::ToGimbal
        } else {
            Direction::FromGimbal
        };
        let p = siyi::Packet::decode(frame, direction).ok()?;
        Some(Described {
            protocol: "SIYI",
            id: u32::from(p.message.id()),
            digits: 2,
            name: p.message.name().to_string(),
            fields: fields_text(&p.message),
        })
    }

    fn routine(id: u32, from_fc: bool) -> bool {
        if from_fc {
            // Identity, configuration, attitude, laser, thermal, codec polls and the
            // aircraft's attitude and position.
            matches!(
                id,
                0x00 | 0x01 | 0x02 | 0x0A | 0x0D | 0x14 | 0x15 | 0x20 | 0x22 | 0x3E
            )
        } else {
            // Every reply but the function feedback (photo/record failures).
            id != 0x0B
        }
    }

    fn command_name(fc_id: u16) -> String {
        let name = siyi::CATALOG
            .iter()
            .find(|e| u16::from(e.id) == fc_id)
            .map_or("?", |e| e.name);
        format!("SIYI 0x{fc_id:02X} {name}")
    }

    fn healthy(&self) -> bool {
        ApSiyi::healthy(self)
    }
    fn health_log(&self) -> &[(u64, bool)] {
        &self.health_log
    }
    fn true_utc_us(&self, t_us: u64) -> u64 {
        self.fc_utc_us(t_us)
    }
    fn first_utc_sent_us(&self) -> Option<u64> {
        Self::first_utc_sent_us(self)
    }
    fn board_clock(&self) -> Option<&super::FcClock> {
        Some(self.clock())
    }
    fn aircraft(&self) -> &Aircraft {
        &self.aircraft
    }
    fn parse_errors(&self) -> u32 {
        self.parse_errors
    }
    fn mount_angles(&self) -> Option<(f64, f64)> {
        self.attitude.map(|(_, yaw, pitch, _)| (yaw, pitch))
    }

    fn point(&mut self, yaw_deg: f64, pitch_deg: f64) {
        self.target = Some(MountTarget::Angle { yaw_deg, pitch_deg });
    }
    fn turn(&mut self, yaw_dps: f64, pitch_dps: f64) {
        self.target = Some(MountTarget::Rate {
            yaw_dps,
            pitch_dps,
            yaw_is_ef: false,
        });
    }
    fn zoom(&mut self, rate: i8) {
        self.set_zoom_rate(rate);
    }
    fn take_picture(&mut self) {
        ApSiyi::take_picture(self);
    }
    fn record(&mut self, on: bool) {
        self.record_video(on);
    }
    fn reboot(&mut self, now_us: u64, reboot: FcReboot) {
        ApSiyi::reboot(self, now_us, reboot);
    }
}

impl Pilot for ApViewpro {
    const PROTOCOL: FcProtocol = FcProtocol::Viewlink;
    const DRIVER: &'static str = "ArduPilot AP_Mount_Viewpro (simulated)";
    type Framing = ViewlinkFraming;

    fn with_seed(seed: u64) -> Self {
        ApViewpro::new(ApViewproConfig {
            seed,
            ..ApViewproConfig::default()
        })
    }

    fn framing(_from_fc: bool) -> ViewlinkFraming {
        ViewlinkFraming::new()
    }

    fn describe(frame: &[u8], _from_fc: bool) -> Option<Described> {
        let p = viewlink::Packet::decode(frame).ok()?;
        Some(Described {
            protocol: "Viewlink",
            id: u32::from(p.message.id()),
            digits: 2,
            name: p.message.name().to_string(),
            fields: fields_text(&p.message),
        })
    }

    fn routine(id: u32, from_fc: bool) -> bool {
        if from_fc {
            // Handshake, identity queries (U) and M_AHRS.
            matches!(id, 0x00 | 0x01 | 0xB1)
        } else {
            // Status (0x40) and identity (V) replies.
            true
        }
    }

    fn command_name(fc_id: u16) -> String {
        let [frame, command] = fc_id.to_be_bytes();
        let name = viewlink::CATALOG
            .iter()
            .find(|e| e.id == frame)
            .map_or("?", |e| e.name);
        format!("Viewlink 0x{frame:02X} {name} (command 0x{command:02X})")
    }

    fn healthy(&self) -> bool {
        ApViewpro::healthy(self)
    }
    fn health_log(&self) -> &[(u64, bool)] {
        &self.health_log
    }
    fn true_utc_us(&self, t_us: u64) -> u64 {
        self.fc_utc_us(t_us)
    }
    fn first_utc_sent_us(&self) -> Option<u64> {
        Self::first_utc_sent_us(self)
    }
    fn board_clock(&self) -> Option<&super::FcClock> {
        Some(self.clock())
    }
    fn aircraft(&self) -> &Aircraft {
        &self.aircraft
    }
    fn parse_errors(&self) -> u32 {
        self.parse_errors
    }
    fn mount_angles(&self) -> Option<(f64, f64)> {
        self.attitude.map(|a| (a.yaw_deg, a.pitch_deg))
    }

    fn point(&mut self, yaw_deg: f64, pitch_deg: f64) {
        self.target = Some(MountTarget::Angle { yaw_deg, pitch_deg });
    }
    fn turn(&mut self, yaw_dps: f64, pitch_dps: f64) {
        self.target = Some(MountTarget::Rate {
            yaw_dps,
            pitch_dps,
            yaw_is_ef: false,
        });
    }
    fn zoom(&mut self, rate: i8) {
        self.set_zoom_rate(f64::from(rate));
    }
    fn take_picture(&mut self) {
        ApViewpro::take_picture(self);
    }
    fn record(&mut self, on: bool) {
        self.record_video(on);
    }
    fn reboot(&mut self, now_us: u64, reboot: FcReboot) {
        ApViewpro::reboot(self, now_us, reboot);
    }
}

/// Degrees to the K40T's unsigned 0.01° magnitude.
fn cdeg(deg: f64) -> u16 {
    (deg.abs() * 100.0).round().min(f64::from(u16::MAX)) as u16
}

impl Pilot for FcK40t {
    const PROTOCOL: FcProtocol = FcProtocol::K40t;
    const DRIVER: &'static str = "flight controller speaking K40T (simulated)";
    const STREAMS: bool = false;
    type Framing = K40tFraming;

    fn with_seed(_seed: u64) -> Self {
        // No randomness in this simulator.
        FcK40t::default()
    }

    fn framing(_from_fc: bool) -> K40tFraming {
        K40tFraming::any()
    }

    fn describe(frame: &[u8], _from_fc: bool) -> Option<Described> {
        describe_k40t(frame)
    }

    fn routine(id: u32, from_fc: bool) -> bool {
        if from_fc {
            // Its own 0x00030E every 10 s.
            id == k40t::TimeSync::ID.to_u32()
        } else {
            // What the bridge forwards from the pod, but the pod's GPS requests.
            id != k40t::GpsRequest::ID.to_u32()
        }
    }

    fn command_name(fc_id: u16) -> String {
        format!("K40T 0x{fc_id:06X} {}", k40t_name(fc_id))
    }

    fn healthy(&self) -> bool {
        FcK40t::healthy(self)
    }
    fn health_log(&self) -> &[(u64, bool)] {
        &self.health_log
    }
    fn true_utc_us(&self, t_us: u64) -> u64 {
        self.utc_us(t_us)
    }
    fn first_utc_sent_us(&self) -> Option<u64> {
        Self::first_utc_sent_us(self)
    }
    fn aircraft(&self) -> &Aircraft {
        &self.aircraft
    }
    fn parse_errors(&self) -> u32 {
        0
    }
    fn mount_angles(&self) -> Option<(f64, f64)> {
        let (_, _, a) = self.received_of::<GimbalAttitude>().pop()?;
        Some((
            f64::from(a.yaw_joint_cdeg) / 100.0,
            f64::from(a.pitch_joint_cdeg) / 100.0,
        ))
    }

    fn point(&mut self, yaw_deg: f64, pitch_deg: f64) {
        self.send(&GimbalAngle {
            pitch_direction: if pitch_deg < 0.0 {
                PitchMotion::Down
            } else {
                PitchMotion::Up
            },
            pitch_cdeg: cdeg(pitch_deg),
            yaw_direction: if yaw_deg < 0.0 {
                YawMotion::Left
            } else {
                YawMotion::Right
            },
            yaw_cdeg: cdeg(yaw_deg),
            reserved: 0,
        });
    }
    fn turn(&mut self, yaw_dps: f64, pitch_dps: f64) {
        // Dial speed in 0.2 °/s (5..=150), then the directions, held (repeated) while
        // they turn the pod.
        let x5 = |dps: f64| ((dps.abs() * 5.0).round() as u8).clamp(5, 150);
        self.send(&DialSpeed {
            pitch_dps_x5: x5(pitch_dps),
            yaw_dps_x5: x5(yaw_dps),
            reserved: 0,
        });
        let yaw = match yaw_dps {
            r if r > 0.0 => YawMotion::Right,
            r if r < 0.0 => YawMotion::Left,
            _ => YawMotion::Stop,
        };
        let pitch = match pitch_dps {
            r if r > 0.0 => PitchMotion::Up,
            r if r < 0.0 => PitchMotion::Down,
            _ => PitchMotion::Stop,
        };
        self.hold_motion(GimbalControl {
            function: GimbalFunction::None,
            yaw,
            pitch,
            reserved: 0,
        });
    }
    fn zoom(&mut self, rate: i8) {
        let control = match rate.signum() {
            1 => ZoomControl::In,
            -1 => ZoomControl::Out,
            _ => ZoomControl::Stop,
        };
        self.send(&ContinuousZoom {
            control,
            reserved: 0,
        });
    }
    fn take_picture(&mut self) {
        self.send(&TakePhoto {
            action: ShootAction::Start,
            ..TakePhoto::default()
        });
    }
    fn record(&mut self, on: bool) {
        self.send(&k40t::Record {
            action: if on {
                RecordAction::Start
            } else {
                RecordAction::Stop
            },
            ..k40t::Record::default()
        });
    }
    fn reboot(&mut self, now_us: u64, reboot: FcReboot) {
        FcK40t::reboot(self, now_us, reboot);
    }
}

/// Centidegrees as degrees with two decimals, for display.
fn deg2(cdeg: i32) -> String {
    format!("{:.2}", f64::from(cdeg) / 100.0)
}

impl Pilot for ApXfRobot {
    const PROTOCOL: FcProtocol = FcProtocol::Gcu;
    const DRIVER: &'static str = "ArduPilot AP_Mount_XFRobot (simulated)";
    type Framing = GcuFraming;

    fn with_seed(seed: u64) -> Self {
        ApXfRobot::new(ApXfRobotConfig {
            seed,
            ..ApXfRobotConfig::default()
        })
    }

    fn framing(from_fc: bool) -> GcuFraming {
        if from_fc {
            GcuFraming::host()
        } else {
            GcuFraming::gcu()
        }
    }

    fn describe(frame: &[u8], _from_fc: bool) -> Option<Described> {
        // The control quantities or the gimbal's angles of the main frame, then the
        // order's parameters or its feedback.
        let (id, name, fields) = match gcu::Packet::decode(frame).ok()? {
            gcu::Packet::Host(p) => {
                let m = p.frames.main;
                // The control quantities' unit follows the order (the gimbal mode).
                let unit = match p.message.id() {
                    0x10 | 0x14 => " (0.01°)",
                    0x11..=0x13 | 0x16 => " (0.1°/s)",
                    _ => "",
                };
                let control = format!(
                    "control roll={} pitch={} yaw={}{unit}",
                    m.roll_control, m.pitch_control, m.yaw_control
                );
                let params = fields_text(&p.message);
                let fields = if params.is_empty() || matches!(p.message, gcu::Message::Raw(_)) {
                    control
                } else {
                    format!("{control} {params}")
                };
                (p.message.id(), p.message.name(), fields)
            }
            gcu::Packet::Gcu(p) => {
                let m = p.frames.main;
                let mut fields = format!(
                    "mode={} roll={} pitch={} yaw={}",
                    fields_text(&m.mode),
                    deg2(i32::from(m.rel_x_cdeg)),
                    deg2(i32::from(m.rel_y_cdeg)),
                    deg2(i32::from(m.rel_z_cdeg)),
                );
                if let Some(e) = p.feedback.execution {
                    fields.push_str(" feedback=");
                    fields.push_str(e.name());
                }
                (p.feedback.id(), p.feedback.order.name(), fields)
            }
        };
        Some(Described {
            protocol: "GCU",
            id: u32::from(id),
            digits: 2,
            name: name.to_string(),
            fields,
        })
    }

    fn routine(id: u32, from_fc: bool) -> bool {
        // Every package from ArduPilot carries the control quantities (its commands):
        // none is routine; every reply is.
        let _ = id;
        !from_fc
    }

    fn command_name(fc_id: u16) -> String {
        let name = gcu::CATALOG
            .iter()
            .find(|e| u16::from(e.id) == fc_id)
            .map_or("?", |e| e.name);
        format!("GCU 0x{fc_id:02X} {name}")
    }

    fn healthy(&self) -> bool {
        ApXfRobot::healthy(self)
    }
    fn health_log(&self) -> &[(u64, bool)] {
        &self.health_log
    }
    fn true_utc_us(&self, t_us: u64) -> u64 {
        self.gps_utc_us(t_us)
    }
    fn first_utc_sent_us(&self) -> Option<u64> {
        Self::first_utc_sent_us(self)
    }
    fn board_clock(&self) -> Option<&super::FcClock> {
        Some(self.clock())
    }
    fn aircraft(&self) -> &Aircraft {
        &self.aircraft
    }
    fn parse_errors(&self) -> u32 {
        self.parse_errors
    }
    fn mount_angles(&self) -> Option<(f64, f64)> {
        self.attitude.map(|(_, _, pitch, yaw)| (yaw, pitch))
    }

    fn point(&mut self, yaw_deg: f64, pitch_deg: f64) {
        self.target = Some(ap_xfrobot::MountTarget::Angle {
            roll_deg: 0.0,
            pitch_deg,
            yaw_deg,
            yaw_is_ef: false,
        });
    }
    fn turn(&mut self, yaw_dps: f64, pitch_dps: f64) {
        self.target = Some(ap_xfrobot::MountTarget::Rate {
            pitch_dps,
            yaw_dps,
            yaw_is_ef: false,
        });
    }
    fn zoom(&mut self, rate: i8) {
        self.set_zoom_rate(f64::from(rate));
    }
    fn take_picture(&mut self) {
        ApXfRobot::take_picture(self);
    }
    fn record(&mut self, on: bool) {
        self.record_video(on);
    }
    fn reboot(&mut self, now_us: u64, reboot: FcReboot) {
        ApXfRobot::reboot(self, now_us, reboot);
    }
}
