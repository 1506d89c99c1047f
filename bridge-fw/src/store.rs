//! The persistent store: the engine's records ([`bridge_engine::store`]) kept in a flash
//! range through sequential-storage's map ([`FlashStore`], over any
//! `embedded_storage_async` NOR flash), or anywhere else a [`RecordStore`] keeps them (the
//! Linux runner's state file). The engine decides what to save and when; this module
//! only moves the bytes: [`restore`] hands the engine what the store holds before the
//! first input, [`store_task`] writes what the engine gives.
//!
//! # Why sequential-storage's map
//! The STM32L4's flash has ECC: a double word (8 bytes) is written once between erases
//! (a second write, even of the same bits, is refused), and a page (2 KiB) is the erase
//! unit. sequential-storage's map appends each record as a new item (a header with a CRC,
//! then the value, in whole words) and erases a page only when the range is full; reading
//! a key finds its newest item whose CRC checks. `store_item` and `fetch_item` need
//! only `NorFlash` (each word written once); the map's removal and the queue's pop need
//! `MultiwriteNorFlash` (a word written twice), which this flash is not, and are not used.
//! An item cut by a power loss fails its CRC and the previous item of its key is read; a
//! page state cut half-way is repaired on the next access (the crate's auto-repair).
//! The records are overwritten in place by appending, so the wear spreads over the eight
//! pages: at one timestamp save in 30 s (48 bytes with its header) a page is erased about
//! every 7 hours of signing.

use core::future::Future;
use core::sync::atomic::Ordering;

use bridge_engine::store::{Key, MAX_VALUE, Problem};
use bridge_engine::{Config, Restore, Restored, Sides};
use embassy_sync::blocking_mutex::raw::RawMutex;
use embedded_storage_async::nor_flash::NorFlash;
use sequential_storage::cache::{Cache, Uncached};
use sequential_storage::map::{MapConfig, MapStorage};

use crate::engine::BridgeEngine;
use crate::shared::{LogKind, Shared};

/// A place that keeps the engine's records by key.
pub trait RecordStore {
    /// Reads the record of `key` into `buf`: its length, `None` when there is none.
    /// An error means the store cannot be read.
    fn load(&mut self, key: u16, buf: &mut [u8])
    -> impl Future<Output = Result<Option<usize>, ()>>;
    /// Writes `value` as the record of `key`, replacing any before.
    fn save(&mut self, key: u16, value: &[u8]) -> impl Future<Output = Result<(), ()>>;
}

/// Bytes of the work buffer: a record's key (2 bytes) and longest value, in whole words
/// of the largest flash write (8 bytes).
const BUFFER: usize = (2 + MAX_VALUE).div_ceil(8) * 8;

/// A store's range that is not whole pages of its flash, or fewer than two.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RangeError;

/// sequential-storage's cache, none (the store is read once, at start).
type NoCache = Cache<Uncached, Uncached, Uncached, u16>;

/// The records in a range of a NOR flash, through sequential-storage's map.
pub struct FlashStore<F: NorFlash> {
    map: MapStorage<u16, F, NoCache>,
    buf: [u8; BUFFER],
}

impl<F: NorFlash> FlashStore<F> {
    /// The store in `range` of `flash` (offsets from the flash's start; whole pages, at
    /// least two).
    ///
    /// # Errors
    /// A range that is not whole pages, or shorter than two.
    pub fn new(flash: F, range: core::ops::Range<u32>) -> Result<Self, RangeError> {
        let config = MapConfig::try_new(range).map_err(|_| RangeError)?;
        Ok(FlashStore {
            map: MapStorage::new(flash, config, Cache::new_uncached()),
            buf: [0; BUFFER],
        })
    }

    /// Erases the whole range (a store found corrupt starts blank).
    pub async fn erase(&mut self) -> Result<(), ()> {
        self.map.erase_all().await.map_err(|_| ())
    }

    /// The flash.
    pub fn flash_mut(&mut self) -> &mut F {
        self.map.flash()
    }

    /// The flash, back.
    pub fn into_flash(self) -> F {
        self.map.destroy().0
    }
}

impl<F: NorFlash> RecordStore for FlashStore<F> {
    async fn load(&mut self, key: u16, buf: &mut [u8]) -> Result<Option<usize>, ()> {
        let value: Option<&[u8]> = self
            .map
            .fetch_item(&mut self.buf, &key)
            .await
            .map_err(|_| ())?;
        Ok(value.map(|v| {
            let n = v.len().min(buf.len());
            for (d, s) in buf.iter_mut().zip(v) {
                *d = *s;
            }
            n
        }))
    }

    async fn save(&mut self, key: u16, value: &[u8]) -> Result<(), ()> {
        self.map
            .store_item(&mut self.buf, &key, &value)
            .await
            .map_err(|_| ())
    }
}

/// Hands the engine every record `store` holds ([`Key::ALL`]), before its first input.
/// A store that cannot be read: the engine is told ([`Problem::Unreadable`]) and starts on
/// its defaults; `true` is returned so that the caller may start the store afresh.
pub async fn restore<M: RawMutex, E: BridgeEngine>(
    shared: &Shared<M, E>,
    store: &mut impl RecordStore,
) -> bool {
    let mut buf = [0u8; MAX_VALUE];
    for key in Key::ALL {
        match store.load(key.0, &mut buf).await {
            Ok(Some(n)) => {
                let value = buf.get(..n).unwrap_or_default();
                shared.input(|e| e.restore(key.0, value));
            }
            Ok(None) => {}
            Err(()) => {
                shared.input(|e| e.restore_failed(Problem::Unreadable));
                return true;
            }
        }
    }
    false
}

/// Reads the settings' records from `store` ([`Restore::keys`]) before the engine is made:
/// the configuration to start with (`defaults` with the settings kept) and what the engine
/// reports ([`Engine::restored`](bridge_engine::Engine::restored)). `true` with it: the
/// store could not be read (the caller may start it afresh).
pub async fn restore_settings(
    store: &mut impl RecordStore,
    defaults: Config,
    sides: Sides,
) -> (Restored, bool) {
    let mut restore = Restore::new(defaults, sides);
    let mut buf = [0u8; MAX_VALUE];
    let mut unreadable = false;
    for key in Restore::keys() {
        match store.load(key, &mut buf).await {
            Ok(Some(n)) => restore.record(key, buf.get(..n).unwrap_or_default()),
            Ok(None) => {}
            Err(()) => {
                restore.unreadable();
                unreadable = true;
                break;
            }
        }
    }
    (restore.finish(), unreadable)
}

/// Writes every record the engine gives ([`BridgeEngine::take_record`]) to `store`, woken
/// by [`Changes::STORE`](bridge_engine::Changes::STORE). A write that fails is logged
/// ([`LogKind::StoreError`]); the engine asks again at its next save. Not supervised by the
/// watchdog: it sleeps while nothing is to be saved.
pub async fn store_task<M: RawMutex, E: BridgeEngine>(
    shared: &Shared<M, E>,
    mut store: impl RecordStore,
) -> ! {
    loop {
        shared.wake_store.wait().await;
        loop {
            // Marked busy in the same lock that takes the record: a restart waits for
            // the write it started (`records_due` no longer shows the record).
            let taken = shared.with(|e| {
                let r = e.take_record();
                shared.store_busy.store(r.is_some(), Ordering::Release);
                r
            });
            let Some(record) = taken else { break };
            if store.save(record.key.0, record.value()).await.is_err() {
                shared.record(crate::now(), LogKind::StoreError(record.key.0));
            }
        }
        shared.store_busy.store(false, Ordering::Release);
    }
}
