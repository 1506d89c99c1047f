//! What a MAVLink device learns from the autopilot on its link, shared by the MAVLink FC
//! side and the telemetry link: the autopilot's identity, the streams asked of it, the
//! aircraft's attitude and position, and time (see docs/src/bridge/time.md and
//! docs/src/bridge/geotag.md; what ArduPilot and PX4 send and answer:
//! docs/src/autopilots/ardupilot.md, docs/src/autopilots/px4.md).
//!
//! # Time: TIMESYNC and SYSTEM_TIME
//! The bridge learns the autopilot's boot clock against its own with TIMESYNC, and UTC
//! against the boot clock from SYSTEM_TIME; UTC = local → boot → UTC.
//!
//! - **Requests.** Once the autopilot is known, a TIMESYNC request (tc1 = 0, ts1 = the
//!   bridge's clock in ns, the autopilot as target) goes out every 50..100 ms twelve
//!   times, then every 150..350 ms (dithered to the microsecond, so that its arrival
//!   does not lock to the autopilot's loop), when nothing else waits to be sent. One is
//!   outstanding at a time; a reply is matched on its ts1 (ArduPilot's TIMESYNC has no
//!   target fields: its own requests every 10 s, and a ground station's requests and
//!   replies, are routed onto the link too) and taken within [`TIMESYNC_MAX_RTT`].
//! - **Where the autopilot read tc1.** Each reply says the autopilot's boot clock read
//!   tc1 at some instant after the request started: the boot clock when the bridge
//!   queued it (no later than its start) was at most tc1, a *lower bound* of the offset,
//!   and the bound holds whatever delays the reply (the autopilot's loop, its output
//!   buffer, 10 ms of transport jitter: none of them enters it). How tight it is depends
//!   on where tc1 was read (see docs/src/bridge/time.md): ArduPilot stamps it with its
//!   UART's estimate of the request's *start* (`receive_time_constraint_us`, never
//!   earlier than the start): tight to that estimate. PX4 reads it when its receive
//!   thread parses the request, after its *end*: tc1 less the request's serial time is
//!   the bound, tight to PX4's parse latency. Any other autopilot: tc1 itself (looser by
//!   up to the request's serial time, never wrong). The discipline keeps the tightest
//!   bound of each bin (its minimum filter on negated points): the low-round-trip samples
//!   are the ones that count.
//! - **SYSTEM_TIME.** Both fields are read from one clock in one call: `d =
//!   time_unix_usec − 1000·time_boot_ms` is the UTC − boot shift plus the sub-millisecond
//!   phase truncated off `time_boot_ms`, so the least `d` over a few seconds is the shift
//!   (the discipline's `system_time`); the transport delay cancels. `time_unix_usec` 0
//!   (ArduPilot before its clock is set) is no time; a `d` that steps makes UTC invalid
//!   until the new shift is confirmed. The discipline uses the boot clock only once `d`
//!   shows UTC in step with it; a `d` that runs apart (a simulator in lockstep: PX4 SITL)
//!   makes each SYSTEM_TIME a direct UTC sample, timed by its arrival less its serial
//!   time.
//! - **A faster link.** A TIMESYNC reply back in less than half the time the request and
//!   the reply take at the configured rate shows a link faster than that UART (a
//!   pseudo-terminal, a socket to a simulator): its frames are then taken to spend no
//!   serial time (SYSTEM_TIME's transit, PX4's tc1 correction).
//! - **No TIMESYNC.** If the autopilot answers none within [`TIMESYNC_GRACE`] of its
//!   first SYSTEM_TIME, SYSTEM_TIME is used alone as a direct UTC sample, timed from the
//!   frame's first byte (the earlier, coarser estimate); a later reply switches to the
//!   TIMESYNC path.

use crate::discipline::{Sample, serial_time};
use crate::event::Event;
use crate::fixes::{Fix, Velocity};
use crate::time::{Duration, Instant};
use protocol_core::mavlink::dialect::{
    GLOBAL_POSITION_INT_DATA, GPS_RAW_INT_DATA, GpsFixType, HEARTBEAT_DATA, MavAutopilot, MavCmd,
    MavType, SETUP_SIGNING_DATA, SYSTEM_TIME_DATA, TIMESYNC_DATA,
};
use protocol_core::mavlink::{
    self, Header, MAX_FRAME_LEN, MavMessage, Message, Packet, Raw, Signer,
};

use super::super::{Ctx, clamp_i16};
use super::math;
use super::signing::{Check, LinkSigning};
use crate::access::{Gated, Refusal};
use crate::store;

