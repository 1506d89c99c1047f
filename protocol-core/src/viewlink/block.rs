//! The [`Block`] trait (how a packet block reads from and writes to the data of a
//! frame), the field types several blocks share ([`Bytes`], [`Date`], [`TimeCs`]), the
//! bit-field helpers, and the macro that declares the blocks whose parameters depend on
//! their command byte. Block fields are big-endian.

use crate::wire::encoding::{Be, Field};
use crate::wire::table::PayloadCodec;
use crate::wire::{Reader, Writer};
use crate::{Error, Result};

/// One packet block (A1, C1, ... M) or combination of blocks: how it reads from and
/// writes to the data of a frame.
///
/// Every fixed-size block is a [`Field<Be>`](Field) (declared with the crate's
/// `wire_struct!` or by hand for bit fields) and is a `Block` through the blanket
/// implementation. Variable-size blocks (V, M, the AI and KLV packets, transparent
/// data) implement it directly; they are always the last block of their frame and read
/// every remaining byte.
pub trait Block: Sized {
    /// Most encoded bytes: the length of a fixed-size block, the largest length of a
    /// variable-size one.
    const MAX_LEN: usize;

    /// Reads the block from the front of `r`.
    ///
    /// # Errors
    /// [`Error::Truncated`] when `r` holds too few bytes, [`Error::BadLength`] when a
    /// variable-size block's bytes do not make a whole block.
    fn read_block(r: &mut Reader<'_>) -> Result<Self>;

    /// Writes the block.
    ///
    /// # Errors
    /// [`Error::BufferTooSmall`] when `w` has no room for it, [`Error::OutOfRange`] for
    /// a bit field whose value does not fit its bits.
    fn write_block(&self, w: &mut Writer<'_>) -> Result<()>;

    /// Encoded length in bytes.
    fn block_len(&self) -> usize;

    /// Decodes a block from exactly `bytes`.
    ///
    /// # Errors
    /// As [`Block::read_block`]; bytes after the block are [`Error::BadLength`].
    fn from_bytes(bytes: &[u8]) -> Result<Self> {
        let mut r = Reader::new(bytes);
        let v = Self::read_block(&mut r)?;
        r.finish()?;
        Ok(v)
    }

    /// Encodes the block into `buf` and returns its length.
    ///
    /// # Errors
    /// As [`Block::write_block`].
    fn to_bytes(&self, buf: &mut [u8]) -> Result<usize> {
        let mut w = Writer::new(buf);
        self.write_block(&mut w)?;
        Ok(w.finish())
    }
}

impl<T: Field<Be>> Block for T {
    const MAX_LEN: usize = <T as Field<Be>>::LEN;

    fn read_block(r: &mut Reader<'_>) -> Result<Self> {
        <T as Field<Be>>::read(r)
    }

    fn write_block(&self, w: &mut Writer<'_>) -> Result<()> {
        <T as Field<Be>>::write(self, w)
    }

    fn block_len(&self) -> usize {
        <T as Field<Be>>::LEN
    }
}

/// The Viewlink length rules, for the message table: a frame's payload is one [`Block`]
/// (a combination is a block of blocks) taking all of its bytes.
impl<T: Block> PayloadCodec<T> for super::Viewlink {
    const MAX_LEN: usize = T::MAX_LEN;

    fn decode(payload: &[u8]) -> Result<T> {
        T::from_bytes(payload)
    }

    fn encoded_len(value: &T) -> usize {
        value.block_len()
    }

    fn encode(value: &T, w: &mut Writer<'_>) -> Result<()> {
        value.write_block(w)
    }
}

/// A block with a fixed wire length (every [`Field<Be>`](Field)).
pub trait FixedBlock {
    /// Encoded length in bytes.
    const LEN: usize;
}

impl<T: Field<Be>> FixedBlock for T {
    const LEN: usize = <T as Field<Be>>::LEN;
}

/// `value` shifted right by `shift` and masked to `bits` bits.
pub(crate) const fn bits_of(value: u16, shift: u32, bits: u32) -> u16 {
    let mask = match 1u16.checked_shl(bits) {
        Some(m) => m.wrapping_sub(1),
        None => u16::MAX,
    };
    value.wrapping_shr(shift) & mask
}

/// [`bits_of`] for a field of at most 8 bits, as a byte.
pub(crate) const fn byte_of(value: u16, shift: u32, bits: u32) -> u8 {
    // The mask leaves at most `bits` (<= 8) bits: the high byte is zero.
    let [_, low] = bits_of(value, shift, if bits > 8 { 8 } else { bits }).to_be_bytes();
    low
}

/// Adds `value` as a `bits`-bit field at `shift` to `acc`; a value that does not fit is
/// [`Error::OutOfRange`].
pub(crate) fn put_bits(acc: u16, value: u16, shift: u32, bits: u32) -> Result<u16> {
    if bits_of(value, 0, bits) != value {
        return Err(Error::OutOfRange);
    }
    Ok(acc | value.wrapping_shl(shift))
}

/// Byte version of [`bits_of`].
pub(crate) const fn bits8(value: u8, shift: u32, bits: u32) -> u8 {
    let mask = match 1u8.checked_shl(bits) {
        Some(m) => m.wrapping_sub(1),
        None => u8::MAX,
    };
    value.wrapping_shr(shift) & mask
}

/// Byte version of [`put_bits`].
pub(crate) fn put_bits8(acc: u8, value: u8, shift: u32, bits: u32) -> Result<u8> {
    let v = put_bits(u16::from(acc), u16::from(value), shift, bits)?;
    u8::try_from(v).map_err(|_| Error::OutOfRange)
}

/// Declares a block whose first byte is a command and whose parameters depend on it: one
/// variant per command with defined parameters (the command is implied by the variant),
/// and `Plain` for the other commands (parameters kept as bytes). Every variant's
/// parameters have the same length, checked at compile time. Generates the enum,
/// `command()`, `plain()`, `Default` (`Plain` with command 0) and [`Field<Be>`](Field)
/// (hence [`Block`]).
macro_rules! viewlink_command_block {
    (
        $(#[$meta:meta])*
        pub enum $name:ident: $cmd:ident [$plen:literal] {
            $( $(#[$vm:meta])* $variant:ident($ty:ty) = $code:ident, )*
        }
    ) => {
        wire_derive! {
            [Eq, Hash]
            $(#[$meta])*
            pub enum $name {
                $( $(#[$vm])* $variant($ty), )*
                /// A command without parameters of its own (or one the document does not
                /// list), with the parameter bytes as received.
                Plain {
                    /// The command byte.
                    command: $cmd,
                    /// The parameter bytes.
                    params: [u8; $plen],
                },
            }
        }

        // One compile-time check per variant: its parameters fill the parameter bytes.
        $( const _: () = assert!(<$ty as $crate::wire::encoding::Field<$crate::wire::encoding::Be>>::LEN == $plen); )*

        impl $name {
            /// The command byte.
            #[must_use]
            pub const fn command(&self) -> $cmd {
                match self {
                    $( Self::$variant(_) => $cmd::$code, )*
                    Self::Plain { command, .. } => *command,
                }
            }

            /// A command with all parameter bytes zero (`Plain`, whatever the command).
            #[must_use]
            pub const fn plain(command: $cmd) -> Self {
                Self::Plain { command, params: [0; $plen] }
            }
        }

        impl Default for $name {
            fn default() -> Self {
                Self::plain($cmd::from_value(0))
            }
        }

        impl $crate::wire::encoding::Field<$crate::wire::encoding::Be> for $name {
            const LEN: usize = 1 + $plen;

            fn read(r: &mut $crate::wire::Reader<'_>) -> $crate::Result<Self> {
                let command = $cmd::from_value(r.u8()?);
                Ok(match command {
                    $( $cmd::$code => Self::$variant($crate::wire::encoding::Field::<$crate::wire::encoding::Be>::read(r)?), )*
                    command => Self::Plain { command, params: r.array()? },
                })
            }

            fn write(&self, w: &mut $crate::wire::Writer<'_>) -> $crate::Result<()> {
                w.u8(self.command().value())?;
                match self {
                    $( Self::$variant(v) => $crate::wire::encoding::Field::<$crate::wire::encoding::Be>::write(v, w), )*
                    Self::Plain { params, .. } => w.put(params),
                }
            }
        }
    };
}

wire_derive! {
    custom_serde [Eq, Hash]
    /// Up to `N` bytes of variable-length data, kept as received. The bytes after the
    /// length are always zero, so the derived comparisons compare the bytes held.
    pub struct Bytes<const N: usize> {
        len: u8,
        buf: [u8; N],
    }
}

impl<const N: usize> Default for Bytes<N> {
    fn default() -> Self {
        Bytes {
            len: 0,
            buf: [0; N],
        }
    }
}

impl<const N: usize> Bytes<N> {
    /// The bytes of `data`.
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for more than `N` bytes (or more than 255).
    pub fn new(data: &[u8]) -> Result<Self> {
        let mut b = Bytes::default();
        let dst = b.buf.get_mut(..data.len()).ok_or(Error::OutOfRange)?;
        crate::wire::copy(dst, data);
        b.len = u8::try_from(data.len()).map_err(|_| Error::OutOfRange)?;
        Ok(b)
    }

    /// The bytes held.
    #[must_use]
    pub fn as_slice(&self) -> &[u8] {
        self.buf.get(..usize::from(self.len)).unwrap_or_default()
    }

    /// Number of bytes held.
    #[must_use]
    pub const fn len(&self) -> usize {
        // Widening (`usize::from` is not const).
        self.len as usize
    }

    /// True when no byte is held.
    #[must_use]
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Reads every remaining byte of `r` (more than `N` is [`Error::BadLength`]).
    pub(crate) fn read_rest(r: &mut Reader<'_>) -> Result<Self> {
        Bytes::new(r.rest()).map_err(|_| Error::BadLength)
    }
}

#[cfg(feature = "serde")]
impl<const N: usize> serde::Serialize for Bytes<N> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> core::result::Result<S::Ok, S::Error> {
        s.collect_seq(self.as_slice().iter())
    }
}

wire_derive! {
    custom_serde [Eq, Hash, Default]
    /// A UTC date packed in 16 bits (M and T2 packets): bits 15..11 day, 10..7 month,
    /// 6..0 year minus 2000. Kept as the 16 bits received.
    pub struct Date(pub u16);
}

impl Date {
    /// The date for a day (1..=31), month (1..=12) and year (2000..=2127).
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for a value that does not fit its bits.
    pub fn new(year: u16, month: u8, day: u8) -> Result<Self> {
        let y = year.checked_sub(2000).ok_or(Error::OutOfRange)?;
        let v = put_bits(0, y, 0, 7)?;
        let v = put_bits(v, u16::from(month), 7, 4)?;
        put_bits(v, u16::from(day), 11, 5).map(Date)
    }

    /// Day of the month (bits 15..11).
    #[must_use]
    pub const fn day(self) -> u8 {
        byte_of(self.0, 11, 5)
    }

    /// Month (bits 10..7).
    #[must_use]
    pub const fn month(self) -> u8 {
        byte_of(self.0, 7, 4)
    }

    /// Year (bits 6..0, plus 2000).
    #[must_use]
    pub const fn year(self) -> u16 {
        bits_of(self.0, 0, 7).wrapping_add(2000)
    }
}

#[cfg(feature = "serde")]
impl serde::Serialize for Date {
    fn serialize<S: serde::Serializer>(&self, s: S) -> core::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut out = s.serialize_struct("Date", 3)?;
        out.serialize_field("year", &self.year())?;
        out.serialize_field("month", &self.month())?;
        out.serialize_field("day", &self.day())?;
        out.end()
    }
}

impl Field<Be> for Date {
    const LEN: usize = 2;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        r.u16_be().map(Date)
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u16_be(self.0)
    }
}

wire_derive! {
    [Eq, Hash, Default]
    /// Time of day in 0.01 s since UTC midnight, 3 bytes big-endian (M and T2 packets).
    pub struct TimeCs(pub u32);
}

impl TimeCs {
    /// The time for hours, minutes, seconds and hundredths.
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for an hour above 23, a minute above 59, a second above 60
    /// or hundredths above 99.
    pub fn new(hour: u8, minute: u8, second: u8, centis: u8) -> Result<Self> {
        if hour > 23 || minute > 59 || second > 60 || centis > 99 {
            return Err(Error::OutOfRange);
        }
        let s = u32::from(hour)
            .saturating_mul(3600)
            .saturating_add(u32::from(minute).saturating_mul(60))
            .saturating_add(u32::from(second));
        Ok(TimeCs(
            s.saturating_mul(100).saturating_add(u32::from(centis)),
        ))
    }
}

impl Field<Be> for TimeCs {
    const LEN: usize = 3;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        r.u24_be().map(TimeCs)
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u24_be(self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bit_helpers() {
        assert_eq!(bits_of(0x0278, 6, 7), 0x09);
        assert_eq!(bits_of(0x0278, 3, 3), 7);
        assert_eq!(put_bits(0, 0x09, 6, 7), Ok(0x0240));
        assert_eq!(put_bits(0, 0x80, 6, 7), Err(Error::OutOfRange));
        assert_eq!(put_bits8(0x01, 3, 6, 2), Ok(0xC1));
        assert_eq!(put_bits8(0, 4, 6, 2), Err(Error::OutOfRange));
        assert_eq!(bits_of(0xFFFF, 0, 16), 0xFFFF);
    }

    #[test]
    fn date_and_time() {
        let d = Date::new(2026, 1, 31).unwrap();
        assert_eq!((d.year(), d.month(), d.day()), (2026, 1, 31));
        assert_eq!(d.0, (31 << 11) | (1 << 7) | (2026 - 2000));
        assert!(Date::new(1999, 1, 1).is_err());
        assert!(Date::new(2000, 16, 1).is_err());
        assert_eq!(TimeCs::new(23, 59, 59, 99).unwrap().0, 8_639_999);
        assert!(TimeCs::new(24, 0, 0, 0).is_err());
    }

    #[test]
    fn bytes() {
        let b = Bytes::<4>::new(&[1, 2]).unwrap();
        assert_eq!(b.as_slice(), &[1, 2]);
        assert!(Bytes::<1>::new(&[1, 2]).is_err());
    }
}
