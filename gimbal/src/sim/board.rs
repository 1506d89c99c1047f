//! The board every simulated autopilot runs on, written once: its clock across reboots,
//! its power, its main loop, its output queue and the health log of its mount driver.
//! Each simulator ([`super::ap_siyi::ApSiyi`], [`super::ap_viewpro::ApViewpro`],
//! [`super::ap_xfrobot::ApXfRobot`], [`super::ap_mavlink::ApMavlink`], [`super::px4::Px4`],
//! [`super::fc_k40t::FcK40t`]) embeds a [`Board`] and implements [`Autopilot`]: its
//! protocol's part (what one run of the loop sends, how it reads bytes, when it calls
//! the mount healthy, what it forgets at a reboot). The [`Peer`] side (bytes in and out,
//! polls, power) and the accessors (health, clock, UTC, reboots) come with the trait.
//!
//! Time is simulated true time in µs. The board's time (`now_us`) is that of the work in
//! progress: a loop run's instant while it runs, else the latest instant processed.
//!
//! **Power.** [`Autopilot::reboot`] cuts the power: what the board wrote that has not
//! started on the wire is lost, the mount driver's health goes false at once, and until
//! power-on ([`FcReboot::off_us`] later) the board sends nothing and what arrives is lost
//! (counted). At the first instant after power-on, the loop restarts on the new boot's
//! clock and the simulator's [`Autopilot::power_on`] makes its driver new.

use super::peer::Peer;
use super::{FcBoot, FcClock, FcReboot, XorShift};

/// The simulated aircraft: a straight line at constant speed and height.
#[derive(Debug, Clone, Copy)]
pub struct Aircraft {
    /// Latitude at true time 0, degrees.
    pub lat0_deg: f64,
    /// Longitude at true time 0, degrees.
    pub lon0_deg: f64,
    /// Altitude above mean sea level, m.
    pub alt_msl_m: f64,
    /// Ground speed, m/s, heading north-east.
    pub speed_m_s: f64,
    /// Heading, degrees.
    pub heading_deg: f64,
}

impl Default for Aircraft {
    fn default() -> Self {
        Aircraft {
            lat0_deg: 47.397_742,
            lon0_deg: 8.545_594,
            alt_msl_m: 488.0,
            speed_m_s: 8.0,
            heading_deg: 45.0,
        }
    }
}

impl Aircraft {
    /// Latitude, longitude (1e-7 deg) at true time `t_us`.
    #[must_use]
    pub fn position_e7(&self, t_us: u64) -> (i32, i32) {
        let d = self.speed_m_s * t_us as f64 / 1e6;
        let h = self.heading_deg.to_radians();
        let lat = self.lat0_deg + d * h.cos() / 111_320.0;
        let lon = self.lon0_deg + d * h.sin() / (111_320.0 * self.lat0_deg.to_radians().cos());
        ((lat * 1e7).round() as i32, (lon * 1e7).round() as i32)
    }

    /// Roll, pitch, yaw (degrees) at true time `t_us`: a gentle roll oscillation.
    #[must_use]
    pub fn attitude_deg(&self, t_us: u64) -> (f64, f64, f64) {
        let s = t_us as f64 / 1e6;
        (5.0 * (s * 0.5).sin(), -3.0, self.heading_deg)
    }

    /// North and east velocity, m/s.
    #[must_use]
    pub fn velocity_m_s(&self) -> (f64, f64) {
        let h = self.heading_deg.to_radians();
        (self.speed_m_s * h.cos(), self.speed_m_s * h.sin())
    }
}

