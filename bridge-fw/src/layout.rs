//! The persistent store's place in the flash, as the firmware's flash driver addresses it.
//! Every range comes from the one flash table, [`bridge_update::layout`] (bootloader, its
//! state, the two slots, the store), which also writes every `memory.x`.

use bridge_update::layout::{FLASH_BASE, STORE};

pub use bridge_update::layout::PAGE as PAGE_SIZE;

/// The persistent store's first byte: the last 16 KiB, eight 2 KiB pages of bank 2.
pub const STORE_START: u32 = STORE.start;
/// The byte after the persistent store (the end of the flash).
pub const STORE_END: u32 = STORE.end();

/// The store's range as offsets from the flash's base (how the flash driver addresses it).
#[must_use]
pub const fn store_offsets() -> core::ops::Range<u32> {
    STORE.offset()..(STORE.offset() + STORE.size)
}

const _: () =
    assert!(STORE_START.is_multiple_of(PAGE_SIZE) && (STORE_END - STORE_START) == 8 * PAGE_SIZE);
// Bank 2 starts half-way: the store never shares a bank with the code that runs.
const _: () = assert!(STORE_START >= FLASH_BASE + bridge_update::layout::FLASH_SIZE / 2);
