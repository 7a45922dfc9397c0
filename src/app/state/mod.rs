//! The app's state in plain Rust: no egui in here, so every rule is unit-tested headlessly.
//!
//! The panels only read [`AppState`] and push [`Command`]s; [`AppState::apply`] runs them after all
//! panels are drawn, and [`AppState::advance`] moves time (and online learning) forward.

// The rooms, one concern each (ARCHITECTURE.md says why this grouping): where recordings come from
// and which are open, playback, learning, models, labels, demos; then the state's commands and what
// the panels read across rooms.
pub mod commands;
pub mod demos;
pub mod labels;
pub mod learning;
pub mod models;
pub mod playback;
pub mod recordings;
pub mod sources;
pub mod views;

// The few pieces every room shares: work on a worker, what a room's command asks of the others,
// what survives a restart.
pub mod effect;
mod job;
mod persisted;

use std::path::PathBuf;

use pushlab_core::domain::DomainMismatch;
use pushlab_core::learn::{OnlineConfig, TrainConfig};
use pushlab_core::model::{ModelKind, OnlineParams, PhysicsOnlyModel};
use pushlab_core::recording::Recording;

use self::demos::demo::{DemoCommand, Demos};
use self::effect::Effect;
use self::labels::labeling::{LabelAction, Labeling};
use self::labels::proposals::{ProposalAction, ProposalState, ProposalTarget};
use self::learning::ahead::LearningAhead;
use self::learning::best_fit::{BestFitCommand, BestFitState};
use self::learning::landscape::{LandscapeCommand, LandscapeState};
use self::learning::next_push::{NextPushCommand, NextPushState};
use self::learning::online::OnlineRun;
use self::models::loaded::Models;
use self::models::training::{Training, TrainingChoice};
pub use self::persisted::Persisted;
use self::playback::cameras::{CameraCommand, Cameras};
use self::playback::layers::Layers;
use self::playback::overview::PathOverview;
use self::playback::timeline::{FrameMove, Timeline, TimelineCommand};
use self::recordings::browser::{BrowserCommand, BrowserMemory};
use self::recordings::session::{RecordingId, Session};
use self::sources::bag_import::{BagChooser, BagCommand};
use self::sources::dataset_import::{DatasetChooser, DatasetCommand};
use self::sources::growing::Growing;
use self::sources::live::{Live, LiveCommand};
use self::sources::sandbox::{SandboxCommand, SandboxSession};
pub use self::views::across::ChooseAgain;
use self::views::frame_cache::FrameCache;

/// Everything a panel can ask the app to do: one enum per concern.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    Timeline(TimelineCommand),
    /// What is open and shown.
    Session(SessionCommand),
    /// Online learning on the recording shown.
    Online(OnlineCommand),
    /// Offline training in the background.
    Training(TrainingCommand),
    /// Which layers the scene draws (the legend's toggles).
    SetLayers(Layers),
    /// Filter or sort the browser's table.
    Browser(BrowserCommand),
    /// Labeling on the selected recording at the frame shown.
    Label(LabelAction),
    /// Jump to the next (`true`) or previous label boundary of the selected recording.
    JumpToLabel {
        forward: bool,
    },
    /// The loss-landscape window.
    Landscape(LandscapeCommand),
    /// The Steer tab's search for the best θ of the recording shown.
    BestFit(BestFitCommand),
    /// The Steer tab's ranking of the object's next pushes.
    NextPush(NextPushCommand),
    /// Accept or reject label proposals on the selected recording.
    Proposal(ProposalAction),
    /// The Demos menu (see `demo`).
    Demo(DemoCommand),
    /// The form that chooses a bag's topics and object (see `bag_import`).
    Bag(BagCommand),
    Dataset(DatasetCommand),
    /// Which camera streams the camera panel shows.
    Camera(CameraCommand),
    /// A file asked for from a menu: losses, labels, a model.
    File(FileCommand),
    /// File → Connect to a live robot…: the form and the session (see `live`).
    Live(LiveCommand),
    /// Push it yourself (see `sources::sandbox`).
    Sandbox(SandboxCommand),
    /// A message for the status line from outside the state (a dialog that could not be shown,
    /// a screenshot saved).
    Report(String),
}

