//! Whether the model in use fits the recordings that are open, and making one that does.
//!
//! A model file records the domain it was trained on (object sizes, pusher radii, frame rates,
//! speeds: `pushlab_core::domain::Domain`); the core's check says when the open recordings lie
//! outside it, and the app says so in the status line and the Steer tab. **Train for these
//! recordings** trains the kind chosen in the Train tab in the background — on the recordings the
//! labels put in the offline split, else on every open recording but the one shown — and the model is
//! saved in the app's model store and remembered for the recordings' folders, so that opening them
//! again reopens it.

use std::collections::BTreeSet;
use std::hash::{Hash, Hasher};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use pushlab_core::domain::DomainMismatch;
use pushlab_core::model::ModelKind;
use pushlab_core::model_file::ModelFile;

use crate::app::state::AppState;
use crate::app::state::models::training::Finished;
use crate::app::state::recordings::session::RecordingId;

impl AppState {
    /// Whether the open recordings lie outside the domain of the model in use (computed when
    /// recordings or the model change, not per frame).
    pub fn domain_mismatch(&self) -> Option<&DomainMismatch> {
        self.fit.as_ref()
    }

    /// Checks the open recordings against the model's domain again.
    pub(in crate::app::state) fn refresh_fit(&mut self) {
        self.fit = self.models.training.domain.as_ref().and_then(|domain| {
            domain.mismatch(self.session.recordings().map(|(_, recording)| recording))
        });
    }

    /// Takes a model file into use: predictions, online learning and the domain check follow it.
    pub fn use_model_file(&mut self, file: ModelFile, source: String) {
        self.models.combined = Some(file.combined);
        self.models.pure_nn = file.pure_nn.map(Arc::new);
        self.models.training = file.training;
        self.models.source = Some(source);
        (self.training).follow_model(self.models.kind(), self.models.horizon());
        self.refresh_fit();
        // The browser's losses were measured under the model before: next to the new model's
        // they would compare two models, not two pushes.
        self.browsed.forget_losses();
        self.restart_run_keeping_frame();
    }

    /// The folders of the open recordings, sorted.
    fn open_folders(&self) -> Vec<PathBuf> {
        let folders: BTreeSet<PathBuf> = self
            .session
            .recordings()
            .filter_map(|(_, r)| r.source.parent().map(Path::to_path_buf))
            .map(|folder| std::path::absolute(&folder).unwrap_or(folder))
            .collect();
        folders.into_iter().collect()
    }

    /// Starts training a model for the open recordings: on those labelled offline, else on all but
    /// the one shown; at the horizon of the model in use.
    pub(in crate::app::state) fn train_for_open_recordings(&mut self) {
        if self.training.is_running() {
            return;
        }
        let all: Vec<RecordingId> = self.session.recordings().map(|(id, _)| id).collect();
        let offline = self.offline_labelled();
        let shown = self.session.selected;
        let (chosen, which) = if offline.is_empty() {
            let others: Vec<RecordingId> =
                all.into_iter().filter(|&id| Some(id) != shown).collect();
            (others, "every open recording but the one shown")
        } else {
            (offline, "the recordings labelled offline")
        };
        self.training.chosen = chosen.into_iter().collect();
        self.training.config.horizon = self.models.horizon();
        let horizon = self.training.config.horizon;
        let recordings = self.training_recordings();
        if recordings.is_empty() {
            self.status = Some(format!(
                "nothing to train on: {which} have no sample at horizon {horizon}"
            ));
            return;
        }
        let count = recordings.len();
        self.training.start(recordings, self.open_folders());
        self.status = Some(format!(
            "training the {} model for these recordings on {which} ({count})…",
            self.training.kind
        ));
    }

    /// Takes a finished training run's model into use; one trained for folders is saved in the
    /// model store and remembered for them.
    pub(in crate::app::state) fn take_trained(&mut self, finished: Finished) {
        let Finished { file, for_folders } = finished;
        let mut source = "trained in the app, not saved".to_owned();
        if !for_folders.is_empty() {
            match self.store_for(&for_folders, &file) {
                Ok(path) => {
                    source = path.display().to_string();
                    for folder in &for_folders {
                        self.settings
                            .folder_models
                            .insert(folder.clone(), path.clone());
                    }
                }
                Err(why) => {
                    self.status = Some(format!(
                        "the model trained for these recordings is in use but not remembered: {why}"
                    ));
                }
            }
        }
        self.use_model_file(file, source);
    }

