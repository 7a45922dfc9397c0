//! The JSON report of an evaluation (`pushlab eval --json`): a stable contract, built here beside the
//! evaluation so that every front end that writes one writes the same. Fields may be added; existing
//! ones keep their meaning.
//!
//! With per-frame output on, each trajectory also lists θ and the losses at every frame, exactly as
//! the online run kept them (`learn::OnlineRun`) — the numbers the app shows for the same recording,
//! model and settings, to the bit.

use serde::Serialize;

use super::best_fit::{BestFit, BestFitSummary};
use super::com_truth::{ComSummary, ComTruth};
use super::data::{Loaded, Skipped, UsedRecording};
use super::evaluate::{Evaluation, PhysicsNmse, PhysicsPush, TrajectoryRun};
use crate::labels::pipeline::LabelMean;
use crate::learn::uncertainty::ComSpreadParts;
use crate::learn::{Nmse, OnlineConfig, Optimizer, Weights};
use crate::model::{FrameLoss, ModelKind, OnlineParams};

/// What the numbers were made with, beyond the evaluation itself.
#[derive(Clone, Debug)]
pub struct ReportContext<'a> {
    pub offline: &'a Loaded,
    pub online: &'a Loaded,
    pub horizon: usize,
    pub kind: ModelKind,
    /// Training epochs (most) and seed of the combined model used.
    pub epochs: usize,
    pub seed: u64,
    pub config: OnlineConfig,
    /// Whether θ was carried from push to push of one object (`EvalOptions::carry`).
    pub carry: bool,
    /// Where pushes not carried on started (`EvalOptions::start_com_shift`).
    pub start_com_shift: Option<[f64; 2]>,
    /// The model file evaluated, or `None` when trained for the evaluation.
    pub model: Option<String>,
    pub split_from_labels: bool,
    /// List θ and the losses at every frame of every trajectory.
    pub per_frame: bool,
}

/// The report.
#[derive(Debug, Serialize)]
pub struct EvalReport {
    /// The pure network and the combined model on the offline data; `null` without offline data
    /// (`pushlab eval --model` with no `--offline`), or, for `offline_nn`, without a pure network.
    pub offline_nn: Option<Nmse>,
    pub offline: Option<Nmse>,
    /// The pure network on the online data, over the frames of `fixed` and `online`; `null`
    /// without a pure network.
    pub online_nn: Option<Nmse>,
    pub fixed: Nmse,
    pub online: Nmse,
    pub trajectories: Vec<TrajectoryReport>,
    pub config: ConfigReport,
    /// The physics-only model on the offline data, fixed and online, when evaluated.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub physics: Option<PhysicsNmse>,
    /// With the physics-only model: where its online run on each push left θ, to set its COM
    /// beside `trajectories`' on the same pushes.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub physics_trajectories: Vec<PhysicsTrajectoryReport>,
    /// With the physics-only model, over the pushes with a known COM: as `com_found`, for its COM.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub physics_com_found: Option<ComSummary>,
    /// When online recordings carry range labels: the mean total loss ℓ per label.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub per_label: Option<PerLabelReport>,
    /// Files and recordings left out, with the reason.
    pub skipped: Vec<Skipped>,
    /// Over the online pushes with a known COM (simulated sets): how often the 95 % ellipse holds
    /// it, the mean final error, and how fast the estimate settled within 5 mm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub com_found: Option<ComSummary>,
    /// With `--best-fit`: each push's best `θ_online` over the pushes, the combined model's and
    /// (with `--physics`) the physics-only model's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub best_fit: Option<BestFitSummary>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub physics_best_fit: Option<BestFitSummary>,
    /// With `--best-fit --carry-theta`: the best `θ_online` over all the pushes of each object at
    /// once (each chain of carried pushes), and over the objects.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub object_best_fits: Vec<ObjectBestFitReport>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub object_best_fit: Option<BestFitSummary>,
}

/// The best `θ_online` over every push of one object (`--best-fit --carry-theta`).
#[derive(Debug, Serialize)]
pub struct ObjectBestFitReport {
    /// The pushes, in order.
    pub sources: Vec<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub best_fit: Option<BestFitReport>,
}

/// One online trajectory.
#[derive(Debug, Serialize)]
pub struct TrajectoryReport {
    pub source: String,
    /// Online time steps (samples) run.
    pub steps: usize,
    pub fixed: Nmse,
    pub online: Nmse,
    /// `θ_online(0)` of this trajectory (per object for the contact-frame model).
    pub theta0: OnlineParams,
    /// θ at its first frame: `theta0`, or with `--carry-theta` where the push before it ended.
    pub theta_start: OnlineParams,
    /// Whether it went on from the push before it (`--carry-theta`, same object).
    pub continued: bool,
    /// `θ_online` at the end of the trajectory: COM − geometric centre, object frame, metres.
    pub com_offset_learned: [f64; 2],
    pub h_learned: f64,
    /// The posterior covariance of the learned COM offset (2 × 2, m², object frame; see
    /// `learn::uncertainty`).
    pub com_offset_cov: [[f64; 2]; 2],
    /// The posterior standard deviation of the learned `h`, metres.
    pub h_std: f64,
    /// What the learned COM's σ is made of: the frames, the model's COM misfit, the estimate's path
    /// drift (`learn::uncertainty::ComSpreadParts`).
    pub com_sigma_parts: ComSpreadParts,
    /// From `setting.json`, when known (simulated sets).
    pub com_offset_true: Option<[f64; 2]>,
    pub h_true: Option<f64>,
    /// With a known COM: the final error, whether the 95 % ellipse holds it, frames to settle.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub com_found: Option<ComTruth>,
    /// With `--best-fit`: the `θ_online` that fits the whole push best.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub best_fit: Option<BestFitReport>,
    /// With per-frame output: every frame that has a sample, in order.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frames: Option<Vec<FrameReport>>,
}

