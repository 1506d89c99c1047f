//! Gimbal messages: rotation and centring (0x07, 0x08), configuration and mode (0x0A,
//! 0x19), attitude and angles (0x0D, 0x0E, 0x26, 0x41), data streams (0x24, 0x25) and
//! the flight controller's attitude and position (0x22, 0x3E).
//!
//! Angles are i16 in 0.1° (`_deg_x10`), rates in 0.1 °/s (`_dps_x10`), in the SIYI
//! convention (ArduPilot negates yaw and yaw rate when it reads 0x0D).

use super::payload::{OnOff, Payload, Trailing, optional, trailing_len};
use crate::wire::encoding::{Field, Le};
use crate::wire::{Reader, Writer};
use crate::{Error, Result};

wire_struct! {
    Le;
    /// 0x07: rotate at a speed (-100..=100 each; 0 stops). Yaw positive to the right,
    /// pitch positive up.
    pub struct GimbalRotation {
        /// Yaw speed, -100..=100.
        pub yaw: i8,
        /// Pitch speed, -100..=100.
        pub pitch: i8,
    }
}

code_enum! {
    /// Position of 0x08.
    pub enum CenterPosition: u8 {
        /// 1: one-key centre.
        OneKeyCenter = 1,
        /// 2: centre and look down.
        CenterDown = 2,
        /// 3: centre.
        Center = 3,
        /// 4: look down.
        Down = 4,
    }
}

wire_struct! {
    Le;
    /// 0x08: centre the gimbal.
    pub struct Center {
        /// Where to.
        pub position: CenterPosition,
    }
}

code_enum! {
    /// Recording state (0x0A).
    pub enum RecordStatus: u8 {
        /// 0: not recording.
        Off = 0,
        /// 1: recording.
        On = 1,
        /// 2: no TF card.
        NoCard = 2,
        /// 3: recording, with data loss (check the TF card).
        DataLoss = 3,
    }
}

code_enum! {
    /// Motion mode (0x0A, 0x19).
    pub enum MotionMode: u8 {
        /// 0: lock (all axes earth frame).
        Lock = 0,
        /// 1: follow (yaw follows the aircraft).
        Follow = 1,
        /// 2: FPV (all axes body frame).
        Fpv = 2,
    }
}

code_enum! {
    /// Mounting direction (0x0A).
    pub enum MountDirection: u8 {
        /// 0: reserved.
        Reserved = 0,
        /// 1: normal.
        Normal = 1,
        /// 2: upside down.
        UpsideDown = 2,
    }
}

code_enum! {
    /// Video output (0x0A; ZT6, A8 mini).
    pub enum VideoOutput: u8 {
        /// 0: HDMI on, CVBS off.
        Hdmi = 0,
        /// 1: HDMI off, CVBS on.
        Cvbs = 1,
    }
}

wire_derive! {
    [Eq, Hash, Default]
    /// Reply of 0x0A: gimbal configuration. 8 bytes in full; models send 5 to 8, so the
    /// trailing fields are optional (`None` from the first missing one on) and the reply
    /// re-encodes to the length it was decoded from. Encoding a `Some` after a `None` is
    /// [`Error::OutOfRange`].
    pub struct GimbalConfig {
        /// Byte 0, reserved.
        pub reserved0: u8,
        /// Byte 1, HDR state.
        pub hdr: OnOff,
        /// Byte 2, reserved.
        pub reserved2: u8,
        /// Byte 3, recording state.
        pub record: RecordStatus,
        /// Byte 4, motion mode.
        pub motion: MotionMode,
        /// Byte 5, mounting direction.
        pub mount: Option<MountDirection>,
        /// Byte 6, video output.
        pub video_output: Option<VideoOutput>,
        /// Byte 7, zoom linkage.
        pub zoom_linkage: Option<u8>,
    }
}

impl GimbalConfig {
    /// Shortest layout.
    pub const MIN_LEN: usize = 5;
    /// Full layout.
    pub const MAX_LEN: usize = 8;
}

