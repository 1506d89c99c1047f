//! The firmware's tasks on the host (feature `host`): virtual time, pipes as UARTs, a
//! minimal simulated K40T pod, a recording RTC_IO pin.
//!
//! The FC sides of the engine are not there yet (FC bytes are ignored and UTC never
//! becomes valid), so the RTC_IO/0x00030E mechanics are tested with a scripted engine
//! that plans edges itself and puts a marker frame at the head of the pod queue on each
//! rising edge, as the engine does with its 0x00030E.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::cell::{Cell, RefCell};
use std::collections::VecDeque;

use bridge_engine::Duration;
use bridge_fw::host::{self, Clock, HostLinks, HostShared, PinRecorder};
use bridge_fw::{
    BridgeEngine, Changes, Config, Engine, Event, Heartbeat, Instant, Level, LogKind, LogRecord,
    PinAction, Port, Status, Timing,
};
use embassy_futures::select::{Either, select, select3};
use embassy_time::{Duration as EDuration, Timer};
use protocol_core::k40t::{
    self, Address, CameraVersionAck, GimbalAttitude, GimbalVersionAck, Header, K40tFraming,
    Message, MessageData, Packet, Request, ResponseCode, Version,
};
use protocol_core::wire::{Deframer, Event as DeframerEvent};

fn ms(ms: u64) -> Instant {
    Instant::from_millis(ms)
}

// ---------------------------------------------------------------------------------------
// A minimal simulated pod: attitude reports at 10 Hz from the gimbal address, answers to
// the two version queries, and a log of every frame the bridge sent it.

#[derive(Default)]
struct PodSide {
    /// Frames received from the bridge: (instant, base id of the request).
    received: Vec<(Instant, Request)>,
    /// Frames the pod sent.
    sent: u32,
    /// Bytes from the bridge that were not part of a valid frame.
    rejected: u32,
}

fn pod_frame<M: MessageData<Protocol = k40t::K40t>>(m: &M, seq: u8, src: Address) -> Vec<u8> {
    let header = Header::new(src, Address::FLIGHT_CONTROLLER, seq);
    let mut buf = [0u8; k40t::MAX_FRAME_LEN];
    let n = k40t::encode(m, &header, &mut buf).unwrap();
    buf[..n].to_vec()
}

/// Runs the pod until `reports_until` (then it falls silent but still listens).
async fn sim_pod(links: &HostLinks, side: &RefCell<PodSide>, reports_until: Instant) -> ! {
    let mut deframer: Deframer<K40tFraming, 512> = Deframer::new(K40tFraming::any());
    let mut seq: u8 = 0;
    let mut next_report = embassy_time::Instant::from_millis(100);
    let mut buf = [0u8; 128];
    loop {
        match select(links.pod_tx.read(&mut buf), Timer::at(next_report)).await {
            Either::First(n) => {
                let now = bridge_fw::now();
                let mut replies = Vec::new();
                deframer.push(&buf[..n], |ev| match ev {
                    DeframerEvent::Frame(f) => {
                        let p = Packet::decode(f).expect("a frame the pod can decode");
                        if let Message::Request(r) = p.message {
                            side.borrow_mut().received.push((now, r));
                            let reply = match r {
                                Request::GimbalVersion(_) => Some(pod_frame(
                                    &GimbalVersionAck {
                                        code: ResponseCode::OK,
                                        hardware: Version {
                                            major: 1,
                                            minor: 2,
                                            patch: 3,
                                        },
                                        software: Version {
                                            major: 4,
                                            minor: 5,
                                            patch: 6,
                                        },
                                        reserved: 0,
                                    },
                                    p.header.seq,
                                    Address::GIMBAL,
                                )),
                                Request::CameraVersion(_) => Some(pod_frame(
                                    &CameraVersionAck {
                                        code: ResponseCode::OK,
                                        version: Version {
                                            major: 2,
                                            minor: 1,
                                            patch: 7,
                                        },
                                    },
                                    p.header.seq,
                                    Address::POD,
                                )),
                                _ => None,
                            };
                            replies.extend(reply);
                        }
                    }
                    _ => side.borrow_mut().rejected += 1,
                });
                for r in replies {
                    links.pod_rx.write_all(&r).await;
                    side.borrow_mut().sent += 1;
                }
            }
            Either::Second(()) => {
                next_report += EDuration::from_millis(100);
                if bridge_fw::now() < reports_until {
                    seq = seq.wrapping_add(1);
                    let att = GimbalAttitude {
                        yaw_cdeg: 1234,
                        pitch_cdeg: -4500,
                        ..GimbalAttitude::default()
                    };
                    links
                        .pod_rx
                        .write_all(&pod_frame(&att, seq, Address::GIMBAL))
                        .await;
                    side.borrow_mut().sent += 1;
                }
            }
        }
    }
}

