//! A list of experiments run into one table: for each, every model (kind or ablation, see
//! [`ModelVariant`]) trained on its offline recordings and evaluated on its online ones, and the
//! physics-only model beside them.
//!
//! The spec is JSON; paths are relative to the spec file's folder and may use `*` and `?` in their
//! last component (`mit/*shape=hex*`):
//!
//! ```json
//! { "horizon": 10, "split_from_labels": true, "models": ["contact", "paper"], "physics": true,
//!   "experiments": [
//!     { "name": "R4a", "offline": ["sample-data/box1-paper-center-front"],
//!       "online": ["sample-data/box1-paper-center-left"] } ] }
//! ```
//!
//! An experiment may compare fewer models than the suite (`"models": ["paper"]`, each one of the
//! suite's): its first is the one weighed with physics alone, and the one its demo in the app
//! shows.
//!
//! Experiments run in parallel, one per worker thread; each is computed exactly as alone (seeded
//! training, nothing shared), so the numbers do not depend on the number of workers.

use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use web_time::Instant;

use serde::{Deserialize, Serialize};

use super::data::{Skipped, load};
use super::evaluate::{EvalOptions, PhysicsNmse, evaluate};
use super::train::train_combined;
use super::variant::ModelVariant;
use crate::json_problem::{self, JsonProblem};
use crate::labels::Split;
use crate::learn::{Nmse, OnlineConfig, TrainConfig};
use crate::model::{DEFAULT_CONTACT_TOLERANCE, ModelKind};
use crate::pattern::wildcard_match;

/// A suite as written in its JSON file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SuiteSpec {
    /// Prediction horizon in frames for every experiment that does not give its own.
    #[serde(default = "one")]
    pub horizon: usize,
    /// Offline recordings are those whose split is offline, online those whose split is online.
    #[serde(default)]
    pub split_from_labels: bool,
    #[serde(default = "default_epochs")]
    pub epochs: usize,
    #[serde(default)]
    pub seed: u64,
    #[serde(default = "default_patience")]
    pub patience: usize,
    /// The models to compare (default: every kind): `contact`, `paper`, or the ablations
    /// `contact-no-prior`, `contact-prior-only`, `paper-augmented`.
    #[serde(default = "all_kinds")]
    pub models: Vec<ModelVariant>,
    /// Also the physics-only model.
    #[serde(default = "yes")]
    pub physics: bool,
    #[serde(default = "default_tolerance")]
    pub contact_tolerance: f64,
    #[serde(default = "default_steps")]
    pub steps: usize,
    #[serde(default = "default_lr")]
    pub lr: f64,
    /// `gd` (the paper's, default) or `gauss-newton`.
    #[serde(default)]
    pub optimizer: crate::learn::Optimizer,
    /// Each online recording goes on from where the one before it ended when both push the same
    /// object (`pushlab eval --carry-theta`; `EvalOptions::carry`).
    #[serde(default)]
    pub carry_theta: bool,
    pub experiments: Vec<ExperimentSpec>,
}

/// One experiment of a suite.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExperimentSpec {
    pub name: String,
    pub offline: Vec<String>,
    pub online: Vec<String>,
    #[serde(default)]
    pub horizon: Option<usize>,
    /// The models this experiment compares, when not all of the suite's (each one of them, so
    /// that the table has its columns): the first is the one weighed with physics alone, and the
    /// one its demo trains and shows.
    #[serde(default)]
    pub models: Option<Vec<ModelVariant>>,
}

fn one() -> usize {
    1
}
fn default_epochs() -> usize {
    100
}
fn default_patience() -> usize {
    15
}
fn all_kinds() -> Vec<ModelVariant> {
    ModelKind::ALL.map(ModelVariant::Kind).to_vec()
}
fn yes() -> bool {
    true
}
fn default_tolerance() -> f64 {
    DEFAULT_CONTACT_TOLERANCE
}
fn default_steps() -> usize {
    5
}
fn default_lr() -> f64 {
    0.005
}

/// Why a suite could not be read.
#[derive(Debug, thiserror::Error)]
pub enum SuiteError {
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: {problem}")]
    Malformed { path: PathBuf, problem: JsonProblem },
    #[error("{path}: {message}")]
    Invalid { path: PathBuf, message: String },
}

