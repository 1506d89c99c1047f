//! Ports: serial devices, TCP (connect or listen), UDP ([`super::udp`]) and the built-in
//! simulators, and the std threads that pump a real port into and out of the bridge's
//! pipes.
//!
//! | PORT | what |
//! | --- | --- |
//! | `/dev/ttyUSB0[:BAUD]`, `serial:PATH[:BAUD]` | a serial device, 8N1, no flow control; reopened with back-off when it fails |
//! | `tcp:HOST:PORT` | connect; reconnect with back-off (250 ms doubling to 5 s) when refused or lost |
//! | `tcp-listen:[HOST:]PORT` | listen (all interfaces by default); one connection at a time, the next one accepted when it closes; port 0: any free port |
//! | `udp:HOST:PORT` | send datagrams to HOST:PORT from a free local port; take them from anyone; answer the peer that spoke last |
//! | `udp-listen:[HOST:]PORT` | bind (all interfaces by default; port 0: any free one); answer the peer that spoke last (nothing is sent before one speaks) |
//! | `sim` | the built-in simulator (no thread: it runs on the bridge's executor) |
//!
//! A port has two threads: the reader (connects, accepts or reopens; moves what arrives
//! into the incoming pipe) and the writer (moves what the bridge writes to the current
//! connection; with none, the bytes are dropped, as on an unconnected UART, so the
//! bridge never stalls).
//!
//! A port can be a faulty cable ([`CableFaults`]: a seeded [`Faults`] model per
//! direction): arriving bytes go through it before anything sees them, bytes to send
//! after the trace has seen them, so a trace shows what the bridge sent and what it got.

use std::fmt;
use std::io::{self, Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream, ToSocketAddrs};
use std::str::FromStr;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use bridge_fw::host::{self, HostPipe};
use serde_json::{Value, json};

use super::event_name::EventName;
use super::output::Output;
use super::udp::Datagrams;
use crate::sim::faults::{FaultStage, FaultStats, Faults};

/// Where a link goes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PortSpec {
    /// A serial device.
    Serial {
        /// Its path.
        path: String,
        /// `:BAUD` (else the link's configured rate).
        baud: Option<u32>,
    },
    /// Connect to a TCP server.
    Tcp {
        /// Host name or address (`[::1]` for IPv6).
        host: String,
        /// TCP port.
        port: u16,
    },
    /// Accept connections.
    TcpListen {
        /// Address to bind (default: all interfaces).
        host: Option<String>,
        /// TCP port (0: any free one).
        port: u16,
    },
    /// UDP: send to HOST:PORT first, then to whoever spoke last.
    Udp {
        /// Host name or address.
        host: String,
        /// UDP port.
        port: u16,
    },
    /// UDP: bind, answer whoever spoke last.
    UdpListen {
        /// Address to bind (default: all interfaces).
        host: Option<String>,
        /// UDP port (0: any free one).
        port: u16,
    },
    /// The built-in simulator.
    Sim,
}

/// What a PORT may be, for error messages.
pub const PORT_SYNTAX: &str = "a serial device (/dev/ttyUSB0[:BAUD]), tcp:HOST:PORT, \
tcp-listen:[HOST:]PORT, udp:HOST:PORT, udp-listen:[HOST:]PORT or sim";

fn tcp_port(s: &str, whole: &str, zero_ok: bool) -> Result<u16, String> {
    match s.parse::<u16>() {
        Ok(p) if p > 0 || zero_ok => Ok(p),
        _ => Err(format!(
            "`{whole}`: `{s}` is not a port number ({}..=65535)",
            u8::from(!zero_ok)
        )),
    }
}

fn serial_spec(s: &str, whole: &str) -> Result<PortSpec, String> {
    let (path, baud) = match s.rsplit_once(':') {
        Some((p, b)) if !b.is_empty() && b.bytes().all(|c| c.is_ascii_digit()) => {
            let baud = b
                .parse::<u32>()
                .ok()
                .filter(|b| (1200..=4_000_000).contains(b))
                .ok_or_else(|| format!("`{whole}`: baud rate {b} is not in 1200..=4000000"))?;
            (p, Some(baud))
        }
        _ => (s, None),
    };
    if path.is_empty() {
        return Err(format!("`{whole}`: no device path"));
    }
    Ok(PortSpec::Serial {
        path: path.to_string(),
        baud,
    })
}

