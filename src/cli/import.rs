//! `pushlab import BAG --pusher TOPIC[:CHILD_FRAME] --object TOPIC[:CHILD_FRAME] --setting SETTING.json
//! --out SET`: turns a ROS 2 bag (an `.mcap` file or a rosbag2 folder) into a native recording set.
//! `pushlab import BAG --out SET` uses the choice remembered beside the bag (chosen in the app).
//!
//! The setting file gives what a bag does not record (the object's shape, the pusher radius,
//! materials); its `trajectories` are replaced by the pushes imported: one per bag, or one per piece
//! between pauses longer than `--split-gap` seconds. Each push's entry keeps the bag and the Unix
//! time of its first frame.
//!
//! With `--camera TOPIC` (repeatable), each camera's frames during each push are written beside its
//! CSV as an image sequence (`NAME.images/frames.csv` and the images; with several cameras one
//! folder each, `NAME.images/CAMERA/`): JPEG and PNG frames copied byte for byte, raw ones
//! (`sensor_msgs/msg/Image`) written as PNG. A frame that cannot be read is left out and counted.
//!
//! A `/tf` frame (`--pusher /tf:tip`) is the pose of that frame in the root of its transform tree,
//! composed from the transforms of the topic and of `/tf_static` (`recording/bag/tf_tree.rs`); the
//! pusher's and the object's chains must end in the same root frame.
//!
//! Exit code 0 when the set was written (warnings are printed), 1 when the bag, the topics or the
//! setting cannot be used (a missing or unreadable topic lists the bag's topics), 2 for wrong
//! arguments.

use std::path::PathBuf;

use anyhow::{Context, bail};

use super::experiment::args::positive_real;
use clap::Args;
use pushlab_core::recording::bag::{self, BagChoice, ImportOptions, SettingSource, TopicSpec};
use pushlab_core::recording::dataset::{self, Columns, ObjectSource};
use pushlab_core::recording::native::SETTING_FILE;
use pushlab_core::recording::{ReadError, write_set};

use super::cameras_out;
use super::load_bar::with_load_bar;

/// Arguments of `pushlab import`.
#[derive(Debug, Args)]
pub struct ImportArgs {
    /// The bag: an .mcap file or a rosbag2 folder (with metadata.yaml); or a Push-T dataset: a
    /// zarr replay buffer (Diffusion Policy's) or a LeRobot dataset folder.
    pub bag: PathBuf,
    /// The pusher's topic; for a tf2_msgs/msg/TFMessage topic such as /tf add the frame:
    /// /tf:pusher_tip (its pose in the root of its transform tree, with /tf_static). Without
    /// --pusher, --object and --setting, the choice remembered beside the bag (made in the app) is
    /// used.
    #[arg(long, value_name = "TOPIC[:CHILD_FRAME]", requires_all = ["object", "setting"])]
    pub pusher: Option<TopicSpec>,
    /// The object's topic, as --pusher.
    #[arg(long, value_name = "TOPIC[:CHILD_FRAME]", requires_all = ["pusher", "setting"])]
    pub object: Option<TopicSpec>,
    /// A setting.json giving the object, the pusher radius and the rest (its trajectories are replaced).
    #[arg(long, value_name = "SETTING.json", requires_all = ["pusher", "object"])]
    pub setting: Option<PathBuf>,
    /// The folder of the native set to write.
    #[arg(long, value_name = "SET")]
    pub out: PathBuf,
    /// Split into several pushes where the pusher or the object pauses for longer than this, seconds.
    #[arg(long, value_name = "SECONDS", value_parser = positive_real)]
    pub split_gap: Option<f64>,
    /// Rate of the common time grid, Hz, at most 5000 (default: the slower stream's rate).
    #[arg(long, value_name = "HZ", value_parser = rate)]
    pub rate: Option<f64>,
    /// A camera topic (sensor_msgs/msg/CompressedImage or Image) whose frames are written beside
    /// each push; repeat for several. Without any, the cameras remembered with the bag's choice.
    #[arg(long = "camera", value_name = "TOPIC")]
    pub cameras: Vec<String>,
    /// Replace a set already in --out.
    #[arg(long)]
    pub overwrite: bool,
    /// Datasets: metres per pixel of the 512 × 512 Push-T arena (default 0.001: a 120 mm T, a 15 mm
    /// pusher; or the scale remembered with the dataset's choice).
    #[arg(long, value_name = "METRES_PER_PX", value_parser = positive_real)]
    pub scale: Option<f64>,
    /// Datasets: import only the episodes A, A+1, …, B−1 (counted from 0).
    #[arg(long, value_name = "A..B", value_parser = super::import_dataset::episode_range)]
    pub episodes: Option<std::ops::Range<usize>>,
    /// Datasets: the pusher's x, y as FEATURE[:COLUMN] (default: remembered, or Push-T's layout).
    #[arg(long, value_name = "FEATURE[:COLUMN]", requires = "object_feature")]
    pub pusher_feature: Option<Columns>,
    /// Datasets: the T as pose:FEATURE[:COLUMN] (x, y, angle of its local origin) or
    /// keypoints:FEATURE (its 8 corners, gym-pusht's order).
    #[arg(long, value_name = "SOURCE", requires = "pusher_feature")]
    pub object_feature: Option<ObjectSource>,
}

