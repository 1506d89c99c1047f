//! Fixed-size text fields.

use crate::wire::encoding::Field;
use crate::wire::{Reader, Writer};
use crate::{Error, Result};

wire_derive! {
    custom_serde [Eq, Hash]
    /// A fixed-size text field (K40T folder and file names, Viewlink firmware, model and
    /// serial strings): `N` bytes, not NUL-terminated, padded with 0x00 or spaces, empty
    /// when all bytes are 0x00 or spaces. Kept as the bytes received.
    pub struct Text<const N: usize> {
        /// The bytes as on the wire.
        pub raw: [u8; N],
    }
}

impl<const N: usize> Default for Text<N> {
    fn default() -> Self {
        Text { raw: [0; N] }
    }
}

impl<const N: usize> Text<N> {
    /// The text for `s`, padded with 0x00. More than `N` bytes, or a byte that is not
    /// printable ASCII, is [`Error::OutOfRange`].
    ///
    /// # Errors
    /// [`Error::OutOfRange`] when `s` is longer than `N` bytes or not printable ASCII.
    pub fn new(s: &str) -> Result<Self> {
        if s.len() > N || !s.bytes().all(|b| b.is_ascii_graphic() || b == b' ') {
            return Err(Error::OutOfRange);
        }
        let mut raw = [0; N];
        let dst = raw.get_mut(..s.len()).ok_or(Error::OutOfRange)?;
        crate::wire::copy(dst, s.as_bytes());
        Ok(Text { raw })
    }

    /// The text without trailing 0x00 and spaces; `None` if that is not UTF-8.
    #[must_use]
    pub fn as_str(&self) -> Option<&str> {
        let end = self
            .raw
            .iter()
            .rposition(|&b| b != 0 && b != b' ')
            .map_or(0, |i| i.saturating_add(1));
        core::str::from_utf8(self.raw.get(..end)?).ok()
    }

    /// True when the field is all 0x00 or spaces (the document's "NULL or empty").
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.raw.iter().all(|&b| b == 0 || b == b' ')
    }
}

#[cfg(feature = "serde")]
impl<const N: usize> serde::Serialize for Text<N> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> core::result::Result<S::Ok, S::Error> {
        match self.as_str() {
            Some(text) => s.serialize_str(text),
            None => s.collect_seq(self.raw.iter()),
        }
    }
}

impl<O, const N: usize> Field<O> for Text<N> {
    const LEN: usize = N;
    fn read(r: &mut Reader<'_>) -> Result<Self> {
        r.array().map(|raw| Text { raw })
    }
    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        w.put(&self.raw)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_fields() {
        let t = Text::<20>::new("flight 7").unwrap();
        assert_eq!(t.as_str(), Some("flight 7"));
        assert!(!t.is_empty());
        assert!(Text::<4>::new("abcde").is_err());
        assert!(Text::<4>::new("é").is_err());
        assert!(Text::<4>::new("   ").unwrap().is_empty());
        let spaces = Text::<4> { raw: *b"ab  " };
        assert_eq!(spaces.as_str(), Some("ab"));
        assert_eq!(Text::<10>::new("Z40K").unwrap().as_str(), Some("Z40K"));
        assert!(Text::<2>::new("abc").is_err());
    }
}
