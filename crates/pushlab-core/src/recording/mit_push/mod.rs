//! Import of the MIT Push Dataset (Yu, Bauza, Fazeli, Rodriguez, IROS 2016): one push per `.json` or
//! `.h5` file, three unsynchronised streams (`tip_pose`, `object_pose`, `ft_wrench`, each N × 4 with
//! its own timestamps) and the experiment's parameters in the file name.
//!
//! What the importer does, in order, and why:
//! 1. Refuses files it cannot use (missing streams, rows that are not 4 numbers, non-finite values,
//!    fewer than [`MIN_ROWS`] rows, streams overlapping for less than
//!    [`MIN_DURATION_S`](super::resample::MIN_DURATION_S)).
//! 2. Drops samples whose timestamp does not increase (real files step back by up to ~2 ms); a
//!    stream must be monotone to be interpolated. Counted and reported as a warning.
//! 3. Unwraps the object's yaw, which the dataset keeps in (−π, π] (a note: nothing is lost).
//! 4. Resamples the tip and object streams by linear interpolation onto one grid of
//!    [`RESAMPLE_HZ`] (the dataset's nominal rate) over the interval both cover, as every user of
//!    this dataset does; yaw is interpolated after unwrapping. Time starts at 0 (the Unix time of
//!    the first sample is kept in the trajectory entry as `mit_start_unix_s`).
//! 5. Moves the object pose from the dataset's object frame to the geometric centre of the
//!    footprint, pushlab's convention. For rectangles, ellipses and the hexagon these coincide; the
//!    triangles' frame is not at their centroid (their right-angle corner sits at (45, 45) mm in it),
//!    so for them the position changes by the centroid rotated into the world.
//!
//! The force stream is only checked (for being frozen), never imported: pushlab's model does not use
//! forces, so a frozen sensor is a note, not a warning.

mod error;
mod problem;
mod set;

use std::collections::HashMap;
use std::path::Path;

use nalgebra::{Point2, Vector2};
use serde::Deserialize;

pub use self::error::MitError;
pub use self::problem::MitProblem;
pub(crate) use self::set::recordings_for;
pub use self::set::{KEY_REP, KEY_SHAPE, KEY_SIDE, KEY_SIDE_POSITION, KEY_SPEED, MitShape, shape};
use super::resample::{self, GAP_WARN_S, Interpolator, MAX_POSITION_M, MIN_ROWS, grid, unwrap_yaw};
use crate::geometry::Pose2;
use crate::trajectory::{Frame, Trajectory};

/// Rate of the common time grid the streams are resampled onto, Hz: the dataset's nominal rate.
pub const RESAMPLE_HZ: f64 = 250.0;
/// Radius of the dataset's steel pusher, metres.
pub const PUSHER_RADIUS: f64 = 0.00475;
/// Pusher–object friction coefficient reported by the dataset's authors.
pub const PUSHER_FRICTION: f64 = 0.25;

/// The experiment's parameters, read from a file name such as
/// `motion_surface=abs_shape=rect1_a=0_v=75_i=2.000_s=0.800_t=0.349`.
#[derive(Clone, Debug, PartialEq)]
pub struct MitName {
    /// Surface material: abs, delrin, plywood or pu.
    pub surface: String,
    /// Object: rect1..3, tri1..3, ellip1..3, hex or butter.
    pub shape: String,
    /// Pusher acceleration, mm/s² (0 = constant speed).
    pub accel_mm_s2: f64,
    /// Pusher speed, mm/s.
    pub speed_mm_s: f64,
    /// Index of the pushed side of the object (the dataset's `i`).
    pub side: f64,
    /// Position of the contact along that side, 0..1 (the dataset's `s`).
    pub side_position: f64,
    /// Push angle from the side's normal, radians (the dataset's `t`).
    pub angle_rad: f64,
    /// Repetition number, when the name has one.
    pub rep: Option<u32>,
}

