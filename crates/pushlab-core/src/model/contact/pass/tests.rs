//! Tests of the contact-frame model's pass: gradients against central differences, the symmetries
//! (a push rotated onto another face of a square, a mirrored object) and wild learning rates.

use std::f64::consts::FRAC_PI_2;

use super::super::ContactInputs;
use super::*;
use crate::geometry::{Outline, rotate};
use crate::model::LossScale;
use crate::model::ObjectMotion;
use crate::model::Sample;
use crate::model::kernel::{RealSample, loss_gradient, loss_weights, theta_real};
use crate::model::mlp::{Mlp, Network};
use crate::rng::SplitMix64;

/// A random contact-frame model in f64 for boxes of a few decimetres pushed by a 5 cm disc, with
/// a wide clamp range so that the gradient checks see the unclamped network.
pub fn model_f64(seed: u64) -> ContactModel<f64> {
    let mut rng = SplitMix64::new(seed);
    ContactModel::from_parts(
        Network::new(Mlp::<f64, CONTACT_INPUTS>::random(&mut rng, 0.5)),
        ContactInputs {
            low: [-10.0; CONTACT_INPUTS],
            high: [10.0; CONTACT_INPUTS],
            motion_floor: 0.001,
        },
        0.3,
        0.003,
        LossScale {
            sigma_pos: [0.004, 0.002],
            sigma_rot: 0.02,
        },
        1,
        Default::default(),
    )
}

pub fn square() -> ContactGeometry {
    ContactGeometry::new(&Outline::rectangle(0.3, 0.3).expect("valid square"), 0.05)
}

/// A push on the front face below the middle, angled so that it slides.
pub fn sample() -> Sample {
    Sample {
        input: SampleInput {
            robot_in_object: [-0.2005, -0.06],
            robot_motion_in_object: [0.008, -0.03],
        },
        target: ObjectMotion {
            translation: [0.009, -0.001],
            rotation: 0.03,
        },
        frame: 0,
    }
}

fn loss_of(
    model: &ContactModel<f64>,
    prepared: &Prepared<f64>,
    target: &[f64; 3],
    theta: &[f64; 3],
) -> f64 {
    let mut pass = Pass::default();
    let out = model.forward::<Unfused>(prepared, theta, &mut pass);
    loss_gradient(out, target, &loss_weights(&model.loss_scale)).0
}

fn relative_error(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(1e-12)
}

