//! Labeling in the app, driven by the keyboard and the accessibility tree as a user would: paint a
//! range with a held key while stepping, undo, redo, save, reopen the folder, and see the same labels.
//! Every test works on a private copy of one sample-data set, never on the repository's files.

use crate::common;
use crate::skip;

use std::path::Path;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use nalgebra::Point2;
use pushlab::app::state::Persisted;
use pushlab::app::state::recordings::browser::Column;
use pushlab::app::{PushlabApp, initial_state};
use pushlab_core::labels::{LABELS_FILE_NAME, Split};

/// The app opened on `dir`, showing the Labels tab.
fn app_on(dir: &Path) -> Harness<'static, PushlabApp> {
    let app = PushlabApp::new(initial_state(&[dir.to_path_buf()], Persisted::default()));
    assert!(
        app.state.recording().is_some(),
        "{:?}",
        app.state.session().problems
    );
    let mut harness = common::harness(app, 0.05);
    harness.run_steps(2);
    harness.get_by_label("Labels").click();
    harness.run_steps(2);
    harness
}

fn seek(harness: &mut Harness<'_, PushlabApp>, frame: usize) {
    harness
        .get_by_role_and_label(egui::accesskit::Role::Slider, "Frame")
        .set_value_accesskit(frame as f64);
    harness.run_steps(2);
    assert_eq!(harness.state().state.frame(), frame);
}

fn shows(harness: &Harness<'_, PushlabApp>, text: &str) -> bool {
    harness.query_all_by_label_contains(text).next().is_some()
}

