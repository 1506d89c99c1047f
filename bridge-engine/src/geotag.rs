//! Answers to the pod's GPS request (0x000310 → 0x010310).
//!
//! # Decisions
//! - **The instant asked**: the request names a UTC time of day; the nearest instant
//!   with that time of day (across midnight) is mapped to local time by the UTC
//!   discipline, and the fix history gives the position and attitude then.
//! - **Waiting for the next fix**: the pod asks about 20 ms after the shot, while the
//!   FC's newest fix is up to one period (100 ms at 10 Hz) older than the shot. Held,
//!   that fix would put the photo up to a metre behind at 10 m/s. So a request for an
//!   instant after the newest fix waits for the fix that follows it, up to
//!   [`FixConfig::max_wait`](super::fixes::FixConfig) (250 ms), and is then interpolated
//!   (or, if no fix came, the newest is carried forward with the aircraft's velocity,
//!   for at most [`FixConfig::max_extrapolate`](super::fixes::FixConfig), 1 s). One
//!   request waits at a time; a second one answers the first with what there is.
//! - **Failure**: no UTC, no fix, a stale fix (beyond the extrapolation limit, or with
//!   no velocity to carry it) gives the failure code 0x0001 with the time echoed and
//!   zero position and attitude: the answer says nothing the bridge does not know.

use super::Outputs;
use super::discipline::TimeDiscipline;
use super::event::{Event, GeotagMiss};
use super::fixes::{Fix, FixHistory};
use super::pod::PodDriver;
use super::time::{Instant, TimeOfDay, UtcTime};
use protocol_core::k40t::{AckCode, GpsReply, GpsRequest, Header, ResponseCode};

/// A request waiting for a newer fix.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Waiting {
    header: Header,
    request: GpsRequest,
    /// The local instant asked.
    at: Instant,
    /// The UTC asked.
    utc: UtcTime,
    /// When it is answered with what there is.
    deadline: Instant,
}

/// A photo the pod geotagged: its UTC and the fix there.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Photo {
    pub(crate) utc: UtcTime,
    pub(crate) fix: Fix,
}

/// The pod's GPS requests, answered now or after the next fix.
#[derive(Debug, Clone, Default)]
pub(crate) struct Geotagger {
    waiting: Option<Waiting>,
    /// The last photo answered with a fix, until taken ([`Geotagger::take_photo`]).
    photo: Option<Photo>,
}

impl Geotagger {
    /// A GPS request from the pod.
    #[allow(clippy::too_many_arguments)] // the engine's parts, borrowed apart
    pub(crate) fn request(
        &mut self,
        now: Instant,
        header: Header,
        request: GpsRequest,
        time: &TimeDiscipline,
        fixes: &FixHistory,
        pod: &mut PodDriver,
        out: &mut Outputs,
    ) {
        if let Some(w) = self.waiting.take() {
            let fix = fixes.at(w.at).map(|f| (w.utc, f));
            self.answer(w.header, w.request, fix.map_err(Into::into), pod, out);
        }
        let asked = TimeOfDay::new(
            request.hour,
            request.minute,
            request.second,
            request.millisecond,
        )
        .and_then(|tod| time.utc(now)?.nearest_with_time_of_day(tod))
        .and_then(|utc| Some((time.local_of(utc)?, utc)));
        let Some((at, utc)) = asked else {
            self.answer(header, request, Err(GeotagMiss::UtcUnknown), pod, out);
            return;
        };
        let newest = fixes.latest().map(|f| f.at);
        let max_wait = fixes.config().max_wait;
        // Worth waiting: the newest fix is older than the instant asked, and the next
        // one (due within a period) can still cover it.
        if newest.is_some_and(|n| {
            n < at && at.saturating_duration_since(n) <= fixes.config().max_extrapolate
        }) && max_wait.as_micros() > 0
        {
            self.waiting = Some(Waiting {
                header,
                request,
                at,
                utc,
                deadline: now.saturating_add(max_wait),
            });
            return;
        }
        let fix = fixes.at(at).map(|f| (utc, f));
        self.answer(header, request, fix.map_err(Into::into), pod, out);
    }

    /// Answers the waiting request once a fix at or after its instant is in, or at its
    /// deadline.
    pub(crate) fn poll(
        &mut self,
        now: Instant,
        fixes: &FixHistory,
        pod: &mut PodDriver,
        out: &mut Outputs,
    ) {
        let Some(w) = self.waiting else {
            return;
        };
        let covered = fixes.latest().is_some_and(|f| f.at >= w.at);
        if covered || now >= w.deadline {
            self.waiting = None;
            let fix = fixes.at(w.at).map(|f| (w.utc, f));
            self.answer(w.header, w.request, fix.map_err(Into::into), pod, out);
        }
    }

    /// The last photo answered with a fix, once.
    pub(crate) fn take_photo(&mut self) -> Option<Photo> {
        self.photo.take()
    }

    /// Answers `request` ([`answer`]) and keeps the photo when a fix was given.
    fn answer(
        &mut self,
        header: Header,
        request: GpsRequest,
        fix: Result<(UtcTime, Fix), GeotagMiss>,
        pod: &mut PodDriver,
        out: &mut Outputs,
    ) {
        if let Ok((utc, fix)) = fix {
            self.photo = Some(Photo { utc, fix });
        }
        answer(header, request, fix, pod, out);
    }

    /// The deadline of the waiting request.
    pub(crate) fn poll_at(&self) -> Option<Instant> {
        self.waiting.map(|w| w.deadline)
    }
}

/// Sends the 0x010310 for `request`: the fix (with the UTC asked, resolved to its
/// date), or the failure code with the time echoed; a fix given is also a
/// [`Event::Photo`].
fn answer(
    header: Header,
    request: GpsRequest,
    fix: Result<(UtcTime, Fix), GeotagMiss>,
    pod: &mut PodDriver,
    out: &mut Outputs,
) {
    let mut reply = GpsReply {
        code: ResponseCode::new(AckCode::Failure),
        hour: request.hour,
        minute: request.minute,
        second: request.second,
        millisecond: request.millisecond,
        ..GpsReply::default()
    };
    if let Ok((utc, f)) = fix {
        out.event(Event::Photo(crate::event::PhotoEvent {
            utc_us: utc.as_unix_micros(),
            lat_e7: f.lat_e7,
            lon_e7: f.lon_e7,
            alt_msl_dm: f.alt_msl_dm,
            rel_alt_dm: f.rel_alt_dm,
            yaw_cdeg: f.yaw_cdeg,
            roll_cdeg: f.roll_cdeg,
            pitch_cdeg: f.pitch_cdeg,
        }));
        reply.code = ResponseCode::OK;
        reply.lon_e7 = f.lon_e7;
        reply.lat_e7 = f.lat_e7;
        reply.rel_alt_dm = f.rel_alt_dm;
        reply.alt_msl_dm = f.alt_msl_dm;
        reply.yaw_cdeg = f.yaw_cdeg;
        reply.roll_cdeg = f.roll_cdeg;
        reply.pitch_cdeg = f.pitch_cdeg;
    }
    pod.send_gps_reply(header, reply, out);
    let answered = fix.is_ok();
    let c = &mut out.counters;
    if answered {
        c.geotags = c.geotags.saturating_add(1);
    } else {
        c.geotags_failed = c.geotags_failed.saturating_add(1);
    }
    let time_of_day_ms = TimeOfDay::new(
        request.hour,
        request.minute,
        request.second,
        request.millisecond,
    )
    .map_or(0, TimeOfDay::millis_of_day);
    out.event(Event::Geotag {
        time_of_day_ms,
        missed: fix.err(),
    });
}
