//! What the engine reports for logging: [`Event`]s (small, `Copy`, queued) and
//! [`Counters`] (read any time).

use super::time::{Duration, Instant};
use crate::access::Refusal;
use protocol_core::k40t::{AckCode, Address, CrcCoverage};

protocol_core::wire_derive! {
    [Eq, Hash]
    /// One of the two serial links.
    pub enum Port {
        /// The flight controller's.
        Fc,
        /// The pod's.
        Pod,
        /// The optional MAVLink telemetry link to the autopilot (an ArduPilot
        /// `SERIALn_PROTOCOL` 2 or PX4 `MAV_n_CONFIG` port) beside a SIYI, Viewlink, GCU or
        /// K40T FC link: the source of UTC, fixes and the aircraft's attitude while it
        /// gives them. Needs the `mavlink` feature (without it its bytes are ignored).
        Telemetry,
    }
}

protocol_core::wire_derive! {
    [Eq, Hash]
    /// A geotagged photo ([`Event::Photo`]).
    pub struct PhotoEvent {
        /// The photo's UTC, µs since the Unix epoch (the pod names it to the ms).
        pub utc_us: u64,
        /// Latitude, 1e-7 degree.
        pub lat_e7: i32,
        /// Longitude, 1e-7 degree.
        pub lon_e7: i32,
        /// Altitude above mean sea level, 0.1 m.
        pub alt_msl_dm: i16,
        /// Height above home, 0.1 m.
        pub rel_alt_dm: i16,
        /// The aircraft's yaw (heading), 0.01°.
        pub yaw_cdeg: i16,
        /// The aircraft's roll, 0.01°.
        pub roll_cdeg: i16,
        /// The aircraft's pitch, 0.01°.
        pub pitch_cdeg: i16,
    }
}

