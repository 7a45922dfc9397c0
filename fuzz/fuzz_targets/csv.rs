//! The native CSV reader and the setting.json reader must turn any bytes into frames or an error.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| pushlab_fuzz::csv(data));
