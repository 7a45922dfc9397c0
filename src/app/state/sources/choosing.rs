//! What opening a ROS 2 bag and opening a Push-T dataset share: the forms waiting for the user's
//! choice, shown one at a time, and the sources being opened with a choice not yet remembered.
//!
//! The invariant of both: a choice is remembered beside its source only after the source opened
//! with it, so what is remembered always worked once; a choice that fails comes back to its form
//! with the session's error, and the source's earlier file (if any) is left as it was. Kept here
//! once so that the two cannot drift; what differs (the form, the listing, the words) stays in
//! `bag_import` and `dataset_import`.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};

use crate::app::state::effect::Effect;
use crate::app::state::recordings::session::{LoadProblem, RecordingId, Session};

/// A form that chooses how to open one source (a bag, a dataset).
pub trait ChoiceForm {
    /// What the form makes, remembered beside the source once it opened.
    type Choice: Clone;
    /// What is chosen, as the status line says it: "topics", "features".
    const CHOSEN: &'static str;
    /// The source the form chooses for.
    fn source(&self) -> &Path;
    /// Why the last attempt to open the source with this form failed.
    fn set_error(&mut self, error: Option<String>);
    /// Whether a load problem is this source's (a bag's may name a file inside its folder).
    fn is_problem_of(problem: &LoadProblem, source: &Path) -> bool;
    /// Writes the choice beside the source; returns the file written.
    fn remember(source: &Path, choice: &Self::Choice) -> std::io::Result<PathBuf>;
}

/// Forms waiting for a choice (the shown one first) and the sources being opened with one.
pub struct Choosing<F: ChoiceForm> {
    queue: VecDeque<F>,
    trying: Vec<(F, F::Choice)>,
}

impl<F: ChoiceForm> Default for Choosing<F> {
    fn default() -> Self {
        Self {
            queue: VecDeque::new(),
            trying: Vec::new(),
        }
    }
}

impl<F: ChoiceForm> Choosing<F> {
    /// The form shown, if any.
    pub fn form(&self) -> Option<&F> {
        self.queue.front()
    }

    /// The form shown, to edit.
    pub fn form_mut(&mut self) -> Option<&mut F> {
        self.queue.front_mut()
    }

    /// Forms waiting behind the one shown.
    pub fn waiting(&self) -> usize {
        self.queue.len().saturating_sub(1)
    }

    /// Sources being opened with a choice.
    pub fn opening(&self) -> impl Iterator<Item = &Path> {
        self.trying.iter().map(|(f, _)| f.source())
    }

    /// Shows `form` now, in place of any form for the same source.
    pub fn show(&mut self, form: F) {
        self.queue.retain(|f| f.source() != form.source());
        self.queue.push_front(form);
    }

    /// Queues `form` behind the others, in place of any form for the same source.
    pub fn ask(&mut self, form: F) {
        self.queue.retain(|f| f.source() != form.source());
        self.queue.push_back(form);
    }

    /// The shown form's source is being opened with `choice`: the form waits, out of the queue,
    /// until [`Choosing::settle`] sees how it went. Returns the source.
    pub fn open_shown(&mut self, choice: F::Choice) -> Option<PathBuf> {
        let mut form = self.queue.pop_front()?;
        let source = form.source().to_path_buf();
        form.set_error(None);
        self.trying.retain(|(f, _)| f.source() != source);
        self.trying.push((form, choice));
        Some(source)
    }

    /// Drops the shown form (the user skipped its source); returns the source.
    pub fn skip_shown(&mut self) -> Option<PathBuf> {
        self.queue.pop_front().map(|f| f.source().to_path_buf())
    }

    /// The load was cancelled: the sources being opened go back to their forms, saying so.
    pub fn loading_cancelled(&mut self) {
        for (mut form, _) in std::mem::take(&mut self.trying) {
            form.set_error(Some("opening was cancelled".to_owned()));
            self.queue.push_front(form);
        }
    }

    /// Once no load is running: each source opened with a choice is shown and its choice
    /// remembered, or its form comes back with the session's error for it (taken from the
    /// session's problems).
    pub fn settle(&mut self, session: &mut Session) -> Vec<Effect> {
        let mut effects = Vec::new();
        if session.loading().is_some() {
            return effects;
        }
        let chosen = F::CHOSEN;
        for (mut form, choice) in std::mem::take(&mut self.trying) {
            let source = form.source().to_path_buf();
            let failed = session
                .problems
                .iter()
                .any(|p| F::is_problem_of(p, &source));
            let opened = session.sets.iter().position(|s| s.dir == source);
            if let (false, Some(set)) = (failed, opened) {
                // The user just chose this source: show it.
                effects.push(Effect::Select(RecordingId { set, recording: 0 }));
                effects.push(Effect::Status(match F::remember(&source, &choice) {
                    Ok(file) => format!(
                        "opened {}; its {chosen} are remembered in {}",
                        source.display(),
                        file.display()
                    ),
                    Err(e) => format!(
                        "opened {}, but its {chosen} could not be remembered beside it ({e}); \
                         they will be asked again",
                        source.display()
                    ),
                }));
                continue;
            }
            let error = (session.problems.iter())
                .position(|p| F::is_problem_of(p, &source))
                .map(|i| session.problems.remove(i).message);
            form.set_error(error.or(Some(format!("{} did not open", source.display()))));
            self.queue.push_front(form);
        }
        effects
    }
}
