//! The one message-table generator of the four codecs, `message_table!`, and the traits
//! its tables implement: [`Protocol`] (a protocol's id and message types) and
//! [`MessageData`] (one typed message, after rust-mavlink's).
//!
//! Each protocol declares its messages once, in a table in its own module; the table
//! generates the payload types it defines, the message enums with their decoders and
//! encoders, [`MessageData`] for every payload type and the protocol's `CATALOG`, so
//! they cannot disagree.

use crate::Result;
use crate::wire::Writer;

/// A protocol whose messages a `message_table!` declares (implemented by the protocol's
/// marker type: `k40t::K40t`, `siyi::Siyi`, `viewlink::Viewlink`, `gcu::Gcu`).
pub trait Protocol {
    /// A message id: K40T's `MsgId` (kind and base id), the command, frame or order byte
    /// of the others.
    type Id: Copy + PartialEq + core::fmt::Debug;
    /// A decoded message: a variant per message of the table, and `Raw` for the others.
    type Message<'a>;
}

/// A typed message: the payload type of one message of a protocol (after rust-mavlink's
/// `MessageData`), implemented by the protocol's message table for every payload type it
/// names. Each protocol module re-exports it.
///
/// A function over the messages of one protocol names the protocol in the bound:
///
/// ```
/// use protocol_core::k40t::{self, Address, Header, HybridZoom, K40t, MessageData};
///
/// /// Any K40T message as a frame from the flight controller to the pod.
/// fn to_pod<M>(m: &M, buf: &mut [u8]) -> protocol_core::Result<usize>
/// where
///     M: MessageData<Protocol = K40t>,
/// {
///     k40t::encode(m, &Header::new(Address::FLIGHT_CONTROLLER, Address::POD, 0), buf)
/// }
///
/// let mut buf = [0u8; k40t::MAX_FRAME_LEN];
/// let zoom = HybridZoom { start: 0, zoom_x10: 45 };
/// assert_eq!(to_pod(&zoom, &mut buf), Ok(k40t::MIN_FRAME_LEN + HybridZoom::ENCODED_LEN));
/// ```
pub trait MessageData: Copy {
    /// The protocol the message belongs to.
    type Protocol: Protocol;
    /// The message id.
    const ID: <Self::Protocol as Protocol>::Id;
    /// The name of the table row: the message name its protocol's `CATALOG` lists
    /// (shared by the messages of one row: a K40T request and its ACK, a SIYI request and
    /// its reply).
    const NAME: &'static str;
    /// Encoded payload length in bytes; the longest one where the length varies (SIYI's
    /// variable replies, Viewlink's variable blocks).
    const ENCODED_LEN: usize;

    /// This payload as a decoded message.
    fn into_message(self) -> <Self::Protocol as Protocol>::Message<'static>;

