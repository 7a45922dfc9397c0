//! What eval uses and refuses: exit codes 1 and 2, splits and bad tracking from labels, the real MIT files.

use super::*;
use crate::skip;

#[test]
fn nothing_usable_is_exit_1_and_wrong_arguments_exit_2() {
    let dir = temp_dir("exit");
    let missing = dir.join("no-such-folder").display().to_string();
    let online = online_subset();
    let run = pushlab(&eval_args(
        std::slice::from_ref(&missing),
        &online,
        &["--epochs", "1"],
    ));
    assert_eq!(run.code, 1, "{}\n{}", run.stdout, run.stderr);
    assert!(
        run.stderr.contains(&format!(
            "nothing usable in --offline: no recording could be used (1 skipped: {missing}: cannot read"
        )),
        "{}",
        run.stderr
    );
    assert!(
        run.stdout
            .contains(&format!("skipped: {missing}: cannot read")),
        "{}",
        run.stdout
    );

    let offline = offline_subset();
    let run = pushlab(&eval_args(
        &offline,
        &online,
        &["--horizon", "500", "--epochs", "1"],
    ));
    assert_eq!(run.code, 1);
    assert!(
        run.stderr.contains(
            "nothing usable in --offline: no recording could be used (6 without a sample at horizon 500 (shorter than 501 frames))"
        ),
        "{}",
        run.stderr
    );
    let run = pushlab(&["train", "--data", &missing, "--out", "never-written.json"]);
    assert_eq!(run.code, 1);
    assert!(run.stderr.contains("nothing to train on"), "{}", run.stderr);
    assert!(!Path::new("never-written.json").exists());

    let run = pushlab(&["eval", "--offline", &offline[0]]);
    assert_eq!(run.code, 2);
    assert!(run.stderr.contains("--online"), "{}", run.stderr);
    // --offline is needed without a model to train, and the help says when.
    let run = pushlab(&["eval", "--online", &online[0]]);
    assert_eq!(run.code, 2);
    assert!(run.stderr.contains("--offline <PATH>"), "{}", run.stderr);
    let help = pushlab(&["eval", "--help"]);
    assert!(
        help.stdout.contains("Needed unless --model is given"),
        "{}",
        help.stdout
    );
    let run = pushlab(&eval_args(&offline, &online, &["--lr", "0"]));
    assert_eq!(run.code, 2);
    assert!(
        run.stderr.contains("must be a finite number above 0"),
        "{}",
        run.stderr
    );
    let run = pushlab(&eval_args(&offline, &online, &["--horizon", "0"]));
    assert_eq!(run.code, 2);
    assert!(run.stderr.contains("must be at least 1"), "{}", run.stderr);
    for shift in ["0.02", "0.02,north"] {
        let run = pushlab(&eval_args(&offline, &online, &["--start-com-shift", shift]));
        assert_eq!(run.code, 2, "{shift}");
        assert!(
            run.stderr.contains("expected X,Y in metres (e.g. 0.02,0)"),
            "{}",
            run.stderr
        );
    }
    let run = pushlab(&["train", "--data", &offline[0]]);
    assert_eq!(run.code, 2);
    assert!(run.stderr.contains("--out"), "{}", run.stderr);
}

