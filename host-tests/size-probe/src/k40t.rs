//! K40T: deframe, decode every message kind, encode.

use protocol_core::k40t::{K40tFraming, MAX_FRAME_LEN, Packet};
use protocol_core::wire::{Deframer, Event};

pub fn probe(input: &[u8], out: &mut [u8]) -> usize {
    let mut deframer = Deframer::<K40tFraming, MAX_FRAME_LEN>::new(K40tFraming::any());
    let mut total = 0;
    deframer.push(input, |event| {
        if let Event::Frame(bytes) = event
            && let Ok(packet) = Packet::decode(bytes)
        {
            total += packet.emit(out).unwrap_or(0);
        }
    });
    total
}
