//! The protocol-neutral vocabulary of the bridge: what a flight controller asks a gimbal
//! to do, whatever protocol it speaks. The flight-controller sides of the bridge
//! translate their protocol into a [`Command`]; the pod driver translates a [`Command`]
//! into K40T frames.
//!
//! # Conventions
//! Angles in 0.01 degree, rates in 0.01 degree per second. Yaw is relative to the
//! aircraft's nose (body frame) and positive to the right (clockwise seen from above);
//! pitch is relative to the horizon and positive up; roll positive right side down.
//! Each protocol side converts from its own convention (SIYI yaw is positive to the
//! left, `AP_Mount_Viewpro` sends pitch negated, ...).

protocol_core::wire_derive! {
    [Eq, Hash]
    /// How the gimbal's yaw behaves when no rate is commanded.
    pub enum GimbalMode {
        /// Yaw holds its heading on the ground (earth frame).
        Lock,
        /// Yaw follows the aircraft's nose (body frame).
        Follow,
        /// First-person view: roll and pitch follow the aircraft too.
        Fpv,
    }
}

protocol_core::wire_derive! {
    [Eq, Hash]
    /// A continuous motion of a lens group (zoom or focus).
    pub enum Motion {
        /// Zoom in / focus far.
        In,
        /// Zoom out / focus near.
        Out,
        /// No motion on this axis (rate zero).
        Stop,
    }
}

protocol_core::wire_derive! {
    [Eq, Hash]
    /// Which picture the pod streams (and which lens the FC's zoom addresses).
    pub enum View {
        /// The visible camera (telephoto/wide hybrid zoom).
        Visible,
        /// The thermal camera.
        Thermal,
        /// Split screen: visible and thermal.
        Split,
    }
}

protocol_core::wire_derive! {
    [Eq, Hash]
    /// Laser rangefinder operation.
    pub enum Ranging {
        /// One measurement.
        Single,
        /// Continuous measurements.
        Continuous,
        /// Stop measuring.
        Off,
    }
}

protocol_core::wire_derive! {
    [Eq, Hash]
    /// A point or a box in the streamed image, in pixels of a 1920 x 1080 picture
    /// (0,0 top left).
    pub enum Target {
        /// A point.
        Point {
            /// X, 0..1920.
            x: u16,
            /// Y, 0..1080.
            y: u16,
        },
        /// A box.
        Box {
            /// Left edge.
            x0: u16,
            /// Top edge.
            y0: u16,
            /// Right edge.
            x1: u16,
            /// Bottom edge.
            y1: u16,
        },
    }
}

protocol_core::wire_derive! {
    [Eq, Hash]
    /// What a flight controller asks the gimbal to do.
    pub enum Command {
        /// Turn at these rates (0.01 °/s; 0 stops the axis). Superseded by the next
        /// motion command; the bridge stops the pod when the FC falls silent.
        Rates {
            /// Yaw rate, positive right.
            yaw_cdeg_s: i32,
            /// Pitch rate, positive up.
            pitch_cdeg_s: i32,
        },
        /// Turn to these angles (0.01 °): yaw relative to the nose, pitch to the horizon.
        Angles {
            /// Yaw, positive right, -18000..=18000.
            yaw_cdeg: i32,
            /// Pitch, positive up.
            pitch_cdeg: i32,
        },
        /// Back to the neutral position (yaw and pitch 0).
        Center,
        /// Look straight down (pitch -90°).
        LookDown,
        /// Yaw behaviour.
        Mode(GimbalMode),
        /// Take one photo.
        TakePhoto,
        /// Start (`true`) or stop (`false`) recording video.
        Record(bool),
        /// The camera's capture mode: video (`true`) or photo (`false`).
        VideoMode(bool),
        /// Zoom continuously in or out, or stop.
        Zoom(Motion),
        /// Zoom to a ratio (times ten: 45 = 4.5x).
        ZoomTo {
            /// The ratio times ten.
            zoom_x10: u16,
        },
        /// Zoom the thermal camera to a digital ratio (1..=8x).
        ThermalZoom {
            /// The ratio, 1..=8.
            ratio: u8,
        },
        /// Focus continuously far (`In`) or near (`Out`), or stop.
        Focus(Motion),
        /// Autofocus, on the whole picture or at a point of it.
        AutoFocus(Option<Target>),
        /// Manual focus mode (`false` returns to autofocus).
        ManualFocus(bool),
        /// Stream this picture.
        View(View),
        /// Thermal palette, as the K40T numbers its palettes.
        Palette(protocol_core::k40t::Palette),
        /// Thermal gain: high (`true`, narrow temperature range) or low.
        ThermalHighGain(bool),
        /// Laser rangefinder.
        Laser(Ranging),
        /// Track the object at a point or in a box (`None` stops tracking).
        Track(Option<Target>),
        /// Turn the gimbal so that this point of the picture comes to the centre.
        Aim(Target),
    }
}

impl Command {
    /// True for the commands that move the gimbal (never retried; the next one
    /// supersedes them).
    #[must_use]
    pub const fn is_motion(&self) -> bool {
        matches!(
            self,
            Command::Rates { .. } | Command::Angles { .. } | Command::Center | Command::LookDown
        )
    }
}
