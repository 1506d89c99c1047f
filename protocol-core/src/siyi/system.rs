//! System messages: heartbeat (0x00), firmware version (0x01), UTC time (0x30),
//! SD card format (0x48) and soft reboot (0x80). The hardware id (0x02) is
//! [`HardwareId`](super::HardwareId).

use super::Payload;
use super::field::{FirmwareVersion, Trailing, optional, trailing_len};
use crate::wire::{Reader, Writer};
use crate::{Error, Result};

/// 0x00, TCP heartbeat (the document: no data and no ACK, TCP only). The document's
/// own example frame carries one data byte 0x00, so both forms decode; the byte, if
/// any, is kept.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Heartbeat {
    /// The data byte, when the frame has one (0x00 in the document's example).
    pub byte: Option<u8>,
}

impl Heartbeat {
    /// The heartbeat as the document prints it (`55 66 01 01 00 00 00 00 00 59 8B`).
    pub const DOCUMENT: Heartbeat = Heartbeat { byte: Some(0) };
}

impl Payload for Heartbeat {
    fn decode(data: &[u8]) -> Result<Self> {
        match data {
            [] => Ok(Heartbeat { byte: None }),
            [b] => Ok(Heartbeat { byte: Some(*b) }),
            _ => Err(Error::BadLength),
        }
    }
    fn encoded_len(&self) -> usize {
        usize::from(self.byte.is_some())
    }
    fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
        match self.byte {
            Some(b) => w.u8(b),
            None => Ok(()),
        }
    }
}

/// Reply of 0x01: firmware versions. 12 bytes (camera, gimbal, zoom), or 8 bytes from
/// models without a zoom module (A8 mini): `zoom` is then `None`, and the reply
/// re-encodes to 8 bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FirmwareVersions {
    /// Camera firmware (`code_board_ver`).
    pub camera: FirmwareVersion,
    /// Gimbal firmware (`gimbal_firmware_ver`).
    pub gimbal: FirmwareVersion,
    /// Zoom firmware (`zoom_firmware_ver`), optical-zoom models only.
    pub zoom: Option<FirmwareVersion>,
}

impl Payload for FirmwareVersions {
    fn decode(data: &[u8]) -> Result<Self> {
        if data.len() != 8 && data.len() != 12 {
            return Err(Error::BadLength);
        }
        let mut r = Reader::new(data);
        let v = FirmwareVersions {
            camera: super::field::Field::<crate::wire::encoding::Le>::read(&mut r)?,
            gimbal: super::field::Field::<crate::wire::encoding::Le>::read(&mut r)?,
            zoom: optional(&mut r)?,
        };
        r.finish()?;
        Ok(v)
    }
    fn encoded_len(&self) -> usize {
        8usize.saturating_add(trailing_len(&[(self.zoom.is_some(), 4)]))
    }
    fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
        super::field::Field::<crate::wire::encoding::Le>::write(&self.camera, w)?;
        super::field::Field::<crate::wire::encoding::Le>::write(&self.gimbal, w)?;
        Trailing::new(w).field(&self.zoom)
    }
}

payload! {
    /// 0x30: set the camera's UTC time.
    pub struct UtcTime {
        /// Microseconds since 1970-01-01T00:00:00Z.
        pub unix_us: u64,
    }
}

payload! {
    /// Reply of 0x30.
    pub struct TimeAck {
        /// Result (1 = success).
        pub result: i8,
    }
}

code_enum! {
    /// Action of one 0x80 field.
    pub enum RebootAction: u8 {
        /// 0: no action.
        None = 0,
        /// 1: reboot.
        Reboot = 1,
    }
}

payload! {
    /// 0x80 request and reply: soft reboot of camera and/or gimbal (the reply echoes
    /// what is done).
    pub struct SoftReboot {
        /// Camera reboot.
        pub camera: RebootAction,
        /// Gimbal reboot.
        pub gimbal: RebootAction,
    }
}
