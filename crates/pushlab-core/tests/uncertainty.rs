//! Beyond the paper's point estimate, checked against independent truth: the posterior of a
//! linear-Gaussian problem against its closed form and its coverage over repeated noise, the
//! Jacobians against central differences, Gauss–Newton against gradient descent where the true COM
//! is known, the loss landscape's minimum against the simulator's COM, and rollouts against the
//! one-step prediction and the recorded poses.

use crate::toy;

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use nalgebra::{DMatrix, DVector};
use pushlab_core::experiment::ComTruth;
use pushlab_core::inspect::{ComGrid, com_landscape, com_landscape_in_slices, h_slice, rollout};
use pushlab_core::learn::uncertainty::{CHI2_2DOF_95, Spread};
use pushlab_core::learn::{
    ContactTrajectory, OnlineConfig, Optimizer, TrainConfig, train_contact, train_paper,
};
use pushlab_core::model::{
    CombinedModel, ContactGeometry, LossScale, OnlineModel, OnlineParams, OnlineStep,
    PhysicsOnlyModel, Sample, sample_at, samples_from_trajectory,
};
use pushlab_core::recording::{ObjectShape, PushSide};
use pushlab_core::rng::SplitMix64;
use pushlab_core::sim::{GeneratedSet, NoiseSpec, PressureModel, PushSpec, SetSpec, generate_set};
use pushlab_core::slices;

use toy::{Chain, GAUSS_NEWTON, LinearToy, theta_vector, toy_samples};

