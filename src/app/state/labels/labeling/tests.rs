//! The labeling state's rules, on private copies of a sample set.

#![allow(clippy::unwrap_used)]

use std::path::PathBuf;

use pushlab_core::labels::{LABELS_FILE_NAME, Split};

use super::*;
use crate::app::state::models::Models;
use crate::app::state::playback::timeline::TimelineCommand;
use crate::app::state::{AppState, Command};
use crate::app::state::{OnlineCommand, TrainingCommand};

/// A private copy of one sample-data set, so tests never write into the repository.
/// `sample-data/` is committed: a missing set is a broken checkout, so the test fails.
pub(in crate::app::state) fn copy_of_sample_set(test: &str) -> PathBuf {
    let source = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("sample-data")
        .join("box1-paper-center-front");
    assert!(
        source.is_dir(),
        "{} is missing: sample-data/ is part of the repository",
        source.display()
    );
    let dir = std::env::temp_dir().join(format!("pushlab-labels-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for entry in std::fs::read_dir(&source).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(entry.path(), dir.join(entry.file_name())).unwrap();
    }
    dir
}

fn state_on(dir: &std::path::Path) -> AppState {
    let mut state = AppState::new(Default::default(), Models::default());
    state.open_blocking(&[dir.to_path_buf()]);
    assert!(state.recording().is_some(), "{:?}", state.session.problems);
    state
}

fn label(state: &mut AppState, action: LabelAction) {
    state.apply(Command::Label(action));
}

fn seek(state: &mut AppState, frame: usize) {
    state.apply(Command::Timeline(TimelineCommand::SeekTo(frame)));
}

/// Paints `label` over `first..=last` with the in and out points, as a user would.
pub(in crate::app::state) fn paint_frames(
    state: &mut AppState,
    label_name: &str,
    first: usize,
    last: usize,
) {
    seek(state, first);
    label(state, LabelAction::SetInPoint);
    seek(state, last);
    label(state, LabelAction::SetActive(label_name.into()));
    label(state, LabelAction::PaintFromInPoint);
}

/// Forgets what was learned and steps over the first `frames` frames with "Learn while
/// playing" on (the default), so that each of them is learned from.
fn learn_from_start(state: &mut AppState, frames: usize) {
    seek(state, 0);
    state.apply(Command::Online(OnlineCommand::ResetTheta));
    for _ in 0..frames {
        state.apply(Command::Timeline(TimelineCommand::Step(1)));
    }
}

fn segments(state: &AppState) -> Vec<(String, std::ops::Range<usize>)> {
    let target = state.label_target().unwrap();
    state
        .labels
        .labels_of(&target)
        .map(|l| {
            l.segments
                .iter()
                .map(|s| (s.label.clone(), s.frames()))
                .collect()
        })
        .unwrap_or_default()
}

#[test]
fn a_held_hotkey_paints_every_frame_passed_as_one_undo_step() {
    let dir = copy_of_sample_set("stroke");
    let mut state = state_on(&dir);
    seek(&mut state, 5);
    label(&mut state, LabelAction::Hotkey("contact".into()));
    for _ in 0..3 {
        state.apply(Command::Timeline(TimelineCommand::Step(1)));
    }
    // Stepping back inside the stroke keeps what was painted.
    state.apply(Command::Timeline(TimelineCommand::Step(-1)));
    label(&mut state, LabelAction::EndStroke);
    assert_eq!(segments(&state), vec![("contact".to_owned(), 5..9)]);
    assert_eq!(state.labels.active.as_deref(), Some("contact"));
    label(&mut state, LabelAction::Undo);
    assert_eq!(segments(&state), vec![]);
    assert!(
        state
            .status
            .as_deref()
            .unwrap()
            .contains("paint \"contact\"")
    );
    label(&mut state, LabelAction::Redo);
    assert_eq!(segments(&state), vec![("contact".to_owned(), 5..9)]);
}

#[test]
fn painting_an_exclusive_label_cuts_the_other_and_erase_clears_frames() {
    let dir = copy_of_sample_set("exclusive");
    let mut state = state_on(&dir);
    seek(&mut state, 10);
    label(&mut state, LabelAction::SetInPoint);
    seek(&mut state, 19);
    label(&mut state, LabelAction::SetActive("sticking".into()));
    label(&mut state, LabelAction::PaintFromInPoint);
    assert_eq!(segments(&state), vec![("sticking".to_owned(), 10..20)]);
    assert_eq!(state.labels.in_point, None);
    // Slipping over 15..=16 splits sticking in two.
    seek(&mut state, 15);
    label(&mut state, LabelAction::Hotkey("slipping".into()));
    seek(&mut state, 16);
    label(&mut state, LabelAction::EndStroke);
    assert_eq!(
        segments(&state),
        vec![
            ("sticking".to_owned(), 10..15),
            ("slipping".to_owned(), 15..17),
            ("sticking".to_owned(), 17..20)
        ]
    );
    // Delete held from 12 back to 11 erases both frames of every label.
    seek(&mut state, 12);
    label(&mut state, LabelAction::StartErase);
    state.apply(Command::Timeline(TimelineCommand::Step(-1)));
    label(&mut state, LabelAction::EndStroke);
    assert_eq!(
        segments(&state),
        vec![
            ("sticking".to_owned(), 10..11),
            ("sticking".to_owned(), 13..15),
            ("slipping".to_owned(), 15..17),
            ("sticking".to_owned(), 17..20)
        ]
    );
}

#[test]
fn out_point_without_in_point_or_label_says_what_is_missing() {
    let dir = copy_of_sample_set("inout");
    let mut state = state_on(&dir);
    label(&mut state, LabelAction::PaintFromInPoint);
    assert!(state.status.as_deref().unwrap().contains("range label"));
    label(&mut state, LabelAction::SetActive("contact".into()));
    label(&mut state, LabelAction::PaintFromInPoint);
    assert!(state.status.as_deref().unwrap().contains("in point"));
    assert_eq!(segments(&state), vec![]);
}

#[test]
fn an_event_hotkey_toggles_its_event_and_label_keys_jump_between_boundaries() {
    let dir = copy_of_sample_set("events");
    let mut state = state_on(&dir);
    seek(&mut state, 7);
    label(&mut state, LabelAction::Hotkey("contact made".into()));
    let target = state.label_target().unwrap();
    let events = |s: &AppState| {
        s.labels
            .labels_of(&target)
            .map(|l| l.events.iter().map(|e| e.frame).collect::<Vec<_>>())
            .unwrap_or_default()
    };
    assert_eq!(events(&state), vec![7]);
    paint_frames(&mut state, "contact", 20, 30);
    seek(&mut state, 0);
    let mut visited = Vec::new();
    for _ in 0..4 {
        state.apply(Command::JumpToLabel { forward: true });
        visited.push(state.frame());
    }
    assert_eq!(visited, vec![7, 20, 30, 30]);
    assert!(
        state
            .status
            .as_deref()
            .unwrap()
            .contains("no label after frame 30")
    );
    state.apply(Command::JumpToLabel { forward: false });
    assert_eq!(state.frame(), 20);
    seek(&mut state, 7);
    label(&mut state, LabelAction::Hotkey("contact made".into()));
    assert_eq!(events(&state), Vec::<usize>::new());
}

#[test]
fn autosave_writes_the_file_after_a_quiet_half_second() {
    let dir = copy_of_sample_set("autosave");
    let file = dir.join(LABELS_FILE_NAME);
    let before = std::fs::read_to_string(&file).unwrap();
    let mut state = state_on(&dir);
    let target = state.label_target().unwrap();
    label(&mut state, LabelAction::Hotkey("bad tracking".into()));
    label(&mut state, LabelAction::EndStroke);
    assert_eq!(state.labels.save_state(&target), Some(SaveState::Unsaved));
    state.autosave_labels(10.0);
    assert_eq!(
        std::fs::read_to_string(&file).unwrap(),
        before,
        "saved too early"
    );
    state.autosave_labels(10.6);
    assert_eq!(state.labels.save_state(&target), Some(SaveState::Saved));
    let saved = pushlab_core::labels::file::read(&file).unwrap();
    let labels = saved.recording(&target.recording).unwrap();
    assert_eq!(labels.segments.len(), 1);
    assert_eq!(labels.segments[0].label, "bad tracking");
    // What was there before is kept.
    assert_eq!(saved.split_of(&target.recording), Some(Split::Offline));
}

#[test]
fn an_unreadable_labels_file_is_never_overwritten() {
    let dir = copy_of_sample_set("unreadable");
    let file = dir.join(LABELS_FILE_NAME);
    std::fs::write(&file, "{ \"format\": \"pushlab-labels\", \"version\": 1, ").unwrap();
    let mut state = state_on(&dir);
    let target = state.label_target().unwrap();
    let reason = state.labels.read_only_reason(&target).unwrap().to_owned();
    assert!(reason.contains(LABELS_FILE_NAME), "{reason}");
    label(&mut state, LabelAction::Hotkey("contact".into()));
    assert!(state.status.as_deref().unwrap().contains("read-only"));
    label(&mut state, LabelAction::SaveAll);
    state.autosave_labels(100.0);
    assert_eq!(
        std::fs::read_to_string(&file).unwrap(),
        "{ \"format\": \"pushlab-labels\", \"version\": 1, "
    );
    // Fixed on disk and opened again: labeling works.
    std::fs::remove_file(&file).unwrap();
    state.open_blocking(std::slice::from_ref(&dir));
    assert_eq!(state.labels.read_only_reason(&target), None);
    label(&mut state, LabelAction::Hotkey("contact".into()));
    label(&mut state, LabelAction::EndStroke);
    assert_eq!(segments(&state).len(), 1);
}

#[test]
fn training_chooses_the_offline_split_and_leaves_out_bad_tracking() {
    let dir = copy_of_sample_set("training");
    let mut state = state_on(&dir);
    state.apply(Command::Training(TrainingCommand::ChooseOfflineLabelled));
    let chosen: Vec<String> = state
        .training
        .chosen
        .iter()
        .map(|&id| state.session.get(id).unwrap().name.clone())
        .collect();
    assert_eq!(chosen.len(), 27, "{chosen:?}");
    assert!(chosen.iter().all(|n| n.starts_with("offline_")));
    assert!(state.status.as_deref().unwrap().contains("27"));
    // Relabel the first offline push as held out: it leaves the choice.
    let target = state.label_target().unwrap();
    label(
        &mut state,
        LabelAction::Edit(pushlab_core::labels::Command::SetMeta {
            recording: target.recording.clone(),
            field: pushlab_core::labels::MetaField::Split(Some(Split::HeldOut)),
        }),
    );
    state.apply(Command::Training(TrainingCommand::ChooseOfflineLabelled));
    assert_eq!(state.training.chosen.len(), 26);

    // Bad tracking over frames 10..=14 of the selected push removes every sample touching them.
    let selected = state.session.selected.unwrap();
    state.training.chosen = [selected].into_iter().collect();
    state.training.config.horizon = 2;
    let samples = |state: &AppState| state.training_recordings()[0].samples(2);
    let all = samples(&state).len();
    paint_frames(&mut state, "bad tracking", 10, 14);
    let kept: Vec<usize> = samples(&state).iter().map(|s| s.frame).collect();
    // Samples start at 8..=14 touch a skipped frame (start or start + 2).
    assert_eq!(kept.len(), all - 7);
    assert!(kept.iter().all(|&f| !(8..=14).contains(&f)), "{kept:?}");
}

#[test]
fn losses_by_label_average_online_and_fixed_over_the_same_learned_frames() {
    let dir = copy_of_sample_set("losses");
    let mut state = state_on(&dir);
    paint_frames(&mut state, "sticking", 20, 29);
    learn_from_start(&mut state, 40);
    let rows = state.loss_by_label();
    assert_eq!(rows[0].label, "all");
    assert_eq!(rows[0].frames, 40);
    let sticking = rows.iter().find(|r| r.label == "sticking").unwrap();
    assert_eq!(sticking.frames, 10);
    let run = state.run.as_ref().unwrap();
    let mean = |f: &dyn Fn(usize) -> f64| (20..30).map(f).sum::<f64>() / 10.0;
    let online_pos = mean(&|k| run.learned()[k].unwrap().pos);
    let fixed_rot = mean(&|k| run.fixed()[k].rot);
    assert!((sticking.online_pos - online_pos).abs() < 1e-12);
    assert!((sticking.fixed_rot - fixed_rot).abs() < 1e-12);
    assert_ne!(sticking.online_pos, sticking.fixed_pos);
}

#[test]
fn a_stroke_paints_while_playing() {
    let dir = copy_of_sample_set("playing");
    let mut state = state_on(&dir);
    seek(&mut state, 3);
    label(&mut state, LabelAction::Hotkey("slipping".into()));
    state.apply(Command::Timeline(TimelineCommand::TogglePlay));
    // The sample data runs at 10 Hz: a second of playback passes ten frames.
    for _ in 0..20 {
        state.advance(0.05);
    }
    state.apply(Command::Timeline(TimelineCommand::TogglePlay));
    label(&mut state, LabelAction::EndStroke);
    let end = state.frame();
    assert!((12..=14).contains(&end), "stopped at {end}");
    assert_eq!(segments(&state), vec![("slipping".to_owned(), 3..end + 1)]);
    label(&mut state, LabelAction::Undo);
    assert_eq!(
        segments(&state),
        vec![],
        "the whole stroke is one undo step"
    );
}

#[test]
fn online_learning_holds_theta_over_bad_tracking_and_says_why() {
    let dir = copy_of_sample_set("badtracking");
    let mut state = state_on(&dir);
    paint_frames(&mut state, "bad tracking", 30, 34);
    learn_from_start(&mut state, 60);
    let skip = state.frames_to_skip();
    let run = state.run.as_ref().unwrap();
    let mut held = 0;
    for k in 0..60 {
        if run.is_skipped(k, &skip) {
            held += 1;
            assert!(run.learned()[k].is_none(), "learned from frame {k}");
            assert_eq!(run.checkpoints()[k + 1], run.checkpoints()[k]);
        } else {
            assert!(run.learned()[k].is_some(), "frame {k} not learned");
        }
    }
    // Frames 30..=34 and the samples ending on them (the model's horizon before).
    assert!(held >= 5, "{held} frames held");
    seek(&mut state, 32);
    state.apply(Command::Online(OnlineCommand::LearnThisFrame));
    assert!(state.status.as_deref().unwrap().contains("bad tracking"));
}

#[test]
fn labels_changed_by_another_program_are_kept_and_ours_are_rescued_on_exit() {
    let dir = copy_of_sample_set("conflict");
    let file = dir.join(LABELS_FILE_NAME);
    let mut state = state_on(&dir);
    let target = state.label_target().unwrap();
    label(&mut state, LabelAction::Hotkey("contact".into()));
    label(&mut state, LabelAction::EndStroke);
    // `pushlab labels init-splits` or an editor rewrites the file meanwhile.
    let theirs = std::fs::read_to_string(&file)
        .unwrap()
        .replace("\"paper\"", "\"cardboard\"");
    std::fs::write(&file, &theirs).unwrap();
    state.autosave_labels(1.0);
    state.autosave_labels(2.0);
    assert!(
        state
            .status
            .as_deref()
            .unwrap()
            .contains("changed by another program")
    );
    assert_eq!(std::fs::read_to_string(&file).unwrap(), theirs);
    assert!(
        state
            .labels
            .document(&target.document)
            .unwrap()
            .has_conflict()
    );

    let lines = state.labels.save_on_exit();
    assert_eq!(lines.len(), 1);
    assert!(lines[0].contains("pushlab-labels.unsaved-"), "{}", lines[0]);
    assert_eq!(
        std::fs::read_to_string(&file).unwrap(),
        theirs,
        "theirs untouched"
    );
    let rescued = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.to_string_lossy().contains("unsaved-"))
        .expect("a rescue file");
    let rescued = pushlab_core::labels::file::read(&rescued).unwrap();
    assert_eq!(
        rescued.recording(&target.recording).unwrap().segments.len(),
        1
    );

    // Reload takes their version.
    label(&mut state, LabelAction::Reload);
    let meta = &state.labels.labels_of(&target).unwrap().meta;
    assert_eq!(meta.material, "cardboard");
    assert!(segments(&state).is_empty());
    // Or, after another edit and conflict, overwrite with ours.
    std::fs::write(&file, theirs.replace("cardboard", "felt")).unwrap();
    label(&mut state, LabelAction::Hotkey("sticking".into()));
    label(&mut state, LabelAction::EndStroke);
    label(&mut state, LabelAction::SaveAll);
    assert!(
        state
            .status
            .as_deref()
            .unwrap()
            .contains("changed by another program")
    );
    label(&mut state, LabelAction::Overwrite);
    let on_disk = pushlab_core::labels::file::read(&file).unwrap();
    assert_eq!(
        on_disk.recording(&target.recording).unwrap().meta.material,
        "cardboard"
    );
    assert_eq!(
        on_disk.recording(&target.recording).unwrap().segments.len(),
        1
    );
}

