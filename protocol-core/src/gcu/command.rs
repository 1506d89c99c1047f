//! The command part of host packages (order and parameters) and the feedback part of
//! GCU packages (order and execution state), for every order of the document's
//! Command & Feedback tables.

use super::field::{Field, decode_exact};
use crate::wire::{Reader, Writer};
use crate::{Error, Result};

/// A set of cameras (the document's `KK` and `NN` bytes): bit 0 is camera 1 (the
/// visible-light zoom camera by default), bit 1 camera 2 (the thermal camera by
/// default), up to bit 7, camera 8.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct CameraSet(pub u8);

impl CameraSet {
    /// No camera.
    pub const NONE: CameraSet = CameraSet(0);
    /// Camera 1, the visible-light zoom camera by default.
    pub const CAMERA_1: CameraSet = CameraSet(0x01);
    /// Camera 2, the thermal camera by default.
    pub const CAMERA_2: CameraSet = CameraSet(0x02);
    /// Every camera (0xFF).
    pub const ALL: CameraSet = CameraSet(0xFF);

    /// The set holding only camera `n` (1..=8); `None` for another number.
    pub const fn camera(n: u8) -> Option<CameraSet> {
        match n {
            1..=8 => Some(CameraSet(1u8.wrapping_shl((n as u32).wrapping_sub(1)))),
            _ => None,
        }
    }

    /// True when camera `n` (1..=8) is in the set.
    pub const fn contains(self, n: u8) -> bool {
        match CameraSet::camera(n) {
            Some(c) => self.0 & c.0 != 0,
            None => false,
        }
    }

    /// This set with camera `n` (1..=8) added (unchanged for another number).
    #[must_use]
    pub const fn with(self, n: u8) -> CameraSet {
        match CameraSet::camera(n) {
            Some(c) => CameraSet(self.0 | c.0),
            None => self,
        }
    }

    /// True when no camera is in the set.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// The camera numbers in the set, ascending.
    pub fn iter(self) -> impl Iterator<Item = u8> {
        (1..=8u8).filter(move |&n| self.contains(n))
    }
}

impl Field<crate::wire::encoding::Le> for CameraSet {
    const LEN: usize = 1;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        r.u8().map(CameraSet)
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u8(self.0)
    }
}

code_enum! {
    /// `TT` of the track order (0x17).
    pub enum TrackAction: u8 {
        /// Exit tracking.
        Exit = 0x00,
        /// Start tracking.
        Start = 0x01,
    }
}

code_enum! {
    /// `TT` of the external track order (0x1B).
    pub enum ExternalTrackAction: u8 {
        /// Exit tracking.
        Exit = 0x00,
        /// Start tracking.
        Start = 0x02,
    }
}

code_enum! {
    /// `TT` of the palette order (0x2A).
    pub enum PaletteAction: u8 {
        /// Next palette option.
        Next = 0x00,
    }
}

code_enum! {
    /// On/off switch `TT` (night vision 0x2B: on/off; OSD 0x73: display/hide).
    pub enum OnOff: u8 {
        /// Off (OSD: undisplay).
        Off = 0x00,
        /// On (OSD: display).
        On = 0x01,
    }
}

code_enum! {
    /// `TT` of the picture-in-picture order (0x74). The document defines 0x00; 1..4 are
    /// the views ArduPilot's XFRobot driver selects (its `CameraType`).
    pub enum PipView: u8 {
        /// Next view.
        Next = 0x00,
        /// Main: zoom camera, thermal as picture in picture.
        PipZoomMainThermalSub = 0x01,
        /// Main: thermal camera, sub: zoom camera.
        ThermalMainZoomSub = 0x02,
        /// Main: thermal camera, zoom as picture in picture.
        PipThermalMainZoomSub = 0x03,
        /// Main: zoom camera, sub: thermal camera.
        ZoomMainThermalSub = 0x04,
    }
}

code_enum! {
    /// `TT` of the continuous ranging order (0x81).
    pub enum RangingState: u8 {
        /// Ranging off.
        Off = 0x00,
        /// Ranging on.
        On = 0x02,
    }
}

