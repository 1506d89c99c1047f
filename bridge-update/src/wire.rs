//! The update protocol's frames, on any byte link (the console's port, a UART, a pipe).
//!
//! ```text
//! 0xB7 0x4D | kind: u8 | len: u16 LE | payload (len bytes) | CRC-32 LE over kind, len and payload
//! ```
//!
//! Every frame carries its own checksum (CRC-32/ISO-HDLC, the one of zlib and Ethernet), so a
//! chunk damaged on the wire is refused alone and sent again; the framing is protocol-core's
//! streaming deframer, which finds the next frame after garbage without losing it.
//!
//! A client sends [`Request`]s and the board answers each with one [`Response`]. All
//! integers are little-endian.

use crc::{CRC_32_ISO_HDLC, Crc};
use protocol_core::wire::{Framing, Reader, Writer};
use protocol_core::{Error, Result};

/// The two bytes every frame starts with.
pub const SYNC: [u8; 2] = [0xB7, 0x4D];
/// Sync, kind and length.
pub const HEADER_LEN: usize = 5;
/// The CRC-32 at the end.
pub const CRC_LEN: usize = 4;
/// The largest chunk of image data in one [`Request::Chunk`] (half a flash page).
pub const MAX_CHUNK: usize = 1024;
/// The largest payload: a chunk with its offset.
pub const MAX_PAYLOAD: usize = MAX_CHUNK + 4;
/// The largest frame.
pub const MAX_FRAME: usize = HEADER_LEN + MAX_PAYLOAD + CRC_LEN;
/// The longest version text an [`Info`] carries.
pub const MAX_VERSION: usize = 128;
/// An ed25519 signature.
pub const SIGNATURE_LEN: usize = 64;

const CRC32: Crc<u32> = Crc::<u32>::new(&CRC_32_ISO_HDLC);

/// The update protocol's framing, for [`protocol_core::wire::Deframer`].
#[derive(Debug, Clone, Copy, Default)]
pub struct UpdateFraming;

impl Framing for UpdateFraming {
    fn sync(&self) -> &[u8] {
        &SYNC
    }

    fn header_len(&self) -> usize {
        HEADER_LEN
    }

    fn frame_len(&self, header: &[u8]) -> Result<usize> {
        let len = match header {
            [_, _, _, lo, hi, ..] => usize::from(u16::from_le_bytes([*lo, *hi])),
            _ => return Err(Error::Truncated),
        };
        if len > MAX_PAYLOAD {
            return Err(Error::BadLength);
        }
        Ok(HEADER_LEN.saturating_add(len).saturating_add(CRC_LEN))
    }

    fn check(&self, frame: &[u8]) -> Result<()> {
        let split = frame.len().checked_sub(CRC_LEN).ok_or(Error::Truncated)?;
        let (body, crc) = frame.split_at_checked(split).ok_or(Error::Truncated)?;
        let covered = body.get(SYNC.len()..).ok_or(Error::Truncated)?;
        let received = u32::from_le_bytes(crc.try_into().map_err(|_| Error::Truncated)?);
        let computed = CRC32.checksum(covered);
        if computed == received {
            Ok(())
        } else {
            // The error type's fields are 16 bits wide: the low halves say enough.
            #[allow(clippy::cast_possible_truncation)]
            Err(Error::BadChecksum {
                computed: computed as u16,
                received: received as u16,
            })
        }
    }
}

/// Kinds of frame.
mod kind {
    pub const HELLO: u8 = 0x01;
    pub const BEGIN: u8 = 0x02;
    pub const CHUNK: u8 = 0x03;
    pub const FINISH: u8 = 0x04;
    pub const REBOOT: u8 = 0x05;
    pub const INFO: u8 = 0x81;
    pub const READY: u8 = 0x82;
    pub const ACK: u8 = 0x83;
    pub const VERIFIED: u8 = 0x84;
    pub const REBOOTING: u8 = 0x85;
    pub const REFUSED: u8 = 0xFF;
}

