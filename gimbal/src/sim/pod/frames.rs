//! Frames in and out: the receiver (deframing, arrival instants, requests) and the sender
//! (sequence numbers, ACKs, queued frames, output faults).

use super::*;

/// A frame waiting for its instant.
#[derive(Debug, Clone)]
pub(super) struct Queued {
    pub(super) due_us: u64,
    pub(super) header: Header,
    pub(super) id: MsgId,
    pub(super) payload: Vec<u8>,
}

/// The deframer's framing for `config`.
pub(super) fn framing_of(config: &PodSimConfig) -> K40tFraming {
    if config.accept_any_coverage {
        K40tFraming::any()
    } else {
        K40tFraming::with(config.coverage)
    }
}

/// The payload bytes of a message.
pub(super) fn payload<M: MessageData<Protocol = K40t>>(m: &M) -> Vec<u8> {
    let mut buf = vec![0; M::ENCODED_LEN];
    let mut w = Writer::new(&mut buf);
    // Cannot fail: the buffer has the message's encoded length.
    let _ = m.encode_payload(&mut w);
    buf
}

/// A message as (id, payload bytes).
pub(super) fn message<M: MessageData<Protocol = K40t>>(m: &M) -> (MsgId, Vec<u8>) {
    (M::ID, payload(m))
}

impl SimPod {
    /// Drains the deframer's events (idle: gives up an incomplete candidate); returns
    /// whether any event came.
    pub(super) fn drain_deframer(&mut self, now: u64, idle: bool) -> bool {
        let mut any = false;
        loop {
            let event = if idle {
                self.deframer.poll_idle()
            } else {
                self.deframer.poll()
            };
            let frame = match event {
                None => break,
                Some(Event::Frame(bytes)) => Some(bytes.to_vec()),
                Some(Event::Rejected { .. } | Event::Skipped(_)) => None,
            };
            any = true;
            if let Some(frame) = frame {
                // The bytes after the frame are what the deframer still holds.
                let end = self.rx_fed - self.deframer.buffered() as u64;
                let start = end.saturating_sub(frame.len() as u64);
                let start_us = self.arrival_of(start);
                let at_us = self.arrival_of(end.saturating_sub(1)).max(start_us);
                self.handle_frame(now, frame, start_us, at_us);
            }
        }
        any
    }

    /// When the byte at stream offset `offset` arrived.
    pub(super) fn arrival_of(&self, offset: u64) -> u64 {
        self.rx_chunks
            .iter()
            .rev()
            .find(|&&(first, _)| first <= offset)
            .map_or(self.last_rx_us, |&(_, t)| t)
    }

    /// Forgets chunks no buffered byte belongs to.
    pub(super) fn prune_chunks(&mut self) {
        let oldest_held = self.rx_fed - self.deframer.buffered() as u64;
        while self.rx_chunks.len() > 1 && self.rx_chunks.get(1).is_some_and(|c| c.0 <= oldest_held)
        {
            self.rx_chunks.pop_front();
        }
    }

    pub(super) fn handle_frame(&mut self, now: u64, frame: Vec<u8>, start_us: u64, at_us: u64) {
        self.rx.frames += 1;
        let packet = match Packet::decode(&frame) {
            Ok(p) => p,
            Err(_) => {
                self.rx.malformed += 1;
                return;
            }
        };
        let header = packet.header;
        let id = packet.message.id();
        *self.rx_counts.entry(id.to_u32()).or_insert(0) += 1;
        let message = packet.message;
        let reply = message.get::<GpsReply>();
        let request = match message {
            Message::Request(r) => Some(r),
            _ => None,
        };
        let raw_request =
            matches!(message, Message::Raw(Raw { id, .. }) if id.kind == Kind::Request);
        self.received.push(RxRecord {
            start_us,
            at_us,
            header,
            id,
            frame,
        });
        if self.config.strict_destination
            && header.dst != self.config.gimbal_address
            && header.dst != self.config.camera_address
        {
            self.rx.misaddressed += 1;
            return;
        }
        if let Some(reply) = reply {
            self.handle_gps_reply(now, header, reply);
        } else if let Some(request) = request {
            self.handle_request(now, header, request, start_us);
        } else if raw_request && self.config.ack_unknown {
            let _ = self.ack(now, header, id.base, Ok(None));
        }
    }

    pub(super) fn handle_request(
        &mut self,
        t: u64,
        header: Header,
        request: Request,
        start_us: u64,
    ) {
        let base = request.base();
        let mut record = RequestRecord {
            at_us: t,
            header,
            request,
            code: None,
            executed: false,
            ack_seq: None,
        };
        // The bridge has no business sending reports or GPS requests: no ACK.
        if matches!(base, 0x0001..=0x0008 | 0x0310) {
            self.requests.push(record);
            return;
        }
        if let Some(&code) = self.config.nak.get(&base) {
            record.code = Some(code);
            record.ack_seq = self.ack(t, header, base, Err(code));
            self.requests.push(record);
            return;
        }
        self.deferred.clear();
        let result = self.execute(t, request, start_us);
        record.code = Some(match &result {
            Ok(_) => AckCode::Ok,
            Err(code) => *code,
        });
        record.executed = result.is_ok();
        record.ack_seq = self.ack(t, header, base, result);
        self.requests.push(record);
        let deferred = std::mem::take(&mut self.deferred);
        for (id, payload) in deferred {
            self.send_payload(t.saturating_add(self.config.ack_delay_us), id, payload);
        }
    }