impl SuiteSpec {
    /// Reads and checks a suite file.
    pub fn load(path: &Path) -> Result<Self, SuiteError> {
        let bytes = crate::files::read(path).map_err(|source| SuiteError::Io {
            path: path.to_owned(),
            source,
        })?;
        let spec: SuiteSpec =
            json_problem::from_file_bytes(&bytes).map_err(|problem| SuiteError::Malformed {
                path: path.to_owned(),
                problem,
            })?;
        let invalid = |message: String| SuiteError::Invalid {
            path: path.to_owned(),
            message,
        };
        if spec.experiments.is_empty() {
            return Err(invalid("\"experiments\" is empty: nothing to run".into()));
        }
        if spec.models.is_empty() {
            return Err(invalid("\"models\" is empty: no model to evaluate".into()));
        }
        if spec.horizon == 0 || spec.epochs == 0 {
            return Err(invalid(
                "\"horizon\" and \"epochs\" must be at least 1".into(),
            ));
        }
        if !(spec.lr.is_finite() && spec.lr > 0.0) {
            return Err(invalid(format!(
                "\"lr\" must be above 0, found {}",
                spec.lr
            )));
        }
        for (i, e) in spec.experiments.iter().enumerate() {
            if e.offline.is_empty() || e.online.is_empty() {
                return Err(invalid(format!(
                    "experiments[{i}] (\"{}\"): \"offline\" and \"online\" each need at least one path",
                    e.name
                )));
            }
            if e.horizon == Some(0) {
                return Err(invalid(format!(
                    "experiments[{i}] (\"{}\"): \"horizon\" must be at least 1",
                    e.name
                )));
            }
            if let Some(models) = &e.models {
                if models.is_empty() {
                    return Err(invalid(format!(
                        "experiments[{i}] (\"{}\"): \"models\" is empty: leave it out to compare the suite's",
                        e.name
                    )));
                }
                if let Some(other) = models.iter().find(|m| !spec.models.contains(m)) {
                    return Err(invalid(format!(
                        "experiments[{i}] (\"{}\"): \"models\" names {}, which is not one of the suite's \"models\" (its table has no column for it)",
                        e.name,
                        other.name()
                    )));
                }
            }
        }
        Ok(spec)
    }

    /// The horizon `experiment` runs at: its own, else the suite's.
    pub fn horizon_of(&self, experiment: &ExperimentSpec) -> usize {
        experiment.horizon.unwrap_or(self.horizon)
    }

    /// The models `experiment` compares, in order: its own, else the suite's. The first is weighed
    /// with physics alone, and is what its demo trains and shows.
    pub fn models_of<'a>(&'a self, experiment: &'a ExperimentSpec) -> &'a [ModelVariant] {
        experiment.models.as_deref().unwrap_or(&self.models)
    }

    /// The split the recordings of a role (offline or online) must be in to be used: `Some` when the
    /// suite takes splits from labels (`split_from_labels`), `None` when every recording counts.
    pub fn split_wanted(&self, role: Split) -> Option<Split> {
        self.split_from_labels.then_some(role)
    }

    /// How `variant` is trained in `experiment`: the suite's epochs, seed and patience at the
    /// experiment's horizon, adjusted by the variant.
    pub fn train_config(&self, experiment: &ExperimentSpec, variant: ModelVariant) -> TrainConfig {
        variant.configure(&TrainConfig {
            epochs: self.epochs,
            seed: self.seed,
            patience: self.patience,
            horizon: self.horizon_of(experiment),
            ..TrainConfig::default()
        })
    }
}

impl ExperimentSpec {
    /// The offline paths, relative to `base` (the spec file's folder), wildcards expanded.
    pub fn offline_paths(&self, base: &Path) -> Vec<PathBuf> {
        expand(base, &self.offline)
    }

    /// The online paths, relative to `base`, wildcards expanded.
    pub fn online_paths(&self, base: &Path) -> Vec<PathBuf> {
        expand(base, &self.online)
    }
}

/// One model's numbers in one experiment.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModelResult {
    pub model: ModelVariant,
    pub offline: Nmse,
    pub fixed: Nmse,
    pub online: Nmse,
    /// Epochs run and the epoch kept.
    pub epochs_run: usize,
    pub best_epoch: usize,
    /// Training plus evaluation, seconds.
    pub seconds: f64,
}

/// One experiment's row.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ExperimentResult {
    pub name: String,
    pub horizon: usize,
    pub offline_recordings: usize,
    pub online_recordings: usize,
    pub offline_samples: usize,
    pub online_samples: usize,
    pub models: Vec<ModelResult>,
    pub physics: Option<PhysicsNmse>,
    /// Why the experiment (or one of its kinds) could not run; the numbers that did run are kept.
    pub errors: Vec<String>,
    /// Files and recordings left out, with the reason.
    pub skipped: Vec<Skipped>,
}

