//! The native recording set: a folder with `setting.json` and one CSV per trajectory.
//!
//! The CSV is parsed by hand rather than through serde: a set of 100,000 samples must load in well
//! under half a second, and a hand-written loop also lets every error name its line and column.
//! Values are written with Rust's shortest round-trip float formatting, so a write → read cycle
//! gives back bit-identical numbers.

mod error;
pub mod images;
mod problem;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use nalgebra::Point2;

pub use self::error::{NativeError, WriteError};
pub use self::problem::{CSV_HEADER, CsvProblem};
use super::camera::CameraStream;
use super::read::read_file;
use super::{Recording, RecordingSet, Setting};
use crate::geometry::{Pose2, unwrap_angles};
use crate::json_problem;
use crate::trajectory::{Frame, Trajectory};

/// The name of the file that makes a folder a recording set.
pub const SETTING_FILE: &str = "setting.json";

const COLUMNS: [&str; 6] = [
    "time",
    "robot_x",
    "robot_y",
    "object_x",
    "object_y",
    "object_theta",
];

/// Largest magnitude accepted per column: Unix times in seconds, metres, unwrapped radians. Larger
/// values are corrupt data, and would overflow or lose all precision in later arithmetic
/// (differences, angle unwrapping).
const LIMITS: [f64; 6] = [1e12, 1e6, 1e6, 1e6, 1e6, 1e6];

/// Longest piece of offending text quoted in an error; fuzzed junk must not make megabyte messages.
const MAX_QUOTED: usize = 40;

/// One CSV parsed from bytes: the frames and what was done to read them.
#[derive(Clone, Debug, PartialEq)]
pub struct ParsedCsv {
    /// The frames, object yaw unwrapped.
    pub trajectory: Trajectory,
    /// What reading did that loses nothing (wrapped yaw unwrapped), each a sentence with numbers.
    pub notes: Vec<String>,
}

/// Parses a native trajectory CSV held in memory; `path` is only used in messages.
///
/// Exposed so that fuzzing and tests can feed any byte sequence without touching the disk.
pub fn parse_csv(bytes: &[u8], path: &Path) -> Result<ParsedCsv, NativeError> {
    let err = |line: usize, problem: CsvProblem| NativeError::Csv {
        path: path.to_path_buf(),
        line,
        problem,
    };
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let mut lines = bytes.split(|&b| b == b'\n').enumerate();

    // Header: the first line, which must be exactly the documented one.
    let header = lines.next().map(|(_, l)| strip_cr(l)).unwrap_or_default();
    if header.iter().all(u8::is_ascii_whitespace) {
        return Err(err(1, CsvProblem::Empty));
    }
    if header != CSV_HEADER.as_bytes() {
        return Err(err(
            1,
            CsvProblem::Header {
                found: quote(&String::from_utf8_lossy(header)),
            },
        ));
    }

    // A typical line is ~100 bytes; reserving avoids regrowing for large sets.
    let mut frames = Vec::with_capacity(bytes.len() / 90);
    let mut thetas = Vec::with_capacity(bytes.len() / 90);
    for (index, raw) in lines {
        let line_no = index + 1;
        let line = strip_cr(raw);
        if line.iter().all(u8::is_ascii_whitespace) {
            continue; // blank lines (e.g. the trailing newline) carry nothing
        }
        let mut values = [0.0f64; 6];
        let mut count = 0;
        for field in line.split(|&b| b == b',') {
            if count < 6 {
                values[count] = parse_field(field, COLUMNS[count], LIMITS[count])
                    .map_err(|p| err(line_no, p))?;
            }
            count += 1;
        }
        if count != 6 {
            return Err(err(line_no, CsvProblem::FieldCount { found: count }));
        }
        if let Some(previous) = frames.last().map(|f: &Frame| f.time)
            && values[0] <= previous
        {
            return Err(err(
                line_no,
                CsvProblem::TimeNotIncreasing {
                    time: values[0],
                    previous,
                },
            ));
        }
        thetas.push(values[5]);
        frames.push(Frame {
            time: values[0],
            robot: Point2::new(values[1], values[2]),
            object: Pose2::new(values[3], values[4], values[5]),
        });
    }
    if frames.len() < 2 {
        let last_line = bytes.split(|&b| b == b'\n').count();
        return Err(err(
            last_line,
            CsvProblem::TooFewRows { rows: frames.len() },
        ));
    }

    let mut notes = Vec::new();
    let wraps = unwrap_angles(&mut thetas);
    if wraps > 0 {
        for (frame, theta) in frames.iter_mut().zip(&thetas) {
            frame.object.yaw = *theta;
        }
        notes.push(format!(
            "object_theta jumps by more than π {wraps} time(s) (wrapped angles); unwrapped on loading"
        ));
    }
    Ok(ParsedCsv {
        trajectory: Trajectory::new(frames),
        notes,
    })
}

