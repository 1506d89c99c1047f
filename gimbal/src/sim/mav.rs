//! MAVLink plumbing shared by the simulated autopilots ([`super::ap_mavlink`],
//! [`super::px4`]) and the QGroundControl-like client ([`super::qgc`]): an endpoint that
//! numbers its frames, a receiver, command and angle helpers. The simulators use the
//! project's MAVLink 2 codec for bytes (tested on its own against the spec's frames)
//! and decide everything else from what the autopilots and the ground station do
//! (docs/src/autopilots/ardupilot.md, docs/src/autopilots/px4.md,
//! docs/src/autopilots/qgroundcontrol.md), not from the bridge.

use protocol_core::mavlink::dialect::{
    ATTITUDE_DATA, AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA, COMMAND_ACK_DATA, COMMAND_INT_DATA,
    COMMAND_LONG_DATA, EstimatorStatusFlags, GLOBAL_POSITION_INT_DATA, HEARTBEAT_DATA,
    MavAutopilot, MavCmd, MavFrame, MavLandedState, MavModeFlag, MavResult, MavState, MavType,
    Message as _, MessageData as _,
};
use protocol_core::mavlink::{
    self, DEFRAMER_LEN, Header, MAX_FRAME_LEN, MavMessage, MavlinkFraming, Message, Packet,
};
use protocol_core::wire::{Deframer, Event};

use super::board::Aircraft;

/// MAV_COMP_ID_AUTOPILOT1.
pub const AUTOPILOT: u8 = 1;
/// MAV_COMP_ID_GIMBAL.
pub const GIMBAL: u8 = 154;
/// MAV_COMP_ID_CAMERA.
pub const CAMERA: u8 = 100;
/// MAV_COMP_ID_MISSIONPLANNER (QGroundControl's component id).
pub const GCS: u8 = 190;

/// A MAVLink sender: system and component id, its own sequence numbers.
#[derive(Debug, Clone)]
pub struct Endpoint {
    /// System id.
    pub sysid: u8,
    /// Component id.
    pub compid: u8,
    seq: u8,
}

impl Endpoint {
    /// An endpoint whose first frame has sequence number 0.
    #[must_use]
    pub const fn new(sysid: u8, compid: u8) -> Self {
        Endpoint {
            sysid,
            compid,
            seq: 0,
        }
    }

    /// One MAVLink 2 frame of `msg` from this endpoint.
    pub fn frame(&mut self, msg: &MavMessage) -> Vec<u8> {
        let header = Header {
            sequence: self.seq,
            system_id: self.sysid,
            component_id: self.compid,
        };
        self.seq = self.seq.wrapping_add(1);
        let mut buf = [0u8; MAX_FRAME_LEN];
        let n = mavlink::encode(msg, &header, &mut buf).expect("a frame fits MAX_FRAME_LEN");
        buf[..n].to_vec()
    }
}

/// A frame received and decoded.
#[derive(Debug, Clone)]
pub struct Received {
    /// Its header.
    pub header: Header,
    /// The message (ids outside the dialect are not delivered).
    pub message: MavMessage,
    /// The frame's bytes (for routing it on as it came).
    pub bytes: Vec<u8>,
}

/// A MAVLink 2 receiver.
#[derive(Debug, Clone)]
pub struct Rx {
    deframer: Deframer<MavlinkFraming, DEFRAMER_LEN>,
    /// Frames whose content the dialect could not represent.
    pub undecodable: u32,
}

impl Default for Rx {
    fn default() -> Self {
        Rx {
            deframer: Deframer::new(MavlinkFraming::new()),
            undecodable: 0,
        }
    }
}

impl Rx {
    /// The frames completed by `bytes`.
    pub fn push(&mut self, bytes: &[u8]) -> Vec<Received> {
        let mut out = Vec::new();
        let mut bad = 0;
        self.deframer.push(bytes, |ev| {
            if let Event::Frame(f) = ev {
                match Packet::decode(f) {
                    Ok(Packet {
                        header,
                        message: Message::Known(message),
                        ..
                    }) => out.push(Received {
                        header,
                        message,
                        bytes: f.to_vec(),
                    }),
                    _ => bad += 1,
                }
            }
        });
        self.undecodable += bad;
        out
    }

