//! Camera messages: CDR `CompressedImage` and `Image` payloads read and their frames decoded.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| pushlab_fuzz::image_message(data));
