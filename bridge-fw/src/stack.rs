//! Stack high-water mark: the stack is painted with a pattern at start-up, and the lowest
//! word that no longer holds it tells how deep the stack (tasks and interrupts) has ever
//! reached. With flip-link the stack is the bottom of RAM, from `_stack_start` down to
//! `_stack_end` (the RAM origin); an overflow faults instead of corrupting `.bss`.
//!
//! `unsafe`: reading the linker's symbols and writing/reading the unused stack words
//! (volatile, below the current stack pointer, word-aligned), which is why the module
//! allows `unsafe_code`.

use core::ptr;

const PAINT: u32 = 0x5AC3_A53C;
/// Words left unpainted just below the stack pointer while painting (this function's own
/// frame and an interrupt's).
const MARGIN: usize = 256;

unsafe extern "C" {
    static _stack_start: u32;
    static _stack_end: u32;
}

fn bounds() -> (usize, usize) {
    // Only the symbols' addresses are taken, never their contents.
    (
        ptr::addr_of!(_stack_end) as usize,
        ptr::addr_of!(_stack_start) as usize,
    )
}

/// Paints the unused stack. Call once, first thing in `main`.
pub fn paint() {
    let (low, _) = bounds();
    let sp = cortex_m::register::msp::read() as usize;
    let mut a = (low + 3) & !3;
    while a + MARGIN < sp {
        // SAFETY: `a` is word-aligned, inside the stack region and below the live
        // stack (an interrupt during painting uses the stack below `sp` and is done
        // before painting resumes).
        unsafe { ptr::write_volatile(a as *mut u32, PAINT) };
        a += 4;
    }
}

/// (bytes ever used, bytes in all) of the stack.
pub fn high_water() -> (usize, usize) {
    let (low, high) = bounds();
    let mut a = (low + 3) & !3;
    // SAFETY: word-aligned reads inside the stack region.
    while a < high && unsafe { ptr::read_volatile(a as *const u32) } == PAINT {
        a += 4;
    }
    (high - a, high - low)
}
