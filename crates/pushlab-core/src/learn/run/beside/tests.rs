use std::sync::Arc;

use crate::geometry::{Outline, Pose2};
use crate::learn::{ModelWeight, OnlineConfig, OnlineRun, WeightConfig};
use crate::model::{
    FrameLoss, Loss, LossScale, OnlineModel, PhysicsOnlyModel, SharedOnlineModel,
    samples_from_trajectory,
};
use crate::trajectory::{Frame, Trajectory};

/// A 10 cm box pushed along +x at 100 Hz for `frames` frames, turning.
fn push(frames: usize) -> Arc<Trajectory> {
    let frames = (0..frames)
        .map(|i| {
            let t = i as f64 * 0.01;
            let object = Pose2::new(0.05 * t, 0.002 * (3.0 * t).sin(), 0.3 * t);
            let robot = object.point_in_world(nalgebra::Point2::new(-0.06, 0.01));
            Frame {
                time: t,
                robot,
                object,
            }
        })
        .collect();
    Arc::new(Trajectory::new(frames))
}

/// Two physics-only models that differ (the box's depth, so the contact point), standing in for
/// the combined model and physics alone: what matters here is that their predictions differ.
fn model(trajectory: &Trajectory, depth: f64) -> SharedOnlineModel {
    let outline = Outline::rectangle(depth, 0.1).expect("valid box");
    let mut scale = LossScale::from_samples(&samples_from_trajectory(trajectory, 1));
    scale.sigma_pos = scale.sigma_pos.map(|s| s.max(1e-3));
    scale.sigma_rot = scale.sigma_rot.max(1e-3);
    Arc::new(PhysicsOnlyModel::new(outline, 0.01, 0.03, scale))
}

fn runs(trajectory: &Arc<Trajectory>) -> (OnlineRun, OnlineRun) {
    let config = OnlineConfig::default();
    let run = |depth| OnlineRun::new(model(trajectory, depth), Arc::clone(trajectory), 1, config);
    (run(0.1), run(0.13))
}

fn beside(trajectory: &Arc<Trajectory>) -> OnlineRun {
    let (combined, physics) = runs(trajectory);
    combined.with_physics_beside(physics, ModelWeight::new(WeightConfig::default()))
}

#[test]
fn the_weights_kept_beside_a_run_are_evals_weights_of_the_two_runs_apart() {
    let trajectory = push(300);
    let skip: Vec<bool> = (0..300).map(|k| (120..130).contains(&k)).collect();
    let mut run = beside(&trajectory);
    run.learn_all(&skip);
    // eval: the two runs learned apart, then weighed.
    let (mut combined, mut physics) = runs(&trajectory);
    combined.learn_all(&skip);
    physics.learn_all(&skip);
    let mut weight = ModelWeight::new(WeightConfig::default());
    combined.weigh_against(&physics, &mut weight);
    assert_eq!(run.model_weight(), Some(&weight));
    assert_eq!(
        run.physics_beside().map(OnlineRun::checkpoints),
        Some(physics.checkpoints())
    );
    let last = weight.frames().last().expect("frames weighed");
    assert!(
        last.weight.pos != 0.5 && last.weight.rot != 0.5,
        "the weights moved"
    );
}

#[test]
fn rewinding_the_run_rewinds_the_weights_and_learning_again_gives_the_same_bits() {
    let trajectory = push(300);
    let mut run = beside(&trajectory);
    run.learn_all(&[]);
    let first = run.model_weight().cloned();
    // A label painted after learning: everything from it is learned again, the weights too, as a
    // run that had the label from the start.
    let skip: Vec<bool> = (0..300).map(|k| k == 150).collect();
    run.learn_all(&skip);
    let mut labelled = beside(&trajectory);
    labelled.learn_all(&skip);
    assert_eq!(run.model_weight(), labelled.model_weight());
    assert_ne!(run.model_weight().cloned(), first);
    // Back to the start and again.
    run.reset();
    assert_eq!(run.model_weight().map(|w| w.frames().len()), Some(0));
    run.learn_all(&skip);
    assert_eq!(run.model_weight(), labelled.model_weight());
    // Steering θ at frame 100 keeps the weights before it and drops the rest until learned again.
    run.set_theta_at(100, run.theta_at(100));
    assert_eq!(run.model_weight().map(|w| w.frames().len()), Some(100));
}

#[test]
fn a_run_grown_frame_by_frame_weighs_as_one_made_whole() {
    let whole = push(200);
    let mut grown = beside(&Arc::new(Trajectory::new(whole.frames[..20].to_vec())));
    grown.learn_all(&[]);
    for chunk in whole.frames[20..].chunks(7) {
        grown.extend(chunk.iter().copied());
        let frontier = grown.frontier();
        grown.learn_through(frontier, grown.sample_count(), &[]);
    }
    let mut at_once = beside(&whole);
    at_once.learn_all(&[]);
    assert_eq!(grown.model_weight(), at_once.model_weight());
    // The physics-only run shares the grown trajectory rather than holding a copy of it.
    let physics = grown.physics_beside().expect("physics beside");
    assert!(Arc::ptr_eq(
        grown.shared_trajectory(),
        physics.shared_trajectory()
    ));
    assert_eq!(
        physics.fixed(),
        at_once
            .physics_beside()
            .map(OnlineRun::fixed)
            .unwrap_or_default()
    );
}

#[test]
fn following_two_runs_predicts_each_frame_with_the_theta_it_had_then() {
    let trajectory = push(150);
    let (mut a, mut b) = runs(&trajectory);
    a.learn_through(0, 100, &[]);
    b.learn_through(0, 100, &[]);
    // A run's loss at frame k is its prediction with θ at frame k (before learning from k): the
    // prediction the weighting blends.
    for k in 0..100 {
        let sample = a.sample(k).expect("a sample");
        let predicted = a.model().predict(&sample.input, &a.theta_at(k));
        let loss = FrameLoss::of(&Loss::of(
            &predicted.motion,
            &sample.target,
            &a.model().loss_scale(),
        ));
        assert_eq!(Some(loss), a.learned()[k], "frame {k}");
    }
    // With all the weight on one run the blend is that run's own prediction: its learned losses.
    let all_on_a = WeightConfig {
        half_life_s: 1e-9,
        prior: 1.0,
    };
    let mut weight = ModelWeight::new(all_on_a);
    a.weigh_against(&b, &mut weight);
    assert_eq!(weight.frames().len(), 100);
    for f in weight.frames() {
        let learned = a.learned()[f.frame].expect("learned");
        let w = f.weight;
        assert!(w.pos > 0.99 && w.rot > 0.99, "{w:?}");
        assert!((f.loss.total() - learned.total()).abs() <= 0.03 * learned.total() + 1e-9);
    }
    // Following again later takes in only the frames learned since.
    a.learn_through(100, 120, &[]);
    b.learn_through(100, 120, &[]);
    a.weigh_against(&b, &mut weight);
    assert_eq!(weight.frames().len(), 120);
    assert_eq!(weight.frames()[119].frame, 119);
}
