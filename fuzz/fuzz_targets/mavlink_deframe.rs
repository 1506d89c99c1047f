#![no_main]
// Properties: `fuzz_checks::mavlink::deframe` (host-tests/fuzz-checks).
libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzz_checks::mavlink::deframe(data));
