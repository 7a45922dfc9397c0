//! Online learning of `θ_online` (eq. 13, Algorithm 1): at each step, predict with `θ_online(t)` and
//! record the loss; then observe the outcome and take a few gradient-descent steps on `θ_online` only,
//! with the gradient taken through the whole model.
//!
//! Every model kind runs the same descent (`model::kernel::descend`): one rule for the step sizes, the
//! range of `h` and non-finite steps.

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::loss::{Loss, LossScale};
use super::uncertainty::{OnlineState, Optimizer, Posterior, learn_step};
use crate::model::{
    ContactGeometry, ContactModel, Linearization, OnlineParams, PaperModel, PhysicsOnlyModel,
    Prediction, RealSample, Sample, SampleInput,
};
use crate::real::Real;

/// How online learning updates `θ_online` after each observed step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct OnlineConfig {
    /// Gradient-descent steps per observed step (the paper: 5). Zero gives the "fixed" model.
    pub steps: usize,
    /// Learning rate on `θ_online` divided component-wise by the model's scales (the paper: 0.005).
    pub lr: f64,
    /// Gradient descent (the paper's) or Gauss–Newton (`learn::uncertainty`).
    #[serde(default)]
    pub optimizer: Optimizer,
}

impl Default for OnlineConfig {
    fn default() -> Self {
        Self {
            steps: 5,
            lr: 0.005,
            optimizer: Optimizer::Gd,
        }
    }
}

impl OnlineConfig {
    /// The "fixed" model of the paper's figures: predicts, never updates.
    pub fn fixed() -> Self {
        Self {
            steps: 0,
            lr: 0.0,
            optimizer: Optimizer::Gd,
        }
    }
}

/// Everything one online step did, so that a UI can show it and rewind to it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct OnlineStep {
    /// `θ_online(t)`: the parameters the prediction was made with.
    pub theta_before: OnlineParams,
    /// The prediction made with `theta_before`, before the outcome was observed.
    pub prediction: Prediction,
    /// Its loss against the observed outcome.
    pub loss: Loss,
    /// `∂ℓ/∂(com_x, com_y, h)` at `theta_before`, per metre.
    pub gradient: [f64; 3],
    /// `θ_online(t+1)`: the parameters after learning from this step.
    pub theta_after: OnlineParams,
}

impl OnlineStep {
    fn of(
        sample: &Sample,
        theta_before: OnlineParams,
        (prediction, gradient, theta_after): (Prediction, [f64; 3], OnlineParams),
        scale: &LossScale,
    ) -> Self {
        Self {
            theta_before,
            prediction,
            loss: Loss::of(&prediction.motion, &sample.target, scale),
            gradient,
            theta_after,
        }
    }
}

/// A model whose `θ_online` can be learned online, on one object.
pub trait OnlineModel {
    /// Where online learning starts.
    fn theta0(&self) -> OnlineParams;
    /// The scales `s` of `θ_online`'s components for gradient descent, metres.
    fn theta_scales(&self) -> [f64; 3];
    /// The σ that normalise the losses.
    fn loss_scale(&self) -> LossScale;
    /// Frames between a sample's input and its target (1 for models that take any).
    fn horizon(&self) -> usize {
        1
    }
    /// Predicts with the given `θ_online`.
    fn predict(&self, input: &SampleInput, theta: &OnlineParams) -> Prediction;
    /// What one online step from `theta` gives: the prediction with `theta`, its loss and gradient,
    /// and `θ_online` after `config.steps` gradient-descent steps on `θ_online / s` with learning rate
    /// `config.lr`, keeping `h` in range. A pure function: nothing is changed, the caller decides
    /// whether to take `theta_after` (as [`OnlineLearner::step`] does).
    fn online_step(
        &self,
        sample: &Sample,
        theta: &OnlineParams,
        config: &OnlineConfig,
    ) -> OnlineStep;
    /// The sample's residual normalised by the loss's σ and its Jacobian with respect to
    /// `θ_online` at `theta`: what Gauss–Newton and the posterior of `θ_online` are built from.
    fn linearize(&self, sample: &Sample, theta: &OnlineParams) -> Linearization;
    /// The prediction for a sample, its loss, and the gradient of the loss with respect to
    /// `θ_online` (`[com_x, com_y, h]`, per metre).
    fn loss_and_gradient(
        &self,
        sample: &Sample,
        theta: &OnlineParams,
    ) -> (Prediction, Loss, [f64; 3]) {
        let step = self.online_step(sample, theta, &OnlineConfig::fixed());
        (step.prediction, step.loss, step.gradient)
    }
}