#[test]
fn splits_and_bad_tracking_come_from_the_labels_file() {
    // A copy of four pushes of one set, with labels: two offline, two online, bad tracking on
    // frames 10..30 of one online push, and a slipping segment on the other.
    let dir = temp_dir("labels");
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("sample-data/box1-paper-ur-front");
    let files = [
        "offline_000.csv",
        "offline_013.csv",
        "online_001.csv",
        "online_002.csv",
    ];
    for f in files {
        std::fs::copy(source.join(f), dir.join(f)).unwrap();
    }
    let mut setting: Value =
        serde_json::from_str(&std::fs::read_to_string(source.join("setting.json")).unwrap())
            .unwrap();
    let entries: Vec<Value> = setting["trajectories"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|t| files.contains(&t["file"].as_str().unwrap()))
        .map(|t| {
            // Drop the simulator's split so that only the labels file can give one.
            let mut t = t.clone();
            t.as_object_mut().unwrap().remove("split");
            t
        })
        .collect();
    setting["trajectories"] = Value::Array(entries);
    std::fs::write(dir.join("setting.json"), setting.to_string()).unwrap();
    std::fs::write(
        dir.join("pushlab-labels.json"),
        r#"{"format": "pushlab-labels", "version": 1, "recordings": {
            "offline_000.csv": {"meta": {"split": "offline"}},
            "offline_013.csv": {"meta": {"split": "offline"}},
            "online_001.csv": {"meta": {"split": "online"},
                               "segments": [{"label": "bad tracking", "start": 10, "end": 30}]},
            "online_002.csv": {"meta": {"split": "online"},
                               "segments": [{"label": "slipping", "start": 0, "end": 40}]}
        }}"#,
    )
    .unwrap();
    let json = dir.join("out.json");
    let (dir_s, json_s) = (dir.display().to_string(), json.display().to_string());
    let run = pushlab(&[
        "eval",
        "--offline",
        &dir_s,
        "--online",
        &dir_s,
        "--split-from-labels",
        "--epochs",
        "2",
        "--json",
        &json_s,
    ]);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    assert!(
        run.stdout
            .contains("(2 recording(s) with another split left out)"),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout
            .contains("(20 frame(s) labelled bad tracking left out)"),
        "{}",
        run.stdout
    );
    let report: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let sources = |key: &str| -> Vec<String> {
        report["config"][key]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s.as_str().unwrap().rsplit('/').next().unwrap().to_owned())
            .collect()
    };
    assert_eq!(
        sources("offline_sources"),
        ["offline_000.csv", "offline_013.csv"]
    );
    assert_eq!(
        sources("online_sources"),
        ["online_001.csv", "online_002.csv"]
    );
    let steps: Vec<u64> = report["trajectories"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t["steps"].as_u64().unwrap())
        .collect();
    // Horizon 1: a sample is skipped when its frame t or t+1 is bad: frames 9..=29, 21 samples.
    assert_eq!(steps[1] - steps[0], 21, "{steps:?}");
    let per_label = &report["per_label"]["online"];
    let slipping = per_label
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["label"] == "slipping")
        .expect("a slipping mean");
    assert_eq!(slipping["count"], 40);
    assert!(slipping["mean"].as_f64().unwrap().is_finite());
    assert_eq!(report["per_label"]["fixed"][0]["label"], "all");
}

#[test]
fn real_mit_files_evaluate() {
    let Some(dir) = skip::shared(Path::new(env!("CARGO_MANIFEST_DIR")), "mit-push") else {
        return;
    };
    let file = |name: &str| dir.join(name).display().to_string();
    let offline = [
        file("motion_surface=abs_shape=rect1_a=0_v=75_i=2.000_s=0.800_t=0.349.h5"),
        file("motion_surface=abs_shape=hex_a=0_v=50_i=4.000_s=0.700_t=0.000.h5"),
    ];
    let online = [file(
        "motion_surface=plywood_shape=hex_a=0_v=150_i=1.000_s=0.000_t=-0.349.json",
    )];
    let out = temp_dir("mit").join("mit.json");
    let out_s = out.display().to_string();
    let run = pushlab(&eval_args(
        &offline,
        &online,
        &["--epochs", "2", "--json", &out_s],
    ));
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    let report: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    for key in ["offline_nn", "offline", "fixed", "online"] {
        let v = &report[key];
        assert!(v["pos"].as_f64().unwrap().is_finite(), "{key}: {v}");
        assert!(v["rot"].as_f64().unwrap().is_finite(), "{key}: {v}");
    }
    assert_eq!(report["trajectories"][0]["com_offset_true"], Value::Null);
}
