//! QEMU's process and sockets: the machine started with the firmware, the side's straps on
//! its semihosting command line, UART4 (FC), USART2 (pod), LPUART1 (telemetry) and USART1
//! (the PPS test source) on Unix-socket chardevs and its GPIO trace in a file; two threads
//! per socket move the bytes between the socket and the host pipes of `bridge_fw::host`
//! (one, host to QEMU, for the PPS source).

use core::cell::RefCell;
use std::fs::File;
use std::io::{Read as _, Write as _};
use std::os::unix::net::UnixStream;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration as StdDuration, Instant as StdInstant};

use bridge_fw::host::{self, HostLinks, HostPipe};
use embassy_time::{Duration, with_timeout};

use crate::script::{FcUnderTest, drive};
use crate::{Check, Options, Outcome, Side};

/// Socket to pipe, until `stop` or the socket closes.
fn pump_in(sock: &UnixStream, pipe: &HostPipe, stop: &AtomicBool) {
    let mut sock = sock;
    let mut buf = [0u8; 256];
    while !stop.load(Ordering::Relaxed) {
        match sock.read(&mut buf) {
            Ok(0) => return,
            Ok(n) => {
                let mut rest = buf.get(..n).unwrap_or_default();
                while !rest.is_empty() && !stop.load(Ordering::Relaxed) {
                    match pipe.try_write(rest) {
                        Ok(k) => rest = rest.get(k..).unwrap_or_default(),
                        Err(_) => std::thread::sleep(StdDuration::from_millis(1)),
                    }
                }
            }
            Err(e)
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock
                        | std::io::ErrorKind::TimedOut
                        | std::io::ErrorKind::Interrupted
                ) => {}
            Err(_) => return,
        }
    }
}

/// Pipe to socket, until `stop` or the socket fails.
fn pump_out(sock: &UnixStream, pipe: &HostPipe, stop: &AtomicBool) {
    let mut sock = sock;
    let mut buf = [0u8; 256];
    while !stop.load(Ordering::Relaxed) {
        let read = host::block_on(with_timeout(
            Duration::from_millis(100),
            pipe.read(&mut buf),
        ));
        if let Ok(n) = read
            && sock.write_all(buf.get(..n).unwrap_or_default()).is_err()
        {
            return;
        }
    }
}

/// Sets the flag when dropped.
struct StopOnDrop<'a>(&'a AtomicBool);

impl Drop for StopOnDrop<'_> {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Relaxed);
    }
}

/// QEMU, killed when dropped.
pub(crate) struct Qemu(Child);

impl Qemu {
    pub(crate) fn running(&mut self) -> bool {
        matches!(self.0.try_wait(), Ok(None))
    }
}

