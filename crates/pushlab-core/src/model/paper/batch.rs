//! Offline training's hot loop for the paper model: a batch of samples one network layer at a time.

use super::PaperModel;
use crate::model::kernel::{RealSample, loss_gradient};
use crate::model::mlp::{BATCH, BatchActivations, HIDDEN, Mlp, OUTPUTS};
use crate::model::tail::TailPass;
use crate::real::Real;
use crate::simd::MulAdd;

/// Scratch space of [`PaperModel::accumulate_batch`]: a batch's activations and gradients.
#[derive(Clone, Debug)]
pub(crate) struct BatchPass<T> {
    pub(super) activations: BatchActivations<T>,
    pub(super) output: [[T; OUTPUTS]; BATCH],
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

impl<T: Real> PaperModel<T> {
    /// The network's inputs of a batch of samples at `theta`.
    #[inline(always)]
    pub(super) fn batch_inputs<'a, A: MulAdd>(
        &self,
        inputs: impl Iterator<Item = &'a [T; 4]>,
        theta: &[T; 3],
        batch: &mut BatchActivations<T>,
    ) -> usize {
        let mut n = 0;
        for (x, input) in batch.input.iter_mut().zip(inputs) {
            let (position, motion) = self.normalized(input);
            *x = self.network_input::<A>(position, motion, theta);
            n += 1;
        }
        n
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
        let indices = &indices[..indices.len().min(BATCH)];
        let n = self.batch_inputs::<A>(
            indices.iter().map(|&i| &samples[i].input),
            theta,
            &mut batch.activations,
        );
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
            let mut tail = TailPass::default();
            let (contact, contact_motion) = self.contact_of::<A>(z);
            tail.forward::<A>(contact, contact_motion, theta);
            let (l, d_output) = loss_gradient(tail.output(), &samples[i].target, weights);
            loss = loss + l;
            let d_tail = tail.backward::<A>(theta, d_output);
            *d_z = self.contact_gradient(d_tail.contact, d_tail.contact_motion);
            *d_theta = [d_tail.com_offset[0], d_tail.com_offset[1], d_tail.h];
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
                let g = self.theta_gradient::<A>(d_x, [d_theta[0], d_theta[1]], d_theta[2]);
                for (acc, gi) in total.iter_mut().zip(g) {
                    *acc += gi.as_f64();
                }
            }
        }
        loss
    }
}

#[cfg(test)]
mod tests {
    use super::super::pass::tests::{model_f64, sample};
    use super::*;
    use crate::model::Sample;
    use crate::model::kernel::loss_weights;
    use crate::model::paper::Pass;
    use crate::rng::SplitMix64;
    use crate::simd::{Fused, Unfused};

    /// Samples around `sample()`, varied so that different ReLUs are active.
    pub fn varied_samples(count: usize) -> Vec<Sample> {
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
            let output = model.forward(&samples[i].input, &theta, &mut pass);
            let (loss, d_output) = loss_gradient(output, &samples[i].target, &weights);
            let g =
                model.backward_with::<Unfused>(&pass, &theta, d_output, Some(&mut expected_grad));
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
                    model.accumulate_batch::<Fused>(
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
}
