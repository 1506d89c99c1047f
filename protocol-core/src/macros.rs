//! The macros every codec declares its types with.
//!
//! - [`wire_derive!`]: the derives every public wire type carries (written once).
//! - [`code_enum!`]: an enumeration carried as an integer code, lossless (`Other`).
//! - [`wire_struct!`]: a fixed-layout struct, its fields in wire order, for either byte
//!   order; implements [`Field`](crate::wire::encoding::Field).
//! - [`wire_newtype!`], [`bit_set!`]: integer newtypes (packed values, flags).
//!
//! Each protocol's own payload trait (K40T and GCU read payloads through `Field`
//! directly, SIYI through `siyi::Payload`, Viewlink through `viewlink::Block`) has a
//! blanket implementation over `Field<O>`, so one struct macro, parameterised by the
//! byte order, serves all four.

/// Emits an item with the derives every public wire type of the crate carries: `Debug`,
/// `Clone`, `Copy`, `PartialEq`, the extra ones listed in brackets (`Eq`, `Hash`,
/// `Default` where the fields allow), `defmt::Format` and `serde::Serialize` behind
/// their features.
///
/// Exported so that crates built on the codecs (the bridge engine) declare their types
/// the same way. The `defmt` and `serde` features it tests are the *calling* crate's
/// (a `cfg_attr` in a macro's output is evaluated where it expands), so the caller needs
/// features of those names; `custom_serde` leaves `serde::Serialize` out, for a type
/// that implements it by hand or has none.
///
/// ```
/// protocol_core::wire_derive! {
///     [Eq, Hash]
///     /// A level.
///     pub enum Level { Low, High }
/// }
/// assert_ne!(Level::Low, Level::High);
/// ```
#[macro_export]
macro_rules! wire_derive {
    // `custom_serde`: the type implements `serde::Serialize` by hand.
    (custom_serde [$($extra:ident),*] $($item:tt)*) => {
        #[derive(Debug, Clone, Copy, PartialEq $(, $extra)*)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        $($item)*
    };
    ([$($extra:ident),*] $($item:tt)*) => {
        $crate::wire_derive! {
            custom_serde [$($extra),*]
            #[cfg_attr(feature = "serde", derive(serde::Serialize))]
            $($item)*
        }
    };
}