/// The whole bridge on the real engine with the simulated pod, for `secs` of virtual time.
struct Run {
    shared: HostShared,
    records: Vec<LogRecord>,
    pod: PodSide,
    feeds: u32,
    edges: Vec<(Level, Instant)>,
}

fn run_with_pod(secs: u64, reports_until: Instant) -> Run {
    let config = Config::DEFAULT;
    let shared = HostShared::new(Engine::new(config), Timing::from_config(&config));
    let links = HostLinks::new();
    let rtc_io = PinRecorder::new();
    let records = RefCell::new(Vec::new());
    let feeds = Cell::new(0u32);
    let pod = RefCell::new(PodSide::default());
    host::run(Clock::Virtual, || {
        select3(
            host::bridge(
                &shared,
                &links,
                rtc_io.clone(),
                |r: &LogRecord| records.borrow_mut().push(*r),
                || feeds.set(feeds.get() + 1),
            ),
            sim_pod(&links, &pod, reports_until),
            Timer::after(EDuration::from_secs(secs)),
        )
    });
    Run {
        shared,
        records: records.into_inner(),
        pod: pod.into_inner(),
        feeds: feeds.get(),
        edges: rtc_io.edges(),
    }
}

fn engine_events(records: &[LogRecord]) -> Vec<(Instant, Event)> {
    records
        .iter()
        .filter_map(|r| match r.what {
            LogKind::Engine(e) => Some((r.at, e)),
            _ => None,
        })
        .collect()
}

#[test]
fn pod_link_comes_up_versions_are_answered_reports_are_processed() {
    let run = run_with_pod(30, ms(u64::MAX / 1000));
    let events = engine_events(&run.records);
    let (up_at, _) = events
        .iter()
        .find(|(_, e)| *e == Event::PodLinkUp)
        .expect("pod link up");
    // The first report leaves the pod at 100 ms: handled at once (virtual time).
    assert_eq!(*up_at, ms(100));
    assert!(
        !events.iter().any(|(_, e)| *e == Event::PodLinkDown),
        "{events:?}"
    );

    let (gimbal, camera, counters, status) = run.shared.with(|e| {
        (
            e.pod_state().gimbal_version,
            e.pod_state().camera_version,
            e.counters(),
            BridgeEngine::status(e),
        )
    });
    let gimbal = gimbal.expect("gimbal version asked and answered");
    assert_eq!(
        gimbal.software,
        Version {
            major: 4,
            minor: 5,
            patch: 6
        }
    );
    assert_eq!(
        camera,
        Some(Version {
            major: 2,
            minor: 1,
            patch: 7
        })
    );
    assert_eq!(
        status,
        Status {
            fc_link: false,
            pod_link: true,
            utc: false,
            pps_locked: false,
        }
    );

    // No byte lost or mangled in either direction: every frame the pod sent was taken
    // whole (the last report may still be in flight), every frame the bridge sent decodes.
    assert!(run.pod.sent >= 300, "{}", run.pod.sent);
    assert!(
        counters.pod_frames + 1 >= run.pod.sent,
        "{counters:?} vs {}",
        run.pod.sent
    );
    assert_eq!(counters.pod_rejected, 0);
    assert_eq!(counters.pod_garbage_bytes, 0);
    assert_eq!(run.pod.rejected, 0);
    assert_eq!(counters.dropped, 0);

    // No UTC (no FC side yet): no RTC_IO pulse, no time sync, ever.
    assert!(run.edges.is_empty(), "{:?}", run.edges);
    assert_eq!(counters.time_syncs, 0);
    assert!(
        !events
            .iter()
            .any(|(_, e)| matches!(e, Event::TimeSync { .. }))
    );

    // Every loop made progress: the watchdog was fed every 250 ms, never reported a stall.
    assert!(
        (119..=120).contains(&run.feeds),
        "fed every 250 ms: {}",
        run.feeds
    );
    assert!(
        !run.records
            .iter()
            .any(|r| matches!(r.what, LogKind::Stalled(_)))
    );
    assert_eq!(run.shared.records_dropped(), 0);
}

