//! The combined prediction model of the paper's Fig. 4: COM correction (eq. 14) → MLP φ → Lynch's
//! physical model → motion correction (eq. 15).

use serde::{Deserialize, Serialize};

use super::mlp::{Activations, BATCH, BatchActivations, HIDDEN, Mlp, Network, OUTPUTS};
use super::normalization::InputNormalization;
use super::params::OnlineParams;
use super::physics::{
    ComMotion, LynchCache, centre_motion_backward_rotated, centre_motion_rotated,
    lynch_backward_cached, lynch_forward,
};
use super::{ObjectMotion, Prediction, SampleInput};
use crate::learn::LossScale;
use crate::real::Real;
use crate::simd::{MulAdd, Unfused};

/// The combined model: the offline part (the network and its normalisation) and the starting point of
/// the online part, `θ_online(0)`.
///
/// `θ_online` itself is not stored here: it is an argument of every prediction, so that one trained
/// model can serve many online learners (the app's "fixed" and "online" runs, one per trajectory).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(bound = "", from = "CombinedModelData<T>")]
pub struct CombinedModel<T: Real = f32> {
    /// The network φ: normalised (COM-relative pusher position, pusher motion) → normalised (contact
    /// point relative to the COM, contact motion).
    pub(crate) network: Network<T>,
    pub(crate) normalization: InputNormalization,
    pub(crate) theta0: OnlineParams,
    pub(crate) loss_scale: LossScale,
    pub(crate) horizon: usize,
    /// Per-component scales of `θ_online` for online gradient descent, metres (see
    /// [`CombinedModel::theta_scales`]).
    pub(crate) theta_scales: [f64; 3],
    /// `normalization` and `loss_scale` as the constants the hot loops use, derived once.
    #[serde(skip)]
    constants: Constants<T>,
}

/// What a model file holds of a [`CombinedModel`]: everything but the derived constants.
#[derive(Deserialize)]
#[serde(bound = "")]
struct CombinedModelData<T: Real> {
    network: Network<T>,
    normalization: InputNormalization,
    theta0: OnlineParams,
    loss_scale: LossScale,
    horizon: usize,
    theta_scales: [f64; 3],
}

impl<T: Real> From<CombinedModelData<T>> for CombinedModel<T> {
    fn from(d: CombinedModelData<T>) -> Self {
        Self {
            constants: Constants::of(&d.normalization, &d.loss_scale),
            network: d.network,
            normalization: d.normalization,
            theta0: d.theta0,
            loss_scale: d.loss_scale,
            horizon: d.horizon,
            theta_scales: d.theta_scales,
        }
    }
}

/// The normalisation and the loss weights in the model's float type, with reciprocals of the
/// standard deviations: the forward and backward passes multiply instead of converting from `f64` and
/// dividing on every call.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Constants<T> {
    position_mean: [T; 2],
    position_std: [T; 2],
    position_inv_std: [T; 2],
    motion_mean: [T; 2],
    motion_std: [T; 2],
    motion_inv_std: [T; 2],
    /// See [`loss_weights`].
    loss_weights: [T; 3],
}

impl<T: Real> Constants<T> {
    fn of(n: &InputNormalization, loss_scale: &LossScale) -> Self {
        let t = |a: [f64; 2]| a.map(T::of);
        let inv = |a: [f64; 2]| a.map(|x| T::of(1.0 / x));
        Self {
            position_mean: t(n.position.mean),
            position_std: t(n.position.std),
            position_inv_std: inv(n.position.std),
            motion_mean: t(n.motion.mean),
            motion_std: t(n.motion.std),
            motion_inv_std: inv(n.motion.std),
            loss_weights: loss_weights(loss_scale),
        }
    }
}

/// Everything one forward pass computes that its backward pass needs.
#[derive(Clone, Debug, Default)]
pub(crate) struct Pass<T> {
    activations: Activations<T>,
    physics: PhysicsPass<T>,
}

/// What the forward pass after the network (output scaling, Lynch, eq. 15) keeps for its backward pass.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct PhysicsPass<T> {
    /// Contact point relative to the COM, object frame.
    contact: [T; 2],
    contact_motion: [T; 2],
    com: ComMotion<T>,
    lynch: LynchCache<T>,
    /// `(sin Δω, cos Δω)` of the predicted rotation.
    rotation_sin_cos: (T, T),
    /// Predicted motion of the geometric centre.
    centre: [T; 2],
}