    pub(super) fn source_for(&self, base: u16) -> Address {
        if matches!(base, 0x0001 | 0x0002 | 0x0010..=0x00FF) {
            self.config.gimbal_address
        } else {
            self.config.camera_address
        }
    }

    pub(super) fn next_seq(&mut self, src: Address) -> u8 {
        let seq = self
            .seqs
            .entry((src.system, src.component))
            .or_insert(self.seq_base);
        let current = *seq;
        *seq = seq.wrapping_add(1);
        current
    }

    /// Sends a pod-originated message now; returns its sequence number.
    pub(super) fn send<M: MessageData<Protocol = K40t>>(&mut self, t: u64, m: &M) -> u8 {
        let (id, bytes) = message(m);
        self.send_payload(t, id, bytes)
    }

    /// Sends a pod-originated frame at `due` (now if not later than `now_us`).
    pub(super) fn send_payload(&mut self, due: u64, id: MsgId, payload: Vec<u8>) -> u8 {
        let src = self.source_for(id.base);
        let seq = self.next_seq(src);
        let header = Header {
            dst: self.config.fc_address,
            src,
            seq,
            coverage: self.config.coverage,
        };
        self.queue(due, header, id, payload);
        seq
    }

    pub(super) fn queue(&mut self, due: u64, header: Header, id: MsgId, payload: Vec<u8>) {
        // Queued frames due by now have gone out already (the outbox timer ran first).
        if due <= self.model_us {
            self.emit(self.model_us, header, id, &payload);
        } else {
            let at = self.outbox.partition_point(|q| q.due_us <= due);
            self.outbox.insert(
                at,
                Queued {
                    due_us: due,
                    header,
                    id,
                    payload,
                },
            );
        }
    }

    /// Sends the ACK of a request (`result` as [`SimPod::execute`] returns it).
    /// Returns the ACK's sequence number (`None`: dropped).
    pub(super) fn ack(
        &mut self,
        t: u64,
        request: Header,
        base: u16,
        result: Result<Option<Vec<u8>>, AckCode>,
    ) -> Option<u8> {
        let src = self.source_for(base);
        // A dropped ACK was sent and lost on the way: it used its number.
        let seq = match self.config.ack_seq {
            AckSeq::Echo => request.seq,
            AckSeq::OwnCounter => self.next_seq(src),
        };
        if let Some(left) = self.config.drop_acks.get_mut(&base).filter(|n| **n > 0) {
            *left -= 1;
            self.acks_dropped += 1;
            return None;
        }
        let (code, mut bytes) = match result {
            Ok(Some(bytes)) => (AckCode::Ok, bytes),
            Ok(None) => (AckCode::Ok, vec![0; 2]),
            Err(code) => {
                // The ACK's layout, data zeroed.
                let len = Ack::decode(base, &[])
                    .and_then(Result::ok)
                    .map_or(2, |a| a.payload_len());
                (code, vec![0; len.max(2)])
            }
        };
        let raw = if self.config.ack_code_le {
            code.value().to_le_bytes()
        } else {
            code.value().to_be_bytes()
        };
        if let Some(head) = bytes.get_mut(..2) {
            head.copy_from_slice(&raw);
        }
        let header = Header {
            dst: request.src,
            src,
            seq,
            coverage: self.config.coverage,
        };
        let due = t.saturating_add(self.config.ack_delay_us);
        self.queue(due, header, MsgId::new(Kind::Ack, base), bytes);
        Some(seq)
    }

    /// Puts a frame on the line (or loses it while silent), with output faults.
    pub(super) fn emit(&mut self, t: u64, header: Header, id: MsgId, payload: &[u8]) {
        let packet = Packet {
            header,
            message: Message::Raw(Raw { id, payload }),
        };
        let mut buf = [0u8; MAX_FRAME_LEN];
        let Ok(n) = packet.emit(&mut buf) else {
            return;
        };
        let frame = buf.get(..n).unwrap_or_default().to_vec();
        if self.silent {
            self.lost_while_silent += 1;
            return;
        }
        *self.tx_counts.entry(id.to_u32()).or_insert(0) += 1;
        let faults = self.config.faults;
        if self.rng.chance(faults.garbage_probability) {
            let len = 1 + self.rng.below(faults.max_garbage_len.max(1));
            for _ in 0..len {
                self.out.push(self.rng.next_u64() as u8);
            }
            self.garbage_bursts += 1;
        }
        let mut wire = frame.clone();
        if self.rng.chance(faults.bit_flip_probability) {
            let bit = self.rng.below(wire.len() * 8);
            if let Some(b) = wire.get_mut(bit / 8) {
                *b ^= 1 << (bit % 8);
            }
            self.bit_flips += 1;
        }
        self.out.extend_from_slice(&wire);
        self.sent.push(TxRecord {
            at_us: t,
            header,
            id,
            frame,
        });
    }
}
