//! The app's longer workflows, driven through the UI: drag-and-drop opening, offline training in the
//! background with progress and cancel, and the files the app exports (losses CSV, PNG regions,
//! model files, labels). The native rfd dialogs themselves cannot run headless; these tests call what
//! each dialog's answer triggers.

use crate::common;

use std::path::{Path, PathBuf};

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use pushlab::app::dialogs::{DialogResult, LabelExportFormat};
use pushlab::app::state::models::training::RunEnd;
use pushlab::app::state::recordings::session::RecordingId;
use pushlab::app::state::{Command, Persisted, TrainingCommand};
use pushlab::app::{PushlabApp, export, initial_state};
use pushlab_core::learn::TrainConfig;

/// A file dropped on the window, as the native integration hands it over.
#[derive(Debug)]
struct Dropped(PathBuf);

impl egui::DroppedFile for Dropped {
    fn path(&self) -> &Path {
        &self.0
    }

    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|e| e.to_string())
    }
}

fn app_on(paths: &[PathBuf]) -> Harness<'static, PushlabApp> {
    let app = PushlabApp::new(initial_state(paths, Persisted::default()));
    let mut harness = common::harness(app, 0.05);
    harness.run_steps(2);
    harness
}

#[test]
fn dropping_a_folder_opens_it_and_a_bad_file_is_reported_without_closing_anything() {
    let (first, second) = (
        common::sample_dir("box1-paper-center-front"),
        common::sample_dir("box2-plastic-center-front"),
    );
    let mut harness = app_on(std::slice::from_ref(&first));
    let before = harness.state().state.session().recording_count();
    assert!(before > 0);

    let scratch = common::scratch_dir("drop");
    let bad = scratch.join("not-a-push.csv");
    std::fs::write(&bad, "time,robot_x\n0.0,banana\n").expect("write bad file");
    for path in [second.clone(), bad.clone()] {
        harness
            .input_mut()
            .dropped_files
            .push(std::sync::Arc::new(Dropped(path)));
    }
    harness.run_steps(1);
    common::run_until(&mut harness, "the dropped paths to load", |app| {
        app.state.session().loading().is_none()
    });

    let state = &harness.state().state;
    assert!(
        state.session().recording_count() > before,
        "the dropped folder added recordings"
    );
    assert_eq!(
        state.session().selected,
        Some(RecordingId {
            set: 1,
            recording: 0
        }),
        "what was dropped is shown: the dropped folder's first push"
    );
    assert!(
        state
            .session()
            .problems
            .iter()
            .any(|p| p.path == bad && p.message.contains("not-a-push.csv")),
        "{:?}",
        state.session().problems
    );
    assert!(
        harness
            .state()
            .state
            .browser_rows()
            .iter()
            .any(|r| r.set == "box2-plastic-center-front"),
        "the browser lists the dropped set"
    );
    assert!(
        harness
            .query_all_by_label_contains(&format!("{0} of {0} recordings", 36 * 2))
            .next()
            .is_some(),
        "the browser counts the dropped set's recordings"
    );
    assert!(
        harness
            .query_all_by_label_contains("not-a-push.csv")
            .next()
            .is_some(),
        "the browser shows the load error by file name"
    );
    assert!(
        harness
            .query_all_by_label_contains("recordings; 1 file could not be read")
            .next()
            .is_some(),
        "the status line sums up the load"
    );
    let _ = std::fs::remove_dir_all(&scratch);
}