#[test]
fn the_posterior_of_a_linear_gaussian_problem_is_its_closed_form_and_covers_the_truth() {
    let truth = OnlineParams {
        com_offset: [0.03, -0.02],
        h: 0.42,
    };
    let mut rng = SplitMix64::new(17);
    let samples = toy_samples(&mut rng, &truth, 40, 0.05);
    let mut learner = Chain::new(LinearToy, GAUSS_NEWTON);
    let steps = learner.run(&samples);
    let posterior = learner.posterior();
    let estimate = theta_vector(&learner.theta());

    // The closed form, from the stacked system A θ = y with frame i of n weighed by
    // (1 − 1/MEMORY_FRAMES)^(n − 1 − i) (the posterior's forgetting): the noise variance of the
    // weighted fit at the estimate and the covariance (AᵀWA / s² + Λ₀)⁻¹ with the prior
    // N(θ₀, (2 h₀)² I).
    let n = samples.len();
    let keep = 1.0 - 1.0 / pushlab_core::learn::uncertainty::MEMORY_FRAMES;
    let weights = DVector::from_fn(3 * n, |row, _| keep.powi((n - 1 - row / 3) as i32));
    let w = DMatrix::from_diagonal(&weights);
    let a = DMatrix::from_fn(3 * n, 3, |row, col| {
        LinearToy::matrix(&samples[row / 3].input)[(row % 3, col)]
    });
    let y = DVector::from_fn(3 * n, |row, _| {
        let t = samples[row / 3].target;
        [t.translation[0], t.translation[1], t.rotation][row % 3]
    });
    let residual = &a * DVector::from_column_slice(estimate.as_slice()) - &y;
    let weight_sum = weights.sum() / 3.0;
    let s2 =
        (residual.component_mul(&residual).dot(&weights) + 3.0) / (3.0 * weight_sum - 3.0 + 3.0);
    assert!((posterior.noise_variance() - s2).abs() < 1e-9 * s2);
    // The correlation factor: 40 frames make 10 batches of 4 (16 of 1 merged to 8 of 2, 16 of 2 to
    // 8 of 4); each batch's score Σ Aₜᵀ(Aₜ θ̂ − yₜ) at the estimate, their scatter about the mean,
    // in the metric of the mean batch's AᵀA, over what independent errors give (s² per frame).
    assert_eq!(posterior.score_batches(), (10, 4));
    let theta_hat = DVector::from_column_slice(estimate.as_slice());
    let batch = |b: usize| a.rows(12 * b, 12);
    let scores: Vec<DVector<f64>> = (0..10)
        .map(|b| batch(b).transpose() * (batch(b) * &theta_hat - y.rows(12 * b, 12)))
        .collect();
    let mean = scores.iter().fold(DVector::zeros(3), |m, g| m + g) / 10.0;
    let scatter = scores.iter().fold(DMatrix::zeros(3, 3), |s, g| {
        s + (g - &mean) * (g - &mean).transpose()
    }) / 9.0;
    let mean_ata = (0..10).fold(DMatrix::zeros(3, 3), |s, b| {
        s + batch(b).transpose() * batch(b)
    }) / 10.0;
    let per_frame = (mean_ata.try_inverse().expect("invertible") * scatter).trace() / 3.0;
    let c = (per_frame / s2).clamp(1.0, 100.0);
    assert!((posterior.correlation_factor() - c).abs() < 1e-9 * c);
    let prior_precision = 1.0 / (2.0 * 0.5_f64).powi(2);
    let information =
        a.transpose() * &w * &a / (s2 * c) + DMatrix::identity(3, 3) * prior_precision;
    let closed = information.try_inverse().expect("positive definite");
    let covariance = posterior.mode_covariance();
    for i in 0..3 {
        for j in 0..3 {
            assert!(
                (covariance[(i, j)] - closed[(i, j)]).abs()
                    < 1e-9 * closed[(i, i)].abs().max(1e-12),
                "covariance[{i},{j}] {} against {}",
                covariance[(i, j)],
                closed[(i, j)]
            );
        }
    }
    // The mode is the batch MAP estimate, and the recursive Gauss–Newton steps reach it (within a
    // tenth of a standard deviation: each frame was weighed with the noise variance known when it
    // came); the estimate's error covariance adds its offset from the mode.
    let map = &closed
        * (a.transpose() * &w * &y / (s2 * c)
            + DVector::from_column_slice(&[0.0, 0.0, 0.5]) * prior_precision);
    let mode = posterior.mode();
    for i in 0..3 {
        assert!(
            (mode[i] - map[i]).abs() < 1e-9 * (1.0 + map[i].abs()),
            "mode {mode} against {map}"
        );
        assert!(
            (estimate[i] - map[i]).abs() < 0.1 * closed[(i, i)].sqrt(),
            "θ[{i}] {} against the MAP {}",
            estimate[i],
            map[i]
        );
    }
    // It also adds, on each COM component, 6 × the drift of the COM estimates the frames were
    // learned at: their scatter about their mean, less what their steps would scatter them by in
    // uncorrelated directions (a step moves the weight after it against the weight before it), frame
    // i weighed like its residuals.
    let frame_weight = |i: usize| keep.powi((n - 1 - i) as i32);
    let total: f64 = (0..n).map(frame_weight).sum();
    let path: Vec<[f64; 2]> = steps.iter().map(|s| s.theta_before.com_offset).collect();
    let path_mean = (0..n).fold([0.0; 2], |m, i| {
        [
            m[0] + frame_weight(i) * path[i][0] / total,
            m[1] + frame_weight(i) * path[i][1] / total,
        ]
    });
    let squared = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2);
    let scatter: f64 = (0..n)
        .map(|i| frame_weight(i) * squared(path[i], path_mean))
        .sum::<f64>()
        / total;
    let jitter: f64 = (1..n)
        .map(|k| {
            let after = (k..n).map(frame_weight).sum::<f64>() / total;
            squared(path[k], path[k - 1]) * after * (1.0 - after)
        })
        .sum();
    let path_variance = 6.0 * (scatter - jitter).max(0.0);
    assert!(
        (posterior.com_path_variance() - path_variance).abs() < 1e-9 * scatter,
        "path variance {} against {path_variance} (scatter {scatter}, jitter {jitter})",
        posterior.com_path_variance()
    );
    let offset = estimate - mode;
    let from_frames = covariance + offset * offset.transpose();
    assert!((posterior.covariance_from_frames() - from_frames).norm() < 1e-12 * from_frames.norm());
    let mut expected = from_frames;
    expected[(0, 0)] += path_variance;
    expected[(1, 1)] += path_variance;
    assert!((posterior.covariance() - expected).norm() < 1e-12 * expected.norm());
    // Its parts, as the app lists them, add up to the mean COM variance.
    let parts = posterior.com_spread_parts();
    let mean_variance = (expected[(0, 0)] + expected[(1, 1)]) / 2.0;
    let sum = parts.frames_m.powi(2) + parts.misfit_m.powi(2) + parts.drift_m.powi(2);
    assert!((sum - mean_variance).abs() < 1e-12 * mean_variance);
    assert_eq!(parts.misfit_m, 0.0);
    assert!((parts.drift_m.powi(2) - path_variance).abs() <= 1e-12 * mean_variance);
    // The spread kept for every frame gives the same parts (in f32), a misfit included: what the
    // app lists for the frame shown.
    for misfit in [0.0, 0.004] {
        let posterior = posterior.with_com_misfit(misfit);
        let exact = posterior.com_spread_parts();
        let kept = Spread::of(&posterior).com_parts();
        assert!((kept.misfit_m - misfit).abs() < 1e-7, "{kept:?}");
        for (a, b) in [
            (kept.frames_m, exact.frames_m),
            (kept.misfit_m, exact.misfit_m),
            (kept.drift_m, exact.drift_m),
        ] {
            assert!(
                (a - b).abs() < 1e-5 * mean_variance.sqrt(),
                "{kept:?} against {exact:?}"
            );
        }
    }

    // Over repeated noise the frames' 95 % ellipse of the COM holds the truth about 95 % of the
    // time. The noise is that of a model that predicts nothing (normalised variance 1), which the
    // noise variance's pseudo-frame assumes; smaller noise makes the first frames' ellipses
    // conservative. The path's drift, added for the ellipse the app shows, widens it little for a
    // model this right: Gauss–Newton's steps are uncorrelated when its model fits.
    let trials = 400;
    let within = |c: nalgebra::Matrix3<f64>, e: [f64; 2]| {
        let c = nalgebra::Matrix2::new(c[(0, 0)], c[(0, 1)], c[(1, 0)], c[(1, 1)]);
        let e = nalgebra::Vector2::from(e);
        (e.transpose() * c.try_inverse().expect("invertible") * e)[(0, 0)] <= CHI2_2DOF_95
    };
    let (mut held_from_frames, mut held, mut widening) = (0, 0, Vec::new());
    for _ in 0..trials {
        let samples = toy_samples(&mut rng, &truth, 30, 1.0);
        let mut learner = Chain::new(LinearToy, GAUSS_NEWTON);
        learner.run(&samples);
        let posterior = learner.posterior();
        let found = learner.theta().com_offset;
        let error = [
            found[0] - truth.com_offset[0],
            found[1] - truth.com_offset[1],
        ];
        held_from_frames += usize::from(within(posterior.covariance_from_frames(), error));
        held += usize::from(posterior.com_within_95(found, truth.com_offset));
        let trace = |c: nalgebra::Matrix3<f64>| c[(0, 0)] + c[(1, 1)];
        widening.push(
            (trace(posterior.covariance()) / trace(posterior.covariance_from_frames())).sqrt(),
        );
    }
    let coverage = held_from_frames as f64 / trials as f64;
    assert!(
        (0.91..=0.99).contains(&coverage),
        "the frames' 95 % ellipse held the truth in {:.1} % of {trials} trials",
        100.0 * coverage
    );
    widening.sort_by(f64::total_cmp);
    let median_widening = widening[trials / 2];
    assert!(
        (0.91..=0.99).contains(&(held as f64 / trials as f64)) && median_widening < 1.1,
        "with the path: held {held} of {trials} (the frames' ellipse {held_from_frames}), its median {median_widening:.2}× as wide"
    );
}

