//! The sans-IO bridge engine: a K40T pod on one side, a flight controller (FC) speaking
//! SIYI, Viewlink, GCU, K40T or MAVLink on the other, and (feature `telemetry`) an
//! optional MAVLink telemetry link to the same autopilot, the source of UTC and fixes
//! while it gives them ([`Port::Telemetry`]).
//!
//! No I/O, no clock reads, no allocation, a size fixed at compile time. Like smoltcp's
//! `Interface`, the [`Engine`] is driven by its caller, per [`Port`] (the FC's serial
//! link, the pod's, the telemetry link):
//!
//! - **Inputs:** bytes from a port ([`Engine::receive`]), with the local [`Instant`] the
//!   last of them arrived; "the line went idle" ([`Engine::idle`]); and [`Engine::poll`]
//!   at the instant [`Engine::poll_at`] names.
//! - **Outputs:** whole frames for a port, one at a time ([`Engine::transmit`] copies the
//!   next into the caller's buffer and takes it off the queue; [`Engine::pending`] gives
//!   its length); the RTC_IO pin ([`Engine::pin`], [`Engine::pin_done`]); [`Event`]s for
//!   logging and [`Counters`].
//! - **What changed:** every input ([`Engine::receive`], [`Engine::idle`],
//!   [`Engine::poll`], [`Engine::pin_done`]) returns the [`Changes`] since the previous
//!   one (a port's queue got a frame, the RTC_IO plan changed, events wait), so that a
//!   caller with a task per output wakes only the task concerned. [`Engine::poll_at`] may
//!   move with any input: read it again after each.
//!
//! # RTC_IO and time sync
//! While UTC is valid the engine plans a pulse every [`SyncConfig::period`](sync::SyncConfig)
//! on the UTC grid (10 s by default): [`Engine::pin`] names the local instant of the next
//! rising edge. The caller raises the pin **at** that instant (a timer alarm), reads its
//! clock, and calls [`Engine::pin_done`] with the instant it raised it: the engine puts a
//! 0x00030E carrying the UTC of that edge at the head of the pod queue, to be sent next,
//! and names the falling edge. No sync is ever sent while UTC is unknown.
//!
//! # Geotag
//! The pod's GPS request (0x000310, a UTC time of day) is answered (0x010310) from the
//! fix history, interpolated to the instant asked; a request for an instant after the
//! newest fix waits up to 250 ms for the next one, and is otherwise carried forward with
//! the aircraft's velocity for at most 1 s (see [`geotag`] and [`fixes`]). No fix, a
//! stale fix, or no UTC gives the failure code 0x0001 with the time echoed and zero
//! position and attitude: nothing is invented.
//!
//! # Cargo features
//! | feature | default | what it adds |
//! | --- | --- | --- |
//! | `siyi` | yes | the SIYI FC side (the bridge as a SIYI ZT30) |
//! | `viewlink` | yes | the Viewlink FC side (the bridge as a Viewpro gimbal) |
//! | `gcu` | yes | the GCU FC side (the bridge as an XF Robot gimbal) |
//! | `mavlink` | no | the MAVLink FC side (a MAVLink gimbal device and camera) |
//! | `telemetry` | no | the MAVLink telemetry link ([`Port::Telemetry`]) beside any other FC side; brings `mavlink`'s codec |
//! | `defmt` | no | `defmt::Format` on every public type |
//! | `serde` | no | `serde::Serialize` on the public types, `serde::Deserialize` on [`Config`] from the configuration file's keys |
//! | `bake` | no | `databake::Bake` on [`Config`] and what it holds (host only: a build script that writes a configuration out as Rust source) |
//!
//! The K40T FC side is always built: the pod speaks K40T, so its codec is in anyway.

#![cfg_attr(not(test), no_std)]
#![cfg_attr(
    test,
    allow(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::indexing_slicing,
        clippy::arithmetic_side_effects
    )
)]

pub mod access;
pub mod config;
pub mod discipline;
pub mod event;
pub(crate) mod fc;
pub mod fixes;
pub mod geotag;
pub mod gimbal;
pub mod pod;
pub mod queue;
pub mod settings;
pub mod store;
pub mod sync;
pub mod time;
pub mod version;

pub use access::{K40tAllow, Refusal, SigningKey, SigningMode, SystemIds};
pub use config::{
    Config, FcProtocol, GcuIdentity, MavlinkConfig, PodConfig, SiyiIdentity, ViewlinkIdentity,
};
pub use event::{
    Counters, Decline, Event, GeotagMiss, PhotoEvent, Port, SettingOutcome, SettingSource,
};
pub use pod::PodState;
pub use settings::console::{Action as ConsoleAction, UPDATE_IDLE, UPDATE_SYNC};
pub use settings::{Restore, Restored, Settings, Sides};
pub use time::{Duration, Instant, InstantNs, UtcTime};
pub use version::BuildInfo;

use discipline::{DisciplineState, PpsState, PpsVerdict, TimeDiscipline};
use fc::{Ctx, FcSide};
use fixes::FixHistory;
use geotag::Geotagger;
use pod::{PodDriver, PodNotice};
use queue::FrameQueue;
use sync::{SyncEdge, SyncScheduler};

use event::EventQueue;
use protocol_core::k40t::{self, Frame, K40tFraming};
use protocol_core::wire::{Deframer, Event as DeframerEvent, Stats};

/// Bytes of the queue of frames for the FC. With the `mavlink` feature 512: a MAVLink
/// frame is up to 280 bytes; the largest the bridge sends, CAMERA_INFORMATION (250 bytes
/// with its record header), its ACK and a poll's routine frames (attitude status,
/// heartbeats) fit, and the line drains the queue in 45 ms at 115200 baud.
pub const FC_QUEUE: usize = if cfg!(feature = "mavlink") { 512 } else { 256 };
/// Bytes of the queue of frames for the pod.
pub const POD_QUEUE: usize = 384;
/// Bytes of the queue of frames for the telemetry link: what it sends when the autopilot
/// appears (four stream requests of 45 bytes, a heartbeat of 21, a TIMESYNC of 30) fits.
/// Zero without the `telemetry` feature.
pub const TELEMETRY_QUEUE: usize = if cfg!(feature = "telemetry") { 256 } else { 0 };
/// A buffer of this many bytes takes any frame [`Engine::transmit`] gives (a frame never
/// exceeds its queue).
pub const MAX_FRAME_LEN: usize = if FC_QUEUE > POD_QUEUE {
    FC_QUEUE
} else {
    POD_QUEUE
};

protocol_core::wire_derive! {
    [Eq, Hash]
    /// The level of the RTC_IO pin.
    pub enum Level {
        /// Pin low (idle).
        Low,
        /// Pin high: the edge the pod time-stamps.
        High,
    }
}

protocol_core::wire_derive! {
    [Eq, Hash]
    /// A change of the RTC_IO pin the caller must make at a local instant.
    pub struct PinAction {
        /// The level to set.
        pub level: Level,
        /// The local instant at which to apply it (the microsecond it falls in).
        pub at: Instant,
        /// Nanoseconds after `at` (0..1000) at which a timer's output compare applies it:
        /// the PPS-locked mapping's resolution (0 otherwise, and for the falling edge). A
        /// timer alarm with a microsecond's resolution ignores it.
        pub sub_us_ns: u16,
    }
}