/// An enumeration carried on the wire as an integer, with an `Other` variant that keeps
/// any value the document does not list (so decoding is lossless).
///
/// Generates the enum, `value()`, `from_value()`, `name()`, `From` both ways, `Default`
/// (the variant for 0, or `Other(0)`) and [`WireCode`](crate::wire::encoding::WireCode)
/// (hence [`Field`](crate::wire::encoding::Field) in both byte orders). With the `serde`
/// feature it serialises as `{"name": "ZoomIn", "code": 9}` (`"Other"` for an unlisted
/// code), so a capture decoder shows both the name and the wire code. A variant without
/// a doc comment is documented by its wire value.
macro_rules! code_enum {
    (
        $(#[$meta:meta])*
        $vis:vis enum $name:ident: $repr:ty {
            $( $(#[$vmeta:meta])* $variant:ident = $value:literal, )*
        }
    ) => {
        wire_derive! {
            custom_serde [Eq, Hash]
            $(#[$meta])*
            $vis enum $name {
                $(
                    $(#[$vmeta])*
                    #[doc = code_enum!(@value_doc [$(#[$vmeta])*] $value)]
                    $variant,
                )*
                /// A value the document does not list, kept as received.
                Other($repr),
            }
        }

        impl $name {
            /// The value on the wire.
            #[must_use]
            pub const fn value(self) -> $repr {
                match self {
                    $( Self::$variant => $value, )*
                    Self::Other(v) => v,
                }
            }

            /// The variant for a wire value (`Other` when the document does not list it).
            #[must_use]
            pub const fn from_value(v: $repr) -> Self {
                match v {
                    $( $value => Self::$variant, )*
                    other => Self::Other(other),
                }
            }

            /// The variant's name (`"Other"` for an unlisted value).
            #[must_use]
            pub const fn name(self) -> &'static str {
                match self {
                    $( Self::$variant => stringify!($variant), )*
                    Self::Other(_) => "Other",
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

        impl $crate::wire::encoding::WireCode for $name {
            type Repr = $repr;
            fn to_repr(self) -> $repr {
                self.value()
            }
            fn from_repr(v: $repr) -> Self {
                Self::from_value(v)
            }
        }

        #[cfg(feature = "serde")]
        impl serde::Serialize for $name {
            fn serialize<S: serde::Serializer>(&self, s: S) -> core::result::Result<S::Ok, S::Error> {
                $crate::macros::serialize_code(s, self.name(), self.value())
            }
        }
    };
    // The doc of an undocumented variant: its wire value (nothing added to a documented one).
    (@value_doc [] $value:literal) => {
        concat!("Wire value ", stringify!($value), ".")
    };
    (@value_doc [$($documented:tt)+] $value:literal) => {
        ""
    };
}

/// Serialises an enumeration value as `{"name": .., "code": ..}` (see [`code_enum!`]).
#[cfg(feature = "serde")]
pub(crate) fn serialize_code<S: serde::Serializer, C: serde::Serialize>(
    s: S,
    name: &'static str,
    code: C,
) -> core::result::Result<S::Ok, S::Error> {
    use serde::ser::SerializeStruct as _;
    let mut out = s.serialize_struct("Code", 2)?;
    out.serialize_field("name", name)?;
    out.serialize_field("code", &code)?;
    out.end()
}

/// Declares a fixed-layout struct: the fields in wire order, each a
/// [`Field`](crate::wire::encoding::Field) in byte order `Le` or `Be`.
///
/// ```ignore
/// wire_struct! {
///     Le;
///     /// 0x000304: hybrid zoom.
///     pub struct HybridZoom {
///         /// Start flag.
///         pub start: u8,
///         /// Zoom ratio times ten.
///         pub zoom_x10: u16,
///     }
/// }
/// ```
///
/// Generates the struct (with [`wire_derive!`]: `Eq`, `Hash`, `Default` too, unless the
/// order is followed by `float`, for structs with `f32` fields; more derives may follow
/// the order in brackets, `Le [PartialOrd, Ord];`), an associated `LEN` and the `Field`
/// implementation. `Le, bytes;` declares a struct of `u8` fields only, read and written
/// as one array.
macro_rules! wire_struct {
    // `bytes`: every field is a `u8`; read and written as one array (smaller code than a
    // bounds check per field).
    (
        $order:ident, bytes $([$($more:ident),*])?;
        $(#[$meta:meta])*
        pub struct $name:ident {
            $( $(#[$fmeta:meta])* pub $field:ident: u8, )*
        }
    ) => {
        wire_derive! {
            [Eq, Hash, Default $($(, $more)*)?]
            $(#[$meta])*
            pub struct $name {
                $( $(#[$fmeta])* pub $field: u8, )*
            }
        }

        impl $name {
            /// Encoded length in bytes.
            pub const LEN: usize = [$( stringify!($field) ),*].len();
        }

        impl<O> $crate::wire::encoding::Field<O> for $name {
            const LEN: usize = $name::LEN;

            fn read(r: &mut $crate::wire::Reader<'_>) -> $crate::Result<Self> {
                let [$($field),*] = r.array()?;
                Ok(Self { $($field),* })
            }

            fn write(&self, w: &mut $crate::wire::Writer<'_>) -> $crate::Result<()> {
                w.put(&[$(self.$field),*])
            }
        }
    };
    (
        $order:ident, float;
        $(#[$meta:meta])*
        pub struct $name:ident { $($body:tt)* }
    ) => {
        wire_struct!(@def $order [Default] $(#[$meta])* $name { $($body)* });
    };
    (
        $order:ident $([$($more:ident),*])?;
        $(#[$meta:meta])*
        pub struct $name:ident { $($body:tt)* }
    ) => {
        wire_struct!(@def $order [Eq, Hash, Default $($(, $more)*)?] $(#[$meta])* $name { $($body)* });
    };
    (
        @def $order:ident [$($extra:ident),*]
        $(#[$meta:meta])*
        $name:ident {
            $( $(#[$fmeta:meta])* pub $field:ident: $ty:ty, )*
        }
    ) => {
        wire_derive! {
            [$($extra),*]
            $(#[$meta])*
            pub struct $name {
                $( $(#[$fmeta])* pub $field: $ty, )*
            }
        }

        impl $name {
            /// Encoded length in bytes.
            // `0 $(+ ...)*`: the sum of the field lengths, 0 for a struct without fields.
            pub const LEN: usize = 0 $( + <$ty as $crate::wire::encoding::Field<$crate::wire::encoding::$order>>::LEN )*;
        }

        impl $crate::wire::encoding::Field<$crate::wire::encoding::$order> for $name {
            const LEN: usize = $name::LEN;

            // `_r`/`_w`: unused in a struct without fields.
            fn read(_r: &mut $crate::wire::Reader<'_>) -> $crate::Result<Self> {
                Ok(Self { $( $field: $crate::wire::encoding::Field::<$crate::wire::encoding::$order>::read(_r)?, )* })
            }

            fn write(&self, _w: &mut $crate::wire::Writer<'_>) -> $crate::Result<()> {
                $( $crate::wire::encoding::Field::<$crate::wire::encoding::$order>::write(&self.$field, _w)?; )*
                Ok(())
            }
        }
    };
}

/// Declares newtypes over an integer carried as is (bit sets, packed nibbles) or over
/// another wire type (a message that shares another's layout), with
/// [`Field`](crate::wire::encoding::Field) in every byte order the inner type has;
/// accessors are written by hand next to them.
macro_rules! wire_newtype {
    ($( $(#[$meta:meta])* pub struct $name:ident($repr:ty); )*) => {$(
        wire_newtype!(@def [] $(#[$meta])* $name($repr));
    )*};
    // `[custom_serde]`: the type implements `serde::Serialize` by hand (`bit_set!`).
    (@def [$($custom:ident)?] $(#[$meta:meta])* $name:ident($repr:ty)) => {
        wire_derive! {
            $($custom)? [Eq, Hash, Default]
            $(#[$meta])*
            pub struct $name(pub $repr);
        }

        impl<O> $crate::wire::encoding::Field<O> for $name
        where
            $repr: $crate::wire::encoding::Field<O>,
        {
            const LEN: usize = <$repr as $crate::wire::encoding::Field<O>>::LEN;
            fn read(r: &mut $crate::wire::Reader<'_>) -> $crate::Result<Self> {
                <$repr as $crate::wire::encoding::Field<O>>::read(r).map(Self)
            }
            fn write(&self, w: &mut $crate::wire::Writer<'_>) -> $crate::Result<()> {
                <$repr as $crate::wire::encoding::Field<O>>::write(&self.0, w)
            }
        }
    };
}

/// Declares a [`wire_newtype!`] whose bits are flags (lossless: every bit is kept, named
/// or not), with a reader and a `with_*` builder per named bit, `contains(mask)` and
/// `reserved_bits()`.
macro_rules! bit_set {
    (
        $(#[$meta:meta])*
        pub struct $name:ident($repr:ty) {
            $( $(#[$bmeta:meta])* $bit:literal => $get:ident, $set:ident; )*
        }
    ) => {
        wire_newtype!(@def [custom_serde] $(#[$meta])* $name($repr));

        /// Serialised as `{"raw": n, "<bit>": bool, ...}`: the value and every named bit.
        #[cfg(feature = "serde")]
        impl serde::Serialize for $name {
            fn serialize<S: serde::Serializer>(&self, s: S) -> core::result::Result<S::Ok, S::Error> {
                use serde::ser::SerializeStruct as _;
                // "raw" and one field per named bit.
                let fields = [$( stringify!($get) ),*].len().saturating_add(1);
                let mut out = s.serialize_struct(stringify!($name), fields)?;
                out.serialize_field("raw", &self.0)?;
                $( out.serialize_field(stringify!($get), &self.$get())?; )*
                out.end()
            }
        }

        impl $name {
            $(
                $(#[$bmeta])*
                #[must_use]
                pub const fn $get(self) -> bool {
                    self.0 & (1 << $bit) != 0
                }

                #[doc = concat!("This set with `", stringify!($get), "` on or off.")]
                #[must_use]
                pub const fn $set(self, on: bool) -> Self {
                    if on {
                        Self(self.0 | (1 << $bit))
                    } else {
                        Self(self.0 & !(1 << $bit))
                    }
                }
            )*

            /// True when every bit of `mask` is set.
            #[must_use]
            pub const fn contains(self, mask: $repr) -> bool {
                self.0 & mask == mask
            }

            /// The bits no name is given to.
            #[must_use]
            pub const fn reserved_bits(self) -> $repr {
                // `0 $(| ...)*`: the mask of the named bits.
                self.0 & !(0 $( | (1 << $bit) )*)
            }
        }
    };
}

/// Declares a protocol's checked zero-copy frame view, `Frame<T: AsRef<[u8]>>`, with what
/// every protocol's view has: `new_unchecked`, `new_checked` (which calls the protocol's
/// own `check_len`), `into_inner`, and the private `byte`/`set_byte` accessors that read
/// 0 and write nothing past the end of the buffer. The protocol adds its field accessors.
macro_rules! frame_view {
    ($(#[$meta:meta])*) => {
        $(#[$meta])*
        #[derive(Debug, Clone)]
        pub struct Frame<T: AsRef<[u8]>> {
            buffer: T,
        }

        impl<T: AsRef<[u8]>> Frame<T> {
            /// A view without checks: accessors of an invalid buffer return zero or empty
            /// values (they never panic). Use [`Frame::new_checked`] for received bytes.
            pub const fn new_unchecked(buffer: T) -> Self {
                Frame { buffer }
            }

            /// A view of a buffer that holds a whole frame (its checksum is not verified
            /// here: see [`Frame::verify`]).
            ///
            /// # Errors
            /// As [`Frame::check_len`].
            pub fn new_checked(buffer: T) -> $crate::Result<Self> {
                let frame = Frame { buffer };
                frame.check_len()?;
                Ok(frame)
            }

            /// The underlying buffer.
            pub fn into_inner(self) -> T {
                self.buffer
            }

            /// The byte at `i` (0 past the end of the buffer).
            fn byte(&self, i: usize) -> u8 {
                self.buffer.as_ref().get(i).copied().unwrap_or(0)
            }
        }

        impl<T: AsRef<[u8]> + AsMut<[u8]>> Frame<T> {
            /// Sets the byte at `i` (nothing past the end of the buffer).
            fn set_byte(&mut self, i: usize, v: u8) {
                if let Some(b) = self.buffer.as_mut().get_mut(i) {
                    *b = v;
                }
            }
        }
    };
}
