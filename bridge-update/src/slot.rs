//! The update slot as the receiver sees it, and its implementation over embassy-boot
//! ([`FlashSlot`], feature `embassy-boot`).

use crate::wire::BootState;

/// Why the slot refused an operation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SlotError {
    /// The flash refused a read, write or erase (or lost power).
    Flash,
    /// The running image is on trial (or a swap is pending): the update slot holds the
    /// image a rollback needs and is not written.
    NotConfirmed,
}

/// The update slot and the boot state, as the [`Receiver`](crate::Receiver) uses them.
pub trait Slot {
    /// Bytes the slot takes (the largest image).
    fn capacity(&self) -> u32;
    /// The running image's state.
    ///
    /// # Errors
    /// [`SlotError::Flash`] when the state cannot be read.
    fn state(&mut self) -> Result<BootState, SlotError>;
    /// A new transfer starts at offset 0: every page is erased again before it is written.
    fn begin(&mut self);
    /// Writes `data` at `offset`, erasing each page at the first write into it since
    /// [`Slot::begin`]. Writes come in order, contiguous from 0 (or from where an
    /// interrupted transfer stopped); `offset` is a multiple of 8, and so is `data`'s
    /// length except at the image's end.
    ///
    /// # Errors
    /// [`SlotError::NotConfirmed`] while the running image is not confirmed;
    /// [`SlotError::Flash`].
    fn write(&mut self, offset: u32, data: &[u8]) -> Result<(), SlotError>;
    /// Reads the slot back.
    ///
    /// # Errors
    /// [`SlotError::Flash`].
    fn read(&mut self, offset: u32, buf: &mut [u8]) -> Result<(), SlotError>;
    /// Marks the slot's image for the swap at the next reset.
    ///
    /// # Errors
    /// [`SlotError::Flash`].
    fn mark_updated(&mut self) -> Result<(), SlotError>;
    /// Withdraws a [`Slot::mark_updated`] that no reset has acted on yet.
    ///
    /// # Errors
    /// [`SlotError::Flash`].
    fn cancel_swap(&mut self) -> Result<(), SlotError>;
    /// Confirms the running image (after a swap: no rollback at the next reset).
    ///
    /// # Errors
    /// [`SlotError::Flash`].
    fn mark_booted(&mut self) -> Result<(), SlotError>;
}

#[cfg(feature = "embassy-boot")]
pub use flash::FlashSlot;

#[cfg(feature = "embassy-boot")]
mod flash {
    use embassy_boot::{BlockingFirmwareState, State};
    use embedded_storage::nor_flash::NorFlash;

    use super::{Slot, SlotError};
    use crate::wire::BootState;

