//! The update port: the update protocol's bytes between a serial port and the sans-IO
//! [`Receiver`](bridge_update::Receiver), and the trial of a freshly swapped-in image.
//!
//! On the board the port is the ST-LINK virtual COM port (USART1). The console
//! ([`console_task`](crate::console_task)) owns that port and hands it over on its `update`
//! command, or on an update frame's sync at a line's start; it gets it back after
//! [`UPDATE_IDLE`](bridge_engine::UPDATE_IDLE) without a frame. [`update_task`] is the port
//! without the console. Nothing here decides anything: the
//! receiver decides what to write and whether the signature holds, [`Trial`] when the
//! image confirms itself.

use bridge_update::wire::{BootState, MAX_FRAME, Refusal, Request, Response, UpdateFraming};
use bridge_update::{Receiver, Slot, Trial};
use embassy_futures::select::{Either, select};
use embassy_futures::yield_now;
use embassy_sync::blocking_mutex::raw::RawMutex;
use embassy_time::{Duration, Timer};
use embedded_io_async::{Read, Write};
use protocol_core::wire::{Deframer, Event};

use crate::engine::BridgeEngine;
use crate::now;
use crate::shared::{LogKind, Shared};

/// What the update port did (logged as [`LogKind::Update`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum UpdateLog {
    /// The state the running image started in.
    Started(BootState),
    /// The image on trial confirmed itself (links up, or the bounded time).
    Confirmed,
    /// The confirmation could not be written (it is tried again every second).
    ConfirmFailed,
    /// A transfer began (image bytes).
    Begun(u32),
    /// The signature held: the image is marked for the swap at the next reset.
    Verified,
    /// A request was refused.
    Refused(Refusal),
    /// The client asked for the reset.
    Rebooting,
}

/// How often a trial checks the links.
pub(crate) const TRIAL_CHECK: Duration = Duration::from_secs(1);

/// Serves the update protocol on `rx`/`tx` until the client asks for a reset (then
/// returns: the caller resets once the answer has left), and confirms an image on trial
/// once [`Trial::healthy`] says so (checked every second with the engine's status). The
/// port alone, without the console ([`console_task`](crate::console_task) hands its port
/// over the same way).
pub async fn update_task<M: RawMutex, E: BridgeEngine, R: Read, W: Write, S: Slot>(
    shared: &Shared<M, E>,
    rx: &mut R,
    tx: &mut W,
    slot: &mut S,
    receiver: &mut Receiver<'_>,
) {
    let mut trial = start_trial(shared, slot);
    let mut port = UpdatePort {
        rx,
        tx,
        slot,
        receiver,
    };
    while !port.serve(shared, &[], None, &mut trial).await {}
}

/// The running image's boot state, logged; a trial when it is on trial.
pub(crate) fn start_trial<M: RawMutex, E: BridgeEngine, S: Slot>(
    shared: &Shared<M, E>,
    slot: &mut S,
) -> Option<Trial> {
    let state = slot.state();
    if let Ok(state) = state {
        shared.record(now(), LogKind::Update(UpdateLog::Started(state)));
    }
    (state == Ok(BootState::Trial)).then(|| Trial::new(now().as_micros()))
}

/// Confirms the image on trial once [`Trial::healthy`] says so (`trial` ends then).
pub(crate) fn check_trial<M: RawMutex, E: BridgeEngine, S: Slot>(
    shared: &Shared<M, E>,
    slot: &mut S,
    trial: &mut Option<Trial>,
) {
    let Some(t) = trial else { return };
    let status = shared.with_state(|s| s.engine.status());
    if t.healthy(now().as_micros(), status.fc_link, status.pod_link) {
        let done = slot.mark_booted().is_ok();
        let log = if done {
            UpdateLog::Confirmed
        } else {
            UpdateLog::ConfirmFailed
        };
        shared.record(now(), LogKind::Update(log));
        if done {
            *trial = None;
        }
    }
}

