//! `pushlab control --sandbox SEED --goal X,Y,YAW`: the controller (the core's `control`) pushing
//! the sandbox's mystery object to a goal with the model it learns as it pushes, headless. With
//! `--json`, a line per control step (the pose, θ, the goal error, the pusher's target) and a last
//! line with the outcome; else a progress bar and the outcome. Exit 0 when the goal is reached
//! and held, 1 when the time limit passes first.
//!
//! `pushlab control --pipe --setting S.json --goal X,Y,YAW`: the controller on poses from another
//! program (a physics engine, a tracker), a JSON line each control step on standard input,
//! `{"t": s, "pusher": [x, y], "object": [x, y, yaw]}`, answered by a line with the pusher's
//! target (`control::PoseControl`: live input's grid and learner). It sends nothing to a robot.

use anyhow::anyhow;
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use pushlab_core::control::{Goal, PlanWith, PlannerConfig, SandboxControl};
use pushlab_core::geometry::Pose2;
use pushlab_core::learn::OnlineConfig;
use pushlab_core::sandbox::mystery::SANDBOX_NOISE;
use pushlab_core::sandbox::{Mystery, MysteryObject};
use serde_json::json;

use crate::cli::exit::Failure;
use crate::cli::model_arg::load_model;

#[derive(Debug, Args)]
pub struct ControlArgs {
    /// The sandbox's mystery of this seed (its link's `?sandbox=SEED`): the object pushed, its
    /// COM and `h` hidden from the controller.
    #[arg(
        long,
        value_name = "SEED",
        required_unless_present = "pipe",
        conflicts_with = "pipe"
    )]
    pub sandbox: Option<u64>,
    /// Poses from another program on standard input, a JSON line each control step
    /// (`{"t": s, "pusher": [x, y], "object": [x, y, yaw]}`), each answered on standard output
    /// with the pusher's target; the object and pusher are --setting's.
    #[arg(long, requires = "setting")]
    pub pipe: bool,
    /// With --pipe: the object's and pusher's setting.json (its com_offset and h, if it has them,
    /// are what --theta truth plans with).
    #[arg(long, value_name = "SETTING.json")]
    pub setting: Option<std::path::PathBuf>,
    /// With --pipe: control steps a second (the poses' rate).
    #[arg(long, default_value_t = 10.0)]
    pub rate: f64,
    /// With --pipe: the pusher's speed, m/s: no target is further than a step of it.
    #[arg(long, default_value_t = 0.04)]
    pub speed: f64,
    /// The sandbox's object: box, t or ellipse.
    #[arg(long, default_value = "box")]
    pub object: String,
    /// The goal: the object's centre x,y (metres) and yaw (radians), in the frame the object
    /// starts at the origin of.
    #[arg(long, value_name = "X,Y,YAW", allow_hyphen_values = true)]
    pub goal: String,
    /// What the controller plans with: online (θ learned as it pushes), fixed (θ_online(0)),
    /// physics (Lynch's model alone, θ learned) or truth (the hidden θ: an upper bound).
    #[arg(long, default_value = "online")]
    pub theta: String,
    /// The model (default: the app's, assets/default-model.json).
    #[arg(long, value_name = "MODEL.json")]
    pub model: Option<std::path::PathBuf>,
    /// Tracking noise on the poses the controller is given (the sandbox's: 2 mm, 0.5°).
    #[arg(long)]
    pub noise: bool,
    /// Seconds before the run is called failed.
    #[arg(long, default_value_t = pushlab_core::control::sandbox_run::DEFAULT_TIME_LIMIT_S)]
    pub time_limit: f64,
    /// A JSON line per control step and one for the outcome, instead of the progress bar.
    #[arg(long)]
    pub json: bool,
}

/// `X,Y,YAW` as a pose, or what is wrong with it.
fn parse_goal(text: &str) -> Result<Pose2, String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let [x, y, yaw] = parts.as_slice() else {
        return Err(format!(
            "--goal '{text}': expected X,Y,YAW (metres, metres, radians), got {} values",
            parts.len()
        ));
    };
    let number = |name: &str, v: &str| {
        v.parse::<f64>()
            .ok()
            .filter(|n| n.is_finite())
            .ok_or_else(|| format!("--goal '{text}': {name} '{v}' is not a finite number"))
    };
    Ok(Pose2::new(
        number("X", x)?,
        number("Y", y)?,
        number("YAW", yaw)?,
    ))
}

pub fn run(args: &ControlArgs) -> Result<(), Failure> {
    let usage = |e: String| Failure::Usage(anyhow!(e));
    let goal = parse_goal(&args.goal).map_err(usage)?;
    let plan_with = PlanWith::from_name(&args.theta).ok_or_else(|| {
        usage(format!(
            "--theta '{}': expected online, fixed, physics or truth",
            args.theta
        ))
    })?;
    let object: MysteryObject = args.object.parse().map_err(usage)?;
    if !(args.time_limit.is_finite() && args.time_limit > 0.0) {
        return Err(usage(format!(
            "--time-limit {}: expected a positive number of seconds",
            args.time_limit
        )));
    }
    let (model, _) = load_model(args.model.as_deref())?;
    let Some(seed) = args.sandbox else {
        return run_pipe(args, &model.combined, goal, plan_with);
    };
    let mystery = Mystery::draw(seed, object).map_err(|e| anyhow!("{e}"))?;
    let mut control = SandboxControl::new(
        mystery,
        args.noise.then_some(SANDBOX_NOISE),
        &model.combined,
        plan_with,
        OnlineConfig::default(),
        Goal::at(goal),
        PlannerConfig {
            seed,
            ..PlannerConfig::default()
        },
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

/// One line of poses on standard input.
#[derive(serde::Deserialize)]
struct PoseLine {
    t: f64,
    pusher: [f64; 2],
    object: [f64; 3],
}

/// `--pipe`: poses in, targets out, until the goal is held or the input ends.
fn run_pipe(
    args: &ControlArgs,
    model: &pushlab_core::model::CombinedModel,
    goal: Pose2,
    plan_with: PlanWith,
) -> Result<(), Failure> {
    use std::io::{BufRead, Write};
    let usage = |e: String| Failure::Usage(anyhow!(e));
    let Some(path) = &args.setting else {
        return Err(usage("--pipe needs --setting SETTING.json".into()));
    };
    for (name, value) in [("--rate", args.rate), ("--speed", args.speed)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(usage(format!("{name} {value}: expected a positive number")));
        }
    }
    let setting = pushlab_core::recording::bag::SettingSource::File(path.clone())
        .resolve()
        .map_err(|e| Failure::Failed(anyhow!("{e}")))?;
    let mut control = pushlab_core::control::PoseControl::new(
        model,
        &setting,
        plan_with,
        OnlineConfig::default(),
        Goal::at(goal),
        PlannerConfig::default(),
        args.rate,
        args.speed,
    )
    .map_err(|e| usage(format!("{}: {e}", path.display())))?;
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
