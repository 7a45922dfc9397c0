//! `pushlab control --pipe`: poses from another program on standard input, a JSON line each
//! control step, each answered with the pusher's target.

use anyhow::anyhow;
use pushlab_core::control::PlanWith;
use pushlab_core::geometry::Pose2;
use serde_json::json;

use super::args::ControlArgs;
use crate::cli::exit::Failure;

/// One line of poses on standard input.
#[derive(serde::Deserialize)]
struct PoseLine {
    t: f64,
    pusher: [f64; 2],
    object: [f64; 3],
}

/// `--pipe`: poses in, targets out, until the goal is held or the input ends.
pub(super) fn run_pipe(
    args: &ControlArgs,
    model: &pushlab_core::model::CombinedModel,
    goal: Pose2,
    plan_with: PlanWith,
) -> Result<(), Failure> {
    use std::io::{BufRead, Write};
    let (mut control, _) = super::args::pose_control(args, "--pipe", model, None, goal, plan_with)?;
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    for (n, line) in std::io::stdin().lock().lines().enumerate() {
        let line = line.map_err(|e| anyhow!("standard input: {e}"))?;
        if line.trim().is_empty() {
            continue;
        }
        let poses: PoseLine = serde_json::from_str(&line).map_err(|e| {
            anyhow!(
                "standard input, line {}: expected {{\"t\": s, \"pusher\": [x, y], \"object\": [x, y, yaw]}}: {e}",
                n + 1
            )
        })?;
        let [x, y, yaw] = poses.object;
        let step = control.step(
            poses.t,
            nalgebra::Point2::new(poses.pusher[0], poses.pusher[1]),
            Pose2::new(x, y, yaw),
        );
        let done = control.is_done();
        let written =
            writeln!(out, "{}", json!({ "step": step, "done": done })).and_then(|()| out.flush());
        if written.is_err() || done {
            break;
        }
    }
    Ok(())
}
