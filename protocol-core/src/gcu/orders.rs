//! The orders of the document's Command & Feedback tables, declared once in one message
//! table: [`Order`], the typed command of every order
//! ([`MessageData`](crate::wire::MessageData)), [`Command`],
//! [`Message`] and [`CATALOG`].

use super::Raw;
use super::feedback::FeedbackKind;
use super::params::{
    CameraSet, ClickToAim, ExternalTrack, GeoTarget, NightVision, OnOff, Palette, PipView,
    RangingState, Track, ZoomTo,
};

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

impl CatalogEntry {
    /// The entry of a table row with the encoded length of its command.
    const fn new(id: u8, name: &'static str, lens: &[usize]) -> Self {
        let payload_len = match lens {
            [len, ..] => *len,
            [] => 0,
        };
        CatalogEntry {
            id,
            name,
            payload_len,
            feedback: Order::from_value(id).feedback_kind(),
        }
    }
}

// Every order once, with its typed command: an empty struct named after the order for an
// order without parameters (`Neutral {}`), a newtype named after it for one parameter
// (`Shutter(CameraSet)`), or a type of `params.rs`.
message_table! {
    /// The GCU protocol: every typed command implements
    /// [`MessageData`](crate::wire::MessageData) with `Protocol = Gcu`.
    ///
    /// ```
    /// use protocol_core::gcu::{MessageData, Order, Shutter, Track};
    /// assert_eq!(Shutter::ID, Order::Shutter.value());
    /// assert_eq!(Shutter::NAME, "Shutter");
    /// assert_eq!(Track::ENCODED_LEN, 10);
    /// ```
    protocol Gcu {
        id: u8, key: u8, order: Le, lengths: fixed, encoders: inlined,
        /// The order byte (package byte 69, the message id) of every order of the Command &
        /// Feedback tables.
        ids: order() -> Order(u8),
    }
    /// Every order this codec knows, in the document's order.
    catalog;
    /// The order part of a host package: what its order byte and parameters mean.
    message Message [Eq, Hash] {
        /// An unknown order, or a known one with parameters of another length.
        Raw;
        /// The command part of a host package whose order this codec knows and whose
        /// parameters have the length the document gives: one variant per order.
        Command [Eq, Hash];
    }
    /// 0x00 null: separates two commands with the same order (the GCU executes an order
    /// once while it repeats).
    0x00 Null: Command(Null {});
    /// 0x01 calibration (keep the gimbal still for a few seconds).
    0x01 Calibration: Command(Calibration {});
    /// 0x03 neutral: back to the pitch/yaw neutral position, same mode.
    0x03 Neutral: Command(Neutral {});
    /// 0x10 FPV mode: control quantities are angles relative to the carrier.
    0x10 Fpv: Command(Fpv {});
    /// 0x11 head lock mode: control quantities are angular rates.
    0x11 HeadLock: Command(HeadLock {});
    /// 0x12 head follow mode: control quantities are angular rates.
    0x12 HeadFollow: Command(HeadFollow {});
    /// 0x13 orthoview mode: pitch locked at -90°.
    0x13 Orthoview: Command(Orthoview {});
    /// 0x14 Euler angle control mode: control quantities are Euler angles.
    0x14 EulerAngle: Command(EulerAngle {});
    /// 0x15 gaze with geo-coordinates guide: aim at a point.
    0x15 GazeGeoGuide: Command(GeoTarget);
    /// 0x16 gaze with geo-coordinates lock: keep aiming at the current centre.
    0x16 GazeLock: Command(GazeLock {});
    /// 0x17 track (the gimbal's own image processor).
    0x17 Track: Command(Track);
    /// 0x1A click to aim.
    0x1A ClickToAim: Command(ClickToAim);
    /// 0x1B external track (exempt from the edge trigger).
    0x1B ExternalTrack: Command(ExternalTrack);
    /// 0x20 shutter: take a picture (the document sends 0x01, camera 1).
    0x20 Shutter: Command(Shutter(CameraSet));
    /// 0x21 record start/stop (the document sends 0x01, camera 1; ArduPilot sends 0x01
    /// to start and 0x00 to stop).
    0x21 Record: Command(Record(CameraSet));
    /// 0x22 zoom in continuously.
    0x22 ZoomIn: Command(ZoomIn(CameraSet));
    /// 0x23 zoom out continuously.
    0x23 ZoomOut: Command(ZoomOut(CameraSet));
    /// 0x24 stop zooming.
    0x24 ZoomStop: Command(ZoomStop(CameraSet));
    /// 0x25 zoom to a specified rate.
    0x25 ZoomTo: Command(ZoomTo);
    /// 0x26 focus (the document sends 0x01, camera 1).
    0x26 Focus: Command(Focus(CameraSet));
    /// 0x2A palette.
    0x2A Palette: Command(Palette);
    /// 0x2B night vision.
    0x2B NightVision: Command(NightVision);
    /// 0x73 OSD display/undisplay.
    0x73 Osd: Command(Osd(OnOff));
    /// 0x74 picture in picture.
    0x74 PictureInPicture: Command(PictureInPicture(PipView));
    /// 0x80 lighting, brightness 0..=255 (0 off). Lighting on also turns night vision
    /// on; lighting off leaves night vision as it is.
    0x80 Lighting: Command(Lighting(u8));
    /// 0x81 continuous ranging.
    0x81 Ranging: Command(Ranging(RangingState));
}

impl Order {
    /// How the feedback of this order reads: the set of cameras that failed for the orders
    /// whose failure the document prints as `NN` or as the camera byte (0x17, 0x1A, 0x1B,
    /// 0x20..0x26, 0x2A, 0x2B), a status for the others (unlisted orders too).
    #[must_use]
    pub const fn feedback_kind(self) -> FeedbackKind {
        match self {
            Order::Track
            | Order::ClickToAim
            | Order::ExternalTrack
            | Order::Shutter
            | Order::Record
            | Order::ZoomIn
            | Order::ZoomOut
            | Order::ZoomStop
            | Order::ZoomTo
            | Order::Focus
            | Order::Palette
            | Order::NightVision => FeedbackKind::Cameras,
            _ => FeedbackKind::Status,
        }
    }

    /// Length of the order's parameters in a host package (`None` when unlisted).
    #[must_use]
    pub const fn payload_len(self) -> Option<usize> {
        if let Order::Other(_) = self {
            return None;
        }
        let mut rest = CATALOG;
        while let [entry, tail @ ..] = rest {
            if entry.id == self.value() {
                return Some(entry.payload_len);
            }
            rest = tail;
        }
        None
    }
}
