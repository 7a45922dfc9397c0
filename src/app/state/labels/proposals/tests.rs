//! The proposals' rules: accepting is one undo step and never paints over a user's labels,
//! rejecting hides and restoring shows again, odd recordings give a reason instead of a panic.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use pushlab_core::labels::schema::names::{BAD_TRACKING, CONTACT, NO_CONTACT, STICKING};
use pushlab_core::labels::{LABELS_FILE_NAME, Segment};

use super::*;
use crate::app::state::labels::labeling::LabelAction;
use crate::app::state::models::Models;
use crate::app::state::playback::timeline::TimelineCommand;
use crate::app::state::{AppState, Command, Persisted};

/// A private copy of one sample-data set, each CSV cut to `rows` frames when given.
fn copy_of_sample_set(test: &str, rows: Option<usize>) -> PathBuf {
    let source = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("sample-data")
        .join("box1-paper-center-front");
    assert!(source.is_dir(), "{} is missing", source.display());
    let dir = std::env::temp_dir().join(format!("pushlab-proposals-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for entry in std::fs::read_dir(&source).unwrap() {
        let entry = entry.unwrap();
        let to = dir.join(entry.file_name());
        let is_csv = entry.path().extension().is_some_and(|e| e == "csv");
        match rows {
            Some(rows) if is_csv => {
                let text = std::fs::read_to_string(entry.path()).unwrap();
                let cut: Vec<&str> = text.lines().take(rows + 1).collect();
                std::fs::write(&to, cut.join("\n") + "\n").unwrap();
            }
            _ => {
                std::fs::copy(entry.path(), &to).unwrap();
            }
        }
    }
    dir
}

fn state_on(dir: &Path) -> AppState {
    let mut state = AppState::new(Persisted::default(), Models::default());
    state.open_blocking(&[dir.to_path_buf()]);
    assert!(state.recording().is_some(), "{:?}", state.session.problems);
    state
}

fn labels(state: &AppState) -> Vec<Segment> {
    let target = state.label_target().unwrap();
    state
        .labels
        .labels_of(&target)
        .map(|l| l.segments.clone())
        .unwrap_or_default()
}

/// The first pending proposal of `label`: (index, frames).
fn first_pending(state: &AppState, label: &str) -> (usize, Range<usize>) {
    state
        .pending_proposals()
        .iter()
        .find(|p| p.proposal.label == label)
        .map(|p| (p.index, p.proposal.frames.clone()))
        .unwrap_or_else(|| panic!("no pending {label:?} proposal"))
}

fn has_label_at(state: &AppState, label: &str, frame: usize) -> bool {
    labels(state)
        .iter()
        .any(|s| s.label == label && s.contains(frame))
}

#[test]
fn proposals_are_ready_after_opening_and_are_not_labels() {
    let dir = copy_of_sample_set("ready", None);
    let before = std::fs::read(dir.join(LABELS_FILE_NAME)).unwrap();
    let state = state_on(&dir);
    let source = state.recording().unwrap().source.clone();
    assert!(matches!(state.proposals.status(&source), Status::Ready(_)));
    let pending = state.pending_proposals();
    assert!(
        pending.iter().any(|p| p.proposal.label == CONTACT),
        "{pending:?}"
    );
    assert!(labels(&state).is_empty(), "proposals are not labels");
    assert!(!state.labels.any_unsaved());
    assert_eq!(std::fs::read(dir.join(LABELS_FILE_NAME)).unwrap(), before);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn accepting_a_segment_labels_its_frames_in_one_undo_step_and_undo_shows_it_again() {
    let dir = copy_of_sample_set("accept", None);
    let mut state = state_on(&dir);
    let (index, frames) = first_pending(&state, CONTACT);
    state.apply(Command::Proposal(ProposalAction::Accept(index)));
    assert_eq!(
        labels(&state),
        vec![Segment::new(CONTACT, frames.clone())],
        "{:?}",
        state.status
    );
    assert!(state.labels.any_unsaved());
    assert!(state.pending_proposals().iter().all(|p| p.index != index));

    state.apply(Command::Label(LabelAction::Undo));
    assert!(labels(&state).is_empty(), "one undo removes the acceptance");
    assert!(
        state
            .status
            .as_deref()
            .unwrap()
            .starts_with("undid: accept proposed contact")
    );
    assert_eq!(first_pending(&state, CONTACT), (index, frames));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn accepting_fills_only_frames_the_labels_group_leaves_empty() {
    let dir = copy_of_sample_set("overlap", None);
    let mut state = state_on(&dir);
    let (index, frames) = first_pending(&state, CONTACT);
    assert!(frames.len() > 10, "{frames:?}");
    // The user calls a few frames in the middle "no contact", and one "sticking" (another group).
    let middle = frames.start + 4..frames.start + 7;
    let target = state.label_target().unwrap();
    for (label, range) in [
        (NO_CONTACT, middle.clone()),
        (STICKING, frames.start..frames.start + 2),
    ] {
        state.apply(Command::Label(LabelAction::Edit(labels::Command::Paint {
            recording: target.recording.clone(),
            label: label.into(),
            frames: range,
        })));
    }
    state.apply(Command::Proposal(ProposalAction::Accept(index)));
    for frame in frames.clone() {
        let expected = if middle.contains(&frame) {
            NO_CONTACT
        } else {
            CONTACT
        };
        assert!(has_label_at(&state, expected, frame), "frame {frame}");
    }
    assert!(
        has_label_at(&state, STICKING, frames.start),
        "another group is kept"
    );
    assert!(
        state.status.as_deref().unwrap().contains(" and "),
        "{:?}",
        state.status
    );

    // A proposal whose frames are all labelled in its group is no longer pending.
    state.apply(Command::Label(LabelAction::Undo));
    state.apply(Command::Label(LabelAction::Edit(labels::Command::Paint {
        recording: target.recording.clone(),
        label: NO_CONTACT.into(),
        frames: frames.clone(),
    })));
    assert!(state.pending_proposals().iter().all(|p| p.index != index));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn accept_all_of_a_label_is_one_undo_step_and_accept_here_takes_every_proposal_at_the_frame() {
    let dir = copy_of_sample_set("accept-all", None);
    let mut state = state_on(&dir);
    let contact = |s: &AppState| {
        s.pending_proposals()
            .iter()
            .filter(|p| p.proposal.label == CONTACT)
            .count()
    };
    assert!(contact(&state) > 0);
    state.apply(Command::Proposal(ProposalAction::AcceptAll(CONTACT.into())));
    assert_eq!(contact(&state), 0);
    assert!(labels(&state).iter().all(|s| s.label == CONTACT));
    state.apply(Command::Label(LabelAction::Undo));
    assert!(labels(&state).is_empty());
    assert!(contact(&state) > 0);

    let (_, frames) = first_pending(&state, STICKING);
    state.apply(Command::Timeline(TimelineCommand::SeekTo(frames.start)));
    let here = |s: &AppState| {
        let frame = s.frame();
        s.pending_proposals()
            .iter()
            .filter(|p| p.proposal.frames.contains(&frame))
            .count()
    };
    assert!(
        here(&state) >= 2,
        "contact and sticking at {}",
        frames.start
    );
    state.apply(Command::Proposal(ProposalAction::AcceptHere));
    assert_eq!(here(&state), 0);
    assert!(has_label_at(&state, STICKING, frames.start));
    assert!(has_label_at(&state, CONTACT, frames.start));
    state.apply(Command::Label(LabelAction::Undo));
    assert!(labels(&state).is_empty(), "accept here is one undo step");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn rejecting_hides_a_proposal_and_restoring_shows_it_again() {
    let dir = copy_of_sample_set("reject", None);
    let mut state = state_on(&dir);
    let count = state.pending_proposals().len();
    let (index, frames) = first_pending(&state, CONTACT);
    state.apply(Command::Proposal(ProposalAction::Reject(index)));
    assert_eq!(state.pending_proposals().len(), count - 1);
    assert!(state.pending_proposals().iter().all(|p| p.index != index));
    assert!(labels(&state).is_empty(), "rejecting writes no labels");
    assert!(!state.labels.any_unsaved());

    // Rejections survive a recomputation (another model's residuals) and another selection.
    state.restart_run_keeping_frame();
    state.proposals.wait();
    assert_eq!(state.pending_proposals().len(), count - 1);

    state.apply(Command::Timeline(TimelineCommand::SeekTo(frames.start)));
    state.apply(Command::Proposal(ProposalAction::RejectHere));
    assert!(state.pending_proposals().len() < count - 1);
    state.apply(Command::Proposal(ProposalAction::RestoreRejected));
    assert_eq!(state.pending_proposals().len(), count);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_recording_too_short_to_propose_for_gives_a_reason_and_odd_lengths_do_not_panic() {
    // Loading refuses fewer than 2 frames.
    for rows in [2, MIN_FRAMES - 1] {
        let dir = copy_of_sample_set(&format!("short-{rows}"), Some(rows));
        let state = state_on(&dir);
        let source = state.recording().unwrap().source.clone();
        match state.proposals.status(&source) {
            Status::Failed(reason) => assert!(reason.contains("too few"), "{reason}"),
            other => panic!("{rows} frames: {other:?}"),
        }
        assert!(state.pending_proposals().is_empty());
        let _ = std::fs::remove_dir_all(&dir);
    }
    for rows in [MIN_FRAMES, MIN_FRAMES + 1, 8] {
        let dir = copy_of_sample_set(&format!("few-{rows}"), Some(rows));
        let mut state = state_on(&dir);
        let source = state.recording().unwrap().source.clone();
        assert!(
            !matches!(
                state.proposals.status(&source),
                Status::Running(_) | Status::None
            ),
            "{rows} frames"
        );
        state.apply(Command::Proposal(ProposalAction::AcceptHere));
        let _ = std::fs::remove_dir_all(&dir);
    }
}

#[test]
fn open_frames_leave_out_the_labels_group_and_for_ungrouped_labels_the_label_itself() {
    let schema = LabelSchema::default();
    let proposal = |label: &'static str| Proposal {
        label,
        frames: 0..10,
        confidence: 0.9,
    };
    let labels = RecordingLabels {
        segments: vec![
            Segment::new(BAD_TRACKING, 1..2),
            Segment::new(NO_CONTACT, 3..5),
            Segment::new(STICKING, 6..8),
            Segment::new(CONTACT, 9..12),
        ],
        ..RecordingLabels::default()
    };
    assert_eq!(
        open_frames(&proposal(CONTACT), Some(&labels), &schema),
        vec![0..3, 5..9]
    );
    assert_eq!(
        open_frames(&proposal(BAD_TRACKING), Some(&labels), &schema),
        vec![0..1, 2..10]
    );
    assert_eq!(open_frames(&proposal(STICKING), None, &schema), vec![0..10]);
    assert_eq!(frames_text(&[0..3, 5..9]), "frames 0–2 and 5–8");
}
