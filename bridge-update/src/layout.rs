//! The flash layout of the bridge MCU (STM32L475VG: 1 MiB of flash in 2 KiB pages, 96 KiB
//! of SRAM1), the one place every memory map comes from.
//!
//! | region | start | size | what |
//! | --- | --- | --- | --- |
//! | [`BOOTLOADER`] | 0x0800_0000 | 32 KiB | the bootloader (`bootloader/`): swaps and reverts, then jumps to the active slot |
//! | [`BOOT_STATE`] | 0x0800_8000 | 8 KiB | embassy-boot's state: magic word and swap/revert progress |
//! | [`ACTIVE`] | 0x0800_A000 | 482 KiB | the running firmware (`bridge-fw` links here) |
//! | [`DFU`] | 0x0808_2800 | 484 KiB | the update slot: a received image, then the previous one after a swap |
//! | [`RESERVED`] | 0x080F_B800 | 2 KiB | unused (what the slot pair leaves before the store) |
//! | [`STORE`] | 0x080F_C000 | 16 KiB | the persistent store (settings, signing timestamps): the last eight pages |
//!
//! The bootloader's and the firmware's `memory.x` are written from these constants by
//! their build scripts ([`memory_x`]); the firmware's update slot and the bootloader's
//! partitions are made from them too, so no address is written twice. The compile-time
//! checks below refuse a table whose regions overlap, are not page-aligned, leave the
//! chip, or break embassy-boot's rules (the update slot one page larger than the active
//! one; the state large enough for the progress of a swap and a revert).

use core::fmt;

/// Flash base address (the bootloader's vector table, aliased at 0 at reset).
pub const FLASH_BASE: u32 = 0x0800_0000;
/// Flash size: 1 MiB (two banks of 512 KiB).
pub const FLASH_SIZE: u32 = 1024 * 1024;
/// Erase unit (a page, in either bank).
pub const PAGE: u32 = 2048;
/// Program unit (a double word, the smallest write the flash takes).
pub const WRITE: u32 = 8;
/// SRAM1: 96 KiB at 0x2000_0000 (SRAM2 is not used by the linker).
pub const RAM: Region = Region::new("RAM", 0x2000_0000, 96 * 1024);

/// One region of the map: absolute start address and size in bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Region {
    /// Its name in `memory.x` and in messages.
    pub name: &'static str,
    /// First address.
    pub start: u32,
    /// Bytes.
    pub size: u32,
}

impl Region {
    /// A region.
    #[must_use]
    pub const fn new(name: &'static str, start: u32, size: u32) -> Self {
        Region { name, start, size }
    }

    /// The address after its last byte (saturating: a region at the top of the address
    /// space ends there).
    #[must_use]
    pub const fn end(&self) -> u32 {
        self.start.saturating_add(self.size)
    }

    /// Its start as an offset from [`FLASH_BASE`] (what embassy-stm32's flash driver and
    /// embassy-boot's partitions take).
    #[must_use]
    pub const fn offset(&self) -> u32 {
        self.start.saturating_sub(FLASH_BASE)
    }

    /// Size in KiB (rounded down).
    #[must_use]
    pub const fn kib(&self) -> u32 {
        self.size / 1024
    }
}

