//! A faulty cable: a seeded, reproducible fault model for one direction of a serial
//! link, usable between any two ports (the engine-level [`Line`](super::line::Line),
//! the task bench's [`Wire`](super::tasks::Wire), the Linux runner's ports).
//!
//! Each byte that enters a [`FaultStage`] is, independently:
//! - preceded by one random garbage byte with probability [`Faults::garbage_rate`]
//!   (noise on an idle line, a glitch read as a start bit);
//! - lost with probability [`Faults::drop_rate`] (an overrun, a framing error the
//!   receiving UART discards);
//! - otherwise passed with each of its 8 bits flipped with probability
//!   [`Faults::bit_error_rate`] (bit errors on the wire).
//!
//! The instants of the faults are drawn as geometric gaps between events from a
//! xorshift64* generator seeded with [`Faults::seed`], counted in bytes (and bits) of
//! the stream, not in calls: the output depends only on the bytes and the seed, not on
//! how they were cut into writes. Rates of 0 change nothing and draw nothing.
//!
//! On the command line a fault model is written `ber=1e-4,drop=1e-5,garbage=0,seed=3`
//! (any subset, in any order; `none` for no faults): [`Faults`] implements `FromStr` and
//! `Display` in that syntax.

use std::fmt;
use std::str::FromStr;

use super::XorShift;

/// Changes bytes as they go on a cable (garbage, bit flips), for fault scenarios:
/// `f(now_us, bytes) -> bytes passed`.
pub type Corrupter = dyn FnMut(u64, &[u8]) -> Vec<u8> + Send;

/// What a faulty cable does to the bytes of one direction ([`super::line::Line`] and
/// [`super::tasks::Wire`]): a scenario's own [`Corrupter`], then a seeded [`Faults`]
/// model; neither by default.
#[derive(Default)]
pub struct Damage {
    corrupt: Option<Box<Corrupter>>,
    faults: Option<FaultStage>,
}

impl fmt::Debug for Damage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Damage")
            .field("corrupter", &self.corrupt.is_some())
            .field("faults", &self.faults)
            .finish()
    }
}

impl Damage {
    /// Changes every write with `f(now_us, bytes) -> bytes passed`.
    pub fn set_corrupter(&mut self, f: Box<Corrupter>) {
        self.corrupt = Some(f);
    }

    /// Stops the corrupter.
    pub fn clear_corrupter(&mut self) {
        self.corrupt = None;
    }

    /// Applies `faults` from now on, after any corrupter (`None`, or a model whose rates
    /// are all 0: no fault model). The stage starts afresh from its seed.
    pub fn set_faults(&mut self, faults: Option<Faults>) {
        self.faults = faults.filter(|f| !f.is_none()).map(FaultStage::new);
    }

    /// What the fault model did so far (`None`: no model set).
    #[must_use]
    pub fn fault_stats(&self) -> Option<FaultStats> {
        self.faults.as_ref().map(FaultStage::stats)
    }

    /// What goes on for `bytes` written at `now_us`.
    pub fn apply(&mut self, now_us: u64, bytes: &[u8]) -> Vec<u8> {
        let mut out = match self.corrupt.as_mut() {
            Some(f) => f(now_us, bytes),
            None => bytes.to_vec(),
        };
        if let Some(stage) = self.faults.as_mut() {
            out = stage.apply(&out);
        }
        out
    }
}

/// The fault model of one direction of a cable.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Faults {
    /// Probability that a bit is flipped (per bit of every byte that is not dropped).
    pub bit_error_rate: f64,
    /// Probability that a byte is lost (per byte).
    pub drop_rate: f64,
    /// Probability that a random byte is inserted before a byte (per byte).
    pub garbage_rate: f64,
    /// Seed of the generator (0 is replaced by a fixed non-zero value).
    pub seed: u64,
}

impl Faults {
    /// No faults.
    pub const NONE: Faults = Faults {
        bit_error_rate: 0.0,
        drop_rate: 0.0,
        garbage_rate: 0.0,
        seed: 1,
    };

    /// Bit errors only.
    #[must_use]
    pub const fn bit_errors(bit_error_rate: f64, seed: u64) -> Self {
        Faults {
            bit_error_rate,
            seed,
            ..Faults::NONE
        }
    }

