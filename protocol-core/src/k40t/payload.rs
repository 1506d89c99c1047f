//! Types several K40T payloads share (the ACK response code, versions), the decoding
//! rule for payload lengths, and the declaration helpers of the K40T payload structs.
//! Payload fields are little-endian (except the ACK response code).

use crate::wire::encoding::{Field, Le};
use crate::wire::table::PayloadCodec;
use crate::wire::{Reader, Writer};
use crate::{Error, Result};

/// The K40T length rules, for the message table: a payload is read with
/// [`decode_payload`] and written with its layout.
impl<T: Field<Le>> PayloadCodec<T> for super::K40t {
    const MAX_LEN: usize = T::LEN;

    fn decode(payload: &[u8]) -> Result<T> {
        decode_payload(payload)
    }

    fn encoded_len(_: &T) -> usize {
        T::LEN
    }

    fn encode(value: &T, w: &mut Writer<'_>) -> Result<()> {
        value.write(w)
    }
}

/// Decodes a payload the way the frame carries it.
///
/// A payload shorter than the layout is zero-extended: the LEN description of the
/// document is MAVLink v2's, whose senders drop trailing zero bytes, and several of the
/// document's layouts disagree by a trailing reserved byte. A longer one is
/// [`Error::BadLength`].
pub(crate) fn decode_payload<T: Field<Le>>(payload: &[u8]) -> Result<T> {
    let mut extended = [0u8; super::MAX_PAYLOAD_LEN];
    let bytes = match payload.len() {
        n if n == T::LEN => payload,
        n if n > T::LEN => return Err(Error::BadLength),
        n => {
            let dst = extended.get_mut(..n).ok_or(Error::BadLength)?;
            crate::wire::copy(dst, payload);
            extended.get(..T::LEN).ok_or(Error::BadLength)?
        }
    };
    let mut r = Reader::new(bytes);
    let v = T::read(&mut r)?;
    r.finish()?;
    Ok(v)
}

code_enum! {
    /// ACK response codes (table 3.3).
    pub enum AckCode: u16 {
        /// OK, success.
        Ok = 0x0000,
        Failure = 0x0001,
        /// Unknown error.
        UnknownError = 0x0002,
        /// Verification failed.
        VerificationFailed = 0x0003,
        Timeout = 0x0004,
        /// MD5 verification failed.
        Md5Failed = 0x0005,
        /// Insufficient system space.
        NoSpace = 0x0006,
        /// The data length does not match the actual length.
        LengthMismatch = 0x0007,
        /// In progress, repeated request.
        InProgress = 0x0008,
        /// The file does not exist.
        FileNotFound = 0x0009,
        /// Error merging files.
        MergeFailed = 0x000A,
        /// Recording video.
        Recording = 0x0201,
        /// Failed to open the camera.
        CameraOpenFailed = 0x0202,
        /// A photo is being taken.
        PhotoInProgress = 0x0203,
        /// No SD card is inserted.
        NoSdCard = 0x0204,
    }
}

wire_derive! {
    custom_serde [Eq, Hash, Default]
    /// The 2-byte response code of an ACK, kept as the two bytes received.
    ///
    /// The document says multi-byte fields are little-endian "except ACK": this crate
    /// encodes the code big-endian. Devices may send either order; every code of table 3.3
    /// is unambiguous in both, so [`ResponseCode::code`] reports the known code for either
    /// order, and re-encoding gives back the bytes received.
    pub struct ResponseCode {
        /// The two bytes as on the wire.
        pub raw: [u8; 2],
    }
}

impl ResponseCode {
    /// Success (0x0000).
    pub const OK: ResponseCode = ResponseCode { raw: [0, 0] };

    /// The code, encoded big-endian.
    #[must_use]
    pub const fn new(code: AckCode) -> Self {
        ResponseCode {
            raw: code.value().to_be_bytes(),
        }
    }

    /// The code, read in whichever byte order gives a code of table 3.3 (big-endian
    /// first); an unknown code is reported big-endian as `Other`.
    #[must_use]
    pub const fn code(&self) -> AckCode {
        let be = AckCode::from_value(u16::from_be_bytes(self.raw));
        match (be, AckCode::from_value(u16::from_le_bytes(self.raw))) {
            (AckCode::Other(_), AckCode::Other(_)) => be,
            (AckCode::Other(_), le) => le,
            (be, _) => be,
        }
    }

    /// True for code 0 (success).
    #[must_use]
    pub const fn is_ok(&self) -> bool {
        matches!(self.code(), AckCode::Ok)
    }
}

impl From<AckCode> for ResponseCode {
    fn from(code: AckCode) -> Self {
        ResponseCode::new(code)
    }
}

#[cfg(feature = "serde")]
impl serde::Serialize for ResponseCode {
    fn serialize<S: serde::Serializer>(&self, s: S) -> core::result::Result<S::Ok, S::Error> {
        self.code().serialize(s)
    }
}

impl Field<Le> for ResponseCode {
    const LEN: usize = 2;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        r.array().map(|raw| ResponseCode { raw })
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        w.put(&self.raw)
    }
}

wire_struct! {
    Le, bytes [PartialOrd, Ord];
    /// A three-part version number (major, minor, patch), one byte each.
    pub struct Version {
        /// Major version.
        pub major: u8,
        /// Minor (sub) version.
        pub minor: u8,
        /// Patch version.
        pub patch: u8,
    }
}

/// Declares the "command byte + reserved byte" requests (drift calibration, soft
/// restart, format, ...).
macro_rules! trigger {
    ($($(#[$m:meta])* $name:ident;)*) => {$(
        wire_struct! {
            Le;
            $(#[$m])*
            pub struct $name {
                /// The command byte.
                pub command: u8,
                /// Reserved; kept as received, so the frame re-encodes as it came.
                pub reserved: u8,
            }
        }
    )*};
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn response_code_accepts_both_byte_orders() {
        for code in [
            AckCode::Ok,
            AckCode::Failure,
            AckCode::MergeFailed,
            AckCode::Recording,
            AckCode::NoSdCard,
        ] {
            let be = ResponseCode {
                raw: code.value().to_be_bytes(),
            };
            let le = ResponseCode {
                raw: code.value().to_le_bytes(),
            };
            assert_eq!(be.code(), code);
            assert_eq!(le.code(), code);
        }
        assert_eq!(ResponseCode::new(AckCode::Recording).raw, [0x02, 0x01]);
        assert_eq!(
            ResponseCode { raw: [0x12, 0x34] }.code(),
            AckCode::Other(0x1234)
        );
        assert!(ResponseCode::OK.is_ok());
        assert!(!ResponseCode { raw: [1, 0] }.is_ok());
    }

    #[test]
    fn short_payload_is_zero_extended_and_long_one_refused() {
        wire_struct! {
            Le;
            /// Two bytes.
            pub struct Two {
                pub a: u8,
                pub b: u8,
            }
        }
        #[allow(non_snake_case)]
        fn Two(a: u8, b: u8) -> Two {
            Two { a, b }
        }
        assert_eq!(decode_payload::<Two>(&[7]), Ok(Two(7, 0)));
        assert_eq!(decode_payload::<Two>(&[7, 8]), Ok(Two(7, 8)));
        assert_eq!(decode_payload::<Two>(&[7, 8, 9]), Err(Error::BadLength));
    }
}
