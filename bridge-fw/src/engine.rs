//! What the tasks need of the engine, as a trait: [`Engine`] implements it; tests wrap it
//! (for instance to plan RTC_IO edges before an FC side gives UTC).

use protocol_core::bridge::{Engine, Event, Instant, Level, PinAction, Port};

/// Link and time status, for the LED.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Status {
    /// The FC link is up.
    pub fc_link: bool,
    /// The pod link is up.
    pub pod_link: bool,
    /// UTC is known (time syncs are sent).
    pub utc: bool,
}

/// The sans-IO engine as the tasks drive it. Each method is the [`Engine`] method of the
/// same name for `port`.
pub trait BridgeEngine {
    /// Bytes from `port`, the last of them at `now`.
    fn receive(&mut self, port: Port, now: Instant, bytes: &[u8]);
    /// `port`'s line has gone idle.
    fn idle(&mut self, port: Port, now: Instant);
    /// [`Engine::poll`].
    fn poll(&mut self, now: Instant);
    /// [`Engine::poll_at`].
    fn poll_at(&self) -> Option<Instant>;
    /// The next frame for `port`.
    fn frame(&self, port: Port) -> Option<&[u8]>;
    /// The frame [`BridgeEngine::frame`] gave is on its way.
    fn sent(&mut self, port: Port);
    /// [`Engine::pin`].
    fn pin(&self) -> Option<PinAction>;
    /// [`Engine::pin_done`].
    fn pin_done(&mut self, level: Level, at: Instant);
    /// [`Engine::next_event`].
    fn next_event(&mut self) -> Option<Event>;
    /// Link and time status.
    fn status(&self) -> Status;
}

impl BridgeEngine for Engine {
    fn receive(&mut self, port: Port, now: Instant, bytes: &[u8]) {
        match port {
            Port::Fc => self.receive_fc(now, bytes),
            Port::Pod => self.receive_pod(now, bytes),
        }
    }

    fn idle(&mut self, port: Port, now: Instant) {
        match port {
            Port::Fc => self.fc_idle(now),
            Port::Pod => self.pod_idle(now),
        }
    }

    fn poll(&mut self, now: Instant) {
        Engine::poll(self, now);
    }

    fn poll_at(&self) -> Option<Instant> {
        Engine::poll_at(self)
    }

    fn frame(&self, port: Port) -> Option<&[u8]> {
        match port {
            Port::Fc => self.fc_frame(),
            Port::Pod => self.pod_frame(),
        }
    }

    fn sent(&mut self, port: Port) {
        match port {
            Port::Fc => self.fc_sent(),
            Port::Pod => self.pod_sent(),
        }
    }

    fn pin(&self) -> Option<PinAction> {
        Engine::pin(self)
    }

    fn pin_done(&mut self, level: Level, at: Instant) {
        Engine::pin_done(self, level, at);
    }

    fn next_event(&mut self) -> Option<Event> {
        Engine::next_event(self)
    }

    fn status(&self) -> Status {
        Status {
            fc_link: self.fc_link(),
            pod_link: self.pod_state().link,
            utc: self.utc_state().is_usable(),
        }
    }
}
