//! `pushlab eval --offline PATH... --online PATH...`: the paper's Tables I and II for any recordings.
//!
//! Trains (or loads with `--model`) the combined model and the pure network on the offline
//! recordings, then reports positional and rotational NMSE (eq. 7) for
//! - **Offline NN** and **Offline**: the pure network and the combined model on the offline data;
//! - **Fixed**: the combined model on the online data with `θ_online` kept at `θ_online(0)`;
//! - **Online**: the combined model learning `θ_online` online (eq. 13), reset to `θ_online(0)` at the
//!   start of each online trajectory;
//! - with `--physics`, the physics-only model (outline + Lynch, no network) fixed and online, which
//!   shows what the network buys.
//!
//! All losses are normalised by the σ of the offline training data (the combined model's scale), so
//! every row is comparable. `--json` writes the report documented in the README; `--plot` the figure.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, anyhow};
use clap::Args;
use pushlab_core::atomic_file::write_atomically;
use pushlab_core::labels::Split;
use pushlab_core::labels::pipeline::{LabelMean, PerLabelMeans, key_of};
use pushlab_core::learn::{
    Loss, LossScale, Nmse, OnlineConfig, OnlineLearner, OnlineModel, TrainConfig,
};
use pushlab_core::model::{CombinedModel, OnlineParams, PhysicsOnlyModel, PureNnModel, Sample};
use pushlab_core::model_file::ModelFile;
use serde::Serialize;

use super::data::{self, Loaded, Skipped, Used};
use super::plot::{self, Figure, OfflineMeans, StepLosses};
use super::train::train_config;
use super::training::{self, TrainedModels};
use super::{DEFAULT_HORIZON, Failure, TrainingArgs, positive_real};

/// Arguments of `pushlab eval`.
#[derive(Debug, Args)]
pub struct EvalArgs {
    /// Recordings for offline training (files or folders, as for `pushlab validate`).
    #[arg(long, required = true, num_args = 1.., value_name = "PATH")]
    pub offline: Vec<PathBuf>,
    /// Recordings streamed to online learning.
    #[arg(long, required = true, num_args = 1.., value_name = "PATH")]
    pub online: Vec<PathBuf>,
    /// Use this trained model instead of training on --offline (its pure network too, when the file
    /// has one; otherwise the pure network is trained on --offline).
    #[arg(long, value_name = "MODEL.json")]
    pub model: Option<PathBuf>,
    #[command(flatten)]
    pub training: TrainingArgs,
    /// Gradient-descent steps on θ_online per online time step (the paper: 5).
    #[arg(long, value_name = "N", default_value_t = 5)]
    pub steps: usize,
    /// Online learning rate on θ_online / L (the paper: 0.005).
    #[arg(long, value_name = "LR", default_value_t = 0.005, value_parser = positive_real)]
    pub lr: f64,
    /// Write the results as JSON (the format is documented in the README).
    #[arg(long, value_name = "OUT.json")]
    pub json: Option<PathBuf>,
    /// Draw the paper-style figure of the online losses as a PNG.
    #[arg(long, value_name = "OUT.png")]
    pub plot: Option<PathBuf>,
    /// Also evaluate the physics-only model (object outline + Lynch, no network).
    #[arg(long)]
    pub physics: bool,
    /// For --physics: how far the pusher's rim may be from the outline and still count as touching
    /// it, metres. Tracked poses are noisy (the sample data: 2 mm, 0.5°, about 3 mm on the gap);
    /// without contact the physics-only model predicts no motion.
    #[arg(long, value_name = "METRES", default_value_t = 0.01, value_parser = positive_real)]
    pub contact_tolerance: f64,
}

/// The JSON report: a stable contract. Fields may be added; existing ones keep their meaning.
#[derive(Debug, Serialize)]
pub struct Report {
    pub offline_nn: Nmse,
    pub offline: Nmse,
    pub fixed: Nmse,
    pub online: Nmse,
    pub trajectories: Vec<TrajectoryReport>,
    pub config: ConfigReport,
    /// With `--physics`: the physics-only model on the offline data, fixed and online.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub physics: Option<PhysicsReport>,
    /// When online recordings carry range labels: the mean total loss ℓ per label.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub per_label: Option<PerLabelReport>,
    /// Files and recordings left out, with the reason.
    pub skipped: Vec<Skipped>,
}

