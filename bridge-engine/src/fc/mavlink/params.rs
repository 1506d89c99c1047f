//! The camera's settings as extended parameters (PARAM_EXT_*, component 100), the
//! parameters of the camera definition ([`settings`](super::settings); see
//! docs/src/bridge/mavlink.md, "Settings and the camera definition").
//!
//! - **Values** are the pod's: read from its all-settings ACKs (0x000100, 0x000200;
//!   asked when the pod link comes up and after every accepted set) and its periodic
//!   reports; a setting the pod has not reported yet reads as the definition's default,
//!   the temperature overlay (which the pod never reports) as the value it last
//!   accepted. Each goes out as PARAM_EXT_VALUE typed as the definition types it
//!   (uint8, CAM_MODE uint32): the value's little-endian bytes at the start of
//!   `param_value`, the rest zero.
//! - **PARAM_EXT_REQUEST_LIST** sends every parameter, **PARAM_EXT_REQUEST_READ** one
//!   (by name with index −1, else by index); an unknown one is not answered. The values
//!   are paced: one PARAM_EXT_VALUE (161 bytes) only when the FC queue is empty, the next
//!   no sooner than 1.5 times its serial time later. Once a client has asked, a value
//!   that changes (a set from another client, SET_CAMERA_MODE, the pod's own reports) is
//!   sent unasked, as MAVSDK and QGroundControl take updates.
//! - **PARAM_EXT_SET**: an unknown name, another type than the definition's, or a value
//!   not among the parameter's: VALUE_UNSUPPORTED with the current value. The current
//!   value again: ACCEPTED at once. Otherwise the K40T set command goes to the pod and
//!   the answer is IN_PROGRESS, then, on the pod's ACK, ACCEPTED with the new value (FAILED
//!   with the current one on a refusal, on the pod's time-out, or at once while the pod
//!   does not report). A repeat of a set in progress is answered IN_PROGRESS again, not
//!   sent twice. Until the pod's reports show an accepted value (at most
//!   [`ACCEPTED_HOLD`]), the accepted value is the one reported.

use crate::discipline::serial_time;
use crate::event::Event;
use crate::time::{Duration, Instant};
use protocol_core::k40t::Request;
use protocol_core::mavlink::Header;

use super::settings::{ALL, COUNT, Setting, Source};
use super::{Comp, MavlinkSide};
use crate::fc::Ctx;

/// PARAM_EXT_REQUEST_READ.
pub(super) const REQUEST_READ: u32 = 320;
/// PARAM_EXT_REQUEST_LIST.
pub(super) const REQUEST_LIST: u32 = 321;
/// PARAM_EXT_VALUE.
const VALUE: u32 = 322;
/// PARAM_EXT_SET.
pub(super) const SET: u32 = 323;
/// PARAM_EXT_ACK.
const ACK: u32 = 324;

/// PARAM_ACK values.
mod ack {
    pub(super) const ACCEPTED: u8 = 0;
    pub(super) const VALUE_UNSUPPORTED: u8 = 1;
    pub(super) const FAILED: u8 = 2;
    pub(super) const IN_PROGRESS: u8 = 3;
}

/// MAV_PARAM_EXT_TYPE values.
const UINT8: u8 = 1;
const UINT32: u8 = 5;

/// Sets waiting for the pod at once.
const PENDING: usize = 4;
/// Accepted values held until the pod reports them.
const RECENT: usize = 4;
/// A set the pod has not answered after this has failed.
const SET_WAIT: Duration = Duration::from_millis(1500);
/// An accepted value is reported for this long at most before the pod's own reports
/// (0x000003 comes every second; 0x000100 and 0x000200 are asked again at once).
pub(super) const ACCEPTED_HOLD: Duration = Duration::from_millis(2500);
/// A value due while frames wait in the FC queue is tried again this much later.
const QUEUE_WAIT: Duration = Duration::from_millis(3);
/// Bytes of a PARAM_EXT_VALUE frame.
const VALUE_FRAME: u32 = 161;

/// A set sent to the pod, waiting for its ACK.
#[derive(Debug, Clone, Copy)]
struct PendingSet {
    setting: Setting,
    value: u8,
    base: u16,
    at: Instant,
}

/// A value the pod accepted, reported until its reports show it.
#[derive(Debug, Clone, Copy)]
struct Accepted {
    setting: Setting,
    value: u8,
    until: Instant,
}

