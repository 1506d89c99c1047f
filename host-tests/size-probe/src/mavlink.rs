//! MAVLink 2: deframe (MAVLink 1 skipped), decode every message of the dialect, encode.

use protocol_core::mavlink::{MAX_FRAME_LEN, MavlinkFraming, Packet};
use protocol_core::wire::{Deframer, Event};

pub fn probe(input: &[u8], out: &mut [u8]) -> usize {
    let mut deframer = Deframer::<MavlinkFraming, MAX_FRAME_LEN>::new(MavlinkFraming::new());
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
