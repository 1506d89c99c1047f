//! The project's test harness beyond the test files: the emulated-board driver
//! ([`emulated`], run by the `qemu-e2e` binary). The simulators it drives are the `gimbal`
//! tool's ([`gimbal::sim`]).

pub mod emulated;
