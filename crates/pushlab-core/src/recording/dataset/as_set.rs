//! A dataset's episodes as a recording set: one recording per episode, the Push-T T as the object.
//!
//! **The convention.** gym-pusht's state gives the block's pymunk `Body.position` — the T's local
//! origin, the middle of the bar's outer edge — and its angle, in pixels of the 512 × 512 arena,
//! pymunk's axes (the same right-handed x, y the environment's state uses; the rendering flips y,
//! the state does not). pushlab's object pose is the T's area centroid, local (0, 285/7) px, moved
//! there through the angle and scaled: `centroid = (origin + R(angle)·(0, 285/7)) · metres_per_px`,
//! yaw = the angle, unwrapped ([`crate::geometry::PushT`]). The pusher is the agent's centre, a disc
//! of 15 px. The setting's COM offset is gym-pusht's (COM at local (0, 45) px: (0, 30/7) px from the
//! centroid), the truth online learning should find.

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use nalgebra::Point2;

use super::cameras::DatasetCameras;
use super::choice::{Columns, DatasetChoice, ObjectSource};
use super::error::DatasetError;
use super::problem::DatasetProblem;
use super::table::{DatasetTable, Feature};
use crate::geometry::{PUSH_T, Pose2, PushT, fit_rigid, unwrap_angles};
use crate::recording::setting::{Setting, ShapePreset, TrajectoryEntry};
use crate::recording::{Recording, RecordingSet};
use crate::trajectory::{Frame, Trajectory};

/// A keypoint fit worse than this (RMS, pixels) is reported: the keypoints are not the T's corners
/// in gym-pusht's order.
const KEYPOINT_WARN_PX: f64 = 1.0;

/// The setting of a Push-T dataset at `metres_per_px`, one entry per episode imported.
pub fn setting_for(
    dataset: &Path,
    table: &DatasetTable,
    choice: &DatasetChoice,
    episodes: &[usize],
) -> Setting {
    let scale = choice.metres_per_px;
    // The folder's name, less a replay buffer's `.zarr`: `lerobot-v2.1` keeps its `.1`.
    let name = dataset.file_name().map_or_else(
        || "push-t".into(),
        |s| {
            let s = s.to_string_lossy();
            s.strip_suffix(".zarr").unwrap_or(&s).to_owned()
        },
    );
    let mut setting = Setting::of_object(
        name,
        ShapePreset::shape(PUSH_T, scale),
        PushT::AGENT_RADIUS_PX * scale,
    );
    let com = PushT::com_offset(scale);
    setting.com_offset = Some([com.x, com.y]);
    setting.material = Some("gym-pusht (pymunk)".into());
    setting.sample_rate_hz = Some(table.fps);
    setting
        .extra
        .insert("dataset".into(), dataset.display().to_string().into());
    setting
        .extra
        .insert("dataset_format".into(), table.format.to_string().into());
    setting
        .extra
        .insert("dataset_pusher".into(), choice.pusher.to_string().into());
    setting
        .extra
        .insert("dataset_object".into(), choice.object.to_string().into());
    setting.trajectories = (episodes.iter())
        .map(|&i| {
            let mut extra = serde_json::Map::new();
            extra.insert("episode".into(), i.into());
            TrajectoryEntry {
                file: format!("{}.csv", episode_name(i)),
                contact_offset: None,
                push_angle_deg: None,
                extra,
            }
        })
        .collect();
    setting
}

fn episode_name(index: usize) -> String {
    format!("episode_{index:03}")
}

/// The episodes of `range` (all when `None`), checked against the dataset's count.
pub fn episode_indexes(
    table: &DatasetTable,
    range: Option<Range<usize>>,
) -> Result<Vec<usize>, DatasetProblem> {
    let count = table.episodes.len();
    let range = range.unwrap_or(0..count);
    let chosen: Vec<usize> = range.clone().filter(|&i| i < count).collect();
    if chosen.is_empty() {
        return Err(DatasetProblem::NoEpisodes {
            asked: format!("{}..{}", range.start, range.end),
            count,
        });
    }
    Ok(chosen)
}

