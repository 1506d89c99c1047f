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
//! **Photo order.** Each photo gets its place in the order the photos were taken when it
//! becomes known (a command in the order the commands went, a series' photo when its
//! request comes), and everything is matched by that order, never by where a photo is
//! kept: the pod driver reports the ACK of the newest photo command only (a newer command
//! supersedes an older one's, whose ACK is then absorbed), so an ACK or a time-out is the
//! newest command's; a request goes to the oldest photo it can be of; and a request that
//! names an instant before a photo still unreported came out of order and takes that
//! photo's place (the photos keep the order of the instants their requests named).
//! Photos are reported in that order: a photo whose geotag is answered waits for the
//! older ones still in flight (at most [`SHOT_WAIT`]); a command the pod refused or never
//! answered, which is no photo, is reported at once.
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

/// Photos in flight at once (ACK, request or geotag pending, or waiting for an older
/// photo): photos commanded 150 ms apart that the pod takes 400 ms later, each waiting
/// for the requests of the commands before its instant, keep six in flight.
const SHOTS: usize = 8;
/// A photo the pod ACKed asks its position within this, or it is reported without.
const GPS_WAIT: Duration = Duration::from_secs(1);
/// Beyond the engine's wait for the next fix (250 ms): the geotag has been answered.
const GEOTAG_WAIT: Duration = Duration::from_millis(300);
/// A photo whose ACK never comes is given up after this.
const SHOT_WAIT: Duration = Duration::from_secs(2);
/// A photo whose request named an instant after another photo's command, whose request
/// has not come yet, waits this long for it (that request may name an earlier instant).
const REORDER_WAIT: Duration = Duration::from_secs(1);
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
    /// Its place in the order the photos were taken.
    order: u32,
    /// When the photo command went, or (a series' photo) its request came.
    since: Instant,
    /// The pod's ACK of its command: when, and OK (a series' photo: its request).
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
    /// The next photo's place in the order.
    next_order: u32,
    /// The newest photo command (its order) while its ACK is awaited.
    commanded: Option<u32>,
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

    /// When the captures have work: the oldest photo's deadline (every other photo
    /// waits for it), and the deadlines of the commands not yet known to be photos (a
    /// command that made none is reported at once).
    pub(super) fn poll_at(&self) -> Option<Instant> {
        let first = self.oldest(|_| true);
        let shots = self
            .shots
            .iter()
            .enumerate()
            .filter_map(|(i, s)| s.map(|s| (i, s)))
            .filter(|(i, s)| Some(*i) == first || !is_photo(s))
            .filter_map(|(_, s)| self.deadline(&s));
        let held = self.held.map(|(_, when)| when.saturating_add(HELD));
        shots.chain(held).chain(self.series_until).min()
    }

    /// When photo `s` is done at the latest (`None`: now).
    fn deadline(&self, s: &Shot) -> Option<Instant> {
        match (s.acked, s.asked) {
            (_, Some((Some(at), when))) => {
                Some(when.saturating_add(if self.may_precede(s.order, at) {
                    REORDER_WAIT
                } else {
                    GEOTAG_WAIT
                }))
            }
            (_, Some((None, _))) | (Some((_, false)), None) => None,
            (Some((at, true)), None) => Some(at.saturating_add(GPS_WAIT)),
            (None, None) => Some(s.since.saturating_add(SHOT_WAIT)),
        }
    }

    /// Photo `s` is done at `now` (the newest fix at `fix`): its geotag answered (a fix
    /// at or after its instant, and no other request can come before it), or its
    /// deadline passed.
    fn done(&self, s: &Shot, now: Instant, fix: Option<Instant>) -> bool {
        let answered = match s.asked {
            Some((Some(at), _)) => fix.is_some_and(|f| f >= at) && !self.may_precede(s.order, at),
            _ => false,
        };
        answered || self.deadline(s).is_none_or(|d| now >= d)
    }

    /// Another photo's request may still come and name an instant before `at`: a photo
    /// command went before `at` and its request has not come, or a commanded burst has
    /// photos to come.
    fn may_precede(&self, order: u32, at: Instant) -> bool {
        self.burst_left > 0
            || self.shots.iter().flatten().any(|o| {
                o.order != order
                    && o.asked.is_none()
                    && o.acked.is_none_or(|a| a.1)
                    && o.since <= at.saturating_add(BEFORE_COMMAND)
            })
    }

    /// Puts a shot, next in the order, in a free slot (all taken: the oldest is reported
    /// first by the caller); returns its slot.
    fn put(&mut self, since: Instant, acked: Option<(Instant, bool)>) -> Option<usize> {
        let order = self.next_order;
        self.next_order = order.wrapping_add(1);
        let i = self.shots.iter().position(Option::is_none)?;
        if let Some(slot) = self.shots.get_mut(i) {
            *slot = Some(Shot {
                order,
                since,
                acked,
                asked: None,
                failed: false,
            });
        }
        Some(i)
    }

    /// The slot of the photo with place `order`.
    fn slot_of(&self, order: u32) -> Option<usize> {
        self.shots
            .iter()
            .position(|s| s.is_some_and(|s| s.order == order))
    }

    /// The slot of the oldest photo (first in the order) that `f` accepts.
    fn oldest(&self, f: impl Fn(&Shot) -> bool) -> Option<usize> {
        self.shots
            .iter()
            .enumerate()
            .filter_map(|(i, s)| s.filter(|s| f(s)).map(|s| (s.order, i)))
            .min()
            .map(|(_, i)| i)
    }

    /// The slots in the order of their photos (then `SHOTS`, no slot, for the empty
    /// ones). Selection, not a sort: eight slots, and no sort routine in the firmware.
    fn in_order(&self) -> [usize; SHOTS] {
        let mut slots = [SHOTS; SHOTS];
        let mut last: Option<u32> = None;
        for slot in &mut slots {
            let next = self
                .shots
                .iter()
                .enumerate()
                .filter_map(|(i, s)| s.map(|s| (s.order, i)))
                .filter(|(order, _)| last.is_none_or(|l| *order > l))
                .min();
            if let Some((order, i)) = next {
                *slot = i;
                last = Some(order);
            }
        }
        slots
    }

    /// Requests given out of order (one named an instant before an older photo's still
    /// unreported: it came late, or went to a photo ACKed before an older one) move so
    /// that the photos keep the order of the instants their requests named: the
    /// earliest request goes to the oldest photo that has one, and so on.
    fn keep_request_order(&mut self) {
        let named = |s: &Option<Shot>| s.and_then(|s| s.asked.filter(|a| a.0.is_some()));
        let asked: [Option<(Option<Instant>, Instant)>; SHOTS] =
            core::array::from_fn(|i| self.shots.get(i).and_then(named));
        let mut given = [false; SHOTS];
        for i in self.in_order() {
            if self.shots.get(i).and_then(named).is_none() {
                continue;
            }
            let earliest = asked
                .iter()
                .zip(&given)
                .enumerate()
                .filter_map(|(j, (a, g))| a.filter(|_| !*g).map(|a| (a.0, j)))
                .min();
            let Some((_, j)) = earliest else {
                return;
            };
            if let Some(g) = given.get_mut(j) {
                *g = true;
            }
            if let (Some(Some(s)), Some(a)) = (self.shots.get_mut(i), asked.get(j).copied()) {
                s.asked = a;
            }
        }
    }
}

