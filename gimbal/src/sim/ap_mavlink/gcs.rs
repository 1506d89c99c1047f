//! The GCS link of the port (`GCS_MAVLINK`): what the loop reads and sends, and how it
//! routes a ground station's traffic.
//!
//! - **Streams.** Copter's defaults stream nothing to the port; Plane's 1 Hz
//!   ([`ApVehicle`]). MAV_CMD_SET_MESSAGE_INTERVAL to this system and component 1 sets
//!   the port's interval of a message (0 default, −1 stop), DENIED above 0.8 ×
//!   `SCHED_LOOP_RATE` ([`ApMavlinkConfig::loop_rate_hz`]). SYSTEM_TIME's Unix time is 0
//!   until the clock is set from GPS; GPS_RAW_INT's `time_usec` is the fix time since
//!   boot; GLOBAL_POSITION_INT is sent with or without a fix.
//! - **TIMESYNC** request every 10 s (tc1 0, ts1 boot ns + sysid); replies with that ts1
//!   are recorded. A request from the device (tc1 0, target 0 or this system and 0 or
//!   component 1) is answered in the loop that reads it, in that loop's burst, on this
//!   port: ts1 echoed, no target fields, tc1 = boot µs × 1000 of the UART's estimate of
//!   the request's start (ChibiOS `receive_time_constraint_us(len)`): the FC-clock
//!   timestamp of the last chunk the UART delivered, minus (len + the bytes still
//!   unread behind the request) × the byte time at [`ApMavlinkConfig::baud`] (10 bits,
//!   integer µs as ChibiOS computes it). `len` is the frame's length or GCS_Common's
//!   `PAYLOAD_SIZE(TIMESYNC)` ([`TimesyncLen`]). Every answer is recorded
//!   ([`ApMavlink::timesync_answers`]).
//! - **SYSTEM_TIME**: `time_unix_usec` (the FC's UTC, 0 until set) and `time_boot_ms`
//!   (boot µs / 1000, truncated) from one reading of the FC clock at composition.
//! - **Routing.** A ground station ([`Qgc`]) can be attached: the device's messages
//!   without a target, with target 0 or the ground station's system reach it; its
//!   messages for the device (or broadcast) go onto the port as they came. A ground app
//!   on another link ([`ApMavlink::ground`], e.g. MAVSDK over UDP) is routed the same way
//!   ([`crate::sim::ground`]); it gets the FC's HEARTBEAT at 1 Hz, and a command
//!   addressed to the FC itself is answered UNSUPPORTED (this simulator is no gimbal
//!   manager).

use protocol_core::mavlink::MavMessage;
use protocol_core::mavlink::dialect::{
    ATTITUDE_DATA, AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA, GLOBAL_POSITION_INT_DATA,
    GPS_RAW_INT_DATA, GpsFixType, MavAutopilot, MavCmd, MavLandedState, MavResult, MavType,
    MessageData as _, SYSTEM_TIME_DATA, TIMESYNC_DATA,
};

use super::{ApMavlink, ApVehicle, Heard, TIMESYNC_PAYLOAD_SIZE, TimesyncLen, announced};
use crate::sim::ground::Route;
use crate::sim::mav::{self, AUTOPILOT, AircraftState, CAMERA, GIMBAL, Rx, TimesyncAnswer};
use protocol_core::mavlink::Header;

impl ApMavlink {
    pub(super) fn default_streams(&mut self) {
        self.intervals.clear();
        self.next_due.clear();
        if self.config.vehicle == ApVehicle::Plane {
            for id in [
                SYSTEM_TIME_DATA::ID,
                GLOBAL_POSITION_INT_DATA::ID,
                ATTITUDE_DATA::ID,
                GPS_RAW_INT_DATA::ID,
            ] {
                self.intervals.insert(id, 1_000_000);
            }
        }
    }

    fn in_search_window(&self) -> bool {
        let uptime_ms = self.board.fc_ms();
        let armed = self
            .config
            .armed_at_us
            .is_some_and(|a| self.board.now_us() >= a);
        uptime_ms >= 10_000 && !(uptime_ms > 60_000 && armed)
    }