/// Scratch space of [`CombinedModel::accumulate_batch`]: a batch's activations and gradients.
#[derive(Clone, Debug)]
pub(crate) struct BatchPass<T> {
    activations: BatchActivations<T>,
    output: [[T; OUTPUTS]; BATCH],
    d_output: [[T; OUTPUTS]; BATCH],
    d1: [[T; HIDDEN]; BATCH],
    /// Per sample: the direct gradient with respect to the COM offset and `h`.
    d_theta: [[T; 3]; BATCH],
}

impl<T: Real> Default for BatchPass<T> {
    fn default() -> Self {
        let z = T::zero();
        Self {
            activations: BatchActivations::default(),
            output: [[z; OUTPUTS]; BATCH],
            d_output: [[z; OUTPUTS]; BATCH],
            d1: [[z; HIDDEN]; BATCH],
            d_theta: [[z; 3]; BATCH],
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
    motion_part: [T; HIDDEN],
}

/// A sample converted once to the model's float type: `[p_x, p_y, u_x, u_y]` and
/// `[Δp_x, Δp_y, Δω]`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RealSample<T> {
    pub input: [T; 4],
    pub target: [T; 3],
}

impl<T: Real> RealSample<T> {
    pub fn of(sample: &super::Sample) -> Self {
        let i = &sample.input;
        let t = &sample.target;
        Self {
            input: [
                T::of(i.robot_in_object[0]),
                T::of(i.robot_in_object[1]),
                T::of(i.robot_motion_in_object[0]),
                T::of(i.robot_motion_in_object[1]),
            ],
            target: [
                T::of(t.translation[0]),
                T::of(t.translation[1]),
                T::of(t.rotation),
            ],
        }
    }
}

/// The inverse squared σ of each output, the weights of the loss.
pub(crate) fn loss_weights<T: Real>(scale: &LossScale) -> [T; 3] {
    [
        T::of(1.0 / (scale.sigma_pos[0] * scale.sigma_pos[0])),
        T::of(1.0 / (scale.sigma_pos[1] * scale.sigma_pos[1])),
        T::of(1.0 / (scale.sigma_rot * scale.sigma_rot)),
    ]
}

impl<T: Real> CombinedModel<T> {
    /// A model from its parts (used by training and model files).
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
            constants: Constants::of(&normalization, &loss_scale),
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
    /// [`CombinedModel::calibrate_theta_scales`]): a single length (the spread of the pusher position)
    /// is not enough, because the network is far steeper along the push — where the offline pushes never
    /// moved the pusher — than across it, and one step size either diverged along the push or crawled
    /// across it.
    pub fn theta_scales(&self) -> [f64; 3] {
        self.theta_scales
    }

    /// Sets [`CombinedModel::theta_scales`] from the Gauss–Newton diagonal of the loss at `θ_online(0)`
    /// over `samples`: `s_i = 1 / sqrt(mean_samples Σ_k 2 w_k (∂ŷ_k/∂θ_i)²)`.
    pub fn calibrate_theta_scales(&mut self, samples: &[super::Sample]) {
        if samples.is_empty() {
            return;
        }
        let curvature = self.theta_curvature(samples);
        let fallback = self.normalization.position.scale();
        for (scale, c) in self.theta_scales.iter_mut().zip(curvature) {
            let mean = c / samples.len() as f64;
            *scale = if mean.is_finite() && mean > 0.0 {
                1.0 / mean.sqrt()
            } else {
                fallback
            };
        }
    }

    crate::simd::dispatch_simd! {
        /// `Σ_samples Σ_k 2 w_k (∂ŷ_k/∂θ_i)²` at `θ_online(0)`, in the widest SIMD available.
        fn theta_curvature(&self, samples: &[super::Sample]) -> [f64; 3]
            => theta_curvature_portable, theta_curvature_avx2
    }

