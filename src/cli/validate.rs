//! `pushlab validate PATH...`: load recordings the way the app does and say, one line per recording,
//! whether each is fine, has recoverable defects, or cannot be used and why.
//!
//! Lines (stdout), then a summary line:
//! - `ok: PATH (N frames, D s)`
//! - `N warning(s): PATH: first; second; …` — the frames are not all the file had (rows dropped,
//!   gaps interpolated across, a file cut short)
//!
//! Either line ends in ` — notes: first; …` when loading did something that loses nothing (an
//! angle unwrapped, streams put on one clock): said, but the recording is not counted as warned.
//! - `error: PATH[ line L]: what is wrong, expected what`
//!
//! A ROS 2 bag (an `.mcap` file or a rosbag2 folder) holds no push until its topics are chosen, so
//! for one the lines list its topics first (`topic: PATH: NAME TYPE, N messages, R Hz[, readable][,
//! child frames: A, B][, camera: ENCODING W×H]`) and an unreadable bag is an `error:` line; a bag
//! whose choice is remembered
//! beside it is then validated like any recording.
//!
//! A Push-T dataset (a zarr replay buffer or a LeRobot dataset folder) is listed first — its
//! format, episodes, features and the pusher and object features it will be read with
//! (`dataset: PATH: …`, `note: PATH: …` where its metadata and its files disagree, `episode: PATH:
//! N: F frames, D s`) — and then validated like any recording. A dataset or bag that cannot be
//! listed says its error once.
//!
//! Exit code 0 when every recording loaded (warnings allowed), 1 when any did not, 2 for wrong
//! arguments (handled by clap before this runs).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use pushlab_core::recording::bag;
use pushlab_core::recording::dataset::{self, choice};
use pushlab_core::recording::load_paths_with;

use super::load_bar::with_load_bar;

/// Arguments of `pushlab validate`.
#[derive(Debug, Args)]
pub struct ValidateArgs {
    /// Set folders, CSV files inside a set, MIT Push Dataset .json/.h5 files, or folders of them;
    /// ROS 2 bags (.mcap files, rosbag2 folders) to list their topics.
    #[arg(required = true)]
    pub paths: Vec<PathBuf>,
}

