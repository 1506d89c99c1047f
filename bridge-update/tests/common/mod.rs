//! A board on the host and a client talking to it, frame by frame through the codec.
#![allow(
    dead_code,
    clippy::unwrap_used,
    clippy::indexing_slicing,
    clippy::arithmetic_side_effects,
    clippy::panic,
    clippy::cast_possible_truncation
)]

use bridge_update::client::{Client, ClientError, Progress};
use bridge_update::sim::{SimBoard, SimFlash, SimLayout};
use bridge_update::wire::{MAX_FRAME, Request, Response, UpdateFraming};
use bridge_update::{Receiver, Slot};
use ed25519_dalek::SigningKey;
use protocol_core::wire::{Deframer, Event};

pub const LAYOUT: SimLayout = SimLayout { active_pages: 3 };

/// The key the boards are built with, and another one.
pub fn key() -> SigningKey {
    SigningKey::from_bytes(&[7; 32])
}
pub fn other_key() -> SigningKey {
    SigningKey::from_bytes(&[9; 32])
}

/// An image of `len` bytes that names itself (`tag`) and differs everywhere from another tag's.
pub fn image(tag: u8, len: usize) -> Vec<u8> {
    (0..len)
        .map(|i| tag ^ (i as u8).wrapping_mul(31) ^ (i >> 8) as u8)
        .collect()
}

pub fn signature(key: &SigningKey, image: &[u8]) -> [u8; 64] {
    let sig = bridge_update::keys::sign(key, image);
    bridge_update::keys::parse_sig(&sig).unwrap().0
}

fn one_frame(bytes: &[u8]) -> Vec<u8> {
    let mut d = Deframer::<UpdateFraming, MAX_FRAME>::new(UpdateFraming);
    let mut out = Vec::new();
    d.push(bytes, |e| {
        if let Event::Frame(f) = e {
            out = f.to_vec();
        }
    });
    out
}

/// One request through the wire to the receiver and its answer back.
pub fn exchange<S: Slot>(
    receiver: &mut Receiver<'_>,
    slot: &mut S,
    request: &Request<'_>,
) -> Vec<u8> {
    let mut buf = [0u8; MAX_FRAME];
    let n = request.emit(&mut buf).unwrap();
    let frame = one_frame(&buf[..n]);
    let request = Request::parse(&frame).unwrap();
    let mut response = receiver.handle(request, slot);
    while response.is_none() {
        response = receiver.work(slot);
    }
    let n = response.unwrap().emit(&mut buf).unwrap();
    one_frame(&buf[..n])
}

/// What [`update`] ended with.
#[derive(Debug, PartialEq, Eq)]
pub enum Ended {
    Verified,
    Failed(ClientError),
    /// The flash lost power.
    PowerLost,
}

/// A whole transfer, from Hello to Verified: `requests` counts the frames sent.
pub fn update(board: &SimBoard, image: &[u8], sig: [u8; 64], requests: &mut usize) -> Ended {
    let mut aligned = [0; 8];
    let Ok(mut slot) = board.slot(&mut aligned) else {
        return Ended::PowerLost;
    };
    let mut receiver = Receiver::new(*key().verifying_key().as_bytes(), false, "test");
    let mut client = Client::new(image, sig).unwrap();
    while let Some(request) = client.request() {
        *requests += 1;
        let frame = exchange(&mut receiver, &mut slot, &request);
        if board.with_flash(|f: &mut SimFlash| f.lost_power()) {
            return Ended::PowerLost;
        }
        match client.response(&Response::parse(&frame).unwrap()) {
            Ok(Progress::Verified) => return Ended::Verified,
            Ok(_) => {}
            Err(e) => return Ended::Failed(e),
        }
    }
    Ended::Verified
}

pub fn new_board(image: &[u8]) -> SimBoard {
    SimBoard::new(LAYOUT, image)
}
