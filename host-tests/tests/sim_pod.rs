//! The simulated K40T pod (`gimbal::sim::pod`), driven the way the bridge will drive
//! it: frames built with the codec go in, the pod's bytes come out and are deframed.

use gimbal::sim::pod::{AckSeq, MotionCommand, OutputFaults, PodSimConfig, SimPod, SyncOutcome};
use protocol_core::k40t::{
    self, AckCode, Address, AiRecognition, CameraVersionAck, CameraVersionQuery, ContinuousZoom,
    CrcCoverage, DialSpeed, Focus, FocusMode, FocusState, GimbalAngle, GimbalAttitude,
    GimbalControl, GimbalFunction, GimbalStatus, GimbalVersionAck, GimbalVersionQuery, GpsReply,
    GpsRequest, Header, HybridZoom, ImageMode, ImageModeSetting, IrMeasurement, IrPalette,
    IrParams, IrParamsQuery, IrStatus, K40tFraming, Kind, LaserDistance, LaserMode, LaserPeriodic,
    LaserPeriodicStatus, LaserRange, Lens, MAX_FRAME_LEN, MeasureSwitch, Message, MessageData,
    MsgId, OnOff, Packet, Palette, PhotoMode, PhotoParams, PhotoSensors, PhotoState, PhotoStatus,
    PitchMotion, PointToAim, Raw, Record, RecordAction, RecordSensors, RecordState, RecordStatus,
    ResponseCode, ShootAction, SystemStatus, TakePhoto, TimeSync, Toggle, TrackBox, Version,
    VisibleStatus, YawMotion, ZoomControl, ZoomState, ZoomStatus,
};
use protocol_core::wire::{Deframer, Event};

/// The pod with ACKs that echo the request's SEQ: the older tests of this file were
/// written against it (the default numbers ACKs with the pod's own counter, as the
/// document reads; its tests set it explicitly).
fn echoing() -> PodSimConfig {
    PodSimConfig {
        ack_seq: AckSeq::Echo,
        ..PodSimConfig::default()
    }
}

const FC: Address = Address::FLIGHT_CONTROLLER;
const GIMBAL: Address = Address::GIMBAL;
const POD: Address = Address::POD;
const S: u64 = 1_000_000;
const MS: u64 = 1_000;
/// 2026-01-01T00:00:00Z (the reference time-sync frame of docs/src/protocols/k40t.md).
const NEW_YEAR_2026_MS: u64 = 1_767_225_600_000;

/// The bridge's side: builds requests, deframes what the pod sends, with the instant
/// the bytes were taken.
struct Fc {
    seq: u8,
    coverage: CrcCoverage,
    deframer: Deframer<K40tFraming, MAX_FRAME_LEN>,
    frames: Vec<(u64, Vec<u8>)>,
}

impl Fc {
    fn new() -> Self {
        Fc::with(CrcCoverage::ExcludeStx)
    }

    fn with(coverage: CrcCoverage) -> Self {
        Fc {
            seq: 0,
            coverage,
            deframer: Deframer::new(K40tFraming::with(coverage)),
            frames: Vec::new(),
        }
    }

    /// The frame of `m` to `dst` with the next sequence number.
    fn frame<M: MessageData<Protocol = k40t::K40t>>(
        &mut self,
        dst: Address,
        m: &M,
    ) -> (u8, Vec<u8>) {
        let seq = self.seq;
        self.seq = self.seq.wrapping_add(1);
        let header = Header {
            coverage: self.coverage,
            ..Header::new(FC, dst, seq)
        };
        let mut buf = [0u8; MAX_FRAME_LEN];
        let n = k40t::encode(m, &header, &mut buf).unwrap();
        (seq, buf[..n].to_vec())
    }

    /// Runs the pod up to `t`, then sends `m` to the address its class uses; returns its
    /// sequence number.
    fn send<M: MessageData<Protocol = k40t::K40t>>(
        &mut self,
        pod: &mut SimPod,
        t: u64,
        m: &M,
    ) -> u8 {
        run(pod, self, t);
        let dst = if matches!(M::ID.base, 0x0010..=0x00FF) {
            GIMBAL
        } else {
            POD
        };
        let (seq, frame) = self.frame(dst, m);
        pod.receive(t, &frame);
        self.collect(pod, t);
        seq
    }

    /// Takes the pod's output at `t`.
    fn collect(&mut self, pod: &mut SimPod, t: u64) {
        let bytes = pod.transmit();
        let frames = &mut self.frames;
        self.deframer.push(&bytes, |ev| {
            if let Event::Frame(f) = ev {
                frames.push((t, f.to_vec()));
            }
        });
    }

    /// Every decoded frame with its instant.
    fn packets(&self) -> Vec<(u64, Packet<'_>)> {
        self.frames
            .iter()
            .map(|(t, f)| (*t, Packet::decode(f).unwrap()))
            .collect()
    }

    /// Every message `M` received, with instant and header.
    fn of<M: MessageData<Protocol = k40t::K40t>>(&self) -> Vec<(u64, Header, M)> {
        self.packets()
            .into_iter()
            .filter_map(|(t, p)| Some((t, p.header, p.message.get::<M>()?)))
            .collect()
    }

    /// Frames with the 24-bit id `id`.
    fn count(&self, id: u32) -> usize {
        self.packets()
            .iter()
            .filter(|(_, p)| p.message.id().to_u32() == id)
            .count()
    }

    /// The ACK of base id `base` with sequence number `seq`: (instant, header, payload).
    fn ack(&self, base: u16, seq: u8) -> Option<(u64, Header, Vec<u8>)> {
        self.frames.iter().find_map(|(t, f)| {
            let p = Packet::decode(f).ok()?;
            let id = p.message.id();
            (id == MsgId::new(Kind::Ack, base) && p.header.seq == seq)
                .then(|| (*t, p.header, f[10..f.len() - 2].to_vec()))
        })
    }

    fn clear(&mut self) {
        self.frames.clear();
    }
}

/// Runs the pod up to `until` (inclusive), waking it when it asks.
fn run(pod: &mut SimPod, fc: &mut Fc, until: u64) {
    loop {
        let t = pod.next_wakeup();
        if t > until {
            break;
        }
        pod.poll(t);
        fc.collect(pod, t);
    }
    pod.poll(until);
    fc.collect(pod, until);
}

fn default_pod() -> (SimPod, Fc) {
    let mut pod = SimPod::new(echoing());
    let mut fc = Fc::new();
    run(&mut pod, &mut fc, 0);
    fc.clear();
    (pod, fc)
}

fn control(yaw: YawMotion, pitch: PitchMotion) -> GimbalControl {
    GimbalControl {
        function: GimbalFunction::None,
        yaw,
        pitch,
        reserved: 0,
    }
}

fn quick(function: GimbalFunction) -> GimbalControl {
    GimbalControl {
        function,
        yaw: YawMotion::Stop,
        pitch: PitchMotion::Stop,
        reserved: 0,
    }
}

fn angle(pitch: PitchMotion, pitch_cdeg: u16, yaw: YawMotion, yaw_cdeg: u16) -> GimbalAngle {
    GimbalAngle {
        pitch_direction: pitch,
        pitch_cdeg,
        yaw_direction: yaw,
        yaw_cdeg,
        reserved: 0,
    }
}

fn photo(action: ShootAction) -> TakePhoto {
    TakePhoto {
        sensors: PhotoSensors::Default,
        action,
        ..TakePhoto::default()
    }
}

fn zoom(zoom_x10: u16) -> HybridZoom {
    HybridZoom { start: 0, zoom_x10 }
}

fn sync(unix_ms: u64) -> TimeSync {
    TimeSync {
        unix_ms,
        tz_minuteswest: -480,
        tz_dsttime: 0,
    }
}

/// The attitude report sent at `t`.
fn attitude_at(fc: &Fc, t: u64) -> GimbalAttitude {
    fc.of::<GimbalAttitude>()
        .into_iter()
        .find(|(at, _, _)| *at == t)
        .unwrap_or_else(|| panic!("no attitude report at {t}"))
        .2
}

fn ms_of_day(unix_ms: u64) -> (u8, u8, u8, u16) {
    let d = unix_ms % 86_400_000;
    (
        (d / 3_600_000) as u8,
        (d / 60_000 % 60) as u8,
        (d / 1000 % 60) as u8,
        (d % 1000) as u16,
    )
}

#[test]
fn reports_arrive_at_the_document_rates_with_incrementing_sequence_numbers() {
    let mut pod = SimPod::new(echoing());
    let mut fc = Fc::new();
    run(&mut pod, &mut fc, 10 * S - 1);

    // [0, 10 s): 2 Hz, 10 Hz, 1 Hz, 5 Hz, 5 Hz.
    assert_eq!(fc.count(0x00_0001), 20);
    assert_eq!(fc.count(0x00_0002), 100);
    assert_eq!(fc.count(0x00_0003), 10);
    assert_eq!(fc.count(0x00_0004), 50);
    assert_eq!(fc.count(0x00_0005), 50);
    assert_eq!(fc.frames.len(), 230);
    assert_eq!(fc.deframer.stats().checksum_errors, 0);
    assert_eq!(pod.sent_count(0x00_0002), 100);

    // Exactly periodic.
    let times: Vec<u64> = fc.of::<GimbalAttitude>().iter().map(|r| r.0).collect();
    assert_eq!(times.first(), Some(&0));
    assert!(times.windows(2).all(|w| w[1] - w[0] == 100 * MS));
    let times: Vec<u64> = fc.of::<GimbalStatus>().iter().map(|r| r.0).collect();
    assert!(times.windows(2).all(|w| w[1] - w[0] == 500 * MS));

    // Gimbal reports from 0x03/0x01, camera reports from 0x04/0x01, to the FC, default
    // coverage, one counter per source.
    let packets = fc.packets();
    for src in [GIMBAL, POD] {
        let seqs: Vec<u8> = packets
            .iter()
            .filter(|(_, p)| p.header.src == src)
            .map(|(_, p)| p.header.seq)
            .collect();
        let expected = if src == GIMBAL { 120 } else { 110 };
        assert_eq!(seqs.len(), expected);
        assert!(
            seqs.iter().enumerate().all(|(i, &s)| s == i as u8),
            "{src:?}"
        );
    }
    for (_, p) in &packets {
        assert_eq!(p.header.dst, FC);
        assert_eq!(p.header.coverage, CrcCoverage::ExcludeStx);
        let base = p.message.id().base;
        let src = if base <= 2 { GIMBAL } else { POD };
        assert_eq!(p.header.src, src, "{base:#x}");
    }

    // Report contents at rest.
    let s = fc.of::<GimbalStatus>()[0].2;
    assert!(s.links.gimbal_ok() && s.links.camera_ok());
    assert_eq!(s.self_test.0, 0x0F);
    let sys = fc.of::<SystemStatus>()[0].2;
    assert_eq!(sys.stream, ImageMode::Visible);
    assert_eq!(fc.of::<IrStatus>()[0].2, gimbal::sim::pod::IR_STATUS);
    let vis = fc.of::<VisibleStatus>()[0].2;
    assert_eq!((vis.zoom_x10, vis.zoom_state), (10, ZoomState::Done));
    assert_eq!(vis.focal_length_10um, 450);
}

