//! Tests of the MLP: the forward pass against a naive one, gradients of the input and of every weight
//! against central differences, the batch pass, forward-mode Jacobian and affine piece against single
//! samples, and a wrong parameter count refused with the counts.

use super::*;

/// A scalar of the output to differentiate: a fixed weighting of the four outputs.
fn objective(mlp: &Network<f64>, x: &[f64; INPUTS]) -> f64 {
    let y = mlp.eval(x);
    0.3 * y[0] - 1.1 * y[1] + 0.7 * y[2] + 2.0 * y[3] + 0.5 * y[0] * y[0]
}

fn d_objective(mlp: &Network<f64>, x: &[f64; INPUTS]) -> [f64; OUTPUTS] {
    let y = mlp.eval(x);
    [0.3 + y[0], -1.1, 0.7, 2.0]
}

fn random_mlp(seed: u64) -> Network<f64> {
    let mut rng = SplitMix64::new(seed);
    let mut mlp = Mlp::<f64>::random(&mut rng, 1.0);
    // Non-zero biases so that every code path is exercised.
    for (i, b) in mlp.b1.iter_mut().chain(&mut mlp.b2).enumerate() {
        *b = 0.05 * (i as f64 - 8.0);
    }
    Network::new(mlp)
}

fn relative_error(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(1e-8)
}

#[test]
fn parameter_count_is_692() {
    assert_eq!(PARAMETER_COUNT, 692);
    assert_eq!(Mlp::<f32>::zeros().parameters().count(), 692);
}

#[test]
fn forward_matches_a_naive_implementation() {
    let mlp = random_mlp(1);
    let x = [0.3, -0.7, 1.2, 0.05];
    let p = mlp.parameters().to_vec();
    // Naive row-major evaluation straight from the flat parameter order.
    let mut offset = 0;
    let mut layer = |input: &[f64], inputs: usize, outputs: usize, relu: bool| {
        let w = &p[offset..offset + inputs * outputs];
        let b = &p[offset + inputs * outputs..offset + inputs * outputs + outputs];
        offset += inputs * outputs + outputs;
        (0..outputs)
            .map(|i| {
                let z = b[i]
                    + (0..inputs)
                        .map(|j| w[j * outputs + i] * input[j])
                        .sum::<f64>();
                if relu { z.max(0.0) } else { z }
            })
            .collect::<Vec<_>>()
    };
    let h1 = layer(&x, 4, 16, true);
    let h2 = layer(&h1, 16, 16, true);
    let h3 = layer(&h2, 16, 16, true);
    let y = layer(&h3, 16, 4, false);
    let fast = mlp.eval(&x);
    for i in 0..4 {
        assert!((fast[i] - y[i]).abs() < 1e-14);
    }
}

#[test]
fn weight_gradients_match_central_differences() {
    let mlp = random_mlp(2);
    let x = [0.4, -0.2, 0.9, -1.3];
    let mut act = Activations::default();
    mlp.forward(&x, &mut act);
    let mut grad = Mlp::zeros();
    mlp.backward(&act, &d_objective(&mlp, &x), &mut grad);
    let analytic = grad.to_vec();
    let base = mlp.parameters().to_vec();
    // The objective is quadratic in each weight between ReLU kinks, where central differences are
    // exact: the step only needs to be large enough that rounding in the objective (~1e-16 of its
    // size, divided by the step) stays far below 1e-5 of the smallest gradients checked (~1e-5).
    let eps = 1e-4;
    let mut checked = 0;
    for k in 0..PARAMETER_COUNT {
        let mut plus = base.clone();
        plus[k] += eps;
        let mut minus = base.clone();
        minus[k] -= eps;
        let fp = objective(&Network::new(Mlp::from_slice(&plus).expect("finite")), &x);
        let fm = objective(&Network::new(Mlp::from_slice(&minus).expect("finite")), &x);
        let numeric = (fp - fm) / (2.0 * eps);
        if numeric.abs() < 1e-7 && analytic[k].abs() < 1e-7 {
            continue; // an inactive unit: both zero
        }
        assert!(
            relative_error(analytic[k], numeric) <= 1e-5,
            "parameter {k}: analytic {} numeric {numeric}",
            analytic[k]
        );
        checked += 1;
    }
    assert!(checked > 200, "only {checked} parameters had a gradient");
}

