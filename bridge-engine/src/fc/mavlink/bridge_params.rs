//! The bridge's settings as MAVLink parameters (PARAM_REQUEST_LIST, PARAM_REQUEST_READ,
//! PARAM_SET, PARAM_VALUE) of its own component: the gimbal's (154) on the MAVLink side,
//! 158 on the telemetry link; the table is [`crate::settings::table`] (the settings with a
//! parameter name). See docs/src/firmware/configuration.md, "Settings".
//!
//! - **Addressed** to the component, or broadcast (QGroundControl asks every component of
//!   the vehicle with component 0 and lists each one that answers); PARAM_SET passes the
//!   gate first (docs/src/security.md). The camera's settings stay PARAM_EXT_* on
//!   component 100 ([`params`](super::params)).
//! - **Values** are the settings as set (a restart setting shows its new value before the
//!   restart, as the autopilots' own reboot-required parameters do). The list is paced:
//!   a PARAM_VALUE only when the link's queue is empty, the next no sooner than three times
//!   its serial time later (a third of the line at most).
//! - **Encoding.** QGroundControl decodes every component of a vehicle as its autopilot
//!   encodes: byte-wise for PX4, a C cast for ArduPilot (its ArduPilot plugin converts).
//!   PARAM_VALUE follows the pinned autopilot (PX4: byte-wise; any other: the cast, exact
//!   for every value here, all below 2^24). A PARAM_SET is read either way: a value whose
//!   float is zero or subnormal is read byte-wise (every whole number here below 2^23 is
//!   subnormal as bytes; bytes beyond the type's width make the whole word the value, for
//!   the range to refuse), any other as a cast, which must be a whole number.
//! - **PARAM_SET** is checked as the console's `set` is, and kept at once (the protocol has
//!   no save step); the answer is PARAM_VALUE with the value in force as set, the old one
//!   after a refusal, with a STATUSTEXT saying why (MAVLink's parameter service names no
//!   error message; QGroundControl shows STATUSTEXT).

use crate::discipline::serial_time;
use crate::event::{Event, SettingOutcome, SettingSource};
use crate::settings::table::{self, Applies, ParamType, Setting};
use crate::time::{Duration, Instant};

use super::autopilot::Autopilot;
use crate::fc::Ctx;

/// PARAM_REQUEST_READ.
pub(super) const REQUEST_READ: u32 = 20;
/// PARAM_REQUEST_LIST.
pub(super) const REQUEST_LIST: u32 = 21;
/// PARAM_VALUE.
const VALUE: u32 = 22;
/// PARAM_SET.
pub(super) const SET: u32 = 23;
/// STATUSTEXT.
const STATUSTEXT: u32 = 253;
/// MAV_SEVERITY_WARNING.
const WARNING: u8 = 4;
/// Bytes of a PARAM_VALUE frame (unsigned: 12 of header and CRC, 25 of payload).
const VALUE_FRAME: u32 = 37;
/// A value due while frames wait in the queue is tried again this much later.
const QUEUE_WAIT: Duration = Duration::from_millis(3);

/// The parameters' state on one link.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct BridgeParams {
    /// Parameters whose PARAM_VALUE waits (bit = parameter index).
    to_send: u64,
    /// No PARAM_VALUE before this.
    next: Instant,
}

/// `p` zero-extended to `N` bytes.
fn extended<const N: usize>(p: &[u8]) -> [u8; N] {
    let mut out = [0u8; N];
    protocol_core::wire::copy(&mut out, p);
    out
}

fn bit(index: usize) -> u64 {
    1u64.checked_shl(u32::try_from(index).unwrap_or(64))
        .unwrap_or(0)
}