/// How the board's main loop is paced. Each run's instant is the board's time while the
/// simulator does the run's work.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MainLoop {
    /// ArduPilot's scheduler calling a serial mount driver's `update()` at 50 Hz on the
    /// FC's crystal (every 20 ms of the boot clock, from the first multiple of 20 ms after
    /// power-on), each run late by a draw uniform in `0..jitter_us` made as it starts.
    Scheduler50Hz {
        /// Lateness bound of a run, µs.
        jitter_us: u64,
        /// FC-clock ms of the next run.
        next_fc_ms: u64,
    },
    /// ArduPilot's main loop at `SCHED_LOOP_RATE`, paced by the IMU, whose oscillator is
    /// not the FC crystal: run `k` of a boot at true time
    /// `power-on + k·period/(1 + imu_ppm)` plus a lateness uniform in `0..jitter_us`
    /// (drawn when the run before it ends), never before the run before it.
    Imu {
        /// Loop period of a perfect oscillator, true µs.
        period_us: f64,
        /// Rate error of the IMU's oscillator, ppm (fast when positive).
        imu_ppm: f64,
        /// Lateness bound of a run, µs.
        jitter_us: u64,
        /// True time of run 0 of this boot.
        epoch_us: u64,
        /// Index of the next run in this boot.
        index: u64,
        /// True time of the next run (lateness included).
        next_at_us: u64,
    },
    /// A thread woken every `period_us` of true time from true time 0, across reboots
    /// (PX4's MAVLink threads): after a power cut it catches up on the runs it missed.
    Ticks {
        /// The period, µs.
        period_us: u64,
        /// True time of the next run.
        next_us: u64,
    },
    /// No loop: the simulator acts on its own instants ([`Autopilot::next_work_us`]).
    None,
}

impl MainLoop {
    /// ArduPilot's 50 Hz scheduler, runs late by up to `jitter_us`.
    #[must_use]
    pub const fn scheduler_50hz(jitter_us: u64) -> Self {
        MainLoop::Scheduler50Hz {
            jitter_us,
            next_fc_ms: 0,
        }
    }

    /// ArduPilot's main loop at `rate_hz` on an IMU `imu_ppm` off, runs late by up to
    /// `jitter_us`.
    #[must_use]
    pub fn imu(rate_hz: u32, imu_ppm: f64, jitter_us: u64) -> Self {
        MainLoop::Imu {
            period_us: 1e6 / f64::from(rate_hz.max(1)),
            imu_ppm,
            jitter_us,
            epoch_us: 0,
            index: 0,
            next_at_us: 0,
        }
    }

    /// A run every `period_us` of true time.
    #[must_use]
    pub const fn ticks(period_us: u64) -> Self {
        MainLoop::Ticks {
            period_us,
            next_us: 0,
        }
    }
}

/// What the power is at an instant the board is woken at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Power {
    /// Off: the board does nothing.
    Off,
    /// The first instant after power-on: the simulator makes its driver new.
    Booted,
    /// Running.
    On,
}

/// The board of a simulated autopilot: clock, power, main loop, output queue, health
/// log, the aircraft it flies, the frames its driver's parser dropped, and the seeded
/// noise of its jitters.
#[derive(Debug)]
pub struct Board {
    aircraft: Aircraft,
    parse_errors: u32,
    rng: XorShift,
    now_us: u64,
    clock: FcClock,
    power_on_at: Option<u64>,
    lost_while_off: u64,
    main_loop: MainLoop,
    out: Vec<(u64, Vec<u8>)>,
    /// The board time at which the last burst of `out` was opened.
    burst_opened_at: Option<u64>,
    healthy: bool,
    health_log: Vec<(u64, bool)>,
}

impl Board {
    /// An ArduPilot board: `clock`, the 50 Hz scheduler late by up to `loop_jitter_us`,
    /// jitters drawn from `seed`.
    #[must_use]
    pub(crate) fn scheduler_50hz(clock: FcClock, seed: u64, loop_jitter_us: u64) -> Self {
        Board::new(
            clock,
            XorShift(seed.max(1)),
            MainLoop::scheduler_50hz(loop_jitter_us),
        )
    }

