use super::*;
use crate::geometry::{Outline, Pose2};
use crate::learn::{Optimizer, learn_step};
use crate::model::{LossScale, OnlineModel, PhysicsOnlyModel, samples_from_trajectory};
use crate::trajectory::Frame;

/// A 10 cm box pushed along +x at its face, turning slowly (as an off-centre COM would make it):
/// enough signal for learning to move θ.
fn push(frames: usize) -> Arc<Trajectory> {
    turning_push(frames, 0.3, [-0.05 - 0.01, 0.01])
}

/// The box pushed along +x at 5 cm/s for `frames` frames at 100 Hz, turning at `yaw_rate` rad/s,
/// the pusher held at `robot_in_object`.
fn turning_push(frames: usize, yaw_rate: f64, robot_in_object: [f64; 2]) -> Arc<Trajectory> {
    let frames = (0..frames)
        .map(|i| {
            let t = i as f64 * 0.01;
            let object = Pose2::new(0.05 * t, 0.0, yaw_rate * t);
            let robot = object.point_in_world(nalgebra::Point2::from(robot_in_object));
            Frame {
                time: t,
                robot,
                object,
            }
        })
        .collect();
    Arc::new(Trajectory::new(frames))
}

fn model(trajectory: &Trajectory) -> SharedOnlineModel {
    let outline = Outline::rectangle(0.1, 0.1).expect("valid box");
    let mut scale = LossScale::from_samples(&samples_from_trajectory(trajectory, 1));
    // This synthetic push barely moves sideways; keep the σ of a real push's millimetres.
    scale.sigma_pos = scale.sigma_pos.map(|s| s.max(1e-3));
    scale.sigma_rot = scale.sigma_rot.max(1e-3);
    Arc::new(PhysicsOnlyModel::new(outline, 0.01, 0.002, scale))
}

fn run_with(config: OnlineConfig) -> OnlineRun {
    let trajectory = push(200);
    OnlineRun::new(model(&trajectory), trajectory, 1, config)
}

fn run() -> OnlineRun {
    run_with(OnlineConfig::default())
}

#[test]
fn learning_moves_theta_and_keeps_a_checkpoint_per_frame() {
    let mut run = run();
    let theta0 = run.theta0();
    run.learn_through(0, 50, &[]);
    assert_eq!(run.frontier(), 50);
    assert_eq!(run.checkpoints().len(), 51);
    assert_ne!(
        run.theta_at(50),
        theta0,
        "50 steps of learning changed nothing"
    );
    for k in 0..50 {
        let loss = run.learned()[k].expect("every frame was learned");
        // The step learned at k predicted with θ(k) and moved it to θ(k + 1).
        let step = run.evaluate(k).expect("frame has a sample");
        assert_eq!(step.theta_before, run.theta_at(k));
        assert_eq!(FrameLoss::of(&step.loss), loss);
        let relearned = run.model().online_step(
            &run.sample(k).expect("sample"),
            &run.theta_at(k),
            &run.config().descent(),
        );
        assert_eq!(relearned.theta_after, run.theta_at(k + 1));
    }
}

/// Independent of the run's bookkeeping: the chain of [`learn_step`]s over the samples that are not
/// skipped, as Algorithm 1 states it.
fn chained(run: &OnlineRun, skip: &[bool]) -> (Vec<OnlineParams>, Vec<FrameLoss>, Posterior) {
    let model = run.model().clone();
    let mut state = OnlineState::start(model.as_ref(), run.config().optimizer);
    let (mut thetas, mut losses) = (Vec::new(), Vec::new());
    for sample in samples_from_trajectory(run.trajectory(), run.horizon()) {
        if sample_is_skipped(skip, sample.frame, run.horizon()) {
            continue;
        }
        let (step, next) = learn_step(model.as_ref(), &sample, &state, &run.config());
        losses.push(FrameLoss::of(&step.loss));
        thetas.push(next.theta);
        state = next;
    }
    (thetas, losses, state.posterior)
}