    /// The GCS receive processing: every byte the UART delivered so far.
    pub(super) fn gcs_receive(&mut self) {
        let chunks = std::mem::take(&mut self.uart);
        let Some(&(last_at, _)) = chunks.last() else {
            return;
        };
        // The UART's timestamp of the last chunk it delivered, on the FC clock.
        let stamp_us = self.board.fc_us(last_at);
        let bytes: Vec<u8> = chunks.into_iter().flat_map(|(_, b)| b).collect();
        for (r, after) in self.rx.push_counting(&bytes) {
            self.process(r, stamp_us, after);
        }
    }

    /// ChibiOS `receive_time_constraint_us(len)`: the UART's estimate (FC µs) of when a
    /// `len`-byte packet began, `after` bytes being still unread behind it.
    fn receive_time_constraint_us(&self, stamp_us: u64, len: usize, after: usize) -> u64 {
        // 10 bits a byte, in whole µs as the driver computes it.
        let byte_us = 10_000_000 / u64::from(self.config.baud.max(1));
        stamp_us.saturating_sub(byte_us * (len + after) as u64)
    }

    /// ArduPilot's HEARTBEAT: its vehicle type, autopilot ArduPilot.
    fn own_heartbeat(&self) -> MavMessage {
        let mavtype = match self.config.vehicle {
            ApVehicle::Copter => MavType::MAV_TYPE_QUADROTOR,
            ApVehicle::Plane => MavType::MAV_TYPE_FIXED_WING,
        };
        mav::autopilot_heartbeat(mavtype, MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA)
    }

    /// The GCS send processing: heartbeat, own TIMESYNC request, due streams.
    pub(super) fn update_send(&mut self) {
        let ms = self.board.fc_ms();
        if self.last_heartbeat_ms.is_none_or(|l| ms - l >= 1000) {
            self.last_heartbeat_ms = Some(ms);
            self.send(&self.own_heartbeat());
        }
        if self.last_timesync_ms.is_none_or(|l| ms - l >= 10_000) {
            self.last_timesync_ms = Some(ms);
            let ts1 = (self.board.fc_us(self.board.now_us()) * 1000 + u64::from(self.config.sysid))
                as i64;
            self.send(&MavMessage::TIMESYNC(TIMESYNC_DATA {
                tc1: 0,
                ts1,
                target_system: 0,
                target_component: 0,
            }));
        }
        self.streams();
    }

    fn streams(&mut self) {
        let fc_us = self.board.fc_us(self.board.now_us());
        let due: Vec<u32> = self
            .intervals
            .iter()
            .filter(|(id, _)| self.next_due.get(id).is_none_or(|&d| fc_us >= d))
            .map(|(id, _)| *id)
            .collect();
        for id in due {
            let interval = self.intervals[&id];
            let next = self.next_due.get(&id).copied().unwrap_or(fc_us) + interval;
            self.next_due.insert(
                id,
                if next <= fc_us {
                    fc_us + interval
                } else {
                    next
                },
            );
            if let Some(msg) = self.stream_message(id) {
                self.send(&msg);
            }
        }
    }

    /// The stream message `id` now.
    fn stream_message(&self, id: u32) -> Option<MavMessage> {
        let t = self.board.now_us();
        let fc_us = self.board.fc_us(t);
        let a = AircraftState::of(self.board.aircraft(), t, fc_us);
        let (lat, lon) = a.lat_lon_e7;
        let alt_mm = a.alt_mm;
        Some(match id {
            SYSTEM_TIME_DATA::ID => MavMessage::SYSTEM_TIME(SYSTEM_TIME_DATA {
                time_unix_usec: if self.board.utc_valid() {
                    self.board.clock().utc_us(t)
                } else {
                    0
                },
                time_boot_ms: a.boot_ms,
            }),
            GPS_RAW_INT_DATA::ID => MavMessage::GPS_RAW_INT(GPS_RAW_INT_DATA {
                // The last fix's time since boot (5 Hz GPS), not UTC.
                time_usec: fc_us / 200_000 * 200_000,
                lat,
                lon,
                alt: alt_mm,
                eph: 90,
                epv: 140,
                vel: (self.board.aircraft().speed_m_s * 100.0) as u16,
                cog: (self.board.aircraft().heading_deg * 100.0) as u16,
                fix_type: if self.config.gps_fix {
                    GpsFixType::GPS_FIX_TYPE_3D_FIX
                } else {
                    GpsFixType::GPS_FIX_TYPE_NO_FIX
                },
                satellites_visible: 14,
                alt_ellipsoid: alt_mm + 48_000,
                h_acc: 700,
                v_acc: 1200,
                vel_acc: 150,
                hdg_acc: 0,
                yaw: 0,
            }),
            GLOBAL_POSITION_INT_DATA::ID => a.global_position(
                ((self.board.aircraft().alt_msl_m - self.config.home_alt_m) * 1000.0) as i32,
            ),
            ATTITUDE_DATA::ID => a.attitude(),
            // AP_HAL::micros(): 32 bits.
            AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA::ID => a.autopilot_state(
                u64::from(fc_us as u32),
                0x01A7,
                self.config.sysid,
                MavLandedState::MAV_LANDED_STATE_UNDEFINED,
            ),
            _ => return None,
        })
    }

