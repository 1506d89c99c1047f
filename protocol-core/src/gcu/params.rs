//! The parameter types of the host's commands: camera sets, the actions of the
//! enumerated parameters, and the multi-field parameter layouts (all little-endian).

wire_newtype! {
    /// A set of cameras (the document's `KK` and `NN` bytes): bit 0 is camera 1 (the
    /// visible-light zoom camera by default), bit 1 camera 2 (the thermal camera by
    /// default), up to bit 7, camera 8.
    pub struct CameraSet(u8);
}

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
    #[must_use]
    pub const fn camera(n: u8) -> Option<CameraSet> {
        match n {
            // `n - 1` is 0..=7: the shift stays inside the byte.
            1..=8 => Some(CameraSet(1u8.wrapping_shl(n.wrapping_sub(1) as u32))),
            _ => None,
        }
    }

    /// True when camera `n` (1..=8) is in the set.
    #[must_use]
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
    #[must_use]
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }

    /// The camera numbers in the set, ascending.
    pub fn iter(self) -> impl Iterator<Item = u8> {
        (1..=8u8).filter(move |&n| self.contains(n))
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
    /// the views `AP_Mount_XFRobot` selects (its `CameraType`).
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
    Le;
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
    Le;
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
    Le;
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
    Le;
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
    Le;
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
    #[must_use]
    pub const fn ratio(cameras: CameraSet, ratio_x10: u16) -> Option<ZoomTo> {
        if ratio_x10 < 10 || ratio_x10 > 32768 {
            return None;
        }
        // 10..=32768 negated modulo 2^16 is the two's complement of -10..=-32768.
        let zoom_code = i16::from_ne_bytes(ratio_x10.wrapping_neg().to_ne_bytes());
        Some(ZoomTo { cameras, zoom_code })
    }

    /// Zoom `cameras` to a fraction of the zoom range (1..=10000).
    #[must_use]
    pub const fn fraction_of_range(cameras: CameraSet, fraction: u16) -> Option<ZoomTo> {
        if fraction < 1 || fraction > 10000 {
            return None;
        }
        Some(ZoomTo {
            cameras,
            // 1..=10000 reads the same as an i16.
            zoom_code: i16::from_ne_bytes(fraction.to_ne_bytes()),
        })
    }

    /// The desired zoom ratio in 0.1x, when the code is one (≤ -10).
    #[must_use]
    pub const fn ratio_x10(self) -> Option<u16> {
        if self.zoom_code <= -10 {
            Some(self.zoom_code.unsigned_abs())
        } else {
            None
        }
    }

    /// The desired fraction of the zoom range (1..=10000), when the code is one.
    #[must_use]
    pub const fn fraction(self) -> Option<u16> {
        if 1 <= self.zoom_code && self.zoom_code <= 10000 {
            Some(self.zoom_code.unsigned_abs())
        } else {
            None
        }
    }
}

wire_struct! {
    Le;
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
    Le;
    /// Parameters of the night vision order (0x2B). The document's examples send
    /// `0x01 TT`: camera 1.
    pub struct NightVision {
        /// Cameras (0x01 in the document).
        pub cameras: CameraSet,
        /// On or off (`TT`).
        pub state: OnOff,
    }
}
