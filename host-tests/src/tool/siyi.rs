//! `gimbal` adapter for the Siyi protocol (codec not implemented yet).

use super::{Item, Protocol, not_yet};

/// The Siyi protocol.
pub struct Siyi;

impl Protocol for Siyi {
    fn name(&self) -> &'static str {
        "siyi"
    }

    fn scan(&self, _capture: &[u8]) -> Vec<Item> {
        not_yet("siyi")
    }

    fn messages(&self) -> Vec<String> {
        Vec::new()
    }
}
