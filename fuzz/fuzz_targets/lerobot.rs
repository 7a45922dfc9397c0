//! LeRobot datasets v2.1 and v3.0: `info.json`, `episodes.jsonl`, the episode metadata and the
//! parquet rows, one file of the Push-T fixtures at a time.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| pushlab_fuzz::lerobot(data));