#[test]
fn the_95_ellipse_has_the_covariance_s_axes() {
    let mut rng = SplitMix64::new(3);
    let truth = OnlineParams {
        com_offset: [0.01, 0.02],
        h: 0.3,
    };
    let mut learner = Chain::new(LinearToy, GAUSS_NEWTON);
    learner.run(&toy_samples(&mut rng, &truth, 10, 0.1));
    let posterior = learner.posterior();
    let ([major, minor], angle) = posterior.com_ellipse_95();
    let c = posterior.com_covariance();
    // A point on the major axis at the ellipse's edge has Mahalanobis distance² χ²(2, 95 %).
    let d = [major * angle.cos(), major * angle.sin()];
    let inverse = nalgebra::Matrix2::new(c[0][0], c[0][1], c[1][0], c[1][1])
        .try_inverse()
        .expect("invertible");
    let v = nalgebra::Vector2::new(d[0], d[1]);
    let m2 = (v.transpose() * inverse * v)[(0, 0)];
    assert!((m2 - CHI2_2DOF_95).abs() < 1e-9, "{m2}");
    assert!(major >= minor && minor > 0.0);
    let centre = [0.0, 0.0];
    assert!(posterior.com_within_95(centre, [d[0] * 0.99, d[1] * 0.99]));
    assert!(!posterior.com_within_95(centre, [d[0] * 1.01, d[1] * 1.01]));
}

