//! A simulated flight controller that speaks the K40T protocol itself (as 0x02/0x01):
//! it sends commands, a 0x00030E every 10 s right after its own (unwired) RTC_IO pulse,
//! and answers the pod's GPS requests from its position, unless told not to.
//!
//! No ArduPilot driver speaks K40T, so "healthy" is this simulator's own rule, in the
//! spirit of the others: a pod attitude report (0x000002) received within the last
//! second ([`FcK40t::healthy`], [`FcK40t::health_log`]). A motion held with
//! [`FcK40t::hold_motion`] is repeated every [`MOTION_REPEAT_US`] while it turns the pod,
//! as a stick held over would (the bridge stops a pod whose FC falls silent).
//!
//! Sequence numbers: the FC's own counter, from 0, for every frame it originates. Its
//! GPS replies (0x010310) take the FC's own next number by default, as the document's
//! field table reads ([`AckSeq::OwnCounter`]); with [`FcK40t::reply_seq`] =
//! [`AckSeq::Echo`] they carry the request's SEQ.
//!
//! [`FcK40t::reboot`]: silent and deaf for [`FcReboot::off_us`], then the counter
//! restarts at 0, the held motion is forgotten and the time syncs start again 1 s after
//! power-on (or when the UTC is valid, if later), with a UTC that differs from the
//! previous boot's by [`FcReboot::utc_shift_us`] ([`FcK40t::utc_us`] follows it).

use protocol_core::k40t::{
    self, Address, CrcCoverage, GimbalAttitude, GimbalControl, GpsReply, Header, K40t, K40tFraming,
    Message, MessageData, Packet, PitchMotion, Request, ResponseCode, TimeSync, YawMotion,
};
use protocol_core::wire::{Deframer, Event};

use super::FcReboot;
use super::ap_siyi::Aircraft;
use super::pod::AckSeq;
use super::scenario::FcSim;

/// A frame the FC received, with the true time of its arrival.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Received {
    /// True time of arrival.
    pub at_us: u64,
    /// The frame.
    pub frame: Vec<u8>,
}

/// The simulated K40T flight controller.
pub struct FcK40t {
    now_us: u64,
    seq: u8,
    deframer: Deframer<K40tFraming, { k40t::MAX_FRAME_LEN }>,
    out: Vec<(u64, Vec<u8>)>,
    next_sync_us: u64,
    /// The FC's UTC at true time 0, µs.
    pub utc_at_zero_us: u64,
    /// Answer the pod's GPS requests.
    pub answer_gps: bool,
    /// Sequence number of the GPS replies.
    pub reply_seq: AckSeq,
    /// (power-on instant, UTC shift since the first boot, µs), per reboot.
    utc_shifts: Vec<(u64, i64)>,
    /// (power-off, power-on) of every reboot.
    pub reboots: Vec<(u64, u64)>,
    /// Bytes from the bridge lost while the FC was off.
    pub lost_while_off: u64,
    /// The aircraft.
    pub aircraft: Aircraft,
    /// Every frame received from the bridge.
    pub received: Vec<Received>,
    /// Frames the FC sent: (true time, sequence number, message id).
    pub sent: Vec<(u64, u8, u32)>,
    /// True time of the last pod attitude report received.
    last_report_us: Option<u64>,
    /// The motion repeated while it turns, and when it is next due.
    held: Option<(GimbalControl, u64)>,
    healthy: bool,
    /// True times at which [`FcK40t::healthy`] changed, with the new value.
    pub health_log: Vec<(u64, bool)>,
}

impl std::fmt::Debug for FcK40t {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FcK40t")
            .field("now_us", &self.now_us)
            .field("received", &self.received.len())
            .finish_non_exhaustive()
    }
}

impl Default for FcK40t {
    fn default() -> Self {
        FcK40t {
            now_us: 0,
            seq: 0,
            deframer: Deframer::new(K40tFraming::any()),
            out: Vec::new(),
            next_sync_us: 1_000_000,
            utc_at_zero_us: 1_795_428_000_123_456,
            answer_gps: true,
            reply_seq: AckSeq::OwnCounter,
            utc_shifts: Vec::new(),
            reboots: Vec::new(),
            lost_while_off: 0,
            aircraft: Aircraft::default(),
            received: Vec::new(),
            sent: Vec::new(),
            last_report_us: None,
            held: None,
            healthy: false,
            health_log: Vec::new(),
        }
    }
}

/// A report older than this leaves the FC unhealthy.
const HEALTH_TIMEOUT_US: u64 = 1_000_000;
/// A held motion is sent again this often while it turns the pod.
pub const MOTION_REPEAT_US: u64 = 200_000;

impl FcK40t {
    /// True time of the first 0x00030E (UTC) sent, µs.
    #[must_use]
    pub fn first_utc_sent_us(&self) -> Option<u64> {
        self.sent
            .iter()
            .find(|(_, _, id)| *id == 0x00_030E)
            .map(|(t, _, _)| *t)
    }

