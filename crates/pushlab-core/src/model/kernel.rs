//! What every model kind shares around its own forward and backward pass: samples in the model's
//! float type, the loss (eq. 8) and its gradient, and the online step's gradient descent on
//! `θ_online` (eq. 13) with one rule for `h`'s range and for non-finite steps.

use super::params::{COM_OFFSET_MAX, H_MAX, H_MIN, OnlineParams};
use super::{Prediction, Sample};
use crate::model::LossScale;
use crate::parallel;
use crate::real::Real;
use crate::simd::MulAdd;

/// One sample's terms `2 w_k (∂ŷ_k/∂θ_i)²` of the Gauss–Newton diagonal of the loss in `θ_online`,
/// by output `k` and component `i`: what the online step scales are calibrated from.
pub(crate) type CurvatureTerms = [[f64; 3]; 3];

/// The Gauss–Newton diagonal over `samples`, from each sample's [`CurvatureTerms`] as `terms` hands
/// them over, slice by slice in sample order: added by sample, output and component, the order of
/// the single-sample passes the kinds calibrated with first, so the stored scales keep their bits,
/// while the later samples' terms are computed on the machine's other cores
/// ([`parallel::ordered_sum`]).
pub(crate) fn curvature_sum<S: Sync>(
    samples: &[S],
    terms: impl Fn(&[S], &mut dyn FnMut(CurvatureTerms)) + Sync,
) -> [f64; 3] {
    let add = add_curvature_terms;
    parallel::ordered_sum(samples, parallel::SAMPLES_PER_WORKER, [0.0; 3], add, terms)
}

/// Adds one sample's terms to `curvature`, by output, then component: the order the sums' bits
/// depend on.
pub(crate) fn add_curvature_terms(curvature: &mut [f64; 3], terms: CurvatureTerms) {
    for output in terms {
        for (c, term) in curvature.iter_mut().zip(output) {
            *c += term;
        }
    }
}

/// A sample converted once to the model's float type: `[p_x, p_y, u_x, u_y]` and
/// `[Δp_x, Δp_y, Δω]`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RealSample<T> {
    pub input: [T; 4],
    pub target: [T; 3],
}