wire_struct! {
    /// Parameters of gaze with geo-coordinates guide (0x15): the point of interest. The
    /// GCU needs valid carrier INS data to do this.
    pub struct GeoTarget {
        /// Longitude, 1e-7° (`PP PP PP PP`).
        pub lon_e7: i32,
        /// Latitude, 1e-7° (`QQ QQ QQ QQ`).
        pub lat_e7: i32,
        /// Altitude, mm (`RR RR RR RR`).
        pub alt_mm: i32,
    }
}

wire_struct! {
    /// Parameters of track (0x17): the target box, in screen coordinates 0..=10000
    /// from the top-left corner (rightward X, downward Y).
    pub struct Track {
        /// Cameras (`KK`).
        pub cameras: CameraSet,
        /// Start or exit (`TT`).
        pub action: TrackAction,
        /// Top-left corner X.
        pub x0: u16,
        /// Top-left corner Y.
        pub y0: u16,
        /// Lower-right corner X.
        pub x1: u16,
        /// Lower-right corner Y.
        pub y1: u16,
    }
}

wire_struct! {
    /// Parameters of click to aim (0x1A): the target point, in screen coordinates
    /// 0..=10000 from the top-left corner (rightward X, downward Y).
    pub struct ClickToAim {
        /// Cameras (`KK`).
        pub cameras: CameraSet,
        /// Target X.
        pub x: u16,
        /// Target Y.
        pub y: u16,
    }
}

wire_struct! {
    /// Parameters of external track (0x1B): the target miss measured by an external
    /// image processor, [-1024, 1024] from the screen centre (rightward X, downward Y);
    /// both ≥ 3071 mark invalid data when tracking fails.
    pub struct ExternalTrack {
        /// Cameras (`KK`).
        pub cameras: CameraSet,
        /// Horizontal miss (`PP PP`).
        pub miss_x: i16,
        /// Vertical miss (`VV VV`).
        pub miss_y: i16,
        /// Start or exit (`TT`).
        pub action: ExternalTrackAction,
    }
}

wire_struct! {
    /// Parameters of zoom to a specified rate (0x25).
    ///
    /// `zoom_code` (`ZZ`, S16): -32768..=-10 is the desired zoom ratio, negated, in
    /// 0.1x (-10 = 1.0x, -603 = 60.3x); 1..=10000 is the desired fraction of the zoom
    /// range (1 the minimum, 10000 the maximum ratio). See [`ZoomTo::ratio_x10`] and
    /// [`ZoomTo::fraction`].
    pub struct ZoomTo {
        /// Cameras (`KK`).
        pub cameras: CameraSet,
        /// The zoom code.
        pub zoom_code: i16,
    }
}

impl ZoomTo {
    /// Zoom `cameras` to `ratio_x10` (0.1x; 10..=32768, i.e. 1.0x..3276.8x).
    pub const fn ratio(cameras: CameraSet, ratio_x10: u16) -> Option<ZoomTo> {
        if ratio_x10 < 10 || ratio_x10 > 32768 {
            return None;
        }
        // 10..=32768 negated fits an i16.
        let zoom_code = (ratio_x10 as i32).wrapping_neg() as i16;
        Some(ZoomTo { cameras, zoom_code })
    }

    /// Zoom `cameras` to a fraction of the zoom range (1..=10000).
    pub const fn fraction_of_range(cameras: CameraSet, fraction: u16) -> Option<ZoomTo> {
        if fraction < 1 || fraction > 10000 {
            return None;
        }
        Some(ZoomTo {
            cameras,
            zoom_code: fraction as i16,
        })
    }

    /// The desired zoom ratio in 0.1x, when the code is one (≤ -10).
    pub const fn ratio_x10(&self) -> Option<u16> {
        if self.zoom_code <= -10 {
            Some(self.zoom_code.unsigned_abs())
        } else {
            None
        }
    }

    /// The desired fraction of the zoom range (1..=10000), when the code is one.
    pub const fn fraction(&self) -> Option<u16> {
        if self.zoom_code >= 1 && self.zoom_code <= 10000 {
            Some(self.zoom_code.unsigned_abs())
        } else {
            None
        }
    }
}