#[test]
fn acks_echo_the_sequence_number_and_carry_the_documented_data() {
    let (mut pod, mut fc) = default_pod();

    // The reference ACK exchange of docs/src/protocols/k40t.md, byte for byte.
    fc.seq = 7;
    fc.send(&mut pod, 0, &zoom(45));
    let ack = fc.ack(0x0304, 7).unwrap();
    assert_eq!(
        fc.frames
            .iter()
            .find(|(_, f)| f[7..10] == [0x04, 0x03, 0x01])
            .unwrap()
            .1,
        [
            0xFD, 0x02, 0x02, 0x01, 0x07, 0x04, 0x01, 0x04, 0x03, 0x01, 0x00, 0x00, 0xE8, 0xEB
        ]
    );
    assert_eq!(ack.2, [0, 0]);

    fc.seq = 200;
    let s = fc.send(
        &mut pod,
        10 * MS,
        &GimbalVersionQuery {
            command: 1,
            reserved: 0,
        },
    );
    let (t, h, _) = fc.ack(0x0018, s).unwrap();
    assert_eq!((t, h.src, h.dst, h.seq), (10 * MS, GIMBAL, FC, 200));
    let v = fc.of::<GimbalVersionAck>()[0].2;
    assert!(v.code.is_ok());
    assert_eq!(
        v.hardware,
        Version {
            major: 1,
            minor: 0,
            patch: 0
        }
    );
    assert_eq!(
        v.software,
        Version {
            major: 1,
            minor: 2,
            patch: 3
        }
    );

    let s = fc.send(
        &mut pod,
        20 * MS,
        &CameraVersionQuery {
            command: 1,
            reserved: 0,
        },
    );
    assert_eq!(fc.ack(0x0317, s).unwrap().1.src, POD);
    let v = fc.of::<CameraVersionAck>()[0].2;
    assert_eq!(
        v.version,
        Version {
            major: 2,
            minor: 0,
            patch: 1
        }
    );

    let single = LaserRange {
        mode: LaserMode::Single,
        reserved: 0,
    };
    fc.send(&mut pod, 30 * MS, &single);
    pod.set_laser_distance_dm(567);
    fc.send(&mut pod, 40 * MS, &single);
    fc.send(
        &mut pod,
        50 * MS,
        &LaserRange {
            mode: LaserMode::Off,
            reserved: 0,
        },
    );
    let d: Vec<u16> = fc
        .of::<LaserDistance>()
        .iter()
        .map(|r| r.2.distance_dm)
        .collect();
    assert_eq!(d, [1234, 567, 0]);

    // A bare-code ACK for the others, seq wrapping past 255.
    fc.seq = 255;
    let s1 = fc.send(
        &mut pod,
        60 * MS,
        &IrPalette {
            palette: Palette::Rainbow,
            reserved: 0,
        },
    );
    let s2 = fc.send(
        &mut pod,
        70 * MS,
        &IrParamsQuery {
            command: 1,
            reserved: 0,
        },
    );
    assert_eq!((s1, s2), (255, 0));
    assert_eq!(fc.ack(0x0106, 255).unwrap().2, [0, 0]);
    let ir = fc.of::<IrParams>();
    assert_eq!((ir[0].1.seq, ir[0].2.palette), (0, Palette::Rainbow));

    // Every request above got exactly one ACK.
    let acks = fc
        .packets()
        .iter()
        .filter(|(_, p)| p.message.id().kind == Kind::Ack)
        .count();
    assert_eq!(acks, 8);
}

#[test]
fn motion_integrates_at_the_dial_speed_and_stops_at_the_limits() {
    let (mut pod, mut fc) = default_pod();
    assert_eq!(pod.gimbal().yaw_speed_dps, 10.0);
    // Pitch 20 °/s (100 x 0.2), yaw 10 °/s.
    let dial = DialSpeed {
        pitch_dps_x5: 100,
        yaw_dps_x5: 50,
        reserved: 0,
    };
    fc.send(&mut pod, 0, &dial);
    assert_eq!(pod.gimbal().pitch_speed_dps, 20.0);

    fc.send(&mut pod, S, &control(YawMotion::Right, PitchMotion::Stop));
    run(&mut pod, &mut fc, 3 * S);
    let a = attitude_at(&fc, 2 * S);
    assert_eq!(
        (a.yaw_joint_cdeg, a.yaw_cdeg, a.yaw_rate_cdeg_s),
        (1000, 1000, 1000)
    );
    assert_eq!((a.pitch_joint_cdeg, a.pitch_rate_cdeg_s), (0, 0));
    assert!((pod.gimbal().yaw_deg - 20.0).abs() < 1e-9);

    fc.send(&mut pod, 3 * S, &control(YawMotion::Stop, PitchMotion::Up));
    run(&mut pod, &mut fc, 6 * S);
    let a = attitude_at(&fc, 4 * S);
    assert_eq!((a.yaw_joint_cdeg, a.yaw_rate_cdeg_s), (2000, 0));
    assert_eq!((a.pitch_joint_cdeg, a.pitch_rate_cdeg_s), (2000, 2000));
    // +30° reached at 4.5 s: held there, rate 0.
    let a = attitude_at(&fc, 5 * S);
    assert_eq!((a.pitch_joint_cdeg, a.pitch_rate_cdeg_s), (3000, 0));
    let last = pod.last_motion().unwrap();
    assert_eq!(last.at_us, 3 * S);
    assert_eq!(
        last.command,
        MotionCommand::Control(control(YawMotion::Stop, PitchMotion::Up))
    );

    // Left and down; a new dial speed applies to the motion in progress.
    fc.send(
        &mut pod,
        6 * S,
        &control(YawMotion::Left, PitchMotion::Down),
    );
    run(&mut pod, &mut fc, 7 * S);
    let dial = DialSpeed {
        pitch_dps_x5: 5,
        yaw_dps_x5: 150,
        reserved: 0,
    };
    fc.send(&mut pod, 7 * S, &dial);
    run(&mut pod, &mut fc, 8 * S);
    let g = pod.gimbal();
    // Yaw: 20 − 10 − 30 = −20; pitch: 30 − 20 − 1 = 9.
    assert!((g.yaw_deg + 20.0).abs() < 1e-9, "{g:?}");
    assert!((g.pitch_deg - 9.0).abs() < 1e-9, "{g:?}");
    assert_eq!((g.yaw_rate_dps, g.pitch_rate_dps), (-30.0, -1.0));
    assert_eq!(pod.motions().len(), 5);
}

#[test]
fn angle_commands_centre_and_look_down_move_at_the_slew_speed() {
    let (mut pod, mut fc) = default_pod();
    // 45° down and 90° left at 45 °/s.
    fc.send(
        &mut pod,
        0,
        &angle(PitchMotion::Down, 4500, YawMotion::Left, 9000),
    );
    run(&mut pod, &mut fc, 3 * S);
    let a = attitude_at(&fc, S);
    assert_eq!((a.pitch_joint_cdeg, a.pitch_rate_cdeg_s), (-4500, 0));
    assert_eq!((a.yaw_joint_cdeg, a.yaw_rate_cdeg_s), (-4500, -4500));
    let a = attitude_at(&fc, 2 * S);
    assert_eq!((a.yaw_joint_cdeg, a.yaw_rate_cdeg_s), (-9000, 0));

    // Clamped to the limits; direction 2 leaves an axis alone.
    fc.send(
        &mut pod,
        3 * S,
        &angle(PitchMotion::Down, 12000, YawMotion::Stop, 0),
    );
    run(&mut pod, &mut fc, 5 * S);
    assert_eq!(attitude_at(&fc, 5 * S).pitch_joint_cdeg, -9000);
    assert_eq!(attitude_at(&fc, 5 * S).yaw_joint_cdeg, -9000);
    fc.send(
        &mut pod,
        5 * S,
        &angle(PitchMotion::Up, 5000, YawMotion::Right, 20000),
    );
    run(&mut pod, &mut fc, 15 * S);
    let g = pod.gimbal();
    assert_eq!((g.pitch_deg, g.yaw_deg), (30.0, 180.0));

    // Centre: both axes to 0 (yaw 180° away: 4 s).
    fc.send(&mut pod, 15 * S, &quick(GimbalFunction::Center));
    run(&mut pod, &mut fc, 19 * S);
    assert_eq!(attitude_at(&fc, 17 * S).yaw_joint_cdeg, 9000);
    let g = pod.gimbal();
    assert_eq!((g.pitch_deg, g.yaw_deg), (0.0, 0.0));

    // Look down: pitch −90°, yaw kept.
    fc.send(
        &mut pod,
        19 * S,
        &angle(PitchMotion::Stop, 0, YawMotion::Right, 3000),
    );
    run(&mut pod, &mut fc, 20 * S);
    fc.send(&mut pod, 20 * S, &quick(GimbalFunction::LookDown));
    run(&mut pod, &mut fc, 23 * S);
    let a = attitude_at(&fc, 23 * S);
    assert_eq!((a.pitch_joint_cdeg, a.yaw_joint_cdeg), (-9000, 3000));
}

