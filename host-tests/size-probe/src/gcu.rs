//! GCU: deframe host packages (what the bridge receives as the GCU), decode every
//! command, encode it, and encode the GCU reply.

use protocol_core::gcu::{Execution, GcuFrames, GcuFraming, HostPacket, MAX_FRAME_LEN, Packet};
use protocol_core::wire::{Deframer, Event};

pub fn probe(input: &[u8], out: &mut [u8]) -> usize {
    let mut deframer = Deframer::<GcuFraming, MAX_FRAME_LEN>::new(GcuFraming::host());
    let mut total = 0;
    deframer.push(input, |event| {
        if let Event::Frame(bytes) = event
            && let Ok(packet) = HostPacket::decode(bytes)
        {
            total += packet.emit(out).unwrap_or(0);
            let reply = packet.answer(GcuFrames::default(), Execution::Success);
            total += reply.emit(out).unwrap_or(0);
        }
    });
    // Replies from a GCU decode too (either direction).
    if let Ok(packet) = Packet::decode(input) {
        total += packet.emit(out).unwrap_or(0);
    }
    total
}
