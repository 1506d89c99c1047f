//! MAVLink plumbing shared by the simulated autopilots ([`super::ap_mavlink`],
//! [`super::px4`]) and the QGroundControl-like client ([`super::qgc`]): an endpoint that
//! numbers its frames, a receiver, command and angle helpers. The simulators use the
//! project's MAVLink 2 codec for bytes (tested on its own against the spec's frames)
//! and decide everything else from `shared/MAVLINK-TRAFFIC.md`, not from the bridge.

use protocol_core::mavlink::dialect::{COMMAND_LONG_DATA, MavCmd, Message as _, MessageData as _};
use protocol_core::mavlink::{
    self, Header, MAX_FRAME_LEN, MavMessage, MavlinkFraming, Message, Packet,
};
use protocol_core::wire::{Deframer, Event};

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
    deframer: Deframer<MavlinkFraming, MAX_FRAME_LEN>,
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

    /// Frames dropped for a bad checksum or length (the parser's errors).
    #[must_use]
    pub fn errors(&self) -> u32 {
        let s = self.deframer.stats();
        s.checksum_errors.saturating_add(s.length_errors)
    }
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

/// A MAVLink frame decoded for display (the demo and traces).
#[must_use]
pub fn describe(frame: &[u8]) -> Option<super::pilot::Described> {
    let p = Packet::decode(frame).ok()?;
    let Message::Known(m) = &p.message else {
        return None;
    };
    let id = m.message_id();
    Some(super::pilot::Described {
        protocol: "MAVLink",
        id,
        digits: 0,
        name: m.message_name().to_string(),
        fields: format!(
            "from {}/{} {}",
            p.header.system_id,
            p.header.component_id,
            super::pilot::fields_text(m)
        ),
    })
}

/// A message-id check for tests: `M::ID == id`.
#[must_use]
pub fn is<M: protocol_core::mavlink::MessageData>(id: u32) -> bool {
    M::ID == id
}

/// `COMMAND_LONG_DATA::ID`, for routing checks.
pub const COMMAND_LONG_ID: u32 = COMMAND_LONG_DATA::ID;
