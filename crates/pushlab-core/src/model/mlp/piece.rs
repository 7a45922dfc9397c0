//! The network's affine piece around one input: what an online step needs of the network.
//!
//! A ReLU network is affine wherever none of its hidden units changes sign: around an input `x*`,
//! `z(x) = z(x*) + J (x − x*)` as long as every pre-activation keeps its sign. Online learning moves
//! only the two position inputs (through `θ_online`), and the five gradient steps of one online step
//! move them by little, so the units rarely change sign between them.
//!
//! Why: an online step ran the whole network forward and back at each of its five steps, the
//! backward pass only to get `Jᵀ d_z` for two inputs. Now it runs the network forward once, takes
//! `J`'s two columns forward through the layers (each hidden layer's slope too, so that a later
//! input can be checked), and each later step costs three 16 × 2 multiply-adds to check the 48
//! signs, an affine output and a 4 × 2 product for the gradient. Where a sign changes, the step runs
//! the network again and takes the piece there. The outputs are the network's — at the anchor, to
//! the bit — and the gradient is the exact derivative of the piece (not the same rounding as a
//! backward pass).

use super::layers::{relu_backward, sum_of_columns};
use super::{HIDDEN, Network, OUTPUTS};
use crate::real::Real;
use crate::simd::MulAdd;

/// The network around one input: its outputs there and their slopes in the two position inputs, and
/// the hidden layers' pre-activations and slopes, which decide where the piece ends.
#[derive(Clone, Debug)]
pub(crate) struct AffinePiece<T> {
    /// The position inputs `x*` the piece was taken at.
    anchor: [T; 2],
    /// The hidden layers' pre-activations at the anchor.
    pre: [[T; HIDDEN]; 3],
    /// `slopes[l][k] = ∂pre_l/∂x_k` on the piece.
    slopes: [[[T; HIDDEN]; 2]; 3],
    /// The outputs at the anchor.
    output: [T; OUTPUTS],
    /// `jacobian[k] = ∂z/∂x_k` on the piece.
    jacobian: [[T; OUTPUTS]; 2],
}

impl<T: Real, const I: usize> Network<T, I> {
    /// The piece of the network around `input`, whose share of the first layer without the position
    /// inputs is `context_part` ([`Network::first_layer_context`]); its outputs at `input` are
    /// [`Network::forward_from`]'s, to the bit.
    #[inline(always)]
    pub(crate) fn piece_at<A: MulAdd>(
        &self,
        context_part: &[T; HIDDEN],
        input: &[T; I],
    ) -> AffinePiece<T> {
        let p = &self.params;
        let ([pre1, pre2, pre3], output) = self.pre_activations::<A>(context_part, input);
        // The slopes, forward through the active units (ReLU's gradient rule: `pre > 0`): both columns of a layer before the next, so
        // that their chains of multiply-adds overlap. (Plain loops, not closures, which might not be
        // inlined into the caller's AVX2 + FMA copy.)
        let s1 = [p.w1[0], p.w1[1]];
        let mut s2 = [[T::zero(); HIDDEN]; 2];
        for k in 0..2 {
            s2[k] = sum_of_columns::<T, A, HIDDEN, HIDDEN>(&p.w2, &relu_backward(&pre1, &s1[k]));
        }
        let mut s3 = [[T::zero(); HIDDEN]; 2];
        for k in 0..2 {
            s3[k] = sum_of_columns::<T, A, HIDDEN, HIDDEN>(&p.w3, &relu_backward(&pre2, &s2[k]));
        }
        let mut jacobian = [[T::zero(); OUTPUTS]; 2];
        for k in 0..2 {
            jacobian[k] =
                sum_of_columns::<T, A, HIDDEN, OUTPUTS>(&p.w4, &relu_backward(&pre3, &s3[k]));
        }
        AffinePiece {
            anchor: [input[0], input[1]],
            pre: [pre1, pre2, pre3],
            slopes: [s1, s2, s3],
            output,
            jacobian,
        }
    }
}

impl<T: Real> AffinePiece<T> {
    /// The network's outputs at the position inputs `position` (the other inputs those of the
    /// anchor), or `None` where a hidden unit's sign differs from the anchor's: off the piece.
    #[inline(always)]
    pub(crate) fn output_at<A: MulAdd>(&self, position: [T; 2]) -> Option<[T; OUTPUTS]> {
        let d = [position[0] - self.anchor[0], position[1] - self.anchor[1]];
        let mut same_signs = true;
        for (pre, [s0, s1]) in self.pre.iter().zip(&self.slopes) {
            for j in 0..HIDDEN {
                let moved = A::mul_add(s1[j], d[1], A::mul_add(s0[j], d[0], pre[j]));
                // Without a branch, so that the 16 lanes are compared at once.
                same_signs &= (moved > T::zero()) == (pre[j] > T::zero());
            }
        }
        if !same_signs {
            return None;
        }
        let [j0, j1] = &self.jacobian;
        let mut z = self.output;
        for i in 0..OUTPUTS {
            z[i] = A::mul_add(j1[i], d[1], A::mul_add(j0[i], d[0], z[i]));
        }
        Some(z)
    }

    /// The outputs at the anchor.
    #[inline(always)]
    pub(crate) fn output(&self) -> [T; OUTPUTS] {
        self.output
    }

    /// The gradient with respect to the two position inputs of a scalar whose gradient with respect
    /// to the outputs is `d_output`: `Jᵀ d_output`.
    #[inline(always)]
    pub(crate) fn position_gradient<A: MulAdd>(&self, d_output: &[T; OUTPUTS]) -> [T; 2] {
        let mut gradient = [T::zero(); 2];
        for (g, column) in gradient.iter_mut().zip(&self.jacobian) {
            *g = column[0] * d_output[0];
            for i in 1..OUTPUTS {
                *g = A::mul_add(column[i], d_output[i], *g);
            }
        }
        gradient
    }
}
