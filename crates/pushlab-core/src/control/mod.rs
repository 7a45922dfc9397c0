//! Pushing an object to a goal with the model being learned: model-predictive control whose
//! predictions are the combined model's with `θ_online` as the online run has it at each step (or
//! `θ_online(0)` held fixed, the physics-only model learning online, the weighted prediction of
//! the two, or the true θ where it is known, to compare). The paper's reason for a push model is
//! planning; this is where pushlab uses its own.
//!
//! The pieces: [`goal`] (the goal pose and when it is reached), [`arc`] (one prediction as the arc
//! of a push held on its contact), [`sites`] (where a push can start and the pusher's way round
//! the object), [`planner`] (one control step: the cross-entropy search over pushes, and a
//! lookahead that weighs the best as the first of two, measured and left off), [`predict`] (what
//! it predicts a push with: one model at one θ, or the weighted prediction),
//! [`sandbox_run`] (the controller on the sandbox's simulated object, learning as it pushes),
//! [`external`] (the controller on poses from outside, learned by live input's grid and learner),
//! [`drive`] (that controller driving a robot through its Foxglove server, behind a safety gate),
//! [`replay`] (what the controller would do at a frame of a recorded push), [`track`] (a filter
//! on the poses planned from, for tracking noise).

pub mod arc;
pub mod drive;
pub mod external;
pub mod goal;
pub mod planner;
pub mod predict;
pub mod replay;
pub mod sandbox_run;
pub mod sites;
pub mod track;

pub use external::PoseControl;
pub use goal::{Goal, GoalError};
pub use planner::{ChosenPush, Phase, Plan, Planner, PlannerConfig, SecondPush};
pub use predict::{AtTheta, Predict, Weighted};
pub use sandbox_run::{ControlError, ControlOutcome, ControlStep, Decision, SandboxControl};

use crate::learn::OnlineRun;
use crate::model::OnlineParams;
use crate::trajectory::Frame;

/// How fast a controller acts: the pusher's top speed, control steps a second, and the rate of
/// the grid the model predicts on (a robot may be steered faster than the model's frames come).
/// The one place a step's length and a prediction's travel are worked out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pacing {
    /// Metres a second.
    pub pusher_speed: f64,
    pub control_hz: f64,
    pub grid_hz: f64,
}

impl Pacing {
    /// The sandbox's: its pusher's speed, a control step per frame.
    pub fn sandbox() -> Self {
        use crate::sandbox::mystery::{PUSHER_SPEED, RATE_HZ};
        Self {
            pusher_speed: PUSHER_SPEED,
            control_hz: RATE_HZ,
            grid_hz: RATE_HZ,
        }
    }

    /// The farthest the pusher's target may be from the pusher, metres: a control step's travel.
    pub fn step_m(&self) -> f64 {
        self.pusher_speed / self.control_hz
    }

    /// How far the pusher travels over one prediction of a model of `horizon` grid frames.
    pub fn travel_per_prediction(&self, horizon: usize) -> f64 {
        self.pusher_speed / self.grid_hz * horizon as f64
    }
}

/// How far from touching the pusher may be and still be taken as pushing, metres: tracking noise
/// (the sandbox's 2 mm) and the model's contact tolerance fit well within it.
pub const AWAY_GAP_M: f64 = 0.01;

/// Which θ the controller plans with.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "lowercase")]
pub enum PlanWith {
    /// The combined model with θ as learned online so far.
    #[default]
    Online,
    /// The combined model with `θ_online(0)`, never learned.
    Fixed,
    /// The physics-only model, its θ learned online.
    Physics,
    /// The combined model with the true θ (where the truth is known: an upper bound).
    Truth,
    /// The weighted prediction: the combined model and physics alone, each learning its θ
    /// online, mixed by the weights the weighting finds as it pushes.
    Weighted,
}

impl PlanWith {
    pub const ALL: [PlanWith; 5] = [
        PlanWith::Online,
        PlanWith::Fixed,
        PlanWith::Physics,
        PlanWith::Truth,
        PlanWith::Weighted,
    ];

    pub fn name(self) -> &'static str {
        match self {
            PlanWith::Online => "online",
            PlanWith::Fixed => "fixed",
            PlanWith::Physics => "physics",
            PlanWith::Truth => "truth",
            PlanWith::Weighted => "weighted",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|p| p.name() == name)
    }

    /// The names [`PlanWith::from_name`] takes, for a refusal: "online, fixed, … or weighted".
    pub fn expected() -> String {
        let names = Self::ALL.map(Self::name);
        let (last, rest) = names.split_last().unwrap_or((&"", &[]));
        format!("{} or {last}", rest.join(", "))
    }

    /// What a pane says the controller plans with.
    pub fn description(self) -> &'static str {
        match self {
            PlanWith::Online => "the combined model, θ learned online as it pushes",
            PlanWith::Fixed => "the combined model, θ held at θ_online(0)",
            PlanWith::Physics => "physics alone (Lynch's model), θ learned online",
            PlanWith::Truth => "the combined model with the true θ (an upper bound)",
            PlanWith::Weighted => {
                "the weighted prediction: the combined model and physics alone, each θ learned \
                 online, mixed by their weights"
            }
        }
    }
}

