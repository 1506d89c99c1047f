//! The client and the receiver against each other on the host flash model, through the
//! codec: a whole update, the swap, the trial, the rollback, a resumed transfer, and every
//! refusal that protects the board.
#![allow(
    clippy::unwrap_used,
    clippy::indexing_slicing,
    clippy::arithmetic_side_effects,
    clippy::panic,
    clippy::cast_possible_truncation
)]

mod common;

use bridge_update::client::{Client, ClientError, Progress};
use bridge_update::wire::{BootState, Refusal, Request, Response};
use bridge_update::{Receiver, Slot};
use common::*;
use embassy_boot::State;

const LEN: usize = 2 * 2048 + 300;

#[test]
fn an_update_is_swapped_in_confirmed_and_kept() {
    let (a, b) = (image(0xA0, LEN), image(0xB0, LEN));
    let board = new_board(&a);
    let mut requests = 0;
    assert_eq!(
        update(&board, &b, signature(&key(), &b), &mut requests),
        Ended::Verified
    );
    // Hello, Begin, 5 chunks of 1 KiB (the last 300 B), Finish.
    assert_eq!(requests, 1 + 1 + 5 + 1);
    assert_eq!(board.active(LEN), a, "nothing swapped before the reset");
    assert_eq!(board.reset().unwrap().state, State::Swap);
    assert_eq!(board.active(LEN), b);
    let mut aligned = [0; 8];
    assert_eq!(
        board.slot(&mut aligned).unwrap().state(),
        Ok(BootState::Trial)
    );
    board.confirm().unwrap();
    assert_eq!(board.reset().unwrap().state, State::Boot);
    assert_eq!(board.active(LEN), b);
}

#[test]
fn an_image_that_does_not_confirm_itself_is_rolled_back() {
    let (a, b) = (image(0xA0, LEN), image(0xB0, LEN));
    let board = new_board(&a);
    assert_eq!(
        update(&board, &b, signature(&key(), &b), &mut 0),
        Ended::Verified
    );
    board.reset().unwrap();
    assert_eq!(board.active(LEN), b);
    // No confirmation: the watchdog (or a power cut) resets the board.
    assert_eq!(board.reset().unwrap().state, State::Swap, "the revert ran");
    assert_eq!(board.active(LEN), a);
    let mut aligned = [0; 8];
    assert_eq!(
        board.slot(&mut aligned).unwrap().state(),
        Ok(BootState::RolledBack)
    );
    assert_eq!(board.reset().unwrap().state, State::Revert);
    assert_eq!(board.active(LEN), a, "and stays");
}

#[test]
fn a_wrong_signature_is_refused_and_nothing_is_marked() {
    let (a, b) = (image(0xA0, LEN), image(0xB0, LEN));
    let board = new_board(&a);
    // Signed by another key; then signed by the right key but for another image.
    for sig in [signature(&other_key(), &b), signature(&key(), &a)] {
        assert_eq!(
            update(&board, &b, sig, &mut 0),
            Ended::Failed(ClientError::Refused(Refusal::BadSignature))
        );
        assert_eq!(board.reset().unwrap().state, State::Boot);
        assert_eq!(board.active(LEN), a);
    }
    // A slot changed after the transfer (one bit) fails the check too: the signature is
    // checked over what the flash holds.
    let mut aligned = [0; 8];
    let mut slot = board.slot(&mut aligned).unwrap();
    let mut receiver = Receiver::new(*key().verifying_key().as_bytes(), false, "t");
    let sig = signature(&key(), &b);
    exchange(
        &mut receiver,
        &mut slot,
        &Request::Begin {
            size: LEN as u32,
            signature: sig,
        },
    );
    for (i, chunk) in b.chunks(1024).enumerate() {
        let mut data = chunk.to_vec();
        if i == 2 {
            data[17] ^= 1;
        }
        exchange(
            &mut receiver,
            &mut slot,
            &Request::Chunk {
                offset: (i * 1024) as u32,
                data: &data,
            },
        );
    }
    let answer = exchange(&mut receiver, &mut slot, &Request::Finish);
    assert_eq!(
        Response::parse(&answer).unwrap(),
        Response::Refused {
            reason: Refusal::BadSignature,
            detail: 0
        }
    );
    assert_eq!(board.reset().unwrap().state, State::Boot);
    assert_eq!(board.active(LEN), a);
}

