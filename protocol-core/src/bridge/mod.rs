//! The sans-IO bridge engine: a K40T pod on one side, a flight controller speaking
//! SIYI, Viewlink, GCU or K40T on the other.
//!
//! No I/O, no clock reads, no allocation: the caller feeds bytes and the current
//! instant, and drains bytes, pin actions and events.

pub mod time;
