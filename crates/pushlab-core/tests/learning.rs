//! Learning checked against the simulator's ground truth: online learning recovers the true COM offset
//! and `h`, online adaptation beats the fixed model where the COM moved, training is reproducible and
//! cancellable, and model files round-trip and refuse what they cannot read.

use crate::toy;

use std::sync::atomic::{AtomicBool, Ordering};

use pushlab_core::learn::{
    Nmse, OnlineConfig, TrainConfig, train_paper, train_paper_in_slices, train_pure_nn,
};
use pushlab_core::slices;
use toy::Chain;

use pushlab_core::model::OnlineModel;
use std::sync::Arc;

use pushlab_core::learn::{ContactTrajectory, train_contact};
use pushlab_core::model::{
    CombinedModel, ContactGeometry, ModelKind, OnlineParams, PhysicsOnlyModel, Sample,
    samples_from_trajectory,
};
use pushlab_core::model_file::{ModelFile, ModelFileError};
use pushlab_core::recording::{ObjectShape, PushSide};
use pushlab_core::sim::{GeneratedSet, NoiseSpec, PressureModel, PushSpec, SetSpec, generate_set};

/// A box pushed on its front face from many contact points and angles, recorded at 10 Hz, 4 mm per
/// frame.
fn simulated(
    com_offset: [f64; 2],
    pressure: PressureModel,
    noise_m: f64,
    seed: u64,
) -> GeneratedSet {
    simulated_on(PushSide::Front, com_offset, pressure, noise_m, seed)
}

/// As [`simulated`], pushing on the given side.
fn simulated_on(
    side: PushSide,
    com_offset: [f64; 2],
    pressure: PressureModel,
    noise_m: f64,
    seed: u64,
) -> GeneratedSet {
    let mut pushes = Vec::new();
    for offset in [-0.12, -0.06, 0.0, 0.06, 0.12] {
        for angle in [-20.0, 0.0, 20.0] {
            pushes.push(PushSpec {
                contact_offset: offset,
                push_angle_deg: angle,
                curvature: 0.0,
                split: None,
            });
        }
    }
    let spec = SetSpec {
        name: "test".into(),
        object: ObjectShape::Box {
            width: 0.3,
            length: 0.4,
        },
        com_offset,
        pressure,
        material: None,
        floor_friction: None,
        // High pusher friction: every push sticks, as the physics-only model assumes.
        pusher_friction: 0.9,
        pusher_radius: 0.05,
        push_side: side,
        sample_rate_hz: 10.0,
        duration_s: 6.0,
        speed: 0.04,
        approach: 0.0,
        noise: NoiseSpec {
            position_m: noise_m,
            yaw_deg: 0.0,
        },
        start_position_spread_m: 0.2,
        start_yaw_spread_deg: 90.0,
        seed,
        pushes,
    };
    generate_set(&spec, &mut |_, _| {}).expect("valid simulation spec")
}

fn samples(set: &GeneratedSet) -> Vec<Vec<Sample>> {
    set.trajectories
        .iter()
        .map(|t| samples_from_trajectory(t, 1))
        .collect()
}

fn mean_total(steps: &[pushlab_core::model::OnlineStep]) -> f64 {
    steps.iter().map(|s| s.loss.total()).sum::<f64>() / steps.len() as f64
}