#[test]
fn training_in_the_app_runs_in_the_background_and_replaces_the_model() {
    let set = common::sample_dir("box1-paper-center-front");
    let mut harness = app_on(std::slice::from_ref(&set));
    let fixed_before = harness
        .state()
        .state
        .run()
        .as_ref()
        .expect("an online run")
        .fixed()[10]
        .pos;
    harness.get_by_label("Train").click();
    harness.run_steps(2);
    // The tab starts from the model in use: the bundled model's horizon (10 frames), not 1.
    let horizon_in_use = harness.state().state.models().horizon();
    assert_eq!(horizon_in_use, 10);
    assert_eq!(
        harness
            .get_by_role_and_label(egui::accesskit::Role::SpinButton, "Horizon (frames)")
            .value()
            .as_deref(),
        Some("10")
    );
    harness.get_by_label("Labelled offline").click();
    harness.run_steps(2);
    assert_eq!(harness.state().state.training().chosen.len(), 27);
    harness
        .get_by_role_and_label(egui::accesskit::Role::SpinButton, "Epochs")
        .set_value_accesskit(3.0);
    harness.run_steps(2);
    assert_eq!(harness.state().state.training().config.epochs, 3);
    harness
        .query_all_by_label("Train")
        .last()
        .expect("the Train button")
        .click();
    harness.run_steps(1);
    assert!(harness.state().state.training().is_running());
    common::run_until(&mut harness, "training to finish", |app| {
        !app.state.training().is_running()
    });

    let state = &harness.state().state;
    let status = state.status().unwrap_or_default().to_owned();
    assert!(
        status.contains("training the contact model finished after 3 epochs"),
        "{status}"
    );
    assert_eq!(
        state.models().kind(),
        Some(pushlab_core::model::ModelKind::Contact),
        "the Train tab trains the default kind"
    );
    assert_eq!(
        state.training().history.len(),
        3,
        "one progress report per epoch"
    );
    assert_eq!(
        state.models().source.as_deref(),
        Some("trained in the app, not saved")
    );
    assert_eq!(
        state.models().horizon(),
        horizon_in_use,
        "pressing Train with the tab's defaults keeps the horizon of the model it replaces"
    );
    let fixed_after = state.run().expect("an online run").fixed()[10].pos;
    assert_ne!(
        fixed_before, fixed_after,
        "predictions come from the new model"
    );
    // The bar says which epoch's weights the model has, the one with the best validation loss.
    let Some(RunEnd::Trained { report, .. }) = state.training().last_end() else {
        panic!("the run's report")
    };
    let losses: Vec<f64> = (state.training().history.iter())
        .filter_map(|p| p.validation_loss)
        .collect();
    let best = (losses.iter().enumerate())
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map(|(i, _)| i + 1)
        .expect("validation losses");
    assert_eq!(report.best_epoch, best);
    let said = format!("finished after 3 of 3 epochs; kept epoch {best}");
    assert!(
        harness.query_all_by_label_contains(&said).next().is_some(),
        "the progress bar says how the run ended: {said}"
    );

    // Save it from the app and load it back: same predictions.
    let scratch = common::scratch_dir("train");
    let model = scratch.join("model.json");
    harness
        .state()
        .state
        .save_model(&model)
        .expect("save model");
    let mut state = initial_state(std::slice::from_ref(&set), Persisted::default());
    state.load_model(&model).expect("load model");
    state.restart_run_keeping_frame();
    let reloaded = state.run().expect("an online run").fixed()[10].pos;
    assert_eq!(reloaded, fixed_after);
    let _ = std::fs::remove_dir_all(&scratch);
}

#[test]
fn a_refused_model_file_keeps_the_current_model_and_the_status_says_why() {
    let set = common::sample_dir("box1-paper-center-front");
    let mut harness = app_on(std::slice::from_ref(&set));
    let (source, combined) = {
        let models = &harness.state().state.models();
        (models.source.clone(), models.combined.clone())
    };
    assert!(
        source
            .as_deref()
            .is_some_and(|s| s.ends_with("default-model.json")),
        "{source:?}"
    );
    let text = std::fs::read_to_string(export::default_model_path().expect("bundled model"))
        .expect("readable");
    let scratch = common::scratch_dir("bad-model");
    let ctx = harness.ctx.clone();
    for (pointer, why) in [
        (
            "/combined/loss_scale/sigma_rot",
            "combined.loss_scale.sigma_rot: must be > 0, found 0",
        ),
        (
            "/combined/horizon",
            "combined.horizon: must be at least 1 frame, found 0",
        ),
    ] {
        let mut json: serde_json::Value = serde_json::from_str(&text).expect("json");
        *json.pointer_mut(pointer).expect("field") = serde_json::json!(0);
        let bad = scratch.join("bad.json");
        std::fs::write(&bad, json.to_string()).expect("write");
        harness
            .state_mut()
            .apply_dialog_result(&ctx, DialogResult::LoadModel(bad.clone()));
        harness.run_steps(2);
        let state = &harness.state().state;
        assert_eq!(state.models().source, source);
        assert!(state.models().combined == combined, "the model changed");
        let expected = format!(
            "model not loaded, the combined model (contact) stays in use: {}: {why}",
            bad.display()
        );
        let status = state.status().unwrap_or_default().to_owned();
        assert_eq!(status, expected);
        assert!(
            harness.query_all_by_label_contains(why).next().is_some(),
            "the status line shows why"
        );
    }
    let _ = std::fs::remove_dir_all(&scratch);
}

