//! The network's batch passes for offline training and calibration: each layer for up to [`BATCH`]
//! samples before the next. The samples of a layer are independent, so the CPU overlaps their
//! dependency chains instead of waiting on each sample's; every sum keeps the single-sample passes'
//! order, so a batch gives the same bits as its samples one by one.

use super::layers::{
    accumulate_outer_batch, axpy, back_through, dense, dot, relu, relu_backward, sum_of_columns,
};
use super::{HIDDEN, INPUTS, Mlp, Network, OUTPUTS, first_layer_context_part};
use crate::real::Real;
use crate::simd::MulAdd;

/// The most samples [`Network::forward_batch`] and [`Network::backward_batch`] take at once: the
/// paper's batch size. Larger batches are processed in chunks of this size.
pub(crate) const BATCH: usize = 32;

/// [`Activations`](super::Activations) of up to [`BATCH`] samples, layer by layer (6.6 kB for `f32`).
#[derive(Clone, Debug)]
pub(crate) struct BatchActivations<T, const I: usize = INPUTS> {
    pub input: [[T; I]; BATCH],
    hidden1: [[T; HIDDEN]; BATCH],
    hidden2: [[T; HIDDEN]; BATCH],
    hidden3: [[T; HIDDEN]; BATCH],
}

impl<T: Real, const I: usize> Default for BatchActivations<T, I> {
    fn default() -> Self {
        let z = T::zero();
        Self {
            input: [[z; I]; BATCH],
            hidden1: [[z; HIDDEN]; BATCH],
            hidden2: [[z; HIDDEN]; BATCH],
            hidden3: [[z; HIDDEN]; BATCH],
        }
    }
}

impl<T: Real, const I: usize> Network<T, I> {
    /// The forward pass of the first `n` samples of `act.input` (at most [`BATCH`]), one layer for
    /// all samples before the next.
    #[inline(always)]
    pub(crate) fn forward_batch<A: MulAdd>(
        &self,
        n: usize,
        act: &mut BatchActivations<T, I>,
        output: &mut [[T; OUTPUTS]; BATCH],
    ) {
        self.forward_batch_with::<A, A>(n, act, output);
    }

    /// [`Network::forward_batch`] with the context's share of the first layer
    /// ([`Network::first_layer_context`]) summed with the multiply-add `C`: the contact kind's
    /// training computes that share unfused, as its per-sample pass and online learning do.
    #[inline(always)]
    pub(crate) fn forward_batch_with<A: MulAdd, C: MulAdd>(
        &self,
        n: usize,
        act: &mut BatchActivations<T, I>,
        output: &mut [[T; OUTPUTS]; BATCH],
    ) {
        let p = &self.params;
        let n = n.min(BATCH);
        for (x, h) in act.input[..n].iter().zip(&mut act.hidden1[..n]) {
            let mut z = first_layer_context_part::<T, C, I>(p, x);
            axpy::<T, A, HIDDEN>(&mut z, &p.w1[0], x[0]);
            axpy::<T, A, HIDDEN>(&mut z, &p.w1[1], x[1]);
            *h = relu(z);
        }
        for (x, h) in act.hidden1[..n].iter().zip(&mut act.hidden2[..n]) {
            *h = relu(dense::<T, A, HIDDEN, HIDDEN>(&p.w2, &p.b2, x));
        }
        for (x, h) in act.hidden2[..n].iter().zip(&mut act.hidden3[..n]) {
            *h = relu(dense::<T, A, HIDDEN, HIDDEN>(&p.w3, &p.b3, x));
        }
        for (x, y) in act.hidden3[..n].iter().zip(&mut output[..n]) {
            *y = dense::<T, A, HIDDEN, OUTPUTS>(&p.w4, &p.b4, x);
        }
    }

    /// The backward pass of the first `n` samples of a [`Network::forward_batch`]: adds the gradient
    /// of every weight and bias (summed over the samples, in sample order) to `grad`, and leaves the
    /// gradient with respect to each sample's first-layer pre-activation in `d1` (for
    /// [`Network::first_layer_input_gradient`]).
    #[inline(always)]
    pub(crate) fn backward_batch<A: MulAdd>(
        &self,
        n: usize,
        act: &BatchActivations<T, I>,
        d_output: &[[T; OUTPUTS]; BATCH],
        grad: &mut Mlp<T, I>,
        d1: &mut [[T; HIDDEN]; BATCH],
    ) {
        let n = n.min(BATCH);
        let mut d3 = [[T::zero(); HIDDEN]; BATCH];
        let mut d2 = [[T::zero(); HIDDEN]; BATCH];
        for ((d, a), dz) in d3[..n].iter_mut().zip(&act.hidden3).zip(d_output) {
            *d = relu_backward(a, &back_through::<T, A, _, _>(&self.wt4, dz));
        }
        for ((d, a), dz) in d2[..n].iter_mut().zip(&act.hidden2).zip(&d3) {
            *d = relu_backward(a, &back_through::<T, A, _, _>(&self.wt3, dz));
        }
        for ((d, a), dz) in d1[..n].iter_mut().zip(&act.hidden1).zip(&d2) {
            *d = relu_backward(a, &back_through::<T, A, _, _>(&self.wt2, dz));
        }
        accumulate_outer_batch::<T, A, _, _>(
            &mut grad.w4,
            &mut grad.b4,
            &act.hidden3[..n],
            &d_output[..n],
        );
        accumulate_outer_batch::<T, A, _, _>(
            &mut grad.w3,
            &mut grad.b3,
            &act.hidden2[..n],
            &d3[..n],
        );
        accumulate_outer_batch::<T, A, _, _>(
            &mut grad.w2,
            &mut grad.b2,
            &act.hidden1[..n],
            &d2[..n],
        );
        accumulate_outer_batch::<T, A, _, _>(&mut grad.w1, &mut grad.b1, &act.input[..n], &d1[..n]);
    }