    #[inline(always)]
    fn theta_curvature_portable<A: MulAdd>(&self, samples: &[super::Sample]) -> [f64; 3] {
        let c = &self.constants;
        let weights = c.loss_weights;
        let theta = theta_real(&self.theta0);
        let mut curvature = [0.0f64; 3];
        let mut batch = Box::<BatchPass<T>>::default();
        let mut tangents = Box::new([[[T::zero(); HIDDEN]; 2]; BATCH]);
        let mut jacobians = Box::new([[[T::zero(); OUTPUTS]; 2]; BATCH]);
        let mut physics = PhysicsPass::default();
        for chunk in samples.chunks(BATCH) {
            let n = chunk.len();
            for (x, sample) in batch.activations.input.iter_mut().zip(chunk) {
                let input = RealSample::<T>::of(sample).input;
                *x = self.network_input::<A>(&input, &theta);
            }
            self.network
                .forward_batch::<A>(n, &mut batch.activations, &mut batch.output);
            // The network's Jacobian with respect to its position inputs (forward mode), then one
            // cheap backward pass through the physics per output.
            self.network.position_jacobian_batch::<A>(
                n,
                &batch.activations,
                &mut tangents,
                &mut jacobians,
            );
            for (z, [ja, jb]) in batch.output[..n].iter().zip(&*jacobians) {
                self.physics_forward::<A>(*z, &theta, &mut physics);
                for (k, w) in weights.iter().enumerate() {
                    let mut d_centre = [T::zero(); 2];
                    let mut d_rotation = T::zero();
                    if k < 2 {
                        d_centre[k] = T::one();
                    } else {
                        d_rotation = T::one();
                    }
                    let (d_z, d_offset, d_h) =
                        self.physics_backward::<A>(&physics, &theta, d_centre, d_rotation);
                    let d_x = [
                        A::mul_add(d_z[0], ja[0], d_z[1] * ja[1])
                            + A::mul_add(d_z[2], ja[2], d_z[3] * ja[3]),
                        A::mul_add(d_z[0], jb[0], d_z[1] * jb[1])
                            + A::mul_add(d_z[2], jb[2], d_z[3] * jb[3]),
                    ];
                    let row = [
                        A::mul_add(-d_x[0], c.position_inv_std[0], d_offset[0]),
                        A::mul_add(-d_x[1], c.position_inv_std[1], d_offset[1]),
                        d_h,
                    ];
                    for (c, j) in curvature.iter_mut().zip(row) {
                        *c += 2.0 * w.as_f64() * j.as_f64() * j.as_f64();
                    }
                }
            }
        }
        curvature
    }

    /// The network's input for a pusher position and motion (`[p_x, p_y, u_x, u_y]`, object frame)
    /// and `θ_online`, exactly as [`CombinedModel::prepare`] and [`CombinedModel::forward_prepared`]
    /// compute it: `x = (p − mean) / std − offset / std`, `(u − mean) / std`.
    #[inline(always)]
    fn network_input<A: MulAdd>(&self, input: &[T; 4], theta: &[T; 3]) -> [T; 4] {
        let c = &self.constants;
        [
            A::mul_add(
                -theta[0],
                c.position_inv_std[0],
                (input[0] - c.position_mean[0]) * c.position_inv_std[0],
            ),
            A::mul_add(
                -theta[1],
                c.position_inv_std[1],
                (input[1] - c.position_mean[1]) * c.position_inv_std[1],
            ),
            (input[2] - c.motion_mean[0]) * c.motion_inv_std[0],
            (input[3] - c.motion_mean[1]) * c.motion_inv_std[1],
        ]
    }