wire_struct! {
    /// Parameters of the palette order (0x2A). The document prints `0x02 TT`: camera 2,
    /// the thermal camera.
    pub struct Palette {
        /// Cameras (0x02 in the document).
        pub cameras: CameraSet,
        /// The palette action (`TT`).
        pub action: PaletteAction,
    }
}

wire_struct! {
    /// Parameters of the night vision order (0x2B). The document's examples send
    /// `0x01 TT`: camera 1.
    pub struct NightVision {
        /// Cameras (0x01 in the document).
        pub cameras: CameraSet,
        /// On or off (`TT`).
        pub state: OnOff,
    }
}

/// How the byte after the order in a GCU feedback part reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum FeedbackKind {
    /// 0x00 success, 0x01 fail, 0x02 operating (calibration).
    Status,
    /// 0x00 success, otherwise the set of cameras that failed (`NN`).
    Cameras,
}

/// One entry of [`CATALOG`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CatalogEntry {
    /// The order byte.
    pub order: u8,
    /// Name of the order.
    pub name: &'static str,
    /// Length of its parameters in a host package.
    pub params_len: usize,
    /// How its feedback reads.
    pub feedback: FeedbackKind,
}

/// A command whose order this codec does not know, or whose parameters do not have the
/// length the document gives the order; kept as received.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct RawCommand<'a> {
    /// The order byte.
    pub order: u8,
    /// The parameter bytes.
    pub params: &'a [u8],
}

macro_rules! params_len {
    () => {
        0
    };
    ($ty:ty) => {
        <$ty as Field<crate::wire::encoding::Le>>::LEN
    };
}

macro_rules! decode_arm {
    ($name:ident, $params:ident) => {
        $params.is_empty().then_some(Command::$name)
    };
    ($name:ident, $params:ident, $ty:ty) => {
        decode_exact::<$ty>($params).ok().map(Command::$name)
    };
}

macro_rules! encode_arm {
    ($self:ident, $w:ident, $name:ident) => {
        Ok(())
    };
    ($self:ident, $w:ident, $name:ident, $ty:ty) => {
        match $self {
            Command::$name(p) => Field::<crate::wire::encoding::Le>::write(p, $w),
            _ => Ok(()),
        }
    };
}