/// One online trajectory.
#[derive(Debug, Serialize)]
pub struct TrajectoryReport {
    pub source: String,
    /// Online time steps (samples) run.
    pub steps: usize,
    pub fixed: Nmse,
    pub online: Nmse,
    /// `θ_online` at the end of the trajectory: COM − geometric centre, object frame, metres.
    pub com_offset_learned: [f64; 2],
    pub h_learned: f64,
    /// From `setting.json`, when known (simulated sets).
    pub com_offset_true: Option<[f64; 2]>,
    pub h_true: Option<f64>,
}

/// How the numbers were made.
#[derive(Debug, Serialize)]
pub struct ConfigReport {
    pub horizon: usize,
    /// Training epochs (most) and seed of the combined model used.
    pub epochs: usize,
    pub seed: u64,
    pub steps: usize,
    pub lr: f64,
    /// The model file given with `--model`, or `null` when trained here.
    pub model: Option<String>,
    pub split_from_labels: bool,
    /// `θ_online(0)` of the combined model.
    pub theta0: OnlineParams,
    pub offline_samples: usize,
    pub online_samples: usize,
    pub offline_sources: Vec<String>,
    pub online_sources: Vec<String>,
    pub pushlab_version: String,
}

/// The physics-only baseline.
#[derive(Debug, Serialize)]
pub struct PhysicsReport {
    pub offline: Nmse,
    pub fixed: Nmse,
    pub online: Nmse,
}

/// Mean total loss per label on the online data.
#[derive(Debug, Serialize)]
pub struct PerLabelReport {
    pub fixed: Vec<LabelMeanReport>,
    pub online: Vec<LabelMeanReport>,
}

#[derive(Debug, Serialize)]
pub struct LabelMeanReport {
    pub label: String,
    pub count: usize,
    pub mean: f64,
}

impl From<LabelMean> for LabelMeanReport {
    fn from(m: LabelMean) -> Self {
        Self {
            label: m.label,
            count: m.count,
            mean: m.mean,
        }
    }
}

