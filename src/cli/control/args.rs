//! `pushlab control`'s arguments, and what the sandbox, `--pipe` and a robot read from them alike:
//! the goal, the setting and the pacing.

use anyhow::anyhow;
use clap::Args;
use pushlab_core::control::Pacing;
use pushlab_core::geometry::Pose2;
use pushlab_core::recording::Setting;
use pushlab_core::recording::bag::SettingSource;
use std::path::PathBuf;

use crate::cli::exit::Failure;
use crate::cli::experiment::args::OnlineArgs;

#[derive(Debug, Args)]
pub struct ControlArgs {
    /// A robot's Foxglove WebSocket server, ws://HOST:PORT, to drive: its pose topics are read
    /// (--pusher, --object) and the pusher's target is published on --command.
    #[arg(value_name = "ws://HOST:PORT", conflicts_with_all = ["sandbox", "pipe"])]
    pub url: Option<String>,
    /// The sandbox's mystery of this seed (its link's `?sandbox=SEED`): the object pushed, its
    /// COM and `h` hidden from the controller.
    #[arg(
        long,
        value_name = "SEED",
        required_unless_present_any = ["pipe", "url"],
        conflicts_with = "pipe"
    )]
    pub sandbox: Option<u64>,
    /// Poses from another program on standard input, a JSON line each control step
    /// (`{"t": s, "pusher": [x, y], "object": [x, y, yaw]}`), each answered on standard output
    /// with the pusher's target; the object and pusher are --setting's.
    #[arg(long, requires = "setting")]
    pub pipe: bool,
    /// With --pipe or a robot: the object's and pusher's setting.json (its com_offset and h, if
    /// it has them, are what --theta truth plans with).
    #[arg(long, value_name = "SETTING.json")]
    pub setting: Option<std::path::PathBuf>,
    #[command(flatten)]
    pub robot: RobotArgs,
    /// With --pipe or a robot: control steps a second.
    #[arg(long, default_value_t = 10.0)]
    pub rate: f64,
    /// With --pipe or a robot: the pusher's top speed, m/s: no target is further than a step of
    /// it from the pusher.
    #[arg(long, default_value_t = 0.04)]
    pub speed: f64,
    /// In the sandbox, its object: box (the default), t or ellipse. With a robot, the object's
    /// pose topic (TOPIC:CHILD_FRAME for a TFMessage topic).
    #[arg(long, value_name = "SHAPE|TOPIC")]
    pub object: Option<String>,
    /// The goal: the object's centre x,y (metres) and yaw (radians); in the sandbox, in the frame
    /// the object starts at the origin of; else in the pose streams' frame.
    #[arg(long, value_name = "X,Y,YAW", allow_hyphen_values = true)]
    pub goal: String,
    /// What the controller plans with: online (θ learned as it pushes), fixed (θ_online(0)),
    /// physics (Lynch's model alone, θ learned), truth (the hidden θ: an upper bound) or weighted
    /// (the combined model and physics alone, each learning, mixed by the weighting's weights).
    #[arg(long, default_value = "online")]
    pub theta: String,
    /// The model (default: the app's, assets/default-model.json).
    #[arg(long, value_name = "MODEL.json")]
    pub model: Option<std::path::PathBuf>,
    /// Tracking noise on the poses the controller is given (the sandbox's: 2 mm, 0.5°).
    #[arg(long)]
    pub noise: bool,
    /// Plan from poses filtered for tracking noise: an alpha–beta filter, ALPHA of each residual
    /// into the pose and BETA into its rate per step (0.5,0.1 was chosen on noisy poses; it costs
    /// goals on clean ones: see the guide).
    #[arg(long, value_name = "ALPHA,BETA", value_parser = pushlab_core::control::track::TrackConfig::parse)]
    pub track: Option<pushlab_core::control::track::TrackConfig>,
    /// Weigh the best pushes as the first of two, with the push each sets up (off: measured, it
    /// reached fewer goals learning online in both engines; see the guide).
    #[arg(long)]
    pub lookahead: bool,
    /// Draw the planner's samples from another stream (0: the one the guide's tables were
    /// measured with); the object, the goal and every rule stay: how much of a result is the
    /// planner's chance.
    #[arg(long, value_name = "K", default_value_t = 0)]
    pub planner_seed: u64,
    /// How θ learns as it pushes (the run's learner, as `pushlab eval` and `pushlab live` take it).
    #[command(flatten)]
    pub online: OnlineArgs,
    /// Seconds before the run is called failed.
    #[arg(long, default_value_t = pushlab_core::control::sandbox_run::DEFAULT_TIME_LIMIT_S)]
    pub time_limit: f64,
    /// A JSON line per control step and one for the outcome, instead of the progress bar.
    #[arg(long)]
    pub json: bool,
}

