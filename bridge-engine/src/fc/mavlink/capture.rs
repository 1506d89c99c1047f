//! Captures: one CAMERA_IMAGE_CAPTURED per photo the pod takes (see
//! docs/src/bridge/mavlink.md, "Captures").
//!
//! The pod tells of a photo only by its GPS request ("Before taking a photo, a GPS request
//! command will be sent to the flight controller": K40T external protocol, 3.2.4.3 and
//! 3.2.4.15), the ACK of a photo command, and the photo status frames 0x020302, sent for
//! bursts and time-lapses, none for a single shot. It also asks for GPS without taking a
//! photo (periodically, while recording). So a GPS request is a photo's only when a photo
//! is expected:
//! - **A photo command the bridge sent** (IMAGE_START_CAPTURE, each shot of an interval),
//!   before its ACK or after an OK one: one photo in the pod's single mode; the burst count
//!   of its 0x000003 (3.2.1.1) in burst mode; every photo until the series ends in
//!   time-lapse mode.
//! - **A series the pod runs** (its own burst or time-lapse, known from a status frame
//!   "burst" or "time-lapse in progress"): every request while it runs, and the one just
//!   before its first frame (the pod asks, then shoots, then reports). A series ends with
//!   "photo taken" or "stopped", or [`SERIES_IDLE`] after its last request.
//!
//! A commanded photo is taken after its command went: a request naming an instant before
//! it (beyond the time sync's error) is not that photo's. Any other request (periodic, or
//! a single photo the pod took alone, which nothing tells from a periodic one) is
//! answered as a geotag and not reported; a periodic request that comes between a
//! command and its photo's own request is taken for the photo (nothing tells them apart
//! either). The request's "lens
//! enable" byte is not used: the document does not say what it means for a request.
//!
//! **Report**, once the photo's geotag has been answered (a fix at or after its instant
//! came, or the geotagger's wait is over): `capture_result` 1 with the photo's UTC (the
//! instant the request named) and the geotag's position; 0 with no position when the
//! geotag could not be answered (no UTC: no time either; no fix: the time). A photo ACKed
//! OK whose request never comes (the pod asks none before its clock is synced) is reported
//! [`GPS_WAIT`] after the ACK with 0, no position, the ACK's UTC. **Indices count photos**;
//! a command the pod refused or never answered, or a photo it reported failed
//! ("photo taken failed", an SD card error), made none: reported with 0 and index −1
//! (MAVSDK reports no index that is not above the last it saw; QGroundControl plots only
//! successes).

use crate::fc::Ctx;
use crate::time::{Duration, Instant, TimeOfDay};
use protocol_core::k40t::{GpsRequest, PhotoMode, PhotoState};
use protocol_core::mavlink::MavMessage;
use protocol_core::mavlink::dialect::{CAMERA_IMAGE_CAPTURED_DATA, CharArray, MavBool};

use super::gimbal::{PITCH_SHOWN, boot_ms};
use super::{Comp, MavlinkSide, math};

/// Photos in flight at once (ACK, request or geotag pending).
const SHOTS: usize = 4;
/// A photo the pod ACKed asks its position within this, or it is reported without.
const GPS_WAIT: Duration = Duration::from_secs(1);
/// Beyond the engine's wait for the next fix (250 ms): the geotag has been answered.
const GEOTAG_WAIT: Duration = Duration::from_millis(300);
/// A photo whose ACK never comes is given up after this.
const SHOT_WAIT: Duration = Duration::from_secs(2);
/// A request no photo claimed is kept this long, for a series status that may follow.
const HELD: Duration = Duration::from_millis(500);
/// A series with no request for this long (beyond its time-lapse period) has ended.
const SERIES_IDLE: Duration = Duration::from_secs(3);
/// A commanded photo is taken after its command went: a request naming an instant
/// earlier than the command by more than this (the time sync's error, with margin) is
/// not that photo's.
const BEFORE_COMMAND: Duration = Duration::from_millis(10);

/// A photo on its way.
#[derive(Debug, Clone, Copy)]
struct Shot {
    /// When the photo command went, or (a series' photo) its request came.
    since: Instant,
    /// The pod's ACK: when, and OK (a series' photo: its request).
    acked: Option<(Instant, bool)>,
    /// The GPS request: the instant it named (`None`: no UTC to map it) and when it came.
    asked: Option<(Option<Instant>, Instant)>,
    /// The pod reported the photo failed.
    failed: bool,
}