/// Declares every order once: [`Order`], [`Command`] and [`CATALOG`] come from the one
/// table, so they cannot disagree.
macro_rules! orders {
    ($(
        $(#[$meta:meta])*
        $code:literal $name:ident $(($ty:ty))? => $kind:ident;
    )*) => {
        code_enum! {
            /// The order byte (package byte 69) of every order of the Command & Feedback
            /// tables.
            pub enum Order: u8 {
                $( $(#[$meta])* $name = $code, )*
            }
        }

        impl Order {
            /// How the feedback of this order reads (unlisted orders: as a status).
            pub const fn feedback_kind(self) -> FeedbackKind {
                match self {
                    $( Order::$name => FeedbackKind::$kind, )*
                    Order::Other(_) => FeedbackKind::Status,
                }
            }

            /// Length of the order's parameters in a host package (`None` when unlisted).
            pub const fn params_len(self) -> Option<usize> {
                match self {
                    $( Order::$name => Some(params_len!($($ty)?)), )*
                    Order::Other(_) => None,
                }
            }
        }

        /// The command part of a host package: an order and its parameters.
        ///
        /// A known order whose parameters have another length than the document gives
        /// decodes to [`Command::Raw`], like an unknown order: decoding never fails.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[cfg_attr(feature = "defmt", derive(defmt::Format))]
        #[cfg_attr(feature = "serde", derive(serde::Serialize))]
        pub enum Command<'a> {
            $( $(#[$meta])* $name $(($ty))?, )*
            /// An unknown order, or a known one with parameters of another length.
            Raw(RawCommand<'a>),
        }

        impl<'a> Command<'a> {
            /// The order.
            pub const fn order(&self) -> Order {
                match self {
                    $( Command::$name { .. } => Order::$name, )*
                    Command::Raw(r) => Order::from_value(r.order),
                }
            }

            /// The order's name (`"Raw"` for [`Command::Raw`]).
            pub const fn name(&self) -> &'static str {
                match self {
                    $( Command::$name { .. } => stringify!($name), )*
                    Command::Raw(_) => "Raw",
                }
            }

            /// Length of the parameters.
            pub const fn params_len(&self) -> usize {
                match self {
                    $( Command::$name { .. } => params_len!($($ty)?), )*
                    Command::Raw(r) => r.params.len(),
                }
            }

            /// The command for an order byte and its parameters.
            pub fn decode(order: u8, params: &'a [u8]) -> Self {
                let known = match Order::from_value(order) {
                    $( Order::$name => decode_arm!($name, params $(, $ty)?), )*
                    Order::Other(_) => None,
                };
                known.unwrap_or(Command::Raw(RawCommand { order, params }))
            }

            /// Writes the order byte and the parameters.
            pub fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
                w.u8(self.order().value())?;
                match self {
                    $( Command::$name { .. } => encode_arm!(self, w, $name $(, $ty)?), )*
                    Command::Raw(r) => w.put(r.params),
                }
            }
        }

        /// Every order this codec knows, in the document's order.
        pub const CATALOG: &[CatalogEntry] = &[$(
            CatalogEntry {
                order: $code,
                name: stringify!($name),
                params_len: params_len!($($ty)?),
                feedback: FeedbackKind::$kind,
            },
        )*];
    };
}

orders! {
    /// 0x00 null: separates two commands with the same order (the GCU executes an order
    /// once while it repeats).
    0x00 Null => Status;
    /// 0x01 calibration (keep the gimbal still for a few seconds).
    0x01 Calibration => Status;
    /// 0x03 neutral: back to the pitch/yaw neutral position, same mode.
    0x03 Neutral => Status;
    /// 0x10 FPV mode: control quantities are angles relative to the carrier.
    0x10 Fpv => Status;
    /// 0x11 head lock mode: control quantities are angular rates.
    0x11 HeadLock => Status;
    /// 0x12 head follow mode: control quantities are angular rates.
    0x12 HeadFollow => Status;
    /// 0x13 orthoview mode: pitch locked at -90°.
    0x13 Orthoview => Status;
    /// 0x14 Euler angle control mode: control quantities are Euler angles.
    0x14 EulerAngle => Status;
    /// 0x15 gaze with geo-coordinates guide: aim at a point.
    0x15 GazeGeoGuide(GeoTarget) => Status;
    /// 0x16 gaze with geo-coordinates lock: keep aiming at the current centre.
    0x16 GazeLock => Status;
    /// 0x17 track (the gimbal's own image processor).
    0x17 Track(Track) => Cameras;
    /// 0x1A click to aim.
    0x1A ClickToAim(ClickToAim) => Cameras;
    /// 0x1B external track (exempt from the edge trigger).
    0x1B ExternalTrack(ExternalTrack) => Cameras;
    /// 0x20 shutter: take a picture (the document sends 0x01, camera 1).
    0x20 Shutter(CameraSet) => Cameras;
    /// 0x21 record start/stop (the document sends 0x01, camera 1; ArduPilot sends 0x01
    /// to start and 0x00 to stop).
    0x21 Record(CameraSet) => Cameras;
    /// 0x22 zoom in continuously.
    0x22 ZoomIn(CameraSet) => Cameras;
    /// 0x23 zoom out continuously.
    0x23 ZoomOut(CameraSet) => Cameras;
    /// 0x24 stop zooming.
    0x24 ZoomStop(CameraSet) => Cameras;
    /// 0x25 zoom to a specified rate.
    0x25 ZoomTo(ZoomTo) => Cameras;
    /// 0x26 focus (the document sends 0x01, camera 1).
    0x26 Focus(CameraSet) => Cameras;
    /// 0x2A palette.
    0x2A Palette(Palette) => Cameras;
    /// 0x2B night vision.
    0x2B NightVision(NightVision) => Cameras;
    /// 0x73 OSD display/undisplay.
    0x73 Osd(OnOff) => Status;
    /// 0x74 picture in picture.
    0x74 PictureInPicture(PipView) => Status;
    /// 0x80 lighting, brightness 0..=255 (0 off). Lighting on also turns night vision
    /// on; lighting off leaves night vision as it is.
    0x80 Lighting(u8) => Status;
    /// 0x81 continuous ranging.
    0x81 Ranging(RangingState) => Status;
}

/// The execution state in a GCU feedback part (the byte after the order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum Execution {
    /// 0x00: success.
    Success,
    /// 0x01 for a [`FeedbackKind::Status`] order: fail.
    Fail,
    /// 0x02 for a [`FeedbackKind::Status`] order: operating (calibration).
    Operating,
    /// Non-zero for a [`FeedbackKind::Cameras`] order: the cameras that failed (`NN`).
    FailedCameras(CameraSet),
    /// Another value for a [`FeedbackKind::Status`] order, kept as received.
    Other(u8),
}

impl Execution {
    /// The execution state for a byte, read as `kind` says.
    pub const fn from_value(kind: FeedbackKind, v: u8) -> Execution {
        match (kind, v) {
            (_, 0x00) => Execution::Success,
            (FeedbackKind::Cameras, v) => Execution::FailedCameras(CameraSet(v)),
            (FeedbackKind::Status, 0x01) => Execution::Fail,
            (FeedbackKind::Status, 0x02) => Execution::Operating,
            (FeedbackKind::Status, v) => Execution::Other(v),
        }
    }

    /// The byte on the wire.
    pub const fn value(self) -> u8 {
        match self {
            Execution::Success => 0x00,
            Execution::Fail => 0x01,
            Execution::Operating => 0x02,
            Execution::FailedCameras(c) => c.0,
            Execution::Other(v) => v,
        }
    }

    /// The failure state to report for `order`: [`Execution::Fail`] for a status order,
    /// the `cameras` the command named for a camera order (or camera 1 if it named
    /// none, so the byte is never the 0x00 of success).
    pub const fn failure(order: Order, cameras: CameraSet) -> Execution {
        match order.feedback_kind() {
            FeedbackKind::Status => Execution::Fail,
            FeedbackKind::Cameras if cameras.is_empty() => {
                Execution::FailedCameras(CameraSet::CAMERA_1)
            }
            FeedbackKind::Cameras => Execution::FailedCameras(cameras),
        }
    }

    /// True for success.
    pub const fn is_success(self) -> bool {
        self.value() == 0
    }
}

/// The feedback part of a GCU package: the order answered and its execution state.
///
/// The document prints every feedback as `order, state`. A feedback with the order byte
/// alone decodes with `execution: None`; bytes after the state are kept in `extra`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Feedback<'a> {
    /// The order answered.
    pub order: Order,
    /// Its execution state (`None` when the package ends after the order byte).
    pub execution: Option<Execution>,
    /// Bytes after the execution state, kept as received (none in the document).
    pub extra: &'a [u8],
}

impl<'a> Feedback<'a> {
    /// The feedback `order, execution`.
    pub const fn new(order: Order, execution: Execution) -> Self {
        Feedback {
            order,
            execution: Some(execution),
            extra: &[],
        }
    }

    /// Success feedback for a command (what the GCU answers to a command it accepted).
    pub const fn success(command: &Command<'_>) -> Self {
        Feedback::new(command.order(), Execution::Success)
    }

    /// The feedback for an order byte and the bytes after it.
    pub fn decode(order: u8, data: &'a [u8]) -> Self {
        let order = Order::from_value(order);
        let (execution, extra) = match data.split_first() {
            Some((&v, extra)) => (Some(Execution::from_value(order.feedback_kind(), v)), extra),
            None => (None, data),
        };
        Feedback {
            order,
            execution,
            extra,
        }
    }

    /// Length of the bytes after the order byte.
    pub const fn data_len(&self) -> usize {
        match self.execution {
            Some(_) => self.extra.len().saturating_add(1),
            None => self.extra.len(),
        }
    }

    /// Writes the order byte, the execution state and the extra bytes. Extra bytes
    /// without an execution state are [`Error::OutOfRange`] (they would read as one).
    pub fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u8(self.order.value())?;
        match self.execution {
            Some(e) => w.u8(e.value())?,
            None if !self.extra.is_empty() => return Err(Error::OutOfRange),
            None => {}
        }
        w.put(self.extra)
    }
}
