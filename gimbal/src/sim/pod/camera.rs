//! The camera: focus, photos (each shot with its GPS request: the geotag client),
//! recording.

use super::*;

#[derive(Debug, Clone, Copy)]
pub(super) struct PhotoJob {
    pub(super) sensors: PhotoSensors,
    pub(super) mode: PhotoMode,
    /// Shots to take (None: until stopped).
    pub(super) total: Option<u16>,
    pub(super) done: u16,
    pub(super) next_us: u64,
    pub(super) interval_us: u64,
}

/// The camera as at power-up.
pub(super) fn initial_camera(
    config: &PodSimConfig,
    laser_distance_dm: u16,
    photos_taken: u32,
) -> CameraState {
    CameraState {
        mode: CaptureMode::Photo,
        photo_mode: PhotoMode::Single,
        timelapse_s: 5,
        burst_count: 3,
        image_mode: ImageMode::Visible,
        codec: VideoCodec::H264,
        bitrate: StreamBitrate::M4,
        palette: Palette::WhiteHot,
        ir_measuring: true,
        zoom_x10: f64::from(config.zoom_min_x10),
        zoom_target_x10: None,
        zooming: false,
        focus: None,
        af_after_zoom: false,
        recording: None,
        photos_taken,
        laser_periodic: false,
        laser_distance_dm,
        ai: false,
        track: None,
        ev: Ev::Auto,
        ae_lock: AeLock::Off,
        settings: PodSettings::default(),
    }
}

/// The 0x020303 status of a recording at `t`.
pub(super) fn record_status(rec: Recording, state: RecordState, t: u64) -> RecordStatus {
    RecordStatus {
        sensors: rec.sensors,
        state,
        elapsed_s: u16::try_from(t.saturating_sub(rec.since_us) / ONE_SECOND_US)
            .unwrap_or(u16::MAX),
        reserved: [0; 3],
    }
}

impl SimPod {
    pub(super) fn focus(&mut self, t: u64, mode: FocusMode) {
        self.camera.focus = Some(mode);
        match mode {
            FocusMode::Auto | FocusMode::Area | FocusMode::OneTouch => {
                self.manual_focus = false;
                self.focus_until_us = t.saturating_add(self.config.focus_duration_us);
            }
            FocusMode::ManualPlus | FocusMode::ManualMinus => self.manual_focus = true,
            FocusMode::ManualStop => self.manual_focus = false,
            FocusMode::AfAfterZoomOn => self.camera.af_after_zoom = true,
            FocusMode::AfAfterZoomOff => self.camera.af_after_zoom = false,
            FocusMode::Other(_) => {}
        }
    }

    pub(super) fn take_photo(&mut self, t: u64, p: k40t::TakePhoto) -> Result<(), AckCode> {
        if p.action == ShootAction::Stop {
            if let Some(job) = self.photo_job.take()
                && job.mode != PhotoMode::Single
            {
                self.deferred.push(message(&PhotoStatus {
                    sensors: job.sensors,
                    state: PhotoState::Stopped,
                    burst_count: job.done,
                    reserved: [0; 3],
                }));
            }
            return Ok(());
        }
        if self.photo_job.is_some() {
            return Err(AckCode::PhotoInProgress);
        }
        if self.config.enforce_capture_mode && self.camera.mode != CaptureMode::Photo {
            return Err(AckCode::Failure);
        }
        let mode = self.camera.photo_mode;
        let (total, interval_us) = match mode {
            PhotoMode::Burst => (
                Some(u16::from(self.camera.burst_count.max(1))),
                self.config.burst_interval_us,
            ),
            PhotoMode::TimeLapse => (
                None,
                u64::from(self.camera.timelapse_s.max(1)) * ONE_SECOND_US,
            ),
            _ => {
                // Every shutter press is a shot, even one behind a pending shot.
                let due = t.saturating_add(self.config.photo_gps_delay_us);
                self.single_shots.push_back((due, p.sensors));
                return Ok(());
            }
        };
        if !self.single_shots.is_empty() {
            return Err(AckCode::PhotoInProgress);
        }
        self.photo_job = Some(PhotoJob {
            sensors: p.sensors,
            mode,
            total,
            done: 0,
            next_us: t.saturating_add(self.config.photo_gps_delay_us),
            interval_us: interval_us.max(1),
        });
        Ok(())
    }

    pub(super) fn take_shot(&mut self, t: u64) {
        let single = self.single_shots.front().filter(|s| s.0 <= t).map(|s| s.1);
        let mut job = match (single, self.photo_job) {
            (Some(sensors), _) => {
                self.single_shots.pop_front();
                PhotoJob {
                    sensors,
                    mode: PhotoMode::Single,
                    total: Some(1),
                    done: 0,
                    next_us: t,
                    interval_us: ONE_SECOND_US,
                }
            }
            (None, Some(job)) => job,
            (None, None) => return,
        };
        job.done = job.done.saturating_add(1);
        let pod_unix_ms = self.clock_unix_ms(t);
        let photo = self.photos.len();
        self.camera.photos_taken += 1;
        let gps_request = self.ask_gps(t, Some(photo), self.config.gps_lens_enable);
        self.photos.push(PhotoRecord {
            at_us: t,
            sensors: job.sensors,
            pod_unix_ms,
            shot: job.done,
            gps_request,
        });
        let progress = match job.mode {
            PhotoMode::Burst => Some(PhotoState::Burst),
            PhotoMode::TimeLapse => Some(PhotoState::TimeLapse),
            _ => self
                .config
                .single_shot_status
                .then_some(PhotoState::SingleShot),
        };
        let status = |state| PhotoStatus {
            sensors: job.sensors,
            state,
            burst_count: job.done,
            reserved: [0; 3],
        };
        if let Some(state) = progress {
            self.send(t, &status(state));
        }
        if job.total.is_some_and(|n| job.done >= n) {
            if single.is_none() {
                self.photo_job = None;
            }
            if progress.is_some() {
                self.send(t, &status(PhotoState::Taken));
            }
        } else {
            job.next_us = t.saturating_add(job.interval_us);
            self.photo_job = Some(job);
        }
    }