    /// The same model in another float type (`f64` for gradient checks).
    pub fn cast<U: Real>(&self) -> CombinedModel<U> {
        CombinedModel {
            network: self.network.cast(),
            normalization: self.normalization,
            theta0: self.theta0,
            loss_scale: self.loss_scale,
            horizon: self.horizon,
            theta_scales: self.theta_scales,
            constants: Constants::of(&self.normalization, &self.loss_scale),
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
        pass.prediction(theta)
    }

    /// The forward pass in the model's float type. `theta` is `[com_x, com_y, h]`.
    #[inline(always)]
    pub(crate) fn forward(&self, input: &[T; 4], theta: &[T; 3], pass: &mut Pass<T>) {
        self.forward_with::<Unfused>(input, theta, pass);
    }

    /// [`CombinedModel::forward`] with the multiply-add of the compiled copy.
    #[inline(always)]
    pub(crate) fn forward_with<A: MulAdd>(
        &self,
        input: &[T; 4],
        theta: &[T; 3],
        pass: &mut Pass<T>,
    ) {
        let prepared = self.prepare::<A>(input);
        self.forward_prepared::<A>(&prepared, theta, pass);
    }

    /// The part of the forward pass that does not depend on `θ_online`.
    #[inline(always)]
    pub(crate) fn prepare<A: MulAdd>(&self, input: &[T; 4]) -> Prepared<T> {
        let c = &self.constants;
        let position = [
            (input[0] - c.position_mean[0]) * c.position_inv_std[0],
            (input[1] - c.position_mean[1]) * c.position_inv_std[1],
        ];
        let motion = [
            (input[2] - c.motion_mean[0]) * c.motion_inv_std[0],
            (input[3] - c.motion_mean[1]) * c.motion_inv_std[1],
        ];
        Prepared {
            position,
            motion,
            motion_part: self.network.first_layer_motion::<A>(motion),
        }
    }

    /// The forward pass from a prepared input.
    #[inline(always)]
    pub(crate) fn forward_prepared<A: MulAdd>(
        &self,
        prepared: &Prepared<T>,
        theta: &[T; 3],
        pass: &mut Pass<T>,
    ) {
        let c = &self.constants;
        // Eq. 14: the pusher relative to the COM rather than to the centre,
        // x = (p − offset − mean) / std.
        let x = [
            A::mul_add(-theta[0], c.position_inv_std[0], prepared.position[0]),
            A::mul_add(-theta[1], c.position_inv_std[1], prepared.position[1]),
            prepared.motion[0],
            prepared.motion[1],
        ];
        let z = self
            .network
            .forward_from::<A>(&prepared.motion_part, &x, &mut pass.activations);
        self.physics_forward::<A>(z, theta, &mut pass.physics);
    }

    /// The forward pass after the network: output scaling, Lynch (with the COM-relative contact) and
    /// the motion correction (eq. 15).
    #[inline(always)]
    fn physics_forward<A: MulAdd>(
        &self,
        z: [T; OUTPUTS],
        theta: &[T; 3],
        out: &mut PhysicsPass<T>,
    ) {
        // Written field by field into `out` before the call to `sin_cos`: every vector register is
        // caller-saved, so values kept only in registers across the call would all be spilled.
        let c = &self.constants;
        out.contact = [
            A::mul_add(z[0], c.position_std[0], c.position_mean[0]),
            A::mul_add(z[1], c.position_std[1], c.position_mean[1]),
        ];
        out.contact_motion = [
            A::mul_add(z[2], c.motion_std[0], c.motion_mean[0]),
            A::mul_add(z[3], c.motion_std[1], c.motion_mean[1]),
        ];
        (out.com, out.lynch) = lynch_forward::<T, A>(out.contact, out.contact_motion, theta[2]);
        out.rotation_sin_cos = out.com.rotation.sin_cos();
        out.centre =
            centre_motion_rotated::<T, A>(&out.com, out.rotation_sin_cos, [theta[0], theta[1]]);
    }

    /// The backward pass: from the gradient of a scalar with respect to the predicted centre motion and
    /// rotation, the gradient with respect to `θ_online` (`[com_x, com_y, h]`), and, when `network_grad`
    /// is given, the gradient with respect to the network's weights added to it. (The hot loops call
    /// [`CombinedModel::backward_with`] in their compiled copy; this is for the gradient checks.)
    #[cfg(test)]
    pub(crate) fn backward(
        &self,
        pass: &Pass<T>,
        theta: &[T; 3],
        d_centre: [T; 2],
        d_rotation: T,
        network_grad: Option<&mut Mlp<T>>,
    ) -> [T; 3] {
        self.backward_with::<Unfused>(pass, theta, d_centre, d_rotation, network_grad)
    }

    /// [`CombinedModel::backward`] with the multiply-add of the compiled copy.
    #[inline(always)]
    pub(crate) fn backward_with<A: MulAdd>(
        &self,
        pass: &Pass<T>,
        theta: &[T; 3],
        d_centre: [T; 2],
        d_rotation: T,
        network_grad: Option<&mut Mlp<T>>,
    ) -> [T; 3] {
        let c = &self.constants;
        let (d_z, d_offset, d_h) =
            self.physics_backward::<A>(&pass.physics, theta, d_centre, d_rotation);
        let d_x = match network_grad {
            Some(grad) => {
                let d1 = self
                    .network
                    .weight_gradient::<A>(&pass.activations, &d_z, grad);
                [
                    self.network.first_layer_input_gradient::<A>(&d1, 0),
                    self.network.first_layer_input_gradient::<A>(&d1, 1),
                ]
            }
            None => self.network.position_gradient::<A>(&pass.activations, &d_z),
        };
        // x = (p − offset − mean) / std.
        [
            A::mul_add(-d_x[0], c.position_inv_std[0], d_offset[0]),
            A::mul_add(-d_x[1], c.position_inv_std[1], d_offset[1]),
            d_h,
        ]
    }

    /// The backward pass through the physics (eq. 15, Lynch and the output scaling): the gradient with
    /// respect to the network's output `z`, the direct gradient with respect to the COM offset, and the
    /// gradient with respect to `h`.
    #[inline(always)]
    fn physics_backward<A: MulAdd>(
        &self,
        pass: &PhysicsPass<T>,
        theta: &[T; 3],
        d_centre: [T; 2],
        d_rotation: T,
    ) -> ([T; 4], [T; 2], T) {
        let c = &self.constants;
        let offset = [theta[0], theta[1]];
        let (d_com, d_offset) = centre_motion_backward_rotated::<T, A>(
            pass.rotation_sin_cos,
            offset,
            d_centre,
            d_rotation,
        );
        let d_lynch = lynch_backward_cached::<T, A>(
            pass.contact,
            pass.contact_motion,
            theta[2],
            &pass.com,
            &pass.lynch,
            &d_com,
        );
        let d_z = [
            d_lynch.contact[0] * c.position_std[0],
            d_lynch.contact[1] * c.position_std[1],
            d_lynch.contact_motion[0] * c.motion_std[0],
            d_lynch.contact_motion[1] * c.motion_std[1],
        ];
        (d_z, d_offset, d_lynch.h)
    }

    /// Loss (eq. 8) of one sample and its gradient with respect to the predicted outputs.
    #[inline(always)]
    pub(crate) fn loss_gradient(
        pass: &Pass<T>,
        target: &[T; 3],
        weights: &[T; 3],
    ) -> (T, [T; 2], T) {
        Self::physics_loss_gradient(&pass.physics, target, weights)
    }

    #[inline(always)]
    fn physics_loss_gradient(
        pass: &PhysicsPass<T>,
        target: &[T; 3],
        weights: &[T; 3],
    ) -> (T, [T; 2], T) {
        let e = [
            pass.centre[0] - target[0],
            pass.centre[1] - target[1],
            pass.com.rotation - target[2],
        ];
        let two = T::one() + T::one();
        let loss = weights[0] * e[0] * e[0] + weights[1] * e[1] * e[1] + weights[2] * e[2] * e[2];
        (
            loss,
            [two * weights[0] * e[0], two * weights[1] * e[1]],
            two * weights[2] * e[2],
        )
    }

    /// Offline training's hot loop for one batch (at most [`BATCH`] samples, `samples[i]` for `i` in
    /// `indices`): the forward pass, the loss (eq. 8) and the backward pass, one network layer at a
    /// time for all samples. Adds the weight gradient summed over the samples to `grad`, and the
    /// `θ_online` gradient to `theta_gradient` when given; returns the summed loss.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn accumulate_batch<A: MulAdd>(
        &self,
        samples: &[RealSample<T>],
        indices: &[usize],
        theta: &[T; 3],
        weights: &[T; 3],
        batch: &mut BatchPass<T>,
        grad: &mut Mlp<T>,
        theta_gradient: Option<&mut [f64; 3]>,
    ) -> T {
        let c = &self.constants;
        let n = indices.len().min(BATCH);
        let indices = &indices[..n];
        for (x, &i) in batch.activations.input.iter_mut().zip(indices) {
            *x = self.network_input::<A>(&samples[i].input, theta);
        }
        self.network
            .forward_batch::<A>(n, &mut batch.activations, &mut batch.output);
        let mut loss = T::zero();
        let per_sample = batch
            .output
            .iter()
            .zip(&mut batch.d_output)
            .zip(&mut batch.d_theta)
            .zip(indices);
        for (((z, d_z), d_theta), &i) in per_sample {
            let mut physics = PhysicsPass::default();
            self.physics_forward::<A>(*z, theta, &mut physics);
            let (l, d_centre, d_rotation) =
                Self::physics_loss_gradient(&physics, &samples[i].target, weights);
            loss = loss + l;
            let (d_output, d_offset, d_h) =
                self.physics_backward::<A>(&physics, theta, d_centre, d_rotation);
            *d_z = d_output;
            *d_theta = [d_offset[0], d_offset[1], d_h];
        }
        self.network.backward_batch::<A>(
            n,
            &batch.activations,
            &batch.d_output,
            grad,
            &mut batch.d1,
        );
        if let Some(total) = theta_gradient {
            for (d1, d_theta) in batch.d1[..n].iter().zip(&batch.d_theta) {
                let d_x = [
                    self.network.first_layer_input_gradient::<A>(d1, 0),
                    self.network.first_layer_input_gradient::<A>(d1, 1),
                ];
                // x = (p − offset − mean) / std.
                let g = [
                    A::mul_add(-d_x[0], c.position_inv_std[0], d_theta[0]),
                    A::mul_add(-d_x[1], c.position_inv_std[1], d_theta[1]),
                    d_theta[2],
                ];
                for (acc, gi) in total.iter_mut().zip(g) {
                    *acc += gi.as_f64();
                }
            }
        }
        loss
    }

