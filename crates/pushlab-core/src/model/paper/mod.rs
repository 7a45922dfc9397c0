//! The paper's combined model (Fig. 4), kept exactly so that the paper's tables can be reproduced:
//! COM correction (eq. 14) → MLP φ on the pusher's position and motion in the object frame → Lynch's
//! model → motion correction (eq. 15).
//!
//! - this module: the model's data, its constants and its public entry points;
//! - [`pass`]: the single-sample forward and backward pass, and the online step;
//! - [`batch`]: offline training's layer-by-layer batch kernel;
//! - [`calibrate`]: the per-component step sizes of online learning.
//!
//! The chain rule through the input normalisation is written once, in [`PaperModel::network_input`]
//! and [`PaperModel::theta_gradient`]; every pass goes through them.

mod batch;
mod calibrate;
mod pass;

use serde::{Deserialize, Serialize};

pub(crate) use self::batch::BatchPass;
pub(crate) use self::calibrate::scales_from_curvature;
pub(crate) use self::pass::Pass;
use super::kernel::{RealSample, theta_real};
use super::mlp::{HIDDEN, Network, OUTPUTS};
use super::normalization::InputNormalization;
use super::params::OnlineParams;
use super::{ObjectMotion, Prediction, SampleInput};
use crate::model::{ComMisfit, LossScale};
use crate::real::Real;
use crate::simd::MulAdd;

/// The paper's combined model: the offline part (the network and its normalisation) and the starting
/// point of the online part, `θ_online(0)`.
///
/// `θ_online` itself is not stored here: it is an argument of every prediction, so that one trained
/// model can serve many online learners (the app's "fixed" and "online" runs, one per trajectory).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(bound = "", from = "PaperModelData<T>")]
pub struct PaperModel<T: Real = f32> {
    /// The network φ: normalised (COM-relative pusher position, pusher motion) → normalised (contact
    /// point relative to the COM, contact motion).
    pub(crate) network: Network<T>,
    pub(crate) normalization: InputNormalization,
    pub(crate) theta0: OnlineParams,
    pub(crate) loss_scale: LossScale,
    pub(crate) horizon: usize,
    /// Per-component scales of `θ_online` for online gradient descent, metres (see
    /// [`PaperModel::theta_scales`]).
    pub(crate) theta_scales: [f64; 3],
    /// How far its learned COM lands from the truth on objects it did not train on.
    #[serde(default)]
    pub(crate) com_misfit: ComMisfit,
    /// `normalization` as the constants the hot loops use, derived once.
    #[serde(skip)]
    constants: Constants<T>,
}

/// What a model file holds of a [`PaperModel`]: everything but the derived constants.
#[derive(Deserialize)]
#[serde(bound = "")]
struct PaperModelData<T: Real> {
    network: Network<T>,
    normalization: InputNormalization,
    theta0: OnlineParams,
    loss_scale: LossScale,
    horizon: usize,
    theta_scales: [f64; 3],
    #[serde(default)]
    com_misfit: ComMisfit,
}

impl<T: Real> From<PaperModelData<T>> for PaperModel<T> {
    fn from(d: PaperModelData<T>) -> Self {
        Self {
            constants: Constants::of(&d.normalization),
            network: d.network,
            normalization: d.normalization,
            theta0: d.theta0,
            loss_scale: d.loss_scale,
            horizon: d.horizon,
            theta_scales: d.theta_scales,
            com_misfit: d.com_misfit,
        }
    }
}

/// The normalisation in the model's float type, with reciprocals of the standard deviations: the
/// forward and backward passes multiply instead of converting from `f64` and dividing on every call.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Constants<T> {
    position_mean: [T; 2],
    position_std: [T; 2],
    position_inv_std: [T; 2],
    motion_mean: [T; 2],
    motion_std: [T; 2],
    motion_inv_std: [T; 2],
}