/// Parses an MIT Push Dataset file stem (the name without `.json`/`.h5`).
pub fn parse_file_name(stem: &str) -> Result<MitName, MitProblem> {
    let bad = |why: String| MitProblem::FileName { why };
    let rest = stem
        .strip_prefix("motion_")
        .ok_or_else(|| bad("it does not start with 'motion_'".into()))?;
    let mut fields: HashMap<&str, &str> = HashMap::new();
    for part in rest.split('_') {
        let (key, value) = part
            .split_once('=')
            .ok_or_else(|| bad(format!("'{part}' is not key=value")))?;
        fields.insert(key, value);
    }
    let text = |key: &str| {
        fields
            .get(key)
            .copied()
            .ok_or_else(|| bad(format!("no '{key}='")))
    };
    let number = |key: &str| -> Result<f64, MitProblem> {
        let t = text(key)?;
        t.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| bad(format!("{key}='{t}' is not a finite number")))
    };
    let rep = match fields.get("rep") {
        None => None,
        Some(t) => Some(
            t.parse::<u32>()
                .map_err(|_| bad(format!("rep='{t}' is not a whole number")))?,
        ),
    };
    Ok(MitName {
        surface: text("surface")?.to_string(),
        shape: text("shape")?.to_string(),
        accel_mm_s2: number("a")?,
        speed_mm_s: number("v")?,
        side: number("i")?,
        side_position: number("s")?,
        angle_rad: number("t")?,
        rep,
    })
}

/// The three raw streams of one file, rows `[t, a, b, c]` as stored.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Streams {
    /// `[t, x, y, yaw]` of the pusher centre (yaw ≈ 0, ignored).
    pub tip_pose: Vec<[f64; 4]>,
    /// `[t, x, y, yaw]` of the dataset's object frame.
    pub object_pose: Vec<[f64; 4]>,
    /// `[t, fx, fy, torque_z]` the object exerts on the pusher.
    pub ft_wrench: Vec<[f64; 4]>,
}

const KEYS: [&str; 3] = ["tip_pose", "object_pose", "ft_wrench"];

/// Reads the streams of a `.json` file held in memory.
pub fn parse_json(bytes: &[u8]) -> Result<Streams, MitProblem> {
    // Keys are required: serde's "missing field `tip_pose`" is turned into our message.
    #[derive(Deserialize)]
    struct Raw {
        tip_pose: Option<Vec<[f64; 4]>>,
        object_pose: Option<Vec<[f64; 4]>>,
        ft_wrench: Option<Vec<[f64; 4]>>,
    }
    let raw: Raw = serde_json::from_slice(bytes).map_err(|e| MitProblem::Json(e.to_string()))?;
    Ok(Streams {
        tip_pose: raw.tip_pose.ok_or(MitProblem::MissingKey(KEYS[0]))?,
        object_pose: raw.object_pose.ok_or(MitProblem::MissingKey(KEYS[1]))?,
        ft_wrench: raw.ft_wrench.ok_or(MitProblem::MissingKey(KEYS[2]))?,
    })
}

/// Reads the streams of a `.h5` file held in memory with the pure-Rust `hdf5-pure` reader (no system
/// HDF5 library needed).
pub fn parse_h5(bytes: &[u8]) -> Result<Streams, MitProblem> {
    let h5 = |e: hdf5_pure::Error| MitProblem::Hdf5(e.to_string());
    let file = hdf5_pure::File::from_bytes(bytes.to_vec()).map_err(h5)?;
    let read = |key: &'static str| -> Result<Vec<[f64; 4]>, MitProblem> {
        let dataset = file.dataset(key).map_err(|_| MitProblem::MissingKey(key))?;
        let shape = dataset.shape().map_err(h5)?;
        let rows = match shape.as_slice() {
            [rows, 4] => *rows,
            _ => {
                return Err(MitProblem::BadShape {
                    key,
                    shape: format!("{shape:?}"),
                });
            }
        };
        // The dataset's files are uncompressed float64: a claimed size beyond the file is corrupt
        // (and reading it would try to allocate it).
        if rows.saturating_mul(32) > bytes.len() as u64 {
            return Err(MitProblem::BadShape {
                key,
                shape: format!("{shape:?} (larger than the file)"),
            });
        }
        let values = dataset.read_f64().map_err(h5)?;
        if values.len() as u64 != rows * 4 {
            return Err(MitProblem::BadShape {
                key,
                shape: format!("{shape:?} with {} values", values.len()),
            });
        }
        Ok(values
            .chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect())
    };
    Ok(Streams {
        tip_pose: read(KEYS[0])?,
        object_pose: read(KEYS[1])?,
        ft_wrench: read(KEYS[2])?,
    })
}

