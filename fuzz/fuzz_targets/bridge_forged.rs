#![no_main]
// Properties: `fuzz_checks::bridge_mavlink::run_forged` (host-tests/fuzz-checks).
libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzz_checks::bridge_mavlink::run_forged(data));
