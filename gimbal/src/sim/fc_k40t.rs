//! A simulated flight controller that speaks the K40T protocol itself (as 0x02/0x01):
//! it sends commands, a 0x00030E every 10 s right after its own (unwired) RTC_IO pulse,
//! and answers the pod's GPS requests from its position, unless told not to.
//!
//! No ArduPilot driver speaks K40T, so "healthy" is this simulator's own rule, in the
//! spirit of the others: a pod attitude report (0x000002) received within the last
//! second ([`Autopilot::healthy`], [`Autopilot::health_log`]). A motion held with
//! [`FcK40t::hold_motion`] is repeated every [`MOTION_REPEAT_US`] while it turns the pod,
//! as a stick held over would (the bridge stops a pod whose FC falls silent).
//!
//! Sequence numbers: the FC's own counter, from 0, for every frame it originates. Its
//! GPS replies (0x010310) take the FC's own next number by default, as the document's
//! field table reads ([`AckSeq::OwnCounter`]); with [`FcK40t::reply_seq`] =
//! [`AckSeq::Echo`] they carry the request's SEQ.
//!
//! [`Autopilot::reboot`] (on the [`Board`], whose clock runs without error: this FC's
//! boot clock is not on the wire): the counter restarts at 0, the held motion is
//! forgotten and the time syncs start again 1 s after power-on (or when the UTC is
//! valid, if later), with the new boot's UTC ([`Autopilot::fc_utc_us`] follows it).

use protocol_core::k40t::{
    self, Address, ContinuousZoom, CrcCoverage, DialSpeed, GimbalAngle, GimbalAttitude,
    GimbalControl, GimbalFunction, GpsReply, Header, K40t, K40tFraming, Message, MessageData,
    Packet, PitchMotion, RecordAction, Request, ResponseCode, ShootAction, TakePhoto, TimeSync,
    YawMotion, ZoomControl,
};
use protocol_core::wire::{Deframer, Event};

use super::board::{Autopilot, Board, MainLoop, board_field};
use super::describe::K40tFrames;
use super::pilot::Pilot;
use super::pod::AckSeq;
use super::{FcClock, XorShift};

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
    board: Board,
    seq: u8,
    deframer: Deframer<K40tFraming, { k40t::MAX_FRAME_LEN }>,
    next_sync_us: u64,
    /// Answer the pod's GPS requests.
    pub answer_gps: bool,
    /// Sequence number of the GPS replies.
    pub reply_seq: AckSeq,
    /// Every frame received from the bridge.
    pub received: Vec<Received>,
    /// Frames the FC sent: (true time, sequence number, message id).
    pub sent: Vec<(u64, u8, u32)>,
    /// True time of the last pod attitude report received.
    last_report_us: Option<u64>,
    /// The motion repeated while it turns, and when it is next due.
    held: Option<(GimbalControl, u64)>,
}

impl std::fmt::Debug for FcK40t {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FcK40t")
            .field("now_us", &self.board.now_us())
            .field("received", &self.received.len())
            .finish_non_exhaustive()
    }
}

impl Default for FcK40t {
    fn default() -> Self {
        // 2026-11-23T10:00:00.123456Z
        FcK40t::new(1_795_428_000_123_456)
    }
}

/// A report older than this leaves the FC unhealthy.
const HEALTH_TIMEOUT_US: u64 = 1_000_000;
/// A held motion is sent again this often while it turns the pod.
pub const MOTION_REPEAT_US: u64 = 200_000;

impl FcK40t {
    /// An FC whose UTC reads `utc_at_zero_us` at true time 0 (and is valid from then).
    #[must_use]
    pub fn new(utc_at_zero_us: u64) -> Self {
        // No randomness in this simulator; a clock without error.
        let clock = FcClock::new(0.0, 0, utc_at_zero_us, 0);
        FcK40t {
            board: Board::new(clock, XorShift::new(0), MainLoop::None),
            seq: 0,
            deframer: Deframer::new(K40tFraming::any()),
            next_sync_us: 1_000_000,
            answer_gps: true,
            reply_seq: AckSeq::OwnCounter,
            received: Vec::new(),
            sent: Vec::new(),
            last_report_us: None,
            held: None,
        }
    }

    /// Sends `control` now and, while it turns the pod, again every
    /// [`MOTION_REPEAT_US`] until another motion is held.
    pub fn hold_motion(&mut self, control: GimbalControl) {
        self.send(&control);
        let turns = control.yaw != YawMotion::Stop || control.pitch != PitchMotion::Stop;
        self.held = turns.then_some((control, self.board.now_us() + MOTION_REPEAT_US));
    }

