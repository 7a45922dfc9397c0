//! `pushlab eval --offline PATH... --online PATH...`: the paper's Tables I and II for any recordings.
//!
//! Trains (or loads with `--model`) a combined model and the pure network on the offline recordings,
//! then reports positional and rotational NMSE (eq. 7) for
//! - **Offline NN** and **Offline**: the pure network and the combined model on the offline data;
//! - **Fixed**: the combined model on the online data with `θ_online` kept at `θ_online(0)`;
//! - **Online**: the combined model learning `θ_online` online (eq. 13), reset to `θ_online(0)` at the
//!   start of each online trajectory, or with `--carry-theta` going on from the push before it when
//!   both push the same object;
//! - with `--physics`, the physics-only model (outline + Lynch, no network) fixed and online, which
//!   shows what the network buys.
//!
//! With `--model`, `--offline` is optional: a model file carries everything the online run needs,
//! so a model received, or trained on data kept elsewhere, is evaluated on new pushes alone, without
//! the offline rows.
//!
//! Every number comes from `pushlab_core::experiment::evaluate`; this module prints and writes them.

mod table;

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use anyhow::{Context, anyhow, bail};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use pushlab_core::atomic_file::write_atomically;
use pushlab_core::domain::Domain;
use pushlab_core::experiment::DEFAULT_HORIZON;
use pushlab_core::experiment::report::{EvalReport, ReportContext};
use pushlab_core::experiment::{self, EvalOptions, Evaluation, Loaded, UsedRecording};
use pushlab_core::labels::Split;
use pushlab_core::learn::WeightConfig;
use pushlab_core::model::{
    CombinedModel, DEFAULT_CONTACT_TOLERANCE, FrameLoss, ModelKind, PureNnModel,
};
use pushlab_core::model_file::ModelFile;

use super::args::{OnlineArgs, TrainingArgs, offset_xy, positive_real, unit_interval};
use super::data;
use super::train::train_config;
use super::train_progress::{self, TrainedModels};
use crate::cli::exit::Failure;
use pushlab::figures::Format;
use pushlab::figures::eval::{self as plot, Figure, OfflineMeans, StepLosses};