protocol_core::wire_derive! {
    [Eq, Hash, Default]
    /// What an input changed, for a caller that wakes only whom it concerns (after smoltcp's
    /// `PollResult`): [`Engine::receive`], [`Engine::idle`], [`Engine::poll`] and
    /// [`Engine::pin_done`] each return the changes since the previous of them. A small bit
    /// set: test it with [`Changes::contains`], combine with `|`.
    ///
    /// Deadlines are not in it: [`Engine::poll_at`] may move with any input, whatever the
    /// changes say.
    pub struct Changes(u8);
}

impl Changes {
    /// Nothing changed.
    pub const NONE: Self = Self(0);
    /// The FC queue got a frame ([`Engine::transmit`] for [`Port::Fc`]).
    pub const FC_FRAME: Self = Self(1);
    /// The pod queue got a frame ([`Engine::transmit`] for [`Port::Pod`]); after a rising
    /// edge, the 0x00030E at its head.
    pub const POD_FRAME: Self = Self(1 << 1);
    /// The RTC_IO plan changed: [`Engine::pin`] names another action, or none.
    pub const PIN: Self = Self(1 << 2);
    /// New events wait ([`Engine::next_event`]).
    pub const EVENTS: Self = Self(1 << 3);
    /// The telemetry queue got a frame ([`Engine::transmit`] for [`Port::Telemetry`]).
    pub const TELEMETRY_FRAME: Self = Self(1 << 4);
    /// Records wait to be written to the persistent store ([`Engine::take_record`]).
    pub const STORE: Self = Self(1 << 5);
    /// The console has output ([`Engine::console_transmit`]).
    pub const CONSOLE: Self = Self(1 << 6);

    /// The queue of `port` got a frame: [`Changes::FC_FRAME`], [`Changes::POD_FRAME`] or
    /// [`Changes::TELEMETRY_FRAME`].
    #[must_use]
    pub const fn frame(port: Port) -> Self {
        match port {
            Port::Fc => Self::FC_FRAME,
            Port::Pod => Self::POD_FRAME,
            Port::Telemetry => Self::TELEMETRY_FRAME,
        }
    }

    /// Nothing changed.
    #[must_use]
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// Every change of `other` is in `self`.
    #[must_use]
    pub const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// `self` and `other` have a change in common.
    #[must_use]
    pub const fn intersects(self, other: Self) -> bool {
        self.0 & other.0 != 0
    }
}

impl core::ops::BitOr for Changes {
    type Output = Self;

    fn bitor(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }
}

impl core::ops::BitOrAssign for Changes {
    fn bitor_assign(&mut self, other: Self) {
        self.0 |= other.0;
    }
}

/// The engine's outputs, shared by its parts.
#[derive(Debug, Clone)]
pub(crate) struct Outputs {
    pub(crate) fc: FrameQueue<FC_QUEUE>,
    pub(crate) pod: FrameQueue<POD_QUEUE>,
    pub(crate) tel: FrameQueue<TELEMETRY_QUEUE>,
    pub(crate) events: EventQueue,
    /// Which refusals become events.
    refusals: event::RefusalReports,
    /// Records to write to the store.
    pub(crate) store: store::Pending,
    pub(crate) counters: Counters,
    /// What changed since the last report ([`EngineState::report`]).
    pub(crate) changes: Changes,
}

impl Outputs {
    /// Empty queues, no event, zero counters, no change.
    pub(crate) fn new() -> Self {
        Outputs {
            fc: FrameQueue::new(),
            pod: FrameQueue::new(),
            tel: FrameQueue::new(),
            events: EventQueue::new(),
            refusals: event::RefusalReports::new(),
            store: store::Pending::default(),
            counters: Counters::default(),
            changes: Changes::NONE,
        }
    }

    pub(crate) fn event(&mut self, e: Event) {
        match self.events.push(e) {
            event::Pushed::Queued => self.changes |= Changes::EVENTS,
            event::Pushed::Displaced => {
                self.changes |= Changes::EVENTS;
                self.counters.events_dropped = self.counters.events_dropped.saturating_add(1);
            }
            event::Pushed::NotQueued => {
                let n = &mut self.counters.refusals_unreported;
                *n = n.saturating_add(1);
            }
        }
    }

    /// The record of `key` is to be written to the store.
    #[cfg_attr(not(feature = "mavlink"), allow(dead_code))]
    pub(crate) fn save(&mut self, key: store::Key) {
        self.store.mark(key);
        self.changes |= Changes::STORE;
    }

    /// A refusal: counted by its reason, reported (`Event::Refused`) at most once per
    /// reason and stream a second (`event::RefusalReports`). `from`: the MAVLink sender's
    /// system and component (K40T: 0, 0); `id`: what was refused.
    pub(crate) fn refuse(
        &mut self,
        now: Instant,
        port: Port,
        reason: Refusal,
        id: u32,
        from: (u8, u8),
    ) {
        let c = &mut self.counters;
        // Each reason's own counter, and the older totals it is part of.
        let (by_reason, total) = match reason {
            Refusal::BadSignature => (
                &mut c.refused_bad_signature,
                Some(&mut c.signature_failures),
            ),
            Refusal::Replayed => (&mut c.refused_replayed, Some(&mut c.signature_failures)),
            Refusal::Stale => (&mut c.refused_stale, Some(&mut c.signature_failures)),
            Refusal::Sender => (&mut c.refused_sender, Some(&mut c.commands_refused)),
            Refusal::Guarded => (&mut c.refused_guarded, Some(&mut c.commands_refused)),
            Refusal::Unsigned => (&mut c.unsigned_refused, None),
        };
        *by_reason = by_reason.saturating_add(1);
        if let Some(t) = total {
            *t = t.saturating_add(1);
        }
        if self.refusals.due(now, port, reason, from) {
            self.event(Event::Refused {
                port,
                reason,
                id,
                sender: from.0,
            });
        } else {
            self.counters.refusals_unreported = self.counters.refusals_unreported.saturating_add(1);
        }
    }

    fn pushed(&mut self, port: Port, p: queue::Pushed) -> bool {
        let dropped = u32::from(p.dropped).saturating_add(u32::from(!p.queued));
        if dropped > 0 {
            self.counters.dropped = self.counters.dropped.saturating_add(dropped);
            self.event(Event::Dropped {
                port,
                frames: u8::try_from(dropped).unwrap_or(u8::MAX),
            });
        }
        if p.queued {
            self.changes |= Changes::frame(port);
            let sent = match port {
                Port::Fc => &mut self.counters.fc_sent,
                Port::Pod => &mut self.counters.pod_sent,
                Port::Telemetry => &mut self.counters.telemetry_sent,
            };
            *sent = sent.saturating_add(1);
        }
        p.queued
    }

