//! The pod's timers: the work due at each instant, in firing order.

use super::*;

/// Interval of the 0x020304 status frames while a hybrid zoom moves.
pub(super) const ZOOM_STATUS_PERIOD_US: u64 = 200_000;

/// Interval of the 0x020303 and 0x020406 status frames.
pub(super) const ONE_SECOND_US: u64 = 1_000_000;

/// Work with a due instant, in firing order for equal instants.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Timer {
    RxIdle,
    Outbox,
    Report(usize),
    ZoomStatus,
    RecordStatus,
    Laser,
    PhotoShot,
    GpsPeriodic,
    GpsTimeout,
}

impl SimPod {
    /// Takes `now_us` (never backwards), powers up on the first call and at the end of
    /// a reboot, runs due work (none while off).
    pub(super) fn enter(&mut self, now_us: u64) -> u64 {
        let now = now_us.max(self.now_us);
        if !self.booted {
            self.boot(now);
        }
        self.now_us = now;
        if let Some(on) = self.off_until {
            if now < on {
                return now;
            }
            self.boot(on);
        }
        self.run_until(now);
        now
    }

    pub(super) fn next_timer(&self) -> Option<(u64, Timer)> {
        let idle =
            (self.config.rx_idle_timeout_us > 0 && self.deframer.buffered() > 0).then(|| {
                self.last_rx_us
                    .saturating_add(self.config.rx_idle_timeout_us)
            });
        let gps = self.gps_open.front().and_then(|&i| {
            self.gps_requests
                .get(i)
                .map(|r| r.at_us.saturating_add(self.config.gps_timeout_us))
        });
        let mut candidates = vec![
            (idle, Timer::RxIdle),
            (self.outbox.first().map(|q| q.due_us), Timer::Outbox),
        ];
        candidates.extend(
            self.report_due
                .iter()
                .enumerate()
                .map(|(i, &due)| (due, Timer::Report(i))),
        );
        candidates.extend([
            (self.zoom_status_due, Timer::ZoomStatus),
            (self.record_status_due, Timer::RecordStatus),
            (self.laser_due, Timer::Laser),
            (
                [
                    self.photo_job.map(|j| j.next_us),
                    self.single_shots.front().map(|s| s.0),
                ]
                .into_iter()
                .flatten()
                .min(),
                Timer::PhotoShot,
            ),
            (self.gps_periodic_due, Timer::GpsPeriodic),
            (gps, Timer::GpsTimeout),
        ]);
        // The first of the earliest: candidates are in firing order.
        candidates
            .into_iter()
            .filter_map(|(due, timer)| due.map(|t| (t, timer)))
            .fold(None, |best: Option<(u64, Timer)>, c| match best {
                Some(b) if b.0 <= c.0 => Some(b),
                _ => Some(c),
            })
    }

    pub(super) fn run_until(&mut self, now: u64) {
        while let Some((t, timer)) = self.next_timer() {
            if t > now {
                break;
            }
            self.integrate(t);
            self.fire(timer, t);
        }
        self.integrate(now);
    }

    /// Does the work of `timer`, due at `t`; always moves the timer past `t` or clears it.
    pub(super) fn fire(&mut self, timer: Timer, t: u64) {
        match timer {
            Timer::RxIdle => {
                self.drain_deframer(t, true);
                self.prune_chunks();
            }
            Timer::Outbox => {
                while self.outbox.first().is_some_and(|q| q.due_us <= t) {
                    let q = self.outbox.remove(0);
                    self.emit(t, q.header, q.id, &q.payload);
                }
            }
            Timer::Report(i) => {
                let period = self.config.reports.as_array().get(i).copied().unwrap_or(0);
                if let Some(due) = self.report_due.get_mut(i) {
                    *due = (period > 0).then(|| t.saturating_add(period));
                }
                self.send_report(i, t);
            }
            Timer::ZoomStatus => {
                if let ZoomMotion::Target {
                    target,
                    hybrid: true,
                } = self.zoom
                {
                    self.send(
                        t,
                        &ZoomStatus {
                            state: ZoomState::Zooming,
                            reserved: 0,
                        },
                    );
                    let reach = self.zoom_reach_us(target);
                    self.zoom_status_due =
                        Some(t.saturating_add(ZOOM_STATUS_PERIOD_US.min(reach.max(1))));
                } else {
                    self.send(
                        t,
                        &ZoomStatus {
                            state: ZoomState::Done,
                            reserved: 0,
                        },
                    );
                    self.zoom_status_due = None;
                }
            }
            Timer::RecordStatus => match self.camera.recording {
                Some(rec) => {
                    self.send(t, &record_status(rec, RecordState::Recording, t));
                    self.record_status_due = Some(t.saturating_add(ONE_SECOND_US));
                }
                None => self.record_status_due = None,
            },
            Timer::Laser => {
                if self.camera.laser_periodic {
                    self.send(t, &LaserPeriodicStatus(self.laser_reading()));
                    self.laser_due = Some(t.saturating_add(ONE_SECOND_US));
                } else {
                    self.laser_due = None;
                }
            }
            Timer::PhotoShot => self.take_shot(t),
            Timer::GpsPeriodic => self.periodic_gps(t),
            Timer::GpsTimeout => {
                if let Some(i) = self.gps_open.pop_front() {
                    if let Some(r) = self.gps_requests.get_mut(i) {
                        r.timed_out = true;
                    }
                    self.gps_unanswered += 1;
                }
            }
        }
    }
}