protocol_core::wire_derive! {
    [Eq, Hash]
    /// Something worth logging. Drained with [`Engine::next_event`](super::Engine::next_event);
    /// when more than the queue holds are pending, the oldest are dropped (counted in
    /// [`Counters::events_dropped`]).
    pub enum Event {
        /// The FC's first valid frame after silence.
        FcLinkUp,
        /// No valid frame from the FC for [`Config::fc_link_timeout`](super::Config::fc_link_timeout).
        FcLinkDown,
        /// The pod's first report after silence.
        PodLinkUp,
        /// No report from the pod for the pod link time-out.
        PodLinkDown,
        /// UTC became known well enough to send time syncs (or a new mapping replaced one
        /// that disagreed with it, after [`Event::UtcLost`]).
        UtcValid {
            /// The error the discipline believes its UTC has now, µs.
            error_bound_us: u32,
            /// From a converged fit (else a first mapping, refined as samples come).
            converged: bool,
        },
        /// UTC is no longer known (holdover expired, the time source jumped or contradicts
        /// the mapping): no more time syncs until it is valid again.
        UtcLost,
        /// RTC_IO rose at `edge` and a 0x00030E carrying `utc_ms` went to the head of the
        /// pod queue.
        TimeSync {
            /// Local instant of the rising edge.
            edge: Instant,
            /// The UTC the frame carries, ms since the Unix epoch.
            utc_ms: u64,
            /// The error the discipline believes that UTC has, µs (never above
            /// [`SyncConfig::max_error`](super::sync::SyncConfig::max_error)).
            error_bound_us: u32,
        },
        /// The pod asked (0x000310) for the aircraft's position at a time of day.
        Geotag {
            /// The time of day asked, ms since midnight UTC.
            time_of_day_ms: u32,
            /// `None`: a fix was given; else why the reply carried the failure code.
            missed: Option<GeotagMiss>,
        },
        /// A photo's time and place, as the geotag answer gave them (after
        /// [`Event::Geotag`] with a fix): the UTC the pod asked for (its time of day on
        /// the disciplined clock's date) and the fix interpolated there. What a photo
        /// event file records (docs/src/linux-bridge.md).
        Photo(PhotoEvent),
        /// An FC command became a pod command.
        Translated {
            /// The FC protocol's message id.
            fc_id: u16,
            /// The K40T base id sent.
            pod_base: u16,
        },
        /// The pod answered a command with a failure code.
        PodRefused {
            /// The command's base id.
            base: u16,
            /// The code.
            code: AckCode,
        },
        /// A command got no ACK after all its tries.
        PodTimeout {
            /// The command's base id.
            base: u16,
        },
        /// The FC stopped sending motion while the pod turned: the bridge stopped it.
        FcSilenceStop,
        /// A rate was beyond what the pod can turn (30 °/s) and was clamped.
        RateClamped {
            /// The rate asked, 0.01 °/s.
            requested_cdeg_s: i32,
        },
        /// The pod's addresses, as its reports show them.
        PodAddresses {
            /// Source of the gimbal reports.
            gimbal: Address,
            /// Source of the camera reports.
            camera: Address,
        },
        /// The CRC coverage the pod uses.
        PodCoverage(CrcCoverage),
        /// Where UTC and fixes come from changed: the telemetry link (`true`: the
        /// autopilot's TIMESYNC, SYSTEM_TIME and position streams) or the FC link
        /// (`false`: the telemetry link stopped giving time). The UTC mapping starts again
        /// from the new source (the old one is kept in holdover meanwhile).
        TimeSource {
            /// The telemetry link is the source.
            telemetry: bool,
        },
        /// A command that erases (MAVLink MAV_CMD_STORAGE_FORMAT 526, MAV_CMD_RESET_CAMERA_SETTINGS
        /// 529) was DENIED: the configuration does not allow destructive commands
        /// (`mavlink.allow_destructive`).
        DestructiveDenied {
            /// The FC protocol's command id.
            command: u16,
        },
        /// The autopilot on this MAVLink link answered none of the bridge's requests for
        /// time and position (no ACK of SET_MESSAGE_INTERVAL, no TIMESYNC reply) and sent
        /// no SYSTEM_TIME or position within 10 s of its first HEARTBEAT, as PX4 1.16's
        /// link in mode Gimbal does (it handles only the gimbal messages): no UTC, so no
        /// time syncs, and no geotags come from it. Set the link to mode Normal (PX4
        /// `MAV_n_MODE` 0), or give the bridge the autopilot's telemetry link
        /// (docs/src/autopilots/px4.md). Said once per autopilot learnt.
        NoTimeOrFixes {
            /// The link.
            port: Port,
        },
        /// The pod told its IP address (0x000312): the video stream's.
        PodIp {
            /// The address, octets in dotted order.
            address: [u8; 4],
        },
        /// The bridge declined an FC command it cannot serve (the pod was not asked),
        /// and why.
        Declined {
            /// The FC protocol's command id (a MAV_CMD value on the MAVLink side).
            fc_id: u16,
            /// Why.
            reason: Decline,
        },
        /// The clock locked to the PPS edges: the mapping is their line (see
        /// docs/src/bridge/time.md, "PPS").
        PpsLocked {
            /// Local instant of the first edge of the run that locked.
            first_edge: Instant,
        },
        /// The PPS edges stopped: the clock runs on at their last rate (holdover).
        PpsHoldover,
        /// The PPS line is no longer the mapping: handed back to the FC's UTC (slewed), or
        /// its holdover ended.
        PpsReleased,
        /// A frame or command the bridge would not take (see docs/src/security.md).
        Refused {
            /// The link it came on.
            port: Port,
            /// Why.
            reason: Refusal,
            /// What: the MAVLink message id (a command's MAV_CMD for COMMAND_LONG and
            /// COMMAND_INT), or the K40T request's id.
            id: u32,
            /// The sender: its MAVLink system id (K40T: 0).
            sender: u8,
        },
        /// The MAVLink signing key changed (SETUP_SIGNING from the autopilot's system,
        /// signed with the key in use): `on` false when it turned signing off.
        SigningKeyChanged {
            /// The link it came on.
            port: Port,
            /// A key is in use now.
            on: bool,
        },
        /// An autopilot-type HEARTBEAT from another system than the autopilot the link
        /// is pinned to (`autopilot_sysid`, or the first heard): counted
        /// ([`Counters::other_autopilots`]), reported once per system and link, and
        /// changes nothing (see docs/src/security.md, "The autopilot's system").
        OtherAutopilot {
            /// The link it came on.
            port: Port,
            /// Its system id.
            sysid: u8,
        },
        /// A record of the bridge's persistent store was not restored: the bridge starts
        /// on that record's defaults ([`crate::store`]).
        StoreRecord {
            /// The record's key ([`crate::store::Key`]; `0xFFFF`: the whole store).
            key: u16,
            /// What was wrong.
            problem: crate::store::Problem,
        },
        /// A setting changed, was refused, was kept, or every setting went back to its
        /// default (docs/src/console.md; [`crate::settings`]).
        Setting {
            /// The setting's record key (`0x0100 + id`; [`crate::settings::HEADER`] for
            /// `save` and `defaults`, which concern every setting).
            key: u16,
            /// Who changed it.
            source: SettingSource,
            /// What happened.
            outcome: SettingOutcome,
        },
        /// Output frames dropped because a queue was full.
        Dropped {
            /// The queue's port.
            port: Port,
            /// Frames dropped.
            frames: u8,
        },
    }
}

