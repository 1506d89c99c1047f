//! The serial links: UART → engine, engine → UART.

use bridge_engine::{Instant, Level, MAX_FRAME_LEN, PinAction, Port};
use embassy_futures::join::join;
use embassy_futures::select::select;
use embassy_sync::blocking_mutex::raw::RawMutex;
use embassy_time::{Timer, with_timeout};
use embedded_io_async::{Read, Write};

use crate::engine::BridgeEngine;
use crate::shared::LogKind;
use crate::shared::{Heartbeat, Shared, Timing};
use crate::{now, to_embassy};

/// Bytes taken from the UART per read (the UART driver buffers the rest).
const READ_CHUNK: usize = 64;

/// Reads `port` forever: bytes go to the engine with the instant they were read; when
/// the line has been silent for [`Timing::idle`] after bytes, the engine is told the line
/// is idle (frames are complete). That is all it says: what a silence means (on the FC
/// link, where a burst starts) is the engine's decision. Each input wakes the tasks it
/// concerns ([`Shared::input`]). Marks its heartbeat at least every
/// [`Timing::heartbeat`]. Read errors are logged and reading goes on.
pub async fn link_reader<M: RawMutex, E: BridgeEngine, R: Read>(
    shared: &Shared<M, E>,
    port: Port,
    mut rx: R,
) -> ! {
    let timing = *shared.timing();
    let mut buf = [0u8; READ_CHUNK];
    // Bytes arrived since the line was last idle.
    let mut pending = false;
    loop {
        let wait = if pending {
            timing.idle(port)
        } else {
            timing.heartbeat
        };
        match with_timeout(to_embassy_duration(wait), rx.read(&mut buf)).await {
            Ok(Ok(n)) if n > 0 => {
                let at = now();
                let bytes = buf.get(..n).unwrap_or(&buf);
                shared.input(|e| e.receive(at, port, bytes));
                pending = true;
            }
            // End of stream (a host peer closed): nothing to read for now.
            Ok(Ok(_)) => Timer::after(to_embassy_duration(timing.heartbeat)).await,
            Ok(Err(_)) => shared.record(now(), LogKind::ReadError(port)),
            Err(_) if pending => {
                let at = now();
                shared.input(|e| e.idle(at, port));
                pending = false;
            }
            Err(_) => {}
        }
        shared.alive(Heartbeat::rx(port));
    }
}

/// What the writer does next.
enum Next {
    /// Write the frame copied into the buffer (this many bytes).
    Write(usize),
    /// A planned edge comes before the frame would be out: wait for it (or this instant).
    Hold(Instant),
    /// Nothing to send.
    Idle,
}

/// Whether a frame of `wire` time started `now` would still be on the wire at the next
/// rising edge: then it waits until the edge (the 0x00030E goes first).
fn hold_for_edge(
    pin: Option<PinAction>,
    now: Instant,
    wire: bridge_engine::Duration,
) -> Option<Instant> {
    let edge = pin.filter(|p| p.level == Level::High)?.at;
    (now.saturating_add(wire) >= edge).then_some(edge)
}

/// Writes `port`'s frames forever, one whole frame at a time, each taken from the engine
/// ([`Engine::transmit`](bridge_engine::Engine::transmit)) under the lock, then
/// written and flushed: a frame is never split and never waits behind more than the frame
/// before it in the UART's buffer. Woken when its queue gets a frame (the pod writer also
/// when the RTC_IO plan changes), else it looks every [`Timing::heartbeat`].
///
/// On the pod link, a frame that would still be on the wire at the next planned RTC_IO
/// rising edge ([`Timing::wire_time`] at the link's baud rate, plus two byte times) is
/// held until the edge: the 0x00030E that the engine then puts at the head goes first,
/// so the delay from the edge to its first byte is one task hand-over. This is timing,
/// not protocol: the writer never looks inside a frame.
pub async fn link_writer<M: RawMutex, E: BridgeEngine, W: Write>(
    shared: &Shared<M, E>,
    port: Port,
    mut tx: W,
) -> ! {
    let timing: Timing = *shared.timing();
    let mut buf = [0u8; MAX_FRAME_LEN];
    loop {
        let start = now();
        let mut edge = None;
        let next = shared.with_state(|s| {
            let Some(n) = s.engine.pending(port) else {
                return Next::Idle;
            };
            if port == Port::Pod {
                let wire = timing.wire_time(port, n.saturating_add(2));
                if let Some(at) = hold_for_edge(s.engine.pin(), start, wire) {
                    return Next::Hold(at);
                }
                edge = s.edge.take();
            }
            // The buffer holds any frame a queue can (`None`: cannot happen).
            s.engine
                .transmit(port, &mut buf)
                .map_or(Next::Idle, Next::Write)
        });
        match next {
            Next::Write(n) => {
                if let Some(edge) = edge {
                    shared.record(
                        start,
                        LogKind::EdgeToFrame {
                            delay: start.saturating_duration_since(edge),
                            len: u16::try_from(n).unwrap_or(u16::MAX),
                        },
                    );
                }
                let frame = buf.get(..n).unwrap_or(&buf);
                let ok = tx.write_all(frame).await.is_ok() && tx.flush().await.is_ok();
                if !ok {
                    shared.record(now(), LogKind::WriteError(port));
                }
            }
            Next::Hold(at) => {
                // The engine task wakes us right after the edge; the deadline is a safety net.
                let until = to_embassy(at.max(start)) + to_embassy_duration(timing.idle_min);
                select(shared.wake_tx(port).wait(), Timer::at(until)).await;
            }
            Next::Idle => {
                select(
                    shared.wake_tx(port).wait(),
                    Timer::after(to_embassy_duration(timing.heartbeat)),
                )
                .await;
            }
        }
        shared.alive(Heartbeat::tx(port));
    }
}

/// Both directions of one link: [`link_reader`] and [`link_writer`] joined.
pub async fn link<M: RawMutex, E: BridgeEngine, R: Read, W: Write>(
    shared: &Shared<M, E>,
    port: Port,
    rx: R,
    tx: W,
) -> ! {
    let (never, _) = join(link_reader(shared, port, rx), link_writer(shared, port, tx)).await;
    never
}

/// An engine duration as an embassy-time duration.
pub(crate) const fn to_embassy_duration(d: bridge_engine::Duration) -> embassy_time::Duration {
    embassy_time::Duration::from_micros(d.as_micros())
}
