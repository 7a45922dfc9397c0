//! From the two raw pose streams of a bag to pushes: cleaning, optional splitting at gaps, and
//! resampling onto one grid, by the rules MIT files follow ([`crate::recording::resample`]).

use std::path::Path;
use std::sync::Arc;

use super::error::BagError;
use super::problem::BagProblem;
use super::spec::TopicSpec;
use super::streams::{BagStreams, read_streams, read_streams_bytes};
use super::topic_info::TopicInfo;
use crate::recording::camera::CameraStream;
use crate::recording::progress::{NoProgress, Progress};
use crate::recording::resample::{
    Interpolator, MIN_ROWS, SpanProblem, clean, grid, grid_frame, grid_time, unwrap_yaw,
};
use crate::trajectory::Trajectory;

/// Highest grid rate, Hz: far above what a pose tracker publishes, and it bounds the frames a push
/// can have (with [`crate::recording::resample::MAX_DURATION_S`]) whatever the stamps say.
pub const MAX_RATE_HZ: f64 = 5_000.0;

/// How a bag becomes pushes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImportOptions {
    /// Rate of the common grid, Hz; `None`: the slower stream's rate (from its median step), rounded
    /// to whole Hz. Clamped to 1 … [`MAX_RATE_HZ`].
    pub rate_hz: Option<f64>,
    /// Split into several pushes where either stream pauses for longer than this, seconds; `None`:
    /// the whole bag is one push.
    pub split_gap_s: Option<f64>,
}

/// One push taken from a bag.
#[derive(Clone, Debug)]
pub struct BagPush {
    /// Resampled frames, time from 0.
    pub trajectory: Trajectory,
    /// Unix time of the first frame, seconds.
    pub start_unix_s: f64,
    /// Recoverable defects found, each a sentence with numbers (see [`Recording::warnings`]).
    pub warnings: Vec<String>,
    /// What reading did that loses nothing (see [`Recording::notes`]).
    pub notes: Vec<String>,
    /// The frames of the cameras asked for, on the push's clock: those from a second before its
    /// first frame to a second after its last.
    pub cameras: Vec<Arc<CameraStream>>,
}

/// Seconds of camera frames kept before a push's first frame and after its last: enough for the
/// frame shown at its start, whatever the camera's rate.
const CAMERA_MARGIN_S: f64 = 1.0;

/// A bag imported: its pushes, the grid rate used and the bag's topics.
#[derive(Clone, Debug)]
pub struct BagImport {
    pub pushes: Vec<BagPush>,
    pub rate_hz: f64,
    pub topics: Vec<TopicInfo>,
}

/// Reads and imports the poses of a bag (an `.mcap` file or a rosbag2 folder).
pub fn import(
    path: &Path,
    pusher: &TopicSpec,
    object: &TopicSpec,
    options: ImportOptions,
) -> Result<BagImport, BagError> {
    import_with_cameras(path, pusher, object, &[], options, &NoProgress)
}

/// [`import`], with the frames of the camera topics named indexed for each push, in one pass that
/// reports the bytes it passes to `progress` and stops when it is cancelled.
pub fn import_with_cameras(
    path: &Path,
    pusher: &TopicSpec,
    object: &TopicSpec,
    cameras: &[String],
    options: ImportOptions,
    progress: &dyn Progress,
) -> Result<BagImport, BagError> {
    let streams = read_streams(path, pusher, object, cameras, progress)?;
    finish(path, &streams, pusher, object, options)
}

/// Imports one `.mcap` file held in memory; `path` is only used in messages.
pub fn import_bytes(
    bytes: &[u8],
    path: &Path,
    pusher: &TopicSpec,
    object: &TopicSpec,
    options: ImportOptions,
) -> Result<BagImport, BagError> {
    import_bytes_with_cameras(bytes, path, pusher, object, &[], options)
}

