//! A setting's value as text: TOML's forms, the configuration file's, so that what the
//! console's `get` writes is a configuration file (`gimbal bridge --config`, `gimbal config
//! load`) and what `set` takes is what the file says.
//!
//! - a bare word: `57600`, `-480`, `0x00030D`, `true`, `require`, `rtsp://10.0.0.9/live`
//!   (up to a space or `#`);
//! - a quoted text: `"K40T BRIDGE"` (TOML's basic string; `\"` and `\\` are its only
//!   escapes here: the settings' texts are printable ASCII);
//! - a list of whole numbers: `[255, 245]`, `[0x00030D]`, `[]`.
//!
//! A `#` after the value starts a comment. Parsing never panics and says what was wrong
//! ([`ValueError`]).

use core::fmt;

/// Longest text a setting takes (the video address, MAVLink's `uri`).
pub const MAX_TEXT: usize = crate::config::URI_LEN;
/// Most numbers in a list (`gcs_ids` takes 8, `k40t_allow` 11).
pub const MAX_LIST: usize = 16;

/// A list of whole numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Ints {
    items: [i64; MAX_LIST],
    len: u8,
}

impl Ints {
    /// An empty list.
    pub const EMPTY: Self = Self {
        items: [0; MAX_LIST],
        len: 0,
    };

    /// The numbers.
    #[must_use]
    pub fn as_slice(&self) -> &[i64] {
        self.items.get(..usize::from(self.len)).unwrap_or(&[])
    }

    fn push(&mut self, v: i64) -> Result<(), ValueError> {
        let slot = self
            .items
            .get_mut(usize::from(self.len))
            .ok_or(ValueError::TooMany)?;
        *slot = v;
        self.len = self.len.saturating_add(1);
        Ok(())
    }
}

/// A value as written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Value<'a> {
    /// A bare word (a number, `true`, a name, an address).
    Word(&'a str),
    /// A quoted text, its escapes resolved.
    Quoted(&'a str),
    /// A list of whole numbers.
    List(Ints),
}

impl Value<'_> {
    /// The text of a word or a quoted text (`None` for a list).
    #[must_use]
    pub fn text(&self) -> Option<&str> {
        match self {
            Value::Word(t) | Value::Quoted(t) => Some(t),
            Value::List(_) => None,
        }
    }
}

/// What is wrong with a value's text.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ValueError {
    /// No value.
    Missing,
    /// A quoted text without its closing quote.
    Unterminated,
    /// An escape other than `\"` and `\\`.
    Escape,
    /// A text longer than [`MAX_TEXT`].
    TooLong,
    /// A list that is not whole numbers between `[` and `]`, separated by commas.
    List,
    /// A list of more than [`MAX_LIST`] numbers.
    TooMany,
    /// Something after the value (other than a `#` comment).
    Trailing,
}

impl fmt::Display for ValueError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ValueError::Missing => "no value",
            ValueError::Unterminated => "a quoted text without its closing quote",
            ValueError::Escape => "only \\\" and \\\\ may be escaped",
            ValueError::TooLong => "a text longer than 160 characters",
            ValueError::List => "a list is whole numbers between [ and ], separated by commas",
            ValueError::TooMany => "a list of more than 16 numbers",
            ValueError::Trailing => "something after the value (a comment starts with #)",
        })
    }
}

/// The value at the start of `text` (spaces around it and a `#` comment after it
/// allowed). A quoted text with escapes is resolved into `scratch`.
///
/// # Errors
/// What is wrong with it.
pub fn parse<'a>(text: &'a str, scratch: &'a mut [u8; MAX_TEXT]) -> Result<Value<'a>, ValueError> {
    let text = text.trim_start();
    let (value, rest) = if let Some(quoted) = text.strip_prefix('"') {
        quoted_text(quoted, scratch)?
    } else if let Some(list) = text.strip_prefix('[') {
        let end = list.find(is_close_bracket).ok_or(ValueError::List)?;
        let (inside, rest) = list.split_at_checked(end).ok_or(ValueError::List)?;
        (Value::List(ints(inside)?), rest.get(1..).unwrap_or(""))
    } else {
        let end = text
            .find(|c: char| c.is_ascii_whitespace() || c == '#')
            .unwrap_or(text.len());
        let (word, rest) = text.split_at_checked(end).ok_or(ValueError::Missing)?;
        if word.is_empty() {
            return Err(ValueError::Missing);
        }
        (Value::Word(word), rest)
    };
    let rest = rest.trim_start();
    if rest.is_empty() || rest.starts_with('#') {
        Ok(value)
    } else {
        Err(ValueError::Trailing)
    }
}

