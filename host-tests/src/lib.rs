//! Host-side harness of the project: the `gimbal` command-line tool (decode captures,
//! list messages) and, as integration tests, the native test suites.

pub mod tool;
