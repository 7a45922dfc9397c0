//! What several panels read each frame, computed once per change rather than once per reader: the
//! what-if rollout (the scene, the Inspect and the Steer tabs all show it), the controller's step
//! from the frame shown (the scene draws it, the Steer tab says it) and the skip mask (one flag per
//! frame of the recording, which learning while playing consults every frame moved).
//!
//! Each is kept with the key it was computed for and computed again only when the key changes —
//! another frame, θ, step count or run for the rollout; another recording or labels edit for the
//! mask — so a frame that changes nothing costs nothing, and a paused app computes neither. The
//! cache knows nothing of the rest of the state: the owner hands it the run and the labels.

use std::sync::Arc;

use pushlab_core::control::replay::{ReplayedPush, replay_pacing};
use pushlab_core::control::{Goal, Pacing, Plan};
use pushlab_core::geometry::Outline;
use pushlab_core::inspect::{Rollout, rollout};
use pushlab_core::model::OnlineParams;

use crate::app::state::labels::labeling::{LabelTarget, Labeling};
use crate::app::state::learning::online::OnlineRun;

/// The rollout and the mask, with what they were computed for.
#[derive(Default)]
pub struct FrameCache {
    what_if: Option<(WhatIfKey, Rollout)>,
    /// The controller's step from the frame (`None` inside: the push has no pace to plan at).
    controller: Option<(ControllerKey, Option<(Goal, Plan)>)>,
    /// The pace of the run's push, measured once per run (it reads every frame of the push).
    replay_pace: Option<(u64, Option<Pacing>)>,
    skip: Option<(SkipKey, Arc<[bool]>)>,
}

/// What a what-if rollout is computed for.
#[derive(Clone, Copy, Debug, PartialEq)]
struct WhatIfKey {
    run: u64,
    frame: usize,
    theta: OnlineParams,
    steps: usize,
}

/// What the controller's step is planned for: the run, the frame and θ there.
#[derive(Clone, Copy, Debug, PartialEq)]
struct ControllerKey {
    run: u64,
    frame: usize,
    theta: OnlineParams,
}

type SkipKey = (Option<LabelTarget>, Option<u64>);

impl FrameCache {
    /// Forgets both (a new run: its rollouts differ even at the same frame and θ).
    pub fn clear(&mut self) {
        *self = Self::default();
    }

    /// The rollout last computed by [`FrameCache::refresh_what_if`].
    pub fn what_if(&self) -> Option<&Rollout> {
        self.what_if.as_ref().map(|(_, rollout)| rollout)
    }

    /// The what-if rollout from `frame`: the run's model with `θ` at this frame (as learned or as
    /// the sliders set it) fed its own predictions for `steps` steps along the recorded pusher
    /// path; `None` without a run. `generation` tells runs apart.
    pub fn refresh_what_if(
        &mut self,
        run: Option<&OnlineRun>,
        generation: u64,
        frame: usize,
        steps: usize,
    ) {
        let Some(run) = run else {
            self.what_if = None;
            return;
        };
        let key = WhatIfKey {
            run: generation,
            frame,
            theta: run.theta_at(frame),
            steps,
        };
        if self.what_if.as_ref().is_some_and(|(k, _)| *k == key) {
            return;
        }
        let rollout = rollout(
            run.model().as_ref(),
            run.trajectory(),
            key.frame,
            run.horizon(),
            key.steps,
            &key.theta,
        );
        self.what_if = Some((key, rollout));
    }

    /// The controller's step last planned by [`FrameCache::refresh_controller`], with its goal.
    pub fn controller(&self) -> Option<&(Goal, Plan)> {
        self.controller.as_ref().and_then(|(_, plan)| plan.as_ref())
    }

    /// What the controller would do from `frame` of the run's push (the core's
    /// `control::replay`), on the object and pusher `shape` gives (its outline and radius, asked
    /// only when the step is planned again); forgotten with no run (the layer off, or none).
    pub fn refresh_controller(
        &mut self,
        run: Option<&OnlineRun>,
        shape: impl FnOnce() -> Option<(Outline, f64)>,
        generation: u64,
        frame: usize,
    ) {
        let Some(run) = run else {
            self.controller = None;
            return;
        };
        let key = ControllerKey {
            run: generation,
            frame,
            theta: run.theta_at(frame),
        };
        if self.controller.as_ref().is_some_and(|(k, _)| *k == key) {
            return;
        }
        if self.replay_pace.is_none_or(|(run, _)| run != generation) {
            self.replay_pace = Some((generation, replay_pacing(run.trajectory())));
        }
        let pacing = self.replay_pace.and_then(|(_, pace)| pace);
        let plan = (pacing.zip(shape())).and_then(|(pacing, (outline, pusher_radius))| {
            let push = ReplayedPush {
                trajectory: run.trajectory(),
                outline: &outline,
                pusher_radius,
                model: run.model().as_ref(),
                horizon: run.horizon(),
                pacing,
            };
            push.plan_at(frame, &key.theta)
        });
        self.controller = Some((key, plan));
    }

    /// One flag per frame of `target`'s recording: labelled "skip in training" (bad tracking).
    /// Shared, so that learning reads it without copying.
    pub fn frames_to_skip(
        &mut self,
        target: Option<LabelTarget>,
        labels: &Labeling,
    ) -> Arc<[bool]> {
        let state = (target.as_ref())
            .and_then(|t| labels.document(&t.document))
            .map(|d| d.state_id());
        let key = (target, state);
        if !self.skip.as_ref().is_some_and(|(k, _)| *k == key) {
            let mask = (key.0.as_ref())
                .map(|t| labels.frames_to_skip(t))
                .unwrap_or_default();
            self.skip = Some((key, Arc::from(mask)));
        }
        (self.skip.as_ref()).map_or_else(|| Arc::from([]), |(_, mask)| Arc::clone(mask))
    }
}
