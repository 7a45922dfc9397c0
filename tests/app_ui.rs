//! The desktop app driven headlessly through its accessibility tree, as a user would: by the labels of
//! its buttons and sliders. Each test opens the bundled sample data like `cargo run` does.

use crate::common;
use crate::skip;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT as _, Queryable, by};
use pushlab::app::state::models::Models;
use pushlab::app::state::{AppState, Persisted};
use pushlab::app::state::{OnlineCommand, SessionCommand};
use pushlab::app::{PushlabApp, initial_state};

/// The app on the sample data in a 1400×900 window. Like `App::logic`, each frame first advances time
/// by the frame's `dt`, then draws.
fn app() -> Harness<'static, PushlabApp> {
    let app = PushlabApp::new(initial_state(&[], Persisted::default()));
    assert!(
        app.state.session().recording_count() > 0,
        "the sample data did not open: {:?}",
        app.state.session().problems
    );
    common::harness(app, 0.05)
}

/// Seeks with the scrub slider to the middle of the push, then steps forward until the pusher is in
/// contact (the model's gradient is non-zero), as a user would look for a frame with a push.
fn go_to_a_pushing_frame(harness: &mut Harness<'_, PushlabApp>) {
    let middle = harness.state().state.timeline().len() / 2;
    harness
        .get_by_role_and_label(egui::accesskit::Role::Slider, "Frame")
        .set_value_accesskit(middle as f64);
    harness.run_steps(1);
    assert_eq!(harness.state().state.frame(), middle);
    for _ in 0..200 {
        let step = harness
            .state()
            .state
            .current_step()
            .expect("frame has a sample");
        let moving = step
            .prediction
            .motion
            .translation
            .iter()
            .any(|d| d.abs() > 1e-9);
        if moving && step.gradient.iter().any(|g| g.abs() > 1e-9) {
            return;
        }
        harness.get_by_label("+1").click();
        harness.run_steps(1);
    }
    panic!("no frame with the pusher in contact after the middle of the push");
}

fn theta(harness: &Harness<'_, PushlabApp>) -> [f64; 3] {
    harness
        .state()
        .state
        .theta()
        .expect("a recording is selected")
        .to_array()
}

#[test]
fn opening_the_sample_data_lists_its_recordings_and_selects_the_first() {
    let mut harness = app();
    harness.run_steps(2);
    let state = &harness.state().state;
    assert!(
        state.session().problems.is_empty(),
        "{:?}",
        state.session().problems
    );
    let first = state.recording().expect("first recording selected");
    let name = first.name.clone();
    let setting = first.setting.name.clone();
    assert!(
        harness.query_all_by_label_contains(&name).next().is_some(),
        "browser lists {name}"
    );
    assert!(
        harness
            .query_all_by_label_contains(&setting)
            .next()
            .is_some(),
        "browser lists {setting}"
    );
}

#[test]
fn a_recording_selected_from_elsewhere_is_scrolled_into_sight_in_the_table() {
    let mut harness = app();
    harness.run_steps(2);
    let state = &harness.state().state;
    // The last row of the table as sorted, far below the rows in sight (only those are built).
    let last = *state.browser_shown().last().expect("rows");
    let name = state.session().get(last).expect("open").name.clone();
    let sibling_count = |h: &Harness<'_, PushlabApp>| h.query_all_by_label(&name).count();
    let before = sibling_count(&harness);
    // Selected as a link, a drop or a demo selects it: not by a click in the table.
    harness
        .state_mut()
        .state
        .apply(pushlab::app::state::Command::Session(
            SessionCommand::Select(last),
        ));
    harness.run_steps(3);
    assert!(
        sibling_count(&harness) > before,
        "{name}, the last of {} rows, is drawn in the table once selected",
        harness.state().state.browser_shown().len()
    );
}

#[test]
fn play_advances_frames_and_pause_stops_them() {
    let mut harness = app();
    harness.run_steps(1);
    harness.get_by_label("Play").click();
    harness.run_steps(10);
    let frame = harness.state().state.frame();
    assert!(frame > 0, "still at frame 0 after 0.5 s of playing");
    harness.get_by_label("Pause").click();
    harness.run_steps(1);
    let paused_at = harness.state().state.frame();
    harness.run_steps(10);
    assert_eq!(harness.state().state.frame(), paused_at);
}

