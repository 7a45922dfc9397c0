//! What the panels read that combines sub-states: θ's ranges for the object shown, the labels of
//! the recording shown, the browser's rows, the pending proposals, the what-if rollout and the
//! losses by label. Each is the state's method over its sub-states' own rules; the state imports
//! nothing from here.

use std::sync::Arc;

use pushlab_core::inspect::Rollout;
use pushlab_core::learn::MeanLosses;
use pushlab_core::model::OnlineParams;
use pushlab_core::recording::Recording;

use super::AppState;
use super::browser::Row;
use super::cameras::Cameras;
use super::label_losses;
use super::labels::LabelTarget;
use super::landscape::LandscapeSource;
use super::proposals::Pending;

impl AppState {
    /// The range each component of `θ_online` is steered and plotted in, metres (the core's
    /// [`OnlineParams::plausible_ranges`] for the object shown).
    pub fn theta_ranges(&self) -> [(f64, f64); 3] {
        let outline = self
            .recording()
            .and_then(|r| r.setting.object.outline().ok());
        OnlineParams::plausible_ranges(outline.as_ref())
    }

    /// The selected recording's cameras and their frames.
    pub fn cameras(&self) -> &Cameras {
        &self.cameras
    }

    /// Where the selected recording's labels live.
    pub fn label_target(&self) -> Option<LabelTarget> {
        self.recording().and_then(LabelTarget::of)
    }

    /// Mean online and fixed losses by label over the frames learned so far on the selected
    /// recording ("all" first); empty without an online run.
    pub fn loss_by_label(&self) -> Vec<label_losses::LabelLoss> {
        let Some(run) = &self.run else {
            return Vec::new();
        };
        let labels = self
            .label_target()
            .and_then(|t| self.labels.labels_of(&t).cloned());
        label_losses::loss_by_label(run, labels.as_ref())
    }

    /// The what-if rollout from the frame shown: the online model with `θ` at this frame (as learned
    /// or as the sliders set it) fed its own predictions for the what-if steps along the recorded
    /// pusher path. `None` without a run. Computed once per change (see `frame_cache`).
    pub fn what_if(&self) -> Option<&Rollout> {
        self.frame_cache.what_if()
    }

    /// One flag per frame of the selected recording: labelled "skip in training" (bad tracking).
    /// Shared, so that learning reads it without copying; computed once per labels edit.
    pub fn frames_to_skip(&mut self) -> Arc<[bool]> {
        let target = self.label_target();
        self.frame_cache.frames_to_skip(target, &self.labels)
    }

    /// Computes again what changed since the last call: once per frame and after each command.
    pub(super) fn refresh_frame_cache(&mut self) {
        let (frame, steps) = (self.frame(), self.settings.what_if_steps);
        (self.frame_cache).refresh_what_if(self.run.as_ref(), self.run_generation, frame, steps);
    }

    /// The browser's rows: every open recording that passes the filter, sorted.
    pub fn browser_rows(&self) -> Vec<Row<'_>> {
        (self.browsed).rows(&self.session, &self.labels, &self.settings.browser)
    }

    /// The mean losses last seen on a recording's run.
    pub fn remembered_losses(&self, recording: &Recording) -> Option<MeanLosses> {
        self.browsed.losses_of(recording)
    }

    /// Reads the push parameters of the open recordings not seen before.
    pub(super) fn remember_parameters(&mut self) {
        self.browsed.remember_parameters(&self.session);
    }

    /// Keeps the selected recording's mean losses as its run learns.
    pub(super) fn remember_losses(&mut self) {
        let recording = self.session.selected_recording();
        self.browsed.remember_losses(self.run.as_ref(), recording);
    }

    /// The selected recording's pending proposals (see `ProposalState::pending`).
    pub fn pending_proposals(&self) -> Vec<Pending<'_>> {
        let (Some(recording), Some(target)) = (self.recording(), self.label_target()) else {
            return Vec::new();
        };
        (self.proposals).pending_in(&recording.source, &target, &self.labels)
    }

    /// Takes a finished landscape and starts the one of the frame shown when the window wants it.
    /// Returns whether one is being computed.
    pub(super) fn update_landscape(&mut self) -> bool {
        // The mask only while the window is open: it is what a landscape's samples leave out.
        let skip = if self.landscape.open {
            self.frames_to_skip()
        } else {
            Arc::from([])
        };
        let (frame, ranges) = (self.frame(), self.theta_ranges());
        let source = (self.run.as_ref()).map(|run| LandscapeSource {
            run,
            frame,
            ranges,
            skip,
        });
        self.landscape.update(source)
    }
}
