//! Runs the shared codec cases (`host-tests/codec-cases`) natively, one libtest test per case.
//! The same cases run on Cortex-M under QEMU (`host-tests/qemu-cases`).

use libtest_mimic::{Arguments, Failed, Trial};

fn main() {
    let args = Arguments::from_args();
    let trials = codec_cases::all()
        .map(|case| {
            let run = case.run;
            Trial::test(case.name, move || {
                run().map_err(|f| Failed::from(f.to_string()))
            })
        })
        .collect();
    libtest_mimic::run(&args, trials).exit();
}