/// The bootloader: 32 KiB (its build is about a third of it: room for defmt and growth).
pub const BOOTLOADER: Region = Region::new("BOOTLOADER", FLASH_BASE, 32 * 1024);
/// embassy-boot's state: a magic word, a progress-validity word and one word per page
/// step of a swap and of a revert (`2 + 4 × pages` double words: 966 of the 1 024 that
/// 8 KiB hold for the 241 pages of the active slot).
pub const BOOT_STATE: Region = Region::new("BOOTLOADER_STATE", BOOTLOADER.end(), 8 * 1024);
/// The store's 16 KiB, the last eight pages of the chip (issue 33: settings and signing
/// timestamps, wear-levelled). Fixed: stored data must survive every update.
pub const STORE: Region = Region::new("STORE", 0x080F_C000, 16 * 1024);
/// The active slot: as large as the room between the state and the store allows, the update
/// slot being one page larger ([`DFU`]).
pub const ACTIVE: Region = Region::new("FLASH", BOOT_STATE.end(), active_size());
/// The update slot: one page more than the active slot (embassy-boot's swap moves each page
/// of the active slot one page up in it).
pub const DFU: Region = Region::new("DFU", ACTIVE.end(), ACTIVE.size + PAGE);
/// What the slot pair leaves before the store (less than two pages): not used.
pub const RESERVED: Region =
    Region::new("RESERVED", DFU.end(), STORE.start.saturating_sub(DFU.end()));

/// Every flash region, in address order.
pub const FLASH_REGIONS: [Region; 6] = [BOOTLOADER, BOOT_STATE, ACTIVE, DFU, RESERVED, STORE];

// Constant evaluation: an overflow or an index out of range is a compile error, not a panic.
#[allow(clippy::arithmetic_side_effects)]
const fn active_size() -> u32 {
    let room = STORE.start - BOOT_STATE.end();
    // active + (active + PAGE) <= room, in whole pages
    (room - PAGE) / 2 / PAGE * PAGE
}

/// The page steps of a swap plus those of a revert, each a progress word in the state.
#[allow(clippy::arithmetic_side_effects)]
const fn state_words_needed() -> u32 {
    2 + 4 * (ACTIVE.size / PAGE)
}

// The layout's rules, checked when anything that uses it compiles (constant evaluation: an
// index out of range or an overflow here is a compile error).
#[allow(clippy::indexing_slicing, clippy::arithmetic_side_effects)]
const _: () = {
    let mut i = 0;
    while i < FLASH_REGIONS.len() {
        let r = FLASH_REGIONS[i];
        assert!(
            r.start.is_multiple_of(PAGE) && r.size.is_multiple_of(PAGE),
            "regions are whole pages"
        );
        assert!(
            r.start >= FLASH_BASE && r.end() <= FLASH_BASE + FLASH_SIZE,
            "regions lie in the flash"
        );
        if i > 0 {
            assert!(
                FLASH_REGIONS[i - 1].end() == r.start,
                "regions are contiguous, in order, without overlap"
            );
        }
        i += 1;
    }
    assert!(
        BOOTLOADER.start == FLASH_BASE,
        "the bootloader holds the reset vector"
    );
    assert!(
        STORE.start == 0x080F_C000 && STORE.end() == 0x0810_0000,
        "the store is the last 16 KiB"
    );
    assert!(
        DFU.size >= ACTIVE.size + PAGE,
        "embassy-boot: the update slot is a page larger"
    );
    assert!(
        state_words_needed() <= BOOT_STATE.size / WRITE,
        "embassy-boot: state words for a swap and a revert"
    );
    assert!(
        RESERVED.size < 2 * PAGE,
        "the slots take all the room but what a page pair cannot use"
    );
};

/// Which image a `memory.x` is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Image {
    /// The bootloader: linked at [`BOOTLOADER`].
    Bootloader,
    /// The firmware (`bridge-fw`, and the size probe that stands for it): linked at
    /// [`ACTIVE`], the slot the bootloader jumps to.
    Firmware,
    /// A binary that is linked and never flashed (`host-tests/no-panic`, a link-time proof
    /// with every entry point, 830 KB of code at opt-level 3): the whole flash.
    LinkOnly,
}