impl<T: Real> OnlineModel for PaperModel<T> {
    fn theta0(&self) -> OnlineParams {
        PaperModel::theta0(self)
    }

    fn horizon(&self) -> usize {
        PaperModel::horizon(self)
    }

    fn theta_scales(&self) -> [f64; 3] {
        PaperModel::theta_scales(self)
    }

    fn loss_scale(&self) -> LossScale {
        PaperModel::loss_scale(self)
    }

    fn predict(&self, input: &SampleInput, theta: &OnlineParams) -> Prediction {
        PaperModel::predict(self, input, theta)
    }

    /// The fast path: the whole update runs in the model's float type without allocating.
    fn online_step(
        &self,
        sample: &Sample,
        theta: &OnlineParams,
        config: &OnlineConfig,
    ) -> OnlineStep {
        let theta_before = theta.clamped();
        let real = RealSample::<T>::of(sample);
        let result = self.online_update(&real, &theta_before, config.steps, config.lr);
        OnlineStep::of(sample, theta_before, result, &self.loss_scale)
    }

    fn linearize(&self, sample: &Sample, theta: &OnlineParams) -> Linearization {
        PaperModel::linearize(self, &RealSample::<T>::of(sample), &theta.clamped())
    }
}

/// The contact-frame model on one object: its geometry decides the contact frame, `θ_online(0)` and
/// the step scales.
#[derive(Clone, Debug)]
pub struct ContactLearner {
    model: Arc<ContactModel>,
    geometry: Arc<ContactGeometry>,
}

impl ContactLearner {
    /// The model on an object of this geometry.
    pub fn new(model: Arc<ContactModel>, geometry: Arc<ContactGeometry>) -> Self {
        Self { model, geometry }
    }
}

impl OnlineModel for ContactLearner {
    fn theta0(&self) -> OnlineParams {
        self.model.theta0(&self.geometry)
    }

    fn horizon(&self) -> usize {
        self.model.horizon()
    }

    fn theta_scales(&self) -> [f64; 3] {
        self.model.theta_scales(&self.geometry)
    }

    fn loss_scale(&self) -> LossScale {
        self.model.loss_scale()
    }

    fn predict(&self, input: &SampleInput, theta: &OnlineParams) -> Prediction {
        self.model.predict(&self.geometry, input, theta)
    }

    fn online_step(
        &self,
        sample: &Sample,
        theta: &OnlineParams,
        config: &OnlineConfig,
    ) -> OnlineStep {
        let theta_before = theta.clamped();
        let result = self.model.online_update(
            &self.geometry,
            sample,
            &theta_before,
            config.steps,
            config.lr,
        );
        OnlineStep::of(sample, theta_before, result, &self.model.loss_scale())
    }

    fn linearize(&self, sample: &Sample, theta: &OnlineParams) -> Linearization {
        self.model
            .linearize(&self.geometry, sample, &theta.clamped())
    }
}

/// The physics-only model learns `θ_online` too; each component is scaled by half the object's size.
impl OnlineModel for PhysicsOnlyModel {
    fn theta0(&self) -> OnlineParams {
        PhysicsOnlyModel::theta0(self)
    }

    fn theta_scales(&self) -> [f64; 3] {
        PhysicsOnlyModel::theta_scales(self)
    }

    fn loss_scale(&self) -> LossScale {
        PhysicsOnlyModel::loss_scale(self)
    }

    fn predict(&self, input: &SampleInput, theta: &OnlineParams) -> Prediction {
        PhysicsOnlyModel::predict(self, input, theta)
    }

    fn online_step(
        &self,
        sample: &Sample,
        theta: &OnlineParams,
        config: &OnlineConfig,
    ) -> OnlineStep {
        let theta_before = theta.clamped();
        let result = self.online_update(sample, &theta_before, config.steps, config.lr);
        OnlineStep::of(sample, theta_before, result, &self.loss_scale())
    }

