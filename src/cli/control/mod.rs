//! `pushlab control --sandbox SEED --goal X,Y,YAW`: the controller (the core's `control`) pushing
//! the sandbox's mystery object to a goal with the model it learns as it pushes, headless. With
//! `--json`, a line per control step (the pose, θ, the goal error, the pusher's target) and a last
//! line with the outcome; else a progress bar and the outcome. Exit 0 when the goal is reached
//! and held, 1 when the time limit passes first.
//!
//! `pushlab control --pipe --setting S.json --goal X,Y,YAW`: the controller on poses from another
//! program (a physics engine, a tracker), a JSON line each control step on standard input,
//! `{"t": s, "pusher": [x, y], "object": [x, y, yaw]}`, answered by a line with the pusher's
//! target (`control::PoseControl`: live input's grid and learner) ([`pipe`]).
//!
//! `pushlab control ws://HOST:PORT --pusher T --object T --command T --setting S.json --goal …`:
//! the same controller driving a robot through its Foxglove server ([`robot`]), behind the core's
//! safety gate: nothing is sent without `--arm`.

mod args;
mod pipe;
mod robot;

pub use self::args::ControlArgs;

use anyhow::anyhow;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use pushlab_core::control::{Goal, PlanWith, PlannerConfig, SandboxControl};
use pushlab_core::sandbox::mystery::SANDBOX_NOISE;
use pushlab_core::sandbox::{Mystery, MysteryObject};
use serde_json::json;

use crate::cli::exit::Failure;
use crate::cli::model_arg::load_model;

pub fn run(args: &ControlArgs) -> Result<(), Failure> {
    let usage = |e: String| Failure::Usage(anyhow!(e));
    let goal = args::parse_goal(&args.goal).map_err(usage)?;
    let plan_with = PlanWith::from_name(&args.theta).ok_or_else(|| {
        usage(format!(
            "--theta '{}': expected {}",
            args.theta,
            PlanWith::expected()
        ))
    })?;
    if !(args.time_limit.is_finite() && args.time_limit > 0.0) {
        return Err(usage(format!(
            "--time-limit {}: expected a positive number of seconds",
            args.time_limit
        )));
    }
    let (model, _) = load_model(args.model.as_deref())?;
    if let Some(url) = &args.url {
        return robot::run_robot(args, url, &model, goal, plan_with);
    }
    let Some(seed) = args.sandbox else {
        return pipe::run_pipe(args, &model.combined, goal, plan_with);
    };
    let object: MysteryObject = (args.object.as_deref().unwrap_or("box"))
        .parse()
        .map_err(usage)?;
    let mystery = Mystery::draw(seed, object).map_err(|e| anyhow!("{e}"))?;
    let mut control = SandboxControl::new(
        mystery,
        args.noise.then_some(SANDBOX_NOISE),
        &model.combined,
        plan_with,
        args.online.config(),
        Goal::at(goal),
        PlannerConfig {
            track: args.track,
            lookahead: args.lookahead,
            ..PlannerConfig::default()
        }
        .drawing_from(seed, args.planner_seed),
    )
    .map_err(|e| anyhow!("{e}"))?;
    let bar = if args.json {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::with_draw_target(
            Some((args.time_limit * 10.0).ceil() as u64),
            ProgressDrawTarget::stderr(),
        );
        bar.set_style(
            ProgressStyle::with_template("{bar:30} {pos}/{len} steps  {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        bar
    };
    let outcome = control.run_to_goal(args.time_limit, |step| {
        if args.json {
            println!("{}", json!({ "step": step }));
        } else {
            bar.set_position(step.step as u64 + 1);
            bar.set_message(format!(
                "{}, {:.1} mm, {:.1}° from the goal",
                step.phase,
                step.position_error_m * 1e3,
                step.yaw_error_rad.to_degrees()
            ));
        }
    });
    bar.finish_and_clear();
    if args.json {
        println!(
            "{}",
            json!({ "outcome": outcome, "plans_with": plan_with.name() })
        );
    } else {
        let mystery = control.sandbox().mystery();
        println!(
            "goal {} in {:.1} s (planned with {}): the pusher moved {:.2} m; final error {:.1} mm, {:.2}°",
            if outcome.reached {
                "reached"
            } else {
                "not reached"
            },
            outcome.time_s,
            plan_with.description(),
            outcome.pusher_path_m,
            outcome.final_position_error_m * 1e3,
            outcome.final_yaw_error_rad.to_degrees(),
        );
        println!(
            "θ learned: COM offset ({:.1}, {:.1}) mm, h {:.1} mm; hidden: COM offset ({:.1}, {:.1}) mm, h {:.1} mm",
            outcome.theta_end.com_offset[0] * 1e3,
            outcome.theta_end.com_offset[1] * 1e3,
            outcome.theta_end.h * 1e3,
            mystery.hidden.com_offset[0] * 1e3,
            mystery.hidden.com_offset[1] * 1e3,
            mystery.h * 1e3,
        );
    }
    if outcome.reached {
        Ok(())
    } else {
        Err(Failure::Failed(anyhow!(
            "the goal was not reached within {} s",
            args.time_limit
        )))
    }
}
