//! The emulated board's PPS test source (`qemu` feature): QEMU's `b-l475e-iot01a` models no
//! timer, so no input capture, and cannot drive a GPIO input from outside; a byte on
//! USART1 (the ST-LINK virtual COM port, QEMU's first `-serial`) stands for an edge, taken
//! at the instant the reader sees it (the time driver's clock: the host's). What it
//! shows and what it cannot: docs/src/firmware/emulated-board.md.

use bridge_engine::InstantNs;
use bridge_fw::PpsInput;
use embassy_stm32::usart::BufferedUartRx;
use embedded_io_async::Read;

/// A byte on USART1 is a PPS edge.
pub struct PpsOverSerial {
    pub rx: BufferedUartRx<'static>,
}

impl PpsInput for PpsOverSerial {
    async fn edge(&mut self) -> InstantNs {
        let mut buf = [0u8; 8];
        loop {
            if matches!(self.rx.read(&mut buf).await, Ok(n) if n > 0) {
                return InstantNs::from_instant(bridge_fw::now());
            }
        }
    }
}
