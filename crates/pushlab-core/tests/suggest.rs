//! The next push that teaches the most (`experiment::suggest`, `pushlab suggest`): a push's shape
//! read against what the simulator was told to do, the ranking against the physics of which face
//! was pushed, and the measurement's runs against `pushlab eval --carry-theta`'s.
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use pushlab_core::experiment::suggest::{self, Choice, Criterion};
use pushlab_core::experiment::{self, EvalOptions, TrajectoryRun, UsedRecording};
use pushlab_core::inspect::shape_of;
use pushlab_core::labels::Split;
use pushlab_core::learn::{OnlineConfig, OnlineState, Optimizer, TrainConfig};
use pushlab_core::model::{DEFAULT_CONTACT_TOLERANCE, LossScale, ModelKind};

fn load(names: &[&str], split: Split) -> Vec<UsedRecording> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../sample-data");
    let paths: Vec<_> = names.iter().map(|n| root.join(n)).collect();
    let loaded = experiment::load(&paths, Some(split), 1);
    assert!(!loaded.used.is_empty(), "{names:?} load");
    loaded.used
}

fn unit_scale() -> LossScale {
    LossScale {
        sigma_pos: [0.005, 0.005],
        sigma_rot: 0.02,
    }
}

#[test]
fn a_pushs_shape_is_the_offset_and_angle_the_simulator_was_told() {
    // The sample data's setting.json lists each push's contact offset (positive to the left of the
    // push) and angle (counter-clockwise from the face normal); read from the recorded motion.
    let used = load(&["box1-paper-center-front"], Split::Online);
    for u in &used {
        let recording = &u.recording;
        let entry = recording.entry.as_ref().expect("listed");
        let outline = recording.setting.object.outline().unwrap();
        let poses: Vec<_> = recording
            .trajectory
            .frames
            .iter()
            .map(|f| f.object)
            .collect();
        let shape = shape_of(
            &outline,
            recording.setting.pusher_radius,
            &recording.trajectory,
            &poses,
        )
        .expect("touches");
        let (offset, angle) = (entry.contact_offset.unwrap(), entry.push_angle_deg.unwrap());
        assert!(
            (shape.offset_m - offset).abs() < 0.01,
            "{}: {} vs {offset}",
            recording.name,
            shape.offset_m
        );
        assert!(
            (shape.angle_rad.to_degrees() - angle).abs() < 5.0,
            "{}: {} vs {angle}",
            recording.name,
            shape.angle_rad.to_degrees()
        );
    }
}

/// The front and the left pushes of box 1 on paper, as one object: their two folders' files seen
/// as one folder's (same box, floor and pusher).
fn two_faces() -> Vec<UsedRecording> {
    let mut used = load(
        &["box1-paper-center-front", "box1-paper-center-left"],
        Split::Online,
    );
    for u in &mut used {
        let file = u.recording.source.file_name().unwrap().to_owned();
        let face = u
            .recording
            .setting
            .name
            .rsplit('-')
            .next()
            .unwrap()
            .to_owned();
        u.recording.source = PathBuf::from("box1").join(format!("{face}-{}", file.display()));
    }
    used
}