    crate::simd::dispatch_simd! {
        /// One online update (Algorithm 1 with eq. 13 solved by `steps` gradient-descent steps): predicts
        /// with `theta`, then descends the loss of this sample in `θ_online` scaled by
        /// [`CombinedModel::theta_scales`]. Returns the prediction and gradient at `theta` and the updated
        /// parameters. Runs entirely in the model's float type and allocates nothing.
        pub(crate) fn online_update(&self, sample: &RealSample<T>, theta: &OnlineParams, steps: usize, lr: f64)
            -> (Prediction, [f64; 3], OnlineParams)
            => online_update_portable, online_update_avx2
    }

    #[inline(always)]
    fn online_update_portable<A: MulAdd>(
        &self,
        sample: &RealSample<T>,
        theta: &OnlineParams,
        steps: usize,
        lr: f64,
    ) -> (Prediction, [f64; 3], OnlineParams) {
        let weights = self.constants.loss_weights;
        let step = self.theta_scales.map(|s| T::of(lr * s * s));
        let (h_min, h_max) = (T::of(super::params::H_MIN), T::of(super::params::H_MAX));
        let mut th = theta_real(theta);
        let mut pass = Pass::default();
        // Everything that does not depend on θ_online, once for all the gradient steps.
        let prepared = self.prepare::<A>(&sample.input);
        self.forward_prepared::<A>(&prepared, &th, &mut pass);
        let prediction = pass.prediction(&th);
        let mut first_gradient = [0.0; 3];
        for k in 0..steps {
            if k > 0 {
                self.forward_prepared::<A>(&prepared, &th, &mut pass);
            }
            let (_, d_centre, d_rotation) = Self::loss_gradient(&pass, &sample.target, &weights);
            let g = self.backward_with::<A>(&pass, &th, d_centre, d_rotation, None);
            if k == 0 {
                first_gradient = g.map(|x| x.as_f64());
            }
            // Gradient descent on θ_i / s_i: θ_i ← θ_i − lr · s_i² · ∂ℓ/∂θ_i.
            for ((t, gi), si) in th.iter_mut().zip(g).zip(step) {
                *t = A::mul_add(-si, gi, *t);
            }
            th[2] = th[2].max(h_min).min(h_max);
            if !th.iter().all(|t| t.is_finite()) {
                // A degenerate sample (e.g. a NaN in the data) must not poison the learner.
                th = theta_real(theta);
                break;
            }
        }
        if steps == 0 {
            let (_, d_centre, d_rotation) = Self::loss_gradient(&pass, &sample.target, &weights);
            first_gradient = self
                .backward_with::<A>(&pass, &th, d_centre, d_rotation, None)
                .map(|x| x.as_f64());
        }
        let after = OnlineParams {
            com_offset: [th[0].as_f64(), th[1].as_f64()],
            h: th[2].as_f64(),
        }
        .clamped();
        (prediction, first_gradient, after)
    }
}

/// `θ_online` as `[com_x, com_y, h]` in the model's float type.
pub(crate) fn theta_real<T: Real>(theta: &OnlineParams) -> [T; 3] {
    let t = theta.clamped();
    [T::of(t.com_offset[0]), T::of(t.com_offset[1]), T::of(t.h)]
}

impl<T: Real> Pass<T> {
    /// The public prediction of this pass.
    #[inline(always)]
    fn prediction(&self, theta: &[T; 3]) -> Prediction {
        let f = |x: T| x.as_f64();
        let p = &self.physics;
        Prediction {
            motion: ObjectMotion {
                translation: [f(p.centre[0]), f(p.centre[1])],
                rotation: f(p.com.rotation),
            },
            contact: Some([f(p.contact[0] + theta[0]), f(p.contact[1] + theta[1])]),
            contact_motion: Some([f(p.contact_motion[0]), f(p.contact_motion[1])]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Sample;
    use crate::model::normalization::Stats2;
    use crate::rng::SplitMix64;

    /// A random model in f64 with plausible normalisation for a 0.3 m box pushed by a 0.05 m disc.
    fn model_f64(seed: u64) -> CombinedModel<f64> {
        let mut rng = SplitMix64::new(seed);
        CombinedModel::from_parts(
            Network::new(Mlp::<f64>::random(&mut rng, 0.5)),
            InputNormalization {
                position: Stats2 {
                    mean: [-0.2, 0.01],
                    std: [0.03, 0.06],
                },
                motion: Stats2 {
                    mean: [0.01, 0.0],
                    std: [0.004, 0.003],
                },
            },
            OnlineParams {
                com_offset: [0.01, -0.02],
                h: 0.08,
            },
            LossScale {
                sigma_pos: [0.004, 0.002],
                sigma_rot: 0.02,
            },
            1,
        )
    }

    fn sample() -> Sample {
        Sample {
            input: SampleInput {
                robot_in_object: [-0.21, 0.04],
                robot_motion_in_object: [0.012, -0.002],
            },
            target: ObjectMotion {
                translation: [0.009, 0.001],
                rotation: -0.03,
            },
            frame: 0,
        }
    }

    /// The loss ℓ of the sample as a function of the network's parameters and θ.
    fn loss_of(model: &CombinedModel<f64>, theta: &[f64; 3]) -> f64 {
        let s = RealSample::<f64>::of(&sample());
        let mut pass = Pass::default();
        model.forward(&s.input, theta, &mut pass);
        CombinedModel::loss_gradient(&pass, &s.target, &loss_weights(&model.loss_scale)).0
    }

    fn relative_error(a: f64, b: f64) -> f64 {
        (a - b).abs() / a.abs().max(b.abs()).max(1e-12)
    }

    #[test]
    fn gradients_of_weights_and_theta_match_central_differences() {
        for seed in [1, 2, 3] {
            let model = model_f64(seed);
            let theta = [0.012, -0.018, 0.07];
            let s = RealSample::<f64>::of(&sample());
            let mut pass = Pass::default();
            model.forward(&s.input, &theta, &mut pass);
            let (_, d_centre, d_rotation) =
                CombinedModel::loss_gradient(&pass, &s.target, &loss_weights(&model.loss_scale));
            let mut grad = Mlp::zeros();
            let g_theta = model.backward(&pass, &theta, d_centre, d_rotation, Some(&mut grad));

            // θ_online, with a step relative to its size.
            for k in 0..3 {
                let eps = 1e-7;
                let mut plus = theta;
                plus[k] += eps;
                let mut minus = theta;
                minus[k] -= eps;
                let numeric = (loss_of(&model, &plus) - loss_of(&model, &minus)) / (2.0 * eps);
                assert!(
                    relative_error(g_theta[k], numeric) <= 1e-5,
                    "seed {seed} θ[{k}]: analytic {} numeric {numeric}",
                    g_theta[k]
                );
            }

            // Every weight and bias of the network.
            let base = model.network.parameters().to_vec();
            let analytic = grad.to_vec();
            let mut checked = 0;
            for k in 0..base.len() {
                let eps = 1e-6;
                let mut m = model.clone();
                let mut p = base.clone();
                p[k] += eps;
                m.network = Network::new(Mlp::from_slice(&p).expect("finite"));
                let lp = loss_of(&m, &theta);
                p[k] -= 2.0 * eps;
                m.network = Network::new(Mlp::from_slice(&p).expect("finite"));
                let lm = loss_of(&m, &theta);
                let numeric = (lp - lm) / (2.0 * eps);
                if numeric.abs() < 1e-9 && analytic[k].abs() < 1e-9 {
                    continue; // a dead unit: no gradient either way
                }
                assert!(
                    relative_error(analytic[k], numeric) <= 1e-5,
                    "seed {seed} weight {k}: analytic {} numeric {numeric}",
                    analytic[k]
                );
                checked += 1;
            }
            assert!(checked > 100, "seed {seed}: only {checked} weights checked");
        }
    }

    #[test]
    fn online_update_descends_the_loss_and_keeps_h_in_range() {
        let model = model_f64(4);
        let s = sample();
        let theta = model.theta0();
        let real = RealSample::<f64>::of(&s);
        let (_, g, after) = model.online_update(&real, &theta, 5, 0.005);
        let before_loss = loss_of(&model, &theta_real(&theta));
        let after_loss = loss_of(&model, &theta_real(&after));
        assert!(after_loss < before_loss, "{after_loss} !< {before_loss}");
        assert!(g.iter().any(|x| *x != 0.0));
        // A huge learning rate can push h anywhere; it must stay in range.
        let (_, _, wild) = model.online_update(&real, &theta, 5, 1e6);
        assert!((crate::model::H_MIN..=crate::model::H_MAX).contains(&wild.h));
    }

    /// Samples around `sample()`, varied so that different ReLUs are active.
    fn varied_samples(count: usize) -> Vec<Sample> {
        let mut rng = SplitMix64::new(9);
        (0..count)
            .map(|frame| {
                let mut s = sample();
                s.input.robot_in_object[0] += 0.02 * rng.normal();
                s.input.robot_in_object[1] += 0.05 * rng.normal();
                s.input.robot_motion_in_object[0] += 0.003 * rng.normal();
                s.input.robot_motion_in_object[1] += 0.003 * rng.normal();
                s.target.rotation += 0.01 * rng.normal();
                s.frame = frame;
                s
            })
            .collect()
    }

    #[test]
    fn batch_gradient_is_the_sum_of_per_sample_gradients() {
        // The training loop's layer-by-layer batch pass against the per-sample pass that the finite-
        // difference test checks, for a full batch and a short last one, in both compiled variants.
        let model = model_f64(6);
        let theta = [0.012, -0.018, 0.07];
        let weights = loss_weights(&model.loss_scale);
        let samples: Vec<RealSample<f64>> = varied_samples(45).iter().map(RealSample::of).collect();
        let indices: Vec<usize> = (0..45).rev().collect();
        let mut expected_grad = Mlp::zeros();
        let mut expected_theta = [0.0; 3];
        let mut expected_loss = 0.0;
        let mut pass = Pass::default();
        for &i in &indices {
            model.forward(&samples[i].input, &theta, &mut pass);
            let (loss, d_centre, d_rotation) =
                CombinedModel::loss_gradient(&pass, &samples[i].target, &weights);
            let g = model.backward(
                &pass,
                &theta,
                d_centre,
                d_rotation,
                Some(&mut expected_grad),
            );
            for (e, gi) in expected_theta.iter_mut().zip(g) {
                *e += gi;
            }
            expected_loss += loss;
        }
        let check = |grad: &Mlp<f64>, theta_gradient: &[f64; 3], loss: f64| {
            for (a, b) in grad.to_vec().iter().zip(expected_grad.to_vec()) {
                assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "{a} vs {b}");
            }
            for (a, b) in theta_gradient.iter().zip(expected_theta) {
                assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "θ: {a} vs {b}");
            }
            assert!((loss - expected_loss).abs() <= 1e-12 * expected_loss);
        };
        let mut batch = BatchPass::default();
        for fused in [false, true] {
            let mut grad = Mlp::zeros();
            let mut theta_gradient = [0.0; 3];
            let mut loss = 0.0;
            for chunk in indices.chunks(BATCH) {
                loss += if fused {
                    model.accumulate_batch::<crate::simd::Fused>(
                        &samples,
                        chunk,
                        &theta,
                        &weights,
                        &mut batch,
                        &mut grad,
                        Some(&mut theta_gradient),
                    )
                } else {
                    model.accumulate_batch::<Unfused>(
                        &samples,
                        chunk,
                        &theta,
                        &weights,
                        &mut batch,
                        &mut grad,
                        Some(&mut theta_gradient),
                    )
                };
            }
            check(&grad, &theta_gradient, loss);
        }
    }

    #[test]
    fn theta_curvature_matches_reverse_mode_jacobians() {
        // The calibration's forward-mode Jacobian against one backward pass per output.
        let model = model_f64(7);
        let samples = varied_samples(20);
        let weights = loss_weights::<f64>(&model.loss_scale);
        let theta = theta_real::<f64>(&model.theta0);
        let mut expected = [0.0; 3];
        let mut pass = Pass::default();
        for sample in &samples {
            let real = RealSample::<f64>::of(sample);
            model.forward(&real.input, &theta, &mut pass);
            for (k, w) in weights.iter().enumerate() {
                let mut d_centre = [0.0; 2];
                let mut d_rotation = 0.0;
                if k < 2 {
                    d_centre[k] = 1.0;
                } else {
                    d_rotation = 1.0;
                }
                let row = model.backward(&pass, &theta, d_centre, d_rotation, None);
                for (e, j) in expected.iter_mut().zip(row) {
                    *e += 2.0 * w * j * j;
                }
            }
        }
        let curvature = model.theta_curvature_portable::<Unfused>(&samples);
        for (a, b) in curvature.iter().zip(expected) {
            assert!(b > 0.0 && relative_error(*a, b) <= 1e-12, "{a} vs {b}");
        }
    }

    #[test]
    fn f32_and_f64_models_agree() {
        let model = model_f64(5);
        let single: CombinedModel<f32> = model.cast();
        let theta = model.theta0();
        let a = model.predict(&sample().input, &theta);
        let b = single.predict(&sample().input, &theta);
        assert!((a.motion.translation[0] - b.motion.translation[0]).abs() < 1e-6);
        assert!((a.motion.rotation - b.motion.rotation).abs() < 1e-5);
    }
}
