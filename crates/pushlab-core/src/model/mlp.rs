//! The paper's small MLP φ: I → 16 → 16 → 16 → 4, ReLU after each hidden layer, linear output. The
//! paper's network and the pure-network baseline have four inputs; the contact-frame model has six.
//!
//! The first two inputs are where `θ_online` enters (the COM-relative pusher or contact position); the
//! others — the *context* — do not depend on it, so online learning computes their share of the first
//! layer once per online step ([`Network::first_layer_context`]).
//!
//! Written by hand on fixed-size arrays rather than with a tensor library: for a network this small
//! per-operation overhead dominates (PyTorch needs ~3 ms per online step on this model; this needs well
//! under a microsecond). Weights are stored column by column (`w[input][output]`) so that the forward
//! pass is a sequence of 16-wide multiply-adds that the compiler vectorises, and nothing allocates.

use serde::{Deserialize, Serialize};

use crate::real::Real;
use crate::rng::SplitMix64;
use crate::simd::{MulAdd, Unfused};

mod batch;
mod layers;
mod piece;
mod shape;
pub(crate) use self::batch::{BATCH, BatchActivations};
use self::layers::{accumulate_outer, axpy, back_through, dense, dot, relu, relu_backward};
pub(crate) use self::piece::AffinePiece;
pub use self::shape::{HIDDEN, INPUTS, OUTPUTS, PARAMETER_COUNT, parameter_count};

/// Weights and biases of the MLP. Also used for same-shaped quantities: gradients, Adam's moments.
#[derive(Clone, Debug, PartialEq)]
pub struct Mlp<T, const I: usize = INPUTS> {
    w1: [[T; HIDDEN]; I],
    b1: [T; HIDDEN],
    w2: [[T; HIDDEN]; HIDDEN],
    b2: [T; HIDDEN],
    w3: [[T; HIDDEN]; HIDDEN],
    b3: [T; HIDDEN],
    w4: [[T; OUTPUTS]; HIDDEN],
    b4: [T; OUTPUTS],
}

/// What the forward pass keeps for the backward pass: the input and each hidden layer after ReLU.
#[derive(Clone, Debug)]
pub struct Activations<T, const I: usize = INPUTS> {
    input: [T; I],
    hidden1: [T; HIDDEN],
    hidden2: [T; HIDDEN],
    hidden3: [T; HIDDEN],
}

impl<T: Real, const I: usize> Default for Activations<T, I> {
    fn default() -> Self {
        let z = T::zero();
        Self {
            input: [z; I],
            hidden1: [z; HIDDEN],
            hidden2: [z; HIDDEN],
            hidden3: [z; HIDDEN],
        }
    }
}

impl<T: Real, const I: usize> Mlp<T, I> {
    /// All weights and biases zero: the neutral element for accumulating gradients.
    pub fn zeros() -> Self {
        let z = T::zero();
        Self {
            w1: [[z; HIDDEN]; I],
            b1: [z; HIDDEN],
            w2: [[z; HIDDEN]; HIDDEN],
            b2: [z; HIDDEN],
            w3: [[z; HIDDEN]; HIDDEN],
            b3: [z; HIDDEN],
            w4: [[z; OUTPUTS]; HIDDEN],
            b4: [z; OUTPUTS],
        }
    }

    /// He-initialised weights (normal, variance 2/fan-in) and zero biases. The output layer is scaled
    /// down by `output_gain` so that an untrained network starts near its output normalisation's mean.
    pub fn random(rng: &mut SplitMix64, output_gain: f64) -> Self {
        let mut mlp = Self::zeros();
        let mut fill = |w: &mut [T], fan_in: usize, gain: f64| {
            let std = (2.0 / fan_in as f64).sqrt() * gain;
            for x in w {
                *x = T::of(rng.normal() * std);
            }
        };
        fill(mlp.w1.as_flattened_mut(), I, 1.0);
        fill(mlp.w2.as_flattened_mut(), HIDDEN, 1.0);
        fill(mlp.w3.as_flattened_mut(), HIDDEN, 1.0);
        fill(mlp.w4.as_flattened_mut(), HIDDEN, output_gain);
        mlp
    }

