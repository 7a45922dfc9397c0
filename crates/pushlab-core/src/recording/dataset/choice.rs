//! Which features of a dataset are the pusher and the object, and at what scale: chosen once and
//! remembered beside the dataset, as a bag's topics are (`replay.zarr` →
//! `replay.zarr.pushlab-dataset.json`, never inside it).
//!
//! The pusher is two values of a feature (its x and y, from a given column). The object is the
//! Push-T T, given either as a pose — three values, x, y and angle of the T's local origin, as
//! gym-pusht's state holds them — or as the T's eight corner keypoints (16 values), registered to
//! a pose by a least-squares rigid fit. [`suggest`] pre-selects Push-T's own layouts: a replay
//! buffer's `state` (agent x, y, block x, y, angle) and a LeRobot dataset's `observation.state`
//! with `observation.environment_state`.

use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use super::error::DatasetError;
use super::problem::DatasetProblem;
use super::table::DatasetTable;
use crate::atomic_file::write_atomically;
use crate::geometry::PushT;
use crate::json_problem;
use crate::recording::read::{file_beside, read_file};

/// Appended to a dataset's folder name to name its remembered choice.
pub const CHOICE_SUFFIX: &str = ".pushlab-dataset.json";

/// The `format` value of a choice file, so that another tool's JSON is not taken for one.
const FORMAT: &str = "pushlab-dataset-choice";

/// Values of a feature from column `first` on: `state:2`, or `observation.state` for column 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Columns {
    pub feature: String,
    pub first: usize,
}

impl Columns {
    /// Columns of `feature` from column `first` on.
    pub fn new(feature: impl Into<String>, first: usize) -> Self {
        Self {
            feature: feature.into(),
            first,
        }
    }
}

impl fmt::Display for Columns {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.first == 0 {
            write!(f, "{}", self.feature)
        } else {
            write!(f, "{}:{}", self.feature, self.first)
        }
    }
}

impl FromStr for Columns {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let (feature, first) = match text.rsplit_once(':') {
            Some((feature, first)) => match first.parse::<usize>() {
                Ok(first) => (feature, first),
                Err(_) => return Err(format!("'{first}' is not a column number in '{text}'")),
            },
            None => (text, 0),
        };
        if feature.is_empty() {
            return Err(format!(
                "no feature named in '{text}', expected FEATURE[:COLUMN]"
            ));
        }
        Ok(Self::new(feature, first))
    }
}

/// How the object (the Push-T T) is read.
#[derive(Clone, Debug, PartialEq)]
pub enum ObjectSource {
    /// x, y (pixels) and angle (radians) of the T's local origin, from these columns.
    Pose(Columns),
    /// The T's eight corners (x0, y0 … x7, y7, pixels, in gym-pusht's order) of this feature.
    Keypoints(String),
}

impl fmt::Display for ObjectSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ObjectSource::Pose(columns) => write!(f, "pose:{columns}"),
            ObjectSource::Keypoints(feature) => write!(f, "keypoints:{feature}"),
        }
    }
}

impl FromStr for ObjectSource {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        if let Some(columns) = text.strip_prefix("pose:") {
            return columns.parse().map(ObjectSource::Pose);
        }
        match text.strip_prefix("keypoints:") {
            Some(feature) if !feature.is_empty() => Ok(ObjectSource::Keypoints(feature.into())),
            _ => Err(format!(
                "'{text}': expected pose:FEATURE[:COLUMN] (x, y, angle of the T's origin) or \
                 keypoints:FEATURE (the T's 8 corners)"
            )),
        }
    }
}

/// What a user chose for a dataset.
#[derive(Clone, Debug, PartialEq)]
pub struct DatasetChoice {
    pub pusher: Columns,
    pub object: ObjectSource,
    /// Metres per pixel of the 512 × 512 arena.
    pub metres_per_px: f64,
}

/// The file as written: flat, readable, with a version.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ChoiceFile {
    format: String,
    version: u32,
    pusher: String,
    object: String,
    metres_per_px: f64,
}

/// The remembered-choice file of a dataset: beside its folder, named after it.
pub fn choice_path(dataset: &Path) -> PathBuf {
    file_beside(dataset, CHOICE_SUFFIX, "dataset")
}

