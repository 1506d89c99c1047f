//! Infrared camera settings (document section 3.2.2, ids 0x000100..0x0001FF).
//! Temperatures are in 0.1 °C; −2732 switches a warning off.

use super::gimbal::OnOff;
use super::payload::ResponseCode;

code_enum! {
    /// Thermal palettes 1..=20 (0x000106, 0x000100 ACK).
    pub enum Palette: u8 {
        /// White hot.
        WhiteHot = 1,
        /// Black hot.
        BlackHot = 2,
        Rainbow = 3,
        /// High-contrast red.
        HighContrastRed = 4,
        /// Iron red.
        IronRed = 5,
        Magma = 6,
        Sky = 7,
        /// Medium grey.
        MediumGray = 8,
        /// Grey red.
        GrayRed = 9,
        /// Purple orange.
        PurpleOrange = 10,
        /// Special 1.
        Special1 = 11,
        /// Warning red.
        WarningRed = 12,
        /// Ice fire.
        IceFire = 13,
        /// Yellow red.
        YellowRed = 14,
        /// Special 2.
        Special2 = 15,
        /// Gradient red.
        GradientRed = 16,
        /// Gradient green.
        GradientGreen = 17,
        /// Gradient yellow.
        GradientYellow = 18,
        /// Warning green.
        WarningGreen = 19,
        /// Warning blue.
        WarningBlue = 20,
    }
}

code_enum! {
    /// Infrared gain mode (0x000123, 0x000100 ACK).
    pub enum IrGain: u8 {
        /// High gain.
        High = 0,
        /// Low gain.
        Low = 1,
        Auto = 2,
    }
}

code_enum! {
    /// Temperature measurement switch of 0x000108 (note: 0 = on).
    pub enum MeasureSwitch: u8 {
        /// Measurement on (the default; the camera reports 0x000004 periodically).
        On = 0,
        /// Measurement off.
        Off = 1,
    }
}

wire_newtype! {
    /// Measurement configuration byte of the 0x000100 ACK.
    pub struct MeasureConfig(u8);
}

impl MeasureConfig {
    /// Bit 0: measurement on (0 = on).
    #[must_use]
    pub const fn measuring(self) -> bool {
        self.0 & 0x01 == 0
    }
    /// Bit 1: area measurement (else point).
    #[must_use]
    pub const fn area(self) -> bool {
        self.0 & 0x02 != 0
    }
    /// Bit 2: radiometric core (else sighting core).
    #[must_use]
    pub const fn radiometric(self) -> bool {
        self.0 & 0x04 != 0
    }
    /// Bits 3..7: electronic zoom.
    #[must_use]
    pub const fn digital_zoom(self) -> u8 {
        self.0 >> 3
    }
}

wire_newtype! {
    /// A switch in bit 7 and a level in bits 0..6 (denoising in the 0x000100 ACK).
    pub struct SwitchLevel(u8);
}

impl SwitchLevel {
    /// Bit 7: on.
    #[must_use]
    pub const fn on(self) -> bool {
        self.0 & 0x80 != 0
    }
    /// Bits 0..6: level.
    #[must_use]
    pub const fn level(self) -> u8 {
        self.0 & 0x7F
    }
}

