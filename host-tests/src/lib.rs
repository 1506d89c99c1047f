//! Host-side harness of the project: the `gimbal` command-line tool (decode captures,
//! list messages), the simulated peers of the bridge ([`sim`]) and, as integration
//! tests, the native test suites.

pub mod demo;
pub mod sim;
pub mod tool;
