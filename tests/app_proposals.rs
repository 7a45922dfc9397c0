//! Label proposals in the app, as a user meets them: the band under the label bands shows what was
//! proposed; clicking a proposed segment labels its frames (on disk only once saved), Ctrl+Z takes
//! exactly that back, Backspace or a right-click rejects, the menu accepts every proposal of a label,
//! and the inspector says why a frame was proposed. Every test works on a private copy of a sample
//! set.

use crate::common;

use std::ops::Range;
use std::path::Path;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use pushlab::app::state::Persisted;
use pushlab::app::{PushlabApp, initial_state};
use pushlab_core::labels::schema::names::{CONTACT, SLIPPING, STICKING};
use pushlab_core::labels::{LABELS_FILE_NAME, Segment, file};

fn app_on(dir: &Path) -> Harness<'static, PushlabApp> {
    let app = PushlabApp::new(initial_state(&[dir.to_path_buf()], Persisted::default()));
    assert!(
        app.state.recording().is_some(),
        "{:?}",
        app.state.session().problems
    );
    let mut harness = common::harness(app, 0.05);
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

/// Every text shown that contains `text` (labels keep theirs in the value).
fn texts(harness: &Harness<'_, PushlabApp>, text: &str) -> Vec<String> {
    harness
        .query_all_by_label_contains(text)
        .filter_map(|node| {
            let node = node.accesskit_node();
            node.label().or_else(|| node.value())
        })
        .collect()
}

fn shows(harness: &Harness<'_, PushlabApp>, text: &str) -> bool {
    !texts(harness, text).is_empty()
}

/// The selected recording's labelled segments, in the app.
fn segments(harness: &Harness<'_, PushlabApp>) -> Vec<Segment> {
    let state = &harness.state().state;
    let target = state.label_target().expect("target");
    state
        .labels()
        .labels_of(&target)
        .map(|l| l.segments.clone())
        .unwrap_or_default()
}

/// The selected recording's segments in the labels file on disk.
fn segments_on_disk(harness: &Harness<'_, PushlabApp>, dir: &Path) -> Vec<Segment> {
    let target = harness.state().state.label_target().expect("target");
    file::read(&dir.join(LABELS_FILE_NAME))
        .expect("labels file")
        .recording(&target.recording)
        .map(|l| l.segments.clone())
        .unwrap_or_default()
}

/// The first pending proposal of `label`: its frames and what accepting it labels.
fn pending(harness: &Harness<'_, PushlabApp>, label: &str) -> Option<(Range<usize>, Range<usize>)> {
    harness
        .state()
        .state
        .pending_proposals()
        .iter()
        .find(|p| p.proposal.label == label)
        .map(|p| (p.proposal.frames.clone(), p.open[0].clone()))
}

fn pending_count(harness: &Harness<'_, PushlabApp>) -> usize {
    harness.state().state.pending_proposals().len()
}

/// Where frame `frame` of the band's row `row` (contact / no contact, then sticking / slipping) is
/// drawn.
fn band_point(harness: &Harness<'_, PushlabApp>, row: usize, frame: usize) -> egui::Pos2 {
    let band = harness.get_by_label("Proposals band").rect();
    let frames = harness.state().state.timeline().len() as f32;
    egui::pos2(
        band.left() + band.width() * ((frame as f32 + 0.5) / frames),
        band.top() + 6.0 + 9.0 * row as f32,
    )
}

fn click(harness: &mut Harness<'_, PushlabApp>, at: egui::Pos2, button: egui::PointerButton) {
    harness.hover_at(at);
    harness.run_steps(1);
    for pressed in [true, false] {
        harness.event(egui::Event::PointerButton {
            pos: at,
            button,
            pressed,
            modifiers: egui::Modifiers::NONE,
        });
        harness.run_steps(1);
    }
    harness.run_steps(2);
}