#[test]
fn point_to_aim_turns_the_pixel_to_the_centre() {
    let (mut pod, mut fc) = default_pod();
    // At 1x (60° horizontal field), the right edge is 30° right; the bottom edge is
    // atan(tan 30° x 1080/1920) = 18.0° down.
    let aim = PointToAim {
        lens: Lens::Telephoto,
        zoom_x10: 10,
        x: 1920,
        y: 1080,
    };
    fc.send(&mut pod, 0, &aim);
    run(&mut pod, &mut fc, 2 * S);
    let g = pod.gimbal();
    let down = (30f64.to_radians().tan() * 1080.0 / 1920.0)
        .atan()
        .to_degrees();
    assert!((g.yaw_deg - 30.0).abs() < 1e-9, "{g:?}");
    assert!((g.pitch_deg + down).abs() < 1e-9, "{g:?}");
    assert_eq!(attitude_at(&fc, 2 * S).pitch_joint_cdeg, -1799);
    // At 10x the same pixel is ten times closer to the centre (in tangent).
    let aim = PointToAim {
        lens: Lens::Telephoto,
        zoom_x10: 100,
        x: 1920,
        y: 540,
    };
    fc.send(&mut pod, 2 * S, &aim);
    run(&mut pod, &mut fc, 5 * S);
    let expected = 30.0 + (30f64.to_radians().tan() / 10.0).atan().to_degrees();
    assert!((pod.gimbal().yaw_deg - expected).abs() < 1e-9);
    assert_eq!(pod.camera().zoom_x10, 100.0);
}

#[test]
fn a_photo_after_a_sync_asks_gps_for_the_synced_time_of_day() {
    let (mut pod, mut fc) = default_pod();
    let utc = NEW_YEAR_2026_MS + 12 * 3_600_000 + 34 * 60_000 + 56_789; // 12:34:56.789
    // Edge at 1 s, the frame arrives 2 ms later, the pin falls at 1.05 s.
    pod.rtc_edge(S, true);
    fc.send(&mut pod, S + 2 * MS, &sync(utc));
    pod.rtc_edge(S + 50 * MS, false);
    assert!(fc.ack(0x030E, 0).unwrap().2 == [0, 0]);

    let rec = pod.syncs()[0];
    assert_eq!(rec.outcome, SyncOutcome::Applied);
    assert_eq!(rec.edge_us, Some(S));
    assert_eq!(
        (rec.frame_start_us, rec.arrival_us),
        (S + 2 * MS, S + 2 * MS)
    );
    assert_eq!(rec.delay_us, Some(2 * MS));
    assert_eq!((rec.unix_ms, rec.tz_minuteswest), (utc, -480));
    assert!(pod.is_synced());
    assert_eq!(pod.clock_unix_ms(S), utc);
    assert_eq!(pod.clock_unix_ms(5 * S), utc + 4000);
    assert_eq!(pod.rtc_edges().len(), 2);

    // Photo at 5 s: ACK at once, GPS request 20 ms later for 12:35:00.809.
    fc.clear();
    let seq = fc.send(&mut pod, 5 * S, &photo(ShootAction::Start));
    run(&mut pod, &mut fc, 5 * S + 100 * MS);
    let (t_ack, _, code) = fc.ack(0x0302, seq).unwrap();
    assert_eq!((t_ack, code), (5 * S, vec![0, 0]));
    let requests = fc.of::<GpsRequest>();
    assert_eq!(requests.len(), 1);
    let (t, h, q) = requests[0];
    assert_eq!(t, 5 * S + 20 * MS);
    assert_eq!((h.src, h.dst), (POD, FC));
    assert_eq!(
        (q.lens_enable, q.hour, q.minute, q.second, q.millisecond),
        (1, 12, 35, 0, 809)
    );
    assert_eq!(ms_of_day(utc + 4020), (12, 35, 0, 809));
    let order: Vec<u32> = fc
        .packets()
        .iter()
        .map(|(_, p)| p.message.id().to_u32())
        .filter(|&id| id & 0xFFFF == 0x0302 || id == 0x00_0310)
        .collect();
    assert_eq!(order, [0x01_0302, 0x00_0310]);
    // A single shot has no status frame.
    assert_eq!(fc.count(0x02_0302), 0);

    // The FC answers with the same sequence number.
    let reply = GpsReply {
        code: ResponseCode::OK,
        hour: q.hour,
        minute: q.minute,
        second: q.second,
        millisecond: q.millisecond,
        lon_e7: 1_134_567_890,
        lat_e7: 225_432_100,
        rel_alt_dm: 1234,
        alt_msl_dm: 5678,
        yaw_cdeg: 9000,
        roll_cdeg: -150,
        pitch_cdeg: 250,
    };
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = k40t::encode(&reply, &Header::new(FC, POD, h.seq), &mut buf).unwrap();
    pod.receive(5 * S + 100 * MS, &buf[..n]);
    run(&mut pod, &mut fc, 10 * S);

    let r = pod.gps_replies()[0];
    assert_eq!(r.reply, reply);
    assert_eq!(r.request, Some(0));
    assert_eq!(r.latency_us, Some(80 * MS));
    assert!(r.time_matches && !r.late);
    let photo = pod.photos()[0];
    assert_eq!(
        (photo.at_us, photo.pod_unix_ms),
        (5 * S + 20 * MS, utc + 4020)
    );
    assert_eq!(photo.gps_request, Some(0));
    let req = pod.gps_requests()[0];
    assert_eq!(
        (req.seq, req.reply, req.synced, req.timed_out),
        (h.seq, Some(0), true, false)
    );
    assert_eq!(pod.gps_unanswered(), 0);
    assert_eq!(pod.camera().photos_taken, 1);
    // The reply is an ACK: the pod does not acknowledge it.
    assert_eq!(fc.count(0x01_0310), 0);
}

#[test]
fn sync_errors_are_recorded_and_not_applied() {
    let (mut pod, mut fc) = default_pod();
    // No edge at all.
    fc.send(&mut pod, S, &sync(NEW_YEAR_2026_MS));
    // Edge 200 ms before the frame (window 100 ms).
    pod.rtc_edge(2 * S, true);
    pod.rtc_edge(2 * S + 50 * MS, false);
    fc.send(&mut pod, 2 * S + 200 * MS, &sync(NEW_YEAR_2026_MS));
    assert!(!pod.is_synced());
    assert_eq!(pod.clock_unix_ms(3 * S), 3000, "free-running since 0");

    // A good one, then a second frame for the same (consumed) edge.
    pod.rtc_edge(3 * S, true);
    fc.send(&mut pod, 3 * S + 500, &sync(NEW_YEAR_2026_MS));
    fc.send(&mut pod, 3 * S + 10 * MS, &sync(NEW_YEAR_2026_MS + 999));
    pod.rtc_edge(3 * S + 50 * MS, false);

    // The edge rises while the frame is arriving: first half at 4 s, edge, second half.
    let (_, frame) = fc.frame(POD, &sync(NEW_YEAR_2026_MS + 60_000));
    pod.receive(4 * S, &frame[..10]);
    pod.rtc_edge(4 * S + MS, true);
    pod.receive(4 * S + 2 * MS, &frame[10..]);
    pod.rtc_edge(4 * S + 50 * MS, false);
    fc.collect(&mut pod, 4 * S + 2 * MS);

    let outcomes: Vec<SyncOutcome> = pod.syncs().iter().map(|s| s.outcome).collect();
    assert_eq!(
        outcomes,
        [
            SyncOutcome::NoEdge,
            SyncOutcome::EdgeTooOld,
            SyncOutcome::Applied,
            SyncOutcome::NoEdge,
            SyncOutcome::EdgeAfterFrameStart,
        ]
    );
    let s = pod.syncs();
    assert_eq!((s[0].edge_us, s[0].delay_us), (None, None));
    assert_eq!((s[1].edge_us, s[1].delay_us), (Some(2 * S), Some(200 * MS)));
    assert_eq!(s[2].delay_us, Some(500));
    assert_eq!(
        (
            s[4].frame_start_us,
            s[4].arrival_us,
            s[4].edge_us,
            s[4].delay_us
        ),
        (4 * S, 4 * S + 2 * MS, Some(4 * S + MS), None)
    );
    // Only the good one set the clock: 3 s reads New Year.
    assert_eq!(pod.clock_unix_ms(3 * S), NEW_YEAR_2026_MS);
    assert_eq!(pod.clock_unix_ms(5 * S), NEW_YEAR_2026_MS + 2000);
    // Every sync is ACKed OK regardless.
    assert_eq!(fc.count(0x01_030E), 5);
}

#[test]
fn clock_error_drift_unsynced_and_local_time_options() {
    // A pod that adds 3 ms when it sets its clock and runs 100 ppm fast.
    let config = PodSimConfig {
        sync_error_us: 3000,
        clock_drift_ppm: 100,
        gps_local_time: true,
        ..echoing()
    };
    let mut pod = SimPod::new(config);
    let mut fc = Fc::new();
    run(&mut pod, &mut fc, 0);
    // Unsynchronised: asks with its free-running clock (1.0001 x 2.02 s after 0).
    fc.send(&mut pod, 2 * S, &photo(ShootAction::Start));
    run(&mut pod, &mut fc, 2 * S + 100 * MS);
    let q = fc.of::<GpsRequest>()[0].2;
    assert_eq!((q.hour, q.minute, q.second, q.millisecond), (0, 0, 2, 20));
    assert!(!pod.gps_requests()[0].synced);

    pod.rtc_edge(3 * S, true);
    fc.send(&mut pod, 3 * S, &sync(NEW_YEAR_2026_MS));
    assert_eq!(pod.clock_unix_ms(3 * S), NEW_YEAR_2026_MS + 3);
    // 10 s later: +10 000 ms, +1 ms of drift.
    assert_eq!(pod.clock_unix_ms(13 * S), NEW_YEAR_2026_MS + 10_004);
    // Local time: tz_minuteswest −480 is UTC+8.
    fc.send(&mut pod, 13 * S - 20 * MS, &photo(ShootAction::Start));
    run(&mut pod, &mut fc, 13 * S + 100 * MS);
    let q = fc.of::<GpsRequest>()[1].2;
    assert_eq!((q.hour, q.minute, q.second, q.millisecond), (8, 0, 10, 4));

    // A pod that does not ask while unsynchronised.
    let config = PodSimConfig {
        gps_when_unsynced: false,
        ..echoing()
    };
    let mut pod = SimPod::new(config);
    let mut fc = Fc::new();
    fc.send(&mut pod, 0, &photo(ShootAction::Start));
    run(&mut pod, &mut fc, S);
    assert_eq!(pod.photos().len(), 1);
    assert_eq!(pod.photos()[0].gps_request, None);
    assert_eq!(fc.count(0x00_0310), 0);
}

