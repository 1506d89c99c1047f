//! The orders of the document's Command & Feedback tables, declared once: [`Order`],
//! the typed command of every order ([`MessageData`]), [`Command`], and [`CATALOG`].

use super::decode_exact;
use super::feedback::FeedbackKind;
use super::params::{
    CameraSet, ClickToAim, ExternalTrack, GeoTarget, NightVision, OnOff, Palette, PipView,
    RangingState, Track, ZoomTo,
};
use super::{Message, MessageData};
use crate::Result;
use crate::wire::Writer;
use crate::wire::encoding::{Field, Le};

/// One entry of [`CATALOG`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CatalogEntry {
    /// The order byte (the message id).
    pub id: u8,
    /// Name of the order (and of its typed command).
    pub name: &'static str,
    /// Length of its parameters (the payload) in a host package.
    pub payload_len: usize,
    /// How its feedback reads.
    pub feedback: FeedbackKind,
}

/// The typed command of an order entry: `{}` an empty struct named after the order,
/// `(Inner)` a newtype named after the order, `[Type]` a type declared in `params.rs`.
// Invoked in type position (`Command::$name(gcu_payload_type!(..))`, `impl .. for ..`),
// so that one table entry names its type without a second column.
macro_rules! gcu_payload_type {
    ($name:ident {}) => {
        $name
    };
    ($name:ident ($inner:ty)) => {
        $name
    };
    ($name:ident [$ty:ty]) => {
        $ty
    };
}

