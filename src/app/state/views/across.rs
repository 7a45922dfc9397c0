//! What the panels read that combines sub-states: θ's ranges for the object shown, the labels of
//! the recording shown, the browser's rows, the pending proposals, the what-if rollout and the
//! losses by label. Each is the state's method over its sub-states' own rules; the state imports
//! nothing from here.

use std::path::PathBuf;
use std::sync::Arc;

use pushlab_core::control::{Goal, Plan};
use pushlab_core::inspect::Rollout;
use pushlab_core::learn::MeanLosses;
use pushlab_core::model::OnlineParams;
use pushlab_core::recording::{Recording, bag, dataset};

use pushlab_core::model::PhysicsOnlyModel;

use crate::app::state::demos::demo::Demos;
use crate::app::state::labels::labeling::LabelTarget;
use crate::app::state::labels::labeling::Labeling;
use crate::app::state::labels::losses;
use crate::app::state::labels::proposals::Pending;
use crate::app::state::labels::proposals::ProposalState;
use crate::app::state::learning::best_fit::BestFitState;
use crate::app::state::learning::landscape::LandscapeSource;
use crate::app::state::learning::landscape::LandscapeState;
use crate::app::state::learning::next_push::{Candidates, NextPushState, ToRank, grid};
use crate::app::state::learning::online::OnlineRun;
use crate::app::state::models::Models;
use crate::app::state::models::training::Training;
use crate::app::state::playback::cameras::Cameras;
use crate::app::state::playback::overview::PathOverview;
use crate::app::state::playback::timeline::Timeline;
use crate::app::state::recordings::browser::{Column, Row};
use crate::app::state::recordings::session::{RecordingId, Session};
use crate::app::state::sources::bag_import::BagChooser;
use crate::app::state::sources::dataset_import::DatasetChooser;
use crate::app::state::{AppState, Persisted};

impl AppState {
    /// Whether work runs off the UI thread: a load, training, the landscape, proposals, or
    /// learning far ahead (a page's test hook waits for it to end).
    pub fn is_busy(&self) -> bool {
        self.session.loading().is_some()
            || self.training.is_running()
            || self.landscape.is_running()
            || self.proposals.is_running()
            || self.learning_ahead.is_running()
            || self.next_push.is_running()
    }

    /// The persisted settings as they stand (layers, online settings, the browser's view…).
    pub fn settings(&self) -> &Persisted {
        &self.settings
    }

    /// The open sets, what is loading and what failed.
    pub fn session(&self) -> &Session {
        &self.session
    }

    /// The models in use.
    pub fn models(&self) -> &Models {
        &self.models
    }

    /// Playback: the frame shown, playing, speed, loop.
    pub fn timeline(&self) -> &Timeline {
        &self.timeline
    }

    /// Online learning on the selected recording; `None` until a recording is selected.
    pub fn run(&self) -> Option<&OnlineRun> {
        self.run.as_ref()
    }

    /// The physics-only model of the selected recording (its prediction layer), once per run.
    pub fn physics(&self) -> Option<&PhysicsOnlyModel> {
        self.physics.as_ref()
    }

    /// The selected recording's whole path, thinned for drawing.
    pub fn overview(&self) -> &PathOverview {
        &self.overview
    }

    /// Offline training in the background, and the Train tab's choices.
    pub fn training(&self) -> &Training {
        &self.training
    }

    /// The labels files of the open recordings, and the labeling tools' state.
    pub fn labels(&self) -> &Labeling {
        &self.labels
    }

    /// The selected recording's label proposals, and those rejected.
    pub fn proposals(&self) -> &ProposalState {
        &self.proposals
    }

    /// The status line: what just happened, or what went wrong.
    pub fn status(&self) -> Option<&str> {
        self.status.as_deref()
    }

    /// Where models trained for folders are kept (see [`AppState::keep_files_in`]).
    pub fn model_store(&self) -> Option<&std::path::Path> {
        self.model_store.as_deref()
    }

    /// The loss-landscape window and its background work.
    pub fn landscape(&self) -> &LandscapeState {
        &self.landscape
    }

    /// The Steer tab's best θ for the recording shown and its search.
    pub fn best_fit(&self) -> &BestFitState {
        &self.best_fit
    }

    /// The Steer tab's ranking of the next pushes and its work.
    pub fn next_push(&self) -> &NextPushState {
        &self.next_push
    }

    /// The other open pushes of the object shown (`Recording::same_object_as`): the candidates
    /// the next-push ranking chooses among.
    pub fn other_pushes_of_object(&self) -> Vec<(RecordingId, &Recording)> {
        let Some(selected) = self.session.selected else {
            return Vec::new();
        };
        let Some(shown) = self.session.get(selected) else {
            return Vec::new();
        };
        self.session
            .recordings()
            .filter(|(id, r)| *id != selected && r.same_object_as(shown))
            .collect()
    }

    /// What the next-push ranking chooses among: the object's other open pushes, or with none
    /// open the core's default grid of pushes laid out on the object shown.
    /// A sandbox's own pushes are never the candidates: each began where the object lay then,
    /// and the student's next push starts where it rests now, so the grid is laid out there.
    pub fn pushes_to_rank(&self) -> ToRank {
        let open = self.other_pushes_of_object();
        if !open.is_empty() && !self.sandbox_shown() {
            return ToRank {
                pushes: open.into_iter().map(|(_, r)| r.clone()).collect(),
                from: Candidates::Open,
            };
        }
        let grid = (self.session.selected_recording()).and_then(|shown| grid().pushes(shown).ok());
        match grid {
            Some(grid) => ToRank {
                pushes: grid.pushes,
                from: Candidates::Grid {
                    left_out: grid.skipped,
                },
            },
            None => ToRank {
                pushes: Vec::new(),
                from: Candidates::Open,
            },
        }
    }