#[test]
fn gps_requests_without_an_answer_are_counted() {
    let (mut pod, mut fc) = default_pod();
    fc.send(&mut pod, 0, &photo(ShootAction::Start));
    run(&mut pod, &mut fc, 500 * MS);
    assert_eq!(pod.gps_unanswered(), 0);
    run(&mut pod, &mut fc, 1020 * MS);
    // Timeout 1 s after the request (sent at 20 ms).
    assert_eq!(pod.gps_unanswered(), 1);
    assert!(pod.gps_requests()[0].timed_out);

    // A reply with the wrong sequence number matches nothing; a late one is recorded.
    let seq = pod.gps_requests()[0].seq;
    let reply = GpsReply {
        code: ResponseCode::OK,
        ..GpsReply::default()
    };
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = k40t::encode(&reply, &Header::new(FC, POD, seq.wrapping_add(9)), &mut buf).unwrap();
    pod.receive(1100 * MS, &buf[..n]);
    let n = k40t::encode(&reply, &Header::new(FC, POD, seq), &mut buf).unwrap();
    pod.receive(1200 * MS, &buf[..n]);
    let r = pod.gps_replies();
    assert_eq!(r.len(), 2);
    assert_eq!((r[0].request, r[0].late), (None, false));
    assert_eq!(
        (r[1].request, r[1].late, r[1].latency_us),
        (Some(0), true, Some(1180 * MS))
    );
    assert!(
        !r[1].time_matches,
        "00:00:00.000 was not the requested time"
    );
    assert_eq!(pod.gps_unanswered(), 1);
}

#[test]
fn burst_and_time_lapse_photos_send_status_frames_and_one_gps_request_per_shot() {
    let (mut pod, mut fc) = default_pod();
    let burst = PhotoParams {
        mode: PhotoMode::Burst,
        timelapse_s: 5,
        burst_count: 3,
        reserved: 0,
    };
    fc.send(&mut pod, 0, &burst);
    fc.send(&mut pod, S, &photo(ShootAction::Start));
    // A second photo request while the burst runs.
    let busy = fc.send(&mut pod, S + 100 * MS, &photo(ShootAction::Start));
    run(&mut pod, &mut fc, 3 * S);
    let code = ResponseCode {
        raw: fc.ack(0x0302, busy).unwrap().2[..2].try_into().unwrap(),
    };
    assert_eq!(code.code(), AckCode::PhotoInProgress);
    let shots: Vec<u64> = fc.of::<GpsRequest>().iter().map(|r| r.0).collect();
    assert_eq!(shots, [S + 20 * MS, S + 320 * MS, S + 620 * MS]);
    let status: Vec<(PhotoState, u16)> = fc
        .of::<PhotoStatus>()
        .iter()
        .map(|r| (r.2.state, r.2.burst_count))
        .collect();
    assert_eq!(
        status,
        [
            (PhotoState::Burst, 1),
            (PhotoState::Burst, 2),
            (PhotoState::Burst, 3),
            (PhotoState::Taken, 3)
        ]
    );
    let shot_numbers: Vec<u16> = pod.photos().iter().map(|p| p.shot).collect();
    assert_eq!(shot_numbers, [1, 2, 3]);

    // Time-lapse every 5 s until stopped.
    fc.clear();
    let lapse = PhotoParams {
        mode: PhotoMode::TimeLapse,
        timelapse_s: 5,
        burst_count: 3,
        reserved: 0,
    };
    fc.send(&mut pod, 3 * S, &lapse);
    fc.send(&mut pod, 4 * S, &photo(ShootAction::Start));
    run(&mut pod, &mut fc, 16 * S);
    fc.send(&mut pod, 16 * S, &photo(ShootAction::Stop));
    run(&mut pod, &mut fc, 30 * S);
    let shots: Vec<u64> = fc.of::<GpsRequest>().iter().map(|r| r.0).collect();
    assert_eq!(shots, [4 * S + 20 * MS, 9 * S + 20 * MS, 14 * S + 20 * MS]);
    let status: Vec<(u64, PhotoState, u16)> = fc
        .of::<PhotoStatus>()
        .iter()
        .map(|r| (r.0, r.2.state, r.2.burst_count))
        .collect();
    assert_eq!(status.last(), Some(&(16 * S, PhotoState::Stopped, 3)));
    assert_eq!(status.len(), 4);
    assert_eq!(
        fc.of::<SystemStatus>().last().unwrap().2.photo_mode,
        PhotoMode::TimeLapse
    );
}

#[test]
fn single_shot_status_and_capture_mode_enforcement_are_options() {
    let config = PodSimConfig {
        single_shot_status: true,
        enforce_capture_mode: true,
        ..echoing()
    };
    let mut pod = SimPod::new(config);
    let mut fc = Fc::new();
    fc.send(&mut pod, 0, &photo(ShootAction::Start));
    run(&mut pod, &mut fc, S);
    let states: Vec<PhotoState> = fc.of::<PhotoStatus>().iter().map(|r| r.2.state).collect();
    assert_eq!(states, [PhotoState::SingleShot, PhotoState::Taken]);

    // Photo mode: recording is refused.
    let rec = Record {
        sensors: RecordSensors::Stream,
        action: RecordAction::Start,
        ..Record::default()
    };
    let seq = fc.send(&mut pod, S, &rec);
    assert_eq!(fc.ack(0x0303, seq).unwrap().2, [0x00, 0x01]);
    assert!(pod.camera().recording.is_none());
}

#[test]
fn recording_reports_its_status_every_second() {
    let (mut pod, mut fc) = default_pod();
    let mut rec = Record {
        sensors: RecordSensors::Both,
        action: RecordAction::Start,
        ..Record::default()
    };
    fc.send(&mut pod, S, &rec);
    // Starting again does not restart or stop it.
    fc.send(&mut pod, 2500 * MS, &rec);
    run(&mut pod, &mut fc, 4 * S);
    rec.action = RecordAction::Stop;
    fc.send(&mut pod, 4500 * MS, &rec);
    run(&mut pod, &mut fc, 8 * S);
    let status: Vec<(u64, RecordState, u16)> = fc
        .of::<RecordStatus>()
        .iter()
        .map(|r| (r.0, r.2.state, r.2.elapsed_s))
        .collect();
    assert_eq!(
        status,
        [
            (S, RecordState::Recording, 0),
            (2 * S, RecordState::Recording, 1),
            (3 * S, RecordState::Recording, 2),
            (4 * S, RecordState::Recording, 3),
            (4500 * MS, RecordState::Stopped, 3),
        ]
    );
    assert!(
        fc.of::<RecordStatus>()
            .iter()
            .all(|r| r.2.sensors == RecordSensors::Both)
    );
    // The 1 s report went out before the request was handled; video mode from 2 s.
    let modes: Vec<(u64, k40t::CaptureMode)> = fc
        .of::<SystemStatus>()
        .iter()
        .map(|r| (r.0, r.2.mode))
        .collect();
    assert_eq!(modes[0], (S, k40t::CaptureMode::Photo));
    assert_eq!(modes[1], (2 * S, k40t::CaptureMode::Video));
    assert!(pod.camera().recording.is_none());
}

#[test]
fn hybrid_zoom_moves_towards_the_target_with_status_frames() {
    let (mut pod, mut fc) = default_pod();
    let seq = fc.send(&mut pod, 0, &zoom(100));
    run(&mut pod, &mut fc, 4 * S);
    assert!(fc.ack(0x0304, seq).is_some());
    // 1x -> 10x at ln(10) per... 1.0/s: 2.302585 s.
    let status: Vec<(u64, ZoomState)> = fc
        .of::<ZoomStatus>()
        .iter()
        .map(|r| (r.0, r.2.state))
        .collect();
    assert_eq!(status.len(), 13);
    for (i, (t, state)) in status[..12].iter().enumerate() {
        assert_eq!((*t, *state), (i as u64 * 200 * MS, ZoomState::Zooming));
    }
    let (done_at, done) = status[12];
    assert_eq!(done, ZoomState::Done);
    assert!((2_302_585..=2_302_587).contains(&done_at), "{done_at}");
    // The ACK comes first.
    assert_eq!(fc.packets()[0].1.message.id().to_u32(), 0x01_0304);

    let vis = fc.of::<VisibleStatus>();
    assert!(vis.windows(2).all(|w| w[1].2.zoom_x10 >= w[0].2.zoom_x10));
    let at = |t: u64| vis.iter().find(|r| r.0 == t).unwrap().2;
    // e^1 after 1 s: 27.18 -> 27.
    assert_eq!((at(S).zoom_x10, at(S).zoom_state), (27, ZoomState::Zooming));
    assert_eq!(at(S).focal_length_10um, 1223);
    assert_eq!(
        (at(3 * S).zoom_x10, at(3 * S).zoom_state),
        (100, ZoomState::Done)
    );
    assert_eq!(at(3 * S).focal_length_10um, 4500);

    // Beyond the optical part the focal length stays at 11x; the ratio is clamped.
    fc.send(&mut pod, 4 * S, &zoom(5000));
    run(&mut pod, &mut fc, 10 * S);
    assert_eq!(pod.camera().zoom_x10, 1600.0);
    let last = fc.of::<VisibleStatus>().last().unwrap().2;
    assert_eq!((last.zoom_x10, last.focal_length_10um), (1600, 4950));
}

