//! The B-L475E-IOT01A binding: clocks, pins, UARTs, RTC_IO, LED2, watchdog, strap pins,
//! the reset cause.
//!
//! | signal | MCU pin | board connector | level | to |
//! | --- | --- | --- | --- | --- |
//! | FC TX (UART4, AF8) | PA0 | Arduino D1 | 3.3 V | FC's RX |
//! | FC RX (UART4, AF8) | PA1 | Arduino D0 | 3.3 V (5 V tolerant) | FC's TX |
//! | pod TX (USART2, AF7) | PD5 | PMOD pin 2 (PMOD_UART2_TX) | 3.3 V | pod's RX |
//! | pod RX (USART2, AF7) | PD6 | PMOD pin 3 (PMOD_UART2_RX) | 3.3 V (5 V tolerant) | pod's TX |
//! | telemetry TX (LPUART1, AF8) | PC1 | Arduino A4 | 3.3 V | autopilot's telemetry RX |
//! | telemetry RX (LPUART1, AF8) | PC0 | Arduino A5 | 3.3 V (5 V tolerant) | autopilot's telemetry TX |
//! | RTC_IO (TIM2_CH3 output compare, AF1; `qemu`: GPIO) | PA2 | Arduino D10 | 3.3 V | pod's RTC_IO |
//! | PPS in (TIM2_CH1 input capture, AF1, pull-down) | PA15 | Arduino D9 | 3.3 V (5 V tolerant) | GNSS module's PPS / timepulse |
//! | FC strap A (in, pull-up) | PA3 | Arduino D4 | open / GND | (all-FC builds) |
//! | FC strap B (in, pull-up) | PA4 | Arduino D7 | open / GND | (all-FC builds) |
//! | FC strap C (in, pull-up) | PB2 | Arduino D8 | open / GND (MAVLink) | (all-FC builds) |
//! | LED2 | PB14 | on board | | |
//!
//! The telemetry rows are wired only in builds with the `telemetry` feature (a MAVLink 2
//! serial port of the autopilot: ArduPilot `SERIALn_PROTOCOL 2`, PX4 `MAV_n_CONFIG`); the
//! Arduino analog header's A4/A5 carry LPUART1 (AF8) and nothing else on this board, so
//! the FC and telemetry links are both on the Arduino connector.
//!
//! | update port TX / RX (USART1, AF7) | PB6 / PB7 | ST-LINK virtual COM port (USB) | 3.3 V | the host's `gimbal update` |
//!
//! TIM2 (32-bit, 80 MHz) carries both timing pins on one counter (`src/tim2.rs`); the
//! embassy-time driver is on TIM15 (`time-driver-tim15`). USART1 (the ST-LINK virtual COM
//! port) is the update port on the board; the `qemu` flavour takes its PPS test source there
//! and its update port on USART3 (a
//! byte an edge: QEMU models no timer and cannot drive a GPIO input). USART3 is wired
//! to the on-board modules, not to a header.

use core::cell::RefCell;

use bridge_engine::Config;
use bridge_fw::config::StrapError;
use bridge_fw::reset::ResetCause;
use embassy_stm32::flash::{Blocking, Flash};
#[cfg(not(feature = "qemu"))]
use embassy_stm32::gpio::OutputType;
use embassy_stm32::gpio::{Input, Level, Output, Pull, Speed};
use embassy_stm32::peripherals::IWDG;
#[cfg(not(feature = "qemu"))]
use embassy_stm32::timer::{self, input_capture, low_level::CountingMode, simple_pwm::PwmPin};
use embassy_stm32::usart::{self, BufferedUart};
use embassy_stm32::wdg::IndependentWatchdog;
use embassy_stm32::{bind_interrupts, peripherals};
use embassy_sync::blocking_mutex::Mutex;
use embassy_sync::blocking_mutex::raw::ThreadModeRawMutex;
use static_cell::StaticCell;