impl FromStr for PortSpec {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        if s == "sim" {
            return Ok(PortSpec::Sim);
        }
        for (listen, connect, udp) in [
            ("tcp-listen:", "tcp:", false),
            ("udp-listen:", "udp:", true),
        ] {
            if let Some(rest) = s.strip_prefix(listen) {
                let (host, port) = match rest.rsplit_once(':') {
                    Some((host, port)) if !host.is_empty() => (Some(host.to_string()), port),
                    Some(_) => return Err(format!("`{s}`: empty host")),
                    None => (None, rest),
                };
                let port = tcp_port(port, s, true)?;
                return Ok(if udp {
                    PortSpec::UdpListen { host, port }
                } else {
                    PortSpec::TcpListen { host, port }
                });
            }
            if let Some(rest) = s.strip_prefix(connect) {
                let Some((host, port)) = rest.rsplit_once(':').filter(|(h, _)| !h.is_empty())
                else {
                    return Err(format!("`{s}`: expected {connect}HOST:PORT"));
                };
                let (host, port) = (host.to_string(), tcp_port(port, s, false)?);
                return Ok(if udp {
                    PortSpec::Udp { host, port }
                } else {
                    PortSpec::Tcp { host, port }
                });
            }
        }
        if let Some(rest) = s.strip_prefix("serial:") {
            return serial_spec(rest, s);
        }
        if s.starts_with('/') {
            return serial_spec(s, s);
        }
        Err(format!("`{s}` is not a port: expected {PORT_SYNTAX}"))
    }
}

impl fmt::Display for PortSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PortSpec::Serial { path, baud: None } => write!(f, "{path}"),
            PortSpec::Serial {
                path,
                baud: Some(b),
            } => write!(f, "{path}:{b}"),
            PortSpec::Tcp { host, port } => write!(f, "tcp:{host}:{port}"),
            PortSpec::TcpListen { host: None, port } => write!(f, "tcp-listen:{port}"),
            PortSpec::TcpListen {
                host: Some(h),
                port,
            } => write!(f, "tcp-listen:{h}:{port}"),
            PortSpec::Udp { host, port } => write!(f, "udp:{host}:{port}"),
            PortSpec::UdpListen { host: None, port } => write!(f, "udp-listen:{port}"),
            PortSpec::UdpListen {
                host: Some(h),
                port,
            } => write!(f, "udp-listen:{h}:{port}"),
            PortSpec::Sim => f.write_str("sim"),
        }
    }
}

impl PortSpec {
    /// The `:BAUD` of a serial device.
    #[must_use]
    pub const fn baud(&self) -> Option<u32> {
        match self {
            PortSpec::Serial { baud, .. } => *baud,
            _ => None,
        }
    }

    /// True for `sim`.
    #[must_use]
    pub const fn is_sim(&self) -> bool {
        matches!(self, PortSpec::Sim)
    }
}

/// The line rate of a link: the port's `:BAUD`, else `option`, else 115200; both given
/// and different is an error.
///
/// # Errors
/// The two rates disagree.
pub fn link_baud(spec: &PortSpec, option: Option<u32>, what: &str) -> Result<u32, String> {
    Ok(port_baud(spec, option, what)?.unwrap_or(115_200))
}

/// The baud rate the command line gives a link: the port's `:BAUD` or the option (the
/// two must agree), or `None` when neither says.
///
/// # Errors
/// The port and the option name different rates.
pub fn port_baud(spec: &PortSpec, option: Option<u32>, what: &str) -> Result<Option<u32>, String> {
    match (spec.baud(), option) {
        (Some(a), Some(b)) if a != b => Err(format!(
            "{what}: the port says {a} baud and the option {b}: give one"
        )),
        (Some(a), _) => Ok(Some(a)),
        (None, b) => Ok(b),
    }
}

/// One connection: a TCP stream, a serial device or a UDP socket.
pub enum Conn {
    /// A TCP connection (client or accepted).
    Tcp(TcpStream),
    /// A serial device, opened raw at the configured baud rate.
    Serial(Box<serialport::TTYPort>),
    /// A UDP socket and the peer it answers.
    Udp(Datagrams),
}

impl Conn {
    fn try_clone(&self) -> io::Result<Conn> {
        match self {
            Conn::Tcp(s) => s.try_clone().map(Conn::Tcp),
            Conn::Udp(d) => d.try_clone().map(Conn::Udp),
            Conn::Serial(p) => p
                .try_clone_native()
                .map(|p| Conn::Serial(Box::new(p)))
                .map_err(io::Error::from),
        }
    }

    fn shutdown(&self) {
        if let Conn::Tcp(s) = self {
            let _ = s.shutdown(std::net::Shutdown::Both);
        }
    }