protocol_core::wire_derive! {
    [Eq, Hash]
    /// Who changed a setting ([`Event::Setting`]).
    pub enum SettingSource {
        /// The console.
        Console,
        /// A MAVLink PARAM_SET on this link (the MAVLink side's, or the telemetry link).
        Parameter(Port),
    }
}

protocol_core::wire_derive! {
    [Eq, Hash]
    /// What became of a setting ([`Event::Setting`]).
    pub enum SettingOutcome {
        /// Set, and in force at once (a live setting).
        Applied,
        /// Set; in force at the next start.
        AtRestart,
        /// Refused (its form, its range, or the configuration it would make).
        Refused,
        /// The settings set since the last save were kept (`save`; a PARAM_SET keeps its
        /// own at once).
        Saved,
        /// Every setting back to its default, kept.
        Defaults,
    }
}

impl SettingOutcome {
    /// The outcome as a word, for logs.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            SettingOutcome::Applied => "applied",
            SettingOutcome::AtRestart => "at_restart",
            SettingOutcome::Refused => "refused",
            SettingOutcome::Saved => "saved",
            SettingOutcome::Defaults => "defaults",
        }
    }
}

protocol_core::wire_derive! {
    [Eq, Hash]
    /// Why a geotag request got the failure code ([`Event::Geotag`]).
    pub enum GeotagMiss {
        /// The bridge does not know UTC, or the time of day asked is not one (so the
        /// instant asked is unknown).
        UtcUnknown,
        /// No fix has been received.
        NoFix,
        /// The instant asked is further than the hold limit from any fix kept.
        OutOfRange,
    }
}

impl GeotagMiss {
    /// The reason as a word, for logs.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            GeotagMiss::UtcUnknown => "utc_unknown",
            GeotagMiss::NoFix => "no_fix",
            GeotagMiss::OutOfRange => "out_of_range",
        }
    }
}

impl From<crate::fixes::GeotagError> for GeotagMiss {
    fn from(e: crate::fixes::GeotagError) -> Self {
        match e {
            crate::fixes::GeotagError::NoFix => GeotagMiss::NoFix,
            crate::fixes::GeotagError::OutOfRange => GeotagMiss::OutOfRange,
        }
    }
}

protocol_core::wire_derive! {
    [Eq, Hash]
    /// Why the bridge declined an FC command ([`Event::Declined`]).
    pub enum Decline {
        /// A parameter the command needs is NaN (not given).
        NotGiven,
        /// A parameter is out of its range.
        OutOfRange,
        /// The command names a camera or stream the bridge does not have.
        OtherDevice,
        /// The video stream's address is not known (the pod has not told it; no
        /// `video.uri`).
        NoStreamAddress,
        /// The pod does not measure temperatures now (no 0x000004).
        NoMeasurement,
        /// The laser measured nothing (a distance of 0).
        NoLaserReturn,
        /// A frame of reference the bridge does not take.
        Frame,
        /// The aircraft's position or heading is not known.
        NoPosition,
        /// The pod does not report (its link is down).
        PodLost,
    }
}

impl Decline {
    /// The reason as a word, for logs.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Decline::NotGiven => "not_given",
            Decline::OutOfRange => "out_of_range",
            Decline::OtherDevice => "other_device",
            Decline::NoStreamAddress => "no_stream_address",
            Decline::NoMeasurement => "no_measurement",
            Decline::NoLaserReturn => "no_laser_return",
            Decline::Frame => "frame",
            Decline::NoPosition => "no_position",
            Decline::PodLost => "pod_lost",
        }
    }
}

