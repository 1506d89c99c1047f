//! The `gimbal` tool as a library: its command line ([`cli`]), the bridge and the
//! simulators on real ports ([`runner`]), the demo ([`demo`]), the simulated flight
//! controllers, pod and cables ([`sim`]) and the capture decoder ([`tool`]). The binary
//! (`src/main.rs`) only dispatches; `host-tests` uses the simulators in its scenarios.

pub mod cli;
pub mod demo;
pub mod runner;
pub mod sim;
pub mod tool;
