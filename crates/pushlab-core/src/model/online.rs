//! What online learning needs of a model: `θ_online(0)`, the scales of its components, predictions
//! with any `θ_online`, and one online step of eq. 13 — the model's own gradient descent on
//! `θ_online` only, with the gradient taken through the whole model — as a pure function.
//!
//! Every model kind runs the same descent (`kernel::descend`): one rule for the step sizes, the range
//! of `h` and non-finite steps. How steps chain along a recording, the posterior and Gauss–Newton are
//! `learn`'s, one layer up.

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::loss::{Loss, LossScale};
use super::{
    ComMisfit, ContactGeometry, ContactModel, Linearization, OnlineParams, PaperModel,
    PhysicalBounds, PhysicsOnlyModel, Prediction, RealSample, Sample, SampleInput,
};
use crate::real::Real;

/// The gradient-descent part of an online step (eq. 13): `steps` steps on `θ_online / s` with
/// learning rate `lr` (the paper: 5 at 0.005). No steps predicts without learning.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Descent {
    pub steps: usize,
    pub lr: f64,
}

impl Descent {
    /// Predict and differentiate, never update: the "fixed" model.
    pub const NONE: Descent = Descent { steps: 0, lr: 0.0 };
}

/// A model bound to an object, shared across threads (the app's UI and its workers, a suite's jobs).
pub type SharedOnlineModel = Arc<dyn OnlineModel + Send + Sync>;

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
    /// and `θ_online` after `descent.steps` gradient-descent steps on `θ_online / s` with learning rate
    /// `descent.lr`, keeping `h` in range. A pure function: nothing is changed, the caller decides
    /// whether to take `theta_after` (as `learn`'s online run does).
    fn online_step(&self, sample: &Sample, theta: &OnlineParams, descent: &Descent) -> OnlineStep;
    /// The sample's residual normalised by the loss's σ and its Jacobian with respect to
    /// `θ_online` at `theta`: what Gauss–Newton and the posterior of `θ_online` are built from.
    fn linearize(&self, sample: &Sample, theta: &OnlineParams) -> Linearization;
    /// [`OnlineModel::linearize`] and [`OnlineModel::online_step`] from the same `theta`: what
    /// gradient descent with the posterior kept beside it needs each frame (`learn::learn_step`). The
    /// same numbers as the two calls; a model may share their common work (the contact model
    /// prepares the sample and runs the forward pass at `theta` once).
    fn linearize_and_step(
        &self,
        sample: &Sample,
        theta: &OnlineParams,
        descent: &Descent,
    ) -> (Linearization, OnlineStep) {
        (
            self.linearize(sample, theta),
            self.online_step(sample, theta, descent),
        )
    }
    /// Where `θ_online` can physically be on the object, when the model knows its outline: online
    /// learning keeps every step inside (`learn::step`).
    fn bounds(&self) -> Option<&PhysicalBounds> {
        None
    }
    /// How far its learned COM lands from the truth on objects it did not train on, measured at
    /// training: the posterior adds it to the COM's spread (none for a model not calibrated).
    fn com_misfit(&self) -> ComMisfit {
        ComMisfit::default()
    }
    /// `theta` kept inside [`OnlineModel::bounds`] (only [`OnlineParams::clamped`] for a model
    /// without an outline): what every update and every steering of `θ_online` goes through.
    fn keep_physical(&self, theta: OnlineParams) -> OnlineParams {
        match self.bounds() {
            Some(bounds) => bounds.keep(theta),
            None => theta.clamped(),
        }
    }
    /// The prediction for a sample, its loss, and the gradient of the loss with respect to
    /// `θ_online` (`[com_x, com_y, h]`, per metre).
    fn loss_and_gradient(
        &self,
        sample: &Sample,
        theta: &OnlineParams,
    ) -> (Prediction, Loss, [f64; 3]) {
        let step = self.evaluate(sample, theta);
        (step.prediction, step.loss, step.gradient)
    }
    /// The prediction with `theta`, its loss and gradient, without learning (`θ_online` after it is
    /// `theta` clamped into range): the "fixed" model, and what a UI shows at a frame.
    fn evaluate(&self, sample: &Sample, theta: &OnlineParams) -> OnlineStep {
        self.online_step(sample, theta, &Descent::NONE)
    }
    /// [`OnlineModel::evaluate`]'s loss alone, the same bits, at the cost of a prediction: no
    /// gradient. What a pass that keeps only losses takes (the fixed run of every recording
    /// opened: a third of the time of selecting a million-frame recording was its gradients).
    fn loss_at(&self, sample: &Sample, theta: &OnlineParams) -> Loss {
        let prediction = self.predict(&sample.input, &theta.clamped());
        Loss::of(&prediction.motion, &sample.target, &self.loss_scale())
    }
}

