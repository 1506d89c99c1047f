#![no_main]
// Properties: `fuzz_checks::console::run` (host-tests/fuzz-checks).
libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzz_checks::console::run(data));
