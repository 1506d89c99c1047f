//! Bridge firmware for the STM32L475VG (B-L475E-IOT01A): the board binding ([`board`])
//! and the Embassy tasks, each a thin wrapper of a task of the `bridge_fw` library with
//! the concrete types.
//!
//! Flavours: `hw` (default; embassy-stm32's time driver, 80 MHz) and `qemu` (QEMU 10's
//! `b-l475e-iot01a`: time driver on the host clock with SysTick alarms, an executor idling
//! with WFI, 16 MHz, strap levels from the semihosting command line, the vendored
//! embassy-stm32's QEMU workarounds, semihosting boot line). See docs/src/firmware/emulated-board.md.
#![no_std]
#![no_main]
// The binary only brings the board up: its `expect`s are start-up checks of fixed things (a
// task pool taken twice, a UART configuration the peripheral refuses), build or board
// errors that panic-probe reports over defmt before anything runs. The tasks (library)
// keep the lint.
#![allow(clippy::expect_used)]

#[cfg(all(feature = "hw", feature = "qemu"))]
compile_error!(
    "`qemu` replaces the hardware time driver: build it with `--no-default-features --features qemu,fc-all`"
);

mod board;
#[cfg(feature = "qemu")]
#[allow(unsafe_code)]
mod qemu_executor;
#[cfg(feature = "qemu")]
mod qemu_pps;
#[allow(unsafe_code)]
mod stack;
#[cfg(feature = "qemu")]
#[allow(unsafe_code)]
mod systick_driver;
#[cfg(not(feature = "qemu"))]
mod tim2;

use bridge_fw::reset::ResetCause;
use bridge_fw::{Engine, Heartbeat, LogKind, LogRecord, Port, Shared, Timing};
use defmt_rtt as _;
use embassy_executor::Spawner;
use embassy_stm32::gpio::Output;
use embassy_stm32::peripherals::IWDG;
use embassy_stm32::usart::{BufferedUartRx, BufferedUartTx};
use embassy_stm32::wdg::IndependentWatchdog;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_time::Duration;
#[cfg(feature = "hw")]
use panic_probe as _;
use static_cell::StaticCell;

/// The tasks' shared state, concrete.
type BoardShared = Shared<CriticalSectionRawMutex, Engine>;

/// The watchdog check period (the supervised loops mark their heartbeat every 100 ms).
const WATCHDOG_PERIOD: Duration = Duration::from_millis(250);

#[cfg(not(feature = "qemu"))]
#[embassy_executor::main]
async fn main(spawner: Spawner) {
    start(spawner);
}

/// The emulated board: the same start-up on an executor that idles with WFI
/// ([`qemu_executor`]).
#[cfg(feature = "qemu")]
#[cortex_m_rt::entry]
fn main() -> ! {
    qemu_executor::run(start)
}