#[test]
fn cancelling_training_stops_early_and_keeps_the_best_model_so_far() {
    let set = common::sample_dir("box1-paper-center-front");
    let mut harness = app_on(std::slice::from_ref(&set));
    harness.get_by_label("Train").click();
    harness.run_steps(2);
    harness.get_by_label("All").click();
    harness.run_steps(2);
    let config = TrainConfig {
        epochs: 10_000,
        patience: 0,
        ..harness.state().state.training().config
    };
    (harness.state_mut().state).apply(Command::Training(TrainingCommand::SetConfig(config)));
    harness
        .query_all_by_label("Train")
        .last()
        .expect("the Train button")
        .click();
    common::run_until(&mut harness, "the first epoch", |app| {
        !app.state.training().history.is_empty()
    });
    harness.get_by_label("Cancel training").click();
    common::run_until(&mut harness, "training to stop", |app| {
        !app.state.training().is_running()
    });
    let state = &harness.state().state;
    let status = state.status().unwrap_or_default().to_owned();
    assert!(status.contains("model cancelled"), "{status}");
    let epochs = state.training().history.len();
    assert!(epochs < 10_000);
    let Some(RunEnd::Trained { report, .. }) = state.training().last_end() else {
        panic!("the run's report")
    };
    assert!(report.cancelled && report.best_epoch >= 1 && report.best_epoch <= epochs);
    assert_eq!(
        state.models().source.as_deref(),
        Some("trained in the app, not saved")
    );
    harness.run_steps(2);
    let said = format!("cancelled after {epochs} of 10000 epochs; kept epoch");
    assert!(
        harness.query_all_by_label_contains(&said).next().is_some(),
        "{said}"
    );
}

#[test]
fn exports_write_the_losses_a_png_region_and_the_labels() {
    let set = common::sample_dir("box1-paper-center-front");
    let mut harness = app_on(std::slice::from_ref(&set));
    for _ in 0..20 {
        harness.key_press(egui::Key::ArrowRight);
        harness.run_steps(1);
    }
    let scratch = common::scratch_dir("export");
    let state = &harness.state().state;

    // Losses: one row per sample, online values up to the frame learned.
    let csv_path = scratch.join("losses.csv");
    let rows = state.save_losses_csv(&csv_path).expect("losses csv");
    let text = std::fs::read_to_string(&csv_path).expect("read csv");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), rows + 1);
    assert_eq!(rows, state.run().expect("run").sample_count());
    assert!(lines[0].starts_with("frame,time,fixed_loss_pos"));
    let row_5: Vec<&str> = lines[6].split(',').collect();
    assert_eq!(row_5[0], "5");
    assert!(
        row_5[4].parse::<f64>().is_ok(),
        "online loss at a learned frame: {}",
        lines[6]
    );
    let row_last: Vec<&str> = lines[rows].split(',').collect();
    assert_eq!(row_last[4], "", "no online loss past the learned frames");

    // A PNG region: the crop of a screenshot at the window's pixel scale.
    let image = egui::ColorImage::filled([200, 100], egui::Color32::from_rgb(10, 200, 30));
    let png_path = scratch.join("scene.png");
    let rect = egui::Rect::from_min_size(egui::pos2(10.0, 20.0), egui::vec2(50.0, 30.0));
    export::save_region_png(&image, rect, 2.0, &png_path).expect("png");
    let png = image::open(&png_path).expect("valid png").to_rgb8();
    assert_eq!(png.dimensions(), (100, 60));
    assert_eq!(png.get_pixel(5, 5).0, [10, 200, 30]);

    // Labels of the whole folder, with frame times.
    let labels_path = scratch.join("labels.csv");
    let label_rows = state
        .export_labels(&labels_path, LabelExportFormat::Csv)
        .expect("labels csv");
    let text = std::fs::read_to_string(&labels_path).expect("read labels csv");
    assert_eq!(text.lines().count(), label_rows + 1);
    assert!(text.starts_with("recording,label,kind,first_frame,last_frame,first_time,last_time"));
    let json_path = scratch.join("labels.json");
    state
        .export_labels(&json_path, LabelExportFormat::Json)
        .expect("labels json");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json_path).expect("read json"))
            .expect("valid json");
    assert_eq!(json["format"], "pushlab-labels-export");
    assert_eq!(json["recordings"]["offline_000.csv"]["split"], "offline");
    let _ = std::fs::remove_dir_all(&scratch);
}