    /// True when every rate is 0 (the stage passes bytes unchanged).
    #[must_use]
    pub fn is_none(&self) -> bool {
        self.bit_error_rate <= 0.0 && self.drop_rate <= 0.0 && self.garbage_rate <= 0.0
    }

    /// The same rates with a seed derived from this one for direction or port `index`,
    /// so that the two directions of a cable (or several cables) configured with one
    /// seed draw different faults.
    #[must_use]
    pub fn derived(&self, index: u64) -> Self {
        // splitmix64 of the seed and the index.
        let mut z = self
            .seed
            .wrapping_add(index.wrapping_add(1).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        Faults {
            seed: z ^ (z >> 31),
            ..*self
        }
    }

    /// A stage applying this model.
    #[must_use]
    pub fn stage(&self) -> FaultStage {
        FaultStage::new(*self)
    }

    /// This model as a [`Corrupter`] (for [`Damage::set_corrupter`]).
    #[must_use]
    pub fn corrupter(&self) -> Box<Corrupter> {
        let mut stage = self.stage();
        Box::new(move |_, bytes: &[u8]| stage.apply(bytes))
    }
}

impl Default for Faults {
    fn default() -> Self {
        Faults::NONE
    }
}

impl fmt::Display for Faults {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_none() {
            return f.write_str("none");
        }
        // The rates that are not 0, then the seed.
        for (key, rate) in [
            ("ber", self.bit_error_rate),
            ("drop", self.drop_rate),
            ("garbage", self.garbage_rate),
        ] {
            if rate > 0.0 {
                write!(f, "{key}={rate:e},")?;
            }
        }
        write!(f, "seed={}", self.seed)
    }
}

/// The command-line syntax, for error messages.
pub const FAULTS_SYNTAX: &str = "`ber=RATE,drop=RATE,garbage=RATE,seed=N` (any subset; rates \
are probabilities 0..=1: ber per bit, drop and garbage per byte), or `none`";

impl FromStr for Faults {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let mut f = Faults::NONE;
        if s.eq_ignore_ascii_case("none") || s.eq_ignore_ascii_case("off") {
            return Ok(f);
        }
        for part in s.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let (key, value) = part.split_once('=').ok_or_else(|| {
                format!("`{s}`: `{part}` is not KEY=VALUE; expected {FAULTS_SYNTAX}")
            })?;
            let rate = || -> Result<f64, String> {
                value
                    .parse::<f64>()
                    .ok()
                    .filter(|r| (0.0..=1.0).contains(r))
                    .ok_or_else(|| format!("`{s}`: {key}={value} is not a probability 0..=1"))
            };
            match key.trim().to_ascii_lowercase().as_str() {
                "ber" | "bit_error_rate" => f.bit_error_rate = rate()?,
                "drop" | "drop_rate" => f.drop_rate = rate()?,
                "garbage" | "garbage_rate" => f.garbage_rate = rate()?,
                "seed" => {
                    f.seed = value
                        .parse()
                        .map_err(|_| format!("`{s}`: seed={value} is not an unsigned integer"))?;
                }
                other => {
                    return Err(format!(
                        "`{s}`: unknown key `{other}`; expected {FAULTS_SYNTAX}"
                    ));
                }
            }
        }
        Ok(f)
    }
}

/// What a [`FaultStage`] did so far.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FaultStats {
    /// Bytes that entered.
    pub bytes_in: u64,
    /// Bytes that left (passed, possibly with flipped bits, plus garbage).
    pub bytes_out: u64,
    /// Bits flipped.
    pub bits_flipped: u64,
    /// Bytes with at least one flipped bit.
    pub bytes_corrupted: u64,
    /// Bytes lost.
    pub bytes_dropped: u64,
    /// Garbage bytes inserted.
    pub garbage_bytes: u64,
}

/// One direction of a faulty cable: applies a [`Faults`] model to a byte stream.
#[derive(Debug, Clone)]
pub struct FaultStage {
    faults: Faults,
    rng: XorShift,
    /// Bits (of bytes that enter) before the next bit error: 0 = the next bit.
    bits_to_flip: u64,
    /// Bytes before the next drop.
    bytes_to_drop: u64,
    /// Bytes before the next garbage insertion.
    bytes_to_garbage: u64,
    stats: FaultStats,
}