#[test]
fn continuous_zoom_steps_and_focus() {
    let (mut pod, mut fc) = default_pod();
    let cz = |control| ContinuousZoom {
        control,
        reserved: 0,
    };
    fc.send(&mut pod, 0, &cz(ZoomControl::In));
    run(&mut pod, &mut fc, S);
    fc.send(&mut pod, S, &cz(ZoomControl::Stop));
    assert!((pod.camera().zoom_x10 - 10.0 * 1f64.exp()).abs() < 1e-9);
    assert!(!pod.camera().zooming);
    fc.send(&mut pod, S, &cz(ZoomControl::StepIn));
    run(&mut pod, &mut fc, 2 * S);
    assert_eq!(pod.camera().zoom_x10, 37.0);
    fc.send(&mut pod, 2 * S, &cz(ZoomControl::Out));
    run(&mut pod, &mut fc, 5 * S);
    assert_eq!(pod.camera().zoom_x10, 10.0);
    assert!(!pod.camera().zooming, "stops at the limit");
    assert_eq!(
        fc.count(0x02_0304),
        0,
        "no status frames for continuous zoom"
    );

    // Auto focus: focusing for 0.5 s.
    let focus = |mode| Focus {
        mode,
        ..Focus::default()
    };
    fc.clear();
    fc.send(&mut pod, 5 * S, &focus(FocusMode::Auto));
    run(&mut pod, &mut fc, 6 * S);
    let states: Vec<(u64, FocusState)> = fc
        .of::<VisibleStatus>()
        .iter()
        .map(|r| (r.0, r.2.focus))
        .collect();
    assert_eq!(states[0], (5200 * MS, FocusState::Focusing));
    assert_eq!(states[1], (5400 * MS, FocusState::Focusing));
    assert_eq!(states[2], (5600 * MS, FocusState::Done));
    // Auto focus after zoom.
    fc.send(&mut pod, 6 * S, &focus(FocusMode::AfAfterZoomOn));
    fc.send(&mut pod, 6 * S, &zoom(20));
    run(&mut pod, &mut fc, 8 * S);
    let vis = fc.of::<VisibleStatus>();
    let at = |t: u64| vis.iter().find(|r| r.0 == t).unwrap().2;
    // 1x -> 2x takes ln 2 = 0.69 s: focusing from 6.69 s to 7.19 s.
    assert_eq!(at(6800 * MS).focus, FocusState::Focusing);
    assert_eq!(at(7200 * MS).focus, FocusState::Done);
    assert_eq!(pod.camera().focus, Some(FocusMode::AfAfterZoomOn));
}

#[test]
fn laser_periodic_ranging_reports_every_second_until_disabled() {
    let (mut pod, mut fc) = default_pod();
    let on = LaserPeriodic {
        enable: OnOff::On,
        reserved: 0,
    };
    fc.send(&mut pod, S, &on);
    run(&mut pod, &mut fc, 2500 * MS);
    pod.set_laser_distance_dm(500);
    run(&mut pod, &mut fc, 3500 * MS);
    fc.send(
        &mut pod,
        3500 * MS,
        &LaserPeriodic {
            enable: OnOff::Off,
            reserved: 0,
        },
    );
    run(&mut pod, &mut fc, 6 * S);
    let status: Vec<(u64, u16)> = fc
        .of::<LaserPeriodicStatus>()
        .iter()
        .map(|r| (r.0, r.2.0.distance_dm))
        .collect();
    assert_eq!(status, [(S, 1234), (2 * S, 1234), (3 * S, 500)]);
    assert!(
        fc.of::<LaserPeriodicStatus>()
            .iter()
            .all(|r| r.2.0.code.is_ok())
    );
}

#[test]
fn settings_show_in_reports_and_tracking_needs_ai() {
    let (mut pod, mut fc) = default_pod();
    fc.send(
        &mut pod,
        0,
        &ImageModeSetting {
            mode: ImageMode::Split,
            reserved: 0,
        },
    );
    fc.send(
        &mut pod,
        0,
        &IrMeasurement {
            switch: MeasureSwitch::Off,
            reserved: 0,
        },
    );
    run(&mut pod, &mut fc, 2 * S);
    assert_eq!(
        fc.of::<SystemStatus>().last().unwrap().2.stream,
        ImageMode::Split
    );
    assert_eq!(fc.count(0x00_0004), 0, "IR measurement off: no 0x000004");
    fc.send(
        &mut pod,
        2 * S,
        &IrParamsQuery {
            command: 1,
            reserved: 0,
        },
    );
    assert!(!fc.of::<IrParams>()[0].2.measure.measuring());

    // Tracking without AI is refused; with AI it blocks motion until switched off.
    let track = TrackBox {
        enable: Toggle::On,
        x: 900,
        y: 500,
        width: 120,
        height: 80,
        reserved: 0,
    };
    let seq = fc.send(&mut pod, 2 * S, &track);
    assert_eq!(fc.ack(0x0324, seq).unwrap().2, [0x00, 0x01]);
    assert_eq!(pod.camera().track, None);
    let ai = AiRecognition {
        enable: Toggle::On,
        model: 0,
        classes: [0; 10],
    };
    fc.send(&mut pod, 2 * S, &ai);
    let seq = fc.send(&mut pod, 2 * S, &track);
    assert_eq!(fc.ack(0x0324, seq).unwrap().2, [0, 0]);
    let seq = fc.send(
        &mut pod,
        2 * S,
        &control(YawMotion::Right, PitchMotion::Stop),
    );
    assert_eq!(fc.ack(0x0010, seq).unwrap().2, [0, 0]);
    run(&mut pod, &mut fc, 3 * S);
    assert_eq!(pod.gimbal().yaw_deg, 0.0);
    assert!(!pod.last_motion().unwrap().applied);
    fc.send(
        &mut pod,
        3 * S,
        &TrackBox {
            enable: Toggle::Off,
            ..track
        },
    );
    fc.send(
        &mut pod,
        3 * S,
        &control(YawMotion::Right, PitchMotion::Stop),
    );
    run(&mut pod, &mut fc, 4 * S);
    assert!((pod.gimbal().yaw_deg - 10.0).abs() < 1e-9);
    assert!(pod.last_motion().unwrap().applied);
}

#[test]
fn nak_injection_refuses_the_command_and_dropped_acks_still_execute_it() {
    let mut config = echoing();
    config.nak.insert(0x0304, AckCode::Failure);
    config.nak.insert(0x0400, AckCode::CameraOpenFailed);
    let mut pod = SimPod::new(config);
    let mut fc = Fc::new();
    let seq = fc.send(&mut pod, 0, &zoom(100));
    run(&mut pod, &mut fc, 3 * S);
    assert_eq!(fc.ack(0x0304, seq).unwrap().2, [0x00, 0x01]);
    assert_eq!(pod.camera().zoom_x10, 10.0);
    assert_eq!(fc.count(0x02_0304), 0);
    // An ACK with data keeps its layout, data zeroed.
    let seq = fc.send(
        &mut pod,
        3 * S,
        &LaserRange {
            mode: LaserMode::Single,
            reserved: 0,
        },
    );
    assert_eq!(fc.ack(0x0400, seq).unwrap().2, [0x02, 0x02, 0x00, 0x00]);

    pod.set_nak(0x0304, None);
    let seq = fc.send(&mut pod, 3 * S, &zoom(100));
    run(&mut pod, &mut fc, 6 * S);
    assert_eq!(fc.ack(0x0304, seq).unwrap().2, [0, 0]);
    assert_eq!(pod.camera().zoom_x10, 100.0);

    // The first two ACKs of 0x000010 are lost; the commands run anyway.
    pod.drop_acks(0x0010, 2);
    let seqs: Vec<u8> = (0..3)
        .map(|i| {
            fc.send(
                &mut pod,
                6 * S + i * MS,
                &control(YawMotion::Right, PitchMotion::Stop),
            )
        })
        .collect();
    assert!(fc.ack(0x0010, seqs[0]).is_none());
    assert!(fc.ack(0x0010, seqs[1]).is_none());
    assert!(fc.ack(0x0010, seqs[2]).is_some());
    assert_eq!(pod.acks_dropped(), 2);
    assert_eq!(pod.motions().len(), 3);
    run(&mut pod, &mut fc, 7 * S);
    assert!(pod.gimbal().yaw_deg > 9.9);

    // Little-endian response codes.
    let mut config = PodSimConfig {
        ack_code_le: true,
        ..echoing()
    };
    config.nak.insert(0x0302, AckCode::PhotoInProgress);
    let mut pod = SimPod::new(config);
    let seq = fc.send(&mut pod, 0, &photo(ShootAction::Start));
    assert_eq!(fc.ack(0x0302, seq).unwrap().2, [0x03, 0x02]);
    assert!(pod.photos().is_empty());
}

#[test]
fn ack_delay_delays_the_ack_and_what_follows_it() {
    let config = PodSimConfig {
        ack_delay_us: 30 * MS,
        ..echoing()
    };
    let mut pod = SimPod::new(config);
    let mut fc = Fc::new();
    run(&mut pod, &mut fc, 0);
    fc.clear();
    let seq = fc.send(&mut pod, 10 * MS, &zoom(20));
    assert!(fc.ack(0x0304, seq).is_none());
    run(&mut pod, &mut fc, 100 * MS);
    let (t, ..) = fc.ack(0x0304, seq).unwrap();
    assert_eq!(t, 40 * MS);
    let z = fc.of::<ZoomStatus>();
    assert_eq!((z[0].0, z[0].2.state), (40 * MS, ZoomState::Zooming));
    let ids: Vec<u32> = fc
        .packets()
        .iter()
        .map(|(_, p)| p.message.id().to_u32())
        .collect();
    let ack = ids.iter().position(|&i| i == 0x01_0304).unwrap();
    let status = ids.iter().position(|&i| i == 0x02_0304).unwrap();
    assert!(ack < status);
}

