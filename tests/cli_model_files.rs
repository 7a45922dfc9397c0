//! Every file a user hands `pushlab eval --model` is checked: each kind of bad model file is
//! refused with exit 1 and a message naming the file and the field (the guide's table of bad model
//! files, `docs/src/model.md`, comes from these cases), and at wild learning rates on real MIT
//! pushes no θ and no loss in the JSON report is ever non-finite.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::skip;
use std::path::{Path, PathBuf};

use serde_json::{Value, json};

use crate::cli_common;
use cli_common::pushlab;

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

fn sample(file: &str) -> String {
    repo("sample-data/box1-paper-center-front")
        .join(file)
        .display()
        .to_string()
}

/// `pushlab eval` of `model` on two sample pushes, at the model's horizon.
fn eval_with(model: &Path) -> cli_common::Run {
    pushlab(&[
        "eval",
        "--model",
        &model.display().to_string(),
        "--offline",
        &sample("offline_000.csv"),
        "--online",
        &sample("online_000.csv"),
    ])
}

/// Writes `text` with the value at `pointer` replaced to `dir/name`.
fn write_edited(dir: &Path, name: &str, text: &str, pointer: &str, value: Value) -> PathBuf {
    let mut json: Value = serde_json::from_str(text).expect("json");
    *json
        .pointer_mut(pointer)
        .unwrap_or_else(|| panic!("{pointer} is in the file")) = value;
    let path = dir.join(name);
    std::fs::write(&path, json.to_string()).expect("write");
    path
}

/// Runs eval on each edit of `text`; each must exit 1 with its message, naming the file.
fn check_refusals(dir: &Path, text: &str, cases: &[(&str, Value, &str)]) {
    for (k, (pointer, value, expected)) in cases.iter().enumerate() {
        let name = format!("bad-{k}.json");
        let path = write_edited(dir, &name, text, pointer, value.clone());
        let run = eval_with(&path);
        assert_eq!(run.code, 1, "{pointer}: {}", run.stderr);
        let expected = format!("{}: {expected}", path.display());
        assert!(
            run.stderr.contains(&expected),
            "{pointer}: {}\n  expected {expected}",
            run.stderr
        );
    }
}

