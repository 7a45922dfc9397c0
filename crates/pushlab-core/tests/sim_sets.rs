//! Generated recording sets: the sample-data spec, reproducibility, tracking noise, and the round trip
//! through the native format.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use nalgebra::Vector2;
use pushlab_core::geometry::{Outline, Pose2};
use pushlab_core::recording::{ObjectShape, PushSide, read_set, write_set};
use pushlab_core::sim::{
    NoiseSpec, NoiseStream, PressureModel, PushPlan, PushSpec, SampleSpec, Sampling, SetSpec,
    SimObject, TrackingNoise, generate_set, lynch_h, read_sample_spec, simulate_push,
};

fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn small_spec(seed: u64) -> SetSpec {
    SetSpec {
        name: "test-set".into(),
        object: ObjectShape::Box {
            width: 0.3,
            length: 0.4,
        },
        com_offset: [0.03, -0.02],
        pressure: PressureModel::Rim,
        material: Some("paper".into()),
        floor_friction: Some(0.3),
        pusher_friction: 0.4,
        pusher_radius: 0.175,
        push_side: PushSide::Left,
        sample_rate_hz: 4.0,
        duration_s: 5.0,
        speed: 0.05,
        approach: 0.01,
        noise: NoiseSpec {
            position_m: 0.002,
            yaw_deg: 0.5,
        },
        start_position_spread_m: 0.2,
        start_yaw_spread_deg: 180.0,
        seed,
        pushes: vec![
            PushSpec {
                contact_offset: -0.05,
                push_angle_deg: 10.0,
                curvature: 0.0,
                split: Some("offline".into()),
            },
            PushSpec {
                contact_offset: 0.08,
                push_angle_deg: -5.0,
                curvature: 0.5,
                split: Some("online".into()),
            },
        ],
    }
}

#[test]
fn the_sample_data_spec_mirrors_the_papers_turtlebot_experiments() {
    let sets = read_sample_spec(&repo_root().join("sample-data/spec.json")).unwrap();
    assert!((8..=10).contains(&sets.len()), "{} settings", sets.len());
    for set in &sets {
        let count = |split: &str| {
            set.pushes
                .iter()
                .filter(|p| p.split.as_deref() == Some(split))
                .count()
        };
        assert_eq!((count("offline"), count("online")), (27, 9), "{}", set.name);
    }
    let has = |f: &dyn Fn(&SetSpec) -> bool| sets.iter().any(f);
    // Two boxes, two materials with different h and friction, COM centre/UR/LR, sides front/left.
    assert!(has(&|s| s.name.starts_with("box1")) && has(&|s| s.name.starts_with("box2")));
    assert!(has(&|s| s.com_offset[0] > 0.0 && s.com_offset[1] > 0.0));
    assert!(has(&|s| s.com_offset[0] > 0.0 && s.com_offset[1] < 0.0));
    assert!(has(&|s| s.push_side == PushSide::Left) && has(&|s| s.push_side == PushSide::Front));
    let frictions: std::collections::BTreeSet<_> =
        sets.iter().map(|s| s.pusher_friction.to_bits()).collect();
    assert!(frictions.len() >= 2);
}

#[test]
fn the_committed_sample_data_is_what_the_spec_generates() {
    let root = repo_root();
    let sets = read_sample_spec(&root.join("sample-data/spec.json")).unwrap();
    // One setting in full is enough to catch a changed simulator or a hand-edited file.
    let spec = sets
        .iter()
        .find(|s| s.name == "box1-paper-ur-front")
        .unwrap();
    let generated = generate_set(spec, &mut |_, _| {}).unwrap();
    let (committed, errors) = read_set(&root.join("sample-data").join(&spec.name)).unwrap();
    assert!(errors.is_empty(), "{errors:?}");
    assert_eq!(committed.setting.com_offset, Some(spec.com_offset));
    let h = committed.setting.h.unwrap();
    assert!((h - generated.setting.h.unwrap()).abs() < 1e-12);
    assert_eq!(committed.recordings.len(), generated.trajectories.len());
    for (recording, trajectory) in committed.recordings.iter().zip(&generated.trajectories) {
        assert_eq!(recording.trajectory.len(), trajectory.len());
        for (a, b) in recording.trajectory.frames.iter().zip(&trajectory.frames) {
            // Rounded to 1 µm: allow one unit for a last-bit difference of another platform's libm.
            let d = (a.object.position - b.object.position).norm()
                + (a.robot - b.robot).norm()
                + (a.object.yaw - b.object.yaw).abs();
            assert!(
                d < 5e-6,
                "{}: frame at {} s differs by {d}",
                recording.name,
                a.time
            );
        }
    }
}