/// The last CAMERA_IMAGE_CAPTURED, for a request of it again.
#[derive(Debug, Clone, Copy)]
pub(super) struct Captured {
    pub(super) index: i32,
    time_utc: u64,
    time_boot_ms: u32,
    /// Latitude, longitude (degE7), MSL and relative altitude (mm); zeros: unknown.
    position: [i32; 4],
    q: [f32; 4],
    ok: bool,
}

/// What the camera knows of the photos the pod takes.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Captures {
    shots: [Option<Shot>; SHOTS],
    /// Photos of a commanded burst still to come (beyond the shot of the command).
    burst_left: u8,
    /// A series runs until this instant (renewed by each of its requests).
    series_until: Option<Instant>,
    /// A request no photo claimed: the instant it named, when it came.
    held: Option<(Option<Instant>, Instant)>,
    /// Photos reported (the next image index).
    pub(super) image_count: i32,
    /// The last report.
    pub(super) last: Option<Captured>,
    /// GPS requests that were no photo's.
    pub(super) not_photos: u32,
}

impl Captures {
    /// A photo is in flight (CAMERA_CAPTURE_STATUS: capturing).
    pub(super) fn busy(&self) -> bool {
        self.shots.iter().any(Option::is_some)
    }

    /// When the captures have work.
    pub(super) fn poll_at(&self) -> Option<Instant> {
        let shots = self
            .shots
            .iter()
            .flatten()
            .map(|s| match (s.acked, s.asked) {
                (_, Some((_, when))) => when.saturating_add(GEOTAG_WAIT),
                (Some((at, _)), None) => at.saturating_add(GPS_WAIT),
                (None, None) => s.since.saturating_add(SHOT_WAIT),
            });
        let held = self.held.map(|(_, when)| when.saturating_add(HELD));
        shots.chain(held).chain(self.series_until).min()
    }

    /// Puts a shot in a free slot (all taken: the oldest is reported first by the caller).
    fn put(&mut self, shot: Shot) {
        if let Some(slot) = self.shots.iter_mut().find(|s| s.is_none()) {
            *slot = Some(shot);
        }
    }
}

impl MavlinkSide {
    /// A photo command went to the pod.
    pub(super) fn capture_commanded(&mut self, ctx: &mut Ctx<'_>) {
        self.make_room(ctx);
        self.camera.captures.put(Shot {
            since: ctx.now,
            acked: None,
            asked: None,
            failed: false,
        });
    }

    /// Every slot taken: the oldest is reported with what it has.
    fn make_room(&mut self, ctx: &mut Ctx<'_>) {
        if self.camera.captures.shots.iter().all(Option::is_some) {
            self.finish_shot(ctx, 0);
        }
    }

    /// The pod answered a photo command (or never did: `ok` false).
    pub(super) fn capture_acked(&mut self, ctx: &mut Ctx<'_>, ok: bool) {
        let c = &mut self.camera.captures;
        let Some(i) = c
            .shots
            .iter()
            .position(|s| s.is_some_and(|s| s.acked.is_none()))
        else {
            return;
        };
        if let Some(Some(s)) = c.shots.get_mut(i) {
            s.acked = Some((ctx.now, ok));
        }
        if !ok {
            self.finish_shot(ctx, i);
            return;
        }
        // The pod shoots as its photo mode says (0x000003).
        let system = ctx.pod().system;
        match system.map(|s| s.photo_mode) {
            Some(PhotoMode::Burst) => {
                let n = system.map_or(1, |s| s.burst_count.max(1));
                c.burst_left = c.burst_left.saturating_add(n.saturating_sub(1));
            }
            Some(PhotoMode::TimeLapse) => {
                let period = system.map_or(0, |s| s.timelapse_s);
                c.series_until = Some(series_end(ctx.now, period));
            }
            _ => {}
        }
    }