    /// Queues a frame for the FC.
    #[cfg_attr(
        not(any(feature = "siyi", feature = "viewlink", feature = "gcu")),
        allow(dead_code)
    )]
    pub(crate) fn queue_fc(&mut self, frame: &[u8], critical: bool) -> bool {
        let p = self.fc.push_back(frame, critical);
        self.pushed(Port::Fc, p)
    }

    /// Queues a frame for `port` (the FC or the telemetry link).
    #[cfg_attr(not(feature = "telemetry"), allow(dead_code))]
    pub(crate) fn queue_to(&mut self, port: Port, frame: &[u8]) -> bool {
        match port {
            Port::Telemetry => {
                let p = self.tel.push_back(frame, false);
                self.pushed(Port::Telemetry, p)
            }
            Port::Fc | Port::Pod => self.queue_fc(frame, false),
        }
    }

    /// Queues a frame for the pod (at the head with `front`).
    pub(crate) fn queue_pod(&mut self, frame: &[u8], critical: bool, front: bool) -> bool {
        let p = if front {
            self.pod.push_front(frame, critical)
        } else {
            self.pod.push_back(frame, critical)
        };
        self.pushed(Port::Pod, p)
    }
}

/// Largest pod frame the engine takes (a K40T frame is at most 255 bytes).
const POD_FRAME: usize = k40t::MAX_FRAME_LEN;

/// The bridge engine. See the [module documentation](self).
///
/// # Example
///
/// The default configuration: ArduPilot's SIYI driver on the FC link. A command from the
/// FC goes to the pod; then the FC's time is fed until the first RTC_IO edge, and the
/// 0x00030E of that edge is the next frame for the pod.
///
/// ```
/// use bridge_engine::discipline::serial_time;
/// use bridge_engine::{Changes, Config, Engine, Instant, Level, MAX_FRAME_LEN, Port};
/// use protocol_core::{k40t, siyi};
///
/// let mut engine = Engine::new(Config::DEFAULT);
/// let mut frame = [0u8; 64]; // a SIYI frame from the FC
/// let mut out = [0u8; MAX_FRAME_LEN]; // a frame taken from the engine
///
/// // ArduPilot zooms in (SIYI 0x05): a K40T continuous zoom (0x000306) for the pod, and
/// // the zoom ratio for the FC.
/// let zoom_in = siyi::ManualZoom { direction: siyi::ZoomDirection::In };
/// let n = siyi::encode(&zoom_in, &siyi::Header::request(1), &mut frame)?;
/// let changes = engine.receive(Instant::from_millis(100), Port::Fc, &frame[..n]);
/// assert!(changes.contains(Changes::POD_FRAME | Changes::FC_FRAME));
/// let n = engine.transmit(Port::Pod, &mut out).expect("a frame for the pod");
/// let zoom = k40t::Packet::decode(&out[..n])?.message.get::<k40t::ContinuousZoom>();
/// assert_eq!(zoom.map(|z| z.control), Some(k40t::ZoomControl::In));
///
/// // ArduPilot's time, 10 times a second: its boot clock (0x22, with the aircraft's
/// // attitude) and, in its first five updates, UTC before it (0x30). Its clock and the
/// // bridge's started together, at 2026-01-01 00:00:00.250 UTC; each update arrives
/// // after its time on the wire. The engine plans an RTC_IO edge on the 10 s grid; the
/// // caller raises the pin at that instant and reports it.
/// let boot_utc_us: u64 = 1_767_225_600_250_000;
/// let mut on_the_wire: Option<(Instant, Vec<u8>)> = None;
/// let mut ms: u64 = 200;
/// let edge = loop {
///     let now = Instant::from_millis(ms);
///     if let Some(p) = engine.pin().filter(|p| p.at <= now) {
///         assert_eq!(p.level, Level::High);
///         let changes = engine.pin_done(Level::High, p.at);
///         assert!(changes.contains(Changes::POD_FRAME | Changes::PIN));
///         break p.at;
///     }
///     if ms % 100 == 0 {
///         let mut update = Vec::new();
///         let seq = u16::try_from(ms / 100).unwrap_or(0);
///         if ms <= 600 {
///             let utc = siyi::UtcTime { unix_us: boot_utc_us + ms * 1000 };
///             let n = siyi::encode(&utc, &siyi::Header::request(seq), &mut frame)?;
///             update.extend_from_slice(&frame[..n]);
///         }
///         let attitude = siyi::FcAttitude {
///             time_boot_ms: u32::try_from(ms).unwrap_or(0),
///             ..Default::default()
///         };
///         let n = siyi::encode(&attitude, &siyi::Header::request(seq), &mut frame)?;
///         update.extend_from_slice(&frame[..n]);
///         let wire = serial_time(u32::try_from(update.len()).unwrap_or(0), 115_200);
///         on_the_wire = Some((now.saturating_add(wire), update));
///     }
///     if let Some((arrived, update)) = on_the_wire.take_if(|(at, _)| *at <= now) {
///         engine.receive(arrived, Port::Fc, &update);
///     }
///     if engine.poll_at().is_some_and(|t| t <= now) {
///         engine.poll(now);
///     }
///     // What the writers send: answers to the FC, version probes to the pod.
///     while engine.transmit(Port::Fc, &mut out).is_some() {}
///     while engine.transmit(Port::Pod, &mut out).is_some() {}
///     ms += 1;
/// };
///
/// // The first edge: 00:00:10.000 UTC on the FC's clock, 9.55 s after its first UTC.
/// // The next frame for the pod is that edge's 0x00030E, carrying that UTC.
/// assert_eq!(edge, Instant::from_millis(9_750));
/// assert_eq!(boot_utc_us + edge.as_micros(), 1_767_225_610_000_000);
/// let n = engine.transmit(Port::Pod, &mut out).expect("the time sync");
/// let sync = k40t::Packet::decode(&out[..n])?.message.get::<k40t::TimeSync>();
/// assert_eq!(sync.map(|s| s.unix_ms), Some(1_767_225_610_000));
/// # Ok::<(), protocol_core::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct Engine {
    /// Apart from the rest, so that each frame it yields is handled with all the rest.
    pod_deframer: Deframer<K40tFraming, POD_FRAME>,
    core: EngineState,
}

/// Everything of the engine but the pod deframer.
#[derive(Debug, Clone)]
struct EngineState {
    config: Config,
    /// What this image is (reported by the FC sides' version replies).
    build: BuildInfo,
    fc: FcSide,
    pod: PodDriver,
    time: TimeDiscipline,
    sync: SyncScheduler,
    fixes: FixHistory,
    geotag: Geotagger,
    /// The next rising edge, as planned.
    edge: Option<SyncEdge>,
    /// The planned edge is within the sync lead: kept as it is (the caller may have armed
    /// its timer), and no more polls are wanted for it.
    edge_settled: bool,
    /// The falling edge due after a rising one.
    pin_low: Option<Instant>,
    out: Outputs,
    fc_last: Option<Instant>,
    fc_link: bool,
    /// The MAVLink telemetry link, beside any FC side (beside the MAVLink side too: the
    /// time and fixes when that link gives none; docs/src/bridge/telemetry.md).
    #[cfg(feature = "telemetry")]
    tel: Option<fc::TelemetryLink>,
    /// The telemetry link is the source of UTC and fixes.
    tel_source: bool,
    /// Whether the first input, which says which records were not restored, has come.
    first_input: FirstInput,
    /// The settings: as set, the defaults, what the store keeps.
    settings: Settings,
    /// The console's line, output and long answers.
    console: settings::console::Console,
}