    /// The FC's UTC at true time `t_us`.
    #[must_use]
    pub fn utc_us(&self, t_us: u64) -> u64 {
        let shift = self
            .utc_shifts
            .iter()
            .rev()
            .find(|(at, _)| *at <= t_us)
            .map_or(0, |(_, s)| *s);
        let utc = i128::from(self.utc_at_zero_us) + i128::from(t_us) + i128::from(shift);
        u64::try_from(utc.max(0)).unwrap_or(0)
    }

    /// The FC is without power at `t_us`.
    #[must_use]
    pub fn is_off(&self, t_us: u64) -> bool {
        self.reboots
            .iter()
            .any(|&(off, on)| off <= t_us && t_us < on)
    }

    /// The FC loses power at `now_us` and boots as [`FcReboot`] says (its boot clock is
    /// not on the wire: [`FcReboot::boot_clock_us`] is unused).
    pub fn reboot(&mut self, now_us: u64, reboot: FcReboot) {
        self.poll(now_us);
        let on = now_us.saturating_add(reboot.off_us);
        let shift = self.utc_shifts.last().map_or(0, |(_, s)| *s) + reboot.utc_shift_us;
        self.utc_shifts.push((on, shift));
        self.reboots.push((now_us, on));
        self.out.retain(|(at, _)| *at <= now_us);
        self.seq = 0;
        self.deframer = Deframer::new(K40tFraming::any());
        self.held = None;
        self.last_report_us = None;
        self.next_sync_us = on + reboot.utc_valid_after_us.max(1_000_000);
        if self.healthy {
            self.healthy = false;
            self.health_log.push((now_us, false));
        }
    }

    /// A pod attitude report came within the last second.
    #[must_use]
    pub fn healthy(&self) -> bool {
        self.healthy
    }

    fn update_health(&mut self, now_us: u64) {
        let fresh = self
            .last_report_us
            .is_some_and(|t| now_us <= t + HEALTH_TIMEOUT_US);
        if fresh != self.healthy {
            self.healthy = fresh;
            self.health_log.push((now_us, fresh));
        }
    }

    /// Sends `control` now and, while it turns the pod, again every
    /// [`MOTION_REPEAT_US`] until another motion is held.
    pub fn hold_motion(&mut self, control: GimbalControl) {
        self.send(&control);
        let turns = control.yaw != YawMotion::Stop || control.pitch != PitchMotion::Stop;
        self.held = turns.then_some((control, self.now_us + MOTION_REPEAT_US));
    }

    /// Sends a request to the pod now.
    pub fn send<M: MessageData<Protocol = K40t>>(&mut self, m: &M) {
        if self.is_off(self.now_us) {
            return;
        }
        let header = Header::new(Address::FLIGHT_CONTROLLER, Address::POD, self.seq);
        self.seq = self.seq.wrapping_add(1);
        let mut buf = [0u8; k40t::MAX_FRAME_LEN];
        if let Ok(n) = k40t::encode(m, &header, &mut buf) {
            self.sent.push((self.now_us, header.seq, M::ID.to_u32()));
            self.out.push((self.now_us, buf[..n].to_vec()));
        }
    }

    /// The frames received of message `M`, decoded, with their headers.
    #[must_use]
    pub fn received_of<M: MessageData<Protocol = K40t>>(&self) -> Vec<(u64, Header, M)> {
        self.received
            .iter()
            .filter_map(|r| {
                let p = Packet::decode(&r.frame).ok()?;
                Some((r.at_us, p.header, p.message.get::<M>()?))
            })
            .collect()
    }

    fn answer(&mut self, header: Header, request: k40t::GpsRequest) {
        let (lat_e7, lon_e7) = self.aircraft.position_e7(self.now_us);
        let reply = GpsReply {
            code: ResponseCode::OK,
            hour: request.hour,
            minute: request.minute,
            second: request.second,
            millisecond: request.millisecond,
            lon_e7,
            lat_e7,
            rel_alt_dm: 500,
            alt_msl_dm: (self.aircraft.alt_msl_m * 10.0) as i16,
            yaw_cdeg: (self.aircraft.heading_deg * 100.0) as i16,
            roll_cdeg: 0,
            pitch_cdeg: 0,
        };
        let seq = match self.reply_seq {
            AckSeq::Echo => header.seq,
            AckSeq::OwnCounter => {
                let seq = self.seq;
                self.seq = self.seq.wrapping_add(1);
                seq
            }
        };
        let h = Header {
            dst: header.src,
            src: Address::FLIGHT_CONTROLLER,
            seq,
            coverage: CrcCoverage::ExcludeStx,
        };
        let mut buf = [0u8; k40t::MAX_FRAME_LEN];
        if let Ok(n) = k40t::encode(&reply, &h, &mut buf) {
            self.out.push((self.now_us, buf[..n].to_vec()));
        }
    }
}