/// Runs one experiment of a suite, paths relative to `base`.
pub fn run_experiment(
    spec: &SuiteSpec,
    experiment: &ExperimentSpec,
    base: &Path,
    cancel: &AtomicBool,
) -> ExperimentResult {
    let horizon = spec.horizon_of(experiment);
    let offline = load(
        &experiment.offline_paths(base),
        spec.split_wanted(Split::Offline),
        horizon,
    );
    let online = load(
        &experiment.online_paths(base),
        spec.split_wanted(Split::Online),
        horizon,
    );
    let count = |u: &super::data::Loaded| u.samples(horizon).iter().map(Vec::len).sum();
    let mut result = ExperimentResult {
        name: experiment.name.clone(),
        horizon,
        offline_recordings: offline.used.len(),
        online_recordings: online.used.len(),
        offline_samples: count(&offline),
        online_samples: count(&online),
        models: Vec::new(),
        physics: None,
        errors: Vec::new(),
        skipped: offline
            .skipped
            .iter()
            .chain(&online.skipped)
            .cloned()
            .collect(),
    };
    for (role, loaded) in [("offline", &offline), ("online", &online)] {
        if loaded.used.is_empty() {
            result.errors.push(format!(
                "nothing usable in {role}: {}",
                loaded.why_nothing(horizon)
            ));
        }
    }
    if !result.errors.is_empty() {
        return result;
    }
    for (i, &variant) in spec.models_of(experiment).iter().enumerate() {
        let started = Instant::now();
        let config = spec.train_config(experiment, variant);
        let trained =
            match train_combined(variant.kind(), &offline.used, &config, &mut |_| {}, cancel) {
                Ok(trained) => trained,
                Err(e) => {
                    result.errors.push(format!("{}: {e}", variant.name()));
                    continue;
                }
            };
        if !trained.report.kept_an_epoch() {
            // Cancelled before its first epoch ended: random weights are no model to report.
            result.errors.push(format!(
                "{}: cancelled before its first epoch ended",
                variant.name()
            ));
            break;
        }
        // The physics-only model's losses are normalised like the first model's (every model's σ
        // comes from the same offline samples).
        let options = EvalOptions {
            online: OnlineConfig {
                steps: spec.steps,
                lr: spec.lr,
                optimizer: spec.optimizer,
            },
            physics: (spec.physics && i == 0).then_some(spec.contact_tolerance),
            carry: spec.carry_theta,
            start_com_shift: None,
            weighting: Default::default(),
        };
        let evaluation = evaluate(&trained.model, None, &offline.used, &online.used, &options);
        if let Some(physics) = evaluation.physics {
            result.physics = Some(physics);
        }
        result.skipped.extend(evaluation.left_out);
        result.models.push(ModelResult {
            model: variant,
            // A suite's experiments always have offline recordings (checked when the spec is read).
            offline: evaluation.offline.unwrap_or_default(),
            fixed: evaluation.fixed,
            online: evaluation.online,
            epochs_run: trained.report.epochs_run,
            best_epoch: trained.report.best_epoch,
            seconds: started.elapsed().as_secs_f64(),
        });
    }
    result
}

/// Runs every experiment of a suite on `workers` threads (at least one); `progress` is told each
/// experiment that finishes and how many have. Results are in the spec's order.
#[cfg_attr(
    target_arch = "wasm32",
    expect(
        clippy::disallowed_methods,
        reason = "the suite is the command line's, never a page's"
    )
)]
pub fn run_suite(
    spec: &SuiteSpec,
    base: &Path,
    workers: usize,
    progress: &(dyn Fn(&ExperimentResult, usize) + Sync),
    cancel: &AtomicBool,
) -> Vec<ExperimentResult> {
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<ExperimentResult>>> =
        Mutex::new(vec![None; spec.experiments.len()]);
    std::thread::scope(|scope| {
        for _ in 0..workers.clamp(1, spec.experiments.len().max(1)) {
            scope.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::SeqCst);
                    if i >= spec.experiments.len() || cancel.load(Ordering::Relaxed) {
                        break;
                    }
                    let result = run_experiment(spec, &spec.experiments[i], base, cancel);
                    let finished = done.fetch_add(1, Ordering::SeqCst) + 1;
                    progress(&result, finished);
                    if let Ok(mut all) = results.lock() {
                        all[i] = Some(result);
                    }
                }
            });
        }
    });
    results
        .into_inner()
        .unwrap_or_default()
        .into_iter()
        .flatten()
        .collect()
}

