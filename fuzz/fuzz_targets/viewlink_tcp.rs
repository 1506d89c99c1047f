#![no_main]
// Properties: `fuzz_checks::viewlink::tcp` (host-tests/fuzz-checks).
libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzz_checks::viewlink::tcp(data));