    /// The Demos menu's presets and the demo running.
    pub fn demos(&self) -> &Demos {
        &self.demos
    }

    /// Bags waiting for their topics to be chosen, and those being opened with a choice.
    pub fn bags(&self) -> &BagChooser {
        &self.bags
    }

    /// The datasets waiting for a choice of features, and the form shown.
    pub fn datasets(&self) -> &DatasetChooser {
        &self.datasets
    }

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
    pub fn loss_by_label(&self) -> Vec<losses::LabelLoss> {
        let Some(run) = &self.run else {
            return Vec::new();
        };
        let labels = self
            .label_target()
            .and_then(|t| self.labels.labels_of(&t).cloned());
        losses::loss_by_label(run, labels.as_ref())
    }

    /// The what-if rollout from the frame shown: the online model with `θ` at this frame (as learned
    /// or as the sliders set it) fed its own predictions for the what-if steps along the recorded
    /// pusher path. `None` without a run. Computed once per change (see `frame_cache`).
    pub fn what_if(&self) -> Option<&Rollout> {
        self.frame_cache.what_if()
    }

    /// What the controller would do from the frame shown, toward where the push ends, with θ at
    /// this frame (the core's `control::replay`), with its goal: while the scene's layer is on.
    /// Planned once per frame and θ (see `frame_cache`).
    pub fn controller_here(&self) -> Option<&(Goal, Plan)> {
        self.frame_cache.controller()
    }

    /// One flag per frame of the selected recording: labelled "skip in training" (bad tracking).
    /// Shared, so that learning reads it without copying; computed once per labels edit.
    pub fn frames_to_skip(&mut self) -> Arc<[bool]> {
        let target = self.label_target();
        self.frame_cache.frames_to_skip(target, &self.labels)
    }

    /// Computes again what changed since the last call: once per frame and after each command.
    pub(in crate::app::state) fn refresh_frame_cache(&mut self) {
        let (frame, steps) = (self.frame(), self.settings.what_if_steps);
        (self.frame_cache).refresh_what_if(self.run.as_ref(), self.run_generation, frame, steps);
        // The sandbox has a controller of its own (Push to goal); this one is for replays.
        let replay = self.settings.layers.controller && !self.sandbox_shown();
        let controller = self.run.as_ref().filter(|_| replay);
        let recording = self.session.selected_recording();
        let shape = || {
            let setting = &recording?.setting;
            Some((setting.object.outline().ok()?, setting.pusher_radius))
        };
        (self.frame_cache).refresh_controller(controller, shape, self.run_generation, frame);
        (self.browsed).refresh_shown(&self.session, &self.labels, &self.settings.browser);
    }

    /// The browser's rows: every open recording that passes the filter, sorted, computed now (for
    /// commands and tests; the panel draws [`AppState::browser_shown`]'s rows in view).
    pub fn browser_rows(&self) -> Vec<Row<'_>> {
        (self.browsed).rows(&self.session, &self.labels, &self.settings.browser)
    }

    /// The ids of the browser's rows, filtered and sorted: [`AppState::browser_rows`]'s, kept
    /// between frames until something they depend on changes.
    pub fn browser_shown(&self) -> &[RecordingId] {
        self.browsed.shown_ids()
    }

    /// One row of the browser (the panel builds the rows in view).
    pub fn browser_row(&self, id: RecordingId) -> Option<Row<'_>> {
        self.browsed.row_of(id, &self.session, &self.labels)
    }

    /// The browser's columns for the recordings open (see `BrowserMemory::columns`), kept with the
    /// shown rows.
    pub fn browser_columns(&self) -> &[Column] {
        self.browsed.shown_columns()
    }

    /// The mean losses last seen on a recording's run.
    pub fn remembered_losses(&self, recording: &Recording) -> Option<MeanLosses> {
        self.browsed.losses_of(recording)
    }

    /// Reads the push parameters of the open recordings not seen before.
    pub(in crate::app::state) fn remember_parameters(&mut self) {
        self.browsed.remember_parameters(&self.session);
    }

    /// Keeps the selected recording's mean losses as its run learns.
    pub(in crate::app::state) fn remember_losses(&mut self) {
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
    pub(in crate::app::state) fn update_landscape(&mut self) -> bool {
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

    /// The selected recording's bag or dataset, whose choice (topics, features) can be made again:
    /// opening it with the new choice replaces the set.
    pub fn source_to_choose_again(&self) -> Option<ChooseAgain> {
        let dir = self.session.selected_set_dir()?;
        if dataset::is_dataset(dir) {
            Some(ChooseAgain::Dataset(dir.to_path_buf()))
        } else if bag::is_bag(dir) {
            Some(ChooseAgain::Bag(dir.to_path_buf()))
        } else {
            None
        }
    }
}

/// A source opened with a choice the user can make again.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ChooseAgain {
    Bag(PathBuf),
    Dataset(PathBuf),
}
