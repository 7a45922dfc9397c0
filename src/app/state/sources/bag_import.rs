//! Opening a ROS 2 bag in the app: which topics are the pusher and the object, and what the object
//! is. The rules — the streams a bag offers, the pre-selection, the settings found beside a bag,
//! the remembered file and the import — are the core's (`recording::bag::choice`); this keeps the
//! form the user fills in and the bags waiting for one.
//!
//! The invariant: a choice is remembered beside a bag only after the bag opened with it, so what is
//! remembered always worked once; a choice that fails comes back to its form with the error, and the
//! bag's earlier file (if any) is left as it was (kept once for bags and datasets in `choosing`).

use std::path::{Path, PathBuf};

use pushlab_core::recording::bag::{
    self, BagChoice, BagListing, ImportOptions, SettingSource, TopicInfo, TopicSpec, choice,
};

use crate::app::state::effect::Effect;
use crate::app::state::job::{Job, take_ended};
use crate::app::state::recordings::session::{LoadProblem, Session};
use crate::app::state::sources::choosing::{ChoiceForm, Choosing};

/// A box entered by hand, in the units the form shows (millimetres).
#[derive(Clone, Debug, PartialEq)]
pub struct EnteredBox {
    pub name: String,
    pub width_mm: f64,
    pub length_mm: f64,
    pub pusher_radius_mm: f64,
    pub material: String,
}

impl EnteredBox {
    /// Nothing entered yet: no size (the form asks for one), a 5 mm pusher, the usual probe.
    fn blank(name: String) -> Self {
        Self {
            name,
            width_mm: 0.0,
            length_mm: 0.0,
            pusher_radius_mm: 5.0,
            material: String::new(),
        }
    }
}

/// Where the form takes the object from.
#[derive(Clone, Debug, PartialEq)]
pub enum ObjectSource {
    /// A `setting.json`; with the setting's name, or why it cannot be used.
    File {
        path: PathBuf,
        checked: Result<String, String>,
    },
    Entered(EnteredBox),
}

/// The choice being made for one bag.
#[derive(Clone, Debug, PartialEq)]
pub struct BagForm {
    pub bag: PathBuf,
    pub topics: Vec<TopicInfo>,
    /// The pose streams the bag offers (topics, and TF child frames).
    pub streams: Vec<TopicSpec>,
    pub pusher: Option<TopicSpec>,
    pub object: Option<TopicSpec>,
    pub object_source: ObjectSource,
    /// `setting.json` files found beside the bag, nearest first.
    pub settings_found: Vec<PathBuf>,
    pub options: ImportOptions,
    /// The camera topics to show beside the push (of the bag's camera topics).
    pub cameras: Vec<String>,
    /// Why the last attempt to open the bag with this form failed.
    pub error: Option<String>,
    /// The bag's files cut short (a recording that did not finish): said before choosing, as the
    /// counts above are of what they hold before the cut.
    pub cut_short: Vec<String>,
}

impl BagForm {
    /// A form for `bag`: what was remembered for it, or else the core's pre-selection and the
    /// nearest `setting.json` beside it.
    pub fn new(bag: PathBuf, listing: BagListing, remembered: Option<BagChoice>) -> Self {
        let BagListing { topics, cut_short } = listing;
        let settings_found = choice::settings_beside(&bag);
        let streams = choice::candidates(&topics);
        let stem = bag
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
        let entered = ObjectSource::Entered(EnteredBox::blank(stem));
        let (pusher, object, object_source, options, cameras) = match remembered {
            Some(c) => {
                let source = match c.setting {
                    SettingSource::File(path) => file_source(path),
                    SettingSource::Entered(s) => ObjectSource::Entered(entered_of(&s)),
                };
                (Some(c.pusher), Some(c.object), source, c.options, c.cameras)
            }
            None => {
                let (pusher, object) = choice::suggest(&topics);
                let source = settings_found.first().cloned().map_or(entered, file_source);
                let cameras = choice::suggest_cameras(&topics);
                (pusher, object, source, ImportOptions::default(), cameras)
            }
        };
        Self {
            bag,
            topics,
            streams,
            pusher,
            object,
            object_source,
            settings_found,
            options,
            cameras,
            error: None,
            cut_short,
        }
    }

