use super::*;
use crate::geometry::Outline;
use crate::model::{LossScale, ObjectMotion, PhysicsOnlyModel, SampleInput};
use crate::rng::SplitMix64;

/// Lynch's model alone on a 12 × 16 cm box pushed by a 1 cm disc.
fn physics() -> PhysicsOnlyModel {
    PhysicsOnlyModel::new(
        Outline::rectangle(0.12, 0.16).expect("valid box"),
        0.01,
        0.005,
        LossScale {
            sigma_pos: [2e-4, 2e-4],
            sigma_rot: 2e-3,
        },
    )
}

/// Pushes on the front face (x = −6 cm) and on the bottom face (y = −8 cm), at several contact
/// offsets and angles, each moved as `model` predicts with `truth`, plus `noise` (Gaussian, metres
/// and radians per unit) on the targets.
fn pushes(model: &PhysicsOnlyModel, truth: &OnlineParams, noise: f64) -> Vec<Sample> {
    let mut rng = SplitMix64::new(7);
    let mut samples = Vec::new();
    for k in 0..40 {
        let along = -0.045 + 0.09 * (k as f64 / 39.0);
        let angle = 0.3 * ((k * 7 % 11) as f64 / 10.0 - 0.5);
        let (c, s) = (angle.cos(), angle.sin());
        for (pusher, motion) in [
            ([-0.07, along], [0.002 * c, 0.002 * s]),
            ([along, -0.09], [-0.002 * s, 0.002 * c]),
        ] {
            let input = SampleInput {
                robot_in_object: pusher,
                robot_motion_in_object: motion,
            };
            let m = model.predict(&input, truth).motion;
            samples.push(Sample {
                input,
                target: ObjectMotion {
                    translation: [
                        m.translation[0] + noise * rng.normal(),
                        m.translation[1] + noise * rng.normal(),
                    ],
                    rotation: m.rotation + 10.0 * noise * rng.normal(),
                },
                frame: samples.len(),
            });
        }
    }
    samples
}

const TRUTH: OnlineParams = OnlineParams {
    com_offset: [0.012, -0.018],
    h: 0.045,
};

#[test]
fn on_pushes_made_by_the_model_it_finds_the_theta_that_made_them() {
    let model = physics();
    let samples = pushes(&model, &TRUTH, 0.0);
    // θ_online(0) (the centre, a uniform pressure's h) predicts them poorly: there is something to find.
    let at_theta0 = mean_loss(&model, &samples, &model.theta0());
    assert!(at_theta0 > 1.0, "{at_theta0}");
    let fit = best_fit(&model, &samples, &|| false).expect("samples");
    let t = fit.theta;
    assert!(
        (t.com_offset[0] - TRUTH.com_offset[0]).abs() < 1e-5,
        "{t:?}"
    );
    assert!(
        (t.com_offset[1] - TRUTH.com_offset[1]).abs() < 1e-5,
        "{t:?}"
    );
    assert!((t.h - TRUTH.h).abs() < 1e-5, "{t:?}");
    assert!(fit.mean_loss < 1e-8, "{}", fit.mean_loss);
    assert!(fit.nmse.pos < 1e-8 && fit.nmse.rot < 1e-8, "{:?}", fit.nmse);
}

#[test]
fn with_noise_it_fits_at_least_as_well_as_the_truth_and_reports_its_own_loss() {
    let model = physics();
    let samples = pushes(&model, &TRUTH, 2e-4);
    let fit = best_fit(&model, &samples, &|| false).expect("samples");
    let at_truth = mean_loss(&model, &samples, &TRUTH);
    assert!(fit.mean_loss <= at_truth, "{} > {at_truth}", fit.mean_loss);
    assert!((fit.mean_loss - mean_loss(&model, &samples, &fit.theta)).abs() < 1e-12);
    // Noise of 0.2 mm moves the best COM by well under a millimetre with 80 frames.
    let error = (fit.theta.com_offset[0] - TRUTH.com_offset[0])
        .hypot(fit.theta.com_offset[1] - TRUTH.com_offset[1]);
    assert!(error < 1e-3, "{error}");
}

#[test]
fn the_best_theta_stays_inside_the_footprint() {
    // Targets a COM far outside the box would explain best: the fit stops at the boundary.
    let model = physics();
    let outside = OnlineParams {
        com_offset: [0.0, 0.2],
        h: 0.05,
    };
    let samples = pushes(&model, &outside, 0.0);
    let fit = best_fit(&model, &samples, &|| false).expect("samples");
    let bounds = OnlineModel::bounds(&model).expect("an outline");
    assert!(bounds.com_inside(fit.theta.com_offset), "{:?}", fit.theta);
    assert!(fit.theta.h <= bounds.h_max(fit.theta.com_offset.into()) + 1e-12);
}

#[test]
fn without_samples_or_when_cancelled_there_is_no_fit() {
    let model = physics();
    assert!(best_fit(&model, &[], &|| false).is_none());
    let samples = pushes(&model, &TRUTH, 0.0);
    assert!(best_fit(&model, &samples, &|| true).is_none());
}

#[test]
fn it_polls_as_often_as_it_says_so_that_a_caller_can_show_progress() {
    let model = physics();
    let samples = pushes(&model, &TRUTH, 0.0);
    let polls = std::cell::Cell::new(0);
    best_fit(&model, &samples, &|| {
        polls.set(polls.get() + 1);
        false
    })
    .expect("samples");
    assert_eq!(polls.get(), POLLS);
}

/// What a page does: polls the search a slice at a time. It stops after each grid row and each
/// refinement, finds what the search in one piece finds, and a cancel between slices ends it.
#[test]
fn in_slices_it_pauses_at_each_poll_and_finds_the_same_fit() {
    let model = physics();
    let samples = pushes(&model, &TRUTH, 1e-4);
    let whole = best_fit(&model, &samples, &|| false);
    let polled = std::cell::Cell::new(0);
    let check = || {
        polled.set(polled.get() + 1);
        false
    };
    let mut work = Box::pin(best_fit_in_slices(&model, &samples, &check));
    let mut polls = 1;
    let sliced = loop {
        if let Some(fit) = crate::slices::poll_once(work.as_mut()) {
            break fit;
        }
        polls += 1;
    };
    drop(work);
    assert_eq!(sliced, whole);
    // A pause after every poll of the cancel: a slice holds one row or one refinement.
    assert_eq!(polls, polled.get() + 1);
    assert_eq!(polled.get(), POLLS);

    let cancelled = std::cell::Cell::new(false);
    let check = || cancelled.get();
    let mut work = Box::pin(best_fit_in_slices(&model, &samples, &check));
    assert_eq!(crate::slices::poll_once(work.as_mut()), None);
    cancelled.set(true);
    assert_eq!(crate::slices::poll_once(work.as_mut()), Some(None));
}