#[test]
fn physics_only_online_learning_recovers_the_true_com_offset_and_h() {
    // Pushes on one face alone confound the COM offset along the push with h (both enter Lynch's
    // equations as h² + c_x²), so the robot pushes the object from the front and from the left, in turn.
    let truth_com = [0.03, -0.025];
    let front = simulated_on(PushSide::Front, truth_com, PressureModel::Uniform, 0.0, 7);
    let left = simulated_on(PushSide::Left, truth_com, PressureModel::Uniform, 0.0, 8);
    let truth_h = front.setting.h.expect("the simulator writes the true h");
    assert_eq!(left.setting.h, Some(truth_h));
    let outline = front.setting.object.outline().expect("a box");
    // The physics-only model assumes a sticking contact (u_c = u_r): feed it the pushes that stick.
    let sticking = |set: &GeneratedSet| -> Vec<Vec<Sample>> {
        samples(set)
            .into_iter()
            .zip(&set.sliding_fractions)
            .filter(|(_, sliding)| **sliding == 0.0)
            .map(|(s, _)| s)
            .collect()
    };
    let (front_sticking, left_sticking) = (sticking(&front), sticking(&left));
    assert!(front_sticking.len() >= 8 && left_sticking.len() >= 8);
    let data: Vec<Vec<Sample>> = front_sticking
        .into_iter()
        .zip(left_sticking)
        .flat_map(|(a, b)| [a, b])
        .collect();
    let scale = pushlab_core::model::LossScale::from_samples(data.iter().flatten());
    let model = PhysicsOnlyModel::new(outline, 0.05, 0.005, scale);
    let start = model.theta0();
    assert!(
        (start.com_offset[0] - truth_com[0]).abs() > 0.02,
        "learning must have somewhere to go"
    );
    // Carry θ over from push to push, as a robot pushing the same object again would.
    let mut learner = Chain::new(&model, OnlineConfig::default());
    let mut first_push_loss = None;
    let mut last_push_loss = 0.0;
    for trajectory in &data {
        let steps = learner.run(trajectory);
        first_push_loss.get_or_insert(mean_total(&steps));
        last_push_loss = mean_total(&steps);
    }
    let learned = learner.theta();
    let com_error = ((learned.com_offset[0] - truth_com[0]).powi(2)
        + (learned.com_offset[1] - truth_com[1]).powi(2))
    .sqrt();
    assert!(
        com_error <= 0.002,
        "learned COM offset {:?}, true {truth_com:?}: {:.1} mm off",
        learned.com_offset,
        com_error * 1e3
    );
    let h_error = (learned.h - truth_h).abs() / truth_h;
    assert!(
        h_error <= 0.10,
        "learned h {:.4} m, true {truth_h:.4} m: {:.1} % off",
        learned.h,
        h_error * 100.0
    );
    let first = first_push_loss.expect("at least one push");
    assert!(
        last_push_loss < 0.5 * first,
        "loss {first} → {last_push_loss}"
    );
}

#[test]
fn combined_model_adapts_online_to_a_moved_com_and_beats_the_fixed_model() {
    // Tracking noise of 0.2 mm against 4 mm of motion per frame: with more, noise alone sets the
    // positional NMSE of any model near 1 and hides what learning does.
    let offline = simulated([0.0, 0.0], PressureModel::Rim, 0.0002, 11);
    let online = simulated([0.05, 0.05], PressureModel::Rim, 0.0002, 12);
    let model = train_paper_on(&offline, 60);

    let (mut fixed, mut adaptive) = (Vec::new(), Vec::new());
    for trajectory in samples(&online) {
        // Reset per trajectory, as the paper's evaluation does.
        let mut learner = Chain::new(&model, OnlineConfig::default());
        let frozen = &model;
        for sample in &trajectory {
            fixed.push(frozen.evaluate(sample, &frozen.theta0()).loss);
            adaptive.push(learner.step(sample).loss);
        }
    }
    let (fixed, adaptive) = (Nmse::of(&fixed), Nmse::of(&adaptive));
    let fixed_total = fixed.pos * 2.0 + fixed.rot;
    let adaptive_total = adaptive.pos * 2.0 + adaptive.rot;
    assert!(
        adaptive_total < 0.9 * fixed_total,
        "online {adaptive:?} should beat fixed {fixed:?} where the COM moved"
    );
}

