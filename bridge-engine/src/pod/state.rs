//! The state cache: what the bridge knows of the pod ([`PodState`]), which the FC sides
//! answer from at once.

use crate::gimbal::{GimbalMode, View};
use crate::time::Instant;
use protocol_core::k40t::{
    FormatState, GimbalAttitude, GimbalStatus, GimbalVersionAck, ImageMode, IrParams, IrStatus,
    PhotoState, RecordState, SystemStatus, TargetGpsAck, TrackBox, Version, VisibleParams,
    VisibleStatus, ZoomState,
};

protocol_core::wire_derive! {
    custom_serde [Eq, Default]
    /// What the bridge knows of the pod, from its reports, status frames and ACKs.
    pub struct PodState {
        /// Reports arrive.
        pub link: bool,
        /// The last attitude report (0x000002) and when it came.
        pub attitude: Option<(GimbalAttitude, Instant)>,
        /// The last gimbal status (0x000001).
        pub gimbal_status: Option<GimbalStatus>,
        /// The last camera system status (0x000003): streamed image, SD card.
        pub system: Option<SystemStatus>,
        /// The last infrared measurements (0x000004) and when they came.
        pub ir: Option<(IrStatus, Instant)>,
        /// The last visible camera status (0x000005): zoom ratio, focus.
        pub visible: Option<VisibleStatus>,
        /// The last laser distance (0.1 m, 0 = none) and when it came.
        pub laser_dm: Option<(u16, Instant)>,
        /// Recording, from the 0x020303 status frames (1 Hz while recording) or the ACK of
        /// the last record command.
        pub recording: Option<RecordState>,
        /// The last photo progress (0x020302).
        pub photo: Option<PhotoState>,
        /// Zooming (0x020304).
        pub zoom: Option<ZoomState>,
        /// Gimbal versions (ACK of 0x000018).
        pub gimbal_version: Option<GimbalVersionAck>,
        /// Camera version (ACK of 0x000317).
        pub camera_version: Option<Version>,
        /// The yaw behaviour the FC last asked for (the K40T has no such setting: kept for
        /// the FC sides to report).
        pub mode: Option<GimbalMode>,
        /// The continuous ranging the bridge last switched on.
        pub ranging: bool,
        /// The pod acknowledged AI recognition on (0x000319), which its box tracking needs.
        pub ai: bool,
        /// Every infrared setting: the last OK ACK of 0x000100 (asked by the MAVLink side).
        pub ir_params: Option<IrParams>,
        /// Every visible-camera setting: the last OK ACK of 0x000200.
        pub visible_params: Option<VisibleParams>,
        /// The last SD card formatting progress (0x02030D status frames).
        pub format: Option<FormatState>,
        /// The pod's IP address (ACK of 0x000312, asked at every link-up; kept while the
        /// link is down, replaced at the next answer).
        pub ip: Option<[u8; 4]>,
        /// The box the pod acknowledged tracking (0x000324 on; `None`: not tracking, after
        /// its ACK of "off", the bridge's own "off" before it moved the gimbal, or a lost
        /// link).
        pub track: Option<TrackBox>,
        /// The laser target's position (ACK of 0x000320 with code OK) and when it came.
        pub target: Option<(TargetGpsAck, Instant)>,
        /// The IR digital zoom the pod acknowledged (0x000105, 1..=8).
        pub ir_zoom: Option<u8>,
        /// The pod's IR camera measures temperatures: it sent 0x000004 since its link came
        /// up, first at this instant.
        pub ir_first: Option<Instant>,
    }
}

impl PodState {
    /// Recording now: the last record status (or ACK) says so.
    #[must_use]
    pub fn is_recording(&self) -> bool {
        matches!(
            self.recording,
            Some(RecordState::Recording | RecordState::TimeLapse | RecordState::TimeLapseWaiting)
        )
    }

    /// The hybrid zoom ratio times ten the pod last reported (1x when unknown).
    #[must_use]
    pub fn zoom_x10(&self) -> u16 {
        self.visible.map_or(10, |v| v.zoom_x10.max(10))
    }

    /// The streamed view, from the system status.
    #[must_use]
    pub fn view(&self) -> Option<View> {
        self.system.map(|s| match s.stream {
            ImageMode::Infrared => View::Thermal,
            ImageMode::Split => View::Split,
            _ => View::Visible,
        })
    }
}
