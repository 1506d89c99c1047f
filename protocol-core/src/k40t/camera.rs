//! Periodic camera reports (document section 3.2.1: 0x000003, 0x000004, 0x000005, 0x000008)
//! and the enumerations the camera messages share.

code_enum! {
    /// Photo or video mode (0x000003 byte 1, 0x000300).
    pub enum CaptureMode: u8 {
        /// Photo mode.
        Photo = 0,
        /// Video mode.
        Video = 1,
    }
}

code_enum! {
    /// Preview stream resolution as 0x000003 reports it.
    pub enum PreviewResolution: u8 {
        /// 1080p, 30 fps.
        P1080Fps30 = 0,
        /// 720p, 30 fps.
        P720Fps30 = 1,
    }
}

code_enum! {
    /// Video encoding (0x000003 byte 3, 0x00030B).
    pub enum VideoCodec: u8 {
        H264 = 0,
        H265 = 1,
    }
}

code_enum! {
    /// Which image is streamed (0x000003 byte 4, 0x000318).
    pub enum ImageMode: u8 {
        Infrared = 0x00,
        /// Visible light (code 0x05).
        Visible = 0x05,
        /// Visible light (code 0x06).
        VisibleAlt = 0x06,
        /// Split screen.
        Split = 0x07,
    }
}

code_enum! {
    /// Stream bitrate (0x000003 byte 5, 0x000308).
    pub enum StreamBitrate: u8 {
        /// 1 Mbit/s.
        M1 = 1,
        /// 1.5 Mbit/s.
        M1_5 = 2,
        /// 2 Mbit/s.
        M2 = 3,
        /// 4 Mbit/s.
        M4 = 4,
        /// 8 Mbit/s.
        M8 = 5,
        /// 12 Mbit/s.
        M12 = 6,
    }
}

code_enum! {
    /// Photo function (0x000003 byte 6, 0x000301).
    pub enum PhotoMode: u8 {
        /// Single shot.
        Single = 0,
        /// Burst of 3 or 5.
        Burst = 1,
        TimeLapse = 2,
    }
}

code_enum! {
    /// SD card state (0x000003 byte 9).
    pub enum SdState: u8 {
        Normal = 0,
        /// Abnormal card.
        Abnormal = 1,
        /// Slow card.
        Slow = 2,
        /// No card inserted.
        Missing = 3,
        /// Card full.
        Full = 4,
        /// Card format error.
        FormatError = 5,
    }
}

wire_struct! {
    Le;
    /// 0x000003, report (1 Hz): camera system status. SD capacities are in units of
    /// 10 MB (the document: "MB*10").
    pub struct SystemStatus {
        /// Photo or video mode.
        pub mode: CaptureMode,
        /// Preview stream resolution.
        pub preview_resolution: PreviewResolution,
        /// Preview stream encoding.
        pub preview_codec: VideoCodec,
        /// Streamed image.
        pub stream: ImageMode,
        /// Preview stream bitrate.
        pub preview_bitrate: StreamBitrate,
        /// Photo function.
        pub photo_mode: PhotoMode,
        /// Time-lapse interval (5, 7, 30 or 60 s).
        pub timelapse_s: u8,
        /// Burst count (3 or 5).
        pub burst_count: u8,
        /// SD card state.
        pub sd: SdState,
        /// Total SD capacity.
        pub sd_total_10mb: u16,
        /// Remaining SD capacity.
        pub sd_free_10mb: u16,
        /// Used SD capacity.
        pub sd_used_10mb: u16,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

wire_struct! {
    Le;
    /// 0x000004, report (5 Hz): infrared measurements. Temperatures in 0.1 °C,
    /// coordinates in image pixels; warning flags 1 = warning active.
    pub struct IrStatus {
        /// Region maximum.
        pub max_temp_dc: i16,
        /// Region minimum.
        pub min_temp_dc: i16,
        /// Region centre.
        pub center_temp_dc: i16,
        /// Point measurement.
        pub point_temp_dc: i16,
        /// Region average.
        pub avg_temp_dc: i16,
        /// X of the region maximum.
        pub max_x: u16,
        /// Y of the region maximum.
        pub max_y: u16,
        /// X of the region minimum.
        pub min_x: u16,
        /// Y of the region minimum.
        pub min_y: u16,
        /// X of the region centre.
        pub center_x: u16,
        /// Y of the region centre.
        pub center_y: u16,
        /// X of the measured point.
        pub point_x: u16,
        /// Y of the measured point.
        pub point_y: u16,
        /// High-temperature warning.
        pub high_warning: u8,
        /// Low-temperature warning.
        pub low_warning: u8,
        /// Temperature-difference warning.
        pub diff_warning: u8,
        /// Threshold warning.
        pub threshold_warning: u8,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: [u8; 4],
    }
}

code_enum! {
    /// Zoom progress (0x000005 byte 1, status of 0x000304).
    pub enum ZoomState: u8 {
        /// Zoom completed.
        Done = 0,
        Zooming = 1,
    }
}

code_enum! {
    /// Exposure compensation (0x000005, 0x000200 ACK, 0x000205).
    pub enum Ev: u8 {
        Auto = 0x00,
        /// +2 EV.
        Plus2 = 0x0A,
        /// +1 EV.
        Plus1 = 0x10,
        /// 0 EV.
        Zero = 0x16,
        /// −1 EV.
        Minus1 = 0x1C,
        /// −2 EV.
        Minus2 = 0x23,
    }
}

code_enum! {
    /// AE lock state (0x000005, 0x000200 ACK, 0x00020A).
    pub enum AeLock: u8 {
        On = 0x01,
        Off = 0x02,
    }
}

code_enum! {
    /// Focus progress (0x000005 byte 12).
    pub enum FocusState: u8 {
        /// Focus completed.
        Done = 0,
        Focusing = 1,
    }
}

wire_struct! {
    Le;
    /// 0x000005, report (5 Hz): visible camera parameters.
    pub struct VisibleStatus {
        /// Zoom progress.
        pub zoom_state: ZoomState,
        /// Focal length, 0.01 mm.
        pub focal_length_10um: u16,
        /// Hybrid zoom ratio (above 11x is electronic).
        pub zoom_x10: u16,
        /// Exposure compensation.
        pub ev: Ev,
        /// ISO value, 0.1 dB (the document's unit).
        pub iso_0p1db: u16,
        /// Electronic shutter, microseconds.
        pub shutter_us: u16,
        /// AE lock.
        pub ae_lock: AeLock,
        /// Focus progress.
        pub focus: FocusState,
        /// Focal length of the accurate re-shoot (unit not given by the document).
        pub accurate_focal_length: u16,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

code_enum! {
    /// Upgrade or repair progress state (0x000008 byte 1).
    pub enum UpgradeProgressState: u8 {
        Succeeded = 0,
        Failed = 1,
        Upgrading = 2,
        Repairing = 3,
    }
}

wire_struct! {
    Le;
    /// 0x000008, report (1 Hz): camera upgrade or repair progress.
    pub struct UpgradeStatus {
        /// Upgrading, repairing, or how the last attempt ended.
        pub state: UpgradeProgressState,
        /// Progress, 0..=100 %.
        pub progress_pct: u8,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}