/// The `θ_online` that fits a whole push best (`pushlab eval --best-fit`, `experiment::best_fit`):
/// `theta`, its `nmse` and `mean_loss` over the push's `samples`.
#[derive(Debug, Serialize)]
pub struct BestFitReport {
    #[serde(flatten)]
    pub fit: BestFit,
    /// With a known COM: the distance of the best fit's COM from it, metres.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub com_error_m: Option<f64>,
}

impl BestFitReport {
    /// The report of a push's best fit, its COM error against the setting's COM when it has one.
    pub fn of(fit: Option<BestFit>, used: &UsedRecording) -> Option<Self> {
        fit.map(|fit| Self {
            com_error_m: (used.recording.setting.com_offset).map(|truth| fit.com_error_m(truth)),
            fit,
        })
    }
}

/// The physics-only model's online run on one trajectory.
#[derive(Debug, Serialize)]
pub struct PhysicsTrajectoryReport {
    pub source: String,
    /// NMSE of this push at `θ_online(0)` and learning online, as the combined model's
    /// `TrajectoryReport` gives them.
    pub fixed: Nmse,
    pub online: Nmse,
    /// The combined model and this one weighed online (`learn::ModelWeight`), and the combined
    /// model's weight after the last frame.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub weighted: Option<Nmse>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub weight_end: Option<Weights>,
    /// `θ_online` at the end of the trajectory: COM − geometric centre, object frame, metres.
    pub com_offset_learned: [f64; 2],
    pub h_learned: f64,
    /// The posterior covariance of the learned COM offset (2 × 2, m², object frame).
    pub com_offset_cov: [[f64; 2]; 2],
    /// With a known COM: the final error, whether the 95 % ellipse holds it, frames to settle.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub com_found: Option<ComTruth>,
    /// With `--best-fit`: the `θ_online` that fits the whole push best with this model.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub best_fit: Option<BestFitReport>,
}

impl PhysicsTrajectoryReport {
    fn of(p: &PhysicsPush, used: &UsedRecording) -> Self {
        Self {
            source: used.source(),
            fixed: p.fixed,
            online: p.online,
            weighted: p.weighted,
            weight_end: p.weight_end,
            com_offset_learned: p.theta_end.com_offset,
            h_learned: p.theta_end.h,
            com_offset_cov: p.com_covariance,
            com_found: p.com_truth,
            best_fit: BestFitReport::of(p.best_fit, used),
        }
    }
}

/// One frame of an online trajectory.
#[derive(Debug, Serialize)]
pub struct FrameReport {
    pub frame: usize,
    /// `θ_online` in effect at the frame: what the frame's prediction was made with.
    pub theta: OnlineParams,
    /// The online loss, or `null` where θ was held (a sample on a frame labelled bad tracking).
    pub online: Option<FrameLoss>,
    /// The fixed model's loss (θ = `θ_online(0)`).
    pub fixed: FrameLoss,
}

/// How the numbers were made.
#[derive(Debug, Serialize)]
pub struct ConfigReport {
    /// The combined model's kind: `contact` or `paper`.
    pub kind: ModelKind,
    pub horizon: usize,
    /// Training epochs (most) and seed of the combined model used.
    pub epochs: usize,
    pub seed: u64,
    pub steps: usize,
    pub lr: f64,
    pub optimizer: Optimizer,
    /// Whether θ_online and its posterior went on from each push to the next of the same object
    /// (`--carry-theta`) instead of starting from θ_online(0).
    pub carry_theta: bool,
    /// With `--start-com-shift`: how far from θ_online(0)'s COM (object frame, metres) each push
    /// not carried on started; `null` from θ_online(0).
    pub start_com_shift: Option<[f64; 2]>,
    /// The model file given, or `null` when trained for the evaluation.
    pub model: Option<String>,
    pub split_from_labels: bool,
    /// `θ_online(0)` of the first online trajectory (the paper model's, which every trajectory
    /// shares; the contact-frame model's is per object, see each trajectory).
    pub theta0: Option<OnlineParams>,
    pub offline_samples: usize,
    pub online_samples: usize,
    pub offline_sources: Vec<String>,
    pub online_sources: Vec<String>,
    pub pushlab_version: String,
}

