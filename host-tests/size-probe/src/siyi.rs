//! SIYI: deframe, decode every message in both directions, encode.

use protocol_core::Direction;
use protocol_core::siyi::{DEFAULT_MAX_FRAME_LEN, Packet, SiyiFraming};
use protocol_core::wire::{Deframer, Event};

pub fn probe(input: &[u8], out: &mut [u8]) -> usize {
    let mut deframer = Deframer::<SiyiFraming, DEFAULT_MAX_FRAME_LEN>::new(SiyiFraming::default());
    let mut total = 0;
    deframer.push(input, |event| {
        if let Event::Frame(bytes) = event {
            for direction in [Direction::ToGimbal, Direction::FromGimbal] {
                if let Ok(packet) = Packet::decode(bytes, direction) {
                    total += packet.emit(out).unwrap_or(0);
                }
            }
            if let Ok(packet) = Packet::decode_auto(bytes) {
                total += packet.emit(out).unwrap_or(0);
            }
        }
    });
    total
}