#[test]
fn learning_a_whole_recording_is_algorithm_1_over_the_frames_not_skipped() {
    for optimizer in Optimizer::ALL {
        let mut run = run_with(OnlineConfig {
            optimizer,
            ..OnlineConfig::default()
        });
        let mut skip = vec![false; 200];
        skip[40..47].fill(true);
        run.learn_all(&skip);
        let (thetas, losses, posterior) = chained(&run, &skip);
        let steps: Vec<_> = run.learned_steps().collect();
        assert_eq!(steps.len(), losses.len(), "{optimizer:?}");
        for ((_, loss, theta), (want_loss, want_theta)) in
            steps.iter().zip(losses.iter().zip(&thetas))
        {
            assert_eq!(loss, want_loss);
            assert_eq!(theta, want_theta);
        }
        assert_eq!(run.posterior(), &posterior, "{optimizer:?}");
        assert_eq!(run.frontier(), run.sample_count());
    }
}

#[test]
fn scrubbing_back_restores_the_exact_earlier_theta_and_replay_is_identical() {
    for optimizer in Optimizer::ALL {
        let mut run = run_with(OnlineConfig {
            optimizer,
            ..OnlineConfig::default()
        });
        run.learn_through(0, 180, &[]);
        let all = run.checkpoints().to_vec();
        let spreads = run.spreads().to_vec();
        let posterior = *run.posterior();
        // Back to 130 (two keyframes back from the frontier), then the same frames again.
        let theta = run.theta_at(130);
        run.set_theta_at(130, theta);
        assert_eq!(run.frontier(), 130);
        assert_eq!(run.take_cut(), Some(130));
        assert_eq!(run.take_cut(), None, "taken once");
        run.learn_through(130, 180, &[]);
        assert_eq!(run.checkpoints(), &all[..], "{optimizer:?}");
        assert_eq!(run.spreads(), &spreads[..], "{optimizer:?}");
        assert_eq!(run.posterior(), &posterior, "{optimizer:?}");
    }
}

#[test]
fn steering_drops_the_future_and_beyond_the_frontier_theta_is_held() {
    let mut run = run();
    run.learn_through(0, 40, &[]);
    let mut steered = run.theta_at(20);
    steered.com_offset = [0.01, -0.02];
    run.set_theta_at(20, steered);
    assert_eq!(run.frontier(), 20);
    assert_eq!(run.theta_at(20).com_offset, [0.01, -0.02]);
    assert_eq!(run.theta_at(150), run.theta_at(20));
    // Steering ahead of the frontier holds θ over the gap.
    run.set_theta_at(60, run.theta0());
    assert_eq!(run.frontier(), 60);
    assert!(run.learned()[20..60].iter().all(Option::is_none));
    assert_eq!(run.theta_at(59).com_offset, [0.01, -0.02]);
}

#[test]
fn a_new_rule_learns_the_future_again_with_it() {
    let mut run = run();
    run.learn_through(0, 100, &[]);
    let before = run.theta_at(100);
    let fixed = OnlineConfig::fixed();
    run.set_config_at(50, fixed);
    assert_eq!(run.frontier(), 50);
    run.learn_through(50, 100, &[]);
    assert_eq!(run.config(), fixed);
    assert_eq!(run.theta_at(100), run.theta_at(50), "no steps: θ held");
    assert_ne!(run.theta_at(100), before);
}

#[test]
fn learn_this_frame_lowers_the_loss_at_that_frame() {
    let mut run = run();
    let before = run.evaluate(10).expect("frame 10 has a sample");
    let step = run.learn_this_frame(10).expect("frame 10 has a sample");
    let after = run.evaluate(10).expect("frame 10 has a sample");
    assert_eq!(step.theta_before, before.theta_before);
    assert_eq!(run.theta_at(10), step.theta_after);
    assert!(
        after.loss.total() < before.loss.total(),
        "loss {} → {}",
        before.loss.total(),
        after.loss.total()
    );
}

#[test]
fn the_last_frames_have_no_sample_and_reset_forgets_everything() {
    let mut run = run();
    assert!(run.learn_this_frame(199).is_none());
    run.learn_through(0, 500, &[]);
    assert_eq!(run.frontier(), 199);
    assert!(run.mean_losses().is_some());
    run.reset();
    assert_eq!(run.frontier(), 0);
    assert_eq!(run.theta_at(100), run.theta0());
    assert_eq!(run.mean_losses(), None);
    assert_eq!(run.take_cut(), Some(0));
}