/// The choice remembered beside `dataset`, if any; a file that cannot be used is an error naming
/// it and the field.
pub fn remembered(dataset: &Path) -> Result<Option<DatasetChoice>, DatasetError> {
    let path = choice_path(dataset);
    if !crate::files::is_file(&path) {
        return Ok(None);
    }
    let bytes = read_file(&path)?;
    let bad = |problem| DatasetError::Problem {
        path: path.clone(),
        problem,
    };
    let field = |field: &str, why: String| {
        bad(DatasetProblem::Field {
            field: field.into(),
            why,
        })
    };
    let file: ChoiceFile = json_problem::from_file_bytes(&bytes)
        .map_err(|problem| bad(DatasetProblem::Json(problem)))?;
    if file.format != FORMAT || file.version != 1 {
        return Err(field(
            "format",
            format!(
                "\"{}\" version {}, expected \"{FORMAT}\" version 1",
                file.format, file.version
            ),
        ));
    }
    Ok(Some(DatasetChoice {
        pusher: file.pusher.parse().map_err(|why| field("pusher", why))?,
        object: file.object.parse().map_err(|why| field("object", why))?,
        metres_per_px: checked_scale(file.metres_per_px)
            .map_err(|why| field("metres_per_px", why))?,
    }))
}

/// A scale that is a positive finite number of metres per pixel.
pub fn checked_scale(metres_per_px: f64) -> Result<f64, String> {
    if metres_per_px.is_finite() && metres_per_px > 0.0 {
        Ok(metres_per_px)
    } else {
        Err(format!(
            "{metres_per_px}, expected a positive number of metres per pixel"
        ))
    }
}

/// Remembers `choice` beside `dataset`, atomically.
pub fn remember(dataset: &Path, choice: &DatasetChoice) -> std::io::Result<PathBuf> {
    let path = choice_path(dataset);
    let file = ChoiceFile {
        format: FORMAT.into(),
        version: 1,
        pusher: choice.pusher.to_string(),
        object: choice.object.to_string(),
        metres_per_px: choice.metres_per_px,
    };
    let mut text = serde_json::to_string_pretty(&file).map_err(std::io::Error::other)?;
    text.push('\n');
    write_atomically(&path, text.as_bytes())?;
    Ok(path)
}

/// Push-T's own layouts, at the default scale: a replay buffer's `state` (agent x, y, block x, y,
/// angle), a LeRobot dataset's `observation.state` (agent x, y) with the T's keypoints in
/// `observation.environment_state`, or with the block's pose after the agent in a 5-wide
/// `observation.state`. `None` when the dataset has none of these.
pub fn suggest(table: &DatasetTable) -> Option<DatasetChoice> {
    let width = |name: &str| table.feature(name).map(|f| f.width);
    let choice = |pusher: Columns, object| DatasetChoice {
        pusher,
        object,
        metres_per_px: PushT::DEFAULT_METRES_PER_PX,
    };
    if width("state").is_some_and(|w| w >= 5) {
        return Some(choice(
            Columns::new("state", 0),
            ObjectSource::Pose(Columns::new("state", 2)),
        ));
    }
    let state = width("observation.state")?;
    if width("observation.environment_state") == Some(16) && state >= 2 {
        return Some(choice(
            Columns::new("observation.state", 0),
            ObjectSource::Keypoints("observation.environment_state".into()),
        ));
    }
    (state >= 5).then(|| {
        choice(
            Columns::new("observation.state", 0),
            ObjectSource::Pose(Columns::new("observation.state", 2)),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn choices_read_back_as_written_and_bad_text_is_named() {
        for text in ["state", "state:2", "observation.state"] {
            assert_eq!(
                text.parse::<Columns>().map(|c| c.to_string()),
                Ok(text.into())
            );
        }
        for text in ["pose:state:2", "keypoints:observation.environment_state"] {
            let source: ObjectSource = text.parse().expect(text);
            assert_eq!(source.to_string(), text);
        }
        assert!(
            "state:x"
                .parse::<Columns>()
                .is_err_and(|e| e.contains("'x'"))
        );
        assert!(
            "state"
                .parse::<ObjectSource>()
                .is_err_and(|e| e.contains("keypoints:FEATURE"))
        );
        assert!(checked_scale(0.0).is_err() && checked_scale(f64::NAN).is_err());
    }
}