    /// A board on `clock` (powered on at its latest boot: before that instant it is
    /// off), its loop paced as `main_loop` says, its jitters drawn from `rng`.
    #[must_use]
    pub(crate) fn new(clock: FcClock, rng: XorShift, main_loop: MainLoop) -> Self {
        let on = clock.current().at_us;
        let mut board = Board {
            aircraft: Aircraft::default(),
            parse_errors: 0,
            rng,
            now_us: 0,
            clock,
            power_on_at: (on > 0).then_some(on),
            lost_while_off: 0,
            main_loop,
            out: Vec::new(),
            burst_opened_at: None,
            healthy: false,
            health_log: Vec::new(),
        };
        board.restart_loop();
        board
    }

    /// The board flying `aircraft`.
    #[must_use]
    pub(crate) fn flying(mut self, aircraft: Aircraft) -> Self {
        self.aircraft = aircraft;
        self
    }

    /// The aircraft (its true position and attitude at any instant).
    #[must_use]
    pub fn aircraft(&self) -> &Aircraft {
        &self.aircraft
    }

    /// Frames the driver's parser dropped.
    #[must_use]
    pub fn parse_errors(&self) -> u32 {
        self.parse_errors
    }

    /// The driver's parser dropped a frame.
    pub(crate) fn parse_error(&mut self) {
        self.parse_errors += 1;
    }

    // Time.

    /// The board's time, µs.
    #[must_use]
    pub fn now_us(&self) -> u64 {
        self.now_us
    }

    /// Sets the board's time (the end of a poll, a run's own instant).
    pub(crate) fn set_now(&mut self, now_us: u64) {
        self.now_us = now_us;
    }

    /// The FC's clock: boot clock, crystal, UTC, reboots.
    #[must_use]
    pub fn clock(&self) -> &FcClock {
        &self.clock
    }

    /// The FC's UTC steps by `shift_us` at true time `now_us` (see
    /// [`FcClock::step_utc`]).
    pub fn step_utc(&mut self, now_us: u64, shift_us: i64) {
        self.clock.step_utc(now_us, shift_us);
    }

    /// The FC's boot clock (µs) at true time `t_us`.
    #[must_use]
    pub fn fc_us(&self, t_us: u64) -> u64 {
        self.clock.clock_us(t_us)
    }

    /// The FC's boot clock now, ms.
    #[must_use]
    pub fn fc_ms(&self) -> u64 {
        self.fc_us(self.now_us) / 1000
    }

    /// True time at which the latest boot's clock reads `fc_us`.
    #[must_use]
    pub fn true_of_fc(&self, fc_us: u64) -> u64 {
        self.clock.true_of_clock(fc_us)
    }

    /// The FC knows UTC now.
    #[must_use]
    pub fn utc_valid(&self) -> bool {
        self.clock.utc_valid(self.now_us)
    }

    /// The seeded noise of the board's jitters (and the simulator's own draws, in the
    /// order they are made).
    pub(crate) fn rng(&mut self) -> &mut XorShift {
        &mut self.rng
    }

    // Power.

    /// The board is without power (rebooting) at the latest instant processed.
    #[must_use]
    pub fn is_off(&self) -> bool {
        self.power_on_at.is_some()
    }

    /// Bytes that arrived while the board was off.
    #[must_use]
    pub fn lost_while_off(&self) -> u64 {
        self.lost_while_off
    }

    /// Takes `now_us` (never backwards) and says what the power is then; at the first
    /// instant after power-on the loop restarts. `arriving` bytes are lost while off.
    fn wake(&mut self, now_us: u64, arriving: usize) -> Power {
        self.now_us = self.now_us.max(now_us);
        match self.power_on_at {
            Some(on) if now_us < on => {
                self.lost_while_off += arriving as u64;
                Power::Off
            }
            Some(_) => {
                self.power_on_at = None;
                self.restart_loop();
                Power::Booted
            }
            None => Power::On,
        }
    }

    /// The power goes off now, back as `reboot` says: what has not started on the wire is
    /// lost, the mount driver unhealthy.
    fn power_off(&mut self, reboot: FcReboot) {
        let on = self.clock.reboot(self.now_us, reboot);
        self.power_on_at = Some(on);
        let now = self.now_us;
        self.out.retain(|(at, _)| *at <= now);
        self.set_healthy(false);
    }

