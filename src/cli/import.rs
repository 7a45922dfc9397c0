//! `pushlab import BAG --pusher TOPIC[:CHILD_FRAME] --object TOPIC[:CHILD_FRAME] --setting SETTING.json
//! --out SET`: turns a ROS 2 bag (an `.mcap` file or a rosbag2 folder) into a native recording set.
//!
//! The setting file gives what a bag does not record (the object's shape, the pusher radius,
//! materials); its `trajectories` are replaced by the pushes imported: one per bag, or one per piece
//! between pauses longer than `--split-gap` seconds. Each push's entry keeps the bag and the Unix
//! time of its first frame.
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
use clap::Args;
use pushlab_core::recording::bag::{self, ImportOptions, TopicSpec};
use pushlab_core::recording::native::{SETTING_FILE, parse_setting};
use pushlab_core::recording::{TrajectoryEntry, write_set};

/// Arguments of `pushlab import`.
#[derive(Debug, Args)]
pub struct ImportArgs {
    /// The bag: an .mcap file or a rosbag2 folder (with metadata.yaml).
    pub bag: PathBuf,
    /// The pusher's topic; for a tf2_msgs/msg/TFMessage topic such as /tf add the frame:
    /// /tf:pusher_tip (its pose in the root of its transform tree, with /tf_static).
    #[arg(long, value_name = "TOPIC[:CHILD_FRAME]")]
    pub pusher: TopicSpec,
    /// The object's topic, as --pusher.
    #[arg(long, value_name = "TOPIC[:CHILD_FRAME]")]
    pub object: TopicSpec,
    /// A setting.json giving the object, the pusher radius and the rest (its trajectories are replaced).
    #[arg(long, value_name = "SETTING.json")]
    pub setting: PathBuf,
    /// The folder of the native set to write.
    #[arg(long, value_name = "SET")]
    pub out: PathBuf,
    /// Split into several pushes where the pusher or the object pauses for longer than this, seconds.
    #[arg(long, value_name = "SECONDS", value_parser = positive)]
    pub split_gap: Option<f64>,
    /// Rate of the common time grid, Hz, at most 5000 (default: the slower stream's rate).
    #[arg(long, value_name = "HZ", value_parser = rate)]
    pub rate: Option<f64>,
    /// Replace a set already in --out.
    #[arg(long)]
    pub overwrite: bool,
}

fn positive(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("'{text}': expected a positive number")),
    }
}

fn rate(text: &str) -> Result<f64, String> {
    let hz = positive(text)?;
    if hz > bag::MAX_RATE_HZ {
        return Err(format!(
            "'{text}': expected at most {} Hz",
            bag::MAX_RATE_HZ
        ));
    }
    Ok(hz)
}

/// Runs the command.
pub fn run(args: &ImportArgs) -> anyhow::Result<()> {
    if args.out.join(SETTING_FILE).exists() && !args.overwrite {
        bail!(
            "{} already holds a recording set; pass --overwrite to replace it",
            args.out.display()
        );
    }
    let bytes = std::fs::read(&args.setting)
        .with_context(|| format!("{}: cannot read", args.setting.display()))?;
    let mut setting = parse_setting(&bytes, &args.setting)?;
    let options = ImportOptions {
        rate_hz: args.rate,
        split_gap_s: args.split_gap,
    };
    let import = bag::import(&args.bag, &args.pusher, &args.object, options)?;
    let stem = args
        .bag
        .file_stem()
        .map_or_else(|| "push".to_owned(), |s| s.to_string_lossy().into_owned());
    let stem: String = stem
        .chars()
        .map(|c| {
            if c.is_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    let many = import.pushes.len() > 1;
    setting.trajectories = import
        .pushes
        .iter()
        .enumerate()
        .map(|(i, push)| {
            let mut extra = serde_json::Map::new();
            extra.insert("bag".into(), args.bag.display().to_string().into());
            extra.insert("bag_pusher".into(), args.pusher.to_string().into());
            extra.insert("bag_object".into(), args.object.to_string().into());
            extra.insert("start_unix_s".into(), push.start_unix_s.into());
            TrajectoryEntry {
                file: if many {
                    format!("{stem}_{:03}.csv", i + 1)
                } else {
                    format!("{stem}.csv")
                },
                contact_offset: None,
                push_angle_deg: None,
                extra,
            }
        })
        .collect();
    setting.sample_rate_hz = Some(import.rate_hz);
    let trajectories: Vec<_> = import.pushes.iter().map(|p| p.trajectory.clone()).collect();
    write_set(&args.out, &setting, &trajectories)
        .with_context(|| format!("writing {}", args.out.display()))?;
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
    }
    println!(
        "{} push(es) from {} -> {}",
        import.pushes.len(),
        args.bag.display(),
        args.out.display()
    );
    Ok(())
}
