//! The client's side of the update protocol, sans-IO: which request to send now, and what
//! each response means. The driver (`gimbal update`) moves the bytes, times out and sends
//! [`Client::request`] again, and after a lost link calls [`Client::reconnect`]: the board
//! then says where to resume.

use std::string::String;

use crate::wire::{
    BootState, CRC_LEN, HEADER_LEN, MAX_CHUNK, MAX_VERSION, Refusal, Request, Response,
    SIGNATURE_LEN,
};

/// Where the transfer is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Asking who the board is.
    Hello,
    /// Announcing the image.
    Begin,
    /// Sending chunks.
    Send,
    /// Waiting for the signature check.
    Finish,
    /// Verified and marked for the swap.
    Done,
}

/// What a response told the client.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Progress {
    /// The board's identity.
    Board {
        /// Its firmware's version.
        version: String,
        /// Its running image's state.
        state: BootState,
        /// Its key's id ([`crate::key_id`]).
        key_id: [u8; 8],
        /// Whether its key is a development key.
        dev_key: bool,
    },
    /// The board takes the image from this offset (0: from the start).
    Resumed(u32),
    /// Bytes the board has, of the image.
    Sent(u32),
    /// The signature holds and the image is marked for the swap.
    Verified,
    /// A response that changes nothing (a late answer to a request sent again).
    Nothing,
}

/// Why the update cannot go on.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ClientError {
    /// The board refused (the reason says why).
    Refused(Refusal),
    /// The image is larger than the board's slot.
    TooLarge {
        /// Image bytes.
        image: u32,
        /// Slot bytes.
        slot: u32,
    },
    /// The board answered something that makes no sense at this point.
    Protocol(&'static str),
}

impl core::fmt::Display for ClientError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ClientError::Refused(r) => write!(f, "the board refused: {r}"),
            ClientError::TooLarge { image, slot } => write!(
                f,
                "the image ({image} bytes) is larger than the board's update slot ({slot} bytes)"
            ),
            ClientError::Protocol(what) => write!(f, "protocol error: {what}"),
        }
    }
}

/// One image's transfer.
#[derive(Debug, Clone)]
pub struct Client<'i> {
    image: &'i [u8],
    signature: [u8; SIGNATURE_LEN],
    phase: Phase,
    /// The next offset to send.
    next: u32,
}

impl<'i> Client<'i> {
    /// A transfer of `image` with its `signature`.
    ///
    /// # Errors
    /// [`ClientError::TooLarge`] for an image of 4 GiB or more.
    pub fn new(image: &'i [u8], signature: [u8; SIGNATURE_LEN]) -> Result<Self, ClientError> {
        let Ok(_) = u32::try_from(image.len()) else {
            return Err(ClientError::TooLarge {
                image: u32::MAX,
                slot: 0,
            });
        };
        Ok(Client {
            image,
            signature,
            phase: Phase::Hello,
            next: 0,
        })
    }

    /// Where the transfer is.
    #[must_use]
    pub fn phase(&self) -> Phase {
        self.phase
    }

    fn size(&self) -> u32 {
        u32::try_from(self.image.len()).unwrap_or(u32::MAX)
    }

    /// After a lost link: ask again who the board is and where to resume.
    pub fn reconnect(&mut self) {
        if self.phase != Phase::Done {
            self.phase = Phase::Hello;
        }
    }