#[test]
fn same_seed_gives_bit_identical_models_and_another_seed_does_not() {
    let data = samples(&simulated([0.0, 0.0], PressureModel::Uniform, 0.001, 5));
    let train = |seed| {
        let config = TrainConfig {
            epochs: 5,
            seed,
            ..TrainConfig::default()
        };
        let trained =
            train_paper(&data, &config, &mut |_| {}, &AtomicBool::new(false)).expect("trains");
        (trained.model, trained.report)
    };
    let (a, report_a) = train(42);
    let (b, report_b) = train(42);
    let (c, _) = train(43);
    assert_eq!(a, b);
    assert_eq!(report_a, report_b);
    assert_ne!(a, c);
    let nn = |seed| {
        let config = TrainConfig {
            epochs: 3,
            seed,
            ..TrainConfig::default()
        };
        train_pure_nn(&data, &config, &mut |_| {}, &AtomicBool::new(false))
            .expect("trains")
            .model
    };
    assert_eq!(nn(1), nn(1));
}

#[test]
fn training_lowers_the_loss_reports_progress_and_stops_when_cancelled() {
    let data = samples(&simulated([0.0, 0.0], PressureModel::Uniform, 0.0002, 6));
    let cancel = AtomicBool::new(false);
    let mut seen = Vec::new();
    let config = TrainConfig {
        epochs: 50,
        patience: 0,
        ..TrainConfig::default()
    };
    let trained = train_paper(
        &data,
        &config,
        &mut |p| {
            seen.push((p.epoch, p.train_loss));
            if p.epoch == 20 {
                cancel.store(true, Ordering::Relaxed);
            }
        },
        &cancel,
    )
    .expect("trains");
    assert!(trained.report.cancelled);
    assert_eq!(trained.report.epochs_run, 20);
    assert_eq!(seen.len(), 20);
    assert_eq!(seen[0].0, 1);
    assert!(
        seen[19].1 < 0.5 * seen[0].1,
        "training loss {:?} → {:?}",
        seen[0],
        seen[19]
    );
    // The kept model is the one with the best validation loss, and it predicts better than the mean.
    let validation = trained.report.validation_loss.expect("validation split");
    assert!(
        validation < 3.0,
        "validation loss {validation} (3 = predicting the mean)"
    );
}

/// What a browser tab does with a training: polls it a slice at a time between two frames, with a
/// Cancel that may come between two slices.
#[test]
fn training_in_slices_stops_within_each_epoch_and_a_cancel_between_slices_keeps_the_best_epoch() {
    let data = samples(&simulated([0.0, 0.0], PressureModel::Uniform, 0.0002, 6));
    let config = TrainConfig {
        epochs: 4,
        patience: 0,
        ..TrainConfig::default()
    };
    let never = AtomicBool::new(false);
    let whole = train_paper(&data, &config, &mut |_| {}, &never).expect("trains");
    let epochs_seen = std::cell::Cell::new(0);
    let mut polls_per_epoch = vec![0usize; config.epochs + 1];
    let mut progress = |p: &pushlab_core::learn::TrainProgress| epochs_seen.set(p.epoch);
    let sliced = {
        let mut work = Box::pin(train_paper_in_slices(&data, &config, &mut progress, &never));
        loop {
            polls_per_epoch[epochs_seen.get()] += 1;
            if let Some(done) = slices::poll_once(work.as_mut()) {
                break done.expect("trains");
            }
        }
    };
    // 80 % of the samples train, in batches of 32, 16 batches a slice: more than one slice an
    // epoch, and the model polled in slices is the model trained in one piece.
    let training = whole.report.training_samples;
    let slices_per_epoch = training.div_ceil(32 * 16);
    assert!(slices_per_epoch > 1, "{training} training samples");
    for polls in &polls_per_epoch[..config.epochs] {
        assert!(
            *polls >= slices_per_epoch,
            "polls per epoch {polls_per_epoch:?}"
        );
    }
    assert_eq!(sliced.model, whole.model);
    assert_eq!(sliced.report, whole.report);

    // Cancelled after the first slice of the third epoch: the second epoch's model is kept.
    let cancel = AtomicBool::new(false);
    let epochs_seen = std::cell::Cell::new(0);
    let mut progress = |p: &pushlab_core::learn::TrainProgress| epochs_seen.set(p.epoch);
    let mut work = Box::pin(train_paper_in_slices(
        &data,
        &config,
        &mut progress,
        &cancel,
    ));
    let mut polls_in_third = 0;
    let cancelled = loop {
        if let Some(done) = slices::poll_once(work.as_mut()) {
            break done.expect("trains");
        }
        if epochs_seen.get() == 2 {
            polls_in_third += 1;
            if polls_in_third == 1 {
                cancel.store(true, Ordering::Relaxed);
            }
        }
    };
    assert!(cancelled.report.cancelled);
    assert_eq!(cancelled.report.epochs_run, 2);
    assert!(cancelled.report.kept_an_epoch());
}