/// Arguments of `pushlab eval`.
#[derive(Debug, Args)]
pub struct EvalArgs {
    /// Recordings for offline training (files or folders, as for `pushlab validate`). Needed
    /// unless --model is given; with --model they add the Offline rows (and train the pure network
    /// when the model file has none).
    #[arg(long, required_unless_present = "model", num_args = 1.., value_name = "PATH")]
    pub offline: Vec<PathBuf>,
    /// Recordings streamed to online learning.
    #[arg(long, required = true, num_args = 1.., value_name = "PATH")]
    pub online: Vec<PathBuf>,
    /// Use this trained model instead of training on --offline (its pure network too, when the file
    /// has one; otherwise the pure network is trained on --offline when given). --offline is then
    /// optional.
    #[arg(long, value_name = "MODEL.json")]
    pub model: Option<PathBuf>,
    #[command(flatten)]
    pub training: TrainingArgs,
    #[command(flatten)]
    pub online_rule: OnlineArgs,
    /// Write the results as JSON (the format is documented in the guide, docs/src/experiments.md).
    #[arg(long, value_name = "OUT.json")]
    pub json: Option<PathBuf>,
    /// With --json: also list θ_online and the online and fixed losses at every frame of every
    /// online trajectory (what the app shows for the same recording, model and settings).
    #[arg(long, requires = "json")]
    pub per_frame: bool,
    /// Draw the paper-style figure of the online losses: a PNG, or a vector figure (text as text,
    /// the font embedded) when the name ends in .svg or .pdf.
    #[arg(long, value_name = "OUT.png|OUT.svg|OUT.pdf", value_parser = figure_path)]
    pub plot: Option<PathBuf>,
    /// Also evaluate the physics-only model (object outline + Lynch, no network).
    #[arg(long)]
    pub physics: bool,
    /// For --physics: how far the pusher's rim may be from the outline and still count as touching
    /// it, metres. Tracked poses are noisy (the sample data: 2 mm, 0.5°, about 3 mm on the gap);
    /// without contact the physics-only model predicts no motion.
    #[arg(long, value_name = "METRES", default_value_t = DEFAULT_CONTACT_TOLERANCE, value_parser = positive_real)]
    pub contact_tolerance: f64,
    /// Carry θ_online and its posterior from each online recording to the next when both push the
    /// same object (same folder, footprint, material and pusher), in the order given, instead of
    /// starting every push from θ_online(0): a push on one face barely sees the COM's depth along
    /// its normal, the next push on another face does.
    #[arg(long)]
    pub carry_theta: bool,
    /// Start every push not carried on from another believing the COM this far from θ_online(0)'s
    /// (object frame, metres, e.g. 0.02,0; kept inside the object), the prior centred there, for
    /// the combined and the physics-only model: whether online learning finds a COM it was not
    /// given. On real recordings, whose COM is where θ_online(0) puts it, the one way to see it.
    #[arg(long, value_name = "X,Y", value_parser = offset_xy, allow_hyphen_values = true)]
    pub start_com_shift: Option<[f64; 2]>,
    /// For --physics: the half-life, seconds, of the evidence that weighs the combined model
    /// against the physics-only one in the "weighted" column (how far back "predicted better
    /// lately" looks).
    #[arg(long, value_name = "S", default_value_t = WeightConfig::default().half_life_s, value_parser = positive_real)]
    pub weight_half_life: f64,
    /// For --physics: the combined model's weight before any frame is seen, 0–1.
    #[arg(long, value_name = "W", default_value_t = WeightConfig::default().prior, value_parser = unit_interval)]
    pub weight_prior: f64,
    /// Also find, for each online push, the θ_online that fits the whole push best (a grid over
    /// the object, then Levenberg–Marquardt; with --physics for the physics-only model too): what
    /// no online learner with the model can beat on that push. Where the best COM is as far from
    /// the truth as the learned one, the limit is the model, not the learning.
    #[arg(long)]
    pub best_fit: bool,
}

