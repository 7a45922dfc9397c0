//! `pushlab.Controller`: push to goal on poses from Python (a physics engine, a tracker). It is the
//! core's `control::PoseControl`, which `pushlab control --pipe` and a robot's drive run: poses go
//! onto live input's grid and are learned by its learner, and each step plans from the poses given
//! with θ as the run has it, so a script's targets are the CLI's to the bit.

use std::path::PathBuf;

use pushlab_core::control::track::TrackConfig;
use pushlab_core::control::{Goal, Pacing, PlanWith, PlannerConfig, PoseControl};
use pushlab_core::geometry::Pose2;
use pushlab_core::recording::Setting;
use pushlab_core::recording::bag::SettingSource;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::convert::{from_python, theta_row, to_python};
use crate::error::error;
use crate::model::{Model, online_config};

/// A controller pushing the setting's object to `goal` with `model`, planning with θ as `theta`
/// says: "online" (learned as it pushes, the default), "fixed" (θ_online(0)), "physics" (Lynch's
/// model alone, θ learned) or "truth" (the setting's com_offset and h). `rate` is control steps a
/// second (and the grid's rate), `speed` the pusher's top speed in m/s: no target is further from
/// the pusher than a step of it. `setting` is a setting.json's fields as a dict, or its path.
/// `track=(alpha, beta)` plans from poses filtered for tracking noise, as the CLI's `--track` does
/// (0.5, 0.1 was chosen on noisy poses; it costs goals on clean ones); off by default.
/// `optimizer`, `steps` and `lr` are how θ learns as it pushes (the CLI's `--optimizer`, `--steps`,
/// `--lr`); `lookahead=True` weighs the best pushes as the first of two (`--lookahead`: measured
/// and left off, see the guide); `planner_seed=K` draws the planner's samples from another stream
/// (`--planner-seed`).
#[pyclass(module = "pushlab", name = "Controller")]
pub struct Controller {
    control: PoseControl,
}

#[pymethods]
impl Controller {
    #[new]
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (model, setting, goal, *, theta="online", rate=10.0, speed=0.04, track=None, optimizer="gd", steps=5, lr=0.005, lookahead=false, planner_seed=0))]
    fn new(
        model: &Model,
        setting: &Bound<'_, PyAny>,
        goal: (f64, f64, f64),
        theta: &str,
        rate: f64,
        speed: f64,
        track: Option<(f64, f64)>,
        optimizer: &str,
        steps: usize,
        lr: f64,
        lookahead: bool,
        planner_seed: u64,
    ) -> PyResult<Self> {
        let online = online_config(optimizer, steps, lr)?;
        let setting: Setting = match setting.extract::<PathBuf>() {
            Ok(path) => SettingSource::File(path).resolve().map_err(error)?,
            Err(_) => from_python(setting, "setting")?,
        };
        let plan_with = PlanWith::from_name(theta).ok_or_else(|| {
            PyValueError::new_err(format!(
                "theta '{theta}': expected {}",
                PlanWith::expected()
            ))
        })?;
        for (name, value) in [("rate", rate), ("speed", speed)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(PyValueError::new_err(format!(
                    "{name} {value}: expected a positive number"
                )));
            }
        }
        let track = track
            .map(|(alpha, beta)| {
                TrackConfig::new(alpha, beta)
                    .map_err(|e| PyValueError::new_err(format!("track ({alpha}, {beta}): {e}")))
            })
            .transpose()?;
        let (x, y, yaw) = goal;
        let control = PoseControl::new(
            &model.file().combined,
            &setting,
            plan_with,
            online,
            Goal::at(Pose2::new(x, y, yaw)),
            PlannerConfig {
                track,
                lookahead,
                ..PlannerConfig::default()
            }
            .drawing_from(0, planner_seed),
            Pacing {
                pusher_speed: speed,
                control_hz: rate,
                grid_hz: rate,
            },
        )
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(Self { control })
    }

    /// One control step on the poses at time `t` (seconds): the pusher's `(x, y)` and the
    /// object's `(x, y, yaw)`. The step as `pushlab control --pipe` prints it: `target` (where the
    /// pusher should be next), `phase`, `theta`, the goal's `position_error_m` and
    /// `yaw_error_rad`, …
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        t: f64,
        pusher: (f64, f64),
        object: (f64, f64, f64),
    ) -> PyResult<Bound<'py, PyAny>> {
        let (x, y, yaw) = object;
        let step = self.control.step(
            t,
            nalgebra::Point2::new(pusher.0, pusher.1),
            Pose2::new(x, y, yaw),
        );
        to_python(py, &step)
    }

    /// Whether the goal is reached and held (half a second of steps within 10 mm and 3°).
    #[getter]
    fn done(&self) -> bool {
        self.control.is_done()
    }

    /// θ as learned so far, `[com_x, com_y, h]` in metres.
    #[getter]
    fn theta(&self) -> [f64; 3] {
        let run = self.control.learner().run();
        theta_row(&run.theta_at(run.frontier()))
    }
}
