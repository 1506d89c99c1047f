//! What a ground station does with a camera's definition file and settings, as
//! docs/src/autopilots/qgroundcontrol.md describes QGroundControl and MAVSDK doing it:
//! the download over MAVLink FTP and the extended parameters (PARAM_EXT_*). One client
//! per camera, driven by the ground station ([`super::qgc::Qgc`]), in either style:
//!
//! - **QGroundControl** ([`ClientStyle::Qgc`]): OpenFileRO of the path after `mftp://`
//!   with a `/` before it (no NUL), BurstReadFile from offset 0, the next burst at the
//!   next offset after each `burst_complete`, holes (a reply whose offset is past the one
//!   expected) recorded, until NAK EOF; then ReadFile for each hole; then ResetSessions.
//!   Request seq = last reply seq + 1, replies expected at seq + 1 (a burst's counting
//!   on); a time-out (1 s) sends the same request again, with the same seq, 3 times at
//!   most. Once the file is in: PARAM_EXT_REQUEST_LIST. A set: PARAM_EXT_SET with the
//!   definition's type; IN_PROGRESS restarts the wait, FAILED and no answer are retried
//!   (3 tries), ACCEPTED takes the value.
//! - **MAVSDK** ([`ClientStyle::Mavsdk`]): OpenFileRO of the path after `mftp://` as it
//!   is, with its NUL; ReadFile of min(239, what is left) until the file's length;
//!   TerminateSession (success only on its ACK). Seqs from 0, one per request; a reply
//!   whose seq is the last one seen is ignored; a time-out (0.5 s) resends, 10 times at
//!   most. Once the file is in: every parameter read by name (PARAM_EXT_REQUEST_READ,
//!   index −1), one at a time; after an ACCEPTED set, all of them again.
//!
//! The downloaded `.xz` is inflated (lzma-rs) and its parameters read from the XML's
//! `<parameter name type>` tags. Every FTP opcode sent is logged ([`SettingsClient::ops`]).

use std::collections::{BTreeMap, VecDeque};

use protocol_core::mavlink::Header;
use protocol_core::mavlink::MavMessage;
use protocol_core::mavlink::dialect::CharArray;
use protocol_core::mavlink::dialect::{
    FILE_TRANSFER_PROTOCOL_DATA, MavParamExtType, PARAM_EXT_REQUEST_LIST_DATA,
    PARAM_EXT_REQUEST_READ_DATA, PARAM_EXT_SET_DATA, ParamAck,
};

/// Which ground station's behaviour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ClientStyle {
    /// QGroundControl: burst read, holes, ResetSessions, REQUEST_LIST.
    #[default]
    Qgc,
    /// MAVSDK: ReadFile, TerminateSession, REQUEST_READ by name.
    Mavsdk,
}

/// FTP opcodes.
pub mod op {
    /// TerminateSession.
    pub const TERMINATE: u8 = 1;
    /// ResetSessions.
    pub const RESET: u8 = 2;
    /// OpenFileRO.
    pub const OPEN: u8 = 4;
    /// ReadFile.
    pub const READ: u8 = 5;
    /// BurstReadFile.
    pub const BURST: u8 = 15;
    /// ACK.
    pub const ACK: u8 = 128;
    /// NAK.
    pub const NAK: u8 = 129;
    /// NAK code: end of file.
    pub const EOF: u8 = 6;
}

/// Where the download is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stage {
    Open,
    Burst,
    Holes,
    Read,
    Close,
    Done,
    Failed,
}

/// A parameter the client knows.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Param {
    /// MAV_PARAM_EXT_TYPE the definition gives it.
    pub kind: u8,
    /// The last value received (the bytes of `param_value` its type covers).
    pub value: Option<u64>,
}

/// A set in progress.
#[derive(Debug, Clone)]
struct Set {
    name: String,
    value: u64,
    tries: u8,
    sent_us: u64,
}