    /// `set_message_interval` on this port: the result.
    pub(super) fn set_interval(&mut self, id: u32, interval_us: f32) -> MavResult {
        let known = [
            SYSTEM_TIME_DATA::ID,
            GPS_RAW_INT_DATA::ID,
            ATTITUDE_DATA::ID,
            GLOBAL_POSITION_INT_DATA::ID,
            AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA::ID,
        ];
        if !known.contains(&id) {
            return MavResult::MAV_RESULT_UNSUPPORTED;
        }
        if interval_us < -0.5 {
            self.intervals.remove(&id);
        } else if interval_us < 0.5 {
            let plane = self.config.vehicle == ApVehicle::Plane
                && id != AUTOPILOT_STATE_FOR_GIMBAL_DEVICE_DATA::ID;
            if plane {
                self.intervals.insert(id, 1_000_000);
            } else {
                self.intervals.remove(&id);
            }
        } else {
            let hz = 1e6 / f64::from(interval_us);
            if hz > 0.8 * f64::from(self.loop_rate_hz()) {
                return MavResult::MAV_RESULT_DENIED;
            }
            self.intervals.insert(id, interval_us as u64);
            self.next_due.remove(&id);
        }
        MavResult::MAV_RESULT_ACCEPTED
    }

    /// Asks `target` for message `id` when a second (FC ms) has passed since `last_ms`;
    /// returns the instant of the last request.
    pub(super) fn ask_every_second(
        &mut self,
        last_ms: Option<u64>,
        id: u32,
        target: (u8, u8),
    ) -> Option<u64> {
        let ms = self.board.fc_ms();
        if last_ms.is_some_and(|l| ms - l < 1000) {
            return last_ms;
        }
        self.send(&mav::request_message(id, target));
        Some(ms)
    }

    /// A frame from the device, read in the loop at the board's time; `stamp_us` is the
    /// UART's timestamp of the last chunk, `after` the bytes unread behind the frame.
    fn process(&mut self, r: mav::Received, stamp_us: u64, after: usize) {
        let now_us = self.board.now_us();
        let h = r.header;
        let id = mav::id_of(&r.message);
        self.received.push((now_us, h, id));
        self.route_to_gcs(now_us, &r);
        match r.message {
            MavMessage::HEARTBEAT(hb) if self.in_search_window() => {
                self.discover(h, hb.mavtype);
            }
            MavMessage::GIMBAL_DEVICE_INFORMATION(info) => self.mount_information(h, info),
            MavMessage::GIMBAL_DEVICE_ATTITUDE_STATUS(s) => self.mount_status(h, s),
            MavMessage::CAMERA_INFORMATION(info) => self.camera_information(h, info),
            MavMessage::CAMERA_CAPTURE_STATUS(s) => {
                self.capture_req.1 = 0;
                self.capture_statuses.push(Heard::new(now_us, h, s));
            }
            MavMessage::CAMERA_IMAGE_CAPTURED(c) => self.images.push(Heard::new(now_us, h, c)),
            MavMessage::COMMAND_ACK(a) => self.acks.push(Heard::new(now_us, h, a)),
            MavMessage::COMMAND_LONG(c)
                if c.command == MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL
                    && c.target_system == self.config.sysid
                    && c.target_component == AUTOPILOT =>
            {
                let result = self.set_interval(c.param1 as u32, c.param2);
                self.send(&mav::command_ack(c.command, result, &h));
            }
            MavMessage::TIMESYNC(t)
                if t.tc1 == 0
                    && (t.target_system == 0 || t.target_system == self.config.sysid)
                    && (t.target_component == 0 || t.target_component == AUTOPILOT) =>
            {
                let len = match self.config.timesync_len {
                    TimesyncLen::Frame => r.bytes.len(),
                    TimesyncLen::PayloadSize => TIMESYNC_PAYLOAD_SIZE,
                };
                let rx_us = self.receive_time_constraint_us(stamp_us, len, after);
                let tc1 = (rx_us * 1000) as i64;
                self.send(&MavMessage::TIMESYNC(TIMESYNC_DATA {
                    tc1,
                    ts1: t.ts1,
                    target_system: 0,
                    target_component: 0,
                }));
                if let Some(sent_at_us) = self.board.last_burst_at() {
                    self.timesync_answers.push(TimesyncAnswer {
                        from: h,
                        handled_at_us: now_us,
                        sent_at_us,
                        ts1: t.ts1,
                        tc1,
                        target: (0, 0),
                    });
                }
            }
            MavMessage::TIMESYNC(t) if t.tc1 != 0 => {
                let mine = self
                    .sent
                    .iter()
                    .any(|(_, m)| matches!(m, MavMessage::TIMESYNC(s) if s.ts1 == t.ts1));
                if mine {
                    self.timesync_replies.push((now_us, t.tc1));
                }
            }
            _ => {}
        }
    }