/// One imported push, before it is grouped into a set with the others of its surface and shape.
#[derive(Clone, Debug, PartialEq)]
pub struct MitPush {
    /// The parameters from the file name.
    pub name: MitName,
    /// Resampled frames, object pose at the footprint's geometric centre, time from 0.
    pub trajectory: Trajectory,
    /// Unix time of the first frame, seconds.
    pub start_unix_s: f64,
    /// Recoverable defects found, each a sentence with numbers (see [`Recording::warnings`]).
    pub warnings: Vec<String>,
    /// What reading did that loses nothing (see [`Recording::notes`]).
    pub notes: Vec<String>,
}

/// Imports one MIT file held in memory; the extension of `path` (`.json` or `.h5`) picks the
/// reader and its stem gives the parameters. `path` is also used in messages.
pub fn import_bytes(bytes: &[u8], path: &Path) -> Result<MitPush, MitError> {
    let fail = |problem| MitError::Problem {
        path: path.to_path_buf(),
        problem,
    };
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let name = parse_file_name(&stem).map_err(fail)?;
    let shape = shape(&name.shape).map_err(fail)?;
    let streams = if path.extension().is_some_and(|e| e == "h5") {
        parse_h5(bytes)
    } else {
        parse_json(bytes)
    }
    .map_err(fail)?;
    let (trajectory, start_unix_s, [warnings, notes]) =
        align(&streams, shape.centroid_in_mit_frame).map_err(fail)?;
    Ok(MitPush {
        name,
        trajectory,
        start_unix_s,
        warnings,
        notes,
    })
}

/// Reads and imports one MIT file from disk.
pub fn import_file(path: &Path) -> Result<MitPush, MitError> {
    let bytes = super::read::read_file(path)?;
    import_bytes(&bytes, path)
}

/// Cleans, checks and resamples the streams; returns the frames, the Unix start time, the warnings
/// and the notes.
fn align(
    streams: &Streams,
    centroid_in_mit_frame: Vector2<f64>,
) -> Result<(Trajectory, f64, [Vec<String>; 2]), MitProblem> {
    for (key, rows) in
        KEYS.iter()
            .zip([&streams.tip_pose, &streams.object_pose, &streams.ft_wrench])
    {
        for (row, values) in rows.iter().enumerate() {
            if let Some(column) = values.iter().position(|v| !v.is_finite()) {
                return Err(MitProblem::NonFinite {
                    key,
                    row,
                    column,
                    value: values[column],
                });
            }
        }
    }
    check_ranges(streams)?;
    let (mut warnings, mut notes) = (Vec::new(), Vec::new());
    let (n_tip, n_obj, n_ft) = (
        streams.tip_pose.len(),
        streams.object_pose.len(),
        streams.ft_wrench.len(),
    );
    let tip = clean(KEYS[0], &streams.tip_pose, &mut warnings)?;
    let mut object = clean(KEYS[1], &streams.object_pose, &mut warnings)?;
    if streams.ft_wrench.is_empty() {
        return Err(MitProblem::TooFewRows {
            key: KEYS[2],
            rows: 0,
            min: 1,
        });
    }
    if let Some(apart) = streams_apart(streams) {
        notes.push(format!(
            "streams start or stop up to {:.1} ms apart (tip_pose {n_tip}, object_pose {n_obj}, ft_wrench {n_ft} rows); aligned by resampling at {RESAMPLE_HZ} Hz over the span both poses cover",
            apart * 1e3
        ));
    }
    let repeated = repeated_wrench_rows(&streams.ft_wrench);
    if n_ft >= 2 && repeated as f64 > FROZEN_SHARE * (n_ft - 1) as f64 {
        notes.push(format!(
            "ft_wrench is frozen: {repeated} of {} rows repeat the previous force/torque exactly (the force sensor was not recording)",
            n_ft - 1
        ));
    }
    unwrap_yaw("object", &mut object, &mut notes);
    let (start, count) = grid(&tip, &object, RESAMPLE_HZ).map_err(MitProblem::Span)?;
    let mut tip_at = Interpolator::new(&tip);
    let mut object_at = Interpolator::new(&object);
    let frames = (0..count)
        .map(|k| {
            let t = start + k as f64 / RESAMPLE_HZ;
            let r = tip_at.at(t);
            let o = object_at.at(t);
            let mit_pose = Pose2::new(o[1], o[2], o[3]);
            let centre = mit_pose.point_in_world(Point2::from(centroid_in_mit_frame));
            Frame {
                time: k as f64 / RESAMPLE_HZ,
                robot: Point2::new(r[1], r[2]),
                object: Pose2::new(centre.x, centre.y, o[3]),
            }
        })
        .collect();
    Ok((Trajectory::new(frames), start, [warnings, notes]))
}