/// The arguments only a robot takes.
#[derive(Debug, Args)]
pub struct RobotArgs {
    /// With a robot: the pusher's pose topic (TOPIC:CHILD_FRAME for a TFMessage topic).
    #[arg(long, value_name = "TOPIC")]
    pub pusher: Option<String>,
    /// With a robot: the topic the pusher's target is published on (a
    /// geometry_msgs/msg/PoseStamped, by the protocol's client publish).
    #[arg(long, value_name = "TOPIC")]
    pub command: Option<String>,
    /// With a robot: send the targets. Without it nothing is sent: the controller connects,
    /// learns and plans, and says what it would send.
    #[arg(long)]
    pub arm: bool,
    /// With a robot: the box the pusher's target is kept in, X0,Y0,X1,Y1 metres in the pose
    /// streams' frame (default: around the first poses and the goal, 15 cm beyond the object).
    #[arg(long, value_name = "X0,Y0,X1,Y1", allow_hyphen_values = true)]
    pub workspace: Option<String>,
    /// With a robot: the targets' header.frame_id (the pose streams' frame).
    #[arg(long, value_name = "FRAME", default_value = "")]
    pub frame: String,
    /// With a robot: write every message received and sent to this new MCAP file.
    #[arg(long, value_name = "OUT.mcap")]
    pub record: Option<PathBuf>,
}

/// `X,Y,YAW` as a pose, or what is wrong with it.
pub(super) fn parse_goal(text: &str) -> Result<Pose2, String> {
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

/// The setting `what` (--pipe, a robot) controls the object of, and the pacing --rate and --speed
/// give (the model's grid at `grid_hz`, else at --rate), or what is wrong with them.
fn setting_and_pacing<'a>(
    args: &'a ControlArgs,
    what: &str,
    grid_hz: Option<f64>,
) -> Result<(&'a std::path::Path, Setting, Pacing), Failure> {
    let usage = |e: String| Failure::Usage(anyhow!(e));
    let Some(path) = &args.setting else {
        return Err(usage(format!("{what} needs --setting SETTING.json")));
    };
    for (name, value) in [("--rate", args.rate), ("--speed", args.speed)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(usage(format!("{name} {value}: expected a positive number")));
        }
    }
    let setting = SettingSource::File(path.clone())
        .resolve()
        .map_err(|e| Failure::Failed(anyhow!("{e}")))?;
    let pacing = Pacing {
        pusher_speed: args.speed,
        control_hz: args.rate,
        grid_hz: grid_hz.unwrap_or(args.rate),
    };
    Ok((path, setting, pacing))
}

/// The controller on poses from outside (`--pipe`, a robot) for the setting and pacing of `args`
/// (see [`setting_and_pacing`]), with the pacing.
pub(super) fn pose_control(
    args: &ControlArgs,
    what: &str,
    model: &pushlab_core::model::CombinedModel,
    grid_hz: Option<f64>,
    goal: Pose2,
    plan_with: pushlab_core::control::PlanWith,
) -> Result<(pushlab_core::control::PoseControl, Pacing), Failure> {
    let (path, setting, pacing) = setting_and_pacing(args, what, grid_hz)?;
    let control = pushlab_core::control::PoseControl::new(
        model,
        &setting,
        plan_with,
        args.online.config(),
        pushlab_core::control::Goal::at(goal),
        pushlab_core::control::PlannerConfig {
            track: args.track,
            lookahead: args.lookahead,
            ..pushlab_core::control::PlannerConfig::default()
        }
        .drawing_from(0, args.planner_seed),
        pacing,
    )
    .map_err(|e| Failure::Usage(anyhow!("{}: {e}", path.display())))?;
    Ok((control, pacing))
}