    // Main loop.

    /// The loop's first run of the latest boot.
    fn restart_loop(&mut self) {
        let boot = *self.clock.current();
        match &mut self.main_loop {
            MainLoop::Scheduler50Hz { next_fc_ms, .. } => {
                *next_fc_ms = boot.clock_us.div_ceil(20_000) * 20;
            }
            MainLoop::Imu {
                epoch_us, index, ..
            } => {
                *epoch_us = boot.at_us;
                *index = 0;
            }
            MainLoop::Ticks { .. } | MainLoop::None => {}
        }
        self.schedule_imu_run();
    }

    /// Sets the instant of the IMU-paced run `index`: its nominal instant plus a lateness.
    fn schedule_imu_run(&mut self) {
        let lateness = match self.main_loop {
            MainLoop::Imu { jitter_us, .. } => self.rng.uniform(jitter_us),
            _ => return,
        };
        if let MainLoop::Imu {
            period_us,
            imu_ppm,
            epoch_us,
            index,
            next_at_us,
            ..
        } = &mut self.main_loop
        {
            let k = *index as f64;
            let nominal = *epoch_us + (k * *period_us / (1.0 + *imu_ppm * 1e-6)).round() as u64;
            let at = nominal + lateness;
            // Never before the run before it.
            *next_at_us = if *index == 0 {
                at
            } else {
                at.max(*next_at_us + 1)
            };
        }
    }

    /// True time of the loop's next run (`u64::MAX`: no loop).
    #[must_use]
    pub fn next_run_us(&self) -> u64 {
        match self.main_loop {
            MainLoop::Scheduler50Hz { next_fc_ms, .. } => self.true_of_fc(next_fc_ms * 1000),
            MainLoop::Imu { next_at_us, .. } => next_at_us,
            MainLoop::Ticks { next_us, .. } => next_us,
            MainLoop::None => u64::MAX,
        }
    }

    /// The index of the loop's current run in this boot (the IMU-paced loop; 0 for the
    /// others).
    #[must_use]
    pub fn run_index(&self) -> u64 {
        match self.main_loop {
            MainLoop::Imu { index, .. } => index,
            _ => 0,
        }
    }

    /// Starts the loop's next run when it is due by `until_us` (`inclusive`: at `until_us`
    /// too; the 50 Hz scheduler and the ticks always are): the board's time becomes the
    /// run's. False when no run is due. Call [`Board::end_run`] after the run's work.
    pub(crate) fn start_run(&mut self, until_us: u64, inclusive: bool) -> bool {
        let next = self.next_run_us();
        match &mut self.main_loop {
            MainLoop::Scheduler50Hz {
                jitter_us,
                next_fc_ms,
            } if next <= until_us => {
                // The run starts late; what it reads and writes is stamped then.
                let late = self.rng.uniform(*jitter_us);
                *next_fc_ms += 20;
                self.now_us = next + late;
                true
            }
            MainLoop::Imu { next_at_us, .. }
                if *next_at_us < until_us || (inclusive && *next_at_us == until_us) =>
            {
                self.now_us = *next_at_us;
                true
            }
            MainLoop::Ticks { period_us, next_us } if *next_us <= until_us => {
                self.now_us = *next_us;
                *next_us += *period_us;
                true
            }
            _ => false,
        }
    }

    /// Ends a run started by [`Board::start_run`].
    pub(crate) fn end_run(&mut self) {
        if let MainLoop::Imu { index, .. } = &mut self.main_loop {
            *index += 1;
            self.schedule_imu_run();
        }
    }

    // Output.

    /// Writes `bytes` now into the burst still waiting to leave, or into a new burst
    /// leaving after a transport jitter uniform in `0..jitter_us` (ArduPilot's serial
    /// drivers: what one run writes leaves together).
    pub(crate) fn write_run(&mut self, bytes: Vec<u8>, jitter_us: u64) {
        match self.out.last_mut() {
            Some((at, queued)) if *at >= self.now_us => queued.extend_from_slice(&bytes),
            _ => {
                let at = self.now_us + self.rng.uniform(jitter_us);
                self.out.push((at, bytes));
            }
        }
    }

