//! The board's side of the update protocol, sans-IO: requests in, responses out, the update
//! slot behind the [`Slot`] trait.
//!
//! The rules it keeps:
//! - a chunk is written only at the offset that follows the last one written, so the slot
//!   fills contiguously from 0; a chunk sent again (its ACK lost) is acknowledged, not
//!   written twice;
//! - a transfer interrupted (the link lost, the client restarted) resumes where it stopped
//!   when the client begins the same image again (same size and signature), else starts
//!   at 0;
//! - nothing is written while the running image is on trial (the update slot then holds
//!   the previous image, the one a rollback needs), and a verified image waiting for its
//!   swap is un-marked before its slot is written again;
//! - the image is marked for the swap only after its ed25519 signature has been checked
//!   against the SHA-512 of the slot's contents as read back from the flash, with the key
//!   the firmware was built with; the check runs in steps ([`Receiver::work`]) so the
//!   firmware's other tasks (and the watchdog's feed) keep running.

use ed25519_dalek::{Signature, VerifyingKey};
use sha2::{Digest, Sha512};

use crate::slot::{Slot, SlotError};
use crate::wire::{
    BootState, Info, MAX_CHUNK, MAX_VERSION, Refusal, Request, Response, SIGNATURE_LEN,
};

/// Bytes of the slot hashed per [`Receiver::work`] call: 4 KiB, about 10 ms of SHA-512 on
/// the 80 MHz Cortex-M4 (the watchdog's time-out is 750 ms).
pub const VERIFY_STEP: usize = 4096;

/// The first 8 bytes of the SHA-512 of a public key: how the board names the key it
/// accepts ([`Info::key_id`]).
#[must_use]
pub fn key_id(public_key: &[u8; 32]) -> [u8; 8] {
    let digest = Sha512::digest(public_key);
    let mut id = [0; 8];
    for (d, s) in id.iter_mut().zip(digest.iter()) {
        *d = *s;
    }
    id
}

/// A transfer under way.
#[derive(Debug, Clone)]
struct Transfer {
    size: u32,
    signature: [u8; SIGNATURE_LEN],
    /// Bytes written, contiguous from 0.
    next: u32,
}

/// A signature check under way.
#[derive(Clone)]
struct Check {
    digest: Sha512,
    hashed: u32,
}

/// The board's side of the protocol.
pub struct Receiver<'a> {
    public_key: [u8; 32],
    dev_key: bool,
    version: &'a str,
    transfer: Option<Transfer>,
    check: Option<Check>,
    reboot: bool,
}

fn refused(reason: Refusal) -> Response<'static> {
    Response::Refused { reason, detail: 0 }
}

impl From<SlotError> for Refusal {
    fn from(e: SlotError) -> Self {
        match e {
            SlotError::Flash => Refusal::Flash,
            SlotError::NotConfirmed => Refusal::NotConfirmed,
        }
    }
}

impl<'a> Receiver<'a> {
    /// A receiver that accepts images signed by `public_key` (`dev_key`: a development key,
    /// said so in [`Info`]) and reports `version` as the running firmware's (its first
    /// [`MAX_VERSION`] bytes, cut at a character's boundary).
    #[must_use]
    pub fn new(public_key: [u8; 32], dev_key: bool, version: &'a str) -> Self {
        let mut end = version.len().min(MAX_VERSION);
        while !version.is_char_boundary(end) {
            end = end.saturating_sub(1);
        }
        let version = version.get(..end).unwrap_or_default();
        Receiver {
            public_key,
            dev_key,
            version,
            transfer: None,
            check: None,
            reboot: false,
        }
    }

    /// Whether a signature check is under way: call [`Receiver::work`] until it answers.
    #[must_use]
    pub fn busy(&self) -> bool {
        self.check.is_some()
    }

    /// Whether the client asked for a reset: reset once the [`Response::Rebooting`] has
    /// left.
    #[must_use]
    pub fn reboot_requested(&self) -> bool {
        self.reboot
    }

    /// Bytes received of the transfer under way (for a progress log).
    #[must_use]
    pub fn received(&self) -> Option<(u32, u32)> {
        self.transfer.as_ref().map(|t| (t.next, t.size))
    }

