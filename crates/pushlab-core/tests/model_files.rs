//! Model files are checked before any number is used: every kind of bad value a user could put into
//! `assets/default-model.json` (or a `paper` model) is refused with the file and the JSON path of the
//! field, a good file and version-1 and -2 files still open, and pushlab never saves a file it would refuse.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use pushlab_core::experiment;
use pushlab_core::learn::TrainConfig;
use pushlab_core::model::{CombinedModel, ModelKind};
use pushlab_core::model_file::{ModelFile, ModelFileError};
use serde_json::{Value, json};

fn default_model_text() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/default-model.json");
    std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{} is part of the repository: {e}", path.display()))
}

/// A `paper` model trained for one epoch on a committed sample set, with its pure network, as JSON.
fn paper_model_text() -> String {
    let set =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../sample-data/box1-paper-center-front");
    let loaded = experiment::load(std::slice::from_ref(&set), None, 1);
    assert!(!loaded.used.is_empty(), "{} loads", set.display());
    let config = TrainConfig {
        epochs: 1,
        horizon: 1,
        ..TrainConfig::default()
    };
    let no = AtomicBool::new(false);
    let combined =
        experiment::train_combined(ModelKind::Paper, &loaded.used, &config, &mut |_| {}, &no)
            .expect("trains");
    let pure = experiment::train_baseline(&loaded.used, &config, &mut |_| {}, &no).expect("trains");
    let file = ModelFile {
        combined: combined.model,
        pure_nn: Some(pure.model),
        training: experiment::training_metadata(&loaded.used, 1),
    };
    let dir = std::env::temp_dir().join(format!("pushlab-model-files-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("paper.json");
    file.save(&path).expect("a trained model saves");
    let text = std::fs::read_to_string(&path).expect("written");
    std::fs::remove_dir_all(&dir).ok();
    text
}

/// `text` with the value at the JSON pointer `pointer` replaced.
fn edited(text: &str, pointer: &str, value: Value) -> String {
    let mut json: Value = serde_json::from_str(text).expect("json");
    *json
        .pointer_mut(pointer)
        .unwrap_or_else(|| panic!("{pointer} is in the file")) = value;
    json.to_string()
}

/// Parses `text` as `model.json`; the refusal's message.
fn refusal(text: &str) -> String {
    match ModelFile::from_json(Path::new("model.json"), text.as_bytes()) {
        Ok(_) => panic!("accepted"),
        Err(e) => e.to_string(),
    }
}

/// Each edit of a good file, and the field and problem its refusal must name.
const CONTACT_CASES: &[(&str, f64, &str)] = &[
    (
        "/combined/loss_scale/sigma_rot",
        0.0,
        "combined.loss_scale.sigma_rot: must be > 0, found 0",
    ),
    (
        "/combined/loss_scale/sigma_pos/1",
        -0.01,
        "combined.loss_scale.sigma_pos[1]: must be > 0, found -0.01",
    ),
    (
        "/combined/horizon",
        0.0,
        "combined.horizon: must be at least 1 frame, found 0",
    ),
    (
        "/combined/relative_theta_scales/0",
        0.0,
        "combined.relative_theta_scales[0]: must be > 0, found 0",
    ),
    (
        "/combined/relative_theta_scales/2",
        -1.0,
        "combined.relative_theta_scales[2]: must be > 0, found -1",
    ),
    (
        "/combined/friction",
        -0.3,
        "combined.friction: must be ≥ 0, found -0.3",
    ),
    (
        "/combined/contact_tolerance",
        -0.001,
        "combined.contact_tolerance: must be ≥ 0, found -0.001",
    ),
    (
        "/combined/inputs/motion_floor",
        0.0,
        "combined.inputs.motion_floor: must be > 0, found 0",
    ),
    (
        "/combined/inputs/low/0",
        5.0,
        "combined.inputs.low[0]: must be ≤ combined.inputs.high[0]",
    ),
    (
        "/combined/network/17",
        1e39,
        "combined.network: parameter [17] is 1e39, not a finite number in the network's 32-bit floats",
    ),
    (
        "/pure_nn/input/position/std/0",
        0.0,
        "pure_nn.input.position.std[0]: must be > 0, found 0",
    ),
    (
        "/pure_nn/input/motion/std/1",
        -0.02,
        "pure_nn.input.motion.std[1]: must be > 0, found -0.02",
    ),
    (
        "/pure_nn/output/translation/std/0",
        0.0,
        "pure_nn.output.translation.std[0]: must be > 0, found 0",
    ),
    (
        "/pure_nn/output/rotation/std",
        0.0,
        "pure_nn.output.rotation.std: must be > 0, found 0",
    ),
    (
        "/pure_nn/input/position/mean/0",
        1e300,
        "pure_nn.input.position.mean[0]: must be a finite number between -1e12 and 1e12, found 1e300",
    ),
    (
        "/pure_nn/horizon",
        3.0,
        "pure_nn.horizon: must equal combined.horizon (10), found 3",
    ),
    (
        "/training/domain/object_size/0",
        0.0,
        "training.domain.object_size[0]: must be > 0, found 0",
    ),
];

const PAPER_CASES: &[(&str, f64, &str)] = &[
    (
        "/combined/com_misfit/gd_per_h",
        -0.1,
        "combined.com_misfit.gd_per_h: must be ≥ 0, found -0.1",
    ),
    (
        "/combined/normalization/position/std/0",
        0.0,
        "combined.normalization.position.std[0]: must be > 0, found 0",
    ),
    (
        "/combined/normalization/motion/std/1",
        -1.0,
        "combined.normalization.motion.std[1]: must be > 0, found -1",
    ),
    (
        "/combined/normalization/motion/std/0",
        1e-20,
        "combined.normalization.motion.std[0]: must be between 1e-12 and 1e12",
    ),
    (
        "/combined/theta_scales/1",
        0.0,
        "combined.theta_scales[1]: must be > 0, found 0",
    ),
    (
        "/combined/theta_scales/0",
        -0.05,
        "combined.theta_scales[0]: must be > 0, found -0.05",
    ),
    (
        "/combined/theta0/h",
        0.0,
        "combined.theta0.h: must be between 0.001 and 2 m (the range Lynch's h is kept in), found 0",
    ),
    (
        "/combined/theta0/h",
        -0.2,
        "combined.theta0.h: must be between 0.001 and 2 m",
    ),
    (
        "/combined/theta0/com_offset/1",
        2.5,
        "combined.theta0.com_offset[1]: must be between -2 and 2 m (the range the COM offset is kept in), found 2.5",
    ),
    (
        "/combined/loss_scale/sigma_rot",
        0.0,
        "combined.loss_scale.sigma_rot: must be > 0, found 0",
    ),
    (
        "/combined/horizon",
        0.0,
        "combined.horizon: must be at least 1 frame, found 0",
    ),
];

fn check_cases(text: &str, cases: &[(&str, f64, &str)]) {
    assert!(ModelFile::from_json(Path::new("model.json"), text.as_bytes()).is_ok());
    for &(pointer, value, expected) in cases {
        // Whole numbers stay integers, so that `horizon` keeps its type.
        let value = if value.fract() == 0.0 && value.abs() < 1e15 {
            json!(value as i64)
        } else {
            json!(value)
        };
        let message = refusal(&edited(text, pointer, value));
        assert!(
            message.starts_with("model.json: ") && message.contains(expected),
            "{pointer}: {message}\n  expected {expected}"
        );
    }
}

#[test]
fn every_bad_value_of_a_contact_model_is_refused_with_its_field() {
    check_cases(&default_model_text(), CONTACT_CASES);
}

#[test]
fn every_bad_value_of_a_paper_model_is_refused_with_its_field() {
    let text = paper_model_text();
    check_cases(&text, PAPER_CASES);
    // A version-1 file (before kinds) is migrated and checked by the same rules.
    let version_1 = text
        .replacen("\"version\": 3", "\"version\": 1", 1)
        .replacen("\"kind\": \"paper\",", "", 1);
    let old = ModelFile::from_json(Path::new("old.json"), version_1.as_bytes())
        .expect("a version-1 file opens");
    assert_eq!(old.combined.kind(), ModelKind::Paper);
    let message = refusal(&edited(&version_1, "/combined/theta0/h", json!(0)));
    assert!(
        message.contains("combined.theta0.h: must be between"),
        "{message}"
    );
}

#[test]
fn a_file_before_version_3_opens_without_its_domains_pusher_speeds() {
    let text = default_model_text();
    let current =
        ModelFile::from_json(Path::new("model.json"), text.as_bytes()).expect("the default opens");
    let speeds = current
        .training
        .domain
        .as_ref()
        .and_then(|d| d.pusher_speed);
    assert!(speeds.is_some(), "a version-3 file keeps its speeds");
    // Older files summed noisy frame-to-frame steps: their speeds are dropped, the rest is kept.
    let version_2 = edited(&text, "/version", json!(2));
    let old = ModelFile::from_json(Path::new("old.json"), version_2.as_bytes())
        .expect("a version-2 file opens");
    let mut expected = current.clone();
    if let Some(domain) = expected.training.domain.as_mut() {
        domain.pusher_speed = None;
    }
    assert_eq!(old, expected);
}

#[test]
fn a_field_of_the_wrong_type_or_shape_is_named_by_its_path() {
    let text = default_model_text();
    let message = refusal(&edited(&text, "/combined/horizon", json!(-1)));
    assert!(
        message.contains("combined.horizon: invalid value: integer `-1`"),
        "{message}"
    );
    let mut json: Value = serde_json::from_str(&text).expect("json");
    json["combined"]["network"]
        .as_array_mut()
        .expect("a list")
        .pop();
    let message = refusal(&json.to_string());
    assert!(
        message.contains(
            "combined.network: the network has 723 parameters, expected 724 for a 6-16-16-16-4 MLP"
        ),
        "{message}"
    );
    let message = refusal(&edited(
        &text,
        "/combined/loss_scale",
        json!({"sigma_pos": [1.0, 1.0]}),
    ));
    assert!(
        message.contains("combined.loss_scale: missing field `sigma_rot`"),
        "{message}"
    );
    let message = refusal(&edited(&text, "/kind", json!("quantum")));
    assert!(message.contains("\"kind\" is \"quantum\""), "{message}");
    // Text after the model is refused, not ignored.
    let message = refusal(&format!("{text} {{}}"));
    assert!(message.contains("trailing characters"), "{message}");
}

#[test]
fn pushlab_never_saves_a_model_it_would_refuse() {
    let good = ModelFile::from_json(Path::new("model.json"), default_model_text().as_bytes())
        .expect("the default model opens");
    // The training domain is public: a caller can break it in memory.
    let mut bad = good.clone();
    if let Some(domain) = bad.training.domain.as_mut() {
        domain.horizon = 0;
    } else {
        panic!("the default model records its domain");
    }
    let dir = std::env::temp_dir().join(format!("pushlab-model-save-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path: PathBuf = dir.join("model.json");
    let err = bad.save(&path).expect_err("refused");
    assert!(matches!(err, ModelFileError::Invalid { .. }));
    assert!(
        err.to_string()
            .contains("model.json: training.domain.horizon: must be at least 1 frame, found 0"),
        "{err}"
    );
    assert!(!path.exists(), "nothing was written");
    good.save(&path).expect("a good model saves");
    assert_eq!(ModelFile::load(&path).expect("and loads"), good);
    assert!(matches!(good.combined, CombinedModel::Contact(_)));
    std::fs::remove_dir_all(&dir).ok();
}