#[test]
fn a_lost_link_resumes_where_the_board_stopped() {
    let (a, b) = (image(0xA0, LEN), image(0xB0, LEN));
    let board = new_board(&a);
    let mut aligned = [0; 8];
    let mut slot = board.slot(&mut aligned).unwrap();
    let mut receiver = Receiver::new(*key().verifying_key().as_bytes(), false, "t");
    let sig = signature(&key(), &b);
    let mut client = Client::new(&b, sig).unwrap();
    // Three chunks get through (Hello, Begin, 3 chunks), then the link is lost.
    for _ in 0..5 {
        let r = client.request().unwrap();
        let frame = exchange(&mut receiver, &mut slot, &r);
        client.response(&Response::parse(&frame).unwrap()).unwrap();
    }
    // The fourth chunk reaches the board but its ACK is lost.
    let r = client.request().unwrap();
    exchange(&mut receiver, &mut slot, &r);
    client.reconnect();
    let mut sent_from = None;
    let mut chunks_after = 0;
    while let Some(r) = client.request() {
        if let Request::Chunk { .. } = r {
            chunks_after += 1;
        }
        let frame = exchange(&mut receiver, &mut slot, &r);
        match client.response(&Response::parse(&frame).unwrap()).unwrap() {
            Progress::Resumed(at) => sent_from = Some(at),
            Progress::Verified => break,
            _ => {}
        }
    }
    assert_eq!(sent_from, Some(4096), "the board had four chunks");
    assert_eq!(chunks_after, 1, "only the last chunk is sent again");
    board.reset().unwrap();
    assert_eq!(board.active(LEN), b);
}

#[test]
fn nothing_is_written_while_an_image_is_on_trial() {
    let (a, b, c) = (image(0xA0, LEN), image(0xB0, LEN), image(0xC0, LEN));
    let board = new_board(&a);
    assert_eq!(
        update(&board, &b, signature(&key(), &b), &mut 0),
        Ended::Verified
    );
    board.reset().unwrap();
    // B on trial: the update slot holds A, which a rollback needs.
    assert_eq!(
        update(&board, &c, signature(&key(), &c), &mut 0),
        Ended::Failed(ClientError::Refused(Refusal::NotConfirmed))
    );
    let mut aligned = [0; 8];
    let mut slot = board.slot(&mut aligned).unwrap();
    let mut receiver = Receiver::new(*key().verifying_key().as_bytes(), false, "t");
    let answer = exchange(
        &mut receiver,
        &mut slot,
        &Request::Begin {
            size: LEN as u32,
            signature: [0; 64],
        },
    );
    assert_eq!(
        Response::parse(&answer).unwrap(),
        Response::Refused {
            reason: Refusal::NotConfirmed,
            detail: 0
        }
    );
    assert_eq!(
        slot.write(0, &[0; 8]),
        Err(bridge_update::SlotError::NotConfirmed)
    );
    // Still a rollback to A.
    board.reset().unwrap();
    assert_eq!(board.active(LEN), a);
}

