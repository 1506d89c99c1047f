//! A board's flash on the host (feature `sim`): a NOR flash model that can lose power at
//! any program or erase step, the bootloader's partitions over it, and embassy-boot's own
//! `BootLoader` run on it, for the power-cut tests and the update's host tests.
//!
//! The model's atomic steps are the chip's: programming one double word (8 bytes) and
//! erasing one page. A power cut falls between two steps: a write of many double words or
//! an erase of many pages stops part-way, what was done stays done. (A cut inside one
//! double word's programming leaves a word the STM32L4's ECC flags; no bootloader can
//! tell what it held, and the model does not make one.)

extern crate std;

use core::cell::RefCell;
use std::rc::Rc;
use std::vec;
use std::vec::Vec;

use embassy_boot::{BlockingFirmwareState, BootLoader, BootLoaderConfig, State};
use embassy_embedded_hal::flash::partition::BlockingPartition;
use embassy_sync::blocking_mutex::Mutex;
use embassy_sync::blocking_mutex::raw::NoopRawMutex;
use embedded_storage::nor_flash::{
    ErrorType, NorFlash, NorFlashError, NorFlashErrorKind, ReadNorFlash,
};

use crate::FlashSlot;
use crate::layout::{PAGE, WRITE};

/// The power failed (every operation fails until [`SimFlash::power_on`]), or an operation
/// broke the flash's rules (unaligned, out of range, programming a word not erased).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SimError {
    /// No power.
    PowerLost,
    /// Against the flash's rules (the model's way of catching a caller's bug).
    Misuse(NorFlashErrorKind),
}

impl NorFlashError for SimError {
    fn kind(&self) -> NorFlashErrorKind {
        match self {
            SimError::PowerLost => NorFlashErrorKind::Other,
            SimError::Misuse(k) => *k,
        }
    }
}

/// A NOR flash of 2 KiB pages and 8-byte program words, erased to 0xFF, that may lose power.
#[derive(Debug, Clone)]
pub struct SimFlash {
    bytes: Vec<u8>,
    /// Steps left before the power fails (`None`: it never does).
    budget: Option<u64>,
    powered: bool,
    /// Steps done since the start (every program word and page erase).
    pub steps: u64,
}

#[allow(clippy::arithmetic_side_effects, clippy::indexing_slicing)]
impl SimFlash {
    /// An erased flash of `size` bytes.
    #[must_use]
    pub fn new(size: usize) -> Self {
        SimFlash {
            bytes: vec![0xFF; size],
            budget: None,
            powered: true,
            steps: 0,
        }
    }

    /// The power fails after `steps` more steps.
    pub fn cut_after(&mut self, steps: u64) {
        self.budget = Some(steps);
    }

    /// Power back, no cut planned.
    pub fn power_on(&mut self) {
        self.powered = true;
        self.budget = None;
    }

    /// Whether the power failed.
    #[must_use]
    pub fn lost_power(&self) -> bool {
        !self.powered
    }

    /// The contents.
    #[must_use]
    pub fn bytes(&self) -> &[u8] {
        &self.bytes
    }

    /// Writes bytes as a programmer (a probe) would, without steps or rules.
    pub fn load(&mut self, offset: usize, data: &[u8]) {
        self.bytes[offset..offset + data.len()].copy_from_slice(data);
    }

    fn step(&mut self) -> Result<(), SimError> {
        if !self.powered {
            return Err(SimError::PowerLost);
        }
        if let Some(b) = self.budget.as_mut() {
            if *b == 0 {
                self.powered = false;
                return Err(SimError::PowerLost);
            }
            *b -= 1;
        }
        self.steps += 1;
        Ok(())
    }

    fn check(&self, offset: u32, len: usize, align: u32) -> Result<(), SimError> {
        if !offset.is_multiple_of(align) || !len.is_multiple_of(align as usize) {
            return Err(SimError::Misuse(NorFlashErrorKind::NotAligned));
        }
        if offset as usize + len > self.bytes.len() {
            return Err(SimError::Misuse(NorFlashErrorKind::OutOfBounds));
        }
        Ok(())
    }
}

impl ErrorType for SimFlash {
    type Error = SimError;
}

#[allow(clippy::arithmetic_side_effects, clippy::indexing_slicing)]
impl ReadNorFlash for SimFlash {
    const READ_SIZE: usize = 1;

    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), SimError> {
        if !self.powered {
            return Err(SimError::PowerLost);
        }
        self.check(offset, bytes.len(), 1)?;
        let at = offset as usize;
        bytes.copy_from_slice(&self.bytes[at..at + bytes.len()]);
        Ok(())
    }

    fn capacity(&self) -> usize {
        self.bytes.len()
    }
}

#[allow(clippy::arithmetic_side_effects, clippy::indexing_slicing)]
impl NorFlash for SimFlash {
    const WRITE_SIZE: usize = WRITE as usize;
    const ERASE_SIZE: usize = PAGE as usize;

    fn erase(&mut self, from: u32, to: u32) -> Result<(), SimError> {
        if to < from {
            return Err(SimError::Misuse(NorFlashErrorKind::OutOfBounds));
        }
        self.check(from, (to - from) as usize, PAGE)?;
        for page in (from..to).step_by(PAGE as usize) {
            self.step()?;
            let at = page as usize;
            self.bytes[at..at + PAGE as usize].fill(0xFF);
        }
        Ok(())
    }

    fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), SimError> {
        self.check(offset, bytes.len(), WRITE)?;
        for (i, word) in bytes.chunks(WRITE as usize).enumerate() {
            let at = offset as usize + i * WRITE as usize;
            let erased = self.bytes[at..at + word.len()].iter().all(|&b| b == 0xFF);
            if !erased && word.iter().any(|&b| b != 0) {
                // The STM32L4 refuses to program a double word that is not erased (but
                // for all zeros: PROGERR in the reference manual's FLASH_SR).
                return Err(SimError::Misuse(NorFlashErrorKind::Other));
            }
            self.step()?;
            self.bytes[at..at + word.len()].copy_from_slice(word);
        }
        Ok(())
    }
}

/// A small board: the real layout's shape (bootloader state, active slot, update slot one
/// page larger) with fewer pages, so that a test can cut the power at every step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SimLayout {
    /// Pages of the active slot.
    pub active_pages: u32,
}

#[allow(clippy::arithmetic_side_effects)]
impl SimLayout {
    /// The state partition: one page (enough for `2 + 4 × pages` words up to 63 pages).
    #[must_use]
    pub const fn state(&self) -> (u32, u32) {
        (0, PAGE)
    }
    /// The active slot.
    #[must_use]
    pub const fn active(&self) -> (u32, u32) {
        (PAGE, self.active_pages * PAGE)
    }
    /// The update slot.
    #[must_use]
    pub const fn dfu(&self) -> (u32, u32) {
        (
            PAGE + self.active_pages * PAGE,
            (self.active_pages + 1) * PAGE,
        )
    }
    /// The whole flash.
    #[must_use]
    pub const fn size(&self) -> usize {
        ((2 * self.active_pages + 2) * PAGE) as usize
    }
}

/// What the bootloader did.
#[derive(Debug, PartialEq, Eq)]
pub struct Booted {
    /// embassy-boot's state after `prepare_boot`.
    pub state: State,
}

/// A board on the host: its flash, shared by the bootloader's and the firmware's partitions.
#[derive(Clone)]
pub struct SimBoard {
    /// The layout.
    pub layout: SimLayout,
    /// The flash.
    pub flash: Rc<Mutex<NoopRawMutex, RefCell<SimFlash>>>,
}

/// The update slot of a [`SimBoard`], as the firmware uses it.
pub type SimSlot<'a> = FlashSlot<
    'a,
    BlockingPartition<'a, NoopRawMutex, SimFlash>,
    BlockingPartition<'a, NoopRawMutex, SimFlash>,
>;

#[allow(clippy::arithmetic_side_effects, clippy::indexing_slicing)]
impl SimBoard {
    /// A board whose active slot holds `image` (flashed by probe), state erased.
    #[must_use]
    pub fn new(layout: SimLayout, image: &[u8]) -> Self {
        let mut flash = SimFlash::new(layout.size());
        flash.load(layout.active().0 as usize, image);
        SimBoard {
            layout,
            flash: Rc::new(Mutex::new(RefCell::new(flash))),
        }
    }

    /// Runs `f` on the flash model.
    pub fn with_flash<R>(&self, f: impl FnOnce(&mut SimFlash) -> R) -> R {
        self.flash.lock(|c| f(&mut c.borrow_mut()))
    }

    /// The firmware's update slot (`aligned`: embassy-boot's word buffer).
    ///
    /// # Errors
    /// The state cannot be read (no power).
    pub fn slot<'a>(&'a self, aligned: &'a mut [u8; 8]) -> Result<SimSlot<'a>, crate::SlotError> {
        let (ds, dl) = self.layout.dfu();
        let (ss, sl) = self.layout.state();
        FlashSlot::new(
            BlockingPartition::new(&self.flash, ds, dl),
            BlockingPartition::new(&self.flash, ss, sl),
            aligned,
        )
    }

    /// A reset: embassy-boot's bootloader prepares the boot (swap, revert, or nothing),
    /// with a page-sized buffer as the bootloader crate uses.
    ///
    /// # Errors
    /// A flash error (the power failed during a swap or a revert).
    pub fn reset(&self) -> Result<Booted, embassy_boot::BootError> {
        let (a, al) = self.layout.active();
        let (d, dl) = self.layout.dfu();
        let (s, sl) = self.layout.state();
        let mut loader = BootLoader::new(BootLoaderConfig {
            active: BlockingPartition::new(&self.flash, a, al),
            dfu: BlockingPartition::new(&self.flash, d, dl),
            state: BlockingPartition::new(&self.flash, s, sl),
        });
        let mut buf = [0u8; PAGE as usize];
        let state = loader.prepare_boot(&mut buf)?;
        Ok(Booted { state })
    }

    /// The active slot's first `len` bytes (what the bootloader jumps to).
    #[must_use]
    pub fn active(&self, len: usize) -> Vec<u8> {
        let at = self.layout.active().0 as usize;
        self.with_flash(|f| f.bytes()[at..at + len].to_vec())
    }

    /// The running image confirms itself (embassy-boot's `mark_booted`).
    ///
    /// # Errors
    /// A flash error.
    pub fn confirm(&self) -> Result<(), embassy_boot::FirmwareUpdaterError> {
        let (s, sl) = self.layout.state();
        let mut aligned = [0u8; 8];
        let mut state =
            BlockingFirmwareState::new(BlockingPartition::new(&self.flash, s, sl), &mut aligned);
        state.mark_booted()
    }
}