#[test]
fn step_buttons_and_keys_move_exactly_one_or_ten_frames() {
    let mut harness = app();
    harness.run_steps(1);
    harness.get_by_label("+1").click();
    harness.run_steps(1);
    assert_eq!(harness.state().state.frame(), 1);
    harness.get_by_label("+10").click();
    harness.run_steps(1);
    assert_eq!(harness.state().state.frame(), 11);
    harness.key_press(egui::Key::ArrowLeft);
    harness.run_steps(1);
    assert_eq!(harness.state().state.frame(), 10);
    harness.key_press_modifiers(egui::Modifiers::SHIFT, egui::Key::ArrowRight);
    harness.run_steps(1);
    assert_eq!(harness.state().state.frame(), 20);
    harness.key_press(egui::Key::Home);
    harness.run_steps(1);
    assert_eq!(harness.state().state.frame(), 0);
    harness.key_press(egui::Key::Space);
    harness.run_steps(1);
    assert!(harness.state().state.timeline().playing);
}

#[test]
fn learn_this_frame_changes_theta_and_lowers_the_loss() {
    let mut harness = app();
    harness.run_steps(1);
    go_to_a_pushing_frame(&mut harness);
    let before_theta = theta(&harness);
    let before_loss = harness
        .state()
        .state
        .current_step()
        .expect("frame 10 has a sample")
        .loss;
    harness.get_by_label("Learn this frame").click();
    harness.run_steps(1);
    let after_theta = theta(&harness);
    let after_loss = harness
        .state()
        .state
        .current_step()
        .expect("frame 10 has a sample")
        .loss;
    assert_ne!(before_theta, after_theta);
    assert!(
        after_loss.total() < before_loss.total(),
        "loss {} → {}",
        before_loss.total(),
        after_loss.total()
    );
}

#[test]
fn moving_the_h_slider_changes_the_prediction() {
    let mut harness = app();
    harness.run_steps(1);
    go_to_a_pushing_frame(&mut harness);
    let before = harness
        .state()
        .state
        .current_step()
        .expect("sample")
        .prediction;
    let h = theta(&harness)[2];
    harness
        .get_by_role_and_label(egui::accesskit::Role::Slider, "h")
        .set_value_accesskit(h * 1e3 * 0.5);
    harness.run_steps(1);
    let after_h = theta(&harness)[2];
    // The slider shows and sets h to 0.01 mm.
    assert!((after_h - h * 0.5).abs() < 1e-5, "h {h} → {after_h}");
    let after = harness
        .state()
        .state
        .current_step()
        .expect("sample")
        .prediction;
    assert_ne!(
        before.motion, after.motion,
        "halving h did not change the prediction"
    );
}

#[test]
fn scrubbing_back_restores_the_earlier_theta() {
    let mut harness = app();
    harness.run_steps(1);
    assert!(
        harness.state().state.settings().learn_while_playing,
        "learning while playing is on by default"
    );
    for _ in 0..3 {
        harness.get_by_label("+10").click();
        harness.run_steps(1);
    }
    let at_30 = theta(&harness);
    for _ in 0..3 {
        harness.get_by_label("+10").click();
        harness.run_steps(1);
    }
    let at_60 = theta(&harness);
    assert_ne!(at_30, at_60, "θ did not learn between frames 30 and 60");
    harness.key_press_modifiers(egui::Modifiers::SHIFT, egui::Key::ArrowLeft);
    harness.key_press_modifiers(egui::Modifiers::SHIFT, egui::Key::ArrowLeft);
    harness.key_press_modifiers(egui::Modifiers::SHIFT, egui::Key::ArrowLeft);
    harness.run_steps(1);
    assert_eq!(harness.state().state.frame(), 30);
    assert_eq!(theta(&harness), at_30);
    // Replaying re-learns to exactly the same θ.
    harness.get_by_label("+10").click();
    harness.get_by_label("+10").click();
    harness.get_by_label("+10").click();
    harness.run_steps(1);
    assert_eq!(theta(&harness), at_60);
}

#[test]
fn every_slider_and_checkbox_has_an_accessible_name() {
    let mut harness = app();
    harness.run_steps(2);
    for role in [
        egui::accesskit::Role::Slider,
        egui::accesskit::Role::CheckBox,
    ] {
        for node in harness.query_all(by().role(role)) {
            let label = node.accesskit_node().label().unwrap_or_default().to_owned();
            assert!(!label.trim().is_empty(), "a {role:?} without a name");
        }
    }
}

