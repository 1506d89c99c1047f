#![no_main]
// Properties: `fuzz_checks::siyi::decode` (host-tests/fuzz-checks).
libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzz_checks::siyi::decode(data));
