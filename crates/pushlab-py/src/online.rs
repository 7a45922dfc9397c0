//! `pushlab.OnlineRun`: one online-learning run along a recording (the core's `TrajectoryRun`, what
//! `pushlab eval` reports per trajectory as `online`), as arrays.

use numpy::{PyArray1, PyArray2};
use pushlab_core::experiment::TrajectoryRun;
use pushlab_core::learn::{ModelWeight, Nmse, OnlineState, WeightConfig};
use pushlab_core::recording::Recording;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::convert::{column, rows, theta_row, to_python};

/// Online learning of θ_online along one recording, from θ_online(0). Frames are the recording's;
/// samples are the frames with a frame `horizon` later (the first N − horizon).
#[pyclass(module = "pushlab", name = "OnlineRun", frozen)]
pub struct OnlineRun {
    run: TrajectoryRun,
    frames: usize,
    /// The recording learned along (shared data), to check that a run going on from this one
    /// pushes the same object.
    recording: Recording,
    /// Made by the physics-only model (`model.physics_online`) rather than the combined model: a
    /// run goes on only from a run of the same model.
    physics_only: bool,
}

impl OnlineRun {
    pub(crate) fn new(run: TrajectoryRun, recording: Recording, physics_only: bool) -> Self {
        Self {
            run,
            frames: recording.trajectory.len(),
            recording,
            physics_only,
        }
    }

    pub(crate) fn recording(&self) -> &Recording {
        &self.recording
    }

    pub(crate) fn is_physics_only(&self) -> bool {
        self.physics_only
    }

    /// θ and the posterior where the run ended: what a run on the next push goes on from.
    pub(crate) fn end_state(&self) -> OnlineState {
        self.run.run.end_state()
    }
}

/// `{"pos": …, "rot": …}`.
fn nmse_dict(py: Python<'_>, nmse: Nmse) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("pos", nmse.pos)?;
    d.set_item("rot", nmse.rot)?;
    Ok(d)
}