/// A box pushed from the front and the left in turn, noise-free, its COM moved to `com`.
fn pushes(com: [f64; 2], side: PushSide, seed: u64) -> GeneratedSet {
    let mut pushes = Vec::new();
    for offset in [-0.1, -0.05, 0.0, 0.05, 0.1] {
        for angle in [-15.0, 0.0, 15.0] {
            pushes.push(PushSpec {
                contact_offset: offset,
                push_angle_deg: angle,
                curvature: 0.0,
                split: None,
            });
        }
    }
    generate_set(
        &SetSpec {
            name: "uncertainty".into(),
            object: ObjectShape::Box {
                width: 0.3,
                length: 0.4,
            },
            com_offset: com,
            pressure: PressureModel::Uniform,
            material: None,
            floor_friction: None,
            // Sticking contact, as the physics-only model assumes.
            pusher_friction: 0.9,
            pusher_radius: 0.05,
            push_side: side,
            sample_rate_hz: 10.0,
            duration_s: 6.0,
            speed: 0.04,
            approach: 0.0,
            noise: NoiseSpec {
                position_m: 0.0,
                yaw_deg: 0.0,
            },
            start_position_spread_m: 0.2,
            start_yaw_spread_deg: 90.0,
            seed,
            pushes,
        },
        &mut |_, _| {},
    )
    .expect("valid simulation spec")
}

/// The sticking pushes of a front set and a left set, interleaved.
fn front_and_left(com: [f64; 2], seed: u64) -> (GeneratedSet, Vec<Vec<Sample>>) {
    let front = pushes(com, PushSide::Front, seed);
    let left = pushes(com, PushSide::Left, seed + 1);
    let sticking = |set: &GeneratedSet| -> Vec<Vec<Sample>> {
        set.trajectories
            .iter()
            .zip(&set.sliding_fractions)
            .filter(|(_, sliding)| **sliding == 0.0)
            .map(|(t, _)| samples_from_trajectory(t, 1))
            .collect()
    };
    let data = sticking(&front)
        .into_iter()
        .zip(sticking(&left))
        .flat_map(|(a, b)| [a, b])
        .collect();
    (front, data)
}

fn physics_model(set: &GeneratedSet, data: &[Vec<Sample>]) -> PhysicsOnlyModel {
    let outline = set.setting.object.outline().expect("a box");
    PhysicsOnlyModel::new(
        outline,
        set.setting.pusher_radius,
        0.005,
        LossScale::from_samples(data.iter().flatten()),
    )
}

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

