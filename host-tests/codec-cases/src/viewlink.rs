//! Viewlink codec cases.
//!
//! Frames are built here with the document's checksum rule (XOR of LEN through the
//! last data byte), independently of the codec; the expected messages are written from
//! the document's tables ([`layouts`]) and from the seed vectors' documented fields.

mod layouts;

use crate::{Failure, Outcome};
use layouts::LAYOUTS;
use protocol_core::Error;
use protocol_core::viewlink::tcp::{Envelope, TcpFraming};
use protocol_core::viewlink::*;
use protocol_core::wire::{Deframer, Event, Scanned, Scanner};

type Buf = heapless::Vec<u8, 72>;

/// A frame as the document builds it: sync, LEN (body length + counter), id, data, XOR.
fn frame_with(sync: [u8; 3], id: u8, counter: u8, data: &[u8]) -> Buf {
    let mut f = Buf::new();
    let _ = f.extend_from_slice(&sync);
    let _ = f.push((data.len() as u8 + 3) | (counter << 6));
    let _ = f.push(id);
    let _ = f.extend_from_slice(data);
    let cs = f[3..].iter().fold(0u8, |a, b| a ^ b);
    let _ = f.push(cs);
    f
}

fn frame(id: u8, counter: u8, data: &[u8]) -> Buf {
    frame_with([0x55, 0xAA, 0xDC], id, counter, data)
}

fn emit(p: &Packet<'_>) -> Result<Buf, Failure> {
    let mut out = [0u8; MAX_FRAME_LEN];
    let n = check!(p.emit(&mut out));
    let mut b = Buf::new();
    let _ = b.extend_from_slice(&out[..n]);
    Ok(b)
}

fn fail(what: &'static str, detail: core::fmt::Arguments<'_>) -> Failure {
    Failure::new(file!(), line!(), what, detail)
}

// ------------------------------------------------------------------ seed vectors

fn control(a1: A1, c1: C1, e1: E1) -> Message<'static> {
    Message::Control(Control { a1, c1, e1 })
}

fn speed(yaw: i16, pitch: i16) -> A1 {
    A1::ManualSpeed(ManualSpeed {
        yaw_cdeg_s: yaw,
        pitch_cdeg_s: pitch,
        reserved: [0; 4],
    })
}

fn c1(sensor: Sensor, zoom_speed: u8, operation: OperationCommand) -> C1 {
    C1 {
        sensor,
        zoom_speed,
        operation,
        lrf: LrfCommand::NoAction,
    }
}

/// Optical command with the servo left unchanged (the examples of 4.2, 4.4, 4.5).
fn optics(sensor: Sensor, zoom_speed: u8, operation: OperationCommand) -> Message<'static> {
    control(
        A1::plain(ServoCommand::NoChange),
        c1(sensor, zoom_speed, operation),
        E1::default(),
    )
}

fn rare(c2: C2, e2: E2) -> Message<'static> {
    Message::RareControl(RareControl {
        a2: A2::default(),
        c2,
        e2,
    })
}

/// The documented fields of every serial seed vector (from each vector's `decoded`
/// object and the document's description of the example).
fn vector_message(name: &str) -> Option<(SyncOrder, Message<'static>)> {
    use OperationCommand as Op;
    let none = C1::default();
    let std = SyncOrder::Standard;
    let m = match name {
        "Gimbal movement: Left" => control(speed(-2000, 0), none, E1::default()),
        "Gimbal movement: Right" => control(speed(2000, 0), none, E1::default()),
        "Gimbal movement: Up" => control(speed(0, 2000), none, E1::default()),
        "Gimbal movement: Down" => control(speed(0, -2000), none, E1::default()),
        "Gimbal movement: Stop" => control(speed(0, 0), none, E1::default()),
        "Gimbal movement: Angle control" => control(
            A1::AbsoluteAngle(AbsoluteAngle {
                yaw_bam16: 16380,
                pitch_bam16: 16380,
                reserved: [0; 4],
            }),
            none,
            E1::default(),
        ),
        "Gimbal movement: Recenter" => control(A1::plain(ServoCommand::Home), none, E1::default()),
        "Gimbal movement: Enable follow yaw" => {
            control(A1::plain(ServoCommand::FollowYaw), none, E1::default())
        }
        "Gimbal movement: Disable follow yaw" => control(
            A1::plain(ServoCommand::FollowYawDisable),
            none,
            E1::default(),
        ),
        "Gimbal movement: Motor ON" => control(
            A1::MotorOnOff(MotorOnOff {
                switch: MotorSwitch::On,
                reserved: [0; 6],
            }),
            none,
            E1::default(),
        ),
        "Gimbal movement: Motor OFF" => control(
            A1::MotorOnOff(MotorOnOff {
                switch: MotorSwitch::Off,
                reserved: [0; 6],
            }),
            none,
            E1::default(),
        ),
        "Sensor Control: Zoom in" => optics(Sensor::NoAction, 7, Op::ZoomIn),
        "Sensor Control: Zoom out" => optics(Sensor::NoAction, 7, Op::ZoomOut),
        "Sensor Control: Stop zoom" => optics(Sensor::NoAction, 0, Op::NoAction),
        "Sensor Control: Directly zoom to 20x times" => rare(
            C2::SetEoZoom(Zoom { zoom_x10: 200 }),
            E2::plain(TrackingCommand2::NoAction),
        ),
        "Sensor Control: Switch pic and rec modes" => {
            optics(Sensor::NoAction, 2, Op::TogglePictureRecord)
        }
        "Sensor Control: Take picture" => optics(Sensor::NoAction, 2, Op::TakePicture),
        "Sensor Control: Start record" => optics(Sensor::NoAction, 2, Op::StartRecord),
        "Sensor Control: Stop record" => optics(Sensor::NoAction, 2, Op::StopRecord),
        "With tracking function: Start tracking" => control(
            A1::plain(ServoCommand::Tracking),
            none,
            E1::new(TrackingSource::NoAction, TrackingCommand::Start),
        ),
        "With tracking function: Stop tracking" => control(
            speed(0, 0),
            none,
            E1::new(TrackingSource::Eo1, TrackingCommand::Stop),
        ),
        "With tracking function: Point to track" => rare(
            C2::plain(C2Command::NoAction),
            E2::TrackPoint(Point {
                x_px: -120,
                y_px: 280,
            }),
        ),
        "With digital zoom (D Zoom): IR Dzoom+" => optics(Sensor::NoAction, 2, Op::IrDzoomIn),
        "With digital zoom (D Zoom): IR Dzoom-" => optics(Sensor::NoAction, 2, Op::IrDzoomOut),
        "With digital zoom (D Zoom): EO Dzoom ON" => rare(
            C2::plain(C2Command::EoDzoomOn),
            E2::plain(TrackingCommand2::NoAction),
        ),
        "With digital zoom (D Zoom): EO Dzoom OFF" => rare(
            C2::plain(C2Command::EoDzoomOff),
            E2::plain(TrackingCommand2::NoAction),
        ),
        "IR thermal camera: EO + IR White hot" => optics(Sensor::Eo1IrPip, 0, Op::IrWhiteHot),
        "IR thermal camera: EO + IR Black hot" => optics(Sensor::Eo1IrPip, 0, Op::IrBlackHot),
        "IR thermal camera: EO + IR Pseudo color" => optics(Sensor::Eo1IrPip, 0, Op::IrRainbow),
        "ACK feedback (gimbal ack of received frame 0x1A)" => {
            return Some((SyncOrder::Swapped, Message::Ack(Ack { acked_id: 0x1A })));
        }
        "AI identify information output open (E2 0x20)" => {
            Message::E2(E2::plain(TrackingCommand2::IdentifyOn))
        }
        "AI identify information output close (E2 0x21)" => {
            Message::E2(E2::plain(TrackingCommand2::IdentifyOff))
        }
        _ => return None,
    };
    Some((std, m))
}