    /// The request to send now (again, after a time-out). `None` when done.
    #[must_use]
    pub fn request(&self) -> Option<Request<'i>> {
        Some(match self.phase {
            Phase::Hello => Request::Hello,
            Phase::Begin => Request::Begin {
                size: self.size(),
                signature: self.signature,
            },
            Phase::Send => {
                let from = usize::try_from(self.next).unwrap_or(usize::MAX);
                let to = from.saturating_add(MAX_CHUNK).min(self.image.len());
                Request::Chunk {
                    offset: self.next,
                    data: self.image.get(from..to).unwrap_or_default(),
                }
            }
            Phase::Finish => Request::Finish,
            Phase::Done => return None,
        })
    }

    fn resume(&mut self, at: u32) -> Result<(), ClientError> {
        if at > self.size() || !at.is_multiple_of(8) && at != self.size() {
            return Err(ClientError::Protocol("resume offset outside the image"));
        }
        self.next = at;
        self.phase = if at == self.size() {
            Phase::Finish
        } else {
            Phase::Send
        };
        Ok(())
    }

    /// Takes the board's response to the last request.
    ///
    /// # Errors
    /// [`ClientError`] when the update cannot go on.
    pub fn response(&mut self, response: &Response<'_>) -> Result<Progress, ClientError> {
        match (self.phase, response) {
            (Phase::Hello, Response::Info(info)) => {
                if info.slot_size < self.size() {
                    return Err(ClientError::TooLarge {
                        image: self.size(),
                        slot: info.slot_size,
                    });
                }
                if info.state == BootState::Trial {
                    return Err(ClientError::Refused(Refusal::NotConfirmed));
                }
                self.phase = Phase::Begin;
                Ok(Progress::Board {
                    version: info.version.chars().take(MAX_VERSION).collect(),
                    state: info.state,
                    key_id: info.key_id,
                    dev_key: info.dev_key,
                })
            }
            (Phase::Begin, Response::Ready { resume_at }) => {
                self.resume(*resume_at)?;
                Ok(Progress::Resumed(*resume_at))
            }
            (Phase::Send, Response::Ack { next }) => {
                if *next > self.next {
                    self.resume(*next)?;
                }
                Ok(Progress::Sent(self.next))
            }
            (
                Phase::Send | Phase::Finish,
                Response::Refused {
                    reason: Refusal::WrongOffset,
                    detail,
                },
            ) => {
                self.resume(*detail)?;
                Ok(Progress::Sent(self.next))
            }
            (Phase::Finish, Response::Verified) => {
                self.phase = Phase::Done;
                Ok(Progress::Verified)
            }
            (_, Response::Refused { reason, .. }) => Err(ClientError::Refused(*reason)),
            // A late answer to a request sent again: ignore it.
            (
                Phase::Send | Phase::Finish | Phase::Done,
                Response::Ack { .. } | Response::Ready { .. } | Response::Info(_),
            )
            | (Phase::Begin, Response::Info(_)) => Ok(Progress::Nothing),
            _ => Err(ClientError::Protocol("unexpected response")),
        }
    }
}

/// Bytes on the wire for an update of an image of `size` bytes, without a retry: (to the
/// board, to the client). The board's version text is counted at its longest.
#[must_use]
// u64 sums of a u32 size and small multiples of it: far from overflowing.
#[allow(clippy::arithmetic_side_effects)]
pub fn wire_bytes(size: u32) -> (u64, u64) {
    let frame = |payload: u64| HEADER_LEN as u64 + payload + CRC_LEN as u64;
    let size = u64::from(size);
    let chunks = size.div_ceil(MAX_CHUNK as u64);
    let hello = frame(0);
    let begin = frame(4 + SIGNATURE_LEN as u64);
    let chunk_overhead = frame(4);
    let to_board = hello + begin + chunks * chunk_overhead + size + frame(0) + frame(0);
    let info = frame(1 + 4 + 8 + 1 + MAX_VERSION as u64);
    let to_client = info + frame(4) + chunks * frame(4) + frame(0) + frame(0);
    (to_board, to_client)
}

/// Seconds on a line of `baud` (8N1: 10 bits a byte) for an update of an image of `size`
/// bytes ([`wire_bytes`], both ways, one after the other as the protocol waits for each
/// answer); the flash's own time comes on top.
#[must_use]
pub fn wire_seconds(size: u32, baud: u32) -> f64 {
    let (to_board, to_client) = wire_bytes(size);
    #[allow(clippy::cast_precision_loss)]
    let bits = to_board.saturating_add(to_client).saturating_mul(10) as f64;
    bits / f64::from(baud)
}