    /// A photo status frame (0x020302).
    pub(super) fn capture_photo_status(&mut self, ctx: &mut Ctx<'_>, state: PhotoState) {
        let period = ctx.pod().system.map_or(0, |s| s.timelapse_s);
        let c = &mut self.camera.captures;
        match state {
            PhotoState::Burst | PhotoState::TimeLapse => {
                c.series_until = Some(series_end(ctx.now, period));
                // The pod asked, then shot, then reported: the request held was this
                // series' photo.
                if let Some(asked) = c.held.take() {
                    self.series_photo(ctx, asked);
                }
            }
            PhotoState::Taken => c.series_until = None,
            PhotoState::Stopped => {
                c.series_until = None;
                c.burst_left = 0;
            }
            PhotoState::Failed
            | PhotoState::NoSdCard
            | PhotoState::SdFull
            | PhotoState::SdAbnormal
            | PhotoState::SdFormatError => {
                // The newest photo in flight is the one that failed.
                if let Some(s) = c.shots.iter_mut().rev().flatten().next() {
                    s.failed = true;
                }
            }
            _ => {}
        }
    }

    /// A photo of a series (its request came at `asked`).
    fn series_photo(&mut self, ctx: &mut Ctx<'_>, asked: (Option<Instant>, Instant)) {
        self.make_room(ctx);
        self.camera.captures.put(Shot {
            since: asked.1,
            acked: Some((asked.1, true)),
            asked: Some(asked),
            failed: false,
        });
    }

    /// The pod asks for a position (see the module documentation for which request is
    /// a photo's).
    pub(super) fn capture_gps_request(&mut self, ctx: &mut Ctx<'_>, r: GpsRequest) {
        let at = TimeOfDay::new(r.hour, r.minute, r.second, r.millisecond)
            .and_then(|tod| ctx.time.utc(ctx.now)?.nearest_with_time_of_day(tod))
            .and_then(|utc| ctx.time.local_of(utc));
        let asked = (at, ctx.now);
        let c = &mut self.camera.captures;
        // A commanded photo the request may be of: not asked about, and not taken before
        // its command went.
        let open = |s: &Shot| {
            s.asked.is_none() && at.is_none_or(|at| at.saturating_add(BEFORE_COMMAND) >= s.since)
        };
        // The oldest photo the pod ACKed; else the oldest not yet ACKed (the request says
        // it shoots).
        let pick = c
            .shots
            .iter()
            .position(|s| s.is_some_and(|s| open(&s) && s.acked.is_some_and(|a| a.1)))
            .or_else(|| {
                c.shots
                    .iter()
                    .position(|s| s.is_some_and(|s| open(&s) && s.acked.is_none()))
            });
        if let Some(Some(s)) = pick.and_then(|i| c.shots.get_mut(i)) {
            s.asked = Some(asked);
            s.acked = s.acked.or(Some((ctx.now, true)));
            return;
        }
        if c.burst_left > 0 {
            c.burst_left = c.burst_left.saturating_sub(1);
            self.series_photo(ctx, asked);
            return;
        }
        if c.series_until.is_some_and(|t| ctx.now <= t) {
            let period = ctx.pod().system.map_or(0, |s| s.timelapse_s);
            c.series_until = Some(series_end(ctx.now, period));
            self.series_photo(ctx, asked);
            return;
        }
        // No photo expected: held a moment for a series status, else no photo's.
        if c.held.replace(asked).is_some() {
            c.not_photos = c.not_photos.saturating_add(1);
        }
    }

    /// Periodic work: held requests and series that ended, photos to report.
    pub(super) fn capture_poll(&mut self, ctx: &mut Ctx<'_>) {
        let c = &mut self.camera.captures;
        if c.held
            .is_some_and(|(_, when)| ctx.now.saturating_duration_since(when) >= HELD)
        {
            c.held = None;
            c.not_photos = c.not_photos.saturating_add(1);
        }
        if c.series_until.is_some_and(|t| ctx.now > t) {
            c.series_until = None;
        }
        self.finish_shots(ctx);
    }