    /// TCP and UDP only: non-blocking reads and writes.
    ///
    /// # Errors
    /// The socket's.
    pub fn set_nonblocking(&self, on: bool) -> io::Result<()> {
        match self {
            Conn::Tcp(s) => s.set_nonblocking(on),
            Conn::Udp(d) => d.set_nonblocking(on),
            Conn::Serial(_) => Ok(()),
        }
    }
}

impl Read for Conn {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        match self {
            Conn::Tcp(s) => s.read(buf),
            Conn::Udp(d) => d.read(buf),
            Conn::Serial(p) => p.read(buf),
        }
    }
}

impl Write for Conn {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match self {
            Conn::Tcp(s) => s.write(buf),
            Conn::Udp(d) => d.write(buf),
            Conn::Serial(p) => p.write(buf),
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        match self {
            Conn::Tcp(s) => s.flush(),
            Conn::Udp(d) => d.flush(),
            Conn::Serial(p) => p.flush(),
        }
    }
}

/// Retry delays: 250 ms, doubling, at most 5 s.
#[derive(Debug, Clone, Copy)]
pub struct Backoff(Duration);

impl Backoff {
    const FIRST: Duration = Duration::from_millis(250);
    const MAX: Duration = Duration::from_secs(5);

    /// The first delay.
    #[must_use]
    pub const fn new() -> Self {
        Backoff(Self::FIRST)
    }

    /// The delay to wait now; the next one doubles.
    pub fn next_delay(&mut self) -> Duration {
        let d = self.0;
        self.0 = (self.0 * 2).min(Self::MAX);
        d
    }

    /// Back to the first delay (after a success).
    pub fn reset(&mut self) {
        self.0 = Self::FIRST;
    }
}

impl Default for Backoff {
    fn default() -> Self {
        Self::new()
    }
}

/// A serial open error, with what to do about it.
fn serial_error(path: &str, e: &serialport::Error) -> String {
    let hint = match e.kind() {
        serialport::ErrorKind::NoDevice => {
            " (no such device: is it plugged in? see `ls /dev/tty*`)"
        }
        serialport::ErrorKind::Io(io::ErrorKind::NotFound) => " (no such device)",
        serialport::ErrorKind::Io(io::ErrorKind::PermissionDenied) => {
            " (permission denied: add the user to the `dialout` group)"
        }
        _ => "",
    };
    format!("{path}: {e}{hint}")
}

/// A TCP connect error in words.
fn tcp_error(host: &str, port: u16, e: &io::Error) -> String {
    match e.kind() {
        io::ErrorKind::ConnectionRefused => {
            format!("{host}:{port}: connection refused (nothing listens there yet?)")
        }
        io::ErrorKind::TimedOut => format!("{host}:{port}: connection timed out"),
        _ => format!("{host}:{port}: {e}"),
    }
}

/// How a port gets its connections.
pub enum Connector {
    /// Open the device (again).
    Serial {
        /// The device path (e.g. `/dev/ttyUSB0`).
        path: String,
        /// Its baud rate (8N1).
        baud: u32,
    },
    /// Connect to a TCP server (and reconnect when it closes).
    Tcp {
        /// The server's host name or address.
        host: String,
        /// The server's TCP port.
        port: u16,
    },
    /// Wait for one TCP client at a time on this listener.
    Listen(TcpListener),
    /// A UDP socket: the same one for as long as the port runs.
    Udp(Datagrams),
}

fn open_serial(path: &str, baud: u32) -> Result<Conn, String> {
    serialport::new(path, baud)
        .data_bits(serialport::DataBits::Eight)
        .parity(serialport::Parity::None)
        .stop_bits(serialport::StopBits::One)
        .flow_control(serialport::FlowControl::None)
        .timeout(Duration::from_millis(50))
        .open_native()
        .map(|p| Conn::Serial(Box::new(p)))
        .map_err(|e| serial_error(path, &e))
}

fn connect_tcp(host: &str, port: u16) -> Result<(Conn, SocketAddr), String> {
    let addrs: Vec<SocketAddr> = (host.trim_start_matches('[').trim_end_matches(']'), port)
        .to_socket_addrs()
        .map_err(|e| format!("{host}:{port}: {e}"))?
        .collect();
    let mut last = format!("{host}:{port}: no address");
    for a in addrs {
        match TcpStream::connect_timeout(&a, Duration::from_secs(3)) {
            Ok(s) => {
                let _ = s.set_nodelay(true);
                return Ok((Conn::Tcp(s), a));
            }
            Err(e) => last = tcp_error(host, port, &e),
        }
    }
    Err(last)
}

