//! The `gimbal` tool as a library: its command line ([`cli`]), the bridge and the
//! simulators on real ports ([`runner`]), the demo ([`demo`]), the simulated flight
//! controllers, pod and cables ([`sim`]), the capture decoder ([`tool`]) and a log's
//! report page ([`report`]). The binary
//! (`src/main.rs`) only dispatches; `host-tests` uses the simulators in its scenarios.

pub mod cli;
pub mod client_port;
pub mod console_client;
pub mod demo;
pub mod report;
pub mod runner;
pub mod sim;
pub mod tool;
pub mod update;