impl<T: Real> Constants<T> {
    fn of(n: &InputNormalization) -> Self {
        let t = |a: [f64; 2]| a.map(T::of);
        let inv = |a: [f64; 2]| a.map(|x| T::of(1.0 / x));
        Self {
            position_mean: t(n.position.mean),
            position_std: t(n.position.std),
            position_inv_std: inv(n.position.std),
            motion_mean: t(n.motion.mean),
            motion_std: t(n.motion.std),
            motion_inv_std: inv(n.motion.std),
        }
    }
}

/// The part of a forward pass that does not depend on `θ_online`, computed once per sample: online
/// learning redoes the forward pass for every gradient step with the same input.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Prepared<T> {
    /// The normalised pusher position relative to the centre (the COM offset is subtracted later).
    position: [T; 2],
    /// The normalised pusher motion.
    motion: [T; 2],
    /// The first layer's pre-activation from the motion inputs and the bias.
    context_part: [T; HIDDEN],
}

impl<T: Real> PaperModel<T> {
    /// A model from its parts (used by training).
    pub(crate) fn from_parts(
        network: Network<T>,
        normalization: InputNormalization,
        theta0: OnlineParams,
        loss_scale: LossScale,
        horizon: usize,
    ) -> Self {
        let length = normalization.position.scale();
        Self {
            network,
            normalization,
            theta0: theta0.clamped(),
            loss_scale,
            horizon,
            theta_scales: [length; 3],
            com_misfit: ComMisfit::default(),
            constants: Constants::of(&normalization),
        }
    }

    /// `θ_online(0)`: where online learning starts.
    pub fn theta0(&self) -> OnlineParams {
        self.theta0
    }

    /// The prediction horizon in frames the model was trained for.
    pub fn horizon(&self) -> usize {
        self.horizon
    }

    /// The σ of the offline data that normalise the losses.
    pub fn loss_scale(&self) -> LossScale {
        self.loss_scale
    }

    /// The normalisation of the network's inputs.
    pub fn normalization(&self) -> &InputNormalization {
        &self.normalization
    }

    /// The scales by which online learning divides each component of `θ_online` before taking
    /// gradient steps, metres.
    ///
    /// The paper's learning rate (0.005) was meant for normalised units. Each component is scaled so
    /// that the loss has unit curvature along it on the offline data (the Gauss–Newton diagonal, see
    /// [`PaperModel::calibrate_theta_scales`]): a single length (the spread of the pusher position)
    /// is not enough, because the network is far steeper along the push — where the offline pushes
    /// never moved the pusher — than across it, and one step size either diverged along the push or
    /// crawled across it.
    pub fn theta_scales(&self) -> [f64; 3] {
        self.theta_scales
    }

    /// How far its learned COM lands from the truth on objects it did not train on.
    pub fn com_misfit(&self) -> ComMisfit {
        self.com_misfit
    }

    /// The same model in another float type (`f64` for gradient checks).
    pub fn cast<U: Real>(&self) -> PaperModel<U> {
        PaperModel {
            network: self.network.cast(),
            normalization: self.normalization,
            theta0: self.theta0,
            loss_scale: self.loss_scale,
            horizon: self.horizon,
            theta_scales: self.theta_scales,
            com_misfit: self.com_misfit,
            constants: Constants::of(&self.normalization),
        }
    }

    /// Predicts the object's motion for one input with the given `θ_online`.
    pub fn predict(&self, input: &SampleInput, theta: &OnlineParams) -> Prediction {
        let sample = RealSample::<T>::of(&super::Sample {
            input: *input,
            target: ObjectMotion::default(),
            frame: 0,
        });
        self.predict_real(&sample.input, &theta_real(theta))
    }

    crate::simd::dispatch_simd! {
        /// The forward pass to a [`Prediction`], in the widest SIMD available.
        fn predict_real(&self, input: &[T; 4], theta: &[T; 3]) -> Prediction
            => predict_portable, predict_avx2
    }