/// Before or after the engine's first input ([`EngineState::report`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum FirstInput {
    /// Not yet: records may still be restored.
    Awaited,
    /// Come.
    Seen,
}

impl Engine {
    /// An engine with `config`, nothing received yet, nothing restored (`config` is also
    /// the settings' defaults).
    #[must_use]
    pub fn new(config: Config) -> Self {
        Self::restored(Restored::fresh(config, Sides::COMPILED), BuildInfo::ENGINE)
    }

    /// An engine with the settings `restored` from the store (its configuration: the
    /// defaults with the settings kept; [`settings`]), reporting `build` as its version.
    /// What restoring found wrong is reported as [`Event::StoreRecord`]s.
    #[must_use]
    pub fn restored(restored: Restored, build: BuildInfo) -> Self {
        let config = *restored.config();
        let mut engine = Self::with_config(&config);
        engine.core.build = build;
        let core = &mut engine.core;
        if let Some(problem) = restored.reset {
            core.out.event(Event::StoreRecord {
                key: store::Key::WHOLE_STORE.0,
                problem,
            });
        }
        for found in restored.problems.iter().flatten() {
            core.out.event(Event::StoreRecord {
                key: found.key,
                problem: found.problem,
            });
        }
        core.settings = restored.settings;
        if core.settings.records_due() {
            core.out.changes |= Changes::STORE;
        }
        engine
    }

    fn with_config(config: &Config) -> Self {
        let config = *config;
        Engine {
            pod_deframer: Deframer::new(K40tFraming::any()),
            core: EngineState {
                fc: FcSide::new(&config),
                pod: PodDriver::new(config.pod).with_allow(config.k40t_allow),
                time: TimeDiscipline::new(config.discipline).with_pps(config.pps),
                sync: SyncScheduler::new(config.sync),
                fixes: FixHistory::new(config.fixes),
                geotag: Geotagger::default(),
                edge: None,
                edge_settled: false,
                pin_low: None,
                out: Outputs::new(),
                fc_last: None,
                fc_link: false,
                #[cfg(feature = "telemetry")]
                tel: Some(fc::TelemetryLink::telemetry(&config)),
                tel_source: false,
                first_input: FirstInput::Awaited,
                settings: Settings::new(config, Sides::COMPILED),
                console: settings::console::Console::new(),
                config,
                build: BuildInfo::ENGINE,
            },
        }
    }

    /// An engine with `config` that reports `build` as its version (the firmware's and
    /// `gimbal`'s: [`Engine::new`] knows only the engine's own version).
    #[must_use]
    pub fn with_build(config: Config, build: BuildInfo) -> Self {
        let mut engine = Self::new(config);
        engine.core.build = build;
        engine
    }

    /// What this image is: its version, commit and features.
    #[must_use]
    pub const fn build(&self) -> &BuildInfo {
        &self.core.build
    }

    /// The configuration running (a setting that applies at restart is in
    /// [`Engine::settings`] until then).
    #[must_use]
    pub const fn config(&self) -> &Config {
        &self.core.config
    }

    /// The settings: as set, the defaults, what the store keeps.
    #[must_use]
    pub const fn settings(&self) -> &Settings {
        &self.core.settings
    }

    /// Bytes from the console's port (the console: docs/src/console.md): echoed, and each line a
    /// command. Returns what changed (the console's output, records to store, events) and
    /// what the caller must do: restart the bridge, or hand the port to the update
    /// protocol (the bytes from [`ConsoleAction::Update`]'s `at` on are its own).
    pub fn console_receive(
        &mut self,
        now: Instant,
        bytes: &[u8],
    ) -> (Changes, Option<ConsoleAction>) {
        let status = self.console_status(now);
        let core = &mut self.core;
        let fingerprint = signing_fingerprint(&core.config);
        let mut parts = settings::console::Parts {
            settings: &mut core.settings,
            running: &mut core.config,
            build: &core.build,
            status,
            fingerprint,
        };
        let out = &mut core.out;
        let action = core.console.receive(bytes, &mut parts, |c| {
            out.event(Event::Setting {
                key: c.key,
                source: SettingSource::Console,
                outcome: c.outcome,
            });
        });
        if core.console.has_output() {
            core.out.changes |= Changes::CONSOLE;
        }
        (core.report(), action)
    }

    /// The update protocol gave the console's port back: the console writes a fresh
    /// prompt.
    pub fn console_resume(&mut self) -> Changes {
        self.core.console.resume();
        self.core.out.changes |= Changes::CONSOLE;
        core::mem::take(&mut self.core.out.changes)
    }

    /// Copies the console's next output into `buf` (long answers are written as it
    /// drains); returns its length (0: nothing waits).
    pub fn console_transmit(&mut self, buf: &mut [u8]) -> usize {
        let status = self.console_status(Instant::ZERO);
        let core = &mut self.core;
        let fingerprint = signing_fingerprint(&core.config);
        let parts = settings::console::Parts {
            settings: &mut core.settings,
            running: &mut core.config,
            build: &core.build,
            status,
            fingerprint,
        };
        core.console.transmit(buf, &parts)
    }

    /// Records wait to be written to the store (a restart waits for them).
    #[must_use]
    pub fn records_due(&self) -> bool {
        self.core.settings.records_due() || self.core.out.store.is_pending()
    }

    fn console_status(&self, now: Instant) -> settings::console::Status {
        let c = &self.core;
        settings::console::Status {
            fc: c.config.fc,
            fc_link: c.fc_link,
            pod_link: c.pod.state().link,
            telemetry_source: c.tel_source,
            utc_state: c.time.state(),
            utc: c
                .time
                .utc(now)
                .zip(c.time.error_bound(now))
                .filter(|_| c.time.state().is_usable()),
            pps: c.time.pps_state(),
            counters: self.counters(),
        }
    }

    /// What the bridge knows of the pod.
    #[must_use]
    pub const fn pod_state(&self) -> &PodState {
        self.core.pod.state()
    }

    /// The UTC of a local instant, when known.
    #[must_use]
    pub fn utc(&self, at: Instant) -> Option<UtcTime> {
        self.core.time.utc(at)
    }

    /// The aircraft's newest position from the source in force (the FC link or the
    /// telemetry link), when one came: what `gimbal bridge` logs as its `fix` events.
    #[must_use]
    pub fn latest_fix(&self) -> Option<fixes::Fix> {
        self.core.fixes.latest()
    }

    /// Where the UTC discipline stands.
    #[must_use]
    pub fn utc_state(&self) -> DisciplineState {
        self.core.time.state()
    }

    /// Running totals.
    #[must_use]
    pub fn counters(&self) -> Counters {
        let mut c = self.core.out.counters;
        let pod: Stats = self.pod_deframer.stats();
        c.pod_rejected = pod.checksum_errors.saturating_add(pod.length_errors);
        c.pod_garbage_bytes = pod.bytes_discarded;
        let fc = self.core.fc.deframer_stats();
        c.fc_rejected = fc.checksum_errors.saturating_add(fc.length_errors);
        c.fc_garbage_bytes = fc.bytes_discarded.saturating_sub(fc.bytes_skipped);
        c.fc_unknown_frames = fc.frames_unknown.saturating_add(fc.frames_skipped);
        c
    }