    /// The gradient with respect to the position inputs (0 and 1, where `θ_online` enters) of the
    /// first `n` samples of a [`Network::forward_batch`], given each sample's output gradient;
    /// weights are left alone. The per-sample [`Network::position_gradient`] layer by layer.
    #[inline(always)]
    pub(crate) fn position_gradient_batch<A: MulAdd>(
        &self,
        n: usize,
        act: &BatchActivations<T, I>,
        d_output: &[[T; OUTPUTS]; BATCH],
        d_position: &mut [[T; 2]; BATCH],
    ) {
        let n = n.min(BATCH);
        let mut d3 = [[T::zero(); HIDDEN]; BATCH];
        let mut d2 = [[T::zero(); HIDDEN]; BATCH];
        for ((d, a), dz) in d3[..n].iter_mut().zip(&act.hidden3).zip(d_output) {
            *d = relu_backward(a, &back_through::<T, A, _, _>(&self.wt4, dz));
        }
        for ((d, a), dz) in d2[..n].iter_mut().zip(&act.hidden2).zip(&d3) {
            *d = relu_backward(a, &back_through::<T, A, _, _>(&self.wt3, dz));
        }
        let mut d1 = [[T::zero(); HIDDEN]; BATCH];
        for ((d, a), dz) in d1[..n].iter_mut().zip(&act.hidden1).zip(&d2) {
            *d = relu_backward(a, &back_through::<T, A, _, _>(&self.wt2, dz));
        }
        for (dx, d1) in d_position[..n].iter_mut().zip(&d1) {
            *dx = [
                dot::<T, A>(&self.params.w1[0], d1),
                dot::<T, A>(&self.params.w1[1], d1),
            ];
        }
    }
}

impl<T: Real, const I: usize> Network<T, I> {
    /// `∂output/∂input[0]` and `∂output/∂input[1]` (the position inputs) for each of the first `n`
    /// samples of a [`Network::forward_batch`], by forward-mode differentiation: two tangents per
    /// sample pushed through the layers, one layer for all samples at a time. Cheaper than a backward
    /// pass per output, and the tangents are independent dependency chains. `tangents` is scratch
    /// space.
    #[inline(always)]
    pub(crate) fn position_jacobian_batch<A: MulAdd>(
        &self,
        n: usize,
        act: &BatchActivations<T, I>,
        tangents: &mut [[[T; HIDDEN]; 2]; BATCH],
        jacobian: &mut [[[T; OUTPUTS]; 2]; BATCH],
    ) {
        let p = &self.params;
        let n = n.min(BATCH);
        for (t, a) in tangents[..n].iter_mut().zip(&act.hidden1) {
            t[0] = relu_backward(a, &p.w1[0]);
            t[1] = relu_backward(a, &p.w1[1]);
        }
        for (t, a) in tangents[..n].iter_mut().zip(&act.hidden2) {
            t[0] = relu_backward(a, &sum_of_columns::<T, A, HIDDEN, HIDDEN>(&p.w2, &t[0]));
            t[1] = relu_backward(a, &sum_of_columns::<T, A, HIDDEN, HIDDEN>(&p.w2, &t[1]));
        }
        for (t, a) in tangents[..n].iter_mut().zip(&act.hidden3) {
            t[0] = relu_backward(a, &sum_of_columns::<T, A, HIDDEN, HIDDEN>(&p.w3, &t[0]));
            t[1] = relu_backward(a, &sum_of_columns::<T, A, HIDDEN, HIDDEN>(&p.w3, &t[1]));
        }
        for (j, t) in jacobian[..n].iter_mut().zip(&*tangents) {
            j[0] = sum_of_columns::<T, A, HIDDEN, OUTPUTS>(&p.w4, &t[0]);
            j[1] = sum_of_columns::<T, A, HIDDEN, OUTPUTS>(&p.w4, &t[1]);
        }
    }
}