    #[inline(always)]
    fn predict_portable<A: MulAdd>(&self, input: &[T; 4], theta: &[T; 3]) -> Prediction {
        let mut pass = Pass::default();
        self.forward_with::<A>(input, theta, &mut pass);
        pass.tail.prediction(theta)
    }

    /// The part of the forward pass that does not depend on `θ_online`.
    #[inline(always)]
    pub(crate) fn prepare<A: MulAdd>(&self, input: &[T; 4]) -> Prepared<T> {
        let (position, motion) = self.normalized(input);
        let x = [position[0], position[1], motion[0], motion[1]];
        Prepared {
            position,
            motion,
            context_part: self.network.first_layer_context::<A>(&x),
        }
    }

    /// The normalised pusher position (relative to the centre) and motion.
    #[inline(always)]
    fn normalized(&self, input: &[T; 4]) -> ([T; 2], [T; 2]) {
        let c = &self.constants;
        (
            [
                (input[0] - c.position_mean[0]) * c.position_inv_std[0],
                (input[1] - c.position_mean[1]) * c.position_inv_std[1],
            ],
            [
                (input[2] - c.motion_mean[0]) * c.motion_inv_std[0],
                (input[3] - c.motion_mean[1]) * c.motion_inv_std[1],
            ],
        )
    }

    /// The network's input from the normalised position and motion and `θ_online`. Eq. 14: the
    /// pusher relative to the COM rather than to the centre, `x = (p − mean) / std − offset / std`.
    #[inline(always)]
    pub(crate) fn network_input<A: MulAdd>(
        &self,
        position: [T; 2],
        motion: [T; 2],
        theta: &[T; 3],
    ) -> [T; 4] {
        let c = &self.constants;
        [
            A::mul_add(-theta[0], c.position_inv_std[0], position[0]),
            A::mul_add(-theta[1], c.position_inv_std[1], position[1]),
            motion[0],
            motion[1],
        ]
    }

    /// The gradient with respect to `θ_online` from the gradient with respect to the network's
    /// position inputs `d_x` and the direct gradients of the COM offset (eq. 15) and of `h`: the
    /// backward pass of [`PaperModel::network_input`].
    #[inline(always)]
    pub(crate) fn theta_gradient<A: MulAdd>(
        &self,
        d_x: [T; 2],
        d_offset: [T; 2],
        d_h: T,
    ) -> [T; 3] {
        let c = &self.constants;
        [
            A::mul_add(-d_x[0], c.position_inv_std[0], d_offset[0]),
            A::mul_add(-d_x[1], c.position_inv_std[1], d_offset[1]),
            d_h,
        ]
    }

    /// The COM-relative contact point and the contact motion from the network's output: both are
    /// de-normalised with the input statistics (see [`InputNormalization`]).
    #[inline(always)]
    fn contact_of<A: MulAdd>(&self, z: &[T; OUTPUTS]) -> ([T; 2], [T; 2]) {
        let c = &self.constants;
        (
            [
                A::mul_add(z[0], c.position_std[0], c.position_mean[0]),
                A::mul_add(z[1], c.position_std[1], c.position_mean[1]),
            ],
            [
                A::mul_add(z[2], c.motion_std[0], c.motion_mean[0]),
                A::mul_add(z[3], c.motion_std[1], c.motion_mean[1]),
            ],
        )
    }

    /// The backward pass of [`PaperModel::contact_of`].
    #[inline(always)]
    fn contact_gradient(&self, d_contact: [T; 2], d_contact_motion: [T; 2]) -> [T; OUTPUTS] {
        let c = &self.constants;
        [
            d_contact[0] * c.position_std[0],
            d_contact[1] * c.position_std[1],
            d_contact_motion[0] * c.motion_std[0],
            d_contact_motion[1] * c.motion_std[1],
        ]
    }
}