#[test]
fn after_a_push_on_one_face_the_push_that_teaches_most_is_on_the_other() {
    // Physics alone (no training): one front push pins the COM across the front face; the depth
    // along it is seen by a push on the left face.
    let used = two_faces();
    let missing = suggest::find_object(&used, Some("box2")).unwrap_err();
    assert_eq!(
        missing,
        "no object 'box2' in the recordings; there are 'box1-paper-center-front' (18 pushes)"
    );
    assert_eq!(
        suggest::find_object(&used, None),
        suggest::find_object(&used, Some("center-front"))
    );
    let object = suggest::objects(&used);
    assert_eq!(object.len(), 1, "one object: {object:?}");
    let pushes = &object[0].pushes;
    let front: Vec<usize> = pushes
        .iter()
        .copied()
        .filter(|&i| {
            used[i]
                .recording
                .source
                .to_string_lossy()
                .contains("front-")
        })
        .collect();
    assert!(!front.is_empty() && front.len() < pushes.len());
    let physics = experiment::physics_model(
        &used[front[0]].recording,
        unit_scale(),
        DEFAULT_CONTACT_TOLERANCE,
    )
    .unwrap();
    let config = OnlineConfig {
        optimizer: Optimizer::GaussNewton,
        ..OnlineConfig::default()
    };
    let learned = TrajectoryRun::learn_physics(
        physics.clone(),
        &used[front[0]],
        front[0],
        1,
        &config,
        None,
        None,
    );
    let state = learned.run.end_state();
    let left: Vec<usize> = pushes.iter().copied().filter(|&i| i != front[0]).collect();
    let candidates = |used: &[UsedRecording]| -> Vec<(usize, pushlab_core::recording::Recording)> {
        left.iter()
            .map(|&i| (i, used[i].recording.clone()))
            .collect()
    };
    let rank = |used: &[UsedRecording]| {
        let owned = candidates(used);
        let given: Vec<(usize, &pushlab_core::recording::Recording)> =
            owned.iter().map(|(i, r)| (*i, r)).collect();
        suggest::rank(&physics, 1, &state, &given, Criterion::Spread).expect("ranks")
    };
    let ranking = rank(&used);
    let is_front = |i: usize| front.contains(&i);
    let best = &ranking.suggestions[0];
    let worst = ranking.suggestions.last().unwrap();
    assert!(!is_front(best.push), "{ranking:#?}");
    assert!(is_front(worst.push), "{ranking:#?}");
    assert!(
        best.com_std_after_m < 0.7 * worst.com_std_after_m,
        "{ranking:#?}"
    );
    assert!(worst.com_std_after_m < ranking.com_std_now_m);
    // Every suggestion names where it pushes, read off the model's forecast.
    assert!(ranking.suggestions.iter().all(|s| s.shape.is_some()));
    let start = OnlineState::start(&physics, config.optimizer);
    assert!(ranking.com_std_now_m < Criterion::Spread.std_of(start.posterior.com_covariance()));
    // The forecast never read the candidates' recorded outcome: the same push with the object's
    // recorded motion replaced by standing still ranks the same.
    let mut still = used.clone();
    for i in &left {
        let t = &mut still[*i].recording.trajectory;
        let first = t.frames[0].object;
        let frames = t.frames.iter().map(|f| pushlab_core::trajectory::Frame {
            object: first,
            ..*f
        });
        *t = std::sync::Arc::new(pushlab_core::trajectory::Trajectory::new(frames.collect()));
    }
    let again = rank(&still);
    assert_eq!(again, ranking);
}

#[test]
fn learning_in_the_given_order_is_evals_carried_run_to_the_bit() {
    let offline = load(&["box1-paper-center-front"], Split::Offline);
    let config = TrainConfig {
        epochs: 2,
        horizon: 1,
        ..TrainConfig::default()
    };
    let no = AtomicBool::new(false);
    let model = experiment::train_calibrated(
        ModelKind::Contact,
        &offline,
        &config,
        false,
        &mut |_| {},
        &no,
    )
    .expect("trains")
    .model;
    let online = load(&["box1-paper-lr-front"], Split::Online);
    let online_config = OnlineConfig {
        optimizer: Optimizer::GaussNewton,
        ..OnlineConfig::default()
    };
    let options = EvalOptions {
        online: online_config,
        physics: None,
        carry: true,
        start_com_shift: None,
        weighting: Default::default(),
    };
    let evaluation = experiment::evaluate(&model, None, &[], &online, &options);
    let pushes: Vec<usize> = (0..online.len()).collect();
    let learned = suggest::learn_in_order(
        &model,
        &online,
        &pushes,
        &online_config,
        Choice::InOrder,
        Criterion::Spread,
        pushes.len(),
    )
    .unwrap();
    assert_eq!(learned.len(), online.len());
    for (l, t) in learned.iter().zip(&evaluation.trajectories) {
        assert_eq!(l.push, t.recording);
        assert_eq!(l.com_error_m, t.com_truth.map(|c| c.error_m));
    }
    // Ranked, worst and random orders learn every push once; each step's push was the ranking's
    // first (last) among those left, so the expected spreads of ranked ≤ worst at the first step.
    let order = |choice| {
        suggest::learn_in_order(
            &model,
            &online,
            &pushes,
            &online_config,
            choice,
            Criterion::Spread,
            pushes.len(),
        )
        .unwrap()
    };
    let (ranked, worst, random) = (
        order(Choice::Ranked),
        order(Choice::Worst),
        order(Choice::Random(3)),
    );
    for o in [&ranked, &worst, &random] {
        let mut seen: Vec<usize> = o.iter().map(|l| l.push).collect();
        seen.sort_unstable();
        assert_eq!(seen, pushes);
    }
    assert!(ranked[0].expected_std_m <= worst[0].expected_std_m);
    assert_eq!(order(Choice::Random(3)), random);
    assert_ne!(order(Choice::Random(4)), random);
}