#[test]
fn exporting_the_scene_and_the_plots_writes_pngs_of_their_regions() {
    let set = common::sample_dir("box1-paper-center-front");
    let mut harness = app_on(std::slice::from_ref(&set));
    let scratch = common::scratch_dir("png");
    let ctx = harness.ctx.clone();
    for (result, name) in [
        (
            DialogResult::SaveScene(scratch.join("scene.png")),
            "scene.png",
        ),
        (
            DialogResult::SavePlots(scratch.join("plots.png")),
            "plots.png",
        ),
    ] {
        harness.state_mut().apply_dialog_result(&ctx, result);
        harness.run_steps(3);
        let status = common::status(&harness);
        assert!(status.starts_with("saved "), "{status}");
        assert!(status.ends_with(name), "{status}");
    }
    let ppp = ctx.pixels_per_point();
    for (name, rect) in [
        ("scene.png", harness.state().view.scene.rect()),
        ("plots.png", harness.state().view.plots_rect),
    ] {
        let png = image::open(scratch.join(name)).expect("a PNG").to_rgba8();
        let (w, h) = png.dimensions();
        // The pixel columns and rows the rect's edges fall in (a panel's edges need not sit on
        // whole pixels).
        let pixels = |from: f32, to: f32| (to * ppp) as u32 - (from * ppp) as u32;
        assert_eq!(
            (w, h),
            (
                pixels(rect.min.x, rect.max.x),
                pixels(rect.min.y, rect.max.y)
            ),
            "{name} is the panel's region"
        );
        // Not a blank image: the scene and the plots have more than a handful of colours.
        let colours: std::collections::HashSet<[u8; 4]> = png.pixels().map(|p| p.0).collect();
        assert!(colours.len() > 20, "{name} has {} colours", colours.len());
    }
    let _ = std::fs::remove_dir_all(&scratch);
}

#[test]
fn the_train_tab_offers_every_model_kind_and_the_app_shows_which_is_loaded() {
    let set = common::sample_dir("box1-paper-center-front");
    let mut harness = app_on(std::slice::from_ref(&set));
    harness.get_by_label("Train").click();
    harness.run_steps(2);
    harness
        .get_by_role_and_label(egui::accesskit::Role::ComboBox, "Model kind")
        .click();
    harness.run_steps(2);
    // A button: the browser's Surface column says "paper" too.
    harness
        .get_by_role_and_label(egui::accesskit::Role::Button, "paper")
        .click();
    harness.run_steps(2);
    assert_eq!(
        harness.state().state.training().kind,
        pushlab_core::model::ModelKind::Paper
    );
    harness.get_by_label("Labelled offline").click();
    harness.run_steps(1);
    let config = TrainConfig {
        epochs: 2,
        ..harness.state().state.training().config
    };
    (harness.state_mut().state).apply(Command::Training(TrainingCommand::SetConfig(config)));
    harness
        .query_all_by_label("Train")
        .last()
        .expect("the Train button")
        .click();
    harness.run_steps(1);
    common::run_until(&mut harness, "training to finish", |app| {
        !app.state.training().is_running()
    });
    assert_eq!(
        harness.state().state.models().kind(),
        Some(pushlab_core::model::ModelKind::Paper)
    );
    harness.run_steps(2);
    assert!(
        harness
            .query_all_by_label_contains("In use: the paper model")
            .next()
            .is_some(),
        "the Train tab says which kind is loaded"
    );
}