    /// The weights and biases in a fixed order (layer by layer, weights column by column, then biases):
    /// the order of model files and of the optimiser.
    pub fn parameters(&self) -> impl Iterator<Item = &T> {
        self.w1
            .as_flattened()
            .iter()
            .chain(&self.b1)
            .chain(self.w2.as_flattened())
            .chain(&self.b2)
            .chain(self.w3.as_flattened())
            .chain(&self.b3)
            .chain(self.w4.as_flattened())
            .chain(&self.b4)
    }

    /// Mutable access in the order of [`Mlp::parameters`].
    pub fn parameters_mut(&mut self) -> impl Iterator<Item = &mut T> {
        self.w1
            .as_flattened_mut()
            .iter_mut()
            .chain(&mut self.b1)
            .chain(self.w2.as_flattened_mut())
            .chain(&mut self.b2)
            .chain(self.w3.as_flattened_mut())
            .chain(&mut self.b3)
            .chain(self.w4.as_flattened_mut())
            .chain(&mut self.b4)
    }

    /// The parameters as eight contiguous slices, in the order of [`Mlp::parameters`]: for loops over
    /// all parameters that should vectorise (a chain of eight iterators does not).
    pub fn slices(&self) -> [&[T]; 8] {
        [
            self.w1.as_flattened(),
            &self.b1,
            self.w2.as_flattened(),
            &self.b2,
            self.w3.as_flattened(),
            &self.b3,
            self.w4.as_flattened(),
            &self.b4,
        ]
    }

    /// Mutable [`Mlp::slices`].
    pub fn slices_mut(&mut self) -> [&mut [T]; 8] {
        [
            self.w1.as_flattened_mut(),
            &mut self.b1,
            self.w2.as_flattened_mut(),
            &mut self.b2,
            self.w3.as_flattened_mut(),
            &mut self.b3,
            self.w4.as_flattened_mut(),
            &mut self.b4,
        ]
    }

    /// Sets every parameter to zero, keeping the allocation-free storage.
    pub fn fill_zero(&mut self) {
        *self = Self::zeros();
    }

    /// Multiplies every parameter by `factor`.
    pub fn scale(&mut self, factor: T) {
        for slice in self.slices_mut() {
            for p in slice {
                *p = *p * factor;
            }
        }
    }

    /// The same network in another float type.
    pub fn cast<U: Real>(&self) -> Mlp<U, I> {
        let mut out = Mlp::<U, I>::zeros();
        for (o, p) in out.parameters_mut().zip(self.parameters()) {
            *o = U::of(p.as_f64());
        }
        out
    }

    /// The parameters as `f64`, in the order of [`Mlp::parameters`], for model files.
    pub fn to_vec(&self) -> Vec<f64> {
        self.parameters().map(|p| p.as_f64()).collect()
    }

    /// A network from parameters in the order of [`Mlp::parameters`]; `None` unless there are exactly
    /// [`parameter_count`]`(I)` values, each finite in `T`.
    pub fn from_slice(values: &[f64]) -> Option<Self> {
        Self::try_from_slice(values).ok()
    }

    /// As [`Mlp::from_slice`], with what is wrong: the count, or the first value that is not a
    /// finite number in `T` (a weight of 1e39 is finite in a JSON file but infinite in `f32`, and
    /// would make every prediction NaN).
    pub fn try_from_slice(values: &[f64]) -> Result<Self, String> {
        let expected = parameter_count(I);
        if values.len() != expected {
            return Err(format!(
                "the network has {} parameters, expected {expected} for a {I}-16-16-16-4 MLP",
                values.len()
            ));
        }
        let mut mlp = Self::zeros();
        for (k, (p, v)) in mlp.parameters_mut().zip(values).enumerate() {
            *p = T::of(*v);
            if !p.is_finite() {
                return Err(format!(
                    "parameter [{k}] is {v:e}, not a finite number in the network's {}-bit floats",
                    8 * std::mem::size_of::<T>()
                ));
            }
        }
        Ok(mlp)
    }
}

/// Serialised as the flat list of parameters (see [`Mlp::parameters`]).
impl<T: Real, const I: usize> Serialize for Mlp<T, I> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.to_vec().serialize(serializer)
    }
}

impl<'de, T: Real, const I: usize> Deserialize<'de> for Mlp<T, I> {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let values = Vec::<f64>::deserialize(deserializer)?;
        Self::try_from_slice(&values).map_err(serde::de::Error::custom)
    }
}

