//! The controller on the sandbox's simulator: it reaches goals with the true θ and learning
//! online; the same seed is the same run; the pusher's target never moves faster than the pusher
//! may; frames the pusher is away in are not learned.
//!
//! Learning online against θ held fixed on an offset COM is measured on pairs past the bench's
//! (see the test); it reaches the goals sooner, not always more of them.

#![allow(clippy::unwrap_used)]

use std::path::Path;

use super::*;
use crate::geometry::Pose2;
use crate::learn::OnlineConfig;
use crate::model_file::ModelFile;
use crate::sandbox::mystery::{PUSHER_SPEED, RATE_HZ};
use crate::sandbox::{Mystery, MysteryObject};

fn model() -> crate::model::CombinedModel {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/default-model.json");
    ModelFile::load(&path).unwrap().combined
}

fn control(seed: u64, with: PlanWith, goal: Pose2) -> SandboxControl {
    control_drawing(seed, with, goal, 0)
}

/// The mystery of `seed` with the planner drawing from `stream` of that seed.
fn control_drawing(seed: u64, with: PlanWith, goal: Pose2, stream: u64) -> SandboxControl {
    let mystery = Mystery::draw(seed, MysteryObject::Box).unwrap();
    SandboxControl::new(
        mystery,
        None,
        &model(),
        with,
        OnlineConfig::default(),
        Goal::at(goal),
        PlannerConfig::default().drawing_from(seed, stream),
    )
    .unwrap()
}

const GOAL: Pose2 = Pose2 {
    position: nalgebra::Point2::new(0.25, 0.1),
    yaw: 0.4,
};

#[test]
fn with_the_true_theta_and_learning_online_it_reaches_the_goal_and_holds_it() {
    for (seed, with) in (1..=4).flat_map(|s| [(s, PlanWith::Truth), (s, PlanWith::Online)]) {
        let mut run = control(seed, with, GOAL);
        let outcome = run.run_to_goal(60.0, |_| {});
        assert!(outcome.reached, "seed {seed}, {with:?}: {outcome:?}");
        assert!(
            outcome.final_position_error_m <= 0.0105,
            "seed {seed}: {outcome:?}"
        );
        assert!(
            outcome.final_yaw_error_rad.abs() <= 3.05f64.to_radians(),
            "{outcome:?}"
        );
        // Held: the last steps hold the pusher still.
        let step = run.step();
        assert_eq!(step.phase, "holding");
    }
}

#[test]
fn the_same_seed_is_the_same_run_and_targets_keep_the_pushers_speed() {
    let log = |seed| {
        let mut run = control(seed, PlanWith::Online, GOAL);
        (0..150).map(|_| run.step()).collect::<Vec<_>>()
    };
    let (a, b) = (log(3), log(3));
    assert_eq!(a, b);
    let step_m = PUSHER_SPEED / RATE_HZ;
    for s in &a {
        let moved =
            ((s.target[0] - s.pusher[0]).powi(2) + (s.target[1] - s.pusher[1]).powi(2)).sqrt();
        assert!(moved <= step_m + 1e-9, "step {}: {moved} m", s.step);
    }
    assert!(a.iter().any(|s| s.phase == "moving") && a.iter().any(|s| s.phase == "pushing"));
}

#[test]
fn another_planner_stream_is_another_run_of_the_same_pair_and_stream_zero_the_measured_one() {
    let log = |stream| {
        let mut run = control_drawing(3, PlanWith::Online, GOAL, stream);
        (0..150).map(|_| run.step()).collect::<Vec<_>>()
    };
    let measured = PlannerConfig {
        seed: 3,
        ..PlannerConfig::default()
    };
    assert_eq!(PlannerConfig::default().drawing_from(3, 0), measured);
    let (zero, one) = (log(0), log(1));
    assert_eq!(
        zero[0].object, one[0].object,
        "the same object, where it starts"
    );
    let differ = zero.iter().zip(&one).filter(|(a, b)| a.target != b.target);
    assert!(differ.count() > 10, "stream 1 planned as stream 0 did");
}

#[test]
fn frames_the_pusher_is_away_in_are_not_learned() {
    let mut run = control(2, PlanWith::Online, GOAL);
    for _ in 0..40 {
        run.step();
    }
    // The first frames go round to the first push: θ is held over them.
    let sites = run.planner().sites();
    let frames = &run.run().trajectory().frames;
    let away = frames.iter().take_while(|f| is_away(sites, f)).count();
    assert!(away > 5, "{away}");
    assert_eq!(
        run.run().theta_at(away.saturating_sub(11)),
        run.run().theta0()
    );
}

