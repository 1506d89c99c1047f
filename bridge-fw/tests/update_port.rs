//! The firmware's update task on the host: pipes as the update port, the flash model as the
//! chip, virtual time. A whole transfer through the task (the client on the other end of
//! the pipes), the reset it asks for, and the new image's trial: confirmed once both links
//! are up, or after 60 s of running, and not before. The console task on the same port:
//! commands typed and answered, a setting saved through the store task and restored at
//! the next start, and a transfer handed over from the console.
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

/// Reads what the board writes up to the end of one answer (an `ok` or `error` line,
/// then the prompt).
async fn answer(from_board: &HostPipe) -> String {
    let mut text = String::new();
    while !(text.ends_with("> ") && (text.contains("\nok") || text.contains("\nerror"))) {
        let mut chunk = [0u8; 256];
        let n = from_board.read(&mut chunk).await;
        text.push_str(&String::from_utf8_lossy(&chunk[..n]));
    }
    text
}

/// Types `line` and returns the answer (the echo first).
async fn command(to_board: &HostPipe, from_board: &HostPipe, line: &str) -> String {
    to_board.write_all(format!("{line}\r").as_bytes()).await;
    answer(from_board).await
}

/// What the console's client saw, the task's log, and whether the task returned (the
/// restart).
struct ConsoleRun {
    answers: Vec<String>,
    records: Vec<LogRecord>,
    restarted: bool,
}

/// The firmware's console task with a real engine on the update port, the store task
/// writing to `store_bytes` (a RAM flash of two 512-byte pages, as on the emulated board),
/// and `lines` typed one after the other; then, with `transfer`, an update.
fn run_console(
    board: &SimBoard,
    store_bytes: &mut [u8],
    lines: &[&str],
    transfer: Option<&[u8]>,
) -> ConsoleRun {
    // As the firmware starts: the settings from the store, then the engine.
    let mut store = bridge_fw::FlashStore::new(
        bridge_fw::ram_flash::RamFlash::<512>::keeping(store_bytes),
        0..1024,
    )
    .unwrap();
    let (restored, _) = embassy_futures::block_on(bridge_fw::restore_settings(
        &mut store,
        Config::DEFAULT,
        bridge_engine::Sides::COMPILED,
    ));
    let config = *restored.config();
    let engine = bridge_fw::Engine::restored(restored, bridge_engine::BuildInfo::ENGINE);
    let shared = HostShared::new(engine, Timing::from_config(&config));
    let to_board = HostPipe::new();
    let from_board = HostPipe::new();
    let records = RefCell::new(Vec::new());
    let answers = RefCell::new(Vec::new());
    let mut aligned = [0; 8];
    let mut slot = board.slot(&mut aligned).unwrap();
    let mut receiver = Receiver::new(*key().verifying_key().as_bytes(), false, "test");
    let restarted = host::run(Clock::Virtual, || async {
        let task = async {
            let mut rx = &to_board;
            let mut tx = &from_board;
            bridge_fw::console_task(&shared, &mut rx, &mut tx, &mut slot, &mut receiver).await;
            Timer::after(Duration::from_millis(1)).await;
        };
        let client = async {
            for line in lines {
                let a = command(&to_board, &from_board, line).await;
                answers.borrow_mut().push(a);
            }
            if let Some(img) = transfer {
                client(&to_board, &from_board, img).await;
            }
            core::future::pending::<()>().await
        };
        let logger = log_task(&shared, |r: &LogRecord| records.borrow_mut().push(*r));
        let store = bridge_fw::store_task(&shared, store);
        match select(
            select(task, client),
            select3(logger, store, Timer::after(Duration::from_secs(120))),
        )
        .await
        {
            Either::First(_) => true,
            Either::Second(_) => false,
        }
    });
    ConsoleRun {
        answers: answers.into_inner(),
        records: records.into_inner(),
        restarted,
    }
}

/// The console on the update port: commands typed are echoed and answered; `set` then
/// `save` reach the store through the store task; `reboot` ends the task (the restart) once
/// the store has written them; the next start restores the setting from the flash.
#[test]
fn the_console_sets_saves_and_restarts_and_the_next_start_restores_the_setting() {
    let board = SimBoard::new(LAYOUT, &image(0xA0));
    let mut flash = vec![0xFF; 1024];
    let run = run_console(
        &board,
        &mut flash,
        &["version", "set leap_seconds 19", "save", "reboot"],
        None,
    );
    assert!(run.restarted, "reboot ends the task");
    let a = &run.answers;
    assert!(a[0].starts_with("version\r\n"), "echoed: {:?}", a[0]);
    assert!(a[0].contains(env!("CARGO_PKG_VERSION")), "{:?}", a[0]);
    assert!(a[1].contains("\nok"), "{:?}", a[1]);
    assert!(a[2].contains("\nok"), "{:?}", a[2]);
    assert!(a[3].contains("ok: rebooting"), "{:?}", a[3]);

    // The next start: the setting comes back from the flash the store task wrote.
    let mut st = bridge_fw::FlashStore::new(
        bridge_fw::ram_flash::RamFlash::<512>::keeping(&mut flash),
        0..1024,
    )
    .unwrap();
    let (restored, unreadable) = embassy_futures::block_on(bridge_fw::restore_settings(
        &mut st,
        Config::DEFAULT,
        bridge_engine::Sides::COMPILED,
    ));
    assert!(!unreadable);
    assert!(!restored.store_reset(), "{:?}", restored.reset);
    assert_eq!(restored.config().leap_seconds, 19);
    assert_ne!(Config::DEFAULT.leap_seconds, 19);
}

/// `gimbal update`'s client through the console: its first frame's sync at a line's start
/// hands the port over, after a command typed before it; the transfer completes and the
/// task returns for the reset.
#[test]
fn an_update_through_the_console_after_a_command() {
    let (a, b) = (image(0xA0), image(0xB0));
    let board = SimBoard::new(LAYOUT, &a);
    let mut flash = vec![0xFF; 1024];
    let run = run_console(&board, &mut flash, &["status"], Some(&b));
    assert!(run.answers[0].contains("\nok"), "{:?}", run.answers[0]);
    assert!(run.restarted, "the update client's reset ends the task");
    let log = updates(&run.records);
    assert!(
        log.iter().any(|(_, u)| *u == UpdateLog::Verified),
        "{log:?}"
    );
    board.reset().unwrap();
    assert_eq!(board.active(LEN), b);
}