/// The parameters' state.
#[derive(Debug, Clone, Copy)]
pub(super) struct Params {
    /// What the clients were last told, per setting.
    reported: [u8; COUNT],
    /// Settings whose PARAM_EXT_VALUE waits (bit = index).
    to_send: u64,
    /// A client asked for parameters: changes are sent unasked.
    announce: bool,
    /// No PARAM_EXT_VALUE before this.
    next: Instant,
    pending: [Option<PendingSet>; PENDING],
    recent: [Option<Accepted>; RECENT],
    /// The temperature overlay the pod last accepted (it never reports it).
    pub(super) overlay: Option<u8>,
}

impl Default for Params {
    fn default() -> Self {
        let mut reported = [0u8; COUNT];
        for (r, s) in reported.iter_mut().zip(ALL) {
            *r = s.default_value();
        }
        Params {
            reported,
            to_send: 0,
            announce: false,
            next: Instant::ZERO,
            pending: [None; PENDING],
            recent: [None; RECENT],
            overlay: None,
        }
    }
}

impl Params {
    /// When there is work: a value to send, a set to give up, a held value to drop.
    pub(super) fn poll_at(&self) -> Option<Instant> {
        let send = (self.to_send != 0).then_some(self.next);
        let pending = self
            .pending
            .iter()
            .flatten()
            .map(|p| p.at.saturating_add(SET_WAIT));
        let recent = self.recent.iter().flatten().map(|a| a.until);
        send.into_iter().chain(pending).chain(recent).min()
    }

    /// The clients were told `value` for `s`.
    fn told(&mut self, s: Setting, value: u8) {
        if let Some(r) = self.reported.get_mut(s.index()) {
            *r = value;
        }
    }

    fn mark(&mut self, s: Setting) {
        self.to_send |= 1u64 << (s.index() % 64);
    }
}

/// The parameter id of a PARAM_EXT_* message: up to 16 bytes, NUL-padded or not.
fn param_id(bytes: &[u8]) -> &[u8] {
    let end = bytes.iter().position(|b| *b == 0).unwrap_or(bytes.len());
    bytes.get(..end).unwrap_or_default()
}

/// `s`'s MAVLink type.
fn type_of(s: Setting) -> u8 {
    if s.wide() { UINT32 } else { UINT8 }
}

/// `p` zero-extended to `N` bytes.
fn extended<const N: usize>(p: &[u8]) -> [u8; N] {
    let mut out = [0u8; N];
    for (d, s) in out.iter_mut().zip(p) {
        *d = *s;
    }
    out
}

impl MavlinkSide {
    /// The value the clients are told: an accepted value not yet in the pod's reports,
    /// else the pod's report, else what the pod last accepted (the overlay), else the
    /// definition's default.
    fn param_value(&self, ctx: &Ctx<'_>, s: Setting) -> u8 {
        self.known_value(ctx, s)
            .unwrap_or_else(|| s.default_value())
    }

    /// [`Self::param_value`] without the default: `None` while unknown.
    fn known_value(&self, ctx: &Ctx<'_>, s: Setting) -> Option<u8> {
        let held = self
            .params
            .recent
            .iter()
            .flatten()
            .find(|a| a.setting == s)
            .map(|a| a.value);
        let remembered = (s == Setting::IrTempOverlay)
            .then_some(self.params.overlay)
            .flatten();
        held.or_else(|| s.read(ctx.pod())).or(remembered)
    }

    /// The value a new set command takes for `s` when it sets a neighbour (0x000301 sets
    /// three settings at once): a set in progress first.
    fn intended_value(&self, ctx: &Ctx<'_>, s: Setting) -> u8 {
        self.params
            .pending
            .iter()
            .flatten()
            .filter(|p| p.setting == s)
            .max_by_key(|p| p.at)
            .map_or_else(|| self.param_value(ctx, s), |p| p.value)
    }

    /// A PARAM_EXT_* request (by its message id), from its payload as sent.
    pub(super) fn param_request(
        &mut self,
        ctx: &mut Ctx<'_>,
        from: Header,
        msg: u32,
        payload: &[u8],
    ) {
        match msg {
            REQUEST_LIST => {
                let [ts, tc] = extended::<2>(payload);
                if !self.addressed(ts, tc, Comp::Camera) {
                    ctx.ignored();
                    return;
                }
                self.params.announce = true;
                for s in ALL {
                    self.params.mark(s);
                }
            }
            REQUEST_READ => {
                let p = extended::<20>(payload);
                let [i0, i1, ts, tc, ..] = p;
                if !self.addressed(ts, tc, Comp::Camera) {
                    ctx.ignored();
                    return;
                }
                let index = i16::from_le_bytes([i0, i1]);
                let s = match usize::try_from(index) {
                    Ok(i) => Setting::at(i),
                    Err(_) => Setting::named(param_id(p.get(4..).unwrap_or_default())),
                };
                let Some(s) = s else {
                    ctx.ignored();
                    return;
                };
                self.params.announce = true;
                self.params.mark(s);
            }
            _ => {
                let p = extended::<147>(payload);
                let [ts, tc, ..] = p;
                if !self.addressed(ts, tc, Comp::Camera) {
                    ctx.ignored();
                    return;
                }
                self.param_set(ctx, from, &p);
            }
        }
        self.params_poll(ctx);
    }