/// Files the menus ask for; each outcome is said on the status line (see `files`).
#[derive(Clone, Debug, PartialEq)]
pub enum FileCommand {
    /// The online run's losses and θ per frame, as CSV.
    SaveLosses(PathBuf),
    /// Load a model file and learn online with it.
    LoadModel(PathBuf),
    /// Save the model in use as a model file.
    SaveModel(PathBuf),
    /// The labels of the folder shown, as CSV or JSON.
    ExportLabels(PathBuf, LabelExportFormat),
    /// The plots of the run shown as a figure file (SVG, or PNG by the extension).
    ExportPlots(PathBuf),
    /// Stop writing the video of the push (nothing is written).
    CancelVideoExport,
    /// The sandbox's pushes as a recording set with the truth, into this folder.
    SaveSandbox(PathBuf),
}

/// The two label export formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LabelExportFormat {
    Csv,
    Json,
}

/// What is open and which recording is shown.
#[derive(Clone, Debug, PartialEq)]
pub enum SessionCommand {
    /// Show another recording (starts a fresh online run on it).
    Select(RecordingId),
    /// Open recordings from these paths (files or folders) in the background.
    Open(Vec<PathBuf>),
    /// Forget the load problems listed in the browser.
    DismissProblems,
    /// Stop the loads under way (a large bag, a slow disk).
    CancelLoading,
}

/// Online learning on the recording shown.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OnlineCommand {
    /// Steer: set `θ_online` at the current frame.
    SetTheta(OnlineParams),
    /// One online update from the current frame's sample.
    LearnThisFrame,
    /// Learn from every frame the timeline passes while moving forward.
    SetLearnWhilePlaying(bool),
    /// Back to `θ_online(0)` at frame 0, forgetting what was learned.
    ResetTheta,
    /// Change online steps / learning rate / optimiser (from the current frame on).
    SetConfig(OnlineConfig),
    /// Whether the next push of the same object goes on from what this one learned.
    SetCarryTheta(bool),
    /// Whether physics alone learns beside the run and the two are weighed (the run starts again,
    /// learned up to the frame shown).
    SetWeighPhysics(bool),
    /// How many steps what-if rollouts run ahead.
    SetWhatIfSteps(usize),
    /// Stop learning far ahead on a worker (after a long seek) where it got, keeping what it
    /// learned; θ is held from there.
    StopLearningAhead,
}

/// Offline training of a combined model, in the background.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TrainingCommand {
    /// Train on the recordings chosen in the Train tab.
    Start,
    /// Stop after the current epoch, keeping the best model so far.
    Cancel,
    /// Which combined model the Train tab trains.
    SetKind(ModelKind),
    /// Which recordings the Train tab trains on.
    Choose(TrainingChoice),
    /// Epochs, learning rate, horizon and seed of the Train tab.
    SetConfig(TrainConfig),
    /// Train a model for the open recordings and remember it for their folders (see `model_in_use`).
    TrainForOpenRecordings,
    /// Choose the recordings whose labels (or `setting.json`) put them in the offline split.
    ChooseOfflineLabelled,
}

/// What-if rollouts run this many steps ahead unless the user chooses otherwise.
pub const DEFAULT_WHAT_IF_STEPS: usize = 20;
/// The most steps a what-if rollout runs (each is one prediction, drawn as a ghost).
pub const MAX_WHAT_IF_STEPS: usize = 500;