bind_interrupts!(struct Irqs {
    UART4 => usart::BufferedInterruptHandler<peripherals::UART4>;
    USART2 => usart::BufferedInterruptHandler<peripherals::USART2>;
    #[cfg(feature = "telemetry")]
    LPUART1 => usart::BufferedInterruptHandler<peripherals::LPUART1>;
    #[cfg(not(feature = "qemu"))]
    TIM2 => timer::CaptureCompareInterruptHandler<peripherals::TIM2>;
    // The update port on the board, the PPS test source on the emulated board.
    USART1 => usart::BufferedInterruptHandler<peripherals::USART1>;
    #[cfg(feature = "qemu")]
    USART3 => usart::BufferedInterruptHandler<peripherals::USART3>;
});

/// The flash, shared by the parts that write it (the update slot, and the store): a
/// thread-mode mutex, so an erase does not mask the UARTs' interrupts. The update slot
/// and the store are in bank 2, the code in bank 1: the CPU keeps running while bank 2 is
/// erased or programmed.
pub type BoardFlash = Mutex<ThreadModeRawMutex, RefCell<Flash<'static, Blocking>>>;

/// The persistent store's flash: its 16 KiB at the end of bank 2 (`bridge_fw::layout`),
/// a partition of [`BoardFlash`] seen through sequential-storage's async traits (each
/// operation completes before it returns: a page erase holds the executor for about
/// 22 ms, once per several hours of signing).
#[cfg(not(feature = "qemu"))]
pub type StoreFlash = embassy_embedded_hal::adapter::BlockingAsync<
    embassy_embedded_hal::flash::partition::BlockingPartition<
        'static,
        ThreadModeRawMutex,
        Flash<'static, Blocking>,
    >,
>;
/// The emulated board's store: a RAM model of two 512-byte pages (QEMU's flash is
/// read-only memory and its flash controller is not modelled: the store forgets at each
/// start).
#[cfg(feature = "qemu")]
pub type StoreFlash = bridge_fw::ram_flash::RamFlash<'static, 512>;

/// The store's range in [`StoreFlash`] (offsets from its start: the partition is the
/// store's own range).
#[must_use]
pub const fn store_range() -> core::ops::Range<u32> {
    #[cfg(not(feature = "qemu"))]
    {
        let r = bridge_fw::layout::store_offsets();
        0..(r.end - r.start)
    }
    #[cfg(feature = "qemu")]
    {
        0..1024
    }
}

/// Bytes of each UART ring buffer (22 ms at 115200: far more than any task's latency).
const UART_BUF: usize = 256;

/// The watchdog's time-out (LSI 32 kHz nominal, 29.5..34 kHz: 0.69..0.81 s): more than two
/// feed periods, so one late check does not reset, and a stall resets in under 1 s.
pub const WATCHDOG_TIMEOUT_US: u32 = 750_000;

/// What the firmware runs on.
pub struct Board {
    /// The FC link.
    pub fc: BufferedUart<'static>,
    /// The pod link.
    pub pod: BufferedUart<'static>,
    /// The MAVLink telemetry link (LPUART1).
    #[cfg(feature = "telemetry")]
    pub telemetry: BufferedUart<'static>,
    /// RTC_IO, low: TIM2 CH3's output compare.
    #[cfg(not(feature = "qemu"))]
    pub rtc_io: crate::tim2::RtcCompare,
    /// RTC_IO, low: a GPIO set at the timer alarm (QEMU models no timer).
    #[cfg(feature = "qemu")]
    pub rtc_io: Output<'static>,
    /// The PPS input: TIM2 CH1's capture.
    #[cfg(not(feature = "qemu"))]
    pub pps: crate::tim2::PpsCapture,
    /// The PPS test source: a byte on USART1 is an edge, at the instant it arrives.
    #[cfg(feature = "qemu")]
    pub pps: crate::qemu_pps::PpsOverSerial,
    /// The update port: the ST-LINK virtual COM port (USART1, PB6/PB7); on the emulated
    /// board USART3 (USART1 is the PPS test source there).
    pub update: BufferedUart<'static>,
    /// The flash.
    pub flash: &'static BoardFlash,
    /// LED2, on (from the start of [`init`]: a board stuck starting up stays lit).
    pub led: Output<'static>,
    /// The independent watchdog, configured, not yet started (`unleash`: once the FC side
    /// is known; a strap error runs no task to feed it).
    pub watchdog: IndependentWatchdog<'static, IWDG>,
    /// The configuration, FC protocol resolved (straps read if the build says so), or the
    /// straps' error.
    pub config: Result<Config, StrapError>,
    /// Why the MCU reset (RCC_CSR, read and cleared at boot).
    pub reset: ResetCause,
    /// HCLK, Hz.
    pub hclk: u32,
    /// The persistent store's flash: the settings (every build), and the signing
    /// timestamps and keys (builds with a MAVLink link).
    pub store: StoreFlash,
}

