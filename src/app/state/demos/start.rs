//! Starting a demo, and its narration: a demo opens recordings, selects one, takes a model into use
//! or starts training one, and reads the online run — it spans the whole state, so it is the
//! state's method; the demos' own types (`demo`) know nothing of the state.

use std::path::{Path, PathBuf};

use pushlab_core::experiment::{ModelVariant, split_of};
use pushlab_core::files;
use pushlab_core::labels::Split;
use pushlab_core::model::ModelKind;
use pushlab_core::model_file::ModelFile;

use crate::app::state::AppState;
use crate::app::state::demos::demo::{ActiveDemo, DemoCommand, NarrationNumbers, narration};
use crate::app::state::labels::labeling::LabelTarget;
use crate::app::state::recordings::session::RecordingId;

impl AppState {
    pub(in crate::app::state) fn apply_demo(&mut self, command: DemoCommand) {
        match command {
            DemoCommand::Start(index) => {
                if let Err(why) = self.start_demo(index) {
                    self.status = Some(format!("demo not started: {why}"));
                }
            }
        }
    }

    /// Opens the experiment's recordings, shows its first online one and takes a model for its
    /// offline ones into use (remembered, else trained in the background).
    fn start_demo(&mut self, index: usize) -> Result<(), String> {
        let (spec, base) = self.demos.suite.clone()?;
        let experiment = spec
            .experiments
            .get(index)
            .ok_or_else(|| format!("there is no demo {index}"))?;
        if self.training.is_running() {
            return Err("a model is training; cancel it first".to_owned());
        }
        let offline_paths = canonical(&experiment.offline_paths(&base));
        let online_paths = canonical(&experiment.online_paths(&base));
        let missing: Vec<PathBuf> = offline_paths
            .iter()
            .chain(&online_paths)
            .filter(|p| self.recordings_under(p, None).is_empty())
            .cloned()
            .collect();
        if !missing.is_empty() {
            self.open_blocking(&missing);
        }
        let offline = self.recordings_in(&offline_paths, spec.split_wanted(Split::Offline));
        let online = self.recordings_in(&online_paths, spec.split_wanted(Split::Online));
        let (Some(&shown), false) = (online.first(), offline.is_empty()) else {
            return Err(format!(
                "\"{}\" has {} offline and {} online recordings open",
                experiment.name,
                offline.len(),
                online.len()
            ));
        };
        // Stepping is how a lecture sees learning, so learning follows the timeline.
        self.settings.learn_while_playing = true;
        self.session.selected = Some(shown);
        self.start_run();
        let variant = (spec.models_of(experiment).first().copied())
            .unwrap_or(ModelVariant::Kind(self.training.kind));
        let remembered = self.demo_model_for(&offline_paths, variant.kind());
        let model = match remembered {
            Some((file, path)) => {
                self.use_model_file(file, path.display().to_string());
                format!(
                    "the {} model trained before for these recordings",
                    variant.name()
                )
            }
            None => {
                self.training.kind = variant.kind();
                self.training.config = spec.train_config(experiment, variant);
                self.training.chosen = offline.iter().copied().collect();
                let recordings = self.training_recordings();
                if recordings.is_empty() {
                    return Err("its offline recordings have no sample to train on".to_owned());
                }
                self.training.start(recordings, offline_paths.clone());
                format!("a {} model trained now", variant.name())
            }
        };
        self.status = Some(format!("demo \"{}\": {model}", experiment.name));
        self.demos.active = Some(ActiveDemo {
            name: experiment.name.clone(),
            offline,
            online,
            model,
        });
        Ok(())
    }

    /// A model of `kind` trained before for these folders, if one can be read: the one the model
    /// store keeps for them and this kind, else the one remembered for all of them if it is of this
    /// kind. (Two demos may train two kinds on the same folders: the folders remember the newer,
    /// the store keeps both.)
    fn demo_model_for(&self, folders: &[PathBuf], kind: ModelKind) -> Option<(ModelFile, PathBuf)> {
        let stored = self.store_path(folders, kind).filter(|p| files::is_file(p));
        let remembered = || {
            let path = self.settings.folder_models.get(folders.first()?)?;
            let all = (folders.iter()).all(|f| self.settings.folder_models.get(f) == Some(path));
            all.then(|| path.clone())
        };
        [stored, remembered()]
            .into_iter()
            .flatten()
            .filter_map(|path| Some((ModelFile::load(&path).ok()?, path)))
            .find(|(file, _)| file.combined.kind() == kind)
    }

    /// The open recordings under any of `paths` in the split wanted (`None`: any).
    fn recordings_in(&self, paths: &[PathBuf], want: Option<Split>) -> Vec<RecordingId> {
        let mut ids: Vec<RecordingId> = paths
            .iter()
            .flat_map(|p| self.recordings_under(p, want))
            .collect();
        ids.sort();
        ids.dedup();
        ids
    }

    /// The open recordings whose file is `path` or lies in it, in the split wanted.
    fn recordings_under(&self, path: &Path, want: Option<Split>) -> Vec<RecordingId> {
        self.session
            .recordings()
            .filter(|(_, r)| {
                let source = pushlab_core::files::canonicalize(&r.source)
                    .unwrap_or_else(|_| r.source.clone());
                source.starts_with(path)
            })
            .filter(|(_, r)| {
                let labels = LabelTarget::of(r)
                    .and_then(|t| self.labels.document(&t.document))
                    .map(|d| d.set());
                want.is_none() || split_of(r, labels) == want
            })
            .map(|(id, _)| id)
            .collect()
    }

    /// What the narration line says now: training progress while the demo's model trains, else
    /// what online learning has done so far (θ where learning has got to, the losses over the frames
    /// learned up to there, whatever frame is shown).
    pub fn narration(&self) -> String {
        if self.training.is_running() {
            return format!(
                "Training the offline model: {} {:.0} % done. Cancel to use what it has learned so far.",
                self.training.phase(),
                100.0 * self.training.progress()
            );
        }
        let Some(run) = &self.run else {
            return "Choose a demo from the Demos menu.".to_owned();
        };
        narration(&NarrationNumbers {
            com_start: run.theta0().com_offset,
            com_now: run.theta_at(run.frontier()).com_offset,
            com_true: self.recording().and_then(|r| r.setting.com_offset),
            losses: run.mean_losses(),
            trust: run
                .model_weight()
                .map(|w| (w.at(run.frontier()), w.half_life_s())),
        })
    }
}

/// Paths made canonical where they exist, so that they compare with the recordings' files.
fn canonical(paths: &[PathBuf]) -> Vec<PathBuf> {
    paths
        .iter()
        .map(|p| pushlab_core::files::canonicalize(p).unwrap_or_else(|_| p.clone()))
        .collect()
}
