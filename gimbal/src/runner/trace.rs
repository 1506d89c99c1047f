//! `--trace`: the bytes of one direction of a link, cut into frames as they arrive and
//! printed as `frame` events, each decoded as `gimbal decode --json` prints it.

use std::sync::{Arc, Mutex};

use serde_json::{Map, Value, json};

use super::event_name::EventName;
use super::output::Output;
use super::port::Tap;
use crate::tool::{self, Item};

/// Bytes kept while waiting for the rest of a frame; beyond it they are printed as
/// they are (a length field that promises more than ever comes).
const MAX_PENDING: usize = 4096;

/// One direction of one link.
#[derive(Debug)]
pub struct Tracer {
    protocol: &'static str,
    port: &'static str,
    dir: &'static str,
    pending: Vec<u8>,
    /// Stream offset of `pending[0]`.
    offset: usize,
}

impl Tracer {
    /// The tracer of `port` (`fc`, `pod`) in direction `dir` (`rx`: to the bridge,
    /// `tx`: from the bridge), decoding with the codec called `protocol`.
    #[must_use]
    pub const fn new(protocol: &'static str, port: &'static str, dir: &'static str) -> Self {
        Tracer {
            protocol,
            port,
            dir,
            pending: Vec::new(),
            offset: 0,
        }
    }

    /// Takes `bytes` and returns the events of every item they complete (a frame cut
    /// off at the end waits for the rest).
    pub fn feed(&mut self, bytes: &[u8]) -> Vec<Map<String, Value>> {
        let Some(protocol) = tool::protocol(self.protocol) else {
            return Vec::new();
        };
        self.pending.extend_from_slice(bytes);
        let mut items = protocol.scan(&self.pending);
        // From the first frame cut off by the end of what arrived, everything waits for
        // more bytes (the scanner may see another frame start inside it).
        let cut = items
            .iter()
            .position(|i| matches!(i, Item::Truncated { .. }))
            .filter(|_| self.pending.len() <= MAX_PENDING);
        let keep_from = match cut.and_then(|at| items.get(at)) {
            Some(Item::Truncated { offset, .. }) => {
                let o = *offset;
                items.truncate(cut.unwrap_or(items.len()));
                o
            }
            _ => self.pending.len(),
        };
        let mut events = Vec::with_capacity(items.len());
        for item in &items {
            let decoded: Value = serde_json::from_str(&tool::render(protocol.as_ref(), item, true))
                .unwrap_or(Value::Null);
            let mut m = Map::new();
            m.insert("port".into(), json!(self.port));
            m.insert("dir".into(), json!(self.dir));
            if let Value::Object(d) = decoded {
                for (k, v) in d {
                    let v = if k == "offset" {
                        json!(v.as_u64().unwrap_or(0) + self.offset as u64)
                    } else {
                        v
                    };
                    m.insert(k, v);
                }
            }
            // The decoder's text without its capture offset (`@000123 `): the offset
            // in a stream is the JSON form's.
            let text = tool::render(protocol.as_ref(), item, false);
            let text = match text.split_once(' ') {
                Some((at, rest)) if at.starts_with('@') => rest.to_string(),
                _ => text,
            };
            let arrow = if self.dir == "rx" { "->" } else { "<-" };
            m.insert(
                "text".into(),
                json!(format!("{} {arrow} {text}", self.port)),
            );
            events.push(m);
        }
        self.pending.drain(..keep_from.min(self.pending.len()));
        self.offset += keep_from;
        events
    }
}

/// A tap that prints the frames of one direction as `frame` events on `out` (the
/// `text` field only in the human form).
#[must_use]
pub fn tap(out: &Output, protocol: &'static str, port: &'static str, dir: &'static str) -> Tap {
    let tracer = Mutex::new(Tracer::new(protocol, port, dir));
    let out = out.clone();
    Arc::new(move |bytes: &[u8]| {
        let events = match tracer.lock() {
            Ok(mut t) => t.feed(bytes),
            Err(_) => return,
        };
        for mut fields in events {
            if out.is_json() {
                fields.remove("text");
            }
            out.emit(EventName::Frame, Value::Object(fields));
        }
    })
}

/// A reader that shows what it reads to a tap.
pub struct TapRead<R> {
    /// The stream.
    pub inner: R,
    /// Sees every byte read (`None`: no tracing).
    pub tap: Option<Tap>,
}

/// A writer that shows what it writes to a tap.
pub struct TapWrite<W> {
    /// The stream.
    pub inner: W,
    /// Sees every byte written.
    pub tap: Option<Tap>,
}

impl<R: embedded_io_async::ErrorType> embedded_io_async::ErrorType for TapRead<R> {
    type Error = R::Error;
}

impl<W: embedded_io_async::ErrorType> embedded_io_async::ErrorType for TapWrite<W> {
    type Error = W::Error;
}

impl<R: embedded_io_async::Read> embedded_io_async::Read for TapRead<R> {
    async fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
        let n = self.inner.read(buf).await?;
        if let Some(t) = &self.tap {
            t(buf.get(..n).unwrap_or_default());
        }
        Ok(n)
    }
}

impl<W: embedded_io_async::Write> embedded_io_async::Write for TapWrite<W> {
    async fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
        let n = self.inner.write(buf).await?;
        if let Some(t) = &self.tap {
            t(buf.get(..n).unwrap_or_default());
        }
        Ok(n)
    }

    async fn flush(&mut self) -> Result<(), Self::Error> {
        self.inner.flush().await
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_split_across_reads_are_decoded_once_complete() {
        // The K40T 0x000304 zoom request of the decode tests.
        let frame = crate::tool::parse_hex("FD 03 04 01 07 02 01 04 03 00 00 2D 00 CE 89").unwrap();
        let mut t = Tracer::new("k40t", "pod", "tx");
        assert!(t.feed(&frame[..7]).is_empty(), "half a frame waits");
        let ev = t.feed(&frame[7..]);
        assert_eq!(ev.len(), 1, "{ev:?}");
        assert_eq!(ev[0]["port"], "pod");
        assert_eq!(ev[0]["dir"], "tx");
        assert_eq!(ev[0]["offset"], 0);
        // A SIYI frame whose sequence byte is the start byte, cut right after it.
        let siyi = crate::tool::parse_hex("55 66 01 00 00 55 01 15 de 10").unwrap();
        let mut s = Tracer::new("siyi", "fc", "rx");
        for cut in 1..siyi.len() {
            let mut s2 = Tracer::new("siyi", "fc", "rx");
            let mut ev = s2.feed(&siyi[..cut]);
            ev.extend(s2.feed(&siyi[cut..]));
            assert_eq!(ev.len(), 1, "cut at {cut}: {ev:?}");
            assert_eq!(ev[0]["raw"], "5566010000550115de10", "cut at {cut}");
        }
        assert_eq!(s.feed(&siyi).len(), 1);
        let second = t.feed(&frame);
        assert_eq!(second[0]["offset"], frame.len() as u64);
        assert_eq!(ev[0]["name"], "HybridZoom");
        let text = ev[0]["text"].as_str().unwrap();
        assert!(text.starts_with("pod <- 0x000304 HybridZoom "), "{text}");
        assert_eq!(ev[0]["msg_id"], 0x304);
        assert_eq!(second[0]["name"], ev[0]["name"]);
        assert_eq!(second[0]["raw"], ev[0]["raw"]);
    }
}
