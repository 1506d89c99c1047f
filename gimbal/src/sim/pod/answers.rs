//! What the pod does with a request (`execute`), the data of its ACKs, its periodic
//! reports.

use super::*;

/// Base ids of the periodic reports, in [`ReportPeriods`] order.
pub(super) const REPORT_IDS: [u16; 5] = [0x0001, 0x0002, 0x0003, 0x0004, 0x0005];

impl SimPod {
    /// Executes a request: `Ok(None)` bare OK, `Ok(Some(payload))` OK with the ACK's
    /// whole payload, `Err(code)` refused.
    pub(super) fn execute(
        &mut self,
        t: u64,
        request: Request,
        start_us: u64,
    ) -> Result<Option<Vec<u8>>, AckCode> {
        let motion_blocked = self.camera.track.is_some() && self.config.track_blocks_motion;
        match request {
            Request::GimbalControl(c) => {
                self.motion(t, MotionCommand::Control(c), motion_blocked);
                if !motion_blocked {
                    self.gimbal_control(c);
                }
            }
            Request::GimbalAngle(a) => {
                self.motion(t, MotionCommand::Angle(a), motion_blocked);
                if !motion_blocked {
                    self.gimbal_angle(a);
                }
            }
            Request::DialSpeed(d) => {
                self.motion(t, MotionCommand::DialSpeed(d), false);
                self.pitch_dial_x5 = d.pitch_dps_x5.clamp(5, 150);
                self.yaw_dial_x5 = d.yaw_dps_x5.clamp(5, 150);
            }
            Request::PointToAim(p) => {
                self.motion(t, MotionCommand::PointToAim(p), motion_blocked);
                if !motion_blocked {
                    self.point_to_aim(p);
                }
            }
            Request::ServoOff(_) => {
                self.motion(t, MotionCommand::ServoOff, false);
                self.yaw.motion = AxisMotion::Hold;
                self.pitch.motion = AxisMotion::Hold;
            }
            Request::Stabilization(s) => self.stabilization = s.enable == OnOff::On,
            Request::GimbalVersion(_) => {
                return Ok(Some(payload(&GimbalVersionAck {
                    code: ResponseCode::OK,
                    hardware: self.config.gimbal_hardware,
                    software: self.config.gimbal_software,
                    reserved: 0,
                })));
            }
            Request::IrParams(_) => return Ok(Some(payload(&self.ir_params()))),
            Request::IrPalette(p) => self.camera.palette = p.palette,
            Request::IrMeasurement(m) => self.camera.ir_measuring = m.switch == MeasureSwitch::On,
            Request::VisibleParams(_) => return Ok(Some(payload(&self.visible_params()))),
            Request::Ev(e) => self.camera.ev = e.ev,
            Request::AeLock(l) => self.camera.ae_lock = l.lock,
            Request::CaptureMode(m) => self.camera.mode = m.mode,
            Request::PhotoParams(p) => {
                self.camera.photo_mode = p.mode;
                self.camera.timelapse_s = p.timelapse_s;
                self.camera.burst_count = p.burst_count;
            }
            Request::TakePhoto(p) => return self.take_photo(t, p).map(|()| None),
            Request::Record(r) => return self.record(t, r).map(|()| None),
            Request::HybridZoom(z) => {
                let (min, max) = self.zoom_limits();
                let target = f64::from(z.zoom_x10).clamp(min, max);
                self.zoom_to(target, true);
                self.deferred.push(message(&ZoomStatus {
                    state: ZoomState::Zooming,
                    reserved: 0,
                }));
                let after_ack = t.saturating_add(self.config.ack_delay_us);
                let reach = self.zoom_reach_us(target);
                self.zoom_status_due =
                    Some(after_ack.saturating_add(ZOOM_STATUS_PERIOD_US.min(reach.max(1))));
            }
            Request::ContinuousZoom(c) => self.continuous_zoom(c.control),
            Request::StreamBitrate(b) => self.camera.bitrate = b.bitrate,
            Request::OutputCodec(c) => self.camera.codec = c.codec,
            Request::ImageMode(m) => self.camera.image_mode = m.mode,
            Request::TimeSync(s) => self.time_sync(t, s, start_us),
            Request::GetIp(_) => {
                let [address, netmask, gateway] = self.config.ip;
                return Ok(Some(payload(&IpConfigAck {
                    code: ResponseCode::OK,
                    address,
                    netmask,
                    gateway,
                })));
            }
            Request::Focus(f) => self.focus(t, f.mode),
            Request::CameraVersion(_) => {
                return Ok(Some(payload(&CameraVersionAck {
                    code: ResponseCode::OK,
                    version: self.config.camera_version,
                })));
            }
            Request::AiRecognition(a) => {
                self.camera.ai = a.enable == Toggle::On;
            }
            // "The GPS information of the current laser aiming target": none without a
            // laser distance.
            Request::TargetGps(_) if self.camera.laser_distance_dm == 0 => {
                return Err(AckCode::Failure);
            }
            Request::TargetGps(r) => return Ok(Some(payload(&self.target_gps(&r)))),
            Request::TrackBox(b) => match b.enable {
                Toggle::On if self.config.track_requires_ai && !self.camera.ai => {
                    return Err(AckCode::Failure);
                }
                Toggle::On => {
                    self.camera.track = Some(b);
                    self.yaw.motion = AxisMotion::Hold;
                    self.pitch.motion = AxisMotion::Hold;
                }
                _ => self.camera.track = None,
            },
            Request::LaserRange(l) => {
                let mut reading = self.laser_reading();
                if l.mode != LaserMode::Single {
                    reading.distance_dm = 0;
                }
                return Ok(Some(payload(&reading)));
            }
            Request::LaserPeriodic(p) => {
                let on = p.enable == OnOff::On;
                if on && !self.camera.laser_periodic {
                    self.deferred
                        .push(message(&LaserPeriodicStatus(self.laser_reading())));
                    self.laser_due = Some(
                        t.saturating_add(self.config.ack_delay_us)
                            .saturating_add(ONE_SECOND_US),
                    );
                }
                self.camera.laser_periodic = on;
            }
            Request::SbusConfig(_) => {
                return Ok(Some(payload(&SbusConfig {
                    code: ResponseCode::OK,
                    max: 1811,
                    min: 172,
                    channels: SbusChannelMap {
                        stream: 5,
                        zoom: 6,
                        photo: 7,
                        video: 8,
                        pitch: 1,
                        yaw: 3,
                        center: 9,
                    },
                    reserved: 0,
                })));
            }
            other => return self.apply_setting(t, other),
        }
        Ok(None)
    }