    /// Saves a model trained for `folders` in the model store, at [`Self::store_path`].
    fn store_for(&self, folders: &[PathBuf], file: &ModelFile) -> Result<PathBuf, String> {
        let path = (self.store_path(folders, file.combined.kind()))
            .ok_or("the app has no folder to keep models in")?;
        if let Some(store) = path.parent() {
            pushlab_core::files::create_dir_all(store)
                .map_err(|e| format!("cannot create {}: {e}", store.display()))?;
        }
        file.save(&path).map_err(|e| e.to_string())?;
        Ok(path)
    }

    /// Where the model store keeps the model of `kind` trained for `folders`: named after the
    /// first folder and the kind, and a hash of them all, so that a model of the other kind for
    /// the same folders is kept beside it.
    pub(in crate::app::state) fn store_path(
        &self,
        folders: &[PathBuf],
        kind: ModelKind,
    ) -> Option<PathBuf> {
        let store = self.model_store.as_ref()?;
        let mut hasher = std::collections::hash_map::DefaultHasher::new();
        folders.hash(&mut hasher);
        let name = folders
            .first()
            .and_then(|f| f.file_name())
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "recordings".to_owned());
        Some(store.join(format!("{name}-{kind}-{:016x}.json", hasher.finish())))
    }

    /// After recordings were opened: reopens the model remembered for their folders, if any and if
    /// it is not already in use.
    pub(in crate::app::state) fn reopen_folder_model(&mut self) {
        let remembered = self
            .open_folders()
            .into_iter()
            .find_map(|folder| Some((self.settings.folder_models.get(&folder)?.clone(), folder)));
        let Some((path, folder)) = remembered else {
            return;
        };
        if self.models.source.as_deref() == Some(&path.display().to_string()) {
            return;
        }
        match ModelFile::load(&path) {
            Ok(file) => {
                self.use_model_file(file, path.display().to_string());
                self.status = Some(format!(
                    "reopened the model trained for {}: {} ({})",
                    folder.display(),
                    self.models.learner_name(),
                    path.display()
                ));
            }
            Err(e) => {
                self.status = Some(format!(
                    "the model remembered for {} could not be read, so the current one stays: {e}",
                    folder.display()
                ));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use pushlab_core::model_file::ModelFile;

    use crate::app::state::models::Models;
    use crate::app::state::playback::timeline::TimelineCommand;
    use crate::app::state::{AppState, Command, Persisted};

    #[test]
    fn another_model_clears_the_losses_the_browser_showed() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut state = AppState::new(Persisted::default(), Models::default());
        state.open_blocking(&[root.join("sample-data/box1-paper-center-front")]);
        state.settings.learn_while_playing = true;
        for _ in 0..20 {
            state.apply(Command::Timeline(TimelineCommand::Step(1)));
        }
        let with_losses = |state: &AppState| {
            (state.browser_rows().iter())
                .filter(|row| row.losses.is_some())
                .count()
        };
        assert_eq!(with_losses(&state), 1);
        let file = ModelFile::load(&root.join("assets/default-model.json")).expect("the default");
        state.use_model_file(file, "default".into());
        assert_eq!(with_losses(&state), 0);
        // The run under the new model fills its row in again as it learns.
        for _ in 0..5 {
            state.apply(Command::Timeline(TimelineCommand::Step(1)));
        }
        assert_eq!(with_losses(&state), 1);
    }

    #[test]
    fn another_model_taken_at_a_frame_shows_what_it_learned_up_to_that_frame() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let default = || ModelFile::load(&root.join("assets/default-model.json")).expect("default");
        let opened = || {
            let mut state = AppState::new(Persisted::default(), Models::default());
            state.open_blocking(&[root.join("sample-data/box1-paper-center-front")]);
            state.settings.learn_while_playing = true;
            state
        };
        // The model taken at frame 20 ...
        let mut state = opened();
        state.apply(Command::Timeline(TimelineCommand::SeekTo(20)));
        state.use_model_file(default(), "default".into());
        // ... against a run under that model from frame 0, sought to frame 20.
        let mut reference = opened();
        reference.use_model_file(default(), "default".into());
        reference.apply(Command::Timeline(TimelineCommand::SeekTo(20)));

        let (run, reference) = (state.run().expect("a run"), reference.run().expect("a run"));
        assert_eq!(state.frame(), 20);
        assert_eq!(
            run.frontier(),
            20,
            "frames 0..20 are learned, not held at θ(0)"
        );
        assert_eq!(run.checkpoints(), reference.checkpoints());
        assert_ne!(run.theta_at(20), run.theta0(), "θ moved from θ(0)");
    }
}