#[test]
fn pod_loss_takes_the_link_down_and_probing_resumes() {
    // Reports stop after 2 s (the last at 2.0 s).
    let run = run_with_pod(6, ms(2001));
    let events = engine_events(&run.records);
    let down: Vec<_> = events
        .iter()
        .filter(|(_, e)| *e == Event::PodLinkDown)
        .collect();
    assert_eq!(down.len(), 1, "{events:?}");
    // 1 s after the last report (pod link time-out).
    assert_eq!(down[0].0, ms(3000));
    // While lost, a gimbal version query every second.
    let probes: Vec<Instant> = run
        .pod
        .received
        .iter()
        .filter(|(t, r)| *t > ms(3000) && matches!(r, Request::GimbalVersion(_)))
        .map(|(t, _)| *t)
        .collect();
    assert!(probes.len() >= 2, "{probes:?}");
    for w in probes.windows(2) {
        assert_eq!(w[1].saturating_duration_since(w[0]), Duration::from_secs(1));
    }
    assert!(!run.shared.with(|e| e.pod_state().link));
}

// ---------------------------------------------------------------------------------------
// A spy around the real engine: which inputs reached it, and when.

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Input {
    Bytes(Port, usize),
    Idle(Port),
}

struct Spy {
    inner: Engine,
    inputs: Vec<(Instant, Input)>,
}

impl BridgeEngine for Spy {
    fn receive(&mut self, now: Instant, port: Port, bytes: &[u8]) -> Changes {
        self.inputs.push((now, Input::Bytes(port, bytes.len())));
        self.inner.receive(now, port, bytes)
    }
    fn idle(&mut self, now: Instant, port: Port) -> Changes {
        self.inputs.push((now, Input::Idle(port)));
        self.inner.idle(now, port)
    }
    fn poll(&mut self, now: Instant) -> Changes {
        BridgeEngine::poll(&mut self.inner, now)
    }
    fn poll_at(&self) -> Option<Instant> {
        BridgeEngine::poll_at(&self.inner)
    }
    fn pending(&self, port: Port) -> Option<usize> {
        self.inner.pending(port)
    }
    fn transmit(&mut self, port: Port, buf: &mut [u8]) -> Option<usize> {
        self.inner.transmit(port, buf)
    }
    fn pin(&self) -> Option<PinAction> {
        BridgeEngine::pin(&self.inner)
    }
    fn pin_done(&mut self, level: Level, at: Instant) -> Changes {
        BridgeEngine::pin_done(&mut self.inner, level, at)
    }
    fn next_event(&mut self) -> Option<Event> {
        BridgeEngine::next_event(&mut self.inner)
    }
    fn status(&self) -> Status {
        BridgeEngine::status(&self.inner)
    }
}

