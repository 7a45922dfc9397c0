//! ROS 2 bags: the MCAP reader, chunk decompression, CDR decoding and resampling on arbitrary bytes.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| pushlab_fuzz::mcap(data));