#[test]
fn training_for_no_epoch_is_refused_not_a_random_model() {
    let data = samples(&simulated([0.0, 0.0], PressureModel::Uniform, 0.0002, 2));
    let config = TrainConfig {
        epochs: 0,
        ..TrainConfig::default()
    };
    let error = train_paper(&data, &config, &mut |_| {}, &AtomicBool::new(false))
        .expect_err("no epoch, no model");
    assert_eq!(
        error.to_string(),
        "invalid training configuration: epochs must be at least 1"
    );
}

#[test]
fn model_files_round_trip_and_refuse_wrong_versions_and_shapes() {
    let data = samples(&simulated([0.0, 0.0], PressureModel::Uniform, 0.001, 8));
    let config = TrainConfig {
        epochs: 2,
        ..TrainConfig::default()
    };
    let no = AtomicBool::new(false);
    let combined = train_paper(&data, &config, &mut |_| {}, &no).expect("trains");
    let pure = train_pure_nn(&data, &config, &mut |_| {}, &no).expect("trains");
    let file = ModelFile {
        combined: CombinedModel::Paper(Arc::new(combined.model)),
        pure_nn: Some(pure.model),
        training: pushlab_core::model_file::TrainingMetadata {
            report: Some(combined.report),
            pure_nn_report: Some(pure.report),
            sources: vec!["sim".into()],
            pushlab_version: "test".into(),
            // The domain round-trips with the rest of the file.
            domain: Some(pushlab_core::domain::Domain {
                object_size: [0.4, 0.55],
                pusher_radius: [0.05, 0.05],
                sample_rate_hz: [10.0, 10.0],
                pusher_speed: Some([0.03, 0.06]),
                horizon: 1,
            }),
        },
    };
    let dir = std::env::temp_dir().join(format!("pushlab-model-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("model.json");
    file.save(&path).expect("saves");
    let back = ModelFile::load(&path).expect("loads");
    assert_eq!(back, file);
    // Predictions are the same after the round trip.
    let s = &data[0][3];
    let (saved, loaded) = (
        file.combined
            .on_object(None)
            .expect("the paper model needs no outline"),
        back.combined
            .on_object(None)
            .expect("the paper model needs no outline"),
    );
    let theta = saved.theta0();
    assert_eq!(
        loaded.predict(&s.input, &theta),
        saved.predict(&s.input, &theta)
    );

    let text = std::fs::read_to_string(&path).expect("readable");
    assert!(text.contains("\"version\": 3") && text.contains("\"kind\": \"paper\""));
    // A version-1 file (before model kinds: no "kind") opens as the paper's model.
    let version_1 = text
        .replacen("\"version\": 3", "\"version\": 1", 1)
        .replacen("\"kind\": \"paper\",", "", 1);
    let old = ModelFile::from_json(&path, version_1.as_bytes()).expect("a version-1 file opens");
    assert_eq!(old.combined.kind(), ModelKind::Paper);
    // … without its domain's pusher speeds, which files before version 3 measured by summed steps.
    let mut without_speeds = file.clone();
    if let Some(domain) = without_speeds.training.domain.as_mut() {
        domain.pusher_speed = None;
    }
    assert_eq!(old, without_speeds);
    let unknown = text.replacen("\"kind\": \"paper\"", "\"kind\": \"quantum\"", 1);
    let err = ModelFile::from_json(&path, unknown.as_bytes()).expect_err("unknown kind");
    assert!(err.to_string().contains("\"kind\" is \"quantum\""), "{err}");
    let newer = text.replacen("\"version\": 3", "\"version\": 7", 1);
    let err = ModelFile::from_json(&path, newer.as_bytes()).expect_err("version 7");
    assert!(matches!(err, ModelFileError::WrongVersion { .. }));
    let message = err.to_string();
    assert!(
        message.contains("model.json") && message.contains("version 7") && message.contains('1'),
        "{message}"
    );

    let mut json: serde_json::Value = serde_json::from_str(&text).expect("json");
    json["combined"]["network"]
        .as_array_mut()
        .expect("a list")
        .truncate(600);
    let err = ModelFile::from_json(&path, json.to_string().as_bytes()).expect_err("short network");
    let message = err.to_string();
    assert!(
        message.contains("600 parameters") && message.contains("692"),
        "{message}"
    );

    let err = ModelFile::from_json(&path, b"{\"format\": \"something-else\"}").expect_err("format");
    assert!(
        err.to_string().contains("not a pushlab model file"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Trains the contact-frame model on a simulated set's pushes.
fn train_contact_on(
    set: &GeneratedSet,
    epochs: usize,
) -> (Arc<ContactGeometry>, pushlab_core::model::ContactModel) {
    let outline = set.setting.object.outline().expect("a box");
    let geometry = Arc::new(ContactGeometry::new(&outline, set.setting.pusher_radius));
    let data = samples(set);
    let trajectories: Vec<ContactTrajectory> = data
        .iter()
        .map(|samples| ContactTrajectory {
            geometry: &geometry,
            samples,
        })
        .collect();
    let config = TrainConfig {
        epochs,
        seed: 3,
        ..TrainConfig::default()
    };
    let trained = train_contact(&trajectories, &config, &mut |_| {}, &AtomicBool::new(false))
        .expect("trains");
    (geometry, trained.model)
}

/// Trains the paper's model on a simulated set's pushes, `θ_online(0)` the outline's.
fn train_paper_on(set: &GeneratedSet, epochs: usize) -> pushlab_core::model::PaperModel {
    let outline = set.setting.object.outline().expect("a box");
    let config = TrainConfig {
        epochs,
        seed: 3,
        theta0: Some(OnlineParams::for_outline(&outline)),
        ..TrainConfig::default()
    };
    train_paper(&samples(set), &config, &mut |_| {}, &AtomicBool::new(false))
        .expect("trains")
        .model
}

#[test]
fn the_contact_model_carries_over_to_another_face_where_the_paper_model_does_not() {
    // Offline: front-face pushes. Online: the left face, which puts the pusher where the paper's
    // network never saw it; in the contact frame it is the same kind of push.
    let offline = simulated([0.0, 0.0], PressureModel::Rim, 0.0002, 21);
    let online = simulated_on(PushSide::Left, [0.0, 0.0], PressureModel::Rim, 0.0002, 22);
    let (geometry, contact) = train_contact_on(&offline, 60);
    let contact = CombinedModel::Contact(Arc::new(contact));
    let paper = CombinedModel::Paper(Arc::new(train_paper_on(&offline, 60)));
    let fixed_nmse = |model: &CombinedModel, set: &GeneratedSet| {
        let learner = model
            .on_object(Some(&geometry))
            .expect("a box has an outline");
        let theta = learner.theta0();
        let losses: Vec<_> = samples(set)
            .iter()
            .flatten()
            .map(|s| learner.loss_and_gradient(s, &theta).1)
            .collect();
        Nmse::of(&losses)
    };
    let contact_offline = fixed_nmse(&contact, &offline);
    let contact_left = fixed_nmse(&contact, &online);
    let paper_left = fixed_nmse(&paper, &online);
    assert!(
        contact_left.pos < 2.0 * contact_offline.pos + 0.05
            && contact_left.rot < 2.0 * contact_offline.rot + 0.05,
        "contact model: offline {contact_offline:?}, left face {contact_left:?}"
    );
    assert!(
        contact_left.pos * 3.0 < paper_left.pos,
        "left face: contact {contact_left:?} against paper {paper_left:?}"
    );
}

#[test]
fn the_contact_model_learns_a_moved_com_online_and_its_files_round_trip() {
    let offline = simulated([0.0, 0.0], PressureModel::Rim, 0.0002, 31);
    let online = simulated([0.05, 0.05], PressureModel::Rim, 0.0002, 32);
    let (geometry, model) = train_contact_on(&offline, 60);
    let combined = CombinedModel::Contact(Arc::new(model));
    let learner = combined.on_object(Some(&geometry)).expect("outline");
    assert_eq!(
        combined.on_object(None).err(),
        Some(pushlab_core::model::NoOutline)
    );
    let (mut fixed, mut adaptive) = (Vec::new(), Vec::new());
    for trajectory in samples(&online) {
        let mut learning = Chain::new(&learner, OnlineConfig::default());
        let frozen = &learner;
        for sample in &trajectory {
            fixed.push(frozen.evaluate(sample, &frozen.theta0()).loss);
            adaptive.push(learning.step(sample).loss);
        }
    }
    let (fixed, adaptive) = (Nmse::of(&fixed), Nmse::of(&adaptive));
    assert!(
        adaptive.pos * 2.0 + adaptive.rot < 0.9 * (fixed.pos * 2.0 + fixed.rot),
        "online {adaptive:?} should beat fixed {fixed:?} where the COM moved"
    );

    let file = ModelFile {
        combined,
        pure_nn: None,
        training: Default::default(),
    };
    let dir = std::env::temp_dir().join(format!("pushlab-contact-model-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("contact.json");
    file.save(&path).expect("saves");
    let back = ModelFile::load(&path).expect("loads");
    assert_eq!(back, file);
    assert_eq!(back.combined.kind(), ModelKind::Contact);
    let s = &samples(&online)[0][5];
    let loaded = back.combined.on_object(Some(&geometry)).expect("outline");
    assert_eq!(
        loaded.predict(&s.input, &learner.theta0()),
        learner.predict(&s.input, &learner.theta0())
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A pass that keeps only the losses (the fixed run of every recording opened, the best θ's scores)
/// takes `loss_at`, which skips the gradient: it must be `evaluate`'s loss to the bit, for every
/// kind, at `θ_online(0)`, at a moved COM and at a θ out of range (clamped as `evaluate` clamps it).
#[test]
fn loss_at_is_the_loss_evaluate_gives_to_the_bit_for_every_kind() {
    let offline = simulated([0.0, 0.0], PressureModel::Rim, 0.0002, 41);
    let online = simulated_on(PushSide::Left, [0.03, 0.0], PressureModel::Rim, 0.0002, 42);
    let (geometry, contact) = train_contact_on(&offline, 5);
    let outline = offline.setting.object.outline().expect("a box");
    let paper = train_paper_on(&offline, 5);
    let data = samples(&online);
    let scale = pushlab_core::model::LossScale::from_samples(data.iter().flatten());
    let physics: Arc<dyn OnlineModel + Send + Sync> =
        Arc::new(PhysicsOnlyModel::new(outline, 0.05, 0.005, scale));
    let learners = [
        CombinedModel::Contact(Arc::new(contact))
            .on_object(Some(&geometry))
            .expect("outline"),
        CombinedModel::Paper(Arc::new(paper))
            .on_object(None)
            .expect("no outline needed"),
        physics,
    ];
    for learner in &learners {
        let thetas = [
            learner.theta0(),
            OnlineParams {
                com_offset: [0.04, -0.03],
                h: 0.12,
            },
            OnlineParams {
                com_offset: [0.0, 0.0],
                h: 50.0,
            },
        ];
        for (theta, sample) in thetas
            .iter()
            .flat_map(|t| data.iter().flatten().map(move |s| (t, s)))
        {
            assert_eq!(
                learner.loss_at(sample, theta),
                learner.evaluate(sample, theta).loss,
                "at {theta:?}"
            );
        }
    }
}