#[test]
fn the_layout_holds_still_while_nothing_happens() {
    // The plots panel once took its content's height, which was a few points short, so it shrank
    // every frame and the scene grew under the user's pointer.
    let mut harness = app();
    harness.run_steps(2);
    let scene = harness.state().view.scene.rect();
    let plots = harness.state().view.plots_rect;
    harness.run_steps(30);
    assert_eq!(harness.state().view.scene.rect(), scene);
    assert_eq!(harness.state().view.plots_rect, plots);
    assert!(
        plots.height() > 300.0,
        "plots keep their default height: {plots:?}"
    );
}

/// The app's online run on the real MIT pushes (skipped with a message when `../shared/mit-push/`
/// is absent) at learning rates 10 and 10⁶, for the default `contact` model, a `paper` model and
/// physics only: every θ it keeps, every loss it plots and the Inspect tab's gradient stay finite.
#[test]
fn no_model_learns_a_non_finite_theta_or_loss_in_the_app_at_lr_10_and_1e6_on_real_pushes() {
    use pushlab::app::state::Command;
    use pushlab::app::state::playback::timeline::TimelineCommand;
    use pushlab_core::learn::{OnlineConfig, TrainConfig};
    use pushlab_core::model::ModelKind;
    use pushlab_core::model_file::ModelFile;

    let Some(dir) = skip::shared(std::path::Path::new(env!("CARGO_MANIFEST_DIR")), "mit-push")
    else {
        return;
    };
    let loaded = pushlab_core::experiment::load(std::slice::from_ref(&dir), None, 10);
    let no = std::sync::atomic::AtomicBool::new(false);
    let config = TrainConfig {
        epochs: 1,
        horizon: 10,
        ..TrainConfig::default()
    };
    let paper = pushlab_core::experiment::train_combined(
        ModelKind::Paper,
        &loaded.used,
        &config,
        &mut |_| {},
        &no,
    )
    .expect("trains")
    .model;
    for model in ["contact", "paper", "physics only"] {
        let mut state = initial_state(std::slice::from_ref(&dir), Persisted::default());
        match model {
            "paper" => state.use_model_file(
                ModelFile {
                    combined: paper.clone(),
                    pure_nn: None,
                    training: Default::default(),
                },
                "paper".into(),
            ),
            "physics only" => {
                // As the app starts without a model file: no combined model.
                state = AppState::new(Persisted::default(), Models::default());
                state.open_blocking(std::slice::from_ref(&dir));
            }
            _ => {}
        }
        let ids: Vec<_> = state.session().recordings().map(|(id, _)| id).collect();
        assert_eq!(ids.len(), 4, "{:?}", state.session().problems);
        for id in ids {
            state.apply(Command::Session(SessionCommand::Select(id)));
            for lr in [10.0, 1e6] {
                state.apply(Command::Online(OnlineCommand::SetConfig(OnlineConfig {
                    steps: 5,
                    lr,
                    ..OnlineConfig::default()
                })));
                state.apply(Command::Timeline(TimelineCommand::SeekTo(0)));
                state.apply(Command::Online(OnlineCommand::ResetTheta));
                let what = format!(
                    "{model} at lr {lr} on {:?}",
                    state.recording().map(|r| &r.source)
                );
                let frames = state.run().expect("an online run").sample_count();
                for _ in 0..frames {
                    state.apply(Command::Timeline(TimelineCommand::Step(1)));
                    let step = state.current_step();
                    assert!(
                        step.is_none_or(|s| s.gradient.iter().all(|g| g.is_finite())),
                        "{what}: the Inspect tab's gradient {step:?}"
                    );
                }
                let run = state.run().expect("an online run");
                assert!(
                    run.frontier() + 1 >= frames,
                    "{what}: learned {}",
                    run.frontier()
                );
                for (k, theta) in run.checkpoints().iter().enumerate() {
                    assert!(
                        theta.com_offset.iter().all(|c| c.is_finite()) && theta.h.is_finite(),
                        "{what}: θ at frame {k} {theta:?}"
                    );
                }
                let losses = run.learned().iter().flatten().chain(run.fixed());
                for loss in losses {
                    assert!(
                        loss.pos.is_finite() && loss.rot.is_finite(),
                        "{what}: {loss:?}"
                    );
                }
            }
        }
    }
}
