//! The `zarr` and `lerobot` fuzz targets' promise on stable Rust, over their seeds: the promise is
//! the fuzz crate's own (`fuzz/src/datasets.rs`, included here), so that what the fuzzer checks is
//! what CI checks. Each seed is a file of the Push-T fixtures (`tests/pusht/`) as `fuzz/run` writes
//! it: read as it is it must give every episode; cut short or with bytes changed it must give an
//! error or a dataset that keeps the promise, never a panic. The inputs the fuzzer found
//! (`fuzz/seeds/zarr/`) are run too.

#![allow(clippy::unwrap_used, clippy::expect_used)]

// The fuzzer's own entry points (one copy per process, never removed) are not used here.
#[allow(dead_code)]
#[path = "../../../fuzz/src/datasets.rs"]
mod datasets;

use std::path::Path;

use datasets::{FixtureCopy, LEROBOT, ZARR, as_input, fixture_files};
use pushlab_core::recording::NoProgress;
use pushlab_core::recording::dataset::{self, blosc};

use crate::allocations;

/// The fixture's episodes.
const EPISODES: usize = 8;

/// Each seed of `folders` read as it is, then cut short and with bytes changed; returns the inputs
/// read.
fn seeds_keep_the_promise(
    folders: &[&str],
    run: impl Fn(&FixtureCopy, &[u8]) -> Option<usize>,
) -> usize {
    let copy = FixtureCopy::of(folders);
    let mut state = 0x2545_F491_4F6C_DD1D_u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let mut seen = 0;
    for (name, bytes) in fixture_files(folders) {
        let episodes = run(&copy, &as_input(&name, &bytes));
        // A v2 data file is read with its episode alone listed.
        let expected = if name.contains("/data/chunk-000/episode_") {
            1
        } else {
            EPISODES
        };
        assert_eq!(episodes, Some(expected), "{name} as it is");
        for len in [
            0,
            1,
            8,
            16,
            bytes.len() / 3,
            bytes.len() / 2,
            bytes.len() - 1,
        ] {
            run(&copy, &as_input(&name, &bytes[..len.min(bytes.len())]));
        }
        for _ in 0..6 {
            let mut changed = bytes.clone();
            let at = next() as usize % changed.len();
            changed[at] = (next() >> 32) as u8;
            run(&copy, &as_input(&name, &changed));
        }
        seen += 1;
    }
    seen
}

#[test]
fn zarr_seeds_cut_or_changed_keep_the_promise() {
    let seen = seeds_keep_the_promise(ZARR, datasets::zarr_in);
    assert!(seen >= 20, "{seen} seeds");
}

#[test]
fn lerobot_seeds_cut_or_changed_keep_the_promise() {
    let seen = seeds_keep_the_promise(LEROBOT, datasets::lerobot_in);
    assert!(seen >= 13, "{seen} seeds");
}

/// What the fuzzer found in the zarr reader, each kept in `fuzz/seeds/zarr/` and run here.
#[test]
fn zarr_inputs_the_fuzzer_found_keep_the_promise() {
    let found = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/seeds/zarr");
    let copy = FixtureCopy::of(ZARR);
    let mut count = 0;
    for entry in std::fs::read_dir(&found).unwrap() {
        let input = std::fs::read(entry.unwrap().path()).unwrap();
        assert_eq!(datasets::zarr_in(&copy, &input), None);
        count += 1;
    }
    assert!(count >= 1);
}

/// `fuzz-blosc-block-size`: a chunk of `data/action` whose blosc header keeps the chunk's 512 bytes
/// but claims blocks of 0xBCBCBC00 bytes (3.2 GB). The decoder allocated a block's scratch of the
/// claimed size before reading it; a block is never longer than the chunk, and it is refused,
/// having allocated no more than the chunk.
#[test]
fn a_blosc_block_size_past_the_chunk_allocates_no_more_than_the_chunk() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/seeds/zarr/fuzz-blosc-block-size");
    let input = std::fs::read(path).unwrap();
    let frame = &input[input.iter().position(|&b| b == b'\n').unwrap() + 1..];
    assert_eq!(frame[4..8], 512u32.to_le_bytes());
    assert_eq!(frame[8..12], 0xBCBC_BC00u32.to_le_bytes());
    allocations::forget_largest();
    let refusal = blosc::decompress(frame, 512).unwrap_err().to_string();
    assert!(refusal.starts_with("blosc: "), "{refusal}");
    let largest = allocations::largest_on_this_thread();
    assert!(largest <= 4096, "an allocation of {largest} bytes");
}

/// Found by the fuzzer (`fuzz/found/lerobot/timestamp-not-increasing`): episode 7's data file of
/// the v2.1 fixture with bytes of its `timestamp` column changed reads, and its recording's time
/// went back (0.2 s, then about −1.6·10⁻²³ s). The episode is now refused (`DatasetProblem::
/// TimeNotIncreasing`, naming the row); it fails the promise without that check.
#[test]
fn lerobot_timestamps_that_do_not_increase_are_refused() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fuzz/found/lerobot/timestamp-not-increasing");
    let input = std::fs::read(path).unwrap();
    let copy = FixtureCopy::of(LEROBOT);
    assert_eq!(datasets::lerobot_in(&copy, &input), None, "refused");

    // What the user reads: the row and both times.
    let split = input.iter().position(|&b| b == b'\n').unwrap();
    let name = std::str::from_utf8(&input[..split]).unwrap();
    let dir = std::env::temp_dir().join(format!("pushlab-timestamps-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    for (file, bytes) in fixture_files(&["lerobot-v2.1"]) {
        let path = dir.join(&file);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        let bytes = if file == name {
            &input[split + 1..]
        } else {
            &bytes[..]
        };
        std::fs::write(path, bytes).unwrap();
    }
    let dataset = dir.join("lerobot-v2.1");
    let table = dataset::read_table(&dataset, &NoProgress).unwrap();
    let choice = dataset::choice::suggest(&table).unwrap();
    let error = dataset::to_set(&dataset, &table, &choice, None)
        .unwrap_err()
        .to_string();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        error.ends_with(
            "frame times: row 171 (counting from 0) is at -1.588e-23 s, expected a finite time after row 170's 0.2 s"
        ),
        "{error}"
    );
}