    /// The frames completed by `bytes`, each with the number of bytes that came after
    /// it up to the end of `bytes` (those the parser had not consumed yet when the
    /// frame completed: what a UART driver would still count as available).
    pub fn push_counting(&mut self, bytes: &[u8]) -> Vec<(Received, usize)> {
        let mut out = Vec::new();
        let mut bad = 0;
        self.deframer.push_counting_after(bytes, |ev, after| {
            if let Event::Frame(f) = ev {
                match Packet::decode(f) {
                    Ok(Packet {
                        header,
                        message: Message::Known(message),
                        ..
                    }) => out.push((
                        Received {
                            header,
                            message,
                            bytes: f.to_vec(),
                        },
                        after,
                    )),
                    _ => bad += 1,
                }
            }
        });
        self.undecodable += bad;
        out
    }

    /// Frames dropped for a bad checksum or length (the parser's errors).
    #[must_use]
    pub fn errors(&self) -> u32 {
        let s = self.deframer.stats();
        s.checksum_errors.saturating_add(s.length_errors)
    }
}

/// A TIMESYNC request a simulated autopilot answered.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TimesyncAnswer {
    /// The requester.
    pub from: Header,
    /// True time the autopilot handled the request (ArduPilot: the loop that read it;
    /// PX4: the receive thread's parse).
    pub handled_at_us: u64,
    /// True time the reply's burst starts on the wire.
    pub sent_at_us: u64,
    /// The request's `ts1`, echoed.
    pub ts1: i64,
    /// The reply's `tc1`: the autopilot's boot clock in ns.
    pub tc1: i64,
    /// The reply's target system and component.
    pub target: (u8, u8),
}

/// A COMMAND_LONG.
#[must_use]
pub fn command_long(
    command: MavCmd,
    p: [f32; 7],
    target: (u8, u8),
    confirmation: u8,
) -> MavMessage {
    MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
        param1: p[0],
        param2: p[1],
        param3: p[2],
        param4: p[3],
        param5: p[4],
        param6: p[5],
        param7: p[6],
        command,
        target_system: target.0,
        target_component: target.1,
        confirmation,
    })
}

/// A COMMAND_INT: `p` param1..4, `x` and `y` (e.g. latitude and longitude, degE7), `z`,
/// in `frame`.
#[must_use]
pub fn command_int(
    command: MavCmd,
    p: [f32; 4],
    (x, y, z): (i32, i32, f32),
    frame: MavFrame,
    target: (u8, u8),
) -> MavMessage {
    MavMessage::COMMAND_INT(COMMAND_INT_DATA {
        param1: p[0],
        param2: p[1],
        param3: p[2],
        param4: p[3],
        x,
        y,
        z,
        command,
        target_system: target.0,
        target_component: target.1,
        frame,
        current: 0,
        autocontinue: 0,
    })
}

/// The bearing from north (degrees, to the right) and the elevation above the horizon
/// (degrees) of `to` seen from `from`, each `(lat, lon degE7, alt m)`, in a flat-earth
/// frame (as ArduPilot and PX4 point a gimbal at a location).
#[must_use]
pub fn bearing_elevation(from: (i32, i32, f64), to: (i32, i32, f64)) -> (f64, f64) {
    let m_per_e7 = 111_320.0 / 1e7;
    let north = f64::from(to.0 - from.0) * m_per_e7;
    let east = f64::from(to.1 - from.1) * m_per_e7 * (f64::from(from.0) / 1e7).to_radians().cos();
    let up = to.2 - from.2;
    (
        east.atan2(north).to_degrees(),
        up.atan2(north.hypot(east)).to_degrees(),
    )
}

