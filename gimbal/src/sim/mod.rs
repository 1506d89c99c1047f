//! Simulated peers of the bridge, sans-IO and in simulated time, for the host tests and
//! the demo.

pub mod ap_mavlink;
pub mod ap_siyi;
pub mod ap_viewpro;
pub mod ap_xfrobot;
pub mod board;
pub mod camera_settings;
pub mod clock;
pub mod describe;
pub mod faults;
pub mod fc_k40t;
pub mod gnss;
pub mod ground;
pub mod line;
pub mod mav;
pub mod mount_target;
pub mod peer;
pub mod pilot;
pub mod pod;
pub mod pps_io;
pub mod px4;
pub mod qgc;
pub mod scenario;
pub mod signing;
pub mod tasks;

pub use board::{Aircraft, Autopilot, Board, MainLoop};
pub use clock::{FcBoot, FcClock, FcReboot};
pub use peer::Peer;

/// xorshift64* (Vigna): the simulators' reproducible noise (fault injection, jitter).
#[derive(Debug, Clone)]
pub(crate) struct XorShift(pub(crate) u64);

impl XorShift {
    pub(crate) fn new(seed: u64) -> Self {
        XorShift(if seed == 0 {
            0x9E37_79B9_7F4A_7C15
        } else {
            seed
        })
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// True with probability `p`.
    pub(crate) fn chance(&mut self, p: f64) -> bool {
        p > 0.0 && ((self.next_u64() >> 11) as f64) / ((1u64 << 53) as f64) < p
    }

    /// Uniform in `0..n` (n > 0).
    pub(crate) fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n.max(1) as u64) as usize
    }

    /// Uniform in `0..bound` (0 when `bound` is 0).
    pub(crate) fn uniform(&mut self, bound: u64) -> u64 {
        if bound == 0 {
            0
        } else {
            self.next_u64() % bound
        }
    }
}