fn strip_cr(line: &[u8]) -> &[u8] {
    line.strip_suffix(b"\r").unwrap_or(line)
}

fn parse_field(field: &[u8], column: &'static str, limit: f64) -> Result<f64, CsvProblem> {
    let text = std::str::from_utf8(field).map_err(|_| CsvProblem::NotUtf8)?;
    let trimmed = text.trim();
    match trimmed.parse::<f64>() {
        Ok(v) if v.is_finite() && v.abs() <= limit => Ok(v),
        Ok(v) if v.is_finite() => Err(CsvProblem::OutOfRange {
            column,
            text: quote(trimmed),
            limit,
        }),
        Ok(_) => Err(CsvProblem::NotFinite {
            column,
            text: quote(trimmed),
        }),
        Err(_) => Err(CsvProblem::NotANumber {
            column,
            text: quote(trimmed),
        }),
    }
}

/// Shortens text quoted in a message to [`MAX_QUOTED`] characters.
fn quote(text: &str) -> String {
    if text.chars().count() <= MAX_QUOTED {
        text.to_string()
    } else {
        let mut s: String = text.chars().take(MAX_QUOTED).collect();
        s.push('…');
        s
    }
}

/// Parses and checks a `setting.json` held in memory; `path` is only used in messages.
///
/// Unknown keys are kept (in `extra`) and never an error, so files written by newer tools still load.
pub fn parse_setting(bytes: &[u8], path: &Path) -> Result<Setting, NativeError> {
    let setting: Setting =
        json_problem::from_file_bytes(bytes).map_err(|problem| NativeError::SettingJson {
            path: path.to_path_buf(),
            problem,
        })?;
    check_setting(&setting).map_err(|(field, problem)| NativeError::SettingField {
        path: path.to_path_buf(),
        field,
        problem,
    })?;
    Ok(setting)
}

/// Checks the values serde cannot: a usable outline, positive sizes, plain file names.
pub(crate) fn check_setting(setting: &Setting) -> Result<(), (String, String)> {
    let field = |name: &str, problem: String| Err((name.to_string(), problem));
    if let Err(e) = setting.object.outline() {
        let name = match setting.object.field_of(&e) {
            Some(below) => format!("object.{below}"),
            None => "object".to_owned(),
        };
        let problem = match setting.object.outline_expected() {
            Some(expected) => format!("{e}, expected {expected}"),
            None => e.to_string(),
        };
        return field(&name, problem);
    }
    if !(setting.pusher_radius.is_finite() && setting.pusher_radius >= 0.0) {
        return field(
            "pusher_radius",
            format!(
                "is {}, expected a finite radius ≥ 0 in metres",
                setting.pusher_radius
            ),
        );
    }
    for (name, value) in [
        ("floor_friction", setting.floor_friction),
        ("pusher_friction", setting.pusher_friction),
    ] {
        if let Some(v) = value
            && !(v.is_finite() && v >= 0.0)
        {
            return field(name, format!("is {v}, expected a finite coefficient ≥ 0"));
        }
    }
    if let Some(c) = setting.com_offset
        && !(c[0].is_finite() && c[1].is_finite())
    {
        return field("com_offset", "expected two finite numbers in metres".into());
    }
    if let Some(h) = setting.h
        && !(h.is_finite() && h > 0.0)
    {
        return field(
            "h",
            format!("is {h}, expected a finite length > 0 in metres"),
        );
    }
    if let Some(r) = setting.sample_rate_hz
        && !(r.is_finite() && r > 0.0)
    {
        return field(
            "sample_rate_hz",
            format!("is {r}, expected a rate > 0 in Hz"),
        );
    }
    for (i, entry) in setting.trajectories.iter().enumerate() {
        if !is_plain_csv_name(&entry.file) {
            return field(
                &format!("trajectories[{i}].file"),
                format!(
                    "is '{}', expected a plain file name ending in .csv",
                    quote(&entry.file)
                ),
            );
        }
    }
    Ok(())
}