/// Every serial seed vector decodes to its documented fields (counter 0) and
/// re-encodes byte for byte; the TCP vector decodes to its VISCA body.
fn seed_vectors_decode_to_documented_fields() -> Outcome {
    let mut serial = 0;
    let mut tcp = 0;
    for v in crate::vectors("Viewlink") {
        ensure!(v.verified, "{} is not verified", v.name);
        if v.bytes.first() == Some(&0xEB) {
            let env = check!(Envelope::decode(v.bytes));
            ensure_eq!(env.body, &[0x81, 0x01, 0x04, 0x07, 0x27, 0xFF][..]);
            ensure!(env.serial().is_err());
            let mut out = [0u8; 32];
            let n = check!(env.emit(&mut out));
            ensure_eq!(&out[..n], v.bytes);
            tcp += 1;
            continue;
        }
        let Some((header, expected)) = vector_message(v.name) else {
            return Err(fail(
                "vector",
                format_args!("no expectation for {}", v.name),
            ));
        };
        let p = check!(Packet::decode(v.bytes));
        ensure_eq!((v.name, p.header.sync), (v.name, header));
        ensure_eq!((v.name, p.header.counter), (v.name, 0));
        ensure_eq!((v.name, p.message), (v.name, expected));
        ensure_eq!(p.buffer_len(), v.bytes.len());
        let out = emit(&Packet {
            header: Header {
                sync: header,
                counter: 0,
            },
            message: expected,
        })?;
        ensure_eq!((v.name, &out[..]), (v.name, v.bytes));
        serial += 1;
    }
    ensure_eq!((serial, tcp), (32, 1));
    Ok(())
}

/// The printed frames with a spurious or missing byte (`doc_bytes`) are not frames: the
/// byte at the checksum position LEN gives is not the checksum. The deframer rejects
/// each, discards it, and finds the intact frame that follows it.
fn printed_errata_are_rejected_then_resynchronised() -> Outcome {
    let mut checked = 0;
    let next = frame(0x10, 0, &[0x00]);
    for v in crate::vectors("Viewlink") {
        let Some(doc) = v.doc_bytes.filter(|d| *d != v.bytes) else {
            continue;
        };
        ensure!(
            Packet::decode(doc).is_err(),
            "{} decoded as printed",
            v.name
        );
        let mut stream = heapless::Vec::<u8, 128>::new();
        let _ = stream.extend_from_slice(doc);
        let _ = stream.extend_from_slice(&next);
        let mut d = Deframer::<ViewlinkFraming, MAX_FRAME_LEN>::new(ViewlinkFraming::new());
        let mut frames = heapless::Vec::<Buf, 4>::new();
        let mut rejected = 0;
        d.push(&stream, |e| match e {
            Event::Frame(f) => {
                let mut b = Buf::new();
                let _ = b.extend_from_slice(f);
                let _ = frames.push(b);
            }
            Event::Rejected { .. } | Event::Skipped(_) => rejected += 1,
        });
        ensure_eq!((v.name, frames.len()), (v.name, 1));
        ensure_eq!(&frames[0][..], &next[..]);
        ensure!(rejected >= 1, "{}: nothing rejected", v.name);
        ensure_eq!(
            (v.name, d.stats().bytes_discarded as usize),
            (v.name, doc.len())
        );
        // The corrected frame differs from the printed one by inserted/removed 0x00s.
        let zeros = |b: &[u8]| b.iter().filter(|&&x| x == 0).count();
        ensure_eq!(
            (v.name, doc.len() as isize - v.bytes.len() as isize),
            (v.name, zeros(doc) as isize - zeros(v.bytes) as isize)
        );
        checked += 1;
    }
    ensure_eq!(checked, 13);
    Ok(())
}

// ------------------------------------------------------------------ layouts

/// Every document layout decodes to its message and the message encodes to the frame,
/// with every counter value.
fn layouts_decode_and_reencode() -> Outcome {
    for (i, l) in LAYOUTS.iter().enumerate() {
        let counter = (i % 4) as u8;
        let bytes = frame(l.id, counter, l.data);
        let p = check!(Packet::decode(&bytes));
        let expected = (l.expected)();
        ensure_eq!((l.id, i, p.message), (l.id, i, expected));
        ensure_eq!(p.header.counter, counter);
        ensure_eq!(p.message.id(), l.id);
        ensure_eq!((l.id, p.message.payload_len()), (l.id, l.data.len()));
        let out = emit(&Packet::new(Header::new(counter), expected))?;
        ensure_eq!((l.id, i, &out[..]), (l.id, i, &bytes[..]));
    }
    Ok(())
}

/// The layouts cover every frame id of the catalogue; the catalogue has the 37 ids of
/// section 2.2 and decodes each to a typed message.
fn layouts_cover_every_frame_id() -> Outcome {
    ensure_eq!(CATALOG.len(), 37);
    let ids = [
        0x30, 0x31, 0x32, 0x33, 0x1A, 0x1C, 0x1E, 0x16, 0x2A, 0x2C, 0x2E, 0x26, 0x01, 0x02, 0x40,
        0x42, 0x41, 0xB1, 0xF3, 0xF4, 0x00, 0x10, 0xAC, 0x1D, 0x1B, 0x1F, 0x17, 0x27, 0x2F, 0x2B,
        0x2D, 0xFF, 0x5D, 0xD5, 0x19, 0x29, 0x92u8,
    ];
    for id in ids {
        ensure!(
            CATALOG.iter().any(|e| e.id == id),
            "{id:#04x} not in CATALOG"
        );
    }
    // The combination layouts are their single blocks, concatenated.
    let data_of = |id: u8| LAYOUTS.iter().find(|l| l.id == id).map(|l| l.data);
    let mut status = heapless::Vec::<u8, 64>::new();
    for part in [
        &layouts::T1_BYTES[..],
        &layouts::F1_BYTES,
        &layouts::B1_BYTES,
        &layouts::D1_BYTES,
    ] {
        let _ = status.extend_from_slice(part);
    }
    ensure_eq!(data_of(0x40), Some(&status[..]));
    ensure_eq!(data_of(0x42), Some(&status[..]));
    let mut rare = heapless::Vec::<u8, 64>::new();
    for part in [
        &layouts::T2_BYTES[..],
        &layouts::F2_BYTES,
        &layouts::B2_BYTES,
        &layouts::D2_BYTES,
    ] {
        let _ = rare.extend_from_slice(part);
    }
    ensure_eq!(data_of(0x41), Some(&rare[..]));
    for (id, part) in [
        (0x17, &layouts::T1_BYTES[..]),
        (0x1F, &layouts::F1_BYTES),
        (0x1B, &layouts::B1_BYTES),
        (0x1D, &layouts::D1_BYTES),
        (0x27, &layouts::T2_BYTES),
        (0x2F, &layouts::F2_BYTES),
        (0x2B, &layouts::B2_BYTES),
        (0x2D, &layouts::D2_BYTES),
    ] {
        ensure_eq!(data_of(id), Some(part));
    }
    for e in CATALOG {
        let Some(l) = LAYOUTS.iter().find(|l| l.id == e.id) else {
            return Err(fail("layout", format_args!("no layout for {:#04x}", e.id)));
        };
        let bytes = frame(l.id, 0, l.data);
        let p = check!(Packet::decode(&bytes));
        ensure!(
            !matches!(p.message, Message::Raw(_)),
            "{:#04x} is Raw",
            e.id
        );
        ensure_eq!(p.message.name(), e.name);
    }
    Ok(())
}

