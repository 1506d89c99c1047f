//! What the tasks need of the engine, as a trait: [`Engine`] implements it with its own
//! methods; tests put doubles in its place (a spy around the engine, a scripted engine
//! that plans RTC_IO edges without an FC side).

use bridge_engine::{
    Changes, ConsoleAction, Engine, Event, Instant, InstantNs, Level, PinAction, Port,
};

/// Link and time status, for the LED ([`crate::led`]).
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
    /// UTC is disciplined by the PPS input (locked to its edges).
    pub pps_locked: bool,
}

/// The sans-IO engine as the tasks drive it: each method but [`BridgeEngine::status`] is
/// the [`Engine`] method of the same name. A double must report its [`Changes`] as the
/// engine does: the tasks wake only whom they concern.
pub trait BridgeEngine {
    /// [`Engine::receive`].
    fn receive(&mut self, now: Instant, port: Port, bytes: &[u8]) -> Changes;
    /// [`Engine::idle`].
    fn idle(&mut self, now: Instant, port: Port) -> Changes;
    /// [`Engine::poll`].
    fn poll(&mut self, now: Instant) -> Changes;
    /// [`Engine::poll_at`].
    fn poll_at(&self) -> Option<Instant>;
    /// [`Engine::pending`].
    fn pending(&self, port: Port) -> Option<usize>;
    /// [`Engine::transmit`].
    fn transmit(&mut self, port: Port, buf: &mut [u8]) -> Option<usize>;
    /// [`Engine::pin`].
    fn pin(&self) -> Option<PinAction>;
    /// [`Engine::pin_done`].
    fn pin_done(&mut self, level: Level, at: Instant) -> Changes;
    /// [`Engine::next_event`].
    fn next_event(&mut self) -> Option<Event>;
    /// [`Engine::pps`] (a double without a PPS path ignores the edge).
    fn pps(&mut self, edge: InstantNs) -> Changes {
        let _ = edge;
        Changes::NONE
    }
    /// Link and time status.
    fn status(&self) -> Status;
    /// [`Engine::take_record`] (a double keeps nothing).
    fn take_record(&mut self) -> Option<bridge_engine::store::Record> {
        None
    }
    /// [`Engine::restore`].
    fn restore(&mut self, key: u16, value: &[u8]) -> Changes {
        let _ = (key, value);
        Changes::NONE
    }
    /// [`Engine::restore_failed`].
    fn restore_failed(&mut self, problem: bridge_engine::store::Problem) -> Changes {
        let _ = problem;
        Changes::NONE
    }
    /// [`Engine::console_receive`] (a double has no console).
    fn console_receive(&mut self, now: Instant, bytes: &[u8]) -> (Changes, Option<ConsoleAction>) {
        let _ = (now, bytes);
        (Changes::NONE, None)
    }
    /// [`Engine::console_transmit`].
    fn console_transmit(&mut self, buf: &mut [u8]) -> usize {
        let _ = buf;
        0
    }
    /// [`Engine::console_resume`].
    fn console_resume(&mut self) -> Changes {
        Changes::NONE
    }
    /// [`Engine::records_due`].
    fn records_due(&self) -> bool {
        false
    }
}

impl BridgeEngine for Engine {
    fn receive(&mut self, now: Instant, port: Port, bytes: &[u8]) -> Changes {
        Engine::receive(self, now, port, bytes)
    }

    fn idle(&mut self, now: Instant, port: Port) -> Changes {
        Engine::idle(self, now, port)
    }

    fn poll(&mut self, now: Instant) -> Changes {
        Engine::poll(self, now)
    }

    fn poll_at(&self) -> Option<Instant> {
        Engine::poll_at(self)
    }

    fn pending(&self, port: Port) -> Option<usize> {
        Engine::pending(self, port)
    }

    fn transmit(&mut self, port: Port, buf: &mut [u8]) -> Option<usize> {
        Engine::transmit(self, port, buf)
    }

    fn pin(&self) -> Option<PinAction> {
        Engine::pin(self)
    }

    fn pin_done(&mut self, level: Level, at: Instant) -> Changes {
        Engine::pin_done(self, level, at)
    }

    fn next_event(&mut self) -> Option<Event> {
        Engine::next_event(self)
    }

    fn pps(&mut self, edge: InstantNs) -> Changes {
        Engine::pps(self, edge)
    }

    fn take_record(&mut self) -> Option<bridge_engine::store::Record> {
        Engine::take_record(self)
    }

    fn restore(&mut self, key: u16, value: &[u8]) -> Changes {
        Engine::restore(self, key, value)
    }

    fn restore_failed(&mut self, problem: bridge_engine::store::Problem) -> Changes {
        Engine::restore_failed(self, problem)
    }

    fn console_receive(&mut self, now: Instant, bytes: &[u8]) -> (Changes, Option<ConsoleAction>) {
        Engine::console_receive(self, now, bytes)
    }

    fn console_transmit(&mut self, buf: &mut [u8]) -> usize {
        Engine::console_transmit(self, buf)
    }

    fn console_resume(&mut self) -> Changes {
        Engine::console_resume(self)
    }

    fn records_due(&self) -> bool {
        Engine::records_due(self)
    }

    fn status(&self) -> Status {
        Status {
            fc_link: self.fc_link(),
            pod_link: self.pod_state().link,
            utc: self.utc_state().is_usable(),
            pps_locked: self.pps_state() == bridge_engine::discipline::PpsState::Locked,
        }
    }
}
