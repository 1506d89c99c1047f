//! The camera's MAVLink FTP server (FILE_TRANSFER_PROTOCOL to component 100): one file,
//! read-only, the camera definition `k40t.xml.xz`, as QGroundControl and MAVSDK download
//! it (see docs/src/bridge/mavlink.md, "Settings and the camera definition").
//!
//! - **Requests** addressed to this system and component 100 exactly (the autopilot has
//!   an FTP server of its own: a broadcast is not the camera's). Replies go from 100 to the
//!   requester (target system and component = its header), with seq = the request's
//!   seq + 1; a burst's replies count on from there. Every request is idempotent: a
//!   repeat gets the same answer.
//! - **OpenFileRO** of `k40t.xml.xz` (a leading `/` and trailing NULs ignored: QGC sends
//!   `/k40t.xml.xz` without a NUL, MAVSDK `k40t.xml.xz` with one): ACK of size 4, the
//!   file's length (u32 LE). Any other path: NAK FileNotFound.
//! - **Sessions** belong to a client (system and component): OpenFileRO opens (or
//!   re-opens) the client's, TerminateSession and ResetSessions close it (always ACKed:
//!   MAVSDK reports success only on that ACK, and retries a lost one); ResetSessions
//!   closes only the requester's, so one ground station cannot break another's download.
//!   The session byte of a read is echoed, not checked: MAVSDK 4 reads with session 0
//!   whatever OpenFileRO answered. Two clients at once; a third gets NAK
//!   NoSessionsAvailable unless a session has been idle for [`SESSION_IDLE`] (MAVSDK backs
//!   off and retries).
//! - **ReadFile**: one ACK with the data at the offset (at most 239 bytes); NAK EOF at or
//!   past the end. **BurstReadFile**: ACKs of 239 bytes from the offset, at most
//!   [`BURST`] of them, the last with `burst_complete` (also the one that reaches the
//!   end); at or past the end NAK EOF, which ends QGroundControl's read.
//! - **Anything else** (listing, writing, CRC): NAK UnknownCommand.
//! - **Pacing.** Data replies (up to 266 bytes on the wire) are never queued behind other
//!   frames: one goes out only when the FC queue is empty, and the next no sooner than
//!   1.5 times its serial time later, so that the device's own traffic (attitude status
//!   at 10 Hz, heartbeats, ACKs, TIMESYNC) always finds the line free within one frame
//!   and file data takes at most two thirds of the line.

use crate::discipline::serial_time;
use crate::time::{Duration, Instant};
use protocol_core::mavlink::Header;

use super::{Comp, MavlinkSide};
use crate::fc::Ctx;

/// The camera definition, xz-compressed (`bridge-engine/camera/k40t.xml.xz`).
pub(super) const DEFINITION: &[u8] = include_bytes!("../../../camera/k40t.xml.xz");
/// Its path on the server.
const DEFINITION_PATH: &[u8] = b"k40t.xml.xz";
/// CAMERA_INFORMATION's `cam_definition_uri` (QGroundControl takes `mftp://` only).
pub(super) const DEFINITION_URI: &[u8] = b"mftp://k40t.xml.xz";
/// CAMERA_INFORMATION's `cam_definition_version`: the `version` of the XML's
/// `<definition>` (both ground stations cache the file by vendor, model and version).
pub(super) const DEFINITION_VERSION: u16 = 1;

/// FILE_TRANSFER_PROTOCOL.
pub(super) const ID: u32 = 110;

/// Clients with a session at once.
const SESSIONS: usize = 2;
/// Replies of one BurstReadFile.
pub(super) const BURST: u8 = 8;
/// A session idle this long may be taken by another client.
const SESSION_IDLE: Duration = Duration::from_secs(3);
/// A data reply due while frames wait in the FC queue is tried again this much later.
const QUEUE_WAIT: Duration = Duration::from_millis(3);
/// Data bytes of one reply.
const MAX_DATA: usize = 239;
/// Bytes of FILE_TRANSFER_PROTOCOL's payload (targets and the FTP payload).
const PAYLOAD: usize = 254;

/// FTP opcodes.
mod op {
    pub(super) const TERMINATE_SESSION: u8 = 1;
    pub(super) const RESET_SESSIONS: u8 = 2;
    pub(super) const OPEN_FILE_RO: u8 = 4;
    pub(super) const READ_FILE: u8 = 5;
    pub(super) const BURST_READ_FILE: u8 = 15;
    pub(super) const ACK: u8 = 128;
    pub(super) const NAK: u8 = 129;
}

/// NAK error codes (MAV_FTP_ERR).
mod err {
    pub(super) const INVALID_SESSION: u8 = 4;
    pub(super) const NO_SESSIONS_AVAILABLE: u8 = 5;
    pub(super) const EOF: u8 = 6;
    pub(super) const UNKNOWN_COMMAND: u8 = 7;
    pub(super) const FILE_NOT_FOUND: u8 = 10;
}

