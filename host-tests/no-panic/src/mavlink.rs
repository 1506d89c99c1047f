//! MAVLink 2: the frame view and its setters, checksum and signature, packet decode,
//! parse, emit and buffer_len, message decode (every id of the dialect and any other),
//! `encode` of an opaque typed message, the generated dialect's own decode/encode and
//! lookup, and the deframer with either unknown-id rule (MAVLink 1 skipping included).

use core::hint::black_box;
use protocol_core::mavlink::*;

pub fn exercise(input: &[u8], out: &mut [u8]) {
    let f = Frame::new_unchecked(input);
    black_box((
        f.check_len(),
        f.payload_len(),
        f.incompat_flags(),
        f.compat_flags(),
        f.is_signed(),
        f.sequence(),
    ));
    black_box((
        f.system_id(),
        f.component_id(),
        f.message_id(),
        f.payload(),
        f.payload_ref(),
        f.checksum(),
    ));
    let extra = black_box(0u8);
    black_box((
        f.signature(),
        f.total_len(),
        f.compute_checksum(extra),
        f.verify(),
        f.verify_with(extra),
    ));
    if let Ok(f) = Frame::new_checked(input) {
        black_box(Packet::parse(&f));
    }
    black_box((checksum(input, extra), Signature::from_bytes(input)));

    let b = black_box(0u8);
    let id = black_box(0u32);
    let mut fm = Frame::new_unchecked(&mut *out);
    fm.set_start(b, b);
    fm.set_compat_flags(b);
    fm.set_sequence(b);
    fm.set_system_id(b);
    fm.set_component_id(b);
    fm.set_message_id(id);
    black_box(fm.payload_mut());
    fm.fill_checksum(b);
    if let Some(s) = Signature::from_bytes(input) {
        fm.set_signature(&s);
        black_box(s.to_bytes());
    }
    black_box(fm.into_inner());

    let header = black_box(Header {
        sequence: b,
        system_id: b,
        component_id: b,
    });
    let m = Message::decode(id, input);
    black_box((m.id(), m.name()));
    if let Message::Raw(r) = &m {
        black_box(r.info());
    }
    black_box(Packet::new(header, m.clone()).emit(&mut *out));
    if let Message::Known(known) = &m {
        black_box(encode(known, &header, &mut *out));
    }
    if let Ok(p) = Packet::decode(input) {
        black_box((p.buffer_len(), p.emit(&mut *out)));
    }
    // Signing: the check, the fill, signed encoding, the key's text, the timestamp.
    let key = SecretKey::new(black_box([0u8; KEY_LEN]));
    black_box(signature_matches(input, &key));
    black_box(signature_value(&key, input));
    let signer = Signer {
        key: &key,
        link_id: b,
        timestamp: black_box(0),
    };
    if let Message::Known(known) = &m {
        black_box(encode_signed(known, &header, &signer, &mut *out));
    }
    if let Ok(p) = Packet::decode(input) {
        black_box(p.emit_signed(&signer, &mut *out));
    }
    fill_signature(&mut *out, &key);
    black_box(SecretKey::from_hex(
        core::str::from_utf8(input).unwrap_or_default(),
    ));
    black_box(timestamp_of_unix_micros(black_box(0)));
    black_box(message_info(id));
    black_box(dialect::decode(id, input).is_ok());
    if let Ok(known) = dialect::decode(id, input) {
        let mut payload = [0u8; 255];
        black_box(dialect::encode(&known, &mut payload));
    }

    let framing = black_box(MavlinkFraming::new());
    crate::wire::deframe::<_, MAX_FRAME_LEN>(framing, input);
    crate::wire::deframe::<_, 64>(MavlinkFraming::delivering_unknown_ids(), input);
    crate::wire::deframe::<_, 300>(
        black_box(MavlinkFraming {
            unknown_ids: UnknownIds::Reject,
        }),
        input,
    );
}
