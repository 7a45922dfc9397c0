//! `pushlab.Model`: a trained combined model as the core's model file — loaded, trained on
//! recordings through the core's one training pipeline (`experiment::train_calibrated`, as `pushlab
//! train` and the app), saved atomically — and its predictions and online runs.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};

use numpy::PyArray1;
use pushlab_core::experiment::UsedRecording;
use pushlab_core::experiment::report::BestFitReport;
use pushlab_core::experiment::{
    self, DEFAULT_HORIZON, TrajectoryRun, model_on, physics_model, push_best_fit, train_baseline,
    train_calibrated,
};
use pushlab_core::learn::{OnlineConfig, OnlineState, Optimizer, TrainConfig, TrainProgress};
use pushlab_core::model::{
    DEFAULT_CONTACT_TOLERANCE, ModelKind, NoOutline, OnlineParams, PhysicsOnlyModel, sample_at,
};
use pushlab_core::model_file::ModelFile;
use pyo3::exceptions::{PyIndexError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{column, theta_row, to_python};
use crate::error::error;
use crate::online::OnlineRun;
use crate::recording::Recording;

/// A trained combined model (and, when trained with it, the pure-network baseline), as a pushlab
/// model file holds it.
#[pyclass(module = "pushlab", name = "Model", frozen)]
pub struct Model {
    file: ModelFile,
}

impl Model {
    /// The model file, for the package's other classes (the controller).
    pub(crate) fn file(&self) -> &ModelFile {
        &self.file
    }
}

#[pymethods]
impl Model {
    /// Reads a model file (`pushlab train --out`, the app's Save model); every rule a model file
    /// keeps is checked, and a refusal names the file and the JSON field.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let file = py.detach(|| ModelFile::load(&path)).map_err(error)?;
        Ok(Self { file })
    }

    /// Trains a combined model on recordings, as `pushlab train` does: Adam at `adam_lr` (default
    /// 0.005), batches of 32,
    /// stopping early when the validation loss stops improving for `patience` epochs; samples on
    /// frames labelled bad tracking left out, recordings without a sample at `horizon` skipped.
    /// `kind` is "contact" (default) or "paper"; with `baseline=True` the pure network is trained
    /// too and kept in the file. With `com_calibration=True` (default) and recordings of two or more
    /// objects with a known COM, the COM misfit is measured by leaving each object out of training
    /// in turn (one extra training each) and widens the COM ellipse. Unset options take pushlab's
    /// defaults (`pushlab train --help`).
    /// Ctrl-C stops training at the end of an epoch and raises KeyboardInterrupt.
    #[staticmethod]
    #[pyo3(signature = (recordings, *, kind=None, horizon=None, epochs=None, seed=None, patience=None, adam_lr=None, baseline=false, com_calibration=true))]
    #[allow(clippy::too_many_arguments)]
    fn train(
        py: Python<'_>,
        recordings: Vec<PyRef<'_, Recording>>,
        kind: Option<&str>,
        horizon: Option<usize>,
        epochs: Option<usize>,
        seed: Option<u64>,
        patience: Option<usize>,
        adam_lr: Option<f64>,
        baseline: bool,
        com_calibration: bool,
    ) -> PyResult<Self> {
        let kind = match kind {
            Some(name) => ModelKind::from_name(name).ok_or_else(|| {
                let names: Vec<&str> = ModelKind::ALL.iter().map(|k| k.name()).collect();
                PyValueError::new_err(format!(
                    "unknown model kind {name:?}; expected one of {}",
                    names.join(", ")
                ))
            })?,
            None => ModelKind::default(),
        };
        let horizon = horizon.unwrap_or(DEFAULT_HORIZON);
        if horizon == 0 {
            return Err(PyValueError::new_err("horizon: must be at least 1"));
        }
        let defaults = TrainConfig::default();
        let config = TrainConfig {
            epochs: epochs.unwrap_or(defaults.epochs),
            seed: seed.unwrap_or(defaults.seed),
            patience: patience.unwrap_or(defaults.patience),
            learning_rate: adam_lr.unwrap_or(defaults.learning_rate),
            horizon,
            ..defaults
        };
        let used: Vec<_> = recordings
            .iter()
            .map(|r| r.used.clone())
            .filter(|u| u.has_samples(horizon))
            .collect();
        if recordings.is_empty() {
            return Err(error("nothing to train on: no recordings given"));
        }
        if used.is_empty() {
            return Err(error(format!(
                "nothing to train on: none of the {} recording(s) has a sample at horizon {horizon}",
                recordings.len()
            )));
        }
        let cancel = AtomicBool::new(false);
        let mut interrupted: Option<PyErr> = None;
        let trained = py.detach(|| {
            // Between epochs: a pending Ctrl-C stops training cleanly.
            let mut progress = |_: &TrainProgress| {
                if let Err(e) = Python::attach(|py| py.check_signals()) {
                    interrupted = Some(e);
                    cancel.store(true, Ordering::Relaxed);
                }
            };
            let combined = train_calibrated(
                kind,
                &used,
                &config,
                com_calibration,
                &mut progress,
                &cancel,
            )?;
            let pure_nn = if baseline && !cancel.load(Ordering::Relaxed) {
                Some(train_baseline(&used, &config, &mut progress, &cancel)?)
            } else {
                None
            };
            Ok::<_, pushlab_core::learn::TrainError>((combined, pure_nn))
        });
        if let Some(e) = interrupted {
            return Err(e);
        }
        let (combined, pure_nn) = trained.map_err(error)?;
        let file = ModelFile::from_training(
            combined,
            pure_nn,
            experiment::training_metadata(&used, horizon),
        );
        Ok(Self { file })
    }

    /// Writes the model file atomically (a model that breaks a rule of the format is refused before
    /// anything is written).
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        py.detach(|| self.file.save(&path)).map_err(error)
    }

    /// "contact" or "paper".
    #[getter]
    fn kind(&self) -> &'static str {
        self.file.combined.kind().name()
    }

    /// Frames each prediction looks ahead.
    #[getter]
    fn horizon(&self) -> usize {
        self.file.combined.horizon()
    }

    /// Whether the file holds the pure-network baseline.
    #[getter]
    fn has_baseline(&self) -> bool {
        self.file.pure_nn.is_some()
    }

    /// How it was trained: reports, sources, pushlab version and the domain (a dict).
    #[getter]
    fn training<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.file.training)
    }

    /// θ_online(0) for a recording's object, `[com_x, com_y, h]` in metres.
    fn theta0<'py>(
        &self,
        py: Python<'py>,
        recording: &Recording,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let learner = model_on(&self.file.combined, &recording.used).map_err(error)?;
        Ok(column(py, theta_row(&learner.theta0()).to_vec()))
    }

    /// Predicts how the object moves from `frame` to `frame + horizon` with θ_online = `theta`
    /// (`[com_x, com_y, h]` in metres, the COM offset within ±2 and `h` in [0.001, 2]; default
    /// θ_online(0) for the recording's object), next to what was observed and the loss.
    #[pyo3(signature = (recording, frame, theta=None))]
    fn predict(
        &self,
        recording: &Recording,
        frame: usize,
        theta: Option<[f64; 3]>,
    ) -> PyResult<Prediction> {
        let learner = model_on(&self.file.combined, &recording.used).map_err(error)?;
        let horizon = self.file.combined.horizon();
        let trajectory = &recording.used.recording.trajectory;
        let sample = sample_at(trajectory, frame, horizon).ok_or_else(|| {
            PyIndexError::new_err(format!(
                "frame {frame} has no sample: {} has {} frames and the model predicts {horizon} frame(s) ahead",
                recording.used.recording.name,
                trajectory.len()
            ))
        })?;
        let theta = match theta {
            Some([x, y, h]) => OnlineParams {
                com_offset: [x, y],
                h,
            }
            .checked()
            .map_err(|why| PyValueError::new_err(format!("theta: {why}")))?,
            None => learner.theta0(),
        };
        let step = learner.evaluate(&sample, &theta);
        let p = step.prediction;
        Ok(Prediction {
            frame,
            theta: theta_row(&theta),
            translation: p.motion.translation,
            rotation: p.motion.rotation,
            contact: p.contact,
            contact_motion: p.contact_motion,
            observed_translation: sample.target.translation,
            observed_rotation: sample.target.rotation,
            loss_pos: step.loss.pos(),
            loss_rot: step.loss.rot,
        })
    }

    /// Online learning of θ_online along a recording from θ_online(0) — the core's one online run,
    /// the "Online" pass of `pushlab eval` and what the app plays: `optimizer` "gd" (the paper's
    /// `steps` gradient-descent steps at learning rate `lr` per frame) or "gauss-newton"; θ is held
    /// over samples touching frames labelled bad tracking. With `after`, a run on another push of
    /// the same object, learning goes on from where that run ended (θ and its posterior), as
    /// `pushlab eval --carry-theta` does. With `start_com_shift` (x, y in metres, object frame), a
    /// run not going on from another starts believing the COM that far from θ_online(0)'s, the prior
    /// centred there, as `pushlab eval --start-com-shift` does.
    #[pyo3(signature = (recording, optimizer="gd", *, steps=5, lr=0.005, after=None, start_com_shift=None))]
    #[allow(clippy::too_many_arguments)]
    fn online(
        &self,
        py: Python<'_>,
        recording: &Recording,
        optimizer: &str,
        steps: usize,
        lr: f64,
        after: Option<&OnlineRun>,
        start_com_shift: Option<[f64; 2]>,
    ) -> PyResult<OnlineRun> {
        let config = online_config(optimizer, steps, lr)?;
        let from = start_of(recording, after, start_com_shift, false)?;
        let run = py
            .detach(|| {
                TrajectoryRun::learn_from(
                    &self.file.combined,
                    &recording.used,
                    0,
                    &config,
                    from.as_ref(),
                    start_com_shift,
                )
            })
            .map_err(|e| self.not_on(&recording.used, e))?;
        Ok(OnlineRun::new(run, recording.used.recording.clone(), false))
    }

    /// The physics-only model — the recording's outline and pusher, Lynch's model on the geometric
    /// contact, no network — learning θ_online online along `recording`, at this model's horizon
    /// with losses normalised by this model's offline σ: the "Physics online" pass of `pushlab eval
    /// --physics` (`contact_tolerance` in metres is its `--contact-tolerance`), to the bit. The
    /// arguments are `online`'s; `after` must be a physics-only run too.
    #[pyo3(signature = (recording, optimizer="gd", *, contact_tolerance=DEFAULT_CONTACT_TOLERANCE, steps=5, lr=0.005, after=None, start_com_shift=None))]
    #[allow(clippy::too_many_arguments)]
    fn physics_online(
        &self,
        py: Python<'_>,
        recording: &Recording,
        optimizer: &str,
        contact_tolerance: f64,
        steps: usize,
        lr: f64,
        after: Option<&OnlineRun>,
        start_com_shift: Option<[f64; 2]>,
    ) -> PyResult<OnlineRun> {
        let config = online_config(optimizer, steps, lr)?;
        let from = start_of(recording, after, start_com_shift, true)?;
        let used = &recording.used;
        let physics = self.physics_of(recording, contact_tolerance)?;
        let horizon = self.file.combined.horizon();
        let run = py.detach(|| {
            TrajectoryRun::learn_physics(
                physics,
                used,
                0,
                horizon,
                &config,
                from.as_ref(),
                start_com_shift,
            )
        });
        Ok(OnlineRun::new(run, used.recording.clone(), true))
    }

    /// The θ_online that fits the whole recording best, held fixed over it (a grid over the object,
    /// then Levenberg–Marquardt): what no online learner with this model beats on it, as `pushlab
    /// eval --best-fit` reports it, to the bit — a dict of `theta` (`com_offset`, `h`), `nmse`,
    /// `mean_loss`, `samples` and, when the setting knows the COM, `com_error_m`; None for a
    /// recording without samples. With `physics=True`, the physics-only model's (`contact_tolerance`
    /// as in `physics_online`).
    #[pyo3(signature = (recording, *, physics=false, contact_tolerance=DEFAULT_CONTACT_TOLERANCE))]
    fn best_fit<'py>(
        &self,
        py: Python<'py>,
        recording: &Recording,
        physics: bool,
        contact_tolerance: f64,
    ) -> PyResult<Option<Bound<'py, PyAny>>> {
        let used = &recording.used;
        let horizon = self.file.combined.horizon();
        let fit = if physics {
            let physics = self.physics_of(recording, contact_tolerance)?;
            py.detach(|| push_best_fit(&physics, used, horizon, &|| false))
        } else {
            let learner = model_on(&self.file.combined, used).map_err(|e| self.not_on(used, e))?;
            py.detach(|| push_best_fit(learner.as_ref(), used, horizon, &|| false))
        };
        BestFitReport::of(fit, used)
            .map(|report| to_python(py, &report))
            .transpose()
    }

    fn __repr__(&self) -> String {
        format!(
            "<pushlab.Model {} (horizon {}{})>",
            self.kind(),
            self.horizon(),
            if self.has_baseline() {
                ", with the pure-network baseline"
            } else {
                ""
            }
        )
    }
}

