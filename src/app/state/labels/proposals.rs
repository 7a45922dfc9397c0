//! Label proposals in the app: what the core's `labels::propose` says about the selected recording,
//! shown beside the labels, for the user to accept or reject.
//!
//! Proposals are not labels. They live here, never in a labels file, until the user accepts one;
//! accepting paints its label through the labels document (`LabelAction::EditAll`), so that one
//! acceptance — one segment, the proposals at a frame, or every proposal of one label — is one undo
//! step, and undoing it makes the proposal show again.
//!
//! A user's labels win: accepting fills only the frames of the proposal that no label of its
//! exclusive group covers yet (for a label without a group, no segment of the label itself), so
//! "contact" proposed over frames the user called "no contact" leaves those frames alone. A proposal
//! whose frames are all labelled that way is no longer shown. Rejecting hides a proposal for the
//! session (by its label and frames, so a recomputation keeps it hidden); "restore rejected" shows
//! the rejected ones again, so nothing is lost.
//!
//! Proposing runs off the UI thread (a worker thread on the desktop, a slice of each frame in a
//! page: a million-frame recording takes seconds), with progress and cancel; opening on the calling thread ([`ProposalState::wait`]) waits for it.

use std::collections::{BTreeMap, BTreeSet};
use std::ops::Range;
use std::path::{Path, PathBuf};

use pushlab_core::labels::propose::{
    Proposal, Proposals, ProposeOptions, Residuals, propose_for_in_slices,
};
use pushlab_core::labels::{self, LabelSchema, RecordingLabels};
use pushlab_core::model::LossScale;
use pushlab_core::recording::Recording;

use crate::app::state::job::{Job, take_ended};
use crate::app::state::labels::labeling::{LabelAction, LabelTarget, Labeling};
use crate::app::state::learning::online::OnlineRun;

/// Fewer frames than this give no proposals (no noise to estimate, no window to measure drift in).
pub const MIN_FRAMES: usize = 5;

/// Everything the proposals band and keys can ask for, on the selected recording.
#[derive(Clone, Debug, PartialEq)]
pub enum ProposalAction {
    /// Accepts one proposal, by its index among the recording's proposals: one undo step.
    Accept(usize),
    /// Accepts every pending proposal covering the frame shown: one undo step.
    AcceptHere,
    /// Accepts every pending proposal of one label: one undo step.
    AcceptAll(String),
    /// Hides one proposal.
    Reject(usize),
    /// Hides every pending proposal covering the frame shown.
    RejectHere,
    /// Shows the recording's rejected proposals again.
    RestoreRejected,
}

/// A proposal waiting for a decision.
#[derive(Clone, Debug, PartialEq)]
pub struct Pending<'a> {
    /// Its index among the recording's proposals (what [`ProposalAction::Accept`] names).
    pub index: usize,
    pub proposal: &'a Proposal,
    /// The frames accepting it would label: its frames not yet labelled in its group.
    pub open: Vec<Range<usize>>,
}