#[test]
#[ignore = "a diagnosis: PAIR=n WITH=online cargo test -p pushlab-core --lib control::tests::diagnose -- --ignored --nocapture"]
fn diagnose() {
    let pair: u64 = std::env::var("PAIR")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let with = std::env::var("WITH")
        .ok()
        .and_then(|s| PlanWith::from_name(&s))
        .unwrap_or(PlanWith::Online);
    let goal = goal::pair_goal(pair);
    let mut run = control(pair, with, goal);
    let mut last = String::new();
    let mut segments = Vec::new();
    for _ in 0..1200 {
        if run.is_done() {
            break;
        }
        let s = run.step();
        if s.phase != last {
            segments.push(format!(
                "{:5.1}s {:8} err {:5.1} mm {:5.1}°",
                s.time_s,
                s.phase,
                s.position_error_m * 1e3,
                s.yaw_error_rad.to_degrees()
            ));
            last = s.phase.to_owned();
        }
    }
    eprintln!(
        "goal {goal:?}\n{}\n{:?}",
        segments.join("\n"),
        run.outcome()
    );
}

#[test]
fn poses_from_outside_reach_the_goal_through_live_inputs_grid_and_learner() {
    // The sandbox's simulator as the outside engine: its poses in, the targets out.
    let mystery = Mystery::draw(4, MysteryObject::Box).unwrap();
    let setting = mystery.setting();
    let mut sandbox = crate::sandbox::Sandbox::new(mystery, None);
    let mut control = PoseControl::new(
        &model(),
        &setting,
        PlanWith::Online,
        OnlineConfig::default(),
        Goal::at(GOAL),
        PlannerConfig::default(),
        crate::control::Pacing::sandbox(),
    )
    .unwrap();
    let mut steps = 0;
    while !control.is_done() && steps < 1200 {
        let step = control.step(
            steps as f64 / RATE_HZ,
            sandbox.pusher(),
            sandbox.object_pose(),
        );
        sandbox.hold(nalgebra::Point2::new(step.target[0], step.target[1]));
        sandbox.advance(1.0 / RATE_HZ);
        steps += 1;
    }
    assert!(control.is_done(), "not reached in {steps} steps");
    assert!(Goal::at(GOAL).is_within(&sandbox.object_pose()));
    // Learned as it went, on the grid's frames, with θ held while the pusher was away.
    let run = control.learner().run();
    assert!(
        run.trajectory().len() + 2 >= steps,
        "{} frames",
        run.trajectory().len()
    );
    assert_ne!(run.theta_at(run.frontier()), run.theta0());
}

#[test]
fn the_true_theta_from_outside_needs_the_settings_truth() {
    let mystery = Mystery::draw(4, MysteryObject::Box).unwrap();
    let refused = PoseControl::new(
        &model(),
        &mystery.public_setting(),
        PlanWith::Truth,
        OnlineConfig::default(),
        Goal::at(GOAL),
        PlannerConfig::default(),
        crate::control::Pacing::sandbox(),
    );
    let Err(why) = refused else {
        panic!("planned with a truth it does not have")
    };
    assert!(why.to_string().contains("com_offset and h"), "{why}");
}

#[test]
fn the_weighted_prediction_mixes_both_learned_runs_by_their_weights_and_reaches_goals() {
    let mut run = control(2, PlanWith::Weighted, GOAL);
    for _ in 0..80 {
        run.step();
    }
    let learned = run.run();
    let physics = learned
        .physics_beside()
        .expect("physics alone learns beside");
    let weighted = Weighted::of(learned).unwrap();
    let [combined_theta, physics_theta] = weighted.thetas();
    assert_eq!(combined_theta, learned.theta_at(learned.frontier()));
    assert_eq!(physics_theta, physics.theta_at(physics.frontier()));
    assert_ne!(physics_theta, physics.theta0(), "physics alone learned");
    let w = weighted.weights();
    assert!(
        w.pos > 0.0 && w.pos < 1.0 && w.rot > 0.0 && w.rot < 1.0,
        "{w:?}"
    );
    let input = crate::model::SampleInput {
        robot_in_object: [-0.2, 0.03],
        robot_motion_in_object: [0.004, 0.001],
    };
    let c = learned.model().predict(&input, &combined_theta).motion;
    let p = physics.model().predict(&input, &physics_theta).motion;
    let m = weighted.motion(&input);
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * (1.0 + b.abs());
    assert!(close(
        m.translation[0],
        w.pos * c.translation[0] + (1.0 - w.pos) * p.translation[0]
    ));
    assert!(close(
        m.translation[1],
        w.pos * c.translation[1] + (1.0 - w.pos) * p.translation[1]
    ));
    assert!(close(
        m.rotation,
        w.rot * c.rotation + (1.0 - w.rot) * p.rotation
    ));
    // It is what the controller plans with: the same pairs, planned otherwise, go otherwise.
    let log = |with| {
        let mut run = control(2, with, GOAL);
        (0..120).map(|_| run.step().target).collect::<Vec<_>>()
    };
    assert_ne!(log(PlanWith::Weighted), log(PlanWith::Online));
    for seed in 1..=3 {
        let mut run = control(seed, PlanWith::Weighted, GOAL);
        let outcome = run.run_to_goal(60.0, |_| {});
        assert!(outcome.reached, "seed {seed}: {outcome:?}");
    }
}

