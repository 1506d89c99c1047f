#![no_main]
// Properties: `fuzz_checks::bridge::run_k40t_allow` (host-tests/fuzz-checks).
libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzz_checks::bridge::run_k40t_allow(data));
