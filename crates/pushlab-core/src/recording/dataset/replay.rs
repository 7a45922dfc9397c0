//! Diffusion Policy's replay buffers (`ReplayBuffer`, a zarr v2 group): `data/` holds one array per
//! feature with one row per frame of every episode (`state`: agent x, y, block x, y, angle;
//! `action`; `keypoint`; `img`), `meta/episode_ends` the row after each episode's last. The buffer
//! records no time: gym-pusht's control rate, [`PUSHT_FPS`], is its frame rate.

use std::path::Path;

use super::error::DatasetError;
use super::problem::DatasetProblem;
use super::table::{DatasetFormat, DatasetTable, Feature};
use super::zarr::{ZarrArray, is_array};
use crate::recording::progress::Progress;

/// Frames per second of Push-T: gym-pusht (and Diffusion Policy's own environment) takes 10
/// actions a second (`metadata["render_fps"]`, its `control_hz`).
pub const PUSHT_FPS: f64 = 10.0;

/// Whether `dir` looks like a replay buffer: a zarr group with `data/` and `meta/episode_ends`.
pub fn is_replay_buffer(dir: &Path) -> bool {
    crate::files::is_file(&dir.join(".zgroup")) && is_array(&dir.join("meta").join("episode_ends"))
}

/// Bytes of the arrays read on opening, for the progress bar (images are read when shown).
pub fn bytes(dir: &Path) -> u64 {
    let mut total = 0;
    for array in array_dirs(dir)
        .into_iter()
        .chain([dir.join("meta/episode_ends")])
    {
        if ZarrArray::open(&array).is_ok_and(|a| !is_image(&a)) {
            total += crate::files::read_dir(&array).map_or(0, |entries| {
                entries
                    .iter()
                    .filter_map(|e| crate::files::metadata(&e.path).ok())
                    .map(|m| m.len)
                    .sum()
            });
        }
    }
    total
}

fn array_dirs(dir: &Path) -> Vec<std::path::PathBuf> {
    let data = dir.join("data");
    let mut arrays: Vec<_> = crate::files::read_dir(&data)
        .map(|entries| {
            entries
                .into_iter()
                .map(|e| e.path)
                .filter(|p| is_array(p))
                .collect()
        })
        .unwrap_or_default();
    arrays.sort();
    arrays
}

/// An image array: bytes with height, width (and channels) per frame.
fn is_image(array: &ZarrArray) -> bool {
    array.dtype.is_byte() && array.shape.len() >= 3
}

/// Reads the buffer's numeric arrays and its episodes; images are listed, read when shown.
pub fn read(dir: &Path, progress: &dyn Progress) -> Result<DatasetTable, DatasetError> {
    let ends_dir = dir.join("meta").join("episode_ends");
    let ends_array = ZarrArray::open(&ends_dir)?;
    let ends = ends_array.read_f64(progress)?;
    let fail = |path: &Path, problem| DatasetError::Problem {
        path: path.to_path_buf(),
        problem,
    };
    let mut episodes = Vec::with_capacity(ends.len());
    let mut start = 0usize;
    for (i, &end) in ends.iter().enumerate() {
        if !(end.fract() == 0.0 && end > start as f64 && end < 1e15) {
            return Err(fail(
                &ends_dir,
                DatasetProblem::Episodes(format!(
                    "episode_ends[{i}] is {end}, expected a whole number above {start}"
                )),
            ));
        }
        let end = end as usize;
        episodes.push(start..end);
        start = end;
    }
    let frames = start;
    let mut features = Vec::new();
    let mut cameras = Vec::new();
    for array_dir in array_dirs(dir) {
        let name = array_dir
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let array = ZarrArray::open(&array_dir)?;
        if array.shape[0] != frames {
            return Err(fail(
                &array_dir.join(".zarray"),
                DatasetProblem::Episodes(format!(
                    "`{name}` has {} rows but meta/episode_ends ends at {frames}",
                    array.shape[0]
                )),
            ));
        }
        if is_image(&array) {
            let dims: Vec<String> = array.shape[1..].iter().map(usize::to_string).collect();
            cameras.push((name, format!("images {}", dims.join("×"))));
            continue;
        }
        let values = array.read_f64(progress)?;
        features.push(Feature {
            name,
            width: array.width(),
            values,
        });
    }
    Ok(DatasetTable {
        format: DatasetFormat::ReplayBuffer,
        features,
        episodes,
        fps: PUSHT_FPS,
        times: None,
        cameras,
        videos: Vec::new(),
        images: Vec::new(),
        notes: Vec::new(),
    })
}
