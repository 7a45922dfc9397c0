#![allow(clippy::unwrap_used)]

use super::super::Segment;
use super::super::metadata::Split;
use super::super::schema::names::*;
use std::ops::Range;

use super::super::metadata::MetaField;
use super::super::schema::{LabelDef, Rgb};
use super::*;

const REC: &str = "push_000.csv";

fn doc() -> LabelDocument {
    LabelDocument::new(
        Path::new("/nonexistent/pushlab-labels.json"),
        LabelSet::default(),
    )
}

fn paint(label: &str, frames: Range<usize>) -> Command {
    Command::Paint {
        recording: REC.into(),
        label: label.into(),
        frames,
    }
}

fn segs(doc: &LabelDocument) -> Vec<Segment> {
    doc.recording(REC)
        .map(|r| r.segments.clone())
        .unwrap_or_default()
}

fn s(label: &str, frames: Range<usize>) -> Segment {
    Segment::new(label, frames)
}

#[test]
fn undo_and_redo_walk_through_paint_steps() {
    let mut d = doc();
    assert!(d.apply(paint(STICKING, 0..100)).unwrap());
    assert!(d.apply(paint(SLIPPING, 40..60)).unwrap());
    assert_eq!(
        segs(&d),
        vec![
            s(STICKING, 0..40),
            s(SLIPPING, 40..60),
            s(STICKING, 60..100)
        ]
    );
    assert_eq!(
        d.undo().unwrap(),
        "paint \"slipping\" over frames 40–59 of push_000.csv"
    );
    assert_eq!(segs(&d), vec![s(STICKING, 0..100)]);
    assert_eq!(
        d.undo().unwrap(),
        "paint \"sticking\" over frames 0–99 of push_000.csv"
    );
    assert_eq!(
        d.recording(REC),
        None,
        "an unlabelled recording is absent again"
    );
    assert_eq!(d.undo(), None);
    assert!(d.redo().is_some());
    assert!(d.redo().is_some());
    assert_eq!(d.redo(), None);
    assert_eq!(
        segs(&d),
        vec![
            s(STICKING, 0..40),
            s(SLIPPING, 40..60),
            s(STICKING, 60..100)
        ]
    );
    // A new edit after an undo drops the redo branch.
    d.undo();
    d.apply(paint(BAD_TRACKING, 5..6)).unwrap();
    assert_eq!(d.redo_description(), None);
    assert_eq!(segs(&d), vec![s(STICKING, 0..100), s(BAD_TRACKING, 5..6)]);
}

#[test]
fn refused_and_empty_commands_make_no_step() {
    let mut d = doc();
    let err = d.apply(paint("sliding", 0..10)).unwrap_err();
    assert!(
        err.to_string().starts_with("unknown label \"sliding\""),
        "{err}"
    );
    let err = d.apply(paint(CONTACT_MADE, 0..10)).unwrap_err();
    assert_eq!(
        err.to_string(),
        "\"contact made\" is a point event, expected a range label here"
    );
    assert!(!d.apply(paint(STICKING, 5..5)).unwrap());
    d.apply(paint(STICKING, 0..10)).unwrap();
    assert!(
        !d.apply(paint(STICKING, 2..8)).unwrap(),
        "painting over itself changes nothing"
    );
    d.undo();
    assert_eq!(d.undo(), None);
}