/// A PARAM_SET's value: read byte-wise when its float is zero or subnormal (see the module
/// documentation), else as a whole number cast to a float.
fn set_value(bits: u32, ty: ParamType) -> Option<i64> {
    let f = f32::from_bits(bits);
    if f == 0.0 || f.is_subnormal() {
        let narrow = ty.from_bytes(bits);
        if ty.to_bytes(narrow) == bits {
            return Some(narrow);
        }
        // Bytes beyond the type's width: the whole word, for the range to judge (never
        // its low bytes alone: 100 000 as a UINT8 is no 160).
        let word = match ty {
            ParamType::Int8 | ParamType::Int16 | ParamType::Int32 => {
                i64::from(i32::from_le_bytes(bits.to_le_bytes()))
            }
            ParamType::Uint8 | ParamType::Uint16 | ParamType::Uint32 => i64::from(bits),
        };
        return Some(word);
    }
    // Every value of a setting's range is below 2^24, exact in a float.
    if !(f.is_finite() && f.abs() < 16_777_216.0) {
        return None;
    }
    #[allow(clippy::cast_possible_truncation, clippy::cast_precision_loss)] // below 2^24
    let (n, back) = (f as i64, (f as i64) as f32);
    // A whole number only.
    #[allow(clippy::float_cmp)]
    (back == f).then_some(n)
}

/// `n` as PARAM_VALUE carries it: byte-wise, or cast to a float.
#[allow(clippy::cast_precision_loss)] // every value is below 2^24: exact
fn value_bits(n: i64, ty: ParamType, bytewise: bool) -> u32 {
    if bytewise {
        ty.to_bytes(n)
    } else {
        (n as f32).to_bits()
    }
}

impl BridgeParams {
    /// When a PARAM_VALUE is due.
    pub(super) fn poll_at(&self) -> Option<Instant> {
        (self.to_send != 0).then_some(self.next)
    }

    /// A PARAM_* message (by its id) from its payload as sent, for component `own`:
    /// returns whether it was this component's.
    pub(super) fn request(
        &mut self,
        ctx: &mut Ctx<'_>,
        ap: &mut Autopilot,
        own: u8,
        msg: u32,
        payload: &[u8],
    ) -> bool {
        match msg {
            REQUEST_LIST => {
                let [ts, tc] = extended::<2>(payload);
                if !ap.addressed(ts, tc, own) {
                    return false;
                }
                self.to_send |= bit(table::param_count()).wrapping_sub(1);
            }
            REQUEST_READ => {
                let p = extended::<20>(payload);
                let [i0, i1, ts, tc, ..] = p;
                if !ap.addressed(ts, tc, own) {
                    return false;
                }
                let found = match usize::try_from(i16::from_le_bytes([i0, i1])) {
                    Ok(i) => table::param_at(i).map(|_| i),
                    Err(_) => table::by_param(p.get(4..).unwrap_or_default()).map(|(i, _)| i),
                };
                // An unknown parameter is not answered (as the protocol has it).
                if let Some(i) = found {
                    self.to_send |= bit(i);
                }
            }
            _ => {
                let p = extended::<23>(payload);
                let [v0, v1, v2, v3, ts, tc, ..] = p;
                if !ap.addressed(ts, tc, own) {
                    return false;
                }
                if let Some((i, s)) = table::by_param(p.get(6..22).unwrap_or_default()) {
                    self.set(ctx, ap, own, i, s, u32::from_le_bytes([v0, v1, v2, v3]));
                }
            }
        }
        self.poll(ctx, ap, own);
        true
    }

    /// PARAM_SET of parameter `index` (setting `s`), its value's bits as sent.
    fn set(
        &mut self,
        ctx: &mut Ctx<'_>,
        ap: &mut Autopilot,
        own: u8,
        index: usize,
        s: &Setting,
        bits: u32,
    ) {
        let Some(setting) = crate::settings::Settings::index_of(s.key) else {
            return;
        };
        let ty = s.param_type().unwrap_or(ParamType::Int32);
        let result = match set_value(bits, ty) {
            Some(n) => ctx.settings.set_number(setting, n),
            None => Err(crate::config::ConfigError {
                key: s.key,
                problem: crate::config::Problem::Form(crate::config::Form::Number),
            }),
        };
        let outcome = match result {
            Ok(a) => {
                ctx.settings.keep(setting);
                if a.applies == Applies::Live {
                    SettingOutcome::Applied
                } else {
                    SettingOutcome::AtRestart
                }
            }
            Err(e) => {
                refused(ctx, ap, own, s, &e);
                SettingOutcome::Refused
            }
        };
        ctx.out.event(Event::Setting {
            key: s.record(),
            source: SettingSource::Parameter(ctx.to),
            outcome,
        });
        // The answer: the value in force as set (the old one after a refusal).
        self.to_send |= bit(index);
        self.next = self.next.min(ctx.now);
    }

