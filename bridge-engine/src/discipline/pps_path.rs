//! The PPS path of the [`TimeDiscipline`]: each edge labelled with its UTC second (from
//! the PPS line, checked against the FC's mapping), the lock, the holdover on the line
//! and the slew back to the FC's mapping (see the [discipline](super), "PPS").

use super::pps::Edge;
use super::{PpsState, PpsVerdict, Slew, TimeDiscipline, Using};
use crate::time::{Duration, Instant, InstantNs, UtcTime};

impl TimeDiscipline {
    /// Where the PPS path stands.
    #[must_use]
    pub fn pps_state(&self) -> PpsState {
        match self.using {
            Using::Pps if self.pps.locked => PpsState::Locked,
            Using::Pps => PpsState::Holdover,
            Using::Fc | Using::Slew(_) => PpsState::Off,
        }
    }

    /// The local instant (ns) of the first edge of the PPS run now locked.
    #[must_use]
    pub fn pps_run_start(&self) -> Option<InstantNs> {
        let ns = self.pps.run_start?;
        u64::try_from(ns).ok().map(InstantNs::from_nanos)
    }

    /// A PPS edge (the module's on-time edge) captured at local `edge`. It is labelled
    /// with its UTC second (see docs/src/bridge/time.md, "PPS") and fitted.
    pub fn pps_edge(&mut self, edge: InstantNs) -> PpsVerdict {
        let local = edge.instant();
        self.advance(local);
        let Ok(y) = i64::try_from(edge.as_nanos()) else {
            return PpsVerdict::Rejected;
        };
        let from_line = self.pps.label(y);
        let from_fc = self.fc_label(local);
        let (second, verdict) = match (from_line, from_fc) {
            (Some(a), Some(b)) if a == b => {
                self.pps.agreed();
                (a, PpsVerdict::Accepted)
            }
            (Some(a), Some(b)) => {
                if self.pps.conflict() {
                    // The FC insists: its UTC names the seconds.
                    self.pps.restart();
                    (b, PpsVerdict::Conflict)
                } else {
                    (a, PpsVerdict::Conflict)
                }
            }
            (Some(a), None) => (a, PpsVerdict::Accepted),
            (None, Some(b)) => (b, PpsVerdict::Accepted),
            (None, None) => return PpsVerdict::Unlabelled,
        };
        let taken = self.pps.take(
            Edge {
                second,
                local_ns: y,
            },
            &self.pps_config,
        );
        self.advance(local);
        match taken {
            Ok(()) => verdict,
            Err(v) => v,
        }
    }

    /// The UTC second the FC's mapping names for an edge at `local`, when it is sure of
    /// it (see the [module documentation](self), "PPS").
    fn fc_label(&self, local: Instant) -> Option<i64> {
        let utc = self.fc_utc(local)?.as_unix_micros();
        let bound = self.fc_error_bound(local)?.as_micros();
        let second = utc.checked_add(500_000)? / 1_000_000;
        let diff = utc.abs_diff(second.checked_mul(1_000_000)?);
        let tolerance = self.pps_config.label_tolerance.as_micros();
        if diff.saturating_add(bound) < 500_000 && diff <= bound.saturating_add(tolerance) {
            i64::try_from(second).ok()
        } else {
            None
        }
    }

    /// A change of [`PpsState`] since the last call, once.
    pub fn poll_pps(&mut self) -> Option<PpsState> {
        let now = self.pps_state();
        if now == self.pps_reported {
            return None;
        }
        self.pps_reported = now;
        Some(now)
    }

    /// When the PPS path changes by itself: the lock's time-out, the end of the
    /// holdover, and (in holdover or slewing back) once a second to hand back in time.
    pub(super) fn pps_poll_at(&self) -> Option<Instant> {
        let last = self.pps.last().and_then(|e| u64::try_from(e.local_ns).ok());
        let at = |d: Duration| last.map(|ns| Instant::from_micros(ns / 1_000).saturating_add(d));
        match self.using {
            Using::Pps if self.pps.locked => at(self.pps_config.timeout),
            Using::Pps | Using::Slew(_) => {
                let tick = self.now.saturating_add(Duration::from_secs(1));
                Some(at(self.pps_config.holdover).map_or(tick, |h| h.min(tick)))
            }
            Using::Fc => None,
        }
    }

