//! AUTOPILOT_VERSION from the bridge's own components (the gimbal and the camera on the
//! MAVLink side, component 158 on the telemetry link): asked with
//! MAV_CMD_REQUEST_MESSAGE(148) or MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES addressed to
//! the component, answered with the ACK, then the message ([`crate::version`] gives its
//! fields' forms). A broadcast request is the autopilot's to answer: a ground station
//! that asks everyone would otherwise take the bridge for a second autopilot.

use protocol_core::mavlink::MavMessage;
use protocol_core::mavlink::dialect::{AUTOPILOT_VERSION_DATA, MavProtocolCapability};

use super::autopilot::Autopilot;
use super::{Cmd, Comp, param_id};
use crate::fc::Ctx;

/// AUTOPILOT_VERSION's message id.
pub(super) const AUTOPILOT_VERSION: u32 = 148;
/// MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES (the older request).
pub(super) const REQUEST_AUTOPILOT_CAPABILITIES: u16 = 520;

/// `c` asks for AUTOPILOT_VERSION (either request).
pub(super) fn asks_version(c: &Cmd) -> bool {
    c.command == REQUEST_AUTOPILOT_CAPABILITIES
        || (c.command == super::cmd::REQUEST_MESSAGE
            && param_id(c.param(1)) == Some(AUTOPILOT_VERSION))
}

/// Sends AUTOPILOT_VERSION from component `comp` (an id).
pub(super) fn send_version(ap: &mut Autopilot, ctx: &mut Ctx<'_>, comp: u8) {
    let b = ctx.build;
    let msg = MavMessage::AUTOPILOT_VERSION(AUTOPILOT_VERSION_DATA {
        // MAVLink 2, and commands as COMMAND_INT as well as COMMAND_LONG.
        capabilities: MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_MAVLINK2
            | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_COMMAND_INT,
        uid: 0,
        flight_sw_version: b.flight_sw_version(),
        middleware_sw_version: 0,
        os_sw_version: 0,
        board_version: 0,
        vendor_id: 0,
        product_id: 0,
        flight_custom_version: b.custom_version(),
        middleware_custom_version: [0; 8],
        os_custom_version: [0; 8],
        uid2: [0; 18],
    });
    ap.send(ctx, comp, &msg);
}

impl super::MavlinkSide {
    /// The ACK and AUTOPILOT_VERSION from `comp` (a command addressed to it).
    pub(super) fn serve_version(&mut self, ctx: &mut Ctx<'_>, c: &Cmd, comp: Comp) {
        self.ack(ctx, comp, c.command, super::result::ACCEPTED, c.from);
        send_version(&mut self.ap, ctx, comp.id());
    }
}
