//! The session's, the online run's and training's commands, each applied by its own method, so
//! that [`AppState::apply`](crate::app::state::AppState::apply) only routes.

use pushlab_core::recording::SourceChoice;

use crate::app::state::effect::Effect;
use crate::app::state::playback::timeline::TimelineCommand;
use crate::app::state::{
    AppState, Command, MAX_WHAT_IF_STEPS, OnlineCommand, SessionCommand, TrainingCommand,
};

impl AppState {
    /// Carries out, in order, what sub-states' commands asked of the rest of the state.
    pub(in crate::app::state) fn apply_effects(&mut self, effects: Vec<Effect>) {
        for effect in effects {
            match effect {
                Effect::Status(message) => self.status = Some(message),
                Effect::Select(id) => self.apply_session(SessionCommand::Select(id)),
                Effect::OpenBag { bag, choice } => {
                    // Earlier problems of this bag are retried now; one after this load is new.
                    self.session.problems.retain(|p| !p.path.starts_with(&bag));
                    let choice = SourceChoice::Bag(choice);
                    (self.session).start_loading_choosing(vec![bag.clone()], vec![(bag, choice)]);
                }
                Effect::OpenDataset { dataset, choice } => {
                    self.session.problems.retain(|p| p.path != dataset);
                    let choice = SourceChoice::Dataset(*choice);
                    (self.session)
                        .start_loading_choosing(vec![dataset.clone()], vec![(dataset, choice)]);
                }
                Effect::Problem(problem) => self.session.problems.push(problem),
                Effect::Label(action) => {
                    let (target, frame) = (self.label_target(), self.frame());
                    if let Some(message) = self.labels.apply(target.as_ref(), frame, action) {
                        self.status = Some(message);
                    }
                }
            }
        }
    }

    pub(in crate::app::state) fn apply_session(&mut self, command: SessionCommand) {
        match command {
            SessionCommand::Select(id) => {
                if self.session.get(id).is_some() {
                    self.session.selected = Some(id);
                    self.start_run();
                }
            }
            SessionCommand::Open(paths) => {
                self.remember(&paths);
                // Opening again is how a fixed labels file gets read again.
                self.labels.unreadable.clear();
                self.session.start_loading(paths);
            }
            SessionCommand::DismissProblems => self.session.problems.clear(),
            SessionCommand::CancelLoading => {
                if self.session.cancel_loading() {
                    self.bags.loading_cancelled();
                    self.datasets.loading_cancelled();
                    self.status = Some("opening cancelled".to_owned());
                }
            }
        }
    }

    pub(in crate::app::state) fn apply_online(&mut self, command: OnlineCommand) {
        let frame = self.frame();
        if let OnlineCommand::SetTheta(_)
        | OnlineCommand::LearnThisFrame
        | OnlineCommand::ResetTheta
        | OnlineCommand::SetConfig(_) = command
        {
            // A copy learning ahead would overwrite the change when it is back.
            self.drop_learning_ahead();
        }
        match command {
            OnlineCommand::SetTheta(theta) => {
                if let Some(run) = &mut self.run {
                    run.set_theta_at(frame, theta);
                }
            }
            OnlineCommand::LearnThisFrame => {
                let skip = self.frames_to_skip();
                if let Some(run) = &mut self.run {
                    if run.is_skipped(frame, &skip) {
                        self.status = Some(format!(
                            "frame {frame} is not learned from: its sample touches a frame labelled \\
                             to skip in training (bad tracking); erase that label to learn from it"
                        ));
                    } else if run.learn_this_frame(frame).is_none() {
                        self.status = Some(format!(
                            "frame {frame} has no sample: it is within the prediction horizon of the end"
                        ));
                    }
                }
            }
            OnlineCommand::SetLearnWhilePlaying(on) => self.settings.learn_while_playing = on,
            OnlineCommand::ResetTheta => {
                if let Some(run) = &mut self.run {
                    run.reset();
                }
            }
            OnlineCommand::SetConfig(config) => {
                self.settings.online = config;
                if let Some(run) = &mut self.run {
                    // Steps learned after this frame used the old rule: learn them again.
                    run.set_config_at(frame, config);
                }
            }
            OnlineCommand::SetCarryTheta(on) => self.settings.carry_theta = on,
            OnlineCommand::SetWeighPhysics(on) => {
                if self.settings.weigh_physics != on {
                    self.settings.weigh_physics = on;
                    self.restart_run_keeping_frame();
                }
            }
            OnlineCommand::SetWhatIfSteps(steps) => {
                self.settings.what_if_steps = steps.clamp(1, MAX_WHAT_IF_STEPS);
            }
            OnlineCommand::StopLearningAhead => self.stop_learning_ahead(),
        }
    }

    pub(in crate::app::state) fn apply_training(&mut self, command: TrainingCommand) {
        match command {
            TrainingCommand::Start => self.start_training(),
            TrainingCommand::Cancel => self.training.cancel(),
            TrainingCommand::SetKind(kind) => self.training.set_kind(kind),
            TrainingCommand::Choose(choice) => self.choose_for_training(choice),
            TrainingCommand::SetConfig(config) => self.training.set_config(config),
            TrainingCommand::TrainForOpenRecordings => self.train_for_open_recordings(),
            TrainingCommand::ChooseOfflineLabelled => self.choose_offline_labelled(),
        }
    }

    /// Seeks to the next (`forward`) or previous label boundary of the recording shown, or says
    /// there is none.
    pub(in crate::app::state) fn jump_to_label(&mut self, forward: bool) {
        let frame = self.frame();
        let boundary = self
            .label_target()
            .and_then(|t| self.labels.labels_of(&t).cloned())
            .and_then(|l| {
                if forward {
                    l.next_boundary(frame)
                } else {
                    l.previous_boundary(frame)
                }
            });
        match boundary {
            Some(to) => self.apply(Command::Timeline(TimelineCommand::SeekTo(to))),
            None => {
                let which = if forward { "after" } else { "before" };
                self.status = Some(format!("no label {which} frame {frame}"));
            }
        }
    }
}