fn is_plain_csv_name(name: &str) -> bool {
    !name.is_empty()
        && name.ends_with(".csv")
        && !name.contains(['/', '\\'])
        && name != ".."
        && Path::new(name).file_name().is_some_and(|f| f == name)
}

/// Reads a native recording set from its folder.
///
/// Fails as a whole only when `setting.json` is unusable; a trajectory that cannot be read is returned
/// as an error beside the set so that one bad file does not hide the good ones. The trajectories are
/// those listed in `setting.json`, in order; a set that lists none loads every `.csv` in the folder.
pub fn read_set(dir: &Path) -> Result<(RecordingSet, Vec<NativeError>), NativeError> {
    read_set_filtered(dir, None)
}

/// Reads the set in `dir`, keeping only the trajectory stored in `only` when given (a CSV opened on
/// its own still needs its set's `setting.json`).
pub(crate) fn read_set_filtered(
    dir: &Path,
    only: Option<&Path>,
) -> Result<(RecordingSet, Vec<NativeError>), NativeError> {
    let setting_path = dir.join(SETTING_FILE);
    let bytes = crate::files::read(&setting_path).map_err(|e| NativeError::io(&setting_path, e))?;
    let setting = Arc::new(parse_setting(&bytes, &setting_path)?);

    let files: Vec<(PathBuf, Option<usize>)> = if setting.trajectories.is_empty() {
        csv_files_in(dir)?.into_iter().map(|p| (p, None)).collect()
    } else {
        (setting.trajectories.iter().enumerate())
            .map(|(i, e)| (dir.join(&e.file), Some(i)))
            .collect()
    };

    let mut recordings = Vec::new();
    let mut errors = Vec::new();
    for (path, index) in files {
        if only.is_some_and(|o| o.file_name() != path.file_name()) {
            continue;
        }
        match read_file(&path) {
            Ok(bytes) => match parse_csv(&bytes, &path) {
                Ok(parsed) => recordings.push(Recording {
                    name: file_stem(&path),
                    cameras: cameras_of(&path, &mut errors),
                    source: path,
                    setting: Arc::clone(&setting),
                    entry: index.map(|i| setting.trajectories[i].clone()),
                    trajectory: Arc::new(parsed.trajectory),
                    warnings: Vec::new(),
                    notes: parsed.notes,
                }),
                Err(e) => errors.push(e),
            },
            Err(e) if e.is_not_found() => {
                errors.push(NativeError::MissingTrajectory { path });
            }
            Err(e) => errors.push(e.into()),
        }
    }
    if let Some(only) = only
        && recordings.is_empty()
        && errors.is_empty()
    {
        // The CSV is in the folder but setting.json does not list it: load it with no entry.
        let bytes = read_file(only)?;
        let parsed = parse_csv(&bytes, only)?;
        recordings.push(Recording {
            name: file_stem(only),
            cameras: cameras_of(only, &mut errors),
            source: only.to_path_buf(),
            setting: Arc::clone(&setting),
            entry: None,
            trajectory: Arc::new(parsed.trajectory),
            warnings: Vec::new(),
            notes: parsed.notes,
        });
    }
    Ok((
        RecordingSet {
            dir: dir.to_path_buf(),
            setting,
            recordings,
        },
        errors,
    ))
}

