//! Viewlink: deframe, decode every frame id, encode (and the TCP envelope).

use protocol_core::viewlink::tcp::{self, Envelope, TcpFraming};
use protocol_core::viewlink::{MAX_FRAME_LEN, Packet, ViewlinkFraming};
use protocol_core::wire::{Deframer, Event};

pub fn probe(input: &[u8], out: &mut [u8]) -> usize {
    let mut deframer = Deframer::<ViewlinkFraming, MAX_FRAME_LEN>::new(ViewlinkFraming::new());
    let mut total = 0;
    deframer.push(input, |event| {
        if let Event::Frame(bytes) = event
            && let Ok(packet) = Packet::decode(bytes)
        {
            total += packet.emit(out).unwrap_or(0);
        }
    });
    let mut tcp = Deframer::<TcpFraming, { tcp::MAX_FRAME_LEN }>::new(TcpFraming);
    tcp.push(input, |event| {
        if let Event::Frame(bytes) = event
            && let Ok(env) = Envelope::decode(bytes)
        {
            total += env.emit(out).unwrap_or(0);
        }
    });
    total
}
