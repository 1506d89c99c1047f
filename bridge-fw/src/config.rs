//! The build-time configuration: `bridge-fw/bridge.toml` (or the file `BRIDGE_CONFIG`
//! names), read by `build.rs` into [`CONFIG`] and [`FC`].
//!
//! The FC protocol is fixed at build time ([`FcChoice::Fixed`]) when `fc` names one or
//! when a single `fc-*` feature is enabled; with several FC sides compiled in and
//! `fc = "auto"` it is read from three strap pins at start-up ([`FcChoice::Straps`],
//! [`from_straps`]); straps that select a side not compiled in are an error
//! ([`StrapError`]), never another side. [`BUILD`] says what this build is (version,
//! commit, flavour, FC sides: `build.rs`).

use bridge_engine::version::Version;
use bridge_engine::{BuildInfo, Config, FcProtocol};

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

/// The update key this build accepts images signed by, and the version it reports
/// (`build.rs`: `BRIDGE_UPDATE_KEY`, or the development key).
pub mod update {
    include!(concat!(env!("OUT_DIR"), "/update_key.rs"));
}

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
    #[cfg(feature = "fc-mavlink")]
    FcProtocol::Mavlink,
];

/// The straps select an FC side this image does not have: no FC side runs (the LED shows
/// the strap error code, [`crate::led::STRAP_ERROR`]), never another side.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct StrapError {
    /// The side the straps select.
    pub wanted: FcProtocol,
}

/// The protocol three strap pins select, each pulled up and either open or tied to GND:
///
/// | strap C | strap A | strap B | FC protocol |
/// | --- | --- | --- | --- |
/// | open | open | open | SIYI |
/// | open | GND | open | Viewlink |
/// | open | open | GND | GCU |
/// | open | GND | GND | K40T |
/// | GND | any | any | MAVLink |
///
/// (Strap C came with the fifth side: with it open, A and B select as before.)
///
/// # Errors
/// The side selected is not compiled in ([`COMPILED`]).
pub fn from_straps(
    a_grounded: bool,
    b_grounded: bool,
    c_grounded: bool,
) -> Result<FcProtocol, StrapError> {
    straps_select(a_grounded, b_grounded, c_grounded, COMPILED)
}

/// [`from_straps`] for an image with the FC sides `compiled`.
///
/// # Errors
/// The side selected is not in `compiled`.
pub fn straps_select(
    a_grounded: bool,
    b_grounded: bool,
    c_grounded: bool,
    compiled: &[FcProtocol],
) -> Result<FcProtocol, StrapError> {
    let wanted = match (c_grounded, a_grounded, b_grounded) {
        (true, _, _) => FcProtocol::Mavlink,
        (false, false, false) => FcProtocol::Siyi,
        (false, true, false) => FcProtocol::Viewlink,
        (false, false, true) => FcProtocol::Gcu,
        (false, true, true) => FcProtocol::K40t,
    };
    if compiled.contains(&wanted) {
        Ok(wanted)
    } else {
        Err(StrapError { wanted })
    }
}

/// [`CONFIG`] with its FC protocol resolved: `straps` is called (once) only for
/// [`FcChoice::Straps`] and returns (strap A grounded, strap B grounded, strap C grounded).
///
/// # Errors
/// The straps select a side not compiled in.
pub fn resolve(straps: impl FnOnce() -> (bool, bool, bool)) -> Result<Config, StrapError> {
    let mut c = CONFIG;
    c.fc = match FC {
        FcChoice::Fixed(p) => p,
        FcChoice::Straps => {
            let (a, b, strap_c) = straps();
            from_straps(a, b, strap_c)?
        }
    };
    Ok(c)
}
