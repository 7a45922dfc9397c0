//! The model file reader must turn any bytes into a checked model or an error; what it accepts must
//! write back to the same model and learn online without a non-finite θ.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| pushlab_fuzz::model(data));
