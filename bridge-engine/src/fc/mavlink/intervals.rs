//! A message the camera sends at the interval a client asks with
//! MAV_CMD_SET_MESSAGE_INTERVAL: param2 the interval in µs, 0 the message's default
//! rate, −1 (any negative value) stop; a faster interval than the message's least is
//! clamped to it (docs/src/bridge/mavlink.md, "Message intervals").

use crate::time::{Duration, Instant};

/// The interval of one message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Every {
    /// `None`: not sent at an interval.
    period: Option<Duration>,
    /// When it is next due.
    next: Instant,
}

impl Every {
    /// Not sent unasked.
    pub(super) const OFF: Self = Self {
        period: None,
        next: Instant::ZERO,
    };

    /// Sent every `period` from the start.
    pub(super) const fn at_interval(period: Duration) -> Self {
        Self {
            period: Some(period),
            next: Instant::ZERO,
        }
    }

    /// Applies SET_MESSAGE_INTERVAL's param2 (`us`): `default` for 0, `least` bounds a
    /// positive interval, a negative one stops. The first message is due now. Returns
    /// false for a value that is not a number.
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // clamped first
    pub(super) fn set(
        &mut self,
        now: Instant,
        us: f32,
        default: Duration,
        least: Duration,
    ) -> bool {
        if us.is_nan() {
            return false;
        }
        self.period = if us < 0.0 {
            None
        } else if us < 1.0 {
            Some(default)
        } else {
            let us = us.min(3_600_000_000.0) as u64;
            Some(Duration::from_micros(us).max(least))
        };
        self.next = now;
        true
    }

    /// True (and the next instant planned) when the message is due at `now`.
    pub(super) fn due(&mut self, now: Instant) -> bool {
        match self.period {
            Some(p) if now >= self.next => {
                // Late polls do not make bursts: the next is a period after now.
                self.next = now.saturating_add(p);
                true
            }
            _ => false,
        }
    }

    /// When it is next due (`None`: not at an interval).
    pub(super) fn at(&self) -> Option<Instant> {
        self.period.map(|_| self.next)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intervals_default_clamp_and_stop() {
        let s = Duration::from_secs;
        let ms = Duration::from_millis;
        let t = Instant::from_millis;
        let mut e = Every::OFF;
        assert!(!e.due(t(0)) && e.at().is_none());
        assert!(e.set(t(10), 0.0, s(1), ms(200)));
        assert!(e.due(t(10)) && !e.due(t(500)) && e.due(t(1010)));
        assert!(e.set(t(2000), 50_000.0, s(1), ms(200)));
        assert!(e.due(t(2000)));
        assert_eq!(e.at(), Some(t(2200)));
        assert!(e.set(t(3000), 500_000.0, s(1), ms(200)));
        e.due(t(3000));
        assert_eq!(e.at(), Some(t(3500)));
        assert!(e.set(t(4000), -1.0, s(1), ms(200)));
        assert!(e.at().is_none() && !e.due(t(9000)));
        assert!(!e.set(t(4000), f32::NAN, s(1), ms(200)));
        assert!(Every::at_interval(s(1)).at().is_some());
    }
}