    /// Reports every photo whose geotag is answered (or no longer expected).
    pub(super) fn finish_shots(&mut self, ctx: &mut Ctx<'_>) {
        for i in 0..SHOTS {
            let Some(s) = self.camera.captures.shots.get(i).copied().flatten() else {
                continue;
            };
            let done = match (s.acked, s.asked) {
                (_, Some((Some(at), when))) => {
                    ctx.fixes.latest().is_some_and(|f| f.at >= at)
                        || ctx.now.saturating_duration_since(when) >= GEOTAG_WAIT
                }
                (_, Some((None, _))) | (Some((_, false)), None) => true,
                (Some((at, true)), None) => ctx.now.saturating_duration_since(at) >= GPS_WAIT,
                (None, None) => ctx.now.saturating_duration_since(s.since) >= SHOT_WAIT,
            };
            if done {
                self.finish_shot(ctx, i);
            }
        }
    }

    /// Sends CAMERA_IMAGE_CAPTURED for shot `i` and forgets it.
    fn finish_shot(&mut self, ctx: &mut Ctx<'_>, i: usize) {
        let Some(s) = self.camera.captures.shots.get_mut(i).and_then(Option::take) else {
            return;
        };
        // A photo exists: the pod ACKed (or asked for) it and did not report it failed.
        let photo = s.acked.is_some_and(|a| a.1) && !s.failed;
        // The photo's instant: the one its request named, else its ACK's.
        let at = match s.asked {
            Some((at, _)) => at,
            None => s.acked.map(|a| a.0),
        };
        let fix = at
            .filter(|_| photo && s.asked.is_some())
            .and_then(|at| ctx.fixes.at(at).ok());
        let time_utc = at
            .filter(|_| photo)
            .and_then(|at| ctx.time.utc(at))
            .map_or(0, crate::time::UtcTime::as_unix_micros);
        let ok = fix.is_some() && time_utc != 0;
        let c = &mut self.camera.captures;
        let index = if photo {
            let n = c.image_count;
            c.image_count = n.saturating_add(1);
            n
        } else {
            -1
        };
        let captured = Captured {
            index,
            time_utc,
            time_boot_ms: at.map_or_else(
                || boot_ms(ctx),
                |t| u32::try_from(t.as_millis() % (1u64 << 32)).unwrap_or(0),
            ),
            position: fix.filter(|_| ok).map_or([0; 4], |f| {
                let mm = |dm: i16| i32::from(dm).saturating_mul(100);
                [f.lat_e7, f.lon_e7, mm(f.alt_msl_dm), mm(f.rel_alt_dm)]
            }),
            q: self.camera_attitude(ctx),
            ok,
        };
        self.camera.captures.last = Some(captured);
        self.send_captured(ctx, &captured);
    }

    /// The camera's attitude: the pod's roll and pitch, its yaw from north when the
    /// aircraft's heading is known (else NaN: unknown).
    pub(super) fn camera_attitude(&self, ctx: &Ctx<'_>) -> [f32; 4] {
        let Some(a) = ctx.fresh_attitude() else {
            return [f32::NAN; 4];
        };
        let Some(v) = self.vehicle(ctx.now) else {
            return [f32::NAN; 4];
        };
        let yaw = math::wrap_cdeg(v.yaw.saturating_add(i32::from(a.yaw_joint_cdeg)));
        let pitch = i32::from(a.pitch_cdeg).clamp(-PITCH_SHOWN, PITCH_SHOWN);
        math::quaternion([
            math::rad(i32::from(a.roll_cdeg)),
            math::rad(pitch),
            math::rad(yaw),
        ])
    }

    pub(super) fn send_captured(&mut self, ctx: &mut Ctx<'_>, c: &Captured) {
        let [lat, lon, alt, relative_alt] = c.position;
        let msg = MavMessage::CAMERA_IMAGE_CAPTURED(CAMERA_IMAGE_CAPTURED_DATA {
            time_utc: c.time_utc,
            time_boot_ms: c.time_boot_ms,
            lat,
            lon,
            alt,
            relative_alt,
            q: c.q,
            image_index: c.index,
            camera_id: 0,
            capture_result: if c.ok {
                MavBool::MAV_BOOL_TRUE
            } else {
                MavBool::MAV_BOOL_FALSE
            },
            file_url: CharArray::from([0u8; 205]),
        });
        self.send(ctx, Comp::Camera, &msg);
    }
}

/// When a series with time-lapse period `period_s` (0: unknown) ends without another
/// request.
fn series_end(now: Instant, period_s: u8) -> Instant {
    let period = Duration::from_secs(u64::from(period_s));
    now.saturating_add(period.saturating_add(SERIES_IDLE))
}