#[test]
fn a_generated_set_round_trips_through_the_native_format() {
    let set = generate_set(&small_spec(5), &mut |_, _| {}).unwrap();
    let dir = std::env::temp_dir().join(format!("pushlab-sim-roundtrip-{}", std::process::id()));
    write_set(&dir, &set.setting, &set.trajectories).unwrap();
    let (read, errors) = read_set(&dir).unwrap();
    std::fs::remove_dir_all(&dir).ok();
    assert!(errors.is_empty(), "{errors:?}");
    assert_eq!(read.setting.com_offset, Some([0.03, -0.02]));
    assert_eq!(read.setting.h, set.setting.h);
    let names: Vec<_> = read.recordings.iter().map(|r| r.name.as_str()).collect();
    assert_eq!(names, ["offline_000", "online_000"]);
    let split = |i: usize| read.recordings[i].entry.as_ref().unwrap().extra["split"].clone();
    assert_eq!((split(0), split(1)), ("offline".into(), "online".into()));
    for (recording, trajectory) in read.recordings.iter().zip(&set.trajectories) {
        assert_eq!(&*recording.trajectory, trajectory);
        assert_eq!(recording.trajectory.len(), 21);
    }
}

#[test]
fn equal_seeds_give_equal_sets_and_other_seeds_other_noise() {
    let a = generate_set(&small_spec(5), &mut |_, _| {}).unwrap();
    let b = generate_set(&small_spec(5), &mut |_, _| {}).unwrap();
    let c = generate_set(&small_spec(6), &mut |_, _| {}).unwrap();
    assert_eq!(a, b);
    assert_ne!(a.trajectories, c.trajectories);
    // The true h is the one of the pressure model balanced over the COM.
    let outline = Outline::rectangle(0.3, 0.4).unwrap();
    let h = lynch_h(&outline, PressureModel::Rim, Vector2::new(0.03, -0.02), 200).unwrap();
    assert_eq!(a.setting.h, Some(h));
}

#[test]
fn tracking_noise_has_the_requested_spread() {
    let outline = Outline::rectangle(0.3, 0.4).unwrap();
    let object = SimObject {
        h: lynch_h(&outline, PressureModel::Uniform, Vector2::zeros(), 100).unwrap(),
        outline,
        com_offset: Vector2::zeros(),
        pusher_radius: 0.1,
        pusher_friction: 0.3,
    };
    let start = Pose2::new(0.0, 0.0, 0.0);
    let plan = PushPlan {
        side: PushSide::Front,
        contact_offset: 0.05,
        push_angle_deg: 0.0,
        speed: 0.05,
        curvature: 0.0,
        approach: 0.0,
    };
    let path = plan.path(&object.outline, &start, 0.1).unwrap();
    let sampling = Sampling {
        rate_hz: 100.0,
        duration_s: 40.0,
        max_substep: 1e-3,
    };
    let noise = TrackingNoise {
        position_sd: 0.002,
        yaw_sd: 0.01,
    };
    let mut rng = NoiseStream::new(3);
    let push = simulate_push(&object, start, &path, &sampling, Some((&noise, &mut rng))).unwrap();
    let n = push.truth.len() as f64;
    let (mut sx, mut st) = (0.0, 0.0);
    for (noisy, truth) in push.trajectory.frames.iter().zip(&push.truth.frames) {
        sx += (noisy.object.position.x - truth.object.position.x).powi(2);
        st += (noisy.object.yaw - truth.object.yaw).powi(2);
        assert_eq!(noisy.time, truth.time);
    }
    let (sd_x, sd_theta) = ((sx / n).sqrt(), (st / n).sqrt());
    assert!((sd_x - 0.002).abs() < 0.0002, "position sd {sd_x}");
    assert!((sd_theta - 0.01).abs() < 0.001, "yaw sd {sd_theta}");
}

#[test]
fn a_spec_naming_an_unknown_material_says_which_setting_and_what_exists() {
    let text = std::fs::read_to_string(repo_root().join("sample-data/spec.json")).unwrap();
    let mut spec: SampleSpec = serde_json::from_str(&text).unwrap();
    spec.settings[2].material = "wood".into();
    let message = spec.expand().unwrap_err().to_string();
    assert_eq!(
        message,
        "settings[2].material: unknown material 'wood', expected one of: paper, plastic"
    );
}

#[test]
fn a_broken_spec_file_is_reported_with_its_line() {
    let dir = std::env::temp_dir().join(format!("pushlab-sim-spec-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("spec.json");
    std::fs::write(
        &path,
        "{\n  \"defaults\": {\n    \"pusher_radius\": \"big\"\n",
    )
    .unwrap();
    let message = read_sample_spec(&path).unwrap_err().to_string();
    std::fs::remove_dir_all(&dir).ok();
    // The field first (a spec is edited by hand), then where it is.
    assert!(
        message.ends_with(
            "spec.json: defaults.pusher_radius: invalid type: string \"big\", expected f64 \
             (line 3, column 26)"
        ),
        "{message}"
    );
}
