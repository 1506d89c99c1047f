//! Codec test cases shared by two runners: natively (`host-tests/tests/cases.rs`, one
//! libtest test per case) and as Cortex-M code on `thumbv7m-none-eabi` under QEMU
//! (`host-tests/qemu-cases`). `no_std`, no allocation: a case is a plain function that returns
//! `Err(Failure)` at its first failed check.
//!
//! Each protocol owns one module with a `CASES` table; [`all`] chains them.
#![no_std]
// A failure carries its message inline (no allocator on Cortex-M); it is the cold path.
#![allow(clippy::result_large_err)]

use core::fmt::Write as _;

/// Where and why a case failed.
#[derive(Debug, Clone)]
pub struct Failure {
    /// Source file of the failed check.
    pub file: &'static str,
    /// Line of the failed check.
    pub line: u32,
    /// The check, as written.
    pub check: &'static str,
    /// Values involved (truncated to fit).
    pub detail: heapless::String<192>,
}

impl Failure {
    /// A failure with a formatted detail (truncated if it does not fit).
    pub fn new(
        file: &'static str,
        line: u32,
        check: &'static str,
        detail: core::fmt::Arguments<'_>,
    ) -> Self {
        let mut f = Failure {
            file,
            line,
            check,
            detail: heapless::String::new(),
        };
        let mut w = Truncating(&mut f.detail);
        let _ = w.write_fmt(detail);
        f
    }
}

impl core::fmt::Display for Failure {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "{}:{}: {}", self.file, self.line, self.check)?;
        if !self.detail.is_empty() {
            write!(f, " ({})", self.detail)?;
        }
        Ok(())
    }
}

struct Truncating<'a, const N: usize>(&'a mut heapless::String<N>);

impl<const N: usize> core::fmt::Write for Truncating<'_, N> {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        for c in s.chars() {
            if self.0.push(c).is_err() {
                break;
            }
        }
        Ok(())
    }
}

/// The result of a case.
pub type Outcome = Result<(), Failure>;

/// A named test case.
#[derive(Clone, Copy)]
pub struct Case {
    /// `protocol::case_name`.
    pub name: &'static str,
    /// Runs the case.
    pub run: fn() -> Outcome,
}

/// Fails the case unless the condition holds.
#[macro_export]
macro_rules! ensure {
    ($cond:expr) => {
        if !$cond {
            return Err($crate::Failure::new(file!(), line!(), stringify!($cond), format_args!("")));
        }
    };
    ($cond:expr, $($fmt:tt)+) => {
        if !$cond {
            return Err($crate::Failure::new(file!(), line!(), stringify!($cond), format_args!($($fmt)+)));
        }
    };
}

/// Fails the case unless the two values are equal; reports both.
#[macro_export]
macro_rules! ensure_eq {
    ($left:expr, $right:expr $(,)?) => {
        match (&$left, &$right) {
            (l, r) => {
                if l != r {
                    return Err($crate::Failure::new(
                        file!(),
                        line!(),
                        concat!(stringify!($left), " == ", stringify!($right)),
                        format_args!("{:?} != {:?}", l, r),
                    ));
                }
            }
        }
    };
}

/// Unwraps a `Result` (or `Option`), failing the case with the error otherwise.
#[macro_export]
macro_rules! check {
    ($e:expr) => {
        match $crate::IntoResult::into_result($e) {
            Ok(v) => v,
            Err(e) => {
                return Err($crate::Failure::new(
                    file!(),
                    line!(),
                    stringify!($e),
                    format_args!("{:?}", e),
                ));
            }
        }
    };
}

/// `Result` and `Option` for [`check!`].
pub trait IntoResult<T> {
    /// The error type.
    type Err: core::fmt::Debug;
    /// As a `Result`.
    fn into_result(self) -> Result<T, Self::Err>;
}

impl<T, E: core::fmt::Debug> IntoResult<T> for Result<T, E> {
    type Err = E;
    fn into_result(self) -> Result<T, E> {
        self
    }
}

impl<T> IntoResult<T> for Option<T> {
    type Err = &'static str;
    fn into_result(self) -> Result<T, &'static str> {
        self.ok_or("None")
    }
}

/// Declares a `CASES` table from case functions.
#[macro_export]
macro_rules! cases {
    ($prefix:literal: $($f:ident),* $(,)?) => {
        /// The cases of this module.
        pub static CASES: &[$crate::Case] = &[
            $( $crate::Case { name: concat!($prefix, "::", stringify!($f)), run: $f }, )*
        ];
    };
}

/// One frame of `fixtures/seed_vectors.json`.
#[derive(Debug, Clone, Copy)]
pub struct Vector {
    /// `"GCU"`, `"Viewlink"` or `"SIYI"`.
    pub protocol: &'static str,
    /// What the document says the frame does.
    pub name: &'static str,
    /// The frame to use (corrected where the document misprinted it).
    pub bytes: &'static [u8],
    /// True when the checksum recomputes to the printed one.
    pub verified: bool,
    /// The frame as printed, when it differs and is clean hex.
    pub doc_bytes: Option<&'static [u8]>,
    /// The frame the document's table describes, where the printed one has an erratum.
    pub alt_semantic: Option<&'static [u8]>,
}

include!(concat!(env!("OUT_DIR"), "/vectors.rs"));

/// The vectors of one protocol.
pub fn vectors(protocol: &'static str) -> impl Iterator<Item = &'static Vector> {
    VECTORS.iter().filter(move |v| v.protocol == protocol)
}

pub mod gcu;
pub mod k40t;
pub mod oracle;
pub mod siyi;
pub mod viewlink;
pub mod wire;

/// Every case, protocol by protocol.
pub fn all() -> impl Iterator<Item = &'static Case> {
    wire::CASES
        .iter()
        .chain(k40t::CASES)
        .chain(siyi::CASES)
        .chain(viewlink::CASES)
        .chain(gcu::CASES)
}
