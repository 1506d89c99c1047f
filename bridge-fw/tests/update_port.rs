//! The firmware's update task on the host: pipes as the update port, the flash model as the
//! chip, virtual time. A whole transfer through the task (the client on the other end of
//! the pipes), the reset it asks for, and the new image's trial: confirmed once both links
//! are up, or after 60 s of running, and not before.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing
)]

use std::cell::RefCell;

use bridge_fw::host::{self, Clock, HostPipe, HostShared};
use bridge_fw::{
    BridgeEngine, Changes, Config, Event, Instant, Level, LogKind, LogRecord, PinAction, Port,
    Status, Timing, UpdateLog, log_task, update_task,
};
use bridge_update::client::{Client, Progress};
use bridge_update::sim::{SimBoard, SimLayout};
use bridge_update::wire::{BootState, MAX_FRAME, Response, UpdateFraming};
use bridge_update::{Receiver, Slot};
use ed25519_dalek::SigningKey;
use embassy_futures::select::{Either, select, select3};
use embassy_time::{Duration, Timer};
use protocol_core::wire::{Deframer, Event as DeframerEvent};

/// An engine whose only part is its links' status, set by the test.
#[derive(Default)]
struct Links {
    up: bool,
}

impl BridgeEngine for Links {
    fn receive(&mut self, _: Instant, _: Port, _: &[u8]) -> Changes {
        Changes::NONE
    }
    fn idle(&mut self, _: Instant, _: Port) -> Changes {
        Changes::NONE
    }
    fn poll(&mut self, _: Instant) -> Changes {
        Changes::NONE
    }
    fn poll_at(&self) -> Option<Instant> {
        None
    }
    fn pending(&self, _: Port) -> Option<usize> {
        None
    }
    fn transmit(&mut self, _: Port, _: &mut [u8]) -> Option<usize> {
        None
    }
    fn pin(&self) -> Option<PinAction> {
        None
    }
    fn pin_done(&mut self, _: Level, _: Instant) -> Changes {
        Changes::NONE
    }
    fn next_event(&mut self) -> Option<Event> {
        None
    }
    fn status(&self) -> Status {
        Status {
            fc_link: self.up,
            pod_link: self.up,
            utc: false,
            pps_locked: false,
        }
    }
}

const LAYOUT: SimLayout = SimLayout { active_pages: 8 };
const LEN: usize = 12 * 1024 + 40;

fn key() -> SigningKey {
    SigningKey::from_bytes(&[3; 32])
}

fn image(tag: u8) -> Vec<u8> {
    (0..LEN)
        .map(|i| tag ^ (i as u8).wrapping_mul(13) ^ (i >> 8) as u8)
        .collect()
}

/// The client on the other end of the port: the whole transfer, then the reset.
async fn client(to_board: &HostPipe, from_board: &HostPipe, image: &[u8]) -> Vec<Progress> {
    let sig = bridge_update::keys::sign(&key(), image);
    let (signature, _) = bridge_update::keys::parse_sig(&sig).unwrap();
    let mut client = Client::new(image, signature).unwrap();
    let mut deframer = Deframer::<UpdateFraming, MAX_FRAME>::new(UpdateFraming);
    let mut seen = Vec::new();
    let mut buf = [0u8; MAX_FRAME];
    let mut ask = async |request: bridge_update::wire::Request<'_>,
                         deframer: &mut Deframer<UpdateFraming, MAX_FRAME>| {
        let n = request.emit(&mut buf).unwrap();
        to_board.write_all(&buf[..n]).await;
        loop {
            if let Some(DeframerEvent::Frame(f)) = deframer.poll() {
                return f.to_vec();
            }
            let mut chunk = [0u8; 256];
            let n = from_board.read(&mut chunk).await;
            deframer.feed(&chunk[..n]);
        }
    };
    while let Some(request) = client.request() {
        let frame = ask(request, &mut deframer).await;
        seen.push(client.response(&Response::parse(&frame).unwrap()).unwrap());
    }
    let frame = ask(bridge_update::wire::Request::Reboot, &mut deframer).await;
    assert_eq!(Response::parse(&frame).unwrap(), Response::Rebooting);
    seen
}

