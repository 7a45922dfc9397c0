//! Files the user asks for from the menus: the losses of the run as CSV, the labels of the folder
//! shown exported as CSV or JSON, a model file loaded or saved. Each is a [`FileCommand`] whose
//! outcome is said on the status line; the methods return it too, for callers that want the error
//! (the command line's model, tests). Writes are atomic: a failed save leaves the old file.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::Context as _;
use pushlab_core::labels::export as label_export;
use pushlab_core::labels::pipeline::{key_of, labels_file_beside};
use pushlab_core::model_file::ModelFile;

use crate::app::state::commands::video_export::{VideoExport, VideoWork};
use crate::app::state::learning::online::{Carried, OnlineRun};
use crate::app::state::{AppState, FileCommand, LabelExportFormat};

impl AppState {
    /// Carries out a file command and says on the status line what happened.
    pub(in crate::app::state) fn apply_file(&mut self, command: FileCommand) {
        let message = match command {
            FileCommand::SaveLosses(path) => match self.save_losses_csv(&path) {
                Ok(rows) => format!("saved {rows} rows of losses to {}", path.display()),
                Err(e) => format!("could not save {}: {e:#}", path.display()),
            },
            FileCommand::LoadModel(path) => match self.load_model(&path) {
                Ok(()) => format!("model loaded from {}", path.display()),
                // The core refused the file before anything changed: say so, and why.
                Err(e) => format!(
                    "model not loaded, the {} stays in use: {e:#}",
                    self.models.learner_name()
                ),
            },
            FileCommand::ExportLabels(path, format) => match self.export_labels(&path, format) {
                Ok(rows) => format!("exported {rows} label rows to {}", path.display()),
                Err(e) => format!("could not export labels: {e:#}"),
            },
            FileCommand::ExportPlots(path) => match self.export_plots(&path) {
                Ok(frames) => format!(
                    "exported the plots of {frames} frames to {}",
                    path.display()
                ),
                Err(e) => format!("could not export the plots: {e:#}"),
            },
            FileCommand::CancelVideoExport => match self.video_export.take() {
                Some(export) => export.cancel(),
                None => "no video is being written".to_owned(),
            },
            FileCommand::SaveModel(path) => match self.save_model(&path) {
                Ok(()) => format!("model saved to {}", path.display()),
                Err(e) => format!("{e:#}"),
            },
            FileCommand::SaveSandbox(dir) => {
                // Says what it wrote itself.
                self.save_sandbox(&dir);
                return;
            }
        };
        self.status = Some(message);
    }