    /// Sends a request to the pod now.
    pub fn send<M: MessageData<Protocol = K40t>>(&mut self, m: &M) {
        let now = self.board.now_us();
        // Off by the clock: a held motion due while off is not sent (and stays held).
        if self.board.clock().is_off(now) {
            return;
        }
        let header = Header::new(Address::FLIGHT_CONTROLLER, Address::POD, self.seq);
        self.seq = self.seq.wrapping_add(1);
        let mut buf = [0u8; k40t::MAX_FRAME_LEN];
        if let Ok(n) = k40t::encode(m, &header, &mut buf) {
            self.sent.push((now, header.seq, M::ID.to_u32()));
            self.board.write_at(now, buf[..n].to_vec());
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
        let (lat_e7, lon_e7) = self.board.aircraft().position_e7(self.board.now_us());
        let reply = GpsReply {
            code: ResponseCode::OK,
            hour: request.hour,
            minute: request.minute,
            second: request.second,
            millisecond: request.millisecond,
            lon_e7,
            lat_e7,
            rel_alt_dm: 500,
            alt_msl_dm: (self.board.aircraft().alt_msl_m * 10.0) as i16,
            yaw_cdeg: (self.board.aircraft().heading_deg * 100.0) as i16,
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
            self.board.write_at(self.board.now_us(), buf[..n].to_vec());
        }
    }
}

impl Autopilot for FcK40t {
    board_field!();

    fn take_bytes(&mut self, now_us: u64, bytes: &[u8]) {
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
    }

    /// No loop: the syncs and a held motion have their own instants ([`Autopilot::run_due`]).
    fn run(&mut self) {}

    fn update_health(&mut self) {
        let now = self.board.now_us();
        let fresh = self
            .last_report_us
            .is_some_and(|t| now <= t + HEALTH_TIMEOUT_US);
        self.board.set_healthy(fresh);
    }

    fn run_due(&mut self, now_us: u64) {
        while self.next_sync_us <= now_us {
            let at = self.next_sync_us;
            self.board.set_now(at);
            let unix_ms = self.board.clock().utc_us(at) / 1000;
            self.send(&TimeSync {
                unix_ms,
                tz_minuteswest: 0,
                tz_dsttime: 0,
            });
            self.next_sync_us += 10_000_000;
        }
        while let Some((control, at)) = self.held.filter(|(_, at)| *at <= now_us) {
            self.board.set_now(at);
            self.send(&control);
            self.held = Some((control, at + MOTION_REPEAT_US));
        }
        self.board.set_now(now_us);
        self.update_health();
    }

    fn power_on(&mut self) {}

    fn power_off(&mut self) {
        self.seq = 0;
        self.deframer = Deframer::new(K40tFraming::any());
        self.held = None;
        self.last_report_us = None;
        let boot = *self.board.clock().current();
        self.next_sync_us = boot.utc_valid_at_us.max(boot.at_us + 1_000_000);
    }

    fn next_work_us(&self) -> u64 {
        // The next sync, the next repeat of a held motion, and the instant the last
        // report gets too old.
        let stale = self
            .last_report_us
            .filter(|_| self.board.healthy())
            .map_or(u64::MAX, |t| t + HEALTH_TIMEOUT_US + 1);
        let held = self.held.map_or(u64::MAX, |(_, at)| at);
        self.next_sync_us.min(stale).min(held)
    }
}

/// Degrees to the K40T's unsigned 0.01° magnitude.
fn cdeg(deg: f64) -> u16 {
    (deg.abs() * 100.0).round().min(f64::from(u16::MAX)) as u16
}

impl Pilot for FcK40t {
    const DRIVER: &'static str = "flight controller speaking K40T (simulated)";
    const STREAMS: bool = false;
    type Frames = K40tFrames;

    fn first_utc_sent_us(&self) -> Option<u64> {
        // 0x00030E: the K40T time sync.
        let sync = |&(t, _, id): &(u64, u8, u32)| (id == 0x00_030E).then_some(t);
        self.sent.iter().find_map(sync)
    }
    fn mount_angles(&self) -> Option<(f64, f64)> {
        let (_, _, a) = self.received_of::<GimbalAttitude>().pop()?;
        Some((
            f64::from(a.yaw_joint_cdeg) / 100.0,
            f64::from(a.pitch_joint_cdeg) / 100.0,
        ))
    }

