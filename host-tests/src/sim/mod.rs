//! Simulated peers of the bridge, sans-IO and in simulated time, for the host tests and
//! the demo.

pub mod ap_siyi;
pub mod ap_viewpro;
pub mod ap_xfrobot;
pub mod fc_k40t;
pub mod line;
pub mod peer;
pub mod pilot;
pub mod pod;
pub mod scenario;
pub mod tasks;