/// What is known about the selected recording's proposals.
#[derive(Clone, Debug, PartialEq)]
pub enum Status<'a> {
    /// Nothing selected.
    None,
    /// Being computed; the fraction done.
    Running(f32),
    /// Why there are none (a short recording, an unusable outline).
    Failed(&'a str),
    Ready(&'a Proposals),
}

/// A proposal as rejected: its label and frames (indices change when proposals are recomputed).
type RejectKey = (String, usize, usize);

/// What a proposal job that ended without its result says (its thread panicked).
const WORKER_STOPPED: &str = "no proposals: the worker stopped unexpectedly";

fn key_of(proposal: &Proposal) -> RejectKey {
    (
        proposal.label.to_owned(),
        proposal.frames.start,
        proposal.frames.end,
    )
}

/// The selected recording's proposals and what the user rejected.
#[derive(Default)]
pub struct ProposalState {
    /// The recording proposed for (its source) and the outcome.
    current: Option<(PathBuf, Result<Proposals, String>)>,
    /// The recording being proposed for (its source) and the job.
    job: Option<(PathBuf, Job<Result<Proposals, String>>)>,
    /// Rejected proposals by recording source.
    rejected: BTreeMap<PathBuf, BTreeSet<RejectKey>>,
}

/// A model's fixed-run losses, owned, for the worker thread.
struct OwnedResiduals {
    losses: Vec<f64>,
    horizon: usize,
    scale: LossScale,
}

impl ProposalState {
    /// Starts proposing for `recording` on a worker thread (stopping any earlier job), with the
    /// residuals of a model's fixed run when there is one.
    fn start(&mut self, recording: &Recording, residuals: Option<OwnedResiduals>) {
        self.stop();
        let source = recording.source.clone();
        let frames = recording.trajectory.len();
        if frames < MIN_FRAMES {
            self.current = Some((
                source,
                Err(format!(
                    "no proposals: {frames} frames are too few (at least {MIN_FRAMES})"
                )),
            ));
            return;
        }
        self.current = None;
        let recording = recording.clone();
        let job = Job::spawn_in_slices(move |context| async move {
            let residuals = residuals.as_ref().map(|r| Residuals {
                losses: &r.losses,
                horizon: r.horizon,
                scale: r.scale,
            });
            let result = propose_for_in_slices(
                &recording,
                residuals,
                &ProposeOptions::default(),
                &mut |done| {
                    context.set_progress(done);
                    !context.is_cancelled()
                },
            )
            .await
            .map_err(|e| format!("no proposals: {e}"));
            Some(result)
        });
        self.job = Some((source, job));
    }

    /// Stops the job in progress, if any; its result is dropped.
    pub fn stop(&mut self) {
        // Dropping the job cancels it.
        self.job = None;
    }

    /// Takes a finished job's result. Returns whether proposals arrived.
    pub fn poll(&mut self) -> bool {
        let Some((source, result)) = take_ended(&mut self.job) else {
            return false;
        };
        self.current = Some((source, result.unwrap_or(Err(WORKER_STOPPED.to_owned()))));
        true
    }

    /// Waits for the job in progress (opening on the calling thread: the command line, tests).
    pub fn wait(&mut self) {
        if let Some((source, job)) = self.job.take() {
            let result = job.wait().unwrap_or(Err(WORKER_STOPPED.to_owned()));
            self.current = Some((source, result));
        }
    }

    /// Whether proposing is going on.
    pub fn is_running(&self) -> bool {
        self.job.is_some()
    }

    /// What is known about the proposals of the recording at `source`.
    pub fn status(&self, source: &Path) -> Status<'_> {
        if let Some((_, job)) = self.job.as_ref().filter(|(s, _)| s == source) {
            return Status::Running(job.progress());
        }
        match &self.current {
            Some((s, Ok(proposals))) if s == source => Status::Ready(proposals),
            Some((s, Err(message))) if s == source => Status::Failed(message),
            _ => Status::None,
        }
    }

    /// The proposals of the recording at `source`, when ready.
    pub fn of(&self, source: &Path) -> Option<&Proposals> {
        match self.status(source) {
            Status::Ready(proposals) => Some(proposals),
            _ => None,
        }
    }

    /// The proposals of the recording at `source` still waiting for a decision: not rejected, and
    /// with frames left that its group has no label on in `labels`.
    pub fn pending(
        &self,
        source: &Path,
        labels: Option<&RecordingLabels>,
        schema: &LabelSchema,
    ) -> Vec<Pending<'_>> {
        let Some(proposals) = self.of(source) else {
            return Vec::new();
        };
        let rejected = self.rejected.get(source);
        proposals
            .segments
            .iter()
            .enumerate()
            .filter(|(_, p)| !rejected.is_some_and(|r| r.contains(&key_of(p))))
            .filter_map(|(index, proposal)| {
                let open = open_frames(proposal, labels, schema);
                (!open.is_empty()).then_some(Pending {
                    index,
                    proposal,
                    open,
                })
            })
            .collect()
    }

    /// Whether `proposal` of the recording at `source` was rejected.
    pub fn is_rejected(&self, source: &Path, proposal: &Proposal) -> bool {
        self.rejected
            .get(source)
            .is_some_and(|r| r.contains(&key_of(proposal)))
    }

    /// How many proposals of the recording at `source` were rejected.
    pub fn rejected_count(&self, source: &Path) -> usize {
        self.rejected.get(source).map_or(0, BTreeSet::len)
    }
}

/// The frames of `proposal` that accepting it would label: those where no segment of its exclusive
/// group (for a label without a group, of the label itself) is in `labels`.
pub fn open_frames(
    proposal: &Proposal,
    labels: Option<&RecordingLabels>,
    schema: &LabelSchema,
) -> Vec<Range<usize>> {
    let group = schema.group_of(proposal.label);
    let mut taken: Vec<Range<usize>> = labels
        .map(|l| {
            l.segments_in(proposal.frames.clone())
                .filter(|s| {
                    s.label == proposal.label
                        || group.is_some() && schema.group_of(&s.label) == group
                })
                .map(|s| s.start..s.end)
                .collect()
        })
        .unwrap_or_default();
    taken.sort_by_key(|r| r.start);
    let mut open = Vec::new();
    let mut from = proposal.frames.start;
    for range in taken {
        if range.start > from {
            open.push(from..range.start.min(proposal.frames.end));
        }
        from = from.max(range.end);
    }
    if from < proposal.frames.end {
        open.push(from..proposal.frames.end);
    }
    open
}

/// "frames 3–17" (both included), "frames 3–17 and 20–24", "frames 3–17, 20–24 and 2 more".
fn frames_text(ranges: &[Range<usize>]) -> String {
    let text = |r: &Range<usize>| format!("{}–{}", r.start, r.end.saturating_sub(1));
    match ranges {
        [] => "no frames".to_owned(),
        [one] => format!("frames {}", text(one)),
        [a, b] => format!("frames {} and {}", text(a), text(b)),
        [a, b, rest @ ..] => format!("frames {}, {} and {} more", text(a), text(b), rest.len()),
    }
}

/// Where a proposals action applies: the recording shown (its file and labels) at the frame shown.
#[derive(Clone, Copy)]
pub struct ProposalTarget<'a> {
    pub source: &'a Path,
    pub target: &'a LabelTarget,
    pub labels: &'a Labeling,
    pub frame: usize,
}