#[test]
fn bytes_reach_the_engine_with_their_instant_and_silence_means_idle() {
    let config = Config::DEFAULT;
    let timing = Timing::from_config(&config);
    // 20 byte times at 115200 (1.74 ms) are less than the 5 ms floor.
    assert_eq!(timing.idle(Port::Fc), Duration::from_millis(5));
    let shared = HostShared::new(
        Spy {
            inner: Engine::new(config),
            inputs: Vec::new(),
        },
        timing,
    );
    let links = HostLinks::new();
    host::run(Clock::Virtual, || {
        select(
            host::bridge(
                &shared,
                &links,
                PinRecorder::new(),
                |_: &LogRecord| {},
                || {},
            ),
            async {
                Timer::at(embassy_time::Instant::from_millis(100)).await;
                links.fc_rx.write_all(&[0x55; 10]).await;
                Timer::at(embassy_time::Instant::from_millis(101)).await;
                links.fc_rx.write_all(&[0x66; 5]).await;
                // Garbage on the pod line, then silence.
                Timer::at(embassy_time::Instant::from_millis(200)).await;
                links.pod_rx.write_all(&[0xFD, 0x03, 0x04]).await;
                Timer::at(embassy_time::Instant::from_millis(500)).await;
            },
        )
    });
    let inputs = shared.with(|s| s.inputs.clone());
    let fc: Vec<_> = inputs
        .iter()
        .filter(|(_, i)| matches!(i, Input::Bytes(Port::Fc, _) | Input::Idle(Port::Fc)))
        .copied()
        .collect();
    assert_eq!(
        fc,
        vec![
            (ms(100), Input::Bytes(Port::Fc, 10)),
            (ms(101), Input::Bytes(Port::Fc, 5)),
            // One idle, 5 ms after the last byte: the 1 ms gap was no idle.
            (ms(106), Input::Idle(Port::Fc)),
        ]
    );
    let pod: Vec<_> = inputs
        .iter()
        .filter(|(_, i)| matches!(i, Input::Bytes(Port::Pod, _) | Input::Idle(Port::Pod)))
        .copied()
        .collect();
    assert_eq!(
        pod,
        vec![
            (ms(200), Input::Bytes(Port::Pod, 3)),
            (ms(205), Input::Idle(Port::Pod))
        ]
    );
    // The idle flush dropped the incomplete candidate.
    let c = shared.with(|s| s.inner.counters());
    assert!(c.pod_garbage_bytes + c.pod_rejected > 0, "{c:?}");
}

// ---------------------------------------------------------------------------------------
// A scripted engine for the RTC_IO mechanics: long filler frames for the pod every few
// milliseconds, rising edges at planned instants, and on each a marker frame (standing
// for the 0x00030E) at the head of the pod queue carrying the edge's instant.

const FILLER: u8 = 0xF1;
const MARKER: u8 = 0xA5;
const MARKER_LEN: usize = 16;

struct Scripted {
    pod: VecDeque<Vec<u8>>,
    next_filler: Instant,
    filler_every: Duration,
    filler_len: usize,
    fillers: u32,
    edges: VecDeque<Instant>,
    low_at: Option<Instant>,
}

impl Scripted {
    fn new(edges: &[u64], filler_every_ms: u64, filler_len: usize) -> Self {
        Scripted {
            pod: VecDeque::new(),
            next_filler: ms(0),
            filler_every: Duration::from_millis(filler_every_ms),
            filler_len,
            fillers: 0,
            edges: edges.iter().map(|&t| ms(t)).collect(),
            low_at: None,
        }
    }
}

impl BridgeEngine for Scripted {
    fn receive(&mut self, _: Instant, _: Port, _: &[u8]) -> Changes {
        Changes::NONE
    }
    fn idle(&mut self, _: Instant, _: Port) -> Changes {
        Changes::NONE
    }
    fn poll(&mut self, now: Instant) -> Changes {
        let mut changes = Changes::NONE;
        while self.next_filler <= now {
            let mut f = vec![FILLER; self.filler_len];
            f[1..5].copy_from_slice(&self.fillers.to_le_bytes());
            self.pod.push_back(f);
            self.fillers += 1;
            self.next_filler = self.next_filler.saturating_add(self.filler_every);
            changes |= Changes::POD_FRAME;
        }
        changes
    }
    fn poll_at(&self) -> Option<Instant> {
        Some(self.next_filler)
    }
    fn pending(&self, port: Port) -> Option<usize> {
        match port {
            Port::Pod => self.pod.front().map(Vec::len),
            Port::Fc | Port::Telemetry => None,
        }
    }
    fn transmit(&mut self, port: Port, buf: &mut [u8]) -> Option<usize> {
        let f = match port {
            Port::Pod => self.pod.pop_front()?,
            Port::Fc | Port::Telemetry => return None,
        };
        buf[..f.len()].copy_from_slice(&f);
        Some(f.len())
    }
    fn pin(&self) -> Option<PinAction> {
        match (self.low_at, self.edges.front()) {
            (Some(at), _) => Some(PinAction {
                level: Level::Low,
                at,
                sub_us_ns: 0,
            }),
            (None, Some(&at)) => Some(PinAction {
                level: Level::High,
                at,
                sub_us_ns: 0,
            }),
            (None, None) => None,
        }
    }
    fn pin_done(&mut self, level: Level, at: Instant) -> Changes {
        match level {
            Level::High => {
                self.edges.pop_front();
                let mut m = vec![MARKER; MARKER_LEN];
                m[1..9].copy_from_slice(&at.as_micros().to_le_bytes());
                self.pod.push_front(m);
                self.low_at = Some(at.saturating_add(Duration::from_millis(50)));
                Changes::PIN | Changes::POD_FRAME
            }
            Level::Low => {
                self.low_at = None;
                Changes::PIN
            }
        }
    }
    fn next_event(&mut self) -> Option<Event> {
        None
    }
    fn status(&self) -> Status {
        Status::default()
    }
}