#[test]
fn revert_restores_the_opened_state_and_is_undoable() {
    let mut set = LabelSet::default();
    set.recordings.insert(
        REC.into(),
        RecordingLabels {
            segments: vec![s(CONTACT, 0..50)],
            ..Default::default()
        },
    );
    let mut d = LabelDocument::new(Path::new("/x/l.json"), set);
    d.apply(paint(NO_CONTACT, 20..50)).unwrap();
    d.apply(Command::SetMeta {
        recording: REC.into(),
        field: MetaField::Split(Some(Split::Online)),
    })
    .unwrap();
    d.apply(Command::SetMeta {
        recording: "other.csv".into(),
        field: MetaField::Split(Some(Split::Offline)),
    })
    .unwrap();
    assert!(
        d.apply(Command::RevertRecording {
            recording: REC.into()
        })
        .unwrap()
    );
    assert_eq!(segs(&d), vec![s(CONTACT, 0..50)]);
    assert_eq!(d.recording(REC).unwrap().meta.split, None);
    assert_eq!(
        d.set().split_of("other.csv"),
        Some(Split::Offline),
        "other recordings kept"
    );
    d.undo();
    assert_eq!(segs(&d), vec![s(CONTACT, 0..20), s(NO_CONTACT, 20..50)]);
    assert_eq!(d.recording(REC).unwrap().meta.split, Some(Split::Online));
    // Reverting an unchanged recording is a no-op, and reverting one that did not exist at
    // opening removes it.
    d.redo();
    assert!(
        !d.apply(Command::RevertRecording {
            recording: REC.into()
        })
        .unwrap()
    );
    d.apply(Command::RevertRecording {
        recording: "other.csv".into(),
    })
    .unwrap();
    assert_eq!(d.recording("other.csv"), None);
    d.apply(paint(STICKING, 0..3)).unwrap();
    d.apply(Command::RevertAll).unwrap();
    assert_eq!(d.set(), &d.opened.clone());
}

#[test]
fn typing_in_a_text_field_is_one_step_until_sealed() {
    let mut d = doc();
    for text in ["b", "bo", "box"] {
        d.apply(Command::SetMeta {
            recording: REC.into(),
            field: MetaField::Object(text.into()),
        })
        .unwrap();
    }
    d.seal();
    d.apply(Command::SetMeta {
        recording: REC.into(),
        field: MetaField::Object("box 2".into()),
    })
    .unwrap();
    d.undo();
    assert_eq!(d.recording(REC).unwrap().meta.object, "box");
    d.undo();
    assert_eq!(d.recording(REC), None);
    assert_eq!(d.undo(), None);
    assert!(!d.is_dirty());
}

#[test]
fn typing_back_to_the_start_leaves_no_step() {
    let mut d = doc();
    let notes = |t: &str| Command::SetMeta {
        recording: REC.into(),
        field: MetaField::Notes(t.into()),
    };
    d.apply(notes("x")).unwrap();
    d.apply(notes("")).unwrap();
    assert_eq!(d.undo_description(), None);
    assert!(!d.is_dirty());
}

#[test]
fn a_group_is_one_undo_step() {
    let mut d = doc();
    d.apply(paint(CONTACT, 0..5)).unwrap();
    d.begin_group("paint \"sticking\" while playing");
    for end in 11..=20 {
        d.apply(paint(STICKING, 10..end)).unwrap();
    }
    d.apply(Command::AddEvent {
        recording: REC.into(),
        label: CONTACT_MADE.into(),
        frame: 10,
    })
    .unwrap();
    d.end_group();
    assert_eq!(
        d.undo_description(),
        Some("paint \"sticking\" while playing")
    );
    d.undo();
    assert_eq!(segs(&d), vec![s(CONTACT, 0..5)]);
    assert!(d.recording(REC).unwrap().events.is_empty());
    d.redo();
    assert_eq!(segs(&d), vec![s(CONTACT, 0..5), s(STICKING, 10..20)]);
    // An empty group leaves nothing.
    d.begin_group("nothing");
    d.end_group();
    assert_eq!(
        d.undo_description(),
        Some("paint \"sticking\" while playing")
    );
}