/// Failures before the first success of a Bernoulli(p) process: the gap to the next
/// event (`u64::MAX`: never).
fn geometric(rng: &mut XorShift, p: f64) -> u64 {
    if p <= 0.0 || p.is_nan() {
        return u64::MAX;
    }
    if p >= 1.0 {
        return 0;
    }
    // U uniform in (0, 1].
    let u = ((rng.next_u64() >> 11) as f64 + 1.0) / ((1u64 << 53) as f64);
    let gap = (u.ln() / (-p).ln_1p()).floor();
    if gap >= u64::MAX as f64 {
        u64::MAX
    } else {
        gap as u64
    }
}

impl FaultStage {
    /// A stage at the start of its stream.
    #[must_use]
    pub fn new(faults: Faults) -> Self {
        let mut rng = XorShift::new(faults.seed);
        let bits_to_flip = geometric(&mut rng, faults.bit_error_rate);
        let bytes_to_drop = geometric(&mut rng, faults.drop_rate);
        let bytes_to_garbage = geometric(&mut rng, faults.garbage_rate);
        FaultStage {
            faults,
            rng,
            bits_to_flip,
            bytes_to_drop,
            bytes_to_garbage,
            stats: FaultStats::default(),
        }
    }

    /// The model.
    #[must_use]
    pub fn faults(&self) -> Faults {
        self.faults
    }

    /// What it did so far.
    #[must_use]
    pub fn stats(&self) -> FaultStats {
        self.stats
    }

