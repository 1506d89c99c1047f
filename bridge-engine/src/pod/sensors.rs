//! What the driver asks of the pod's sensors for the FC sides: its IP address (the video
//! stream's, 0x000312), the laser target's position (0x000320), and the end of box
//! tracking before the bridge moves the gimbal itself (0x000324 off); with what their ACKs
//! carry into [`PodState`](super::PodState).

use super::PodDriver;
use crate::Outputs;
use crate::event::Event;
use crate::fixes::Fix;
use crate::time::{Duration, Instant};
use protocol_core::k40t::{
    AckCode, GpsFix, IpQuery, Request, TargetGpsAck, TargetGpsRequest, Toggle, TrackBox,
};

/// The IP query is asked again this long after it got no answer.
const IP_RETRY: Duration = Duration::from_secs(10);

impl PodDriver {
    /// Asks the pod's IP address (K40T external protocol, 3.2.4.17); asked again every
    /// [`IP_RETRY`] until it is answered.
    pub(super) fn query_ip(&mut self, now: Instant, out: &mut Outputs) {
        let q = Request::GetIp(IpQuery {
            command: 1,
            reserved: 0,
        });
        self.send_tracked(now, q, out);
        self.ip_retry = Some(now.saturating_add(IP_RETRY));
    }

    /// Asks the laser target's position (K40T external protocol, 3.2.4.24), giving the
    /// aircraft's state as its fix `f` says (a fix is a 3D GPS fix), with the UTC of the
    /// fix (0: unknown). Airspeed and throttle, which the bridge does not know, are 0.
    #[cfg_attr(not(any(feature = "mavlink", feature = "gcu")), allow(dead_code))]
    pub(crate) fn request_target(&mut self, now: Instant, f: &Fix, utc_ms: u64, out: &mut Outputs) {
        let v = f.velocity.unwrap_or_default();
        // The ground speed as max + 3/8 min of the two components (within 7 %: no square
        // root in core).
        let (n, e) = (
            i32::from(v.north_cm_s).unsigned_abs(),
            i32::from(v.east_cm_s).unsigned_abs(),
        );
        let ground = n.max(e).saturating_add(n.min(e).saturating_mul(3) / 8);
        let request = TargetGpsRequest {
            mounts: 1,
            fix: GpsFix::Fix3d,
            utc_ms,
            lon_e7: f.lon_e7,
            lat_e7: f.lat_e7,
            rel_alt_mm: i32::from(f.rel_alt_dm).saturating_mul(100),
            alt_mm: i32::from(f.alt_msl_dm).saturating_mul(100),
            yaw_cdeg: f.yaw_cdeg,
            roll_cdeg: f.roll_cdeg,
            pitch_cdeg: f.pitch_cdeg,
            airspeed_cm_s: 0,
            groundspeed_cm_s: u16::try_from(ground).unwrap_or(u16::MAX),
            heading_cdeg: u16::try_from(i32::from(f.yaw_cdeg).rem_euclid(36_000)).unwrap_or(0),
            throttle_cpct: 0,
            climb_cm_s: v.down_cm_s.saturating_neg(),
        };
        self.send_tracked(now, Request::TargetGps(request), out);
    }

    /// Ends the pod's box tracking before the bridge moves the gimbal itself: "when you
    /// control the gimbal yourself, you must send a shutdown command to put the gimbal
    /// into normal mode" (K40T external protocol, 3.2.4.25).
    pub(super) fn end_tracking(&mut self, now: Instant, out: &mut Outputs) {
        if self.state.track.take().is_some() {
            let off = Request::TrackBox(TrackBox {
                enable: Toggle::Off,
                x: 0,
                y: 0,
                width: 0,
                height: 0,
                reserved: 0,
            });
            self.send_tracked(now, off, out);
        }
    }

    /// What an ACK with `code` of an outstanding `request` tells of the sensors.
    pub(super) fn sensor_acked(&mut self, request: Request, code: AckCode) {
        match request {
            Request::TrackBox(b) if code == AckCode::Ok => {
                self.state.track = (b.enable == Toggle::On).then_some(b);
            }
            Request::IrDigitalZoom(z) if code == AckCode::Ok => {
                self.state.ir_zoom = Some(z.zoom_x);
            }
            Request::GetIp(_) => self.ip_retry = None,
            _ => {}
        }
    }

    /// The pod's IP address (taken whoever asked), and an event when it is new.
    pub(super) fn ip_answered(&mut self, code: AckCode, address: [u8; 4], out: &mut Outputs) {
        if code == AckCode::Ok && address != [0; 4] {
            if self.state.ip != Some(address) {
                out.event(Event::PodIp { address });
            }
            self.state.ip = Some(address);
            self.ip_retry = None;
        }
    }

    /// The laser target's position, when the pod gave one.
    pub(super) fn target_answered(&mut self, now: Instant, ack: TargetGpsAck) {
        let code = ack.code.code();
        self.state.target =
            (code == AckCode::Ok && (ack.lat_e7, ack.lon_e7) != (0, 0)).then_some((ack, now));
    }
}