/// Data replies still to send for one request.
#[derive(Debug, Clone, Copy)]
struct Stream {
    /// The next reply's seq.
    seq: u16,
    /// The request's session byte, echoed.
    session: u8,
    /// ReadFile or BurstReadFile.
    opcode: u8,
    offset: u32,
    /// Bytes per reply (ReadFile's size; 239 for a burst).
    size: u8,
    /// Replies left.
    left: u8,
}

/// A client's session.
#[derive(Debug, Clone, Copy)]
struct Session {
    /// The client's system and component.
    client: (u8, u8),
    /// Its last request.
    last: Instant,
    stream: Option<Stream>,
}

/// The server's state: the sessions and the pacing of data replies.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Ftp {
    sessions: [Option<Session>; SESSIONS],
    /// No data reply before this.
    next: Instant,
    /// The session whose data goes next (round robin).
    turn: u8,
}

/// One reply.
struct Reply<'a> {
    seq: u16,
    session: u8,
    opcode: u8,
    req_opcode: u8,
    burst_complete: bool,
    offset: u32,
    data: &'a [u8],
}

impl Ftp {
    fn session_mut(&mut self, client: (u8, u8)) -> Option<&mut Session> {
        self.sessions
            .iter_mut()
            .flatten()
            .find(|s| s.client == client)
    }

    /// Opens (or re-opens) `client`'s session; false when none is free.
    fn open(&mut self, client: (u8, u8), now: Instant) -> bool {
        if let Some(s) = self.session_mut(client) {
            s.stream = None;
            return true;
        }
        let free = self.sessions.iter().position(Option::is_none).or_else(|| {
            self.sessions
                .iter()
                .enumerate()
                .filter_map(|(i, s)| s.map(|s| (i, s.last)))
                .filter(|(_, last)| now.saturating_duration_since(*last) >= SESSION_IDLE)
                .min_by_key(|(_, last)| *last)
                .map(|(i, _)| i)
        });
        let Some(slot) = free.and_then(|i| self.sessions.get_mut(i)) else {
            return false;
        };
        *slot = Some(Session {
            client,
            last: now,
            stream: None,
        });
        true
    }

    fn close(&mut self, client: (u8, u8)) {
        for s in &mut self.sessions {
            if s.is_some_and(|s| s.client == client) {
                *s = None;
            }
        }
    }

    /// The next data reply due (the session's client and the reply), taken off its
    /// stream; round robin over the sessions.
    fn next_chunk(&mut self) -> Option<((u8, u8), Stream, usize, bool)> {
        for k in 0..SESSIONS {
            let i = usize::from(self.turn).wrapping_add(k) % SESSIONS;
            let Some(Some(s)) = self.sessions.get_mut(i) else {
                continue;
            };
            let Some(mut st) = s.stream else {
                continue;
            };
            let at = usize::try_from(st.offset).unwrap_or(usize::MAX);
            let n = DEFINITION
                .len()
                .saturating_sub(at)
                .min(usize::from(st.size))
                .min(MAX_DATA);
            let reply = st;
            st.offset = st.offset.saturating_add(u32::try_from(n).unwrap_or(0));
            st.seq = st.seq.wrapping_add(1);
            st.left = st.left.saturating_sub(1);
            let at_end = usize::try_from(st.offset).unwrap_or(usize::MAX) >= DEFINITION.len();
            let burst = reply.opcode == op::BURST_READ_FILE;
            let complete = burst && (st.left == 0 || at_end);
            s.stream = (burst && !complete).then_some(st);
            self.turn = u8::try_from((i.wrapping_add(1)) % SESSIONS).unwrap_or(0);
            return Some((s.client, reply, n, complete));
        }
        None
    }

    /// When data replies wait.
    pub(super) fn poll_at(&self) -> Option<Instant> {
        self.sessions
            .iter()
            .flatten()
            .any(|s| s.stream.is_some())
            .then_some(self.next)
    }
}

/// The requested path, without a leading `/` and trailing NULs.
fn path(data: &[u8]) -> &[u8] {
    let end = data
        .iter()
        .rposition(|b| *b != 0)
        .map_or(0, |i| i.saturating_add(1));
    let p = data.get(..end).unwrap_or_default();
    p.strip_prefix(b"/").unwrap_or(p)
}