impl Model {
    /// Why this model cannot run on `used` (the contact kind without an outline), naming the file.
    fn not_on(&self, used: &UsedRecording, why: NoOutline) -> PyErr {
        error(format!("{}: {} model: {why}", used.source(), self.kind()))
    }

    /// The physics-only model of `recording`'s object with this model's loss scale, a bad
    /// `contact_tolerance` refused with the argument named.
    fn physics_of(
        &self,
        recording: &Recording,
        contact_tolerance: f64,
    ) -> PyResult<PhysicsOnlyModel> {
        if !(contact_tolerance.is_finite() && contact_tolerance > 0.0) {
            return Err(PyValueError::new_err(format!(
                "contact_tolerance: must be a finite number of metres above 0, got {contact_tolerance}"
            )));
        }
        let used = &recording.used;
        physics_model(
            &used.recording,
            self.file.combined.loss_scale(),
            contact_tolerance,
        )
        .map_err(|e| error(format!("{}: physics-only model: {e}", used.source())))
    }
}

/// The online update rule from Python's arguments, a bad one refused with the argument named.
pub(crate) fn online_config(optimizer: &str, steps: usize, lr: f64) -> PyResult<OnlineConfig> {
    let optimizer = Optimizer::from_name(optimizer).ok_or_else(|| {
        PyValueError::new_err(format!(
            "optimizer: expected \"gd\" or \"gauss-newton\", got {optimizer:?}"
        ))
    })?;
    if !(lr.is_finite() && lr > 0.0) {
        return Err(PyValueError::new_err(format!(
            "lr: must be a finite number above 0, got {lr}"
        )));
    }
    Ok(OnlineConfig {
        steps,
        lr,
        optimizer,
    })
}