/// Clock tree. Hardware: 80 MHz from the PLL on HSI16. The emulated board must keep HCLK
/// at 16 MHz or less: QEMU does not model the flash interface (FLASH_ACR reads 0) and
/// embassy-stm32 polls until it reads back the wait states it wrote, 0 only up to 16 MHz.
fn clock_config() -> embassy_stm32::Config {
    use embassy_stm32::rcc::Sysclk;
    let mut config = embassy_stm32::Config::default();
    config.rcc.hsi = true;
    // LPUART1 (the telemetry link) on HSI16 rather than PCLK1: its BRR (256 × clock / baud,
    // 0x300..0xFFFFF, no prescaler on the L4) then takes 3 907 to 5 333 333 baud (4800 to
    // 4M, every MAVLink telemetry rate); on the 80 MHz PCLK1, 19200 baud would not fit. The
    // PLL runs from the same HSI16, so the rate is as accurate as the other UARTs'.
    #[cfg(feature = "telemetry")]
    {
        config.rcc.mux.lpuart1sel = embassy_stm32::rcc::mux::Lpuart1sel::HSI;
    }
    #[cfg(not(feature = "qemu"))]
    {
        use embassy_stm32::rcc::{Pll, PllMul, PllPreDiv, PllRDiv, PllSource};
        // 16 MHz HSI / 1 * 10 / 2 = 80 MHz.
        config.rcc.pll = Some(Pll {
            source: PllSource::HSI,
            prediv: PllPreDiv::DIV1,
            mul: PllMul::MUL10,
            divp: None,
            divq: None,
            divr: Some(PllRDiv::DIV2),
        });
        config.rcc.sys = Sysclk::PLL1_R;
    }
    #[cfg(feature = "qemu")]
    {
        config.rcc.sys = Sysclk::HSI;
    }
    config
}

/// The emulated board's strap levels, from the semihosting command line: QEMU cannot drive
/// a GPIO input from outside (an unconnected pin reads its pull, so the straps read open),
/// so the `qemu` flavour takes `straps=AB` or `straps=ABC`, each `0` (grounded, reads low)
/// or `1` (open; C open when absent), from QEMU's
/// `-semihosting-config enable=on,arg=bridge-fw,arg=straps=ABC`. `None` (pins as read)
/// without such an argument or with a malformed one.
#[cfg(feature = "qemu")]
fn qemu_straps() -> Option<(bool, bool, bool)> {
    let mut buf = [core::mem::MaybeUninit::<u8>::uninit(); 128];
    let line = semihosting::sys::arm_compat::sys_get_cmdline_uninit(&mut buf).ok()?;
    let arg = line
        .split(|&c| c == b' ')
        .find_map(|word| word.strip_prefix(b"straps="))?;
    match arg {
        [a @ (b'0' | b'1'), b @ (b'0' | b'1')] => Some((*a == b'0', *b == b'0', false)),
        [a @ (b'0' | b'1'), b @ (b'0' | b'1'), c @ (b'0' | b'1')] => {
            Some((*a == b'0', *b == b'0', *c == b'0'))
        }
        _ => None,
    }
}