    /// Writes `bytes` now into the burst opened at this very instant, or into a new one
    /// leaving after a transport jitter uniform in `0..jitter_us` (ArduPilot's main loop:
    /// what one loop writes leaves together).
    pub(crate) fn write_loop(&mut self, bytes: Vec<u8>, jitter_us: u64) {
        match self.out.last_mut() {
            Some((_, queued)) if self.burst_opened_at == Some(self.now_us) => {
                queued.extend_from_slice(&bytes);
            }
            _ => {
                let at = self.now_us + self.rng.uniform(jitter_us);
                self.out.push((at, bytes));
                self.burst_opened_at = Some(self.now_us);
            }
        }
    }

    /// Writes `bytes` as a burst of their own leaving at `at_us`, after what was written
    /// before.
    pub(crate) fn write_at(&mut self, at_us: u64, bytes: Vec<u8>) {
        self.out.push((at_us, bytes));
    }

    /// Writes `bytes` as a burst of their own leaving at `at_us`, in the order of the
    /// bursts' instants (threads writing each their own message: PX4).
    pub(crate) fn write_in_order(&mut self, at_us: u64, bytes: Vec<u8>) {
        let i = self.out.partition_point(|(at, _)| *at <= at_us);
        self.out.insert(i, (at_us, bytes));
    }

    /// The instant the latest burst leaves, while it waits.
    #[must_use]
    pub fn last_burst_at(&self) -> Option<u64> {
        self.out.last().map(|(at, _)| *at)
    }

    // Health.

    /// The mount driver calls the mount healthy.
    #[must_use]
    pub fn healthy(&self) -> bool {
        self.healthy
    }

    /// Every change of [`Board::healthy`]: (true time, new value).
    #[must_use]
    pub fn health_log(&self) -> &[(u64, bool)] {
        &self.health_log
    }

    /// The driver's health now is `healthy` (logged when it changes).
    pub(crate) fn set_healthy(&mut self, healthy: bool) {
        self.set_healthy_at(self.now_us, healthy);
    }

    /// The driver's health at `t_us` is `healthy` (logged when it changes).
    pub(crate) fn set_healthy_at(&mut self, t_us: u64, healthy: bool) {
        if healthy != self.healthy {
            self.healthy = healthy;
            self.health_log.push((t_us, healthy));
        }
    }
}

/// The [`Autopilot::board`] and [`Autopilot::board_mut`] of a simulator whose board is
/// its field `board`.
macro_rules! board_field {
    () => {
        fn board(&self) -> &$crate::sim::board::Board {
            &self.board
        }
        fn board_mut(&mut self) -> &mut $crate::sim::board::Board {
            &mut self.board
        }
    };
}
pub(crate) use board_field;

/// A simulated autopilot: its protocol's behaviour on a [`Board`]. The [`Peer`] side
/// (`receive`, `poll`, `next_wakeup`, `transmit`) comes with it: the board's power
/// decides whether bytes and polls reach the simulator, which then takes the bytes
/// ([`Autopilot::take_bytes`]) or does the work due ([`Autopilot::run_due`]: the loop's
/// runs, [`Autopilot::run`]).
pub trait Autopilot {
    /// The board (`board_field!()` when it is the field `board`).
    fn board(&self) -> &Board;
    /// The board, to change.
    fn board_mut(&mut self) -> &mut Board;

    /// The driver's health is taken as bytes arrive too, not only in its loop.
    const HEALTH_ON_RECEIVE: bool = true;

