//! Power cut at every step: the host flash model loses power after each program word and
//! each page erase of a board's life (receive, verify, swap, confirm or rollback), the
//! board is powered again and reset, and embassy-boot's bootloader (the very code the
//! bootloader crate runs) must leave a whole image in the active slot every time: the old
//! one or the new one, never a mix. Then the board goes on (the update is sent again, the
//! image confirms itself or not) and must end as the life without a cut ends.
#![allow(
    clippy::unwrap_used,
    clippy::indexing_slicing,
    clippy::arithmetic_side_effects,
    clippy::panic,
    clippy::cast_possible_truncation
)]

mod common;

use bridge_update::sim::{SimBoard, SimFlash};
use common::*;
use embassy_boot::State;

const LEN: usize = 2 * 2048 + 300;

/// How the new image behaves once it runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum NewImage {
    /// It reaches a healthy state and confirms itself.
    Healthy,
    /// It never confirms itself (hangs: the watchdog resets it).
    Hangs,
}

struct Life {
    a: Vec<u8>,
    b: Vec<u8>,
    sig: [u8; 64],
    new_image: NewImage,
}

impl Life {
    fn new(new_image: NewImage) -> Self {
        let b = image(0xB0, LEN);
        Life {
            a: image(0xA0, LEN),
            sig: signature(&key(), &b),
            b,
            new_image,
        }
    }

    /// The image in the active slot: A or B, whole; anything else fails the test.
    fn running(&self, board: &SimBoard, when: &str) -> char {
        let active = board.active(LEN);
        if active == self.a {
            'A'
        } else if active == self.b {
            'B'
        } else {
            let diff_a = active.iter().zip(&self.a).filter(|(x, y)| x != y).count();
            let diff_b = active.iter().zip(&self.b).filter(|(x, y)| x != y).count();
            panic!(
                "{when}: a half image in the active slot ({diff_a} bytes from A, {diff_b} from B)"
            );
        }
    }

    /// The board's life from where it is, until it has the image it keeps; with the power
    /// planned to fail after `cut` steps (`None`: never). Every reset must boot a whole
    /// image. Returns the image it ends with.
    fn live(&self, board: &SimBoard, cut: Option<u64>) -> char {
        if let Some(steps) = cut {
            board.with_flash(|f| f.cut_after(steps));
        }
        let mut updated = false;
        for round in 0..8 {
            // A reset (the first one of a round after the cut: power back).
            let lost = board.with_flash(|f: &mut SimFlash| f.lost_power());
            if lost {
                board.with_flash(SimFlash::power_on);
            }
            let booted = board.reset();
            if board.with_flash(|f: &mut SimFlash| f.lost_power()) {
                // The power failed during the swap or revert: the next round powers on.
                assert!(booted.is_err());
                continue;
            }
            let state = booted.unwrap().state;
            let running = self.running(board, &format!("round {round}, state {state:?}"));
            let mut aligned = [0; 8];
            let Ok(mut slot) = board.slot(&mut aligned) else {
                continue;
            };
            let on_trial = slot_state(&mut slot) == Some(bridge_update::wire::BootState::Trial);
            match (running, on_trial) {
                ('B', true) => match self.new_image {
                    NewImage::Healthy => {
                        if board.confirm().is_err() {
                            continue;
                        }
                    }
                    NewImage::Hangs => continue, // the watchdog resets it
                },
                // The integrator sends the update, and sends it again when a cut stopped
                // it or rolled it back before it could confirm itself (by design: an
                // image that has not confirmed itself is swapped back at any reset).
                ('A', false) if !updated || self.new_image == NewImage::Healthy => {
                    match update(board, &self.b, self.sig, &mut 0) {
                        Ended::Verified => updated = true,
                        Ended::PowerLost => continue,
                        Ended::Failed(e) => panic!("round {round}: {e}"),
                    }
                    continue;
                }
                ('B', false) if state == State::Boot || state == State::Revert => return 'B',
                ('A', false) => return 'A',
                _ => {}
            }
            if board.with_flash(|f: &mut SimFlash| f.lost_power()) {
                continue;
            }
            // Settled: one more reset must change nothing.
            if board.reset().is_ok() {
                return self.running(board, "after settling");
            }
        }
        panic!("the board did not settle in 8 resets");
    }
}

fn slot_state(slot: &mut impl bridge_update::Slot) -> Option<bridge_update::wire::BootState> {
    slot.state().ok()
}

/// Runs a life without a cut to count its steps, then one life per cut point.
fn every_cut(new_image: NewImage, expected: char) -> u64 {
    let life = Life::new(new_image);
    let board = new_board(&life.a);
    assert_eq!(life.live(&board, None), expected);
    let steps = board.with_flash(|f| f.steps);
    eprintln!("{new_image:?}: {steps} steps, a cut after each");
    for cut in 0..=steps {
        let board = new_board(&life.a);
        let end = life.live(&board, Some(cut));
        assert_eq!(end, expected, "power cut after step {cut} of {steps}");
    }
    steps
}

#[test]
fn a_cut_at_any_step_of_an_update_that_confirms_itself_ends_with_the_update() {
    let steps = every_cut(NewImage::Healthy, 'B');
    // Receive (3 erases, 550 words), the state's marks, the swap (3 pages: 2 erases and
    // 512 words each, 2 progress words), the confirmation: 2 107 steps, each one cut.
    assert_eq!(steps, 2_107);
}

#[test]
fn a_cut_at_any_step_of_an_update_that_hangs_ends_with_the_old_image() {
    let steps = every_cut(NewImage::Hangs, 'A');
    // The same, with the revert (as long as the swap) instead of the confirmation: 3 655
    // steps, each one cut.
    assert_eq!(steps, 3_655);
}

#[test]
fn a_second_cut_while_recovering_from_the_first_still_boots_a_whole_image() {
    // Cuts during the swap and during the revert, then again during the recovery's own
    // swap or revert: sampled (every 37th step for the first, every 53rd for the second).
    let life = Life::new(NewImage::Hangs);
    let board = new_board(&life.a);
    life.live(&board, None);
    let steps = board.with_flash(|f| f.steps);
    let mut runs = 0;
    for first in (0..steps).step_by(37) {
        for second in (0..1_700).step_by(53) {
            let board = new_board(&life.a);
            board.with_flash(|f| f.cut_after(first));
            // Until the first cut: the life as usual.
            let _ = update(&board, &life.b, life.sig, &mut 0);
            for _ in 0..3 {
                if board.with_flash(|f: &mut SimFlash| f.lost_power()) {
                    break;
                }
                let _ = board.reset();
            }
            if !board.with_flash(|f: &mut SimFlash| f.lost_power()) {
                continue;
            }
            board.with_flash(SimFlash::power_on);
            // The recovery's reset, cut again.
            board.with_flash(|f| f.cut_after(second));
            let _ = board.reset();
            board.with_flash(SimFlash::power_on);
            let end = life.live(&board, None);
            assert_eq!(end, 'A', "cuts after {first} and {second} steps");
            runs += 1;
        }
    }
    assert!(runs > 1_000, "{runs} double cuts");
}
