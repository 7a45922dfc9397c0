//! The MIT Push Dataset JSON importer (parse, clean, resample) must turn any bytes into a push or
//! an error.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use pushlab_core::recording::mit_push::import_bytes;

const NAME: &str = "motion_surface=abs_shape=tri1_a=0_v=20_i=0.000_s=0.500_t=0.000.json";

fuzz_target!(|data: &[u8]| {
    if let Ok(push) = import_bytes(data, Path::new(NAME)) {
        let frames = &push.trajectory.frames;
        assert!(frames.windows(2).all(|w| w[1].time > w[0].time));
        assert!(
            frames
                .iter()
                .all(|f| f.object.yaw.is_finite() && f.robot.x.is_finite())
        );
    }
});