/// What the pod saw: (instant the frame's first byte arrived, frame).
async fn pod_reader(
    links: &HostLinks,
    filler_len: usize,
    seen: &RefCell<Vec<(Instant, Vec<u8>)>>,
) -> ! {
    let mut pending: Vec<u8> = Vec::new();
    let mut started: Option<Instant> = None;
    let mut buf = [0u8; 256];
    loop {
        let n = links.pod_tx.read(&mut buf).await;
        let now = bridge_fw::now();
        if pending.is_empty() {
            started = Some(now);
        }
        pending.extend_from_slice(&buf[..n]);
        loop {
            let len = match pending.first() {
                Some(&FILLER) => filler_len,
                Some(&MARKER) => MARKER_LEN,
                Some(other) => panic!("stream out of step at a byte {other:#04x}"),
                None => break,
            };
            if pending.len() < len {
                break;
            }
            let frame: Vec<u8> = pending.drain(..len).collect();
            seen.borrow_mut().push((started.unwrap_or(now), frame));
            started = Some(now);
        }
    }
}

struct EdgeRun {
    edges: Vec<(Level, Instant)>,
    seen: Vec<(Instant, Vec<u8>)>,
    records: Vec<LogRecord>,
    fillers_made: u32,
    fillers_queued: usize,
    timing: Timing,
}

fn run_edges(
    clock: Clock,
    secs_ms: u64,
    edges: &[u64],
    filler_every_ms: u64,
    filler_len: usize,
) -> EdgeRun {
    let config = Config::DEFAULT;
    let timing = Timing::from_config(&config);
    let shared = HostShared::new(Scripted::new(edges, filler_every_ms, filler_len), timing);
    let links = HostLinks::new();
    let rtc_io = PinRecorder::new();
    let records = RefCell::new(Vec::new());
    let seen = RefCell::new(Vec::new());
    host::run(clock, || {
        select3(
            host::bridge(
                &shared,
                &links,
                rtc_io.clone(),
                |r: &LogRecord| records.borrow_mut().push(*r),
                || {},
            ),
            pod_reader(&links, filler_len, &seen),
            Timer::after(EDuration::from_millis(secs_ms)),
        )
    });
    let (fillers_made, fillers_queued) = shared.with(|s| (s.fillers, s.pod.len()));
    EdgeRun {
        edges: rtc_io.edges(),
        seen: seen.into_inner(),
        records: records.into_inner(),
        fillers_made,
        fillers_queued,
        timing,
    }
}