#[test]
fn eval_refuses_each_bad_contact_model_file_with_exit_1_naming_the_field() {
    let dir = cli_common::temp_dir("pushlab-models", "contact");
    let text = std::fs::read_to_string(repo("assets/default-model.json")).expect("default model");
    // The unedited file is used.
    let good = dir.join("good.json");
    std::fs::write(&good, &text).expect("write");
    let run = eval_with(&good);
    assert_eq!(run.code, 0, "{}", run.stderr);
    check_refusals(
        &dir,
        &text,
        &[
            (
                "/combined/loss_scale/sigma_rot",
                json!(0),
                "combined.loss_scale.sigma_rot: must be > 0, found 0",
            ),
            (
                "/combined/horizon",
                json!(0),
                "combined.horizon: must be at least 1 frame, found 0",
            ),
            (
                "/combined/relative_theta_scales/0",
                json!(0),
                "combined.relative_theta_scales[0]: must be > 0, found 0",
            ),
            (
                "/combined/relative_theta_scales/1",
                json!(-0.5),
                "combined.relative_theta_scales[1]: must be > 0, found -0.5",
            ),
            (
                "/pure_nn/input/position/std/0",
                json!(0),
                "pure_nn.input.position.std[0]: must be > 0, found 0",
            ),
            (
                "/pure_nn/output/rotation/std",
                json!(-1),
                "pure_nn.output.rotation.std: must be > 0, found -1",
            ),
            (
                "/combined/network",
                json!([0.5, 0.25]),
                "combined.network: the network has 2 parameters, expected 724 for a 6-16-16-16-4 MLP",
            ),
            (
                "/combined/network/3",
                json!(1e39),
                "combined.network: parameter [3] is 1e39, not a finite number in the network's 32-bit floats",
            ),
            (
                "/kind",
                json!("quantum"),
                "\"kind\" is \"quantum\", expected one of \"contact\", \"paper\"",
            ),
        ],
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn eval_refuses_each_bad_paper_model_file_with_exit_1_naming_the_field() {
    let dir = cli_common::temp_dir("pushlab-models", "paper");
    let model = dir.join("paper.json");
    let model_s = model.display().to_string();
    let train = pushlab(&[
        "train",
        "--data",
        &sample("offline_000.csv"),
        &sample("offline_001.csv"),
        "--model-kind",
        "paper",
        "--epochs",
        "1",
        "--out",
        &model_s,
    ]);
    assert_eq!(train.code, 0, "{}", train.stderr);
    let text = std::fs::read_to_string(&model).expect("trained model");
    check_refusals(
        &dir,
        &text,
        &[
            (
                "/combined/normalization/position/std/0",
                json!(0),
                "combined.normalization.position.std[0]: must be > 0, found 0",
            ),
            (
                "/combined/normalization/motion/std/1",
                json!(-0.01),
                "combined.normalization.motion.std[1]: must be > 0, found -0.01",
            ),
            (
                "/combined/theta_scales/2",
                json!(0),
                "combined.theta_scales[2]: must be > 0, found 0",
            ),
            (
                "/combined/theta0/h",
                json!(0),
                "combined.theta0.h: must be between 0.001 and 2 m (the range Lynch's h is kept in), found 0",
            ),
            (
                "/combined/theta0/h",
                json!(-0.1),
                "combined.theta0.h: must be between 0.001 and 2 m (the range Lynch's h is kept in), found -0.1",
            ),
        ],
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A number of the report at `pointer`; serde_json writes a NaN or an infinity as `null`.
fn finite_at(report: &Value, pointer: &str, what: &str) {
    let v = report.pointer(pointer);
    assert!(
        v.and_then(Value::as_f64).is_some_and(f64::is_finite),
        "{what}: {pointer} is {v:?}"
    );
}

#[test]
fn eval_reports_a_finite_theta_and_finite_losses_at_lr_10_and_1e6_on_real_mit_pushes() {
    let Some(dir) = skip::shared(&repo(""), "mit-push") else {
        return;
    };
    let file = |name: &str| dir.join(name).display().to_string();
    let offline = [
        file("motion_surface=abs_shape=rect1_a=0_v=75_i=2.000_s=0.800_t=0.349.h5"),
        file("motion_surface=abs_shape=ellip1_a=0_v=20_i=0.000_s=0.675_t=0.349.h5"),
    ];
    let online = [
        file("motion_surface=abs_shape=hex_a=0_v=50_i=4.000_s=0.700_t=0.000.h5"),
        file("motion_surface=plywood_shape=hex_a=0_v=150_i=1.000_s=0.000_t=-0.349.json"),
        file("motion_surface=abs_shape=ellip1_a=0_v=20_i=0.000_s=0.675_t=0.349.h5"),
    ];
    let out_dir = cli_common::temp_dir("pushlab-models", "wild");
    for kind in ["contact", "paper"] {
        for lr in ["10", "1e6"] {
            let what = format!("{kind} at lr {lr}");
            let out = out_dir.join(format!("{kind}-{lr}.json"));
            let out_s = out.display().to_string();
            let mut args = vec!["eval", "--offline"];
            args.extend(offline.iter().map(String::as_str));
            args.push("--online");
            args.extend(online.iter().map(String::as_str));
            args.extend_from_slice(&[
                "--model-kind",
                kind,
                "--horizon",
                "10",
                "--epochs",
                "2",
                "--lr",
                lr,
                "--physics",
                "--json",
                &out_s,
            ]);
            let run = pushlab(&args);
            assert_eq!(run.code, 0, "{what}: {}", run.stderr);
            let report: Value =
                serde_json::from_str(&std::fs::read_to_string(&out).expect("report"))
                    .expect("json");
            for row in ["offline_nn", "offline", "fixed", "online"] {
                for axis in ["pos", "rot"] {
                    finite_at(&report, &format!("/{row}/{axis}"), &what);
                }
            }
            for row in ["offline", "fixed", "online"] {
                for axis in ["pos", "rot"] {
                    finite_at(&report, &format!("/physics/{row}/{axis}"), &what);
                }
            }
            let trajectories = report["trajectories"].as_array().expect("trajectories");
            assert_eq!(trajectories.len(), online.len(), "{what}");
            for t in 0..trajectories.len() {
                for field in [
                    "fixed/pos",
                    "fixed/rot",
                    "online/pos",
                    "online/rot",
                    "com_offset_learned/0",
                    "com_offset_learned/1",
                    "h_learned",
                    "theta0/h",
                ] {
                    finite_at(&report, &format!("/trajectories/{t}/{field}"), &what);
                }
            }
        }
    }
    std::fs::remove_dir_all(&out_dir).ok();
}

#[test]
fn train_takes_adams_learning_rate_into_the_model_file_and_refuses_a_bad_one() {
    let dir = cli_common::temp_dir("pushlab-models", "adam-lr");
    let model = dir.join("slow.json");
    let train = |lr: &str| {
        pushlab(&[
            "train",
            "--data",
            &sample("offline_000.csv"),
            &sample("offline_001.csv"),
            "--epochs",
            "1",
            "--no-com-calibration",
            "--adam-lr",
            lr,
            "--out",
            &model.display().to_string(),
        ])
    };
    let run = train("0.001");
    assert_eq!(run.code, 0, "{}", run.stderr);
    let file: Value = serde_json::from_str(&std::fs::read_to_string(&model).unwrap()).unwrap();
    assert_eq!(
        file.pointer("/training/report/config/learning_rate"),
        Some(&json!(0.001))
    );
    for bad in ["0", "inf", "fast"] {
        let run = train(bad);
        assert_eq!(run.code, 2, "--adam-lr {bad}: {}", run.stderr);
        assert!(
            run.stderr.contains("--adam-lr") && run.stderr.contains(&format!("{bad:?}")),
            "{}",
            run.stderr
        );
    }
}
