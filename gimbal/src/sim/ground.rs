//! A ground app (MAVSDK, QGroundControl, a script) on a simulated autopilot's other
//! MAVLink link, as bytes: what a real autopilot's GCS port carries. The runner moves the
//! datagrams between a [`GroundPipe`] and a UDP socket (`gimbal sim-fc mavlink --gcs`);
//! the autopilot ([`super::px4::Px4`], [`super::ap_mavlink::ApMavlink`]) reads the
//! ground app's frames each run, routes them as it routes (docs/src/autopilots/px4.md,
//! docs/src/autopilots/ardupilot.md) and forwards the device's frames to it as they came.
//!
//! - **Frames of any id.** The ground app sends messages the project's dialect does not
//!   know (its own plugins' traffic, MAVLink FTP, extended parameters, the gimbal
//!   manager's inputs): they are framed without their checksum being verified (a
//!   local socket does not corrupt) and forwarded as they came. A message the dialect
//!   knows is decoded, and its target fields read.
//! - **Routing** ([`Route::of`]), as both autopilots route towards a device link: a
//!   message targeted at the autopilot itself (its system, component 1) is its own; one
//!   for component 0 of its system (or system 0) is its own *and* forwarded; one for
//!   another component of its system, or without target fields, is forwarded; one for
//!   another system goes nowhere (no such system on the device link). A message whose
//!   targets cannot be read (an id outside the dialect) is forwarded.
//! - **Towards the ground app**: the device's messages without a target, or for system
//!   0 or the ground app's system (learnt from any of its messages), as they came; and the
//!   autopilot's own messages on this link, numbered by this link's endpoint.

use std::collections::VecDeque;
use std::sync::{Arc, Mutex};

use protocol_core::mavlink::{Header, MAX_FRAME_LEN, MavMessage, MavlinkFraming, Message, Packet};
use protocol_core::wire::{Deframer, Event};

use super::mav::{self, AUTOPILOT, Endpoint};

/// The datagrams between a simulated autopilot and its ground app's transport, shared
/// with the thread that moves them.
#[derive(Debug, Clone, Default)]
pub struct GroundPipe {
    /// From the ground app, each as it came.
    pub to_autopilot: Arc<Mutex<VecDeque<Vec<u8>>>>,
    /// To the ground app: one frame each.
    pub to_ground: Arc<Mutex<VecDeque<Vec<u8>>>>,
}

impl GroundPipe {
    /// A datagram from the ground app.
    pub fn push_from_ground(&self, bytes: &[u8]) {
        if let Ok(mut q) = self.to_autopilot.lock() {
            q.push_back(bytes.to_vec());
        }
    }

    /// The frames for the ground app, in order.
    #[must_use]
    pub fn take_for_ground(&self) -> Vec<Vec<u8>> {
        self.to_ground
            .lock()
            .map(|mut q| q.drain(..).collect())
            .unwrap_or_default()
    }
}

/// A frame from the ground app.
#[derive(Debug, Clone)]
pub struct GroundFrame {
    /// Its header.
    pub header: Header,
    /// Its message id.
    pub id: u32,
    /// The message, when the dialect knows it.
    pub message: Option<MavMessage>,
    /// The payload as sent (trailing zeros possibly dropped).
    pub payload: Vec<u8>,
    /// The whole frame, to forward as it came.
    pub bytes: Vec<u8>,
}

impl GroundFrame {
    /// Its target (system, component), when the dialect knows the message and it has one.
    #[must_use]
    pub fn target(&self) -> Option<(u8, u8)> {
        self.message.as_ref().and_then(mav::target_of)
    }

    /// Payload bytes `at..at + N`, zero-extended (MAVLink 2 trims trailing zeros).
    #[must_use]
    pub fn bytes_at<const N: usize>(&self, at: usize) -> [u8; N] {
        let mut b = [0u8; N];
        for (i, slot) in b.iter_mut().enumerate() {
            *slot = self.payload.get(at + i).copied().unwrap_or(0);
        }
        b
    }

    /// The little-endian `f32` at payload byte `at`.
    #[must_use]
    pub fn f32_at(&self, at: usize) -> f32 {
        f32::from_le_bytes(self.bytes_at(at))
    }
}

/// Where an autopilot routes a frame from its ground app.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Route {
    /// The autopilot handles it.
    pub local: bool,
    /// It goes onto the device link.
    pub forward: bool,
}

impl Route {
    /// The route of `f` through the autopilot of system `sysid` (see the module
    /// documentation).
    #[must_use]
    pub fn of(f: &GroundFrame, sysid: u8) -> Self {
        match f.target() {
            None => Route {
                local: f.message.is_some(),
                forward: true,
            },
            Some((sys, _)) if sys != 0 && sys != sysid => Route {
                local: false,
                forward: false,
            },
            Some((_, AUTOPILOT)) => Route {
                local: true,
                forward: false,
            },
            Some((_, 0)) => Route {
                local: true,
                forward: true,
            },
            Some(_) => Route {
                local: false,
                forward: true,
            },
        }
    }
}

/// The autopilot's end of its link to a ground app.
#[derive(Debug)]
pub struct GroundLink {
    pipe: GroundPipe,
    deframer: Deframer<MavlinkFraming, MAX_FRAME_LEN>,
    me: Endpoint,
    /// The ground app's system and component, from its messages.
    pub app: Option<(u8, u8)>,
    /// Frames received from the ground app.
    pub received: u64,
    /// Frames sent to it (the autopilot's own and the device's forwarded).
    pub sent: u64,
}