impl Payload for GimbalConfig {
    const MAX_LEN: usize = GimbalConfig::MAX_LEN;

    fn decode(data: &[u8]) -> Result<Self> {
        if !(Self::MIN_LEN..=Self::MAX_LEN).contains(&data.len()) {
            return Err(Error::BadLength);
        }
        let mut r = Reader::new(data);
        let v = GimbalConfig {
            reserved0: Field::<Le>::read(&mut r)?,
            hdr: Field::<Le>::read(&mut r)?,
            reserved2: Field::<Le>::read(&mut r)?,
            record: Field::<Le>::read(&mut r)?,
            motion: Field::<Le>::read(&mut r)?,
            mount: optional(&mut r)?,
            video_output: optional(&mut r)?,
            zoom_linkage: optional(&mut r)?,
        };
        r.finish()?;
        Ok(v)
    }
    fn encoded_len(&self) -> usize {
        Self::MIN_LEN.saturating_add(trailing_len(&[
            (self.mount.is_some(), 1),
            (self.video_output.is_some(), 1),
            (self.zoom_linkage.is_some(), 1),
        ]))
    }
    fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
        Field::<Le>::write(&self.reserved0, w)?;
        Field::<Le>::write(&self.hdr, w)?;
        Field::<Le>::write(&self.reserved2, w)?;
        Field::<Le>::write(&self.record, w)?;
        Field::<Le>::write(&self.motion, w)?;
        let mut t = Trailing::new(w);
        t.field(self.mount.as_ref())?;
        t.field(self.video_output.as_ref())?;
        t.field(self.zoom_linkage.as_ref())
    }
}

wire_struct! {
    Le;
    /// Reply of 0x0D (also pushed at the rate set by 0x25): attitude and rates.
    pub struct GimbalAttitude {
        /// Yaw, 0.1°.
        pub yaw_deg_x10: i16,
        /// Pitch, 0.1°.
        pub pitch_deg_x10: i16,
        /// Roll, 0.1°.
        pub roll_deg_x10: i16,
        /// Yaw rate, 0.1 °/s.
        pub yaw_rate_dps_x10: i16,
        /// Pitch rate, 0.1 °/s.
        pub pitch_rate_dps_x10: i16,
        /// Roll rate, 0.1 °/s.
        pub roll_rate_dps_x10: i16,
    }
}

wire_struct! {
    Le;
    /// 0x0E: go to angles (yaw -135.0..=135.0°, pitch -90.0..=25.0°).
    pub struct SetAngles {
        /// Target yaw, 0.1°.
        pub yaw_deg_x10: i16,
        /// Target pitch, 0.1°.
        pub pitch_deg_x10: i16,
    }
}

wire_struct! {
    Le;
    /// Three angles: the layout of [`SetAnglesAck`](super::SetAnglesAck) (0x0E) and
    /// [`SingleAxisAngleAck`](super::SingleAxisAngleAck) (0x41), the current attitude, and of
    /// [`MagneticEncoder`](super::MagneticEncoder) (0x26 reply), the magnetic encoder angles.
    pub struct Angles {
        /// Yaw, 0.1°.
        pub yaw_deg_x10: i16,
        /// Pitch, 0.1°.
        pub pitch_deg_x10: i16,
        /// Roll, 0.1°.
        pub roll_deg_x10: i16,
    }
}

wire_struct! {
    Le;
    /// Reply of 0x19: the motion mode.
    pub struct GimbalMode {
        /// Lock, follow or FPV.
        pub mode: MotionMode,
    }
}

wire_struct! {
    Le, float;
    /// 0x22: the flight controller's attitude, sent to the gimbal (no reply).
    pub struct FcAttitude {
        /// Milliseconds since the flight controller booted.
        pub time_boot_ms: u32,
        /// Roll, radians (-pi..pi).
        pub roll_rad: f32,
        /// Pitch, radians (-pi/2..pi/2).
        pub pitch_rad: f32,
        /// Yaw, radians (-pi..pi).
        pub yaw_rad: f32,
        /// Roll rate, rad/s.
        pub roll_rate_rad_s: f32,
        /// Pitch rate, rad/s.
        pub pitch_rate_rad_s: f32,
        /// Yaw rate, rad/s.
        pub yaw_rate_rad_s: f32,
    }
}

