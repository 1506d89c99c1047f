//! The persistent store (src/store.rs) on the host: sequential-storage's map over a mock of
//! the STM32L4's flash (8-byte words written once between erases, 2 KiB pages, the
//! store's 16 KiB) that loses power at every write and every erase of a long run of saves;
//! after each cut the store reads back the last record written completely or the one
//! being written, never garbage. A blank store and a corrupt one start the engine on its
//! defaults with an event. The firmware's `memory.x` leaves the store alone.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use bridge_engine::store::{self, Key, Problem, Record};
use bridge_engine::{Config, Engine, Event, FcProtocol, Instant, SigningKey, SigningMode};
use bridge_fw::host::HostShared;
use bridge_fw::layout::{self, PAGE_SIZE};
use bridge_fw::ram_flash::RamFlash;
use bridge_fw::{FlashStore, RecordStore, Timing};
use embassy_futures::block_on;
use embedded_storage_async::nor_flash::{
    ErrorType, NorFlash, NorFlashError, NorFlashErrorKind, ReadNorFlash,
};

/// The store's size: the last 16 KiB of the chip.
const SIZE: usize = (layout::STORE_END - layout::STORE_START) as usize;
const WORD: usize = 8;

/// One flash operation of a run, with the flash as it was before it.
struct Op {
    before: Vec<u8>,
    programmed: Vec<bool>,
    kind: OpKind,
    /// The save in progress (its index in the run).
    save: usize,
}

#[derive(Clone)]
enum OpKind {
    Write { offset: usize, bytes: Vec<u8> },
    Erase { from: usize, to: usize },
}

/// The L4's flash, recording each operation: a word is written only once between erases
/// (its ECC), whatever it holds.
struct MockFlash {
    bytes: Vec<u8>,
    programmed: Vec<bool>,
    log: Option<Vec<Op>>,
    save: usize,
}

#[derive(Debug)]
struct MockError;

impl NorFlashError for MockError {
    fn kind(&self) -> NorFlashErrorKind {
        NorFlashErrorKind::Other
    }
}

impl MockFlash {
    fn blank() -> Self {
        Self::of(vec![0xFF; SIZE], vec![false; SIZE / WORD])
    }

    fn of(bytes: Vec<u8>, programmed: Vec<bool>) -> Self {
        MockFlash {
            bytes,
            programmed,
            log: None,
            save: 0,
        }
    }

    fn note(&mut self, kind: OpKind) {
        if let Some(log) = &mut self.log {
            log.push(Op {
                before: self.bytes.clone(),
                programmed: self.programmed.clone(),
                kind,
                save: self.save,
            });
        }
    }
}

impl ErrorType for MockFlash {
    type Error = MockError;
}

impl ReadNorFlash for MockFlash {
    const READ_SIZE: usize = 1;
    async fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), MockError> {
        let o = offset as usize;
        let src = self.bytes.get(o..o + bytes.len()).ok_or(MockError)?;
        bytes.copy_from_slice(src);
        Ok(())
    }
    fn capacity(&self) -> usize {
        SIZE
    }
}

impl NorFlash for MockFlash {
    const WRITE_SIZE: usize = WORD;
    const ERASE_SIZE: usize = PAGE_SIZE as usize;

    async fn erase(&mut self, from: u32, to: u32) -> Result<(), MockError> {
        let (from, to) = (from as usize, to as usize);
        assert!(
            from.is_multiple_of(Self::ERASE_SIZE)
                && to.is_multiple_of(Self::ERASE_SIZE)
                && to <= SIZE
        );
        self.note(OpKind::Erase { from, to });
        self.bytes[from..to].fill(0xFF);
        self.programmed[from / WORD..to / WORD].fill(false);
        Ok(())
    }

    async fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), MockError> {
        let o = offset as usize;
        assert!(
            o.is_multiple_of(WORD) && bytes.len().is_multiple_of(WORD) && o + bytes.len() <= SIZE
        );
        for w in o / WORD..(o + bytes.len()) / WORD {
            assert!(
                !self.programmed[w],
                "word {w} written twice between erases (the L4's ECC flash refuses it)"
            );
        }
        self.note(OpKind::Write {
            offset: o,
            bytes: bytes.to_vec(),
        });
        self.bytes[o..o + bytes.len()].copy_from_slice(bytes);
        self.programmed[o / WORD..(o + bytes.len()) / WORD].fill(true);
        Ok(())
    }
}

