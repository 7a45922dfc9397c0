//! The per-component step sizes of the paper model's online learning: the Gauss–Newton diagonal of
//! the loss at `θ_online(0)` over the offline data.

use super::PaperModel;
use super::batch::BatchPass;
use crate::model::Sample;
use crate::model::kernel::{CurvatureTerms, RealSample, curvature_sum, loss_weights, theta_real};
use crate::model::mlp::{BATCH, HIDDEN, OUTPUTS};
use crate::model::tail::TailPass;
use crate::real::Real;
use crate::simd::MulAdd;

impl<T: Real> PaperModel<T> {
    /// Sets [`PaperModel::theta_scales`] from the Gauss–Newton diagonal of the loss at `θ_online(0)`
    /// over `samples`: `s_i = 1 / sqrt(mean_samples Σ_k 2 w_k (∂ŷ_k/∂θ_i)²)`.
    pub fn calibrate_theta_scales(&mut self, samples: &[Sample]) {
        if samples.is_empty() {
            return;
        }
        let curvature = self.theta_curvature(samples);
        let fallback = self.normalization.position.scale();
        self.theta_scales = scales_from_curvature(curvature, samples.len(), fallback);
    }

    /// `Σ_samples Σ_k 2 w_k (∂ŷ_k/∂θ_i)²` at `θ_online(0)`, the later samples' terms on the
    /// machine's other cores ([`curvature_sum`]: the same bits, four tenths of a one-epoch training
    /// halved on two).
    fn theta_curvature(&self, samples: &[Sample]) -> [f64; 3]
    where
        T: Sync,
    {
        curvature_sum(samples, |part, each| self.theta_curvature_terms(part, each))
    }

    crate::simd::dispatch_simd! {
        /// Each sample's terms of [`PaperModel::theta_curvature`], handed to `each` in sample order,
        /// in the widest SIMD available.
        fn theta_curvature_terms(&self, samples: &[Sample], each: &mut dyn FnMut(CurvatureTerms)) -> ()
            => theta_curvature_terms_portable, theta_curvature_terms_avx2
    }

    #[inline(always)]
    pub(super) fn theta_curvature_terms_portable<A: MulAdd>(
        &self,
        samples: &[Sample],
        each: &mut dyn FnMut(CurvatureTerms),
    ) {
        let weights = loss_weights::<T>(&self.loss_scale);
        let theta = theta_real(&self.theta0);
        let mut batch = Box::<BatchPass<T>>::default();
        let mut tangents = Box::new([[[T::zero(); HIDDEN]; 2]; BATCH]);
        let mut jacobians = Box::new([[[T::zero(); OUTPUTS]; 2]; BATCH]);
        let mut tail = TailPass::default();
        for chunk in samples.chunks(BATCH) {
            let inputs: Vec<RealSample<T>> = chunk.iter().map(RealSample::of).collect();
            let n = self.batch_inputs::<A>(
                inputs.iter().map(|s| &s.input),
                &theta,
                &mut batch.activations,
            );
            self.network
                .forward_batch::<A>(n, &mut batch.activations, &mut batch.output);
            // The network's Jacobian with respect to its position inputs (forward mode), then one
            // cheap backward pass through the tail per output.
            self.network.position_jacobian_batch::<A>(
                n,
                &batch.activations,
                &mut tangents,
                &mut jacobians,
            );
            for (z, [ja, jb]) in batch.output[..n].iter().zip(&*jacobians) {
                let (contact, contact_motion) = self.contact_of::<A>(z);
                tail.forward::<A>(contact, contact_motion, &theta);
                let mut terms = [[0.0f64; 3]; 3];
                for ((k, w), terms) in weights.iter().enumerate().zip(&mut terms) {
                    let mut d_output = [T::zero(); 3];
                    d_output[k] = T::one();
                    let d_tail = tail.backward::<A>(&theta, d_output);
                    let d_z = self.contact_gradient(d_tail.contact, d_tail.contact_motion);
                    let d_x = [
                        A::mul_add(d_z[0], ja[0], d_z[1] * ja[1])
                            + A::mul_add(d_z[2], ja[2], d_z[3] * ja[3]),
                        A::mul_add(d_z[0], jb[0], d_z[1] * jb[1])
                            + A::mul_add(d_z[2], jb[2], d_z[3] * jb[3]),
                    ];
                    let row = self.theta_gradient::<A>(d_x, d_tail.com_offset, d_tail.h);
                    *terms = row.map(|j| 2.0 * w.as_f64() * j.as_f64() * j.as_f64());
                }
                each(terms);
            }
        }
    }
}

