//! Push to goal in the sandbox, in the app's state: the controller pushes the mystery object to
//! a goal the student placed, planning with the model as the push's run learns it, and says when
//! the goal is reached; the same goal with θ held fixed is a different run; the CLI's controller
//! (`pushlab control --sandbox`) on the same mystery and goal reaches it too; `--pipe` answers
//! each line of poses from another program with a target no further than a step of the pusher;
//! the CLI's controller takes the learner's options.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use pushlab::app::initial_state;
use pushlab::app::state::sources::sandbox::SandboxCommand;
use pushlab::app::state::{AppState, Command, Persisted};
use pushlab_core::control::PlanWith;
use pushlab_core::geometry::wrap_angle;
use pushlab_core::sandbox::MysteryObject;
use serde_json::Value;

const GOAL: [f64; 3] = [0.25, 0.1, 0.4];

fn sandbox_with_goal(seed: u64, with: PlanWith) -> AppState {
    let mut state = initial_state(&[], Persisted::default());
    state.apply(Command::Sandbox(SandboxCommand::Start {
        seed,
        object: Some(MysteryObject::Box),
        noise: false,
        challenge: false,
        com: None,
    }));
    state.apply(Command::Sandbox(SandboxCommand::SetGoal(GOAL)));
    state.apply(Command::Sandbox(SandboxCommand::SetPlanWith(with)));
    state
}

/// Lets the app's frames pass (a tenth of a second each) until the controller lets go.
fn until_the_controller_stops(state: &mut AppState) -> usize {
    state.apply(Command::Sandbox(SandboxCommand::PushToGoal));
    for frame in 0..1_500 {
        state.advance(0.1);
        if state.sandbox().unwrap().driving().is_none() {
            return frame;
        }
    }
    panic!("the controller never stopped: {:?}", state.status());
}

#[test]
fn the_controller_pushes_the_mystery_to_the_goal_learning_as_it_goes() {
    let mut state = sandbox_with_goal(4, PlanWith::Online);
    until_the_controller_stops(&mut state);
    let session = state.sandbox().unwrap();
    let (reached, time_s, with) = session.last_drive().expect("how it went");
    assert!(reached, "{:?}", state.status());
    assert_eq!(with, PlanWith::Online);
    assert!(time_s > 5.0 && time_s < 120.0, "{time_s}");
    let pose = session.sandbox().object_pose();
    let (dx, dy) = (pose.position.x - GOAL[0], pose.position.y - GOAL[1]);
    assert!((dx * dx + dy * dy).sqrt() <= 0.0105, "{pose:?}");
    assert!(
        wrap_angle(pose.yaw - GOAL[2]).abs() <= 3.05f64.to_radians(),
        "{pose:?}"
    );
    let status = state.status().unwrap_or_default();
    assert!(status.contains("the goal is reached"), "{status}");
    // It learned as it pushed: θ moved from θ_online(0).
    let run = state.run().expect("the push's run");
    assert_ne!(run.theta_at(run.frontier()), run.theta0());
}

#[test]
fn moving_the_goal_stops_the_controller_and_a_goal_is_needed_first() {
    let mut state = initial_state(&[], Persisted::default());
    state.apply(Command::Sandbox(SandboxCommand::Start {
        seed: 4,
        object: Some(MysteryObject::Box),
        noise: false,
        challenge: false,
        com: None,
    }));
    state.apply(Command::Sandbox(SandboxCommand::PushToGoal));
    assert!(state.sandbox().unwrap().driving().is_none());
    assert!(
        state
            .status()
            .unwrap_or_default()
            .contains("place the goal first")
    );
    state.apply(Command::Sandbox(SandboxCommand::SetGoal(GOAL)));
    state.apply(Command::Sandbox(SandboxCommand::PushToGoal));
    for _ in 0..30 {
        state.advance(0.1);
    }
    let session = state.sandbox().unwrap();
    assert!(session.driving().is_some());
    assert!(
        !session.driving().unwrap().plan().predicted.is_empty(),
        "the arc ahead is drawn"
    );
    state.apply(Command::Sandbox(SandboxCommand::SetGoal([0.0, 0.4, 0.0])));
    let session = state.sandbox().unwrap();
    assert!(session.driving().is_none());
    assert_eq!(session.last_drive().map(|d| d.0), Some(false));
    assert!(
        state
            .status()
            .unwrap_or_default()
            .contains("the goal moved")
    );
}

