//! The frames made of several blocks (section 2.2): control (0x30..0x33) and status
//! (0x40, 0x41).

use super::{A1, A2, B1, B2, C1, C2, D1, D2, E1, E2, F1, F2, S1, S2, T1, T2};

wire_struct! {
    Be;
    /// Frame 0x30: A1 + C1 + E1 (14 bytes), console to payload.
    pub struct Control {
        /// Servo control.
        pub a1: A1,
        /// Optical control.
        pub c1: C1,
        /// Tracking command.
        pub e1: E1,
    }
}

wire_struct! {
    Be;
    /// Frame 0x32: A1 + C1 + E1 + S1 (28 bytes), console to payload.
    pub struct ControlTgcc {
        /// Servo control.
        pub a1: A1,
        /// Optical control.
        pub c1: C1,
        /// Tracking command.
        pub e1: E1,
        /// Target calculation control.
        pub s1: S1,
    }
}

wire_struct! {
    Be;
    /// Frame 0x31: A2 + C2 + E2 (10 bytes), console to payload.
    pub struct RareControl {
        /// Servo control, infrequent.
        pub a2: A2,
        /// Optical control, infrequent.
        pub c2: C2,
        /// Tracking command, infrequent.
        pub e2: E2,
    }
}

wire_struct! {
    Be;
    /// Frame 0x33: A2 + C2 + E2 + S2 (15 bytes), console to payload.
    pub struct RareControlTgcc {
        /// Servo control, infrequent.
        pub a2: A2,
        /// Optical control, infrequent.
        pub c2: C2,
        /// Tracking command, infrequent.
        pub e2: E2,
        /// Target calculation control, infrequent.
        pub s2: S2,
    }
}

wire_struct! {
    Be;
    /// Frame 0x40: T1 + F1 + B1 + D1 (41 bytes), payload to console: the status a
    /// gimbal sends in reply to control frames, handshakes and heartbeats (ArduPilot
    /// reads 0x40). Frame 0x42 carries the same layout as [`StatusOsd`](super::StatusOsd).
    pub struct Status {
        /// Target calculation status.
        pub t1: T1,
        /// Tracker status.
        pub f1: F1,
        /// Servo status.
        pub b1: B1,
        /// Optical status.
        pub d1: D1,
    }
}

wire_struct! {
    Be;
    /// Frame 0x41: T2 + F2 + B2 + D2 (49 bytes), payload to console: sent once when an
    /// A2 asks for it.
    pub struct RareStatus {
        /// Target calculation status, infrequent.
        pub t2: T2,
        /// Tracker status, infrequent.
        pub f2: F2,
        /// Servo status, infrequent.
        pub b2: B2,
        /// Optical status, infrequent.
        pub d2: D2,
    }
}