protocol_core::wire_derive! {
    [Eq, Hash, Default]
    /// Running totals (saturating).
    pub struct Counters {
        /// Valid frames from the FC.
        pub fc_frames: u32,
        /// FC candidates rejected (checksum, length, truncated).
        pub fc_rejected: u32,
        /// Valid FC frames the engine could not use (undecodable, wrong direction).
        pub fc_ignored: u32,
        /// Bytes from the FC outside any frame (valid, or skipped whole).
        pub fc_garbage_bytes: u32,
        /// Well-framed FC frames of a kind the FC side does not read, skipped whole:
        /// MAVLink 2 frames of message ids outside the dialect (their checksum cannot be
        /// checked without the message's CRC_EXTRA: an autopilot's ordinary messages) and
        /// MAVLink 1 frames. Neither rejected nor garbage.
        pub fc_unknown_frames: u32,
        /// Frames queued for the FC.
        pub fc_sent: u32,
        /// Valid frames from the pod.
        pub pod_frames: u32,
        /// Pod candidates rejected.
        pub pod_rejected: u32,
        /// Bytes from the pod outside any valid frame.
        pub pod_garbage_bytes: u32,
        /// Frames queued for the pod.
        pub pod_sent: u32,
        /// Valid frames from the telemetry link.
        pub telemetry_frames: u32,
        /// Frames queued for the telemetry link.
        pub telemetry_sent: u32,
        /// Commands sent again after a time-out.
        pub pod_retries: u32,
        /// Output frames dropped (queue full).
        pub dropped: u32,
        /// Events dropped (event queue full).
        pub events_dropped: u32,
        /// RTC_IO pulses with their 0x00030E.
        pub time_syncs: u32,
        /// GPS requests answered with a fix.
        pub geotags: u32,
        /// GPS requests answered with a failure.
        pub geotags_failed: u32,
        /// PPS edges taken ([`Engine::pps`](super::Engine::pps)).
        pub pps_edges: u32,
        /// PPS edges no UTC second could be named for (no UTC, or not near a second).
        pub pps_unlabelled: u32,
        /// PPS edges the FC's UTC names another second for than the PPS line does.
        pub pps_conflicts: u32,
        /// PPS edges not used: off the line of the previous ones, or out of order.
        pub pps_rejected: u32,
        /// Signed MAVLink frames dropped: signature not the key's, replayed or stale.
        pub signature_failures: u32,
        /// Unsigned MAVLink frames refused while signing is required.
        pub unsigned_refused: u32,
        /// Commands refused for their sender (MAVLink) or because they are destructive
        /// and not allowed (K40T requests).
        pub commands_refused: u32,
        /// Signed MAVLink frames refused: signature not the key's.
        pub refused_bad_signature: u32,
        /// Signed MAVLink frames refused: not newer than their stream's last (a replay).
        pub refused_replayed: u32,
        /// Signed MAVLink frames refused: opening a stream over a minute older than the
        /// bridge's timestamp.
        pub refused_stale: u32,
        /// MAVLink messages that change something, refused for their sender.
        pub refused_sender: u32,
        /// The pod's destructive requests refused (not in `k40t_allow`).
        pub refused_guarded: u32,
        /// Refusals counted but not reported as an event: one of the same reason and
        /// stream was reported less than a second before, or refusal events already wait.
        pub refusals_unreported: u32,
        /// HEARTBEATs of an autopilot other than the one the link is pinned to.
        pub other_autopilots: u32,
    }
}

