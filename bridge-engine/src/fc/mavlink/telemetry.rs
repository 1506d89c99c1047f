//! The telemetry link: a MAVLink 2 port of the autopilot (ArduPilot `SERIALn_PROTOCOL`
//! 2, PX4 `MAV_n_CONFIG`) beside a SIYI, Viewlink, GCU or K40T FC link, or beside the
//! MAVLink FC side when that link gives no time or fixes (PX4 1.16 in mode Gimbal).
//!
//! The bridge is a peripheral there (component 158, MAV_COMP_ID_PERIPHERAL; HEARTBEAT
//! type GENERIC, autopilot INVALID, at 1 Hz once the autopilot is heard, with its system
//! id): it asks for SYSTEM_TIME, GLOBAL_POSITION_INT, ATTITUDE and GPS_RAW_INT, runs
//! TIMESYNC and answers the autopilot's TIMESYNC requests ([`autopilot`](super::autopilot)).
//! Every message that changes something passes the gate first, as on the MAVLink side
//! (docs/src/security.md, "The gate": one from a system that may not command is refused
//! and reported, a command naming this component answered DENIED). The one command it
//! serves is a request of its version (AUTOPILOT_VERSION, addressed to component 158:
//! [`version`](super::version)); any other command addressed to it gets COMMAND_ACK
//! UNSUPPORTED, and broadcast commands are left alone (a ground station's broadcast
//! reaches every component; the autopilot answers it). Each photo the pod geotags goes
//! out as CAMERA_IMAGE_CAPTURED (broadcast: the photo's UTC on the disciplined clock, the
//! fix interpolated there, the aircraft's attitude), which the autopilot forwards to the
//! ground station and its telemetry log records (docs/src/bridge/telemetry.md).
//!
//! While the autopilot gives time on it ([`TelemetrySide::gives_time`]: heard within
//! 3 s, its SYSTEM_TIME stream coming), the engine takes UTC and fixes from this link
//! and not from the FC link's protocol (`Ctx::feeds`).

use crate::geotag::Photo;
use crate::time::{Duration, Instant};
use protocol_core::mavlink::dialect::{
    CAMERA_IMAGE_CAPTURED_DATA, CharArray, HEARTBEAT_DATA, MavAutopilot, MavBool, MavModeFlag,
    MavState, MavType,
};
use protocol_core::mavlink::{Frame, Header, MavMessage, MavlinkFraming, Message, Packet};

use super::super::{Ctx, FcHandler, TimedFrom};
use super::autopilot::{Autopilot, Heartbeat, Took};
use super::{Cmd, ack, bridge_params, result, version};
use crate::access::Refusal;

/// MAV_COMP_ID_PERIPHERAL: the bridge's component on the telemetry link.
pub(crate) const TELEMETRY_COMPONENT: u8 = 158;
/// HEARTBEAT period.
const HEARTBEAT_PERIOD: Duration = Duration::from_secs(1);

/// The telemetry link's decisions (its deframer and timing are the `FcLink`'s).
#[derive(Debug, Clone)]
pub(crate) struct TelemetrySide {
    ap: Autopilot,
    next_heartbeat: Instant,
    /// Photos reported (the next image index).
    images: i32,
    /// The bridge's settings as parameters of this component.
    params: super::bridge_params::BridgeParams,
}

impl TelemetrySide {
    pub(crate) fn new(config: &crate::Config) -> Self {
        TelemetrySide {
            ap: Autopilot::new(TELEMETRY_COMPONENT, config),
            next_heartbeat: Instant::ZERO,
            images: 0,
            params: super::bridge_params::BridgeParams::default(),
        }
    }

    /// A photo the pod geotagged: CAMERA_IMAGE_CAPTURED, once the autopilot is heard.
    pub(crate) fn photo(&mut self, ctx: &mut Ctx<'_>, p: &Photo) {
        if self.ap.sysid.is_none() {
            return;
        }
        let f = &p.fix;
        let mm = |dm: i16| i32::from(dm).saturating_mul(100);
        let msg = MavMessage::CAMERA_IMAGE_CAPTURED(CAMERA_IMAGE_CAPTURED_DATA {
            time_utc: p.utc.as_unix_micros(),
            time_boot_ms: u32::try_from(f.at.as_millis() % (1u64 << 32)).unwrap_or(0),
            lat: f.lat_e7,
            lon: f.lon_e7,
            alt: mm(f.alt_msl_dm),
            relative_alt: mm(f.rel_alt_dm),
            q: super::math::quaternion([
                super::math::rad(i32::from(f.roll_cdeg)),
                super::math::rad(i32::from(f.pitch_cdeg)),
                super::math::rad(i32::from(f.yaw_cdeg)),
            ]),
            image_index: self.images,
            camera_id: 0,
            capture_result: MavBool::MAV_BOOL_TRUE,
            file_url: CharArray::from([0u8; 205]),
        });
        self.images = self.images.saturating_add(1);
        self.ap.send(ctx, TELEMETRY_COMPONENT, &msg);
    }

