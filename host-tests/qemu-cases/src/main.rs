//! Runs every codec case (`codec-cases`) as Cortex-M3 code and reports through
//! semihosting: one line per failure, then `N passed, M failed`; the exit status is
//! non-zero when a case failed.
#![no_std]
#![no_main]

use semihosting::{println, process};

#[cortex_m_rt::entry]
fn main() -> ! {
    let (mut passed, mut failed) = (0u32, 0u32);
    for case in codec_cases::all() {
        match (case.run)() {
            Ok(()) => passed += 1,
            Err(failure) => {
                failed += 1;
                println!("FAIL {}: {}", case.name, failure);
            }
        }
    }
    println!("{} passed, {} failed", passed, failed);
    process::exit(if failed == 0 { 0 } else { 1 })
}