    /// Bytes from the bridge, the last of them arriving at `now_us`, the board on (its
    /// time already taken); the health is taken after ([`Autopilot::HEALTH_ON_RECEIVE`]).
    fn take_bytes(&mut self, now_us: u64, bytes: &[u8]);
    /// One run of the main loop, at the board's time.
    fn run(&mut self);
    /// The driver's health rule at the board's time (the board logs each change).
    fn update_health(&mut self);
    /// The driver as new, at the first instant after power-on (the board has restarted
    /// its loop on the new boot's clock).
    fn power_on(&mut self);
    /// What the driver forgets at once when the power goes off (the board has dropped
    /// its unsent output and logged the driver unhealthy).
    fn power_off(&mut self) {}
    /// When the simulator next has work while on (default: the loop's next run).
    fn next_work_us(&self) -> u64 {
        self.board().next_run_us()
    }
    /// The work due up to `now_us`, the board on: the loop's runs, then the health at
    /// `now_us`.
    fn run_due(&mut self, now_us: u64) {
        self.run_loop_until(now_us, true);
        self.board_mut().set_now(now_us);
        self.update_health();
    }
    /// The loop's runs due before `until_us` (`inclusive`: at it too).
    fn run_loop_until(&mut self, until_us: u64, inclusive: bool) {
        while self.board_mut().start_run(until_us, inclusive) {
            self.run();
            self.board_mut().end_run();
        }
    }

    /// The mount driver calls the mount healthy.
    fn healthy(&self) -> bool {
        self.board().healthy()
    }
    /// Every change of [`Autopilot::healthy`]: (true time, new value).
    fn health_log(&self) -> &[(u64, bool)] {
        self.board().health_log()
    }
    /// The FC's clock (boot clock, crystal, UTC, reboots), e.g. for a MAVLink telemetry
    /// port of the same autopilot ([`super::ap_mavlink::ApMavlink::telemetry`]).
    fn clock(&self) -> &FcClock {
        self.board().clock()
    }
    /// The FC's boot clock (µs) at true time `t_us` (of the boot in effect then).
    fn fc_us(&self, t_us: u64) -> u64 {
        self.board().fc_us(t_us)
    }
    /// The FC's UTC (µs since the Unix epoch) at true time `t_us` (of the boot in effect
    /// then).
    fn fc_utc_us(&self, t_us: u64) -> u64 {
        self.board().clock().utc_us(t_us)
    }
    /// Every boot of the FC (the first at true time 0).
    fn boots(&self) -> &[FcBoot] {
        self.board().clock().boots()
    }
    /// The FC is without power (rebooting) at the latest instant processed.
    fn is_off(&self) -> bool {
        self.board().is_off()
    }
    /// Bytes from the bridge lost while the FC was off.
    fn lost_while_off(&self) -> u64 {
        self.board().lost_while_off()
    }
    /// The aircraft (its true position at any instant).
    fn aircraft(&self) -> &Aircraft {
        self.board().aircraft()
    }
    /// Frames the FC's parser dropped.
    fn parse_errors(&self) -> u32 {
        self.board().parse_errors()
    }
    /// The FC loses power at `now_us` (the work due up to then done first) and boots
    /// again as `reboot` says.
    fn reboot(&mut self, now_us: u64, reboot: FcReboot)
    where
        Self: Sized,
    {
        self.poll(now_us);
        self.board_mut().power_off(reboot);
        self.power_off();
    }
}

impl<A: Autopilot> Peer for A {
    fn receive(&mut self, now_us: u64, bytes: &[u8]) {
        match self.board_mut().wake(now_us, bytes.len()) {
            Power::Off => return,
            Power::Booted => self.power_on(),
            Power::On => {}
        }
        self.take_bytes(now_us, bytes);
        if Self::HEALTH_ON_RECEIVE {
            self.update_health();
        }
    }

    fn poll(&mut self, now_us: u64) {
        match self.board_mut().wake(now_us, 0) {
            Power::Off => return,
            Power::Booted => self.power_on(),
            Power::On => {}
        }
        self.run_due(now_us);
    }

    fn next_wakeup(&self) -> u64 {
        self.board()
            .power_on_at
            .unwrap_or_else(|| self.next_work_us())
    }

    fn transmit(&mut self, _now_us: u64) -> Vec<(u64, Vec<u8>)> {
        std::mem::take(&mut self.board_mut().out)
    }
}
