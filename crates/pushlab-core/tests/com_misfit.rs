//! The COM misfit (`model::ComMisfit`): training on two objects with a known COM measures it by
//! leaving each out, the model file keeps it, and every online run's COM ellipse widens by exactly
//! that spread while θ learns the same path; one object alone cannot measure it.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use pushlab_core::experiment::{self, TrajectoryRun, UsedRecording};
use pushlab_core::labels::Split;
use pushlab_core::learn::{OnlineConfig, Optimizer, Spread, TrainConfig};
use pushlab_core::model::{CombinedModel, ModelKind, OnlineModel};
use pushlab_core::model_file::ModelFile;

fn sample_set(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../sample-data")
        .join(name)
}

fn offline(names: &[&str]) -> Vec<UsedRecording> {
    let paths: Vec<PathBuf> = names.iter().map(|n| sample_set(n)).collect();
    let loaded = experiment::load(&paths, Some(Split::Offline), 1);
    assert!(!loaded.used.is_empty(), "{names:?} load");
    loaded.used
}

fn config() -> TrainConfig {
    TrainConfig {
        epochs: 3,
        horizon: 1,
        ..TrainConfig::default()
    }
}

fn trained(used: &[UsedRecording], calibrate: bool) -> CombinedModel {
    let no = AtomicBool::new(false);
    experiment::train_calibrated(
        ModelKind::Contact,
        used,
        &config(),
        calibrate,
        &mut |_| {},
        &no,
    )
    .expect("trains")
    .model
}

