//! The [`Payload`] trait (how one message's data is decoded and encoded, with the
//! length rules), the helpers of the few variable-length layouts, and the types several
//! messages share. All SIYI payload fields are little-endian.

use crate::wire::encoding::{Field, Le};
use crate::wire::table::PayloadCodec;
use crate::wire::{Reader, Writer};
use crate::{Error, Result};

/// The data of one message in one direction.
///
/// Every fixed-layout type (a [`Field<Le>`]: the structs declared with the crate's
/// struct macro) is a payload of exactly its length; the message types over a shared
/// layout (`GimbalRotationAck(SetStatus)`) are the payload of the layout they wrap; the
/// few layouts that vary in the wild (0x00 request, 0x01, 0x0A and 0x20 replies)
/// implement it by hand, remember the length they were decoded from and encode to it
/// again.
pub trait Payload: Sized {
    /// The longest encoding (the only one for a fixed layout).
    const MAX_LEN: usize;
    /// Decodes all of `data`.
    ///
    /// # Errors
    /// [`Error::BadLength`] for a length the layout does not allow.
    fn decode(data: &[u8]) -> Result<Self>;
    /// Length of the encoded data.
    fn encoded_len(&self) -> usize;
    /// Writes the data.
    ///
    /// # Errors
    /// [`Error::BufferTooSmall`] when `w` has no room for it; [`Error::OutOfRange`] for a
    /// variable-length value that has a trailing field after a missing one.
    fn encode(&self, w: &mut Writer<'_>) -> Result<()>;
}

impl<T: Field<Le>> Payload for T {
    const MAX_LEN: usize = T::LEN;

    fn decode(data: &[u8]) -> Result<Self> {
        if data.len() != T::LEN {
            return Err(Error::BadLength);
        }
        // The length is exact, so reading the layout consumes all of `data`.
        T::read(&mut Reader::new(data))
    }

    fn encoded_len(&self) -> usize {
        T::LEN
    }

    fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
        self.write(w)
    }
}

/// The SIYI length rules, for the message table: every payload is a [`Payload`].
impl<T: Payload> PayloadCodec<T> for super::Siyi {
    const MAX_LEN: usize = T::MAX_LEN;

    fn decode(payload: &[u8]) -> Result<T> {
        T::decode(payload)
    }

    fn encoded_len(value: &T) -> usize {
        value.encoded_len()
    }

    fn encode(value: &T, w: &mut Writer<'_>) -> Result<()> {
        value.encode(w)
    }
}