/// A 0.1 m box pushed by a 5 mm rod at 50 Hz, simulated into `dir` by the built binary: recordings
/// far outside the default model's domain (0.4–0.55 m boxes, a 175 mm disc, 10 Hz).
fn simulate_small_rod_set(dir: &Path) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_pushlab"))
        .args(["simulate", "--out"])
        .arg(dir)
        .args([
            "--box",
            "0.1x0.1",
            "--pusher-radius",
            "0.005",
            "--rate",
            "50",
            "--duration",
            "2",
            "--speed",
            "0.03",
            "--pushes",
            "4",
            "--seed",
            "5",
        ])
        .output()
        .expect("run pushlab simulate");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn recordings_outside_the_model_s_domain_are_said_and_a_model_trained_for_them_is_remembered() {
    let scratch = common::scratch_dir("fit");
    let set = scratch.join("small-rod");
    simulate_small_rod_set(&set);
    let store = scratch.join("models");

    let mut state = initial_state(std::slice::from_ref(&set), Persisted::default());
    state.keep_files_in(Some(scratch.clone()));
    let config = TrainConfig {
        epochs: 3,
        ..state.training().config
    };
    state.apply(Command::Training(TrainingCommand::SetConfig(config)));
    let status = state.status().unwrap_or_default().to_owned();
    assert!(
        status.contains("warning: the model was trained on objects of 0.40–0.55 m"),
        "{status}"
    );
    let mut harness = common::harness(PushlabApp::new(state), 0.05);
    harness.run_steps(2);
    assert!(
        harness
            .query_all_by_label_contains("Warning: the model was trained on")
            .next()
            .is_some(),
        "the Steer tab says the model does not fit"
    );
    // The legend says which prediction layers come from the model of other data.
    harness.get_by_label("Show layers").click();
    harness.run_steps(1);
    assert!(
        harness
            .query_all_by_label_contains("from a model trained on other data")
            .count()
            >= 3,
        "online, fixed and pure-NN layers are marked"
    );
    harness.get_by_label("Train for these recordings").click();
    harness.run_steps(1);
    assert!(harness.state().state.training().is_running());
    common::run_until(&mut harness, "training for these recordings", |app| {
        !app.state.training().is_running()
    });

    let state = &harness.state().state;
    assert!(
        state.domain_mismatch().is_none(),
        "{:?}",
        state.domain_mismatch()
    );
    assert!(
        harness
            .query_all_by_label_contains("Warning: the model was trained on")
            .next()
            .is_none(),
        "the warning went"
    );
    assert!(
        harness
            .query_all_by_label_contains("from a model trained on other data")
            .next()
            .is_none(),
        "every layer comes from the model that fits"
    );
    assert!(
        state.models().pure_nn.is_some(),
        "the pure-NN layer has a baseline trained on the same recordings"
    );
    let status = state.status().unwrap_or_default().to_owned();
    assert!(
        status.contains("its pure-NN baseline after 3 epochs"),
        "{status}"
    );
    // No labels: trained on every recording but the one shown.
    assert_eq!(state.training().chosen.len(), 3);
    let source = PathBuf::from(state.models().source.clone().expect("a model source"));
    assert!(source.starts_with(&store) && source.is_file(), "{source:?}");
    let persisted = state.persisted();
    let folder = std::path::absolute(&set).expect("an absolute path");
    assert_eq!(persisted.folder_models.get(&folder), Some(&source));

    // Opening the folder again (after a restart) reopens its model.
    let state = initial_state(std::slice::from_ref(&set), persisted);
    assert_eq!(
        state.models().source.as_deref(),
        Some(source.display().to_string().as_str())
    );
    assert!(
        state.models().pure_nn.is_some(),
        "the baseline is in the model file"
    );
    let status = state.status().unwrap_or_default().to_owned();
    assert!(
        status.contains("reopened the model trained for"),
        "{status}"
    );
    assert!(state.domain_mismatch().is_none());
    let _ = std::fs::remove_dir_all(&scratch);
}