/// Declares the typed command of an order entry when the table asks for one (`{}` or
/// `(Inner)`, see `gcu_payload_type!`); `[Type]` names a type declared elsewhere.
macro_rules! gcu_order_type {
    ($(#[$meta:meta])* $name:ident {}) => {
        wire_struct! {
            Le;
            $(#[$meta])*
            // An empty `///` line: what follows is a paragraph of its own.
            ///
            /// The order has no parameters.
            pub struct $name {}
        }
    };
    ($(#[$meta:meta])* $name:ident ($inner:ty)) => {
        wire_newtype! {
            $(#[$meta])*
            ///
            #[doc = concat!("The parameter: a [`", stringify!($inner), "`].")]
            pub struct $name($inner);
        }
    };
    ($(#[$meta:meta])* $name:ident [$ty:ty]) => {};
}

/// Declares every order once: [`Order`], the typed commands and their [`MessageData`],
/// [`Command`] and [`CATALOG`] come from the one table, so they cannot disagree.
macro_rules! gcu_orders {
    ($(
        $(#[$meta:meta])*
        // `$def`: one token tree, `{}`, `(Inner)` or `[Type]` (see `gcu_payload_type!`).
        $code:literal $name:ident $def:tt => $kind:ident;
    )*) => {
        code_enum! {
            /// The order byte (package byte 69, the message id) of every order of the
            /// Command & Feedback tables.
            pub enum Order: u8 {
                $( $(#[$meta])* $name = $code, )*
            }
        }

        impl Order {
            /// How the feedback of this order reads (unlisted orders: as a status).
            #[must_use]
            pub const fn feedback_kind(self) -> FeedbackKind {
                match self {
                    $( Order::$name => FeedbackKind::$kind, )*
                    Order::Other(_) => FeedbackKind::Status,
                }
            }

            /// Length of the order's parameters in a host package (`None` when unlisted).
            #[must_use]
            pub const fn payload_len(self) -> Option<usize> {
                match self {
                    $( Order::$name => Some(<gcu_payload_type!($name $def) as Field<Le>>::LEN), )*
                    Order::Other(_) => None,
                }
            }
        }

        $( gcu_order_type!($(#[$meta])* $name $def); )*

        wire_derive! {
            [Eq, Hash]
            /// The command part of a host package whose order this codec knows and whose
            /// parameters have the length the document gives: one variant per order.
            pub enum Command {
                $( $(#[$meta])* $name(gcu_payload_type!($name $def)), )*
            }
        }

        impl Command {
            /// The message id: the order byte.
            #[must_use]
            pub const fn id(&self) -> u8 {
                self.order().value()
            }

            /// The order.
            #[must_use]
            pub const fn order(&self) -> Order {
                match self {
                    $( Command::$name(_) => Order::$name, )*
                }
            }

            /// The order's name.
            #[must_use]
            pub const fn name(&self) -> &'static str {
                match self {
                    $( Command::$name(_) => stringify!($name), )*
                }
            }

            /// Length of the parameters (the payload).
            #[must_use]
            pub const fn payload_len(&self) -> usize {
                match self {
                    $( Command::$name(_) => <gcu_payload_type!($name $def) as Field<Le>>::LEN, )*
                }
            }

            /// Decodes the parameters of a known order (`None` for an unknown one).
            ///
            /// # Errors
            /// [`Error::BadLength`](crate::Error::BadLength) when the parameters have
            /// another length than the document gives the order.
            pub fn decode(id: u8, payload: &[u8]) -> Option<Result<Self>> {
                match Order::from_value(id) {
                    $( Order::$name => Some(decode_exact(payload).map(Command::$name)), )*
                    Order::Other(_) => None,
                }
            }

            /// Writes the parameters (the order byte is the frame's id).
            ///
            /// # Errors
            /// [`Error::BufferTooSmall`](crate::Error::BufferTooSmall) when `w` has no
            /// room for them.
            pub fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
                match self {
                    $( Command::$name(p) => Field::<Le>::write(p, w), )*
                }
            }
        }

        $(
            impl MessageData for gcu_payload_type!($name $def) {
                const ID: u8 = $code;
                const NAME: &'static str = stringify!($name);
                const ENCODED_LEN: usize = <Self as Field<Le>>::LEN;

                fn into_message(self) -> Message<'static> {
                    Message::Command(Command::$name(self))
                }

                fn from_message(message: &Message<'_>) -> Option<Self> {
                    match message {
                        Message::Command(Command::$name(m)) => Some(*m),
                        _ => None,
                    }
                }
            }

            impl From<gcu_payload_type!($name $def)> for Command {
                fn from(m: gcu_payload_type!($name $def)) -> Self {
                    Command::$name(m)
                }
            }

            impl From<gcu_payload_type!($name $def)> for Message<'_> {
                fn from(m: gcu_payload_type!($name $def)) -> Self {
                    Message::Command(Command::$name(m))
                }
            }
        )*

        /// Every order this codec knows, in the document's order.
        pub const CATALOG: &[CatalogEntry] = &[$(
            CatalogEntry {
                id: $code,
                name: stringify!($name),
                payload_len: <gcu_payload_type!($name $def) as Field<Le>>::LEN,
                feedback: FeedbackKind::$kind,
            },
        )*];
    };
}

gcu_orders! {
    /// 0x00 null: separates two commands with the same order (the GCU executes an order
    /// once while it repeats).
    0x00 Null {} => Status;
    /// 0x01 calibration (keep the gimbal still for a few seconds).
    0x01 Calibration {} => Status;
    /// 0x03 neutral: back to the pitch/yaw neutral position, same mode.
    0x03 Neutral {} => Status;
    /// 0x10 FPV mode: control quantities are angles relative to the carrier.
    0x10 Fpv {} => Status;
    /// 0x11 head lock mode: control quantities are angular rates.
    0x11 HeadLock {} => Status;
    /// 0x12 head follow mode: control quantities are angular rates.
    0x12 HeadFollow {} => Status;
    /// 0x13 orthoview mode: pitch locked at -90°.
    0x13 Orthoview {} => Status;
    /// 0x14 Euler angle control mode: control quantities are Euler angles.
    0x14 EulerAngle {} => Status;
    /// 0x15 gaze with geo-coordinates guide: aim at a point.
    0x15 GazeGeoGuide [GeoTarget] => Status;
    /// 0x16 gaze with geo-coordinates lock: keep aiming at the current centre.
    0x16 GazeLock {} => Status;
    /// 0x17 track (the gimbal's own image processor).
    0x17 Track [Track] => Cameras;
    /// 0x1A click to aim.
    0x1A ClickToAim [ClickToAim] => Cameras;
    /// 0x1B external track (exempt from the edge trigger).
    0x1B ExternalTrack [ExternalTrack] => Cameras;
    /// 0x20 shutter: take a picture (the document sends 0x01, camera 1).
    0x20 Shutter (CameraSet) => Cameras;
    /// 0x21 record start/stop (the document sends 0x01, camera 1; ArduPilot sends 0x01
    /// to start and 0x00 to stop).
    0x21 Record (CameraSet) => Cameras;
    /// 0x22 zoom in continuously.
    0x22 ZoomIn (CameraSet) => Cameras;
    /// 0x23 zoom out continuously.
    0x23 ZoomOut (CameraSet) => Cameras;
    /// 0x24 stop zooming.
    0x24 ZoomStop (CameraSet) => Cameras;
    /// 0x25 zoom to a specified rate.
    0x25 ZoomTo [ZoomTo] => Cameras;
    /// 0x26 focus (the document sends 0x01, camera 1).
    0x26 Focus (CameraSet) => Cameras;
    /// 0x2A palette.
    0x2A Palette [Palette] => Cameras;
    /// 0x2B night vision.
    0x2B NightVision [NightVision] => Cameras;
    /// 0x73 OSD display/undisplay.
    0x73 Osd (OnOff) => Status;
    /// 0x74 picture in picture.
    0x74 PictureInPicture (PipView) => Status;
    /// 0x80 lighting, brightness 0..=255 (0 off). Lighting on also turns night vision
    /// on; lighting off leaves night vision as it is.
    0x80 Lighting (u8) => Status;
    /// 0x81 continuous ranging.
    0x81 Ranging (RangingState) => Status;
}
