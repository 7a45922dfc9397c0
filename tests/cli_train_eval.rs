//! `pushlab train` and `pushlab eval` end to end: the built binary on a small subset of the sample
//! data with few epochs; the JSON report's fields and values, the figure, exit codes 1 and 2 with their
//! messages, labels (splits, bad tracking, per-label means) and a train → eval --model round trip.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

mod cli_common;
use cli_common::pushlab;

fn sample(set: &str, file: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("sample-data")
        .join(set)
        .join(file)
        .display()
        .to_string()
}

fn temp_dir(name: &str) -> PathBuf {
    cli_common::temp_dir("pushlab-eval", name)
}

/// Six offline pushes of box1 on paper with the COM at the centre.
fn offline_subset() -> Vec<String> {
    (0..6)
        .map(|i| {
            sample(
                "box1-paper-center-front",
                &format!("offline_{:03}.csv", i * 4),
            )
        })
        .collect()
}

/// Two online pushes of the same box with the COM moved toward the upper right.
fn online_subset() -> Vec<String> {
    vec![
        sample("box1-paper-ur-front", "online_000.csv"),
        sample("box1-paper-ur-front", "online_004.csv"),
    ]
}

fn eval_args<'a>(offline: &'a [String], online: &'a [String], extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec!["eval", "--offline"];
    args.extend(offline.iter().map(String::as_str));
    args.push("--online");
    args.extend(online.iter().map(String::as_str));
    args.extend_from_slice(extra);
    args
}

fn nmse(v: &Value, what: &str) -> (f64, f64) {
    let pos = v["pos"]
        .as_f64()
        .unwrap_or_else(|| panic!("{what}.pos: {v}"));
    let rot = v["rot"]
        .as_f64()
        .unwrap_or_else(|| panic!("{what}.rot: {v}"));
    assert!(
        pos.is_finite() && pos > 0.0 && pos < 50.0,
        "{what}.pos = {pos}"
    );
    assert!(
        rot.is_finite() && rot > 0.0 && rot < 50.0,
        "{what}.rot = {rot}"
    );
    (pos, rot)
}