#[test]
fn each_criterion_reads_the_com_ellipse_as_its_closed_form_whatever_its_turn() {
    // Standard deviations of 2 mm and 1 mm along axes turned by any angle.
    for turn in [0.0f64, 0.5, 1.2] {
        let (c, s) = (turn.cos(), turn.sin());
        let (a, b) = (4e-6, 1e-6);
        let cov = [
            [a * c * c + b * s * s, (a - b) * c * s],
            [(a - b) * c * s, a * s * s + b * c * c],
        ];
        let close = |x: f64, y: f64| (x - y).abs() < 1e-12;
        assert!(close(Criterion::Spread.std_of(cov), 2.5e-6f64.sqrt()));
        assert!(close(
            Criterion::Area.std_of(cov),
            2e-3f64.sqrt() * 1e-3f64.sqrt()
        ));
        assert!(close(Criterion::Axis.std_of(cov), 2e-3));
    }
    assert_eq!("axis".parse::<Criterion>(), Ok(Criterion::Axis));
    assert_eq!(
        "volume".parse::<Criterion>(),
        Err(
            "unknown criterion 'volume': expected 'spread' (the mean COM variance), 'area' (the \
             COM ellipse's area) or 'axis' (its longest axis)"
                .to_owned()
        )
    );
}

#[test]
fn a_grid_lays_out_the_pushes_asked_for_and_after_a_front_push_a_side_one_teaches_most() {
    use pushlab_core::experiment::suggest::PushGrid;
    let used = load(&["box1-paper-center-front"], Split::Online);
    let like = &used[0].recording;
    let grid = PushGrid {
        sides: pushlab_core::recording::PushSide::ALL.to_vec(),
        offsets: vec![-0.5, 0.0, 0.5, 1.5],
        angles_deg: vec![-20.0, 0.0, 20.0],
        length_m: 0.1,
    }
    .pushes(like)
    .unwrap();
    // 4 sides × 3 offsets on the face × 3 angles; the offset beyond the face is said, per angle.
    assert_eq!(grid.pushes.len(), 36);
    assert_eq!(grid.skipped.len(), 12, "{:?}", grid.skipped);
    assert!(
        grid.skipped[0].contains("is off the front face"),
        "{}",
        grid.skipped[0]
    );
    let outline = like.setting.object.outline().unwrap();
    for push in &grid.pushes {
        assert!(push.same_object_as(like), "{}", push.name);
        let t = &push.trajectory;
        let poses: Vec<_> = t.frames.iter().map(|f| f.object).collect();
        let shape = shape_of(&outline, like.setting.pusher_radius, t, &poses).expect("touches");
        // The name says the plan: side, offset, angle; the shape reads them off the motion.
        let words: Vec<&str> = push.name.split(' ').collect();
        let offset_cm: f64 = words[1].parse().unwrap();
        let angle: f64 = words[3].trim_end_matches('°').parse().unwrap();
        assert!(
            (shape.offset_m * 1e2 - offset_cm).abs() < 0.1,
            "{}: {shape:?}",
            push.name
        );
        assert!(
            (shape.angle_rad.to_degrees() - angle).abs() < 0.5,
            "{}: {shape:?}",
            push.name
        );
        assert!(
            (shape.length_m - 0.1).abs() < 0.01,
            "{}: {shape:?}",
            push.name
        );
    }
    // After one front push, physics alone: the push that teaches most is on the left or right,
    // the least on the front or back (they see what the front push saw).
    let physics = experiment::physics_model(like, unit_scale(), DEFAULT_CONTACT_TOLERANCE).unwrap();
    let config = OnlineConfig {
        optimizer: Optimizer::GaussNewton,
        ..OnlineConfig::default()
    };
    let state = TrajectoryRun::learn_physics(physics.clone(), &used[0], 0, 1, &config, None, None)
        .run
        .end_state();
    let given: Vec<(usize, &pushlab_core::recording::Recording)> =
        grid.pushes.iter().enumerate().collect();
    let ranking = suggest::rank(&physics, 1, &state, &given, Criterion::Area).unwrap();
    let side = |s: &suggest::Suggestion| s.name.split(' ').next().unwrap().to_owned();
    let best = side(&ranking.suggestions[0]);
    let worst = side(ranking.suggestions.last().unwrap());
    assert!(best == "left" || best == "right", "{ranking:#?}");
    assert!(worst == "front" || worst == "back", "{ranking:#?}");
}
