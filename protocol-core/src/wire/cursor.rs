//! Bounds-checked cursors over byte slices.
//!
//! [`Reader`] consumes a slice from the front; [`Writer`] fills a mutable slice from the
//! front. Every method that could run past the end returns an [`Error`] instead of
//! panicking: [`Error::Truncated`] when reading, [`Error::BufferTooSmall`] when writing.

use crate::{Error, Result};

/// Reads integers and byte arrays from the front of a byte slice.
#[derive(Debug, Clone)]
pub struct Reader<'a> {
    rest: &'a [u8],
}

macro_rules! read_int {
    ($($(#[$m:meta])* $name:ident -> $ty:ty, $n:literal, $conv:ident;)*) => {$(
        $(#[$m])*
        ///
        /// # Errors
        /// [`Error::Truncated`] when too few bytes remain.
        #[inline]
        pub fn $name(&mut self) -> Result<$ty> {
            Ok(<$ty>::$conv(self.array::<$n>()?))
        }
    )*};
}

impl<'a> Reader<'a> {
    /// A reader positioned at the first byte of `buf`.
    #[must_use]
    pub const fn new(buf: &'a [u8]) -> Self {
        Reader { rest: buf }
    }

    /// Bytes not yet read.
    #[must_use]
    pub const fn remaining(&self) -> usize {
        self.rest.len()
    }

    /// True when every byte has been read.
    #[must_use]
    pub const fn is_empty(&self) -> bool {
        self.rest.is_empty()
    }

    /// The next `n` bytes.
    ///
    /// # Errors
    /// [`Error::Truncated`] when fewer than `n` bytes remain.
    pub fn take(&mut self, n: usize) -> Result<&'a [u8]> {
        let (head, tail) = self.rest.split_at_checked(n).ok_or(Error::Truncated)?;
        self.rest = tail;
        Ok(head)
    }

    /// Skips `n` bytes (reserved fields).
    ///
    /// # Errors
    /// [`Error::Truncated`] when fewer than `n` bytes remain.
    pub fn skip(&mut self, n: usize) -> Result<()> {
        self.take(n).map(|_| ())
    }

    /// The next `N` bytes as an array.
    ///
    /// # Errors
    /// [`Error::Truncated`] when fewer than `N` bytes remain.
    pub fn array<const N: usize>(&mut self) -> Result<[u8; N]> {
        let (head, tail) = self.rest.split_first_chunk::<N>().ok_or(Error::Truncated)?;
        self.rest = tail;
        Ok(*head)
    }

    /// All bytes not yet read; the reader is empty afterwards.
    pub fn rest(&mut self) -> &'a [u8] {
        core::mem::take(&mut self.rest)
    }

    /// Succeeds only when every byte has been read: a payload longer than its
    /// message defines is [`Error::BadLength`].
    ///
    /// # Errors
    /// [`Error::BadLength`] when bytes remain.
    pub fn finish(self) -> Result<()> {
        if self.rest.is_empty() {
            Ok(())
        } else {
            Err(Error::BadLength)
        }
    }

    read_int! {
        /// One unsigned byte.
        u8 -> u8, 1, from_le_bytes;
        /// One signed byte.
        i8 -> i8, 1, from_le_bytes;
        /// u16, little-endian.
        u16_le -> u16, 2, from_le_bytes;
        /// u16, big-endian.
        u16_be -> u16, 2, from_be_bytes;
        /// i16, little-endian.
        i16_le -> i16, 2, from_le_bytes;
        /// i16, big-endian.
        i16_be -> i16, 2, from_be_bytes;
        /// u32, little-endian.
        u32_le -> u32, 4, from_le_bytes;
        /// u32, big-endian.
        u32_be -> u32, 4, from_be_bytes;
        /// i32, little-endian.
        i32_le -> i32, 4, from_le_bytes;
        /// i32, big-endian.
        i32_be -> i32, 4, from_be_bytes;
        /// u64, little-endian.
        u64_le -> u64, 8, from_le_bytes;
        /// u64, big-endian.
        u64_be -> u64, 8, from_be_bytes;
        /// i64, little-endian.
        i64_le -> i64, 8, from_le_bytes;
        /// i64, big-endian.
        i64_be -> i64, 8, from_be_bytes;
        /// IEEE-754 single, little-endian.
        f32_le -> f32, 4, from_le_bytes;
        /// IEEE-754 single, big-endian.
        f32_be -> f32, 4, from_be_bytes;
    }

    /// Unsigned 24-bit integer, little-endian (low, mid, high byte).
    ///
    /// # Errors
    /// [`Error::Truncated`] when fewer than 3 bytes remain.
    pub fn u24_le(&mut self) -> Result<u32> {
        let [a, b, c] = self.array::<3>()?;
        Ok(u32::from_le_bytes([a, b, c, 0]))
    }

    /// Unsigned 24-bit integer, big-endian (high, mid, low byte).
    ///
    /// # Errors
    /// [`Error::Truncated`] when fewer than 3 bytes remain.
    pub fn u24_be(&mut self) -> Result<u32> {
        let [a, b, c] = self.array::<3>()?;
        Ok(u32::from_be_bytes([0, a, b, c]))
    }
}