/// Reads the optional trailing fields of a variable-length layout: `Some` while bytes
/// remain, `None` after. The reader must then be empty.
pub(crate) fn optional<T: Field<Le>>(r: &mut Reader<'_>) -> Result<Option<T>> {
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

    pub(crate) fn field<T: Field<Le>>(&mut self, v: Option<&T>) -> Result<()> {
        match v {
            Some(_) if self.ended => Err(Error::OutOfRange),
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

wire_struct! {
    Le;
    /// A one-byte result (`sta`, `ack`, `format_sta`...): 1 success, 0 failure. The
    /// layout of the `...Ack` replies of the setting commands.
    pub struct SetStatus {
        /// Success or failure (another value kept as received).
        pub status: AckStatus,
    }
}

impl SetStatus {
    /// Success (1).
    pub const SUCCESS: SetStatus = SetStatus {
        status: AckStatus::Success,
    };
    /// Failure (0).
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

wire_derive! {
    [Eq, Hash, Default]
    /// One firmware version word of 0x01: a little-endian u32 whose bytes 0, 1, 2 are
    /// patch, minor, major ("0x6E030203 is v3.2.3"); byte 3 is ignored by readers and
    /// kept.
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
}

impl FirmwareVersion {
    /// A version with the ignored byte zero.
    #[must_use]
    pub const fn new(major: u8, minor: u8, patch: u8) -> Self {
        FirmwareVersion {
            patch,
            minor,
            major,
            ignored: 0,
        }
    }

    /// The version from its u32 value (`0x6E030203` is v3.2.3).
    #[must_use]
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
    #[must_use]
    pub const fn to_u32(self) -> u32 {
        u32::from_le_bytes([self.patch, self.minor, self.major, self.ignored])
    }
}

// Read and written as one u32 (smaller code than four byte fields).
impl Field<Le> for FirmwareVersion {
    const LEN: usize = 4;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        r.u32_le().map(FirmwareVersion::from_u32)
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u32_le(self.to_u32())
    }
}

wire_derive! {
    [Eq, Hash]
    /// The product a [`HardwareId`] names (its first two characters, the product id in
    /// hex text). Not a wire code: two ids name the ZT6.
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
}

impl Product {
    /// The product for a product id.
    #[must_use]
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
    #[must_use]
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
    #[must_use]
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

wire_derive! {
    custom_serde [Eq, Hash, Default]
    /// The hardware id of 0x02: 12 ASCII bytes (a 10-character id, usually NUL-padded)
    /// whose first two characters are the product id in hex text ("7A..." is a ZT30).
    /// Kept as the bytes received; serialises as its text and product name.
    pub struct HardwareId {
        /// The 12 bytes as on the wire.
        pub raw: [u8; 12],
    }
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

    /// The id for `text` (at most 12 printable ASCII characters, NUL-padded).
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for a longer text or one with other characters.
    pub fn from_text(text: &str) -> Result<Self> {
        if text.len() > Self::LEN || !text.bytes().all(|b| b.is_ascii_graphic() || b == b' ') {
            return Err(Error::OutOfRange);
        }
        let mut raw = [0u8; 12];
        let dst = raw.get_mut(..text.len()).ok_or(Error::OutOfRange)?;
        crate::wire::copy(dst, text.as_bytes());
        Ok(HardwareId { raw })
    }

    /// An id for `product`: its two upper-case hex digits (as ArduPilot matches them)
    /// followed by `serial` (at most 10 printable ASCII characters), NUL-padded.
    ///
    /// # Errors
    /// [`Error::OutOfRange`] for [`Product::Unknown`] or a bad serial.
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
        let [first, second, rest @ ..] = &mut raw;
        (*first, *second) = (hi, lo);
        crate::wire::copy(rest, &tail.raw);
        Ok(HardwareId { raw })
    }

    /// The product id: the first two characters read as hex (either case).
    #[must_use]
    pub const fn product_id(&self) -> Option<u8> {
        let [a, b, ..] = self.raw;
        match (hex_digit(a), hex_digit(b)) {
            (Some(h), Some(l)) => Some((h << 4) | l),
            _ => None,
        }
    }

    /// The product the id names (from its first two characters, read as hex).
    #[must_use]
    pub const fn product(&self) -> Product {
        match self.product_id() {
            Some(id) => Product::from_id(id),
            None => Product::Unknown,
        }
    }

    /// The text without trailing NULs and spaces; `None` if it is not UTF-8.
    #[must_use]
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
        let mut out = s.serialize_struct("HardwareId", 2)?;
        match self.as_str() {
            Some(text) => out.serialize_field("text", text)?,
            None => out.serialize_field("text", &self.raw)?,
        }
        out.serialize_field("product", self.product().name())?;
        out.end()
    }
}

impl Field<Le> for HardwareId {
    const LEN: usize = HardwareId::LEN;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        r.array().map(|raw| HardwareId { raw })
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
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
        // The word is little-endian on the wire: byte 0 is the patch.
        let mut buf = [0u8; 4];
        let mut w = Writer::new(&mut buf);
        Field::<Le>::write(&v, &mut w).unwrap();
        assert_eq!(buf, 0x6E03_0203u32.to_le_bytes());
        assert_eq!(<FirmwareVersion as Payload>::decode(&buf), Ok(v));
    }

    #[test]
    fn fixed_layouts_are_payloads_of_exactly_their_length() {
        assert_eq!(<SetStatus as Payload>::decode(&[1]), Ok(SetStatus::SUCCESS));
        assert_eq!(<SetStatus as Payload>::decode(&[]), Err(Error::BadLength));
        assert_eq!(
            <SetStatus as Payload>::decode(&[1, 0]),
            Err(Error::BadLength)
        );
        assert_eq!(<HardwareId as Payload>::MAX_LEN, 12);
        assert_eq!(
            <HardwareId as Payload>::decode(b"7A0123456789").map(|h| h.product()),
            Ok(Product::Zt30)
        );
        assert_eq!(
            <HardwareId as Payload>::decode(b"7A012345678"),
            Err(Error::BadLength)
        );
    }

    #[test]
    fn trailing_lengths() {
        assert_eq!(trailing_len(&[(true, 1), (true, 2), (false, 4)]), 3);
        assert_eq!(trailing_len(&[(false, 1), (true, 2)]), 0);
    }
}
