//! Fixed-size field encodings: how one value (an integer, a byte array, an enumeration
//! code, a whole fixed-layout struct) is laid out on the wire, in a byte order chosen by
//! a marker type ([`Le`] or [`Be`]).
//!
//! Every payload struct of the four codecs is declared field by field with the crate's
//! `wire_struct!` macro, which implements [`Field`] for it; the codecs read and write
//! payloads through this one trait. It is public so that firmware can declare its own
//! payload types the same way.

use crate::Result;
use crate::wire::{Reader, Writer};

/// Byte-order marker: little-endian fields (K40T, SIYI, GCU).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Le {}

/// Byte-order marker: big-endian fields (Viewlink).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Be {}

/// A value carried on the wire as an integer code (every enumeration of the codecs).
///
/// Implemented by the crate's `code_enum!` types; [`Field`] follows from it.
pub trait WireCode: Copy {
    /// The integer type on the wire.
    type Repr;
    /// The wire value.
    fn to_repr(self) -> Self::Repr;
    /// The variant for a wire value (lossless: unlisted values are kept).
    fn from_repr(v: Self::Repr) -> Self;
}

/// A value with a fixed-size wire encoding in byte order `O`.
pub trait Field<O>: Sized {
    /// Encoded size in bytes.
    const LEN: usize;
    /// Reads the value.
    ///
    /// # Errors
    /// [`Error::Truncated`](crate::Error::Truncated) when the reader holds fewer than `LEN` bytes (or the
    /// value's own error, e.g. a bit field out of range).
    fn read(r: &mut Reader<'_>) -> Result<Self>;
    /// Writes the value.
    ///
    /// # Errors
    /// [`Error::BufferTooSmall`](crate::Error::BufferTooSmall) when the writer has no room, [`Error::OutOfRange`](crate::Error::OutOfRange)
    /// when the value cannot be encoded.
    fn write(&self, w: &mut Writer<'_>) -> Result<()>;
}

macro_rules! int_field {
    ($($ty:ty: $n:literal, $le_get:ident, $le_put:ident, $be_get:ident, $be_put:ident;)*) => {$(
        impl Field<Le> for $ty {
            const LEN: usize = $n;
            fn read(r: &mut Reader<'_>) -> Result<Self> {
                r.$le_get()
            }
            fn write(&self, w: &mut Writer<'_>) -> Result<()> {
                w.$le_put(*self)
            }
        }

        impl Field<Be> for $ty {
            const LEN: usize = $n;
            fn read(r: &mut Reader<'_>) -> Result<Self> {
                r.$be_get()
            }
            fn write(&self, w: &mut Writer<'_>) -> Result<()> {
                w.$be_put(*self)
            }
        }
    )*};
}

int_field! {
    u8: 1, u8, u8, u8, u8;
    i8: 1, i8, i8, i8, i8;
    u16: 2, u16_le, u16_le, u16_be, u16_be;
    i16: 2, i16_le, i16_le, i16_be, i16_be;
    u32: 4, u32_le, u32_le, u32_be, u32_be;
    i32: 4, i32_le, i32_le, i32_be, i32_be;
    u64: 8, u64_le, u64_le, u64_be, u64_be;
    i64: 8, i64_le, i64_le, i64_be, i64_be;
    f32: 4, f32_le, f32_le, f32_be, f32_be;
}

impl<O, const N: usize> Field<O> for [u8; N] {
    const LEN: usize = N;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        r.array()
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        w.put(self)
    }
}

impl<O, T: WireCode> Field<O> for T
where
    T::Repr: Field<O>,
{
    const LEN: usize = <T::Repr as Field<O>>::LEN;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        <T::Repr as Field<O>>::read(r).map(T::from_repr)
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        <T::Repr as Field<O>>::write(&self.to_repr(), w)
    }
}
