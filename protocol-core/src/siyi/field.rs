//! Field encodings of SIYI data (all little-endian), the [`Payload`] trait, the macro
//! that declares payload structs, and the types several messages share.

use crate::wire::{Reader, Writer};
use crate::{Error, Result};

pub(crate) use crate::wire::encoding::Field;

/// The data of one message in one direction.
///
/// Most layouts have a fixed length (an associated `LEN` constant on the type); the
/// few that vary in the wild (0x00, 0x01, 0x0A, 0x20 replies) remember the length they
/// were decoded from and encode to it again.
pub trait Payload: Sized {
    /// Decodes all of `data`; a length the layout does not allow is [`Error::BadLength`].
    fn decode(data: &[u8]) -> Result<Self>;
    /// Length of the encoded data.
    fn encoded_len(&self) -> usize;
    /// Writes the data.
    fn encode(&self, w: &mut Writer<'_>) -> Result<()>;
}

/// Declares a fixed-length payload struct: the fields in wire order, each a [`Field`].
/// `#[float]` first drops `Eq`, `Hash` (for structs with `f32` fields).
macro_rules! payload {
    (
        #[float]
        $(#[$meta:meta])*
        pub struct $name:ident { $($body:tt)* }
    ) => {
        payload!(@def [Debug, Clone, Copy, PartialEq, Default] $(#[$meta])* $name { $($body)* });
    };
    (
        $(#[$meta:meta])*
        pub struct $name:ident { $($body:tt)* }
    ) => {
        payload!(@def [Debug, Clone, Copy, PartialEq, Eq, Hash, Default] $(#[$meta])* $name { $($body)* });
    };
    (
        @def [$($derive:ident),*]
        $(#[$meta:meta])*
        $name:ident {
            $( $(#[$fmeta:meta])* pub $field:ident: $ty:ty, )*
        }
    ) => {
        $(#[$meta])*
        #[derive($($derive),*)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        #[cfg_attr(feature = "serde", derive(serde::Serialize))]
        pub struct $name {
            $( $(#[$fmeta])* pub $field: $ty, )*
        }

        impl $name {
            /// Encoded length in bytes.
            pub const LEN: usize = 0 $( + <$ty as $crate::siyi::field::Field<$crate::wire::encoding::Le>>::LEN )*;
        }

        impl $crate::siyi::Payload for $name {
            fn decode(data: &[u8]) -> $crate::Result<Self> {
                if data.len() != Self::LEN {
                    return Err($crate::Error::BadLength);
                }
                #[allow(unused_mut, unused_variables)]
                let mut r = $crate::wire::Reader::new(data);
                Ok(Self { $( $field: $crate::siyi::field::Field::<$crate::wire::encoding::Le>::read(&mut r)?, )* })
            }

            fn encoded_len(&self) -> usize {
                Self::LEN
            }

            #[allow(unused_variables)]
            fn encode(&self, w: &mut $crate::wire::Writer<'_>) -> $crate::Result<()> {
                $( $crate::siyi::field::Field::<$crate::wire::encoding::Le>::write(&self.$field, w)?; )*
                Ok(())
            }
        }
    };
}

payload! {
    /// No data (a request that only asks, or a direction the command does not use).
    pub struct Empty {}
}

/// Reads the optional trailing fields of a variable-length layout: `Some` while bytes
/// remain, `None` after. The reader must then be empty.
pub(crate) fn optional<T: Field<crate::wire::encoding::Le>>(
    r: &mut Reader<'_>,
) -> Result<Option<T>> {
    if r.is_empty() {
        Ok(None)
    } else {
        T::read(r).map(Some)
    }
}

/// Writes trailing optional fields: stops at the first `None`; a `Some` after a `None`
/// cannot be encoded ([`Error::OutOfRange`]).
pub(crate) struct Trailing<'w, 'b> {
    w: &'w mut Writer<'b>,
    ended: bool,
}

impl<'w, 'b> Trailing<'w, 'b> {
    pub(crate) fn new(w: &'w mut Writer<'b>) -> Self {
        Trailing { w, ended: false }
    }

    pub(crate) fn field<T: Field<crate::wire::encoding::Le>>(
        &mut self,
        v: &Option<T>,
    ) -> Result<()> {
        match v {
            Some(v) if self.ended => {
                let _ = v;
                Err(Error::OutOfRange)
            }
            Some(v) => v.write(self.w),
            None => {
                self.ended = true;
                Ok(())
            }
        }
    }
}

/// Length of a run of trailing optional fields, up to the first `None`.
pub(crate) fn trailing_len(present: &[(bool, usize)]) -> usize {
    present
        .iter()
        .take_while(|(is_some, _)| *is_some)
        .fold(0usize, |total, (_, len)| total.saturating_add(*len))
}

code_enum! {
    /// The `sta` byte of setting acknowledgements.
    pub enum AckStatus: u8 {
        /// 0: the setting failed.
        Failed = 0,
        /// 1: the setting succeeded.
        Success = 1,
    }
}

payload! {
    /// A one-byte result (`sta`, `ack`, `format_sta`...): 1 success, 0 failure.
    pub struct SetStatus {
        /// The result.
        pub status: AckStatus,
    }
}

impl SetStatus {
    /// Success.
    pub const SUCCESS: SetStatus = SetStatus {
        status: AckStatus::Success,
    };
    /// Failure.
    pub const FAILED: SetStatus = SetStatus {
        status: AckStatus::Failed,
    };
}

code_enum! {
    /// An on/off switch (laser ranging, thermal environment correction).
    pub enum OnOff: u8 {
        /// 0: off.
        Off = 0,
        /// 1: on.
        On = 1,
    }
}

/// One firmware version word of 0x01: a little-endian u32 whose bytes 0, 1, 2 are
/// patch, minor, major ("0x6E030203 is v3.2.3"); byte 3 is ignored by readers and kept.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FirmwareVersion {
    /// Byte 0.
    pub patch: u8,
    /// Byte 1.
    pub minor: u8,
    /// Byte 2.
    pub major: u8,
    /// Byte 3 (ignored, "high byte").
    pub ignored: u8,
}

impl FirmwareVersion {
    /// A version with the ignored byte zero.
    pub const fn new(major: u8, minor: u8, patch: u8) -> Self {
        FirmwareVersion {
            patch,
            minor,
            major,
            ignored: 0,
        }
    }

    /// The version from its u32 value (`0x6E030203` is v3.2.3).
    pub const fn from_u32(v: u32) -> Self {
        let [patch, minor, major, ignored] = v.to_le_bytes();
        FirmwareVersion {
            patch,
            minor,
            major,
            ignored,
        }
    }

    /// The u32 value.
    pub const fn to_u32(self) -> u32 {
        u32::from_le_bytes([self.patch, self.minor, self.major, self.ignored])
    }
}

impl Field<crate::wire::encoding::Le> for FirmwareVersion {
    const LEN: usize = 4;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        r.u32_le().map(FirmwareVersion::from_u32)
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u32_le(self.to_u32())
    }
}

/// The product a [`HardwareId`] names (its first two characters, the product id in hex
/// text).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Product {
    /// ZR10 ("6B").
    Zr10,
    /// A8 mini ("73").
    A8Mini,
    /// A2 mini ("75").
    A2Mini,
    /// ZR30 ("78").
    Zr30,
    /// ZT6 ("82" in the document, "83" in ArduPilot's table; both are accepted).
    Zt6,
    /// ZT30 ("7A").
    Zt30,
    /// Any other id, or a prefix that is not two hex digits.
    Unknown,
}

impl Product {
    /// The product for a product id.
    pub const fn from_id(id: u8) -> Self {
        match id {
            0x6B => Product::Zr10,
            0x73 => Product::A8Mini,
            0x75 => Product::A2Mini,
            0x78 => Product::Zr30,
            0x82 | 0x83 => Product::Zt6,
            0x7A => Product::Zt30,
            _ => Product::Unknown,
        }
    }

    /// The product id a bridge should announce: for ZT6 0x83, the one ArduPilot's
    /// `AP_Mount_Siyi` recognises. `None` for [`Product::Unknown`].
    pub const fn id(self) -> Option<u8> {
        match self {
            Product::Zr10 => Some(0x6B),
            Product::A8Mini => Some(0x73),
            Product::A2Mini => Some(0x75),
            Product::Zr30 => Some(0x78),
            Product::Zt6 => Some(0x83),
            Product::Zt30 => Some(0x7A),
            Product::Unknown => None,
        }
    }

    /// The product's name ("ZT30", "A8 mini", "unknown").
    pub const fn name(self) -> &'static str {
        match self {
            Product::Zr10 => "ZR10",
            Product::A8Mini => "A8 mini",
            Product::A2Mini => "A2 mini",
            Product::Zr30 => "ZR30",
            Product::Zt6 => "ZT6",
            Product::Zt30 => "ZT30",
            Product::Unknown => "unknown",
        }
    }
}

/// The hardware id of 0x02: 12 ASCII bytes (a 10-character id, usually NUL-padded)
/// whose first two characters are the product id in hex text ("7A..." is a ZT30).
/// Kept as the bytes received.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HardwareId {
    /// The 12 bytes as on the wire.
    pub raw: [u8; 12],
}

/// Hex digit value of an ASCII character.
const fn hex_digit(c: u8) -> Option<u8> {
    match c {
        b'0'..=b'9' => Some(c.wrapping_sub(b'0')),
        b'A'..=b'F' => Some(c.wrapping_sub(b'A').wrapping_add(10)),
        b'a'..=b'f' => Some(c.wrapping_sub(b'a').wrapping_add(10)),
        _ => None,
    }
}

impl HardwareId {
    /// Encoded length.
    pub const LEN: usize = 12;

    /// The id for `text` (at most 12 printable ASCII characters, NUL-padded); anything
    /// else is [`Error::OutOfRange`].
    pub fn from_text(text: &str) -> Result<Self> {
        if text.len() > Self::LEN || !text.bytes().all(|b| b.is_ascii_graphic() || b == b' ') {
            return Err(Error::OutOfRange);
        }
        let mut raw = [0u8; 12];
        raw.get_mut(..text.len())
            .ok_or(Error::OutOfRange)?
            .copy_from_slice(text.as_bytes());
        Ok(HardwareId { raw })
    }

    /// An id for `product`: its two upper-case hex digits (as ArduPilot matches them)
    /// followed by `serial` (at most 10 printable ASCII characters), NUL-padded.
    /// [`Product::Unknown`] or a bad serial is [`Error::OutOfRange`].
    pub fn for_product(product: Product, serial: &str) -> Result<Self> {
        const DIGITS: &[u8; 16] = b"0123456789ABCDEF";
        let id = product.id().ok_or(Error::OutOfRange)?;
        let tail = HardwareId::from_text(serial)?;
        if serial.len() > Self::LEN.saturating_sub(2) {
            return Err(Error::OutOfRange);
        }
        let mut raw = [0u8; 12];
        let hi = DIGITS.get(usize::from(id >> 4)).copied().unwrap_or(b'0');
        let lo = DIGITS.get(usize::from(id & 0x0F)).copied().unwrap_or(b'0');
        let (prefix, rest) = raw.split_at_mut(2);
        prefix.copy_from_slice(&[hi, lo]);
        let n = rest.len();
        rest.copy_from_slice(tail.raw.get(..n).unwrap_or_default());
        Ok(HardwareId { raw })
    }

    /// The product id: the first two characters read as hex (either case).
    pub const fn product_id(&self) -> Option<u8> {
        let [a, b, ..] = self.raw;
        match (hex_digit(a), hex_digit(b)) {
            (Some(h), Some(l)) => Some((h << 4) | l),
            _ => None,
        }
    }

    /// The product.
    pub const fn product(&self) -> Product {
        match self.product_id() {
            Some(id) => Product::from_id(id),
            None => Product::Unknown,
        }
    }

    /// The text without trailing NULs and spaces; `None` if it is not UTF-8.
    pub fn as_str(&self) -> Option<&str> {
        let end = self
            .raw
            .iter()
            .rposition(|&b| b != 0 && b != b' ')
            .map_or(0, |i| i.saturating_add(1));
        core::str::from_utf8(self.raw.get(..end)?).ok()
    }
}

#[cfg(feature = "serde")]
impl serde::Serialize for HardwareId {
    fn serialize<S: serde::Serializer>(&self, s: S) -> core::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut st = s.serialize_struct("HardwareId", 2)?;
        match self.as_str() {
            Some(text) => st.serialize_field("text", text)?,
            None => st.serialize_field("text", &self.raw)?,
        }
        st.serialize_field("product", self.product().name())?;
        st.end()
    }
}

impl Field<crate::wire::encoding::Le> for HardwareId {
    const LEN: usize = 12;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        r.array().map(|raw| HardwareId { raw })
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        w.put(&self.raw)
    }
}

impl Payload for HardwareId {
    fn decode(data: &[u8]) -> Result<Self> {
        let raw = <[u8; 12]>::try_from(data).map_err(|_| Error::BadLength)?;
        Ok(HardwareId { raw })
    }
    fn encoded_len(&self) -> usize {
        Self::LEN
    }
    fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
        w.put(&self.raw)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hardware_id_products() {
        let cases = [
            ("6B01234567", Product::Zr10),
            ("7301234567", Product::A8Mini),
            ("7501234567", Product::A2Mini),
            ("7801234567", Product::Zr30),
            ("8201234567", Product::Zt6),
            ("8301234567", Product::Zt6),
            ("7A01234567", Product::Zt30),
            ("7a01234567", Product::Zt30),
            ("6801130111", Product::Unknown),
            ("Z1", Product::Unknown),
            ("", Product::Unknown),
        ];
        for (text, product) in cases {
            let id = HardwareId::from_text(text).unwrap();
            assert_eq!(id.product(), product, "{text}");
            assert_eq!(id.as_str(), Some(text));
        }
        let id = HardwareId::for_product(Product::Zt30, "0123456789").unwrap();
        assert_eq!(&id.raw, b"7A0123456789");
        let id = HardwareId::for_product(Product::Zt6, "1").unwrap();
        assert_eq!(&id.raw, b"831\0\0\0\0\0\0\0\0\0");
        assert!(HardwareId::for_product(Product::Zt6, "01234567890").is_err());
        assert!(HardwareId::for_product(Product::Unknown, "1").is_err());
        assert!(HardwareId::from_text("0123456789ABC").is_err());
    }

    #[test]
    fn firmware_version_word() {
        let v = FirmwareVersion::from_u32(0x6E03_0203);
        assert_eq!((v.major, v.minor, v.patch, v.ignored), (3, 2, 3, 0x6E));
        assert_eq!(v.to_u32(), 0x6E03_0203);
    }

    #[test]
    fn trailing_lengths() {
        assert_eq!(trailing_len(&[(true, 1), (true, 2), (false, 4)]), 3);
        assert_eq!(trailing_len(&[(false, 1), (true, 2)]), 0);
    }
}