#[test]
fn silent_mode_cuts_the_cable_both_ways() {
    let (mut pod, mut fc) = default_pod();
    run(&mut pod, &mut fc, S);
    let before = fc.frames.len();
    let last_gimbal_seq = fc
        .packets()
        .iter()
        .filter(|(_, p)| p.header.src == GIMBAL)
        .map(|(_, p)| p.header.seq)
        .next_back()
        .unwrap();

    pod.set_silent(true);
    assert!(pod.is_silent());
    let (_, frame) = fc.frame(POD, &zoom(100));
    pod.receive(1500 * MS, &frame);
    pod.rtc_edge(1600 * MS, true);
    run(&mut pod, &mut fc, 3 * S);
    assert_eq!(fc.frames.len(), before, "nothing out");
    assert_eq!(pod.camera().zoom_x10, 10.0, "nothing in");
    assert!(pod.rtc_edges().is_empty());
    assert_eq!(pod.rx_stats().dropped_while_silent, frame.len() as u64);
    assert_eq!(pod.received_count(0x00_0304), 0);
    // (1 s, 3 s]: 20 attitude, 4 gimbal status, 2 system, 10 IR, 10 visible reports.
    assert_eq!(pod.lost_while_silent(), 46);

    pod.set_silent(false);
    run(&mut pod, &mut fc, 4 * S);
    let first_after = fc.packets()[before..]
        .iter()
        .find(|(_, p)| p.header.src == GIMBAL)
        .map(|(t, p)| (*t, p.header.seq))
        .unwrap();
    assert_eq!(first_after.0, 3100 * MS);
    // The 24 lost gimbal frames consumed their numbers.
    assert_eq!(first_after.1, last_gimbal_seq.wrapping_add(1 + 4 + 20));
    fc.send(&mut pod, 4 * S, &zoom(100));
    assert_eq!(pod.received_count(0x00_0304), 1);
}

#[test]
fn crc_coverage_and_addresses_are_configurable() {
    let config = PodSimConfig {
        coverage: CrcCoverage::IncludeStx,
        gimbal_address: POD,
        ..echoing()
    };
    let mut pod = SimPod::new(config);
    let mut fc = Fc::with(CrcCoverage::IncludeStx);
    run(&mut pod, &mut fc, S);
    // [0, 1 s]: 3 + 11 + 2 + 6 + 6 reports.
    assert_eq!(fc.frames.len(), 28);
    for (_, p) in fc.packets() {
        assert_eq!(p.header.coverage, CrcCoverage::IncludeStx);
        assert_eq!(p.header.src, POD);
    }
    // One sequence counter for the one address.
    let seqs: Vec<u8> = fc.packets().iter().map(|(_, p)| p.header.seq).collect();
    assert!(seqs.iter().enumerate().all(|(i, &s)| s == i as u8));

    // The pod accepts only its own coverage.
    let mut other = Fc::with(CrcCoverage::ExcludeStx);
    let seq = other.send(&mut pod, S, &zoom(20));
    fc.collect(&mut pod, S);
    assert!(fc.ack(0x0304, seq).is_none());
    assert_eq!(pod.rx_stats().deframer.checksum_errors, 1);
    let seq = fc.send(&mut pod, S, &zoom(20));
    let (_, h, _) = fc.ack(0x0304, seq).unwrap();
    assert_eq!((h.src, h.coverage), (POD, CrcCoverage::IncludeStx));

    // Either coverage, when configured.
    let config = PodSimConfig {
        accept_any_coverage: true,
        ..echoing()
    };
    let mut pod = SimPod::new(config);
    let mut fc = Fc::new();
    let a = fc.send(&mut pod, 0, &zoom(20));
    let mut include = Fc::with(CrcCoverage::IncludeStx);
    include.seq = 50;
    let (_, frame) = include.frame(POD, &zoom(20));
    pod.receive(0, &frame);
    fc.collect(&mut pod, 0);
    assert!(fc.ack(0x0304, a).is_some());
    assert_eq!(pod.received_count(0x00_0304), 2);
    assert_eq!(
        fc.count(0x01_0304),
        2,
        "both ACKed, with the pod's own coverage"
    );

    // Strict destination: 0x05/0x01 is ignored, the gimbal and camera addresses are not.
    let config = PodSimConfig {
        strict_destination: true,
        ..echoing()
    };
    let mut pod = SimPod::new(config);
    let mut fc = Fc::new();
    let (seq, frame) = fc.frame(Address::new(0x05, 0x01), &zoom(20));
    pod.receive(0, &frame);
    fc.collect(&mut pod, 0);
    assert!(fc.ack(0x0304, seq).is_none());
    assert_eq!(pod.rx_stats().misaddressed, 1);
    let (seq, frame) = fc.frame(GIMBAL, &zoom(20));
    pod.receive(0, &frame);
    fc.collect(&mut pod, 0);
    assert!(fc.ack(0x0304, seq).is_some());
}

#[test]
fn received_frames_are_counted_per_id_and_in_bytes() {
    let (mut pod, mut fc) = default_pod();
    let mut bytes = 0;
    for i in 0..5u64 {
        let (_, f) = fc.frame(GIMBAL, &control(YawMotion::Stop, PitchMotion::Stop));
        bytes += f.len();
        pod.receive(i * 100 * MS, &f);
    }
    let (_, f) = fc.frame(POD, &zoom(30));
    bytes += f.len();
    pod.receive(S, &f);
    assert_eq!(pod.received_count(0x00_0010), 5);
    assert_eq!(pod.received_count(0x00_0304), 1);
    assert_eq!(pod.received_count(0x00_0302), 0);
    let stats = pod.rx_stats();
    assert_eq!((stats.bytes, stats.frames), (bytes as u64, 6));
    let controls = pod.received_of::<GimbalControl>();
    assert_eq!(controls.len(), 5);
    assert_eq!(
        (controls[3].0, controls[3].1.seq, controls[3].1.dst),
        (300 * MS, 3, GIMBAL)
    );
    assert_eq!(pod.received()[5].id, HybridZoom::ID);
    pod.clear_records();
    assert!(pod.received().is_empty() && pod.sent().is_empty());
    assert_eq!(pod.received_count(0x00_0010), 5);
    assert_eq!(pod.sent_count(0x00_0002), 11, "counters stay");

    // Frames the bridge should not send are counted, not answered.
    let (_, f) = fc.frame(GIMBAL, &GimbalStatus::default());
    pod.receive(S, &f);
    let unknown = Packet {
        header: Header::new(FC, POD, 99),
        message: Message::Raw(Raw {
            id: MsgId::new(Kind::Request, 0x0399),
            payload: &[1, 0],
        }),
    };
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = unknown.emit(&mut buf).unwrap();
    pod.receive(S, &buf[..n]);
    fc.collect(&mut pod, S);
    assert_eq!(pod.received_count(0x00_0001), 1);
    assert_eq!(pod.received_count(0x00_0399), 1);
    assert!(fc.ack(0x0001, 6).is_none());
    assert!(fc.ack(0x0399, 99).is_none());

    let config = PodSimConfig {
        ack_unknown: true,
        ..echoing()
    };
    let mut pod = SimPod::new(config);
    pod.receive(0, &buf[..n]);
    fc.collect(&mut pod, 0);
    assert_eq!(fc.ack(0x0399, 99).unwrap().2, [0, 0]);
}

#[test]
fn garbage_bit_flips_and_cut_frames_on_the_input_are_survived() {
    let (mut pod, mut fc) = default_pod();
    let (bad_seq, mut bad) = fc.frame(POD, &zoom(30));
    bad[12] ^= 0x10;
    let (good_seq, good) = fc.frame(POD, &zoom(40));
    let mut chunk = vec![0x00, 0xFD, 0xFF, 0x12, 0xFD];
    chunk.extend_from_slice(&bad);
    chunk.extend_from_slice(&good);
    pod.receive(0, &chunk);
    fc.collect(&mut pod, 0);
    assert!(fc.ack(0x0304, bad_seq).is_none());
    assert!(fc.ack(0x0304, good_seq).is_some());
    assert_eq!(pod.rx_stats().frames, 1);
    assert!(pod.rx_stats().deframer.checksum_errors >= 1);

    // A length byte corrupted upwards holds the next frame back until the line is idle
    // (10 ms), then the frame behind it is found.
    let (_, mut long) = fc.frame(POD, &zoom(50));
    long[1] = 200;
    let (seq, next) = fc.frame(POD, &zoom(60));
    pod.receive(S, &long);
    pod.receive(S + MS, &next);
    fc.collect(&mut pod, S + MS);
    assert!(fc.ack(0x0304, seq).is_none());
    assert_eq!(pod.next_wakeup(), S + 11 * MS);
    run(&mut pod, &mut fc, S + 20 * MS);
    let (t, ..) = fc.ack(0x0304, seq).unwrap();
    assert_eq!(t, S + 11 * MS);
    let rec = pod.received().last().unwrap();
    assert_eq!((rec.start_us, rec.at_us), (S + MS, S + MS));
    assert_eq!(
        pod.camera()
            .zoom_target_x10
            .unwrap_or(pod.camera().zoom_x10),
        60.0
    );

    // A frame cut in two chunks is reassembled.
    let (seq, f) = fc.frame(POD, &zoom(70));
    pod.receive(2 * S, &f[..5]);
    pod.receive(2 * S + 2 * MS, &f[5..]);
    fc.collect(&mut pod, 2 * S + 2 * MS);
    assert!(fc.ack(0x0304, seq).is_some());
    let rec = pod.received().last().unwrap();
    assert_eq!((rec.start_us, rec.at_us), (2 * S, 2 * S + 2 * MS));
}

#[test]
fn output_faults_are_reproducible_and_detected_by_the_receiver() {
    let faults = OutputFaults {
        seed: 42,
        garbage_probability: 0.2,
        max_garbage_len: 8,
        bit_flip_probability: 0.2,
    };
    let capture = |faults: OutputFaults| {
        let config = PodSimConfig {
            faults,
            ..echoing()
        };
        let mut pod = SimPod::new(config);
        let mut wire = Vec::new();
        while pod.next_wakeup() <= 5 * S {
            let t = pod.next_wakeup();
            pod.poll(t);
            wire.extend(pod.transmit());
        }
        (pod, wire)
    };
    let (pod, wire) = capture(faults);
    let (garbage, flips) = pod.faults_injected();
    let sent = pod.sent().len() as u32;
    assert!(garbage > 10 && flips > 10, "{garbage} {flips} of {sent}");

    let mut d = Deframer::<_, MAX_FRAME_LEN>::new(K40tFraming::with(CrcCoverage::ExcludeStx));
    let mut ok = Vec::new();
    d.push(&wire, |ev| {
        if let Event::Frame(f) = ev {
            ok.push(f.to_vec());
        }
    });
    d.flush(|ev| {
        if let Event::Frame(f) = ev {
            ok.push(f.to_vec());
        }
    });
    // Each flipped frame is lost, nothing else; what arrives is what was sent.
    assert_eq!(ok.len() as u32, sent - flips);
    let clean: Vec<&Vec<u8>> = pod.sent().iter().map(|r| &r.frame).collect();
    assert!(ok.iter().all(|f| clean.contains(&f)));
    assert!(d.stats().checksum_errors > 0);

    // Same seed, same bytes; another seed, other bytes.
    assert_eq!(capture(faults).1, wire);
    assert_ne!(capture(OutputFaults { seed: 43, ..faults }).1, wire);
    assert_eq!(capture(OutputFaults::default()).0.faults_injected(), (0, 0));
}