impl Counters {
    /// Every counter with its name (the JSON log's), in order.
    #[must_use]
    pub const fn named(&self) -> [(&'static str, u32); 31] {
        [
            ("fc_frames", self.fc_frames),
            ("fc_rejected", self.fc_rejected),
            ("fc_ignored", self.fc_ignored),
            ("fc_garbage_bytes", self.fc_garbage_bytes),
            ("fc_sent", self.fc_sent),
            ("pod_frames", self.pod_frames),
            ("pod_rejected", self.pod_rejected),
            ("pod_garbage_bytes", self.pod_garbage_bytes),
            ("pod_sent", self.pod_sent),
            ("telemetry_frames", self.telemetry_frames),
            ("telemetry_sent", self.telemetry_sent),
            ("pod_retries", self.pod_retries),
            ("dropped", self.dropped),
            ("events_dropped", self.events_dropped),
            ("time_syncs", self.time_syncs),
            ("geotags", self.geotags),
            ("geotags_failed", self.geotags_failed),
            ("pps_edges", self.pps_edges),
            ("pps_unlabelled", self.pps_unlabelled),
            ("pps_conflicts", self.pps_conflicts),
            ("pps_rejected", self.pps_rejected),
            ("signature_failures", self.signature_failures),
            ("unsigned_refused", self.unsigned_refused),
            ("commands_refused", self.commands_refused),
            ("refused_bad_signature", self.refused_bad_signature),
            ("refused_replayed", self.refused_replayed),
            ("refused_stale", self.refused_stale),
            ("refused_sender", self.refused_sender),
            ("refused_guarded", self.refused_guarded),
            ("refusals_unreported", self.refusals_unreported),
            ("other_autopilots", self.other_autopilots),
        ]
    }
}

/// A bounded event queue. When it is full a new event displaces the oldest refusal
/// ([`Event::Refused`]) waiting, else the oldest event; a refusal never displaces another
/// event and waits only while fewer than [`REFUSALS_WAITING`] refusals do: refusals, which
/// a peer on a link can cause at will, never push out time-sync, geotag or PPS events.
#[derive(Debug, Clone)]
pub(crate) struct EventQueue {
    /// Oldest first; the first `len` are events.
    items: [Option<Event>; EVENTS],
    len: usize,
}

/// Events the queue holds.
pub(crate) const EVENTS: usize = 16;
/// Refusal events that may wait at once.
pub(crate) const REFUSALS_WAITING: usize = 4;

/// What [`EventQueue::push`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Pushed {
    /// Queued.
    Queued,
    /// Queued, and an older event was dropped for it.
    Displaced,
    /// Not queued: a refusal, with the queue full or enough refusals waiting.
    NotQueued,
}

const fn is_refusal(e: &Event) -> bool {
    matches!(e, Event::Refused { .. })
}

impl EventQueue {
    pub(crate) const fn new() -> Self {
        EventQueue {
            items: [None; EVENTS],
            len: 0,
        }
    }

    fn waiting(&self) -> impl Iterator<Item = &Event> {
        self.items.iter().take(self.len).flatten()
    }

    /// Queues `e` (see the type's documentation).
    pub(crate) fn push(&mut self, e: Event) -> Pushed {
        let mut pushed = Pushed::Queued;
        if is_refusal(&e) {
            let refusals = self.waiting().filter(|w| is_refusal(w)).count();
            if refusals >= REFUSALS_WAITING || self.len >= EVENTS {
                return Pushed::NotQueued;
            }
        } else if self.len >= EVENTS {
            let victim = self.waiting().position(is_refusal).unwrap_or(0);
            self.remove(victim);
            pushed = Pushed::Displaced;
        }
        if let Some(slot) = self.items.get_mut(self.len) {
            *slot = Some(e);
            self.len = self.len.saturating_add(1);
        }
        pushed
    }

    /// Takes the event at `i` out, the later ones moving up.
    fn remove(&mut self, i: usize) -> Option<Event> {
        if i >= self.len {
            return None;
        }
        // From the last event down to `i`, each slot takes the one after it.
        let mut carry = None;
        for slot in self.items.iter_mut().take(self.len).skip(i).rev() {
            core::mem::swap(slot, &mut carry);
        }
        self.len = self.len.saturating_sub(1);
        carry
    }

    pub(crate) fn pop(&mut self) -> Option<Event> {
        self.remove(0)
    }
}

/// A refusal of the same reason and stream is reported at most once in this time (the
/// rest are counted).
pub const REFUSAL_REPORT_PERIOD: Duration = Duration::from_secs(1);
/// Streams whose last report is remembered.
const REPORTED_STREAMS: usize = 8;

/// One refusal stream's last report: the link, the reason, the sender (MAVLink system and
/// component; K40T: 0, 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Reported {
    port: Port,
    reason: Refusal,
    from: (u8, u8),
    at: Instant,
}

/// Which refusals are reported as events: at most one per reason and stream per
/// [`REFUSAL_REPORT_PERIOD`] (a peer that sends a thousand bad frames a second makes one
/// event a second; the counters count every one).
#[derive(Debug, Clone)]
pub(crate) struct RefusalReports {
    recent: [Option<Reported>; REPORTED_STREAMS],
}

impl RefusalReports {
    pub(crate) const fn new() -> Self {
        RefusalReports {
            recent: [None; REPORTED_STREAMS],
        }
    }