    /// The choice the form makes, or what is still missing, as the Open button's hover says it.
    pub fn choice(&self) -> Result<BagChoice, String> {
        let (Some(pusher), Some(object)) = (&self.pusher, &self.object) else {
            return Err("choose the pusher's and the object's topics".to_owned());
        };
        if pusher == object {
            return Err(format!("the pusher and the object are both {pusher}"));
        }
        let setting = match &self.object_source {
            ObjectSource::File { path, checked } => match checked {
                Ok(_) => SettingSource::File(path.clone()),
                Err(why) => return Err(why.clone()),
            },
            ObjectSource::Entered(b) => SettingSource::Entered(
                choice::entered_box(
                    &b.name,
                    b.width_mm * 1e-3,
                    b.length_mm * 1e-3,
                    b.pusher_radius_mm * 1e-3,
                    Some(&b.material),
                )
                .map_err(|why| format!("the object: {why}"))?,
            ),
        };
        Ok(BagChoice {
            pusher: pusher.clone(),
            object: object.clone(),
            setting,
            options: self.options,
            cameras: self.cameras.clone(),
        })
    }
}

/// A setting file, read and checked once when chosen (not on every frame the form is drawn).
fn file_source(path: PathBuf) -> ObjectSource {
    let checked = SettingSource::File(path.clone())
        .resolve()
        .map(|s| s.name)
        .map_err(|e| e.to_string());
    ObjectSource::File { path, checked }
}

fn entered_of(setting: &pushlab_core::recording::Setting) -> EnteredBox {
    let (width, length) = match setting.object {
        pushlab_core::recording::ObjectShape::Box { width, length } => (width, length),
        // Only boxes are entered in the form; a polygon or a preset comes from a setting file.
        pushlab_core::recording::ObjectShape::Polygon { .. }
        | pushlab_core::recording::ObjectShape::Preset(_) => (0.0, 0.0),
    };
    EnteredBox {
        name: setting.name.clone(),
        width_mm: width * 1e3,
        length_mm: length * 1e3,
        pusher_radius_mm: setting.pusher_radius * 1e3,
        material: setting.material.clone().unwrap_or_default(),
    }
}

/// What the bag form asks for.
#[derive(Clone, Debug, PartialEq)]
pub enum BagCommand {
    SetPusher(TopicSpec),
    SetObject(TopicSpec),
    /// Take the object from this `setting.json`.
    UseSettingFile(PathBuf),
    /// Enter the object by hand (keeps what was entered before).
    EnterObject,
    SetEntered(EnteredBox),
    SetOptions(ImportOptions),
    /// Show the camera topic beside the push, or not.
    SetCamera {
        topic: String,
        shown: bool,
    },
    /// Open the bag with the form's choice (remembered once it opened).
    Open,
    /// Do not open this bag now; it stays listed as a problem with a way back to its form.
    Skip,
    /// Show the form again for a bag (its topics are read on a worker thread).
    ChooseAgain(PathBuf),
}

impl ChoiceForm for BagForm {
    type Choice = BagChoice;
    const CHOSEN: &'static str = "topics";

    fn source(&self) -> &Path {
        &self.bag
    }

    fn set_error(&mut self, error: Option<String>) {
        self.error = error;
    }

    fn is_problem_of(problem: &LoadProblem, bag: &Path) -> bool {
        // A rosbag2 folder's problem may name a file inside it.
        problem.path.starts_with(bag)
    }

    fn remember(bag: &Path, choice: &BagChoice) -> std::io::Result<PathBuf> {
        choice::remember(bag, choice)
    }
}

/// Bags waiting for a choice, the ones being opened with one, and topic listings under way.
#[derive(Default)]
pub struct BagChooser {
    /// The forms and the bags being opened with their choice (see [`Choosing`]).
    forms: Choosing<BagForm>,
    /// A bag's topics being read for [`BagCommand::ChooseAgain`].
    listing: Option<(PathBuf, Job<Result<BagForm, String>>)>,
    /// What was entered by hand before switching to a setting file, restored when switching back.
    entered_keep: Option<EnteredBox>,
}

impl BagChooser {
    /// The form shown, if any.
    pub fn form(&self) -> Option<&BagForm> {
        self.forms.form()
    }

    /// Bags waiting behind the form shown.
    pub fn waiting(&self) -> usize {
        self.forms.waiting()
    }

    /// The bag whose topics are being read, if any.
    pub fn listing(&self) -> Option<&Path> {
        self.listing.as_ref().map(|(p, _)| p.as_path())
    }

    /// Bags being opened with a choice.
    pub fn opening(&self) -> impl Iterator<Item = &Path> {
        self.forms.opening()
    }

    /// The load was cancelled: the bags being opened go back to their forms, saying so.
    pub(in crate::app::state) fn loading_cancelled(&mut self) {
        self.forms.loading_cancelled();
    }
}