/// A quoted text's contents (after the opening quote) and what follows its closing quote.
fn quoted_text<'a>(
    text: &'a str,
    scratch: &'a mut [u8; MAX_TEXT],
) -> Result<(Value<'a>, &'a str), ValueError> {
    let bytes = text.as_bytes();
    let end = bytes
        .iter()
        .enumerate()
        .scan(false, |escaped, (i, &b)| {
            let at_end = !*escaped && b == b'"';
            *escaped = !*escaped && b == b'\\';
            Some((i, at_end))
        })
        .find(|(_, at_end)| *at_end)
        .map(|(i, _)| i)
        .ok_or(ValueError::Unterminated)?;
    let (inside, rest) = text.split_at_checked(end).ok_or(ValueError::Unterminated)?;
    let rest = rest.get(1..).unwrap_or("");
    if !inside.contains('\\') {
        if inside.len() > MAX_TEXT {
            return Err(ValueError::TooLong);
        }
        return Ok((Value::Quoted(inside), rest));
    }
    let mut n = 0usize;
    let mut escaped = false;
    for b in inside.bytes() {
        if !escaped && b == b'\\' {
            escaped = true;
            continue;
        }
        if escaped && b != b'"' && b != b'\\' {
            return Err(ValueError::Escape);
        }
        escaped = false;
        *scratch.get_mut(n).ok_or(ValueError::TooLong)? = b;
        n = n.saturating_add(1);
    }
    let resolved = scratch.get(..n).unwrap_or_default();
    // Only ASCII bytes were taken apart (a backslash, a quote): the rest is as it came.
    let resolved = core::str::from_utf8(resolved).map_err(|_| ValueError::Escape)?;
    Ok((Value::Quoted(resolved), rest))
}

// The delimiters as predicates, not `char` patterns, and splits checked: core's one-char
// searcher and `str::split_at` keep a panicking branch the optimiser cannot remove
// (scripts/no-panic finds it).

/// A space, the console's separator.
pub(crate) fn is_space(c: char) -> bool {
    c == ' '
}

fn is_comma(c: char) -> bool {
    c == ','
}

fn is_close_bracket(c: char) -> bool {
    c == ']'
}

/// Whole numbers separated by commas (a trailing comma allowed, as in TOML).
fn ints(inside: &str) -> Result<Ints, ValueError> {
    let mut out = Ints::EMPTY;
    let mut items = inside.split(is_comma).map(str::trim).peekable();
    while let Some(item) = items.next() {
        if item.is_empty() {
            // `[]`, or the end after a trailing comma.
            if items.peek().is_none() {
                break;
            }
            return Err(ValueError::List);
        }
        out.push(int(item).ok_or(ValueError::List)?)?;
    }
    Ok(out)
}

/// A whole number as TOML writes one: decimal with an optional sign, or `0x` hexadecimal;
/// `_` between digits.
#[must_use]
pub fn int(text: &str) -> Option<i64> {
    let (negative, digits) = match text.as_bytes().first() {
        Some(b'-') => (true, text.get(1..)?),
        Some(b'+') => (false, text.get(1..)?),
        _ => (false, text),
    };
    let (radix, digits) = match digits
        .strip_prefix("0x")
        .or_else(|| digits.strip_prefix("0X"))
    {
        Some(hex) => (16, hex),
        None => (10, digits),
    };
    if digits.is_empty() || digits.starts_with('_') || digits.ends_with('_') {
        return None;
    }
    let mut v: i64 = 0;
    for c in digits.chars().filter(|c| *c != '_') {
        let d = c.to_digit(radix)?;
        v = v.checked_mul(i64::from(radix))?.checked_add(i64::from(d))?;
    }
    if negative { v.checked_neg() } else { Some(v) }
}