#[test]
fn input_gradient_matches_central_differences_and_backward() {
    let mlp = random_mlp(3);
    let x = [0.1, 0.8, -0.5, 0.6];
    let mut act = Activations::default();
    mlp.forward(&x, &mut act);
    let d = d_objective(&mlp, &x);
    let g = mlp.input_gradient(&act, &d);
    let mut scratch = Mlp::zeros();
    let g2 = mlp.backward(&act, &d, &mut scratch);
    let eps = 1e-6;
    for j in 0..INPUTS {
        let mut xp = x;
        xp[j] += eps;
        let mut xm = x;
        xm[j] -= eps;
        let numeric = (objective(&mlp, &xp) - objective(&mlp, &xm)) / (2.0 * eps);
        assert!(relative_error(g[j], numeric) <= 1e-5, "input {j}");
        assert_eq!(g[j], g2[j]);
    }
}

#[test]
fn batch_forward_and_forward_mode_jacobian_match_the_single_sample_passes() {
    let mlp = random_mlp(4);
    let inputs = [
        [0.2, -0.6, 0.9, -0.3],
        [-0.4, 0.3, 0.1, 0.8],
        [1.1, 0.2, -0.7, 0.0],
    ];
    let mut batch = BatchActivations::default();
    batch.input[..3].copy_from_slice(&inputs);
    let mut outputs = [[0.0; OUTPUTS]; BATCH];
    mlp.forward_batch::<Unfused>(3, &mut batch, &mut outputs);
    let mut tangents = [[[0.0; HIDDEN]; 2]; BATCH];
    let mut jacobians = [[[0.0; OUTPUTS]; 2]; BATCH];
    mlp.position_jacobian_batch::<Unfused>(3, &batch, &mut tangents, &mut jacobians);
    let mut nonzero = false;
    for (s, x) in inputs.iter().enumerate() {
        let mut act = Activations::default();
        assert_eq!(mlp.forward(x, &mut act), outputs[s], "sample {s}");
        for o in 0..OUTPUTS {
            let mut d = [0.0; OUTPUTS];
            d[o] = 1.0;
            let g = mlp.input_gradient(&act, &d);
            for j in 0..2 {
                let forward_mode = jacobians[s][j][o];
                assert!(
                    relative_error(forward_mode, g[j]) <= 1e-12,
                    "sample {s} ∂y{o}/∂x{j}: forward {forward_mode} backward {}",
                    g[j]
                );
                nonzero |= forward_mode.abs() > 1e-3;
            }
        }
    }
    assert!(nonzero);
}

#[test]
fn the_affine_piece_is_the_network_until_a_hidden_unit_changes_sign() {
    let mlp = random_mlp(5);
    let x = [0.3, -0.2, 0.5, -0.4];
    let piece = mlp.piece_at::<Unfused>(&mlp.first_layer_context::<Unfused>(&x), &x);
    assert_eq!(
        piece.output(),
        mlp.eval(&x),
        "the anchor's outputs, to the bit"
    );
    let mut at_anchor = Activations::default();
    mlp.forward(&x, &mut at_anchor);
    let d = d_objective(&mlp, &x);
    let backward = mlp.input_gradient(&at_anchor, &d);
    let gradient = piece.position_gradient::<Unfused>(&d);
    for j in 0..2 {
        assert!(
            relative_error(gradient[j], backward[j]) <= 1e-12,
            "input {j}: piece {} backward {}",
            gradient[j],
            backward[j]
        );
    }
    // Along a line through the anchor: the network's outputs while every unit keeps its sign, and
    // `None` exactly where one does not.
    let pattern = |act: &Activations<f64, INPUTS>| {
        [act.hidden1, act.hidden2, act.hidden3].map(|layer| layer.map(|a| a > 0.0))
    };
    let (mut on, mut off) = (0, 0);
    for k in 1..=200 {
        let t = 1e-4 * 1.05_f64.powi(k);
        let moved = [x[0] + t, x[1] - 0.5 * t, x[2], x[3]];
        let mut act = Activations::default();
        let truth = mlp.forward(&moved, &mut act);
        let same = pattern(&act) == pattern(&at_anchor);
        match piece.output_at::<Unfused>([moved[0], moved[1]]) {
            Some(z) => {
                assert!(same, "t = {t}: a unit changed sign but the piece answered");
                for i in 0..OUTPUTS {
                    assert!(
                        (z[i] - truth[i]).abs() <= 1e-12 * truth[i].abs().max(1.0),
                        "t = {t}, output {i}: piece {} network {}",
                        z[i],
                        truth[i]
                    );
                }
                on += 1;
            }
            None => {
                assert!(!same, "t = {t}: off the piece with the anchor's signs");
                off += 1;
            }
        }
    }
    assert!(on > 5 && off > 5, "on the piece {on} times, off it {off}");
}

#[test]
fn wrong_parameter_count_is_refused_with_the_counts() {
    let err = serde_json::from_str::<Mlp<f32>>("[1.0, 2.0]").expect_err("too short");
    assert!(err.to_string().contains("has 2 parameters"), "{err}");
    assert!(err.to_string().contains("692"), "{err}");
}
