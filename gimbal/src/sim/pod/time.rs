//! The pod's clock and the time-sync receiver (an RTC_IO edge, then its 0x00030E).

use super::*;

/// Milliseconds in a day.
pub(super) const DAY_MS: i128 = 86_400_000;

/// The pod's clock: `base_unix_us` at simulated instant `base_us`.
#[derive(Debug, Clone, Copy)]
pub(super) struct PodClock {
    pub(super) base_us: u64,
    pub(super) base_unix_us: i128,
    pub(super) drift_ppm: i32,
    pub(super) synced: bool,
}

impl PodClock {
    pub(super) fn unix_us(&self, now_us: u64) -> i128 {
        let elapsed = i128::from(now_us) - i128::from(self.base_us);
        self.base_unix_us + elapsed + elapsed * i128::from(self.drift_ppm) / 1_000_000
    }
}

impl SimPod {
    pub(super) fn time_sync(&mut self, t: u64, s: k40t::TimeSync, start_us: u64) {
        let edge = self.pending_edge.take();
        let outcome = match edge {
            None => SyncOutcome::NoEdge,
            Some(e) if e > start_us => SyncOutcome::EdgeAfterFrameStart,
            Some(e) if start_us - e > self.config.sync_window_us => SyncOutcome::EdgeTooOld,
            Some(_) => SyncOutcome::Applied,
        };
        if let (SyncOutcome::Applied, Some(e)) = (outcome, edge) {
            self.clock.base_us = e;
            self.clock.base_unix_us =
                i128::from(s.unix_ms) * 1000 + i128::from(self.config.sync_error_us);
            self.clock.synced = true;
            self.tz = (s.tz_minuteswest, s.tz_dsttime);
        }
        self.syncs.push(SyncRecord {
            edge_us: edge,
            frame_start_us: start_us,
            arrival_us: t,
            unix_ms: s.unix_ms,
            tz_minuteswest: s.tz_minuteswest,
            tz_dsttime: s.tz_dsttime,
            delay_us: edge.and_then(|e| start_us.checked_sub(e)),
            outcome,
        });
    }

    /// The pod's clock at `t` as (hour, minute, second, millisecond) of the day.
    pub(super) fn time_of_day(&self, t: u64) -> (u8, u8, u8, u16) {
        let mut ms = self.clock.unix_us(t).div_euclid(1000);
        if self.config.gps_local_time {
            ms -= i128::from(self.tz.0) * 60_000;
        }
        let of_day = ms.rem_euclid(DAY_MS);
        let part = |div: i128, modulo: i128| u16::try_from(of_day / div % modulo).unwrap_or(0);
        let byte = |v: u16| u8::try_from(v).unwrap_or(0);
        (
            byte(part(3_600_000, 24)),
            byte(part(60_000, 60)),
            byte(part(1000, 60)),
            part(1, 1000),
        )
    }
}
