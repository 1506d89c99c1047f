//! Simulated peers of the bridge, sans-IO and in simulated time, for the host tests and
//! the demo.

pub mod pod;
