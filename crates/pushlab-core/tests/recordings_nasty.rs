//! Nasty inputs for every reader, kept as regular tests so that CI checks without the fuzzer what
//! fuzzing found or could find: hand-made files in `tests/nasty/` (plus inputs the fuzzer found,
//! named `fuzz_*`), and systematic truncations and byte flips of a valid HDF5 file.
//!
//! Every input must give either an error that names the file or a recording that keeps the
//! format's promises (≥ 2 frames, time strictly increasing, finite values). Files named `ok_*` must
//! load; all others must be refused.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};

use pushlab_core::recording::mit_push::import_bytes;
use pushlab_core::recording::native::{parse_csv, parse_setting};
use pushlab_core::trajectory::Trajectory;

fn nasty_files(kind: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/nasty")
        .join(kind);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("tests/nasty exists")
        .map(|e| e.expect("entry").path())
        .collect();
    files.sort();
    assert!(files.len() >= 5, "{}: too few nasty inputs", dir.display());
    files
}

fn check_promises(trajectory: &Trajectory, what: &str) {
    let frames = &trajectory.frames;
    assert!(frames.len() >= 2, "{what}: fewer than 2 frames");
    assert!(
        frames.windows(2).all(|w| w[1].time > w[0].time),
        "{what}: time not increasing"
    );
    assert!(
        frames.iter().all(|f| [
            f.time,
            f.robot.x,
            f.robot.y,
            f.object.position.x,
            f.object.position.y,
            f.object.yaw
        ]
        .iter()
        .all(|v| v.is_finite())),
        "{what}: non-finite value"
    );
    assert!(
        frames
            .windows(2)
            .all(|w| (w[1].object.yaw - w[0].object.yaw).abs() <= std::f64::consts::PI),
        "{what}: theta not unwrapped"
    );
}

fn expect_outcome<T, E: std::fmt::Display>(path: &Path, result: Result<T, E>, check: impl Fn(&T)) {
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    let should_load = name.starts_with("ok_");
    match result {
        Ok(value) => {
            assert!(should_load, "{name} loaded but should be refused");
            check(&value);
        }
        Err(e) => {
            assert!(!should_load, "{name} should load: {e}");
            let message = e.to_string();
            assert!(
                message.starts_with(&path.display().to_string()),
                "{name}: error does not name the file: {message}"
            );
            assert!(message.len() < 600, "{name}: message too long: {message}");
        }
    }
}

#[test]
fn nasty_csv_files_are_refused_or_loaded_correctly() {
    for path in nasty_files("csv") {
        let bytes = std::fs::read(&path).unwrap();
        let what = path.display().to_string();
        expect_outcome(&path, parse_csv(&bytes, &path), |parsed| {
            check_promises(&parsed.trajectory, &what)
        });
        // Also as a setting.json: never a panic; always an error for these.
        assert!(parse_setting(&bytes, &path).is_err(), "{what}");
    }
}

fn mit_name(ext: &str) -> PathBuf {
    PathBuf::from(format!(
        "motion_surface=abs_shape=rect2_a=0_v=20_i=0.000_s=0.500_t=0.000.{ext}"
    ))
}

#[test]
fn nasty_mit_json_files_are_refused_or_loaded_correctly() {
    for path in nasty_files("json") {
        let bytes = std::fs::read(&path).unwrap();
        // The importer takes the parameters from the name, so import under a valid one.
        let named = path.with_extension("").join(mit_name("json"));
        let result = import_bytes(&bytes, &named);
        let what = path.display().to_string();
        match (
            &result,
            path.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("ok_"),
        ) {
            (Ok(push), true) => check_promises(&push.trajectory, &what),
            (Err(e), false) => assert!(e.to_string().starts_with(&named.display().to_string())),
            (Ok(_), false) => panic!("{what} loaded but should be refused"),
            (Err(e), true) => panic!("{what} should load: {e}"),
        }
    }
}

#[test]
fn nasty_h5_files_are_refused() {
    for path in nasty_files("h5") {
        let bytes = std::fs::read(&path).unwrap();
        let named = path.with_extension("").join(mit_name("h5"));
        let err = import_bytes(&bytes, &named).expect_err("nasty h5 must be refused");
        assert!(
            err.to_string().contains("HDF5") || err.to_string().contains('`'),
            "{err}"
        );
    }
}

/// A valid synthetic h5 push with 40 rows per stream.
fn valid_h5() -> Vec<u8> {
    let t0 = 1_461_697_707.0;
    let rows = |offset: f64| -> Vec<f64> {
        (0..40)
            .flat_map(|i| {
                let t = t0 + offset + i as f64 * 0.004;
                [t, 0.3 + i as f64 * 1e-4, -0.02, 3.0 + i as f64 * 0.01]
            })
            .collect()
    };
    let mut builder = hdf5_pure::FileBuilder::new();
    for (i, key) in ["tip_pose", "object_pose", "ft_wrench"]
        .into_iter()
        .enumerate()
    {
        builder
            .create_dataset(key)
            .with_f64_data(&rows(i as f64 * 0.001))
            .with_shape(&[40, 4]);
    }
    builder.finish().unwrap()
}

#[test]
fn every_truncation_of_a_valid_h5_is_refused_without_panic() {
    let bytes = valid_h5();
    let name = mit_name("h5");
    let push = import_bytes(&bytes, &name).expect("the untouched file loads");
    check_promises(&push.trajectory, "valid h5");
    for len in 0..bytes.len() {
        let result = import_bytes(&bytes[..len], &name);
        if let Ok(push) = result {
            // Only possible when the cut falls in trailing bytes nothing points into.
            check_promises(&push.trajectory, &format!("truncated to {len}"));
        }
    }
}

#[test]
fn every_single_byte_corruption_of_a_valid_h5_is_survived() {
    let bytes = valid_h5();
    let name = mit_name("h5");
    for index in 0..bytes.len() {
        for value in [
            0x00u8,
            0xFF,
            bytes[index] ^ 0x01,
            bytes[index].wrapping_add(0x80),
        ] {
            let mut corrupt = bytes.clone();
            corrupt[index] = value;
            if let Ok(push) = import_bytes(&corrupt, &name) {
                check_promises(&push.trajectory, &format!("byte {index} = {value:#x}"));
            }
        }
    }
}
