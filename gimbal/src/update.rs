//! `gimbal update`, `gimbal sign` and `gimbal update-key`: a signed image to a board over
//! its update port, with the protocol of `bridge_update` (the sans-IO client does the
//! protocol; this moves its bytes, times out, reconnects and shows the progress).

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use bridge_update::client::{Client, Progress};
use bridge_update::keys;
use bridge_update::wire::{BootState, MAX_FRAME, Request, Response, UpdateFraming};
use indicatif::{ProgressBar, ProgressStyle};
use protocol_core::wire::{Deframer, Event};

use crate::client_port::{self, ReadWrite};

/// How long a request waits for its answer before it is sent again (a 1 KiB chunk takes
/// 90 ms at 115200 baud, its flash write some 25 ms more).
const ANSWER_TIMEOUT: Duration = Duration::from_secs(1);
/// Requests sent again before the link counts as lost (then the port is opened again and
/// the board asked where to resume).
const TRIES: u32 = 4;

/// What `gimbal update` was asked.
#[derive(Debug, Clone)]
pub struct UpdateOptions {
    /// The serial device (or any path a serial port opens).
    pub port: String,
    /// Its baud rate.
    pub baud: u32,
    /// The image (`.bin`).
    pub image: PathBuf,
    /// Its signature file (default: `IMAGE.sig`).
    pub sig: Option<PathBuf>,
    /// How long to wait for the board to come back after the reset (the swap of the whole
    /// slot takes some 20 s on the board).
    pub wait: Duration,
    /// Give up after this long without progress.
    pub give_up: Duration,
}

/// The signature file of an image: `IMAGE.sig`.
#[must_use]
pub fn sig_path(image: &Path) -> PathBuf {
    let mut name = image.as_os_str().to_owned();
    name.push(".sig");
    PathBuf::from(name)
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// One open link to the board: frames out, frames in.
struct Link {
    port: Box<dyn ReadWrite>,
    deframer: Deframer<UpdateFraming, MAX_FRAME>,
}

impl Link {
    fn open(opts: &UpdateOptions) -> Result<Self, String> {
        let port = client_port::open(&opts.port, opts.baud, Duration::from_millis(50))?;
        Ok(Link {
            port,
            deframer: Deframer::new(UpdateFraming),
        })
    }

    fn send(&mut self, request: &Request<'_>) -> Result<(), String> {
        let mut buf = [0u8; MAX_FRAME];
        let n = request.emit(&mut buf).map_err(|e| format!("{e}"))?;
        self.port
            .write_all(&buf[..n])
            .map_err(|e| format!("write: {e}"))?;
        self.port.flush().map_err(|e| format!("write: {e}"))
    }

    /// The next frame from the board, or `None` after `timeout`.
    fn receive(&mut self, timeout: Duration) -> Result<Option<Vec<u8>>, String> {
        let until = Instant::now() + timeout;
        loop {
            if let Some(Event::Frame(f)) = self.deframer.poll() {
                return Ok(Some(f.to_vec()));
            }
            if Instant::now() >= until {
                return Ok(None);
            }
            let mut buf = [0u8; 256];
            match self.port.read(&mut buf) {
                Ok(0) => return Err("read: the port closed".into()),
                Ok(n) => {
                    let mut input = &buf[..n];
                    while !input.is_empty() {
                        let taken = self.deframer.feed(input);
                        input = &input[taken..];
                        if taken == 0 {
                            // Full of a candidate: let poll drain it.
                            if let Some(Event::Frame(f)) = self.deframer.poll() {
                                return Ok(Some(f.to_vec()));
                            }
                        }
                    }
                }
                Err(e) if client_port::timed_out(&e) => {}
                Err(e) => return Err(format!("read: {e}")),
            }
        }
    }

    /// Sends `request` until an answer comes (at most [`TRIES`] times).
    fn ask(&mut self, request: &Request<'_>) -> Result<Option<Vec<u8>>, String> {
        for _ in 0..TRIES {
            self.send(request)?;
            if let Some(frame) = self.receive(ANSWER_TIMEOUT)? {
                return Ok(Some(frame));
            }
        }
        Ok(None)
    }
}

/// A line on stderr above the progress bar (also when the bar is hidden: not a terminal).
fn say(bar: &ProgressBar, line: impl AsRef<str>) {
    bar.suspend(|| eprintln!("{}", line.as_ref()));
}

/// What the board said at the end.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Outcome {
    /// The version it runs now.
    pub version: String,
    /// Its image's state.
    pub state: BootState,
}