#[test]
fn a_stroke_paints_what_was_shown_not_what_a_seek_or_a_loop_jumped_over() {
    let dir = copy_of_sample_set("jumps");
    let mut state = state_on(&dir);
    let last = state.timeline.last_frame();
    // A seek during a stroke paints where it lands, not the frames between.
    seek(&mut state, 10);
    label(&mut state, LabelAction::Hotkey("contact".into()));
    seek(&mut state, 50);
    state.apply(Command::Timeline(TimelineCommand::Step(1)));
    label(&mut state, LabelAction::EndStroke);
    assert_eq!(
        segments(&state),
        vec![
            ("contact".to_owned(), 10..11),
            ("contact".to_owned(), 50..52)
        ]
    );
    // Looping playback that wraps around paints the end and the start, not everything.
    state.apply(Command::Timeline(TimelineCommand::SetLoop(true)));
    seek(&mut state, last - 2);
    label(&mut state, LabelAction::Hotkey("slipping".into()));
    state.apply(Command::Timeline(TimelineCommand::TogglePlay));
    while state.frame() >= last - 2 || state.frame() < 2 {
        state.advance(0.05);
    }
    state.apply(Command::Timeline(TimelineCommand::TogglePlay));
    label(&mut state, LabelAction::EndStroke);
    let now = state.frame();
    let slipping: Vec<_> = segments(&state)
        .into_iter()
        .filter(|(l, _)| l == "slipping")
        .map(|(_, r)| r)
        .collect();
    assert_eq!(slipping, vec![0..now + 1, last - 2..last + 1]);
}