    /// The payload, if `message` is this message.
    fn from_message(message: &<Self::Protocol as Protocol>::Message<'_>) -> Option<Self>;

    /// Length of this value's encoded payload ([`MessageData::ENCODED_LEN`] unless the
    /// length varies).
    fn payload_len(&self) -> usize;

    /// Decodes a whole payload, by the protocol's length rules.
    ///
    /// # Errors
    /// [`Error::BadLength`](crate::Error::BadLength) for a length the protocol's rules
    /// refuse, and the layout's own errors.
    fn decode_payload(payload: &[u8]) -> Result<Self>;

    /// Writes the payload.
    ///
    /// # Errors
    /// [`Error::BufferTooSmall`](crate::Error::BufferTooSmall) when `w` has no room for it;
    /// [`Error::OutOfRange`](crate::Error::OutOfRange) for a value the layout cannot
    /// encode.
    fn encode_payload(&self, w: &mut Writer<'_>) -> Result<()>;
}

/// How a protocol reads and writes the payload layouts its table names (implemented by
/// the protocol's marker type over the protocol's own payload trait): the one place that
/// holds its length rules.
pub(crate) trait PayloadCodec<T> {
    /// The longest encoding of a `T`.
    const MAX_LEN: usize;
    /// Decodes a whole payload.
    fn decode(payload: &[u8]) -> Result<T>;
    /// Length of `value`'s encoding.
    fn encoded_len(value: &T) -> usize;
    /// Writes `value`.
    fn encode(value: &T, w: &mut Writer<'_>) -> Result<()>;
}

/// Declares a protocol's messages, once: the header says what the protocol's types are,
/// each row is one message id with the payload type of each of its messages.
///
/// ```text
/// message_table! {
///     /// The K40T protocol.
///     protocol K40t { id: MsgId, key: u16, order: Le, lengths: fixed, encoders: out_of_line }
///     /// Every base id this codec knows.
///     catalog;
///     /// A decoded message.
///     message Message [Eq] {
///         /// Unknown id or kind.
///         Raw;
///         /// Kind 0x00: requests and reports.
///         Request [Eq] = MsgId::new(Kind::Request);
///         /// Kind 0x01: acknowledgements.
///         Ack [Eq] = MsgId::new(Kind::Ack) impl AckPayload {
///             fn code(&self) -> ResponseCode { self.code }
///         };
///     }
///     0x0001 GimbalStatus: Request(GimbalStatus);
///     0x0304 HybridZoom: Request(HybridZoom), Ack(HybridZoomAck { code: ResponseCode });
/// }
/// ```
///
/// **Header.**
/// - `protocol Name { id: Id, key: Key, order: Le|Be, lengths: fixed|variable,
///   encoders: out_of_line|inlined, ids: order() -> Order(u8) }`: the marker type it
///   declares, with [`Protocol`] (`Id` its message id, `Message` the table's message
///   enum); `Key` is the type of the row ids; `order` the byte order of the structs the
///   table defines; `fixed` when every payload has its [`MessageData::ENCODED_LEN`]
///   (`payload_len` is then a `const fn`), `variable` when the value says;
///   `out_of_line` keeps one copy of each enum's `encode` (`#[inline(never)]`). Its
///   payloads are read and written through `PayloadCodec`, which the protocol implements
///   for its marker. `ids` (optional, nested tables) declares the row ids as a
///   `code_enum!` named after the rows, which the groups' enums match on and return
///   (`order()`).
/// - `catalog;`: `CATALOG`, one entry per row, built by the protocol's
///   `CatalogEntry::new(row id, name, &[ENCODED_LEN of each message of the row], args..)`.
/// - `message Message [derives] { Raw; groups }`: the decoded message, with its `Raw`
///   variant for unknown ids (the protocol declares `Raw<'a>` with `id` and `payload`).
///   With no group, the rows are its variants (`Message::decode` included). Each group
///   `Group [derives] = id_fn(args) impl Trait { items };` is an enum with a variant per
///   row that has a message of it, and a variant of `Message`; `= id_fn(args)` makes the
///   message id `id_fn(args.., row id)` (else the row id is the id); every payload of the
///   group implements each `impl Trait { .. }` (constants, and `&self` methods the
///   group's enum gets too, dispatched to its variant).
///
/// **Rows.** `0x07 Name: Group(Type), Group(Type) => args;`, the messages a prefix of the
/// groups, in order (`Message(Type)` without groups). `Type` is declared elsewhere, or
/// here: `Type {}` an empty struct, `Type(Layout)` a newtype and `Type { field: Layout }`
/// a one-field struct over another message's layout, decoded and encoded through that
/// layout's functions (so that code size does not grow with the number of messages that
/// share one). A row's doc comments go to its variants and the types it defines.
macro_rules! message_table {
    (
        $(#[$proto_meta:meta])*
        protocol $proto:ident {
            id: $id:ty, key: $key:ty, order: $order:ident, lengths: $lengths:ident,
            encoders: $encoders:ident
            $(, $(#[$ids_meta:meta])* ids: $ids_fn:ident() -> $ids:ident($ids_repr:ty))? $(,)?
        }
        $(#[$catalog_meta:meta])*
        catalog;
        $(#[$message_meta:meta])*
        message $message:ident [$($message_derive:ident),*] {
            $(#[$raw_meta:meta])*
            Raw;
            $(
                $(#[$group_meta:meta])*
                $group:ident [$($group_derive:ident),*]
                $(= $($id_fn:ident)::+ ($($id_arg:expr),*))?
                $(impl $group_trait:path { $($group_item:tt)* })*;
            )*
        }
        $(
            $(#[$row_meta:meta])*
            $row:literal $name:ident: $($label:ident ($($message_spec:tt)*)),+
            $(=> $($catalog_arg:expr),+)?;
        )*
    ) => {
        message_table!(@arity [$($group)*]
            [$proto [$(#[$proto_meta])*] [$id] [$key] $order $lengths $encoders]
            [$(#[$catalog_meta])*]
            [$( [$(#[$ids_meta])*] $ids [$ids_repr] $ids_fn )?]
            [$message [$($message_derive),*] [$(#[$message_meta])*] [$(#[$raw_meta])*]]
            [$(
                [$group [$(#[$group_meta])*] [$($group_derive),*]
                    [$($($id_fn)::+ ($($id_arg),*))?]
                    [$(impl $group_trait { $($group_item)* })*]]
            )*]
            $(
                [$(#[$row_meta])*] $row $name: $($label ($($message_spec)*)),+
                [$($($catalog_arg),+)?];
            )*
        );
    };

    // Sorting each row's messages into their groups, by position (a row's messages are a
    // prefix of the groups). Without groups the rows are the message's variants.
    (@arity [] $header:tt $catalog:tt $ids:tt [$message:ident $($message_rest:tt)*] [] $(
        $row_meta:tt $row:literal $name:ident: $l1:ident ($t1:ident $($d1:tt)?)
            [$($catalog_arg:expr),*];
    )*) => {
        message_table!(@generate flat $header $catalog $ids [$message $($message_rest)*]
            [[[$message [] [] [] []] [$( [$l1 $row $name $t1 [$($d1)?] $row_meta] )*]]]
            [$( [$row_meta $row $name [$t1] [$($catalog_arg),*]] )*]
        );
    };
    (@arity [$_g1:ident] $header:tt $catalog:tt $ids:tt $message:tt [$group1:tt] $(
        $row_meta:tt $row:literal $name:ident: $l1:ident ($t1:ident $($d1:tt)?)
            [$($catalog_arg:expr),*];
    )*) => {
        message_table!(@generate nested $header $catalog $ids $message
            [[$group1 [$( [$l1 $row $name $t1 [$($d1)?] $row_meta] )*]]]
            [$( [$row_meta $row $name [$t1] [$($catalog_arg),*]] )*]
        );
    };
    (@arity [$_g1:ident $_g2:ident] $header:tt $catalog:tt $ids:tt $message:tt
        [$group1:tt $group2:tt] $(
        $row_meta:tt $row:literal $name:ident:
            $l1:ident ($t1:ident $($d1:tt)?) $(, $l2:ident ($t2:ident $($d2:tt)?))?
            [$($catalog_arg:expr),*];
    )*) => {
        message_table!(@generate nested $header $catalog $ids $message
            [
                [$group1 [$( [$l1 $row $name $t1 [$($d1)?] $row_meta] )*]]
                [$group2 [$( $( [$l2 $row $name $t2 [$($d2)?] $row_meta] )? )*]]
            ]
            [$( [$row_meta $row $name [$t1 $(, $t2)?] [$($catalog_arg),*]] )*]
        );
    };
    (@arity [$_g1:ident $_g2:ident $_g3:ident] $header:tt $catalog:tt $ids:tt $message:tt
        [$group1:tt $group2:tt $group3:tt] $(
        $row_meta:tt $row:literal $name:ident:
            $l1:ident ($t1:ident $($d1:tt)?)
            $(, $l2:ident ($t2:ident $($d2:tt)?) $(, $l3:ident ($t3:ident $($d3:tt)?))?)?
            [$($catalog_arg:expr),*];
    )*) => {
        message_table!(@generate nested $header $catalog $ids $message
            [
                [$group1 [$( [$l1 $row $name $t1 [$($d1)?] $row_meta] )*]]
                [$group2 [$( $( [$l2 $row $name $t2 [$($d2)?] $row_meta] )? )*]]
                [$group3 [$( $( $( [$l3 $row $name $t3 [$($d3)?] $row_meta] )? )? )*]]
            ]
            [$( [$row_meta $row $name [$t1 $(, $t2 $(, $t3)?)?] [$($catalog_arg),*]] )*]
        );
    };

    // Everything, from the sorted table.
    (@generate $mode:ident
        [$proto:ident [$($proto_meta:tt)*] [$id:ty] [$key:ty]
            $order:ident $lengths:ident $encoders:ident]
        [$($catalog_meta:tt)*]
        $ids:tt
        [$message:ident [$($message_derive:ident),*] [$($message_meta:tt)*] [$($raw_meta:tt)*]]
        [$(
            [[$group:ident $group_meta:tt $group_derive:tt $id_spec:tt $impls:tt]
                [$( [$label:ident $row:literal $name:ident $ty:ident $shape:tt $row_meta:tt] )*]]
        )*]
        [$(
            [[$($catalog_row_meta:tt)*] $catalog_row:literal $catalog_name:ident
                [$($catalog_ty:ident),*] [$($catalog_arg:expr),*]]
        )*]
    ) => {
        $($proto_meta)*
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        pub enum $proto {}

        impl $crate::wire::Protocol for $proto {
            type Id = $id;
            type Message<'a> = $message<'a>;
        }

        $(
            $(
                message_table!(@declare_type $order $group $row $name $ty $shape $row_meta);
                message_table!(@message_data $mode $proto [$id] $message $group $id_spec
                    $label $row $name $ty $shape);
                message_table!(@member_impls $ty $impls);
            )*
            message_table!(@group $mode $proto [$id] [$key] $lengths $encoders $ids
                [$group $group_meta $group_derive $impls]
                [$( [$row $name $ty $shape $row_meta] )*]);
        )*

        message_table!(@message $mode $proto [$id] [$key] $lengths $encoders
            [$message [$($message_derive),*] [$($message_meta)*] [$($raw_meta)*]]
            [$( [$group $group_meta] )*]
            [$($( [$row $name $ty $shape $row_meta] )*)*]);

        message_table!(@ids $ids [$( [$($catalog_row_meta)*] $catalog_row $catalog_name )*]);

        $($catalog_meta)*
        pub const CATALOG: &[CatalogEntry] = &[$(
            CatalogEntry::new(
                $catalog_row,
                stringify!($catalog_name),
                &[$(<$catalog_ty as $crate::wire::MessageData>::ENCODED_LEN),*],
                $($catalog_arg),*
            ),
        )*];

        impl $message<'_> {
            /// The typed payload, if this is message `M`: `message.get::<Type>()`.
            #[must_use]
            pub fn get<M: $crate::wire::MessageData<Protocol = $proto>>(&self) -> Option<M> {
                M::from_message(self)
            }
        }
    };

    // The payload types a row defines (nothing for a type declared elsewhere).
    (@declare_type $order:ident $group:ident $row:literal $name:ident $ty:ident []
        $row_meta:tt) => {};
    (@declare_type $order:ident $group:ident $row:literal $name:ident $ty:ident [{}]
        [$($row_meta:tt)*]) => {
        wire_struct! {
            $order;
            $($row_meta)*
            #[doc = ""]
            #[doc = concat!(stringify!($group), " ", stringify!($row), " (", stringify!($name),
                "): no data.")]
            pub struct $ty {}
        }
    };
    (@declare_type $order:ident $group:ident $row:literal $name:ident $ty:ident [($layout:ty)]
        [$($row_meta:tt)*]) => {
        wire_newtype! {
            $($row_meta)*
            #[doc = ""]
            #[doc = concat!(stringify!($group), " ", stringify!($row), " (", stringify!($name),
                "): the layout of [`", stringify!($layout), "`].")]
            pub struct $ty($layout);
        }

        impl From<$layout> for $ty {
            fn from(layout: $layout) -> Self {
                $ty(layout)
            }
        }
    };
    (@declare_type $order:ident $group:ident $row:literal $name:ident $ty:ident
        [{ $field:ident: $layout:ty }] [$($row_meta:tt)*]) => {
        wire_struct! {
            $order;
            $($row_meta)*
            #[doc = ""]
            #[doc = concat!(stringify!($group), " ", stringify!($row), " (", stringify!($name),
                "): a [`", stringify!($layout), "`].")]
            pub struct $ty {
                #[doc = concat!("The [`", stringify!($layout), "`].")]
                pub $field: $layout,
            }
        }

        impl From<$layout> for $ty {
            fn from($field: $layout) -> Self {
                $ty { $field }
            }
        }
    };

    // A payload type's layout: its own, or the one it wraps.
    (@layout $ty:ident []) => { $ty };
    (@layout $ty:ident [{}]) => { $ty };
    (@layout $ty:ident [($layout:ty)]) => { $layout };
    (@layout $ty:ident [{ $field:ident: $layout:ty }]) => { $layout };
    // The layout of the payload `$value` (a reference).
    (@layout_of [] $value:tt) => { $value };
    (@layout_of [{}] $value:tt) => { $value };
    (@layout_of [($layout:ty)] $value:tt) => { &$value.0 };
    (@layout_of [{ $field:ident: $layout:ty }] $value:tt) => { &$value.$field };
    // Decodes a payload of type `$ty` from `$payload`, through its layout.
    (@decode $proto:ident $ty:ident [] $payload:ident) => {
        <$proto as $crate::wire::table::PayloadCodec<$ty>>::decode($payload)
    };
    (@decode $proto:ident $ty:ident [{}] $payload:ident) => {
        <$proto as $crate::wire::table::PayloadCodec<$ty>>::decode($payload)
    };
    (@decode $proto:ident $ty:ident [$wrapped:tt] $payload:ident) => {
        <$proto as $crate::wire::table::PayloadCodec<message_table!(@layout $ty [$wrapped])>>
            ::decode($payload)
            .map(<$ty>::from)
    };
    // Writes the payload `$value` (a reference) through its layout.
    (@encode $proto:ident $ty:ident $shape:tt $value:tt $w:ident) => {
        <$proto as $crate::wire::table::PayloadCodec<message_table!(@layout $ty $shape)>>::encode(
            message_table!(@layout_of $shape $value),
            $w,
        )
    };
    // The message id of a row's message in a group.
    (@id [] $row:literal) => { $row };
    (@id [$($id_fn:ident)::+ ($($id_arg:expr),*)] $row:literal) => {
        $($id_fn)::+($($id_arg,)* $row)
    };
    // The decoded message holding `$value` (an expression or a pattern).
    (@variant flat $message:ident $group:ident $name:ident $value:tt) => {
        $message::$name($value)
    };
    (@variant nested $message:ident $group:ident $name:ident $value:tt) => {
        $message::$group($group::$name($value))
    };

    // `MessageData` of one payload type, and `From` it into its enums.
    (@message_data $mode:ident $proto:ident [$id:ty] $message:ident $group:ident $id_spec:tt
        $label:ident $row:literal $name:ident $ty:ident $shape:tt) => {
        // The table names this message's group: it must be the group of its position.
        const _: () = {
            let _group_of_its_position: fn($ty) -> _ = $label::$name;
        };

        impl $crate::wire::MessageData for $ty {
            type Protocol = $proto;
            const ID: $id = message_table!(@id $id_spec $row);
            const NAME: &'static str = stringify!($name);
            const ENCODED_LEN: usize =
                <$proto as $crate::wire::table::PayloadCodec<message_table!(@layout $ty $shape)>>
                    ::MAX_LEN;

            fn into_message(self) -> $message<'static> {
                message_table!(@variant $mode $message $group $name self)
            }

            fn from_message(message: &$message<'_>) -> Option<Self> {
                match message {
                    message_table!(@variant $mode $message $group $name m) => Some(*m),
                    _ => None,
                }
            }

            fn payload_len(&self) -> usize {
                <$proto as $crate::wire::table::PayloadCodec<message_table!(@layout $ty $shape)>>
                    ::encoded_len(message_table!(@layout_of $shape self))
            }

            fn decode_payload(payload: &[u8]) -> $crate::Result<Self> {
                message_table!(@decode $proto $ty $shape payload)
            }

            fn encode_payload(&self, w: &mut $crate::wire::Writer<'_>) -> $crate::Result<()> {
                message_table!(@encode $proto $ty $shape self w)
            }
        }

        impl From<$ty> for $message<'_> {
            fn from(m: $ty) -> Self {
                message_table!(@variant $mode $message $group $name m)
            }
        }

        message_table!(@into_group $mode $group $name $ty);
    };
    (@into_group flat $group:ident $name:ident $ty:ident) => {};
    (@into_group nested $group:ident $name:ident $ty:ident) => {
        impl From<$ty> for $group {
            fn from(m: $ty) -> Self {
                $group::$name(m)
            }
        }
    };

    // The traits every payload of a group implements.
    (@member_impls $ty:ident [$(impl $group_trait:path { $($group_item:tt)* })*]) => {
        $( impl $group_trait for $ty { $($group_item)* } )*
    };
    // The same items on the group's enum: constants as they are, methods dispatched.
    (@group_items $members:tt [$(impl $group_trait:path {
        $(const $constant:ident: $constant_ty:ty = $value:expr;)*
        $(fn $method:ident(&self) -> $method_ty:ty $body:block)*
    })*]) => {
        $(
            $(
                #[doc = concat!("The [`", stringify!($group_trait), "::", stringify!($constant),
                    "`] of every message of this enum.")]
                pub const $constant: $constant_ty = $value;
            )*
            $( message_table!(@dispatch [$group_trait] $method [$method_ty] $members); )*
        )*
    };
    (@dispatch [$group_trait:path] $method:ident [$method_ty:ty]
        [$( [$row:literal $name:ident $ty:ident $shape:tt $row_meta:tt] )*]) => {
        #[doc = concat!("The [`", stringify!($group_trait), "::", stringify!($method),
            "`] of the payload.")]
        #[must_use]
        pub fn $method(&self) -> $method_ty {
            match self {
                $( Self::$name(m) => <$ty as $group_trait>::$method(m), )*
            }
        }
    };

    // A group's enum (nested tables; a flat table's rows are the message's variants).
    (@group flat $($rest:tt)*) => {};
    (@group nested $proto:ident [$id:ty] [$key:ty] $lengths:ident $encoders:ident $ids:tt
        [$group:ident [$($group_meta:tt)*] [$($group_derive:ident),*] $impls:tt]
        [$( [$row:literal $name:ident $ty:ident $shape:tt [$($row_meta:tt)*]] )*]) => {
        wire_derive! {
            [$($group_derive),*]
            $($group_meta)*
            pub enum $group {
                $(
                    $($row_meta)*
                    #[doc = concat!(stringify!($row), ": [`", stringify!($ty), "`].")]
                    $name($ty),
                )*
            }
        }

        impl $group {
            message_table!(@methods [] $ids $proto [$id] $lengths $encoders
                [$( [$name $ty $shape] )*]);

            /// Decodes the payload of the message with row id `id` (`None` for an id
            /// without a message of this enum).
            ///
            /// # Errors
            /// [`Error::BadLength`](crate::Error::BadLength) for a payload length the
            /// protocol's rules refuse (see the module documentation), and the layout's
            /// own errors.
            pub fn decode(id: $key, payload: &[u8]) -> Option<$crate::Result<Self>> {
                match message_table!(@scrutinee $ids id) {
                    $(
                        message_table!(@pattern $ids $row $name) => {
                            Some(message_table!(@decode $proto $ty $shape payload).map(Self::$name))
                        }
                    )*
                    _ => None,
                }
            }

            message_table!(@group_items [$( [$row $name $ty $shape []] )*] $impls);
        }
    };

    // What a message enum and a group's enum both have.
    (@methods [$($raw:ident)?] $ids:tt $proto:ident [$id:ty] $lengths:ident $encoders:ident
        [$( [$name:ident $ty:ident $shape:tt] )*]) => {
        message_table!(@id_fn $ids [$id] [$($raw)?] [$( [$name $ty] )*]);

        /// The message name (the table row's).
        #[must_use]
        pub const fn name(&self) -> &'static str {
            match self {
                $( Self::$name(_) => stringify!($name), )*
                $( Self::$raw(_) => stringify!($raw), )?
            }
        }

        message_table!(@payload_len $lengths [$($raw)?] [$( [$name $ty] )*]);

        message_table!(@encoder $encoders
            /// Writes the payload.
            ///
            /// # Errors
            /// [`Error::BufferTooSmall`](crate::Error::BufferTooSmall) when `w` has no room
            /// for it; [`Error::OutOfRange`](crate::Error::OutOfRange) for a value the
            /// layout cannot encode.
            pub fn encode(&self, w: &mut $crate::wire::Writer<'_>) -> $crate::Result<()> {
                match self {
                    $( Self::$name(m) => message_table!(@encode $proto $ty $shape m w), )*
                    $( Self::$raw(r) => w.put(r.payload), )?
                }
            }
        );
    };
    // `out_of_line`: one copy of each encoder, whatever calls it (K40T's per-kind `emit`
    // and its message's `encode` both do: inlined into both it costs kilobytes);
    // `inlined`: as the compiler chooses.
    (@encoder out_of_line $($encoder:tt)*) => { #[inline(never)] $($encoder)* };
    (@encoder inlined $($encoder:tt)*) => { $($encoder)* };
    // The message id: through the ids enumeration where the table has one (a match on its
    // dense variants is smaller than one on the sparse ids).
    (@id_fn [] [$id:ty] [$($raw:ident)?] [$( [$name:ident $ty:ident] )*]) => {
        /// The message id.
        #[must_use]
        pub const fn id(&self) -> $id {
            match self {
                $( Self::$name(_) => <$ty as $crate::wire::MessageData>::ID, )*
                $( Self::$raw(r) => r.id, )?
            }
        }
    };
    (@id_fn [[$($ids_meta:tt)*] $ids:ident [$ids_repr:ty] $ids_fn:ident] [$id:ty] []
        [$( [$name:ident $ty:ident] )*]) => {
        /// The message id.
        #[must_use]
        pub const fn id(&self) -> $id {
            self.$ids_fn().value()
        }

        #[doc = concat!("The message id as an [`", stringify!($ids), "`].")]
        #[must_use]
        pub const fn $ids_fn(&self) -> $ids {
            match self {
                $( Self::$name(_) => $ids::$name, )*
            }
        }
    };
    (@scrutinee [] $id:ident) => { $id };
    (@scrutinee [[$($ids_meta:tt)*] $ids:ident [$ids_repr:ty] $ids_fn:ident] $id:ident) => {
        $ids::from_value($id)
    };
    (@pattern [] $row:literal $name:ident) => { $row };
    (@pattern [[$($ids_meta:tt)*] $ids:ident [$ids_repr:ty] $ids_fn:ident]
        $row:literal $name:ident) => {
        $ids::$name
    };
    (@payload_len fixed [$($raw:ident)?] [$( [$name:ident $ty:ident] )*]) => {
        /// Encoded payload length.
        #[must_use]
        pub const fn payload_len(&self) -> usize {
            match self {
                $( Self::$name(_) => <$ty as $crate::wire::MessageData>::ENCODED_LEN, )*
                $( Self::$raw(r) => r.payload.len(), )?
            }
        }
    };
    (@payload_len variable [$($raw:ident)?] [$( [$name:ident $ty:ident] )*]) => {
        /// Encoded payload length.
        #[must_use]
        pub fn payload_len(&self) -> usize {
            match self {
                $( Self::$name(m) => $crate::wire::MessageData::payload_len(m), )*
                $( Self::$raw(r) => r.payload.len(), )?
            }
        }
    };

    // The decoded message: over the rows (flat) or over the groups (nested).
    (@message flat $proto:ident [$id:ty] [$key:ty] $lengths:ident $encoders:ident
        [$message:ident [$($message_derive:ident),*] [$($message_meta:tt)*] [$($raw_meta:tt)*]]
        $groups:tt
        [$( [$row:literal $name:ident $ty:ident $shape:tt [$($row_meta:tt)*]] )*]) => {
        wire_derive! {
            [$($message_derive),*]
            $($message_meta)*
            pub enum $message<'a> {
                $(
                    $($row_meta)*
                    #[doc = concat!(stringify!($row), ": [`", stringify!($ty), "`].")]
                    $name($ty),
                )*
                $($raw_meta)*
                Raw(Raw<'a>),
            }
        }

        impl<'a> $message<'a> {
            /// Decodes the payload of a frame with id `id`. Unknown ids give
            /// [`Raw`](Self::Raw).
            ///
            /// # Errors
            /// [`Error::BadLength`](crate::Error::BadLength) when a known id's payload
            /// does not have a length its layout takes (too few bytes too: the frame's
            /// length says the payload is complete, so it is never
            /// [`Error::Truncated`](crate::Error::Truncated)), and the layout's own
            /// errors.
            pub fn decode(id: $key, payload: &'a [u8]) -> $crate::Result<Self> {
                let decoded = match id {
                    $(
                        $row => message_table!(@decode $proto $ty $shape payload).map(Self::$name),
                    )*
                    _ => Ok(Self::Raw(Raw { id, payload })),
                };
                decoded.map_err(|e| match e {
                    $crate::Error::Truncated => $crate::Error::BadLength,
                    other => other,
                })
            }

            message_table!(@methods [Raw] [] $proto [$id] $lengths $encoders
                [$( [$name $ty $shape] )*]);
        }
    };
    (@message nested $proto:ident [$id:ty] [$key:ty] $lengths:ident $encoders:ident
        [$message:ident [$($message_derive:ident),*] [$($message_meta:tt)*] [$($raw_meta:tt)*]]
        [$( [$group:ident [$($group_meta:tt)*]] )*]
        $_rows:tt) => {
        wire_derive! {
            [$($message_derive),*]
            $($message_meta)*
            pub enum $message<'a> {
                $( $($group_meta)* $group($group), )*
                $($raw_meta)*
                Raw(Raw<'a>),
            }
        }

        impl $message<'_> {
            /// The message id.
            #[must_use]
            pub const fn id(&self) -> $id {
                match self {
                    $( Self::$group(m) => m.id(), )*
                    Self::Raw(r) => r.id,
                }
            }

            /// The message name (the table row's; `"Raw"` for unknown ids).
            #[must_use]
            pub const fn name(&self) -> &'static str {
                match self {
                    $( Self::$group(m) => m.name(), )*
                    Self::Raw(_) => "Raw",
                }
            }

            message_table!(@message_payload_len $lengths [$($group)*]);

            /// Writes the payload.
            ///
            /// # Errors
            /// [`Error::BufferTooSmall`](crate::Error::BufferTooSmall) when `w` has no room
            /// for it; [`Error::OutOfRange`](crate::Error::OutOfRange) for a value the
            /// layout cannot encode.
            pub fn encode(&self, w: &mut $crate::wire::Writer<'_>) -> $crate::Result<()> {
                match self {
                    $( Self::$group(m) => m.encode(w), )*
                    Self::Raw(r) => w.put(r.payload),
                }
            }
        }

        $(
            impl From<$group> for $message<'_> {
                fn from(m: $group) -> Self {
                    Self::$group(m)
                }
            }
        )*
    };
    (@message_payload_len fixed [$($group:ident)*]) => {
        /// Encoded payload length.
        #[must_use]
        pub const fn payload_len(&self) -> usize {
            match self {
                $( Self::$group(m) => m.payload_len(), )*
                Self::Raw(r) => r.payload.len(),
            }
        }
    };
    (@message_payload_len variable [$($group:ident)*]) => {
        /// Encoded payload length.
        #[must_use]
        pub fn payload_len(&self) -> usize {
            match self {
                $( Self::$group(m) => m.payload_len(), )*
                Self::Raw(r) => r.payload.len(),
            }
        }
    };

    // The row ids as an enumeration, when the header asks for one.
    (@ids [] $rows:tt) => {};
    (@ids [[$($ids_meta:tt)*] $ids:ident [$ids_repr:ty] $ids_fn:ident]
        [$( [$($row_meta:tt)*] $row:literal $name:ident )*]) => {
        code_enum! {
            $($ids_meta)*
            pub enum $ids: $ids_repr {
                $( $($row_meta)* $name = $row, )*
            }
        }
    };
}
