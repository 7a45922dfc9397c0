//! Adam (Kingma and Ba 2015) over the network's weights, the optimiser of offline training.

use crate::model::Mlp;
use crate::real::Real;

/// Adam's state for one network: first and second moment estimates of every weight.
#[derive(Clone, Debug)]
pub(crate) struct Adam<T, const I: usize> {
    m: Mlp<T, I>,
    v: Mlp<T, I>,
    steps: i32,
    lr: f64,
}

const BETA1: f64 = 0.9;
const BETA2: f64 = 0.999;
const EPSILON: f64 = 1e-8;

impl<T: Real, const I: usize> Adam<T, I> {
    /// Fresh state with the learning rate `lr`.
    pub fn new(lr: f64) -> Self {
        Self {
            m: Mlp::zeros(),
            v: Mlp::zeros(),
            steps: 0,
            lr,
        }
    }

    /// One update of `params` along the (mean) gradient `grad`.
    #[inline(always)]
    pub fn step(&mut self, params: &mut Mlp<T, I>, grad: &Mlp<T, I>) {
        self.steps += 1;
        let (b1, b2) = (T::of(BETA1), T::of(BETA2));
        let (one_b1, one_b2) = (T::of(1.0 - BETA1), T::of(1.0 - BETA2));
        // Bias corrections folded into the step size, as Kingma and Ba suggest at the end of their Sec. 2.
        let correction1 = 1.0 - BETA1.powi(self.steps);
        let correction2 = 1.0 - BETA2.powi(self.steps);
        let step = T::of(self.lr * correction2.sqrt() / correction1);
        let eps = T::of(EPSILON * correction2.sqrt());
        let slices = params
            .slices_mut()
            .into_iter()
            .zip(grad.slices())
            .zip(self.m.slices_mut())
            .zip(self.v.slices_mut());
        for (((ps, gs), ms), vs) in slices {
            for (((p, g), m), v) in ps.iter_mut().zip(gs).zip(ms.iter_mut()).zip(vs.iter_mut()) {
                *m = b1 * *m + one_b1 * *g;
                *v = b2 * *v + one_b2 * *g * *g;
                *p = *p - step * *m / (v.sqrt() + eps);
            }
        }
    }
}

/// Adam over a few plain parameters (`θ_online` when it is trained offline too).
#[derive(Clone, Debug)]
pub(crate) struct SmallAdam<const N: usize> {
    m: [f64; N],
    v: [f64; N],
    steps: i32,
    lr: f64,
}

impl<const N: usize> SmallAdam<N> {
    pub fn new(lr: f64) -> Self {
        Self {
            m: [0.0; N],
            v: [0.0; N],
            steps: 0,
            lr,
        }
    }

    pub fn step(&mut self, params: &mut [f64; N], grad: &[f64; N]) {
        self.steps += 1;
        let c1 = 1.0 - BETA1.powi(self.steps);
        let c2 = 1.0 - BETA2.powi(self.steps);
        for i in 0..N {
            self.m[i] = BETA1 * self.m[i] + (1.0 - BETA1) * grad[i];
            self.v[i] = BETA2 * self.v[i] + (1.0 - BETA2) * grad[i] * grad[i];
            params[i] -= self.lr * (self.m[i] / c1) / ((self.v[i] / c2).sqrt() + EPSILON);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_adam_minimises_a_quadratic() {
        let mut x = [3.0, -2.0];
        let mut adam = SmallAdam::<2>::new(0.05);
        for _ in 0..2000 {
            let g = [2.0 * (x[0] - 1.0), 2.0 * (x[1] + 0.5)];
            adam.step(&mut x, &g);
        }
        assert!(
            (x[0] - 1.0).abs() < 1e-3 && (x[1] + 0.5).abs() < 1e-3,
            "{x:?}"
        );
    }

    #[test]
    fn first_adam_step_moves_each_weight_by_the_learning_rate() {
        // With bias correction, the first step is lr · sign(g) for every non-zero gradient.
        let mut params = Mlp::<f64>::zeros();
        let mut grad = Mlp::<f64>::zeros();
        for (i, g) in grad.parameters_mut().enumerate() {
            *g = if i % 2 == 0 { 0.3 } else { -7.0 };
        }
        Adam::new(0.005).step(&mut params, &grad);
        for (i, p) in params.parameters().enumerate() {
            let expected = if i % 2 == 0 { -0.005 } else { 0.005 };
            assert!((p - expected).abs() < 1e-9, "{i}: {p}");
        }
    }
}