impl FcSim for FcK40t {
    fn receive(&mut self, now_us: u64, bytes: &[u8]) {
        self.now_us = self.now_us.max(now_us);
        if self.is_off(now_us) {
            self.lost_while_off += bytes.len() as u64;
            return;
        }
        let mut frames = Vec::new();
        self.deframer.push(bytes, |e| {
            if let Event::Frame(f) = e {
                frames.push(f.to_vec());
            }
        });
        for f in frames {
            if let Ok(p) = Packet::decode(&f) {
                if p.message.get::<GimbalAttitude>().is_some() {
                    self.last_report_us = Some(now_us);
                }
                if let Message::Request(Request::GpsRequest(r)) = p.message
                    && self.answer_gps
                {
                    self.answer(p.header, r);
                }
            }
            self.received.push(Received {
                at_us: now_us,
                frame: f,
            });
        }
        self.update_health(now_us);
    }

    fn poll(&mut self, now_us: u64) {
        self.now_us = self.now_us.max(now_us);
        while self.next_sync_us <= now_us {
            self.now_us = self.next_sync_us;
            let unix_ms = self.utc_us(self.now_us) / 1000;
            self.send(&TimeSync {
                unix_ms,
                tz_minuteswest: 0,
                tz_dsttime: 0,
            });
            self.next_sync_us += 10_000_000;
        }
        while let Some((control, at)) = self.held.filter(|(_, at)| *at <= now_us) {
            self.now_us = at;
            self.send(&control);
            self.held = Some((control, at + MOTION_REPEAT_US));
        }
        self.now_us = now_us;
        self.update_health(now_us);
    }

    fn next_wakeup(&self) -> u64 {
        // The next sync, and the instant the last report gets too old.
        let stale = self
            .last_report_us
            .filter(|_| self.healthy)
            .map_or(u64::MAX, |t| t + HEALTH_TIMEOUT_US + 1);
        let held = self.held.map_or(u64::MAX, |(_, at)| at);
        self.next_sync_us.min(stale).min(held)
    }

    fn transmit(&mut self) -> Vec<(u64, Vec<u8>)> {
        std::mem::take(&mut self.out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use protocol_core::k40t::GpsRequest;

    fn decoded(fc: &mut FcK40t) -> Vec<(u64, Header, Message<'static>)> {
        fc.transmit()
            .into_iter()
            .map(|(at, f)| {
                let f: &'static [u8] = Box::leak(f.into_boxed_slice());
                let p = Packet::decode(f).unwrap();
                (at, p.header, p.message)
            })
            .collect()
    }

    #[test]
    fn a_reboot_restarts_the_counter_and_the_syncs_with_the_new_utc() {
        let mut fc = FcK40t::default();
        let utc0 = fc.utc_at_zero_us;
        fc.poll(15_000_000);
        let syncs: Vec<(u64, u8, u64)> = decoded(&mut fc)
            .into_iter()
            .filter_map(|(at, h, m)| Some((at, h.seq, m.get::<TimeSync>()?.unix_ms)))
            .collect();
        assert_eq!(
            syncs,
            [
                (1_000_000, 0, (utc0 + 1_000_000) / 1000),
                (11_000_000, 1, (utc0 + 11_000_000) / 1000)
            ]
        );
        fc.reboot(
            15_000_000,
            FcReboot {
                utc_shift_us: 2_000_000,
                ..FcReboot::default()
            },
        );
        assert!(fc.is_off(17_000_000) && !fc.is_off(18_000_000));
        fc.receive(16_000_000, &[0xFD, 0x00]);
        assert_eq!(fc.lost_while_off, 2);
        fc.poll(30_000_000);
        let syncs: Vec<(u64, u8, u64)> = decoded(&mut fc)
            .into_iter()
            .filter_map(|(at, h, m)| Some((at, h.seq, m.get::<TimeSync>()?.unix_ms)))
            .collect();
        assert_eq!(
            syncs,
            [
                (19_000_000, 0, (utc0 + 21_000_000) / 1000),
                (29_000_000, 1, (utc0 + 31_000_000) / 1000)
            ]
        );
        assert_eq!(fc.utc_us(29_000_000), utc0 + 31_000_000);
    }

    #[test]
    fn gps_replies_echo_the_seq_or_take_the_fcs_own_counter() {
        for (reply_seq, expected, next) in [(AckSeq::Echo, 42, 0), (AckSeq::OwnCounter, 0, 1)] {
            let mut fc = FcK40t {
                reply_seq,
                ..FcK40t::default()
            };
            let mut buf = [0u8; k40t::MAX_FRAME_LEN];
            let n = k40t::encode(
                &GpsRequest::default(),
                &Header::new(Address::POD, Address::FLIGHT_CONTROLLER, 42),
                &mut buf,
            )
            .unwrap();
            fc.receive(500_000, &buf[..n]);
            let replies: Vec<u8> = decoded(&mut fc)
                .into_iter()
                .filter(|(_, _, m)| m.get::<GpsReply>().is_some())
                .map(|(_, h, _)| h.seq)
                .collect();
            assert_eq!(replies, [expected], "{reply_seq:?}");
            // The next frame the FC originates continues its own counter.
            fc.poll(1_000_000);
            assert_eq!(decoded(&mut fc)[0].1.seq, next, "{reply_seq:?}");
        }
    }
}