/// Mean total loss per label on the online data.
#[derive(Debug, Serialize)]
pub struct PerLabelReport {
    pub fixed: Vec<LabelMeanReport>,
    pub online: Vec<LabelMeanReport>,
}

/// One label's mean.
#[derive(Debug, Serialize)]
pub struct LabelMeanReport {
    pub label: String,
    pub count: usize,
    pub mean: f64,
}

impl From<&LabelMean> for LabelMeanReport {
    fn from(m: &LabelMean) -> Self {
        Self {
            label: m.label.clone(),
            count: m.count,
            mean: m.mean,
        }
    }
}

impl EvalReport {
    /// The report of an evaluation.
    pub fn of(evaluation: &Evaluation, context: &ReportContext<'_>) -> Self {
        let (offline, online) = (context.offline, context.online);
        let mut skipped = offline.skipped.clone();
        skipped.extend(online.skipped.iter().cloned());
        skipped.extend(evaluation.left_out.iter().cloned());
        let count = |l: &Loaded| l.samples(context.horizon).iter().map(Vec::len).sum();
        Self {
            offline_nn: evaluation.offline_nn,
            offline: evaluation.offline,
            online_nn: evaluation.online_nn,
            fixed: evaluation.fixed,
            online: evaluation.online,
            trajectories: evaluation
                .trajectories
                .iter()
                .map(|r| TrajectoryReport::of(r, &online.used[r.recording], context.per_frame))
                .collect(),
            config: ConfigReport {
                kind: context.kind,
                horizon: context.horizon,
                epochs: context.epochs,
                seed: context.seed,
                steps: context.config.steps,
                lr: context.config.lr,
                optimizer: context.config.optimizer,
                carry_theta: context.carry,
                start_com_shift: context.start_com_shift,
                model: context.model.clone(),
                split_from_labels: context.split_from_labels,
                theta0: evaluation.trajectories.first().map(TrajectoryRun::theta0),
                offline_samples: count(offline),
                online_samples: count(online),
                offline_sources: offline.used.iter().map(UsedRecording::source).collect(),
                online_sources: online.used.iter().map(UsedRecording::source).collect(),
                pushlab_version: env!("CARGO_PKG_VERSION").to_owned(),
            },
            physics: evaluation.physics,
            physics_trajectories: (evaluation.physics_pushes.iter())
                .map(|p| PhysicsTrajectoryReport::of(p, &online.used[p.recording]))
                .collect(),
            physics_com_found: evaluation.physics_com_summary,
            per_label: evaluation.per_label.as_ref().map(|p| PerLabelReport {
                fixed: p.fixed.iter().map(LabelMeanReport::from).collect(),
                online: p.online.iter().map(LabelMeanReport::from).collect(),
            }),
            skipped,
            com_found: evaluation.com_summary,
            best_fit: BestFitSummary::of(evaluation.trajectories.iter().filter_map(|r| {
                let truth = online.used[r.recording].recording.setting.com_offset;
                r.best_fit.as_ref().map(|fit| (fit, truth))
            })),
            physics_best_fit: BestFitSummary::of(evaluation.physics_pushes.iter().filter_map(
                |p| {
                    let truth = online.used[p.recording].recording.setting.com_offset;
                    p.best_fit.as_ref().map(|fit| (fit, truth))
                },
            )),
            object_best_fits: (evaluation.object_best_fits.iter())
                .map(|o| ObjectBestFitReport {
                    sources: o
                        .recordings
                        .iter()
                        .map(|&r| online.used[r].source())
                        .collect(),
                    best_fit: BestFitReport::of(o.fit, &online.used[o.recordings[0]]),
                })
                .collect(),
            object_best_fit: BestFitSummary::of(evaluation.object_best_fits.iter().filter_map(
                |o| {
                    let truth = online.used[o.recordings[0]].recording.setting.com_offset;
                    o.fit.as_ref().map(|fit| (fit, truth))
                },
            )),
        }
    }
}

impl TrajectoryReport {
    fn of(r: &TrajectoryRun, used: &UsedRecording, per_frame: bool) -> Self {
        let setting = &used.recording.setting;
        let theta_end = r.theta_end();
        let posterior = r.posterior_end();
        Self {
            source: used.source(),
            steps: r.steps(),
            fixed: r.fixed_nmse(),
            online: r.online_nmse(),
            theta0: r.theta0(),
            theta_start: r.run.theta_at(0),
            continued: r.continued,
            com_offset_learned: theta_end.com_offset,
            h_learned: theta_end.h,
            com_offset_cov: posterior.com_covariance(),
            h_std: posterior.std()[2],
            com_sigma_parts: posterior.com_spread_parts(),
            com_offset_true: setting.com_offset,
            h_true: setting.h,
            com_found: r.com_truth,
            best_fit: BestFitReport::of(r.best_fit, used),
            frames: per_frame.then(|| {
                let run = &r.run;
                (0..run.sample_count())
                    .map(|frame| FrameReport {
                        frame,
                        theta: run.theta_at(frame),
                        online: run.learned().get(frame).copied().flatten(),
                        fixed: run.fixed()[frame],
                    })
                    .collect()
            }),
        }
    }
}