code_enum! {
    /// Output rate of a data stream (0x24, 0x25).
    pub enum StreamFrequency: u8 {
        /// 0: off.
        Off = 0,
        /// 1: 2 Hz.
        Hz2 = 1,
        /// 2: 4 Hz.
        Hz4 = 2,
        /// 3: 5 Hz.
        Hz5 = 3,
        /// 4: 10 Hz.
        Hz10 = 4,
        /// 5: 20 Hz.
        Hz20 = 5,
        /// 6: 50 Hz.
        Hz50 = 6,
        /// 7: 100 Hz.
        Hz100 = 7,
    }
}

code_enum! {
    /// Data the gimbal asks the flight controller for (0x24).
    pub enum FcDataType: u8 {
        /// 1: attitude (0x22).
        Attitude = 1,
        /// 2: RC channels (not used yet).
        RcChannels = 2,
    }
}

wire_struct! {
    Le;
    /// 0x24: the gimbal asks the flight controller for a data stream.
    pub struct FcStreamRequest {
        /// Attitude or RC channels.
        pub data_type: FcDataType,
        /// Off, or 2..100 Hz.
        pub frequency: StreamFrequency,
    }
}

wire_struct! {
    Le;
    /// Reply of 0x24.
    pub struct FcStreamAck {
        /// Attitude or RC channels.
        pub data_type: FcDataType,
    }
}

code_enum! {
    /// Data the gimbal is asked to push (0x25).
    pub enum GimbalDataType: u8 {
        /// 1: attitude (0x0D).
        Attitude = 1,
        /// 2: laser distance (0x15; ZT30).
        Laser = 2,
        /// 3: magnetic encoder angles (0x26).
        MagneticEncoder = 3,
        /// 4: motor voltage.
        MotorVoltage = 4,
    }
}

wire_struct! {
    Le;
    /// 0x25: ask the gimbal to push a data stream.
    pub struct GimbalStreamRequest {
        /// Attitude, laser distance, magnetic encoder angles or motor voltage.
        pub data_type: GimbalDataType,
        /// Off, or 2..100 Hz.
        pub frequency: StreamFrequency,
    }
}

wire_struct! {
    Le;
    /// Reply of 0x25.
    pub struct GimbalStreamAck {
        /// Attitude, laser distance, magnetic encoder angles or motor voltage.
        pub data_type: GimbalDataType,
    }
}

wire_struct! {
    Le;
    /// 0x3E: the flight controller's position and velocity, sent to the gimbal (no
    /// reply).
    pub struct FcPosition {
        /// Milliseconds since the flight controller booted.
        pub time_boot_ms: u32,
        /// Latitude, 1e-7 degree.
        pub lat_e7: i32,
        /// Longitude, 1e-7 degree.
        pub lon_e7: i32,
        /// Altitude above mean sea level, cm.
        pub alt_msl_cm: i32,
        /// Altitude above the WGS84 ellipsoid, cm.
        pub alt_ellipsoid_cm: i32,
        /// Velocity north, mm/s.
        pub vel_north_mm_s: i32,
        /// Velocity east, mm/s.
        pub vel_east_mm_s: i32,
        /// Velocity down, mm/s.
        pub vel_down_mm_s: i32,
    }
}

code_enum! {
    /// Axis of 0x41.
    pub enum Axis: u8 {
        /// 0: yaw.
        Yaw = 0,
        /// 1: pitch.
        Pitch = 1,
    }
}

wire_struct! {
    Le;
    /// 0x41: move one axis to an angle (A8 mini).
    pub struct SingleAxisAngle {
        /// Target angle, 0.1°.
        pub angle_deg_x10: i16,
        /// Yaw or pitch.
        pub axis: Axis,
    }
}