/// The flash after `op` was cut by a power loss part-way: a write with its first half of
/// words programmed and the next word half-programmed (NOR programming clears bits: some
/// of its zeros not yet there); an erase with only its first half erased.
fn cut(op: &Op) -> MockFlash {
    let mut f = MockFlash::of(op.before.clone(), op.programmed.clone());
    match op.kind.clone() {
        OpKind::Write { offset, bytes } => {
            let words = bytes.len() / WORD;
            let whole = words / 2;
            let done = whole * WORD;
            f.bytes[offset..offset + done].copy_from_slice(&bytes[..done]);
            f.programmed[offset / WORD..offset / WORD + whole].fill(true);
            if whole < words {
                for (i, b) in bytes[done..done + WORD].iter().enumerate() {
                    f.bytes[offset + done + i] = b | 0x5A;
                }
                f.programmed[offset / WORD + whole] = true;
            }
        }
        OpKind::Erase { from, to } => {
            let mid = from + (to - from) / 2;
            f.bytes[from..mid].fill(0xFF);
            f.programmed[from / WORD..mid / WORD].fill(false);
        }
    }
    f
}

fn store_of(flash: MockFlash) -> FlashStore<MockFlash> {
    FlashStore::new(flash, 0..SIZE as u32).expect("whole pages")
}

fn load(store: &mut FlashStore<MockFlash>, key: Key) -> Option<Vec<u8>> {
    let mut buf = [0u8; store::MAX_VALUE];
    let n = block_on(store.load(key.0, &mut buf)).expect("the store reads after a cut");
    n.map(|n| buf[..n].to_vec())
}

/// The records of save `i` of the run: a timestamp every save, a key every fifth.
fn records(i: usize) -> Vec<Record> {
    let mut out = vec![Record::timestamp(
        Key::SIGNING_FC,
        3_500_000_000_000 + i as u64 * 3_000_000,
    )];
    if i.is_multiple_of(5) {
        out.push(Record::signing_key(
            Key::SIGNING_KEY_FC,
            Some([i as u8; 32]),
            [1, 2, 3, 4, 5, 6],
        ));
    }
    out
}

/// The last value of `key` saved up to and including save `upto` (`None`: none yet).
fn value_at(key: Key, upto: Option<usize>) -> Option<Vec<u8>> {
    let upto = upto?;
    (0..=upto)
        .rev()
        .flat_map(records)
        .find(|r| r.key == key)
        .map(|r| r.value().to_vec())
}

/// Saves enough records to go round the store's eight pages twice (each page erased
/// and reused), cutting the power at every write and every erase in turn: after each
/// cut, a new store over what the flash holds reads each key's last value saved
/// completely or the value being saved, decodes it, and keeps on saving.
#[test]
fn every_power_cut_leaves_the_last_complete_record_or_the_one_before() {
    let mut flash = MockFlash::blank();
    flash.log = Some(Vec::new());
    let mut st = store_of(flash);
    // Records take 24 and 56 bytes with their headers (35 bytes a save on average):
    // 1,000 saves are ~35 KB, the 16 KiB store twice over.
    const SAVES: usize = 1000;
    for i in 0..SAVES {
        st.flash_mut().save = i;
        for r in records(i) {
            block_on(st.save(r.key.0, r.value())).expect("save");
        }
    }
    let log = st.into_flash().log.take().unwrap();
    let erases = log
        .iter()
        .filter(|o| matches!(o.kind, OpKind::Erase { .. }))
        .count();
    // Every page erased and used again at least once (measured: 11 erases).
    assert!(erases >= 8, "the run erased {erases} pages");
    let mut seen_in_progress = 0;
    for (n, op) in log.iter().enumerate() {
        let mut st = store_of(cut(op));
        for key in [Key::SIGNING_FC, Key::SIGNING_KEY_FC] {
            let got = load(&mut st, key);
            let complete = value_at(key, op.save.checked_sub(1));
            let in_progress = value_at(key, Some(op.save));
            assert!(
                got == complete || got == in_progress,
                "cut at op {n} (save {}): {key:?} reads {got:?}, expected {complete:?} or {in_progress:?}",
                op.save
            );
            if got.is_some() && got != complete {
                seen_in_progress += 1;
            }
            // Never garbage: what it reads decodes.
            if let Some(v) = &got {
                if key == Key::SIGNING_FC {
                    store::decode_timestamp(v).expect("a timestamp");
                } else {
                    store::decode_signing_key(v).expect("a key");
                }
            }
        }
        // The store goes on after the cut (repairing what the cut left).
        let next = records(op.save + 1);
        for r in &next {
            block_on(st.save(r.key.0, r.value())).expect("a save after the cut");
        }
        assert_eq!(
            load(&mut st, Key::SIGNING_FC).as_deref(),
            Some(next[0].value())
        );
    }
    println!(
        "{} cuts (writes and erases, {erases} erases), {seen_in_progress} read the record being written",
        log.len()
    );
}