#[test]
fn a_drag_ends_a_stroke_and_each_is_one_undo_step() {
    let dir = copy_of_sample_set("overlap");
    let mut state = state_on(&dir);
    let target = state.label_target().unwrap();
    seek(&mut state, 5);
    label(&mut state, LabelAction::Hotkey("contact".into()));
    state.apply(Command::Timeline(TimelineCommand::Step(2)));
    // A drag of the COM label starts while the key is still down.
    label(
        &mut state,
        LabelAction::BeginGroup("move the COM label".into()),
    );
    assert_eq!(state.labels.stroke_hotkey(), None, "the stroke ended");
    for x in [0.01, 0.02] {
        label(
            &mut state,
            LabelAction::Edit(pushlab_core::labels::Command::SetMeta {
                recording: target.recording.clone(),
                field: pushlab_core::labels::MetaField::ComOffset(Some([x, 0.0])),
            }),
        );
    }
    label(&mut state, LabelAction::Hotkey("sticking".into()));
    assert!(state.status.as_deref().unwrap().contains("finish the drag"));
    label(&mut state, LabelAction::Undo);
    assert!(state.status.as_deref().unwrap().contains("finish the drag"));
    label(&mut state, LabelAction::EndGroup);
    label(&mut state, LabelAction::EndStroke);
    label(&mut state, LabelAction::Undo);
    assert!(
        state
            .status
            .as_deref()
            .unwrap()
            .contains("move the COM label")
    );
    label(&mut state, LabelAction::Undo);
    assert!(
        state
            .status
            .as_deref()
            .unwrap()
            .contains("paint \"contact\"")
    );
    assert!(segments(&state).is_empty());
}

#[test]
fn a_new_model_keeps_the_stroke_the_in_point_and_playback() {
    let dir = copy_of_sample_set("restart");
    let mut state = state_on(&dir);
    seek(&mut state, 4);
    label(&mut state, LabelAction::SetInPoint);
    label(&mut state, LabelAction::Hotkey("contact".into()));
    state.apply(Command::Timeline(TimelineCommand::TogglePlay));
    // What a finished training run or a loaded model does.
    state.restart_run_keeping_frame();
    assert_eq!(state.frame(), 4);
    assert!(state.timeline.playing);
    assert_eq!(state.labels.in_point, Some(4));
    assert_eq!(state.labels.stroke_hotkey(), Some("1"));
    state.apply(Command::Timeline(TimelineCommand::Step(2)));
    label(&mut state, LabelAction::EndStroke);
    assert_eq!(segments(&state), vec![("contact".to_owned(), 4..7)]);
}