#[test]
fn a_pending_swap_is_withdrawn_before_its_slot_is_written_again() {
    let (a, b, c) = (image(0xA0, LEN), image(0xB0, LEN), image(0xC0, LEN));
    let board = new_board(&a);
    let mut aligned = [0; 8];
    let mut slot = board.slot(&mut aligned).unwrap();
    let mut receiver = Receiver::new(*key().verifying_key().as_bytes(), false, "t");
    let sig_b = signature(&key(), &b);
    let sig_c = signature(&key(), &c);
    let mut run = |img: &[u8], sig, cut_after: Option<usize>| {
        let mut client = Client::new(img, sig).unwrap();
        let mut n = 0;
        while let Some(r) = client.request() {
            if Some(n) == cut_after {
                return;
            }
            n += 1;
            let frame = exchange(&mut receiver, &mut slot, &r);
            client.response(&Response::parse(&frame).unwrap()).unwrap();
        }
    };
    run(&b, sig_b, None);
    // C's transfer starts (Hello, Begin, one chunk) and stops: B's mark must be gone.
    run(&c, sig_c, Some(3));
    assert_eq!(
        board.reset().unwrap().state,
        State::Boot,
        "no swap of a half-written slot"
    );
    assert_eq!(board.active(LEN), a);
}

#[test]
fn bad_requests_are_refused_with_their_reason() {
    let a = image(0xA0, LEN);
    let board = new_board(&a);
    let mut aligned = [0; 8];
    let mut slot = board.slot(&mut aligned).unwrap();
    let long = "é".repeat(100);
    let mut long_receiver = Receiver::new([0; 32], false, &long);
    match Response::parse(&exchange(&mut long_receiver, &mut slot, &Request::Hello)).unwrap() {
        Response::Info(info) => assert_eq!(info.version, "é".repeat(64), "cut at 128 bytes"),
        other => panic!("{other:?}"),
    }
    let mut receiver = Receiver::new(*key().verifying_key().as_bytes(), true, "0.2.0");
    let begin = |size| Request::Begin {
        size,
        signature: [0; 64],
    };
    let chunk = |offset, data: &'static [u8]| Request::Chunk { offset, data };
    let refused = |reason| Kind::Refused(reason, 0);
    // In order: each request, what it gets.
    let script = [
        (chunk(0, &[1; 8]), refused(Refusal::NoTransfer)),
        (Request::Finish, refused(Refusal::NoTransfer)),
        (begin(3 * 2048 + 1), refused(Refusal::TooLarge)),
        (begin(0), refused(Refusal::TooLarge)),
        (begin(100), Kind::Ready(0)),
        (chunk(8, &[1; 8]), Kind::Refused(Refusal::WrongOffset, 0)),
        (chunk(0, &[1; 7]), refused(Refusal::BadChunk)),
        (chunk(0, &[1; 104]), refused(Refusal::BadChunk)),
        (chunk(0, &[1; 96]), Kind::Ack(96)),
        // Sent again (its ACK lost): acknowledged, not written again.
        (chunk(0, &[1; 96]), Kind::Ack(96)),
        // 4 bytes missing.
        (Request::Finish, refused(Refusal::NoTransfer)),
        (chunk(96, &[1; 4]), Kind::Ack(100)),
        (Request::Finish, refused(Refusal::BadSignature)),
        (
            Request::Hello,
            Kind::Info("0.2.0".into(), BootState::Confirmed, 3 * 2048, true),
        ),
    ];
    for (i, (request, expected)) in script.into_iter().enumerate() {
        let frame = exchange(&mut receiver, &mut slot, &request);
        let answer = Response::parse(&frame).unwrap().to_owned_kind();
        assert_eq!(answer, expected, "request {i}: {request:?}");
    }
    assert_eq!(board.reset().unwrap().state, State::Boot);
}

/// A response without borrows, to compare.
#[derive(Debug, PartialEq, Eq)]
enum Kind {
    Info(String, BootState, u32, bool),
    Ready(u32),
    Ack(u32),
    Refused(Refusal, u32),
    Other,
}

trait ToOwnedKind {
    fn to_owned_kind(&self) -> Kind;
}

impl ToOwnedKind for Response<'_> {
    fn to_owned_kind(&self) -> Kind {
        match *self {
            Response::Info(i) => Kind::Info(i.version.to_string(), i.state, i.slot_size, i.dev_key),
            Response::Ready { resume_at } => Kind::Ready(resume_at),
            Response::Ack { next } => Kind::Ack(next),
            Response::Refused { reason, detail } => Kind::Refused(reason, detail),
            _ => Kind::Other,
        }
    }
}