impl<T: Real> OnlineModel for PaperModel<T> {
    fn theta0(&self) -> OnlineParams {
        PaperModel::theta0(self)
    }

    fn com_misfit(&self) -> ComMisfit {
        PaperModel::com_misfit(self)
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
    fn online_step(&self, sample: &Sample, theta: &OnlineParams, descent: &Descent) -> OnlineStep {
        let theta_before = theta.clamped();
        let real = RealSample::<T>::of(sample);
        let result = self.online_update(&real, &theta_before, descent.steps, descent.lr);
        OnlineStep::of(sample, theta_before, result, &self.loss_scale)
    }

    fn linearize(&self, sample: &Sample, theta: &OnlineParams) -> Linearization {
        PaperModel::linearize(self, &RealSample::<T>::of(sample), &theta.clamped())
    }
}

/// The contact-frame model bound to one object: its geometry decides the contact frame,
/// `θ_online(0)` and the step scales. The contact model itself is shared by every object it is bound
/// to.
#[derive(Clone, Debug)]
pub struct ContactModelOnObject {
    model: Arc<ContactModel>,
    geometry: Arc<ContactGeometry>,
}

impl ContactModelOnObject {
    /// The model on an object of this geometry.
    pub fn new(model: Arc<ContactModel>, geometry: Arc<ContactGeometry>) -> Self {
        Self { model, geometry }
    }
}

impl OnlineModel for ContactModelOnObject {
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

    fn online_step(&self, sample: &Sample, theta: &OnlineParams, descent: &Descent) -> OnlineStep {
        let theta_before = theta.clamped();
        let result = self.model.online_update(
            &self.geometry,
            sample,
            &theta_before,
            descent.steps,
            descent.lr,
        );
        OnlineStep::of(sample, theta_before, result, &self.model.loss_scale())
    }

    fn linearize(&self, sample: &Sample, theta: &OnlineParams) -> Linearization {
        self.model
            .linearize(&self.geometry, sample, &theta.clamped())
    }

    fn linearize_and_step(
        &self,
        sample: &Sample,
        theta: &OnlineParams,
        descent: &Descent,
    ) -> (Linearization, OnlineStep) {
        let theta_before = theta.clamped();
        let (linearization, result) = self.model.linearize_and_update(
            &self.geometry,
            sample,
            &theta_before,
            descent.steps,
            descent.lr,
        );
        let step = OnlineStep::of(sample, theta_before, result, &self.model.loss_scale());
        (linearization, step)
    }

    fn bounds(&self) -> Option<&PhysicalBounds> {
        Some(self.geometry.bounds())
    }

    fn com_misfit(&self) -> ComMisfit {
        self.model.com_misfit()
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

    fn online_step(&self, sample: &Sample, theta: &OnlineParams, descent: &Descent) -> OnlineStep {
        let theta_before = theta.clamped();
        let result = self.online_update(sample, &theta_before, descent.steps, descent.lr);
        OnlineStep::of(sample, theta_before, result, &self.loss_scale())
    }

    fn linearize(&self, sample: &Sample, theta: &OnlineParams) -> Linearization {
        PhysicsOnlyModel::linearize(self, sample, &theta.clamped())
    }

    fn bounds(&self) -> Option<&PhysicalBounds> {
        Some(PhysicsOnlyModel::bounds(self))
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
            fn online_step(&self, sample: &Sample, theta: &OnlineParams, descent: &Descent) -> OnlineStep {
                (**self).online_step(sample, theta, descent)
            }
            fn evaluate(&self, sample: &Sample, theta: &OnlineParams) -> OnlineStep {
                (**self).evaluate(sample, theta)
            }
            fn loss_at(&self, sample: &Sample, theta: &OnlineParams) -> Loss {
                (**self).loss_at(sample, theta)
            }
            fn linearize(&self, sample: &Sample, theta: &OnlineParams) -> Linearization {
                (**self).linearize(sample, theta)
            }
            fn linearize_and_step(&self, sample: &Sample, theta: &OnlineParams, descent: &Descent) -> (Linearization, OnlineStep) {
                (**self).linearize_and_step(sample, theta, descent)
            }
            fn bounds(&self) -> Option<&PhysicalBounds> { (**self).bounds() }
            fn com_misfit(&self) -> ComMisfit { (**self).com_misfit() }
        }
    )*};
}
forward_online_model!(&M, Arc<M>, Box<M>);
