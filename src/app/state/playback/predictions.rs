//! Every prediction shown for the frame on screen, produced by the state so that the scene and the
//! inspector only draw numbers: the online-learned and fixed combined model (with their losses and
//! gradients), the physics-only model with the same `θ`, and the pure-network baseline.
//!
//! The models behind them are built once per run (`AppState::start_run`); what is computed here per
//! drawn frame is four predictions of one sample, a few microseconds.

use pushlab_core::model::{OnlineStep, Prediction, Sample};

use crate::app::state::AppState;

/// A layer of predictions in the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PredictionLayer {
    Online,
    Fixed,
    PureNn,
    Physics,
}

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
    /// The physics-only model with its own θ at this frame when it learns beside the run, else
    /// with `θ_online`.
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
            // With physics alone learning its own θ beside the run, its θ; else the run's.
            physics: self.physics.as_ref().map(|model| {
                let own = run.physics_beside().map(|p| p.theta_at(frame));
                model.predict(&sample.input, &own.unwrap_or(theta))
            }),
            pure_nn: self
                .models
                .pure_nn
                .as_ref()
                .map(|model| model.predict(&sample.input)),
        })
    }

    /// Why a prediction layer draws nothing, or draws a model trained on other data; `None` when it
    /// comes from a model that fits the open recordings. The legend shows it beside the layer.
    pub fn layer_note(&self, layer: PredictionLayer) -> Option<String> {
        let other_data = self
            .domain_mismatch()
            .map(|_| "from a model trained on other data (see Steer)".to_owned());
        match layer {
            PredictionLayer::Online | PredictionLayer::Fixed if self.run.is_none() => {
                Some("no model runs on this recording (see the status line)".to_owned())
            }
            PredictionLayer::Online | PredictionLayer::Fixed => other_data,
            PredictionLayer::PureNn if self.models.pure_nn.is_none() => Some(
                "the model in use has no pure-NN baseline; Train for these recordings trains one"
                    .to_owned(),
            ),
            PredictionLayer::PureNn => other_data,
            PredictionLayer::Physics if self.physics.is_none() => {
                Some("no physics model: the object's outline is unusable".to_owned())
            }
            PredictionLayer::Physics => None,
        }
    }

    /// The online model's prediction, loss and gradient at the frame shown, with θ at that frame.
    pub fn current_step(&self) -> Option<OnlineStep> {
        self.run.as_ref()?.evaluate(self.frame())
    }
}
