//! Zarr replay buffers: `.zarray` metadata, blosc (LZ4, zstd, shuffles), zstd and LZ4 chunks and
//! `episode_ends`, one file of the Push-T fixture at a time.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| pushlab_fuzz::zarr(data));