#[test]
fn target_gps_and_other_queries_answer_with_data() {
    let (mut pod, mut fc) = default_pod();
    // Look 90° right and 45° down: the target is 100 m away, 70.7 m east, 70.7 m below.
    fc.send(
        &mut pod,
        0,
        &angle(PitchMotion::Down, 4500, YawMotion::Right, 9000),
    );
    run(&mut pod, &mut fc, 3 * S);
    pod.set_laser_distance_dm(1000);
    let req = k40t::TargetGpsRequest {
        mounts: 1,
        fix: k40t::GpsFix::Fix3d,
        utc_ms: NEW_YEAR_2026_MS,
        lon_e7: 1_000_000_000,
        lat_e7: 0,
        rel_alt_mm: 100_000,
        alt_mm: 150_000,
        heading_cdeg: 0,
        ..k40t::TargetGpsRequest::default()
    };
    fc.send(&mut pod, 3 * S, &req);
    let ack = fc.of::<k40t::TargetGpsAck>()[0].2;
    assert!(ack.code.is_ok());
    assert_eq!((ack.mount, ack.utc_ms), (0x1F, NEW_YEAR_2026_MS));
    // 70.71 m east at the equator: 70.71 / 111 320 deg.
    assert_eq!(ack.lon_e7, 1_000_000_000 + 6352);
    assert_eq!(ack.lat_e7, 0);
    assert_eq!(
        (ack.rel_alt_mm, ack.alt_mm),
        (100_000 - 70_711, 150_000 - 70_711)
    );

    fc.send(
        &mut pod,
        3 * S,
        &k40t::IpQuery {
            command: 1,
            reserved: 0,
        },
    );
    let ip = fc.of::<k40t::IpConfigAck>()[0].2;
    assert_eq!(ip.address, [192, 168, 144, 64]);
    fc.send(
        &mut pod,
        3 * S,
        &k40t::VisibleParamsQuery {
            command: 1,
            reserved: 0,
        },
    );
    assert!(fc.of::<k40t::VisibleParams>()[0].2.code.is_ok());
    fc.send(
        &mut pod,
        3 * S,
        &k40t::SbusConfigQuery {
            command: 1,
            reserved: 0,
        },
    );
    assert_eq!(fc.of::<k40t::SbusConfig>()[0].2.max, 1811);
}

// ----- ACK numbering, GPS reply matching, shutter presses, reboot -----

fn pod_with(config: PodSimConfig) -> (SimPod, Fc) {
    let mut pod = SimPod::new(config);
    let mut fc = Fc::new();
    run(&mut pod, &mut fc, 0);
    fc.clear();
    (pod, fc)
}

/// The sequence numbers of the frames from `src` at instant `t`, in order, with their ids.
fn seqs_at(fc: &Fc, src: Address, t: u64) -> Vec<(u32, u8)> {
    fc.packets()
        .iter()
        .filter(|(at, p)| *at == t && p.header.src == src)
        .map(|(_, p)| (p.message.id().to_u32(), p.header.seq))
        .collect()
}

const GIMBAL_VERSION: GimbalVersionQuery = GimbalVersionQuery {
    command: 1,
    reserved: 0,
};

#[test]
fn acks_take_the_pods_own_counter_in_the_documents_reading() {
    // At power-up (t = 0) the gimbal address sent 0x000001 and 0x000002 (SEQ 0, 1) and
    // the camera address 0x000003..5 (SEQ 0, 1, 2).
    let (mut pod, mut fc) = pod_with(PodSimConfig {
        ack_seq: AckSeq::OwnCounter,
        ..echoing()
    });
    fc.seq = 200;
    fc.send(&mut pod, 10 * MS, &GIMBAL_VERSION);
    fc.send(&mut pod, 20 * MS, &CameraVersionQuery::default());
    run(&mut pod, &mut fc, 200 * MS);
    // Each ACK takes its source's next number; the reports after it continue from there.
    assert_eq!(seqs_at(&fc, GIMBAL, 10 * MS), [(0x01_0018, 2)]);
    assert_eq!(seqs_at(&fc, POD, 20 * MS), [(0x01_0317, 3)]);
    assert_eq!(seqs_at(&fc, GIMBAL, 100 * MS), [(0x00_0002, 3)]);
    assert_eq!(
        seqs_at(&fc, POD, 200 * MS),
        [(0x00_0004, 4), (0x00_0005, 5)]
    );
    assert_eq!(seqs_at(&fc, GIMBAL, 200 * MS), [(0x00_0002, 4)]);
    // The ACK goes back to the requester, whose SEQ (200, 201) it does not carry.
    let acks: Vec<(Address, u8)> = fc
        .packets()
        .iter()
        .filter(|(_, p)| p.message.id().kind == Kind::Ack)
        .map(|(_, p)| (p.header.dst, p.header.seq))
        .collect();
    assert_eq!(acks, [(FC, 2), (FC, 3)]);
    let log = pod.requests();
    assert_eq!(log.len(), 2);
    assert_eq!(
        (
            log[0].header.seq,
            log[0].ack_seq,
            log[0].code,
            log[0].executed
        ),
        (200, Some(2), Some(AckCode::Ok), true)
    );
    assert_eq!((log[1].header.seq, log[1].ack_seq), (201, Some(3)));

    // A dropped ACK was sent and lost: it used its number (the next ACK shows the gap);
    // a refused request's ACK takes a number too.
    fc.clear();
    pod.drop_acks(0x0018, 1);
    pod.set_nak(0x0317, Some(AckCode::Failure));
    fc.send(&mut pod, 210 * MS, &GIMBAL_VERSION);
    fc.send(&mut pod, 220 * MS, &GIMBAL_VERSION);
    fc.send(&mut pod, 230 * MS, &CameraVersionQuery::default());
    assert_eq!(seqs_at(&fc, GIMBAL, 210 * MS), []);
    assert_eq!(seqs_at(&fc, GIMBAL, 220 * MS), [(0x01_0018, 6)]);
    assert_eq!(seqs_at(&fc, POD, 230 * MS), [(0x01_0317, 6)]);
    let log = pod.requests();
    assert_eq!((log[2].ack_seq, log[2].executed), (None, true));
    assert_eq!(
        (log[4].ack_seq, log[4].code, log[4].executed),
        (Some(6), Some(AckCode::Failure), false)
    );
    assert_eq!(pod.acks_dropped(), 1);
}

#[test]
fn echoed_acks_carry_the_requests_seq_and_leave_the_counter_alone() {
    let (mut pod, mut fc) = default_pod();
    assert_eq!(pod.config().ack_seq, AckSeq::Echo);
    assert_eq!(
        PodSimConfig::default().ack_seq,
        AckSeq::OwnCounter,
        "the document's reading is the default"
    );
    fc.seq = 200;
    fc.send(&mut pod, 10 * MS, &GIMBAL_VERSION);
    fc.send(&mut pod, 20 * MS, &CameraVersionQuery::default());
    run(&mut pod, &mut fc, 200 * MS);
    assert_eq!(seqs_at(&fc, GIMBAL, 10 * MS), [(0x01_0018, 200)]);
    assert_eq!(seqs_at(&fc, POD, 20 * MS), [(0x01_0317, 201)]);
    assert_eq!(seqs_at(&fc, GIMBAL, 100 * MS), [(0x00_0002, 2)]);
    assert_eq!(
        seqs_at(&fc, POD, 200 * MS),
        [(0x00_0004, 3), (0x00_0005, 4)]
    );
    assert_eq!(pod.requests()[0].ack_seq, Some(200));
}

/// A 0x010310 reply to the pod with sequence number `seq`.
fn gps_reply(seq: u8, lat_e7: i32) -> Vec<u8> {
    let reply = GpsReply {
        code: ResponseCode::OK,
        lat_e7,
        ..GpsReply::default()
    };
    let mut buf = [0u8; MAX_FRAME_LEN];
    let n = k40t::encode(&reply, &Header::new(FC, POD, seq), &mut buf).unwrap();
    buf[..n].to_vec()
}

#[test]
fn gps_replies_match_the_oldest_pending_request_preferring_the_same_seq() {
    let (mut pod, mut fc) = default_pod();
    for i in 0..3 {
        fc.send(&mut pod, i * 100 * MS, &photo(ShootAction::Start));
    }
    run(&mut pod, &mut fc, 250 * MS);
    let q: Vec<u8> = pod.gps_requests().iter().map(|r| r.seq).collect();
    assert_eq!(q.len(), 3);
    assert!(q.iter().all(|&s| s < 100), "{q:?}");
    // The exact SEQ wins over age: the third request.
    pod.receive(250 * MS, &gps_reply(q[2], 3));
    // A SEQ that no request has (the FC's own counter): the oldest pending request.
    pod.receive(260 * MS, &gps_reply(200, 1));
    // The first request's SEQ again, now answered: the oldest pending one, the second.
    pod.receive(270 * MS, &gps_reply(q[0], 2));
    // Nothing pending: a reply matches nothing.
    pod.receive(280 * MS, &gps_reply(201, 9));
    let r = pod.gps_replies();
    let got: Vec<(Option<usize>, bool, i32)> = r
        .iter()
        .map(|r| (r.request, r.seq_matches, r.reply.lat_e7))
        .collect();
    assert_eq!(
        got,
        [
            (Some(2), true, 3),
            (Some(0), false, 1),
            (Some(1), false, 2),
            (None, false, 9)
        ]
    );
    let replies: Vec<Option<usize>> = pod.gps_requests().iter().map(|r| r.reply).collect();
    assert_eq!(replies, [Some(1), Some(2), Some(0)]);
    assert_eq!(r[1].latency_us, Some(240 * MS));
    run(&mut pod, &mut fc, 3 * S);
    assert_eq!(pod.gps_unanswered(), 0);

    // The same with an FC that numbers its replies with its own counter, after a
    // timeout: a late reply only matches by its exact SEQ.
    fc.send(&mut pod, 3 * S, &photo(ShootAction::Start));
    run(&mut pod, &mut fc, 4100 * MS);
    assert_eq!(pod.gps_unanswered(), 1);
    let late = pod.gps_requests()[3].seq;
    pod.receive(4200 * MS, &gps_reply(late.wrapping_add(50), 5));
    pod.receive(4300 * MS, &gps_reply(late, 6));
    let r = pod.gps_replies();
    assert_eq!(
        (r[4].request, r[5].request, r[5].late),
        (None, Some(3), true)
    );
}