#[test]
fn eval_writes_the_documented_json_and_a_png_and_skips_a_broken_file() {
    let dir = temp_dir("eval");
    let broken = dir.join("motion_surface=abs_shape=rect1_broken.json");
    std::fs::write(&broken, "{ this is not json").unwrap();
    let json = dir.join("out.json");
    let png = dir.join("out.png");
    let offline = offline_subset();
    let mut online = online_subset();
    online.push(broken.display().to_string());
    let (json_s, png_s) = (json.display().to_string(), png.display().to_string());
    let args = eval_args(
        &offline,
        &online,
        &[
            "--epochs",
            "3",
            "--seed",
            "7",
            "--horizon",
            "5",
            "--steps",
            "4",
            "--lr",
            "0.01",
            "--physics",
            "--best-fit",
            "--json",
            &json_s,
            "--plot",
            &png_s,
        ],
    );
    let run = pushlab(&args);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);

    // The files used and the broken one, by name with its reason.
    assert!(
        run.stdout.contains("offline: 6 recording(s)"),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout.contains("online: 2 recording(s)"),
        "{}",
        run.stdout
    );
    assert!(run.stdout.contains("offline_020.csv"), "{}", run.stdout);
    let skipped_line = run
        .stdout
        .lines()
        .find(|l| l.contains("skipped:"))
        .expect("a skipped line");
    assert!(skipped_line.contains("rect1_broken.json"), "{skipped_line}");
    // The table rows.
    for row in [
        "Offline NN",
        "Offline ",
        "Fixed ",
        "Online ",
        "Physics fixed",
        "Physics online",
    ] {
        assert!(
            run.stdout.lines().any(|l| l.starts_with(row)),
            "no row {row:?}:\n{}",
            run.stdout
        );
    }

    let report: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    for key in ["offline_nn", "offline", "fixed", "online"] {
        nmse(&report[key], key);
    }
    let config = &report["config"];
    assert_eq!(config["horizon"], 5);
    assert_eq!(config["epochs"], 3);
    assert_eq!(config["seed"], 7);
    assert_eq!(config["steps"], 4);
    assert_eq!(config["lr"], 0.01);
    assert_eq!(config["model"], Value::Null);
    assert_eq!(config["offline_sources"].as_array().unwrap().len(), 6);
    let trajectories = report["trajectories"].as_array().unwrap();
    assert_eq!(trajectories.len(), 2);
    for (t, source) in trajectories.iter().zip(online_subset()) {
        assert_eq!(t["source"].as_str().unwrap(), source);
        // 100 frames at horizon 5 give 95 steps (the sample data has 10 s at 10 Hz plus one frame).
        let steps = t["steps"].as_u64().unwrap();
        assert!((90..=100).contains(&steps), "steps {steps}");
        nmse(&t["fixed"], "fixed");
        nmse(&t["online"], "online");
        let learned = t["com_offset_learned"].as_array().unwrap();
        assert_eq!(learned.len(), 2);
        for c in learned {
            let c = c.as_f64().unwrap();
            assert!(
                c.abs() < 0.3,
                "learned COM offset {c} is outside a 0.3 × 0.4 m box"
            );
        }
        let h = t["h_learned"].as_f64().unwrap();
        assert!((0.001..=2.0).contains(&h), "h {h}");
        assert_eq!(t["com_offset_true"], serde_json::json!([0.05, 0.05]));
        let h_true = t["h_true"].as_f64().unwrap();
        assert!(h_true > 0.05 && h_true < 0.3, "h_true {h_true}");
    }
    for key in ["offline", "fixed", "online"] {
        nmse(&report["physics"][key], key);
    }
    // The physics-only model's COM on the same pushes, its error against the same truth, and the
    // line that sets it beside the combined model's.
    let physics = report["physics_trajectories"].as_array().unwrap();
    assert_eq!(physics.len(), 2);
    for (p, source) in physics.iter().zip(online_subset()) {
        assert_eq!(p["source"].as_str().unwrap(), source);
        let learned: Vec<f64> = (p["com_offset_learned"].as_array().unwrap().iter())
            .map(|c| c.as_f64().unwrap())
            .collect();
        let error = p["com_found"]["error_m"].as_f64().unwrap();
        let distance = (learned[0] - 0.05).hypot(learned[1] - 0.05);
        assert!(
            (error - distance).abs() < 1e-12,
            "{error} against {distance}"
        );
        // Learning moved it from the geometric centre (θ_online(0)) toward the true COM.
        assert!(
            error < 0.05_f64.hypot(0.05),
            "physics-only COM error {error} m"
        );
    }
    // Each push's physics-only NMSE: the report's row is their mean weighted by the push's samples
    // (the same frames as the combined model's), and the table prints it beside the combined model's.
    for key in ["fixed", "online"] {
        let (mut sum_pos, mut sum_rot, mut samples) = (0.0, 0.0, 0.0);
        for (p, t) in physics.iter().zip(trajectories) {
            nmse(&p[key], key);
            let steps = t["steps"].as_f64().unwrap();
            sum_pos += steps * p[key]["pos"].as_f64().unwrap();
            sum_rot += steps * p[key]["rot"].as_f64().unwrap();
            samples += steps;
        }
        let row = &report["physics"][key];
        for (mean, axis) in [(sum_pos / samples, "pos"), (sum_rot / samples, "rot")] {
            let expected = row[axis].as_f64().unwrap();
            assert!(
                (mean - expected).abs() <= 1e-12 * expected.abs(),
                "physics {key} {axis}: {mean} from the pushes, {expected} in the row"
            );
        }
    }
    let header = (run.stdout.lines())
        .find(|l| l.starts_with("online trajectory"))
        .unwrap();
    assert!(
        header.contains("online pos/rot     phys online"),
        "{header}"
    );
    let first = physics[0]["online"]["pos"].as_f64().unwrap();
    assert!(
        (run.stdout.lines()).any(|l| l.contains(&format!(
            "/{:<7.3} {first:>7.3}/",
            trajectories[0]["online"]["rot"].as_f64().unwrap()
        ))),
        "{}",
        run.stdout
    );
    assert_eq!(report["physics_com_found"]["pushes"], 2);
    assert!(
        run.stdout
            .lines()
            .any(|l| l.starts_with("Physics-only online: COM found on 2 pushes")),
        "{}",
        run.stdout
    );
    // --best-fit: each push's best θ for both models fits the whole push at least as well as
    // θ_online(0) (the fixed run), its COM error is against the setting's truth, and the summary
    // lines are printed.
    for (t, p) in trajectories.iter().zip(physics) {
        for (kind, push) in [("combined", t), ("physics", p)] {
            let fit = &push["best_fit"];
            assert_eq!(fit["samples"], t["steps"], "{kind}: {fit}");
            let fixed = 2.0 * push["fixed"]["pos"].as_f64().unwrap()
                + push["fixed"]["rot"].as_f64().unwrap();
            let best = fit["mean_loss"].as_f64().unwrap();
            assert!(best <= fixed + 1e-12, "{kind}: best {best} > fixed {fixed}");
            let total =
                2.0 * fit["nmse"]["pos"].as_f64().unwrap() + fit["nmse"]["rot"].as_f64().unwrap();
            assert!(
                (total - best).abs() < 1e-9 * best.max(1.0),
                "{kind}: {total} vs {best}"
            );
            let (com, truth) = (&fit["theta"]["com_offset"], &t["com_offset_true"]);
            let error = (com[0].as_f64().unwrap() - truth[0].as_f64().unwrap())
                .hypot(com[1].as_f64().unwrap() - truth[1].as_f64().unwrap());
            let reported = fit["com_error_m"].as_f64().unwrap();
            assert!((reported - error).abs() < 1e-12, "{kind}: {fit}");
        }
    }
    // The trajectory table gives each push's best NMSE in a "best θ" column after "phys online".
    let header = (run.stdout.lines())
        .find(|l| l.starts_with("online trajectory"))
        .unwrap();
    assert!(header.contains("phys online          best θ"), "{header}");
    let (first, phys) = (&trajectories[0], &physics[0]);
    let cells = format!(
        "{:>7.3}/{:<7.3} {:>7.3}/{:<7.3}",
        phys["online"]["pos"].as_f64().unwrap(),
        phys["online"]["rot"].as_f64().unwrap(),
        first["best_fit"]["nmse"]["pos"].as_f64().unwrap(),
        first["best_fit"]["nmse"]["rot"].as_f64().unwrap(),
    );
    assert!(
        (run.stdout.lines()).any(|l| l.contains(&cells)),
        "{cells}\n{}",
        run.stdout
    );
    assert_eq!(report["best_fit"]["pushes"], 2);
    assert_eq!(report["physics_best_fit"]["pushes"], 2);
    for line in [
        "Best θ per push (the whole push",
        "Physics-only best θ per push",
    ] {
        assert!(
            run.stdout.lines().any(|l| l.starts_with(line)),
            "{line}: {}",
            run.stdout
        );
    }
    let skipped = report["skipped"].as_array().unwrap();
    assert_eq!(skipped.len(), 1, "{skipped:?}");
    assert!(
        skipped[0]["path"]
            .as_str()
            .unwrap()
            .ends_with("rect1_broken.json")
    );

    // The figure: a valid PNG of the documented size, with both curve colours drawn.
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let image = image::load_from_memory(&bytes)
        .expect("decodable PNG")
        .to_rgb8();
    assert_eq!(image.dimensions(), (1000, 400));
    let has = |rgb: [u8; 3]| image.pixels().filter(|p| p.0 == rgb).count();
    assert!(has([31, 119, 180]) > 500, "blue (fixed) curve missing");
    assert!(has([255, 127, 14]) > 500, "orange (online) curve missing");
    assert!(has([0, 0, 0]) > 500, "black offline line and text missing");
}