fn signing_engine() -> HostShared<Engine> {
    let mut c = Config::for_fc(FcProtocol::Mavlink);
    c.signing = SigningMode::Require;
    c.signing_key = Some(SigningKey([3; 32]));
    HostShared::new(Engine::new(c), Timing::from_config(&c))
}

fn events(shared: &HostShared<Engine>) -> Vec<Event> {
    shared.with(|e| core::iter::from_fn(|| e.next_event()).collect())
}

/// A blank store restores nothing: at its first input the engine says the signing
/// timestamp was missing; a corrupt one (garbage in every page) cannot be read: the engine
/// starts on its defaults and says so, and the store starts blank.
#[test]
fn a_blank_or_corrupt_store_starts_on_defaults_with_an_event() {
    let shared = signing_engine();
    let mut st = store_of(MockFlash::blank());
    assert!(!block_on(bridge_fw::restore(&shared, &mut st)));
    shared.input(|e| e.poll(Instant::from_millis(1)));
    // Both MAVLink links sign (the MAVLink side's and the telemetry link).
    let missing = |key: Key| Event::StoreRecord {
        key: key.0,
        problem: Problem::Missing,
    };
    assert_eq!(
        events(&shared),
        vec![missing(Key::SIGNING_FC), missing(Key::SIGNING_TELEMETRY)]
    );

    let shared = signing_engine();
    let garbage: Vec<u8> = (0..SIZE).map(|i| (i * 151 % 251) as u8).collect();
    let mut st = store_of(MockFlash::of(garbage, vec![true; SIZE / WORD]));
    let unreadable = block_on(bridge_fw::restore(&shared, &mut st));
    assert!(unreadable, "garbage is no store");
    assert_eq!(
        events(&shared),
        vec![Event::StoreRecord {
            key: Key::WHOLE_STORE.0,
            problem: Problem::Unreadable
        }]
    );
    block_on(st.erase()).unwrap();
    let r = Record::timestamp(Key::SIGNING_FC, 42);
    block_on(st.save(r.key.0, r.value())).unwrap();
    assert_eq!(load(&mut st, Key::SIGNING_FC).as_deref(), Some(r.value()));
}

/// A record written by one run is the next run's: the engine restores it (its
/// timestamp then signs above it) and a record of a bad version is reported.
#[test]
fn records_come_back_at_the_next_start() {
    let shared = signing_engine();
    let mut st = store_of(MockFlash::blank());
    let t = Record::timestamp(Key::SIGNING_FC, 3_600_000_000_000);
    block_on(st.save(t.key.0, t.value())).unwrap();
    block_on(st.save(Key::SIGNING_KEY_FC.0, &[9, 1, 2])).unwrap();
    assert!(!block_on(bridge_fw::restore(&shared, &mut st)));
    shared.input(|e| e.poll(Instant::from_millis(1)));
    assert_eq!(
        events(&shared),
        vec![
            Event::StoreRecord {
                key: Key::SIGNING_KEY_FC.0,
                problem: Problem::Version { found: 9 }
            },
            // The telemetry link's timestamp was never saved.
            Event::StoreRecord {
                key: Key::SIGNING_TELEMETRY.0,
                problem: Problem::Missing
            },
        ]
    );
}