/// The autopilot's component id.
pub(super) const AUTOPILOT: u8 = 1;
/// A stream not received for this long is asked for again.
const STREAM_STALE: Duration = Duration::from_secs(3);
/// Tries of SET_MESSAGE_INTERVAL a second apart before slowing to one every
/// [`STREAM_BACKOFF`].
const STREAM_QUICK_TRIES: u8 = 5;
/// Retry period after the quick tries.
const STREAM_BACKOFF: Duration = Duration::from_secs(10);
/// The aircraft's attitude older than this is not used.
const VEHICLE_FRESH: Duration = Duration::from_secs(1);
/// A GPS_RAW_INT 3D fix older than this does not make positions fixes.
const GPS_FRESH: Duration = Duration::from_secs(3);
/// The autopilot is gone after this long without its HEARTBEAT (1 Hz).
#[cfg(feature = "telemetry")]
const AUTOPILOT_GONE: Duration = Duration::from_secs(3);
/// A TIMESYNC reply later than this after its request is not used.
pub(crate) const TIMESYNC_MAX_RTT: Duration = Duration::from_millis(200);
/// Least time between TIMESYNC requests, µs; a dither of up to [`TIMESYNC_SPREAD_US`]
/// (in microseconds, so that the requests' phase against the autopilot's loop takes
/// every value: whole milliseconds would leave a 2.5 ms loop only a few phases, and its
/// least reply latency up to half a millisecond).
const TIMESYNC_MIN_PERIOD_US: u32 = 150_000;
const TIMESYNC_SPREAD_US: u32 = 200_000;
/// The first [`TIMESYNC_QUICK`] requests after the autopilot is learnt go out every
/// 50..100 ms, for a first mapping within a second.
const TIMESYNC_QUICK: u8 = 12;
const TIMESYNC_QUICK_MIN_US: u32 = 50_000;
const TIMESYNC_QUICK_SPREAD_US: u32 = 50_000;
/// A TIMESYNC request due while frames wait in the queue is tried again this much later.
const TIMESYNC_QUEUE_WAIT: Duration = Duration::from_millis(3);
/// SYSTEM_TIME is used alone when no TIMESYNC reply came this long after the first.
pub(crate) const TIMESYNC_GRACE: Duration = Duration::from_secs(5);
/// An autopilot that answered none of the device's requests for time and position and
/// sent none this long after it was learnt gives neither (PX4 1.16's link in mode
/// Gimbal): [`Event::NoTimeOrFixes`], once.
const SILENT_WAIT: Duration = Duration::from_secs(10);

/// MAV_CMD_SET_MESSAGE_INTERVAL.
pub(super) const SET_MESSAGE_INTERVAL: u16 = 511;

/// The streams the device asks the autopilot for (message ids).
pub(super) mod stream {
    pub(in super::super) const SYSTEM_TIME: u8 = 2;
    pub(in super::super) const GPS_RAW_INT: u8 = 24;
    pub(in super::super) const ATTITUDE: u8 = 30;
    pub(in super::super) const GLOBAL_POSITION_INT: u8 = 33;
}

/// A stream the device asks the autopilot for.
#[derive(Debug, Clone, Copy)]
struct Stream {
    /// The message id (all below 256).
    id: u8,
    interval_us: u32,
    /// The last one received.
    last: Option<Instant>,
    /// Requests since it was last received.
    tries: u8,
    /// When it may be asked for again.
    next_try: Instant,
}

impl Stream {
    const fn new(id: u8, interval_us: u32) -> Self {
        Stream {
            id,
            interval_us,
            last: None,
            tries: 0,
            next_try: Instant::ZERO,
        }
    }

    /// When it is next asked for (stale: at its retry instant).
    fn due(&self) -> Instant {
        match self.last {
            Some(last) => self.next_try.max(last.saturating_add(STREAM_STALE)),
            None => self.next_try,
        }
    }
}

/// The aircraft's attitude, 0.01° (yaw from north) and 0.01°/s.
#[derive(Debug, Clone, Copy)]
pub(super) struct Vehicle {
    pub(super) roll: i32,
    pub(super) pitch: i32,
    pub(super) yaw: i32,
    /// Earth-frame yaw rate, when known.
    pub(super) yaw_rate: Option<i32>,
    pub(super) at: Instant,
}

/// Where an autopilot reads a TIMESYNC request's tc1.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum AutopilotKind {
    /// At its UART's estimate of the request's start (never earlier).
    ArduPilot,
    /// When its receive thread parses the request: after its end.
    Px4,
    /// Unknown: somewhere after its start.
    Other,
}

/// The outstanding TIMESYNC request.
#[derive(Debug, Clone, Copy)]
struct Request {
    ts1: i64,
    /// When it was queued: no later than it started on the wire.
    sent: Instant,
    /// Its length, bytes.
    len: u32,
}

/// The TIMESYNC requester.
#[derive(Debug, Clone, Copy)]
struct Timesync {
    next: Instant,
    outstanding: Option<Request>,
    /// A reply was matched since the autopilot was learnt.
    answered: bool,
    /// Requests sent since the autopilot was learnt (saturating).
    sent: u8,
    /// Dither state (xorshift32).
    rng: u32,
    /// The last reply's tc1 (µs of the autopilot's 64-bit boot clock) and the local
    /// instant its request was queued: SYSTEM_TIME's `time_boot_ms` is unwrapped to it.
    clock: Option<(Instant, u64)>,
    /// A reply came back in less than half the time the request and the reply take on a
    /// line at the configured rate: the link is faster (a pseudo-terminal or a socket to
    /// a simulator), its frames take no serial time worth counting.
    fast_link: bool,
}