impl Connector {
    /// Prepares `spec` for `label`: binds a listening socket, or opens a serial device
    /// once to find out now (not at the first retry) that it does not exist. Returns
    /// the connector and the connection already open (serial).
    ///
    /// # Errors
    /// The device cannot be opened, the address cannot be bound, or `spec` is `sim`.
    pub fn prepare(
        label: &str,
        spec: &PortSpec,
        baud: u32,
        out: &Output,
    ) -> Result<(Connector, Option<Conn>), String> {
        match spec {
            PortSpec::Serial { path, .. } => {
                let conn = open_serial(path, baud).map_err(|e| format!("{label} port {e}"))?;
                out.emit(
                    EventName::PortOpened,
                    json!({"port": label, "device": path, "baud": baud}),
                );
                Ok((
                    Connector::Serial {
                        path: path.clone(),
                        baud,
                    },
                    Some(conn),
                ))
            }
            PortSpec::Tcp { host, port } => Ok((
                Connector::Tcp {
                    host: host.clone(),
                    port: *port,
                },
                None,
            )),
            PortSpec::TcpListen { host, port } => {
                let host = host.as_deref().unwrap_or("0.0.0.0");
                let bind = (host.trim_start_matches('[').trim_end_matches(']'), *port);
                let listener = TcpListener::bind(bind).map_err(|e| {
                    format!("{label} port {spec}: cannot listen on {host}:{port}: {e}")
                })?;
                let address = listener
                    .local_addr()
                    .map_or_else(|_| format!("{host}:{port}"), |a| a.to_string());
                out.emit(
                    EventName::PortListening,
                    json!({"port": label, "address": address}),
                );
                Ok((Connector::Listen(listener), None))
            }
            PortSpec::Udp { host, port } => {
                let d = Datagrams::connect(label, host, *port, out)
                    .map_err(|e| format!("{label} port {spec}: {e}"))?;
                Ok((Connector::Udp(d), None))
            }
            PortSpec::UdpListen { host, port } => {
                let d = Datagrams::listen(label, host.as_deref(), *port, out)?;
                Ok((Connector::Udp(d), None))
            }
            PortSpec::Sim => Err(format!("{label} port: `sim` has no connection")),
        }
    }

    /// Blocks until there is a connection, retrying with back-off (each failure is a
    /// `port_error` event).
    pub fn connect(&self, label: &str, out: &Output, backoff: &mut Backoff) -> Conn {
        loop {
            let result = match self {
                Connector::Serial { path, baud } => open_serial(path, *baud).inspect(|_| {
                    out.emit(
                        EventName::PortOpened,
                        json!({"port": label, "device": path, "baud": baud}),
                    );
                }),
                Connector::Tcp { host, port } => connect_tcp(host, *port).map(|(c, a)| {
                    out.emit(
                        EventName::PortConnected,
                        json!({"port": label, "peer": a.to_string()}),
                    );
                    c
                }),
                Connector::Listen(l) => l
                    .accept()
                    .map(|(s, a)| {
                        let _ = s.set_nodelay(true);
                        out.emit(
                            EventName::PortConnected,
                            json!({"port": label, "peer": a.to_string()}),
                        );
                        Conn::Tcp(s)
                    })
                    .map_err(|e| format!("accept: {e}")),
                Connector::Udp(d) => d.try_clone().map(Conn::Udp).map_err(|e| e.to_string()),
            };
            match result {
                Ok(c) => {
                    backoff.reset();
                    return c;
                }
                Err(e) => {
                    let wait = backoff.next_delay();
                    out.emit(
                        EventName::PortError,
                        json!({"port": label, "error": e, "retry_ms": wait.as_millis()}),
                    );
                    std::thread::sleep(wait);
                }
            }
        }
    }
}

/// The current connection's writing half, shared by the threads of a port.
pub type SharedWriter = Arc<Mutex<Option<Conn>>>;

/// Bytes seen on a port (for `--trace`).
pub type Tap = Arc<dyn Fn(&[u8]) + Send + Sync>;

/// One direction of a faulty cable, shared by a port's thread and whoever reports.
pub type SharedStage = Arc<Mutex<FaultStage>>;

/// A faulty cable at a port: one fault stage per direction, each seeded from the
/// model's seed ([`Faults::derived`]: 0 arriving, 1 sent).
#[derive(Clone)]
pub struct CableFaults {
    /// Bytes arriving at the port.
    pub incoming: SharedStage,
    /// Bytes sent from the port.
    pub outgoing: SharedStage,
}

impl CableFaults {
    /// Both directions of `faults`.
    #[must_use]
    pub fn new(faults: Faults) -> Self {
        CableFaults {
            incoming: Arc::new(Mutex::new(faults.derived(0).stage())),
            outgoing: Arc::new(Mutex::new(faults.derived(1).stage())),
        }
    }