    pub(super) fn laser_reading(&self) -> LaserDistance {
        LaserDistance {
            code: ResponseCode::OK,
            distance_dm: self.camera.laser_distance_dm,
        }
    }

    /// The laser target's position, flat earth, from the aircraft's position and heading,
    /// the gimbal angles and the laser distance.
    pub(super) fn target_gps(&self, r: &TargetGpsRequest) -> TargetGpsAck {
        let d = f64::from(self.camera.laser_distance_dm) / 10.0;
        let pitch = self.pitch.angle.to_radians();
        let horizontal = d * pitch.cos();
        let drop_mm = (-d * pitch.sin() * 1000.0).round() as i32;
        let bearing = (f64::from(r.heading_cdeg) / 100.0 + self.yaw.angle).to_radians();
        let lat = f64::from(r.lat_e7) / 1e7;
        let metres_per_deg = 111_320.0;
        let dlat = horizontal * bearing.cos() / metres_per_deg;
        let dlon = horizontal * bearing.sin() / (metres_per_deg * lat.to_radians().cos().max(1e-6));
        TargetGpsAck {
            code: ResponseCode::OK,
            mount: 0x1F,
            utc_ms: r.utc_ms,
            lon_e7: r.lon_e7.saturating_add((dlon * 1e7).round() as i32),
            lat_e7: r.lat_e7.saturating_add((dlat * 1e7).round() as i32),
            rel_alt_mm: r.rel_alt_mm.saturating_sub(drop_mm),
            alt_mm: r.alt_mm.saturating_sub(drop_mm),
        }
    }

    pub(super) fn send_report(&mut self, index: usize, t: u64) {
        match REPORT_IDS.get(index) {
            Some(0x0001) => {
                let status = GimbalStatus {
                    links: Links(0),
                    upgrade: UpgradeState::Normal,
                    self_test: SelfTest(0x0F),
                    stabilization: if self.stabilization {
                        StabilizationState::Active
                    } else {
                        StabilizationState::Off
                    },
                    reserved: [0; 3],
                };
                self.send(t, &status);
            }
            Some(0x0002) => {
                let g = self.gimbal();
                let cdeg = |deg: f64| (deg * 100.0).round() as i16;
                let attitude = GimbalAttitude {
                    yaw_joint_cdeg: cdeg(g.yaw_deg),
                    roll_joint_cdeg: 0,
                    pitch_joint_cdeg: cdeg(g.pitch_deg),
                    yaw_cdeg: cdeg(g.yaw_deg),
                    roll_cdeg: 0,
                    pitch_cdeg: cdeg(g.pitch_deg),
                    yaw_rate_cdeg_s: cdeg(g.yaw_rate_dps),
                    pitch_rate_cdeg_s: cdeg(g.pitch_rate_dps),
                    roll_rate_cdeg_s: 0,
                    reserved: [0; 2],
                };
                self.send(t, &attitude);
            }
            Some(0x0003) => {
                let c = &self.camera;
                let (sd_total_10mb, sd_free_10mb, sd_used_10mb) = self.card_at(t);
                let status = SystemStatus {
                    mode: c.mode,
                    preview_resolution: PreviewResolution::P1080Fps30,
                    preview_codec: c.codec,
                    stream: c.image_mode,
                    preview_bitrate: c.bitrate,
                    photo_mode: c.photo_mode,
                    timelapse_s: c.timelapse_s,
                    burst_count: c.burst_count,
                    sd: SdState::Normal,
                    sd_total_10mb,
                    sd_free_10mb,
                    sd_used_10mb,
                    reserved: 0,
                };
                self.send(t, &status);
            }
            Some(0x0004) if self.camera.ir_measuring => {
                self.send(t, &ir_scene(t));
            }
            Some(0x0005) => {
                let c = &self.camera;
                let optical = c.zoom_x10.min(OPTICAL_MAX_X10) / 10.0;
                let status = VisibleStatus {
                    zoom_state: if c.zooming {
                        ZoomState::Zooming
                    } else {
                        ZoomState::Done
                    },
                    focal_length_10um: (f64::from(self.config.focal_length_1x_10um) * optical)
                        .round() as u16,
                    zoom_x10: c.zoom_x10.round() as u16,
                    ev: c.ev,
                    iso_0p1db: 0,
                    shutter_us: 1000,
                    ae_lock: c.ae_lock,
                    focus: if self.manual_focus || self.focus_until_us > t {
                        FocusState::Focusing
                    } else {
                        FocusState::Done
                    },
                    accurate_focal_length: 0,
                    reserved: 0,
                };
                self.send(t, &status);
            }
            _ => {}
        }
    }
}