#[test]
fn rtc_io_rises_at_the_planned_instant_and_the_marker_is_the_next_frame() {
    // 120-byte frames every 7 ms (10.6 ms on the wire each: the link is saturated), edges
    // at 1 s, 2 s and 3 s.
    let len = 120;
    let run = run_edges(Clock::Virtual, 3500, &[1000, 2000, 3000], 7, len);
    let rises: Vec<Instant> = run
        .edges
        .iter()
        .filter(|(l, _)| *l == Level::High)
        .map(|(_, t)| *t)
        .collect();
    // A timer alarm at the planned instant: exactly on time in virtual time.
    assert_eq!(rises, vec![ms(1000), ms(2000), ms(3000)]);
    let falls: Vec<Instant> = run
        .edges
        .iter()
        .filter(|(l, _)| *l == Level::Low)
        .map(|(_, t)| *t)
        .collect();
    assert_eq!(falls, vec![ms(1050), ms(2050), ms(3050)]);

    let wire = run.timing.wire_time(Port::Pod, len);
    for &edge in &rises {
        // The first frame to start at or after the edge is the marker, and it carries the
        // edge's instant.
        let (at, first) = run.seen.iter().find(|(t, _)| *t >= edge).unwrap();
        assert_eq!(first[0], MARKER, "first frame after the edge at {edge:?}");
        assert_eq!(
            u64::from_le_bytes(first[1..9].try_into().unwrap()),
            edge.as_micros()
        );
        assert_eq!(*at, edge, "no delay on virtual time");
        // No frame started before the edge is still on the wire at the edge.
        let (last_at, last) = run.seen.iter().rev().find(|(t, _)| *t < edge).unwrap();
        assert_eq!(last[0], FILLER);
        assert!(
            last_at.saturating_add(wire) < edge,
            "a {len}-byte frame started at {last_at:?} would still be on the wire at {edge:?}"
        );
    }
    // Measured delays (virtual time: zero), one per edge.
    let delays: Vec<_> = run
        .records
        .iter()
        .filter_map(|r| match r.what {
            LogKind::EdgeToFrame { delay, len } => Some((delay, len)),
            _ => None,
        })
        .collect();
    assert_eq!(delays, vec![(Duration::ZERO, MARKER_LEN as u16); 3]);
    // Nothing lost: every filler made was either seen whole, in order, or is still queued.
    let fillers: Vec<u32> = run
        .seen
        .iter()
        .filter(|(_, f)| f[0] == FILLER)
        .map(|(_, f)| u32::from_le_bytes(f[1..5].try_into().unwrap()))
        .collect();
    assert_eq!(fillers, (0..fillers.len() as u32).collect::<Vec<_>>());
    assert_eq!(
        fillers.len() + run.fillers_queued,
        run.fillers_made as usize
    );
}

#[test]
fn edge_to_marker_delay_on_real_time() {
    // Real time: the delay from the pin edge to the marker's first write, as the tasks
    // measure it (What::EdgeToFrame), on this host, under the test harness's load.
    let run = run_edges(Clock::Real, 1300, &[400, 800, 1200], 7, 120);
    let rises = run.edges.iter().filter(|(l, _)| *l == Level::High).count();
    assert_eq!(rises, 3);
    let delays: Vec<Duration> = run
        .records
        .iter()
        .filter_map(|r| match r.what {
            LogKind::EdgeToFrame { delay, .. } => Some(delay),
            _ => None,
        })
        .collect();
    assert_eq!(delays.len(), 3);
    let worst = delays.iter().max().unwrap();
    eprintln!(
        "edge -> first marker byte on real time (host): {:?} µs",
        delays.iter().map(|d| d.as_micros()).collect::<Vec<_>>()
    );
    // Generous: a loaded CI machine may deschedule the thread.
    assert!(worst.as_micros() < 20_000, "{worst:?}");
    // The pin rose within a scheduler tick of the plan.
    for ((_, at), planned) in run
        .edges
        .iter()
        .filter(|(l, _)| *l == Level::High)
        .zip([400, 800, 1200])
    {
        assert!(
            *at >= ms(planned)
                && at.saturating_duration_since(ms(planned)) < Duration::from_millis(20)
        );
    }
}

#[test]
fn a_stalled_writer_stops_the_watchdog_feed() {
    // Nobody reads the pod pipe: once it is full the pod writer blocks in `write`.
    let config = Config::DEFAULT;
    let shared = HostShared::new(Scripted::new(&[], 5, 200), Timing::from_config(&config));
    let links = HostLinks::new();
    let records = RefCell::new(Vec::new());
    let feeds = RefCell::new(Vec::new());
    host::run(Clock::Virtual, || {
        select(
            host::bridge(
                &shared,
                &links,
                PinRecorder::new(),
                |r: &LogRecord| records.borrow_mut().push(*r),
                || feeds.borrow_mut().push(bridge_fw::now()),
            ),
            Timer::after(EDuration::from_secs(3)),
        )
    });
    let feeds = feeds.into_inner();
    // Fed while the pipe filled (1024 bytes: 5 frames, 25 ms), then never again.
    assert_eq!(feeds.first(), Some(&ms(250)));
    let last = *feeds.last().unwrap();
    assert!(last <= ms(500), "{feeds:?}");
    let stalled: Vec<_> = records
        .borrow()
        .iter()
        .filter_map(|r| match r.what {
            LogKind::Stalled(h) => Some((r.at, h)),
            _ => None,
        })
        .collect();
    assert!(!stalled.is_empty());
    assert!(
        stalled.iter().all(|(_, h)| *h == Heartbeat::POD_TX),
        "{stalled:?}"
    );
    // With the MCU's 750 ms watchdog, the reset comes well within 1 s of the stall.
    assert!(stalled[0].0.saturating_duration_since(last) <= Duration::from_millis(250));
}