/// Every listed U command decodes to its typed variant (only 0x00 is plain).
fn every_u_command_is_typed() -> Outcome {
    let mut typed = 0;
    for b in 0..=255u8 {
        let cmd = UCommand::from_value(b);
        let mut data = [0u8; 10];
        data[0] = b;
        data[1] = 0x01;
        let bytes = frame(0x01, 0, &data);
        let p = check!(Packet::decode(&bytes));
        let Message::U(u) = p.message else {
            return Err(fail("U", format_args!("{b:#04x}: {:?}", p.message)));
        };
        ensure_eq!(u.command(), cmd);
        let plain = matches!(u, U::Plain { .. });
        let listed = !matches!(cmd, UCommand::Other(_));
        ensure!(
            plain == (!listed || cmd == UCommand::None),
            "{b:#04x}: plain {plain}, listed {listed}"
        );
        typed += usize::from(!plain);
        ensure!(LAYOUTS.iter().any(|l| l.id == 0x01 && l.data[0] == b) || !listed);
    }
    ensure_eq!(typed, 57);
    Ok(())
}

/// Every command with parameters of A1, C2, E2, S1 and the SD feedback has a layout
/// (a typed variant), and the others are plain.
fn command_blocks_type_their_parameters() -> Outcome {
    let cases: [(u8, usize, &[u8]); 4] = [
        (
            0x1A,
            9,
            &[0x00, 0x01, 0x05, 0x09, 0x0B, 0x0D, 0x0E, 0x10, 0x11, 0x1B],
        ),
        (
            0x2C,
            3,
            &[
                0x08, 0x14, 0x1E, 0x4E, 0x50, 0x51, 0x52, 0x53, 0x54, 0x55, 0x56, 0x74, 0x75, 0x76,
            ],
        ),
        (0x2E, 5, &[0x01, 0x0A, 0x0B, 0x0C, 0x1F]),
        (0x16, 14, &[0x01, 0x04, 0x05]),
    ];
    for (id, len, typed) in cases {
        for b in 0..=255u8 {
            let mut data = [0u8; 14];
            data[0] = b;
            let bytes = frame(id, 0, &data[..len]);
            let p = check!(Packet::decode(&bytes));
            let plain = match p.message {
                Message::A1(m) => matches!(m, A1::Plain { .. }),
                Message::C2(m) => matches!(m, C2::Plain { .. }),
                Message::E2(m) => matches!(m, E2::Plain { .. }),
                Message::S1(m) => matches!(m, S1::Plain { .. }),
                other => return Err(fail("block", format_args!("{other:?}"))),
            };
            ensure_eq!((id, b, plain), (id, b, !typed.contains(&b)));
            let out = emit(&p)?;
            ensure_eq!(&out[..], &frame(id, 0, &data[..len])[..]);
        }
    }
    for b in 0..=255u8 {
        let bytes = frame(0xD5, 0, &[b, 1, 2, 3, 4]);
        let p = check!(Packet::decode(&bytes));
        let Message::SdFeedback(f) = p.message else {
            return Err(fail("sd", format_args!("{:?}", p.message)));
        };
        ensure_eq!(matches!(f, SdFeedback::Plain { .. }), !(1..=5).contains(&b));
        ensure_eq!(f.command().value(), b);
    }
    Ok(())
}

