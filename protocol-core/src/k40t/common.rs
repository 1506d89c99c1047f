//! Common camera commands (document section 3.2.4, ids 0x000300..0x0003FF): capture,
//! zoom, stream, storage, time sync, GPS exchange, network, focus, AI and tracking.

use super::camera::{CaptureMode, ImageMode, PhotoMode, StreamBitrate, VideoCodec, ZoomState};
use super::gimbal::OnOff;
use super::payload::{ResponseCode, Version};
use super::visible::{PhotoResolution, Toggle};
use crate::Text;

/// Folder name field (20 bytes).
pub type Folder = Text<20>;
/// File name field (32 bytes).
pub type FileName = Text<32>;

wire_struct! {
    Le;
    /// 0x000300: photo or video mode (in photo mode the camera ignores recording
    /// commands, and the reverse).
    pub struct CaptureModeSetting {
        /// Photo or video mode.
        pub mode: CaptureMode,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

wire_struct! {
    Le;
    /// 0x000301: photo parameters.
    pub struct PhotoParams {
        /// Photo function.
        pub mode: PhotoMode,
        /// Time-lapse interval (5, 7, 30 or 60 s).
        pub timelapse_s: u8,
        /// Burst count (3 or 5).
        pub burst_count: u8,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

code_enum! {
    /// Which sensors take the photo (0x000302, 0x000307 and their status frames).
    pub enum PhotoSensors: u8 {
        /// Default (infrared + visible).
        Default = 0x00,
        /// Infrared (640 x 512).
        Infrared = 0x01,
        /// Visible (4000 x 3000).
        Visible = 0x02,
        /// Infrared + visible.
        Both = 0x03,
    }
}

code_enum! {
    /// Shooting command of 0x000302.
    pub enum ShootAction: u8 {
        /// Single shot / start shooting.
        Start = 0x00,
        /// Stop shooting (continuous modes only).
        Stop = 0x01,
    }
}

wire_struct! {
    Le;
    /// 0x000302: take a photo. Empty folder = root directory; empty name = default
    /// naming. The pod asks for GPS (0x000310) before it takes the photo.
    pub struct TakePhoto {
        /// The cameras concerned: infrared, visible or both.
        pub sensors: PhotoSensors,
        /// Start or stop.
        pub action: ShootAction,
        /// Folder name.
        pub folder: Folder,
        /// Image name.
        pub name: FileName,
    }
}

code_enum! {
    /// Photo progress in the status frames of 0x000302 and 0x000307.
    pub enum PhotoState: u8 {
        /// Photo taken.
        Taken = 0,
        /// Single shot in progress.
        SingleShot = 1,
        /// Burst in progress.
        Burst = 2,
        /// Time-lapse in progress.
        TimeLapse = 3,
        /// Shooting stopped.
        Stopped = 4,
        /// Single shot in progress (code 5).
        SingleShotAlt = 5,
        /// Photo failed.
        Failed = 6,
        /// No SD card.
        NoSdCard = 7,
        /// SD card full.
        SdFull = 8,
        /// Abnormal card.
        SdAbnormal = 9,
        /// Slow card.
        SdSlow = 10,
        /// SD card format error.
        SdFormatError = 11,
        /// Accurate re-shoot (0x000307).
        AccurateReshoot = 12,
    }
}

wire_struct! {
    Le;
    /// Status frame of 0x000302 (none for a single shot).
    pub struct PhotoStatus {
        /// The cameras concerned: infrared, visible or both.
        pub sensors: PhotoSensors,
        /// How far the shot is, or why it failed (SD card states included).
        pub state: PhotoState,
        /// Burst count.
        pub burst_count: u16,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: [u8; 3],
    }
}

code_enum! {
    /// Recording sensors of 0x000303.
    pub enum RecordSensors: u8 {
        /// Default (infrared + visible).
        Default = 0x00,
        /// Infrared (640 x 512).
        Infrared = 0x01,
        /// Visible (4000 x 3000).
        Visible = 0x02,
        /// Infrared + visible.
        Both = 0x03,
        /// The video stream (1920 x 1080).
        Stream = 0x04,
    }
}

code_enum! {
    /// Recording command of 0x000303.
    pub enum RecordAction: u8 {
        /// Start (repeating it does not stop recording).
        Start = 0x01,
        Stop = 0x02,
    }
}

wire_struct! {
    Le;
    /// 0x000303: record video.
    pub struct Record {
        /// The cameras concerned: infrared, visible, both, or the video stream.
        pub sensors: RecordSensors,
        /// Start or stop.
        pub action: RecordAction,
        /// Folder name.
        pub folder: Folder,
        /// Video name.
        pub name: FileName,
    }
}

code_enum! {
    /// Recording progress in the status frame of 0x000303.
    pub enum RecordState: u8 {
        Stopped = 0,
        Recording = 1,
        /// Waiting for time-lapse recording.
        TimeLapseWaiting = 2,
        /// Time-lapse recording.
        TimeLapse = 3,
        /// No SD card.
        NoSdCard = 4,
        /// SD card full.
        SdFull = 5,
        /// Abnormal card.
        SdAbnormal = 6,
        /// Slow card.
        SdSlow = 7,
        /// SD card format error.
        SdFormatError = 8,
    }
}

wire_struct! {
    Le;
    /// Status frame of 0x000303 (1 Hz).
    pub struct RecordStatus {
        /// The cameras concerned: infrared, visible, both, or the video stream.
        pub sensors: RecordSensors,
        /// Recording, stopped or time-lapse, or why it cannot record (SD card states).
        pub state: RecordState,
        /// Recording time (the document gives no unit; seconds assumed).
        pub elapsed_s: u16,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: [u8; 3],
    }
}

wire_struct! {
    Le;
    /// 0x000304: go to a hybrid zoom ratio (1..=160x).
    pub struct HybridZoom {
        /// Start setting (0).
        pub start: u8,
        /// Zoom ratio.
        pub zoom_x10: u16,
    }
}

wire_struct! {
    Le;
    /// Status frame of 0x000304.
    pub struct ZoomStatus {
        /// Zoom progress.
        pub state: ZoomState,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

code_enum! {
    /// Continuous zoom command of 0x000306.
    pub enum ZoomControl: u8 {
        /// Zoom in continuously.
        In = 0x00,
        /// Zoom out continuously.
        Out = 0x01,
        /// Stop zooming.
        Stop = 0x02,
        /// Zoom in one step.
        StepIn = 0x03,
        /// Zoom out one step.
        StepOut = 0x04,
    }
}

wire_struct! {
    Le;
    /// 0x000306: continuous zoom.
    pub struct ContinuousZoom {
        /// The zoom command.
        pub control: ZoomControl,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

wire_struct! {
    Le;
    /// 0x000307: accurate re-shoot (photo at a given resolution, zoom and focal length).
    pub struct AccurateShoot {
        /// The cameras concerned: infrared, visible or both.
        pub sensors: PhotoSensors,
        /// Visible photo resolution.
        pub resolution: PhotoResolution,
        /// Visible zoom ratio.
        pub zoom_x10: u16,
        /// Visible focal length of the re-shoot (unit not given by the document).
        pub focal_length: u16,
        /// Folder name.
        pub folder: Folder,
        /// Image name.
        pub name: FileName,
    }
}

wire_struct! {
    Le;
    /// Status frame of 0x000307.
    pub struct AccurateShootStatus {
        /// The cameras concerned: infrared, visible or both.
        pub sensors: PhotoSensors,
        /// How far the shot is, or why it failed (SD card states included).
        pub state: PhotoState,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: [u8; 5],
    }
}

wire_struct! {
    Le;
    /// 0x000308: output stream bitrate.
    pub struct StreamBitrateSetting {
        /// The output stream's bitrate, 1 to 12 Mbit/s.
        pub bitrate: StreamBitrate,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

code_enum! {
    /// Output resolution of 0x00030A (note: coded from 1, unlike 0x000003).
    pub enum OutputResolution: u8 {
        /// 1080p, 30 fps.
        P1080Fps30 = 1,
        /// 720p, 30 fps (not supported by the pod).
        P720Fps30 = 2,
    }
}

wire_struct! {
    Le;
    /// 0x00030A: video output resolution.
    pub struct OutputResolutionSetting {
        /// 1080p or 720p at 30 fps (the pod supports 1080p only).
        pub resolution: OutputResolution,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

wire_struct! {
    Le;
    /// 0x00030B: video output encoding.
    pub struct OutputCodecSetting {
        /// H.264 or H.265.
        pub codec: VideoCodec,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

trigger! {
    /// 0x00030C: TF card upgrade (command 1 = start, 0 = invalid).
    TfUpgrade;
    /// 0x00030D: format the SD card (command 0x01).
    FormatSd;
    /// 0x00030F: restore factory settings (command 0x01; restarts after 1 s).
    FactoryReset;
    /// 0x000312: query the IP address (command 1); the ACK is [`IpConfigAck`].
    IpQuery;
    /// 0x000316: camera shutdown (command 0x01 = about to shut down).
    Shutdown;
    /// 0x000317: get the camera version (command 0x01); the ACK is [`CameraVersionAck`].
    CameraVersionQuery;
}

code_enum! {
    /// TF card upgrade progress (status of 0x00030C).
    pub enum TfUpgradeState: u8 {
        /// Upgraded successfully.
        Succeeded = 0x00,
        Upgrading = 0x01,
        /// Upgrade failed.
        Failed = 0x02,
    }
}

wire_struct! {
    Le;
    /// Status frame of 0x00030C.
    pub struct TfUpgradeStatus {
        /// Upgrading, upgraded or failed.
        pub state: TfUpgradeState,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

code_enum! {
    /// Formatting progress (status of 0x00030D).
    pub enum FormatState: u8 {
        /// Formatting completed.
        Done = 0x00,
        InProgress = 0x01,
        /// Formatting failed.
        Failed = 0x02,
        /// SD card unavailable.
        Unavailable = 0x03,
    }
}

wire_struct! {
    Le;
    /// Status frame of 0x00030D (5 Hz).
    pub struct FormatStatus {
        /// Formatting, done, failed, or the card unavailable.
        pub state: FormatState,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: [u8; 2],
    }
}

wire_struct! {
    Le;
    /// 0x00030E: time sync. Sent immediately after the rising edge of RTC_IO, carrying
    /// the UTC time of that edge; repeated every 10 s.
    pub struct TimeSync {
        /// Milliseconds since 1970-01-01T00:00:00Z at the RTC_IO rising edge.
        pub unix_ms: u64,
        /// Time zone, minutes west of Greenwich (`tz_minuteswest`).
        pub tz_minuteswest: i32,
        /// Daylight-saving correction type (`tz_dsttime`).
        pub tz_dsttime: i32,
    }
}

wire_struct! {
    Le;
    /// 0x000310, sent by the pod to the flight controller: GPS wanted for this UTC
    /// time of day. The ACK ([`GpsReply`]) comes from the flight controller.
    pub struct GpsRequest {
        /// Lens enable (0 disabled, 1 enabled).
        pub lens_enable: u8,
        /// Hour, 0..=23.
        pub hour: u8,
        /// Minute, 0..=59.
        pub minute: u8,
        /// Second, 0..=59.
        pub second: u8,
        /// Millisecond, 0..=999.
        pub millisecond: u16,
    }
}

wire_struct! {
    Le;
    /// ACK of 0x000310, sent by the flight controller: position and attitude at the
    /// requested time (echoed).
    pub struct GpsReply {
        /// Response code.
        pub code: ResponseCode,
        /// Hour (as requested).
        pub hour: u8,
        /// Minute (as requested).
        pub minute: u8,
        /// Second (as requested).
        pub second: u8,
        /// Millisecond (as requested).
        pub millisecond: u16,
        /// Longitude, 1e-7 degree.
        pub lon_e7: i32,
        /// Latitude, 1e-7 degree.
        pub lat_e7: i32,
        /// Height relative to home, 0.1 m.
        pub rel_alt_dm: i16,
        /// Altitude above mean sea level, 0.1 m.
        pub alt_msl_dm: i16,
        /// Aircraft yaw, 0.01°.
        pub yaw_cdeg: i16,
        /// Aircraft roll, 0.01°.
        pub roll_cdeg: i16,
        /// Aircraft pitch, 0.01°.
        pub pitch_cdeg: i16,
    }
}

code_enum! {
    /// IP configuration mode of 0x000311.
    pub enum IpMode: u8 {
        /// Static address.
        Static = 0,
        /// Address from a DHCP server.
        Dynamic = 1,
    }
}

wire_struct! {
    Le;
    /// 0x000311: set the camera's IP configuration (octets in dotted order).
    pub struct SetIp {
        /// Static or dynamic.
        pub mode: IpMode,
        /// The IPv4 address, octets in dotted order.
        pub address: [u8; 4],
        /// Subnet mask.
        pub netmask: [u8; 4],
        /// Default gateway.
        pub gateway: [u8; 4],
    }
}

wire_struct! {
    Le;
    /// ACK of 0x000312: the camera's IP configuration.
    pub struct IpConfigAck {
        /// Response code.
        pub code: ResponseCode,
        /// The IPv4 address, octets in dotted order.
        pub address: [u8; 4],
        /// Subnet mask.
        pub netmask: [u8; 4],
        /// Default gateway.
        pub gateway: [u8; 4],
    }
}

code_enum! {
    /// Focus command of 0x000313.
    pub enum FocusMode: u8 {
        /// Auto focus.
        Auto = 0x00,
        /// Manual fine focus +.
        ManualPlus = 0x01,
        /// Manual fine focus −.
        ManualMinus = 0x02,
        /// Stop manual focus.
        ManualStop = 0x03,
        /// Area auto focus (uses the rectangle).
        Area = 0x04,
        /// One-touch focus.
        OneTouch = 0x05,
        /// Auto focus after zooming: on.
        AfAfterZoomOn = 0x06,
        /// Auto focus after zooming: off.
        AfAfterZoomOff = 0x07,
    }
}

wire_struct! {
    Le;
    /// 0x000313: focus.
    pub struct Focus {
        /// Focus command.
        pub mode: FocusMode,
        /// Area: upper-left X.
        pub x0: u16,
        /// Area: upper-left Y.
        pub y0: u16,
        /// Area: lower-right X.
        pub x1: u16,
        /// Area: lower-right Y.
        pub y1: u16,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

wire_struct! {
    Le;
    /// 0x000314: OSD watermark.
    pub struct Watermark {
        /// Whether the watermark is shown.
        pub enable: OnOff,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: [u8; 2],
    }
}

wire_struct! {
    Le;
    /// ACK of 0x000317: the camera version.
    pub struct CameraVersionAck {
        /// Response code.
        pub code: ResponseCode,
        /// The camera firmware version.
        pub version: Version,
    }
}

wire_struct! {
    Le;
    /// 0x000318: image (stream) mode.
    pub struct ImageModeSetting {
        /// Infrared, visible light or split screen.
        pub mode: ImageMode,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}

wire_struct! {
    Le;
    /// 0x000319: AI recognition.
    pub struct AiRecognition {
        /// Switch (1 on, 2 off).
        pub enable: Toggle,
        /// Model to load (YOLO series; default 0).
        pub model: u8,
        /// Up to ten target class ids.
        pub classes: [u8; 10],
    }
}

code_enum! {
    /// GPS fix type (0x000320); 3 and above are usable.
    pub enum GpsFix: u8 {
        /// No GPS connected.
        NoGps = 0,
        /// No position.
        NoFix = 1,
        Fix2d = 2,
        Fix3d = 3,
        /// 3D with DGPS/SBAS.
        Dgps = 4,
        /// RTK float.
        RtkFloat = 5,
        /// RTK fixed.
        RtkFixed = 6,
        /// Static (base station).
        Static = 7,
        Ppp = 8,
    }
}

wire_struct! {
    Le;
    /// 0x000320, flight controller to camera: ask for the GPS position of the laser
    /// target, giving the aircraft's state.
    pub struct TargetGpsRequest {
        /// Mounts asked (bit n = mount n+1; default mount 1).
        pub mounts: u8,
        /// GPS fix type.
        pub fix: GpsFix,
        /// UTC, milliseconds since the Unix epoch.
        pub utc_ms: u64,
        /// Longitude, 1e-7 degree.
        pub lon_e7: i32,
        /// Latitude, 1e-7 degree.
        pub lat_e7: i32,
        /// Height relative to home, millimetres.
        pub rel_alt_mm: i32,
        /// Altitude, millimetres.
        pub alt_mm: i32,
        /// Aircraft yaw, 0.01°.
        pub yaw_cdeg: i16,
        /// Aircraft roll, 0.01°.
        pub roll_cdeg: i16,
        /// Aircraft pitch, 0.01°.
        pub pitch_cdeg: i16,
        /// Airspeed, cm/s.
        pub airspeed_cm_s: u16,
        /// Ground speed, cm/s.
        pub groundspeed_cm_s: u16,
        /// Heading, 0.01° (0..36000, 0 = north).
        pub heading_cdeg: u16,
        /// Throttle, 0.01 % (0..=10000).
        pub throttle_cpct: u16,
        /// Climb rate, cm/s.
        pub climb_cm_s: i16,
    }
}

wire_struct! {
    Le;
    /// ACK of 0x000320: the target's position.
    pub struct TargetGpsAck {
        /// Response code.
        pub code: ResponseCode,
        /// Mount (fixed 0x1F).
        pub mount: u8,
        /// UTC, milliseconds since the Unix epoch.
        pub utc_ms: u64,
        /// Longitude, 1e-7 degree.
        pub lon_e7: i32,
        /// Latitude, 1e-7 degree.
        pub lat_e7: i32,
        /// Height relative to home, millimetres.
        pub rel_alt_mm: i32,
        /// Altitude, millimetres.
        pub alt_mm: i32,
    }
}

wire_struct! {
    Le;
    /// 0x000324: track the target in a box (AI recognition must be on).
    pub struct TrackBox {
        /// Enable (1) or disable (2).
        pub enable: Toggle,
        /// Upper-left X, 0..=1920.
        pub x: u16,
        /// Upper-left Y, 0..=1080.
        pub y: u16,
        /// Width (x + width ≤ 1920).
        pub width: u16,
        /// Height (y + height ≤ 1080).
        pub height: u16,
        /// Reserved; kept as received, so the frame re-encodes as it came.
        pub reserved: u8,
    }
}
