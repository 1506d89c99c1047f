//! Viewlink: the serial frame view (either sync order), packet decode/parse/emit,
//! message decoding and encoding, `encode::<M>` for every frame id's type, blocks, the
//! frame counter, the TCP envelope (view, decode/parse/emit, serial body), and the
//! deframers of both.

use core::hint::black_box;
use protocol_core::viewlink::tcp::{self, Envelope, TcpFrame, TcpFraming};
use protocol_core::viewlink::*;
use protocol_core::wire::Writer;

macro_rules! typed {
    ($message:expr, $header:expr, $out:expr; $($t:ty),* $(,)?) => {$(
        if let Some(m) = $message.get::<$t>() {
            black_box(encode(&m, $header, $out));
            black_box(m.to_bytes(&mut *$out));
            black_box(<$t as Block>::from_bytes($out));
            black_box(read_block::<$t>($out));
        }
    )*};
}

pub fn exercise(input: &[u8], out: &mut [u8]) {
    let f = Frame::new_unchecked(input);
    black_box((
        f.check_len(),
        f.sync_order(),
        f.len_field(),
        f.body_len(),
        f.counter(),
    ));
    black_box((
        f.total_len(),
        f.id(),
        f.payload_len(),
        f.payload(),
        f.payload_ref(),
    ));
    black_box((
        f.checksum(),
        f.compute_checksum(),
        f.verify(),
        SyncOrder::of(input),
    ));
    if let Ok(f) = Frame::new_checked(input) {
        black_box(Packet::parse(&f));
    }

    let mut fm = Frame::new_unchecked(&mut *out);
    let b = black_box(0u8);
    fm.set_sync_order(black_box(SyncOrder::Swapped));
    fm.set_len(b, b);
    fm.set_id(b);
    black_box(fm.payload_mut());
    fm.fill_checksum();
    black_box(fm.into_inner());

    let mut counter = black_box(FrameCounter::new());
    black_box((counter.next_value(), counter.next_header(), len_byte(b, b)));

    if let Ok(m) = Message::decode(b, input) {
        black_box((m.id(), m.name(), m.payload_len()));
        black_box(m.encode(&mut Writer::new(&mut *out)));
    }
    if let Ok(p) = Packet::decode(input) {
        black_box((p.buffer_len(), p.emit(&mut *out)));
        let header = &p.header;
        typed!(p.message, header, &mut *out;
        Control, ControlTgcc, A1, C1, E1, S1, RareControl, RareControlTgcc, A2, C2, E2,
        S2, U, V, Status, StatusOsd, RareStatus, M, AiTargets, Klv, Handshake,
        Heartbeat, Ack, D1, B1, F1, T1, T2, F2, B2, D2, Transparent, SdQuery,
        SdFeedback, IpQuery, IpAddress, IpFeedback        );
    }

    let t = TcpFrame::new_unchecked(input);
    black_box((
        t.check_len(),
        t.body_len(),
        t.total_len(),
        t.body(),
        t.body_ref(),
    ));
    black_box((t.checksum(), t.compute_checksum(), t.verify()));
    if let Ok(t) = TcpFrame::new_checked(input) {
        black_box(Envelope::parse(&t));
        black_box(t.into_inner());
    }
    if let Ok(env) = Envelope::decode(input) {
        black_box((env.buffer_len(), env.emit(&mut *out)));
        black_box(env.serial().map(|p| p.emit(&mut *out)));
    }
    black_box(Envelope { body: input }.emit(&mut *out));

    crate::wire::deframe::<_, MAX_FRAME_LEN>(black_box(ViewlinkFraming::new()), input);
    crate::wire::deframe::<_, { tcp::MAX_FRAME_LEN }>(TcpFraming, input);
}