/// One camera's definition and settings, as a ground station handles them.
#[derive(Debug, Clone)]
pub struct SettingsClient {
    style: ClientStyle,
    /// The vehicle's system and the camera's component.
    target: (u8, u8),
    path: String,
    stage: Stage,
    /// FTP: the request in flight, its seq and when it went (resent as it is).
    request: Option<(FILE_TRANSFER_PROTOCOL_DATA, u64)>,
    tries: u8,
    /// QGC: the seq the next reply must have at least; MAVSDK: the last seq seen.
    expected: u16,
    next_seq: u16,
    offset: u32,
    /// Burst replies to lose on the way, by their number (from 0).
    drop_replies: Vec<usize>,
    burst_replies: usize,
    /// The file's length and what came of it (None: not yet).
    size: u32,
    bytes: Vec<Option<u8>>,
    holes: VecDeque<(u32, u32)>,
    /// Every FTP opcode sent, in order.
    pub ops: Vec<u8>,
    /// The file as downloaded (compressed), once complete.
    pub file: Option<Vec<u8>>,
    /// The definition, inflated.
    pub definition: Option<String>,
    /// The parameters the definition lists, with the values received.
    pub params: BTreeMap<String, Param>,
    /// The definition's parameter names, in its order.
    pub names: Vec<String>,
    /// MAVSDK: parameters still to read.
    to_read: VecDeque<String>,
    reading: Option<(String, u64)>,
    set: Option<Set>,
    sets: VecDeque<(String, u64)>,
    /// Every PARAM_EXT_ACK received: (name, result, value).
    pub acks: Vec<(String, ParamAck, u64)>,
    /// The final result of each set.
    pub set_results: Vec<(String, ParamAck)>,
    /// PARAM_EXT_VALUE received.
    pub values_received: usize,
    out: Vec<MavMessage>,
}

/// The bytes of a value of MAV_PARAM_EXT_TYPE `kind`.
fn width(kind: u8) -> usize {
    match kind {
        1 | 2 => 1,
        3 | 4 => 2,
        7 | 8 | 10 => 8,
        _ => 4,
    }
}

fn ext_type(kind: u8) -> MavParamExtType {
    match kind {
        5 => MavParamExtType::MAV_PARAM_EXT_TYPE_UINT32,
        3 => MavParamExtType::MAV_PARAM_EXT_TYPE_UINT16,
        _ => MavParamExtType::MAV_PARAM_EXT_TYPE_UINT8,
    }
}

/// The text of a NUL-padded char array.
fn text(bytes: &[u8]) -> String {
    let end = bytes.iter().position(|b| *b == 0).unwrap_or(bytes.len());
    String::from_utf8_lossy(&bytes[..end]).into_owned()
}

/// (name, MAV_PARAM_EXT_TYPE) of every `<parameter>` of a definition.
#[must_use]
pub fn definition_parameters(xml: &str) -> Vec<(String, u8)> {
    let attr = |tag: &str, a: &str| {
        let key = format!(" {a}=\"");
        tag.find(&key).map(|s| {
            let rest = &tag[s + key.len()..];
            rest[..rest.find('"').unwrap_or(0)].to_owned()
        })
    };
    xml.match_indices("<parameter ")
        .filter_map(|(at, _)| {
            let tag = &xml[at + 10..];
            let tag = &tag[..tag.find('>')?];
            let kind = match attr(tag, "type")?.as_str() {
                "uint8" | "bool" => 1,
                "int8" => 2,
                "uint16" => 3,
                "int16" => 4,
                "uint32" => 5,
                "int32" => 6,
                "float" => 9,
                _ => return None,
            };
            Some((attr(tag, "name")?, kind))
        })
        .collect()
}