/// The whole app state.
pub struct AppState {
    /// What survives a restart, kept here as it is saved: the recent paths, layers, online
    /// settings, the models per folder, the browser's view, the what-if steps. Playback speed and
    /// loop, and the cameras hidden, are the timeline's and the cameras' own while the app runs
    /// (this holds what they started with); [`AppState::persisted`] takes them from there.
    settings: Persisted,
    session: Session,
    models: Models,
    timeline: Timeline,
    /// Online learning on the selected recording; `None` until a recording is selected.
    run: Option<OnlineRun>,
    /// The physics-only model of the selected recording (for its prediction layer), built once per
    /// run rather than once per drawn frame.
    physics: Option<PhysicsOnlyModel>,
    /// The selected recording's path as the scene draws it whole (built once per selection).
    overview: PathOverview,
    training: Training,
    /// The labels files of the open recordings, and the labeling tools' state.
    labels: Labeling,
    /// The selected recording's label proposals, and those rejected.
    proposals: ProposalState,
    /// A short message for the status bar (what just happened, or what went wrong).
    status: Option<String>,
    /// Whether the open recordings lie outside the model's domain (see `model_in_use`).
    fit: Option<DomainMismatch>,
    /// Where models trained for folders are kept (the app's data folder); `None`: not kept.
    model_store: Option<PathBuf>,
    /// The browser's per-recording parameters and losses.
    browsed: BrowserMemory,
    /// The loss-landscape window and its background work.
    landscape: LandscapeState,
    /// The best θ for the recording shown, and its search in the background.
    best_fit: BestFitState,
    /// The object's next pushes ranked by what each would teach, and the ranking in the background.
    next_push: NextPushState,
    /// The Demos menu's presets and the demo running.
    demos: Demos,
    /// ROS 2 bags waiting for their topics to be chosen, and those being opened with a choice.
    bags: BagChooser,
    /// Datasets waiting for their features to be chosen, and those being opened with a choice.
    datasets: DatasetChooser,
    /// The selected recording's cameras and their frames.
    cameras: Cameras,
    /// What several panels read each frame, computed once per change.
    frame_cache: FrameCache,
    /// Counts the runs started, so that what was computed for one is not taken for another's.
    run_generation: u64,
    /// A copy of the run learning far ahead on a worker.
    learning_ahead: LearningAhead,
    /// The Connect form and the live session (see `live_feed`).
    live: Live,
    /// The push growing as its frames arrive, whatever feeds it (see `sources::grow`).
    growing: Option<Growing>,
    /// Push it yourself: the mystery object and the pushes made on it.
    sandbox: Option<SandboxSession>,
    /// The frames the path overview was made of (a live push's is made again as it grows).
    overview_frames: usize,
    /// File → Export video of this push…, while it is written.
    video_export: Option<commands::video_export::VideoExport>,
}

impl AppState {
    /// A state with nothing open, restoring what was persisted.
    pub fn new(persisted: Persisted, models: Models) -> Self {
        let mut timeline = Timeline::new(Vec::new());
        timeline.apply(TimelineCommand::SetSpeed(persisted.speed));
        timeline.apply(TimelineCommand::SetLoop(persisted.looping));
        let cameras = Cameras::new(persisted.hidden_cameras.clone());
        let live = Live::new(persisted.live_choices.clone(), persisted.live_url.clone());
        let mut settings = persisted;
        settings.what_if_steps = settings.what_if_steps.clamp(1, MAX_WHAT_IF_STEPS);
        let mut training = Training::default();
        training.follow_model(models.kind(), models.horizon());
        Self {
            settings,
            session: Session::default(),
            models,
            timeline,
            run: None,
            physics: None,
            overview: PathOverview::default(),
            training,
            labels: Labeling::default(),
            proposals: ProposalState::default(),
            status: None,
            fit: None,
            model_store: None,
            browsed: BrowserMemory::default(),
            landscape: LandscapeState::default(),
            best_fit: BestFitState::default(),
            next_push: NextPushState::default(),
            demos: Demos::default(),
            bags: BagChooser::default(),
            datasets: DatasetChooser::default(),
            cameras,
            frame_cache: FrameCache::default(),
            run_generation: 0,
            learning_ahead: LearningAhead::default(),
            live,
            growing: None,
            sandbox: None,
            overview_frames: 0,
            video_export: None,
        }
    }

    /// Where the app keeps its own files, beside eframe's state and never in a user's data: models
    /// trained for folders (`models/`) and labels whose own folder cannot be written
    /// (`unsaved-labels/`). `None`: neither is kept.
    pub fn keep_files_in(&mut self, app_dir: Option<PathBuf>) {
        self.model_store = app_dir.as_ref().map(|dir| dir.join("models"));
        self.labels.rescue_dir = app_dir.map(|dir| dir.join("unsaved-labels"));
    }

    /// Reads the Demos menu's presets from a suite file (see `demo`).
    pub fn load_demos(&mut self, suite: &std::path::Path) {
        self.demos = Demos::load(suite);
    }

    /// Adds a set built in memory (benchmarks, tests) without showing it, listed in the browser as
    /// an opened one is; returns its first recording's id.
    pub fn add_set(&mut self, set: pushlab_core::recording::RecordingSet) -> RecordingId {
        self.session.sets.push(set);
        self.remember_parameters();
        self.refresh_frame_cache();
        RecordingId {
            set: self.session.sets.len() - 1,
            recording: 0,
        }
    }