    fn point(&mut self, yaw_deg: f64, pitch_deg: f64) {
        self.send(&GimbalAngle {
            pitch_direction: if pitch_deg < 0.0 {
                PitchMotion::Down
            } else {
                PitchMotion::Up
            },
            pitch_cdeg: cdeg(pitch_deg),
            yaw_direction: if yaw_deg < 0.0 {
                YawMotion::Left
            } else {
                YawMotion::Right
            },
            yaw_cdeg: cdeg(yaw_deg),
            reserved: 0,
        });
    }
    fn turn(&mut self, yaw_dps: f64, pitch_dps: f64) {
        // Dial speed in 0.2 °/s (5..=150), then the directions, held (repeated) while
        // they turn the pod.
        let x5 = |dps: f64| ((dps.abs() * 5.0).round() as u8).clamp(5, 150);
        self.send(&DialSpeed {
            pitch_dps_x5: x5(pitch_dps),
            yaw_dps_x5: x5(yaw_dps),
            reserved: 0,
        });
        let yaw = match yaw_dps {
            r if r > 0.0 => YawMotion::Right,
            r if r < 0.0 => YawMotion::Left,
            _ => YawMotion::Stop,
        };
        let pitch = match pitch_dps {
            r if r > 0.0 => PitchMotion::Up,
            r if r < 0.0 => PitchMotion::Down,
            _ => PitchMotion::Stop,
        };
        self.hold_motion(GimbalControl {
            function: GimbalFunction::None,
            yaw,
            pitch,
            reserved: 0,
        });
    }
    fn zoom(&mut self, rate: i8) {
        let control = match rate.signum() {
            1 => ZoomControl::In,
            -1 => ZoomControl::Out,
            _ => ZoomControl::Stop,
        };
        self.send(&ContinuousZoom {
            control,
            reserved: 0,
        });
    }
    fn take_picture(&mut self) {
        self.send(&TakePhoto {
            action: ShootAction::Start,
            ..TakePhoto::default()
        });
    }
    fn record(&mut self, on: bool) {
        self.send(&k40t::Record {
            action: if on {
                RecordAction::Start
            } else {
                RecordAction::Stop
            },
            ..k40t::Record::default()
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{FcReboot, Peer};
    use protocol_core::k40t::GpsRequest;

    fn decoded(fc: &mut FcK40t) -> Vec<(u64, Header, Message<'static>)> {
        fc.transmit(0)
            .into_iter()
            .map(|(at, f)| {
                let f: &'static [u8] = Box::leak(f.into_boxed_slice());
                let p = Packet::decode(f).unwrap();
                (at, p.header, p.message)
            })
            .collect()
    }

    /// The syncs sent: (true µs, sequence number, UTC ms).
    fn syncs_sent(fc: &mut FcK40t) -> Vec<(u64, u8, u64)> {
        decoded(fc)
            .into_iter()
            .filter_map(|(at, h, m)| Some((at, h.seq, m.get::<TimeSync>()?.unix_ms)))
            .collect()
    }

    #[test]
    fn a_reboot_restarts_the_counter_and_the_syncs_with_the_new_utc() {
        let mut fc = FcK40t::default();
        let utc0 = fc.fc_utc_us(0);
        // Two syncs 10 s apart from sequence number 0, each with the FC's UTC then.
        let two_syncs = |at: u64, utc: u64| {
            [
                (at, 0, utc / 1000),
                (at + 10_000_000, 1, (utc + 10_000_000) / 1000),
            ]
        };
        fc.poll(15_000_000);
        assert_eq!(syncs_sent(&mut fc), two_syncs(1_000_000, utc0 + 1_000_000));
        fc.reboot(
            15_000_000,
            FcReboot {
                utc_shift_us: 2_000_000,
                ..FcReboot::default()
            },
        );
        let clock = fc.clock();
        assert!(clock.is_off(17_000_000) && !clock.is_off(18_000_000));
        fc.receive(16_000_000, &[0xFD, 0x00]);
        assert_eq!(fc.lost_while_off(), 2);
        fc.poll(30_000_000);
        assert_eq!(
            syncs_sent(&mut fc),
            two_syncs(19_000_000, utc0 + 21_000_000)
        );
        assert_eq!(fc.fc_utc_us(29_000_000), utc0 + 31_000_000);
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