/// The photo was taken: the pod ACKed its command, or asked for its position, and did not
/// report it failed.
fn is_photo(s: &Shot) -> bool {
    (s.asked.is_some() || s.acked.is_some_and(|a| a.1)) && !s.failed
}

impl MavlinkSide {
    /// A photo command went to the pod.
    pub(super) fn capture_commanded(&mut self, ctx: &mut Ctx<'_>) {
        self.make_room(ctx);
        let c = &mut self.camera.captures;
        let order = c.next_order;
        c.commanded = c.put(ctx.now, None).map(|_| order);
    }

    /// Every slot taken: the oldest is reported with what it has.
    fn make_room(&mut self, ctx: &mut Ctx<'_>) {
        let c = &self.camera.captures;
        if c.shots.iter().all(Option::is_some)
            && let Some(i) = c.oldest(|_| true)
        {
            self.finish_shot(ctx, i);
        }
    }

    /// The pod answered the newest photo command (or never did: `ok` false).
    pub(super) fn capture_acked(&mut self, ctx: &mut Ctx<'_>, ok: bool) {
        let c = &mut self.camera.captures;
        let Some(i) = c.commanded.take().and_then(|o| c.slot_of(o)) else {
            // Reported already (its request came and its geotag was answered).
            return;
        };
        let Some(Some(s)) = c.shots.get_mut(i) else {
            return;
        };
        if !ok && s.asked.is_some() {
            // The pod asked for the photo's position: it shot.
            return;
        }
        s.acked = Some((ctx.now, ok));
        if !ok {
            self.finish_shots(ctx);
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
                let newest = c.shots.iter().flatten().map(|s| s.order).max();
                if let Some(s) = c
                    .shots
                    .iter_mut()
                    .flatten()
                    .find(|s| Some(s.order) == newest)
                {
                    s.failed = true;
                }
            }
            _ => {}
        }
    }

    /// A photo of a series (its request came at `asked`).
    fn series_photo(&mut self, ctx: &mut Ctx<'_>, asked: (Option<Instant>, Instant)) {
        self.make_room(ctx);
        let c = &mut self.camera.captures;
        let Some(i) = c.put(asked.1, Some((asked.1, true))) else {
            return;
        };
        if let Some(Some(s)) = c.shots.get_mut(i) {
            s.asked = Some(asked);
        }
        c.keep_request_order();
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
        // its command went. The oldest the pod ACKed; else the oldest not yet ACKed (the
        // request says it shoots; a command superseded by a newer one gets no ACK).
        let open = |s: &Shot| {
            s.asked.is_none() && at.is_none_or(|at| at.saturating_add(BEFORE_COMMAND) >= s.since)
        };
        let pick = c
            .oldest(|s| open(s) && s.acked.is_some_and(|a| a.1))
            .or_else(|| c.oldest(|s| open(s) && s.acked.is_none()));
        if let Some(i) = pick {
            if let Some(Some(s)) = c.shots.get_mut(i) {
                s.asked = Some(asked);
            }
            c.keep_request_order();
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

    /// Reports, in the order taken, every photo whose geotag is answered (or no longer
    /// expected); a photo waits for the older ones still in flight. A command that made
    /// no photo is reported at once (it takes no index).
    pub(super) fn finish_shots(&mut self, ctx: &mut Ctx<'_>) {
        let mut older_in_flight = false;
        let fix = ctx.fixes.latest().map(|f| f.at);
        for i in self.camera.captures.in_order() {
            let c = &self.camera.captures;
            let Some(s) = c.shots.get(i).copied().flatten() else {
                continue;
            };
            let done = c.done(&s, ctx.now, fix);
            if done && !(older_in_flight && is_photo(&s)) {
                self.finish_shot(ctx, i);
            } else if !done {
                older_in_flight = true;
            }
        }
    }

    /// Sends CAMERA_IMAGE_CAPTURED for shot `i` and forgets it.
    fn finish_shot(&mut self, ctx: &mut Ctx<'_>, i: usize) {
        let Some(s) = self.camera.captures.shots.get_mut(i).and_then(Option::take) else {
            return;
        };
        let photo = is_photo(&s);
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