    /// The FC link is up (a valid frame within the FC link time-out).
    #[must_use]
    pub const fn fc_link(&self) -> bool {
        self.core.fc_link
    }

    /// The next event, oldest first.
    pub fn next_event(&mut self) -> Option<Event> {
        self.core.out.events.pop()
    }

    /// A record the caller found in its persistent store, given before the first input
    /// ([`store`]): taken, or discarded with [`Event::StoreRecord`] saying why (the bridge
    /// keeps that record's defaults). Returns what changed (events).
    pub fn restore(&mut self, key: u16, value: &[u8]) -> Changes {
        self.core.restore(store::Key(key), value);
        core::mem::take(&mut self.core.out.changes)
    }

    /// The caller could not read its persistent store (or found it corrupt): the bridge
    /// starts on every record's defaults, and says so ([`Event::StoreRecord`] for
    /// [`store::Key::WHOLE_STORE`]). Returns what changed (events).
    pub fn restore_failed(&mut self, problem: store::Problem) -> Changes {
        self.core.out.event(Event::StoreRecord {
            key: store::Key::WHOLE_STORE.0,
            problem,
        });
        core::mem::take(&mut self.core.out.changes)
    }

    /// The next record to write to the persistent store (after [`Changes::STORE`]), with
    /// its current value; `None` when none waits. Write each, in the order given.
    pub fn take_record(&mut self) -> Option<store::Record> {
        while let Some(key) = self.core.out.store.take() {
            let port = match key {
                store::Key::SIGNING_TELEMETRY | store::Key::SIGNING_KEY_TELEMETRY => {
                    Port::Telemetry
                }
                _ => Port::Fc,
            };
            if let Some(s) = self.core.signing_of(port) {
                return Some(s.record(key));
            }
        }
        self.core.settings.take_record()
    }

    /// Copies the next frame for `port` into `buf` and takes it off the queue; returns its
    /// length (`None`: nothing queued, or `buf` too small and the frame kept; a buffer of
    /// [`MAX_FRAME_LEN`] bytes takes any). Write the whole frame before taking the next. A
    /// time-sync frame put at the head of the pod queue while a taken frame is being
    /// written comes next.
    // `#[inline]` here and on `pending`, `receive` and `idle`: a dispatch on the port that
    // the caller often knows; out of line, the call cost a driver's loop 2 % more
    // instructions (scripts/bench).
    #[inline]
    pub fn transmit(&mut self, port: Port, buf: &mut [u8]) -> Option<usize> {
        match port {
            Port::Fc => self.core.out.fc.pop_into(buf),
            Port::Pod => self.core.out.pod.pop_into(buf),
            Port::Telemetry => self.core.out.tel.pop_into(buf),
        }
    }

    /// The length of the next frame [`Engine::transmit`] gives for `port` (`None`: nothing
    /// queued), for a writer that times a frame before it takes it.
    #[inline]
    #[must_use]
    pub fn pending(&self, port: Port) -> Option<usize> {
        match port {
            Port::Fc => self.core.out.fc.front(),
            Port::Pod => self.core.out.pod.front(),
            Port::Telemetry => self.core.out.tel.front(),
        }
        .map(<[u8]>::len)
    }

    /// Bytes from `port`; `now` is the local instant the last of them arrived. Returns what
    /// changed.
    #[inline]
    pub fn receive(&mut self, now: Instant, port: Port, bytes: &[u8]) -> Changes {
        match port {
            Port::Fc => self.fc_bytes(now, bytes),
            Port::Pod => self.pod_bytes(now, bytes),
            Port::Telemetry => self.telemetry_input(now, Some(bytes)),
        }
    }

    /// `port`'s line has gone idle (a UART idle interrupt, a read time-out): frames are
    /// complete, and an incomplete candidate will not be (see
    /// [`Deframer::poll_idle`](protocol_core::wire::Deframer::poll_idle)). On the FC link it is
    /// also one of the two signs by which the engine tells the FC's bursts apart (the
    /// other, a quiet line before bytes, it sees itself). Returns what changed.
    #[inline]
    pub fn idle(&mut self, now: Instant, port: Port) -> Changes {
        match port {
            Port::Fc => self.fc_line_idle(now),
            Port::Pod => self.pod_line_idle(now),
            Port::Telemetry => self.telemetry_input(now, None),
        }
    }

    /// [`Engine::receive`] for the FC.
    fn fc_bytes(&mut self, now: Instant, bytes: &[u8]) -> Changes {
        let core = &mut self.core;
        let (fc, mut ctx) = core.ctx(now);
        fc.receive(&mut ctx, bytes);
        let seen = ctx.fc_seen;
        core.fc_frame_seen(now, seen);
        core.after_input(now)
    }

    /// [`Engine::idle`] for the FC.
    fn fc_line_idle(&mut self, now: Instant) -> Changes {
        let core = &mut self.core;
        let (fc, mut ctx) = core.ctx(now);
        fc.idle(&mut ctx);
        let seen = ctx.fc_seen;
        core.fc_frame_seen(now, seen);
        core.after_input(now)
    }

    /// [`Engine::receive`] (`Some`) and [`Engine::idle`] (`None`) for the telemetry link.
    fn telemetry_input(&mut self, now: Instant, bytes: Option<&[u8]>) -> Changes {
        let core = &mut self.core;
        #[cfg(feature = "telemetry")]
        {
            let (tel, mut ctx) = core.telemetry_ctx(now);
            if let Some(tel) = tel {
                match bytes {
                    Some(b) => tel.receive(&mut ctx, b),
                    None => tel.idle(&mut ctx),
                }
            }
            core.time_source(now);
        }
        #[cfg(not(feature = "telemetry"))]
        let _ = bytes;
        core.after_input(now)
    }

    /// [`Engine::receive`] for the pod.
    fn pod_bytes(&mut self, now: Instant, bytes: &[u8]) -> Changes {
        let core = &mut self.core;
        self.pod_deframer.push(bytes, |ev| {
            if let DeframerEvent::Frame(f) = ev {
                core.pod_frame(now, f);
            }
        });
        core.after_input(now)
    }

    /// [`Engine::idle`] for the pod.
    fn pod_line_idle(&mut self, now: Instant) -> Changes {
        let core = &mut self.core;
        self.pod_deframer.flush(|ev| {
            if let DeframerEvent::Frame(f) = ev {
                core.pod_frame(now, f);
            }
        });
        core.after_input(now)
    }

    /// A PPS edge: the GNSS module's on-time edge ([`PpsConfig::active_low`](discipline::PpsConfig::active_low)
    /// says which one) at the local instant `edge` a timer captured, to the nanosecond
    /// (read the capture register, not the clock in an interrupt). It is labelled with
    /// its UTC second and disciplines the clock (see [`discipline`], "PPS"); the planned
    /// RTC_IO edge follows. Returns what changed.
    pub fn pps(&mut self, edge: InstantNs) -> Changes {
        let core = &mut self.core;
        let verdict = core.time.pps_edge(edge);
        let c = &mut core.out.counters;
        c.pps_edges = c.pps_edges.saturating_add(1);
        let n = match verdict {
            PpsVerdict::Accepted => None,
            PpsVerdict::Unlabelled => Some(&mut c.pps_unlabelled),
            PpsVerdict::Conflict => Some(&mut c.pps_conflicts),
            PpsVerdict::Outlier | PpsVerdict::Rejected => Some(&mut c.pps_rejected),
        };
        if let Some(n) = n {
            *n = n.saturating_add(1);
        }
        core.after_input(edge.instant())
    }