    /// What to persist: the settings, with the timeline's speed and loop and the cameras hidden.
    pub fn persisted(&self) -> Persisted {
        Persisted {
            speed: self.timeline.speed,
            looping: self.timeline.looping,
            hidden_cameras: self.cameras.hidden().clone(),
            live_choices: self.live.remembered().clone(),
            live_url: self.live.last_url().map(str::to_owned),
            ..self.settings.clone()
        }
    }

    /// Saves every labels file with unsaved edits now (the window is closing); returns what to
    /// tell the user about each that could not be written where it belongs.
    pub fn save_labels_on_exit(&mut self) -> Vec<String> {
        self.labels.save_on_exit()
    }

    /// Saves labels files whose autosave is due; `now_s` is any steady clock in seconds.
    pub fn autosave_labels(&mut self, now_s: f64) {
        if let Some(message) = self.labels.autosave(now_s) {
            self.status = Some(message);
        }
    }

    /// The selected recording.
    pub fn recording(&self) -> Option<&Recording> {
        self.session.selected_recording()
    }

    /// Index of the frame shown.
    pub fn frame(&self) -> usize {
        self.timeline.frame()
    }

    /// `θ_online` at the frame shown (or `θ_online(0)` of the model when nothing is selected).
    pub fn theta(&self) -> Option<OnlineParams> {
        self.run.as_ref().map(|r| r.theta_at(self.frame()))
    }

    /// Applies one command.
    pub fn apply(&mut self, command: Command) {
        self.apply_command(command);
        self.remember_losses();
        self.learning_ahead_follows_labels();
        self.refresh_frame_cache();
    }

    fn apply_command(&mut self, command: Command) {
        match command {
            Command::Timeline(c) => {
                let before = self.timeline.frame();
                self.timeline.apply(c);
                // Stepping passes the frames between; a seek, a jump or a restart from the end
                // lands on a frame without passing the ones between.
                let how = match c {
                    TimelineCommand::Step(_) => FrameMove::Passed,
                    _ => FrameMove::Jumped,
                };
                if self.timeline.frame() != before {
                    self.frame_moved(before, how);
                }
                self.growing_timeline_moved();
            }
            Command::Session(c) => self.apply_session(c),
            Command::Online(c) => self.apply_online(c),
            Command::Training(c) => self.apply_training(c),
            Command::SetLayers(layers) => self.settings.layers = layers,
            Command::Browser(c) => self.settings.browser.apply(c),
            Command::Label(action) => self.apply_effects(vec![Effect::Label(action)]),
            Command::JumpToLabel { forward } => self.jump_to_label(forward),
            Command::Landscape(c) => {
                self.landscape.apply(c);
                self.update_landscape();
            }
            Command::BestFit(c) => {
                let skip = self.frames_to_skip();
                self.best_fit.apply(c, self.run.as_ref(), &skip);
            }
            Command::NextPush(c) => {
                let candidates = self.pushes_to_rank();
                self.next_push.apply(c, self.run.as_ref(), candidates);
            }
            Command::Proposal(action) => {
                let target = self.label_target();
                let recording = self.session.selected_recording();
                let (Some(recording), Some(target)) = (recording, target) else {
                    return;
                };
                let on = ProposalTarget {
                    source: &recording.source,
                    target: &target,
                    labels: &self.labels,
                    frame: self.timeline.frame(),
                };
                let asked = self.proposals.apply(action, on);
                self.apply_effects(Effect::asked_by_proposals(asked));
            }
            Command::Demo(c) => self.apply_demo(c),
            Command::Bag(c) => {
                let effects = self.bags.apply(c);
                self.apply_effects(effects);
            }
            Command::Dataset(c) => {
                let effects = self.datasets.apply(c);
                self.apply_effects(effects);
            }
            Command::Camera(c) => self.cameras.apply(c),
            Command::File(c) => self.apply_file(c),
            Command::Live(c) => self.apply_live(&c),
            Command::Sandbox(c) => self.apply_sandbox(c),
            Command::Report(message) => self.status = Some(message),
        }
    }