/// Brings the board up and spawns every task (with a strap error: only the LED's).
fn start(spawner: Spawner) {
    stack::paint();
    let b = board::init();
    let build = bridge_fw::config::BUILD;

    #[cfg(feature = "qemu")]
    {
        let core = cortex_m::Peripherals::take().expect("core peripherals taken twice");
        systick_driver::init(core.SYST, b.hclk);
        semihosting::println!(
            "bridge-fw (qemu): {}, reset: {}",
            DisplayBuild(&build),
            b.reset.name()
        );
    }
    defmt::info!(
        "bridge-fw {} commit {}{}, {}: {}; reset: {}",
        build.semver,
        build.commit,
        if build.dirty { "-dirty" } else { "" },
        build.flavour,
        build.features,
        b.reset
    );
    let config = match b.config {
        Ok(c) => c,
        Err(e) => {
            // No FC side: never another one. Nothing runs but the LED's code (and no
            // watchdog: no task would feed it).
            defmt::error!(
                "strap error: the straps select {}, which this build does not have; no FC side runs",
                e.wanted
            );
            #[cfg(feature = "qemu")]
            semihosting::println!(
                "bridge-fw (qemu): strap error: the straps select {}, not in this build; no FC side",
                fc_name(e.wanted)
            );
            spawner.spawn(strap_error_led(b.led).expect("task strap_error_led"));
            return;
        }
    };
    let mut watchdog = b.watchdog;
    watchdog.unleash();
    static FAULTS: bridge_fw::Faults = bridge_fw::Faults::new();
    if b.reset == ResetCause::Watchdog {
        FAULTS.raise(bridge_fw::Fault::WatchdogReset);
    }

    // The settings kept in the store, before the engine: the configuration to start with.
    let mut store = bridge_fw::FlashStore::new(b.store, board::store_range())
        .expect("the store's range is whole pages");
    let sides = bridge_engine::Sides::of(bridge_fw::config::COMPILED);
    let (mut restored, mut unreadable) =
        embassy_futures::block_on(bridge_fw::restore_settings(&mut store, config, sides));
    // The UARTs were made at the defaults' rates: a rate set differently is applied here,
    // or, one the UART cannot make, falls back to its default (the setting stays set).
    let (fc, pod) = (b.fc, b.pod);
    let started = *restored.config();
    if started.fc_baud != config.fc_baud && fc.set_baudrate(started.fc_baud).is_err() {
        restored.fall_back("fc_baud");
    }
    if started.pod_baud != config.pod_baud && pod.set_baudrate(started.pod_baud).is_err() {
        restored.fall_back("pod_baud");
    }
    #[cfg(feature = "telemetry")]
    let telemetry = b.telemetry;
    #[cfg(feature = "telemetry")]
    if started.telemetry_baud != config.telemetry_baud
        && telemetry.set_baudrate(started.telemetry_baud).is_err()
    {
        restored.fall_back("telemetry_baud");
    }
    let store_reset = restored.store_reset();
    let config = *restored.config();

    #[cfg(feature = "qemu")]
    semihosting::println!(
        "bridge-fw (qemu): up, HCLK {} Hz, FC {:?}",
        b.hclk,
        fc_name(config.fc)
    );
    // The same idle detection as on the board: QEMU hands the guest one received byte per
    // SysTick period (100 µs, `systick_driver`), well inside the 5 ms that ends a burst.
    let timing = Timing::from_config(&config);
    defmt::info!(
        "bridge-fw: up, HCLK {} Hz, FC {}, {}",
        b.hclk,
        config.fc,
        timing
    );
    static SHARED: StaticCell<BoardShared> = StaticCell::new();
    let shared: &'static BoardShared =
        SHARED.init_with(|| Shared::new(Engine::restored(restored, build), timing));

    let (fc_tx, fc_rx) = fc.split();
    let (pod_tx, pod_rx) = pod.split();
    spawner.spawn(fc_link(shared, fc_rx, fc_tx).expect("task fc_link"));
    spawner.spawn(pod_link(shared, pod_rx, pod_tx).expect("task pod_link"));
    #[cfg(feature = "telemetry")]
    {
        let (tel_tx, tel_rx) = telemetry.split();
        spawner.spawn(telemetry_link(shared, tel_rx, tel_tx).expect("task telemetry_link"));
    }
    // The other records kept across restarts (the signing state) go to the engine before
    // its first input.
    if !unreadable {
        unreadable = embassy_futures::block_on(bridge_fw::restore(shared, &mut store));
    }
    if unreadable {
        // Found corrupt: started on defaults (the engine said so); a blank store.
        let erased = embassy_futures::block_on(store.erase());
        defmt::warn!("store: unreadable, erased ({})", erased.is_ok());
    }
    if unreadable || store_reset {
        // Blank (a first start), unreadable, or its settings invalid together: the
        // defaults run, and the LED says so until the next start.
        defmt::warn!("store: reset, the settings are the defaults");
        FAULTS.raise(bridge_fw::Fault::StoreReset);
    }
    #[cfg(feature = "qemu")]
    semihosting::println!(
        "bridge-fw (qemu): store on a RAM model (QEMU cannot program flash): nothing kept across restarts"
    );
    spawner.spawn(store_records(shared, store).expect("task store"));
    spawner.spawn(engine(shared, b.rtc_io).expect("task engine"));
    spawner.spawn(pps(shared, b.pps).expect("task pps"));
    spawner.spawn(watchdog_task(shared, watchdog).expect("task watchdog"));
    spawner.spawn(led(shared, &FAULTS, config.fc, b.led).expect("task led"));
    spawner.spawn(log(shared).expect("task log"));
    spawner.spawn(console(shared, b.update, b.flash).expect("task console"));
    spawner.spawn(stack_watch().expect("task stack_watch"));
}

/// [`BuildInfo`](bridge_engine::BuildInfo) through `core::fmt` (semihosting's `println`).
#[cfg(feature = "qemu")]
struct DisplayBuild<'a>(&'a bridge_engine::BuildInfo);

#[cfg(feature = "qemu")]
impl core::fmt::Display for DisplayBuild<'_> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "version {}", self.0)
    }
}

