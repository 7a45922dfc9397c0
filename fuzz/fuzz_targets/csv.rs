//! The native CSV reader and the setting.json reader must turn any bytes into frames or an error.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use pushlab_core::recording::native::{parse_csv, parse_setting};

fuzz_target!(|data: &[u8]| {
    if let Ok(parsed) = parse_csv(data, Path::new("fuzz.csv")) {
        // What loads obeys the format's promises.
        let frames = &parsed.trajectory.frames;
        assert!(frames.len() >= 2);
        assert!(frames.windows(2).all(|w| w[1].time > w[0].time));
    }
    let _ = parse_setting(data, Path::new("setting.json"));
});
