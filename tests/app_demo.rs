//! Demo mode, driven through the UI: every preset of the Demos menu (the experiments of
//! `experiments/sample-data.json`) opens its online set with a model of its offline set — trained in
//! the background the first time, reused after — in the presentation layout; Step learns one frame
//! and the narration says something new. A snapshot of the presentation layout.

use crate::common;

use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use pushlab::app::state::demos::demo::DemoCommand;
use pushlab::app::state::playback::timeline::TimelineCommand;
use pushlab::app::state::{Command, Persisted};
use pushlab::app::{PushlabApp, demo_suite_path, export, initial_state};
use pushlab_core::experiment::split_of;
use pushlab_core::experiment::suite::SuiteSpec;
use pushlab_core::labels::Split;

/// The narration line as the window shows it.
fn narration_shown(harness: &Harness<'_, PushlabApp>) -> String {
    let expected = harness.state().state.narration();
    let shown: Vec<String> = harness
        .query_all_by_label_contains(&expected[..20])
        .filter_map(|node| {
            let node = node.accesskit_node();
            node.label().or_else(|| node.value())
        })
        .collect();
    assert!(
        shown.contains(&expected),
        "the narration {expected:?} is not shown: {shown:?}"
    );
    expected
}

#[test]
fn every_preset_opens_its_online_set_and_step_learns_one_frame() {
    let spec = SuiteSpec::load(&demo_suite_path()).expect("the sample-data suite");
    let mut state = initial_state(&[], Persisted::default());
    state.keep_files_in(Some(common::scratch_dir("demo-app-dir")));
    let mut harness = common::harness(PushlabApp::new(state), 0.05);
    harness.run_steps(2);
    let mut trained_for = Vec::new();
    for experiment in &spec.experiments {
        harness.get_by_label("Demos").click();
        harness.run_steps(2);
        harness.get_by_label(&experiment.name).click();
        harness.run_steps(2);
        assert!(harness.state().view.presentation, "{}", experiment.name);
        // A model is trained once for each offline set and kind (the store keeps both kinds).
        let offline = (experiment.offline.clone(), spec.models_of(experiment)[0]);
        let reused = trained_for.contains(&offline);
        if !reused {
            assert!(
                harness.state().state.training().is_running(),
                "{}: its offline model trains",
                experiment.name
            );
            assert!(narration_shown(&harness).starts_with("Training the offline model"));
            trained_for.push(offline);
        }
        common::run_until(&mut harness, "the demo's model", |app| {
            !app.state.training().is_running()
        });
        let app = harness.state();
        let state = &app.state;
        let store = state
            .model_store()
            .and_then(|p| p.to_str())
            .expect("a model store");
        let demo = state.demos().active.as_ref().expect("a demo");
        assert_eq!(demo.name, experiment.name);
        assert_eq!(
            demo.model.contains("trained before"),
            reused,
            "{}: {}",
            experiment.name,
            demo.model
        );
        assert!(
            state
                .models()
                .source
                .as_deref()
                .is_some_and(|s| s.contains(store)),
            "{}: the model in use is the demo's, {:?}",
            experiment.name,
            state.models().source
        );
        // The recording shown is one of the online set's, in the online split.
        let shown = state.recording().expect("a recording shown");
        let folder = shown
            .source
            .parent()
            .and_then(|p| p.file_name())
            .and_then(|n| n.to_str())
            .expect("a folder");
        assert!(
            experiment.online[0].ends_with(folder),
            "{}: shows {}",
            experiment.name,
            shown.source.display()
        );
        assert_eq!(split_of(shown, None), Some(Split::Online));
        assert_eq!(state.frame(), 0);
        let before = narration_shown(&harness);
        assert!(before.starts_with("Nothing learned yet"), "{before}");

        harness.get_by_label("Step").click();
        harness.run_steps(2);
        let state = &harness.state().state;
        let learned = state.run().and_then(|r| r.mean_losses());
        assert_eq!(learned.map(|l| l.frames), Some(1), "{}", experiment.name);
        let after = narration_shown(&harness);
        assert_ne!(after, before);
        assert!(after.starts_with("After 1 frame learned"), "{after}");
    }
}