impl GroundLink {
    /// The link of the autopilot of system `sysid` (component 1) over `pipe`.
    #[must_use]
    pub fn new(pipe: GroundPipe, sysid: u8) -> Self {
        GroundLink {
            pipe,
            deframer: Deframer::new(MavlinkFraming::delivering_unknown_ids()),
            me: Endpoint::new(sysid, AUTOPILOT),
            app: None,
            received: 0,
            sent: 0,
        }
    }

    /// The frames the ground app sent since the last call.
    pub fn take(&mut self) -> Vec<GroundFrame> {
        let datagrams: Vec<Vec<u8>> = self
            .pipe
            .to_autopilot
            .lock()
            .map(|mut q| q.drain(..).collect())
            .unwrap_or_default();
        let mut out = Vec::new();
        for d in datagrams {
            self.deframer.push(&d, |ev| {
                let Event::Frame(f) = ev else {
                    return;
                };
                let Ok(p) = Packet::decode(f) else {
                    return;
                };
                let (id, message, payload) = match p.message {
                    Message::Known(m) => {
                        let id = mav::id_of(&m);
                        (id, Some(m), payload_of(f))
                    }
                    Message::Raw(r) => (r.id, None, r.payload.to_vec()),
                };
                out.push(GroundFrame {
                    header: p.header,
                    id,
                    message,
                    payload,
                    bytes: f.to_vec(),
                });
            });
        }
        // A route is learnt from any message, as the autopilots learn theirs.
        if let Some(f) = out.last() {
            self.app = Some((f.header.system_id, f.header.component_id));
        }
        self.received += out.len() as u64;
        out
    }

    /// Sends the autopilot's own `msg` to the ground app.
    pub fn send(&mut self, msg: &MavMessage) {
        let frame = self.me.frame(msg);
        self.push(frame);
    }

    /// Forwards a device's frame to the ground app when it is for it (see the module
    /// documentation).
    pub fn forward(&mut self, msg: &MavMessage, bytes: &[u8]) {
        let for_app = match (mav::target_of(msg), self.app) {
            (None, _) => true,
            (Some((0, _)), _) => true,
            (Some((sys, _)), Some((app, _))) => sys == app,
            (Some(_), None) => false,
        };
        if for_app {
            self.push(bytes.to_vec());
        }
    }

    fn push(&mut self, frame: Vec<u8>) {
        if let Ok(mut q) = self.pipe.to_ground.lock() {
            q.push_back(frame);
            self.sent += 1;
        }
    }
}

/// The payload bytes of a MAVLink 2 frame (after the 10-byte header).
fn payload_of(frame: &[u8]) -> Vec<u8> {
    let len = usize::from(frame.get(1).copied().unwrap_or(0));
    frame.get(10..10 + len).unwrap_or_default().to_vec()
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol_core::mavlink::dialect::{HEARTBEAT_DATA, MavCmd};

    #[test]
    fn a_ground_frame_is_routed_by_its_target_and_unknown_ids_are_forwarded() {
        let pipe = GroundPipe::default();
        let mut link = GroundLink::new(pipe.clone(), 1);
        let mut app = Endpoint::new(245, 190);
        pipe.push_from_ground(&app.frame(&MavMessage::HEARTBEAT(HEARTBEAT_DATA::default())));
        let to = |t| mav::request_message(259, t);
        for t in [(1, 1), (1, 0), (1, 100), (7, 100)] {
            pipe.push_from_ground(&app.frame(&to(t)));
        }
        // GIMBAL_MANAGER_SET_ATTITUDE (282, outside the dialect), CRC not checked.
        let mut raw = vec![0xFD, 35, 0, 0, 9, 245, 190, 0x1A, 0x01, 0x00];
        raw.extend([0u8; 35]);
        raw.extend([0x12, 0x34]);
        pipe.push_from_ground(&raw);
        let frames = link.take();
        assert_eq!(link.app, Some((245, 190)));
        let routes: Vec<(u32, Route)> = frames.iter().map(|f| (f.id, Route::of(f, 1))).collect();
        let r = |local, forward| Route { local, forward };
        assert_eq!(
            routes,
            [
                (0, r(true, true)),
                (76, r(true, false)),
                (76, r(true, true)),
                (76, r(false, true)),
                (76, r(false, false)),
                (282, r(false, true)),
            ]
        );
        assert_eq!(frames[5].payload.len(), 35);
        // Towards the app: untargeted and its own system's; the autopilot's own.
        let ack = mav::command_ack(
            MavCmd::MAV_CMD_REQUEST_MESSAGE,
            protocol_core::mavlink::dialect::MavResult::MAV_RESULT_ACCEPTED,
            &Header {
                sequence: 0,
                system_id: 245,
                component_id: 190,
            },
        );
        link.forward(&ack, b"ack");
        let other = mav::request_message(1, (9, 1));
        link.forward(&other, b"other");
        link.send(&MavMessage::HEARTBEAT(HEARTBEAT_DATA::default()));
        let out = pipe.take_for_ground();
        assert_eq!(out.len(), 2);
        assert_eq!(out[0], b"ack");
        assert_eq!(link.sent, 2);
    }
}