#[test]
fn click_a_proposed_segment_to_label_it_save_writes_it_and_undo_takes_exactly_that_back() {
    let dir = common::copy_of_sample_set("box1-paper-center-front", "proposals-accept");
    let mut harness = app_on(&dir);
    assert!(
        shows(&harness, "Proposals ("),
        "the band's menu counts the proposals"
    );
    let (frames, open) = pending(&harness, CONTACT).expect("contact is proposed");
    assert_eq!(
        frames, open,
        "nothing labelled yet, so all of it would be labelled"
    );
    assert!(segments(&harness).is_empty());
    let count = pending_count(&harness);

    let at = band_point(&harness, 0, (frames.start + frames.end) / 2);
    click(&mut harness, at, egui::PointerButton::Primary);
    assert_eq!(
        segments(&harness),
        vec![Segment::new(CONTACT, frames.clone())]
    );
    assert_eq!(
        pending_count(&harness),
        count - 1,
        "accepted: no longer proposed"
    );
    assert!(
        shows(&harness, "accept proposed contact"),
        "the status says so"
    );
    assert!(
        segments_on_disk(&harness, &dir).is_empty(),
        "not on disk before it is saved"
    );
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::S);
    harness.run_steps(2);
    assert_eq!(
        segments_on_disk(&harness, &dir),
        vec![Segment::new(CONTACT, frames.clone())]
    );

    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(2);
    assert!(
        segments(&harness).is_empty(),
        "undo took the acceptance back"
    );
    assert!(shows(&harness, "undid: accept proposed contact"));
    assert_eq!(pending_count(&harness), count, "and it is proposed again");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn reject_by_key_and_right_click_hides_proposals_and_the_menu_restores_them_and_accepts_all() {
    let dir = common::copy_of_sample_set("box1-paper-center-front", "proposals-reject");
    let mut harness = app_on(&dir);
    let count = pending_count(&harness);
    let (frames, _) = pending(&harness, CONTACT).expect("contact is proposed");
    seek(&mut harness, frames.start);
    let here = harness
        .state()
        .state
        .pending_proposals()
        .iter()
        .filter(|p| p.proposal.frames.contains(&frames.start))
        .count();
    harness.key_press(egui::Key::Backspace);
    harness.run_steps(2);
    assert_eq!(pending_count(&harness), count - here);
    assert!(shows(&harness, "rejected the proposed contact"));
    assert!(segments(&harness).is_empty(), "rejecting labels nothing");

    let (frames, _) = pending(&harness, SLIPPING).expect("slipping is proposed");
    let at = band_point(&harness, 1, (frames.start + frames.end) / 2);
    click(&mut harness, at, egui::PointerButton::Secondary);
    assert_eq!(pending_count(&harness), count - here - 1);
    assert!(segments(&harness).is_empty());

    harness.get_by_label_contains("Proposals (").click();
    harness.run_steps(2);
    harness.get_by_label_contains("Restore rejected").click();
    harness.run_steps(2);
    assert_eq!(pending_count(&harness), count, "nothing rejected is lost");

    let sticking = |h: &Harness<'_, PushlabApp>| {
        h.state()
            .state
            .pending_proposals()
            .iter()
            .filter(|p| p.proposal.label == STICKING)
            .count()
    };
    let n = sticking(&harness);
    assert!(n > 0);
    harness.get_by_label_contains("Proposals (").click();
    harness.run_steps(2);
    harness
        .get_by_label(&format!("Accept all {STICKING} ({n})"))
        .click();
    harness.run_steps(2);
    assert_eq!(sticking(&harness), 0);
    assert!(segments(&harness).iter().all(|s| s.label == STICKING));
    harness.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    harness.run_steps(2);
    assert!(segments(&harness).is_empty(), "accept all is one undo step");
    assert_eq!(sticking(&harness), n);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn enter_accepts_the_proposals_at_the_playhead_and_the_inspector_says_why() {
    let dir = common::copy_of_sample_set("box1-paper-center-front", "proposals-why");
    let mut harness = app_on(&dir);
    harness.get_by_label("Inspect").click();
    harness.run_steps(2);
    let (frames, _) = pending(&harness, STICKING).expect("sticking is proposed");
    let frame = frames.start + 1;
    seek(&mut harness, frame);
    let why = texts(&harness, "sticking: the pusher drifts");
    assert_eq!(why.len(), 1, "{why:?}");
    assert!(why[0].contains(" σ; slipping from 3 σ)") && why[0].contains("% sure"));
    let contact = texts(&harness, "contact: the pusher's rim is");
    assert!(
        contact
            .iter()
            .any(|t| t.contains("mm from the outline (contact within")),
        "{contact:?}"
    );
    assert!(
        shows(&harness, "model residual:"),
        "the default model's residual"
    );

    harness.key_press(egui::Key::Enter);
    harness.run_steps(2);
    let state = &harness.state().state;
    let target = state.label_target().expect("target");
    let labels = state.labels().labels_of(&target).expect("labelled");
    assert!(labels.has_label_at(STICKING, frame) && labels.has_label_at(CONTACT, frame));
    assert!(
        texts(&harness, "sticking: the pusher drifts")[0].ends_with("(labelled)"),
        "the inspector marks it decided"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
