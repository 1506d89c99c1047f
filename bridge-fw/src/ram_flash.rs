//! A NOR flash in RAM with the STM32L4's geometry on a small scale: erased to 0xFF, written
//! in 8-byte words, each only while it is erased (the L4's ECC flash takes one write of a
//! double word between erases). The emulated board's store lives in it: QEMU's
//! `b-l475e-iot01a` models the flash as read-only memory and its flash controller not at
//! all (writes are lost), so its store forgets everything at each start and says so.

use embedded_storage_async::nor_flash::{
    ErrorType, NorFlash, NorFlashError, NorFlashErrorKind, ReadNorFlash,
};

/// A flash over a buffer (its length a multiple of `PAGE`), in pages of `PAGE` bytes (a
/// multiple of 8).
#[derive(Debug)]
pub struct RamFlash<'a, const PAGE: usize> {
    bytes: &'a mut [u8],
}

/// What a [`RamFlash`] refuses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RamFlashError {
    /// Outside the flash, or not aligned.
    OutOfBounds,
    /// A word that is not erased (the L4's PROGERR).
    NotErased,
}

impl NorFlashError for RamFlashError {
    fn kind(&self) -> NorFlashErrorKind {
        match self {
            RamFlashError::OutOfBounds => NorFlashErrorKind::OutOfBounds,
            RamFlashError::NotErased => NorFlashErrorKind::Other,
        }
    }
}

impl<'a, const PAGE: usize> RamFlash<'a, PAGE> {
    /// The flash over `bytes`, erased.
    pub fn new(bytes: &'a mut [u8]) -> Self {
        bytes.fill(0xFF);
        RamFlash { bytes }
    }

    /// The flash over `bytes` as they are (a flash that kept its contents).
    pub fn keeping(bytes: &'a mut [u8]) -> Self {
        RamFlash { bytes }
    }

    /// Its bytes.
    #[must_use]
    pub fn bytes(&self) -> &[u8] {
        self.bytes
    }

    fn range(
        &self,
        offset: u32,
        len: usize,
        align: usize,
    ) -> Result<core::ops::Range<usize>, RamFlashError> {
        let start = usize::try_from(offset).map_err(|_| RamFlashError::OutOfBounds)?;
        let end = start.checked_add(len).ok_or(RamFlashError::OutOfBounds)?;
        let aligned = start.checked_rem(align) == Some(0) && end.checked_rem(align) == Some(0);
        if end > self.bytes.len() || !aligned {
            return Err(RamFlashError::OutOfBounds);
        }
        Ok(start..end)
    }
}

impl<const PAGE: usize> ErrorType for RamFlash<'_, PAGE> {
    type Error = RamFlashError;
}

impl<const PAGE: usize> ReadNorFlash for RamFlash<'_, PAGE> {
    const READ_SIZE: usize = 1;

    async fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), Self::Error> {
        let r = self.range(offset, bytes.len(), 1)?;
        let src = self.bytes.get(r).ok_or(RamFlashError::OutOfBounds)?;
        bytes.copy_from_slice(src);
        Ok(())
    }

    fn capacity(&self) -> usize {
        self.bytes.len()
    }
}

impl<const PAGE: usize> NorFlash for RamFlash<'_, PAGE> {
    const WRITE_SIZE: usize = 8;
    const ERASE_SIZE: usize = PAGE;

    async fn erase(&mut self, from: u32, to: u32) -> Result<(), Self::Error> {
        let len =
            usize::try_from(to.saturating_sub(from)).map_err(|_| RamFlashError::OutOfBounds)?;
        let r = self.range(from, len, PAGE)?;
        self.bytes
            .get_mut(r)
            .ok_or(RamFlashError::OutOfBounds)?
            .fill(0xFF);
        Ok(())
    }

    async fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Self::Error> {
        let r = self.range(offset, bytes.len(), 8)?;
        let dst = self.bytes.get_mut(r).ok_or(RamFlashError::OutOfBounds)?;
        if dst.iter().any(|b| *b != 0xFF) {
            return Err(RamFlashError::NotErased);
        }
        dst.copy_from_slice(bytes);
        Ok(())
    }
}