#[test]
fn jacobians_match_central_differences_of_the_residual_for_every_kind() {
    let (set, data) = front_and_left([0.02, -0.01], 40);
    let physics = physics_model(&set, &data);
    let outline = set.setting.object.outline().expect("a box");
    let training: Vec<Vec<Sample>> = data.iter().take(6).cloned().collect();
    let config = TrainConfig {
        epochs: 3,
        seed: 1,
        theta0: Some(OnlineParams::for_outline(&outline)),
        ..TrainConfig::default()
    };
    let never = AtomicBool::new(false);
    let paper = train_paper(&training, &config, &mut |_| {}, &never).expect("trains");
    let geometry = Arc::new(ContactGeometry::new(&outline, set.setting.pusher_radius));
    let contact_data: Vec<ContactTrajectory> = training
        .iter()
        .map(|samples| ContactTrajectory {
            geometry: &geometry,
            samples,
        })
        .collect();
    let contact = train_contact(&contact_data, &config, &mut |_| {}, &never).expect("trains");
    let contact = CombinedModel::Contact(Arc::new(contact.model))
        .on_object(Some(&geometry))
        .expect("outline");
    // The paper model predicts in f32 (its default) and f64: the check runs on the f64 one, whose
    // central differences resolve the Jacobian to 1e-4.
    let paper = paper.model.cast::<f64>();
    // The contact learner runs its network in f32: wider differences, a looser tolerance (its f64
    // pass is checked to 1e-6 in the crate's unit tests).
    let models: [(&str, &dyn OnlineModel, f64, f64); 3] = [
        ("physics only", &physics, 1e-6, 1e-4),
        ("paper", &paper, 1e-6, 1e-4),
        ("contact", contact.as_ref(), 1e-4, 1e-2),
    ];
    for (kind, model, eps, tolerance) in models {
        let mut checked = 0;
        for sample in data.iter().flatten().step_by(7).take(12) {
            let theta = OnlineParams {
                com_offset: [0.012, -0.008],
                h: 0.11,
            };
            let lin = model.linearize(sample, &theta);
            // The residual is the loss's: Σ r² = ℓ.
            let loss = model.loss_and_gradient(sample, &theta).1.total();
            assert!(
                (lin.residual.iter().map(|r| r * r).sum::<f64>() - loss).abs()
                    < 1e-6 * (1.0 + loss)
            );
            for j in 0..3 {
                let shifted = |sign: f64| {
                    let mut v = [theta.com_offset[0], theta.com_offset[1], theta.h];
                    v[j] += sign * eps;
                    let t = OnlineParams {
                        com_offset: [v[0], v[1]],
                        h: v[2],
                    };
                    model.linearize(sample, &t).residual
                };
                let (plus, minus) = (shifted(1.0), shifted(-1.0));
                for i in 0..3 {
                    let numeric = (plus[i] - minus[i]) / (2.0 * eps);
                    let analytic = lin.jacobian[i][j];
                    assert!(
                        (numeric - analytic).abs()
                            <= tolerance * (1.0 + numeric.abs().max(analytic.abs())),
                        "{kind}: ∂r{i}/∂θ{j} analytic {analytic}, numeric {numeric}"
                    );
                }
            }
            checked += 1;
        }
        assert!(checked >= 10, "{kind}: {checked} samples");
    }
}

/// Frames learned until the COM estimate came within 5 mm of `truth` and stayed there, and the
/// final error (as `pushlab eval` counts them, `experiment::ComTruth`).
fn frames_to_5mm(
    config: OnlineConfig,
    model: &PhysicsOnlyModel,
    data: &[Vec<Sample>],
    truth: [f64; 2],
) -> (Option<usize>, f64) {
    let mut learner = Chain::new(model, config);
    let steps: Vec<OnlineStep> = data.iter().flat_map(|t| learner.run(t)).collect();
    let com_after: Vec<[f64; 2]> = steps.iter().map(|s| s.theta_after.com_offset).collect();
    let found = ComTruth::of(&com_after, &learner.posterior(), truth).expect("frames");
    (found.frames_to_near, found.error_m)
}

#[test]
fn gauss_newton_finds_a_known_com_in_fewer_frames_than_gradient_descent() {
    let truth = [0.03, -0.025];
    let (set, data) = front_and_left(truth, 7);
    let model = physics_model(&set, &data);
    assert!(
        distance(model.theta0().com_offset, truth) > 0.03,
        "somewhere to go"
    );
    let (gd_frames, gd_error) = frames_to_5mm(OnlineConfig::default(), &model, &data, truth);
    let gauss_newton = OnlineConfig {
        optimizer: Optimizer::GaussNewton,
        ..OnlineConfig::default()
    };
    let (gn_frames, gn_error) = frames_to_5mm(gauss_newton, &model, &data, truth);
    let gn_frames = gn_frames.expect("Gauss–Newton settles within 5 mm");
    assert!(
        gd_frames.is_none_or(|gd| 2 * gn_frames <= gd),
        "Gauss–Newton {gn_frames} frames, gradient descent {gd_frames:?}"
    );
    assert!(
        gn_error <= 0.002 && gn_error <= gd_error,
        "final errors: GN {gn_error}, GD {gd_error}"
    );
}

