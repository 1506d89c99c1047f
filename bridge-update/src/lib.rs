//! Firmware updates of the K40T bridge.
//!
//! - [`layout`]: the flash map (bootloader, its state, the active and update slots, the
//!   store), the one place every `memory.x` and every partition comes from;
//! - [`wire`]: the update protocol's frames (chunks with a CRC-32 each);
//! - [`Receiver`]: the board's side, sans-IO, over a [`Slot`] ([`FlashSlot`]: embassy-boot's
//!   partitions and state, feature `embassy-boot`);
//! - [`Trial`]: when a freshly swapped-in image confirms itself (the rollback rule);
//! - [`client`] (feature `std`): the client's side, sans-IO, and the protocol's bytes on
//!   the wire;
//! - [`keys`] (feature `keys`): key files, the development key, signing;
//! - [`sim`] (feature `sim`): a board's flash on the host that loses power at any step,
//!   with embassy-boot's bootloader on it.
//!
//! A crate of its own rather than a part of the bridge engine: the update is the same
//! whatever FC side is built, the client (`gimbal`) and the bootloader's build share it,
//! and the engine's size and no-panic proofs stay as they are.
#![cfg_attr(not(test), no_std)]
#![cfg_attr(
    test,
    allow(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::indexing_slicing,
        clippy::arithmetic_side_effects
    )
)]

#[cfg(feature = "std")]
extern crate std;

#[cfg(feature = "std")]
pub mod client;
#[cfg(feature = "keys")]
pub mod keys;
pub mod layout;
mod receiver;
#[cfg(feature = "sim")]
pub mod sim;
mod slot;
mod trial;
pub mod wire;

pub use receiver::{Receiver, VERIFY_STEP, key_id};
#[cfg(feature = "embassy-boot")]
pub use slot::FlashSlot;
pub use slot::{Slot, SlotError};
pub use trial::{CONFIRM_AFTER_S, Trial};
