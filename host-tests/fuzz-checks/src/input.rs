//! Reading a fuzzer's bytes as parameters: a cursor that never fails (it yields zeros
//! past the end), and the chunk plan the deframer targets feed their stream with.

/// A cursor over the fuzzer's input.
#[derive(Debug, Clone, Copy)]
pub struct Input<'a> {
    data: &'a [u8],
}

impl<'a> Input<'a> {
    /// A cursor at the start of `data`.
    #[must_use]
    pub fn new(data: &'a [u8]) -> Self {
        Input { data }
    }

    /// The next byte (0 once the input is exhausted).
    pub fn byte(&mut self) -> u8 {
        match self.data.split_first() {
            Some((&b, rest)) => {
                self.data = rest;
                b
            }
            None => 0,
        }
    }

    /// The next `n` bytes (fewer at the end of the input).
    pub fn bytes(&mut self, n: usize) -> &'a [u8] {
        let (head, rest) = self.data.split_at(n.min(self.data.len()));
        self.data = rest;
        head
    }

    /// The bytes not read yet.
    #[must_use]
    pub fn rest(self) -> &'a [u8] {
        self.data
    }
}

/// How a stream is cut into the pieces a UART driver would deliver.
///
/// Encoded in front of the stream: one byte `c` (bits 0..2: the plan has `(c & 7) + 1`
/// chunk bytes; bits 3..7: a selector the target uses, e.g. the framing variant), then
/// the chunk bytes. A chunk byte `b` is a piece of `b + 1` bytes; the plan repeats.
/// In the driver-style run, `b == 0` also marks the line idle after that piece and
/// `b == 0xFF` clears the deframer.
#[derive(Debug, Clone)]
pub struct Plan {
    sizes: Vec<u8>,
}

/// One piece of a planned stream.
#[derive(Debug, Clone, Copy)]
pub struct Piece<'s> {
    /// The bytes.
    pub bytes: &'s [u8],
    /// The line goes idle after this piece.
    pub idle: bool,
    /// The deframer is cleared after this piece.
    pub clear: bool,
}

impl Plan {
    /// Reads a plan from the front of `input`; returns the selector bits (0..32) too.
    pub fn read(input: &mut Input<'_>) -> (u8, Plan) {
        let c = input.byte();
        let n = usize::from(c & 7) + 1;
        let sizes = input.bytes(n).to_vec();
        (c >> 3, Plan { sizes })
    }

    /// The encoding of a plan with these chunk bytes (at most 8) and selector (0..32),
    /// for seeds.
    #[must_use]
    pub fn encode(selector: u8, sizes: &[u8]) -> Vec<u8> {
        let n = sizes.len().clamp(1, 8);
        let mut out = vec![(selector << 3) | u8::try_from(n - 1).unwrap_or(0)];
        out.extend((0..n).map(|i| sizes.get(i).copied().unwrap_or(63)));
        out
    }

    /// The pieces of `stream` under this plan.
    pub fn pieces<'s>(&'s self, mut stream: &'s [u8]) -> impl Iterator<Item = Piece<'s>> + 's {
        let mut sizes = self.sizes.iter().copied().cycle();
        std::iter::from_fn(move || {
            if stream.is_empty() {
                return None;
            }
            let b = sizes.next().unwrap_or(63);
            let (bytes, rest) = stream.split_at((usize::from(b) + 1).min(stream.len()));
            stream = rest;
            Some(Piece {
                bytes,
                idle: b == 0,
                clear: b == 0xFF,
            })
        })
    }
}
