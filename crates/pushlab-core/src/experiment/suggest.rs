//! The next push that teaches the most: an object's candidate pushes ranked by how much each is
//! expected to shrink the COM's uncertainty, given what online learning knows now.
//!
//! One push leaves the COM's depth along the pushed face nearly unseen (the trust experiment), so
//! which push comes next decides how soon the COM is known. Each candidate — a recorded push of the
//! same object, its pusher path taken relative to the object's pose at its start — is played
//! through the model with today's `θ` (`inspect::next_push`), its frames' Fisher information added
//! to the posterior, and the COM's expected spread after it read off
//! (`learn::Posterior::com_covariance_after`). The candidate leaving the least is suggested first.
//! Nothing reads a candidate's recorded outcome: what it would teach is the model's own forecast.
//!
//! Where no recorded push says where to push next, [`PushGrid`] lays candidates out on the object.
//!
//! [`learn_in_order`] is the measurement: an object's pushes learned one after another with θ
//! carried on, each next push chosen by the ranking, by its reverse or at random.

mod grid;

use crate::math;
use std::str::FromStr;

use serde::Serialize;

use super::data::UsedRecording;
use super::runs::{TrajectoryRun, model_on};
use crate::geometry::OutlineError;
use crate::inspect::{PushShape, information_along, predicted_poses, shape_of};
use crate::learn::{OnlineConfig, OnlineState, Posterior, PushInformation};
use crate::model::{CombinedModel, NoOutline, OnlineModel};
use crate::recording::Recording;
use crate::rng::SplitMix64;
use crate::slices;

pub use grid::{APPROACH_M, GridPushes, PushGrid};

/// What "the COM's uncertainty" a push should shrink is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Criterion {
    /// The mean of the two COM variances: the expected squared error of the estimate (an
    /// "A-optimal" design).
    Spread,
    /// The area of the COM's ellipse, `√det` (a "D-optimal" design): the information gained,
    /// whatever its direction. The default: on the second draw of MuJoCo pushes it found the COM
    /// soonest of the three (`experiments/next-push/run`).
    #[default]
    Area,
    /// The ellipse's longest axis, the largest variance (an "E-optimal" design): the direction
    /// least known, alone.
    Axis,
}

impl Criterion {
    /// The COM's uncertainty by this criterion as one standard deviation, metres: `√(tr C / 2)`,
    /// `det(C)^¼` or `√λ_max`.
    pub fn std_of(self, c: [[f64; 2]; 2]) -> f64 {
        let half_trace = (c[0][0] + c[1][1]) / 2.0;
        match self {
            Self::Spread => half_trace.max(0.0).sqrt(),
            Self::Area => (c[0][0] * c[1][1] - c[0][1] * c[1][0])
                .max(0.0)
                .sqrt()
                .sqrt(),
            Self::Axis => {
                let half_gap = (c[0][0] - c[1][1]) / 2.0;
                (half_trace + math::hypot(half_gap, c[0][1]))
                    .max(0.0)
                    .sqrt()
            }
        }
    }
}

impl Criterion {
    /// The criterion's name, as `--criterion` takes it.
    pub fn name(self) -> &'static str {
        match self {
            Self::Spread => "spread",
            Self::Area => "area",
            Self::Axis => "axis",
        }
    }
}

impl std::fmt::Display for Criterion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Criterion {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "spread" => Ok(Self::Spread),
            "area" => Ok(Self::Area),
            "axis" => Ok(Self::Axis),
            other => Err(format!(
                "unknown criterion '{other}': expected 'spread' (the mean COM variance), 'area' \
                 (the COM ellipse's area) or 'axis' (its longest axis)"
            )),
        }
    }
}

/// One candidate push and what it is expected to leave.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Suggestion {
    /// The push: its index among the recordings given.
    pub push: usize,
    /// Its recording's name.
    pub name: String,
    /// Where and how it pushes the object, as the model expects it to go; `None` when the model
    /// expects the pusher to miss the object.
    pub shape: Option<PushShape>,
    /// The COM's uncertainty expected after it, by the ranking's criterion, metres.
    pub com_std_after_m: f64,
}

/// Candidate pushes ranked, the most teaching first.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Ranking {
    /// How uncertainty was measured.
    pub criterion: Criterion,
    /// The COM's uncertainty now, by the same criterion and rule, metres.
    pub com_std_now_m: f64,
    /// Of it, the model's COM misfit (one standard deviation per component, metres): the floor no
    /// push can take the uncertainty below.
    pub com_misfit_m: f64,
    pub suggestions: Vec<Suggestion>,
}

