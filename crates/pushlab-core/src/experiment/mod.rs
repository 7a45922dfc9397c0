//! One experiment pipeline for the CLI and the app: which recordings and frames an experiment uses
//! ([`data`]), how a model of each kind is trained on them ([`train`]), and how it is evaluated
//! ([`evaluate`]); [`suggest`] ranks an object's next pushes by what each would teach; [`suite`] runs a list of experiments in parallel into one table; [`report`] is
//! `pushlab eval`'s JSON report.
//!
//! Every rule lives here once — the split of a recording, the samples left out for bad tracking,
//! `θ_online(0)`, the physics-only model's tolerance and loss scale, the fixed and online passes — so
//! that `pushlab train`, `pushlab eval`, the suite and the app cannot drift apart.

pub mod best_fit;
pub mod com_truth;
pub mod data;
pub mod evaluate;
pub mod misfit;
mod push_fits;
pub mod report;
mod runs;
pub mod suggest;
pub mod suite;
pub mod train;
pub mod variant;

/// Frames a model predicts ahead unless told otherwise: the paper's one step. `pushlab train` and
/// `eval` train for it without `--horizon`, and the app's physics-only model (with no trained model to
/// take a horizon from) predicts that far.
pub const DEFAULT_HORIZON: usize = 1;

pub use best_fit::{
    BestFit, BestFitSummary, ObjectBestFit, POLLS as BEST_FIT_POLLS, best_fit, best_fit_in_slices,
};
pub use com_truth::{ComSummary, ComTruth};
pub use data::{Loaded, Skipped, UsedRecording, geometry_of, load, load_all, split_of};
pub use evaluate::{
    EvalOptions, Evaluation, OfflineMeans, PerLabel, PhysicsNmse, PhysicsPush, TrajectoryRun,
    evaluate, fixed_pass, loss_scale_for, model_on, online_run, physics_model,
};
pub use misfit::{calibrate_com_misfit_in_slices, train_calibrated, train_calibrated_in_slices};
pub use push_fits::push_best_fit;
pub use train::{
    paper_theta0_for, train_baseline, train_baseline_in_slices, train_combined,
    train_combined_in_slices, training_metadata,
};
pub use variant::ModelVariant;