impl SettingsClient {
    /// A client of the camera `target` (system, component) for `uri` (`mftp://...`),
    /// losing the burst replies numbered in `drop_replies`.
    #[must_use]
    pub fn new(style: ClientStyle, target: (u8, u8), uri: &str, drop_replies: Vec<usize>) -> Self {
        let path = uri.strip_prefix("mftp://").unwrap_or(uri);
        let path = match style {
            ClientStyle::Qgc => format!("/{path}"),
            ClientStyle::Mavsdk => path.to_owned(),
        };
        SettingsClient {
            style,
            target,
            path,
            stage: Stage::Open,
            request: None,
            tries: 0,
            expected: 0,
            next_seq: 0,
            offset: 0,
            drop_replies,
            burst_replies: 0,
            size: 0,
            bytes: Vec::new(),
            holes: VecDeque::new(),
            ops: Vec::new(),
            file: None,
            definition: None,
            params: BTreeMap::new(),
            names: Vec::new(),
            to_read: VecDeque::new(),
            reading: None,
            set: None,
            sets: VecDeque::new(),
            acks: Vec::new(),
            set_results: Vec::new(),
            values_received: 0,
            out: Vec::new(),
        }
    }

    /// The download failed (the ground station then shows a basic camera; QGC asks
    /// nothing more of it).
    #[must_use]
    pub fn failed(&self) -> bool {
        self.stage == Stage::Failed
    }

    /// The definition is in.
    #[must_use]
    pub fn loaded(&self) -> bool {
        self.definition.is_some()
    }

    /// Every parameter has a value.
    #[must_use]
    pub fn all_values(&self) -> bool {
        !self.params.is_empty() && self.params.values().all(|p| p.value.is_some())
    }

    /// Asks for every parameter again (QGroundControl's PARAM_EXT_REQUEST_LIST, as after
    /// a camera reset).
    pub fn request_list(&mut self) {
        self.out.push(MavMessage::PARAM_EXT_REQUEST_LIST(
            PARAM_EXT_REQUEST_LIST_DATA {
                target_system: self.target.0,
                target_component: self.target.1,
            },
        ));
    }

    /// Sets `name` to `value` (queued behind a set in progress).
    pub fn set(&mut self, name: &str, value: u64) {
        self.sets.push_back((name.to_owned(), value));
    }

    /// The value received for `name`.
    #[must_use]
    pub fn value(&self, name: &str) -> Option<u64> {
        self.params.get(name).and_then(|p| p.value)
    }

    /// Messages to send.
    pub fn transmit(&mut self) -> Vec<MavMessage> {
        std::mem::take(&mut self.out)
    }

    fn ftp(&mut self, now: u64, seq: u16, opcode: u8, size: u8, offset: u32, data: &[u8]) {
        let mut payload = [0u8; 251];
        payload[..2].copy_from_slice(&seq.to_le_bytes());
        payload[3] = opcode;
        payload[4] = size;
        payload[8..12].copy_from_slice(&offset.to_le_bytes());
        payload[12..12 + data.len()].copy_from_slice(data);
        let m = FILE_TRANSFER_PROTOCOL_DATA {
            target_network: 0,
            target_system: self.target.0,
            target_component: self.target.1,
            payload,
        };
        self.ops.push(opcode);
        self.request = Some((m.clone(), now));
        self.out.push(MavMessage::FILE_TRANSFER_PROTOCOL(m));
    }

    /// Sends the next request of the style's sequence (a new seq).
    fn request(&mut self, now: u64, opcode: u8, size: u8, offset: u32, data: &[u8]) {
        let seq = match self.style {
            ClientStyle::Qgc => {
                let s = self.expected.wrapping_add(1);
                self.expected = self.expected.wrapping_add(2);
                s
            }
            ClientStyle::Mavsdk => {
                let s = self.next_seq;
                self.next_seq = self.next_seq.wrapping_add(1);
                s
            }
        };
        self.tries = 0;
        self.ftp(now, seq, opcode, size, offset, data);
    }

    fn open(&mut self, now: u64) {
        let mut path = self.path.clone().into_bytes();
        let size = match self.style {
            ClientStyle::Qgc => path.len(),
            ClientStyle::Mavsdk => {
                path.push(0);
                path.len()
            }
        };
        self.request(now, op::OPEN, size as u8, 0, &path);
    }

