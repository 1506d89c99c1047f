//! The sans-IO bridge engine: a K40T pod on one side, a flight controller speaking
//! SIYI, Viewlink, GCU or K40T on the other.
//!
//! No I/O, no clock reads, no allocation: the caller feeds bytes and the current
//! [`Instant`](time::Instant), and drains bytes, pin actions and events.

pub mod discipline;
pub mod fixes;
pub mod sync;
pub mod time;