pub(super) fn rate(text: &str) -> Result<f64, String> {
    let hz = positive_real(text)?;
    if hz > bag::MAX_RATE_HZ {
        return Err(format!(
            "'{text}': expected at most {} Hz",
            bag::MAX_RATE_HZ
        ));
    }
    Ok(hz)
}

/// The topics, setting and options: from the arguments, or remembered beside the bag (where
/// --split-gap and --rate, when given, override what is remembered).
fn choice_of(args: &ImportArgs) -> anyhow::Result<BagChoice> {
    if let (Some(pusher), Some(object), Some(setting)) = (&args.pusher, &args.object, &args.setting)
    {
        return Ok(BagChoice {
            pusher: pusher.clone(),
            object: object.clone(),
            setting: SettingSource::File(setting.clone()),
            options: ImportOptions {
                rate_hz: args.rate,
                split_gap_s: args.split_gap,
            },
            cameras: args.cameras.clone(),
        });
    }
    let Some(mut choice) = bag::choice::remembered(&args.bag)? else {
        bail!(
            "{}: no topics given and none remembered beside the bag (expected {}): pass --pusher, \
             --object and --setting, or choose them by opening the bag in the app",
            args.bag.display(),
            bag::choice::choice_path(&args.bag).display()
        );
    };
    if args.rate.is_some() {
        choice.options.rate_hz = args.rate;
    }
    if args.split_gap.is_some() {
        choice.options.split_gap_s = args.split_gap;
    }
    if !args.cameras.is_empty() {
        choice.cameras.clone_from(&args.cameras);
    }
    Ok(choice)
}

/// Runs the command.
pub fn run(args: &ImportArgs) -> anyhow::Result<()> {
    // A mistyped path is said as such, not as a bag with no choice remembered beside it.
    if let Err(source) = std::fs::metadata(&args.bag) {
        return Err(ReadError::Io {
            path: args.bag.clone(),
            source,
        }
        .into());
    }
    if args.out.join(SETTING_FILE).exists() && !args.overwrite {
        bail!(
            "{} already holds a recording set; pass --overwrite to replace it",
            args.out.display()
        );
    }
    if dataset::is_dataset(&args.bag) {
        return super::import_dataset::run(&super::import_dataset::DatasetImport {
            bag: &args.bag,
            out: &args.out,
            overwrite: args.overwrite,
            scale: args.scale,
            episodes: args.episodes.clone(),
            pusher_feature: args.pusher_feature.clone(),
            object_feature: args.object_feature.clone(),
        });
    }
    let choice = choice_of(args)?;
    let (pusher, object) = (&choice.pusher, &choice.object);
    let setting = choice.setting.resolve()?;
    let size: u64 = bag::bag_files(&args.bag)?
        .iter()
        .map(|f| std::fs::metadata(f).map_or(0, |m| m.len()))
        .sum();
    let import = with_load_bar("reading the bag", |progress| {
        progress.plan(1, size);
        bag::import_with_cameras(
            &args.bag,
            pusher,
            object,
            &choice.cameras,
            choice.options,
            progress,
        )
    })?;
    let setting = bag::setting_for(&args.bag, &import, pusher, object, setting);
    let trajectories: Vec<_> = import.pushes.iter().map(|p| p.trajectory.clone()).collect();
    write_set(&args.out, &setting, &trajectories)
        .with_context(|| format!("writing {}", args.out.display()))?;
    for (entry, push) in setting.trajectories.iter().zip(&import.pushes) {
        cameras_out::write_cameras(&args.out.join(&entry.file), &push.cameras)?;
    }
    for (entry, push) in setting.trajectories.iter().zip(&import.pushes) {
        let t = &push.trajectory;
        println!(
            "{}: {} frames at {} Hz, {:.2} s",
            entry.file,
            t.len(),
            import.rate_hz,
            t.duration()
        );
    }
    if let Some(first) = import.pushes.first() {
        for warning in &first.warnings {
            println!("warning: {warning}");
        }
        for note in &first.notes {
            println!("note: {note}");
        }
    }
    println!(
        "{} push(es) from {} -> {}",
        import.pushes.len(),
        args.bag.display(),
        args.out.display()
    );
    Ok(())
}