    /// What each direction did, as JSON (`{"in": {...}, "out": {...}}`).
    #[must_use]
    pub fn stats_json(&self) -> Value {
        let get = |s: &SharedStage| s.lock().map(|s| s.stats()).unwrap_or_default();
        json!({"in": stats_json(&get(&self.incoming)), "out": stats_json(&get(&self.outgoing))})
    }
}

/// What a fault stage did, as JSON.
#[must_use]
pub fn stats_json(s: &FaultStats) -> Value {
    json!({
        "bytes_in": s.bytes_in, "bytes_out": s.bytes_out, "bits_flipped": s.bits_flipped,
        "bytes_corrupted": s.bytes_corrupted, "bytes_dropped": s.bytes_dropped,
        "garbage_bytes": s.garbage_bytes,
    })
}

/// `bytes` through `stage` (unchanged without one).
fn through(stage: Option<&SharedStage>, bytes: &[u8]) -> Vec<u8> {
    match stage.and_then(|s| s.lock().ok()) {
        Some(mut s) => s.apply(bytes),
        None => bytes.to_vec(),
    }
}

/// A real port and what to do with its bytes.
pub struct Pump {
    /// Its name in events: `fc`, `pod`, `telemetry`, `rtc_io`.
    pub label: &'static str,
    /// Where the port is (as given on the command line).
    pub spec: PortSpec,
    /// Line rate (serial devices).
    pub baud: u32,
    /// Where the port's status events go.
    pub out: Output,
    /// Where arriving bytes go (`None`: dropped).
    pub incoming: Option<&'static HostPipe>,
    /// What to send (`None`: nothing; write to [`PortHandle::writer`] directly).
    pub outgoing: Option<&'static HostPipe>,
    /// Sees arriving bytes.
    pub tap_in: Option<Tap>,
    /// Sees bytes sent.
    pub tap_out: Option<Tap>,
    /// A faulty cable (`None`: a good one).
    pub faults: Option<CableFaults>,
}

/// A running port.
pub struct PortHandle {
    /// The current connection's writing half (`None` while there is none).
    pub writer: SharedWriter,
}

/// Starts the threads of a real port. Fails at once when a serial device cannot be
/// opened or a listening address cannot be bound; a TCP peer that is not there yet,
/// or one that goes away later, is retried with back-off.
///
/// # Errors
/// As above, with a message naming the port.
pub fn start(p: Pump) -> Result<PortHandle, String> {
    let (connector, first) = Connector::prepare(p.label, &p.spec, p.baud, &p.out)?;
    let writer: SharedWriter = Arc::new(Mutex::new(None));
    let serial = matches!(connector, Connector::Serial { .. });
    {
        let writer = writer.clone();
        let out = p.out.clone();
        let label = p.label;
        let (incoming, tap_in) = (p.incoming, p.tap_in);
        let faults_in = p.faults.as_ref().map(|f| f.incoming.clone());
        std::thread::Builder::new()
            .name(format!("{label}-rx"))
            .spawn(move || {
                let mut first = first;
                let mut backoff = Backoff::new();
                let mut buf = [0u8; 512];
                loop {
                    let mut conn = match first.take() {
                        Some(c) => c,
                        None => connector.connect(label, &out, &mut backoff),
                    };
                    match conn.try_clone() {
                        Ok(w) => {
                            if let Ok(mut g) = writer.lock() {
                                *g = Some(w);
                            }
                        }
                        Err(e) => {
                            out.emit(
                                EventName::PortClosed,
                                json!({"port": label, "reason": e.to_string()}),
                            );
                            std::thread::sleep(backoff.next_delay());
                            continue;
                        }
                    }
                    let reason = loop {
                        match conn.read(&mut buf) {
                            Ok(0) if !serial => break "closed by the peer".to_string(),
                            Ok(0) => {}
                            Ok(n) => {
                                let bytes =
                                    through(faults_in.as_ref(), buf.get(..n).unwrap_or_default());
                                if let Some(t) = &tap_in {
                                    t(&bytes);
                                }
                                if let Some(pipe) = incoming {
                                    host::block_on(pipe.write_all(&bytes));
                                }
                            }
                            Err(e) if is_transient(&e) => {}
                            Err(e) => break e.to_string(),
                        }
                    };
                    if let Ok(mut g) = writer.lock() {
                        *g = None;
                    }
                    conn.shutdown();
                    out.emit(
                        EventName::PortClosed,
                        json!({"port": label, "reason": reason}),
                    );
                    if serial {
                        std::thread::sleep(backoff.next_delay());
                    }
                }
            })
            .map_err(|e| format!("{} port: cannot start a thread: {e}", p.label))?;
    }
    if let Some(outgoing) = p.outgoing {
        let writer = writer.clone();
        let tap_out = p.tap_out;
        let faults_out = p.faults.as_ref().map(|f| f.outgoing.clone());
        std::thread::Builder::new()
            .name(format!("{}-tx", p.label))
            .spawn(move || {
                let mut buf = [0u8; 512];
                loop {
                    let n = host::block_on(outgoing.read(&mut buf));
                    let bytes = buf.get(..n).unwrap_or_default();
                    if let Some(t) = &tap_out {
                        t(bytes);
                    }
                    let bytes = through(faults_out.as_ref(), bytes);
                    if let Ok(mut g) = writer.lock()
                        && let Some(w) = g.as_mut()
                        && write_patiently(w, &bytes).is_err()
                    {
                        // The reader sees the end of the connection and reports it.
                        w.shutdown();
                        *g = None;
                    }
                }
            })
            .map_err(|e| format!("{} port: cannot start a thread: {e}", p.label))?;
    }
    Ok(PortHandle { writer })
}

