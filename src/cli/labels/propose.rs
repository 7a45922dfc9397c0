//! `pushlab labels propose SET --out FILE`: label proposals from the recordings' own physics, written
//! as a labels file for a person to review, compare (`pushlab labels compare`) or open.
//!
//! Proposals are not labels: they go to a file of their own, never into the set's
//! `pushlab-labels.json`, and the recordings are only read. A run that fails or is stopped writes
//! nothing.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use pushlab_core::experiment::evaluate::fixed_pass;
use pushlab_core::experiment::geometry_of;
use pushlab_core::labels::file::{self, LABELS_FILE_NAME};
use pushlab_core::labels::pipeline::key_of;
use pushlab_core::labels::propose::{Proposals, ProposeOptions, Residuals, propose_for};
use pushlab_core::labels::schema::names::{BAD_TRACKING, CONTACT, SLIPPING};
use pushlab_core::labels::{LabelSet, RecordingLabels};
use pushlab_core::model::{CombinedModel, samples_from_trajectory};
use pushlab_core::model_file::ModelFile;
use pushlab_core::recording::native::SETTING_FILE;
use pushlab_core::recording::{Recording, load_paths};

use crate::cli::experiment::train_progress::{cancel_flag, cancelled};

/// Arguments of `pushlab labels propose`.
#[derive(Debug, Args)]
pub struct ProposeArgs {
    /// A recording set folder, recording files, MIT Push Dataset files, or folders of them.
    #[arg(required = true)]
    sets: Vec<PathBuf>,
    /// The proposals file to write (labels-file format); refused if it is one of the recordings,
    /// a `setting.json` or a set's own `pushlab-labels.json`.
    #[arg(long, value_name = "FILE")]
    out: PathBuf,
    /// Leave out proposed segments less sure than this (0.5 on a threshold, 1 certain).
    #[arg(long, value_name = "C", default_value_t = 0.0, value_parser = confidence)]
    min_confidence: f32,
    /// Contact while the pusher's rim is within the gap's offset plus this many σ of its noise.
    #[arg(long, value_name = "K", default_value_t = ProposeOptions::default().contact_sigmas)]
    contact_sigmas: f64,
    /// Slipping while the pusher drifts over the object this many standard errors from zero.
    #[arg(long, value_name = "K", default_value_t = ProposeOptions::default().slip_sigmas)]
    slip_sigmas: f64,
    /// The slip is measured over a window in which the pusher travels this many σ of the noise of
    /// its place on the object (longer: slower slips found, changes blurred).
    #[arg(long, value_name = "K", default_value_t = ProposeOptions::default().window_sigmas)]
    window_sigmas: f64,
    /// Bad tracking where a pose jump exceeds what the pusher explains by this many σ.
    #[arg(long, value_name = "K", default_value_t = ProposeOptions::default().jump_sigmas)]
    jump_sigmas: f64,
    /// Bad tracking where the model's residual is this many robust σ above its median.
    #[arg(long, value_name = "K", default_value_t = ProposeOptions::default().residual_sigmas)]
    residual_sigmas: f64,
    /// A trained model (`pushlab train`) whose residuals, with `θ_online(0)` fixed, also mark bad
    /// tracking where they spike; without it only pose jumps do.
    #[arg(long, value_name = "FILE")]
    model: Option<PathBuf>,
}

fn confidence(text: &str) -> Result<f32, String> {
    match text.parse::<f32>() {
        Ok(c) if (0.0..=1.0).contains(&c) => Ok(c),
        Ok(c) => Err(format!("expected a confidence from 0 to 1, found {c}")),
        Err(e) => Err(format!("{text:?} is not a number: {e}")),
    }
}

