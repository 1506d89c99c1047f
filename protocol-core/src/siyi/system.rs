//! System messages: heartbeat (0x00), firmware version (0x01), UTC time (0x30),
//! SD card format (0x48) and soft reboot (0x80). The hardware id (0x02) is
//! [`HardwareId`](super::HardwareId).

use super::payload::{FirmwareVersion, Payload, Trailing, optional, trailing_len};
use crate::wire::encoding::{Field, Le};
use crate::wire::{Reader, Writer};
use crate::{Error, Result};

wire_derive! {
    [Eq, Hash, Default]
    /// 0x00, TCP heartbeat (the document: no data and no ACK, TCP only). The document's
    /// own example frame carries one data byte 0x00, so both forms decode; the byte, if
    /// any, is kept.
    pub struct Heartbeat {
        /// The data byte, when the frame has one (0x00 in the document's example).
        pub byte: Option<u8>,
    }
}

impl Heartbeat {
    /// The heartbeat as the document prints it (`55 66 01 01 00 00 00 00 00 59 8B`).
    pub const DOCUMENT: Heartbeat = Heartbeat { byte: Some(0) };
}

impl Payload for Heartbeat {
    const MAX_LEN: usize = 1;

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

wire_derive! {
    [Eq, Hash, Default]
    /// Reply of 0x01: firmware versions. 12 bytes (camera, gimbal, zoom), or 8 bytes from
    /// models without a zoom module (A8 mini): `zoom` is then `None`, and the reply
    /// re-encodes to 8 bytes.
    pub struct FirmwareVersions {
        /// Camera firmware (`code_board_ver`).
        pub camera: FirmwareVersion,
        /// Gimbal firmware (`gimbal_firmware_ver`).
        pub gimbal: FirmwareVersion,
        /// Zoom firmware (`zoom_firmware_ver`), optical-zoom models only.
        pub zoom: Option<FirmwareVersion>,
    }
}

/// 0x01 reply without the zoom firmware.
const FIRMWARE_VERSIONS_MIN_LEN: usize = 8;

impl Payload for FirmwareVersions {
    const MAX_LEN: usize = 12;

    fn decode(data: &[u8]) -> Result<Self> {
        if data.len() != FIRMWARE_VERSIONS_MIN_LEN && data.len() != Self::MAX_LEN {
            return Err(Error::BadLength);
        }
        let mut r = Reader::new(data);
        let v = FirmwareVersions {
            camera: Field::<Le>::read(&mut r)?,
            gimbal: Field::<Le>::read(&mut r)?,
            zoom: optional(&mut r)?,
        };
        r.finish()?;
        Ok(v)
    }
    fn encoded_len(&self) -> usize {
        FIRMWARE_VERSIONS_MIN_LEN.saturating_add(trailing_len(&[(
            self.zoom.is_some(),
            <FirmwareVersion as Field<Le>>::LEN,
        )]))
    }
    fn encode(&self, w: &mut Writer<'_>) -> Result<()> {
        Field::<Le>::write(&self.camera, w)?;
        Field::<Le>::write(&self.gimbal, w)?;
        Trailing::new(w).field(self.zoom.as_ref())
    }
}

wire_struct! {
    Le;
    /// 0x30: set the camera's UTC time.
    pub struct UtcTime {
        /// Microseconds since 1970-01-01T00:00:00Z.
        pub unix_us: u64,
    }
}

wire_struct! {
    Le;
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

wire_struct! {
    Le;
    /// 0x80 request: soft reboot of camera and/or gimbal (the reply,
    /// [`SoftRebootAck`](super::SoftRebootAck), echoes what is done).
    pub struct SoftReboot {
        /// Camera reboot.
        pub camera: RebootAction,
        /// Gimbal reboot.
        pub gimbal: RebootAction,
    }
}