/// What [`Autopilot::message`] did with a message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Took {
    /// Not one of the autopilot's messages the link reads.
    No,
    /// Read.
    Yes,
    /// Read, and a fix went into the history.
    Fix,
}

/// What [`Autopilot::heartbeat`] made of a HEARTBEAT.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Heartbeat {
    /// Not an autopilot's.
    NotAutopilot,
    /// The autopilot's, already known.
    Known,
    /// The autopilot's, new: the device introduces itself.
    New,
    /// Another autopilot's than the pinned one: counted, reported once, nothing changed.
    Other,
}

/// The autopilot on a MAVLink link, as a device (component `own`) sees it.
#[derive(Debug, Clone)]
pub(super) struct Autopilot {
    /// The autopilot's system id, the device's own (from the autopilot's HEARTBEAT).
    pub(super) sysid: Option<u8>,
    /// Which autopilot (where it reads a TIMESYNC request's tc1).
    kind: AutopilotKind,
    /// The device's component that talks to the autopilot.
    own: u8,
    /// Next sequence number of frames from `own` and from a second component (camera).
    seq: [u8; 2],
    /// The pinned autopilot's last HEARTBEAT.
    heard: Option<Instant>,
    /// Other autopilots' system ids already reported (bit = system id).
    others_reported: [u32; 8],
    streams: [Stream; 4],
    vehicle: Option<Vehicle>,
    /// The last GPS_RAW_INT with a 3D fix.
    gps_fix_at: Option<Instant>,
    /// The first SYSTEM_TIME with a set clock since the autopilot was learnt.
    first_time: Option<Instant>,
    sync: Timesync,
    /// When the autopilot was learnt, until it answers a request for time or position or
    /// sends either (then `None`), or [`Event::NoTimeOrFixes`] has been said.
    silent_since: Option<Instant>,
    /// MAVLink signing on this link.
    pub(super) signing: LinkSigning,
}

impl Autopilot {
    pub(super) fn new(own: u8, config: &crate::Config) -> Self {
        Autopilot {
            sysid: None,
            kind: AutopilotKind::Other,
            own,
            seq: [0; 2],
            heard: None,
            others_reported: [0; 8],
            streams: [
                Stream::new(stream::SYSTEM_TIME, 100_000),
                Stream::new(stream::GLOBAL_POSITION_INT, 100_000),
                Stream::new(stream::ATTITUDE, 100_000),
                Stream::new(stream::GPS_RAW_INT, 500_000),
            ],
            vehicle: None,
            gps_fix_at: None,
            first_time: None,
            silent_since: None,
            sync: Timesync {
                next: Instant::ZERO,
                outstanding: None,
                answered: false,
                sent: 0,
                rng: 0x9E37_79B9,
                clock: None,
                fast_link: false,
            },
            signing: LinkSigning::new(config, 0),
        }
    }

    /// The device's frame header for component `comp` (its next sequence number).
    pub(super) fn header(&mut self, comp: u8) -> Option<Header> {
        let system_id = self.sysid?;
        let slot = self.seq.get_mut(usize::from(comp != self.own))?;
        let sequence = *slot;
        *slot = slot.wrapping_add(1);
        Some(Header {
            sequence,
            system_id,
            component_id: comp,
        })
    }