#[test]
fn label_a_range_by_keyboard_undo_redo_save_reopen_and_see_the_same_labels() {
    let dir = common::copy_of_sample_set("box1-paper-center-front", "labels-roundtrip");
    let mut harness = app_on(&dir);
    seek(&mut harness, 5);

    // Hold "1" (contact) and step three frames.
    harness.key_down(egui::Key::Num1);
    harness.run_steps(2);
    for _ in 0..3 {
        harness.key_press(egui::Key::ArrowRight);
        harness.run_steps(2);
    }
    harness.key_up(egui::Key::Num1);
    harness.run_steps(2);
    assert_eq!(harness.state().state.frame(), 8);
    assert!(shows(&harness, "contact: frames 5–8"), "segment listed");
    {
        let state = &harness.state().state;
        let rows = state.browser_rows();
        let row = rows
            .iter()
            .find(|r| r.name == "offline_000")
            .expect("the browser lists offline_000");
        assert_eq!(
            (row.text(Column::Split), row.text(Column::Labels)),
            ("offline".to_owned(), "1".to_owned()),
            "the browser shows the split and the label count"
        );
    }
    assert!(shows(&harness, "labels unsaved"), "indicator says unsaved");

    // After release, stepping no longer paints.
    harness.key_press(egui::Key::ArrowRight);
    harness.run_steps(2);
    assert!(shows(&harness, "contact: frames 5–8"));

    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(2);
    assert!(
        !shows(&harness, "contact: frames"),
        "undo removed the stroke"
    );
    assert!(
        shows(&harness, "undid: paint \"contact\""),
        "status says what was undone"
    );

    harness.key_press_modifiers(
        egui::Modifiers::COMMAND | egui::Modifiers::SHIFT,
        egui::Key::Z,
    );
    harness.run_steps(2);
    assert!(
        shows(&harness, "contact: frames 5–8"),
        "redo brought it back"
    );

    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::S);
    harness.run_steps(2);
    assert!(shows(&harness, "labels saved"), "indicator says saved");
    let text = std::fs::read_to_string(dir.join(LABELS_FILE_NAME)).expect("labels file");
    assert!(text.contains("\"contact\""), "{text}");
    drop(harness);

    let mut reopened = app_on(&dir);
    reopened.run_steps(2);
    assert!(
        shows(&reopened, "contact: frames 5–8"),
        "labels survive reopening"
    );
    seek(&mut reopened, 6);
    assert!(shows(&reopened, "Frame 6: contact"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn event_key_bands_and_next_label_key() {
    let dir = common::copy_of_sample_set("box1-paper-center-front", "labels-events");
    let mut harness = app_on(&dir);
    seek(&mut harness, 12);
    harness.key_press(egui::Key::Num6); // "contact made" event
    harness.run_steps(2);
    assert!(shows(&harness, "contact made: frame 12"));
    // In point at 20, out point at 24 with the chosen label.
    harness.get_by_label("sticking").click();
    harness.run_steps(2);
    seek(&mut harness, 20);
    harness.key_press(egui::Key::I);
    harness.run_steps(2);
    assert!(shows(&harness, "In point: frame 20"));
    seek(&mut harness, 24);
    harness.key_press(egui::Key::O);
    harness.run_steps(2);
    assert!(shows(&harness, "sticking: frames 20–24"));
    harness.key_press(egui::Key::I);
    harness.run_steps(2);
    harness.get_by_label("Clear in").click();
    harness.run_steps(2);
    assert!(shows(&harness, "In point: not set"));

    harness.key_press(egui::Key::Home);
    harness.run_steps(2);
    let mut visited = Vec::new();
    for _ in 0..3 {
        harness.key_press(egui::Key::CloseBracket);
        harness.run_steps(2);
        visited.push(harness.state().state.frame());
    }
    assert_eq!(visited, vec![12, 20, 24]);
    harness.key_press(egui::Key::OpenBracket);
    harness.run_steps(2);
    assert_eq!(harness.state().state.frame(), 20);

    // Clicking the bands jumps to the frame under the pointer.
    let bands = harness.get_by_label("Label bands").rect();
    let frames = harness.state().state.timeline().len() as f32;
    let at = egui::pos2(
        bands.left() + bands.width() * (22.5 / frames),
        bands.center().y,
    );
    harness.hover_at(at);
    harness.run_steps(1);
    harness.drag_at(at);
    harness.run_steps(1);
    harness.drop_at(at);
    harness.run_steps(2);
    assert_eq!(harness.state().state.frame(), 22);

    // Deleting the segment from the list is undoable like any edit.
    harness
        .query_all_by_label("Delete")
        .next()
        .expect("a Delete button")
        .click();
    harness.run_steps(2);
    assert!(!shows(&harness, "sticking: frames 20–24"));
    harness.get_by_label("Undo").click();
    harness.run_steps(2);
    assert!(shows(&harness, "sticking: frames 20–24"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn metadata_form_edits_are_undoable_typing_is_one_step_and_keys_do_not_fire_in_text() {
    let dir = common::copy_of_sample_set("box1-paper-center-front", "labels-meta");
    let mut harness = app_on(&dir);
    let recording = harness
        .state()
        .state
        .label_target()
        .expect("target")
        .recording;
    let meta = |h: &Harness<'_, PushlabApp>| {
        let state = &h.state().state;
        let target = state.label_target().expect("target");
        state
            .labels()
            .labels_of(&target)
            .map(|l| l.meta.clone())
            .unwrap_or_default()
    };
    assert_eq!(meta(&harness).material, "paper");
    // Typing into the Material field: "1" is text there, not the contact hotkey.
    harness
        .get_by_role_and_label(egui::accesskit::Role::TextInput, "Material")
        .click();
    harness.run_steps(2);
    for text in [" ", "1", "x"] {
        if text == "1" {
            harness.key_press(egui::Key::Num1);
        }
        harness.event(egui::Event::Text(text.to_owned()));
        harness.run_steps(2);
    }
    assert_eq!(meta(&harness).material, "paper 1x");
    assert!(
        !shows(&harness, "contact: frames"),
        "typing painted a label"
    );
    harness.key_press(egui::Key::Escape);
    harness.run_steps(2);
    harness.get_by_label("Undo").click();
    harness.run_steps(2);
    assert_eq!(
        meta(&harness).material,
        "paper",
        "one undo step for the typing"
    );

    // The split drop-down (the browser's "Split" column header is a button).
    harness
        .get_by_role_and_label(egui::accesskit::Role::ComboBox, "Split")
        .click();
    harness.run_steps(2);
    harness.get_by_label("held-out").click();
    harness.run_steps(2);
    assert_eq!(meta(&harness).split, Some(Split::HeldOut));
    harness.get_by_label("Undo").click();
    harness.run_steps(2);
    assert_eq!(meta(&harness).split, Some(Split::Offline));

    harness.get_by_label("Clear").click(); // the COM label of the sample data
    harness.run_steps(2);
    assert_eq!(meta(&harness).com_offset, None);
    harness.get_by_label("Place at estimated COM").click();
    harness.run_steps(2);
    let theta = harness.state().state.theta().expect("theta").com_offset;
    assert_eq!(meta(&harness).com_offset, Some(theta));
    harness.get_by_label("Show layers").click();
    harness.run_steps(2);
    assert!(
        shows(&harness, "Labelled COM, diamond"),
        "the scene legend lists the COM label"
    );

    harness.get_by_label("Undo").click();
    harness.run_steps(2);
    harness.get_by_label("Undo").click();
    harness.run_steps(2);
    assert_eq!(meta(&harness).com_offset, Some([0.0, 0.0]), "{recording}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn question_mark_shows_the_cheat_sheet_with_the_label_keys() {
    let dir = common::copy_of_sample_set("box1-paper-center-front", "labels-sheet");
    let mut harness = app_on(&dir);
    assert!(!shows(&harness, "hold to paint while stepping or playing"));
    harness.key_press(egui::Key::F1);
    harness.run_steps(2);
    assert!(shows(&harness, "Keyboard shortcuts"));
    assert!(shows(
        &harness,
        "contact: hold to paint while stepping or playing"
    ));
    assert!(shows(
        &harness,
        "contact made: place or remove the event here"
    ));
    assert!(shows(&harness, "undo a label edit"));
    harness.key_press(egui::Key::F1);
    harness.run_steps(2);
    assert!(!shows(&harness, "hold to paint while stepping or playing"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn quick_presses_within_one_frame_all_count_and_events_land_during_a_stroke() {
    let dir = common::copy_of_sample_set("box1-paper-center-front", "labels-quick");
    let mut harness = app_on(&dir);
    seek(&mut harness, 10);
    // Key down "3" (sticking), "6" (contact made) and five → all before the next frame is drawn.
    harness.key_down(egui::Key::Num3);
    harness.key_press(egui::Key::Num6);
    for _ in 0..5 {
        harness.key_press(egui::Key::ArrowRight);
    }
    harness.run_steps(2);
    harness.key_up(egui::Key::Num3);
    harness.run_steps(2);
    assert_eq!(harness.state().state.frame(), 15);
    assert!(shows(&harness, "sticking: frames 10–15"));
    assert!(shows(&harness, "contact made: frame 10"));

    // Keys act in the order they were pressed, even within one frame: → I → 7 → gives the in point
    // and the event at 16, then moves on to 17.
    harness.key_press(egui::Key::ArrowRight);
    harness.key_press(egui::Key::I);
    harness.key_press(egui::Key::Num7);
    harness.key_press(egui::Key::ArrowRight);
    harness.run_steps(2);
    assert_eq!(harness.state().state.frame(), 17);
    assert_eq!(harness.state().state.labels().in_point, Some(16));
    assert!(shows(&harness, "contact lost: frame 16"));
    // A tap and a step in one frame paint one frame only.
    harness.key_press(egui::Key::Num2);
    harness.key_press(egui::Key::ArrowRight);
    harness.run_steps(2);
    assert!(shows(&harness, "no contact: frame 17"));
    assert!(!shows(&harness, "no contact: frames"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn dragging_the_com_label_diamond_moves_the_label_in_one_undo_step() {
    let dir = common::copy_of_sample_set("box1-paper-center-front", "labels-comdrag");
    let mut harness = app_on(&dir);
    // Only the diamond under the pointer: hide the estimated-COM marker, which sits nearby (in the
    // legend, folded by default), and fold the legend again.
    harness.get_by_label("Show layers").click();
    harness.run_steps(1);
    harness.get_by_label("Estimated COM (drag me)").click();
    harness.run_steps(1);
    harness.get_by_label("Hide layers").click();
    harness.run_steps(2);
    let (start, end, expected) = {
        let app = harness.state();
        let state = &app.state;
        let target = state.label_target().expect("target");
        let com = state
            .labels()
            .labels_of(&target)
            .and_then(|l| l.meta.com_offset)
            .expect("the sample data labels the COM");
        assert_eq!(com, [0.0, 0.0]);
        let pose = state.recording().expect("recording").trajectory.frames[state.frame()].object;
        let projection = app.view.scene.projection();
        let start = projection.to_screen(pose.point_in_world(Point2::from(com)));
        let end = start + egui::vec2(40.0, -25.0);
        let expected = pose.point_in_object(projection.to_world(end));
        (start, end, expected)
    };
    harness.hover_at(start);
    harness.run_steps(1);
    harness.drag_at(start);
    harness.run_steps(1);
    for t in [0.25, 0.5, 0.75, 1.0] {
        harness.hover_at(start + (end - start) * t);
        harness.run_steps(1);
    }
    harness.drop_at(end);
    harness.run_steps(2);
    let com = |h: &Harness<'_, PushlabApp>| {
        let state = &h.state().state;
        let target = state.label_target().expect("target");
        state
            .labels()
            .labels_of(&target)
            .and_then(|l| l.meta.com_offset)
            .expect("a COM label")
    };
    let moved = com(&harness);
    assert!(
        (moved[0] - expected.x).abs() < 1e-9 && (moved[1] - expected.y).abs() < 1e-9,
        "{moved:?} vs {expected:?}"
    );
    assert!(
        harness.state().state.theta().expect("theta").com_offset != moved,
        "the drag moved the label, not the estimate"
    );
    harness.get_by_label("Undo").click();
    harness.run_steps(2);
    assert_eq!(com(&harness), [0.0, 0.0], "one undo undoes the whole drag");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn letting_go_of_a_paint_key_while_typing_ends_the_stroke() {
    let dir = common::copy_of_sample_set("box1-paper-center-front", "labels-focus");
    let mut harness = app_on(&dir);
    seek(&mut harness, 10);
    harness.key_down(egui::Key::Num1);
    harness.run_steps(2);
    assert_eq!(harness.state().state.labels().stroke_hotkey(), Some("1"));
    // The user clicks into the notes while still holding "1", then lets go of it.
    harness
        .get_by_role_and_label(egui::accesskit::Role::MultilineTextInput, "Notes")
        .click();
    harness.run_steps(2);
    harness.key_up(egui::Key::Num1);
    harness.run_steps(2);
    assert_eq!(harness.state().state.labels().stroke_hotkey(), None);
    harness.event(egui::Event::Text("hello".to_owned()));
    harness.run_steps(2);
    harness.key_press(egui::Key::Escape);
    harness.run_steps(2);
    harness.get_by_label("Undo").click();
    harness.run_steps(2);
    assert!(
        shows(&harness, "contact: frame 10"),
        "undoing the typing leaves the stroke"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_new_label_added_in_the_app_gets_a_key_paints_and_saves() {
    let dir = common::copy_of_sample_set("box1-paper-center-front", "labels-schema");
    let mut harness = app_on(&dir);
    harness.get_by_label("Edit labels").click();
    harness.run_steps(2);
    harness
        .get_by_role_and_label(egui::accesskit::Role::TextInput, "New label")
        .click();
    harness.run_steps(2);
    harness.event(egui::Event::Text("wobble".to_owned()));
    harness.run_steps(2);
    harness.key_press(egui::Key::Escape);
    harness.run_steps(2);
    harness.get_by_label("Add label").click();
    harness.run_steps(2);
    assert!(shows(&harness, "wobble"), "the palette lists the new label");

    // It got the first free digit, 8: hold it and step.
    seek(&mut harness, 30);
    harness.key_down(egui::Key::Num8);
    harness.run_steps(2);
    harness.key_press(egui::Key::ArrowRight);
    harness.run_steps(2);
    harness.key_up(egui::Key::Num8);
    harness.run_steps(2);
    assert!(shows(&harness, "wobble: frames 30–31"));

    // Removing a label still in use is refused, and says so.
    let removes = harness.query_all_by_label("Remove").count();
    harness
        .query_all_by_label("Remove")
        .nth(removes - 1)
        .expect("the new label's Remove button")
        .click();
    harness.run_steps(2);
    assert!(shows(&harness, "is used"), "the status says why");
    assert!(shows(&harness, "wobble: frames 30–31"));

    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::S);
    harness.run_steps(2);
    let saved = pushlab_core::labels::file::read(&dir.join(LABELS_FILE_NAME)).expect("saved");
    let wobble = saved
        .schema
        .get("wobble")
        .expect("the schema has the new label");
    assert_eq!(wobble.hotkey.as_deref(), Some("8"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn opening_a_folder_without_labels_and_closing_it_writes_nothing_into_it() {
    let dir = common::copy_of_sample_set("box1-paper-center-front", "no-write");
    std::fs::remove_file(dir.join(LABELS_FILE_NAME)).expect("the copy has a labels file");
    let mut harness = app_on(&dir);
    // Play for a while and step through the tabs, editing nothing.
    harness.key_press(egui::Key::Space);
    harness.run_steps(30);
    harness.state_mut().state.autosave_labels(1e6);
    let closing = harness.state_mut().state.save_labels_on_exit();
    assert!(closing.is_empty(), "{closing:?}");
    assert!(
        !dir.join(LABELS_FILE_NAME).exists(),
        "a labels file appeared without an edit"
    );
    // The first edit creates it.
    harness.key_down(egui::Key::Num3);
    harness.run_steps(1);
    harness.key_up(egui::Key::Num3);
    harness.run_steps(1);
    harness.state_mut().state.save_labels_on_exit();
    assert!(dir.join(LABELS_FILE_NAME).exists(), "an edit is saved");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_folder_that_cannot_be_written_opens_keeps_labels_in_memory_and_says_where_they_go() {
    let dir = common::copy_of_sample_set("box1-paper-center-front", "read-only");
    let before = common::contents(&dir);
    let Some(guard) = common::Unwritable::make(&dir) else {
        skip::skip(
            "a folder this process cannot write (neither chmod 555 nor chattr +i stopped it)",
        );
        return;
    };
    let app_dir = common::scratch_dir("rescue");
    let rescue_dir = app_dir.join("unsaved-labels");
    let mut harness = app_on(&dir);
    harness.state_mut().state.keep_files_in(Some(app_dir));
    harness.key_down(egui::Key::Num3);
    harness.run_steps(1);
    harness.key_up(egui::Key::Num3);
    harness.run_steps(1);
    // Autosave notices the edit, then saves once it is due.
    harness.state_mut().state.autosave_labels(1e6);
    harness.state_mut().state.autosave_labels(1e6 + 1.0);
    harness.run_steps(1);
    let document = dir.join(LABELS_FILE_NAME);
    let rescue = pushlab::app::state::labels::labeling::rescue_path(&document, &rescue_dir);
    let status = common::status(&harness);
    assert!(
        status.starts_with(&format!(
            "labels kept in memory: {} cannot be written",
            dir.display()
        )) && status.ends_with(&format!("saves them to {}", rescue.display())),
        "{status}"
    );
    assert!(
        shows(&harness, "labels kept in memory"),
        "the status line shows it"
    );
    let painted = |harness: &Harness<'_, PushlabApp>| {
        let state = &harness.state().state;
        let target = state.label_target().expect("a recording");
        state.labels().labels_of(&target).map(|l| l.segments.len())
    };
    assert_eq!(painted(&harness), Some(1), "the edit is kept in memory");

    // Ctrl+S writes them where the message said.
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::S);
    harness.run_steps(2);
    let status = common::status(&harness);
    assert!(
        status.contains(&format!("its labels were saved to {}", rescue.display())),
        "{status}"
    );
    let saved = pushlab_core::labels::file::read(&rescue).expect("the rescued labels read back");
    let key = harness
        .state()
        .state
        .label_target()
        .expect("a recording")
        .recording;
    assert_eq!(saved.recording(&key).map(|l| l.segments.len()), Some(1));
    // Closing says so too, and the user's folder is as it was.
    let closing = harness.state_mut().state.save_labels_on_exit();
    assert!(
        closing
            .iter()
            .any(|l| l.contains(&rescue.display().to_string())),
        "{closing:?}"
    );
    drop(guard);
    assert!(
        common::contents(&dir) == before,
        "the unwritable folder changed"
    );
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&rescue_dir);
}