#[test]
fn switching_the_optimiser_changes_theta_and_zero_steps_learns_nothing() {
    let (set, data) = front_and_left([0.03, -0.025], 9);
    let model = physics_model(&set, &data);
    let run = |config: OnlineConfig| {
        let mut learner = Chain::new(&model, config);
        learner.run(&data[0]);
        learner.theta()
    };
    let gd = run(OnlineConfig::default());
    let gn = run(OnlineConfig {
        optimizer: Optimizer::GaussNewton,
        ..OnlineConfig::default()
    });
    assert_ne!(gd, gn);
    let frozen = run(OnlineConfig {
        steps: 0,
        optimizer: Optimizer::GaussNewton,
        ..OnlineConfig::default()
    });
    assert_eq!(frozen, model.theta0());
}

#[test]
fn the_landscape_minimum_lies_within_one_cell_of_the_true_com() {
    let truth = [0.035, -0.02];
    let (set, data) = front_and_left(truth, 21);
    let model = physics_model(&set, &data);
    let h = set.setting.h.expect("the simulator writes h");
    let frames: Vec<Sample> = data.iter().take(4).flatten().copied().collect();
    let grid = ComGrid {
        centre: [0.0, 0.0],
        half_width: 0.1,
        cells: 64,
    };
    let landscape = com_landscape(&model, &frames, &grid, h, &|| false).expect("not cancelled");
    assert_eq!(landscape.loss.len(), 64 * 64);
    let (minimum, loss) = landscape.minimum().expect("finite losses");
    let cell = grid.cell_size();
    assert!(
        (minimum[0] - truth[0]).abs() <= cell && (minimum[1] - truth[1]).abs() <= cell,
        "minimum at {minimum:?} (loss {loss}), true COM {truth:?}, cell {cell}"
    );
    let (low, high) = landscape.range().expect("finite");
    assert!(
        high > 10.0 * low.max(1e-9),
        "a landscape with relief: {low}..{high}"
    );
    // The slice over h at the true COM is lowest near the true h.
    let hs: Vec<f64> = (1..=40).map(|i| h * i as f64 / 20.0).collect();
    let slice = h_slice(&model, &frames, truth, &hs);
    let best = (0..hs.len())
        .min_by(|&a, &b| slice[a].total_cmp(&slice[b]))
        .expect("values");
    assert!(
        (hs[best] - h).abs() <= h / 20.0 + 1e-12,
        "h slice lowest at {}, true {h}",
        hs[best]
    );
    // Cancelled before it starts: nothing.
    assert!(com_landscape(&model, &frames, &grid, h, &|| true).is_none());
}

/// What a page does with the landscape: polls it a slice at a time. Its one core computes the rows
/// one after another, a pause after each, to the same losses as in one piece; a cancel between two
/// rows ends it.
#[test]
fn the_landscape_in_slices_pauses_after_each_row_and_a_cancel_between_rows_ends_it() {
    let (set, data) = front_and_left([0.035, -0.02], 21);
    let model = physics_model(&set, &data);
    let h = set.setting.h.expect("the simulator writes h");
    // Few enough cells and frames that even a machine of many cores takes the rows one by one.
    let frames: Vec<Sample> = data[0].iter().take(40).copied().collect();
    let grid = ComGrid {
        centre: [0.0, 0.0],
        half_width: 0.1,
        cells: 10,
    };
    let whole = com_landscape(&model, &frames, &grid, h, &|| false).expect("not cancelled");
    let mut work = Box::pin(com_landscape_in_slices(&model, &frames, &grid, h, &|| {
        false
    }));
    let mut polls = 1;
    let sliced = loop {
        if let Some(landscape) = slices::poll_once(work.as_mut()) {
            break landscape.expect("not cancelled");
        }
        polls += 1;
    };
    drop(work);
    assert_eq!(polls, grid.cells + 1);
    assert_eq!(sliced.loss, whole.loss);

    let cancel = std::sync::atomic::AtomicBool::new(false);
    let check = || cancel.load(std::sync::atomic::Ordering::Relaxed);
    let mut work = Box::pin(com_landscape_in_slices(&model, &frames, &grid, h, &check));
    assert!(slices::poll_once(work.as_mut()).is_none());
    cancel.store(true, std::sync::atomic::Ordering::Relaxed);
    assert_eq!(
        slices::poll_once(work.as_mut()).map(|l| l.is_none()),
        Some(true)
    );
}