/// `pushlab control --sandbox 4 --goal …` with `extra`: its JSON lines, the outcome last.
fn control_lines(extra: &[&str]) -> Vec<Value> {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_pushlab"))
        .args([
            "control",
            "--sandbox",
            "4",
            "--goal",
            "0.25,0.1,0.4",
            "--json",
        ])
        .args(extra)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    (String::from_utf8_lossy(&out.stdout).lines())
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

#[test]
fn the_cli_controller_reaches_the_goal_and_prints_a_line_per_step() {
    let lines = control_lines(&[]);
    let last = lines.last().unwrap();
    assert_eq!(last["outcome"]["reached"], true, "{last}");
    assert!(last["outcome"]["final_position_error_m"].as_f64().unwrap() <= 0.0105);
    let steps = &lines[..lines.len() - 1];
    assert_eq!(
        steps.len() as u64,
        last["outcome"]["steps"].as_u64().unwrap()
    );
    assert!(steps.iter().all(|l| l["step"]["theta"]["h"].is_number()));
    // A bad goal is refused by name, with the usage exit code.
    let bad = std::process::Command::new(env!("CARGO_BIN_EXE_pushlab"))
        .args(["control", "--sandbox", "4", "--goal", "0.25,north,0.4"])
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(err.contains("Y 'north' is not a finite number"), "{err}");
}

/// The learner's options, as `pushlab eval` and `live` take them: `--steps 0` learns nothing and
/// so plans as θ fixed does, target for target; `--optimizer gauss-newton` learns another θ.
#[test]
fn the_cli_controller_takes_the_learners_options() {
    let targets = |lines: &[Value]| -> Vec<Value> {
        let steps = &lines[..lines.len() - 1];
        steps.iter().map(|l| l["step"]["target"].clone()).collect()
    };
    let theta_end = |lines: &[Value]| lines.last().unwrap()["outcome"]["theta_end"].clone();
    let still = control_lines(&["--steps", "0"]);
    let fixed = control_lines(&["--theta", "fixed"]);
    assert_eq!(targets(&still), targets(&fixed));
    assert_eq!(
        theta_end(&still)["com_offset"],
        serde_json::json!([0.0, 0.0]),
        "--steps 0 left θ at θ_online(0)"
    );
    let gd = control_lines(&[]);
    let gauss_newton = control_lines(&["--optimizer", "gauss-newton"]);
    assert_ne!(theta_end(&gd), theta_end(&gauss_newton));
    assert_ne!(theta_end(&gauss_newton), theta_end(&still));
}

#[test]
fn the_pipe_answers_each_line_of_poses_with_a_target_and_names_a_bad_line() {
    use std::io::Write;
    let setting = std::env::temp_dir().join(format!("pushlab-pipe-{}.json", std::process::id()));
    std::fs::write(
        &setting,
        r#"{"name": "pipe", "object": {"shape": "box", "width": 0.3, "length": 0.4},
            "pusher_radius": 0.175, "sample_rate_hz": 10.0, "trajectories": []}"#,
    )
    .unwrap();
    let run = |input: &str| {
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_pushlab"))
            .args(["control", "--pipe", "--setting"])
            .arg(&setting)
            .args(["--goal", "0.25,0.1,0.4"])
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        child
            .stdin
            .take()
            .unwrap()
            .write_all(input.as_bytes())
            .unwrap();
        child.wait_with_output().unwrap()
    };
    let lines: String = (0..5)
        .map(|k| {
            format!(
                "{{\"t\": {}, \"pusher\": [{}, 0.0], \"object\": [0.0, 0.0, 0.0]}}\n",
                k as f64 * 0.1,
                -0.375 + 0.004 * k as f64
            )
        })
        .collect();
    let out = run(&lines);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let answers: Vec<Value> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(answers.len(), 5);
    for (k, a) in answers.iter().enumerate() {
        let target = &a["step"]["target"];
        let (tx, ty) = (target[0].as_f64().unwrap(), target[1].as_f64().unwrap());
        let px = -0.375 + 0.004 * k as f64;
        assert!(((tx - px).powi(2) + ty * ty).sqrt() <= 0.004 + 1e-9, "{a}");
        assert_eq!(a["done"], false);
    }
    let bad = run("{\"t\": 0.0, \"pusher\": [0.0]}\n");
    assert_eq!(bad.status.code(), Some(1));
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(err.contains("standard input, line 1: expected"), "{err}");
    std::fs::remove_file(&setting).ok();
}

#[test]
fn the_weighted_prediction_plans_with_the_weighting_and_needs_it_on() {
    use pushlab::app::state::OnlineCommand;
    let mut state = sandbox_with_goal(4, PlanWith::Weighted);
    until_the_controller_stops(&mut state);
    let (reached, _, with) = state.sandbox().unwrap().last_drive().expect("how it went");
    assert!(reached, "{:?}", state.status());
    assert_eq!(with, PlanWith::Weighted);
    // Both runs learned as it pushed, and the weights moved from their prior.
    let run = state.run().expect("the push's run");
    let physics = run.physics_beside().expect("physics alone beside");
    assert_ne!(physics.theta_at(physics.frontier()), physics.theta0());
    assert!(run.model_weight().unwrap().frames().len() > 10);

    let mut state = sandbox_with_goal(4, PlanWith::Weighted);
    state.apply(Command::Online(OnlineCommand::SetWeighPhysics(false)));
    until_the_controller_stops(&mut state);
    let status = state.status().unwrap_or_default();
    assert!(
        status.contains("the weighted prediction plan with the physics run beside"),
        "{status}"
    );
}