impl BagChooser {
    /// Applies a command to the form shown (the first waiting). What it asks of the rest of the app
    /// — a bag to open with its choice, a problem for the browser, a status line — comes back as
    /// effects.
    pub fn apply(&mut self, command: BagCommand) -> Vec<Effect> {
        if let BagCommand::ChooseAgain(bag) = command {
            return self.list_topics_of(bag).into_iter().collect();
        }
        let Some(form) = self.forms.form_mut() else {
            return Vec::new();
        };
        match command {
            BagCommand::SetPusher(spec) => form.pusher = Some(spec),
            BagCommand::SetObject(spec) => form.object = Some(spec),
            BagCommand::UseSettingFile(path) => {
                if let ObjectSource::Entered(b) = &form.object_source {
                    self.entered_keep = Some(b.clone());
                }
                form.object_source = file_source(path);
            }
            BagCommand::EnterObject => {
                if matches!(form.object_source, ObjectSource::File { .. }) {
                    let kept = (self.entered_keep.take())
                        .unwrap_or_else(|| EnteredBox::blank(String::new()));
                    form.object_source = ObjectSource::Entered(kept);
                }
            }
            BagCommand::SetEntered(entered) => {
                if matches!(form.object_source, ObjectSource::Entered(_)) {
                    form.object_source = ObjectSource::Entered(entered);
                }
            }
            BagCommand::SetOptions(options) => form.options = options,
            BagCommand::SetCamera { topic, shown } => {
                form.cameras.retain(|t| *t != topic);
                if shown {
                    form.cameras.push(topic);
                }
            }
            BagCommand::Open => match form.choice() {
                Ok(choice) => {
                    let Some(bag) = self.forms.open_shown(choice.clone()) else {
                        return Vec::new();
                    };
                    return vec![Effect::OpenBag {
                        bag,
                        choice: Box::new(choice),
                    }];
                }
                Err(why) => form.error = Some(why),
            },
            BagCommand::Skip => {
                let Some(bag) = self.forms.skip_shown() else {
                    return Vec::new();
                };
                return vec![Effect::Problem(LoadProblem {
                    message: format!(
                        "{}: not opened: its pusher and object topics were not chosen",
                        bag.display()
                    ),
                    path: bag,
                    bag_to_choose: true,
                    dataset_to_choose: false,
                })];
            }
            BagCommand::ChooseAgain(_) => {}
        }
        Vec::new()
    }

    /// Reads a bag's topics and remembered choice on a worker thread; the form opens when done.
    /// Says so instead while another bag's topics are being read.
    fn list_topics_of(&mut self, bag: PathBuf) -> Option<Effect> {
        if self.listing.is_some() {
            return Some(Effect::Status(
                "still reading another bag's topics".to_owned(),
            ));
        }
        let worker_bag = bag.clone();
        let job = Job::spawn(move |_| {
            let form = bag::topics(&worker_bag)
                .map_err(|e| e.to_string())
                .map(|listing| {
                    // A remembered file that cannot be read is not offered; the form starts afresh.
                    let remembered = choice::remembered(&worker_bag).ok().flatten();
                    BagForm::new(worker_bag, listing, remembered)
                });
            Some(form)
        });
        self.listing = Some((bag, job));
        None
    }

    /// Merges what loading and topic listing finished: forms for bags that need a choice (the
    /// session's list of them is taken), and for each bag opened with a choice, the choice
    /// remembered (it opened: the bag is shown) or its form back with the session's error for it.
    pub fn poll(&mut self, session: &mut Session) -> Vec<Effect> {
        let mut effects = Vec::new();
        if let Some((bag, listed)) = take_ended(&mut self.listing) {
            let listed = listed.unwrap_or_else(|| {
                Err(format!(
                    "{}: reading its topics stopped unexpectedly",
                    bag.display()
                ))
            });
            match listed {
                Ok(form) => {
                    (session.problems).retain(|p| !(p.bag_to_choose && p.path == form.bag));
                    self.forms.show(form);
                }
                Err(why) => effects.push(Effect::Status(why)),
            }
        }
        let asked = std::mem::take(&mut session.bags_to_choose);
        if !asked.is_empty() {
            effects.push(Effect::Status(format!(
                "{} ROS 2 bag(s) wait for their pusher and object topics to be chosen",
                asked.len()
            )));
        }
        for (bag, listing) in asked {
            self.forms.ask(BagForm::new(bag, listing, None));
        }
        effects.extend(self.forms.settle(session));
        effects
    }
}

#[cfg(test)]
mod tests;