impl<T: Real> RealSample<T> {
    pub fn of(sample: &Sample) -> Self {
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

/// The loss ℓ (eq. 8) of a predicted `[Δp_x, Δp_y, Δω]` and its gradient with respect to it.
#[inline(always)]
pub(crate) fn loss_gradient<T: Real>(
    predicted: [T; 3],
    target: &[T; 3],
    weights: &[T; 3],
) -> (T, [T; 3]) {
    let e = [
        predicted[0] - target[0],
        predicted[1] - target[1],
        predicted[2] - target[2],
    ];
    let two = T::one() + T::one();
    let loss = weights[0] * e[0] * e[0] + weights[1] * e[1] * e[1] + weights[2] * e[2] * e[2];
    (
        loss,
        [
            two * weights[0] * e[0],
            two * weights[1] * e[1],
            two * weights[2] * e[2],
        ],
    )
}

/// `θ_online` as `[com_x, com_y, h]` in the model's float type.
pub(crate) fn theta_real<T: Real>(theta: &OnlineParams) -> [T; 3] {
    let t = theta.clamped();
    [T::of(t.com_offset[0]), T::of(t.com_offset[1]), T::of(t.h)]
}

/// `[com_x, com_y, h]` back to parameters.
pub(crate) fn theta_params<T: Real>(theta: &[T; 3]) -> OnlineParams {
    OnlineParams {
        com_offset: [theta[0].as_f64(), theta[1].as_f64()],
        h: theta[2].as_f64(),
    }
    .clamped()
}

/// One model kind's forward and backward pass with respect to `θ_online` on one prepared sample: what
/// the shared online step needs.
pub(crate) trait ThetaPass<T: Real> {
    /// The forward pass at `theta`: the predicted `[Δp_x, Δp_y, Δω]`.
    fn forward(&mut self, theta: &[T; 3]) -> [T; 3];
    /// The gradient with respect to `theta` of a scalar whose gradient with respect to the last
    /// forward pass's output is `d_output`.
    fn backward(&mut self, theta: &[T; 3], d_output: [T; 3]) -> [T; 3];
    /// [`ThetaPass::backward`] of several `d_output` after the same forward pass, each the same
    /// numbers; a kind may take them together (see `Network::position_gradients`).
    #[inline(always)]
    fn backward_many<const N: usize>(
        &mut self,
        theta: &[T; 3],
        d_outputs: [[T; 3]; N],
    ) -> [[T; 3]; N] {
        let mut gradients = [[T::zero(); 3]; N];
        for (g, d) in gradients.iter_mut().zip(d_outputs) {
            *g = self.backward(theta, d);
        }
        gradients
    }
    /// The public prediction of the last forward pass.
    fn prediction(&self, theta: &[T; 3]) -> Prediction;
}

/// What one sample says about `θ_online` near a point: the prediction there, the residual normalised
/// by the loss's σ (`r_i = (predicted_i − target_i) / σ_i`, so that the loss is `Σ r_i²`) and its
/// Jacobian `∂r_i/∂θ_j` (per metre). Gauss–Newton steps and the Laplace posterior of `θ_online` are
/// built from these (`learn::uncertainty`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Linearization {
    pub prediction: Prediction,
    pub residual: [f64; 3],
    /// Row `i` is the gradient of `r_i` with respect to `[com_x, com_y, h]`.
    pub jacobian: [[f64; 3]; 3],
}

/// [`Linearization`] of any kind's pass: one forward pass at `theta` and three backward passes, one
/// per output (the backward passes only read what the forward pass left).
#[inline(always)]
pub(crate) fn linearize<T: Real>(
    pass: &mut impl ThetaPass<T>,
    target: &[T; 3],
    scale: &LossScale,
    theta: &OnlineParams,
) -> Linearization {
    let th = theta_real(theta);
    let output = pass.forward(&th);
    let rows = pass.backward_many(&th, unit_seeds());
    linearization_from(pass, output, target, scale, &th, &rows)
}

/// The three unit output gradients, whose backward passes are the rows of the Jacobian.
#[inline(always)]
fn unit_seeds<T: Real>() -> [[T; 3]; 3] {
    let (o, l) = (T::zero(), T::one());
    [[l, o, o], [o, l, o], [o, o, l]]
}

/// [`Linearization`] from a forward pass's `output` and the backward passes of the unit seeds,
/// `rows[i] = ∂output_i/∂θ`.
#[inline(always)]
fn linearization_from<T: Real>(
    pass: &impl ThetaPass<T>,
    output: [T; 3],
    target: &[T; 3],
    scale: &LossScale,
    th: &[T; 3],
    rows: &[[T; 3]; 3],
) -> Linearization {
    let prediction = pass.prediction(th);
    let sigma = [scale.sigma_pos[0], scale.sigma_pos[1], scale.sigma_rot];
    let mut residual = [0.0; 3];
    let mut jacobian = [[0.0; 3]; 3];
    for i in 0..3 {
        residual[i] = (output[i] - target[i]).as_f64() / sigma[i];
        jacobian[i] = rows[i].map(|d| d.as_f64() / sigma[i]);
    }
    Linearization {
        prediction,
        residual,
        jacobian,
    }
}

/// The rule of [`descend`]'s steps: how far each component moves per unit of gradient, and for how
/// many steps.
#[derive(Clone, Copy)]
pub(crate) struct DescentRule {
    pub scales: [f64; 3],
    pub steps: usize,
    pub lr: f64,
}

/// [`linearize`] and [`descend`] from the same `theta` with one forward pass between them: what an
/// online step that keeps the posterior beside gradient descent needs (`learn::learn_step`). The
/// forward pass at `theta` is deterministic and the backward passes only read it, so both results
/// are bit for bit those of the two functions called one after the other.
#[inline(always)]
pub(crate) fn linearize_and_descend<T: Real, A: MulAdd>(
    pass: &mut impl ThetaPass<T>,
    target: &[T; 3],
    scale: &LossScale,
    theta: &OnlineParams,
    rule: DescentRule,
) -> (Linearization, (Prediction, [f64; 3], OnlineParams)) {
    let th = theta_real(theta);
    let output = pass.forward(&th);
    let weights = loss_weights(scale);
    // The Jacobian's three backward passes and the loss's, taken together.
    let [e0, e1, e2] = unit_seeds();
    let [r0, r1, r2, gradient] =
        pass.backward_many(&th, [e0, e1, e2, loss_gradient(output, target, &weights).1]);
    let linearization = linearization_from(pass, output, target, scale, &th, &[r0, r1, r2]);
    let after = descend_from::<T, A>(pass, target, &weights, th, gradient, rule);
    (
        linearization,
        (
            linearization.prediction,
            gradient.map(|x| x.as_f64()),
            after,
        ),
    )
}

/// The online step of Algorithm 1 with eq. 13 solved by `rule.steps` gradient-descent steps, for any
/// model kind: predicts with `theta`, then descends the loss in `θ_online / scales` (`θ_i ← θ_i − lr · s_i² ·
/// ∂ℓ/∂θ_i`), keeping `h` in [`H_MIN`, `H_MAX`] and the COM offset in ±[`COM_OFFSET_MAX`] (projected
/// gradient descent on the box of physical values). Returns the prediction and gradient at `theta` and the
/// updated parameters.
///
/// One rule for every kind: a step that makes any component non-finite (a degenerate sample, a wild
/// learning rate) is not taken, and the descent stops there with the last finite `θ`.
#[inline(always)]
pub(crate) fn descend<T: Real, A: MulAdd>(
    pass: &mut impl ThetaPass<T>,
    target: &[T; 3],
    weights: &[T; 3],
    theta: &OnlineParams,
    rule: DescentRule,
) -> (Prediction, [f64; 3], OnlineParams) {
    let th = theta_real(theta);
    let output = pass.forward(&th);
    let prediction = pass.prediction(&th);
    let (_, d_output) = loss_gradient(output, target, weights);
    let gradient = pass.backward(&th, d_output);
    let after = descend_from::<T, A>(pass, target, weights, th, gradient, rule);
    (prediction, gradient.map(|x| x.as_f64()), after)
}

/// [`descend`]'s steps from `th`, where the loss's gradient is `gradient`: `θ_online` after them.
#[inline(always)]
fn descend_from<T: Real, A: MulAdd>(
    pass: &mut impl ThetaPass<T>,
    target: &[T; 3],
    weights: &[T; 3],
    mut th: [T; 3],
    gradient: [T; 3],
    rule: DescentRule,
) -> OnlineParams {
    let step = rule.scales.map(|s| T::of(rule.lr * s * s));
    let (h_min, h_max) = (T::of(H_MIN), T::of(H_MAX));
    let com_max = T::of(COM_OFFSET_MAX);
    let mut g = gradient;
    for k in 0..rule.steps {
        if k > 0 {
            let output = pass.forward(&th);
            g = pass.backward(&th, loss_gradient(output, target, weights).1);
        }
        let mut next = th;
        for ((t, gi), si) in next.iter_mut().zip(g).zip(step) {
            *t = A::mul_add(-si, gi, *t);
        }
        // Checked before clamping: `max` would turn a NaN into a bound.
        if !next.iter().all(|t| t.is_finite()) {
            break;
        }
        next[0] = next[0].max(-com_max).min(com_max);
        next[1] = next[1].max(-com_max).min(com_max);
        next[2] = next[2].max(h_min).min(h_max);
        th = next;
    }
    theta_params(&th)
}