#[test]
fn gradients_of_theta_weights_and_friction_match_central_differences() {
    let geometry = square();
    let s = sample();
    let target = RealSample::<f64>::of(&s).target;
    for seed in [1, 2, 3] {
        let model = model_f64(seed);
        let prepared = model.prepare(&geometry, &s.input);
        let theta = [0.012, -0.018, 0.07];
        let mut pass = Pass::default();
        let out = model.forward::<Unfused>(&prepared, &theta, &mut pass);
        assert!(
            pass.outer.sliding_for_tests(),
            "seed {seed}: the test push must slide"
        );
        let (_, d_out) = loss_gradient(out, &target, &loss_weights(&model.loss_scale));
        let mut grad = Mlp::zeros();
        let mut d_friction = 0.0;
        let g = model.backward::<Unfused>(
            &prepared,
            &pass,
            &theta,
            d_out,
            Some((&mut grad, &mut d_friction)),
        );
        for k in 0..3 {
            let eps = 1e-7;
            let (mut plus, mut minus) = (theta, theta);
            plus[k] += eps;
            minus[k] -= eps;
            let numeric = (loss_of(&model, &prepared, &target, &plus)
                - loss_of(&model, &prepared, &target, &minus))
                / (2.0 * eps);
            assert!(
                relative_error(g[k], numeric) <= 1e-5,
                "seed {seed} θ[{k}]: analytic {} numeric {numeric}",
                g[k]
            );
        }
        let eps = 1e-7;
        let friction_loss = |mu: f64| {
            let mut m = model.clone();
            m.set_friction(mu);
            loss_of(&m, &prepared, &target, &theta)
        };
        let numeric = (friction_loss(0.3 + eps) - friction_loss(0.3 - eps)) / (2.0 * eps);
        assert!(
            relative_error(d_friction, numeric) <= 1e-5,
            "seed {seed} μ: analytic {d_friction} numeric {numeric}"
        );
        let base = model.network.parameters().to_vec();
        let analytic = grad.to_vec();
        let mut checked = 0;
        for k in 0..base.len() {
            let eps = 1e-6;
            let mut m = model.clone();
            let mut p = base.clone();
            p[k] += eps;
            m.network = Network::new(Mlp::from_slice(&p).expect("finite"));
            let prepared_plus = m.prepare(&geometry, &s.input);
            let lp = loss_of(&m, &prepared_plus, &target, &theta);
            p[k] -= 2.0 * eps;
            m.network = Network::new(Mlp::from_slice(&p).expect("finite"));
            let prepared_minus = m.prepare(&geometry, &s.input);
            let lm = loss_of(&m, &prepared_minus, &target, &theta);
            let numeric = (lp - lm) / (2.0 * eps);
            if numeric.abs() < 1e-9 && analytic[k].abs() < 1e-9 {
                continue;
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

fn rotated(v: [f64; 2], angle: f64) -> [f64; 2] {
    let r = rotate(Vector2::from(v), angle);
    [r.x, r.y]
}

#[test]
fn a_push_rotated_onto_another_face_of_a_square_gives_the_same_prediction() {
    let geometry = square();
    let model = model_f64(11);
    let s = sample();
    let theta = OnlineParams {
        com_offset: [0.02, -0.01],
        h: 0.09,
    };
    let base = model.predict(&geometry, &s.input, &theta);
    for quarter in 1..4 {
        let angle = FRAC_PI_2 * quarter as f64;
        let input = SampleInput {
            robot_in_object: rotated(s.input.robot_in_object, angle),
            robot_motion_in_object: rotated(s.input.robot_motion_in_object, angle),
        };
        let turned = OnlineParams {
            com_offset: rotated(theta.com_offset, angle),
            ..theta
        };
        let p = model.predict(&geometry, &input, &turned);
        let expected = rotated(base.motion.translation, angle);
        for k in 0..2 {
            assert!(
                (p.motion.translation[k] - expected[k]).abs() < 1e-9,
                "quarter {quarter}: {:?} vs {expected:?}",
                p.motion.translation
            );
        }
        assert!((p.motion.rotation - base.motion.rotation).abs() < 1e-9);
    }
}

#[test]
fn a_push_on_a_mirrored_object_gives_the_mirrored_prediction() {
    // An irregular convex outline and its mirror image about the x axis.
    let vertices = [
        [0.12, -0.05],
        [0.1, 0.09],
        [-0.04, 0.13],
        [-0.15, 0.02],
        [-0.08, -0.11],
    ];
    let outline = Outline::try_from(vertices.to_vec()).expect("convex");
    let mirrored: Vec<[f64; 2]> = vertices.iter().rev().map(|v| [v[0], -v[1]]).collect();
    let mirrored = Outline::try_from(mirrored).expect("convex");
    let (a, b) = (
        ContactGeometry::new(&outline, 0.02),
        ContactGeometry::new(&mirrored, 0.02),
    );
    let model = model_f64(12);
    let mirror = |v: [f64; 2]| [v[0], -v[1]];
    for (p, u) in [
        ([-0.19, 0.01], [0.01, 0.004]),
        ([0.05, 0.17], [-0.003, -0.012]),
        ([0.16, 0.08], [-0.01, -0.002]),
    ] {
        let theta = OnlineParams {
            com_offset: [0.01, 0.015],
            h: 0.06,
        };
        let input = SampleInput {
            robot_in_object: p,
            robot_motion_in_object: u,
        };
        let mirrored_input = SampleInput {
            robot_in_object: mirror(p),
            robot_motion_in_object: mirror(u),
        };
        let mirrored_theta = OnlineParams {
            com_offset: mirror(theta.com_offset),
            ..theta
        };
        let one = model.predict(&a, &input, &theta);
        let other = model.predict(&b, &mirrored_input, &mirrored_theta);
        let expected = mirror(one.motion.translation);
        assert!((other.motion.translation[0] - expected[0]).abs() < 1e-9);
        assert!((other.motion.translation[1] - expected[1]).abs() < 1e-9);
        assert!((other.motion.rotation + one.motion.rotation).abs() < 1e-9);
        assert!(
            one.motion.rotation.abs() > 1e-6,
            "a push that turns the object"
        );
    }
}

#[test]
fn online_update_descends_the_loss_and_survives_wild_learning_rates() {
    let geometry = square();
    let model = model_f64(4);
    let s = sample();
    let theta = model.theta0(&geometry);
    let prepared = model.prepare(&geometry, &s.input);
    let target = RealSample::<f64>::of(&s).target;
    let (_, g, after) = model.online_update(&geometry, &s, &theta, 5, 0.005);
    let before_loss = loss_of(&model, &prepared, &target, &theta_real(&theta));
    let after_loss = loss_of(&model, &prepared, &target, &theta_real(&after));
    assert!(after_loss < before_loss, "{after_loss} !< {before_loss}");
    assert!(g.iter().any(|x| *x != 0.0));
    for lr in [10.0, 1e6, 1e300] {
        let (_, _, wild) = model.online_update(&geometry, &s, &theta, 5, lr);
        assert!((crate::model::H_MIN..=crate::model::H_MAX).contains(&wild.h));
        assert!(wild.com_offset.iter().all(|c| c.is_finite()), "lr {lr}");
    }
}

#[test]
fn the_linearization_s_jacobian_matches_central_differences_of_its_residual() {
    let geometry = square();
    let s = sample();
    for seed in [1, 2, 3] {
        let model = model_f64(seed);
        let theta = OnlineParams {
            com_offset: [0.012, -0.018],
            h: 0.07,
        };
        let lin = model.linearize(&geometry, &s, &theta);
        for j in 0..3 {
            let eps = 1e-7;
            let at = |sign: f64| {
                let mut v = [theta.com_offset[0], theta.com_offset[1], theta.h];
                v[j] += sign * eps;
                let t = OnlineParams {
                    com_offset: [v[0], v[1]],
                    h: v[2],
                };
                model.linearize(&geometry, &s, &t).residual
            };
            let (plus, minus) = (at(1.0), at(-1.0));
            for i in 0..3 {
                let numeric = (plus[i] - minus[i]) / (2.0 * eps);
                assert!(
                    (lin.jacobian[i][j] - numeric).abs() <= 1e-5 * (1.0 + numeric.abs()),
                    "seed {seed} ∂r{i}/∂θ{j}: analytic {} numeric {numeric}",
                    lin.jacobian[i][j]
                );
            }
        }
    }
}

#[test]
fn linearizing_and_updating_together_gives_the_bits_of_the_two_calls() {
    let geometry = square();
    let s = sample();
    for seed in [1, 2, 3] {
        let model = model_f64(seed).cast::<f32>();
        for theta in [
            OnlineParams {
                com_offset: [0.012, -0.018],
                h: 0.07,
            },
            model.theta0(&geometry),
        ] {
            let (lin, update) = model.linearize_and_update(&geometry, &s, &theta, 5, 0.005);
            assert_eq!(lin, model.linearize(&geometry, &s, &theta), "seed {seed}");
            assert_eq!(
                update,
                model.online_update(&geometry, &s, &theta, 5, 0.005),
                "seed {seed}"
            );
            assert_ne!(update.2, theta, "the step must learn something");
        }
    }
}
