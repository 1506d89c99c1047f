//! The crate's single error type.

use core::fmt;

wire_derive! {
    [Eq, Hash]
    /// What was wrong with a frame, a payload or an output buffer.
    ///
    /// Small and `Copy`; every decoding and encoding failure in the crate is one of these.
    /// No function of the crate panics on any input.
    pub enum Error {
        /// The input ended before the structure was complete.
        Truncated,
        /// The frame does not start with the protocol's sync bytes.
        BadSync,
        /// A length field is inconsistent with the protocol or with the bytes present,
        /// or a payload has more or fewer bytes than its message defines.
        BadLength,
        /// The checksum carried by the frame does not match the one computed over it.
        BadChecksum {
            /// Checksum computed over the received bytes.
            computed: u16,
            /// Checksum the frame carries.
            received: u16,
        },
        /// The message id is not one this codec knows and the operation needs a known one
        /// (decoding never fails for this: unknown ids decode to a raw variant).
        UnknownId,
        /// A field holds a value outside the range its type or the protocol allows.
        OutOfRange,
        /// The output buffer is too small for the encoded frame.
        BufferTooSmall,
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Truncated => f.write_str("truncated: input ended early"),
            Error::BadSync => f.write_str("bad sync bytes"),
            Error::BadLength => f.write_str("bad length"),
            Error::BadChecksum { computed, received } => write!(
                f,
                "bad checksum: computed {computed:#06x}, frame carries {received:#06x}"
            ),
            Error::UnknownId => f.write_str("unknown message id"),
            Error::OutOfRange => f.write_str("field out of range"),
            Error::BufferTooSmall => f.write_str("output buffer too small"),
        }
    }
}

impl core::error::Error for Error {}

/// Result with the crate's [`Error`].
pub type Result<T> = core::result::Result<T, Error>;
