//! Thermal camera messages (ZT30, ZT6): temperature measurement (0x12..0x14), palette
//! (0x1A, 0x1B), output mode (0x33..0x35), gain (0x37, 0x38) and environment
//! correction (0x39..0x3C).
//!
//! Temperatures are u16 in 0.01 °C, as the document types them (`_c_x100`).

use super::payload::OnOff;

code_enum! {
    /// Measurement flag of 0x12..0x14.
    pub enum MeasureFlag: u8 {
        /// 0: stop measuring.
        Off = 0,
        /// 1: measure once.
        Once = 1,
        /// 2: measure continuously (5 Hz).
        Continuous = 2,
    }
}

wire_struct! {
    Le;
    /// 0x12: temperature at a point.
    pub struct PointTemperatureRequest {
        /// X coordinate.
        pub x: u16,
        /// Y coordinate.
        pub y: u16,
        /// Stop, measure once, or measure continuously (5 Hz).
        pub flag: MeasureFlag,
    }
}

wire_struct! {
    Le;
    /// Reply of 0x12.
    pub struct PointTemperature {
        /// Temperature, 0.01 °C.
        pub temp_c_x100: u16,
        /// X coordinate.
        pub x: u16,
        /// Y coordinate.
        pub y: u16,
    }
}

wire_struct! {
    Le;
    /// 0x13: maximum and minimum temperature in a box.
    pub struct BoxTemperatureRequest {
        /// Start corner X.
        pub start_x: u16,
        /// Start corner Y.
        pub start_y: u16,
        /// End corner X.
        pub end_x: u16,
        /// End corner Y.
        pub end_y: u16,
        /// Stop, measure once, or measure continuously (5 Hz).
        pub flag: MeasureFlag,
    }
}

wire_struct! {
    Le;
    /// Reply of 0x13.
    pub struct BoxTemperature {
        /// Start corner X.
        pub start_x: u16,
        /// Start corner Y.
        pub start_y: u16,
        /// End corner X.
        pub end_x: u16,
        /// End corner Y.
        pub end_y: u16,
        /// Maximum temperature in the box, 0.01 °C.
        pub max_c_x100: u16,
        /// Minimum temperature in the box, 0.01 °C.
        pub min_c_x100: u16,
        /// X of the maximum.
        pub max_x: u16,
        /// Y of the maximum.
        pub max_y: u16,
        /// X of the minimum.
        pub min_x: u16,
        /// Y of the minimum.
        pub min_y: u16,
    }
}

wire_struct! {
    Le;
    /// 0x14: maximum and minimum temperature of the whole image.
    pub struct GlobalTemperatureRequest {
        /// Stop, measure once, or measure continuously (5 Hz).
        pub flag: MeasureFlag,
    }
}

wire_struct! {
    Le;
    /// Reply of 0x14.
    pub struct GlobalTemperature {
        /// Maximum temperature, 0.01 °C.
        pub max_c_x100: u16,
        /// Minimum temperature, 0.01 °C.
        pub min_c_x100: u16,
        /// X of the maximum.
        pub max_x: u16,
        /// Y of the maximum.
        pub max_y: u16,
        /// X of the minimum.
        pub min_x: u16,
        /// Y of the minimum.
        pub min_y: u16,
    }
}

code_enum! {
    /// Thermal palette (0x1A, 0x1B); 1 is reserved.
    pub enum Palette: u8 {
        /// 0: white hot.
        WhiteHot = 0,
        /// 2: sepia.
        Sepia = 2,
        /// 3: ironbow.
        Ironbow = 3,
        /// 4: rainbow.
        Rainbow = 4,
        /// 5: night.
        Night = 5,
        /// 6: aurora.
        Aurora = 6,
        /// 7: red hot.
        RedHot = 7,
        /// 8: jungle.
        Jungle = 8,
        /// 9: medical.
        Medical = 9,
        /// 10: black hot.
        BlackHot = 10,
        /// 11: glory hot.
        GloryHot = 11,
    }
}

wire_struct! {
    Le;
    /// Reply of 0x1A: the thermal palette (also the layout of 0x1B,
    /// [`SetThermalPalette`](super::SetThermalPalette) and
    /// [`SetThermalPaletteAck`](super::SetThermalPaletteAck)).
    pub struct ThermalPalette {
        /// The false-colour palette of the thermal image.
        pub palette: Palette,
    }
}

code_enum! {
    /// Thermal output mode (0x33, 0x34).
    pub enum ThermalOutput: u8 {
        /// 0: 30 fps.
        Fps30 = 0,
        /// 1: 25 fps with temperature frames.
        Fps25Temperature = 1,
    }
}

wire_struct! {
    Le;
    /// Reply of 0x33: the thermal output mode (also the layout of 0x34,
    /// [`SetThermalOutput`](super::SetThermalOutput) and
    /// [`SetThermalOutputAck`](super::SetThermalOutputAck)).
    pub struct ThermalOutputMode {
        /// 30 fps, or 25 fps with temperature frames.
        pub mode: ThermalOutput,
    }
}

code_enum! {
    /// Thermal gain (0x37, 0x38).
    pub enum Gain: u8 {
        /// 0: low gain (wide range, 50..550 °C).
        Low = 0,
        /// 1: high gain (-20..150 °C).
        High = 1,
    }
}

wire_struct! {
    Le;
    /// Reply of 0x37: the thermal gain (also the layout of 0x38,
    /// [`SetThermalGain`](super::SetThermalGain) and
    /// [`SetThermalGainAck`](super::SetThermalGainAck)).
    pub struct ThermalGain {
        /// Low gain (50..550 °C) or high gain (-20..150 °C).
        pub gain: Gain,
    }
}

wire_struct! {
    Le;
    /// Reply of 0x39: thermal environment parameters, each times 100 (also the layout
    /// of the 0x3A request, [`SetThermalEnvironment`](super::SetThermalEnvironment)).
    pub struct ThermalEnvironment {
        /// Distance to the target, 0.01 m.
        pub distance_m_x100: u16,
        /// Target emissivity, 0.01 %.
        pub emissivity_pct_x100: u16,
        /// Relative humidity, 0.01 %.
        pub humidity_pct_x100: u16,
        /// Air temperature, 0.01 °C.
        pub air_temp_c_x100: u16,
        /// Reflected temperature, 0.01 °C.
        pub reflected_temp_c_x100: u16,
    }
}

wire_struct! {
    Le;
    /// Reply of 0x3B: thermal environment correction on/off (also the layout of 0x3C,
    /// [`SetEnvCorrection`](super::SetEnvCorrection) and
    /// [`SetEnvCorrectionAck`](super::SetEnvCorrectionAck)).
    pub struct EnvCorrection {
        /// Environment correction on or off.
        pub state: OnOff,
    }
}
