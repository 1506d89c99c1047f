//! Macros shared by the codecs.

/// An enumeration carried on the wire as an integer, with an `Other` variant that keeps
/// any value the document does not list (so decoding is lossless).
///
/// Generates the enum (deriving the usual traits, `defmt::Format` and `serde::Serialize`
/// behind their features), `value()`, `from_value()`, `From` both ways, `Default` (the
/// variant for 0, or `Other(0)`), and an implementation of [`WireCode`](crate::macros::WireCode).
macro_rules! code_enum {
    (
        $(#[$meta:meta])*
        $vis:vis enum $name:ident: $repr:ty {
            $( $(#[$vmeta:meta])* $variant:ident = $value:literal, )*
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        #[cfg_attr(feature = "serde", derive(serde::Serialize))]
        $vis enum $name {
            $( $(#[$vmeta])* $variant, )*
            /// A value the document does not list, kept as received.
            Other($repr),
        }

        impl $name {
            /// The value on the wire.
            pub const fn value(self) -> $repr {
                match self {
                    $( Self::$variant => $value, )*
                    Self::Other(v) => v,
                }
            }

            /// The variant for a wire value (`Other` when the document does not list it).
            pub const fn from_value(v: $repr) -> Self {
                match v {
                    $( $value => Self::$variant, )*
                    other => Self::Other(other),
                }
            }
        }

        impl From<$repr> for $name {
            fn from(v: $repr) -> Self {
                Self::from_value(v)
            }
        }

        impl From<$name> for $repr {
            fn from(v: $name) -> Self {
                v.value()
            }
        }

        impl Default for $name {
            fn default() -> Self {
                Self::from_value(0)
            }
        }

        impl $crate::macros::WireCode for $name {
            type Repr = $repr;
            fn to_repr(self) -> $repr {
                self.value()
            }
            fn from_repr(v: $repr) -> Self {
                Self::from_value(v)
            }
        }
    };
}

/// Implemented by every [`code_enum!`] type: conversion to and from the wire integer.
pub(crate) trait WireCode: Copy {
    /// The integer type on the wire.
    type Repr;
    /// The wire value.
    fn to_repr(self) -> Self::Repr;
    /// The variant for a wire value.
    fn from_repr(v: Self::Repr) -> Self;
}