/// Sends a signed image and reports the version that runs afterwards.
///
/// # Errors
/// A message that says what went wrong (the board's refusal, a missing signature, a port
/// that cannot be opened, a board that does not come back).
pub fn update(opts: &UpdateOptions, out: &mut impl Write) -> Result<Outcome, String> {
    let image = std::fs::read(&opts.image).map_err(|e| format!("{}: {e}", opts.image.display()))?;
    let sig_file = opts.sig.clone().unwrap_or_else(|| sig_path(&opts.image));
    let sig_bytes = std::fs::read(&sig_file).map_err(|e| {
        format!(
            "{}: {e} (sign the image with `gimbal sign --key KEY {}`, or use the release folder's)",
            sig_file.display(),
            opts.image.display()
        )
    })?;
    let (signature, signer) =
        keys::parse_sig(&sig_bytes).map_err(|e| format!("{}: {e}", sig_file.display()))?;
    if !keys::verify(&signer, &image, &signature) {
        return Err(format!(
            "{}: not a signature of {} (another image's?)",
            sig_file.display(),
            opts.image.display()
        ));
    }
    let mut client = Client::new(&image, signature).map_err(|e| e.to_string())?;
    let mut link = Link::open(opts)?;
    let bar = ProgressBar::new(image.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {bytes}/{total_bytes} {bytes_per_sec} ETA {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut last_progress = Instant::now();
    while let Some(request) = client.request() {
        let Some(frame) = link.ask(&request)? else {
            if last_progress.elapsed() > opts.give_up {
                bar.abandon();
                return Err(format!(
                    "no answer from the board on {} for {:?}",
                    opts.port, opts.give_up
                ));
            }
            // The link is lost: open the port again and ask where to resume.
            say(&bar, "no answer: opening the port again to resume");
            std::thread::sleep(Duration::from_millis(500));
            if let Ok(l) = Link::open(opts) {
                link = l;
            }
            client.reconnect();
            continue;
        };
        let Ok(response) = Response::parse(&frame) else {
            continue;
        };
        match client.response(&response) {
            Ok(Progress::Board {
                version,
                state,
                key_id,
                dev_key,
            }) => {
                let ours = bridge_update::key_id(&signer);
                if key_id != ours {
                    bar.abandon();
                    return Err(format!(
                        "the board accepts images signed by key {} and this image is signed by key {}: it would refuse it",
                        hex(&key_id),
                        hex(&ours)
                    ));
                }
                say(
                    &bar,
                    format!(
                        "board: {version} ({state:?}); its key {}{}",
                        hex(&key_id),
                        if dev_key {
                            " (the DEVELOPMENT key)"
                        } else {
                            ""
                        }
                    ),
                );
            }
            Ok(Progress::Resumed(at)) => {
                if at > 0 {
                    say(&bar, format!("resuming at byte {at}"));
                }
                bar.set_position(u64::from(at));
                last_progress = Instant::now();
            }
            Ok(Progress::Sent(n)) => {
                bar.set_position(u64::from(n));
                last_progress = Instant::now();
            }
            Ok(Progress::Verified) => bar.finish(),
            Ok(Progress::Nothing) => {}
            Err(e) => {
                bar.abandon();
                return Err(e.to_string());
            }
        }
    }
    writeln!(
        out,
        "signature verified by the board; resetting it to swap the image in"
    )
    .map_err(|e| e.to_string())?;
    // The reset: the board answers, then resets.
    let _ = link.ask(&Request::Reboot)?;
    drop(link);
    let until = Instant::now() + opts.wait;
    loop {
        std::thread::sleep(Duration::from_millis(500));
        if let Ok(mut l) = Link::open(opts)
            && let Some(frame) = l.ask(&Request::Hello)?
            && let Ok(Response::Info(info)) = Response::parse(&frame)
        {
            let outcome = Outcome {
                version: info.version.to_string(),
                state: info.state,
            };
            return match info.state {
                BootState::Trial => {
                    writeln!(
                        out,
                        "now running: {} (on trial: it confirms itself when its FC and pod links are up, or after {} s; a reset before that swaps the previous image back)",
                        info.version,
                        bridge_update::CONFIRM_AFTER_S
                    )
                    .map_err(|e| e.to_string())?;
                    Ok(outcome)
                }
                BootState::RolledBack => Err(format!(
                    "the new image did not confirm itself and was rolled back: {} runs",
                    info.version
                )),
                _ => {
                    writeln!(out, "now running: {} ({:?})", info.version, info.state)
                        .map_err(|e| e.to_string())?;
                    Ok(outcome)
                }
            };
        }
        if Instant::now() >= until {
            return Err(format!(
                "the board did not answer within {:?} of its reset",
                opts.wait
            ));
        }
    }
}

/// `gimbal sign`: writes `IMAGE.sig` with the key (the development key without one).
///
/// # Errors
/// The key or the image cannot be read, or the signature written.
pub fn sign(key: Option<&Path>, image: &Path, out: &mut impl Write) -> Result<PathBuf, String> {
    let (key, dev) = match key {
        Some(k) => (keys::read_signing_key(k)?, false),
        None => {
            let (k, made) = keys::dev_key()?;
            if made {
                writeln!(
                    out,
                    "made the DEVELOPMENT key {}",
                    keys::dev_key_path().display()
                )
                .map_err(|e| e.to_string())?;
            }
            (k, true)
        }
    };
    let bytes = std::fs::read(image).map_err(|e| format!("{}: {e}", image.display()))?;
    let path = sig_path(image);
    std::fs::write(&path, keys::sign(&key, &bytes))
        .map_err(|e| format!("{}: {e}", path.display()))?;
    writeln!(
        out,
        "signed {} with key {}{}",
        image.display(),
        hex(&bridge_update::key_id(key.verifying_key().as_bytes())),
        if dev { " (the DEVELOPMENT key)" } else { "" }
    )
    .map_err(|e| e.to_string())?;
    Ok(path)
}

/// `gimbal update-key PATH`: a new key pair (PATH and PATH's `.pub.pem`).
///
/// # Errors
/// PATH exists, or a file cannot be written.
pub fn new_key(path: &Path, out: &mut impl Write) -> Result<(), String> {
    if path.exists() {
        return Err(format!(
            "{}: exists (a key is never overwritten)",
            path.display()
        ));
    }
    let key = keys::generate();
    keys::write_key_pair(path, &key)?;
    writeln!(
        out,
        "wrote {} (private: keep it off the build machines' shared disks) and {}; key {}",
        path.display(),
        keys::public_path(path).display(),
        hex(&bridge_update::key_id(key.verifying_key().as_bytes()))
    )
    .map_err(|e| e.to_string())
}

/// `gimbal image-info`: what the release manifest says of an image, as one JSON object:
/// its size, SHA-256, the slot it must fit (the active slot of the flash layout) and the
/// room left, the signer's key id and whether the signature holds, and the time its update
/// takes on the wire at 115200 baud (the protocol's bytes both ways, without the flash's
/// own time), and the flash layout.
///
/// # Errors
/// The image or its signature file cannot be read.
pub fn image_info(image: &Path) -> Result<serde_json::Value, String> {
    use sha2::Digest;
    let bytes = std::fs::read(image).map_err(|e| format!("{}: {e}", image.display()))?;
    let size = u32::try_from(bytes.len())
        .map_err(|_| format!("{}: larger than 4 GiB", image.display()))?;
    let slot = bridge_update::layout::ACTIVE.size;
    let sig = std::fs::read(sig_path(image))
        .ok()
        .and_then(|s| keys::parse_sig(&s).ok());
    let (signed_by, signature_ok) = match sig {
        Some((signature, signer)) => (
            Some(hex(&bridge_update::key_id(&signer))),
            keys::verify(&signer, &bytes, &signature),
        ),
        None => (None, false),
    };
    let (to_board, to_client) = bridge_update::client::wire_bytes(size);
    let layout: Vec<serde_json::Value> = bridge_update::layout::FLASH_REGIONS
        .iter()
        .map(|r| serde_json::json!({"name": r.name, "start": format!("{:#010x}", r.start), "bytes": r.size}))
        .collect();
    Ok(serde_json::json!({
        "file": image.file_name().map(|n| n.to_string_lossy().into_owned()),
        "bytes": size,
        "sha256": hex(&sha2::Sha256::digest(&bytes)),
        "slot_bytes": slot,
        "margin_bytes": i64::from(slot) - i64::from(size),
        "signed_by": signed_by,
        "signature_ok": signature_ok,
        "update_wire_bytes": to_board + to_client,
        "update_seconds_115200": (bridge_update::client::wire_seconds(size, 115_200) * 10.0).round() / 10.0,
        "layout": layout,
    }))
}