/// Ranks `candidates` — pushes of one object, each with an index the caller knows it by — for a
/// model bound to that object, with `state` what online learning knows now.
pub fn rank(
    learner: &dyn OnlineModel,
    horizon: usize,
    state: &OnlineState,
    candidates: &[(usize, &Recording)],
    criterion: Criterion,
) -> Result<Ranking, OutlineError> {
    let never = || false;
    slices::finish(rank_in_slices(
        learner, horizon, state, candidates, criterion, &never,
    ))
    .map(|ranking| ranking.unwrap_or_else(|| ranked(state, criterion, Vec::new())))
}

/// [`rank`] pausing after each candidate (`slices`), asking `cancelled` there: `Ok(None)` when it
/// said so. The app ranks this way, a candidate a slice in a page.
pub async fn rank_in_slices(
    learner: &dyn OnlineModel,
    horizon: usize,
    state: &OnlineState,
    candidates: &[(usize, &Recording)],
    criterion: Criterion,
    cancelled: &dyn Fn() -> bool,
) -> Result<Option<Ranking>, OutlineError> {
    let mut suggestions = Vec::with_capacity(candidates.len());
    for &(push, recording) in candidates {
        if cancelled() {
            return Ok(None);
        }
        suggestions.push(suggestion(
            learner, horizon, state, push, recording, criterion,
        )?);
        slices::pause().await;
    }
    Ok(Some(ranked(state, criterion, suggestions)))
}

/// One candidate played through the model, and the COM's uncertainty it is expected to leave.
fn suggestion(
    learner: &dyn OnlineModel,
    horizon: usize,
    state: &OnlineState,
    push: usize,
    recording: &Recording,
    criterion: Criterion,
) -> Result<Suggestion, OutlineError> {
    let trajectory = &recording.trajectory;
    let poses = predicted_poses(learner, trajectory, horizon, &state.theta);
    let information = information_along(learner, trajectory, &poses, horizon, &state.theta);
    let outline = recording.setting.object.outline()?;
    Ok(Suggestion {
        push,
        name: recording.name.clone(),
        shape: shape_of(
            &outline,
            recording.setting.pusher_radius,
            trajectory,
            &poses,
        ),
        com_std_after_m: criterion.std_of(state.posterior.com_covariance_after(&information)),
    })
}

/// The suggestions sorted, the most teaching first (ties, pushes that teach nothing, keep their
/// order), with where the COM's uncertainty stands now.
fn ranked(state: &OnlineState, criterion: Criterion, mut suggestions: Vec<Suggestion>) -> Ranking {
    let posterior: &Posterior = &state.posterior;
    suggestions.sort_by(|a, b| a.com_std_after_m.total_cmp(&b.com_std_after_m));
    Ranking {
        criterion,
        com_std_now_m: criterion.std_of(posterior.com_covariance_after(&PushInformation::none())),
        com_misfit_m: posterior.com_spread_parts().misfit_m,
        suggestions,
    }
}

/// The recordings of one object.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectPushes {
    /// The setting's name.
    pub name: String,
    /// Indices into the recordings, in their order.
    pub pushes: Vec<usize>,
}

/// The objects `used` pushes, each with its recordings (`UsedRecording::same_object_as`).
pub fn objects(used: &[UsedRecording]) -> Vec<ObjectPushes> {
    let mut objects: Vec<ObjectPushes> = Vec::new();
    for (i, recording) in used.iter().enumerate() {
        match objects
            .iter_mut()
            .find(|o| used[o.pushes[0]].same_object_as(recording))
        {
            Some(object) => object.pushes.push(i),
            None => objects.push(ObjectPushes {
                name: recording.recording.setting.name.clone(),
                pushes: vec![i],
            }),
        }
    }
    objects
}

/// The object called `name` among those `used` pushes — its setting's name, or that name's last
/// `-`-separated part onwards (`rect1` for `mit-abs-rect1`) — or the only one when `name` is
/// `None`. The error lists the objects there are.
pub fn find_object(used: &[UsedRecording], name: Option<&str>) -> Result<ObjectPushes, String> {
    let all = objects(used);
    let names = || {
        all.iter()
            .map(|o| format!("'{}' ({} pushes)", o.name, o.pushes.len()))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let found: Vec<&ObjectPushes> = match name {
        Some(name) => all
            .iter()
            .filter(|o| o.name == name || o.name.ends_with(&format!("-{name}")))
            .collect(),
        None => all.iter().collect(),
    };
    match (found.as_slice(), name) {
        ([one], _) => Ok((*one).clone()),
        ([], Some(name)) => Err(format!(
            "no object '{name}' in the recordings; there are {}",
            names()
        )),
        (_, Some(name)) => Err(format!(
            "'{name}' names more than one object; name one of {}",
            names()
        )),
        (_, None) => Err(format!(
            "the recordings push {} objects: choose one with --object, one of {}",
            all.len(),
            names()
        )),
    }
}

/// How the next push of an order is chosen among those left.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Choice {
    /// The push the ranking puts first.
    Ranked,
    /// The push the ranking puts last.
    Worst,
    /// A push drawn at random with this seed.
    Random(u64),
    /// The pushes in the order given.
    InOrder,
}

