//! UDP ports, for companion computers (docs/src/deployment.md): `udp:HOST:PORT` sends to
//! HOST:PORT and `udp-listen:[HOST:]PORT` binds PORT; either takes datagrams from anyone
//! and answers the peer that spoke last, as mavlink-router's and MAVProxy's endpoints
//! expect (a router restarted on another source port is followed at its first datagram).
//!
//! The bridge says nothing on a link before it hears the autopilot there, and an endpoint
//! that listens (mavlink-router's `Mode = Server`, MAVProxy's and pymavlink's `udpin`)
//! sends nothing before it hears someone: so `udp:HOST:PORT` sends an empty datagram to
//! HOST:PORT every second until a datagram arrives. Nothing parses an empty datagram;
//! its source address is what those endpoints learn (they answer the last sender).
//!
//! A UDP port is a [`Conn`](super::port::Conn) like the others: the port's reader thread
//! reads datagrams as a byte stream (the bridge's deframers take what they carry), the
//! writer sends each write as one datagram. The bridge's link writer writes one whole
//! frame at a time, so a datagram carries whole frames (more than one only when the
//! sending thread fell behind). Until a peer is known (`udp-listen`, before its first
//! datagram) what the bridge writes is dropped, as on an unconnected UART.

use std::io;
use std::net::{SocketAddr, ToSocketAddrs, UdpSocket};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use serde_json::json;

use super::event_name::EventName;
use super::output::Output;

/// How often `udp:HOST:PORT` knocks until it hears someone.
const KNOCK_PERIOD: Duration = Duration::from_secs(1);

/// One UDP socket and the peer it answers.
pub struct Datagrams {
    socket: UdpSocket,
    peer: Arc<Mutex<Option<SocketAddr>>>,
    /// A datagram arrived (the knocking stops).
    heard: Arc<AtomicBool>,
    label: String,
    out: Output,
}

/// `HOST:PORT` (`[::1]:PORT` for IPv6) as socket addresses.
fn resolve(host: &str, port: u16) -> Result<Vec<SocketAddr>, String> {
    let host = host.trim_start_matches('[').trim_end_matches(']');
    (host, port)
        .to_socket_addrs()
        .map(Iterator::collect)
        .map_err(|e| format!("{host}:{port}: {e}"))
}

impl Datagrams {
    /// `udp:HOST:PORT`: a socket on a free local port of the peer's address family, whose
    /// first peer is HOST:PORT.
    ///
    /// # Errors
    /// HOST does not resolve, or no socket can be bound.
    pub fn connect(label: &str, host: &str, port: u16, out: &Output) -> Result<Self, String> {
        let to = resolve(host, port)?
            .into_iter()
            .next()
            .ok_or_else(|| format!("{host}:{port}: no address"))?;
        let local: SocketAddr = if to.is_ipv4() {
            ([0, 0, 0, 0], 0).into()
        } else {
            ([0u16; 8], 0).into()
        };
        let socket = UdpSocket::bind(local).map_err(|e| format!("{label} port: udp: {e}"))?;
        out.emit(
            EventName::PortOpened,
            json!({"port": label, "udp": socket.local_addr().map(|a| a.to_string()).ok(), "peer": to.to_string()}),
        );
        let d = Self::with(socket, Some(to), label, out);
        let knocker = d
            .socket
            .try_clone()
            .map_err(|e| format!("{label} port: udp: {e}"))?;
        let heard = d.heard.clone();
        std::thread::Builder::new()
            .name(format!("{label}-knock"))
            .spawn(move || {
                while !heard.load(Ordering::Relaxed) {
                    let _ = knocker.send_to(&[], to);
                    std::thread::sleep(KNOCK_PERIOD);
                }
            })
            .map_err(|e| format!("{label} port: cannot start a thread: {e}"))?;
        Ok(d)
    }

    /// `udp-listen:[HOST:]PORT`: a socket bound to HOST (all interfaces by default) and
    /// PORT (0: any free one, printed in the `port_listening` event); no peer yet.
    ///
    /// # Errors
    /// The address cannot be bound.
    pub fn listen(
        label: &str,
        host: Option<&str>,
        port: u16,
        out: &Output,
    ) -> Result<Self, String> {
        let host = host.unwrap_or("0.0.0.0");
        let bind = resolve(host, port)?;
        let socket = UdpSocket::bind(bind.as_slice())
            .map_err(|e| format!("{label} port: cannot listen on udp {host}:{port}: {e}"))?;
        let address = socket
            .local_addr()
            .map_or_else(|_| format!("{host}:{port}"), |a| a.to_string());
        out.emit(
            EventName::PortListening,
            json!({"port": label, "address": address, "udp": true}),
        );
        Ok(Self::with(socket, None, label, out))
    }

    fn with(socket: UdpSocket, peer: Option<SocketAddr>, label: &str, out: &Output) -> Self {
        Datagrams {
            socket,
            peer: Arc::new(Mutex::new(peer)),
            heard: Arc::new(AtomicBool::new(false)),
            label: label.to_owned(),
            out: out.clone(),
        }
    }

    /// The same socket and peer (for the port's other thread).
    ///
    /// # Errors
    /// The socket's.
    pub fn try_clone(&self) -> io::Result<Self> {
        Ok(Datagrams {
            socket: self.socket.try_clone()?,
            peer: self.peer.clone(),
            heard: self.heard.clone(),
            label: self.label.clone(),
            out: self.out.clone(),
        })
    }