/// The console and the update port ([`bridge_fw::console_task`]) over the update slot of
/// the flash layout; resets the board on `reboot` or when the update client asks (the
/// bootloader then swaps a verified image in).
#[embassy_executor::task]
async fn console(
    shared: &'static BoardShared,
    port: embassy_stm32::usart::BufferedUart<'static>,
    flash: &'static board::BoardFlash,
) -> ! {
    use bridge_fw::config::update::{FIRMWARE_VERSION, UPDATE_KEY, UPDATE_KEY_IS_DEV};
    use bridge_update::layout::{BOOT_STATE, DFU};
    use embassy_embedded_hal::flash::partition::BlockingPartition;
    if UPDATE_KEY_IS_DEV {
        defmt::warn!("update: images must be signed by the DEVELOPMENT key (not for the field)");
    }
    let (mut tx, mut rx) = port.split();
    let mut aligned = [0u8; 8];
    let slot = bridge_update::FlashSlot::new(
        BlockingPartition::new(flash, DFU.offset(), DFU.size),
        BlockingPartition::new(flash, BOOT_STATE.offset(), BOOT_STATE.size),
        &mut aligned,
    );
    match slot {
        Ok(mut slot) => {
            let mut receiver =
                bridge_update::Receiver::new(UPDATE_KEY, UPDATE_KEY_IS_DEV, FIRMWARE_VERSION);
            bridge_fw::console_task(shared, &mut rx, &mut tx, &mut slot, &mut receiver).await;
            // Let the answer leave the UART (a few bytes at 115200 baud).
            embassy_time::Timer::after_millis(20).await;
            cortex_m::peripheral::SCB::sys_reset()
        }
        Err(_) => {
            defmt::error!("update: the boot state cannot be read: no update port");
            loop {
                embassy_time::Timer::after_secs(3600).await;
            }
        }
    }
}

/// Logs the stack's high-water mark since start-up ended (every task and interrupt):
/// every minute over defmt, and on QEMU every 10 s on its stdout (the emulated-board
/// scenarios report it).
#[embassy_executor::task]
async fn stack_watch() -> ! {
    // Start-up builds the engine on the stack (in `main`'s frame) before moving it into
    // its static: report that once, then, `main` having returned, paint again so that
    // what follows is the tasks' and interrupts' own depth.
    let (boot, total) = stack::high_water();
    defmt::info!("stack: start-up used {} of {} bytes", boot, total);
    #[cfg(feature = "qemu")]
    semihosting::println!(
        "bridge-fw (qemu): stack at start-up {} of {} bytes",
        boot,
        total
    );
    stack::paint();
    let period = if cfg!(feature = "qemu") { 10 } else { 60 };
    loop {
        embassy_time::Timer::after_secs(period).await;
        let (used, total) = stack::high_water();
        defmt::info!("stack: {} of {} bytes used at most", used, total);
        #[cfg(feature = "qemu")]
        semihosting::println!(
            "bridge-fw (qemu): stack high-water {} of {} bytes",
            used,
            total
        );
    }
}

#[cfg(feature = "qemu")]
fn fc_name(fc: bridge_engine::FcProtocol) -> &'static str {
    use bridge_engine::FcProtocol;
    match fc {
        FcProtocol::Siyi => "siyi",
        FcProtocol::Viewlink => "viewlink",
        FcProtocol::Gcu => "gcu",
        FcProtocol::K40t => "k40t",
        FcProtocol::Mavlink => "mavlink",
    }
}

#[embassy_executor::task]
async fn fc_link(
    shared: &'static BoardShared,
    rx: BufferedUartRx<'static>,
    tx: BufferedUartTx<'static>,
) -> ! {
    bridge_fw::link(shared, Port::Fc, rx, tx).await
}

#[embassy_executor::task]
async fn pod_link(
    shared: &'static BoardShared,
    rx: BufferedUartRx<'static>,
    tx: BufferedUartTx<'static>,
) -> ! {
    bridge_fw::link(shared, Port::Pod, rx, tx).await
}

/// The MAVLink telemetry link (LPUART1), beside any FC side (beside the MAVLink side:
/// when its link gives no time, as PX4 1.16's in mode Gimbal).
#[cfg(feature = "telemetry")]
#[embassy_executor::task]
async fn telemetry_link(
    shared: &'static BoardShared,
    rx: BufferedUartRx<'static>,
    tx: BufferedUartTx<'static>,
) -> ! {
    bridge_fw::link(shared, Port::Telemetry, rx, tx).await
}

/// RTC_IO: TIM2 CH3's output compare on the board, a GPIO on the emulated board.
#[cfg(not(feature = "qemu"))]
type RtcIoPin = tim2::RtcCompare;
#[cfg(feature = "qemu")]
type RtcIoPin = Output<'static>;
/// The PPS input: TIM2 CH1's capture on the board, a byte on USART1 on the emulated one.
#[cfg(not(feature = "qemu"))]
type PpsPin = tim2::PpsCapture;
#[cfg(feature = "qemu")]
type PpsPin = qemu_pps::PpsOverSerial;