    /// The update slot on a flash: `DFU` (the update slot's partition) written page by
    /// page, `STATE` (embassy-boot's state partition) through embassy-boot's
    /// [`BlockingFirmwareState`], so the bootloader reads exactly what it expects.
    ///
    /// embassy-boot's `FirmwareUpdater::write_firmware` erases a page when a write enters
    /// a page other than the one it erased last, for the life of the updater: a transfer
    /// restarted inside that page would then program flash that is not erased. This slot
    /// keeps the same rule per transfer ([`Slot::begin`] forgets the erased pages) and
    /// leaves the state partition, the part the bootloader depends on, to embassy-boot.
    pub struct FlashSlot<'d, DFU: NorFlash, STATE: NorFlash> {
        dfu: DFU,
        state: BlockingFirmwareState<'d, STATE>,
        /// Pages below this offset were erased in this transfer.
        erased_to: u32,
        /// The state read `Swap` at start: this image is on trial.
        trial: bool,
        /// This run marked an image for the swap.
        pending: bool,
    }

    fn flash<E>(_: E) -> SlotError {
        SlotError::Flash
    }

    impl<'d, DFU: NorFlash, STATE: NorFlash> FlashSlot<'d, DFU, STATE> {
        /// The slot over its two partitions; `aligned` is a buffer of `STATE::WRITE_SIZE`
        /// bytes (embassy-boot's rule). Reads the state: `Swap` now means this image was
        /// just swapped in and is on trial.
        ///
        /// # Errors
        /// [`SlotError::Flash`] when the state cannot be read.
        pub fn new(dfu: DFU, state: STATE, aligned: &'d mut [u8; 8]) -> Result<Self, SlotError> {
            let mut state = BlockingFirmwareState::new(state, aligned);
            let trial = state.get_state().map_err(flash)? == State::Swap;
            Ok(FlashSlot {
                dfu,
                state,
                erased_to: 0,
                trial,
                pending: false,
            })
        }

        fn confirmed(&mut self) -> Result<(), SlotError> {
            match self.state()? {
                BootState::Confirmed | BootState::RolledBack => Ok(()),
                BootState::Trial | BootState::SwapPending => Err(SlotError::NotConfirmed),
            }
        }
    }

    impl<DFU: NorFlash, STATE: NorFlash> Slot for FlashSlot<'_, DFU, STATE> {
        fn capacity(&self) -> u32 {
            // The update slot is one page larger than the active slot: the swap's spare
            // page. The image must fit the active slot.
            let spare = u32::try_from(DFU::ERASE_SIZE).unwrap_or(u32::MAX);
            u32::try_from(self.dfu.capacity())
                .unwrap_or(0)
                .saturating_sub(spare)
        }

        fn state(&mut self) -> Result<BootState, SlotError> {
            Ok(match self.state.get_state().map_err(flash)? {
                State::Swap if self.pending => BootState::SwapPending,
                State::Swap if self.trial => BootState::Trial,
                // Swap magic neither this run nor the bootloader set: a pending swap left
                // by a run that ended before resetting (the next reset swaps).
                State::Swap => BootState::SwapPending,
                State::Revert => BootState::RolledBack,
                State::Boot | State::DfuDetach => BootState::Confirmed,
            })
        }

        fn begin(&mut self) {
            self.erased_to = 0;
        }

        fn write(&mut self, offset: u32, data: &[u8]) -> Result<(), SlotError> {
            self.confirmed()?;
            let page = u32::try_from(DFU::ERASE_SIZE).map_err(flash)?;
            let len = u32::try_from(data.len()).map_err(flash)?;
            let end = offset.checked_add(len).ok_or(SlotError::Flash)?;
            // Erase every page this write touches that this transfer has not erased.
            let first = offset.checked_div(page).ok_or(SlotError::Flash)?;
            let mut at = first
                .checked_mul(page)
                .ok_or(SlotError::Flash)?
                .max(self.erased_to);
            while at < end {
                let next = at.checked_add(page).ok_or(SlotError::Flash)?;
                self.dfu.erase(at, next).map_err(flash)?;
                self.erased_to = next;
                at = next;
            }
            // Whole double words, then the image's tail padded with the erased value.
            let whole = data.len() & !7;
            let (body, tail) = data.split_at(whole);
            if !body.is_empty() {
                self.dfu.write(offset, body).map_err(flash)?;
            }
            if !tail.is_empty() {
                let mut word = [0xFF; 8];
                for (w, t) in word.iter_mut().zip(tail) {
                    *w = *t;
                }
                let at = offset
                    .checked_add(u32::try_from(whole).map_err(flash)?)
                    .ok_or(SlotError::Flash)?;
                self.dfu.write(at, &word).map_err(flash)?;
            }
            Ok(())
        }

        fn read(&mut self, offset: u32, buf: &mut [u8]) -> Result<(), SlotError> {
            self.dfu.read(offset, buf).map_err(flash)
        }

        fn mark_updated(&mut self) -> Result<(), SlotError> {
            self.state.mark_updated().map_err(flash)?;
            self.pending = true;
            Ok(())
        }

        fn cancel_swap(&mut self) -> Result<(), SlotError> {
            // The Boot magic, as after a confirmed boot: the bootloader then boots the
            // active slot as it is.
            self.state.mark_booted().map_err(flash)?;
            self.pending = false;
            Ok(())
        }

        fn mark_booted(&mut self) -> Result<(), SlotError> {
            self.state.mark_booted().map_err(flash)?;
            self.trial = false;
            Ok(())
        }
    }
}