/// Runs the command.
pub fn run(args: &ProposeArgs) -> anyhow::Result<()> {
    let report = load_paths(&args.sets);
    for error in &report.errors {
        eprintln!("warning: {error}");
    }
    let recordings: Vec<&Recording> = report.sets.iter().flat_map(|s| &s.recordings).collect();
    if recordings.is_empty() {
        bail!(
            "no recording could be loaded from {}",
            list(args.sets.iter().map(|p| p.display().to_string()))
        );
    }
    refuse_to_overwrite_inputs(&args.out, &report.sets)?;
    let model = match &args.model {
        Some(path) => Some(ModelFile::load(path)?.combined),
        None => None,
    };
    let options = ProposeOptions {
        contact_sigmas: args.contact_sigmas,
        slip_sigmas: args.slip_sigmas,
        window_sigmas: args.window_sigmas,
        jump_sigmas: args.jump_sigmas,
        residual_sigmas: args.residual_sigmas,
    };
    let cancel = cancel_flag();
    let bar =
        ProgressBar::with_draw_target(Some(recordings.len() as u64), ProgressDrawTarget::stderr());
    if let Ok(style) =
        ProgressStyle::with_template("propose [{bar:30}] {pos}/{len} recordings {msg} ({elapsed})")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    let mut set = LabelSet::default();
    let mut summary = String::new();
    for (done, recording) in recordings.iter().enumerate() {
        let name = key_of(&recording.source)
            .with_context(|| format!("{}: no file name", recording.source.display()))?;
        bar.set_message(name.clone());
        let losses = match &model {
            Some(model) => Some((model, model_residuals(model, recording)?)),
            None => None,
        };
        let residuals = losses.as_ref().map(|(model, losses)| Residuals {
            losses,
            horizon: model.horizon(),
            scale: model.loss_scale(),
        });
        let proposals = propose_for(recording, residuals, &options, &mut |_| {
            !cancel.load(std::sync::atomic::Ordering::Relaxed)
        });
        if cancelled() {
            bar.finish_and_clear();
            bail!("stopped by Ctrl-C; nothing written");
        }
        let proposals = proposals?;
        let labels = proposals.to_labels(args.min_confidence);
        if set.recordings.contains_key(&name) {
            bail!(
                "{}: two recordings are called {name}; propose for one set at a time",
                recording.source.display()
            );
        }
        summary.push_str(&line(&name, &proposals, &labels));
        set.recordings.insert(name, labels);
        bar.set_position(done as u64 + 1);
    }
    bar.finish_and_clear();
    set.normalise_and_validate()
        .map_err(|(field, message)| anyhow::anyhow!("proposals: {field}: {message}"))?;
    print!("{summary}");
    file::write(&args.out, &set)?;
    println!(
        "wrote {} ({} recordings; proposals, not labels: review them before use)",
        args.out.display(),
        set.recordings.len()
    );
    Ok(())
}

/// The loss of each sample of `recording` under `model` with `θ_online(0)` fixed, by the sample's
/// first frame: the residuals whose spikes point at frames the model cannot explain.
fn model_residuals(model: &CombinedModel, recording: &Recording) -> anyhow::Result<Vec<f64>> {
    let geometry = geometry_of(&recording.setting).ok();
    let learner = model.on_object(geometry.as_ref()).with_context(|| {
        format!(
            "{}: the model cannot predict this recording",
            recording.source.display()
        )
    })?;
    let samples = samples_from_trajectory(&recording.trajectory, model.horizon());
    Ok(fixed_pass(learner.as_ref(), &samples)
        .iter()
        .map(pushlab_core::model::Loss::total)
        .collect())
}

/// One line per recording: what was proposed and the noise it was judged against.
fn line(name: &str, proposals: &Proposals, labels: &RecordingLabels) -> String {
    let frames = proposals.evidence.len().max(1) as f64;
    let share = |label: &str| {
        let n: usize = labels
            .segments
            .iter()
            .filter(|s| s.label == label)
            .map(|s| s.end - s.start)
            .sum();
        100.0 * n as f64 / frames
    };
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{name:<24} {:>6} frames: contact {:>5.1} %, slipping {:>5.1} %, bad tracking {:>4.1} % (noise {:.2} mm, contact within {:.1} mm)",
        proposals.evidence.len(),
        share(CONTACT),
        share(SLIPPING),
        share(BAD_TRACKING),
        proposals.noise.object_sd.max(proposals.noise.robot_sd) * 1e3,
        proposals.contact_tolerance * 1e3,
    );
    out
}

/// Refuses an output path that is one of the inputs: a recording, a `setting.json` or a set's own
/// labels file (proposals would replace a person's labels there).
fn refuse_to_overwrite_inputs(
    out: &Path,
    sets: &[pushlab_core::recording::RecordingSet],
) -> anyhow::Result<()> {
    let out_full = full_path(out);
    for set in sets {
        let mut inputs: Vec<PathBuf> = set.recordings.iter().map(|r| r.source.clone()).collect();
        inputs.push(set.dir.join(SETTING_FILE));
        inputs.push(set.dir.join(LABELS_FILE_NAME));
        if let Some(input) = inputs.iter().find(|p| full_path(p) == out_full) {
            bail!(
                "--out {}: is {}, an input of the proposals; write them to a file of their own (e.g. {})",
                out.display(),
                input.display(),
                set.dir.join("proposed-labels.json").display()
            );
        }
    }
    Ok(())
}

/// `path` made absolute with its folder's symbolic links resolved (the file itself may not exist).
fn full_path(path: &Path) -> PathBuf {
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let parent = parent.canonicalize().unwrap_or(parent);
    match path.file_name() {
        Some(name) => parent.join(name),
        None => parent,
    }
}

fn list(items: impl Iterator<Item = String>) -> String {
    items.collect::<Vec<_>>().join(", ")
}