    /// The PPS path at `self.now`: lock time-out, holdover end, and which mapping to use.
    pub(super) fn advance_pps(&mut self) {
        let x = i64::try_from(self.now.as_micros()).unwrap_or(i64::MAX);
        let now_ns = x.saturating_mul(1_000);
        if let Some(last) = self.pps.last() {
            let age = u64::try_from(now_ns.saturating_sub(last.local_ns)).unwrap_or(0);
            if age > self.pps_config.holdover.as_micros().saturating_mul(1_000) {
                self.pps.restart();
            } else if age > self.pps_config.timeout.as_micros().saturating_mul(1_000) {
                self.pps.locked = false;
            }
        }
        let fc_usable = self.state.is_usable() && self.output.is_some();
        self.using = match self.using {
            _ if self.pps.locked => Using::Pps,
            Using::Pps => {
                let pps = self.pps_error_bound_ns(x);
                let fc = self
                    .fc_error_bound(self.now)
                    .map(|b| u128::from(b.as_micros()).saturating_mul(1_000));
                match (pps, fc) {
                    (Some(p), Some(f)) if f < p => self.slew_from_pps(x),
                    (Some(_), _) => Using::Pps,
                    (None, _) if fc_usable => self.slew_from_pps(x),
                    (None, _) => Using::Fc,
                }
            }
            Using::Slew(s) if fc_usable && self.slew_left(s, x) != 0 => Using::Slew(s),
            Using::Slew(_) | Using::Fc => Using::Fc,
        };
    }

    /// The hand-back from the PPS line at `x`: a slew from its offset to the FC's (none
    /// left when either is unknown).
    pub(super) fn slew_from_pps(&self, x: i64) -> Using {
        let pps = self
            .pps_utc_ns(x.saturating_mul(1_000))
            .map(|u| i128::from(x).saturating_sub(u / 1_000));
        let fc = self.output.and_then(|o| o.line.offset_at(x));
        match (pps, fc) {
            (Some(p), Some(f)) => {
                let d0 = i64::try_from(p.saturating_sub(i128::from(f))).unwrap_or(0);
                if d0 == 0 {
                    Using::Fc
                } else {
                    Using::Slew(Slew { x0: x, d0 })
                }
            }
            _ => Using::Fc,
        }
    }

    /// What is left of the slew's offset at `x`, µs.
    pub(super) fn slew_left(&self, s: Slew, x: i64) -> i64 {
        let elapsed = u128::try_from(x.saturating_sub(s.x0)).unwrap_or(0);
        let slewed =
            elapsed.saturating_mul(u128::from(self.pps_config.handback_slew_ppm)) / 1_000_000;
        let left = u128::from(s.d0.unsigned_abs()).saturating_sub(slewed);
        let left = i64::try_from(left).unwrap_or(0);
        if s.d0 < 0 {
            left.saturating_neg()
        } else {
            left
        }
    }

    /// UTC (ns) of the PPS line at local `x_ns`, within its holdover.
    pub(super) fn pps_utc_ns(&self, x_ns: i64) -> Option<i128> {
        let last = self.pps.last()?;
        let horizon = last.local_ns.checked_add(
            i64::try_from(self.pps_config.holdover.as_micros().checked_mul(1_000)?).ok()?,
        )?;
        if x_ns > horizon {
            return None;
        }
        self.pps.line?.utc_ns(i128::from(x_ns))
    }

    /// The error the PPS line believes it has at `x` µs, ns: one edge's error, twice the
    /// recent spread, and the holdover drift since the last edge.
    pub(super) fn pps_error_bound_ns(&self, x: i64) -> Option<u128> {
        let last = self.pps.last()?;
        self.pps.line?;
        let x_ns = x.checked_mul(1_000)?;
        let age = u128::from(x_ns.abs_diff(last.local_ns));
        let drift = age.saturating_mul(u128::from(self.pps_config.holdover_ppm)) / 1_000_000;
        Some(
            u128::from(self.pps_config.edge_error_ns)
                .saturating_add(u128::from(self.pps.spread_ns).saturating_mul(2))
                .saturating_add(drift),
        )
    }

    /// UTC at local instant `at` in nanoseconds since the Unix epoch (the PPS line's
    /// resolution; the FC's mapping is known to the microsecond), with the conditions of
    /// [`utc`](Self::utc).
    #[must_use]
    pub fn utc_ns(&self, at: InstantNs) -> Option<u64> {
        if self.using == Using::Pps {
            let ns = self.pps_utc_ns(i64::try_from(at.as_nanos()).ok()?)?;
            return u64::try_from(ns).ok();
        }
        let us = self.utc(at.instant())?.as_unix_micros();
        us.checked_mul(1_000)?
            .checked_add(u64::from(at.sub_micros_ns()))
    }

    /// The local instant (ns) at which UTC is `utc`: the PPS line's to the nanosecond,
    /// else [`local_of`](Self::local_of)'s microsecond.
    #[must_use]
    pub fn local_of_ns(&self, utc: UtcTime) -> Option<InstantNs> {
        if self.using == Using::Pps {
            let r = i128::from(utc.as_unix_micros()).checked_mul(1_000)?;
            let x = self.pps.line?.local_ns(r)?;
            let last = self.pps.last()?;
            let horizon = i128::from(last.local_ns).checked_add(i128::from(
                self.pps_config.holdover.as_micros().checked_mul(1_000)?,
            ))?;
            if x > horizon {
                return None;
            }
            return u64::try_from(x).ok().map(InstantNs::from_nanos);
        }
        self.local_of(utc).map(InstantNs::from_instant)
    }
}