/// Refuses values no real file holds: positions beyond [`MAX_POSITION_M`] of the robot base and
/// object yaw outside the dataset's (−π, π] (with slack). Such values are corruption, and would
/// break angle unwrapping and interpolation later.
fn check_ranges(streams: &Streams) -> Result<(), MitProblem> {
    for (key, rows) in [
        (KEYS[0], &streams.tip_pose),
        (KEYS[1], &streams.object_pose),
    ] {
        for (row, values) in rows.iter().enumerate() {
            for (column, value) in values.iter().enumerate().take(3).skip(1) {
                if value.abs() > MAX_POSITION_M {
                    return Err(MitProblem::OutOfRange {
                        key,
                        row,
                        column,
                        value: *value,
                        expected: "a position within 100 m of the robot base",
                    });
                }
            }
        }
    }
    for (row, values) in streams.object_pose.iter().enumerate() {
        if values[3].abs() > 2.0 * std::f64::consts::PI {
            return Err(MitProblem::OutOfRange {
                key: KEYS[1],
                row,
                column: 3,
                value: values[3],
                expected: "a yaw in (−π, π] radians",
            });
        }
    }
    Ok(())
}

/// Keeps the rows whose timestamp increases (see [`resample::clean`]) and refuses a stream left
/// with fewer than [`MIN_ROWS`].
fn clean(
    key: &'static str,
    rows: &[[f64; 4]],
    warnings: &mut Vec<String>,
) -> Result<Vec<[f64; 4]>, MitProblem> {
    let kept = resample::clean(key, rows, warnings);
    if kept.len() < MIN_ROWS {
        return Err(MitProblem::TooFewRows {
            key,
            rows: kept.len(),
            min: MIN_ROWS,
        });
    }
    Ok(kept)
}

/// How many force/torque rows repeat the previous row exactly. A live sensor's readings never
/// repeat to the last bit (noise alone changes them); a dead one repeats a stale value, with the odd
/// real reading in between (the dataset's rect1 file here: 287 of 293).
fn repeated_wrench_rows(rows: &[[f64; 4]]) -> usize {
    rows.windows(2).filter(|w| w[0][1..] == w[1][1..]).count()
}

/// Share of repeated rows above which the force stream counts as frozen.
const FROZEN_SHARE: f64 = 0.5;

/// How far apart, seconds, the streams start or stop, when it is more than a gap worth a warning
/// ([`GAP_WARN_S`]): a stream that starts late or stops early by that much leaves the push without
/// it there, like a gap. A few rows apart is how every file of the dataset starts and stops its
/// sensors (at most 35 ms at the start and 14 ms at the end in the 54 real files here), which the
/// resampling over the span both poses cover absorbs: said of every file, as it was, it hid the
/// defects among routine.
fn streams_apart(streams: &Streams) -> Option<f64> {
    let all = [&streams.tip_pose, &streams.object_pose, &streams.ft_wrench];
    // How far apart the streams' first (or last) stamps are.
    let apart = |end: fn(&[[f64; 4]]) -> Option<&[f64; 4]>| {
        let stamps = all.iter().filter_map(|rows| end(rows)).map(|row| row[0]);
        let (low, high) = stamps.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), t| {
            (l.min(t), h.max(t))
        });
        high - low
    };
    let most = apart(<[_]>::first).max(apart(<[_]>::last));
    (most > GAP_WARN_S).then_some(most)
}
