#![no_main]
// Properties: `fuzz_checks::resync::resync` (host-tests/fuzz-checks).
libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzz_checks::resync::resync(data));
