//! The app's online run and `pushlab eval`'s are one: for the same recording, model and settings, θ
//! and the losses at every frame the app plays are those `pushlab eval --json --per-frame` writes, to
//! the bit — with frames labelled bad tracking held over in both.

use crate::common;

use std::path::Path;
use std::process::Command as Process;

use pushlab::app::initial_state;
use pushlab::app::state::playback::timeline::TimelineCommand;
use pushlab::app::state::{Command, OnlineCommand, Persisted, SessionCommand};
use pushlab_core::learn::Nmse;
use pushlab_core::model::FrameLoss;
use serde_json::Value;

const SET: &str = "box1-paper-lr-front";
const RECORDING: &str = "online_002.csv";
/// Frames labelled bad tracking in the copy of the set (half-open).
const BAD_TRACKING: (usize, usize) = (30, 36);

/// Labels the set's copy with a stretch of bad tracking on the recording, keeping its schema.
fn label_bad_tracking(dir: &Path) {
    let path = dir.join("pushlab-labels.json");
    let mut labels: Value =
        serde_json::from_slice(&std::fs::read(&path).expect("labels file")).expect("JSON");
    labels["recordings"][RECORDING]["segments"] = serde_json::json!([
        {"label": "bad tracking", "start": BAD_TRACKING.0, "end": BAD_TRACKING.1}
    ]);
    std::fs::write(&path, serde_json::to_vec_pretty(&labels).expect("JSON")).expect("writes");
}

fn loss(value: &Value) -> Option<FrameLoss> {
    serde_json::from_value(value.clone()).ok()
}

/// Plays the recording shown to its end, learning as it goes.
fn play_to_end(state: &mut pushlab::app::state::AppState) {
    let frames = state.recording().expect("a recording").trajectory.len();
    for _ in 0..frames {
        state.apply(Command::Timeline(TimelineCommand::Step(1)));
    }
}