/// [`import_bytes`] with cameras (see [`import_with_cameras`]).
pub fn import_bytes_with_cameras(
    bytes: &[u8],
    path: &Path,
    pusher: &TopicSpec,
    object: &TopicSpec,
    cameras: &[String],
    options: ImportOptions,
) -> Result<BagImport, BagError> {
    let streams = read_streams_bytes(bytes, path, pusher, object, cameras)?;
    finish(path, &streams, pusher, object, options)
}

fn finish(
    path: &Path,
    streams: &BagStreams,
    pusher: &TopicSpec,
    object: &TopicSpec,
    options: ImportOptions,
) -> Result<BagImport, BagError> {
    let (pushes, rate_hz) =
        resample_streams(streams, pusher, object, options).map_err(|problem| {
            BagError::Problem {
                path: path.to_path_buf(),
                problem,
            }
        })?;
    Ok(BagImport {
        pushes,
        rate_hz,
        topics: streams.topics.clone(),
    })
}

/// Rate of a cleaned stream from its median step, Hz: pauses (split at or not) do not lower it.
fn median_rate(rows: &[[f64; 4]]) -> f64 {
    let mut steps: Vec<f64> = rows.windows(2).map(|w| w[1][0] - w[0][0]).collect();
    if steps.is_empty() {
        return 0.0;
    }
    let middle = steps.len() / 2;
    let (_, median, _) = steps.select_nth_unstable_by(middle, f64::total_cmp);
    1.0 / *median
}

/// Cleans both streams, splits them at gaps when asked, and resamples each piece; returns the pushes
/// and the grid rate. Without splitting, a stream too short or an overlap too short or long is an
/// error; with it, such pieces are skipped (and said so), and it is an error only when none is left.
pub fn resample_streams(
    streams: &BagStreams,
    pusher: &TopicSpec,
    object: &TopicSpec,
    options: ImportOptions,
) -> Result<(Vec<BagPush>, f64), BagProblem> {
    let (pusher_key, object_key) = (format!("pusher {pusher}"), format!("object {object}"));
    // The whole streams, cleaned, give the rates and the pauses; each piece is cleaned again below
    // so that its warnings speak of it alone.
    let mut scratch = Vec::new();
    let tip_all = clean(&pusher_key, &streams.pusher, &mut scratch);
    let obj_all = clean(&object_key, &streams.object, &mut scratch);
    let (tip_rate, obj_rate) = (median_rate(&tip_all), median_rate(&obj_all));
    let rate_hz = options
        .rate_hz
        .unwrap_or_else(|| tip_rate.min(obj_rate).round())
        .clamp(1.0, MAX_RATE_HZ);
    let mut common_notes = streams.notes.clone();
    if (tip_rate - obj_rate).abs() > 0.1 * tip_rate.max(obj_rate) {
        common_notes.push(format!(
            "streams have unequal rates ({pusher_key} {tip_rate:.1} Hz, {object_key} {obj_rate:.1} Hz); aligned by resampling at {rate_hz} Hz"
        ));
    }
    let base_s = streams.base_unix_ns as f64 * 1e-9;
    let pieces = match options.split_gap_s {
        Some(gap) => pieces(&tip_all, &obj_all, gap),
        None => vec![(f64::NEG_INFINITY, f64::INFINITY)],
    };
    let splitting = pieces.len() > 1;
    let mut pushes = Vec::new();
    let mut skipped = Vec::new();
    let mut last_problem = None;
    for (from, to) in pieces {
        let within = |rows: &[[f64; 4]]| -> Vec<[f64; 4]> {
            rows.iter()
                .filter(|r| r[0] >= from && r[0] <= to)
                .copied()
                .collect()
        };
        let (mut warnings, mut notes) = (streams.warnings.clone(), common_notes.clone());
        let t = clean(&pusher_key, &within(&streams.pusher), &mut warnings);
        let mut o = clean(&object_key, &within(&streams.object), &mut warnings);
        let too_few = [(pusher, &t), (object, &o)]
            .into_iter()
            .find(|(_, rows)| rows.len() < MIN_ROWS)
            .map(|(spec, rows)| BagProblem::TooFewRows {
                topic: spec.to_string(),
                rows: rows.len(),
                min: MIN_ROWS,
            });
        let problem = match too_few {
            Some(problem) => Some(problem),
            None => {
                unwrap_yaw(&object_key, &mut o, &mut notes);
                match grid(&t, &o, rate_hz) {
                    Ok((start, count)) => {
                        let trajectory = resample(&t, &o, start, count, rate_hz);
                        let span = (-CAMERA_MARGIN_S, trajectory.duration() + CAMERA_MARGIN_S);
                        let cameras = (streams.cameras.iter())
                            .map(|c| {
                                Arc::new(c.stream(&streams.bag, streams.base_unix_ns, start, span))
                            })
                            .collect();
                        pushes.push(BagPush {
                            trajectory,
                            start_unix_s: base_s + start,
                            warnings,
                            notes,
                            cameras,
                        });
                        None
                    }
                    Err(span) => Some(BagProblem::Span(span)),
                }
            }
        };
        if let Some(problem) = problem {
            if !splitting {
                return Err(problem);
            }
            skipped.push(format!("{:.3}–{:.3} s", from.max(0.0), to));
            last_problem = Some(problem);
        }
    }
    if pushes.is_empty() {
        return Err(
            last_problem.unwrap_or(BagProblem::Span(SpanProblem::TooShort { seconds: 0.0 }))
        );
    }
    if !skipped.is_empty() {
        let note = format!(
            "{} piece(s) between pauses too short or too long to be a push, skipped (at {})",
            skipped.len(),
            skipped.join(", ")
        );
        for push in &mut pushes {
            push.notes.push(note.clone());
        }
    }
    // The pushes before the last end before the cut: whole.
    if let (Some(cut), Some(last)) = (&streams.cut_short, pushes.last_mut()) {
        cut.clone().say(&mut last.warnings, &mut last.notes);
    }
    Ok((pushes, rate_hz))
}