    /// Writes the plots of the run shown — its losses and θ as the plots panel draws them — as a
    /// figure file (`figures::run`: SVG, or PNG by the extension), atomically. Returns the frames
    /// learned that it shows.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn export_plots(&self, path: &Path) -> anyhow::Result<usize> {
        use crate::figures::{self, run::RunFigure};
        let (Some(run), Some(recording)) = (self.run.as_ref(), self.recording()) else {
            anyhow::bail!("no recording is shown");
        };
        let frames = &recording.trajectory.frames;
        let t0 = frames.first().map_or(0.0, |f| f.time);
        let learned = run.frontier();
        let setting = &recording.setting;
        let figure = RunFigure {
            title: format!("{} — {}", recording.name, self.models.learner_name()),
            times: frames.iter().map(|f| f.time - t0).collect(),
            fixed: run.fixed(),
            learned: &run.learned()[..learned.min(run.learned().len())],
            theta: &run.checkpoints()[..(learned + 1).min(run.checkpoints().len())],
            spreads: &run.spreads()[..(learned + 1).min(run.spreads().len())],
            truth: [
                setting.com_offset.map(|c| c[0]),
                setting.com_offset.map(|c| c[1]),
                setting.h,
            ],
        };
        figures::write(path, &figure)?;
        Ok(learned)
    }

    /// In a page the figure is not offered (see `dialogs::browser`).
    #[cfg(target_arch = "wasm32")]
    pub fn export_plots(&self, _: &Path) -> anyhow::Result<usize> {
        anyhow::bail!("exporting the plots as a figure needs the desktop app")
    }

    /// Exports the labels file of the selected recording's folder (every recording in it, with
    /// frame times from the open recordings) as CSV or JSON. Returns the number of segment and
    /// event rows.
    pub fn export_labels(&self, path: &Path, format: LabelExportFormat) -> anyhow::Result<usize> {
        let target = (self.label_target()).context("select a recording whose labels to export")?;
        let document = (self.labels.document(&target.document))
            .with_context(|| format!("{} could not be read", target.document.display()))?;
        let times: BTreeMap<String, Vec<f64>> = (self.session.recordings())
            .filter(|(_, r)| labels_file_beside(&r.source) == target.document)
            .filter_map(|(_, r)| {
                let key = key_of(&r.source)?;
                Some((key, r.trajectory.frames.iter().map(|f| f.time).collect()))
            })
            .collect();
        let set = document.set();
        let rows = label_export::rows(set, &times)?.len();
        let text = match format {
            LabelExportFormat::Csv => label_export::to_csv(set, &times)?,
            LabelExportFormat::Json => label_export::to_json(set, &times)?,
        };
        label_export::write(path, &text)?;
        Ok(rows)
    }

    /// The online run's losses as CSV, one row per sample: the fixed and online losses and `θ` at
    /// the frame (`θ_online(0)`, and with θ at each learned frame: the step that was learned there)
    /// at full precision. `None` without a run.
    pub fn losses_csv(&self) -> Option<String> {
        let run = self.run.as_ref()?;
        let recording = self.recording()?;
        let frames = &recording.trajectory.frames;
        let t0 = frames.first().map_or(0.0, |f| f.time);
        let mut csv = String::from(
            "frame,time,fixed_loss_pos,fixed_loss_rot,online_loss_pos,online_loss_rot,com_offset_x,com_offset_y,h\n",
        );
        for k in 0..run.sample_count() {
            let time = frames.get(k).map_or(f64::NAN, |f| f.time - t0);
            let fixed = run.evaluate_fixed(k)?.loss;
            let _ = write!(csv, "{k},{time},{},{}", fixed.pos(), fixed.rot);
            match run.learned().get(k).copied().flatten() {
                Some(_) => {
                    let online = run.evaluate(k)?.loss;
                    let _ = write!(csv, ",{},{}", online.pos(), online.rot);
                }
                None => csv.push_str(",,"),
            }
            if k <= run.frontier() {
                let theta = run.theta_at(k);
                let [x, y] = theta.com_offset;
                let _ = writeln!(csv, ",{x},{y},{}", theta.h);
            } else {
                csv.push_str(",,,\n");
            }
        }
        Some(csv)
    }

    /// Saves [`AppState::losses_csv`] atomically; returns the number of data rows.
    pub fn save_losses_csv(&self, path: &Path) -> anyhow::Result<usize> {
        let csv = self
            .losses_csv()
            .context("no recording selected: nothing to export")?;
        pushlab_core::atomic_file::write_atomically(path, csv.as_bytes())
            .with_context(|| format!("{}: cannot write", path.display()))?;
        Ok(csv.lines().count().saturating_sub(1))
    }

    /// Loads a model file and restarts online learning with it; a file the core refuses changes
    /// nothing.
    pub fn load_model(&mut self, path: &Path) -> anyhow::Result<()> {
        let file = ModelFile::load(path)?;
        self.use_model_file(file, path.display().to_string());
        Ok(())
    }

    /// Saves the combined model in use (and the pure-network baseline, if any) as a model file.
    pub fn save_model(&self, path: &Path) -> anyhow::Result<()> {
        let combined = (self.models.combined.as_ref())
            .context("no trained model to save: train one or load a model file first")?;
        let file = ModelFile {
            combined: combined.clone(),
            pure_nn: self.models.pure_nn.as_deref().cloned(),
            training: self.models.training.clone(),
        };
        file.save(path)?;
        Ok(())
    }
}

/// File → Export video of this push… (`video_export`): started with the work the app's shell
/// makes, polled every frame, cancelled by [`FileCommand::CancelVideoExport`].
impl AppState {
    /// Runs the push shown again from `carried` (where another state's run started, having gone on
    /// from an earlier push): what a video export's own state shows when the window's run carried
    /// θ on, which that state, opening the push alone, could not.
    pub fn go_on_as(&mut self, carried: Carried) {
        let Some(recording) = self.session.selected_recording() else {
            return;
        };
        if let Ok((model, horizon)) = self.models.learner_for(recording) {
            let physics = self.physics_to_weigh();
            self.run = Some(OnlineRun::again_from(
                model,
                recording,
                (horizon, self.settings.online),
                carried,
                physics,
            ));
        }
    }

    /// Starts writing a video of the push shown to `path` by `work` off the UI thread; one at a
    /// time (a second replaces the first, which stops and writes nothing).
    pub fn start_video_export(&mut self, path: PathBuf, work: VideoWork) {
        self.status = Some(format!(
            "writing a video of the push to {}…",
            path.display()
        ));
        self.video_export = Some(VideoExport::start(path, work));
    }

    /// The video being written and the share done.
    pub fn video_export(&self) -> Option<(&Path, f32)> {
        (self.video_export.as_ref()).map(|v| (v.path(), v.progress()))
    }

    /// Takes the video's end, said on the status line. Returns whether one is still being written.
    pub(in crate::app::state) fn poll_video_export(&mut self) -> bool {
        let Some(ended) = self.video_export.as_ref().map(VideoExport::ended) else {
            return false;
        };
        match ended {
            None => true,
            Some(said) => {
                self.status = Some(said);
                self.video_export = None;
                false
            }
        }
    }
}
