//! `pushlab control ws://HOST:PORT`: the controller driving a robot through its Foxglove server
//! (the core's `control::drive`). Without `--arm` it connects, learns and plans, and says what it
//! would send, sending nothing. Armed, each target goes through the safety gate (the pusher's
//! speed, the workspace); stale poses, Ctrl-C, a lost link, the time limit or the goal reached
//! send one hold and end. `--json` prints a line per control step and per halt.

use anyhow::anyhow;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use nalgebra::Point2;
use pushlab_core::control::PlanWith;
use pushlab_core::control::drive::{Command, Drive, DriveConfig, DriveEvent, Halt, Workspace};
use pushlab_core::geometry::Pose2;
use pushlab_core::model_file::ModelFile;
use serde_json::json;

use super::args::ControlArgs;
use crate::cli::exit::Failure;
use crate::cli::{interrupt, live};

/// `X0,Y0,X1,Y1` as a workspace, or what is wrong with it.
fn parse_workspace(text: &str) -> Result<Workspace, String> {
    let values: Vec<f64> = (text.split(','))
        .map(|v| v.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("--workspace '{text}': {e}; expected X0,Y0,X1,Y1 (metres)"))?;
    let [x0, y0, x1, y1] = values.as_slice() else {
        return Err(format!(
            "--workspace '{text}': expected X0,Y0,X1,Y1 (metres), got {} values",
            values.len()
        ));
    };
    Workspace::new(Point2::new(*x0, *y0), Point2::new(*x1, *y1))
        .map_err(|e| format!("--workspace '{text}': {e}"))
}

/// Runs the controller on the robot at `url`.
pub(super) fn run_robot(
    args: &ControlArgs,
    url: &str,
    model: &ModelFile,
    goal: Pose2,
    plan_with: PlanWith,
) -> Result<(), Failure> {
    let usage = |e: String| Failure::Usage(anyhow!(e));
    let robot = &args.robot;
    let need = |value: &Option<String>, flag: &str| {
        value
            .clone()
            .ok_or_else(|| usage(format!("driving a robot needs {flag} TOPIC")))
    };
    let (pusher, object, command) = (
        need(&robot.pusher, "--pusher")?,
        need(&args.object, "--object")?,
        need(&robot.command, "--command")?,
    );
    let workspace = robot.workspace.as_deref().map(parse_workspace).transpose();
    let workspace = workspace.map_err(usage)?;
    let grid_hz = model
        .training
        .domain
        .as_ref()
        .and_then(|d| d.single_rate_hz());
    let (control, pacing) = super::args::pose_control(
        args,
        "driving a robot",
        &model.combined,
        grid_hz,
        goal,
        plan_with,
    )?;
    let config = DriveConfig {
        url: url.to_owned(),
        pusher_topic: pusher,
        object_topic: object,
        command_topic: command.clone(),
        frame_id: robot.frame.clone(),
        record: robot.record.clone(),
        workspace,
        pacing,
        arm: robot.arm,
        time_limit_s: args.time_limit,
    };
    interrupt::cancel_flag();
    let (drive, encoding) =
        Drive::open(config, control, &interrupt::cancelled).map_err(|e| match e {
            pushlab_core::control::drive::DriveError::Session(e) => live::failure(e),
        })?;
    let said = if robot.arm {
        format!(
            "ARMED: the pusher's target goes to {command} ({}) at {} Hz, at most {} m/s; Ctrl-C holds the pusher and stops",
            encoding.name(),
            pacing.control_hz,
            pacing.pusher_speed
        )
    } else {
        format!(
            "not armed: planning only, nothing is sent to {command} (add --arm to drive the robot)"
        )
    };
    if args.json {
        println!(
            "{}",
            json!({ "said": format!("connected to {url}; {said}") })
        );
    } else {
        println!("connected to {url}; {said}");
    }
    let bar = match args.json {
        true => ProgressBar::hidden(),
        false => {
            let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
            bar.set_style(
                ProgressStyle::with_template("{spinner} {elapsed} {msg}")
                    .unwrap_or_else(|_| ProgressStyle::default_spinner()),
            );
            bar
        }
    };
    let mut each = |event: DriveEvent| show(args.json, &bar, event);
    let end = drive
        .run(&interrupt::cancelled, &mut || None, &mut each)
        .map_err(|e| match e {
            pushlab_core::control::drive::DriveError::Session(e) => live::failure(e),
        })?;
    bar.finish_and_clear();
    let recorded = end.recorded.as_ref().map(|r| {
        format!(
            "; recorded {} message(s) both ways to {}",
            r.messages,
            r.path.display()
        )
    });
    let line = format!(
        "{} after {} control step(s): {} target(s) sent{}",
        end.why.describe(),
        end.steps,
        end.commands_sent,
        recorded.unwrap_or_default()
    );
    match args.json {
        true => println!(
            "{}",
            json!({"outcome": {"why": end.why, "steps": end.steps, "commands_sent": end.commands_sent}})
        ),
        false => println!("{line}"),
    }
    match end.why {
        Halt::Reached => Ok(()),
        _ => Err(Failure::Failed(anyhow!("{line}"))),
    }
}

/// One event of the drive, as a JSON line or on the progress line.
fn show(json: bool, bar: &ProgressBar, event: DriveEvent) {
    let point = |c: &Command| {
        let p = c.point();
        format!("({:.3}, {:.3})", p.x, p.y)
    };
    match (json, event) {
        (
            true,
            DriveEvent::Step {
                step,
                command,
                sent,
            },
        ) => {
            println!(
                "{}",
                json!({"step": step, "command": command, "sent": sent})
            );
        }
        (true, DriveEvent::Halted { why, hold, sent }) => {
            println!("{}", json!({"halted": why, "hold": hold, "sent": sent}));
        }
        (true, DriveEvent::Said(what)) => println!("{}", json!({ "said": what })),
        (
            false,
            DriveEvent::Step {
                step,
                command,
                sent,
            },
        ) => bar.set_message(format!(
            "{}, {:.1} mm, {:.1}° from the goal; {}",
            step.phase,
            step.position_error_m * 1e3,
            step.yaw_error_rad.to_degrees(),
            match (command, sent) {
                (Some(c), true) => format!("sent {}", point(&c)),
                (Some(c), false) => format!("not sent (link down) {}", point(&c)),
                (None, _) => format!("would send ({:.3}, {:.3})", step.target[0], step.target[1]),
            }
        )),
        (false, DriveEvent::Halted { why, hold, sent }) => bar.println(format!(
            "halted: {}{}",
            why.describe(),
            match (hold, sent) {
                (Some(h), true) => format!("; held the pusher at {}", point(&h)),
                (Some(h), false) => format!("; the hold at {} could not be sent", point(&h)),
                (None, _) => String::new(),
            }
        )),
        (false, DriveEvent::Said(what)) => bar.println(format!("note: {what}")),
    }
}