/// Interpolates both cleaned streams onto the grid `start + k / rate_hz`, `k < count`.
fn resample(
    tip: &[[f64; 4]],
    obj: &[[f64; 4]],
    start: f64,
    count: usize,
    rate_hz: f64,
) -> Trajectory {
    let mut tip_at = Interpolator::new(tip);
    let mut obj_at = Interpolator::new(obj);
    let frames = (0..count)
        .map(|k| {
            let time = grid_time(start, k, rate_hz);
            grid_frame(k, rate_hz, tip_at.at(time), obj_at.at(time))
        })
        .collect();
    Trajectory::new(frames)
}

/// The time intervals between pauses longer than `gap` seconds in either stream.
fn pieces(tip: &[[f64; 4]], obj: &[[f64; 4]], gap: f64) -> Vec<(f64, f64)> {
    let mut holes: Vec<(f64, f64)> = [tip, obj]
        .iter()
        .flat_map(|rows| rows.windows(2))
        .filter(|w| w[1][0] - w[0][0] > gap)
        .map(|w| (w[0][0], w[1][0]))
        .collect();
    holes.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut pieces = Vec::new();
    let mut from = f64::NEG_INFINITY;
    for (a, b) in holes {
        if a > from {
            pieces.push((from, a));
        }
        from = from.max(b);
    }
    pieces.push((from, f64::INFINITY));
    pieces
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pieces_split_at_holes_of_either_stream() {
        let tip: Vec<[f64; 4]> = [0.0, 1.0, 5.0, 6.0]
            .iter()
            .map(|&t| [t, 0.0, 0.0, 0.0])
            .collect();
        let obj: Vec<[f64; 4]> = [0.0, 0.5, 1.0, 2.5, 5.0, 6.0]
            .iter()
            .map(|&t| [t, 0.0, 0.0, 0.0])
            .collect();
        let p = pieces(&tip, &obj, 1.2);
        assert_eq!(p, vec![(f64::NEG_INFINITY, 1.0), (5.0, f64::INFINITY)]);
    }
}
