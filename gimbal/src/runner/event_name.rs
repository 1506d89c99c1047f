//! Every event name the tool writes, in one list: [`EventName`]. The runner's output
//! ([`crate::runner::output`]) takes an [`EventName`], never a free string, so an event
//! cannot be written without being listed here; the book's event table
//! (docs/src/linux-bridge.md, "Output and the JSON events") is checked against
//! [`EventName::ALL`] by `host-tests/tests/book.rs`, and `gimbal report` knows every name
//! in it.

/// Declares [`EventName`], its [`EventName::ALL`] and its snake_case names at once, so
/// that the three cannot disagree.
macro_rules! event_names {
    ($($(#[$doc:meta])* $variant:ident = $name:literal,)*) => {
        /// The name of an event (its `"event"` field).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum EventName {
            $($(#[$doc])* $variant,)*
        }

        impl EventName {
            /// Every event name, in the order of the book's table.
            pub const ALL: &'static [EventName] = &[$(EventName::$variant,)*];

            /// The name as written (`"time_sync"`).
            #[must_use]
            pub const fn as_str(self) -> &'static str {
                match self {
                    $(EventName::$variant => $name,)*
                }
            }
        }
    };
}

event_names! {
    /// `gimbal bridge`'s first line.
    BridgeStarted = "bridge_started",
    /// `gimbal demo --events json`'s first line.
    DemoStarted = "demo_started",
    /// The state file could not be read and was set aside.
    StateFileSetAside = "state_file_set_aside",
    /// A listening port is bound.
    PortListening = "port_listening",
    /// A serial device opened, a `udp:` socket bound.
    PortOpened = "port_opened",
    /// A UDP port heard from a new peer.
    PortPeer = "port_peer",
    /// A TCP connection made or accepted.
    PortConnected = "port_connected",
    /// A connection ended.
    PortClosed = "port_closed",
    /// Connecting or reopening failed.
    PortError = "port_error",
    /// The engine's FC link came up.
    FcLinkUp = "fc_link_up",
    /// The engine's FC link went down.
    FcLinkDown = "fc_link_down",
    /// The engine's pod link came up.
    PodLinkUp = "pod_link_up",
    /// The engine's pod link went down.
    PodLinkDown = "pod_link_down",
    /// The UTC estimate became trusted.
    UtcValid = "utc_valid",
    /// The UTC estimate was lost.
    UtcLost = "utc_lost",
    /// The source of UTC and fixes changed.
    TimeSource = "time_source",
    /// The RTC_IO pin changed.
    RtcIo = "rtc_io",
    /// Setting the RTC_IO line failed.
    RtcIoError = "rtc_io_error",
    /// A 0x00030E was queued for the pod.
    TimeSync = "time_sync",
    /// The 0x00030E left after its edge.
    EdgeToFrame = "edge_to_frame",
    /// The pod asked for a photo's position.
    Geotag = "geotag",
    /// A geotag answered with a fix.
    Photo = "photo",
    /// The engine's newest fix (at most once a second).
    Fix = "fix",
    /// The clock locked to the PPS edges.
    PpsLocked = "pps_locked",
    /// The PPS edges stopped.
    PpsHoldover = "pps_holdover",
    /// The PPS lock was released.
    PpsReleased = "pps_released",
    /// The PPS source failed.
    PpsError = "pps_error",
    /// A row of the photo event file could not be written.
    PhotoEventsError = "photo_events_error",
    /// An FC command became a pod command.
    Translated = "translated",
    /// The pod refused a command.
    PodRefused = "pod_refused",
    /// The pod did not answer a command.
    PodTimeout = "pod_timeout",
    /// The pod was stopped because the FC went silent.
    FcSilenceStop = "fc_silence_stop",
    /// The autopilot's MAVLink link gives no time and no position.
    NoTimeOrFixes = "no_time_or_fixes",
    /// A rate beyond the pod's was clamped.
    RateClamped = "rate_clamped",
    /// The pod's addresses learnt.
    PodAddresses = "pod_addresses",
    /// The pod's CRC coverage learnt.
    PodCoverage = "pod_coverage",
    /// The pod's IP address learnt.
    PodIp = "pod_ip",
    /// A command the bridge declined itself.
    Declined = "declined",
    /// A destructive command DENIED by the configuration.
    DestructiveDenied = "destructive_denied",
    /// A frame refused by the gate or the signing rules.
    Refused = "refused",
    /// SETUP_SIGNING changed a link's key.
    SigningKeyChanged = "signing_key_changed",
    /// Another autopilot's HEARTBEAT while the pinned one is heard.
    OtherAutopilot = "other_autopilot",
    /// A record of the persistent store was not restored.
    StoreRecord = "store_record",
    /// A record could not be written to the persistent store.
    StoreError = "store_error",
    /// A setting set, refused, saved or reset (console or parameter protocol).
    Setting = "setting",
    /// The update port's progress (the board's).
    Update = "update",
    /// Frames dropped from a full queue.
    Dropped = "dropped",
    /// A link task's read failed.
    ReadError = "read_error",
    /// A link task's write failed.
    WriteError = "write_error",
    /// The watchdog task saw loops make no progress.
    Stalled = "stalled",
    /// A frame in either direction (`--trace`).
    Frame = "frame",
    /// The engine's counters.
    Counters = "counters",
    /// The run ended.
    Stopped = "stopped",
    /// `gimbal sim-fc`'s first line.
    SimFcStarted = "sim_fc_started",
    /// The simulated FC's health changed.
    SimFcHealth = "sim_fc_health",
    /// The simulated FC took a picture.
    SimFcPhoto = "sim_fc_photo",
    /// The simulated FC's turn (`--yaw-rate`, `--pitch-rate`).
    SimFcRates = "sim_fc_rates",
    /// `gimbal sim-pod`'s first line.
    SimPodStarted = "sim_pod_started",
    /// The simulated pod's RTC_IO input changed.
    SimPodRtcIo = "sim_pod_rtc_io",
    /// The simulated pod handled a 0x00030E.
    SimPodSync = "sim_pod_sync",
    /// The simulated pod took a photo.
    SimPodPhoto = "sim_pod_photo",
    /// The simulated pod got its GPS reply.
    SimPodGpsReply = "sim_pod_gps_reply",
    /// The simulated pod booted (a task bench's log: the demo's).
    SimPodBoot = "sim_pod_boot",
    /// A simulator's last line.
    Summary = "summary",
}

impl EventName {
    /// The event named `name`, if the tool writes one.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|e| e.as_str() == name)
    }
}

impl core::fmt::Display for EventName {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::EventName;

    #[test]
    fn names_are_snake_case_and_unique() {
        let mut seen = std::collections::HashSet::new();
        for e in EventName::ALL {
            let n = e.as_str();
            assert!(n.chars().all(|c| c.is_ascii_lowercase() || c == '_'), "{n}");
            assert!(seen.insert(n), "{n} twice");
            assert_eq!(EventName::from_name(n), Some(*e));
        }
        assert_eq!(EventName::from_name("no_such_event"), None);
    }
}