    /// Whether a refusal of `reason` from `from` on `port` at `now` is reported; notes it
    /// when it is (a new stream takes the slot reported longest ago).
    pub(crate) fn due(
        &mut self,
        now: Instant,
        port: Port,
        reason: Refusal,
        from: (u8, u8),
    ) -> bool {
        let same = |r: &Reported| r.port == port && r.reason == reason && r.from == from;
        let slot = self.recent.iter().position(|r| r.is_some_and(|r| same(&r)));
        if let Some(r) = slot.and_then(|i| self.recent.get(i)).copied().flatten()
            && now.saturating_duration_since(r.at) < REFUSAL_REPORT_PERIOD
        {
            return false;
        }
        let i = slot.unwrap_or_else(|| {
            self.recent
                .iter()
                .enumerate()
                .min_by_key(|(_, r)| r.map(|r| r.at))
                .map_or(0, |(i, _)| i)
        });
        if let Some(r) = self.recent.get_mut(i) {
            *r = Some(Reported {
                port,
                reason,
                from,
                at: now,
            });
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn event_queue_keeps_the_newest() {
        let mut q = EventQueue::new();
        for i in 0..EVENTS + 3 {
            let pushed = q.push(Event::PodTimeout {
                base: u16::try_from(i).unwrap(),
            });
            let expected = if i < EVENTS {
                Pushed::Queued
            } else {
                Pushed::Displaced
            };
            assert_eq!(pushed, expected);
        }
        let mut bases = vec![];
        while let Some(Event::PodTimeout { base }) = q.pop() {
            bases.push(base);
        }
        assert_eq!(
            bases,
            (3..u16::try_from(EVENTS + 3).unwrap()).collect::<Vec<_>>()
        );
        assert_eq!(q.pop(), None);
    }

    fn refused(sender: u8) -> Event {
        Event::Refused {
            port: Port::Fc,
            reason: Refusal::BadSignature,
            id: 0,
            sender,
        }
    }

    /// Refusals wait four at a time, never displace another event, and are the first
    /// displaced by one.
    #[test]
    fn refusals_never_displace_other_events() {
        let mut q = EventQueue::new();
        for i in 0..10u8 {
            let pushed = q.push(refused(i));
            let expected = if usize::from(i) < REFUSALS_WAITING {
                Pushed::Queued
            } else {
                Pushed::NotQueued
            };
            assert_eq!(pushed, expected, "refusal {i}");
        }
        for base in 0..12u16 {
            assert_eq!(q.push(Event::PodTimeout { base }), Pushed::Queued);
        }
        // Full: a sync displaces the oldest refusal, not the oldest event.
        let sync = Event::UtcLost;
        assert_eq!(q.push(sync), Pushed::Displaced);
        assert_eq!(q.push(refused(99)), Pushed::NotQueued);
        let all: Vec<Event> = core::iter::from_fn(|| q.pop()).collect();
        assert_eq!(all.len(), EVENTS);
        assert_eq!(&all[..3], &[refused(1), refused(2), refused(3)]);
        assert_eq!(all.last(), Some(&sync));
        for _ in 0..4 {
            assert_eq!(q.push(refused(7)), Pushed::Queued);
        }
        for base in 0..EVENTS {
            q.push(Event::PodTimeout {
                base: u16::try_from(base).unwrap(),
            });
        }
        // Every refusal went first.
        assert!(core::iter::from_fn(|| q.pop()).all(|e| !is_refusal(&e)));
    }

    /// One report per reason and stream per second; another stream, another reason or
    /// the next second is reported.
    #[test]
    fn refusals_are_reported_once_a_second_per_reason_and_stream() {
        let mut r = RefusalReports::new();
        let ms = Instant::from_millis;
        let bad = Refusal::BadSignature;
        assert!(r.due(ms(0), Port::Fc, bad, (1, 1)));
        assert!(!r.due(ms(999), Port::Fc, bad, (1, 1)));
        assert!(r.due(ms(999), Port::Fc, bad, (1, 2)));
        assert!(r.due(ms(999), Port::Telemetry, bad, (1, 1)));
        assert!(r.due(ms(999), Port::Fc, Refusal::Replayed, (1, 1)));
        assert!(r.due(ms(1000), Port::Fc, bad, (1, 1)));
        assert!(!r.due(ms(1500), Port::Fc, bad, (1, 1)));
        // Many streams: the table forgets the oldest, never more than one event per
        // stream and second for those it keeps.
        let reported = (0..100u8)
            .filter(|i| r.due(ms(2000), Port::Fc, bad, (*i, 0)))
            .count();
        assert_eq!(reported, 100);
    }
}