    /// Writes a frame with `write` (signed when the link signs: see
    /// [`LinkSigning::next_signer`]) and queues it on the link; returns its length when
    /// queued.
    fn queue(
        &mut self,
        ctx: &mut Ctx<'_>,
        write: impl FnOnce(Option<&Signer<'_>>, &mut [u8]) -> protocol_core::Result<usize>,
    ) -> Option<usize> {
        let mut buf = [0u8; MAX_FRAME_LEN];
        let utc = ctx.time.utc(ctx.now);
        let signer = self.signing.next_signer(utc);
        let n = write(signer.as_ref(), &mut buf).ok();
        self.save_if_due(ctx);
        let n = n?;
        ctx.reply(buf.get(..n).unwrap_or_default()).then_some(n)
    }

    /// Asks the store to save the signing timestamp when it is due (see
    /// [`LinkSigning::save_due`]).
    fn save_if_due(&mut self, ctx: &mut Ctx<'_>) {
        if self.signing.save_due(ctx.now) {
            ctx.out.save(store::Key::signing(ctx.to));
        }
    }

    /// Encodes `msg` from component `comp` and queues it on the link.
    pub(super) fn send(&mut self, ctx: &mut Ctx<'_>, comp: u8, msg: &MavMessage) {
        let Some(header) = self.header(comp) else {
            return;
        };
        self.queue(ctx, |signer, buf| match signer {
            Some(s) => mavlink::encode_signed(msg, &header, s, buf),
            None => mavlink::encode(msg, &header, buf),
        });
    }

    /// Queues a message from component `comp` given as its id and payload (trailing
    /// zeros are trimmed, as MAVLink 2 sends them).
    pub(super) fn send_raw(&mut self, ctx: &mut Ctx<'_>, comp: u8, id: u32, payload: &[u8]) {
        let Some(header) = self.header(comp) else {
            return;
        };
        let n = payload
            .iter()
            .rposition(|b| *b != 0)
            .map_or(1, |i| i.saturating_add(1));
        let packet = Packet::new(
            header,
            Message::Raw(Raw {
                id,
                payload: payload.get(..n).unwrap_or_default(),
            }),
        );
        self.queue(ctx, |signer, buf| match signer {
            Some(s) => packet.emit_signed(s, buf),
            None => packet.emit(buf),
        });
    }

    /// Whether a received frame is read at all, by the link's signing (see
    /// docs/src/security.md): `Some(signed)` to read it, `None` when it was refused
    /// (counted; a signed frame that does not check also reported). An unsigned message of
    /// the gate's table goes on to [`Autopilot::gate`], which refuses it while signing is
    /// required.
    pub(super) fn admit(&mut self, ctx: &mut Ctx<'_>, frame: &[u8]) -> Option<bool> {
        let utc = ctx.time.utc(ctx.now);
        let view = protocol_core::mavlink::Frame::new_unchecked(frame);
        let (id, from) = (view.message_id(), (view.system_id(), view.component_id()));
        let check = self.signing.check(frame, utc);
        if check == Check::Signed {
            self.save_if_due(ctx);
        }
        match check {
            Check::Signed => Some(true),
            Check::Refused(reason) => {
                ctx.refuse(reason, id, from);
                None
            }
            Check::Unsigned if !self.signing.required() => Some(false),
            Check::Unsigned if Gated::of(id, view.payload_ref()).is_some() => Some(false),
            Check::Unsigned if ctx.config.signing_unsigned_telemetry => Some(false),
            Check::Unsigned => {
                // Telemetry refused is counted, not reported (it comes many times a
                // second).
                let n = &mut ctx.out.counters.unsigned_refused;
                *n = n.saturating_add(1);
                None
            }
        }
    }

    /// The gate (docs/src/security.md, "The gate"): a message of the table
    /// [`GATED`](crate::access::GATED), which changes something, addressed to this device
    /// (to one of `components`, or broadcast) is taken only from an allowed sender
    /// ([`Autopilot::may_command`]) and, while signing is required, only signed; the same
    /// rule for every one of them. Returns the refusal (counted and reported; a command
    /// is named by its MAV_CMD), `None` to read the message on (messages for others are
    /// their handlers' to ignore).
    pub(super) fn gate(
        &mut self,
        ctx: &mut Ctx<'_>,
        frame: &protocol_core::mavlink::Frame<&[u8]>,
        signed: bool,
        components: &[u8],
    ) -> Option<Refusal> {
        let payload = frame.payload_ref();
        let gated = Gated::of(frame.message_id(), payload)?;
        let (ts, tc) = gated.target(payload);
        if self.sysid.is_none() || !self.addressed_to_any(ts, tc, components) {
            return None;
        }
        let from = Header {
            sequence: frame.sequence(),
            system_id: frame.system_id(),
            component_id: frame.component_id(),
        };
        let reason = if self.signing.required() && !signed {
            Refusal::Unsigned
        } else if !self.may_command(ctx, from) {
            Refusal::Sender
        } else {
            return None;
        };
        let what = if gated.is_command() {
            let at = |i: usize| payload.get(i).copied().unwrap_or(0);
            u32::from(u16::from_le_bytes([at(28), at(29)]))
        } else {
            gated.id
        };
        ctx.refuse(reason, what, (from.system_id, from.component_id));
        Some(reason)
    }

    /// The sender may change things on the device: the autopilot's system, or a listed
    /// ground station's.
    pub(super) fn may_command(&self, ctx: &Ctx<'_>, h: Header) -> bool {
        self.sysid == Some(h.system_id) || ctx.config.gcs_ids.contains(h.system_id)
    }

    /// A message addressed to one of `components` of this device, or broadcast.
    fn addressed_to_any(&self, target_system: u8, target_component: u8, components: &[u8]) -> bool {
        (target_system == 0 || self.sysid == Some(target_system))
            && (target_component == 0 || components.contains(&target_component))
    }

    /// SETUP_SIGNING addressed to this device: taken only from the autopilot's system,
    /// in a frame signed with the key in use (a key is given once by configuration and
    /// only replaced by one who holds it; see docs/src/security.md).
    pub(super) fn setup_signing(
        &mut self,
        ctx: &mut Ctx<'_>,
        h: Header,
        s: &SETUP_SIGNING_DATA,
        signed: bool,
    ) -> Took {
        if !self.addressed(s.target_system, s.target_component, self.own) || s.target_system == 0 {
            return Took::No;
        }
        // Past the gate: from an allowed sender, signed if signing is required. A key
        // changes only for the autopilot's system, signed with the key in use.
        let from = (h.system_id, h.component_id);
        if !signed {
            ctx.refuse(Refusal::Unsigned, SETUP_SIGNING_ID, from);
        } else if self.sysid != Some(h.system_id) {
            ctx.refuse(Refusal::Sender, SETUP_SIGNING_ID, from);
        } else {
            let on = self.signing.set_key(s.secret_key, s.initial_timestamp);
            // Kept across restarts at once, with the timestamp.
            ctx.out.save(store::Key::signing_key(ctx.to));
            ctx.out.save(store::Key::signing(ctx.to));
            ctx.out
                .event(crate::Event::SigningKeyChanged { port: ctx.to, on });
        }
        Took::Yes
    }

    /// Parameters are encoded byte-wise on this link: the pinned autopilot is PX4 (whose
    /// ground stations decode every component so; see `bridge_params`).
    pub(super) fn params_bytewise(&self) -> bool {
        self.kind == AutopilotKind::Px4
    }

    /// The sender is the autopilot.
    pub(super) fn is_autopilot(&self, h: Header) -> bool {
        h.component_id == AUTOPILOT && self.sysid == Some(h.system_id)
    }

    /// A message addressed to component `comp` of this device, or broadcast.
    pub(super) fn addressed(&self, target_system: u8, target_component: u8, comp: u8) -> bool {
        (target_system == 0 || self.sysid == Some(target_system))
            && (target_component == 0 || target_component == comp)
    }

    /// The autopilot is heard (its HEARTBEAT within the last 3 s).
    #[cfg(feature = "telemetry")]
    pub(super) fn is_heard(&self, now: Instant) -> bool {
        self.heard
            .is_some_and(|t| now.saturating_duration_since(t) <= AUTOPILOT_GONE)
    }

    /// The autopilot gives time: heard, with its SYSTEM_TIME stream coming.
    #[cfg(feature = "telemetry")]
    pub(super) fn gives_time(&self, now: Instant) -> bool {
        self.is_heard(now)
            && self
                .streams
                .first()
                .and_then(|s| s.last)
                .is_some_and(|t| now.saturating_duration_since(t) <= STREAM_STALE)
    }

    /// A HEARTBEAT (see docs/src/security.md, "The autopilot's system"). An autopilot's
    /// (component 1, an autopilot type; not a ground station's, gimbal's or camera's,
    /// routed onto the link) gives the device its system id: the configured
    /// `autopilot_sysid`'s, or (0: learn) the first heard after power-on, which stays
    /// pinned until none came for `autopilot_forget_ms`. Any other autopilot's is
    /// counted, reported once per system, and changes nothing.
    pub(super) fn heartbeat(
        &mut self,
        ctx: &mut Ctx<'_>,
        h: Header,
        hb: &HEARTBEAT_DATA,
    ) -> Heartbeat {
        let autopilot = h.component_id == AUTOPILOT
            && hb.autopilot != MavAutopilot::MAV_AUTOPILOT_INVALID
            && !matches!(
                hb.mavtype,
                MavType::MAV_TYPE_GCS | MavType::MAV_TYPE_GIMBAL | MavType::MAV_TYPE_CAMERA
            );
        if !autopilot {
            return Heartbeat::NotAutopilot;
        }
        let pinned = match ctx.config.autopilot_sysid {
            0 => self.sysid.filter(|_| {
                self.heard.is_some_and(|t| {
                    ctx.now.saturating_duration_since(t) < ctx.config.autopilot_forget
                })
            }),
            configured => Some(configured),
        };
        if pinned.is_some_and(|p| p != h.system_id) {
            self.other_autopilot(ctx, h.system_id);
            return Heartbeat::Other;
        }
        self.heard = Some(ctx.now);
        self.kind = match hb.autopilot {
            MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA => AutopilotKind::ArduPilot,
            MavAutopilot::MAV_AUTOPILOT_PX4 => AutopilotKind::Px4,
            _ => AutopilotKind::Other,
        };
        if self.sysid == Some(h.system_id) {
            return Heartbeat::Known;
        }
        self.sysid = Some(h.system_id);
        // Ask for the streams and start TIMESYNC now.
        for s in &mut self.streams {
            s.tries = 0;
            s.next_try = ctx.now;
        }
        self.first_time = None;
        self.silent_since = Some(ctx.now);
        self.sync.next = ctx.now;
        self.sync.outstanding = None;
        self.sync.answered = false;
        self.sync.clock = None;
        self.sync.sent = 0;
        Heartbeat::New
    }

    /// Another autopilot's HEARTBEAT: counted, reported the first time of its system.
    fn other_autopilot(&mut self, ctx: &mut Ctx<'_>, sysid: u8) {
        let n = &mut ctx.out.counters.other_autopilots;
        *n = n.saturating_add(1);
        let bit = 1u32 << (sysid % 32);
        if let Some(word) = self.others_reported.get_mut(usize::from(sysid / 32))
            && *word & bit == 0
        {
            *word |= bit;
            ctx.out.event(Event::OtherAutopilot {
                port: ctx.to,
                sysid,
            });
        }
    }

    /// One of the autopilot's messages the link reads (time, position, attitude,
    /// TIMESYNC); see [`Took`].
    pub(super) fn message(&mut self, ctx: &mut Ctx<'_>, h: Header, m: &MavMessage) -> Took {
        let autopilot = self.is_autopilot(h);
        if autopilot
            && matches!(
                m,
                MavMessage::SYSTEM_TIME(_)
                    | MavMessage::GPS_RAW_INT(_)
                    | MavMessage::GLOBAL_POSITION_INT(_)
            )
        {
            self.silent_since = None;
        }
        match m {
            MavMessage::TIMESYNC(t) => self.timesync(ctx, h, t),
            MavMessage::COMMAND_ACK(a)
                if autopilot && a.command == MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL =>
            {
                // Answered (whatever the result): the link handles the device's requests.
                self.silent_since = None;
                Took::Yes
            }
            MavMessage::SYSTEM_TIME(t) if autopilot => {
                self.stream_seen(ctx, stream::SYSTEM_TIME);
                self.system_time(ctx, t);
                Took::Yes
            }
            MavMessage::GPS_RAW_INT(g) if autopilot => {
                self.stream_seen(ctx, stream::GPS_RAW_INT);
                self.gps_raw(ctx, g);
                Took::Yes
            }
            MavMessage::GLOBAL_POSITION_INT(p) if autopilot => {
                self.stream_seen(ctx, stream::GLOBAL_POSITION_INT);
                if self.position(ctx, p) {
                    Took::Fix
                } else {
                    Took::Yes
                }
            }
            MavMessage::ATTITUDE(a) if autopilot => {
                self.stream_seen(ctx, stream::ATTITUDE);
                let c = |r: f32| math::cdeg(r).unwrap_or(0);
                let yaw_rate = math::cdeg(a.yawspeed);
                self.vehicle_attitude(ctx, [c(a.roll), c(a.pitch), c(a.yaw)], yaw_rate);
                Took::Yes
            }
            MavMessage::AUTOPILOT_STATE_FOR_GIMBAL_DEVICE(s) if autopilot => {
                if let Some(e) = math::euler(s.q) {
                    let e = e.map(|r| math::cdeg(r).unwrap_or(0));
                    let rate = math::cdeg(s.angular_velocity_z);
                    self.vehicle_attitude(ctx, e, rate);
                }
                Took::Yes
            }
            _ => Took::No,
        }
    }

    /// Periodic work: stream requests, TIMESYNC requests.
    pub(super) fn poll(&mut self, ctx: &mut Ctx<'_>) {
        self.save_if_due(ctx);
        if self.sysid.is_none() {
            return;
        }
        if self
            .silent_since
            .is_some_and(|t| ctx.now >= t.saturating_add(SILENT_WAIT))
        {
            self.silent_since = None;
            ctx.out.event(Event::NoTimeOrFixes { port: ctx.to });
        }
        self.request_streams(ctx);
        if ctx.now >= self.sync.next {
            self.request_timesync(ctx);
        }
    }

    /// When [`Autopilot::poll`] has work: the next stream request (a stream that stops is
    /// asked for again 3 s after its last message, which is also when a silent autopilot
    /// stops giving time) and the next TIMESYNC request. Never an instant already past
    /// once polled: the heartbeat's own time-out is no deadline (a SYSTEM_TIME coming
    /// without heartbeats is an input, and each input re-reads the time source).
    pub(super) fn poll_at(&self) -> Option<Instant> {
        self.sysid?;
        let streams = self.streams.iter().map(Stream::due);
        let silent = self.silent_since.map(|t| t.saturating_add(SILENT_WAIT));
        streams.chain([self.sync.next]).chain(silent).min()
    }

    /// The aircraft's attitude now, when fresh.
    pub(super) fn vehicle(&self, now: Instant) -> Option<Vehicle> {
        self.vehicle
            .filter(|v| now.saturating_duration_since(v.at) <= VEHICLE_FRESH)
    }

    fn stream_seen(&mut self, ctx: &Ctx<'_>, id: u8) {
        if let Some(s) = self.streams.iter_mut().find(|s| s.id == id) {
            s.last = Some(ctx.now);
            s.tries = 0;
        }
    }

    /// MAV_CMD_SET_MESSAGE_INTERVAL to the autopilot for every stream that is not
    /// coming: once a second for the first tries, then every 10 s.
    fn request_streams(&mut self, ctx: &mut Ctx<'_>) {
        for i in 0..self.streams.len() {
            let Some(s) = self.streams.get(i).copied() else {
                continue;
            };
            if ctx.now < s.due() {
                continue;
            }
            let wait = if s.tries < STREAM_QUICK_TRIES {
                Duration::from_secs(1)
            } else {
                STREAM_BACKOFF
            };
            if let Some(slot) = self.streams.get_mut(i) {
                slot.tries = slot.tries.saturating_add(1);
                slot.next_try = ctx.now.saturating_add(wait);
            }
            self.command_autopilot(
                ctx,
                SET_MESSAGE_INTERVAL,
                [id_f32(u32::from(s.id)), id_f32(s.interval_us)],
                s.tries,
            );
        }
    }

    /// A COMMAND_LONG from the device's component to the autopilot.
    fn command_autopilot(&mut self, ctx: &mut Ctx<'_>, command: u16, p: [f32; 2], tries: u8) {
        let Some(sysid) = self.sysid else {
            return;
        };
        // COMMAND_LONG: param1..7, command, target system and component, confirmation.
        let mut payload = [0u8; 33];
        for (d, s) in payload
            .iter_mut()
            .zip(p[0].to_le_bytes().into_iter().chain(p[1].to_le_bytes()))
        {
            *d = s;
        }
        let [c0, c1] = command.to_le_bytes();
        for (d, s) in payload
            .iter_mut()
            .skip(28)
            .zip([c0, c1, sysid, AUTOPILOT, tries])
        {
            *d = s;
        }
        let own = self.own;
        self.send_raw(ctx, own, 76, &payload);
    }

    /// The bridge's clock in ns (TIMESYNC).
    fn now_ns(now: Instant) -> i64 {
        i64::try_from(now.as_micros())
            .unwrap_or(i64::MAX)
            .saturating_mul(1000)
    }

    /// Sends the next TIMESYNC request and plans the one after (dithered). A request
    /// waits for an empty queue (then it starts on the wire when queued, or after the
    /// one frame being written): its queue instant is its start, or a little before.
    fn request_timesync(&mut self, ctx: &mut Ctx<'_>) {
        let Some(sysid) = self.sysid else {
            return;
        };
        if !ctx.link_idle() {
            self.sync.next = ctx.now.saturating_add(TIMESYNC_QUEUE_WAIT);
            return;
        }
        let mut r = self.sync.rng;
        r ^= r << 13;
        r ^= r >> 17;
        r ^= r << 5;
        self.sync.rng = r;
        let (least, spread) = if self.sync.sent < TIMESYNC_QUICK {
            (TIMESYNC_QUICK_MIN_US, TIMESYNC_QUICK_SPREAD_US)
        } else {
            (TIMESYNC_MIN_PERIOD_US, TIMESYNC_SPREAD_US)
        };
        self.sync.sent = self.sync.sent.saturating_add(1);
        let wait = least.saturating_add(r.checked_rem(spread).unwrap_or(0));
        self.sync.next = ctx
            .now
            .saturating_add(Duration::from_micros(u64::from(wait)));
        let ts1 = Self::now_ns(ctx.now).max(1);
        let msg = MavMessage::TIMESYNC(TIMESYNC_DATA {
            tc1: 0,
            ts1,
            target_system: sysid,
            target_component: AUTOPILOT,
        });
        let Some(header) = self.header(self.own) else {
            return;
        };
        let queued = self.queue(ctx, |signer, buf| match signer {
            Some(s) => mavlink::encode_signed(&msg, &header, s, buf),
            None => mavlink::encode(&msg, &header, buf),
        });
        if let Some(n) = queued {
            self.sync.outstanding = Some(Request {
                ts1,
                sent: ctx.now,
                len: u32::try_from(n).unwrap_or(0),
            });
        }
    }

    /// A TIMESYNC: a request (tc1 = 0: the autopilot's every 10 s, or another
    /// system's routed here) is answered with the bridge's clock in ns; the reply to the
    /// outstanding request is an FC clock sample (see the module documentation).
    fn timesync(&mut self, ctx: &mut Ctx<'_>, h: Header, t: &TIMESYNC_DATA) -> Took {
        if t.tc1 == 0 {
            if !self.addressed(t.target_system, t.target_component, self.own) {
                return Took::No;
            }
            let reply = MavMessage::TIMESYNC(TIMESYNC_DATA {
                tc1: Self::now_ns(ctx.now).max(1),
                ts1: t.ts1,
                target_system: h.system_id,
                target_component: h.component_id,
            });
            let own = self.own;
            self.send(ctx, own, &reply);
            return Took::Yes;
        }
        let Some(req) = self.sync.outstanding.filter(|r| r.ts1 == t.ts1) else {
            return Took::No;
        };
        if !self.is_autopilot(h) {
            return Took::No;
        }
        self.sync.outstanding = None;
        self.silent_since = None;
        let rtt = ctx.now.saturating_duration_since(req.sent);
        if rtt > TIMESYNC_MAX_RTT {
            return Took::Yes;
        }
        // At the configured rate the request and the reply (`ctx.transit`: its own serial
        // time and what followed it) take this long on the line at least; a reply in half
        // of it (a pseudo-terminal's: a quarter of a millisecond) came over a faster link.
        let line_least = serial_time(req.len, ctx.baud).saturating_add(ctx.transit);
        if rtt.as_micros().saturating_mul(2) < line_least.as_micros() {
            self.sync.fast_link = true;
        }
        let Ok(tc1_us) = u64::try_from(t.tc1 / 1000) else {
            return Took::Yes;
        };
        self.sync.clock = Some((req.sent, tc1_us));
        if !self.sync.answered {
            self.sync.answered = true;
            if self
                .first_time
                .is_some_and(|t0| ctx.now.saturating_duration_since(t0) > TIMESYNC_GRACE)
                && ctx.feeds
            {
                // SYSTEM_TIME was used alone: the TIMESYNC path replaces it.
                ctx.time.switch_source();
            }
        }
        if ctx.feeds {
            // The boot clock when the request started was at most tc1 (ArduPilot's
            // estimate of the start, never earlier; any other autopilot read it later),
            // and PX4's, read when the request had ended, at most tc1 less its serial
            // time.
            let read_after = match self.kind {
                AutopilotKind::Px4 => self.transit(serial_time(req.len, ctx.baud)).as_micros(),
                AutopilotKind::ArduPilot | AutopilotKind::Other => 0,
            };
            // The boot clock may be a simulator's (PX4 SITL in lockstep: 0.87 % slow).
            let s = Sample::new(req.sent, tc1_us.saturating_sub(read_after), 1)
                .lower_bound()
                .any_rate();
            ctx.time.fc_clock_sample(s);
        }
        Took::Yes
    }

    /// The serial time of bytes on this link: `serial` at the configured rate, none on a
    /// faster link.
    fn transit(&self, serial: Duration) -> Duration {
        if self.sync.fast_link {
            Duration::ZERO
        } else {
            serial
        }
    }

    /// SYSTEM_TIME: the boot clock against UTC (or, without TIMESYNC, a UTC sample).
    fn system_time(&mut self, ctx: &mut Ctx<'_>, t: &SYSTEM_TIME_DATA) {
        if t.time_unix_usec == 0 {
            return;
        }
        let first = *self.first_time.get_or_insert(ctx.now);
        if !ctx.feeds {
            return;
        }
        let utc = Sample::new(ctx.now, t.time_unix_usec, 1).with_transit(self.transit(ctx.transit));
        if self.sync.answered {
            // `time_boot_ms` wraps every 49.7 days, TIMESYNC's clock does not.
            let boot_ms = self
                .sync
                .clock
                .map_or(u64::from(t.time_boot_ms), |(at, tc1_us)| {
                    let expected_us =
                        tc1_us.saturating_add(ctx.now.saturating_duration_since(at).as_micros());
                    crate::time::nearest_wrap_ms(t.time_boot_ms, expected_us / 1000)
                });
            ctx.time.system_time(utc, boot_ms);
        } else if ctx.now.saturating_duration_since(first) > TIMESYNC_GRACE {
            ctx.time.utc_sample(utc);
        }
    }

    fn gps_raw(&mut self, ctx: &Ctx<'_>, g: &GPS_RAW_INT_DATA) {
        let fixed = matches!(
            g.fix_type,
            GpsFixType::GPS_FIX_TYPE_3D_FIX
                | GpsFixType::GPS_FIX_TYPE_DGPS
                | GpsFixType::GPS_FIX_TYPE_RTK_FLOAT
                | GpsFixType::GPS_FIX_TYPE_RTK_FIXED
                | GpsFixType::GPS_FIX_TYPE_STATIC
                | GpsFixType::GPS_FIX_TYPE_PPP
        );
        self.gps_fix_at = if fixed { Some(ctx.now) } else { None };
    }

    fn vehicle_attitude(&mut self, ctx: &Ctx<'_>, [roll, pitch, yaw]: [i32; 3], rate: Option<i32>) {
        self.vehicle = Some(Vehicle {
            roll,
            pitch,
            yaw: math::wrap_cdeg(yaw),
            yaw_rate: rate,
            at: ctx.now.saturating_sub(ctx.transit),
        });
    }

    /// A GLOBAL_POSITION_INT becomes a fix while the GPS has a 3D fix (ArduPilot sends
    /// positions without one) and this link feeds the history. Returns true when it did.
    fn position(&mut self, ctx: &mut Ctx<'_>, p: &GLOBAL_POSITION_INT_DATA) -> bool {
        let fixed = self
            .gps_fix_at
            .is_some_and(|t| ctx.now.saturating_duration_since(t) <= GPS_FRESH);
        if !fixed || !ctx.feeds {
            return false;
        }
        let attitude = self.vehicle(ctx.now).map(|v| [v.roll, v.pitch, v.yaw]);
        let [roll, pitch, yaw] = attitude.unwrap_or_else(|| {
            // The heading only (UINT16_MAX: unknown).
            let hdg = if p.hdg == u16::MAX {
                0
            } else {
                math::wrap_cdeg(i32::from(p.hdg))
            };
            [0, 0, hdg]
        });
        let dm = |mm: i32| clamp_i16(mm / 100);
        ctx.fixes.push(Fix {
            at: ctx.now.saturating_sub(ctx.transit),
            lat_e7: p.lat,
            lon_e7: p.lon,
            alt_msl_dm: dm(p.alt),
            rel_alt_dm: dm(p.relative_alt),
            yaw_cdeg: clamp_i16(yaw),
            roll_cdeg: clamp_i16(roll),
            pitch_cdeg: clamp_i16(pitch),
            velocity: Some(Velocity::from_cm_s(
                i32::from(p.vx),
                i32::from(p.vy),
                i32::from(p.vz),
            )),
        });
        true
    }
}

/// SETUP_SIGNING's message id.
const SETUP_SIGNING_ID: u32 = 256;

/// A message id or interval as a command parameter.
#[allow(clippy::cast_precision_loss)] // ids and intervals below 2^24 are exact
pub(super) fn id_f32(v: u32) -> f32 {
    v as f32
}