/// Pair 17 of the bench (`benches/control.rs`), with the sandbox's tracking noise (2 mm, 0.5°) on
/// every pose: planned from the raw poses, the box is still 22 mm off after 120 s; from the poses
/// filtered by `track` (the alpha–beta filter at 0.5, 0.1), it is reached in 56.6 s.
#[test]
fn planning_from_filtered_poses_reaches_a_goal_that_noisy_poses_miss() {
    let goal = goal::pair_goal(17);
    let run = |track| {
        let mystery = Mystery::draw(17, MysteryObject::Box).unwrap();
        let mut control = SandboxControl::new(
            mystery,
            Some(crate::sandbox::mystery::SANDBOX_NOISE),
            &model(),
            PlanWith::Online,
            OnlineConfig::default(),
            Goal::at(goal),
            PlannerConfig {
                seed: 17,
                track,
                ..PlannerConfig::default()
            },
        )
        .unwrap();
        control.run_to_goal(120.0, |_| {})
    };
    let raw = run(None);
    assert!(!raw.reached, "{raw:?}");
    let filtered = run(Some(track::TrackConfig {
        alpha: 0.5,
        beta: 0.1,
    }));
    assert!(filtered.reached, "{filtered:?}");
    assert!((filtered.time_s - 56.6).abs() < 0.05, "{filtered:?}");
}

/// MuJoCo's pair 73 at 70 s, learning online (`experiments/control/mujoco_control.py`): the box
/// 10.3 mm from its goal, the pusher a few centimetres from its back face. The planner chose a
/// push, went to its start and began it, and the next step weighed the line in afresh against
/// every other push and went elsewhere: in and out of the approach, never touching, until the
/// 120 s limit. A push begun is kept until it touches; here the box does not move until then.
#[test]
fn a_push_begun_is_carried_in_to_the_object_not_abandoned_on_its_way_in() {
    let setting = crate::recording::Setting::of_object(
        "MuJoCo's pair 73",
        crate::recording::ObjectShape::Box {
            width: 0.3,
            length: 0.4,
        },
        0.175,
    );
    let outline = setting.object.outline().unwrap();
    let combined = model();
    // The model as `--pipe` plans with it: on the setting's object.
    let model = learner_for(&combined, &setting, PlanWith::Online).unwrap();
    let goal = Goal::at(Pose2::new(
        -0.30346608306917755,
        0.07596493992436402,
        0.13624547050102592,
    ));
    let theta = crate::model::OnlineParams {
        com_offset: [0.003963284660130739, 0.003992623183876276],
        h: 0.13563020527362823,
    };
    let object = Pose2::new(-0.30223174710577083, 0.065774195338507, 0.13631277260131375);
    let pacing = Pacing {
        pusher_speed: 0.04,
        control_hz: 10.0,
        grid_hz: 10.0,
    };
    let mut planner = Planner::paced(
        &outline,
        0.175,
        goal,
        pacing,
        combined.horizon(),
        PlannerConfig::default(),
    );
    let mut pusher = nalgebra::Point2::new(0.06241370039879296, -0.04148283680784727);
    let gap = |planner: &Planner, pusher| planner.sites().gap(object.point_in_object(pusher));
    let mut phases = String::new();
    for _ in 0..100 {
        if gap(&planner, pusher) <= 5e-4 {
            return;
        }
        let plan = planner.step(&object, pusher, model.as_ref(), &theta);
        phases.push(plan.phase.map_or('-', |p| p.name().chars().next().unwrap()));
        pusher = plan.target;
    }
    panic!(
        "not touching after 10 s, {:.1} mm away; phases {phases}",
        gap(&planner, pusher) * 1e3
    );
}

/// Learning online against θ held at θ_online(0) on boxes whose hidden COM is at least 4 cm off
/// their centre: the first ten such pairs from seed 131, past the bench's 31–130 (so neither the
/// pairs the planner was weighed on nor those its table measured). Learning online reaches at
/// least as many goals, and sooner over all, a miss counted at the 120 s limit. Measured on
/// all 65 such pairs of 131–230 (`--first 131 --with online,fixed`): 60 goals each, a mean of
/// 59.3 s against 63.9 s; from 5 cm, 40 against 43 of 44 goals, 60.6 s against 63.0 s. So the
/// claim tested is "sooner", not "more".
#[test]
fn on_an_offset_com_learning_online_reaches_the_goals_sooner_than_theta_fixed() {
    let pairs: Vec<u64> = (131..)
        .filter(|&seed| {
            let [x, y] = (Mystery::draw(seed, MysteryObject::Box).unwrap())
                .hidden
                .com_offset;
            x.hypot(y) >= 0.04
        })
        .take(10)
        .collect();
    let over_the_pairs = |with| {
        let runs = pairs.iter().map(|&seed| {
            let outcome = control(seed, with, goal::pair_goal(seed)).run_to_goal(120.0, |_| {});
            (usize::from(outcome.reached), outcome.time_s)
        });
        runs.fold((0, 0.0), |(n, t), (reached, time_s)| {
            (n + reached, t + time_s)
        })
    };
    let (online, fixed) = (
        over_the_pairs(PlanWith::Online),
        over_the_pairs(PlanWith::Fixed),
    );
    assert!(online.0 >= fixed.0, "goals: {online:?} against {fixed:?}");
    assert!(
        online.1 < fixed.1,
        "time over pairs {pairs:?}: {online:?} against {fixed:?}"
    );
}