/// Writes the `memory.x` linker script of `image` (cortex-m-rt's `FLASH` and `RAM`
/// regions, the whole table as a comment).
///
/// # Errors
/// Only `out`'s own.
pub fn memory_x(image: Image, out: &mut impl fmt::Write) -> fmt::Result {
    let flash = match image {
        Image::Bootloader => BOOTLOADER,
        Image::Firmware => ACTIVE,
        Image::LinkOnly => Region::new("FLASH", FLASH_BASE, FLASH_SIZE),
    };
    writeln!(
        out,
        "/* Generated by bridge_update::layout::memory_x: do not edit. */"
    )?;
    writeln!(
        out,
        "/* STM32L475VG flash map ({} KiB, {} B pages):",
        FLASH_SIZE / 1024,
        PAGE
    )?;
    for r in FLASH_REGIONS {
        writeln!(
            out,
            "   {:<17} {:#010x}..{:#010x} {:>4} KiB",
            r.name,
            r.start,
            r.end(),
            r.kib()
        )?;
    }
    writeln!(out, "   This image: {image:?}. */")?;
    writeln!(out, "MEMORY")?;
    writeln!(out, "{{")?;
    writeln!(
        out,
        "  FLASH : ORIGIN = {:#010X}, LENGTH = {}K",
        flash.start,
        flash.kib()
    )?;
    writeln!(
        out,
        "  RAM   : ORIGIN = {:#010X}, LENGTH = {}K",
        RAM.start,
        RAM.kib()
    )?;
    writeln!(out, "}}")
}

/// For a build script (feature `std`): writes `image`'s `memory.x` into `OUT_DIR` and puts
/// that directory on the linker's search path (cortex-m-rt's `link.x` includes
/// `memory.x`). Exits the build with a message when it cannot.
#[cfg(feature = "std")]
pub fn build_script(image: Image) {
    use std::string::String;
    let out = std::path::PathBuf::from(std::env::var_os("OUT_DIR").unwrap_or_default());
    let mut text = String::new();
    let written = memory_x(image, &mut text)
        .map_err(|e| std::format!("{e}"))
        .and_then(|()| std::fs::write(out.join("memory.x"), text).map_err(|e| std::format!("{e}")));
    if let Err(e) = written {
        std::eprintln!("memory.x: {e}");
        std::process::exit(1);
    }
    std::println!("cargo:rustc-link-search={}", out.display());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_as_the_book_gives_it() {
        assert_eq!(
            (BOOTLOADER.start, BOOTLOADER.size),
            (0x0800_0000, 32 * 1024)
        );
        assert_eq!((BOOT_STATE.start, BOOT_STATE.size), (0x0800_8000, 8 * 1024));
        assert_eq!((ACTIVE.start, ACTIVE.size), (0x0800_A000, 482 * 1024));
        assert_eq!((DFU.start, DFU.size), (0x0808_2800, 484 * 1024));
        assert_eq!((RESERVED.start, RESERVED.size), (0x080F_B800, 2 * 1024));
        assert_eq!((STORE.start, STORE.end()), (0x080F_C000, 0x0810_0000));
        let total: u32 = FLASH_REGIONS.iter().map(|r| r.size).sum();
        assert_eq!(total, FLASH_SIZE);
        assert_eq!(state_words_needed(), 966);
    }

    #[test]
    fn memory_x_links_each_image_at_its_region() {
        let mut fw = String::new();
        memory_x(Image::Firmware, &mut fw).unwrap();
        assert!(
            fw.contains("FLASH : ORIGIN = 0x0800A000, LENGTH = 482K"),
            "{fw}"
        );
        assert!(
            fw.contains("RAM   : ORIGIN = 0x20000000, LENGTH = 96K"),
            "{fw}"
        );
        let mut bl = String::new();
        memory_x(Image::Bootloader, &mut bl).unwrap();
        assert!(
            bl.contains("FLASH : ORIGIN = 0x08000000, LENGTH = 32K"),
            "{bl}"
        );
        // The store is never in a linked region.
        for text in [&fw, &bl] {
            assert!(
                text.contains("STORE             0x080fc000..0x08100000   16 KiB"),
                "{text}"
            );
        }
    }
}
