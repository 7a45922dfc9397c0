//! What the planner predicts a push with: one model at one θ, or the weighted prediction — the
//! combined model and physics alone, each at the θ it has learned, mixed by the weights the
//! weighting has found (`learn::Weights::blend`, the rule the weighted run is scored by). The
//! planner asks only for a push's motion, so it plans with either the same way.

use crate::learn::{OnlineRun, Weights};
use crate::model::{ObjectMotion, OnlineModel, OnlineParams, SampleInput};

/// A push's motion, predicted.
pub trait Predict {
    fn motion(&self, input: &SampleInput) -> ObjectMotion;
}

/// One model at one θ.
pub struct AtTheta<'a, M: ?Sized> {
    pub model: &'a M,
    pub theta: OnlineParams,
}

impl<M: OnlineModel + ?Sized> Predict for AtTheta<'_, M> {
    fn motion(&self, input: &SampleInput) -> ObjectMotion {
        self.model.predict(input, &self.theta).motion
    }
}

/// The weighted prediction of a run that learns with physics alone beside it.
pub struct Weighted<'a> {
    combined: AtTheta<'a, dyn OnlineModel + Send + Sync>,
    physics: AtTheta<'a, dyn OnlineModel + Send + Sync>,
    weights: Weights,
}

impl<'a> Weighted<'a> {
    /// `run`'s weighted prediction, both runs at the θ they have learned so far; `None` unless
    /// physics alone runs beside it.
    pub fn of(run: &'a OnlineRun) -> Option<Self> {
        let physics = run.physics_beside()?;
        let weights = run.model_weight()?.weight();
        Some(Self {
            combined: AtTheta {
                model: run.model().as_ref(),
                theta: run.theta_at(run.frontier()),
            },
            physics: AtTheta {
                model: physics.model().as_ref(),
                theta: physics.theta_at(physics.frontier()),
            },
            weights,
        })
    }

    pub fn weights(&self) -> Weights {
        self.weights
    }

    /// The combined model's θ and physics alone's, as predicted with.
    pub fn thetas(&self) -> [OnlineParams; 2] {
        [self.combined.theta, self.physics.theta]
    }
}

impl Predict for Weighted<'_> {
    fn motion(&self, input: &SampleInput) -> ObjectMotion {
        let combined = self.combined.motion(input);
        let physics = self.physics.motion(input);
        self.weights.blend(&combined, &physics)
    }
}