/// The network ready to run: its parameters plus a transposed copy of the weight matrices the backward
/// pass multiplies by.
///
/// The forward pass multiplies by each weight matrix and the backward pass by its transpose. Both are
/// fastest as broadcast multiply-adds over contiguous 16-wide columns, so the transpose is kept as a
/// second copy (2.3 kB) instead of being read with a stride or reduced lane by lane (measured 3× more
/// instructions). The first layer is the exception: its input gradient has only four (online: two)
/// components, each one 16-wide dot product of a stored column. The copy is derived state: the
/// parameters can only change through [`Network::update`], which re-derives it.
#[derive(Clone, Debug, PartialEq)]
pub struct Network<T, const I: usize = INPUTS> {
    params: Mlp<T, I>,
    wt2: [[T; HIDDEN]; HIDDEN],
    wt3: [[T; HIDDEN]; HIDDEN],
    wt4: [[T; HIDDEN]; OUTPUTS],
}

impl<T: Real, const I: usize> Network<T, I> {
    /// A network with these parameters.
    pub fn new(params: Mlp<T, I>) -> Self {
        let z = T::zero();
        let mut network = Self {
            params,
            wt2: [[z; HIDDEN]; HIDDEN],
            wt3: [[z; HIDDEN]; HIDDEN],
            wt4: [[z; HIDDEN]; OUTPUTS],
        };
        network.derive_transposes();
        network
    }

    /// The parameters.
    pub fn parameters(&self) -> &Mlp<T, I> {
        &self.params
    }

    /// Changes the parameters (an optimiser step) and re-derives the transposed copies.
    pub fn update(&mut self, change: impl FnOnce(&mut Mlp<T, I>)) {
        change(&mut self.params);
        self.derive_transposes();
    }

    /// The same network in another float type.
    pub fn cast<U: Real>(&self) -> Network<U, I> {
        Network::new(self.params.cast())
    }

    fn derive_transposes(&mut self) {
        transpose_into(&self.params.w2, &mut self.wt2);
        transpose_into(&self.params.w3, &mut self.wt3);
        transpose_into(&self.params.w4, &mut self.wt4);
    }

    /// Runs the network, keeping what the backward pass needs in `act`.
    #[inline(always)]
    pub fn forward(&self, input: &[T; I], act: &mut Activations<T, I>) -> [T; OUTPUTS] {
        self.forward_with::<Unfused>(input, act)
    }

    /// [`Network::forward`] with the multiply-add of the compiled copy.
    #[inline(always)]
    pub(crate) fn forward_with<A: MulAdd>(
        &self,
        input: &[T; I],
        act: &mut Activations<T, I>,
    ) -> [T; OUTPUTS] {
        let context_part = self.first_layer_context::<A>(input);
        self.forward_from::<A>(&context_part, input, act)
    }

    /// The first layer's pre-activation without the two position inputs: `b1 + Σ_{j≥2} w1[j] x_j`.
    /// Online learning moves only the position inputs (through `θ_online`), so this is computed once
    /// per online step instead of once per gradient step.
    #[inline(always)]
    pub(crate) fn first_layer_context<A: MulAdd>(&self, input: &[T; I]) -> [T; HIDDEN] {
        first_layer_context_part::<T, A, I>(&self.params, input)
    }

    /// The forward pass from [`Network::first_layer_context`] of `input` and the whole input.
    #[inline(always)]
    pub(crate) fn forward_from<A: MulAdd>(
        &self,
        context_part: &[T; HIDDEN],
        input: &[T; I],
        act: &mut Activations<T, I>,
    ) -> [T; OUTPUTS] {
        let ([pre1, pre2, pre3], output) = self.pre_activations::<A>(context_part, input);
        act.input = *input;
        act.hidden1 = relu(pre1);
        act.hidden2 = relu(pre2);
        act.hidden3 = relu(pre3);
        output
    }