/// Writes all of `bytes`; a serial device that does not take them within its time-out
/// is given up to a second.
/// A read or write that may simply be tried again (a time-out, no data yet, a signal).
fn is_transient(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock | io::ErrorKind::Interrupted
    )
}

fn write_patiently(w: &mut Conn, mut bytes: &[u8]) -> io::Result<()> {
    let mut stalls = 0;
    while !bytes.is_empty() {
        match w.write(bytes) {
            Ok(0) => return Err(io::ErrorKind::WriteZero.into()),
            Ok(n) => bytes = bytes.get(n..).unwrap_or_default(),
            Err(e) if is_transient(&e) => {
                stalls += 1;
                if stalls > 20 {
                    return Err(e);
                }
            }
            Err(e) => return Err(e),
        }
    }
    w.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A host pipe that lives as long as the pump threads.
    fn pipe() -> &'static HostPipe {
        Box::leak(Box::new(HostPipe::new()))
    }

    /// Starts a pump with no taps, `label` on `spec` (panics when it cannot).
    fn start_pump(
        label: &'static str,
        spec: &str,
        baud: u32,
        out: &Output,
        pipes: (Option<&'static HostPipe>, Option<&'static HostPipe>),
        faults: Option<CableFaults>,
    ) -> PortHandle {
        start(Pump {
            label,
            spec: spec.parse().unwrap(),
            baud,
            out: out.clone(),
            incoming: pipes.0,
            outgoing: pipes.1,
            tap_in: None,
            tap_out: None,
            faults,
        })
        .unwrap()
    }

    /// Waits (up to `tries` times `step_ms`) until at least `count` events named `name`
    /// were output, and returns those there are.
    fn wait_for_events(
        out: &Output,
        name: &str,
        count: usize,
        tries: u32,
        step_ms: u64,
    ) -> Vec<serde_json::Map<String, serde_json::Value>> {
        let mut found = Vec::new();
        for _ in 0..tries {
            found = out
                .captured()
                .into_iter()
                .filter(|e| e["event"] == name)
                .collect();
            if found.len() >= count {
                break;
            }
            std::thread::sleep(Duration::from_millis(step_ms));
        }
        found
    }

    /// Reads exactly `buf.len()` bytes from a pipe.
    fn read_all(pipe: &HostPipe, buf: &mut [u8]) {
        let mut n = 0;
        while n < buf.len() {
            n += host::block_on(pipe.read(&mut buf[n..]));
        }
    }

    #[test]
    fn port_specs() {
        let p = |s: &str| s.parse::<PortSpec>();
        assert_eq!(p("sim"), Ok(PortSpec::Sim));
        assert_eq!(
            p("/dev/ttyUSB0"),
            Ok(PortSpec::Serial {
                path: "/dev/ttyUSB0".into(),
                baud: None
            })
        );
        assert_eq!(
            p("/dev/ttyAMA0:921600"),
            Ok(PortSpec::Serial {
                path: "/dev/ttyAMA0".into(),
                baud: Some(921_600)
            })
        );
        assert_eq!(
            p("serial:COM3:57600"),
            Ok(PortSpec::Serial {
                path: "COM3".into(),
                baud: Some(57_600)
            })
        );
        // A by-path name with colons and no baud rate.
        assert_eq!(
            p("/dev/serial/by-path/pci-0000:00:14.0-usb-0:2:1.0-port0"),
            Ok(PortSpec::Serial {
                path: "/dev/serial/by-path/pci-0000:00:14.0-usb-0:2:1.0-port0".into(),
                baud: None
            })
        );
        assert_eq!(
            p("tcp:127.0.0.1:5760"),
            Ok(PortSpec::Tcp {
                host: "127.0.0.1".into(),
                port: 5760
            })
        );
        assert_eq!(
            p("tcp:[::1]:5760"),
            Ok(PortSpec::Tcp {
                host: "[::1]".into(),
                port: 5760
            })
        );
        assert_eq!(
            p("tcp-listen:4441"),
            Ok(PortSpec::TcpListen {
                host: None,
                port: 4441
            })
        );
        assert_eq!(
            p("tcp-listen:127.0.0.1:0"),
            Ok(PortSpec::TcpListen {
                host: Some("127.0.0.1".into()),
                port: 0
            })
        );
        for bad in [
            "",
            "ttyUSB0",
            "tcp:",
            "tcp:host",
            "tcp:host:0",
            "tcp:host:65536",
            "tcp::80",
            "tcp-listen:x",
            "tcp-listen::80",
            "/dev/ttyS0:300",
            "/dev/ttyS0:99999999",
            "serial:",
            "udp:",
            "udp:host",
            "udp:host:0",
            "udp-listen::80",
            "udp-listen:x",
        ] {
            let e = p(bad).expect_err(bad);
            assert!(e.contains(&format!("`{bad}`")), "{bad}: {e}");
        }
        for s in [
            "sim",
            "/dev/ttyUSB0",
            "/dev/ttyAMA0:921600",
            "tcp:h:1",
            "tcp-listen:2",
            "tcp-listen:[::1]:3",
            "udp:127.0.0.1:14550",
            "udp-listen:14550",
            "udp-listen:127.0.0.1:0",
        ] {
            assert_eq!(p(s).unwrap().to_string(), s);
        }
    }

    #[test]
    fn baud_rates() {
        let serial = PortSpec::Serial {
            path: "/dev/x".into(),
            baud: Some(57_600),
        };
        assert_eq!(link_baud(&serial, None, "fc"), Ok(57_600));
        assert_eq!(link_baud(&serial, Some(57_600), "fc"), Ok(57_600));
        assert!(link_baud(&serial, Some(9600), "fc").is_err());
        assert_eq!(link_baud(&PortSpec::Sim, Some(9600), "fc"), Ok(9600));
        assert_eq!(link_baud(&PortSpec::Sim, None, "fc"), Ok(115_200));
    }

    #[test]
    fn backoff_doubles_to_five_seconds() {
        let mut b = Backoff::new();
        let ms: Vec<u128> = (0..7).map(|_| b.next_delay().as_millis()).collect();
        assert_eq!(ms, [250, 500, 1000, 2000, 4000, 5000, 5000]);
        b.reset();
        assert_eq!(b.next_delay().as_millis(), 250);
    }

    #[test]
    fn a_missing_device_is_a_clear_error() {
        let out = Output::capture();
        let spec: PortSpec = "/dev/no-such-tty-for-gimbal".parse().unwrap();
        let Err(e) = Connector::prepare("fc", &spec, 115_200, &out) else {
            panic!("opened a missing device");
        };
        assert!(e.starts_with("fc port /dev/no-such-tty-for-gimbal:"), "{e}");
        assert!(
            e.contains("no such device") || e.contains("No such file"),
            "{e}"
        );
    }

    #[test]
    fn tcp_ports_pump_both_ways_and_accept_again() {
        let out = Output::capture();
        let (incoming, outgoing) = (pipe(), pipe());
        let pipes = (Some(incoming), Some(outgoing));
        start_pump("fc", "tcp-listen:127.0.0.1:0", 115_200, &out, pipes, None);
        let listening = out.captured();
        assert_eq!(listening[0]["event"], "port_listening");
        let address = listening[0]["address"].as_str().unwrap().to_string();
        for round in 0..2u8 {
            let mut client = TcpStream::connect(&address).unwrap();
            client.write_all(&[round, 1, 2]).unwrap();
            let mut got = [0u8; 3];
            read_all(incoming, &mut got);
            assert_eq!(got, [round, 1, 2]);
            // The writer needs the connection registered: wait for it.
            let round_events = usize::from(round) + 1;
            wait_for_events(&out, "port_connected", round_events, 200, 5);
            host::block_on(outgoing.write_all(&[9, round]));
            let mut back = [0u8; 2];
            client
                .set_read_timeout(Some(Duration::from_secs(10)))
                .unwrap();
            client.read_exact(&mut back).unwrap();
            assert_eq!(back, [9, round]);
            drop(client);
            // The close is seen before the next connection is accepted.
            wait_for_events(&out, "port_closed", round_events, 400, 5);
        }
        let events: Vec<String> = out
            .captured()
            .iter()
            .map(|e| e["event"].as_str().unwrap().to_string())
            .collect();
        assert_eq!(
            events,
            [
                "port_listening",
                "port_connected",
                "port_closed",
                "port_connected",
                "port_closed"
            ]
        );
    }

    #[test]
    fn a_faulty_cable_changes_the_bytes_both_ways() {
        // Every bit flipped: what arrives and what leaves is inverted.
        let out = Output::capture();
        let (incoming, outgoing) = (pipe(), pipe());
        let cable = CableFaults::new(Faults::bit_errors(1.0, 9));
        let (pipes, faults) = ((Some(incoming), Some(outgoing)), Some(cable.clone()));
        start_pump(
            "pod",
            "tcp-listen:127.0.0.1:0",
            115_200,
            &out,
            pipes,
            faults,
        );
        let address = out.captured()[0]["address"].as_str().unwrap().to_string();
        let mut client = TcpStream::connect(&address).unwrap();
        client.write_all(&[0x00, 0x0F]).unwrap();
        let mut got = [0u8; 2];
        read_all(incoming, &mut got);
        assert_eq!(got, [0xFF, 0xF0]);
        wait_for_events(&out, "port_connected", 1, 200, 5);
        host::block_on(outgoing.write_all(&[0xAA]));
        client
            .set_read_timeout(Some(Duration::from_secs(10)))
            .unwrap();
        let mut back = [0u8; 1];
        client.read_exact(&mut back).unwrap();
        assert_eq!(back, [0x55]);
        let stats = cable.stats_json();
        assert_eq!(stats["in"]["bits_flipped"], 16);
        assert_eq!(stats["out"]["bits_flipped"], 8);
        assert_eq!(stats["out"]["bytes_in"], 1);
    }

    #[test]
    fn a_serial_device_is_pumped_both_ways() {
        use serialport::SerialPort;
        // A pseudo-terminal: the test holds the master end, the pump opens the other
        // end by its path, as it would /dev/ttyUSB0.
        let (mut master, slave) = serialport::TTYPort::pair().expect("a pty");
        let path = slave.name().expect("the pty's path");
        drop(slave);
        let out = Output::capture();
        let (incoming, outgoing) = (pipe(), pipe());
        let pipes = (Some(incoming), Some(outgoing));
        start_pump("pod", &format!("{path}:57600"), 57_600, &out, pipes, None);
        let opened = out.captured();
        assert_eq!(opened[0]["event"], "port_opened");
        assert_eq!(opened[0]["device"], path.as_str());
        assert_eq!(opened[0]["baud"], 57_600);
        let frame = [0xfd, 0x03, 0x04, 0x01, 0x07, 0x00, 0x0a, 0x0d];
        master.write_all(&frame).unwrap();
        let mut got = [0u8; 8];
        read_all(incoming, &mut got);
        assert_eq!(
            got, frame,
            "bytes arrive unchanged (raw mode: no CR/LF mapping)"
        );
        host::block_on(outgoing.write_all(&[0x0a, 0x0d, 0x55]));
        master.set_timeout(Duration::from_secs(10)).unwrap();
        let mut back = [0u8; 3];
        master.read_exact(&mut back).unwrap();
        assert_eq!(back, [0x0a, 0x0d, 0x55]);
    }

    #[test]
    fn a_refused_connection_is_retried_with_backoff() {
        // A port that was free a moment ago: nothing listens there.
        let port = TcpListener::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let out = Output::capture();
        let incoming = pipe();
        let spec = format!("tcp:127.0.0.1:{port}");
        start_pump("pod", &spec, 115_200, &out, (Some(incoming), None), None);
        let errors = wait_for_events(&out, "port_error", 2, 400, 10);
        assert!(errors.len() >= 2, "{errors:?}");
        assert_eq!(errors[0]["port"], "pod");
        assert!(
            errors[0]["error"]
                .as_str()
                .unwrap()
                .contains("connection refused"),
            "{:?}",
            errors[0]
        );
        assert_eq!(errors[0]["retry_ms"], 250);
        assert_eq!(errors[1]["retry_ms"], 500);
        // Now something listens: the next retry connects.
        let listener = TcpListener::bind(("127.0.0.1", port)).unwrap();
        let (mut s, _) = listener.accept().unwrap();
        s.write_all(b"hi").unwrap();
        let mut got = [0u8; 2];
        read_all(incoming, &mut got);
        assert_eq!(&got, b"hi");
    }
}