/// What a client asks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Request<'a> {
    /// Who are you: answered with [`Response::Info`].
    Hello,
    /// An image of `size` bytes whose ed25519 signature (over its SHA-512) is `signature`
    /// follows: answered with [`Response::Ready`] and the offset to send from (0, or
    /// where an interrupted transfer of the same image stopped).
    Begin {
        /// Image bytes.
        size: u32,
        /// Its signature; it also names the image for a resumed transfer.
        signature: [u8; SIGNATURE_LEN],
    },
    /// Image bytes at `offset`: answered with [`Response::Ack`] and the next offset.
    Chunk {
        /// Where in the image.
        offset: u32,
        /// At most [`MAX_CHUNK`] bytes.
        data: &'a [u8],
    },
    /// Every byte sent: verify the signature over the slot's contents and, if it holds,
    /// mark the image for the swap at the next reset ([`Response::Verified`]).
    Finish,
    /// Reset now ([`Response::Rebooting`] first): the bootloader swaps a verified image in.
    Reboot,
}

/// The state of the running image, as embassy-boot's state partition says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum BootState {
    /// Confirmed: it marked itself good, or it was never swapped in.
    Confirmed,
    /// Swapped in at the last reset and not yet confirmed: a reset before it confirms
    /// itself swaps the previous image back.
    Trial,
    /// A verified image waits in the update slot: the next reset swaps it in.
    SwapPending,
    /// The last update did not confirm itself and was swapped back: the previous image runs.
    RolledBack,
}

impl BootState {
    fn code(self) -> u8 {
        match self {
            BootState::Confirmed => 0,
            BootState::Trial => 1,
            BootState::SwapPending => 2,
            BootState::RolledBack => 3,
        }
    }

    fn from_code(code: u8) -> Result<Self> {
        Ok(match code {
            0 => BootState::Confirmed,
            1 => BootState::Trial,
            2 => BootState::SwapPending,
            3 => BootState::RolledBack,
            _ => return Err(Error::OutOfRange),
        })
    }
}

/// Who the board is: [`Response::Info`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Info<'a> {
    /// The running firmware's version text (UTF-8, at most [`MAX_VERSION`] bytes).
    pub version: &'a str,
    /// The state of the running image.
    pub state: BootState,
    /// The largest image the update slot takes.
    pub slot_size: u32,
    /// The first 8 bytes of the SHA-512 of the public key it accepts images signed by.
    pub key_id: [u8; 8],
    /// Whether that key is a development key.
    pub dev_key: bool,
}

/// Why a request was refused ([`Response::Refused`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Refusal {
    /// A request the board does not understand, or a payload of the wrong length.
    Malformed,
    /// The image is larger than the update slot.
    TooLarge,
    /// A chunk before any [`Request::Begin`], or a [`Request::Finish`] before every byte.
    NoTransfer,
    /// A chunk not at the offset expected (the detail): send from there.
    WrongOffset,
    /// A chunk longer than [`MAX_CHUNK`], beyond the image, or of a length the flash
    /// cannot take (a multiple of 8 bytes, but the image's last).
    BadChunk,
    /// The signature does not hold for the slot's contents with the board's key: nothing
    /// was marked, the running image stays.
    BadSignature,
    /// The running image is on trial or a swap is pending: confirm or reset first.
    NotConfirmed,
    /// The flash refused a write, an erase or a read.
    Flash,
}

impl Refusal {
    fn code(self) -> u8 {
        match self {
            Refusal::Malformed => 1,
            Refusal::TooLarge => 2,
            Refusal::NoTransfer => 3,
            Refusal::WrongOffset => 4,
            Refusal::BadChunk => 5,
            Refusal::BadSignature => 6,
            Refusal::NotConfirmed => 7,
            Refusal::Flash => 8,
        }
    }