#[test]
fn mean_losses_average_the_learned_frames_and_the_fixed_losses_there() {
    let mut run = run();
    let mut skip = vec![false; 200];
    skip[10..20].fill(true);
    run.learn_through(0, 60, &skip);
    let means = run.mean_losses().expect("frames learned");
    let learned: Vec<(usize, FrameLoss)> = run.learned_steps().map(|(k, l, _)| (k, l)).collect();
    assert_eq!(means.frames, learned.len());
    assert_eq!(learned.len(), 60 - 11, "frames 9..20 touch a skipped frame");
    let n = learned.len() as f64;
    let online_pos = learned.iter().map(|(_, l)| l.pos).sum::<f64>() / n;
    let fixed_rot = learned
        .iter()
        .map(|(k, _)| run.fixed()[*k].rot)
        .sum::<f64>()
        / n;
    assert_eq!(means.online_pos, online_pos);
    assert_eq!(means.fixed_rot, fixed_rot);
}

#[test]
fn frames_flagged_to_skip_hold_theta_and_the_rest_learn() {
    let mut run = run();
    let mut skip = vec![false; 200];
    skip[20..25].fill(true);
    run.learn_through(0, 40, &skip);
    for k in 0..40 {
        // Horizon 1: the sample at k uses frames k and k + 1.
        let skipped = (19..25).contains(&k);
        assert_eq!(run.learned()[k].is_none(), skipped, "frame {k}");
        if skipped {
            assert_eq!(
                run.checkpoints()[k + 1],
                run.checkpoints()[k],
                "θ held at {k}"
            );
        }
    }
    assert_ne!(
        run.checkpoints()[40],
        run.checkpoints()[0],
        "the other frames learned"
    );
    // Playing over the same frames again changes nothing.
    let before = run.checkpoints().to_vec();
    run.take_cut();
    run.learn_through(10, 40, &skip);
    assert_eq!(run.checkpoints(), &before[..]);
    assert_eq!(run.take_cut(), None, "nothing was dropped");

    // Flagging frames that were already learned: playing over them again holds θ there.
    skip[30..33].fill(true);
    run.learn_through(0, 40, &skip);
    assert_eq!(
        run.take_cut(),
        Some(29),
        "the first frame done the other way"
    );
    for k in 29..33 {
        assert!(run.learned()[k].is_none(), "frame {k} still learned");
    }
    assert!(
        run.learned()[35].is_some(),
        "the frames after are learned again"
    );
    // And erasing the flags learns them again.
    skip.fill(false);
    run.learn_through(0, 40, &skip);
    assert!(run.learned()[..40].iter().all(Option::is_some));
}

/// The 10 cm box pushed at the middle of a face and turning faster than any COM on it can
/// explain: learning wants the COM far outside the box, and every optimiser is kept inside it (and
/// `h` below the farthest corner).
#[test]
fn every_optimiser_keeps_theta_physical_where_the_data_ask_for_the_impossible() {
    let trajectory = turning_push(200, 1.0, [-0.06, 0.0]);
    for config in [
        OnlineConfig {
            lr: 500.0,
            ..OnlineConfig::default()
        },
        OnlineConfig {
            optimizer: Optimizer::GaussNewton,
            ..OnlineConfig::default()
        },
    ] {
        let model = model(&trajectory);
        let mut run = OnlineRun::new(model.clone(), trajectory.clone(), 1, config);
        run.learn_all(&[]);
        let mut wanted_outside = false;
        for (k, theta) in run.checkpoints().iter().enumerate() {
            let [x, y] = theta.com_offset;
            assert!(
                x.abs() <= 0.05 + 1e-12 && y.abs() <= 0.05 + 1e-12,
                "{config:?}: COM ({x}, {y}) outside the box at frame {k}"
            );
            let farthest = (0.05 + x.abs()).hypot(0.05 + y.abs());
            assert!(
                theta.h <= farthest + 1e-12,
                "{config:?}: h {} at frame {k}",
                theta.h
            );
            // What the optimiser's own step asked for, before the bounds.
            if config.optimizer == Optimizer::Gd
                && let Some(sample) = run.sample(k)
            {
                let raw = model
                    .online_step(&sample, theta, &config.descent())
                    .theta_after;
                wanted_outside |= raw.com_offset.iter().any(|c| c.abs() > 0.05 + 1e-9);
            }
        }
        assert!(
            config.optimizer != Optimizer::Gd || wanted_outside,
            "the test push never asked for a COM outside the box"
        );
        // A user's steering outside the box lands on its edge.
        run.set_theta_at(
            10,
            OnlineParams {
                com_offset: [0.2, 0.0],
                h: 0.03,
            },
        );
        assert_eq!(run.theta_at(10).com_offset, [0.05, 0.0]);
    }
}

