//! The port a client tool opens to the board: `gimbal config` (the console) and `gimbal
//! update` (the update port). A serial device at a baud rate, or `tcp:HOST:PORT` (a
//! board's port forwarded over the network, or `gimbal bridge`'s console).

use std::io::{self, Read, Write};
use std::net::TcpStream;
use std::time::Duration;

/// An open client port: bytes both ways.
pub trait ReadWrite: Read + Write + Send {}
impl<T: Read + Write + Send> ReadWrite for T {}

/// Opens `port` (a serial device at `baud`, 8N1, or `tcp:HOST:PORT`); a read waits at most
/// `read_timeout` ([`timed_out`] tells such a read's error).
///
/// # Errors
/// The port cannot be opened, as `PORT: reason`.
pub fn open(port: &str, baud: u32, read_timeout: Duration) -> Result<Box<dyn ReadWrite>, String> {
    let opened: io::Result<Box<dyn ReadWrite>> = match port.strip_prefix("tcp:") {
        Some(addr) => TcpStream::connect(addr).and_then(|s| {
            s.set_read_timeout(Some(read_timeout))?;
            Ok(Box::new(s) as Box<dyn ReadWrite>)
        }),
        None => serialport::new(port, baud)
            .timeout(read_timeout)
            .open()
            .map(|p| Box::new(p) as Box<dyn ReadWrite>)
            .map_err(io::Error::from),
    };
    opened.map_err(|e| format!("{port}: {e}"))
}

/// Whether a read's error is its timeout running out (a serial port says `TimedOut`, a TCP
/// socket `WouldBlock` or `TimedOut`).
#[must_use]
pub fn timed_out(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::net::TcpListener;

    #[test]
    fn a_tcp_port_opens_reads_with_its_timeout_and_writes() {
        let listener = TcpListener::bind("127.0.0.1:0").unwrap();
        let addr = listener.local_addr().unwrap();
        let mut port = open(&format!("tcp:{addr}"), 115_200, Duration::from_millis(20)).unwrap();
        let (mut peer, _) = listener.accept().unwrap();
        let mut buf = [0u8; 8];
        let e = port.read(&mut buf).unwrap_err();
        assert!(timed_out(&e), "{e:?}");
        port.write_all(b"hi").unwrap();
        let mut got = [0u8; 2];
        peer.read_exact(&mut got).unwrap();
        assert_eq!(&got, b"hi");
    }

    #[test]
    fn a_port_that_cannot_open_says_which_and_why() {
        let e = open("/dev/no-such-port", 115_200, Duration::from_millis(20))
            .err()
            .unwrap();
        assert!(e.starts_with("/dev/no-such-port: "), "{e}");
        let e = open("tcp:127.0.0.1:1", 115_200, Duration::from_millis(20))
            .err()
            .unwrap();
        assert!(e.starts_with("tcp:127.0.0.1:1: "), "{e}");
    }
}