#[test]
fn a_rollout_of_one_step_is_the_one_step_prediction_and_the_true_model_tracks_the_recording() {
    let truth = [0.02, -0.015];
    let (set, data) = front_and_left(truth, 31);
    let model = physics_model(&set, &data);
    let theta = OnlineParams {
        com_offset: truth,
        h: set.setting.h.expect("true h"),
    };
    let (trajectory, _) = set
        .trajectories
        .iter()
        .zip(&set.sliding_fractions)
        .find(|(_, sliding)| **sliding == 0.0)
        .expect("a sticking push");
    let start = 12;
    let one = rollout(&model, trajectory, start, 1, 1, &theta);
    let sample = sample_at(trajectory, start, 1).expect("a sample");
    let motion = model.predict(&sample.input, &theta).motion;
    let expected = trajectory.frames[start]
        .object
        .moved_by(nalgebra::Vector2::from(motion.translation), motion.rotation);
    assert_eq!(one.poses, vec![(start + 1, expected)]);

    // The model with the simulator's own COM and h, on a noise-free sticking push, stays with the
    // recorded poses for 20 steps; with a COM 5 cm off it drifts away.
    let twenty = rollout(&model, trajectory, start, 1, 20, &theta);
    assert_eq!(twenty.poses.len(), 20);
    let (offset, yaw) = twenty.final_error(trajectory).expect("poses");
    assert!(
        offset < 0.002 && yaw.abs() < 0.01,
        "true θ: {offset} m, {yaw} rad"
    );
    let wrong = OnlineParams {
        com_offset: [truth[0] - 0.05, truth[1] + 0.05],
        ..theta
    };
    let (wrong_offset, wrong_yaw) = rollout(&model, trajectory, start, 1, 20, &wrong)
        .final_error(trajectory)
        .expect("poses");
    assert!(wrong_offset > 3.0 * offset.max(1e-4) || wrong_yaw.abs() > 3.0 * yaw.abs().max(1e-3));
    // At the end of the recording a rollout stops.
    let end = trajectory.frames.len() - 3;
    assert_eq!(
        rollout(&model, trajectory, end, 1, 20, &theta).poses.len(),
        2
    );
}

/// A long recording whose object changes late: 10,000 frames of the linear toy with one `θ`, then
/// 5,000 with another. Gauss–Newton's posterior forgets (`MEMORY_FRAMES`, 2000): the first θ's
/// frames keep `e^(−5000/2000)` ≈ 8 % of their weight, and it ends 7 % of the way back towards the
/// first θ. Without forgetting it ended 66 % of the way back (its gain falls as one over the frames
/// seen), which gradient descent's constant steps do not suffer from.
#[test]
fn gauss_newton_forgets_and_follows_a_change_late_in_a_long_recording() {
    use pushlab_core::learn::uncertainty::MEMORY_FRAMES;
    let first = OnlineParams {
        com_offset: [0.03, -0.02],
        h: 0.42,
    };
    let second = OnlineParams {
        com_offset: [-0.01, 0.02],
        h: 0.30,
    };
    let mut rng = SplitMix64::new(5);
    let mut samples = toy_samples(&mut rng, &first, 10_000, 0.05);
    samples.extend(toy_samples(&mut rng, &second, 5_000, 0.05));
    let mut learner = Chain::new(LinearToy, GAUSS_NEWTON);
    learner.run(&samples);
    let end = theta_vector(&learner.theta());
    let (first, second) = (theta_vector(&first), theta_vector(&second));
    assert!(
        (end - second).norm() < 0.15 * (first - second).norm(),
        "after {} frames of the second θ ({} frames remembered) Gauss–Newton ended at {end:?}, \
         the second θ is {second:?}",
        5_000,
        MEMORY_FRAMES
    );
}
