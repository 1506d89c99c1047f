//! Field encodings of the GCU data frames and parameters (all little-endian; only the
//! CRC is big-endian) and the macro that declares fixed-layout structs.

use crate::wire::Reader;
use crate::{Error, Result};

pub(crate) use crate::wire::encoding::Field;

/// Decodes exactly `T::LEN` bytes; any other length is [`Error::BadLength`].
pub(crate) fn decode_exact<T: Field<crate::wire::encoding::Le>>(bytes: &[u8]) -> Result<T> {
    if bytes.len() != T::LEN {
        return Err(Error::BadLength);
    }
    let mut r = Reader::new(bytes);
    let v = T::read(&mut r)?;
    r.finish()?;
    Ok(v)
}

/// Declares a fixed-layout struct: the fields in wire order, each a [`Field`].
macro_rules! wire_struct {
    (
        $(#[$meta:meta])*
        pub struct $name:ident {
            $( $(#[$fmeta:meta])* pub $field:ident: $ty:ty, )*
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        #[cfg_attr(feature = "serde", derive(serde::Serialize))]
        pub struct $name {
            $( $(#[$fmeta])* pub $field: $ty, )*
        }

        impl $name {
            /// Encoded length in bytes.
            pub const LEN: usize = 0 $( + <$ty as $crate::gcu::field::Field<$crate::wire::encoding::Le>>::LEN )*;

            /// Decodes exactly [`Self::LEN`] bytes (any other length is
            /// [`Error::BadLength`](crate::Error::BadLength)).
            pub fn from_bytes(bytes: &[u8]) -> $crate::Result<Self> {
                $crate::gcu::field::decode_exact(bytes)
            }

            /// Encodes into the front of `out`; returns [`Self::LEN`].
            pub fn to_bytes(&self, out: &mut [u8]) -> $crate::Result<usize> {
                let mut w = $crate::wire::Writer::new(out);
                $crate::gcu::field::Field::<$crate::wire::encoding::Le>::write(self, &mut w)?;
                Ok(w.finish())
            }
        }

        impl $crate::gcu::field::Field<$crate::wire::encoding::Le> for $name {
            const LEN: usize = $name::LEN;

            fn read(r: &mut $crate::wire::Reader<'_>) -> $crate::Result<Self> {
                Ok(Self { $( $field: $crate::gcu::field::Field::<$crate::wire::encoding::Le>::read(r)?, )* })
            }

            fn write(&self, w: &mut $crate::wire::Writer<'_>) -> $crate::Result<()> {
                $( $crate::gcu::field::Field::<$crate::wire::encoding::Le>::write(&self.$field, w)?; )*
                Ok(())
            }
        }
    };
}

/// Declares a bit-set newtype over an unsigned integer (lossless: every bit is kept),
/// with a reader per named bit and a `with_*` builder per named bit.
macro_rules! bit_set {
    (
        $(#[$meta:meta])*
        pub struct $name:ident($repr:ty) {
            $( $(#[$bmeta:meta])* $bit:literal => $get:ident, $set:ident; )*
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        pub struct $name(pub $repr);

        impl $name {
            /// Every bit the document names.
            pub const NAMED: $repr = 0 $( | (1 << $bit) )*;

            $(
                $(#[$bmeta])*
                pub const fn $get(self) -> bool {
                    self.0 & (1 << $bit) != 0
                }

                #[doc = concat!("This value with bit ", stringify!($bit), " (`", stringify!($get), "`) set or cleared.")]
                #[must_use]
                pub const fn $set(self, on: bool) -> Self {
                    if on {
                        Self(self.0 | (1 << $bit))
                    } else {
                        Self(self.0 & !(1 << $bit))
                    }
                }
            )*

            /// The bits the document marks reserved, as received.
            pub const fn reserved_bits(self) -> $repr {
                self.0 & !Self::NAMED
            }
        }

        impl $crate::gcu::field::Field<$crate::wire::encoding::Le> for $name {
            const LEN: usize = core::mem::size_of::<$repr>();
            fn read(r: &mut $crate::wire::Reader<'_>) -> $crate::Result<Self> {
                <$repr as $crate::gcu::field::Field<$crate::wire::encoding::Le>>::read(r).map(Self)
            }
            fn write(&self, w: &mut $crate::wire::Writer<'_>) -> $crate::Result<()> {
                $crate::gcu::field::Field::<$crate::wire::encoding::Le>::write(&self.0, w)
            }
        }

        /// Serialized as `{"raw": n, "<bit>": bool, ...}`.
        #[cfg(feature = "serde")]
        impl serde::Serialize for $name {
            fn serialize<S: serde::Serializer>(&self, s: S) -> core::result::Result<S::Ok, S::Error> {
                use serde::ser::SerializeStruct;
                let fields = [$( stringify!($get) ),*].len().saturating_add(1);
                let mut st = s.serialize_struct(stringify!($name), fields)?;
                st.serialize_field("raw", &self.0)?;
                $( st.serialize_field(stringify!($get), &self.$get())?; )*
                st.end()
            }
        }
    };
}