impl Drop for Qemu {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn connect(path: &Path, qemu: &mut Qemu, deadline: StdInstant) -> Result<UnixStream, String> {
    loop {
        match UnixStream::connect(path) {
            Ok(s) => return Ok(s),
            Err(e) => {
                if !qemu.running() {
                    return Err(format!("QEMU ended before {} was up", path.display()));
                }
                if StdInstant::now() > deadline {
                    return Err(format!("{}: {e}", path.display()));
                }
                std::thread::sleep(StdDuration::from_millis(50));
            }
        }
    }
}

pub(crate) fn run_with<F: FcUnderTest>(side: Side, o: &Options) -> Outcome {
    let start = StdInstant::now();
    let qemu_out = o.work.join("qemu.out");
    let trace = o.work.join("trace.log");
    let mut outcome = Outcome {
        side,
        checks: Vec::new(),
        wall: StdDuration::ZERO,
        qemu_out: qemu_out.clone(),
        trace: trace.clone(),
    };
    let fail = |outcome: &mut Outcome, name: &'static str, detail: String| {
        outcome.checks.push(Check {
            name,
            ok: false,
            detail,
        });
        outcome.wall = start.elapsed();
    };
    if let Err(e) = std::fs::create_dir_all(&o.work) {
        fail(&mut outcome, "boots", format!("{}: {e}", o.work.display()));
        return outcome;
    }
    let (fc_sock, pod_sock) = (o.work.join("fc.sock"), o.work.join("pod.sock"));
    let tel_sock = o.work.join("telemetry.sock");
    let pps_sock = o.work.join("pps.sock");
    let _ = std::fs::remove_file(&pps_sock);
    let _ = std::fs::remove_file(&fc_sock);
    let _ = std::fs::remove_file(&pod_sock);
    let _ = std::fs::remove_file(&tel_sock);
    let _ = std::fs::remove_file(&trace);
    let out = match File::create(&qemu_out).and_then(|f| Ok((f.try_clone()?, f))) {
        Ok(f) => f,
        Err(e) => {
            fail(
                &mut outcome,
                "boots",
                format!("{}: {e}", qemu_out.display()),
            );
            return outcome;
        }
    };
    let chardev =
        |id: &str, p: &Path| format!("socket,id={id},path={},server=on,wait=off", p.display());
    // -serial maps in order to USART1 (the PPS test source), USART2 (pod), USART3, UART4
    // (FC), UART5 and LPUART1 (telemetry).
    let mut qemu_cmd = Command::new(&o.qemu);
    qemu_cmd
        .args([
            "-machine",
            "b-l475e-iot01a",
            "-nographic",
            "-monitor",
            "none",
        ])
        .arg("-semihosting-config")
        .arg(format!(
            "enable=on,target=native,arg=bridge-fw,arg=straps={}",
            side.straps()
        ))
        .arg("-chardev")
        .arg(chardev("pod", &pod_sock))
        .arg("-chardev")
        .arg(chardev("fc", &fc_sock));
    if side.pps() {
        qemu_cmd
            .arg("-chardev")
            .arg(chardev("pps", &pps_sock))
            .args(["-serial", "chardev:pps"]);
    } else {
        qemu_cmd.args(["-serial", "null"]);
    }
    qemu_cmd
        .args(["-serial", "chardev:pod"])
        .args(["-serial", "null", "-serial", "chardev:fc"]);
    if side.telemetry() {
        qemu_cmd
            .arg("-chardev")
            .arg(chardev("tel", &tel_sock))
            .args(["-serial", "null", "-serial", "chardev:tel"]);
    }
    let child = qemu_cmd
        .args(["-msg", "timestamp=on"])
        .args(["-trace", "enable=stm32l4x5_gpio_write", "-D"])
        .arg(&trace)
        // The bootloader at the reset vector; the firmware's image in the active slot, from
        // its Intel HEX file (the flash contents only: both ELFs also have segments for
        // their statics at the top of RAM, which QEMU refuses to load twice).
        .arg("-kernel")
        .arg(&o.bootloader)
        .arg("-device")
        .arg(format!("loader,file={}", o.image.display()))
        .stdin(Stdio::null())
        .stdout(out.0)
        .stderr(out.1)
        .spawn();
    let mut qemu = match child {
        Ok(c) => Qemu(c),
        Err(e) => {
            fail(&mut outcome, "boots", format!("{}: {e}", o.qemu.display()));
            return outcome;
        }
    };
    let deadline = start + o.timeout;
    let socks = connect(&pod_sock, &mut qemu, deadline)
        .and_then(|p| Ok((p, connect(&fc_sock, &mut qemu, deadline)?)));
    let (pod_stream, fc_stream) = match socks {
        Ok(s) => s,
        Err(e) => {
            fail(&mut outcome, "boots", e);
            return outcome;
        }
    };
    let tel_stream = if side.telemetry() {
        match connect(&tel_sock, &mut qemu, deadline) {
            Ok(s) => Some(s),
            Err(e) => {
                fail(&mut outcome, "boots", e);
                return outcome;
            }
        }
    } else {
        None
    };
    let pps_stream = if side.pps() {
        match connect(&pps_sock, &mut qemu, deadline) {
            Ok(s) => Some(s),
            Err(e) => {
                fail(&mut outcome, "boots", e);
                return outcome;
            }
        }
    } else {
        None
    };
    let pps_pipe = HostPipe::new();
    for s in [&pod_stream, &fc_stream]
        .into_iter()
        .chain(&tel_stream)
        .chain(&pps_stream)
    {
        let _ = s.set_read_timeout(Some(StdDuration::from_millis(100)));
    }

    let links = if side.telemetry() {
        HostLinks::with_telemetry()
    } else {
        HostLinks::new()
    };
    let stop = AtomicBool::new(false);
    let qemu = RefCell::new(qemu);
    let checks = std::thread::scope(|scope| {
        let (l, st) = (&links, &stop);
        let (fs, ps) = (&fc_stream, &pod_stream);
        scope.spawn(move || pump_in(fs, &l.fc_tx, st));
        scope.spawn(move || pump_out(fs, &l.fc_rx, st));
        scope.spawn(move || pump_in(ps, &l.pod_tx, st));
        scope.spawn(move || pump_out(ps, &l.pod_rx, st));
        if let (Some(ts), Some(t)) = (&tel_stream, &l.telemetry) {
            scope.spawn(move || pump_in(ts, &t.tx, st));
            scope.spawn(move || pump_out(ts, &t.rx, st));
        }
        let pps = pps_stream.as_ref().map(|ps| {
            let pipe = &pps_pipe;
            scope.spawn(move || pump_out(ps, pipe, st));
            pipe
        });
        // The pumps stop however `drive` ends (a panic too: the scope joins them).
        let _stop = StopOnDrop(st);
        drive::<F>(side, &links, pps, &qemu, &qemu_out, &trace, deadline)
    });
    outcome.checks = checks;
    outcome.wall = start.elapsed();
    outcome
}