#[test]
fn events_are_added_moved_and_removed() {
    let mut d = doc();
    let add = |frame| Command::AddEvent {
        recording: REC.into(),
        label: CONTACT_LOST.into(),
        frame,
    };
    d.apply(add(30)).unwrap();
    assert!(!d.apply(add(30)).unwrap(), "same event twice is one event");
    d.apply(add(10)).unwrap();
    d.apply(Command::MoveEvent {
        recording: REC.into(),
        label: CONTACT_LOST.into(),
        from: 30,
        to: 5,
    })
    .unwrap();
    let frames: Vec<usize> = d
        .recording(REC)
        .unwrap()
        .events
        .iter()
        .map(|e| e.frame)
        .collect();
    assert_eq!(frames, vec![5, 10]);
    d.apply(Command::RemoveEvent {
        recording: REC.into(),
        label: CONTACT_LOST.into(),
        frame: 10,
    })
    .unwrap();
    assert_eq!(d.recording(REC).unwrap().events.len(), 1);
    let err = d.apply(add(1).clone()).map(|_| ());
    assert!(err.is_ok());
    let err = d
        .apply(Command::AddEvent {
            recording: REC.into(),
            label: STICKING.into(),
            frame: 1,
        })
        .unwrap_err();
    assert!(err.to_string().contains("is a range label"), "{err}");
}