/// Every catalogue id, with patterned data of each valid length, decodes (typed) and
/// re-encodes byte for byte; every other length is `BadLength`, never `Truncated` (the
/// frame is complete: found by fuzzing, `fixtures/fuzz/viewlink_decode/`).
fn every_frame_id_round_trips() -> Outcome {
    for e in CATALOG {
        for len in 1..=MAX_PAYLOAD_LEN {
            let mut data = [0u8; MAX_PAYLOAD_LEN];
            for (i, b) in data.iter_mut().enumerate() {
                *b = (i as u8).wrapping_mul(37).wrapping_add(e.id);
            }
            if e.id == 0xB1 {
                // M: the data type must match the length.
                data[0] = match len {
                    8 => 0x04,
                    14 => 0x05,
                    36 => 0x06,
                    42 => 0x07,
                    _ => 0x03,
                };
            }
            let bytes = frame(e.id, (len % 4) as u8, &data[..len]);
            match Packet::decode(&bytes) {
                Ok(p) => {
                    ensure!(!matches!(p.message, Message::Raw(_)));
                    let out = emit(&p)?;
                    ensure_eq!((e.id, len, &out[..]), (e.id, len, &bytes[..]));
                }
                Err(Error::BadLength) => {}
                Err(other) => {
                    return Err(fail(
                        "decode",
                        format_args!("{:#04x}/{len}: {other:?}", e.id),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// M: each of the 256 data-type bytes, with exactly the groups its bits 0 and 1 select.
fn m_every_data_type() -> Outcome {
    for t in 0..=255u8 {
        let mut data = heapless::Vec::<u8, 42>::new();
        let _ = data.push(t);
        let _ = data.extend_from_slice(&[9, 8, 7, 6, 5, 4, 3]);
        if t & 1 != 0 {
            let _ = data.extend_from_slice(&layouts::M_ATTITUDE_BYTES);
        }
        if t & 2 != 0 {
            let _ = data.extend_from_slice(&layouts::M_GPS_BYTES);
        }
        let bytes = frame(0xB1, 0, &data);
        let p = check!(Packet::decode(&bytes));
        let Message::M(m) = p.message else {
            return Err(fail("M", format_args!("{:?}", p.message)));
        };
        ensure_eq!(m.data_type(), t);
        ensure_eq!(m.reserved, [9, 8, 7, 6, 5, 4, 3]);
        ensure_eq!(m.attitude, (t & 1 != 0).then(layouts::m_attitude));
        ensure_eq!(m.gps, (t & 2 != 0).then(layouts::m_gps));
        ensure_eq!(p.message.payload_len(), data.len());
        ensure_eq!(&emit(&p)?[..], &bytes[..]);
        // A group too many or too few is a length error.
        let mut longer = heapless::Vec::<u8, 43>::new();
        let _ = longer.extend_from_slice(&data);
        let _ = longer.push(0);
        {
            ensure_eq!(
                Packet::decode(&frame(0xB1, 0, &longer)).err(),
                Some(Error::BadLength)
            );
        }
        ensure!(Packet::decode(&frame(0xB1, 0, &data[..data.len() - 1])).is_err());
    }
    // The constructor sets the gyro bit, as ArduPilot's 0x07.
    ensure_eq!(
        M::new(Some(layouts::m_attitude()), Some(layouts::m_gps())).data_type(),
        0x07
    );
    ensure_eq!(M::new(None, None).data_type(), 0x04);
    Ok(())
}

/// Every frame-counter value is decoded, kept, re-encoded and covered by the checksum.
fn every_counter_value() -> Outcome {
    let data = [0x0B, 0x3F, 0xFC, 0x3F, 0xFC, 0, 0, 0, 0];
    for counter in 0..4u8 {
        let bytes = frame(0x1A, counter, &data);
        ensure_eq!(bytes[3], 0x0C | (counter << 6));
        let f = check!(Frame::new_checked(&bytes[..]));
        ensure_eq!((f.counter(), f.body_len()), (counter, 12));
        let p = check!(Packet::decode(&bytes));
        ensure_eq!(p.header.counter, counter);
        ensure_eq!(&emit(&p)?[..], &bytes[..]);
        // The counter bits are covered by the checksum.
        let mut other = bytes.clone();
        other[3] ^= 0x40;
        ensure!(matches!(
            Packet::decode(&other),
            Err(Error::BadChecksum { .. })
        ));
    }
    let p = Packet::new(Header::new(4), Message::Heartbeat(Heartbeat { value: 0 }));
    ensure_eq!(p.emit(&mut [0u8; 16]), Err(Error::OutOfRange));
    let mut c = FrameCounter::new();
    let seq: [u8; 6] = core::array::from_fn(|_| c.next_value());
    ensure_eq!(seq, [1, 2, 3, 0, 1, 2]);
    ensure_eq!(len_byte(12, 3), 0xCC);
    Ok(())
}

/// `AA 55 DC` frames decode (sync order kept) and re-encode; the default framing
/// does not take them, the swapped one does.
fn swapped_sync_order() -> Outcome {
    let bytes = frame_with([0xAA, 0x55, 0xDC], 0x40, 2, &[0u8; 41]);
    let p = check!(Packet::decode(&bytes));
    ensure_eq!(p.header.sync, SyncOrder::Swapped);
    ensure_eq!(&emit(&p)?[..], &bytes[..]);
    let count = |framing: ViewlinkFraming| {
        let mut d = Deframer::<ViewlinkFraming, MAX_FRAME_LEN>::new(framing);
        let mut n = 0;
        d.push(&bytes, |e| n += usize::from(matches!(e, Event::Frame(_))));
        n
    };
    ensure_eq!(count(ViewlinkFraming::new()), 0);
    ensure_eq!(count(ViewlinkFraming::swapped()), 1);
    ensure_eq!(SyncOrder::Swapped.bytes(), SYNC_SWAPPED);
    Ok(())
}

// ------------------------------------------------------------------ errors

/// Malformed input is an error value, never a panic: every prefix, every bit flip, bad
/// sync, impossible lengths, a too-small output buffer.
fn malformed_frames_are_errors() -> Outcome {
    let good = frame(0x40, 1, &[0x5A; 41]);
    ensure!(Packet::decode(&good).is_ok());
    for n in 0..good.len() {
        ensure!(Packet::decode(&good[..n]).is_err(), "prefix {n} accepted");
    }
    ensure_eq!(Packet::decode(&good[1..]).err(), Some(Error::BadSync));
    ensure_eq!(Packet::decode(&[]).err(), Some(Error::Truncated));
    for i in 0..good.len() {
        for bit in 0..8 {
            let mut bad = good.clone();
            bad[i] ^= 1 << bit;
            ensure!(Packet::decode(&bad).is_err(), "flip {i}.{bit} accepted");
        }
    }
    for len in 0..4u8 {
        let f = [0x55, 0xAA, 0xDC, len, 0x00, 0x00, 0x00];
        ensure_eq!(Packet::decode(&f).err(), Some(Error::BadLength));
    }
    let p = check!(Packet::decode(&good));
    ensure_eq!(p.emit(&mut [0u8; 46]), Err(Error::BufferTooSmall));
    ensure_eq!(p.buffer_len(), good.len());
    ensure_eq!(good.len(), 47);
    // Too much data for one frame.
    let big = [0u8; 61];
    let raw = Packet::new(
        Header::new(0),
        Message::Raw(Raw {
            id: 0x77,
            payload: &big,
        }),
    );
    ensure_eq!(raw.emit(&mut [0u8; 80]), Err(Error::BadLength));
    let empty = Packet::new(
        Header::new(0),
        Message::Raw(Raw {
            id: 0x77,
            payload: &[],
        }),
    );
    ensure_eq!(empty.emit(&mut [0u8; 80]), Err(Error::BadLength));
    Ok(())
}

/// A known id with the wrong amount of data is a length error.
fn wrong_length_known_ids() -> Outcome {
    for e in CATALOG {
        let Some(l) = LAYOUTS.iter().find(|l| l.id == e.id) else {
            continue;
        };
        let fixed = !matches!(e.id, 0x02 | 0xB1 | 0xF3 | 0xF4 | 0xFF);
        if !fixed {
            continue;
        }
        let mut longer = heapless::Vec::<u8, 64>::new();
        let _ = longer.extend_from_slice(l.data);
        let _ = longer.push(0);
        ensure!(
            Packet::decode(&frame(e.id, 0, &longer)).is_err(),
            "{:#04x} + 1 accepted",
            e.id
        );
        if l.data.len() > 1 {
            ensure!(
                Packet::decode(&frame(e.id, 0, &l.data[..l.data.len() - 1])).is_err(),
                "{:#04x} - 1 accepted",
                e.id
            );
        }
    }
    // Variable blocks: V over 22 parameter bytes, AI not a multiple of 13, more than
    // four targets, KLV over 57 data bytes.
    ensure_eq!(
        Packet::decode(&frame(0x02, 0, &[0xD0; 24])).err(),
        Some(Error::BadLength)
    );
    ensure_eq!(
        Packet::decode(&frame(0xF3, 0, &[0; 8 + 12])).err(),
        Some(Error::BadLength)
    );
    ensure!(Packet::decode(&frame(0xF3, 0, &[0; 8 + 4 * 13])).is_ok());
    ensure_eq!(
        Packet::decode(&frame(0xF4, 0, &[0; 3 + 57])).map(|p| p.message.payload_len()),
        Ok(60)
    );
    Ok(())
}

/// Unknown ids decode to Raw and re-encode unchanged.
fn unknown_ids_are_raw() -> Outcome {
    let mut unknown = 0;
    for id in 0..=255u8 {
        if CATALOG.iter().any(|e| e.id == id) {
            continue;
        }
        let data = [id, 1, 2];
        let bytes = frame(id, 3, &data);
        let p = check!(Packet::decode(&bytes));
        ensure_eq!(p.message, Message::Raw(Raw { id, payload: &data }));
        ensure_eq!(p.message.name(), "Raw");
        ensure_eq!(&emit(&p)?[..], &bytes[..]);
        unknown += 1;
    }
    ensure_eq!(unknown, 256 - 37);
    Ok(())
}

/// A stream of every layout frame, with garbage, false syncs and corrupted frames, fed
/// in chunks of several sizes, yields every intact frame in order.
fn deframer_recovers_every_frame() -> Outcome {
    for chunk in [1usize, 5, 64, 4096] {
        let mut stream = heapless::Vec::<u8, 16384>::new();
        for (i, l) in LAYOUTS.iter().enumerate() {
            let f = frame(l.id, (i % 4) as u8, l.data);
            match i % 4 {
                0 => {
                    let _ = stream.extend_from_slice(&[0x00, 0x55, 0xAA, 0x55, 0xAA, 0xDC]);
                }
                1 => {
                    let mut bad = f.clone();
                    let last = bad.len() - 1;
                    bad[last] ^= 0x01;
                    let _ = stream.extend_from_slice(&bad);
                }
                _ => {}
            }
            ensure!(stream.extend_from_slice(&f).is_ok());
        }
        let mut d = Deframer::<ViewlinkFraming, MAX_FRAME_LEN>::new(ViewlinkFraming::new());
        let mut next = 0usize;
        let mut ok = true;
        for part in stream.chunks(chunk) {
            d.push(part, |ev| {
                if let Event::Frame(f) = ev {
                    let l = &LAYOUTS[next.min(LAYOUTS.len() - 1)];
                    ok &= f == &frame(l.id, (next % 4) as u8, l.data)[..];
                    next += 1;
                }
            });
        }
        d.flush(|ev| {
            if let Event::Frame(_) = ev {
                next += 1;
            }
        });
        ensure!(ok, "frames out of order or altered (chunk {chunk})");
        ensure_eq!(next, LAYOUTS.len());
        ensure!(d.stats().checksum_errors as usize >= LAYOUTS.len() / 4);
    }
    Ok(())
}

// ------------------------------------------------------------------ fields

/// Bit-field accessors and constructors follow the document.
fn bit_fields() -> Outcome {
    // C1 of the document's zoom-in example, and every field at its extreme.
    ensure_eq!(
        C1::from_u16(0x0278),
        c1(Sensor::NoAction, 7, OperationCommand::ZoomIn)
    );
    let all = C1 {
        sensor: Sensor::Ir2_52mm,
        zoom_speed: 7,
        operation: OperationCommand::Other(0x7F),
        lrf: LrfCommand::Other(7),
    };
    ensure_eq!(all.to_u16(), Ok(0xFFFF));
    ensure_eq!(C1::from_u16(0xFFFF), all);
    ensure_eq!(
        C1 {
            lrf: LrfCommand::Single,
            ..C1::default()
        }
        .to_u16(),
        Ok(0x2000)
    );
    // B1 roll: 12 bits, 0 at -90°.
    let b = b1_of(&[0x5F, 0xFF, 0, 0, 0, 0])?;
    ensure_eq!(b.servo, ServoCommand::AzimuthScan);
    ensure_eq!(b.roll_raw12, 0xFFF);
    ensure_eq!(b.roll_cdeg(), 9000);
    ensure_eq!(B1::roll_raw_from_cdeg(0), 2048);
    ensure_eq!(B1::roll_raw_from_cdeg(-9000), 0);
    ensure_eq!(B1::roll_raw_from_cdeg(12000), 4095);
    ensure_eq!(
        B1 {
            roll_raw12: 0,
            ..B1::default()
        }
        .roll_cdeg(),
        -9000
    );
    // Azimuth scan parameter 3.
    let scan = AzimuthScan {
        yaw_speed: 50,
        pitch_speed: -50,
        range: 0xC012,
        angle_bam16: 0,
    };
    ensure!(scan.is_circle() && scan.earth_frame());
    ensure_eq!(scan.tilt_gain(), 0x12);
    ensure_eq!(
        (scan.yaw_speed_cdeg_s(), scan.pitch_speed_cdeg_s()),
        (500, -500)
    );
    let half = AzimuthScan {
        range: 0x1000,
        ..scan
    };
    ensure!(!half.is_circle() && !half.earth_frame());
    ensure_eq!(half.yaw_speed_cdeg_s(), 50);
    // Dates and times.
    let d = check!(Date::new(2026, 3, 15));
    ensure_eq!(d.0, 0x799A);
    ensure_eq!((d.year(), d.month(), d.day()), (2026, 3, 15));
    ensure_eq!(check!(TimeCs::new(12, 34, 56, 78)).0, 4_529_678);
    // Packed bytes.
    ensure_eq!((ChannelPair(0x21).high(), ChannelPair(0x21).low()), (2, 1));
    ensure_eq!(ChannelPair::new(15, 0), Ok(ChannelPair(0xF0)));
    ensure_eq!(ChannelPair::new(16, 0), Err(Error::OutOfRange));
    let osd = OsdWord(0x8105);
    ensure_eq!(osd.osd1(), OsdFlags(0x05));
    ensure_eq!(osd.osd2(), OsdTypeFlags(0x81));
    let hide_all_angles = OsdFlags::default()
        .with_hide_all(true)
        .with_hide_angles(true);
    ensure_eq!(hide_all_angles, OsdFlags(0x05));
    ensure!(osd.osd1().contains(hide_all_angles.0));
    ensure!(osd.osd1().hide_all() && osd.osd1().hide_angles());
    ensure!(!osd.osd1().hide_cross());
    ensure!(
        !osd.osd1()
            .contains(OsdFlags::default().with_hide_cross(true).0)
    );
    // Flag bytes: the named bits, and the others kept.
    let sd = SdStateFlags(0x09);
    ensure!(sd.inserted() && sd.formatted() && !sd.full());
    ensure_eq!(
        SdStateFlags::default()
            .with_inserted(true)
            .with_formatted(true),
        sd
    );
    ensure_eq!(PrmInvert(0xFF).reserved_bits(), 0x03);
    ensure_eq!(YpmzInvert(0xFF).reserved_bits(), 0x00);
    let calc = TargetCalcFlags(0x51);
    ensure!(calc.osd_object_gps() && calc.serial_output());
    ensure_eq!(calc.output_format(), 2);
    let power = PowerControl(0x4009);
    ensure_eq!(
        (power.eo1(), power.ir(), power.eo2(), power.laser()),
        (
            PowerSwitch::On,
            PowerSwitch::Off,
            PowerSwitch::NoChange,
            PowerSwitch::On
        )
    );
    ensure_eq!(
        PowerControl::new(
            PowerSwitch::On,
            PowerSwitch::Off,
            PowerSwitch::NoChange,
            PowerSwitch::On
        ),
        Ok(power)
    );
    let cal = CalibrationSources(0x0D);
    ensure_eq!(
        (cal.yaw(), cal.pitch()),
        (YawCalibration::Manual, PitchCalibration::FromHeight)
    );
    ensure_eq!(
        CalibrationSources::new(YawCalibration::Manual, PitchCalibration::FromHeight),
        Ok(cal)
    );
    // B2's fault code is the whole byte 0xEE.
    let mut fault = [0u8; 11];
    fault[0] = 0xEE;
    let bytes = frame(0x2B, 0, &fault);
    let p = check!(Packet::decode(&bytes));
    let Message::B2(b2) = p.message else {
        return Err(fail("B2", format_args!("{:?}", p.message)));
    };
    ensure!(b2.is_fault());
    ensure!(!layouts::b2().is_fault());
    // E1 helpers.
    let e = E1::search(TrackingSource::Ir, 3, 17);
    ensure_eq!(
        (e.param1, e.param2, e.command),
        (3, 17, TrackingCommand::Search)
    );
    ensure_eq!(E1::ai_detection(TrackingSource::Eo1, OnOff::On).param2, 1);
    let speed = E1 {
        param2: 10,
        ..E1::new(TrackingSource::Eo1, TrackingCommand::TrackingSpeed)
    };
    ensure_eq!(speed.tracking_speed_5th_dps(), Some(10));
    ensure_eq!(speed.speed_coefficient_x10(), None);
    // KLV payload is the valid part.
    let klv = Klv {
        total_packets: 2,
        packet_index: 0,
        valid_len: 2,
        data: check!(Bytes::new(&[1, 2, 3])),
    };
    ensure_eq!(klv.payload(), &[1, 2]);
    Ok(())
}

fn b1_of(data: &[u8]) -> Result<B1, Failure> {
    let bytes = frame(0x1B, 0, data);
    let p = check!(Packet::decode(&bytes));
    match p.message {
        Message::B1(b) => Ok(b),
        other => Err(fail("B1", format_args!("{other:?}"))),
    }
}

/// Values that do not fit their bits are refused when encoding, never truncated.
fn encode_refuses_values_that_do_not_fit() -> Outcome {
    let mut buf = [0u8; MAX_FRAME_LEN];
    let cases: [Message<'static>; 9] = [
        Message::C1(C1 {
            zoom_speed: 8,
            ..C1::default()
        }),
        Message::C1(C1 {
            operation: OperationCommand::Other(0x80),
            ..C1::default()
        }),
        Message::A2(A2 {
            counter: 4,
            ..A2::default()
        }),
        Message::A2(A2 {
            action: ServoAction::Other(0x20),
            ..A2::default()
        }),
        Message::B1(B1 {
            roll_raw12: 0x1000,
            ..B1::default()
        }),
        Message::B1(B1 {
            servo: ServoCommand::AbsoluteAngle720,
            ..B1::default()
        }),
        Message::F1(F1 {
            state: TrackerState::Other(4),
            ..layouts::f1()
        }),
        Message::D1(D1 {
            lrf_latency_ms: 64,
            ..layouts::d1()
        }),
        Message::V(V::new(
            VCommand::QueryModel,
            VData::Firmware(Text::default()),
        )),
    ];
    for m in cases {
        ensure_eq!(
            (m.name(), Packet::new(Header::new(0), m).emit(&mut buf)),
            (m.name(), Err(Error::OutOfRange))
        );
    }
    let one = [AiTarget::default(); 1];
    ensure!(AiTargets::new(1, 1, 0, &one).is_ok());
    let too_many = [AiTarget::default(); 5];
    ensure_eq!(
        AiTargets::new(5, 2, 0, &too_many).err(),
        Some(Error::OutOfRange)
    );
    Ok(())
}

// ------------------------------------------------------------------ typed messages

/// One payload type of the typed API, with the frame id this test knows it by.
struct Typed {
    id: u8,
    /// Checks the type against a frame of its id (see [`check_typed`]).
    check: fn(&Packet<'_>, &[u8]) -> Outcome,
    /// `message.get::<T>().is_some()`.
    is: fn(&Message<'_>) -> bool,
}

macro_rules! typed {
    ($($id:literal $ty:ty),* $(,)?) => {
        &[$( Typed { id: $id, check: check_typed::<$ty>, is: |m| m.get::<$ty>().is_some() }, )*]
    };
}

/// Every frame id's payload type, as section 2.2 pairs them (0x42 and 0x92 carry the
/// layouts of 0x40 and 0x29 under their own types).
static TYPED: &[Typed] = typed![
    0x30 Control, 0x32 ControlTgcc, 0x1A A1, 0x1C C1, 0x1E E1, 0x16 S1,
    0x31 RareControl, 0x33 RareControlTgcc, 0x2A A2, 0x2C C2, 0x2E E2, 0x26 S2,
    0x01 U, 0x02 V, 0x40 Status, 0x42 StatusOsd, 0x41 RareStatus, 0xB1 M,
    0xF3 AiTargets, 0xF4 Klv, 0x00 Handshake, 0x10 Heartbeat, 0xAC Ack,
    0x1D D1, 0x1B B1, 0x1F F1, 0x17 T1, 0x27 T2, 0x2F F2, 0x2B B2, 0x2D D2,
    0xFF Transparent, 0x5D SdQuery, 0xD5 SdFeedback, 0x19 IpQuery, 0x29 IpAddress,
    0x92 IpFeedback,
];

/// The variable-size payloads and their largest length (V: command and 22 parameter
/// bytes; M: every group; AI: four targets; KLV: 57 data bytes; transparent: a full
/// frame).
const VARIABLE: [(u8, usize); 5] = [(0x02, 23), (0xB1, 42), (0xF3, 60), (0xF4, 60), (0xFF, 60)];

/// `T` against a decoded frame of its id: its id and name are the catalogue's, `get`
/// finds it, the typed `encode` gives the frame's bytes (as the enum path does), and
/// `ENCODED_LEN` is the payload length (the largest one for variable payloads).
fn check_typed<T: MessageData<Protocol = Viewlink> + PartialEq + core::fmt::Debug>(
    p: &Packet<'_>,
    bytes: &[u8],
) -> Outcome {
    ensure_eq!(T::ID, p.message.id());
    let Some(entry) = CATALOG.iter().find(|e| e.id == T::ID) else {
        return Err(fail("catalog", format_args!("{:#04x} not listed", T::ID)));
    };
    ensure_eq!(T::NAME, entry.name);
    let Some(typed) = p.message.get::<T>() else {
        return Err(fail("get", format_args!("{}: {:?}", T::NAME, p.message)));
    };
    ensure_eq!(typed.into_message(), p.message);
    ensure_eq!(T::from_message(&p.message), Some(typed));
    let mut out = [0u8; MAX_FRAME_LEN];
    let n = check!(encode(&typed, &p.header, &mut out));
    ensure_eq!((T::NAME, &out[..n]), (T::NAME, bytes));
    ensure_eq!(&emit(p)?[..], &out[..n]);
    let len = p.message.payload_len();
    match VARIABLE.iter().find(|(id, _)| *id == T::ID) {
        Some(&(_, max)) => {
            ensure_eq!((T::NAME, T::ENCODED_LEN), (T::NAME, max));
            ensure!(len <= max, "{}: {len} > {max}", T::NAME);
        }
        None => ensure_eq!((T::NAME, T::ENCODED_LEN), (T::NAME, len)),
    }
    Ok(())
}

/// Every payload type's `MessageData` matches the catalogue, and on every document
/// layout `get::<T>()` finds exactly the frame id's type, the typed `encode` gives the
/// same bytes as `Packet::emit`, and `ENCODED_LEN` is the encoded length.
fn typed_messages_match_the_catalogue() -> Outcome {
    ensure_eq!(TYPED.len(), CATALOG.len());
    for e in CATALOG {
        ensure_eq!(
            (e.id, TYPED.iter().filter(|t| t.id == e.id).count()),
            (e.id, 1)
        );
    }
    for (i, l) in LAYOUTS.iter().enumerate() {
        let counter = (i % 4) as u8;
        let bytes = frame(l.id, counter, l.data);
        let p = check!(Packet::decode(&bytes));
        let Some(t) = TYPED.iter().find(|t| t.id == l.id) else {
            return Err(fail("typed", format_args!("{:#04x}", l.id)));
        };
        (t.check)(&p, &bytes)?;
        // `get` misses every other type (0x42 is not a Status, 0x92 not an IpAddress).
        let hits = TYPED.iter().filter(|t| (t.is)(&p.message)).count();
        ensure_eq!((l.id, i, hits), (l.id, i, 1));
    }
    // Raw frames are none of the types.
    let raw = frame(0x77, 0, &[1, 2, 3]);
    let p = check!(Packet::decode(&raw));
    ensure!(TYPED.iter().all(|t| !(t.is)(&p.message)));
    // The largest variable payloads are frames of their own.
    let mut v = [0u8; 23];
    v[0] = 0xD0;
    let mut m = [0u8; 42];
    m[0] = 0x07;
    let largest: [(u8, &[u8]); 5] = [
        (0x02, &v),
        (0xB1, &m),
        (0xF3, &[0; 60]),
        (0xF4, &[0; 60]),
        (0xFF, &[0x5A; 60]),
    ];
    for (id, data) in largest {
        let bytes = frame(id, 0, data);
        let p = check!(Packet::decode(&bytes));
        let Some(t) = TYPED.iter().find(|t| t.id == id) else {
            return Err(fail("typed", format_args!("{id:#04x}")));
        };
        (t.check)(&p, &bytes)?;
        ensure_eq!((id, p.message.payload_len()), (id, data.len()));
    }
    Ok(())
}

/// The path a bridge takes: ArduPilot's single blocks decode to their types with
/// `get`, and the replies it sends (0x40 status, 0x02 V) encode from typed values with
/// the counter a sender keeps, to the bytes the enum path gives.
fn bridge_path_with_typed_messages() -> Outcome {
    // Received: A1, C1, E1, C2, E2, M, handshake, U (the frames of ardupilot_interop).
    let a1 = frame(0x1A, 1, &[0x0B, 0x20, 0x00, 0xF0, 0x00, 0, 0, 0, 0]);
    ensure_eq!(
        check!(Packet::decode(&a1)).message.get::<A1>(),
        Some(A1::AbsoluteAngle(AbsoluteAngle {
            yaw_bam16: 0x2000,
            pitch_bam16: -0x1000,
            reserved: [0; 4],
        }))
    );
    let zoom = frame(0x1C, 2, &[0x02, 0x7A]);
    ensure_eq!(
        check!(Packet::decode(&zoom)).message.get::<C1>(),
        Some(C1 {
            sensor: Sensor::Ir,
            ..c1(Sensor::NoAction, 7, OperationCommand::ZoomIn)
        })
    );
    let e1 = frame(0x1E, 3, &[0x02, 0x03, 0x00]);
    ensure_eq!(
        check!(Packet::decode(&e1)).message.get::<E1>(),
        Some(E1::new(TrackingSource::Ir, TrackingCommand::Start))
    );
    let c2 = frame(0x2C, 0, &[0x53, 0x00, 0x64]);
    ensure_eq!(
        check!(Packet::decode(&c2)).message.get::<C2>(),
        Some(C2::SetEoZoom(Zoom { zoom_x10: 100 }))
    );
    let e2 = frame(0x2E, 1, &[0x0B, 0xFE, 0x20, 0x00, 0x87]);
    ensure_eq!(
        check!(Packet::decode(&e2)).message.get::<E2>(),
        Some(E2::RectTopLeft(Point {
            x_px: -480,
            y_px: 135
        }))
    );
    let mut m = [0u8; 42];
    m[0] = 0x07;
    m[8..14].copy_from_slice(&layouts::M_ATTITUDE_BYTES);
    m[14..].copy_from_slice(&layouts::M_GPS_BYTES);
    let m = frame(0xB1, 2, &m);
    let ahrs = check!(Packet::decode(&m)).message.get::<M>();
    ensure_eq!(
        ahrs,
        Some(M::new(Some(layouts::m_attitude()), Some(layouts::m_gps())))
    );
    ensure_eq!(ahrs.and_then(|m| m.attitude), Some(layouts::m_attitude()));
    let hello = frame(0x00, 3, &[0x00]);
    ensure_eq!(
        check!(Packet::decode(&hello)).message.get::<Handshake>(),
        Some(Handshake { value: 0 })
    );
    let query = frame(0x01, 0, &[0xE4, 0, 0, 0, 0, 0, 0, 0, 0, 0]);
    let Some(u) = check!(Packet::decode(&query)).message.get::<U>() else {
        return Err(fail("U", format_args!("not a U")));
    };
    ensure_eq!(u.command(), UCommand::QueryModel);
    ensure_eq!(u.reply_command(), VCommand::QueryModel);
    // A frame of another id is none of these.
    ensure_eq!(check!(Packet::decode(&a1)).message.get::<C1>(), None);
    ensure_eq!(
        check!(Packet::decode(&hello)).message.get::<Heartbeat>(),
        None
    );

    // Sent: the 0x40 status and the V model reply, counters 1 and 2.
    let mut counter = FrameCounter::new();
    let status = Status {
        t1: layouts::t1(),
        f1: layouts::f1(),
        b1: layouts::b1(),
        d1: layouts::d1(),
    };
    let mut out = [0u8; MAX_FRAME_LEN];
    let n = check!(encode(&status, &counter.next_header(), &mut out));
    ensure_eq!(Message::from(status), Message::Status(status));
    let by_enum = emit(&Packet::new(Header::new(1), Message::from(status)))?;
    ensure_eq!(&out[..n], &by_enum[..]);
    ensure_eq!(&out[..5], &[0x55, 0xAA, 0xDC, 0x6C, 0x40]);
    let reply = V::new(u.reply_command(), VData::Model(check!(Text::new("Z40K"))));
    let n = check!(encode(&reply, &counter.next_header(), &mut out));
    let by_enum = emit(&Packet::new(Header::new(2), Message::V(reply)))?;
    ensure_eq!(&out[..n], &by_enum[..]);
    ensure_eq!(&out[5..10], &[0xE4, b'Z', b'4', b'0', b'K']);
    // The same errors as the enum path.
    let no_counter = Header {
        counter: 4,
        ..Header::default()
    };
    ensure_eq!(
        encode(&status, &no_counter, &mut out),
        Err(Error::OutOfRange)
    );
    ensure_eq!(
        encode(&status, &Header::default(), &mut out[..46]),
        Err(Error::BufferTooSmall)
    );
    let too_long = C1 {
        zoom_speed: 8,
        ..C1::default()
    };
    ensure_eq!(
        encode(&too_long, &Header::default(), &mut out),
        Err(Error::OutOfRange)
    );
    Ok(())
}

// ------------------------------------------------------------------ TCP

/// The TCP envelope: decode, encode, checksum, framing.
fn tcp_envelope() -> Outcome {
    let doc = [0xEB, 0x90, 0x06, 0x81, 0x01, 0x04, 0x07, 0x27, 0xFF, 0xB3];
    let env = check!(Envelope::decode(&doc));
    ensure_eq!(env.buffer_len(), doc.len());
    // An envelope around a serial frame.
    let inner = frame(0x1C, 1, &[0x02, 0x78]);
    let wrapped = Envelope { body: &inner };
    let mut out = [0u8; 64];
    let n = check!(wrapped.emit(&mut out));
    ensure_eq!(out[2] as usize, inner.len());
    let sum = inner.iter().fold(0u8, |a, b| a.wrapping_add(*b));
    ensure_eq!(out[n - 1], sum);
    let back = check!(Envelope::decode(&out[..n]));
    let p = check!(back.serial());
    ensure_eq!(
        p.message,
        Message::C1(c1(Sensor::NoAction, 7, OperationCommand::ZoomIn))
    );
    let mut bad = doc;
    bad[9] ^= 1;
    ensure_eq!(
        Envelope::decode(&bad).err(),
        Some(Error::BadChecksum {
            computed: 0xB3,
            received: 0xB2
        })
    );
    ensure_eq!(Envelope::decode(&doc[..9]).err(), Some(Error::Truncated));
    ensure_eq!(Envelope::decode(&doc[1..]).err(), Some(Error::BadSync));
    let mut stream = heapless::Vec::<u8, 64>::new();
    let _ = stream.extend_from_slice(&[0xEB, 0x00]);
    let _ = stream.extend_from_slice(&doc);
    let _ = stream.extend_from_slice(&out[..n]);
    let mut found = 0;
    for item in Scanner::new(TcpFraming, &stream) {
        if let Scanned::Frame { bytes, .. } = item {
            ensure!(Envelope::decode(bytes).is_ok());
            found += 1;
        }
    }
    ensure_eq!(found, 2);
    Ok(())
}

// ------------------------------------------------------------------ ArduPilot

/// Frames built the way ArduPilot's Viewpro driver builds them decode to what it
/// means, and the replies this codec encodes carry each value where the driver reads
/// it (offsets of its parser, relative to the first data byte).
fn ardupilot_interop() -> Outcome {
    // Handshake, U queries, A1 angle/rate/lock, C1, C2 zoom, E1, E2, M (counter 1..).
    let sent: [(u8, &[u8], Message<'static>); 8] = [
        (0x00, &[0x00], Message::Handshake(Handshake { value: 0 })),
        (
            0x01,
            &[0xE4, 0, 0, 0, 0, 0, 0, 0, 0, 0],
            Message::U(U::QueryModel(QueryParams { reserved: [0; 9] })),
        ),
        (
            0x1A,
            &[0x0B, 0x20, 0x00, 0xF0, 0x00, 0, 0, 0, 0],
            Message::A1(A1::AbsoluteAngle(AbsoluteAngle {
                yaw_bam16: 0x2000,
                pitch_bam16: -0x1000,
                reserved: [0; 4],
            })),
        ),
        (
            0x1A,
            &[0x0A, 0, 0, 0, 0, 0, 0, 0, 0],
            Message::A1(A1::plain(ServoCommand::FollowYawDisable)),
        ),
        (
            0x1C,
            &[0x02, 0x7A],
            Message::C1(C1 {
                sensor: Sensor::Ir,
                ..c1(Sensor::NoAction, 7, OperationCommand::ZoomIn)
            }),
        ),
        (
            0x2C,
            &[0x53, 0x00, 0x64],
            Message::C2(C2::SetEoZoom(Zoom { zoom_x10: 100 })),
        ),
        (
            0x1E,
            &[0x02, 0x03, 0x00],
            Message::E1(E1::new(TrackingSource::Ir, TrackingCommand::Start)),
        ),
        (
            0x2E,
            &[0x0B, 0xFE, 0x20, 0x00, 0x87],
            Message::E2(E2::RectTopLeft(Point {
                x_px: -480,
                y_px: 135,
            })),
        ),
    ];
    for (i, (id, data, expected)) in sent.into_iter().enumerate() {
        let bytes = frame(id, ((i + 1) % 4) as u8, data);
        let p = check!(Packet::decode(&bytes));
        ensure_eq!((id, p.message), (id, expected));
        ensure_eq!(&emit(&p)?[..], &bytes[..]);
    }
    // The M packet: data type 0x07, roll at data bytes 8..9, pitch 10..11, yaw 12..13.
    let mut m = [0u8; 42];
    m[0] = 0x07;
    m[8..14].copy_from_slice(&layouts::M_ATTITUDE_BYTES);
    m[14..].copy_from_slice(&layouts::M_GPS_BYTES);
    let bytes = frame(0xB1, 1, &m);
    let p = check!(Packet::decode(&bytes));
    ensure_eq!(
        p.message,
        Message::M(M::new(Some(layouts::m_attitude()), Some(layouts::m_gps())))
    );
    // Our 0x40 reply, read at the driver's offsets.
    let status = Status {
        t1: layouts::t1(),
        f1: F1 {
            sensor: TrackerSensor::Eo1,
            state: TrackerState::Search,
            reserved: 0,
        },
        b1: B1 {
            servo: ServoCommand::FollowYaw,
            roll_raw12: B1::roll_raw_from_cdeg(1000),
            yaw_bam16: 0x2000,
            pitch_bam16: 0x1000,
        },
        d1: D1 {
            ir_color: IrColorMode::Grayscale,
            ..layouts::d1()
        },
    };
    let out = emit(&Packet::new(Header::new(1), Message::Status(status)))?;
    ensure_eq!(&out[..5], &[0x55, 0xAA, 0xDC, 0x6C, 0x40]);
    let d = &out[5..out.len() - 1];
    ensure_eq!((d[22] & 0x18) >> 3, 1); // tracking: searching
    let roll = u16::from_be_bytes([d[23] & 0x0F, d[24]]);
    ensure_eq!(roll, B1::roll_raw_from_cdeg(1000));
    ensure_eq!(i16::from_be_bytes([d[25], d[26]]), 0x2000);
    ensure_eq!(i16::from_be_bytes([d[27], d[28]]), 0x1000);
    ensure_eq!(d[29] & 0x07, VideoSource::IrEo1Pip.value());
    ensure_eq!((d[29] >> 3) & 0x0F, 4); // IR zoom index
    ensure_eq!(d[32] & 0x07, 1); // recording
    ensure_eq!(u16::from_be_bytes([d[33], d[34]]), 1234); // 123.4 m
    ensure_eq!(u16::from_be_bytes([d[39], d[40]]), 200); // 20x
    // The V replies to the queries: model from data byte 1, firmware digits at 4..9.
    let model = emit(&Packet::new(
        Header::new(2),
        Message::V(V::new(
            VCommand::QueryModel,
            VData::Model(check!(Text::new("Z40K"))),
        )),
    ))?;
    ensure_eq!(model[5], 0xE4);
    ensure_eq!(&model[6..10], b"Z40K");
    ensure_eq!(model.len(), 3 + 3 + 1 + 10);
    let fw = emit(&Packet::new(
        Header::new(3),
        Message::V(V::new(
            VCommand::QueryFirmware,
            VData::Firmware(check!(Text::new("S20230415"))),
        )),
    ))?;
    ensure_eq!(fw[5], 0xD0);
    ensure_eq!(&fw[5 + 4..5 + 10], b"230415");
    ensure_eq!(fw.len(), 3 + 3 + 1 + 20);
    Ok(())
}

cases!("viewlink":
    seed_vectors_decode_to_documented_fields,
    printed_errata_are_rejected_then_resynchronised,
    layouts_decode_and_reencode,
    layouts_cover_every_frame_id,
    every_u_command_is_typed,
    command_blocks_type_their_parameters,
    every_frame_id_round_trips,
    m_every_data_type,
    every_counter_value,
    swapped_sync_order,
    malformed_frames_are_errors,
    wrong_length_known_ids,
    unknown_ids_are_raw,
    deframer_recovers_every_frame,
    bit_fields,
    encode_refuses_values_that_do_not_fit,
    typed_messages_match_the_catalogue,
    bridge_path_with_typed_messages,
    tcp_envelope,
    ardupilot_interop,
);