    /// UTC at a local instant to the nanosecond (ns since the Unix epoch), when known:
    /// the PPS line's resolution (the FC's mapping is known to the microsecond).
    #[must_use]
    pub fn utc_ns(&self, at: InstantNs) -> Option<u64> {
        self.core.time.utc_ns(at)
    }

    /// Where the PPS path stands.
    #[must_use]
    pub fn pps_state(&self) -> PpsState {
        self.core.time.pps_state()
    }

    /// Does the work due at `now`: retries and time-outs, link supervision, the FC
    /// silence stop, streamed replies, the UTC discipline and the sync plan. Returns what
    /// changed.
    pub fn poll(&mut self, now: Instant) -> Changes {
        self.core.poll(now);
        self.core.report()
    }

    /// The next RTC_IO change: the planned rising edge, or the falling edge after it.
    /// Apply it at its instant and report it with [`Engine::pin_done`].
    #[must_use]
    pub fn pin(&self) -> Option<PinAction> {
        match (self.core.pin_low, self.core.edge) {
            (Some(at), _) => Some(PinAction {
                level: Level::Low,
                at,
                sub_us_ns: 0,
            }),
            (None, Some(e)) => Some(PinAction {
                level: Level::High,
                at: e.at,
                sub_us_ns: e.sub_us_ns,
            }),
            (None, None) => None,
        }
    }

    /// The caller set RTC_IO to `level` at the local instant `at`. For a rising edge,
    /// the 0x00030E of that edge goes to the head of the pod queue (send it next) and
    /// the falling edge is planned. Returns what changed (always the pin plan).
    pub fn pin_done(&mut self, level: Level, at: Instant) -> Changes {
        self.core.pin_done(level, at);
        self.core.report()
    }

    /// When the engine wants [`Engine::poll`] called next (`None`: only on input).
    /// The RTC_IO edges have their own instants ([`Engine::pin`]); this is never later
    /// than the planned rising edge minus the sync lead, so that a re-planned edge is
    /// seen in time.
    #[must_use]
    pub fn poll_at(&self) -> Option<Instant> {
        let c = &self.core;
        let fc_down = c
            .fc_last
            .filter(|_| c.fc_link)
            .map(|t| t.saturating_add(c.config.fc_link_timeout));
        [
            c.pod.poll_at(c.config.fc_silence_stop),
            c.fc.poll_at(),
            c.telemetry_poll_at(),
            c.time.poll_at(),
            c.geotag.poll_at(),
            fc_down,
            // Re-plan the edge once more just before it; a settled edge needs no poll.
            c.edge
                .filter(|_| !c.edge_settled)
                .map(|e| e.at.saturating_sub(c.config.sync.lead)),
        ]
        .into_iter()
        .flatten()
        .min()
    }
}

/// The running signing key's fingerprint (MAVLink builds: the one SETUP_SIGNING records
/// name; without MAVLink nothing signs).
fn signing_fingerprint(config: &Config) -> Option<[u8; 6]> {
    #[cfg(feature = "mavlink")]
    {
        fc::LinkSigning::key_fingerprint(config.signing_key.as_ref())
    }
    #[cfg(not(feature = "mavlink"))]
    {
        let _ = config;
        None
    }
}

/// The [`Ctx`] of a link of `$state` (an [`EngineState`]): the engine's parts, borrowed
/// field by field (so that the caller may hold its link beside it).
macro_rules! engine_ctx {
    ($state:ident, $now:expr, $port:expr, $baud:expr, $feeds:expr) => {
        Ctx {
            now: $now,
            config: &$state.config,
            build: &$state.build,
            pod: &mut $state.pod,
            time: &mut $state.time,
            fixes: &mut $state.fixes,
            geotag: &mut $state.geotag,
            out: &mut $state.out,
            settings: &mut $state.settings,
            fc_seen: false,
            transit: Duration::ZERO,
            baud: $baud,
            to: $port,
            feeds: $feeds,
        }
    };
}

impl EngineState {
    /// When the telemetry link has work.
    #[cfg_attr(not(feature = "telemetry"), allow(clippy::unused_self))]
    fn telemetry_poll_at(&self) -> Option<Instant> {
        #[cfg(feature = "telemetry")]
        {
            use fc::FcHandler as _;
            self.tel.as_ref().and_then(|t| t.handler.poll_at())
        }
        #[cfg(not(feature = "telemetry"))]
        None
    }

    /// What changed since the last report; starts collecting again. The first report
    /// (the first input) says which records the bridge needs were not restored.
    fn report(&mut self) -> Changes {
        if self.first_input == FirstInput::Awaited {
            self.first_input = FirstInput::Seen;
            for port in [Port::Fc, Port::Telemetry] {
                if self
                    .signing_of(port)
                    .is_some_and(fc::LinkSigning::restore_missing)
                {
                    self.out.event(Event::StoreRecord {
                        key: store::Key::signing(port).0,
                        problem: store::Problem::Missing,
                    });
                }
            }
        }
        // Live settings (a PARAM_SET, the console) reach the parts that hold them.
        self.settings.apply_live(&mut self.config);
        self.pod.set_live(&self.config.pod, self.config.k40t_allow);
        if self.settings.records_due() {
            self.out.changes |= Changes::STORE;
        }
        core::mem::take(&mut self.out.changes)
    }

    /// The signing of the MAVLink link on `port` (the MAVLink side's on [`Port::Fc`], the
    /// telemetry link's), when there is one.
    #[allow(clippy::unnecessary_wraps, clippy::unused_self)] // without the MAVLink links
    fn signing_of(&mut self, port: Port) -> Option<&mut fc::LinkSigning> {
        match port {
            #[cfg(feature = "telemetry")]
            Port::Telemetry => self.tel.as_mut().map(|t| t.handler.signing()),
            Port::Fc => self.fc.link_signing(),
            _ => None,
        }
    }

    /// A record the caller found in its store (see [`store`]).
    fn restore(&mut self, key: store::Key, value: &[u8]) {
        use store::{Key, Problem};
        let port = match key {
            Key::SIGNING_FC | Key::SIGNING_KEY_FC => Port::Fc,
            Key::SIGNING_TELEMETRY | Key::SIGNING_KEY_TELEMETRY => Port::Telemetry,
            _ => Port::Pod,
        };
        let timestamp = key == Key::signing(port);
        let restored = match self.signing_of(port) {
            Some(s) if timestamp => s.restore_timestamp(value),
            Some(s) => s.restore_key(value),
            None => Err(Problem::UnknownKey),
        };
        if let Err(problem) = restored {
            self.out.event(Event::StoreRecord {
                key: key.0,
                problem,
            });
        }
    }

    fn ctx(&mut self, now: Instant) -> (&mut FcSide, Ctx<'_>) {
        let feeds = !self.tel_source;
        let baud = self.config.fc_baud;
        (&mut self.fc, engine_ctx!(self, now, Port::Fc, baud, feeds))
    }