#[pymethods]
impl OnlineRun {
    /// θ_online in effect at each frame, `[com_x, com_y, h]` in metres, shape (N, 3): row k is what
    /// the prediction from frame k was made with (the last learned θ past the last sample).
    #[getter]
    fn theta<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let theta: Vec<[f64; 3]> = (0..self.frames)
            .map(|k| theta_row(&self.run.run.theta_at(k)))
            .collect();
        rows(py, &theta)
    }

    /// The posterior's standard deviation of `[com_x, com_y, h]` at each frame, metres, shape (N, 3)
    /// (what the app draws as the ±2σ bands).
    #[getter]
    fn std<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let std: Vec<[f64; 3]> = (0..self.frames)
            .map(|k| self.run.run.spread_at(k).std())
            .collect();
        rows(py, &std)
    }

    /// The online loss at each sample, `[pos, rot]`, shape (N − horizon, 2); NaN where θ was held
    /// (a sample touching a frame labelled bad tracking).
    #[getter]
    fn losses<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let run = &self.run.run;
        let losses: Vec<[f64; 2]> = (0..run.sample_count())
            .map(|k| match run.learned().get(k).copied().flatten() {
                Some(l) => [l.pos, l.rot],
                None => [f64::NAN, f64::NAN],
            })
            .collect();
        rows(py, &losses)
    }

    /// The fixed model's loss (θ = θ_online(0) throughout) at each sample, shape (N − horizon, 2).
    #[getter]
    fn fixed_losses<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let losses: Vec<[f64; 2]> = self
            .run
            .run
            .fixed()
            .iter()
            .map(|l| [l.pos, l.rot])
            .collect();
        rows(py, &losses)
    }

    /// The frames learned from, in order.
    #[getter]
    fn learned_frames<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<usize>> {
        column(py, self.run.frames().collect())
    }

    /// NMSE of the online losses over the frames learned from, `{"pos": …, "rot": …}`: the
    /// trajectory's `online` in `pushlab eval --json`.
    #[getter]
    fn nmse<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        nmse_dict(py, self.run.online_nmse())
    }

    /// This run (the combined model's) and `physics` (the physics-only run on the same recording,
    /// `model.physics_online`) weighed online, as `pushlab eval --physics` weighs them
    /// (`learn::ModelWeight`; `half_life` in seconds, `prior` the combined model's weight before any
    /// frame): a dict of `nmse` (the physics trajectory's `weighted` in `pushlab eval --json`),
    /// `weights` (rows `[frame, translation, rotation]`, the combined model's weights each learned
    /// frame was predicted with) and `weight_end` (`[translation, rotation]` after the last).
    /// Weights carried from push to push (`eval --carry-theta`) are not offered here.
    #[pyo3(signature = (physics, *, half_life=WeightConfig::default().half_life_s, prior=WeightConfig::default().prior))]
    fn weighed_with<'py>(
        &self,
        py: Python<'py>,
        physics: &OnlineRun,
        half_life: f64,
        prior: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        if self.physics_only || !physics.physics_only {
            return Err(pyo3::exceptions::PyValueError::new_err(
                "weighed_with: call it on a combined model's run (model.online) with a physics-only \
                 run (model.physics_online)",
            ));
        }
        if physics.recording.source != self.recording.source {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "weighed_with: the physics-only run is on {}, this run on {}",
                physics.recording.source.display(),
                self.recording.source.display()
            )));
        }
        if !(half_life.is_finite() && half_life > 0.0 && (0.0..=1.0).contains(&prior)) {
            return Err(pyo3::exceptions::PyValueError::new_err(
                "weighed_with: half_life must be above 0 seconds and prior from 0 to 1",
            ));
        }
        let mut weight = ModelWeight::new(WeightConfig {
            half_life_s: half_life,
            prior,
        });
        self.run.run.weigh_against(&physics.run.run, &mut weight);
        let d = PyDict::new(py);
        let nmse = Nmse::of_frames(weight.frames().iter().map(|f| f.loss));
        d.set_item("nmse", nmse_dict(py, nmse)?)?;
        let weights: Vec<[f64; 3]> = (weight.frames().iter())
            .map(|f| [f.frame as f64, f.weight.pos, f.weight.rot])
            .collect();
        d.set_item("weights", rows(py, &weights)?)?;
        let end = weight.weight();
        d.set_item("weight_end", [end.pos, end.rot])?;
        Ok(d)
    }

    /// NMSE of the fixed model over the same frames: the trajectory's `fixed` in `pushlab eval --json`.
    #[getter]
    fn fixed_nmse<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        nmse_dict(py, self.run.fixed_nmse())
    }

    /// θ_online(0), `[com_x, com_y, h]`.
    #[getter]
    fn theta0<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        column(py, theta_row(&self.run.theta0()).to_vec())
    }

    /// θ_online after the last online step, `[com_x, com_y, h]`.
    #[getter]
    fn theta_end<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        column(py, theta_row(&self.run.theta_end()).to_vec())
    }

    /// The posterior covariance of the learned COM offset at the end (2 × 2, m², object frame).
    #[getter]
    fn com_offset_cov<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        rows(py, &self.run.posterior_end().com_covariance())
    }

    /// The posterior standard deviation of the learned h at the end, metres.
    #[getter]
    fn h_std(&self) -> f64 {
        self.run.posterior_end().std()[2]
    }

    /// What the learned COM's σ at the end is made of, metres: {"frames_m", "misfit_m", "drift_m"}
    /// (what the frames say, the model's COM misfit, the estimate's path drift; they add in squares).
    #[getter]
    fn com_sigma_parts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.run.posterior_end().com_spread_parts())
    }

    /// With a known COM (simulated sets): the final error, whether the 95 % ellipse holds it, and the
    /// frames it took to settle, as a dict; else None.
    #[getter]
    fn com_found<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.run
            .com_truth
            .as_ref()
            .map(|c| to_python(py, c))
            .transpose()
    }

    /// Whether learning went on from another run (`model.online(…, after=run)`) rather than from
    /// θ_online(0); `theta[0]` is then where that run ended.
    #[getter]
    fn continued(&self) -> bool {
        self.run.continued
    }

    /// Samples learned from.
    #[getter]
    fn steps(&self) -> usize {
        self.run.steps()
    }

    /// Whether the physics-only model made this run (`model.physics_online`), not the combined
    /// model (`model.online`).
    #[getter]
    fn physics_only(&self) -> bool {
        self.physics_only
    }

    fn __repr__(&self) -> String {
        let n = self.run.online_nmse();
        let t = self.run.theta_end();
        format!(
            "<pushlab.OnlineRun{} {} steps, NMSE pos {:.4} rot {:.4}; COM offset ({:.4}, {:.4}) m, h {:.4} m>",
            if self.physics_only {
                " (physics-only)"
            } else {
                ""
            },
            self.run.steps(),
            n.pos,
            n.rot,
            t.com_offset[0],
            t.com_offset[1],
            t.h
        )
    }
}