/// Runs the command; see the module documentation for the output and exit codes.
pub fn run(args: &ValidateArgs) -> ExitCode {
    let (bags, paths): (Vec<PathBuf>, Vec<PathBuf>) =
        args.paths.iter().cloned().partition(|p| bag::is_bag(p));
    // A dataset or bag whose listing failed has said its error: it is not loaded again to say it
    // twice, but it counts in the summary's errors.
    let mut listing_errors = 0;
    let mut paths: Vec<PathBuf> = (paths.into_iter())
        .filter(|path| {
            let failed = dataset::is_dataset(path) && !list_dataset(path);
            listing_errors += usize::from(failed);
            !failed
        })
        .collect();
    for path in &bags {
        if !list_topics(path) {
            listing_errors += 1;
        } else if bag::choice::choice_path(path).is_file() {
            paths.push(path.clone());
        }
    }
    if paths.is_empty() {
        if listing_errors == 0 {
            return ExitCode::SUCCESS;
        }
        println!("0 recording(s) loaded (0 with warnings), {listing_errors} error(s)");
        return ExitCode::from(1);
    }
    let report = with_load_bar("loading", |progress| load_paths_with(&paths, &[], progress));
    let (mut with_warnings, mut with_notes) = (0, 0);
    for set in &report.sets {
        for recording in &set.recordings {
            let path = recording.source.display();
            let notes = if recording.notes.is_empty() {
                String::new()
            } else {
                with_notes += 1;
                format!(" — notes: {}", recording.notes.join("; "))
            };
            if recording.warnings.is_empty() {
                println!(
                    "ok: {path} ({} frames, {:.2} s){notes}",
                    recording.trajectory.len(),
                    recording.trajectory.duration()
                );
            } else {
                with_warnings += 1;
                let n = recording.warnings.len();
                let plural = if n == 1 { "warning" } else { "warnings" };
                println!(
                    "{n} {plural}: {path}: {}{notes}",
                    recording.warnings.join("; ")
                );
            }
        }
    }
    let noted = if with_notes > 0 {
        format!(", {with_notes} with notes")
    } else {
        String::new()
    };
    for error in &report.errors {
        println!("error: {error}");
    }
    println!(
        "{} recording(s) loaded ({with_warnings} with warnings{noted}), {} error(s)",
        report.recording_count(),
        report.errors.len() + listing_errors
    );
    if report.errors.is_empty() && listing_errors == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

/// Prints the topics of the bag at `path`, one line each; whether the bag could be read.
fn list_topics(path: &std::path::Path) -> bool {
    let listing = match bag::topics(path) {
        Ok(listing) => listing,
        Err(err) => {
            println!("error: {err}");
            return false;
        }
    };
    let topics = &listing.topics;
    let readable = topics.iter().filter(|t| t.pose_type().is_some()).count();
    for topic in topics {
        let frames = if topic.child_frames.is_empty() {
            String::new()
        } else {
            format!(", child frames: {}", topic.child_frames.join(", "))
        };
        let camera = match &topic.camera {
            Some(c) => match c.size {
                Some((w, h)) => format!(", camera: {} {w}×{h}", c.encoding),
                None => format!(", camera: {}", c.encoding),
            },
            None if topic.is_camera() => ", camera".to_owned(),
            None => String::new(),
        };
        println!(
            "topic: {}: {} {}, {} messages, {:.1} Hz{}{frames}{camera}",
            path.display(),
            topic.topic,
            topic.type_name,
            topic.count,
            topic.rate_hz(),
            if topic.pose_type().is_some() {
                ", readable"
            } else {
                ""
            }
        );
    }
    let cameras = topics.iter().filter(|t| t.is_camera()).count();
    println!(
        "{}: {} topic(s), {readable} readable as a pusher or object pose, {cameras} camera(s); import with pushlab import {} --pusher TOPIC[:CHILD_FRAME] --object TOPIC[:CHILD_FRAME] --setting SETTING.json [--camera TOPIC] --out SET",
        path.display(),
        topics.len(),
        path.display()
    );
    for cut in &listing.cut_short {
        println!("warning: {}: {cut}", path.display());
    }
    true
}

/// Prints a dataset's format, episodes and features, and the features it will be read with;
/// whether it could be read.
fn list_dataset(path: &std::path::Path) -> bool {
    let table = match dataset::read_table(path, &pushlab_core::recording::NoProgress) {
        Ok(table) => table,
        Err(err) => {
            println!("error: {err}");
            return false;
        }
    };
    let frames: usize = table.episodes.iter().map(ExactSizeIterator::len).sum();
    let cameras: Vec<String> = (table.cameras.iter())
        .map(|(name, what)| format!("{name} ({what})"))
        .collect();
    println!(
        "dataset: {}: {}, {} episode(s), {frames} frames at {} Hz; features: {}{}",
        path.display(),
        table.format,
        table.episodes.len(),
        table.fps,
        table.feature_list(),
        if cameras.is_empty() {
            String::new()
        } else {
            format!("; cameras: {}", cameras.join(", "))
        }
    );
    for note in &table.notes {
        println!("note: {}: {note}", path.display());
    }
    for (i, rows) in table.episodes.iter().enumerate() {
        let last = rows.end.saturating_sub(1).max(rows.start);
        println!(
            "episode: {}: {i}: {} frames, {:.2} s",
            path.display(),
            rows.len(),
            table.time(last, rows.start)
        );
    }
    let remembered = choice::remembered(path).ok().flatten();
    let how = if remembered.is_some() {
        "remembered"
    } else {
        "Push-T's layout"
    };
    match remembered.or_else(|| choice::suggest(&table)) {
        Some(c) => println!(
            "{}: pusher {}, object {} ({how}), {} m/px",
            path.display(),
            c.pusher,
            c.object,
            c.metres_per_px
        ),
        None => println!(
            "{}: no pusher or object chosen; import with pushlab import {} --pusher-feature \
             FEATURE[:COLUMN] --object-feature pose:FEATURE[:COLUMN]|keypoints:FEATURE --out SET",
            path.display(),
            path.display()
        ),
    }
    true
}