#[test]
fn every_photo_request_takes_a_photo_even_a_retry() {
    let (mut pod, mut fc) = default_pod();
    // A shutter press, and the same request again 5 ms later (a retry while the first
    // shot is still pending): two photos, two GPS requests, two OK ACKs.
    let a = fc.send(&mut pod, S, &photo(ShootAction::Start));
    let b = fc.send(&mut pod, S + 5 * MS, &photo(ShootAction::Start));
    run(&mut pod, &mut fc, 2 * S);
    assert_eq!(fc.ack(0x0302, a).unwrap().2, [0, 0]);
    assert_eq!(fc.ack(0x0302, b).unwrap().2, [0, 0]);
    let shots: Vec<u64> = pod.photos().iter().map(|p| p.at_us).collect();
    assert_eq!(shots, [S + 20 * MS, S + 25 * MS]);
    assert_eq!(pod.gps_requests().len(), 2);
    assert_eq!(pod.photo_requests(), 2);
    assert_eq!(pod.requests_received(0x0302), 2);
    assert_eq!(pod.camera().photos_taken, 2);

    // A burst cannot start while a shot is pending, nor a shot while a burst runs: the
    // camera says "photo in progress" and takes nothing more.
    fc.send(
        &mut pod,
        3 * S,
        &PhotoParams {
            mode: PhotoMode::Burst,
            timelapse_s: 5,
            burst_count: 3,
            reserved: 0,
        },
    );
    fc.send(&mut pod, 4 * S, &photo(ShootAction::Start));
    let c = fc.send(&mut pod, 4 * S + 100 * MS, &photo(ShootAction::Start));
    run(&mut pod, &mut fc, 6 * S);
    assert_eq!(fc.ack(0x0302, c).unwrap().2, [0x02, 0x03]);
    assert_eq!(pod.photos().len(), 5, "2 single shots and a burst of 3");
    assert_eq!(pod.photo_requests(), 4);
    let refused: Vec<(bool, Option<AckCode>)> = pod
        .requests()
        .iter()
        .filter(|r| r.request.base() == 0x0302)
        .map(|r| (r.executed, r.code))
        .collect();
    assert_eq!(refused[3], (false, Some(AckCode::PhotoInProgress)));
}

#[test]
fn a_reboot_silences_the_pod_then_it_boots_as_at_power_up() {
    let (mut pod, mut fc) = pod_with(PodSimConfig {
        ack_seq: AckSeq::OwnCounter,
        ..echoing()
    });
    // Synchronised, zoomed, turned, recording, tracking.
    pod.rtc_edge(S, true);
    fc.send(&mut pod, S + 2 * MS, &sync(NEW_YEAR_2026_MS));
    pod.rtc_edge(S + 50 * MS, false);
    fc.send(&mut pod, S + 100 * MS, &zoom(50));
    fc.send(
        &mut pod,
        S + 200 * MS,
        &angle(PitchMotion::Down, 3000, YawMotion::Right, 4500),
    );
    fc.send(
        &mut pod,
        S + 300 * MS,
        &DialSpeed {
            pitch_dps_x5: 100,
            yaw_dps_x5: 100,
            reserved: 0,
        },
    );
    fc.send(
        &mut pod,
        S + 400 * MS,
        &Record {
            sensors: RecordSensors::Both,
            action: RecordAction::Start,
            ..Record::default()
        },
    );
    fc.send(
        &mut pod,
        S + 500 * MS,
        &AiRecognition {
            enable: Toggle::On,
            model: 0,
            classes: [0; 10],
        },
    );
    fc.send(&mut pod, S + 600 * MS, &photo(ShootAction::Start));
    run(&mut pod, &mut fc, 5 * S);
    assert!(pod.is_synced());
    assert_eq!(pod.camera().zoom_x10, 50.0);
    assert!(pod.camera().recording.is_some() && pod.camera().ai);
    assert_eq!(
        (pod.gimbal().yaw_deg, pod.gimbal().pitch_deg),
        (45.0, -30.0)
    );
    let last_seq = fc.of::<GimbalAttitude>().last().unwrap().1.seq;
    assert!(last_seq > 40, "{last_seq}");

    // Power off at 5 s for 3 s: nothing goes out, nothing comes in.
    pod.reboot(5 * S, 3 * S);
    fc.clear();
    assert!(pod.is_off());
    assert_eq!(pod.next_wakeup(), 8 * S);
    run(&mut pod, &mut fc, 6 * S);
    fc.send(&mut pod, 6 * S, &GIMBAL_VERSION);
    pod.rtc_edge(7 * S, true);
    fc.send(&mut pod, 7 * S + 2 * MS, &sync(NEW_YEAR_2026_MS + 6000));
    pod.rtc_edge(7 * S + 50 * MS, false);
    run(&mut pod, &mut fc, 8 * S - 1);
    assert!(fc.frames.is_empty(), "silent while off");
    assert!(pod.rx_stats().dropped_while_off > 0);
    assert_eq!(pod.syncs().len(), 1, "the sync while off never arrived");
    assert_eq!(pod.rtc_edges().len(), 2);

    // Power-up at 8 s: the five reports at once, every counter from 0 again.
    run(&mut pod, &mut fc, 8 * S);
    assert!(!pod.is_off());
    assert_eq!(pod.boots(), [0, 8 * S]);
    assert_eq!(
        seqs_at(&fc, GIMBAL, 8 * S),
        [(0x00_0001, 0), (0x00_0002, 1)]
    );
    assert_eq!(
        seqs_at(&fc, POD, 8 * S),
        [(0x00_0003, 0), (0x00_0004, 1), (0x00_0005, 2)]
    );
    // The free-running power-up clock (1970), no UTC, zoom 1x, centred, defaults.
    assert!(!pod.is_synced());
    assert_eq!(pod.clock_unix_ms(8 * S), 0);
    assert_eq!(pod.clock_unix_ms(9 * S), 1000);
    let c = pod.camera();
    assert_eq!((c.zoom_x10, c.zooming), (10.0, false));
    assert!(c.recording.is_none() && !c.ai && c.track.is_none());
    assert_eq!(c.photos_taken, 1, "the photo count is a record");
    let g = pod.gimbal();
    assert_eq!(
        (g.yaw_deg, g.pitch_deg, g.yaw_speed_dps, g.pitch_speed_dps),
        (0.0, 0.0, 10.0, 10.0)
    );
    let a = attitude_at(&fc, 8 * S);
    assert_eq!((a.yaw_cdeg, a.pitch_cdeg), (0, 0));
    let v = fc.of::<VisibleStatus>()[0].2;
    assert_eq!(v.zoom_x10, 10);
    assert_eq!(fc.of::<SystemStatus>()[0].2.mode, k40t::CaptureMode::Photo);

    // It answers again, from its new counter; a photo asks GPS for 1970's time of day.
    fc.send(&mut pod, 8 * S + 10 * MS, &GIMBAL_VERSION);
    assert_eq!(seqs_at(&fc, GIMBAL, 8 * S + 10 * MS), [(0x01_0018, 2)]);
    fc.send(&mut pod, 8 * S + 500 * MS, &photo(ShootAction::Start));
    run(&mut pod, &mut fc, 9 * S);
    let q = pod.gps_requests()[1];
    assert_eq!(
        (
            q.request.hour,
            q.request.minute,
            q.request.second,
            q.request.millisecond
        ),
        (0, 0, 0, 520)
    );
    assert_eq!((q.synced, q.boot), (false, 1));
    // The records are kept.
    assert_eq!(pod.photos().len(), 2);
    assert_eq!(pod.syncs().len(), 1);
    assert!(pod.requests().len() >= 9);

    // Another reboot, with the counters starting elsewhere.
    run(&mut pod, &mut fc, 10 * S);
    pod.reboot_with(10 * S, 3 * S, Some(100));
    fc.clear();
    run(&mut pod, &mut fc, 13 * S);
    assert_eq!(pod.boots(), [0, 8 * S, 13 * S]);
    assert_eq!(
        seqs_at(&fc, GIMBAL, 13 * S),
        [(0x00_0001, 100), (0x00_0002, 101)]
    );
}

#[test]
fn a_pending_gps_request_dies_with_the_power() {
    let (mut pod, mut fc) = default_pod();
    fc.send(&mut pod, S, &photo(ShootAction::Start));
    run(&mut pod, &mut fc, S + 30 * MS);
    assert_eq!(pod.gps_requests().len(), 1);
    pod.reboot(S + 30 * MS, 3 * S);
    assert_eq!(pod.gps_unanswered(), 1);
    assert!(pod.gps_requests()[0].timed_out);
    run(&mut pod, &mut fc, 5 * S);
    // A reply after the reboot is for a request the pod forgot: it matches nothing.
    let seq = pod.gps_requests()[0].seq;
    pod.receive(5 * S, &gps_reply(seq, 1));
    assert_eq!(pod.gps_replies()[0].request, None);
    // A shot pending at the power cut is never taken.
    fc.send(&mut pod, 6 * S, &photo(ShootAction::Start));
    pod.reboot(6 * S + 10 * MS, S);
    run(&mut pod, &mut fc, 8 * S);
    assert_eq!(pod.photos().len(), 1);
    assert_eq!(pod.photo_requests(), 2);
}
