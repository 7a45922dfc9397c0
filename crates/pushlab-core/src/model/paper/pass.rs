//! The paper model's single-sample forward and backward pass, and its online step.

use super::{PaperModel, Prepared};
use crate::model::Prediction;
use crate::model::kernel::{
    DescentRule, Linearization, RealSample, ThetaPass, descend, linearize, loss_weights,
};
use crate::model::mlp::{Activations, Mlp, OUTPUTS};
use crate::model::params::OnlineParams;
use crate::model::tail::{TailGradient, TailPass};
use crate::real::Real;
use crate::simd::{MulAdd, Unfused};

/// Everything one forward pass computes that its backward pass needs.
#[derive(Clone, Debug)]
pub(crate) struct Pass<T> {
    activations: Activations<T>,
    pub tail: TailPass<T>,
}

impl<T: Real> Default for Pass<T> {
    fn default() -> Self {
        Self {
            activations: Activations::default(),
            tail: TailPass::default(),
        }
    }
}

impl<T: Real> PaperModel<T> {
    /// The forward pass in the model's float type. `theta` is `[com_x, com_y, h]`.
    #[inline(always)]
    pub(crate) fn forward(&self, input: &[T; 4], theta: &[T; 3], pass: &mut Pass<T>) -> [T; 3] {
        self.forward_with::<Unfused>(input, theta, pass)
    }

    /// [`PaperModel::forward`] with the multiply-add of the compiled copy.
    #[inline(always)]
    pub(crate) fn forward_with<A: MulAdd>(
        &self,
        input: &[T; 4],
        theta: &[T; 3],
        pass: &mut Pass<T>,
    ) -> [T; 3] {
        let prepared = self.prepare::<A>(input);
        self.forward_prepared::<A>(&prepared, theta, pass)
    }

    /// The forward pass from a prepared input.
    #[inline(always)]
    pub(crate) fn forward_prepared<A: MulAdd>(
        &self,
        prepared: &Prepared<T>,
        theta: &[T; 3],
        pass: &mut Pass<T>,
    ) -> [T; 3] {
        let x = self.network_input::<A>(prepared.position, prepared.motion, theta);
        let z = self
            .network
            .forward_from::<A>(&prepared.context_part, &x, &mut pass.activations);
        let (contact, contact_motion) = self.contact_of::<A>(&z);
        pass.tail.forward::<A>(contact, contact_motion, theta);
        pass.tail.output()
    }

    /// The backward pass: from the gradient of a scalar with respect to the predicted
    /// `[Δp_x, Δp_y, Δω]`, the gradient with respect to `θ_online`, and, when `network_grad` is given,
    /// the gradient with respect to the network's weights added to it.
    #[inline(always)]
    pub(crate) fn backward_with<A: MulAdd>(
        &self,
        pass: &Pass<T>,
        theta: &[T; 3],
        d_output: [T; 3],
        network_grad: Option<&mut Mlp<T>>,
    ) -> [T; 3] {
        let d_tail = pass.tail.backward::<A>(theta, d_output);
        let d_z = self.contact_gradient(d_tail.contact, d_tail.contact_motion);
        let d_x =
            self.network
                .position_and_weight_gradient::<A>(&pass.activations, &d_z, network_grad);
        self.theta_gradient::<A>(d_x, d_tail.com_offset, d_tail.h)
    }

    /// [`PaperModel::backward_with`] without weights for several `d_output` after the same forward
    /// pass, the network's part taken for all of them at once (`Network::position_gradients`):
    /// each result is the same numbers as its own backward pass.
    #[inline(always)]
    pub(crate) fn backward_many<A: MulAdd, const N: usize>(
        &self,
        pass: &Pass<T>,
        theta: &[T; 3],
        d_outputs: [[T; 3]; N],
    ) -> [[T; 3]; N] {
        let mut d_tails = [TailGradient::default(); N];
        let mut d_z = [[T::zero(); OUTPUTS]; N];
        for ((t, z), d) in d_tails.iter_mut().zip(&mut d_z).zip(d_outputs) {
            *t = pass.tail.backward::<A>(theta, d);
            *z = self.contact_gradient(t.contact, t.contact_motion);
        }
        let d_x = self
            .network
            .position_gradients::<A, N>(&pass.activations, &d_z);
        let mut gradients = [[T::zero(); 3]; N];
        for ((g, t), d) in gradients.iter_mut().zip(d_tails).zip(d_x) {
            *g = self.theta_gradient::<A>(d, t.com_offset, t.h);
        }
        gradients
    }

    crate::simd::dispatch_simd! {
        /// One online update (Algorithm 1 with eq. 13 solved by `steps` gradient-descent steps, see
        /// [`descend`]) with this model's step scales. Runs entirely in the model's float type and
        /// allocates nothing.
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
        let weights = loss_weights(&self.loss_scale);
        // Everything that does not depend on θ_online, once for all the gradient steps.
        let mut pass = OnlinePass::<T, A> {
            model: self,
            prepared: self.prepare::<A>(&sample.input),
            pass: Pass::default(),
            multiply_add: std::marker::PhantomData,
        };
        descend::<T, A>(
            &mut pass,
            &sample.target,
            &weights,
            theta,
            DescentRule {
                scales: self.theta_scales,
                steps,
                lr,
            },
        )
    }
}

