//! The labels file reader must turn any bytes into labels or an error, and what it accepts must
//! write back to the same labels.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| pushlab_fuzz::labels(data));