    /// Advances time by `dt` seconds and merges finished background work. Returns whether anything
    /// is still moving (so the caller keeps repainting).
    pub fn advance(&mut self, dt: f64) -> bool {
        self.poll_opening();
        let live = self.poll_live();
        let sandbox = self.poll_sandbox(dt);
        let video = self.poll_video_export();
        self.proposals.poll();
        if let Some(message) = self.training.poll() {
            self.status = Some(message);
        }
        if let Some(finished) = self.training.take_finished() {
            self.take_trained(finished);
        }
        let before = self.timeline.frame();
        if self.timeline.update(dt) {
            let how = if self.timeline.frame() >= before {
                FrameMove::Passed
            } else {
                FrameMove::Wrapped
            };
            self.frame_moved(before, how);
        }
        self.remember_losses();
        let landscape = self.update_landscape();
        let best_fit = self.best_fit.poll();
        let next_push = self.next_push.poll();
        self.learning_ahead_follows_labels();
        let learning_ahead = self.poll_learning_ahead();
        (self.cameras).update(
            self.timeline.frame_time(),
            self.timeline.playing,
            self.timeline.speed,
        );
        self.refresh_frame_cache();
        self.timeline.playing
            || self.cameras.is_busy()
            || self.session.loading().is_some()
            || self.training.is_running()
            || self.proposals.is_running()
            || self.bags.listing().is_some()
            || self.datasets.listing().is_some()
            || landscape
            || best_fit
            || next_push
            || learning_ahead
            || live
            || sandbox
            || video
    }

    /// A fresh timeline and online run for the selected recording; labeling starts over too (no
    /// stroke, no in point).
    pub fn start_run(&mut self) {
        self.labels.end_stroke();
        self.labels.in_point = None;
        self.start_run_keeping_labels();
    }

    fn start_run_keeping_labels(&mut self) {
        self.run_generation += 1;
        self.learning_ahead.cancel();
        self.frame_cache.clear();
        self.cameras.select(self.session.selected_recording());
        let Some(recording) = self.session.selected_recording() else {
            self.proposals.stop();
            self.run = None;
            self.physics = None;
            self.overview = PathOverview::default();
            self.timeline = Timeline::new(Vec::new());
            return;
        };
        let times = recording.trajectory.frames.iter().map(|f| f.time).collect();
        let (speed, looping) = (self.timeline.speed, self.timeline.looping);
        self.timeline = Timeline::new(times);
        self.timeline.apply(TimelineCommand::SetSpeed(speed));
        self.timeline.apply(TimelineCommand::SetLoop(looping));
        self.physics = self.models.physics_for(recording).ok();
        self.overview = PathOverview::of(&recording.trajectory);
        self.overview_frames = recording.trajectory.len();
        // Another push of the same object goes on from what the run shown learned, when asked to.
        let previous = self.run.take();
        let from = previous
            .as_ref()
            .filter(|p| self.settings.carry_theta && p.carries_to(recording));
        // A sandbox's push goes on from the push before it, whatever was shown meanwhile.
        let sandbox_start = (self.session.selected).and_then(|id| self.sandbox_carried_for(id));
        self.run = match self.models.learner_for(recording) {
            Ok((model, horizon)) => Some(match sandbox_start {
                Some(carried) => OnlineRun::again_from(
                    model,
                    recording,
                    (horizon, self.settings.online),
                    carried,
                    self.physics_to_weigh(),
                ),
                None => OnlineRun::starting(
                    model,
                    recording,
                    (horizon, self.settings.online),
                    from,
                    self.settings.start_com_shift,
                    self.physics_to_weigh(),
                ),
            }),
            Err(message) => {
                self.status = Some(message);
                None
            }
        };
        (self.proposals).refresh(self.session.selected_recording(), self.run.as_ref());
    }

    /// The physics-only model to learn beside the run and weigh against it, when that is on and a
    /// network is learned (physics alone learning is the run itself then).
    pub(super) fn physics_to_weigh(&self) -> Option<PhysicsOnlyModel> {
        (self.settings.weigh_physics && self.models.kind().is_some())
            .then(|| self.physics.clone())
            .flatten()
    }

    /// A fresh online run with the current models (a model trained or loaded), staying at the frame
    /// shown and learned up to it, playing on if it was, and keeping a paint stroke and the in
    /// point.
    pub fn restart_run_keeping_frame(&mut self) {
        let (frame, playing) = (self.frame(), self.timeline.playing);
        self.start_run_keeping_labels();
        self.timeline.apply(TimelineCommand::SeekTo(frame));
        // What the new model learned up to the frame shown, as a seek there from frame 0 would
        // learn: θ(0) held over those frames would show a model that learned nothing yet.
        self.learn_while_playing(0, self.frame());
        if playing {
            self.timeline.apply(TimelineCommand::TogglePlay);
        }
    }
}
