//! Visible-light camera settings (document section 3.2.3, ids 0x000200..0x0002FF).
//! Every setting request starts with a "start setting" byte (0x00).

use super::camera::{AeLock, Ev};
use super::payload::ResponseCode;

code_enum! {
    /// Photo resolution (0x000202, 0x000307, 0x000200 ACK).
    pub enum PhotoResolution: u8 {
        /// 8000 x 6000.
        R8000x6000 = 0x14,
        /// 4000 x 3000.
        R4000x3000 = 0x15,
        /// 5160 x 3870.
        R5160x3870 = 0x16,
        /// 5664 x 4248 (0x000307 only).
        R5664x4248 = 0x17,
    }
}

code_enum! {
    /// Video recording resolution (0x000201, 0x000200 ACK).
    pub enum VideoResolution: u8 {
        /// 1920 x 1080.
        R1080p = 0x08,
        /// 3840 x 2160.
        R4k = 0x26,
        /// 4000 x 3000.
        R4000x3000 = 0x36,
    }
}

code_enum! {
    /// ISO (0x000203, 0x000200 ACK).
    pub enum Iso: u8 {
        Auto = 0x00,
        /// ISO 100.
        Iso100 = 0x01,
        /// ISO 200.
        Iso200 = 0x02,
        /// ISO 400.
        Iso400 = 0x03,
        /// ISO 800.
        Iso800 = 0x04,
        /// ISO 1600.
        Iso1600 = 0x05,
        /// ISO 3200.
        Iso3200 = 0x06,
        /// ISO 6400.
        Iso6400 = 0x07,
    }
}

code_enum! {
    /// Electronic shutter (0x000204, 0x000200 ACK). The document lists 0x0C twice
    /// (1/5000 and 1/6000) and skips 0x0D: 1/6000 is taken to be 0x0D.
    pub enum Shutter: u8 {
        Auto = 0x00,
        /// 1/4 s.
        S1_4 = 0x01,
        /// 1/8 s.
        S1_8 = 0x02,
        /// 1/15 s.
        S1_15 = 0x03,
        /// 1/30 s.
        S1_30 = 0x04,
        /// 1/60 s.
        S1_60 = 0x05,
        /// 1/125 s.
        S1_125 = 0x06,
        /// 1/250 s.
        S1_250 = 0x07,
        /// 1/500 s.
        S1_500 = 0x08,
        /// 1/1000 s.
        S1_1000 = 0x09,
        /// 1/2000 s.
        S1_2000 = 0x0A,
        /// 1/4000 s.
        S1_4000 = 0x0B,
        /// 1/5000 s.
        S1_5000 = 0x0C,
        /// 1/6000 s.
        S1_6000 = 0x0D,
        /// 1/8000 s.
        S1_8000 = 0x0E,
    }
}

code_enum! {
    /// White balance (bits 0..3; bits 4..7 reserved and kept in `Other`).
    pub enum WhiteBalance: u8 {
        Auto = 0x01,
        /// Incandescent light.
        Incandescent = 0x02,
        /// Fluorescent light.
        Fluorescent = 0x03,
        /// Warm daylight.
        WarmDaylight = 0x04,
        Daylight = 0x05,
        Cloudy = 0x06,
        Dusk = 0x07,
        Dark = 0x08,
    }
}

code_enum! {
    /// Anti-flicker (0x000207).
    pub enum AntiFlicker: u8 {
        Off = 0x01,
        /// 50 Hz.
        Hz50 = 0x02,
        /// 60 Hz.
        Hz60 = 0x03,
        Auto = 0x04,
    }
}

code_enum! {
    /// Metering mode (0x00020B, 0x000200 ACK).
    pub enum Metering: u8 {
        CenterWeighted = 0x01,
        /// Zone (area).
        Zone = 0x02,
        Average = 0x03,
    }
}

code_enum! {
    /// A two-state switch encoded 1 = on, 2 = off (visible camera, AI, tracking).
    pub enum Toggle: u8 {
        /// On / enable.
        On = 0x01,
        /// Off / disable.
        Off = 0x02,
    }
}

wire_newtype! {
    /// Byte 16 of the 0x000200 ACK: watermark switch (bits 0..3) and anti-flicker (4..7).
    pub struct OsdFlicker(u8);
}

