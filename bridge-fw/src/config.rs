//! The build-time configuration: `bridge-fw/bridge.toml` (or the file `BRIDGE_CONFIG`
//! names), read by `build.rs` into [`CONFIG`] and [`FC`].
//!
//! The FC protocol is fixed at build time ([`FcChoice::Fixed`]) when `fc` names one or
//! when a single `fc-*` feature is enabled; with several FC sides compiled in and
//! `fc = "auto"` it is read from two strap pins at start-up ([`FcChoice::Straps`],
//! [`from_straps`]).

use protocol_core::bridge::{Config, FcProtocol};

/// How the firmware picks its FC protocol.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FcChoice {
    /// Chosen at build time.
    Fixed(FcProtocol),
    /// Read from the strap pins at start-up.
    Straps,
}

include!(concat!(env!("OUT_DIR"), "/bridge_config.rs"));

/// The FC sides compiled into this build (features `fc-*`).
pub const COMPILED: &[FcProtocol] = &[
    #[cfg(feature = "fc-siyi")]
    FcProtocol::Siyi,
    #[cfg(feature = "fc-viewlink")]
    FcProtocol::Viewlink,
    #[cfg(feature = "fc-gcu")]
    FcProtocol::Gcu,
    #[cfg(feature = "fc-k40t")]
    FcProtocol::K40t,
];

/// The protocol two strap pins select, each pulled up and either open or tied to GND:
///
/// | strap A | strap B | FC protocol |
/// | --- | --- | --- |
/// | open | open | SIYI |
/// | GND | open | Viewlink |
/// | open | GND | GCU |
/// | GND | GND | K40T |
///
/// A protocol not compiled in gives the first one compiled in (`None` only when none is).
#[must_use]
pub fn from_straps(a_grounded: bool, b_grounded: bool) -> Option<FcProtocol> {
    let wanted = match (a_grounded, b_grounded) {
        (false, false) => FcProtocol::Siyi,
        (true, false) => FcProtocol::Viewlink,
        (false, true) => FcProtocol::Gcu,
        (true, true) => FcProtocol::K40t,
    };
    if COMPILED.contains(&wanted) {
        Some(wanted)
    } else {
        COMPILED.first().copied()
    }
}

/// [`CONFIG`] with its FC protocol resolved: `straps` is called (once) only for
/// [`FcChoice::Straps`] and returns (strap A grounded, strap B grounded).
pub fn resolve(straps: impl FnOnce() -> (bool, bool)) -> Config {
    let mut c = CONFIG;
    c.fc = match FC {
        FcChoice::Fixed(p) => p,
        FcChoice::Straps => {
            let (a, b) = straps();
            from_straps(a, b).unwrap_or(c.fc)
        }
    };
    c
}