#[test]
fn led_task_shows_boot_the_side_then_the_status_and_the_faults() {
    use bridge_engine::FcProtocol;
    use bridge_fw::{Fault, Faults};
    let config = Config::DEFAULT;
    let shared = HostShared::new(Engine::new(config), Timing::from_config(&config));
    let faults = Faults::new();
    faults.raise(Fault::WatchdogReset);
    let led = PinRecorder::new();
    host::run(Clock::Virtual, || {
        select(
            bridge_fw::led_task(&shared, &faults, FcProtocol::Gcu, led.clone()),
            Timer::after(EDuration::from_millis(7100)),
        )
    });
    // Each flash as (on at, ms on): the level's changes only (the task sets the level of
    // every step, changed or not).
    let mut flashes = Vec::new();
    let mut level = Level::Low;
    let mut since = ms(0);
    for (l, t) in led.edges() {
        if l != level {
            if l == Level::Low {
                flashes.push((
                    since.as_millis(),
                    t.saturating_duration_since(since).as_millis(),
                ));
            }
            (level, since) = (l, t);
        }
    }
    let [boot, side @ ..] = flashes.as_slice() else {
        panic!("no flash: {flashes:?}");
    };
    assert_eq!(*boot, (0, 1000), "boot: on 1 s, then 1 s dark");
    // GCU: three flashes of 200 ms, 500 ms apart, then 1 s dark; then nothing up: three
    // short flashes 400 ms apart, 800 ms dark, the watchdog reset's six 50 ms flashes.
    let mut want = vec![(2000, 200), (2500, 200), (3000, 200)];
    want.extend([(4500, 40), (4900, 40), (5300, 40)]);
    want.extend((0..6).map(|i| (6500 + 100 * i, 50)));
    assert_eq!(side, want.as_slice());
}

#[test]
fn a_strap_error_shows_its_code_forever() {
    let led = PinRecorder::new();
    host::run(Clock::Virtual, || {
        select(
            bridge_fw::strap_error_led(led.clone()),
            Timer::after(EDuration::from_millis(2999)),
        )
    });
    let highs: Vec<u64> = led
        .edges()
        .iter()
        .filter(|(l, _)| *l == Level::High)
        .map(|(_, t)| t.as_millis())
        .collect();
    // Boot (0), then on every 200 ms from 2 s on.
    assert_eq!(highs, vec![0, 2000, 2200, 2400, 2600, 2800]);
}

#[test]
fn real_time_with_the_pod_fed_from_another_thread() {
    // The Linux runner's shape: the bridge on real time in one thread, a port reader in
    // another feeding the pipe through `host::block_on`.
    let config = Config::DEFAULT;
    let shared = HostShared::new(Engine::new(config), Timing::from_config(&config));
    let links = HostLinks::new();
    let records = RefCell::new(Vec::new());
    std::thread::scope(|scope| {
        let links = &links;
        scope.spawn(move || {
            host::block_on(async {
                for seq in 1..=8u8 {
                    Timer::after(EDuration::from_millis(50)).await;
                    let f = pod_frame(&GimbalAttitude::default(), seq, Address::GIMBAL);
                    links.pod_rx.write_all(&f).await;
                }
            });
        });
        host::run(Clock::Real, || {
            select(
                host::bridge(
                    &shared,
                    links,
                    PinRecorder::new(),
                    |r: &LogRecord| records.borrow_mut().push(*r),
                    || {},
                ),
                Timer::after(EDuration::from_millis(600)),
            )
        });
    });
    let c = shared.with(|e| e.counters());
    assert_eq!(c.pod_frames, 8, "{c:?}");
    assert!(
        engine_events(&records.into_inner())
            .iter()
            .any(|(_, e)| *e == Event::PodLinkUp)
    );
}