    /// The forward pass from [`Network::first_layer_context`] of `input` and the whole input: the
    /// hidden layers before ReLU and the outputs. What [`Network::forward_from`] keeps for the
    /// backward pass and the affine piece (`piece.rs`) for its signs.
    #[inline(always)]
    pub(super) fn pre_activations<A: MulAdd>(
        &self,
        context_part: &[T; HIDDEN],
        input: &[T; I],
    ) -> ([[T; HIDDEN]; 3], [T; OUTPUTS]) {
        let p = &self.params;
        let mut pre1 = *context_part;
        axpy::<T, A, HIDDEN>(&mut pre1, &p.w1[0], input[0]);
        axpy::<T, A, HIDDEN>(&mut pre1, &p.w1[1], input[1]);
        let pre2 = dense::<T, A, HIDDEN, HIDDEN>(&p.w2, &p.b2, &relu(pre1));
        let pre3 = dense::<T, A, HIDDEN, HIDDEN>(&p.w3, &p.b3, &relu(pre2));
        let output = dense::<T, A, HIDDEN, OUTPUTS>(&p.w4, &p.b4, &relu(pre3));
        ([pre1, pre2, pre3], output)
    }

    /// Runs the network without keeping activations.
    #[inline]
    pub fn eval(&self, input: &[T; I]) -> [T; OUTPUTS] {
        self.forward(input, &mut Activations::default())
    }

    /// Gradient of a scalar with respect to the input, given its gradient `d_output` with respect to
    /// the output of the forward pass that filled `act`. Weights are left alone: online learning only
    /// needs to reach `θ_online`, which enters through the input.
    #[inline(always)]
    pub fn input_gradient(&self, act: &Activations<T, I>, d_output: &[T; OUTPUTS]) -> [T; I] {
        let d1 = self.first_layer_gradient::<Unfused>(act, d_output);
        std::array::from_fn(|j| dot::<T, Unfused>(&self.params.w1[j], &d1))
    }

    /// The first two components of [`Network::input_gradient`] (the position inputs, through which
    /// `θ_online` enters), with the multiply-add of the compiled copy.
    #[inline(always)]
    pub(crate) fn position_gradient<A: MulAdd>(
        &self,
        act: &Activations<T, I>,
        d_output: &[T; OUTPUTS],
    ) -> [T; 2] {
        let [position] = self.position_gradients::<A, 1>(act, &[*d_output]);
        position
    }

    /// [`Network::position_gradient`] of several output gradients from the same forward pass, each
    /// the same numbers to the bit. Taken layer by layer for all of them at once: their chains are
    /// independent, and interleaved they wait on one another's multiply-adds less than one after
    /// the other (a linearisation's three outputs and the loss's gradient).
    #[inline(always)]
    pub(crate) fn position_gradients<A: MulAdd, const N: usize>(
        &self,
        act: &Activations<T, I>,
        d_outputs: &[[T; OUTPUTS]; N],
    ) -> [[T; 2]; N] {
        let mut d3 = [[T::zero(); HIDDEN]; N];
        for (d, d_output) in d3.iter_mut().zip(d_outputs) {
            *d = relu_backward(
                &act.hidden3,
                &back_through::<T, A, _, _>(&self.wt4, d_output),
            );
        }
        let mut d2 = [[T::zero(); HIDDEN]; N];
        for (d, d_above) in d2.iter_mut().zip(&d3) {
            *d = relu_backward(
                &act.hidden2,
                &back_through::<T, A, _, _>(&self.wt3, d_above),
            );
        }
        let mut d1 = [[T::zero(); HIDDEN]; N];
        for (d, d_above) in d1.iter_mut().zip(&d2) {
            *d = relu_backward(
                &act.hidden1,
                &back_through::<T, A, _, _>(&self.wt2, d_above),
            );
        }
        let mut position = [[T::zero(); 2]; N];
        for (p, d) in position.iter_mut().zip(&d1) {
            *p = [
                dot::<T, A>(&self.params.w1[0], d),
                dot::<T, A>(&self.params.w1[1], d),
            ];
        }
        position
    }

    /// [`Network::position_gradient`], and with `weights` also every weight's and bias's gradient
    /// added to it: the one step every combined model takes back from its network's outputs to the
    /// inputs where `θ_online` enters.
    #[inline(always)]
    pub(crate) fn position_and_weight_gradient<A: MulAdd>(
        &self,
        act: &Activations<T, I>,
        d_output: &[T; OUTPUTS],
        weights: Option<&mut Mlp<T, I>>,
    ) -> [T; 2] {
        match weights {
            Some(grad) => {
                let d1 = self.weight_gradient::<A>(act, d_output, grad);
                [
                    self.first_layer_input_gradient::<A>(&d1, 0),
                    self.first_layer_input_gradient::<A>(&d1, 1),
                ]
            }
            None => self.position_gradient::<A>(act, d_output),
        }
    }