/// Declares the "one setting byte + reserved" IR requests.
macro_rules! ir_setting {
    ($($(#[$m:meta])* $name:ident { $(#[$fm:meta])* $field:ident: $ty:ty };)*) => {$(
        wire_struct! {
    Le;
            $(#[$m])*
            pub struct $name {
                $(#[$fm])*
                pub $field: $ty,
                /// Reserved; kept as received, so the frame re-encodes as it came.
                pub reserved: u8,
            }
        }
    )*};
}

ir_setting! {
    /// 0x000100: read all infrared parameters (command 0x01); the ACK is [`IrParams`].
    IrParamsQuery {
        /// The command byte.
        command: u8
    };
    /// 0x000105: infrared electronic zoom.
    IrDigitalZoom {
        /// 1 = none, 2..=8 = 2x..8x.
        zoom_x: u8
    };
    /// 0x000106: thermal palette.
    IrPalette {
        /// The false-colour palette of the thermal image.
        palette: Palette
    };
    /// 0x000108: temperature measurement switch.
    IrMeasurement {
        /// The switch (0 = on).
        switch: MeasureSwitch
    };
    /// 0x00010A: sharpening.
    IrSharpness {
        /// 0..=100.
        sharpness: u8
    };
    /// 0x00010B: brightness.
    IrBrightness {
        /// 0..=100.
        brightness: u8
    };
    /// 0x00010C: contrast.
    IrContrast {
        /// 0..=100.
        contrast: u8
    };
    /// 0x00010E: image enhancement.
    IrEnhancement {
        /// 0 = off, 1..=10 = level.
        level: u8
    };
    /// 0x000123: gain mode.
    IrGainMode {
        /// The gain mode.
        gain: IrGain
    };
    /// 0x000125: temperature overlay on the image.
    IrTempOverlay {
        /// The overlay switch.
        overlay: OnOff
    };
}

wire_struct! {
    Le;
    /// ACK of 0x000100: every infrared setting.
    pub struct IrParams {
        /// Response code.
        pub code: ResponseCode,
        /// Thermal palette.
        pub palette: Palette,
        /// Measurement switch, type, core and electronic zoom.
        pub measure: MeasureConfig,
        /// Sharpening, 0..=100.
        pub sharpness: u8,
        /// Gain mode.
        pub gain: IrGain,
        /// Brightness, 0..=100.
        pub brightness: u8,
        /// Contrast, 0..=100.
        pub contrast: u8,
        /// Denoising switch (bit 7) and level.
        pub denoise: SwitchLevel,
        /// Enhancement (the document gives a switch in bit 0 and parameters in bits 0..6;
        /// kept as the raw byte).
        pub enhancement: u8,
        /// High-temperature warning threshold (−2732 = off).
        pub high_warning_dc: i16,
        /// Low-temperature warning threshold (−2732 = off).
        pub low_warning_dc: i16,
        /// Temperature-difference warning (−2732 = off).
        pub diff_warning_dc: i16,
        /// Threshold warning switch (0 off, 1 on).
        pub threshold_warning: OnOff,
        /// Threshold reference temperature (−300..=500).
        pub threshold_ref_dc: i16,
        /// Threshold floating band (0..=800).
        pub threshold_float_dc: i16,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: [u8; 2],
    }
}

wire_struct! {
    Le;
    /// 0x00010D: denoising.
    pub struct IrDenoise {
        /// Denoising on or off.
        pub enable: OnOff,
        /// Level 0..=100.
        pub level: u8,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

wire_struct! {
    Le;
    /// 0x00010F: point temperature measurement at a cursor (0..=1920 x 0..=1088, black
    /// border included).
    pub struct IrPointMeasure {
        /// Cursor X.
        pub x: u16,
        /// Cursor Y.
        pub y: u16,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

wire_struct! {
    Le;
    /// 0x000110: rectangular area temperature measurement.
    pub struct IrAreaMeasure {
        /// Frame width.
        pub width: u16,
        /// Frame height.
        pub height: u16,
        /// Frame centre X.
        pub center_x: u16,
        /// Frame centre Y.
        pub center_y: u16,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

wire_struct! {
    Le;
    /// 0x000124: temperature warnings (−2732 = off). The document's table gives one
    /// reserved byte (7 bytes), its field list two (8 bytes); this crate encodes 8 and
    /// accepts 7.
    pub struct IrTempWarning {
        /// High-temperature threshold (−1000..=5000).
        pub high_dc: i16,
        /// Low-temperature threshold (−1000..=5000).
        pub low_dc: i16,
        /// Temperature difference (1..=6000).
        pub diff_dc: i16,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: [u8; 2],
    }
}

wire_struct! {
    Le;
    /// 0x000126: threshold temperature-difference warning.
    pub struct IrThresholdWarning {
        /// The warning on or off.
        pub enable: OnOff,
        /// Reference temperature (−300..=500).
        pub reference_dc: i16,
        /// Floating band (0..=800).
        pub float_dc: i16,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}