    /// PARAM_EXT_SET (its payload zero-extended): see the module documentation.
    fn param_set(&mut self, ctx: &mut Ctx<'_>, from: Header, p: &[u8; 147]) {
        let _ = from;
        let name = param_id(p.get(2..18).unwrap_or_default());
        let ty = p.get(146).copied().unwrap_or(0);
        let Some(s) = Setting::named(name) else {
            // Unknown: its id and type echoed, no value.
            let mut id = [0u8; 16];
            for (d, b) in id.iter_mut().zip(name) {
                *d = *b;
            }
            self.param_ack_raw(ctx, &id, 0, ty, ack::VALUE_UNSUPPORTED);
            return;
        };
        let [v0, v1, v2, v3] = extended::<4>(p.get(18..22).unwrap_or_default());
        let wide = u32::from_le_bytes([v0, v1, v2, v3]);
        let value = if s.wide() {
            u8::try_from(wide).ok()
        } else {
            Some(v0)
        };
        let current = self.param_value(ctx, s);
        let Some(value) = value.filter(|v| ty == type_of(s) && s.allows(*v)) else {
            self.param_ack(ctx, s, current, ack::VALUE_UNSUPPORTED);
            return;
        };
        if self.known_value(ctx, s) == Some(value) {
            self.param_ack(ctx, s, value, ack::ACCEPTED);
            self.params.told(s, value);
            return;
        }
        if !ctx.pod().link {
            self.param_ack(ctx, s, current, ack::FAILED);
            return;
        }
        let repeat = self
            .params
            .pending
            .iter()
            .flatten()
            .any(|q| q.setting == s && q.value == value);
        if !repeat {
            let request = s.request(value, |x| self.intended_value(ctx, x));
            let base = send_setting(ctx, request);
            let set = PendingSet {
                setting: s,
                value,
                base,
                at: ctx.now,
            };
            let pending = &mut self.params.pending;
            // A newer set of the same setting replaces the older (which gets no answer of
            // its own: ground stations match PARAM_EXT_ACK by name); else a free slot,
            // else the oldest.
            let slot = pending
                .iter()
                .position(|q| q.is_some_and(|q| q.setting == s))
                .or_else(|| pending.iter().position(Option::is_none))
                .or_else(|| {
                    pending
                        .iter()
                        .enumerate()
                        .min_by_key(|(_, q)| q.map(|q| q.at))
                        .map(|(i, _)| i)
                });
            if let Some(slot) = slot.and_then(|i| pending.get_mut(i)) {
                *slot = Some(set);
            }
        }
        self.param_ack(ctx, s, value, ack::IN_PROGRESS);
    }

    /// The pod answered (or never did) a request of base `base`: the oldest set waiting
    /// on it is ACCEPTED or FAILED.
    pub(super) fn params_pod_answer(&mut self, ctx: &mut Ctx<'_>, base: u16, ok: bool) {
        let oldest = self
            .params
            .pending
            .iter()
            .enumerate()
            .filter_map(|(i, q)| q.filter(|q| q.base == base).map(|q| (i, q)))
            .min_by_key(|(_, q)| q.at);
        let Some((i, set)) = oldest else {
            return;
        };
        if let Some(slot) = self.params.pending.get_mut(i) {
            *slot = None;
        }
        self.param_answered(ctx, set, ok);
    }

    fn param_answered(&mut self, ctx: &mut Ctx<'_>, set: PendingSet, ok: bool) {
        let s = set.setting;
        if !ok {
            let current = self.param_value(ctx, s);
            self.param_ack(ctx, s, current, ack::FAILED);
            return;
        }
        if s == Setting::IrTempOverlay {
            self.params.overlay = Some(set.value);
        }
        let held = Accepted {
            setting: s,
            value: set.value,
            until: ctx.now.saturating_add(ACCEPTED_HOLD),
        };
        let recent = &mut self.params.recent;
        let slot = recent
            .iter()
            .position(|a| a.is_some_and(|a| a.setting == s))
            .or_else(|| recent.iter().position(Option::is_none))
            .or_else(|| {
                recent
                    .iter()
                    .enumerate()
                    .min_by_key(|(_, a)| a.map(|a| a.until))
                    .map(|(i, _)| i)
            });
        if let Some(slot) = slot.and_then(|i| recent.get_mut(i)) {
            *slot = Some(held);
        }
        self.params.told(s, set.value);
        self.param_ack(ctx, s, set.value, ack::ACCEPTED);
        // Read the pod's settings back.
        match s.source() {
            Source::Ir => ctx.pod.query_settings(ctx.now, true, false, ctx.out),
            Source::Visible => ctx.pod.query_settings(ctx.now, false, true, ctx.out),
            Source::Report | Source::None => {}
        }
    }