/// A camera command of four parameters (the other three 0), unconfirmed.
#[must_use]
pub fn camera_command(command: MavCmd, p: [f32; 4], target: (u8, u8)) -> MavMessage {
    command_long(command, [p[0], p[1], p[2], p[3], 0.0, 0.0, 0.0], target, 0)
}

/// MAV_CMD_VIDEO_START_CAPTURE (`on`) or MAV_CMD_VIDEO_STOP_CAPTURE.
#[must_use]
pub fn video_capture(on: bool) -> MavCmd {
    if on {
        MavCmd::MAV_CMD_VIDEO_START_CAPTURE
    } else {
        MavCmd::MAV_CMD_VIDEO_STOP_CAPTURE
    }
}

/// MAV_CMD_REQUEST_MESSAGE for message `id`, to `target`.
#[must_use]
pub fn request_message(id: u32, target: (u8, u8)) -> MavMessage {
    let p = [id as f32, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    command_long(MavCmd::MAV_CMD_REQUEST_MESSAGE, p, target, 0)
}

/// The COMMAND_ACK of `command` with `result`, to the sender `to`.
#[must_use]
pub fn command_ack(command: MavCmd, result: MavResult, to: &Header) -> MavMessage {
    MavMessage::COMMAND_ACK(COMMAND_ACK_DATA {
        command,
        result,
        progress: 0,
        result_param2: 0,
        target_system: to.system_id,
        target_component: to.component_id,
    })
}

/// An autopilot's HEARTBEAT (custom mode, standby).
#[must_use]
pub fn autopilot_heartbeat(mavtype: MavType, autopilot: MavAutopilot) -> MavMessage {
    MavMessage::HEARTBEAT(HEARTBEAT_DATA {
        custom_mode: 0,
        mavtype,
        autopilot,
        base_mode: MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED,
        system_status: MavState::MAV_STATE_STANDBY,
        mavlink_version: 3,
    })
}

/// A message of no target, or with target system 0 or `sysid`: routed to system `sysid`.
#[must_use]
pub fn routed_to(msg: &MavMessage, sysid: u8) -> bool {
    target_of(msg).is_none_or(|(sys, _)| sys == 0 || sys == sysid)
}

/// The aircraft as an autopilot's streams tell it at one instant.
#[derive(Debug, Clone, Copy)]
pub struct AircraftState {
    /// The boot clock, ms (truncated).
    pub boot_ms: u32,
    /// Latitude, longitude, 1e-7 degrees.
    pub lat_lon_e7: (i32, i32),
    /// Altitude above mean sea level, mm.
    pub alt_mm: i32,
    /// Roll, pitch, yaw, degrees.
    pub attitude_deg: (f64, f64, f64),
    /// North and east velocity, m/s.
    pub velocity_m_s: (f64, f64),
}

impl AircraftState {
    /// `aircraft` at true time `t_us`, the boot clock reading `boot_us`.
    #[must_use]
    pub fn of(aircraft: &Aircraft, t_us: u64, boot_us: u64) -> Self {
        AircraftState {
            boot_ms: (boot_us / 1000) as u32,
            lat_lon_e7: aircraft.position_e7(t_us),
            alt_mm: (aircraft.alt_msl_m * 1000.0) as i32,
            attitude_deg: aircraft.attitude_deg(t_us),
            velocity_m_s: aircraft.velocity_m_s(),
        }
    }

    /// ATTITUDE (no rotation rates).
    #[must_use]
    pub fn attitude(&self) -> MavMessage {
        let (roll, pitch, yaw) = self.attitude_deg;
        MavMessage::ATTITUDE(ATTITUDE_DATA {
            time_boot_ms: self.boot_ms,
            roll: roll.to_radians() as f32,
            pitch: pitch.to_radians() as f32,
            yaw: yaw.to_radians() as f32,
            rollspeed: 0.0,
            pitchspeed: 0.0,
            yawspeed: 0.0,
        })
    }

    /// GLOBAL_POSITION_INT with this relative altitude (mm).
    #[must_use]
    pub fn global_position(&self, relative_alt_mm: i32) -> MavMessage {
        let (vn, ve) = self.velocity_m_s;
        MavMessage::GLOBAL_POSITION_INT(GLOBAL_POSITION_INT_DATA {
            time_boot_ms: self.boot_ms,
            lat: self.lat_lon_e7.0,
            lon: self.lat_lon_e7.1,
            alt: self.alt_mm,
            relative_alt: relative_alt_mm,
            vx: (vn * 100.0) as i16,
            vy: (ve * 100.0) as i16,
            vz: 0,
            hdg: (self.attitude_deg.2.rem_euclid(360.0) * 100.0) as u16,
        })
    }

    /// AUTOPILOT_STATE_FOR_GIMBAL_DEVICE stamped `time_boot_us`, to `target_system`.
    #[must_use]
    pub fn autopilot_state(
        &self,
        time_boot_us: u64,
        estimator_status: u16,
        target_system: u8,
        landed_state: MavLandedState,
    ) -> MavMessage {
        let (roll, pitch, yaw) = self.attitude_deg;
        let (vn, ve) = self.velocity_m_s;
        MavMessage::AUTOPILOT_STATE_FOR_GIMBAL_DEVICE(AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA {
            time_boot_us,
            q: quat_deg(roll, pitch, yaw),
            q_estimated_delay_us: 0,
            vx: vn as f32,
            vy: ve as f32,
            vz: 0.0,
            v_estimated_delay_us: 0,
            feed_forward_angular_velocity_z: 0.0,
            estimator_status: EstimatorStatusFlags::from_bits_retain(estimator_status),
            target_system,
            target_component: 0,
            landed_state,
            angular_velocity_z: 0.0,
        })
    }
}

/// A message's target (system, component), for messages that have one.
#[must_use]
pub fn target_of(msg: &MavMessage) -> Option<(u8, u8)> {
    Some((msg.target_system_id()?, msg.target_component_id()?))
}

/// The message id.
#[must_use]
pub fn id_of(msg: &MavMessage) -> u32 {
    msg.message_id()
}

/// The message id of a message type.
#[must_use]
pub fn id<M: protocol_core::mavlink::MessageData>() -> u32 {
    M::ID
}

/// The quaternion `[w, x, y, z]` of roll, pitch, yaw in degrees (ZYX).
#[must_use]
pub fn quat_deg(roll: f64, pitch: f64, yaw: f64) -> [f32; 4] {
    let (sr, cr) = (roll.to_radians() / 2.0).sin_cos();
    let (sp, cp) = (pitch.to_radians() / 2.0).sin_cos();
    let (sy, cy) = (yaw.to_radians() / 2.0).sin_cos();
    [
        (cr * cp * cy + sr * sp * sy) as f32,
        (sr * cp * cy - cr * sp * sy) as f32,
        (cr * sp * cy + sr * cp * sy) as f32,
        (cr * cp * sy - sr * sp * cy) as f32,
    ]
}

/// Roll, pitch, yaw in degrees of a quaternion (`None` if not finite).
#[must_use]
pub fn euler_deg(q: [f32; 4]) -> Option<(f64, f64, f64)> {
    if q.iter().any(|c| !c.is_finite()) {
        return None;
    }
    let [w, x, y, z] = q.map(f64::from);
    let n = (w * w + x * x + y * y + z * z).sqrt();
    if n < 1e-9 {
        return None;
    }
    let (w, x, y, z) = (w / n, x / n, y / n, z / n);
    let roll = (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y));
    let pitch = (2.0 * (w * y - z * x)).clamp(-1.0, 1.0).asin();
    let yaw = (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z));
    Some((roll.to_degrees(), pitch.to_degrees(), yaw.to_degrees()))
}