/// Where a run on `recording` starts: from where `after` ended — a run of the same model
/// (`physics_only` or combined) on the same object — or from θ_online(0), moved by
/// `start_com_shift` when given (checked here, applied by the core).
fn start_of(
    recording: &Recording,
    after: Option<&OnlineRun>,
    start_com_shift: Option<[f64; 2]>,
    physics_only: bool,
) -> PyResult<Option<OnlineState>> {
    if let Some(shift) = start_com_shift {
        if after.is_some() {
            return Err(PyValueError::new_err(
                "start_com_shift: a run going on from `after` starts where that run ended",
            ));
        }
        if !shift.iter().all(|x| x.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "start_com_shift: expected two finite numbers (x, y in metres), got {shift:?}"
            )));
        }
    }
    let Some(after) = after else {
        return Ok(None);
    };
    let model = |physics_only| {
        if physics_only {
            "the physics-only model (model.physics_online)"
        } else {
            "the combined model (model.online)"
        }
    };
    if after.is_physics_only() != physics_only {
        return Err(PyValueError::new_err(format!(
            "after: a run of {}; this one is of {}, which goes on only from its own runs",
            model(after.is_physics_only()),
            model(physics_only)
        )));
    }
    if !after.recording().same_object_as(&recording.used.recording) {
        return Err(PyValueError::new_err(format!(
            "after: the run on {} pushes another object than {} (same folder, footprint, \
             material and pusher needed to go on from it)",
            after.recording().source.display(),
            recording.used.source()
        )));
    }
    Ok(Some(after.end_state()))
}

