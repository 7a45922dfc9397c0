//! A model trained by `pushlab train` gives `eval --model` the numbers eval trains itself; Ctrl-C keeps the best model.

use super::*;

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

    // Without --offline, a model file is evaluated on new pushes alone: every online row (fixed,
    // online, the network alone, physics, each push frame by frame) as with --offline, to the bit;
    // the offline rows null, said once.
    let (alone_json, beside_json) = (dir.join("alone.json"), dir.join("beside.json"));
    let (alone_s, beside_s) = (
        alone_json.display().to_string(),
        beside_json.display().to_string(),
    );
    let mut alone_args = vec!["eval", "--model", &model_s, "--online"];
    alone_args.extend(online.iter().map(String::as_str));
    alone_args.extend(["--physics", "--per-frame", "--json", &alone_s]);
    let alone = pushlab(&alone_args);
    assert_eq!(alone.code, 0, "{}\n{}", alone.stdout, alone.stderr);
    assert_eq!(
        alone
            .stdout
            .matches("no --offline: the offline rows are not computed")
            .count(),
        1,
        "{}",
        alone.stdout
    );
    assert!(!alone.stdout.contains("Offline"), "{}", alone.stdout);
    assert!(alone.stdout.contains("Online NN"), "{}", alone.stdout);
    let beside = pushlab(&eval_args(
        &offline,
        &online,
        &[
            "--model",
            &model_s,
            "--physics",
            "--per-frame",
            "--json",
            &beside_s,
        ],
    ));
    assert_eq!(beside.code, 0, "{}\n{}", beside.stdout, beside.stderr);
    let a: Value = serde_json::from_str(&std::fs::read_to_string(&alone_json).unwrap()).unwrap();
    let b: Value = serde_json::from_str(&std::fs::read_to_string(&beside_json).unwrap()).unwrap();
    for key in ["fixed", "online", "online_nn", "trajectories"] {
        assert_eq!(a[key], b[key], "{key} differs without --offline");
    }
    for key in ["fixed", "online"] {
        assert_eq!(a["physics"][key], b["physics"][key], "physics.{key}");
    }
    assert!(a["trajectories"][0]["frames"].as_array().unwrap().len() > 10);
    nmse(&a["online_nn"], "online_nn");
    nmse(&b["offline"], "offline");
    for key in ["offline_nn", "offline"] {
        assert!(a[key].is_null(), "{key}: {}", a[key]);
    }
    assert!(a["physics"]["offline"].is_null(), "{}", a["physics"]);
    assert_eq!(a["config"]["offline_samples"], 0);

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

#[test]
fn the_apps_default_model_evaluates_on_new_pushes_without_its_training_data() {
    let dir = temp_dir("default-model");
    let report = dir.join("report.json");
    let report_s = report.display().to_string();
    let model = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets")
        .join("default-model.json")
        .display()
        .to_string();
    let online = online_subset();
    let mut args = vec!["eval", "--model", &model, "--online"];
    args.extend(online.iter().map(String::as_str));
    args.extend(["--json", &report_s]);
    let run = pushlab(&args);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(v["config"]["horizon"], 10);
    assert_eq!(v["trajectories"].as_array().unwrap().len(), 2);
    let (fixed, online) = (nmse(&v["fixed"], "fixed"), nmse(&v["online"], "online"));
    nmse(&v["online_nn"], "online_nn");
    assert!(v["offline"].is_null() && v["offline_nn"].is_null(), "{v}");
    // The pushes have the COM moved from θ_online(0)'s: learning it online must help.
    assert!(online.0 < fixed.0, "online {online:?} vs fixed {fixed:?}");
}