/// A message-id check for tests: `M::ID == id`.
#[must_use]
pub fn is<M: protocol_core::mavlink::MessageData>(id: u32) -> bool {
    M::ID == id
}

/// `COMMAND_LONG_DATA::ID`, for routing checks.
pub const COMMAND_LONG_ID: u32 = COMMAND_LONG_DATA::ID;

/// Test helpers: bytes as a UART hands them over, a driver that records every loop.
#[cfg(test)]
pub(crate) mod testing {
    use super::super::peer::Peer;
    use super::Endpoint;
    use protocol_core::mavlink::dialect::{MavCmd, TIMESYNC_DATA};

    /// µs of one byte (10 bits) at `baud`.
    pub(crate) fn byte_us(baud: u32) -> f64 {
        1e7 / f64::from(baud)
    }

    /// `bytes` whose first start bit is at true `t0_us`, as a UART hands them over:
    /// chunks of up to 16 bytes, each at the arrival of its last stop bit (rounded up).
    pub(crate) fn uart_chunks(t0_us: u64, baud: u32, bytes: &[u8]) -> Vec<(u64, Vec<u8>)> {
        bytes
            .chunks(16)
            .scan(0usize, |sent, c| {
                *sent += c.len();
                let at = t0_us + (*sent as f64 * byte_us(baud)).ceil() as u64;
                Some((at, c.to_vec()))
            })
            .collect()
    }

