#![no_main]
// Properties: `fuzz_checks::gcu::deframe` (host-tests/fuzz-checks).
libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzz_checks::gcu::deframe(data));