/// Writes `text` as a TOML basic string.
///
/// # Errors
/// The writer's.
pub fn write_quoted(out: &mut impl fmt::Write, text: &[u8]) -> fmt::Result {
    out.write_char('"')?;
    for &b in text {
        if b == b'"' || b == b'\\' {
            out.write_char('\\')?;
        }
        out.write_char(char::from(b))?;
    }
    out.write_char('"')
}

#[cfg(test)]
mod tests {
    use super::*;

    extern crate std;
    use std::string::String;

    fn value(text: &str) -> Result<std::string::String, ValueError> {
        let mut scratch = [0u8; MAX_TEXT];
        parse(text, &mut scratch).map(|v| std::format!("{v:?}"))
    }

    #[test]
    fn words_quoted_texts_and_lists() {
        assert_eq!(value(" 57600 ").unwrap(), "Word(\"57600\")");
        assert_eq!(value("require # why").unwrap(), "Word(\"require\")");
        assert_eq!(value("\"K40T BRIDGE\"").unwrap(), "Quoted(\"K40T BRIDGE\")");
        assert_eq!(value(r#""a\"b\\c""#).unwrap(), "Quoted(\"a\\\"b\\\\c\")");
        assert_eq!(value("\"\"").unwrap(), "Quoted(\"\")");
        let mut scratch = [0u8; MAX_TEXT];
        let Ok(Value::List(l)) = parse("[255, 0x00030D, -1,]", &mut scratch) else {
            panic!("a list");
        };
        assert_eq!(l.as_slice(), &[255, 0x30D, -1]);
        let Ok(Value::List(l)) = parse("[ ]", &mut scratch) else {
            panic!("an empty list");
        };
        assert!(l.as_slice().is_empty());
    }

    #[test]
    fn bad_values_say_what_is_wrong() {
        for (text, e) in [
            ("", ValueError::Missing),
            ("  # only a comment", ValueError::Missing),
            ("\"open", ValueError::Unterminated),
            ("\"a\\nb\"", ValueError::Escape),
            ("[1, x]", ValueError::List),
            ("[1,, 2]", ValueError::List),
            ("[1, 2", ValueError::List),
            ("1 2", ValueError::Trailing),
            ("\"a\" b", ValueError::Trailing),
        ] {
            assert_eq!(value(text), Err(e), "{text:?}");
        }
        let long = std::format!("\"{}\"", "x".repeat(161));
        assert_eq!(value(&long), Err(ValueError::TooLong));
        let long = std::format!("\"{}\\\\\"", "x".repeat(160));
        assert_eq!(value(&long), Err(ValueError::TooLong));
        let many = std::format!("[{}]", "1,".repeat(17));
        assert_eq!(value(&many), Err(ValueError::TooMany));
    }

    #[test]
    fn integers_as_toml_writes_them() {
        assert_eq!(int("4_000_000"), Some(4_000_000));
        assert_eq!(int("-1440"), Some(-1440));
        assert_eq!(int("0x00030D"), Some(0x30D));
        assert_eq!(int("+7"), Some(7));
        for bad in [
            "",
            "-",
            "0x",
            "1_",
            "_1",
            "12a",
            "99999999999999999999",
            "7A0000000001",
        ] {
            assert_eq!(int(bad), None, "{bad:?}");
        }
        assert_eq!(
            int("-9223372036854775808"),
            None,
            "beyond i64 before its sign"
        );
    }

    #[test]
    fn quoted_texts_round_trip() {
        for text in ["rtsp://10.0.0.9:558/live", "a\"b", "back\\slash", ""] {
            let mut s = String::new();
            write_quoted(&mut s, text.as_bytes()).unwrap();
            let mut scratch = [0u8; MAX_TEXT];
            assert_eq!(parse(&s, &mut scratch), Ok(Value::Quoted(text)), "{s}");
        }
    }
}