#[test]
fn two_objects_measure_the_misfit_and_every_run_adds_it_to_the_com_ellipse() {
    let used = offline(&["box1-paper-center-front", "box2-paper-center-front"]);
    let calibrated = trained(&used, true);
    let misfit = calibrated.com_misfit();
    assert_eq!(misfit.objects, 2, "{misfit:?}");
    assert_eq!(misfit.pushes, used.len(), "every recording knows its COM");
    assert!(
        misfit.gd_per_h > 0.0 && misfit.gauss_newton_per_h > 0.0,
        "a model trained on one box misses the other's COM: {misfit:?}"
    );

    // The same training without calibration is the same model but for the misfit.
    let plain = trained(&used, false);
    assert_eq!(plain.com_misfit(), Default::default());
    assert_eq!(plain.clone().with_com_misfit(misfit), calibrated);

    for optimizer in [Optimizer::Gd, Optimizer::GaussNewton] {
        let config = OnlineConfig {
            optimizer,
            ..OnlineConfig::default()
        };
        let run = |model: &CombinedModel| {
            TrajectoryRun::learn(model, &used[0], 0, &config)
                .expect("an outline")
                .run
        };
        let (wide, narrow) = (run(&calibrated), run(&plain));
        let last = wide.frontier();
        assert_eq!(
            wide.theta_at(last),
            narrow.theta_at(last),
            "θ learns the same"
        );
        let h0 = experiment::model_on(&calibrated, &used[0])
            .expect("an outline")
            .theta0()
            .h;
        let per_h = match optimizer {
            Optimizer::Gd => misfit.gd_per_h,
            Optimizer::GaussNewton => misfit.gauss_newton_per_h,
        };
        let added = (per_h * h0).powi(2);
        let (w, n) = (
            wide.posterior().com_covariance(),
            narrow.posterior().com_covariance(),
        );
        for (i, j) in [(0, 0), (1, 1), (0, 1)] {
            let expected = n[i][j] + if i == j { added } else { 0.0 };
            assert!(
                (w[i][j] - expected).abs() <= 1e-12 * expected.abs().max(1e-9),
                "{optimizer:?} C[{i}][{j}] {} against {expected}",
                w[i][j]
            );
        }
    }

    // The model file keeps it.
    let dir = std::env::temp_dir().join(format!("pushlab-com-misfit-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("model.json");
    let file = ModelFile {
        combined: calibrated,
        pure_nn: None,
        training: experiment::training_metadata(&used, 1),
    };
    file.save(&path).expect("saves");
    let read = ModelFile::load(&path).expect("loads");
    assert_eq!(read.combined.com_misfit(), misfit);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn one_object_cannot_measure_it() {
    let used = offline(&["box1-paper-center-front", "box1-plastic-center-front"]);
    let model = trained(&used, true);
    assert!(!model.com_misfit().is_calibrated());
    assert_eq!(model.com_misfit().gd_per_h, 0.0);
}

#[test]
fn a_cancel_during_the_misfit_trainings_is_the_run_s_cancel() {
    use pushlab_core::learn::TrainStage;
    use std::sync::atomic::Ordering;
    let used = offline(&["box1-paper-center-front", "box2-paper-center-front"]);
    let cancel = AtomicBool::new(false);
    let trained = experiment::train_calibrated(
        ModelKind::Contact,
        &used,
        &config(),
        true,
        &mut |p| {
            // The user presses Cancel once the first object-left-out model has an epoch.
            if p.stage != TrainStage::Model {
                cancel.store(true, Ordering::Relaxed);
            }
        },
        &cancel,
    )
    .expect("trains");
    assert_eq!(
        trained.report.epochs_run, 3,
        "the model itself trained to its end"
    );
    assert!(trained.report.kept_an_epoch());
    assert!(
        trained.report.cancelled,
        "the report says the run was cancelled"
    );
    assert!(!trained.model.com_misfit().is_calibrated());
}

#[test]
fn progress_says_which_object_each_misfit_training_leaves_out() {
    use pushlab_core::learn::TrainStage;
    let used = offline(&["box1-paper-center-front", "box2-paper-center-front"]);
    let no = AtomicBool::new(false);
    let mut stages = Vec::new();
    experiment::train_calibrated(
        ModelKind::Contact,
        &used,
        &config(),
        true,
        &mut |p| {
            if stages.last() != Some(&p.stage) {
                stages.push(p.stage);
            }
        },
        &no,
    )
    .expect("trains");
    assert_eq!(
        stages,
        [
            TrainStage::Model,
            TrainStage::MisfitFold { fold: 1, folds: 2 },
            TrainStage::MisfitFold { fold: 2, folds: 2 },
        ]
    );
}

#[test]
fn a_new_optimiser_at_an_earlier_frame_widens_the_ellipse_by_its_own_misfit() {
    let used = offline(&["box1-paper-center-front", "box2-paper-center-front"]);
    let calibrated = trained(&used, true);
    let plain = calibrated.clone().with_com_misfit(Default::default());
    let misfit = calibrated.com_misfit();
    assert!(misfit.gd_per_h != misfit.gauss_newton_per_h, "{misfit:?}");
    let gauss_newton = OnlineConfig {
        optimizer: Optimizer::GaussNewton,
        ..OnlineConfig::default()
    };
    // Learned to the end with gradient descent, then Gauss–Newton from frame 10 on (a user who
    // scrubbed back and switched), learned to the end again.
    let run = |model: &CombinedModel| {
        let mut run = TrajectoryRun::learn(model, &used[0], 0, &OnlineConfig::default())
            .expect("an outline")
            .run;
        assert!(run.frontier() > 10 + pushlab_core::learn::KEYFRAME);
        run.set_config_at(10, gauss_newton);
        run.learn_all(&used[0].skip);
        run
    };
    let (wide, narrow) = (run(&calibrated), run(&plain));
    let h0 = wide.theta_at(0).h;
    let added = (misfit.gauss_newton_per_h * h0).powi(2);
    let (w, n) = (
        wide.posterior().com_covariance(),
        narrow.posterior().com_covariance(),
    );
    for i in 0..2 {
        let expected = n[i][i] + added;
        assert!(
            (w[i][i] - expected).abs() <= 1e-12 * expected,
            "C[{i}][{i}] {} against {expected} (Gauss–Newton's misfit added)",
            w[i][i]
        );
    }
    let last = wide.frontier();
    let spread = wide.spread_at(last);
    let expected = Spread::of(wide.posterior());
    assert_eq!(
        spread, expected,
        "the spread shown at the end is the posterior's"
    );
}
