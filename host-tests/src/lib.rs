//! Host-side harness of the project: the `gimbal` command-line tool (decode captures,
//! list messages, the bridge on Linux, the simulators on real ports), the simulated
//! peers of the bridge ([`sim`]) and, as integration tests, the native test suites.

pub mod cli;
pub mod demo;
pub mod emulated;
pub mod runner;
pub mod sim;
pub mod tool;