/// One prediction: how the object moves from `frame` to `frame + horizon`, in the object frame of
/// `frame` (translation of the geometric centre in metres, rotation in radians), with what was
/// observed and the normalised losses (eq. 6).
#[pyclass(module = "pushlab", name = "Prediction", frozen, get_all)]
pub struct Prediction {
    /// The frame predicted from.
    frame: usize,
    /// θ_online used, `[com_x, com_y, h]`.
    theta: [f64; 3],
    /// Predicted translation of the geometric centre, object frame, metres.
    translation: [f64; 2],
    /// Predicted rotation, radians.
    rotation: f64,
    /// The contact point (object frame, from the geometric centre), when the model has one.
    contact: Option<[f64; 2]>,
    /// The contact's motion, object frame, when the model has one.
    contact_motion: Option<[f64; 2]>,
    /// What the recording shows over the same frames.
    observed_translation: [f64; 2],
    observed_rotation: f64,
    /// The positional and rotational loss of this prediction (the terms NMSE averages).
    loss_pos: f64,
    loss_rot: f64,
}

#[pymethods]
impl Prediction {
    /// The prediction as a dict.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        d.set_item("frame", self.frame)?;
        d.set_item("theta", self.theta)?;
        d.set_item("translation", self.translation)?;
        d.set_item("rotation", self.rotation)?;
        d.set_item("contact", self.contact)?;
        d.set_item("contact_motion", self.contact_motion)?;
        d.set_item("observed_translation", self.observed_translation)?;
        d.set_item("observed_rotation", self.observed_rotation)?;
        d.set_item("loss_pos", self.loss_pos)?;
        d.set_item("loss_rot", self.loss_rot)?;
        Ok(d)
    }

    fn __repr__(&self) -> String {
        format!(
            "<pushlab.Prediction frame {}: translation ({:.5}, {:.5}) m, rotation {:.5} rad; observed ({:.5}, {:.5}) m, {:.5} rad>",
            self.frame,
            self.translation[0],
            self.translation[1],
            self.rotation,
            self.observed_translation[0],
            self.observed_translation[1],
            self.observed_rotation
        )
    }
}