    /// The peer answered now.
    #[must_use]
    pub fn peer(&self) -> Option<SocketAddr> {
        self.peer.lock().ok().and_then(|p| *p)
    }

    /// Non-blocking reads and writes.
    ///
    /// # Errors
    /// The socket's.
    pub fn set_nonblocking(&self, on: bool) -> io::Result<()> {
        self.socket.set_nonblocking(on)
    }
}

impl io::Read for Datagrams {
    /// The next non-empty datagram (cut to `buf`); its sender becomes the peer (a
    /// `port_peer` event when it changes).
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        loop {
            let (n, from) = self.socket.recv_from(buf)?;
            self.heard.store(true, Ordering::Relaxed);
            if n == 0 {
                continue;
            }
            let changed = self
                .peer
                .lock()
                .is_ok_and(|mut p| p.replace(from) != Some(from));
            if changed {
                self.out.emit(
                    EventName::PortPeer,
                    json!({"port": self.label, "peer": from.to_string()}),
                );
            }
            return Ok(n);
        }
    }
}

impl io::Write for Datagrams {
    /// `buf` as one datagram to the peer; dropped while there is none.
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match self.peer() {
            Some(to) => self.socket.send_to(buf, to),
            None => Ok(buf.len()),
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::{Read, Write};

    fn quiet() -> Output {
        Output::capture()
    }

    #[test]
    fn a_listener_answers_the_peer_that_spoke_last() {
        let mut port = Datagrams::listen("fc", Some("127.0.0.1"), 0, &quiet()).unwrap();
        let at = port.socket.local_addr().unwrap();
        // Nothing to answer yet: written bytes are dropped.
        assert_eq!(port.write(b"lost").unwrap(), 4);
        let a = UdpSocket::bind("127.0.0.1:0").unwrap();
        let b = UdpSocket::bind("127.0.0.1:0").unwrap();
        for s in [&a, &b] {
            s.set_read_timeout(Some(Duration::from_secs(2))).unwrap();
        }
        let mut buf = [0u8; 64];
        for (from, text) in [(&a, &b"one"[..]), (&b, b"two"), (&a, b"three")] {
            from.send_to(text, at).unwrap();
            let n = port.read(&mut buf).unwrap();
            assert_eq!(&buf[..n], text);
            assert_eq!(port.peer(), Some(from.local_addr().unwrap()));
            assert_eq!(port.write(b"reply").unwrap(), 5);
            let (n, src) = from.recv_from(&mut buf).unwrap();
            assert_eq!((&buf[..n], src), (&b"reply"[..], at));
        }
        // `b` got one reply only (the one after it spoke).
        b.set_read_timeout(Some(Duration::from_millis(100)))
            .unwrap();
        assert!(b.recv_from(&mut buf).is_err());
    }

    #[test]
    fn a_sender_starts_at_its_host_and_follows_who_answers() {
        let first = UdpSocket::bind("127.0.0.1:0").unwrap();
        let other = UdpSocket::bind("127.0.0.1:0").unwrap();
        for s in [&first, &other] {
            s.set_read_timeout(Some(Duration::from_secs(2))).unwrap();
        }
        let addr = first.local_addr().unwrap();
        let mut port = Datagrams::connect("telemetry", "127.0.0.1", addr.port(), &quiet()).unwrap();
        let mut reader = port.try_clone().unwrap();
        let mut buf = [0u8; 64];
        // The knock: an empty datagram, before the bridge says anything.
        let (n, me) = first.recv_from(&mut buf).unwrap();
        assert_eq!(n, 0);
        assert_eq!(port.write(b"hello").unwrap(), 5);
        let (n, from) = first.recv_from(&mut buf).unwrap();
        assert_eq!((&buf[..n], from), (&b"hello"[..], me));
        // A reply from another address (a router on a new source port) takes over.
        other.send_to(b"here", me).unwrap();
        let n = reader.read(&mut buf).unwrap();
        assert_eq!(&buf[..n], b"here");
        assert_eq!(port.write(b"again").unwrap(), 5);
        let (n, _) = other.recv_from(&mut buf).unwrap();
        assert_eq!(&buf[..n], b"again");
        // Heard: no more knocks (one may have left before the reply arrived).
        std::thread::sleep(KNOCK_PERIOD * 2);
        first
            .set_read_timeout(Some(Duration::from_millis(10)))
            .unwrap();
        while first.recv_from(&mut buf).is_ok() {}
        std::thread::sleep(KNOCK_PERIOD + KNOCK_PERIOD / 2);
        assert!(first.recv_from(&mut buf).is_err(), "still knocking");
    }

    #[test]
    fn bad_addresses_are_errors_naming_them() {
        let e = Datagrams::connect("fc", "no.such.host.invalid", 14550, &quiet())
            .err()
            .unwrap();
        assert!(e.starts_with("no.such.host.invalid:14550"), "{e}");
        let taken = UdpSocket::bind("127.0.0.1:0").unwrap();
        let port = taken.local_addr().unwrap().port();
        let e = Datagrams::listen("fc", Some("127.0.0.1"), port, &quiet())
            .err()
            .unwrap();
        assert!(
            e.contains(&format!("cannot listen on udp 127.0.0.1:{port}")),
            "{e}"
        );
    }
}