    /// A HEARTBEAT in the drivers' search window: the gimbal (type 26 from component 154)
    /// or the camera (type 30 from component 100) found, when the driver is configured
    /// and has found none yet.
    fn discover(&mut self, h: Header, mavtype: MavType) {
        let gimbal = (MavType::MAV_TYPE_GIMBAL, GIMBAL);
        if let Some(system) = announced(self.mount_found, &h, mavtype, gimbal)
            && self.config.mount
        {
            self.mount_found = Some(system);
            self.mount_found_at_us = Some(self.board.now_us());
        }
        let camera = (MavType::MAV_TYPE_CAMERA, CAMERA);
        if let Some(system) = announced(self.camera_found, &h, mavtype, camera)
            && self.config.camera
        {
            self.camera_found = Some(system);
        }
    }

    /// The ground app's frames, routed; the FC's HEARTBEAT to it every second.
    pub(super) fn ground_run(&mut self) {
        let Some(mut g) = self.ground.take() else {
            return;
        };
        for f in g.take() {
            let route = Route::of(&f, self.config.sysid);
            if route.forward && !self.board.is_off() {
                self.board
                    .write_loop(f.bytes.clone(), self.config.jitter_us);
            }
            if let (true, Some(MavMessage::COMMAND_LONG(c))) = (route.local, &f.message)
                && c.target_component == AUTOPILOT
            {
                let ack = mav::command_ack(c.command, MavResult::MAV_RESULT_UNSUPPORTED, &f.header);
                g.send(&ack);
            }
        }
        let ms = self.board.fc_ms();
        if self.ground_heartbeat_ms.is_none_or(|l| ms - l >= 1000) {
            self.ground_heartbeat_ms = Some(ms);
            g.send(&self.own_heartbeat());
        }
        self.ground = Some(g);
    }

    /// ArduPilot's routing towards the ground station: messages without a target, with
    /// target system 0 or the ground station's system.
    fn route_to_gcs(&mut self, now_us: u64, r: &mav::Received) {
        if let Some(g) = self.ground.as_mut() {
            g.forward(&r.message, &r.bytes);
        }
        let Some(gcs) = self.gcs.as_mut() else {
            return;
        };
        if mav::routed_to(&r.message, gcs.config.sysid) {
            gcs.receive(now_us, r.header, &r.message);
        }
    }

    /// The ground station's frame onto the device's port when it is for the device (its
    /// system, or broadcast), as it came.
    pub(super) fn route_from_gcs(&mut self, frame: Vec<u8>) {
        let mut rx = Rx::default();
        let Some(r) = rx.push(&frame).pop() else {
            return;
        };
        let for_device = match mav::target_of(&r.message) {
            None => true,
            Some((sys, comp)) => sys == 0 || (sys == self.config.sysid && comp != AUTOPILOT),
        };
        if for_device && !self.board.is_off() {
            self.board.write_loop(frame, self.config.jitter_us);
        }
    }
}