    /// Handles one request. `None` only for [`Request::Finish`] when the check has
    /// begun: [`Receiver::work`] gives the answer.
    pub fn handle<S: Slot>(&mut self, request: Request<'_>, slot: &mut S) -> Option<Response<'a>> {
        Some(match request {
            Request::Hello => match slot.state() {
                Ok(state) => Response::Info(Info {
                    version: self.version,
                    state,
                    slot_size: slot.capacity(),
                    key_id: key_id(&self.public_key),
                    dev_key: self.dev_key,
                }),
                Err(e) => refused(e.into()),
            },
            Request::Begin { size, signature } => self.begin(size, signature, slot),
            Request::Chunk { offset, data } => self.chunk(offset, data, slot),
            Request::Finish => {
                let complete = self.transfer.as_ref().is_some_and(|t| t.next == t.size);
                if !complete {
                    return Some(refused(Refusal::NoTransfer));
                }
                self.check = Some(Check {
                    digest: Sha512::new(),
                    hashed: 0,
                });
                return None;
            }
            Request::Reboot => {
                self.reboot = true;
                Response::Rebooting
            }
        })
    }

    fn begin<S: Slot>(
        &mut self,
        size: u32,
        signature: [u8; SIGNATURE_LEN],
        slot: &mut S,
    ) -> Response<'a> {
        if size == 0 || size > slot.capacity() {
            return refused(Refusal::TooLarge);
        }
        match slot.state() {
            Ok(BootState::Confirmed | BootState::RolledBack) => {}
            // A verified image not yet swapped in: un-mark it before its slot is written.
            Ok(BootState::SwapPending) => {
                if let Err(e) = slot.cancel_swap() {
                    return refused(e.into());
                }
            }
            Ok(BootState::Trial) => return refused(Refusal::NotConfirmed),
            Err(e) => return refused(e.into()),
        }
        let same = self
            .transfer
            .as_ref()
            .is_some_and(|t| t.size == size && t.signature == signature);
        if !same {
            slot.begin();
            self.transfer = Some(Transfer {
                size,
                signature,
                next: 0,
            });
        }
        Response::Ready {
            resume_at: self.transfer.as_ref().map_or(0, |t| t.next),
        }
    }

    fn chunk<S: Slot>(&mut self, offset: u32, data: &[u8], slot: &mut S) -> Response<'a> {
        let Some(t) = self.transfer.as_mut() else {
            return refused(Refusal::NoTransfer);
        };
        let Ok(len) = u32::try_from(data.len()) else {
            return refused(Refusal::BadChunk);
        };
        let Some(end) = offset.checked_add(len) else {
            return refused(Refusal::BadChunk);
        };
        if data.is_empty() || data.len() > MAX_CHUNK || end > t.size {
            return refused(Refusal::BadChunk);
        }
        if end <= t.next {
            // Sent again after a lost ACK: already written.
            return Response::Ack { next: t.next };
        }
        if offset != t.next {
            return Response::Refused {
                reason: Refusal::WrongOffset,
                detail: t.next,
            };
        }
        // The flash takes whole double words: every chunk but the image's last is a
        // multiple of 8 bytes, so every chunk starts on one.
        if !len.is_multiple_of(8) && end != t.size {
            return refused(Refusal::BadChunk);
        }
        if let Err(e) = slot.write(offset, data) {
            return refused(e.into());
        }
        t.next = end;
        Response::Ack { next: end }
    }

    /// Continues the signature check: hashes the next [`VERIFY_STEP`] bytes of the slot,
    /// and after the last one checks the signature and marks the image for the swap.
    /// `Some` with the answer to [`Request::Finish`] when done, `None` while under way
    /// (and when nothing is).
    pub fn work<S: Slot>(&mut self, slot: &mut S) -> Option<Response<'a>> {
        let check = self.check.as_mut()?;
        let Some(t) = self.transfer.as_ref() else {
            self.check = None;
            return Some(refused(Refusal::NoTransfer));
        };
        let mut buf = [0u8; VERIFY_STEP];
        let left = usize::try_from(t.size.saturating_sub(check.hashed)).unwrap_or(VERIFY_STEP);
        if left > 0 {
            let part = buf.get_mut(..left.min(VERIFY_STEP)).unwrap_or_default();
            if slot.read(check.hashed, part).is_err() {
                self.check = None;
                return Some(refused(Refusal::Flash));
            }
            check.digest.update(&*part);
            let n = u32::try_from(part.len()).unwrap_or(0);
            check.hashed = check.hashed.saturating_add(n);
            return None;
        }
        let digest = check.digest.clone().finalize();
        self.check = None;
        let holds = VerifyingKey::from_bytes(&self.public_key)
            .and_then(|key| key.verify_strict(&digest, &Signature::from_bytes(&t.signature)))
            .is_ok();
        if !holds {
            return Some(refused(Refusal::BadSignature));
        }
        Some(match slot.mark_updated() {
            Ok(()) => Response::Verified,
            Err(e) => refused(e.into()),
        })
    }
}