/// Writes integers and byte arrays into a mutable byte slice, front to back.
#[derive(Debug)]
pub struct Writer<'a> {
    buf: &'a mut [u8],
    len: usize,
}

macro_rules! write_int {
    ($($(#[$m:meta])* $name:ident($ty:ty), $conv:ident;)*) => {$(
        $(#[$m])*
        ///
        /// # Errors
        /// [`Error::BufferTooSmall`] when the buffer has no room.
        #[inline]
        pub fn $name(&mut self, v: $ty) -> Result<()> {
            self.put(&v.$conv())
        }
    )*};
}

impl<'a> Writer<'a> {
    /// A writer that fills `buf` from its first byte.
    pub fn new(buf: &'a mut [u8]) -> Self {
        Writer { buf, len: 0 }
    }

    /// Bytes written so far.
    #[must_use]
    pub const fn len(&self) -> usize {
        self.len
    }

    /// True when nothing has been written.
    #[must_use]
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The bytes written so far.
    #[must_use]
    pub fn written(&self) -> &[u8] {
        self.buf.get(..self.len).unwrap_or_default()
    }

    /// Appends `bytes`.
    ///
    /// # Errors
    /// [`Error::BufferTooSmall`] when the buffer has no room for them.
    pub fn put(&mut self, bytes: &[u8]) -> Result<()> {
        let end = self
            .len
            .checked_add(bytes.len())
            .ok_or(Error::BufferTooSmall)?;
        let dst = self
            .buf
            .get_mut(self.len..end)
            .ok_or(Error::BufferTooSmall)?;
        super::copy(dst, bytes);
        self.len = end;
        Ok(())
    }

    /// Appends `n` zero bytes (reserved fields).
    ///
    /// # Errors
    /// [`Error::BufferTooSmall`] when the buffer has no room for them.
    pub fn zeros(&mut self, n: usize) -> Result<()> {
        let end = self.len.checked_add(n).ok_or(Error::BufferTooSmall)?;
        let dst = self
            .buf
            .get_mut(self.len..end)
            .ok_or(Error::BufferTooSmall)?;
        dst.fill(0);
        self.len = end;
        Ok(())
    }

    /// Overwrites one already-written byte at `index` (e.g. a length field known only
    /// after the payload is written).
    ///
    /// # Errors
    /// [`Error::BufferTooSmall`] when `index` was not written yet.
    pub fn set_u8(&mut self, index: usize, v: u8) -> Result<()> {
        if index >= self.len {
            return Err(Error::BufferTooSmall);
        }
        let b = self.buf.get_mut(index).ok_or(Error::BufferTooSmall)?;
        *b = v;
        Ok(())
    }

    /// Consumes the writer and returns the number of bytes written.
    #[must_use]
    pub const fn finish(self) -> usize {
        self.len
    }

    write_int! {
        /// One unsigned byte.
        u8(u8), to_le_bytes;
        /// One signed byte.
        i8(i8), to_le_bytes;
        /// u16, little-endian.
        u16_le(u16), to_le_bytes;
        /// u16, big-endian.
        u16_be(u16), to_be_bytes;
        /// i16, little-endian.
        i16_le(i16), to_le_bytes;
        /// i16, big-endian.
        i16_be(i16), to_be_bytes;
        /// u32, little-endian.
        u32_le(u32), to_le_bytes;
        /// u32, big-endian.
        u32_be(u32), to_be_bytes;
        /// i32, little-endian.
        i32_le(i32), to_le_bytes;
        /// i32, big-endian.
        i32_be(i32), to_be_bytes;
        /// u64, little-endian.
        u64_le(u64), to_le_bytes;
        /// u64, big-endian.
        u64_be(u64), to_be_bytes;
        /// i64, little-endian.
        i64_le(i64), to_le_bytes;
        /// i64, big-endian.
        i64_be(i64), to_be_bytes;
        /// IEEE-754 single, little-endian.
        f32_le(f32), to_le_bytes;
        /// IEEE-754 single, big-endian.
        f32_be(f32), to_be_bytes;
    }

    /// Unsigned 24-bit integer, little-endian. Values above 0xFF_FFFF are [`Error::OutOfRange`].
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for a value above 24 bits, [`Error::BufferTooSmall`]
    /// when the buffer has no room.
    pub fn u24_le(&mut self, v: u32) -> Result<()> {
        let [a, b, c, hi] = v.to_le_bytes();
        if hi != 0 {
            return Err(Error::OutOfRange);
        }
        self.put(&[a, b, c])
    }

    /// Unsigned 24-bit integer, big-endian. Values above 0xFF_FFFF are [`Error::OutOfRange`].
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for a value above 24 bits, [`Error::BufferTooSmall`]
    /// when the buffer has no room.
    pub fn u24_be(&mut self, v: u32) -> Result<()> {
        let [hi, a, b, c] = v.to_be_bytes();
        if hi != 0 {
            return Err(Error::OutOfRange);
        }
        self.put(&[a, b, c])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_every_width_and_order() {
        let data = [1, 2, 3, 4, 5, 6, 7, 8];
        let mut r = Reader::new(&data);
        assert_eq!(r.u16_le(), Ok(0x0201));
        assert_eq!(r.u16_be(), Ok(0x0304));
        assert_eq!(r.u24_le(), Ok(0x07_0605));
        assert_eq!(r.remaining(), 1);
        assert_eq!(r.u16_le(), Err(Error::Truncated));
        assert_eq!(r.u8(), Ok(8));
        assert!(r.finish().is_ok());
        let mut r = Reader::new(&data);
        assert_eq!(r.u24_be(), Ok(0x01_0203));
        assert_eq!(r.u32_be(), Ok(0x0405_0607));
        assert_eq!(r.clone().finish(), Err(Error::BadLength));
        assert_eq!(r.u64_le(), Err(Error::Truncated));
        assert_eq!(r.array::<1>(), Ok([8]));
        assert_eq!(Reader::new(&[0xFE]).i8(), Ok(-2));
        assert_eq!(Reader::new(&[0xFF; 8]).i64_be(), Ok(-1));
    }

    #[test]
    fn writes_and_refuses_overflow() {
        let mut buf = [0u8; 6];
        let mut w = Writer::new(&mut buf);
        assert_eq!(w.u16_be(0x0102), Ok(()));
        assert_eq!(w.u24_le(0x0A_0B0C), Ok(()));
        assert_eq!(w.u24_le(0x100_0000), Err(Error::OutOfRange));
        assert_eq!(w.u16_le(1), Err(Error::BufferTooSmall));
        assert_eq!(w.set_u8(5, 1), Err(Error::BufferTooSmall));
        assert_eq!(w.set_u8(0, 9), Ok(()));
        assert_eq!(w.written(), &[9, 2, 0x0C, 0x0B, 0x0A]);
        assert_eq!(w.u8(0xEE), Ok(()));
        assert_eq!(w.zeros(1), Err(Error::BufferTooSmall));
        assert_eq!(w.finish(), 6);
        assert_eq!(buf, [9, 2, 0x0C, 0x0B, 0x0A, 0xEE]);
    }
}
