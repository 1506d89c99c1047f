//! Where things lie in the STM32L475VG's flash (1 MiB at 0x0800_0000, two banks of 256
//! pages of 2 KiB): the one place that names these ranges, which `memory.x` follows (a
//! test checks them against each other).
//!
//! | range | what |
//! | --- | --- |
//! | 0x0800_0000..0x080F_C000 | the firmware (`memory.x`'s FLASH: 1008 KiB) |
//! | 0x080F_C000..0x0810_0000 | the persistent store: the last 16 KiB, eight 2 KiB pages of bank 2 ([`crate::store`]) |

/// The flash's first byte.
pub const FLASH_BASE: u32 = 0x0800_0000;
/// The flash's size.
pub const FLASH_SIZE: u32 = 1024 * 1024;
/// A flash page (the erase unit).
pub const PAGE_SIZE: u32 = 2048;
/// The persistent store's first byte.
pub const STORE_START: u32 = 0x080F_C000;
/// The byte after the persistent store (the end of the flash).
pub const STORE_END: u32 = FLASH_BASE + FLASH_SIZE;
/// The firmware's flash (`memory.x`'s FLASH region): everything before the store.
pub const FIRMWARE_SIZE: u32 = STORE_START - FLASH_BASE;

/// The store's range as offsets from the flash's base (how the flash driver addresses it).
#[must_use]
pub const fn store_offsets() -> core::ops::Range<u32> {
    (STORE_START - FLASH_BASE)..(STORE_END - FLASH_BASE)
}

const _: () =
    assert!(STORE_START.is_multiple_of(PAGE_SIZE) && (STORE_END - STORE_START) == 8 * PAGE_SIZE);
// Bank 2 starts half-way: the store never shares a bank with the code that runs.
const _: () = assert!(STORE_START >= FLASH_BASE + FLASH_SIZE / 2);
