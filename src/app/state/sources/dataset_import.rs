//! Opening a Push-T dataset (a zarr replay buffer or a LeRobot folder) in the app: which feature is
//! the pusher, how the T is read, at what scale. The rules — the features a dataset offers, Push-T's
//! pre-selection, the remembered file, the import — are the core's (`recording::dataset`); this
//! keeps the form the user fills in and the datasets waiting for one, as `bag_import` does for bags.
//!
//! The invariant is the bags': a choice is remembered beside a dataset only after the dataset
//! opened with it; a choice that fails comes back to its form with the error, and the dataset's
//! earlier file (if any) is left as it was.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};

use pushlab_core::recording::NoProgress;
use pushlab_core::recording::dataset::{
    self, Columns, DatasetChoice, DatasetTable, ObjectSource, choice,
};

use crate::app::state::effect::Effect;
use crate::app::state::job::{Job, take_ended};
use crate::app::state::recordings::session::{LoadProblem, Session};
use crate::app::state::sources::choosing::{ChoiceForm, Choosing};

/// What a dataset offers to choose from, read once when its form opens.
#[derive(Clone, Debug, PartialEq)]
pub struct DatasetSummary {
    /// `zarr replay buffer`, `LeRobot dataset v3.0`.
    pub format: String,
    /// Each numeric feature's name and values per frame, in the dataset's order.
    pub features: Vec<(String, usize)>,
    pub episodes: usize,
    pub frames: usize,
    pub fps: f64,
}

impl DatasetSummary {
    fn of(table: &DatasetTable) -> Self {
        Self {
            format: table.format.to_string(),
            features: (table.features.iter())
                .map(|f| (f.name.clone(), f.width))
                .collect(),
            episodes: table.episodes.len(),
            frames: table.episodes.last().map_or(0, |e| e.end),
            fps: table.fps,
        }
    }
}

/// The choice being made for one dataset.
#[derive(Clone, Debug, PartialEq)]
pub struct DatasetForm {
    pub dataset: PathBuf,
    pub summary: DatasetSummary,
    /// The agent's x and y.
    pub pusher: Option<Columns>,
    /// The T, as a pose or as its keypoints.
    pub object: Option<ObjectSource>,
    pub metres_per_px: f64,
    /// Why the last attempt to open the dataset with this form failed.
    pub error: Option<String>,
}

impl DatasetForm {
    /// A form for `dataset`: what was remembered for it, or else Push-T's pre-selection.
    pub fn new(dataset: PathBuf, table: &DatasetTable, remembered: Option<DatasetChoice>) -> Self {
        let choice = remembered.or_else(|| choice::suggest(table));
        Self {
            dataset,
            summary: DatasetSummary::of(table),
            pusher: choice.as_ref().map(|c| c.pusher.clone()),
            object: choice.as_ref().map(|c| c.object.clone()),
            metres_per_px: choice
                .map_or(pushlab_core::geometry::PushT::DEFAULT_METRES_PER_PX, |c| {
                    c.metres_per_px
                }),
            error: None,
        }
    }

    /// Values per frame of the feature called `name`.
    pub fn width(&self, name: &str) -> Option<usize> {
        (self.summary.features.iter())
            .find(|(n, _)| n == name)
            .map(|(_, w)| *w)
    }

    /// The choice the form makes, or what is still missing or wrong, as the Open button's hover
    /// says it. Widths are checked here so that the form says at once what opening would refuse.
    pub fn choice(&self) -> Result<DatasetChoice, String> {
        let (Some(pusher), Some(object)) = (&self.pusher, &self.object) else {
            return Err("choose the pusher's and the object's features".to_owned());
        };
        self.fits(&pusher.feature, pusher.first, 2, "the pusher (x, y)")?;
        match object {
            ObjectSource::Pose(c) => {
                self.fits(&c.feature, c.first, 3, "the T's pose (x, y, angle)")?
            }
            ObjectSource::Keypoints(f) => self.fits(f, 0, 16, "the T's 8 keypoints")?,
        }
        let metres_per_px =
            choice::checked_scale(self.metres_per_px).map_err(|why| format!("the scale: {why}"))?;
        Ok(DatasetChoice {
            pusher: pusher.clone(),
            object: object.clone(),
            metres_per_px,
        })
    }

    fn fits(&self, feature: &str, first: usize, needed: usize, what: &str) -> Result<(), String> {
        match self.width(feature) {
            None => Err(format!("{what}: the dataset has no feature `{feature}`")),
            Some(width) if first + needed > width => Err(format!(
                "{what}: `{feature}` has {width} value(s) per frame, {needed} are needed from \
                 column {first}"
            )),
            Some(_) => Ok(()),
        }
    }
}

/// What the dataset form asks for.
#[derive(Clone, Debug, PartialEq)]
pub enum DatasetCommand {
    SetPusher(Columns),
    SetObject(ObjectSource),
    SetScale(f64),
    /// Open the dataset with the form's choice (remembered once it opened).
    Open,
    /// Do not open this dataset now; it stays listed as a problem with a way back to its form.
    Skip,
    /// Show the form for a dataset (its features are read on a worker thread).
    Choose(PathBuf),
}

