//! `gimbal` adapter for the Gcu protocol (codec not implemented yet).

use super::{Item, Protocol, not_yet};

/// The Gcu protocol.
pub struct Gcu;

impl Protocol for Gcu {
    fn name(&self) -> &'static str {
        "gcu"
    }

    fn scan(&self, _capture: &[u8]) -> Vec<Item> {
        not_yet("gcu")
    }

    fn messages(&self) -> Vec<String> {
        Vec::new()
    }
}