    /// Sends a GPS request at `t` (unless the pod has never been synchronised and
    /// [`PodSimConfig::gps_when_unsynced`] is off) for photo `photo` (`None`: a periodic
    /// one); returns its index in the records.
    pub(super) fn ask_gps(
        &mut self,
        t: u64,
        photo: Option<usize>,
        lens_enable: u8,
    ) -> Option<usize> {
        if !(self.clock.synced || self.config.gps_when_unsynced) {
            return None;
        }
        let pod_unix_ms = self.clock_unix_ms(t);
        let (hour, minute, second, millisecond) = self.time_of_day(t);
        let request = GpsRequest {
            lens_enable,
            hour,
            minute,
            second,
            millisecond,
        };
        let late = photo.and_then(|p| self.config.photo_gps_late_us.get(&p).copied());
        let sent_us = t.saturating_add(late.unwrap_or(0));
        let (id, payload) = message(&request);
        let seq = self.send_payload(sent_us, id, payload);
        self.gps_requests.push(GpsRequestRecord {
            at_us: sent_us,
            seq,
            request,
            pod_unix_ms,
            synced: self.clock.synced,
            photo,
            reply: None,
            timed_out: false,
            boot: self.boots.len().saturating_sub(1),
        });
        self.gps_open.push_back(self.gps_requests.len() - 1);
        Some(self.gps_requests.len() - 1)
    }

    /// The periodic GPS request due at `t` ([`PodSimConfig::gps_periodic`]).
    pub(super) fn periodic_gps(&mut self, t: u64) {
        let Some(period) = self.config.gps_periodic.period_us() else {
            self.gps_periodic_due = None;
            return;
        };
        let active = match self.config.gps_periodic {
            PeriodicGps::WhileRecording { .. } => self.camera.recording.is_some(),
            _ => true,
        };
        if active {
            self.ask_gps(t, None, self.config.gps_periodic_lens_enable);
            self.gps_periodic_due = Some(t.saturating_add(period.max(1)));
        } else {
            self.gps_periodic_due = None;
        }
    }

    pub(super) fn record(&mut self, t: u64, r: k40t::Record) -> Result<(), AckCode> {
        match r.action {
            RecordAction::Start => {
                if self.config.enforce_capture_mode && self.camera.mode != CaptureMode::Video {
                    return Err(AckCode::Failure);
                }
                if self.camera.recording.is_none() {
                    let since_us = t.saturating_add(self.config.ack_delay_us);
                    self.camera.recording = Some(Recording {
                        sensors: r.sensors,
                        since_us,
                    });
                    self.camera.mode = CaptureMode::Video;
                    self.record_status_due = Some(since_us);
                    if let PeriodicGps::WhileRecording { period_us } = self.config.gps_periodic {
                        self.gps_periodic_due = Some(since_us.saturating_add(period_us.max(1)));
                    }
                }
            }
            RecordAction::Stop => {
                if let Some(rec) = self.camera.recording.take() {
                    let at = t.saturating_add(self.config.ack_delay_us);
                    self.deferred
                        .push(message(&record_status(rec, RecordState::Stopped, at)));
                    self.record_status_due = None;
                }
            }
            RecordAction::Other(_) => {}
        }
        Ok(())
    }

    pub(super) fn handle_gps_reply(&mut self, t: u64, header: Header, reply: GpsReply) {
        let index = self.gps_replies.len();
        let request = self.match_gps_reply(header.seq);
        let mut record = GpsReplyRecord {
            at_us: t,
            header,
            reply,
            request,
            seq_matches: false,
            latency_us: None,
            time_matches: false,
            late: false,
        };
        if let Some(i) = request {
            self.gps_open.retain(|&open| open != i);
            if let Some(r) = self.gps_requests.get_mut(i) {
                r.reply = Some(index);
                record.seq_matches = r.seq == header.seq;
                record.latency_us = Some(t.saturating_sub(r.at_us));
                record.late = r.timed_out;
                let q = r.request;
                record.time_matches = (q.hour, q.minute, q.second, q.millisecond)
                    == (reply.hour, reply.minute, reply.second, reply.millisecond);
            }
        }
        self.gps_replies.push(record);
    }

    /// The request a GPS reply with sequence number `seq` answers: a pending one with
    /// that number (the oldest), else the latest of this boot that timed out with it,
    /// else the oldest pending one.
    pub(super) fn match_gps_reply(&self, seq: u8) -> Option<usize> {
        let boot = self.boots.len().saturating_sub(1);
        let seq_of = |i: usize| self.gps_requests.get(i).map(|r| r.seq);
        self.gps_open
            .iter()
            .copied()
            .find(|&i| seq_of(i) == Some(seq))
            .or_else(|| {
                self.gps_requests.iter().rposition(|r| {
                    r.boot == boot && r.timed_out && r.reply.is_none() && r.seq == seq
                })
            })
            .or_else(|| self.gps_open.front().copied())
    }
}