    fn from_code(code: u8) -> Result<Self> {
        Ok(match code {
            1 => Refusal::Malformed,
            2 => Refusal::TooLarge,
            3 => Refusal::NoTransfer,
            4 => Refusal::WrongOffset,
            5 => Refusal::BadChunk,
            6 => Refusal::BadSignature,
            7 => Refusal::NotConfirmed,
            8 => Refusal::Flash,
            _ => return Err(Error::OutOfRange),
        })
    }
}

impl core::fmt::Display for Refusal {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Refusal::Malformed => "malformed request",
            Refusal::TooLarge => "the image is larger than the update slot",
            Refusal::NoTransfer => "no transfer begun, or not every byte sent",
            Refusal::WrongOffset => "chunk at the wrong offset",
            Refusal::BadChunk => "bad chunk length",
            Refusal::BadSignature => {
                "the signature does not hold with the board's key (nothing was changed)"
            }
            Refusal::NotConfirmed => {
                "the running image is not confirmed yet (on trial or a swap pending): wait for it or reset the board"
            }
            Refusal::Flash => "the board's flash refused an operation",
        })
    }
}

/// What the board answers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Response<'a> {
    /// To [`Request::Hello`].
    Info(Info<'a>),
    /// To [`Request::Begin`]: send from this offset.
    Ready {
        /// The first byte the board still needs.
        resume_at: u32,
    },
    /// To [`Request::Chunk`]: the next offset the board expects.
    Ack {
        /// Bytes received so far, contiguous from 0.
        next: u32,
    },
    /// To [`Request::Finish`]: signature good, the image is marked for the swap.
    Verified,
    /// To [`Request::Reboot`]: the board resets once this is sent.
    Rebooting,
    /// The request was refused.
    Refused {
        /// Why.
        reason: Refusal,
        /// The expected offset ([`Refusal::WrongOffset`]), else 0.
        detail: u32,
    },
}