/// The cameras of the recording in `csv`; a camera whose frame list is broken is left out and its
/// error listed with the set's, so that the poses still open.
fn cameras_of(csv: &Path, errors: &mut Vec<NativeError>) -> Vec<Arc<CameraStream>> {
    match images::read_cameras(csv) {
        Ok(cameras) => cameras.into_iter().map(Arc::new).collect(),
        Err(e) => {
            errors.push(e);
            Vec::new()
        }
    }
}

fn csv_files_in(dir: &Path) -> Result<Vec<PathBuf>, NativeError> {
    let mut files = Vec::new();
    for entry in crate::files::read_dir(dir).map_err(|e| NativeError::io(dir, e))? {
        let path = entry.path;
        if path.extension().is_some_and(|e| e == "csv") && !entry.is_dir {
            files.push(path);
        }
    }
    files.sort();
    Ok(files)
}

pub(crate) fn file_stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// Writes a native recording set: `setting.json` and, for each `trajectories[i]`, the CSV named by
/// `setting.trajectories[i].file`.
///
/// Creates the folder if needed and writes every file atomically (a temporary file in the same
/// folder, then a rename), so a crash never leaves a half-written recording. Refuses trajectories the
/// reader would refuse (non-finite values, time not strictly increasing) so that what is written
/// always loads again.
pub fn write_set(
    dir: &Path,
    setting: &Setting,
    trajectories: &[Trajectory],
) -> Result<(), WriteError> {
    if setting.trajectories.len() != trajectories.len() {
        return Err(WriteError::CountMismatch {
            entries: setting.trajectories.len(),
            trajectories: trajectories.len(),
        });
    }
    for (entry, trajectory) in setting.trajectories.iter().zip(trajectories) {
        if !is_plain_csv_name(&entry.file) {
            return Err(WriteError::BadFileName(entry.file.clone()));
        }
        check_trajectory(trajectory).map_err(|(frame, problem)| WriteError::BadTrajectory {
            file: entry.file.clone(),
            frame,
            problem,
        })?;
    }
    crate::files::create_dir_all(dir).map_err(|source| WriteError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    for (entry, trajectory) in setting.trajectories.iter().zip(trajectories) {
        write_atomic(&dir.join(&entry.file), &csv_bytes(trajectory))?;
    }
    let mut json =
        serde_json::to_vec_pretty(setting).map_err(|e| WriteError::Json(e.to_string()))?;
    json.push(b'\n');
    write_atomic(&dir.join(SETTING_FILE), &json)
}

fn check_trajectory(trajectory: &Trajectory) -> Result<(), (usize, String)> {
    if trajectory.frames.len() < 2 {
        return Err((0, "fewer than 2 frames, expected at least 2".into()));
    }
    let mut previous = f64::NEG_INFINITY;
    for (i, f) in trajectory.frames.iter().enumerate() {
        let values = [
            f.time,
            f.robot.x,
            f.robot.y,
            f.object.position.x,
            f.object.position.y,
            f.object.yaw,
        ];
        if let Some(c) = values.iter().position(|v| !v.is_finite()) {
            return Err((
                i,
                format!("{} is {}, expected a finite number", COLUMNS[c], values[c]),
            ));
        }
        if f.time <= previous {
            return Err((i, format!("time {} is not after {previous}", f.time)));
        }
        previous = f.time;
    }
    Ok(())
}

/// The CSV text of a trajectory, shortest round-trip formatting (`{}` of f64 never loses bits).
fn csv_bytes(trajectory: &Trajectory) -> Vec<u8> {
    use std::fmt::Write as _;
    let mut s = String::with_capacity(64 + trajectory.frames.len() * 110);
    s.push_str(CSV_HEADER);
    s.push('\n');
    for f in &trajectory.frames {
        // Writing into a String cannot fail.
        let _ = writeln!(
            s,
            "{},{},{},{},{},{}",
            f.time, f.robot.x, f.robot.y, f.object.position.x, f.object.position.y, f.object.yaw
        );
    }
    s.into_bytes()
}

/// Writes `bytes` to `path` atomically (see [`crate::files::write_atomically`]).
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    crate::files::write_atomically(path, bytes).map_err(|source| WriteError::Io {
        path: path.to_path_buf(),
        source,
    })
}