/// Runs `pushlab eval --per-frame` with `model` on the offline folder and the online files, plus
/// `extra` arguments, writing `json`: its standard output and the report.
fn eval_per_frame(
    model: &Path,
    offline: &Path,
    online: &[std::path::PathBuf],
    json: &Path,
    extra: &[&str],
) -> (String, Value) {
    let output = Process::new(env!("CARGO_BIN_EXE_pushlab"))
        .args(["eval", "--per-frame", "--model"])
        .arg(model)
        .arg("--offline")
        .arg(offline)
        .arg("--online")
        .args(online)
        .arg("--json")
        .arg(json)
        .args(extra)
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

/// Asserts that θ at frame `k` of the report's `frame` is the app's θ at `k`, bit for bit.
fn assert_theta_is_reported(frame: &Value, theta: pushlab_core::model::OnlineParams, k: usize) {
    let bits = |v: &Value| v.as_f64().expect("a number").to_bits();
    assert_eq!(bits(&frame["theta"]["h"]), theta.h.to_bits(), "h at {k}");
    for (c, value) in theta.com_offset.iter().enumerate() {
        assert_eq!(
            bits(&frame["theta"]["com_offset"][c]),
            value.to_bits(),
            "COM offset {c} at {k}"
        );
    }
}

#[test]
fn the_apps_theta_and_losses_at_every_frame_are_pushlab_evals_to_the_bit() {
    let dir = common::copy_of_sample_set(SET, "app-equals-eval");
    label_bad_tracking(&dir);
    let csv = dir.join(RECORDING);
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/default-model.json");

    // The app, opened on the recording with the bundled default model and default settings, plays
    // it to the end learning as it goes.
    let mut state = initial_state(std::slice::from_ref(&csv), Persisted::default());
    play_to_end(&mut state);
    let run = state.run().expect("an online run");
    assert_eq!(run.frontier(), run.sample_count(), "played to the end");

    // `pushlab eval` on the same recording and model, default settings.
    let json = dir.join("eval.json");
    let (_, report) = eval_per_frame(
        &model,
        &dir,
        std::slice::from_ref(&csv),
        &json,
        &["--physics"],
    );
    let trajectories = report["trajectories"].as_array().expect("trajectories");
    assert_eq!(trajectories.len(), 1);
    let reported = trajectories[0]["frames"]
        .as_array()
        .expect("per-frame output");
    assert_eq!(reported.len(), run.sample_count());

    let mut held = 0;
    for (k, frame) in reported.iter().enumerate() {
        assert_theta_is_reported(frame, run.theta_at(k), k);
        let online = run.learned()[k];
        assert_eq!(loss(&frame["online"]), online, "online loss at {k}");
        assert_eq!(
            loss(&frame["fixed"]),
            Some(run.fixed()[k]),
            "fixed loss at {k}"
        );
        held += usize::from(online.is_none());
    }
    // Horizon 10: a sample from frame k ends at k + 10, so those starting in the labelled stretch and
    // those ending in it are held — two stretches of six frames.
    assert_eq!(held, 2 * (BAD_TRACKING.1 - BAD_TRACKING.0));
    assert_weighed_as_reported(run, &report["physics_trajectories"][0]);
    std::fs::remove_dir_all(&dir).ok();
}

/// Asserts that physics alone learned beside the app's run as `eval --physics` learned it, and
/// that the weights and the weighted NMSE are the report's, bit for bit.
fn assert_weighed_as_reported(run: &pushlab_core::learn::OnlineRun, reported: &Value) {
    let bits = |v: &Value| v.as_f64().expect("a number").to_bits();
    let physics = run
        .physics_beside()
        .expect("physics alone learns beside the run");
    let theta = physics.theta_at(physics.frontier());
    assert_eq!(bits(&reported["h_learned"]), theta.h.to_bits());
    let weight = run.model_weight().expect("the weights");
    let weighted = Nmse::of_frames(weight.frames().iter().map(|f| f.loss));
    assert_eq!(bits(&reported["weighted"]["pos"]), weighted.pos.to_bits());
    assert_eq!(bits(&reported["weighted"]["rot"]), weighted.rot.to_bits());
    let end = weight.weight();
    assert_eq!(bits(&reported["weight_end"]["pos"]), end.pos.to_bits());
    assert_eq!(bits(&reported["weight_end"]["rot"]), end.rot.to_bits());
}

#[test]
fn carrying_theta_to_the_next_push_is_pushlab_eval_carry_theta_to_the_bit() {
    let dir = common::copy_of_sample_set(SET, "app-carry-theta");
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/default-model.json");
    let settings = Persisted {
        carry_theta: true,
        ..Persisted::default()
    };
    let mut state = initial_state(std::slice::from_ref(&dir), settings);
    let id_of = |state: &pushlab::app::state::AppState, name: &str| {
        state
            .session()
            .recordings()
            .find(|(_, r)| r.name == name)
            .map(|(id, _)| id)
            .unwrap_or_else(|| panic!("{name} is open"))
    };
    let (first, second) = (id_of(&state, "online_001"), id_of(&state, "online_002"));
    state.apply(Command::Session(SessionCommand::Select(first)));
    play_to_end(&mut state);
    let first_end = state.run().expect("a run").end_state();
    state.apply(Command::Session(SessionCommand::Select(second)));
    let run = state.run().expect("a run");
    assert_eq!(run.continued_from(), Some("online_001"));
    assert_eq!(
        run.theta_at(0),
        first_end.theta,
        "goes on from the first push's θ"
    );
    play_to_end(&mut state);

    let json = dir.join("eval.json");
    let online = [dir.join("online_001.csv"), dir.join("online_002.csv")];
    let (stdout, report) = eval_per_frame(
        &model,
        &dir,
        &online,
        &json,
        &["--carry-theta", "--physics"],
    );
    assert!(
        stdout.contains("--carry-theta: 1 of 2 trajectories went on from the one before them"),
        "{stdout}"
    );
    assert_eq!(report["config"]["carry_theta"], Value::Bool(true));
    let second_report = &report["trajectories"][1];
    assert_eq!(second_report["continued"], Value::Bool(true));
    let reported = second_report["frames"]
        .as_array()
        .expect("per-frame output");
    let run = state.run().expect("a run");
    assert_eq!(reported.len(), run.sample_count());
    for (k, frame) in reported.iter().enumerate() {
        assert_theta_is_reported(frame, run.theta_at(k), k);
    }
    // The weights went on from the first push's too.
    assert_weighed_as_reported(run, &report["physics_trajectories"][1]);

    // Switched off, the next push starts from θ_online(0) again.
    state.apply(Command::Online(OnlineCommand::SetCarryTheta(false)));
    state.apply(Command::Session(SessionCommand::Select(first)));
    let run = state.run().expect("a run");
    assert_eq!(run.continued_from(), None);
    assert_eq!(run.theta_at(0), run.theta0());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_steer_tabs_best_theta_is_pushlab_eval_best_fit_to_the_bit_and_steers_there() {
    use pushlab::app::state::learning::best_fit::BestFitCommand;
    let dir = common::copy_of_sample_set(SET, "app-best-fit");
    label_bad_tracking(&dir);
    let csv = dir.join(RECORDING);
    let model = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/default-model.json");
    let mut state = initial_state(std::slice::from_ref(&csv), Persisted::default());
    state.apply(Command::BestFit(BestFitCommand::Find));
    let mut waited = 0;
    while state.advance(0.0)
        && (state.run()).is_some_and(|run| state.best_fit().progress_for(run).is_some())
    {
        std::thread::sleep(std::time::Duration::from_millis(20));
        waited += 1;
        assert!(waited < 3000, "the best θ took over a minute");
    }
    let run = state.run().expect("a run");
    let fit = (state.best_fit().result_for(run))
        .and_then(|r| r.fit)
        .expect("a best fit for the run shown");

    let json = dir.join("eval.json");
    let (stdout, report) = eval_per_frame(
        &model,
        &dir,
        std::slice::from_ref(&csv),
        &json,
        &["--best-fit"],
    );
    assert!(
        stdout.contains("Best θ per push (the whole push"),
        "{stdout}"
    );
    let reported = &report["trajectories"][0]["best_fit"];
    assert_theta_is_reported(reported, fit.theta, 0);
    // Frames labelled bad tracking are left out of both: two stretches of six samples at horizon 10.
    assert_eq!(reported["samples"], run.sample_count() - 12);
    assert_eq!(fit.samples, run.sample_count() - 12);

    // "Use it here" steers θ at the frame shown to it.
    state.apply(Command::Online(OnlineCommand::SetTheta(fit.theta)));
    assert_eq!(state.theta(), Some(fit.theta));
    std::fs::remove_dir_all(&dir).ok();
}
