//! The loss-landscape window, driven through the UI: F2 (or View → Loss landscape) opens it, the
//! landscape of the frame shown is computed in the background and marks θ there, the lowest cell and
//! the true COM; it follows the frame; cancel holds until asked again; closing stops it.

use crate::common;

use eframe::egui::Key;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use pushlab::app::PushlabApp;
use pushlab::app::state::Command;
use pushlab::app::state::learning::landscape::{LandscapeCommand, LandscapeResult};
use pushlab_core::inspect::LandscapeFrames;

/// The landscape computed last.
fn landscape<'a>(harness: &'a Harness<'_, PushlabApp>) -> &'a LandscapeResult {
    harness
        .state()
        .state
        .landscape()
        .result()
        .expect("a landscape")
}

/// Waits for the landscape of the frame shown.
fn wait_for_landscape(harness: &mut Harness<'_, PushlabApp>) {
    common::run_until(harness, "the landscape of the frame shown", |app| {
        let state = &app.state;
        !state.landscape().is_running()
            && state
                .landscape()
                .result()
                .is_some_and(|r| r.request.frame == state.frame())
    });
}

/// Every text in the window that starts with `prefix`.
fn texts_starting(harness: &Harness<'_, PushlabApp>, prefix: &str) -> Vec<String> {
    harness
        .query_all_by_label_contains(prefix)
        .filter_map(|node| {
            let node = node.accesskit_node();
            node.label().or_else(|| node.value())
        })
        .filter(|text| text.starts_with(prefix))
        .collect()
}

/// The two millimetre values in "… x = X mm, y = Y mm".
fn xy_mm(text: &str) -> [f64; 2] {
    let number = |after: &str| -> f64 {
        let rest = &text[text.find(after).expect(after) + after.len()..];
        rest.split_whitespace()
            .next()
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("a number after {after:?} in {text:?}"))
    };
    [number("x = "), number("y = ")]
}

#[test]
fn f2_opens_the_landscape_which_marks_theta_the_lowest_cell_and_the_true_com() {
    let mut harness = common::app_on_sample("box1-paper-ur-front");
    common::step_frames(&mut harness, 30);
    assert!(texts_starting(&harness, "θ at frame").is_empty());
    harness.key_press(Key::F2);
    harness.run_steps(2);
    assert!(harness.state().state.landscape().open);
    wait_for_landscape(&mut harness);

    let theta = harness.state().state.theta().expect("a run").com_offset;
    let shown = texts_starting(&harness, "θ at frame 30: COM");
    assert_eq!(shown.len(), 1, "{shown:?}");
    let [x, y] = xy_mm(&shown[0]);
    assert!((x - theta[0] * 1e3).abs() < 0.051 && (y - theta[1] * 1e3).abs() < 0.051);
    assert_eq!(harness.get_all_by_label("θ now").count(), 1, "legend entry");
    // The set's true COM offset (spec: upper right), and the lowest cell inside the object.
    let truth = harness
        .state()
        .state
        .recording()
        .expect("a recording")
        .setting
        .com_offset;
    let truth = truth.expect("a simulated set knows its COM");
    let true_text = texts_starting(&harness, "true COM:");
    assert_eq!(
        xy_mm(&true_text[0]).map(|v| v.round()),
        truth.map(|v| (v * 1e3).round())
    );
    let lowest = xy_mm(&texts_starting(&harness, "lowest cell:")[0]);
    assert!(
        lowest[0].abs() <= 160.0 && lowest[1].abs() <= 210.0,
        "{lowest:?}"
    );
    let result = landscape(&harness);
    // "Last 50" at frame 30: the samples from frames 0 to 30.
    assert_eq!(result.samples, 31);
    assert_eq!(
        texts_starting(&harness, "31 samples from frames 0–30").len(),
        1
    );
}

#[test]
fn the_landscape_follows_the_frame_and_the_frames_chosen() {
    let mut harness = common::app_on_sample("box1-paper-ur-front");
    common::step_frames(&mut harness, 10);
    harness
        .state_mut()
        .state
        .apply(Command::Landscape(LandscapeCommand::Show(true)));
    wait_for_landscape(&mut harness);
    let first = landscape(&harness).generation;
    common::step_frames(&mut harness, 5);
    wait_for_landscape(&mut harness);
    let result = landscape(&harness);
    assert!(result.generation > first);
    assert_eq!(texts_starting(&harness, "θ at frame 15").len(), 1);

    harness.get_by_label("this one").click();
    harness.run_steps(2);
    assert_eq!(
        harness.state().state.landscape().frames,
        LandscapeFrames::ThisFrame
    );
    wait_for_landscape(&mut harness);
    let result = landscape(&harness);
    assert_eq!(result.samples, 1);
    assert_eq!(
        texts_starting(&harness, "1 sample from frame 15 at").len(),
        1
    );
}

#[test]
fn cancel_holds_until_asked_again_and_closing_stops_the_work() {
    let mut harness = common::app_on_sample("box1-paper-ur-front");
    common::step_frames(&mut harness, 10);
    let state = &mut harness.state_mut().state;
    state.apply(Command::Landscape(LandscapeCommand::Show(true)));
    assert!(state.landscape().is_running());
    state.apply(Command::Landscape(LandscapeCommand::Cancel));
    assert!(!state.landscape().is_running() && state.landscape().was_cancelled());
    harness.run_steps(5);
    assert!(harness.state().state.landscape().result().is_none());
    assert!(!harness.state().state.landscape().is_running());
    harness.get_by_label("Compute").click();
    harness.run_steps(1);
    wait_for_landscape(&mut harness);
    assert!(harness.state().state.landscape().result().is_some());

    // F2 again closes the window: nothing more is computed as the frame moves.
    harness.key_press(Key::F2);
    harness.run_steps(1);
    assert!(!harness.state().state.landscape().open);
    common::step_frames(&mut harness, 3);
    assert!(!harness.state().state.landscape().is_running());
    assert!(texts_starting(&harness, "θ at frame").is_empty());
}
