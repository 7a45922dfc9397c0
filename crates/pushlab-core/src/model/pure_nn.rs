//! The paper's "Offline NN" baseline: the same MLP mapping `x` straight to `y`, no physics.

use serde::{Deserialize, Serialize};

use super::kernel::RealSample;
use super::mlp::{Activations, Mlp, Network};
use super::normalization::{InputNormalization, Stats1, Stats2};
use super::{ObjectMotion, Prediction, SampleInput};
use crate::model::LossScale;
use crate::real::Real;

/// How the pure network's outputs are scaled back to metres and radians.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct OutputNormalization {
    pub translation: Stats2,
    pub rotation: Stats1,
}

/// The pure neural-network model: normalised `(p_r^o, u_r^o)` → normalised `(Δp_o, Δω_o)`.
///
/// It has no `θ_online`, so it cannot adapt online: it shows what the physics in the combined model buys.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(bound = "")]
pub struct PureNnModel<T: Real = f32> {
    pub(crate) network: Network<T>,
    pub(crate) input: InputNormalization,
    pub(crate) output: OutputNormalization,
    pub(crate) loss_scale: LossScale,
    pub(crate) horizon: usize,
}

impl<T: Real> PureNnModel<T> {
    /// The prediction horizon in frames the model was trained for.
    pub fn horizon(&self) -> usize {
        self.horizon
    }

    /// The σ of the offline data that normalise the losses.
    pub fn loss_scale(&self) -> LossScale {
        self.loss_scale
    }

    /// Predicts the object's motion.
    pub fn predict(&self, input: &SampleInput) -> Prediction {
        let sample = RealSample::<T>::of(&super::Sample {
            input: *input,
            target: ObjectMotion::default(),
            frame: 0,
        });
        let mut act = Activations::default();
        let y = self.forward(&sample.input, &mut act);
        Prediction {
            motion: ObjectMotion {
                translation: [y[0].as_f64(), y[1].as_f64()],
                rotation: y[2].as_f64(),
            },
            contact: None,
            contact_motion: None,
        }
    }

    /// The forward pass: `[Δp_x, Δp_y, Δω]` in metres and radians. The network's fourth output is
    /// unused (the paper's network has four outputs; the pure model needs three).
    #[inline(always)]
    pub(crate) fn forward(&self, input: &[T; 4], act: &mut Activations<T>) -> [T; 3] {
        let n = &self.input;
        let x = [
            (input[0] - T::of(n.position.mean[0])) / T::of(n.position.std[0]),
            (input[1] - T::of(n.position.mean[1])) / T::of(n.position.std[1]),
            (input[2] - T::of(n.motion.mean[0])) / T::of(n.motion.std[0]),
            (input[3] - T::of(n.motion.mean[1])) / T::of(n.motion.std[1]),
        ];
        let z = self.network.forward(&x, act);
        let o = &self.output;
        [
            z[0] * T::of(o.translation.std[0]) + T::of(o.translation.mean[0]),
            z[1] * T::of(o.translation.std[1]) + T::of(o.translation.mean[1]),
            z[2] * T::of(o.rotation.std) + T::of(o.rotation.mean),
        ]
    }

    /// Adds the weight gradient of `loss = Σ w_i (y_i − target_i)²` to `grad`; returns the loss.
    #[inline(always)]
    pub(crate) fn accumulate_gradient(
        &self,
        sample: &RealSample<T>,
        weights: &[T; 3],
        act: &mut Activations<T>,
        grad: &mut Mlp<T>,
    ) -> T {
        let y = self.forward(&sample.input, act);
        let two = T::one() + T::one();
        let o = &self.output;
        let scales = [
            T::of(o.translation.std[0]),
            T::of(o.translation.std[1]),
            T::of(o.rotation.std),
        ];
        let mut loss = T::zero();
        let mut d_z = [T::zero(); 4];
        for i in 0..3 {
            let e = y[i] - sample.target[i];
            loss = loss + weights[i] * e * e;
            d_z[i] = two * weights[i] * e * scales[i];
        }
        self.network.backward(act, &d_z, grad);
        loss
    }

    /// The same model in another float type.
    pub fn cast<U: Real>(&self) -> PureNnModel<U> {
        PureNnModel {
            network: self.network.cast(),
            input: self.input,
            output: self.output,
            loss_scale: self.loss_scale,
            horizon: self.horizon,
        }
    }
}