impl MavlinkSide {
    /// A FILE_TRANSFER_PROTOCOL from `from` (its payload as sent: zero-extended here).
    pub(super) fn ftp_request(&mut self, ctx: &mut Ctx<'_>, from: Header, payload: &[u8]) {
        let mut p = [0u8; PAYLOAD];
        for (d, s) in p.iter_mut().zip(payload) {
            *d = *s;
        }
        let [
            _,
            target_system,
            target_component,
            s0,
            s1,
            session,
            opcode,
            size,
            ..,
        ] = p;
        if self.ap.sysid != Some(target_system) || target_component != Comp::Camera.id() {
            ctx.ignored();
            return;
        }
        // Replies from another server, routed onto the link: not requests.
        if opcode >= op::ACK {
            ctx.ignored();
            return;
        }
        let seq = u16::from_le_bytes([s0, s1]);
        let mut o = [0u8; 4];
        for (d, s) in o.iter_mut().zip(p.iter().skip(11)) {
            *d = *s;
        }
        let offset = u32::from_le_bytes(o);
        let data = p
            .get(15..15usize.saturating_add(usize::from(size).min(MAX_DATA)))
            .unwrap_or_default();
        let client = (from.system_id, from.component_id);
        if let Some(s) = self.ftp.session_mut(client) {
            s.last = ctx.now;
        }
        let reply = seq.wrapping_add(1);
        let ack = Reply {
            seq: reply,
            session,
            opcode: op::ACK,
            req_opcode: opcode,
            burst_complete: false,
            offset,
            data: &[],
        };
        let nak = |code: u8| (reply, session, opcode, offset, code);
        match opcode {
            op::OPEN_FILE_RO => {
                if path(data) != DEFINITION_PATH {
                    self.ftp_nak(ctx, client, nak(err::FILE_NOT_FOUND));
                } else if self.ftp.open(client, ctx.now) {
                    let len = u32::try_from(DEFINITION.len()).unwrap_or(0).to_le_bytes();
                    let open = Reply {
                        offset: 0,
                        data: &len,
                        ..ack
                    };
                    self.ftp_reply(ctx, client, &open);
                } else {
                    self.ftp_nak(ctx, client, nak(err::NO_SESSIONS_AVAILABLE));
                }
            }
            op::READ_FILE | op::BURST_READ_FILE => {
                let Some(s) = self.ftp.session_mut(client) else {
                    self.ftp_nak(ctx, client, nak(err::INVALID_SESSION));
                    return;
                };
                if usize::try_from(offset).unwrap_or(usize::MAX) >= DEFINITION.len() {
                    s.stream = None;
                    self.ftp_nak(ctx, client, nak(err::EOF));
                    return;
                }
                let burst = opcode == op::BURST_READ_FILE;
                s.stream = Some(Stream {
                    seq: reply,
                    session,
                    opcode,
                    offset,
                    size: if burst { u8::MAX } else { size },
                    left: if burst { BURST } else { 1 },
                });
                self.ftp_poll(ctx);
            }
            op::TERMINATE_SESSION | op::RESET_SESSIONS => {
                self.ftp.close(client);
                self.ftp_reply(ctx, client, &ack);
            }
            _ => self.ftp_nak(ctx, client, nak(err::UNKNOWN_COMMAND)),
        }
    }

    /// Sends the next data reply when it is due and the FC queue is empty.
    pub(super) fn ftp_poll(&mut self, ctx: &mut Ctx<'_>) {
        if self.ftp.poll_at().is_none_or(|t| ctx.now < t) {
            return;
        }
        if !ctx.link_idle() {
            self.ftp.next = ctx.now.saturating_add(QUEUE_WAIT);
            return;
        }
        let Some((client, st, n, complete)) = self.ftp.next_chunk() else {
            return;
        };
        let at = usize::try_from(st.offset).unwrap_or(usize::MAX);
        let data = DEFINITION.get(at..at.saturating_add(n)).unwrap_or_default();
        let reply = Reply {
            seq: st.seq,
            session: st.session,
            opcode: op::ACK,
            req_opcode: st.opcode,
            burst_complete: complete,
            offset: st.offset,
            data,
        };
        self.ftp_reply(ctx, client, &reply);
        // Header, checksum, targets, the FTP header and the data; half as long again.
        let bytes = u32::try_from(n.saturating_add(27).saturating_mul(3) / 2).unwrap_or(0);
        self.ftp.next = ctx.now.saturating_add(serial_time(bytes, ctx.baud));
    }

    /// A NAK: (seq, session, request opcode, offset, error).
    fn ftp_nak(&mut self, ctx: &mut Ctx<'_>, client: (u8, u8), n: (u16, u8, u8, u32, u8)) {
        let (seq, session, req_opcode, offset, code) = n;
        let reply = Reply {
            seq,
            session,
            opcode: op::NAK,
            req_opcode,
            burst_complete: false,
            offset,
            data: &[code],
        };
        self.ftp_reply(ctx, client, &reply);
    }

    fn ftp_reply(&mut self, ctx: &mut Ctx<'_>, client: (u8, u8), r: &Reply<'_>) {
        let mut p = [0u8; PAYLOAD];
        let [s0, s1] = r.seq.to_le_bytes();
        let size = u8::try_from(r.data.len()).unwrap_or(0);
        let head = [
            0,
            client.0,
            client.1,
            s0,
            s1,
            r.session,
            r.opcode,
            size,
            r.req_opcode,
            u8::from(r.burst_complete),
            0,
        ];
        let offset = r.offset.to_le_bytes();
        let bytes = head.iter().chain(&offset).chain(r.data);
        for (d, s) in p.iter_mut().zip(bytes) {
            *d = *s;
        }
        self.ap.send_raw(ctx, Comp::Camera.id(), ID, &p);
    }
}
