#![no_main]
// Properties: `fuzz_checks::k40t::deframe` (host-tests/fuzz-checks).
libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzz_checks::k40t::deframe(data));
