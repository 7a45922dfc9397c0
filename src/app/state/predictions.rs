//! Every prediction shown for the frame on screen, produced by the state so that the scene and the
//! inspector only draw numbers: the online-learned and fixed combined model (with their losses and
//! gradients), the physics-only model with the same `θ`, and the pure-network baseline.
//!
//! The models behind them are built once per run (`AppState::start_run`); what is computed here per
//! drawn frame is four predictions of one sample, a few microseconds.

use pushlab_core::learn::OnlineStep;
use pushlab_core::model::{Prediction, Sample};

use super::AppState;

/// The predictions at one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FramePredictions {
    /// The frame predicted from.
    pub frame: usize,
    /// Its sample: the model's inputs and the measured motion to the target frame.
    pub sample: Sample,
    /// The combined model with `θ_online` at this frame: prediction, loss, gradient.
    pub online: OnlineStep,
    /// The combined model with `θ_online(0)`, never updated.
    pub fixed: OnlineStep,
    /// The physics-only model with `θ_online` at this frame.
    pub physics: Option<Prediction>,
    /// The pure-network baseline, when the model file has one.
    pub pure_nn: Option<Prediction>,
}

impl AppState {
    /// The predictions at the frame shown; `None` without a run, or within the prediction horizon
    /// of the end (no sample there).
    pub fn predictions(&self) -> Option<FramePredictions> {
        let run = self.run.as_ref()?;
        let frame = self.frame();
        let sample = run.sample(frame)?;
        let theta = run.theta_at(frame);
        Some(FramePredictions {
            frame,
            sample,
            online: run.evaluate(frame)?,
            fixed: run.evaluate_fixed(frame)?,
            physics: self
                .physics
                .as_ref()
                .map(|model| model.predict(&sample.input, &theta)),
            pure_nn: self
                .models
                .pure_nn
                .as_ref()
                .map(|model| model.predict(&sample.input)),
        })
    }

    /// The online model's prediction, loss and gradient at the frame shown, with θ at that frame.
    pub fn current_step(&self) -> Option<OnlineStep> {
        self.run.as_ref()?.evaluate(self.frame())
    }
}
