//! The Steer tab's "Next push that teaches the most" is `pushlab suggest`'s ranking to the bit: the
//! same candidates (the object's other open pushes, or with none open the default grid), the same
//! order and the same expected COM σ, ranked after the push the app learned to its end and
//! `--after` that push.

use std::path::Path;
use std::process::Command as Process;

use pushlab::app::initial_state;
use pushlab::app::state::AppState;
use pushlab::app::state::learning::next_push::{Candidates, NextPushCommand, NextPushResult};
use pushlab::app::state::playback::timeline::TimelineCommand;
use pushlab::app::state::{Command, Persisted};
use serde_json::Value;

use crate::common;

/// Steps the recording shown to its last frame, learning each.
fn play_to_end(state: &mut AppState) {
    let frames = state.recording().expect("a recording").trajectory.len();
    for _ in 0..frames {
        state.apply(Command::Timeline(TimelineCommand::Step(1)));
    }
}

/// Asks for the next pushes and waits (a minute at most) for the ranking to end.
fn rank_next_pushes(state: &mut AppState) {
    state.apply(Command::NextPush(NextPushCommand::Suggest));
    let mut waited = 0;
    while state.advance(0.0)
        && (state.run()).is_some_and(|run| state.next_push().progress_for(run).is_some())
    {
        std::thread::sleep(std::time::Duration::from_millis(20));
        waited += 1;
        assert!(waited < 3000, "the ranking took over a minute");
    }
}

/// The ranking the run shown has.
fn ranking_of(state: &AppState) -> &NextPushResult {
    let run = state.run().expect("a run");
    state.next_push().result_for(run).expect("a ranking")
}

/// Runs `pushlab suggest PATH ARGS --json JSON`: its standard output and the report.
fn suggest_json(path: &Path, args: &[&str], json: &Path) -> (String, Value) {
    let output = Process::new(env!("CARGO_BIN_EXE_pushlab"))
        .arg("suggest")
        .arg(path)
        .args(args)
        .arg("--json")
        .arg(json)
        .output()
        .expect("runs pushlab");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let report = serde_json::from_slice(&std::fs::read(json).expect("report")).expect("JSON");
    (String::from_utf8_lossy(&output.stdout).into_owned(), report)
}

/// Asserts that the report's ranking is the app's, bit for bit: the σ now, and each suggestion's
/// name and σ after, in order.
fn assert_reported(result: &NextPushResult, report: &Value) {
    let reported = report["ranking"]["suggestions"].as_array().expect("a list");
    assert_eq!(reported.len(), result.ranking.suggestions.len());
    let bits = |v: &Value| v.as_f64().expect("a number").to_bits();
    assert_eq!(
        bits(&report["ranking"]["com_std_now_m"]),
        result.ranking.com_std_now_m.to_bits()
    );
    for (app, cli) in result.ranking.suggestions.iter().zip(reported) {
        assert_eq!(cli["name"], Value::from(app.name.as_str()));
        assert_eq!(bits(&cli["com_std_after_m"]), app.com_std_after_m.to_bits());
    }
}

#[test]
fn the_steer_tabs_next_pushes_are_pushlab_suggests_to_the_bit() {
    let dir = common::copy_of_sample_set("box1-paper-lr-front", "app-next-push");
    let mut state = initial_state(std::slice::from_ref(&dir), Persisted::default());
    let shown = state.recording().expect("a recording").name.clone();
    play_to_end(&mut state);
    let candidates = state.other_pushes_of_object().len();
    assert_eq!(candidates, 35, "the set's other pushes");
    rank_next_pushes(&mut state);
    let result = ranking_of(&state);
    assert_eq!(result.frame, state.run().expect("a run").frontier());
    assert_eq!(result.ranking.suggestions.len(), candidates);

    let (stdout, report) = suggest_json(&dir, &["--after", &shown], &dir.join("suggest.json"));
    assert!(
        stdout.contains(&format!("after {shown}: COM σ now")),
        "{stdout}"
    );
    assert_reported(result, &report);
    // The best push is not the one just learned, and teaches more than the worst.
    let best = &result.ranking.suggestions[0];
    assert_ne!(best.name, shown);
    assert!(best.com_std_after_m < result.ranking.suggestions[candidates - 1].com_std_after_m);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_best_next_pushes_are_drawn_as_numbered_arrows_and_listed_in_the_steer_tab() {
    use egui_kittest::Harness;
    use egui_kittest::kittest::Queryable;
    use pushlab::app::PushlabApp;
    let app = PushlabApp::new(initial_state(&[], Persisted::default()));
    let mut harness = Harness::builder()
        .with_size([1400.0, 900.0])
        .with_render_cursor(false)
        .build_ui_state(|ui, app: &mut PushlabApp| app.show(ui), app);
    harness.run_steps(2);
    let state = &mut harness.state_mut().state;
    for _ in 0..4 {
        state.apply(Command::Timeline(TimelineCommand::Step(10)));
    }
    rank_next_pushes(state);
    harness.run_steps(3);
    let ranking = ranking_of(&harness.state().state).ranking.clone();
    let best = &ranking.suggestions[0];
    harness.get_by_label("Next push that teaches the most");
    // The best push's row: its name (also in the browser) and the σ it leaves.
    assert!(harness.get_all_by_label(&best.name).count() >= 2);
    let leaves = format!("leaves COM σ {:.1} mm", best.com_std_after_m * 1e3);
    assert!(
        harness.get_all_by_label(&leaves).next().is_some(),
        "{leaves}"
    );
    harness.snapshot("next_pushes");
}

#[test]
fn with_no_other_push_open_the_steer_tab_ranks_pushlab_suggests_grid_to_the_bit() {
    let dir = common::copy_of_sample_set("box1-paper-lr-front", "app-next-push-grid");
    let csv = dir.join("online_003.csv");
    let mut state = initial_state(std::slice::from_ref(&csv), Persisted::default());
    assert!(state.other_pushes_of_object().is_empty());
    play_to_end(&mut state);
    rank_next_pushes(&mut state);
    let result = ranking_of(&state);
    assert!(matches!(
        &result.candidates,
        Candidates::Grid { left_out } if left_out.is_empty()
    ));
    assert_eq!(
        result.ranking.suggestions.len(),
        36,
        "4 sides × 3 offsets × 3 angles"
    );
    let args = ["--grid", "--after", "online_003"];
    let (_, report) = suggest_json(&csv, &args, &dir.join("suggest-grid.json"));
    assert_reported(result, &report);
    std::fs::remove_dir_all(&dir).ok();
}