/// The emulated board's RAM model keeps the L4's rules: whole words, each written once
/// between erases.
#[test]
fn the_ram_model_writes_each_word_once_between_erases() {
    let mut buf = [0u8; 1024];
    let mut f: RamFlash<'_, 512> = RamFlash::new(&mut buf);
    block_on(f.write(8, &[1; 8])).unwrap();
    assert!(block_on(f.write(8, &[1; 8])).is_err());
    assert!(block_on(f.write(4, &[1; 8])).is_err(), "unaligned");
    assert!(block_on(f.write(1024, &[1; 8])).is_err(), "outside");
    block_on(f.erase(0, 512)).unwrap();
    block_on(f.write(8, &[2; 8])).unwrap();
    let mut st = FlashStore::new(f, 0..1024).unwrap();
    let r = Record::timestamp(Key::SIGNING_FC, 7);
    for _ in 0..100 {
        block_on(st.save(r.key.0, r.value())).unwrap();
    }
    let mut out = [0u8; 16];
    assert_eq!(block_on(st.load(r.key.0, &mut out)), Ok(Some(7)));
}

/// The firmware's `memory.x` (written from the one flash table) ends its flash before the
/// store begins, and the store is the chip's last 16 KiB.
#[test]
fn the_linker_map_leaves_the_store_to_the_store() {
    use bridge_update::layout::{Image, memory_x};
    let mut memory = String::new();
    memory_x(Image::Firmware, &mut memory).unwrap();
    let flash = memory
        .lines()
        .find(|l| l.trim_start().starts_with("FLASH :"))
        .unwrap();
    let origin = u32::from_str_radix(
        flash
            .split("ORIGIN = 0x")
            .nth(1)
            .and_then(|l| l.split(',').next())
            .unwrap(),
        16,
    )
    .unwrap();
    let kib: u32 = flash
        .split("LENGTH = ")
        .nth(1)
        .and_then(|l| l.trim().strip_suffix('K'))
        .unwrap()
        .parse()
        .unwrap();
    assert!(origin + kib * 1024 <= layout::STORE_START, "{flash}");
    assert_eq!(layout::STORE_START, 0x080F_C000);
    assert_eq!(layout::STORE_END, 0x0810_0000);
}

/// The settings through the store's flash model, as the firmware starts: a blank store
/// starts on the defaults and says so (the store-reset LED code), and writes its header;
/// a setting set and saved on the console is the next start's configuration; a corrupt
/// store starts on the defaults again.
#[test]
fn a_setting_survives_a_restart_through_the_flash() {
    let start = |st: &mut FlashStore<MockFlash>| {
        block_on(bridge_fw::restore_settings(
            st,
            Config::DEFAULT,
            bridge_engine::Sides::COMPILED,
        ))
    };
    let mut st = store_of(MockFlash::blank());
    let (restored, unreadable) = start(&mut st);
    assert!(!unreadable);
    assert_eq!(restored.reset, Some(Problem::Missing), "blank: a reset");
    let mut e = Engine::restored(restored, bridge_engine::BuildInfo::ENGINE);
    let (_, action) = e.console_receive(Instant::ZERO, b"set pod_baud 230400\rsave\r");
    assert_eq!(action, None);
    let mut out = [0u8; 512];
    let mut said = Vec::new();
    while let n @ 1.. = e.console_transmit(&mut out) {
        said.extend_from_slice(&out[..n]);
    }
    let said = String::from_utf8_lossy(&said);
    assert!(said.contains("ok: 1 settings kept"), "{said}");
    let mut written = 0;
    while let Some(r) = e.take_record() {
        block_on(st.save(r.key.0, r.value())).unwrap();
        written += 1;
    }
    assert_eq!(written, 2, "the header, then the setting");

    // The next start (a fresh map over the same flash).
    let mut st = store_of(st.into_flash());
    let (restored, unreadable) = start(&mut st);
    assert!(!unreadable);
    assert_eq!(restored.reset, None);
    assert_eq!(restored.config().pod_baud, 230_400);
    assert_ne!(Config::DEFAULT.pod_baud, 230_400);

    let garbage: Vec<u8> = (0..SIZE).map(|i| (i * 151 % 251) as u8).collect();
    let mut st = store_of(MockFlash::of(garbage, vec![true; SIZE / WORD]));
    let (restored, unreadable) = start(&mut st);
    assert!(unreadable);
    assert_eq!(restored.reset, Some(Problem::Unreadable));
    assert_eq!(*restored.config(), Config::DEFAULT);
}