    fn next_read(&mut self, now: u64) {
        match self.stage {
            Stage::Burst => self.request(now, op::BURST, 239, self.offset, &[]),
            Stage::Holes => match self.holes.front().copied() {
                Some((at, len)) => self.request(now, op::READ, len.min(239) as u8, at, &[]),
                None => {
                    self.stage = Stage::Close;
                    self.request(now, op::RESET, 0, 0, &[]);
                }
            },
            Stage::Read if self.offset < self.size => {
                let n = (self.size - self.offset).min(239) as u8;
                self.request(now, op::READ, n, self.offset, &[]);
            }
            Stage::Read => {
                self.stage = Stage::Close;
                self.request(now, op::TERMINATE, 0, 0, &[]);
            }
            _ => {}
        }
    }

    fn write(&mut self, offset: u32, data: &[u8]) {
        for (i, b) in data.iter().enumerate() {
            if let Some(slot) = self.bytes.get_mut(offset as usize + i) {
                *slot = Some(*b);
            }
        }
    }

    /// A message the autopilot routed to the ground station.
    pub fn receive(&mut self, now: u64, h: Header, msg: &MavMessage) {
        if (h.system_id, h.component_id) != self.target {
            return;
        }
        match msg {
            MavMessage::FILE_TRANSFER_PROTOCOL(f) => self.ftp_reply(now, &f.payload),
            MavMessage::PARAM_EXT_VALUE(v) => {
                self.values_received += 1;
                let name = text(&v.param_id[..]);
                let kind = v.param_type as u8;
                let mut raw = [0u8; 8];
                let w = width(kind);
                raw[..w].copy_from_slice(&v.param_value[..w]);
                let value = u64::from_le_bytes(raw);
                if let Some(p) = self.params.get_mut(&name) {
                    p.value = Some(value);
                }
                if self.reading.as_ref().is_some_and(|(n, _)| *n == name) {
                    self.reading = None;
                }
            }
            MavMessage::PARAM_EXT_ACK(a) => {
                let name = text(&a.param_id[..]);
                let mut raw = [0u8; 8];
                let w = width(a.param_type as u8);
                raw[..w].copy_from_slice(&a.param_value[..w]);
                let value = u64::from_le_bytes(raw);
                self.acks.push((name.clone(), a.param_result, value));
                self.param_ack(now, &name, a.param_result, value);
            }
            _ => {}
        }
    }