    fn linearize(&self, sample: &Sample, theta: &OnlineParams) -> Linearization {
        PhysicsOnlyModel::linearize(self, sample, &theta.clamped())
    }
}

macro_rules! forward_online_model {
    ($($wrapper:ty),*) => {$(
        impl<M: OnlineModel + ?Sized> OnlineModel for $wrapper {
            fn theta0(&self) -> OnlineParams { (**self).theta0() }
            fn horizon(&self) -> usize { (**self).horizon() }
            fn theta_scales(&self) -> [f64; 3] { (**self).theta_scales() }
            fn loss_scale(&self) -> LossScale { (**self).loss_scale() }
            fn predict(&self, input: &SampleInput, theta: &OnlineParams) -> Prediction {
                (**self).predict(input, theta)
            }
            fn loss_and_gradient(&self, sample: &Sample, theta: &OnlineParams) -> (Prediction, Loss, [f64; 3]) {
                (**self).loss_and_gradient(sample, theta)
            }
            fn online_step(&self, sample: &Sample, theta: &OnlineParams, config: &OnlineConfig) -> OnlineStep {
                (**self).online_step(sample, theta, config)
            }
            fn linearize(&self, sample: &Sample, theta: &OnlineParams) -> Linearization {
                (**self).linearize(sample, theta)
            }
        }
    )*};
}
forward_online_model!(&M, Arc<M>, Box<M>);

/// Learns `θ_online` along a stream of samples (Algorithm 1), with the configured optimiser.
///
/// Holds only the current `θ_online` and its posterior: a caller that wants to rewind keeps the
/// returned [`OnlineStep`]s (each has `theta_before`) and calls [`OnlineLearner::set_theta`].
#[derive(Clone, Debug)]
pub struct OnlineLearner<M> {
    model: M,
    config: OnlineConfig,
    state: OnlineState,
}

impl<M: OnlineModel> OnlineLearner<M> {
    /// A learner starting at the model's `θ_online(0)` and the prior.
    pub fn new(model: M, config: OnlineConfig) -> Self {
        let state = OnlineState::start(&model);
        Self {
            model,
            config,
            state,
        }
    }

    /// The model it learns for.
    pub fn model(&self) -> &M {
        &self.model
    }

    /// The current `θ_online(t)`.
    pub fn theta(&self) -> OnlineParams {
        self.state.theta
    }

    /// What the frames learned so far say about `θ_online`.
    pub fn posterior(&self) -> Posterior {
        self.state.posterior
    }

    /// Sets `θ_online` (a user's slider, a rewind to a checkpoint); `h` is clamped into range. The
    /// posterior is kept.
    pub fn set_theta(&mut self, theta: OnlineParams) {
        self.state = OnlineState::at(theta, self.state.posterior);
    }

    /// Back to `θ_online(0)` and the prior, as at the start of each trajectory when resetting per
    /// trajectory.
    pub fn reset(&mut self) {
        self.state = OnlineState::start(&self.model);
    }

    /// The update rule.
    pub fn config(&self) -> OnlineConfig {
        self.config
    }

    /// Changes the update rule (steps, learning rate, optimiser) from the next step on.
    pub fn set_config(&mut self, config: OnlineConfig) {
        self.config = config;
    }

    /// Predicts for `sample` with `θ_online(t)`, records the loss, then learns from its outcome.
    pub fn step(&mut self, sample: &Sample) -> OnlineStep {
        let (step, next) = learn_step(&self.model, sample, &self.state, &self.config);
        self.state = next;
        step
    }

    /// Predicts and scores `sample` with `θ_online(t)` without learning (the "fixed" run).
    pub fn evaluate(&self, sample: &Sample) -> OnlineStep {
        self.model
            .online_step(sample, &self.state.theta, &OnlineConfig::fixed())
    }

    /// Runs [`OnlineLearner::step`] over a trajectory's samples.
    pub fn run(&mut self, samples: &[Sample]) -> Vec<OnlineStep> {
        samples.iter().map(|s| self.step(s)).collect()
    }
}