/// One push of an order, learned.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LearnedPush {
    /// The push: its index among the recordings.
    pub push: usize,
    /// The COM estimate's distance from the truth after it, metres, when the truth is known.
    pub com_error_m: Option<f64>,
    /// Whether the 95 % ellipse then holds the truth.
    pub within_95: Option<bool>,
    /// The COM's uncertainty the ranking expected after it (by `criterion`), metres.
    pub expected_std_m: f64,
}

/// `count` of `pushes` (indices into `used`, one object) learned one after another, θ and the
/// posterior carried from each to the next as `pushlab eval --carry-theta` carries them, each next
/// push chosen by `choice` among those not yet learned; every next push is ranked first (by
/// `criterion`), so each step says what it was expected to leave.
pub fn learn_in_order(
    model: &CombinedModel,
    used: &[UsedRecording],
    pushes: &[usize],
    config: &OnlineConfig,
    choice: Choice,
    criterion: Criterion,
    count: usize,
) -> Result<Vec<LearnedPush>, SuggestError> {
    let Some(&first) = pushes.first() else {
        return Ok(Vec::new());
    };
    let learner = model_on(model, &used[first])?;
    let horizon = model.horizon();
    let mut rng = match choice {
        Choice::Random(seed) => Some(SplitMix64::new(seed)),
        _ => None,
    };
    let mut left: Vec<usize> = pushes.to_vec();
    let mut state = OnlineState::start(learner.as_ref(), config.optimizer);
    let mut learned = Vec::with_capacity(count.min(pushes.len()));
    while learned.len() < count && !left.is_empty() {
        let candidates: Vec<(usize, &Recording)> =
            left.iter().map(|&p| (p, &used[p].recording)).collect();
        let ranking = rank(learner.as_ref(), horizon, &state, &candidates, criterion)?;
        let pick = match (choice, rng.as_mut()) {
            (Choice::Ranked, _) => ranking.suggestions.first(),
            (Choice::Worst, _) => ranking.suggestions.last(),
            (Choice::Random(_), Some(rng)) => {
                let push = left[rng.below(left.len())];
                ranking.suggestions.iter().find(|s| s.push == push)
            }
            (_, _) => ranking.suggestions.iter().find(|s| s.push == left[0]),
        };
        let Some(pick) = pick else { break };
        let (push, expected_std_m) = (pick.push, pick.com_std_after_m);
        left.retain(|&p| p != push);
        // The first push starts afresh, as `pushlab eval --carry-theta` starts an object's first.
        let from = (!learned.is_empty()).then_some(&state);
        let run = TrajectoryRun::learn_from(model, &used[push], push, config, from, None)?;
        state = run.run.end_state();
        learned.push(LearnedPush {
            push,
            com_error_m: run.com_truth.map(|t| t.error_m),
            within_95: run.com_truth.map(|t| t.within_95),
            expected_std_m,
        });
    }
    Ok(learned)
}

/// What online learning knows after `pushes` (indices into `used`, one object) were learned in
/// that order, θ carried on; the start (`θ_online(0)` and the prior) when there are none.
pub fn state_after(
    model: &CombinedModel,
    used: &[UsedRecording],
    object: &[usize],
    pushes: &[usize],
    config: &OnlineConfig,
) -> Result<OnlineState, SuggestError> {
    let first = pushes.first().or(object.first()).copied().unwrap_or(0);
    let learner = model_on(model, used.get(first).ok_or(SuggestError::NoPushes)?)?;
    let mut state = OnlineState::start(learner.as_ref(), config.optimizer);
    for (i, &push) in pushes.iter().enumerate() {
        let from = (i > 0).then_some(&state);
        let run = TrajectoryRun::learn_from(model, &used[push], push, config, from, None)?;
        state = run.run.end_state();
    }
    Ok(state)
}

/// Why pushes could not be ranked or learned.
#[derive(Debug, thiserror::Error)]
pub enum SuggestError {
    #[error(transparent)]
    NoOutline(#[from] NoOutline),
    #[error("the object's outline: {0}")]
    Outline(#[from] OutlineError),
    #[error("no pushes of the object to learn from")]
    NoPushes,
}