    fn ftp_reply(&mut self, now: u64, p: &[u8; 251]) {
        let seq = u16::from_le_bytes([p[0], p[1]]);
        let (opcode, size, req, complete) = (p[3], p[4], p[5], p[6] != 0);
        let offset = u32::from_le_bytes([p[8], p[9], p[10], p[11]]);
        let data = &p[12..12 + usize::from(size).min(239)];
        match self.style {
            ClientStyle::Qgc => {
                // Old or reordered replies are ignored.
                if self.expected.wrapping_sub(1).wrapping_sub(seq) < u16::MAX / 2 {
                    return;
                }
            }
            ClientStyle::Mavsdk => {
                if seq != 0 && seq == self.expected {
                    return;
                }
                self.expected = seq;
            }
        }
        let Some((sent, _)) = self.request.as_ref() else {
            return;
        };
        if req != sent.payload[3] {
            return;
        }
        match (self.stage, opcode) {
            (Stage::Open, op::ACK) if self.style == ClientStyle::Qgc && size != 4 => {
                self.stage = Stage::Failed;
            }
            (Stage::Open, op::ACK) => {
                self.size = u32::from_le_bytes([data[0], data[1], data[2], data[3]]);
                self.bytes = vec![None; self.size as usize];
                self.stage = match self.style {
                    ClientStyle::Qgc => Stage::Burst,
                    ClientStyle::Mavsdk => Stage::Read,
                };
                self.next_read(now);
            }
            (Stage::Burst, op::ACK) => {
                let n = self.burst_replies;
                self.burst_replies += 1;
                if self.drop_replies.contains(&n) {
                    return;
                }
                if offset < self.offset {
                    return;
                }
                if offset > self.offset {
                    self.holes.push_back((self.offset, offset - self.offset));
                }
                self.write(offset, data);
                self.offset = offset + u32::from(size);
                if complete {
                    self.expected = seq;
                    self.next_read(now);
                } else {
                    self.expected = seq.wrapping_add(1);
                    if let Some(r) = self.request.as_mut() {
                        r.1 = now;
                    }
                }
            }
            (Stage::Burst, op::NAK) if data.first() == Some(&op::EOF) => {
                if seq == self.expected {
                    self.stage = Stage::Holes;
                } else {
                    self.expected = seq;
                }
                self.next_read(now);
            }
            (Stage::Holes, op::ACK) if seq == self.expected => {
                let Some((at, len)) = self.holes.pop_front() else {
                    return;
                };
                if offset != at {
                    self.holes.push_front((at, len));
                    return;
                }
                self.write(offset, data);
                let got = u32::from(size);
                if got < len {
                    self.holes.push_front((at + got, len - got));
                }
                self.next_read(now);
            }
            (Stage::Read, op::ACK) => {
                if offset == self.offset {
                    self.write(offset, data);
                    self.offset += u32::from(size);
                }
                self.next_read(now);
            }
            (Stage::Close, op::ACK) | (Stage::Close, op::NAK)
                if self.style == ClientStyle::Qgc || opcode == op::ACK =>
            {
                self.request = None;
                self.finish(now);
            }
            (_, op::NAK) => self.stage = Stage::Failed,
            _ => {}
        }
    }

    /// The file is in: inflate it, list its parameters, ask for their values.
    fn finish(&mut self, now: u64) {
        let file: Option<Vec<u8>> = self.bytes.iter().copied().collect();
        let Some(file) = file else {
            self.stage = Stage::Failed;
            return;
        };
        let mut xml = Vec::new();
        if lzma_rs::xz_decompress(&mut &file[..], &mut xml).is_err() {
            self.stage = Stage::Failed;
            return;
        }
        self.file = Some(file);
        let xml = String::from_utf8_lossy(&xml).into_owned();
        for (name, kind) in definition_parameters(&xml) {
            self.names.push(name.clone());
            self.params.insert(name, Param { kind, value: None });
        }
        self.definition = Some(xml);
        self.stage = Stage::Done;
        match self.style {
            ClientStyle::Qgc => self.out.push(MavMessage::PARAM_EXT_REQUEST_LIST(
                PARAM_EXT_REQUEST_LIST_DATA {
                    target_system: self.target.0,
                    target_component: self.target.1,
                },
            )),
            ClientStyle::Mavsdk => self.refresh(),
        }
        let _ = now;
    }

    /// MAVSDK: every parameter read again, one at a time.
    fn refresh(&mut self) {
        self.to_read = self.names.iter().cloned().collect();
    }

    fn param_ack(&mut self, now: u64, name: &str, result: ParamAck, value: u64) {
        let Some(set) = self.set.as_mut().filter(|s| s.name == name) else {
            return;
        };
        match result {
            ParamAck::PARAM_ACK_IN_PROGRESS => set.sent_us = now,
            ParamAck::PARAM_ACK_ACCEPTED => {
                if let Some(p) = self.params.get_mut(name) {
                    p.value = Some(value);
                }
                self.set_results
                    .push((name.to_owned(), ParamAck::PARAM_ACK_ACCEPTED));
                self.set = None;
                if self.style == ClientStyle::Mavsdk {
                    self.refresh();
                }
            }
            ParamAck::PARAM_ACK_FAILED if self.style == ClientStyle::Qgc && set.tries < 3 => {
                let (n, v) = (set.name.clone(), set.value);
                self.send_set(now, &n, v);
                if let Some(s) = self.set.as_mut() {
                    s.tries += 1;
                }
            }
            other => {
                self.set_results.push((name.to_owned(), other));
                self.set = None;
            }
        }
    }