    /// Sends the next PARAM_VALUE when it is due and the link is free.
    pub(super) fn poll(&mut self, ctx: &mut Ctx<'_>, ap: &mut Autopilot, own: u8) {
        if self.to_send == 0 || ctx.now < self.next {
            return;
        }
        if !ctx.link_idle() {
            self.next = ctx.now.saturating_add(QUEUE_WAIT);
            return;
        }
        let index = usize::try_from(self.to_send.trailing_zeros()).unwrap_or(0);
        self.to_send &= !bit(index);
        let Some(s) = table::param_at(index) else {
            return;
        };
        let ty = s.param_type().unwrap_or(ParamType::Int32);
        let n = s.number(ctx.settings.pending()).unwrap_or(0);
        let bits = value_bits(n, ty, ap.params_bytewise());
        let count = u16::try_from(table::param_count()).unwrap_or(0);
        let mut p = [0u8; 25];
        let (value, rest) = p.split_at_mut(4);
        protocol_core::wire::copy(value, &bits.to_le_bytes());
        let (head, rest) = rest.split_at_mut(4);
        let index16 = u16::try_from(index).unwrap_or(0);
        let [c0, c1] = count.to_le_bytes();
        let [i0, i1] = index16.to_le_bytes();
        protocol_core::wire::copy(head, &[c0, c1, i0, i1]);
        let (name, ty_byte) = rest.split_at_mut(16);
        protocol_core::wire::copy(name, s.param.unwrap_or("").as_bytes());
        protocol_core::wire::copy(ty_byte, &[ty.code()]);
        ap.send_raw(ctx, own, VALUE, &p);
        let wire = serial_time(VALUE_FRAME.saturating_mul(3), ctx.baud);
        self.next = ctx.now.saturating_add(wire);
    }
}

/// STATUSTEXT (a warning) saying why a PARAM_SET of `s` was refused.
fn refused(
    ctx: &mut Ctx<'_>,
    ap: &mut Autopilot,
    own: u8,
    s: &Setting,
    e: &crate::config::ConfigError,
) {
    use core::fmt::Write as _;
    let mut text = [0u8; 50];
    let mut w = crate::settings::Writer::new(&mut text);
    let name = s.param.unwrap_or("");
    // Cut at 50 characters, as STATUSTEXT carries them.
    let _ = if e.key == s.key {
        write!(w, "{name}: {}", e.problem)
    } else {
        write!(w, "{name}: {e}")
    };
    let mut p = [0u8; 51];
    let (severity, rest) = p.split_at_mut(1);
    protocol_core::wire::copy(severity, &[WARNING]);
    protocol_core::wire::copy(rest, &text);
    ap.send_raw(ctx, own, STATUSTEXT, &p);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A PARAM_SET's value is read byte-wise when its bits make a zero or subnormal float,
    /// else as a cast whole number; PARAM_VALUE writes either way.
    #[test]
    fn values_both_ways() {
        for (ty, n) in [
            (ParamType::Uint32, 57_600),
            (ParamType::Uint32, 4_000_000),
            (ParamType::Int16, -480),
            (ParamType::Int16, 1440),
            (ParamType::Uint8, 1),
            (ParamType::Uint16, 0x7FF),
            (ParamType::Uint8, 0),
        ] {
            for bytewise in [true, false] {
                let bits = value_bits(n, ty, bytewise);
                assert_eq!(
                    set_value(bits, ty),
                    Some(n),
                    "{ty:?} {n} bytewise {bytewise}"
                );
            }
        }
        // Byte-wise, wider than its type: the whole word (refused by the range).
        assert_eq!(set_value(100_000, ParamType::Uint8), Some(100_000));
        assert_eq!(set_value(0x0001_0000, ParamType::Int16), Some(65_536));
        assert_eq!(set_value(1.5f32.to_bits(), ParamType::Uint8), None);
        assert_eq!(set_value(f32::NAN.to_bits(), ParamType::Uint8), None);
        assert_eq!(set_value(f32::INFINITY.to_bits(), ParamType::Uint32), None);
        assert_eq!(set_value(3e9f32.to_bits(), ParamType::Uint32), None);
    }
}