/// Runs `pushlab eval`.
pub fn run(args: &EvalArgs) -> Result<(), Failure> {
    let started = Instant::now();
    // Ctrl-C from here on stops training cleanly instead of killing the process.
    train_progress::cancel_flag();
    let model_file = match &args.model {
        Some(path) => Some(ModelFile::load(path).map_err(|e| anyhow!("{e}"))?),
        None => None,
    };
    let horizon = match (&model_file, args.training.horizon) {
        (Some(m), Some(k)) if k != m.combined.horizon() => {
            return Err(Failure::Usage(anyhow!(
                "--horizon {k} differs from the horizon the model was trained for ({}); leave --horizon out or retrain",
                m.combined.horizon()
            )));
        }
        (Some(m), _) => m.combined.horizon(),
        (None, k) => k.unwrap_or(DEFAULT_HORIZON),
    };
    let kind = match (&model_file, args.training.model_kind) {
        (Some(m), Some(k)) if k != m.combined.kind() => {
            return Err(Failure::Usage(anyhow!(
                "--model-kind {k} differs from the kind of the model file ({}); leave --model-kind out",
                m.combined.kind()
            )));
        }
        (Some(m), _) => m.combined.kind(),
        (None, k) => k.unwrap_or_default(),
    };
    let by_split = args.training.split_from_labels;
    let has_offline = !args.offline.is_empty();
    let offline = match has_offline {
        true => experiment::load(&args.offline, by_split.then_some(Split::Offline), horizon),
        false => Loaded::default(),
    };
    let online = experiment::load(&args.online, by_split.then_some(Split::Online), horizon);
    if has_offline {
        data::print_summary("offline", &offline, horizon);
    } else {
        println!("no --offline: the offline rows are not computed");
    }
    data::print_summary("online", &online, horizon);
    let given = [("--offline", &offline)]
        .into_iter()
        .filter(|_| has_offline);
    for (role, loaded) in given.chain([("--online", &online)]) {
        if loaded.used.is_empty() {
            return Err(Failure::Failed(anyhow!(
                "nothing usable in {role}: {}",
                loaded.why_nothing(horizon)
            )));
        }
    }

    // The one core check of a model's domain (the app's too): the model file's, or that of the
    // offline data the model is about to be trained on.
    let domain = match &model_file {
        Some(m) => m.training.domain.clone(),
        None => Domain::of(offline.used.iter().map(|u| &u.recording), horizon),
    };
    if let Some(mismatch) =
        domain.and_then(|d| d.mismatch(online.used.iter().map(|u| &u.recording)))
    {
        eprintln!("warning: {}", mismatch.message);
    }

    let training_started = Instant::now();
    let calibrate = !args.training.no_com_calibration;
    let (combined, pure_nn, trained_with) =
        models(model_file, args, horizon, kind, &offline.used, calibrate)?;
    let training_time = training_started.elapsed();
    if train_progress::cancelled() {
        println!("training stopped by Ctrl-C: evaluating the best models so far");
    }

    let pass_started = Instant::now();
    let options = EvalOptions {
        online: args.online_rule.config(),
        physics: args.physics.then_some(args.contact_tolerance),
        carry: args.carry_theta,
        start_com_shift: args.start_com_shift,
        weighting: WeightConfig {
            half_life_s: args.weight_half_life,
            prior: args.weight_prior,
        },
    };
    let mut evaluation = experiment::evaluate(
        &combined,
        pure_nn.as_ref(),
        &offline.used,
        &online.used,
        &options,
    );
    if args.best_fit {
        find_best_fits(&mut evaluation, &combined, &online.used, &options);
    }
    let pass_time = pass_started.elapsed();

    let report = EvalReport::of(
        &evaluation,
        &ReportContext {
            offline: &offline,
            online: &online,
            horizon,
            kind,
            epochs: trained_with.epochs,
            seed: trained_with.seed,
            config: options.online,
            carry: options.carry,
            start_com_shift: options.start_com_shift,
            model: args.model.as_ref().map(|p| p.display().to_string()),
            split_from_labels: args.training.split_from_labels,
            per_frame: args.per_frame,
        },
    );
    table::print_tables(&report, &evaluation, &online.used);
    if let Some(path) = &args.json {
        let mut json = serde_json::to_vec_pretty(&report).context("cannot encode the report")?;
        json.push(b'\n');
        write_atomically(path, &json)
            .with_context(|| format!("cannot write {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &args.plot {
        let steps_of = |losses: Vec<FrameLoss>| StepLosses {
            total: losses.iter().map(FrameLoss::total).collect(),
            pos: losses.iter().map(|l| l.pos).collect(),
            rot: losses.iter().map(|l| l.rot).collect(),
        };
        let runs = &evaluation.trajectories;
        let fixed: Vec<StepLosses> = runs.iter().map(|r| steps_of(r.fixed().collect())).collect();
        let learning: Vec<StepLosses> = runs
            .iter()
            .map(|r| steps_of(r.online().collect()))
            .collect();
        let title = match has_offline {
            true => format!(
                "{kind} model — offline: {}   online: {}",
                setting_names(&offline.used),
                setting_names(&online.used)
            ),
            false => format!("{kind} model — online: {}", setting_names(&online.used)),
        };
        let figure = Figure {
            title,
            fixed: &fixed,
            online: &learning,
            offline: evaluation.offline_means.map(|means| OfflineMeans {
                total: means.total,
                pos: means.pos,
                rot: means.rot,
            }),
        };
        plot::write(path, &figure)?;
        println!("wrote {}", path.display());
    }
    println!(
        "eval took {:.2} s (training {:.2} s, evaluation {:.2} s)",
        started.elapsed().as_secs_f64(),
        training_time.as_secs_f64(),
        pass_time.as_secs_f64()
    );
    Ok(())
}

/// Each push's best θ, with a progress bar on stderr; Ctrl-C stops it, keeping the pushes done.
fn find_best_fits(
    evaluation: &mut Evaluation,
    model: &CombinedModel,
    online: &[UsedRecording],
    options: &EvalOptions,
) {
    let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
    if let Ok(style) =
        ProgressStyle::with_template("{prefix:>13} [{bar:30}] push {pos}/{len} ({eta})")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_prefix("best θ");
    let finished = evaluation.find_best_fits(
        model,
        online,
        options,
        &mut |done, total| {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
        },
        &train_progress::cancelled,
    );
    bar.finish_and_clear();
    if !finished {
        println!("best θ stopped by Ctrl-C: the pushes done so far are reported");
    }
}

/// The training configuration that made the combined model.
struct TrainedWith {
    epochs: usize,
    seed: u64,
}

/// The combined model and the pure network: loaded, or trained on the offline recordings. The pure
/// network is `None` when a model file without one is evaluated without offline recordings.
fn models(
    file: Option<ModelFile>,
    args: &EvalArgs,
    horizon: usize,
    kind: ModelKind,
    offline: &[UsedRecording],
    calibrate: bool,
) -> anyhow::Result<(CombinedModel, Option<PureNnModel>, TrainedWith)> {
    let config = || train_config(&args.training, horizon, kind, offline);
    let Some(file) = file else {
        let config = config();
        let TrainedModels { combined, pure_nn } =
            train_progress::train_models(kind, offline, &config, calibrate, true)?;
        if !combined.report.kept_an_epoch() {
            bail!("stopped by Ctrl-C before the first epoch ended: no model to evaluate");
        }
        let pure_nn = match pure_nn {
            Some(trained) => trained.model,
            // Ctrl-C before the baseline had an epoch: the table's "Offline NN" row still needs
            // a trained network, not random weights, so it trains to its end (a second Ctrl-C
            // quits at once).
            None => train_progress::train_pure_nn(offline, &config, &AtomicBool::new(false))?.model,
        };
        let with = TrainedWith {
            epochs: combined.report.config.epochs,
            seed: combined.report.config.seed,
        };
        return Ok((combined.model, Some(pure_nn), with));
    };
    let with = match &file.training.report {
        Some(r) => TrainedWith {
            epochs: r.config.epochs,
            seed: r.config.seed,
        },
        None => TrainedWith {
            epochs: args.training.epochs,
            seed: args.training.seed,
        },
    };
    let pure_nn = match file.pure_nn {
        Some(nn) if nn.horizon() == file.combined.horizon() => Some(nn),
        _ if offline.is_empty() => {
            println!(
                "the model file has no pure network for this horizon and there is no --offline to \
                 train one on: the NN rows are not computed"
            );
            None
        }
        _ => {
            println!(
                "the model file has no pure network for this horizon: training one on --offline"
            );
            // The table needs it trained, as above.
            let config = config();
            Some(train_progress::train_pure_nn(offline, &config, &AtomicBool::new(false))?.model)
        }
    };
    Ok((file.combined, pure_nn, with))
}

/// The distinct setting names of some recordings, joined with "+".
fn setting_names(used: &[UsedRecording]) -> String {
    let mut names: Vec<&str> = Vec::new();
    for u in used {
        let name = u.recording.setting.name.as_str();
        if !names.contains(&name) {
            names.push(name);
        }
    }
    names.join("+")
}

/// A figure's file name: its format checked before anything is trained.
fn figure_path(text: &str) -> Result<PathBuf, String> {
    let path = PathBuf::from(text);
    Format::of(&path)?;
    Ok(path)
}