    fn send_set(&mut self, now: u64, name: &str, value: u64) {
        let kind = self.params.get(name).map_or(1, |p| p.kind);
        let mut id = [0u8; 16];
        id[..name.len().min(16)].copy_from_slice(&name.as_bytes()[..name.len().min(16)]);
        let mut v = [0u8; 128];
        let w = width(kind);
        v[..w].copy_from_slice(&value.to_le_bytes()[..w]);
        self.out.push(MavMessage::PARAM_EXT_SET(PARAM_EXT_SET_DATA {
            target_system: self.target.0,
            target_component: self.target.1,
            param_id: CharArray::from(id),
            param_value: CharArray::from(v),
            param_type: ext_type(kind),
        }));
        if let Some(s) = self.set.as_mut() {
            s.sent_us = now;
        }
    }

    fn read(&mut self, now: u64, name: &str) {
        let mut id = [0u8; 16];
        id[..name.len().min(16)].copy_from_slice(&name.as_bytes()[..name.len().min(16)]);
        self.out.push(MavMessage::PARAM_EXT_REQUEST_READ(
            PARAM_EXT_REQUEST_READ_DATA {
                param_index: -1,
                target_system: self.target.0,
                target_component: self.target.1,
                param_id: CharArray::from(id),
            },
        ));
        self.reading = Some((name.to_owned(), now));
    }

    /// Work due at `now`: the first request, time-outs, the next read or set.
    pub fn poll(&mut self, now: u64) {
        if self.stage == Stage::Open && self.request.is_none() {
            self.open(now);
            return;
        }
        let (timeout, max_tries) = match self.style {
            ClientStyle::Qgc => (1_000_000, 3),
            ClientStyle::Mavsdk => (500_000, 10),
        };
        if let Some((m, sent)) = self.request.clone()
            && !matches!(self.stage, Stage::Done | Stage::Failed)
            && now - sent >= timeout
        {
            if self.tries >= max_tries {
                self.stage = Stage::Failed;
            } else {
                self.tries += 1;
                // QGC sends the request again with its seq; MAVSDK its payload as it was.
                let seq = u16::from_le_bytes([m.payload[0], m.payload[1]]);
                if self.style == ClientStyle::Qgc {
                    self.expected = seq.wrapping_add(1);
                }
                let tries = self.tries;
                self.ftp(
                    now,
                    seq,
                    m.payload[3],
                    m.payload[4],
                    u32::from_le_bytes([m.payload[8], m.payload[9], m.payload[10], m.payload[11]]),
                    &m.payload[12..12 + usize::from(m.payload[4]).min(239)],
                );
                self.tries = tries;
            }
        }
        if self.stage != Stage::Done {
            return;
        }
        if let Some((name, at)) = self.reading.clone() {
            if now - at >= 500_000 {
                self.read(now, &name);
            }
            return;
        }
        if let Some(set) = self.set.clone() {
            if now - set.sent_us >= 1_500_000 {
                if set.tries >= 3 {
                    self.set_results
                        .push((set.name, ParamAck::PARAM_ACK_FAILED));
                    self.set = None;
                } else {
                    self.send_set(now, &set.name, set.value);
                    if let Some(s) = self.set.as_mut() {
                        s.tries += 1;
                    }
                }
            }
            return;
        }
        if let Some(name) = self.to_read.pop_front() {
            self.read(now, &name);
            return;
        }
        if let Some((name, value)) = self.sets.pop_front() {
            self.set = Some(Set {
                name: name.clone(),
                value,
                tries: 1,
                sent_us: now,
            });
            self.send_set(now, &name, value);
        }
    }
}