impl<T: Real> PaperModel<T> {
    crate::simd::dispatch_simd! {
        /// The sample's normalised residual and its Jacobian with respect to `θ_online` at `theta`
        /// (see [`linearize`]).
        pub(crate) fn linearize(&self, sample: &RealSample<T>, theta: &OnlineParams) -> Linearization
            => linearize_portable, linearize_avx2
    }

    #[inline(always)]
    fn linearize_portable<A: MulAdd>(
        &self,
        sample: &RealSample<T>,
        theta: &OnlineParams,
    ) -> Linearization {
        let mut pass = OnlinePass::<T, A> {
            model: self,
            prepared: self.prepare::<A>(&sample.input),
            pass: Pass::default(),
            multiply_add: std::marker::PhantomData,
        };
        linearize(&mut pass, &sample.target, &self.loss_scale, theta)
    }
}

/// One prepared sample of the paper model, as the shared online step sees it.
struct OnlinePass<'a, T: Real, A> {
    model: &'a PaperModel<T>,
    prepared: Prepared<T>,
    pass: Pass<T>,
    multiply_add: std::marker::PhantomData<A>,
}

impl<T: Real, A: MulAdd> ThetaPass<T> for OnlinePass<'_, T, A> {
    #[inline(always)]
    fn forward(&mut self, theta: &[T; 3]) -> [T; 3] {
        self.model
            .forward_prepared::<A>(&self.prepared, theta, &mut self.pass)
    }

    #[inline(always)]
    fn backward(&mut self, theta: &[T; 3], d_output: [T; 3]) -> [T; 3] {
        self.model
            .backward_with::<A>(&self.pass, theta, d_output, None)
    }

    #[inline(always)]
    fn backward_many<const N: usize>(
        &mut self,
        theta: &[T; 3],
        d_outputs: [[T; 3]; N],
    ) -> [[T; 3]; N] {
        self.model
            .backward_many::<A, N>(&self.pass, theta, d_outputs)
    }

    #[inline(always)]
    fn prediction(&self, theta: &[T; 3]) -> Prediction {
        self.pass.tail.prediction(theta)
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::model::LossScale;
    use crate::model::kernel::{loss_gradient, theta_real};
    use crate::model::mlp::Network;
    use crate::model::normalization::{InputNormalization, Stats2};
    use crate::model::{ObjectMotion, Sample, SampleInput};
    use crate::rng::SplitMix64;

    /// A random model in f64 with plausible normalisation for a 0.3 m box pushed by a 0.05 m disc.
    pub fn model_f64(seed: u64) -> PaperModel<f64> {
        let mut rng = SplitMix64::new(seed);
        PaperModel::from_parts(
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

    pub fn sample() -> Sample {
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
    fn loss_of(model: &PaperModel<f64>, theta: &[f64; 3]) -> f64 {
        let s = RealSample::<f64>::of(&sample());
        let mut pass = Pass::default();
        let output = model.forward(&s.input, theta, &mut pass);
        loss_gradient(output, &s.target, &loss_weights(&model.loss_scale)).0
    }

    #[test]
    fn backward_passes_taken_together_give_the_bits_of_each_alone() {
        use crate::simd::Fused;
        for seed in [1, 2, 3] {
            let model = model_f64(seed).cast::<f32>();
            let s = RealSample::<f32>::of(&sample());
            let theta = [0.012, -0.018, 0.07];
            let mut pass = Pass::default();
            model.forward_with::<Fused>(&s.input, &theta, &mut pass);
            let seeds = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
            let together = model.backward_many::<Fused, 3>(&pass, &theta, seeds);
            for (d, g) in seeds.into_iter().zip(together) {
                let alone = model.backward_with::<Fused>(&pass, &theta, d, None);
                assert_eq!(g.map(f32::to_bits), alone.map(f32::to_bits), "seed {seed}");
                assert!(
                    g.iter().any(|x| *x != 0.0),
                    "seed {seed}, {d:?}: a gradient"
                );
            }
        }
    }

    pub fn relative_error(a: f64, b: f64) -> f64 {
        (a - b).abs() / a.abs().max(b.abs()).max(1e-12)
    }

    #[test]
    fn gradients_of_weights_and_theta_match_central_differences() {
        for seed in [1, 2, 3] {
            let model = model_f64(seed);
            let theta = [0.012, -0.018, 0.07];
            let s = RealSample::<f64>::of(&sample());
            let mut pass = Pass::default();
            let output = model.forward(&s.input, &theta, &mut pass);
            let (_, d_output) = loss_gradient(output, &s.target, &loss_weights(&model.loss_scale));
            let mut grad = Mlp::zeros();
            let g_theta = model.backward_with::<Unfused>(&pass, &theta, d_output, Some(&mut grad));

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
        // A huge learning rate can push h anywhere; it must stay in range and finite.
        for lr in [10.0, 1e6, 1e300] {
            let (_, _, wild) = model.online_update(&real, &theta, 5, lr);
            assert!((crate::model::H_MIN..=crate::model::H_MAX).contains(&wild.h));
            assert!(wild.com_offset.iter().all(|c| c.is_finite()), "lr {lr}");
        }
    }

    #[test]
    fn f32_and_f64_models_agree() {
        let model = model_f64(5);
        let single: PaperModel<f32> = model.cast();
        let theta = model.theta0();
        let a = model.predict(&sample().input, &theta);
        let b = single.predict(&sample().input, &theta);
        assert!((a.motion.translation[0] - b.motion.translation[0]).abs() < 1e-6);
        assert!((a.motion.rotation - b.motion.rotation).abs() < 1e-5);
    }
}