    /// The link's signing (the engine saves and restores its timestamp and key).
    pub(crate) fn signing(&mut self) -> &mut super::LinkSigning {
        &mut self.ap.signing
    }

    /// The autopilot gives time on this link: it is the source of UTC and fixes.
    pub(crate) fn gives_time(&self, now: Instant) -> bool {
        self.ap.gives_time(now)
    }

    /// A command addressed to this component, past the gate: its version, or UNSUPPORTED.
    fn command(&mut self, ctx: &mut Ctx<'_>, c: &Cmd) {
        let result = if version::asks_version(c) {
            result::ACCEPTED
        } else {
            result::UNSUPPORTED
        };
        self.ack(ctx, c, result);
        if result == result::ACCEPTED {
            version::send_version(&mut self.ap, ctx, TELEMETRY_COMPONENT);
        }
    }

    /// COMMAND_ACK from this component to the sender of `c`.
    fn ack(&mut self, ctx: &mut Ctx<'_>, c: &Cmd, result: u8) {
        ack(
            &mut self.ap,
            ctx,
            TELEMETRY_COMPONENT,
            c.command,
            result,
            c.from,
        );
    }

    fn heartbeat(&mut self, ctx: &mut Ctx<'_>) {
        let hb = MavMessage::HEARTBEAT(HEARTBEAT_DATA {
            custom_mode: 0,
            mavtype: MavType::MAV_TYPE_GENERIC,
            autopilot: MavAutopilot::MAV_AUTOPILOT_INVALID,
            base_mode: MavModeFlag::empty(),
            system_status: MavState::MAV_STATE_ACTIVE,
            mavlink_version: 3,
        });
        self.ap.send(ctx, TELEMETRY_COMPONENT, &hb);
    }
}

impl FcHandler for TelemetrySide {
    type Framing = MavlinkFraming;
    // An autopilot composes each message when it writes it.
    const TIMED_FROM: TimedFrom = TimedFrom::Frame;

    fn frame(&mut self, ctx: &mut Ctx<'_>, f: &[u8]) {
        ctx.seen();
        let Ok(frame) = Frame::new_checked(f) else {
            return;
        };
        let Some(signed) = self.ap.admit(ctx, f) else {
            return;
        };
        let h = Header {
            sequence: frame.sequence(),
            system_id: frame.system_id(),
            component_id: frame.component_id(),
        };
        // The gate, as on the MAVLink side (docs/src/security.md, "The gate"); a command
        // naming this component from a sender that may not command is told DENIED.
        if let Some(refusal) = self.ap.gate(ctx, &frame, signed, &[TELEMETRY_COMPONENT]) {
            if refusal == Refusal::Sender
                && let Some(c) = Cmd::from_payload(frame.message_id(), frame.payload_ref(), h)
                && c.target_component == TELEMETRY_COMPONENT
            {
                self.ack(ctx, &c, result::DENIED);
            }
            return;
        }
        if let Some(c) = Cmd::from_payload(frame.message_id(), frame.payload_ref(), h)
            && c.target_component == TELEMETRY_COMPONENT
            && self.ap.sysid.is_some_and(|s| s == c.target_system)
        {
            self.command(ctx, &c);
            return;
        }
        if let id @ (bridge_params::REQUEST_READ
        | bridge_params::REQUEST_LIST
        | bridge_params::SET) = frame.message_id()
        {
            if self.ap.sysid.is_some() {
                let p = frame.payload_ref();
                self.params
                    .request(ctx, &mut self.ap, TELEMETRY_COMPONENT, id, p);
            }
            return;
        }
        let Ok(Message::Known(m)) = Packet::parse(&frame).map(|p| p.message) else {
            return;
        };
        if let MavMessage::SETUP_SIGNING(s) = &m {
            self.ap.setup_signing(ctx, h, s, signed);
            return;
        }
        if let MavMessage::HEARTBEAT(hb) = &m {
            if self.ap.heartbeat(ctx, h, hb) == Heartbeat::New {
                self.next_heartbeat = ctx.now;
            }
            return;
        }
        if self.ap.message(ctx, h, &m) == Took::No {
            ctx.ignored();
        }
    }

    fn poll(&mut self, ctx: &mut Ctx<'_>) {
        if self.ap.sysid.is_none() {
            return;
        }
        if ctx.now >= self.next_heartbeat {
            self.next_heartbeat = ctx.now.saturating_add(HEARTBEAT_PERIOD);
            self.heartbeat(ctx);
        }
        self.ap.poll(ctx);
        self.params.poll(ctx, &mut self.ap, TELEMETRY_COMPONENT);
    }

    fn poll_at(&self) -> Option<Instant> {
        let hb = self.ap.sysid.map(|_| self.next_heartbeat);
        let params = self.ap.sysid.and(self.params.poll_at());
        [hb, self.ap.poll_at(), params].into_iter().flatten().min()
    }
}