/// The paths of a spec, relative to `base`, with `*` and `?` in the last component expanded (sorted;
/// a pattern that matches nothing is kept, so that loading reports it as missing). A path named twice
/// (or matched by two patterns) is used once, so that no recording counts double in a mean.
pub fn expand(base: &Path, paths: &[String]) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut seen = std::collections::HashSet::new();
    let mut push = |out: &mut Vec<PathBuf>, path: PathBuf| {
        if seen.insert(path.clone()) {
            out.push(path);
        }
    };
    for path in paths {
        let full = base.join(path);
        let name = full
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        if !name.contains(['*', '?']) {
            push(&mut out, full);
            continue;
        }
        let folder = full.parent().unwrap_or(base).to_path_buf();
        let mut matched: Vec<PathBuf> = std::fs::read_dir(&folder)
            .into_iter()
            .flatten()
            .flatten()
            .filter(|entry| wildcard_match(&name, &entry.file_name().to_string_lossy()))
            .map(|entry| entry.path())
            .collect();
        matched.sort();
        if matched.is_empty() {
            push(&mut out, full);
        }
        for path in matched {
            push(&mut out, path);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A suite of one experiment on the sample data (paths relative to the repository's
    /// `experiments/` folder), written to a scratch file; `experiment` is the experiment's JSON
    /// members after its name and paths.
    fn one_experiment_suite(file: &str, experiment: &str) -> Result<SuiteSpec, SuiteError> {
        let dir = std::env::temp_dir().join(format!("pushlab-suite-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a scratch folder");
        let path = dir.join(file);
        let json = format!(
            r#"{{ "horizon": 10, "split_from_labels": true, "epochs": 1, "models": ["contact", "paper"],
                "experiments": [ {{ "name": "R3a", "offline": ["../sample-data/box1-paper-center-front"],
                "online": ["../sample-data/box2-paper-center-front"]{experiment} }} ] }}"#
        );
        std::fs::write(&path, json).expect("the suite written");
        SuiteSpec::load(&path)
    }

    #[test]
    fn an_experiment_compares_only_its_own_models_and_weighs_the_first() {
        let spec = one_experiment_suite("own.json", r#", "models": ["paper"]"#).expect("loads");
        assert_eq!(
            spec.models_of(&spec.experiments[0]),
            [ModelVariant::Kind(ModelKind::Paper)]
        );
        let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../experiments");
        let result = run_experiment(&spec, &spec.experiments[0], &base, &AtomicBool::new(false));
        assert!(result.errors.is_empty(), "{:?}", result.errors);
        let models: Vec<ModelVariant> = result.models.iter().map(|m| m.model).collect();
        assert_eq!(models, [ModelVariant::Kind(ModelKind::Paper)]);
        let physics = result.physics.expect("physics alone beside it");
        assert!(physics.weighted.is_some(), "the paper model weighed");
        // Without its own list, the suite's two.
        let all = one_experiment_suite("all.json", "").expect("loads");
        assert_eq!(all.models_of(&all.experiments[0]), all.models.as_slice());
    }

    #[test]
    fn an_experiments_models_must_be_some_of_the_suites() {
        let empty = one_experiment_suite("empty.json", r#", "models": []"#)
            .expect_err("an empty list is refused");
        assert!(
            empty.to_string().ends_with(
                r#"experiments[0] ("R3a"): "models" is empty: leave it out to compare the suite's"#
            ),
            "{empty}"
        );
        let other = one_experiment_suite("other.json", r#", "models": ["paper-augmented"]"#)
            .expect_err("a model the suite has no column for is refused");
        assert!(
            other.to_string().ends_with(
                r#"experiments[0] ("R3a"): "models" names paper-augmented, which is not one of the suite's "models" (its table has no column for it)"#
            ),
            "{other}"
        );
    }

    #[test]
    fn a_model_cancelled_before_its_first_epoch_ended_is_an_error_not_a_row() {
        let suite =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../../experiments/sample-data.json");
        let spec = SuiteSpec::load(&suite).expect("the sample suite loads");
        let base = suite.parent().expect("a folder");
        let cancelled = AtomicBool::new(true);
        let result = run_experiment(&spec, &spec.experiments[0], base, &cancelled);
        assert!(result.models.is_empty(), "{:?}", result.models);
        assert_eq!(result.errors.len(), 1, "{:?}", result.errors);
        assert!(
            result.errors[0].ends_with(": cancelled before its first epoch ended"),
            "{:?}",
            result.errors
        );
    }
}