#[test]
fn dirty_state_follows_undo_to_the_saved_point() {
    let dir = std::env::temp_dir().join(format!("pushlab-labels-doc-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut d = LabelDocument::open_set_folder(&dir).unwrap();
    // Without a file and without edits there is nothing to save: opening writes nothing.
    assert_eq!(d.save_state(), SaveState::Saved);
    assert!(!d.save_if_dirty().unwrap());
    assert!(!file::path_in(&dir).exists(), "nothing was written");
    d.save().unwrap();
    assert_eq!(d.save_state(), SaveState::Saved);
    d.apply(paint(STICKING, 0..10)).unwrap();
    assert_eq!(d.save_state(), SaveState::Unsaved);
    d.save().unwrap();
    d.apply(paint(SLIPPING, 5..10)).unwrap();
    assert!(d.is_dirty());
    d.undo();
    assert!(!d.is_dirty(), "undo back to what is on disk");
    d.undo();
    assert!(d.is_dirty());
    d.redo();
    assert!(!d.is_dirty());
    // Reopening shows what was saved, and that is the new revert point.
    let reopened = LabelDocument::open_set_folder(&dir).unwrap();
    assert_eq!(reopened.set(), d.set());
    assert_eq!(reopened.save_state(), SaveState::Saved);
}

#[test]
fn failed_save_is_reported_and_edits_are_kept() {
    let mut d = doc();
    d.apply(paint(STICKING, 0..10)).unwrap();
    let err = d.save().unwrap_err().to_string();
    assert!(err.contains("/nonexistent/pushlab-labels.json"), "{err}");
    assert_eq!(d.save_state(), SaveState::Failed(err));
    assert_eq!(segs(&d), vec![s(STICKING, 0..10)]);
}

#[test]
fn schema_edits_are_checked_and_undoable() {
    let mut d = doc();
    d.apply(paint(SLIPPING, 0..10)).unwrap();
    let err = d
        .apply(Command::RemoveLabel {
            name: SLIPPING.into(),
            with_uses: false,
        })
        .unwrap_err();
    assert_eq!(
        err.to_string(),
        "label \"slipping\" is used 1 times (in push_000.csv); erase it first or remove it with its uses"
    );
    d.apply(Command::RenameLabel {
        from: SLIPPING.into(),
        to: "sliding".into(),
    })
    .unwrap();
    assert_eq!(segs(&d), vec![s("sliding", 0..10)]);
    assert!(
        d.schema().excludes("sliding", STICKING),
        "the group travels with the name"
    );
    let err = d
        .apply(Command::SetLabelAppearance {
            name: "sliding".into(),
            colour: Rgb::new(1, 2, 3),
            hotkey: Some("1".into()),
        })
        .unwrap_err();
    assert!(
        err.to_string()
            .contains("hotkey \"1\" is used by two labels"),
        "{err}"
    );
    d.apply(Command::RemoveLabel {
        name: "sliding".into(),
        with_uses: true,
    })
    .unwrap();
    assert_eq!(d.recording(REC), None);
    assert!(d.schema().get("sliding").is_none());
    d.undo();
    d.undo();
    assert_eq!(segs(&d), vec![s(SLIPPING, 0..10)]);
    assert_eq!(d.schema(), &LabelSchema::default());
    d.apply(Command::AddLabel(LabelDef::range(
        "pusher occluded",
        Rgb::new(9, 9, 9),
    )))
    .unwrap();
    assert!(d.schema().get("pusher occluded").is_some());
}

#[test]
fn non_finite_com_is_refused() {
    let mut d = doc();
    let err = d
        .apply(Command::SetMeta {
            recording: REC.into(),
            field: MetaField::ComOffset(Some([0.0, f64::INFINITY])),
        })
        .unwrap_err();
    assert!(
        err.to_string()
            .starts_with("com_offset: expected two finite numbers"),
        "{err}"
    );
    assert_eq!(d.recording(REC), None);
}

#[test]
fn autosave_waits_for_a_pause_but_not_forever() {
    let dir = std::env::temp_dir().join(format!("pushlab-labels-auto-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut d = LabelDocument::open_set_folder(&dir).unwrap();
    d.save().unwrap();
    let mut auto = Autosave::default();
    assert!(auto.poll(&mut d, 0.0).is_none());
    d.apply(paint(STICKING, 0..1)).unwrap();
    assert!(auto.poll(&mut d, 0.1).is_none(), "too soon after the edit");
    assert!(auto.poll(&mut d, 0.7).unwrap().is_ok());
    assert!(!d.is_dirty());
    assert_eq!(file::read(d.path()).unwrap(), d.set().clone());
    // Painting every 0.1 s during playback: saved once max_delay has passed.
    let mut saved_at = None;
    for i in 0..80 {
        let t = 1.0 + 0.1 * f64::from(i);
        d.apply(paint(STICKING, 0..2 + i as usize)).unwrap();
        if auto.poll(&mut d, t).is_some() {
            saved_at = Some(t);
            break;
        }
    }
    let saved_at = saved_at.unwrap();
    assert!((5.9..6.2).contains(&saved_at), "saved at {saved_at}");
}

#[test]
fn a_file_changed_by_another_program_is_not_overwritten_until_asked() {
    let dir = std::env::temp_dir().join(format!("pushlab-doc-conflict-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = super::super::file::path_in(&dir);
    let mut d = LabelDocument::open(&path).unwrap();
    d.apply(paint(STICKING, 0..10)).unwrap();
    d.save().unwrap();

    // Another program (`pushlab labels init-splits`, a text editor) writes the file.
    let mut theirs = d.set().clone();
    theirs.recordings.get_mut(REC).unwrap().meta.notes = "written elsewhere".into();
    super::super::file::write(&path, &theirs).unwrap();
    let on_disk = std::fs::read_to_string(&path).unwrap();

    d.apply(paint(SLIPPING, 20..30)).unwrap();
    let err = d.save().unwrap_err();
    assert!(matches!(err, LabelFileError::ChangedOnDisk { .. }), "{err}");
    assert!(err.to_string().contains("changed by another program"));
    assert!(d.has_conflict());
    assert!(matches!(d.save_state(), SaveState::Failed(_)));
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        on_disk,
        "their file is kept"
    );
    assert_eq!(segs(&d).len(), 2, "our edits are kept");

    // Reload takes their version; a later edit saves normally on top of it.
    let mut reloaded = d.clone();
    reloaded.reload().unwrap();
    assert_eq!(reloaded.set(), &theirs);
    assert!(!reloaded.has_conflict());
    reloaded.apply(paint(CONTACT, 40..50)).unwrap();
    reloaded.save().unwrap();

    // Or overwrite with ours (on the original document, whose file changed again meanwhile).
    d.overwrite().unwrap();
    assert!(!d.has_conflict());
    assert_eq!(d.save_state(), SaveState::Saved);
    assert_eq!(&super::super::file::read(&path).unwrap(), d.set());
    let _ = std::fs::remove_dir_all(&dir);
}