#[test]
fn a_run_continuing_from_the_start_state_learns_as_a_new_run() {
    for optimizer in [Optimizer::Gd, Optimizer::GaussNewton] {
        let config = OnlineConfig {
            optimizer,
            ..OnlineConfig::default()
        };
        let trajectory = push(120);
        let learner = model(&trajectory);
        let start = OnlineState::start(learner.as_ref(), optimizer);
        let mut fresh = OnlineRun::new(learner.clone(), trajectory.clone(), 1, config);
        let mut from_start = OnlineRun::continuing(learner, trajectory, 1, config, &start);
        fresh.learn_all(&[]);
        from_start.learn_all(&[]);
        assert_eq!(
            fresh.checkpoints(),
            from_start.checkpoints(),
            "{optimizer:?}"
        );
        assert_eq!(fresh.spreads(), from_start.spreads(), "{optimizer:?}");
    }
}

#[test]
fn a_continuing_run_starts_where_the_earlier_push_ended_and_resets_there() {
    let config = OnlineConfig {
        optimizer: Optimizer::GaussNewton,
        ..OnlineConfig::default()
    };
    let first_push = push(120);
    let learner = model(&first_push);
    let mut first = OnlineRun::new(learner.clone(), first_push, 1, config);
    first.learn_all(&[]);
    let ended = first.end_state();
    assert_ne!(ended.theta, first.theta0(), "the first push learned");

    // The second push of the same box, on the side face and turning the other way.
    let second_push = turning_push(120, -0.2, [0.01, -0.05 - 0.01]);
    let mut second = OnlineRun::continuing(learner.clone(), second_push.clone(), 1, config, &ended);
    assert_eq!(
        second.theta_at(0),
        ended.theta,
        "starts at the first push's end"
    );
    let fresh = OnlineRun::new(learner, second_push, 1, config);
    let (carried, prior) = (second.spread_at(0), fresh.spread_at(0));
    let trace = |s: Spread| s.com_cov[0] + s.com_cov[2];
    assert!(
        trace(carried) < trace(prior),
        "the posterior carries what the first push saw: {carried:?} against the prior {prior:?}"
    );
    // The fixed run is still θ_online(0)'s.
    assert_eq!(second.fixed(), fresh.fixed());

    second.learn_through(0, 60, &[]);
    assert_ne!(second.theta_at(60), ended.theta);
    second.reset();
    assert_eq!(second.frontier(), 0);
    assert_eq!(
        second.theta_at(0),
        ended.theta,
        "reset returns to the carried start"
    );
    assert_eq!(second.spread_at(0), carried);
}

#[test]
fn a_long_recordings_fixed_run_shared_between_cores_is_the_serial_one() {
    // Long enough to be shared (more than two slices of the fixed run), turning, so that the
    // losses differ from frame to frame.
    let trajectory = turning_push(3 * FIXED_PER_WORKER, 0.3, [-0.06, 0.01]);
    let model = model(&trajectory);
    let run = OnlineRun::new(
        Arc::clone(&model),
        Arc::clone(&trajectory),
        1,
        OnlineConfig::default(),
    );
    let theta0 = model.theta0();
    let serial: Vec<FrameLoss> = samples_from_trajectory(&trajectory, 1)
        .iter()
        .map(|s| FrameLoss::of(&model.loss_at(s, &theta0)))
        .collect();
    assert_eq!(serial.len(), 3 * FIXED_PER_WORKER - 1);
    let distinct: std::collections::HashSet<_> = (serial.iter())
        .map(|l| (l.pos.to_bits(), l.rot.to_bits()))
        .collect();
    assert!(
        distinct.len() > 1000,
        "{} distinct: the order must show",
        distinct.len()
    );
    assert_eq!(run.fixed(), serial.as_slice());
}
