//! The Linux bridge runner behind `gimbal bridge`, `gimbal sim-fc` and `gimbal sim-pod`:
//! ports (serial, TCP, UDP, simulators) pumped by std threads into the bridge's pipes, the
//! RTC_IO output, the PPS input, the photo event file, and the events printed as text or
//! JSON lines; a task bench's run as the same JSON lines ([`bench_log`]).

pub mod bench_log;
pub mod bridge;
pub mod event_name;
pub mod events;
pub mod options;
pub mod output;
pub mod photos;
pub mod pin;
pub mod port;
pub mod pps;
pub mod simfc;
pub mod sims;
pub mod state;
pub mod trace;
pub mod udp;
pub mod watch;