#[test]
fn best_fit_with_carried_theta_fits_each_object_over_all_its_pushes() {
    let dir = temp_dir("eval-object-best-fit");
    let json = dir.join("out.json");
    let json_s = json.display().to_string();
    let (offline, online) = (offline_subset(), online_subset());
    let eval = |carry: &[&str]| {
        let mut extra = vec![
            "--epochs",
            "3",
            "--horizon",
            "5",
            "--best-fit",
            "--json",
            &json_s,
        ];
        extra.extend_from_slice(carry);
        let run = pushlab(&eval_args(&offline, &online, &extra));
        assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
        let report: Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
        (run, report)
    };
    let (run, report) = eval(&["--carry-theta"]);
    // The two pushes are of one box: one object, both its pushes, every sample of both.
    let objects = report["object_best_fits"].as_array().unwrap();
    assert_eq!(objects.len(), 1, "{objects:?}");
    assert_eq!(objects[0]["sources"], serde_json::json!(online));
    let trajectories = report["trajectories"].as_array().unwrap();
    let steps: u64 = trajectories
        .iter()
        .map(|t| t["steps"].as_u64().unwrap())
        .sum();
    let fit = &objects[0]["best_fit"];
    assert_eq!(fit["samples"].as_u64(), Some(steps));
    // It fits both pushes at least as well as θ_online(0) does (the fixed runs, by samples).
    let fixed: f64 = (trajectories.iter())
        .map(|t| {
            let n = t["steps"].as_f64().unwrap();
            n * (2.0 * t["fixed"]["pos"].as_f64().unwrap() + t["fixed"]["rot"].as_f64().unwrap())
        })
        .sum::<f64>()
        / steps as f64;
    let best = fit["mean_loss"].as_f64().unwrap();
    assert!(best <= fixed + 1e-12, "object best {best} > fixed {fixed}");
    assert_eq!(report["object_best_fit"]["pushes"], 1);
    assert!(
        (run.stdout.lines())
            .any(|l| l.starts_with("Best θ per object (all its carried pushes at once")),
        "{}",
        run.stdout
    );
    // Without --carry-theta there are no objects' fits.
    let (_, report) = eval(&[]);
    assert!(report.get("object_best_fits").is_none(), "{report}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn train_then_eval_with_the_model_gives_the_same_numbers() {
    let dir = temp_dir("roundtrip");
    let model = dir.join("model.json");
    let model_s = model.display().to_string();
    let offline = offline_subset();
    let mut train = vec!["train", "--data"];
    train.extend(offline.iter().map(String::as_str));
    train.extend([
        "--out",
        &model_s,
        "--epochs",
        "2",
        "--seed",
        "3",
        "--horizon",
        "2",
        "--baseline",
    ]);
    let run = pushlab(&train);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    assert!(
        run.stdout.contains(&format!("wrote {model_s}")),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout.contains("pure NN: 2 epoch(s) run"),
        "{}",
        run.stdout
    );
    let file: Value = serde_json::from_str(&std::fs::read_to_string(&model).unwrap()).unwrap();
    assert_eq!(file["format"], "pushlab-model");
    assert_eq!(file["combined"]["horizon"], 2);
    assert!(file["pure_nn"].is_object());
    assert_eq!(file["training"]["sources"].as_array().unwrap().len(), 6);

    let online = online_subset();
    let (loaded_json, trained_json) = (dir.join("loaded.json"), dir.join("trained.json"));
    let (loaded_s, trained_s) = (
        loaded_json.display().to_string(),
        trained_json.display().to_string(),
    );
    let with_model = pushlab(&eval_args(
        &offline,
        &online,
        &["--model", &model_s, "--json", &loaded_s],
    ));
    assert_eq!(
        with_model.code, 0,
        "{}\n{}",
        with_model.stdout, with_model.stderr
    );
    // Training in eval with the same data, seed, epochs and horizon makes the same models.
    let trained = pushlab(&eval_args(
        &offline,
        &online,
        &[
            "--epochs",
            "2",
            "--seed",
            "3",
            "--horizon",
            "2",
            "--json",
            &trained_s,
        ],
    ));
    assert_eq!(trained.code, 0, "{}\n{}", trained.stdout, trained.stderr);
    let a: Value = serde_json::from_str(&std::fs::read_to_string(&loaded_json).unwrap()).unwrap();
    let b: Value = serde_json::from_str(&std::fs::read_to_string(&trained_json).unwrap()).unwrap();
    assert_eq!(a["config"]["model"].as_str().unwrap(), model_s);
    assert_eq!(a["config"]["horizon"], 2);
    for key in ["offline_nn", "offline", "fixed", "online", "trajectories"] {
        assert_eq!(
            a[key], b[key],
            "{key} differs between --model and training in eval"
        );
    }

    // A --horizon that contradicts the model is a wrong argument.
    let run = pushlab(&eval_args(
        &offline,
        &online,
        &["--model", &model_s, "--horizon", "3"],
    ));
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(
        run.stderr
            .contains("--horizon 3 differs from the horizon the model was trained for (2)"),
        "{}",
        run.stderr
    );
    // A model file that is not one fails with its name.
    let not_a_model = dir.join("not-a-model.json");
    std::fs::write(&not_a_model, r#"{"format": "something else"}"#).unwrap();
    let not_s = not_a_model.display().to_string();
    let run = pushlab(&eval_args(&offline, &online, &["--model", &not_s]));
    assert_eq!(run.code, 1, "{}", run.stderr);
    assert!(
        run.stderr
            .contains("not-a-model.json: not a pushlab model file"),
        "{}",
        run.stderr
    );
}

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
        run.stderr
            .contains("nothing usable in --offline: no recording could be used (1 skipped)"),
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
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/mit-push");
    if !dir.is_dir() {
        eprintln!("skipped: {} is absent (real MIT Push files)", dir.display());
        return;
    }
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

#[cfg(unix)]
#[test]
fn ctrl_c_stops_training_and_keeps_the_best_model() {
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;
    use std::time::{Duration, Instant};

    let dir = temp_dir("ctrlc");
    let model = dir.join("model.json");
    // Without early stopping and with a million epochs, only Ctrl-C ends this run.
    let mut child = Command::new(env!("CARGO_BIN_EXE_pushlab"))
        .args([
            "train",
            "--epochs",
            "1000000",
            "--patience",
            "0",
            "--baseline",
            "--out",
        ])
        .arg(&model)
        .arg("--data")
        .args(offline_subset())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start pushlab train");
    let mut stdout = BufReader::new(child.stdout.take().expect("stdout"));
    // The first line is printed after the Ctrl-C handler is installed.
    let mut first = String::new();
    stdout.read_line(&mut first).expect("first line");
    assert!(first.starts_with("data: 6 recording(s)"), "{first}");
    std::thread::sleep(Duration::from_millis(800));
    // The shell's built-in kill: no procps needed on a fresh machine.
    let killed = Command::new("sh")
        .args(["-c", &format!("kill -INT {}", child.id())])
        .status()
        .expect("run kill");
    assert!(killed.success());
    let deadline = Instant::now() + Duration::from_secs(30);
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        assert!(
            Instant::now() < deadline,
            "pushlab did not stop after Ctrl-C"
        );
        std::thread::sleep(Duration::from_millis(50));
    };
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut stdout, &mut rest).expect("rest of stdout");
    assert_eq!(status.code(), Some(0), "{first}{rest}");
    assert!(
        rest.contains("(stopped by Ctrl-C; best model so far kept)"),
        "{rest}"
    );
    assert!(
        rest.contains("the pure network was not trained (stopped by Ctrl-C)"),
        "{rest}"
    );
    let file: Value = serde_json::from_str(&std::fs::read_to_string(&model).unwrap()).unwrap();
    let report = &file["training"]["report"];
    assert_eq!(report["cancelled"], true);
    assert!(report["epochs_run"].as_u64().unwrap() < 1_000_000);
    assert!(file["pure_nn"].is_null());
}
