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
/// A gradient or first moment smaller than this is taken as zero, and a second moment smaller than
/// its square. Such a weight would move by under `lr · 1e-7` a step (its step is `m / (√v + ε)`, and
/// ε is 1e-8): below an `f32` weight's rounding unless the weight is itself tiny. Without the flush,
/// the moments of weights whose gradient is almost always zero (units that are rarely active) decay
/// geometrically into the subnormal range, where every x86 multiply takes a microcode assist of
/// about a hundred cycles: on the contact kind, Adam's loop over those moments was half an epoch's
/// time (`docs/src/performance.md`, issue #51).
const TINY: f64 = 1e-15;

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
        let (tiny, tiny_squared) = (T::of(TINY), T::of(TINY * TINY));
        let flush = |x: T, below: T| if x.abs() < below { T::zero() } else { x };
        let slices = params
            .slices_mut()
            .into_iter()
            .zip(grad.slices())
            .zip(self.m.slices_mut())
            .zip(self.v.slices_mut());
        for (((ps, gs), ms), vs) in slices {
            for (((p, g), m), v) in ps.iter_mut().zip(gs).zip(ms.iter_mut()).zip(vs.iter_mut()) {
                let g = flush(*g, tiny);
                *m = flush(b1 * *m + one_b1 * g, tiny);
                *v = flush(b2 * *v + one_b2 * g * g, tiny_squared);
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

    /// Adam as Kingma and Ba write it, in `f32`, without the flush: the reference.
    fn textbook_step(p: &mut f32, m: &mut f32, v: &mut f32, g: f32, t: i32, lr: f64) {
        let c1 = 1.0 - BETA1.powi(t);
        let c2 = 1.0 - BETA2.powi(t);
        let (b1, b2) = (BETA1 as f32, BETA2 as f32);
        let (one_b1, one_b2) = ((1.0 - BETA1) as f32, (1.0 - BETA2) as f32);
        *m = b1 * *m + one_b1 * g;
        *v = b2 * *v + one_b2 * g * g;
        let step = (lr * c2.sqrt() / c1) as f32;
        let eps = (EPSILON * c2.sqrt()) as f32;
        *p -= step * *m / (v.sqrt() + eps);
    }

    #[test]
    fn a_weight_whose_gradient_stops_never_keeps_a_subnormal_moment() {
        // Three weights: one learning, one whose gradient stops (a unit that fell silent), one
        // with gradients too small to move it.
        let mut params = Mlp::<f32>::zeros();
        let mut grad = Mlp::<f32>::zeros();
        let mut adam = Adam::new(0.005);
        let mut textbook = [(0.0f32, 0.0f32, 0.0f32); 3];
        let mut subnormal_in_textbook = false;
        for t in 1..=3000 {
            let gradients = [
                (t as f32 * 0.37).sin() * 1e-2,
                if t <= 50 { 1e-3 } else { 0.0 },
                1e-20,
            ];
            for (g, value) in grad.parameters_mut().zip(gradients) {
                *g = value;
            }
            adam.step(&mut params, &grad);
            for ((p, m, v), g) in textbook.iter_mut().zip(gradients) {
                textbook_step(p, m, v, g, t, 0.005);
                subnormal_in_textbook |= m.is_subnormal() || v.is_subnormal();
            }
            let mut moments = adam.m.parameters().chain(adam.v.parameters());
            assert!(moments.all(|x| !x.is_subnormal()), "step {t}");
            let learned: Vec<f32> = params.parameters().take(3).copied().collect();
            // The learning weight and the silent one move as the textbook's do; the flush only
            // cuts the tails the textbook keeps as subnormal numbers.
            assert_eq!(learned[0].to_bits(), textbook[0].0.to_bits(), "step {t}");
            assert_eq!(learned[1].to_bits(), textbook[1].0.to_bits(), "step {t}");
            assert!(learned[2].abs() < 1e-9, "step {t}: {}", learned[2]);
        }
        assert!(
            subnormal_in_textbook,
            "the test's gradients must drive the textbook's moments subnormal"
        );
    }
}