impl ProposalState {
    /// Proposes labels for the recording shown again (it was selected, or the model whose
    /// residuals mark bad tracking changed); stops proposing when nothing is shown.
    pub fn refresh(&mut self, recording: Option<&Recording>, run: Option<&OnlineRun>) {
        let Some(recording) = recording else {
            self.stop();
            return;
        };
        let residuals = run.map(|run| OwnedResiduals {
            losses: run.fixed().iter().map(|l| l.total()).collect(),
            horizon: run.horizon(),
            scale: run.model().loss_scale(),
        });
        self.start(recording, residuals);
    }

    /// The pending proposals of the recording at `source` against its labels in `labels` (the
    /// default schema while its labels file is unreadable).
    pub fn pending_in(
        &self,
        source: &Path,
        target: &LabelTarget,
        labels: &Labeling,
    ) -> Vec<Pending<'_>> {
        let default_schema;
        let schema = match labels.schema_of(target) {
            Some(schema) => schema,
            None => {
                default_schema = LabelSchema::default();
                &default_schema
            }
        };
        self.pending(source, labels.labels_of(target), schema)
    }

    /// Applies a proposals action: rejecting and restoring here, accepting as one labels edit
    /// returned for the state to carry out (with what the status line says).
    pub fn apply(&mut self, action: ProposalAction, on: ProposalTarget<'_>) -> Asked {
        let frame = on.frame;
        let chosen: Vec<(Proposal, Vec<Range<usize>>)> = {
            let pending = self.pending_in(on.source, on.target, on.labels);
            let picked: Vec<&Pending<'_>> = match &action {
                ProposalAction::Accept(i) | ProposalAction::Reject(i) => {
                    pending.iter().filter(|p| p.index == *i).collect()
                }
                ProposalAction::AcceptHere | ProposalAction::RejectHere => pending
                    .iter()
                    .filter(|p| p.proposal.frames.contains(&frame))
                    .collect(),
                ProposalAction::AcceptAll(label) => pending
                    .iter()
                    .filter(|p| p.proposal.label == label)
                    .collect(),
                ProposalAction::RestoreRejected => Vec::new(),
            };
            (picked.into_iter())
                .map(|p| (p.proposal.clone(), p.open.clone()))
                .collect()
        };
        let status = |status: String| Asked { status, edit: None };
        match action {
            ProposalAction::RestoreRejected => {
                let n = (self.rejected.remove(on.source)).map_or(0, |r| r.len());
                status(match n {
                    0 => "no rejected proposals to restore".to_owned(),
                    1 => "1 rejected proposal shown again".to_owned(),
                    n => format!("{n} rejected proposals shown again"),
                })
            }
            ProposalAction::Reject(_) | ProposalAction::RejectHere => {
                if chosen.is_empty() {
                    return status(format!("no proposal to reject at frame {frame}"));
                }
                let rejected = self.rejected.entry(on.source.to_path_buf()).or_default();
                let mut what = Vec::new();
                for (proposal, _) in &chosen {
                    rejected.insert(key_of(proposal));
                    what.push(format!(
                        "{} ({})",
                        proposal.label,
                        frames_text(std::slice::from_ref(&proposal.frames))
                    ));
                }
                status(format!(
                    "rejected the proposed {}; the Proposals menu restores rejected proposals",
                    what.join(", ")
                ))
            }
            ProposalAction::Accept(_)
            | ProposalAction::AcceptHere
            | ProposalAction::AcceptAll(_) => {
                if chosen.is_empty() {
                    return status(match action {
                        ProposalAction::AcceptAll(label) => {
                            format!("no pending proposal of {label:?} to accept")
                        }
                        _ => format!("no proposal to accept at frame {frame}"),
                    });
                }
                let recording = &on.target.recording;
                let mut commands = Vec::new();
                let mut what = Vec::new();
                for (proposal, open) in &chosen {
                    for frames in open {
                        commands.push(labels::Command::Paint {
                            recording: recording.clone(),
                            label: proposal.label.to_owned(),
                            frames: frames.clone(),
                        });
                    }
                    what.push(format!("{} on {}", proposal.label, frames_text(open)));
                }
                let description = match &action {
                    ProposalAction::AcceptAll(label) => format!(
                        "accept {} proposed {label:?} segments on {recording}",
                        chosen.len(),
                    ),
                    _ => format!("accept proposed {} on {recording}", what.join(", ")),
                };
                Asked {
                    status: format!("{description} (Ctrl+Z undoes)"),
                    edit: Some(LabelAction::EditAll {
                        description,
                        commands,
                    }),
                }
            }
        }
    }
}

/// What a proposals action asks of the rest of the app: a line for the status bar and, when proposals
/// were accepted, the one labels edit that paints them. The state carries it out as its effects
/// (`Effect::asked_by_proposals`): proposals are below the effects, which name the labels' edits.
#[derive(Debug)]
pub struct Asked {
    pub status: String,
    pub edit: Option<LabelAction>,
}

#[cfg(test)]
mod tests;