    /// The bytes that come out of the cable for `bytes` going in.
    pub fn apply(&mut self, bytes: &[u8]) -> Vec<u8> {
        if self.faults.is_none() {
            self.stats.bytes_in += bytes.len() as u64;
            self.stats.bytes_out += bytes.len() as u64;
            return bytes.to_vec();
        }
        let mut out = Vec::with_capacity(bytes.len() + 1);
        for &b in bytes {
            self.stats.bytes_in += 1;
            if self.bytes_to_garbage == 0 {
                out.push(self.rng.next_u64() as u8);
                self.stats.garbage_bytes += 1;
                self.bytes_to_garbage = geometric(&mut self.rng, self.faults.garbage_rate);
            } else {
                self.bytes_to_garbage -= 1;
            }
            let mut byte = b;
            let mut flipped = 0;
            while self.bits_to_flip < 8 {
                byte ^= 1 << self.bits_to_flip;
                flipped += 1;
                let gap = geometric(&mut self.rng, self.faults.bit_error_rate);
                self.bits_to_flip = self.bits_to_flip.saturating_add(1).saturating_add(gap);
            }
            self.bits_to_flip = self.bits_to_flip.saturating_sub(8);
            if self.bytes_to_drop == 0 {
                self.stats.bytes_dropped += 1;
                self.bytes_to_drop = geometric(&mut self.rng, self.faults.drop_rate);
                continue;
            }
            self.bytes_to_drop -= 1;
            if flipped > 0 {
                self.stats.bits_flipped += flipped;
                self.stats.bytes_corrupted += 1;
            }
            out.push(byte);
        }
        self.stats.bytes_out += out.len() as u64;
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Faults at these rates (bit errors, drops, garbage) and seed.
    fn faults(bit_error_rate: f64, drop_rate: f64, garbage_rate: f64, seed: u64) -> Faults {
        Faults {
            bit_error_rate,
            drop_rate,
            garbage_rate,
            seed,
        }
    }

    /// A long stream of varied bytes.
    fn stream(n: usize) -> Vec<u8> {
        (0..n).map(|i| (i * 7 + i / 251) as u8).collect()
    }

    #[test]
    fn zero_rates_change_nothing() {
        let data = stream(100_000);
        let mut s = Faults::NONE.stage();
        assert_eq!(s.apply(&data), data);
        let f = Faults {
            seed: 99,
            ..Faults::NONE
        };
        assert_eq!(f.stage().apply(&data), data);
        let stats = s.stats();
        assert_eq!((stats.bytes_in, stats.bytes_out), (100_000, 100_000));
        assert_eq!(
            (stats.bits_flipped, stats.bytes_dropped, stats.garbage_bytes),
            (0, 0, 0)
        );
    }

    #[test]
    fn measured_rates_are_close_to_the_configured_ones() {
        let data = stream(2_000_000);
        let f = faults(1e-3, 5e-4, 2e-4, 7);
        let mut s = f.stage();
        let out = s.apply(&data);
        let stats = s.stats();
        // Each count within 4 standard deviations of its expectation (binomial).
        let close = |count: u64, n: u64, p: f64| {
            let mean = n as f64 * p;
            (count as f64 - mean).abs() < 4.0 * (mean * (1.0 - p)).sqrt()
        };
        let bits = 8 * (stats.bytes_in - stats.bytes_dropped);
        assert!(close(stats.bits_flipped, bits, 1e-3), "{stats:?}");
        assert!(
            close(stats.bytes_dropped, stats.bytes_in, 5e-4),
            "{stats:?}"
        );
        assert!(
            close(stats.garbage_bytes, stats.bytes_in, 2e-4),
            "{stats:?}"
        );
        // About 16 000 bit errors: within 4 % of the rate.
        let ber = stats.bits_flipped as f64 / bits as f64;
        assert!((ber / 1e-3 - 1.0).abs() < 0.04, "ber {ber}");
        assert_eq!(
            out.len() as u64,
            stats.bytes_in - stats.bytes_dropped + stats.garbage_bytes
        );
        assert_eq!(out.len() as u64, stats.bytes_out);

        // The flipped bits are where the stream differs: with bit errors only, the
        // output aligns with the input.
        let mut s = Faults::bit_errors(1e-2, 3).stage();
        let out = s.apply(&data[..200_000]);
        let diff: u64 = out
            .iter()
            .zip(&data)
            .map(|(a, b)| u64::from((a ^ b).count_ones()))
            .sum();
        assert_eq!(diff, s.stats().bits_flipped);
        assert!(close(diff, 1_600_000, 1e-2), "{diff} bits flipped");
    }

    #[test]
    fn a_seed_reproduces_the_faults_whatever_the_chunks() {
        let data = stream(50_000);
        let f = faults(1e-3, 1e-3, 1e-3, 42);
        let whole = f.stage().apply(&data);
        let mut s = f.stage();
        let mut pieces = Vec::new();
        for chunk in data.chunks(13) {
            pieces.extend(s.apply(chunk));
        }
        assert_eq!(whole, pieces);
        assert_ne!(whole, data);
        let other = Faults { seed: 43, ..f }.stage().apply(&data);
        assert_ne!(whole, other, "another seed, other faults");
        assert_ne!(f.derived(0).seed, f.derived(1).seed);
        assert_eq!(f.derived(1), f.derived(1));
    }

    #[test]
    fn certain_faults() {
        let mut s = Faults {
            drop_rate: 1.0,
            ..Faults::NONE
        }
        .stage();
        assert!(s.apply(&[1, 2, 3]).is_empty());
        let mut s = Faults::bit_errors(1.0, 5).stage();
        assert_eq!(s.apply(&[0x00, 0xF0]), [0xFF, 0x0F]);
        let mut s = Faults {
            garbage_rate: 1.0,
            ..Faults::NONE
        }
        .stage();
        assert_eq!(s.apply(&[1, 2]).len(), 4);
    }

    #[test]
    fn the_command_line_syntax() {
        let f: Faults = "ber=1e-4,drop=1e-5,seed=3".parse().unwrap();
        assert_eq!(
            f,
            Faults {
                bit_error_rate: 1e-4,
                drop_rate: 1e-5,
                garbage_rate: 0.0,
                seed: 3
            }
        );
        assert_eq!(f.to_string(), "ber=1e-4,drop=1e-5,seed=3");
        assert_eq!(
            Faults {
                garbage_rate: 0.25,
                ..Faults::NONE
            }
            .to_string(),
            "garbage=2.5e-1,seed=1"
        );
        assert_eq!(f.to_string().parse::<Faults>(), Ok(f));
        assert_eq!("none".parse::<Faults>(), Ok(Faults::NONE));
        assert_eq!(Faults::NONE.to_string(), "none");
        assert_eq!(
            " garbage=0.5 , ber=0 "
                .parse::<Faults>()
                .map(|f| f.garbage_rate),
            Ok(0.5)
        );
        for bad in ["ber", "ber=2", "ber=-1", "drop=x", "seed=-1", "noise=1"] {
            let e = bad.parse::<Faults>().unwrap_err();
            assert!(e.contains(&format!("`{bad}`")), "{bad}: {e}");
        }
    }
}