/// The true θ of the object of `setting`, where the setting gives its COM offset and `h` (a
/// simulated object's): what `PlanWith::Truth` plans with, refused where it is `None`.
pub fn truth_of(setting: &crate::recording::Setting) -> Option<OnlineParams> {
    match (setting.com_offset, setting.h) {
        (Some(com_offset), Some(h)) => Some(OnlineParams { com_offset, h }),
        _ => None,
    }
}

/// The model a controller's online run learns with on the object of `setting`: the physics-only
/// model for `PlanWith::Physics` (its losses scaled as the combined model's), else the combined
/// model set on the object by the evaluation's rule.
pub fn learner_for(
    model: &crate::model::CombinedModel,
    setting: &crate::recording::Setting,
    plan_with: PlanWith,
) -> Result<crate::model::SharedOnlineModel, ControlError> {
    match plan_with {
        PlanWith::Physics => {
            let outline =
                (setting.object.outline()).map_err(|e| ControlError::Outline(e.to_string()))?;
            Ok(std::sync::Arc::new(crate::model::PhysicsOnlyModel::new(
                outline,
                setting.pusher_radius,
                crate::model::DEFAULT_CONTACT_TOLERANCE,
                model.loss_scale(),
            )))
        }
        _ => {
            let geometry = crate::experiment::geometry_of(setting);
            model
                .on_object(geometry.as_ref().ok())
                .map_err(|e| ControlError::Model(e.to_string()))
        }
    }
}

/// The θ a control step plans with, from the run learning the push (for `Physics`, the
/// physics-only model's run): the one rule the app, the CLI and the experiments share.
pub fn planning_theta(run: &OnlineRun, plan_with: PlanWith, truth: &OnlineParams) -> OnlineParams {
    match plan_with {
        PlanWith::Online | PlanWith::Physics | PlanWith::Weighted => run.theta_at(run.frontier()),
        PlanWith::Fixed => run.theta0(),
        PlanWith::Truth => *truth,
    }
}

/// The online run a controller learns in, on a push not begun, for `plan_with`: with
/// [`learner_for`]'s model, and for the weighted prediction with physics alone learning beside it
/// and the weighting between them, as the app's run has them when the weighting is on.
pub fn run_for(
    model: &crate::model::CombinedModel,
    setting: &crate::recording::Setting,
    plan_with: PlanWith,
    config: crate::learn::OnlineConfig,
) -> Result<OnlineRun, ControlError> {
    let empty = || std::sync::Arc::new(crate::trajectory::Trajectory::new(Vec::new()));
    let horizon = model.horizon();
    let learner = learner_for(model, setting, plan_with)?;
    let run = OnlineRun::new(learner, empty(), horizon, config);
    if plan_with != PlanWith::Weighted {
        return Ok(run);
    }
    let physics = learner_for(model, setting, PlanWith::Physics)?;
    let beside = OnlineRun::new(physics, empty(), horizon, config);
    let weight = crate::learn::ModelWeight::new(crate::learn::WeightConfig::default());
    Ok(run.with_physics_beside(beside, weight))
}

/// One control step of `planner` from `object` and `pusher`, predicting as `plan_with` says with
/// what `run` has learned (θ from [`planning_theta`]; for the weighted prediction, both runs' θ
/// and the weights): the one rule the sandbox's controller and the one on poses from outside
/// share. `None` for the weighted prediction of a run without physics alone beside it.
pub fn plan_step<'p>(
    planner: &'p mut Planner,
    run: &OnlineRun,
    plan_with: PlanWith,
    truth: &OnlineParams,
    (object, pusher): (&crate::geometry::Pose2, nalgebra::Point2<f64>),
) -> Option<&'p Plan> {
    if plan_with == PlanWith::Weighted {
        let predict = Weighted::of(run)?;
        return Some(planner.step_predicting(object, pusher, &predict));
    }
    let theta = planning_theta(run, plan_with, truth);
    Some(planner.step(object, pusher, run.model().as_ref(), &theta))
}

/// Whether the pusher is away from the object in `frame`: farther than [`AWAY_GAP_M`] from
/// touching it. A controller's pusher spends much of its time going round the object; a sample
/// it does not touch the object in says nothing about θ, and learning from it walked the
/// combined model's θ off: with gradient descent, two of six runs that failed learning from them
/// reach their goal without; with Gauss–Newton, `h` was learned at 0.38 m against a true 0.17. The controller's online
/// run holds θ over such samples, as it holds it over frames labelled bad.
pub fn is_away(sites: &sites::Sites, frame: &Frame) -> bool {
    sites.gap(frame.object.point_in_object(frame.robot)) > AWAY_GAP_M
}

#[cfg(test)]
mod tests;