/// Runs the update task with the board's slot until it returns (the reset) or `secs` of
/// virtual time pass; `links_up_at`: when the engine's links come up.
fn run_task(
    board: &SimBoard,
    links_up_at: Option<u64>,
    secs: u64,
    transfer: Option<&[u8]>,
) -> (Vec<LogRecord>, bool) {
    let shared = HostShared::new(Links::default(), Timing::from_config(&Config::DEFAULT));
    let to_board = HostPipe::new();
    let from_board = HostPipe::new();
    let records = RefCell::new(Vec::new());
    let mut aligned = [0; 8];
    let mut slot = board.slot(&mut aligned).unwrap();
    let mut receiver = Receiver::new(*key().verifying_key().as_bytes(), false, "test");
    let reset = host::run(Clock::Virtual, || async {
        let task = async {
            let mut rx = &to_board;
            let mut tx = &from_board;
            update_task(&shared, &mut rx, &mut tx, &mut slot, &mut receiver).await;
            // Let the logger take the last records.
            Timer::after(Duration::from_millis(1)).await;
        };
        let links = async {
            if let Some(at) = links_up_at {
                Timer::after(Duration::from_secs(at)).await;
                shared.input(|e| {
                    e.up = true;
                    Changes::NONE
                });
            }
            core::future::pending::<()>().await
        };
        let client = async {
            match transfer {
                Some(img) => {
                    client(&to_board, &from_board, img).await;
                }
                None => core::future::pending::<()>().await,
            }
            core::future::pending::<()>().await
        };
        let logger = log_task(&shared, |r: &LogRecord| records.borrow_mut().push(*r));
        match select(
            select3(task, links, client),
            select(logger, Timer::after(Duration::from_secs(secs))),
        )
        .await
        {
            Either::First(_) => true,
            Either::Second(_) => false,
        }
    });
    (records.into_inner(), reset)
}

fn updates(records: &[LogRecord]) -> Vec<(u64, UpdateLog)> {
    records
        .iter()
        .filter_map(|r| match r.what {
            LogKind::Update(u) => Some((r.at.as_micros() / 1_000_000, u)),
            _ => None,
        })
        .collect()
}

#[test]
fn a_transfer_through_the_task_then_the_trial_confirmed_when_the_links_come_up() {
    let (a, b) = (image(0xA0), image(0xB0));
    let board = SimBoard::new(LAYOUT, &a);
    let (records, reset) = run_task(&board, None, 600, Some(&b));
    assert!(reset, "the task returns for the reset");
    let log = updates(&records);
    assert!(
        log.contains(&(0, UpdateLog::Started(BootState::Confirmed))),
        "{log:?}"
    );
    assert!(
        log.iter().any(|(_, u)| *u == UpdateLog::Begun(LEN as u32)),
        "{log:?}"
    );
    assert!(
        log.iter().any(|(_, u)| *u == UpdateLog::Verified),
        "{log:?}"
    );
    assert!(
        log.iter().any(|(_, u)| *u == UpdateLog::Rebooting),
        "{log:?}"
    );
    board.reset().unwrap();
    assert_eq!(board.active(LEN), b);

    // The new image on trial, its links up after 5 s: confirmed at the next check.
    let (records, _) = run_task(&board, Some(5), 20, None);
    let log = updates(&records);
    assert_eq!(
        log.first(),
        Some(&(0, UpdateLog::Started(BootState::Trial))),
        "{log:?}"
    );
    assert!(log.contains(&(6, UpdateLog::Confirmed)), "{log:?}");
    let mut aligned = [0; 8];
    assert_eq!(
        board.slot(&mut aligned).unwrap().state(),
        Ok(BootState::Confirmed)
    );
    board.reset().unwrap();
    assert_eq!(board.active(LEN), b, "kept");
}

#[test]
fn without_its_links_the_image_confirms_itself_after_60_s_and_not_before() {
    let (a, b) = (image(0xA0), image(0xB0));
    let board = SimBoard::new(LAYOUT, &a);
    run_task(&board, None, 600, Some(&b));
    board.reset().unwrap();
    // 59 s without links: not confirmed; a reset then rolls back.
    let trial = board.clone();
    let (records, _) = run_task(&trial, None, 59, None);
    assert!(
        !updates(&records)
            .iter()
            .any(|(_, u)| *u == UpdateLog::Confirmed),
        "{records:?}"
    );
    let (records, _) = run_task(&board, None, 70, None);
    let log = updates(&records);
    assert!(log.contains(&(60, UpdateLog::Confirmed)), "{log:?}");
}