#[test]
fn timing_straps_and_led_codes() {
    let t = Timing::from_config(&Config::DEFAULT);
    // 10 bits a byte at 115200: 86.8 µs, rounded up per frame.
    assert_eq!(t.wire_time(Port::Pod, 1), Duration::from_micros(87));
    assert_eq!(t.wire_time(Port::Pod, 255), Duration::from_micros(22_136));
    let mut slow = Config::DEFAULT;
    slow.fc_baud = 9600;
    // 20 byte times at 9600: 20.8 ms.
    assert_eq!(
        Timing::from_config(&slow).idle(Port::Fc),
        Duration::from_micros(20_834)
    );

    use bridge_engine::FcProtocol;
    use bridge_fw::config::{self, FcChoice};
    assert_eq!(config::COMPILED.len(), 5);
    assert_eq!(config::FC, FcChoice::Straps, "all five compiled, fc = auto");
    let all: [(bool, bool, bool, FcProtocol); 5] = [
        (false, false, false, FcProtocol::Siyi),
        (true, false, false, FcProtocol::Viewlink),
        (false, true, false, FcProtocol::Gcu),
        (true, true, false, FcProtocol::K40t),
        (true, false, true, FcProtocol::Mavlink),
    ];
    for (a, b, c, fc) in all {
        assert_eq!(config::from_straps(a, b, c), Ok(fc));
        assert_eq!(config::resolve(|| (a, b, c)).map(|c| c.fc), Ok(fc));
    }
    for (a, b) in [(false, false), (true, false), (false, true), (true, true)] {
        assert_eq!(config::from_straps(a, b, true), Ok(FcProtocol::Mavlink));
    }
    // An image without the side the straps select: an error naming it, never another
    // side (whichever sides it has).
    let sides = [
        FcProtocol::Siyi,
        FcProtocol::Viewlink,
        FcProtocol::Gcu,
        FcProtocol::K40t,
        FcProtocol::Mavlink,
    ];
    for (a, b, c, wanted) in all {
        for missing in 0u8..32 {
            let compiled: Vec<FcProtocol> = sides
                .iter()
                .enumerate()
                .filter(|(i, _)| missing & (1 << i) == 0)
                .map(|(_, s)| *s)
                .collect();
            let got = config::straps_select(a, b, c, &compiled);
            if compiled.contains(&wanted) {
                assert_eq!(got, Ok(wanted));
            } else {
                assert_eq!(got, Err(config::StrapError { wanted }), "{compiled:?}");
            }
        }
    }
    assert_eq!(config::CONFIG.fc_baud, 115_200);
    assert_eq!(config::CONFIG.siyi.hardware_id, *b"7A0000000001");

    // The status cycle's codes: long when up, short when down, a double flash for PPS.
    use bridge_fw::led::{LedCode, status_codes};
    let ons = |codes: [Option<&LedCode>; 5]| -> Vec<Vec<u16>> {
        codes
            .into_iter()
            .flatten()
            .map(|c| c.steps().filter(|s| s.on).map(|s| s.ms).collect())
            .collect()
    };
    let all_up = Status {
        fc_link: true,
        pod_link: true,
        utc: true,
        pps_locked: false,
    };
    assert_eq!(
        ons(status_codes(all_up, false, false)),
        [[300], [300], [300]]
    );
    let pps = Status {
        pps_locked: true,
        ..all_up
    };
    assert_eq!(
        ons(status_codes(pps, false, true)),
        vec![vec![300], vec![300], vec![100, 100], vec![1200]]
    );
    let pod_only = Status {
        pod_link: true,
        ..Status::default()
    };
    assert_eq!(
        ons(status_codes(pod_only, true, false)),
        vec![vec![40], vec![300], vec![40], vec![50; 6]]
    );
}

/// `bridge.toml` lists every key with its default: the configuration `build.rs` wrote out
/// (deserialized into protocol-core's `Config`, validated, baked as a `const`) is
/// `Config::DEFAULT` itself, and valid.
#[test]
fn the_built_configuration_is_bridge_toml() {
    assert_eq!(bridge_fw::config::CONFIG, Config::DEFAULT);
    assert_eq!(bridge_fw::config::CONFIG.validate(), Ok(()));
}
