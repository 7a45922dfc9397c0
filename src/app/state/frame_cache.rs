//! What several panels read each frame, computed once per change rather than once per reader: the
//! what-if rollout (the scene, the Inspect and the Steer tabs all show it) and the skip mask
//! (one flag per frame of the recording, which learning while playing consults every frame moved).
//!
//! Each is kept with the key it was computed for and computed again only when the key changes —
//! another frame, θ, step count or run for the rollout; another recording or labels edit for the
//! mask — so a frame that changes nothing costs nothing, and a paused app computes neither.

use std::sync::Arc;

use pushlab_core::inspect::{Rollout, rollout};
use pushlab_core::model::OnlineParams;

use super::AppState;
use super::labels::LabelTarget;

/// The rollout and the mask, with what they were computed for.
#[derive(Default)]
pub struct FrameCache {
    what_if: Option<(WhatIfKey, Option<Rollout>)>,
    skip: Option<(SkipKey, Arc<[bool]>)>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
struct WhatIfKey {
    run: u64,
    frame: usize,
    theta: OnlineParams,
    steps: usize,
}

type SkipKey = (Option<LabelTarget>, Option<u64>);

impl FrameCache {
    /// Forgets both (a new run: its rollouts differ even at the same frame and θ).
    pub fn clear(&mut self) {
        *self = Self::default();
    }
}

impl AppState {
    /// The what-if rollout from the frame shown: the online model with `θ` at this frame (as learned
    /// or as the sliders set it) fed its own predictions for `what_if_steps` steps along the recorded
    /// pusher path. `None` without a run. Computed by [`AppState::refresh_frame_cache`].
    pub fn what_if(&self) -> Option<&Rollout> {
        self.frame_cache.what_if.as_ref()?.1.as_ref()
    }

    /// One flag per frame of the selected recording: labelled "skip in training" (bad tracking).
    /// Shared, so that learning reads it without copying.
    pub fn frames_to_skip(&mut self) -> Arc<[bool]> {
        self.refresh_skip();
        (self.frame_cache.skip.as_ref()).map_or_else(|| Arc::from([]), |(_, mask)| Arc::clone(mask))
    }

    /// Computes again what changed since the last call: once per frame and after each command.
    pub(super) fn refresh_frame_cache(&mut self) {
        let key = self.run.as_ref().map(|run| WhatIfKey {
            run: self.run_generation,
            frame: self.frame(),
            theta: run.theta_at(self.frame()),
            steps: self.settings.what_if_steps,
        });
        let Some(key) = key else {
            self.frame_cache.what_if = None;
            return;
        };
        if self
            .frame_cache
            .what_if
            .as_ref()
            .is_some_and(|(k, _)| *k == key)
        {
            return;
        }
        let rollout = self.run.as_ref().map(|run| {
            rollout(
                run.model().as_ref(),
                run.trajectory(),
                key.frame,
                run.horizon(),
                key.steps,
                &key.theta,
            )
        });
        self.frame_cache.what_if = Some((key, rollout));
    }

    fn refresh_skip(&mut self) {
        let target = self.label_target();
        let state = (target.as_ref())
            .and_then(|t| self.labels.document(&t.document))
            .map(|d| d.state_id());
        let key = (target, state);
        if self
            .frame_cache
            .skip
            .as_ref()
            .is_some_and(|(k, _)| *k == key)
        {
            return;
        }
        let mask = (key.0.as_ref())
            .map(|t| self.labels.frames_to_skip(t))
            .unwrap_or_default();
        self.frame_cache.skip = Some((key, Arc::from(mask)));
    }
}