    /// The gradient with respect to the first layer's pre-activation.
    #[inline(always)]
    fn first_layer_gradient<A: MulAdd>(
        &self,
        act: &Activations<T, I>,
        d_output: &[T; OUTPUTS],
    ) -> [T; HIDDEN] {
        let d3 = relu_backward(
            &act.hidden3,
            &back_through::<T, A, _, _>(&self.wt4, d_output),
        );
        let d2 = relu_backward(&act.hidden2, &back_through::<T, A, _, _>(&self.wt3, &d3));
        relu_backward(&act.hidden1, &back_through::<T, A, _, _>(&self.wt2, &d2))
    }

    /// Adds the gradient with respect to every weight and bias to `grad`, and returns the gradient with
    /// respect to the input; `d_output` as in [`Network::input_gradient`].
    #[inline(always)]
    pub fn backward(
        &self,
        act: &Activations<T, I>,
        d_output: &[T; OUTPUTS],
        grad: &mut Mlp<T, I>,
    ) -> [T; I] {
        let d1 = self.weight_gradient::<Unfused>(act, d_output, grad);
        std::array::from_fn(|j| dot::<T, Unfused>(&self.params.w1[j], &d1))
    }

    /// Adds the gradient with respect to every weight and bias to `grad` and returns the gradient with
    /// respect to the first layer's pre-activation (from which any input gradient follows by
    /// [`Network::first_layer_input_gradient`]).
    #[inline(always)]
    pub(crate) fn weight_gradient<A: MulAdd>(
        &self,
        act: &Activations<T, I>,
        d_output: &[T; OUTPUTS],
        grad: &mut Mlp<T, I>,
    ) -> [T; HIDDEN] {
        accumulate_outer::<T, A, _, _>(&mut grad.w4, &mut grad.b4, &act.hidden3, d_output);
        let d3 = relu_backward(
            &act.hidden3,
            &back_through::<T, A, _, _>(&self.wt4, d_output),
        );
        accumulate_outer::<T, A, _, _>(&mut grad.w3, &mut grad.b3, &act.hidden2, &d3);
        let d2 = relu_backward(&act.hidden2, &back_through::<T, A, _, _>(&self.wt3, &d3));
        accumulate_outer::<T, A, _, _>(&mut grad.w2, &mut grad.b2, &act.hidden1, &d2);
        let d1 = relu_backward(&act.hidden1, &back_through::<T, A, _, _>(&self.wt2, &d2));
        accumulate_outer::<T, A, _, _>(&mut grad.w1, &mut grad.b1, &act.input, &d1);
        d1
    }

    /// The gradient with respect to input `j` from the first layer's pre-activation gradient `d1`.
    #[inline(always)]
    pub(crate) fn first_layer_input_gradient<A: MulAdd>(&self, d1: &[T; HIDDEN], j: usize) -> T {
        dot::<T, A>(&self.params.w1[j], d1)
    }
}

/// `b1 + Σ_{j≥2} w1[j] x_j`: see [`Network::first_layer_context`].
#[inline(always)]
fn first_layer_context_part<T: Real, A: MulAdd, const I: usize>(
    p: &Mlp<T, I>,
    input: &[T; I],
) -> [T; HIDDEN] {
    let mut z = p.b1;
    for (column, &x) in p.w1.iter().zip(input).skip(2) {
        axpy::<T, A, HIDDEN>(&mut z, column, x);
    }
    z
}

/// `out[i][j] = w[j][i]`.
fn transpose_into<T: Copy, const I: usize, const O: usize>(w: &[[T; O]; I], out: &mut [[T; I]; O]) {
    for (j, column) in w.iter().enumerate() {
        for (i, &x) in column.iter().enumerate() {
            out[i][j] = x;
        }
    }
}

/// Serialised as the flat list of parameters (see [`Mlp::parameters`]).
impl<T: Real, const I: usize> Serialize for Network<T, I> {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.params.serialize(serializer)
    }
}

impl<'de, T: Real, const I: usize> Deserialize<'de> for Network<T, I> {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        Mlp::<T, I>::deserialize(deserializer).map(Network::new)
    }
}

#[cfg(test)]
mod tests;
