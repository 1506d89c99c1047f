//! `gimbal` adapter for the Viewlink protocol (codec not implemented yet).

use super::{Item, Protocol, not_yet};

/// The Viewlink protocol.
pub struct Viewlink;

impl Protocol for Viewlink {
    fn name(&self) -> &'static str {
        "viewlink"
    }

    fn scan(&self, _capture: &[u8]) -> Vec<Item> {
        not_yet("viewlink")
    }

    fn messages(&self) -> Vec<String> {
        Vec::new()
    }
}