/// The preset that shows the weighting: the paper's network, trained on box1, pushes box2, which it
/// never saw. Over the first online push the prediction turns to physics alone for the translation,
/// and the narration says so and why; the weights are the run's (`tests/app_equals_eval.rs`: to
/// the bit `pushlab eval --physics`'s).
#[test]
fn the_papers_network_on_an_object_it_never_saw_turns_to_physics() {
    let name = "R3a objects, the paper's network";
    let mut state = initial_state(&[], Persisted::default());
    state.keep_files_in(Some(common::scratch_dir("demo-trust")));
    let mut harness = common::harness(PushlabApp::new(state), 0.05);
    harness.run_steps(2);
    harness.get_by_label("Demos").click();
    harness.run_steps(2);
    harness.get_by_label(name).click();
    harness.run_steps(2);
    common::run_until(&mut harness, "the demo's model", |app| {
        !app.state.training().is_running()
    });
    let state = &mut harness.state_mut().state;
    assert_eq!(
        state.models().learner_name(),
        "combined model (paper)",
        "{:?}",
        state.status()
    );
    let samples = state.run().expect("a run").sample_count();
    for _ in 0..samples {
        state.apply(Command::Timeline(TimelineCommand::Step(1)));
    }
    harness.run_steps(2);
    let run = harness.state().state.run().expect("a run");
    let weight = run.model_weight().expect("weighed against physics alone");
    let end = weight.at(run.frontier());
    assert!(
        end.pos < 0.5,
        "the translation still trusts the network: {end:?}"
    );
    // Physics took over early: most frames' translation trusted it.
    let physics_frames = (weight.frames().iter())
        .filter(|f| f.weight.pos < 0.5)
        .count();
    assert!(
        physics_frames * 2 > weight.frames().len(),
        "{physics_frames} of {} frames",
        weight.frames().len()
    );
    // And the blend predicted the push's translation better than the network did.
    let frames = weight.frames().len() as f64;
    let weighted = weight.frames().iter().map(|f| f.loss.pos).sum::<f64>() / frames;
    let combined = run.mean_losses().expect("frames learned").online_pos;
    assert!(weighted < combined, "{weighted} against {combined}");
    let narration = narration_shown(&harness);
    assert!(
        narration.contains(&format!(
            "Trusting physics {:.2} for the translation: the network has predicted this object's \
             translation worse than Lynch's model alone over the last 4 s.",
            1.0 - end.pos
        )),
        "{narration}"
    );
}

#[test]
fn f5_leaves_and_enters_the_presentation_layout() {
    let mut harness = common::app_on_sample("box1-paper-lr-front");
    harness.run_steps(2);
    assert!(harness.query_by_label("Step").is_none());
    harness.key_press(eframe::egui::Key::F5);
    harness.run_steps(2);
    assert!(harness.state().view.presentation);
    assert!(harness.query_by_label("Step").is_some());
    harness.key_press(eframe::egui::Key::F5);
    harness.run_steps(2);
    assert!(!harness.state().view.presentation);
    assert!(harness.query_by_label("Step").is_none());
}

/// A class's hidden controls come back from the app itself: the View menu hides the menu bar and
/// the timeline, F10 brings the menu bar back, and a link made meanwhile says what is hidden.
#[test]
fn the_view_menu_hides_the_menu_bar_and_f10_brings_it_back() {
    let mut harness = common::app_on_sample("box1-paper-lr-front");
    harness.run_steps(2);
    harness.get_by_label("View").click();
    harness.run_steps(2);
    harness.get_by_label("Timeline").click();
    harness.run_steps(2);
    assert!(harness.state().view.hide_timeline);
    assert!(
        harness.query_by_label("Play").is_none(),
        "the timeline is hidden"
    );
    // A checkbox leaves the menu open; open it again only if it closed.
    if harness
        .query_by_label_contains("Hide the menu bar")
        .is_none()
    {
        harness.get_by_label("View").click();
        harness.run_steps(2);
    }
    harness.get_by_label_contains("Hide the menu bar").click();
    harness.run_steps(2);
    assert!(
        harness.query_by_label("File").is_none(),
        "the menu bar is hidden"
    );
    assert_eq!(
        harness.state().view.link_part().hide,
        vec!["timeline".to_owned(), "menu".to_owned()]
    );
    harness.key_press(eframe::egui::Key::F10);
    harness.run_steps(2);
    assert!(
        harness.query_by_label("File").is_some(),
        "F10 shows the menu bar again"
    );
    assert!(!harness.state().view.hide_menu);
}

#[test]
fn presentation_layout_snapshot() {
    let spec = SuiteSpec::load(&demo_suite_path()).expect("the sample-data suite");
    let index = spec
        .experiments
        .iter()
        .position(|e| e.name == "R2a COM")
        .expect("R2a in the suite");
    // The bundled model stands in for a model trained before for the offline set, so that the
    // picture does not wait for training.
    let base = demo_suite_path()
        .parent()
        .expect("the suite's folder")
        .to_path_buf();
    let offline = spec.experiments[index].offline_paths(&base)[0]
        .canonicalize()
        .expect("the offline set");
    let model = export::default_model_path().expect("the bundled model");
    let mut persisted = Persisted::default();
    persisted.folder_models.insert(offline, model);
    let mut state = initial_state(&[], persisted);
    state.apply(pushlab::app::state::Command::Demo(DemoCommand::Start(
        index,
    )));
    assert!(!state.training().is_running(), "{:?}", state.status());
    for _ in 0..40 {
        state.apply(pushlab::app::state::Command::Timeline(
            TimelineCommand::Step(1),
        ));
    }
    let mut app = PushlabApp::new(state);
    app.view.presentation = true;
    let mut harness = Harness::builder()
        .with_size([1400.0, 900.0])
        .with_render_cursor(false)
        .build_ui_state(|ui, app: &mut PushlabApp| app.show(ui), app);
    harness.run_steps(3);
    let narration = narration_shown(&harness);
    assert!(
        narration.starts_with("After 40 frames learned"),
        "{narration}"
    );
    harness.snapshot("presentation");
}