    /// A TIMESYNC request (tc1 0) with `ts1`, to `target`.
    pub(crate) fn timesync_request(ts1: i64, target: (u8, u8)) -> super::MavMessage {
        super::MavMessage::TIMESYNC(TIMESYNC_DATA {
            tc1: 0,
            ts1,
            target_system: target.0,
            target_component: target.1,
        })
    }

    /// MAV_CMD_SET_MESSAGE_INTERVAL of message `id` to system 1's autopilot.
    pub(crate) fn set_interval(id: u32, interval_us: f32) -> super::MavMessage {
        super::command_long(
            MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL,
            [id as f32, interval_us, 0.0, 0.0, 0.0, 0.0, 0.0],
            (1, super::AUTOPILOT),
            0,
        )
    }

    /// Drives a simulated FC in true time as the scenario does: each wakeup polled at
    /// its instant, each chunk received at its instant (after the wakeups before it).
    pub(crate) struct Driver {
        /// Instants the FC was polled at.
        pub wakeups: Vec<u64>,
        /// Its bursts: (start, bytes).
        pub bursts: Vec<(u64, Vec<u8>)>,
    }

    impl Driver {
        pub(crate) fn new() -> Self {
            Driver {
                wakeups: Vec::new(),
                bursts: Vec::new(),
            }
        }

        /// Polls every wakeup up to `t_us` included.
        pub(crate) fn run_until(&mut self, fc: &mut impl Peer, t_us: u64) {
            while fc.next_wakeup() <= t_us {
                let w = fc.next_wakeup();
                self.wakeups.push(w);
                fc.poll(w);
                self.bursts.extend(fc.transmit(w));
            }
        }

        /// Hands `chunks` over, each at its instant.
        pub(crate) fn deliver(&mut self, fc: &mut impl Peer, chunks: &[(u64, Vec<u8>)]) {
            for (at, c) in chunks {
                self.run_until(fc, at - 1);
                fc.receive(*at, c);
                self.bursts.extend(fc.transmit(*at));
            }
        }

        /// `msg` from `dev`, its first start bit at `t0_us` on a 115 200 baud line.
        pub(crate) fn send(
            &mut self,
            fc: &mut impl Peer,
            t0_us: u64,
            dev: &mut Endpoint,
            msg: &super::MavMessage,
        ) {
            self.deliver(fc, &uart_chunks(t0_us, 115_200, &dev.frame(msg)));
        }

        /// Every frame sent, with the start of its burst.
        pub(crate) fn frames(&self) -> Vec<(u64, super::Received)> {
            let mut rx = super::Rx::default();
            let mut bursts = self.bursts.clone();
            bursts.sort_by_key(|(at, _)| *at);
            bursts
                .iter()
                .flat_map(|(at, b)| rx.push(b).into_iter().map(move |r| (*at, r)))
                .collect()
        }
    }
}