impl ChoiceForm for DatasetForm {
    type Choice = DatasetChoice;
    const CHOSEN: &'static str = "features";

    fn source(&self) -> &Path {
        &self.dataset
    }

    fn set_error(&mut self, error: Option<String>) {
        self.error = error;
    }

    fn is_problem_of(problem: &LoadProblem, dataset: &Path) -> bool {
        problem.path == dataset
    }

    fn remember(dataset: &Path, choice: &DatasetChoice) -> std::io::Result<PathBuf> {
        choice::remember(dataset, choice)
    }
}

/// Datasets waiting for a choice, the ones being opened with one, and a dataset being read.
#[derive(Default)]
pub struct DatasetChooser {
    /// The forms and the datasets being opened with their choice (see [`Choosing`]).
    forms: Choosing<DatasetForm>,
    /// A dataset being read for its form, and those waiting to be.
    listing: Option<(PathBuf, Job<Result<DatasetForm, String>>)>,
    to_list: VecDeque<PathBuf>,
}

impl DatasetChooser {
    /// The form shown, if any.
    pub fn form(&self) -> Option<&DatasetForm> {
        self.forms.form()
    }

    /// The dataset being read for its form, if any.
    pub fn listing(&self) -> Option<&Path> {
        self.listing.as_ref().map(|(p, _)| p.as_path())
    }

    /// The load was cancelled: the datasets being opened go back to their forms, saying so.
    pub(in crate::app::state) fn loading_cancelled(&mut self) {
        self.forms.loading_cancelled();
    }

    /// Applies a command to the form shown. What it asks of the rest of the app — a dataset to
    /// open with its choice, a problem for the browser — comes back as effects.
    pub fn apply(&mut self, command: DatasetCommand) -> Vec<Effect> {
        if let DatasetCommand::Choose(dataset) = command {
            self.to_list.retain(|p| *p != dataset);
            self.to_list.push_back(dataset);
            self.list_next();
            return Vec::new();
        }
        let Some(form) = self.forms.form_mut() else {
            return Vec::new();
        };
        match command {
            DatasetCommand::SetPusher(columns) => form.pusher = Some(columns),
            DatasetCommand::SetObject(source) => form.object = Some(source),
            DatasetCommand::SetScale(metres_per_px) => form.metres_per_px = metres_per_px,
            DatasetCommand::Open => match form.choice() {
                Ok(choice) => {
                    let Some(dataset) = self.forms.open_shown(choice.clone()) else {
                        return Vec::new();
                    };
                    return vec![Effect::OpenDataset {
                        dataset,
                        choice: Box::new(choice),
                    }];
                }
                Err(why) => form.error = Some(why),
            },
            DatasetCommand::Skip => {
                let Some(dataset) = self.forms.skip_shown() else {
                    return Vec::new();
                };
                return vec![Effect::Problem(LoadProblem {
                    message: format!(
                        "{}: not opened: its pusher and object features were not chosen",
                        dataset.display()
                    ),
                    path: dataset,
                    bag_to_choose: false,
                    dataset_to_choose: true,
                })];
            }
            DatasetCommand::Choose(_) => {}
        }
        Vec::new()
    }

    /// Reads the next waiting dataset's features and remembered choice on a worker thread.
    fn list_next(&mut self) {
        if self.listing.is_some() {
            return;
        }
        let Some(dataset) = self.to_list.pop_front() else {
            return;
        };
        let worker_dataset = dataset.clone();
        let job = Job::spawn(move |_| {
            let form = dataset::read_table(&worker_dataset, &NoProgress)
                .map_err(|e| e.to_string())
                .map(|table| {
                    // A remembered file that cannot be read is not offered; the form starts afresh.
                    let remembered = choice::remembered(&worker_dataset).ok().flatten();
                    DatasetForm::new(worker_dataset, &table, remembered)
                });
            Some(form)
        });
        self.listing = Some((dataset, job));
    }

    /// Merges what loading and reading finished: forms for datasets that need a choice (the
    /// session's list of them is taken), and for each dataset opened with a choice, the choice
    /// remembered (it opened: the dataset is shown) or its form back with the session's error.
    pub fn poll(&mut self, session: &mut Session) -> Vec<Effect> {
        let mut effects = Vec::new();
        for dataset in std::mem::take(&mut session.datasets_to_choose) {
            self.to_list.retain(|p| *p != dataset);
            self.to_list.push_back(dataset);
        }
        if let Some((dataset, listed)) = take_ended(&mut self.listing) {
            let listed = listed.unwrap_or_else(|| {
                Err(format!(
                    "{}: reading its features stopped unexpectedly",
                    dataset.display()
                ))
            });
            match listed {
                Ok(form) => {
                    (session.problems).retain(|p| !(p.dataset_to_choose && p.path == form.dataset));
                    self.forms.show(form);
                }
                Err(why) => effects.push(Effect::Status(why)),
            }
        }
        self.list_next();
        effects.extend(self.forms.settle(session));
        effects
    }
}