    /// The telemetry link (when there is one) and its context.
    #[cfg(feature = "telemetry")]
    fn telemetry_ctx(&mut self, now: Instant) -> (Option<&mut fc::TelemetryLink>, Ctx<'_>) {
        let (feeds, baud) = (self.tel_source, self.config.telemetry_baud);
        let ctx = engine_ctx!(self, now, Port::Telemetry, baud, feeds);
        (self.tel.as_mut(), ctx)
    }

    /// Makes the telemetry link the source of UTC and fixes while it gives time, the FC
    /// link otherwise. On a change the UTC discipline starts again from the new source,
    /// keeping its mapping in holdover until the new one is known.
    #[cfg(feature = "telemetry")]
    fn time_source(&mut self, now: Instant) {
        let tel = self.tel.as_ref().is_some_and(|t| t.handler.gives_time(now));
        if tel != self.tel_source {
            self.tel_source = tel;
            self.time.switch_source();
            self.out.event(Event::TimeSource { telemetry: tel });
        }
    }

    /// A photo the geotag answered goes to the telemetry link as CAMERA_IMAGE_CAPTURED
    /// (the MAVLink FC side reports its own photos).
    #[cfg_attr(not(feature = "telemetry"), allow(clippy::unused_self))]
    fn photo_out(&mut self, now: Instant) {
        let Some(photo) = self.geotag.take_photo() else {
            return;
        };
        #[cfg(feature = "telemetry")]
        {
            let (tel, mut ctx) = self.telemetry_ctx(now);
            if let Some(tel) = tel {
                tel.handler.photo(&mut ctx, &photo);
            }
        }
        #[cfg(not(feature = "telemetry"))]
        let _ = (now, photo);
    }

    fn fc_frame_seen(&mut self, now: Instant, seen: bool) {
        if seen {
            self.fc_last = Some(now);
            if !self.fc_link {
                self.fc_link = true;
                self.out.event(Event::FcLinkUp);
            }
        }
    }

    /// One valid frame from the pod. An ACK goes to whoever has the better claim on it: the pod driver's own outstanding requests, or (K40T side) the FC's
    /// forwarded ones; see `pod::AckClaim`.
    fn pod_frame(&mut self, now: Instant, f: &[u8]) {
        self.out.counters.pod_frames = self.out.counters.pod_frames.saturating_add(1);
        let Ok(frame) = Frame::new_checked(f) else {
            return;
        };
        let Some(header) = frame.header() else {
            return;
        };
        let id = frame.id();
        let (driver_claimed, fc_claimed) = if id.kind == k40t::Kind::Ack {
            let driver = self.pod.ack_claim(id.base, header.seq);
            let fc = self.fc.ack_claim(now, id.base, header.seq);
            match (driver, fc) {
                (Some(d), Some(f)) => (!f.beats(d) || d.beats(f), f.beats(d) && !d.beats(f)),
                (d, f) => (d.is_some(), f.is_some()),
            }
        } else {
            (false, false)
        };
        let notices = self
            .pod
            .handle(now, &frame, header, driver_claimed, &mut self.out);
        {
            let (fc, mut ctx) = self.ctx(now);
            fc.pod_frame(
                &mut ctx,
                fc::PodFrame {
                    bytes: f,
                    id,
                    header,
                    ack_claimed: fc_claimed,
                },
            );
        }
        for n in notices.iter() {
            self.notice(now, n);
        }
    }

    fn notice(&mut self, now: Instant, n: PodNotice) {
        match n {
            PodNotice::LinkUp => {
                self.out.event(Event::PodLinkUp);
                // `laser.periodic`: ranging every second from every link-up.
                if self.config.laser.periodic {
                    let on = gimbal::Command::Laser(gimbal::Ranging::Continuous);
                    self.pod.command(now, on, &mut self.out);
                }
            }
            PodNotice::LinkDown => self.out.event(Event::PodLinkDown),
            PodNotice::Acked { .. } | PodNotice::TimedOut { .. } | PodNotice::Photo(_) => {}
            PodNotice::GpsRequest { header, request } => {
                let (fc, mut ctx) = self.ctx(now);
                if !fc.gps_request(&mut ctx, header, request) {
                    ctx.geotag(header, request);
                }
                self.photo_out(now);
                return;
            }
        }
        let (fc, mut ctx) = self.ctx(now);
        fc.pod_notice(&mut ctx, n);
    }

    /// Reports a change of the UTC discipline's state (samples arrive with the input)
    /// and plans the next edge; returns what the input changed.
    fn after_input(&mut self, now: Instant) -> Changes {
        self.utc_transition(now);
        // A fix may have come in for a waiting GPS request.
        self.geotag
            .poll(now, &self.fixes, &mut self.pod, &mut self.out);
        self.photo_out(now);
        self.plan_sync(now);
        self.report()
    }

    fn utc_transition(&mut self, now: Instant) {
        let t = self.time.poll(now);
        if let Some(p) = self.time.poll_pps() {
            self.out.event(match p {
                PpsState::Locked => Event::PpsLocked {
                    first_edge: self.time.pps_run_start().map_or(now, InstantNs::instant),
                },
                PpsState::Holdover => Event::PpsHoldover,
                PpsState::Off => Event::PpsReleased,
            });
        }
        if let Some(t) = t {
            if t.utc_lost() {
                self.out.event(Event::UtcLost);
            }
            if t.utc_became_valid() {
                let bound = self.time.error_bound(now).unwrap_or(Duration::ZERO);
                self.out.event(Event::UtcValid {
                    error_bound_us: u32::try_from(bound.as_micros()).unwrap_or(u32::MAX),
                    converged: self.time.is_converged(),
                });
            }
        }
    }

    fn poll(&mut self, now: Instant) {
        self.utc_transition(now);
        let notices = self
            .pod
            .poll(now, self.config.fc_silence_stop, &mut self.out);
        for n in notices.iter() {
            self.notice(now, n);
        }
        {
            let (fc, mut ctx) = self.ctx(now);
            fc.poll(&mut ctx);
        }
        #[cfg(feature = "telemetry")]
        {
            use fc::FcHandler as _;
            let (tel, mut ctx) = self.telemetry_ctx(now);
            if let Some(tel) = tel {
                tel.handler.poll(&mut ctx);
            }
            self.time_source(now);
        }
        self.geotag
            .poll(now, &self.fixes, &mut self.pod, &mut self.out);
        self.photo_out(now);
        if self.fc_link
            && self
                .fc_last
                .is_none_or(|t| now.saturating_duration_since(t) >= self.config.fc_link_timeout)
        {
            self.fc_link = false;
            self.out.event(Event::FcLinkDown);
        }
        self.plan_sync(now);
    }

    /// Plans (or re-plans, or cancels) the next rising edge.
    fn plan_sync(&mut self, now: Instant) {
        if self.pin_low.is_some() {
            return;
        }
        // An edge within `lead` is kept as planned: the caller may have armed its timer.
        let lead_start = now.saturating_add(self.config.sync.lead);
        self.edge_settled = self.edge.is_some_and(|e| e.at <= lead_start);
        if self.edge_settled {
            return;
        }
        // Holdover is still usable: the local clock carries UTC between sparse samples
        // (the K40T FC sends one every 10 s) and after the FC falls silent, for a while.
        let planned = self.edge.map(|e| e.at);
        self.edge = if self.time.state().is_usable() {
            self.sync.next_edge(now, &self.time)
        } else {
            None
        };
        if self.edge.map(|e| e.at) != planned {
            self.out.changes |= Changes::PIN;
        }
        self.edge_settled = self.edge.is_some_and(|e| e.at <= lead_start);
    }