/// Runs `pushlab eval`.
pub fn run(args: &EvalArgs) -> Result<(), Failure> {
    let started = Instant::now();
    // Ctrl-C from here on stops training cleanly instead of killing the process.
    training::cancel_flag();
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
    let by_split = args.training.split_from_labels;
    let offline = data::load(&args.offline, by_split.then_some(Split::Offline), horizon);
    let online = data::load(&args.online, by_split.then_some(Split::Online), horizon);
    data::print_summary("offline", &offline, horizon);
    data::print_summary("online", &online, horizon);
    let offline_samples: Vec<Vec<Sample>> =
        offline.used.iter().map(|u| u.samples(horizon)).collect();
    let online_samples: Vec<Vec<Sample>> = online.used.iter().map(|u| u.samples(horizon)).collect();
    for (role, loaded) in [("--offline", &offline), ("--online", &online)] {
        if loaded.used.is_empty() {
            return Err(Failure::Failed(anyhow!(
                "nothing usable in {role}: {}",
                loaded.why_nothing(horizon)
            )));
        }
    }

    let config = train_config(&args.training, horizon, &offline.used);
    let training_started = Instant::now();
    let (combined, pure_nn, trained_with) = models(model_file, &offline_samples, &config)?;
    let training_time = training_started.elapsed();
    if training::cancelled() {
        println!("training stopped by Ctrl-C: evaluating the best models so far");
    }

    let pass_started = Instant::now();
    let online_config = OnlineConfig {
        steps: args.steps,
        lr: args.lr,
    };
    let scale = combined.loss_scale();
    let offline_losses = offline_losses(&combined, &pure_nn, &offline_samples, &scale);
    let runs: Vec<OnlineRun> = online
        .used
        .iter()
        .zip(&online_samples)
        .map(|(u, samples)| OnlineRun::of(&combined, u, samples, &online_config))
        .collect();
    let physics = args.physics.then(|| {
        physics_losses(
            &offline,
            &offline_samples,
            &online,
            &online_samples,
            &scale,
            &online_config,
            args.contact_tolerance,
        )
    });
    let pass_time = pass_started.elapsed();

    let mut skipped = offline.skipped.clone();
    skipped.extend(online.skipped.iter().cloned());
    let report = Report {
        offline_nn: Nmse::of(&offline_losses.pure_nn),
        offline: Nmse::of(&offline_losses.combined),
        fixed: Nmse::of(runs.iter().flat_map(|r| r.fixed.iter())),
        online: Nmse::of(runs.iter().flat_map(|r| r.online.iter())),
        trajectories: runs.iter().map(OnlineRun::report).collect(),
        config: ConfigReport {
            horizon,
            epochs: trained_with.epochs,
            seed: trained_with.seed,
            steps: args.steps,
            lr: args.lr,
            model: args.model.as_ref().map(|p| p.display().to_string()),
            split_from_labels: by_split,
            theta0: combined.theta0(),
            offline_samples: offline_samples.iter().map(Vec::len).sum(),
            online_samples: online_samples.iter().map(Vec::len).sum(),
            offline_sources: offline.used.iter().map(Used::source).collect(),
            online_sources: online.used.iter().map(Used::source).collect(),
            pushlab_version: env!("CARGO_PKG_VERSION").to_owned(),
        },
        physics: physics.as_ref().map(|p| PhysicsReport {
            offline: Nmse::of(&p.offline),
            fixed: Nmse::of(p.fixed.iter().flatten()),
            online: Nmse::of(p.online.iter().flatten()),
        }),
        per_label: per_label(&runs),
        skipped,
    };
    print_tables(&report, &runs);
    if let Some(path) = &args.json {
        let mut json = serde_json::to_vec_pretty(&report).context("cannot encode the report")?;
        json.push(b'\n');
        write_atomically(path, &json)
            .with_context(|| format!("cannot write {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &args.plot {
        let fixed: Vec<StepLosses> = runs.iter().map(|r| steps_of(&r.fixed)).collect();
        let learning: Vec<StepLosses> = runs.iter().map(|r| steps_of(&r.online)).collect();
        let mean = |f: fn(&Loss) -> f64| {
            let n = offline_losses.combined.len().max(1) as f64;
            offline_losses.combined.iter().map(f).sum::<f64>() / n
        };
        let figure = Figure {
            title: format!(
                "offline: {}   online: {}",
                setting_names(&offline.used),
                setting_names(&online.used)
            ),
            fixed: &fixed,
            online: &learning,
            offline: OfflineMeans {
                total: mean(Loss::total),
                pos: mean(Loss::pos),
                rot: mean(|l| l.rot),
            },
        };
        plot::write_png(path, &figure)?;
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

/// The training configuration that made the combined model.
struct TrainedWith {
    epochs: usize,
    seed: u64,
}

/// The combined model and the pure network: loaded, or trained on the offline samples.
fn models(
    file: Option<ModelFile>,
    offline: &[Vec<Sample>],
    config: &TrainConfig,
) -> anyhow::Result<(CombinedModel, PureNnModel, TrainedWith)> {
    let Some(file) = file else {
        let TrainedModels { combined, pure_nn } = training::train_models(offline, config, true)?;
        let pure_nn = match pure_nn {
            Some(trained) => trained.model,
            // Ctrl-C during the combined model's training: the baseline still needs a model.
            None => training::train_baseline(offline, config)?.model,
        };
        let with = TrainedWith {
            epochs: combined.report.config.epochs,
            seed: combined.report.config.seed,
        };
        return Ok((combined.model, pure_nn, with));
    };
    let with = match &file.training.report {
        Some(r) => TrainedWith {
            epochs: r.config.epochs,
            seed: r.config.seed,
        },
        None => TrainedWith {
            epochs: config.epochs,
            seed: config.seed,
        },
    };
    let pure_nn = match file.pure_nn {
        Some(nn) if nn.horizon() == file.combined.horizon() => nn,
        _ => {
            println!(
                "the model file has no pure network for this horizon: training one on --offline"
            );
            training::train_baseline(offline, config)?.model
        }
    };
    Ok((file.combined, pure_nn, with))
}

/// Per-sample losses of both models on the offline data, `θ_online` at `θ_online(0)`.
struct OfflineLosses {
    combined: Vec<Loss>,
    pure_nn: Vec<Loss>,
}

fn offline_losses(
    combined: &CombinedModel,
    pure_nn: &PureNnModel,
    samples: &[Vec<Sample>],
    scale: &LossScale,
) -> OfflineLosses {
    let theta0 = combined.theta0();
    let fixed = OnlineConfig::fixed();
    let mut losses = OfflineLosses {
        combined: Vec::new(),
        pure_nn: Vec::new(),
    };
    for s in samples.iter().flatten() {
        let prediction = combined.online_step(s, &theta0, &fixed).prediction;
        losses
            .combined
            .push(Loss::of(&prediction.motion, &s.target, scale));
        let prediction = pure_nn.predict(&s.input);
        losses
            .pure_nn
            .push(Loss::of(&prediction.motion, &s.target, scale));
    }
    losses
}

/// The fixed and online runs over one online trajectory.
struct OnlineRun<'a> {
    used: &'a Used,
    frames: Vec<usize>,
    fixed: Vec<Loss>,
    online: Vec<Loss>,
    theta_end: OnlineParams,
}

impl<'a> OnlineRun<'a> {
    fn of(
        model: &CombinedModel,
        used: &'a Used,
        samples: &[Sample],
        config: &OnlineConfig,
    ) -> Self {
        let theta0 = model.theta0();
        let mut learner = OnlineLearner::new(model, *config);
        learner.reset();
        let fixed_config = OnlineConfig::fixed();
        let mut run = OnlineRun {
            used,
            frames: Vec::with_capacity(samples.len()),
            fixed: Vec::with_capacity(samples.len()),
            online: Vec::with_capacity(samples.len()),
            theta_end: theta0,
        };
        for s in samples {
            run.frames.push(s.frame);
            run.fixed
                .push(model.online_step(s, &theta0, &fixed_config).loss);
            run.online.push(learner.step(s).loss);
        }
        run.theta_end = learner.theta();
        run
    }

    fn report(&self) -> TrajectoryReport {
        let setting = &self.used.recording.setting;
        TrajectoryReport {
            source: self.used.source(),
            steps: self.fixed.len(),
            fixed: Nmse::of(&self.fixed),
            online: Nmse::of(&self.online),
            com_offset_learned: self.theta_end.com_offset,
            h_learned: self.theta_end.h,
            com_offset_true: setting.com_offset,
            h_true: setting.h,
        }
    }
}

/// Per-sample losses of the physics-only model: offline (fixed), and online fixed and learning,
/// one model per recording's own outline and pusher.
struct PhysicsLosses {
    offline: Vec<Loss>,
    fixed: Vec<Vec<Loss>>,
    online: Vec<Vec<Loss>>,
}

fn physics_losses(
    offline: &Loaded,
    offline_samples: &[Vec<Sample>],
    online: &Loaded,
    online_samples: &[Vec<Sample>],
    scale: &LossScale,
    config: &OnlineConfig,
    contact_tolerance: f64,
) -> PhysicsLosses {
    let model_for = |u: &Used| -> Option<PhysicsOnlyModel> {
        let setting = &u.recording.setting;
        match setting.object.outline() {
            Ok(outline) => Some(PhysicsOnlyModel::new(
                outline,
                setting.pusher_radius,
                contact_tolerance,
                *scale,
            )),
            Err(e) => {
                println!(
                    "physics-only: {} left out: unusable outline: {e}",
                    u.source()
                );
                None
            }
        }
    };
    let mut out = PhysicsLosses {
        offline: Vec::new(),
        fixed: Vec::new(),
        online: Vec::new(),
    };
    for (u, samples) in offline.used.iter().zip(offline_samples) {
        if let Some(model) = model_for(u) {
            let theta0 = model.theta0();
            out.offline.extend(
                samples
                    .iter()
                    .map(|s| model.loss_and_gradient(s, &theta0).1),
            );
        }
    }
    for (u, samples) in online.used.iter().zip(online_samples) {
        if let Some(model) = model_for(u) {
            let theta0 = model.theta0();
            let mut learner = OnlineLearner::new(&model, *config);
            out.fixed.push(
                samples
                    .iter()
                    .map(|s| model.loss_and_gradient(s, &theta0).1)
                    .collect(),
            );
            out.online
                .push(samples.iter().map(|s| learner.step(s).loss).collect());
        }
    }
    out
}

/// Mean total loss per range label over the online data, when any online recording has labels.
fn per_label(runs: &[OnlineRun]) -> Option<PerLabelReport> {
    if !runs.iter().any(|r| {
        r.used
            .labels
            .as_ref()
            .is_some_and(|l| !l.segments.is_empty())
    }) {
        return None;
    }
    let mut fixed = PerLabelMeans::new();
    let mut online = PerLabelMeans::new();
    for r in runs {
        let key = key_of(&r.used.recording.source).unwrap_or_default();
        let labels = r.used.labels.as_ref();
        let totals = |l: &[Loss]| l.iter().map(Loss::total).collect::<Vec<_>>();
        // Lengths match by construction (one frame per loss), so adding cannot fail.
        let _ = fixed.add(&key, labels, &r.frames, &totals(&r.fixed));
        let _ = online.add(&key, labels, &r.frames, &totals(&r.online));
    }
    let list = |m: &PerLabelMeans| {
        std::iter::once(m.all())
            .chain(m.by_label())
            .map(LabelMeanReport::from)
            .collect()
    };
    Some(PerLabelReport {
        fixed: list(&fixed),
        online: list(&online),
    })
}

fn steps_of(losses: &[Loss]) -> StepLosses {
    StepLosses {
        total: losses.iter().map(Loss::total).collect(),
        pos: losses.iter().map(Loss::pos).collect(),
        rot: losses.iter().map(|l| l.rot).collect(),
    }
}

/// The distinct setting names of some recordings, joined with "+".
fn setting_names(used: &[Used]) -> String {
    let mut names: Vec<&str> = Vec::new();
    for u in used {
        let name = u.recording.setting.name.as_str();
        if !names.contains(&name) {
            names.push(name);
        }
    }
    names.join("+")
}

/// Prints the paper-style table, the physics rows, the per-trajectory results and per-label means.
fn print_tables(report: &Report, runs: &[OnlineRun]) {
    println!();
    println!("{:<18} {:>9} {:>9}   data", "NMSE", "pos", "rot");
    let row = |name: &str, n: &Nmse, data: &str| {
        println!("{name:<18} {:>9.3} {:>9.3}   {data}", n.pos, n.rot);
    };
    row("Offline NN", &report.offline_nn, "offline");
    row("Offline", &report.offline, "offline");
    row("Fixed", &report.fixed, "online");
    row("Online", &report.online, "online");
    if let Some(p) = &report.physics {
        row(
            "Physics offline",
            &p.offline,
            "offline (physics only, no network)",
        );
        row(
            "Physics fixed",
            &p.fixed,
            "online (physics only, no network)",
        );
        row(
            "Physics online",
            &p.online,
            "online (physics only, no network)",
        );
    }
    println!();
    println!(
        "{:<28} {:>5} {:>15} {:>15} {:>27} {:>15}",
        "online trajectory",
        "steps",
        "fixed pos/rot",
        "online pos/rot",
        "COM offset learned (true)",
        "h learned (true)"
    );
    for (t, r) in report.trajectories.iter().zip(runs) {
        let name = format!(
            "{}/{}",
            r.used.recording.setting.name, r.used.recording.name
        );
        let com_true = t
            .com_offset_true
            .map(|c| format!("({:.3},{:.3})", c[0], c[1]))
            .unwrap_or_else(|| "?".into());
        let h_true = t
            .h_true
            .map(|h| format!("{h:.3}"))
            .unwrap_or_else(|| "?".into());
        println!(
            "{name:<28} {:>5} {:>7.3}/{:<7.3} {:>7.3}/{:<7.3} {:>13} {:<13} {:>6.3} {:<8}",
            t.steps,
            t.fixed.pos,
            t.fixed.rot,
            t.online.pos,
            t.online.rot,
            format!(
                "({:.3},{:.3})",
                t.com_offset_learned[0], t.com_offset_learned[1]
            ),
            com_true,
            t.h_learned,
            format!("({h_true})"),
        );
    }
    if let Some(p) = &report.per_label {
        println!();
        println!(
            "{:<18} {:>8} {:>11} {:>11}",
            "mean loss by label", "frames", "fixed", "online"
        );
        for (f, o) in p.fixed.iter().zip(&p.online) {
            println!(
                "{:<18} {:>8} {:>11.3} {:>11.3}",
                f.label, f.count, f.mean, o.mean
            );
        }
    }
    println!();
}