impl OsdFlicker {
    /// Watermark switch (bits 0..3).
    #[must_use]
    pub const fn watermark(self) -> u8 {
        self.0 & 0x0F
    }
    /// Anti-flicker state (bits 4..7).
    #[must_use]
    pub const fn anti_flicker(self) -> AntiFlicker {
        AntiFlicker::from_value(self.0 >> 4)
    }
}

wire_struct! {
    Le;
    /// 0x000200: read all visible-camera parameters (command 0x01); the ACK is
    /// [`VisibleParams`].
    pub struct VisibleParamsQuery {
        /// The command byte.
        pub command: u8,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

wire_struct! {
    Le;
    /// ACK of 0x000200: every visible-camera setting.
    pub struct VisibleParams {
        /// Response code.
        pub code: ResponseCode,
        /// Photo resolution.
        pub photo_resolution: PhotoResolution,
        /// Video resolution.
        pub video_resolution: VideoResolution,
        /// Video bitrate index 0..=3 (its Mbit/s depend on codec and resolution).
        pub video_bitrate: u8,
        /// White balance.
        pub white_balance: WhiteBalance,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: [u8; 2],
        /// Exposure compensation.
        pub ev: Ev,
        /// Automatic, or ISO 100..6400.
        pub iso: Iso,
        /// Electronic shutter.
        pub shutter: Shutter,
        /// Zoom fine-tuning, 0..=100.
        pub zoom_fine: u8,
        /// Backlight compensation (switch bit 7, value bits 0..6), raw.
        pub backlight: u8,
        /// Strong-light suppression (switch bit 7, value bits 0..6), raw.
        pub strong_light: u8,
        /// AE lock.
        pub ae_lock: AeLock,
        /// Watermark and anti-flicker.
        pub osd_flicker: OsdFlicker,
        /// Metering mode.
        pub metering: Metering,
    }
}

/// Declares the "start byte + one setting" visible requests.
macro_rules! visible_setting {
    ($($(#[$m:meta])* $name:ident { $(#[$fm:meta])* $field:ident: $ty:ty };)*) => {$(
        wire_struct! {
    Le;
            $(#[$m])*
            pub struct $name {
                /// Start setting (0x00).
                pub start: u8,
                $(#[$fm])*
                pub $field: $ty,
            }
        }
    )*};
}

visible_setting! {
    /// 0x000201: video recording resolution.
    VideoResolutionSetting {
        /// The video recording resolution.
        resolution: VideoResolution
    };
    /// 0x000202: photo resolution.
    PhotoResolutionSetting {
        /// The photo resolution.
        resolution: PhotoResolution
    };
    /// 0x000203: ISO.
    IsoSetting {
        /// Automatic, or ISO 100..6400.
        iso: Iso
    };
    /// 0x000204: electronic shutter.
    ShutterSetting {
        /// Automatic, or an exposure time.
        shutter: Shutter
    };
    /// 0x000205: exposure compensation.
    EvSetting {
        /// The exposure compensation step.
        ev: Ev
    };
    /// 0x000207: anti-flicker.
    AntiFlickerSetting {
        /// Anti-flicker mode.
        mode: AntiFlicker
    };
    /// 0x00020A: AE lock.
    AeLockSetting {
        /// AE lock.
        lock: AeLock
    };
    /// 0x00020B: metering mode.
    MeteringSetting {
        /// Metering mode.
        mode: Metering
    };
}

wire_struct! {
    Le;
    /// 0x000206: white balance.
    pub struct WhiteBalanceSetting {
        /// Start setting (0x00).
        pub start: u8,
        /// White balance.
        pub white_balance: WhiteBalance,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: [u8; 2],
    }
}

wire_struct! {
    Le;
    /// 0x000208: strong-light suppression (cannot be on with backlight compensation).
    pub struct StrongLightSetting {
        /// Start setting (0x00).
        pub start: u8,
        /// Strong-light suppression on or off.
        pub enable: Toggle,
        /// Value 0..=100.
        pub value: u8,
    }
}

wire_struct! {
    Le;
    /// 0x000209: backlight compensation (cannot be on with strong-light suppression).
    pub struct BacklightSetting {
        /// Start setting (0x00).
        pub start: u8,
        /// Backlight compensation on or off.
        pub enable: Toggle,
        /// Value 0..=100.
        pub value: u8,
    }
}