/// `s_i = 1 / sqrt(curvature_i / count)`, or `fallback` where the curvature is zero or not finite.
pub(crate) fn scales_from_curvature(curvature: [f64; 3], count: usize, fallback: f64) -> [f64; 3] {
    curvature.map(|c| {
        let mean = c / count.max(1) as f64;
        if mean.is_finite() && mean > 0.0 {
            1.0 / mean.sqrt()
        } else {
            fallback
        }
    })
}

#[cfg(test)]
mod tests {
    use super::super::pass::tests::{model_f64, relative_error, sample};
    use super::*;
    use crate::model::kernel::add_curvature_terms;
    use crate::model::paper::Pass;
    use crate::rng::SplitMix64;
    use crate::simd::Unfused;

    #[test]
    fn theta_curvature_matches_reverse_mode_jacobians() {
        // The calibration's forward-mode Jacobian against one backward pass per output.
        let model = model_f64(7);
        let samples = varied(20, 9);
        let weights = loss_weights::<f64>(&model.loss_scale);
        let theta = theta_real::<f64>(&model.theta0);
        let mut expected = [0.0; 3];
        let mut pass = Pass::default();
        for sample in &samples {
            let real = RealSample::<f64>::of(sample);
            model.forward(&real.input, &theta, &mut pass);
            for (k, w) in weights.iter().enumerate() {
                let mut d_output = [0.0; 3];
                d_output[k] = 1.0;
                let row = model.backward_with::<Unfused>(&pass, &theta, d_output, None);
                for (e, j) in expected.iter_mut().zip(row) {
                    *e += 2.0 * w * j * j;
                }
            }
        }
        let curvature =
            added_here(|each| model.theta_curvature_terms_portable::<Unfused>(&samples, each));
        for (a, b) in curvature.iter().zip(expected) {
            assert!(b > 0.0 && relative_error(*a, b) <= 1e-12, "{a} vs {b}");
        }
    }

    /// `count` pushes around the test sample, the pusher moved about at random (`seed`).
    fn varied(count: usize, seed: u64) -> Vec<Sample> {
        let mut rng = SplitMix64::new(seed);
        (0..count)
            .map(|frame| {
                let mut s = sample();
                s.input.robot_in_object[0] += 0.02 * rng.normal();
                s.input.robot_in_object[1] += 0.05 * rng.normal();
                s.frame = frame;
                s
            })
            .collect()
    }

    /// The terms a pass hands over, added on this thread alone by sample, output and component.
    fn added_here(pass: impl FnOnce(&mut dyn FnMut(CurvatureTerms))) -> [f64; 3] {
        let mut curvature = [0.0; 3];
        pass(&mut |terms| add_curvature_terms(&mut curvature, terms));
        curvature
    }

    #[test]
    fn theta_curvature_on_several_cores_keeps_the_bits_of_one() {
        // Enough samples to be shared between threads where there are cores.
        let model = model_f64(7);
        let samples = varied(2 * crate::parallel::SAMPLES_PER_WORKER + 5, 10);
        let shared = model.theta_curvature(&samples);
        // The dispatched terms, as `theta_curvature` takes them, all added here.
        let serial = added_here(|each| model.theta_curvature_terms(&samples, each));
        assert_eq!(shared.map(f64::to_bits), serial.map(f64::to_bits));
    }
}
