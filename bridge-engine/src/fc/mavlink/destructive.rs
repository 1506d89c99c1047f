//! The camera commands that erase: MAV_CMD_STORAGE_FORMAT (526, the pod's SD card,
//! 0x00030D) and MAV_CMD_RESET_CAMERA_SETTINGS (529, the pod's factory reset, 0x00030F:
//! the only reset the K40T external protocol offers, 3.2.4.14; it also resets the pod's IP
//! configuration and restarts the pod after a second, so it is destructive beyond the
//! camera's settings). See docs/src/bridge/mavlink.md, "Storage and reset".
//!
//! - Without `mavlink.allow_destructive` both are DENIED, with
//!   [`Event::DestructiveDenied`] saying why.
//! - Allowed: TEMPORARILY_REJECTED while the pod does not report; a storage other than 0
//!   (all) or 1 (the SD card): DENIED; `param2` 0 (do not format): ACCEPTED, nothing to
//!   do. Else the K40T request goes to the pod and the ACK waits for the pod's:
//!   ACCEPTED, or FAILED on a refusal (the pod refuses to format while it records or
//!   takes a photo, 3.2.4.12) or time-out. A repeat of the command while it waits is
//!   not sent again; another destructive command meanwhile is TEMPORARILY_REJECTED.
//! - After an accepted format: STORAGE_INFORMATION at once, and again whenever the
//!   card's state or used space changes in the next [`WATCH`] (the pod formats, then
//!   reports the emptied card in its 1 Hz 0x000003). After an accepted reset: the
//!   remembered temperature overlay is forgotten and the settings asked again (they are
//!   asked anyway when the restarted pod reports again).

use crate::event::Event;
use crate::time::{Duration, Instant};
use protocol_core::k40t::{FactoryReset, FormatSd, Request};
use protocol_core::mavlink::Header;

use super::{Cmd, Comp, MavlinkSide, cmd, result};
use crate::fc::Ctx;

/// A pod ACK not come after this: the command failed.
const ACK_WAIT: Duration = Duration::from_millis(1500);
/// How long after a format the card's reports are watched.
const WATCH: Duration = Duration::from_secs(15);

/// A destructive command waiting for the pod's ACK.
#[derive(Debug, Clone, Copy)]
struct Waiting {
    command: u16,
    base: u16,
    from: Header,
    at: Instant,
}

/// The destructive commands' state.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Destructive {
    waiting: Option<Waiting>,
    /// After a format: until when the card is watched, and its state (SD state, used
    /// space) last sent.
    watch: Option<(Instant, (u8, u16))>,
}

impl Destructive {
    /// When there is work.
    pub(super) fn poll_at(&self) -> Option<Instant> {
        let waiting = self.waiting.map(|w| w.at.saturating_add(ACK_WAIT));
        // The card is looked at in every poll of the side (10 Hz at least, the attitude
        // status's); the watch ends at its instant.
        let watch = self.watch.map(|(until, _)| until);
        waiting.into_iter().chain(watch).min()
    }
}

/// A parameter as a whole number (NaN and negatives: `None`).
#[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // checked range
fn whole(p: f32) -> Option<u32> {
    (0.0..4.0e9).contains(&p).then_some(p as u32)
}

impl MavlinkSide {
    /// MAV_CMD_STORAGE_FORMAT or MAV_CMD_RESET_CAMERA_SETTINGS (see the module
    /// documentation).
    pub(super) fn destructive_command(&mut self, ctx: &mut Ctx<'_>, c: &Cmd) {
        let answer = |r: u8| (c.command, r, c.from);
        if !ctx.config.mavlink.allow_destructive {
            ctx.out
                .event(Event::DestructiveDenied { command: c.command });
            self.destructive_ack(ctx, answer(result::DENIED));
            return;
        }
        if let Some(w) = self.destructive.waiting {
            if w.command != c.command {
                self.destructive_ack(ctx, answer(result::TEMPORARILY_REJECTED));
            }
            return;
        }
        if !ctx.pod().link {
            self.destructive_ack(ctx, answer(result::TEMPORARILY_REJECTED));
            return;
        }
        let request = if c.command == cmd::STORAGE_FORMAT {
            // param1: the storage (NaN: not given, all); param2: format (0: do not).
            if !matches!(whole(c.param(1)).unwrap_or(0), 0 | 1) {
                self.destructive_ack(ctx, answer(result::DENIED));
                return;
            }
            if whole(c.param(2)) == Some(0) {
                self.destructive_ack(ctx, answer(result::ACCEPTED));
                return;
            }
            Request::FormatSd(FormatSd {
                command: 1,
                reserved: 0,
            })
        } else {
            Request::FactoryReset(FactoryReset {
                command: 1,
                reserved: 0,
            })
        };
        let base = ctx.pod.send_setting(ctx.now, request, ctx.out);
        ctx.out.event(Event::Translated {
            fc_id: c.command,
            pod_base: base,
        });
        self.destructive.waiting = Some(Waiting {
            command: c.command,
            base,
            from: c.from,
            at: ctx.now,
        });
    }

    /// The pod answered (or never did) a request of base `base`.
    pub(super) fn destructive_pod_answer(&mut self, ctx: &mut Ctx<'_>, base: u16, ok: bool) {
        let Some(w) = self.destructive.waiting.filter(|w| w.base == base) else {
            return;
        };
        self.destructive.waiting = None;
        let r = if ok { result::ACCEPTED } else { result::FAILED };
        self.destructive_ack(ctx, (w.command, r, w.from));
        if !ok {
            return;
        }
        if w.command == cmd::STORAGE_FORMAT {
            self.storage_information(ctx);
            let until = ctx.now.saturating_add(WATCH);
            self.destructive.watch = Some((until, card(ctx)));
        } else {
            self.params.overlay = None;
            self.params_pod_up(ctx);
        }
    }

    /// Periodic work: the pod's ACK that never came, the card after a format.
    pub(super) fn destructive_poll(&mut self, ctx: &mut Ctx<'_>) {
        if let Some(w) = self
            .destructive
            .waiting
            .filter(|w| ctx.now.saturating_duration_since(w.at) >= ACK_WAIT)
        {
            self.destructive_pod_answer(ctx, w.base, false);
        }
        let Some((until, last)) = self.destructive.watch else {
            return;
        };
        let now = card(ctx);
        if now != last {
            self.storage_information(ctx);
        }
        self.destructive.watch = (ctx.now < until).then_some((until, now));
    }

    fn destructive_ack(&mut self, ctx: &mut Ctx<'_>, (command, r, to): (u16, u8, Header)) {
        self.ack(ctx, Comp::Camera, command, r, to);
    }
}

/// The card as STORAGE_INFORMATION shows it: its state and used space (10 MB units).
fn card(ctx: &Ctx<'_>) -> (u8, u16) {
    ctx.pod()
        .system
        .map_or((u8::MAX, 0), |s| (s.sd.value(), s.sd_used_10mb))
}
