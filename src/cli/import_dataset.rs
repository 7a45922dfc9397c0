//! `pushlab import DATASET --out SET [--scale S] [--episodes A..B]`: a Push-T dataset (a zarr
//! replay buffer or a LeRobot dataset folder) as a native recording set, one push per episode.
//!
//! The pusher and object features are those given (`--pusher-feature`, `--object-feature`), else
//! those remembered beside the dataset (chosen in the app), else Push-T's own layout; the scale
//! likewise (`--scale`, else remembered, else 1 mm per pixel). Every rule is the core's
//! `recording::dataset`; the dataset is only read, and the set is written atomically. A replay
//! buffer's images (`data/img`) are written beside each push as its camera's image sequence (PNG).

use std::ops::Range;

use anyhow::{Context, bail};
use pushlab_core::recording::dataset::{self, DatasetChoice, choice};
use pushlab_core::recording::native::SETTING_FILE;
use pushlab_core::recording::write_set;

use std::path::Path;

use super::load_bar::with_load_bar;
use pushlab_core::recording::dataset::{Columns, ObjectSource};

/// `A..B` (episodes A to B−1) or a single episode `A`.
pub fn episode_range(text: &str) -> Result<Range<usize>, String> {
    let number = |part: &str| {
        part.trim().parse::<usize>().map_err(|_| {
            format!("expected A..B with whole numbers A < B, e.g. 0..10, found '{text}'")
        })
    };
    match text.split_once("..") {
        Some((a, b)) => {
            let (a, b) = (number(a)?, number(b)?);
            if a < b {
                Ok(a..b)
            } else {
                Err(format!(
                    "the range '{text}' holds no episode: expected A < B"
                ))
            }
        }
        None => number(text).map(|a| a..a + 1),
    }
}

/// What `pushlab import` was asked for a dataset.
pub struct DatasetImport<'a> {
    /// The dataset (`bag` on the command line).
    pub bag: &'a Path,
    pub out: &'a Path,
    pub overwrite: bool,
    pub scale: Option<f64>,
    pub episodes: Option<Range<usize>>,
    pub pusher_feature: Option<Columns>,
    pub object_feature: Option<ObjectSource>,
}

/// Runs the command for a dataset.
pub fn run(args: &DatasetImport) -> anyhow::Result<()> {
    if args.out.join(SETTING_FILE).exists() && !args.overwrite {
        bail!(
            "{} already holds a recording set; pass --overwrite to replace it",
            args.out.display()
        );
    }
    let table = with_load_bar("reading the dataset", |progress| {
        progress.plan(1, dataset::bytes(args.bag));
        dataset::read_table(args.bag, progress)
    })?;
    let remembered = choice::remembered(args.bag)?;
    let mut chosen = match (&args.pusher_feature, &args.object_feature) {
        (Some(pusher), Some(object)) => DatasetChoice {
            pusher: pusher.clone(),
            object: object.clone(),
            metres_per_px: remembered.map_or(0.001, |c| c.metres_per_px),
        },
        _ => match remembered.or_else(|| choice::suggest(&table)) {
            Some(choice) => choice,
            None => bail!(
                "{}: which features are the pusher and the object is not remembered and not \
                 Push-T's layout; its features: {}; pass --pusher-feature FEATURE[:COLUMN] and \
                 --object-feature pose:FEATURE[:COLUMN] or keypoints:FEATURE",
                args.bag.display(),
                table.feature_list()
            ),
        },
    };
    if let Some(scale) = args.scale {
        chosen.metres_per_px = scale;
    }
    let set = dataset::to_set(args.bag, &table, &chosen, args.episodes.clone())?;
    let trajectories: Vec<_> = (set.recordings.iter())
        .map(|r| r.trajectory.as_ref().clone())
        .collect();
    write_set(args.out, &set.setting, &trajectories)
        .with_context(|| format!("writing {}", args.out.display()))?;
    // A replay buffer's images become each push's image sequence, as a bag's cameras do.
    for (entry, recording) in set.setting.trajectories.iter().zip(&set.recordings) {
        super::cameras_out::write_cameras(&args.out.join(&entry.file), &recording.cameras)?;
    }
    for recording in &set.recordings {
        let t = &recording.trajectory;
        println!(
            "{}.csv: {} frames, {:.2} s",
            recording.name,
            t.len(),
            t.duration()
        );
        for warning in &recording.warnings {
            println!("warning: {}: {warning}", recording.name);
        }
        for note in &recording.notes {
            println!("note: {}: {note}", recording.name);
        }
    }
    println!(
        "{} episode(s) of {} ({}, pusher {}, object {}, {} m/px) -> {}",
        set.recordings.len(),
        args.bag.display(),
        table.format,
        chosen.pusher,
        chosen.object,
        chosen.metres_per_px,
        args.out.display()
    );
    Ok(())
}