/// The update port's resources: the serial port's halves, the slot, the receiver.
pub(crate) struct UpdatePort<'a, 'k, R, W, S> {
    pub(crate) rx: &'a mut R,
    pub(crate) tx: &'a mut W,
    pub(crate) slot: &'a mut S,
    pub(crate) receiver: &'a mut Receiver<'k>,
}

impl<R: Read, W: Write, S: Slot> UpdatePort<'_, '_, R, W, S> {
    /// Serves the update protocol, `first` being its first bytes, until the client asks
    /// for a reset (`true`) or, with `idle`, that long passes without a frame (`false`:
    /// the port goes back to the console).
    pub(crate) async fn serve<M: RawMutex, E: BridgeEngine>(
        &mut self,
        shared: &Shared<M, E>,
        first: &[u8],
        idle: Option<Duration>,
        trial: &mut Option<Trial>,
    ) -> bool {
        let mut deframer = Deframer::<UpdateFraming, MAX_FRAME>::new(UpdateFraming);
        let mut buf = [0u8; 64];
        let mut pending = first;
        let mut last_frame = embassy_time::Instant::now();
        loop {
            let input = if pending.is_empty() {
                let read = match select(self.rx.read(&mut buf), Timer::after(TRIAL_CHECK)).await {
                    Either::First(Ok(n)) => n,
                    Either::First(Err(_)) => 0,
                    Either::Second(()) => {
                        check_trial(shared, self.slot, trial);
                        if idle.is_some_and(|d| last_frame.elapsed() >= d) {
                            return false;
                        }
                        continue;
                    }
                };
                buf.get(..read).unwrap_or_default()
            } else {
                core::mem::take(&mut pending)
            };
            let mut input = input;
            while !input.is_empty() {
                let taken = deframer.feed(input);
                input = input.get(taken..).unwrap_or_default();
                let mut out = [0u8; MAX_FRAME];
                loop {
                    let len = match deframer.poll() {
                        Some(Event::Frame(frame)) => {
                            last_frame = embassy_time::Instant::now();
                            answer(shared, self.receiver, self.slot, frame, &mut out)
                        }
                        Some(_) => continue,
                        None => break,
                    };
                    let len = match len {
                        Some(len) => len,
                        // A signature check under way: in steps, letting the other tasks run.
                        None => loop {
                            if let Some(response) = self.receiver.work(self.slot) {
                                log_response(shared, &response);
                                break response.emit(&mut out).unwrap_or(0);
                            }
                            yield_now().await;
                        },
                    };
                    let reply = out.get(..len).unwrap_or_default();
                    if self.tx.write_all(reply).await.is_err() || self.tx.flush().await.is_err() {
                        continue;
                    }
                    if self.receiver.reboot_requested() {
                        shared.record(now(), LogKind::Update(UpdateLog::Rebooting));
                        return true;
                    }
                }
            }
        }
    }
}

/// The answer to one frame, written into `out` (its length), or `None` while the
/// signature check runs.
fn answer<M: RawMutex, E: BridgeEngine, S: Slot>(
    shared: &Shared<M, E>,
    receiver: &mut Receiver<'_>,
    slot: &mut S,
    frame: &[u8],
    out: &mut [u8],
) -> Option<usize> {
    let response = match Request::parse(frame) {
        Ok(request) => {
            if let Request::Begin { size, .. } = request {
                shared.record(now(), LogKind::Update(UpdateLog::Begun(size)));
            }
            receiver.handle(request, slot)?
        }
        Err(_) => Response::Refused {
            reason: Refusal::Malformed,
            detail: 0,
        },
    };
    log_response(shared, &response);
    Some(response.emit(out).unwrap_or(0))
}

fn log_response<M: RawMutex, E: BridgeEngine>(shared: &Shared<M, E>, response: &Response<'_>) {
    let log = match response {
        Response::Verified => UpdateLog::Verified,
        Response::Refused { reason, .. } => UpdateLog::Refused(*reason),
        _ => return,
    };
    shared.record(now(), LogKind::Update(log));
}
