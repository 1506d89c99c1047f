//! GCU: the package view, host/GCU/either packet decode, parse and emit, the answer to
//! a host package, command and feedback decoding and encoding, `encode::<M>` for every
//! order's type, GPS time conversions, and the deframer for an opaque direction.

use core::hint::black_box;
use protocol_core::Direction;
use protocol_core::gcu::*;
use protocol_core::wire::Writer;

macro_rules! typed {
    ($message:expr, $header:expr, $frames:expr, $out:expr; $($t:ty),* $(,)?) => {$(
        if let Some(m) = $message.get::<$t>() {
            black_box(encode(&m, $header, $frames, $out));
        }
    )*};
}

pub fn exercise(input: &[u8], out: &mut [u8]) {
    let f = Frame::new_unchecked(input);
    black_box((
        f.check_len(),
        f.direction(),
        f.total_len(),
        f.version(),
        f.main(),
        f.sub(),
    ));
    black_box((
        f.id(),
        f.payload_len(),
        f.payload(),
        f.checksum(),
        f.compute_checksum(),
    ));
    black_box((f.main_ref(), f.sub_ref(), f.payload_ref(), f.verify()));
    if let Ok(f) = Frame::new_checked(input) {
        black_box((
            Packet::parse(&f),
            HostPacket::parse(&f),
            GcuPacket::parse(&f),
        ));
    }

    let mut fm = Frame::new_unchecked(&mut *out);
    let b = black_box(0u8);
    let direction = black_box(Direction::FromGimbal);
    fm.set_start(direction, u16::from(b));
    fm.set_version(b);
    fm.set_id(b);
    black_box((fm.main_mut().len(), fm.sub_mut().len()));
    black_box(fm.payload_mut());
    fm.fill_checksum();
    black_box(fm.into_inner());
    black_box((sync_of(direction), direction_of([b, b])));

    let m = Message::decode(b, input);
    black_box((m.id(), m.order(), m.name(), m.payload_len()));
    black_box(m.encode(&mut Writer::new(&mut *out)));
    let fb = Feedback::decode(b, input);
    black_box((
        fb.id(),
        fb.payload_len(),
        fb.encode(&mut Writer::new(&mut *out)),
    ));

    black_box(Packet::decode(input).map(|p| (p.buffer_len(), p.emit(&mut *out), p.order())));
    black_box(GcuPacket::decode(input).map(|p| (p.buffer_len(), p.emit(&mut *out))));
    if let Ok(p) = HostPacket::decode(input) {
        black_box((p.buffer_len(), p.emit(&mut *out)));
        let answer = p.answer(
            black_box(GcuFrames::default()),
            black_box(Execution::Success),
        );
        black_box(answer.emit(&mut *out));
        black_box(p.frames.main.carrier_yaw_0_36000_cdeg());
        let (header, frames) = (&p.header, &p.frames);
        typed!(p.message, header, frames, &mut *out;
        Null, Calibration, Neutral, Fpv, HeadLock, HeadFollow, Orthoview, EulerAngle,
        GeoTarget, GazeLock, Track, ClickToAim, ExternalTrack, Shutter, Record, ZoomIn,
        ZoomOut, ZoomStop, ZoomTo, Focus, Palette, NightVision, Osd, PictureInPicture,
        Lighting, Ranging        );
    }

    let ms = black_box(0u64);
    let leap = black_box(DEFAULT_LEAP_SECONDS);
    black_box(GpsTime::from_unix_ms(ms, leap).map(|t| t.to_unix_ms(leap)));

    let framing = GcuFraming::new(black_box(Direction::ToGimbal));
    crate::wire::deframe::<_, MAX_FRAME_LEN>(framing, input);
}