    fn pin_done(&mut self, level: Level, at: Instant) {
        // The action done is no longer the next one.
        self.out.changes |= Changes::PIN;
        match level {
            Level::Low => self.pin_low = None,
            Level::High => {
                self.pin_low = Some(at.saturating_add(self.config.sync.width));
                self.edge_settled = false;
                let Some(edge) = self.edge.take() else {
                    return;
                };
                self.sync.fired(&edge);
                let Some(utc) = self.sync.stamp(&edge, at, &self.time) else {
                    return;
                };
                let utc_ms = utc.as_unix_millis_rounded();
                let bound = self.time.error_bound(at).unwrap_or(Duration::ZERO);
                if self
                    .pod
                    .send_time_sync(utc_ms, self.config.tz_minuteswest, &mut self.out)
                {
                    self.out.counters.time_syncs = self.out.counters.time_syncs.saturating_add(1);
                    self.out.event(Event::TimeSync {
                        edge: at,
                        utc_ms,
                        error_bound_us: u32::try_from(bound.as_micros()).unwrap_or(u32::MAX),
                    });
                }
            }
        }
    }
}

#[cfg(test)]
mod changes_tests {
    use super::*;
    use protocol_core::k40t::{Address, Header, TimeSync};

    fn frame_from_fc<M: k40t::MessageData<Protocol = k40t::K40t>>(m: &M, seq: u8) -> Vec<u8> {
        let header = Header::new(Address::FLIGHT_CONTROLLER, Address::POD, seq);
        let mut buf = [0u8; k40t::MAX_FRAME_LEN];
        let n = k40t::encode(m, &header, &mut buf).unwrap();
        buf[..n].to_vec()
    }

    /// Each input reports what it changed, and only that (the firmware wakes its tasks
    /// by it); `poll_at` is not in it.
    #[test]
    fn each_input_reports_what_it_changed() {
        let mut e = Engine::new(Config::for_fc(FcProtocol::K40t));
        let mut buf = [0u8; MAX_FRAME_LEN];
        let ms = Instant::from_millis;
        // The pod is not there: a version probe for it.
        assert_eq!(e.poll(ms(0)), Changes::POD_FRAME);
        assert!(e.transmit(Port::Pod, &mut buf).is_some());
        // Nothing due, nothing to say.
        assert_eq!(e.poll(ms(1)), Changes::NONE);
        // The FC's own time sync (K40T side): ACKed to the FC, the FC link comes up, UTC
        // becomes valid and the first edge is planned.
        let sync = TimeSync {
            unix_ms: 1_767_225_600_000,
            tz_minuteswest: 0,
            tz_dsttime: 0,
        };
        let c = e.receive(ms(100), Port::Fc, &frame_from_fc(&sync, 1));
        assert_eq!(c, Changes::FC_FRAME | Changes::PIN | Changes::EVENTS);
        assert!(e.pending(Port::Fc).is_some() && e.pending(Port::Pod).is_none());
        let edge = e.pin().unwrap();
        assert_eq!(edge.level, Level::High);
        // The line goes idle with nothing left in the deframer: nothing changed.
        assert_eq!(e.idle(ms(105), Port::Fc), Changes::NONE);
        // Taking outputs is no input: it reports nothing, and clears nothing.
        while e.next_event().is_some() {}
        assert!(e.transmit(Port::Fc, &mut buf).is_some());
        // The rising edge: the 0x00030E at the head of the pod queue, the falling edge
        // planned, the time-sync event.
        let c = e.pin_done(Level::High, edge.at);
        assert_eq!(c, Changes::POD_FRAME | Changes::PIN | Changes::EVENTS);
        let n = e.pending(Port::Pod).unwrap();
        assert_eq!(e.transmit(Port::Pod, &mut buf), Some(n));
        let sync = k40t::Packet::decode(&buf[..n]).unwrap();
        assert!(sync.message.get::<TimeSync>().is_some());
        assert_eq!(e.pin().map(|p| p.level), Some(Level::Low));
        // A buffer too small keeps the frame.
        let mut small = [0u8; 4];
        e.pin_done(
            Level::Low,
            edge.at.saturating_add(Duration::from_millis(50)),
        );
        e.poll(ms(12_000));
        let n = e.pending(Port::Pod).unwrap();
        assert_eq!(e.transmit(Port::Pod, &mut small), None);
        assert_eq!(e.pending(Port::Pod), Some(n));
    }

    #[test]
    fn changes_are_a_small_bit_set() {
        let c = Changes::FC_FRAME | Changes::EVENTS;
        assert!(c.contains(Changes::FC_FRAME) && c.contains(Changes::EVENTS));
        assert!(!c.contains(Changes::FC_FRAME | Changes::PIN));
        assert!(c.intersects(Changes::FC_FRAME | Changes::PIN));
        assert!(!c.intersects(Changes::frame(Port::Pod)));
        assert_eq!(Changes::frame(Port::Fc), Changes::FC_FRAME);
        assert!(Changes::NONE.is_empty() && !c.is_empty());
        assert_eq!(Changes::default(), Changes::NONE);
    }
}

#[cfg(test)]
mod size_tests {
    use super::*;

    /// The engine's size is fixed at compile time; with every FC side compiled in it
    /// stays under 14 KiB on the 64-bit host (7.9 KB before ACK matching kept
    /// superseded requests and their send instants, and the discipline its error bound;
    /// 9.1 KB before the MAVLink telemetry link: its 280-byte deframer, 192-byte queue
    /// and autopilot state; 10.7 KB before the camera's settings: the parameters' and FTP
    /// sessions' state, the pod's all-settings replies and two more pod requests
    /// tracked, and the discipline's rate; under 11.5 KiB before the PPS path: its 16
    /// edges and line, and the photo event, which makes every queued event 8 bytes
    /// longer; 12.1 KB before the two links' signing state; 13.1 KB before the refusal
    /// limiter, the pinned autopilot, the store's pending records and the build line;
    /// 13 504 B before the settings, measured with every feature: the settings as set and
    /// the defaults, two `Config`s, and the console's line, output and counters; 15 744 B
    /// before the two MAVLink deframers grew from 281 to 561 bytes to judge a frame of an
    /// unknown id on every byte that can decide it). Measured 16 304 B; bound 16 KiB.
    #[test]
    fn the_engine_fits_in_16_kib() {
        let size = core::mem::size_of::<Engine>();
        println!(
            "engine {size} B: pod driver {}, discipline {}, fixes {}, outputs {}, FC side {}",
            core::mem::size_of::<PodDriver>(),
            core::mem::size_of::<TimeDiscipline>(),
            core::mem::size_of::<FixHistory>(),
            core::mem::size_of::<Outputs>(),
            core::mem::size_of::<FcSide>(),
        );
        assert!(size <= 16 * 1024, "{size} bytes");
    }
}
