//! The pod's settings as the MAVLink side reaches them: a setting request sent as it is
//! (the K40T codec types every set command) and tracked for its ACK like any other
//! setting, and the all-settings queries (0x000100 infrared, 0x000200 visible) whose ACKs
//! fill [`PodState::ir_params`](super::PodState::ir_params) and
//! [`PodState::visible_params`](super::PodState::visible_params).

use super::PodDriver;
use crate::Outputs;
use crate::time::Instant;
use protocol_core::k40t::{IrParamsQuery, Request, VisibleParamsQuery};

impl PodDriver {
    /// Sends a setting (or a one-off camera request such as 0x00030D) and tracks it for
    /// its ACK; returns its base id. Settings are idempotent: retried as the driver
    /// retries settings.
    pub(crate) fn send_setting(
        &mut self,
        now: Instant,
        request: Request,
        out: &mut Outputs,
    ) -> u16 {
        let base = request.base();
        self.send_tracked(now, request, out);
        base
    }

    /// Asks for every infrared (0x000100) and/or visible-camera (0x000200) setting.
    pub(crate) fn query_settings(
        &mut self,
        now: Instant,
        ir: bool,
        visible: bool,
        out: &mut Outputs,
    ) {
        if ir {
            let q = Request::IrParams(IrParamsQuery {
                command: 1,
                reserved: 0,
            });
            self.send_tracked(now, q, out);
        }
        if visible {
            let q = Request::VisibleParams(VisibleParamsQuery {
                command: 1,
                reserved: 0,
            });
            self.send_tracked(now, q, out);
        }
    }
}