    /// The pod came back: its settings are asked for.
    #[allow(clippy::unused_self)] // with the side's other reactions to the pod
    pub(super) fn params_pod_up(&mut self, ctx: &mut Ctx<'_>) {
        ctx.pod.query_settings(ctx.now, true, true, ctx.out);
    }

    /// Periodic work: sets the pod never answered, held values the pod's reports show
    /// (or that expired), changed values to announce, the next value to send.
    pub(super) fn params_poll(&mut self, ctx: &mut Ctx<'_>) {
        let now = ctx.now;
        for i in 0..PENDING {
            let stale = self
                .params
                .pending
                .get(i)
                .copied()
                .flatten()
                .filter(|q| now.saturating_duration_since(q.at) >= SET_WAIT);
            if let Some(set) = stale {
                if let Some(slot) = self.params.pending.get_mut(i) {
                    *slot = None;
                }
                self.param_answered(ctx, set, false);
            }
        }
        for a in &mut self.params.recent {
            if a.is_some_and(|a| now >= a.until || a.setting.read(ctx.pod()) == Some(a.value)) {
                *a = None;
            }
        }
        if self.params.announce {
            for s in ALL {
                if self.param_value(ctx, s)
                    != self.params.reported.get(s.index()).copied().unwrap_or(0)
                {
                    self.params.mark(s);
                }
            }
        }
        if self.params.to_send == 0 || now < self.params.next {
            return;
        }
        if !ctx.link_idle() {
            self.params.next = now.saturating_add(QUEUE_WAIT);
            return;
        }
        let index = usize::try_from(self.params.to_send.trailing_zeros()).unwrap_or(0);
        self.params.to_send &= !(1u64 << (index % 64));
        if let Some(s) = Setting::at(index) {
            self.param_value_message(ctx, s);
            self.params.next = now.saturating_add(serial_time(VALUE_FRAME * 3 / 2, ctx.baud));
        }
    }

    /// PARAM_EXT_VALUE of `s`, from the camera.
    fn param_value_message(&mut self, ctx: &mut Ctx<'_>, s: Setting) {
        let value = self.param_value(ctx, s);
        self.params.told(s, value);
        let mut p = [0u8; 149];
        let count = u16::try_from(COUNT).unwrap_or(0).to_le_bytes();
        let index = u16::try_from(s.index()).unwrap_or(0).to_le_bytes();
        let head = count.iter().chain(&index).chain(s.name().as_bytes());
        for (d, b) in p.iter_mut().zip(head) {
            *d = *b;
        }
        if let Some(v) = p.get_mut(20) {
            *v = value;
        }
        if let Some(t) = p.get_mut(148) {
            *t = type_of(s);
        }
        self.ap.send_raw(ctx, Comp::Camera.id(), VALUE, &p);
    }

    /// PARAM_EXT_ACK of `s` with `value`.
    fn param_ack(&mut self, ctx: &mut Ctx<'_>, s: Setting, value: u8, result: u8) {
        let mut name = [0u8; 16];
        for (d, b) in name.iter_mut().zip(s.name().as_bytes()) {
            *d = *b;
        }
        self.param_ack_raw(ctx, &name, value, type_of(s), result);
    }

    fn param_ack_raw(&mut self, ctx: &mut Ctx<'_>, name: &[u8; 16], value: u8, ty: u8, result: u8) {
        let mut p = [0u8; 146];
        for (d, b) in p.iter_mut().zip(name) {
            *d = *b;
        }
        let tail = [(16, value), (144, ty), (145, result)];
        for (at, b) in tail {
            if let Some(d) = p.get_mut(at) {
                *d = b;
            }
        }
        self.ap.send_raw(ctx, Comp::Camera.id(), ACK, &p);
    }
}

/// Sends a setting to the pod (the event names PARAM_EXT_SET as the FC's message).
fn send_setting(ctx: &mut Ctx<'_>, request: Request) -> u16 {
    let base = ctx.pod.send_setting(ctx.now, request, ctx.out);
    let fc_id = u16::try_from(SET).unwrap_or(0);
    ctx.out.event(Event::Translated {
        fc_id,
        pod_base: base,
    });
    base
}