/// The persistent store's writer.
#[embassy_executor::task]
async fn store_records(
    shared: &'static BoardShared,
    store: bridge_fw::FlashStore<board::StoreFlash>,
) -> ! {
    bridge_fw::store_task(shared, store).await
}

#[embassy_executor::task]
async fn engine(shared: &'static BoardShared, rtc_io: RtcIoPin) -> ! {
    bridge_fw::engine_task(shared, rtc_io).await
}

#[embassy_executor::task]
async fn pps(shared: &'static BoardShared, input: PpsPin) -> ! {
    bridge_fw::pps_task(shared, input).await
}

#[embassy_executor::task]
async fn watchdog_task(
    shared: &'static BoardShared,
    mut wd: IndependentWatchdog<'static, IWDG>,
) -> ! {
    // The telemetry link's loops run (and are supervised) whenever it is built in.
    let supervised = Heartbeat::supervised(cfg!(feature = "telemetry"));
    bridge_fw::watchdog_task(shared, WATCHDOG_PERIOD, supervised, || wd.pet()).await
}

#[embassy_executor::task]
async fn led(
    shared: &'static BoardShared,
    faults: &'static bridge_fw::Faults,
    fc: bridge_engine::FcProtocol,
    led: Output<'static>,
) -> ! {
    bridge_fw::led_task(shared, faults, fc, led).await
}

/// The strap error's LED code, forever (the only task of a board without an FC side).
#[embassy_executor::task]
async fn strap_error_led(led: Output<'static>) -> ! {
    bridge_fw::strap_error_led(led).await
}

#[embassy_executor::task]
async fn log(shared: &'static BoardShared) -> ! {
    bridge_fw::log_task(shared, |r: &LogRecord| {
        #[cfg(feature = "qemu")]
        qemu_time_event(r);
        log_defmt(r);
    })
    .await
}

/// The time-sync events (and the time source and the PPS lock) on QEMU's stdout (the
/// emulated-board scenarios report them).
#[cfg(feature = "qemu")]
fn qemu_time_event(r: &LogRecord) {
    use bridge_fw::Event;
    let at = r.at.as_micros();
    match r.what {
        LogKind::Engine(Event::UtcValid {
            error_bound_us,
            converged,
        }) => semihosting::println!(
            "bridge-fw (qemu): {at} us: UTC valid, bound {error_bound_us} us, converged {converged}"
        ),
        LogKind::Engine(Event::UtcLost) => {
            semihosting::println!("bridge-fw (qemu): {at} us: UTC lost")
        }
        LogKind::Engine(Event::PpsLocked { first_edge }) => semihosting::println!(
            "bridge-fw (qemu): {at} us: PPS locked, first edge {} us",
            first_edge.as_micros()
        ),
        LogKind::Engine(Event::PpsHoldover) => {
            semihosting::println!("bridge-fw (qemu): {at} us: PPS holdover")
        }
        LogKind::Engine(Event::PpsReleased) => {
            semihosting::println!("bridge-fw (qemu): {at} us: PPS released")
        }
        LogKind::Engine(Event::TimeSource { telemetry }) => semihosting::println!(
            "bridge-fw (qemu): {at} us: time source {}",
            if telemetry { "telemetry" } else { "fc" }
        ),
        LogKind::Engine(Event::TimeSync {
            edge,
            utc_ms,
            error_bound_us,
        }) => semihosting::println!(
            "bridge-fw (qemu): {at} us: time sync, edge {} us, UTC {utc_ms} ms, bound {error_bound_us} us",
            edge.as_micros()
        ),
        _ => {}
    }
}

fn log_defmt(r: &LogRecord) {
    match r.what {
        LogKind::ReadError(_)
        | LogKind::WriteError(_)
        | LogKind::PinError(_)
        | LogKind::Stalled(_)
        | LogKind::StoreError(_) => {
            defmt::warn!("{}", r);
        }
        _ => defmt::info!("{}", r),
    }
}

/// Emulated board: report a fault on QEMU's stdout and end QEMU with a failure code, so a
/// CI run fails at once instead of timing out.
#[cfg(feature = "qemu")]
#[allow(unsafe_code)]
#[cortex_m_rt::exception]
unsafe fn HardFault(frame: &cortex_m_rt::ExceptionFrame) -> ! {
    semihosting::eprintln!("bridge-fw (qemu): HardFault, PC {:#010x}", frame.pc());
    semihosting::process::exit(1)
}