/// Brings the board up. Panics only on a board or build error (a UART configuration
/// the peripheral refuses, a buffer taken twice).
pub fn init() -> Board {
    // The reset flags before anything can reset again; cleared so the next boot reads
    // only its own (RMVF).
    let csr = embassy_stm32::pac::RCC.csr().read().0;
    embassy_stm32::pac::RCC.csr().modify(|w| w.set_rmvf(true));
    let p = embassy_stm32::init(clock_config());
    let led = Output::new(p.PB14, Level::High, Speed::Low);
    let hclk = embassy_stm32::rcc::clocks(&p.RCC)
        .hclk1
        .to_hertz()
        .map_or(0, |hz| hz.0);

    let config = bridge_fw::config::resolve(|| {
        let a = Input::new(p.PA3, Pull::Up);
        let b = Input::new(p.PA4, Pull::Up);
        let c = Input::new(p.PB2, Pull::Up);
        // Let the pull-ups charge the header pins (40 kΩ, some 10 pF: well under 1 µs).
        cortex_m::asm::delay(hclk / 100_000);
        let levels = (a.is_low(), b.is_low(), c.is_low());
        #[cfg(feature = "qemu")]
        let levels = qemu_straps().unwrap_or(levels);
        levels
    });

    // The emulated board's PPS test source is stamped when the reader task sees its byte
    // (milliseconds of jitter under QEMU), not by a capture register: a wide tolerance.
    #[cfg(feature = "qemu")]
    let config = config.map(|mut c| {
        c.pps.tolerance_ns = 20_000_000;
        c
    });
    // Without a side, the links run at the configuration's rates (nothing reads them).
    let rates = config.map_or(bridge_fw::config::CONFIG, |c| c);

    let watchdog = IndependentWatchdog::new(p.IWDG, WATCHDOG_TIMEOUT_US);

    let uart = |baud: u32| {
        let mut c = usart::Config::default(); // 8N1
        c.baudrate = baud;
        // Wake the reader on every byte: frames are handled as they arrive, and QEMU's
        // USART never raises IDLE, the other thing that wakes a buffered read.
        c.eager_reads = Some(1);
        c
    };
    static FC_TX: StaticCell<[u8; UART_BUF]> = StaticCell::new();
    static FC_RX: StaticCell<[u8; UART_BUF]> = StaticCell::new();
    static POD_TX: StaticCell<[u8; UART_BUF]> = StaticCell::new();
    static POD_RX: StaticCell<[u8; UART_BUF]> = StaticCell::new();
    let fc = BufferedUart::new(
        p.UART4,
        p.PA1,
        p.PA0,
        FC_TX.init([0; UART_BUF]),
        FC_RX.init([0; UART_BUF]),
        Irqs,
        uart(rates.fc_baud),
    )
    .expect("FC UART configuration");
    let pod = BufferedUart::new(
        p.USART2,
        p.PD6,
        p.PD5,
        POD_TX.init([0; UART_BUF]),
        POD_RX.init([0; UART_BUF]),
        Irqs,
        uart(rates.pod_baud),
    )
    .expect("pod UART configuration");
    // LPUART1 on HSI16 (`clock_config`).
    #[cfg(feature = "telemetry")]
    let telemetry = {
        static TEL_TX: StaticCell<[u8; UART_BUF]> = StaticCell::new();
        static TEL_RX: StaticCell<[u8; UART_BUF]> = StaticCell::new();
        BufferedUart::new(
            p.LPUART1,
            p.PC0,
            p.PC1,
            TEL_TX.init([0; UART_BUF]),
            TEL_RX.init([0; UART_BUF]),
            Irqs,
            uart(rates.telemetry_baud),
        )
        .expect("telemetry UART configuration")
    };

    // TIM2 at the timer clock (HCLK: the APB1 prescaler is 1), counting from here; the
    // PPS capture on CH1, RTC_IO on CH3's compare, both mapped to the engine's clock by
    // one pair of counter reads (src/tim2.rs).
    #[cfg(not(feature = "qemu"))]
    let (rtc_io, pps) = {
        assert_eq!(hclk, 80_000_000, "TIM2's ticks are 12.5 ns (src/tim2.rs)");
        let pps_pin: input_capture::CapturePin<'static, peripherals::TIM2, timer::Ch1> =
            input_capture::CapturePin::new(p.PA15, Pull::Down);
        let capture = input_capture::InputCapture::new(
            p.TIM2,
            Some(pps_pin),
            None,
            None,
            None,
            Irqs,
            embassy_stm32::time::Hertz(hclk),
            CountingMode::EdgeAlignedUp,
        );
        embassy_stm32::pac::TIM2.arr().write_value(u32::MAX);
        let clock = crate::tim2::read_tick_clock();
        let rtc_pin: PwmPin<'static, peripherals::TIM2, timer::Ch3> =
            PwmPin::new(p.PA2, OutputType::PushPull);
        (
            crate::tim2::RtcCompare::new(rtc_pin, clock),
            crate::tim2::PpsCapture {
                capture,
                clock,
                falling: rates.pps.active_low,
            },
        )
    };
    #[cfg(feature = "qemu")]
    let (rtc_io, pps) = {
        static PPS_TX: StaticCell<[u8; 16]> = StaticCell::new();
        static PPS_RX: StaticCell<[u8; 16]> = StaticCell::new();
        let serial = BufferedUart::new(
            p.USART1,
            p.PB7,
            p.PB6,
            PPS_TX.init([0; 16]),
            PPS_RX.init([0; 16]),
            Irqs,
            uart(115_200),
        )
        .expect("PPS test source UART configuration");
        let (_, rx) = serial.split();
        (
            Output::new(p.PA2, Level::Low, Speed::VeryHigh),
            crate::qemu_pps::PpsOverSerial { rx },
        )
    };

    static UPDATE_TX: StaticCell<[u8; UART_BUF]> = StaticCell::new();
    static UPDATE_RX: StaticCell<[u8; UART_BUF]> = StaticCell::new();
    // The ST-LINK virtual COM port; on the emulated board USART3 (its USART1 is the PPS
    // test source).
    #[cfg(not(feature = "qemu"))]
    let (update_uart, update_rx, update_tx) = (p.USART1, p.PB7, p.PB6);
    #[cfg(feature = "qemu")]
    let (update_uart, update_rx, update_tx) = (p.USART3, p.PD9, p.PD8);
    let update = BufferedUart::new(
        update_uart,
        update_rx,
        update_tx,
        UPDATE_TX.init([0; UART_BUF]),
        UPDATE_RX.init([0; UART_BUF]),
        Irqs,
        uart(115_200),
    )
    .expect("update UART configuration");
    static FLASH: StaticCell<BoardFlash> = StaticCell::new();
    let flash = FLASH.init(Mutex::new(RefCell::new(Flash::new_blocking(p.FLASH))));

    Board {
        fc,
        pod,
        update,
        flash,
        #[cfg(feature = "telemetry")]
        telemetry,
        rtc_io,
        pps,
        led,
        watchdog,
        config,
        reset: ResetCause::from_rcc_csr(csr),
        hclk,
        #[cfg(not(feature = "qemu"))]
        store: {
            let r = bridge_fw::layout::store_offsets();
            embassy_embedded_hal::adapter::BlockingAsync::new(
                embassy_embedded_hal::flash::partition::BlockingPartition::new(
                    flash,
                    r.start,
                    r.end - r.start,
                ),
            )
        },
        #[cfg(feature = "qemu")]
        store: {
            static STORE: StaticCell<[u8; 1024]> = StaticCell::new();
            bridge_fw::ram_flash::RamFlash::new(STORE.init([0xFF; 1024]))
        },
    }
}