/// The episodes of `range` as a recording set, in memory; the set's folder is the dataset's.
pub fn to_set(
    dataset: &Path,
    table: &DatasetTable,
    choice: &DatasetChoice,
    range: Option<Range<usize>>,
) -> Result<RecordingSet, DatasetError> {
    let fail = |problem| DatasetError::Problem {
        path: dataset.to_path_buf(),
        problem,
    };
    let indexes = episode_indexes(table, range).map_err(fail)?;
    let pusher = columns(table, &choice.pusher, 2, "2 (x, y)").map_err(fail)?;
    let object = match &choice.object {
        ObjectSource::Pose(c) => {
            Object::Pose(columns(table, c, 3, "3 (x, y, angle)").map_err(fail)?)
        }
        ObjectSource::Keypoints(name) => {
            let c = Columns::new(name.clone(), 0);
            Object::Keypoints(columns(table, &c, 16, "16 (the T's 8 corners)").map_err(fail)?)
        }
    };
    let setting = Arc::new(setting_for(dataset, table, choice, &indexes));
    let cameras = DatasetCameras::open(dataset, table)?;
    let mut recordings = Vec::with_capacity(indexes.len());
    for (&index, entry) in indexes.iter().zip(&setting.trajectories) {
        let (trajectory, worst_residual_px) = episode(
            table,
            &table.episodes[index],
            pusher,
            &object,
            choice.metres_per_px,
        )
        .map_err(fail)?;
        let mut warnings = Vec::new();
        let mut entry = entry.clone();
        if let Some(residual) = worst_residual_px {
            let metres = residual * choice.metres_per_px;
            entry
                .extra
                .insert("keypoint_rms_residual_m".into(), metres.into());
            if residual > KEYPOINT_WARN_PX {
                warnings.push(format!(
                    "the keypoints fit the T's corners to {residual:.2} px RMS at worst; are they \
                     gym-pusht's 8 corners in its order?"
                ));
            }
        }
        recordings.push(Recording {
            source: PathBuf::from(format!("{}#{}", dataset.display(), episode_name(index))),
            name: episode_name(index),
            setting: Arc::clone(&setting),
            entry: Some(entry),
            trajectory: Arc::new(trajectory),
            warnings,
            notes: table.notes.clone(),
            cameras: cameras.of_episode(table, index),
        });
    }
    Ok(RecordingSet {
        dir: dataset.to_path_buf(),
        setting,
        recordings,
    })
}

enum Object<'a> {
    Pose((&'a Feature, usize)),
    Keypoints((&'a Feature, usize)),
}

/// The feature of `columns`, checked to hold `needed` values from its first column on.
fn columns<'a>(
    table: &'a DatasetTable,
    columns: &Columns,
    needed: usize,
    what: &str,
) -> Result<(&'a Feature, usize), DatasetProblem> {
    let feature =
        table
            .feature(&columns.feature)
            .ok_or_else(|| DatasetProblem::MissingFeature {
                name: columns.feature.clone(),
                available: table.feature_list(),
            })?;
    if columns.first + needed > feature.width {
        return Err(DatasetProblem::FeatureWidth {
            name: columns.feature.clone(),
            width: feature.width,
            expected: format!("expected {what} from column {}", columns.first),
        });
    }
    Ok((feature, columns.first))
}

/// One episode's frames, and the worst keypoint fit's RMS residual (pixels) when fitted.
fn episode(
    table: &DatasetTable,
    rows: &Range<usize>,
    (pusher, pusher_first): (&Feature, usize),
    object: &Object,
    scale: f64,
) -> Result<(Trajectory, Option<f64>), DatasetProblem> {
    let finite = |feature: &Feature, row: usize, values: &[f64]| match values
        .iter()
        .find(|v| !v.is_finite())
    {
        Some(&value) => Err(DatasetProblem::NotFinite {
            name: feature.name.clone(),
            row,
            value,
        }),
        None => Ok(()),
    };
    let local: Vec<Point2<f64>> = PushT::KEYPOINTS_PX
        .iter()
        .map(|&p| Point2::from(p))
        .collect();
    let mut origins = Vec::with_capacity(rows.len());
    let mut worst: Option<f64> = None;
    for row in rows.clone() {
        let origin = match object {
            Object::Pose((feature, first)) => {
                let v = &feature.row(row)[*first..first + 3];
                finite(feature, row, v)?;
                Pose2::new(v[0], v[1], v[2])
            }
            Object::Keypoints((feature, _)) => {
                let v = feature.row(row);
                finite(feature, row, v)?;
                let seen: Vec<Point2<f64>> =
                    v.chunks_exact(2).map(|p| Point2::new(p[0], p[1])).collect();
                let fit = fit_rigid(&local, &seen).ok_or_else(|| DatasetProblem::NotFinite {
                    name: feature.name.clone(),
                    row,
                    value: f64::NAN,
                })?;
                worst = Some(worst.map_or(fit.rms_residual, |w| w.max(fit.rms_residual)));
                fit.pose
            }
        };
        origins.push(origin);
    }
    let mut yaws: Vec<f64> = origins.iter().map(|o| o.yaw).collect();
    unwrap_angles(&mut yaws);
    let centroid = Point2::from(PushT::CENTROID_PX);
    let mut frames = Vec::with_capacity(rows.len());
    for ((row, origin), yaw) in rows.clone().zip(&origins).zip(yaws) {
        let p = &pusher.row(row)[pusher_first..pusher_first + 2];
        finite(pusher, row, p)?;
        let at = Pose2::new(origin.position.x, origin.position.y, yaw).point_in_world(centroid);
        let time = table.time(row, rows.start);
        // Written so that a NaN is refused too; a recording's time only goes forward.
        if let Some(previous) = frames.last().map(|f: &Frame| f.time)
            && !(time > previous && time.is_finite())
        {
            return Err(DatasetProblem::TimeNotIncreasing {
                row,
                time,
                previous,
            });
        }
        frames.push(Frame {
            time,
            robot: Point2::new(p[0] * scale, p[1] * scale),
            object: Pose2::new(at.x * scale, at.y * scale, yaw),
        });
    }
    Ok((Trajectory::new(frames), worst))
}
