//! The project's test suites are this crate's tests (`tests/`): engine and task
//! scenarios, codec properties and cases, fuzz replays, the demo. The library holds
//! nothing; the emulated-board driver is the `emulated-board` crate beside it.