fn frame(
    out: &mut [u8],
    kind: u8,
    payload: impl FnOnce(&mut Writer<'_>) -> Result<()>,
) -> Result<usize> {
    let mut w = Writer::new(out);
    w.put(&SYNC)?;
    w.u8(kind)?;
    w.u16_le(0)?;
    payload(&mut w)?;
    let len = w.len();
    let payload_len =
        u16::try_from(len.saturating_sub(HEADER_LEN)).map_err(|_| Error::BufferTooSmall)?;
    let [lo, hi] = payload_len.to_le_bytes();
    w.set_u8(3, lo)?;
    w.set_u8(4, hi)?;
    let crc = CRC32.checksum(w.written().get(SYNC.len()..).unwrap_or_default());
    w.u32_le(crc)?;
    Ok(w.len())
}

/// The kind and payload of a frame that [`UpdateFraming`] accepted (checksum included).
fn parts(frame: &[u8]) -> Result<(u8, &[u8])> {
    let kind = *frame.get(2).ok_or(Error::Truncated)?;
    let end = frame.len().checked_sub(CRC_LEN).ok_or(Error::Truncated)?;
    let payload = frame.get(HEADER_LEN..end).ok_or(Error::Truncated)?;
    Ok((kind, payload))
}

impl<'a> Request<'a> {
    /// Writes the frame into `out`; its length.
    ///
    /// # Errors
    /// [`Error::BufferTooSmall`] when `out` is shorter than the frame (at most
    /// [`MAX_FRAME`]), [`Error::BadLength`] for a chunk longer than [`MAX_CHUNK`].
    pub fn emit(&self, out: &mut [u8]) -> Result<usize> {
        match *self {
            Request::Hello => frame(out, kind::HELLO, |_| Ok(())),
            Request::Begin { size, signature } => frame(out, kind::BEGIN, |w| {
                w.u32_le(size)?;
                w.put(&signature)
            }),
            Request::Chunk { offset, data } => {
                if data.len() > MAX_CHUNK {
                    return Err(Error::BadLength);
                }
                frame(out, kind::CHUNK, |w| {
                    w.u32_le(offset)?;
                    w.put(data)
                })
            }
            Request::Finish => frame(out, kind::FINISH, |_| Ok(())),
            Request::Reboot => frame(out, kind::REBOOT, |_| Ok(())),
        }
    }

    /// The request in a frame the deframer delivered.
    ///
    /// # Errors
    /// [`Error::UnknownId`] for a kind that is not a request, [`Error::BadLength`] for a
    /// payload of the wrong length.
    pub fn parse(frame: &'a [u8]) -> Result<Self> {
        let (kind, payload) = parts(frame)?;
        let mut r = Reader::new(payload);
        let request = match kind {
            kind::HELLO => Request::Hello,
            kind::BEGIN => Request::Begin {
                size: r.u32_le()?,
                signature: r.array()?,
            },
            kind::CHUNK => {
                let offset = r.u32_le()?;
                let data = r.rest();
                if data.len() > MAX_CHUNK {
                    return Err(Error::BadLength);
                }
                Request::Chunk { offset, data }
            }
            kind::FINISH => Request::Finish,
            kind::REBOOT => Request::Reboot,
            _ => return Err(Error::UnknownId),
        };
        r.finish().map_err(|_| Error::BadLength)?;
        Ok(request)
    }
}

impl<'a> Response<'a> {
    /// Writes the frame into `out`; its length.
    ///
    /// # Errors
    /// [`Error::BufferTooSmall`] when `out` is too short, [`Error::BadLength`] for a
    /// version text longer than [`MAX_VERSION`].
    pub fn emit(&self, out: &mut [u8]) -> Result<usize> {
        match *self {
            Response::Info(info) => {
                if info.version.len() > MAX_VERSION {
                    return Err(Error::BadLength);
                }
                frame(out, kind::INFO, |w| {
                    w.u8(info.state.code())?;
                    w.u32_le(info.slot_size)?;
                    w.put(&info.key_id)?;
                    w.u8(u8::from(info.dev_key))?;
                    w.put(info.version.as_bytes())
                })
            }
            Response::Ready { resume_at } => frame(out, kind::READY, |w| w.u32_le(resume_at)),
            Response::Ack { next } => frame(out, kind::ACK, |w| w.u32_le(next)),
            Response::Verified => frame(out, kind::VERIFIED, |_| Ok(())),
            Response::Rebooting => frame(out, kind::REBOOTING, |_| Ok(())),
            Response::Refused { reason, detail } => frame(out, kind::REFUSED, |w| {
                w.u8(reason.code())?;
                w.u32_le(detail)
            }),
        }
    }

    /// The response in a frame the deframer delivered.
    ///
    /// # Errors
    /// [`Error::UnknownId`] for a kind that is not a response, [`Error::BadLength`] for a
    /// payload of the wrong length, [`Error::OutOfRange`] for an unknown state or reason
    /// or a version that is not UTF-8.
    pub fn parse(frame: &'a [u8]) -> Result<Self> {
        let (kind, payload) = parts(frame)?;
        let mut r = Reader::new(payload);
        let response = match kind {
            kind::INFO => {
                let state = BootState::from_code(r.u8()?)?;
                let slot_size = r.u32_le()?;
                let key_id = r.array()?;
                let dev_key = r.u8()? != 0;
                let text = r.rest();
                if text.len() > MAX_VERSION {
                    return Err(Error::BadLength);
                }
                let version = core::str::from_utf8(text).map_err(|_| Error::OutOfRange)?;
                Response::Info(Info {
                    version,
                    state,
                    slot_size,
                    key_id,
                    dev_key,
                })
            }
            kind::READY => Response::Ready {
                resume_at: r.u32_le()?,
            },
            kind::ACK => Response::Ack { next: r.u32_le()? },
            kind::VERIFIED => Response::Verified,
            kind::REBOOTING => Response::Rebooting,
            kind::REFUSED => Response::Refused {
                reason: Refusal::from_code(r.u8()?)?,
                detail: r.u32_le()?,
            },
            _ => return Err(Error::UnknownId),
        };
        r.finish().map_err(|_| Error::BadLength)?;
        Ok(response)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol_core::wire::{Deframer, Event};

    fn frames_of(bytes: &[u8]) -> Vec<Vec<u8>> {
        let mut d = Deframer::<UpdateFraming, MAX_FRAME>::new(UpdateFraming);
        let mut out = Vec::new();
        d.push(bytes, |e| {
            if let Event::Frame(f) = e {
                out.push(f.to_vec());
            }
        });
        out
    }

    #[test]
    fn every_request_and_response_round_trips() {
        let data = [0x5A; MAX_CHUNK];
        let requests = [
            Request::Hello,
            Request::Begin {
                size: 123_456,
                signature: [7; 64],
            },
            Request::Chunk {
                offset: 4096,
                data: &data,
            },
            Request::Finish,
            Request::Reboot,
        ];
        for req in requests {
            let mut buf = [0; MAX_FRAME];
            let n = req.emit(&mut buf).unwrap();
            let frames = frames_of(&buf[..n]);
            assert_eq!(frames.len(), 1, "{req:?}");
            assert_eq!(Request::parse(&frames[0]), Ok(req));
        }
        let responses = [
            Response::Info(Info {
                version: "0.2.0+abc fc-siyi",
                state: BootState::Trial,
                slot_size: 493_568,
                key_id: [1, 2, 3, 4, 5, 6, 7, 8],
                dev_key: true,
            }),
            Response::Ready { resume_at: 2048 },
            Response::Ack { next: 3072 },
            Response::Verified,
            Response::Rebooting,
            Response::Refused {
                reason: Refusal::WrongOffset,
                detail: 1024,
            },
        ];
        for resp in responses {
            let mut buf = [0; MAX_FRAME];
            let n = resp.emit(&mut buf).unwrap();
            let frames = frames_of(&buf[..n]);
            assert_eq!(Response::parse(&frames[0]), Ok(resp));
        }
    }

    #[test]
    fn a_damaged_chunk_is_dropped_and_the_next_frame_still_found() {
        let data = [0x11; 512];
        let mut buf = [0; 2 * MAX_FRAME];
        let n = Request::Chunk {
            offset: 0,
            data: &data,
        }
        .emit(&mut buf)
        .unwrap();
        let m = Request::Finish.emit(&mut buf[n..]).unwrap();
        buf[100] ^= 0x40; // one bit flipped inside the first chunk
        let frames = frames_of(&buf[..n + m]);
        assert_eq!(frames.len(), 1);
        assert_eq!(Request::parse(&frames[0]), Ok(Request::Finish));
    }

    #[test]
    fn wrong_lengths_and_kinds_are_errors_not_panics() {
        let mut buf = [0; MAX_FRAME];
        let long = [0; MAX_CHUNK + 1];
        assert_eq!(
            Request::Chunk {
                offset: 0,
                data: &long
            }
            .emit(&mut buf),
            Err(Error::BadLength)
        );
        // A Begin whose signature is cut short.
        let n = frame(&mut buf, kind::BEGIN, |w| w.u32_le(1)).unwrap();
        assert_eq!(Request::parse(&buf[..n]), Err(Error::Truncated));
        // A Hello with a payload.
        let n = frame(&mut buf, kind::HELLO, |w| w.u8(0)).unwrap();
        assert_eq!(Request::parse(&buf[..n]), Err(Error::BadLength));
        // A response kind where a request is expected.
        let n = Response::Verified.emit(&mut buf).unwrap();
        assert_eq!(Request::parse(&buf[..n]), Err(Error::UnknownId));
        let n = frame(&mut buf, kind::REFUSED, |w| {
            w.u8(99)?;
            w.u32_le(0)
        })
        .unwrap();
        assert_eq!(Response::parse(&buf[..n]), Err(Error::OutOfRange));
        assert_eq!(
            Request::Hello.emit(&mut buf[..8]),
            Err(Error::BufferTooSmall)
        );
    }
}
